"""Offsets in circle-space coordinates (x, y, T), T = x² + y² − R.

A circle of centre (x, y) and squared radius R is A(X² + Y²) − 2xX − 2yY + T = 0 with A = 1 and
T = x² + y² − R, the power of the origin with respect to the circle (Pedoe, *Geometry: a
comprehensive course*, §20, the "circle space" of Möbius geometry).  The map (x, y, R) ↦
(x, y, T) is a polynomial automorphism of C³ defined over Q, so the offset system and its
composition g_i(x, y, T) = o_i(x, y, x² + y² − T) have the same solutions with the same
multiplicities.  The composition lowers the total degree of the offsets (thesis App. B: weighted
degree 8 / 6 / 4 in (x, y, R) for the ellipse / parabola / circle families) to 6 / 5 / 2, and a
Voronoi vertex far from the sites is an ordinary point of the closure (the circle tends to a line,
A → 0).  Used by the mixed-volume bound (:mod:`runtime.certify.root_bound`), the zero-dimension
proof (:mod:`runtime.certify.dimension`), the chart certification (:mod:`runtime.certify.chart`),
msolve's input (:mod:`runtime.solve.exact`) and the toric null space (:mod:`runtime.solve.toric`).

One composition, exact (python-flint multivariate polynomials over Z or Q); the floating-point
form converts each float coefficient exactly (a double is a dyadic rational) and rounds once at the
end.
"""
from __future__ import annotations

from fractions import Fraction

import numpy as np

__all__ = ["circle_space_polynomial", "circle_space_terms", "circle_space_float", "polytope_bounds"]


def circle_space_polynomial(poly: dict):
    """g(x, y, T) = o(x, y, x² + y² − T) of an offset {(i, j, k): c} in (x, y, R), exactly: a
    python-flint ``fmpz_mpoly`` in (x, y, T) when every c is an integer, else an ``fmpq_mpoly``
    (c rational: int, Fraction, or float taken at its exact binary value)."""
    import flint

    if all(isinstance(c, int) or (hasattr(c, "denominator") and c.denominator == 1 and not isinstance(c, float))
           for c in poly.values()):
        ctx = flint.fmpz_mpoly_ctx.get(("x", "y", "T"))
        coeffs = {tuple(int(v) for v in e): int(c) for e, c in poly.items()}
    else:
        ctx = flint.fmpq_mpoly_ctx.get(("x", "y", "T"))
        coeffs = {tuple(int(v) for v in e): flint.fmpq(*Fraction(c).as_integer_ratio()) for e, c in poly.items()}
    x, y, t = ctx.gens()
    return ctx.from_dict(coeffs).compose(x, y, x * x + y * y - t)


def circle_space_terms(poly: dict) -> dict[tuple[int, int, int], Fraction]:
    """:func:`circle_space_polynomial` as {(i, j, k): Fraction} (exponents of x, y, T)."""
    g = circle_space_polynomial(poly)
    out = {}
    for e, c in g.to_dict().items():
        f = Fraction(int(c)) if not hasattr(c, "q") else Fraction(int(c.p), int(c.q))
        out[tuple(int(v) for v in e)] = f
    return out


def circle_space_float(poly: dict) -> tuple[np.ndarray, np.ndarray]:
    """(exponents (n, 3) of x, y, T; float coefficients (n,)) of the circle-space form of an offset
    with float coefficients: exact composition, one rounding per coefficient."""
    g = circle_space_polynomial({e: float(c) for e, c in poly.items()})
    d = g.to_dict()
    E = np.array([tuple(int(v) for v in e) for e in d], dtype=np.int64).reshape(-1, 3)
    C = np.array([float(c) for c in d.values()])
    return E, C


def polytope_bounds(E: np.ndarray) -> tuple[int, int]:
    """(a, b) of the smallest polytope {i + j + k ≤ a, i + j + 2k ≤ b} in the positive orthant
    containing the exponents E (rows (i, j, k) of x, y, T): for the ellipse family (6, 8), whose
    normalised volume 184 is the generic number of solutions of three ellipse offsets."""
    return int(E.sum(axis=1).max()), int((E[:, 0] + E[:, 1] + 2 * E[:, 2]).max())
