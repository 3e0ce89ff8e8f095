"""Mixed volumes / mixed cells from a seeded lifting (thesis §3.3.1, §4.4)."""
import itertools
import random
import time
from fractions import Fraction

import flint
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from curvedvoronoi.precompute.mixed import (MixedSubdivision, mixed_cells, mixed_volume, mixed_volume_ie,
                              random_lifting)
from curvedvoronoi.precompute.polytopes import as_points, lattice_points, convex_hull, minkowski_sum, support, vertices


def cyclic(n):
    sups = []
    for k in range(1, n):
        pts = []
        for i in range(n):
            e = [0] * n
            for j in range(k):
                e[(i + j) % n] += 1
            pts.append(e)
        sups.append(pts)
    sups.append([[1] * n, [0] * n])
    return sups


def dense(d, n=2):
    return [e for e in itertools.product(range(d + 1), repeat=n) if sum(e) <= d]


def test_bezout_dense_supports():
    assert mixed_volume([dense(2), dense(3)]) == 6
    assert mixed_volume([dense(1, 3), dense(2, 3), dense(3, 3)]) == 6
    assert mixed_volume([dense(2, 3)] * 3) == 8


def _q(rng):
    return flint.fmpq(rng.randint(-50, 50) or 1, rng.randint(1, 40))


def _offset_equations(kind, rng):
    """f, n, d of §4.4 in (x, y) with random rational u, v, R and conic parameters."""
    ctx = flint.fmpq_mpoly_ctx.get(("x", "y"), "lex")
    x, y = ctx.gens()
    u, v, R = _q(rng), _q(rng), _q(rng)
    if kind == "generic":
        a, b, c, d, e, f0 = (_q(rng) for _ in range(6))
        f = a * x**2 + b * x * y + c * y**2 + d * x + e * y + f0
    elif kind == "ellipse":
        c, e = _q(rng), _q(rng)
        f = x**2 + c * y**2 + e
    else:
        p = _q(rng)
        f = y**2 - 2 * p * x
    fx, fy = f.derivative("x"), f.derivative("y")
    n = -fy * (u - x) + fx * (v - y)
    d = (u - x) ** 2 + (v - y) ** 2 - R
    return f, n, d, f.to_dict().get((2, 0), 0), n.to_dict().get((2, 0), 0)


def test_section_4_4_mixed_volumes():
    rng = random.Random(44)
    # generic conic: MV(f, αn−βf) = 4, MV(αn−βf, f−αd) = 3, MV(f, f−αd) = 4
    f, n, d, alpha, ncoef = _offset_equations("generic", rng)
    n2 = alpha * n - ncoef * f
    d2 = f - alpha * d
    assert (2, 0) not in n2.to_dict() and (2, 0) not in d2.to_dict()
    S = lambda p: support(p)
    assert mixed_volume([S(f), S(n2)]) == 4
    assert mixed_volume([S(n2), S(d2)]) == 3
    assert mixed_volume([S(f), S(d2)]) == 4
    # ellipse/hyperbola x^2 + c y^2 + e: MV(f, n) = 4, MV(n, f−d) = 3, MV(f, f−d) = 4
    f, n, d, _, _ = _offset_equations("ellipse", rng)
    assert [mixed_volume([S(f), S(n)]), mixed_volume([S(n), S(f - d)]), mixed_volume([S(f), S(f - d)])] == [4, 3, 4]
    # parabola y^2 − 2px: MV(f, n) = 3, MV(n, f−d) = 3, MV(f, f−d) = 4
    f, n, d, _, _ = _offset_equations("parabola", rng)
    assert [mixed_volume([S(f), S(n)]), mixed_volume([S(n), S(f - d)]), mixed_volume([S(f), S(f - d)])] == [3, 3, 4]


@pytest.mark.parametrize("n,mv", [(5, 70), (6, 156)])
def test_cyclic(n, mv):
    assert mixed_volume(cyclic(n)) == mv


def test_cyclic5_independent_of_seed_and_cells_are_exact():
    sup = [vertices(as_points(s)) for s in cyclic(5)]
    for seed in range(4):
        lift = random_lifting(sup, seed)
        cells = mixed_cells(sup, lift)
        assert sum(c.volume for c in cells) == 70
        for c in cells:  # exact: (α,1) selects exactly the two edge points on every support
            for a, w, (i, j) in zip(sup, lift, c.edges):
                vals = [sum(Fraction(int(p[k])) * c.normal[k] for k in range(5)) + int(wp)
                        for p, wp in zip(a, w)]
                m = min(vals)
                assert vals[i] == vals[j] == m and sum(v == m for v in vals) == 2


small_sets = st.lists(st.tuples(st.integers(0, 4), st.integers(0, 4), st.integers(0, 4)),
                      min_size=2, max_size=9)


@settings(max_examples=25, deadline=None)
@given(small_sets, small_sets, small_sets, st.integers(0, 1000))
def test_cells_agree_with_inclusion_exclusion(a, b, c, seed):
    sup = [as_points(a), as_points(b), as_points(c)]
    assert mixed_volume(sup, seed=seed) == mixed_volume_ie(sup)


@settings(max_examples=25, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 5), st.integers(0, 5)), min_size=2, max_size=10),
       st.lists(st.tuples(st.integers(0, 5), st.integers(0, 5)), min_size=2, max_size=10),
       st.integers(0, 1000))
def test_full_supports_without_reduction(a, b, seed):
    sup = [as_points(a), as_points(b)]
    cells = mixed_cells(sup, random_lifting(sup, seed))
    assert sum(c.volume for c in cells) == mixed_volume_ie(sup)


def test_subdivision_cells_tile_the_minkowski_sum():
    """Cells located for all points of E: every cell is a sum of simplices with Σ dim = N."""
    sup = [as_points(dense(1)), as_points(dense(2)), as_points([[0, 0], [1, 1], [2, 1], [0, 2]])]
    sub = MixedSubdivision(sup, random_lifting(sup, 3))
    hull = convex_hull(minkowski_sum(*sup))
    delta = (Fraction(1, 101), Fraction(1, 103))
    pts = lattice_points(hull, delta)                       # E = (Q + δ) ∩ Z^2
    owner = sub.locate(pts, tuple(-d for d in delta))       # cells of p − δ ∈ Q
    assert (owner >= 0).all()
    for cell in sub.cells:
        assert sum(len(f) - 1 for f in cell.faces) == 2
    # points in mixed cells of (A1, A2) (translated by a vertex of A0) number MV(A1, A2)
    # (CLO ch. 7, Thm 6.19: the basis of Theorem 3.3.14 restricted to B_0)
    mixed_pts = sum(1 for o in owner if [len(f) for f in sub.cells[o].faces] == [1, 2, 2])
    assert mixed_pts == mixed_volume_ie(sup[1:]) == 6
