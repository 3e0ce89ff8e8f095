"""The construction's degree check (runtime/segments/construction._degree_checks): a vertex whose
walks do not give one edge per pair of cyclically consecutive sites is named with the edges it
has and those it should have, its sites are refined, and complete vertices are left alone; the
walks' ends arrive in any order (here interleaved between vertices)."""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from curvedvoronoi.runtime.predicates.circles import Point
from curvedvoronoi.runtime.segments.construction import _degree_checks, _Refine
from curvedvoronoi.runtime.segments.elementary import decompose


def test_incomplete_vertices_are_named_with_their_edges():
    E = decompose([Point(x, y) for x, y in ((0, 0), (4, 0), (0, 4), (4, 4), (9, 1), (7, 7))])
    base = len(E) + 1
    V = [SimpleNamespace(sites=[0, 1, 2], x=1.0, y=1.0), SimpleNamespace(sites=[1, 3, 2], x=3.0, y=3.0),
         SimpleNamespace(sites=[3, 4, 5], x=7.0, y=4.0), SimpleNamespace(sites=[1, 4, 3], x=6.0, y=2.0)]
    # (vertex, pair) ends of walks: vertex 0 lacks (0, 2); vertex 2 has (3, 4) twice and no (4, 5);
    # vertices 1 and 3 are complete; listed interleaved
    ends = [(1, (1, 3)), (0, (0, 1)), (2, (3, 4)), (3, (1, 4)), (1, (2, 3)), (0, (1, 2)), (2, (3, 5)),
            (3, (3, 4)), (1, (1, 2)), (2, (3, 4)), (3, (1, 3))]
    hv = np.array([v for v, _p in ends], np.int64)
    hk = np.array([min(p) * base + max(p) for _v, p in ends], np.int64)
    refine, graded, problems = _Refine(), {}, []
    _degree_checks(E, V, hv, hk, refine, graded, problems, {})
    assert problems == [
        "sites 0, 1, 2: the vertex at (1, 1) has incident edges [(0, 1), (1, 2)], expected [(0, 1), (0, 2), (1, 2)]",
        "sites 3, 4, 5: the vertex at (7, 4) has incident edges [(3, 4), (3, 4), (3, 5)], expected "
        "[(3, 4), (3, 5), (4, 5)]"]
    assert set(refine) == {0, 1, 2, 3, 4, 5} and not graded


def test_a_single_incomplete_vertex_is_named():
    E = decompose([Point(x, y) for x, y in ((0, 0), (4, 0), (0, 4), (4, 4))])
    base = len(E) + 1
    V = [SimpleNamespace(sites=[0, 1, 2], x=1.0, y=1.0), SimpleNamespace(sites=[1, 3, 2], x=3.0, y=3.0)]
    ends = [(1, (1, 3)), (0, (0, 1)), (1, (2, 3)), (0, (0, 2)), (1, (1, 2))]     # vertex 0 lacks (1, 2)
    hv = np.array([v for v, _p in ends], np.int64)
    hk = np.array([min(p) * base + max(p) for _v, p in ends], np.int64)
    refine, problems = _Refine(), []
    _degree_checks(E, V, hv, hk, refine, {}, problems, {})
    assert problems == ["sites 0, 1, 2: the vertex at (1, 1) has incident edges [(0, 1), (0, 2)], expected "
                        "[(0, 1), (0, 2), (1, 2)]"]
    assert set(refine) == {0, 1, 2}
