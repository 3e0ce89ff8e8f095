"""Exact rational input: one conversion of user numbers to exact rationals.

Every exact computation of the library (thesis §3.1 circle locator, ch. 4 offsets, the foot-point
certificates) starts from rational data.  User numbers -- ints, rational or decimal strings, floats
(taken at their exact binary value), Decimal, numpy scalars, python-flint fmpz/fmpq -- are converted
here and nowhere else; NaN, inf and bools are refused with :class:`runtime.result.InvalidConicError`.
"""
from __future__ import annotations

import math
import numbers
from decimal import Decimal
from fractions import Fraction
from typing import Any

import flint

from ..result import InvalidConicError

__all__ = ["to_fraction", "parse_rational"]


def to_fraction(v: Any, name: str = "value") -> Fraction:
    """Exact conversion of ``v`` to a Fraction.

    Accepts int, Fraction, rational strings ("3/5", "-2", "1.25", "1e-3"), floats and numpy
    scalars (taken at their exact binary value), Decimal, flint fmpz/fmpq.  Raises
    :class:`InvalidConicError` for NaN/inf, bools and anything else.
    """
    if isinstance(v, bool):
        raise InvalidConicError(f"{name}: bool {v!r} is not a number")
    if isinstance(v, Fraction):
        return v
    if isinstance(v, numbers.Integral):
        return Fraction(int(v))
    if isinstance(v, (float, numbers.Real)) and not isinstance(v, numbers.Rational) and not isinstance(v, Decimal):
        fv = float(v)
        if not math.isfinite(fv):
            raise InvalidConicError(f"{name} is not finite ({v!r}): NaN/inf is not accepted")
        return Fraction(fv)
    if isinstance(v, numbers.Rational):
        return Fraction(int(v.numerator), int(v.denominator))
    if isinstance(v, Decimal):
        if not v.is_finite():
            raise InvalidConicError(f"{name} is not finite ({v!r}): NaN/inf is not accepted")
        return Fraction(v)
    if isinstance(v, flint.fmpz):
        return Fraction(int(v))
    if isinstance(v, flint.fmpq):
        return Fraction(int(v.p), int(v.q))
    if isinstance(v, str):
        s = v.strip()
        try:
            return Fraction(s)
        except (ValueError, ZeroDivisionError) as exc:
            raise InvalidConicError(f"{name}: cannot parse {v!r} as an exact rational number ({exc})") from None
    raise InvalidConicError(f"{name}: unsupported type {type(v).__name__} ({v!r})")


def parse_rational(v: Any, what: str = "value") -> flint.fmpq:
    """:func:`to_fraction` as a python-flint ``fmpq``."""
    if isinstance(v, flint.fmpq):
        return v
    f = to_fraction(v, what)
    return flint.fmpq(f.numerator, f.denominator)
