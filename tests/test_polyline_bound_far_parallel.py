"""The Hausdorff bound of runtime/voronoi/verify/polyline_bound.py holds for a polyline far from
its arc, where the rounding of the distances (relative to them) exceeds the curve's absolute
rounding terms.

Sites: the points (0, 0) and (2, 2); their bisector is the line x + y = 2.  The polyline is the
one segment from P_0 = (1 + K − 3, 1 + K + 3) to P_1 = (1 + K + 3, 1 + K − 3) (doubles for the K
below): it lies on the parallel line x + y = 2 + 2K, and the feet of its ends on the bisector are
(−2, 4) and (4, −2), so the arc it follows is the segment between them, its translate by
−(K, K).  The Hausdorff distance between the two is exactly |(K, K)| = √2·K, irrational, and the
bound must be at least that: checked exactly as bound² ≥ 2K² in rationals.  The curve's rounding
terms are of the order 1e-13 (the scene's size is 2), far below the rounding of distances of
order K (1e-16·K); the bound is also sharp, within a relative 1e-9 of √2·K.
"""
from __future__ import annotations

import math
from fractions import Fraction

import pytest

from curvedvoronoi.runtime.predicates.circles import Point
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify.edges import CircleTable, bisector
from curvedvoronoi.runtime.voronoi.verify.polyline_bound import hausdorff_bound, hausdorff_bounds


@pytest.fixture(scope="module")
def line():
    table = CircleTable([site_geometry(s) for s in (Point(0, 0), Point(2, 2))])
    bis = bisector(table, 0, 1)
    assert bis.kind == "hyperbola" and bis.a == 0           # the line x + y = 2
    return bis


KS = [10.0 ** 6, 10.0 ** 7, 50000006.0, 50000011.0, 50000019.0, 10.0 ** 9, 10.0 ** 12]


def _parallel(K):
    return [[1 + K - 3, 1 + K + 3], [1 + K + 3, 1 + K - 3]]


@pytest.mark.parametrize("K", KS)
def test_the_bound_of_a_far_parallel_segment_is_at_least_its_distance(line, K):
    bound, why = hausdorff_bound(line, _parallel(K))
    assert why is None
    assert Fraction(bound) ** 2 >= 2 * Fraction(K) ** 2
    assert bound <= math.sqrt(2) * K * (1 + 1e-9)


def test_many_far_segments_at_once(line):
    bounds = hausdorff_bounds([line] * len(KS), [_parallel(K) for K in KS])
    for b, K in zip(bounds, KS):
        assert Fraction(float(b)) ** 2 >= 2 * Fraction(K) ** 2
