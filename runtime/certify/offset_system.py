"""The triple offset system o1 = o2 = o3 = 0 in (x, y, R) over the complex balls (python-flint acb).

The generalised Voronoi vertices of three conics are the common zeros of their generalised
offsets o_i(x, y, R) (thesis ch. 4, §5.3; R the squared radius).  This module specialises the
offset artefacts (App. B) to given conics with exact rational arithmetic
(:func:`offset_terms`), evaluates the system and its Jacobian in ball arithmetic
(:class:`OffsetSystem`), and proves a simple zero in a polydisc with Krawczyk's test
(:func:`krawczyk_complex`; Krawczyk 1969, Moore 1977, thesis §3.3.3) after Newton steps at the
working precision (:func:`newton_track`).  The completeness proof (:mod:`runtime.certify.complete`)
and the circle-space chart certificates (:mod:`runtime.certify.chart`) both build on it.
"""
from __future__ import annotations

from fractions import Fraction
from functools import lru_cache

import flint
from flint import acb, acb_mat, arb

from ..artefacts import load_offset
from ..sites.rationals import parse_rational
from .foot import normalised_coefficients
from .interval_newton import KrawczykFailure, krawczyk_inflation, strictly_inside

__all__ = ["offset_terms", "exact_offset_terms", "OffsetSystem", "scene_frame", "framed_offset_system",
           "clear_offset_system_caches",
           "krawczyk_complex", "newton_track", "inside_disc"]


@lru_cache(maxsize=256)
def offset_terms(co: tuple[Fraction, ...]):
    o = load_offset("generic")
    spec = _specialise_int(o, co)
    if spec is None:
        a, b, c, d, e, f = co
        spec = o.specialise(a=a, b=b, c=c, d=d, e=e, f=f)
    m = max(abs(v) for v in spec.values())
    return tuple((i, j, k, Fraction(v) / m) for (i, j, k), v in spec.items())


def exact_offset_terms(conic) -> tuple[tuple[int, int, int, Fraction], ...]:
    """The verified generic offset (App. B.1–B.2) specialised at the exact (normalised) coefficients
    of ``conic``: terms (i, j, k, c) of c·x^i·y^j·R^k, scaled so that max |c| = 1."""
    return offset_terms(normalised_coefficients(conic))


def _specialise_int(o, co):
    """``o.specialise`` up to the positive factor q^D, in integer arithmetic (exact, ~10× faster):
    with co = (p_1, ..., p_6)/q and integer coefficients homogeneous of degree D in (a..f),
    q^D · o(co) = Σ coef · Π p_i^{e_i}.  None if the artefact is not of that form."""
    idx = [o.variables.index(p) for p in o.parameters]
    if len(idx) != 6 or len(o.variables) != 9 or idx != [3, 4, 5, 6, 7, 8]:
        return None
    q = 1
    for c in co:
        q = _lcm(q, c.denominator)
    P = [int(c * q) for c in co]
    degs, out = set(), {}
    powc = [[1] for _ in range(6)]
    for exps, coef in o.terms:
        if getattr(coef, "denominator", 1) != 1:
            return None
        degs.add(sum(exps[3:]))
        val = int(coef)
        for t in range(6):
            e = exps[3 + t]
            if e:
                pw = powc[t]
                while len(pw) <= e:
                    pw.append(pw[-1] * P[t])
                val *= pw[e]
        key = (exps[0], exps[1], exps[2])
        out[key] = out.get(key, 0) + val
    if len(degs) != 1:
        return None
    return {k: v for k, v in out.items() if v != 0}


def _lcm(a: int, b: int) -> int:
    from math import gcd
    return a // gcd(a, b) * b


class OffsetSystem:
    """o1, o2, o3 in (x, y, R) with exact rational coefficients, evaluated in acb.  ``terms``
    (instead of ``conics``): the three polynomials as tuples (i, j, k, Fraction c) of c·x^i·y^j·R^k."""

    def __init__(self, conics=None, *, terms=None):
        if terms is None:
            terms = [offset_terms(normalised_coefficients(c)) for c in conics]
        self.terms = [tuple(T) for T in terms]
        self._arb: dict = {}

    @property
    def fmpq_terms(self):
        """``terms`` with python-flint fmpq coefficients (exact; converted once)."""
        if "fmpq" not in self._arb:
            self._arb["fmpq"] = [[(i, j, k, _fmpq(c)) for i, j, k, c in T] for T in self.terms]
        return self._arb["fmpq"]

    def _coeffs(self):
        prec = flint.ctx.prec
        if prec not in self._arb:
            self._arb[prec] = [[(i, j, k, arb(v)) for i, j, k, v in T] for T in self.fmpq_terms]
        return self._arb[prec]

    def value_gradient_columns(self) -> list[dict]:
        """The 12 polynomials o_1, o_2, o_3, then ∂o_i/∂x_j (column 3 + 3i + j, (x_0, x_1, x_2) =
        (x, y, R)), each as {(i, j, k): exact fmpq coefficient} (cached)."""
        if "cols" not in self._arb:
            cols: list[dict] = [{} for _ in range(12)]
            for q, T in enumerate(self.fmpq_terms):
                for i, j, k, c in T:
                    cols[q][(i, j, k)] = cols[q].get((i, j, k), 0) + c
                    for var, e in enumerate((i, j, k)):
                        if e:
                            ex = [i, j, k]
                            ex[var] -= 1
                            d = cols[3 + 3 * q + var]
                            d[tuple(ex)] = d.get(tuple(ex), 0) + c * e
            self._arb["cols"] = cols
        return self._arb["cols"]

    def _matrix(self):
        """(monomials, acb_mat C) with row t of C the coefficients of monomial t in the 12
        polynomials of :meth:`value_gradient_columns`, exact rationals rounded to balls at the
        current precision."""
        prec = flint.ctx.prec
        key = ("mat", prec)
        if key not in self._arb:
            cols = self.value_gradient_columns()
            mons = sorted({m for col in cols for m in col})
            # one conversion of the whole table (exact rationals rounded to balls at this precision)
            C = acb_mat([[dct.get(m, 0) for dct in cols] for m in mons]) if mons else acb_mat(0, 12)
            self._arb[key] = (mons, C, max(max(m) for m in mons) if mons else 0)
        return self._arb[key]

    def eval(self, z, jac: bool = True):
        """Values [o_1, o_2, o_3] and Jacobian rows at the acb point z (one acb matrix product
        of the monomial vector with the coefficient matrix)."""
        mons, C, n = self._matrix()
        u, v, w = z
        U, V, W = [acb(1)], [acb(1)], [acb(1)]
        for _ in range(n):
            U.append(U[-1] * u)
            V.append(V[-1] * v)
            W.append(W[-1] * w)
        row = acb_mat([[U[i] * V[j] * W[k] for i, j, k in mons]])
        P = row * C
        vals = [P[0, q] for q in range(3)]
        J = [[P[0, 3 + 3 * q + var] for var in range(3)] for q in range(3)]
        return vals, J


def scene_frame(conics) -> tuple[Fraction, Fraction, Fraction]:
    """An exact similarity (px, py, s) -- dyadic centre, power-of-two scale -- bringing the conics'
    cores near the unit disc (the numeric working frame :func:`runtime.algebra.polyalg.working_frame`
    without its rotation, rounded to dyadic rationals).  Any choice is sound; this one keeps the
    offsets well scaled for the float certification of spread-out scenes."""
    import math

    from ..algebra.polyalg import working_frame

    wf = working_frame(list(conics), conics[0])
    e = int(round(math.log2(wf.L))) if wf.L > 0 and math.isfinite(wf.L) else 0
    s = Fraction(2) ** e
    q = Fraction(2) ** (e - 12)            # centre rounded to s·2^-12

    def rnd(t: float) -> Fraction:
        return Fraction(round(t / float(q))) * q if math.isfinite(t) else Fraction(0)

    return rnd(wf.px), rnd(wf.py), s


@lru_cache(maxsize=64)
def _framed_terms(co: tuple[Fraction, ...], px: Fraction, py: Fraction, s: Fraction):
    """Terms of o(px + s·u, py + s·v, s²·S) (exact, python-flint fmpq_mpoly), max |c| = 1, for the
    offset o of the conic with normalised coefficients ``co`` (the cache key: six rationals, not
    the ~100 terms, whose hashing cost a third of the composition)."""
    T = offset_terms(co)
    ctx = flint.fmpq_mpoly_ctx.get(("u", "v", "S"))
    u, v, S = ctx.gens()
    o = ctx.from_dict({(i, j, k): _fmpq(c) for i, j, k, c in T})
    g = o.compose(_fmpq(px) + _fmpq(s) * u, _fmpq(py) + _fmpq(s) * v, _fmpq(s * s) * S)
    g = g * (1 / max(abs(c) for c in g.coeffs()))     # exact, in flint
    # fmpq coefficients (exact): the consumers (OffsetSystem.fmpq_terms) use them as they are
    return tuple(sorted((int(e[0]), int(e[1]), int(e[2]), c) for e, c in zip(g.monoms(), g.coeffs())))


def _fmpq(c):
    return parse_rational(c)


def framed_offset_system(conics, frame) -> OffsetSystem:
    """The offset system in scene coordinates (u, v, S): x = px + s·u, y = py + s·v, R = s²·S for
    the exact ``frame`` (px, py, s) (:func:`scene_frame`).  Its zeros are the images of the zeros of
    :class:`OffsetSystem` under this affine bijection (real to real), simple iff simple."""
    return _framed_system(tuple(normalised_coefficients(c) for c in conics), tuple(Fraction(t) for t in frame))


@lru_cache(maxsize=64)
def _framed_system(cos, frame) -> OffsetSystem:
    px, py, s = frame
    return OffsetSystem(terms=[_framed_terms(co, px, py, s) for co in cos])


def clear_offset_system_caches() -> None:
    """Forget the cached scene-frame systems (the specialised offsets themselves stay cached)."""
    _framed_system.cache_clear()
    _framed_terms.cache_clear()


def krawczyk_complex(sys: OffsetSystem, m: list[acb], symmetric: bool, attempts: int = 5):
    """Complex Krawczyk test around the (exact) point m; returns (K, X) or None
    (:func:`runtime.certify.interval_newton.krawczyk_inflation` on square complex boxes)."""
    floor = [(abs(t).abs_upper() + 1) * arb(2) ** (-flint.ctx.prec // 2) for t in m]
    try:
        return krawczyk_inflation(lambda z: sys.eval(z)[0], lambda z: sys.eval(z)[1], m,
                                  attempts=attempts + 3, floor=floor)
    except KrawczykFailure:
        return None


def inside_disc(k: acb, m: acb, r: arb) -> bool:
    """k ⊂ int(m + [−r, r] + i[−r, r]) (:func:`runtime.certify.interval_newton.strictly_inside`)."""
    return strictly_inside(k, m, r)


def newton_track(sys, m, real: bool, iters: int):
    """Newton steps at the working precision; (point, converged) -- converged: the last step is
    below 2^-(prec/2) relative to the point (quadratic convergence reached)."""
    tol = arb(2) ** (-flint.ctx.prec // 2)
    for _ in range(iters):
        vals, J = sys.eval(m)
        try:
            step = acb_mat(J).mid().solve(acb_mat([[v.mid()] for v in vals]))
        except ZeroDivisionError:
            return m, False
        m = [(m[i] - step[i, 0]).mid() for i in range(3)]
        if real:
            m = [acb(t.real.mid(), 0) for t in m]
        size = max(abs(t).mid() for t in m) + 1
        if all(abs(step[i, 0]).mid() < tol * size for i in range(3)):
            return m, True
    return m, False
