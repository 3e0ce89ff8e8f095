"""Mutants of :mod:`curvedvoronoi.runtime.voronoi.verify.document` (mutation sample seed 38).

A certificate states that every polyline lies within its edge's stated ``tolerance`` of the true
bisector (Anton's thesis, ch. 5: a certified diagram is exact combinatorics plus an approximation
of known error).  A tolerance that is not a finite number >= 0 bounds nothing: +inf makes the
claim "within +inf of the bisector", true of every point of the plane, so a document stating it
must not be certified, whatever its polylines are."""
import math
from fractions import Fraction as F

import pytest

from curvedvoronoi.runtime.predicates.circles import Circle
from curvedvoronoi.runtime.voronoi.construction import voronoi
from curvedvoronoi.runtime.voronoi.verify.certificate import verify


def _three_circles():
    # pairwise disjoint circles with non-collinear centres: three bounded-tolerance edges
    return voronoi([Circle.from_radius(0, 0, 1), Circle.from_radius(10, 0, 2), Circle.from_radius(4, 8, F(1, 2))],
                   certify=False)


def test_the_diagram_with_its_own_finite_tolerances_is_certified():
    D = _three_circles()
    assert all(math.isfinite(float(e.tolerance)) and float(e.tolerance) >= 0 for e in D.edges)
    assert verify(D).ok


@pytest.mark.parametrize("bad", [math.inf, math.nan, -1.0])
def test_a_tolerance_that_bounds_nothing_is_refused(bad):
    D = _three_circles()
    D.edges[0].tolerance = bad
    cert = verify(D)
    assert not cert.ok
