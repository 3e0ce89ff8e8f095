"""Labelled samples of points, segments and arcs and their Delaunay triangulation (thesis §1.2).

The construction (:mod:`runtime.segments.construction`) reads the combinatorics of the diagram
off the Delaunay triangulation of samples of the sites: every point site is one sample, a curve
of length L gets ⌈L / spacing⌉ samples at parameters (k + ½)/n (arcs by angle).  The initial
spacing of a curve is its gap to the nearest non-adjacent site divided by
:data:`SPACING_PER_GAP` (at most a quarter of its length); refinement divides it further.

Public API: :func:`initial_spacing`, :func:`samples`, :func:`curve_lengths`, :func:`triangulation`,
:func:`flat`, :func:`nearest_point`, :data:`SPACING_PER_GAP`.
"""
from __future__ import annotations

import numpy as np
from scipy.spatial import Delaunay, QhullError, cKDTree

from ..voronoi.sample_delaunay import SampleTriangulation
from .bisectors import arc_range
from .distance import in_arc
from .elementary import ARC, POINT, ElementarySites

__all__ = ["initial_spacing", "samples", "curve_lengths", "triangulation", "flat", "nearest_point",
           "SPACING_PER_GAP"]

#: initial sample spacing of a curve: its gap to the nearest non-adjacent site divided by this
SPACING_PER_GAP = 4.0


def initial_spacing(E: ElementarySites) -> np.ndarray:
    """Per site: the sample spacing along a segment (∞ for a point): half its gap to the nearest
    non-adjacent site, at most a quarter of its length."""
    n = len(E)
    L = curve_lengths(E)
    sp = np.where(E.kind == POINT, np.inf, L / 4)
    P, lab = samples(E, sp)
    if len(P) < 3:
        return sp
    tree = cKDTree(P)
    k = min(len(P), 12)
    dist, idx = tree.query(P, k=k)
    gap = np.full(n, np.inf)
    for c in range(1, k):
        other = lab[idx[:, c]]
        ok = (other != lab) & ~_adjacent(E, lab, other)
        np.minimum.at(gap, lab[ok], dist[ok, c])
    finite = np.isfinite(gap)
    gap[~finite] = np.median(gap[finite]) if finite.any() else 1.0
    return np.where(E.kind == POINT, np.inf, np.minimum(L / 4, gap / SPACING_PER_GAP))


def curve_lengths(E: ElementarySites) -> np.ndarray:
    """Lengths of the curves (0 for points): chords of segments, ρ·span of arcs."""
    L = np.hypot(*(E.B - E.A).T)
    for s in np.nonzero(E.kind == ARC)[0].tolist():
        L[s] = E.rho[s] * arc_range(E, s)[1]
    return L


def _adjacent(E: ElementarySites, a, b):
    """Elementwise: site a is an end of curve b or vice versa, or they share an end."""
    ea, eb = E.ends[a], E.ends[b]
    pa = np.where(E.kind[a] == POINT, a, -5)
    pb = np.where(E.kind[b] == POINT, b, -7)
    share = ((ea[:, :, None] == eb[:, None, :]) & (ea[:, :, None] != -1)).any(axis=(1, 2))
    return share | (ea == pb[:, None]).any(axis=1) | (eb == pa[:, None]).any(axis=1)


def samples(E: ElementarySites, spacing, extra=None):
    """Every point site, and n = ⌈L / spacing⌉ points at parameters (k + ½)/n along each curve,
    plus ``extra`` points {curve: [(x, y), ...]} (points of the curves added where a curve was
    found inside a candidate's circle)."""
    pts = [E.A[:E.n_points]]
    labs = [np.arange(E.n_points)]
    seg = np.arange(E.n_points, len(E))
    if len(seg):
        L = curve_lengths(E)[seg]
        cnt = np.maximum(1, np.ceil(L / spacing[seg]).astype(np.int64))
        owner = np.repeat(seg, cnt)
        start = np.repeat(np.cumsum(cnt) - cnt, cnt)
        k = np.arange(int(cnt.sum())) - start
        t = (k + 0.5) / np.repeat(cnt, cnt)
        Q = E.A[owner] + t[:, None] * (E.B[owner] - E.A[owner])
        arc = E.kind[owner] == ARC
        if arc.any():
            ranges = {s_: arc_range(E, s_) for s_ in np.unique(owner[arc]).tolist()}
            al = np.array([ranges[s_][0] for s_ in owner[arc].tolist()])
            be = np.array([ranges[s_][1] for s_ in owner[arc].tolist()])
            th = al + t[arc] * be
            # samples of one circle are co-circular: qhull's triangles inside the circle would all
            # share its centre as circumcentre.  A radial jitter of 10⁻⁹ ρ (deterministic) breaks
            # the tie; the samples only guide the combinatorics, which are proved afterwards.
            jitter = 1 + 1e-9 * (np.arange(len(th)) % 7 - 3)
            Q[arc] = E.C[owner[arc]] + (E.rho[owner[arc]] * jitter)[:, None] * np.column_stack([np.cos(th), np.sin(th)])
        pts.append(Q)
        labs.append(owner)
    for t, P in (extra or {}).items():
        pts.append(np.asarray(P, float).reshape(-1, 2))
        labs.append(np.full(len(P), t))
    P, lab = np.concatenate(pts), np.concatenate(labs)
    if extra:
        # an added point may repeat a sample; qhull would drop it as coplanar and the
        # triangulation would fall back to joggling
        _, keep = np.unique(P, axis=0, return_index=True)
        keep.sort()
        P, lab = P[keep], lab[keep]
    return P, lab


def nearest_point(E: ElementarySites, t: int, q) -> tuple[float, float]:
    """The point of curve t nearest to q (floats; an end when the foot falls outside)."""
    q = np.asarray(q, float)
    if E.kind[t] == ARC:
        w = q - E.C[t]
        u = w / max(np.hypot(*w), 1e-300)
        f = E.C[t] + E.rho[t] * u
        ends = [E.A[t], E.B[t]]
        if in_arc(E.C[[t]], E.A[[t]], E.B[[t]], w[None, :])[0]:
            return float(f[0]), float(f[1])
        e = min(ends, key=lambda P: np.hypot(*(P - q)))
        return float(e[0]), float(e[1])
    a, b = E.A[t], E.B[t]
    d = b - a
    # strictly inside the segment: an end is a point site's sample already
    f = a + np.clip(np.dot(q - a, d) / np.dot(d, d), 1e-6, 1 - 1e-6) * d
    return float(f[0]), float(f[1])


def triangulation(P, lab) -> SampleTriangulation:
    """qhull without joggling whenever it keeps every sample (segment samples are collinear in
    runs, which qhull's merged facets handle; joggling would flip the slivers on the hull whose
    circumcentres are the far vertices of nearly collinear hull sites), else joggled."""
    c = (P.min(axis=0) + P.max(axis=0)) / 2
    try:
        d = Delaunay(P - c, qhull_options="Qbb Qc Qz Q12")
        if not len(d.coplanar):
            return SampleTriangulation(P, lab, d.simplices, d.neighbors)
    except QhullError:
        pass
    return SampleTriangulation(P, lab)


def flat(P) -> bool:
    """Fewer than three samples, or all of them on one line (relative 1e-12)."""
    if len(P) < 3:
        return True
    Q = P - P[0]
    s = np.linalg.svd(Q, compute_uv=False)
    return bool(s[1] <= 1e-12 * max(s[0], 1e-300))
