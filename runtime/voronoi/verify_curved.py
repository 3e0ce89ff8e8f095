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


# ============================================================================ support functions

class SupportTable:
    """Support functions of bounded convex sites about the centre m of their bounding boxes.

    h_k(θ) = max_{p ∈ S_k} u(θ)·(p − m) (ellipses: :func:`runtime.interval.bound.support_function`,
    exact up to rounding: h(u) = u·(c − m) + sqrt(uᵀAu)); h_k'(θ) = (p_k(θ) − m)·u⊥(θ) with p_k(θ)
    the support point (∇ of h in u); ρ_k bounds the radius of curvature (a²/b for an ellipse with
    semi-axes a ≥ b, r for a circle, 0 for a point), so h_k + h_k'' = ρ_k(θ) ∈ [0, ρ_k] and the
    support point moves by at most ρ_k·|Δθ|.  W ≥ max_{p ∈ ∪S} |p − m|, so |h_k| ≤ W and
    |h_k'| ≤ W.  Every float value is widened by ``mu`` (rounding of the float data and of the
    evaluation, relative to the scene's size, with a wide margin).  ``ok`` is False when a site is
    not a point, circle or ellipse (no support function)."""

    def __init__(self, geoms):
        from ..interval.bound import support_function
        from ..interval.curves import parse_curve

        self.n = len(geoms)
        self.ok = all(g.kind in ("point", "circle", "ellipse") for g in geoms) and self.n > 0
        if not self.ok:
            return
        bx = np.array([g.bounding_box() for g in geoms], float)
        self.m = 0.5 * (bx[:, :2].min(0) + bx[:, 2:].max(0))
        self.kind, self.cen, self.rho, self.ell = [], [], [], []
        W = 0.0
        for g in geoms:
            if g.kind == "point":
                c, r, rc = (g.x0, g.y0), 0.0, 0.0
                self.ell.append(None)
            elif g.kind == "circle":
                c, r, rc = (g.cx, g.cy), g.rho, g.rho
                self.ell.append(None)
            else:
                c, r = (g.tx, g.ty), max(g.a, g.b)
                rc = max(g.a, g.b) ** 2 / min(g.a, g.b)
                self.ell.append((parse_curve(g.exact), g.a, g.b, g.c / math.hypot(g.c, g.s), g.s / math.hypot(g.c, g.s)))
            self.kind.append(g.kind)
            self.cen.append(c)
            self.rho.append(r)
            W = max(W, math.hypot(c[0] - self.m[0], c[1] - self.m[1]) + r)
        self.cen = np.array(self.cen, float)
        self.rho = np.array(self.rho, float)
        self.rcurv = np.array([max(g.a, g.b) ** 2 / min(g.a, g.b) if g.kind == "ellipse" else
                               (g.rho if g.kind == "circle" else 0.0) for g in geoms], float) * (1 + 1e-9)
        self.mu = 1e-11 * (W + float(np.abs(self.m).sum()) + float(np.abs(self.cen).max()) + 1.0)
        self.W = W * (1 + 1e-9) + self.mu
        self._sf = support_function

    def h(self, k, th):
        """Float h_k(θ) (error ≤ mu)."""
        th = np.asarray(th, float)
        ux, uy = np.cos(th), np.sin(th)
        e = self.ell[k]
        if e is not None:
            lo, _ = self._sf(e[0], ux, uy, tuple(self.m))
            return np.asarray(lo, float)
        c = self.cen[k]
        return ux * (c[0] - self.m[0]) + uy * (c[1] - self.m[1]) + self.rho[k]

    def hp(self, k, th):
        """Float h_k'(θ) = (p_k(θ) − m)·u⊥(θ) (error ≤ mu)."""
        th = np.asarray(th, float)
        ux, uy = np.cos(th), np.sin(th)
        c = self.cen[k]
        v = -uy * (c[0] - self.m[0]) + ux * (c[1] - self.m[1])
        e = self.ell[k]
        if e is not None:
            _, a, b, cs, sn = e
            uX, uY = cs * ux + sn * uy, -sn * ux + cs * uy
            vX, vY = cs * (-uy) + sn * ux, -sn * (-uy) + cs * ux
            v = v + (a * a * uX * vX + b * b * uY * vY) / np.sqrt(a * a * uX * uX + b * b * uY * uY)
        return v

    def h_range(self, k, thc, half):
        """Enclosure of h_k on [θc − half, θc + half] (|h'| ≤ W)."""
        v = self.h(k, thc)
        r = self.W * half + self.mu
        return v - r, v + r


def _imul(a0, a1, b0, b1):
    """Interval product [a0, a1]·[b0, b1] (float; callers add their own margins)."""
    p = np.stack([a0 * b0, a0 * b1, a1 * b0, a1 * b1])
    return p.min(0), p.max(0)


def _eps(W, t0):
    """W²/(2(t0 − W)): d(m + t·u, S) − (t − h_S(u)) ∈ [0, this] for t ≥ t0 > W (tail docstring)."""
    return W * W / (2.0 * (t0 - W)) * (1 + 1e-12)


def prove_tail(sup: SupportTable, geoms, pair, link, scale, max_work: int = 200000):
    """Prove the unbounded end of the edge (i, j) beyond the link point (see :data:`TAIL_DOC`).

    ``link`` = (P0, t, n, L, w, s_x): the chain's last rectangle {P0 + s·t + λ·n : s ∈ [0, L],
    |λ| ≤ w} (proved: β meets it in one arc, all of it closer to i, j than to other sites) and
    the position s_x on its axis where the link circle crosses it.  Returns (ok, message, sector)
    with sector = (θa, θb, σ) the angular sector of the asymptotic direction."""
    i, j = pair
    if not sup.ok:
        return False, "the tail needs bounded convex sites (points, circles, ellipses)", None
    m, W = sup.m, sup.W
    P0, tv, nv, L, w, sx = link
    X = np.asarray(P0, float) + sx * np.asarray(tv, float)
    r = float(math.hypot(X[0] - m[0], X[1] - m[1]))
    if not r > 2.0 * W:
        return False, "the proved part does not reach far enough for the tail argument", None
    thX = math.atan2(X[1] - m[1], X[0] - m[0])
    # ---- the asymptotic direction: a zero of g = h_i − h_j where i, j are the two largest
    grid = thX + np.linspace(-math.pi, math.pi, 4097)
    g = sup.h(i, grid) - sup.h(j, grid)
    hij = np.maximum(sup.h(i, grid), sup.h(j, grid))
    top = np.full(len(grid), -np.inf)
    for k in range(sup.n):
        if k not in pair:
            top = np.maximum(top, sup.h(k, grid))
    ch = np.nonzero((np.sign(g[:-1]) != np.sign(g[1:])) & (hij[:-1] > top[:-1]) & (hij[1:] > top[1:]))[0]
    if not len(ch):
        return False, "no direction where its two sites lead the support functions", None
    c0 = int(ch[np.argmin(np.abs(grid[ch] - thX))])
    a_, b_ = grid[c0], grid[c0 + 1]
    ga = sup.h(i, a_) - sup.h(j, a_)
    for _ in range(60):
        mid = 0.5 * (a_ + b_)
        gm = sup.h(i, mid) - sup.h(j, mid)
        if np.sign(gm) == np.sign(ga):
            a_, ga = mid, gm
        else:
            b_ = mid
    ths = 0.5 * (a_ + b_)
    # ---- the link: two points of the circle |q − m| = r inside the rectangle, f of opposite signs
    dl = 0.5 * w / r
    sag = r * dl * dl
    Q = np.array([[m[0] + r * math.cos(thX + s * dl), m[1] + r * math.sin(thX + s * dl)] for s in (-1.0, 1.0)])
    rel = Q - np.asarray(P0, float)
    sc, lc = rel @ np.asarray(tv, float), rel @ np.asarray(nv, float)
    pad = sag + 1e-12 * scale
    if not (np.all(sc > pad) and np.all(sc < L - pad) and np.all(np.abs(lc) < w - pad)):
        return False, "the link circle does not cross the last proved strip", None
    lo_i, hi_i = geoms[i].distance_bounds(Q)
    lo_j, hi_j = geoms[j].distance_bounds(Q)
    pos = lo_i - hi_j > 0
    neg = hi_i - lo_j < 0
    if not ((pos[0] and neg[1]) or (neg[0] and pos[1])):
        return False, "the bisector's crossing of the link circle is not decided", None
    msg = "no sector decided"
    for half in (0.4, 0.2, 0.1, 0.05, 0.025, 0.0125):
        tha, thb = ths - half, ths + half
        if not (tha < thX - dl and thX + dl < thb):
            continue
        gb = float(sup.h(i, thb) - sup.h(j, thb))
        ga = float(sup.h(i, tha) - sup.h(j, tha))
        if not (gb * ga < 0):
            continue
        sigma = -1.0 if gb > 0 else 1.0          # σ·f > 0 on the ray θb, f ≈ −g far away
        ok, msg = _prove_sector(sup, geoms, pair, tha, thb, sigma, r, scale, max_work)
        if ok:
            return True, None, (tha, thb, sigma)
    return False, msg, None


def _prove_sector(sup, geoms, pair, tha, thb, sigma, T0, scale, max_work):
    """(A) third sites, (M) σ·∂f/∂θ > 0 on Σ = {t ≥ T0, θ ∈ [θa, θb]}, (R) σ·f < 0 on the ray θa
    and > 0 on the ray θb; cells in (τ = 1/t, θ), halved until decided (TAIL_DOC)."""
    i, j = pair
    W, m, mu = sup.W, sup.m, sup.mu
    others = [k for k in range(sup.n) if k not in pair]
    opi, opj = _SiteOps(geoms[i], scale), _SiteOps(geoms[j], scale)
    ops = {k: _SiteOps(geoms[k], scale) for k in others}
    tmax = 1.0 / T0
    # ---- rays: 1-D cells in τ
    for th, want in ((tha, -1.0), (thb, 1.0)):
        gv = float(sup.h(i, th) - sup.h(j, th))
        T_a, T_b = np.array([0.0]), np.array([tmax])
        work = 0
        while len(T_a):
            work += len(T_a)
            if work > max_work:
                return False, f"the sign of d_{i} - d_{j} on the ray at angle {th:.6g} is undecided"
            t0 = 1.0 / T_b
            eps = _eps(W, t0)
            ok = want * sigma * (-gv) - eps - 2 * mu > 0        # f = −g + e, |e| ≤ ε
            fin = T_a > 0
            if fin.any():
                t1 = np.where(fin, 1.0 / np.where(fin, T_a, 1.0), np.inf)
                tc = 0.5 * (t0 + t1)
                C = m + tc[:, None] * np.array([math.cos(th), math.sin(th)])
                R = np.where(fin, 0.5 * (t1 - t0), np.inf) * (1 + 1e-12)
                li, hi_ = opi.bounds(C)
                lj, hj = opj.bounds(C)
                fl, fh = li - hj - 2 * R, hi_ - lj + 2 * R
                ok |= fin & (((want * sigma > 0) & (fl > 0)) | ((want * sigma < 0) & (fh < 0)))
            bad = ~ok
            if not bad.any():
                break
            a_, b_ = T_a[bad], T_b[bad]
            mid = 0.5 * (a_ + b_)
            T_a, T_b = np.concatenate([a_, mid]), np.concatenate([mid, b_])
    # ---- the sector: 2-D cells
    nt, nth = 8, 8
    ta = np.repeat(np.linspace(0, tmax, nt + 1)[:-1], nth)
    tb = np.repeat(np.linspace(0, tmax, nt + 1)[1:], nth)
    tb[-nth:] = tmax
    e = np.linspace(tha, thb, nth + 1)
    h0 = np.tile(e[:-1], nt)
    h1 = np.tile(e[1:], nt)
    work = 0
    while len(ta):
        work += len(ta)
        if work > max_work:
            k = int(np.argmax(tb))
            return False, f"the tail is undecided near angle {0.5 * (h0[k] + h1[k]):.6g}"
        thc, half = 0.5 * (h0 + h1), 0.5 * (h1 - h0) * (1 + 1e-12)
        t0 = 1.0 / tb
        eps = _eps(W, t0)
        fin = ta > 0
        t1 = np.where(fin, 1.0 / np.where(fin, ta, 1.0), np.inf)
        tc = np.where(fin, 0.5 * (t0 + t1), t0)
        U = np.column_stack([np.cos(thc), np.sin(thc)])
        C = m + tc[:, None] * U
        R = np.where(fin, t1 * half + 0.5 * (t1 - t0), np.inf) * (1 + 1e-12) + 1e-15 * scale
        # (A) third sites: support bounds, or distance bounds on the cell's disc
        li_s, _ = sup.h_range(i, thc, half)
        lj_s, _ = sup.h_range(j, thc, half)
        hmax_lo = np.maximum(li_s, lj_s)
        okA = np.ones(len(ta), bool)
        if fin.any():
            Cf = np.where(fin[:, None], C, m + T0 * U)
            _, hi_i = opi.bounds(Cf)
            _, hi_j = opj.bounds(Cf)
            hi_min = np.minimum(hi_i, hi_j)
        for k in others:
            _, hk = sup.h_range(k, thc, half)
            okk = hmax_lo - hk - eps > 0
            if fin.any() and not okk.all():
                lo_k, _ = ops[k].bounds(Cf)
                okk |= fin & (lo_k - R > hi_min + R)
            okA &= okk
        # (M) σ·∂f/∂θ > 0: support-point enclosure (TAIL_DOC) or gradient enclosures on the disc
        Wt = W * tb
        alpha = np.arcsin(np.minimum(1.0, Wt / (1 - Wt)))
        k_lo, k_hi = 1.0 / (1 + Wt), 1.0 / (1 - Wt)
        parts = []
        for s in (i, j):
            pc = sup.hp(s, thc)
            rr = sup.rcurv[s] * (alpha + half) + W * half + mu
            parts.append(_imul(k_lo, k_hi, pc - rr, pc + rr))
        d_lo = parts[1][0] - parts[0][1]          # −κ_i P_i + κ_j P_j
        d_hi = parts[1][1] - parts[0][0]
        d_lo, d_hi = d_lo - 1e-12 * W, d_hi + 1e-12 * W
        okM = (d_lo > 0) if sigma > 0 else (d_hi < 0)
        if fin.any() and not okM.all():
            Gi, si, vi = opi.gradient(Cf, np.where(fin, R, 0.0))
            Gj, sj, vj = opj.gradient(Cf, np.where(fin, R, 0.0))
            Df = Gi - Gj
            perp = np.column_stack([-U[:, 1], U[:, 0]])
            val = sigma * (Df * perp).sum(1) - np.hypot(Df[:, 0], Df[:, 1]) * half - (si + sj) - 1e-12
            okM |= fin & vi & vj & (val > 0)
        bad = ~(okA & okM)
        if not bad.any():
            return True, None
        # halve the undecided cells in both τ and θ
        a_, b_, c_, d_ = ta[bad], tb[bad], h0[bad], h1[bad]
        mt, mh = 0.5 * (a_ + b_), 0.5 * (c_ + d_)
        ta = np.concatenate([a_, a_, mt, mt])
        tb = np.concatenate([mt, mt, b_, b_])
        h0 = np.concatenate([c_, mh, c_, mh])
        h1 = np.concatenate([mh, d_, mh, d_])
    return True, None
