"""Two exact third-site rules of the edges next to elliptic pieces
(runtime.segments.certificate_ellipse_edges; thesis §2.2, ch. 4), each tested on both sides of its
boundary against closed-form geometry of the ellipse (x/2)² + y² = 1:

* ``normal_line_monotone``: on the normal line at a piece's point-site end E, a piece of the same
  ellipse tied at an end vertex is farther all along an edge that leaves the vertex outwards.  The
  arc φ ∈ [2.95, π + 0.09] is cut at the major vertex (−2, 0) into an upper piece k and a short
  lower piece s ending at E = e(π + 0.09); E's normal line meets the axis y = 0 at v, where E's
  mirror image E' = e(π − 0.09) ∈ k is exactly as far as E (symmetry): k ties at v.  Between v
  and E (and beyond, outwards) k is farther than ρ = |x − E|; past v (across the axis) E' is
  nearer — checked in mpmath here, then the rule must accept the first way and refuse the second.
* ``_line_rule(...).curve``: on two points' bisector, a segment or a piece whose support in the
  edge's direction is strictly below the points' is farther all along the edge from its vertex;
  a piece reaching beyond it is nearer far out (mpmath), and refused.
"""
from __future__ import annotations

from fractions import Fraction

import mpmath as mp
import pytest

import curvedvoronoi as cv
from curvedvoronoi.runtime.certify.foot import working_prec
from curvedvoronoi.runtime.segments.certificate_ellipse_curves import NormalLine
from curvedvoronoi.runtime.segments.certificate_ellipse_edges import _line_rule, normal_line_monotone
from curvedvoronoi.runtime.segments.certificate_sites import ELLIPSE, POINT, SiteTable

pytestmark = pytest.mark.mpmath_dps(30)

RING = [(-5, 0), (-1, 4), (-1, -4), (4, 0)]


def mq(q):
    q = Fraction(q)
    return mp.mpf(q.numerator) / q.denominator


@pytest.fixture(scope="module")
def joined():
    D = cv.voronoi([cv.Arc.elliptic((0, 0), (2, 0), "1/2", 2.95, float(mp.pi) + 0.09)] + [cv.Point(*p) for p in RING],
                   certify=False)
    T = SiteTable(D.sites)
    pieces = [k for k in range(T.n) if T.kind[k] == ELLIPSE]
    s = next(k for k in pieces if T.sites[k].ua[1] <= 0 and T.sites[k].ub[1] < 0)     # the lower piece
    (k,) = [q for q in pieces if q != s]
    E = next(code for code in T.ends[s] if code >= 0)
    lx, ly = T.leaving(s, E)
    c = NormalLine(T, E, (ly, -lx), [(s, T.which_end(s, E))])
    return T, s, k, E, c


def _mp_piece_distance(T, k, x):
    """min over piece k's exact parameter range of |x − e(φ)| (dense samples, golden section)."""
    site = T.sites[k]
    p0 = mp.atan2(mq(site.ua[1]), mq(site.ua[0]))
    p1 = mp.atan2(mq(site.ub[1]), mq(site.ub[0]))
    while p1 <= p0:
        p1 += 2 * mp.pi

    def f(t):
        return (x[0] - 2 * mp.cos(t)) ** 2 + (x[1] - mp.sin(t)) ** 2
    n = 400
    ts = [p0 + (p1 - p0) * m / n for m in range(n + 1)]
    m = min(range(n + 1), key=lambda q: f(ts[q]))
    a, b = ts[max(m - 1, 0)], ts[min(m + 1, n)]
    g = (mp.sqrt(5) - 1) / 2
    for _ in range(80):
        x1, x2 = b - g * (b - a), a + g * (b - a)
        if f(x1) < f(x2):
            b = x2
        else:
            a = x1
    return mp.sqrt(min(f((a + b) / 2), f(p0), f(p1)))


def test_the_mirror_piece_ties_at_the_axis_and_is_farther_only_towards_e(joined):
    """The closed-form reference of the rule's two verdicts (mpmath)."""
    T, s, k, E, c = joined
    e = (mq(T.a[E][0]), mq(T.a[E][1]))
    w = (mq(c.wq[0]), mq(c.wq[1]))
    tv = -e[1] / w[1]                                  # the axis crossing v = E + t_v w
    v = (e[0] + tv * w[0], 0)
    assert -mp.mpf(3) / 2 < v[0] < 0                   # inside, past the centre of curvature (−3/2, 0)
    rho_v = mp.hypot(v[0] - e[0], v[1] - e[1])
    assert abs(_mp_piece_distance(T, k, v) - rho_v) < mp.mpf(10) ** -12        # k ties at v (E' ∈ k)
    for frac in (mp.mpf("0.01"), mp.mpf("0.3"), mp.mpf("0.9"), mp.mpf("1.5"), mp.mpf(3)):
        x = (v[0] + (0 - tv) * frac * w[0], v[1] + (0 - tv) * frac * w[1])   # from v towards E and beyond
        rho = mp.hypot(x[0] - e[0], x[1] - e[1])
        assert _mp_piece_distance(T, k, x) > rho
    for frac in (mp.mpf("0.01"), mp.mpf("0.2")):
        x = (v[0] - (0 - tv) * frac * w[0], v[1] - (0 - tv) * frac * w[1])   # past v, across the axis
        rho = mp.hypot(x[0] - e[0], x[1] - e[1])
        assert _mp_piece_distance(T, k, x) < rho


def test_normal_line_monotone_accepts_the_outward_edge_only(joined):
    T, s, k, E, c = joined
    e = (mq(T.a[E][0]), mq(T.a[E][1]))
    # the outward way along w: the gradient (x/2, 2y) of (x/2)² + y² at E
    way = 1 if c.wq[0] * T.a[E][0] / 2 + c.wq[1] * 2 * T.a[E][1] > 0 else -1
    tv = -e[1] / mq(c.wq[1])
    assert tv * way < 0                                # v is on the inner side
    # v is the lower end of an edge that goes the outward way when way > 0, its upper end else
    outward = ({k}, set()) if way > 0 else (set(), {k})
    inward = (set(), {k}) if way > 0 else ({k}, set())
    with working_prec(128):
        assert normal_line_monotone(T, c, k, outward) is True
        assert normal_line_monotone(T, c, k, inward) is False
        assert normal_line_monotone(T, c, k, (set(), set())) is False
        p = next(q for q in range(T.n) if T.kind[q] == POINT and q != E)
        assert normal_line_monotone(T, c, p, ({p}, {p})) is False


# ---------------------------------------------------------------- two points' bisector and a piece
def _bisector_table(dx):
    """Points (0, 3), (0, −3): the bisector y = 0, w = (6, 0) (+x).  An arc φ ∈ [0.2, 1.3] of an
    ellipse (x − cx)²/4 + (y − 1/2)² = 1 placed so that its rightmost point, its start
    e(0.2) = (cx + 2 cos 0.2, ...), has x = dx (rational: the exact start of the arc)."""
    arc = cv.Arc.elliptic((0, "1/2"), (2, 0), "1/2", 0.2, 1.3)
    D = cv.voronoi([arc, cv.Point(0, 3), cv.Point(0, -3)], certify=False)
    T0 = SiteTable(D.sites)
    k0 = next(q for q in range(T0.n) if T0.kind[q] == ELLIPSE)
    x_start = T0.sites[k0].c[0] + 2 * T0.sites[k0].ua[0]
    cx = Fraction(dx) - x_start
    arc = cv.Arc.elliptic((cx, "1/2"), (2, 0), "1/2", 0.2, 1.3)
    D = cv.voronoi([arc, cv.Point(0, 3), cv.Point(0, -3)], certify=False)
    T = SiteTable(D.sites)
    k = next(q for q in range(T.n) if T.kind[q] == ELLIPSE)
    i = next(q for q in range(T.n) if T.kind[q] == POINT and T.a[q] == (0, 3))
    j = next(q for q in range(T.n) if T.kind[q] == POINT and T.a[q] == (0, -3))
    return T, k, i, j


@pytest.mark.parametrize("dx,proved", [(Fraction(-1, 10 ** 9), True), (Fraction(0), False),
                                       (Fraction(1, 10 ** 9), False)])
def test_the_points_line_rule_on_a_piece_against_its_support(dx, proved):
    """Rightmost point of the piece at x = dx: below the points' support w·p = 0 (dx < 0) every
    point of the piece is farther all along the edge leaving a vertex in +x; at or above it, not
    proved (the rule needs a strict slope)."""
    T, k, i, j = _bisector_table(dx)
    assert max(T.sites[k].c[0] + 2 * u for u in (T.sites[k].ua[0], T.sites[k].ub[0])) == dx
    wx = -(T.a[j][1] - T.a[i][1])
    sentinel = object()
    lo_vertex = (sentinel, None) if wx > 0 else (None, sentinel)       # the vertex at the end with the smaller x
    hi_vertex = (None, sentinel) if wx > 0 else (sentinel, None)
    assert _line_rule(T, i, j, *lo_vertex).curve(k) is proved
    assert _line_rule(T, i, j, *hi_vertex).curve(k) is False           # the edge going −x: the piece comes nearer


def test_a_piece_beyond_the_points_support_is_nearer_far_along_the_bisector():
    """The reference of the refusal for dx > 0: at x = (X, 0), X large, the piece's start
    (dx, y₀) is nearer than the points when X dx > (9 − y₀²)/2, i.e. far out (mpmath)."""
    T, k, i, j = _bisector_table(Fraction(1, 10 ** 9))
    y0 = mq(T.sites[k].c[1] + T.sites[k].ua[1] * T.sites[k].N[1])
    X = mp.mpf(10) ** 11
    start = (mp.mpf(1) / 10 ** 9, y0)
    assert mp.hypot(X - start[0], start[1]) < mp.hypot(X, 3)
