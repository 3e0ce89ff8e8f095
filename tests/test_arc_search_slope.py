"""The slope bound of the disc search (``_slope_bound`` in runtime/voronoi/verify/arc_search.py)
against gradients sampled directly: for a circle/point site s, d_s(q) = | |q − c_s| − ρ_s | has
gradient ±(q − c_s)/|q − c_s|; the bound must hold at every point of the disc B(Q, R).

The scenes put the disc far from both sites (an arc near the hull, where the bound
2|c_i − c_k|/(|Q − c_i| − R) is the one used) and near them (a site's centre just outside the
disc, where |q − c_k| is small and the factor 2 of that bound is needed), and inside a big
circle k around site i (a nested pair, where that bound does not apply)."""
from __future__ import annotations

import numpy as np
import pytest

from curvedvoronoi.runtime.voronoi.verify.arc_search import _slope_bound
from curvedvoronoi.runtime.voronoi.verify.edges import CircleTable


def _gradient(q, c, rho):
    v = q - c
    n = np.hypot(v[:, 0], v[:, 1])
    return np.sign(n - rho)[:, None] * v / n[:, None]


def _disc_points(Q, R, rng, m=4000):
    ang = rng.uniform(0, 2 * np.pi, m)
    rad = R * np.sqrt(rng.uniform(0, 1, m))
    rad[: m // 4] = R                                         # the rim, where the bound is tight
    return Q + np.c_[rad * np.cos(ang), rad * np.sin(ang)]


def _scenes(seed):
    rng = np.random.default_rng(seed)
    for _ in range(60):
        ck, ci = rng.uniform(-10, 10, 2), rng.uniform(-10, 10, 2)
        rk, ri = rng.choice([0.0, rng.uniform(0, 2)]), rng.choice([0.0, rng.uniform(0, 2)])
        if np.hypot(*(ck - ci)) <= rk + ri:
            continue
        far = rng.uniform(50, 1e5)
        u = rng.normal(size=2)
        Q = ci + far * u / np.hypot(*u)
        yield ck, rk, ci, ri, Q, rng.uniform(0.05, 0.9) * (far - ri)          # far from both sites
        # near: the disc passes within a hair of site k's circle
        dirk = rng.normal(size=2)
        dirk /= np.hypot(*dirk)
        R = rng.uniform(0.1, 5)
        Q = ck + dirk * (rk + R * (1 + rng.uniform(1e-6, 0.05)))
        if np.hypot(*(Q - ci)) - ri > R * 1.01:
            yield ck, rk, ci, ri, Q, R
        # nested: the disc inside a big circle k around site i, where d_k's gradient points
        # inwards (−(q − c_k)/|q − c_k|) and the difference is near 2 however close c_i is to c_k
        big = rng.uniform(30, 60)
        off = rng.uniform(-1, 1, 2)
        Q = ck + rng.uniform(5, big - 10) * dirk
        R = rng.uniform(0.1, 4)
        yield ck, big, ck + off, rng.choice([0.0, 0.5]), Q, R


@pytest.mark.parametrize("seed", range(6))
def test_the_slope_bound_holds_on_the_whole_disc(seed):
    rng = np.random.default_rng(1000 + seed)
    checked = 0
    for ck, rk, ci, ri, Q, R in _scenes(seed):
        table = CircleTable.from_arrays(np.array([ck, ci]), np.array([rk, ri]))
        L = float(_slope_bound(table, Q[None, :], np.array([0]), np.array([1]), np.array([R]))[0])
        q = _disc_points(Q, R, rng)
        diff = np.hypot(*(_gradient(q, ck, rk) - _gradient(q, ci, ri)).T)
        assert diff.max() <= L, (ck, rk, ci, ri, Q, R, diff.max(), L)
        checked += 1
    assert checked >= 60


def test_far_from_the_sites_the_bound_is_small():
    """An arc 10⁵ away from two sites 10 apart, on a piece of radius 5·10⁴: the gradients turn by
    about R/|Q| each, but their difference stays below 2·10/(10⁵ − 5·10⁴) = 4·10⁻⁴."""
    table = CircleTable.from_arrays(np.array([[0.0, 0.0], [10.0, 0.0]]), np.array([1.0, 2.0]))
    L = _slope_bound(table, np.array([[5.0, 1e5]]), np.array([0]), np.array([1]), np.array([5e4]))
    assert 0 < float(L[0]) <= 4.01e-4
