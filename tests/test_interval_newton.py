"""Krawczyk's test (runtime.certify.interval_newton) on systems whose zeros are known exactly:
it proves simple zeros (real and complex), and fails where there is no zero or no unique one."""
from __future__ import annotations

import math

import pytest
from flint import acb, arb
from hypothesis import given, settings, strategies as st

from curvedvoronoi.runtime.certify.interval_newton import KrawczykFailure, krawczyk_inflation


def circle_line(a: float):
    """x² + y² = 2, y = a·x: zeros ±(1, a)·√(2/(1 + a²))."""
    def F(z):
        x, y = z
        return [x * x + y * y - 2, y - a * x]

    def J(z):
        x, y = z
        return [[2 * x, 2 * y], [arb(-a), arb(1)]]
    return F, J


@given(st.integers(-20, 20))
@settings(max_examples=25, deadline=None)
def test_proves_the_simple_real_zero_and_encloses_it(k):
    a = k / 7
    F, J = circle_line(a)
    t = math.sqrt(2 / (1 + a * a))
    K, X = krawczyk_inflation(F, J, [arb(t * (1 + 1e-9)), arb(a * t * (1 - 1e-9))])
    T = (2 / (1 + arb(a) * arb(a))).sqrt()           # the exact zero (a is a float: exact in arb)
    assert K[0].overlaps(T) and K[1].overlaps(arb(a) * T)
    assert abs(float(K[0].mid()) - t) < 1e-13 and abs(float(K[1].mid()) - a * t) < 1e-13
    assert all(x.contains(k_) for x, k_ in zip(X, K))


def test_no_real_zero_is_not_proved():
    """x² + y² = −1 has no real zero: the test must fail, whatever the candidate."""
    def F(z):
        x, y = z
        return [x * x + y * y + 1, y - x]

    def J(z):
        x, y = z
        return [[2 * x, 2 * y], [arb(-1), arb(1)]]
    for c in (0.1, 1.0, 3.0):
        with pytest.raises(KrawczykFailure):
            krawczyk_inflation(F, J, [arb(c), arb(c)])


def test_double_zero_is_not_proved():
    """The tangent line y = 1 meets x² + y² = 1 in a double zero: no uniqueness proof."""
    def F(z):
        x, y = z
        return [x * x + y * y - 1, y - 1]

    def J(z):
        x, y = z
        return [[2 * x, 2 * y], [arb(0), arb(1)]]
    with pytest.raises(KrawczykFailure):
        krawczyk_inflation(F, J, [arb(1e-9), arb(1)])


def test_complex_zero_of_z_squared_plus_one():
    def F(z):
        return [z[0] * z[0] + 1]

    def J(z):
        return [[2 * z[0]]]
    K, X = krawczyk_inflation(F, J, [acb(1e-8, 1 + 1e-8)])
    assert K[0].contains(acb(0, 1))
    with pytest.raises(KrawczykFailure):                     # corrupted system z² − 4: no zero near i
        krawczyk_inflation(lambda z: [z[0] * z[0] - 4], J, [acb(1e-8, 1 + 1e-8)])
