"""Enclosures of the generalised gradient of the distance to a circle or an ellipse, from inside,
on discs that reach the medial axis (where d is not differentiable).

Inside a circle or an ellipse beyond the reach of its boundary (depth ≥ b²/a), the nearest point
of q need not be unique and d = d(·, C) has a ridge along the medial axis; the gradient
enclosures of :func:`runtime.voronoi.verify.site_table.gradient_enclosure` stop there.  The
distance to a compact set C is still locally Lipschitz off C, and d = min_{p ∈ C} |q − p| is a
pointwise minimum of functions smooth in q (continuous in (q, p), p in a compact set), so its
Clarke generalised gradient is

    ∂d(q) ⊂ co { (q − p)/|q − p| : p ∈ C, |q − p| = d(q) }

(Clarke, *Optimization and Nonsmooth Analysis*, Wiley 1983, Thm 2.8.2 applied to −d, a pointwise
maximum; ∂(−d) = −∂d, Prop. 2.3.1).  Lebourg's mean value theorem (ibid., Thm 2.3.7) then gives,
for f = d_i − d_j (∂f ⊂ ∂d_i − ∂d_j, Prop. 2.3.3) and any segment [x, y],
f(y) − f(x) = g·(y − x) with g ∈ ∂f(z) for some z on it: a sign of g·n over every g of every
∂f(q) on a strip makes f strictly monotone along n there, which is all the strip proof
(:mod:`runtime.voronoi.verify.strips`, (T1)) needs.

**Enclosure on a disc** B(Q, R) with rigorous bounds lo ≤ d(Q) ≤ hi, lo > R.  A nearest point p of
q ∈ B(Q, R) satisfies |p − Q| ≤ d(q) + R ≤ hi + 2R (d is 1-Lipschitz), and |q − p| ≥ lo − R,
|Q − p| ≥ lo; x ↦ x/|x| is (1/m)-Lipschitz on {|x| ≥ m} (m·x/|x| is the projection on the ball
of radius m), so (q − p)/|q − p| lies within R/(lo − R) of u(p) = (Q − p)/|Q − p|.  The curve is
p(θ) = c + Rot(a cos θ, b sin θ) (a = b = ρ for a circle), |p'(θ)| ≤ max(a, b), so on a
parameter interval of half-length h every point lies within ℓ = max(a, b)·h of the float point
p̃ at its middle, up to δ (the float frame and the evaluation of p̃: far below δ =
2¹⁰·rounding_slack(size, 32), the allowance of the site table's bounds times 2¹⁰).  An interval
with |p̃ − Q| − ℓ − δ > hi + 2R holds no nearest point; on the others u(p) lies within
(ℓ + δ)/(lo − δ) of ũ = (Q − p̃)/|Q − p̃|.  So

    ∂d(q) ⊂ co ⋃_m B(ũ_m, s_m),  s_m = (ℓ_m + δ)/(lo − δ) + R/(lo − R) + 1e-12,

over the kept intervals m, for every q ∈ B(Q, R); and g·n over that hull lies in
[min_m ũ_m·n − s_m, max_m ũ_m·n + s_m] (a linear function's extremes over a convex hull are at
its generators).  The intervals are halved (from 64 per curve) while ℓ > ``TOL``·lo, a kept
interval at a time, at most ``LEVELS`` times.

For f = d_i − d_j, :func:`difference_range` gives [min, max] of g·n over ∂d_i − ∂d_j from
[a_i, b_i] and [a_j, b_j] of each: [a_i − b_j, b_i − a_j]; each site's range is the intersection
of this enclosure and the gradient enclosure where both hold (∂d(q) = {∇d(q)} where d is
continuously differentiable near q, Clarke Prop. 2.2.4).

Public API: :func:`clarke_normal_range`, :func:`difference_range`.
"""
from __future__ import annotations

import numpy as np

from ...sites.kinds import SiteKind
from ..geometry import rounding_slack

__all__ = ["clarke_normal_range", "difference_range"]

START = 64          # parameter intervals per curve at the start
LEVELS = 12         # halvings at most
TOL = 1e-3          # target ℓ/lo of a kept interval
MAX_KEPT = 4096     # kept intervals per row at most (else the row is not enclosed)


def clarke_normal_range(table, Q, K, lo, hi, R, n):
    """(gmin, gmax, ok): gmin ≤ g·n ≤ gmax for every g in the Clarke gradient ∂d(q, S_K) at every q
    in B(Q, R), where ok (circle and ellipse sites K, lo > 2R; module docstring).  ``table``: a
    :class:`runtime.voronoi.verify.site_table.SiteTable`; lo, hi: rigorous bounds of d(Q, S_K)."""
    Q = np.asarray(Q, float).reshape(-1, 2)
    K = np.asarray(K, int).reshape(-1)
    m = len(K)
    R = np.broadcast_to(np.asarray(R, float), (m,))
    n = np.asarray(n, float).reshape(-1, 2)
    gmin, gmax = np.full(m, -np.inf), np.full(m, np.inf)
    ok = np.zeros(m, bool)
    kind = table.kind[K]
    rows = np.nonzero(((kind == SiteKind.CIRCLE) | (kind == SiteKind.ELLIPSE)) & (lo > 2 * R)
                      & np.isfinite(hi) & np.isfinite(Q).all(1) & np.isfinite(n).all(1))[0]
    if not len(rows):
        return gmin, gmax, ok
    k = K[rows]
    circ = table.kind[k] == SiteKind.CIRCLE
    a = np.where(circ, table.rho[k], table.a[k])
    b = np.where(circ, table.rho[k], table.b[k])
    c = np.where(circ, 1.0, table.c[k])
    s = np.where(circ, 0.0, table.s[k])
    cx, cy = table.cx[k], table.cy[k]
    amax = np.maximum(a, b)
    size = np.abs(Q[rows]).sum(1) + np.abs(cx) + np.abs(cy) + a + b + hi[rows] + R[rows]
    delta = 1024.0 * rounding_slack(size, 32)
    lo_r, hi_r, R_r = lo[rows], hi[rows], R[rows]
    reach = hi_r + 2 * R_r
    # intervals: owner (index into rows), middle θ, half-length h
    own = np.repeat(np.arange(len(rows)), START)
    h0 = np.pi / START
    mid = (np.tile(np.arange(START), len(rows)) * 2 + 1) * h0
    half = np.full(len(own), h0)
    gens_own, gens_lo, gens_hi = [], [], []
    alive = np.ones(len(rows), bool)
    for level in range(LEVELS + 1):
        if not len(own):
            break
        ct, st = np.cos(mid), np.sin(mid)
        X, Y = a[own] * ct, b[own] * st
        px = cx[own] + c[own] * X - s[own] * Y
        py = cy[own] + s[own] * X + c[own] * Y
        wx, wy = Q[rows[own], 0] - px, Q[rows[own], 1] - py
        dist = np.hypot(wx, wy)
        ell = amax[own] * half * (1 + 1e-12)
        keep = dist - ell - delta[own] <= reach[own] * (1 + 1e-12)
        own, mid, half, wx, wy, dist, ell = own[keep], mid[keep], half[keep], wx[keep], wy[keep], dist[keep], ell[keep]
        fine = (ell <= TOL * lo_r[own]) | (level == LEVELS)
        if fine.any():
            o = own[fine]
            with np.errstate(divide="ignore", invalid="ignore"):
                un = (wx[fine] * n[rows[o], 0] + wy[fine] * n[rows[o], 1]) / dist[fine]
                sl = ((ell[fine] + delta[o]) / (lo_r[o] - delta[o]) + R_r[o] / (lo_r[o] - R_r[o]) + 1e-12) * (1 + 1e-12)
            gens_own.append(o)
            gens_lo.append(un - sl)
            gens_hi.append(un + sl)
        own, mid, half = own[~fine], mid[~fine], half[~fine]
        cnt = np.bincount(own, minlength=len(rows))
        alive &= cnt <= MAX_KEPT
        sel = alive[own]
        own, mid, half = own[sel], mid[sel], half[sel]
        half = 0.5 * half
        own = np.concatenate([own, own])
        mid = np.concatenate([mid - half, mid + half])
        half = np.concatenate([half, half])
    if gens_own:
        go = np.concatenate(gens_own)
        glo, ghi = np.concatenate(gens_lo), np.concatenate(gens_hi)
        good = np.isfinite(glo) & np.isfinite(ghi)
        bad_rows = np.unique(go[~good])
        alive[bad_rows] = False
        mn = np.full(len(rows), np.inf)
        mx = np.full(len(rows), -np.inf)
        np.minimum.at(mn, go[good], glo[good])
        np.maximum.at(mx, go[good], ghi[good])
        has = np.bincount(go, minlength=len(rows)) > 0
        fin = alive & has & (lo_r - delta > 0)
        gmin[rows[fin]] = np.maximum(mn[fin], -1.0 - 1e-12)
        gmax[rows[fin]] = np.minimum(mx[fin], 1.0 + 1e-12)
        ok[rows[fin]] = True
    return gmin, gmax, ok


def difference_range(table, Q, R, n, K, V, grads):
    """(lo, hi, ok): lo ≤ g·n ≤ hi for every g in ∂d_i − ∂d_j at every q in B(Q, R), where ok.
    ``K`` = (K_i, K_j) sites, ``V`` = (V_i, V_j) their values at Q (site table), ``grads`` =
    ((G_i, s_i, valid_i), (G_j, s_j, valid_j)): gradient enclosures |∇d − G| ≤ s on the discs
    (:func:`runtime.voronoi.verify.site_table.gradient_enclosure`); each site's range is that of
    its gradient enclosure, intersected with :func:`clarke_normal_range` where both hold."""
    n = np.asarray(n, float).reshape(-1, 2)
    rng = []
    for Kx, Vx, (Gx, sx, vx) in zip(K, V, grads):
        cl, ch, cok = clarke_normal_range(table, Q, Kx, Vx.lo, Vx.hi, R, n)
        gn = (Gx * n).sum(1)
        gl = np.where(vx, gn - sx, -np.inf)
        gh = np.where(vx, gn + sx, np.inf)
        rng.append((np.where(cok, np.maximum(gl, cl), gl), np.where(cok, np.minimum(gh, ch), gh), vx | cok))
    (il, ih, iok), (jl, jh, jok) = rng
    ok = iok & jok
    return np.where(ok, il - jh, -np.inf), np.where(ok, ih - jl, np.inf), ok
