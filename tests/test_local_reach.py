"""``local_reach`` (runtime/voronoi/verify/vertices.py) against its derivation, checked at the
extremes: the reported vertex v is accepted within tol + 2h of the proved centre q̃ and its radius
within tol + 2h of r̃; the true vertex lies in the box |q* − q̃|∞ ≤ h, |r* − r̃| ≤ h.  The true empty
circle D(q*, r*) must lie in D(v, local_reach(v)): |q* − v| + r* ≤ local_reach for every corner."""
from __future__ import annotations

import itertools
import math

import pytest

from curvedvoronoi.runtime.voronoi.structure import DiagramVertex
from curvedvoronoi.runtime.voronoi.verify.vertices import VertexInfo, local_reach


@pytest.mark.parametrize("h_over_tol", [0.0, 0.3, 1.0, 42.0])
@pytest.mark.parametrize("angle", [0.0, 0.7, 2.1, 4.0])
def test_the_true_circle_lies_in_the_local_reach(h_over_tol, angle):
    info = VertexInfo(0, (0, 1, 2), 123.0, -45.0, 7.0)
    info.h = h_over_tol * info.tol
    off = info.tol + 2 * info.h                       # the largest accepted report offset
    v = DiagramVertex(0, (0, 1, 2), info.x + off * math.cos(angle), info.y + off * math.sin(angle), info.r - off)
    R = local_reach(v, info)
    for sx, sy, sr in itertools.product((-1, 1), repeat=3):
        qx, qy, r = info.x + sx * info.h, info.y + sy * info.h, info.r + sr * info.h
        assert math.hypot(qx - v.x, qy - v.y) + r <= R


def test_a_run_lists_the_coarse_vertices(monkeypatch):
    """``verify`` (a chunk of the chunked certificate or a whole run) must list in
    ``stats["vertex_reach"]`` every proved vertex whose proof box is coarse enough that its true
    circle may reach past the chunk's first list of sites: here one vertex's box is widened to
    h = 2·tol, so r + 2·tol + 7h = r + 16·tol exceeds the first list's r + 5·tol (written out here,
    not taken from the library).  The chunked certificate also reads these radii as bounds on the
    distance from a reported vertex to its true one (its test for a vertex reported twice)."""
    from curvedvoronoi.runtime.voronoi.construction import voronoi
    from curvedvoronoi.runtime.voronoi.verify import certificate
    from scenes import random_disjoint_circles

    d = voronoi(random_disjoint_circles(60, 3), progress=False, certify=False)
    real = certificate.prove_vertices
    target = d.vertices[len(d.vertices) // 2].id

    def coarse(*a, **k):
        vinfo, vok = real(*a, **k)
        vinfo[target].h = max(vinfo[target].h, 2 * vinfo[target].tol)
        return vinfo, vok

    monkeypatch.setattr(certificate, "prove_vertices", coarse)
    local = certificate.verify(d, progress=False, at_infinity=False)
    listed = {m: R for m, R in local.stats["vertex_reach"]}
    v = d.vertices[target]
    tol = 1e-10 * (1 + abs(v.x) + abs(v.y) + abs(v.radius))
    assert target in listed and listed[target] >= v.radius + 15 * tol
    whole = {m: R for m, R in certificate.verify(d, progress=False).stats["vertex_reach"]}
    assert whole[target] == listed[target] and len(whole) < len(d.vertices) // 2
