"""Sampling of the sites for the sample Delaunay triangulation.

Every site is sampled with spacing ``SPACING_FACTOR``·min(size, gap), the gap a lower bound of
the distance to the other sites from a k-d tree on bounding discs (floored at ``GAP_FLOOR``·size:
a narrow gap between two convex sites does not change the combinatorics, and where a third site
makes it matter the refinement rounds densify).  Unbounded sites are clipped to the window.

Circles are sampled at the angles 2πk/n; a refinement multiplies n by a power of two, so the
samples of a round are a subset of those of the next (bitwise: 2π·2k/(2n) = 2πk/n in floating
point), and the sample triangulation can be updated by insertion only
(:meth:`runtime.voronoi.sample_delaunay.SampleTriangulation.update`).

The full triangulation is qhull's (:func:`runtime.voronoi.sample_delaunay.delaunay`); the memory
qhull frees is given back to the operating system (:func:`release_free_memory`) before the
triangulation's arrays are built, so that the two do not add up in the resident size.

Public API: :func:`initial_spacing`, :func:`clamp_spacing`, :func:`sample_sites`,
:func:`release_free_memory`.
"""
from __future__ import annotations

import ctypes
import ctypes.util
import math

import numpy as np
from scipy.spatial import ConvexHull, QhullError, cKDTree

from .conic_geometry import ellipse_samples
from .exact_delaunay import exact_delaunay, is_delaunay
from .sample_delaunay import JOGGLE_ABOVE, SampleTriangulation, delaunay, perturbed
from .site_arrays import SiteArrays
from .strip_delaunay import strip_delaunay

__all__ = ["Samples", "hull_neighbours", "initial_spacing", "clamp_spacing", "sample_sites", "circle_sample_counts", "SPACING_FACTOR", "MAX_SAMPLES_FIRST",
           "MAX_SAMPLES", "GAP_FLOOR"]

def _libc_trim():
    """glibc's ``malloc_trim`` (None elsewhere)."""
    try:
        return ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6").malloc_trim
    except (OSError, AttributeError):
        return None


_TRIM = _libc_trim()


def release_free_memory() -> None:
    """Give the heap pages freed by a phase back to the operating system (glibc ``malloc_trim``,
    which also releases whole free pages inside the heap; nothing elsewhere).  glibc keeps freed
    memory mapped for reuse, while numpy's large arrays are mapped apart (``mmap``): the memory
    qhull frees after a triangulation (its facets) and the freed blocks of a round, scattered
    among the blocks the next round keeps, would stay resident beside the arrays built after them
    (measured on 3·10⁴ random circles: 649 MB resident after the construction, 396 MB after one
    trim).  The data are unchanged; only the resident size, and so the peak of later phases, drops."""
    if _TRIM is not None:
        _TRIM(0)


#: sampling spacing as a fraction of min(gap, size)
SPACING_FACTOR = 0.6
#: samples per site: at the first round / at most after refinement
MAX_SAMPLES_FIRST = 2048
MAX_SAMPLES = 1 << 15
#: the gap used for the first spacing is at least this fraction of the size (narrow gaps between two
#: convex sites do not change the combinatorics; where they do, the refinement rounds densify)
GAP_FLOOR = 0.5


def initial_spacing(S: SiteArrays) -> np.ndarray:
    """spacing_i = c·min(gap_i, size_i), gap_i a lower bound from bounding discs (k-d tree)."""
    n = S.n
    size = S.size.copy()
    gap = np.full(n, np.inf)
    if n > 1:
        tree = cKDTree(S.C)
        k = min(n, 9)
        dd, jj = tree.query(S.C, k=k)
        for col in range(1, k):
            j = jj[:, col]
            g = dd[:, col] - S.R - S.R[j]
            ok = (g > 0) & S.bounded & S.bounded[j]
            gap = np.where(ok, np.minimum(gap, g), gap)
    gap = np.maximum(np.where(np.isfinite(gap), gap, size), GAP_FLOOR * size)
    sp = SPACING_FACTOR * np.minimum(gap, size)
    sp = np.where(sp > 0, sp, SPACING_FACTOR * size)
    return clamp_spacing(S, sp, MAX_SAMPLES_FIRST)


def clamp_spacing(S: SiteArrays, sp, max_samples):
    perim = 2 * math.pi * S.size
    floor = perim / max_samples
    sp = np.maximum(sp, floor)
    return np.where(sp > 0, sp, 1.0)


def circle_sample_counts(S: SiteArrays, spacing, base=None):
    """Samples per circle: max(8, ⌈2πr / spacing⌉), or, given the counts ``base`` of the first
    round, the least base·2^k reaching that (so that later rounds only add samples); 1 for a point."""
    R = S.R
    need = np.where(R > 0, np.maximum(8, np.ceil(2 * math.pi * R / spacing)), 1).astype(np.int64)
    if base is None:
        return need
    k = np.ceil(np.log2(np.maximum(need / np.maximum(base, 1), 1.0)) - 1e-12).astype(np.int64)
    return np.where(R > 0, base * (1 << np.maximum(k, 0)), 1).astype(np.int64)


def sample_sites(S: SiteArrays, spacing, sites=None, base=None):
    """The samples (m, 2) of ``sites`` (all when None) and their site labels.  Circles: the angles
    2πk/n, n from :func:`circle_sample_counts` (``base``: the first round's counts)."""
    idx = np.arange(S.n) if sites is None else np.asarray(sites, dtype=np.int64)
    if S.all_circles:
        R = S.R
        nper = circle_sample_counts(S, spacing, base)[idx]
        lab = np.repeat(idx, nper)
        start = np.concatenate([[0], np.cumsum(nper)[:-1]])
        k = np.arange(len(lab)) - np.repeat(start, nper)
        t = 2 * math.pi * k / np.repeat(nper, nper)
        P = np.column_stack([S.C[lab, 0] + R[lab] * np.cos(t), S.C[lab, 1] + R[lab] * np.sin(t)])
        return P, lab
    parts, labs = [np.zeros((0, 2))], [np.zeros(0, np.int64)]
    ell = idx[S.ellipse[idx]]
    if len(ell):          # the ellipses together (the same points as their own samples())
        Pe, ne = ellipse_samples([S.geoms[i] for i in ell.tolist()], np.asarray(spacing, float)[ell])
        of = dict(zip(ell.tolist(), np.split(Pe, np.cumsum(ne)[:-1])))
    for i in idx.tolist():
        p = of[i] if S.ellipse[i] else \
            np.asarray(S.geoms[i].samples(float(spacing[i]), S.window), float).reshape(-1, 2)
        parts.append(p)
        labs.append(np.full(len(p), i, dtype=np.int64))
    return np.concatenate(parts), np.concatenate(labs)


class Samples:
    """The samples of every site at the current ``spacing`` and their Delaunay triangulation,
    kept across refinement rounds.  :meth:`triangulation` re-samples only the sites whose spacing
    changed and updates the last triangulation locally
    (:meth:`runtime.voronoi.sample_delaunay.SampleTriangulation.update`: the samples that
    disappear are removed, the new ones inserted), with a full qhull triangulation when the
    local update declines."""

    def __init__(self, S: SiteArrays, spacing):
        self.S = S
        self.spacing = np.asarray(spacing, float).copy()
        self.base = circle_sample_counts(S, self.spacing) if S.all_circles else None
        self.sampled = None          # the spacing of the samples in self.tri
        self.tri = None
        # the spacing of the last full sampling, the sites updated since, and the triangulation
        # these describe (None: self.tri came from elsewhere, e.g. a deletion)
        self.full_spacing = self.touched = self.tracked = None

    def refine(self, idx, new_spacing):
        self.spacing[idx] = new_spacing
        self.spacing[:] = clamp_spacing(self.S, self.spacing, MAX_SAMPLES)

    def triangulation(self, stats) -> SampleTriangulation:
        S = self.S
        if self.tri is not None:
            changed = np.nonzero(self.spacing != self.sampled)[0]
            if not len(changed):
                return self.tri
            Pn, ln = sample_sites(S, self.spacing, sites=changed, base=self.base)
            old = np.nonzero(np.isin(self.tri.lab, changed))[0]
            zo = self.tri.P[old, 0] + 1j * self.tri.P[old, 1]
            zn = Pn[:, 0] + 1j * Pn[:, 1]
            add = ~np.isin(zn, zo)
            remove = old[~np.isin(zo, zn)]
            if not add.any() and not len(remove):        # same samples (e.g. at the sample cap)
                self.sampled = self.spacing.copy()
                return self.tri
            tri = self.tri.update(remove, Pn[add], ln[add])
            if tri is not None:
                stats["local_updates"] = stats.get("local_updates", 0) + 1
                if self.tracked is self.tri:
                    self.touched[changed] = True
                    self.tracked = tri
                self.tri, self.sampled = tri, self.spacing.copy()
                return tri
        stats["triangulations"] = stats.get("triangulations", 0) + 1
        P, lab = self._all_samples()
        self.tri = None                  # the last triangulation is not needed for a full one
        points = S.all_circles and not S.R.any()     # point sites: the samples are the sites
        try:
            simp, nb = _triangles(P, lab)
        except QhullError:
            if not points:
                raise
            simp = nb = None             # e.g. three points 1e-14 off a line: a flat initial simplex
        release_free_memory()            # qhull's facets, before the triangulation's arrays
        if points and (simp is None or not is_delaunay(P, simp, nb)):
            # qhull decides in floats; the diagram of points is the exact Delaunay triangulation
            exact = exact_delaunay(P)
            if exact is None:
                raise QhullError("the points lie on one line")
            simp, nb = exact
            stats["exact_delaunay"] = stats.get("exact_delaunay", 0) + 1
        self.tri, self.sampled = SampleTriangulation(P, lab, simp, nb), self.spacing.copy()
        self.full_spacing, self.touched, self.tracked = self.sampled, np.zeros(S.n, bool), self.tri
        return self.tri

    def _all_samples(self):
        """:func:`sample_sites` of every site at the current spacing.  A site whose spacing is that
        of the last full sampling and which no batch update touched since has those samples, in
        their order, in the current triangulation (the update keeps the kept samples in their
        order and appends the new ones): they are taken from there, the other sites sampled
        anew (a site's samples do not depend on the other sites of the call)."""
        S, tri = self.S, self.tri
        if tri is None or self.tracked is not tri:
            return sample_sites(S, self.spacing, base=self.base)
        same = (self.spacing == self.full_spacing) & ~self.touched
        Pn, ln = sample_sites(S, self.spacing, sites=np.nonzero(~same)[0], base=self.base)
        rows = np.nonzero(same[tri.lab])[0]
        lab = np.concatenate([tri.lab[rows], ln])
        order = np.argsort(lab, kind="stable")          # by site, each site's samples in order
        return np.concatenate([tri.P[rows], Pn])[order], lab[order]


def _triangles(P, lab):
    """(simplices, neighbours) of the samples' Delaunay triangulation: strip by strip
    (:func:`runtime.voronoi.strip_delaunay.strip_delaunay`, in a fraction of qhull's memory) for
    many samples, which qhull would triangulate perturbed (:func:`runtime.voronoi.sample_delaunay.
    delaunay`: the same perturbation), else -- or when a strip's check fails -- qhull's on all."""
    if len(P) >= JOGGLE_ABOVE:
        c = (P.min(axis=0) + P.max(axis=0)) / 2
        found = strip_delaunay(perturbed(P - c), lab)
        if found is not None:
            return found
    qh, _ = delaunay(P)
    return qh.simplices, qh.neighbors


#: samples per site for the convex hull of :func:`hull_neighbours` (sagitta 1 − cos(π/256) ≈ 7.5e-5
#: of the size)
HULL_SAMPLES = 256


def hull_neighbours(S: SiteArrays, sites) -> set:
    """The pairs of ``sites`` consecutive on the convex hull of their fine samples
    (``HULL_SAMPLES`` per site).  For bounded sites, two sites consecutive on the convex hull of
    all sites have an unbounded Voronoi edge (its points far along the outer normal of their common
    supporting line are nearest to them); ``sites`` must hold every site of that hull."""
    idx = np.asarray(sorted(set(int(s) for s in sites)), dtype=np.int64)
    if len(idx) < 2:
        return set()
    spacing = np.full(S.n, np.inf)
    spacing[idx] = np.maximum(2 * math.pi * S.size[idx] / HULL_SAMPLES, 1e-300)
    P, lab = sample_sites(S, spacing, sites=idx)
    try:
        order = ConvexHull(P).vertices            # counter-clockwise
    except Exception:  # noqa: BLE001 - flat or too few points: no hull pairs to check
        return set()
    L = lab[order]
    # hull sides joining two sites, and whether a third site (nearly) touches the side's line:
    # then the sites tie at infinity in that direction (collinear points, sites tangent to one
    # line) and which of them have unbounded edges is left to the verifier's exact accounting
    Pn = P[np.roll(order, -1)]
    Po = P[order]
    d = Pn - Po
    nrm = np.column_stack([d[:, 1], -d[:, 0]])
    ln = np.hypot(nrm[:, 0], nrm[:, 1])
    side = np.nonzero((L != np.roll(L, -1)) & (ln > 0))[0]
    tied = set()
    if len(side):
        u = nrm[side] / ln[side, None]
        h = (Po[side] * u).sum(axis=1)
        sag = (math.pi / HULL_SAMPLES) ** 2 * S.size[idx].max()       # a sample's depth below the hull
        reach = P @ u.T - h[None, :]                                  # (samples, sides)
        other = (lab[:, None] != L[side][None, :]) & (lab[:, None] != L[(side + 1) % len(L)][None, :])
        near = ((reach >= -2 * sag - 1e-9 * (np.abs(P).max() + 1)) & other).any(axis=0)
        tied = {(min(int(L[t]), int(L[(t + 1) % len(L)])), max(int(L[t]), int(L[(t + 1) % len(L)])))
                for t in side[near].tolist()}
    L = L[np.concatenate([[True], L[1:] != L[:-1]])]
    if len(L) > 1 and L[0] == L[-1]:
        L = L[:-1]
    if len(L) < 2 or len(set(L.tolist())) != len(L):
        return set()                               # a site twice on the hull: leave it to the verifier
    pairs = {(min(a, b), max(a, b)) for a, b in zip(L.tolist(), np.roll(L, -1).tolist()) if a != b}
    return pairs - tied
