"""Euclidean distance from a point to a conic: the scalar float API.

The distance d(q, C) = min over p ∈ C of |q − p| is the function whose equalities define the
Voronoi diagram of the sites (thesis §5.1–5.2; a Voronoi vertex q has
d(q, C1) = d(q, C2) = d(q, C3)).  Its critical points ("foot points") are the points of C
where q − p is normal to C (thesis §5.2, the normal condition behind Thm 5.2.2).

This module is the one-point interface to :mod:`runtime.sites.foot_points`, which computes the
foot points for many points at once: :func:`distance` and :func:`closest_point` take the closest
foot (:func:`runtime.sites.foot_points.closest_feet`, a safeguarded Newton iteration on the
bracketed root of the normal condition), :func:`foot_points` lists every critical point
(:func:`runtime.sites.foot_points.canonical_foot_points`).

The rigorous enclosures are in :mod:`runtime.sites.distance_ball`.
"""
from __future__ import annotations

import math

import numpy as np

from .conic import Conic
from .foot_points import canonical_foot_points, closest_feet

__all__ = ["canonical_foot_points", "closest_point", "distance", "foot_points"]


def _canonical_point(conic: Conic, x, y):
    fr = conic.frame
    X0, Y0 = fr.to_canonical(float(x), float(y))
    return fr, float(X0), float(Y0)


def _closest_canonical(fr, X0: float, Y0: float) -> tuple[float, float]:
    X, Y = closest_feet(fr.kind, fr.params, np.array([X0]), np.array([Y0]))
    return float(X[0]), float(Y[0])


def foot_points(conic: Conic, x, y) -> list[tuple[float, float, float]]:
    """All real critical points of the distance from (x, y) to the curve, as (px, py, dist)
    in world coordinates: first the closest point of :func:`closest_point`, then the others sorted
    by dist.
    At the centre of a circle (infinitely many foot points) one representative is returned."""
    fr, X0, Y0 = _canonical_point(conic, x, y)
    Xc, Yc = _closest_canonical(fr, X0, Y0)
    dc = math.hypot(Xc - X0, Yc - Y0)
    close = 1e-8 * (1.0 + abs(Xc) + abs(Yc) + dc)
    others = []
    for X, Y, _ok in canonical_foot_points(fr.kind, fr.params, X0, Y0):
        if math.hypot(X - Xc, Y - Yc) > close:
            others.append((X, Y, math.hypot(X - X0, Y - Y0)))
    out = []
    for X, Y, dist in [(Xc, Yc, dc)] + sorted(others, key=lambda t: t[2]):
        px, py = fr.from_canonical(X, Y)
        out.append((float(px), float(py), dist))
    return out


def distance(conic: Conic, x, y) -> float:
    """Euclidean distance from (x, y) to the conic (both branches of a hyperbola)."""
    fr, X0, Y0 = _canonical_point(conic, x, y)
    if fr.kind == "circle":
        return abs(math.hypot(X0, Y0) - math.sqrt(fr.params["r2"]))
    X, Y = _closest_canonical(fr, X0, Y0)
    return math.hypot(X - X0, Y - Y0)


def closest_point(conic: Conic, x, y) -> tuple[float, float, float]:
    """(px, py, dist) of a closest point of the conic to (x, y)."""
    fr, X0, Y0 = _canonical_point(conic, x, y)
    X, Y = _closest_canonical(fr, X0, Y0)
    px, py = fr.from_canonical(X, Y)
    return float(px), float(py), math.hypot(X - X0, Y - Y0)
