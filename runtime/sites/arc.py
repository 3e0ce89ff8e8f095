"""Circular arcs with exact rational data (thesis §2.2: pieces of conics as semi-algebraic sites).

An :class:`Arc` is the closed piece of the circle of rational centre c and rational radius ρ
running **counter-clockwise** from the rational point a to the rational point b of that circle
(DXF's ARC convention).  Keeping the endpoints rational keeps every predicate of the diagram in
rational arithmetic and quadratic extensions: rational points are dense on a rational circle
(c + ρ·((1 − t²)/(1 + t²), 2t/(1 + t²)), t = tan(θ/2) rational), so an angle θ given in degrees is
realised by the rational t nearest to tan(θ/2) in floating point (a relative error of about
10⁻¹⁶; multiples of 90° exactly), and a DXF bulge b = tan(θ/4) between rational vertices gives
a rational centre and radius.

In a Voronoi diagram an arc is split, like a segment, into its endpoints (point sites) and its
open interior (:mod:`runtime.segments.elementary`); a circle touches a circular arc at most once,
so the interior is a harmless site (Alt–Schwarzkopf, thesis §2.2) without further cuts.

A whole circle of rational radius enters a diagram of pieces as its two halves
(:func:`circle_halves`): two arcs meeting at smooth joints, the union of which is the circle (the
same distance function); inside the disc their bisector is the diameter through the joints.

Elliptic arcs (DXF's ELLIPSE) are :class:`runtime.sites.elliptic_arc.EllipticArc` sites, made by
:meth:`Arc.elliptic`.

Public API: :class:`Arc`, :func:`exact_sqrt`, :func:`circle_halves`.
"""
from __future__ import annotations

import math
from fractions import Fraction

from ..result import InvalidConicError
from .elliptic_arc import EllipticArc
from .rationals import to_fraction
from .segment import as_point_pair
from .kinds import KeyedSite

__all__ = ["Arc", "exact_sqrt", "circle_halves"]


def _rational_direction(deg: Fraction | float) -> tuple[Fraction, Fraction]:
    """(cos θ, sin θ) for θ in degrees: exact at multiples of 90°, else the rational point of
    the unit circle at t = tan(θ/2) taken exactly from its float value (t for |θ| ≤ 90° after
    reduction, the complementary formula near 180°)."""
    d = Fraction(deg) % 360
    exact = {Fraction(0): (Fraction(1), Fraction(0)), Fraction(90): (Fraction(0), Fraction(1)),
             Fraction(180): (Fraction(-1), Fraction(0)), Fraction(270): (Fraction(0), Fraction(-1))}
    if d in exact:
        return exact[d]
    theta = math.radians(float(d))
    if d <= 90 or d >= 270:
        t = Fraction(math.tan(theta / 2))
        return (1 - t * t) / (1 + t * t), 2 * t / (1 + t * t)
    # near 180°: rotate by 180° (t' = tan((θ − 180°)/2)) and negate
    t = Fraction(math.tan((theta - math.pi) / 2))
    return -(1 - t * t) / (1 + t * t), -2 * t / (1 + t * t)


class Arc(KeyedSite):
    """The counter-clockwise arc of the circle (``centre``, ``radius``) from ``start`` to
    ``end`` (rational points of the circle, distinct).

    >>> from curvedvoronoi import Arc
    >>> a = Arc.circular((0, 0), 2, 0, 90)
    >>> a
    Arc(centre=(0, 0), radius=2, from (2, 0) to (0, 2))
    >>> a.contains_direction((1, 1)), a.contains_direction((-1, 1))
    (True, False)
    """

    __slots__ = ("c", "rho", "a", "b", "label")
    KIND = "arc"

    def __init__(self, centre, radius, start, end, label: str | None = None):
        self.c = as_point_pair(centre, "arc centre")
        self.rho = to_fraction(radius, "arc radius")
        if not self.rho > 0:
            raise InvalidConicError(f"arc radius must be positive, got {self.rho}")
        self.a = as_point_pair(start, "arc start")
        self.b = as_point_pair(end, "arc end")
        for name, p in (("start", self.a), ("end", self.b)):
            if (p[0] - self.c[0]) ** 2 + (p[1] - self.c[1]) ** 2 != self.rho ** 2:
                raise InvalidConicError(f"arc {name} ({p[0]}, {p[1]}) is not on the circle of centre "
                                        f"({self.c[0]}, {self.c[1]}) and radius {self.rho} (exactly)")
        if self.a == self.b:
            raise InvalidConicError("an arc needs two distinct endpoints (a whole circle is a Circle site)")
        self.label = label

    # ------------------------------------------------------------------ constructors
    @classmethod
    def circular(cls, centre, radius, start_deg, end_deg, label: str | None = None) -> "Arc":
        """DXF's ARC: counter-clockwise from ``start_deg`` to ``end_deg`` (degrees)."""
        c = as_point_pair(centre, "arc centre")
        rho = to_fraction(radius, "arc radius")
        if not rho > 0:
            raise InvalidConicError(f"arc radius must be positive, got {rho}")
        pts = []
        for deg in (start_deg, end_deg):
            ux, uy = _rational_direction(to_fraction(deg, "arc angle"))
            pts.append((c[0] + rho * ux, c[1] + rho * uy))
        return cls(c, rho, pts[0], pts[1], label)

    @classmethod
    def from_bulge(cls, p, q, bulge, label: str | None = None) -> "Arc":
        """The arc from p to q of a DXF polyline vertex with ``bulge`` = tan(θ/4) (θ the included
        angle; positive: counter-clockwise from p to q)."""
        p = as_point_pair(p, "bulge start")
        q = as_point_pair(q, "bulge end")
        b = to_fraction(bulge, "bulge")
        if b == 0 or p == q:
            raise InvalidConicError("a bulge arc needs a nonzero bulge and two distinct points")
        # centre = midpoint + ((1 - b²) / (4 b)) · perp(q - p), radius = |q - p| (1 + b²) / (4 |b|)
        mx, my = (p[0] + q[0]) / 2, (p[1] + q[1]) / 2
        dx, dy = q[0] - p[0], q[1] - p[1]
        k = (1 - b * b) / (4 * b)
        c = (mx - k * dy, my + k * dx)
        r2 = (p[0] - c[0]) ** 2 + (p[1] - c[1]) ** 2
        rho = exact_sqrt(r2)
        if rho is None:
            raise InvalidConicError(f"bulge {b}: the radius √{r2} of the arc is irrational")
        return cls(c, rho, p, q, label) if b > 0 else cls(c, rho, q, p, label)

    @staticmethod
    def elliptic(centre, major_axis, ratio, start_param, end_param, label: str | None = None):
        """DXF's ELLIPSE arc: the :class:`runtime.sites.elliptic_arc.EllipticArc` of the ellipse of
        ``centre``, major-axis vector ``major_axis`` and ``ratio`` = minor/major (0 < ratio < 1),
        counter-clockwise from ``start_param`` to ``end_param`` (radians; ends rational, see
        :func:`runtime.sites.elliptic_arc.rational_unit`).  A whole ellipse (end − start ≥ 2π)
        is refused here: :meth:`EllipticArc.from_dxf` gives its two halves."""
        out = EllipticArc.from_dxf(centre, major_axis, ratio, start_param, end_param, label)
        if len(out) != 1:
            raise InvalidConicError("Arc.elliptic: a whole ellipse is not an arc (use EllipticArc.from_dxf for its "
                                    "two halves, or a Conic.ellipse site)")
        return out[0]

    # ------------------------------------------------------------------ geometry
    def contains_direction(self, u) -> bool:
        """The direction u (from the centre) lies in the closed angular range of the arc."""
        ax, ay = self.a[0] - self.c[0], self.a[1] - self.c[1]
        bx, by = self.b[0] - self.c[0], self.b[1] - self.c[1]
        ux, uy = (to_fraction(u[0]), to_fraction(u[1]))
        ca = ax * uy - ay * ux          # a → u counter-clockwise
        cb = ux * by - uy * bx          # u → b counter-clockwise
        if ax * by - ay * bx > 0 or (ax * by - ay * bx == 0 and ax * bx + ay * by < 0 and ca >= 0):
            return ca >= 0 and cb >= 0
        return ca >= 0 or cb >= 0

    def float_data(self):
        """((cx, cy), ρ, (ax, ay), (bx, by)) as floats."""
        f = float
        return (f(self.c[0]), f(self.c[1])), f(self.rho), (f(self.a[0]), f(self.a[1])), (f(self.b[0]), f(self.b[1]))

    def key(self) -> tuple:
        return (self.c, self.rho, self.a, self.b)

    def __repr__(self) -> str:
        return (f"Arc(centre=({self.c[0]}, {self.c[1]}), radius={self.rho}, from ({self.a[0]}, {self.a[1]}) "
                f"to ({self.b[0]}, {self.b[1]}))")


def exact_sqrt(q: Fraction) -> Fraction | None:
    """The rational square root of q, or None when q is not the square of a rational."""
    n, d = q.numerator, q.denominator
    rn, rd = math.isqrt(n), math.isqrt(d)
    if rn * rn == n and rd * rd == d:
        return Fraction(rn, rd)
    return None


def circle_halves(centre, radius_squared, label: str | None = None, what: str = "circle") -> list[Arc]:
    """The circle of ``centre`` and squared radius ``radius_squared`` as two counter-clockwise
    half arcs, from (cx + ρ, cy) to (cx − ρ, cy) and back, the radius ρ rational.

    >>> circle_halves((0, 0), 4)
    [Arc(centre=(0, 0), radius=2, from (2, 0) to (-2, 0)), Arc(centre=(0, 0), radius=2, from (-2, 0) to (2, 0))]
    """
    cx, cy = as_point_pair(centre, f"{what} centre")
    r2 = to_fraction(radius_squared, f"{what} squared radius")
    rho = exact_sqrt(r2) if r2 > 0 else None
    if rho is None:
        raise InvalidConicError(f"{what}: the radius √{r2} is not rational (or not positive); a circle among "
                                "segments and arcs needs a rational radius: give it with Circle.from_radius")
    east, west = (cx + rho, cy), (cx - rho, cy)
    return [Arc((cx, cy), rho, east, west, label), Arc((cx, cy), rho, west, east, label)]
