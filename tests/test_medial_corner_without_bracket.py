"""A drawn closed edge whose chord crosses an ellipse's medial axis between the bisector's two
corners there is refused with a problem, not an exception (runtime.voronoi.verify.medial_corners:
a crossing where no bracket of proved opposite signs is found is reported as not enclosed).

Scene: the unit circle at the origin nested in the ellipse x²/100 + y²/16 = 1 (thesis ch. 4: the
bisector is a closed curve around the circle, with a corner at each crossing of the ellipse's
medial axis, the segment |X| < 8.4 of the major axis).  The closed edge is redrawn: its nodes
with x > c + 0.3 are kept, and the loop is closed by the vertical chord x = c between the
bisector's points above and below (found on that line by bisection of d_E − d_C, d_E by dense
sampling of the ellipse).  The chord crosses the axis at (c, 0), |c| ≤ 0.1, where
d_E ≥ 4 − |c| (the disc of radius 4 about the origin lies inside the ellipse) and
d_C = |1 − |c|| ≤ 1: |d_E − d_C| ≥ 2.9, and since d_E − d_C is 2-Lipschitz, (c, 0) is at least
1.45 from the bisector, far beyond the stated tolerance: the drawing is wrong and must be refused.
No bracket exists around X = c: the bisector crosses the axis only at X ≈ ±4.49, symmetric about
the crossing up to 0.1, and d_E − d_C has one sign on (−4.49, 4.49) and the other outside."""
from __future__ import annotations

import copy
import math

import numpy as np
import pytest

import curvedvoronoi as cv

_T = np.linspace(0.0, 2 * math.pi, 200_000, endpoint=False)
_E = np.column_stack([10 * np.cos(_T), 4 * np.sin(_T)])


def _f(x, y):
    """d_E − d_C at (x, y) outside the unit circle; d_E by sampling (error ≤ 2π·10/200000)."""
    return float(np.hypot(_E[:, 0] - x, _E[:, 1] - y).min()) - (math.hypot(x, y) - 1)


def _bisector_on_vertical(x, sign):
    """The point (x, y) of the bisector with sign·y in (1, 4), by bisection (f > 0 at |y| = 1.01,
    f < 0 at |y| = 3.99)."""
    lo, hi = 1.01, 3.99
    for _ in range(48):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if _f(x, sign * mid) > 0 else (lo, mid)
    return (x, sign * 0.5 * (lo + hi))


@pytest.fixture(scope="module")
def diagram():
    d = cv.voronoi([cv.Conic.ellipse((0, 0), (10, 4)), (0, 0, 1)], progress=False)
    assert len(d.edges) == 1 and d.edges[0].closed
    return d


@pytest.mark.parametrize("c", [-0.1, -0.05])
def test_a_chord_across_the_ridge_between_the_corners_is_refused(diagram, c):
    top, bottom = _bisector_on_vertical(c, 1), _bisector_on_vertical(c, -1)
    assert abs(_f(*top)) < 1e-6 and abs(_f(*bottom)) < 1e-6
    P = np.asarray(diagram.edges[0].polyline, float)[:-1]
    keep = P[P[:, 0] > c + 0.3]
    keep = keep[np.argsort(np.arctan2(keep[:, 1], keep[:, 0]))]      # bottom, right, top
    D = copy.deepcopy(diagram)
    D.edges[0].polyline = [bottom] + [tuple(p) for p in keep] + [top, bottom]
    tol = float(D.edges[0].tolerance)
    # the chord's point on the axis is provably far from the bisector (module docstring)
    assert (4 - abs(c)) - abs(1 - abs(c)) > 2 * 10 * tol
    res = cv.verify(D)
    assert not res.ok and res.problems
