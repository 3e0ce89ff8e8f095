"""The verifier run chunk by chunk (runtime/voronoi/chunked_certificate.py) sets aside a site's
line only when it says the site has no edge; the line "sites a and b intersect or touch" must
still refuse.

Four sites on the x-axis: the point P = (-4, 0), the unit circles A (centre (0, 0)) and B (centre
(t, 0)), and the point Q = (t + 4, 0).  The bisector of P and A, |x - A| - 1 = |x - P|, is the
branch nearer P of the hyperbola with foci P, A, centre (-2, 0), a = 1/2, c = 2, b = √15/2; it
lies in x <= -5/2.  Likewise the bisector of B and Q is the branch nearer Q of the hyperbola of
centre (t + 2, 0), in x >= t + 5/2.  A and B have equal radii, so their bisector is the line
x = t/2, between the two branches: the true diagram has three whole edges (P, A), (A, B), (B, Q)
and no vertex (far along the branch of (P, A), in a direction e(φ) = (-cos φ, ± sin φ) with
cos φ = 1/4, the support values are h_A = h_P = 1 and h_B = 1 - 1/4, so B is strictly farther;
the same for A along the branch of (B, Q)).

The reported diagram drops the line of (A, B).  The two branches left are whole true edges (the
verifier proves both in every chunk), every site keeps an edge and there is no vertex, so the
closure of the whole diagram holds.  The diagram is wrong (an edge is missing), and for t < 2
(|AB| < 2: the discs overlap) or t = 2 (margin 0: they touch at (1, 0)) the sites are not
disjoint, which the accounting at infinity reports as a line of kind "site" before returning
False.  A chunk must not set that line aside (it is not a "site ... has no edge" line).  For
t = 2 + 1e-9 the discs are disjoint and the accounting itself sees the missing edge.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import curvedvoronoi as cv
from curvedvoronoi.runtime.voronoi.chunked_certificate import chunked_verify
from curvedvoronoi.runtime.voronoi.structure import Diagram, DiagramEdge
from curvedvoronoi.runtime.voronoi.verify.certificate import verify


@pytest.fixture(scope="module")
def client():
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as c:
        yield c


def _branch(cx: float, side: int, U: float = 4.0, n: int = 161) -> np.ndarray:
    """The branch x = cx + side·a·cosh u, y = b·sinh u (a = 1/2, c = 2) for u in [-U, U]."""
    a, c = 0.5, 2.0
    b = math.sqrt(c * c - a * a)
    u = np.linspace(-U, U, n)
    return np.column_stack([cx + side * a * np.cosh(u), b * np.sinh(u)])


def _without_the_line_of_a_and_b(t: float) -> Diagram:
    sites = [cv.Circle(-4, 0, 0), cv.Circle(0, 0, 1), cv.Circle(t, 0, 1), cv.Circle(t + 4, 0, 0)]
    edges = [DiagramEdge(0, (0, 1), (None, None), False, _branch(-2.0, -1), 1e-2),
             DiagramEdge(1, (2, 3), (None, None), False, _branch(t + 2.0, 1), 1e-2)]
    return Diagram(sites, [], edges)


@pytest.mark.parametrize("t", [1.0, 2.0], ids=["overlapping", "touching"])
def test_meeting_circles_are_refused_chunk_by_chunk(client, t):
    bad = _without_the_line_of_a_and_b(t)
    whole = verify(bad)
    assert not whole.ok and all(whole.edges)
    cc = chunked_verify(bad, [[0], [1]], client)
    assert all(cc.edges)                      # the two branches are true whole edges
    assert not cc.ok
    assert any("sites 1 and 2 intersect or touch" in str(p) for p in cc.problems)


def test_disjoint_circles_without_their_line_are_refused_at_infinity(client):
    bad = _without_the_line_of_a_and_b(2.0 + 1e-9)
    cc = chunked_verify(bad, [[0], [1]], client)
    assert all(cc.edges)
    assert not cc.ok
    assert not any("intersect or touch" in str(p) for p in cc.problems)


@pytest.mark.parametrize("here", [True, False], ids=["here", "workers"])
def test_equal_circles_meeting_across_a_bounded_edge_are_refused_chunk_by_chunk(client, here):
    """Equal circles of radius 6/5 at A = (0, 0), B = (10, 0), C = (5, 1), D = (5, -1): the centres'
    Delaunay graph is the hull A D B C and the diagonal C D, whose Voronoi edge is bounded.  C
    and D (2 apart) overlap; every other Delaunay pair is more than 12/5 apart.  The reported
    diagram is the centres' diagram (the equal circles' diagram when they are disjoint): the
    chunk of the edge (C, D) proves it as the centres' edge, and must not call it proved for the
    circles, which are not disjoint there (no other check sees C and D: the chunk of the unbounded
    edges checks the pairs of its own edges)."""
    from fractions import Fraction

    centres = [(0, 0), (10, 0), (5, 1), (5, -1)]
    pts = cv.voronoi([(x, y, 0) for x, y in centres], progress=False)
    assert pts.certified and len(pts.vertices) == 2
    r = Fraction(6, 5)
    sites = [cv.Circle(x, y, r * r) for x, y in centres]
    from curvedvoronoi.runtime.voronoi.structure import DiagramVertex

    verts = [DiagramVertex(v.id, tuple(v.sites), v.x, v.y, v.radius - float(r)) for v in pts.vertices]
    bad = Diagram(sites, verts, list(pts.edges))
    assert not verify(bad).ok
    cc = chunked_verify(bad, [[k] for k in range(len(bad.edges))], None if here else client)
    assert not cc.ok
