"""The polyline checks of an edge (runtime/voronoi/verify/edge_checks.py, ``_polyline_on_arc``) on
each side separately: a node beyond only the first end vertex, or only the last, is refused as not
on the arc between its ends; a node off the bisector by three times the stated tolerance is
refused as that far from the bisector.

Scene in closed form (as in tests/test_line_bisector_parameter_slack.py): the points (0, ±1) have
the x-axis as bisector, and with (±3, 0) their edge runs between the vertices (∓4/3, 0)
(x² + 1 = (3 − |x|)², radius 5/3).  A node (x, 0) with |x| > 4/3 lies on the bisector beyond an
end, at distance |x| − 4/3 from the edge; a node (0, y) with 0 < y < 1 is at distances 1 − y and
1 + y from the two points, so the verifier's lower bound |d_i − d_j|/2 on its distance from the
bisector is y itself.
"""
from __future__ import annotations

import copy

import pytest

import curvedvoronoi as cv


@pytest.fixture(scope="module")
def four_points():
    d = cv.voronoi([cv.Point(0, 1), cv.Point(0, -1), cv.Point(-3, 0), cv.Point(3, 0)])
    assert d.certified
    return d.to_json()


def _edge(doc, nodes, tol=1e-4):
    """The document with the edge of sites 0, 1 drawn from (−4/3, 0) through ``nodes`` to (4/3, 0)."""
    D = copy.deepcopy(doc)
    e, = [e for e in D["edges"] if sorted(e["sites"]) == [0, 1]]
    P = e["polyline"]
    if P[0][0] > 0:
        P.reverse()
    assert P[0][0] == pytest.approx(-4 / 3, abs=1e-15) and P[-1][0] == pytest.approx(4 / 3, abs=1e-15)
    e["polyline"] = [P[0], *nodes, P[-1]]
    e["tolerance"] = tol
    return D


def test_the_edge_with_nodes_on_its_arc_is_accepted(four_points):
    cert = cv.verify(_edge(four_points, [[-0.5, 0.0], [0.5, 0.0]]))
    assert cert.ok, cert.problems


@pytest.mark.parametrize("side", [-1, 1])
def test_a_node_beyond_one_end_only_is_refused(four_points, side):
    # 10⁻³ beyond the end (4/3, 0) or (−4/3, 0): within the tolerance of the bisector line, outside
    # the edge's parameter range [−ln 3, ln 3] by far more than its slack 10⁻⁶·(1 + |u|)
    x = side * (4 / 3 + 1e-3)
    nodes = [[x, 0.0], [0.0, 0.0]] if side < 0 else [[0.0, 0.0], [x, 0.0]]
    cert = cv.verify(_edge(four_points, nodes, tol=2e-3))
    assert not cert.ok
    assert any("not on the arc between its ends" in p for p in cert.problems), cert.problems


def test_a_node_off_the_bisector_by_three_tolerances_is_named(four_points):
    y = 3e-4                                     # the stated tolerance is 1e-4
    assert abs((1 + y) - (1 - y)) / 2 == pytest.approx(y, rel=1e-9)
    cert = cv.verify(_edge(four_points, [[0.0, y]]))
    assert not cert.ok
    assert any("from the bisector (stated tolerance" in p for p in cert.problems), cert.problems
