"""The Hausdorff bound of runtime/voronoi/verify/polyline_bound.py is sharp for a polyline whose
nodes lie off the arc along its normal (the feet are found, not the points of the same e_y
coordinate).

Sites: the circle of radius 9 about the origin and the point (11, 0).  Their bisector is the branch
|q| − 9 = |q − (11, 0)| of a hyperbola (foci 0 and (11, 0), a = 9/2, c = 11/2, b = √10), whose far
parts are slanted (asymptotes at atan(b/a) ≈ 35° from the foci axis).  Each node is a point q of
the branch (x solved by bisection on its line y = const, independently of the library's
parametrisation) moved by δ = 1/100 along the unit normal ∇F/|∇F|, F(q) = |q| − |q − (11, 0)| − 9:
its distance to the curve is δ up to O(δ² κ), and the nodes are dense (chord deviations far below
δ), so the Hausdorff distance between the polyline and the arc is δ to within a few per cent.  The
bound must hold (≥ 0.99 δ) and be sharp (≤ 1.2 δ): the point of the same e_y coordinate, the
starting guess of the foot, is about 1.7 δ away on these slanted parts, so the foot parameters must
be improved (Newton's steps toward the foot, which only make the bound sharp).
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from curvedvoronoi.runtime.predicates.circles import Circle, Point
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify.edges import CircleTable, bisector
from curvedvoronoi.runtime.voronoi.verify.polyline_bound import hausdorff_bound

DELTA = 0.01


def _branch_x(y: float) -> float:
    """x of the branch |q| − 9 = |q − (11, 0)| on the line y (F increases with x)."""
    def f(x):
        return math.hypot(x, y) - 9 - math.hypot(x - 11, y)
    lo, hi = -1e4, 1e4
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if f(mid) < 0 else (lo, mid)
    return 0.5 * (lo + hi)


@pytest.mark.parametrize("y0, y1", [(20, 40), (-40, -20)])
def test_the_bound_of_a_polyline_off_the_arc_along_its_normal_is_sharp(y0, y1):
    table = CircleTable([site_geometry(s) for s in (Circle.from_radius(0, 0, 9), Point(11, 0))])
    bis = bisector(table, 0, 1)
    assert bis.kind == "hyperbola" and bis.a == 4.5
    nodes = []
    for y in np.linspace(y0, y1, 41):
        q = np.array([_branch_x(y), y])
        g = q / np.hypot(*q) - (q - (11.0, 0.0)) / np.hypot(*(q - (11.0, 0.0)))
        nodes.append(q + DELTA * g / np.hypot(*g))
    bound, why = hausdorff_bound(bis, np.array(nodes))
    assert why is None
    assert 0.99 * DELTA <= bound <= 1.2 * DELTA
