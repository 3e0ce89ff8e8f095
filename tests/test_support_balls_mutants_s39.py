"""Ball support functions (runtime/voronoi/verify/support_balls.py) at the boundaries of their
claims, on scenes whose support functions are closed forms (Schneider, *Convex Bodies*, §1.7:
h_S(u) = max_{p ∈ S} u·(p − m); a point p gives u·(p − m), a circle of centre c and radius r gives
u·(c − m) + r).

* A point s = (10, 0) and the unit circle k about the origin: h_s − h_k = 10 cos θ − 1 exactly
  (the centre m cancels).  On the cell |θ| ≤ δ its minimum is 10 cos δ − 1, positive exactly for
  δ < arccos(1/10) ≈ 1.4706.  The cell bound of :meth:`SupportBalls.gap_lower` subtracts
  (M_s + M_k)·δ²/2 with M = ρ + W (|h''| = |ρ(θ) − h| ≤ ρ + W): it may refuse cells where the truth
  is positive but must never accept one where it is not; :func:`sole_maximum` likewise.
* An exact tie: h_s(θ) = h_k(θ) at a direction where both support values are equal as real
  numbers (two points on a line orthogonal to u, two equal circles with irrational radius √2).
  The docstring's promise: an exact tie is never decided here — the sign is 0 and no strict lead
  is proved, at every precision.
"""
from __future__ import annotations

from fractions import Fraction

import mpmath
import pytest

from curvedvoronoi.runtime.predicates.circles import Circle, Point
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify.support import SupportTable
from curvedvoronoi.runtime.voronoi.verify.support_balls import SupportBalls, sole_maximum


def _point_and_circle():
    return SupportTable([site_geometry(Point(Fraction(10), Fraction(0))),
                         site_geometry(Circle.from_radius(0, 0, 1))])


def _true_min(delta):
    """min over |θ| ≤ δ of h_s − h_k = 10 cos θ − 1 (δ ≤ π: at the cell's ends), mpmath."""
    return 10 * mpmath.cos(mpmath.mpf(delta)) - 1


@pytest.mark.parametrize("delta", [0.25, 0.5, 0.9, 1.3, 1.45, 1.5, 1.55, 1.6, 1.7, 2.0])
def test_a_ball_cell_bound_is_positive_only_where_the_support_gap_is(delta):
    sup = _point_and_circle()
    b = SupportBalls(sup)
    proved = b.gap_lower(0, 1, 0.0, delta)
    if proved:
        assert _true_min(delta) > 0, (delta, float(_true_min(delta)))
    if delta >= 1.5:                     # 10 cos δ − 1 < 0 there: a lead of k at the cell's ends
        assert not proved
    if delta <= 0.9:                     # the bound 9 − (M_s + M_k)·δ²/2 ≥ 9 − 6·0.81 > 0
        assert proved


@pytest.mark.parametrize("delta", [0.5, 1.2, 1.45, 1.5, 1.6])
def test_sole_maximum_of_the_point_against_the_circle(delta):
    """h_s > h_k on [−δ, δ] exactly when 10 cos δ > 1 (δ < 1.4706): sole_maximum may say False
    near the boundary (cells of width 10⁻¹⁵ are its limit) but never True past it."""
    sup = _point_and_circle()
    got = sole_maximum(sup, 0, -delta, delta)
    truth = _true_min(delta) > 0
    if got:
        assert truth, delta
    if delta <= 1.2:
        assert got
    if not truth:
        assert not got


def test_the_sign_of_an_exact_tie_of_two_points_is_zero():
    """Points (1, 0) and (1, 5) in the direction θ = 0: h = 1 − m_x for both (exact floats
    cos 0 = 1, sin 0 = 0), so h_0 − h_1 = 0; the point (2, 5) is ahead by 1."""
    sup = SupportTable([site_geometry(Point(1, 0)), site_geometry(Point(1, 5)), site_geometry(Point(2, 5))])
    b = SupportBalls(sup)
    assert b.sign(0, 1, 0.0) == 0
    assert b.sign(1, 0, 0.0) == 0
    assert b.sign(2, 0, 0.0) == 1
    assert b.sign(0, 2, 0.0) == -1
    assert not b.gap_lower(0, 1, 0.0, 0.0)
    assert not b.gap_lower(1, 0, 0.0, 0.0)
    assert b.gap_lower(2, 0, 0.0, 0.0)


def test_an_exact_tie_of_irrational_support_values_is_never_proved_a_lead():
    """Two circles of radius √2 about (0, 0) and (0, 5), direction θ = 0: h = √2 − m_x for both.
    The balls of the two values overlap at every precision (√2 is not a dyadic), so the tie is
    undecided: neither site may be proved ahead, and the sign is 0."""
    sup = SupportTable([site_geometry(Circle(0, 0, r2=2)), site_geometry(Circle(0, 5, r2=2))])
    b = SupportBalls(sup)
    assert b.sign(0, 1, 0.0) == 0
    assert not b.gap_lower(0, 1, 0.0, 0.0)
    assert not b.gap_lower(1, 0, 0.0, 0.0)
