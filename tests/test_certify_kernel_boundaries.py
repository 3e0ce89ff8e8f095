"""The proof kernel of the certification stage against exact rational arithmetic.

* The foot-point system of :mod:`runtime.certify.krawczyk` (thesis §6.1, App. D.1): with
  z = (x, y, x1, y1, x2, y2, x3, y3) and conics f_i = a x² + b xy + c y² + d x + e y + f,

      f_i(p_i) = 0,   (x − x_i) ∂_y f_i(p_i) − (y − y_i) ∂_x f_i(p_i) = 0      (i = 1, 2, 3)
      |q − p_1|² − |q − p_2|² = 0,   |q − p_1|² − |q − p_3|² = 0.

  Every equation is a polynomial of degree ≤ 2 in z, so the central difference
  (F(z + h e_j) − F(z − h e_j)) / 2h is EXACTLY ∂F/∂z_j at z for any h ≠ 0: the balls of
  ``residual`` and ``jacobian`` at a rational point must contain the values computed here in
  Fractions from the equations above.
* Krawczyk's test on balls (:func:`runtime.certify.interval_newton.krawczyk_inflation`) and on
  float batches (:func:`float_krawczyk_test`): a simple zero is proved inside the returned box,
  and boxes holding two zeros or none are refused, at the boundary of the contraction (a box
  whose radius is exactly the distance to the second zero).
"""
from __future__ import annotations

from fractions import Fraction as Q

import numpy as np
import pytest
from flint import arb

CONICS = [
    (Q(1), Q(0), Q(4), Q(-2), Q(0), Q(-3)),          # (x − 1)² + 4y² = 4
    (Q(2), Q(1), Q(3), Q(0), Q(-5), Q(1, 2)),        # a rotated ellipse
    (Q(1), Q(0), Q(-1), Q(0), Q(0), Q(-7)),          # a hyperbola x² − y² = 7
]
Z = [Q(3, 7), Q(-5, 3), Q(2), Q(1, 9), Q(-4, 5), Q(11, 4), Q(6), Q(-1, 8)]


def _exact_residual(z):
    x, y = z[0], z[1]
    out, sq = [], []
    for i, (a, b, c, d, e, f) in enumerate(CONICS):
        xi, yi = z[2 + 2 * i], z[3 + 2 * i]
        fx, fy = 2 * a * xi + b * yi + d, b * xi + 2 * c * yi + e
        out.append(a * xi * xi + b * xi * yi + c * yi * yi + d * xi + e * yi + f)
        out.append((x - xi) * fy - (y - yi) * fx)
        sq.append((x - xi) ** 2 + (y - yi) ** 2)
    return out + [sq[0] - sq[1], sq[0] - sq[2]]


def _contains(ball: arb, q: Q) -> bool:
    """q ∈ ball, with q as a ball of radius ~2^-400 (so only q's own position matters)."""
    import flint

    old = flint.ctx.prec
    flint.ctx.prec = 400
    try:
        qb = arb(q.numerator) / q.denominator
    finally:
        flint.ctx.prec = old
    return bool(ball.contains(qb))


def test_foot_system_residual_is_the_system():
    from curvedvoronoi.runtime.certify.krawczyk import FootSystem

    S = FootSystem(CONICS)
    got = S.residual([arb(v.numerator) / v.denominator for v in Z])
    want = _exact_residual(Z)
    assert len(got) == 8
    for g, w in zip(got, want):
        assert _contains(g, w), (g, w)


def test_foot_system_jacobian_is_the_exact_derivative():
    """Central differences of a degree-2 polynomial are its derivative exactly (module docstring)."""
    from curvedvoronoi.runtime.certify.krawczyk import FootSystem

    S = FootSystem(CONICS)
    J = S.jacobian([arb(v.numerator) / v.denominator for v in Z])
    h = Q(1, 3)
    for j in range(8):
        zp, zm = list(Z), list(Z)
        zp[j] += h
        zm[j] -= h
        col = [(p - m) / (2 * h) for p, m in zip(_exact_residual(zp), _exact_residual(zm))]
        for i in range(8):
            assert _contains(J[i, j], col[i]), (i, j, J[i, j], col[i])


def test_foot_system_krawczyk_encloses_the_exact_foot_vertex():
    """Three unit circles centred at (0, 0), (4, 0), (0, 4) as conics: the vertex is (2, 2)
    (equidistant from the three centres, radius 2√2 − 1), the feet are the centres moved by 1
    towards it.  The proved box (at 53 bits) must contain the exact vertex (2, 2) and the feet, e.g.
    p_1 = (1/√2, 1/√2), from a start 1e-3 off."""
    from curvedvoronoi.runtime.certify.krawczyk import FootSystem

    circ = [(Q(1), Q(0), Q(1), Q(-2 * cx), Q(-2 * cy), Q(cx * cx + cy * cy - 1)) for cx, cy in ((0, 0), (4, 0), (0, 4))]
    S = FootSystem(circ)
    s = 2 ** -0.5
    start = [2.001, 1.999, s, s, 4 - s, s, s, 4 - s]
    m = S.newton([arb(v) for v in start], 100)
    box = S.krawczyk(m)
    assert box[0].contains(arb(2)) and box[1].contains(arb(2))
    r = arb(2).sqrt() / 2
    for v, w in zip(box[2:], [r, r, 4 - r, r, r, 4 - r]):
        assert v.overlaps(w)
    assert all(float(b.rad()) < 1e-9 for b in box)          # a proof, not a vague box


# ----------------------------------------------------------------------------- balls

@pytest.mark.parametrize("c, proved", [(Q(1, 10 ** 6), True), (Q(0), False), (Q(-1, 10 ** 6), False)])
def test_krawczyk_inflation_near_a_double_zero(c, proved):
    """F(x) = x² − c with the candidate m = √c (or 0): for c > 0 the zeros ±√c are simple and
    2√c apart, and the box around √c must hold exactly one (√(1e-6) = 1e-3, provable); c = 0 is a
    double zero (F' = 0 there: no contraction), c < 0 no real zero: both refused."""
    from curvedvoronoi.runtime.certify.interval_newton import KrawczykFailure, krawczyk_inflation

    m0 = arb(c.numerator) / c.denominator
    m = [m0.sqrt() if c > 0 else arb(0)]

    def F(z):
        return [z[0] * z[0] - m0]

    def J(z):
        return [[2 * z[0]]]
    if proved:
        K, X = krawczyk_inflation(F, J, m)
        assert K[0].contains(m0.sqrt())
        assert not X[0].contains(-m0.sqrt())      # the box of uniqueness excludes the other zero
    else:
        with pytest.raises(KrawczykFailure):
            krawczyk_inflation(F, J, m)


# ----------------------------------------------------------------------------- float batches

@pytest.mark.parametrize("r, proved", [(0.5, True), (0.999, True), (2.0, False), (3.0, False)])
def test_float_krawczyk_proves_one_zero_and_never_two(r, proved):
    """F(x) = x² − 1 around m = 1 with Y = 1/2 (= 1/F'(1)): on the box |x − 1| ≤ r the
    Jacobian 2x lies in [2 − 2r, 2 + 2r], so |1 − Y J| ≤ r and b = |Y F(1)| = 0: the norm test
    b + Δ r < r reads r² < r and proves the zero 1 for r < 1 (its enclosure then has radius
    below r).  For r ≥ 2 the box holds both zeros −1 and 1, so any success would be a false
    claim of uniqueness: refused.  The bounds are the kernel's, from the enclosures."""
    from curvedvoronoi.runtime.certify.interval_newton import (float_contraction_bound, float_krawczyk_test,
                                                               float_residual_bound)

    Y = np.array([[[0.5]]])
    b = float_residual_bound(Y, np.array([[0.0]]), np.array([[0.0]]))
    D = float_contraction_bound(Y, np.array([[[2.0]]]), np.array([[[2.0 * r]]]))
    ok, rad = float_krawczyk_test(b, D, np.array([[r]]))
    assert bool(ok[0]) is proved
    if proved:
        assert 0 <= rad[0, 0] < r


# ----------------------------------------------------------------------------- feet on a symmetry axis

@pytest.mark.parametrize("co, q, rot, shift", [
    ((1, 0, 4, 0, 0, -4), (Q(1, 2), Q(0)), (1, 0), (0, 0)),                  # x²/4 + y² = 1
    ((1, 0, 4, -2, 0, -3), (Q(3, 2), Q(0)), (1, 0), (1, 0)),                 # the same, centred at (1, 0)
    ((73, -72, 52, 0, 0, -100), (Q(3, 10), Q(2, 5)), (Q(3, 5), Q(4, 5)), (0, 0)),   # turned by (3/5, 4/5)
])
def test_feet_from_a_point_on_the_major_axis(co, q, rot, shift):
    """The ellipse X²/4 + Y² = 1 (in its own frame: turned by ``rot``, centred at ``shift``) seen
    from the point of its major axis at X = 1/2: the normal at (2 cos t, sin t) meets the axis at
    X = (4 − 1)/2 · cos t, so cos t = 1/3 and the feet are (2/3, ±2√2/3) at squared distance
    (2/3 − 1/2)² + 8/9 = 11/12, besides the vertices (±2, 0) at 9/4 and 25/4.  On the axis the foot
    polynomial has a double root at a singular multiplier (the conjugate pair of feet): the balls
    of the cluster route must hold the exact feet."""
    from flint import arb as arb_

    from curvedvoronoi.runtime.certify.foot import foot_polynomial, real_feet_ball, working_prec

    fp = foot_polynomial(tuple(Q(v) for v in co))
    with working_prec(128):
        feet = real_feet_ball(fp, arb_(q[0].numerator) / q[0].denominator, arb_(q[1].numerator) / q[1].denominator)
        s = arb_(8).sqrt() / 3
        c, sn = (arb_(Q(v).numerator) / Q(v).denominator for v in rot)
        want = []
        for X, Y, D in ((arb_(2) / 3, s, arb_(11) / 12), (arb_(2) / 3, -s, arb_(11) / 12),
                        (arb_(2), arb_(0), arb_(9) / 4), (arb_(-2), arb_(0), arb_(25) / 4)):
            want.append((c * X - sn * Y + shift[0], sn * X + c * Y + shift[1], D))
    assert len(feet) == 4
    for x, y, D in want:
        assert any(f.px.overlaps(x) and f.py.overlaps(y) and f.D.overlaps(D) and float(f.D.rad()) < 1e-6
                   for f in feet), (x, y, D)


# ----------------------------------------------------------------------------- zero-dimensionality

def test_a_vanishing_equation_never_passes_the_top_form_test():
    """With one polynomial identically 0 the system in (x, y, T) is two equations in three
    unknowns: its zero set has positive dimension (a curve at least), so the sufficient test
    'the top forms have a constant gcd' must not pass, whatever the two others are (here
    xy + 1 and x² + y, whose tops xy and x² share x, and x² + y, y² + x, coprime tops)."""
    from curvedvoronoi.runtime.certify import dimension as d

    P = d.DIMENSION_PRIME
    for rest in ([{(1, 1, 0): 1, (0, 0, 0): 1}, {(2, 0, 0): 1, (0, 1, 0): 1}],
                 [{(2, 0, 0): 1, (0, 1, 0): 1}, {(0, 2, 0): 1, (1, 0, 0): 1}]):
        for at in range(3):
            polys = list(rest)
            polys.insert(at, {})
            assert d._top_forms_coprime(polys, P) is False


# ----------------------------------------------------------------------------- rounding bounds at their limits

def test_residual_and_contraction_bounds_under_catastrophic_cancellation():
    """Y's first row (1, 1, 1) against F, a permutation of (1, 2⁻⁶⁰, −1): the exact (Y F)_0 is 2⁻⁶⁰,
    but a float sum that adds 2⁻⁶⁰ to ±1 first gives 0 (which order the dot product uses is not
    ours to choose: every order is tried); only the rounding term 2γ_{k+1}·Σ|y||f| (≈ 2⁻⁴⁹ here)
    covers it.  The same column as a Jacobian column gives the exact off-diagonal
    |0 − (Y M)_01| = 2⁻⁶⁰."""
    import itertools

    from curvedvoronoi.runtime.certify.interval_newton import float_contraction_bound, float_residual_bound

    Y = np.array([[[1.0, 1.0, 1.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]])
    for perm in itertools.permutations((1.0, 2.0 ** -60, -1.0)):
        F = np.array([perm])
        b = float_residual_bound(Y, F, np.zeros((1, 3)))
        assert Q(b[0, 0]) >= Q(2) ** -60, perm
        J = np.zeros((1, 3, 3))
        J[0, :, 1] = F[0]
        D = float_contraction_bound(Y, J, np.zeros((1, 3, 3)))
        assert Q(D[0, 0, 1]) >= Q(2) ** -60, perm


def test_residual_bound_covers_products_that_underflow():
    """y = f = 2⁻⁶⁰⁰: the product 2⁻¹²⁰⁰ underflows to 0 in binary64; the exact |Y F| is not 0 and
    the bound must cover it (the absolute allowance for underflow)."""
    from curvedvoronoi.runtime.certify.interval_newton import float_residual_bound

    Y = np.array([[[2.0 ** -600, 0.0], [0.0, 1.0]]])
    F = np.array([[2.0 ** -600, 0.0]])
    b = float_residual_bound(Y, F, np.zeros((1, 2)))
    assert Q(b[0, 0]) >= Q(2) ** -1200 > 0


def test_the_modulus_bound_of_a_nearly_real_number():
    """z = 1 + 2⁻⁶⁰ i: |z| = √(1 + 2⁻¹²⁰) > 1, while |Re z| + |Im z| = 1 + 2⁻⁶⁰ rounds to 1.0 in
    binary64: the upper bound of |z| must still be ≥ |z| (checked on squares, exactly)."""
    from curvedvoronoi.runtime.certify.interval_newton import abs_upper

    z = np.array([1.0 + 1j * 2.0 ** -60])
    assert Q(abs_upper(z)[0]) ** 2 >= 1 + Q(2) ** -120


@pytest.mark.parametrize("k", [1, 64, 4000])
def test_round_up_bounds_a_float_sum_that_rounds_down_at_every_step(k):
    """``round_up`` (interval_newton) bounds the exact value of a non-negative float expression of
    at most a few thousand operations.  1 + d with d = 2⁻⁵³ − 2⁻⁶⁰ (below half an ulp of 1, and
    its float sum stays 1) rounds down to 1 at every one of k additions, so the float sum is 1
    while the exact sum is 1 + k·d, a relative error of about k·2⁻⁵³ (≈ 2⁻⁴¹ for k = 4000): its
    round_up must reach the exact value (the relative 2⁻⁴⁰ does; a relative 2⁻⁸⁰, which is
    absorbed by the rounding of 1 + 2⁻⁸⁰, does not).  Checked in Fractions."""
    from curvedvoronoi.runtime.certify.interval_newton import round_up

    d = 2.0 ** -53 - 2.0 ** -60
    s = 1.0
    for _ in range(k):
        s = s + d
    assert s == 1.0                                   # every addition rounded down
    exact = Q(1) + k * Q(d)
    assert Q(float(round_up(s))) >= exact
    assert Q(float(round_up(np.float64(s)))) >= exact


def test_foot_system_newton_reaches_the_foot_vertex_from_a_rough_start():
    """Newton's method on the foot system of the three unit circles above (vertex (2, 2), feet the
    centres moved by 1 towards it) converges quadratically from a start 0.05 off in every
    coordinate: after its 12 steps at most, the point is within 1e-12 of the exact solution
    (one step leaves an error of the order of 0.05² = 2.5e-3).  Krawczyk then proves it at 53
    bits."""
    from curvedvoronoi.runtime.certify.krawczyk import FootSystem

    circ = [(Q(1), Q(0), Q(1), Q(-2 * cx), Q(-2 * cy), Q(cx * cx + cy * cy - 1)) for cx, cy in ((0, 0), (4, 0), (0, 4))]
    S = FootSystem(circ)
    s = 2 ** -0.5
    exact = [2.0, 2.0, s, s, 4 - s, s, s, 4 - s]
    start = [v + (0.05 if t % 2 == 0 else -0.05) for t, v in enumerate(exact)]
    m = S.newton([arb(v) for v in start], 53)
    assert max(abs(float(a.mid()) - b) for a, b in zip(m, exact)) < 1e-12
    box = S.krawczyk(m)
    assert box[0].contains(arb(2)) and box[1].contains(arb(2))


@pytest.mark.parametrize("attempts", [1, 6])
def test_krawczyk_inflation_from_a_rough_candidate(attempts):
    """F(x) = x² − 7/10 from the candidate m = 1 (the zero is √0.7 ≈ 0.837): Y = 1/F'(1) = 1/2 and
    Y·F(m) = 3/20, so the first box of the ε-inflation (Rump), radius 4·|Y F(m)| = 3/5, is
    X = [2/5, 8/5].  There J(X) = 2X = [4/5, 16/5], C = 1 − Y·J(X) = [−3/5, 3/5] and
    K(X) − m = −3/20 + C·[−3/5, 3/5] ⊂ [−0.51, 0.21], strictly inside [−3/5, 3/5]: the zero is
    proved in X at the first attempt, and X excludes the other zero −√0.7 and the critical point 0
    (a box reaching 0, e.g. of radius 8·|Y F(m)| = 6/5, holds a singular Jacobian: no contraction
    there nor in any larger box)."""
    from curvedvoronoi.runtime.certify.interval_newton import krawczyk_inflation

    c = arb(7) / 10

    def F(z):
        return [z[0] * z[0] - c]

    def J(z):
        return [[2 * z[0]]]
    K, X = krawczyk_inflation(F, J, [arb(1)], attempts=attempts)
    assert K[0].contains(c.sqrt())
    assert X[0].lower() > 0 and not X[0].contains(-c.sqrt())


def test_the_float_test_proves_a_box_whose_margin_exceeds_one_rounding_allowance():
    """Completeness at the float bounds' own scale: Y = [[1, 2²⁰], [0, 1]] and J = [[1, −2²⁰],
    [0, 1]] give Y J = I exactly, and F = (2²⁰, −1) gives (Y F)_0 = 0 exactly, so the exact Krawczyk
    quantities of the box are b = (0, 1), |I − Y J| = 0.  The float bounds add, per dot product
    of length k = 2, the rounding allowance 2γ₃·Σ|y||f| of the module docstring: 2γ₃·2²¹ ≈ 1.4e-9
    in the first row (2.8e-9 once multiplied by r₁ = 2 in Δ r), the 2⁻⁴⁰ of round_up being far
    smaller.  A first component of radius 2e-9 (residual) and a margin of 4e-9 on r₀ = 1
    (contraction) exceed those allowances 1.43 times: both boxes must be proved; a bound charging
    the rounding twice (2.8e-9 > 2e-9, 5.6e-9 > 4e-9) would not prove them."""
    from curvedvoronoi.runtime.certify.interval_newton import (float_contraction_bound, float_krawczyk_test,
                                                               float_residual_bound)

    Y = np.array([[[1.0, 2.0 ** 20], [0.0, 1.0]]])
    J = np.array([[[1.0, -2.0 ** 20], [0.0, 1.0]]])
    assert (np.einsum("...ij,...jl->...il", Y, J) == np.eye(2)).all()
    # the residual: b_0 covers the rounding of a dot product whose exact value is 0
    F = np.array([[2.0 ** 20, -1.0]])
    b = float_residual_bound(Y, F, np.zeros((1, 2)))
    assert Q(b[0, 0]) >= 0 and b[0, 1] >= 1
    ok, rad = float_krawczyk_test(b, np.zeros((1, 2, 2)), np.array([[2e-9, 2.0]]))
    assert ok[0]
    # the contraction: Δ_01 carries the rounding of (Y J)_01 = 1·(−2²⁰) + 2²⁰·1 = 0
    D = float_contraction_bound(Y, J, np.zeros((1, 2, 2)))
    r = np.array([[1.0, 2.0]])
    ok, rad = float_krawczyk_test(np.array([[1.0 - 4e-9, 0.5]]), D, r)
    assert ok[0]
