"""Emptiness of the circle of a proved vertex: no site enters it (thesis §5.2, the vertex condition).

Rigorous distance lower bounds to every site whose bounding disc can reach the circle (k-d tree:
the nearest centres first, all sites in bounded batches only for a wide disc with no conflict
among them);
undecided circle/point cases go to the exact conflict test of thesis §3.1.3
(:func:`runtime.predicates.circles.decide_conflict`).

Public API: :func:`prove_empty`.
"""
from __future__ import annotations

import math

import numpy as np

from ..predicates.circles import as_circle, decide_conflict
from ..predicates.symmetry import equidistant_by_symmetry, mirror_orbits, rational_candidates
from ..result import InvalidConicError, LocatorError
from .apollonius_vertices import exact_vertex
from .site_arrays import SiteArrays

__all__ = ["prove_empty", "PAIRS_PER_BATCH"]

#: (vertex, site) pairs listed at a time for the wide discs of :func:`prove_empty`
PAIRS_PER_BATCH = 1 << 20


def prove_empty(S: SiteArrays, clusters, stats):
    """Prove that no site enters the empty circle of each proved vertex; returns, per cluster,
    True (empty, proved), False (a site enters: not a Voronoi vertex) or None (undecided), and the
    conflicting site.

    The sites that may enter are first looked up among the nearest centres
    (:meth:`runtime.voronoi.site_arrays.SiteArrays.nearest_sites`); a circle whose disc meets
    more sites than that (a candidate far outside the sites, whose circle may hold all of them)
    is not empty when one of those nearest sites provably enters, and otherwise every site that
    may enter is listed, :data:`PAIRS_PER_BATCH` (vertex, site) pairs at a time."""
    idx = [c for c, cl in enumerate(clusters) if cl["ok"]]
    res = [None] * len(clusters)
    culprit = [None] * len(clusters)
    if not idx:
        return res, culprit
    M = np.array([[clusters[c]["x"], clusters[c]["y"]] for c in idx])
    H = np.array([clusters[c]["h"] for c in idx]) * math.sqrt(2)
    RLO = np.array([clusters[c]["rlo"] for c in idx])
    RHI = np.array([clusters[c]["rhi"] for c in idx])
    TT = np.array([clusters[c]["triple"] for c in idx])
    bad = np.zeros(len(idx), bool)
    und = np.zeros(len(idx), bool)
    first_bad: dict = {}
    und_pairs: dict = {}

    def classify(rows, cols):
        """Distance bounds of the (vertex, site) pairs: conflicts and undecided pairs recorded."""
        keep = (cols != TT[rows, 0]) & (cols != TT[rows, 1]) & (cols != TT[rows, 2])
        rows, cols = rows[keep], cols[keep]
        lo, hi = S.dist_bounds(M[rows], cols)
        lo, hi = lo - H[rows], hi + H[rows]
        safe = lo > RHI[rows]
        conflict = hi < RLO[rows]
        np.logical_or.at(bad, rows[conflict], True)
        undecided = ~safe & ~conflict
        np.logical_or.at(und, rows[undecided], True)
        depth = (RLO[rows] - hi)[conflict]
        for r, c, dp in zip(rows[conflict].tolist(), cols[conflict].tolist(), depth.tolist()):
            if r not in first_bad or dp < clusters[idx[r]].get("intrusion", np.inf):
                first_bad[r] = c
                clusters[idx[r]]["intrusion"] = dp
        for r, c in zip(rows[undecided].tolist(), cols[undecided].tolist()):
            und_pairs.setdefault(r, []).append(c)
        stats["emptiness_pairs"] = stats.get("emptiness_pairs", 0) + int(len(rows))

    reach = RHI + H
    rows, cols, complete = S.nearest_sites(M, reach)
    classify(rows, cols)
    del rows, cols
    # wide discs with no conflict among the nearest sites: all sites that may enter, in batches
    wide = np.nonzero(~complete & ~bad)[0]
    if len(wide):
        stats["wide_emptiness_queries"] = stats.get("wide_emptiness_queries", 0) + int(len(wide))
        und[wide] = False                    # listed again in full below
        for r in wide.tolist():
            und_pairs.pop(r, None)
        step = max(1, PAIRS_PER_BATCH // max(S.n, 1))
        for b0 in range(0, len(wide), step):
            part = wide[b0:b0 + step]
            rows, cols = S.near_sites(M[part], reach[part])
            classify(part[rows], cols)
            del rows, cols
    for a, c in enumerate(idx):
        if bad[a]:
            res[c], culprit[c] = False, first_bad[a]
            continue
        if not und[a]:
            res[c] = True
            continue
        # undecided: the exact circle route when everything is a circle
        cl = clusters[c]
        decided = None
        if S.all_circles:
            decided = True
            try:
                if cl["exact"] is None:
                    stats["full_triple_solves"] = stats.get("full_triple_solves", 0) + 1
                tv, v = cl["exact"] or exact_vertex(S, cl)
                cl["exact"] = (tv, v)
                for k in und_pairs[a]:
                    stats["exact_conflict_calls"] = stats.get("exact_conflict_calls", 0) + 1
                    dec = decide_conflict(tv, v, as_circle(S.sites[k]))
                    if dec.in_conflict:
                        decided, culprit[c] = False, k
                        break
                    if dec.tangent:      # site k touches the empty circle: a degenerate vertex
                        cl.setdefault("tangent", []).append(k)
            except (LocatorError, InvalidConicError, ValueError):
                decided = None
        elif cl.get("box") is not None or cl.get("h"):
            decided = _symmetric_tangency(S, cl, und_pairs[a], stats)
        if decided is None and culprit[c] is None:
            culprit[c] = und_pairs[a][0]
        res[c] = decided
    return res, culprit


def _symmetric_tangency(S: SiteArrays, cl, undecided, stats):
    """Sites the floats cannot separate from the circle of a conic vertex: tangent when a rational
    point p at the vertex is fixed by isometries that join the triple and these sites
    (:func:`runtime.predicates.symmetry.equidistant_by_symmetry`: then all are exactly at one
    distance from p, and p, equidistant from the triple in the vertex's proof box, is the vertex).
    Returns True (the vertex moved to p, the sites recorded as tangent) or None."""
    x, y = cl["x"], cl["y"]
    reach = 4 * cl.get("h", 0.0) + 1e-9 * (abs(x) + abs(y) + float(cl.get("rhi", 0.0)) + 1.0)
    K = [S.sites[t] for t in (*cl["triple"], *undecided)]
    for p in rational_candidates(x, y, reach):
        if equidistant_by_symmetry(K, p):
            stats["symmetric_vertices"] = stats.get("symmetric_vertices", 0) + 1
            cl.update(x=float(p[0]), y=float(p[1]), symmetric=p)
            cl.setdefault("tangent", []).extend(int(k) for k in undecided)
            return True
    # a mirror of the sites in two orbits through the vertex: on it d_a = d_a', d_b = d_b', and the
    # vertex (d_a = d_b) has them all at one distance (the verifier proves it on the line)
    found = mirror_orbits(K)
    if found is not None and len(found[1]) == 2:
        (n, k), _ = found
        off = abs(float(n[0]) * x + float(n[1]) * y - float(k)) / math.hypot(float(n[0]), float(n[1]))
        if off <= reach:
            stats["mirror_vertices"] = stats.get("mirror_vertices", 0) + 1
            cl.setdefault("tangent", []).extend(int(t) for t in undecided)
            return True
    return None
