"""Nearly co-circular circles and points: the local diagram decided exactly (thesis §3.1.3).

Floats that are only *nearly* co-circular (a ring of circles placed with ``cos``/``sin``, a circle
moved by 10⁻⁸ off a common tangent circle) have Voronoi vertices 10⁻¹⁵–10⁻⁸ apart, joined by
edges that short.  Sampling cannot see them: refining the samples near such a vertex feeds the
triangulation ever more points and never separates the candidates.  Instead, when a proved
candidate vertex fails its emptiness test by a relative margin below :data:`NEAR`, the sites
that come that close to its circle form a *cluster* K, and the Voronoi vertices of K near the
candidate are found exactly: for every triple of K its vertices (at most two, thesis §3.1.2) in
the quadratic tower of :func:`runtime.predicates.circles.voronoi_vertices_circles`, each kept
when no other site of K enters its circle (:func:`runtime.predicates.circles.decide_conflict`;
sites that touch it exactly make a vertex of degree > 3).  This is the local step of the
incremental algorithms that decide every predicate exactly (Karavelas & Yvinec, *The Voronoi
diagram of planar convex objects*, ESA 2003; CGAL's ``Apollonius_graph_2``), applied only where
the floats cannot decide: |K| is small, so trying every triple (O(|K|⁴) exact tests) is cheap.

Nothing here is trusted: the vertices found are proved empty of all sites by the construction's
emptiness step, and the whole diagram by the independent verifier.

Public API: :func:`near_degenerate_clusters`, :data:`NEAR`, :data:`MAX_CLUSTER`.
"""
from __future__ import annotations

import math
from itertools import combinations

import numpy as np
from scipy.cluster.hierarchy import DisjointSet

from ..predicates.circles import decide_conflict, voronoi_vertices_circles
from ..result import InvalidConicError, LocatorError
from .site_arrays import SiteArrays

__all__ = ["near_degenerate_clusters", "NEAR", "MAX_CLUSTER"]

#: a candidate whose circle a site enters (or nearly touches) by less than this fraction of its
#: radius is resolved exactly instead of by finer samples
NEAR = 1e-7
#: clusters with more sites are left to the refinement (and reported if they stay unproved)
MAX_CLUSTER = 24


def _sites_near(S: SiteArrays, x, y, r):
    """Sites whose float distance to (x, y) is within r·(1 + NEAR) (plus rounding)."""
    rows, cols = S.near_sites(np.array([[x, y]]), np.array([r * (1 + 2 * NEAR) + 1e-300]))
    if not len(cols):
        return set()
    lo, _ = S.dist_bounds(np.repeat(np.array([[x, y]]), len(cols), axis=0), cols)
    return {int(k) for k, d in zip(cols.tolist(), lo.tolist()) if d <= r * (1 + NEAR) + 1e-300}


def near_degenerate_clusters(S: SiteArrays, clusters, empty, stats):
    """Resolve the candidate vertices that a site enters or nearly touches by a relative margin
    below :data:`NEAR`.  Returns (new clusters, groups): each new cluster is a vertex of a cluster
    K found exactly (keys as in :func:`runtime.voronoi.apollonius_vertices.apollonius_vertices`,
    ``exact`` set, ``tangent``: sites of K touching its circle, ``group``: its group); ``groups``
    maps a group id to the set of old cluster ids it replaces."""
    bad = []
    for c, cl in enumerate(clusters):
        if not cl["ok"] or empty[c] is True or not np.isfinite(cl["x"]):
            continue
        r = 0.5 * (cl["rlo"] + cl["rhi"])
        if r <= 0:
            continue
        near = _sites_near(S, cl["x"], cl["y"], r) | set(cl["triple"])
        if len(near) > 3:
            bad.append((c, r, near))
    if not bad:
        return [], {}
    # groups: candidates within NEAR·r of each other sharing sites (disjoint sets)
    joined = DisjointSet(range(len(bad)))
    for a in range(len(bad)):
        ca, ra, na = bad[a]
        for b in range(a + 1, len(bad)):
            cb, rb, nb = bad[b]
            reach = 10 * NEAR * (ra + rb)
            if (len(na & nb) >= 3 and abs(clusters[ca]["x"] - clusters[cb]["x"]) <= reach
                    and abs(clusters[ca]["y"] - clusters[cb]["y"]) <= reach):
                joined.merge(a, b)
    members = {min(sub): sorted(sub) for sub in joined.subsets()}
    new, groups = [], {}
    for gid, (_, idx) in enumerate(sorted(members.items())):
        K = sorted(set().union(*[bad[a][2] for a in idx]))
        if len(K) > MAX_CLUSTER:
            continue
        cx = float(np.mean([clusters[bad[a][0]]["x"] for a in idx]))
        cy = float(np.mean([clusters[bad[a][0]]["y"] for a in idx]))
        r = max(bad[a][1] for a in idx)
        found = _local_vertices(S, K, cx, cy, r, gid, stats)
        if found:
            new.extend(found)
            groups[gid] = {bad[a][0] for a in idx}
    stats["near_degenerate_clusters"] = stats.get("near_degenerate_clusters", 0) + len(groups)
    return new, groups


def _local_vertices(S: SiteArrays, K, cx, cy, r, gid, stats):
    """Every Voronoi vertex of the sites K within 10·NEAR·r of (cx, cy), exactly."""
    out = []
    circles = {k: S.geoms[k].exact for k in K}
    reach = 10 * NEAR * r + 1e-12 * (abs(cx) + abs(cy) + r)
    for tr in combinations(K, 3):
        try:
            tv = voronoi_vertices_circles(*[circles[k] for k in tr])
        except (LocatorError, InvalidConicError):
            continue
        stats["exact_vertex_calls"] = stats.get("exact_vertex_calls", 0) + 1
        for w in tv.vertices:
            if math.hypot(w.x - cx, w.y - cy) > reach:
                continue
            tangent, inside = [], False
            for m in K:
                if m in tr:
                    continue
                dec = decide_conflict(tv, w, circles[m])
                if dec.in_conflict:
                    inside = True
                    break
                if dec.tangent:
                    tangent.append(m)
            if inside:
                continue
            eps = 4e-16 * (abs(w.x) + abs(w.y) + w.radius) + 1e-300
            out.append({"triple": tuple(tr), "first": None, "x": w.x, "y": w.y, "ok": True,
                        "rlo": w.radius - eps, "rhi": w.radius + eps, "h": eps, "exact": (tv, w),
                        "radius": w.radius, "tangent": tangent, "group": gid})
    return out
