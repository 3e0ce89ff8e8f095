"""The sites of a diagram as flat arrays: vectorised distances, gradients and neighbour queries.

Every site has a geometry (:mod:`runtime.voronoi.geometry`, :mod:`runtime.voronoi.conic_geometry`)
giving float distances, foot points and rigorous distance bounds; when every site is a circle or
a point the distances are evaluated on arrays of centres and radii at once.  The neighbour query
(k-d tree on bounding discs, "big" sites checked one by one) serves the emptiness proofs; its
bounded form (:meth:`SiteArrays.nearest_sites`) looks at the k nearest centres only and says when
that is all.

Public API: :class:`SiteArrays`, :func:`site_groups`.
"""
from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from ..sites.foot_points import ellipse_foot_points
from ..sites.kinds import SiteKind
from .conic_geometry import EllipseGeometry
from .geometry import rounding_slack

__all__ = ["SiteArrays", "site_groups", "NEAREST"]

#: small sites looked up per query by :meth:`SiteArrays.nearest_sites` (an empty circle's disc,
#: widened by the largest small radius, meets a few sites; more means a wide query)
NEAREST = 32


class SiteArrays:
    """The geometries plus, when every site is a circle or a point, flat arrays for the
    vectorised paths."""

    def __init__(self, sites, geoms):
        self.sites = sites
        self.geoms = geoms
        self.n = len(geoms)
        self.all_circles = all(SiteKind.of(g.kind).circular for g in geoms)
        boxes = np.array([g.bounding_box() for g in geoms], dtype=float)
        self.boxes = boxes
        self.bounded = np.array([g.bounded for g in geoms])
        self.ellipse = np.array([isinstance(g, EllipseGeometry) for g in geoms])
        #: a, b, cos, sin, tx, ty of the ellipses' canonical frames (NaN for other sites)
        self.ellipse_frames = tuple(np.array([getattr(g, k) if isinstance(g, EllipseGeometry) else np.nan
                                              for g in geoms]) for k in ("a", "b", "c", "s", "tx", "ty"))
        if self.all_circles:
            circle = [SiteKind.of(g.kind) is SiteKind.CIRCLE for g in geoms]
            self.C = np.array([[g.cx, g.cy] if c else [g.x0, g.y0] for g, c in zip(geoms, circle)])
            self.R = np.array([g.rho if c else 0.0 for g, c in zip(geoms, circle)])
        else:
            fin = np.where(np.isfinite(boxes), boxes, 0.0)
            self.C = np.column_stack([(fin[:, 0] + fin[:, 2]) / 2, (fin[:, 1] + fin[:, 3]) / 2])
            self.R = np.hypot(fin[:, 2] - fin[:, 0], fin[:, 3] - fin[:, 1]) / 2
        # the window holds the bounded sites and the features of the unbounded ones (a hyperbola's
        # centre and vertices, a parabola's vertex and focus): a point at a hyperbola's centre alone
        # would otherwise give a window of size 0, with no sample of the hyperbola in it
        feats = [_feature_box(g) for g in geoms if not g.bounded]
        b = np.vstack([boxes[self.bounded], *[np.array([f]) for f in feats if f is not None]]) \
            if (self.bounded.any() or any(f is not None for f in feats)) else np.zeros((1, 4))
        x0, y0, x1, y1 = b[:, 0].min(), b[:, 1].min(), b[:, 2].max(), b[:, 3].max()
        w = max(x1 - x0, y1 - y0, 1e-9 * (1 + abs(x0) + abs(y0)), 1.0 if not self.bounded.any() else 0.0)
        cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
        self.window = (cx - 1.5 * w, cy - 1.5 * w, cx + 1.5 * w, cy + 1.5 * w)
        self.scale = float(max(abs(cx), abs(cy)) + 2 * w)
        self.size = np.where(self.bounded, self.R, 0.25 * w)
        # "big" sites (checked one by one in emptiness tests): radius beyond 8x the 90th percentile
        pos = self.R[self.bounded & (self.R > 0)]
        big = self.R > 8 * (float(np.percentile(pos, 90)) if len(pos) else 0.0)
        self.big = np.nonzero(big | ~self.bounded)[0]
        small = np.nonzero(~(big | ~self.bounded))[0]
        self.small = small
        self.small_tree = cKDTree(self.C[small]) if len(small) else None
        self.small_rmax = float(self.R[small].max()) if len(small) else 0.0
        self._table = None

    # ---- distances, vectorised over (point, site) pairs
    def dist_grad(self, P, lab):
        """Float d(P[m], site lab[m]) and the unit gradient U (from the foot point to P)."""
        P = np.asarray(P, float)
        if self.all_circles:
            V = P - self.C[lab]
            n = np.hypot(V[:, 0], V[:, 1])
            with np.errstate(invalid="ignore", over="ignore"):        # far (inf) points: masked later
                D = np.where(n[:, None] > 0, V / np.where(n > 0, n, 1.0)[:, None], np.array([1.0, 0.0]))
            g = n - self.R[lab]
            return np.abs(g), np.where((g >= 0)[:, None], D, -D)
        d = np.empty(len(P))
        U = np.empty((len(P), 2))
        ell = self.ellipse[lab]
        if ell.any():              # all ellipses at once (vectorised over sites)
            r = np.nonzero(ell)[0]
            s = lab[r]
            F, U[r] = ellipse_foot_points(P[r], *(col[s] for col in self.ellipse_frames))
            d[r] = np.hypot(P[r, 0] - F[:, 0], P[r, 1] - F[:, 1])
        if not ell.all():
            r0 = np.nonzero(~ell)[0]
            for s, rows in site_groups(lab[r0]):
                rows = r0[rows]
                F, U[rows] = self.geoms[s].foot_points(P[rows])
                d[rows] = np.hypot(P[rows, 0] - F[:, 0], P[rows, 1] - F[:, 1])     # one foot-point solve
        return d, U

    def dist_bounds(self, P, lab):
        """Rigorous (lo, hi) of d(P[m], site lab[m])."""
        P = np.asarray(P, float)
        if self.all_circles:
            d, _ = self.dist_grad(P, lab)
            s = rounding_slack(np.abs(P).sum(axis=1) + np.abs(self.C[lab]).sum(axis=1) + self.R[lab])
            return np.maximum(d - s, 0.0), d + s
        table = self.site_table()
        if table is not None:                 # all (point, site) rows in one call
            V = table.evaluate(P, lab)
            return V.lo, V.hi
        lo = np.empty(len(P))
        hi = np.empty(len(P))
        for s, rows in site_groups(lab):
            lo[rows], hi[rows] = self.geoms[s].distance_bounds(P[rows])
        return lo, hi

    def site_table(self):
        """The sites as a :class:`runtime.voronoi.verify.site_table.SiteTable` (built on first
        use; None when a site is of a kind it does not hold): rigorous distance bounds of many
        (point, site) rows in one call, vectorised over the ellipses as well as the points (the
        bounds of the site geometries, which it defers to where its own are not tight)."""
        if self._table is None:
            from .verify.site_table import SiteTable
            try:
                self._table = SiteTable(self.geoms, self.scale)
            except ValueError:                # a kind the table does not hold
                self._table = False
        return self._table or None

    def nearest_sites(self, Q, reach, k: int = NEAREST):
        """The sites of :meth:`near_sites` found among the ``k`` small sites with the nearest
        centres (and every big site), in memory O(k) per query whatever the reach -- a candidate
        vertex far outside the sites may have a circle holding all of them.  Returns flat arrays
        (m, site) and ``complete[m]``: True when those are *all* the sites of :meth:`near_sites`
        for Q[m] (the k-th nearest centre is beyond reach[m] + the largest small radius, so no
        further small site's bounding disc meets the disc (Q[m], reach[m]))."""
        Q = np.asarray(Q, float).reshape(-1, 2)
        reach = np.asarray(reach, float)
        rows, cols = [], []
        complete = np.ones(len(Q), bool)
        if self.small_tree is not None and len(Q):
            kk = min(int(k), len(self.small))
            dd, jj = self.small_tree.query(Q, k=kk)
            dd, jj = dd.reshape(len(Q), kk), jj.reshape(len(Q), kk)
            r = reach + self.small_rmax
            complete = (kk == len(self.small)) | (dd[:, -1] > r)
            m, t = np.nonzero(dd <= r[:, None])
            rows.append(m)
            cols.append(self.small[jj[m, t]])
        big_rows, big_cols = self._near_big(Q, reach)
        rows += big_rows
        cols += big_cols
        if not rows:
            return np.zeros(0, int), np.zeros(0, int), complete
        return np.concatenate(rows), np.concatenate(cols), complete

    def _near_big(self, Q, reach):
        rows, cols = [], []
        for b in self.big:
            if self.bounded[b]:
                dd = np.hypot(Q[:, 0] - self.C[b, 0], Q[:, 1] - self.C[b, 1])
                m = np.nonzero(dd <= reach + self.R[b] + 1e-12 * self.scale)[0]
            else:
                m = np.arange(len(Q))
            rows.append(m)
            cols.append(np.full(len(m), b))
        return rows, cols

    def near_sites(self, Q, reach):
        """For each query point Q[m], the sites whose bounding disc meets the disc (Q[m], reach[m]):
        returns flat arrays (m, site)."""
        rows, cols = [], []
        if self.small_tree is not None and len(Q):
            lists = self.small_tree.query_ball_point(Q, reach + self.small_rmax)
            lens = np.fromiter((len(x) for x in lists), int, len(lists))
            if lens.sum():
                rows.append(np.repeat(np.arange(len(Q)), lens))
                cols.append(self.small[np.concatenate([np.asarray(x, int) for x in lists if len(x)])])
        big_rows, big_cols = self._near_big(Q, reach)
        rows += big_rows
        cols += big_cols
        if not rows:
            return np.zeros(0, int), np.zeros(0, int)
        return np.concatenate(rows), np.concatenate(cols)


def site_groups(lab):
    lab = np.asarray(lab)
    order = np.argsort(lab, kind="stable")
    sl = lab[order]
    cuts = np.nonzero(np.diff(sl))[0] + 1
    for part in np.split(order, cuts):
        if len(part):
            yield int(lab[part[0]]), part


def _feature_box(g):
    """A box around the features of an unbounded conic site: centre ± the semi-axes of a
    hyperbola, vertex ± 4p of a parabola (None when not known)."""
    tx, ty = getattr(g, "tx", None), getattr(g, "ty", None)
    if tx is None or not (np.isfinite(tx) and np.isfinite(ty)):
        return None
    size = max(float(getattr(g, "a", 0.0) or 0.0), float(getattr(g, "b", 0.0) or 0.0),
               4 * float(getattr(g, "p", 0.0) or 0.0))
    if not size > 0 or not np.isfinite(size):
        return None
    return (tx - size, ty - size, tx + size, ty + size)
