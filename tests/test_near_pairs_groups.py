"""Third-site candidates by groups (runtime/voronoi/verify/site_table.py, ``SiteTable.near_pairs``
with ``levels``): a site may be left out of the (piece, site) pairs only if its bounding box is
beyond the piece's reach or the supporting half-plane bound proves it farther,
base[row, s] − h_k(u_s) > 0 for s = 0 or 1 (h_k the support function about m).

The expectation is computed without the verifier's tables: the ellipses are drawn here from their
exact parameters (centre, semi-axes, a Pythagorean rotation), their support functions are the
closed form h(u) = u·(c − m) + √((a·u·e₁)² + (b·u·e₂)²), their bounding boxes the exact extents
c ± (√(a²e₁ₓ² + b²e₂ₓ²), √(a²e₁ᵧ² + b²e₂ᵧ²)).  Rows near the sites (the k-d tree) and far from them
(the groups walked), levels set at quantiles of the sites' support values so that many sites
lie just above and just below them."""
import math
from fractions import Fraction

import numpy as np
import pytest

from curvedvoronoi.runtime.sites.conic import Conic
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify.site_table import SiteTable

ROT = [(Fraction(1), Fraction(0)), (Fraction(3, 5), Fraction(4, 5)), (Fraction(5, 13), Fraction(12, 13)),
       (Fraction(8, 17), Fraction(-15, 17))]


def scene(rng, n_side=12):
    """Ellipses in the cells of an n_side² grid of side 8 (disjoint: semi-axes ≤ 3.5)."""
    ells = []
    for gx in range(n_side):
        for gy in range(n_side):
            a = Fraction(int(rng.integers(16, 56)), 16)
            b = a * Fraction(int(rng.integers(5, 15)), 16)
            cx = Fraction(8 * gx) + Fraction(int(rng.integers(-8, 9)), 16)
            cy = Fraction(8 * gy) + Fraction(int(rng.integers(-8, 9)), 16)
            ells.append((cx, cy, a, b, ROT[int(rng.integers(len(ROT)))]))
    return ells


def support(ell, U, m):
    cx, cy, a, b, (c, s) = ell
    a, b, c, s = float(a), float(b), float(c), float(s)
    along = U[:, 0] * c + U[:, 1] * s
    across = -U[:, 0] * s + U[:, 1] * c
    return U[:, 0] * (float(cx) - m[0]) + U[:, 1] * (float(cy) - m[1]) + np.hypot(a * along, b * across)


def box_distance(ell, C):
    cx, cy, a, b, (c, s) = ell
    a, b, c, s = float(a), float(b), float(c), float(s)
    hx, hy = math.hypot(a * c, b * s), math.hypot(a * s, b * c)
    dx = np.maximum(np.abs(C[:, 0] - float(cx)) - hx, 0.0)
    dy = np.maximum(np.abs(C[:, 1] - float(cy)) - hy, 0.0)
    return np.hypot(dx, dy)


@pytest.mark.parametrize("seed", range(3))
def test_a_site_left_out_is_beyond_reach_or_below_the_level(seed):
    rng = np.random.default_rng(seed)
    ells = scene(rng)
    sites = [Conic.ellipse(centre=(cx, cy), axes=(a, b), rotation=rot) for cx, cy, a, b, rot in ells]
    table = SiteTable([site_geometry(s) for s in sites], 100.0)
    n = len(ells)
    m = np.array([44.0, 44.0])
    mu = 1e-9
    # rows near the sites (reach 1..10: the k-d tree) and far out (reach ≈ their distance + up to 30 %)
    near = rng.uniform(-5, 95, (60, 2))
    ang = rng.uniform(0, 2 * math.pi, 90)
    t = np.exp(rng.uniform(math.log(80), math.log(5000), 90))
    far = m + np.column_stack([t * np.cos(ang), t * np.sin(ang)])
    C = np.vstack([near, far])
    reach = np.concatenate([rng.uniform(1, 10, 60), (t - 60) * rng.uniform(1.0, 1.3, 90) + 20])
    reach[-3:] = np.inf
    r = len(C)
    # levels: u toward the row (or random), base at a quantile of the sites' support values
    U = np.empty((r, 2, 2))
    base = np.empty((r, 2))
    for s_ in (0, 1):
        th = np.where(rng.random(r) < 0.7, np.arctan2(C[:, 1] - m[1], C[:, 0] - m[0]) + rng.normal(0, 0.2, r),
                      rng.uniform(0, 2 * math.pi, r))
        U[:, s_] = np.column_stack([np.cos(th), np.sin(th)])
        H = np.array([support(e, U[:, s_], m) for e in ells])          # (site, row)
        base[:, s_] = [np.quantile(H[:, q], rng.uniform(0.2, 1.0)) for q in range(r)]
    base[rng.random((r, 2)) < 0.1] = -np.inf
    pair = (0, 1)
    rows, ks = table.near_pairs(C, reach, pair, levels=(U, base, m, mu))
    got = set(zip(rows.tolist(), ks.tolist()))
    assert len(got) == len(rows)
    within = np.array([box_distance(e, C) for e in ells]) <= reach[None, :] * (1 + 1e-9) + 1e-9   # (site, row)
    gap = np.stack([base[:, s_][None, :] - np.array([support(e, U[:, s_], m) for e in ells]) for s_ in (0, 1)]).max(0)
    dropped = 0
    for k in range(2, n):
        for q in range(r):
            if (q, k) in got:
                assert box_distance(ells[k], C[q:q + 1])[0] <= reach[q] * (1 + 1e-9) + 1e-9, (q, k)
            elif within[k, q]:
                # left out within reach: proved farther by the half-plane bound
                assert gap[k, q] > 2 * mu - 1e-9, (q, k, gap[k, q])
                dropped += 1
    assert dropped > 1000                     # the groups did leave sites out
    # sites just above the level (undecided) are kept
    kept_tight = sum((q, k) in got for k in range(2, n) for q in range(r) if within[k, q] and gap[k, q] < 0)
    assert kept_tight > 100


@pytest.mark.parametrize("seed", range(3))
def test_without_levels_every_box_within_reach_is_listed(seed):
    """``near_pairs`` without levels (the candidates of the conic vertices' emptiness test,
    runtime/voronoi/verify/vertices.py, and of the strips): exactly the (row, site) pairs whose
    exact bounding box comes within the row's reach, up to 10⁻⁹; the sites of ``pair`` never;
    with a hyperbola added (an unbounded box), that site on every row."""
    rng = np.random.default_rng(100 + seed)
    ells = scene(rng, n_side=8)
    sites = [Conic.ellipse(centre=(cx, cy), axes=(a, b), rotation=rot) for cx, cy, a, b, rot in ells]
    hyp = Conic.from_coefficients(1, 0, -1, -200, 0, 9999)       # (x − 100)² − y² = 1, far right
    table = SiteTable([site_geometry(s) for s in sites + [hyp]], 100.0)
    C = rng.uniform(-10, 70, (200, 2))
    reach = rng.exponential(6.0, 200)
    rows, ks = table.near_pairs(C, reach, (3, 5))
    got = set(zip(rows.tolist(), ks.tolist()))
    assert len(got) == len(rows)
    D = np.array([box_distance(e, C) for e in ells])               # (site, row)
    for q in range(len(C)):
        for k in range(len(ells)):
            if k in (3, 5):
                assert (q, k) not in got
            elif D[k, q] <= reach[q] * (1 - 1e-9):
                assert (q, k) in got, (q, k)
            elif D[k, q] > reach[q] * (1 + 1e-9) + 1e-9:
                assert (q, k) not in got, (q, k)
        assert (q, len(ells)) in got
