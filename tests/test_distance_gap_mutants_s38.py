"""Mutants of :mod:`curvedvoronoi.runtime.voronoi.verify.distance_gap` (mutation sample seed 38).

The second-order lower bound of d_k − d_i on a disc B(Q, R) needs d_k convex on the disc: for a
hyperbola, d_k is the minimum of the distances to its two branches, convex only where one branch
is the nearer on the whole disc (the disc clear of the conjugate axis).  Across that axis d_k has
a concave kink: walking away from the nearer branch, d_k grows up to the axis and then falls
with the other branch's slope, below the linear extrapolation from Q.

Sites: k = {x² − y² = 1} and i = {(x − 9/100)² − y² = (99/100)²}, rectangular hyperbolas opening
along the x-axis.  On the x-axis, at a point (x, 0) between the branches of a rectangular
hyperbola (x − h)² − y² = a², the nearest points are the vertices: the squared distance to
(h + s, y) is (s − t)² + s² − a² (t = x − h), whose minimum over |s| ≥ a is at s = ±a since the
free minimum t/2 has |t/2| < a; so d = a − |x − h| (closed form).  Off the axis the reference
distance is a dense minimisation over the branches (h ± a·cosh u, a·sinh u).
"""
from __future__ import annotations

from fractions import Fraction as Fr

import numpy as np
from scipy.optimize import minimize_scalar

from curvedvoronoi.runtime.sites.conic import Conic
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify.curved_edges import curved_scale
from curvedvoronoi.runtime.voronoi.verify.distance_gap import gap_lower
from curvedvoronoi.runtime.voronoi.verify.site_table import SiteTable

HK, AK = 0.0, 1.0          # site k: centre (HK, 0), semi-axes AK = AK
HI, AI = 0.09, 0.99        # site i
R = 0.1


def _table():
    sites = [Conic.hyperbola(centre=(0, 0), axes=(1, 1)),
             Conic.hyperbola(centre=(Fr(9, 100), 0), axes=(Fr(99, 100), Fr(99, 100)))]
    geoms = [site_geometry(s) for s in sites]
    return SiteTable(geoms, curved_scale(geoms))


def _bound(table, Q):
    Q = np.array([Q], float)
    return float(gap_lower(Q, table.evaluate(Q, [0]), table.evaluate(Q, [1]), R, table.scale)[0])


def _on_axis(h, a, x):
    """Distance from (x, 0), between the branches, to (x − h)² − y² = a² (module docstring)."""
    return a - abs(x - h)


def _distance(h, a, q):
    """Distance from q to (x − h)² − y² = a²: dense grid over both branches, then refined."""
    best = np.inf
    for side in (-1.0, 1.0):
        def f(u):
            return float(np.hypot(h + side * a * np.cosh(u) - q[0], a * np.sinh(u) - q[1]))
        us = np.linspace(-4, 4, 801)
        vals = [f(u) for u in us]
        u0 = us[int(np.argmin(vals))]
        res = minimize_scalar(f, bounds=(u0 - 0.02, u0 + 0.02), method="bounded", options={"xatol": 1e-12})
        best = min(best, float(res.fun), min(vals))
    return best


def test_no_gap_is_claimed_on_a_disc_across_the_conjugate_axis():
    """Q = (−1/1000, 0): k's conjugate axis x = 0 is 0.001 from Q, inside B(Q, 0.1).  At Q,
    d_k − d_i = 0.999 − 0.899 = 0.1 and both gradients are (1, 0), yet at q = (0.085, 0) in the
    disc d_k − d_i = (1 − 0.085) − (0.99 − 0.005) = −0.07: no positive lower bound exists."""
    table = _table()
    Q = (-1e-3, 0.0)
    q = (0.085, 0.0)
    assert np.hypot(q[0] - Q[0], q[1] - Q[1]) < R
    assert _on_axis(HK, AK, Q[0]) - _on_axis(HI, AI, Q[0]) > 0.09      # the gap at the centre
    low_true = _on_axis(HK, AK, q[0]) - _on_axis(HI, AI, q[0])
    assert low_true < -0.05
    assert _bound(table, Q) <= low_true


def test_a_gap_is_proved_on_a_disc_clear_of_both_conjugate_axes():
    """Q = (−1/2, 0): the disc B(Q, 0.1) is 0.4 from k's conjugate axis and 0.49 from i's, so
    each d is convex there; the bound is positive and below d_k − d_i on a grid of the disc."""
    table = _table()
    Q = (-0.5, 0.0)
    low = _bound(table, Q)
    assert low > 0
    g = np.linspace(-R, R, 15)
    for dx in g:
        for dy in g:
            if dx * dx + dy * dy <= R * R:
                q = (Q[0] + dx, Q[1] + dy)
                assert low <= _distance(HK, AK, q) - _distance(HI, AI, q)
