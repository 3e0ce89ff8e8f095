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

Float, batched versions of the test with rounding-error bounds serve as *filters in front of*
this one (the Apollonius filters of the diagram, the norm-form test of
:mod:`runtime.certify.complete`); a filter's failure falls back here, never to a guess.
"""
from __future__ import annotations

from typing import Callable, Sequence

import flint
from flint import acb, acb_mat, arb, arb_mat

__all__ = ["KrawczykFailure", "krawczyk_image", "krawczyk_inflation", "strictly_inside"]


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
