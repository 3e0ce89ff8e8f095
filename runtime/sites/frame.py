"""Canonical (Euclidean) frames of conics from exact coefficients (thesis §3.1, §4.4 and App. B:
the offsets are stored in canonical coordinates).

:func:`canonical_frame` runs one algorithm in any number system: exact rationals
(:class:`ExactField`, when every square root is rational), flint ``arb`` balls or mpmath numbers.
Every branch decision is taken on the exact rational data; the only irrational operations are
square roots.  The convention is stated in :mod:`runtime.sites.conic`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any, Callable

import flint

from .rationals import parse_rational

__all__ = ["CanonicalFrame", "ExactField", "FRAME_PREC", "canonical_frame", "fraction_sqrt", "sign",
           "to_arb_ball", "to_fmpq"]

#: working precision (bits) of the ball computation from which the float frame is rounded
FRAME_PREC = 128


# --------------------------------------------------------------------------- exact helpers

def _isqrt_exact(n: int) -> int | None:
    if n < 0:
        return None
    r = math.isqrt(n)
    return r if r * r == n else None


def fraction_sqrt(q: Fraction) -> Fraction | None:
    """The exact square root of ``q`` if it is a rational square, else None."""
    q = Fraction(q)
    if q < 0:
        return None
    rn = _isqrt_exact(q.numerator)
    rd = _isqrt_exact(q.denominator)
    if rn is None or rd is None:
        return None
    return Fraction(rn, rd)


def to_fmpq(q: Fraction) -> flint.fmpq:
    return parse_rational(q)


def to_arb_ball(q: Fraction) -> flint.arb:
    return flint.arb(to_fmpq(q))


def sign(q: Fraction) -> int:
    return (q > 0) - (q < 0)


# --------------------------------------------------------------------------- frame


@dataclass(frozen=True)
class CanonicalFrame:
    """Rigid motion to the canonical form (see the module docstring for the convention).

    Fields are floats (:attr:`Conic.frame`), Fractions (:attr:`Conic.exact_frame`),
    mpmath mpf (:meth:`Conic.frame_mp`) or flint arb balls (:meth:`Conic.frame_arb`).
    """

    cos: Any
    sin: Any
    tx: Any
    ty: Any
    kind: str
    params: dict = field(default_factory=dict)

    def to_canonical(self, x, y):
        """World (x, y) -> canonical (X, Y)."""
        dx, dy = x - self.tx, y - self.ty
        return self.cos * dx + self.sin * dy, -self.sin * dx + self.cos * dy

    def from_canonical(self, X, Y):
        """Canonical (X, Y) -> world (x, y)."""
        return self.tx + self.cos * X - self.sin * Y, self.ty + self.sin * X + self.cos * Y

    def normalized(self) -> "CanonicalFrame":
        """Representative modulo the symmetry group of the canonical form.

        Ellipse: major axis on X (swap A2/B2 and turn by 90° if needed), then
        (cos > 0) or (cos == 0 and sin > 0); hyperbola: the same sign rule; circle:
        cos = 1, sin = 0; parabola: unchanged (no symmetry besides Y -> −Y, which does not
        change the frame).  Two frames describe the same curve iff their normalized forms
        are equal (exactly for exact frames).
        """
        c, s, prm = self.cos, self.sin, dict(self.params)
        if self.kind == "circle":
            one = c * c + s * s  # 1 in the right number type
            return CanonicalFrame(one, s - s, self.tx, self.ty, "circle", prm)
        if self.kind == "ellipse" and prm["A2"] < prm["B2"]:
            prm = {"A2": prm["B2"], "B2": prm["A2"]}
            c, s = -s, c
        if self.kind in ("ellipse", "hyperbola"):
            if c < 0 or (c == 0 and s < 0):
                c, s = -c, -s
        return CanonicalFrame(c, s, self.tx, self.ty, self.kind, prm)

    def as_dict(self) -> dict:
        d = {"type": self.kind, "cos": self.cos, "sin": self.sin, "tx": self.tx, "ty": self.ty}
        d.update(self.params)
        return d


def canonical_frame(coeffs: tuple[Fraction, ...], kind: str, num: Callable[[Fraction], Any],
                   sqrt_: Callable[[Fraction], Any]) -> CanonicalFrame:
    """Canonical frame from exact coefficients in any number system.

    ``num`` converts an exact Fraction to the number system, ``sqrt_`` returns the square
    root of a non-negative Fraction in it.  Every branch decision uses exact rationals; the
    only irrational operations are the square roots (the rotation may be irrational).
    """
    a, b, c, d, e, f = coeffs
    if kind == "parabola":
        lam = a + c
        nraw = (a, b / 2) if abs(a) >= abs(c) else (b / 2, c)
        uraw = (-nraw[1], nraw[0])
        Dn = d * nraw[0] + e * nraw[1]
        Du = d * uraw[0] + e * uraw[1]
        if -Du / lam < 0:  # orient the axis so that the parabola opens towards +X
            uraw = (-uraw[0], -uraw[1])
            Du = -Du
        N2 = nraw[0] ** 2 + nraw[1] ** 2
        vx = -Dn * nraw[0] / (2 * lam * N2) + (Dn * Dn / (4 * lam * N2) - f) * uraw[0] / Du
        vy = -Dn * nraw[1] / (2 * lam * N2) + (Dn * Dn / (4 * lam * N2) - f) * uraw[1] / Du
        N = sqrt_(N2)
        cos_, sin_ = num(uraw[0]) / N, num(uraw[1]) / N
        p = num(abs(Du) / (2 * abs(lam))) / N
        return CanonicalFrame(cos_, sin_, num(vx), num(vy), kind, {"p": p})

    detQ = a * c - b * b / 4
    # centre: Q t = -(d/2, e/2)
    tx = (b * e / 4 - c * d / 2) / detQ
    ty = (b * d / 4 - a * e / 2) / detQ
    fc = f + (d * tx + e * ty) / 2  # value of the form at the centre = det M / det Q
    if kind == "circle":
        return CanonicalFrame(num(Fraction(1)), num(Fraction(0)), num(tx), num(ty), kind, {"r2": num(-fc / a)})
    h, k = (a - c) / 2, b / 2
    r2 = h * h + k * k  # > 0 (not a circle)
    r = sqrt_(r2)
    s_ = a + c
    # eigenvector of lambda_+ = (a+c)/2 + r, chosen without cancellation
    if h >= 0:
        vplus = (num(h) + r, num(k))
        n2p = num(2 * r2) + num(2 * h) * r  # |vplus|² = 2r(r+h)
        plus_first_sign = 1
    else:
        vplus = (num(k), r - num(h))
        n2p = num(2 * r2) - num(2 * h) * r
        plus_first_sign = sign(k)
    lam_plus_big = s_ >= 0  # |lambda_+| >= |lambda_-|
    big = num(s_ / 2) + r if lam_plus_big else num(s_ / 2) - r
    small = num(detQ) / big
    lam_plus = big if lam_plus_big else small
    lam_minus = small if lam_plus_big else big
    if kind == "ellipse":
        use_plus = not lam_plus_big  # X axis = eigenvector of the eigenvalue of smaller modulus
    else:  # hyperbola: -fc / lambda_X > 0
        use_plus = fc < 0
    if use_plus:
        vec, first_sign = vplus, plus_first_sign
        lx, ly = lam_plus, lam_minus
    else:
        vec = (-vplus[1], vplus[0])
        # first component: -k (h >= 0) or h - r < 0 (h < 0)
        first_sign = -sign(k) if h >= 0 else -1
        lx, ly = lam_minus, lam_plus
    if first_sign < 0:
        vec = (-vec[0], -vec[1])
    norm = sqrt_(n2p) if isinstance(n2p, Fraction) else n2p.sqrt()
    cos_, sin_ = vec[0] / norm, vec[1] / norm
    nfc = num(fc)
    if kind == "ellipse":
        params = {"A2": -nfc / lx, "B2": -nfc / ly}
    else:
        params = {"A2": -nfc / lx, "B2": nfc / ly}
    return CanonicalFrame(cos_, sin_, num(tx), num(ty), kind, params)


class ExactField:
    """Adapter so that canonical_frame can run in exact arithmetic when all roots are rational."""

    class NotRational(Exception):
        pass

    @staticmethod
    def num(q: Fraction) -> Fraction:
        return Fraction(q)

    @staticmethod
    def sqrt(q: Fraction) -> Fraction:
        r = fraction_sqrt(q)
        if r is None:
            raise ExactField.NotRational
        return r
