"""Voronoi vertices of degree k > 3: sites touching one empty circle (thesis §5.2, Def. 5.2.1).

A Voronoi vertex is the centre of an empty circle touching k ≥ 3 sites.  In general position
k = 3, but the inputs people draw are not in general position: a grid of points has vertices of
degree 4, points or circles tangent to one circle one vertex of degree k.  The construction finds
such a vertex as several proved triples whose exact emptiness test (thesis §3.1.3,
:func:`runtime.predicates.circles.decide_conflict`) reports the other sites as *tangent*: they
touch the empty circle exactly.  This module merges those triples into one vertex of k sites.

Identity is decided exactly, never by a tolerance: two proved triples belong to one vertex when
the exact vertex of the first is tangent to every site of the second (the same set of touching
sites, established by the exact test) and their proof boxes meet; a triple with tangent sites
whose partner triples are missing still yields the full site set (its own three plus the tangent
ones).  The k sites are ordered counter-clockwise by their contact points with the empty circle:
seen from the vertex q a site's contact point lies in the direction −∇d(q) (towards a centre
outside, away from the centre of a containing circle).  Around q the nearest site in direction
u is, to first order, the one whose contact direction is closest to u (d_s(q + εu) = ρ −
ε·u·n_s + O(ε²)), so the vertex's edges are exactly the bisectors of cyclically consecutive
sites (Okabe, Boots, Sugihara & Chiu, *Spatial Tessellations*, 2nd ed., §2.3, for points).

Public API: :func:`contact_order`, :func:`contact_order_triples`, :func:`merge_cocircular`,
:func:`consecutive_pairs`, :func:`assemble_vertices`.
"""
from __future__ import annotations

import math

import numpy as np

from .site_arrays import SiteArrays

__all__ = ["contact_order", "contact_order_triples", "merge_cocircular", "consecutive_pairs", "assemble_vertices"]


def contact_order_triples(S: SiteArrays, X, T) -> np.ndarray:
    """:func:`contact_order` for many vertices of three sites at once: X (n, 2) positions, T (n, 3)
    sites.  Rows whose contact directions cannot be ordered keep their given order (for three
    sites every pair is consecutive whatever the order, so only the listing changes)."""
    X = np.asarray(X, float).reshape(-1, 2)
    T = np.asarray(T, np.int64).reshape(-1, 3)
    if not len(T):
        return T
    q = np.repeat(X, 3, axis=0)
    _, U = S.dist_grad(q, T.ravel())
    ang = np.arctan2(-U[:, 1], -U[:, 0]).reshape(-1, 3)
    ang = np.where(np.isfinite(ang), ang, np.arange(3)[None, :])
    order = np.argsort(ang, axis=1, kind="stable")
    R = np.take_along_axis(T, order, axis=1)
    shift = np.argmin(R, axis=1)
    idx = (np.arange(3)[None, :] + shift[:, None]) % 3
    return np.take_along_axis(R, idx, axis=1)


def contact_order(S: SiteArrays, x: float, y: float, sites) -> tuple[int, ...] | None:
    """The sites sorted counter-clockwise by the direction of their contact point with the circle
    about (x, y), rotated so that the smallest index comes first.  None when two contact
    directions are too close to order in floating point (then the order is not decided)."""
    sites = [int(s) for s in sites]
    q = np.repeat(np.array([[float(x), float(y)]]), len(sites), axis=0)
    _, U = S.dist_grad(q, np.array(sites, dtype=np.int64))
    ang = np.arctan2(-U[:, 1], -U[:, 0])
    order = np.argsort(ang, kind="stable")
    a = ang[order]
    gaps = np.diff(np.concatenate([a, [a[0] + 2 * math.pi]]))
    if not np.isfinite(gaps).all() or gaps.min() <= 1e-9:
        return None
    out = [sites[t] for t in order.tolist()]
    m = out.index(min(out))
    return tuple(out[m:] + out[:m])


def consecutive_pairs(sites) -> list[tuple[int, int]]:
    """The sorted pairs of cyclically consecutive sites of a vertex (its edges' pairs)."""
    s = [int(v) for v in sites]
    return [(a, b) if a <= b else (b, a) for a, b in zip(s, s[1:] + s[:1])]


def merge_cocircular(S: SiteArrays, clusters, usable):
    """Group the usable (proved, empty) clusters into vertices.  A cluster's site set is its
    triple plus the sites the exact test found tangent to its circle (``cluster["tangent"]``).
    Clusters with the same site set whose boxes meet are one vertex; a cluster whose tangent
    sites do not all have the same set back is kept apart (the construction then refines it).

    Returns a list of groups ``(cluster ids, ordered sites or None)``; ``None``: the contact
    points could not be ordered (reported by the caller)."""
    groups: dict = {}
    for c in usable:
        cl = clusters[c]
        full = tr = cl["triple"]
        if cl.get("tangent") or len(tr) != 3 or not tr[0] < tr[1] < tr[2]:
            full = tuple(sorted(set(tr) | set(cl.get("tangent", ()))))
        groups.setdefault(full, []).append(c)
    out = []
    for full, members in groups.items():
        # members of one site set: distinct vertices only if their boxes are disjoint
        parts: list[list[int]] = []
        for c in members:
            cl = clusters[c]
            for part in parts:
                ref = clusters[part[0]]
                reach = ref["h"] + cl["h"]
                if abs(ref["x"] - cl["x"]) <= reach and abs(ref["y"] - cl["y"]) <= reach:
                    part.append(c)
                    break
            else:
                parts.append([c])
        for part in parts:
            head = clusters[part[0]]
            order = contact_order(S, head["x"], head["y"], full) if len(full) > 3 else tuple(full)
            out.append((part, order))
    return out


def assemble_vertices(S: SiteArrays, clusters, usable, groups, n_old, problems, vertex_cls):
    """The diagram's vertices from the usable clusters (:func:`merge_cocircular`), and for each
    near-degenerate group of :func:`runtime.voronoi.near_degenerate.near_degenerate_clusters`
    (clusters ``n_old`` and after) its local edges: a pair consecutive at two of the group's
    vertices is an edge between them, a pair consecutive at one leaves the group there.

    Returns (vertices, cluster → vertex id, group → {pair: vertex id}, local edges
    [(pair, [va, vb])], vertex id → group); problems are appended."""
    vertices = []
    cluster_vid: dict = {}
    for members, order in merge_cocircular(S, clusters, usable):
        head = clusters[members[0]]
        if order is None:
            full = sorted(set(head["triple"]) | set(head.get("tangent", ())))
            problems.append(f"sites {', '.join(map(str, full))}: the vertex at ({head['x']:.6g}, {head['y']:.6g}) "
                            "touches them at points too close to order")
            continue
        vid = len(vertices)
        for c in members:
            cluster_vid[c] = vid
        r = float(head.get("radius") or 0.0) or float((head["rlo"] + head["rhi"]) / 2)
        vertices.append(vertex_cls(vid, tuple(order), float(head["x"]), float(head["y"]), r, True))
    group_out: dict = {}
    local_edges = []
    vgroup: dict = {}
    for g in groups:
        count: dict = {}
        for c in range(n_old, len(clusters)):
            if clusters[c].get("group") == g and c in cluster_vid:
                vid = cluster_vid[c]
                vgroup[vid] = g
                for pr in consecutive_pairs(vertices[vid].sites):
                    count.setdefault(pr, set()).add(vid)
        out = group_out.setdefault(g, {})
        for pr, vids in count.items():
            vids = sorted(vids)
            if len(vids) == 1:
                out[pr] = vids[0]
            elif len(vids) == 2:
                local_edges.append((pr, vids))
            else:
                problems.append(f"sites {pr[0]}, {pr[1]}: their bisector meets {len(vids)} vertices of one "
                                "near-degenerate cluster")
    return vertices, cluster_vid, group_out, local_edges, vgroup
