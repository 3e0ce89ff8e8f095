"""Corruptions of diagrams with vertices of degree k > 3 are rejected, naming the part: a vertex
whose sites are listed in the wrong cyclic order, a degree-4 vertex split into two triples at one
point (the old way of reporting it), a site dropped from a vertex, a short edge of nearly
co-circular floats removed.  Expectations from geometry (the 2×2 cell of a grid, a ring)."""
from __future__ import annotations

import copy
import math

import curvedvoronoi as cv


def grid_doc():
    d = cv.voronoi([(i, j, 0) for i in range(3) for j in range(3)])
    assert d.certified, d.problems
    return d.to_json()


def renumber(doc):
    for t, e in enumerate(doc["edges"]):
        e["id"] = t
    doc["delaunay_edges"] = sorted({tuple(sorted(e["sites"])) for e in doc["edges"]})
    return doc


def test_wrong_cyclic_order_is_rejected():
    doc = grid_doc()
    v = doc["vertices"][0]
    a, b, c, d = v["sites"]
    v["sites"] = [a, c, b, d]                   # a diagonal pair made consecutive
    cert = cv.verify(doc)
    assert not cert.ok and any(f"vertex {v['id']} " in p for p in cert.problems), cert.problems


def test_a_degree_four_vertex_split_into_two_triples_is_rejected():
    doc = grid_doc()
    v = doc["vertices"][0]
    s = v["sites"]
    w = dict(v, id=len(doc["vertices"]), sites=[s[0], s[2], s[3]])
    v["sites"] = [s[0], s[1], s[2]]
    doc["vertices"].append(w)
    cert = cv.verify(doc)
    assert not cert.ok                           # the fourth site touches each triple's circle


def test_a_site_dropped_from_a_vertex_is_rejected():
    doc = grid_doc()
    doc["vertices"][0]["sites"] = doc["vertices"][0]["sites"][:3]
    assert not cv.verify(doc).ok


def test_a_short_edge_of_a_float_ring_removed_is_rejected():
    ring = [(10 * math.cos(2 * math.pi * k / 12), 10 * math.sin(2 * math.pi * k / 12), 1) for k in range(12)]
    d = cv.voronoi(ring)
    assert d.certified and len(d.edges) == 21
    doc = d.to_json()
    bounded = [t for t, e in enumerate(doc["edges"]) if None not in e["ends"]]
    bad = copy.deepcopy(doc)
    del bad["edges"][bounded[0]]
    cert = cv.verify(renumber(bad))
    assert not cert.ok and cert.problems


def test_unbounded_sites_alone_or_around_a_point_give_a_diagram_not_an_exception():
    """A point at the centre of a hyperbola (the bounded sites' box is one point: the sampling
    window once had size 0 and qhull raised), a point beside a parabola, two parabolas: a diagram
    comes back, with what is not proved named."""
    C = cv.Conic
    for sites in ([C.hyperbola(centre=(0, 0), axes=(2, 1)), (0, 0, 0)],
                  [C.parabola(vertex=(0, 0), p=1), (-3, 0, 0)],
                  [C.from_coefficients(1, 0, 0, 0, -1, 1), C.from_coefficients(-1, 0, 0, 0, -1, -1)]):
        d = cv.voronoi(sites, time_limit=60)
        assert d.edges and (d.certified or d.problems)
