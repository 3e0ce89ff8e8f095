"""Command line for segments: `diagram part.dxf|shapes.geojson|sites.json` (segment diagrams) and
`medial-axis shape.{dxf,geojson,json}` (runtime/segments/command.py): outputs, the one summary
line, exit codes (0 certified, 1 not certified, 2 bad input naming the entity), the outer/hole rule."""
from __future__ import annotations

import json
import math
import os
import re
import subprocess
import sys
from pathlib import Path

import networkx as nx
import numpy as np
import pytest

from curvedvoronoi.runtime.cli import main

ROOT = Path(__file__).resolve().parents[1]

RECT = [(0, 0), (4, 0), (4, 2), (0, 2)]


def cli(capsys, *args):
    """(exit status, stdout, stderr) of the command run in this process."""
    code = main([str(a) for a in args])
    out = capsys.readouterr()
    return code, out.out, out.err


def one_error_line(err: str) -> str:
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("error: "), err
    return lines[0]


def sites_file(tmp_path, segments, name="sites.json") -> Path:
    p = tmp_path / name
    p.write_text(json.dumps({"sites": [{"segment": [list(a), list(b)]} for a, b in segments]}))
    return p


def ring(pts):
    return list(zip(pts, pts[1:] + pts[:1]))


def geojson_file(tmp_path, geometry, name="shape.geojson") -> Path:
    p = tmp_path / name
    p.write_text(json.dumps({"type": "Feature", "properties": {}, "geometry": geometry}))
    return p


def dxf_file(tmp_path, build, name="part.dxf") -> Path:
    ezdxf = pytest.importorskip("ezdxf", reason="DXF input needs ezdxf (test extra)")
    doc = ezdxf.new()
    build(doc.modelspace())
    p = tmp_path / name
    doc.saveas(p)
    return p


def closed(msp, pts, layer="0"):
    msp.add_lwpolyline(pts, close=True, dxfattribs={"layer": layer})


# ------------------------------------------------------------------------------------ diagram
def test_diagram_of_a_sites_file_with_segment_records(tmp_path, capsys):
    out = tmp_path / "d.json"
    code, _, err = cli(capsys, "diagram", sites_file(tmp_path, ring(RECT)), "--json", out, "--quiet")
    doc = json.loads(out.read_text())
    assert code == (0 if doc["certified"] else 1), err
    assert sum("segment" in s for s in doc["sites"]) == 4 and sum("point" in s for s in doc["sites"]) == 4


def test_diagram_of_a_dxf_drawing_outputs_and_sources(tmp_path, capsys):
    def build(msp):
        msp.add_line((0, 0), (4, 0), dxfattribs={"layer": "a"})
        msp.add_line((4, 0), (4, 3), dxfattribs={"layer": "b"})
        msp.add_line((4, 3), (0, 0), dxfattribs={"layer": "c"})
        msp.add_point((10, 10))

    dxf = dxf_file(tmp_path, build)
    paths = {k: tmp_path / f"d.{k}" for k in ("json", "png", "geojson")}
    code, out, err = cli(capsys, "diagram", dxf, "--json", paths["json"], "--png", paths["png"],
                         "--geojson", paths["geojson"])
    doc = json.loads(paths["json"].read_text())
    assert code == (0 if doc["certified"] else 1), err
    assert paths["png"].stat().st_size > 1000
    assert json.loads(paths["geojson"].read_text())["type"] == "FeatureCollection"
    # 4 point sites (3 corners + the POINT), 3 open segments; each source is its DXF entity (0..3)
    assert len(doc["sites"]) == 7
    seg_sources = sorted(s["source"] for s in doc["sites"] if "segment" in s)
    assert seg_sources == [0, 1, 2]
    assert {"point": ["10", "10"], "label": "0", "source": 3} in doc["sites"]      # the label: its layer
    assert re.search(r"^7 sites, \d+ vertices, \d+ edges, \d+ Delaunay edges, certified=", err, re.M)


def test_diagram_of_geojson(tmp_path, capsys):
    g = geojson_file(tmp_path, {"type": "Polygon", "coordinates": [[list(p) for p in RECT + [RECT[0]]]]})
    out = tmp_path / "d.json"
    code, _, err = cli(capsys, "diagram", g, "--json", out, "--quiet")
    doc = json.loads(out.read_text())
    assert code == (0 if doc["certified"] else 1), err
    assert len(doc["sites"]) == 8 and {s["source"] for s in doc["sites"]} == {0}


@pytest.mark.parametrize("case", ["crossing", "ellipse", "text", "z"])
def test_diagram_bad_drawing_exits_2_with_one_line_naming_the_entity(tmp_path, capsys, case):
    if case == "z":
        g = geojson_file(tmp_path, {"type": "LineString", "coordinates": [[0, 0, 1], [1, 1, 1]]})
        code, _, err = cli(capsys, "diagram", g)
        assert code == 2 and "3-D coordinates" in one_error_line(err)
        return

    def build(msp):
        closed(msp, RECT, layer="walls")
        if case == "crossing":
            msp.add_line((1, 1), (7, 2), dxfattribs={"layer": "cut"})
        elif case == "ellipse":
            msp.add_ellipse((2, 1), major_axis=(1, 0), ratio=1)       # a circle drawn as an ELLIPSE: refused
        else:
            msp.add_text("label")

    code, _, err = cli(capsys, "diagram", dxf_file(tmp_path, build))
    line = one_error_line(err)
    assert code == 2
    if case == "crossing":
        assert "LWPOLYLINE (handle" in line and "layer 'walls'" in line and "LINE (handle" in line
        assert "layer 'cut'" in line and "cross at (4, 3/2)" in line
    elif case == "ellipse":
        assert "ELLIPSE (handle" in line
    else:
        assert "TEXT (handle" in line and "--skip TEXT" in line


def test_diagram_skip_ignores_entity_types_and_is_refused_for_sites_files(tmp_path, capsys):
    dxf = dxf_file(tmp_path, lambda msp: (closed(msp, RECT), msp.add_text("label")))
    out = tmp_path / "d.json"
    code, _, err = cli(capsys, "diagram", dxf, "--skip", "text,mtext", "--json", out, "--quiet")
    assert code in (0, 1) and len(json.loads(out.read_text())["sites"]) == 8, err
    code, _, err = cli(capsys, "diagram", sites_file(tmp_path, ring(RECT)), "--skip", "TEXT")
    assert code == 2 and "--skip" in one_error_line(err)


# ------------------------------------------------------------------------------------ medial-axis
SUMMARY = re.compile(r"^medial axis: (\d+) edges, (\d+) vertices, largest inscribed circle centre "
                     r"\((\S+), (\S+)\) radius (\S+), certified=(True|False)")


def summary(out: str):
    lines = out.strip().splitlines()
    assert len(lines) == 1, out
    m = SUMMARY.match(lines[0])
    assert m, out
    return int(m[1]), int(m[2]), (float(m[3]), float(m[4]), float(m[5])), m[6] == "True"


@pytest.mark.parametrize("form", ["json", "geojson", "dxf", "geojson-in-json"])
def test_medial_axis_of_a_rectangle_in_each_input_form(tmp_path, capsys, form):
    if form == "json":
        src = sites_file(tmp_path, ring(RECT))
    elif form == "dxf":
        src = dxf_file(tmp_path, lambda msp: closed(msp, RECT))
    else:
        src = geojson_file(tmp_path, {"type": "Polygon", "coordinates": [[list(p) for p in RECT]]},
                           name="shape.json" if form == "geojson-in-json" else "shape.geojson")
    paths = {k: tmp_path / f"m.{k}" for k in ("json", "png", "geojson")}
    code, out, err = cli(capsys, "medial-axis", src, "--json", paths["json"], "--png", paths["png"],
                         "--geojson", paths["geojson"])
    edges, verts, (x, y, r), certified = summary(out)
    assert code == (0 if certified else 1), err
    assert (edges, verts) == (5, 6) and r == pytest.approx(1) and y == pytest.approx(1) and x in (1, 3)
    doc = json.loads(paths["json"].read_text())
    assert doc["format"] == "curvedvoronoi.medial_axis/1" and doc["certified"] is certified
    inner = sorted((round(v["x"], 9), round(v["y"], 9), round(v["radius"], 9)) for v in doc["vertices"]
                   if v["radius"] > 0)
    assert inner == [(1, 1, 1), (3, 1, 1)]
    for e in doc["edges"]:
        assert len(e["polyline"]) == len(e["radius"]) >= 2
    assert doc["largest_inscribed_circle"]["radius"] == pytest.approx(1)
    gj = json.loads(paths["geojson"].read_text())
    assert sum(f["properties"]["kind"] == "edge" for f in gj["features"]) == 5
    assert paths["png"].stat().st_size > 1000


def test_medial_axis_outer_and_hole_from_a_dxf_by_the_containment_rule(tmp_path, capsys):
    # the hole comes first in the file: the rule, not the order, makes the other loop the outer one
    dxf = dxf_file(tmp_path, lambda msp: (closed(msp, [(2, 2), (4, 2), (4, 4), (2, 4)], "hole"),
                                          closed(msp, [(0, 0), (6, 0), (6, 6), (0, 6)], "outer")))
    out = tmp_path / "m.json"
    code, stdout, err = cli(capsys, "medial-axis", dxf, "--json", out)
    *_, certified = summary(stdout)
    assert code == (0 if certified else 1), err
    doc = json.loads(out.read_text())
    G = nx.Graph([tuple(e["ends"]) for e in doc["edges"]])
    assert len(nx.cycle_basis(G)) == 1                     # around the hole
    assert sorted(d for _, d in G.degree() if d == 1) == [1, 1, 1, 1]   # the outer boundary's 4 corners
    assert {s["source"] for s in doc["sites"]} == {0, 1}   # DXF entities: the hole is entity 0


def test_medial_axis_exit_1_when_not_certified(tmp_path, capsys, monkeypatch):
    import curvedvoronoi.runtime.segments.medial_axis as ma

    real = ma.medial_axis

    def uncertified(*a, **k):
        m = real(*a, **k)
        m.certified = False
        m.problems = ["planted: not proved"] + m.problems
        return m

    monkeypatch.setattr(ma, "medial_axis", uncertified)
    out = tmp_path / "m.json"
    code, stdout, _ = cli(capsys, "medial-axis", sites_file(tmp_path, ring(RECT)), "--json", out)
    assert code == 1 and "certified=False; " in stdout and "first: planted: not proved" in stdout
    assert json.loads(out.read_text())["certified"] is False       # the outputs are still written
    code, stdout, _ = cli(capsys, "medial-axis", sites_file(tmp_path, ring(RECT)), "--no-certify", "-q")
    assert code == 0 and stdout == ""


def _two(msp):
    closed(msp, RECT)
    closed(msp, [(5, 0), (7, 0), (7, 2)])


def _island(msp):
    closed(msp, [(0, 0), (10, 0), (10, 10), (0, 10)])
    closed(msp, [(2, 2), (8, 2), (8, 8), (2, 8)])
    closed(msp, [(4, 4), (6, 4), (6, 6), (4, 6)])


BAD_DXF = {
    "side by side": (_two, "none contains all the others"),
    "island": (_island, "LWPOLYLINE (handle 31, layer '0') lies inside the hole LWPOLYLINE (handle 30"),
    "open": (lambda msp: msp.add_lwpolyline(RECT, close=False), "LWPOLYLINE (handle 2F, layer '0') segment 0: "
                                                              "its end (0, 0) is not joined"),
    "point": (lambda msp: (closed(msp, RECT), msp.add_point((1, 1))), "POINT (handle 30"),
    "open arc": (lambda msp: (closed(msp, RECT), msp.add_arc((2, 1), 0.5, 0, 90)),
                 "ARC (handle 30, layer '0'): its end (5/2, 1) is not joined to another segment or arc"),
    "open bulge": (lambda msp: msp.add_lwpolyline([(0, 0, 1), (2, 0, 0), (2, 2, 0)], format="xyb"),
                   "LWPOLYLINE (handle 2F, layer '0') arc 0: its end (0, 0) is not joined"),
    "touching": (lambda msp: (closed(msp, RECT), closed(msp, [(4, 2), (5, 3), (4, 3)])), "4 segments meet at (4, 2)"),
}


@pytest.mark.parametrize("case", sorted(BAD_DXF))
def test_medial_axis_bad_dxf_exits_2_with_one_line(tmp_path, capsys, case):
    build, needle = BAD_DXF[case]
    code, out, err = cli(capsys, "medial-axis", dxf_file(tmp_path, build))
    assert code == 2 and out == ""
    assert needle in one_error_line(err)


BAD_OTHER = {
    "linestring": ({"type": "LineString", "coordinates": [[0, 0], [1, 1]]}, "needs polygons"),
    "hole outside": ({"type": "Polygon", "coordinates": [[[0, 0], [4, 0], [4, 2], [0, 2]],
                                                         [[5, 0], [6, 0], [6, 1]]]}, "hole 0 is not inside its shell"),
    "overlap": ({"type": "MultiPolygon", "coordinates": [[[[0, 0], [9, 0], [9, 9], [0, 9]]],
                                                         [[[1, 1], [2, 1], [2, 2]]]]}, "polygons must not overlap"),
    "open sites": ([(RECT[0], RECT[1]), (RECT[1], RECT[2])], "is not joined to another segment"),
    "crossing sites": (ring(RECT) + [((1, 1), (5, 1))], "site 1 (segment) and site 4 (segment): segments cross"),
    "circle in sites": ([{"segment": [[0, 0], [4, 0]]}, {"circle": {"centre": [2, 5], "radius": 1}}],
                        "site 1 (circle): a circle is not supported in the boundary of the medial axis"),
}


@pytest.mark.parametrize("case", sorted(BAD_OTHER))
def test_medial_axis_bad_geojson_or_sites_exits_2_with_one_line(tmp_path, capsys, case):
    data, needle = BAD_OTHER[case]
    if isinstance(data, list) and isinstance(data[0], dict):           # records as they are
        src = tmp_path / "sites.json"
        src.write_text(json.dumps({"sites": data}))
    else:
        src = sites_file(tmp_path, data) if isinstance(data, list) else geojson_file(tmp_path, data)
    code, out, err = cli(capsys, "medial-axis", src)
    assert code == 2 and out == ""
    assert needle in one_error_line(err)


def test_medial_axis_of_a_multipolygon_is_the_union_of_the_axes(tmp_path, capsys):
    sq = lambda x0: [[x0, 0], [x0 + 2, 0], [x0 + 2, 2], [x0, 2]]      # noqa: E731
    g = geojson_file(tmp_path, {"type": "MultiPolygon", "coordinates": [[sq(0)], [sq(5)]]})
    out = tmp_path / "m.json"
    code, stdout, err = cli(capsys, "medial-axis", g, "--json", out, "--no-certify")
    assert code == 0, err
    doc = json.loads(out.read_text())
    centres = sorted((round(v["x"], 9), round(v["y"], 9)) for v in doc["vertices"] if v["radius"] > 0)
    assert centres == [(1, 1), (6, 1)]                      # each square's degree-4 centre
    assert len(doc["edges"]) == 8


def test_the_installed_command_lists_and_runs_medial_axis(tmp_path):
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    run = lambda *a: subprocess.run([sys.executable, "-m", "curvedvoronoi", *map(str, a)], cwd=ROOT, env=env,  # noqa: E731
                                    capture_output=True, text=True, timeout=300)
    assert "medial-axis" in run("--help").stdout
    r = run("medial-axis", "--help")
    assert r.returncode == 0 and "the loop containing all the" in r.stdout.replace("\n", " ").replace("  ", " ")
    r = run("medial-axis", sites_file(tmp_path, ring(RECT)))
    edges, verts, _, certified = summary(r.stdout)
    assert r.returncode == (0 if certified else 1) and (edges, verts) == (5, 6)


# ------------------------------------------------------------------------------------ arcs
def arc_record(centre, radius, start, end):
    return {"arc": {"centre": list(centre), "radius": radius, "start": list(start), "end": list(end)}}


#: the stadium [0, 4] x [0, 2] with half discs of radius 1 at both ends, as exact sites records
STADIUM = [{"segment": [[0, 0], [4, 0]]}, arc_record((4, 1), 1, (4, 0), (4, 2)),
           {"segment": [[4, 2], [0, 2]]}, arc_record((0, 1), 1, (0, 2), (0, 0))]


def stadium(msp, length=4, r=1):
    """LINEs and ARC entities: the stadium [0, length] x [0, 2r] with half discs at both ends."""
    msp.add_line((0, 0), (length, 0))
    msp.add_arc((length, r), r, -90, 90)
    msp.add_line((length, 2 * r), (0, 2 * r))
    msp.add_arc((0, r), r, 90, 270)


def status_agrees(code, certified, summary_line):
    """Exit 0 when certified, else 1 with the first problem in the summary line (diagrams with
    arcs may not be certified yet: the certificate for arcs is being extended)."""
    assert code == (0 if certified else 1), summary_line
    assert certified or re.search(r"certified=False; \d+ problems, first: \S", summary_line), summary_line


def near(doc_vertices, x, y, r, tol=1e-9):
    return [v for v in doc_vertices if abs(v["x"] - x) < tol and abs(v["y"] - y) < tol and abs(v["radius"] - r) < tol]


def test_medial_axis_of_a_stadium_of_dxf_arc_entities(tmp_path, capsys):
    """Closed form: the segment joining the half discs' centres (0, 1) and (4, 1), radius 1 along it."""
    out = tmp_path / "m.json"
    code, stdout, err = cli(capsys, "medial-axis", dxf_file(tmp_path, stadium), "--json", out)
    edges, verts, (x, y, r), certified = summary(stdout)
    status_agrees(code, certified, stdout)
    doc = json.loads(out.read_text())
    assert (edges, verts) == (1, 2) and r == pytest.approx(1) and y == pytest.approx(1)
    assert near(doc["vertices"], 0, 1, 1) and near(doc["vertices"], 4, 1, 1)
    P, R = np.array(doc["edges"][0]["polyline"]), np.array(doc["edges"][0]["radius"])
    assert np.allclose(P[:, 1], 1, atol=1e-9) and np.allclose(R, 1, atol=1e-9)
    assert sorted(P[[0, -1], 0].round(9).tolist()) == [0, 4]
    arcs = [s for s in doc["sites"] if "arc" in s]
    assert sorted(s["source"] for s in arcs) == [1, 3]                 # the ARC entities
    assert {s["arc"]["radius"] for s in arcs} == {"1"}
    # the same drawing through `diagram`: the arcs are sites there too
    code, _, err = cli(capsys, "diagram", dxf_file(tmp_path, stadium, "d.dxf"), "--json", tmp_path / "d.json")
    d = json.loads((tmp_path / "d.json").read_text())
    status_agrees(code, d["certified"], err)
    assert sum("arc" in s for s in d["sites"]) == 2


def test_medial_axis_circular_hole_of_two_arcs_comes_first_in_the_dxf(tmp_path, capsys):
    """A stadium of half-width 3 around [0, 8] with a hole of radius 1/2 at (4, 3) (two ARCs, drawn
    first): the containment rule with arcs makes the stadium the outer boundary.  Closed form: the
    centre line from (0, 3) to (1/2, 3) and from (15/2, 3) to (8, 3) (radius 3), and around the hole
    two parabola-like branches (|v - (4, 3)| - 1/2 = distance to the straight side)."""
    def build(msp):
        msp.add_arc((4, 3), 0.5, 0, 180)
        msp.add_arc((4, 3), 0.5, 180, 360)
        stadium(msp, 8, 3)

    out = tmp_path / "m.json"
    code, stdout, err = cli(capsys, "medial-axis", dxf_file(tmp_path, build), "--json", out)
    *_, certified = summary(stdout)
    status_agrees(code, certified, stdout)
    doc = json.loads(out.read_text())
    for x in (0, 0.5, 7.5, 8):
        assert near(doc["vertices"], x, 3, 3), x
    G = nx.MultiGraph([tuple(e["ends"]) for e in doc["edges"]])        # two branches (0.5, 3) -- (7.5, 3)
    assert G.number_of_edges() - G.number_of_nodes() + nx.number_connected_components(G) == 1   # around the hole
    for e in doc["edges"]:                                              # radius = distance to the hole
        P, R = np.array(e["polyline"]), np.array(e["radius"])
        assert np.allclose(R, np.hypot(P[:, 0] - 4, P[:, 1] - 3) - 0.5, atol=1e-6) or np.allclose(R, 3, atol=1e-9)
    assert {s["source"] for s in doc["sites"] if "arc" in s} == {0, 1, 3, 5}


def test_loop_containment_uses_the_exact_arcs_not_their_chords():
    """A hole in the bulge of a half disc, outside the polygon of the arc's endpoints."""
    from curvedvoronoi import Arc, Segment
    from curvedvoronoi.runtime.segments.loops import loop_contains

    half_disc = [Segment((0, 2), (0, -2)), Arc((0, 0), 2, (0, -2), (0, 2))]
    tri = [Segment((1, "-1/5"), ("199/100", 0)), Segment(("199/100", 0), (1, "1/5")), Segment((1, "1/5"), (1, "-1/5"))]
    assert loop_contains(half_disc, tri) and not loop_contains(tri, half_disc)
    outside = [Segment(("201/100", 0), (3, 1)), Segment((3, 1), (3, -1)), Segment((3, -1), ("201/100", 0))]
    assert not loop_contains(half_disc, outside)
    circle = [Arc((0, 0), 3, (3, 0), (-3, 0)), Arc((0, 0), 3, (-3, 0), (3, 0))]     # a loop of arcs only
    assert loop_contains(circle, half_disc) and not loop_contains(half_disc, circle)


def test_medial_axis_of_a_dxf_rounded_rectangle_of_bulges(tmp_path, capsys):
    """[0, 8] x [0, 4] with fillets of radius 1 (LWPOLYLINE bulges tan(22.5°)).  Closed form: the
    middle segment from (2, 2) to (6, 2) (radius 2), and from its ends diagonal segments to the
    fillets' centres (1, 1), (7, 1), (7, 3), (1, 3) (radius 1 there, r = 2 - |x - 2| along them)."""
    b = math.tan(math.pi / 8)
    pts = [(1, 0, 0), (7, 0, b), (8, 1, 0), (8, 3, b), (7, 4, 0), (1, 4, b), (0, 3, 0), (0, 1, b)]
    dxf = dxf_file(tmp_path, lambda msp: msp.add_lwpolyline(pts, format="xyb", close=True))
    _check_rounded_rectangle(capsys, dxf, tmp_path / "m.json")


def test_medial_axis_of_an_exact_rounded_rectangle_in_sites_json(tmp_path, capsys):
    """The rounded rectangle of the test above with exact fillets (arc records)."""
    recs = [{"segment": [[1, 0], [7, 0]]}, arc_record((7, 1), 1, (7, 0), (8, 1)), {"segment": [[8, 1], [8, 3]]},
            arc_record((7, 3), 1, (8, 3), (7, 4)), {"segment": [[7, 4], [1, 4]]}, arc_record((1, 3), 1, (1, 4), (0, 3)),
            {"segment": [[0, 3], [0, 1]]}, arc_record((1, 1), 1, (0, 1), (1, 0))]
    src = tmp_path / "rr.json"
    src.write_text(json.dumps({"sites": recs}))
    _check_rounded_rectangle(capsys, src, tmp_path / "m.json")


def _check_rounded_rectangle(capsys, src, out):
    code, stdout, _ = cli(capsys, "medial-axis", src, "--json", out)
    edges, verts, (x, y, r), certified = summary(stdout)
    status_agrees(code, certified, stdout)
    doc = json.loads(out.read_text())
    assert r == pytest.approx(2) and y == pytest.approx(2) and x in (pytest.approx(2), pytest.approx(6))
    for cx, cy in ((1, 1), (7, 1), (7, 3), (1, 3)):
        assert near(doc["vertices"], cx, cy, 1), (cx, cy)
    assert near(doc["vertices"], 2, 2, 2) and near(doc["vertices"], 6, 2, 2)
    assert (edges, verts) == (5, 6)
    middle = [e for e in doc["edges"] if np.allclose(np.array(e["polyline"])[:, 1], 2, atol=1e-9)]
    assert len(middle) == 1 and np.allclose(middle[0]["radius"], 2, atol=1e-9)
    assert sorted(np.array(middle[0]["polyline"])[[0, -1], 0].round(9).tolist()) == [2, 6]
    for e in doc["edges"]:                                   # r = distance to the nearest straight side
        P, R = np.array(e["polyline"]), np.array(e["radius"])
        assert np.allclose(R, np.minimum.reduce([P[:, 1], 4 - P[:, 1], P[:, 0], 8 - P[:, 0]]), atol=1e-9)


def test_diagram_of_a_sites_file_with_arc_records(tmp_path, capsys):
    """The stadium as exact segment and arc records: the arcs are sites of the diagram (written in
    their exact form), and the half discs' centres are Voronoi vertices at distance 1."""
    src = tmp_path / "stadium.json"
    src.write_text(json.dumps({"sites": STADIUM}))
    out = tmp_path / "d.json"
    code, _, err = cli(capsys, "diagram", src, "--json", out)
    doc = json.loads(out.read_text())
    status_agrees(code, doc["certified"], err)
    assert [next(iter(s)) for s in doc["sites"]] == ["segment", "arc", "segment", "arc"]
    assert doc["sites"][1]["arc"] == {"centre": ["4", "1"], "radius": "1", "start": ["4", "0"], "end": ["4", "2"]}
    xy = sorted((round(v["x"], 9), round(v["y"], 9)) for v in doc["vertices"])
    assert xy == [(0, 1), (4, 1)], doc["vertices"]
    assert re.search(r"^4 sites, 2 vertices, \d+ edges, \d+ Delaunay edges, certified=", err, re.M)
