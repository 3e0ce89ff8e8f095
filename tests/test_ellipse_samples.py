"""The samples of many ellipses drawn together (runtime/voronoi/conic_geometry.ellipse_samples, used
by the construction's sampling, runtime/voronoi/sampling.sample_sites).

Mathematical facts, with independent references: every sample lies on its exact ellipse (the
conic's rational equation evaluated by mpmath at the float point, relative to the size of the
terms), consecutive samples (the last joined to the first) are at most the spacing apart, and
their number is the perimeter's share: 1.1·P/spacing within one, P = 4a·E(1 − b²/a²) from
mpmath's complete elliptic integral (the sampler measures a 2048-chord polyline, shorter than P
by less than 1e-5 relative).  And the contract the construction relies on for unchanged
diagrams: the points are those of each site geometry's own ``samples``, float for float."""
from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest

import curvedvoronoi as cv
from curvedvoronoi.runtime.voronoi.conic_geometry import ellipse_samples, site_geometry
from scenes import random_ellipses


def _ellipses():
    sites = list(random_ellipses(12, 3))
    sites += [cv.Conic.ellipse(centre=(5, -3), axes=(7, "1/50"), rotation=("3/5", "4/5")),   # thin
              cv.Conic.ellipse(centre=(-1000, 2000), axes=(3, 2), degrees=90),
              cv.Conic.ellipse(centre=(0, 0), axes=("1/1000", "1/1024"))]
    return sites, [site_geometry(s) for s in sites]


def _on_conic(conic, P):
    """Largest |f(p)| / (sum of |terms|) over the points (the exact rational conic, mpmath)."""
    a, b, c, d, e, f = (mpmath.mpf(v.numerator) / v.denominator for v in conic.coefficients)
    worst = 0.0
    for x, y in P.tolist():
        x, y = mpmath.mpf(x), mpmath.mpf(y)
        terms = [a * x * x, b * x * y, c * y * y, d * x, e * y, f]
        worst = max(worst, float(abs(sum(terms)) / sum(abs(t) for t in terms)))
    return worst


def test_samples_lie_on_their_ellipses_within_the_spacing():
    sites, geoms = _ellipses()
    with mpmath.workdps(30):
        perims = [float(4 * g.a * mpmath.ellipe(1 - (mpmath.mpf(g.b) / g.a) ** 2)) for g in geoms]
    sp = np.array([p / k for p, k in zip(perims, [7, 40, 13, 300, 5, 64, 9, 100, 21, 3, 77, 500, 30, 11, 200])])
    P, n = ellipse_samples(geoms, sp)
    assert len(P) == n.sum()
    parts = np.split(P, np.cumsum(n)[:-1])
    for s, per, spacing, Q in zip(sites, perims, sp, parts):
        assert _on_conic(s, Q) < 1e-13
        closed = np.vstack([Q, Q[:1]])
        assert np.hypot(*np.diff(closed, axis=0).T).max() <= spacing
        assert abs(len(Q) - 1.1 * per / spacing) <= 1.0 + 1e-9 * len(Q)


@pytest.mark.parametrize("rel", [0.3, 0.05, 0.004, 1e-5])
def test_samples_are_each_geometrys_own_float_for_float(rel):
    _, geoms = _ellipses()
    rng = np.random.default_rng(7)
    sp = np.array([(g.a + g.b) * rel * rng.uniform(0.5, 2.0) for g in geoms])
    P, n = ellipse_samples(geoms, sp)
    own = [np.asarray(g.samples(float(s)), float).reshape(-1, 2) for g, s in zip(geoms, sp)]
    assert n.tolist() == [len(q) for q in own]
    assert np.array_equal(P, np.concatenate(own))          # bit for bit, not within a tolerance


def test_blocks_do_not_change_the_samples(monkeypatch):
    from curvedvoronoi.runtime.voronoi import conic_geometry
    _, geoms = _ellipses()
    sp = np.array([(g.a + g.b) * 0.1 for g in geoms])
    P, n = ellipse_samples(geoms, sp)
    monkeypatch.setattr(conic_geometry, "SAMPLE_BLOCK", 4)
    P4, n4 = ellipse_samples(geoms, sp)
    assert np.array_equal(P, P4) and np.array_equal(n, n4)
    assert math.isclose(len(P), sum(len(g.samples(float(s))) for g, s in zip(geoms, sp)))
