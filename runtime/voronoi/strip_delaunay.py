"""The Delaunay triangulation of many points, strip by strip, in a fraction of qhull's memory.

qhull keeps about 1 kB of facet structures per input point while it triangulates (measured:
+1.4 GB for 1.5·10⁶ samples of 10⁵ circles), more than everything else the construction holds.
Here the points, sorted by abscissa, are cut into vertical strips of about :data:`STRIP_POINTS`
points; each strip is triangulated by qhull together with a *halo* (the points of a quarter strip
on either side), and keeps the triangles it *owns*: those whose circumcentre lies in the strip
(computed from the corners in increasing index order, so that it is the same float in every
strip), and those with three corners on one site whose site's mean abscissa lies in the strip
(samples of one circle are nearly co-circular: their circumcentres are ill-conditioned and
qhull's choice of diagonals among them depends on the other points, so a site's own triangles
come whole from one qhull run).  Each triangle has exactly one owner.

A kept triangle is a Delaunay triangle of all the points when its open circumdisk holds none of
them (Delaunay 1934; in general position, which the fixed perturbation of
:func:`runtime.voronoi.sample_delaunay.perturbed` gives, the Delaunay triangulation is the set of
such triangles): qhull finds the disk empty of the strip's and halo's points, and the disk holds
no other point when it lies within the abscissae of the halo; a disk reaching beyond them (near
the convex hull, a disk can be almost a half-plane) is searched for the other points with a k-d
tree, and the triangle dropped when one is inside.  The kept triangles then tile the convex hull
when every side on no second triangle has no point strictly beyond it (exact orientation: the
dual graph of a triangulation of a convex polygon is connected, so a missing triangle leaves an
inner side open).  The triangles missed (a far corner outside the owner's halo) have their
corners among the points of no kept triangle and the ends of the open inner sides: those points
are triangulated by qhull, and the triangles with an empty circumdisk, between two sites, that
meet the kept ones only across open inner sides are added; the check is repeated.  When any of
this fails -- a strip where qhull drops a point, a side of three triangles, a side left open --
the caller triangulates all the points at once.

The triangles between two or three sites (all the walks and vertices read) were the same as
qhull's on all samples at once on 10³–10⁵ random circles; the triangles inside one circle may
take other diagonals (qhull's float decisions among nearly co-circular samples); their order
and corner order differ, so the circumcentre seeds of the vertices differ in the last bits.

Public API: :func:`strip_delaunay`, :data:`STRIP_POINTS`.
"""
from __future__ import annotations

import numpy as np
from scipy.spatial import Delaunay, QhullError, cKDTree

from ..predicates.orientation import orient2d, orient2d_filter
from .sample_delaunay import QHULL_PLAIN, circumcentres, side_neighbours

__all__ = ["strip_delaunay", "STRIP_POINTS"]

#: points per strip (qhull's facets for 3·10⁴ points, the strip and its halo: about 30 MB)
STRIP_POINTS = 20000
#: relative margin of the disk tests (a circumdisk must clear the halo's abscissae by this much of
#: its radius plus the extent; a corner is on its own circumcircle up to rounding)
MARGIN = 1e-9


def strip_delaunay(Q, lab, strip_points: int | None = None):
    """(simplices, neighbours) of the Delaunay triangulation of the points ``Q`` (n × 2, in
    general position, e.g. perturbed) labelled by their sites ``lab`` (ints ≥ 0), in qhull's layout (``neighbours[t, k]`` across the side
    opposite corner k, −1 on the hull; int32), built strip by strip (module docstring); None when
    there are fewer than two strips' worth of points (default
    :data:`STRIP_POINTS`) or a check fails."""
    Q = np.ascontiguousarray(Q, dtype=float)
    strip_points = STRIP_POINTS if strip_points is None else strip_points
    n = len(Q)
    k = n // strip_points
    if k < 2:
        return None
    order = np.argsort(Q[:, 0], kind="stable").astype(np.int32)
    xs = Q[order, 0]
    cut = np.linspace(0, n, k + 1).astype(np.int64)
    extent = float(np.abs(Q).max())
    lab = np.asarray(lab)
    # a site's place: the mean abscissa of its points (the triangles with three corners on one
    # site, nearly co-circular on a circle, go with their site to one strip)
    place = np.bincount(lab, weights=Q[:, 0]) / np.maximum(np.bincount(lab), 1)
    parts, tree = [], None
    for s in range(k):
        lo, hi = int(cut[s]), int(cut[s + 1])
        a = xs[lo] if s else -np.inf                 # the strip owns circumcentres with a ≤ x < b
        b = xs[hi] if s < k - 1 else np.inf
        halo = (hi - lo) // 4
        hlo, hhi = max(lo - halo, 0), min(hi + halo, n)
        # every point whose abscissa lies in [xlo, xhi] is in the strip or its halo
        xlo = xs[hlo] if hlo > 0 else -np.inf
        xhi = xs[hhi - 1] if hhi < n else np.inf
        hlo = int(np.searchsorted(xs, xlo, side="left")) if hlo > 0 else 0
        hhi = int(np.searchsorted(xs, xhi, side="right")) if hhi < n else n
        idx = order[hlo:hhi]
        try:
            tri = Delaunay(Q[idx], qhull_options=QHULL_PLAIN)
        except QhullError:
            return None
        if len(tri.coplanar):
            return None
        simp = idx[tri.simplices]
        del tri
        srt = np.sort(simp, axis=1)                  # corners in increasing index order
        cc = circumcentres(Q[srt[:, 0]], Q[srt[:, 1]], Q[srt[:, 2]])
        L = lab[srt]
        x = np.where((L[:, 0] == L[:, 1]) & (L[:, 1] == L[:, 2]), place[L[:, 0]], cc[:, 0])
        own = (x >= a) & (x < b)
        del L, x
        simp, cc = simp[own], cc[own]
        r = np.hypot(*(Q[srt[own, 0]] - cc).T)
        del srt
        slack = MARGIN * (r + extent)
        inside = (cc[:, 0] - r - slack > xlo) & (cc[:, 0] + r + slack < xhi)
        far = np.nonzero(~inside)[0]
        if len(far):
            if tree is None:
                tree = cKDTree(Q)
            drop = far[~_empty(tree, simp[far], cc[far], r[far], extent)]
            simp = np.delete(simp, drop, axis=0)     # not Delaunay: the repair below
        parts.append(simp.astype(np.int32))
        del cc, r, simp
    simp = np.concatenate(parts)
    del parts
    nb = side_neighbours(simp, n, dtype=np.int32)
    if nb is None:
        return None
    bad = _open_inner_sides(Q, simp, nb)
    if bad:
        # the triangles missed (near the hull, a circumcentre's strip may lack a far corner) have
        # their corners among the points of no kept triangle and the ends of the open inner sides
        used = np.zeros(n, bool)
        used[simp.ravel()] = True
        R = np.union1d(np.nonzero(~used)[0], np.array(bad, dtype=np.int64).ravel())
        del used
        if len(R) > strip_points or len(R) < 3:
            return None
        try:
            tri = Delaunay(Q[R], qhull_options=QHULL_PLAIN)
        except QhullError:
            return None
        more = R[tri.simplices].astype(np.int32)
        del tri
        srt = np.sort(more, axis=1)
        cc = circumcentres(Q[srt[:, 0]], Q[srt[:, 1]], Q[srt[:, 2]])
        r = np.hypot(*(Q[srt[:, 0]] - cc).T)
        if tree is None:
            tree = cKDTree(Q)
        L = lab[srt]
        # a site's own triangles (nearly co-circular corners on a circle: beyond the margin of the
        # disk test) come whole from its strip; the repair adds the others
        keep = _empty(tree, more, cc, r, extent) & ((L[:, 0] != L[:, 1]) | (L[:, 1] != L[:, 2]))
        del L
        # the kept triangles that may share a side with a new one: two corners among R
        in_r = np.zeros(n, bool)
        in_r[R] = True
        near = simp[in_r[simp].sum(axis=1) >= 2]
        del in_r
        keep &= ~np.isin(_rows(srt), _rows(np.sort(near, axis=1)))
        # a new triangle may only meet the kept ones across an open inner side
        closed = _side_keys(near, n)
        closed = np.setdiff1d(closed, np.array([min(a, b) * n + max(a, b) for a, b in bad], dtype=np.int64))
        keep &= ~np.isin(_side_keys(more, n), closed).reshape(3, -1).any(axis=0)
        del closed, near
        simp = np.concatenate([simp, more[keep]])
        del tree, more, srt, cc, r
        nb = side_neighbours(simp, n, dtype=np.int32)
        if nb is None or _open_inner_sides(Q, simp, nb):
            return None
    return simp, nb


def _side_keys(simp, n):
    """One int key per side of each triangle (side k of all triangles, then side k + 1, …)."""
    a = np.concatenate([simp[:, (k + 1) % 3] for k in range(3)]).astype(np.int64)
    b = np.concatenate([simp[:, (k + 2) % 3] for k in range(3)]).astype(np.int64)
    return np.minimum(a, b) * n + np.maximum(a, b)


def _rows(srt):
    """The triangles (corners in increasing order, int32) as one record each, for ``np.isin``."""
    return np.ascontiguousarray(srt, dtype=np.int32).view(
        np.dtype([("a", np.int32), ("b", np.int32), ("c", np.int32)])).ravel()


def _open_inner_sides(Q, simp, nb) -> list:
    """The sides on no second triangle with a point strictly beyond them (on the side away from
    their triangle): not sides of the convex hull."""
    t, kk = np.nonzero(nb < 0)
    bad = []
    extent = float(np.abs(Q).max()) if len(t) else 0.0
    for ti, ki in zip(t.tolist(), kk.tolist()):
        a, b, c = (int(simp[ti, (ki + j) % 3]) for j in (1, 2, 0))
        if _beyond(Q, a, b, c, extent):
            bad.append((a, b))
    return bad


def _empty(tree, simp, cc, r, extent):
    """Per triangle: its circumdisk (centre ``cc``, radius ``r``) shrunk by :data:`MARGIN` holds
    no point but its corners (the four points nearest the centre, from the k-d tree)."""
    d, i = tree.query(cc, k=4)
    near = d < r[:, None] * (1 - MARGIN) - MARGIN * extent
    corner = (i[:, :, None] == simp[:, None, :]).any(axis=2)
    return ~(near & ~corner).any(axis=1)


#: points per block of the hull test
BLOCK = 1 << 18


def _beyond(Q, a, b, c, extent) -> bool:
    """Is a point of ``Q`` strictly on the other side of the line (a, b) than c (exact signs:
    :func:`runtime.predicates.orientation.orient2d_filter`, then ``orient2d`` for the undecided
    points)?  Only the points not surely on c's side are examined: the float orientation
    det = u_x (y − a_y) − u_y (x − a_x), u = b − a, is within 8ε|u|₁·extent of the exact one
    (``extent`` = max|Q|; four roundings of terms at most |u|₁ · 2 extent, ε = 2⁻⁵³), far below
    the slack used, 10⁻¹² |u|₁·extent (plus 10⁻³⁰⁰ for underflow); NaN is examined."""
    side = orient2d(Q[a], Q[b], Q[c])
    (ax, ay), (ux, uy) = Q[a], Q[b] - Q[a]
    slack = 1e-12 * (abs(ux) + abs(uy)) * extent + 1e-300
    for lo in range(0, len(Q), BLOCK):
        X = Q[lo:lo + BLOCK]
        with np.errstate(invalid="ignore", over="ignore"):
            X = X[~(side * (ux * (X[:, 1] - ay) - uy * (X[:, 0] - ax)) > slack)]
        det, decided = orient2d_filter(Q[a][None, :], Q[b][None, :], X)
        if (decided & (det * side < 0)).any():
            return True
        for i in np.nonzero(~decided)[0].tolist():
            if orient2d(Q[a], Q[b], X[i]) * side < 0:
                return True
    return False
