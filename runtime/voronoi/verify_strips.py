"""A chain of strips that contains one arc of a bisector of convex sites (thesis §5.1–5.2).

Used by :mod:`runtime.voronoi.verify_curved` for an edge (i, j) whose bisector has no closed form
(one of i, j, or a third site, is an ellipse).  For each polyline segment, with unit direction
t, normal n and length L, take the rectangle (a trapezoid when the half-widths of its two nodes
differ) Π = {P_l + s·t + λ·n : s ∈ [−e, L + e], |λ| ≤ w(s)} (e covers the turn to the next
segment and the vertex boxes).  With f = d_i − d_j:

(T1) **monotone**: (∇d_i − ∇d_j)·n has one strict sign σ on Π;
(T4) **crossing**: σ·f > 0 on the side λ = +w and σ·f < 0 on the side λ = −w.

Then every cross-section s = const meets the bisector β exactly once, so β ∩ Π is one arc, a
graph over s (implicit function theorem).  The arc leaves Π through the cap s = L + e at
|λ| < w, inside the next rectangle (e ≥ w·|sin θ| for the turn θ), so the arcs chain into one
curve of β through both end vertices (each lies in the first / last rectangle).  Along it:

(T2) every other site k is proved farther on each piece (lo_k − R > min(hi_i, hi_j) + R on a disc
     of radius R covering the piece; d is 1-Lipschitz), or to first order
     d_k − d_i ≥ (lo_k − hi_i)(C) − R·(|G_k − G_i| + s_k + s_i) > 0 with the gradient enclosures
     G ± s on the disc (far from the sites all gradients are nearly equal, so the pieces may be
     much larger than the margin d_k − d_i); the same with j (d_i = d_j on β); sites whose
     bounding box is farther than min(hi_i, hi_j) + 2R from the piece's centre pass without
     evaluation;
(T3) or, for the third site k0 of the first vertex (k1 of the last), the derivative of
     g = d_k0 − d_i along the arc has a proved sign: the arc's tangent is ± rot90(∇f), so
     g' ∝ σ_t·(∇d_k0 − ∇d_i)·rot90(∇d_i − ∇d_j) (transversality at the vertex).  Since g = 0 at
     the vertex, g' > 0 on a run of pieces that starts at the vertex or after a (T2) piece keeps
     g > 0 (symmetrically g' < 0 before the last vertex).

Pieces are the rectangles cut across s; a piece that fails is halved (its two halves re-tested),
the others are done.  The gradients come with the enclosures of
:func:`runtime.voronoi.verify_sitetable.gradient_enclosure`.  :func:`prove_strips` is a
generator: it yields its requests of distance values to a
:class:`runtime.voronoi.verify_sitetable.SiteTable` (run with
:func:`runtime.voronoi.verify_sitetable.run_lockstep`, all edges side by side).
"""
from __future__ import annotations

import numpy as np

from .verify_sitetable import gradient_enclosure

__all__ = ["prove_strips", "rot90"]

MAX_DEPTH = 40
STALL = 3           # rounds of halving without progress before giving up
PIECE = 4.0         # initial pieces: PIECE times as long as the strip is wide


def rot90(V):
    return np.column_stack([-V[:, 1], V[:, 0]])


def prove_strips(table, S, T, N, L, e_lo, e_hi, W, pair, k0, k1, scale):
    """(T1)–(T4) on the trapezoids of the polyline S (segments T, N, L; node half-widths W; cap
    extensions e_lo, e_hi).  Generator; returns (ok, message or None)."""
    i, j = pair
    m = len(L)
    slope = (W[1:] - W[:-1]) / L                     # half-width w(s) = W_l + slope_l·s (trapezoids)
    init = np.maximum(np.ceil((L + e_lo + e_hi) / (2 * PIECE * np.minimum(W[:-1], W[1:]))).astype(int), 1)
    init = np.minimum(init, 400)
    seg_id = np.repeat(np.arange(m), init)
    frac0 = np.concatenate([np.arange(n) / n for n in init])
    frac1 = np.concatenate([np.arange(1, n + 1) / n for n in init])
    span = (L + e_lo + e_hi)[seg_id]
    sa = -e_lo[seg_id] + frac0 * span
    sb = -e_lo[seg_id] + frac1 * span
    start = np.concatenate([[0.0], np.cumsum(L)[:-1]])      # arc position of each segment start
    total = float(L.sum())
    sigma = None
    work = stall = 0
    for depth in range(MAX_DEPTH):
        p = len(sa)
        sm = 0.5 * (sa + sb)
        Tn, Nn = T[seg_id], N[seg_id]
        C = S[seg_id] + sm[:, None] * Tn
        half = 0.5 * (sb - sa)
        wa = np.maximum(W[seg_id] + slope[seg_id] * sa, 0.0)
        wb = np.maximum(W[seg_id] + slope[seg_id] * sb, 0.0)
        w = 0.5 * (wa + wb)                           # half-width at the piece centre
        wmax = np.maximum(wa, wb)
        R = np.hypot(half, wmax) * (1 + 1e-12) + 1e-15 * scale
        side_len = half * np.sqrt(1 + slope[seg_id] ** 2) * (1 + 1e-12)
        Qp, Qm = C + w[:, None] * Nn, C - w[:, None] * Nn
        V = yield (np.concatenate([C, C, Qp, Qp, Qm, Qm]), np.repeat([i, j, i, j, i, j], p))
        Vi, Vj = V.part(0, p), V.part(p, 2 * p)
        lo_i, hi_i, hi_j = Vi.lo, Vi.hi, Vj.hi
        Gi, si, vi = gradient_enclosure(C, Vi, R, scale)
        Gj, sj, vj = gradient_enclosure(C, Vj, R, scale)
        Df = Gi - Gj
        sf = si + sj
        mono = (Df * Nn).sum(1)
        if sigma is None:
            good = np.abs(mono) > sf
            if not good.any():
                return False, "the bisector's direction is not decided (monotonicity)"
            sigma = float(np.sign(mono[good][0]))
        t1 = sigma * mono - sf > 0
        # (T4) lateral sides of this piece: f at (s, ±w), first order along the side where the
        # gradients are enclosed, else 2-Lipschitz
        side_ok = np.ones(p, bool)
        for b, (Qs, sg) in enumerate(((Qp, 1.0), (Qm, -1.0))):
            Vis, Vjs = V.part((2 + 2 * b) * p, (3 + 2 * b) * p), V.part((3 + 2 * b) * p, (4 + 2 * b) * p)
            tside = Tn + (sg * slope[seg_id])[:, None] * Nn
            tside /= np.hypot(*tside.T)[:, None]
            Gis, sis, vis = gradient_enclosure(Qs, Vis, side_len, scale)
            Gjs, sjs, vjs = gradient_enclosure(Qs, Vjs, side_len, scale)
            rate = np.abs(((Gis - Gjs) * tside).sum(1)) + sis + sjs
            rate = np.where(vis & vjs & np.isfinite(rate), np.minimum(rate, 2.0), 2.0) * (1 + 1e-12)
            if sg * sigma > 0:      # f > 0 needed on this side
                side_ok &= (Vis.lo - Vjs.hi) - rate * side_len > 0
            else:                   # f < 0 needed
                side_ok &= (Vjs.lo - Vis.hi) - rate * side_len > 0
        # (T2)/(T3) third sites, only where (T1) and (T4) hold
        third_ok = np.ones(p, bool)
        pre = t1 & side_ok & vi & vj
        hi = np.minimum(hi_i, hi_j)
        rows, ks = table.near_pairs(C[pre], (hi + 2 * R)[pre], pair)
        rows = np.nonzero(pre)[0][rows]
        if len(rows):
            Vk = yield (C[rows], ks)
            Rr = R[rows]
            t2 = Vk.lo - Rr > hi[rows] + Rr
            okk = t2.copy()
            # (T2') first order: d_k − d_i ≥ (lo_k − hi_i)(C) − R·sup|∇d_k − ∇d_i| on the disc
            GK, SK, VK = gradient_enclosure(C[rows], Vk, Rr, scale)
            for G_, s_, v_, h_ in ((Gi, si, vi, hi_i), (Gj, sj, vj, hi_j)):
                lip = np.hypot(*(GK - G_[rows]).T) + SK + s_[rows]
                lip = np.where(VK & v_[rows] & np.isfinite(lip), np.minimum(lip, 2.0), 2.0) * (1 + 1e-12)
                okk |= Vk.lo - h_[rows] - lip * Rr > 0
            pos = start[seg_id[rows]] + sm[rows]
            for kk, want in ((k0, 1.0), (k1, -1.0)):
                sel = np.nonzero((ks == kk) & ~okk)[0]
                if kk is None or not len(sel):
                    continue
                r_ = rows[sel]
                Gk, sk, vk = GK[sel], SK[sel], VK[sel]
                Dg = Gk - Gi[r_]
                sg_ = si[r_] + sk
                rf = rot90(Df[r_])
                tt = (rf * Tn[r_]).sum(1)
                dec_t = np.abs(tt) > sf[r_]
                val = np.sign(tt) * (Dg * rf).sum(1)
                err = np.hypot(*Dg.T) * sf[r_] + np.hypot(*Df[r_].T) * sg_ + sf[r_] * sg_
                t3 = dec_t & vk & (want * val - err * (1 + 1e-9) - 1e-12 > 0)
                if k0 == k1:    # same third site at both ends: g' > 0 in the first half, < 0 in the second
                    t3 &= (pos[sel] <= 0.5 * total) if want > 0 else (pos[sel] > 0.5 * total)
                okk[sel] |= t3
            np.logical_and.at(third_ok, rows, okk)
        good = pre & third_ok
        if good.all():
            return True, None
        work += p
        nbad = int((~good).sum())
        # halving that decides (almost) no piece for STALL rounds will not decide them: the
        # strip, not the pieces, is too wide (R stays ≥ w); give up early, the caller narrows it
        stall = stall + 1 if nbad > 0.98 * p and depth >= 2 else 0
        if depth == MAX_DEPTH - 1 or nbad > 20000 or work > 30000 or stall >= STALL:
            b = int(np.nonzero(~good)[0][0])
            what = ("monotonicity" if not (t1[b] and vi[b] and vj[b]) else
                    "the bisector leaves the polyline's strip" if not side_ok[b] else "a third site")
            return False, f"not proved near ({C[b, 0]:.9g}, {C[b, 1]:.9g}): {what} undecided"
        bad = ~good
        # keep the good pieces out; halve the bad ones
        seg_id = np.concatenate([seg_id[bad], seg_id[bad]])
        sa, sb = np.concatenate([sa[bad], sm[bad]]), np.concatenate([sm[bad], sb[bad]])
    return False, "not proved"
