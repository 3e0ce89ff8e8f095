"""Conic site geometry: float foot points and rigorous distance bounds (thesis §5.2).

References independent of the code under test: the rigorous ball route of runtime.sites.distance
(Lagrange polynomial of the foot points, exact coefficients), dense sampling of the curve, and
the exact conic equation."""
from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from curvedvoronoi.runtime.predicates.circles import Circle, Point
from curvedvoronoi.runtime.sites.conic import Conic
from curvedvoronoi.runtime.sites.distance_ball import distance_ball
from curvedvoronoi.runtime.sites.intersection import circles_meet, sites_intersect
from curvedvoronoi.runtime.voronoi.conic_geometry import (EllipseGeometry, HyperbolaGeometry,
                                                          ParabolaGeometry, conic_geometry, site_inside)
from curvedvoronoi.runtime.voronoi.geometry import CircleGeometry


def _rotation(m, n):
    """A rational unit vector from a Pythagorean triple (m² − n², 2mn, m² + n²)."""
    h = m * m + n * n
    return (Fraction(m * m - n * n, h), Fraction(2 * m * n, h))


def make_conic(kind, m, n, cx, cy, A, B):
    rot = _rotation(m, n)
    if kind == "ellipse":
        A, B = max(A, B), min(A, B)
        if A == B:
            A = A + Fraction(1, 3)
        return Conic.ellipse(centre=(cx, cy), axes=(A, B), rotation=rot)
    if kind == "hyperbola":
        return Conic.hyperbola(centre=(cx, cy), axes=(A, B), rotation=rot)
    return Conic.parabola(vertex=(cx, cy), p=A, rotation=rot)


rat = st.fractions(min_value=-5, max_value=5, max_denominator=8)
pos = st.fractions(min_value=Fraction(1, 4), max_value=4, max_denominator=8)
conics = st.builds(make_conic, st.sampled_from(["ellipse", "hyperbola", "parabola"]),
                   st.integers(1, 6), st.integers(0, 6), rat, rat, pos, pos)
queries = st.lists(st.tuples(st.floats(-12, 12), st.floats(-12, 12)), min_size=1, max_size=6)


def ball(conic, x, y):
    b = distance_ball(conic, float(x), float(y), prec=64)
    return float(b.lower()), float(b.upper())


@settings(max_examples=20)
@given(conics, queries)
def test_bounds_contain_the_rigorous_distance(conic, pts):
    g = conic_geometry(conic)
    P = np.array(pts, dtype=float)
    lo, hi = g.distance_bounds(P)
    d = g.distance(P)
    for i, (x, y) in enumerate(P):
        blo, bhi = ball(conic, x, y)
        assert lo[i] <= bhi * (1 + 1e-15) + 1e-300
        assert hi[i] >= blo * (1 - 1e-15)
        assert lo[i] <= d[i] <= hi[i]
        assert abs(d[i] - 0.5 * (blo + bhi)) <= 1e-12 * (1 + abs(x) + abs(y))


@settings(max_examples=25)
@given(conics, queries)
def test_bounds_against_dense_sampling(conic, pts):
    """d_true ≤ d_samples ≤ d_true + h/2 for samples at most h apart along the curve (the
    window holds every curve point within 24 of the queries)."""
    g = conic_geometry(conic)
    P = np.array(pts, dtype=float)
    h = 4e-3
    S = g.samples(h, (-36, -36, 36, 36))
    lo, hi = g.distance_bounds(P)
    for i, q in enumerate(P):
        ds = float(np.min(np.hypot(S[:, 0] - q[0], S[:, 1] - q[1])))
        assert lo[i] <= ds + 1e-12
        assert hi[i] >= ds - h / 2 - 1e-12


@settings(max_examples=30)
@given(conics, queries)
def test_bounds_are_tight_away_from_the_curve(conic, pts):
    g = conic_geometry(conic)
    P = np.array(pts, dtype=float)
    lo, hi = g.distance_bounds(P)
    far = hi > 0.05
    assert np.all((hi[far] - lo[far]) <= 1e-9 * hi[far])


@settings(max_examples=30)
@given(conics, queries)
def test_foot_points_are_normal_feet_on_the_curve(conic, pts):
    g = conic_geometry(conic)
    P = np.array(pts, dtype=float)
    F, U = g.foot_points(P)
    a, b, c, d, e, f = (float(v) for v in conic.coefficients)
    for q, p, u in zip(P, F, U):
        x, y = p
        val = a * x * x + b * x * y + c * y * y + d * x + e * y + f
        grad = np.array([2 * a * x + b * y + d, b * x + 2 * c * y + e])
        scale = np.abs([a * x * x, b * x * y, c * y * y, d * x, e * y, f]).sum()
        assert abs(val) <= 1e-12 * scale
        assert abs(np.hypot(*u) - 1) < 1e-14
        gn = grad / np.hypot(*grad)
        assert abs(abs(float(gn @ u)) - 1) < 1e-9      # U is the curve normal at F
        v = q - p
        if np.hypot(*v) > 1e-9:
            assert np.allclose(v / np.hypot(*v), u, atol=1e-9)


SPECIAL = [(0, 0), (1, 0), (-1, 0), (0, 1), (0, -1), (2.6, 0), (8 / 3, 0), (2.7, 0), (5, 0), (0, 5),
           (1e-9, 1e-9), (1, 1e-12), (-3, 0), (3, 0), (10, 0), (4.9, 0), (2.5, 2.5), (1e6, 1e6),
           (math.sqrt(8), 0), (1 / 3, 0), (0.5, 1e-30)]


@pytest.mark.parametrize("conic", [Conic.ellipse(centre=(0, 0), axes=(3, 1)),
                                   Conic.hyperbola(centre=(0, 0), axes=(2, 1)),
                                   Conic.parabola(vertex=(0, 0), p=1)], ids=lambda c: c.kind)
def test_axes_centre_foci_evolute(conic):
    """Points on the symmetry axes, the centre, the foci and the evolute cusps (where the
    foot point jumps or is double) against the ball route."""
    g = conic_geometry(conic)
    P = np.array(SPECIAL, dtype=float)
    lo, hi = g.distance_bounds(P)
    d = g.distance(P)
    for i, (x, y) in enumerate(P):
        blo, bhi = ball(conic, x, y)
        assert lo[i] <= bhi * (1 + 1e-15) and hi[i] >= blo * (1 - 1e-15)
        assert abs(d[i] - 0.5 * (blo + bhi)) <= 1e-12 * (1 + abs(x) + abs(y))


def test_known_distances():
    E = conic_geometry(Conic.ellipse(centre=(0, 0), axes=(3, 1)))
    # centre: the nearest points are the co-vertices (0, ±1); beyond the vertex: |x| − 3
    d = E.distance(np.array([[0.0, 0.0], [5.0, 0.0], [0.0, 4.0]]))
    assert np.allclose(d, [1.0, 2.0, 3.0], rtol=0, atol=1e-15)
    # inside, on the major axis between the cusps ±(a² − b²)/a = ±8/3: d² = b²(1 − x²/(a² − b²))
    x = 1.0
    assert abs(E.distance(np.array([[x, 0.0]]))[0] - math.sqrt(1 - x * x / 8)) < 1e-15
    H = conic_geometry(Conic.hyperbola(centre=(0, 0), axes=(2, 1)))
    assert abs(H.distance(np.array([[0.0, 0.0]]))[0] - 2.0) < 1e-15
    P = conic_geometry(Conic.parabola(vertex=(0, 0), p=1))
    # beyond x = p on the axis the feet are (x − p, ±sqrt(2p(x − p))): d² = p² + 2p(x − p)
    assert abs(P.distance(np.array([[3.0, 0.0]]))[0] - math.sqrt(1 + 4)) < 1e-15
    assert abs(P.distance(np.array([[0.5, 0.0]]))[0] - 0.5) < 1e-15


def test_corrupted_conic_is_detected():
    """Bounds of a slightly wrong conic (axes off by 1e-6) exclude the true distance: the bounds
    are tight enough to tell the two apart, so they can serve as a verifier."""
    true = Conic.ellipse(centre=(1, 2), axes=(3, 1), rotation=_rotation(2, 1))
    wrong = Conic.ellipse(centre=(1, 2), axes=(3 + Fraction(3, 10 ** 6), 1), rotation=_rotation(2, 1))
    g = conic_geometry(wrong)
    P = np.array([[7.0, 2.0], [-4.0, 3.0], [1.5, 2.1]])
    lo, hi = g.distance_bounds(P)
    excluded = 0
    for i, (x, y) in enumerate(P):
        blo, bhi = ball(true, x, y)
        excluded += (hi[i] < blo) or (lo[i] > bhi)
    assert excluded >= 2


def test_samples_lie_on_the_curve_and_are_dense():
    for conic in [Conic.ellipse(centre=(1, 2), axes=(3, "1/5"), rotation=_rotation(2, 1)),
                  Conic.hyperbola(centre=(0, 1), axes=(2, 1), rotation=_rotation(3, 2)),
                  Conic.parabola(vertex=(1, -1), p="1/3", rotation=_rotation(4, 1))]:
        g = conic_geometry(conic)
        h = 0.02
        S = g.samples(h, (-10, -10, 10, 10))
        a, b, c, d, e, f = (float(v) for v in conic.coefficients)
        x, y = S[:, 0], S[:, 1]
        val = a * x * x + b * x * y + c * y * y + d * x + e * y + f
        assert np.all(np.abs(val) <= 1e-11 * (1 + np.abs(x) + np.abs(y)) ** 2 * max(map(abs, (a, b, c, d, e, f))))
        gaps = np.hypot(*np.diff(S, axis=0).T)
        # consecutive samples along one branch are at most h apart (jumps are branch/window changes)
        assert np.median(gaps) <= h and np.sum(gaps > h * 1.0001) <= 4
        # dense: every curve point of a finer sampling is within h/2 of a sample
        F = g.samples(h / 10, (-9, -9, 9, 9))
        dmin = np.array([np.min(np.hypot(S[:, 0] - p[0], S[:, 1] - p[1])) for p in F[::7]])
        assert np.all(dmin <= h / 2 + 1e-12)


def test_bounding_box_of_an_ellipse():
    conic = Conic.ellipse(centre=(1, 2), axes=(3, 1), rotation=_rotation(2, 1))
    g = conic_geometry(conic)
    S = g.samples(1e-3, None)
    x0, y0, x1, y1 = g.bounding_box()
    assert x0 <= S[:, 0].min() and S[:, 0].max() <= x1 and y0 <= S[:, 1].min() and S[:, 1].max() <= y1
    assert S[:, 0].min() - x0 < 1e-5 and x1 - S[:, 0].max() < 1e-5


def test_dispatch():
    assert isinstance(conic_geometry(Conic.ellipse(axes=(2, 1))), EllipseGeometry)
    assert isinstance(conic_geometry(Conic.hyperbola(axes=(2, 1))), HyperbolaGeometry)
    assert isinstance(conic_geometry(Conic.parabola(p=1)), ParabolaGeometry)
    assert isinstance(conic_geometry(Conic.circle(radius=2)), CircleGeometry)
    with pytest.raises(TypeError):
        conic_geometry((1, 0, 1, 0, 0, -1))


# --------------------------------------------------------------------------- intersections

E1 = Conic.ellipse(centre=(0, 0), axes=(3, 1))


@pytest.mark.parametrize("a, b, expected", [
    (E1, Conic.ellipse(centre=(0, 0), axes=(2, "1/2")), False),           # nested
    (E1, Conic.ellipse(centre=(5, 0), axes=(3, 1)), True),                 # overlapping
    (E1, Conic.ellipse(centre=(6, 0), axes=(3, 1)), True),                 # tangent at (3, 0)
    (E1, Conic.ellipse(centre=(7, 0), axes=(3, 1)), False),                # disjoint
    (E1, Conic.ellipse(centre=(0, 0), axes=(1, 2)), True),                 # crossing
    (Circle(0, 0, 1), Circle(3, 0, 1), False),
    (Circle(0, 0, 1), Circle(2, 0, 1), True),                              # tangent
    (Circle(0, 0, 4), Circle(0, 0, 1), False),                             # concentric
    (Circle(0, 0, 1), Circle(3, 0, 4), True),
    (Point(3, 0), E1, True), (Point(1, 0), E1, False), (Point(1, 0), Point(1, 0), True),
    (Conic.hyperbola(centre=(0, 0), axes=(2, 1)), E1, True),
    (Conic.hyperbola(centre=(0, 0), axes=(2, 1)), Conic.ellipse(centre=(0, 0), axes=(1, "1/2")), False),
    (Conic.parabola(vertex=(0, 0), p=1), Conic.ellipse(centre=(5, 0), axes=(1, "1/2")), False),
    (Conic.parabola(vertex=(0, 0), p=1), Conic.ellipse(centre=(2, 2), axes=(1, "1/2")), True),
    (Conic.parabola(vertex=(0, 0), p=1), Conic.parabola(vertex=(-1, 0), p=1), False),  # translate: nested
    (Conic.parabola(vertex=(0, 0), p=1), Conic.parabola(vertex=(0, 0), p=2), True),    # touch at vertex
])
def test_sites_intersect(a, b, expected):
    assert sites_intersect(a, b) is expected
    assert sites_intersect(b, a) is expected


@settings(max_examples=200, deadline=None)
@given(st.integers(1, 12), st.integers(0, 12), st.integers(-3, 3), st.integers(-3, 3),
       st.fractions(0, 20, max_denominator=8), st.fractions(0, 20, max_denominator=8),
       st.sampled_from([-1, 0, 1]))
def test_circles_meet_against_distances(m, n, x0, y0, r1, r2, shift):
    """Exact circle test on centres a Pythagorean distance D = m² + n² apart: the circles (radii
    ρ1, ρ2) meet iff |ρ1 − ρ2| ≤ D ≤ ρ1 + ρ2, with the tangent cases ρ2 = D − ρ1 (outer) and
    ρ2 = ρ1 − D (inner) made exact, and off-tangent radii decided by the same inequalities on
    rationals (no squares).  A radius 0 is a point."""
    D = m * m + n * n
    c1, c2 = (x0, y0), (x0 + m * m - n * n, y0 + 2 * m * n)
    if shift == 0:                                   # exactly tangent (outer or inner)
        r2 = abs(D - r1)
    else:                                            # off tangency by a rational step
        r2 = abs(D - r1) + Fraction(shift, 7) if abs(D - r1) + Fraction(shift, 7) >= 0 else r2
    expected = abs(r1 - r2) <= D <= r1 + r2
    a, b = (c1[0], c1[1], r1 * r1), (c2[0], c2[1], r2 * r2)
    assert circles_meet(a, b) is expected
    assert circles_meet(b, a) is expected
    assert sites_intersect(Circle(*a), Circle(*b)) is expected


def test_intersection_against_sampling():
    """Random ellipse pairs: a sign change of f_B along dense samples of A proves an
    intersection; a clear margin of one sign (no sign change, min |f_B| large) proves none."""
    rng = np.random.default_rng(7)
    checked = 0
    for _ in range(40):
        A = make_conic("ellipse", int(rng.integers(1, 5)), int(rng.integers(0, 5)),
                       Fraction(int(rng.integers(-6, 7)), 2), Fraction(int(rng.integers(-6, 7)), 2),
                       Fraction(int(rng.integers(2, 9)), 2), Fraction(int(rng.integers(1, 5)), 2))
        B = make_conic("parabola" if rng.random() < 0.5 else "ellipse", int(rng.integers(1, 5)),
                       int(rng.integers(0, 5)), Fraction(int(rng.integers(-6, 7)), 2),
                       Fraction(int(rng.integers(-6, 7)), 2), Fraction(int(rng.integers(2, 9)), 2),
                       Fraction(int(rng.integers(1, 5)), 2))
        S = conic_geometry(A).samples(1e-3, None)
        a, b, c, d, e, f = (float(v) for v in B.coefficients)
        x, y = S[:, 0], S[:, 1]
        v = a * x * x + b * x * y + c * y * y + d * x + e * y + f
        if v.min() < -1e-6 and v.max() > 1e-6:
            assert sites_intersect(A, B)
            checked += 1
        elif np.abs(v).min() > 1e-2 * np.abs(v).max():
            assert not sites_intersect(A, B)
            checked += 1
    assert checked >= 30


def test_site_inside():
    assert site_inside(Conic.ellipse(centre=(0, 0), axes=(2, "1/2")), E1)
    assert not site_inside(E1, Conic.ellipse(centre=(0, 0), axes=(2, "1/2")))
    assert not site_inside(Conic.ellipse(centre=(7, 0), axes=(3, 1)), E1)
    assert site_inside(Circle(0, 0, 1), Circle(0, 0, 4)) and not site_inside(Circle(0, 0, 4), Circle(0, 0, 1))
    assert site_inside(Point(1, 0), E1) and not site_inside(Point(5, 0), E1)
    assert site_inside(Conic.ellipse(centre=(5, 0), axes=(1, "1/2")), Conic.hyperbola(centre=(0, 0), axes=(2, 1)))
    assert site_inside(Conic.parabola(vertex=(0, 0), p=1), Conic.parabola(vertex=(-1, 0), p=1))
    assert not site_inside(Conic.parabola(vertex=(-1, 0), p=1), Conic.parabola(vertex=(0, 0), p=1))


@settings(max_examples=20, deadline=None)
@given(conics, st.integers(0, 2 ** 32 - 1))
def test_vectorised_feet_agree_with_the_ball_route(conic, seed):
    """More than 16 query points take the vectorised root finder (fewer take the scalar one):
    random points, points on the symmetry axes and near the curve, against the rigorous ball
    route and against one-point queries."""
    g = conic_geometry(conic)
    rng = np.random.default_rng(seed)
    Q = rng.uniform(-12, 12, (24, 2))
    S = g.samples(0.5, (-12, -12, 12, 12))
    near = S[rng.integers(0, len(S), 8)] + rng.normal(scale=1e-3, size=(8, 2))
    axis = g.from_canonical(rng.uniform(-8, 8, 8), np.zeros(8))
    P = np.vstack([Q, near, axis, g.from_canonical(np.zeros(4), rng.uniform(-8, 8, 4))])
    lo, hi = g.distance_bounds(P)
    d = g.distance(P)
    F, _ = g.foot_points(P)
    for i, (x, y) in enumerate(P):
        blo, bhi = ball(conic, x, y)
        assert lo[i] <= bhi * (1 + 1e-15) + 1e-300 and hi[i] >= blo * (1 - 1e-15)
        assert lo[i] <= d[i] <= hi[i]
        assert abs(d[i] - 0.5 * (blo + bhi)) <= 1e-12 * (1 + abs(x) + abs(y))
        assert abs(np.hypot(*(P[i] - F[i])) - d[i]) <= 1e-12 * (1 + abs(x) + abs(y))
        assert abs(g.distance(P[i:i + 1])[0] - d[i]) <= 1e-12 * (1 + abs(x) + abs(y))
