"""150 random circular arcs (tests/scenes.py random_arcs): certified, and the Delaunay graph over the
elementary sites agrees with dense sampling of the distance functions written here from their
definitions (numpy floats; no runtime code).

Sampling: on a grid of step h, each grid point's nearest elementary site (an arc's open interior
owns only the points whose direction from its centre lies strictly inside its range — elsewhere
its nearest point is an end, a point site, which owns the tie by the convention of CGAL and of
the thesis's harmless sites).  Two neighbouring grid points p, p' with nearest sites i ≠ j whose
third-nearest site is farther than the second by more than 2h at both are joined by a Voronoi edge
of (i, j): along [p, p'] (length ≤ h, distances 1-Lipschitz) i and j stay strictly nearer than
every other site, and d_i − d_j changes sign.  So every such pair must be a Delaunay edge of the
diagram; conversely, at the middle point of each edge's polyline its two sites must be the
nearest (to the polyline's stated tolerance).
"""
from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np

import curvedvoronoi as cv

sys.path.insert(0, str(Path(__file__).parent))
import scenes  # noqa: E402

STEP = 2.0


def _owned_distance(site, P):
    """The distance from the points P to the elementary site where that site owns it (an arc's
    interior only strictly inside its angular range), +∞ elsewhere."""
    if isinstance(site, cv.Arc):
        cx, cy, rho = float(site.c[0]), float(site.c[1]), float(site.rho)
        a0 = math.atan2(float(site.a[1]) - cy, float(site.a[0]) - cx)
        span = (math.atan2(float(site.b[1]) - cy, float(site.b[0]) - cx) - a0) % (2 * math.pi)
        w = (np.arctan2(P[:, 1] - cy, P[:, 0] - cx) - a0) % (2 * math.pi)
        inside = (w > 1e-12) & (w < span - 1e-12)
        return np.where(inside, np.abs(np.hypot(P[:, 0] - cx, P[:, 1] - cy) - rho), np.inf)
    return np.hypot(P[:, 0] - float(site.x), P[:, 1] - float(site.y))


def _three_nearest(sites, P):
    """Per point: the indices of the nearest and second-nearest sites and the three smallest
    distances."""
    n = len(P)
    best = np.full((n, 3), np.inf)
    idx = np.full((n, 3), -1)
    for k, s in enumerate(sites):
        d = _owned_distance(s, P)
        for r in range(3):
            better = d < best[:, r]
            if r < 2:
                best[better, r + 1:] = best[better, r:-1]
                idx[better, r + 1:] = idx[better, r:-1]
            best[better, r] = d[better]
            idx[better, r] = k
            d = np.where(better, np.inf, d)
    return idx, best


def test_150_random_arcs_certified_and_their_delaunay_graph_sampled():
    arcs = scenes.random_arcs(150, 5)
    d = cv.voronoi(arcs)
    assert d.certified, d.problems[:3]
    ours = {tuple(sorted(p)) for p in d.delaunay_edges()}
    # the grid: the scene's bounding box and a margin of two cells
    C = np.array([[float(a.c[0]), float(a.c[1])] for a in arcs])
    lo, hi = C.min(axis=0) - 80, C.max(axis=0) + 80
    xs = np.arange(lo[0], hi[0], STEP)
    ys = np.arange(lo[1], hi[1], STEP)
    X, Y = np.meshgrid(xs, ys)
    P = np.column_stack([X.ravel(), Y.ravel()])
    idx, best = _three_nearest(d.sites, P)
    near = idx[:, 0].reshape(X.shape)
    robust = (best[:, 2] - best[:, 1] > 2 * STEP * math.sqrt(2)).reshape(X.shape)
    sampled = set()
    for a, b, ra, rb in ((near[:, :-1], near[:, 1:], robust[:, :-1], robust[:, 1:]),
                         (near[:-1, :], near[1:, :], robust[:-1, :], robust[1:, :])):
        m = (a != b) & ra & rb
        sampled |= {tuple(sorted(p)) for p in zip(a[m].tolist(), b[m].tolist())}
    assert len(sampled) > 300
    assert sampled <= ours, sorted(sampled - ours)[:5]
    # every edge's middle polyline point has its two sites as the nearest
    mids = np.array([np.asarray(e.polyline)[len(e.polyline) // 2] if len(e.polyline) > 2 else
                     np.asarray(e.polyline).mean(axis=0) for e in d.edges])
    D = np.column_stack([np.minimum(_owned_distance(s, mids), _closed_end_distance(s, mids)) for s in d.sites])
    for e, row in zip(d.edges, D):
        i, j = e.sites
        tol = 2 * float(e.tolerance) + 1e-9 * (1 + row[i])
        own = max(row[i], row[j])
        assert abs(row[i] - row[j]) <= tol, e
        assert np.delete(row, [i, j]).min() >= own - tol, e


def _closed_end_distance(site, P):
    """An arc's distance where its nearest point is an end (the closed site), +∞ for points."""
    if isinstance(site, cv.Arc):
        return np.minimum(np.hypot(P[:, 0] - float(site.a[0]), P[:, 1] - float(site.a[1])),
                          np.hypot(P[:, 0] - float(site.b[0]), P[:, 1] - float(site.b[1])))
    return np.full(len(P), np.inf)
