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
:func:`runtime.voronoi.verify.site_table.run_lockstep` (a :class:`ProjectJob`, :class:`AdaptJob`,
:class:`WidthJob` or :class:`TaperJob`, served for all edges at once by the matching ``*_many``).

Public API: :func:`project`, :func:`project_many`, :func:`project_rows`, :class:`ProjectJob`,
:func:`node_width`, :func:`node_width_many`, :class:`WidthJob`, :func:`refine`, :func:`adapt`,
:func:`adapt_many`, :class:`AdaptJob`, :func:`vertex_taper`, :func:`vertex_taper_many`, :class:`TaperJob`,
:func:`cut_outside`.
"""
from __future__ import annotations

import math

import numpy as np

from .strips import evaluate_rows

__all__ = ["AdaptJob", "ProjectJob", "TaperJob", "WidthJob", "adapt", "adapt_many", "cut_outside", "node_width",
           "node_width_many", "project", "project_many", "project_rows", "refine", "vertex_taper", "vertex_taper_many"]

#: Newton steps of a projection onto β
NEWTON = 6


class TaperJob:
    """The vertex ``v`` of an edge of ``pair`` with the third sites ``ks`` (:func:`vertex_taper`)."""

    __slots__ = ("v", "pair", "ks")

    def __init__(self, v, pair, ks):
        self.v, self.pair, self.ks = v, pair, tuple(int(k) for k in ks)


def vertex_taper(v, pair, ks):
    """(sin θ, w_v) at the vertex v of the edge of ``pair`` = (i, j) with the third sites ``ks``
    (float, only to choose strip widths): θ the smallest angle between ∇d_i − ∇d_j and
    ∇d_k − ∇d_i, w_v = d·|∇d_k − ∇d_i|·|∇d_i − ∇d_j|·sin θ / (8 (|∇d_k − ∇d_i| + |∇d_i − ∇d_j|)).
    The transversality test (T3) of :mod:`runtime.voronoi.verify.strips` holds on a piece of
    radius R when its error, about (2R/d)(|∇d_k − ∇d_i| + |∇d_i − ∇d_j|) (gradient slack R/d
    per site), is below |∇d_k − ∇d_i|·|∇d_i − ∇d_j|·sin θ: R about w_v.  Away from the vertex
    d_k − d_i grows like s·|∇d_k − ∇d_i|·sin θ, so the first-order test (T2) takes over for R
    below s·sin θ.  At a vertex 10³ scene units out, θ is of the order of (site gap)/d and a
    fixed fraction of d (the strips' other narrowing) is far too wide.  None when undefined (the
    third site of the smallest w_v: the first of equal ones).  Generator: the vertices of all
    edges are served together (:func:`vertex_taper_many`)."""
    return (yield TaperJob(v, pair, ks))


def vertex_taper_many(table, jobs):
    """:func:`vertex_taper` for many :class:`TaperJob` at once: the rows (i, j, k...) of every job
    in one table call, every value computed row by row as for one vertex alone."""
    cnt = np.array([2 + len(jb.ks) for jb in jobs], int)
    X = np.repeat([[float(jb.v.x), float(jb.v.y)] for jb in jobs], cnt, axis=0).reshape(-1, 2)
    K = np.array([k for jb in jobs for k in (jb.pair[0], jb.pair[1]) + jb.ks], int)
    V = evaluate_rows(table, X, K)
    first = np.concatenate([[0], np.cumsum(cnt)[:-1]]).astype(int)
    third = np.repeat(first, cnt - 2)                       # the row of i for each third site's row
    rows = np.concatenate([np.arange(f + 2, f + c) for f, c in zip(first.tolist(), cnt.tolist())]).astype(int) \
        if len(jobs) else np.zeros(0, int)
    with np.errstate(invalid="ignore", divide="ignore"):
        G = (X - V.F) / V.d[:, None]
        Df = G[third] - G[third + 1]
        Dg = G[rows] - G[third]
        nf = np.array([math.hypot(x, y) for x, y in Df.tolist()])
        ng = np.array([math.hypot(x, y) for x, y in Dg.tolist()])
        sin_t = np.abs(Df[:, 0] * Dg[:, 1] - Df[:, 1] * Dg[:, 0]) / (nf * ng)
        wv = np.minimum(V.d[third], V.d[third + 1]) * ng * nf * sin_t / (8 * (ng + nf))
        fine = np.isfinite(sin_t) & np.isfinite(wv) & (wv > 0)
    out, pos = [], 0
    for c in (cnt - 2).tolist():
        if c == 0 or not fine[pos:pos + c].all():
            out.append(None)
        else:
            b = pos + int(np.argmin(wv[pos:pos + c]))
            out.append((min(float(sin_t[b]), 1.0), float(wv[b])))
        pos += c
    return out


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


def _fgrad_values(M, Vi, Vj):
    """Float f = d_i − d_j, ∇f, d_i and d_j at the points M from the table's values Vi, Vj there
    (the float foot points)."""
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
    cnt = [len(jb.M) for jb in jobs]
    Mn, dev = project_rows(table, np.concatenate([jb.M for jb in jobs]), np.concatenate([jb.t for jb in jobs]),
                           np.repeat([jb.pair[0] for jb in jobs], cnt), np.repeat([jb.pair[1] for jb in jobs], cnt))
    res, pos = [], 0
    for c in cnt:
        res.append((Mn[pos:pos + c], dev[pos:pos + c]))
        pos += c
    return res


def project_rows(table, M, t, I, J):
    """(points, offsets): the points M moved onto the bisector of (I, J) (one pair per row) along
    the normals of the directions t, row by row (float Newton steps, moves at most |t|/2; a row's
    result depends on that row only; the table in calls of at most
    :data:`runtime.voronoi.verify.strips.ROWS_PER_CALL` rows)."""
    M = np.asarray(M, float).reshape(-1, 2)
    t = np.asarray(t, float).reshape(-1, 2)
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
        V = evaluate_rows(table, np.concatenate([X, X]), np.concatenate([I[act], J[act]]))
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
    return Mn, dev


class WidthJob:
    """The nodes X of a guide of the bisector of ``pair`` (:func:`node_width`)."""

    __slots__ = ("X", "pair", "tol", "scale")

    def __init__(self, X, pair, tol, scale):
        self.X, self.pair, self.tol, self.scale = np.asarray(X, float).reshape(-1, 2), pair, tol, scale


def node_width(X, pair, tol, scale):
    """Strip half-width wanted at the polyline nodes X: about 3x the stated tolerance, at most a
    small fraction of d·|∇d_i − ∇d_j| (the gradient enclosures of the monotonicity test
    have slack ~ R/d).  Generator: the nodes of all edges are served together
    (:func:`node_width_many`)."""
    return (yield WidthJob(X, pair, tol, scale))


def node_width_many(table, jobs):
    """:func:`node_width` for many :class:`WidthJob` at once (one table call; row by row the
    values of one job alone)."""
    cnt = [len(jb.X) for jb in jobs]
    X = np.concatenate([jb.X for jb in jobs]) if jobs else np.zeros((0, 2))
    m = len(X)
    V = evaluate_rows(table, np.concatenate([X, X]), np.concatenate([np.repeat([jb.pair[0] for jb in jobs], cnt),
                                                                     np.repeat([jb.pair[1] for jb in jobs], cnt)]))
    w = _frame_values(_fgrad_values(X, V.part(0, m), V.part(m, 2 * m)), np.repeat([jb.tol for jb in jobs], cnt),
                      np.repeat([jb.scale for jb in jobs], cnt))[0]
    bounds = np.concatenate([[0], np.cumsum(cnt)]).astype(int)
    return [w[bounds[t]:bounds[t + 1]] for t in range(len(jobs))]


def _frame_values(fg, tol, scale):
    """(:func:`node_width`, the unit normals ∇f/|∇f| of the bisector; NaN where undefined) from the
    float values ``fg`` of :func:`_fgrad_values` (``tol`` and ``scale`` scalars or one per row)."""
    _, D, di, dj = fg
    with np.errstate(invalid="ignore", divide="ignore"):
        nD = np.hypot(D[:, 0], D[:, 1])
        c = 0.03 * np.minimum(di, dj) * nD
        U = D / nD[:, None]
    c = np.where(np.isfinite(c), c, 0.0)
    return np.maximum(np.minimum(np.maximum(3 * tol, 1e-6 * scale), c), 1e-9 * scale), U


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


class AdaptJob:
    """The guide S of the bisector of ``pair`` to split (:func:`adapt`)."""

    __slots__ = ("S", "pair", "frac", "tol", "scale", "rounds", "cap", "ends")

    def __init__(self, S, pair, frac, tol, scale, rounds, cap, ends):
        self.S, self.pair, self.frac, self.tol, self.scale = np.asarray(S, float).reshape(-1, 2), pair, frac, tol, scale
        self.rounds, self.cap, self.ends = rounds, cap, ends


def adapt(S, pair, frac, tol, scale, rounds=12, cap=4000, ends=(None, None)):
    """Split the segments whose bisector arc strays more than ``frac`` times the wanted strip
    half-width from the chord, to a bounded depth: the strips must contain the arc.  Two float
    estimates: the offset of the projected midpoint, and L·sin α with α the angle between the
    chord and the bisector's tangent at either end (the arc of a segment where β turns by less
    than a right angle lies in the triangle of the chord and the end tangents, within s·tan α of
    the chord at distance s from that end: the midpoint alone misses a bend near one end, as
    next to a vertex near the sites on an edge running 10³ scene units out).  ``ends``: the
    half-widths wanted at the first and last node (the strips narrowed at the vertices), or None.
    Only the new segments are projected again.  Only a guide; the proof decides.  Generator: all
    pending guides of all edges are split together (:func:`adapt_many`)."""
    return (yield AdaptJob(S, pair, frac, tol, scale, rounds, cap, ends))


def _midpoints(table, A, B, I, J, Ua, Ub, tmin):
    """(Mn, dev) of :func:`adapt_many`: the midpoints of the segments AB projected onto the
    bisector of (I, J) (one pair per row, :func:`project_rows`) where the chord may stray more
    than tmin/2 from β; elsewhere the chord's midpoint and dev = 0.  Where β turns by less than a
    right angle along AB, it lies in the triangle of the chord and the end tangents (normals Ua,
    Ub), within (L/2)·tan α of the chord (α the larger angle between the chord and an end
    tangent): L·tan α ≤ tmin leaves the segment unsplit either way."""
    seg = B - A
    Ls = np.hypot(seg[:, 0], seg[:, 1])
    Tc = seg / np.maximum(Ls, 1e-300)[:, None]
    with np.errstate(invalid="ignore", divide="ignore"):
        sin_a = np.maximum(np.abs((Tc * Ua).sum(1)), np.abs((Tc * Ub).sum(1)))
        clear = Ls * sin_a <= tmin * np.sqrt(np.maximum(1.0 - sin_a * sin_a, 0.0))
    Mn, dev = 0.5 * (A + B), np.zeros(len(A))
    need = np.nonzero(~clear)[0]
    if len(need):
        Mn[need], dev[need] = project_rows(table, Mn[need], seg[need], I[need], J[need])
    return Mn, dev


def adapt_many(table, jobs):
    """:func:`adapt` for many jobs at once: the nodes of all guides in one flat array (each guide's
    nodes contiguous), one table call per round for the node frames and one projection of the new
    segments' midpoints (only where the end tangents leave room for a split: :func:`_midpoints`).
    Every value is computed row by row as for one guide alone, so each guide
    is split exactly as it would be on its own (a guide stops at its first round without a split,
    or when the split would exceed its ``cap`` nodes, or after its ``rounds``)."""
    nj = len(jobs)
    cnt = np.array([len(jb.S) for jb in jobs], int)
    S = np.concatenate([jb.S for jb in jobs]) if nj else np.zeros((0, 2))
    jn = np.repeat(np.arange(nj), cnt)                        # guide of each node
    PI = np.array([jb.pair[0] for jb in jobs], int)
    PJ = np.array([jb.pair[1] for jb in jobs], int)
    frac = np.array([jb.frac for jb in jobs], float)
    tol = np.array([jb.tol for jb in jobs], float)
    scale = np.array([jb.scale for jb in jobs], float)
    rounds = np.array([jb.rounds for jb in jobs], int)
    cap = np.array([jb.cap for jb in jobs], int)
    wend = np.array([[np.nan if w is None else w for w in jb.ends] for jb in jobs], float).reshape(nj, 2)

    def frames(X, g):
        """(frac·node width, unit normal) at the nodes X of the guides g."""
        m = len(X)
        V = evaluate_rows(table, np.concatenate([X, X]), np.concatenate([PI[g], PJ[g]]))
        tn_, U_ = _frame_values(_fgrad_values(X, V.part(0, m), V.part(m, 2 * m)), tol[g], scale[g])
        return frac[g] * tn_, U_

    inner = jn[:-1] == jn[1:]                                 # node t starts a segment of its guide
    sg = jn[:-1][inner]                                       # guide of each segment
    tn, U = frames(S, jn)
    active = cnt >= 2
    # the strips narrowed at the end vertices (the first and last nodes stay first and last)
    first = np.concatenate([[0], np.cumsum(cnt)[:-1]])
    for t, at in ((0, first), (1, first + cnt - 1)):
        has = active & ~np.isnan(wend[:, t])
        tn[at[has]] = np.minimum(tn[at[has]], frac[has] * wend[has, t])
    Mn, dev = _midpoints(table, S[:-1][inner], S[1:][inner], PI[sg], PJ[sg], U[:-1][inner], U[1:][inner],
                         np.minimum(tn[:-1][inner], tn[1:][inner]))
    for r in range(int(rounds.max()) if nj else 0):
        active &= r < rounds
        A, B = S[:-1][inner], S[1:][inner]
        seg = B - A
        Ls = np.hypot(seg[:, 0], seg[:, 1])
        Tc = seg / np.maximum(Ls, 1e-300)[:, None]
        Ua, Ub = U[:-1][inner], U[1:][inner]
        with np.errstate(invalid="ignore"):
            sin_end = np.maximum(np.abs((Tc * Ua).sum(1)), np.abs((Tc * Ub).sum(1)))
        tmin = np.minimum(tn[:-1][inner], tn[1:][inner])
        bend = np.where(np.isfinite(sin_end), Ls * sin_end > 4 * tmin, False)
        sel = ((dev > tmin) | bend) & (dev < 0.25 * Ls)     # else the projection is not trusted
        nsel = np.bincount(sg[sel], minlength=nj)
        active &= (nsel > 0) & (cnt + nsel <= cap)
        sel &= active[sg]
        if not sel.any():
            break
        # insert the projected midpoints of the selected segments after their first node
        after = np.zeros(len(S), bool)
        after[np.nonzero(inner)[0][sel]] = True
        tw, Uw = frames(Mn[sel], sg[sel])
        S = _insert(S, after[:-1], Mn[sel])
        tn = _insert(tn[:, None], after[:-1], tw[:, None])[:, 0]
        U = _insert(U, after[:-1], Uw)
        jn = _insert(jn[:, None].astype(float), after[:-1], sg[sel][:, None].astype(float))[:, 0].astype(int)
        cnt = cnt + np.bincount(sg[sel], minlength=nj)
        fresh = np.repeat(sel, 1 + sel)                       # the two halves of every split segment
        Mn, dev = np.repeat(Mn, 1 + sel, axis=0), np.repeat(dev, 1 + sel)
        inner = jn[:-1] == jn[1:]
        sg = jn[:-1][inner]
        sf = sg[fresh]
        Mf, df = _midpoints(table, S[:-1][inner][fresh], S[1:][inner][fresh], PI[sf], PJ[sf], U[:-1][inner][fresh],
                            U[1:][inner][fresh], np.minimum(tn[:-1][inner], tn[1:][inner])[fresh])
        Mn[fresh], dev[fresh] = Mf, df
    bounds = np.concatenate([[0], np.cumsum(cnt)])
    return [S[bounds[t]:bounds[t + 1]] for t in range(nj)]
