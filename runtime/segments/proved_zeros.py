"""The proved zeros of the contact systems met by the rounds of the segment construction (thesis §1.2).

A round of :mod:`runtime.segments.construction` meets a candidate vertex for every sample
triangle with three labels: tens of thousands per round, most of them met in the round before.
A proved zero (x, y, r) of a triple's contact system (:func:`runtime.segments.vertices.prove_zero`)
and its emptiness verdict (:mod:`runtime.segments.emptiness`) depend on the sites only, not on
the samples, so they are kept across rounds, here as arrays: a candidate takes a known zero of its
triple within its reach of the seed (a sorted search on the triples' keys, vectorised over all
candidates), the verdicts of the zeros not decided yet are found together (the float filter on
all of them, the arb and exact tests one by one), and every empty zero is given its *vertex*: the
first empty zero with the same sites (the triple and the sites found exactly on the circle) at the
same position within 10⁻⁹ of the scale, with its counter-clockwise contact order
(:func:`runtime.segments.contact_order.contact_orders`, on arrays) and its
:class:`runtime.voronoi.structure.DiagramVertex`, made once.

Public API: :class:`ZeroTable`.
"""
from __future__ import annotations

import numpy as np

from ..voronoi.structure import DiagramVertex
from .contact_order import contact_orders
from .elementary import ElementarySites
from .emptiness import empty_by_filter, prove_empty

__all__ = ["ZeroTable"]

#: emptiness states of a zero: not decided yet, empty (a vertex), a site enters the circle, undecided
UNKNOWN, EMPTY, ENTERED, UNDECIDED = 0, 1, 2, 3


class ZeroTable:
    """Proved zeros by row: ``sols`` (:class:`runtime.segments.vertices.VertexSolution`),
    ``triples``, ``key`` (the triple's integer key), ``xy``, ``state`` (:data:`EMPTY`, ...),
    ``members`` and ``culprit`` (of :func:`runtime.segments.emptiness.prove_empty`), ``vertex``
    (the row of the zero's vertex, −1 unless empty) and ``diagram_vertex`` (by vertex row)."""

    def __init__(self, n_sites: int):
        self.n = int(n_sites) + 1            # one more: the ghost label of a flat scene
        self.sols: list = []
        self.triples: list = []
        self.row_of: dict = {}               # id(sol) -> row
        self.key = np.empty(0, np.int64)
        self.xy = np.empty((0, 2))
        self.state = np.empty(0, np.int8)
        self.vertex = np.empty(0, np.int64)
        self.members: list = []
        self.culprit: list = []
        self.diagram_vertex: dict = {}
        self._by_members: dict = {}
        self._order = None                   # rows sorted by key (stable), None after an addition

    def keys(self, T) -> np.ndarray:
        """The integer keys of the sorted triples ``T`` (rows)."""
        T = np.asarray(T, np.int64).reshape(-1, 3)
        return (T[:, 0] * self.n + T[:, 1]) * self.n + T[:, 2]

    def near(self, keys, seeds, reach) -> np.ndarray:
        """Per candidate (triple key, seed, reach): the first known zero of its triple (in the
        order they were added) within ``reach`` of the seed, else −1."""
        out = np.full(len(keys), -1, np.int64)
        if not len(self.key) or not len(keys):
            return out
        if self._order is None:
            self._order = np.argsort(self.key, kind="stable")
        order = self._order
        sk = self.key[order]
        lo = np.searchsorted(sk, keys, side="left")
        hi = np.searchsorted(sk, keys, side="right")
        for j in range(int((hi - lo).max())):
            has = (hi - lo > j) & (out < 0)
            if not has.any():
                break
            i = np.nonzero(has)[0]
            rows = order[lo[i] + j]
            d = np.hypot(*(self.xy[rows] - seeds[i]).T)
            ok = d <= reach[i]
            out[i[ok]] = rows[ok]
        return out

    def add_many(self, triples, sols) -> np.ndarray:
        """The rows of the proved zeros ``sols`` of ``triples`` (new rows for those not known),
        the arrays grown once."""
        rows = np.empty(len(sols), np.int64)
        new_t, new_xy = [], []
        for k, (triple, sol) in enumerate(zip(triples, sols)):
            row = self.row_of.get(id(sol))
            if row is None:
                row = self.row_of[id(sol)] = len(self.sols)
                self.sols.append(sol)
                self.triples.append(tuple(triple))
                self.members.append(tuple(triple))
                self.culprit.append(None)
                new_t.append(triple)
                new_xy.append((sol.x, sol.y))
            rows[k] = row
        if new_t:
            m = len(new_t)
            self.key = np.concatenate([self.key, self.keys(new_t)])
            self.xy = np.vstack([self.xy, np.array(new_xy, float).reshape(m, 2)])
            self.state = np.concatenate([self.state, np.zeros(m, np.int8)])
            self.vertex = np.concatenate([self.vertex, np.full(m, -1, np.int64)])
            self._order = None
        return rows

    def decide(self, E: ElementarySites, tree, lab, hmax: float, rows) -> None:
        """The emptiness verdicts of the zeros ``rows`` not decided yet: the float filter
        (:func:`runtime.segments.emptiness.empty_by_filter`) on all of them, then
        :func:`runtime.segments.emptiness.prove_empty` one by one; empty zeros get their vertex."""
        rows = np.unique(np.asarray(rows, np.int64))
        rows = rows[self.state[rows] == UNKNOWN]
        if not len(rows):
            return
        sols = self.sols
        passed = empty_by_filter(E, tree, lab, hmax, [(self.triples[r], sols[r]) for r in rows.tolist()])
        fresh = []
        for r in rows.tolist():
            sol = sols[r]
            verdict = passed.get(id(sol))
            if verdict is None:
                verdict = prove_empty(E, tree, lab, hmax, self.triples[r], sol)
            empty, members, culprit = verdict
            self.members[r], self.culprit[r] = tuple(members), culprit
            if empty:
                self.state[r] = EMPTY
                self.vertex[r] = v = self._vertex_row(r)
                if v == r:
                    fresh.append(r)
            else:
                self.state[r] = ENTERED if empty is False else UNDECIDED
        # the new vertices' contact orders, on arrays at once
        orders = contact_orders(E, [self.members[r] for r in fresh], self.xy[np.array(fresh, np.int64)])
        for r, order in zip(fresh, orders):
            sol = sols[r]
            self.diagram_vertex[r] = DiagramVertex(-1, order, sol.x, sol.y, sol.r, True)

    def _vertex_row(self, r: int) -> int:
        """The row of the vertex of empty zero r: the first empty zero with its sites at its
        position (within 10⁻⁹ of the scale), r itself when it is new."""
        sol = self.sols[r]
        key = tuple(sorted(self.members[r]))
        tol = 1e-9 * (1.0 + abs(sol.x) + abs(sol.y) + sol.r)
        for v in self._by_members.get(key, ()):
            o = self.sols[v]
            if abs(o.x - sol.x) <= tol and abs(o.y - sol.y) <= tol:
                return v
        self._by_members.setdefault(key, []).append(r)
        return r
