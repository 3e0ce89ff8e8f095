"""The edges of the diagram as polylines on the bisectors.

The circumcentres along a walk of the sample triangulation are projected onto the true bisector
(Newton steps on d_i − d_j along its gradient, using the foot points); the ends are the vertices.
``tolerance`` of an edge is max(max |d_i − d_j| / 2 at its points, the deviation of each chord
midpoint from its projection onto the bisector): a *measured* figure, not a proof; the proof that
every arc is a true edge is the independent verifier's (:func:`runtime.voronoi.verify.certificate.verify`).

The edges are computed in groups of :data:`GROUP`, so that the temporaries (projections,
densification, the bisectors and their Hausdorff bounds) take memory in proportion to a group's
points rather than to all the polylines at once.

Length: the steps of one polyline (projection, trimming at the vertices, loops around point
sites, densification, tolerance) work on the same per-group arrays and are kept together.

Public API: :func:`edge_polylines`, :class:`PolylineMemo`, :func:`project_to_bisector`, :func:`bisector_offset`,
:func:`root_on_normal`.
"""
from __future__ import annotations

import numpy as np

from .exact_delaunay import orientation
from .ridge_nodes import insert_ridge_nodes
from .sample_delaunay import SampleTriangulation
from .site_arrays import SiteArrays
from .structure import DiagramEdge

__all__ = ["edge_polylines", "PolylineMemo", "project_to_bisector", "bisector_offset", "root_on_normal", "MAX_EDGE_POINTS",
           "DENSIFY_REL"]

#: interior points kept per edge polyline (evenly chosen among the walk's circumcentres; a third
#: of it for conics, whose foot points cost more, before densification)
MAX_EDGE_POINTS = 32
#: a projected circumcentre with |d_i − d_j|/2 above this fraction of its distance to the sites is
#: not on the bisector and is dropped from the polyline
UNPROJECTED_REL = 1e-6
#: rays cast from a nested point site for its closed edge (:func:`_point_loops`)
LOOP_RAYS = 64
#: polyline chords are split while their midpoint is farther from the bisector than this fraction of
#: the distance to the sites there
DENSIFY_REL = 1e-3


def project_to_bisector(S: SiteArrays, P, I, J, iters=6, distances=False):
    """Newton steps on f = d_I − d_J along ∇f (foot-point normals): points onto the bisector.
    Points already on it (|f| ≤ 1e-12·scale) stop early.  Returns the points and |f|/2 (and, with
    ``distances``, max(d_I, d_J) there)."""
    P = P.copy()
    act = np.arange(len(P))
    res = np.zeros(len(P))
    dist = np.zeros(len(P))
    for it in range(iters + 1):
        if not len(act):
            break
        Q = P[act]
        di, Ui = S.dist_grad(Q, I[act])
        dj, Uj = S.dist_grad(Q, J[act])
        f = di - dj
        res[act] = np.abs(f) / 2
        dist[act] = np.maximum(di, dj)
        if it == iters:
            break
        G = Ui - Uj
        g2 = (G * G).sum(axis=1)
        with np.errstate(divide="ignore", invalid="ignore"):
            st = np.where(g2 > 1e-30, f / g2, 0.0)
        lim = 0.25 * np.maximum(di, dj)
        st = np.clip(st, -lim, lim)
        P[act] = Q - st[:, None] * G
        keep = np.abs(f) > 1e-12 * (np.abs(Q).sum(axis=1) + di + 1e-300)
        act = act[keep]
    return (P, res, dist) if distances else (P, res)


def bisector_offset(S: SiteArrays, P, I, J):
    """First-order distance from P to the bisector: |d_I − d_J| / |∇(d_I − d_J)|."""
    di, Ui = S.dist_grad(P, I)
    dj, Uj = S.dist_grad(P, J)
    g = np.hypot(*(Ui - Uj).T)
    return np.abs(di - dj) / np.maximum(g, 1e-3), di



def edge_polylines(S: SiteArrays, tri: SampleTriangulation, vertices, edges_raw):
    """Polylines of the edges: vertex, projected circumcentres, vertex (hull ends extended to the
    window), with their measured tolerance."""
    if not edges_raw:
        return []
    far = 2.0 * (S.window[2] - S.window[0])
    nT, nV = len(tri.cc), len(vertices)
    VX = np.array([[v.x, v.y] for v in vertices], dtype=float).reshape(-1, 2)
    hull_pts = []
    rows, lens = [], []             # rows of the table [circumcentres; vertices; hull points]
    cap = MAX_EDGE_POINTS if S.all_circles else MAX_EDGE_POINTS // 3
    for pair, start, chain, end, ends in edges_raw:
        if len(chain) > cap:
            chain = [chain[m] for m in np.linspace(0, len(chain) - 1, cap).round().astype(int).tolist()]
        r = []
        if start is not None and start[0] == "hull":
            hull_pts.append(_hull_point(tri, start, chain[0] if chain else None, far))
            r.append(nT + nV + len(hull_pts) - 1)
        elif ends[0] is not None:
            r.append(nT + ends[0])
        r.extend(chain)
        if end is None:               # closed
            r.append(r[0])
        elif end[0] == "hull":
            base = chain[-1] if chain else None
            vtx = vertices[ends[0]] if (not chain and ends[0] is not None) else None
            hull_pts.append(_hull_point(tri, end, base, far, vertex=vtx))
            r.append(nT + nV + len(hull_pts) - 1)
        else:
            r.append(nT + ends[1])
        rows.extend(r)
        lens.append(len(r))
    rows = np.array(rows, dtype=np.int64)
    lens = np.array(lens, dtype=np.int64)
    table = np.vstack([tri.cc, VX, np.array(hull_pts, dtype=float).reshape(-1, 2)])
    E = len(edges_raw)
    # an edge with the same end points and the same first / last circumcentres and count as an edge
    # of the previous triangulation (``tri.prior_edge_memo``, kept triangles keep their exact
    # circumcentres) is the same arc of the same bisector: its polyline is reused
    first = np.cumsum(lens) - lens
    key = np.column_stack([table[rows[first]], table[rows[first + 1]], table[rows[first + lens - 2]],
                           table[rows[first + lens - 1]], lens.astype(float)])
    keys = [k.tobytes() for k in key]
    prior = getattr(tri, "prior_edge_memo", None) or {}
    known = [prior.get(k) for k in keys]
    del keys
    todo = np.array([e for e in range(E) if known[e] is None], dtype=np.int64)
    # the edges in groups of GROUP: the temporaries (projections, densification, the bisectors and
    # their Hausdorff bounds) take memory in proportion to a group's points, not to all of them
    ctx = _Context(S, vertices, VX, nT, nV)
    polys, tol = {}, np.zeros(E)
    for g in range(0, len(todo), GROUP):
        part = todo[g:g + GROUP]
        p, t = _fresh_polylines(ctx, [edges_raw[e] for e in part.tolist()], _rows_of(rows, first, lens, part),
                                lens[part], table)
        polys.update(zip(part.tolist(), p))
        tol[part] = t
    del rows, table
    edges = []
    for e, (pair, start, chain, end, ends) in enumerate(edges_raw):
        if known[e] is not None:         # the previous round's polyline: not shared with its edge
            poly, tl = known[e][0].copy(), known[e][1]
        else:
            poly, tl = polys.pop(e), tol[e]
        closed = end is None and start is None
        edges.append(DiagramEdge(e, pair, (ends[0], ends[1]), closed, poly, float(tl), False))
    tri.edge_memo = PolylineMemo(key, [ed.polyline for ed in edges], np.array([ed.tolerance for ed in edges]))
    return edges


class PolylineMemo:
    """The polylines and tolerances of a triangulation's edges by their key (the end points, the
    first and last circumcentres and the count of :func:`edge_polylines`), for the edges of the
    next triangulation: ``get(key bytes)`` is (polyline, tolerance) or None, the last edge of a
    repeated key winning.  The keys are one (E, 9) float array and the lookup table is made on
    the first ``get`` (the memo that a diagram keeps after its construction, for
    :func:`runtime.voronoi.deletion.delete_site`, takes 90 bytes an edge besides the polylines,
    which its edges share; a dict of byte strings and tuples took 200)."""

    __slots__ = ("keys", "polylines", "tolerances", "_index")

    def __init__(self, keys, polylines, tolerances):
        self.keys, self.polylines, self.tolerances, self._index = keys, polylines, tolerances, None

    def __len__(self) -> int:
        return len(self.polylines)

    def get(self, key):
        if self._index is None:
            self._index = {row.tobytes(): e for e, row in enumerate(self.keys)}
        e = self._index.get(key)
        return None if e is None else (self.polylines[e], float(self.tolerances[e]))


#: edges whose polylines are computed together (bounds the temporaries of :func:`_fresh_polylines`)
GROUP = 4096


class _Context:
    """What every group of edges shares: the sites, the vertices' sites and points, and (circles
    and points) the verifier's table of circles for the tolerances."""

    def __init__(self, S, vertices, VX, nT, nV):
        self.S, self.VX, self.nT, self.nV = S, VX, nT, nV
        width = max((len(v.sites) for v in vertices), default=3)
        self.VT = np.full((len(vertices), width), -1, dtype=np.int64)
        for t, v in enumerate(vertices):
            self.VT[t, :len(v.sites)] = v.sites
        self.circles = None
        if S.all_circles:
            from .verify.edges import CircleTable
            self.circles = CircleTable(S.geoms)


def _rows_of(rows, first, lens, part):
    """The rows of the edges ``part`` (in that order) of the flat table ``rows`` (edge e:
    rows[first[e]:first[e] + lens[e]])."""
    ln = lens[part]
    start = np.cumsum(ln) - ln
    return rows[np.repeat(first[part] - start, ln) + np.arange(int(ln.sum()))]


def _fresh_polylines(ctx, sub, rows, lens, table):
    """The polylines and tolerances of the edges ``sub`` (raw edges, whose rows of ``table`` are
    ``rows``, ``lens[m]`` for edge m, in order): a list of arrays and an array."""
    S, nT, nV = ctx.S, ctx.nT, ctx.nV
    if not len(sub):
        return [], np.zeros(0)
    own = np.repeat(np.arange(len(sub)), lens)
    P = table[rows]
    PI = np.array([er[0][0] for er in sub], dtype=np.int64)
    PJ = np.array([er[0][1] for er in sub], dtype=np.int64)
    ENDS = np.array([[-1 if v is None else v for v in er[4]] for er in sub], dtype=np.int64).reshape(-1, 2)
    free = ~((rows >= nT) & (rows < nT + nV))
    Pp = P.copy()
    on = np.ones(len(P), bool)
    if free.any():
        Pp[free], res, dist = project_to_bisector(S, P[free], PI[own[free]], PJ[own[free]], distances=True)
        # circumcentres that Newton did not bring onto the bisector are dropped: next to two sites
        # that nearly touch, some lie inside a site, where the foot-point normals mislead Newton
        # (measured: 512 random ellipses, an edge through a gap of 0.14 whose polyline zigzagged
        # through such points, "tolerance" 23); the chords that replace them are densified below
        on[free] = res <= UNPROJECTED_REL * dist + 1e-12 * S.scale
        pos = np.arange(len(P)) - (np.cumsum(lens) - lens)[own]
        on |= (pos == 0) | (pos == lens[own] - 1)          # the ends (vertices, far hull points) stay
    keep = _untrimmed(Pp, own, lens, _leaving_directions(S, ctx.VT, ctx.VX, PI, PJ, ENDS)) & on
    del P
    Q, own = Pp[keep], own[keep]
    del Pp
    Q, own = _point_loops(S, Q, own, sub, PI, PJ)
    # measured tolerance on the final polylines: residual at the points, offset of chord midpoints
    if S.all_circles:
        Q, own, chord_off = _densify(S, Q, own, PI, PJ)
    else:   # conic foot points are costlier: a coarser target
        Q, own, chord_off = _densify(S, Q, own, PI, PJ, rel=10 * DENSIFY_REL, passes=3)
        n = len(Q)
        Q, own = insert_ridge_nodes(S, Q, own, PI, PJ)     # corners on an ellipse's medial axis
        if len(Q) != n:
            chord_off = np.full(len(Q), np.nan)
    pi, pj = PI[own], PJ[own]
    same = own[1:] == own[:-1]
    di, _ = S.dist_grad(Q, pi)
    dj, _ = S.dist_grad(Q, pj)
    tol = np.zeros(len(sub))
    np.maximum.at(tol, own, np.abs(di - dj) / 2)
    mids = ((Q[1:] + Q[:-1]) / 2)[same]
    if len(mids):
        off = chord_off[:-1][same]
        fresh = np.isnan(off)        # chords that densification did not measure as they are
        off[fresh] = bisector_offset(S, mids[fresh], pi[1:][same][fresh], pj[1:][same][fresh])[0]
        np.maximum.at(tol, own[1:][same], off)
    cuts = np.searchsorted(own, np.arange(len(sub) + 1))
    polys = []
    for m, (_, start, _, end, _) in enumerate(sub):
        poly = Q[cuts[m]:cuts[m + 1]].copy()
        if end is None and start is None:       # closed
            poly[-1] = poly[0]
        polys.append(poly)
    if S.all_circles:
        _circle_tolerances(ctx.circles, sub, polys, tol)
    return polys, tol


def _circle_tolerances(circles, sub, polys, tol):
    """Circles and points: the stated tolerance is the bound on the Hausdorff distance between the
    polyline and the arc that the verifier proves (:func:`runtime.voronoi.verify.polyline_bound.
    hausdorff_bounds`, the one implementation of that bound; the chord-midpoint measure misses the
    bulge of a long, asymmetric piece of hyperbola), at least twice the measured deviation plus a
    rounding allowance of the coordinates.  ``circles``: the verifier's
    :class:`runtime.voronoi.verify.edges.CircleTable` of the sites; ``sub``, ``polys``, ``tol``:
    the raw edges, their polylines (replaced when reordered) and tolerances (updated), aligned."""
    from .verify.edges import bisector
    from .verify.polyline_bound import hausdorff_bounds

    es = list(range(len(sub)))
    biss = [bisector(circles, *sub[e][0]) for e in es]
    good = [t for t, b in enumerate(biss) if not isinstance(b, str)]
    _along_the_branch([biss[t] for t in good], [es[t] for t in good], polys)
    hb = hausdorff_bounds([biss[t] for t in good], [polys[es[t]] for t in good])
    bound = dict(zip([es[t] for t in good], hb.tolist()))
    for e in es:
        allowance = 1e-10 * (1 + float(np.abs(polys[e]).max()))
        tol[e] = max(2 * tol[e] + allowance, bound.get(e, 0.0) * (1 + 1e-9) + allowance)


def _along_the_branch(biss, es, polys):
    """On a hyperbola branch (exterior circle/point pairs), the interior points of polyline e in the
    order of their parameter from its first point to its last, without those whose parameter is not
    strictly between the ends' (the circumcentres of a walk can zig-zag along the edge, and one past
    an end vertex is not on the edge's arc).  Ellipse (nested) edges are left as they are."""
    from .verify.edges import params

    hyp = [t for t, b in enumerate(biss) if b.kind == "hyperbola" and len(polys[es[t]]) > 2]
    if not hyp:
        return
    P = np.concatenate([polys[es[t]] for t in hyp])
    lens = np.array([len(polys[es[t]]) for t in hyp])
    own = np.repeat(np.arange(len(hyp)), lens)
    u = params([biss[t] for t in hyp], own, P)
    first = np.cumsum(lens) - lens
    last = first + lens - 1
    u0, u1 = u[first][own], u[last][own]
    sgn = np.sign(u1 - u0)
    key = (u - u0) * sgn                       # 0 at the first point, > 0 towards the last
    inner = (key > 0) & (key < (u1 - u0) * sgn)
    key[first], key[last] = -np.inf, np.inf
    keep = inner | np.isin(np.arange(len(P)), np.concatenate([first, last]))
    keep &= sgn != 0
    order = np.lexsort((key, own))
    moved = (order != np.arange(len(P))) | ~keep
    if not moved.any():
        return
    order = order[keep[order]]
    cuts = np.searchsorted(own[order], np.arange(len(hyp) + 1))
    for m in np.unique(own[moved]).tolist():
        e = es[hyp[m]]
        if sgn[first[m]] != 0:
            polys[e] = P[order[cuts[m]:cuts[m + 1]]]


def _point_loops(S: SiteArrays, Q, own, sub, PI, PJ, n=LOOP_RAYS):
    """The closed edges around a point site, cast along rays from the point.

    A point p nested in a site J has a closed edge when nothing else cuts its region.  The region
    {q : |q − p| ≤ d(q, J)} is star-shaped from p (on the segment from p to q, |q' − p| falls as
    fast as d(q', J) can), and along the ray q(t) = p + t·u, f(t) = t − d(q(t), J) is
    non-decreasing (d is 1-Lipschitz) from f(0) = −d(p, J) < 0: its zero, found by bisection, is
    the loop's point in the direction u.  The circumcentres of a coarse sample triangulation around
    a small loop may retrace one side (measured: a point 0.2 inside an ellipse, the loop given as
    a path out and back, which the verifier refused).  Other edges are returned unchanged."""
    todo = [m for m, er in enumerate(sub) if er[1] is None and er[3] is None
            and any(S.geoms[k].kind == "point" for k in er[0])]
    if not todo:
        return Q, own
    cuts = np.searchsorted(own, np.arange(len(sub) + 1))
    parts = {m: (Q[cuts[m]:cuts[m + 1]], own[cuts[m]:cuts[m + 1]]) for m in range(len(sub))}
    th = 2 * np.pi * np.arange(n) / n
    U = np.column_stack([np.cos(th), np.sin(th)])
    for m in todo:
        i, j = int(PI[m]), int(PJ[m])
        p_site, other = (i, j) if S.geoms[i].kind == "point" else (j, i)
        p = np.array([float(S.sites[p_site].cx), float(S.sites[p_site].cy)])
        lab = np.full(n, other)
        box = S.boxes[other]
        T = 2.0 * float(np.hypot(box[2] - box[0], box[3] - box[1])) + float(np.hypot(*(p - box[:2])))
        if not np.isfinite(T):
            continue
        lo, hi = np.zeros(n), np.full(n, T)
        if not np.all(hi - S.dist_grad(p + hi[:, None] * U, lab)[0] > 0):
            continue
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            f = mid - S.dist_grad(p + mid[:, None] * U, lab)[0]
            lo, hi = np.where(f < 0, mid, lo), np.where(f < 0, hi, mid)
        L = p + (0.5 * (lo + hi))[:, None] * U
        parts[m] = (np.vstack([L, L[:1]]), np.full(n + 1, m))
    return (np.vstack([parts[m][0] for m in range(len(sub))]),
            np.concatenate([parts[m][1] for m in range(len(sub))]))


def _densify(S: SiteArrays, Q, own, PI, PJ, rel=DENSIFY_REL, passes=6):
    """Insert projected chord midpoints where a chord strays from the bisector by more than
    ``rel`` times the distance to the sites there (a few vectorised passes; after the first pass
    only the halves of split chords are examined).  Returns the points, their edges and, for the
    chord starting at each point, the offset of its midpoint (:func:`bisector_offset`) where
    measured on the final chord (NaN elsewhere)."""
    check = np.ones(len(Q), bool)          # examine the chord starting at this point
    chord_off = np.full(len(Q), np.nan)
    for _ in range(passes):
        same = np.nonzero((own[1:] == own[:-1]) & check[:-1])[0]
        if not len(same):
            break
        mids = (Q[same] + Q[same + 1]) / 2
        a, b = PI[own[same]], PJ[own[same]]
        off, dloc = bisector_offset(S, mids, a, b)
        chord_off[same] = off
        seg = np.hypot(*(Q[same + 1] - Q[same]).T)
        split = (off > rel * np.maximum(dloc, 1e-12 * S.scale)) & (seg > 1e-9 * S.scale)
        if not split.any():
            break
        k = same[split]
        a, b, M = a[split], b[split], mids[split]
        newp, res, dist = project_to_bisector(S, M, a, b, distances=True)
        # Newton from a midpoint inside a site, next to a narrow gap, can stall off the bisector
        # (measured: 10⁴ random ellipses, a gap of 0.14, inserted nodes 0.1 off it and a polyline
        # turning by 48°): such midpoints are bracketed on the chord's normal instead, and a chord
        # whose normal holds no root keeps its measured offset in the stated tolerance
        off = res > UNPROJECTED_REL * dist + 1e-12 * S.scale
        if off.any():
            newp[off], found = root_on_normal(S, M[off], Q[k[off] + 1] - Q[k[off]], a[off], b[off])
            off[off] = ~found
        k, newp = k[~off], newp[~off]
        check[:] = False
        check[k] = True
        chord_off[k] = np.nan
        Q = np.insert(Q, k + 1, newp, axis=0)
        own = np.insert(own, k + 1, own[k])
        check = np.insert(check, k + 1, True)
        chord_off = np.insert(chord_off, k + 1, np.nan)
    return Q, own, chord_off


#: distances from a chord's midpoint, in chord lengths, at which :func:`root_on_normal` looks for a
#: sign change of d_i − d_j (both sides, nearest first)
NORMAL_STEPS = (1 / 16, 1 / 8, 1 / 4, 1 / 2, 1.0, 2.0)
NORMAL_BISECTIONS = 54


def root_on_normal(S: SiteArrays, M, chord, I, J):
    """Points of the bisector of sites I[m], J[m] on the normal line through M[m] to ``chord[m]``:
    the sign change of f = d_I − d_J nearest to M among the steps :data:`NORMAL_STEPS`, then
    bisection.  f is continuous and, for sites that are disjoint curves, changes sign only on the
    bisector (a point inside a site is nearer to it than to the other).  Returns the points and a
    mask of those where a sign change was found."""
    L = np.hypot(chord[:, 0], chord[:, 1])
    N = np.stack([-chord[:, 1], chord[:, 0]], axis=1) / np.where(L > 0, L, 1.0)[:, None]

    def f(t):
        P = M + t[:, None] * N
        return S.dist_grad(P, I)[0] - S.dist_grad(P, J)[0]

    s0 = np.sign(f(np.zeros(len(M))))
    lo, hi = np.zeros(len(M)), np.full(len(M), np.nan)
    last = {1.0: np.zeros(len(M)), -1.0: np.zeros(len(M))}
    for step in NORMAL_STEPS:
        for side in (1.0, -1.0):
            t = side * step * L
            flip = np.isnan(hi) & (np.sign(f(t)) != s0)
            lo[flip], hi[flip] = last[side][flip], t[flip]
            last[side] = t
    found = ~np.isnan(hi) & (s0 != 0) & (L > 0)
    lo, hi = lo[found], hi[found]
    if found.any():
        Mf, Nf, If, Jf = M[found], N[found], I[found], J[found]
        sf = s0[found]
        for _ in range(NORMAL_BISECTIONS):
            mid = 0.5 * (lo + hi)
            P = Mf + mid[:, None] * Nf
            same = np.sign(S.dist_grad(P, If)[0] - S.dist_grad(P, Jf)[0]) == sf
            lo, hi = np.where(same, mid, lo), np.where(same, hi, mid)
    out = M.copy()
    out[found] = M[found] + (0.5 * (lo + hi))[:, None] * N[found]
    return out, found


def _leaving_directions(S: SiteArrays, VT, VX, PI, PJ, ENDS):
    """For each vertex end of an edge (i, j), the unit tangent of the bisector at the vertex pointing
    into the edge: the side where another site k of the vertex is farther than i and j.  Returns
    (E, 2, 2) (NaN where an end is not a vertex of a triple holding i and j)."""
    out = np.full((len(PI), 2, 2), np.nan)
    if not len(VT):
        return out
    e, side = np.nonzero(ENDS >= 0)
    v = ENDS[e, side]
    tr = VT[v]
    i, j = PI[e], PJ[e]
    ok = (tr == i[:, None]).any(axis=1) & (tr == j[:, None]).any(axis=1) & (i != j)
    e, side, v, tr, i, j = e[ok], side[ok], v[ok], tr[ok], i[ok], j[ok]
    if not len(e):
        return out
    # any other site of the vertex: at a vertex of degree k the edge (i, j) of consecutive sites
    # leaves on the side where every other site of the vertex is farther
    other = (tr != i[:, None]) & (tr != j[:, None]) & (tr >= 0)
    k = tr[np.arange(len(tr)), np.argmax(other, axis=1)]
    # a vertex ends each of its edges: the gradients of its sites there, once per (vertex, site)
    key = np.concatenate([v * S.n + i, v * S.n + j, v * S.n + k])
    once, at = np.unique(key, return_inverse=True)
    _, U = S.dist_grad(VX[once // S.n], once % S.n)
    Ui, Uj, Uk = np.split(U[at.reshape(-1)], 3)
    G = Ui - Uj
    T = np.column_stack([-G[:, 1], G[:, 0]])
    sgn = np.where(((Uk - Ui) * T).sum(axis=1) < 0, -1.0, 1.0)
    T = T * sgn[:, None]
    T /= np.maximum(np.hypot(T[:, 0], T[:, 1]), 1e-300)[:, None]
    out[e, side] = T
    return out


def _untrimmed(P, own, lens, tau):
    """Mask of the polyline points to keep: interior points lying behind an end vertex (the
    circumcentres of the sample triangles next to a vertex may overshoot it along the bisector)
    are dropped, from each end until the first point in front of it."""
    start = np.concatenate([[0], np.cumsum(lens)[:-1]])
    pos = np.arange(len(P)) - start[own]
    interior = (pos >= 1) & (pos <= lens[own] - 2)
    keep = np.ones(len(P), bool)
    for side, ref in ((0, start), (1, start + lens - 1)):
        t = tau[own, side]
        has = np.isfinite(t[:, 0]) & interior
        front = has & (((P - P[ref[own]]) * np.where(np.isfinite(t), t, 0.0)).sum(axis=1) > 0)
        f = front.astype(np.int64)
        if side == 0:
            run = np.cumsum(f) - np.cumsum(f)[start[own]] + f[start[own]]
        else:
            rc = np.cumsum(f[::-1])[::-1]                      # sum of f over [m, end of array)
            stop = start + lens - 1
            run = rc - rc[stop[own]] + f[stop[own]]
        keep &= ~(has & (run == 0))
    return keep


def _hull_point(tri, end, t_chain, far, vertex=None):
    """A far point along the outward normal of a bichromatic hull side (the edge goes to infinity)."""
    _, t, k = end
    a = tri.simp[t, (k + 1) % 3]
    b = tri.simp[t, (k + 2) % 3]
    A, B = tri.P[a], tri.P[b]
    opp = tri.P[tri.simp[t, k]]
    d = B - A
    n = np.array([-d[1], d[0]])              # left of A → B; outward when the triangle lies right
    if orientation(A, B, opp) > 0:           # exactly: opp may lie a hair off the line (slivers)
        n = -n
    n = n / (np.hypot(*n) or 1.0)
    base = tri.cc[t_chain] if t_chain is not None else (np.array([vertex.x, vertex.y]) if vertex is not None
                                                        else (A + B) / 2)
    mid = (A + B) / 2
    base = base if np.all(np.isfinite(base)) else mid
    start = mid if np.dot(base - mid, n) < 0 else base
    # a vertex far out (10¹⁶: nearly collinear points) needs a step its floats can show
    return tuple(start + max(far, 1e-6 * float(np.abs(start).max())) * n)
