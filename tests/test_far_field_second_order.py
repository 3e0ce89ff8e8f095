"""The second-order terms of the far-field gap bound (runtime/voronoi/verify/far_field.py,
support_gap_lower / gap_lower): the δ² term on an input where it is exact to leading order, and the
curvature term of the slope enclosure (slope_square) where h_s' grows across the cell.

Two points s = (2, 0), k = (−2, 0), their bounding-box centre m = 0, W = 2: h_s(θ) = 2 cos θ,
h_k(θ) = −2 cos θ, so h_s − h_k = 4 cos θ with (h_s − h_k)'' = −4 at θ = 0, while the bound's
curvature constants are M_s = M_k = ρ + W = 2 (points, ρ = 0; Schneider, *Convex Bodies*, §1.7:
h + h'' = ρ): the term (M_s + M_k)·δ²/2 = 2δ² is exactly the dip of 4 cos δ = 4 − 2δ² + O(δ⁴).
Along the cell θ ∈ [−δ, δ], t = t0 the true gap is d_k − d_s = 8t cos θ / (d_k + d_s)
≤ 4 cos θ (d_k + d_s ≥ 2t), computed here in mpmath at 40 digits from the two distances.
Without the δ² term the bound would claim d_k − d_s ≥ 4 − O(μ + δ²/t) at θ = ±δ, where the
truth is 4 − 2δ² + O(δ⁴): false for every δ above ~10⁻⁵ (μ = 5·10⁻¹¹ here).
"""
from __future__ import annotations

from fractions import Fraction

import mpmath
import numpy as np

from curvedvoronoi.runtime.predicates.circles import Point
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify import far_field
from curvedvoronoi.runtime.voronoi.verify.support import SupportTable


def _dist(p, t, th):
    return mpmath.sqrt((t * mpmath.cos(th) - p[0]) ** 2 + (t * mpmath.sin(th) - p[1]) ** 2)


def test_the_second_order_term_is_needed_where_the_support_gap_is_curved():
    mpmath.mp.dps = 40
    S, K = (2, 0), (-2, 0)
    sup = SupportTable([site_geometry(Point(Fraction(S[0]), Fraction(S[1]))),
                        site_geometry(Point(Fraction(K[0]), Fraction(K[1])))])
    assert list(sup.m) == [0.0, 0.0]
    for half in (1e-2, 1e-3, 1e-4):
        for t0 in (1e3, 1e4, 1e5):
            lo = float(far_field.gap_lower(sup, 0, 1, 0.0, half, t0, t0))
            xs = [mpmath.mpf(half) * j / 8 for j in range(-8, 9)]
            true = min(_dist(K, t0, x) - _dist(S, t0, x) for x in xs)
            assert lo <= true, (half, t0, lo, float(true))
            # the truth at the cell's edges is below 4 − 2δ² + δ⁴/6, so the bound must be too
            assert true <= 4 - 2 * mpmath.mpf(half) ** 2 + mpmath.mpf(half) ** 4 / 6
            # on the one-direction cell (δ = 0) the same bound is within 2μ + W²·(ρ + 2W)/t0² of 4
            lo0 = float(far_field.gap_lower(sup, 0, 1, 0.0, 0.0, t0, t0))
            true0 = _dist(K, t0, 0) - _dist(S, t0, 0)
            assert lo0 <= true0 <= lo0 + 2 * sup.mu + 8 * sup.W ** 3 / t0 ** 2 + 1e-15 * 8


def test_the_slope_enclosure_keeps_the_change_of_h_prime_on_the_cell():
    """slope_square encloses h'² on the cell through |h''| ≤ M = ρ + W: the loss h_s'²/(2(t0 − W))
    must use the largest |h_s'| on the cell, not its value at θc.  Points s = (−27/10, −21/10),
    k = (23/10, −13/10) about m = 0: at θc = 3.05, h_s' = (p_s − m)·u⊥ ≈ 2.34 and h_s'' = −h_s ≈ −2.50
    (a point: ρ = 0), so |h_s'| grows to ≈ 2.57 at θc − 0.1 and ≈ 3.0 at θc − 0.3, and d_s − (t − h_s)
    ≈ h_s'²/(2t) with it; the bound must stay below the true d_k − d_s on the cell (mpmath, 30 digits,
    41 directions × 5 radii)."""
    mpmath.mp.dps = 30
    S, K = (Fraction(-27, 10), Fraction(-21, 10)), (Fraction(23, 10), Fraction(-13, 10))
    sup = SupportTable([site_geometry(Point(*S)), site_geometry(Point(*K))]).recentred(np.zeros(2))
    Sm = tuple(mpmath.mpf(x.numerator) / x.denominator for x in S)
    Km = tuple(mpmath.mpf(x.numerator) / x.denominator for x in K)
    for thc, half, t0, t1 in ((3.05, 0.3, 17.0, 17.0), (3.05, 0.3, 17.0, 25.5), (3.05, 0.1, 17.0, 17.0),
                              (3.05, 0.03, 17.0, 17.0), (3.05, 0.3, 50.0, 50.0)):
        lo = float(far_field.gap_lower(sup, 0, 1, thc, half, t0, t1))
        th = [mpmath.mpf(thc) + mpmath.mpf(half) * j / 20 for j in range(-20, 21)]
        ts = [mpmath.mpf(t0) + (mpmath.mpf(t1) - t0) * j / 4 for j in range(5)]
        true = min(_dist(Km, t, x) - _dist(Sm, t, x) for x in th for t in ts)
        assert lo <= true, (thc, half, t0, t1, lo, float(true))
