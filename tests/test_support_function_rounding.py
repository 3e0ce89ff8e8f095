"""The support functions of the far field (runtime/voronoi/verify/support.py; Schneider, *Convex
Bodies*, §1.7) are float values within ``mu`` of the exact h_k(θ) = max_{p ∈ S_k} u(θ)·(p − m),
also about a new centre (:meth:`SupportTable.recentred`, used by the tails at infinity).

Reference: h of a point p is u·(p − m), of a circle of centre c and radius r is u·(c − m) + r,
evaluated with mpmath at 60 digits at the float angle θ (cos and sin of that binary number), for
sites whose data are exact binary numbers (no rounding of the input)."""
from __future__ import annotations

import mpmath
import numpy as np
import pytest

from curvedvoronoi.runtime.predicates.circles import Circle, Point
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify.support import SupportTable

SITES = [Point(3, 1), Circle.from_radius(-7, 2, 3), Point(11, -5), Circle.from_radius(0.5, 9.25, 1.5)]
DATA = [(3, 1, 0), (-7, 2, 3), (11, -5, 0), (0.5, 9.25, 1.5)]


def exact_h(k, th, m):
    with mpmath.workdps(60):
        cx, cy, r = DATA[k]
        t = mpmath.mpf(float(th))
        return mpmath.cos(t) * (cx - mpmath.mpf(float(m[0]))) + mpmath.sin(t) * (cy - mpmath.mpf(float(m[1]))) + r


@pytest.mark.parametrize("m", [None, (0.1, -0.3), (123.456, 78.9), (-1e3 / 3, 1e3 / 7)])
def test_support_values_are_within_mu_of_the_exact_support_function(m):
    sup = SupportTable([site_geometry(s) for s in SITES])
    assert sup.ok
    if m is not None:
        sup = sup.recentred(m)
    assert sup.mu > 0
    ths = np.linspace(-np.pi, np.pi, 257)[:-1] + 1e-3
    worst = 0.0
    for k in range(len(SITES)):
        hv = sup.h(k, ths)
        lo, hi = sup.h_range(k, ths, 0.0)
        for t, th in enumerate(ths):
            e = exact_h(k, th, sup.m)
            assert abs(mpmath.mpf(float(hv[t])) - e) <= sup.mu
            assert mpmath.mpf(float(lo[t])) <= e <= mpmath.mpf(float(hi[t]))
            worst = max(worst, float(abs(mpmath.mpf(float(hv[t])) - e)))
    # the float evaluation does round (so the allowance is needed), by far less than mu
    assert 0 < worst < 1e-3 * sup.mu
