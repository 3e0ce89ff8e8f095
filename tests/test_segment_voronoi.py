"""The Voronoi diagram of points and segments (thesis §2.2): closed-form diagrams and identities.

References here are computed in the test from the definitions (exact rationals or plain float
formulas written below), never with the library's distance code."""
from __future__ import annotations

import math
import sys
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest

import curvedvoronoi as cv
from curvedvoronoi.runtime.segments.construction import segment_voronoi

sys.path.insert(0, str(Path(__file__).parent))
from scenes import random_segments  # noqa: E402

S = cv.Segment


def seg_dist(q, a, b):
    """Distance from q to the closed segment [a, b], plain floats (the definition)."""
    ax, ay = a
    bx, by = b
    dx, dy = bx - ax, by - ay
    L2 = dx * dx + dy * dy
    t = 0.0 if L2 == 0 else max(0.0, min(1.0, ((q[0] - ax) * dx + (q[1] - ay) * dy) / L2))
    return math.hypot(q[0] - ax - t * dx, q[1] - ay - t * dy)


def site_dist(site, q):
    if isinstance(site, S):
        (a, b) = site.float_endpoints()
        return seg_dist(q, a, b)
    return math.hypot(q[0] - float(site.x), q[1] - float(site.y))


def test_two_points_one_bisector_line():
    d = segment_voronoi([(0, 0), (2, 0)], certify=False)
    assert d.vertices == [] and len(d.edges) == 1
    P = d.edges[0].polyline
    assert np.allclose(P[:, 0], 1.0)          # the perpendicular bisector x = 1
    assert d.edges[0].ends == (None, None)


def test_lone_segment_has_two_perpendiculars():
    d = segment_voronoi([S((0, 0), (4, 0))], certify=False)
    assert len(d.sites) == 3 and d.vertices == []
    xs = sorted(float(np.mean(e.polyline[:, 0])) for e in d.edges)
    assert xs == pytest.approx([0.0, 4.0])
    assert all(np.allclose(e.polyline[:, 0], e.polyline[0, 0]) for e in d.edges)   # vertical lines


def test_triangle_incircle_and_corners():
    # right triangle 3-4-5: the incircle has radius (3 + 4 - 5)/2 = 1, centre (1, 1)
    d = segment_voronoi([S((0, 0), (4, 0)), S((4, 0), (0, 3)), S((0, 3), (0, 0))], certify=False)
    inner = [v for v in d.vertices if v.radius > 0]
    corners = [v for v in d.vertices if v.radius == 0]
    assert len(corners) == 3
    assert any(abs(v.x - 1) < 1e-12 and abs(v.y - 1) < 1e-12 and abs(v.radius - 1) < 1e-12 for v in inner)
    # every vertex of the three segments' interiors alone is the incentre
    segs = {i for i, s in enumerate(d.sites) if isinstance(s, S)}
    assert [v for v in d.vertices if set(v.sites) == segs][0].radius == pytest.approx(1.0, abs=1e-12)


def test_rectangle_medial_vertices_and_square_degree_four():
    d = segment_voronoi([S((0, 0), (4, 0)), S((4, 0), (4, 2)), S((4, 2), (0, 2)), S((0, 2), (0, 0))], certify=False)
    inner = sorted((round(v.x, 12), round(v.y, 12), round(v.radius, 12)) for v in d.vertices if v.radius > 0)
    assert inner == [(1.0, 1.0, 1.0), (3.0, 1.0, 1.0)]
    sq = segment_voronoi([S((0, 0), (2, 0)), S((2, 0), (2, 2)), S((2, 2), (0, 2)), S((0, 2), (0, 0))], certify=False)
    centre = [v for v in sq.vertices if v.radius > 0]
    assert len(centre) == 1 and centre[0].degree == 4
    assert (centre[0].x, centre[0].y, centre[0].radius) == pytest.approx((1.0, 1.0, 1.0), abs=1e-12)
    assert not [p for p in sq.problems if "not verified" not in p]


def test_point_and_segment_parabola():
    # the bisector of the point (2, 2) and the segment [(0, 0), (4, 0)] is y = ((x - 2)² + 4)/4
    d = segment_voronoi([S((0, 0), (4, 0)), (2, 2)], certify=False)
    par = [e for e in d.edges if set(e.sites) == {2, 3}]
    assert len(par) == 1
    P = par[0].polyline
    assert np.max(np.abs(P[:, 1] - ((P[:, 0] - 2) ** 2 + 4) / 4)) <= par[0].tolerance + 1e-12
    assert len(P) > 3
    # its ends: equidistant from the point, the segment and an endpoint: x = 0 or 4, y = 2
    ends = sorted((round(d.vertices[v].x, 12), round(d.vertices[v].y, 12)) for v in par[0].ends)
    assert ends == [(0.0, 2.0), (4.0, 2.0)]


def test_straight_joint_merged_and_junction_refused():
    d = segment_voronoi([S((0, 0), (1, 0)), S((1, 0), (3, 0))], certify=False)
    assert len(d.sites) == 3          # (0,0), (3,0) and one merged interior; (1, 0) is not a site
    with pytest.raises(cv.SiteError, match="through a junction"):
        segment_voronoi([S((0, 0), (1, 0)), S((1, 0), (3, 0)), S((1, 0), (1, 2))], certify=False)


def test_crossing_segments_named():
    with pytest.raises(cv.SiteError, match="sites 0 and 1"):
        cv.voronoi([S((0, 0), (2, 2)), S((0, 2), (2, 0))])


def _check_diagram_facts(d):
    """Vertices equidistant from their sites and no site nearer; edge points nearest to their
    two sites; by the definitions, in floats with a relative margin."""
    sites = d.sites
    for v in d.vertices:
        q = (v.x, v.y)
        dist = np.array([site_dist(s, q) for s in sites])
        scale = 1e-9 * (1 + abs(v.x) + abs(v.y) + v.radius)
        assert np.all(np.abs(dist[list(v.sites)] - v.radius) <= scale), v
        others = np.delete(dist, list(v.sites))
        assert np.all(others >= v.radius - scale), v
    for e in d.edges:
        P = np.asarray(e.polyline)
        for q in P[1:-1:max(1, len(P) // 5)]:
            dist = np.array([site_dist(s, q) for s in sites])
            i, j = e.sites
            tol = e.tolerance * 2 + 1e-9 * (1 + abs(q).max())
            assert abs(dist[i] - dist[j]) <= 2 * tol + 1e-9
            assert np.delete(dist, [i, j]).min() >= min(dist[i], dist[j]) - 2 * tol


@pytest.mark.parametrize("n,seed", [(15, 0), (40, 1), (80, 2)])
def test_random_segments_satisfy_the_definitions(n, seed):
    segs = random_segments(n, seed)
    d = segment_voronoi([S(*s) for s in segs], certify=False)
    assert not [p for p in d.problems if "not verified" not in p], d.problems[:3]
    _check_diagram_facts(d)
    # Euler's formula for the planar graph with a vertex at infinity: every edge has two ends
    n_inf = sum(e.ends.count(None) for e in d.edges)
    assert 2 * len(d.edges) == sum(v.degree for v in d.vertices) + n_inf


def test_sources_map_back_to_the_input():
    pieces = [S((0, 0), (4, 0)), (2, 3), S((4, 0), (4, 3))]
    d = segment_voronoi(pieces, certify=False)
    for site, src in zip(d.sites, d.sources):
        if isinstance(site, S):
            assert pieces[src] == site
        elif isinstance(pieces[src], S):
            assert (Fraction(str(site.x)), Fraction(str(site.y))) in (pieces[src].p, pieces[src].q)
        else:
            assert (float(site.x), float(site.y)) == pieces[src]
