"""Rigorous distance bounds of many (point, site) rows at once (runtime/voronoi/site_arrays.SiteArrays.
dist_bounds, which the construction's emptiness proofs use: runtime/voronoi/vertex_emptiness.py).

Reference independent of the code: d(q, C) for the exact rational conic C, the least critical value
of |p − q|² on C (thesis §5.2: the foot points, where q − p is normal to C), solved by mpmath at 40
digits on the exact equations f(p) = 0, (p − q) × ∇f(p) = 0 from the nearest of 4000 points of the
ellipse.  Rows mix ellipses, circles and points, and query points outside, inside (where the
supporting line proves nothing) and on the major axis inside, next to the evolute."""
from __future__ import annotations

import math
from fractions import Fraction

import mpmath
import numpy as np

import curvedvoronoi as cv
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.site_arrays import SiteArrays
from scenes import random_ellipses


def _mp(v):
    """An exact rational (Fraction or flint fmpq) as an mpmath number."""
    v = Fraction(str(v))
    return mpmath.mpf(v.numerator) / v.denominator


def _distance(site, g, x, y):
    """d((x, y), site) to ~1e-30 (exact coefficients; the float frame only seeds the root)."""
    q = (mpmath.mpf(x), mpmath.mpf(y))
    if getattr(site, "r2", None) is not None:                     # a circle or a point
        cx, cy, r2 = (_mp(v) for v in (site.cx, site.cy, site.r2))
        return abs(mpmath.hypot(q[0] - cx, q[1] - cy) - mpmath.sqrt(r2))
    a, b, c, d, e, f = (_mp(v) for v in site.coefficients)
    t = np.linspace(0, 2 * math.pi, 4000, endpoint=False)
    X, Y = g.a * np.cos(t), g.b * np.sin(t)
    P = np.column_stack([g.tx + g.c * X - g.s * Y, g.ty + g.s * X + g.c * Y])
    best = None
    for k in np.argsort(np.hypot(P[:, 0] - x, P[:, 1] - y))[:3]:
        def eqs(u, v):
            fx, fy = 2 * a * u + b * v + d, b * u + 2 * c * v + e
            return [a * u * u + b * u * v + c * v * v + d * u + e * v + f, (u - q[0]) * fy - (v - q[1]) * fx]
        u, v = mpmath.findroot(eqs, (mpmath.mpf(P[k, 0]), mpmath.mpf(P[k, 1])))
        dist = mpmath.hypot(u - q[0], v - q[1])
        best = dist if best is None or dist < best else best
    return best


def test_bounds_of_mixed_rows_hold_the_exact_distances():
    sites = list(random_ellipses(6, 2)) + [cv.Circle.from_radius(40, 40, 3), cv.Circle.from_radius(-40, 35, 0)]
    geoms = [site_geometry(s) for s in sites]
    S = SiteArrays(sites, geoms)
    assert not S.all_circles
    rng = np.random.default_rng(11)
    rows, lab = [], []
    for k, g in enumerate(geoms):
        if hasattr(g, "a"):
            cx, cy, r = g.tx, g.ty, g.a
            # outside, inside, and on the major axis inside next to the centre of curvature
            pts = [(cx + 3 * r * math.cos(w), cy + 3 * r * math.sin(w)) for w in rng.uniform(0, 2 * math.pi, 4)]
            pts += [(cx + 0.3 * g.b * math.cos(w), cy + 0.3 * g.b * math.sin(w)) for w in rng.uniform(0, 2 * math.pi, 3)]
            e = (g.a * g.a - g.b * g.b) / g.a * 0.999
            pts += [(cx + e * g.c, cy + e * g.s)]
        else:
            pts = [(x, y) for x, y in rng.uniform(-60, 60, (4, 2))]
        for p in pts:
            for j in (k, (k + 1) % len(sites)):
                rows.append(p)
                lab.append(j)
    P, lab = np.array(rows), np.array(lab)
    lo, hi = S.dist_bounds(P, lab)
    with mpmath.workdps(40):
        for (x, y), j, l_, h_ in zip(P.tolist(), lab.tolist(), lo.tolist(), hi.tolist()):
            dist = _distance(sites[j], geoms[j], x, y)
            assert l_ <= dist <= h_, (j, x, y, l_, float(dist), h_)
            assert h_ - l_ <= 1e-9 * (1 + float(dist)), (j, x, y, l_, h_)
