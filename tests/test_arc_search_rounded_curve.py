"""The disc search of runtime/voronoi/verify/arc_search.py judges the TRUE bisector, not its float
curve: a third site tied with the edge's sites at a point of the true arc must not be proved
farther, even where the float curve passes it at a visible distance.

Sites: the circle i of radius r = 0.95 about the origin and the point j = (x_j, 0), x_j = 0.950000000108108
(both doubles, taken exactly): a gap g ≈ 1.08e-10 between them.  Their bisector
|q| − r = |q − (x_j, 0)| is the branch q(u) = (c + a·cosh u, b·sinh u) with c = x_j/2, a = r/2 and
b = √(c² − a²) ≈ 7.2e-6: a very thin hyperbola.  Computed in doubles, c² − a² loses all but a few
digits to cancellation, so the float curve's b is off by a relative 2.4e-7 and, at u₀ = 3.33 (the
point x* ≈ (7.12, 1.0e-4)), the float point is 2.4e-11 below the true one -- far more than the
rounding of the distances there (1e-13) and far less than the verifier's bound on the curve's
error (≈ 4e-8, which grows like c/b).

The third site k is a point above x* at distance d_i(x*) from it, with its ordinate the largest
double that keeps |x* − k| ≤ d_i(x*) (x* and d_i computed here with mpmath at 300 bits from the
exact site data): d_k = d_i = d_j at x* up to a margin of at most 0 ("margin 0"), or k moved 1e-12
closer.  The arc [u₀, u₀] (one point) or [u₀, u₀ + 8 ulps] holds x*, where k is not strictly
farther than i: ``prove_arcs`` must refuse.  At the float point k is 2.4e-11 farther than i
(measured below), so a search that took the float curve for the true one would prove it.  The
counterpart: k moved 1/100 up is farther on the whole (tiny) arc by ≈ 1/100 and is proved.
"""
from __future__ import annotations

import functools

import mpmath as mp
import numpy as np
import pytest

from curvedvoronoi.runtime.predicates.circles import Circle, Point
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify.arc_search import prove_arcs
from curvedvoronoi.runtime.voronoi.verify.edges import CircleTable, bisector

R, XJ, U0 = 0.95, 0.950000000108108, 3.33
H = 8 * 2.0 ** -51                       # 8 ulps of u₀


def _exact(prec=300):
    """x* = q(u₀) on the true bisector and d_i(x*), at ``prec`` bits."""
    with mp.workprec(prec):
        c, a = mp.mpf(XJ) / 2, mp.mpf(R) / 2
        b = mp.sqrt(c * c - a * a)
        x = (c + a * mp.cosh(U0), b * mp.sinh(U0))
        return x, mp.sqrt(x[0] ** 2 + x[1] ** 2) - R, b


def _margin(k, p, prec=300):
    """d_k(p) − d_i(p) for the point k, at ``prec`` bits."""
    with mp.workprec(prec):
        return mp.sqrt((p[0] - k[0]) ** 2 + (p[1] - k[1]) ** 2) - (mp.sqrt(p[0] ** 2 + p[1] ** 2) - R)


def _tied_point():
    """k above x* at distance d_i(x*), its ordinate rounded down until |x* − k| <= d_i(x*)."""
    return list(_tied())


@functools.lru_cache(maxsize=1)
def _tied():
    x, di, _ = _exact()
    k = [float(x[0]), float(x[1] + di)]
    while _margin(k, x) > 0:
        k[1] = float(np.nextafter(k[1], -np.inf))
    return tuple(k)


def _prove(k, h):
    table = CircleTable([site_geometry(s) for s in (Circle.from_radius(0, 0, R), Point(XJ, 0), Point(*k))])
    bis = bisector(table, 0, 1)
    assert not isinstance(bis, str) and bis.kind == "hyperbola"
    (ok, detail), = prove_arcs(table, [(bis, U0, U0 + h, ())], max_pieces=64)
    return ok, detail, bis


def test_the_float_curve_is_visibly_off_the_thin_true_bisector():
    x, di, b = _exact()
    with mp.workprec(300):
        dj = mp.sqrt((x[0] - XJ) ** 2 + x[1] ** 2)
        assert abs(di - dj) < mp.mpf(10) ** -60                      # x* is on the bisector
    _, _, bis = _prove(_tied_point(), 0.0)
    q = bis.point(np.array([U0]))[0]
    assert abs(bis.b - float(b)) > 1e-7 * float(b)                  # cancellation in c² − a²
    assert float(x[1]) - q[1] > 1e-11                              # the float point is below x*
    assert float(bis.curve_error(U0)) > float(x[1]) - q[1]               # the verifier's bound covers it


@pytest.mark.parametrize("h", [0.0, H], ids=["one point", "8 ulps"])
@pytest.mark.parametrize("closer", [0.0, 1e-12], ids=["margin 0", "k 1e-12 nearer"])
def test_a_site_tied_on_the_true_arc_is_not_proved_farther(h, closer):
    k = _tied_point()
    k[1] -= closer
    x, _, _ = _exact()
    assert _margin(k, x) <= 0                                       # not strictly farther at x*
    ok, detail, bis = _prove(k, h)
    q = bis.point(np.array([U0]))[0]
    assert _margin(k, (mp.mpf(q[0]), mp.mpf(q[1]))) > 1e-11          # ... but farther at the float point
    assert not ok and detail[0] == 2


@pytest.mark.parametrize("h", [0.0, H], ids=["one point", "8 ulps"])
def test_the_same_site_a_hundredth_farther_is_proved(h):
    k = _tied_point()
    k[1] += 0.01
    x, _, _ = _exact()
    assert _margin(k, x) > 0.009
    ok, detail, _ = _prove(k, h)
    assert ok and detail is None
