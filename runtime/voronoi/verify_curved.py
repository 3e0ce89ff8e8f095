"""Proofs for Voronoi edges of convex curved sites (ellipses, mixed with circles and points).

Used by :mod:`runtime.voronoi.verify` for an edge (i, j) between two proved vertices when one of
i, j (or a third site of an end vertex) is an ellipse, where the bisector has no closed form.
The reported polyline only guides the proof.  For each polyline segment, with unit direction t,
normal n and length L, take the rectangle Π = {P_l + s·t + λ·n : s ∈ [−e, L + e], |λ| ≤ w}
(e covers the turn to the next segment and the vertex boxes).  With f = d_i − d_j:

(T1) **monotone**: (∇d_i − ∇d_j)·n has one strict sign σ on Π;
(T4) **crossing**: σ·f > 0 on the side λ = +w and σ·f < 0 on the side λ = −w.

Then every cross-section s = const meets the bisector β exactly once, so β ∩ Π is one arc, a
graph over s (implicit function theorem).  The arc leaves Π through the cap s = L + e at
|λ| < w, inside the next rectangle (e ≥ w·|sin θ| for the turn θ), so the arcs chain into one
curve of β through both end vertices (each lies in the first / last rectangle).  Along it:

(T2) every other site k is proved farther on each piece (lo_k − R > min(hi_i, hi_j) + R on a disc
     of radius R covering the piece; d is 1-Lipschitz);
(T3) or, for the third site k0 of the first vertex (k1 of the last), the derivative of
     g = d_k0 − d_i along the arc has a proved sign: the arc's tangent is ± rot90(∇f), so
     g' ∝ σ_t·(∇d_k0 − ∇d_i)·rot90(∇d_i − ∇d_j) (transversality at the vertex).  Since g = 0 at
     the vertex, g' > 0 on a run of pieces that starts at the vertex or after a (T2) piece keeps
     g > 0 (symmetrically g' < 0 before the last vertex).

**Gradient enclosures** for a convex site S and q outside its convex hull K: ∇d(q) = (q − p)/|q − p|
with p the projection of q on K, which is 1-Lipschitz; so on B(c, R) the gradient is within
4R/d(c) of ∇d(c), and the float foot point F (on S) gives ∇d(c) within 2·e_F/d(c), where
e_F² = |c − F|² − d(c)² bounds |F − p|² (projection inequality |c − F|² ≥ |c − p|² + |p − F|²).

Unbounded edges of conic sites are proved up to the last polyline point only ("not proved beyond").
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["prove_curved_edge"]

EPS = 2.0 ** -53
MAX_DEPTH = 40


class _SiteOps:
    """Vectorised helpers over one site geometry: bounds, outside test, gradient enclosure."""

    def __init__(self, g, scale):
        self.g = g
        self.scale = scale
        self.convex = g.kind in ("point", "circle", "ellipse")

    def bounds(self, Q):
        return self.g.distance_bounds(np.asarray(Q, float).reshape(-1, 2))

    def outside(self, Q):
        g = self.g
        if g.kind == "point":
            return np.ones(len(Q), bool)
        if g.kind == "circle":
            return np.hypot(Q[:, 0] - g.cx, Q[:, 1] - g.cy) > g.rho * (1 + 1e-12)
        if g.kind == "ellipse":
            X, Y = g.to_canonical(Q)
            return (X / g.a) ** 2 + (Y / g.b) ** 2 > 1 + 1e-9
        return np.zeros(len(Q), bool)

    def gradient(self, Q, R):
        """(G, slack, valid): |∇d(q) − G| ≤ slack on B(Q, R) where valid (module docstring)."""
        Q = np.asarray(Q, float).reshape(-1, 2)
        lo, _ = self.bounds(Q)
        F, _ = self.g.foot_points(Q)
        V = Q - F
        dF = np.hypot(V[:, 0], V[:, 1])
        dF_hi = dF * (1 + 8 * EPS) + 1e-14 * (np.abs(Q).sum(1) + self.scale)
        eF = np.sqrt(np.maximum(dF_hi ** 2 - lo ** 2, 0.0)) + 1e-12 * (np.abs(Q).sum(1) + self.scale)
        valid = self.convex & self.outside(Q) & (lo > 2 * R + eF) & (dF > 0)
        with np.errstate(divide="ignore", invalid="ignore"):
            G = V / dF[:, None]
            slack = (2 * eF + 4 * R) / lo + 1e-12
        return G, np.where(valid, slack, np.inf), valid


def _rot90(V):
    return np.column_stack([-V[:, 1], V[:, 0]])


def prove_curved_edge(geoms, scale, pair, P, v0, v1, tol):
    """Prove an edge of convex sites along its polyline P (ends at the vertices v0, v1; either may
    be None = infinity, then only up to the polyline's end).  Returns (ok, message or None,
    beyond) where ``beyond`` is the point past which an unbounded edge is not proved."""
    i, j = pair
    ops = {}

    def op(k):
        if k not in ops:
            ops[k] = _SiteOps(geoms[k], scale)
        return ops[k]

    if not (op(i).convex and op(j).convex):
        return False, "edges of hyperbolas and parabolas are not verified by this version", None
    S = np.array(P, float)
    beyond = None
    if v0 is None or v1 is None:
        # an unbounded edge is proved up to a point at a few times the scene's size only
        fb = [g.bounding_box() for g in geoms if g.bounded]
        bx = np.array(fb, float)
        cen = 0.5 * (bx[:, :2].min(0) + bx[:, 2:].max(0))
        rad = 0.5 * float(np.hypot(*(bx[:, 2:].max(0) - bx[:, :2].min(0)))) + 1.0
        if v0 is None:
            S, v0f = S[::-1], True
        else:
            v0f = False
        dist = np.hypot(S[:, 0] - cen[0], S[:, 1] - cen[1])
        far = np.nonzero(dist > 3 * rad)[0]
        if len(far) and far[0] > 0:
            f0 = int(far[0])                       # cut the chord where it leaves the disc of radius 3·rad
            A_, B_ = S[f0 - 1], S[f0]
            lo_t, hi_t = 0.0, 1.0
            for _ in range(60):
                mt = 0.5 * (lo_t + hi_t)
                if np.hypot(*(A_ + mt * (B_ - A_) - cen)) > 3 * rad:
                    hi_t = mt
                else:
                    lo_t = mt
            S = np.vstack([S[:f0], A_ + hi_t * (B_ - A_)])
        elif len(far):
            S = S[:2]
        beyond = tuple(S[-1])
        if v0f:
            S = S[::-1]
    if v0 is not None:
        S[0] = (v0.x, v0.y)
    if v1 is not None:
        S[-1] = (v1.x, v1.y)
    k0 = next(s for s in v0.sites if s not in pair) if v0 is not None else None
    k1 = next(s for s in v1.sites if s not in pair) if v1 is not None else None
    h0 = (v0.h * 2 + v0.tol) if v0 is not None else 0.0
    h1 = (v1.h * 2 + v1.tol) if v1 is not None else 0.0
    last_msg = None
    attempts = 0
    for refine in range(3):
        if refine:      # the polyline is only a guide: halve its segments, nodes moved onto β
            S = _refine(S, geoms[i], geoms[j])
        seg = S[1:] - S[:-1]
        L = np.hypot(seg[:, 0], seg[:, 1])
        if np.any(L <= 1e-12 * scale):
            keep = np.concatenate([[True], L > 1e-12 * scale])
            S = S[keep]
            seg = S[1:] - S[:-1]
            L = np.hypot(seg[:, 0], seg[:, 1])
        if len(S) < 2:
            return False, "degenerate polyline", None
        T = seg / L[:, None]
        N = _rot90(T)
        # turning angles between consecutive segments
        cosang = np.clip((T[:-1] * T[1:]).sum(1), -1, 1)
        if np.any(cosang < math.cos(math.radians(60))):
            last_msg = "polyline turns by more than 60 degrees"
            continue
        sinang = np.sqrt(1 - cosang ** 2)
        # node half-widths: about 3x the stated tolerance, at most a quarter of the adjacent segments
        Lmin = np.minimum(np.concatenate([[L[0]], L]), np.concatenate([L, [L[-1]]]))
        for wfac, endfac in ((1.0, 1e-3), (0.3, 1e-5), (3.0, 1e-3)):
            W = np.minimum(0.25 * Lmin, max(3 * tol, 1e-6 * scale) * wfac)
            W = np.maximum(W, 1e-12 * scale)
            # narrow at the vertices: the transversality test (T3) needs the gradient enclosures
            # (slack ~ 4R/d) well below the angle between the bisectors
            if v0 is not None:
                W[0] = max(min(W[0], 0.05 * L[0], endfac * (v0.r + 1.0)), 8 * h0 + 1e-12 * scale)
            if v1 is not None:
                W[-1] = max(min(W[-1], 0.05 * L[-1], endfac * (v1.r + 1.0)), 8 * h1 + 1e-12 * scale)
            wn = np.maximum(W[:-1], W[1:])
            e_lo = np.concatenate([[0.0], wn[:-1] * sinang]) + 1e-12 * scale
            e_hi = np.concatenate([wn[1:] * sinang, [0.0]]) + 1e-12 * scale
            e_lo[0] += 2 * h0
            e_hi[-1] += 2 * h1
            ok, msg = _prove_rects(op, geoms, S, T, N, L, e_lo, e_hi, W, pair, k0, k1, scale)
            if ok:
                return True, None, beyond
            last_msg = msg
            attempts += 1
            if attempts >= 4:
                return False, last_msg, beyond
            if "bisector leaves" in msg or "monotonicity" in msg:
                break       # refine the guide rather than try other widths
    return False, last_msg, beyond


def _refine(S, gi, gj):
    """Insert the midpoint of every segment, moved onto the bisector along the segment's normal
    (float secant steps on f = d_i − d_j; only a better guide, nothing is assumed of it)."""
    A, B = S[:-1], S[1:]
    M = 0.5 * (A + B)
    t = B - A
    n = np.column_stack([-t[:, 1], t[:, 0]]) / np.maximum(np.hypot(t[:, 0], t[:, 1]), 1e-300)[:, None]
    f = lambda X: gi.distance(X) - gj.distance(X)       # noqa: E731
    h = 1e-3 * np.hypot(t[:, 0], t[:, 1])
    lam0, lam1 = np.zeros(len(M)), h
    f0, f1 = f(M), f(M + lam1[:, None] * n)
    for _ in range(8):
        den = f1 - f0
        ok = np.abs(den) > 1e-300
        lam2 = np.where(ok, lam1 - f1 * (lam1 - lam0) / np.where(ok, den, 1.0), lam1)
        lam2 = np.clip(lam2, -0.5 * np.hypot(t[:, 0], t[:, 1]), 0.5 * np.hypot(t[:, 0], t[:, 1]))
        lam0, f0 = lam1, f1
        lam1, f1 = lam2, f(M + lam2[:, None] * n)
    Mn = np.where(np.isfinite(lam1)[:, None], M + lam1[:, None] * n, M)
    out = np.empty((2 * len(S) - 1, 2))
    out[0::2] = S
    out[1::2] = Mn
    return out


def _prove_rects(op, geoms, S, T, N, L, e_lo, e_hi, W, pair, k0, k1, scale):
    i, j = pair
    m = len(L)
    # ---- pieces: (segment, s-interval), full width; ordered along the edge
    slope = (W[1:] - W[:-1]) / L                     # half-width w(s) = W_l + slope_l·s (trapezoids)
    init = np.maximum(np.ceil((L + e_lo + e_hi) / (2 * np.minimum(W[:-1], W[1:]))).astype(int), 1)
    init = np.minimum(init, 400)
    seg_id = np.repeat(np.arange(m), init)
    frac0 = np.concatenate([np.arange(n) / n for n in init])
    frac1 = np.concatenate([np.arange(1, n + 1) / n for n in init])
    span = (L + e_lo + e_hi)[seg_id]
    sa = -e_lo[seg_id] + frac0 * span
    sb = -e_lo[seg_id] + frac1 * span
    start = np.concatenate([[0.0], np.cumsum(L)[:-1]])      # arc position of each segment start
    total = float(L.sum())
    # (T4) crossing, then (T1)(T2)(T3) on pieces, halving failures
    sigma = None
    work = 0
    for depth in range(MAX_DEPTH):
        sm = 0.5 * (sa + sb)
        C = S[seg_id] + sm[:, None] * T[seg_id]
        half = 0.5 * (sb - sa)
        wa = np.maximum(W[seg_id] + slope[seg_id] * sa, 0.0)
        wb = np.maximum(W[seg_id] + slope[seg_id] * sb, 0.0)
        w = 0.5 * (wa + wb)                           # half-width at the piece centre
        wmax = np.maximum(wa, wb)
        R = np.hypot(half, wmax) * (1 + 1e-12) + 1e-15 * scale
        side_len = half * np.sqrt(1 + slope[seg_id] ** 2) * (1 + 1e-12)
        lo_i, hi_i = op(i).bounds(C)
        lo_j, hi_j = op(j).bounds(C)
        Gi, si, vi = op(i).gradient(C, R)
        Gj, sj, vj = op(j).gradient(C, R)
        Df = Gi - Gj
        sf = si + sj
        mono = (Df * N[seg_id]).sum(1)
        if sigma is None:
            good = np.abs(mono) > sf
            if not good.any():
                return False, "the bisector's direction is not decided (monotonicity)"
            sigma = float(np.sign(mono[good][0]))
        t1 = sigma * mono - sf > 0
        # (T4) lateral sides of this piece: f at (s, ±w), 2-Lipschitz over the half length
        side_ok = np.ones(len(sa), bool)
        for lam, sg in ((w, 1.0), (-w, -1.0)):   # the lateral sides through (s_m, ±w(s_m))
            Qs = C + lam[:, None] * N[seg_id]
            li, hi_ = op(i).bounds(Qs)
            lj, hj = op(j).bounds(Qs)
            # change of f along the side: first order where the gradients are enclosed, else 2-Lipschitz
            tside = T[seg_id] + (sg * slope[seg_id])[:, None] * N[seg_id]
            tside /= np.hypot(*tside.T)[:, None]
            Gis, sis, vis = op(i).gradient(Qs, side_len)
            Gjs, sjs, vjs = op(j).gradient(Qs, side_len)
            rate = np.abs(((Gis - Gjs) * tside).sum(1)) + sis + sjs
            rate = np.where(vis & vjs & np.isfinite(rate), np.minimum(rate, 2.0), 2.0) * (1 + 1e-12)
            if sg * sigma > 0:      # f > 0 needed on this side
                side_ok &= (li - hj) - rate * side_len > 0
            else:                   # f < 0 needed
                side_ok &= (lj - hi_) - rate * side_len > 0
        # (T2)/(T3) third sites
        third_ok = np.ones(len(sa), bool)
        hi = np.minimum(hi_i, hi_j)
        cand = _candidates(geoms, C, hi + 2 * R, pair)
        pos = start[seg_id] + sm
        first_half = pos <= 0.5 * total
        for k in cand:
            lo_k, _ = op(k).bounds(C)
            t2 = lo_k - R > hi + R
            okk = t2.copy()
            for kk, want in ((k0, 1.0), (k1, -1.0)):
                if k != kk:
                    continue
                Gk, sk, vk = op(k).gradient(C, R)
                Dg = Gk - Gi
                sg_ = si + sk
                rf = _rot90(Df)
                st = np.sign((rf * T[seg_id]).sum(1))
                dec_t = np.abs((rf * T[seg_id]).sum(1)) > sf
                val = st * (Dg * rf).sum(1)
                err = np.hypot(*Dg.T) * sf + np.hypot(*Df.T) * sg_ + sf * sg_
                t3 = dec_t & vk & (want * val - err * (1 + 1e-9) - 1e-12 > 0)
                if k0 == k1:    # same third site at both ends: g' > 0 in the first half, < 0 in the second
                    t3 &= first_half if want > 0 else ~first_half
                okk |= t3
            third_ok &= okk
        good = t1 & side_ok & third_ok & vi & vj
        if good.all():
            return True, None
        work += len(sa)
        if depth == MAX_DEPTH - 1 or (~good).sum() > 20000 or work > 30000:
            b = int(np.nonzero(~good)[0][0])
            what = ("monotonicity" if not (t1[b] and vi[b] and vj[b]) else
                    "the bisector leaves the polyline's strip" if not side_ok[b] else "a third site")
            return False, f"not proved near ({C[b, 0]:.9g}, {C[b, 1]:.9g}): {what} undecided"
        bad = ~good
        # keep the good pieces out; halve the bad ones (the order along s is kept per segment)
        mid = 0.5 * (sa + sb)
        seg_id = np.concatenate([seg_id[bad], seg_id[bad]])
        sa, sb = np.concatenate([sa[bad], mid[bad]]), np.concatenate([mid[bad], sb[bad]])
    return False, "not proved"


def _candidates(geoms, C, reach, pair):
    """Sites whose bounding box comes within reach of some piece centre (rigorous: d(q, S) is at
    least the distance from q to the bounding box of S)."""
    out = []
    box = ((C[:, 0] - reach).min(), (C[:, 1] - reach).min(), (C[:, 0] + reach).max(), (C[:, 1] + reach).max())
    for k, g in enumerate(geoms):
        if k in pair:
            continue
        b = g.bounding_box()
        if b[0] > box[2] or b[2] < box[0] or b[1] > box[3] or b[3] < box[1]:
            continue
        dx = np.maximum(np.maximum(b[0] - C[:, 0], C[:, 0] - b[2]), 0.0)
        dy = np.maximum(np.maximum(b[1] - C[:, 1], C[:, 1] - b[3]), 0.0)
        dd = np.where(np.isfinite(dx) & np.isfinite(dy), np.hypot(dx, dy), 0.0)
        if np.any(dd * (1 - 1e-12) <= reach):
            out.append(k)
    return out
