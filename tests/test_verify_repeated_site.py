"""A document that lists one site twice is refused with a certificate, not an exception.

The Voronoi diagram is defined for pairwise disjoint sites (thesis §1.2); two equal sites have
the whole plane as their bisector, so no vertex of theirs is defined.  The verifier's contract is
a verdict on every well-formed document: :func:`curvedvoronoi.runtime.voronoi.verify.certificate.
verify` returns a certificate that is not ok, whose vertices listing both copies are not proved.

The scene: the four points (±1, 0), (0, ±1) are co-circular about the origin, a vertex of degree 4
(the origin is at distance 1 from each), plus the point (5, 5).  The exact (tower) proof of a
degree-4 vertex tries the triples of its consecutive sites until one has a Voronoi vertex
(thesis §3.1.3); with the first two sites equal, its first triple has none (the exact solver
reports the coincident circles), and the proof must go on to the next triple or refuse."""
from __future__ import annotations

import copy

from curvedvoronoi.runtime.voronoi.construction import voronoi
from curvedvoronoi.runtime.voronoi.verify.certificate import verify


def _document():
    return voronoi([(1, 0), (0, 1), (-1, 0), (0, -1), (5, 5)], certify=False).to_json()


def test_the_co_circular_diagram_is_proved():
    doc = _document()
    (v4,) = [v for v in doc["vertices"] if len(v["sites"]) == 4]
    assert (v4["x"], v4["y"]) == (0.0, 0.0)
    cert = verify(doc)
    assert cert.ok and all(cert.vertices) and all(cert.edges)


def test_a_degree_four_vertex_whose_first_two_sites_are_equal_is_refused():
    doc = copy.deepcopy(_document())
    k4 = next(k for k, v in enumerate(doc["vertices"]) if len(v["sites"]) == 4)
    a, b = doc["vertices"][k4]["sites"][:2]
    doc["sites"][b] = copy.deepcopy(doc["sites"][a])
    cert = verify(doc)
    assert not cert.ok
    assert not cert.vertices[k4]
