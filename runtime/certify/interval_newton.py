"""Krawczyk's interval Newton test on arb (real) or acb (complex) boxes: the one implementation.

Krawczyk's theorem (Krawczyk 1969; Moore, Kearfott & Cloud, *Introduction to Interval Analysis*,
§8.2; thesis §3.3.3): for a box X = m + [−r, r], any matrix Y and an enclosure J(X) of the
Jacobian of F over X,

    K(X) = m − Y F(m) + (I − Y J(X)) (X − m) ⊂ int X   ⇒   F has exactly one zero in X,

and that zero lies in K(X) ∩ X.  In the complex case X is a product of squares
m_i + [−r_i, r_i] + i[−r_i, r_i] and the same statement holds for holomorphic F (the Jacobian is
the complex one; Rump 1983, Frommer–Lang 2005).

:func:`krawczyk_image` is the operator itself (used one step at a time by the branch-and-prune
solver of ch. 6, :mod:`runtime.interval.solver`).  :func:`krawczyk_inflation` proves a zero near
an (exact) candidate m: Y = mid J(m)⁻¹, a first radius 4|Y F(m)| (floored), then ε-inflation
(Rump 1983) r ← max(2|K − m|, 2r) until K ⊂ int X or ``attempts`` run out.  Callers pass their
own F and J (foot-point system, offset system, Apollonius system): the test is the same.

The same theorem is decided on *float batches* by :func:`float_krawczyk_test`, in norm form
(Neumaier, *Interval Methods for Systems of Equations*, 1990, §5.1; the ε-inflation of Rump 1983)
with every rounding of IEEE binary64 (round to nearest) bounded outward: callers compute, for a
box X = {|x_i − m_i| ≤ r_i} (real intervals or complex discs) and any float matrix Y,

    b ≥ |Y F(m)|                                   (:func:`float_residual_bound`)
    Δ ≥ |I − Y M| for every M with entries in the enclosures of ∂F_i/∂x_j over X
                                                   (:func:`float_contraction_bound`)

and the test is b + Δ r < r.  Proof: g(x) = x − Y F(x) maps X into X, since by the mean-value
theorem (for holomorphic F, the integral form) g(x) − m = −Y F(m) + (I − Y J̄)(x − m) with J̄ an
average of Jacobians over the segment [m, x] ⊂ X, whose entries lie in the (convex) enclosures;
so Brouwer gives a fixed point, a zero of F.  As Δ ≥ 0 and Δ r < r with r > 0, the spectral
radius of Δ is < 1 (Perron–Frobenius), so every I − Y J̄ has spectral radius < 1, Y and the
Jacobians on X are nonsingular: the zero is simple and the only one in X (two zeros x, x' would
give |x − x'| ≤ Δ |x − x'|), and it lies in |x − m| ≤ b + Δ r.  If m is real, X is symmetric
under conjugation and F has real coefficients, the zero is real.

The float test is the batched fast path (the Apollonius vertices of the diagram, the offset
solutions of :mod:`runtime.certify.complete`); where it fails, callers fall back to the ball
test above or to exact arithmetic, never to a guess.  The two are the only places where
K(X) ⊂ int X is decided.
"""
from __future__ import annotations

from typing import Callable, Sequence

import flint
import numpy as np
from flint import acb, acb_mat, arb, arb_mat

__all__ = ["KrawczykFailure", "krawczyk_image", "krawczyk_inflation", "strictly_inside",
           "UNIT_ROUNDOFF", "UNDERFLOW", "round_up", "abs_upper", "gamma", "float_inverse",
           "float_residual_bound", "float_contraction_bound", "float_krawczyk_test"]


class KrawczykFailure(Exception):
    """No Krawczyk proof at this precision (singular Jacobian, no contraction, ...)."""


def _identity(n: int, mat):
    eye = mat(n, n)
    for i in range(n):
        eye[i, i] = 1
    return eye


def krawczyk_image(m: Sequence, YF, Y, JX, dX: Sequence) -> list:
    """K(X) = m − Y F(m) + (I − Y J(X))·dX with dX = X − m (balls), YF = Y·F(m) (column matrix),
    Y a point matrix and JX an enclosure of the Jacobian over X (arb_mat or acb_mat)."""
    n = len(m)
    mat = acb_mat if isinstance(JX, acb_mat) else arb_mat
    C = _identity(n, mat) - Y * JX
    CdX = C * mat([[d] for d in dX])
    return [m[i] - YF[i, 0] + CdX[i, 0] for i in range(n)]


def strictly_inside(k, m, r: arb) -> bool:
    """K_i ⊂ int(m_i + [−r, r]) (real) or int(m_i + [−r, r] + i[−r, r]) (complex), proved."""
    d = k - m
    if isinstance(d, acb):
        return bool(abs(d.real).abs_upper() < r and abs(d.imag).abs_upper() < r)
    return bool(abs(d).abs_upper() < r)


def krawczyk_inflation(F: Callable, J: Callable, m: Sequence, *, attempts: int = 6,
                       floor_bits: int = 24, floor=None) -> tuple[list, list]:
    """A box around the exact candidate ``m`` proved to hold exactly one zero of F.

    ``F(z)`` returns the list of values and ``J(z)`` the Jacobian rows (lists of balls), both
    at ball arguments z; ``m`` is a list of arb (real test) or acb (complex test) midpoints.
    Returns (K ∩ X or K, X): the enclosure of the zero and the box X in which it is unique.
    ``floor`` (an arb, or one per component) bounds the first radius from below; by default
    (max|m| + 1)·2^(floor_bits − prec).  Raises :class:`KrawczykFailure`.
    """
    complex_ = isinstance(m[0], acb)
    mat = acb_mat if complex_ else arb_mat
    m = [t.mid() for t in m]
    n = len(m)
    try:
        Y = mat(J(m)).mid().inv().mid()
    except ZeroDivisionError:
        raise KrawczykFailure("singular Jacobian at the candidate") from None
    YF = Y * mat([[v] for v in F(m)])
    if floor is None:
        scale = max(abs(t).abs_upper() for t in m) + 1
        floor = scale * arb(2) ** (floor_bits - flint.ctx.prec)
    floors = list(floor) if isinstance(floor, (list, tuple)) else [floor] * n
    r = [max(4 * abs(YF[i, 0]).abs_upper(), floors[i]) for i in range(n)]
    for _ in range(attempts):
        dX = [acb(arb(0, ri), arb(0, ri)) if complex_ else arb(0, ri) for ri in r]
        X = [m[i] + dX[i] for i in range(n)]
        K = krawczyk_image(m, YF, Y, mat(J(X)), dX)
        if not all(k.is_finite() for k in K):
            break
        if all(strictly_inside(K[i], m[i], r[i]) for i in range(n)):
            if complex_:
                return K, X
            return [K[i].intersection(X[i]) for i in range(n)], X
        r = [max(2 * abs(K[i] - m[i]).abs_upper(), 2 * r[i]) for i in range(n)]
    raise KrawczykFailure("Krawczyk operator did not contract")


# --------------------------------------------------------------------------- float batches
#
# The rounding model (Higham, *Accuracy and Stability of Numerical Algorithms*, 2nd ed., §2.2,
# §3.1, Lemma 3.5): with u = 2^-53, a real operation gives fl(a ∘ b) = (a ∘ b)(1 + δ), |δ| ≤ u,
# plus an absolute error below 2^-1074 on underflow; a complex product fl(ab) = ab(1 + δ),
# |δ| ≤ √2·γ₂; a sum of k terms is off by at most γ_{k−1} times the sum of their moduli.  Hence a
# dot product of length k, real or complex, is off by at most 2·γ_{k+1}·Σ|y_j||f_j| (plus k
# underflows).  Non-negative bounds are computed in round-to-nearest and then passed through
# round_up, whose relative 2^-40 dominates the at most a few thousand relative roundings of size
# u made while computing them, and whose absolute 2^-1000 dominates their underflows.  Overflow
# gives inf or NaN, which fails every test below.

#: unit roundoff of IEEE binary64, round to nearest
UNIT_ROUNDOFF = 2.0 ** -53
#: an absolute allowance larger than the underflow error of any few thousand operations
UNDERFLOW = 2.0 ** -1000
_ROUND_UP = 1 + 2.0 ** -40


def round_up(t):
    """An upper bound of the exact value of a non-negative float expression ``t`` computed in
    round-to-nearest from non-negative terms (at most a few thousand operations)."""
    return t * _ROUND_UP + UNDERFLOW


def abs_upper(z):
    """An upper bound of |z| (elementwise): exact for real arrays, |Re z| + |Im z| (rounded up)
    for complex ones."""
    z = np.asarray(z)
    if np.iscomplexobj(z):
        return (np.abs(z.real) + np.abs(z.imag)) * (1 + 2.0 ** -50)
    return np.abs(z)


def gamma(n: int) -> float:
    """Higham's γ_n = n·u / (1 − n·u), rounded up."""
    return n * UNIT_ROUNDOFF / (1 - n * UNIT_ROUNDOFF) * _ROUND_UP


def float_inverse(J):
    """(Y, good): float inverses of the batched square matrices ``J`` (…, k, k), and the rows
    where J is finite and its float determinant nonzero (elsewhere Y = 0).  Y needs no accuracy:
    any matrix serves Krawczyk's test, which then fails or succeeds on its own."""
    J = np.asarray(J)
    with np.errstate(all="ignore"):
        good = np.isfinite(J).all(axis=(-2, -1))
        good &= np.abs(np.linalg.det(np.where(good[..., None, None], J, 0))) > 0
        Y = np.zeros_like(J)
        if good.any():
            Y[good] = np.linalg.inv(J[good])
    return Y, good


def float_residual_bound(Y, F, F_rad):
    """b ≥ |Y F(m)| (…, k) for every value F(m) within ``F_rad`` of the float ``F`` (…, k)."""
    k = np.shape(Y)[-1]
    with np.errstate(all="ignore"):
        aY = abs_upper(Y)
        YF = np.einsum("...ij,...j->...i", Y, F)
        return round_up(abs_upper(YF) + 2 * gamma(k + 1) * np.einsum("...ij,...j->...i", aY, abs_upper(F))
                        + np.einsum("...ij,...j->...i", aY, F_rad) + k * UNDERFLOW)


def float_contraction_bound(Y, J, J_rad):
    """Δ ≥ |I − Y M| (…, k, k) for every matrix M whose entries lie within ``J_rad`` of the float
    ``J`` (…, k, k) -- the enclosure of the Jacobian over the box."""
    k = np.shape(Y)[-1]
    with np.errstate(all="ignore"):
        aY = abs_upper(Y)
        C = np.eye(k) - np.einsum("...ij,...jl->...il", Y, J)
        aYaJ = np.einsum("...ij,...jl->...il", aY, abs_upper(J))
        # fl(I − fl(Y J)): the products by 2γ_{k+1}|Y||J|, the subtraction by 4u of the result
        return round_up(abs_upper(C) * (1 + 4 * UNIT_ROUNDOFF) + 2 * gamma(k + 1) * aYaJ
                        + np.einsum("...ij,...jl->...il", aY, J_rad) + UNDERFLOW)


def float_krawczyk_test(b, Delta, r):
    """Krawczyk's test in norm form on a batch of boxes {|x_i − m_i| ≤ r_i} (module docstring).

    ``b`` (…, k) and ``Delta`` (…, k, k) are the bounds of :func:`float_residual_bound` and
    :func:`float_contraction_bound` for the box of radii ``r`` (…, k).  Returns (ok, rad): where
    ok, the box holds exactly one zero of F, simple, within ``rad`` (…, k) of m componentwise."""
    with np.errstate(all="ignore"):
        rad = round_up(b + np.einsum("...ij,...j->...i", Delta, r))
        ok = (np.isfinite(rad) & (rad < r)).all(axis=-1)
    return ok, rad
