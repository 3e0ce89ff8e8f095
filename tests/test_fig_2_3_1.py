"""Thesis Fig. 2.3.1 as tests: the medial axis of a curved domain and of its polygonal approximations,
and closed-form / independently checked medial axes of polygons (``cv.medial_axis``).

* The ellipse x²/a² + y²/b² < 1 has the medial axis |x| <= (a² - b²)/a, y = 0: two ends.  An inscribed
  n-gon (vertices at rational points of the ellipse, t = tan(θ/2) in the rational parametrisation)
  has a medial axis with one branch per convex corner: a tree with n leaves, for n = 15 and 60.
* Convergence: the part of the n-gon's axis whose two nearest boundary points are at least λ apart
  (the λ-medial axis of Chazal & Lieutier, 2005) tends to the ellipse's λ-medial axis (Hausdorff
  distance decreasing from n = 15 to n = 60), whereas the part of radius > ρ does **not** converge:
  the branches of the corners on the flat sides reach the middle segment at radius ~b for every n
  (the instability of the medial axis that Fig. 2.3.1 shows).
* Rectangle and square (closed form), an L-shape and a square with a square hole checked against
  shapely (an independent distance): along every edge the distance to the boundary equals the
  reported radius and is reached at two distinct boundary points; and for random points of the
  domain, the ray from the nearest boundary point through the point leaves the set of centres of
  inscribed discs touching there exactly on the reported axis.
"""
from __future__ import annotations

import math
from fractions import Fraction

import networkx as nx
import numpy as np
import pytest

import curvedvoronoi as cv

shapely = pytest.importorskip("shapely", reason="the independent distances come from shapely (test extra)")

A, B = 2, 1                          # the ellipse's semi-axes; its medial axis is |x| <= X, y = 0
X = (A * A - B * B) / A


def ellipse_polygon(n: int, a=A, b=B, den=1000) -> list[tuple[Fraction, Fraction]]:
    """n vertices on the ellipse, exactly: (a (1 - t²)/(1 + t²), b 2t/(1 + t²)) with t a rational
    close to tan(θ_k/2), θ_k = 2πk/n (θ = π is the point (-a, 0))."""
    pts = []
    for k in range(n):
        th = 2 * math.pi * k / n
        if abs(th - math.pi) < 1e-12:
            pts.append((Fraction(-a), Fraction(0)))
            continue
        t = Fraction(math.tan(th / 2)).limit_denominator(den)
        pts.append((a * (1 - t * t) / (1 + t * t), b * 2 * t / (1 + t * t)))
    return pts


def graph(m) -> nx.Graph:
    """The medial axis as a graph on the diagram's vertex ids (the edges' end vertices)."""
    G = nx.Graph()
    for e in m.edges:
        assert None not in e.ends
        G.add_edge(*e.ends)
    return G


def leaves(m, G) -> list:
    by_id = {v.id: v for v in m.vertices}
    return [by_id[v] for v, d in G.degree() if d == 1]


def dense(P, h):
    out = [P[:1]]
    for p, q in zip(P[:-1], P[1:]):
        k = max(1, int(np.ceil(np.hypot(*(q - p)) / h)))
        out.append(p + (np.arange(1, k + 1) / k)[:, None] * (q - p))
    return np.vstack(out)


def feet(E, i, P):
    """The nearest points of elementary site i (a point, or a closed segment) to the points P."""
    a, b = E.A[i], E.B[i]
    d = b - a
    L2 = float(d @ d)
    t = np.zeros(len(P)) if L2 == 0 else np.clip((P - a) @ d / L2, 0, 1)
    return a + t[:, None] * d


def samples(m, h):
    """Points along the edges' polylines with the radius there and the distance between the two
    nearest boundary points (the feet on the edge's two sites)."""
    E = m.diagram.elementary
    pts, rad, chord = [], [], []
    for e in m.edges:
        P = dense(np.asarray(e.polyline, float), h)
        Fi, Fj = feet(E, e.sites[0], P), feet(E, e.sites[1], P)
        pts.append(P)
        rad.append(np.hypot(*(P - Fi).T))
        chord.append(np.hypot(*(Fi - Fj).T))
    return np.vstack(pts), np.concatenate(rad), np.concatenate(chord)


def ellipse_axis_part(kind: str, thr: float, m=20001):
    """Points of the ellipse's medial axis with radius > thr (kind "r") or feet at least thr apart
    (kind "chord").  The normal at (a cos s, b sin s) meets the axis at x = X cos s, with radius
    sqrt(b⁴/a² cos² s + b² sin² s) and feet (a cos s, ±b sin s), 2 b |sin s| apart."""
    s = np.linspace(0, math.pi, m)
    r = np.sqrt(B ** 4 / A ** 2 * np.cos(s) ** 2 + B * B * np.sin(s) ** 2)
    keep = (r > thr) if kind == "r" else (2 * B * np.sin(s) >= thr)
    return np.column_stack([X * np.cos(s[keep]), np.zeros(int(keep.sum()))])


def hausdorff(P, Q) -> float:
    from scipy.spatial import cKDTree

    return float(max(cKDTree(Q).query(P)[0].max(), cKDTree(P).query(Q)[0].max()))


@pytest.fixture(scope="module")
def ngon15():
    return cv.medial_axis(ellipse_polygon(15), certify=False)


@pytest.fixture(scope="module")
def ngon60():
    return cv.medial_axis(ellipse_polygon(60), certify=False)


def _check_ngon(m, n):
    G = graph(m)
    assert nx.is_tree(G)
    ends = leaves(m, G)
    assert len(ends) == n                                     # one branch per convex corner
    corners = {(float(x), float(y)) for x, y in ellipse_polygon(n)}
    assert {(v.x, v.y) for v in ends} == corners and all(v.radius == 0 for v in ends)
    inner = [v for v in m.vertices if v.radius > 0]
    assert all(abs(v.y) < 1e-9 and abs(v.x) <= X for v in inner if G.degree(v.id) >= 4)


def test_the_15_gon_in_the_ellipse_has_15_leaves_and_is_a_tree(ngon15):
    _check_ngon(ngon15, 15)


@pytest.mark.slow
def test_the_60_gon_in_the_ellipse_has_60_leaves_and_is_a_tree(ngon60):
    _check_ngon(ngon60, 60)


@pytest.mark.slow
def test_the_lambda_medial_axis_converges_and_the_high_radius_part_does_not(ngon15, ngon60):
    h = 0.005
    lam = {n: hausdorff(*_part(m, "chord", B, h)) for n, m in ((15, ngon15), (60, ngon60))}
    assert lam[60] < lam[15] / 4 and lam[60] < 0.02, lam
    rho = 0.8                         # every n: branches of radius up to ~b stick out from y = 0 by ~b - rho
    for m in (ngon15, ngon60):
        P, Q = _part(m, "r", rho, h)
        assert hausdorff(P, Q) > 0.15
        assert float(np.max(np.abs(P[:, 1]))) > 0.15


def _part(m, kind, thr, h):
    P, r, chord = samples(m, h)
    return P[(r if kind == "r" else chord) > thr - 1e-12], ellipse_axis_part(kind, thr)


def test_ellipse_axis_part_matches_the_closed_form_segment():
    P = ellipse_axis_part("r", 0.0)
    assert P[:, 0].max() == pytest.approx(X) and P[:, 0].min() == pytest.approx(-X)
    # its ends have the radius of curvature b²/a of the ellipse at (±a, 0)
    assert ellipse_axis_part("r", B * B / A + 1e-9)[:, 0].max() < X


# ------------------------------------------------------------------------------------ closed forms
def _edge_set(m, nd=9):
    return sorted(tuple(sorted((round(float(p[0]), nd), round(float(p[1]), nd)) for p in
                               (e.polyline[0], e.polyline[-1]))) for e in m.edges)


def test_rectangle_middle_segment_and_four_corner_diagonals():
    w, h = 5, 2
    m = cv.medial_axis([(0, 0), (w, 0), (w, h), (0, h)])
    c0, c1 = (h / 2, h / 2), (w - h / 2, h / 2)
    want = sorted(tuple(sorted(p)) for p in [(c0, c1), ((0, 0), c0), ((0, h), c0), ((w, 0), c1), ((w, h), c1)])
    assert _edge_set(m) == want
    inner = sorted((v.x, v.y, v.radius) for v in m.vertices if v.radius > 0)
    assert inner == [(c0[0], c0[1], h / 2), (c1[0], c1[1], h / 2)]          # exact in floats
    for e in m.edges:                                   # straight edges: every polyline point on its line
        P = np.asarray(e.polyline)
        d = P[-1] - P[0]
        assert np.allclose((P - P[0]) @ np.array([-d[1], d[0]]), 0, atol=1e-12)
        assert np.allclose(e.radius, [min(x, y, w - x, h - y) for x, y in P], atol=1e-12)
    assert m.certified, m.problems
    assert m.largest_inscribed_circle[2] == h / 2


def test_square_one_degree_4_vertex_at_the_centre():
    m = cv.medial_axis([(0, 0), (2, 0), (2, 2), (0, 2)])
    G = graph(m)
    centre = [v for v in m.vertices if v.radius > 0]
    assert [(v.x, v.y, v.radius) for v in centre] == [(1, 1, 1)] and G.degree(centre[0].id) == 4
    assert len(m.edges) == 4 and nx.is_tree(G) and len(leaves(m, G)) == 4
    assert m.certified, m.problems


# ------------------------------------------------------------------------------------ shapely oracle
def _oracle(m, polygon, n_random=400, seed=7):
    """The medial axis against shapely's distance to the boundary (see the module docstring)."""
    boundary = polygon.boundary
    E = m.diagram.elementary
    scale = max(polygon.bounds[2] - polygon.bounds[0], polygon.bounds[3] - polygon.bounds[1])
    # (1) along each edge: the boundary distance is the reported radius, reached at two distinct feet
    for e in m.edges:
        P = np.asarray(e.polyline, float)
        tol = e.tolerance + 1e-9 * scale
        d = shapely.distance(boundary, shapely.points(P))
        assert np.allclose(d, e.radius, atol=tol), (e.sites, np.abs(d - e.radius).max())
        Fi, Fj = feet(E, e.sites[0], P), feet(E, e.sites[1], P)
        assert np.allclose(np.hypot(*(P - Fi).T), d, atol=tol) and np.allclose(np.hypot(*(P - Fj).T), d, atol=tol)
        inner = d > 1e-6 * scale
        assert np.all(np.hypot(*(Fi - Fj).T)[inner] > 1e-9 * scale)
        assert np.all(shapely.contains(polygon, shapely.points(P[inner])))
    # (2) random points: from the nearest boundary point f through p, the disc centred on the ray and
    # touching f stays inside up to the axis: t - dist(f + t u) leaves 0 exactly where the ray meets it
    rng = np.random.default_rng(seed)
    x0, y0, x1, y1 = polygon.bounds
    Q = rng.uniform((x0, y0), (x1, y1), size=(4 * n_random, 2))
    Q = Q[shapely.contains(polygon, shapely.points(Q))][:n_random]
    F = shapely.get_coordinates(shapely.shortest_line(boundary, shapely.points(Q))).reshape(-1, 2, 2)[:, 0]
    U = (Q - F) / np.hypot(*(Q - F).T)[:, None]
    lo, hi = np.hypot(*(Q - F).T), np.full(len(Q), 2 * scale)
    eta = 1e-10 * scale
    for _ in range(60):
        mid = (lo + hi) / 2
        g = mid - shapely.distance(boundary, shapely.points(F + mid[:, None] * U))
        inside = g <= eta
        lo, hi = np.where(inside, mid, lo), np.where(inside, hi, mid)
    exits = F + lo[:, None] * U
    axis = m.to_shapely()
    gap = shapely.distance(axis, shapely.points(exits))
    tol = max(e.tolerance for e in m.edges) + 1e-6 * scale
    assert np.all(gap <= tol), (gap.max(), exits[np.argmax(gap)])
    return len(Q)


def test_l_shape_against_shapely_distances():
    from shapely.geometry import Polygon

    pts = [(0, 0), (4, 0), (4, 1), (1, 1), (1, 3), (0, 3)]
    m = cv.medial_axis(pts)
    assert _oracle(m, Polygon(pts)) >= 200
    G = graph(m)
    assert nx.is_tree(G) and len(leaves(m, G)) == 5                   # 5 convex corners, 1 reflex
    r = 2 - math.sqrt(2)                     # the disc touching both long sides and the reflex corner
    assert m.largest_inscribed_circle == pytest.approx((r, r, r), abs=1e-12)


def test_square_with_a_square_hole_against_shapely_distances():
    from shapely.geometry import Polygon

    outer, hole = [(0, 0), (6, 0), (6, 6), (0, 6)], [(2, 2), (4, 2), (4, 4), (2, 4)]
    m = cv.medial_axis(outer, [hole])
    assert _oracle(m, Polygon(outer, [hole])) >= 200
    G = graph(m)
    assert len(nx.cycle_basis(G)) == 1 and nx.is_connected(G)        # one loop around the hole
    assert len(leaves(m, G)) == 4                                     # the outer corners
    r = 4 - 2 * math.sqrt(2)                 # near an outer corner: touching two sides and a hole corner
    assert m.largest_inscribed_circle[2] == pytest.approx(r, abs=1e-12)
