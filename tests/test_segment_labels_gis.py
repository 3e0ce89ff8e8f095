"""Segment, arc and point diagrams in GIS terms: the labels of the input pieces on the elementary
sites (JSON, GeoJSON, GeoDataFrames), the medial axis as GeoJSON with its boundary and a CRS, the
``--crs`` option of the segment commands, proximity queries next to circular arcs (checked against
the definition of the distance to an arc), and ``cv.verify`` with (x, y) pairs."""
from __future__ import annotations

import json
import warnings
from fractions import Fraction

import mpmath
import numpy as np
import pytest

import curvedvoronoi as cv
from curvedvoronoi.runtime.cli import main

S, A = cv.Segment, cv.Arc


def cli(capsys, *args):
    code = main([str(a) for a in args])
    out = capsys.readouterr()
    return code, out.out, out.err


def _read(path):
    """The file read by geopandas (GDAL), with the warnings raised while reading it."""
    gpd = pytest.importorskip("geopandas")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        frame = gpd.read_file(path)
    return frame, [str(w.message) for w in caught]


def _scene():
    # 'wall' and 'door' share the end (4, 0): it takes the label of the first piece ending there
    return [S((0, 0), (4, 0), label="wall"), S((4, 0), (4, 3), label="door"), cv.Point(1, 2, label="lamp"),
            A.circular((8, 4), 1, 0, 90, label="kerb"), (9, 0)]


@pytest.fixture(scope="module")
def diagram():
    return cv.voronoi(_scene())


def _expected_labels(d):
    """The label of each elementary site by the rule: the piece ``d.sources`` names."""
    pieces = _scene()
    return [getattr(pieces[k], "label", None) for k in d.sources]


# ------------------------------------------------------------------------------------ labels
def test_elementary_sites_carry_the_label_of_their_source_piece(diagram):
    d = diagram
    labels = [getattr(s, "label", None) for s in d.sites]
    assert labels == _expected_labels(d)
    by_site = {repr(s): getattr(s, "label", None) for s in d.sites}
    assert by_site["Point(4, 0)"] == "wall"            # shared end: the first piece ending there
    assert by_site["Point(4, 3)"] == "door" and by_site["Point(1, 2)"] == "lamp"
    assert by_site["Point(9, 0)"] is None               # an (x, y) pair has no label
    assert by_site["Segment((0, 0), (4, 0))"] == "wall" and by_site["Segment((4, 0), (4, 3))"] == "door"
    assert [getattr(s, "label", None) for s in d.sites if isinstance(s, A)] == ["kerb"]
    assert sum(getattr(s, "label", None) == "kerb" for s in d.sites) == 3     # the arc and its two ends


def test_a_merged_straight_joint_keeps_the_first_label():
    d = cv.voronoi([S((0, 0), (1, 0), label="a"), S((1, 0), (3, 0), label="b"), cv.Point(1, 2, label="p")])
    assert [(repr(s), s.label) for s in d.sites] == [("Point(0, 0)", "a"), ("Point(3, 0)", "b"),
                                                     ("Point(1, 2)", "p"), ("Segment((0, 0), (3, 0))", "a")]


def test_labels_survive_the_diagram_json(diagram):
    doc = json.loads(json.dumps(diagram.to_json()))
    assert [s.get("label") for s in doc["sites"]] == _expected_labels(diagram)
    back = cv.Diagram.from_json(doc)
    assert [getattr(s, "label", None) for s in back.sites] == _expected_labels(diagram)
    assert back.sources == diagram.sources


def test_labels_of_sites_file_records(tmp_path, capsys):
    src = tmp_path / "sites.json"
    src.write_text(json.dumps({"sites": [
        {"segment": [[0, 0], [4, 0]], "label": "wall 3"},
        {"point": [1, 2], "label": "lamp"},
        {"arc": {"centre": [8, 4], "radius": 1, "start": [9, 4], "end": [8, 5]}, "label": "kerb"},
        {"point": [9, 0]}]}))
    d = cv.voronoi(cv.read_sites(src))
    want = {"Point(0, 0)": "wall 3", "Point(4, 0)": "wall 3", "Point(1, 2)": "lamp", "Point(9, 4)": "kerb",
            "Point(8, 5)": "kerb", "Point(9, 0)": None, "Segment((0, 0), (4, 0))": "wall 3"}
    got = {repr(s): getattr(s, "label", None) for s in d.sites}
    assert {k: got[k] for k in want} == want and [s.label for s in d.sites if isinstance(s, A)] == ["kerb"]
    out = tmp_path / "d.json"
    code, _, err = cli(capsys, "diagram", src, "--json", out, "--quiet")
    doc = json.loads(out.read_text())
    assert code == (0 if doc["certified"] else 1), err
    assert [s.get("label") for s in doc["sites"]] == [getattr(s, "label", None) for s in d.sites]


# ------------------------------------------------------------------------------------ GeoJSON
def test_geojson_read_back_with_labels_unique_ids_and_the_crs(diagram, tmp_path):
    pyproj = pytest.importorskip("pyproj")
    d = diagram
    path = tmp_path / "d.geojson"
    path.write_text(json.dumps(d.to_geojson(crs="EPSG:32633")))
    g, warned = _read(path)
    assert not [w for w in warned if "Several features with id" in w], warned
    assert g.crs == pyproj.CRS("EPSG:32633") and g["id"].is_unique
    sites = g[g["kind"] == "site"].sort_values("number")
    assert [None if isinstance(v, float) else v for v in sites["label"]] == _expected_labels(d)
    assert sites["shape"].tolist().count("arc") == 1 and sites["shape"].tolist().count("segment") == 2


def test_geopandas_frames_carry_the_labels(diagram):
    pytest.importorskip("geopandas")
    frames = diagram.to_geopandas(crs="EPSG:32633")
    for frame in (frames.cells, frames.sites):
        assert [None if isinstance(v, float) else v for v in frame["label"]] == _expected_labels(diagram)
    assert frames.sites.crs.to_epsg() == 32633


def _ring_with_labels():
    return [S((0, 0), (6, 0), label="south"), S((6, 0), (6, 4), label="east"), S((6, 4), (0, 4), label="north"),
            S((0, 4), (0, 0), label="west")]


def test_medial_axis_geojson_has_the_boundary_labels_unique_ids_and_a_crs(tmp_path):
    pyproj = pytest.importorskip("pyproj")
    m = cv.medial_axis(_ring_with_labels())
    gj = m.to_geojson()
    assert gj["crs"]["properties"]["name"].startswith("ENGCRS")         # planar by default, as Diagram's
    assert "crs" not in m.to_geojson(crs=False)
    ids = [f["id"] for f in gj["features"]]
    assert len(set(ids)) == len(ids)
    assert sorted(i for i in ids if i.startswith("medial-edge-")) == sorted(f"medial-edge-{e.id}" for e in m.edges)
    assert sorted(i for i in ids if i.startswith("medial-vertex-")) == sorted(f"medial-vertex-{v.id}"
                                                                              for v in m.vertices)
    sites = [f for f in gj["features"] if f["properties"]["kind"] == "site"]
    assert [f["id"] for f in sites] == [f"site-{i}" for i in range(len(m.diagram.sites))]
    assert {f["properties"]["label"] for f in sites} == {"south", "east", "north", "west"}
    for f in gj["features"]:
        assert "id" not in f["properties"]
    path = tmp_path / "m.geojson"
    path.write_text(json.dumps(m.to_geojson(crs="EPSG:32633")))
    g, warned = _read(path)
    assert not [w for w in warned if "Several features with id" in w], warned
    assert g.crs == pyproj.CRS("EPSG:32633") and len(g) == len(gj["features"])
    assert (g["kind"] == "edge").sum() == len(m.edges)


# ------------------------------------------------------------------------------------ --crs
def _dxf(tmp_path):
    ezdxf = pytest.importorskip("ezdxf", reason="DXF input needs ezdxf (test extra)")
    doc = ezdxf.new()
    msp = doc.modelspace()
    msp.add_line((0, 0), (6, 0), dxfattribs={"layer": "walls"})
    msp.add_line((6, 0), (6, 4), dxfattribs={"layer": "walls"})
    msp.add_line((6, 4), (0, 4), dxfattribs={"layer": "facade"})
    msp.add_line((0, 4), (0, 0), dxfattribs={"layer": "walls"})
    path = tmp_path / "room.dxf"
    doc.saveas(path)
    return path


@pytest.mark.parametrize("command", ["diagram", "medial-axis"])
def test_segment_commands_take_crs(tmp_path, capsys, command):
    pyproj = pytest.importorskip("pyproj")
    dxf = _dxf(tmp_path)
    out = tmp_path / "o.geojson"
    quiet = ["--quiet"] if command == "diagram" else ["-q"]
    code, _, err = cli(capsys, command, dxf, "--geojson", out, "--crs", "EPSG:32633", *quiet)
    assert code in (0, 1), err
    doc = json.loads(out.read_text())
    assert doc["crs"] == {"type": "name", "properties": {"name": "EPSG:32633"}}
    g, warned = _read(out)
    assert g.crs == pyproj.CRS("EPSG:32633") and not [w for w in warned if "Several features" in w], warned
    labels = {f["properties"]["label"] for f in doc["features"] if f["properties"]["kind"] == "site"}
    assert labels == {"walls", "facade"}                      # the DXF layers
    code, _, err = cli(capsys, command, dxf, "--geojson", out, "--crs", "none", *quiet)
    assert "crs" not in json.loads(out.read_text())
    code, _, err = cli(capsys, command, dxf, "--geojson", out, *quiet)
    assert json.loads(out.read_text())["crs"]["properties"]["name"].startswith("ENGCRS")


# ------------------------------------------------------------------------------------ arcs in queries


pytestmark = pytest.mark.mpmath_dps(40)


@pytest.fixture(autouse=True)
def _mpmath_digits():
    """40 digits for this module's references, restored after each test (another module's
    setting must not leak in, nor this one out)."""
    with mpmath.workdps(40):
        yield


def _ref_distance(site, q):
    """The distance from q to a site by definition, in 40-digit arithmetic: a point's |q − p|; a
    closed segment's distance to the clamped foot; a closed counter-clockwise arc's |‖q − c‖ − ρ|
    when the direction of q from c lies in the arc's angular range, else the nearer end's."""
    mp = mpmath.mp
    qx, qy = mp.mpf(q[0]), mp.mpf(q[1])

    def num(v):                     # Fraction or flint fmpq, exactly
        n, d = (v.numerator, v.denominator) if isinstance(v, Fraction) else (v.p, v.q)
        return mp.mpf(int(n)) / int(d)

    def to(p):
        return num(p[0]), num(p[1])

    if isinstance(site, S):
        (ax, ay), (bx, by) = to(site.p), to(site.q)
        t = ((qx - ax) * (bx - ax) + (qy - ay) * (by - ay)) / ((bx - ax) ** 2 + (by - ay) ** 2)
        t = min(max(t, 0), 1)
        return mp.hypot(qx - ax - t * (bx - ax), qy - ay - t * (by - ay))
    if isinstance(site, A):
        (cx, cy), (ax, ay), (bx, by) = to(site.c), to(site.a), to(site.b)
        rho = num(site.rho)
        ta, tb = mp.atan2(ay - cy, ax - cx), mp.atan2(by - cy, bx - cx)
        theta = mp.atan2(qy - cy, qx - cx)
        if (theta - ta) % (2 * mp.pi) <= (tb - ta) % (2 * mp.pi):
            return abs(mp.hypot(qx - cx, qy - cy) - rho)
        return min(mp.hypot(qx - ax, qy - ay), mp.hypot(qx - bx, qy - by))
    cx, cy = num(site.cx), num(site.cy)
    return mp.hypot(qx - cx, qy - cy)


ARC_SCENE = [S((0, 0), (1, 0)), (0, 3), A.circular((5, 5), 1, 0, 90)]


@pytest.fixture(scope="module")
def arc_diagram():
    return cv.voronoi(ARC_SCENE)


def test_cells_and_geopandas_with_an_arc_and_a_tied_point(arc_diagram):
    d = arc_diagram
    cells = d.cells()
    assert len(cells) == len(d.sites) and all(c.is_valid for c in cells)
    box = d.cells((-2, -2, 8, 8))
    assert sum(c.area for c in box) == pytest.approx(100, rel=1e-6)
    pytest.importorskip("geopandas")
    frames = d.to_geopandas()
    assert len(frames.cells) == len(frames.sites) == len(d.sites) and "arc" in frames.sites["kind"].tolist()


def test_nearest_and_site_distance_next_to_an_arc_match_the_definition(arc_diagram):
    d = arc_diagram
    rng = np.random.default_rng(7)
    P = np.vstack([rng.uniform(-2, 8, size=(300, 2)),
                   [[5, 5], [5.5, 5.5], [7, 7], [5, 3], [3, 5], [6.5, 5], [4, 4], [5.2, 5.1]]])
    ref = np.array([[float(_ref_distance(s, q)) for s in d.sites] for q in P.tolist()])
    assert np.allclose(d.site_distance(P), ref, rtol=1e-12, atol=1e-12)
    lo, hi = d.site_distance(P, bounds=True)
    for r, q in enumerate(P.tolist()):
        for j, s in enumerate(d.sites):
            exact = _ref_distance(s, q)
            assert lo[r, j] <= exact <= hi[r, j], (q, s)
    res = d.nearest(P)
    for r in range(len(P)):
        order = np.argsort(ref[r])
        if ref[r, order[1]] - ref[r, order[0]] > 1e-9:
            assert res.proved[r] and res.index[r] == order[0], (P[r], res.index[r], order[0])
        else:
            assert not res.proved[r] or res.index[r] in order[:2]
    # the arc's centre: both ends and the arc's interior at distance 1, the interior gives way
    k = len(P) - 8
    ends = sorted(i for i, s in enumerate(d.sites) if repr(s) in ("Point(6, 5)", "Point(5, 6)"))
    assert res.index[k] == -1 and res.ties[k] == tuple(ends) and res.exact[k]


def test_an_exact_tie_between_an_arc_and_a_point():
    # the upper half circle of radius 1 and the point (0, 5): (0, 3) is at distance 2 from both
    d = cv.voronoi([A((0, 0), 1, (1, 0), (-1, 0)), (0, 5)])
    res = d.nearest([[0, 3], [0, 2.5], [0.25, 3]])
    arc = next(i for i, s in enumerate(d.sites) if isinstance(s, A))
    top = next(i for i, s in enumerate(d.sites) if repr(s) == "Point(0, 5)")
    assert res.index[0] == -1 and res.ties[0] == tuple(sorted((arc, top))) and res.exact[0]
    assert res.index[1] == arc and res.proved[1] and res.distance[1] == pytest.approx(1.5)
    q = (0.25, 3)
    want = min(range(len(d.sites)), key=lambda j: _ref_distance(d.sites[j], q))
    assert res.index[2] == want and res.proved[2]


# ------------------------------------------------------------------------------------ verify
def test_verify_takes_xy_pairs_and_the_certificate_prints_one_line():
    sites = [(0, 0), (4, 0), (2, 4), (1, 1)]
    d = cv.voronoi(sites)
    c = cv.verify(d, sites)
    assert c.ok and not c.problems
    nv, ne = len(d.vertices), len(d.edges)
    assert repr(c) == f"Certificate(ok=True, {nv}/{nv} vertices, {ne}/{ne} edges proved, 0 problems)"
    assert "\n" not in repr(cv.verify(d, [(0, 0), (4, 0), (2, 4), (1, 2)]))
