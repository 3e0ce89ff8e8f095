"""The sites that can reach a changed part of a diagram of points and circles: a union of discs.

A local update (:mod:`runtime.voronoi.insertion`, thesis §1.2) proves its new vertices and arcs
against the sites that can enter their empty circles.  A site k (centre c_k, radius ρ_k) enters the
empty circle of a point q (radius r(q), the distance from q to the sites of q's vertex or edge)
only if |c_k − q| − ρ_k < r(q).  Hence it suffices to hand the verifier every site whose disc
comes within r_j of P_j for one of finitely many discs (P_j, r_j) that each contain the empty
circles of a part of the changed skeleton:

* a vertex v: the disc (v, r_v) itself, widened by the verifier's vertex tolerance;
* an arc, within its tolerance t of its polyline: the segments are cut into pieces of half-length
  h (:func:`polyline_pieces`) no longer than a tenth of the distance to the sites, and for the
  midpoint M of a piece and a point q of the arc near it, |q − M| ≤ h + t and, the distance d_i to
  a site being 1-Lipschitz, r(q) = d_i(q) ≤ d_i(M) + h + t: the empty circle of q lies in the disc
  (M, d_i(M) + 2(h + t)).

One disc around the whole changed part (its mean and the largest |q − X0| + r(q)) holds the same
sites but, near the convex hull, where the empty circles are large, it held most of the scene
(900 of 10³ random circles); the pieces hug the circles and hold 10–30.  Its radius, edge by edge
(:func:`polyline_reach`): q lies within t + ℓ of a point P of the polyline (ℓ its longest segment),
so |q − X0| + r(q) ≤ |P − X0| + d_i(P) + 2(t + ℓ).

Public API: :func:`polyline_pieces`, :func:`arc_discs`, :func:`polyline_reach`, :func:`distance_to_site`,
:func:`sites_meeting_discs`, :data:`PIECE_REL`, :data:`MAX_PIECES`.
"""
from __future__ import annotations

import numpy as np

__all__ = ["polyline_pieces", "arc_discs", "polyline_reach", "distance_to_site", "sites_meeting_discs", "PIECE_REL",
           "MAX_PIECES"]

#: a polyline's segments are cut into pieces no longer than this fraction of the distance to the
#: site at the segment's ends
PIECE_REL = 0.1
#: at most this many pieces per segment (any number is sound; more pieces, tighter discs)
MAX_PIECES = 256


def distance_to_site(g, P) -> np.ndarray:
    """Distance from the points P (m, 2) to the point or circle site of geometry ``g``, for points
    outside the circle: | |P − c| − ρ |."""
    c = np.array([g.x0, g.y0] if g.kind == "point" else [g.cx, g.cy], float)
    return np.abs(np.hypot(*(np.asarray(P, float) - c).T) - (0.0 if g.kind == "point" else g.rho))


def polyline_pieces(P, g):
    """(M, h): midpoints and half-lengths of pieces covering the segments of the polyline P, each
    segment cut into equal pieces no longer than :data:`PIECE_REL` times the distance to site
    ``g`` at its nearer end (at most :data:`MAX_PIECES`).  Every point of the polyline lies within
    h of the midpoint of its piece (h is widened for the rounding of M).  A polyline of one point
    gives that point with h = 0."""
    P = np.asarray(P, float).reshape(-1, 2)
    if len(P) < 2:
        return P, np.zeros(len(P))
    A, B = P[:-1], P[1:]
    L = np.hypot(*(B - A).T)
    d = distance_to_site(g, P)
    step = PIECE_REL * np.minimum(d[:-1], d[1:])
    with np.errstate(divide="ignore", invalid="ignore"):
        m = np.where(step > 0, np.ceil(L / step), MAX_PIECES)
    m = np.clip(np.nan_to_num(m, nan=MAX_PIECES), 1, MAX_PIECES).astype(np.int64)
    seg = np.repeat(np.arange(len(A)), m)
    k = np.arange(int(m.sum())) - np.repeat(np.cumsum(m) - m, m)
    t = (k + 0.5) / m[seg]
    M = A[seg] + t[:, None] * (B[seg] - A[seg])
    h = L[seg] / (2 * m[seg]) * (1 + 1e-12) + 1e-15 * (np.abs(M).sum(axis=1) + np.abs(A[seg]).sum(axis=1) + 1)
    return M, h


def arc_discs(P, g, tol):
    """(M, r): discs holding the empty circle of every point of the arc of an edge of site ``g``
    (point or circle) that lies within ``tol`` of the polyline P: the pieces' midpoints M of
    :func:`polyline_pieces` and r = d_g(M) + 2(h + tol), widened by 1e-9 relatively for the
    rounding (module docstring)."""
    M, h = polyline_pieces(P, g)
    r = distance_to_site(g, M) + 2 * (h + tol)
    return M, r * (1 + 1e-9) + 1e-9 * (np.abs(M).sum(axis=1) + 1)


def polyline_reach(polys, C, R, tol, X0) -> np.ndarray:
    """For edges of circle and point sites given by their polylines ``polys`` (each (m_e, 2), m_e ≥ 1),
    the centre C[e] and radius R[e] of one of the edge's sites and its tolerance tol[e]: a bound on
    |q − X0[e]| + r(q) over the points q of the true arc within tol[e] of the polyline (module
    docstring), max_P (|P − X0[e]| + d_i(P)) + 2(t + ℓ), all edges at once.  ``X0``: (n_e, 2), or
    one point for all.  Not widened for rounding (the callers add their margins)."""
    lens = np.array([len(P) for P in polys])
    P = np.concatenate(polys)
    own = np.repeat(np.arange(len(polys)), lens)
    first = np.cumsum(lens) - lens
    X0 = np.broadcast_to(np.asarray(X0, float), (len(polys), 2))
    C, R = np.asarray(C, float).reshape(-1, 2), np.asarray(R, float)
    val = np.hypot(*(P - X0[own]).T) + np.abs(np.hypot(*(P - C[own]).T) - R[own])
    seg = np.zeros(len(polys))
    same = own[1:] == own[:-1]
    np.maximum.at(seg, own[1:][same], np.hypot(*np.diff(P, axis=0).T)[same])
    return np.maximum.reduceat(val, first) + 2 * (np.asarray(tol, float) + seg)


def sites_meeting_discs(dyn, P, r) -> list[int]:
    """Indices k of the sites of ``dyn`` (a :class:`runtime.voronoi.adjacency.DynamicState`:
    centres ``C``, radii ``R``, a k-d tree over the centres and the sites added since) whose disc
    comes within r_j of P_j for some j, |c_k − P_j| − R_k ≤ r_j, with a relative margin of 1e-9
    for the rounding (a superset is returned).  Candidates from the k-d tree within r_j + max R,
    then each pair tested with its own R_k."""
    P = np.asarray(P, float).reshape(-1, 2)
    r = np.asarray(r, float)
    reach = (r + dyn.rmax) * (1 + 1e-9) + 1e-9
    js, ks = [], []
    if dyn.tree is not None and len(P):
        hits = dyn.tree.query_ball_point(P, reach, return_sorted=False)
        lens = np.fromiter((len(h) for h in hits), dtype=np.int64, count=len(hits))
        flat = np.fromiter((t for h in hits for t in h), dtype=np.int64, count=int(lens.sum()))
        js.append(np.repeat(np.arange(len(P)), lens))
        ks.append(np.asarray(dyn.slot, dtype=np.int64)[flat])
    if dyn.extra and len(P):
        ex = np.asarray(dyn.extra, dtype=np.int64)
        js.append(np.repeat(np.arange(len(P)), len(ex)))
        ks.append(np.tile(ex, len(P)))
    if not js:
        return []
    j, k = np.concatenate(js), np.concatenate(ks)
    live = k >= 0
    j, k = j[live], k[live]
    gap = np.hypot(dyn.C[k, 0] - P[j, 0], dyn.C[k, 1] - P[j, 1]) - dyn.R[k]
    keep = gap <= r[j] * (1 + 1e-9) + 1e-9 * (np.abs(P[j]).sum(axis=1) + dyn.R[k] + 1)
    return np.unique(k[keep]).tolist()
