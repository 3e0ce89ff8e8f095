"""Edge polylines through a narrow gap between two ellipses.

Three ellipses of ``tests/scenes.random_ellipses(10010, 1)`` (indices 2966, 5839, 8303): the
bisector of the last two passes through a gap of about 0.14 between them.  Chord midpoints of its
polyline lie inside the smaller ellipse, where Newton's steps on d_i − d_j stalled 0.1 off the
bisector; the construction inserted them anyway, the polyline turned by 48° at them and the
10⁴-ellipse diagram was not certified.  The ellipses are written here from their geometry (centre,
squared semi-axes, rotation by a Pythagorean cosine and sine); the reference distances are mpmath
minimisations over the parametrisation, no library distance code.
"""
from fractions import Fraction as F

import mpmath as mp
import numpy as np
import pytest

import curvedvoronoi as cv

pytestmark = pytest.mark.mpmath_dps(30)

#: (centre, A², B², cos, sin) of the three ellipses
ELLIPSES = [
    ((F(11773, 16), F(727, 32)), F(841, 256), F(142129, 65536), F(0), F(1)),
    ((F(5893, 8), F(217, 8)), F(841, 256), F(68121, 65536), F(3, 5), F(4, 5)),
    ((F(11819, 16), F(2001, 64)), F(121, 16), F(20449, 4096), F(5, 13), F(12, 13)),
]


def implicit(centre, A2, B2, c, s):
    """Coefficients of ((x − cx)c + (y − cy)s)²/A² + (−(x − cx)s + (y − cy)c)²/B² = 1, scaled by A²B²."""
    cx, cy = centre
    # u = c x + s y − (c cx + s cy), v = −s x + c y − (−s cx + c cy)
    u = (c, s, -(c * cx + s * cy))
    v = (-s, c, s * cx - c * cy)

    def sq(w, k):
        x, y, z = w
        return [k * x * x, k * 2 * x * y, k * y * y, k * 2 * x * z, k * 2 * y * z, k * z * z]

    co = [p + q for p, q in zip(sq(u, B2), sq(v, A2))]
    co[5] -= A2 * B2
    return co


def reference_distance(e, p):
    """min over t of |p − γ(t)| for the ellipse e, by a grid and mpmath's root of the derivative."""
    (cx, cy), A2, B2, c, s = e
    a, b = mp.sqrt(mp.mpf(A2.numerator) / A2.denominator), mp.sqrt(mp.mpf(B2.numerator) / B2.denominator)
    cx, cy, c, s = (mp.mpf(q.numerator) / q.denominator for q in (cx, cy, c, s))
    px, py = mp.mpf(p[0]), mp.mpf(p[1])

    def g(t):
        x = cx + c * a * mp.cos(t) - s * b * mp.sin(t)
        y = cy + s * a * mp.cos(t) + c * b * mp.sin(t)
        return (x - px) ** 2 + (y - py) ** 2

    ts = [2 * mp.pi * k / 720 for k in range(720)]
    t0 = min(ts, key=g)
    t = mp.findroot(lambda t: mp.diff(g, t), t0)
    return mp.sqrt(min(g(t), g(t0)))


def diagram():
    sites = [cv.Conic.from_coefficients(*implicit(*e)) for e in ELLIPSES]
    return cv.voronoi(sites, progress=False, certify=True)


def test_the_written_ellipses_are_the_benchmark_ones():
    """The geometry above gives the exact coefficients of the scene (up to a common factor)."""
    listed = [(262144, 0, 173056, -385777664, -7863232, 142018766581),
              (49408, -43008, 36864, -71623744, 29680896, 25977304939),
              (2629696, -668160, 1967104, -3864156688, 370555968, 1421395466241)]
    for e, want in zip(ELLIPSES, listed):
        got = implicit(*e)
        k = got[0] / want[0]
        assert all(g == k * w for g, w in zip(got, want))


def test_narrow_gap_edge_certified_and_on_the_bisector():
    d = diagram()
    assert d.certified, [str(p) for p in d.problems]
    (gap,) = [e for e in d.edges if set(e.sites) == {1, 2}]
    P = np.asarray(gap.polyline, float)
    assert len(P) >= 10
    for p in P:
        if np.hypot(*(p - [737.0, 28.0])) > 20:          # the far end of the unbounded side
            continue
        d1, d2 = reference_distance(ELLIPSES[1], p), reference_distance(ELLIPSES[2], p)
        assert abs(d1 - d2) / 2 <= gap.tolerance
        assert abs(d1 - d2) < 1e-6 * (1 + d1), (p, d1, d2)
    # the nodes next to the gap (within 0.5 of the smaller ellipse) are on the bisector too
    near = [p for p in P if reference_distance(ELLIPSES[1], p) < 0.5]
    assert len(near) >= 3
