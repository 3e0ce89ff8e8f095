"""(T2) of the strip test by supporting half-planes (runtime/voronoi/verify/strips.py,
``_support_half_planes``): a third site k accepted as farther than s = i or j on a piece's disc
B(C, R) must be farther at every point of the disc.

The expectation is computed without the verifier: distances to the ellipses by dense sampling
of their boundaries refined by a bounded scalar minimisation (scipy), at points of the disc (its
centre, rings of points and its boundary).  Discs near the sites and far from them, small and
as large as a third of their distance; sites k placed just behind the supporting line of s, where
the inequality's losses R²/(2(d − R)) and 2e·R decide.  (With e the slack of the disc's gradient
enclosure, ≈ 2R/(d − R), the term 2e·R alone exceeds what the float gradient at C needs; the
R²/(2(d − R)) term is then not what decides, and dropping it stays sound.)  The level of s must come from
the upper bound hi_s (d_s(q) ≤ d_s(C) + u*·(q − C) + … needs d_s(C) ≤ hi_s(C)): the second test widens
the enclosures of i and j, still valid, so that a level taken from lo_s would accept nearer sites."""
import math
from typing import NamedTuple

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

import curvedvoronoi as cv
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify import strips
from curvedvoronoi.runtime.voronoi.verify.site_table import SiteTable, SiteValues, gradient_enclosure
from curvedvoronoi.runtime.voronoi.verify.support import SupportTable


class Pieces(NamedTuple):
    C: np.ndarray
    R: np.ndarray


def ellipse_distance(e, q):
    """Distance from q (outside) to the ellipse e = (cx, cy, a, b, rot): a 2000-sample grid of the
    parameter, then a bounded minimisation around the best sample."""
    cx, cy, a, b, rot = e
    c, s = math.cos(rot), math.sin(rot)

    def dist(t):
        x, y = a * math.cos(t), b * math.sin(t)
        return math.hypot(cx + c * x - s * y - q[0], cy + s * x + c * y - q[1])

    ts = np.linspace(0, 2 * math.pi, 2001)
    k = int(np.argmin([dist(t) for t in ts]))
    return minimize_scalar(dist, bounds=(ts[k] - 0.004, ts[k] + 0.004), method="bounded",
                           options={"xatol": 1e-12}).fun


def disc_points(C, R):
    pts = [C]
    for r in (0.5 * R, R):
        for t in np.linspace(0, 2 * math.pi, 12, endpoint=False):
            pts.append(C + r * np.array([math.cos(t), math.sin(t)]))
    return pts


def scene(rng):
    ells = []
    for _ in range(4):
        a = rng.uniform(0.5, 3.0)
        ells.append((rng.uniform(-8, 8), rng.uniform(-8, 8), a, a * rng.uniform(0.2, 1.0), rng.uniform(0, math.pi)))
    # k: a copy of ellipse 0 moved along a direction by a small amount (nearly tied with it there)
    ang = rng.uniform(0, 2 * math.pi)
    shift = rng.uniform(-0.3, 0.3)
    cx, cy, a, b, rot = ells[0]
    ells.append((cx - shift * math.cos(ang) + 0.2 * math.sin(ang) * rng.uniform(-1, 1),
                 cy - shift * math.sin(ang) - 0.2 * math.cos(ang) * rng.uniform(-1, 1), a, b, rot))
    return ells, ang


def _accepted_are_farther(seed, rmax, widen=0.0, sample=None):
    """Discs in the direction ang from ellipse 0 (where k = 4 nearly ties it), at distances
    15..3000; the sites the bound accepts must be farther than s = i or j on the whole disc.  With
    ``widen`` the enclosures of i and j get their lower bounds lowered by widen·hi (wider, still
    valid: the level must come from hi_s); ``sample``: at most that many accepted rows checked."""
    rng = np.random.default_rng(seed)
    ells, ang = scene(rng)
    sites = [cv.Conic.ellipse(centre=(cx, cy), axes=(a, b), radians=rot) for cx, cy, a, b, rot in ells]
    geoms = [site_geometry(s) for s in sites]
    sup, table = SupportTable(geoms), SiteTable(geoms, 20.0)
    n = len(ells)
    t = np.exp(rng.uniform(math.log(15), math.log(3000), 40))
    C = np.column_stack([t * math.cos(ang), t * math.sin(ang)]) + rng.normal(0, 1, (40, 2)) * t[:, None] * 0.05
    R = t * rng.uniform(0.001, rmax, 40)
    i, j = 0, 1
    Vi = strips.evaluate_rows(table, C, np.full(40, i))
    Vj = strips.evaluate_rows(table, C, np.full(40, j))
    enc_i = gradient_enclosure(C, Vi, R, table.scale)
    enc_j = gradient_enclosure(C, Vj, R, table.scale)
    if widen:
        Vi, Vj = (SiteValues(np.maximum(V.lo - widen * V.hi, 0.0), V.hi, V.F, V.d, V.base, V.inner, V.reach,
                             V.sep, V.K, V.table) for V in (Vi, Vj))
        assert (Vi.hi - Vi.lo > 0.5 * widen * Vi.hi).all()
    rows = np.repeat(np.arange(40), n - 2)
    ks = np.tile([k for k in range(n) if k not in (i, j)], 40)
    ok = strips._support_half_planes(sup, Pieces(C, R), rows, ks, Vi, Vj, enc_i, enc_j)
    assert ok.any()
    acc = np.nonzero(ok)[0]
    if sample is not None:
        acc = rng.choice(acc, min(len(acc), sample), replace=False)
    for r in acc:
        p, k = rows[r], ks[r]
        pts = disc_points(C[p], R[p])
        dk = np.array([ellipse_distance(ells[k], q) for q in pts])
        # d_k − d_s > 0 on the whole disc for s = i or for s = j (the test's claim)
        gap = max(float((dk - np.array([ellipse_distance(ells[s], q) for q in pts])).min()) for s in (i, j))
        assert gap > -1e-7, (p, k, gap)


@pytest.mark.parametrize("seed", range(4))
def test_a_site_accepted_by_the_half_plane_bound_is_farther_on_the_whole_disc(seed):
    _accepted_are_farther(seed, 0.3)


@pytest.mark.parametrize("seed", range(3))
def test_a_wide_enclosure_does_not_make_the_half_plane_bound_accept_nearer_sites(seed):
    """The table's enclosures are a few ulps wide, so a level taken from lo_s would go unnoticed on
    them: here the lower bounds are lowered by a tenth of the distance."""
    _accepted_are_farther(seed, 0.05, widen=0.1, sample=12)
