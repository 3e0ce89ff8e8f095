"""A polyline node a hair beyond an edge's end vertex, on the bisector of two points
(runtime/voronoi/verify/edge_checks.py): the node's float curve parameter u may lie up to
1e-6·(1 + |u|) outside the edge's parameter range (the rounding of the float parameters), the
bound included; a node far beyond the end is refused.

The scene in closed form: the points (0, ±1) have the x-axis as bisector, q(u) = (sinh u, 0)
(half-distance c = 1, centre 0); with (±3, 0) its edge runs between the vertices (∓4/3, 0)
(x² + 1 = (3 − |x|)², radius 5/3), i.e. u ∈ [−asinh(4/3), asinh(4/3)] = [−ln 3, ln 3].  A node
(x, 0) lies on the bisector line, so its distance from the edge is |x| − 4/3 when |x| > 4/3; the
stated tolerance 1e-4 allows the nodes about 3.5·10⁻⁶ beyond the vertex (where the parameter
slack ends) and not one 10⁻³ beyond.  The nodes exactly at the end of the slack are found in
floats, as the rule is stated: u = asinh(x) and its bound asinh(4/3) + 1e-6·(1 + |u|), both
rounded to double (the vertex (4/3, 0) is proved at the double nearest 4/3)."""
from __future__ import annotations

import copy

import numpy as np
import pytest

import curvedvoronoi as cv


@pytest.fixture(scope="module")
def four_points():
    d = cv.voronoi([cv.Point(0, 1), cv.Point(0, -1), cv.Point(-3, 0), cv.Point(3, 0)])
    assert d.certified
    doc = d.to_json()
    e, = [e for e in doc["edges"] if sorted(e["sites"]) == [0, 1]]
    assert sorted(abs(p[0]) for p in e["polyline"]) == pytest.approx([4 / 3, 4 / 3], abs=1e-15)
    return doc


def _slack_end_nodes():
    """The doubles x > 4/3 with asinh(x) = asinh(4/3) + 1e-6·(1 + asinh(x)) in double arithmetic
    (the last parameters within the slack)."""
    A = float(np.arcsinh(4 / 3))

    def beyond(x):             # > 0: the parameter of (−x, 0) is past the slack
        u = float(np.arcsinh(-x))
        return (-A - 1e-6 * (1 + abs(u))) - u

    a, b = 4 / 3, 4 / 3 + 1e-5
    for _ in range(200):       # bisection on doubles: the slack ends between a and b
        m = 0.5 * (a + b)
        a, b = (m, b) if beyond(m) <= 0 else (a, m)
    xs, x = [], a
    for _ in range(64):
        x = float(np.nextafter(x, 0))
    for _ in range(128):
        if beyond(x) == 0:
            xs.append(x)
        x = float(np.nextafter(x, 2))
    return xs


def _with_overshoot(doc, x, tol=1e-4):
    D = copy.deepcopy(doc)
    e, = [e for e in D["edges"] if sorted(e["sites"]) == [0, 1]]
    P = e["polyline"]
    if P[0][0] > 0:
        P.reverse()
    # from (−4/3, 0) out to (−x, 0), back along the line to (x, 0) beyond (4/3, 0), and to (4/3, 0)
    e["polyline"] = [P[0], [-x, 0.0], [x, 0.0], P[-1]]
    e["tolerance"] = tol
    return D


def test_nodes_at_the_end_of_the_parameter_slack_are_on_the_edge(four_points):
    xs = _slack_end_nodes()
    assert xs, "no double sits exactly at the end of the slack"
    for x in xs:
        assert 3.4e-6 < x - 4 / 3 < 3.6e-6        # within the stated tolerance 1e-4 of the edge
        cert = cv.verify(_with_overshoot(four_points, x))
        assert cert.ok, (x, cert.problems)


def test_a_node_far_beyond_the_end_vertex_is_refused(four_points):
    cert = cv.verify(_with_overshoot(four_points, 4 / 3 + 1e-3))
    assert not cert.ok
    assert any("not on the arc between its ends" in p for p in cert.problems)
