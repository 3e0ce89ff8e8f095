"""Elliptic arcs with exact rational data (thesis §2.2 and ch. 4: pieces of conics as sites).

An :class:`EllipticArc` follows DXF's ELLIPSE convention: the ellipse of rational centre c,
rational major-axis vector M (from the centre to a major vertex) and rational ratio
k = minor / major (0 < k < 1), with minor-axis vector N = k·perp(M) = k·(−M_y, M_x), is the curve
φ ↦ e(φ) = c + cos φ · M + sin φ · N, and the arc runs **counter-clockwise** in φ from a start to an
end parameter.  The semi-axes |M| and k|M| may be irrational; the arc's data stay rational: its
ends are given by their *frame directions* (cos φ, sin φ), rational points of the unit circle
(u = (1 − t²)/(1 + t²), v = 2t/(1 + t²) for rational t = tan(φ/2)), so the end points
c + u M + v N are rational.  A parameter given as a float is realised by the rational t nearest
to tan(φ/2) in floating point (a relative error of about 10⁻¹⁶), exactly at multiples of π/2 (and
at parameters within 10⁻¹² of one: DXF writes 2π as 6.283185307179586).

In a Voronoi diagram an elliptic arc is cut at the ellipse's vertices c ± M, c ± N (its
curvature extrema, all rational) into pieces (:meth:`EllipticArc.pieces`): on a piece the
curvature is monotone, its evolute piece is convex without cusps, so the foot-point map is
monotone and a circle centred off the piece touches it at most once at a nearest point (the
harmless sites of Alt–Schwarzkopf, thesis §2.2).  Each piece is then split like a segment into
its two end points (point sites) and its open interior.

A ratio of exactly 1 is a circle: :meth:`EllipticArc.from_dxf` refuses it unless the radius is
rational (then a circular :class:`runtime.sites.arc.Arc` does the same job).

Public API: :class:`EllipticArc`, :func:`rational_unit`.
"""
from __future__ import annotations

import math
from fractions import Fraction

from ..result import InvalidConicError
from .rationals import to_fraction
from .segment import as_point_pair
from .kinds import KeyedSite

__all__ = ["EllipticArc", "rational_unit"]

#: the frame directions of the ellipse's four vertices, counter-clockwise from the major vertex c + M
VERTEX_DIRECTIONS = ((Fraction(1), Fraction(0)), (Fraction(0), Fraction(1)),
                     (Fraction(-1), Fraction(0)), (Fraction(0), Fraction(-1)))


def rational_unit(param) -> tuple[Fraction, Fraction]:
    """(cos φ, sin φ) as a rational point of the unit circle for φ in radians: exact at (and within
    10⁻¹² of) multiples of π/2, else from the rational t = tan(φ/2) of the reduced angle."""
    phi = float(param)
    if not math.isfinite(phi):
        raise InvalidConicError(f"elliptic arc parameter {param!r} is not finite")
    q = phi / (math.pi / 2)
    k = round(q)
    if abs(q - k) <= 1e-12 * max(1.0, abs(q)):
        return VERTEX_DIRECTIONS[k % 4]
    red = phi - k * (math.pi / 2)                  # |red| < π/4: t well conditioned
    t = Fraction(math.tan(red / 2))
    u, v = (1 - t * t) / (1 + t * t), 2 * t / (1 + t * t)
    for _ in range(k % 4):                         # rotate by k quarter turns, exactly
        u, v = -v, u
    return u, v


def _ccw_between(a, u, b) -> bool:
    """The unit direction u lies in the closed counter-clockwise range from a to b (a ≠ b)."""
    ca = a[0] * u[1] - a[1] * u[0]
    cb = u[0] * b[1] - u[1] * b[0]
    ab = a[0] * b[1] - a[1] * b[0]
    if ab > 0 or (ab == 0 and a[0] * b[0] + a[1] * b[1] < 0 and ca >= 0):
        return ca >= 0 and cb >= 0
    return ca >= 0 or cb >= 0


class EllipticArc(KeyedSite):
    """The counter-clockwise arc of the ellipse (``centre``, ``major_axis``, ``ratio``) from the
    frame direction ``start`` to ``end`` (rational unit vectors (cos φ, sin φ), distinct).

    >>> from curvedvoronoi import Arc
    >>> e = Arc.elliptic((0, 0), (2, 0), "1/2", 0, 3.141592653589793)
    >>> e
    EllipticArc(centre=(0, 0), major_axis=(2, 0), ratio=1/2, from (2, 0) to (-2, 0))
    >>> [p.b for p in e.pieces()]
    [(Fraction(0, 1), Fraction(1, 1)), (Fraction(-2, 1), Fraction(0, 1))]
    """

    __slots__ = ("c", "M", "ratio", "N", "ua", "ub", "a", "b", "label")
    KIND = "elliptic_arc"

    def __init__(self, centre, major_axis, ratio, start, end, label: str | None = None):
        self.c = as_point_pair(centre, "elliptic arc centre")
        self.M = as_point_pair(major_axis, "elliptic arc major axis")
        if self.M == (0, 0):
            raise InvalidConicError("elliptic arc: the major axis vector is zero")
        self.ratio = to_fraction(ratio, "elliptic arc ratio")
        if not 0 < self.ratio < 1:
            raise InvalidConicError(f"elliptic arc: the ratio minor/major must satisfy 0 < ratio < 1, got {self.ratio}"
                                    + (" (a circle: use Arc.circular)" if self.ratio == 1 else ""))
        self.N = (-self.ratio * self.M[1], self.ratio * self.M[0])
        self.ua = as_point_pair(start, "elliptic arc start direction")
        self.ub = as_point_pair(end, "elliptic arc end direction")
        for name, u in (("start", self.ua), ("end", self.ub)):
            if u[0] * u[0] + u[1] * u[1] != 1:
                raise InvalidConicError(f"elliptic arc {name} direction ({u[0]}, {u[1]}) is not a unit vector")
        if self.ua == self.ub:
            raise InvalidConicError("an elliptic arc needs two distinct end parameters (a whole ellipse: "
                                    "give 0 and 2π to Arc.elliptic)")
        self.a, self.b = self.point(self.ua), self.point(self.ub)
        self.label = label

    # ------------------------------------------------------------------ constructors
    @classmethod
    def from_dxf(cls, centre, major_axis, ratio, start_param, end_param, label: str | None = None) -> list:
        """DXF's ELLIPSE (parameters in radians, counter-clockwise) as a list of arcs: one arc,
        or two halves for a whole ellipse (end − start ≥ 2π up to 10⁻¹²)."""
        r = to_fraction(ratio, "elliptic arc ratio")
        if not 0 < r <= 1:
            raise InvalidConicError(f"elliptic arc: the ratio minor/major must satisfy 0 < ratio <= 1, got {r}")
        M = as_point_pair(major_axis, "elliptic arc major axis")
        if M == (0, 0):
            raise InvalidConicError("elliptic arc: the major axis vector is zero")
        if r == 1:
            raise InvalidConicError("elliptic arc with ratio 1 is a circular arc: give it with Arc.circular "
                                    "(a rational radius)")
        s, e = float(start_param), float(end_param)
        if e - s >= 2 * math.pi - 1e-12:
            return [cls(centre, M, r, VERTEX_DIRECTIONS[0], VERTEX_DIRECTIONS[2], label),
                    cls(centre, M, r, VERTEX_DIRECTIONS[2], VERTEX_DIRECTIONS[0], label)]
        return [cls(centre, M, r, rational_unit(s), rational_unit(e), label)]

    # ------------------------------------------------------------------ geometry
    def point(self, u) -> tuple[Fraction, Fraction]:
        """The exact point c + u₀ M + u₁ N of frame direction u = (cos φ, sin φ)."""
        return (self.c[0] + u[0] * self.M[0] + u[1] * self.N[0], self.c[1] + u[0] * self.M[1] + u[1] * self.N[1])

    def tangent(self, u) -> tuple[Fraction, Fraction]:
        """The exact counter-clockwise tangent e'(φ) = −sin φ M + cos φ N at frame direction u."""
        return (-u[1] * self.M[0] + u[0] * self.N[0], -u[1] * self.M[1] + u[0] * self.N[1])

    def contains_direction(self, u) -> bool:
        """The frame direction u (any nonzero rational vector) lies in the closed range of the arc."""
        return _ccw_between(self.ua, (to_fraction(u[0]), to_fraction(u[1])), self.ub)

    def pieces(self) -> list["EllipticArc"]:
        """The arc cut at the ellipse's vertices strictly inside it (its curvature extrema)."""
        cuts = [d for d in VERTEX_DIRECTIONS if d not in (self.ua, self.ub) and self.contains_direction(d)]
        start = math.atan2(float(self.ua[1]), float(self.ua[0]))
        cuts.sort(key=lambda d: (math.atan2(float(d[1]), float(d[0])) - start) % (2 * math.pi))
        ends = [self.ua] + cuts + [self.ub]
        return [EllipticArc(self.c, self.M, self.ratio, u, v, self.label) for u, v in zip(ends, ends[1:])]

    def parameters(self) -> tuple[float, float]:
        """(φ₀, φ₁) floats with φ₀ ∈ (−π, π] and φ₀ < φ₁ ≤ φ₀ + 2π."""
        p0 = math.atan2(float(self.ua[1]), float(self.ua[0]))
        span = (math.atan2(float(self.ub[1]), float(self.ub[0])) - p0) % (2 * math.pi)
        return p0, p0 + (span or 2 * math.pi)

    def float_data(self):
        """((cx, cy), (Mx, My), (Nx, Ny), φ₀, φ₁) as floats."""
        f = float
        return ((f(self.c[0]), f(self.c[1])), (f(self.M[0]), f(self.M[1])), (f(self.N[0]), f(self.N[1])),
                *self.parameters())

    def key(self) -> tuple:
        return (self.c, self.M, self.ratio, self.ua, self.ub)

    def __repr__(self) -> str:
        return (f"EllipticArc(centre=({self.c[0]}, {self.c[1]}), major_axis=({self.M[0]}, {self.M[1]}), "
                f"ratio={self.ratio}, from ({self.a[0]}, {self.a[1]}) to ({self.b[0]}, {self.b[1]}))")
