"""The float vertex proof of convex conic sites (runtime.voronoi.verify.conic_vertices) from a
start off the vertex (thesis §6.1; Krawczyk's test, Moore, Kearfott & Cloud, *Introduction to
Interval Analysis*, SIAM 2009, §8.2).

Krawczyk's test can prove a zero only in a square that holds it, and the tried squares are at
most 4·10⁻¹¹·(1 + |x| + |y| + r) wide around the centre handed to the test.  A start 10⁻⁵ off the
vertex is therefore proved only after the float Newton steps on F = (d_i − d_j, d_i − d_k) have
moved the centre (Newton converges quadratically from there: F is smooth near a vertex outside
the sites' hulls).  The scenes have closed-form vertices: three equal circles with
centres (0, 0), (8, 0), (0, 6) meet at the circumcentre (4, 3) at distance 5 − r."""
from __future__ import annotations

from fractions import Fraction as F

import pytest

from curvedvoronoi.runtime.sites.conic import Conic
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify.conic_vertices import prove_conic_vertices
from curvedvoronoi.runtime.voronoi.verify.curved_edges import curved_scale

CENTRES = [(0, 0), (8, 0), (0, 6)]
VERTEX = (4, 3)                           # the circumcentre: 5 from every centre


def _sites(r):
    return [Conic.circle(centre=c, radius=r) for c in CENTRES]


@pytest.mark.parametrize("r", [1, F(1, 2)])
@pytest.mark.parametrize("off", [(1e-5, -2e-5), (-3e-4, 1e-4), (2e-7, 2e-7)])
def test_a_vertex_is_proved_from_a_start_off_the_vertex(r, off):
    geoms = [site_geometry(s) for s in _sites(r)]
    start = (VERTEX[0] + off[0], VERTEX[1] + off[1])
    res, = prove_conic_vertices(geoms, [(0, 1, 2)], [start], curved_scale(geoms))
    assert res is not None
    x, y, h, r_lo, r_hi = res
    # the proved square holds the exact vertex (Fractions: no rounding in the check) and is small
    assert abs(F(x) - VERTEX[0]) <= F(h) and abs(F(y) - VERTEX[1]) <= F(h)
    assert h <= 1e-9
    assert F(r_lo) <= 5 - F(r) <= F(r_hi)
