"""Exact arithmetic and exact signs in towers of real quadratic extensions.

Thesis §3.1.2–§3.1.3: the Apollonius circles of three circles are expressed with quadratic
radicals of the data, so every quantity the circle conflict locator needs (the signed
expansion r, the value of g = (x4-x)^2+(y4-y)^2-(r+r4)^2, ...) lives in a tower

    Q = K_0 ⊂ K_1 = K_0(√d_0) ⊂ K_2 = K_1(√d_1) ⊂ ...     (d_k ∈ K_k, d_k ≥ 0)

(radii √r2_i of circles with a non-square squared radius, the discriminant of the quadratic
in r, ...).  An element of K_{k+1} is stored as ``(k, a, b)`` meaning ``a + b·√d_k`` with
``a, b ∈ K_k``; a rational is a :class:`flint.fmpq` and is valid at every level (no lifting).

The sign of ``a + b√d`` is decided exactly with only ring operations ("comparing squares"):
if a and b have the same sign (or one is 0) the answer is immediate, otherwise
``sign(a + b√d) = sign(a) · sign(a² − b²d)``.  The recursion ends in signs of rationals.
This identity holds for the positive real root √d whatever the algebraic relations between
the radicands are, so the representation need not be canonical: a zero may be stored as a
non-trivial tuple, and :meth:`QuadTower.sign` still returns 0 for it.  No division is ever
performed in the tower (callers keep fractions ``num/den`` with a denominator of known sign).
"""
from __future__ import annotations

from fractions import Fraction
from typing import Union

from flint import arb, ctx, fmpq

Elem = Union[fmpq, tuple]

ZERO = fmpq(0)
ONE = fmpq(1)
_FILTER_PREC = 128


def rational_sqrt(q: fmpq) -> fmpq | None:
    """Exact square root of a non-negative rational if it is a perfect square, else None."""
    if q < 0:
        return None
    p, d = q.p, q.q
    if p.is_square() and d.is_square():
        return fmpq(p.isqrt(), d.isqrt())
    return None


def _top(x: Elem) -> int:
    return x[0] if isinstance(x, tuple) else -1


def _is_rat_zero(x: Elem) -> bool:
    return (not isinstance(x, tuple)) and x == 0


class QuadTower:
    """A tower of real quadratic extensions of Q given by its radicands ``d_0, d_1, ...``.

    Instances are immutable; :meth:`extend` returns a new tower sharing the prefix, so that an
    element built in a prefix tower stays valid in every extension.
    """

    __slots__ = ("rads", "_rad_arb")

    def __init__(self, rads: tuple = ()):
        self.rads = tuple(rads)
        self._rad_arb: dict[int, tuple[int, arb]] = {}

    # ----------------------------------------------------------------- construction
    def extend(self, d: Elem) -> tuple["QuadTower", tuple]:
        """Adjoin √d (d ≥ 0 exactly, checked).  Returns (new tower, the element √d)."""
        s = self.sign(d)
        if s < 0:
            raise ValueError("cannot adjoin the square root of a negative number")
        t = QuadTower(self.rads + (d,))
        k = len(self.rads)
        return t, (k, ZERO, ONE)

    def gen(self, k: int) -> tuple:
        return (k, ZERO, ONE)

    @property
    def depth(self) -> int:
        return len(self.rads)

    # ----------------------------------------------------------------- ring operations
    def add(self, x: Elem, y: Elem) -> Elem:
        kx, ky = _top(x), _top(y)
        if kx < 0 and ky < 0:
            return x + y
        if kx > ky:
            return self._mk(kx, self.add(x[1], y), x[2])
        if ky > kx:
            return self._mk(ky, self.add(x, y[1]), y[2])
        return self._mk(kx, self.add(x[1], y[1]), self.add(x[2], y[2]))

    def neg(self, x: Elem) -> Elem:
        if not isinstance(x, tuple):
            return -x
        return (x[0], self.neg(x[1]), self.neg(x[2]))

    def sub(self, x: Elem, y: Elem) -> Elem:
        return self.add(x, self.neg(y))

    def mul(self, x: Elem, y: Elem) -> Elem:
        kx, ky = _top(x), _top(y)
        if kx < 0 and ky < 0:
            return x * y
        if kx < 0 and x == 0 or ky < 0 and y == 0:
            return ZERO
        if kx > ky:
            return self._mk(kx, self.mul(x[1], y), self.mul(x[2], y))
        if ky > kx:
            return self._mk(ky, self.mul(x, y[1]), self.mul(x, y[2]))
        a1, b1, a2, b2 = x[1], x[2], y[1], y[2]
        d = self.rads[kx]
        aa = self.mul(a1, a2)
        bb = self.mul(b1, b2)
        # Karatsuba: a1 b2 + a2 b1 = (a1+b1)(a2+b2) - aa - bb
        cross = self.sub(self.sub(self.mul(self.add(a1, b1), self.add(a2, b2)), aa), bb)
        return self._mk(kx, self.add(aa, self.mul(bb, d)), cross)

    def sqr(self, x: Elem) -> Elem:
        return self.mul(x, x)

    def dot(self, xs, ys) -> Elem:
        acc: Elem = ZERO
        for a, b in zip(xs, ys):
            acc = self.add(acc, self.mul(a, b))
        return acc

    @staticmethod
    def _mk(k: int, a: Elem, b: Elem) -> Elem:
        if _is_rat_zero(b):
            return a
        return (k, a, b)

    # ----------------------------------------------------------------- exact sign
    def sign(self, x: Elem) -> int:
        """Exact sign (-1, 0, 1) of x.

        Filtered: a 128-bit arb enclosure that excludes 0 proves the sign (ball arithmetic is
        rigorous); otherwise the sign is decided by recursive comparison of squares.
        """
        if not isinstance(x, tuple):
            return (x > 0) - (x < 0)
        with ctx.workprec(_FILTER_PREC):
            b = self._arb(x, _FILTER_PREC)
        if b > 0:
            return 1
        if b < 0:
            return -1
        return self._sign_exact(x)

    def _sign_exact(self, x: Elem) -> int:
        k, a, b = x
        sb = self.sign(b)
        if sb == 0:
            return self.sign(a)
        sa = self.sign(a)
        d = self.rads[k]
        if sa == 0:
            return sb if self.sign(d) != 0 else 0
        if sa == sb:
            return sa
        # opposite signs: compare a^2 with b^2 d
        return sa * self.sign(self.sub(self.mul(a, a), self.mul(self.mul(b, b), d)))

    def is_zero(self, x: Elem) -> bool:
        return self.sign(x) == 0

    # ----------------------------------------------------------------- numerical value
    def to_arb(self, x: Elem, prec: int) -> arb:
        """A rigorous ball enclosure of x computed at working precision ``prec`` bits."""
        with ctx.workprec(prec):
            return self._arb(x, prec)

    def _arb(self, x: Elem, prec: int) -> arb:
        if not isinstance(x, tuple):
            return arb(x)
        k, a, b = x
        return self._arb(a, prec) + self._arb(b, prec) * self._sqrt_rad(k, prec)

    def _sqrt_rad(self, k: int, prec: int) -> arb:
        hit = self._rad_arb.get(k)
        if hit is not None and hit[0] == prec:
            return hit[1]
        d = self._arb(self.rads[k], prec)
        # d >= 0 exactly (checked in extend): clip a ball straddling 0
        if not (d > 0):
            d = d.nonnegative_part()
        s = d.sqrt()
        self._rad_arb[k] = (prec, s)
        return s

    def to_float(self, x: Elem, max_prec: int = 4096) -> float:
        """x rounded to a double, with relative accuracy ~2^-52 (an exact 0 gives 0.0).

        The precision is doubled until the ball is relatively tight; if x is (exactly) zero
        the loop is cut short by the exact sign test.
        """
        if not isinstance(x, tuple):
            return float(x.p) / float(x.q) if abs(x.p) < 2**1000 and x.q < 2**1000 else _big_float(x)
        if self.sign(x) == 0:
            return 0.0
        prec = 128
        while True:
            b = self.to_arb(x, prec)
            if b.rel_accuracy_bits() >= 60 or prec >= max_prec:
                return float(b.mid())
            prec *= 2


def _big_float(q: fmpq) -> float:
    return float(Fraction(int(q.p), int(q.q)))


class Frac:
    """``num / den`` with num, den in a tower and den ≠ 0; no tower division is needed."""

    __slots__ = ("num", "den")

    def __init__(self, num: Elem, den: Elem = ONE):
        self.num = num
        self.den = den

    def __repr__(self) -> str:  # pragma: no cover - debugging aid
        return f"Frac({self.num!r}, {self.den!r})"


def frac_add(T: QuadTower, x: Frac, y: Frac) -> Frac:
    if x.den is y.den or (not isinstance(x.den, tuple) and not isinstance(y.den, tuple) and x.den == y.den):
        return Frac(T.add(x.num, y.num), x.den)
    return Frac(T.add(T.mul(x.num, y.den), T.mul(y.num, x.den)), T.mul(x.den, y.den))


def frac_sub(T: QuadTower, x: Frac, y: Frac) -> Frac:
    return frac_add(T, x, Frac(T.neg(y.num), y.den))


def frac_mul(T: QuadTower, x: Frac, y: Frac) -> Frac:
    return Frac(T.mul(x.num, y.num), T.mul(x.den, y.den))


def frac_sign(T: QuadTower, x: Frac) -> int:
    return T.sign(x.num) * T.sign(x.den)


def frac_to_float(T: QuadTower, x: Frac) -> float:
    if frac_sign(T, x) == 0:
        return 0.0
    prec = 128
    while True:
        with ctx.workprec(prec):
            v = T._arb(x.num, prec) / T._arb(x.den, prec)
        if v.rel_accuracy_bits() >= 60 or prec >= 4096:
            return float(v.mid())
        prec *= 2
