"""Completeness of the disc search of runtime/voronoi/verify/arc_search.py at its stated resolution.

The module's docstring (and runtime/voronoi/verify/edges.py, item 1) gives the test of a piece of
the bisector arc: the piece lies in the disc of centre q(u_m) and radius R (the larger arc length
from q(u_m) to an end: c·|Δ sinh u| on a hyperbola, at most max(A, B)·(half the parameter width)
on an ellipse, plus a rounding bound), and every distance function is 1-Lipschitz, so a third site k
is farther than i on the piece as soon as d_k(q_m) − d_i(q_m) > 2R (plus the few-ulp slacks).
Before the candidates are listed, a piece whose disc radius exceeds half the distance from its
mid point to the edge's sites is halved (``_Curves.pieces``).  Each arc below is a true Voronoi edge
piece (k farther than i on the whole arc, shown in closed form), and the search is given exactly
the resolution at which that Lipschitz test decides it, no more: it must prove the arc.
"""
from __future__ import annotations

import math
from fractions import Fraction

from curvedvoronoi.runtime.predicates.circles import Circle, Point
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify.arc_search import prove_arcs
from curvedvoronoi.runtime.voronoi.verify.edges import CircleTable, bisector


def _line_table(xk):
    """Points i, j = (∓10, 0) (bisector x = 0, y = 10 sinh u) and a third point k = (xk, 0)."""
    table = CircleTable([site_geometry(s) for s in (Point(-10, 0), Point(10, 0), Point(xk, 0))])
    bis = bisector(table, 0, 1)
    assert bis.kind == "hyperbola" and bis.a == 0 and bis.b == 10 and bis.c == 10
    return table, bis


def test_a_long_arc_is_halved_near_the_sites_before_it_is_searched():
    """k = (38, 0), arc y ∈ [−15, 15] of x = 0, given as ONE piece with no halving in the search
    (max_depth = 0).  On x = 0, d_k² − d_i² = 38² − 10² = 1344 > 0: k is farther on the whole
    line.  Moreover d_k ≥ 2.2 d_i on the arc (d_k² − 4.84 d_i² = 960 − 3.84 y² ≥ 96 for |y| ≤ 15).
    The pieces left by the halving before the search have R ≤ d_i(q_m)/2, so
    d_k − d_i − 2R ≥ 0.2 d_i(q_m) ≥ 2 at every mid point: proved at depth 0.  Unhalved, the one
    piece (R = 15 about (0, 0)) cannot decide k: 38 − 10 < 2·15."""
    table, bis = _line_table(38)
    for y in (0, 7.5, 15):
        assert 38 ** 2 + y * y - 2.2 ** 2 * (100 + y * y) > 0
    (ok, detail), = prove_arcs(table, [(bis, math.asinh(-1.5), math.asinh(1.5), ())], init=1, max_depth=0)
    assert ok and detail is None


def test_one_undecided_piece_within_a_budget_of_one_is_halved_not_given_up():
    """k = (19, 0), arc y ∈ [−4.9, 4.9] of x = 0, one piece, ``max_pieces`` = 1 (the undecided
    pieces allowed before the search gives up).  k is farther on the whole line
    (d_k² − d_i² = 361 − 100 > 0).  The piece about (0, 0) has R = 4.9 < d_i/2 = 5 (not halved
    before the search) and does not decide k (19 − 10 < 2·4.9, and the two gradients (∓1, 0)
    there are opposite: slope bound 2); that is ONE undecided piece, within the budget, so it is
    halved.  Each half has mid point (0, ±y_m) with y_m = 10 sinh(asinh(0.49)/2) ∈ (2.38, 2.39)
    and R = max(y_m, 4.9 − y_m) < 2.52, and d_k − d_i ≥ √(361 + 2.38²) − √(100 + 2.39²) > 8.8 > 2·2.52
    there: proved at depth 1."""
    table, bis = _line_table(19)
    ym = 10 * math.sinh(math.asinh(0.49) / 2)
    assert 2.38 < ym < 2.39 and 19 - 10 < 2 * 4.9 and math.hypot(19, 2.38) - math.hypot(10, 2.39) > 8.8 > 2 * 2.52
    job = (bis, math.asinh(-0.49), math.asinh(0.49), ())
    (ok, detail), = prove_arcs(table, [job], init=1, max_depth=1, max_pieces=1)
    assert ok and detail is None
    # the same piece with no halving allowed is undecided (the budget above was needed)
    (ok0, detail0), = prove_arcs(table, [job], init=1, max_depth=0)
    assert not ok0 and detail0[0] == 2 and detail0[2] == "undecided"


def test_an_ellipse_arc_is_decided_by_its_disc_of_radius_max_axis_times_half_width():
    """Nested sites: i the circle of radius 10 about the origin, j the point (6, 0) inside it,
    k the point (15/2, 0) inside it.  The bisector of i and j is the ellipse |q| + |q − j| = 10
    (centre (3, 0), A = 5, B = 4); its point of parameter π is (−2, 0).  On the arc
    t ∈ [π − 1/10, π + 1/10] (x ∈ [−2, −1.97], |y| < 0.4): d_i = 10 − |q| ≤ 8 and
    d_k = |q − k| ≥ 9.47, so k is farther by more than 1.47.  The arc lies in the disc of
    radius max(A, B)·(1/10) = 1/2 about (−2, 0), where d_k − d_i = 9.5 − 8 = 1.5 > 2·(1/2): one
    piece (init = 1) decides it at depth 0.  (A disc of radius 1, twice the arc's bound, would not:
    1.5 < 2·1, with opposite gradients (±1, 0) of d_i and d_k at (−2, 0).)"""
    table = CircleTable([site_geometry(s) for s in (Circle(0, 0, 100), Point(6, 0), Point(Fraction(15, 2), 0))])
    bis = bisector(table, 0, 1)
    assert bis.kind == "ellipse" and (bis.a, bis.b, bis.c) == (5, 4, 3)
    for t in (math.pi - 0.1, math.pi, math.pi + 0.1):
        x, y = 3 + 5 * math.cos(t), 4 * math.sin(t)
        assert math.hypot(x - 7.5, y) - (10 - math.hypot(x, y)) > 1.47
    (ok, detail), = prove_arcs(table, [(bis, math.pi - 0.1, math.pi + 0.1, ())], init=1, max_depth=0)
    assert ok and detail is None
