"""Gradient enclosures of the verifier (runtime/voronoi/verify/site_table.py, gradient_enclosure)
on discs INSIDE a circle site: |∇d(q) − G| ≤ slack at every point q of the disc B(Q, R) where d is
differentiable, for every row marked valid.

The site is the circle of radius 10 about the origin; inside it d(q) = 10 − |q| and
∇d(q) = −q/|q| (closed form), undefined only at the centre, where d has a ridge point (its reach,
H. Federer, *Curvature measures*, 1959: the foot map is r/(r − t)-Lipschitz at depth t < r only).
A disc that holds the centre contains points with opposite gradients, so a valid enclosure there
needs slack ≥ 1; discs at every depth, from near the curve to across the centre, are tried."""
from __future__ import annotations

import math

import numpy as np
import pytest

import curvedvoronoi as cv
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify import strips
from curvedvoronoi.runtime.voronoi.verify.site_table import SiteTable, gradient_enclosure

CASES = [(s, R) for s in (0.3, 1.0, 2.0, 3.0, 4.0, 6.0, 8.0, 9.0) for R in (0.1, 0.5, 0.9, 1.5, 2.5, 3.9)
         if s + R < 9.99]


def _disc_points(Q, R, n=24):
    ang = np.linspace(0, 2 * math.pi, n, endpoint=False)
    pts = [Q + f * R * np.array([math.cos(a), math.sin(a)]) for f in (0.25, 0.5, 0.75, 1.0) for a in ang]
    return np.array(pts + [Q])


@pytest.mark.parametrize("s, R", CASES)
def test_the_enclosure_holds_on_discs_inside_the_circle(s, R):
    table = SiteTable([site_geometry(cv.Circle.from_radius(0, 0, 10))], 10.0)
    Q = np.array([[s * math.cos(0.7), s * math.sin(0.7)]])
    V = strips.evaluate_rows(table, Q, np.array([0]))
    G, slack, valid = gradient_enclosure(Q, V, np.array([R]), table.scale)
    if not valid[0]:
        return
    pts = _disc_points(Q[0], R)
    nrm = np.hypot(*pts.T)
    pts = pts[nrm > 1e-9]
    grad = -pts / np.hypot(*pts.T)[:, None]
    dev = np.hypot(*(grad - G[0]).T)
    assert dev.max() <= slack[0] * (1 + 1e-9) + 1e-12, (s, R, slack[0], dev.max())
    if s < R:                                      # the disc holds the centre: opposite gradients
        assert slack[0] >= 1


def test_discs_away_from_the_centre_are_enclosed():
    """Completeness: a disc well inside, away from the centre, gets a finite enclosure."""
    table = SiteTable([site_geometry(cv.Circle.from_radius(0, 0, 10))], 10.0)
    Q = np.array([[6 * math.cos(0.7), 6 * math.sin(0.7)]])
    V = strips.evaluate_rows(table, Q, np.array([0]))
    G, slack, valid = gradient_enclosure(Q, V, np.array([0.5]), table.scale)
    assert valid[0] and slack[0] < 0.5
