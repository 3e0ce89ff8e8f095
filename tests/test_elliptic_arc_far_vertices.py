"""Edges next to elliptic arc pieces that the certificate proves with exact rules instead of boxes
(runtime/segments/certificate_ellipse_edges.py, runtime/segments/ellipse_pieces.py):

* along the bisector of two points, a point e (a point site, or the end of a curve whose nearest
  point over a box is that end) has |γ − e|² − ρ² affine in the parameter, so its sign on the
  open edge follows from the end vertices — nearly collinear points, whose far vertex makes the
  margin of a box test grow by 10⁻⁴ per unit of length, are decided at once;
* the nearest end of an elliptic piece over a box a few 10⁻² wide, by a cover of the piece with
  monotone and concave parts and differences f(φ) − f(end).

References are this file's own, in mpmath from the exact site data (the piece by 160 samples and
golden-section refinement in the best cells; no distance code of the library).
"""
from __future__ import annotations

import math
import random
from fractions import Fraction as F

import mpmath
import pytest
from flint import arb

import curvedvoronoi as cv
from curvedvoronoi.runtime.segments.certificate import verify_segments
from curvedvoronoi.runtime.segments.ellipse_pieces import PieceData, closest_at_an_end
from curvedvoronoi.runtime.sites.elliptic_arc import EllipticArc

pytestmark = pytest.mark.mpmath_dps(30)


def mpf(q):
    q = F(q) if isinstance(q, int) else q
    if isinstance(q, F):
        return mpmath.mpf(q.numerator) / q.denominator
    return mpmath.mpf(F(str(q)).numerator) / F(str(q)).denominator


def piece_f(P, q):
    """f(φ) = |q − e(φ)|² of the piece P = (c, M, N), in mpmath."""
    c, M, N = ([mpf(v) for v in w] for w in (P.c, P.M, P.N))

    def f(p):
        x = c[0] + mpmath.cos(p) * M[0] + mpmath.sin(p) * N[0]
        y = c[1] + mpmath.cos(p) * M[1] + mpmath.sin(p) * N[1]
        return (q[0] - x) ** 2 + (q[1] - y) ** 2
    return f


def piece_range(P):
    p0 = mpmath.atan2(mpf(P.ua[1]), mpf(P.ua[0]))
    span = mpmath.atan2(mpf(P.ua[0] * P.ub[1] - P.ua[1] * P.ub[0]), mpf(P.ua[0] * P.ub[0] + P.ua[1] * P.ub[1]))
    return p0, p0 + (span if span > 0 else span + 2 * mpmath.pi)


def nearest_parameter(P, q, n=160):
    """The parameter of the nearest point of the closed piece to q (mpmath: samples, then
    golden-section search in the best sample's two cells)."""
    f = piece_f(P, q)
    p0, p1 = piece_range(P)
    grid = [p0 + (p1 - p0) * k / n for k in range(n + 1)]
    vals = [f(p) for p in grid]
    k = min(range(n + 1), key=lambda m: vals[m])
    a, b = grid[max(k - 1, 0)], grid[min(k + 1, n)]
    g = (mpmath.sqrt(5) - 1) / 2
    for _ in range(90):
        x1, x2 = b - g * (b - a), a + g * (b - a)
        if f(x1) < f(x2):
            b = x2
        else:
            a = x1
    return (a + b) / 2, (p0, p1)


def point_distance(s, q):
    return mpmath.hypot(q[0] - mpf(s.cx), q[1] - mpf(s.cy))


# ------------------------------------------------------------------------------ nearly collinear points
def collinear_scene():
    """The arc φ 0.2..1.3 of (x/2)² + y² = 1 and three integer points nearly collinear with its
    start e(0.2): their bisectors meet at a vertex about 320 units out."""
    return [cv.Arc.elliptic((0, 0), (2, 0), "1/2", 0.2, 1.3), (5, 5), (-4, 1), (0, -3)]


@pytest.fixture(scope="module")
def collinear():
    D = cv.voronoi(collinear_scene(), certify=False)
    return D, verify_segments(D)


def test_the_far_vertex_of_nearly_collinear_points_is_far(collinear):
    """The fact that makes the scene hard: the arc's start and two of the points are collinear
    to within 0.8°, so the vertex of the three is ~320 units out (mpmath circumcentre)."""
    D, _ = collinear
    far = [v for v in D.vertices if v.radius > 100]
    assert len(far) == 1
    v = far[0]
    pts = [D.sites[int(s)] for s in v.sites]
    assert all(not isinstance(s, EllipticArc) for s in pts)
    d = [point_distance(s, (mpf(v.x), mpf(v.y))) for s in pts]
    assert max(d) - min(d) < 1e-9 * v.radius
    assert 300 < v.radius < 350


def test_the_edges_at_the_far_vertex_are_proved(collinear):
    """Every edge of two points — the three at the far vertex among them, two of them 300 units
    long with a third point tied at one end — is proved (before the affine rule: "the piece
    budget is spent before the edge is proved")."""
    D, C = collinear
    far = next(v for v in D.vertices if v.radius > 100)
    at_far = [n for n, e in enumerate(D.edges) if far.id in e.ends]
    assert len(at_far) == 3
    for n, e in enumerate(D.edges):
        if all(not isinstance(D.sites[int(s)], EllipticArc) for s in e.sites):
            assert C.edges[n], (e.id, [str(p) for p in C.problems])
    assert not any("budget" in str(p) for p in C.problems)


def test_the_proved_point_edges_agree_with_mpmath(collinear):
    """The polylines of the proved edges of two points are equidistant from their sites and not
    nearer to any other site, at their nodes and midpoints (mpmath, the edge's own tolerance)."""
    D, C = collinear
    arc = next(s for s in D.sites if isinstance(s, EllipticArc))
    P = PieceData.of(arc)
    for n, e in enumerate(D.edges):
        if not C.edges[n] or any(isinstance(D.sites[int(s)], EllipticArc) for s in e.sites):
            continue
        i, j = (int(s) for s in e.sites)
        pts = [tuple(map(float, p)) for p in e.polyline]
        pts += [((a[0] + b[0]) / 2, (a[1] + b[1]) / 2) for a, b in zip(pts, pts[1:])]
        tol = 2 * float(e.tolerance) + 1e-9
        for x, y in pts:
            q = (mpmath.mpf(x), mpmath.mpf(y))
            di, dj = point_distance(D.sites[i], q), point_distance(D.sites[j], q)
            assert abs(di - dj) <= tol * (1 + abs(x) + abs(y))
            for k, s in enumerate(D.sites):
                if k in (i, j):
                    continue
                if isinstance(s, EllipticArc):
                    phi, _ = nearest_parameter(P, q)
                    dk = mpmath.sqrt(piece_f(P, q)(phi))
                else:
                    dk = point_distance(s, q)
                assert dk >= min(di, dj) - tol * (1 + abs(x) + abs(y)), (e.id, k, x, y)


# ------------------------------------------------------------------------------ the nearest end over a box
def test_the_nearest_end_over_a_box_at_a_joint():
    """Below the ellipse's vertex (0, −1), points of a box 0.02 wide have the vertex — the end of
    the piece coming from the left — as their nearest point of that piece (mpmath at the box's
    corners and centre); closest_at_an_end proves it (before the cover: not proved for this
    box, only for boxes ten times smaller)."""
    c, M, N = (F(0), F(0)), (F(2), F(0)), (F(0), F(1))
    ua = (F(-1), F(0))                                 # φ = π: (−2, 0)
    ub = (F(0), F(-1))                                 # φ = 3π/2: (0, −1)
    P = PieceData(c, M, N, ua, ub, 3.141592653589793, 4.71238898038469)
    for cx, cy in ((0.098, -4.099), (0.3, 1.7), (1.0, -3.0)):
        X, Y = arb(cx, 0.01), arb(cy, 0.01)
        got = closest_at_an_end(P, X, Y)
        for dx in (-0.01, 0.0, 0.01):
            for dy in (-0.01, 0.0, 0.01):
                q = (mpf(cx + dx), mpf(cy + dy))
                phi, (p0, p1) = nearest_parameter(P, q)
                assert abs(phi - p1) < 1e-12, (cx, cy, dx, dy, phi)
        assert got == (1,), (cx, cy, got)


def _random_piece(rng):
    """A piece of a random ellipse with a rational frame (M ⟂ N), between two rational directions
    at most a half-turn apart."""
    a, b = rng.choice([(3, 4), (5, 12), (8, 15)])
    m = rng.choice([1, 2])
    r = F(*rng.choice([(1, 2), (2, 3), (1, 3)]))
    M = (F(a * m, 5), F(b * m, 5))
    N = (-F(b * m, 5) * r, F(a * m, 5) * r)
    c = (F(rng.randint(-3, 3)), F(rng.randint(-3, 3)))

    def unit(t):
        u = F(t, 16)
        return ((1 - u * u) / (1 + u * u), 2 * u / (1 + u * u))
    t0 = rng.randint(-30, 20)
    t1 = t0 + rng.randint(2, 14)
    ua, ub = unit(t0), unit(t1)
    p0 = math.atan2(float(ua[1]), float(ua[0]))
    span = math.atan2(float(ua[0] * ub[1] - ua[1] * ub[0]), float(ua[0] * ub[0] + ua[1] * ub[1]))
    return PieceData(c, M, N, ua, ub, p0, p0 + span)


def test_a_proved_nearest_end_is_the_nearest_point_at_random():
    """Whenever closest_at_an_end names one end for a box, that end is the nearest point of the
    piece (mpmath) at the box's centre and corners — random pieces, boxes from 10⁻³ to 0.3 wide
    around points inside, on and outside the ellipse and 100 units out; some boxes name an end,
    some do not."""
    rng = random.Random(11)
    named = 0
    for n in range(90):
        P = _random_piece(rng)
        far = 6 if n % 3 else 100                   # a third far out: pieces concave over the box
        cx, cy = (float(P.c[k]) + rng.uniform(-far, far) for k in (0, 1))
        rad = rng.choice([1e-3, 0.03, 0.3])
        got = closest_at_an_end(P, arb(cx, rad), arb(cy, rad))
        if got is None or len(got) != 1:
            continue
        named += 1
        for dx in (-rad, 0.0, rad):
            for dy in (-rad, 0.0, rad):
                q = (mpf(cx + dx), mpf(cy + dy))
                phi, (p0, p1) = nearest_parameter(P, q)
                end = p0 if got == (0,) else p1
                f = piece_f(P, q)
                assert f(end) <= f(phi) + mpmath.mpf(10) ** -20, (got, cx, cy, rad)
    assert named >= 20


# ------------------------------------------------------------------------------ the affine rule itself
def test_the_affine_rule_on_exact_random_lines():
    """_line_rule(T, i, j, vlo, vhi)(e) claims |γ(t) − e|² > |γ(t) − p_i|² on the open edge
    γ(t) = O + t w, O the midpoint of p_i, p_j, w = rot90(p_j − p_i), between end vertices where
    that difference is ≥ 0 (what a proved vertex guarantees), an end at infinity where there is
    none.  Checked in rationals at the ends' neighbourhood and far out; and where the difference
    turns negative inside the claimed range the rule must say no."""
    from types import SimpleNamespace

    from curvedvoronoi.runtime.segments.certificate_ellipse_edges import _line_rule
    rng = random.Random(3)
    said = {True: 0, False: 0}
    for _ in range(400):
        pi = (F(rng.randint(-9, 9)), F(rng.randint(-9, 9)))
        pj = (F(rng.randint(-9, 9)), F(rng.randint(-9, 9)))
        e = (F(rng.randint(-9, 9), rng.randint(1, 3)), F(rng.randint(-9, 9), rng.randint(1, 3)))
        if pi == pj or e in (pi, pj):
            continue
        O = ((pi[0] + pj[0]) / 2, (pi[1] + pj[1]) / 2)
        w = (-(pj[1] - pi[1]), pj[0] - pi[0])

        def a(t):
            x, y = O[0] + t * w[0], O[1] + t * w[1]
            return (x - e[0]) ** 2 + (y - e[1]) ** 2 - (x - pi[0]) ** 2 - (y - pi[1]) ** 2
        t0, t1 = sorted(F(rng.randint(-40, 40), 8) for _ in range(2))
        if t0 == t1:
            continue
        lo_vertex = rng.random() < 0.7 and a(t0) >= 0
        hi_vertex = rng.random() < 0.7 and a(t1) >= 0
        T = SimpleNamespace(a={0: pi, 1: pj})
        ok = _line_rule(T, 0, 1, object() if lo_vertex else None, object() if hi_vertex else None)(e)
        said[ok] += 1
        lo = t0 if lo_vertex else t0 - 10 ** 6
        hi = t1 if hi_vertex else t1 + 10 ** 6
        ts = [lo + (hi - lo) * F(k, 64) for k in range(1, 64)] + [lo + F(1, 10 ** 9), hi - F(1, 10 ** 9)]
        if ok:
            assert all(a(t) > 0 for t in ts), (pi, pj, e, t0, t1, lo_vertex, hi_vertex)
        elif lo_vertex and hi_vertex:
            # both ends are vertices: the rule fails only for a ≡ 0 on the line
            assert all(a(t) == 0 for t in (t0, t1, (t0 + t1) / 2))
    assert said[True] > 50 and said[False] > 50


# ------------------------------------------------------------------------------ an arc's end on the hull
def hull_end_scene():
    """The arc φ 3.21..5.22 of (x/2)² + y² = 1 with six integer points: the arc's start
    e(3.21) ≈ (−2, −0.07) is a vertex of the sites' hull, so two edges of that point site go to
    infinity next to its own piece (random scene 3 of ``bench/bench_elliptic_ring.py 1``)."""
    return [cv.Arc.elliptic((0, 0), (2, 0), "1/2", 3.21, 5.22), (2, 3), (1, 3), (-2, -5), (1, -5), (2, -5), (2, -4)]


@pytest.fixture(scope="module")
def hull_end():
    D = cv.voronoi(hull_end_scene(), certify=False)
    return D, verify_segments(D)


def test_an_arc_end_on_the_hull_is_certified(hull_end):
    """Before: verify_segments raised KeyError (the hull's tie list took the piece for a circular
    arc), and the two infinite edges of the arc's end point were refused."""
    D, C = hull_end
    assert C.ok and C.complete, [str(p) for p in C.problems]
    arc = next(k for k, s in enumerate(D.sites) if isinstance(s, EllipticArc))
    ends = [k for k, s in enumerate(D.sites) if not isinstance(s, EllipticArc)
            and any(k in (int(a), int(b)) for a, b in [e.sites for e in D.edges if None in e.ends])]
    assert ends
    # the two unbounded edges of the arc's start: one of its end points with two other points
    start = [e for e in D.edges if None in e.ends and any(
        not isinstance(D.sites[int(s)], EllipticArc) and arc in _curves_ending_at(D, int(s)) for s in e.sites)]
    assert len(start) >= 2


def _curves_ending_at(D, p):
    s = D.sites[p]
    q = (F(str(s.cx)) if not isinstance(s.cx, F) else s.cx, F(str(s.cy)) if not isinstance(s.cy, F) else s.cy)
    out = []
    for k, t in enumerate(D.sites):
        if isinstance(t, EllipticArc):
            for u in (t.ua, t.ub):
                if tuple(t.c[m] + u[0] * t.M[m] + u[1] * t.N[m] for m in (0, 1)) == q:
                    out.append(k)
    return out


def test_the_arc_end_scene_agrees_with_mpmath(hull_end):
    """Every edge's polyline (nodes and midpoints, the infinite ones out to their drawn far
    points) is equidistant from its two sites and nearer to them than to any other site; every
    vertex is at distance r from its listed sites and not nearer to any other (mpmath)."""
    D, C = hull_end
    arc = next(s for s in D.sites if isinstance(s, EllipticArc))
    P = PieceData.of(arc)

    def dist(k, q):
        s = D.sites[k]
        if isinstance(s, EllipticArc):
            Q = PieceData.of(s)
            phi, _ = nearest_parameter(Q, q)
            return mpmath.sqrt(piece_f(Q, q)(phi))
        return point_distance(s, q)
    assert P is not None
    for e in D.edges:
        i, j = (int(s) for s in e.sites)
        pts = [tuple(map(float, p)) for p in e.polyline]
        pts += [((a[0] + b[0]) / 2, (a[1] + b[1]) / 2) for a, b in zip(pts, pts[1:])]
        for x, y in pts[:: max(1, len(pts) // 12)]:
            q = (mpmath.mpf(x), mpmath.mpf(y))
            tol = (2 * float(e.tolerance) + 1e-9) * (1 + abs(x) + abs(y))
            d = [dist(k, q) for k in range(len(D.sites))]
            assert abs(d[i] - d[j]) <= tol, (e.id, x, y)
            assert min(x_ for k, x_ in enumerate(d) if k not in (i, j)) >= min(d[i], d[j]) - tol, (e.id, x, y)
    for v in D.vertices:
        q = (mpmath.mpf(v.x), mpmath.mpf(v.y))
        listed = {int(s) for s in v.sites}
        for k in range(len(D.sites)):
            dk = dist(k, q)
            if k in listed:
                assert abs(dk - v.radius) < 1e-9 * (1 + v.radius), (v.id, k)
            else:
                assert dk > v.radius - 1e-9 * (1 + v.radius), (v.id, k)
