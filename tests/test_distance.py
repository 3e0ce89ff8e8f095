"""Tests of runtime.sites.distance against the independent sampling oracle of tests/reference.py
(thesis §5.2: the Voronoi vertex conditions are equalities of these distances)."""
from __future__ import annotations

import math
import random
from fractions import Fraction as F

import flint
import mpmath
import pytest
from hypothesis import example, given, settings, strategies as st, HealthCheck

from curvedvoronoi.runtime.sites.conic import Conic
from curvedvoronoi.runtime.sites.distance import closest_point, distance, foot_points
from curvedvoronoi.runtime.sites.distance_ball import (distance_ball, distance_sign_vs, squared_distance_ball,
                                                       tangency_polynomial)
from curvedvoronoi.runtime.validation import required_cases_path, load_cases
from reference import RefConic, ref_distance, ref_foot, _dist2, _golden_mp

CASES_PATH = required_cases_path()   # a missing file fails loudly, never skips


@st.composite
def rotation(draw):
    m, n = draw(st.integers(1, 20)), draw(st.integers(0, 20))
    c, s = F(m * m - n * n, m * m + n * n), F(2 * m * n, m * m + n * n)
    for _ in range(draw(st.integers(0, 3))):
        c, s = -s, c
    return c, s


pos = st.fractions(min_value=F(1, 10), max_value=10, max_denominator=20)
coord = st.fractions(min_value=-10, max_value=10, max_denominator=20)


@st.composite
def conic_spec(draw):
    kind = draw(st.sampled_from(["ellipse", "hyperbola", "parabola", "circle"]))
    c, s = draw(rotation())
    tx, ty = draw(coord), draw(coord)
    if kind in ("ellipse", "hyperbola"):
        A2, B2 = draw(pos), draw(pos)
        if kind == "ellipse" and A2 == B2:
            B2 = A2 / 2
        prm = {"A2": A2, "B2": B2}
    elif kind == "parabola":
        prm = {"p": draw(pos)}
    else:
        prm = {"r2": draw(pos)}
        c, s = F(1), F(0)
    spec = {"type": kind, "cos": c, "sin": s, "tx": tx, "ty": ty, **prm}
    return spec


def build(spec) -> Conic:
    prm = {k: v for k, v in spec.items() if k in ("A2", "B2", "p", "r2")}
    return Conic.from_canonical(spec["type"], spec["cos"], spec["sin"], spec["tx"], spec["ty"], **prm)


def world(spec, X, Y):
    c, s = spec["cos"], spec["sin"]
    return spec["tx"] + c * X - s * Y, spec["ty"] + s * X + c * Y


def special_points(spec):
    """canonical-frame points: centre/vertex, on both axes, near evolute cusps, far away."""
    k = spec["type"]
    pts = [(F(0), F(0)), (F(1, 3), F(0)), (F(0), F(2, 7)), (F(10 ** 6), F(-3 * 10 ** 5)), (F(-4000), F(7))]
    if k in ("ellipse", "hyperbola"):
        A2, B2 = spec["A2"], spec["B2"]
        sgn = 1 if k == "ellipse" else -1
        # cusps of the evolute: ((A2 - sgn B2)/a, 0) and (0, (B2 - sgn A2)/b) (approximately)
        a, b = math.sqrt(A2), math.sqrt(B2)
        cx = (float(A2) - sgn * float(B2)) / a
        cy = (float(B2) - sgn * float(A2)) / b
        for eps in (0.0, 1e-6, -1e-6):
            pts += [(F(cx + eps), F(0)), (F(cx), F(eps)), (F(0), F(cy + eps))]
        pts += [(F(a) * 2, F(0)), (F(0), F(b) * 2), (F(a), F(b))]
    elif k == "parabola":
        p = spec["p"]
        for eps in (0, F(1, 10 ** 6), -F(1, 10 ** 6)):
            pts += [(p + eps, F(0)), (p, eps), (3 * p, eps), (-p, eps)]
    else:
        r = math.sqrt(spec["r2"])
        pts += [(F(r) * F(1, 2), F(0)), (F(r) * 3, F(r))]
    return pts


def close(a, b, rel=1e-10):
    return abs(float(a) - float(b)) <= rel * (1 + abs(float(b)))


# ----------------------------------------------------------------------------- float route

@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(conic_spec(), st.lists(st.tuples(coord, coord), min_size=1, max_size=3))
def test_distance_matches_reference_random_points(spec, pts):
    con, ref = build(spec), RefConic(spec)
    for x, y in pts:
        d = distance(con, float(x), float(y))
        r = ref_distance(ref, float(x), float(y))
        assert close(d, r, 1e-10), (spec, x, y, d, r)


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(conic_spec())
def test_distance_special_points(spec):
    con, ref = build(spec), RefConic(spec)
    for X, Y in special_points(spec):
        x, y = world(spec, X, Y)
        d = distance(con, float(x), float(y))
        r = ref_distance(ref, float(x), float(y))
        assert close(d, r, 1e-9), (spec, X, Y, d, r)
        fps = foot_points(con, float(x), float(y))
        assert fps and fps[0][2] == pytest.approx(d, rel=1e-9, abs=1e-12)
        px, py, dd = closest_point(con, float(x), float(y))
        assert dd == pytest.approx(d, rel=1e-12, abs=1e-15)


def test_foot_points_counts_and_normal_condition():
    e = Conic.ellipse((1, 2), (3, 1), (F(3, 5), F(4, 5)))
    fps = foot_points(e, 1.0, 2.0)  # centre: the four vertices
    assert len(fps) == 4
    assert [round(t[2], 12) for t in fps] == [1.0, 1.0, 3.0, 3.0]
    h = Conic.hyperbola((0, 0), (1, 2))
    assert [round(t[2], 12) for t in foot_points(h, 0.0, 0.0)] == [1.0, 1.0]
    p = Conic.parabola((0, 0), p=1)
    assert len(foot_points(p, 3.0, 0.0)) == 3  # inside the evolute: vertex and two symmetric feet
    assert len(foot_points(p, 0.5, 0.0)) == 1
    # normal condition at every foot point: (q - P) parallel to the gradient
    for con, q in ((e, (0.3, 0.9)), (h, (0.2, 3.0)), (p, (2.0, 0.7))):
        a, b, c, d, ee, f = (float(v) for v in con.coefficients)
        for px, py, dist in foot_points(con, *q):
            gx, gy = 2 * a * px + b * py + d, b * px + 2 * c * py + ee
            cross = (q[0] - px) * gy - (q[1] - py) * gx
            assert abs(cross) <= 1e-9 * math.hypot(gx, gy) * (1 + dist)
            assert abs(con(px, py)) <= 1e-9 * (1 + abs(gx) + abs(gy))


def _lagrange_real_roots(kind, A2, B2, p, u, v) -> int:
    """Independent count of the foot points of q = (u, v) (canonical frame, u v ≠ 0): the real
    roots λ of the Lagrange polynomial of q − P = λ ∇g(P)/2 (each gives one foot point), found
    by mpmath at 60 digits.  Ellipse (X, Y) = (A2 u/(A2 + λ), B2 v/(B2 + λ)); hyperbola
    (A2 u/(A2 + λ), B2 v/(B2 − λ)); parabola Y² = 2pX: (u + λ p, v/(1 + λ))."""
    with mpmath.workdps(60):
        u, v = mpmath.mpf(u), mpmath.mpf(v)
        if kind == "ellipse":
            A, B = mpmath.mpf(A2), mpmath.mpf(B2)
            # A u² (λ + B)² + B v² (λ + A)² − (λ + A)² (λ + B)²
            coeffs = _padd(_padd(_pmul([A * u * u], _psq([1, B])), _pmul([B * v * v], _psq([1, A]))),
                           [-c for c in _pmul(_psq([1, A]), _psq([1, B]))])
        elif kind == "hyperbola":
            A, B = mpmath.mpf(A2), mpmath.mpf(B2)
            # A u² (B − λ)² − B v² (λ + A)² − (λ + A)² (B − λ)²
            coeffs = _padd(_padd(_pmul([A * u * u], _psq([-1, B])), [-c for c in _pmul([B * v * v], _psq([1, A]))]),
                           [-c for c in _pmul(_psq([1, A]), _psq([-1, B]))])
        else:
            pp = mpmath.mpf(p)
            # v² − 2p (u + λ p) (1 + λ)²
            coeffs = _padd([v * v], [-c for c in _pmul([2 * pp * pp, 2 * pp * u], _psq([1, 1]))])
        roots = mpmath.polyroots(coeffs, maxsteps=500, extraprec=500)
        return sum(1 for z in roots if abs(mpmath.im(z)) <= mpmath.mpf(10) ** -40 * (1 + abs(z)))


def _pmul(f, g):
    out = [0] * (len(f) + len(g) - 1)
    for i, a in enumerate(f):
        for j, b in enumerate(g):
            out[i + j] += a * b
    return out


def _psq(f):
    return _pmul(f, f)


def _padd(f, g):
    n = max(len(f), len(g))
    f, g = [0] * (n - len(f)) + list(f), [0] * (n - len(g)) + list(g)
    return [a + b for a, b in zip(f, g)]


def test_foot_point_count_matches_lagrange_polynomial_near_the_evolute():
    """The number of foot points equals the number of real roots of the Lagrange polynomial
    (independent, 60 digits) for points at relative distance 1e-10 and 1e-7 on either side of the
    evolute (where a double root splits into two real or two complex roots, imaginary parts
    ~1e-5 relative) and at random points; a complex pair close to the real axis is not a foot
    point."""
    rng = random.Random(20261123)
    for _ in range(150):
        kind = rng.choice(["ellipse", "hyperbola", "parabola"])
        A2, B2, p = rng.uniform(0.2, 5), rng.uniform(0.2, 5), rng.uniform(0.2, 3)
        if kind == "ellipse":
            A2, B2 = max(A2, B2) + 0.1, min(A2, B2)
            a, b, th = math.sqrt(A2), math.sqrt(B2), rng.uniform(0.1, 1.4)
            X0, Y0 = (A2 - B2) / a * math.cos(th) ** 3, (A2 - B2) / b * math.sin(th) ** 3
        elif kind == "hyperbola":
            a, b, t = math.sqrt(A2), math.sqrt(B2), rng.uniform(0.1, 1.5)
            X0, Y0 = (A2 + B2) / a * math.cosh(t) ** 3, (A2 + B2) / b * math.sinh(t) ** 3
        else:
            s = rng.uniform(0.2, 2) * p
            X0, Y0 = p + 1.5 * s * s / p, s ** 3 / p ** 2
        f = 1 + rng.choice([-1e-10, 1e-10, -1e-7, 1e-7, 0.3, -0.3])
        X0, Y0 = X0 * f * rng.choice([-1, 1]), Y0 * f * rng.choice([-1, 1])
        spec = {"type": kind, "cos": F(1), "sin": F(0), "tx": F(0), "ty": F(0)}
        spec.update({"p": F(p)} if kind == "parabola" else {"A2": F(A2), "B2": F(B2)})
        con = build(spec)
        prm = con.frame.params
        want = _lagrange_real_roots(kind, prm.get("A2"), prm.get("B2"), prm.get("p"), X0, Y0)
        got = foot_points(con, X0, Y0)
        assert len(got) == want, (spec, X0, Y0, got, want)
        d = ref_distance(RefConic(spec), X0, Y0)
        assert close(got[0][2], d, 1e-9), (spec, X0, Y0, got, d)


# ----------------------------------------------------------------------------- rigorous route

def _mp(x: flint.arb) -> mpmath.mpf:
    m, e = x.man_exp()
    return mpmath.ldexp(mpmath.mpf(int(m)), int(e))


def _contains(ball: flint.arb, value: mpmath.mpf, slack: float) -> bool:
    with mpmath.workdps(60):
        m, rad = _mp(ball.mid()), _mp(ball.rad())
        return abs(m - value) <= rad + slack * (1 + abs(value))


def ref_distance_polished(ref: RefConic, x, y, dps: int = 50) -> mpmath.mpf:
    """ref_distance, then a golden-section minimisation of the squared distance on each side of
    the reference foot parameter (the reference's own parametrisation and routines).

    Needed within ~1e-17 of an evolute cusp: the sampling oracle brackets the vertex, which is
    there a local *maximum* of the distance along the curve lying ~1e-33 above the two nearby
    true minima (e.g. ellipse A2 = 3/10, B2 = 1/10, q = (float((A2 − B2)/√A2), 0), just inside
    the evolute: d = 0.18257418583505539717643691294120077..., vertex 0.18257418583505539717643691294120355...).
    Every value considered is the distance to a true curve point, so the result is still an
    upper bound of the distance, never below it."""
    with mpmath.workdps(dps + 10):
        d, wx, wy = ref_foot(ref, x, y, dps=dps)
        if not mpmath.isfinite(d):
            return d
        xm, ym = (mpmath.mpf(v.numerator) / v.denominator if isinstance(v, F) else mpmath.mpf(v)
                  for v in (x, y))
        X0, Y0 = ref.to_canon(xm, ym)
        PX, PY = ref.to_canon(wx, wy)
        if ref.kind in ("ellipse", "circle"):
            t, br, h = mpmath.atan2(PY / ref.b, PX / ref.a), 0, mpmath.mpf("1e-3")
        elif ref.kind == "hyperbola":
            t, br, h = mpmath.asinh(PY / ref.b), (1 if PX > 0 else -1), mpmath.mpf("1e-3")
        else:
            t, br, h = PY, 0, mpmath.mpf("1e-3") * ref.p
        best = d * d
        for a_, b_ in ((t - h, t), (t, t + h)):
            tm = _golden_mp(lambda s: _dist2(ref, s, br, X0, Y0), a_, b_, dps)
            best = min(best, _dist2(ref, tm, br, X0, Y0))
        return mpmath.sqrt(best)


ELLIPSE_NEAR_CUSP = {"type": "ellipse", "cos": F(1), "sin": F(0), "tx": F(0), "ty": F(0),
                     "A2": F(3, 10), "B2": F(1, 10)}


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(conic_spec(), st.tuples(coord, coord))
@example(ELLIPSE_NEAR_CUSP, (F(0), F(0)))  # special point q = (float(cusp), 0), just inside the evolute
def test_distance_ball_encloses_reference(spec, q):
    con, ref = build(spec), RefConic(spec)
    pts = [q] + [world(spec, X, Y) for X, Y in special_points(spec)[:6]]
    for x, y in pts:
        b = distance_ball(con, x, y, prec=128)
        r = ref_distance_polished(ref, x, y)
        assert _contains(b, r, 1e-33), (spec, x, y, b, r)
        # tight: relative radius (points on the curve lose half the digits through the square root)
        assert float(b.rad()) <= 1e-15 * (1 + float(r))


def test_distance_ball_with_ball_input_encloses_box():
    con = Conic.hyperbola((1, -1), (2, 1), (F(5, 13), F(12, 13)))
    spec = {"type": "hyperbola", "cos": F(5, 13), "sin": F(12, 13), "tx": 1, "ty": -1, "A2": 4, "B2": 1}
    ref = RefConic(spec)
    bx, by = flint.arb(0.7, 0.01), flint.arb(-2.3, 0.02)
    b = distance_ball(con, bx, by, prec=64)
    for x in (0.69, 0.7, 0.71):
        for y in (-2.32, -2.3, -2.28):
            assert _contains(b, ref_distance(ref, x, y), 0)
    assert float(b.rad()) < 0.05


def test_squared_distance_ball_on_degenerate_points():
    # centre of an ellipse (four critical points), on an axis near the evolute cusp
    e = Conic.ellipse((0, 0), (2, 1))
    lo, hi, _ = squared_distance_ball(e, 0, 0, prec=100)
    assert lo <= 1 <= hi and float(hi - lo) < 1e-25
    cusp = F(3, 2)  # (A2 - B2)/a = 3/2: degenerate quartic minimum at the vertex (2, 0)
    lo, hi, _ = squared_distance_ball(e, cusp, 0, prec=100)
    assert lo <= flint.arb(0.25) <= hi and float(hi - lo) < 1e-25


# ----------------------------------------------------------------------------- signs and tangency

def test_sign_vs_radius_and_exact_tangency():
    # parabola y² = 2x, q = (5/2, 0): d² = 2pX0 − p² = 4 exactly (feet at X = 3/2)
    rot = (F(3, 5), F(4, 5))
    par = Conic.parabola((F(1, 3), F(-2, 7)), p=1, rotation=rot)
    qx, qy = F(1, 3) + F(3, 5) * F(5, 2), F(-2, 7) + F(4, 5) * F(5, 2)
    assert distance(par, float(qx), float(qy)) == pytest.approx(2.0, rel=1e-14)
    assert distance_sign_vs(par, qx, qy, 2) == 0
    assert distance_sign_vs(par, qx, qy, 2 + F(1, 10 ** 20)) == -1
    assert distance_sign_vs(par, qx, qy, 2 - F(1, 10 ** 20)) == 1
    assert distance_sign_vs(par, float(qx), float(qy), 1.5) == 1
    # centre of an ellipse: d = minor semi-axis (a degenerate, symmetric configuration)
    ell = Conic.ellipse((1, 1), (3, 2), rot)
    assert distance_sign_vs(ell, 1, 1, 2) == 0
    assert distance_sign_vs(ell, 1, 1, F(201, 100)) == -1
    # centre of a hyperbola: d = real semi-axis
    hyp = Conic.hyperbola((0, 0), (F(3, 2), 1), (F(-8, 17), F(15, 17)))
    assert distance_sign_vs(hyp, 0, 0, F(3, 2)) == 0
    # circle: exact decision, including tangency from inside and outside
    cir = Conic.circle((1, 2), radius=3)
    assert distance_sign_vs(cir, 1, 7, 2) == 0
    assert distance_sign_vs(cir, 1, 3, 2) == 0
    assert distance_sign_vs(cir, 1, 3, F(199, 100)) == 1
    # a critical value that is not the minimum is not a tangency of the empty circle
    assert distance_sign_vs(ell, 1, 1, 3) == -1


def test_tangency_polynomial_vanishes_at_critical_values():
    e = Conic.ellipse((0, 0), (2, 1))
    P = tangency_polynomial(e, 0, 0)
    assert P(1) == 0 and P(4) == 0 and P(2) != 0


# ----------------------------------------------------------------------------- validation cases

def test_validation_vertex_distances():
    """At every stored vertex: distance() gives the radius for C1..C3 and the stored distance
    to C4; distance_ball at the 30-digit vertex encloses the stored values (1-Lipschitz
    slack for the rounding of the vertex)."""
    cases = load_cases(CASES_PATH)
    nb = 0
    for case in cases:
        for v in case.vertices:
            x, y = float(v.x), float(v.y)
            for con in case.conics[:3]:
                assert close(distance(con, x, y), v.radius, 1e-11)
            assert close(distance(case.conics[3], x, y), v.distance_to_fourth, 1e-11)
            if nb < 40 or case.group in ("near_degenerate", "exactly_tangent") and v.tangent or abs(v.margin) < 1e-6:
                nb += 1
                b = distance_ball(case.conics[3], v.x, v.y, prec=128)
                with mpmath.workdps(50):
                    want = mpmath.mpf(v.distance_to_fourth.numerator) / v.distance_to_fourth.denominator
                assert _contains(b, want, 1e-28)
