"""Circle and point sites: exact rational centre and squared radius (thesis §3.1: a point is a
circle of radius 0, an additively weighted point of weight 0).

The site records themselves, below every predicate and construction that uses them; the exact
predicates of circles are in :mod:`runtime.predicates.circles` (which re-exports these names).

Public API: :class:`Circle`, :class:`Point`, :func:`as_circle`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

from flint import fmpq

from ..result import InvalidConicError
from .rationals import parse_rational

__all__ = ["Circle", "Point", "as_circle"]


@dataclass(frozen=True)
class Circle:
    """A circle site (x - cx)² + (y - cy)² = r2, exact rational cx, cy and **squared** radius r2 ≥ 0.

    Build it with :meth:`from_radius` (centre and radius).  ``Circle(cx, cy, r2=...)`` takes the
    **squared** radius, which need not be a perfect square (a circle from coefficients
    x²+y²+dx+ey+f = 0 has r2 = (d²+e²)/4 − f, see :meth:`from_coefficients`).
    r2 = 0 is a point site (:class:`Point`).  ``label``: an optional string kept through the
    diagram's JSON and GeoJSON, not part of equality.

    >>> Circle.from_radius(1, 2, 3)
    Circle(centre=(1, 2), radius_squared=9)
    >>> Circle(0, 0, r2=2).radius_squared, round(Circle(0, 0, r2=2).rho, 6)
    (2, 1.414214)
    """

    cx: fmpq
    cy: fmpq
    r2: fmpq
    label: str | None = field(default=None, compare=False, repr=False)

    def __init__(self, cx, cy, r2, label: str | None = None):
        object.__setattr__(self, "label", label)
        object.__setattr__(self, "cx", parse_rational(cx, "circle centre x"))
        object.__setattr__(self, "cy", parse_rational(cy, "circle centre y"))
        r2q = parse_rational(r2, "circle squared radius")
        if r2q < 0:
            raise InvalidConicError(f"circle squared radius r2 = {r2q} is negative (imaginary circle)")
        object.__setattr__(self, "r2", r2q)

    @classmethod
    def from_radius(cls, cx, cy, rho, label: str | None = None) -> "Circle":
        """The circle of centre (cx, cy) and radius ``rho`` ≥ 0 (exact; floats at their binary value)."""
        r = parse_rational(rho, "circle radius")
        if r < 0:
            raise InvalidConicError(f"circle radius {rho!r} is negative")
        return cls(cx, cy, r * r, label)

    @classmethod
    def from_coefficients(cls, a, b, c, d, e, f) -> "Circle":
        """From a x² + b xy + c y² + d x + e y + f = 0 (needs b = 0, a = c ≠ 0)."""
        a, b, c, d, e, f = (parse_rational(t, "conic coefficient") for t in (a, b, c, d, e, f))
        if b != 0 or a != c or a == 0:
            raise InvalidConicError("not a circle: need b = 0 and a = c != 0")
        cx, cy = -d / (2 * a), -e / (2 * a)
        return cls(cx, cy, cx * cx + cy * cy - f / a)

    @classmethod
    def from_canonical(cls, can: dict) -> "Circle":
        """From the ``canonical`` record of tests/data/validation_cases.json (type circle)."""
        if can.get("type") != "circle":
            raise InvalidConicError(f"not a circle: {can.get('type')}")
        return cls(can["tx"], can["ty"], can["r2"])

    @property
    def radius_squared(self) -> fmpq:
        """The exact squared radius r2 (the radius itself may be irrational)."""
        return self.r2

    @property
    def rho(self) -> float:
        """The radius √r2 as a float."""
        return math.sqrt(float(self.r2))

    def __repr__(self) -> str:
        return f"Circle(centre=({self.cx}, {self.cy}), radius_squared={self.r2})"

    def distance(self, x: float, y: float) -> float:
        """Float distance | |q - c| - ρ | (diagnostics only)."""
        return abs(math.hypot(x - float(self.cx), y - float(self.cy)) - self.rho)


class Point(Circle):
    """A point site (x, y): a circle of radius 0 (thesis §3.1.2, additively weighted points of
    weight 0).  Every circle routine accepts it."""

    def __init__(self, x, y, label: str | None = None):
        super().__init__(x, y, 0, label)

    @property
    def x(self) -> fmpq:
        return self.cx

    @property
    def y(self) -> fmpq:
        return self.cy

    def __repr__(self) -> str:
        return f"Point({self.cx}, {self.cy})"


def as_circle(c) -> Circle:
    """Accept a Circle, a pair (x, y) (a point) or a triple (centre_x, centre_y, radius)."""
    if isinstance(c, Circle):
        return c
    if isinstance(c, (tuple, list)) and len(c) == 2:
        return Point(*c)
    try:
        cx, cy, rho = c
    except (TypeError, ValueError):
        raise InvalidConicError(f"a circle is Circle.from_radius(cx, cy, radius), a triple (cx, cy, radius) or a "
                                f"point (x, y), got {c!r}") from None
    return Circle.from_radius(cx, cy, rho)
