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
* **The third site a site of the only vertex** (ε = 2⁻⁴⁰ configurations): the sign of
  d_k − d_i's derivative at that vertex decides the edge, and the true diagrams are certified.
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
    # the same edge with its ends listed the other way, and with i and j exchanged (the branch
    # parameter then runs downwards)
    assert circle_edge_clear(geoms, 0, 1, 2, ((0, 1, 2), hi), ((0, 1, 2), lo)) is False
    assert circle_edge_clear(geoms, 1, 0, 2, ((0, 1, 2), lo), ((0, 1, 2), hi)) is False
    assert circle_edge_clear(geoms, 1, 0, 2, ((0, 1, 2), hi), ((0, 1, 2), lo)) is False


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


EPS = Fraction(1, 2 ** 40)


def test_a_third_site_touching_the_only_vertex_is_decided_by_its_slope():
    """Points A = (0, 0), B = (2, 0) and the circle C of radius 1/4 centred (1, ε + 1/4), ε = 2⁻⁴⁰
    (its lowest point (1, ε)).  On x = 1 below C, d_C = ε − y and d_A = √(1 + y²), equal where
    (ε − y)² = 1 + y², at the single vertex V = (1, y₀), y₀ = (ε² − 1)/(2ε) ≈ −5.5·10¹¹; every edge
    is a ray from V.  C is a site of V, so no end tells its sign on the ray of A, B (d_C = d_A at
    V, and C is farther below V by less than 10⁻¹¹ over its first 10¹¹, far below the floats):
    the sign of the derivative at V decides it (and the other two rays likewise)."""
    import curvedvoronoi as cv

    sites = [cv.Circle(0, 0, 0), cv.Circle(2, 0, 0), cv.Circle(1, EPS + Fraction(1, 4), Fraction(1, 16))]
    y0 = (EPS * EPS - 1) / (2 * EPS)
    assert (EPS - y0) ** 2 == 1 + y0 * y0
    d = cv.voronoi(sites, progress=False)
    assert d.certified
    assert len(d.vertices) == 1 and abs(d.vertices[0].x - 1) < 1e-9 and abs(d.vertices[0].y / float(y0) - 1) < 1e-12
    assert sorted(tuple(sorted(e.sites)) for e in d.edges) == [(0, 1), (0, 2), (1, 2)]
    assert all(e.ends.count(None) == 1 for e in d.edges)


def test_a_far_vertex_of_two_circles_and_a_point_is_found_and_proved():
    """Circles of radius 1/4 centred (0, 0), (2, 0) and the point P = (1, ε − 1/4): on x = 1,
    d_A = √(1 + y²) − 1/4 and d_P = |y − ε + 1/4|.  Below P they meet where √(1 + y²) = ε − y, at
    y₁ = (ε² − 1)/(2ε) ≈ −5.5·10¹¹; above P where y + 1/2 − ε = √(1 + y²), at
    y₂ = (1 − (1/2 − ε)²)/(1 − 2ε) ≈ 3/4.  The diagram has both vertices, joined by the edge of the
    circles; the far one holds P by less than the floats resolve."""
    import curvedvoronoi as cv

    q = Fraction(1, 4)
    sites = [cv.Circle(0, 0, q * q), cv.Circle(2, 0, q * q), cv.Circle(1, EPS - q, 0)]
    y1 = (EPS * EPS - 1) / (2 * EPS)
    y2 = (1 - (Fraction(1, 2) - EPS) ** 2) / (1 - 2 * EPS)
    assert (EPS - y1) ** 2 == 1 + y1 * y1 and (y2 + Fraction(1, 2) - EPS) ** 2 == 1 + y2 * y2
    d = cv.voronoi(sites, progress=False)
    assert d.certified
    ys = sorted(v.y for v in d.vertices)
    assert len(ys) == 2 and abs(ys[0] / float(y1) - 1) < 1e-12 and abs(ys[1] - float(y2)) < 1e-9


def test_a_ray_from_the_only_vertex_into_the_third_site_is_refused():
    """The sites of the first ε-test above.  The ray of A, B from V downwards (the branch parameter
    s = (q − m)·rot90(B − A) = 2(y − 0) decreasing, σ = −1) is a true edge: C is farther there.
    Upwards from V (σ = +1) C is nearer: just above V, d_C − d_A < 0 (d_C = ε − y, d_A = √(1 + y²)
    and (ε − y)² < 1 + y² ⟺ y > y₀).  With A and B exchanged, s = −2y and the directions swap."""
    from curvedvoronoi.runtime.predicates.circles import Circle as C

    a, b, c = C(0, 0, 0), C(2, 0, 0), C(1, EPS + Fraction(1, 4), Fraction(1, 16))
    geoms = [site_geometry(s) for s in (a, b, c)]
    (v,) = voronoi_vertices_circles(a, b, c).vertices
    assert circle_edge_clear(geoms, 0, 1, 2, ((0, 1, 2), v), ("inf", -1)) is True
    assert circle_edge_clear(geoms, 0, 1, 2, ((0, 1, 2), v), ("inf", 1)) is False
    assert circle_edge_clear(geoms, 1, 0, 2, ("inf", 1), ((0, 1, 2), v)) is True
    assert circle_edge_clear(geoms, 1, 0, 2, ("inf", -1), ((0, 1, 2), v)) is False
