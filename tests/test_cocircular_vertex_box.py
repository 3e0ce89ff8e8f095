"""The box of a co-circular vertex proved exactly (runtime/voronoi/verify/exact_vertices.py,
thesis §3.1.3) must hold the exact vertex: the tower vertex is exact, but the box the edges
build on is its float conversion (x, y) with a half-width h, so h must cover that rounding.

The reference is a closed form: four points at rational positions c + (3/5, 4/5)·R rotated by
quarter turns lie on the circle of centre c and radius R, so c is their Voronoi vertex; with
c = (1/3, 1/7) no float equals c, and the box of half-width h about (x, y) must contain it
(exact rational comparison)."""
from __future__ import annotations

from fractions import Fraction as F

import pytest

from curvedvoronoi.runtime.predicates.circles import Point
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify.exact_vertices import cocircular_vertex
from curvedvoronoi.runtime.voronoi.verify.vertices import VertexInfo


class _Reported:
    """A reported vertex: id, sites, float position (the verifier reads only these)."""

    def __init__(self, x, y, sites):
        self.id, self.x, self.y, self.sites = 0, float(x), float(y), tuple(sites)


def _square_on_circle(c, R):
    """Four points c + R·u, u = (3/5, 4/5) and its quarter turns, counter-clockwise."""
    u = (F(3, 5), F(4, 5))
    out = []
    for _ in range(4):
        out.append(Point(c[0] + R * u[0], c[1] + R * u[1]))
        u = (-u[1], u[0])
    return out


@pytest.mark.parametrize("c, R", [((F(1, 3), F(1, 7)), F(1)), ((F(1000, 3), F(-2000, 7)), F(10, 3)),
                                  ((F(-1, 10), F(2, 3)), F(1, 1000))])
def test_the_box_of_a_cocircular_vertex_holds_the_exact_centre(c, R):
    pts = _square_on_circle(c, R)
    geoms = [site_geometry(p) for p in pts]
    problems = []
    info = cocircular_vertex(_Reported(c[0], c[1], range(4)), (0, 1, 2, 3), geoms, problems, VertexInfo)
    assert info is not None, problems
    # the radius is R exactly; the centre is not a float, so the box must have width
    assert F(info.x) != c[0] or F(info.y) != c[1]
    assert abs(F(info.x) - c[0]) <= F(info.h) and abs(F(info.y) - c[1]) <= F(info.h)
    assert abs(F(info.r) - R) <= F(info.h)
    # and h is a rounding allowance, not a search radius
    assert info.h < 1e-12 * (1 + abs(info.x) + abs(info.y) + info.r)
