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
        self.C = np.array([c for c, _ in discs], float).reshape(-1, 2)
        self.R = np.array([r for _, r in discs], float)
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

    def _rebuild_tree(self):
        n = len(self.C)
        self.tree = cKDTree(self.C) if n else None
        self.slot = np.arange(n)            # tree slot -> site index (-1: deleted)
        self.extra: list[int] = []          # sites added since
        self.rmax = float(self.R.max()) if n else 0.0

    def near(self, X, radius):
        """Site indices whose centre lies within ``radius`` of X (a superset is fine)."""
        out = []
        if self.tree is not None:
            got = self.slot[np.asarray(self.tree.query_ball_point(X, radius * (1 + 1e-12)), dtype=int)]
            out = got[got >= 0].tolist()
        for k in self.extra:
            if math.hypot(self.C[k, 0] - X[0], self.C[k, 1] - X[1]) <= radius * (1 + 1e-12):
                out.append(k)
        return sorted(set(out))

    def add_site(self, site, g):
        self.geoms.append(g)
        c, r = site_disc(g)
        self.C = np.vstack([self.C, c])
        self.R = np.append(self.R, r)
        self.ellipses += g.kind == "ellipse"
        self.rmax = max(self.rmax, float(self.R[-1]))
        self.site_v.append(set())
        self.site_e.append(set())
        self.extra.append(len(self.C) - 1)
        if len(self.extra) > 64 + 2 * math.sqrt(len(self.C)):
            self._rebuild_tree()

    def remove_site(self, i, renumber):
        """Drop site i: ``renumber="shift"`` (j > i becomes j − 1) or ``"last"`` (site N − 1
        becomes i)."""
        n = len(self.C)
        self.ellipses -= self.geoms[i].kind == "ellipse"
        if renumber == "last" and i != n - 1:
            last = n - 1
            self.C[i], self.R[i] = self.C[last], self.R[last]
            self.geoms[i] = self.geoms[last]
            self.site_v[i], self.site_e[i] = self.site_v[last], self.site_e[last]
            self.slot[self.slot == i] = -1
            self.slot[self.slot == last] = i
            self.extra = [i if k == last else k for k in self.extra if k != i]
            i = last
        else:
            self.slot[self.slot == i] = -1
            self.slot[self.slot > i] -= 1
            self.extra = [k - (k > i) for k in self.extra if k != i]
        self.C = np.delete(self.C, i, axis=0)
        self.R = np.delete(self.R, i)
        del self.geoms[i], self.site_v[i], self.site_e[i]


def dynamic_state(D):
    """The diagram's :class:`DynamicState`, built on first use; taken away from ``D``'s
    construction state (it moves to the updated diagram)."""
    st = D.construction
    dyn = getattr(st, "dynamic", None)
    if dyn is None or len(dyn.C if not dyn.unsupported else dyn.geoms) != len(D.sites):
        dyn = DynamicState(D)
    st.dynamic = None
    return dyn
