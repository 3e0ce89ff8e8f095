"""The reach bound of the ellipse updates (runtime.voronoi.conflict: cell_radius, arc_reach,
inequalities (1)-(3) of its docstring) tested at its boundary, against closed forms.

For disc sites (c_k, R_k) the region of i among T in the bound's sense,
{q : |q − c_i| − R_i ≤ |q − c_k| + R_k for k ∈ T}, is star-shaped from c_i and its boundary in
the direction u is at the exact distance t*(u) = min_k (|w|² − s²) / (2 (u·w − s)) over the k with
u·w > s (w = c_k − c_i, s = R_i + R_k; the closed form of the squared inequality).  The tests:

* the farthest boundary point q* (maximised over directions with scipy, not sampled on a grid)
  satisfies the region's inequalities with equality for one k and lies within ρ: ρ ≥ |q* − c_i|,
  and ρ is not wasteful (≤ 1.25 |q* − c_i|);
* a square of point sites, whose region is the square of half side d/2 with its corners at
  exactly d/√2, and three sites at 120° (a triangle) are bounded; three sites on a half circle
  leave the region unbounded and give None, and so does one missing direction by a hair;
* the worst site for the reach: a disc k placed on the far side of the empty circle of q* (radius
  |q* − c_i| + R_i, the upper bound of d(q*, S_i)), touching it from outside, has its centre at
  distance 2|q* − c_i| + R_i + R_k ≤ arc_reach + R_k; a site whose disc stays clear of that
  circle has more distance and the bound does not claim it (no test of a strict superset);
* the same through the adjacency state's search: ``near(c_i, arc_reach + rmax)`` holds that
  worst site.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from curvedvoronoi.runtime.voronoi.conflict import arc_reach, cell_radius


def _t_star(C, R, i, T, theta):
    """Exact distance from c_i to the region's boundary in direction theta (inf: unbounded)."""
    u = np.array([math.cos(theta), math.sin(theta)])
    best = math.inf
    for k in T:
        w = C[k] - C[i]
        s = R[i] + R[k]
        uw = float(u @ w)
        if uw > s:
            best = min(best, (float(w @ w) - s * s) / (2 * (uw - s)))
    return best


def _farthest(C, R, i, T):
    """(θ*, t*) maximising the boundary distance: a fine scan, then a bounded scalar maximisation
    around the best scan point (t* is piecewise smooth in θ)."""
    th = np.linspace(0, 2 * math.pi, 4097)[:-1]
    vals = np.array([_t_star(C, R, i, T, t) for t in th])
    j = int(np.argmax(vals))
    step = th[1] - th[0]
    res = minimize_scalar(lambda t: -_t_star(C, R, i, T, t), bounds=(th[j] - step, th[j] + step),
                          method="bounded", options={"xatol": 1e-13})
    return (float(res.x), -float(res.fun)) if -res.fun >= vals[j] else (float(th[j]), float(vals[j]))


def _random_surrounded(seed):
    rng = np.random.default_rng(seed)
    while True:
        m = int(rng.integers(4, 12))
        ang = np.sort(rng.uniform(0, 2 * math.pi, m))
        dist = rng.uniform(3, 12, m)
        C = np.vstack([[0.0, 0.0], np.column_stack([dist * np.cos(ang), dist * np.sin(ang)])])
        C += rng.uniform(-100, 100, 2)
        R = np.concatenate([[rng.uniform(0.0, 1.0)], rng.uniform(0.0, 1.2, m)])
        if rng.random() < 0.3:
            R[:] = 0.0                                      # point sites
        T = list(range(1, m + 1))
        if all(np.hypot(*(C[k] - C[0])) > R[0] + R[k] for k in T) and cell_radius(C, R, 0, T) is not None:
            return C, R, T


@pytest.mark.parametrize("seed", range(12))
def test_cell_radius_holds_the_farthest_boundary_point(seed):
    C, R, T = _random_surrounded(seed)
    theta, t = _farthest(C, R, 0, T)
    q = C[0] + t * np.array([math.cos(theta), math.sin(theta)])
    # q* is on the boundary: one inequality of the region is an equality, none is violated
    gap = np.array([np.hypot(*(q - C[k])) + R[k] - (np.hypot(*(q - C[0])) - R[0]) for k in T])
    assert gap.min() == pytest.approx(0.0, abs=1e-9 * (1 + t))
    assert (gap >= -1e-9 * (1 + t)).all()
    rho = cell_radius(C, R, 0, T)
    assert rho >= t
    assert rho <= 1.25 * t


def test_square_of_points_reaches_its_corners():
    d = 3.0
    C = np.array([[0.0, 0.0], [d, 0.0], [-d, 0.0], [0.0, d], [0.0, -d]])
    R = np.zeros(5)
    rho = cell_radius(C, R, 0, [1, 2, 3, 4])
    corner = d / math.sqrt(2)                       # the region is the square |x|, |y| ≤ d/2
    assert corner <= rho <= 1.1 * corner
    assert arc_reach(C, R, 0, [1, 2, 3, 4]) == pytest.approx(2 * rho)


def test_open_and_closed_fans_of_sites():
    R = np.zeros(4)
    tri = np.array([[0.0, 0.0]] + [[4 * math.cos(a), 4 * math.sin(a)] for a in (0, 2 * math.pi / 3, 4 * math.pi / 3)])
    # a triangle of sites: the region is the triangle with vertices at distance 4 (circumradius
    # of the triangle formed by the three bisectors)
    rho = cell_radius(tri, R, 0, [1, 2, 3])
    assert rho is not None and 4.0 <= rho
    half = np.array([[0.0, 0.0]] + [[4 * math.cos(a), 4 * math.sin(a)] for a in (0, math.pi / 2, math.pi)])
    assert cell_radius(half, R, 0, [1, 2, 3]) is None            # open towards −y
    # the same with the third site a hair past the half circle: still open (between π + 1e-6 and
    # 2π the sites offer no bound on a half-line of directions), hence None
    hair = np.array([[0.0, 0.0]] + [[4 * math.cos(a), 4 * math.sin(a)] for a in (0, math.pi / 2, math.pi + 1e-6)])
    assert cell_radius(hair, R, 0, [1, 2, 3]) is None


@pytest.mark.parametrize("seed", range(12))
def test_the_worst_site_is_within_reach(seed):
    C, R, T = _random_surrounded(seed)
    theta, t = _farthest(C, R, 0, T)
    u = np.array([math.cos(theta), math.sin(theta)])
    q = C[0] + t * u
    r_q = t + R[0]                      # the bound of d(q*, S_0) the argument uses
    for R_k in (0.0, 0.7, 3.0):
        c_k = q + (r_q + R_k) * u       # disc k touches the empty circle of q* from outside
        reach = arc_reach(C, R, 0, T)
        assert np.hypot(*(c_k - C[0])) <= reach + R_k
        # with a bound of half the reach the worst site would be missed: the factor 2 is needed
        assert np.hypot(*(c_k - C[0])) > (reach - R[0]) / 2 + R[0] + R_k - 1e-9 or t < 1e-9


def test_the_adjacency_search_returns_the_worst_site():
    import curvedvoronoi as cv
    from curvedvoronoi.runtime.voronoi.adjacency import DynamicState
    from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
    from curvedvoronoi.runtime.voronoi.site_input import as_site

    C, R, T = _random_surrounded(3)
    R = np.maximum(R, 0.05)
    d = cv.voronoi([(float(x), float(y), float(r)) for (x, y), r in zip(C, R)], certify=False)
    dyn = DynamicState(d)
    theta, t = _farthest(dyn.C, dyn.R, 0, T)
    u = np.array([math.cos(theta), math.sin(theta)])
    R_k = float(dyn.R.max())
    c_k = dyn.C[0] + (2 * t + dyn.R[0] + R_k) * u * (1 - 1e-12)
    s = as_site((float(c_k[0]), float(c_k[1]), R_k))
    dyn.add_site(s, site_geometry(s))
    reach = arc_reach(dyn.C, dyn.R, 0, T)
    assert len(dyn.C) - 1 in dyn.near(dyn.C[0], reach * (1 + 1e-9) + dyn.rmax)
