"""Krawczyk's ε-inflation (runtime/certify/interval_newton.py, ``krawczyk_inflation``) on a zero whose
proof needs a radius in a narrow window, computed by hand.

f(x) = x² − 14160 at the candidate m = 120, with the Jacobian enclosure J(X) = 2X + [−ε, ε]·240,
ε = 81/100 (a valid, deliberately loose enclosure of f' = 2x: it contains 2x for every x in X).
Then Y = 1/240, Y f(m) = (14400 − 14160)/240 = 1 exactly, and on X = m + [−r, r]

    I − Y J(X) = −[−r, r]/120 + [−ε, ε],   K(X) − m = −1 + (I − Y J(X))·[−r, r] ⊂ −1 + [−w, w],
    w = r²/120 + ε r,

so K(X) ⊂ int X exactly when 1 + ε r + r²/120 < r, i.e. r² − 22.8 r + 120 < 0:
r ∈ (r₋, r₊) = (11.4 − √9.96, 11.4 + √9.96) ≈ (8.244, 14.556).  The schedule of the module
docstring starts at 4|Y f(m)| = 4 and goes on with max(2|K − m|, 2r): |K − m| = 1 + 3.24 + 16/120
≈ 4.373 at r = 4, so the second radius is ≈ 8.747, inside the window.  Plain doubling
(4, 8, 16, …) jumps over it, and so does an inflation by 4|K − m| (≈ 17.49) or by 4r (16).
"""
from __future__ import annotations

import math
from fractions import Fraction

import pytest
from flint import arb, fmpq

from curvedvoronoi.runtime.certify.interval_newton import KrawczykFailure, krawczyk_inflation

M, A, EPS = 120, 14160, Fraction(81, 100)


def _f(z):
    return [z[0] * z[0] - A]


def _j(z):
    return [[2 * z[0] + arb(0, arb(fmpq(EPS.numerator, EPS.denominator)) * 2 * M)]]


def _proves(r: float) -> bool:
    """1 + ε r + r²/120 < r (module docstring), in exact rationals."""
    q = Fraction(r)
    return 1 + EPS * q + q * q / 120 < q


def test_the_window_of_radii_is_narrow():
    """The closed form above: the window (r₋, r₊) holds the schedule's second radius but no power of
    two times the first radius, nor 4|K − m| at r = 4."""
    lo, hi = 11.4 - math.sqrt(9.96), 11.4 + math.sqrt(9.96)
    assert 8.24 < lo < 8.25 and 14.55 < hi < 14.56
    assert not any(_proves(4.0 * 2 ** k) for k in range(6))
    second = 2 * (1 + float(EPS) * 4 + 16 / 120)
    assert _proves(second) and not _proves(2 * second)


def test_the_inflation_follows_the_image_into_a_narrow_window():
    """krawczyk_inflation proves the zero √14160 ≈ 118.996 of f with the loose Jacobian enclosure
    (the radius max(2|K − m|, 2r) lands in the window); the enclosure holds √14160 and the uniqueness
    box lies in m + (−r₊, r₊)."""
    try:
        K, X = krawczyk_inflation(_f, _j, [arb(M)])
    except KrawczykFailure as exc:                       # pragma: no cover - the failure under test
        pytest.fail(f"the zero of x² − {A} near {M} was not proved: {exc}")
    root = arb(A).sqrt()
    assert K[0].overlaps(root) and X[0].contains(K[0])
    assert (X[0] - M).abs_upper() < 14.556
    lo, hi = K[0].lower(), K[0].upper()
    assert lo * lo <= A <= hi * hi and lo > 0


def test_a_component_already_inside_keeps_growing_with_the_others():
    """Two unknowns: f₁ = x₁² − 10⁶ at its exact zero m₁ = 1000 and f₂ = f above, with the loose
    enclosure J₁₂ = [−c, c]·2000 (c = 1/10; the true ∂f₁/∂x₂ is 0) and a first radius r₁ ≥ 1
    (``floor``).  Y = diag(1/2000, 1/240), Y f(m) = (0, 1), and

        K₁ − m₁ ⊂ ±(r₁²/1000 + c r₂),   K₂ − m₂ as in the module docstring.

    At r = (1, 4): |K₁ − m₁| ≤ 0.401 < 1 (inside) while the second component is not.  The schedule
    doubles r₁ to 2 and takes r₂ = 2|K₂ − m₂| ≈ 8.747; then 0.004 + 0.875 < 2 and the second
    component is in its window: proved.  Shrinking r₁ to the image (2·0.401 = 0.802) would leave
    K₁ outside, since 0.875 > 0.802."""
    c = arb(fmpq(1, 10))

    def f(z):
        return [z[0] * z[0] - 10 ** 6, z[1] * z[1] - A]

    def j(z):
        return [[2 * z[0], arb(0, c * 2000)],
                [arb(0), 2 * z[1] + arb(0, arb(fmpq(EPS.numerator, EPS.denominator)) * 2 * M)]]

    cq = Fraction(1, 10)
    w1 = lambda r1, r2: r1 * r1 / 1000 + cq * r2         # the bound on |K₁ − m₁| above
    assert w1(1, 4) < 1                                  # attempt 0: K₁ inside
    r2 = 2 * (1 + EPS * 4 + Fraction(16, 120))           # ≈ 8.747, in the window of f₂
    assert _proves(float(r2)) and w1(2, r2) < 2          # attempt 1 with r₁ doubled: proved
    assert w1(2 * w1(1, 4), r2) > 2 * w1(1, 4)           # with r₁ = 2|K₁ − m₁|: not
    try:
        K, X = krawczyk_inflation(f, j, [arb(1000), arb(M)], floor=[arb(1), arb(0)])
    except KrawczykFailure as exc:                       # pragma: no cover - the failure under test
        pytest.fail(f"the zero (1000, √{A}) was not proved: {exc}")
    assert K[0].contains(1000) and K[1].overlaps(arb(A).sqrt())
    lo, hi = K[1].lower(), K[1].upper()
    assert lo * lo <= A <= hi * hi
