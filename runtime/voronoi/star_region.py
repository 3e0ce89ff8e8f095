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
points of an edge (s, t) where the ray from c_s in direction e meets the bisector, at distance
λ = (|w|² − δ²) / (2(δ + e·w)) (w = c_t − c_s, δ = ρ_t − ρ_s: the squared form of
|λe − w| = λ + δ), and the cut edge from the old polyline's points before the crossing; the
polylines and their tolerances are then made by the construction's
:func:`runtime.voronoi.edge_polylines.edge_polylines` (projection, densification, the verifier's
Hausdorff bound), given these points as its chains.

Nothing here is a proof.  The candidate goes through the same closure check and the same proofs as
a local diagram from the construction (:func:`runtime.voronoi.insertion.local_update`): when an
edge with both ends in X keeps a middle piece (an edge conflicting at both ends), a degree-4
vertex, the point at infinity, or Newton's other solution make the candidate wrong, a proof or the
closure fails and the insertion falls back to the construction's local diagram.  ``None`` is
returned when the generic picture does not even hold (an unbounded edge at X, a point of the
polyline of an edge with both ends in X farther from s than from the edge's sites, no sign change
along a cut edge, consecutive vertices not sharing exactly one site, fewer than three new
vertices).

Public API: :func:`star_region`.
"""
from __future__ import annotations

import math
import types

import numpy as np

from .edge_polylines import edge_polylines
from .site_arrays import SiteArrays
from .structure import DiagramVertex

__all__ = ["star_region"]

#: interior points of an edge (s, t) per radian of direction from c_s (at least 2, at most 32)
POINTS_PER_RADIAN = 8


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
    cut = []                                    # (edge id, kept end w, oriented polyline)
    for e in sorted(rm_e):
        ends = edges[e].ends
        if None in ends:
            return None
        inside = [w in X for w in ends]
        if all(inside):
            # removed whole: a polyline point farther from s than from the edge's sites means a
            # middle piece survives (an edge conflicting at both ends), outside the generic picture
            P = np.asarray(edges[e].polyline, float)
            ax, ay, ra = _centre(dyn.geoms[edges[e].sites[0]])
            h = (np.hypot(P[:, 0] - cx, P[:, 1] - cy) - rs) - (np.hypot(P[:, 0] - ax, P[:, 1] - ay) - ra)
            if np.any(h > 0):
                return None
            continue
        P = np.asarray(edges[e].polyline, float)
        w = ends[0] if not inside[0] else ends[1]
        if ends[0] != w:
            P = P[::-1]
        cut.append((e, w, P))
    if len(cut) < 3:
        return None
    cs = np.array([cx, cy])
    seeds, pairs, chains = [], [], []
    for e, w, P in cut:
        a, b = edges[e].sites
        ga, gb = dyn.geoms[a], dyn.geoms[b]
        if ga.kind not in ("point", "circle") or gb.kind not in ("point", "circle"):
            return None
        ax, ay, ra = _centre(ga)
        h = (np.hypot(P[:, 0] - cx, P[:, 1] - cy) - rs) - (np.hypot(P[:, 0] - ax, P[:, 1] - ay) - ra)
        neg = np.nonzero(h <= 0)[0]
        if not len(neg) or neg[0] == 0:
            return None
        k = int(neg[0])
        t = h[k - 1] / (h[k - 1] - h[k])
        seeds.append(P[k - 1] + t * (P[k] - P[k - 1]))
        pairs.append((a, b))
        chains.append(P[1:k])
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
    # the edges (s, t) between consecutive vertices around c_s
    s_edges = []                                # (t, k from, k to, interior points)
    for q in range(m):
        k0, k1 = int(order[q]), int(order[(q + 1) % m])
        shared = set(pairs[k0]) & set(pairs[k1])
        if len(shared) != 1:
            return None
        t = shared.pop()
        a0 = float(ang[k0])
        span = (float(ang[k1]) - a0) % (2 * math.pi)
        if not 0 < span < 2 * math.pi:
            return None
        npts = int(min(32, max(2, math.ceil(POINTS_PER_RADIAN * span))))
        th = a0 + span * np.arange(1, npts + 1) / (npts + 1)
        E = np.column_stack([np.cos(th), np.sin(th)])
        tx, ty, rt = _centre(dyn.geoms[t])
        wv = np.array([tx - cx, ty - cy])
        dl = rt - rs
        den = 2 * (dl + E @ wv)
        if not np.all(den > 0):
            return None
        lam = (float(wv @ wv) - dl * dl) / den
        if not np.all((lam >= rs) & (lam + dl >= 0)):
            return None
        s_edges.append((t, k0, k1, cs + lam[:, None] * E))
    # the polylines: the construction's edge_polylines over these chains, in local numbering
    kept = sorted({w for _, w, _ in cut})
    L = sorted({s} | {t for p in pairs for t in p} | {t for w in kept for t in verts[w].sites})
    pos = {t: k for k, t in enumerate(L)}
    vl = [DiagramVertex(k, tuple(pos[t] for t in gs), lv.x, lv.y, lv.radius) for k, (lv, gs) in enumerate(new_v)]
    vl += [DiagramVertex(m + k, tuple(pos[t] for t in verts[w].sites), verts[w].x, verts[w].y, verts[w].radius)
           for k, w in enumerate(kept)]
    kpos = {w: m + k for k, w in enumerate(kept)}
    cc, raw, meta = [], [], []
    for k, ((e, w, _), chain) in enumerate(zip(cut, chains)):
        idx = list(range(len(cc), len(cc) + len(chain)))
        cc.extend(chain.tolist())
        raw.append((tuple(sorted((pos[pairs[k][0]], pos[pairs[k][1]]))), ("v",), idx, ("v",), (kpos[w], k)))
        meta.append((tuple(sorted(pairs[k])), [("old", w), ("new", k)]))
    for t, k0, k1, pts in s_edges:
        idx = list(range(len(cc), len(cc) + len(pts)))
        cc.extend(pts.tolist())
        raw.append((tuple(sorted((pos[s], pos[t]))), ("v",), idx, ("v",), (k0, k1)))
        meta.append((tuple(sorted((s, t))), [("new", k0), ("new", k1)]))
    S = SiteArrays([sites[t] for t in L], [dyn.geoms[t] for t in L])
    tri = types.SimpleNamespace(cc=np.array(cc, float).reshape(-1, 2))
    loc_edges = edge_polylines(S, tri, vl, raw)
    new_e = [(le, pair, ends) for le, (pair, ends) in zip(loc_edges, meta)]
    return {"loc": None, "L": sorted({s} | {t for p in pairs for t in p}), "new_v": new_v, "new_e": new_e,
            "rm_v": set(X), "rm_e": rm_e}


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
