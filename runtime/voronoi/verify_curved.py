"""Proofs for Voronoi edges of convex curved sites (ellipses, mixed with circles and points).

Used by :mod:`runtime.voronoi.verify` for an edge (i, j) between two proved vertices when one of
i, j (or a third site of an end vertex) is an ellipse, where the bisector has no closed form.
The reported polyline only guides the proof: its nodes are moved onto β (float secant steps),
nodes where it turns back are dropped, and a segment is split (its projected midpoint inserted)
while the arc strays from the chord by more than a tenth of the wanted strip half-width
(about 3x the stated tolerance, at most 0.03·d·|∇d_i − ∇d_j|); when a third site stays undecided
the strips are narrowed (factors 0.2, 0.05) and the guide re-split.  For each polyline segment, with unit direction t,
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

**Unbounded edges** (:func:`prove_tail`).  The chain above proves the edge from its vertex up to
a polyline point at about ``TAIL_CUT`` times the scene's radius; beyond, support functions
(thesis §1.2 on far regions; Schneider, *Convex Bodies*, §1.7) take over.  Let every site lie
in the disc D(m, W) and h_S(θ) = max_{p ∈ S} u(θ)·(p − m) (:class:`SupportTable`; ellipses via
:func:`runtime.interval.bound.support_function`).  For q = m + t·u, t > W:

* d(q, S) ≥ t − h_S(u) (the supporting line of conv S with normal u separates q from S);
* d(q, S) ≤ |q − p_u| = √((t − h)² + h'(θ)²) ≤ t − h_S(u) + h_S'(θ)²/(2(t − W)), p_u the support
  point, whose component across u is h'(θ) (so e_S := d − (t − h_S) ∈ [0, h'²/(2(t − W))]);
* for the gradient, ∇d_S(q) = (q − p)/|q − p| with p the nearest point, the support point of the
  normal direction ν, |ν − u| ≤ α = asin(W/(t − W)); the support point moves by at most ρ_S·|Δθ|
  (ρ_S the largest radius of curvature: a²/b, r, 0), and h_S + h_S'' = ρ_S(θ) ∈ [0, ρ_S], so
  t·∂_θ d_S = −κ_S·(p − m)·u⊥ with κ_S = t/|q − p| ∈ [1/(1 + W/t), 1/(1 − W/t)] and
  (p − m)·u⊥ ∈ h_S'(θ_c) ± (ρ_S(α + δ) + W·δ) on an angular cell of half-width δ.

m is moved, for the tail of (i, j), onto the normal line of p_i at the float asymptotic direction
θ* (a zero of g = h_i − h_j where i, j lead), so that h_i' ≈ 0 and the bound on e_i is sharp.
On the sector Σ = {t ≥ T, θ ∈ [θa, θb]} ∋ θ*, with f = d_i − d_j ∈ [−g − e_j, −g + e_i], cells in
(τ = 1/t, θ) (τ = 0 included, so Σ is covered to infinity), each halved until it satisfies

(F) f has one strict sign on the cell (β does not meet it), or
(A)+(M) every other site k is farther than d_i = d_j on the cell (max(h_i − e_i, h_j − e_j) > h_k,
    or the distance bounds on the cell's disc as in (T2), or to first order
    d_k − d_i ≥ lo_k(C) − hi_i(C) − R·(|G_k − G_i| + s_k + s_i) with the gradient enclosures) and
    σ·∂f/∂θ > 0 on it (the enclosure above, or the gradient enclosures on the cell's disc);

and on the rays θa, θb: σ·f < 0, resp. > 0, for all t ≥ T (τ-intervals, same bounds).  Then on
every circle t = const ≥ T, θ ↦ f is negative then positive (σ = 1) with all its zeros in (M)
cells, where it strictly increases: exactly one zero θ(t), continuous (implicit functions).  So
β ∩ Σ is one curve from the circle t = T to infinity, closer to i, j than to every other site,
with the asymptotic direction in the sector.  **Link**: two points Q± of the circle t = T inside
the chain's last rectangle (shrunk by the arc's sagitta), with f(Q−), f(Q+) of opposite proved
signs, bracket θ(T): the curve starts inside that rectangle, on the chain's arc (β meets the
rectangle in one arc, all proved).  Hence chain ∪ tail is the whole edge from its vertex to
infinity.  For the accounting of ends at infinity, :func:`prove_tail` also returns an interval
J = [α, β] ∋ θ* inside the sector on which only i and j attain max_k h_k and g has strict opposite
signs at α and β.  Not proved (reported): tails whose chain does not reach T > 2W, a lead of i, j
too narrow for the 4096-direction scan, cells undecided within the work limit.  Vertex-less
edges (two sites only, nested sites) of conic sites are not handled.
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["prove_curved_edge", "prove_tail", "SupportTable"]

EPS = 2.0 ** -53
MAX_DEPTH = 40
TAIL_CUT = 12.0         # the chain proves an unbounded edge up to TAIL_CUT·(scene radius), the tail beyond


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
    be None = infinity, then up to a point at ``TAIL_CUT`` times the scene's radius).  Returns
    (ok, message or None, beyond): for an unbounded edge proved so far, ``beyond`` is a dict with
    the cut ``point`` and the ``link`` rectangle for :func:`prove_tail`."""
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
    v0f, rad = False, 0.0
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
        far = np.nonzero(dist > TAIL_CUT * rad)[0]
        if len(far) and far[0] > 0:
            f0 = int(far[0])                       # cut the chord where it leaves the disc of radius 3·rad
            A_, B_ = S[f0 - 1], S[f0]
            lo_t, hi_t = 0.0, 1.0
            for _ in range(60):
                mt = 0.5 * (lo_t + hi_t)
                if np.hypot(*(A_ + mt * (B_ - A_) - cen)) > TAIL_CUT * rad:
                    hi_t = mt
                else:
                    lo_t = mt
            S = np.vstack([S[:f0], A_ + hi_t * (B_ - A_)])
        elif len(far):
            S = S[:2]
        beyond = tuple(S[-1])
        if v0f:
            S = S[::-1]
    if len(S) >= 2:
        # the nodes are only a guide: move them onto β (also the cut of an unbounded end)
        lo_k = 1 if v0 is not None else 0
        hi_k = len(S) - 1 if v1 is not None else len(S)
        ks = np.arange(lo_k, hi_k)
        if len(ks):
            dirs = S[np.minimum(ks + 1, len(S) - 1)] - S[np.maximum(ks - 1, 0)]
            Xn, dev = _project(S[ks], dirs, geoms[i], geoms[j])
            okn = np.isfinite(dev) & np.isfinite(Xn).all(1)
            S[ks[okn]] = Xn[okn]
        for _ in range(len(S)):
            # drop inner nodes where the guide turns back (off-bisector or misplaced points)
            if len(S) < 3:
                break
            sg = S[1:] - S[:-1]
            Tg = sg / np.maximum(np.hypot(sg[:, 0], sg[:, 1]), 1e-300)[:, None]
            cg = (Tg[:-1] * Tg[1:]).sum(1)
            if not cg.min() < 0.5:
                break
            S = np.delete(S, int(np.argmin(cg)) + 1, axis=0)
    if v0 is not None:
        S[0] = (v0.x, v0.y)
    if v1 is not None:
        S[-1] = (v1.x, v1.y)
    k0 = next(s for s in v0.sites if s not in pair) if v0 is not None else None
    k1 = next(s for s in v1.sites if s not in pair) if v1 is not None else None
    h0 = (v0.h * 2 + v0.tol) if v0 is not None else 0.0
    h1 = (v1.h * 2 + v1.tol) if v1 is not None else 0.0
    S_guide = S
    for narrow in (1.0, 0.2, 0.05):
        S = S_guide.copy()
        last_msg = None
        attempts = 0
        for refine in range(3):
            if refine:      # the polyline is only a guide: halve its segments, nodes moved onto β
                S = _refine(S, geoms[i], geoms[j])
            # split where the arc strays from the chord by more than a fraction of the strip width
            S = _adapt(S, geoms[i], geoms[j], lambda X: 0.1 * narrow * _node_width(X, geoms[i], geoms[j], tol, scale))
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
            wnode = narrow * _node_width(S, geoms[i], geoms[j], tol, scale)
            # node half-widths: about 3x the stated tolerance, at most a quarter of the adjacent segments
            Lmin = np.minimum(np.concatenate([[L[0]], L]), np.concatenate([L, [L[-1]]]))
            for wfac, endfac in ((1.0, 1e-3), (0.3, 1e-5), (3.0, 1e-3)):
                W = np.minimum(0.25 * Lmin, wnode * wfac)
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
                    if beyond is not None:
                        # the chain's rectangle at the unbounded end, for the link with the tail
                        l = 0 if v0f else len(L) - 1
                        sx = min(0.5 * L[l], 0.25 * rad)
                        beyond = {"point": beyond, "rad": rad,
                                  "link": (S[l].copy(), T[l].copy(), N[l].copy(), float(L[l]),
                                           float(min(W[l], W[l + 1])), sx if v0f else float(L[l]) - sx)}
                    return True, None, beyond
                last_msg = msg
                attempts += 1
                if attempts >= 4:
                    break
                if "bisector leaves" in msg or "monotonicity" in msg:
                    break       # refine the guide rather than try other widths
            if attempts >= 4:
                break
        # a third site undecided: the strips (and the pieces' discs) are too wide; narrow them
        if last_msg is None or "a third site" not in last_msg:
            break
    return False, last_msg, beyond


def _project_mid(A, B, gi, gj):
    """Midpoints of the segments [A, B] moved onto the bisector along the segments' normals
    (float secant steps on f = d_i − d_j; only a better guide, nothing is assumed of it).
    Returns (points, offsets)."""
    return _project(0.5 * (A + B), B - A, gi, gj)


def _project(M, t, gi, gj):
    """Points M moved onto the bisector along the normals of the directions t (float secant
    steps, moves at most |t|/2).  Returns (points, offsets)."""
    Ls = np.maximum(np.hypot(t[:, 0], t[:, 1]), 1e-300)
    n = np.column_stack([-t[:, 1], t[:, 0]]) / Ls[:, None]
    f = lambda X: gi.distance(X) - gj.distance(X)       # noqa: E731
    lam0, lam1 = np.zeros(len(M)), 1e-3 * Ls
    f0, f1 = f(M), f(M + lam1[:, None] * n)
    fM = np.abs(f0)
    for _ in range(8):
        den = f1 - f0
        ok = np.abs(den) > 1e-300
        lam2 = np.where(ok, lam1 - f1 * (lam1 - lam0) / np.where(ok, den, 1.0), lam1)
        lam2 = np.clip(lam2, -0.5 * Ls, 0.5 * Ls)
        lam0, f0 = lam1, f1
        lam1, f1 = lam2, f(M + lam2[:, None] * n)
    good = np.isfinite(lam1) & np.isfinite(f1) & ((np.abs(f1) <= 1e-3 * fM) | (np.abs(f1) < 1e-12 * (1 + np.abs(M).sum(1))))
    Mn = np.where(good[:, None], M + np.where(good, lam1, 0.0)[:, None] * n, M)
    return Mn, np.where(good, np.abs(lam1), np.inf)


def _node_width(X, gi, gj, tol, scale):
    """Strip half-width wanted at the polyline nodes X: about 3x the stated tolerance, at most a
    small fraction of d·|∇d_i − ∇d_j| (the gradient enclosures of the monotonicity test
    (T1) have slack ~ 4R/d)."""
    X = np.asarray(X, float).reshape(-1, 2)
    with np.errstate(divide="ignore", invalid="ignore"):
        Fi, _ = gi.foot_points(X)
        Fj, _ = gj.foot_points(X)
        Vi, Vj = X - Fi, X - Fj
        di = np.hypot(Vi[:, 0], Vi[:, 1])
        dj = np.hypot(Vj[:, 0], Vj[:, 1])
        D = Vi / di[:, None] - Vj / dj[:, None]
        c = 0.03 * np.minimum(di, dj) * np.hypot(D[:, 0], D[:, 1])
    c = np.where(np.isfinite(c), c, 0.0)
    return np.maximum(np.minimum(max(3 * tol, 1e-6 * scale), c), 1e-9 * scale)


def _refine(S, gi, gj, sel=None):
    """Insert the midpoint of every segment (or of the selected ones), moved onto the bisector
    (:func:`_project_mid`)."""
    if sel is None:
        sel = np.ones(len(S) - 1, bool)
    Mn, _ = _project_mid(S[:-1][sel], S[1:][sel], gi, gj)
    return _insert(S, sel, Mn)


def _insert(S, sel, Mn):
    out = np.empty((len(S) + int(sel.sum()), 2))
    pos = np.arange(len(S)) + np.concatenate([[0], np.cumsum(sel)])
    out[pos] = S
    out[pos[:-1][sel] + 1] = Mn
    return out


def _adapt(S, gi, gj, target, rounds=12, cap=4000):
    """Split the segments whose bisector arc strays more than ``target`` from the chord (offset
    of the projected midpoint, float), to a bounded depth: the strips of :func:`_prove_rects`
    must contain the arc.  Only a guide; the proof decides."""
    for _ in range(rounds):
        Mn, dev = _project_mid(S[:-1], S[1:], gi, gj)
        tn = target(S)
        Ls = np.hypot(*(S[1:] - S[:-1]).T)
        sel = (dev > np.minimum(tn[:-1], tn[1:])) & (dev < 0.25 * Ls)     # else the projection is not trusted
        if not sel.any() or len(S) + int(sel.sum()) > cap:
            break
        S = _insert(S, sel, Mn[sel])
    return S


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
                c, r = (g.x0, g.y0), 0.0
                self.ell.append(None)
            elif g.kind == "circle":
                c, r = (g.cx, g.cy), g.rho
                self.ell.append(None)
            else:
                c, r = (g.tx, g.ty), max(g.a, g.b)
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

    def recentred(self, m):
        """The same table about another centre m (W and mu recomputed)."""
        import copy

        t = copy.copy(self)
        t.m = np.asarray(m, float)
        W = float(np.max(np.hypot(self.cen[:, 0] - t.m[0], self.cen[:, 1] - t.m[1]) + self.rho))
        t.mu = 1e-11 * (W + float(np.abs(t.m).sum()) + float(np.abs(self.cen).max()) + 1.0)
        t.W = W * (1 + 1e-9) + t.mu
        return t

    def hp_abs(self, k, thc, half):
        """Bound on |h_k'| on [θc − half, θc + half] (|h''| ≤ ρ_k + W)."""
        return np.abs(self.hp(k, thc)) + (self.rcurv[k] + self.W) * half + self.mu

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


def _eps1(hp_abs, W, t0):
    """h'²/(2(t0 − W)): d(m + t·u, S) − (t − h_S(u)) ∈ [0, this] when |h_S'(u)| ≤ hp_abs, t ≥ t0 > W."""
    return hp_abs * hp_abs / (2.0 * (t0 - W)) * (1 + 1e-12)


def prove_tail(sup: SupportTable, geoms, pair, link, scale, max_work: int = 100000):
    """Prove the unbounded end of the edge (i, j) beyond the link point (module docstring,
    *Unbounded edges*).

    ``link`` = (P0, t, n, L, w, s_x): the chain's last rectangle {P0 + s·t + λ·n : s ∈ [0, L],
    |λ| ≤ w} (proved: β meets it in one arc, all of it closer to i, j than to other sites) and
    the position s_x on its axis where the link circle crosses it.  Returns (ok, message, J)
    with J = (α, β, σ): the interval of directions for the accounting (module docstring)."""
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
    for npts in (4097, 65537):
        grid = thX + np.linspace(-math.pi, math.pi, npts)
        g = sup.h(i, grid) - sup.h(j, grid)
        hij = np.maximum(sup.h(i, grid), sup.h(j, grid))
        top = np.full(len(grid), -np.inf)
        for k in range(sup.n):
            if k not in pair:
                top = np.maximum(top, sup.h(k, grid))
        ch = np.nonzero((np.sign(g[:-1]) != np.sign(g[1:])) & (hij[:-1] > top[:-1]) & (hij[1:] > top[1:]))[0]
        if len(ch):
            break
    else:
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
    # centre on the normal line of site i's support point in the asymptotic direction: there
    # h_i' ≈ 0, which makes the upper bound d_i ≤ t − h_i + h_i'²/(2(t − W)) sharp (module docstring)
    m = m + float(sup.hp(i, ths)) * np.array([-math.sin(ths), math.cos(ths)])
    sup = sup.recentred(m)
    W = sup.W
    r = float(math.hypot(X[0] - m[0], X[1] - m[1]))
    if not r > 2.0 * W:
        return False, "the proved part does not reach far enough for the tail argument", None
    thX = math.atan2(X[1] - m[1], X[0] - m[0])
    ths = thX + ((ths - thX + math.pi) % (2 * math.pi)) - math.pi     # same branch as thX
    # ---- the link: two points of the circle |q − m| = r inside the rectangle, near its two
    # lateral sides (where the chain proved f's signs), with f of opposite signs
    tv, nv, P0 = np.asarray(tv, float), np.asarray(nv, float), np.asarray(P0, float)

    def lat(phi):
        return (m + r * np.array([math.cos(phi), math.sin(phi)]) - P0) @ nv

    dlat = -math.sin(thX) * nv[0] + math.cos(thX) * nv[1]
    if abs(dlat) < 0.2:
        return False, "the link circle is nearly tangent to the last proved strip", None
    Qs = []
    for target in (-0.97 * w, 0.97 * w):
        a_, b_ = thX, thX + 2.0 * (target - lat(thX)) / (r * dlat)
        for _ in range(80):                                 # float bisection on λ(φ) = target
            mid = 0.5 * (a_ + b_)
            if (lat(mid) - target) * (lat(a_) - target) > 0:
                a_ = mid
            else:
                b_ = mid
        Qs.append(0.5 * (a_ + b_))
    phi_lo, phi_hi = min(Qs), max(Qs)
    dl = 0.5 * (phi_hi - phi_lo)
    sag = r * dl * dl
    Q = np.array([[m[0] + r * math.cos(p_), m[1] + r * math.sin(p_)] for p_ in (phi_lo, phi_hi)])
    rel = Q - P0
    sc, lc = rel @ tv, rel @ nv
    pad = sag + 1e-12 * scale
    if not (np.all(sc > pad) and np.all(sc < L - pad) and np.all(np.abs(lc) < w - pad)):
        return False, "the link circle does not cross the last proved strip", None
    lo_i, hi_i = geoms[i].distance_bounds(Q)
    lo_j, hi_j = geoms[j].distance_bounds(Q)
    fl = 4e-12 * (scale + r)        # Q is a float point within ~1e-15·r of the circle; f is 2-Lipschitz
    pos = lo_i - hi_j > fl
    neg = hi_i - lo_j < -fl
    if not ((pos[0] and neg[1]) or (neg[0] and pos[1])):
        return False, "the bisector's crossing of the link circle is not decided", None
    thX = 0.5 * (phi_lo + phi_hi)
    msg = "no sector decided"
    lo0, hi0 = min(ths, thX - dl), max(ths, thX + dl)
    for half in (0.005, 0.02, 0.06, 0.15, 0.4):
        tha, thb = lo0 - half, hi0 + half
        gb = float(sup.h(i, thb) - sup.h(j, thb))
        ga = float(sup.h(i, tha) - sup.h(j, tha))
        if not (gb * ga < 0):
            continue
        sigma = -1.0 if gb > 0 else 1.0          # σ·f > 0 on the ray θb, f ≈ −g far away
        ok, msg = _prove_sector(sup, geoms, pair, tha, thb, sigma, r, scale, max_work)
        if ok:
            J = _lead_interval(sup, i, j, ths, tha, thb)
            if J is None:
                return False, "no interval of directions around the asymptote where its sites lead", None
            return True, None, J
    return False, msg, None


def _lead_interval(sup, i, j, ths, tha, thb):
    """An interval J = [α, β] ⊂ (θa, θb) around the float asymptotic direction ths on which only
    i and j attain max_k h_k and h_i − h_j has strict opposite signs at α and β (for the
    accounting of :func:`runtime.voronoi.verify_closure.verify_accounting_conics`), or None."""
    mu = sup.mu
    others = [k for k in range(sup.n) if k not in (i, j)]
    for eta in (1e-3, 1e-5, 1e-7):
        a, b = ths - eta, ths + eta
        if not (tha < a and b < thb):
            continue
        ga = float(sup.h(i, a) - sup.h(j, a))
        gb = float(sup.h(i, b) - sup.h(j, b))
        if not (ga * gb < 0 and min(abs(ga), abs(gb)) > 4 * mu):
            continue
        e = np.linspace(a, b, 9)
        c0, c1 = e[:-1], e[1:]
        good = True
        for _ in range(30):
            thc, half = 0.5 * (c0 + c1), 0.5 * (c1 - c0) * (1 + 1e-12)
            lo = np.maximum(sup.h_range(i, thc, half)[0], sup.h_range(j, thc, half)[0])
            okc = np.ones(len(thc), bool)
            for k in others:
                okc &= lo - sup.h_range(k, thc, half)[1] > 0
            if okc.all():
                break
            c0, c1 = c0[~okc], c1[~okc]
            if len(c0) > 4096:
                good = False
                break
            mid = 0.5 * (c0 + c1)
            c0, c1 = np.concatenate([c0, mid]), np.concatenate([mid, c1])
        else:
            good = False
        if good:
            return (a, b, 1.0 if gb < 0 else -1.0)
    return None


def _prove_sector(sup, geoms, pair, tha, thb, sigma, T0, scale, max_work):
    """(A) third sites, (M) σ·∂f/∂θ > 0 on Σ = {t ≥ T0, θ ∈ [θa, θb]}, (R) σ·f < 0 on the ray θa
    and > 0 on the ray θb; cells in (τ = 1/t, θ), halved until decided (module docstring)."""
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
            e_i = _eps1(sup.hp_abs(i, th, 0.0), W, t0)
            e_j = _eps1(sup.hp_abs(j, th, 0.0), W, t0)
            f_lo, f_hi = -gv - 2 * mu - e_j, -gv + 2 * mu + e_i      # f ∈ [−g − e_j, −g + e_i]
            ok = np.where(want * sigma > 0, f_lo > 0, f_hi < 0)
            fin = T_a > 0
            if fin.any():
                t1 = np.where(fin, 1.0 / np.where(fin, T_a, 1.0), t0)
                tc = 0.5 * (t0 + t1)
                C = m + tc[:, None] * np.array([math.cos(th), math.sin(th)])
                R = np.where(fin, 0.5 * (t1 - t0), np.inf) * (1 + 1e-12) + 1e-12 * (scale + tc)
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
    okA_last = np.ones(len(ta), bool)
    work = 0
    while len(ta):
        work += len(ta)
        if work > max_work:
            k = int(np.argmax(tb))
            what = "third site" if not okA_last[k] else "monotonicity"
            return False, (f"the tail is undecided ({what}) near angle {0.5 * (h0[k] + h1[k]):.6g}, "
                           f"distance {1.0 / tb[k]:.6g} from the scene's centre")
        thc, half = 0.5 * (h0 + h1), 0.5 * (h1 - h0) * (1 + 1e-12)
        t0 = 1.0 / tb
        e_i = _eps1(sup.hp_abs(i, thc, half), W, t0)
        e_j = _eps1(sup.hp_abs(j, thc, half), W, t0)
        fin = ta > 0
        t1 = np.where(fin, 1.0 / np.where(fin, ta, 1.0), np.inf)
        tc = np.where(fin, 0.5 * (t0 + t1), t0)
        U = np.column_stack([np.cos(thc), np.sin(thc)])
        C = m + tc[:, None] * U
        R = np.where(fin, t1 * half + 0.5 * (t1 - t0) + 1e-12 * (scale + tc), np.inf) * (1 + 1e-12)
        # (A) third sites: support bounds, or distance bounds on the cell's disc
        li_s, _ = sup.h_range(i, thc, half)
        lj_s, _ = sup.h_range(j, thc, half)
        hmax_lo = np.maximum(li_s - e_i, lj_s - e_j)     # on β: d_i = d_j ≤ t − hmax_lo
        okA = np.ones(len(ta), bool)
        if fin.any():
            Cf = np.where(fin[:, None], C, m + T0 * U)
            _, hi_i = opi.bounds(Cf)
            _, hi_j = opj.bounds(Cf)
            hi_min = np.minimum(hi_i, hi_j)
        grad_i = None
        for k in others:
            _, hk = sup.h_range(k, thc, half)
            okk = hmax_lo - hk > 0
            if fin.any() and not okk.all():
                lo_k, _ = ops[k].bounds(Cf)
                okk |= fin & (lo_k - R > hi_min + R)
                todo = fin & ~okk
                if todo.any():
                    # first order: d_k − d_i ≥ (lo_k − hi_i)(C) − R·sup|∇d_k − ∇d_i| on the disc
                    if grad_i is None:
                        Rf = np.where(fin, R, 0.0)
                        grad_i = opi.gradient(Cf, Rf)
                    Gi_, si_, vi_ = grad_i
                    Gk, sk, vk = ops[k].gradient(Cf, Rf)
                    lip = np.hypot(*(Gk - Gi_).T) + sk + si_
                    lip = np.where(vk & vi_ & np.isfinite(lip), np.minimum(lip, 2.0), 2.0) * (1 + 1e-12)
                    okk |= todo & (lo_k - hi_i - lip * R > 0)
            okA &= okk
        # (M) σ·∂f/∂θ > 0: support-point enclosure (module docstring) or gradient enclosures on the disc
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
        # (F) f has one strict sign on the cell: β does not meet it
        gc = sup.h(i, thc) - sup.h(j, thc)
        gr = 2 * W * half + 2 * mu
        okF = (-(gc + gr) - e_j > 0) | (-(gc - gr) + e_i < 0)
        if fin.any():
            li, hi_ = opi.bounds(Cf)
            lj, hj = opj.bounds(Cf)
            okF |= fin & ((li - hj - 2 * R > 0) | (hi_ - lj + 2 * R < 0))
        bad = ~(okF | (okA & okM))
        if not bad.any():
            return True, None
        # halve the undecided cells: infinite cells in τ and θ, finite ones across their longer side
        a_, b_, c_, d_ = ta[bad], tb[bad], h0[bad], h1[bad]
        oA = okA[bad]
        mt, mh = 0.5 * (a_ + b_), 0.5 * (c_ + d_)
        inf_ = a_ <= 0
        ta_f = np.where(inf_, np.inf, 1.0 / np.where(inf_, 1.0, a_))
        radial = 0.5 * (ta_f - 1.0 / b_)
        lateral = ta_f * 0.5 * (d_ - c_)
        cut_t = inf_ | (radial >= lateral)
        cut_h = inf_ | (radial < lateral)
        parts = []
        for ct, ch in ((False, False), (True, False), (False, True), (True, True)):
            # quarter (ct, ch): upper τ half if ct, upper θ half if ch; kept when that cut is made
            sel = (cut_t | ~np.array(ct)) & (cut_h | ~np.array(ch))
            A0 = np.where(cut_t, np.where(ct, mt, a_), a_)
            B0 = np.where(cut_t, np.where(ct, b_, mt), b_)
            C0 = np.where(cut_h, np.where(ch, mh, c_), c_)
            D0 = np.where(cut_h, np.where(ch, d_, mh), d_)
            parts.append((A0[sel], B0[sel], C0[sel], D0[sel], oA[sel]))
        ta = np.concatenate([p_[0] for p_ in parts])
        tb = np.concatenate([p_[1] for p_ in parts])
        h0 = np.concatenate([p_[2] for p_ in parts])
        h1 = np.concatenate([p_[3] for p_ in parts])
        okA_last = np.concatenate([p_[4] for p_ in parts])
    return True, None
