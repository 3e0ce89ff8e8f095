"""The diagram left in the region of a deleted circle or point, built directly from its neighbours.

When site i is deleted (thesis §1.2: nothing changes outside the region of i), the old region of i
is shared among its Delaunay neighbours N, and the new diagram there is the Voronoi diagram of N
restricted to that region (Karavelas & Yvinec, *Dynamic additively weighted Voronoi diagrams in
2D*, ESA 2002, the deletion of CGAL's ``Apollonius_graph_2::remove``; for points, the star of
the removed Delaunay vertex is re-triangulated from its link, Devillers, *On deletion in Delaunay
triangulations*, IJCGA 12 (2002)).  In the generic case:

* every vertex v = (i, a, b) of i is removed; the edge (a, b) that left v towards a kept vertex w
  now goes on into the old region of i (its *exit* at w);
* the new vertices are the Voronoi vertices of triples of N lying in the old region of i: the
  points q equidistant from three sites of N (both roots of each triple in closed form: the two
  linear equations d_l − d_0 = 0 give q = p0 − r·p1 and d_0 = r a quadratic in r, thesis §3.1.2)
  with r > 0, every other site of N farther than r, and site i nearer than r (q was in i's region);
* each pair (a, b) of sites then has exactly two ends in the region, new vertices or exits, joined
  by one edge (the region's new part is a tree whose leaves are the exits).

This module builds that candidate with floating point, its polylines on the closed-form bisectors
(:func:`runtime.voronoi.star_region.bisector_polylines`).  Nothing here is a proof: the candidate
goes through the closure check and the proofs of :func:`runtime.voronoi.insertion.local_update`,
as the construction's local diagram does, and when it is wrong (a vertex of degree four, a
bisector meeting the region twice, nearly co-circular sites) a check or a proof fails and the
deletion falls back to the construction's local diagram.  ``None`` is returned when the generic
picture does not even hold (a vertex of i with more than three sites, an unbounded edge of i, an
edge (a, b) with both ends at vertices of i, a pair without exactly two ends, an ellipse).

Public API: :func:`hole_region`.
"""
from __future__ import annotations

import itertools
import math
import types

import numpy as np

from .star_region import bisector_polylines

__all__ = ["hole_region"]


def _disc(g):
    return (g.x0, g.y0, 0.0) if g.kind == "point" else (g.cx, g.cy, g.rho)


def hole_region(D, dyn, X, i, new_index):
    """The candidate splice for deleting site ``i`` (``D``'s numbering; ``dyn`` its
    :class:`runtime.voronoi.adjacency.DynamicState`, still in that numbering) whose vertices are
    ``X``; ``new_index`` maps an old site index to the new one.  Returns the dict that
    :func:`runtime.voronoi.insertion.local_update` checks and proves (``new_v``, ``new_e``, ``rm_v``,
    ``rm_e``, ``L``; sites in the new numbering, kept vertices by their ids in ``D``), or None
    (module docstring)."""
    verts, edges = D.vertices, D.edges
    if len(X) < 2 or dyn.geoms[i].kind not in ("point", "circle"):
        return None
    if any(None in edges[e].ends for e in dyn.site_e[i]):
        return None                             # i's region reaches infinity
    rm_e = set(dyn.site_e[i]) | {e for v in X for e in dyn.v_e[v]}
    exits = []                                  # (pair, kept vertex w)
    for v in X:
        s = verts[v].sites
        if len(s) != 3:
            return None
        pair = tuple(sorted(t for t in s if t != i))
        out = [e for e in dyn.v_e[v] if tuple(edges[e].sites) == pair]
        if len(out) != 1:
            return None
        ends = edges[out[0]].ends
        w = ends[0] if ends[1] == v else ends[1]
        if w is None or w in X or None in ends:
            return None
        exits.append((pair, w))
    N = sorted({t for p, _ in exits for t in p})
    G = np.array([_disc(dyn.geoms[t]) for t in N], float)
    if any(dyn.geoms[t].kind not in ("point", "circle") for t in N):
        return None
    ci = np.array(_disc(dyn.geoms[i]), float)
    V, T = _vertices(G, ci)
    if V is None:
        return None
    # the ends of each pair: new vertices and exits
    ends_of: dict = {}
    for k, tri in enumerate(T):
        for a, b in ((0, 1), (0, 2), (1, 2)):
            ends_of.setdefault((N[tri[a]], N[tri[b]]), []).append(("new", k))
    for pair, w in exits:
        ends_of.setdefault(pair, []).append(("old", w))
    if any(len(x) != 2 for x in ends_of.values()):
        return None
    new_v = []
    for k, tri in enumerate(T):
        x, y, r = V[k]
        gl = [N[t] for t in tri]
        th = [math.atan2(G[t, 1] - y, G[t, 0] - x) for t in tri]
        gs = tuple(new_index(t) for _, t in sorted(zip(th, gl)))
        q = gs.index(min(gs))
        new_v.append((types.SimpleNamespace(x=float(x), y=float(y), radius=float(r)), gs[q:] + gs[:q]))

    def xy(end):
        return (V[end[1], 0], V[end[1], 1]) if end[0] == "new" else (verts[end[1]].x, verts[end[1]].y)

    pairs = sorted(ends_of)
    polys = bisector_polylines(dyn, pairs, np.array([[xy(x) for x in ends_of[p]] for p in pairs], float))
    if polys is None:
        return None
    new_e = [(types.SimpleNamespace(polyline=P, tolerance=tol), tuple(sorted(new_index(t) for t in p)), ends_of[p])
             for (P, tol), p in zip(polys, pairs)]
    return {"loc": None, "L": sorted(new_index(t) for t in N), "new_v": new_v, "new_e": new_e,
            "rm_v": set(X), "rm_e": rm_e}


def _vertices(G, ci):
    """The Voronoi vertices of the sites G (rows x, y, ρ; pairwise disjoint circles or points)
    that lie where the site ``ci`` is nearer than their three sites: (rows x, y, r; triples of row
    indices), or (None, None) when a triple is too close to degenerate to tell (collinear centres
    with equal radii, a double root)."""
    n = len(G)
    T = np.array(list(itertools.combinations(range(n), 3)), dtype=np.int64).reshape(-1, 3)
    if not len(T):
        return np.zeros((0, 3)), []
    c0, r0 = G[T[:, 0], :2], G[T[:, 0], 2]
    E = G[T[:, 1:], :2] - c0[:, None, :]                          # (m, 2, 2): e_1, e_2
    rho = G[T[:, 1:], 2]
    A = 2 * E
    b = (E ** 2).sum(-1) - rho ** 2 + r0[:, None] ** 2
    d = 2 * (rho - r0[:, None])
    det = A[:, 0, 0] * A[:, 1, 1] - A[:, 0, 1] * A[:, 1, 0]
    scale = float(np.abs(A).max()) if len(A) else 1.0
    regular = np.abs(det) > 1e-9 * scale * scale
    Ag = np.where(regular[:, None, None], A, np.eye(2))
    p0 = np.linalg.solve(Ag, b[..., None])[..., 0]
    p1 = np.linalg.solve(Ag, d[..., None])[..., 0]
    qa = (p1 ** 2).sum(-1) - 1
    qb = -2 * ((p0 * p1).sum(-1) + r0)
    qc = (p0 ** 2).sum(-1) - r0 ** 2
    disc = qb * qb - 4 * qa * qc
    with np.errstate(all="ignore"):
        sq = np.sqrt(np.maximum(disc, 0.0))
        big = -0.5 * (qb + np.where(qb >= 0, sq, -sq))              # stable roots: big / qa, qc / big
        roots = np.stack([np.where(np.abs(qa) > 1e-12 * (1 + np.abs(qb)), big / qa, np.nan), qc / big], axis=1)
    rows = np.repeat(np.arange(len(T)), 2)
    r = roots.ravel()
    ok = regular[rows] & (disc[rows] >= 0) & np.isfinite(r) & (r > 0)
    rows, r = rows[ok], r[ok]
    Q = c0[rows] + p0[rows] - r[:, None] * p1[rows]
    # empty of the other sites, and site i nearer than the three (the point was in its region)
    dist = np.hypot(Q[:, None, 0] - G[None, :, 0], Q[:, None, 1] - G[None, :, 1]) - G[None, :, 2]
    own = np.zeros_like(dist, bool)
    own[np.arange(len(rows))[:, None], T[rows]] = True
    tol = 1e-9 * (1 + np.abs(Q).sum(axis=1) + r)
    empty = np.where(own, True, dist > r[:, None] + tol[:, None]).all(axis=1)
    ambiguous = (~own & (np.abs(dist - r[:, None]) <= tol[:, None])).any(axis=1)
    di = np.hypot(Q[:, 0] - ci[0], Q[:, 1] - ci[1]) - ci[2]
    inside = di < r - tol
    keep = empty & inside
    near = di < r + tol                         # in or at the region: what the candidate depends on
    if (ambiguous & near).any() or (empty & (np.abs(di - r) <= tol)).any() or (~regular).any():
        return None, None
    return np.column_stack([Q[keep], r[keep]]), [tuple(int(t) for t in T[k]) for k in rows[keep]]
