"""The exact third-site decision of the circle route, :func:`circle_edge_clear`
(runtime/voronoi/verify/exact_edges.py), on edges whose ends it cannot use to decide the sign.

Both scenes put the edge of two circles on the line x = 0 (their bisector: equal radii), so
every fact below is checked by hand with d_i(0, y) = √(4 + y²) − 1 (circles of radius 1 at
(∓2, 0)) or √(100 + y²) − 5 (radius 5 at (∓10, 0)).

* **Both ends are vertices of (i, j, k).**  i, j of radius 5 at (∓10, 0) and the point
  k = (0, 3): |y − 3| < √(100 + y²) − 5 exactly for y ∈ (−9/4, 24), so the triple's vertices are
  (0, −9/4) and (0, 24) and k is strictly nearer on the whole open segment between them.  With
  k a site of both ends, d_k − d_i vanishes at both: no end tells the sign, and the edge must
  not be called clear.
* **A vertex of (i, j, k) at an end that k is not a site of** (four sites on one circle).  i, j
  of radius 1 at (∓2, 0), m = (0, −1), n = (0, 10) and k = (0, 1): the circle of radius 1 about
  the origin touches i, j, m and k, so the vertex u = (0, 0) of (i, j, m) is also the only vertex
  of (i, j, k) (for y < 1: 1 − y = √(4 + y²) − 1 ⟺ y = 0; for y > 1: y = √(4 + y²), none).  On the
  edge of i, j drawn from u up to the vertex of (i, j, n), k is strictly nearer just above u
  (at y = 1/2: 1/2 < √(17/4) − 1 ≈ 1.06).  The zero of d_k − d_i coincides with the end u, which
  k is not a site of: the routine cannot place it and must refuse.
"""
from __future__ import annotations

from fractions import Fraction

from curvedvoronoi.runtime.predicates.circles import Circle, Point, voronoi_vertices_circles
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify.exact_edges import circle_edge_clear


def _vertex_at(sites, x, y):
    tv = voronoi_vertices_circles(*sites)
    near = [z for z in tv.vertices if abs(float(z.x) - x) + abs(float(z.y) - y) < 1e-9]
    assert len(near) == 1, [(float(z.x), float(z.y)) for z in tv.vertices]
    return near[0]


def test_an_edge_between_the_two_vertices_of_its_third_site_is_not_clear():
    sites = [Circle(-10, 0, 25), Circle(10, 0, 25), Point(0, 3)]
    geoms = [site_geometry(s) for s in sites]
    lo, hi = _vertex_at(sites, 0, -2.25), _vertex_at(sites, 0, 24)
    # the fact the refusal rests on: k nearer at the middle point (0, 10) of the open segment
    # (d_k = 7 < √200 − 5 = d_i ⟺ 12² < 200)
    assert 12 ** 2 < 100 + 10 ** 2
    assert circle_edge_clear(geoms, 0, 1, 2, ((0, 1, 2), lo), ((0, 1, 2), hi)) is False


def test_a_zero_at_an_end_that_the_third_site_does_not_define_is_refused():
    i, j, m, n, k = Circle(-2, 0, 1), Circle(2, 0, 1), Point(0, -1), Point(0, 10), Point(0, 1)
    sites = [i, j, m, n, k]
    geoms = [site_geometry(s) for s in sites]
    u = _vertex_at([i, j, m], 0, 0)
    top = [z for z in voronoi_vertices_circles(i, j, n).vertices if float(z.y) > 0]
    assert len(top) == 1
    zs = voronoi_vertices_circles(i, j, k).vertices
    assert len(zs) == 1 and zs[0].x == 0 and zs[0].y == 0        # the vertex of (i, j, k) is u
    # k nearer just above u: at (0, 1/2), |1/2 − 1| = 1/2 < √(17/4) − 1 ⟺ (3/2)² < 17/4
    assert Fraction(3, 2) ** 2 < Fraction(17, 4)
    assert circle_edge_clear(geoms, 0, 1, 4, ((0, 1, 2), u), ((0, 1, 3), top[0])) is False
    # and the edge from u up to infinity (the branch parameter u of y = b·sinh u grows upwards:
    # e_x = (1, 0) from c_i to c_j, e_y = (0, 1))
    assert circle_edge_clear(geoms, 0, 1, 4, ((0, 1, 2), u), ("inf", 1)) is False
