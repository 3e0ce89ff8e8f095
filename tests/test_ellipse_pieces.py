"""The rigorous primitives of elliptic pieces, each on both sides of its boundary, against mpmath.

Reference: the squared distance f(φ) = |q − c − cos φ M − sin φ N|² minimised by dense sampling and
golden-section refinement at 40 digits (this file's own code), and its critical points by mpmath's
``findroot``.
"""
from __future__ import annotations

import math
import random

import mpmath
import pytest
from flint import arb

import curvedvoronoi as cv
from curvedvoronoi.runtime.segments.ellipse_pieces import (PieceData, closest_at_an_end, foot_enclosure,
                                                           nearest_verdict, piece_distance_ball, piece_distances)



pytestmark = pytest.mark.mpmath_dps(40)


def piece(centre=(0, 0), major=(4, 0), ratio="1/2", s=0.2, e=1.4):
    """The first piece of the elliptic arc (cut at the ellipse's vertices)."""
    p = cv.Arc.elliptic(centre, major, ratio, s, e).pieces()[0]
    return p, PieceData.of(p)


def ref_f(p, q, phi):
    cx, cy = (mpmath.mpf(p.c[0].numerator) / p.c[0].denominator, mpmath.mpf(p.c[1].numerator) / p.c[1].denominator)
    M = [mpmath.mpf(v.numerator) / v.denominator for v in p.M]
    N = [mpmath.mpf(v.numerator) / v.denominator for v in p.N]
    return (q[0] - cx - mpmath.cos(phi) * M[0] - mpmath.sin(phi) * N[0]) ** 2 + \
        (q[1] - cy - mpmath.cos(phi) * M[1] - mpmath.sin(phi) * N[1]) ** 2


def ref_distance(p, q, lo, hi):
    best = None
    n = 4000
    for k in range(n + 1):
        phi = mpmath.mpf(lo) + (mpmath.mpf(hi) - mpmath.mpf(lo)) * k / n
        v = ref_f(p, q, phi)
        if best is None or v < best[0]:
            best = (v, k)
    k = best[1]
    a = mpmath.mpf(lo) + (mpmath.mpf(hi) - mpmath.mpf(lo)) * max(k - 1, 0) / n
    b = mpmath.mpf(lo) + (mpmath.mpf(hi) - mpmath.mpf(lo)) * min(k + 1, n) / n
    g = (mpmath.sqrt(5) - 1) / 2
    for _ in range(150):
        x1, x2 = b - g * (b - a), a + g * (b - a)
        if ref_f(p, q, x1) < ref_f(p, q, x2):
            b = x2
        else:
            a = x1
    return mpmath.sqrt(min(ref_f(p, q, (a + b) / 2), best[0]))


def test_distance_ball_holds_the_reference_and_the_float_is_close():
    rng = random.Random(7)
    p, P = piece((1, -1), (3, 4), "2/5", -0.4, 1.1)
    for _ in range(40):
        q = (rng.uniform(-8, 10), rng.uniform(-8, 10))
        d = ref_distance(p, [mpmath.mpf(q[0]), mpmath.mpf(q[1])], P.phi0, P.phi1)
        ball = piece_distance_ball(P, arb(q[0]), arb(q[1]))
        assert ball.contains(arb(str(mpmath.nstr(d, 30)))), (q, ball, d)
        assert float(ball.rad()) < 1e-9
        assert abs(float(piece_distances(P, [q])[0]) - float(d)) < 1e-10
    # a box: the ball holds the distance of every point of the box
    ball = piece_distance_ball(P, arb(2, 0.01), arb(3, 0.01))
    for dx in (-0.01, 0, 0.01):
        for dy in (-0.01, 0.01):
            d = ref_distance(p, [mpmath.mpf(2 + dx), mpmath.mpf(3 + dy)], P.phi0, P.phi1)
            assert ball.contains(arb(str(mpmath.nstr(d, 30))))


def test_foot_enclosure_holds_the_critical_point():
    p, P = piece()
    q = (1.5, 2.5)
    ref = mpmath.findroot(lambda t: mpmath.diff(lambda u: ref_f(p, q, u), t), 0.8)
    Phi = foot_enclosure(P, arb(q[0]), arb(q[1]), float(ref) + 1e-6)
    assert Phi is not None and Phi.contains(arb(str(mpmath.nstr(ref, 30))))
    assert float(Phi.rad()) < 1e-12
    # at the evolute's cusp region (the centre of curvature of a vertex) f'' vanishes: no enclosure
    _, Q = piece((0, 0), (4, 0), "1/2", -0.3, 0.3)
    assert foot_enclosure(Q, arb(3.0), arb(0.0), 0.0) is None        # (a − b²/a, 0) = (3, 0)


def test_nearest_verdict_on_both_sides():
    p, P = piece((0, 0), (4, 0), "1/2", 0.05, 1.5)
    # outside the ellipse: the foot is the nearest point (True)
    q = (4.5, 2.0)
    ref = mpmath.findroot(lambda t: mpmath.diff(lambda u: ref_f(p, q, u), t), 0.4)
    r = mpmath.sqrt(ref_f(p, q, ref))
    Phi = foot_enclosure(P, arb(q[0]), arb(q[1]), float(ref))
    assert nearest_verdict(P, arb(q[0]), arb(q[1]), arb(str(mpmath.nstr(r, 30))), Phi) is True
    # inside, near the centre: the critical point near the major vertex is a local maximum
    q = (0.2, -0.5)
    crit = mpmath.findroot(lambda t: mpmath.diff(lambda u: ref_f(p, q, u), t), 0.09)
    assert 0.05 < crit < 1.5 and mpmath.diff(lambda u: ref_f(p, q, u), crit, 2) < 0
    Phi = foot_enclosure(P, arb(q[0]), arb(q[1]), float(crit))
    r = mpmath.sqrt(ref_f(p, q, crit))
    assert nearest_verdict(P, arb(q[0]), arb(q[1]), arb(str(mpmath.nstr(r, 30))), Phi) is False


def test_local_minimum_that_is_not_nearest_is_refused():
    # piece from φ = 0.02 to π/2 of x²/16 + y²: q inside near the minor axis sees the minor vertex
    # (distance ≈ 1 − y) nearer than a local minimum near the major vertex
    p, P = piece((0, 0), (4, 0), "1/4", 0.0, math.pi / 2)
    q = (3.5, 0.0)
    # the critical points of f on (0, π/2) for this q
    crits = []
    for t0 in [0.05 * k for k in range(1, 31)]:
        try:
            c = mpmath.findroot(lambda t: mpmath.diff(lambda u: ref_f(p, q, u), t), t0)
        except (ValueError, ZeroDivisionError):
            continue
        if 0 < c < math.pi / 2 and all(abs(c - d) > 1e-10 for d in crits):
            crits.append(c)
    mins = [c for c in crits if mpmath.diff(lambda u: ref_f(p, q, u), c, 2) > 0]
    assert mins
    c = mins[0]
    r = mpmath.sqrt(ref_f(p, q, c))
    Phi = foot_enclosure(P, arb(q[0]), arb(q[1]), float(c))
    glob = ref_distance(p, [mpmath.mpf(q[0]), mpmath.mpf(q[1])], P.phi0, P.phi1)
    verdict = nearest_verdict(P, arb(q[0]), arb(q[1]), arb(str(mpmath.nstr(r, 30))), Phi)
    if glob < r - mpmath.mpf(10) ** -12:
        assert verdict is not True
    else:
        assert verdict is True


@pytest.mark.parametrize("q, ends", [((6.0, -1.0), (0,)), ((-3.0, 4.0), (1,)), ((3.7, 3.2), None)])
def test_closest_at_an_end_on_both_sides(q, ends):
    p, P = piece((0, 0), (4, 0), "1/2", 0.3, 1.3)
    got = closest_at_an_end(P, arb(q[0]), arb(q[1]))
    ref_end = [ref_f(p, q, mpmath.mpf(P.phi0)), ref_f(p, q, mpmath.mpf(P.phi1))]
    glob = ref_distance(p, [mpmath.mpf(q[0]), mpmath.mpf(q[1])], P.phi0, P.phi1) ** 2
    if ends is None:
        # the nearest point is interior: never claimed at an end
        assert glob < min(ref_end) - mpmath.mpf(10) ** -9
        assert got is None
    else:
        assert got == ends
        assert abs(glob - ref_end[ends[0]]) < mpmath.mpf(10) ** -20


def test_nearest_verdict_radius_on_both_sides_of_the_distance():
    """With the true foot, r = the true distance is proved (True); a radius 10⁻³ larger is not:
    then points of the piece next to the foot are strictly nearer than r."""
    p, P = piece((0, 0), (4, 0), "1/2", 0.05, 1.5)
    q = (4.5, 2.0)
    ref = mpmath.findroot(lambda t: mpmath.diff(lambda u: ref_f(p, q, u), t), 0.4)
    d = mpmath.sqrt(ref_f(p, q, ref))
    Phi = foot_enclosure(P, arb(q[0]), arb(q[1]), float(ref))
    assert nearest_verdict(P, arb(q[0]), arb(q[1]), arb(str(mpmath.nstr(d, 30))), Phi) is True
    assert nearest_verdict(P, arb(q[0]), arb(q[1]), arb(str(mpmath.nstr(d + mpmath.mpf("1e-3"), 30))), Phi) is not True


def test_foot_enclosure_refuses_a_box_across_the_evolute_and_holds_the_feet_otherwise():
    _, P = piece((0, 0), (4, 0), "1/2", 0.0, 1.0)
    # the centre of curvature of the major vertex is (3, 0): a box around it has no unique foot
    assert foot_enclosure(P, arb(3, 0.4), arb(0.2, 0.4), 0.3) is None
    p, P = piece((0, 0), (4, 0), "1/2", 0.2, 1.4)
    Phi = foot_enclosure(P, arb(5, 0.05), arb(2, 0.05), 0.5)
    assert Phi is not None
    for dx in (-0.05, 0.05):
        for dy in (-0.05, 0.05):
            q = (5 + dx, 2 + dy)
            c = mpmath.findroot(lambda t: mpmath.diff(lambda u: ref_f(p, q, u), t), 0.5)
            assert Phi.contains(arb(str(mpmath.nstr(c, 30))))
