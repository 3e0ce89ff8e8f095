"""The first checks of an edge in the certificate (runtime/voronoi/verify/edge_checks.py): an edge whose
polyline does not start at its end vertex, or whose end is a vertex id the document does not list, is
refused by name, and its own flag in the certificate is False (not only the diagram's verdict).

Scene in closed form: the points (0, ±1) and (±3, 0); the edge of (0, 1) and (0, −1) lies on the
x-axis between the vertices (∓4/3, 0) (x² + 1 = (3 − |x|)²).
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


def _edge_index(doc):
    k, = [k for k, e in enumerate(doc["edges"]) if sorted(e["sites"]) == [0, 1]]
    return k


def test_the_untouched_document_is_proved(four_points):
    cert = cv.verify(copy.deepcopy(four_points))
    assert cert.ok and all(cert.edges), cert.problems


def test_a_polyline_that_does_not_start_at_its_vertex_is_refused_with_its_flag(four_points):
    D = copy.deepcopy(four_points)
    k = _edge_index(D)
    P = D["edges"][k]["polyline"]
    # the first point moved 10⁻³ along the bisector: still on it, but not at the vertex (±4/3, 0)
    P[0] = [P[0][0] * (1 - 7.5e-4), P[0][1]]
    cert = cv.verify(D)
    assert not cert.ok
    assert not cert.edges[k]
    assert any("not at vertex" in p for p in cert.problems), cert.problems


def test_an_end_that_is_not_a_listed_vertex_is_refused_with_its_flag(four_points):
    D = copy.deepcopy(four_points)
    k = _edge_index(D)
    ends = list(D["edges"][k]["ends"])
    ends[0] = 10 ** 6                      # no vertex has this id
    D["edges"][k]["ends"] = ends
    cert = cv.verify(D)
    assert not cert.ok
    assert not cert.edges[k]
    assert any("which is not listed" in p for p in cert.problems), cert.problems
