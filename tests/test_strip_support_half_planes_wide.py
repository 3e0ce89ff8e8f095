"""(T2) by supporting half-planes (runtime/voronoi/verify/strips.py) with wide distance
enclosures: the level of s is u·(C − m) − hi_s(C) − losses, and only the UPPER bound hi_s makes
it a bound — d_s(q) ≤ |q − p*| ≤ d_s(C) + u*·(q − C) + … needs d_s(C) ≤ hi_s(C).  The table's
enclosures are a few ulps wide, so a level taken from lo_s would go unnoticed on them; here the
lower bounds are lowered by a tenth of the distance (still valid enclosures, hence a valid input),
and every site the test accepts must still be farther than s on the whole disc (distances by dense
sampling and scipy, as in tests/test_strip_support_half_planes.py)."""
import math

import numpy as np
import pytest

import curvedvoronoi as cv
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify import strips
from curvedvoronoi.runtime.voronoi.verify.site_table import SiteTable, SiteValues, gradient_enclosure
from curvedvoronoi.runtime.voronoi.verify.support import SupportTable
from test_strip_support_half_planes import Pieces, disc_points, ellipse_distance, scene


def widened(V, frac):
    """The same values with lo lowered by ``frac``·hi (kept above 0): a wider, still valid enclosure."""
    lo = np.maximum(V.lo - frac * V.hi, 0.0)
    return SiteValues(lo, V.hi, V.F, V.d, V.base, V.inner, V.reach, V.sep, V.K, V.table)


@pytest.mark.parametrize("seed", range(3))
def test_a_wide_enclosure_does_not_make_the_half_plane_bound_accept_nearer_sites(seed):
    rng = np.random.default_rng(seed)
    ells, ang = scene(rng)
    sites = [cv.Conic.ellipse(centre=(cx, cy), axes=(a, b), radians=rot) for cx, cy, a, b, rot in ells]
    geoms = [site_geometry(s) for s in sites]
    sup, table = SupportTable(geoms), SiteTable(geoms, 20.0)
    n = len(ells)
    t = np.exp(rng.uniform(math.log(15), math.log(3000), 40))
    C = np.column_stack([t * math.cos(ang), t * math.sin(ang)]) + rng.normal(0, 1, (40, 2)) * t[:, None] * 0.05
    R = t * rng.uniform(0.001, 0.05, 40)
    i, j = 0, 1
    Vi = strips.evaluate_rows(table, C, np.full(40, i))
    Vj = strips.evaluate_rows(table, C, np.full(40, j))
    enc_i = gradient_enclosure(C, Vi, R, table.scale)
    enc_j = gradient_enclosure(C, Vj, R, table.scale)
    Wi, Wj = widened(Vi, 0.1), widened(Vj, 0.1)
    assert (Wi.hi - Wi.lo > 0.05 * Wi.hi).all()
    rows = np.repeat(np.arange(40), n - 2)
    ks = np.tile([k for k in range(n) if k not in (i, j)], 40)
    ok = strips._support_half_planes(sup, Pieces(C, R), rows, ks, Wi, Wj, enc_i, enc_j)
    assert ok.any()
    acc = np.nonzero(ok)[0]
    for r in rng.choice(acc, min(len(acc), 12), replace=False):
        p, k = rows[r], ks[r]
        pts = disc_points(C[p], R[p])
        dk = np.array([ellipse_distance(ells[k], q) for q in pts])
        gap = max(float((dk - np.array([ellipse_distance(ells[s], q) for q in pts])).min()) for s in (i, j))
        assert gap > -1e-7, (p, k, gap)
