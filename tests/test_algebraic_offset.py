"""Generalised offsets of plane algebraic curves and the degree formula of thesis §4.2.

Facts checked: thesis Table 4.1 (degrees of the conic offsets) and Props 4.3.1-4.3.3 (the terms of
Theorem 4.2.18 for circles, ellipses, parabolas); Remark 4.2.17 (multiplicity 6 of x²y − y³ at the
origin); the offsets of the conic families equal the generated artefacts (App. B) up to a constant;
the offsets vanish exactly at random exact offset points (rational parametrisations, and points over
number fields for curves without one); the extraneous circle of a node is rejected (§4.1); the degree
formula against elimination, with the cardioid as the documented disagreement.
"""
from __future__ import annotations

import io
import json
import random
from contextlib import redirect_stdout
from fractions import Fraction
from functools import lru_cache
from pathlib import Path

import flint
import pytest
from hypothesis import given, settings, strategies as st

from curvedvoronoi.runtime.algebra.algebraic_offset import (
    curve_points, evaluate_at_point, offset, offset_point, parse_curve, select_factors)
from curvedvoronoi.runtime.algebra.offset_degrees import offset_degrees_on_line
from curvedvoronoi.runtime.artefacts import load_offset
from curvedvoronoi.runtime.cli import main as cli_main
from curvedvoronoi.runtime.algebra.degree_formula import degree_formula

GOLDEN = Path(__file__).parent / "golden"
STROPHOID = "y^2 - x^2 - x^3"


@lru_cache(maxsize=None)
def cached_offset(f: str):
    return offset(f)


def exact_value(poly, u, v, R) -> Fraction:
    return sum((Fraction(int(c)) * u ** int(i) * v ** int(j) * R ** int(k)
                for (i, j, k), c in poly.to_dict().items()), Fraction(0))


def gradient_offset_point(f, fx, fy, x0, y0, k):
    """(u, v, R) = p + k·∇f(p), k²|∇f(p)|² for a rational point p of V(f)."""
    assert f(x0, y0) == 0
    gx, gy = fx(x0, y0), fy(x0, y0)
    return x0 + k * gx, y0 + k * gy, k * k * (gx * gx + gy * gy)


rationals = st.fractions(min_value=-20, max_value=20, max_denominator=30)
nonzero_rationals = rationals.filter(lambda q: q != 0)


# --------------------------------------------------------------------------------------------
# the strophoid (thesis Figs 4.1.1-4.1.3)
# --------------------------------------------------------------------------------------------

def test_strophoid_offset_equals_golden():
    gold = json.loads((GOLDEN / "strophoid_offset.json").read_text())
    o = cached_offset(STROPHOID)
    got = sorted(([int(e) for e in k], str(int(c))) for k, c in o.polynomial.to_dict().items())
    assert got == sorted((k, c) for k, c in gold["polynomial"])
    assert (o.degree_uv, o.degrees, o.terms) == (gold["degree_uv"], gold["degrees"], gold["terms"]) \
        == (10, {"u": 10, "v": 8, "R": 5}, 75)
    _, facs = o.polynomial.factor()
    assert len(facs) == 1 and int(facs[0][1]) == 1          # irreducible: the offset surface itself


def test_strophoid_node_circle_is_rejected():
    """§4.1: the node (0, 0) gives the extraneous circle u² + v² = R; it is in the resultant and rejected."""
    o = cached_offset(STROPHOID)
    circles = [r for r in o.rejected if "singular point (0, 0)" in r.reason]
    assert len(circles) == 1
    c = circles[0].polynomial
    assert c == c.context().from_dict({(2, 0, 0): 1, (0, 2, 0): 1, (0, 0, 1): -1}) or \
        c == -c.context().from_dict({(2, 0, 0): 1, (0, 2, 0): 1, (0, 0, 1): -1})
    # the circle's generic points are not on the generalised offset: (3/5·s, 4/5·s), R = s²
    for s in (Fraction(1, 3), Fraction(2), Fraction(7, 5)):
        assert exact_value(o.polynomial, Fraction(3, 5) * s, Fraction(4, 5) * s, s * s) != 0


@settings(max_examples=40, deadline=None)
@given(t=rationals, k=nonzero_rationals)
def test_strophoid_offset_vanishes_on_parametrised_points(t, k):
    """x = t² − 1, y = t(t² − 1) parametrises the strophoid; p + k∇f(p) is on its offset (exact)."""
    f = lambda x, y: y * y - x * x - x ** 3          # noqa: E731
    fx = lambda x, y: -2 * x - 3 * x * x              # noqa: E731
    fy = lambda x, y: 2 * y                           # noqa: E731
    x0, y0 = t * t - 1, t * (t * t - 1)
    if fx(x0, y0) == 0 and fy(x0, y0) == 0:
        return                                        # the node: not a point of Definition 4.1.3
    u, v, R = gradient_offset_point(f, fx, fy, x0, y0, k)
    assert exact_value(cached_offset(STROPHOID).polynomial, u, v, R) == 0


def test_select_factors_rule_and_single_implementation():
    """Kept iff zero on a whole group; coverage fails when a point is on no kept factor."""
    import curvedvoronoi.precompute.offsets as pre

    assert pre.select_factors is select_factors
    zeros = {"A": {1, 2, 3}, "B": {1}, "C": {4}}
    sel = select_factors(["A", "B", "C"], [[1, 2], [3]], lambda f, p: p in zeros[f])
    assert sel.kept == (0,) and sel.covered
    sel = select_factors(["B", "C"], [[1, 2], [3]], lambda f, p: p in zeros[f])
    assert sel.kept == () and not sel.covered
    sel = select_factors(["B", "C"], [[1], [4], [2]], lambda f, p: p in zeros[f])
    assert sel.kept == (0, 1) and not sel.covered


def test_corrupted_offset_is_detected():
    """The vanishing test is not vacuous: one changed coefficient makes it fail."""
    o = cached_offset(STROPHOID)
    d = o.polynomial.to_dict()
    key = next(iter(d))
    bad = o.polynomial.context().from_dict({**d, key: int(d[key]) + 1})
    f = lambda x, y: y * y - x * x - x ** 3          # noqa: E731
    pt = gradient_offset_point(f, lambda x, y: -2 * x - 3 * x * x, lambda x, y: 2 * y,
                               Fraction(3), Fraction(6), Fraction(1, 7))   # t = 2
    assert exact_value(o.polynomial, *pt) == 0
    assert exact_value(bad, *pt) != 0


# --------------------------------------------------------------------------------------------
# curves without rational parametrisation: exact points over number fields
# --------------------------------------------------------------------------------------------

NUMBER_FIELD_CURVES = ["y^2 - x^3 - x - 1",                      # smooth cubic (genus 1)
                       "x^3 + y^3 - 3*x*y",                      # folium (nodal)
                       "y^2 - x^3",                              # cuspidal
                       "(x^2 + y^2 - 2*x)^2 - 4*(x^2 + y^2)"]     # cardioid


@pytest.mark.parametrize("curve", NUMBER_FIELD_CURVES)
@settings(max_examples=8, deadline=None)
@given(seed=st.integers(0, 10**6), k=nonzero_rationals)
def test_offset_vanishes_at_number_field_points(curve, seed, k):
    o = cached_offset(curve)
    f = parse_curve(curve)
    (pt,) = curve_points(f, 1, random.Random(seed))
    q = offset_point(f, pt, k)
    assert evaluate_at_point(o.polynomial, q).is_zero()
    # and not every polynomial vanishes there: the offset with u shifted by 1 does not
    shifted = o.polynomial.compose(*(g + (1 if i == 0 else 0) for i, g in enumerate(o.polynomial.context().gens())))
    assert not evaluate_at_point(shifted, q).is_zero()


def test_number_field_point_is_on_the_curve_and_exact():
    f = parse_curve("y^2 - x^3 - x - 1")
    x0, X, Y, gx, gy, mod, swapped = curve_points(f, 1, random.Random(3))[0]
    assert not swapped and mod.degree() >= 1
    val = sum((int(c) * X ** int(i) * Y ** int(j) for (i, j), c in f.to_dict().items()), flint.fmpq_poly(0)) % mod
    assert val.is_zero()


def test_offset_of_curves_without_rational_points_uses_number_fields():
    """x³ + 2y³ = 5 (smooth, the samples lie in cubic fields) and x² + y² + 1 (no real point: the
    samples are complex, in imaginary quadratic fields) still get their exact offsets."""
    o = offset("x^3 + 2*y^3 - 5")
    assert o.degree_uv == degree_formula("x^3 + 2*y^3 - 5").degree == 18
    assert all("a^3" in s for s in o.samples)
    imaginary = offset("x^2 + y^2 + 1")
    assert imaginary.degree_uv == 4 and all("a^2" in s for s in imaginary.samples)
    # o(0, 0, R) = (R + 1)²: the centre is at squared distance −1 from the (complex) circle
    assert exact_value(imaginary.polynomial, Fraction(0), Fraction(0), Fraction(-1)) == 0   # centre, r² = −1


# --------------------------------------------------------------------------------------------
# conics: Table 4.1 and the generated artefacts (App. B)
# --------------------------------------------------------------------------------------------

CONICS = {   # family: (parameters, polynomial string)
    "circle": ({"rho": Fraction(3, 2)}, "x^2 + y^2 - 9/4"),
    "ellipse": ({"c": Fraction(4, 9), "e": Fraction(-3)}, "x^2 + 4/9*y^2 - 3"),
    "parabola": ({"p": Fraction(3, 4)}, "y^2 - 3/2*x"),
    "lines_parallel": ({"h": Fraction(2)}, "y^2 - 4"),
    "lines_intersecting": ({"t": Fraction(3, 2)}, "y^2 - 9/4*x^2"),
    "generic": ({"a": 2, "b": -1, "c": 3, "d": 1, "e": -2, "f": -5}, "2*x^2 - x*y + 3*y^2 + x - 2*y - 5"),
}


def test_table_4_1_degrees():
    table = json.loads((GOLDEN / "table_4_1.json").read_text())["families"]
    for fam, (_, f) in CONICS.items():
        assert cached_offset(f).degree_uv == table[fam], fam
        assert degree_formula(f).degree == table[fam], fam
    assert offset("x^2 - 2*y^2 - 1").degree_uv == table["ellipse"]      # a hyperbola


@pytest.mark.parametrize("family", sorted(CONICS))
def test_conic_offsets_equal_artefacts_up_to_a_constant(family):
    params, f = CONICS[family]
    art = load_offset(family).specialise(**{k: Fraction(v) for k, v in params.items()})
    mine = {tuple(int(e) for e in k): Fraction(int(c)) for k, c in cached_offset(f).polynomial.to_dict().items()}
    assert set(art) == set(mine)
    key = next(iter(mine))
    ratio = Fraction(art[key]) / mine[key]
    assert all(Fraction(art[k]) == ratio * mine[k] for k in mine)


def test_conic_offset_vanishes_at_rational_points():
    """Ellipse x² + 4y² = 4 via its rational parametrisation ((1−t²)/(1+t²)·2, 2t/(1+t²))."""
    o = cached_offset("x^2 + 4*y^2 - 4").polynomial
    for t, k in ((Fraction(1, 2), Fraction(3)), (Fraction(-7, 3), Fraction(-1, 5))):
        x0, y0 = 2 * (1 - t * t) / (1 + t * t), 2 * t / (1 + t * t)
        pt = gradient_offset_point(lambda x, y: x * x + 4 * y * y - 4, lambda x, y: 2 * x, lambda x, y: 8 * y, x0, y0, k)
        assert exact_value(o, *pt) == 0


# --------------------------------------------------------------------------------------------
# Theorem 4.2.18 term by term
# --------------------------------------------------------------------------------------------

def test_thesis_terms_for_conics():
    circle, ellipse, parabola = (degree_formula(f) for f in ("x^2 + y^2 - 1", "x^2 + 4*y^2 - 4", "y^2 - 2*x"))
    # Prop 4.3.1: l = 1, the two cyclic points, μ = 1 each: 8 − 4 = 4
    assert (circle.l, circle.sum_infinity, circle.infinity_correction, circle.degree) == (1, 2, 4, 4)
    # Prop 4.3.2: l = 0, no singular point: 8
    assert (ellipse.l, ellipse.sum_singular, ellipse.degree) == (0, 0, 8)
    # Prop 4.3.3: l = 1, the point (0:1:0), μ = 1: 8 − 2 = 6
    assert (parabola.l, parabola.sum_infinity, parabola.degree) == (1, 1, 6)
    assert parabola.infinity == [{"factor": "y", "points": 1, "multiplicity_in_fT": 2, "mu": 1}]


def test_singular_multiplicities():
    # Remark 4.2.17: x²y − y³ at the origin, multiplicity 6 in the affine plane
    three = degree_formula("x^2*y - y^3")
    assert three.singular == [{"points": 1, "mu": 6, "where": "(0, 0)"}]
    # after Theorem 4.2.18: at least m_q(m_q − 1); a node 2, a cusp 3 (= Milnor number + m_q − 1)
    assert degree_formula(STROPHOID).singular[0]["mu"] == 2
    assert degree_formula("y^2 - x^3").singular[0]["mu"] == 3


def test_degree_table_golden():
    rows = json.loads((GOLDEN / "offset_degree_table.json").read_text())["rows"]
    for row in rows:
        df = degree_formula(row["curve"])
        got = {"m": df.m, "l": df.l, "sum_infinity": df.sum_infinity, "sum_singular": df.sum_singular,
               "formula": df.degree}
        assert got == {k: row[k] for k in got}, row["name"]
        assert df.draws_agree, row["name"]
        line = offset_degrees_on_line(row["curve"])
        assert (line["degree_uv"], line["degree_R"]) == (row["elimination"], row["degree_R"]), row["name"]
        # two independent computations: feet of the normals from a generic point = degree of o in R
        assert df.normal_feet == row["degree_R"], row["name"]
    disagree = [r["name"] for r in rows if r["formula"] != r["elimination"]]
    assert disagree == ["cardioid"]


@pytest.mark.parametrize("curve", ["y^2 - x^3 - x - 1", "x^3 + y^3 - 3*x*y", "y^2 - x^3", "x^2*y - y^3",
                                   "(x^2 + y^2 - 2*x)^2 - 4*(x^2 + y^2)"])
def test_full_offset_degrees_match_line_restriction(curve):
    o = cached_offset(curve)
    line = offset_degrees_on_line(curve)
    assert (o.degree_uv, o.degrees["R"]) == (line["degree_uv"], line["degree_R"])


def test_cardioid_disagreement():
    """The cardioid: 3 normals from a generic point (degree 3 in R), offset of degree 8 (classical),
    Theorem 4.2.18 read with generic multiplicities gives 2·3 = 6."""
    f = "(x^2 + y^2 - 2*x)^2 - 4*(x^2 + y^2)"
    o, df = cached_offset(f), degree_formula(f)
    assert (o.degree_uv, o.degrees["R"]) == (8, 3)
    assert (df.degree, df.normal_feet) == (6, 3)
    # the 2 extra degrees: lc_R(o) = −((u − 1)² + v²), the isotropic (cuspidal) tangents at the
    # circular points meet at (1, 0); from q on them one normal has its foot at infinity
    assert leading_coefficient_in_R(o) == {(2, 0): -1, (1, 0): 2, (0, 2): -1, (0, 0): -1}


def leading_coefficient_in_R(o) -> dict:
    N = o.degrees["R"]
    return {(int(i), int(j)): int(c) for (i, j, k), c in o.polynomial.to_dict().items() if int(k) == N}


@pytest.mark.parametrize("curve", ["x^2 + y^2 - 1", "x*y - 1", "y^2 - 2*x", STROPHOID, "y^2 - x^3 - x - 1",
                                   "x^3 + y^3 - 3*x*y", "y^2 - x^3", "x^2*y - y^3",
                                   "(x^2 + y^2 - 2*x)^2 - 4*(x^2 + y^2)"])
def test_degree_is_twice_the_normals_plus_the_leading_coefficient(curve):
    """deg_(u,v) o = 2·deg_R o + deg lc_R(o): the formula's 2·(normals) is right iff lc_R is constant."""
    o = cached_offset(curve)
    lc = leading_coefficient_in_R(o)
    assert o.degree_uv == 2 * o.degrees["R"] + max(i + j for i, j in lc)
    assert (degree_formula(curve).degree == o.degree_uv) == (max(i + j for i, j in lc) == 0)


@pytest.mark.parametrize("degree,seed", [(2, 11), (2, 12), (3, 13), (3, 14)])
def test_random_curves_formula_matches_elimination(degree, seed):
    rng = random.Random(seed)
    f = " + ".join(f"({rng.randint(-5, 5)})*x^{i}*y^{j}" for i in range(degree + 1) for j in range(degree + 1 - i))
    df = degree_formula(f)
    line = offset_degrees_on_line(f)
    assert df.degree == line["degree_uv"]
    assert df.normal_feet == line["degree_R"]


# --------------------------------------------------------------------------------------------
# input and command line
# --------------------------------------------------------------------------------------------

@pytest.mark.parametrize("bad,msg", [("(x - y)^2 + 0", "not square-free"), ("3", "constant"),
                                     ("x^2 + z", "other than x, y"), ("x^2 +* y", "cannot parse"),
                                     ("sin(x) + y", "polynomial"), ("x^2 + y^2", "isotropic")])
def test_bad_curves(bad, msg):
    with pytest.raises(ValueError, match=msg):
        offset(bad)


def test_inputs_sympy_and_flint():
    import sympy

    x, y = sympy.symbols("x y")
    a = offset(y**2 - x**2 - x**3).polynomial
    ctx = flint.fmpq_mpoly_ctx.get(("x", "y"), "lex")
    X, Y = ctx.gens()
    b = offset(Y**2 - X**2 - X**3).polynomial
    assert a == b == cached_offset(STROPHOID).polynomial
    assert offset("y^2 = x^2 + x^3").polynomial == a


def test_cli_offsets_curve():
    buf = io.StringIO()
    with redirect_stdout(buf):
        assert cli_main(["offsets", "--curve", STROPHOID]) == 0
    out = buf.getvalue()
    assert "degree in (u, v): 10" in out and "75 terms" in out
    assert "2*3^2 - 4 - 4 = 10 (elimination: 10)" in out
    assert "singular point (0, 0)" in out
    buf = io.StringIO()
    with redirect_stdout(buf):
        assert cli_main(["offsets", "--curve", STROPHOID, "--json"]) == 0
    doc = json.loads(buf.getvalue())
    assert doc["offset"]["degree_uv"] == doc["degree_formula"]["degree"] == 10
    assert cli_main(["offsets", "--curve", "x^2 + z"]) == 2


def test_doctests():
    import doctest

    import curvedvoronoi.runtime.algebra.algebraic_offset as a
    import curvedvoronoi.runtime.algebra.degree_formula as d

    for mod in (a, d):
        assert doctest.testmod(mod).failed == 0
