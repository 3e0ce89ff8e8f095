"""The perpendiculars at a segment's two ends: parallel rays that meet only in the samples.

The Voronoi edges between an open segment s and its end points p and q (outside a convex corner)
are the two rays perpendicular to s at p and at q: parallel, both to infinity (thesis §2.2; Lee,
*Medial axis transformation of a planar shape*, IEEE PAMI 1982).  No Voronoi vertex has the sites
p, q and s (a circle through both ends of s has s inside).  Yet far out the sample triangulation
(:mod:`runtime.segments.sampling`) may close the two rays' chains of triangles with one triangle
labelled p, q, s, whose circumcentre is about h / δ away (h the sample spacing, δ the rounding
of the samples' directions): 10¹³ times the scene for a circle's buffer of 32 sides.  Such a
triangle is an end at infinity for the walks reaching it, like the ghost ring of a flat input.

Public API: :func:`parallel_ray_triangles`.
"""
from __future__ import annotations

import numpy as np

from .elementary import SEGMENT, ElementarySites

__all__ = ["parallel_ray_triangles", "FAR"]

#: a triangle of s and its two ends whose circumcentre is farther than this many lengths of s
FAR = 1e3


def parallel_ray_triangles(E: ElementarySites, T3, seeds) -> np.ndarray:
    """For each triangle (its sorted labels in ``T3``, circumcentre in ``seeds``): True when its
    labels are a segment s and both ends of s and its circumcentre lies farther than
    :data:`FAR` lengths of s from s's midpoint."""
    T3 = np.asarray(T3)
    out = np.zeros(len(T3), dtype=bool)
    if not len(T3):
        return out
    s = T3[:, 2]
    cand = (s >= E.n_points) & (s < len(E)) & (T3[:, 1] < E.n_points)
    for r in np.nonzero(cand)[0].tolist():
        a, b, k = (int(v) for v in T3[r])
        if E.kind[k] != SEGMENT or {a, b} != {int(E.ends[k, 0]), int(E.ends[k, 1])}:
            continue
        length = float(np.hypot(*(E.B[k] - E.A[k])))
        mid = (E.A[k] + E.B[k]) / 2
        out[r] = bool(np.hypot(*(np.asarray(seeds[r], float) - mid)) > FAR * length)
    return out
