"""Far-field enclosures of the distance to a parabola / hyperbola and of its gradient
(runtime.voronoi.verify.far_conics), the asymptotic functions and the accounting of directions
at infinity (runtime.voronoi.verify.far_accounting), and the tails between unbounded sites
(runtime.voronoi.verify.conic_tail).

Each inequality is tested on hand-built inputs on both sides of its boundary (exact rational
constructions: a point on a known normal of the curve, a point on the curve, on the asymptote),
with margins 1e-9 and 0; the enclosures are checked against an independent reference: the
nearest point found by mpmath (the real roots of the parabola's foot cubic by mpmath.polyroots;
for a hyperbola dense sampling of both branches refined by mpmath.findroot), never our own
distance code.
"""
from __future__ import annotations

import math
import random
from fractions import Fraction as Fr

import mpmath as mp
import numpy as np
import pytest

from curvedvoronoi.runtime.predicates.circles import Point
from curvedvoronoi.runtime.sites.conic import Conic
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify import far_accounting as FA
from curvedvoronoi.runtime.voronoi.verify import far_conics as FC

pytestmark = pytest.mark.mpmath_dps(30)


@pytest.fixture(autouse=True)
def _mpmath_digits():
    """30 digits for this module's references, restored after each test (another module's
    setting must not leak in, nor this one out)."""
    with mp.workdps(30):
        yield


# ----------------------------------------------------------------------------- references (mpmath)

def _mpf(v):
    v = Fr(v)
    return mp.mpf(v.numerator) / v.denominator


def _canon(conic, q):
    fr = conic.frame
    cs, sn, tx, ty = (_mpf(v) for v in (fr.cos, fr.sin, fr.tx, fr.ty))
    dx, dy = mp.mpf(q[0]) - tx, mp.mpf(q[1]) - ty
    return cs * dx + sn * dy, -sn * dx + cs * dy, cs, sn


def ref_nearest(conic, q):
    """(distance, world angle of q − p*) with p* the nearest point of the curve (mpmath)."""
    X, Y, cs, sn = _canon(conic, q)
    fr = conic.frame
    cands = []
    if conic.frame.kind == "parabola":
        p = _mpf(fr.params["p"])
        for r in mp.polyroots([1 / (2 * p * p), 0, 1 - X / p, -Y], maxsteps=200, extraprec=200):
            if abs(mp.im(r)) < mp.mpf(10) ** -20 * (1 + abs(r)):
                s = mp.re(r)
                cands.append((s * s / (2 * p), s))
    else:
        a, b = mp.sqrt(_mpf(fr.params["A2"])), mp.sqrt(_mpf(fr.params["B2"]))
        W = float(mp.asinh(4 * (abs(X) + abs(Y)) / b)) + 2
        for br in (1, -1):
            ws = np.linspace(-W, W, 4001)
            d2 = (br * float(a) * np.cosh(ws) - float(X)) ** 2 + (float(b) * np.sinh(ws) - float(Y)) ** 2
            k = int(np.argmin(d2))
            w0 = mp.findroot(lambda w: (br * a * mp.cosh(w) - X) * br * a * mp.sinh(w) + (b * mp.sinh(w) - Y) * b * mp.cosh(w),
                             mp.mpf(ws[k]))
            cands.append((br * a * mp.cosh(w0), b * mp.sinh(w0)))
    best = min(cands, key=lambda c: (c[0] - X) ** 2 + (c[1] - Y) ** 2)
    dX, dY = X - best[0], Y - best[1]
    d = mp.sqrt(dX * dX + dY * dY)
    wx, wy = cs * dX - sn * dY, sn * dX + cs * dY          # back to the world frame
    return float(d), float(mp.atan2(wy, wx))


def _in_arc(a, lo, hi, tol=1e-12):
    k = math.floor((lo - a) / (2 * math.pi))
    return any(lo - tol <= a + 2 * math.pi * kk <= hi + tol for kk in (k, k + 1, k + 2))


# ----------------------------------------------------------------------------- boundary tests

# Parabola Y² = 2X (p = 1): c(−2) = (2, −2), normal direction (−p, s) = (−1, −2); q = c(−2) + 3·(−1, −2)
# = (−1, −8) has its foot exactly at s* = −2: f(−2) = −4 − 2·(1 + 1) + 8 = 0.  At t = 8 (τ = 1/8).
PQ = (-1.0, -8.0)


@pytest.mark.parametrize("eps, want", [(1e-9, "above"), (0.0, "neither"), (-1e-9, "below")])
def test_parabola_foot_sign_on_both_sides_of_the_exact_foot(eps, want):
    t = 8.0
    X, Y = PQ[0] / t, PQ[1] / t
    lo, hi = FC.parabola_foot_sign(np.array(-2.0 + eps), 1 / t, 1 / t, X, X, Y, Y, 1.0)
    if want == "above":            # S above s*: f(S) > 0 proved
        assert lo > 0
    elif want == "below":
        assert hi < 0
    else:
        assert lo <= 0 <= hi
    ref = FC.parabola_foot_guess(PQ[0], PQ[1], 1.0)
    assert abs(ref + 2.0) < 1e-12


# Hyperbola X²/9 − Y²/16 = 1: w = ln 2 (cosh = 5/4, sinh = 3/4), c(w) = (15/4, 3), normal
# (−b cosh, a sinh) = (−5, 9/4); q = c(w) + (1/4)·(−5, 9/4) = (5/2, 57/16):
# g(ln 2) = 25·(3/4)(5/4) − 3·(5/2)(3/4) − 4·(57/16)(5/4) = 0.  At t = 1.
HQ = (2.5, 57 / 16)


@pytest.mark.parametrize("eps, want", [(1e-9, "above"), (0.0, "neither"), (-1e-9, "below")])
def test_hyperbola_foot_sign_on_both_sides_of_the_exact_foot(eps, want):
    lo, hi = FC.hyperbola_foot_sign(np.array(math.log(2.0) + eps), 1.0, 1.0, HQ[0], HQ[0], HQ[1], HQ[1], 3.0, 4.0)
    if want == "above":
        assert lo > 0
    elif want == "below":
        assert hi < 0
    else:
        assert lo <= 0 <= hi
    assert abs(FC.hyperbola_foot_guess(HQ[0], HQ[1], 3.0, 4.0) - math.log(2.0)) < 1e-12


@pytest.mark.parametrize("eps", [1e-9, 0.0, -1e-9])
def test_outside_the_parabola_on_both_sides_of_the_curve(eps):
    # (2, −2) is on Y² = 2X; at t = 2: X/t = 1, Y/t = −1, τ = 1/2; Y/t = −1 − eps is outside iff eps > 0
    m = FC.parabola_outside(0.5, 0.5, 1.0, -1.0 - eps, 1.0)
    assert (m > 0) == (eps > 0)


@pytest.mark.parametrize("eps", [1e-9, 0.0, -1e-9])
def test_above_the_asymptote_on_both_sides(eps):
    # a = 3, b = 4: the asymptote bX = aY passes through (3, 4)
    assert (FC.above_asymptote(3.0, 4.0 + eps, 3.0, 4.0) > 0) == (eps > 0)


def _boxes(rng, k, sign_x=None):
    out = []
    for _ in range(k):
        t1 = rng.choice([1.0, 0.1, 1e-3])
        t0 = t1 * rng.choice([0.0, 0.5, 0.9])
        x = rng.uniform(-1, 1) if sign_x is None else rng.uniform(0.05, 1)
        y = -rng.uniform(0.05, 1)
        wx, wy = rng.choice([1e-3, 0.05]), rng.choice([1e-3, 0.05])
        out.append((t0, t1, x, x + wx, y - wy, y))
    return out


def test_foot_sign_and_side_enclosures_contain_the_values_at_the_box_corners():
    """f(S)/t, g(W)/t, (Y0/t)² − 2pτX0/t and aY0/t − bX0/t are linear (or convex) in each of τ,
    X0/t, Y0/t: their extremes over a box are at its corners (exact rational arithmetic there); the
    enclosures must contain every corner value."""
    rng = random.Random(7)
    for t0, t1, xl, xh, yl, yh in _boxes(rng, 200):
        Fx = [Fr(v) for v in (t0, t1)], [Fr(v) for v in (xl, xh)], [Fr(v) for v in (yl, yh)]
        p = Fr(3, 2)
        S = Fr(-rng.uniform(0.1, 20))
        lo, hi = FC.parabola_foot_sign(np.array(float(S)), t0, t1, xl, xh, yl, yh, float(p))
        vals = [T * (S ** 3 / (2 * p * p) + S) - S / p * X - Y for T in Fx[0] for X in Fx[1] for Y in Fx[2]]
        assert lo <= min(vals) and max(vals) <= hi
        om = FC.parabola_outside(t0, t1, xh, yh, float(p))
        assert om <= min(Y * Y - 2 * p * T * X for T in Fx[0] for X in Fx[1] for Y in Fx[2])
        a, b = Fr(3), Fr(4)
        W = rng.uniform(0, 5)
        sh, ch = Fr(math.sinh(W)), Fr(math.cosh(W))
        xa, ya = sorted((abs(xl), abs(xh))), sorted((abs(yl), abs(yh)))
        lo, hi = FC.hyperbola_foot_sign(np.array(W), t0, t1, xa[0], xa[1], ya[0], ya[1], 3.0, 4.0)
        vals = [T * (a * a + b * b) * sh * ch - a * sh * Fr(X) - b * ch * Fr(Y) for T in Fx[0] for X in xa for Y in ya]
        # sinh, cosh of the float W are within 1e-15 relative of the Fractions used here
        slack = 1e-13 * float(max(abs(v) for v in vals) + 1)
        assert lo <= float(min(vals)) + slack and float(max(vals)) - slack <= hi
        am = FC.above_asymptote(xa[1], ya[0], 3.0, 4.0)
        assert am <= min(a * Fr(Y) - b * Fr(X) for X in xa for Y in ya)


def test_upper_bounds_hold_with_the_exact_distances():
    """d ≤ bound at the hand-built points: the parabola's q = (−1, −8) is at distance 3√5 (on the
    normal of its foot), the hyperbola's q = (5/2, 57/16) at (1/4)·|(−5, 9/4)| = √481/16."""
    up = FC.parabola_upper(-1 / 8, -1 / 8, -1.0)
    assert up >= 3 * math.sqrt(5) / 8
    upa = FC.parabola_upper(1 / 8, 1 / 8, -1.0)                # X0 ≥ 0: |Y0|
    assert upa == pytest.approx(1.0, abs=1e-11)
    uph = FC.hyperbola_upper(1.0, 1.0, HQ[0], HQ[0], HQ[1], HQ[1], 3.0, 4.0)
    assert uph >= math.sqrt(481) / 16


# ----------------------------------------------------------------------------- against mpmath

SITES = [Conic.parabola(vertex=(1, -2), p=Fr(3, 2), rotation=(Fr(3, 5), Fr(4, 5))),
         Conic.parabola(vertex=(40, 84), p=3, rotation=(0, 1)),
         Conic.hyperbola(centre=(2, 1), axes=(5, 3), rotation=(Fr(5, 13), Fr(12, 13))),
         Conic.hyperbola(centre=(40, 40), axes=(44, 44), rotation=(1, 0))]


def _cells(rng, k):
    out = []
    for _ in range(k):
        th = rng.uniform(-math.pi, math.pi)
        w = rng.choice([1e-3, 1e-2, 0.1])
        T = rng.choice([30.0, 200.0, 3000.0])
        t1 = 1 / T
        t0 = rng.choice([0.0, t1 * rng.uniform(0.3, 0.99)])
        out.append((t0, t1, th, th + w))
    return out


@pytest.mark.parametrize("site", range(len(SITES)))
def test_gradient_and_upper_bound_enclosures_contain_the_mpmath_values(site):
    """On random cells (some reaching infinity), wherever the enclosure is claimed (ok), the
    gradient's angle of the mpmath nearest point lies in [αlo, αhi] and d/t ≤ the upper bound, at
    sampled points of the cell; the enclosure is claimed on a fair share of the cells."""
    conic = SITES[site]
    g = site_geometry(conic)
    m = np.array([3.0, -1.0])
    fc = FC.FarConic(g, m)
    rng = random.Random(1000 + site)
    cells = _cells(rng, 60)
    t0, t1, a0, a1 = (np.array(v, float) for v in zip(*cells))
    ok, lo, hi, up = fc.gradient(t0, t1, a0, a1)
    assert ok.sum() >= 15
    for c in np.nonzero(ok)[0][:25]:
        for _ in range(3):
            tau = rng.uniform(t0[c], t1[c]) if t0[c] > 0 else 1 / rng.uniform(1 / t1[c], 1e6)
            th = rng.uniform(a0[c], a1[c])
            q = m + (1 / tau) * np.array([math.cos(th), math.sin(th)])
            d, ang = ref_nearest(conic, q)
            assert _in_arc(ang, lo[c], hi[c]), (c, ang, lo[c], hi[c])
            assert d * tau <= up[c] * (1 + 1e-12)


@pytest.mark.parametrize("site", range(len(SITES)))
def test_third_site_lower_bounds_are_below_the_mpmath_distance(site):
    """FarConic.lower (tangent half-planes, asymptotic cones) is a lower bound of d/t on random
    cells, also for points on the convex side of the site (where it must fall to 0 or below)."""
    conic = SITES[site]
    fc = FC.FarConic(site_geometry(conic), np.array([3.0, -1.0]))
    rng = random.Random(2000 + site)
    cells = _cells(rng, 40)
    t0, t1, a0, a1 = (np.array(v, float) for v in zip(*cells))
    tang = (0.0, 1.5, -1.5, 12.0, -12.0)
    low = fc.lower(t0, t1, a0, a1, tangents=tang)
    assert (low > 0.05).sum() >= 8
    for c in range(len(cells)):
        tau = rng.uniform(t0[c], t1[c]) if t0[c] > 0 else 1 / rng.uniform(1 / t1[c], 1e6)
        th = rng.uniform(a0[c], a1[c])
        q = np.array([3.0, -1.0]) + (1 / tau) * np.array([math.cos(th), math.sin(th)])
        d, _ = ref_nearest(conic, q)
        assert low[c] <= d * tau * (1 + 1e-12) + 1e-15


def test_bounded_lower_bound_boundary():
    """d ≥ t − |m − c| − ρ: a point site at distance 5 from m (3-4-5), ρ = 0: at t = 10 in the
    direction away from it d = 15 ≥ 10·(1 − 0.5); the bound is exactly 1 − τ·5 (margins 1e-12)."""
    v = FC.bounded_lower((0.0, 0.0), (3.0, 4.0), 0.0, 0.1)
    assert 0.5 - 1e-11 < v <= 0.5
    v2 = FC.bounded_lower((0.0, 0.0), (3.0, 4.0), 1.0, 0.1)
    assert 0.4 - 1e-11 < v2 <= 0.4


# ----------------------------------------------------------------------------- asymptotic functions

@pytest.mark.parametrize("site", range(len(SITES)))
def test_asymptotic_function_is_the_far_distance_ratio(site):
    """c_k(θ) = lim d(t·u)/t (mpmath at t = 10⁹, error O(1/√t) for a parabola) and c_range
    contains it on cells; at the rays of the asymptotic cone c = 0."""
    conic = SITES[site]
    fc = FC.FarConic(site_geometry(conic), np.zeros(2))
    fars = {0: fc}
    rng = random.Random(3000 + site)
    for _ in range(12):
        th = rng.uniform(-math.pi, math.pi)
        t = 1e9
        d, _ = ref_nearest(conic, (t * math.cos(th), t * math.sin(th)))
        assert abs(d / t - float(FA.c_float(fars, 0, th))) < 1e-3
        lo, hi = FA.c_range(fars, 0, th + 0.001, 0.002)
        assert lo <= float(FA.c_float(fars, 0, th)) <= hi
    for r in fc.rays():
        assert FA.c_range(fars, 0, r, 1e-9)[0] <= 0.0


# ----------------------------------------------------------------------------- tails and accounting

def _scene():
    return [Conic.parabola(vertex=(0, 12), p=3, rotation=(0, 1)), Conic.parabola(vertex=(0, -12), p=3, rotation=(0, -1)),
            Conic.hyperbola(centre=(0, 0), axes=(14, 14), rotation=(1, 0)), Point(1, 2), Point(-3, -1), Point(2, -4)]


@pytest.fixture(scope="module")
def proved_scene():
    from curvedvoronoi.runtime.voronoi.construction import voronoi
    from curvedvoronoi.runtime.voronoi.verify.certificate import verify

    sites = _scene()
    D = voronoi(sites, certify=False)
    return sites, D, verify(D, sites)


def _far_owner(sites, th, t=1e7):
    """Index of the nearest site at t·u(θ) (mpmath references; points directly)."""
    q = (t * math.cos(th), t * math.sin(th))
    ds = []
    for s in sites:
        if isinstance(s, Point):
            ds.append(math.hypot(q[0] - float(s.x), q[1] - float(s.y)))
        else:
            ds.append(ref_nearest(s, q)[0])
    return int(np.argmin(ds))


def test_tails_between_parabolas_and_hyperbola_are_proved_and_match_the_far_owners(proved_scene):
    """Two parabolas (up, down) and a hyperbola around three points: the four unbounded edges
    (parabola–hyperbola) are proved with the accounting, and their pairs are the owners on either
    side of each change of nearest site on a circle of radius 10⁷ (mpmath distances)."""
    sites, D, cert = proved_scene
    assert cert.ok and cert.complete, cert.problems
    unb = sorted(tuple(sorted(e.sites)) for e in D.edges if None in e.ends)
    ths = np.linspace(-math.pi, math.pi, 73)[:-1] + 0.01
    own = [_far_owner(sites, th) for th in ths]
    changes = sorted(tuple(sorted((own[k], own[(k + 1) % len(own)]))) for k in range(len(own))
                     if own[k] != own[(k + 1) % len(own)])
    assert unb == changes == [(0, 2), (0, 2), (1, 2), (1, 2)]


def test_accounting_rejects_a_missing_or_misplaced_end(proved_scene):
    """The ends at infinity of the proved tails with one dropped, or with a pair changed, are
    rejected by the accounting; all of them are accepted."""
    from curvedvoronoi.runtime.voronoi.verify.edge_checks import check_edges  # noqa: F401  (import check only)

    sites, D, cert = proved_scene
    geoms = [site_geometry(s) for s in sites]
    m = FA.far_centre(geoms)
    fars = {k: FC.FarConic(g, m) for k, g in enumerate(geoms) if g.kind in FC.UNBOUNDED}
    ends = []
    for e in D.edges:
        if None not in e.ends:
            continue
        P = np.array(e.polyline, float)
        q = P[-1] if e.ends[1] is None else P[0]
        th0 = math.atan2(q[1] - m[1], q[0] - m[0])
        i, j = sorted(e.sites)
        ths = FA.asymptotic_direction(fars, len(geoms), i, j, th0)
        J = FA.lead_interval(fars, len(geoms), i, j, ths, ths - 0.1, ths + 0.1)
        assert J is not None
        ends.append((ths, (i, j), (J[0], J[1]), e.id))
    probs = []
    assert FA.accounting_unbounded(geoms, ends, probs), probs
    probs = []
    assert not FA.accounting_unbounded(geoms, ends[1:], probs) and probs
    bad = [(ends[0][0], (0, 1) if ends[0][1] != (0, 1) else (0, 2), ends[0][2], ends[0][3])] + ends[1:]
    probs = []
    assert not FA.accounting_unbounded(geoms, bad, probs) and probs


def test_a_point_inside_a_parabola_is_not_accepted(proved_scene):
    """A point site on the convex side of the upper parabola (at (0, 20)): the separation of step
    (b) fails, so the accounting fails and names the pair; at (0, 12 − 10⁻⁹·…) just below the vertex
    (outside) it does not fail on that account."""
    sites, D, cert = proved_scene
    for y, inside in ((20, True), (Fr(119, 10), False)):
        geoms = [site_geometry(s) for s in list(sites) + [Point(0, y)]]
        probs = []
        FA.accounting_unbounded(geoms, [], probs)
        named = any("not proved outside the convex side of the unbounded site 0" in p for p in probs)
        assert named == inside, probs


def test_tail_with_a_third_site_near_its_far_bisector_is_not_proved(monkeypatch):
    """The tail proofs of the scene, replayed with one more point site: at 3 times the radius of
    the link point, 0.5 off the bisector's far direction, it owns part of the bisector's far
    neighbourhood, and the tail of that edge is not proved (a third site undecided); a point at (4, 1)
    among the others leaves every replayed tail proved."""
    from curvedvoronoi.runtime.voronoi.construction import voronoi
    from curvedvoronoi.runtime.voronoi.verify import tail
    from curvedvoronoi.runtime.voronoi.verify.certificate import verify
    from curvedvoronoi.runtime.voronoi.verify.conic_tail import prove_conic_tail
    from curvedvoronoi.runtime.voronoi.verify.site_table import SiteTable

    calls = []

    def spy(geoms, table, pair, link, scale, max_work=200000):
        calls.append((pair, link, scale))
        return prove_conic_tail(geoms, table, pair, link, scale, max_work)

    monkeypatch.setattr(tail, "prove_conic_tail", spy)
    sites = _scene()
    assert verify(voronoi(sites, certify=False), sites).ok
    assert len(calls) == 4
    for pair, link, scale in calls[:2]:
        P0, tv = np.asarray(link[0], float), np.asarray(link[1], float)
        X = P0 + link[5] * tv
        for q, proved in ((3 * X, False), ((4, 1), True)):
            pt = Point(round(q[0]), round(q[1]))
            geoms = [site_geometry(s) for s in sites + [pt]]
            ok, msg, _ = prove_conic_tail(geoms, SiteTable(geoms, scale), pair, link, scale, 20000)
            assert ok == proved, (pair, q, msg)
            assert proved or "undecided" in msg, msg


def test_a_sector_ray_that_the_bisector_crosses_far_out_is_refused(monkeypatch):
    """The bisector of the upper parabola and the hyperbola crosses the link circle at an angle
    θX and tends to the asymptotic direction θ* ≠ θX: on the ray at (θX + θ*)/2 the sign of
    d_i − d_j at the link circle is that of one side, far out that of the other (c_i − c_j).
    prove_sector on a sector ending at that ray must fail for both orientations σ, while the
    sector around θX and θ* is proved."""
    from curvedvoronoi.runtime.voronoi.construction import voronoi
    from curvedvoronoi.runtime.voronoi.verify import tail
    from curvedvoronoi.runtime.voronoi.verify.certificate import verify
    from curvedvoronoi.runtime.voronoi.verify.conic_tail import prove_conic_tail, prove_sector
    from curvedvoronoi.runtime.voronoi.verify.site_table import SiteTable
    from curvedvoronoi.runtime.voronoi.verify.tail_link import link_arc

    calls = []
    monkeypatch.setattr(tail, "prove_conic_tail",
                        lambda g, tb, pair, link, scale, mw=200000: calls.append((g, pair, link, scale))
                        or prove_conic_tail(g, tb, pair, link, scale, mw))
    sites = _scene()
    assert verify(voronoi(sites, certify=False), sites).ok
    geoms, pair, link, scale = calls[0]
    table = SiteTable(geoms, scale)
    m = FA.far_centre(geoms)
    fars = {k: FC.FarConic(g, m) for k, g in enumerate(geoms) if g.kind in FC.UNBOUNDED}
    ok, _, plo, phi, r = link_arc(m, table, pair, link, scale)
    thX = 0.5 * (plo + phi)
    ths = FA.asymptotic_direction(fars, len(geoms), pair[0], pair[1], thX)
    ths = thX + ((ths - thX + math.pi) % (2 * math.pi)) - math.pi
    assert ok and abs(ths - thX) > 0.01
    mid = 0.5 * (thX + ths)
    side = math.copysign(0.08, thX - ths)
    tha, thb = sorted((mid, thX + side))
    msgs = []
    for sigma in (1.0, -1.0):
        ok, msg = prove_sector(geoms, fars, table, pair, tha, thb, sigma, r, m, scale, 20000)
        assert not ok
        msgs.append(msg)
    # one orientation fails at the link circle, the other on the ray further out
    assert sum("on the ray at angle" in s_ for s_ in msgs) == 1, msgs
    tha, thb = min(thX, ths) - 0.05, max(thX, ths) + 0.05
    res = [prove_sector(geoms, fars, table, pair, tha, thb, s, r, m, scale, 20000)[0] for s in (1.0, -1.0)]
    assert sorted(res) == [False, True]


def test_lead_interval_refuses_a_direction_where_a_third_site_is_nearer():
    """Parabolas with axes at 0° and at atan2(4, 3): c_0 = c_1 at half that angle (26.57°).  A third
    parabola whose axis points at 16.26° (24/25, 7/25) has c_2 = sin(10.3°) < sin(26.57°) there:
    no interval J; with its axis reversed (c_2 = 1) J exists."""
    m = np.zeros(2)
    ths = 0.5 * math.atan2(4, 3)
    for rot, want in (((Fr(24, 25), Fr(7, 25)), False), ((Fr(-24, 25), Fr(-7, 25)), True)):
        sites = [Conic.parabola(vertex=(0, 0), p=1, rotation=(1, 0)),
                 Conic.parabola(vertex=(0, 0), p=1, rotation=(Fr(3, 5), Fr(4, 5))),
                 Conic.parabola(vertex=(0, 0), p=1, rotation=rot)]
        fars = {k: FC.FarConic(site_geometry(s), m) for k, s in enumerate(sites)}
        J = FA.lead_interval(fars, 3, 0, 1, ths, ths - 0.2, ths + 0.2)
        assert (J is not None) == want
        if want:
            assert J[0] < ths < J[1]


@pytest.mark.parametrize("factor", [2.0, 0.5])
@pytest.mark.parametrize("site", [1, 3])
def test_wrong_float_guides_of_the_foot_are_refused(site, factor, monkeypatch):
    """The foot brackets are float guesses checked by the proof: with guesses twice the true foot
    parameter or half of it (on the wrong side of it for one end of the bracket), every cell the
    enclosure still claims contains the mpmath gradient (the proof refused the wrong brackets)."""
    conic = SITES[site]
    fp, fh = FC.parabola_foot_guess, FC.hyperbola_foot_guess
    monkeypatch.setattr(FC, "parabola_foot_guess", lambda X, Y, p: factor * fp(X, Y, p))
    monkeypatch.setattr(FC, "hyperbola_foot_guess", lambda X, Y, a, b: factor * fh(X, Y, a, b))
    m = np.array([3.0, -1.0])
    fc = FC.FarConic(site_geometry(conic), m)
    rng = random.Random(4000 + site)
    cells = _cells(rng, 40)
    t0, t1, a0, a1 = (np.array(v, float) for v in zip(*cells))
    ok, lo, hi, up = fc.gradient(t0, t1, a0, a1)
    for c in np.nonzero(ok)[0][:12]:
        for tau in {t1[c], t0[c] if t0[c] > 0 else t1[c] * 1e-3}:
            for th in (a0[c], a1[c]):
                d, ang = ref_nearest(conic, m + (1 / tau) * np.array([math.cos(th), math.sin(th)]))
                assert _in_arc(ang, lo[c], hi[c]), (c, ang, lo[c], hi[c])


@pytest.mark.parametrize("eps", [1e-9, 0.0, -1e-9])
def test_monotonicity_on_both_sides_of_equal_normal_components(eps):
    """(M) at θ = π/2 with ∇d_i = u(θ + x), ∇d_j = u(θ + π − x + eps), x = π/3: the components along
    u⊥ are sin x and sin(π − x + eps) = sin(x − eps), difference ≈ eps·cos x: σ = 1 proved for
    eps = 1e-9, σ = −1 for eps = −1e-9, neither at eps = 0 (equal components)."""
    from curvedvoronoi.runtime.voronoi.verify.conic_tail import monotone_in_theta

    th, x = 0.5 * math.pi, math.pi / 3
    ai = np.array([th + x])
    aj = np.array([th + math.pi - x + eps])
    pos = monotone_in_theta(ai, ai, aj, aj, np.array([th]), np.array([th]), 1.0)[0]
    neg = monotone_in_theta(ai, ai, aj, aj, np.array([th]), np.array([th]), -1.0)[0]
    assert (pos, neg) == (eps > 0, eps < 0)
    # on the cell θ ∈ [π/2 − 1e-6, π/2 + 1e-6] the difference is ≈ cos x·(eps − 2(θ − π/2)): it changes
    # sign inside the cell for eps = 1e-9, so neither orientation may be proved there
    w = np.array([1e-6])
    cell = [monotone_in_theta(ai, ai, aj, aj, th - w, th + w, s)[0] for s in (1.0, -1.0)]
    assert cell == [False, False]
