"""The float cells of the verifier's walks over directions are covered by their balls, exactly
(runtime/certify/cell_cover.py): checked in rational arithmetic on hand-built cells one to a few
ulps wide (where the rounding of the centre matters) and on random cells (hypothesis)."""
from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
from hypothesis import given, settings, strategies as st

from curvedvoronoi.runtime.certify.cell_cover import CellTest, CoverOutcome, cell_balls, halve, walk_cells


def _covers(a, b, c, half) -> bool:
    A, B, C, H = (Fraction(float(v)) for v in (a, b, c, half))
    return C - H <= A and B <= C + H


def test_three_ulp_cell_is_covered_where_the_naive_ball_is_not():
    a, b = 1.0, 1.0 + 3 * 2.0 ** -52
    naive_c, naive_half = 0.5 * (a + b), 0.5 * (b - a) * (1 + 1e-12)
    # the naive centre rounds to 1 + 2·2⁻⁵² (ties to even), the exact midpoint is 1 + 1.5·2⁻⁵²
    assert Fraction(naive_c) == 1 + Fraction(2, 2 ** 52)
    assert not _covers(a, b, naive_c, naive_half)
    c, half = cell_balls(a, b)
    assert _covers(a, b, c, half)


def test_a_cell_across_zero_whose_half_width_rounds_down_is_covered():
    """[−10⁻²⁰, 2]: c = 1 and c − a = 1 + 10⁻²⁰ rounds to 1, so max(c − a, b − c) = 1 misses a;
    the next double above it does not."""
    a, b = -1e-20, 2.0
    c = 0.5 * (a + b)
    assert not _covers(a, b, c, max(c - a, b - c))
    assert _covers(a, b, *cell_balls(a, b))


def test_cells_near_atan2_tie_and_subnormal_and_huge():
    t = math.atan2(4, 3)
    cells = [(t, math.nextafter(t, 4)), (t, t + 5 * 2.0 ** -52), (t - 1e-13, t), (0.0, 5e-324),
             (-3 * 5e-324, 7 * 5e-324), (1e300, 1e300 * (1 + 7 * 2.0 ** -52)), (-2.0, 2.0), (t, t)]
    a = np.array([x for x, _ in cells])
    b = np.array([y for _, y in cells])
    c, half = cell_balls(a, b)
    assert all(_covers(*row) for row in zip(a, b, c, half))


@settings(max_examples=400, deadline=None)
@given(st.floats(-1e6, 1e6, allow_nan=False, allow_infinity=False), st.integers(0, 2 ** 20))
def test_random_cells_are_covered(x, k):
    y = x
    for _ in range(k % 40):
        y = math.nextafter(y, math.inf)
    y += k * 1e-9 * (k > 2 ** 19)
    c, half = cell_balls(x, y)
    assert _covers(x, y, c, half)


def test_halving_keeps_the_union_and_the_carried_data():
    a = np.array([0.0, 1.0, 2.0])
    b = np.array([1.0, 1.0 + 3 * 2.0 ** -52, 3.0])
    K = np.array([5, 6, 7])
    a2, b2, K2 = halve(a, b, np.array([False, True, True]), K)
    assert sorted(K2.tolist()) == [6, 6, 7, 7]
    for k, (lo, hi) in ((6, (a[1], b[1])), (7, (a[2], b[2]))):
        parts = sorted((Fraction(float(x)), Fraction(float(y))) for x, y, kk in zip(a2, b2, K2) if kk == k)
        assert parts[0][0] == Fraction(lo) and parts[-1][1] == Fraction(hi) and parts[0][1] == parts[1][0]
        assert Fraction(lo) <= parts[0][1] <= Fraction(hi)


# ---------------------------------------------------------------------------- the shared walk

def _cos_positive(c, half, *carry):
    """cos θ > 0 on the ball [c − half, c + half]: cos c − half > 0 (|cos'| ≤ 1, the rounding of
    cos c far below the margins used here); refuted where cos c < −10⁻¹² (θ beyond ±π/2).
    ``carry``: per-cell data the test does not read."""
    cc = np.cos(c)
    return CellTest(fault=cc < -1e-12, undecided=~(cc - half * (1 + 1e-9) > 1e-12))


def test_walk_proves_cos_positive_inside_the_right_half_plane():
    a = np.linspace(-1.5, 1.5, 5)
    out = walk_cells(a[:-1], a[1:], _cos_positive, 10 ** 5)
    assert out.proved and out.exit == "decided" and out.cell is None


def test_walk_reports_a_cell_past_the_zero_of_cos_as_fault():
    out = walk_cells(np.array([0.0]), np.array([2.0]), _cos_positive, 10 ** 5)
    assert not out.proved and out.exit == "fault"
    lo, hi = out.cell
    # the reported cell holds a direction where cos < 0: it reaches beyond π/2
    assert 0.0 <= lo < hi <= 2.0 and hi > math.pi / 2


def test_walk_stops_at_the_smallest_cell_when_the_statement_touches_its_bound():
    """cos θ > 0 on [0, π/2] fails only at the end point π/2 (cos π/2 ≈ 6·10⁻¹⁷, no fault): the
    walk halves towards it and gives up there; the carried row follows its cell."""
    tag = np.array([7])
    out = walk_cells(np.array([0.0]), np.array([math.pi / 2]), _cos_positive, 10 ** 6, carry=(tag,),
                     smallest=1e-9)
    assert out.exit == "undecided" and not out.proved
    lo, hi, row = out.cell
    assert row == 7 and hi == math.pi / 2 and hi - lo < 4e-9


def test_walk_budget_counts_every_tested_cell():
    a = np.linspace(-1.5, 1.5, 5)
    # four cells, then their halves: a budget of 3 stops before the first round
    assert walk_cells(a[:-1], a[1:], _cos_positive, 3).exit == "budget"
    # without a smallest cell an undecidable statement ends on the budget, never "proved"
    out = walk_cells(np.array([0.0]), np.array([math.pi / 2]), _cos_positive, 2000)
    assert out == CoverOutcome(False, "budget")
