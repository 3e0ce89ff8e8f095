"""Generalised offsets of plane algebraic curves (thesis ch. 4, §4.1).

Definition (thesis Definition 4.1.3, after Arrondo–Sendra–Sendra): the generalised offset of
C = V(f) at squared distance R is the Zariski closure of the set of points q = (u, v) with

    f(x, y) = 0,
    n(x, y, u, v) = −f_y·(u − x) + f_x·(v − y) = 0          (q on the normal at p = (x, y)),
    d(x, y, u, v, R) = (u − x)² + (v − y)² − R = 0           (|q − p|² = R),
    (f_x, f_y)(p) ≠ (0, 0)                                   (p not singular).

``R`` is the *squared* distance, as for the conic offsets (thesis §5.3, "r² → r").

Elimination and the choice of the offset factors
------------------------------------------------
(x, y) are eliminated by iterated resultants, ``Res_x(Res_y(f, n), Res_y(f, d))`` (python-flint,
exact over ℤ), and the result is factored over ℚ.  Iterated resultants give a *multiple* of the
offset: besides the offset they contain

* the circles ``(u − a)² + (v − b)² − R`` centred at the singular points (a, b) of C, where the
  normal equation n vanishes identically (thesis §4.1: the strophoid's node gives a circle of
  extraneous points, Fig. 4.1.2);
* factors made of pairs of distinct points of C that share an x-coordinate (an artefact of
  eliminating y first), and powers of the offset itself.

A factor is kept iff it vanishes *exactly* at points built on the true offset.  For a curve with
no rational parametrisation the points are taken over a number field: a rational x₀, an
irreducible factor p(y) of f(x₀, y) over ℚ, α a root of p, the curve point P = (x₀, α) ∈ ℚ(α)²,
the gradient g = ∇f(P) ≠ 0 and a rational k: then q = P + k·g, R = k²·|g|² is a point of the
generalised offset with coordinates in ℚ(α), and a factor F vanishes there iff F(q, R) ≡ 0 mod
p — an exact test in ℚ[α]/(p).  Every irreducible component over ℚ of C gets its own samples;
an irreducible factor of the resultant that is not a component of the offset meets the offset
surface in a curve only, so it does not vanish at such points (the test is exact; only the
choice of the points is a generic one, and two points per component are used).

Examples
--------
>>> o = offset("y^2 - x^2 - x^3")          # the strophoid (thesis Fig. 4.1.1-4.1.3)
>>> o.degree_uv, o.degrees
(10, {'u': 10, 'v': 8, 'R': 5})
>>> [r.reason.split(":")[0] for r in o.rejected]
['extraneous factor of the iterated resultant', 'extraneous circle of the singular point (0, 0)']
"""
from __future__ import annotations

import math
import random
import time
from dataclasses import dataclass, field
from fractions import Fraction

import flint

from .curve_points import (OffsetPoint, curve_at_abscissa, curve_points, evaluate_at_point,
                           leading_coefficient, offset_point, parse_curve)

__all__ = ["AlgebraicOffset", "FactorSelection", "RejectedFactor", "OffsetPoint", "OFFSET_VARIABLES",
           "curve_points", "evaluate_at_point", "factor_over_z", "first_resultants", "offset",
           "offset_point", "parse_curve", "select_factors"]

#: variables of every offset polynomial returned here
OFFSET_VARIABLES = ("u", "v", "R")

_ELIM_CTX = flint.fmpz_mpoly_ctx.get(("x", "y", "u", "v", "R"), "lex")
_OUT_CTX = flint.fmpz_mpoly_ctx.get(OFFSET_VARIABLES, "lex")


# ------------------------------------------------------------------------------------------
# the offset
# ------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class RejectedFactor:
    """An irreducible factor of the iterated resultant that is not part of the offset."""

    polynomial: flint.fmpz_mpoly
    multiplicity: int
    reason: str

    @property
    def terms(self) -> int:
        return len(self.polynomial)

    @property
    def degrees(self) -> dict[str, int]:
        return dict(zip(OFFSET_VARIABLES, (int(d) for d in self.polynomial.degrees())))


@dataclass
class AlgebraicOffset:
    """The implicit equation o(u, v, R) = 0 of the generalised offset of V(f) (thesis §4.1).

    ``polynomial`` is a primitive ``fmpz_mpoly`` in (u, v, R) with positive leading coefficient
    (lex order u > v > R), the product of the kept irreducible factors, each once.
    """

    curve: flint.fmpz_mpoly
    polynomial: flint.fmpz_mpoly
    kept: list[dict] = field(default_factory=list)
    rejected: list[RejectedFactor] = field(default_factory=list)
    samples: list[str] = field(default_factory=list)
    seconds: dict[str, float] = field(default_factory=dict)

    @property
    def degrees(self) -> dict[str, int]:
        """Degree in each of u, v, R."""
        return dict(zip(OFFSET_VARIABLES, (int(d) for d in self.polynomial.degrees())))

    @property
    def degree_uv(self) -> int:
        """Total degree in (u, v): the degree of the offset curve at a generic fixed R (Theorem 4.2.18)."""
        return max(int(e[0]) + int(e[1]) for e in self.polynomial.to_dict())

    @property
    def terms(self) -> int:
        return len(self.polynomial)

    def __str__(self) -> str:
        return str(self.polynomial)

    def evaluate(self, u, v, R):
        """Exact (Fraction) or float value of the offset polynomial at (u, v, R)."""
        total = 0
        for (i, j, l), c in self.polynomial.to_dict().items():
            total = total + int(c) * u ** int(i) * v ** int(j) * R ** int(l)
        return total

    def to_dict(self) -> dict:
        """JSON-ready summary (the polynomial as a sorted term list)."""
        return {"curve": str(self.curve), "variables": list(OFFSET_VARIABLES),
                "degrees": self.degrees, "degree_uv": self.degree_uv, "terms": self.terms,
                "polynomial": [[list(map(int, k)), str(int(c))]
                               for k, c in sorted(self.polynomial.to_dict().items(), reverse=True)],
                "kept": self.kept,
                "rejected": [{"terms": r.terms, "degrees": r.degrees, "multiplicity": r.multiplicity,
                              "reason": r.reason} for r in self.rejected],
                "seconds": {k: round(v, 4) for k, v in self.seconds.items()}}


def _rational_singular_points(curve) -> list[tuple[Fraction, Fraction]]:
    """The singular points of V(curve) with rational coordinates (exact)."""
    fx, fy = curve.derivative(0), curve.derivative(1)
    out = []
    # x-coordinates: rational roots of the gcd of the resultants in y (or all of x when f has no y)
    if curve.degrees()[1] == 0:
        px = _to_univariate(curve, 0)
        cands = [(r, None) for r in _rational_roots(px)]
    else:
        r1 = curve.resultant(fx, "y") if fx.degrees()[1] > 0 else fx
        r2 = curve.resultant(fy, "y") if fy.degrees()[1] > 0 else fy
        g = r1.gcd(r2) if not r1.is_zero() and not r2.is_zero() else (r1 if not r1.is_zero() else r2)
        if g.is_zero() or g.degrees()[1] > 0:
            return out
        cands = [(r, None) for r in _rational_roots(_to_univariate(g, 0))]
    for x0, _ in cands:
        py = curve_at_abscissa(curve, x0, False)
        ys = _rational_roots(py) if py.degree() >= 1 else []
        for y0 in ys:
            vals = [_eval_rational(p, x0, y0) for p in (curve, fx, fy)]
            if all(v == 0 for v in vals):
                out.append((x0, y0))
    return out


def _to_univariate(poly, var: int) -> flint.fmpq_poly:
    coeffs: dict[int, int] = {}
    for k, c in poly.to_dict().items():
        coeffs[int(k[var])] = coeffs.get(int(k[var]), 0) + int(c)
    deg = max(coeffs) if coeffs else 0
    return flint.fmpq_poly([coeffs.get(e, 0) for e in range(deg + 1)])


def _rational_roots(p: flint.fmpq_poly) -> list[Fraction]:
    if p.is_zero() or p.degree() < 1:
        return []
    out = []
    for g, _ in p.factor()[1]:
        if g.degree() == 1:
            c = g.coeffs()
            r = -c[0] / c[1]
            out.append(Fraction(int(r.p), int(r.q)))
    return out


def _eval_rational(poly, x0: Fraction, y0: Fraction) -> Fraction:
    return sum((Fraction(int(c)) * x0 ** int(i) * y0 ** int(j) for (i, j), c in poly.to_dict().items()),
               Fraction(0))


def _is_singular_circle(fac, sing: list[tuple[Fraction, Fraction]]):
    """(a, b) if fac is a constant times (u − a)² + (v − b)² − R for a listed singular point."""
    for a, b in sing:
        den = a.denominator * a.denominator * b.denominator * b.denominator
        coeffs = {(2, 0, 0): 1, (0, 2, 0): 1, (1, 0, 0): -2 * a, (0, 1, 0): -2 * b,
                  (0, 0, 1): -1, (0, 0, 0): a * a + b * b}
        circ = _OUT_CTX.from_dict({k: int(c * den) for k, c in coeffs.items() if c != 0})
        circ = circ.primitive()[1]
        if fac == circ or fac == -circ:
            return a, b
    return None


def factor_over_z(p) -> list:
    """Irreducible factors of an fmpz_mpoly over ℤ (content dropped).  python-flint 0.9's
    ``fmpz_mpoly.factor`` raises OverflowError while sorting two factors of equal length with
    huge coefficients; ``fmpq_mpoly.factor`` does not, so it is the fallback."""
    _, prim = p.primitive()
    try:
        return [(g, int(e)) for g, e in prim.factor()[1]]
    except OverflowError:
        ctx = prim.context()
        qctx = flint.fmpq_mpoly_ctx.get(ctx.names(), "lex")
        q = qctx.from_dict({k: flint.fmpq(int(c)) for k, c in prim.to_dict().items()})
        out = []
        for g, e in q.factor()[1]:
            den = 1
            for c in g.to_dict().values():
                den = den * int(c.q) // math.gcd(den, int(c.q))
            gz = ctx.from_dict({k: int(c * den) for k, c in g.to_dict().items()}).primitive()[1]
            out.append((gz, int(e)))
        return out


def first_resultants(comp, ctx, x, y, u, v, R):
    """The offset system of the curve comp = 0 at the point (u, v) and squared distance R (thesis
    §4.1: normality n = 0 and distance d = 0), and the resultants of comp with n and with d in the
    first variable eliminated (y, or x for a component free of y).
    Returns (comp in ctx, Res(comp, n), Res(comp, d), the variable left to eliminate)."""
    fe = comp.compose(x, y, ctx=ctx)
    fx, fy = fe.derivative("x"), fe.derivative("y")
    n = -fy * (u - x) + fx * (v - y)
    d = (u - x) ** 2 + (v - y) ** 2 - R
    first, second = ("y", "x") if comp.degrees()[1] > 0 else ("x", "y")
    return fe, fe.resultant(n, first), fe.resultant(d, first), second


def _resultant_factors(comp):
    """Irreducible factors (with multiplicities) of the iterated resultant for one ℚ-irreducible
    component ``comp`` of the curve: Res_x(P, Res_y(comp, d)) with P the part of Res_y(comp, n)
    that depends on (u, v).  The factors of Res_y(comp, n) free of u and v are x-coordinates where
    comp and n share a root for every (u, v) — singular points of comp, or a common vanishing of
    the leading coefficients — never feet of normals from a generic point: their share Res(g, Res_y(comp, d)) of the
    full resultant is computed alone (it holds the singular circles), which avoids most of the
    blow-up of the full resultant (quartics ~7× faster).  A component free of y (vertical
    lines) is eliminated in the other order."""
    x, y, u, v, R = _ELIM_CTX.gens()
    fe, r1, r2, second = first_resultants(comp, _ELIM_CTX, x, y, u, v, R)
    part = _ELIM_CTX.from_dict({(0, 0, 0, 0, 0): 1})
    out = []
    for g, e in factor_over_z(r1):
        degs = g.degrees()
        if degs[2] or degs[3]:
            part = part * g ** int(e)
        elif not g.is_constant():
            # its share of the full resultant, Res(g, r2)^e: the circles centred at the points of
            # the curve above the root(s) of g, among them the singular circle of §4.1 (cheap)
            out += [(h, int(e) * int(k)) for h, k in factor_over_z(g.resultant(r2, second)) if not h.is_constant()]
    res = part.resultant(r2, second)
    if res.is_zero():
        raise ValueError(f"offset of {comp}: the iterated resultant vanishes identically")
    return [(g, int(e)) for g, e in factor_over_z(res) if not g.is_constant()] + out


@dataclass(frozen=True)
class FactorSelection:
    """Outcome of :func:`select_factors`: ``kept`` indices, the per-factor ``hits`` (one list of
    booleans per group of points) and whether every point lies on some kept factor."""

    kept: tuple[int, ...]
    hits: tuple[tuple[tuple[bool, ...], ...], ...]
    covered: bool


def select_factors(factors, groups, vanishes) -> FactorSelection:
    """Select the factors of an eliminant that define the offset (thesis §4.1, §4.4).

    ``groups`` are lists of exact points of the true offset, one list per component that must be
    explained by a single factor (one group per ℚ-irreducible component of the curve; for a
    family whose offset is reducible in an unknown way, one group per point).  A factor is kept
    iff ``vanishes(factor, point)`` holds at every point of at least one group; the selection is
    complete (``covered``) iff every point lies on some kept factor.  This is the one factor
    selection of the library: :func:`offset` and the conic families of the offline stage use it.
    """
    kept, all_hits = [], []
    covered = [[False] * len(g) for g in groups]
    for i, fac in enumerate(factors):
        hits = tuple(tuple(bool(vanishes(fac, p)) for p in g) for g in groups)
        all_hits.append(hits)
        if any(h and all(h) for h in hits):
            kept.append(i)
            covered = [[c or h for c, h in zip(cc, hh)] for cc, hh in zip(covered, hits)]
    return FactorSelection(tuple(kept), tuple(all_hits), all(all(c) for c in covered))


def offset(f, *, samples_per_component: int = 2, seed: int = 20030101) -> AlgebraicOffset:
    """The generalised offset of the square-free plane curve V(f), exact (thesis §4.1).

    Parameters
    ----------
    f : str, SymPy or python-flint polynomial in x, y with rational coefficients.
    samples_per_component : exact offset points per ℚ-irreducible component of V(f) used to
        select the factors (see the module docstring).
    seed : seed of the choice of those points.

    Returns
    -------
    AlgebraicOffset with ``polynomial`` (in u, v, R; R = squared distance), ``degrees``,
    ``degree_uv``, ``terms``, ``rejected`` (each with the reason) and ``seconds``.

    Examples
    --------
    >>> offset("x^2 + y^2 - 1").polynomial
    u^4 + 2*u^2*v^2 - 2*u^2*R - 2*u^2 + v^4 - 2*v^2*R - 2*v^2 + R^2 - 2*R + 1
    """
    curve = parse_curve(f)
    t0 = time.perf_counter()
    comps = [g for g, _ in curve.factor()[1] if not g.is_constant()]
    factors: list = []
    for comp in comps:                      # the offset of a union is the product of the offsets
        for fac, mult in _resultant_factors(comp):
            same = [i for i, (g, _) in enumerate(factors) if g == fac or g == -fac]
            if same:
                factors[same[0]] = (factors[same[0]][0], factors[same[0]][1] + mult)
            else:
                factors.append((fac, mult))
    t1 = time.perf_counter()
    rng = random.Random(seed)
    comp_points = []
    for comp in comps:
        pts = curve_points(comp, samples_per_component, rng)
        comp_points.append([offset_point(comp, p, Fraction(rng.randint(-60, 60) or 7, rng.randint(1, 9)))
                            for p in pts])
        if any(q.R.is_zero() for q in comp_points[-1]):
            raise ValueError(f"component {comp} of the curve has isotropic normals (f_x² + f_y² = 0 on it, "
                             "e.g. the lines x ± i·y = c): its generalised offset is degenerate (R = 0 only)")
    sing = _rational_singular_points(curve)

    kept, kept_info, rejected, candidates = [], [], [], []
    for fac, mult in factors:
        fo = fac.project_to_context(_OUT_CTX)
        degs = [int(e) for e in fo.degrees()]
        if degs[0] == 0 and degs[1] == 0:
            rejected.append(RejectedFactor(fo, int(mult), "no u, v: constant or R-only content of the resultant"))
        else:
            candidates.append((fo, int(mult)))
    sel = select_factors([fo for fo, _ in candidates], comp_points,
                         lambda fo, p: evaluate_at_point(fo, p).is_zero())
    for i, (fo, mult) in enumerate(candidates):
        if i in sel.kept:
            kept.append(fo)
            kept_info.append({"terms": len(fo), "degrees": dict(zip(OFFSET_VARIABLES, (int(e) for e in fo.degrees()))),
                              "multiplicity_in_resultant": mult,
                              "vanishing_samples": sum(map(sum, sel.hits[i]))})
            continue
        circle = _is_singular_circle(fo, sing)
        if circle is not None:
            reason = (f"extraneous circle of the singular point ({circle[0]}, {circle[1]}): "
                      "the normal equation vanishes identically there (thesis §4.1)")
        else:
            bad = next(p for g, hh in zip(comp_points, sel.hits[i]) for p, h in zip(g, hh) if not h)
            reason = ("extraneous factor of the iterated resultant: nonzero at the exact offset point "
                      + bad.describe())
        rejected.append(RejectedFactor(fo, mult, reason))
    if not kept or not sel.covered:
        raise RuntimeError(f"offset of {curve}: no product of factors vanishes at all exact offset points")
    poly = kept[0]
    for k_ in kept[1:]:
        poly = poly * k_
    poly = poly.primitive()[1]
    if leading_coefficient(poly) < 0:
        poly = -poly
    samples = [p.describe() for pts in comp_points for p in pts]
    return AlgebraicOffset(curve, poly, kept_info, rejected, samples,
                           {"elimination": t1 - t0, "selection": time.perf_counter() - t1,
                            "total": time.perf_counter() - t0})
