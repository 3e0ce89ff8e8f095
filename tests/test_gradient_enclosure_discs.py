"""The gradient enclosures of the verifier (runtime/voronoi/verify/site_table.py,
``gradient_enclosure``) on discs outside convex sites: |∇d(q) − G| ≤ slack at every q of B(Q, R).

The disc term R/(d(Q) − R) rests on I − P being 1-Lipschitz for the projection P onto a closed
convex set.  For a point site it is nearly tight: at distance d, the points of the disc seen at the
largest angle from the site have ∇d turned by asin(R/d) from ∇d(Q), i.e. moved by ≈ R/d — so any
enclosure smaller than about half of it fails at those points.  Expectations: ∇d(q) = (q − p)/|q − p|
with p the nearest point, for points in closed form and for ellipses by dense sampling refined with
scipy, independently of the verifier."""
import math

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

import curvedvoronoi as cv
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify import strips
from curvedvoronoi.runtime.voronoi.verify.site_table import SiteTable, gradient_enclosure


def ellipse_foot(e, q):
    cx, cy, a, b, rot = e
    c, s = math.cos(rot), math.sin(rot)

    def pt(t):
        x, y = a * math.cos(t), b * math.sin(t)
        return np.array([cx + c * x - s * y, cy + s * x + c * y])

    ts = np.linspace(0, 2 * math.pi, 2001)
    k = int(np.argmin([np.hypot(*(pt(t) - q)) for t in ts]))
    res = minimize_scalar(lambda t: float(np.hypot(*(pt(t) - q))), bounds=(ts[k] - 0.004, ts[k] + 0.004),
                          method="bounded", options={"xatol": 1e-13})
    return pt(res.x)


def rim(Q, R, n=64):
    ang = np.linspace(0, 2 * math.pi, n, endpoint=False)
    return Q[None, :] + R * np.column_stack([np.cos(ang), np.sin(ang)])


@pytest.mark.parametrize("ratio", [0.02, 0.1, 0.3, 0.45])
def test_point_site_enclosure_holds_on_the_disc_and_is_nearly_tight(ratio):
    table = SiteTable([site_geometry(cv.Point(0, 0))], 10.0)
    d = 7.0
    Q = np.array([[d * math.cos(0.3), d * math.sin(0.3)]])
    R = np.array([ratio * d])
    V = strips.evaluate_rows(table, Q, np.array([0]))
    G, slack, valid = gradient_enclosure(Q, V, R, table.scale)
    assert valid[0]
    pts = rim(Q[0], R[0], 720)
    grad = pts / np.hypot(*pts.T)[:, None]
    dev = np.hypot(*(grad - G[0]).T)
    assert dev.max() <= slack[0]
    assert dev.max() > 0.55 * slack[0]          # nearly tight: half the slack would fail here


@pytest.mark.parametrize("seed", range(4))
def test_ellipse_enclosures_hold_on_the_disc(seed):
    rng = np.random.default_rng(seed)
    a = rng.uniform(1, 3)
    e = (rng.uniform(-2, 2), rng.uniform(-2, 2), a, a * rng.uniform(0.2, 1), rng.uniform(0, math.pi))
    geoms = [site_geometry(cv.Conic.ellipse(centre=(e[0], e[1]), axes=(e[2], e[3]), radians=e[4]))]
    table = SiteTable(geoms, 10.0)
    ang = rng.uniform(0, 2 * math.pi, 6)
    dist = rng.uniform(4, 30, 6)
    Q = np.column_stack([e[0] + dist * np.cos(ang), e[1] + dist * np.sin(ang)])
    R = dist * rng.uniform(0.01, 0.2, 6)
    V = strips.evaluate_rows(table, Q, np.zeros(6, int))
    G, slack, valid = gradient_enclosure(Q, V, R, table.scale)
    assert valid.any()
    for r in np.nonzero(valid)[0]:
        for q in rim(Q[r], R[r], 16):
            p = ellipse_foot(e, q)
            g = (q - p) / np.hypot(*(q - p))
            assert np.hypot(*(g - G[r])) <= slack[r] * (1 + 1e-6) + 1e-9
