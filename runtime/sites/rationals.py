"""Exact rational input: the one conversion of numbers to exact rationals.

Every exact computation of the library (thesis §3.1 circle locator, ch. 4 offsets, the foot-point
certificates, the ch. 6 interval polynomials) starts from rational data.  Numbers -- ints,
rational or decimal strings, floats (taken at their exact binary value, as ``Fraction(float)``
does), Decimal, numpy scalars, python-flint fmpz/fmpq, SymPy Integer/Rational/Float (a Float at
its exact binary value, whatever its precision) -- are converted here and nowhere else; NaN,
infinities, bools and irrational or symbolic values are refused with
:class:`runtime.result.InvalidConicError` (a ``ValueError``) naming the value.

This module sits below every other module of ``runtime`` (it imports only :mod:`runtime.result`),
so the sites, the algebra, the interval solver and the diagram can all use it.
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


def _not_finite(name: str, v: Any) -> InvalidConicError:
    return InvalidConicError(f"{name} is not finite ({v!r}): NaN/inf is not accepted")


def _float(v: float, name: str) -> Fraction:
    if not math.isfinite(v):
        raise _not_finite(name, v)
    return Fraction(v)


def _sympy_number(v: Any, name: str) -> Fraction:
    """A SymPy number: Integer and Rational exactly, Float at its exact binary value."""
    if v.is_Rational:
        return Fraction(int(v.p), int(v.q))
    if v.is_finite is False or (v.is_Number and v.is_finite is None):
        raise _not_finite(name, v)           # oo, -oo, zoo; nan
    if v.is_Float:
        import sympy                          # already imported: v is a SymPy object

        r = sympy.Rational(v)
        return Fraction(int(r.p), int(r.q))
    raise InvalidConicError(f"{name}: {v!r} is not a rational number (a symbolic or irrational value)")


#: exact types with a direct conversion (the common case, without abstract-base-class checks)
_FAST = {
    Fraction: lambda v, name: v,
    int: lambda v, name: Fraction(v),
    float: _float,
    flint.fmpq: lambda v, name: Fraction(int(v.p), int(v.q)),
    flint.fmpz: lambda v, name: Fraction(int(v)),
}


def to_fraction(v: Any, name: str = "value") -> Fraction:
    """Exact conversion of ``v`` to a Fraction.

    Parameters
    ----------
    v
        int, Fraction, a rational or decimal string (``"3/5"``, ``"-2"``, ``"1.25"``, ``"1e-3"``),
        float or numpy scalar (its exact binary value), Decimal, python-flint fmpz/fmpq, or a
        SymPy Integer, Rational or Float.
    name
        How error messages name the value.

    Raises
    ------
    InvalidConicError
        For NaN and infinities, bools, unparsable strings, symbolic values and other types.

    Examples
    --------
    >>> to_fraction("1/3"), to_fraction(0.5), to_fraction("1e-3")
    (Fraction(1, 3), Fraction(1, 2), Fraction(1, 1000))
    >>> to_fraction(0.1) == Fraction(3602879701896397, 36028797018963968)
    True
    """
    fast = _FAST.get(type(v))
    if fast is not None:
        return fast(v, name)
    if isinstance(v, bool):
        raise InvalidConicError(f"{name}: bool {v!r} is not a number")
    if isinstance(v, Fraction):
        return v
    if isinstance(v, numbers.Integral):
        return Fraction(int(v))
    if isinstance(v, numbers.Rational):
        return Fraction(int(v.numerator), int(v.denominator))
    if isinstance(v, Decimal):
        if not v.is_finite():
            raise _not_finite(name, v)
        return Fraction(v)
    if type(v).__module__.startswith("sympy"):
        return _sympy_number(v, name)
    if isinstance(v, numbers.Real):              # numpy floating scalars and other binary floats
        return _float(float(v), name)
    if isinstance(v, str):
        try:
            return Fraction(v.strip())
        except (ValueError, ZeroDivisionError) as exc:
            raise InvalidConicError(f"{name}: {v!r} is not a rational number (cannot parse it: {exc})") from None
    raise InvalidConicError(f"{name}: unsupported type {type(v).__name__} ({v!r})")


def parse_rational(v: Any, what: str = "value") -> flint.fmpq:
    """:func:`to_fraction` as a python-flint ``fmpq``."""
    if type(v) is flint.fmpq:
        return v
    f = to_fraction(v, what)
    return flint.fmpq(f.numerator, f.denominator)
