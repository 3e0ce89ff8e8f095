"""The two rules of the strip guide (runtime/voronoi/verify/bisector_guide.py) at their boundaries,
on the bisector of two points where every quantity is exact.

Points p_0 = (-1, 0) and p_1 = (1, 0): the bisector is the line x = 0, and on the segment between
them f = d_0 − d_1 = (x + 1) − (1 − x) = 2x, linear, with ∇f = (2, 0) and unit normal U = (1, 0).

* Projection (:func:`project_many`): a point M is moved along the normal of a direction t, by at
  most |t|/2, and the move is kept only when Newton's steps brought |f| down to at most 10⁻³ of
  its start (or below 10⁻¹² of the size).  From M = (−1/2, 0) along n = (1, 0) the bisector is
  1/2 away; with |t| = L < 1 the move stops at L/2, where |f_1| / |f_0| = (1/2 − L/2)/(1/2) =
  1 − L exactly.  L = 1 − 2⁻¹⁰: ratio 2⁻¹⁰ < 10⁻³, the move is kept (offset L/2); L = 1 − 2⁻⁹:
  ratio 2⁻⁹ ≈ 1.95·10⁻³ > 10⁻³, the point is returned where it was, with offset ∞ (the
  projection is not trusted); L = 1: the point lands on the bisector (0, 0).
* Bends (:func:`adapt`): a segment of length L_s whose chord makes the angle α with the
  bisector's tangent at an end is split when L_s·sin α > 4 t, t the wanted half-width at its
  ends (its arc strays up to s·tan α from the chord at distance s from that end).  The chord
  [(−a, 0), (a, 0)] crosses the bisector at a right angle (sin α = 1 at both ends, where U is
  exactly (1, 0)); its midpoint (0, 0) is on the bisector (offset 0).  With tolerance 2⁻¹⁰ the
  wanted half-width is 3·2⁻¹⁰ (the gradient cap 0.03·d·|∇f| ≈ 0.06 is larger), so the boundary is
  2a = 12·2⁻¹⁰: a = 6·2⁻¹⁰ (margin 0) keeps the segment, a = 6·2⁻¹⁰·(1 + 2⁻²⁰) splits it once
  at (0, 0) (its halves have L_s·sin α = a < 4 t), a = 6·2⁻¹⁰·(1 − 2⁻²⁰) keeps it.
"""
from __future__ import annotations

import numpy as np
import pytest

from curvedvoronoi.runtime.predicates.circles import Point
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify.bisector_guide import AdaptJob, ProjectJob, adapt, adapt_many, project_many
from curvedvoronoi.runtime.voronoi.verify.site_table import SiteTable, run_lockstep


@pytest.fixture(scope="module")
def table():
    return SiteTable([site_geometry(Point(-1, 0)), site_geometry(Point(1, 0))], 2.0)


@pytest.mark.parametrize("L, kept", [(1 - 2.0 ** -10, True), (1 - 2.0 ** -11, True), (1 - 2.0 ** -9, False),
                                     (1 - 2.0 ** -8, False)])
def test_a_projection_capped_short_of_the_bisector_is_kept_only_when_f_dropped_a_thousandfold(table, L, kept):
    (Mn, dev), = project_many(table, [ProjectJob([[-0.5, 0.0]], [[0.0, -L]], (0, 1))])
    if kept:
        assert dev[0] == L / 2
        assert Mn[0].tolist() == [-0.5 + L / 2, 0.0]
    else:
        assert dev[0] == np.inf
        assert Mn[0].tolist() == [-0.5, 0.0]


def test_a_projection_that_reaches_the_bisector_lands_on_it(table):
    (Mn, dev), = project_many(table, [ProjectJob([[-0.5, 0.0]], [[0.0, -1.0]], (0, 1))])
    assert dev[0] == 0.5 and Mn[0].tolist() == [0.0, 0.0]


@pytest.mark.parametrize("a, split", [(6 * 2.0 ** -10, False), (6 * 2.0 ** -10 * (1 + 2.0 ** -20), True),
                                      (6 * 2.0 ** -10 * (1 - 2.0 ** -20), False)],
                         ids=["margin 0", "just longer", "just shorter"])
def test_a_chord_across_the_bisector_is_split_only_when_longer_than_four_half_widths(table, a, split):
    S = np.array([[-a, 0.0], [a, 0.0]])
    out, = run_lockstep([adapt(S, (0, 1), 1.0, 2.0 ** -10, 2.0)], table, collective={ProjectJob: project_many, AdaptJob: adapt_many})
    want = [[-a, 0.0], [0.0, 0.0], [a, 0.0]] if split else [[-a, 0.0], [a, 0.0]]
    assert np.asarray(out).tolist() == want
