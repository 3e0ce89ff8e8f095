"""Exact intersection of two sites: do two conics, circles or points have a common real point?

The test is exact over Q (thesis §4.4 conics with rational coefficients): a resultant in x after a
shear, its real roots counted and the sign of a discriminant decided at them by Sturm–Tarski
queries (Basu, Pollack & Roy, *Algorithms in Real Algebraic Geometry*, 2nd ed., Thm 2.73), with
python-flint's ``fmpq_poly``.  The diagram's input checks refuse intersecting sites with it, and
the locator names a pair of meeting sites when a vertex cannot be certified.
"""
from __future__ import annotations

from fractions import Fraction

from flint import fmpq, fmpq_poly

from .circle import Circle
from .conic import Conic

__all__ = ["exact_coefficients", "conic_value", "circles_meet", "sites_intersect"]


def exact_coefficients(site):
    """Exact rational coefficients (a, b, c, d, e, f) of a conic or circle site, or ('point', x, y)."""
    if isinstance(site, Circle):
        cx = Fraction(int(site.cx.p), int(site.cx.q))
        cy = Fraction(int(site.cy.p), int(site.cy.q))
        r2 = Fraction(int(site.r2.p), int(site.r2.q))
        if r2 == 0:
            return ("point", cx, cy)
        return (Fraction(1), Fraction(0), Fraction(1), -2 * cx, -2 * cy, cx * cx + cy * cy - r2)
    if isinstance(site, Conic):
        return tuple(site.coefficients)
    raise TypeError(f"not a site: {site!r}")


def conic_value(co, x, y):
    """a·x² + b·xy + c·y² + d·x + e·y + f for co = (a, b, c, d, e, f) (exact on Fractions)."""
    a, b, c, d, e, f = co
    return a * x * x + b * x * y + c * y * y + d * x + e * y + f


def _shear(co, k):
    """Coefficients of the conic after the substitution x -> x + k y (rational k)."""
    a, b, c, d, e, f = co
    return (a, b + 2 * a * k, c + b * k + a * k * k, d, e + d * k, f)


def _tarski_query(p, q=None) -> int:
    """Sturm–Tarski query TaQ(q, p) = #{x real: p(x) = 0, q(x) > 0} − #{x real: p(x) = 0, q(x) < 0}
    for a non-zero fmpq_poly p (q = 1: the number of distinct real roots of p), from the signed
    remainder sequence of p and p'·q (Basu, Pollack & Roy, *Algorithms in Real Algebraic
    Geometry*, Thm 2.73).  Exact."""
    if p.degree() <= 0:
        return 0
    second = p.derivative() if q is None else p.derivative() * q
    chain = [p]
    if not second.is_zero():
        chain.append(second)
        while True:
            r = -(chain[-2] % chain[-1])
            if r.is_zero():
                break
            chain.append(r)

    def variations(at_minus):
        signs = []
        for f in chain:
            lc = f.leading_coefficient()
            sg = 1 if lc > 0 else -1
            if at_minus and f.degree() % 2 == 1:
                sg = -sg
            signs.append(sg)
        return sum(1 for u, v in zip(signs, signs[1:]) if u != v)

    return variations(True) - variations(False)


def circles_meet(ca, cb) -> bool:
    """Do the circles ca = (x1, y1, r1), cb = (x2, y2, r2) (centre, squared radius r = ρ² ≥ 0; r = 0
    a point) have a common point?  They meet iff (ρ1 − ρ2)² ≤ |c1 − c2|² ≤ (ρ1 + ρ2)², decided
    exactly on the r_i (any exact number type: Fraction, fmpq) by squaring once:
    |D − r1 − r2| ≤ 2 ρ1 ρ2 ⇔ (D − r1 − r2)² ≤ 4 r1 r2."""
    (x1, y1, r1), (x2, y2, r2) = ca, cb
    D = (x1 - x2) ** 2 + (y1 - y2) ** 2
    t = D - r1 - r2
    return t * t <= 4 * r1 * r2


def _circle_data(co):
    a, b, c, d, e, f = co
    if a == c and b == 0:
        cx, cy = -d / (2 * a), -e / (2 * a)
        return (cx, cy, cx * cx + cy * cy - f / a)
    return None


def sites_intersect(A, B) -> bool:
    """Exactly decide whether two sites (Conic, Circle or Point) have a common real point.

    Two conics: after an exact shear x → x + k y making both y²-coefficients non-zero (a real
    linear bijection: real intersection points correspond), write f_A = a2 y² + a1 y + a0,
    f_B = b2 y² + b1 y + b0 with a2, b2 non-zero constants.  The resultant
    R(x) = (a2 b0 − a0 b2)² − (a2 b1 − a1 b2)(a1 b0 − a0 b1) has the x-coordinates of all complex
    intersections as roots and no others (constant leading coefficients).  At a real root x of R
    the first subresultant S1 = b2 f_A − a2 f_B = s1(x) y + s0(x) gives the common root
    y = −s0/s1, real, when s1(x) ≠ 0; if s1(x) = 0 then f_A(x, ·) and f_B(x, ·) are
    proportional and have a real common root iff their discriminant is ≥ 0.  Real roots are
    counted, and the sign of the discriminant at them decided, with Sturm–Tarski queries over Q
    (python-flint ``fmpq_poly``).  Two circles are compared directly.  Identical conics
    intersect.
    """
    ca, cb = exact_coefficients(A), exact_coefficients(B)
    if ca[0] == "point" and cb[0] == "point":
        return ca[1:] == cb[1:]
    if ca[0] == "point":
        return conic_value(cb, ca[1], ca[2]) == 0
    if cb[0] == "point":
        return conic_value(ca, cb[1], cb[2]) == 0
    ra, rb = _circle_data(ca), _circle_data(cb)
    if ra is not None and rb is not None:
        return circles_meet(ra, rb)
    for k in (Fraction(0), Fraction(1), Fraction(-1), Fraction(1, 2), Fraction(2), Fraction(-3, 7)):
        sa, sb = _shear(ca, k), _shear(cb, k)
        if sa[2] != 0 and sb[2] != 0:
            break

    def P(*cs):
        return fmpq_poly([fmpq(c.numerator, c.denominator) for c in cs])

    def split(co):
        a, b, c, d, e, f = co
        return P(c), P(e, b), P(f, d, a)       # coefficients of y², y, 1 as polynomials in x

    a2, a1, a0 = split(sa)
    b2, b1, b0 = split(sb)
    s1 = b2 * a1 - a2 * b1
    s0 = b2 * a0 - a2 * b0
    if s1.is_zero() and s0.is_zero():
        return True  # proportional equations: the same conic
    R = (a2 * b0 - a0 * b2) ** 2 - (a2 * b1 - a1 * b2) * (a1 * b0 - a0 * b1)
    if R.is_zero():
        return True
    if R.degree() <= 0:
        return False
    Rs = R / R.gcd(R.derivative()) if R.derivative().degree() >= 0 else R
    G = Rs.gcd(s1) if not s1.is_zero() else Rs
    free = Rs / G if G.degree() > 0 else Rs
    if free.degree() > 0 and _tarski_query(free) > 0:
        return True
    if G.degree() <= 0 or _tarski_query(G) == 0:
        return False
    # proportional rows at the real roots of G: a common real y iff disc(x) ≥ 0 there
    disc = a1 * a1 - 4 * a2 * a0
    h = G.gcd(disc) if not disc.is_zero() else G
    if h.degree() > 0 and _tarski_query(h) > 0:
        return True                       # disc = 0 at a real root: a real double root y
    Gr = G / h if h.degree() > 0 else G
    n = _tarski_query(Gr)
    return n > 0 and (n + _tarski_query(Gr, disc)) // 2 > 0
