"""Which site is nearest, and how far: proved nearest-site queries on the sites of a diagram.

Thesis §1.1 opens with the proximity query ("which site is nearest to q?"); issue 35 asks for it
vectorised and **proved**.  Every distance here comes from the one site-geometry kernel
(:mod:`runtime.voronoi.geometry`, :mod:`runtime.voronoi.conic_geometry`: ``distance`` in floats,
``distance_bounds`` rigorous, rounding accounted for).  Point and circle sites are evaluated for
many (point, site) pairs at once by giving one :class:`~runtime.voronoi.geometry.CircleGeometry`
arrays of centres and radii (its formulas are elementwise numpy; a point is a circle of radius 0,
with the same rounding allowance as :class:`~runtime.voronoi.geometry.PointGeometry`); conic sites
call their own geometry, grouped by site; segment sites (open interiors, thesis §2.2) the
distance of :mod:`runtime.segments.distance` (:class:`SegmentGeometry`); elliptic arcs their
pieces' (:class:`~runtime.segments.geometry.EllipticArcGeometry`).

:meth:`SiteIndex.nearest` (one round per query point, vectorised over the points):

1. **candidates**: the K nearest centres of the bounding discs of the "small" sites (a
   ``scipy.spatial.cKDTree``), plus every "big" site (unbounded conics, and discs much larger than
   the others, e.g. a circle holding many nested sites);
2. **evaluation**: rigorous bounds lo ≤ d(q, S) ≤ hi on every candidate; the candidate c with the
   smallest hi is the answer if hi_c < lo_j for every other candidate j;
3. **pruning, rigorously**: a small site j outside the K nearest centres lies in its disc
   (C_j, R_j) with |q − C_j| ≥ r_K (the K-th centre distance), so d(q, S_j) ≥ r_K − R_max;
   when r_K − R_max (minus rounding) does not exceed hi_c the point is retried with 4K
   candidates (up to all sites);
4. **ties**: the sites whose lower bound does not clear hi_c are decided in exact arithmetic for
   points and circles (the query float is an exact rational q; d(q, S)² = D + r² − 2·√(D·r²) with
   D = |q − c|², compared by an exact zero test and ball arithmetic otherwise), conics by the
   ball enclosure of :func:`runtime.sites.distance_ball.distance_ball` at rising precision.  A
   unique minimum makes the row proved; several sites at exactly equal distance are reported as
   an **exact tie**; what cannot be separated (equal distances to conics) is an undecided tie.
   Segments and circular arcs are decided exactly too: the squared distance to a closed segment
   is rational (the clamped rational foot parameter), and the distance to a closed arc of centre
   c and radius ρ is |‖q − c‖ − ρ| when the direction q − c lies in the arc's angular range (an
   exact orientation test), so d² = D + ρ² − 2·√(D·ρ²) as for a circle, else the distance to the
   nearer end (rational d²).  A segment's or arc's interior tied with its own endpoint gives way
   to the endpoint (the diagram's convention, :mod:`runtime.sites.segment`); an elliptic arc's
   piece too, where its nearest point is proved to be that end.  (:mod:`runtime.voronoi.exact_ties`.)
   A tied row never has a guessed winner: ``index`` is −1 there.

Public API: :class:`SiteIndex`, :class:`NearestResult`, :func:`site_index`, :func:`query_geometry`,
:class:`SegmentGeometry`.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
from scipy.spatial import cKDTree

from ..segments.geometry import ArcGeometry, EllipticArcGeometry, SegmentGeometry
from ..sites.arc import Arc
from ..sites.elliptic_arc import EllipticArc
from ..sites.segment import Segment
from .conic_geometry import site_geometry
from .exact_ties import decide_nearest
from .geometry import CircleGeometry, rounding_slack

__all__ = ["NearestResult", "SegmentGeometry", "ArcGeometry", "SiteIndex", "query_geometry", "site_index"]

#: rows per vectorised batch (bounds the temporaries of :meth:`SiteIndex.distance`)
_CHUNK_PAIRS = 1 << 22


class NearestResult(NamedTuple):
    """The answer of :meth:`Diagram.nearest` for n query points.

    index : (n,) int
        The nearest site; −1 where two or more sites tie (see ``ties``).
    distance : (n,) float
        The distance to the nearest site(s) (float evaluation of the site geometry).
    proved : (n,) bool
        True where ``index`` is proved to be the unique nearest site (rigorous bounds, or the
        exact decision of a near tie).
    ties : dict[int, tuple[int, ...]]
        For each tied row: the sites that could not be separated (sorted).
    exact : (n,) bool
        True where the tie of that row is proved exact (equal distances, decided in rational
        arithmetic for points and circles); False at a tied row means *undecided*.
    """

    index: np.ndarray
    distance: np.ndarray
    proved: np.ndarray
    ties: dict
    exact: np.ndarray


class SiteIndex:
    """The sites of a diagram prepared for distance queries: geometries, bounding discs, a k-d
    tree on the centres of the small ones."""

    def __init__(self, sites):
        self.sites = list(sites)
        self.geoms = [query_geometry(s) for s in self.sites]
        m = self.m = len(self.geoms)
        kinds = [g.kind for g in self.geoms]
        self.circular = np.array([k in ("point", "circle") for k in kinds], bool)
        self.bounded = np.array([g.bounded for g in self.geoms], bool)
        # float centre and radius: the circles' own, a bounding disc of the box for ellipses
        C, R = np.zeros((m, 2)), np.zeros(m)
        for i, g in enumerate(self.geoms):
            if g.kind == "point":
                C[i] = (g.x0, g.y0)
            elif g.kind == "circle":
                C[i], R[i] = (g.cx, g.cy), g.rho
            elif g.bounded:
                x0, y0, x1, y1 = g.bounding_box()
                C[i], R[i] = ((x0 + x1) / 2, (y0 + y1) / 2), np.hypot(x1 - x0, y1 - y0) / 2
        self.C, self.R = C, R
        # the disc (C, Rin) holds the exact site: float centre and radius off by a few ulps
        self.Rin = R + rounding_slack(np.abs(C).sum(axis=1) + R, 16)
        pos = R[self.bounded & (R > 0)]
        big = ~self.bounded | (R > 8 * (float(np.percentile(pos, 90)) if len(pos) else 0.0))
        self.big = np.nonzero(big)[0]
        self.small = np.nonzero(~big)[0]
        self.tree = cKDTree(C[self.small]) if len(self.small) else None
        self.rmax = float(self.Rin[self.small].max()) if len(self.small) else 0.0
        self.cmax = float(np.abs(C[self.small]).max()) if len(self.small) else 0.0

    # ------------------------------------------------------------------ distances
    def _circles(self, cols, column: bool = False) -> CircleGeometry:
        """One CircleGeometry whose centre and radius are arrays (one entry per pair, or a
        column vector to broadcast against every query point)."""
        g = CircleGeometry.__new__(CircleGeometry)
        shape = (-1, 1) if column else (-1,)
        g.exact = None
        g.cx, g.cy = self.C[cols, 0].reshape(shape), self.C[cols, 1].reshape(shape)
        g.rho = self.R[cols].reshape(shape)
        return g

    def pair_distance(self, Q, cols, bounds: bool):
        """d(Q[t], site cols[t]) for pairs: floats, or rigorous (lo, hi) when ``bounds``."""
        Q = np.asarray(Q, float)
        cols = np.asarray(cols, int)
        circ = self.circular[cols]
        if circ.all():
            g = self._circles(cols)
            return g.distance_bounds(Q) if bounds else g.distance(Q)
        outs = [np.empty(len(cols)) for _ in range(2 if bounds else 1)]
        if circ.any():
            r = np.nonzero(circ)[0]
            res = self._circles(cols[r]).distance_bounds(Q[r]) if bounds else (self._circles(cols[r]).distance(Q[r]),)
            for o, v in zip(outs, res):
                o[r] = v
        r0 = np.nonzero(~circ)[0]
        order = np.argsort(cols[r0], kind="stable")
        r0 = r0[order]
        cuts = np.nonzero(np.diff(cols[r0]))[0] + 1
        for part in np.split(r0, cuts):
            if len(part):
                g = self.geoms[cols[part[0]]]
                res = g.distance_bounds(Q[part]) if bounds else (g.distance(Q[part]),)
                for o, v in zip(outs, res):
                    o[part] = v
        return tuple(outs) if bounds else outs[0]

    def distance(self, P, sites=None, *, bounds: bool = False):
        """(n, m) float distances from the rows of P to the sites (or the listed ``sites``); with
        ``bounds`` a pair (lo, hi) of such arrays, rigorous.  Memory: the result is n·m·8 bytes
        (twice with ``bounds``); point and circle sites are evaluated in row blocks of about
        4·10⁶ pairs, so the temporaries stay near 100 MB whatever n·m."""
        P = _points(P)
        cols = np.arange(self.m) if sites is None else np.asarray(sites, int).reshape(-1)
        n = len(P)
        outs = [np.empty((n, len(cols))) for _ in range(2 if bounds else 1)]
        circ = np.nonzero(self.circular[cols])[0]
        if len(circ):
            g = self._circles(cols[circ], column=True)
            step = max(1, _CHUNK_PAIRS // len(circ))
            for a in range(0, n, step):
                res = g.distance_bounds(P[a:a + step]) if bounds else (g.distance(P[a:a + step]),)
                for o, v in zip(outs, res):
                    o[a:a + step, circ] = np.asarray(v).T
        for j in np.nonzero(~self.circular[cols])[0]:
            g = self.geoms[cols[j]]
            res = g.distance_bounds(P) if bounds else (g.distance(P),)
            for o, v in zip(outs, res):
                o[:, j] = v
        return tuple(outs) if bounds else outs[0]

    # ------------------------------------------------------------------ nearest
    def nearest(self, P, *, prove: bool = True, k: int = 8) -> NearestResult:
        """The nearest site of each row of P (see the module docstring).  Rows are processed in
        blocks so that the (row, candidate) pairs of one block stay near 4·10⁶."""
        P = _points(P)
        step = max(1, _CHUNK_PAIRS // (k + len(self.big) + 1))
        if len(P) <= step:
            return self._nearest(P, prove, k)
        parts = [self._nearest(P[a:a + step], prove, k) for a in range(0, len(P), step)]
        ties = {a * step + r: T for a, part in enumerate(parts) for r, T in part.ties.items()}
        return NearestResult(*(np.concatenate([getattr(p, f) for p in parts]) for f in ("index", "distance", "proved")),
                             ties, np.concatenate([p.exact for p in parts]))

    def _nearest(self, P, prove: bool, k: int) -> NearestResult:
        n = len(P)
        index = np.full(n, -1, dtype=np.int64)
        dist = np.full(n, np.nan)
        proved = np.zeros(n, bool)
        exact = np.zeros(n, bool)
        ties: dict[int, tuple[int, ...]] = {}
        if self.m == 0 or n == 0:
            return NearestResult(index, dist, proved, ties, exact)
        todo = np.arange(n)
        K = min(k, len(self.small))
        while len(todo):
            done, best, cands, clash = self._round(P[todo], K, prove)
            rows = todo[done]
            index[rows] = best[done]
            if prove:
                c, cd, bd = clash[done], cands[done], best[done]
                tied = c.any(axis=1)
                proved[rows] = ~tied
                for t in np.nonzero(tied)[0]:
                    self._tie(P, int(rows[t]), np.unique(np.append(cd[t][c[t]], bd[t])),
                              index, proved, ties, exact)
            todo = todo[~done]
            K = min(4 * K, len(self.small))
        ok = index >= 0
        dist[ok] = self.pair_distance(P[ok], index[ok], False)
        for r, T in ties.items():
            dist[r] = float(self.pair_distance(P[[r] * len(T)], np.array(T), False).min())
        return NearestResult(index, dist, proved, ties, exact)

    def _round(self, Q, K, prove):
        """One candidate round over the rows of Q: (done, best, cands, clash).  ``done``: the
        candidates provably hold the nearest site; ``clash[t, u]`` (with ``prove``): candidate
        ``cands[t, u]`` is not the best and its lower bound does not clear the best's upper."""
        nq = len(Q)
        blocks, rK = [], None
        ns = len(self.small)
        if ns:
            if K >= ns:
                blocks.append(np.broadcast_to(self.small, (nq, ns)))
            else:
                dd, ii = self.tree.query(Q, k=K)
                blocks.append(self.small[ii.reshape(nq, K)])
                rK = dd.reshape(nq, K)[:, -1]
        if len(self.big):
            blocks.append(np.broadcast_to(self.big, (nq, len(self.big))))
        cands = np.hstack(blocks) if len(blocks) > 1 else np.asarray(blocks[0])
        w = cands.shape[1]
        rows = np.repeat(np.arange(nq), w)
        if prove:
            lo, hi = self.pair_distance(Q[rows], cands.reshape(-1), True)
            lo, hi = lo.reshape(nq, w), hi.reshape(nq, w)
        else:
            lo = hi = self.pair_distance(Q[rows], cands.reshape(-1), False).reshape(nq, w)
        ar = np.arange(nq)
        b = np.argmin(hi, axis=1)
        hb = hi[ar, b]
        if rK is None:
            done = np.ones(nq, bool)
        else:       # every small site beyond the K-th centre is at least r_K − R_max away
            excl = rK - self.rmax - rounding_slack(np.abs(Q).sum(axis=1) + rK + self.cmax, 16)
            done = excl > hb
        clash = None
        if prove:
            clash = lo <= hb[:, None]
            clash[ar, b] = False
        return done, cands[ar, b], cands, clash

    def _tie(self, P, r, T, index, proved, ties, exact):
        """Decide the near tie of row r among the sites T; writes the row's answer."""
        win, is_exact = decide_nearest(self.geoms, [int(t) for t in T], float(P[r, 0]), float(P[r, 1]))
        if len(win) == 1:
            index[r], proved[r] = win[0], True
        else:
            index[r], proved[r] = -1, False
            ties[r] = tuple(sorted(win))
            exact[r] = is_exact


def query_geometry(site):
    """The geometry of a site for queries: :func:`runtime.voronoi.conic_geometry.site_geometry`
    (points, circles, conics), :class:`SegmentGeometry`, :class:`ArcGeometry` or
    :class:`EllipticArcGeometry`."""
    if isinstance(site, Segment):
        return SegmentGeometry(site)
    if isinstance(site, Arc):
        return ArcGeometry(site)
    if isinstance(site, EllipticArc):
        return EllipticArcGeometry(site)
    try:
        return site_geometry(site)
    except TypeError:
        raise TypeError(f"nearest-site queries take points, circles, conics, segments, arcs and elliptic arcs, "
                        f"not {site!r}") from None


def _points(P) -> np.ndarray:
    P = np.asarray(P, dtype=float)
    if P.ndim == 1 and P.shape == (2,):
        P = P.reshape(1, 2)
    if P.ndim != 2 or P.shape[1] != 2:
        raise ValueError(f"expected an (n, 2) array of query points, got shape {P.shape}")
    if not np.isfinite(P).all():
        raise ValueError("query points must be finite")
    return P


def site_index(diagram) -> SiteIndex:
    """The :class:`SiteIndex` of a diagram's sites, built once and kept on the diagram (rebuilt
    if the list of sites changes)."""
    store = getattr(diagram, "__dict__", None)
    if store is None:
        return SiteIndex(diagram.sites)
    key = tuple(map(id, diagram.sites))
    cached = store.get("_site_index")
    if cached is None or cached[0] != key:
        cached = (key, SiteIndex(diagram.sites))
        store["_site_index"] = cached
    return cached[1]
