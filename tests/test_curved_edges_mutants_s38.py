"""Mutants of :mod:`curvedvoronoi.runtime.voronoi.verify.curved_edges` (mutation sample seed 38).

Two parabolas, mirror images of each other in the x-axis and strictly on opposite sides of it
(vertices (0, ±1), opening away from it): their bisector is the mirror line y = 0 (a point q and
its mirror image q' have d_1(q) = d_2(q'), and each site is nearer to the points on its own side).
The mirror-line proof of :func:`runtime.voronoi.verify.mirror_tail.prove_mirror_edge` needs the
support functions of bounded sites, which parabolas do not have; the verifier must still decide
such a diagram (a certificate, certified or with its problems), not fail.
"""
from __future__ import annotations

import numpy as np

from curvedvoronoi.runtime.sites.conic import Conic
from curvedvoronoi.runtime.voronoi.construction import voronoi
from curvedvoronoi.runtime.voronoi.verify.certificate import verify


def test_mirror_image_parabolas_are_decided():
    sites = [Conic.parabola(vertex=(0, 1), p=1, rotation=(0, 1)),
             Conic.parabola(vertex=(0, -1), p=1, rotation=(0, -1))]
    D = voronoi(sites, certify=False)
    assert len(D.edges) == 1
    e = D.edges[0]
    P = np.asarray(e.polyline, float).reshape(-1, 2)
    # the drawn edge is the mirror line, within its stated tolerance
    assert np.all(np.abs(P[:, 1]) <= float(e.tolerance) + 1e-12 * (1 + np.abs(P).max()))
    cert = verify(D)                  # decides: returns a certificate
    assert isinstance(cert.ok, bool)
    if not cert.ok:
        assert cert.problems and all(isinstance(p, str) for p in cert.problems)
