"""The convexity rule of the segment certificate (runtime/segments/certificate_rules.py:
convex_tangents) at its boundary: along the line y = 0 with ρ = 1 (the bisector of the lines
y = 1 and y = −1), a point site p has g(x) = |x − p| − 1, convex.  The rule is sufficient: it
proves g > 0 on [a, b] when the tangents at a and b are positive up to and from a common point,
and must never claim it when g vanishes somewhere in [a, b]."""
from __future__ import annotations

import numpy as np
import pytest
from flint import arb

from curvedvoronoi.runtime.segments.certificate_curves import Line
from curvedvoronoi.runtime.segments.certificate_rules import convex_tangents
from curvedvoronoi.runtime.segments.elementary import ARC, POINT


class _Table:
    kind = np.array([POINT])      # one point site (not an arc)


def _fns(px, py):
    px, py = arb(px), arb(py)

    def value(t, X, Y, rho):
        return ((X - px) ** 2 + (Y - py) ** 2).sqrt() - rho

    def deriv(t, X, Y):
        return (X - px) / ((X - px) ** 2 + (Y - py) ** 2).sqrt()      # d/dx |x − p|, ρ' = 0
    return value, deriv


LINE = Line("segments", (0, 0), wq=(1, 0), side=((arb(0), arb(1)), (arb(0), arb(-1))))


@pytest.mark.parametrize("p,a,b,expected", [
    ((5, 6), 0.0, 10.0, True),          # tangent at 0 stays positive up to 10.6 > 10
    ((5, 1.5), 0.0, 10.0, False),       # g > 0, but its tangents vanish at 4.4 and 5.6: not claimed
    ((5, 0.5), 0.0, 10.0, False),       # g(5) = −0.5 although g(0), g(10) > 0
    ((5, 1), 0.0, 10.0, False),         # g(5) = 0: touching in the middle
    ((0, 0.5), 0.0, 10.0, False),       # g(0) = −0.5 < 0 with slope 0 there
    ((-3, 0.5), 0.0, 10.0, True),       # increasing from g(0) = √9.25 − 1
    ((13, 0.5), 0.0, 10.0, True),       # decreasing to g(10) = √9.25 − 1
])
def test_convex_tangents_boundary(p, a, b, expected):
    assert LINE.rho(arb(0), arb(0), arb(0)) == 1
    assert convex_tangents(_Table(), LINE, 0, _fns(*p), a, b) is expected


def test_convex_tangents_needs_an_affine_radius_and_a_convex_site():
    anchored = Line("point", (0, 0), wq=(1, 0), anchor=(0, 1))
    assert convex_tangents(_Table(), anchored, 0, _fns(5, 3), 0.0, 10.0) is False

    class _Arcs:
        kind = np.array([ARC])
    assert convex_tangents(_Arcs(), LINE, 0, _fns(5, 3), 0.0, 10.0) is False
