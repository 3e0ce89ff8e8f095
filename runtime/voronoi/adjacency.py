"""The adjacency of a diagram kept between local updates (thesis §1.2; used by
:mod:`runtime.voronoi.insertion`): per site its vertices and edges, per vertex its edges, the
sites' bounding discs with a k-d tree over their centres.  It **moves** from a diagram to the
diagram updated from it, so a chain of updates costs what changes; the first update of a diagram
builds it once (O(N)).

Public API: :class:`DynamicState`, :func:`dynamic_state`.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.spatial import cKDTree

from .conflict import LOCAL_KINDS, site_disc
from .conic_geometry import site_geometry

__all__ = ["DynamicState", "dynamic_state"]


class DynamicState:
    """Adjacency of a diagram of point, circle and ellipse sites: per site its vertex ids and edge
    ids, per vertex its edge ids, the sites' bounding discs (:func:`runtime.voronoi.conflict.site_disc`:
    float centres ``C`` and radii ``R``, a circle's own) with a k-d tree over the centres (sites
    added since it was built are scanned linearly until it is rebuilt); the proofs differ when an ellipse is
    among the sites (``ellipses`` counts them)."""

    def __init__(self, D):
        n = len(D.sites)
        # the construction's own geometries, when it has them in the user's frame (a far scene is
        # built in a translated frame: its geometries are not the sites')
        S = getattr(D.construction, "S", None)
        geoms = getattr(S, "geoms", None) if "frame" not in D.stats else None
        self.geoms = list(geoms) if geoms is not None and len(geoms) == n else [site_geometry(s) for s in D.sites]
        self.unsupported = next((g.kind for g in self.geoms if g.kind not in LOCAL_KINDS), None)
        self.ids_ok = all(v.id == t for t, v in enumerate(D.vertices)) and all(e.id == t for t, e in enumerate(D.edges))
        if self.unsupported:
            return
        discs = [site_disc(g) for g in self.geoms]
        self._n = n
        self._C = np.array([c for c, _ in discs], float).reshape(-1, 2)
        self._R = np.array([r for _, r in discs], float)
        self.ellipses = sum(g.kind == "ellipse" for g in self.geoms)
        self.site_v = [set() for _ in range(n)]
        self.site_e = [set() for _ in range(n)]
        self.v_e = [[] for _ in D.vertices]
        for v in D.vertices:
            for s in v.sites:
                self.site_v[s].add(v.id)
        self.closed = 0
        self.unbounded = {e.id for e in D.edges if None in e.ends}
        self.renumber = "shift"
        for e in D.edges:
            self.closed += bool(e.closed)
            for s in e.sites:
                self.site_e[s].add(e.id)
            for w in e.ends:
                if w is not None:
                    self.v_e[w].append(e.id)
        self._rebuild_tree()

    @property
    def C(self):
        """Centres of the sites' bounding discs, (N, 2): a view of a buffer with spare rows, so
        that adding a site costs O(1) amortised (no reallocation of N rows)."""
        return self._C[:self._n]

    @property
    def R(self):
        """Radii of the sites' bounding discs, (N,) (a view, as :attr:`C`)."""
        return self._R[:self._n]

    @property
    def where(self):
        """Tree slot of each site (-1: added since the k-d tree was built); a view as :attr:`C`."""
        return self._W[:self._n]

    @property
    def scale(self) -> float:
        """An upper bound of max |coordinate of a centre| + max radius + 1 over the current
        sites (kept up to date in O(1): it never decreases between rebuilds of the k-d tree, and
        every use of it in an update only widens a margin or declines a local update)."""
        return self.cmax + self.rmax + 1.0

    def _rebuild_tree(self):
        n = self._n
        self.tree = cKDTree(self.C, copy_data=True) if n else None   # C changes in place
        self.slot = np.arange(n)            # tree slot -> site index (-1: deleted)
        self._W = np.full(len(self._C), -1)  # site index -> tree slot (-1: added since)
        self._W[:n] = np.arange(n)
        self.extra: list[int] = []          # sites added since
        self.rmax = float(self.R.max()) if n else 0.0
        self.cmax = float(np.abs(self.C).max()) if n else 0.0

    def near(self, X, radius):
        """Site indices whose centre lies within ``radius`` of X (a superset is fine)."""
        out = []
        r = radius * (1 + 1e-12)
        if self.tree is not None:
            got = self.slot[np.asarray(self.tree.query_ball_point(X, r), dtype=int)]
            out = got[got >= 0].tolist()
        if self.extra:
            ex = np.asarray(self.extra, dtype=int)
            d = np.hypot(self.C[ex, 0] - X[0], self.C[ex, 1] - X[1])
            out += ex[d <= r].tolist()
        return sorted(set(out))

    def nearest(self, X, k):
        """The sites with the k centres nearest to X (ties broken arbitrarily; fewer when there
        are fewer sites): the k-d tree's k nearest live slots and the k nearest of the sites
        added since, merged."""
        cand = []
        m = len(self.slot)
        if self.tree is not None and m:
            kq = min(m, k + 8)
            while True:
                dist, idx = self.tree.query(X, k=kq)
                dist, idx = np.atleast_1d(dist), np.atleast_1d(idx)
                ok = (idx < m)
                live = ok.copy()
                live[ok] = self.slot[idx[ok]] >= 0
                if live.sum() >= k or kq >= m:
                    cand = [(float(d), int(self.slot[t])) for d, t in zip(dist[live], idx[live])]
                    break
                kq = min(m, 4 * kq)
        if self.extra:
            ex = np.asarray(self.extra, dtype=int)
            d = np.hypot(self.C[ex, 0] - X[0], self.C[ex, 1] - X[1])
            cand += list(zip(d.tolist(), ex.tolist()))
        cand.sort()
        return [t for _, t in cand[:k]]

    def add_site(self, site, g):
        self.geoms.append(g)
        c, r = site_disc(g)
        if self._n == len(self._C):               # grow the buffers geometrically
            m = max(16, 2 * self._n)
            C2, R2, W2 = np.empty((m, 2)), np.empty(m), np.empty(m, dtype=self._W.dtype)
            C2[:self._n], R2[:self._n], W2[:self._n] = self._C[:self._n], self._R[:self._n], self._W[:self._n]
            self._C, self._R, self._W = C2, R2, W2
        self._C[self._n] = c
        self._R[self._n] = r
        self._W[self._n] = -1
        self._n += 1
        self.ellipses += g.kind == "ellipse"
        self.rmax = max(self.rmax, float(r))
        self.cmax = max(self.cmax, abs(float(c[0])), abs(float(c[1])))
        self.site_v.append(set())
        self.site_e.append(set())
        self.extra.append(self._n - 1)
        if len(self.extra) > 64 + 2 * math.sqrt(self._n):
            self._rebuild_tree()

    def remove_site(self, i, renumber):
        """Drop site i: ``renumber="shift"`` (j > i becomes j − 1; O(N), as the relabelling of
        the parts) or ``"last"`` (site N − 1 becomes i; O(1) here but for the list of sites
        added since the k-d tree was built, at most 64 + 2√N)."""
        n = self._n
        self.ellipses -= self.geoms[i].kind == "ellipse"
        if self._W[i] >= 0:
            self.slot[self._W[i]] = -1
        if renumber == "last" and i != n - 1:
            last = n - 1
            self._C[i], self._R[i] = self._C[last], self._R[last]
            self.geoms[i] = self.geoms[last]
            self.site_v[i], self.site_e[i] = self.site_v[last], self.site_e[last]
            self._W[i] = self._W[last]
            if self._W[i] >= 0:
                self.slot[self._W[i]] = i
            self.extra = [i if k == last else k for k in self.extra if k != i]
            self.geoms.pop()
            self.site_v.pop()
            self.site_e.pop()
        else:
            self.slot[self.slot > i] -= 1
            self.extra = [k - (k > i) for k in self.extra if k != i]
            self._C[i:n - 1], self._R[i:n - 1] = self._C[i + 1:n], self._R[i + 1:n]
            self._W[i:n - 1] = self._W[i + 1:n]
            del self.geoms[i], self.site_v[i], self.site_e[i]
        self._n = n - 1



def dynamic_state(D):
    """The diagram's :class:`DynamicState`, built on first use; taken away from ``D``'s
    construction state (it moves to the updated diagram)."""
    st = D.construction
    dyn = getattr(st, "dynamic", None)
    if dyn is None or len(dyn.C if not dyn.unsupported else dyn.geoms) != len(D.sites):
        dyn = DynamicState(D)
    st.dynamic = None
    return dyn
