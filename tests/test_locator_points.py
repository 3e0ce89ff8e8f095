"""The conflict locator with point sites among conics (runtime.predicates.locator._locate_with_points).

Facts asserted, against an independent one-dimensional reference: for two points P1, P2 and a
conic E, every Voronoi vertex lies on the perpendicular bisector of P1P2, where it is a zero of
g(t) = |q(t) − P1| − d(q(t), E) (any such zero is a true vertex of the three sites: both distances
are minimal distances).  The zeros are found by sampling g with the oracle's float distances
(tests/reference.py, no runtime code) and refined by bisection with its mpmath distance; the
locator's vertices must be exactly these, proved, and the conflict with C4 must agree with the
oracle's distance.  A point with a parabola is answered but not claimed complete (the verifier
does not prove parabola tails), and sites that meet are refused.
"""
from __future__ import annotations

import math
from fractions import Fraction as F

import mpmath
import numpy as np
import pytest

import curvedvoronoi as cv
from reference import RefConic, _grid_dist, ref_distance


def _E(c, ax, rot=(1, 0)):
    return cv.Conic.ellipse(centre=c, axes=ax, rotation=rot)


def _reference_vertices(p1, p2, conic, span=400.0, n=200001):
    """Zeros of g on the bisector of p1 p2 (module docstring), as (x, y, r) floats."""
    rc = RefConic(conic)
    (ax, ay), (bx, by) = p1, p2
    m = np.array([(ax + bx) / 2, (ay + by) / 2])
    u = np.array([-(by - ay), bx - ax], float)
    u /= math.hypot(*u)
    t = np.linspace(-span, span, n)
    Q = m + t[:, None] * u
    g = np.hypot(Q[:, 0] - ax, Q[:, 1] - ay) - _grid_dist(rc, Q[:, 0], Q[:, 1])
    out = []
    with mpmath.workdps(40):
        M, U = [mpmath.mpf(float(v)) for v in m], [mpmath.mpf(float(v)) for v in u]

        def G(s):
            x, y = M[0] + s * U[0], M[1] + s * U[1]
            return mpmath.sqrt((x - ax) ** 2 + (y - ay) ** 2) - ref_distance(rc, x, y), x, y

        for k in np.nonzero(np.sign(g[:-1]) != np.sign(g[1:]))[0]:
            lo, hi = mpmath.mpf(float(t[k])), mpmath.mpf(float(t[k + 1]))
            glo = G(lo)[0]
            for _ in range(60):
                mid = (lo + hi) / 2
                gm = G(mid)[0]
                if (gm > 0) == (glo > 0):
                    lo, glo = mid, gm
                else:
                    hi = mid
            _, x, y = G((lo + hi) / 2)
            out.append((float(x), float(y), float(mpmath.sqrt((x - ax) ** 2 + (y - ay) ** 2))))
    return out


@pytest.mark.parametrize("p1,p2,conic,c4", [
    ((0, 0), (6, 1), _E((3, 5), (2, 1), (F(3, 5), F(4, 5))), _E((3, 2), (F(1, 2), F(1, 3)))),
    ((0, 0), (9, 0), _E((4, 6), (3, 1)), cv.Point(4, 1)),
    ((-2, 1), (5, -3), cv.Conic.circle(centre=(1, 6), radius=2), _E((8, 8), (1, F(1, 2)))),
    ((0, 0), (600, 100), _E((300, 500), (2, 1), (F(3, 5), F(4, 5))), _E((300, 200), (F(1, 2), F(1, 3)))),
])
def test_two_points_and_a_conic_against_the_bisector_reference(p1, p2, conic, c4):
    span = 40000.0 if abs(p2[0]) > 100 else 400.0
    ref = _reference_vertices(p1, p2, conic, span=span)
    assert ref, "the reference must find the vertices it checks"
    res = cv.locate_conflicts(cv.Point(*p1), cv.Point(*p2), conic, c4)
    assert res.complete and res.certified, res.notes
    assert len(res.vertices) == len(ref)
    for x, y, r in ref:
        (v,) = [v for v in res.vertices if abs(v.x - x) <= 1e-7 * (1 + abs(x)) and abs(v.y - y) <= 1e-7 * (1 + abs(y))]
        assert abs(v.radius - r) <= 1e-7 * (1 + r)
        d4 = float(ref_distance(c4, x, y)) if isinstance(c4, cv.Conic) else math.hypot(x - float(c4.cx), y - float(c4.cy))
        assert v.in_conflict is (d4 < r)
    assert res.conflict is any(v.in_conflict for v in res.vertices)


def test_a_point_with_a_parabola_is_answered_but_not_claimed_complete():
    res = cv.locate_conflicts(cv.Point(0, 0), _E((6, 1), (2, 1)), cv.Conic.parabola(vertex=(2, 6), p=1),
                              _E((3, 2), (F(1, 2), F(1, 3))))
    assert not res.complete and not res.certified
    assert any("not proven" in n for n in res.notes)


def test_a_point_on_a_site_is_refused():
    with pytest.raises(ValueError, match="C1 and C2 intersect"):
        cv.locate_conflicts(cv.Point(2, 0), _E((0, 0), (2, 1)), _E((6, 1), (1, F(1, 2))), cv.Point(9, 9))
