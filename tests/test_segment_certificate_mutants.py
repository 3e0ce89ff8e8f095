"""Predicates of the point/segment/arc certificate (runtime/segments/certificate*.py) at their
boundaries, with exact inputs and verdicts derived by hand below.

The quarter arc A of radius 2 centred at the origin runs counter-clockwise from a = (2, 0) to
b = (0, 2); its angular range is [0°, 90°], its gap (90°, 360°), the gap's middle direction
g = (−1, −1) (225°).  For a point x with direction φ from the centre:

* φ in the closed range: d(x, A) = | |x| − 2 |;
* φ in the gap: d(x, A) = min(|x − a|, |x − b|), and |x − a| < |x − b| exactly when x is on a's
  side of the bisector y = x of a and b, i.e. φ ∈ (225°, 360°) (mod 360°): there a is A's only
  nearest point ("the half of the gap next to a"); at φ = 225° both ends are nearest.
"""
from __future__ import annotations

import pytest
from flint import arb

from curvedvoronoi.runtime.predicates.circles import Point
from curvedvoronoi.runtime.segments.certificate_sites import SiteTable
from curvedvoronoi.runtime.sites.arc import Arc
from curvedvoronoi.runtime.sites.segment import Segment


def _quarter():
    """Sites 0 = a = (2, 0), 1 = b = (0, 2), 2 = the quarter arc A (module docstring)."""
    return SiteTable([Point(2, 0), Point(0, 2), Arc((0, 0), 2, (2, 0), (0, 2))])


# ----------------------------------------------------------------------------- owned_by_end

@pytest.mark.parametrize("x, y, end, owned", [
    (3, 3, 0, False),        # φ = 45°, in the range: nearest point (√2, √2), 3√2 − 2 < √10 = |x − a|
    (3, 3, 1, False),
    (1, -1, 0, True),        # φ = 315°, in the half of the gap next to a
    (1, -1, 1, False),
    (-1, -3, 0, True),       # φ ≈ 251.6° > 225°: still a's half (|x − a|² = 18 < 26 = |x − b|²)
    (-3, -1, 0, False),      # φ ≈ 198.4° < 225°: b's half (|x − a|² = 26 > 18)
    (-3, -1, 1, True),
    (-1, 5, 1, True),        # φ ≈ 101.3° ∈ (90°, 225°): b's half (|x − b|² = 10 < 34 = |x − a|²)
    (-1, 5, 0, False),
])
def test_an_arc_end_owns_exactly_the_half_of_the_gap_next_to_it(x, y, end, owned):
    """A's nearest point to x is its end ``end`` alone iff x's direction lies strictly in the half
    of the gap next to that end (module docstring); inside the range the nearest point is interior."""
    T = _quarter()
    assert T.owned_by_end(2, end, arb(x), arb(y)) is owned


@pytest.mark.parametrize("x, y, end, owned", [(3, 1, 1, True), (3, 1, 0, False), (-1, 1, 0, True),
                                              (-1, 1, 1, False), (1, 1, 0, False), (1, 1, 1, False)])
def test_a_segment_end_owns_exactly_the_points_beyond_it(x, y, end, owned):
    """Segment from (0, 0) (site 0) to (2, 0) (site 1): its nearest point to x is the end (0, 0)
    alone iff the foot parameter x/2 ≤ 0, the end (2, 0) alone iff x/2 ≥ 1."""
    T = SiteTable([Point(0, 0), Point(2, 0), Segment((0, 0), (2, 0))])
    assert T.owned_by_end(2, end, arb(x), arb(y)) is owned


# ----------------------------------------------------------------------------- ray_in_gap_half

@pytest.mark.parametrize("u, far, stays", [
    ((0, -1), None, True),          # (2, −τ): φ from 360° down to 270°
    ((-1, -2), None, True),         # φ → atan2(−2, −1) ≈ 243.4° > 225°, monotonically
    ((-2, -1), None, False),        # φ → ≈ 206.6° < 225°: the ray leaves a's half (at τ = 2)
    ((-2, -1), (0, -1), True),      # τ = 1: (0, −1), φ = 270°
    ((-2, -1), (-2, -2), False),    # τ = 2: φ = 225° exactly, both ends nearest (boundary, margin 0)
    ((-2, -1), (-4, -3), False),    # τ = 3: φ ≈ 216.9°, past the boundary
    ((0, 1), None, False),          # (2, τ): into the range, where A's nearest points are interior
])
def test_a_ray_from_an_arc_end_stays_in_the_half_of_its_gap(u, far, stays):
    """The ray a + τ·u (0 < τ, up to ``far``) stays where a is A's only nearest point iff every
    point of it has its direction in (225°, 360°) (module docstring); the cross product of
    g = (−1, −1) with a + τ·u = (2 + τ u_x, τ u_y) is 2 + τ(u_x − u_y), so with u = (−2, −1) it
    is 2 − τ: > 0 for τ < 2, 0 at τ = 2 (the bisector y = x of a and b)."""
    from curvedvoronoi.runtime.segments.certificate_corner_curves import ray_in_gap_half

    T = _quarter()
    f = None if far is None else (arb(far[0]), arb(far[1]))
    assert ray_in_gap_half(T, 2, 0, arb(u[0]), arb(u[1]), f) is stays


# ----------------------------------------------------------------------------- distance enclosures

def test_the_distance_to_an_arc_from_a_box_in_its_gap_holds_every_point_of_the_box():
    """The box [7/4, 9/4] × [−5/4, −3/4] around (2, −1): every direction from the centre lies in
    (270°, 360°), a's half of the gap, so d(x, A) = |x − a| ∈ [3/4, √(1/16 + 25/16)] (the box's
    nearest and farthest points from a = (2, 0)), far below |x − b| ≥ √(49/16 + 121/16) ≈ 3.26.
    The ball returned for the box must hold the distance of every point of the box: checked at
    its corners, its centre and the point (2, −3/4) nearest to a (distance 3/4 exactly)."""
    import math

    T = _quarter()
    X, Y = arb(2, 0.25), arb(-1, 0.25)
    d = T.distance(2, X, Y)
    for x, y in [(1.75, -1.25), (1.75, -0.75), (2.25, -1.25), (2.25, -0.75), (2, -1), (2, -0.75)]:
        true = math.hypot(x - 2, y)
        assert d.lower() <= true <= d.upper(), (x, y, true, d)
    # and it is an enclosure of the distance to the nearer end only (not a mix of both ends)
    assert d.upper() < math.hypot(1.75, -0.75 - 2)


# ----------------------------------------------------------------------------- corner_ratio

def _corner_scene():
    """Sites 0 = the corner c = (0, 0), 1 = (1, 1), 2 = the arc K of the circle of centre (0, 1)
    and radius 1 from c (direction 270° from the centre) counter-clockwise to (1, 1) (0°): its
    gap is (0°, 270°), the gap's middle 135°, and c is K's only nearest point from directions
    (135°, 270°)."""
    return SiteTable([Point(0, 0), Point(1, 1), Arc((0, 1), 1, (0, 0), (1, 1))])


@pytest.mark.parametrize("u, side, farther", [
    ((0, 1), None, False),            # (0, τ), τ ≤ 1: d_K = 1 − (1 − τ) = τ = |x − c| (nearest point c): a tie
    ((1, 2), None, False),            # (τ, 2τ) inside K's circle: d_K = 1 − √(1 − 4τ + 5τ²) ≈ 2τ < √5 τ
    ((-1, 0), ((-3, 4), 5), True),    # (−τ, 0): d_K = τ (direction from (0, 1) in (180°, 270°)) > ρ = 3τ/5
    ((-1, 0), None, False),           # the same ray against ρ = |x − c| = τ: a tie, not farther
])
def test_a_curve_through_a_corner_is_farther_on_the_ray_only_when_it_is(u, side, farther):
    """The edge from the corner c is the ray c + τ·u with ρ = |x − c| (the corner's own distance)
    or ρ = n̂·x for a unit normal n̂ (a segment's side); K is strictly farther than ρ on the whole
    ray exactly in the cases marked (distances by hand in the parametrisation)."""
    from fractions import Fraction

    from curvedvoronoi.runtime.segments.certificate_curves import Line, q_arb
    from curvedvoronoi.runtime.segments.certificate_rules import corner_ratio

    T = _corner_scene()
    O = (Fraction(0), Fraction(0))
    if side is None:
        c = Line("perp", O, wq=u, anchor=O)
    else:
        (nx, ny), d = side
        c = Line("segments", O, wq=u, side=((q_arb(Fraction(nx, d)), q_arb(Fraction(ny, d))), (q_arb(0), q_arb(0))))
    assert corner_ratio(T, c, 2, 0, True) is farther


# ----------------------------------------------------------------------------- pairs at infinity

def test_a_point_and_a_segment_not_ending_at_it_never_share_an_unbounded_edge():
    """Far out in a direction u the sites touching the support line with normal u follow each
    other along it, and a segment's neighbours there are its own ends (point sites: where the
    foot of a far point is clamped, the end ties with the segment and keeps the region), so a
    point p and a segment s with p not an end of s are never consecutive: here p = (0, 5) and
    s = [(−1, 0), (1, 0)]; its end (−1, 0) with s, and two points, may be."""
    from curvedvoronoi.runtime.segments.certificate_hull import _consecutive_ok

    T = SiteTable([Point(0, 5), Point(-1, 0), Point(1, 0), Segment((-1, 0), (1, 0))])
    assert _consecutive_ok(T, 0, 3) is False
    assert _consecutive_ok(T, 3, 0) is False
    assert _consecutive_ok(T, 1, 3) is True and _consecutive_ok(T, 3, 2) is True
    assert _consecutive_ok(T, 0, 1) is True


# ----------------------------------------------------------------------------- arc_pole

def _pole_case(p):
    from curvedvoronoi.runtime.segments.certificate_arcs import ArcCurve

    T = SiteTable([Point(2, 0), Point(0, 2), Arc((0, 0), 2, (2, 0), (0, 2)), Point(*p)])
    return ArcCurve(T, 2, 3, 1)          # p outside the arc's circle: side σ = +1


def test_a_pole_outside_the_arcs_range_is_never_its_pole():
    """The quarter arc A of radius 2 (range θ ∈ [0, π/2]) and the point p = (2, 5), which lies on
    A's tangent line x = 2 at its start (2, 0).  Their bisector x = (2 + t)·u(θ) (|x − p| = t) has
    t·Δ(θ) = N(θ) with Δ(θ) = 2ρ + 2(c − p)·u(θ) = 4 − 4 cos θ − 10 sin θ: a pole (the branch goes
    to infinity in the direction u(θ)) where Δ = 0, i.e. tan(θ/2)·(4 tan(θ/2) − 10) = 0:
    θ = 0 (the start, p on the tangent there) and θ = 2·atan(5/2) ≈ 136.4°, outside the range.
    ``arc_pole`` keeps the poles in the closed range only: the one at the start (decided in
    rationals), never 136.4° -- from θ_fin = 1 going up there is none."""
    from curvedvoronoi.runtime.segments.certificate_tails import arc_pole

    c = _pole_case((2, 5))
    far = 2 * arb(5 / 2).atan()
    poles = c.poles()
    assert any(q.overlaps(arb(0)) for q in poles) and any(q.overlaps(far) for q in poles)
    for sg in (1, -1):
        got = arc_pole(c, None, sg)
        assert got is not None and got.overlaps(arb(0)) and not got.overlaps(far)
    assert arc_pole(c, arb(1), 1) is None
    assert arc_pole(c, arb(1), -1).overlaps(arb(0))


def test_an_arc_with_both_poles_outside_its_range_has_none():
    """p = (3, 5) (not on a tangent at an end): Δ = 4 − 2(3 cos θ + 5 sin θ) vanishes where
    3 cos θ + 5 sin θ = 2, at θ ≈ −10.9° and θ ≈ 129.0°, both outside [0°, 90°]: no pole."""
    from curvedvoronoi.runtime.segments.certificate_tails import arc_pole

    c = _pole_case((3, 5))
    assert len(c.poles()) == 2
    assert arc_pole(c, None, 1) is None and arc_pole(c, None, -1) is None
