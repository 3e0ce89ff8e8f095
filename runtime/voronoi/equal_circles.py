"""The Voronoi diagram of equal disjoint circles as the diagram of their centres.

Circles of one radius ρ whose centres are more than 2ρ apart have the Voronoi diagram of their
centres: at every point the nearest circles are the circles of the nearest centres (additively
weighted points with equal weights, thesis §3.1.2; the proof, inside the discs too, is in
:mod:`runtime.voronoi.verify.equal_circles`, which the verifier uses to prove such a diagram).  So
their diagram is built as the centres' one, whose triangulation is exact
(:mod:`runtime.voronoi.exact_delaunay`), with each vertex's radius less ρ.  Centres that floats
leave nearly co-circular or nearly collinear (a rotated grid of equal circles) then give the
exact diagram of the input, where the sampled circles' triangulation can miss the far vertices of
nearly collinear rows.

Used by :func:`runtime.voronoi.construction.voronoi` when the sampled construction of equal
circles is not certified.  The diagram has no construction state (``insert`` / ``delete_site``
need the sampled one).

Public API: :func:`equal_circles_diagram`.
"""
from __future__ import annotations

import math

from ..predicates.circles import Circle, Point
from .structure import Diagram, DiagramVertex

__all__ = ["equal_circles_diagram"]


def equal_circles_diagram(sites, build, *, certify=True, progress=None, time_limit=None):
    """The diagram of ``sites`` (circles of one exact positive squared radius; None otherwise) from
    ``build`` (:func:`runtime.voronoi.construction.voronoi`, passed in) on their centres, without
    its certificate, then verified as circles when ``certify``."""
    if not sites or not all(isinstance(s, Circle) and not isinstance(s, Point) for s in sites):
        return None
    if len({s.r2 for s in sites}) != 1:
        return None
    rho = math.sqrt(float(sites[0].r2))
    P = build([Point(s.cx, s.cy) for s in sites], certify=False, progress=progress, time_limit=time_limit)
    vertices = [DiagramVertex(v.id, tuple(v.sites), v.x, v.y, float(v.radius) - rho, v.certified)
                for v in P.vertices]
    for e in P.edges:
        e.certified = False
    problems = [p for p in P.problems if p != "not verified (certify=False)"]
    stats = dict(P.stats, route="equal circles as their centres")
    D = Diagram(list(sites), vertices, list(P.edges), False, problems, stats)
    if not certify:
        D.problems.append("not verified (certify=False)")
        return D
    from .verify.certificate import verify

    cert = verify(D, list(sites))
    D.certified = bool(cert.ok) and not problems and all(v.certified for v in vertices)
    D.problems.extend(cert.problems)
    for e, ok in zip(D.edges, cert.edges):
        e.certified = bool(ok)
    for v, ok in zip(D.vertices, cert.vertices):
        v.certified = v.certified and bool(ok)
    return D
