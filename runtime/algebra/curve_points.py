"""Points of a plane algebraic curve and of its generalised offset over number fields (thesis §4.1).

The curve is parsed into a primitive, square-free integer polynomial f(x, y).  Exact points are
taken over ℚ(α): a rational x₀, an irreducible factor p(y) of f(x₀, y) over ℚ, α a root of p,
P = (x₀, α); then q = P + k·∇f(P), R = k²·|∇f(P)|² is a point of the generalised offset
(Definition 4.1.3) with coordinates in ℚ(α) = ℚ[α]/(p).  :mod:`runtime.algebra.algebraic_offset`
selects the offset's factors by their exact vanishing at such points.
"""
from __future__ import annotations

import math
import random
from dataclasses import dataclass
from fractions import Fraction

import flint

__all__ = ["OffsetPoint", "curve_at_abscissa", "curve_points", "evaluate_at_point", "leading_coefficient",
           "offset_point", "parse_curve"]

_CURVE_CTX = flint.fmpz_mpoly_ctx.get(("x", "y"), "lex")

# ------------------------------------------------------------------------------------------
# input
# ------------------------------------------------------------------------------------------

def parse_curve(f) -> flint.fmpz_mpoly:
    """The curve polynomial as a primitive ``fmpz_mpoly`` in (x, y) with positive leading term.

    ``f`` is a string in x and y ("y^2 - x^2 - x^3", rational coefficients such as "3/5*x"
    allowed), a SymPy expression or Poly in x and y, or a python-flint ``fmpz_mpoly`` /
    ``fmpq_mpoly`` in two variables (named x and y, or taken in the order of their context).
    Raises ``ValueError`` for anything else, for constants and for non-square-free polynomials.
    """
    terms = _terms_of(f)
    terms = {k: Fraction(v) for k, v in terms.items() if v != 0}
    if not terms or all(k == (0, 0) for k in terms):
        raise ValueError("curve polynomial is constant: no curve")
    den = 1
    for c in terms.values():
        den = den * c.denominator // math.gcd(den, c.denominator)
    poly = _CURVE_CTX.from_dict({k: int(c * den) for k, c in terms.items()})
    poly = poly.primitive()[1]
    if leading_coefficient(poly) < 0:
        poly = -poly
    _, facs = poly.factor()
    if any(int(m) > 1 for _, m in facs):
        raise ValueError(f"curve polynomial {poly} is not square-free (thesis Theorem 4.2.18 "
                         "assumes f square-free); pass its square-free part")
    return poly


def leading_coefficient(p) -> int:
    return int(sorted(p.to_dict().items(), reverse=True)[0][1])


def _terms_of(f) -> dict[tuple[int, int], object]:
    if isinstance(f, (flint.fmpz_mpoly, flint.fmpq_mpoly)):
        names = f.context().names()
        if len(names) != 2:
            raise ValueError(f"curve polynomial must have two variables, got {names}")
        swap = tuple(names) == ("y", "x")
        out = {}
        for k, c in f.to_dict().items():
            k = (int(k[1]), int(k[0])) if swap else (int(k[0]), int(k[1]))
            out[k] = Fraction(int(c.p), int(c.q)) if isinstance(c, flint.fmpq) else int(c)
        return out
    import sympy

    x, y = sympy.symbols("x y")
    if isinstance(f, str):
        text = f.replace("^", "**").strip()
        if "=" in text:
            lhs, _, rhs = text.partition("=")
            text = f"({lhs}) - ({rhs})" if rhs.strip() not in ("", "0") else lhs
        try:
            expr = sympy.sympify(text, locals={"x": x, "y": y}, rational=True)
        except (sympy.SympifyError, SyntaxError, TypeError) as exc:
            raise ValueError(f"cannot parse curve {f!r}: {exc}") from None
    elif isinstance(f, sympy.Poly):
        expr = f.as_expr()
    elif isinstance(f, sympy.Basic):
        expr = f
    else:
        raise ValueError(f"curve must be a string, a SymPy or a python-flint polynomial, got {type(f).__name__}")
    extra = expr.free_symbols - {x, y}
    if extra:
        raise ValueError(f"curve polynomial has symbols other than x, y: {sorted(map(str, extra))}")
    try:
        poly = sympy.Poly(sympy.nsimplify(expr, rational=True) if expr.has(sympy.Float) else expr,
                          x, y, domain="QQ")
    except (sympy.PolynomialError, sympy.polys.polyerrors.CoercionFailed) as exc:
        raise ValueError(f"curve is not a polynomial in x, y with rational coefficients: {exc}") from None
    return {tuple(int(e) for e in k): Fraction(int(c.numerator), int(c.denominator))
            for k, c in poly.terms()}


# ------------------------------------------------------------------------------------------
# exact offset points over number fields
# ------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class OffsetPoint:
    """A point (u, v, R) of the generalised offset with coordinates in ℚ(α) = ℚ[α]/(modulus).

    Built from the curve point (x0, α) (or (α, y0) when ``swapped``) and the rational step k
    along the gradient.  ``u``, ``v``, ``R`` are ``fmpq_poly`` in α reduced modulo ``modulus``.
    """

    x0: Fraction
    k: Fraction
    modulus: flint.fmpq_poly
    u: flint.fmpq_poly
    v: flint.fmpq_poly
    R: flint.fmpq_poly
    swapped: bool = False

    def describe(self) -> str:
        a = "alpha"
        pt = f"({a}, {self.x0})" if self.swapped else f"({self.x0}, {a})"
        return f"p = {pt}, {a} root of {self.modulus.str(var='a')}, q = p + ({self.k})*grad f(p)"


def curve_at_abscissa(curve, x0: Fraction, swapped: bool):
    """f(x0, y) (or f(x, y0)) as an fmpq_poly."""
    coeffs: dict[int, Fraction] = {}
    for (i, j), c in curve.to_dict().items():
        i, j = int(i), int(j)
        e, other = (i, j) if swapped else (j, i)
        coeffs[e] = coeffs.get(e, Fraction(0)) + int(c) * x0 ** other
    deg = max(coeffs) if coeffs else 0
    return flint.fmpq_poly([flint.fmpq(coeffs.get(e, Fraction(0)).numerator, coeffs.get(e, Fraction(0)).denominator)
                            for e in range(deg + 1)])


def _eval_xy(poly, x, y, mod):
    """poly(x, y) for x, y fmpq_poly in α, reduced modulo mod (poly an fmpz_mpoly in x, y)."""
    total = flint.fmpq_poly(0)
    for (i, j), c in poly.to_dict().items():
        total += int(c) * (x ** int(i)) * (y ** int(j))
    return total % mod


def curve_points(curve, count: int, rng: random.Random, *, max_tries: int = 200):
    """``count`` generic points of V(curve) over number fields: list of (x, y, modulus, swapped).

    x = x0 rational, y = α a root of an irreducible factor of curve(x0, y) over ℚ (or the roles
    of x and y swapped when the component does not depend on y), the gradient not zero.
    """
    curve = parse_curve(curve) if not isinstance(curve, flint.fmpz_mpoly) else curve
    swapped = curve.degrees()[1] == 0
    fx, fy = curve.derivative(0), curve.derivative(1)
    out = []
    for _ in range(max_tries):
        if len(out) >= count:
            break
        x0 = Fraction(rng.randint(-40, 40), rng.randint(1, 12))
        p = curve_at_abscissa(curve, x0, swapped)
        if p.degree() < 1:
            continue
        _, facs = p.factor()
        facs = [g for g, _ in facs if g.degree() >= 1]
        if not facs:
            continue
        g = rng.choice(facs)
        g = g / g.leading_coefficient()
        alpha = flint.fmpq_poly([0, 1]) % g
        xq = flint.fmpq_poly([flint.fmpq(x0.numerator, x0.denominator)])
        X, Y = (alpha, xq) if swapped else (xq, alpha)
        gx, gy = _eval_xy(fx, X, Y, g), _eval_xy(fy, X, Y, g)
        if gx.is_zero() and gy.is_zero():
            continue                       # a singular point: not a generic point
        out.append((x0, X, Y, gx, gy, g, swapped))
    if len(out) < count:
        raise ValueError(f"could not find {count} generic points on the curve {curve}")
    return out


def offset_point(curve, point, k: Fraction) -> OffsetPoint:
    """The exact offset point q = p + k·∇f(p), R = k²·|∇f(p)|² over the point's number field."""
    x0, X, Y, gx, gy, g, swapped = point
    kq = flint.fmpq(k.numerator, k.denominator)
    u = (X + kq * gx) % g
    v = (Y + kq * gy) % g
    R = (kq * kq * (gx * gx + gy * gy)) % g
    return OffsetPoint(x0, k, g, u, v, R, swapped)


def evaluate_at_point(poly, pt: OffsetPoint) -> flint.fmpq_poly:
    """poly(u, v, R) at the exact point ``pt`` (an element of ℚ[α]/(modulus), as fmpq_poly)."""
    mod = pt.modulus
    cache: dict[tuple[int, int], flint.fmpq_poly] = {}

    def power(which: int, e: int):
        key = (which, e)
        if key not in cache:
            base = (pt.u, pt.v, pt.R)[which]
            cache[key] = flint.fmpq_poly(1) if e == 0 else (power(which, e - 1) * base) % mod
        return cache[key]

    total = flint.fmpq_poly(0)
    for (i, j, l), c in poly.to_dict().items():
        total += int(c) * ((power(0, int(i)) * power(1, int(j))) % mod * power(2, int(l)))
        total %= mod
    return total
