"""Sparse polynomials with exact rational coefficients and compiled interval evaluators.

Thesis §3.3.3: "the bounds of a function depend heavily on the way the function is
written".  Every polynomial is therefore compiled once into a *nested Horner* scheme
(recursive in the variables, in the given order) as Python source; the same code runs on
``flint.arb`` balls (rigorous enclosures) and on floats (Newton refinement).  Gradients are
derived symbolically once (:meth:`Poly.diff`), so the mean-value form
``f(m) + J(X)(X - m)`` and the Krawczyk operator use exact derivative polynomials.
"""
from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
from typing import Iterable, Mapping, Sequence

from flint import arb, fmpq, fmpq_mpoly_ctx

from ..sites.rationals import to_fraction

Exponent = tuple


class Poly:
    """Polynomial ``sum c_e x^e`` in named variables; ``terms`` maps exponent tuples to Fractions."""

    __slots__ = ("names", "terms", "_arb_fn", "_float_fn", "_src")

    def __init__(self, names: Sequence[str], terms: Mapping[Exponent, object]):
        self.names = tuple(names)
        n = len(self.names)
        clean: dict[Exponent, Fraction] = {}
        for e, c in terms.items():
            e = tuple(int(k) for k in e)
            if len(e) != n:
                raise ValueError(f"exponent {e} does not match variables {self.names}")
            c = to_fraction(c, "coefficient")
            if c:
                clean[e] = clean.get(e, Fraction(0)) + c
                if not clean[e]:
                    del clean[e]
        self.terms = clean
        self._arb_fn = None
        self._float_fn = None
        self._src = None

    # ------------------------------------------------------------------ construction
    @classmethod
    def from_sympy(cls, expr, names: Sequence[str]) -> "Poly":
        import sympy

        syms = sympy.symbols(list(names))
        if isinstance(expr, str):
            expr = sympy.sympify(expr, locals={str(s): s for s in syms})
        expr = sympy.nsimplify(expr, rational=True) if expr.has(sympy.Float) else expr
        p = sympy.Poly(sympy.expand(expr), *syms)
        if not p.domain.is_QQ and not p.domain.is_ZZ:
            raise ValueError(f"polynomial {expr} must have rational coefficients in {names}")
        return cls(names, {tuple(m): to_fraction(c) for m, c in p.terms()})

    @classmethod
    def from_flint(cls, mpoly, names: Sequence[str] | None = None) -> "Poly":
        ctx = mpoly.context()
        gens = tuple(str(g) for g in ctx.names()) if hasattr(ctx, "names") else None
        names = tuple(names) if names is not None else gens
        return cls(names, {tuple(e): to_fraction(c, "coefficient") for e, c in mpoly.to_dict().items()})

    @classmethod
    def constant(cls, names, c) -> "Poly":
        return cls(names, {(0,) * len(names): c})

    @classmethod
    def var(cls, names, i) -> "Poly":
        e = [0] * len(names)
        e[i] = 1
        return cls(names, {tuple(e): 1})

    # ------------------------------------------------------------------ algebra
    def __add__(self, other):
        other = self._coerce(other)
        t = dict(self.terms)
        for e, c in other.terms.items():
            t[e] = t.get(e, Fraction(0)) + c
        return Poly(self.names, t)

    __radd__ = __add__

    def __neg__(self):
        return Poly(self.names, {e: -c for e, c in self.terms.items()})

    def __sub__(self, other):
        return self + (-self._coerce(other))

    def __rsub__(self, other):
        return self._coerce(other) - self

    def __mul__(self, other):
        other = self._coerce(other)
        t: dict[Exponent, Fraction] = {}
        for e1, c1 in self.terms.items():
            for e2, c2 in other.terms.items():
                e = tuple(a + b for a, b in zip(e1, e2))
                t[e] = t.get(e, Fraction(0)) + c1 * c2
        return Poly(self.names, t)

    __rmul__ = __mul__

    def __pow__(self, k: int):
        out = Poly.constant(self.names, 1)
        for _ in range(int(k)):
            out = out * self
        return out

    def _coerce(self, other) -> "Poly":
        if isinstance(other, Poly):
            if other.names != self.names:
                raise ValueError(f"variable mismatch {self.names} vs {other.names}")
            return other
        return Poly.constant(self.names, other)

    def diff(self, i: int) -> "Poly":
        t = {}
        for e, c in self.terms.items():
            if e[i]:
                e2 = list(e)
                e2[i] -= 1
                t[tuple(e2)] = c * e[i]
        return Poly(self.names, t)

    def is_zero(self) -> bool:
        return not self.terms

    def degree(self, i: int | None = None) -> int:
        if not self.terms:
            return -1
        if i is None:
            return max(sum(e) for e in self.terms)
        return max(e[i] for e in self.terms)

    def rename(self, names: Sequence[str], mapping: Sequence[int]) -> "Poly":
        """Embed into variables ``names``; variable j of self becomes names[mapping[j]]."""
        n = len(names)
        t = {}
        for e, c in self.terms.items():
            e2 = [0] * n
            for j, k in enumerate(e):
                e2[mapping[j]] += k
            t[tuple(e2)] = t.get(tuple(e2), Fraction(0)) + c
        return Poly(names, t)

    def substitute(self, values: Sequence["Poly"]) -> "Poly":
        """Compose: variable j replaced by ``values[j]`` (Polys in a common variable set)."""
        names = values[0].names
        out = Poly(names, {})
        powcache: dict[tuple[int, int], Poly] = {}

        def pw(j, k):
            if (j, k) not in powcache:
                powcache[(j, k)] = values[j] ** k if k < 2 or (j, k - 1) not in powcache else powcache[(j, k - 1)] * values[j]
            return powcache[(j, k)]

        for e, c in self.terms.items():
            term = Poly.constant(names, c)
            for j, k in enumerate(e):
                if k:
                    term = term * pw(j, k)
            out = out + term
        return out

    def __call__(self, *args):
        """Exact evaluation at rationals (slow path; used in tests and exact checks)."""
        s = Fraction(0)
        for e, c in self.terms.items():
            t = c
            for a, k in zip(args, e):
                if k:
                    t *= Fraction(a) ** k
            s += t
        return s

    def __repr__(self):
        return f"Poly({self.names}, {len(self.terms)} terms, deg {self.degree()})"

    # ------------------------------------------------------------------ compiled evaluation
    def _horner_source(self) -> tuple[str, list[Fraction]]:
        consts: list[Fraction] = []
        n = len(self.names)

        def rec(terms: list[tuple[Exponent, Fraction]], k: int) -> str:
            if k == n:
                c = sum((c for _, c in terms), Fraction(0))
                consts.append(c)
                return f"C[{len(consts) - 1}]"
            groups: dict[int, list] = {}
            for e, c in terms:
                groups.setdefault(e[k], []).append((e, c))
            degs = sorted(groups, reverse=True)
            v = f"a{k}"
            expr = None
            prev = None
            for d in degs:
                sub = rec(groups[d], k + 1)
                if expr is None:
                    expr = sub
                else:
                    gap = prev - d
                    mul = v if gap == 1 else "(" + "*".join([v] * gap) + ")"  # not **: nan on arb balls at 0
                    expr = f"({expr})*{mul}+{sub}"
                prev = d
            if prev:
                mul = v if prev == 1 else "(" + "*".join([v] * prev) + ")"
                expr = f"({expr})*{mul}"
            return expr

        if not self.terms:
            return "C[0]", [Fraction(0)]
        body = rec(sorted(self.terms.items()), 0)
        return body, consts

    def _compile(self, kind: str):
        if self._src is None:
            self._src = self._horner_source()
        body, consts = self._src
        if kind == "arb":
            C = tuple(arb(fmpq(c.numerator, c.denominator)) for c in consts)
        else:
            C = tuple(float(c) for c in consts)
        args = ",".join(f"a{k}" for k in range(len(self.names)))
        ns = {"C": C}
        exec(f"def _f({args}):\n    return {body}\n", ns)  # noqa: S102 - generated from our own terms
        return ns["_f"]

    @property
    def arb_eval(self):
        """Rigorous evaluator on arb balls (nested Horner form)."""
        if self._arb_fn is None:
            self._arb_fn = self._compile("arb")
        return self._arb_fn

    @property
    def float_eval(self):
        if self._float_fn is None:
            self._float_fn = self._compile("float")
        return self._float_fn


def parse_poly(spec, names=("x", "y")) -> Poly:
    """A Poly from a Poly, a sympy expression/string or a python-flint mpoly."""
    if isinstance(spec, Poly):
        if spec.names != tuple(names):
            raise ValueError(f"polynomial in {spec.names}, expected {tuple(names)}")
        return spec
    if hasattr(spec, "to_dict") and hasattr(spec, "context"):
        return Poly.from_flint(spec, names)
    return Poly.from_sympy(spec, names)


def jacobian(polys: Iterable[Poly], nvars: int) -> list[list[Poly]]:
    return [[p.diff(j) for j in range(nvars)] for p in polys]


# ---------------------------------------------------------------------- Taylor (centred) form
def short_dyadic(m: float, w: float) -> Fraction:
    """A dyadic rational near m with few bits (any point of the box is a valid Taylor centre)."""
    if w <= 0 or not (m == m):
        return Fraction(m)
    k = math.floor(math.log2(w)) - 12
    step = Fraction(2) ** k
    return Fraction(round(Fraction(m) / step)) * step


class TaylorForm:
    """Exact Taylor expansion of a Poly at a rational centre c of a box:
    ``f(c + h) = Σ a_α h^α`` (computed with python-flint ``fmpq_mpoly.compose``).

    Enclosures over |h_j| <= ρ_j:  f ∈ a_0 ± Σ_{α≠0} |a_α| ρ^α  and
    ∂_j f ∈ a_{e_j} ± Σ_{α_j>=1, α≠e_j} α_j |a_α| ρ^{α−e_j}  (thesis §3.3.3: the way a function
    is written decides the width; this centred form overestimates by O(width²)).
    Float sums are rounded up by a relative 1e-10 margin (each is a sum of nonnegative terms).
    """

    __slots__ = ("c0", "lin", "E", "A")

    def __init__(self, c0, lin, E, A):
        self.c0, self.lin, self.E, self.A = c0, lin, E, A

    def value(self, rho):
        hp = np.prod(np.power(rho, self.E), axis=1)
        s = float(np.dot(self.A, hp)) * (1 + 1e-10)
        return self.c0 + arb(0, s) if s else self.c0

    def gradient(self, rho):
        out = []
        n = self.E.shape[1]
        for j in range(n):
            ej = self.E[:, j]
            mask = ej >= 1
            mask &= ~((ej == 1) & (self.E.sum(axis=1) == 1))  # the exact linear term is lin[j]
            if not np.any(mask):
                out.append(self.lin[j])
                continue
            E2 = self.E[mask].copy()
            E2[:, j] -= 1
            hp = np.prod(np.power(rho, E2), axis=1)
            s = float(np.dot(self.A[mask] * ej[mask], hp)) * (1 + 1e-10)
            out.append(self.lin[j] + arb(0, s) if s else self.lin[j])
        return out


def _to_arb(q) -> arb:
    return arb(q)


def taylor_form(poly: "Poly", centre) -> TaylorForm:
    """Taylor form of poly at centre (sequence of Fractions)."""
    ctx = fmpq_mpoly_ctx.get(tuple(poly.names), "lex")
    key = id(poly)
    mp = _MPOLY_CACHE.get(key)
    if mp is None or mp[0] is not poly:
        mp = (poly, ctx.from_dict({e: fmpq(c.numerator, c.denominator) for e, c in poly.terms.items()}))
        _MPOLY_CACHE[key] = mp
    gens = ctx.gens()
    shifted = mp[1].compose(*[g + fmpq(c.numerator, c.denominator) for g, c in zip(gens, centre)])
    d = shifted.to_dict()
    n = len(poly.names)
    zero = (0,) * n
    c0 = arb(d.pop(zero, fmpq(0)))
    lin = []
    for j in range(n):
        e = tuple(1 if k == j else 0 for k in range(n))
        lin.append(arb(d.pop(e, fmpq(0))))
        # the linear term is also part of the sum for the value enclosure
        if lin[-1] != 0:
            d[e] = None
    keys = list(d.keys())
    E = np.array(keys, dtype=np.int64).reshape(-1, n)
    A = np.empty(len(keys))
    for i, k in enumerate(keys):
        v = d[k]
        if v is None:
            j = k.index(1)
            A[i] = abs(float(lin[j].mid())) * (1 + 2.0**-50)
        else:
            A[i] = abs(float(v)) * (1 + 2.0**-50)
            if A[i] == 0.0:  # underflow: keep the bound an upper bound
                A[i] = 5e-324
    # linear terms are also stored with their exact value in lin[]; in A for the value bound
    return TaylorForm(c0, lin, E, A)


_MPOLY_CACHE: dict = {}
