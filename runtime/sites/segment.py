"""Segments: the simplest semi-algebraic sites (thesis §2.2).

A :class:`Segment` is the closed segment [p, q] with exact rational endpoints.  In a Voronoi
diagram it is split, as in CGAL's segment Delaunay graph (Karavelas 2004) and Boost.Polygon, into
its **open interior** and its two endpoints as point sites: the "harmless sites" of Alt and
Schwarzkopf (thesis §2.2), so that every bisector is a line or a parabola and a circle touches
each elementary site at most once.  The distance to the open interior is the distance to the
closed segment; the diagram's convention gives a point at equal distance from an endpoint and
the interior (the half-plane beyond the endpoint) to the endpoint, whose region is bounded by
the perpendicular to the segment there.

Public API: :class:`Segment`, :func:`as_point_pair`.
"""
from __future__ import annotations

from fractions import Fraction

from ..result import InvalidConicError
from .rationals import to_fraction
from .kinds import KeyedSite

__all__ = ["Segment", "as_point_pair"]


def as_point_pair(p, name: str = "point") -> tuple[Fraction, Fraction]:
    """``p`` (a pair of numbers, or an object with ``x``, ``y``) as exact rationals."""
    if hasattr(p, "x") and hasattr(p, "y") and not isinstance(p, (tuple, list)):
        x, y = p.x, p.y
    else:
        try:
            x, y = p
        except (TypeError, ValueError):
            raise InvalidConicError(f"{name}: expected a pair (x, y), got {p!r}") from None
    return (to_fraction(_plain(x), f"{name}.x"), to_fraction(_plain(y), f"{name}.y"))


def _plain(v):
    """python-flint rationals as Fractions (to_fraction takes both; this keeps str() exact)."""
    try:
        import flint

        if isinstance(v, flint.fmpq):
            return Fraction(int(v.p), int(v.q))
        if isinstance(v, flint.fmpz):
            return int(v)
    except ImportError:       # pragma: no cover - flint is a dependency
        pass
    return v


class Segment(KeyedSite):
    """The closed segment [p, q] with exact rational endpoints (p ≠ q).

    >>> from curvedvoronoi import Segment
    >>> s = Segment((0, 0), ("1/2", 1))
    >>> s
    Segment((0, 0), (1/2, 1))
    >>> s.length_squared
    Fraction(5, 4)
    """

    __slots__ = ("p", "q", "label")
    KIND = "segment"

    def __init__(self, p, q, label: str | None = None):
        self.p = as_point_pair(p, "segment start")
        self.q = as_point_pair(q, "segment end")
        if self.p == self.q:
            raise InvalidConicError(f"segment from {_fmt(self.p)} to itself: a segment needs two distinct "
                                    "endpoints (use a point site)")
        self.label = label

    @property
    def length_squared(self) -> Fraction:
        return (self.q[0] - self.p[0]) ** 2 + (self.q[1] - self.p[1]) ** 2

    def float_endpoints(self) -> tuple[tuple[float, float], tuple[float, float]]:
        return (float(self.p[0]), float(self.p[1])), (float(self.q[0]), float(self.q[1]))

    def reversed(self) -> "Segment":
        return Segment(self.q, self.p, self.label)

    def key(self) -> tuple:
        """The segment as an unordered pair of endpoints (for equality and hashing)."""
        return tuple(sorted((self.p, self.q)))

    def __repr__(self) -> str:
        return f"Segment({_fmt(self.p)}, {_fmt(self.q)})"


def _fmt(p) -> str:
    return f"({p[0]}, {p[1]})"
