"""Equal disjoint circles have the Voronoi diagram of their centres (runtime/voronoi/verify/
equal_circles.py, the theorem and its proof; runtime/voronoi/equal_circles.py builds it).  The
rotated 8 × 8 grid of equal circles (float centres: nearly co-circular quadruples and nearly
collinear rows) was not certified by the sampled construction (far vertices of nearly collinear
circles missed).  References: CGAL's Apollonius_graph_2 on the same doubles (exact predicates) and
the exact Fraction diagram of the centres (tests/test_degenerate_cgal.py)."""
from __future__ import annotations

import copy
import math

import numpy as np
import pytest

import curvedvoronoi as cv
from curvedvoronoi.runtime.predicates.circles import Circle
from curvedvoronoi.runtime.voronoi.verify.equal_circles import equal_radius, separated_on

from test_degenerate_cgal import cgal_peer, ccw_order, exact_point_voronoi  # noqa: E402


def rotated_grid(n, angle, r):
    c, s = np.cos(angle), np.sin(angle)
    return [(float(c * x - s * y), float(s * x + c * y), r) for x in range(n) for y in range(n)]


@pytest.fixture(scope="module")
def grid_diagram():
    return cv.voronoi(rotated_grid(8, 0.3, 0.2), progress=False)


def test_rotated_grid_of_equal_circles_is_certified_and_equals_cgal(cgal_peer_program, grid_diagram):
    circles = rotated_grid(8, 0.3, 0.2)
    expected, _, hidden, _ = cgal_peer.delaunay_edges_nondegenerate(circles)
    assert hidden == 0
    d = grid_diagram
    assert d.delaunay_edges() == expected       # first: a wrong graph is worse than an unproved one
    assert d.certified, d.problems[:5]
    # vertices: positions, degrees and site order of the exact diagram of the centres; radii less ρ
    pts = [(x, y) for x, y, _ in circles]
    edges, verts = exact_point_voronoi(pts)
    assert sorted(edges) == expected
    want = {tuple(sorted(s)): v for v, s in verts.items()}
    got = {tuple(sorted(v.sites)): v for v in d.vertices}
    assert len(got) == len(d.vertices) == len(verts) and sorted(got) == sorted(want)
    far = 0
    for key, w in want.items():
        g = got[key]
        tol = 1e-9 + 4 * math.ulp(max(1.0, abs(float(w[0])), abs(float(w[1]))))
        assert abs(g.x - float(w[0])) <= tol and abs(g.y - float(w[1])) <= tol, (key, g.x, g.y)
        if len(key) == 3:
            # the three pairs are the edges whatever the order (float angles seen from a vertex
            # 10¹⁶ out cannot order nearly collinear centres; ccw_order cannot either)
            far += abs(g.x) > 1e6
        else:
            assert tuple(g.sites) == ccw_order(w, pts, key)
    assert far > 0                                  # nearly collinear rows: vertices far out
    assert sum(len(k) == 4 for k in want) == sum(v.degree == 4 for v in d.vertices)
    for v in d.vertices:
        cx, cy = circles[v.sites[0]][:2]
        assert abs(v.radius - (math.hypot(v.x - cx, v.y - cy) - 0.2)) <= 1e-9 + 4 * math.ulp(v.radius + 1)


def test_the_certificate_names_the_reduction(grid_diagram):
    c = cv.verify(grid_diagram.to_json())
    assert c.ok and c.stats["route"] == "equal circles as their centres"
    assert any("centres" in h for h in c.hypotheses)


def test_corrupted_equal_circle_diagrams_are_refused(grid_diagram):
    doc = grid_diagram.to_json()
    assert cv.verify(doc).ok
    bad = copy.deepcopy(doc)                       # one edge dropped
    k = max(range(len(bad["edges"])), key=lambda t: len(bad["edges"][t]["polyline"]) if None not in bad["edges"][t]["ends"] else 0)
    del bad["edges"][k]
    for t, e in enumerate(bad["edges"]):
        e["id"] = t
    bad["delaunay_edges"] = sorted({tuple(sorted(e["sites"])) for e in bad["edges"]})
    assert not cv.verify(bad).ok
    bad = copy.deepcopy(doc)                       # one vertex moved by 1e-3
    bad["vertices"][10]["x"] += 1e-3
    assert not cv.verify(bad).ok
    bad = copy.deepcopy(doc)                       # a vertex radius off by 1e-3 (the centres' radius stated)
    bad["vertices"][10]["radius"] += 1e-3
    assert not cv.verify(bad).ok
    # the same diagram for circles of another radius is still their diagram (the theorem) ...
    other = [Circle.from_radius(x, y, 0.3) for x, y, _ in rotated_grid(8, 0.3, 0.2)]
    bad = copy.deepcopy(grid_diagram)
    bad.construction = None
    bad.sites = other
    for v in bad.vertices:
        v.radius -= 0.1
    assert cv.verify(bad).ok
    # ... but not when the input sites differ from the diagram's
    assert not cv.verify(grid_diagram, other).ok


def test_intersecting_equal_circles_are_not_reduced():
    """Centres 1.5 apart, radius 1: the circles intersect, the theorem does not apply, and the
    centres' (valid) diagram read as circles is refused."""
    pts = [(0, 0), (1.5, 0), (0, 5), (3, 4)]
    P = cv.voronoi(pts, certify=False, progress=False)
    D = copy.deepcopy(P)
    D.construction = None
    D.sites = [Circle.from_radius(x, y, 1) for x, y in pts]
    for v in D.vertices:
        v.radius -= 1
    c = cv.verify(D)
    assert not c.ok and c.stats.get("route") != "equal circles as their centres"


def test_separation_is_exact_at_twice_the_radius():
    """Centres exactly 2ρ apart (touching circles): not separated; 2ρ plus one ulp: separated."""
    a = Circle.from_radius(0.0, 0.0, 0.5)
    for x, want in ((1.0, 1), (math.nextafter(1.0, 2.0), 0), (math.nextafter(1.0, 0.0), 1)):
        b = Circle.from_radius(x, 0.0, 0.5)
        assert len(separated_on([a, b], [(0, 1)], a.r2)) == want
    assert equal_radius([a, Circle.from_radius(3, 0, 0.5)]) == a.r2 and float(a.r2) == 0.25
    assert equal_radius([a, Circle.from_radius(3, 0, 0.25)]) is None
    assert equal_radius([a, cv.Circle.from_radius(3, 0, 0)]) is None        # a point is no circle here
