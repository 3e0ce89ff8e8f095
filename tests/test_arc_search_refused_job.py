"""A job refused by the disc search (runtime.voronoi.verify.arc_search.prove_arcs) stops being
searched: its pieces are not undecided pieces, so they do not draw on the budget ``max_pieces``
that the jobs of one call share, and a true arc searched beside a wrong one is proved as it is
alone.

Circles of radius 5 centred at (±10, 0) have the line x = 0 as bisector, y = 10·sinh u, and
d_i = √(100 + y²) − 5 on it.  A point site at (0, 3) is nearer than the circles exactly where
|y − 3| < √(100 + y²) − 5; for y ≥ 3 that is (y + 2)² < 100 + y², i.e. y < 24.  So the arc
y ∈ [−3, 1000] is not an edge (the point is nearer at y = 0: 3 < 5), and on y ∈ [24.5, 1000] the
point is farther everywhere (d_k − d_i = (4y − 96)/(y + 2 + √(100 + y²)) > 0), with a
margin of only 0.04 at y = 24.5, so that arc needs a few halvings near its start."""
from __future__ import annotations

import math

import pytest

from curvedvoronoi.runtime.predicates.circles import Circle, Point
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify.arc_search import prove_arcs
from curvedvoronoi.runtime.voronoi.verify.edges import CircleTable, bisector

BUDGET = 128


@pytest.fixture(scope="module")
def table():
    return CircleTable([site_geometry(s) for s in (Circle(-10, 0, 25), Circle(10, 0, 25), Point(0, 3))])


def _job(table, y0, y1):
    bis = bisector(table, 0, 1)
    assert bis.kind == "hyperbola" and bis.a == 0 and bis.b == 10     # the line x = 0
    return (bis, math.asinh(y0 / 10), math.asinh(y1 / 10), ())


def test_the_true_arc_is_proved_alone_within_the_budget(table):
    assert prove_arcs(table, [_job(table, 24.5, 1000.0)], max_pieces=BUDGET) == [(True, None)]


@pytest.mark.parametrize("wrong_first", [True, False])
def test_a_refused_arc_does_not_use_up_the_budget_of_a_true_one(table, wrong_first):
    wrong, true = _job(table, -3.0, 1000.0), _job(table, 24.5, 1000.0)
    jobs = [wrong, true] if wrong_first else [true, wrong]
    res = prove_arcs(table, jobs, max_pieces=BUDGET)
    r_wrong, r_true = res if wrong_first else res[::-1]
    ok, (k, q, why) = r_wrong
    assert not ok and k == 2 and why == "closer"
    assert -2.25 < q[1] < 24 and math.hypot(q[0], q[1] - 3) < math.hypot(10, q[1]) - 5
    assert r_true == (True, None)
