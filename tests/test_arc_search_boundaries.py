"""The disc search of runtime/voronoi/verify/arc_search.py refuses an arc that a third site
reaches, where its first-order (slope) bound would be wrong.

Sites i, j: points (∓10, 0), or circles of radius 5 centred there; their bisector is the line
x = 0 (y = b·sinh u with b = 10, resp. b = √(100 − 0) = 10 for equal radii: the hyperbola with
a = 0).  A third point k = (0, y_k) ON that line, with y_k inside the arc's range [y_0, y_1], has
d_k = 0 at (0, y_k) while d_i = √(100 + y_k²) − r > 0 there: k is strictly nearer than i and j at a
point of the arc, so the arc is not a Voronoi edge of (i, j) and ``prove_arcs`` must refuse it.

This is where the slope bound ``_slope_bound`` (|∇d_k − ∇d_i| ≤ |G_k − G_i| + R/(|Q − c_k| − R) + …
over the disc B(Q, R) of a piece) stops holding: when the disc holds the point k
(|Q − c_k| < R), ∇d_k is discontinuous there and R/(|Q − c_k| − R) is negative, so the bound
must not be used (the search then takes the Lipschitz constant 2).  The arcs below were chosen so
that some piece's disc holds k with |Q − c_k| just below R (a weakened bound then proves the
arc); the verdict does not depend on the pieces.
"""
from __future__ import annotations

import math

import pytest

from curvedvoronoi.runtime.predicates.circles import Circle, Point
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify.arc_search import prove_arcs
from curvedvoronoi.runtime.voronoi.verify.edges import CircleTable, bisector


@pytest.mark.parametrize("r, yk, y0, y1", [
    (0, 23, -50, 50), (0, 24, -50, 50), (0, 25, -50, 50), (0, 24, -75, 25), (0, 29, -80, 30),
    (0, 43, -55, 45), (5, 28, -70, 30), (5, 48, -50, 50),
])
def test_a_third_point_on_the_arc_is_never_proved_farther(r, yk, y0, y1):
    ij = [Circle(-10, 0, r * r), Circle(10, 0, r * r)] if r else [Point(-10, 0), Point(10, 0)]
    table = CircleTable([site_geometry(s) for s in ij + [Point(0, yk)]])
    bis = bisector(table, 0, 1)
    assert bis.kind == "hyperbola" and bis.a == 0 and bis.b == 10        # the line x = 0, y = 10 sinh u
    assert y0 < yk < y1 and math.hypot(10, yk) - r > 0                    # k on the arc, nearer there
    (ok, detail), = prove_arcs(table, [(bis, math.asinh(y0 / 10), math.asinh(y1 / 10), ())])
    assert not ok
    assert detail[0] == 2


@pytest.mark.parametrize("r, yk, y0, y1", [(0, 24, -50, 50), (5, 28, -70, 30)])
def test_the_same_point_off_the_arc_is_proved_farther(r, yk, y0, y1):
    """The counterpart: k moved to (0, y_1 + 60), beyond the arc's end on the same line.  On the
    arc d_k − d_i = g(y) = (y_k − y) − (√(100 + y²) − r), a linear function minus a convex one:
    concave, so its minimum over [y_0, y_1] is at an end, where it is positive (checked below):
    k is farther on the whole arc and the search must prove it."""
    yk = y1 + 60
    ij = [Circle(-10, 0, r * r), Circle(10, 0, r * r)] if r else [Point(-10, 0), Point(10, 0)]
    table = CircleTable([site_geometry(s) for s in ij + [Point(0, yk)]])
    bis = bisector(table, 0, 1)
    for y in (y0, y1):
        assert (yk - y) - (math.hypot(10, y) - r) > 1
    (ok, detail), = prove_arcs(table, [(bis, math.asinh(y0 / 10), math.asinh(y1 / 10), ())])
    assert ok and detail is None


@pytest.mark.parametrize("y1, proved", [(50, False), (49, False), (48, True), (45, True)])
def test_a_point_nearer_only_near_the_end_of_the_arc(y1, proved):
    """Points i, j = (∓10, 0) (bisector x = 0) and k = (48, 60): on x = 0,
    d_k² − d_i² = 48² + (y − 60)² − (100 + y²) = 5804 − 120 y, so k is nearer exactly for
    y > 5804/120 = 48.36…  On the arc y ∈ [−50, y_1] it is nearer on (48.36…, y_1] when y_1 ≥ 49
    (not an edge: refused, however far k is at the pieces' mid points), and farther on the whole arc
    when y_1 ≤ 48 (d_k² − d_i² ≥ 5804 − 5760 = 44 > 0: proved)."""
    table = CircleTable([site_geometry(s) for s in (Point(-10, 0), Point(10, 0), Point(48, 60))])
    bis = bisector(table, 0, 1)
    assert bis.kind == "hyperbola" and bis.a == 0 and bis.b == 10
    (ok, detail), = prove_arcs(table, [(bis, math.asinh(-5.0), math.asinh(y1 / 10), ())])
    assert ok is proved
    if not proved:
        assert detail[0] == 2 and detail[1][1] > 48


@pytest.mark.parametrize("delta", [0.2, 0.3, 0.5])
def test_a_concentric_circle_nearer_on_an_arc_inside_it_is_found(delta):
    """Nested sites: i the circle of radius 10 about the origin, j the point (99/10, 0) inside it,
    k the circle of radius 19/2 about the origin (inside i, j outside k).  The bisector of i and j
    is the ellipse |q − j| = 10 − |q| (foci 0 and j, semi-axes 5 and √(25 − 4.95²)), whose point of
    parameter π is (−1/20, 0).  Its arc t ∈ [π − δ, π + δ] (δ ≤ 1/2) has x ∈ [−1/20, 0.57] and
    |y| < 0.71, so it lies inside k's circle, where d_k = 19/2 − |q| = d_i − 1/2: k is nearer by
    exactly 1/2 on the whole arc, which is therefore not an edge of (i, j).

    The pieces' discs there hold the common centre of i and k and lie inside both circles, where
    the gradient of d is discontinuous: the slope bound R/(|Q − c| − R) (negative) must not be
    used."""
    from fractions import Fraction

    table = CircleTable([site_geometry(s) for s in (Circle(0, 0, 100), Point(Fraction(99, 10), 0),
                                                    Circle(0, 0, Fraction(361, 4)))])
    bis = bisector(table, 0, 1)
    assert bis.kind == "ellipse" and bis.a == 5
    (ok, detail), = prove_arcs(table, [(bis, math.pi - delta, math.pi + delta, ())])
    assert not ok
    assert detail[0] == 2
