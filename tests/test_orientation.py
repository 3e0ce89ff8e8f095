"""The filtered orientation and incircle predicates (runtime/predicates/orientation.py) at their
boundaries: exact expected signs from sympy's rational determinants (an independent evaluation),
on inputs where the naive float determinant is wrong (Shewchuk's grid near a line, co-circular
points at UTM scale), on exactly degenerate inputs (sign 0), at margins of 10⁻⁹ and of one ulp,
and at the ends of the float range (underflow, overflow); the filter is shown to defer to the
exact path on those inputs and to decide alone on clear ones."""
from fractions import Fraction

import numpy as np
import pytest
import sympy
from hypothesis import given, settings
from hypothesis import strategies as st

from curvedvoronoi.runtime.predicates import orientation as O

U = 2.0 ** -53


def sympy_orient(a, b, c) -> int:
    M = sympy.Matrix([[sympy.Rational(Fraction(x)), sympy.Rational(Fraction(y)), 1] for x, y in (a, b, c)])
    return int(sympy.sign(M.det()))


def sympy_incircle(a, b, c, d) -> int:
    rows = []
    for x, y in (a, b, c, d):
        X, Y = sympy.Rational(Fraction(x)), sympy.Rational(Fraction(y))
        rows.append([X, Y, X * X + Y * Y, 1])
    return int(sympy.sign(sympy.Matrix(rows).det()))


def naive_orient(a, b, c) -> int:
    d = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    return (d > 0) - (d < 0)


def shewchuk_grid():
    """Shewchuk (1997), Fig. 1: p = (0.5 + i·u, 0.5 + j·u) against the line through (12, 12)
    and (24, 24); the float determinant's signs form a wrong, jagged pattern."""
    q, r = (12.0, 12.0), (24.0, 24.0)
    for i in range(0, 48, 3):
        for j in range(0, 48, 3):
            yield (0.5 + i * U, 0.5 + j * U), q, r


def test_orient2d_on_shewchuks_grid_is_exact_where_floats_are_wrong():
    triples = list(shewchuk_grid())
    wrong = sum(naive_orient(*t) != sympy_orient(*t) for t in triples)
    assert wrong > 0                      # the inputs are hard: a float evaluation fails on them
    for t in triples:
        assert O.orient2d(*t) == sympy_orient(*t), t
    A, B, C = (np.array([t[k] for t in triples]) for k in range(3))
    assert O.orient2d_signs(A, B, C).tolist() == [sympy_orient(*t) for t in triples]


def test_orient2d_rational_collinear_and_margins():
    p, q = (Fraction(1, 3), Fraction(2, 7)), (Fraction(10, 3), Fraction(-5, 11))
    for t in (Fraction(1, 2), Fraction(-7, 3), Fraction(10 ** 20, 3)):
        on = (p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1]))
        assert O.orient2d(p, q, on) == 0
        for eps in (Fraction(1, 10 ** 9), Fraction(1, 10 ** 40)):
            for s in (1, -1):
                off = (on[0], on[1] + s * eps)
                assert O.orient2d(p, q, off) == sympy_orient(p, q, off) != 0


def test_incircle_cocircular_at_utm_scale():
    """Four points of the circle x² + y² = 25 (Pythagorean), translated to UTM coordinates and
    scaled by a power of two: all exact floats, exactly co-circular; one ulp moves the fourth."""
    base = [(3, 4), (-4, 3), (-5, 0), (0, -5)]
    for scale, (ox, oy) in ((1.0, (0.0, 0.0)), (2.0 ** -20, (512000.0, 5403000.0)), (2.0 ** 30, (1e6, -3e6))):
        a, b, c, d = [(ox + scale * x, oy + scale * y) for x, y in base]
        assert O.orient2d(a, b, c) == 1
        assert O.incircle(a, b, c, d) == 0 == sympy_incircle(a, b, c, d)
        for nudge in (np.nextafter(d[1], np.inf), np.nextafter(d[1], -np.inf), d[1] + 1e-9 * max(scale, abs(d[1]))):
            e = (d[0], float(nudge))
            assert O.incircle(a, b, c, e) == sympy_incircle(a, b, c, e) != 0
    A, B, C, D = (np.array([p]) for p in base)
    assert O.incircle_signs(A, B, C, D).tolist() == [0]


@pytest.mark.parametrize("scale", [1e-200, 1e-310, 1e200, 1e300])
def test_ends_of_the_float_range(scale):
    """Differences below 2⁻²⁵⁰ (products underflow) or huge (products overflow): the exact path."""
    a, b = (0.0, 0.0), (3.0 * scale, 1.0 * scale)
    for c in ((6.0 * scale, 2.0 * scale), (6.0 * scale, np.nextafter(2.0 * scale, np.inf)), (-3.0 * scale, -1.0 * scale)):
        assert O.orient2d(a, b, c) == sympy_orient(a, b, c)
    d = (1.0 * scale, 5.0 * scale)
    assert O.incircle((3.0 * scale, 4.0 * scale), (-4.0 * scale, 3.0 * scale), (-5.0 * scale, 0.0), d) \
        == sympy_incircle((3.0 * scale, 4.0 * scale), (-4.0 * scale, 3.0 * scale), (-5.0 * scale, 0.0), d)


def test_the_filter_defers_on_degenerate_inputs_and_decides_clear_ones(monkeypatch):
    calls = []
    exact_o, exact_i = O._orient_exact, O._incircle_exact
    monkeypatch.setattr(O, "_orient_exact", lambda *a: calls.append("o") or exact_o(*a))
    monkeypatch.setattr(O, "_incircle_exact", lambda *a: calls.append("i") or exact_i(*a))
    assert O.orient2d((0.0, 0.0), (1.0, 1.0), (0.0, 1.0)) == 1
    assert O.orient2d((Fraction(0), Fraction(0)), (Fraction(1), Fraction(1)), (Fraction(0), Fraction(1))) == 1
    assert O.incircle((1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, 0.0)) == 1
    assert calls == []
    assert O.orient2d((0.0, 0.0), (1.0, 1.0), (2.0, 2.0)) == 0
    assert O.orient2d((Fraction(1, 3), Fraction(1, 3)), (Fraction(2, 3), Fraction(2, 3)), (Fraction(1), Fraction(1))) == 0
    assert O.incircle((1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)) == 0
    assert calls == ["o", "o", "i"]


def test_filtered_sign_never_decides_on_nan_or_inf():
    assert O.filtered_sign(float("nan"), 0.0, lambda: 7) == 7 and O.filtered_sign(0.0, 1.0, max, 3, 7) == 7
    assert O.filtered_sign(float("inf"), float("inf"), lambda: 7) == 7
    assert O.filtered_sign(1.0, 0.5, lambda: 7) == 1 and O.filtered_sign(-1.0, 0.5, lambda: 7) == -1


rationals = st.fractions(min_value=-10 ** 6, max_value=10 ** 6, max_denominator=10 ** 6)


@settings(max_examples=150, deadline=None)
@given(rationals, rationals, rationals, rationals, rationals, st.sampled_from([0, 1, -1]),
       st.sampled_from([Fraction(1, 10 ** 9), Fraction(1, 10 ** 30), Fraction(0)]))
def test_orient2d_near_a_line_matches_sympy(px, py, qx, qy, t, s, eps):
    p, q = (px, py), (qx, qy)
    r = (px + t * (qx - px), py + t * (qy - py) + s * eps)
    assert O.orient2d(p, q, r) == sympy_orient(p, q, r)
    fp, fq, fr = [(float(x), float(y)) for x, y in (p, q, r)]
    assert O.orient2d(fp, fq, fr) == sympy_orient(fp, fq, fr)
