"""The disc search over long bisector arcs (runtime/voronoi/verify/arc_search.py), against distances
computed directly.

Circles of radius 5 centred at (±10, 0) have the line x = 0 as bisector, y = 10·sinh u, and
d_i = √(100 + y²) − 5 on it.  A point site at (0, 3) is nearer exactly for y ∈ (−9/4, 24)
(|y − 3| < √(100 + y²) − 5), a bounded stretch in the middle of the arc y ∈ [−3, 1000]: the
search halves that arc's long pieces before it lists their candidate sites, and a search that
dropped any part of the arc could miss the stretch.  A point at (0, −30) is farther on the whole
arc (y + 30 > |y| + 5 ≥ d_i)."""
from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest

from curvedvoronoi.runtime.predicates.circles import Circle, Point
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify import arc_search
from curvedvoronoi.runtime.voronoi.verify.arc_search import prove_arcs
from curvedvoronoi.runtime.voronoi.verify.edges import CircleTable, bisector


def _table(py):
    sites = [Circle(-10, 0, 25), Circle(10, 0, 25), Point(0, Fraction(py))]
    return CircleTable([site_geometry(s) for s in sites])


def _d_circle(y):
    return math.hypot(10.0, y) - 5.0


def _job(table, y0, y1=1000.0):
    bis = bisector(table, 0, 1)
    assert bis.kind == "hyperbola" and bis.a == 0 and bis.b == 10     # the line x = 0
    return (bis, math.asinh(y0 / 10), math.asinh(y1 / 10), ())


def test_a_nearer_point_in_the_middle_of_a_long_arc_is_found():
    table = _table(3)
    ok, (k, q, why) = prove_arcs(table, [_job(table, -3.0)])[0]
    assert not ok and k == 2 and why == "closer"
    # the reported point is on the line, in the stretch where the point site is nearer
    assert abs(q[0]) < 1e-9 and -2.25 < q[1] < 24
    assert math.hypot(q[0], q[1] - 3) < _d_circle(q[1])


def test_the_arc_is_proved_when_the_point_is_farther_everywhere():
    table = _table(-30)
    assert prove_arcs(table, [_job(table, -3.0)]) == [(True, None)]


@pytest.mark.parametrize("pairs, batch", [(3, 7), (50, 2), (1 << 16, 4096)])
def test_verdicts_match_direct_distances_whatever_the_groups(monkeypatch, pairs, batch):
    """Arcs y ∈ [y0, 1000]: not proved exactly when y0 < 24 (direct distances on a fine grid
    agree), however the jobs and the (piece, candidate) pairs are grouped."""
    table = _table(3)
    starts = [-3.0, -1.0, 0.0, 5.0, 10.0, 20.0, 23.0, 25.0, 30.0, 40.0, 100.0, 500.0]
    ys = [np.linspace(y0, 1000.0, 200001) for y0 in starts]
    direct = [bool(np.all(np.abs(y - 3) > np.hypot(10.0, y) - 5.0)) for y in ys]
    assert direct == [y0 >= 24 for y0 in starts]
    monkeypatch.setattr(arc_search, "PAIRS", pairs)
    monkeypatch.setattr(arc_search, "BATCH", batch)
    res = prove_arcs(table, [_job(table, y0) for y0 in starts])
    assert [ok for ok, _ in res] == direct
    assert all(det[2] == "closer" and det[0] == 2 for ok, det in res if not ok)



@pytest.mark.parametrize("margin", [1e-3, 1e-6])
def test_a_point_nearer_on_a_short_stretch_only_is_found(margin):
    """A point site at (5 − margin, 0), off the line x = 0 next to d_i's minimum d_i(0) = 5:
    |q − p| < d_i(q) only for |y| below about √(20·margin) (to second order; checked on a fine
    grid), so the arc y ∈ [−3, 1000] is not an edge; a disc that does not cover its piece of the
    arc can miss that stretch."""
    x0 = 5.0 - margin
    sites = [Circle(-10, 0, 25), Circle(10, 0, 25), Point(Fraction(x0), 0)]
    table = CircleTable([site_geometry(s) for s in sites])
    y = np.linspace(-3.0, 3.0, 2_000_001)
    nearer = np.hypot(x0, y) < np.hypot(10.0, y) - 5.0
    assert nearer.any() and np.abs(y[nearer]).max() < 1.1 * math.sqrt(20 * margin)
    ok, (k, q, why) = prove_arcs(table, [_job(table, -3.0)])[0]
    assert not ok and k == 2 and why == "closer"


def test_every_piece_lies_in_its_disc():
    """The discs of the search cover their pieces of the arc: on the line x = 0, y = 10·sinh u (the
    test's own parametrisation), every point of a piece u ∈ [A, B] is within the disc's radius of
    its centre, and the radius is not above the larger distance from the middle parameter's point
    to the piece's ends plus rounding (a disc around that point)."""
    table = _table(-30)
    jobs = [_job(table, y0) for y0 in (-3.0, 0.0, 20.0)]
    curves = arc_search._Curves(table, jobs)
    job, A, B = curves.pieces(4)
    _, Q, Rarc, _, R = curves.discs(job, A, B)
    for q, ra, r, a, b in zip(Q, Rarc, R, A, B):
        u = np.linspace(a, b, 2001)
        P = np.column_stack([np.zeros_like(u), 10 * np.sinh(u)])
        far = np.hypot(*(P - q).T).max()
        assert far <= ra <= r
        m = 0.5 * (a + b)
        assert ra <= 10 * max(math.sinh(m) - math.sinh(a), math.sinh(b) - math.sinh(m)) * (1 + 1e-9) + 1e-9
