"""Mutants of :mod:`curvedvoronoi.runtime.voronoi.verify.conic_vertices` (mutation sample seed 38).

Krawczyk's test (Moore, Kearfott & Cloud, *Introduction to Interval Analysis*, SIAM 2009, §8.2)
is sound only if the Jacobian enclosure holds over the whole box: |J(q) − A| ≤ J_rad entrywise
for every q of c + [−ρ, ρ]², J(q) having rows ∇d_i − ∇d_j and ∇d_i − ∇d_k.  Each row moves with
both of its sites' gradients, so where one site is much nearer than the others its gradient's
turn over the square (about ρ/|q − m| for a circle of centre m) dominates the row's deviation.  The
reference gradient of the distance to a circle of centre m, from outside, is (q − m)/|q − m|
(closed form, 30 digits).
"""
from __future__ import annotations

import itertools

import mpmath
import numpy as np
import pytest

from curvedvoronoi.runtime.sites.conic import Conic
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify.conic_vertices import vertex_enclosures
from curvedvoronoi.runtime.voronoi.verify.curved_edges import curved_scale
from curvedvoronoi.runtime.voronoi.verify.site_table import SiteTable

CENTRES = [(0, 0), (20, 0), (0, 20)]
RADII = [1, 2, 3]


def _gradient(m, q):
    """∇d at q of the circle of centre m (q outside it): the unit vector from m to q, 30 digits."""
    with mpmath.workdps(30):
        vx, vy = mpmath.mpf(q[0]) - m[0], mpmath.mpf(q[1]) - m[1]
        n = mpmath.sqrt(vx * vx + vy * vy)
        return vx / n, vy / n


@pytest.mark.parametrize("near", [0, 1, 2])
def test_the_jacobian_bound_holds_where_one_site_is_much_nearer(near):
    """c about 0.5 from one circle (at most 3.6 from its centre) and at least 16 from the others'
    centres, ρ = 0.05: the nearer site's gradient turns by about ρ/3.6 > 0.01 over the square;
    |J(q) − A| ≤ J_rad must still hold entrywise on an 11 × 11 grid of the square (edges and
    corners included)."""
    sites = [Conic.circle(centre=m, radius=r) for m, r in zip(CENTRES, RADII)]
    geoms = [site_geometry(s) for s in sites]
    table = SiteTable(geoms, curved_scale(geoms))
    m0, r0 = CENTRES[near], RADII[near]
    c = np.array([m0[0] + r0 + 0.5, m0[1] + 0.3])          # about 0.5 from site `near`'s circle
    rho = 0.05
    trip = (near,) + tuple(k for k in range(3) if k != near)
    A, _, J_rad, valid = vertex_enclosures(table, c, [trip], [rho], table.scale)
    assert valid[0]
    worst = 0.0
    grid = np.linspace(-rho, rho, 11)
    for sx, sy in itertools.product(grid, grid):
        q = (c[0] + sx, c[1] + sy)
        G = [_gradient(CENTRES[k], q) for k in trip]
        J = [[G[0][0] - G[1][0], G[0][1] - G[1][1]], [G[0][0] - G[2][0], G[0][1] - G[2][1]]]
        for a in range(2):
            for b in range(2):
                dev = abs(J[a][b] - mpmath.mpf(A[0, a, b]))
                assert dev <= mpmath.mpf(J_rad[0, a, b]), (near, sx, sy, a, b, dev, J_rad[0, a, b])
                worst = max(worst, float(dev))
    # the test is not vacuous: some entry moves by more than the far sites' gradients can
    # (each turns by at most ρ√2/16 < 0.005 at 16 from its centre): the near site's turn counts
    assert worst > 0.01, worst
