"""The certification stage at the limits it states, against closed forms and exact rationals.

* :func:`runtime.certify.conflicts.certify_vertex` proves "a true Voronoi vertex near (x, y)":
  its module states the tolerance, the proved vertex within 10⁻⁶ of the scene scale
  s = 1 + |x| + |y| + √R of the candidate.  Three unit circles about (0, 0), (4, 0), (0, 4) have
  the single vertex (2, 2) (equidistant from the centres, radius 2√2 − 1, thesis §3.1), so a
  candidate 1.5·10⁻⁶ s away is not near any vertex and must not be certified, while one
  0.5·10⁻⁶ s away is certified with a box holding (2, 2).
* The interval Newton contraction of :mod:`runtime.certify.foot` (Moore, *Interval analysis*,
  1966): on an isolating interval of a simple root where P' still takes the value 0, it bisects
  on the sign of P (P changes sign across a simple root) before Newton's step; the interval
  [−1/2, 3] isolates √2 among the roots ±√2 of x² − 2, where P'(x) = 2x vanishes at 0.
* The float tables of the batched Krawczyk test (:class:`runtime.certify.offset_batch.FloatOffsetSystem`)
  admit a rational coefficient whose double is a normal number of modulus at least 2⁻¹⁰⁰⁰
  (its stated range): 2⁻¹⁰⁰⁰ itself is a double, held exactly, while 2⁻¹⁰⁰¹ is out of that
  range and refused.
"""
from __future__ import annotations

import math
from fractions import Fraction as Q

import pytest
from flint import arb, arb_poly, fmpq

from curvedvoronoi.runtime.certify.conflicts import certify_vertex

CIRCLES = [(Q(1), Q(0), Q(1), Q(-2 * cx), Q(-2 * cy), Q(cx * cx + cy * cy - 1))
           for cx, cy in ((0, 0), (4, 0), (0, 4))]
R_EXACT = (2 * math.sqrt(2) - 1) ** 2            # the squared radius of the vertex (2, 2)
SCALE = 1 + 2 + 2 + (2 * math.sqrt(2) - 1)       # 1 + |x| + |y| + √R at the vertex


@pytest.mark.parametrize("off, near", [(0.5e-6, True), (1.5e-6, False)])
def test_a_vertex_is_certified_only_near_its_candidate(off, near):
    """A candidate off·s to the right of the only vertex (2, 2): certified iff off < 10⁻⁶ (the
    stated tolerance), and when certified its box holds (2, 2)."""
    x = 2 + off * SCALE
    cv = certify_vertex(*CIRCLES, x, 2.0, R_EXACT)
    assert cv.proven is near, cv.note
    if near:
        assert cv.box[0].contains(arb(2)) and cv.box[1].contains(arb(2))
    else:
        assert cv.box is None and "left the candidate" in cv.note


def test_newton_contraction_bisects_an_interval_where_the_derivative_vanishes():
    """x² − 2 on [−1/2, 3]: one root √2 (the other, −√2, is outside), P' = 2x contains 0.  The
    contraction must return a ball holding √2 of radius below 10⁻¹² (Newton from a bisected
    interval [5/4, 3] or tighter; without the bisection the interval stays [−1/2, 3])."""
    from curvedvoronoi.runtime.certify.foot import _newton_contract

    P = arb_poly([arb(-2), arb(0), arb(1)])
    r = arb(fmpq(5, 4), fmpq(7, 4))                    # [−1/2, 3] as mid ± rad
    out = _newton_contract(P, r)
    root = arb(2).sqrt()
    assert out.overlaps(root)
    assert out.lower() <= root.upper() and out.upper() >= root.lower()
    assert float(out.rad()) < 1e-12


@pytest.mark.parametrize("k, admitted", [(1000, True), (1001, False)])
def test_fast_table_admits_coefficients_down_to_two_to_the_minus_1000(k, admitted):
    """o_1 = x² + y² − R + 2⁻ᵏ (o_2, o_3 translates with integer coefficients): with k = 1000
    the table holds 2⁻¹⁰⁰⁰ exactly and the coefficient 2·1 of x in ∂o_1/∂x; with
    k = 1001 it refuses the system (OverflowError, the callers fall back to ball arithmetic)."""
    from curvedvoronoi.runtime.certify.offset_batch import FloatOffsetSystem
    from curvedvoronoi.runtime.certify.offset_system import OffsetSystem

    tiny = Q(1, 2 ** k)
    terms = [[(2, 0, 0, Q(1)), (0, 2, 0, Q(1)), (0, 0, 1, Q(-1)), (0, 0, 0, tiny)],
             [(2, 0, 0, Q(1)), (0, 2, 0, Q(1)), (1, 0, 0, Q(-8)), (0, 0, 1, Q(-1)), (0, 0, 0, Q(16))],
             [(2, 0, 0, Q(1)), (0, 2, 0, Q(1)), (0, 1, 0, Q(-8)), (0, 0, 1, Q(-1)), (0, 0, 0, Q(16))]]
    sys = OffsetSystem(terms=terms)
    if not admitted:
        with pytest.raises(OverflowError):
            FloatOffsetSystem(sys)
        return
    fs = FloatOffsetSystem(sys)
    rows = {tuple(int(t) for t in e): n for n, e in enumerate(fs.exps)}
    c = rows[(0, 0, 0)]
    assert float(fs.C[c, 0]) == 2.0 ** -1000 and Q(float(fs.C[c, 0])) == tiny
    assert float(fs.C[rows[(1, 0, 0)], 3]) == 2.0     # ∂o_1/∂x = 2x
