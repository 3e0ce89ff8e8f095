"""The circle route's tail test (runtime/voronoi/verify/edges.py, ``prove_tail``) next to a nearly
degenerate hyperbola, where its rounding allowance is large.

Circle i = D((0, 0), 10) and the point j = (10 + g, 0) with a gap g = 10⁻⁶ between them: their
bisector is a thin hyperbola branch (b ≈ √(g·D/2)), whose constants are known only to ~(c/b)²·u
relative, so the allowance for rounding is ~10⁻⁵ of the scene.  A third circle k, centre
c_i + L·v⊥ and radius r_i + δ with v = (a·e_x + b·e_y)/c the asymptotic direction of the branch
going to +∞, is farther than i by |q − c_k| − |q − c_i| − δ ≈ L²/(2t) − δ at distance t along
v: closer than i beyond t ≈ L²/(2δ), so that end of the edge (i, j) is not unbounded in the
diagram of i, j, k, however small δ.  The test must refuse it for every δ > 0 (as undecided, a
tie at the asymptote, when δ is below its allowance) and may prove it when δ < 0.  The
expectation is checked in exact rationals at a far point of the branch, from the foci alone."""
import math
from fractions import Fraction

import numpy as np
import pytest

from curvedvoronoi.runtime.voronoi.verify import edges


def far_branch_point(ci, cj, ri, rj, t):
    """A point of the branch |q − c_i| − |q − c_j| = r_i − r_j at distance ~t, towards +e_y
    (q = m + X·e_x + Y·e_y with X = a·√(1 + Y²/b²), from the hyperbola's equation)."""
    D = math.dist(ci, cj)
    ex = ((cj[0] - ci[0]) / D, (cj[1] - ci[1]) / D)
    ey = (-ex[1], ex[0])
    c, a = D / 2, (ri - rj) / 2
    b = math.sqrt(c * c - a * a)
    Y = t * b / c
    X = a * math.sqrt(1 + Y * Y / (b * b))
    m = ((ci[0] + cj[0]) / 2, (ci[1] + cj[1]) / 2)
    return (m[0] + X * ex[0] + Y * ey[0], m[1] + X * ex[1] + Y * ey[1]), (a * ex[0] + b * ey[0]) / c, \
        (a * ex[1] + b * ey[1]) / c


def closer_far_out(ci, ck, ri, rk, q):
    """d_k(q) − d_i(q) < 0, decided with 60-digit square roots (mpmath)."""
    import mpmath
    mpmath.mp.dps = 60
    Q = [mpmath.mpf(Fraction(v).numerator) / Fraction(v).denominator for v in q]
    di = mpmath.sqrt((Q[0] - ci[0]) ** 2 + (Q[1] - ci[1]) ** 2) - ri
    dk = mpmath.sqrt((Q[0] - ck[0]) ** 2 + (Q[1] - ck[1]) ** 2) - rk
    return dk - di < 0


@pytest.mark.parametrize("rj", [0.0, 0.25])
@pytest.mark.parametrize("delta", [1e-3, 1e-5, 1e-7, -1e-3])
def test_a_third_circle_nearer_at_the_asymptote_is_never_proved_farther(delta, rj):
    """rj = 0: the thin hyperbola of the module docstring; rj = 0.25: a wide one (c/b ≈ 3), where the
    test finds a far point where k is nearer and names it."""
    gap, L = 1e-6, 40.0
    ci, ri = (0.0, 0.0), 10.0
    cj = (ri + rj + gap, 0.0)
    _, vx, vy = far_branch_point(ci, cj, ri, rj, 1.0)
    ck = (ci[0] - L * vy, ci[1] + L * vx)
    rk = ri + delta
    table = edges.CircleTable.from_arrays([ci, cj, ck], [ri, rj, rk])
    bis = edges.bisector(table, 0, 1)
    assert not isinstance(bis, str) and bis.kind == "hyperbola"
    # the branch to σ = +∞ is u → +∞ of m + a·cosh(u)·e_x + b·sinh(u)·e_y: the asymptotic direction
    # v = (a·e_x + b·e_y)/c when the frame is e_x from c_i to c_j and e_y = e_x turned by +90°
    assert np.allclose(bis.ex, (1.0, 0.0)) and np.allclose(bis.ey, (-bis.ex[1], bis.ex[0]))
    t_far = 1e3 * L * L / abs(delta)
    q, _, _ = far_branch_point(ci, cj, ri, rj, t_far)
    k_closer = closer_far_out(ci, ck, ri, rk, q)
    assert k_closer == (delta > 0)
    ok, detail = edges.prove_tail(table, bis, 5.0, 1)
    if k_closer:
        assert not ok, "a tail proved although the third circle is nearer far out"
        assert detail[0] == 2
        if rj > 0:
            assert detail[2] == "closer"
    elif delta < -1e-4:
        assert ok, detail
