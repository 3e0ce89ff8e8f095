"""Formal conic families (thesis §4.4) and exact rational samples on them.

Each :class:`ConicFamily` is a polynomial ``f(x, y; params)`` with integer coefficients in the
parameters, in the canonical frame used by the thesis:

============================  =====================  ===============================  ==========
family                        equation f             parameters                       Table 4.1
============================  =====================  ===============================  ==========
``circle``                    x² + y² − ρ²           ρ (``rho``)                      4
``ellipse`` (and hyperbola)   x² + c·y² + e          c (c>0 ellipse, c<0 hyperbola), e 8
``parabola``                  y² − 2·p·x             p                                6
``lines_parallel``            y² − h²                h  (lines y = ±h)                4
``lines_intersecting``        y² − t²·x²             t  (lines y = ±t·x)              4
``generic``                   a x²+b xy+c y²+d x+e y+f a, b, c, d, e, f              8
============================  =====================  ===============================  ==========

``sample(rng)`` returns exact rational parameter values together with a rational point of the
curve (rational parametrisations), which is what the exact offset verification of §4 needs:
for a point p of the conic, its normal vector n = ∇f(p) and any rational k, the point
q = p + k·n lies on the generalised offset with R = k²·|n|² (R is the *squared* offset distance).
"""
from __future__ import annotations

import random
from dataclasses import dataclass
from fractions import Fraction
from typing import Callable

import flint

Q = Fraction


@dataclass(frozen=True)
class ConicFamily:
    """A formal family of conics ``f(x, y; params) = 0`` (thesis §4.4)."""

    name: str
    equation: str                      # human-readable, with the parameter names
    params: tuple[str, ...]
    offset_degree: int                 # Table 4.1 (degree in u, v of the generalised offset)
    build: Callable[..., object]       # (x, y, *params) -> polynomial (any ring)
    _sampler: Callable[[random.Random], tuple[dict[str, Fraction], tuple[Fraction, Fraction]]]

    @property
    def reducible_offset(self) -> bool:
        """A pair of lines has one offset component per line (Prop. 4.3.5)."""
        return self.name.startswith("lines_")

    def polynomial(self, ctx: flint.fmpz_mpoly_ctx):
        """f as an fmpz_mpoly in ``ctx`` (which must contain x, y and the parameters)."""
        g = dict(zip(ctx.names(), ctx.gens()))
        return self.build(g["x"], g["y"], *(g[p] for p in self.params))

    def sample(self, rng: random.Random) -> tuple[dict[str, Fraction], tuple[Fraction, Fraction]]:
        """Random exact parameters and an exact rational point on the (real, non-degenerate) curve."""
        return self._sampler(rng)

    def value(self, params: dict[str, Fraction], x: Fraction, y: Fraction) -> Fraction:
        return self.build(x, y, *(params[p] for p in self.params))

    def gradient(self, params: dict[str, Fraction], x: Fraction, y: Fraction) -> tuple[Fraction, Fraction]:
        """∇f at (x, y), exactly (central differences are exact for quadratics)."""
        h = Q(1)
        fx = (self.value(params, x + h, y) - self.value(params, x - h, y)) / (2 * h)
        fy = (self.value(params, x, y + h) - self.value(params, x, y - h)) / (2 * h)
        return fx, fy


def _rq(rng: random.Random, lo: int = -9, hi: int = 9, nonzero: bool = True) -> Fraction:
    while True:
        v = Q(rng.randint(lo, hi), rng.randint(1, 7))
        if v != 0 or not nonzero:
            return v


def _circle_point(rho: Fraction, s: Fraction) -> tuple[Fraction, Fraction]:
    # rational parametrisation of x² + y² = rho²
    return rho * (1 - s * s) / (1 + s * s), rho * 2 * s / (1 + s * s)


def _sample_circle(rng):
    rho = abs(_rq(rng))
    return {"rho": rho}, _circle_point(rho, _rq(rng))


def _sample_ellipse(rng):
    # x² + c y² + e with a chosen rational point; c ≠ 1 so that it is no circle, c ≠ 0
    while True:
        c = _rq(rng)
        x0, y0 = _rq(rng), _rq(rng)
        e = -(x0 * x0 + c * y0 * y0)
        if c != 1 and e != 0:
            return {"c": c, "e": e}, (x0, y0)


def _sample_parabola(rng):
    p = _rq(rng)
    y0 = _rq(rng, nonzero=False)
    return {"p": p}, (y0 * y0 / (2 * p), y0)


def _sample_lines_parallel(rng):
    h = _rq(rng)
    return {"h": h}, (_rq(rng, nonzero=False), h * rng.choice((-1, 1)))


def _sample_lines_intersecting(rng):
    t = _rq(rng)
    x0 = _rq(rng)
    return {"t": t}, (x0, t * x0 * rng.choice((-1, 1)))


def _sample_generic(rng):
    while True:
        a, b, c, d, e = (_rq(rng, nonzero=False) for _ in range(5))
        x0, y0 = _rq(rng, nonzero=False), _rq(rng, nonzero=False)
        f = -(a * x0 * x0 + b * x0 * y0 + c * y0 * y0 + d * x0 + e * y0)
        # proper conic: non-zero 3x3 determinant, and a smooth point (∇f(p) ≠ 0)
        det = (a * (c * f - e * e / 4) - b / 2 * (b / 2 * f - e * d / 4) + d / 2 * (b / 2 * e / 2 - c * d / 2))
        grad = (2 * a * x0 + b * y0 + d, b * x0 + 2 * c * y0 + e)
        if det != 0 and a != 0 and b != 0 and grad != (0, 0):
            return dict(zip("abcdef", (a, b, c, d, e, f))), (x0, y0)


FAMILIES: dict[str, ConicFamily] = {
    fam.name: fam
    for fam in (
        ConicFamily("circle", "x^2 + y^2 - rho^2", ("rho",), 4,
                    lambda x, y, rho: x**2 + y**2 - rho**2, _sample_circle),
        ConicFamily("ellipse", "x^2 + c*y^2 + e", ("c", "e"), 8,
                    lambda x, y, c, e: x**2 + c * y**2 + e, _sample_ellipse),
        ConicFamily("parabola", "y^2 - 2*p*x", ("p",), 6,
                    lambda x, y, p: y**2 - 2 * p * x, _sample_parabola),
        ConicFamily("lines_parallel", "y^2 - h^2", ("h",), 4,
                    lambda x, y, h: y**2 - h**2, _sample_lines_parallel),
        ConicFamily("lines_intersecting", "y^2 - t^2*x^2", ("t",), 4,
                    lambda x, y, t: y**2 - t**2 * x**2, _sample_lines_intersecting),
        ConicFamily("generic", "a*x^2 + b*x*y + c*y^2 + d*x + e*y + f", tuple("abcdef"), 8,
                    lambda x, y, a, b, c, d, e, f: a * x**2 + b * x * y + c * y**2 + d * x + e * y + f,
                    _sample_generic),
    )
}
