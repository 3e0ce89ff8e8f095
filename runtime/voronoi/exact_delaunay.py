"""The Delaunay triangulation of point sites, decided exactly (thesis §1.2: the Voronoi diagram of
points is dual to it).

The sample triangulation (:mod:`runtime.voronoi.sample_delaunay`) takes qhull's; for point sites
the samples are the sites themselves and that triangulation *is* the diagram's combinatorics.
qhull decides in floats: points a hair (10⁻¹⁴ of the extent) off a common line — a rotated grid,
three nearly collinear points — come back as a flat simplex error, as dropped "coplanar" points or
as triangles inverted in exact arithmetic.  Here:

* :func:`is_delaunay` checks a triangulation exactly: every triangle counter-clockwise, every
  hull vertex convex or straight, every point a vertex, every interior edge locally Delaunay (the
  fourth point not strictly inside the circle of the three).  By Delaunay's lemma (Delaunay 1934;
  de Berg et al., *Computational Geometry*, Thm 9.8) a triangulation of the convex hull whose edges
  are all locally Delaunay is a Delaunay triangulation.
* :func:`exact_delaunay` builds one: a sweep in lexicographic order (each new point is outside the
  hull of the earlier ones and is joined to the hull edges it sees strictly), then Lawson's flips
  of the edges that are not locally Delaunay (Lawson 1977), each flip decided exactly.
* :func:`lawson_flips` repairs a triangulation made in floats (qhull's, of hundreds of thousands
  of samples), everywhere or where its caller allows: the float filters on the edges at once,
  integers for the few they leave undecided, then Lawson's flips of the edges found strictly
  illegal.  qhull merges facets whose points are co-circular within its roundoff, which grows
  with the number and the magnitude of the points, and triangulates the merged facet in any way:
  a point 10⁻¹¹ of the radius inside a circle can be left outside its triangle (a segment's
  sample 10⁻⁴ from a point site, inside the circle of three point sites by 2·10⁻¹⁰ at
  coordinates 10⁴, among 4·10⁵ samples).

Predicates: :func:`runtime.predicates.orientation.orient2d` and ``incircle`` (Shewchuk's float
filters, DCG 18 (1997), then exact integers: the library's one implementation of both).
Co-circular points are triangulated in either way; the diagram's vertex of a co-circular set is
merged downstream.

Public API: :func:`exact_delaunay`, :func:`is_delaunay`, :func:`lawson_flips`, :func:`orientation`.
"""
from __future__ import annotations

import numpy as np

from ..predicates.orientation import incircle, incircle_filter, orient2d, orient2d_filter

__all__ = ["exact_delaunay", "is_delaunay", "lawson_flips", "orientation"]

class _Points:
    """Float coordinates of the points (checked finite) and the two predicates on their indices."""

    def __init__(self, P):
        self.f = np.asarray(P, float)
        if not np.isfinite(self.f).all():
            raise ValueError("non-finite point coordinates")

    def orient(self, a, b, c) -> int:
        """Sign of the orientation of (a, b, c): > 0 counter-clockwise."""
        f = self.f
        return orient2d(f[a], f[b], f[c])

    def incircle(self, a, b, c, d) -> int:
        """Sign of incircle(a, b, c, d) for (a, b, c) counter-clockwise: > 0 when d is strictly
        inside their circle."""
        f = self.f
        return incircle(f[a], f[b], f[c], f[d])


def orientation(a, b, c) -> int:
    """The exact sign of the orientation of three float points (> 0: counter-clockwise)."""
    return orient2d(*np.array([a, b, c], float))


def is_delaunay(P, simplices, neighbors) -> bool:
    """Is (simplices, neighbors) — qhull's layout: neighbors[t, k] across the side opposite vertex
    k, −1 on the hull — a Delaunay triangulation of all the points P, decided exactly?  The float
    filters run on all triangles and edges at once; only undecided ones go to integers."""
    pts = _Points(P)
    S = np.asarray(simplices, dtype=np.int64)
    N = np.asarray(neighbors, dtype=np.int64)
    n = len(pts.f)
    if n < 3 or len(S) == 0 or len(np.unique(S)) != n:
        return False
    F = pts.f
    det, sure = orient2d_filter(F[S[:, 0]], F[S[:, 1]], F[S[:, 2]])
    if (sure & (det <= 0)).any():
        return False
    for t in np.nonzero(~sure)[0].tolist():
        if pts.orient(*(int(v) for v in S[t])) <= 0:
            return False
    # interior edges: the vertex of the neighbour s opposite the shared side, against t's circle
    t_idx, k_idx = np.nonzero(N >= 0)
    keep = t_idx < N[t_idx, k_idx]
    t_idx, k_idx = t_idx[keep], k_idx[keep]
    s_idx = N[t_idx, k_idx]
    back = N[s_idx] == t_idx[:, None]
    if not (back.sum(axis=1) == 1).all():
        return False
    D = F[S[s_idx, back.argmax(axis=1)]]
    det, sure = incircle_filter(F[S[t_idx, 0]], F[S[t_idx, 1]], F[S[t_idx, 2]], D)
    if (sure & (det > 0)).any():
        return False
    d_idx = S[s_idx, back.argmax(axis=1)]
    for e in np.nonzero(~sure)[0].tolist():
        if pts.incircle(*(int(v) for v in S[t_idx[e]]), int(d_idx[e])) > 0:
            return False
    # hull sides: the boundary turns left or goes straight, one cycle through its vertices
    tb, kb = np.nonzero(N < 0)
    nxt = {int(S[t, (k + 1) % 3]): int(S[t, (k + 2) % 3]) for t, k in zip(tb.tolist(), kb.tolist())}
    if len(nxt) != len(tb):
        return False
    for u, v in nxt.items():
        w = nxt.get(v)
        if w is None or pts.orient(u, v, w) < 0:
            return False
    start = next(iter(nxt))
    seen, u = 0, start
    while True:
        u = nxt[u]
        seen += 1
        if u == start or seen > len(nxt):
            break
    return u == start and seen == len(nxt)


def exact_delaunay(P):
    """(simplices, neighbors) of a Delaunay triangulation of the points P (n × 2, distinct), in
    qhull's layout, triangles counter-clockwise; None when all points lie on one line (exactly)."""
    pts = _Points(P)
    n = len(pts.f)
    order = sorted(range(n), key=lambda k: (pts.f[k, 0], pts.f[k, 1]))     # floats are exact
    if n < 3:
        return None
    # the collinear prefix, then the first point off its line
    m = 2
    while m < n and pts.orient(order[0], order[1], order[m]) == 0:
        m += 1
    if m == n:
        return None
    tris: list = []
    q = order[m]
    chain = order[:m]
    side = pts.orient(chain[0], chain[1], q)
    for a, b in zip(chain, chain[1:]):
        tris.append([a, b, q] if side > 0 else [b, a, q])
    # the hull, counter-clockwise, as successor / predecessor maps
    ring = (chain + [q]) if side > 0 else ([q] + chain[::-1])
    succ = {ring[k]: ring[(k + 1) % len(ring)] for k in range(len(ring))}
    pred = {v: u for u, v in succ.items()}
    last = q
    for r in order[m + 1:]:
        # an edge at the lexicographically last hull vertex is strictly visible from r
        if pts.orient(last, succ[last], r) < 0:
            u = last
        elif pts.orient(pred[last], last, r) < 0:
            u = pred[last]
        else:
            raise AssertionError("sweep: no visible hull edge at the last point")
        lo, hi = u, succ[u]                     # the visible chain lo → … → hi
        while pts.orient(pred[lo], lo, r) < 0:
            lo = pred[lo]
        while pts.orient(hi, succ[hi], r) < 0:
            hi = succ[hi]
        v = lo
        while v != hi:
            w = succ[v]
            tris.append([w, v, r])
            v = w
        # the chain lo … hi leaves the hull; r joins it
        v = succ[lo]
        while v != hi:
            w = succ[v]
            del succ[v], pred[v]
            v = w
        succ[lo], pred[r], succ[r], pred[hi] = r, lo, hi, r
        last = r
    simp = np.array(tris, dtype=np.int64)
    simp = _lawson(pts, simp)
    return simp, _neighbours(simp)


def _neighbours(simp):
    """qhull's neighbour layout from triangles (−1 on the hull)."""
    where = {}
    for t, (a, b, c) in enumerate(simp.tolist()):
        where[(b, c)] = (t, 0)
        where[(c, a)] = (t, 1)
        where[(a, b)] = (t, 2)
    nb = np.full(simp.shape, -1, dtype=np.int64)
    for (u, v), (t, k) in where.items():
        o = where.get((v, u))
        if o is not None:
            nb[t, k] = o[0]
    return nb


def _lawson(pts, simp):
    """Flip edges that are not locally Delaunay until none is left (each flip removes an edge
    whose quadrilateral's fourth point lies strictly inside the circle of the other three, so the
    process ends: the lifted surface only goes down; Lawson 1977)."""
    tris = simp.tolist()
    edge = {}
    for t, (a, b, c) in enumerate(tris):
        edge[(a, b)] = t
        edge[(b, c)] = t
        edge[(c, a)] = t
    stack = [e for e in edge if e[0] < e[1] and (e[1], e[0]) in edge]
    while stack:
        a, b = stack.pop()
        t1, t2 = edge.get((a, b)), edge.get((b, a))
        if t1 is None or t2 is None:
            continue
        c = next(w for w in tris[t1] if w not in (a, b))
        d = next(w for w in tris[t2] if w not in (a, b))
        if pts.incircle(*_rot(tris[t1], a), d) <= 0:
            continue
        # quadrilateral a, d, b, c (counter-clockwise): the diagonal c–d replaces a–b
        for e in ((a, b), (b, c), (c, a), (b, a), (a, d), (d, b)):
            edge.pop(e, None)
        tris[t1], tris[t2] = [a, d, c], [d, b, c]
        for t in (t1, t2):
            x, y, z = tris[t]
            edge[(x, y)], edge[(y, z)], edge[(z, x)] = t, t, t
        for e in ((a, d), (d, b), (b, c), (c, a)):
            stack.append(e)
    return np.array(tris, dtype=np.int64)


def _rot(tri, a):
    """The triangle's vertices counter-clockwise starting at a."""
    k = tri.index(a)
    return tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3]


def lawson_flips(P, simplices, neighbors, allow=None, rows=None):
    """Lawson's flips (Lawson 1977) of the edges of a triangulation that are not locally Delaunay,
    decided exactly: (simplices, neighbors, changed) in qhull's layout (neighbors[t, k] across the
    side opposite vertex k, −1 on the hull), ``changed`` the sorted rows rewritten (each flip
    rewrites its two triangles in place, counter-clockwise; the other rows are untouched); None
    when no edge is flipped.  ``allow(p, q, r, d)`` (optional, point indices): whether the side q–r
    of the triangle (p, q, r), whose neighbour across it has the far corner d, may be flipped to
    p–d; asked of illegal sides only (a caller that knows more than the points, such as which
    sites the points sample, says where).  ``rows`` (optional): only the sides of these triangles
    are examined first (then those of the flipped ones).

    An edge is flipped only when both its triangles are strictly oriented, the fourth point lies
    strictly inside the circle of the other three and both new triangles are strictly oriented
    counter-clockwise (a strictly convex quadrilateral): each flip is then a flip of a valid
    triangulation, the lifted surface goes strictly down and the process ends (de Berg et al.,
    *Computational Geometry*, §9.1–9.2); a triangulation that is not one (qhull's output is
    assumed to be) is stopped after 10 flips per triangle.  Co-circular quadrilaterals (incircle
    exactly 0) are left as they are: either diagonal is Delaunay."""
    F = np.asarray(P, float)
    S = np.asarray(simplices, dtype=np.int64)
    N = np.asarray(neighbors, dtype=np.int64)
    if len(S) < 2:
        return None
    det, sure = orient2d_filter(F[S[:, 0]], F[S[:, 1]], F[S[:, 2]])
    o = np.sign(det).astype(np.int64)
    for t in np.nonzero(~sure)[0].tolist():
        o[t] = orientation(*F[S[t]])
    if rows is None:
        t_idx, k_idx = np.nonzero(N >= 0)
        keep = t_idx < N[t_idx, k_idx]
        t_idx, k_idx = t_idx[keep], k_idx[keep]
    else:
        rows = np.asarray(rows, dtype=np.int64)
        t_idx, k_idx = np.repeat(rows, 3), np.tile(np.arange(3), len(rows))
        keep = N[t_idx, k_idx] >= 0
        t_idx, k_idx = t_idx[keep], k_idx[keep]
    s_idx = N[t_idx, k_idx]
    back = N[s_idx] == t_idx[:, None]
    d_idx = S[s_idx, back.argmax(axis=1)]
    live = (o[t_idx] != 0) & (o[s_idx] != 0) & (back.sum(axis=1) == 1)
    idet, isure = incircle_filter(F[S[t_idx, 0]], F[S[t_idx, 1]], F[S[t_idx, 2]], F[d_idx])
    bad = live & isure & (idet * o[t_idx] > 0)
    for e in np.nonzero(live & ~isure)[0].tolist():
        if incircle(*F[S[t_idx[e]]], F[d_idx[e]]) * o[t_idx[e]] > 0:
            bad[e] = True
    if not bad.any():
        return None
    S, N, o = S.copy(), N.copy(), o.copy()
    stack = list(zip(t_idx[bad].tolist(), k_idx[bad].tolist()))
    if allow is not None:
        stack = [(t, k) for t, k in stack
                 if allow(*(int(S[t, (k + m) % 3]) for m in range(3)), int(S[N[t, k]][N[N[t, k]] == t][0]))]
    changed: set = set()
    budget = 10 * len(S)
    while stack and budget > 0:
        t, k = stack.pop()
        u = int(N[t, k])
        if u < 0 or o[t] == 0 or o[u] == 0:
            continue
        j = [m for m in range(3) if N[u, m] == t]
        if len(j) != 1:
            continue
        j = j[0]
        p = int(S[t, k])
        q, r = (int(S[t, (k + 1) % 3]), int(S[t, (k + 2) % 3]))
        if o[t] < 0:
            q, r = r, q                       # (p, q, r) counter-clockwise
        s = int(S[u, j])
        if incircle(F[p], F[q], F[r], F[s]) <= 0 or (allow is not None and not allow(p, q, r, s)):
            continue
        if orient2d(F[p], F[q], F[s]) <= 0 or orient2d(F[p], F[s], F[r]) <= 0:
            continue                          # the quadrilateral p, q, s, r is not strictly convex
        row_t, row_u = S[t].tolist(), S[u].tolist()
        n_rp = int(N[t, row_t.index(q)])      # across r–p (opposite q in t)
        n_pq = int(N[t, row_t.index(r)])      # across p–q
        n_qs = int(N[u, row_u.index(r)])      # across q–s (opposite r in u)
        n_sr = int(N[u, row_u.index(q)])      # across s–r
        S[t], N[t] = (p, q, s), (n_qs, u, n_pq)
        S[u], N[u] = (p, s, r), (n_sr, n_rp, t)
        o[t] = o[u] = 1
        if n_qs >= 0:
            N[n_qs][N[n_qs] == u] = t
        if n_rp >= 0:
            N[n_rp][N[n_rp] == t] = u
        changed.update((t, u))
        budget -= 1
        stack.extend(((t, 0), (t, 2), (u, 0), (u, 1)))
    if not changed:
        return None
    return S, N, np.array(sorted(changed), dtype=np.int64)
