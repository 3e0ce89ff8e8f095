"""The guide of a chain of strips: a polyline that follows the bisector β of two convex sites
closely enough for the strips of :mod:`runtime.voronoi.verify.strips` (used by
:mod:`runtime.voronoi.verify.curved`).

Nothing here is proved and nothing is assumed of it: the guide only places the strips, which
decide.  Float Newton steps on f = d_i − d_j move points onto β along a given normal
(:func:`project`, served for all edges at once by :func:`project_many`); a segment is split while
its arc strays from the chord by more than a fraction of the wanted strip half-width
(:func:`adapt`: the projected midpoint's offset, and the angle between the chord and β's tangent
at either end); :func:`node_width` is the wanted half-width; :func:`vertex_taper` the narrowing
of the strips next to a vertex where a third site's bisector crosses β at a small angle;
:func:`cut_outside` cuts an unbounded guide at a circle.  The generators yield requests to
:func:`runtime.voronoi.verify.site_table.run_lockstep` (distance values, or a
:class:`ProjectJob`).

Public API: :func:`project`, :func:`project_many`, :class:`ProjectJob`, :func:`node_width`,
:func:`refine`, :func:`adapt`, :func:`vertex_taper`, :func:`cut_outside`.
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["ProjectJob", "adapt", "cut_outside", "node_width", "project", "project_many", "refine", "vertex_taper"]

#: Newton steps of a projection onto β
NEWTON = 6


def vertex_taper(v, pair, ks):
    """(sin θ, w_v) at the vertex v of the edge of ``pair`` = (i, j) with the third sites ``ks``
    (float, only to choose strip widths): θ the smallest angle between ∇d_i − ∇d_j and
    ∇d_k − ∇d_i, w_v = d·|∇d_k − ∇d_i|·|∇d_i − ∇d_j|·sin θ / (8 (|∇d_k − ∇d_i| + |∇d_i − ∇d_j|)).
    The transversality test (T3) of :mod:`runtime.voronoi.verify.strips` holds on a piece of
    radius R when its error, about (4R/d)(|∇d_k − ∇d_i| + |∇d_i − ∇d_j|) (gradient slack 2R/d
    per site), is below |∇d_k − ∇d_i|·|∇d_i − ∇d_j|·sin θ: R about w_v.  Away from the vertex
    d_k − d_i grows like s·|∇d_k − ∇d_i|·sin θ, so the first-order test (T2) takes over for R
    below s·sin θ.  At a vertex 10³ scene units out, θ is of the order of (site gap)/d and a
    fixed fraction of d (the strips' other narrowing) is far too wide.  None when undefined.
    Generator."""
    i, j = pair
    K = [i, j] + [int(k) for k in ks]
    X = np.repeat([[float(v.x), float(v.y)]], len(K), axis=0)
    V = yield (X, np.array(K))
    with np.errstate(invalid="ignore", divide="ignore"):
        G = (X - V.F) / V.d[:, None]
        Df = G[0] - G[1]
        nf = math.hypot(*Df)
        best = None
        for t in range(2, len(K)):
            Dg = G[t] - G[0]
            ng = math.hypot(*Dg)
            sin_t = abs(Df[0] * Dg[1] - Df[1] * Dg[0]) / (nf * ng)
            wv = min(V.d[0], V.d[1]) * ng * nf * sin_t / (8 * (ng + nf))
            if not (math.isfinite(sin_t) and math.isfinite(wv) and wv > 0):
                return None
            if best is None or wv < best[1]:
                best = (min(sin_t, 1.0), wv)
    return best


def cut_outside(S, cen, Rc):
    """The guide S up to where it first leaves the disc D(cen, Rc) after its first node inside the
    disc (cut on the crossing segment by bisection): a guide from a vertex far outside the disc
    (nearly tied sites) crosses the disc and is cut where it leaves it for its end at infinity.
    A guide with no node inside: its first segment."""
    dist = np.hypot(S[:, 0] - cen[0], S[:, 1] - cen[1])
    far = np.nonzero(dist > Rc)[0]
    inside = np.nonzero(dist <= Rc)[0]
    if len(inside):
        far = far[far > inside[0]]
    if len(far) and far[0] > 0:
        f0 = int(far[0])
        A_, B_ = S[f0 - 1], S[f0]
        lo_t, hi_t = 0.0, 1.0
        for _ in range(60):
            mt = 0.5 * (lo_t + hi_t)
            if np.hypot(*(A_ + mt * (B_ - A_) - cen)) > Rc:
                hi_t = mt
            else:
                lo_t = mt
        return np.vstack([S[:f0], A_ + hi_t * (B_ - A_)])
    return S[:2] if len(far) else S


def _fgrad(M, pair):
    """Float f = d_i − d_j and ∇f at the points M (from the float foot points).  Generator."""
    n = len(M)
    V = yield (np.concatenate([M, M]), np.repeat(list(pair), n))
    return _fgrad_values(M, V.part(0, n), V.part(n, 2 * n))


def _fgrad_values(M, Vi, Vj):
    with np.errstate(divide="ignore", invalid="ignore"):
        Ui = (M - Vi.F) / Vi.d[:, None]
        Uj = (M - Vj.F) / Vj.d[:, None]
    return Vi.d - Vj.d, Ui - Uj, Vi.d, Vj.d


def _project_mid(A, B, pair):
    """Midpoints of the segments [A, B] moved onto the bisector along the segments' normals
    (float Newton steps on f = d_i − d_j; only a better guide, nothing is assumed of it).
    Returns (points, offsets).  Generator."""
    return (yield from project(0.5 * (A + B), B - A, pair))


class ProjectJob:
    """Points M to move onto the bisector of ``pair`` along the normals of the directions t."""

    __slots__ = ("M", "t", "pair")

    def __init__(self, M, t, pair):
        self.M, self.t, self.pair = np.asarray(M, float).reshape(-1, 2), np.asarray(t, float).reshape(-1, 2), pair


def project(M, t, pair):
    """Points M moved onto the bisector along the normals of the directions t (float Newton
    steps, moves at most |t|/2).  Returns (points, offsets).  Generator: all pending projections
    of all edges run together (:func:`project_many`)."""
    return (yield ProjectJob(M, t, pair))


def project_many(table, jobs):
    """:func:`project` for many jobs at once (one table call per Newton step)."""
    M = np.concatenate([jb.M for jb in jobs])
    t = np.concatenate([jb.t for jb in jobs])
    cnt = [len(jb.M) for jb in jobs]
    I = np.repeat([jb.pair[0] for jb in jobs], cnt)
    J = np.repeat([jb.pair[1] for jb in jobs], cnt)
    Ls = np.maximum(np.hypot(t[:, 0], t[:, 1]), 1e-300)
    n = np.column_stack([-t[:, 1], t[:, 0]]) / Ls[:, None]
    lam = np.zeros(len(M))
    size = 1 + np.abs(M).sum(1)
    fM = None
    act = np.arange(len(M))
    f1 = np.full(len(M), np.inf)

    def fvalues(act):
        X = M[act] + lam[act, None] * n[act]
        m = len(act)
        V = table.evaluate(np.concatenate([X, X]), np.concatenate([I[act], J[act]]))
        return _fgrad_values(X, V.part(0, m), V.part(m, 2 * m))

    for _ in range(NEWTON):
        if not len(act):
            break
        f, G, _, _ = fvalues(act)
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
        f1[act] = fvalues(act)[0]
    if fM is None:
        fM = np.zeros(len(M))
    good = np.isfinite(lam) & np.isfinite(f1) & ((np.abs(f1) <= 1e-3 * fM) | (np.abs(f1) < 1e-12 * size))
    Mn = np.where(good[:, None], M + np.where(good, lam, 0.0)[:, None] * n, M)
    dev = np.where(good, np.abs(lam), np.inf)
    res, pos = [], 0
    for c in cnt:
        res.append((Mn[pos:pos + c], dev[pos:pos + c]))
        pos += c
    return res


def node_width(X, pair, tol, scale):
    """Strip half-width wanted at the polyline nodes X: about 3x the stated tolerance, at most a
    small fraction of d·|∇d_i − ∇d_j| (the gradient enclosures of the monotonicity test
    have slack ~ 2R/d).  Generator."""
    return (yield from _node_frame(X, pair, tol, scale))[0]


def _node_frame(X, pair, tol, scale):
    """(:func:`node_width` at the nodes X, the unit normals ∇f/|∇f| of the bisector there; NaN
    where undefined).  Generator."""
    X = np.asarray(X, float).reshape(-1, 2)
    _, D, di, dj = yield from _fgrad(X, pair)
    with np.errstate(invalid="ignore", divide="ignore"):
        nD = np.hypot(D[:, 0], D[:, 1])
        c = 0.03 * np.minimum(di, dj) * nD
        U = D / nD[:, None]
    c = np.where(np.isfinite(c), c, 0.0)
    return np.maximum(np.minimum(max(3 * tol, 1e-6 * scale), c), 1e-9 * scale), U


def refine(S, pair, sel=None):
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


def adapt(S, pair, frac, tol, scale, rounds=12, cap=4000, ends=(None, None)):
    """Split the segments whose bisector arc strays more than ``frac`` times the wanted strip
    half-width from the chord, to a bounded depth: the strips must contain the arc.  Two float
    estimates: the offset of the projected midpoint, and L·sin α with α the angle between the
    chord and the bisector's tangent at either end (the arc of a segment where β turns by less
    than a right angle lies in the triangle of the chord and the end tangents, within s·tan α of
    the chord at distance s from that end: the midpoint alone misses a bend near one end, as
    next to a vertex near the sites on an edge running 10³ scene units out).  ``ends``: the
    half-widths wanted at the first and last node (the strips narrowed at the vertices), or None.
    Only the new segments are projected again.  Only a guide; the proof decides.  Generator."""
    Mn, dev = yield from _project_mid(S[:-1], S[1:], pair)
    tn, U = yield from _node_frame(S, pair, tol, scale)
    tn = frac * tn
    for _ in range(rounds):
        for t, w_end in ((0, ends[0]), (-1, ends[1])):
            if w_end is not None:
                tn[t] = min(tn[t], frac * w_end)
        seg = S[1:] - S[:-1]
        Ls = np.hypot(seg[:, 0], seg[:, 1])
        Tc = seg / np.maximum(Ls, 1e-300)[:, None]
        with np.errstate(invalid="ignore"):
            sin_end = np.maximum(np.abs((Tc * U[:-1]).sum(1)), np.abs((Tc * U[1:]).sum(1)))
        tmin = np.minimum(tn[:-1], tn[1:])
        bend = np.where(np.isfinite(sin_end), Ls * sin_end > 4 * tmin, False)
        sel = ((dev > tmin) | bend) & (dev < 0.25 * Ls)     # else the projection is not trusted
        if not sel.any() or len(S) + int(sel.sum()) > cap:
            break
        S = _insert(S, sel, Mn[sel])
        tw, Uw = yield from _node_frame(Mn[sel], pair, tol, scale)
        tn = _insert(tn[:, None], sel, frac * tw[:, None])[:, 0]
        U = _insert(U, sel, Uw)
        fresh = np.repeat(sel, 1 + sel)          # the two halves of every split segment
        Mn, dev = np.repeat(Mn, 1 + sel, axis=0), np.repeat(dev, 1 + sel)
        Mf, df = yield from _project_mid(S[:-1][fresh], S[1:][fresh], pair)
        Mn[fresh], dev[fresh] = Mf, df
    return S
