"""Problems of a certificate as records (runtime/voronoi/verify/problems.py): the faults name the
vertex, edge and sites by field, in Python and in JSON, so that the construction's refinement does
not depend on the wording of a message."""
from __future__ import annotations

import copy
import json

import curvedvoronoi as cv
from curvedvoronoi.runtime.voronoi.verify.problems import Problem


def _doc():
    d = cv.voronoi([(0, 0, 1), (6, 0, 1), (3, 5, 1), (3, -5, 1)])
    assert d.certified, d.problems
    return d.to_json()


def test_an_ignored_site_is_a_fault_naming_the_edge_and_the_sites():
    doc = _doc()
    # drop site 3 from the diagram: its region is missing, and it is closer than the sites of the
    # edges that now run through it
    bad = copy.deepcopy(doc)
    bad["edges"] = [e for e in bad["edges"] if 3 not in e["sites"]]
    bad["vertices"] = [v for v in bad["vertices"] if 3 not in v["sites"]]
    ids = {}
    for t, v in enumerate(bad["vertices"]):
        ids[v["id"]] = t
        v["id"] = t
    for t, e in enumerate(bad["edges"]):
        e["id"] = t
        e["ends"] = [None if x is None or x not in ids else ids[x] for x in e["ends"]]
    bad["delaunay_edges"] = sorted({tuple(e["sites"]) for e in bad["edges"]})
    cert = cv.verify(bad)
    assert not cert.ok
    faults = [p for p in cert.problems if isinstance(p, Problem) and p.fault]
    assert faults and any(3 in p.sites for p in faults), cert.problems
    rec = json.loads(json.dumps(cert.to_json()))["problem_records"]
    assert len(rec) == len(cert.problems) and [r["message"] for r in rec] == [str(p) for p in cert.problems]
    assert any(r["fault"] and 3 in r["sites"] for r in rec)
    for r in rec:
        assert set(r) == {"kind", "sites", "vertex", "edge", "fault", "message"}


def test_a_vertex_with_a_site_inside_its_circle_is_a_vertex_fault():
    doc = _doc()
    bad = copy.deepcopy(doc)
    # site 2 moved onto the vertex's circle's inside: the vertex of 0, 1, 3 is no longer empty
    v = next(v for v in bad["vertices"] if sorted(v["sites"]) == [0, 1, 3])
    bad["sites"][2] = {"circle": {"centre": [str(v["x"]), str(v["y"] + v["radius"] / 2)], "radius": "1/10"}}
    cert = cv.verify(bad)
    assert not cert.ok
    hits = [p for p in cert.problems if isinstance(p, Problem) and p.kind == "vertex" and p.vertex == v["id"]]
    assert hits and all(2 in p.sites and p.fault for p in hits), cert.problems


def test_plain_lines_are_limits_and_messages_do_not_drive_refinement():
    """A Problem is a str (lists print as before); a plain string, whatever it says, is a limit."""
    p = Problem("anything at all", kind="edge", edge=4, sites=(1, 2), fault=True)
    assert p == "anything at all" and p.sites == (1, 2) and p.edge == 4 and p.fault
    from curvedvoronoi.runtime.voronoi.verify.problems import records

    r = records([p, "edge 4 (sites 1, 2): site 3 too close to decide"])
    assert r[0]["fault"] and r[0]["sites"] == [1, 2]
    assert not r[1]["fault"] and r[1]["sites"] == []
