"""A conjugate pair of solutions 10⁻⁶ off the real space, proved non-real in its chart
(:func:`runtime.certify.chart.certify_in_chart`), against an mpmath reference.

Three circles C₁ (centre (0, 0), radius 1/2), C₂ ((1/5, 1/10), 1/20) and C₃ ((t, −1/10), 1/10).
A circle (x, y, √R) is tangent to the circle (a, b, r) iff ((x − a)² + (y − b)² − R − r²)² =
4r²R (the product of the inner and outer tangency conditions), so the solutions (x, y, R) of the
three equations are the circles tangent to all three (eight, Apollonius).  Near t = √15/10, where
C₃ touches C₁ from inside, two solutions near (0.3205, −0.0828, 0.0285) meet: for t a little
larger they are a conjugate pair whose imaginary parts are 0.29·√(t − √15/10) (measured for
t − √15/10 from 10⁻⁸ to 10⁻³, within 1 %).  With
t = 0.387298334620742 + 12·10⁻¹² (= √15/10 + 1.2·10⁻¹¹) the pair's imaginary parts are about
(7.2·10⁻⁷, 1.0·10⁻⁶, −1.5·10⁻⁷): mpmath's ``findroot`` (40 digits) gives the reference root.

The start s is that root with its imaginary parts scaled so that the largest, Im y, is exactly
10⁻⁶ (x, y and T = x² + y² − R are below 1 in modulus: the chart is A = 1 and the nearly-real
threshold is 10⁻⁶ · 1).  A start whose imaginary part reaches the threshold is complex; Newton
in complex arithmetic from it reaches the non-real root, which the chart's Krawczyk test proves
(a box of radius ~10⁻¹⁶ whose imaginary parts exclude 0).  Treated as real, the start would lead
real Newton to a point where no real root is.
"""
from __future__ import annotations

from fractions import Fraction as F

import mpmath as mp
import numpy as np
from flint import acb, arb

from curvedvoronoi.runtime.certify.chart import certify_in_chart
from curvedvoronoi.runtime.sites.conic import Conic

T3 = F(387298334620742, 10 ** 15) + F(12, 10 ** 12)
CIRCLES = [(F(0), F(0), F(1, 2)), (F(1, 5), F(1, 10), F(1, 20)), (T3, F(-1, 10), F(1, 10))]


def _conic(a, b, r):
    return Conic.from_coefficients(1, 0, 1, -2 * a, -2 * b, a * a + b * b - r * r)


def _reference():
    """The non-real root with Im y > 0 (mpmath, 40 digits) and its residual."""
    with mp.workdps(40):
        q = [tuple(mp.mpf(v.numerator) / v.denominator for v in c) for c in CIRCLES]

        def eqs(x, y, R):
            return [((x - a) ** 2 + (y - b) ** 2 - R - r * r) ** 2 - 4 * r * r * R for a, b, r in q]
        start = (mp.mpc("0.3205474497", "7.17e-7"), mp.mpc("-0.0827649956", "1.004e-6"),
                 mp.mpc("0.0285407295", "-1.498e-7"))
        z = mp.findroot(eqs, start, maxsteps=200)
        return list(z), max(abs(e) for e in eqs(*z))


def _ball(v):
    """An acb ball holding the mpmath number v (its 35-digit decimal strings, enclosed by arb)."""
    return acb(arb(mp.nstr(v.real, 35)), arb(mp.nstr(v.imag, 35)))


def test_the_reference_root_is_not_real():
    z, res = _reference()
    assert res < 1e-30
    z = [complex(v) for v in z]
    assert 9.9e-7 < z[1].imag < 1.01e-6 and 7e-7 < z[0].imag < 7.3e-7


def test_a_start_at_the_nearly_real_threshold_is_proved_non_real():
    ref, _ = _reference()
    x, y, R = (complex(v) for v in ref)
    k = 1e-6 / y.imag
    s = np.array([complex(x.real, x.imag * k), complex(y.real, 1e-6), complex(R.real, R.imag * k)])
    u = np.array([s[0], s[1], s[0] * s[0] + s[1] * s[1] - s[2]])      # the chart point (A = 1)
    assert np.abs(u).max() < 1 and float(np.abs(u.imag).max()) == 1e-6   # exactly at the threshold
    res = certify_in_chart([_conic(*c) for c in CIRCLES], s)
    assert res is not None and res[0] == "nonreal"
    for box, v in zip(res[1], ref):
        assert box.overlaps(_ball(v)) and float(abs(box.real.rad()) + abs(box.imag.rad())) < 1e-12
