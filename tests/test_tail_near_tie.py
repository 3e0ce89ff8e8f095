"""A near-tie at infinity of three ellipses (the tail prover, runtime/voronoi/verify/tail.py, with
the first-order far field of runtime/voronoi/verify/far_field.py).

Three ellipses with their leftmost points on x = 0 at heights 0, 50, 100, the second and third moved
right by ε and 4ε: far to the left (direction −x) the middle one leads on an interval of directions
of width ~ 2ε/50 between the others, so the unbounded edges (0, 1) and (1, 2) both go left, nearly
parallel, and along the first the third ellipse is only ~2ε + 2800/t farther than its sites (t
the distance from the scene).  ε = 0 is an exact tie in the direction −x (proved in rationals,
runtime/voronoi/verify/tied_tail.py), ε = 1/1000 the near-tie (proved by sectors to first order in
1/t: the zeroth-order bound d_k ≥ t − h_k cannot separate the third ellipse below t ~ 3·10⁶), ε = 10⁻⁹
and 10⁻¹² below the float rounding margin of the support functions (proved in balls,
runtime/voronoi/verify/support_balls.py).

The reference uses none of the library's geometry: distances to axis-aligned ellipses by dense
sampling of their boundaries, at points far to the left of the scene."""
from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

import curvedvoronoi as cv

#: (cx, cy, a, b) with ε-shifts of the centres' x (multiples of eps)
SCENE = [(2, 0, 2, 1, 0), (2, 50, 2, 1, 1), (3, 100, 3, 2, 4), (20, 50, 2, 1, 0)]


def sites(eps):
    return [cv.Conic.ellipse(centre=(Fraction(cx) + k * eps, Fraction(cy)), axes=(Fraction(a), Fraction(b)))
            for cx, cy, a, b, k in SCENE]


def nearest_far_left(eps, x, ys):
    """The nearest ellipse at the points (x, y), y in ys (dense boundary samples, float)."""
    s = np.linspace(0, 2 * np.pi, 4000, endpoint=False)
    D = []
    for cx, cy, a, b, k in SCENE:
        bx, by = float(cx + k * eps) + a * np.cos(s), cy + b * np.sin(s)
        D.append(np.hypot(x - bx[None, :], ys[:, None] - by[None, :]).min(1))
    return np.argmin(np.array(D), 0)


@pytest.mark.parametrize("eps", [Fraction(0), Fraction(1, 1000), Fraction(1, 10**9), Fraction(1, 10**12)])
def test_near_tie_at_infinity_is_certified_with_the_right_unbounded_edges(eps):
    d = cv.voronoi(sites(eps))
    assert d.certified, d.problems
    # the unbounded edges going left (far point of the polyline at x < −100)
    left = {tuple(e.sites) for e in d.edges if None in e.ends and np.asarray(e.polyline)[:, 0].min() < -100}
    ys = np.linspace(-40, 140, 721)
    owner = nearest_far_left(eps, -2e4, ys)
    expect = {tuple(sorted((int(a), int(b)))) for a, b in zip(owner[:-1], owner[1:]) if a != b}
    assert left == expect == {(0, 1), (1, 2)}


def test_balls_decide_a_support_gap_below_the_float_margin_and_only_its_true_sign():
    """h_0 − h_1 in the direction −x is −ε (site 1 sticks out by ε): proved negative in balls for
    ε = 10⁻¹² (10³ times below the float margin μ), positive for ε = −10⁻¹², and never the wrong way
    (the float direction π differs from −x by 1.2·10⁻¹⁶ rad: 6·10⁻¹⁵ of lateral tilt, far below ε)."""
    from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
    from curvedvoronoi.runtime.voronoi.verify.support import SupportTable
    from curvedvoronoi.runtime.voronoi.verify.support_balls import SupportBalls

    for eps, want in ((Fraction(1, 10**12), -1), (Fraction(-1, 10**12), 1)):
        s = [cv.Conic.ellipse(centre=(Fraction(2), Fraction(0)), axes=(Fraction(2), Fraction(1))),
             cv.Conic.ellipse(centre=(Fraction(3) - eps, Fraction(50)), axes=(Fraction(3), Fraction(2)))]
        sup = SupportTable([site_geometry(x) for x in s])
        assert sup.mu > 1e-10
        b = SupportBalls(sup)
        assert b.sign(0, 1, np.pi) == want
        assert not b.gap_lower(0 if want < 0 else 1, 1 if want < 0 else 0, np.pi, 0.0)
