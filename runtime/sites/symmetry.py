"""A common axis of symmetry of conics, and the similarity that takes it to the u-axis.

Drawings often have one: ellipses centred on a line with their axes along or across it, a parabola
whose axis is that line, circles centred on it.  The reflection in such an axis maps every site to
itself, hence maps each generalised offset to itself (the offset of a conic is defined by
distances to it, thesis ch. 4 and App. B, so it is invariant under the conic's isometries).  In
coordinates (u, v) where the axis is v = 0, every offset is therefore a polynomial in u, v² and R,
and the triple offset system (thesis §5.3) is a system in (u, V = v², R) of half the degree in v:
:func:`runtime.solve.exact.solve_exact` hands that quotient to msolve.

Everything is exact.  The axis passes through the sites' centres (ellipse, hyperbola, circle:
rational, the solution of a 2 × 2 linear system) and parabola vertices (rational when the
parabola's canonical frame is); it is the line through two distinct such points, and each site is
checked to be symmetric about it exactly (:func:`common_axis`).  The map

    x = x0 + dx·u − dy·v,    y = y0 + dy·u + dx·v

is a similarity of ratio k = √(dx² + dy²): lengths in the (x, y) plane are k times those in the
(u, v) plane, so the squared distances R scale by k² = dx² + dy², a rational number (no square
root is needed).  With (dx, dy) the primitive integer direction of the axis, divided by its
length when that length is an integer (Pythagorean directions, k = 1: a rotation), the
coefficients stay small.
"""
from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from math import gcd, isqrt, lcm

from .conic import Conic

__all__ = ["AxisFrame", "centre", "common_axis", "in_axis_frame"]


@dataclass(frozen=True)
class AxisFrame:
    """x = x0 + dx·u − dy·v, y = y0 + dy·u + dx·v (module docstring): the axis is v = 0."""

    x0: Fraction
    y0: Fraction
    dx: Fraction
    dy: Fraction

    @property
    def k2(self) -> Fraction:
        """The square of the similarity ratio: R in (x, y) = k2 · R in (u, v)."""
        return self.dx * self.dx + self.dy * self.dy


def centre(conic: Conic) -> tuple[Fraction, Fraction] | None:
    """The centre of an ellipse, hyperbola or circle (exact), or the vertex of a parabola when its
    canonical frame is rational (else None)."""
    a, b, c, d, e, _ = conic.coefficients
    if conic.kind == "parabola":
        fr = conic.exact_frame
        return None if fr is None else (Fraction(fr.tx), Fraction(fr.ty))
    det = 4 * a * c - b * b
    return (b * e - 2 * c * d) / det, (b * d - 2 * a * e) / det


def in_axis_frame(conic: Conic, frame: AxisFrame) -> Conic:
    """The conic in the (u, v) coordinates of ``frame`` (exact substitution)."""
    a, b, c, d, e, f = conic.coefficients
    # x and y as affine forms (constant, u, v)
    X = (frame.x0, frame.dx, -frame.dy)
    Y = (frame.y0, frame.dy, frame.dx)

    def mul(p, q):
        # product of two affine forms as {(i, j): coefficient of u^i v^j}
        out: dict = {}
        for (m, s) in zip(((0, 0), (1, 0), (0, 1)), p):
            for (n, t) in zip(((0, 0), (1, 0), (0, 1)), q):
                key = (m[0] + n[0], m[1] + n[1])
                out[key] = out.get(key, 0) + s * t
        return out

    poly: dict = {(0, 0): f}
    for coef, form in ((a, mul(X, X)), (b, mul(X, Y)), (c, mul(Y, Y))):
        for key, v in form.items():
            poly[key] = poly.get(key, 0) + coef * v
    for coef, lin in ((d, X), (e, Y)):
        for key, v in zip(((0, 0), (1, 0), (0, 1)), lin):
            poly[key] = poly.get(key, 0) + coef * v
    g = poly.get
    return Conic.from_coefficients(g((2, 0), 0), g((1, 1), 0), g((0, 2), 0), g((1, 0), 0), g((0, 1), 0), g((0, 0), 0))


def _direction(dx: Fraction, dy: Fraction) -> tuple[Fraction, Fraction]:
    """The primitive integer direction of (dx, dy), divided by its length when that is an integer."""
    q = lcm(dx.denominator, dy.denominator)
    ix, iy = int(dx * q), int(dy * q)
    g = gcd(ix, iy)
    ix, iy = ix // g, iy // g
    n2 = ix * ix + iy * iy
    r = isqrt(n2)
    if r * r == n2:
        return Fraction(ix, r), Fraction(iy, r)
    return Fraction(ix), Fraction(iy)


def common_axis(conics) -> AxisFrame | None:
    """An :class:`AxisFrame` whose axis v = 0 is a line of symmetry of every conic, or None.

    The line is the one through the first two distinct centres (:func:`centre`); every conic is
    symmetric about it iff in its (u, v) form the coefficients of u·v and v vanish (exact).  The
    frame's origin is the mean of the centres on the line."""
    pts = []
    for c in conics:
        p = centre(c)
        if p is not None and p not in pts:
            pts.append(p)
    if len(pts) < 2:
        return None
    (px, py), (qx, qy) = pts[0], pts[1]
    dx, dy = _direction(qx - px, qy - py)
    if any((x - px) * dy != (y - py) * dx for x, y in pts[2:]):
        return None                                   # the centres are not collinear
    n = len(pts)
    frame = AxisFrame(sum(p[0] for p in pts) / n, sum(p[1] for p in pts) / n, dx, dy)
    for c in conics:
        co = in_axis_frame(c, frame).coefficients
        if co[1] != 0 or co[4] != 0:
            return None
    return frame
