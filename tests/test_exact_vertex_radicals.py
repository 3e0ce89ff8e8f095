"""The exact vertex of four or more sites (:func:`runtime.segments.certificate_exact.exact_vertex`)
when sympy's closed form holds a radical whose sign balls cannot decide.

Sites (touching types of :mod:`runtime.segments.certificate_vertices`): the point (0, 0), the
circle about (4, 0) of radius 1 touched from outside, the line X + Y + c = 0 touched on the side
σ = +1 (X + Y + c = R√2), and the point (0, 9).  The first three give, with
c = −4 − p/q where p² − 2q² = 1 (p = 768398401, q = 543339720, a solution of Pell's equation):

* point − circle: 8X − 16 + 1 + 2R = 0, so X = (15 − 2R)/8;
* the line: Y = R√2 − c − X;
* the point: X² + Y² = R², a quadratic in R over Q(√2) whose discriminant is
  (15/4)·c·(c + 4 + √2) = (15/4)·c·(√2 − p/q), of the order of 10⁻¹⁷.

Sympy writes the roots with the radical √(p − q√2), p − q√2 = 1/(p + q√2) ≈ 6.5·10⁻¹⁰, which a
53-bit ball of p − q√2 (radius ~10⁻⁷) cannot prove non-negative: the enclosure of that solution
is refused (ValueError) and the next one tried.  Both roots have R ≈ −2.96 (mpmath below): no
circle of positive radius touches the three sites as stated, so the reported vertex (1, 1) of
radius 1 is refused with a message, never an exception.
"""
from __future__ import annotations

from fractions import Fraction as F
from types import SimpleNamespace

import mpmath as mp

from curvedvoronoi.runtime.segments.certificate_exact import exact_vertex

P, Q = 768398401, 543339720
C = -4 - F(P, Q)
TERMS = [("pt", 0, 0), ("arc", 4, 0, 1, 1), ("ln", 1, 1, C, 1), ("pt", 0, 9)]


def _roots_R():
    """The two roots R of the quadratic of the module docstring, in mpmath (60 digits)."""
    with mp.workdps(60):
        c = mp.mpf(C.numerator) / C.denominator
        s2 = mp.sqrt(2)

        def g(R):                                   # X² + Y² − R² on the two linear equations
            X = (15 - 2 * R) / 8
            Y = R * s2 - c - X
            return X * X + Y * Y - R * R
        # a quadratic: its coefficients from three values
        g0, g1, gm = g(mp.mpf(0)), g(mp.mpf(1)), g(mp.mpf(-1))
        A, B, C0 = (g1 + gm) / 2 - g0, (g1 - gm) / 2, g0
        disc = B * B - 4 * A * C0
        return disc, [(-B + e * mp.sqrt(disc)) / (2 * A) for e in (1, -1)]


def test_the_premises_pell_and_the_tiny_discriminant():
    assert P * P - 2 * Q * Q == 1
    disc, roots = _roots_R()
    assert 0 < disc < mp.mpf("1e-15")
    with mp.workdps(60):
        assert mp.mpf(P) - Q * mp.sqrt(2) < mp.mpf("1e-9")
    assert all(-3 < r < -2.9 for r in roots)


def test_a_solution_whose_radical_balls_cannot_enclose_is_skipped_not_a_crash():
    v = SimpleNamespace(x=1.0, y=1.0, radius=1.0)
    out = exact_vertex(TERMS, v, (0, 1, 2, 3), 1e-10)
    assert isinstance(out, str) and "no exact common point" in out
