"""(T4) of the strip test decided from the piece's centre (runtime/voronoi/verify/strips.py,
``_sides_from_centre`` and ``_sides_centre_second_order``), against closed-form distances.

A piece of a chain of strips passes (T4) when σ·f > 0 on its lateral side +w and σ·f < 0 on its
side −w (f = d_i − d_j): the bisector β crosses the piece between its sides.  Both centre routes
bound ς·f on a whole side from the values at the centre C only, to first order (the gradient
enclosures on the disc B(C, R)) or to second order (point enclosures at C and 0 ≤ ∇²d ≤ 1/d off a
convex set).  The route from each side's midpoint (``_sides_at_midpoints``), to which the centre
routes now leave the hard pieces, is checked on the same pieces.

The pieces are drawn around β of a point and a circle (a hyperbola branch), of two points (a
line), and of a point and a circle of radius 10⁴ below it (where f'' = 1/d across β, so the
curvature bound is tight): tilted off β's tangent and shifted off β by random amounts, so that β
crosses a side on 10–30 % of them, and long enough (half-length up to d/4) that β's curvature and
the gradients' turn over the disc decide.  Expectation from closed forms, not from the verifier:
d = |q − p| for a point and |q − c| − r outside a circle, in mpmath at 40 digits; a side is checked
at 201 points.  Every side accepted has the wanted sign at every sample, and each route accepts a
good share of the pieces β does not cross, so that the check is not vacuous.  Without the disc
term (s_i + s_j)·R of the first route, or with the curvature term R²/(2(m − R)) of the second
halved, pieces whose side β crosses are accepted.
"""
import math

import mpmath
import numpy as np
import pytest

import curvedvoronoi as cv
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify import strips
from curvedvoronoi.runtime.voronoi.verify.site_table import SiteTable, gradient_enclosure

mpmath.mp.dps = 40


def exact_f(q, sites):
    """d_i − d_j at q (mpmath): sites are ("point", x, y) or ("circle", x, y, r)."""
    out = []
    for s in sites:
        d = mpmath.sqrt((mpmath.mpf(q[0]) - s[1]) ** 2 + (mpmath.mpf(q[1]) - s[2]) ** 2)
        out.append(d - s[3] if s[0] == "circle" else d)
    return out[0] - out[1]


def float_grad_f(q, sites):
    g = []
    for s in sites:
        v = np.array([q[0] - s[1], q[1] - s[2]])
        g.append(v / np.hypot(*v))
    return g[0] - g[1]


def on_bisector(x, u, sites):
    """A point of β on the line x + t·u (bisection in mpmath on a bracket found in floats)."""
    ts = np.linspace(-30, 30, 601)
    vals = [exact_f(x + t * u, sites) for t in ts]
    for a, b, fa, fb in zip(ts[:-1], ts[1:], vals[:-1], vals[1:]):
        if fa * fb < 0:
            a, b = mpmath.mpf(a), mpmath.mpf(b)
            for _ in range(80):
                m = (a + b) / 2
                if exact_f((float(x[0]) + m * float(u[0]), float(x[1]) + m * float(u[1])), sites) * fa > 0:
                    a = m
                else:
                    b = m
            t = float((a + b) / 2)
            return x + t * u
    return None


def scene(rng, kind):
    pi = rng.uniform(-3, 3, 2)
    if kind == "circle":
        c = rng.uniform(-3, 3, 2)
        while np.hypot(*(c - pi)) < 3:
            c = rng.uniform(-3, 3, 2)
        r = rng.uniform(0.5, 1.5)
        return [("point", *pi), ("circle", *c, r)], [cv.Point(*pi), cv.Circle(c[0], c[1], r * r)]
    if kind == "line":       # a point above a circle of radius 10⁴: f'' = 1/d across, the curvature bound is tight
        gap, r = rng.uniform(1, 3), 1e4
        return ([("point", *pi), ("circle", pi[0], pi[1] - gap - r, r)],
                [cv.Point(*pi), cv.Circle(pi[0], pi[1] - gap - r, r * r)])
    pj = rng.uniform(-3, 3, 2)
    while np.hypot(*(pj - pi)) < 2:
        pj = rng.uniform(-3, 3, 2)
    return [("point", *pi), ("point", *pj)], [cv.Point(*pi), cv.Point(*pj)]


def distance(q, s):
    d = math.hypot(q[0] - s[1], q[1] - s[2])
    return d - s[3] if s[0] == "circle" else d


def pieces_around_bisector(rng, sites, n):
    """n pieces (one segment each, of length 2·half) near β: (chains, lengths, sigma)."""
    S, T, N, W, slope, sig, L = [], [], [], [], [], [], []
    mid = 0.5 * (np.array(sites[0][1:3]) + np.array(sites[1][1:3]))
    if sites[1][0] == "circle" and sites[1][3] > 100:
        mid = np.array(sites[0][1:3]) - np.array([0.0, 0.5 * (sites[0][2] - sites[1][2] - sites[1][3])])
    while len(S) < n:
        ang = rng.uniform(0, 2 * np.pi)
        B = on_bisector(mid + rng.normal(size=2) * 3, np.array([math.cos(ang), math.sin(ang)]), sites)
        if B is None:
            continue
        d = min(distance(B, s) for s in sites)
        g = float_grad_f(B, sites)
        tb = np.array([-g[1], g[0]]) / np.hypot(*g)
        half = d * math.exp(rng.uniform(math.log(0.005), math.log(0.25)))
        w = half * math.exp(rng.uniform(math.log(0.01), math.log(0.3)))
        tilt = rng.uniform(-1, 1) * 0.6 * w / half
        t = np.array([math.cos(tilt) * tb[0] - math.sin(tilt) * tb[1], math.sin(tilt) * tb[0] + math.cos(tilt) * tb[1]])
        nn = np.array([-t[1], t[0]])
        C = B + rng.uniform(-0.9, 0.9) * w * nn
        sl = rng.uniform(-0.2, 0.2) * w / half
        S.append(C - half * t)
        T.append(t)
        N.append(nn)
        W.append(w - sl * half)
        slope.append(sl)
        L.append(2 * half)
        sig.append(1.0 if (g * nn).sum() > 0 else -1.0)
    chains = (np.arange(n), np.array(S), np.array(T), np.array(N), np.array(W), np.array(slope),
              np.zeros(n, int), np.ones(n, int))
    return chains, np.array(L), np.array(sig)


def side_signs(P, slope, sigma, t, sites, sg):
    """min over 201 points of side sg of ς·f (ς = sg·σ), exact."""
    ts = P.Tn[t] + sg * slope[P.seg[t]] * P.Nn[t]
    ts = ts / np.hypot(*ts)
    worst = None
    for tau in np.linspace(-P.side_len[t], P.side_len[t], 201):
        q = P.C[t] + sg * P.ws[t] * P.Nn[t] + tau * ts
        v = sg * sigma[P.jb[t]] * exact_f(q, sites)
        worst = v if worst is None or v < worst else worst
    return worst


@pytest.mark.parametrize("kind,seed", [("circle", 0), ("circle", 1), ("points", 2), ("line", 3), ("line", 4)])
def test_sides_accepted_from_the_centre_hold_on_every_sample(kind, seed):
    rng = np.random.default_rng(seed)
    sites, objs = scene(rng, kind)
    table = SiteTable([site_geometry(s) for s in objs], 20.0)
    n = 120
    chains, L, sigma = pieces_around_bisector(rng, sites, n)
    P = strips._pieces(table.scale, np.arange(n), np.zeros(n), L, chains)
    Vi = strips.evaluate_rows(table, P.C, np.zeros(n, int))
    Vj = strips.evaluate_rows(table, P.C, np.ones(n, int))
    enc_i = gradient_enclosure(P.C, Vi, P.R, table.scale)
    enc_j = gradient_enclosure(P.C, Vj, P.R, table.scale)
    slope = chains[5]
    first = strips._sides_from_centre(slope, sigma, P, enc_i, enc_j, Vi, Vj)
    second = strips._sides_centre_second_order(table.scale, slope, sigma, P, np.arange(n), Vi, Vj)
    at_mid = strips._sides_at_midpoints(table, table.scale, slope, sigma, P, np.arange(n))
    clear = 0
    for t in range(n):
        worst = min(side_signs(P, slope, sigma, t, sites, 1.0), side_signs(P, slope, sigma, t, sites, -1.0))
        if first[t] or second[t] or at_mid[t]:
            assert worst > 0, (kind, seed, t, float(worst), bool(first[t]), bool(second[t]), bool(at_mid[t]))
        clear += worst > 0
    assert 0.25 * n < clear < 0.9 * n          # both kinds of piece are drawn
    assert second.sum() >= 0.3 * clear         # the second-order route decides many clear pieces
    assert first.sum() >= 0.1 * clear
    assert at_mid.sum() >= 0.3 * clear         # the midpoint route, where the centre routes fail
