"""Rigorous distance bounds for many (point, site) pairs at once, for the diagram verifier.

The proofs of :mod:`runtime.voronoi.verify_strips` and :mod:`runtime.voronoi.verify_tail` ask,
again and again, for enclosures of d(q, S_k) and of ∇d(q, S_k) at a few points q of one edge.
Asked site by site and edge by edge, the cost is the fixed cost of a numpy call (about a
millisecond for a conic's foot points), not the arithmetic.  :class:`SiteTable` holds the float
data of every point, circle and ellipse site in flat arrays and evaluates one call for any mix of
(point, site) pairs; :func:`run_lockstep` runs the edge proofs (generators that yield their
requests) side by side so that one call serves every edge.

Bounds (the same as :mod:`runtime.voronoi.geometry` and :mod:`runtime.voronoi.conic_geometry`,
vectorised over the sites as well as the points):

* point / circle: d = | |q − c| − ρ |, widened by ``rounding_slack`` of the data's size;
* ellipse (thesis §5.2; :mod:`runtime.voronoi.conic_geometry`, *Rigorous bounds*): in the float
  canonical frame of the site's geometry, a float foot parameter t (safeguarded Newton on the
  quartic of the normal condition in τ = tan(t/2), any accuracy is sound) gives the upper bound
  |Q − P(t)| and, for Q outside K, the supporting-line lower bound n(t)·(Q − P(t)) (K convex);
  every value is widened by the rounding allowances of that module (ε_P, the normal's rounding,
  the frame's slack σ).  Pairs where these bounds are not tight to 1e-7 relative (Q inside K,
  near the evolute, non-finite), and every pair with a site of another kind (hyperbola,
  parabola), are handed to the site geometry's own ``distance_bounds``, which is exact to
  float resolution (S-lemma, ball route).  So the table never claims more than the site
  geometries do; it only saves their per-call cost where the cheap bound already decides.

**Gradient enclosures** (:func:`gradient_enclosure`) for a convex site S and q outside its convex
hull K: ∇d(q) = (q − p)/|q − p| with p the projection of q on K, which is 1-Lipschitz; so on
B(c, R) the gradient is within 4R/d(c) of ∇d(c), and the float foot point F gives ∇d(c) within
2·e_F/d(c), where e_F² = |c − F|² − d(c)² bounds |F − p|² (projection inequality
|c − F|² ≥ |c − p|² + |p − F|², F ∈ K up to rounding).
"""
from __future__ import annotations

import numpy as np

from .geometry import EPS, rounding_slack

__all__ = ["SiteTable", "SiteValues", "gradient_enclosure", "run_lockstep"]

#: relative gap above which the table defers to the site geometry's own bounds
FALLBACK_GAP = 1e-7
#: Newton iterations of the float foot parameter (converged entries leave earlier)
NEWTON_STEPS = 60
#: a Newton step below this (relative) ends the iteration (conic_geometry's rule)
NEWTON_TOL = 2.0 ** -30


class SiteValues:
    """Values of :meth:`SiteTable.evaluate` at rows (q, k): rigorous ``lo`` ≤ d(q, S_k) ≤ ``hi``,
    a float foot point ``F`` (on S_k up to rounding), its float distance ``d`` and ``base``:
    S_k convex and q proved outside its convex hull (gradient enclosures allowed)."""

    __slots__ = ("lo", "hi", "F", "d", "base")

    def __init__(self, lo, hi, F, d, base):
        self.lo, self.hi, self.F, self.d, self.base = lo, hi, F, d, base

    def part(self, a, b):
        return SiteValues(self.lo[a:b], self.hi[a:b], self.F[a:b], self.d[a:b], self.base[a:b])

    def take(self, idx):
        return SiteValues(self.lo[idx], self.hi[idx], self.F[idx], self.d[idx], self.base[idx])


class SiteTable:
    """Flat float data of the sites (kinds point / circle / ellipse; others via their geometry)."""

    def __init__(self, geoms, scale):
        self.geoms = geoms
        self.scale = float(scale)
        n = len(geoms)
        self.n = n
        self.kind = np.zeros(n, int)          # 0 point, 1 circle, 2 ellipse, 3 other
        self.cx, self.cy, self.rho = np.zeros(n), np.zeros(n), np.zeros(n)
        self.a, self.b, self.c, self.s = np.ones(n), np.ones(n), np.ones(n), np.zeros(n)
        for k, g in enumerate(geoms):
            if g.kind == "point":
                self.cx[k], self.cy[k] = g.x0, g.y0
            elif g.kind == "circle":
                self.kind[k] = 1
                self.cx[k], self.cy[k], self.rho[k] = g.cx, g.cy, g.rho
            elif g.kind == "ellipse":
                self.kind[k] = 2
                self.cx[k], self.cy[k], self.a[k], self.b[k], self.c[k], self.s[k] = g.tx, g.ty, g.a, g.b, g.c, g.s
            else:
                self.kind[k] = 3
        self.convex = self.kind < 3
        self.boxes = np.array([g.bounding_box() for g in geoms], float).reshape(-1, 4)
        self.calls = 0
        self.fallbacks = 0

    # ------------------------------------------------------------------ rigorous values
    def evaluate(self, Q, K) -> SiteValues:
        """Bounds, float feet and the outside flags at the rows (Q[m], K[m])."""
        Q = np.asarray(Q, float).reshape(-1, 2)
        K = np.asarray(K, int).reshape(-1)
        self.calls += 1
        m = len(K)
        lo, hi, d = np.zeros(m), np.full(m, np.inf), np.full(m, np.inf)
        F = np.full((m, 2), np.nan)
        base = np.zeros(m, bool)
        loose = np.zeros(m, bool)
        kind = self.kind[K]
        x, y = Q[:, 0], Q[:, 1]
        # ---- points and circles
        r = np.nonzero(kind <= 1)[0]
        if len(r):
            k = K[r]
            cx, cy, rho = self.cx[k], self.cy[k], self.rho[k]
            vx, vy = x[r] - cx, y[r] - cy
            nv = np.hypot(vx, vy)
            dd = np.abs(nv - rho)
            sl = rounding_slack(np.abs(x[r]) + np.abs(y[r]) + np.abs(cx) + np.abs(cy) + rho)
            lo[r], hi[r], d[r] = np.maximum(dd - sl, 0.0), dd + sl, dd
            with np.errstate(divide="ignore", invalid="ignore"):
                ux, uy = np.where(nv > 0, vx / nv, 1.0), np.where(nv > 0, vy / nv, 0.0)
            F[r, 0], F[r, 1] = cx + rho * ux, cy + rho * uy
            base[r] = nv > rho * (1 + 1e-12)
        # ---- ellipses
        r = np.nonzero(kind == 2)[0]
        if len(r):
            loose[r] = self._ellipses(r, K[r], x[r], y[r], lo, hi, F, d, base)
        # ---- the site geometries' own bounds where the table is not tight or not applicable
        bad = (kind == 3) | loose
        if bad.any():
            idx = np.nonzero(bad)[0]
            for k in np.unique(K[idx]):
                sel = idx[K[idx] == k]
                self.fallbacks += len(sel)
                g = self.geoms[k]
                lo_, hi_ = g.distance_bounds(Q[sel])
                lo[sel], hi[sel] = lo_, hi_
                if kind[sel[0]] == 3 or not np.isfinite(F[sel]).all():
                    F_, _ = g.foot_points(Q[sel])
                    F[sel] = F_
                    d[sel] = np.hypot(*(Q[sel] - F_).T)
        return SiteValues(lo, hi, F, d, base & self.convex[K])

    def _ellipses(self, r, k, x, y, lo, hi, F, d, base):
        a, b, c, s, tx, ty = self.a[k], self.b[k], self.c[k], self.s[k], self.cx[k], self.cy[k]
        dx, dy = x - tx, y - ty
        X0, Y0 = c * dx + s * dy, -s * dx + c * dy
        u, v = np.abs(X0), np.abs(Y0)
        kk = b * b - a * a
        au, bv = a * u, b * v
        # P(τ) = bv (τ⁴ − 1) + 2 (au − k) τ³ + 2 (au + k) τ on [0, 1]: P(0) ≤ 0 ≤ P(1)
        B3, B1 = 2 * (au - kk), 2 * (au + kk)
        cxr, cyr = b * u, a * v
        rr = np.hypot(cxr, cyr)
        with np.errstate(divide="ignore", invalid="ignore"):
            tau = np.clip(np.where(rr > 0, cyr / np.where(rr > 0, rr + cxr, 1.0), 0.5), 0.0625, 0.9375)
        tau = _foot_parameter(tau, bv, B3, B1)
        t = 2.0 * np.arctan(tau)
        ct, st = np.cos(t), np.sin(t)
        sx, sy = np.where(X0 < 0, -1.0, 1.0), np.where(Y0 < 0, -1.0, 1.0)
        X, Y = sx * a * ct, sy * b * st
        NX, NY = sx * b * ct, sy * a * st
        nn = np.hypot(NX, NY)
        NX, NY = NX / nn, NY / nn
        dX, dY = X0 - X, Y0 - Y
        dist = np.hypot(dX, dY)
        sz = a + b
        scale = sz + np.abs(X) + np.abs(Y)
        up = dist + rounding_slack(scale, 16) + rounding_slack(dist + np.abs(X0) + np.abs(Y0) + scale, 8)
        # supporting line at the foot (conic_geometry: lower bound outside K)
        err = rounding_slack(scale, 16) + 16 * EPS * dist + rounding_slack(np.abs(X0) + np.abs(Y0) + scale, 8)
        tl = np.maximum(NX * dX + NY * dY - err, 0.0)
        g = (X0 / a) ** 2 + (Y0 / b) ** 2
        outside = g > 1 + 1e-9
        tl = np.where(g - 1.0 < 0, 0.0, tl)
        sig = rounding_slack(np.abs(x) + np.abs(y) + np.abs(tx) + np.abs(ty) + np.abs(X0) + np.abs(Y0) + up + sz, 32)
        lo_ = np.maximum(tl - sig, 0.0)
        hi_ = up + sig
        lo[r], hi[r] = lo_, hi_
        F[r, 0], F[r, 1] = tx + c * X - s * Y, ty + s * X + c * Y
        d[r] = dist
        base[r] = outside
        # inside K the supporting line proves nothing (the geometry's S-lemma bound decides); the
        # same tightness rule as the geometry's own ball-route fallback
        tight = (hi_ - lo_) <= np.maximum(FALLBACK_GAP * hi_, 64 * sig)
        return ~(outside & tight & np.isfinite(lo_) & np.isfinite(hi_))

    # ------------------------------------------------------------------ third sites
    def candidates(self, C, reach, pair):
        """Sites other than ``pair`` whose bounding box comes within ``reach`` of some point of C
        (rigorous: d(q, S) is at least the distance from q to the bounding box of S)."""
        C = np.asarray(C, float).reshape(-1, 2)
        if not len(C):
            return np.zeros(0, int)
        bx = self.boxes
        lo_ = C.min(0) - np.max(reach)
        hi_ = C.max(0) + np.max(reach)
        near = ~((bx[:, 0] > hi_[0]) | (bx[:, 2] < lo_[0]) | (bx[:, 1] > hi_[1]) | (bx[:, 3] < lo_[1]))
        near[list(pair)] = False
        ks = np.nonzero(near)[0]
        if not len(ks) or len(C) == 0:
            return ks
        with np.errstate(invalid="ignore"):
            dx = np.maximum(np.maximum(bx[ks, 0][None, :] - C[:, :1], C[:, :1] - bx[ks, 2][None, :]), 0.0)
            dy = np.maximum(np.maximum(bx[ks, 1][None, :] - C[:, 1:], C[:, 1:] - bx[ks, 3][None, :]), 0.0)
            dd = np.where(np.isfinite(dx) & np.isfinite(dy), np.hypot(dx, dy), 0.0)
        hit = (dd * (1 - 1e-12) <= np.asarray(reach, float).reshape(-1, 1)).any(0)
        return ks[hit]

    def near_pairs(self, C, reach, pair):
        """(rows, sites): the pairs (C[row], site k ∉ pair) with the bounding box of S_k within
        ``reach[row]`` of C[row]; every other site is proved farther than ``reach`` from its
        point (d(q, S) is at least the distance from q to the bounding box of S)."""
        C = np.asarray(C, float).reshape(-1, 2)
        reach = np.broadcast_to(np.asarray(reach, float), (len(C),))
        ks = self.candidates(C, reach, pair)
        if not len(ks):
            return np.zeros(0, int), np.zeros(0, int)
        bx = self.boxes[ks]
        with np.errstate(invalid="ignore"):
            dx = np.maximum(np.maximum(bx[:, 0][None, :] - C[:, :1], C[:, :1] - bx[:, 2][None, :]), 0.0)
            dy = np.maximum(np.maximum(bx[:, 1][None, :] - C[:, 1:], C[:, 1:] - bx[:, 3][None, :]), 0.0)
            dd = np.where(np.isfinite(dx) & np.isfinite(dy), np.hypot(dx, dy), 0.0)
        rows, cols = np.nonzero(dd * (1 - 1e-12) <= reach[:, None])
        return rows, ks[cols]


def _foot_parameter(x, A, B, C):
    """Float root in [0, 1] of A(τ⁴ − 1) + Bτ³ + Cτ (A ≥ 0, value ≤ 0 at 0 and ≥ 0 at 1):
    Newton's method kept in a bracket by bisection.  Only a guide: every bound built on it holds
    for any parameter."""
    lo, hi = np.zeros_like(x), np.ones_like(x)
    out = x.copy()
    idx = np.arange(len(x))
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        for it in range(NEWTON_STEPS):
            x2 = x * x
            f = A * (x2 * x2 - 1.0) + (B * x2 + C) * x
            flat = np.abs(f) <= 16 * EPS * (np.abs(A) * (x2 * x2 + 1.0) + (np.abs(B) * x2 + np.abs(C)) * x)
            df = (4 * A * x + 3 * B) * x2 + C
            neg = f < 0
            lo = np.where(neg, x, lo)
            hi = np.where(neg, hi, x)
            step = f / df
            xn = x - step
            ok = (xn > lo) & (xn < hi) & np.isfinite(xn)
            xn = np.where(ok, xn, 0.5 * (lo + hi))
            # a Newton step below 2⁻³⁰ relative: the next iterate is exact to float resolution
            # (quadratic convergence at a simple root); else a bracket at float resolution
            done = (ok & (np.abs(step) <= NEWTON_TOL * np.abs(xn) + 2.0 ** -64)) | (hi - lo <= 4 * EPS) | flat
            xn = np.where(flat, x, xn)      # f = 0 within rounding at x
            out[idx] = xn
            if done.all():
                break
            keep = ~done
            idx, x, lo, hi, A, B, C = idx[keep], xn[keep], lo[keep], hi[keep], A[keep], B[keep], C[keep]
    return out


def gradient_enclosure(Q, V: SiteValues, R, scale):
    """(G, slack, valid): |∇d(q) − G| ≤ slack for every q in B(Q, R) where valid (module
    docstring).  ``V`` are the table's values at Q."""
    Q = np.asarray(Q, float).reshape(-1, 2)
    W = Q - V.F
    dF = np.hypot(W[:, 0], W[:, 1])
    size = np.abs(Q).sum(1) + scale
    dF_hi = dF * (1 + 8 * EPS) + 1e-14 * size
    eF = np.sqrt(np.maximum(dF_hi ** 2 - V.lo ** 2, 0.0)) + 1e-12 * size
    valid = V.base & (V.lo > 2 * R + eF) & (dF > 0)
    with np.errstate(divide="ignore", invalid="ignore"):
        G = W / dF[:, None]
        slack = (2 * eF + 4 * R) / V.lo + 1e-12
    return G, np.where(valid, slack, np.inf), valid


def run_lockstep(gens, table: SiteTable):
    """Run generator proofs side by side: each yields requests (Q, K) and receives the
    :class:`SiteValues` at those rows; one :meth:`SiteTable.evaluate` serves all pending requests.
    Returns the generators' return values (in order)."""
    out = [None] * len(gens)
    pending = {}
    for t, g in enumerate(gens):
        try:
            pending[t] = next(g)
        except StopIteration as stop:
            out[t] = stop.value
    while pending:
        keys = list(pending)
        Qs = [np.asarray(pending[t][0], float).reshape(-1, 2) for t in keys]
        Ks = [np.asarray(pending[t][1], int).reshape(-1) for t in keys]
        V = table.evaluate(np.concatenate(Qs), np.concatenate(Ks))
        pos = 0
        nxt = {}
        for t, q in zip(keys, Qs):
            part = V.part(pos, pos + len(q))
            pos += len(q)
            try:
                nxt[t] = gens[t].send(part)
            except StopIteration as stop:
                out[t] = stop.value
        pending = nxt
    return out

