"""SupportTable (runtime/voronoi/verify/support.py): h_k, h_k' and the enclosure h_range of the
support functions of points, circles and rotated ellipses, against an independent reference:
h(θ) = max over the parametrised boundary p(t) of u(θ)·(p(t) − m), maximised with mpmath
(dense samples, then findroot on d/dt at 40 digits), and h'(θ) by mpmath's numerical derivative
of that maximum (Schneider, Convex Bodies, §1.7: h' is the component of the support point along u⊥)."""
from __future__ import annotations

import math
import random
from fractions import Fraction

import mpmath
import numpy as np

from curvedvoronoi.runtime.sites.conic import Conic
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify.support import SupportTable
from curvedvoronoi.runtime.predicates.circles import Circle, Point


def _sites():
    return [Conic.ellipse(centre=(Fraction(3), Fraction(-2)), axes=(Fraction(5, 2), Fraction(3, 4)),
                          rotation=(Fraction(3, 5), Fraction(4, 5))),
            Conic.ellipse(centre=(Fraction(-7), Fraction(4)), axes=(Fraction(2), Fraction(19, 10)),
                          rotation=(Fraction(-5, 13), Fraction(12, 13))),
            Circle.from_radius(1, 6, Fraction(3, 2)), Point(Fraction(-4), Fraction(-5))]


def _boundary(k):
    """p(t) of site k in mpmath (the data of _sites, exactly)."""
    if k == 0:
        c, (a, b), (cs, sn) = (3, -2), (mpmath.mpf(5) / 2, mpmath.mpf(3) / 4), (mpmath.mpf(3) / 5, mpmath.mpf(4) / 5)
    elif k == 1:
        c, (a, b), (cs, sn) = (-7, 4), (2, mpmath.mpf(19) / 10), (-mpmath.mpf(5) / 13, mpmath.mpf(12) / 13)
    elif k == 2:
        c, (a, b), (cs, sn) = (1, 6), (mpmath.mpf(3) / 2, mpmath.mpf(3) / 2), (1, 0)
    else:
        c, (a, b), (cs, sn) = (-4, -5), (0, 0), (1, 0)
    return lambda t: (c[0] + cs * a * mpmath.cos(t) - sn * b * mpmath.sin(t),
                      c[1] + sn * a * mpmath.cos(t) + cs * b * mpmath.sin(t))


def _h_ref(k, th, m):
    p = _boundary(k)
    ux, uy = mpmath.cos(th), mpmath.sin(th)
    f = lambda t: ux * (p(t)[0] - m[0]) + uy * (p(t)[1] - m[1])
    t0 = max((2 * mpmath.pi * i / 720 for i in range(720)), key=f)
    if k == 3:
        return f(0)
    t = mpmath.findroot(lambda t: mpmath.diff(f, t), t0)
    return f(t)


def test_h_hp_and_range_against_mpmath():
    mpmath.mp.dps = 40
    sup = SupportTable([site_geometry(s) for s in _sites()])
    m = [mpmath.mpf(float(x)) for x in sup.m]
    rng = random.Random(5)
    for k in range(4):
        for _ in range(6):
            th = rng.uniform(-math.pi, math.pi)
            ref = _h_ref(k, mpmath.mpf(th), m)
            dref = mpmath.diff(lambda s: _h_ref(k, s, m), mpmath.mpf(th))
            assert abs(float(sup.h(k, th)) - float(ref)) <= sup.mu
            assert abs(float(sup.hp(k, th)) - float(dref)) <= sup.mu + 1e-9
            # the enclosure on [θ − δ, θ + δ] holds the reference at its ends and centre, and is
            # second-order tight (not the crude W·δ) for a small δ
            for half in (1e-3, 0.05):
                lo, hi = sup.h_range(k, th, half)
                for s in (-half, 0.0, half):
                    v = float(_h_ref(k, mpmath.mpf(th + s), m))
                    assert float(lo) <= v <= float(hi)
            lo, hi = sup.h_range(k, th, 1e-3)
            second = abs(float(dref)) * 1e-3 + 0.5 * (sup.rcurv[k] + sup.W) * 1e-6
            assert float(hi - lo) <= 2 * min(second * (1 + 1e-9) + 2 * sup.mu * 1e-3, sup.W * 1e-3) + 3 * sup.mu


def test_vectorised_rows_match_scalar_calls():
    """k as a column against θ as a row (the tails' (site, cell) arrays) equals the scalar calls."""
    sup = SupportTable([site_geometry(s) for s in _sites()])
    ks = np.arange(4)[:, None]
    th = np.linspace(-3, 3, 7)[None, :]
    H, Hp = sup.h(ks, th), sup.hp(ks, th)
    lo, hi = sup.h_range(ks, th, np.full((1, 7), 0.01))
    for k in range(4):
        for c in range(7):
            assert H[k, c] == sup.h(k, th[0, c]) and Hp[k, c] == sup.hp(k, th[0, c])
            assert (lo[k, c], hi[k, c]) == tuple(float(x) for x in sup.h_range(k, th[0, c], 0.01))
