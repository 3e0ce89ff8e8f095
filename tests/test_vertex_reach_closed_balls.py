"""The reach of a proved vertex is a closed disc.

A vertex proved by the verifier (:class:`runtime.voronoi.verify.vertices.VertexInfo`) is a float
point (x, y) with a stated accuracy ``tol`` and box half-width ``h``.  Two consumers read that
accuracy as a closed disc about (x, y):

* an edge's polyline must start and end within tol + 2h (+ 10⁻¹² of the scene's size) of its
  vertices (:func:`runtime.voronoi.verify.curved_edges.curved_job`);
* the exact tower vertex of three circle/point sites (thesis §3.1.3) is identified with the
  proved one when it is the only one within 4(tol + h)
  (:func:`runtime.voronoi.verify.exact_vertices.exact_tower_vertex`).

The inputs below sit exactly on those circles (the 3-4-5 triangle: hypot(3, 4) = 5 in floats), so
a point at distance equal to the radius must be inside.
"""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np

import curvedvoronoi as cv
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify.curved_edges import curved_job
from curvedvoronoi.runtime.voronoi.verify.exact_vertices import exact_tower_vertex
from curvedvoronoi.runtime.voronoi.verify.vertices import VertexInfo


def test_a_polyline_ending_on_the_circle_of_its_vertex_s_reach_is_accepted():
    """Vertex at the origin with tol + 2h + 10⁻¹²·scale = 5 exactly; the polyline's ends (3, 4)
    and (−4, 3) are at distance exactly 5 from it: on the closed disc, so the edge goes on to its
    proof (a job is returned, no problem recorded)."""
    scale = 1.0
    w = SimpleNamespace(x=0.0, y=0.0, tol=4 - 1e-12, h=0.5, id=0)
    assert w.tol + 2 * w.h + 1e-12 * scale == 5.0
    P = np.array([[3.0, 4.0], [1.0, 9.0], [-4.0, 3.0]])
    assert math.hypot(*P[0]) == 5.0 and math.hypot(*P[-1]) == 5.0
    e = SimpleNamespace(closed=False, tolerance=1e-3)
    problems: list = []
    job = curved_job(e, "edge 0", (0, 1), P, (w, w), scale, problems)
    assert job is not None and not problems, problems
    # one ulp farther out is refused
    P2 = P.copy()
    P2[-1, 0] = np.nextafter(-4.0, -5.0)
    assert curved_job(e, "edge 0", (0, 1), P2, (w, w), scale, []) is None


def test_the_tower_vertex_on_the_circle_of_the_proof_s_reach_is_identified():
    """The points (0, 0), (2, 0), (0, 2) have one Voronoi vertex, their circumcentre (1, 1).  A
    proved vertex reported at (4, 5) with tol + h = 5/4 reaches exactly 4·(5/4) = 5 = |(3, 4)|:
    the circumcentre is on the closed disc, the only tower vertex there, and is identified."""
    sites = [cv.Point(0, 0), cv.Point(2, 0), cv.Point(0, 2)]
    geoms = [site_geometry(s) for s in sites]
    inf = VertexInfo(0, (0, 1, 2), 4.0, 5.0, 5.0)
    inf.tol, inf.h = 1.0, 0.25
    assert 4 * (inf.tol + inf.h) == 5.0
    got = exact_tower_vertex(inf, geoms)
    assert got is not None
    _, w = got
    assert (w.x, w.y) == (1.0, 1.0)
    # the same vertex reported one ulp farther: the circumcentre is out of reach
    far = VertexInfo(0, (0, 1, 2), np.nextafter(4.0, 5.0), 5.0, 5.0)
    far.tol, far.h = 1.0, 0.25
    assert exact_tower_vertex(far, geoms) is None
