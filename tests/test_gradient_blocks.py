"""The verifier's gradient enclosures in blocks of rows (runtime/voronoi/verify/site_table.py:
``gradient_enclosure`` cuts more than ``GRADIENT_ROWS`` rows into blocks, so that its
temporaries stay bounded on 2000 ellipses).

Every row of the enclosure depends on that row's data alone (the cheap enclosure, the
Lagrange-multiplier enclosure of runtime/voronoi/verify/ellipse_normal.py, the Clarke boxes deep
inside a site), so blocks of any size must give the very same floats.  Checked with blocks of 3
and 7 rows against one block on random rows near random ellipses, circles and a point (outside,
inside and on the sites), and the enclosures are checked to hold: the exact gradient at the row
point (an ellipse's foot point by dense sampling of the curve) lies within the slack.
"""
from __future__ import annotations

import numpy as np
import pytest

from scenes import random_disjoint_circles, random_ellipses

import curvedvoronoi as cv
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify import site_table
from curvedvoronoi.runtime.voronoi.verify.site_table import SiteTable, gradient_enclosure


def rows_near(table, m, rng):
    K = rng.integers(0, table.n, m)
    bx = table.boxes[K]
    ctr, half = 0.5 * (bx[:, :2] + bx[:, 2:]), 0.5 * (bx[:, 2:] - bx[:, :2])
    Q = ctr + rng.uniform(-4, 4, (m, 2)) * np.maximum(half, 0.5)
    return Q, K


def sampled_gradient(g, q):
    """∇d(q, S) = (q − p)/|q − p| with p the nearest of 200001 points of the ellipse (or the
    circle) S: the true gradient within the sampling's angle."""
    t = np.linspace(0.0, 2 * np.pi, 200001)
    if g.kind == "circle":
        P = np.column_stack([g.cx + g.rho * np.cos(t), g.cy + g.rho * np.sin(t)])
    else:
        X, Y = g.a * np.cos(t), g.b * np.sin(t)
        P = np.column_stack([g.tx + g.c * X - g.s * Y, g.ty + g.s * X + g.c * Y])
    d = np.hypot(*(q - P).T)
    p = P[np.argmin(d)]
    return (q - p) / np.hypot(*(q - p)), float(d.min())


@pytest.mark.parametrize("seed", [1, 2])
@pytest.mark.parametrize("rows", [3, 7])
def test_gradient_blocks_equal_one_block(seed, rows, monkeypatch):
    sites = (list(random_ellipses(12, seed)) + [cv.Circle(*c) for c in random_disjoint_circles(6, seed)]
             + [cv.Point(0.25, -1.5)])
    geoms = [site_geometry(s) for s in sites]
    table = SiteTable(geoms, 40.0)
    rng = np.random.default_rng(seed)
    Q, K = rows_near(table, 101, rng)
    V = table.evaluate(Q, K)
    R = rng.uniform(0.0, 0.05, len(K))
    whole = gradient_enclosure(Q, V, R, 40.0)
    monkeypatch.setattr(site_table, "GRADIENT_ROWS", rows)
    blocks = gradient_enclosure(Q, V, R, 40.0)
    for a, b in zip(whole, blocks):
        assert a.shape == b.shape and np.array_equal(a, b, equal_nan=a.dtype.kind == "f")
    G, slack, valid = whole
    assert valid.sum() > 20             # enclosures were found (not a comparison of failures)
    checked = 0
    for m in np.nonzero(valid)[0][:40]:
        g = geoms[K[m]]
        if g.kind not in ("circle", "ellipse"):
            continue
        gt, d = sampled_gradient(g, Q[m])
        if d < 1e-2:
            continue
        # the sampling's error: the foot moves by ≤ (perimeter/200000) along the curve
        assert np.hypot(*(G[m] - gt)) <= slack[m] + 1e-3 / d + 1e-9
        checked += 1
    assert checked > 5
