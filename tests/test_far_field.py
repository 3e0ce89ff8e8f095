"""First-order far-field bounds (runtime/voronoi/verify/far_field.py) against independent distances.

References: the distance from a far point to a rotated ellipse by mpmath (dense samples of the
parametrised boundary, then findroot on d/ds of the squared distance at 40 digits), to a point in
closed form; h and h' by the closed form of the ellipse's support function written out here
(u·(c − m) + √(a²(u·e₁)² + b²(u·e₂)²) and its derivative), not the SupportTable's."""
from __future__ import annotations

import math
import random
from fractions import Fraction

import mpmath
import numpy as np

from curvedvoronoi.runtime.predicates.circles import Point
from curvedvoronoi.runtime.sites.conic import Conic
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify import far_field
from curvedvoronoi.runtime.voronoi.verify.support import SupportTable

ROT = [(Fraction(3, 5), Fraction(4, 5)), (Fraction(-5, 13), Fraction(12, 13)), (Fraction(1), Fraction(0)),
       (Fraction(8, 17), Fraction(-15, 17))]


def _ellipses(seed, n=5):
    rng = random.Random(seed)
    out = []
    for k in range(n):
        a = Fraction(rng.randint(16, 48), 16)
        b = a * Fraction(rng.randint(5, 14), 16)
        out.append((Fraction(rng.randint(-400, 400), 16), Fraction(rng.randint(-400, 400), 16), a, b, ROT[k % 4]))
    return out


def _dist_ref(e, q):
    """d(q, ellipse) at 40 digits (q far outside)."""
    cx, cy, a, b = (mpmath.mpf(x.numerator) / x.denominator for x in e[:4])
    cs, sn = (mpmath.mpf(x.numerator) / x.denominator for x in e[4])
    qx, qy = mpmath.mpf(q[0]), mpmath.mpf(q[1])

    def d2(s):
        x = cx + cs * a * mpmath.cos(s) - sn * b * mpmath.sin(s)
        y = cy + sn * a * mpmath.cos(s) + cs * b * mpmath.sin(s)
        return (x - qx) ** 2 + (y - qy) ** 2
    s0 = min((2 * mpmath.pi * i / 2000 for i in range(2000)), key=d2)
    s = mpmath.findroot(lambda s: mpmath.diff(d2, s), s0)
    return mpmath.sqrt(min(d2(s), d2(s0)))


def _h_ref(e, th, m):
    """(h, h') of the ellipse about m in the direction θ, closed form in mpmath."""
    cx, cy, a, b = (mpmath.mpf(x.numerator) / x.denominator for x in e[:4])
    cs, sn = (mpmath.mpf(x.numerator) / x.denominator for x in e[4])
    ux, uy = mpmath.cos(th), mpmath.sin(th)
    p1, p2 = ux * cs + uy * sn, -ux * sn + uy * cs          # u in the ellipse's axes
    r = mpmath.sqrt(a * a * p1 * p1 + b * b * p2 * p2)
    h = ux * (cx - m[0]) + uy * (cy - m[1]) + r
    # d/dθ: u' = u⊥, p1' = −p2, p2' = p1
    hp = -uy * (cx - m[0]) + ux * (cy - m[1]) + (b * b - a * a) * p1 * p2 / r
    return h, hp


def test_first_order_enclosure_of_the_distance_to_far_ellipses():
    """t − h + h'²/(2(t + M)) ≤ d(m + t·u, S) ≤ t − h + h'²/(2(t − W)) at far points (closed-form h,
    h'), and gap_lower(s, k) on a one-point cell lies below d_k − d_s by at most the two bounds'
    widths, W²(ρ + 2W)/(t(t − W)): it keeps the first-order terms that t − h drops."""
    mpmath.mp.dps = 40
    for seed in (1, 2):
        els = _ellipses(seed)
        sites = [Conic.ellipse(centre=(cx, cy), axes=(a, b), rotation=rot) for cx, cy, a, b, rot in els]
        sup = SupportTable([site_geometry(s) for s in sites])
        rng = random.Random(seed)
        for _ in range(10):
            s, k = rng.sample(range(len(els)), 2)
            th = rng.uniform(-math.pi, math.pi)
            t = sup.W * rng.choice([3.0, 30.0, 300.0])
            q = sup.m + t * np.array([math.cos(th), math.sin(th)])
            d = {}
            for x in (s, k):
                d[x] = _dist_ref(els[x], q)
                h, hp = _h_ref(els[x], th, sup.m)
                excess = float(d[x] - t + h)          # d − (t − h) ∈ [h'²/(2(t + M)), h'²/(2(t − W))]
                a2, M = float(hp) ** 2, float(sup.rcurv[x] + sup.W)
                assert a2 / (2 * (t + M)) - 1e-25 <= excess <= a2 / (2 * (t - sup.W)) + 1e-25
            lo = float(far_field.gap_lower(sup, s, k, th, 0.0, t, t))
            true = float(d[k] - d[s])
            width = sup.W ** 2 * (float(sup.rcurv.max()) + 2 * sup.W) / (t * (t - sup.W))
            assert lo <= true <= lo + width + 8 * sup.mu, (seed, s, k, th, t, lo, true)


def _three_points(delta):
    """p0 = (0, 0), p1 = (0, 2), p2 = (δ, 6): p0, p1 tie at infinity in the direction −x, p2 lies
    δ behind their common supporting line x = 0."""
    return [Point(Fraction(0), Fraction(0)), Point(Fraction(0), Fraction(2)), Point(Fraction(delta), Fraction(6))]


def _cell(sup, t0, t1, y0, y1):
    """The cell of points m + t·u(θ) with t ∈ [t0, t1] and θ between the directions of (−t0, y0)
    and (−t0, y1) from m (y lateral offsets near the bisector y = 1 of p0, p1)."""
    th0 = math.atan2(y0 - sup.m[1], -t0 - sup.m[0])
    th1 = math.atan2(y1 - sup.m[1], -t0 - sup.m[0])
    thc, half = 0.5 * (th0 + th1), 0.5 * abs(th1 - th0)
    return thc, half


def test_a_third_point_behind_the_tie_line_is_proved_farther_only_to_first_order():
    """On the bisector y = 1 of p0, p1 (x → −∞), d_2 − d_0 = √((x − δ)² + 25) − √(x² + 1) ≈ δ + 12/t,
    while the support gap h_0 − h_2 ≈ δ − 6/t is negative for t < 6/δ: the zeroth-order bound cannot
    prove p2 farther there, the first-order one does; and it never exceeds the true gap on the cell."""
    delta = Fraction(1, 1000)
    # about p0, as the tail prover centres its sector on a leading site's normal line (h_0' = 0)
    sup = SupportTable([site_geometry(p) for p in _three_points(delta)]).recentred(np.zeros(2))
    for t0 in (50.0, 400.0, 3000.0):
        t1 = t0 * 1.25
        thc, half = _cell(sup, t0, t1, 0.5, 1.5)
        lo = float(far_field.gap_lower(sup, 0, 2, thc, half, t0, t1))
        zeroth = float(sup.h_range(0, thc, half)[0] - sup.h_range(2, thc, half)[1]
                       - float(sup.hp_abs(0, thc, half)) ** 2 / (2 * (t0 - sup.W)))
        # the true d_2 − d_0 on the cell (dense samples, closed form for points)
        T, TH = np.meshgrid(np.linspace(t0, t1, 60), np.linspace(thc - half, thc + half, 60))
        X, Y = sup.m[0] + T * np.cos(TH), sup.m[1] + T * np.sin(TH)
        true = np.hypot(X - float(delta), Y - 6) - np.hypot(X, Y)
        assert lo <= true.min()
        assert lo > 0 > zeroth, (t0, lo, zeroth)


def test_a_third_point_ahead_of_the_tie_line_is_never_proved_farther():
    """p2 moved δ ahead of the line (x = −δ): far out on y = 1 it is nearer than p0 (d_2 − d_0 → −δ
    as t → ∞); the bound must stay below the true gap, so it is negative on the infinite cell."""
    sup = SupportTable([site_geometry(p) for p in _three_points(Fraction(-1, 1000))]).recentred(np.zeros(2))
    thc, half = _cell(sup, 1e5, 1e5, 0.5, 1.5)
    assert float(far_field.gap_lower(sup, 0, 2, thc, half, 1e5, np.inf)) < 0
    thc, half = _cell(sup, 1e6, 1e6, 0.5, 1.5)
    assert float(far_field.gap_lower(sup, 0, 2, thc, half, 1e6, 2e6)) < 0
