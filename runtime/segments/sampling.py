"""Labelled samples of points, segments and arcs and their Delaunay triangulation (thesis §1.2).

The construction (:mod:`runtime.segments.construction`) reads the combinatorics of the diagram
off the Delaunay triangulation of samples of the sites: every point site is one sample, a curve
of length L gets ⌈L / spacing⌉ samples at parameters (k + ½)/n (arcs by angle).  The initial
spacing of a curve is its gap to the nearest non-adjacent site divided by
:data:`SPACING_PER_GAP` (at most a quarter of its length); refinement divides it further.

Public API: :func:`initial_spacing`, :func:`samples`, :func:`curve_lengths`, :func:`triangulation`,
:func:`retriangulation`, :func:`exact_matches`,
:func:`flat`, :func:`nearest_point`, :func:`corner_grading`, :func:`end_points`, :data:`SPACING_PER_GAP`.
"""
from __future__ import annotations

import numpy as np
from scipy.spatial import Delaunay, QhullError, cKDTree

from ..voronoi.sample_delaunay import SampleTriangulation
from .bisectors import arc_range
from .distance import in_arc
from .elementary import ARC, ELLIPSE, POINT, ElementarySites
from .ellipse_pieces import piece_at_lengths, piece_feet, piece_lengths, piece_points, piece_tangent

__all__ = ["initial_spacing", "samples", "curve_lengths", "triangulation", "insert_samples", "retriangulation", "exact_matches", "flat", "nearest_point", "corner_grading", "end_points", "GRADING_FLOOR",
           "SPACING_PER_GAP"]

#: graded samples stay this far (relative to the coordinates) from a curve's end
GRADING_FLOOR = 1e-6
#: initial sample spacing of a curve: its gap to the nearest non-adjacent site divided by this
SPACING_PER_GAP = 4.0


def initial_spacing(E: ElementarySites) -> np.ndarray:
    """Per site: the sample spacing along a segment (∞ for a point): half its gap to the nearest
    non-adjacent site, at most a quarter of its length."""
    n = len(E)
    L = curve_lengths(E)
    sp = np.where(E.kind == POINT, np.inf, L / 4)
    P, lab = samples(E, sp, graded=False)
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
    for s in np.nonzero(E.kind == ELLIPSE)[0].tolist():
        L[s] = piece_lengths(E.ellipse[s], 256)[0][-1]
    return L


def _adjacent(E: ElementarySites, a, b):
    """Elementwise: site a is an end of curve b or vice versa, or they share an end."""
    ea, eb = E.ends[a], E.ends[b]
    pa = np.where(E.kind[a] == POINT, a, -5)
    pb = np.where(E.kind[b] == POINT, b, -7)
    share = ((ea[:, :, None] == eb[:, None, :]) & (ea[:, :, None] != -1)).any(axis=(1, 2))
    return share | (ea == pb[:, None]).any(axis=1) | (eb == pa[:, None]).any(axis=1)


def samples(E: ElementarySites, spacing, extra=None, graded: bool = True, ends=()):
    """Every point site, and n = ⌈L / spacing⌉ points at parameters (k + ½)/n along each curve,
    plus ``extra`` points {curve: [(x, y), ...]} (points of the curves added where a curve was
    found inside a candidate's circle) and, with ``graded``, the samples of :func:`corner_grading`
    (``ends``: {(curve, point site): level} graded further)."""
    pts = [E.A[:E.n_points]]
    labs = [np.arange(E.n_points)]
    grade, graded = graded, False
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
        ell = E.kind[owner] == ELLIPSE
        if ell.any():
            for s_ in np.unique(owner[ell]).tolist():
                at = np.nonzero(owner == s_)[0]
                Q[at] = piece_at_lengths(E.ellipse[s_], t[at])
        pts.append(Q)
        labs.append(owner)
        G, glab = corner_grading(E, spacing, ends) if grade else (np.empty((0, 2)), None)
        if len(G):
            graded = True
            pts.append(G)
            labs.append(glab)
    for t, P in (extra or {}).items():
        pts.append(np.asarray(P, float).reshape(-1, 2))
        labs.append(np.full(len(P), t))
    P, lab = np.concatenate(pts), np.concatenate(labs)
    if extra or graded:
        # an added point may repeat a sample; qhull would drop it as coplanar and the
        # triangulation would fall back to joggling
        _, keep = np.unique(P, axis=0, return_index=True)
        keep.sort()
        P, lab = P[keep], lab[keep]
    return P, lab


def corner_grading(E: ElementarySites, spacing, ends=()):
    """Samples graded towards curve ends: (points, labels).

    At a corner p where curves a and b leave at an angle π − δ, the samples nearest to p at
    distance σ along a and b and p itself have their circumcentre at σ / (2 sin(δ/2)) from p, on
    the side where the true bisector of a and b starts.  Up to there the sample triangulation
    gives p a spike of region that separates a from b, so that the edge (a, b) at the corner is
    missing (for δ = 0.005 and σ = 50: a spike of 10⁴).  Samples at σ_j = f 2^-j from p (f the
    distance of the curve's first regular sample), down to σ₀ = 2 sin(δ/2) h (h the curve's
    spacing, at most a quarter of its gap to other sites), shorten the spike to h.  The pairs
    (curve, point site) in ``ends`` (a dict: pair -> level ℓ) are graded down to f 8^-ℓ: the
    construction asks for them where a vertex of p and the curve misses an edge, once more at
    each round that it still does.  Every σ_j stays above
    :data:`GRADING_FLOOR` of the end's coordinates (closer samples make qhull drop points as
    coplanar); one sequence per end, so that no two graded samples nearly coincide.  Arcs' ends
    are graded too (the turn of the sampled end ray, see below)."""
    out, lab = [], []
    L = curve_lengths(E)
    ends = dict(ends) if isinstance(ends, dict) else {e: 60 for e in ends}
    lo = np.minimum(E.A.min(axis=0), E.B.min(axis=0)) if len(E) else np.zeros(2)
    hi = np.maximum(E.A.max(axis=0), E.B.max(axis=0)) if len(E) else np.zeros(2)
    extent = float(np.max(hi - lo)) or 1.0
    for p, curves in enumerate(E.incident):
        asked = [s for s in curves if (s, p) in ends]
        if len(curves) < 2 and not asked and not any(E.kind[s] == ARC for s in curves):
            continue
        c = E.A[p]
        dirs = []
        for s in curves:
            if E.kind[s] == ARC:
                r = c - E.C[s]
                u = np.array([-r[1], r[0]]) if int(E.ends[s, 0]) == p else np.array([r[1], -r[0]])
            elif E.kind[s] == ELLIPSE:
                u = piece_tangent(E.ellipse[s], 0 if int(E.ends[s, 0]) == p else 1)
            else:
                u = (E.B[s] if int(E.ends[s, 0]) == p else E.A[s]) - c
            dirs.append(u / max(np.hypot(*u), 1e-300))
        floor = GRADING_FLOOR * (1 + float(np.max(np.abs(c))))
        for k, s in enumerate(curves):
            h = spacing[s]
            if not np.isfinite(h):
                continue
            n = max(1, int(np.ceil(L[s] / h)))
            first = L[s] / (2 * n)
            sigma0 = np.inf
            if s in asked:
                sigma0 = max(floor, first * 8.0 ** -ends[(s, p)])
            if len(curves) >= 2:
                cos_max = max(float(np.dot(dirs[k], dirs[j])) for j in range(len(curves)) if j != k)
                sigma0 = min(sigma0, max(2 * np.sqrt(max(0.0, (1 + cos_max) / 2)) * h, floor))  # 2 sin(δ/2) h
            if E.kind[s] == ARC:
                # the ray of an arc's end (from the centre through p) is drawn by the samples as
                # the bisector of p and the nearest sample, turned by σ/(2ρ): a sample at
                # σ = 2ρh / extent keeps the turn within h across the scene
                sigma0 = min(sigma0, max(2 * float(E.rho[s]) * h / extent, floor))
            if not np.isfinite(sigma0):
                continue
            dist = first * 0.5 ** np.arange(1, 61)
            dist = dist[dist >= sigma0]
            if not len(dist):
                continue
            out.append(end_points(E, s, p, dist))
            lab.append(np.full(len(dist), s))
    # the smooth joints of elliptic pieces (the ellipse's vertices): samples graded towards the
    # joint down to GRADING_FLOOR, so that the normal line there (an edge that may go to
    # infinity) is resolved far out: a far triangle of the two pieces and a third site is then an
    # end at infinity (runtime.segments.parallel_rays)
    for nd, curves in E.joints.items():
        for s in curves:
            if E.kind[s] != ELLIPSE or not np.isfinite(spacing[s]):
                continue
            end = 0 if int(E.ends[s, 0]) == -2 - nd else 1
            c = E.A[s] if end == 0 else E.B[s]
            n = max(1, int(np.ceil(L[s] / spacing[s])))
            floor = GRADING_FLOOR * (1 + float(np.max(np.abs(c))))
            dist = (L[s] / (2 * n)) * 0.5 ** np.arange(1, 61)
            dist = dist[dist >= floor]
            if len(dist):
                out.append(piece_at_lengths(E.ellipse[s], from_end=end, dist=dist))
                lab.append(np.full(len(dist), s))
    if not out:
        return np.empty((0, 2)), np.empty(0, dtype=np.int64)
    return np.concatenate(out), np.concatenate(lab)


def end_points(E: ElementarySites, s: int, p: int, dist) -> np.ndarray:
    """The points of curve s at arc lengths ``dist`` from its end p (floats, (k, 2))."""
    c = E.A[p]
    dist = np.asarray(dist, float)
    if E.kind[s] == ARC:
        r = c - E.C[s]
        sgn = 1.0 if int(E.ends[s, 0]) == p else -1.0
        th = np.arctan2(r[1], r[0]) + sgn * dist / E.rho[s]
        jitter = 1 + 1e-9 * (np.arange(len(th)) % 7 - 3)       # co-circular samples, see samples()
        return E.C[s] + (E.rho[s] * jitter)[:, None] * np.column_stack([np.cos(th), np.sin(th)])
    if E.kind[s] == ELLIPSE:
        return piece_at_lengths(E.ellipse[s], from_end=0 if int(E.ends[s, 0]) == p else 1, dist=dist)
    u = (E.B[s] if int(E.ends[s, 0]) == p else E.A[s]) - c
    return c + dist[:, None] * (u / max(np.hypot(*u), 1e-300))


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
    if E.kind[t] == ELLIPSE:
        P_ = E.ellipse[t]
        _d, phi = piece_feet(P_, q[None, :])
        span = P_.phi1 - P_.phi0
        f = piece_points(P_, np.clip(phi, P_.phi0 + 1e-6 * span, P_.phi1 - 1e-6 * span))[0]
        return float(f[0]), float(f[1])
    a, b = E.A[t], E.B[t]
    d = b - a
    # strictly inside the segment: an end is a point site's sample already
    f = a + np.clip(np.dot(q - a, d) / np.dot(d, d), 1e-6, 1 - 1e-6) * d
    return float(f[0]), float(f[1])


def triangulation(P, lab, droppable=None) -> SampleTriangulation:
    """qhull without joggling whenever it keeps every sample (segment samples are collinear in
    runs, which qhull's merged facets handle; joggling would flip the slivers on the hull whose
    circumcentres are the far vertices of nearly collinear hull sites), else joggled.

    ``droppable`` (a mask of the samples, e.g. those of curves, not point sites): samples that
    qhull leaves out as coplanar (a rounding away from another sample) may be dropped instead,
    when all of them are droppable; the triangulation is then that of the other samples, without
    joggling (joggling a million samples can take minutes).  The dropped samples are then put back
    by a local Bowyer–Watson step (:meth:`SampleTriangulation.update`, which re-triangulates only
    the cavity, in its own small frame): qhull's roundoff grows with the number and magnitude of
    the points, and a sample it calls coplanar may be the only witness that a curve's interior
    cuts an empty circle (a vertex of degree four split into two vertices closer than the
    spacing).  The samples only
    guide the combinatorics, which are proved afterwards; the result's ``P`` and ``lab`` are its
    own."""
    c = (P.min(axis=0) + P.max(axis=0)) / 2
    try:
        d = Delaunay(P - c, qhull_options="Qbb Qc Qz Q12")
        if not len(d.coplanar):
            return SampleTriangulation(P, lab, d.simplices, d.neighbors)
        gone = np.unique(d.coplanar[:, 0])
        if droppable is not None and droppable[gone].all():
            keep = np.ones(len(P), bool)
            keep[gone] = False
            del d
            Pg, labg = P[gone], lab[gone]
            P, lab = P[keep], lab[keep]
            d = Delaunay(P - c, qhull_options="Qbb Qc Qz Q12")
            if not len(d.coplanar):
                tri = SampleTriangulation(P, lab, d.simplices, d.neighbors)
                del d
                return insert_samples(tri, Pg, labg)
    except QhullError:
        pass
    return SampleTriangulation(P, lab)


#: samples closer than this (relative to their magnitude) to another are roundings of it
ROUNDING = 1e-12


def insert_samples(tri: SampleTriangulation, Pg, labg) -> SampleTriangulation:
    """``tri`` with the samples ``Pg`` (labels ``labg``) inserted locally; left out are those
    within :data:`ROUNDING` of their magnitude from a sample of ``tri`` (a rounding away from it:
    their triangles' circumcentres would be noise) and repeats within ``Pg``; ``tri`` itself
    when the local step refuses."""
    Pg = np.asarray(Pg, dtype=float)
    new = np.ascontiguousarray(Pg).view(np.complex128).ravel()
    _, first = np.unique(new, return_index=True)
    fresh = np.zeros(len(new), bool)
    fresh[first] = True
    gap, _ = cKDTree(tri.P).query(Pg)
    fresh &= gap > ROUNDING * (1.0 + np.abs(Pg).sum(axis=1))
    if not fresh.any():
        return tri
    try:
        out = tri.update(np.zeros(0, np.int64), Pg[fresh], labg[fresh])
    except (ValueError, IndexError, QhullError):
        return tri
    return tri if out is None else out


#: a local update of the triangulation is tried when at most this fraction of the samples changed
LOCAL_FRACTION = 0.5


def retriangulation(prev: SampleTriangulation, P, lab) -> SampleTriangulation | None:
    """The triangulation of the samples ``P`` (labels ``lab``) from ``prev``, the triangulation of
    the previous round's samples, by removing the samples that are gone and inserting the new
    ones (:meth:`runtime.voronoi.sample_delaunay.SampleTriangulation.update`, a batch
    Bowyer–Watson step): refinement changes the samples of a few sites only, and the rest of the
    triangulation stays as it is.  Samples are matched by their exact coordinates (a sample of a
    site whose spacing did not change is recomputed bit for bit).  The result's samples are in
    its own order (kept ones, then new ones).  None when a full triangulation is the better
    choice (too many changes, a relabelled sample) or the update refuses."""
    match = exact_matches(prev.P, P)
    if match is None:
        return None
    keep, add, at = match
    n_change = int((~keep).sum() + add.sum())
    if n_change > LOCAL_FRACTION * len(P):
        return None
    # a kept sample must keep its label
    if not np.array_equal(lab[at], prev.lab[keep]):
        return None
    if n_change == 0:
        return prev
    try:
        return prev.update(np.nonzero(~keep)[0], P[add], lab[add])
    except (ValueError, IndexError, QhullError):
        return None


def _exact_keys(P) -> np.ndarray:
    """64-bit keys of the exact coordinates of the points P (−0.0 taken as 0.0): equal points have
    equal keys; distinct points may collide, which :func:`exact_matches` detects."""
    b = np.ascontiguousarray(np.asarray(P, float).reshape(-1, 2) + 0.0).view(np.uint64)
    return _mix64(_mix64(b[:, 0]) ^ b[:, 1])


def _mix64(z) -> np.ndarray:
    """The splitmix64 finaliser (Steele, Lea & Flood 2014): every input bit reaches every output
    bit (coordinates like 1235.0 or 1633.25 have long runs of zero bits)."""
    z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    return z ^ (z >> np.uint64(31))


def exact_matches(old, cur):
    """(keep, add, at) for the samples ``old`` and ``cur`` (points, compared exactly): ``keep``
    marks the old samples that are in ``cur``, ``add`` the current ones that are not in ``old``,
    ``at`` the positions in ``cur`` of the kept ones; None when ``cur`` repeats a point.  Points
    are found by their :func:`_exact_keys` and then compared coordinate by coordinate; a collision
    of keys (or a non-finite point) falls back to the sorted complex values."""
    old, cur = np.asarray(old, float).reshape(-1, 2), np.asarray(cur, float).reshape(-1, 2)
    ko, kc = _exact_keys(old), _exact_keys(cur)
    oc = np.argsort(kc, kind="stable")
    sc, so = kc[oc], np.sort(ko)
    if not (np.isfinite(old).all() and np.isfinite(cur).all()):
        return _complex_matches(old, cur)
    dup = np.nonzero(sc[1:] == sc[:-1])[0]
    if len(dup):
        if (cur[oc[dup]] == cur[oc[dup + 1]]).all(axis=1).any():
            return None                               # a repeated sample
        return _complex_matches(old, cur)             # a collision of keys
    # (keys of ``cur`` are distinct: a hit is the one candidate; keys of ``old`` may repeat)
    pos = np.minimum(np.searchsorted(sc, ko), len(sc) - 1) if len(sc) else np.zeros(len(ko), np.int64)
    keep = sc[pos] == ko if len(sc) else np.zeros(len(ko), bool)
    at = oc[pos[keep]]
    if not (old[keep] == cur[at]).all():
        return _complex_matches(old, cur)
    # a current sample whose key is an old one's is that old sample: the old one's key hit it
    # (the current keys are distinct) and was just checked coordinate by coordinate
    pos = np.minimum(np.searchsorted(so, kc), len(so) - 1) if len(so) else np.zeros(len(kc), np.int64)
    found = so[pos] == kc if len(so) else np.zeros(len(kc), bool)
    return keep, ~found, at


def _complex_matches(old, cur):
    """:func:`exact_matches` by sorting the points as complex numbers."""
    old = np.ascontiguousarray(old, dtype=float).view(np.complex128).ravel()
    cur = np.ascontiguousarray(cur, dtype=float).view(np.complex128).ravel()
    if len(np.unique(cur)) != len(cur):
        return None
    keep = np.isin(old, cur)
    add = ~np.isin(cur, old)
    order = np.argsort(cur)
    return keep, add, order[np.searchsorted(cur, old[keep], sorter=order)]


def flat(P) -> bool:
    """Fewer than three samples, or all of them on one line (relative 1e-12)."""
    if len(P) < 3:
        return True
    Q = P - P[0]
    s = np.linalg.svd(Q, compute_uv=False)
    return bool(s[1] <= 1e-12 * max(s[0], 1e-300))
