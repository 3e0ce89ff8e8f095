"""The perpendiculars at a segment's two ends: parallel rays that meet only in the samples.

The Voronoi edges between an open segment s and its end points p and q (outside a convex corner)
are the two rays perpendicular to s at p and at q: parallel, both to infinity (thesis §2.2; Lee,
*Medial axis transformation of a planar shape*, IEEE PAMI 1982).  No Voronoi vertex has the sites
p, q and s (a circle through both ends of s has s inside).  Yet far out the sample triangulation
(:mod:`runtime.segments.sampling`) may close the two rays' chains of triangles with one triangle
labelled p, q, s, whose circumcentre is about h / δ away (h the sample spacing, δ the rounding
of the samples' directions): 10¹³ times the scene for a circle's buffer of 32 sides.  Such a
triangle is an end at infinity for the walks reaching it, like the ghost ring of a flat input.

"Far" is measured against the whole scene, not against s: inside the scene the strip of a short
segment is closed by the regions of other sites (vertices s, p, x and s, q, y), and a triangle
p, q, s there only says that the samples do not resolve the strip yet, and the construction must
refine rather than end the walks.

The same holds for the normal line at a smooth joint of two elliptic pieces (a vertex of the
ellipse), an edge that may go to infinity beside a third site: a triangle of the two pieces and
any third site farther than :data:`FAR` scene sizes is an end at infinity (the joint's samples are
graded, :func:`runtime.segments.sampling.corner_grading`).

Public API: :func:`parallel_ray_triangles`.
"""
from __future__ import annotations

import numpy as np

from .elementary import ELLIPSE, SEGMENT, ElementarySites

__all__ = ["parallel_ray_triangles", "FAR"]

#: a triangle of s and its two ends whose circumcentre is farther than this many scene sizes
#: from the scene's centre (and this many lengths of s from s)
FAR = 1e3


def parallel_ray_triangles(E: ElementarySites, T3, seeds) -> np.ndarray:
    """For each triangle (its sorted labels in ``T3``, circumcentre in ``seeds``): True when its
    labels are a segment s and both ends of s and its circumcentre lies farther than
    :data:`FAR` scene sizes (the largest side of the sites' bounding box) from the box's centre
    and :data:`FAR` lengths of s from s's midpoint."""
    T3 = np.asarray(T3)
    out = np.zeros(len(T3), dtype=bool)
    if not len(T3):
        return out
    s = T3[:, 2]
    cand = (s >= E.n_points) & (s < len(E)) & (T3[:, 1] < E.n_points)
    lo = np.minimum(E.A.min(axis=0), E.B.min(axis=0))
    hi = np.maximum(E.A.max(axis=0), E.B.max(axis=0))
    centre, scene = (lo + hi) / 2, float(np.max(hi - lo))
    if E.joints and (E.kind == ELLIPSE).any():
        far = np.hypot(*(np.asarray(seeds, float) - centre).T) > FAR * scene
        for r in np.nonzero(far & (T3 < len(E)).all(axis=1))[0].tolist():
            a, b, c = (int(v) for v in T3[r])
            pairs = ((a, b), (a, c), (b, c))
            if any(E.kind[i] == ELLIPSE and E.kind[j] == ELLIPSE
                   and {int(v) for v in E.ends[i] if v < -1} & {int(v) for v in E.ends[j] if v < -1} for i, j in pairs):
                out[r] = True
    rows = np.nonzero(cand)[0]
    if not len(rows):
        return out
    # (on arrays: the same float expressions row by row)
    a, b, k = T3[rows, 0], T3[rows, 1], T3[rows, 2]
    e0, e1 = E.ends[k, 0], E.ends[k, 1]
    rows = rows[(E.kind[k] == SEGMENT) & (((a == e0) & (b == e1)) | ((a == e1) & (b == e0)))]
    if not len(rows):
        return out
    k = T3[rows, 2]
    length = np.hypot(*(E.B[k] - E.A[k]).T)
    mid = (E.A[k] + E.B[k]) / 2
    c = np.asarray(seeds, float)[rows]
    out[rows] = (np.hypot(*(c - mid).T) > FAR * length) & (np.hypot(*(c - centre).T) > FAR * scene)
    return out
