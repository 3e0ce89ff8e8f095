"""Euclidean distance from a point to a conic: float foot points and rigorous enclosures.

The distance d(q, C) = min over p ∈ C of |q − p| is the function whose equalities define the
Voronoi diagram of the sites (thesis §5.1–5.2; a Voronoi vertex q has
d(q, C1) = d(q, C2) = d(q, C3)).  Its critical points ("foot points") are the points of C
where q − p is normal to C (thesis §5.2, the normal condition behind Thm 5.2.2).

Float route (:func:`foot_points`, :func:`distance`): in the canonical frame (see
:mod:`runtime.sites.conic`) the normal condition is a univariate polynomial in a parameter that
covers the whole curve:

* ellipse  (a cos θ, b sin θ): quartic in u = tan(θ/2) (θ = π added as a seed);
* hyperbola (σ a √(1 + s²/B), s), σ = ±1: quartic in s = Y (both branches);
* parabola (s²/2p, s): cubic s³ + 2p(p − X0) s − 2p² Y0;
* circle: closed form.

Roots come from ``numpy.roots``; every root with small imaginary part and the curve's
vertices are polished by Newton's method on the derivative of the squared distance in the
smooth parameter, so points on the axes, at the centre and near the evolute are handled.

The rigorous enclosures are in :mod:`runtime.sites.distance_ball`.
"""
from __future__ import annotations

import math

import numpy as np

from .conic import Conic
from ..result import InvalidConicError

__all__ = ["canonical_foot_points", "closest_point", "distance", "foot_points"]


# =========================================================================== float route

def _real_roots(coeffs: list[float], tol: float = 1e-6) -> list[float]:
    c = np.asarray(coeffs, dtype=float)
    nz = np.flatnonzero(np.abs(c) > 0)
    if nz.size == 0:
        return []
    c = c[nz[0]:]
    if c.size <= 1:
        return []
    # scale to avoid overflow in the companion matrix
    c = c / np.max(np.abs(c))
    r = np.roots(c)
    out = []
    for z in r:
        if abs(z.imag) <= tol * (1.0 + abs(z.real)) ** 1:
            out.append(float(z.real))
    return out


def _newton(fun, t0: float, iters: int = 60):
    """Newton on fun(t) -> (g, g') with step control; returns (t, |g|)."""
    t = t0
    g, dg = fun(t)
    for _ in range(iters):
        if g == 0.0 or dg == 0.0 or not math.isfinite(dg):
            break
        step = g / dg
        tn = t - step
        gn, dgn = fun(tn)
        if not math.isfinite(gn):
            break
        # accept only if the residual does not grow too much (keeps us in the basin)
        if abs(gn) > 2.0 * abs(g) and abs(step) > 1e-12 * (1.0 + abs(t)):
            tn = t - 0.5 * step
            gn, dgn = fun(tn)
            if abs(gn) > abs(g):
                break
        if abs(tn - t) <= 4e-16 * (1.0 + abs(t)):
            t, g, dg = tn, gn, dgn
            break
        t, g, dg = tn, gn, dgn
    return t, abs(g)


def _canonical_point(conic: Conic, x: float, y: float):
    fr = conic.frame
    X0, Y0 = fr.to_canonical(float(x), float(y))
    return fr, X0, Y0


def canonical_foot_points(kind: str, params: dict, X0: float, Y0: float, all_candidates: bool = False):
    """Critical points of the squared distance from (X0, Y0) to the canonical conic.

    Returns a list of (X, Y, residual_ok).  With ``all_candidates`` the non-converged
    candidates (still points of the curve) are returned too, flagged False.
    """
    if kind == "circle":
        r = math.sqrt(params["r2"])
        n = math.hypot(X0, Y0)
        if n == 0.0:
            return [(r, 0.0, True)]  # every point is a foot point; one representative
        return [(r * X0 / n, r * Y0 / n, True), (-r * X0 / n, -r * Y0 / n, True)]

    if kind == "ellipse":
        A, B = params["A2"], params["B2"]
        L = math.sqrt(max(A, B))
        A, B, x0, y0 = A / L ** 2, B / L ** 2, X0 / L, Y0 / L
        a, b = math.sqrt(A), math.sqrt(B)
        scale = abs(B - A) + a * abs(x0) + b * abs(y0) + 1e-300

        def g(th):
            s, c = math.sin(th), math.cos(th)
            return ((B - A) * s * c + a * x0 * s - b * y0 * c,
                    (B - A) * (c * c - s * s) + a * x0 * c + b * y0 * s)

        coeffs = [b * y0, 2 * (a * x0 - (B - A)), 0.0, 2 * (a * x0 + (B - A)), -b * y0]
        seeds = [2 * math.atan(u) for u in _real_roots(coeffs)]
        seeds += [0.0, math.pi / 2, math.pi, 1.5 * math.pi, math.atan2(y0 / b, x0 / a)]
        pts = []
        for th0 in seeds:
            th, res = _newton(g, th0)
            th = math.remainder(th, 2 * math.pi)
            pts.append((th, res <= 1e-9 * scale))
        uniq: list[tuple[float, bool]] = []
        for th, ok in sorted(pts, key=lambda t: (not t[1], t[0])):
            if not ok and not all_candidates:
                continue
            if any(abs(math.remainder(th - u, 2 * math.pi)) < 1e-9 for u, _ in uniq):
                continue
            uniq.append((th, ok))
        return [(L * a * math.cos(th), L * b * math.sin(th), ok) for th, ok in uniq]

    if kind == "hyperbola":
        A, B = params["A2"], params["B2"]
        L = math.sqrt(max(A, B))
        A, B, x0, y0 = A / L ** 2, B / L ** 2, X0 / L, Y0 / L
        a = math.sqrt(A)
        k = A + B
        coeffs = [k * k, -2 * k * B * y0, B * B * y0 * y0 + B * k * k - A * B * x0 * x0,
                  -2 * k * B * B * y0, B ** 3 * y0 * y0]
        seeds = _real_roots(coeffs) + [0.0, y0, y0 * B / k]
        scale = 1.0 + abs(x0) + abs(y0)
        uniq2: list[tuple[float, float, bool]] = []
        for sg in (1.0, -1.0):
            def h(s, sg=sg):
                w = math.sqrt(1.0 + s * s / B)
                X = sg * a * w
                Xp = sg * a * s / (B * w)
                Xpp = sg * a / (B * w ** 3)
                return (X - x0) * Xp + (s - y0), Xp * Xp + (X - x0) * Xpp + 1.0

            for s0 in seeds:
                s, res = _newton(h, s0)
                if not math.isfinite(s):
                    continue
                ok = res <= 1e-9 * scale * (1.0 + abs(s))
                if not ok and not all_candidates:
                    continue
                if any(sg == t[0] and abs(s - t[1]) < 1e-9 * (1.0 + abs(s)) for t in uniq2):
                    continue
                uniq2.append((sg, s, ok))
        return [(L * sg * a * math.sqrt(1.0 + s * s / B), L * s, ok) for sg, s, ok in uniq2]

    if kind == "parabola":
        p = params["p"]
        x0, y0 = X0 / p, Y0 / p  # scaled: p = 1
        coeffs = [1.0, 0.0, 2 * (1 - x0), -2 * y0]

        def cub(s):
            return s ** 3 + 2 * (1 - x0) * s - 2 * y0, 3 * s * s + 2 * (1 - x0)

        seeds = _real_roots(coeffs) + [0.0, y0]
        scale = 1.0 + abs(x0) + abs(y0)
        uniq3: list[tuple[float, bool]] = []
        for s0 in seeds:
            s, res = _newton(cub, s0)
            ok = res <= 1e-9 * scale * (1.0 + s * s) * (1 + abs(s))
            if not ok and not all_candidates:
                continue
            if any(abs(s - t) < 1e-9 * (1.0 + abs(s)) for t, _ in uniq3):
                continue
            uniq3.append((s, ok))
        return [(p * s * s / 2, p * s, ok) for s, ok in uniq3]
    raise InvalidConicError(f"unknown conic kind {kind!r}")


def foot_points(conic: Conic, x, y) -> list[tuple[float, float, float]]:
    """All real critical points of the distance from (x, y) to the curve, as (px, py, dist)
    in world coordinates, sorted by dist.  At the centre of a circle (infinitely many foot
    points) one representative is returned."""
    fr, X0, Y0 = _canonical_point(conic, x, y)
    res = []
    for X, Y, ok in canonical_foot_points(fr.kind, fr.params, X0, Y0):
        px, py = fr.from_canonical(X, Y)
        res.append((float(px), float(py), math.hypot(X - X0, Y - Y0)))
    res.sort(key=lambda t: t[2])
    return res


def distance(conic: Conic, x, y) -> float:
    """Euclidean distance from (x, y) to the conic (both branches of a hyperbola)."""
    fr, X0, Y0 = _canonical_point(conic, x, y)
    if fr.kind == "circle":
        return abs(math.hypot(X0, Y0) - math.sqrt(fr.params["r2"]))
    cands = canonical_foot_points(fr.kind, fr.params, X0, Y0, all_candidates=True)
    return min(math.hypot(X - X0, Y - Y0) for X, Y, _ in cands)


def closest_point(conic: Conic, x, y) -> tuple[float, float, float]:
    """(px, py, dist) of a closest point of the conic to (x, y)."""
    fr, X0, Y0 = _canonical_point(conic, x, y)
    cands = canonical_foot_points(fr.kind, fr.params, X0, Y0, all_candidates=True)
    X, Y, _ = min(cands, key=lambda t: math.hypot(t[0] - X0, t[1] - Y0))
    px, py = fr.from_canonical(X, Y)
    return float(px), float(py), math.hypot(X - X0, Y - Y0)
