"""The link of a tail far from its sites (runtime/voronoi/verify/tail_link.py): the signs of
f = d_i − d_j at the two points Q± of the link circle must exceed the rounding of Q± (the float
circle points), not a fixed fraction of the circle's radius.  Measured on random_ellipses(10000, 1):
the link circle of an unbounded edge at r = 1.34·10⁶ had f ∈ ∓[0.93, 1.08]·10⁻⁶ at Q± (enclosures
7·10⁻⁸ wide) and was refused against a margin of 4·10⁻¹²·r = 5.4·10⁻⁶.

Points i = (−100, 0), j = (100, 0), k = (0, −200): the edge (i, j) is the ray x = 0 upwards.  A
rectangle {x0 + λ, 10⁶ + s : s ∈ [0, 10], |λ| ≤ 2·10⁻³}: on x = ±2·10⁻³ at y = 10⁶, |f| ≈ 4·10⁻⁷."""
from __future__ import annotations

import math

import numpy as np
import pytest

from curvedvoronoi.runtime.predicates.circles import Point
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify.site_table import SiteTable
from curvedvoronoi.runtime.voronoi.verify.support import SupportTable
from curvedvoronoi.runtime.voronoi.verify.tail import prove_tail

Y = 1e6
W = 2e-3


def _exact_f(x, y):
    """d_i − d_j at (x, y) in exact rationals' square roots (mpmath, 50 digits): the reference."""
    import mpmath
    mpmath.mp.dps = 50
    x, y = mpmath.mpf(x), mpmath.mpf(y)
    return mpmath.sqrt((x + 100) ** 2 + y ** 2) - mpmath.sqrt((x - 100) ** 2 + y ** 2)


@pytest.mark.parametrize("x0, linked", [(0.0, True), (3 * W, False), (-3 * W, False), (1.2 * W, False)])
def test_a_far_tail_links_where_the_signs_are_proved(x0, linked):
    G = [site_geometry(s) for s in (Point(-100, 0), Point(100, 0), Point(0, -200))]
    link = (np.array([x0, Y]), np.array([0.0, 1.0]), np.array([1.0, 0.0]), 10.0, W, 5.0)
    # the reference: f changes sign across the rectangle exactly when x0 is within W of x = 0
    assert (_exact_f(x0 - W, Y + 5) < 0 < _exact_f(x0 + W, Y + 5)) is linked
    assert abs(_exact_f(0.97 * W, Y + 5)) > 3e-7
    ok, msg, J = prove_tail(SupportTable(G), SiteTable(G, 300.0), (0, 1), link, 300.0)
    assert ok is linked, msg
    if linked:
        assert J[0] < math.pi / 2 < J[1]
    else:
        assert "crossing of the link circle" in msg


class _Values:
    def __init__(self, lo, hi):
        self.lo, self.hi = np.asarray(lo, float), np.asarray(hi, float)


class _Table:
    """Enclosures of d_i, d_j at Q−, Q+ (rows i, i, j, j) with f = d_i − d_j = ∓δ exactly."""

    def __init__(self, delta):
        self.delta = delta

    def evaluate(self, Q, K):
        base = 1e6
        return _Values([base - self.delta, base + self.delta, base, base],
                       [base - self.delta, base + self.delta, base, base])


@pytest.mark.parametrize("factor, linked", [(0.0, False), (0.5, False), (0.9, False), (2.5, True), (100.0, True)])
def test_the_link_signs_must_exceed_the_rounding_of_the_circle_points(factor, linked):
    """|f(Q±)| must exceed 2·(6u·(|m| + r)): the circle points at φ± are that close to the float
    Q± and f is 2-Lipschitz, so a smaller |f| at Q± proves no sign on the circle."""
    from curvedvoronoi.runtime.voronoi.verify.tail_link import link_arc

    m = np.array([0.0, 0.0])
    link = (np.array([0.0, Y]), np.array([0.0, 1.0]), np.array([1.0, 0.0]), 10.0, W, 5.0)
    r = Y + 5.0
    rnd = 6 * 2.0 ** -53 * r
    ok, msg, *_ = link_arc(m, _Table(factor * 2 * rnd), (0, 1), link, 300.0)
    assert ok is linked, msg
