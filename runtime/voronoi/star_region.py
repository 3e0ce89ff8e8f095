"""The region of a newly inserted circle or point built directly from its conflict region.

After the conflicting vertices X of a new site s are found (:mod:`runtime.voronoi.insertion`,
thesis §1.2), the changed part of the diagram of circles and points is, in the generic case
(Karavelas & Yvinec, *Dynamic additively weighted Voronoi diagrams in 2D*, ESA 2002, §3, the
update of CGAL's ``Apollonius_graph_2::insert``):

* every edge (a, b) with one end in X and the other end w kept is cut where s gets as near as a
  and b: a new vertex (s, a, b) on it, and the edge now runs from w to that vertex;
* the edges with both ends in X and the vertices X are removed;
* the new vertices, in the order of their directions from the centre c_s (the region of s is
  star-shaped from c_s: on every ray from c_s, d_s − d_k grows at least as fast as the distance
  travelled, since |∇d_k| ≤ 1), are joined by the edges (s, t) of the site t that the two
  consecutive vertices share.

This module builds that candidate with floating point: each new vertex by Newton's method on
d_s = d_a = d_b from the point where d_s − d_a changes sign along the old edge's polyline; the
polylines of the new edges (the cut edges and the edges (s, t)) on their bisectors in closed form
(:func:`bisector_polylines`: the bisector of two disjoint circles or points is a branch of a
hyperbola, thesis §3.1, and an edge is the arc between its vertices' parameters), their
tolerances by the verifier's Hausdorff bound.

Nothing here is a proof.  The candidate goes through the same closure check and the same proofs as
a local diagram from the construction (:func:`runtime.voronoi.insertion.local_update`): when an
edge with both ends in X keeps a middle piece (an edge conflicting at both ends), a degree-4
vertex, the point at infinity, or Newton's other solution make the candidate wrong, a proof or the
closure fails and the insertion falls back to the construction's local diagram.  ``None`` is
returned when the generic picture does not even hold (an unbounded edge at X, a point of the
polyline of an edge with both ends in X farther from s than from the edge's sites, no sign change
along a cut edge, consecutive vertices not sharing exactly one site, fewer than three new
vertices).

Public API: :func:`star_region`, :func:`bisector_polylines`, :data:`INITIAL_PIECES`, :data:`MAX_SPLIT`,
:data:`CHORD_REL`.
"""
from __future__ import annotations

import math
import types

import numpy as np

from .verify.edges import CircleTable, bisector, params
from .verify.polyline_bound import hausdorff_bounds

__all__ = ["star_region", "bisector_polylines", "INITIAL_PIECES", "MAX_SPLIT", "CHORD_REL"]

#: pieces of equal parameter steps an edge's polyline starts from (:func:`bisector_polylines`)
INITIAL_PIECES = 4
#: each of them is cut into at most this many (so at most 4·16 = 64 segments per edge)
MAX_SPLIT = 16
#: the target: the sagitta of a segment at most this fraction of its distance to the sites (on 10⁴
#: random circles it gives the tolerances of the construction's polylines, median 10⁻³ of the
#: distance, with as many points)
CHORD_REL = 2e-3


def _centre(g):
    return (g.x0, g.y0, 0.0) if g.kind == "point" else (g.cx, g.cy, g.rho)


def star_region(D, dyn, sites, X, s):
    """The candidate splice for inserting site ``s`` (index into ``sites``, the new list; the
    others keep their indices) into ``D`` with the conflicting vertices ``X``, or None when the
    generic picture above does not hold.  ``dyn``: the diagram's
    :class:`runtime.voronoi.adjacency.DynamicState` (with s added).  Returns the dict that
    :func:`runtime.voronoi.insertion.local_update` checks and proves: ``new_v`` [(vertex, sites)],
    ``new_e`` [(edge, pair, ends)] with ends ("new", k) or ("old", vertex id), ``rm_v``, ``rm_e``
    and ``L`` (the sites of the new vertices)."""
    if not X:
        return None
    verts, edges = D.vertices, D.edges
    rm_e = {e for v in X for e in dyn.v_e[v]}
    gs_ = dyn.geoms[s]
    if gs_.kind not in ("point", "circle"):
        return None
    cx, cy, rs = _centre(gs_)
    # every polyline of a conflicting edge, oriented from its kept end (if any), with
    # h = (d_s − d_a) at its points (a: the edge's first site; h ≤ 0 where s is at least as near)
    cut, polys, whole, owners = [], [], [], []   # cut: (edge id, kept end w, oriented polyline)
    for e in sorted(rm_e):
        ends = edges[e].ends
        if None in ends:
            return None
        inside = [w in X for w in ends]
        P = np.asarray(edges[e].polyline, float)
        if all(inside):
            whole.append(len(polys))
        else:
            w = ends[0] if not inside[0] else ends[1]
            if ends[0] != w:
                P = P[::-1]
            cut.append((e, w, P))
        polys.append(P)
        owners.append(edges[e].sites)
    if len(cut) < 3:
        return None
    for a, b in owners:
        if dyn.geoms[a].kind not in ("point", "circle") or dyn.geoms[b].kind not in ("point", "circle"):
            return None
    lens = np.array([len(P) for P in polys])
    first = np.cumsum(lens) - lens
    Pall = np.concatenate(polys)
    G = np.array([_centre(dyn.geoms[a]) for a, _ in owners], float)[np.repeat(np.arange(len(polys)), lens)]
    h = (np.hypot(Pall[:, 0] - cx, Pall[:, 1] - cy) - rs) - (np.hypot(Pall[:, 0] - G[:, 0], Pall[:, 1] - G[:, 1]) - G[:, 2])
    if whole and np.any(np.maximum.reduceat(h, first)[whole] > 0):
        # removed whole: a polyline point farther from s than from the edge's sites means a
        # middle piece survives (an edge conflicting at both ends), outside the generic picture
        return None
    seeds, pairs = [], []
    negs = np.flatnonzero(h <= 0)
    ws = set(whole)
    cut_at = [t for t in range(len(polys)) if t not in ws]
    for (e, w, P), t in zip(cut, cut_at):
        k = int(np.searchsorted(negs, first[t]))
        if k == len(negs) or negs[k] >= first[t] + lens[t] or negs[k] == first[t]:
            return None                         # no point of the edge in conflict, or its kept end is
        g = int(negs[k])
        f = h[g - 1] / (h[g - 1] - h[g])
        seeds.append(Pall[g - 1] + f * (Pall[g] - Pall[g - 1]))
        pairs.append(tuple(edges[e].sites))
    cs = np.array([cx, cy])
    V = _newton(np.array(seeds), cs, rs, np.array([_centre(dyn.geoms[a]) for a, _ in pairs]),
                np.array([_centre(dyn.geoms[b]) for _, b in pairs]))
    if V is None:
        return None
    m = len(cut)
    ang = np.arctan2(V[:, 1] - cy, V[:, 0] - cx)
    order = np.argsort(ang)
    if np.any(np.diff(ang[order]) <= 1e-12):
        return None
    scale = 1.0 + float(np.abs(V[:, :2]).max())
    if np.min(np.hypot(*(V[order, :2] - np.roll(V[order, :2], -1, axis=0)).T)) <= 1e-9 * scale:
        return None                             # coinciding vertices (degree 4 or more)
    # the new vertices: sites counter-clockwise by their contact points, the smallest first
    new_v = []
    for k in range(m):
        x, y, r = V[k]
        tri = [s, *pairs[k]]
        th = [math.atan2(_centre(dyn.geoms[t])[1] - y, _centre(dyn.geoms[t])[0] - x) for t in tri]
        gs = tuple(t for _, t in sorted(zip(th, tri)))
        q = gs.index(min(gs))
        new_v.append((types.SimpleNamespace(x=float(x), y=float(y), radius=float(r)), gs[q:] + gs[:q]))
    # the edges: each cut edge from its kept end to its new vertex, and the edges (s, t) between
    # consecutive new vertices around c_s (t the site they share)
    meta, ends_xy = [], []                      # (pair, ends), (start point, end point)
    for k, (e, w, _) in enumerate(cut):
        meta.append((tuple(sorted(pairs[k])), [("old", w), ("new", k)]))
        ends_xy.append(((verts[w].x, verts[w].y), (V[k, 0], V[k, 1])))
    for q in range(m):
        k0, k1 = int(order[q]), int(order[(q + 1) % m])
        shared = set(pairs[k0]) & set(pairs[k1])
        if len(shared) != 1:
            return None
        meta.append((tuple(sorted((s, shared.pop()))), [("new", k0), ("new", k1)]))
        ends_xy.append(((V[k0, 0], V[k0, 1]), (V[k1, 0], V[k1, 1])))
    polys = bisector_polylines(dyn, [p for p, _ in meta], np.array(ends_xy, float))
    if polys is None:
        return None
    new_e = [(types.SimpleNamespace(polyline=P, tolerance=tol), pair, ends)
             for (P, tol), (pair, ends) in zip(polys, meta)]
    return {"loc": None, "L": sorted({s} | {t for p in pairs for t in p}), "new_v": new_v, "new_e": new_e,
            "rm_v": set(X), "rm_e": rm_e}


def bisector_polylines(dyn, pairs, ends):
    """Polylines and tolerances of bounded edges of circle and point sites, sampled on their
    bisectors in closed form: edge t of sites ``pairs[t]`` (indices into ``dyn``) runs from
    ``ends[t, 0]`` to ``ends[t, 1]`` (its vertices).  The bisector of two disjoint, non-nested
    sites is one branch q(u) = m + a·cosh u·e_x + b·sinh u·e_y of a hyperbola (a line when the
    radii are equal; :func:`runtime.voronoi.verify.edges.bisector`, thesis §3.1), a simple curve,
    so the edge is the arc between the parameters of its ends.  It is cut at equal steps of u
    (:data:`INITIAL_PIECES`), and each piece into k equal steps (at most :data:`MAX_SPLIT`), k² at
    least its sagitta (the distance from its mid-parameter point to its chord's midpoint) over
    :data:`CHORD_REL` times that point's distance to the sites.  The polyline is the two end
    vertices with the curve points between them; its tolerance is the verifier's bound on the
    Hausdorff distance between polyline and arc
    (:func:`runtime.voronoi.verify.polyline_bound.hausdorff_bounds`, which accounts for the rounding
    of the float curve), widened as :func:`runtime.voronoi.edge_polylines.edge_polylines` does.
    Returns [(polyline, tolerance)], or None when a pair has no such bisector (nested or touching
    within the float filter).  Nothing here is a proof: the verifier proves the tolerance again."""
    sites = sorted({t for p in pairs for t in p})
    pos = {t: k for k, t in enumerate(sites)}
    geo = np.array([_centre(dyn.geoms[t]) for t in sites], float)
    table = CircleTable.from_arrays(geo[:, :2], geo[:, 2])
    biss = [bisector(table, pos[i], pos[j]) for i, j in pairs]
    if any(isinstance(b, str) or b.kind != "hyperbola" for b in biss):
        return None
    E = len(biss)
    M = np.array([b.m for b in biss])
    EX = np.array([b.ex for b in biss])
    EY = np.array([b.ey for b in biss])
    A = np.array([b.a for b in biss])
    B = np.array([b.b for b in biss])
    CI = table.C[[b.i for b in biss]]
    RI = table.R[[b.i for b in biss]]
    u0 = params(biss, np.arange(E), ends[:, 0])
    u1 = params(biss, np.arange(E), ends[:, 1])
    if not np.all(np.isfinite(u0) & np.isfinite(u1)):
        return None

    def curve(t, u):
        return M[t] + (A[t] * np.cosh(u))[:, None] * EX[t] + (B[t] * np.sinh(u))[:, None] * EY[t]

    # equal steps of u, then each piece cut into k equal steps, k² ≥ its sagitta over the target
    # (the sagitta of a short piece of a smooth curve shrinks as the square of its length)
    f = np.arange(INITIAL_PIECES + 1) / INITIAL_PIECES
    U = u0[:, None] + f[None, :] * (u1 - u0)[:, None]
    ua, ub = U[:, :-1].ravel(), U[:, 1:].ravel()
    t = np.repeat(np.arange(E), INITIAL_PIECES)
    Qm = curve(t, 0.5 * (ua + ub))
    sag = np.hypot(*(Qm - 0.5 * (curve(t, ua) + curve(t, ub))).T)
    dist = np.maximum(np.hypot(*(Qm - CI[t]).T) - RI[t], 1e-12 * table.scale)
    with np.errstate(invalid="ignore"):
        k = np.ceil(np.sqrt(sag / (CHORD_REL * dist)))
    k = np.clip(np.nan_to_num(k, nan=1.0), 1, MAX_SPLIT).astype(np.int64)
    piece = np.repeat(np.arange(len(k)), k)
    step = np.arange(int(k.sum())) - np.repeat(np.cumsum(k) - k, k)
    u = np.concatenate([ua[piece] + step / k[piece] * (ub - ua)[piece], u1])
    own = np.concatenate([t[piece], np.arange(E)])
    order = np.argsort(own, kind="stable")          # each edge's pieces in order, then its end
    u, own = u[order], own[order]
    Q = curve(own, u)
    first = np.searchsorted(own, np.arange(E))
    last = np.append(first[1:], len(own)) - 1
    Q[first], Q[last] = ends[:, 0], ends[:, 1]
    polys = [Q[first[t]:last[t] + 1] for t in range(E)]
    hb = hausdorff_bounds(biss, polys, foot_steps=1)     # the inner points lie on the float curve
    tol = hb * (1 + 1e-9) + 1e-10 * (1 + np.maximum.reduceat(np.abs(Q).max(axis=1), first))
    return list(zip(polys, tol.tolist()))


def _newton(P, cs, rs, A, B, iters: int = 40):
    """Points equidistant from the circle (cs, rs) and the circles A[k], B[k] (rows x, y, ρ), from
    the seeds P, with (x, y, r) rows (r = d_s), or None when Newton's method does not settle."""
    P = P.copy()
    scale = 1.0 + float(np.abs(P).max()) + float(np.abs(cs).max())
    for _ in range(iters):
        ds = np.hypot(P[:, 0] - cs[0], P[:, 1] - cs[1])
        da = np.hypot(P[:, 0] - A[:, 0], P[:, 1] - A[:, 1])
        db = np.hypot(P[:, 0] - B[:, 0], P[:, 1] - B[:, 1])
        if np.any(ds == 0) or np.any(da == 0) or np.any(db == 0):
            return None
        us = (P - cs) / ds[:, None]
        ua = (P - A[:, :2]) / da[:, None]
        ub = (P - B[:, :2]) / db[:, None]
        F1 = (ds - rs) - (da - A[:, 2])
        F2 = (ds - rs) - (db - B[:, 2])
        J11, J12 = (us - ua).T
        J21, J22 = (us - ub).T
        det = J11 * J22 - J12 * J21
        if np.any(np.abs(det) < 1e-14):
            return None
        dx = (F1 * J22 - F2 * J12) / det
        dy = (J11 * F2 - J21 * F1) / det
        step = np.hypot(dx, dy)
        lim = 0.25 * (ds - rs)
        f = np.where(step > lim, lim / np.maximum(step, 1e-300), 1.0)
        P[:, 0] -= f * dx
        P[:, 1] -= f * dy
        if np.all(step <= 1e-15 * scale) or np.all(np.maximum(np.abs(F1), np.abs(F2)) <= 1e-15 * scale):
            break
    ds = np.hypot(P[:, 0] - cs[0], P[:, 1] - cs[1])
    da = np.hypot(P[:, 0] - A[:, 0], P[:, 1] - A[:, 1])
    db = np.hypot(P[:, 0] - B[:, 0], P[:, 1] - B[:, 1])
    r = ds - rs
    if not (np.all(np.abs(r - (da - A[:, 2])) <= 1e-11 * scale)
            and np.all(np.abs(r - (db - B[:, 2])) <= 1e-11 * scale)):
        return None
    if not np.all(r > 0):
        return None
    return np.column_stack([P, r])
