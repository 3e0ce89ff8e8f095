"""Ties at infinity (runtime/voronoi/verify/ties_at_infinity.py, :func:`tied_sectors`): a
direction counts as a tie only when the support values h_k(u) = max_{p ∈ S_k} u·p of the sites
are equal exactly (Schneider, *Convex Bodies*, §1.7), never when they agree only within the float
rounding margin μ of the support table.

* Two points (0, 0) and (1, 10⁻¹³) in the direction u = (0, 1) (or u = (0, 2), the same direction
  as a non-unit rational vector): h_b(u) − h_a(u) = 10⁻¹³ exactly (times |u|), far below μ ≈ 10⁻¹¹,
  so the floats put both among the leaders, but the second point leads alone and their bisector
  goes out along (−10⁻¹³, 1), not along u.  An end claimed for the pair along u is not a tie:
  tied_sectors must refuse it.
* The point (0, 0) and the unit circle about (3, −1) tie exactly in u = (0, 1) (both reach y = 0;
  no mirror maps a point onto a circle, so only the exact support levels prove the tie), and the
  points (0, 0), (1, 0) tie in u = (0, 2) by their mirror x = 1/2, parallel to u: both accepted,
  with one small sector of directions around u.
"""
from __future__ import annotations

import math
from fractions import Fraction

import pytest

from curvedvoronoi.runtime.predicates.circles import Circle, Point
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify.support import SupportTable
from curvedvoronoi.runtime.voronoi.verify.ties_at_infinity import tied_sectors


def _run(sites, u):
    sup = SupportTable([site_geometry(s) for s in sites])
    th = math.atan2(float(u[1]), float(u[0]))
    ends = [(th, (0, 1), ("mirror", u, 0.0), 7)]
    problems = []
    return tied_sectors(sup, sites, ends, problems), problems, sup


@pytest.mark.parametrize("u", [(Fraction(0), Fraction(1)), (Fraction(0), Fraction(2))])
def test_a_near_tie_below_the_float_margin_is_not_a_tie(u):
    eps = Fraction(1, 10 ** 13)
    sites = [Point(0, 0), Point(1, eps)]
    out, problems, sup = _run(sites, u)
    # the premise: the floats cannot tell the two support values apart, the exact ones differ
    assert 8 * sup.mu > float(eps)
    assert Fraction(str(sites[1].cy)) - Fraction(str(sites[0].cy)) == eps != 0
    assert out is None
    assert problems


def test_an_exact_tie_of_a_point_and_a_circle_is_accepted():
    u = (Fraction(0), Fraction(1))
    sites = [Point(0, 0), Circle.from_radius(3, -1, 1)]
    assert sites[1].cy + 1 == sites[0].cy           # the circle's top is at y = 0
    out, problems, _ = _run(sites, u)
    assert out is not None, problems
    (a0, a1, first, eid, last), = out
    assert first == last == (0, 1) and eid == 7
    assert a0 < math.pi / 2 < a1 or a0 < math.pi / 2 + 2 * math.pi < a1


def test_an_exact_tie_by_a_mirror_parallel_to_a_non_unit_direction_is_accepted():
    u = (Fraction(0), Fraction(2))
    out, problems, _ = _run([Point(0, 0), Point(1, 0)], u)
    assert out is not None, problems
    assert out[0][2] == (0, 1)
