"""The pieces of the disc search tile the arc (runtime/voronoi/verify/arc_search.py).

The search proves d_k > d_i on a bisector arc piece by piece; the proof holds for the arc only if
the pieces cover it: the pieces made before the search (``_Curves.pieces``) must tile each job's
parameter interval [ua, ub] — consecutive, the first starting at ua, the last ending at ub, no gap
and no overlap, with equal floats at the joints — and every piece the search cuts must be tiled by
its children in the same way.  The scene needs several rounds of cutting: the points (∓10, 0) have
the line x = 0 as bisector (q(u) = (0, 10 sinh u)), and the circle of centre (12, 0) and radius
7/4 is farther than them on the arc y ∈ [−6, 6]: d_k − d_i = √(144 + y²) − √(100 + y²) − 7/4
= 44/(√(144 + y²) + √(100 + y²)) − 7/4 decreases in |y|, from 1/4 at y = 0 to
44/(√180 + √136) − 7/4 > 0.004 at y = ±6, so the pieces near the ends of the arc must be cut to a
radius of about a thousandth before the Lipschitz test decides them.
"""
from __future__ import annotations

import math

import numpy as np

from curvedvoronoi.runtime.predicates.circles import Circle, Point
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify import arc_search
from curvedvoronoi.runtime.voronoi.verify.arc_search import prove_arcs
from curvedvoronoi.runtime.voronoi.verify.edges import CircleTable, bisector


def _tiles(A, B, lo, hi) -> bool:
    """Whether the intervals [A_t, B_t] tile [lo, hi] exactly (sorted by A)."""
    order = np.argsort(A, kind="stable")
    A, B = np.asarray(A)[order], np.asarray(B)[order]
    return bool(len(A) and A[0] == lo and B[-1] == hi and np.all(B[:-1] == A[1:]) and np.all(A < B))


def _record(monkeypatch):
    """The pieces of every round: one list of (job, A, B) per call of ``_Curves.discs`` inside
    ``_search``, and the output of ``_Curves.pieces``."""
    rounds, made = [], []
    discs, pieces, search = arc_search._Curves.discs, arc_search._Curves.pieces, arc_search._search
    inside = [False]

    def rec_discs(self, job, A, B):
        if inside[0]:
            rounds.append((np.array(job), np.array(A), np.array(B)))
        return discs(self, job, A, B)

    def rec_pieces(self, init):
        out = pieces(self, init)
        made.append(tuple(np.array(x) for x in out))
        return out

    def rec_search(*args, **kw):
        inside[0] = True
        try:
            return search(*args, **kw)
        finally:
            inside[0] = False

    monkeypatch.setattr(arc_search._Curves, "discs", rec_discs)
    monkeypatch.setattr(arc_search._Curves, "pieces", rec_pieces)
    monkeypatch.setattr(arc_search, "_search", rec_search)
    return rounds, made


def test_the_pieces_tile_the_arc_in_every_round(monkeypatch):
    table = CircleTable([site_geometry(s) for s in (Point(-10, 0), Point(10, 0), Circle.from_radius(12, 0, "7/4"))])
    bis = bisector(table, 0, 1)
    assert bis.kind == "hyperbola" and bis.a == 0 and bis.b == 10
    for y in np.linspace(-6, 6, 1201):           # k is farther on the whole arc (module docstring)
        assert math.hypot(12, y) - 1.75 - math.hypot(10, y) > 0.004
    ua, ub = math.asinh(-0.6), math.asinh(0.6)
    rounds, made = _record(monkeypatch)
    (ok, detail), = prove_arcs(table, [(bis, ua, ub, ())])
    assert ok and detail is None
    (job, A, B), = made
    assert _tiles(A, B, ua, ub), "the pieces before the search do not tile the arc"
    assert len(rounds) >= 3, "the scene should need several rounds of cutting"
    for (_, A0, B0), (_, A1, B1) in zip(rounds, rounds[1:]):
        o = np.argsort(A0, kind="stable")
        A0, B0 = A0[o], B0[o]
        # every piece of the next round lies in one piece of this round, and the pieces that
        # were cut are tiled by their children
        parent = np.searchsorted(A0, A1, side="right") - 1
        assert np.all(parent >= 0) and np.all(A0[parent] <= A1) and np.all(B1 <= B0[parent])
        for p in np.unique(parent):
            kids = parent == p
            assert _tiles(A1[kids], B1[kids], A0[p], B0[p]), f"piece [{A0[p]}, {B0[p]}] is not tiled by its children"


def test_a_long_arc_is_tiled_by_the_pieces_made_before_the_search(monkeypatch):
    """The points (∓10, 0) and k = (38, 0): k is farther on the whole line x = 0
    (d_k − d_i = 1344/(√(1444 + y²) + √(100 + y²)) > 0); the arc y ∈ [−150, 150] given as one
    piece has a disc of radius 150 against d_i ≥ 10 at its mid point, so ``_Curves.pieces`` cuts it
    several times before the search."""
    table = CircleTable([site_geometry(s) for s in (Point(-10, 0), Point(10, 0), Point(38, 0))])
    bis = bisector(table, 0, 1)
    ua, ub = math.asinh(-15.0), math.asinh(15.0)
    rounds, made = _record(monkeypatch)
    (ok, detail), = prove_arcs(table, [(bis, ua, ub, ())], init=1)
    assert ok and detail is None
    (job, A, B), = made
    assert len(A) >= 8, "the arc should be cut before the search"
    assert _tiles(A, B, ua, ub), "the pieces before the search do not tile the arc"
