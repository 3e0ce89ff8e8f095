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

**Enclosure on a disc** B(Q, R) with rigorous bounds lo ≤ d(Q) ≤ hi, lo > 2R, Q inside the
curve.  A nearest point p of q ∈ B(Q, R) (q inside, in the open convex region) has
q − p = d(q)·n(p) with n(p) the inward unit normal at p (first-order condition; inward: the
region is convex), so (q − p)/|q − p| = n(p), and p satisfies |p − Q| ≤ d(q) + R ≤ hi + 2R
(d is 1-Lipschitz) and dist(Q, normal line of p) ≤ |q − Q| ≤ R.  The curve is
p(θ) = c + Rot(a cos θ, b sin θ) (a = b = ρ for a circle), n(θ) = −Rot(b cos θ, a sin θ)/|·|,
|p'(θ)| ≤ A = max(a, b) and |n'(θ)| = κ|p'| = ab/(a² sin²θ + b² cos²θ) ≤ A/B, B = min(a, b).
On a parameter interval of half-length h around θ_m: |p(θ) − p(θ_m)| ≤ A·h, |n(θ) − n(θ_m)| ≤
(A/B)·h, and f(θ) = (Q − p(θ)) × n(θ) moves by at most h·(A + (|Q − p(θ_m)| + A·h)·A/B)
(f' = −p' × n + (Q − p) × n').  An interval where |p̃ − Q| − A·h − δ > hi + 2R, or
|f̃| − that bound − δ > R, holds no nearest point (p̃, ñ, f̃ the floats at θ_m; δ =
2¹⁰·rounding_slack(size, 32), far above the float frame's error and the evaluation's).  So

    ∂d(q) ⊂ co ⋃_m B(ñ_m, s_m),  s_m = (A/B)·h_m + 1e-12,

over the kept intervals m, for every q ∈ B(Q, R); and g·n over that hull lies in
[min_m ñ_m·n − s_m, max_m ñ_m·n + s_m] (a linear function's extremes over a convex hull are at
its generators).  The intervals are halved (from 64 per curve) while s_m > ``TOL``, a kept
interval at a time, at most ``LEVELS`` times; the kept ones close in on the nearest points of
the disc's points (width O(R) in θ away from the evolute).

For f = d_i − d_j, :func:`difference_range` gives [min, max] of g·n over ∂d_i − ∂d_j from
[a_i, b_i] and [a_j, b_j] of each: [a_i − b_j, b_i − a_j]; each site's range is the intersection
of this enclosure and the gradient enclosure where both hold (∂d(q) = {∇d(q)} where d is
continuously differentiable near q, Clarke Prop. 2.2.4).

**Off the ridge** the distance is C¹: d_C is differentiable at q ∉ C exactly where q has one
nearest point, and continuously so on the open set of such points (the nearest point depends
continuously on q there), where ∂d = {∇d}.  Inside an ellipse X²/a² + Y²/b² < 1 (a ≥ b) the
points with two nearest points form the open segment |X| < (a² − b²)/a, Y = 0 of the major axis
(its medial axis: H. I. Choi, S. W. Choi, H. P. Moon, *Mathematical theory of medial axis
transform*, Pacific J. Math. 181 (1997); the normals from q with Y ≠ 0 to the half of the ellipse
on the other side are longer than its mirror image's), inside a circle only the centre.  So on a
disc that misses that set, the box [range along x] × [range along y] of :func:`clarke_normal_range`
holds ∇d everywhere: a gradient enclosure (:func:`off_ridge_gradient`) for the tests that need
differentiability (the strips' third sites, (T3)), beyond the reach b²/a where the foot-point
enclosure of :func:`runtime.voronoi.verify.site_table.gradient_enclosure` stops.

Public API: :func:`clarke_normal_range`, :func:`difference_range`, :func:`off_ridge_gradient`.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ...sites.kinds import SiteKind
from ..geometry import rounding_slack

__all__ = ["clarke_normal_range", "difference_range", "off_ridge_gradient"]

START = 64          # parameter intervals per curve at the start
LEVELS = 12         # halvings at most
TOL = 1e-3          # target slack (A/B)·h of a kept interval's normal
MAX_KEPT = 4096     # kept intervals per row at most (else the row is not enclosed)


class _Curves(NamedTuple):
    """The rows of :func:`clarke_normal_range` that can be enclosed (``rows``, into the input) and
    their curves p(θ) = (cx, cy) + Rot(c, s)·(a cos θ, b sin θ) (module docstring), with
    A = ``amax``, the bound ``turn`` ≥ A/B of |n'(θ)|, the evaluation slack ``delta`` = δ, the
    radius ``reach`` = hi + 2R of the nearest points, the discs' centres ``Q`` and radii ``R``, and
    the directions ``n`` of the input (indexed by ``rows``)."""

    rows: np.ndarray
    a: np.ndarray
    b: np.ndarray
    c: np.ndarray
    s: np.ndarray
    cx: np.ndarray
    cy: np.ndarray
    amax: np.ndarray
    turn: np.ndarray
    delta: np.ndarray
    reach: np.ndarray
    R: np.ndarray
    Q: np.ndarray
    n: np.ndarray


def _enclosable_curves(table, Q, K, lo, hi, R, n, inner):
    """The rows the enclosure applies to: circle and ellipse sites, Q proved ``inner``, lo > 2R
    (so that every q of B(Q, R) is at distance > R from the curve), finite data; and their
    curves (:class:`_Curves`).  None when there is no such row."""
    kind = table.kind[K]
    rows = np.nonzero(((kind == SiteKind.CIRCLE) | (kind == SiteKind.ELLIPSE)) & np.asarray(inner, bool)
                      & (lo > 2 * R) & np.isfinite(hi) & np.isfinite(Q).all(1) & np.isfinite(n).all(1))[0]
    if not len(rows):
        return None
    k = K[rows]
    circ = table.kind[k] == SiteKind.CIRCLE
    a = np.where(circ, table.rho[k], table.a[k])
    b = np.where(circ, table.rho[k], table.b[k])
    c = np.where(circ, 1.0, table.c[k])
    s = np.where(circ, 0.0, table.s[k])
    cx, cy = table.cx[k], table.cy[k]
    amax, amin = np.maximum(a, b), np.minimum(a, b)
    turn = amax / amin * (1 + 1e-12)                 # bound of |n'(θ)|
    size = np.abs(Q[rows]).sum(1) + np.abs(cx) + np.abs(cy) + a + b + hi[rows] + R[rows]
    delta = 1024.0 * rounding_slack(size, 32)
    R_r = R[rows]
    reach = hi[rows] + 2 * R_r
    return _Curves(rows, a, b, c, s, cx, cy, amax, turn, delta, reach, R_r, Q[rows], n)


def _may_hold_nearest_point(cv, own, mid, half):
    """(keep, nx, ny): the float inward normals ñ at the middles θ_m of the parameter intervals
    (owner ``own``, half-length h = ``half``), and ``keep`` unless the interval provably holds no
    nearest point of the disc: |p̃ − Q| − A·h − δ > hi + 2R (too far from Q), or
    |f̃| − h·(A + (|Q − p̃| + A·h)·A/B) − δ > R (its normal lines miss the disc; f = (Q − p) × n,
    module docstring)."""
    a, b, c, s = cv.a[own], cv.b[own], cv.c[own], cv.s[own]
    ct, st = np.cos(mid), np.sin(mid)
    X, Y = a * ct, b * st
    px = cv.cx[own] + c * X - s * Y
    py = cv.cy[own] + s * X + c * Y
    NX, NY = -b * ct, -a * st                  # inward normal, canonical frame
    ln = np.hypot(NX, NY)
    nx = (c * NX - s * NY) / ln
    ny = (s * NX + c * NY) / ln
    wx, wy = cv.Q[own, 0] - px, cv.Q[own, 1] - py
    dist = np.hypot(wx, wy)
    move = cv.amax[own] * half * (1 + 1e-12)
    cross = np.abs(wx * ny - wy * nx)
    fmove = half * (cv.amax[own] + (dist + move) * cv.turn[own]) * (1 + 1e-12)
    keep = ((dist - move - cv.delta[own] <= cv.reach[own] * (1 + 1e-12))
            & (cross - fmove - cv.delta[own] <= cv.R[own] * (1 + 1e-12)))
    return keep, nx, ny


def _normal_generators(cv):
    """The generators B(ñ_m, s_m), s_m = (A/B)·h_m + 1e-12, of the kept intervals, as ranges
    [ñ_m·n − s_m, ñ_m·n + s_m] of g·n (owner, lo, hi concatenated), and ``alive``: the rows whose
    kept intervals stayed within ``MAX_KEPT``.  Intervals start at ``START`` per curve and are
    halved while s_m > ``TOL``, at most ``LEVELS`` times (module docstring)."""
    nrow = len(cv.rows)
    own = np.repeat(np.arange(nrow), START)
    h0 = np.pi / START
    mid = (np.tile(np.arange(START), nrow) * 2 + 1) * h0
    half = np.full(len(own), h0)
    gens_own, gens_lo, gens_hi = [], [], []
    alive = np.ones(nrow, bool)
    for level in range(LEVELS + 1):
        if not len(own):
            break
        keep, nx, ny = _may_hold_nearest_point(cv, own, mid, half)
        own, mid, half, nx, ny = own[keep], mid[keep], half[keep], nx[keep], ny[keep]
        sl = (cv.turn[own] * half + 1e-12) * (1 + 1e-12)
        fine = (sl <= TOL) | (level == LEVELS)
        if fine.any():
            o = own[fine]
            un = nx[fine] * cv.n[cv.rows[o], 0] + ny[fine] * cv.n[cv.rows[o], 1]
            gens_own.append(o)
            gens_lo.append(un - sl[fine])
            gens_hi.append(un + sl[fine])
        own, mid, half = own[~fine], mid[~fine], half[~fine]
        cnt = np.bincount(own, minlength=nrow)
        alive &= cnt <= MAX_KEPT
        sel = alive[own]
        own, mid, half = own[sel], mid[sel], half[sel]
        half = 0.5 * half
        own = np.concatenate([own, own])
        mid = np.concatenate([mid - half, mid + half])
        half = np.concatenate([half, half])
    if not gens_own:
        return None
    return np.concatenate(gens_own), np.concatenate(gens_lo), np.concatenate(gens_hi), alive


def _hull_range(cv, gens, gmin, gmax, ok):
    """Write [min_m ñ_m·n − s_m, max_m ñ_m·n + s_m] (clipped to [−1, 1] with 1e-12 slack: g is
    in the convex hull of unit vectors) into gmin, gmax, ok for the rows with generators, all
    finite, and ``alive`` (the extremes of a linear function over a convex hull are at its
    generators)."""
    go, glo, ghi, alive = gens
    rows = cv.rows
    good = np.isfinite(glo) & np.isfinite(ghi)
    alive[np.unique(go[~good])] = False
    mn = np.full(len(rows), np.inf)
    mx = np.full(len(rows), -np.inf)
    np.minimum.at(mn, go[good], glo[good])
    np.maximum.at(mx, go[good], ghi[good])
    has = np.bincount(go, minlength=len(rows)) > 0
    fin = alive & has
    gmin[rows[fin]] = np.maximum(mn[fin], -1.0 - 1e-12)
    gmax[rows[fin]] = np.minimum(mx[fin], 1.0 + 1e-12)
    ok[rows[fin]] = True


def clarke_normal_range(table, Q, K, lo, hi, R, n, inner):
    """(gmin, gmax, ok): gmin ≤ g·n ≤ gmax for every g in the Clarke gradient ∂d(q, S_K) at every q
    in B(Q, R), where ok (circle and ellipse sites K, Q proved ``inner``, lo > 2R; module
    docstring).  ``table``: a :class:`runtime.voronoi.verify.site_table.SiteTable`; lo, hi:
    rigorous bounds of d(Q, S_K).  Steps: the rows and their curves
    (:func:`_enclosable_curves`), the normals of the parameter intervals that may hold a nearest
    point (:func:`_normal_generators`), the range over their convex hull (:func:`_hull_range`)."""
    Q = np.asarray(Q, float).reshape(-1, 2)
    K = np.asarray(K, int).reshape(-1)
    m = len(K)
    R = np.broadcast_to(np.asarray(R, float), (m,))
    n = np.asarray(n, float).reshape(-1, 2)
    gmin, gmax = np.full(m, -np.inf), np.full(m, np.inf)
    ok = np.zeros(m, bool)
    cv = _enclosable_curves(table, Q, K, lo, hi, R, n, inner)
    if cv is None:
        return gmin, gmax, ok
    gens = _normal_generators(cv)
    if gens is not None:
        _hull_range(cv, gens, gmin, gmax, ok)
    return gmin, gmax, ok


def difference_range(table, Q, R, n, K, V, grads):
    """(lo, hi, ok): lo ≤ g·n ≤ hi for every g in ∂d_i − ∂d_j at every q in B(Q, R), where ok.
    ``K`` = (K_i, K_j) sites, ``V`` = (V_i, V_j) their values at Q (site table), ``grads`` =
    ((G_i, s_i, valid_i), (G_j, s_j, valid_j)): gradient enclosures |∇d − G| ≤ s on the discs
    (:func:`runtime.voronoi.verify.site_table.gradient_enclosure`); each site's range is that of
    its gradient enclosure, intersected with :func:`clarke_normal_range` (rows inside the site)
    where both hold."""
    n = np.asarray(n, float).reshape(-1, 2)
    rng = []
    for Kx, Vx, (Gx, sx, vx) in zip(K, V, grads):
        cl, ch, cok = clarke_normal_range(table, Q, Kx, Vx.lo, Vx.hi, R, n, Vx.inner)
        gn = (Gx * n).sum(1)
        gl = np.where(vx, gn - sx, -np.inf)
        gh = np.where(vx, gn + sx, np.inf)
        rng.append((np.where(cok, np.maximum(gl, cl), gl), np.where(cok, np.minimum(gh, ch), gh), vx | cok))
    (il, ih, iok), (jl, jh, jok) = rng
    ok = iok & jok
    return np.where(ok, il - jh, -np.inf), np.where(ok, ih - jl, np.inf), ok


def off_ridge_gradient(table, Q, K, lo, hi, R, inner):
    """(G, slack, ok): |∇d(q, S_K) − G| ≤ slack for every q in B(Q, R) where ok: discs inside
    (``inner``) a circle or an ellipse that miss its ridge (module docstring; margins far above the float
    frame's error), with the Clarke box of :func:`clarke_normal_range`."""
    Q = np.asarray(Q, float).reshape(-1, 2)
    K = np.asarray(K, int).reshape(-1)
    m = len(K)
    R = np.broadcast_to(np.asarray(R, float), (m,))
    G = np.full((m, 2), np.nan)
    slack = np.full(m, np.inf)
    ok = np.zeros(m, bool)
    kind = table.kind[K]
    circ = kind == SiteKind.CIRCLE
    ell = kind == SiteKind.ELLIPSE
    dx, dy = Q[:, 0] - table.cx[K], Q[:, 1] - table.cy[K]
    c, s = np.where(ell, table.c[K], 1.0), np.where(ell, table.s[K], 0.0)
    X0, Y0 = c * dx + s * dy, -s * dx + c * dy
    a, b = np.where(ell, table.a[K], 0.0), np.where(ell, table.b[K], 0.0)
    big, small = np.maximum(a, b), np.minimum(a, b)
    along = np.where(a >= b, X0, Y0)            # the major axis' coordinate
    across = np.where(a >= b, Y0, X0)
    with np.errstate(divide="ignore", invalid="ignore"):
        half = np.where(big > 0, (big - small) * (big + small) / big, 0.0)
    margin = 1e-9 * (np.abs(Q).sum(1) + np.abs(table.cx[K]) + np.abs(table.cy[K]) + big + table.rho[K] + R)
    off = np.where(circ, np.hypot(dx, dy) > R + margin,
                   ell & ((np.abs(across) > R + margin) | (np.abs(along) > half + R + margin)))
    rows = np.nonzero(off & (circ | ell))[0]
    if not len(rows):
        return G, slack, ok
    n = len(rows)
    QQ = np.concatenate([Q[rows], Q[rows]])
    KK = np.concatenate([K[rows], K[rows]])
    N = np.concatenate([np.tile([1.0, 0.0], (n, 1)), np.tile([0.0, 1.0], (n, 1))])
    gl, gh, gok = clarke_normal_range(table, QQ, KK, np.concatenate([lo[rows]] * 2),
                                      np.concatenate([hi[rows]] * 2), np.concatenate([R[rows]] * 2), N,
                                      np.concatenate([np.asarray(inner, bool)[rows]] * 2))
    good = gok[:n] & gok[n:]
    cx_, cy_ = 0.5 * (gl[:n] + gh[:n]), 0.5 * (gl[n:] + gh[n:])
    G[rows, 0], G[rows, 1] = cx_, cy_
    slack[rows] = np.where(good, np.hypot(0.5 * (gh[:n] - gl[:n]), 0.5 * (gh[n:] - gl[n:])) * (1 + 1e-12) + 1e-15,
                           np.inf)
    ok[rows] = good
    return G, slack, ok
