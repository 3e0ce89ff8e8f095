"""The accounting at infinity (runtime/voronoi/verify/closure.py, verify_accounting_conics) where a
gap between two sectors at infinity starts within the float rounding margin μ of a tie: only the
ball fallback (support_balls.sole_maximum) decides, and its verdict must be the exact one.

Three points p0 = (0, 0), p1 = (4, 0), p2 = (0, 3) (thesis §1.2: far away the nearest site is the
one with the largest support function h_k(θ) = u(θ)·(p_k − m)).  The outer normals of the hull's
edges give the three ties at infinity: θ01 = 3π/2, θ12 = atan2(4, 3), θ20 = π.  On the arc
between the sectors of (1, 2) and (2, 0) the shared site is p2, and

    h_2 − h_1 = u·(p2 − p1) = −4 cos θ + 3 sin θ = 5 sin(θ − θ12),   h_2 − h_0 = 3 sin θ,

so p2 strictly leads on [θb, π − 10⁻³] exactly when θb > θ12 (the arc lies in (0, π) and in
(θ12, θ12 + π) then; at θb ≤ θ12 p1 ties or leads at θb).  The sector of (1, 2) is made to end at
doubles θb a few ulps to 10⁻¹³ from θ12, where |h_2 − h_1| ≤ 5·10⁻¹³ is far below 2μ (μ ≈ 10⁻¹⁰
here), so no float comparison decides; the expected verdict is the sign of sin(θb − θ12) in
mpmath at 50 digits.
"""
from __future__ import annotations

import math
from fractions import Fraction

import mpmath

from curvedvoronoi.runtime.predicates.circles import Point
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify.closure import verify_accounting_conics
from curvedvoronoi.runtime.voronoi.verify.support import SupportTable

W = 1e-3     # half-width of the sectors given to the accounting


def _ends(theta_b):
    """The three ends at infinity (θ, pair, sector, edge id), the sector of (1, 2) ending at θb."""
    t01, t12, t20 = 1.5 * math.pi, math.atan2(4, 3), math.pi
    return [(t01, (0, 1), (t01 - W, t01 + W), 0),
            (t12, (1, 2), (t12 - W, theta_b), 1),
            (t20, (2, 0), (t20 - W, t20 + W), 2)]


def test_a_gap_starting_within_the_rounding_margin_of_a_tie_is_decided_exactly():
    mpmath.mp.dps = 50
    pts = [Point(Fraction(0), Fraction(0)), Point(Fraction(4), Fraction(0)), Point(Fraction(0), Fraction(3))]
    sup = SupportTable([site_geometry(p) for p in pts])
    t12 = math.atan2(4, 3)
    exact_t12 = mpmath.atan2(4, 3)
    below, above = [t12], [t12]
    for _ in range(4):                       # 1 to 4 ulps on either side of the double nearest θ12
        below.append(math.nextafter(below[-1], -math.inf))
        above.append(math.nextafter(above[-1], math.inf))
    thetas = sorted(set(below[1:] + above[1:] + [t12 + 1e-13, t12 - 1e-13, t12 + 1e-14, t12 - 1e-14]))
    seen = set()
    for tb in thetas:
        gap = 5 * mpmath.sin(mpmath.mpf(tb) - exact_t12)        # h_2 − h_1 at θb, exactly signed
        assert gap != 0 and abs(gap) < 2 * sup.mu               # no float comparison can decide
        expected = gap > 0
        probs: list = []
        got = verify_accounting_conics(3, sup, _ends(tb), probs)
        assert got == expected, (tb, float(gap), probs)
        assert expected or any("far directions" in m for m in probs), probs
        seen.add(expected)
    assert seen == {True, False}


def test_a_gap_clear_of_the_ties_is_owned_and_a_missing_end_is_not():
    """The same scene with sectors clear of the ties is accounted for; without the end of (1, 2)
    the gap from (0, 1) to (2, 0) shares p0 but p1 and p2 lead inside it (h_1 − h_0 = 4 cos θ > 0
    at θ = 0), so the accounting refuses."""
    pts = [Point(Fraction(0), Fraction(0)), Point(Fraction(4), Fraction(0)), Point(Fraction(0), Fraction(3))]
    sup = SupportTable([site_geometry(p) for p in pts])
    ends = _ends(math.atan2(4, 3) + W)
    probs: list = []
    assert verify_accounting_conics(3, sup, ends, probs), probs
    probs = []
    assert not verify_accounting_conics(3, sup, [ends[0], ends[2]], probs)
    assert any("far directions" in m for m in probs), probs


def test_a_gap_starting_half_an_ulp_before_the_tie_is_refused():
    """θb = the double nearest θ12 = atan2(4, 3), which lies 4.5·10⁻¹⁷ below θ12: at θb,
    h_2 − h_1 = 5 sin(θb − θ12) ≈ −2.3·10⁻¹⁶ < 0 (mpmath), so p2 does not lead on the gap."""
    mpmath.mp.dps = 50
    pts = [Point(Fraction(0), Fraction(0)), Point(Fraction(4), Fraction(0)), Point(Fraction(0), Fraction(3))]
    sup = SupportTable([site_geometry(p) for p in pts])
    tb = math.atan2(4, 3)
    assert 5 * mpmath.sin(mpmath.mpf(tb) - mpmath.atan2(4, 3)) < 0
    assert not verify_accounting_conics(3, sup, _ends(tb), [])
