"""The verifier's second-order bounds at the boundaries of their inequalities, with exact expected
verdicts derived here (runtime/voronoi/verify/distance_gap.py, (T4') of
runtime/voronoi/verify/strips.py).

**gap_lower** (d_k − d_i ≥ lo_k − hi_i − R·(|G_k − G_i| + s) − R²/(2(lo_i − R)) on B(Q, R)):
point sites i = (0, 0), k = (−1, 0) and Q = (X, 0), X > 0.  Then d_k(Q) − d_i(Q) = 1 exactly,
both gradients are (1, 0) (the first-order term vanishes), d_i(Q) = X, and the documented bound
is 1 − R²/(2(X − R)).  With R = 4 it is 0 at X = 12 (16/(2·8) = 1), and its derivative in X is
R²/(2(X − R)²) = 1/8, so X = 12 ± 2⁻²⁶ gives ±1.9·10⁻⁹ (the enclosures' own slack is below
10⁻¹¹ here): proved at 12 + 2⁻²⁶, not at 12 (margin 0) nor at 12 − 2⁻²⁶.
Exact truth on the sound side: k = (0, 1), i = (0, −1), Q = (10, −1/2): on B(Q, 1/2), which
touches the bisector y = 0 at (10, 0), min(d_k − d_i) = 0, and on B(Q, 1/2 + 2⁻³⁰) it is < 0:
neither may be proved.

**(T4')** (ς·f ≥ fval − h·|∇f(Qs)·t| − h²/2·max_k min(|t × G_k| + s_k, 1)²/(lo_k − h) on the
side {Qs + s·t : |s| ≤ h}, G_k ± s_k the enclosure of ∇d_k on the disc B(Qs, h), s_k = 2h/(d_k − h)
for a point up to rounding): i = (3, 4), j = (5, 12) (points), Qs = (0, 0), t = (1, 0), h = 1:
d_i = 5, d_j = 13, ∇d_i = (−3/5, −4/5), ∇d_j = (−5/13, −12/13), ∇f·t = −3/5 + 5/13 = −14/65;
|t × ∇d_i| + s_i = 4/5 + 1/2 ≥ 1 and |t × ∇d_j| + s_j = 12/13 + 1/6 ≥ 1 (capped at 1), so
M = max(1/4, 1/12) = 1/4 and the bound is fval − 14/65 − 1/8 = fval − 177/520: a midpoint bound
fval = 177/520 + 10⁻⁹ proves the side, 177/520 (margin 0) and 177/520 − 10⁻⁹ do not.
Soundness against dense sampling: with
fval = d_j(Qs) − d_i(Qs) = 8 the bound never exceeds min over the side of d_j − d_i (the side
here: |s| ≤ h for h = 1/2, 1, 2, M computed as documented with the exact gradients' cross
products widened by the disc terms).
"""
from __future__ import annotations

from fractions import Fraction as Fr

import numpy as np
import pytest

from curvedvoronoi.runtime.predicates.circles import Circle, Point
from curvedvoronoi.runtime.sites.conic import Conic
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify.distance_gap import gap_lower
from curvedvoronoi.runtime.voronoi.verify.site_table import SiteTable
from curvedvoronoi.runtime.voronoi.verify.strips import side_second_order
from curvedvoronoi.runtime.voronoi.verify.site_table import gradient_enclosure


def table_of(*sites):
    return SiteTable([site_geometry(s) for s in sites], 20.0)


def gap(table, Q, k, i, R):
    Q = np.array([Q], float)
    return float(gap_lower(Q, table.evaluate(Q, [k]), table.evaluate(Q, [i]), np.array([R]), 20.0)[0])


@pytest.mark.parametrize("X, proved", [(12.0 + 2.0 ** -26, True), (12.0, False), (12.0 - 2.0 ** -26, False)])
def test_gap_lower_at_its_boundary(X, proved):
    """1 − R²/(2(X − R)) with R = 4: +1.9e-9, 0, −1.9e-9 (module docstring)."""
    t = table_of(Point(0, 0), Point(-1, 0))
    g = gap(t, (X, 0.0), 1, 0, 4.0)
    assert (g > 0) is proved
    assert abs(g - (1 - 16 / (2 * (X - 4)))) < 1e-10


@pytest.mark.parametrize("R", [0.5, 0.5 + 2.0 ** -30])
def test_gap_lower_never_proves_a_disc_touching_the_bisector(R):
    """k = (0, 1), i = (0, −1), Q = (10, −1/2): min of d_k − d_i on the disc is 0, resp. < 0."""
    t = table_of(Point(0, -1), Point(0, 1))
    assert not gap(t, (10.0, -0.5), 1, 0, R) > 0


def test_gap_lower_is_below_the_sampled_minimum_for_ellipses():
    """Ellipses far out (the case it is made for): the bound never exceeds the minimum of
    d_k − d_i over 400 points of the disc (float distances, 1e-9 allowance)."""
    e1 = Conic.ellipse(centre=(Fr(0), Fr(0)), axes=(Fr(2), Fr(1)), rotation=(Fr(3, 5), Fr(4, 5)))
    e2 = Conic.ellipse(centre=(Fr(-3), Fr(1, 4)), axes=(Fr(3, 2), Fr(1)), rotation=(Fr(1), Fr(0)))
    t = table_of(e1, e2)
    rng = np.random.default_rng(3)
    seen = 0
    for _ in range(40):
        ang = rng.uniform(-0.3, 0.3)
        dist = 10 ** rng.uniform(1.5, 4)
        Q = (dist * np.cos(ang), dist * np.sin(ang))
        R = dist * 10 ** rng.uniform(-4, -1)
        g = gap(t, Q, 1, 0, R)
        a = rng.uniform(0, 2 * np.pi, 400)
        rr = R * np.sqrt(rng.uniform(0, 1, 400))
        P = np.column_stack([Q[0] + rr * np.cos(a), Q[1] + rr * np.sin(a)])
        P = np.vstack([P, np.array(Q)[None, :] + R * np.column_stack([np.cos(a), np.sin(a)])])
        diff = t.geoms[1].distance(P) - t.geoms[0].distance(P)
        assert g <= diff.min() + 1e-9 * dist, (Q, R, g, diff.min())
        seen += g > 0
    assert seen >= 5          # the bound decides a fair share of these discs


def side(fval, h=1.0):
    t = table_of(Point(3, 4), Point(5, 12))
    Qs = np.array([[0.0, 0.0]])
    Vi, Vj = t.evaluate(Qs, [0]), t.evaluate(Qs, [1])
    hh = np.array([h])
    Gi, si, _ = gradient_enclosure(Qs, Vi, hh, 20.0)
    Gj, sj, _ = gradient_enclosure(Qs, Vj, hh, 20.0)
    return bool(side_second_order(Qs, np.array([[1.0, 0.0]]), hh, np.array([fval]), Vi, Vj, Gi, si, Gj, sj, 20.0)[0])


@pytest.mark.parametrize("fval, proved", [(177 / 520 + 1e-9, True), (177 / 520, False), (177 / 520 - 1e-9, False)])
def test_side_second_order_at_its_boundary(fval, proved):
    """fval − 177/520 decides (module docstring)."""
    assert side(fval) is proved


def test_side_second_order_is_sound_along_the_side():
    """The documented bound with fval = 8 (= d_j − d_i at Qs) against d_j − d_i on 2001 points of
    the side: where it proves the side, the sampled minimum is positive, and the bound is below it."""
    i, j = np.array([3.0, 4.0]), np.array([5.0, 12.0])
    for h in (0.5, 1.0, 2.0):
        s = np.linspace(-h, h, 2001)
        P = np.column_stack([s, np.zeros_like(s)])
        f = np.hypot(*(P - j).T) - np.hypot(*(P - i).T)
        M = max(min(0.8 + 2 * h / (5 - h), 1) ** 2 / (5 - h), min(12 / 13 + 2 * h / (13 - h), 1) ** 2 / (13 - h))
        bound = 8 - h * 14 / 65 - h * h / 2 * M
        assert bound <= f.min() + 1e-12
        assert side(8.0, h) and f.min() > 0


def test_gap_lower_refuses_discs_that_reach_a_site():
    """k = the circle of radius 1 at the origin, i = the point (1.1, 0), Q = (1.5, 0), R = 1: the
    disc holds (1, 0) on the circle, where d_k − d_i = 0 − 0.1 < 0, so no lower bound may be
    positive.  (At Q, d_k − d_i = 0.5 − 0.4 > 0 and both gradients are (1, 0); the second-order
    term needs d_i ≥ lo_i − R > 0 on the disc, here lo_i = 0.4 < R.)"""
    t = table_of(Circle(0, 0, 1), Point(Fr(11, 10), 0))
    assert not gap(t, (1.5, 0.0), 0, 1, 1.0) > 0


def test_support_range_to_second_order_at_a_maximum():
    """Points (±100, 0): about m = (0, 0), h_0(θ) = 100·cos θ exactly, maximal at θ = 0 (h' = 0,
    h'' = −h, ρ = 0).  On [−0.01, 0.01] the true minimum is 100·cos 0.01 = 100 − 0.005 +
    4.2·10⁻⁷; the second-order enclosure 100 ± (0·0.01 + (0 + W)·0.01²/2) reaches down to
    100 − 0.005 (W = 100 up to 10⁻⁹ relative), below the true minimum by only 4.2·10⁻⁷, and the
    first-order one (W·0.01 = 1) is 200 times wider.  A bound halving the second-order term
    (100 − 0.0025) would exclude the true minimum."""
    from curvedvoronoi.runtime.voronoi.verify.support import SupportTable

    sup = SupportTable([site_geometry(Point(100, 0)), site_geometry(Point(-100, 0))])
    lo, hi = sup.h_range(0, 0.0, 0.01)
    true_min = 100 * np.cos(0.01)
    assert lo <= true_min and hi >= 100.0
    assert true_min - lo < 1e-6
    # the same at the interval's end: h' = −100·sin θ there, and the range holds θ = 0 (h = 100)
    lo, hi = sup.h_range(0, 0.01, 0.01)
    assert lo <= 100 * np.cos(0.02) and hi >= 100.0


def bgap(table, Q, k, i, j, R):
    from curvedvoronoi.runtime.voronoi.verify.distance_gap import bisector_gap_lower

    Q = np.array([Q], float)
    return float(bisector_gap_lower(Q, table.evaluate(Q, [k]), table.evaluate(Q, [i]), table.evaluate(Q, [j]),
                                    np.array([R]), 20.0)[0])


@pytest.mark.parametrize("da, proved", [(1e-9, True), (0.0, False), (-1e-9, False)])
def test_bisector_gap_lower_at_its_boundary(da, proved):
    """On β = {d_i = d_j} of i = (0, −3), j = (0, 3) (the x-axis), k = (−a, 0), Q = (4, 0), R = 1:
    d_i = d_j = 5, d_k = 4 + a, ∇d_i = (4, 3)/5, ∇d_j = (4, −3)/5, ∇d_k = (1, 0); the λ that
    cancels ∇(d_k − d_i) along ∇(d_i − d_j) = (0, 6/5) is −1/2, so g_λ = d_k − d_i/2 − d_j/2 with
    g_λ(Q) = a − 1, |∇g_λ(Q)| = |(1, 0) − (4/5, 0)| = 1/5 and the concave part
    R²/2·(1/2 + 1/2)/(5 − R) = 1/8: the bound is a − 1 − 1/5 − 1/8 = a − 53/40.  a = 53/40 + δ
    decides: proved for δ = 10⁻⁹, not for 0 or −10⁻⁹."""
    a = 53 / 40 + da
    t = table_of(Point(0, -3), Point(0, 3), Point(-a, 0))
    g = bgap(t, (4.0, 0.0), 2, 0, 1, 1.0)
    assert (g > 0) is proved
    assert abs(g - da) < 1e-10


def test_bisector_gap_lower_holds_on_the_bisector_only():
    """The same sites with a = 1.5 (k = (−1.5, 0)): at q = (4, 1), in the disc, d_k − d_i =
    √31.25 − √32 < 0, so no bound on the whole disc (gap_lower) may be positive; on β (the
    x-axis) d_k − d_i = x + 1.5 − √(x² + 9) > 0 for x ∈ [3, 5], and the bound on β is
    a − 53/40 = 0.175."""
    t = table_of(Point(0, -3), Point(0, 3), Point(-1.5, 0))
    assert not gap(t, (4.0, 0.0), 2, 0, 1.0) > 0
    assert bgap(t, (4.0, 0.0), 2, 0, 1, 1.0) > 0.17
    x = np.linspace(3, 5, 201)
    assert (x + 1.5 - np.sqrt(x * x + 9) > 0).all()


def test_bisector_gap_lower_is_below_the_minimum_on_the_bisector():
    """Ellipses i, j and a third ellipse k: wherever the bound is positive on a disc, d_k − d_i is
    positive at the points of β in the disc (β found by bisection on 60 chords across it; float
    distances, 10⁻⁹ allowance), and the bound is below their minimum."""
    ei = Conic.ellipse(centre=(Fr(0), Fr(-2)), axes=(Fr(2), Fr(1)), rotation=(Fr(3, 5), Fr(4, 5)))
    ej = Conic.ellipse(centre=(Fr(0), Fr(3)), axes=(Fr(3, 2), Fr(1)), rotation=(Fr(1), Fr(0)))
    ek = Conic.ellipse(centre=(Fr(-5), Fr(1, 2)), axes=(Fr(2), Fr(3, 2)), rotation=(Fr(0), Fr(1)))
    t = table_of(ei, ej, ek)
    gi, gj, gk = t.geoms
    seen = 0
    for x0 in (10.0, 40.0, 150.0, 600.0):
        # a point of β near (x0, ·) by bisection on the vertical line
        lo_y, hi_y = -50.0, 50.0
        for _ in range(80):
            m = 0.5 * (lo_y + hi_y)
            f = gi.distance(np.array([[x0, m]]))[0] - gj.distance(np.array([[x0, m]]))[0]
            lo_y, hi_y = (m, hi_y) if f < 0 else (lo_y, m)
        Q = (x0, 0.5 * (lo_y + hi_y))
        for R in (0.01 * x0, 0.1 * x0):
            g = bgap(t, Q, 2, 0, 1, R)
            vals = []
            for xs in np.linspace(Q[0] - R, Q[0] + R, 60):
                a_, b_ = Q[1] - R, Q[1] + R
                fa = gi.distance(np.array([[xs, a_]]))[0] - gj.distance(np.array([[xs, a_]]))[0]
                for _ in range(80):
                    m = 0.5 * (a_ + b_)
                    fm = gi.distance(np.array([[xs, m]]))[0] - gj.distance(np.array([[xs, m]]))[0]
                    a_, b_ = (m, b_) if np.sign(fm) == np.sign(fa) else (a_, m)
                q = np.array([[xs, 0.5 * (a_ + b_)]])
                if np.hypot(*(q[0] - Q)) <= R:
                    vals.append(gk.distance(q)[0] - gi.distance(q)[0])
            if vals:
                assert g <= min(vals) + 1e-9 * x0, (Q, R, g, min(vals))
                seen += g > 0
    assert seen >= 2


def test_bisector_gap_lower_refuses_a_disc_holding_a_site_of_the_pair():
    """i = (0, −3), j = (0, 3), k = (25/8, −3/4), Q = (−1, 13/8), R = 9/4: the disc holds j
    (|Q − j| = √2.890625 < 9/4) and the point q = (1/2, 0) of β ((3/2)² + (13/8)² = 4.890625 ≤
    5.0625), where d_k − d_i = √7.453125 − √9.25 = −0.31 < 0: not proved."""
    t = table_of(Point(0, -3), Point(0, 3), Point(Fr(25, 8), Fr(-3, 4)))
    assert np.sqrt(7.453125) - np.sqrt(9.25) < 0
    assert not bgap(t, (-1.0, 1.625), 2, 0, 1, 2.25) > 0


def test_bisector_gap_lower_uses_the_worst_ends_of_the_enclosures():
    """The configuration of the boundary test with a = 53/40 + 5·10⁻⁷ (g_λ's bound with exact
    distances: +5·10⁻⁷) and every distance enclosure widened to ±10⁻⁶ (still valid): the true
    distances may then be d_k − 10⁻⁶, d_i + 10⁻⁶, d_j + 10⁻⁶, for which g_λ's bound is
    5·10⁻⁷ − (1 + 1/2 + 1/2)·10⁻⁶ < 0, so it must not be proved."""
    from curvedvoronoi.runtime.voronoi.verify.distance_gap import bisector_gap_lower

    a = 53 / 40 + 5e-7
    t = table_of(Point(0, -3), Point(0, 3), Point(-a, 0))
    Q = np.array([[4.0, 0.0]])
    Vs = [t.evaluate(Q, [k]) for k in (2, 0, 1)]
    assert bisector_gap_lower(Q, *Vs, np.array([1.0]), 20.0)[0] > 0     # exact-width enclosures
    for V in Vs:
        V.lo, V.hi = V.lo - 1e-6, V.hi + 1e-6
    assert not bisector_gap_lower(Q, *Vs, np.array([1.0]), 20.0)[0] > 0
