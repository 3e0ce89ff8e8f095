"""The edge of two elliptic pieces joined at an end J of their ellipse's major axis, past J's centre
of curvature K (runtime.segments.certificate_ellipse_axis; thesis §2.2, ch. 4).

The scene: the arc φ ∈ [2.95, 3.4] of (x/2)² + y² = 1 (split at its major vertex J = (−2, 0) into
two pieces of different lengths) inside four integer points.  The edge of the two pieces runs on
the axis y = 0 from a vertex outside the ellipse, through J and K = (−3/2, 0), to the vertex where
the mirror feet reach the far end of the shorter piece.  The references are mpmath: the distance to
a piece by minimising |x − e(φ)|² over its exact parameter range (dense samples, then Newton on the
derivative), the radius past K by the closed form b²(1 − x²/(a² − b²)) of the distance from (x, 0)
to the whole ellipse, |x| < (a² − b²)/a — checked here against that minimisation.
"""
from __future__ import annotations

import dataclasses
import random
from fractions import Fraction

import mpmath as mp
from flint import arb
import pytest

import curvedvoronoi as cv
from curvedvoronoi.runtime.certify.foot import to_arb, working_prec
from curvedvoronoi.runtime.segments.certificate import verify_segments
from curvedvoronoi.runtime.segments.certificate_ellipse_axis import AxisCurve, axis_edge
from curvedvoronoi.runtime.segments.certificate_ellipse_edges import prove_piece_edge
from curvedvoronoi.runtime.segments.certificate_sites import SiteTable
from curvedvoronoi.runtime.segments.certificate_vertices import VertexProof, prove_vertices
from curvedvoronoi.runtime.sites.elliptic_arc import EllipticArc

pytestmark = pytest.mark.mpmath_dps(40)

A2, B2 = 4, 1                    # a², b² of (x/2)² + y² = 1
XK = Fraction(-(A2 - B2), 2)     # K = (−(a² − b²)/a, 0)
ARC = (2.95, 3.4)
POINTS = [(-4, 0), (-1, 3), (-1, -3), (3, 0)]


def build():
    sites = [cv.Arc.elliptic((0, 0), (2, 0), "1/2", *ARC)] + POINTS
    D = cv.voronoi(sites, certify=False)
    return D


def prove_edge(D, e, extra=()):
    """The edge proof of ``e`` with the vertex proofs, against the diagram's sites plus ``extra``
    point sites (appended: the diagram's indices unchanged)."""
    with working_prec(128):
        T = SiteTable(list(D.sites) + [cv.Point(*p) for p in extra])
        vproofs = prove_vertices(D, T, [])
        vindex = {v.id: n for n, v in enumerate(D.vertices)}
        problems: list = []
        ok = prove_piece_edge(T, D, e, vindex, vproofs, problems, [10000]).ok
        ends = [vproofs[vindex[v]] for v in e.ends]
    return ok, problems, ends


@pytest.fixture(scope="module")
def scene():
    D = build()
    pieces = [k for k, s in enumerate(D.sites) if isinstance(s, EllipticArc)]
    edge = next(e for e in D.edges if sorted(int(s) for s in e.sites) == pieces)
    return D, pieces, edge


# ------------------------------------------------------------------ mpmath references
def phi_range(s):
    p0 = mp.atan2(mp.mpf(s.ua[1].numerator) / s.ua[1].denominator, mp.mpf(s.ua[0].numerator) / s.ua[0].denominator)
    p1 = mp.atan2(mp.mpf(s.ub[1].numerator) / s.ub[1].denominator, mp.mpf(s.ub[0].numerator) / s.ub[0].denominator)
    while p1 <= p0:
        p1 += 2 * mp.pi
    return p0, p1


def mp_piece_distance(s, x, y):
    """min over the piece's exact parameter range of |(x, y) − e(φ)| (mpmath)."""
    c = [mp.mpf(v.numerator) / v.denominator for v in s.c]
    M = [mp.mpf(v.numerator) / v.denominator for v in s.M]
    N = [mp.mpf(v.numerator) / v.denominator for v in s.N]
    x, y = mp.mpf(x), mp.mpf(y)
    p0, p1 = phi_range(s)

    def f(p):
        return (x - c[0] - mp.cos(p) * M[0] - mp.sin(p) * N[0]) ** 2 + \
               (y - c[1] - mp.cos(p) * M[1] - mp.sin(p) * N[1]) ** 2

    grid = [p0 + (p1 - p0) * k / 400 for k in range(401)]
    best = min(grid, key=f)
    cands = [p0, p1, best]
    try:
        r = mp.findroot(lambda p: mp.diff(f, p), best)
        if p0 <= r <= p1:
            cands.append(r)
    except (ValueError, ZeroDivisionError):
        pass
    return mp.sqrt(min(f(p) for p in cands))


def mp_distance(site, x, y):
    if isinstance(site, EllipticArc):
        return mp_piece_distance(site, x, y)
    px, py = (mpq(Fraction(int(v.p), int(v.q))) for v in (site.x, site.y))
    return mp.sqrt((mp.mpf(x) - px) ** 2 + (mp.mpf(y) - py) ** 2)


def mpq(q: Fraction):
    return mp.mpf(q.numerator) / q.denominator


def closed_rho(x):
    """ρ on the axis at (x, 0), J = (−2, 0): |x + 2| before K, the mirror feet's distance past it."""
    x = mp.mpf(x)
    if x <= mp.mpf(XK.numerator) / XK.denominator:
        return abs(x + 2)
    return mp.sqrt(B2 * (1 - x * x / (A2 - B2)))


# ------------------------------------------------------------------ tests
def test_the_closed_form_is_the_distance_to_the_ellipse():
    whole = EllipticArc((0, 0), (2, 0), "1/2", (1, 0), (-1, 0))      # the upper half: (x, 0) sees it whole
    for x in ("-1.49", "-1.2", "-0.5", "0.3", "1.4"):
        assert abs(mp_piece_distance(whole, x, 0) - mp.sqrt(B2 * (1 - mp.mpf(x) ** 2 / (A2 - B2)))) < mp.mpf(10) ** -30


def test_the_scene_has_an_axis_edge_past_the_centre_of_curvature(scene):
    D, pieces, e = scene
    vs = {v.id: v for v in D.vertices}
    xs = sorted(float(vs[v].x) for v in e.ends)
    assert all(abs(float(vs[v].y)) < 1e-12 for v in e.ends)
    assert xs[0] < -2 and float(XK) < xs[1] < 0            # through J, and past K


def test_the_axis_edge_is_proved(scene):
    D, pieces, e = scene
    ok, problems, _ = prove_edge(D, e)
    assert ok, problems


def test_the_axis_edge_and_its_vertices_agree_with_mpmath(scene):
    D, pieces, e = scene
    vs = {v.id: v for v in D.vertices}
    for vid in e.ends:
        v = vs[vid]
        d = [mp_distance(s, v.x, v.y) for s in D.sites]
        r = mp.mpf(float(v.radius))
        for k in range(len(D.sites)):
            if k in v.sites:
                assert abs(d[k] - r) < 1e-9, (vid, k)
            else:
                assert d[k] > r + 1e-6, (vid, k)
    x0, x1 = sorted(float(vs[v].x) for v in e.ends)
    for m in range(1, 40):
        x = mp.mpf(x0) + (mp.mpf(x1) - mp.mpf(x0)) * m / 40
        d = [mp_distance(s, x, 0) for s in D.sites]
        rho = closed_rho(x)
        for k in pieces:
            assert abs(d[k] - rho) < mp.mpf(10) ** -25
        assert all(d[k] > rho + 1e-6 for k in range(len(D.sites)) if k not in pieces)


def _point_off_the_feet(mu, delta):
    """x(μ) + (ρ(μ) − δ)·(unit vector to the upper mirror foot), rounded to a rational 10⁻¹⁵ near."""
    x = -2 * mp.mpf(mu)
    C = mp.mpf(A2) * mu / (A2 - B2)
    fx, fy = -2 * C, mp.sqrt(1 - C * C)
    rho = closed_rho(x)
    ux, uy = (fx - x) / rho, fy / rho
    q = (x + (rho - delta) * ux, (rho - delta) * uy)
    return tuple(Fraction(str(mp.nstr(v, 30))).limit_denominator(10 ** 15) for v in q)


def test_a_point_nearer_than_rho_on_the_axis_past_k_is_refused(scene):
    D, pieces, e = scene
    vs = {v.id: v for v in D.vertices}
    mu_p = -max(float(vs[v].x) for v in e.ends) / 2
    mu = mp.mpf(mu_p + (0.75 - mu_p) / 2)
    q = _point_off_the_feet(mu, mp.mpf("1e-6"))
    assert mp_distance(cv.Point(*q), -2 * mu, 0) < closed_rho(-2 * mu) - mp.mpf("0.9e-6")
    ok, problems, ends = prove_edge(D, e, [q])
    assert all(vp.ok for vp in ends)          # q is outside both end vertices' circles
    assert not ok and problems                # refused (q is a site nearer than ρ: no proof can exist)
    q = _point_off_the_feet(mu, mp.mpf("-1e-6"))
    ok, problems, ends = prove_edge(D, e, [q])
    assert ok, problems                       # 10⁻⁶ farther: the exact rule decides it


def test_the_farther_rule_is_sound_on_exact_points(scene):
    D, pieces, e = scene
    with working_prec(128):
        T = SiteTable(D.sites)
        i, j = pieces
        code = next(c for c in set(T.ends[i]) & set(T.ends[j]) if c <= -2)
        c = AxisCurve(T, i, j, code)
    vs = {v.id: v for v in D.vertices}
    x_hi = min(float(vs[v].x) for v in e.ends)
    mu_hi = -x_hi / 2
    c.mu_lo = (A2 - B2) * max(c.far.values()) / A2
    rule = c.farther_rule()
    rng = random.Random(32)
    lo, K = mpq(c.mu_lo), mp.mpf(3) / 4
    grid = [lo + (K - lo) * k / 200 for k in range(201)] + [K + (mp.mpf(mu_hi) - K) * k / 50 for k in range(1, 51)]
    seen = {True: 0, False: 0}
    for n in range(120):
        mu = lo + mp.mpf(rng.random()) * (K - lo)
        delta = rng.choice([1, -1]) * mp.mpf(10) ** rng.uniform(-8, -2)
        q = _point_off_the_feet(mu, delta)
        qx, qy = mpq(q[0]), mpq(q[1])

        def excess(m):
            return (-2 * m - qx) ** 2 + qy ** 2 - closed_rho(-2 * m) ** 2
        if excess(grid[-1]) < 0:
            continue                          # inside the upper vertex's circle: not a case of the rule
        verdict = rule(q)
        seen[verdict] += 1
        if verdict:
            assert min(excess(m) for m in grid[1:-1] + [mu]) > 0, (mu, delta)
        if delta > 0:
            assert not verdict                # nearer than ρ at x(μ)
    assert seen[True] > 10 and seen[False] > 10


def test_the_farther_rule_on_points_tied_at_the_lower_vertex(scene):
    """Exact points of the lower vertex's circle (the far end p reflected across rational lines
    through the vertex x_p): tied there, so the rule may accept them only where they get farther
    along the edge (the sign of the mpmath excess just past x_p)."""
    D, pieces, e = scene
    with working_prec(128):
        T = SiteTable(D.sites)
        i, j = pieces
        code = next(c for c in set(T.ends[i]) & set(T.ends[j]) if c <= -2)
        c = AxisCurve(T, i, j, code)
    c.mu_lo = (A2 - B2) * max(c.far.values()) / A2
    rule = c.farther_rule()
    xp = (-2 * c.mu_lo, Fraction(0))
    p = next(tuple(Fraction(v) for v in T.pt(q)) for k in pieces for q in T.ends[k]
             if q >= 0 and c.far[k] == max(c.far.values()))
    lo, K = mpq(c.mu_lo), mp.mpf(3) / 4
    verdicts = []
    for t in [Fraction(n, 7) for n in range(-21, 22)]:
        # reflect p across the line through x_p with direction (1, t): exact, on the circle
        dx, dy = p[0] - xp[0], p[1] - xp[1]
        n2 = 1 + t * t
        k = 2 * (dx + t * dy) / n2
        q = (xp[0] + k - dx, xp[1] + k * t - dy)
        assert (q[0] - xp[0]) ** 2 + q[1] ** 2 == dx * dx + dy * dy
        m = lo + (K - lo) * mp.mpf("1e-6")
        past = (-2 * m - mpq(q[0])) ** 2 + mpq(q[1]) ** 2 - closed_rho(-2 * m) ** 2
        verdict = rule(q)
        verdicts.append(verdict)
        if verdict:
            assert past > 0, t
    assert True in verdicts and False in verdicts
    assert rule(p)                            # the far end itself: tied at x_p, farther past it
    # p pulled towards x_p: nearer than ρ at the vertex (and just past it)
    assert not rule((xp[0] + (p[0] - xp[0]) * Fraction(999, 1000), p[1] * Fraction(999, 1000)))
    # J is at distance exactly ρ = a(1 − μ) from every axis point between K and J
    assert not rule((Fraction(-2), Fraction(0)))


def test_rho_and_its_derivative_on_the_axis(scene):
    D, pieces, e = scene
    with working_prec(128):
        T = SiteTable(D.sites)
        code = next(c for c in set(T.ends[pieces[0]]) & set(T.ends[pieces[1]]) if c <= -2)
        c = AxisCurve(T, *pieces, code)
        for mu in ("0.6", "0.74", "0.76", "0.9", "1.3"):
            m = mp.mpf(mu)
            rho = closed_rho(-2 * m)
            drho = mp.diff(lambda t: closed_rho(-2 * t), m)
            assert abs(mp.mpf(float(c.rho(arb(mu)).mid())) - rho) < 1e-14
            assert abs(mp.mpf(float(c.drho(arb(mu)).mid())) - drho) < 1e-12
            assert c.rho(arb(mu)).rad() < 1e-30 and c.drho(arb(mu)).rad() < 1e-30


def test_axis_edge_refuses_vertices_that_are_not_where_the_identity_puts_them(scene):
    """A box missing x(μ_p), the far end of the longer piece (its axis point is nearer to that
    end than to the shorter piece: no vertex), and a vertex on J's normal line past K are refused;
    the diagram's own vertices are taken."""
    D, pieces, e = scene
    with working_prec(128):
        T = SiteTable(D.sites)
        vproofs = prove_vertices(D, T, [])
        vindex = {v.id: n for n, v in enumerate(D.vertices)}
        i, j = pieces
        code = next(c for c in set(T.ends[i]) & set(T.ends[j]) if c <= -2)
        c = AxisCurve(T, i, j, code)
        short = max(pieces, key=lambda k: c.far[k])
        long_ = min(pieces, key=lambda k: c.far[k])
        far = {k: next(q for q in T.ends[k] if q >= 0) for k in pieces}
        vps = [vproofs[vindex[v]] for v in e.ends]
        low = min(range(2), key=lambda n: float(vps[n].x.mid()) < -2)
        contacts = [None, None]
        for n in range(2):
            if n == low:
                contacts[n] = [("end", far[k], None) if k == short else ("inside", None) for k in (i, j)]
            else:
                contacts[n] = [("end", code, None)] * 2
        got = axis_edge(T, i, j, code, vps, contacts)
        assert not isinstance(got, str), got
        assert got[1][low].rad() < 1e-30         # x(μ_p) exact
        bad = list(vps)
        bad[low] = dataclasses.replace(vps[low], x=vps[low].x + arb("1e-20"))
        assert isinstance(axis_edge(T, i, j, code, bad, contacts), str)
        mu = Fraction(3, 4) * c.far[long_]
        bad[low] = VertexProof(True, to_arb(-2 * mu) + arb(0, 1e-20), arb(0, 1e-20), vps[low].r,
                               listed=frozenset({i, j, far[long_]}))
        wrong = list(contacts)
        wrong[low] = [("end", far[k], None) if k == long_ else ("inside", None) for k in (i, j)]
        assert isinstance(axis_edge(T, i, j, code, bad, wrong), str)
        bad = list(vps)
        bad[1 - low] = dataclasses.replace(vps[1 - low], x=arb(-2 * 0.74, 1e-20), y=arb(0, 1e-20))
        assert isinstance(axis_edge(T, i, j, code, bad, contacts), str)


@pytest.mark.slow
def test_the_scene_is_certified_and_every_vertex_agrees_with_mpmath(scene):
    D, pieces, e = scene
    C = verify_segments(D)
    assert C.ok, C.problems
    for v in D.vertices:
        d = [mp_distance(s, v.x, v.y) for s in D.sites]
        r = mp.mpf(float(v.radius))
        for k in range(len(D.sites)):
            if k in v.sites:
                assert abs(d[k] - r) < 1e-9, (v.id, k)
            else:
                assert d[k] > r - 1e-9, (v.id, k)
