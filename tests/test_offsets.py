"""Generalised offsets of conics (thesis ch. 4, App. B): golden files, Table 4.1, exact property test."""
from __future__ import annotations

import json
import random
from fractions import Fraction
from pathlib import Path

import pytest
import sympy as sp
from hypothesis import given, settings, strategies as st

from curvedvoronoi.precompute.conics import FAMILIES
from curvedvoronoi.precompute.offsets import derive_offset, evaluate_terms, offset_point
from curvedvoronoi.runtime.artefacts import load_offset

GOLDEN = Path(__file__).parent / "golden"


def _golden_poly(name: str, gens: str) -> sp.Poly:
    text = "\n".join(line for line in (GOLDEN / name).read_text().splitlines() if not line.startswith("#"))
    return sp.Poly(sp.sympify(text.replace("^", "**")), *sp.symbols(gens))


def _artefact_poly(family: str, rename: dict[str, str]) -> sp.Poly:
    off = load_offset(family)
    syms = [sp.Symbol(rename.get(v, v)) for v in off.variables]
    expr = sum(sp.Rational(c.numerator, c.denominator) * sp.Mul(*(s**e for s, e in zip(syms, exps)))
               for exps, c in off.terms)
    return expr


def test_appendix_b4_exactly():
    """Our ellipse/hyperbola offset equals App. B.4 (corrected variant) exactly, R = r²."""
    r, R = sp.symbols("r R")
    golden = _golden_poly("appendix_b4.txt", "u v r c e")
    ours = _artefact_poly("ellipse", {}).subs(R, r**2)
    assert sp.expand(golden.as_expr() - ours) == 0
    assert len(load_offset("ellipse").terms) == 104


def test_appendix_b4_misprint_is_wrong():
    """The other printed variant, −(2c⁴−3c³+2c²)·r² for the u²v² term, is not the offset."""
    u, v, r, c, e, R = sp.symbols("u v r c e R")
    golden = _golden_poly("appendix_b4.txt", "u v r c e").as_expr()
    wrong = golden + 2 * u**2 * v**2 * ((2*c**4 - 3*c**3 - 3*c**2 + 2*c) * e * r**2 - (2*c**4 - 3*c**3 + 2*c**2) * r**2)
    ours = _artefact_poly("ellipse", {}).subs(R, r**2)
    assert sp.expand(wrong - ours) != 0


def test_appendix_b3_exactly():
    """Our parabola offset equals App. B.3 exactly (point called (x, y) there), R = r²."""
    r, R = sp.symbols("r R")
    golden = _golden_poly("appendix_b3.txt", "x y r p")
    ours = _artefact_poly("parabola", {"u": "x", "v": "y"}).subs(R, r**2)
    assert sp.expand(golden.as_expr() - ours) == 0
    assert len(load_offset("parabola").terms) == 23


def test_table_4_1_degrees():
    table = json.loads((GOLDEN / "table_4_1.json").read_text())["families"]
    for family, degree in table.items():
        off = load_offset(family)
        assert off.degree_uv == degree
        assert max(e[0] + e[1] for e, _ in off.terms) == degree


def test_generic_conic_specialises_to_b4():
    """Generic offset at (a, b, c, d, e, f) = (1, 0, c, 0, 0, e) is a constant times App. B.4."""
    gen = load_offset("generic")
    ell = load_offset("ellipse")
    c_, e_ = sp.symbols("c e")
    spec: dict[tuple, object] = {}
    for exps, coef in gen.terms:
        u, v, R, a, b, c, d, e, f = exps
        if b or d or e:
            continue
        key = (u, v, R, c, f)
        spec[key] = spec.get(key, 0) + coef
    spec = {k: val for k, val in spec.items() if val != 0}
    target = {exps: coef for exps, coef in ell.terms}
    assert set(spec) == set(target)
    ratios = {spec[k] / target[k] for k in target}
    assert len(ratios) == 1 and next(iter(ratios)) != 0


def test_circle_and_lines_closed_forms():
    """Circle: (u²+v²+ρ²−R)² − 4ρ²(u²+v²); lines y=±h: ((v−h)²−R)((v+h)²−R)."""
    u, v, R, rho, h, t = sp.symbols("u v R rho h t")
    circle = _artefact_poly("circle", {})
    assert sp.expand(circle - ((u**2 + v**2 + rho**2 - R)**2 - 4 * rho**2 * (u**2 + v**2))) == 0
    lines = _artefact_poly("lines_parallel", {})
    assert sp.expand(lines - ((v - h)**2 - R) * ((v + h)**2 - R)) == 0
    inter = _artefact_poly("lines_intersecting", {})
    expected = ((v - t * u)**2 - R * (1 + t**2)) * ((v + t * u)**2 - R * (1 + t**2))
    assert sp.expand(inter - expected) == 0


@pytest.mark.parametrize("family", sorted(FAMILIES))
@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), k=st.fractions(min_value=-50, max_value=50, max_denominator=1000))
def test_offset_vanishes_on_exact_offset_points(family, seed, k):
    """q = p + k·∇f(p), R = k²|∇f(p)|² is on the offset, exactly, for random rational conics."""
    fam = FAMILIES[family]
    off = load_offset(family)
    params, point = fam.sample(random.Random(seed))
    gx, gy = fam.gradient(params, *point)
    if gx == 0 and gy == 0:
        return  # singular point of a line pair: not on the generalised offset by definition
    u, v, R = offset_point(fam, params, point, Fraction(k))
    assert off.evaluate(u, v, R, **params) == 0
    # and the offset is not identically zero on nearby non-offset points
    assert off.evaluate(u, v, R + 1, **params) != 0 or off.evaluate(u + 1, v, R, **params) != 0


@pytest.mark.parametrize("family", ["ellipse", "circle", "lines_intersecting"])
def test_extraneous_factors_fail_the_exact_check(family):
    """The factors the elimination adds (e.g. the 117-term one for the ellipse) are rejected:
    they do not vanish at exact offset points, while the selected offset does."""
    import flint

    fam = FAMILIES[family]
    names = ("x", "y", "u", "v", "R") + fam.params
    ctx = flint.fmpz_mpoly_ctx.get(names, "lex")
    g = dict(zip(names, ctx.gens()))
    x, y, u, v, R = (g[s] for s in ("x", "y", "u", "v", "R"))
    f = fam.polynomial(ctx)
    n = -f.derivative("y") * (u - x) + f.derivative("x") * (v - y)
    d = (u - x) ** 2 + (v - y) ** 2 - R
    res = f.resultant(n, "x").resultant(f.resultant(d, "x"), "y")
    rng = random.Random(7)
    pts = []
    while len(pts) < 6:
        params, p = fam.sample(rng)
        if 0 in p:
            continue
        pts.append((params, offset_point(fam, params, p, Fraction(rng.randint(1, 10**6), 997))))
    offset_terms = [(e, c) for e, c in load_offset(family).terms]
    spurious = 0
    for fac, _ in res.factor()[1]:
        terms = [(tuple(int(a) for a in k[2:]), int(c)) for k, c in fac.to_dict().items()]
        if all(e[0] == 0 and e[1] == 0 for e, _ in terms):
            continue
        vals = [evaluate_terms(terms, (uu, vv, RR) + tuple(prm[s] for s in fam.params))
                for prm, (uu, vv, RR) in pts]
        divides_offset = all(
            evaluate_terms(offset_terms, (uu, vv, RR) + tuple(prm[s] for s in fam.params)) == 0
            for prm, (uu, vv, RR) in pts)
        assert divides_offset
        if all(val != 0 for val in vals):
            spurious += 1
    assert spurious >= 1  # there are extraneous factors, and they fail the check


def test_derivation_reports_the_known_factors():
    der = derive_offset("ellipse")
    assert [f["terms"] for f in der.kept_factors] == [104]
    assert 117 in [f["terms"] for f in der.spurious_factors]
