"""Tests of runtime.sites.conic: exact classification, canonical frames, constructors (thesis §3.1, §5.1)."""
from __future__ import annotations

import math
from fractions import Fraction as F

import pytest
from hypothesis import given, settings, strategies as st, HealthCheck

from curvedvoronoi.runtime.sites.conic import Conic, CanonicalFrame, fraction_sqrt
from curvedvoronoi.runtime.result import InvalidConicError
from curvedvoronoi.runtime.validation import required_cases_path, load_cases

CASES_PATH = required_cases_path()   # a missing file fails loudly, never skips

# ----------------------------------------------------------------------------- strategies

@st.composite
def pythagorean_rotation(draw):
    """Rational point (cos, sin) of the unit circle from a Pythagorean parametrisation."""
    m = draw(st.integers(1, 30))
    n = draw(st.integers(0, 30))
    c, s = F(m * m - n * n, m * m + n * n), F(2 * m * n, m * m + n * n)
    quad = draw(st.integers(0, 3))
    for _ in range(quad):
        c, s = -s, c
    return c, s


rationals = st.fractions(min_value=-50, max_value=50, max_denominator=60)
positive = st.fractions(min_value=F(1, 50), max_value=40, max_denominator=60)


@st.composite
def canonical_conic(draw):
    kind = draw(st.sampled_from(["ellipse", "hyperbola", "parabola", "circle"]))
    c, s = draw(pythagorean_rotation())
    tx, ty = draw(rationals), draw(rationals)
    if kind in ("ellipse", "hyperbola"):
        A2, B2 = draw(positive), draw(positive)
        if kind == "ellipse" and A2 == B2:
            B2 = A2 * 2
        params = {"A2": A2, "B2": B2}
    elif kind == "parabola":
        params = {"p": draw(positive)}
    else:
        params = {"r2": draw(positive)}
        c, s = F(1), F(0)
    return kind, c, s, tx, ty, params


def same_frame(f1: CanonicalFrame, f2: CanonicalFrame) -> bool:
    return f1.normalized() == f2.normalized()


# ----------------------------------------------------------------------------- classification

@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(canonical_conic(), st.integers(1, 10 ** 6))
def test_classification_and_exact_frame_of_rational_rigid_motions(spec, scale):
    kind, c, s, tx, ty, params = spec
    con = Conic.from_canonical(kind, c, s, tx, ty, **params)
    assert con.kind == kind
    # scaling the equation does not change anything
    con2 = Conic.from_coefficients(*(scale * v for v in con.coefficients))
    assert con2 == con and con2.kind == kind
    ex = con2.exact_frame
    assert ex is not None, "rational rotation must give an exact frame"
    want = CanonicalFrame(c, s, tx, ty, kind, dict(params))
    assert same_frame(ex, want)
    # the float frame is the rounding of the exact one
    fl = con2.frame.normalized()
    exn = ex.normalized()
    for k in ("cos", "sin", "tx", "ty"):
        assert abs(getattr(fl, k) - float(getattr(exn, k))) <= 4e-16 * max(1.0, abs(float(getattr(exn, k))))
    for k, v in exn.params.items():
        assert abs(fl.params[k] - float(v)) <= 4e-16 * float(v)
    # every sampled point lies on the curve (relative residual)
    for x, y in con2.sample(16):
        val = con2(x, y)
        mag = sum(abs(float(v)) for v in con2.coefficients) * (1 + x * x + y * y)
        assert abs(val) <= 1e-11 * mag


@settings(max_examples=150, deadline=None)
@given(canonical_conic(), st.floats(-3.0, 3.0))
def test_float_angle_rotation_keeps_kind_and_shape(spec, angle):
    kind, _, _, tx, ty, params = spec
    con = Conic.from_canonical(kind, math.cos(angle), math.sin(angle), tx, ty, **params)
    assert con.kind == kind
    fr = con.frame
    if kind != "circle":
        # the axis direction is the angle modulo the symmetry of the conic
        per = 2 * math.pi if kind == "parabola" else math.pi
        got = math.atan2(fr.sin, fr.cos)
        if kind == "ellipse" and params["A2"] < params["B2"]:
            got -= math.pi / 2
        diff = math.remainder(got - angle, per)
        assert abs(diff) < 1e-9
    for k, v in params.items():
        if kind == "ellipse" and params["A2"] < params["B2"]:
            k = {"A2": "B2", "B2": "A2"}[k]
        assert fr.params[k] == pytest.approx(float(v), rel=1e-9)


def test_round_trip_coefficients_frame_coefficients_up_to_scale():
    # irrational rotation: float frame -> high-precision rebuild is proportional to the input
    con = Conic.from_coefficients(3, 1, 2, -4, 5, -7)  # ellipse, rotation not rational
    assert con.kind == "ellipse" and con.exact_frame is None
    fr = con.frame
    back = Conic.from_canonical("ellipse", fr.cos, fr.sin, fr.tx, fr.ty, **fr.params)
    u = [float(v) for v in con.normalized_coefficients]
    w = [float(v) for v in back.normalized_coefficients]
    lam = u[0] / w[0]
    assert all(abs(a - lam * b) < 1e-12 for a, b in zip(u, w))


@pytest.mark.parametrize("coeffs,kind", [
    ((1, 0, 1, 0, 0, -1), "circle"),
    ((1, 0, 4, 0, 0, -4), "ellipse"),
    ((1, 0, -1, 0, 0, -1), "hyperbola"),
    ((-1, 0, 1, 0, 0, -1), "hyperbola"),  # opens along y
    ((0, 0, 1, -2, 0, 0), "parabola"),
    ((0, 0, 1, 2, 0, 0), "parabola"),     # opens to -x
    ((1, 2, 1, 1, 0, 0), "parabola"),     # rotated by 45 degrees: irrational frame
    ((0, 1, 0, 0, 0, -1), "hyperbola"),   # xy = 1
    (("1e300", 0, "1e300", 0, 0, "-1e300"), "circle"),
    (("1e-300", 0, "2e-300", 0, 0, "-1e-300"), "ellipse"),
])
def test_kinds_and_frames_of_simple_conics(coeffs, kind):
    con = Conic.from_coefficients(*coeffs)
    assert con.kind == kind
    fr = con.frame
    # the canonical equation holds on sample points mapped to the canonical frame
    for x, y in con.sample(12):
        X, Y = fr.to_canonical(x, y)
        if fr.kind == "parabola":
            assert Y * Y == pytest.approx(2 * fr.params["p"] * X, abs=1e-9 * (1 + Y * Y))
            assert fr.params["p"] > 0
        elif fr.kind == "hyperbola":
            assert X * X / fr.params["A2"] - Y * Y / fr.params["B2"] == pytest.approx(1, abs=1e-9 * (1 + X * X))
        elif fr.kind == "ellipse":
            assert X * X / fr.params["A2"] + Y * Y / fr.params["B2"] == pytest.approx(1, abs=1e-9)
            assert fr.params["A2"] >= fr.params["B2"]
        else:
            assert X * X + Y * Y == pytest.approx(fr.params["r2"], rel=1e-12)


def test_specific_frames():
    p = Conic.from_coefficients(0, 0, 1, 2, 0, 0)  # y² = -2x: opens to -x, p = 1
    ex = p.exact_frame
    assert (ex.cos, ex.sin, ex.tx, ex.ty, ex.params["p"]) == (-1, 0, 0, 0, 1)
    h = Conic.from_coefficients(-1, 0, 1, 0, 0, -1)  # y² - x² = 1 opens along y
    ex = h.exact_frame
    assert (abs(ex.cos), abs(ex.sin)) == (0, 1) and ex.params == {"A2": 1, "B2": 1}
    e = Conic.from_coefficients(4, 0, 1, 0, 0, -4)  # x² + y²/4 = 1: major axis along y
    ex = e.exact_frame
    assert (ex.cos, ex.sin) == (0, 1) and ex.params == {"A2": 4, "B2": 1}
    r45 = Conic.from_coefficients(1, 2, 1, 1, 0, 0)
    assert r45.exact_frame is None
    assert abs(abs(r45.frame.cos) - math.sqrt(0.5)) < 1e-15


def test_huge_and_tiny_coefficients_are_exact():
    base = Conic.from_coefficients(3, 2, 5, -7, 11, -13)
    for k in (10 ** 400, F(1, 10 ** 400)):
        big = Conic.from_coefficients(*(k * v for v in base.coefficients))
        assert big == base and big.kind == base.kind
        assert big.frame == base.frame


# ----------------------------------------------------------------------------- rejection

@pytest.mark.parametrize("coeffs,words", [
    ((1, 0, -1, 0, 0, 0), "intersecting lines"),
    ((1, 0, 0, 0, 0, -1), "parallel lines"),        # x² = 1
    ((1, 2, 1, 0, 0, 0), "double line"),            # (x + y)² = 0
    ((1, 0, 1, 0, 0, 0), "single real point"),      # x² + y² = 0
    ((1, 0, 1, 0, 0, 1), "imaginary"),              # x² + y² + 1 = 0
    ((2, 1, 3, 0, 0, 5), "imaginary"),
    ((0, 0, 0, 1, 2, 3), "not a conic"),
    ((float("nan"), 0, 1, 0, 0, -1), "not finite"),
    ((1, 0, float("inf"), 0, 0, -1), "not finite"),
    (("abc", 0, 1, 0, 0, -1), "cannot parse"),
    ((True, 0, 1, 0, 0, -1), "bool"),
    ((None, 0, 1, 0, 0, -1), "unsupported type"),
])
def test_rejections_have_clear_messages(coeffs, words):
    with pytest.raises(InvalidConicError) as ei:
        Conic.from_coefficients(*coeffs)
    assert words in str(ei.value)
    assert isinstance(ei.value, ValueError)


def test_float_range_rejections():
    with pytest.raises(InvalidConicError, match="overflow"):
        Conic.circle((F(10) ** 400, 0), radius=1)
    with pytest.raises(InvalidConicError, match="underflow"):
        Conic.circle((0, 0), radius=F(1, 10 ** 200))


def test_constructor_validation():
    with pytest.raises(InvalidConicError, match="not exactly a unit vector"):
        Conic.ellipse((0, 0), (2, 1), (F(1, 2), F(1, 2)))
    with pytest.raises(InvalidConicError, match="not a unit vector"):
        Conic.ellipse((0, 0), (2, 1), (0.5, 0.5))
    with pytest.raises(InvalidConicError, match="> 0"):
        Conic.parabola((0, 0), p=-1)
    with pytest.raises(InvalidConicError):
        Conic.circle((0, 0))
    e = Conic.ellipse((1, 2), (3, 2), (F(3, 5), F(4, 5)))
    assert all(v.denominator == 1 for v in e.coefficients)
    assert Conic.ellipse((0, 0), (2, 2)).kind == "circle"
    assert Conic.circle((0, 0), r2=2).exact_frame.params == {"r2": 2}


def test_evaluation_exact_and_float():
    c = Conic.circle((1, 1), radius=F(5, 2))
    assert c(F(1), F(1) + F(5, 2)) == 0
    assert c(1, 1) == c.coefficients[0] * 0 + c(F(1), F(1))
    assert isinstance(c(0.5, 0.5), float)


def test_fraction_sqrt():
    assert fraction_sqrt(F(9, 4)) == F(3, 2)
    assert fraction_sqrt(F(2)) is None and fraction_sqrt(F(-1)) is None


# ----------------------------------------------------------------------------- validation cases

def test_validation_conics_match_their_canonical_construction():
    cases = load_cases(CASES_PATH)
    assert len(cases) == 30
    n = 0
    for case in cases:
        for con, can in zip(case.conics, case.canonical):
            n += 1
            assert con.kind == can["type"]
            params = {k: v for k, v in can.items() if k in ("A2", "B2", "p", "r2")}
            rebuilt = Conic.from_canonical(can["type"], can["cos"], can["sin"], can["tx"], can["ty"], **params)
            assert rebuilt.coefficients == con.coefficients  # primitive, same sign convention
            want = CanonicalFrame(can["cos"], can["sin"], can["tx"], can["ty"], can["type"], params)
            assert con.exact_frame is not None and same_frame(con.exact_frame, want)
            fr = con.frame.normalized()
            wn = want.normalized()
            assert abs(fr.tx - float(wn.tx)) <= 1e-15 * max(1, abs(float(wn.tx)))
    assert n == 120


@pytest.mark.parametrize("coeffs,words", [
    ((1e300, 0, 1, 0, 0, -1), "ellipse size 1e-150"),         # semi-axis 1e-150: squares underflow
    ((1, 0, 1, -2 * 10 ** 31, 0, 10 ** 62 - 1), "centre x = 1e+31"),  # unit circle at x = 1e31
    ((0, 0, 1, F(-1, 10 ** 40), 0, 0), "parabola size"),      # y² = 2p x with p = 5e-41
])
def test_scales_outside_the_float_range_are_refused_by_the_python_api(coeffs, words):
    """The same refusal as for file input: one InvalidConicError naming the size, not a silent
    float overflow later in the numeric routes."""
    with pytest.raises(InvalidConicError, match="outside the supported range") as err:
        Conic.from_coefficients(*coeffs)
    assert words in str(err.value)
