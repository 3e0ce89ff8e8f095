"""The charts tried for a start whose T = x² + y² − R dominates
(:func:`runtime.certify.chart.certify_in_chart`), against an mpmath reference.

Circles C₁ ((7/2, −9/4), 11/4), C₂ ((11/4, 1/4), 3/4), C₃ ((−15/4, 11/4), 5/4).  A circle
(x, y, √R) is tangent to (a, b, r) iff ((x − a)² + (y − b)² − R − r²)² = 4r²R; one of the eight
solutions is the large circle about (55.57, 120.89) with R ≈ 17146.69 (radius ≈ 130.9), found by
mpmath's ``findroot`` (40 digits) below.  There T = x² + y² − R ≈ 555.9: it cancels two digits of
R, so a start whose R is 1 % off has T off by 31 % (T ≈ 384.4 instead of 555.9), larger than
max(1, |x|, |y|) = |y|.  Newton in the chart ŷ = 1 (coordinates (1/y, x/y, T/y)) from there does
not converge to a zero the Krawczyk test proves; the chart T̂ = 1 (coordinates (1/T, x/T, y/T)),
tried second because |T| is the largest, does: the proved real box must hold the reference.
"""
from __future__ import annotations

from fractions import Fraction as F

import mpmath as mp
import numpy as np
from flint import arb

from curvedvoronoi.runtime.certify.chart import certify_in_chart
from curvedvoronoi.runtime.sites.conic import Conic

CIRCLES = [(F(7, 2), F(-9, 4), F(11, 4)), (F(11, 4), F(1, 4), F(3, 4)), (F(-15, 4), F(11, 4), F(5, 4))]


def _reference():
    with mp.workdps(40):
        q = [tuple(mp.mpf(v.numerator) / v.denominator for v in c) for c in CIRCLES]

        def eqs(x, y, R):
            return [((x - a) ** 2 + (y - b) ** 2 - R - r * r) ** 2 - 4 * r * r * R for a, b, r in q]
        z = mp.findroot(eqs, (mp.mpf("55.5686"), mp.mpf("120.8894"), mp.mpf("17146.69")))
        return list(z), max(abs(e) for e in eqs(*z))


def test_a_start_with_r_one_percent_off_is_proved_in_the_t_chart():
    ref, res = _reference()
    assert res < 1e-25
    x, y, R = (float(v) for v in ref)
    s = np.array([x, y, 1.01 * R], dtype=complex)
    T = x * x + y * y - 1.01 * R
    assert abs(T) > max(1.0, abs(x), abs(y))                  # T dominates at the start
    out = certify_in_chart([Conic.from_coefficients(1, 0, 1, -2 * a, -2 * b, a * a + b * b - r * r)
                            for a, b, r in CIRCLES], s)
    assert out is not None and out[0] == "real"
    for box, v in zip(out[1], ref):
        assert box.overlaps(arb(mp.nstr(v, 35))) and float(box.rad()) < 1e-9 * abs(float(v))
