"""Proofs for Voronoi edges of convex curved sites (ellipses, mixed with circles and points).

Used by :mod:`runtime.voronoi.verify` for an edge (i, j) between two proved vertices when one of
i, j (or a third site of an end vertex) is an ellipse, where the bisector has no closed form
(thesis §5.1–5.2).  The proof is a chain of strips around the reported polyline
(:mod:`runtime.voronoi.verify_strips`: in each strip the bisector is one monotone arc, closer to
i and j than to every other site); an unbounded edge is proved by the chain up to a point at
``TAIL_CUT`` times the scene's radius and beyond it by :func:`runtime.voronoi.verify_tail.prove_tail`.

The reported polyline only guides the proof: its nodes are moved onto β (float Newton steps
along the segments' normals), nodes where it turns back are dropped, and a segment is split
(its projected midpoint inserted) while the arc strays from the chord by more than a tenth of
the wanted strip half-width (about 3x the stated tolerance, at most 0.03·d·|∇d_i − ∇d_j|, since
the gradient enclosures of the monotonicity test have slack ~ 4R/d); when a third site stays
undecided the strips are narrowed (factors 0.2, 0.05) and the guide re-split; when the bisector
leaves a strip the guide is refined (segments halved).  Nothing is assumed of the guide: the
strips decide.

:func:`prove_curved_edge` is a generator (its distance requests go to a
:class:`runtime.voronoi.verify_sitetable.SiteTable`; :func:`prove_curved_edges` runs all edges
side by side with :func:`runtime.voronoi.verify_sitetable.run_lockstep`).  Vertex-less edges (two
sites only, nested sites) and edges of hyperbolas and parabolas are not handled here.
"""
from __future__ import annotations

import math

import numpy as np

from .verify_sitetable import run_lockstep
from .verify_strips import prove_strips, rot90

__all__ = ["prove_curved_edge", "prove_curved_edges", "TAIL_CUT"]

TAIL_CUT = 12.0         # the chain proves an unbounded edge up to TAIL_CUT·(scene radius), the tail beyond
NEWTON = 6              # Newton steps of the guide's projection onto β


def prove_curved_edges(table, jobs):
    """:func:`prove_curved_edge` for every job (scale, pair, P, v0, v1, tol), side by side.
    Returns their results (ok, message, beyond) in order."""
    return run_lockstep([prove_curved_edge(table, *job) for job in jobs], table)


def prove_curved_edge(table, scale, pair, P, v0, v1, tol):
    """Prove an edge of convex sites along its polyline P (ends at the vertices v0, v1; either may
    be None = infinity, then up to a point at ``TAIL_CUT`` times the scene's radius).  Returns
    (ok, message or None, beyond): for an unbounded edge proved so far, ``beyond`` is a dict with
    the cut ``point`` and the ``link`` rectangle for :func:`runtime.voronoi.verify_tail.prove_tail`.
    Generator (requests to ``table``)."""
    i, j = pair
    geoms = table.geoms
    if not (table.convex[i] and table.convex[j]):
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
            Xn, dev = yield from _project(S[ks], dirs, pair)
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
                S = yield from _refine(S, pair)
            # split where the arc strays from the chord by more than a fraction of the strip width
            S = yield from _adapt(S, pair, 0.1 * narrow, tol, scale)
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
            N = rot90(T)
            # turning angles between consecutive segments
            cosang = np.clip((T[:-1] * T[1:]).sum(1), -1, 1)
            if np.any(cosang < math.cos(math.radians(60))):
                last_msg = "polyline turns by more than 60 degrees"
                continue
            sinang = np.sqrt(1 - cosang ** 2)
            wnode = narrow * (yield from _node_width(S, pair, tol, scale))
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
                ok, msg = yield from prove_strips(table, S, T, N, L, e_lo, e_hi, W, pair, k0, k1, scale)
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



def _fgrad(M, pair):
    """Float f = d_i − d_j and ∇f at the points M (from the float foot points).  Generator."""
    n = len(M)
    V = yield (np.concatenate([M, M]), np.repeat(list(pair), n))
    with np.errstate(divide="ignore", invalid="ignore"):
        Ui = (M - V.F[:n]) / V.d[:n, None]
        Uj = (M - V.F[n:]) / V.d[n:, None]
    return V.d[:n] - V.d[n:], Ui - Uj, V.d[:n], V.d[n:]


def _project_mid(A, B, pair):
    """Midpoints of the segments [A, B] moved onto the bisector along the segments' normals
    (float Newton steps on f = d_i − d_j; only a better guide, nothing is assumed of it).
    Returns (points, offsets).  Generator."""
    return (yield from _project(0.5 * (A + B), B - A, pair))


def _project(M, t, pair):
    """Points M moved onto the bisector along the normals of the directions t (float Newton
    steps, moves at most |t|/2).  Returns (points, offsets).  Generator."""
    Ls = np.maximum(np.hypot(t[:, 0], t[:, 1]), 1e-300)
    n = np.column_stack([-t[:, 1], t[:, 0]]) / Ls[:, None]
    lam = np.zeros(len(M))
    size = 1 + np.abs(M).sum(1)
    fM = None
    act = np.arange(len(M))
    f1 = np.full(len(M), np.inf)
    for _ in range(NEWTON):
        if not len(act):
            break
        f, G, _, _ = yield from _fgrad(M[act] + lam[act, None] * n[act], pair)
        if fM is None:
            fM = np.abs(f)
        f1[act] = f
        with np.errstate(divide="ignore", invalid="ignore"):
            step = f / (G * n[act]).sum(1)
        ok = np.isfinite(step)
        lam[act] = np.where(ok, np.clip(lam[act] - np.where(ok, step, 0.0), -0.5 * Ls[act], 0.5 * Ls[act]), lam[act])
        keep = ok & (np.abs(step) > 1e-13 * size[act]) & (np.abs(f) > 1e-14 * size[act])
        act = act[keep]
    if len(act):
        f, _, _, _ = yield from _fgrad(M[act] + lam[act, None] * n[act], pair)
        f1[act] = f
    if fM is None:
        fM = np.zeros(len(M))
    good = np.isfinite(lam) & np.isfinite(f1) & ((np.abs(f1) <= 1e-3 * fM) | (np.abs(f1) < 1e-12 * size))
    Mn = np.where(good[:, None], M + np.where(good, lam, 0.0)[:, None] * n, M)
    return Mn, np.where(good, np.abs(lam), np.inf)


def _node_width(X, pair, tol, scale):
    """Strip half-width wanted at the polyline nodes X: about 3x the stated tolerance, at most a
    small fraction of d·|∇d_i − ∇d_j| (the gradient enclosures of the monotonicity test
    have slack ~ 4R/d).  Generator."""
    X = np.asarray(X, float).reshape(-1, 2)
    _, D, di, dj = yield from _fgrad(X, pair)
    with np.errstate(invalid="ignore"):
        c = 0.03 * np.minimum(di, dj) * np.hypot(D[:, 0], D[:, 1])
    c = np.where(np.isfinite(c), c, 0.0)
    return np.maximum(np.minimum(max(3 * tol, 1e-6 * scale), c), 1e-9 * scale)


def _refine(S, pair, sel=None):
    """Insert the midpoint of every segment (or of the selected ones), moved onto the bisector.
    Generator."""
    if sel is None:
        sel = np.ones(len(S) - 1, bool)
    Mn, _ = yield from _project_mid(S[:-1][sel], S[1:][sel], pair)
    return _insert(S, sel, Mn)


def _insert(S, sel, Mn):
    out = np.empty((len(S) + int(sel.sum()), 2))
    pos = np.arange(len(S)) + np.concatenate([[0], np.cumsum(sel)])
    out[pos] = S
    out[pos[:-1][sel] + 1] = Mn
    return out


def _adapt(S, pair, frac, tol, scale, rounds=12, cap=4000):
    """Split the segments whose bisector arc strays more than ``frac`` times the wanted strip
    half-width from the chord (offset of the projected midpoint, float), to a bounded depth: the
    strips must contain the arc.  Only a guide; the proof decides.  Generator."""
    for _ in range(rounds):
        Mn, dev = yield from _project_mid(S[:-1], S[1:], pair)
        tn = frac * (yield from _node_width(S, pair, tol, scale))
        Ls = np.hypot(*(S[1:] - S[:-1]).T)
        sel = (dev > np.minimum(tn[:-1], tn[1:])) & (dev < 0.25 * Ls)     # else the projection is not trusted
        if not sel.any() or len(S) + int(sel.sum()) > cap:
            break
        S = _insert(S, sel, Mn[sel])
    return S
