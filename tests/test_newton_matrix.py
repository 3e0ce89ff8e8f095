"""Canny–Emiris Newton matrices (thesis §3.3.1, Thms 3.3.13–3.3.15; App. B.2)."""
import itertools
import random
from fractions import Fraction

import flint
import numpy as np
import pytest

from curvedvoronoi.precompute.conics import FAMILIES
from curvedvoronoi.precompute.mixed import mixed_volume
from curvedvoronoi.precompute.newton_matrix import newton_matrix
from curvedvoronoi.precompute.offsets import offset_point

PRIME = 4294967291  # < 2^32


def dense(d, n=2):
    return [e for e in itertools.product(range(d + 1), repeat=n) if sum(e) <= d]


SMALL = {
    "2d": [dense(1), dense(2), [(0, 0), (1, 1), (2, 1), (0, 2)]],
    "3d": [dense(1, 3), dense(2, 3), [(0, 0, 0), (1, 1, 0), (0, 1, 2), (2, 0, 1), (1, 0, 0)],
           [(0, 0, 0), (0, 0, 1), (1, 2, 0), (0, 1, 1)]],
}


def _coeffs(mat, rng):
    return [[rng.randrange(1, PRIME) for _ in s] for s in mat.supports]


def _structure_ok(mat):
    n = mat.size
    assert mat.rows.min() >= 0 and mat.rows.max() < n and mat.cols.max() < n
    # each row is x^(p−a)·f_i: exactly |A_i| nonzeros, in the columns p − a + A_i
    counts = np.bincount(mat.rows, minlength=n)
    assert (counts == np.array([len(mat.supports[i]) for i in mat.row_poly])).all()
    shifts = mat.row_monomials
    for k in range(0, mat.nnz, max(1, mat.nnz // 500)):
        r, c, i, j = mat.rows[k], mat.cols[k], mat.poly[k], mat.term[k]
        assert (shifts[r] + mat.supports[i][j] == mat.points[c]).all()
    # the row of p contains its own column (a ∈ A_i, p − a + a = p)
    assert len(set(zip(mat.rows.tolist(), mat.cols.tolist()))) == mat.nnz


@pytest.mark.parametrize("name", sorted(SMALL))
def test_small_systems(name):
    sup = SMALL[name]
    mat = newton_matrix(sup)
    _structure_ok(mat)
    assert mat.n00 == mixed_volume(sup[1:])          # M00 has MV(f1..fN) rows (Thm 3.3.15)
    assert (mat.row_poly[: mat.n00] == 0).all() and (mat.row_poly[mat.n00:] != 0).all()
    rng = random.Random(7)
    for _ in range(3):                               # generic coefficients: nonsingular
        assert mat.fill_nmod(_coeffs(mat, rng), PRIME).rank() == mat.size
    # a common root in the torus: the determinant vanishes
    n = mat.points.shape[1]
    xi = [rng.randrange(2, PRIME) for _ in range(n)]
    co = _coeffs(mat, rng)
    for i, a in enumerate(mat.supports):
        mons = [int(np.prod([pow(xi[k], int(e[k]), PRIME) for k in range(n)], dtype=object) % PRIME) for e in a]
        s = sum(c * m for c, m in zip(co[i][1:], mons[1:])) % PRIME
        co[i][0] = (-s * pow(mons[0], PRIME - 2, PRIME)) % PRIME
    assert mat.fill_nmod(co, PRIME).rank() < mat.size


def test_small_exact_determinant():
    sup = SMALL["2d"]
    mat = newton_matrix(sup)
    rng = random.Random(3)
    co = [[Fraction(rng.randint(-9, 9) or 1, rng.randint(1, 5)) for _ in s] for s in mat.supports]
    dense_ = mat.fill(co)
    det = flint.fmpq_mat([[flint.fmpq(x.numerator, x.denominator) if isinstance(x, Fraction) else x
                           for x in row] for row in dense_]).det()
    assert det != 0


def test_deterministic():
    a = newton_matrix(SMALL["3d"], lifting_seed=5)
    b = newton_matrix(SMALL["3d"], lifting_seed=5)
    for k in ("points", "rows", "cols", "poly", "term", "row_poly", "row_term"):
        assert np.array_equal(getattr(a, k), getattr(b, k))


def _generic_conic_system(params, u, v, R):
    """App. B.1/B.2: f, αn − βf, f − αd in (x, y) for the generic conic (α, β = x², xy coeffs)."""
    ctx = flint.fmpq_mpoly_ctx.get(("x", "y"), "lex")
    x, y = ctx.gens()
    q = lambda t: flint.fmpq(Fraction(t).numerator, Fraction(t).denominator)
    a, b, c, d, e, f0 = (q(params[k]) for k in "abcdef")
    u, v, R = q(u), q(v), q(R)
    f = a * x**2 + b * x * y + c * y**2 + d * x + e * y + f0
    n = -(b * x + 2 * c * y + e) * (u - x) + (2 * a * x + b * y + d) * (v - y)
    dd = (u - x) ** 2 + (v - y) ** 2 - R
    return [f, a * n - b * f, f - a * dd]


def test_generic_conic_offset_divides_determinant():
    """The offset (App. B.2) is a factor of det M: det vanishes on offset points, not elsewhere."""
    fam = FAMILIES["generic"]
    rng = random.Random(2003)
    gen = _generic_conic_system({k: Fraction(rng.randint(1, 30), 7) for k in "abcdef"},
                                Fraction(3, 5), Fraction(-2, 7), Fraction(9, 4))
    mat = newton_matrix(gen)
    assert mat.n00 == 3                      # MV(αn − βf, f − αd) = 3 (§4.4)
    assert mat.size == 14                    # the thesis (Emiris' Resin) got 13 × 13

    def det_at(polys):
        co = [[p.to_dict().get(tuple(int(t) for t in m), 0) for m in s] for p, s in zip(polys, mat.supports)]
        return flint.fmpq_mat(mat.fill(co)).det()

    hits = 0
    for _ in range(6):
        params, point = fam.sample(rng)
        k = Fraction(rng.randint(1, 9), rng.randint(1, 9))
        u, v, R = offset_point(fam, params, point, k)
        assert det_at(_generic_conic_system(params, u, v, R)) == 0
        # a generic (u, v, R) is not on the offset: det ≠ 0
        assert det_at(_generic_conic_system(params, u + Fraction(1, 3), v, R)) != 0
        hits += 1
    assert hits == 6
