"""(M) of the tail argument (runtime/voronoi/verify/tail.py, module docstring): a cell of the sector
{t ≥ T0, θ ∈ [θa, θb]} is accepted only where σ·∂f/∂θ > 0 on the whole cell, f = d_i − d_j.

The expectation is the derivative sampled densely on each cell in closed form: for a circle
S = D(c, r) and q = m + t·u(θ) outside it, ∂d_S/∂θ = t·(q − c)/|q − c|·u⊥(θ).  Every cell is asked
with both signs σ = ±1: a cell across which the derivative changes sign must be refused for both,
and a cell where it has one sign must be refused for the wrong one, however small the derivative
(far cells, where both gradients nearly agree, are where a loosened fallback test would accept)."""
import math

import numpy as np
import pytest

import curvedvoronoi as cv
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify import tail
from curvedvoronoi.runtime.voronoi.verify.conic_tail import quarter_cells, sector_grid
from curvedvoronoi.runtime.voronoi.verify.site_table import SiteTable
from curvedvoronoi.runtime.voronoi.verify.support import SupportTable

#: each first cell quartered three times: cells of 1/64 of the sector's first grid cells, small enough
#: that (M) decides many and that the tight scene below meets its enclosure's angular term
ROUNDS = 3
#: circles of different radii and a point; and two points at the ends of a diameter of the sites'
#: disc, where the variation of h_j' − h_i' over a cell, |c_i − c_j|·δ = 2W·δ, equals the
#: enclosure's angular term (the enclosure is tight there)
SCENES = {"circles": [((-1.5, 0.3), 0.7), ((1.2, -0.4), 0.3), ((0.2, 1.1), 0.0)],
          "diametral points": [((-1.0, 0.0), 0.0), ((1.0, 0.0), 0.0)]}
CASES = [("circles", (0, 1)), ("circles", (1, 2)), ("circles", (0, 2)), ("diametral points", (0, 1))]


def scene(circles):
    sites = [cv.Circle.from_radius(x, y, r) if r else cv.Point(x, y) for (x, y), r in circles]
    geoms = [site_geometry(s) for s in sites]
    return SupportTable(geoms), SiteTable(geoms, 10.0)


def sampled_derivative(circles, m, pair, tau, th):
    """∂f/∂θ on the grid of (τ, θ) samples, in closed form (module docstring); τ > 0."""
    t = 1.0 / tau
    q = m + t[..., None] * np.stack([np.cos(th), np.sin(th)], -1)
    perp = np.stack([-np.sin(th), np.cos(th)], -1)
    out = 0.0
    for s, sign in zip(pair, (1.0, -1.0)):
        c = np.array(circles[s][0])
        v = q - c
        out = out + sign * t * (v * perp).sum(-1) / np.hypot(v[..., 0], v[..., 1])
    return out


def cells_of(sec, rounds):
    """The sector's first grid, every cell quartered ``rounds`` times (the cells the proof visits)."""
    cells = sector_grid(sec.tha, sec.thb, 1.0 / sec.T0)
    for _ in range(rounds):
        cells = quarter_cells(cells, np.ones(len(cells[0]), bool), W=sec.sup.W)
    return cells


@pytest.mark.parametrize("name,pair", CASES)
@pytest.mark.parametrize("sector", range(8))
def test_monotone_cells_have_the_sign_of_the_sampled_derivative(name, pair, sector):
    sup, table = scene(SCENES[name])
    # sectors offset from the axes, so that the derivative's zeros at θ = 0, ±π/2, π of the
    # symmetric scene fall inside cells, not on their sides
    tha = -math.pi + sector * math.pi / 4 + 0.0123
    thb = tha + math.pi / 4
    T0 = 3.0 * sup.W
    proved_any = 0
    for sigma in (1.0, -1.0):
        sec = tail._Sector(sup, table, pair, tha, thb, sigma, T0, 10.0, tail.TAIL_WORK)
        ta, tb, h0, h1 = cells_of(sec, ROUNDS)
        c = tail._cell_discs(sec, ta, tb, h0, h1)
        pv = tail._pair_values(sec, c)
        okM = tail._monotone(sec, c, pv)
        proved_any += int(okM.sum())
        # samples on each cell: τ from its far end (τa > 0, or a far point of an infinite cell) to τb
        s = np.linspace(0.0, 1.0, 9)
        tau = np.maximum(ta[:, None] + s[None, :] * (tb - ta)[:, None], 1e-9 * tb[:, None])
        th = h0[:, None] + s[None, :] * (h1 - h0)[:, None]
        T, H = tau[:, :, None], th[:, None, :]
        T, H = np.broadcast_arrays(T, H)
        d = sigma * sampled_derivative(SCENES[name], sup.m, pair, T, H)
        bad = okM & (d.reshape(len(ta), -1) <= 0).any(1)
        assert not bad.any(), (f"cells accepted where σ·∂f/∂θ ≤ 0 at a sample: sigma={sigma}, "
                               f"{np.nonzero(bad)[0][:5]}")
    assert proved_any > 0          # the test is not vacuous: some cells are decided
