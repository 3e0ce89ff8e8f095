"""Checks of the sample walks of the segment construction against the geometry (thesis §1.2).

The construction (:mod:`runtime.segments.construction`) reads edges off walks through the
labelled sample triangulation.  Three kinds of walks are artefacts of the sampling, not of the
diagram: a walk between the two ends of one segment (:func:`segment_ends`), a walk through the
longest side of a flat sample triangle (:func:`long_side`), and an infinite edge whose far end
lies in a third site's region (:func:`far_ends`, which asks for finer samples).

Public API: :func:`segment_ends`, :func:`long_side`, :func:`far_ends`.
"""
from __future__ import annotations

import numpy as np

from .distance import site_distances
from .edges import edge_polylines
from .elementary import POINT, ElementarySites

__all__ = ["segment_ends", "long_side", "far_ends"]

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
