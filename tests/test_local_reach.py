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
