"""The construction's batched proof of conic Voronoi vertices (runtime/voronoi/conic_vertices.py
through runtime/voronoi/verify/conic_vertices.prove_conic_vertices: the kernel's Krawczyk test on
the distance differences, all vertices at once) against the per-vertex arb Krawczyk on the
foot-point system (runtime/voronoi/vertex.certify_vertex, thesis §6.1), an independent
formulation: the same vertices, proved squares meeting the arb boxes, radius enclosures meeting."""
from __future__ import annotations

import math

import pytest

import curvedvoronoi as cv
from curvedvoronoi.runtime.voronoi import conic_vertices as construction_vertices
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify.conic_vertices import prove_conic_vertices
from curvedvoronoi.runtime.voronoi.vertex import certify_vertex
from scenes import random_ellipses


@pytest.mark.parametrize("seed", [1, 2])
def test_batched_vertex_proofs_meet_the_arb_foot_point_proofs(seed):
    sites = random_ellipses(40, seed)
    D = cv.voronoi(sites, certify=False, progress=False)
    geoms = [site_geometry(s) for s in sites]
    trips = [tuple(int(s) for s in v.sites) for v in D.vertices]
    fin = [abs(b) for g in geoms for b in g.bounding_box() if math.isfinite(b)]
    res = prove_conic_vertices(geoms, trips, [(v.x, v.y) for v in D.vertices], 1.0 + max(fin))
    assert sum(r is not None for r in res) >= 0.95 * len(res)
    for v, t, r in zip(D.vertices, trips, res):
        if r is None:
            continue
        x, y, h, rlo, rhi = r
        pf = certify_vertex([sites[s] for s in t], [geoms[s] for s in t], v.x, v.y)
        assert pf.certified, pf.reason
        (xl, xh), (yl, yh) = pf.box
        assert xl <= x + h and x - h <= xh and yl <= y + h and y - h <= yh, (v.id, pf.box, r)
        assert pf.radius_bounds[0] <= rhi and rlo <= pf.radius_bounds[1], (v.id, pf.radius_bounds, r)


def test_construction_with_and_without_the_batch_gives_the_same_vertices(monkeypatch):
    """The batch changes which test proves a vertex, not the diagram: the same triples and
    positions as the per-vertex arb route alone."""
    sites = random_ellipses(60, 3)
    fast = cv.voronoi(sites, certify=False, progress=False)
    monkeypatch.setattr(construction_vertices, "prove_conic_vertices", lambda g, T, X, s, **kw: [None] * len(T))
    slow = cv.voronoi(sites, certify=False, progress=False)
    key = lambda D: sorted((tuple(sorted(int(s) for s in v.sites)), v.x, v.y) for v in D.vertices)
    a, b = key(fast), key(slow)
    assert [t for t, _, _ in a] == [t for t, _, _ in b]
    for (_, x1, y1), (_, x2, y2) in zip(a, b):
        assert math.hypot(x1 - x2, y1 - y2) <= 1e-9 * (1 + abs(x1) + abs(y1))
