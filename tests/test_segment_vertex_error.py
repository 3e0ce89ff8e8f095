"""A 64-gon of radius 10⁴ with integer vertices (the bore of the gear benchmark): near its centre
the medial axis's vertices are intersections of nearly parallel angle bisectors, known to about
10⁻¹⁰ although they lie within 10 units of the origin.  Each edge's stated ``tolerance`` must
bound the distance from its polyline to the true bisector arc, ends included, so it has to carry
the error of its float end vertices (runtime/segments/edges.vertex_error): 10⁻¹² of |x| + |y|
(the former bound, 6·10⁻¹²) is not enough there, and the certificate refused 24 edges.

Reference: each vertex whose sites are three or more segments is the centre of the circle tangent
to their lines on the polygon's inner side, solved in mpmath at 60 digits from the integer
coordinates (n_k·x − r = n_k·a_k for the unit inner normals n_k), independent of the library."""
from __future__ import annotations

import math
from fractions import Fraction

import mpmath
import shapely

import curvedvoronoi as cv

R = 10000
POLYGON = [(round(R * math.cos(2 * math.pi * k / 64)), round(R * math.sin(2 * math.pi * k / 64))) for k in range(64)]


def _exact_vertex(lines):
    """(x, y, r) of the circle inside the counter-clockwise polygon tangent to the first three
    lines [(a, b)] (mpmath, 60 digits)."""
    with mpmath.workdps(60):
        rows, rhs = [], []
        for a, b in lines[:3]:
            (ax, ay), (bx, by) = [[mpmath.mpf(c.numerator) / c.denominator for c in p] for p in (a, b)]
            dx, dy = bx - ax, by - ay
            n = mpmath.sqrt(dx * dx + dy * dy)
            nx, ny = -dy / n, dx / n                     # the left normal: inward for a CCW polygon
            rows.append([nx, ny, -1])
            rhs.append(nx * ax + ny * ay)
        return mpmath.lu_solve(mpmath.matrix(rows), mpmath.matrix(rhs))


def test_the_integer_64_gon_is_certified_with_true_edge_bounds():
    m = cv.medial_axis(shapely.Polygon(POLYGON))
    assert m.certified, m.diagram.problems[:3]
    D = m.diagram
    sites = D.to_json()["sites"]
    near_centre = 0
    checked = 0
    for v in D.vertices:
        segs = [sites[s]["segment"] for s in v.sites if "segment" in sites[s]]
        if len(segs) < 3 or len(segs) < len(v.sites):
            continue
        lines = [tuple(tuple(Fraction(c) for c in p) for p in seg) for seg in segs]
        X = _exact_vertex(lines)
        near_centre += abs(v.x) + abs(v.y) < 20
        for e in D.edges:
            for end, P in ((e.ends[0], e.polyline[0]), (e.ends[1], e.polyline[-1])):
                if end != v.id:
                    continue
                with mpmath.workdps(60):
                    gap = mpmath.sqrt((mpmath.mpf(float(P[0])) - X[0]) ** 2 + (mpmath.mpf(float(P[1])) - X[1]) ** 2)
                assert gap <= e.tolerance, (v.id, e.id, float(gap), e.tolerance)
                checked += 1
    assert near_centre >= 10 and checked >= 60


def test_the_bound_is_above_the_vertex_error_it_claims():
    """The claim itself, on the float vertices near the centre: the distance from each to its
    exact position is below ``vertex_error`` (and above the former 10⁻¹²(1 + |x| + |y|) for some)."""
    from curvedvoronoi.runtime.segments.edges import vertex_error

    D = cv.medial_axis(shapely.Polygon(POLYGON)).diagram
    sites = D.to_json()["sites"]
    scale = 1.0 + max(abs(c) for p in POLYGON for c in p)
    former_short = 0
    for v in D.vertices:
        segs = [sites[s]["segment"] for s in v.sites if "segment" in sites[s]]
        if len(segs) < 3 or len(segs) < len(v.sites):
            continue
        X = _exact_vertex([tuple(tuple(Fraction(c) for c in p) for p in seg) for seg in segs])
        with mpmath.workdps(60):
            err = float(mpmath.sqrt((mpmath.mpf(v.x) - X[0]) ** 2 + (mpmath.mpf(v.y) - X[1]) ** 2))
        assert err <= vertex_error(v, scale), (v.id, err, vertex_error(v, scale))
        former_short += err > 1e-12 * (1 + max(abs(v.x), abs(v.y)))
    assert former_short >= 1
