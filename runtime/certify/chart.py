"""Krawczyk certification of far solutions in circle-space charts (thesis §4.4, §5.3–§5.5).

Why: a solution (x, y, R) of o1 = o2 = o3 = 0 whose circle is huge (|x| ~ 10⁵–10⁶, the circle
almost a line) is terribly conditioned in (x, y, R) -- Jacobian condition ~10²² -- and the
world-coordinate Krawczyk test of :mod:`runtime.certify.complete` fails on it, although it is a
genuine finite simple solution.

What: the circle with centre (x, y) and squared radius R is A(X² + Y²) − 2x̂X − 2ŷY + T̂ = 0 with
homogeneous coordinates h = [A : x̂ : ŷ : T̂] ∈ P³, x = x̂/A, y = ŷ/A, T̂/A = x² + y² − R (the
power of the origin).  Each exact offset o_i(x, y, R) (``OffsetSystem`` of
:mod:`runtime.certify.complete`) becomes q_i(x, y, T) = o_i(x, y, x² + y² − T), of lower total
degree d_i than the weighted degree 8 of o_i (measured: 5 for a parabola, 6 for an ellipse or a
hyperbola, 6 for a circle, where the specialised generic offset is the degree-2 circle offset times
the square of a quadric), homogenised to Q_i(A, x̂, ŷ, T̂) = c_i·A^{d_i} q_i(x̂/A, ŷ/A, T̂/A) with
coprime integer coefficients (c_i > 0 rational).  Far circles tend to lines, A → 0: regular points
of P³, where the system is well conditioned.

Proof (chart j, the homogeneous coordinate h_j set to 1, unknowns u = the other three):

* on {A ≠ 0} the map φ_j(u) = (x̂/A, ŷ/A, (x̂² + ŷ²)/A² − T̂/A) is a biholomorphism onto the world
  points whose j-th homogeneous coordinate is ≠ 0 (inverse: h/h_j), and G_i(u) := Q_i(h(u)) =
  c_i·A^{d_i}·o_i(φ_j(u)) identically.  So u with A ≠ 0 is a zero of G iff φ_j(u) is a (finite)
  zero of o, and at such a zero J_G = diag(c_i A^{d_i})·J_o(φ_j(u))·J_φ(u) (the derivative of the
  factor A^{d_i} multiplies o_i = 0): J_G is nonsingular iff J_o is -- simple zeros correspond;
* a successful complex Krawczyk test (``krawczyk_complex`` of :mod:`runtime.certify.offset_system`, acb,
  the exact integer coefficients as balls) on a box X of the chart proves a unique simple zero u*
  of G in X, lying in the Krawczyk image K ⊂ X; if the A-component of K excludes 0 (or j = 0,
  A ≡ 1), s* = φ_j(u*) is a finite simple zero of o, and the world enclosure W = φ_j(K),
  evaluated in ball arithmetic, contains s*;
* reality: G has real coefficients; for a real midpoint X is conjugation-symmetric, so u* is real
  (its conjugate is a zero in X too) and so is s* (φ_j is real); if some component of K excludes
  the real axis, u* is non-real and so is s* (φ_j⁻¹ = h/h_j maps real points to real points);
* the completeness argument of :mod:`runtime.certify.complete` needs, per listed solution, only an
  enclosure containing a simple zero of o of the stated reality: the N zeros are distinct because
  the N world enclosures are pairwise disjoint (:func:`runtime.certify.solution_boxes.boxes_disjoint`;
  a zero lies in each enclosure, so two enclosures sharing no point hold different zeros), exactly as for world-coordinate boxes
  (their uniqueness region X is not used there), and N distinct simple zeros = the generic count
  are all the isolated zeros (coefficient-parameter theorem).  Real ones go on to the vertex
  matching / non-vertex proof with their world enclosure W unchanged.
"""
from __future__ import annotations

from fractions import Fraction
from functools import lru_cache

import flint
import numpy as np
from flint import acb, arb

from ..algebra.circle_space import circle_space_terms
from .foot import normalised_coefficients, working_prec
from .offset_system import krawczyk_complex, newton_track, offset_terms

__all__ = ["chart_polynomials", "ChartSystem", "certify_in_chart",
           "world_from_chart", "choose_charts"]

#: precisions (bits) of the chart Krawczyk test
CHART_PRECS = (128, 256)


def _homogenise(q: dict) -> tuple[int, dict[tuple[int, int, int, int], int], Fraction]:
    """(d, Q, c): Q(A, x̂, ŷ, T̂) = c · A^d q(x̂/A, ŷ/A, T̂/A) with coprime integer coefficients
    (c > 0 rational; the common factor does not change the zeros or the Krawczyk test)."""
    d = max(sum(e) for e in q)
    den = 1
    for v in q.values():
        v = Fraction(v)
        den = den * v.denominator // _gcd(den, v.denominator)
    ints = {e: int(Fraction(v) * den) for e, v in q.items()}
    g = 0
    for v in ints.values():
        g = _gcd(g, v)
    return d, {(d - sum(e), e[0], e[1], e[2]): v // g for e, v in ints.items()}, Fraction(den, g)


def _gcd(a: int, b: int) -> int:
    from math import gcd
    return gcd(a, b)


@lru_cache(maxsize=64)
def chart_polynomials(cos: tuple[tuple[Fraction, ...], ...]):
    """Homogeneous circle-space offsets of the three conics (normalised coefficient tuples):
    tuple of (d_i, Q_i = {(a, x̂, ŷ, T̂) exponents: integer coefficient}, c_i) with
    Q_i(1, x, y, x² + y² − R) = c_i · o_i(x, y, R), o_i the offsets of ``OffsetSystem``."""
    return tuple(_homogenise(circle_space_terms({(i, j, k): c for i, j, k, c in offset_terms(co)})) for co in cos)


class ChartSystem:
    """G_i(u) = Q_i(h(u)), h the homogeneous vector with h_chart = 1 and the unknowns u in the other
    three places (order A, x̂, ŷ, T̂ kept); same interface as ``OffsetSystem.eval``.  The exact
    integer coefficients become arb balls at the precision current when the system is built."""

    def __init__(self, polys, chart: int):
        self.chart = chart
        self.free = [t for t in range(4) if t != chart]
        self.polys = []
        for _, Q, _ in polys:
            T = {}
            for e, v in Q.items():
                key = tuple(e[t] for t in self.free)
                T[key] = T.get(key, 0) + v
            self.polys.append([(k[0], k[1], k[2], _ball(v)) for k, v in T.items() if v])
        self.deg = max(max(max(k[:3]) for k in P) for P in self.polys)

    def eval(self, z, jac: bool = True):
        P = []
        for t in range(3):
            pw = [acb(1)]
            for _ in range(self.deg):
                pw.append(pw[-1] * z[t])
            P.append(pw)
        U, V, W = P
        vals, J = [], []
        for T in self.polys:
            s, g0, g1, g2 = acb(0), acb(0), acb(0), acb(0)
            for i, j, k, c in T:
                s += c * U[i] * V[j] * W[k]
                if jac:
                    if i:
                        g0 += (c * i) * U[i - 1] * V[j] * W[k]
                    if j:
                        g1 += (c * j) * U[i] * V[j - 1] * W[k]
                    if k:
                        g2 += (c * k) * U[i] * V[j] * W[k - 1]
            vals.append(s)
            J.append([g0, g1, g2])
        return vals, J


def choose_charts(s) -> list[tuple[int, np.ndarray]]:
    """Charts to try for the world point s, each as (j, chart point h/h_j without its j-th entry),
    h = (1, x, y, x² + y² − R) (complex floats; numerical, not part of the proof).

    First the chart of the largest of |1|, |x|, |y|: a far solution from the numeric stage has
    (x, y, R) accurate to ~10⁻⁶ relative, but T = x² + y² − R cancels and is much worse, so T̂ is
    left free (Newton from there converges back from 10⁻³ relative perturbations of (x, y, R) for
    exact_EPC, where the T̂ = 1 chart fails from 10⁻⁶).  Then the T̂ = 1 chart if |T| is the largest."""
    x, y, R = (complex(t) for t in s)
    h = np.array([1.0, x, y, x * x + y * y - R], dtype=complex)
    j = int(np.argmax(np.abs(h[:3])))
    out = [(j, np.delete(h / h[j], j))]
    if abs(h[3]) > abs(h[j]):
        out.append((3, np.delete(h / h[3], 3)))
    return out


def world_from_chart(chart: int, K) -> list:
    """Ball enclosure of φ_chart(K) = (x̂/A, ŷ/A, x² + y² − T̂/A) (arb or acb balls); None if the
    A-ball contains 0 (the chart point may be at infinity)."""
    one = K[0].__class__(1)
    it = iter(K)
    h = [one if t == chart else next(it) for t in range(4)]
    A = h[0]
    if A.contains(0):
        return None
    x, y = h[1] / A, h[2] / A
    R = x * x + y * y - h[3] / A
    return [x, y, R]


def certify_in_chart(conics, s, *, precs=CHART_PRECS, iters: int = 30):
    """(kind, K) with kind 'real' | 'nonreal' and K the *world* (x, y, R) enclosure of a finite
    simple solution, found by Newton from ``s`` (module docstring), or None.

    ``s`` (complex (x, y, R)) is mapped to a chart (:func:`choose_charts`), Newton-refined there
    (real arithmetic if the chart point is real to 10⁻⁶ relative) and must converge (quadratically);
    then the complex Krawczyk test runs at each precision of ``precs``.

    The zero found need not be the one ``s`` approximates best: in a cluster of far zeros the
    numeric stage's points are off by about their spacing (measured: three hyperbolas 100× apart,
    four real zeros near (−1.3·10⁶, −1.5·10⁷) 2–5·10⁻⁴ of their size apart, each listed 5·10⁻⁴ from
    the zero its chart Newton reaches, all four reached).  The completeness proof does not need it
    to be: it needs one enclosure per listed solution, each holding a simple zero, and proves the
    zeros distinct by the disjointness of all enclosures, so a zero reached twice is caught there
    (and the lost one searched for)."""
    s = np.asarray(s, dtype=complex).reshape(3)
    if not np.isfinite(s).all():
        return None
    polys = chart_polynomials(tuple(normalised_coefficients(c) for c in conics))
    for j, u0 in choose_charts(s):
        if not np.isfinite(u0).all():
            continue
        box = _certify_chart(polys, j, u0, precs, iters)
        if box is not None:
            return box
    return None


def _certify_chart(polys, j, u0, precs, iters):
    """The test of :func:`certify_in_chart` in chart j from the chart point u0 (floats)."""
    nearly_real = float(np.max(np.abs(u0.imag))) < 1e-6 * max(1.0, float(np.max(np.abs(u0))))
    for prec in precs:
        with working_prec(prec):
            sys = ChartSystem(polys, j)
            m = [acb(float(t.real), 0.0 if nearly_real else float(t.imag)) for t in u0]
            m, conv = newton_track(sys, m, nearly_real, iters=iters)
            if not conv:
                return None
            res = krawczyk_complex(sys, m, symmetric=nearly_real)
            if res is None:
                continue
            K, _ = res
            if nearly_real:
                # m real: X is conjugation-symmetric, its unique zero is real (module docstring)
                W = world_from_chart(j, [k.real for k in K])
                if W is not None:
                    return "real", W
                continue
            if not any(not k.imag.contains(0) for k in K):
                continue
            W = world_from_chart(j, K)
            if W is not None:
                return "nonreal", W
    return None


def _ball(v: int) -> arb:
    """The integer v as an arb ball (exact up to the working precision's rounding, enclosed)."""
    return arb(flint.fmpz(v))
