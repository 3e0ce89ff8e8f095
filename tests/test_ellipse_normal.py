"""The tight gradient enclosure outside an ellipse (runtime/voronoi/verify/ellipse_normal.py) at
the boundaries of its inequalities, with exact expected verdicts derived here.

Exact configuration: the ellipse X²/25 + Y²/(25/4) = 1 (a = 5, b = 5/2) and the point
q = (6, 10).  The rational point p = (3, 2) lies on it (9/25 + 16/25 = 1) and
q − p = (3, 8) = 25·(3/25, 2/(25/4)) = μ·∇g(p)/2 with μ = 25 > 0, so p is the projection of q
on the convex inside K (normal cone), d(q) = √73, ∇d(q) = (3, 8)/√73, and the multiplier
equation F(μ) = (aX/(a² + μ))² + (bY/(b² + μ))² − 1 has its zero at μ* = 25:
F(25) = (30/50)² + (25/31.25)² − 1 = 0.36 + 0.64 − 1 = 0, and F'(25) = −2(0.36/50 + 0.64/31.25)
= −0.05536.  Hence F(25 − 10⁻⁹) ≈ +5.5·10⁻¹¹ > 0 and F(25 + 10⁻⁹) < 0: the bracket with margin
10⁻⁹ must be proved on both sides, the one at 25 itself (margin 0) on neither.  With |X| allowed
down to 6 − 10⁻⁹ the minimum of F(25) over the box is < 0 (each term increases with |X|), so
F⁻(25) < 0 there; with |X| up to 6 + 10⁻⁹ the maximum is > 0.

Points inside the ellipse or on it have no positive multiplier (F(0) ≤ 0 and F decreases), so
the enclosure must refuse them.  References for other points: the foot point by minimising
|q − (a cos t, b sin t)|² over t in 50-digit mpmath (not the multiplier equation).
"""
from __future__ import annotations

from fractions import Fraction as Fr

import mpmath
import numpy as np
import pytest

from curvedvoronoi.runtime.sites.conic import Conic
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify.ellipse_normal import (ellipse_normal_enclosure, frame_errors,
                                                                  multiplier_bounds)
from curvedvoronoi.runtime.voronoi.verify.site_table import SiteTable, gradient_enclosure

A, B = 5.0, 2.5
NO_ERR = np.zeros((1, 6))


def bounds(mu, X=6.0, Y=10.0, dX=0.0):
    return multiplier_bounds(np.array([mu]), np.array([X - dX]), np.array([X + dX]), np.array([Y]), np.array([Y]),
                             np.array([A]), np.array([A]), np.array([B]), np.array([B]))


def test_multiplier_bounds_at_the_exact_zero():
    """F(25) = 0 exactly: F⁻(25) ≤ 0 ≤ F⁺(25); 10⁻⁹ to the left F > 0 is proved, to the right F < 0."""
    lo, hi = bounds(25.0)
    assert lo[0] <= 0.0 <= hi[0]
    lo, _ = bounds(25.0 - 1e-9)
    assert lo[0] > 0.0
    _, hi = bounds(25.0 + 1e-9)
    assert hi[0] < 0.0
    # margin 0 on the other side: F(25 + 1e-9) < 0 is not > 0, F(25 − 1e-9) > 0 is not < 0
    lo, _ = bounds(25.0 + 1e-9)
    assert not lo[0] > 0.0
    _, hi = bounds(25.0 - 1e-9)
    assert not hi[0] < 0.0


def test_multiplier_bounds_cover_the_data_box():
    """|X| ∈ [6 − 10⁻⁹, 6 + 10⁻⁹]: min F(25) = F at |X| = 6 − 10⁻⁹ < 0 < max F(25)."""
    lo, hi = bounds(25.0, dX=1e-9)
    assert lo[0] < -1e-11 and hi[0] > 1e-11


def canonical_case():
    E = Conic.ellipse(centre=(Fr(0), Fr(0)), axes=(Fr(5), Fr(5, 2)), rotation=(Fr(1), Fr(0)))
    g = site_geometry(E)
    assert (g.a, g.b, g.c, g.s, g.tx, g.ty) == (5.0, 2.5, 1.0, 0.0, 0.0, 0.0)
    return E, g


def enclose(g, Q, errs=NO_ERR):
    Q = np.asarray(Q, float).reshape(-1, 2)
    F, _ = g.foot_points(Q)
    return ellipse_normal_enclosure(Q, F, g.a, g.b, g.c, g.s, g.tx, g.ty, np.repeat(errs, len(Q), 0))


def test_exact_gradient_is_enclosed_tightly():
    """∇d(6, 10) = (3, 8)/√73 lies within e of G, and e is below 10⁻¹³ (the point of the route)."""
    E, g = canonical_case()
    errs = np.array([frame_errors(E, g.c, g.s, g.tx, g.ty, g.a, g.b)])
    assert (errs < 1e-300).all()      # a dyadic rational frame: the float frame is exact (errors 2^-1070)
    G, e, ok = enclose(g, [[6.0, 10.0]], errs)
    assert ok[0]
    n = np.array([3.0, 8.0]) / np.sqrt(73.0)
    assert np.hypot(*(G[0] - n)) <= e[0] and e[0] < 1e-13


@pytest.mark.parametrize("q", [(3.0, 2.0), (0.0, 2.5), (1.0, 1.0), (4.0, 0.0), (3.0, 2.0 - 2.0 ** -40)])
def test_points_on_or_inside_are_refused(q):
    """On the ellipse (F(0) = 0) or inside it (F(0) < 0) no μ > 0 has F(μ) > 0: not ok."""
    _, g = canonical_case()
    _, _, ok = enclose(g, [q])
    assert not ok[0]


def test_a_point_just_outside_is_enclosed():
    """q = (3, 2 + 2⁻³⁰) is outside (9/25 + (2 + 2⁻³⁰)²/6.25 > 1): enclosed, and the enclosure
    holds the mpmath gradient (the unit normal at the foot)."""
    _, g = canonical_case()
    q = (3.0, 2.0 + 2.0 ** -30)
    G, e, ok = enclose(g, [q])
    assert ok[0]
    n = reference_gradient(5, Fr(5, 2), q)
    assert np.hypot(*(G[0] - n)) <= e[0]


def reference_gradient(a, b, q, centre=(0, 0), rot=(1, 0)):
    """∇d(q) for the ellipse of semi-axes a, b (canonical along rot = (cos, sin)) from the foot
    parameter t minimising |Q − (a cos t, b sin t)|² (50 digits)."""
    with mpmath.workdps(50):
        c, s = mpmath.mpf(Fr(rot[0]).numerator) / Fr(rot[0]).denominator, mpmath.mpf(Fr(rot[1]).numerator) / Fr(rot[1]).denominator
        a = mpmath.mpf(Fr(a).numerator) / Fr(a).denominator
        b = mpmath.mpf(Fr(b).numerator) / Fr(b).denominator
        dx, dy = mpmath.mpf(q[0]) - centre[0], mpmath.mpf(q[1]) - centre[1]
        X, Y = c * dx + s * dy, -s * dx + c * dy

        def d2(t):
            return (X - a * mpmath.cos(t)) ** 2 + (Y - b * mpmath.sin(t)) ** 2

        t0 = min((2 * mpmath.pi * k / 2000 for k in range(2000)), key=d2)
        t = mpmath.findroot(lambda t: mpmath.diff(d2, t), t0)
        nx, ny = X - a * mpmath.cos(t), Y - b * mpmath.sin(t)
        r = mpmath.sqrt(nx * nx + ny * ny)
        nx, ny = nx / r, ny / r
        return np.array([float(c * nx - s * ny), float(s * nx + c * ny)])


def test_rotated_ellipse_far_and_near_points_against_mpmath():
    """A rotated ellipse (rotation (3/5, 4/5), not exact in floats: frame errors > 0); points
    at 1 to 3·10⁴ units: the true gradient is within e of G and e ≤ 10⁻¹²."""
    E = Conic.ellipse(centre=(Fr(1025, 8), Fr(-37, 4)), axes=(Fr(3), Fr(5, 4)), rotation=(Fr(3, 5), Fr(4, 5)))
    g = site_geometry(E)
    errs = np.array([frame_errors(E, g.c, g.s, g.tx, g.ty, g.a, g.b)])
    assert errs[0, 0] > 0 or errs[0, 1] > 0
    rng = np.random.default_rng(5)
    ang = rng.uniform(0, 2 * np.pi, 12)
    rad = np.concatenate([[4.0, 6.0, 10.0], 10.0 ** rng.uniform(1, 4.5, 9)])
    Q = np.column_stack([128.125 + rad * np.cos(ang), -9.25 + rad * np.sin(ang)])
    G, e, ok = enclose(g, Q, errs)
    assert ok.all()
    for q, Gq, eq in zip(Q, G, e):
        n = reference_gradient(3, Fr(5, 4), q, centre=(Fr(1025, 8), Fr(-37, 4)), rot=(Fr(3, 5), Fr(4, 5)))
        assert np.hypot(*(Gq - n)) <= eq, (q, Gq, n, eq)
        assert eq <= 1e-12


def test_gradient_enclosure_on_a_disc_uses_the_tight_route_and_holds():
    """Through the site table: at 3·10⁴ units the slack on a disc of radius 10⁻⁶ is below 10⁻⁹
    (the disc term 2R/(lo − R) is 6·10⁻¹¹; the cheap foot term alone is about 10⁻⁷ there), and at 10 units on a disc of radius 1 the
    slack still covers the true gradient at points of the disc (the disc term 2R/(lo − R))."""
    E = Conic.ellipse(centre=(Fr(3), Fr(-2)), axes=(Fr(5), Fr(2)), rotation=(Fr(3, 5), Fr(4, 5)))
    g = site_geometry(E)
    table = SiteTable([g], 10.0)
    for Qc, R in (((31377.8687, 3393.2373), 1e-6), ((3.0, 12.0), 1.0)):
        Qc = np.array([Qc])
        V = table.evaluate(Qc, [0])
        G, slack, valid = gradient_enclosure(Qc, V, R, 10.0)
        assert valid[0]
        if R < 0.01:
            assert slack[0] < 1e-9
        ang = np.linspace(0, 2 * np.pi, 9)[:-1]
        for r in (0.0, R):
            for q in Qc[0] + r * np.column_stack([np.cos(ang), np.sin(ang)]):
                n = reference_gradient(5, 2, q, centre=(3, -2), rot=(Fr(3, 5), Fr(4, 5)))
                assert np.hypot(*(G[0] - n)) <= slack[0]


def test_frame_errors_widen_the_enclosure():
    """With the semi-axis a known only within ±10⁻¹⁰ (a frame error handed in), the enclosure at
    q = (6, 10) must hold ∇d for every ellipse of the box: for a = 5 ± 9·10⁻¹¹ (exact rationals)
    the mpmath gradients differ from (3, 8)/√73 by about 10⁻¹¹, and each lies within e of G."""
    _, g = canonical_case()
    errs = np.array([[0.0, 0.0, 0.0, 0.0, 1e-10, 0.0]])
    G, e, ok = enclose(g, [[6.0, 10.0]], errs)
    assert ok[0]
    for a in (Fr(5) - Fr(9, 10 ** 11), Fr(5) + Fr(9, 10 ** 11)):
        n = reference_gradient(a, Fr(5, 2), (6.0, 10.0))
        assert np.hypot(*(G[0] - n)) <= e[0]
        assert np.hypot(*(n - np.array([3.0, 8.0]) / np.sqrt(73.0))) > 1e-12
