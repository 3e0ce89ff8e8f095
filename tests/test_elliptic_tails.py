"""Infinite ends of the edges of an elliptic piece on the hull of the sites
(runtime.segments.certificate_ellipse_tails; thesis Prop. 1.2.1, ch. 4 — the foot curve of a conic
and a point —, §2.2).

The references are closed forms of the ellipse (x/2)² + y² = 1 (a = 2, b = 1), independent of the
code: the tangent from p = (3, 0) touches it at e∞ = (4/3, √5/3), φ∞ = arccos(2/3), along the line
x + √5 y = 3; the tangent at a point (2u, v) of the ellipse is x u/2 + y v = 1.  A third point
strictly inside the tangent's half-plane is farther than the two sites far along the edge's
asymptote (its support in the asymptote's direction is smaller, so d_q − t tends to a positive
gap), a point beyond it is nearer there (the edge does not go to infinity in that direction): a
sound tail proof must refuse it.  Both sides of the line are tested at 10⁻⁴ and 10⁻⁹ from it.
"""
from __future__ import annotations

from fractions import Fraction

import mpmath as mp
import numpy as np
import pytest
from flint import arb

import curvedvoronoi as cv
from curvedvoronoi.runtime.certify.foot import working_prec
from curvedvoronoi.runtime.segments.certificate_ellipse_curves import FootCurve
from curvedvoronoi.runtime.segments.certificate_ellipse_tails import foot_poles, foot_tail, normal_ray_farther
from curvedvoronoi.runtime.segments.certificate_hull import infinite_key
from curvedvoronoi.runtime.segments.certificate_sites import ELLIPSE, SiteTable
from curvedvoronoi.runtime.sites.elliptic_arc import EllipticArc

pytestmark = pytest.mark.mpmath_dps(30)

ARC = (0.2, 1.3)                 # one piece, in the first quadrant of the frame
P = (3, 0)


def table(extra=()):
    """The elementary sites of the arc and p (the arc's two ends are point sites), plus ``extra``
    point sites appended; (T, piece index, index of p)."""
    D = cv.voronoi([cv.Arc.elliptic((0, 0), (2, 0), "1/2", *ARC), cv.Point(*P)], certify=False)
    sites = list(D.sites) + [cv.Point(*q) for q in extra]
    T = SiteTable(sites)
    s = next(k for k in range(T.n) if T.kind[k] == ELLIPSE)
    p = next(k for k in range(T.n) if tuple(T.a[k]) == P)
    return T, s, p


def tail(extra):
    with working_prec(128):
        T, s, p = table(extra)
        c = FootCurve(T, s, p, 1, 1)
        (pole,) = foot_poles(T.piece[s], P)
        return foot_tail(T, c, p, arb(0.5), pole, 1)


def test_the_pole_is_the_tangency_point_of_the_tangent_from_p():
    with working_prec(128):
        T, s, _ = table()
        poles = foot_poles(T.piece[s], P)
    assert len(poles) == 1                       # −arccos(2/3) is outside the piece's range
    ref = mp.acos(mp.mpf(2) / 3)
    assert abs(float(poles[0].mid()) - float(ref)) < 1e-15
    assert poles[0].rad() < 1e-20
    # and the tangent at e(φ∞) passes through p: x cos φ/2 + y sin φ = 1 at (3, 0)
    assert abs(3 * mp.cos(ref) / 2 - 1) < mp.mpf(10) ** -25


@pytest.mark.parametrize("gap", [Fraction(1, 10 ** 4), Fraction(1, 10 ** 9)])
def test_a_point_inside_the_asymptotes_support_line_is_farther_on_the_tail(gap):
    # (0, y) with y below 3/√5: x + √5 y < 3
    y = Fraction(mp.nstr(3 / mp.sqrt(5), 30)) - gap
    assert 0 + mp.sqrt(5) * mp.mpf(y.numerator) / y.denominator < 3
    th_s, msg = tail([(0, y)])
    assert msg is None and th_s is not None and 0.5 < th_s < float(mp.acos(mp.mpf(2) / 3))


@pytest.mark.parametrize("gap", [Fraction(1, 10 ** 4), Fraction(1, 10 ** 9)])
def test_a_point_beyond_the_asymptotes_support_line_is_refused(gap):
    y = Fraction(mp.nstr(3 / mp.sqrt(5), 30)) + gap
    assert 0 + mp.sqrt(5) * mp.mpf(y.numerator) / y.denominator > 3
    th_s, msg = tail([(0, y)])
    assert th_s is None and "not proved" in msg


def test_a_point_beyond_the_line_is_nearer_far_along_the_asymptote():
    """The reference of the refusal above: far along x(φ) (φ → φ∞) the point beyond the line is
    nearer than t = |x − p| (mpmath on the exact foot curve)."""
    q = (mp.mpf(0), 3 / mp.sqrt(5) + mp.mpf(10) ** -4)
    pole = mp.acos(mp.mpf(2) / 3)
    phi = pole - mp.mpf(10) ** -8
    e = (2 * mp.cos(phi), mp.sin(phi))
    n = (mp.cos(phi), 2 * mp.sin(phi))                       # (e'_y, −e'_x), e' = (−2 sin, cos)
    ln = mp.sqrt(n[0] ** 2 + n[1] ** 2)
    nu = (n[0] / ln, n[1] / ln)
    D = (e[0] - 3, e[1])
    t = -(D[0] ** 2 + D[1] ** 2) / (2 * (nu[0] * D[0] + nu[1] * D[1]))
    x = (e[0] + t * nu[0], e[1] + t * nu[1])
    assert t > 10 ** 6
    assert abs(mp.hypot(x[0] - 3, x[1]) - t) < mp.mpf(10) ** -15 * t
    assert mp.hypot(x[0] - q[0], x[1] - q[1]) < t


def test_the_tail_key_is_the_side_of_the_tangency_point():
    """("tangent", sign of (z_j − z_i) × u), the sorted pair (p, piece): z the tangency point
    (4/3, √5/3), u ∝ (2/3, 2√5/3) the outward normal there: (−5/3)(2√5/3) − (√5/3)(2/3) < 0."""
    with working_prec(128):
        T, s, p = table()
        (pole,) = foot_poles(T.piece[s], P)
        u = (pole.cos(), 2 * pole.sin())
        assert p < s
        assert infinite_key(T, p, s, u, False) == ("tangent", -1)
        assert infinite_key(T, s, p, u, False) == ("tangent", -1)


def _end(T, s, which):
    code = T.ends[s][which]
    cs = T.sites[s].ua if which == 0 else T.sites[s].ub
    return code, cs


@pytest.mark.parametrize("offset,proved", [(Fraction(-1, 10 ** 9), True), (Fraction(0), False),
                                           (Fraction(1, 10 ** 9), False)])
def test_the_normal_ray_at_an_end_against_the_tangent_line(offset, proved):
    """The end e = (2u, v) at φ = 1.3: the outward normal (u, 2v); the tangent line there is
    x u/2 + y v = 1, met by x = 0 at y = 1/v: a point below it (offset < 0) is farther along the
    whole outer ray, a point on it ties at infinity, a point above is nearer far out."""
    with working_prec(128):
        T0, s, _ = table()
        code, (u, v) = _end(T0, s, 1)
        q = (0, 1 / v + offset)
        T, s, _ = table([q])
        msg = normal_ray_farther(T, s, code, (u, 2 * v))
    assert (msg is None) is proved


def test_the_normal_ray_refuses_an_inward_or_oblique_direction():
    with working_prec(128):
        T, s, _ = table()
        code, (u, v) = _end(T, s, 1)
        assert normal_ray_farther(T, s, code, (u, 2 * v)) is None
        assert normal_ray_farther(T, s, code, (-u, -2 * v)) is not None
        assert normal_ray_farther(T, s, code, (u, 3 * v)) is not None


def test_the_ellipse_support_point_is_the_tangency_point():
    """The hull key's z for a piece: the support point of (x/2)² + y² = 1 in the direction
    (2/3, 2√5/3) is (4/3, √5/3)."""
    from curvedvoronoi.runtime.segments.certificate_hull import _z
    with working_prec(128):
        T, s, _ = table()
        r5 = arb(5).sqrt()
        zx, zy = _z(T, s, arb(2) / 3, 2 * r5 / 3)
        assert (zx - arb(4) / 3).contains(0) and (zy - r5 / 3).contains(0)
        assert zx.rad() < 1e-30 and zy.rad() < 1e-30
    assert isinstance(T.sites[s], EllipticArc)


# ------------------------------------------------------------------ a piece on the hull, end to end
def mq(q):
    q = Fraction(q)
    return mp.mpf(q.numerator) / q.denominator


RING8 = [(-4, -3), (-1, -3), (0, -4), (1, -4), (4, -2)]      # bench_elliptic_ring.py 1 12, scene 8


@pytest.fixture(scope="module")
def on_hull():
    """The arc φ ∈ [1.97, 3.62] of (x/2)² + y² = 1 above five integer points: its piece from
    φ = 1.97 to the vertex (−2, 0) is on the hull of the sites, with two unbounded edges — the
    outer normal at its start (a point site) and its foot curve with (−4, −3) — proved one by
    one."""
    from curvedvoronoi.runtime.segments.certificate_ellipse_edges import prove_piece_edge
    from curvedvoronoi.runtime.segments.certificate_vertices import prove_vertices
    D = cv.voronoi([cv.Arc.elliptic((0, 0), (2, 0), "1/2", 1.97, 3.62)] + [cv.Point(*p) for p in RING8],
                   certify=False)
    out = []
    with working_prec(128):
        T = SiteTable(D.sites)
        vproofs = prove_vertices(D, T, [])
        vindex = {v.id: n for n, v in enumerate(D.vertices)}
        for e in D.edges:
            if None in e.ends and ELLIPSE in {T.kind[int(s)] for s in e.sites}:
                problems: list = []
                out.append((e, prove_piece_edge(T, D, e, vindex, vproofs, problems, [10 ** 5]), problems))
    return D, T, out


def test_the_unbounded_edges_of_a_piece_on_the_hull_are_proved(on_hull):
    D, T, out = on_hull
    assert len(out) == 2
    assert sum(T.is_endpoint(*sorted((int(a) for a in e.sites), key=lambda k: T.kind[k] == ELLIPSE))
               for e, _, _ in out) == 1                  # one normal ray, one foot tail
    for e, pr, problems in out:
        assert pr.ok, (e.id, e.sites, [str(p) for p in problems])
        assert len(pr.infinite) == 1


def test_the_proved_tails_agree_with_mpmath(on_hull):
    """Every node of the proved polylines (out to 40 units) is equidistant from the edge's two
    sites and not farther than any other site (distances in mpmath from the exact sites); the
    foot-curve tails' last chord points along the closed-form asymptote: the outward normal
    (cos φ∞, 2 sin φ∞) at the root of 1 − α cos φ − β sin φ (p = 2α e₁ + β e₂)."""
    from test_elliptic_arcs_certified import distances, reference
    D, T, out = on_hull
    ref = reference(D.sites)
    for e, pr, _ in out:
        i, j = (int(s) for s in e.sites)
        P = np.asarray(e.polyline, float)
        P = P[(np.abs(P) < 40).all(axis=1)]
        tol = 2 * float(e.tolerance) + 1e-9
        for q in P:
            d = distances(ref, q)
            assert abs(d[i] - d[j]) <= tol, (e.id, q)
            assert min(x for m, x in enumerate(d) if m not in (i, j)) >= min(d[i], d[j]) - tol, (e.id, q)
        k = i if T.kind[i] != ELLIPSE else j
        s = j if k == i else i
        if T.is_endpoint(k, s):
            continue
        al, be = mq(T.a[k][0]) / 2, mq(T.a[k][1])
        phi_p, R = mp.atan2(be, al), mp.sqrt(al ** 2 + be ** 2)
        cands = [phi_p + w * mp.acos(1 / R) for w in (1, -1)]
        Pn = np.asarray(e.polyline, float)
        far = Pn[-1] if e.ends[1] is None else Pn[0]
        chord = far - (Pn[-2] if e.ends[1] is None else Pn[1])
        chord = chord / np.hypot(*chord)
        best = min(abs(mp.atan2(2 * mp.sin(c), mp.cos(c)) - mp.atan2(chord[1], chord[0])) % (2 * mp.pi)
                   for c in cands)
        assert min(best, 2 * mp.pi - best) < 0.05, (e.id, best)


def test_the_keys_of_the_foot_tails_are_the_tangency_sides(on_hull):
    """("tangent", sign of (z_j − z_i) × u) with z the tangency point and u its outward normal,
    computed in mpmath from the closed form above; the normal ray's key is its exact direction."""
    D, T, out = on_hull
    for e, pr, _ in out:
        i, j = sorted(int(s) for s in e.sites)
        (pair, key), = pr.infinite
        assert pair == (i, j)
        k = i if T.kind[i] != ELLIPSE else j
        s = j if k == i else i
        if T.is_endpoint(k, s):
            assert key[0] != "tangent"
            continue
        al, be = mq(T.a[k][0]) / 2, mq(T.a[k][1])
        phi_p, R = mp.atan2(be, al), mp.sqrt(al ** 2 + be ** 2)
        P = T.piece[s]
        lo, hi = mp.mpf(P.phi0), mp.mpf(P.phi1)
        roots = [phi_p + w * mp.acos(1 / R) + 2 * m * mp.pi for w in (1, -1) for m in (-1, 0, 1)]
        (c,) = [r for r in roots if lo < r < hi]
        z = (2 * mp.cos(c), mp.sin(c))
        u = (mp.cos(c), 2 * mp.sin(c))
        p = (mq(T.a[k][0]), mq(T.a[k][1]))
        zi, zj = (p, z) if i == k else (z, p)
        cross = (zj[0] - zi[0]) * u[1] - (zj[1] - zi[1]) * u[0]
        assert key == ("tangent", 1 if cross > 0 else -1)
