"""The stitch of tiles (runtime/voronoi/stitch.py) when two tiles report one vertex at slightly
different float positions (a far vertex is ill-conditioned: on 2·10⁵ random circles two copies of a
vertex 2.9·10⁵ from the sites differed by 6.7·10⁻⁵, within the merge tolerance): the merged vertex
keeps one position, and every edge that ends there must start or end exactly at it, with a
tolerance that still covers the arc its tile proved near its old polyline."""
from __future__ import annotations

import math

import numpy as np

from curvedvoronoi.runtime.predicates.circles import Point
from curvedvoronoi.runtime.voronoi.stitch import stitch


def _seg_dist(p, a, b):
    a, b, p = np.asarray(a, float), np.asarray(b, float), np.asarray(p, float)
    t = np.clip(np.dot(p - a, b - a) / max(np.dot(b - a, b - a), 1e-300), 0, 1)
    return float(np.hypot(*(p - (a + t * (b - a)))))


def _reports(delta):
    v0, v1 = (10.0, 5.0), (10.0 + delta, 5.0 - 0.5 * delta)
    tri = (0, 1, 2)
    rep0 = {"tile": 0, "vertices": [(tri, *v0, 3.0, True)],
            "edges": [((0, 1), ((tri, *v0), None), np.array([v0, (10.0, 100.0)]), 0.01, True)]}
    rep1 = {"tile": 1, "vertices": [(tri, *v1, 3.0, True)],
            "edges": [((0, 2), ((tri, *v1), None), np.array([v1, (0.0, -50.0)]), 0.02, True),
                      ((1, 2), (None, (tri, *v1)), np.array([(40.0, 0.0), (20.0, 1.0), v1]), 0.0, True)]}
    return [rep0, rep1], v0, v1


def test_edges_end_exactly_at_the_merged_vertex_with_the_move_in_their_tolerance():
    delta = 3e-8
    reps, v0, v1 = _reports(delta)
    D, info = stitch([Point(0, 0), Point(1, 0), Point(0, 1)], reps, scale=1.0)
    assert info["vertex_copies_merged"] == 1 and len(D.vertices) == 1
    v = D.vertices[0]
    assert (v.x, v.y) == v0
    old = {(0, 1): reps[0]["edges"][0], (0, 2): reps[1]["edges"][0], (1, 2): reps[1]["edges"][1]}
    for e in D.edges:
        P = np.asarray(e.polyline, float)
        k = 0 if e.ends[0] == 0 else len(P) - 1
        assert tuple(P[k]) == (v.x, v.y)                    # exactly at the vertex
        _, _, P_old, tol_old, _ = old[tuple(e.sites)]
        move = math.hypot(*(np.asarray(P_old[k]) - np.asarray(v0)))
        assert e.tolerance >= tol_old + move
        # every point of the old polyline lies within the move of the new one
        for s in np.linspace(0, 1, 101):
            for a, b in zip(P_old[:-1], P_old[1:]):
                q = a + s * (b - a)
                d = min(_seg_dist(q, c, dd) for c, dd in zip(P[:-1], P[1:]))
                assert d <= e.tolerance - tol_old + 1e-12       # this test's own rounding
    first = next(e for e in D.edges if tuple(e.sites) == (0, 1))
    assert first.tolerance == 0.01                          # the copy kept: nothing moved


def test_a_copy_beyond_the_merge_tolerance_is_another_vertex():
    reps, _, _ = _reports(1e-3)
    D, info = stitch([Point(0, 0), Point(1, 0), Point(0, 1)], reps, scale=1.0)
    assert info["vertex_copies_merged"] == 0 and len(D.vertices) == 2
    assert all(e.tolerance in (0.01, 0.02, 0.0) for e in D.edges)
