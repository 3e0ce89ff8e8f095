"""The one conversion of numbers to exact rationals (runtime/sites/rationals.py): every accepted
type gives its exact value (a float its binary value, a SymPy Float too at any precision), every
refused value (bool, NaN, ±inf, unparsable string, symbolic value, other type) raises
InvalidConicError naming it, and the modules that read numbers (the JSON reader, the interval
polynomials, the exact frame translation) go through it."""
from __future__ import annotations

from decimal import Decimal
from fractions import Fraction

import flint
import numpy as np
import pytest
import sympy

from curvedvoronoi.runtime.interval.poly import Poly
from curvedvoronoi.runtime.predicates.circles import Circle, Point
from curvedvoronoi.runtime.result import InvalidConicError
from curvedvoronoi.runtime.sites.conic import Conic
from curvedvoronoi.runtime.sites.rationals import parse_rational, to_fraction
from curvedvoronoi.runtime.sites.reader import parse_number
from curvedvoronoi.runtime.voronoi.frame import translate_site

EXACT = [
    (3, Fraction(3)),
    (-7, Fraction(-7)),
    ("1/3", Fraction(1, 3)),
    (" -2/6 ", Fraction(-1, 3)),
    ("1.25", Fraction(5, 4)),
    ("1e-3", Fraction(1, 1000)),
    (0.1, Fraction(3602879701896397, 2 ** 55)),              # the binary value, not 1/10
    (2.0 ** -1074, Fraction(1, 2 ** 1074)),                    # the smallest subnormal, exactly
    (np.float64(0.5), Fraction(1, 2)),
    (np.float32(0.1), Fraction(13421773, 2 ** 27)),
    (np.int64(-4), Fraction(-4)),
    (Decimal("0.3"), Fraction(3, 10)),
    (Fraction(2, 9), Fraction(2, 9)),
    (flint.fmpq(2, 7), Fraction(2, 7)),
    (flint.fmpz(-9), Fraction(-9)),
    (sympy.Integer(5), Fraction(5)),
    (sympy.Rational(-1, 3), Fraction(-1, 3)),
    (sympy.Float(0.25), Fraction(1, 4)),
]


@pytest.mark.parametrize("value, expected", EXACT, ids=[repr(v) for v, _ in EXACT])
def test_exact_values(value, expected):
    q = to_fraction(value)
    assert type(q) is Fraction and q == expected
    p = parse_rational(value)
    assert isinstance(p, flint.fmpq) and (int(p.p), int(p.q)) == (expected.numerator, expected.denominator)


def test_a_sympy_float_keeps_all_its_bits():
    """A 200-bit SymPy Float is not rounded to a double on the way."""
    x = sympy.Float("0.1", 60)
    q = to_fraction(x)
    assert q != Fraction(0.1) and abs(q - Fraction(1, 10)) < Fraction(1, 10 ** 59)
    assert q.denominator & (q.denominator - 1) == 0                 # a binary fraction: its exact value


REFUSED = [
    (True, "bool"),
    (False, "bool"),
    (float("nan"), "not finite"),
    (float("inf"), "not finite"),
    (-float("inf"), "not finite"),
    (np.float64("nan"), "not finite"),
    (Decimal("NaN"), "not finite"),
    (Decimal("-Infinity"), "not finite"),
    (sympy.oo, "not finite"),
    (sympy.nan, "not finite"),
    (sympy.zoo, "not finite"),
    ("one half", "is not a rational number"),
    ("1/0", "is not a rational number"),
    (sympy.sqrt(2), "is not a rational number"),
    (sympy.Symbol("x"), "is not a rational number"),
    (None, "unsupported type"),
    (1j, "unsupported type"),
]


@pytest.mark.parametrize("value, message", REFUSED, ids=[repr(v) for v, _ in REFUSED])
def test_refusals_name_the_value(value, message):
    with pytest.raises(InvalidConicError, match=message) as err:
        to_fraction(value, "centre x")
    assert "centre x" in str(err.value)
    assert isinstance(err.value, ValueError)                      # callers catching ValueError still do


def test_the_json_reader_takes_only_json_values_and_returns_exact_fractions():
    assert parse_number(0.1, "x") == Fraction(0.1) and type(parse_number(0.1, "x")) is Fraction
    assert parse_number(7, "x") == 7 and type(parse_number(7, "x")) is Fraction
    assert parse_number("-3/4", "x") == Fraction(-3, 4)
    for bad, msg in ((True, "not a number or a rational string"), (Decimal(1), "not a number or a rational string"),
                     (float("nan"), "not finite"), ("x", "sites\\[0\\]: 'x' is not a rational number")):
        with pytest.raises(ValueError, match=msg):
            parse_number(bad, "sites[0]")


def test_interval_polynomials_take_every_exact_coefficient_type():
    p = Poly(("x", "y"), {(1, 0): sympy.Rational(1, 3), (0, 1): flint.fmpq(2, 5), (0, 0): 0.5,
                          (1, 1): flint.fmpz(4), (2, 0): "7/9"})
    assert p.terms == {(1, 0): Fraction(1, 3), (0, 1): Fraction(2, 5), (0, 0): Fraction(1, 2),
                       (1, 1): Fraction(4), (2, 0): Fraction(7, 9)}
    with pytest.raises(InvalidConicError, match="coefficient"):
        Poly(("x",), {(1,): float("nan")})


def test_the_frame_translation_is_exact_for_float_offsets():
    """A float offset moves the site by its exact binary value, for every site kind."""
    t = 0.1
    assert translate_site(Point(1, 2), t, 0) == Point(flint.fmpq(1) - parse_rational(t), 2)
    c = translate_site(Circle(1, 2, 4), "1/3", 0.5)
    assert (c.cx, c.cy, c.r2) == (flint.fmpq(2, 3), flint.fmpq(3, 2), flint.fmpq(4))
    e = translate_site(Conic.from_coefficients(1, 0, 2, 0, 0, -1), "1/3", 0)   # x² + 2y² = 1 moved by −1/3
    a, b, cc, d, ee, f = e.coefficients
    x = Fraction(-1, 3) + 1                                          # (x + 1/3)² = 1 at y = 0
    assert a * x * x + d * x + f == 0


def test_doctests():
    import doctest

    from curvedvoronoi.runtime.sites import rationals

    assert doctest.testmod(rationals).failed == 0
