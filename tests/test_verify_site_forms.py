"""The site forms :func:`curvedvoronoi.runtime.voronoi.verify.certificate.verify` reads.

``verify(diagram, sites)`` takes the true sites in the forms the construction takes: a pair
(x, y) is the point (x, y), a triple (x, y, 0) the same point, and the diagram's site list must
equal them exactly.  The diagram here is written down in closed form, not constructed: the Voronoi
diagram of the three points (0, 0), (4, 0), (0, 4) of a right triangle has one vertex, the
circumcentre, which for a right triangle is the midpoint (2, 2) of the hypotenuse (Thales), at
distance 2√2 from the three points, and three unbounded edges on the perpendicular bisectors
x = 2 (downwards, away from (0, 4)), y = 2 (to the left, away from (4, 0)) and y = x (up and
right, away from (0, 0)) (Aurenhammer & Klein, "Voronoi diagrams", §2: the edges of a vertex of
three points lie on the bisectors of the pairs, each ray leaving the third point's side).  Every
polyline point is exact in floats, so the diagram is exactly right and must be fully proved
whichever form the sites are given in."""
from __future__ import annotations

import math
from fractions import Fraction as F

import pytest

from curvedvoronoi.runtime.predicates.circles import Point
from curvedvoronoi.runtime.voronoi.verify.certificate import verify

L = 64.0          # the rays' polylines run this far out (exact floats on the bisectors)


def _right_triangle_document():
    return {
        "format": "curvedvoronoi.diagram/2",
        "sites": [{"point": ["0", "0"]}, {"point": ["4", "0"]}, {"point": ["0", "4"]}],
        "vertices": [{"id": 0, "sites": [0, 1, 2], "x": 2.0, "y": 2.0, "radius": 2 * math.sqrt(2),
                      "certified": False}],
        "edges": [
            {"id": 0, "sites": [0, 1], "ends": [0, None], "closed": False,
             "polyline": [[2.0, 2.0], [2.0, 0.0], [2.0, -L]], "tolerance": 1e-9, "certified": False},
            {"id": 1, "sites": [0, 2], "ends": [0, None], "closed": False,
             "polyline": [[2.0, 2.0], [0.0, 2.0], [-L, 2.0]], "tolerance": 1e-9, "certified": False},
            {"id": 2, "sites": [1, 2], "ends": [0, None], "closed": False,
             "polyline": [[2.0, 2.0], [4.0, 4.0], [L, L]], "tolerance": 1e-9, "certified": False},
        ],
    }


def test_the_closed_form_diagram_is_correct():
    # the oracle, exactly: the vertex is equidistant from the three points, each polyline point is
    # equidistant from its edge's two sites and not closer to the third
    P = [(F(0), F(0)), (F(4), F(0)), (F(0), F(4))]
    d2 = lambda q, p: (q[0] - p[0]) ** 2 + (q[1] - p[1]) ** 2
    doc = _right_triangle_document()
    v = (F(2), F(2))
    assert d2(v, P[0]) == d2(v, P[1]) == d2(v, P[2]) == 8
    for e in doc["edges"]:
        i, j = e["sites"]
        (k,) = {0, 1, 2} - {i, j}
        for x, y in e["polyline"]:
            q = (F(x), F(y))
            assert d2(q, P[i]) == d2(q, P[j]) <= d2(q, P[k])


@pytest.mark.parametrize("form", ["pairs", "lists", "triples with r = 0", "Point objects"])
def test_sites_given_as_pairs_or_triples_are_read_as_points_and_the_diagram_is_proved(form):
    xy = [(0, 0), (4, 0), (0, 4)]
    sites = {"pairs": xy,
             "lists": [list(p) for p in xy],
             "triples with r = 0": [(x, y, 0) for x, y in xy],
             "Point objects": [Point(x, y) for x, y in xy]}[form]
    cert = verify(_right_triangle_document(), sites)
    assert cert.problems == []
    assert cert.ok and cert.complete
    assert list(cert.vertices) == [True]
    assert list(cert.edges) == [True, True, True]


def test_pairs_that_differ_from_the_diagram_sites_are_refused():
    # the same document against the pair (0, 5) for its third site: the sites differ, not proved
    cert = verify(_right_triangle_document(), [(0, 0), (4, 0), (0, 5)])
    assert not cert.ok
