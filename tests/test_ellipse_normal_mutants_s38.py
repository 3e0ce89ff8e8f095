"""The unit-normal ball of runtime/voronoi/verify/ellipse_normal.py (``_unit_normal_ball``) on a
box wide enough that the deviation bound's denominator matters.

For the normal N of the ellipse at the exact foot point, the module boxes N componentwise:
|N_X| ∈ [xl/(ah² + μ_hi), xh/(al² + μ_lo)] and likewise N_Y, both signs of a component whose
lower end is 0.  With unit axes and μ = 0 the box here is N ∈ [1, 3] × [−1, 1]: centre N₀ = (2, 0),
half-diagonal h = √2.  For every N with |N − N₀| ≤ h < |N₀|,
|N/|N| − N₀/|N₀|| ≤ h/(|N₀| − h) (the module's bound; the triangle inequality on
N/|N| − N₀/|N₀| = (N − N₀)/|N| + N₀(1/|N| − 1/|N₀|)).  The bound h/|N₀| alone is not enough:
the corner N = (1, 1) of the box has direction (1, 1)/√2, at distance
|(1/√2 − 1, 1/√2)| = √(2 − √2) ≈ 0.765 from (1, 0), more than h/|N₀| = √2/2 ≈ 0.707.  The test
samples the box densely (its corners included) and checks every direction against the returned
ball, the directions normalised here in numpy.
"""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from curvedvoronoi.runtime.voronoi.verify.ellipse_normal import _unit_normal_ball


def _box(xl, xh, yl, yh, X0, Y0):
    one = np.array([1.0])
    return SimpleNamespace(xl=np.array([xl]), xh=np.array([xh]), yl=np.array([yl]), yh=np.array([yh]),
                           al=one, ah=one, bl=one, bh=one, X0=np.array([X0]), Y0=np.array([Y0]))


def test_the_unit_normal_ball_holds_every_direction_of_a_wide_box():
    bx = _box(1.0, 3.0, 0.0, 1.0, X0=2.0, Y0=0.5)
    zero = np.array([0.0])
    ux, uy, en, mlow = _unit_normal_ball(bx, np.array([0]), zero, zero)
    assert mlow[0] > 0                        # |N₀| = 2 > h = √2: the bound applies
    g = np.linspace(0.0, 1.0, 201)
    NX, NY = np.meshgrid(1.0 + 2.0 * g, -1.0 + 2.0 * g)     # the box [1, 3] × [−1, 1], corners included
    norm = np.hypot(NX, NY)
    dev = np.hypot(NX / norm - ux[0], NY / norm - uy[0])
    assert dev.max() > np.sqrt(2) / 2         # the corner (1, 1): √(2 − √2) > h/|N₀|
    assert dev.max() <= en[0]


def test_a_box_around_the_origin_has_no_ball():
    """N ∈ [0, 1] × [0, 1] (both lower ends 0: both signs): the box holds N = 0 and opposite
    directions, so no ball of directions exists; the function must not report one (mlow ≤ 0)."""
    bx = _box(0.0, 1.0, 0.0, 1.0, X0=0.5, Y0=0.5)
    zero = np.array([0.0])
    with np.errstate(invalid="ignore", divide="ignore"):      # N₀ = 0: its direction is 0/0
        _, _, en, mlow = _unit_normal_ball(bx, np.array([0]), zero, zero)
    assert not mlow[0] > 0 or not np.isfinite(en[0])


def test_a_component_whose_lower_end_is_zero_takes_both_signs():
    """|N_X| ∈ [0, 1] (lower end 0: N_X may have either sign, whatever the float X0's sign) and
    N_Y ∈ [2, 3]: the box is [−1, 1] × [2, 3] and its directions reach (−1, 2)/√5 and (1, 2)/√5,
    both of which the ball must hold (a ball about the half-box [0, 1] × [2, 3] misses (−1, 2)/√5
    by about 0.65 − 0.38)."""
    bx = _box(0.0, 1.0, 2.0, 3.0, X0=0.25, Y0=2.5)
    zero = np.array([0.0])
    ux, uy, en, mlow = _unit_normal_ball(bx, np.array([0]), zero, zero)
    assert mlow[0] > 0
    g = np.linspace(0.0, 1.0, 201)
    NX, NY = np.meshgrid(-1.0 + 2.0 * g, 2.0 + g)
    norm = np.hypot(NX, NY)
    dev = np.hypot(NX / norm - ux[0], NY / norm - uy[0])
    assert dev.max() <= en[0]
