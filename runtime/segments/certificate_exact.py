"""Vertices of degree k > 3 of the point/segment/arc certificate, decided exactly (step 2 of
:mod:`runtime.segments.certificate`).

Each listed site gives one equation in (x, y, r) of degree ≤ 2 with coefficients in
Q(√(a² + b²)): |v − p|² = r² for a point (or a smooth joint), a x + b y + c = σ r √(a² + b²) for
a segment touched in its interior on the side σ, |v − c|² = (ρ + σ r)² for an arc touched in its
interior on the side σ of its circle, t·(v − e) = 0 for a curve touched at its listed end e (t its
tangent there).
Three equations whose Jacobian is regular at the reported vertex are solved in closed form by
sympy (linear or quadratic); the real solution near the report is enclosed in arb from its
radicals (:func:`to_arb_expr`, rigorous: rationals, sums, products and real radicals of
non-negative balls), and each remaining equation's residual at that solution is proved to vanish
exactly: sympy's ``minimal_polynomial(residual, z)`` is z exactly when the algebraic number is 0.

Public API: :func:`exact_vertex`, :func:`to_arb_expr`.
"""
from __future__ import annotations

import itertools

import numpy as np
from flint import arb, fmpq

__all__ = ["exact_vertex", "to_arb_expr"]


def exact_vertex(terms, v, sites, tol: float):
    """(X, Y, R) arb enclosures of the exact vertex of three of the listed ``sites`` near the
    reported vertex v (within 10³·``tol``), every other listed site proved on its circle exactly;
    or a message.  ``terms``: the touching types of :mod:`runtime.segments.certificate_vertices`
    (("pt", px, py, …), ("ln", nx, ny, c, σ), ("arc", cx, cy, ρ, σ), ("pp", tx, ty, ex, ey, …),
    exact)."""
    import sympy as sp

    X, Y, R = sp.symbols("X Y R", real=True)
    Q = sp.Rational

    def eq(t):
        if t[0] == "pt":
            return (X - Q(t[1])) ** 2 + (Y - Q(t[2])) ** 2 - R ** 2
        if t[0] == "ln":
            return Q(t[1]) * X + Q(t[2]) * Y + Q(t[3]) - t[4] * R * sp.sqrt(Q(t[1] ** 2 + t[2] ** 2))
        if t[0] == "arc":
            return (X - Q(t[1])) ** 2 + (Y - Q(t[2])) ** 2 - (Q(t[3]) + t[4] * R) ** 2
        return Q(t[1]) * (X - Q(t[3])) + Q(t[2]) * (Y - Q(t[4]))

    eqs = [eq(t) for t in terms]
    z0 = {X: float(v.x), Y: float(v.y), R: float(v.radius)}
    jac = np.array([[float(sp.diff(e, s).subs(z0)) for s in (X, Y, R)] for e in eqs])
    scale = 1 + np.abs(jac).max()
    pick = None
    for combo in itertools.combinations(range(len(eqs)), 3):
        if abs(np.linalg.det(jac[list(combo)])) > 1e-8 * scale ** 3:
            pick = combo
            break
    if pick is None:
        return "no three of the listed sites determine the vertex (singular system)"
    try:
        sols = sp.solve([eqs[c] for c in pick], [X, Y, R], dict=True)
    except (NotImplementedError, ValueError):               # pragma: no cover - sympy limits
        return "the exact solution of three of its sites is not available (sympy)"
    best = None
    for sol in sols:
        try:
            Xa, Ya, Ra = (to_arb_expr(sol[s]) for s in (X, Y, R))
        except (ValueError, KeyError, ZeroDivisionError):
            continue
        if (Xa - float(v.x)).abs_upper() <= 1e3 * tol and (Ya - float(v.y)).abs_upper() <= 1e3 * tol and Ra > 0:
            best = (sol, Xa, Ya, Ra)
            break
    if best is None:
        return "no exact common point of three of its sites near the reported position"
    sol, Xa, Ya, Ra = best
    z = sp.Symbol("z")
    for m, e in enumerate(eqs):
        if m in pick:
            continue
        res = sp.expand(e.subs(sol))
        if res == 0:
            continue
        try:
            if not to_arb_expr(res).contains(0):
                return f"site {sites[m]}: listed, but not at the vertex's distance (off its circle)"
        except (ValueError, ZeroDivisionError):
            pass
        if sp.minimal_polynomial(res, z) != z:
            return f"site {sites[m]}: listed, but not exactly at the vertex's distance (off its circle)"
    return Xa, Ya, Ra


def to_arb_expr(e) -> arb:
    """An arb ball holding the real value of a sympy expression built from rationals with +, ×
    and rational powers (ValueError otherwise, e.g. for a non-real radical)."""
    if e.is_Rational:
        return arb(fmpq(int(e.p), int(e.q)))
    if e.is_Add:
        out = arb(0)
        for a in e.args:
            out += to_arb_expr(a)
        return out
    if e.is_Mul:
        out = arb(1)
        for a in e.args:
            out *= to_arb_expr(a)
        return out
    if e.is_Pow:
        b, ex = e.args
        if ex.is_Integer:
            return _ipow(to_arb_expr(b), int(ex))
        if ex.is_Rational:
            bb = to_arb_expr(b)
            if not bb >= 0:
                raise ValueError("a radical of a quantity not proved non-negative")
            root = bb.sqrt() if ex.q == 2 else bb.root(int(ex.q))
            return _ipow(root, int(ex.p))
    raise ValueError(f"cannot enclose {e}")


def _ipow(x: arb, n: int) -> arb:
    """x**n by multiplication (arb's ``**`` is NaN for a ball around 0)."""
    if n < 0:
        return 1 / _ipow(x, -n)
    out = arb(1)
    for _ in range(n):
        out *= x
    return out
