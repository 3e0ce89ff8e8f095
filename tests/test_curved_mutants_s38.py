"""Mutants of :mod:`curvedvoronoi.runtime.voronoi.verify.curved` (mutation sample seed 38).

The bisector of a circle nested in an ellipse is a closed curve around the circle (Anton's
thesis, ch. 4: a vertex-less edge, a whole component of the bisector).  A "closed" polyline of
two points is the segment between them traversed back and forth: it winds 0 times around the
circle and its middle is far from the bisector, since |d_i − d_j| is 2-Lipschitz, so a point x
is at least |d_i(x) − d_j(x)|/2 from the bisector.  Such an edge must be refused."""
import math
from fractions import Fraction as F

import numpy as np

from curvedvoronoi.runtime.predicates.circles import Circle
from curvedvoronoi.runtime.sites.conic import Conic
from curvedvoronoi.runtime.voronoi.construction import voronoi
from curvedvoronoi.runtime.voronoi.verify.certificate import verify

A, B = 6.0, 5.0                      # the ellipse x²/36 + y²/25 = 1
CX, CY, R = 0.5, 0.3, 1.0            # the circle inside it


def _dist_ellipse(x, y, n=200_000):
    """Distance from an inner point to the ellipse by dense sampling: the minimum over the samples
    is within half the largest sample spacing (2π·6/n) above the true distance."""
    t = np.linspace(0, 2 * math.pi, n, endpoint=False)
    d = np.hypot(A * np.cos(t) - x, B * np.sin(t) - y).min()
    return d, 2 * math.pi * A / n


def _diagram():
    return voronoi([Conic.ellipse(centre=(0, 0), axes=(6, 5), rotation=(1, 0)),
                    Circle.from_radius(F(1, 2), F(3, 10), 1)], certify=False)


def test_the_closed_edge_as_drawn_is_certified():
    D = _diagram()
    assert [e.closed for e in D.edges] == [True]
    assert verify(D).ok


def test_a_two_point_closed_polyline_is_refused():
    D = _diagram()
    e = D.edges[0]
    P = np.asarray(e.polyline, float).reshape(-1, 2)
    a, b = P[0], P[len(P) // 2]
    mid = 0.5 * (a + b)
    de, err = _dist_ellipse(*mid)
    dc = math.hypot(mid[0] - CX, mid[1] - CY) - R
    # the middle of the drawn segment is provably farther than the stated tolerance from the bisector
    assert (abs(de - dc) - err) / 2 > 10 * float(e.tolerance)
    e.polyline = [tuple(a), tuple(b)]
    assert not verify(D).ok


def test_the_document_check_refuses_a_loop_of_fewer_than_three_points():
    """A polyline of one or two points winds 0 times around the nested circle (thesis Prop. 1.2.1:
    the closed edge is a Jordan curve around it), whatever its points: the document check says so."""
    from curvedvoronoi.runtime.voronoi.verify.document import check_document
    from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry

    D = _diagram()
    e = D.edges[0]
    P = np.asarray(e.polyline, float).reshape(-1, 2)
    geoms = [site_geometry(s) for s in D.sites]
    for drawn in ([tuple(P[0])], [tuple(P[0]), tuple(P[len(P) // 2])]):
        e.polyline = drawn
        problems = []
        check_document(D, None, geoms, problems)
        assert any("winds 0 times" in str(p) for p in problems), problems
