"""Implicit equations of generalised offsets to conics (thesis ch. 4, §4.4, App. B).

Definition (thesis §4.1, after Arrondo–Sendra–Sendra): the generalised offset of the curve
C = V(f) at squared distance R is the Zariski closure of the projection to the (u, v) plane of

    f(x, y) = 0,
    n(x, y, u, v) = −f_y·(u − x) + f_x·(v − y) = 0          (q = (u, v) on the normal at p),
    d(x, y, u, v) = (u − x)² + (v − y)² − R = 0              (|q − p|² = R),

minus the singular points of C.  We work with R = r² (the squared distance) throughout, as the
thesis does after its substitution "r² → r" (§5.3).

Elimination and the choice of the offset factor
-----------------------------------------------
We eliminate (x, y) by iterated resultants, ``Res_y(Res_x(f, n), Res_x(f, d))`` with
python-flint's multivariate resultants, and factor the result over ℤ.  Iterated resultants are
only a *multiple* of the offset: they contain extraneous factors (for x² + c·y² + e a 117-term
degree-8 factor beside the 104-term offset; parameter-only contents; for line pairs, powers of the
offset of the singular point).  A factor is kept iff it vanishes exactly at points built on the
true offset: for rational parameters, a rational point p of the curve (rational
parametrisation, :mod:`precompute.conics`), n = ∇f(p) and a rational k, the point
q = p + k·n and R = k²·|n|² (q is at distance √R of C along the normal, so (q, R) lies on the
generalised offset).  Spurious factors do not vanish at such generic points.  The product of the
kept factors (each once) is the offset; its degree in (u, v) must equal Table 4.1 (circle 4,
ellipse/hyperbola 8, parabola 6, two lines 4) — we raise if it does not.  For a pair of lines the
offset is reducible (one factor per line) and several factors are kept; each sample point lies
on one line only, so a factor is kept when it vanishes at *some* samples, and the product must
vanish at *all* of them.  The selection rule itself is the library's single one,
:func:`runtime.algebra.algebraic_offset.select_factors` (also used for arbitrary curves).
"""
from __future__ import annotations

import random
import time
from dataclasses import dataclass, field
from fractions import Fraction

import flint

from ..runtime.algebra.algebraic_offset import select_factors
from .conics import FAMILIES, ConicFamily

#: variables of every serialised offset polynomial, before the family parameters
OFFSET_VARS = ("u", "v", "R")


@dataclass
class OffsetDerivation:
    """The offset polynomial of a family plus what the elimination produced."""

    family: str
    poly: flint.fmpz_mpoly                       # in variables OFFSET_VARS + family params
    variables: tuple[str, ...]
    kept_factors: list[dict] = field(default_factory=list)
    spurious_factors: list[dict] = field(default_factory=list)
    seconds: dict[str, float] = field(default_factory=dict)

    @property
    def terms(self) -> list[tuple[tuple[int, ...], int]]:
        """Sorted term list (exponent vector, integer coefficient), lexicographically descending."""
        return sorted(((tuple(int(e) for e in k), int(c)) for k, c in self.poly.to_dict().items()), reverse=True)

    def degree_uv(self) -> int:
        return max(k[0] + k[1] for k, _ in self.terms)


def evaluate_terms(terms, values) -> Fraction:
    """Exact value of a term list at rational ``values`` (same order as the variables)."""
    total = Fraction(0)
    for exps, coef in terms:
        t = Fraction(coef)
        for val, e in zip(values, exps):
            if e:
                t *= val ** e
        total += t
    return total


def offset_point(family: ConicFamily, params, point, k) -> tuple[Fraction, Fraction, Fraction]:
    """(u, v, R) on the generalised offset: q = p + k·∇f(p), R = k²·|∇f(p)|² (exact)."""
    x0, y0 = point
    gx, gy = family.gradient(params, x0, y0)
    return x0 + k * gx, y0 + k * gy, k * k * (gx * gx + gy * gy)


def _elimination_order(family: ConicFamily) -> tuple[str, str]:
    # eliminate first a variable f really depends on (y² − h² has no x)
    return ("y", "x") if family.name == "lines_parallel" else ("x", "y")


def _samples(family: ConicFamily, count: int, seed: int):
    rng = random.Random(seed)
    out = []
    while len(out) < count:
        params, point = family.sample(rng)
        k = Fraction(rng.randint(-10**6, 10**6), rng.randint(1, 10**6))   # generic: avoid coincidences
        if k == 0:
            continue
        gx, gy = family.gradient(params, *point)
        if (gx == 0 and gy == 0) or 0 in point:   # singular / axis points are not generic: skip
            continue
        out.append((params, offset_point(family, params, point, k)))
    return out


def derive_offset(name: str, *, samples: int = 12, seed: int = 20030101) -> OffsetDerivation:
    """Derive the generalised offset of the family ``name`` (see the module docstring)."""
    family = FAMILIES[name]
    names = ("x", "y") + OFFSET_VARS + family.params
    ctx = flint.fmpz_mpoly_ctx.get(names, "lex")
    g = dict(zip(names, ctx.gens()))
    x, y, u, v, R = (g[s] for s in ("x", "y", "u", "v", "R"))
    f = family.polynomial(ctx)
    fx, fy = f.derivative("x"), f.derivative("y")
    n = -fy * (u - x) + fx * (v - y)
    d = (u - x) ** 2 + (v - y) ** 2 - R

    t0 = time.perf_counter()
    first, second = _elimination_order(family)
    res = f.resultant(n, first).resultant(f.resultant(d, first), second)
    t1 = time.perf_counter()
    _, factors = res.factor()
    t2 = time.perf_counter()

    out_names = OFFSET_VARS + family.params
    out_ctx = flint.fmpz_mpoly_ctx.get(out_names, "lex")
    pts = _samples(family, samples, seed)
    sample_values = [tuple([u_, v_, R_] + [p[s] for s in family.params]) for p, (u_, v_, R_) in pts]

    kept, kept_info, spurious_info = [], [], []
    candidates, infos = [], []
    for fac, mult in factors:
        fac_out = fac.project_to_context(out_ctx)
        degs = dict(zip(out_names, fac_out.degrees()))
        info = {"terms": len(fac_out), "multiplicity": int(mult),
                "degree_uv": int(max((e[0] + e[1] for e in fac_out.to_dict()), default=0))}
        if degs["u"] == 0 and degs["v"] == 0:
            info["kind"] = "parameter content"
            infos.append((info, None))
            continue
        terms = [(tuple(int(e) for e in k), int(c)) for k, c in fac_out.to_dict().items()]
        infos.append((info, len(candidates)))
        candidates.append((fac_out, terms))
    # an irreducible offset must vanish at every sample (one group); a line pair's offset has one
    # factor per line and each sample point lies on one line only (one group per sample)
    groups = [[vals] for vals in sample_values] if family.reducible_offset else [sample_values]
    sel = select_factors([terms for _, terms in candidates], groups,
                         lambda terms, vals: evaluate_terms(terms, vals) == 0)
    for info, ci in infos:
        if ci is None:
            spurious_info.append(info)
        elif ci in sel.kept:
            kept.append(candidates[ci][0])
            kept_info.append(info | {"vanishing_samples": sum(map(sum, sel.hits[ci]))})
        else:
            info["kind"] = "extraneous"
            spurious_info.append(info)
    if not kept or not sel.covered:
        raise RuntimeError(f"offset of {name}: no product of factors vanishes on all offset samples")
    poly = kept[0]
    for k_ in kept[1:]:
        poly = poly * k_
    # normalise: primitive, positive leading coefficient (lex order of (u, v, R, params))
    poly = poly.primitive()[1] if hasattr(poly, "primitive") else poly
    lead = sorted(poly.to_dict().items(), reverse=True)[0][1]
    if lead < 0:
        poly = -poly
    der = OffsetDerivation(name, poly, out_names, kept_info, spurious_info,
                           {"resultant": t1 - t0, "factor": t2 - t1, "total": time.perf_counter() - t0})
    if der.degree_uv() != family.offset_degree:
        raise RuntimeError(f"offset of {name}: degree {der.degree_uv()} in (u, v), Table 4.1 says "
                           f"{family.offset_degree}")
    return der


def canonical_offset(name: str):
    """(ctx, poly) of the offset of a family, python-flint fmpz_mpoly in OFFSET_VARS + params."""
    der = derive_offset(name)
    return der.poly.context(), der.poly
