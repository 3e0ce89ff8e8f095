"""Checks of the sample walks of the segment construction against the geometry (thesis §1.2).

The construction (:mod:`runtime.segments.construction`) reads edges off walks through the
labelled sample triangulation.  Three kinds of walks are artefacts of the sampling, not of the
diagram: a walk between the two ends of one segment (:func:`segment_ends`), a walk through the
longest side of a flat sample triangle (:func:`long_side`), and an infinite edge whose far end
lies in a third site's region (:func:`far_ends`, which asks for finer samples).  The walks of a
round as arrays (:func:`walk_arrays`) and the check that every vertex has one edge per pair of
consecutive sites (:func:`degree_mismatches`) run on all walks and vertices at once.

Public API: :func:`segment_ends`, :func:`long_side`, :func:`far_ends`, :func:`walk_arrays`,
:func:`pair_keys`, :func:`degree_mismatches`, :data:`NONE`, :data:`TRI`, :data:`HULL`, :data:`BAD`, :data:`VERTEX`.
"""
from __future__ import annotations

import numpy as np

from .distance import site_distances
from .edges import edge_polylines
from .elementary import POINT, ElementarySites

__all__ = ["segment_ends", "long_side", "far_ends", "walk_arrays", "pair_keys", "degree_mismatches", "NONE", "TRI", "HULL", "BAD", "VERTEX"]

#: kinds of a walk's end in :func:`walk_arrays`: none (a closed chain), a 3-label triangle, the
#: hull, a walk that could not be closed, a vertex given directly
NONE, TRI, HULL, BAD, VERTEX = 0, 1, 2, 3, 4

#: far points times sites per block of distances in :func:`far_ends` (bounds its memory)
FAR_CHUNK = 2_000_000


def segment_ends(E: ElementarySites, pair) -> bool:
    """Both sites of ``pair`` are the two ends of one segment."""
    return (int(pair[0]), int(pair[1])) in E.segment_end_pairs


def long_side(tri, pair, start, end, tri_vid) -> bool:
    """The walk leaves a flat three-label triangle (collinear samples, circumcentre at infinity)
    through its longest side: the middle sample is nearer than the two outer ones to every point
    of their bisector, so that side bounds no cell of the samples at all."""
    for e in (start, end):
        if e is None or e[0] != "tri" or tri_vid.get(e[1]) != "inf":
            continue
        t = e[1]
        idx = tri.simp[t]
        Q = tri.P[idx]
        lengths = [float(np.hypot(*(Q[(k + 1) % 3] - Q[(k + 2) % 3]))) for k in range(3)]
        k = int(np.argmax(lengths))              # side k is opposite vertex k, the middle one
        if int(tri.lab[idx[k]]) not in pair:
            return True
    return False


def far_ends(E: ElementarySites, result, tolerance, lo, hi, caches) -> dict:
    """Infinite edges checked at their far points (floats): a third site nearer there means the
    samples drew the hull wrong (a hull tangent a hair from an arc's end, an end ray turned by a
    coarse sample); the edge's sites are refined, a point and a curve ending at it graded, and
    the check is named among the problems until a round passes it.  Returns {site: refine}."""
    vertices, walks, problems = result
    inf_walks = [w for w in walks if None in w[1]]
    if not inf_walks:
        return {}
    edges = edge_polylines(E, vertices, inf_walks, tolerance, lo, hi)
    if not edges:
        return {}
    Q = np.array([e.polyline[-1] if e.ends[1] is None else e.polyline[0] for e in edges])
    n = len(E)
    out: dict = {}
    graded = caches.setdefault("graded", {})
    rows = max(1, FAR_CHUNK // max(n, 1))           # distances to all sites, a few far points at a time
    D = iter(())
    for m, e in enumerate(edges):
        if m % rows == 0:
            block = Q[m:m + rows]
            D = iter(site_distances(E, np.tile(np.arange(n), len(block)),
                                    np.repeat(block, n, axis=0)).reshape(len(block), n))
        row = next(D)
        i, j = e.sites
        own = max(row[i], row[j])
        row = row.copy()
        row[[i, j]] = np.inf
        k = int(np.argmin(row))
        if row[k] < own - 1e-9 * (1.0 + own):
            problems.append(f"sites {i}, {j}: the infinite edge between them reaches site {k}'s region")
            for t in (i, j, k):
                for s_ in ([t] if E.kind[t] != POINT else E.incident[t]):
                    out[int(s_)] = np.inf
            for p_, t in ((i, j), (j, i)):
                if E.kind[p_] == POINT and E.is_endpoint(p_, t):
                    graded[(int(t), int(p_))] = graded.get((int(t), int(p_)), 0) + 1
    return out


def walk_arrays(raw, base: int, direct=None):
    """The walks ``raw`` of :meth:`runtime.voronoi.sample_delaunay.SampleTriangulation.walks` as
    arrays: pair keys a·base + b (a < b), start and end kinds (:data:`NONE`, :data:`TRI`,
    :data:`HULL`, :data:`BAD`, or :data:`VERTEX` for an end ("tri", key) with ``key`` in the dict
    ``direct``: key -> vertex) and their triangles or vertices (−1 for none), chain lengths."""
    W = len(raw)
    codes = {None: NONE, "tri": TRI, "hull": HULL, "bad": BAD}
    out = []
    for j in (1, 3):
        ends = [w[j] for w in raw]
        kind = np.array([codes[None if e is None else e[0]] for e in ends], np.int64).reshape(W)
        where = [-1 if e is None else e[1] for e in ends]
        if direct:              # ends given as vertices: keys that are not triangle indices
            for i, e in enumerate(ends):
                if e is not None and e[0] == "tri" and not isinstance(e[1], (int, np.integer)):
                    kind[i], where[i] = VERTEX, direct[e[1]]
        out += [kind, np.array(where, np.int64).reshape(W)]
    pa = np.array([w[0][0] for w in raw], np.int64).reshape(W)
    pb = np.array([w[0][1] for w in raw], np.int64).reshape(W)
    length = np.array([len(w[2]) for w in raw], np.int64).reshape(W)
    return (np.minimum(pa, pb) * base + np.maximum(pa, pb), *out, length)


def pair_keys(site_tuples, base: int, memo: dict):
    """(lens, keys): per vertex (its cyclic site tuple) the number of its cyclically consecutive
    site pairs and their sorted pair keys min·base + max, concatenated; vertices of three sites on
    arrays at once, the others through ``memo`` (site tuple -> keys, kept across rounds)."""
    n = len(site_tuples)
    lens = np.fromiter((len(t) for t in site_tuples), np.int64, n)
    start = np.cumsum(lens) - lens
    keys = np.empty(int(lens.sum()), np.int64)
    three = np.nonzero(lens == 3)[0]
    if len(three):
        S = np.array([site_tuples[i] for i in three.tolist()], np.int64).reshape(-1, 3)
        T = np.roll(S, -1, axis=1)
        K = np.sort(np.minimum(S, T) * base + np.maximum(S, T), axis=1)
        keys[start[three][:, None] + np.arange(3)] = K
    for i in np.nonzero(lens != 3)[0].tolist():
        sites = tuple(site_tuples[i])
        w = memo.get(sites)
        if w is None:
            w = memo[sites] = tuple(sorted(min(a, b) * base + max(a, b) for a, b in zip(sites, sites[1:] + sites[:1])))
        keys[start[i]:start[i] + lens[i]] = w
    return lens, keys


def degree_mismatches(want, have_v, have_k, n_vertices: int) -> np.ndarray:
    """The vertices whose edges are not one per pair of cyclically consecutive sites: ``want``
    lists per vertex the sorted pair keys of its consecutive sites (or is the pair (lens, keys) of
    :func:`pair_keys`), (``have_v``, ``have_k``) the ends of the walks at vertices with their pair
    keys.  Compared as sorted multisets."""
    if isinstance(want, tuple) and len(want) == 2 and isinstance(want[0], np.ndarray):
        lens, wk = want
    else:
        lens = np.array([len(w) for w in want], np.int64).reshape(n_vertices)
        wk = np.array([k for w in want for k in w], np.int64).reshape(int(lens.sum()))
    wv = np.repeat(np.arange(n_vertices), lens)
    count = np.bincount(have_v, minlength=n_vertices)
    bad = count != lens
    o = np.lexsort((have_k, have_v))
    hv, hk = have_v[o], have_k[o]
    h_ok, w_ok = ~bad[hv], ~bad[wv]
    diff = hk[h_ok] != wk[w_ok]                  # the same counts: aligned vertex by vertex
    bad[hv[h_ok][diff]] = True
    return np.nonzero(bad)[0]
