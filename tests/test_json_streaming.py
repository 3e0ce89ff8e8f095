"""The streamed writers give the text of ``json.dump`` of the whole document (byte for byte):
:meth:`Diagram.write_json` (runtime/voronoi/structure.py) and
:func:`runtime.voronoi.geojson.write_geojson`, and the command line's ``--json``/``--geojson``
files.  The reference is the standard library's encoder on the materialised document
(``to_json`` / ``to_geojson``), which does not go through the streaming writer."""
import io
import json
import subprocess
import sys

import pytest

import curvedvoronoi as cv
from curvedvoronoi.runtime.voronoi.geojson import Records, write_geojson, write_json_object


def _diagrams():
    # circles, points, a nested circle (a closed edge), an unbounded edge; an ellipse (conic)
    d1 = cv.voronoi([(0, 0, 1), (4, 0, 1), (2, 4, 0), (2, 1.5, 0.3), (-3, 3, 0.5), (6, 5, 0),
                     (10, 10, 3), (10, 10, 0)], certify=False)
    d2 = cv.voronoi([cv.Conic.ellipse((0, 0), (2, 1)), (5, 0, 1), (0, 5, 0)], certify=False)
    return [d1, d2, cv.Diagram(d1.sites[:1], [], [], False, [], {})]


@pytest.mark.parametrize("indent", [None, 1, 2])
def test_write_json_is_json_dump_of_to_json(indent):
    for d in _diagrams():
        out = io.StringIO()
        d.write_json(out, indent=indent)
        assert out.getvalue() == json.dumps(d.to_json(), indent=indent)
        assert cv.Diagram.from_json(json.loads(out.getvalue())).to_json() == d.to_json()


@pytest.mark.parametrize("crs", [None, False, "EPSG:32633"])
def test_write_geojson_is_json_dump_of_to_geojson(crs):
    for d in _diagrams()[:2]:
        for sites in (True, False):
            out = io.StringIO()
            write_geojson(d, out, crs, sites=sites)
            assert out.getvalue() == json.dumps(d.to_geojson(crs=crs, sites=sites))


def test_write_json_object_nesting_and_empty_arrays():
    members = [("a", Records(lambda: iter([]))), ("b", Records(lambda: ({"x": [i, [i, {"s": "q\n"}]]} for i in range(3)))),
               ("c", {"d": [], "e": {}}), ("f", [])]
    doc = {k: list(v) if isinstance(v, Records) else v for k, v in members}
    for indent in (None, 0, 1, 3):
        out = io.StringIO()
        write_json_object(out, members, indent)
        assert out.getvalue() == json.dumps(doc, indent=indent)
    out = io.StringIO()
    write_json_object(out, [], 1)
    assert out.getvalue() == json.dumps({}, indent=1)


def test_command_line_files_are_the_documents(tmp_path):
    src = tmp_path / "sites.json"
    src.write_text(json.dumps({"sites": [{"circle": {"centre": [0, 0], "radius": 1}},
                                         {"circle": {"centre": [4, 0], "radius": 1}},
                                         {"point": [2, 4]}, {"circle": {"centre": [2, 1.5], "radius": "3/10"}}]}))
    js, gj = tmp_path / "d.json", tmp_path / "d.geojson"
    r = subprocess.run([sys.executable, "-m", "curvedvoronoi", "diagram", str(src), "--json", str(js),
                        "--geojson", str(gj), "--quiet", "--no-certify"], capture_output=True, text=True)
    assert r.returncode in (0, 2), r.stderr
    doc = json.loads(js.read_text())
    assert js.read_text() == json.dumps(doc, indent=1)
    ref = cv.voronoi([(0, 0, 1), (4, 0, 1), (2, 4, 0), (2, 1.5, 0.3)], certify=False)
    want = json.loads(json.dumps(ref.to_json()))
    for key in ("vertices", "edges", "delaunay_edges"):
        assert doc[key] == want[key]
    d = cv.Diagram.from_json(doc)
    assert json.loads(gj.read_text()) == json.loads(json.dumps(d.to_geojson()))
    stdout = subprocess.run([sys.executable, "-m", "curvedvoronoi", "diagram", str(src), "--no-certify"],
                            capture_output=True, text=True).stdout
    printed = json.loads(stdout)
    assert stdout.endswith("}\n") and {k: v for k, v in printed.items() if k != "stats"} == \
        {k: v for k, v in doc.items() if k != "stats"}
