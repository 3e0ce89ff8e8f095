"""Three nearly collinear points: the middle one a hair ε inside the hull side of the other two.
The Voronoi vertex of the three is their circumcentre, about 1/(2ε) away on the far side of the
side (thesis §1.2: the empty circle of a Delaunay triangle), and the edge of the two outer points
runs from it to infinity.  Floats cannot tell the distances apart so far out; the certificate
decides the middle point's side of that edge exactly (rational affine power differences), and the
direction of the infinite end from the polyline however far the vertex lies.

Reference: the Delaunay triangles by brute force over all triples with exact rational incircle
tests (no library code), and the circumcentre in rationals."""
from __future__ import annotations

from fractions import Fraction
from itertools import combinations

import numpy as np
import pytest

import curvedvoronoi as cv


def orient(a, b, c):
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])


def incircle(a, b, c, d):
    """> 0 when d is strictly inside the circle through a, b, c (counter-clockwise)."""
    rows = [(p[0] - d[0], p[1] - d[1]) for p in (a, b, c)]
    m = [(x, y, x * x + y * y) for x, y in rows]
    return (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))


def circumcentre(a, b, c):
    d = 2 * (a[0] * (b[1] - c[1]) + b[0] * (c[1] - a[1]) + c[0] * (a[1] - b[1]))
    ux = ((a[0] ** 2 + a[1] ** 2) * (b[1] - c[1]) + (b[0] ** 2 + b[1] ** 2) * (c[1] - a[1])
          + (c[0] ** 2 + c[1] ** 2) * (a[1] - b[1])) / d
    uy = ((a[0] ** 2 + a[1] ** 2) * (c[0] - b[0]) + (b[0] ** 2 + b[1] ** 2) * (a[0] - c[0])
          + (c[0] ** 2 + c[1] ** 2) * (b[0] - a[0])) / d
    return ux, uy


def delaunay(points):
    P = [(Fraction(x), Fraction(y)) for x, y in points]
    tris = []
    for t in combinations(range(len(P)), 3):
        a, b, c = (P[k] for k in t)
        o = orient(a, b, c)
        if o == 0:
            continue
        if o < 0:
            b, c = c, b
        if all(incircle(a, b, c, P[k]) <= 0 for k in range(len(P)) if k not in t):   # none strictly inside
            tris.append(t)
    edges = {tuple(sorted(e)) for t in tris for e in combinations(t, 2)}
    return tris, edges, P


@pytest.mark.parametrize("eps", [1e-3, 1e-6, 1e-9, 1e-12, -1e-9])
def test_a_far_vertex_of_nearly_collinear_points_is_certified(eps):
    pts = [(0, 0), (1, eps), (2, 0), (1, 5)]
    d = cv.voronoi(pts, progress=False)
    assert d.certified, d.problems
    tris, edges, P = delaunay(pts)
    assert set(d.delaunay_edges()) == edges
    assert len(d.vertices) == len(tris)
    for t in tris:
        cx, cy = circumcentre(*(P[k] for k in t))
        v = next(v for v in d.vertices if set(v.sites) == set(t))
        assert abs(Fraction(v.x) - cx) <= 1e-9 * (1 + abs(cx)) and abs(Fraction(v.y) - cy) <= 1e-9 * (1 + abs(cy))
    unbounded = {tuple(e.sites) for e in d.edges if None in e.ends}
    assert ((0, 2) in unbounded) == (eps > 0)


@pytest.mark.parametrize("eps", [-1e-12, 1e-13, -1e-13])
def test_three_nearly_collinear_points_have_one_far_vertex(eps):
    """The circumcentre 1/(2|ε|) out, its three edges: the outer pair's away from the middle point,
    the other two towards it (the end at infinity read from a polyline whose last point is a few
    units beyond a vertex 5·10¹² out)."""
    pts = [(0, 0), (1, eps), (2, 0)]
    d = cv.voronoi(pts, progress=False)
    assert d.certified, d.problems
    (v,) = d.vertices
    cx, cy = circumcentre(*((Fraction(x), Fraction(y)) for x, y in pts))
    assert abs(Fraction(v.y) - cy) <= 1e-9 * abs(cy) and abs(Fraction(v.x) - cx) <= 1e-9
    assert all(None in e.ends for e in d.edges) and len(d.edges) == 3


def delaunay_graph(points):
    """Pairs of points with an empty circle through both and every other point strictly outside:
    an edge of an empty triangle whose empty triangles have two different circumcentres, or a hull
    side (all others on one side, none on the open segment)."""
    tris, _, P = delaunay(points)
    centres: dict = {}
    for t in tris:
        c = circumcentre(*(P[k] for k in t))
        for e in combinations(sorted(t), 2):
            centres.setdefault(e, set()).add(c)
    out = set()
    for (a, b), cs in centres.items():
        sides = [orient(P[a], P[b], P[k]) for k in range(len(P)) if k not in (a, b)]
        on_open = any(s == 0 and min(P[a], P[b]) < P[k] < max(P[a], P[b])
                      for k, s in zip([k for k in range(len(P)) if k not in (a, b)], sides))
        hull = (all(s >= 0 for s in sides) or all(s <= 0 for s in sides)) and not on_open
        if len(cs) > 1 or hull:
            out.add((a, b))
    return out


@pytest.mark.parametrize("angle", [0.3, 1.1])
def test_a_rotated_grid_of_points_is_certified(angle):
    """A 5 × 5 grid rotated in floats: its rows are 10⁻¹⁶ off their lines, so its hull sides carry
    Voronoi vertices 10¹⁵–10¹⁷ out, and its squares are nearly co-circular."""
    c, s = np.cos(angle), np.sin(angle)
    pts = [(c * x - s * y, s * x + c * y) for x in range(5) for y in range(5)]
    d = cv.voronoi(pts, progress=False)
    assert d.certified, d.problems[:3]
    assert set(d.delaunay_edges()) == delaunay_graph(pts)


def test_the_float_filter_of_points_edge_clear_leaves_hairline_cases_to_the_exact_test():
    """A = (0, 0), B = (2, 0), C = (1, 2⁻⁴⁰): the vertex of A, B, C is 5.5·10¹¹ below, and the edge
    of A, B runs from it downwards to infinity.  A fourth point one float inside the circle of A, B,
    C (at x = 3), or 2⁻¹⁰⁰⁰ below the line AB far to the side (it wins far down), is closer than A
    and B somewhere on the edge: exactly decided, far below the floats' rounding."""
    import math

    from curvedvoronoi.runtime.predicates.circles import Point
    from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
    from curvedvoronoi.runtime.voronoi.verify.exact_edges import points_edge_clear

    eps = Fraction(2) ** -40
    y0 = (eps * eps - 1) / (2 * eps)                 # centre (1, y0) of the circle through A, B, C
    r2 = 1 + y0 * y0
    lo, hi = Fraction(-1, 10 ** 6), Fraction(0)      # y_top ≈ −3ε: the circle's point above (3, y0)
    for _ in range(200):
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if 4 + (mid - y0) ** 2 < r2 else (lo, mid)
    q = math.nextafter(float(lo), -math.inf)
    assert 4 + (Fraction(q) - y0) ** 2 < r2          # strictly inside the circle
    sites = [Point(0, 0), Point(2, 0), Point(1, float(eps))]
    down = ("inf", -1)                               # direction −rot90(B − A) = (0, −2)
    G = [site_geometry(s) for s in sites + [Point(3, q)]]
    assert not points_edge_clear(G, 0, 1, (0, 1, 2), down)
    G = [site_geometry(s) for s in sites + [Point(3, float(q) + 1e-6)]]     # outside: clear
    assert points_edge_clear(G, 0, 1, (0, 1, 2), down)
    G = [site_geometry(s) for s in sites + [Point(100, -2.0 ** -1000)]]
    assert not points_edge_clear(G, 0, 1, (0, 1, 2), down)
    G = [site_geometry(s) for s in sites + [Point(100, 2.0 ** -1000)]]
    assert points_edge_clear(G, 0, 1, (0, 1, 2), down)
