"""Distances to elementary sites (points and open segments), vectorised and as balls.

The distance from q to the open interior of the segment [a, b] is the distance to the closed
segment: |q − (a + t (b − a))| with t = clamp((q − a)·(b − a) / |b − a|², 0, 1)  (thesis §2.2:
harmless sites; a point site is the case a = b).  :func:`distances` evaluates it in floats for
many (query, site) pairs; :func:`distance_ball` encloses it rigorously at a ball point with
python-flint ``arb`` (exact rational endpoints), the only rigorous distance of the segment code.

Public API: :func:`distances`, :func:`distance_ball`, :func:`float_error`, :func:`foot_parameter`.
"""
from __future__ import annotations

import numpy as np
from flint import arb

from ..certify.foot import to_arb

__all__ = ["distances", "distance_ball", "float_error", "foot_parameter"]


def distances(A, B, Q):
    """|Q − closest point of [A, B]| row by row (A, B, Q: n × 2 float arrays; A = B for a point)
    and the clamped foot parameters t."""
    D = B - A
    L2 = np.einsum("ij,ij->i", D, D)
    W = Q - A
    with np.errstate(invalid="ignore", divide="ignore"):
        t = np.where(L2 > 0, np.einsum("ij,ij->i", W, D) / np.where(L2 > 0, L2, 1.0), 0.0)
    t = np.clip(t, 0.0, 1.0)
    F = A + t[:, None] * D
    return np.hypot(Q[:, 0] - F[:, 0], Q[:, 1] - F[:, 1]), t


def float_error(A, B, Q):
    """A bound on the rounding error of :func:`distances` (a few units in the last place of the
    coordinates' magnitude): |computed − exact| ≤ this, for float inputs."""
    scale = np.max(np.abs(np.concatenate([A, B, Q], axis=1)), axis=1) + 1.0
    return 64 * np.finfo(float).eps * scale


def distance_ball(a, b, x: arb, y: arb) -> arb:
    """An arb ball holding the distance from every point of the ball box (x, y) to the closed
    segment [a, b] (exact rational pairs; a = b for a point)."""
    ax, ay = to_arb(a[0]), to_arb(a[1])
    if a == b:
        return ((x - ax) ** 2 + (y - ay) ** 2).sqrt()
    bx, by = to_arb(b[0]), to_arb(b[1])
    dx, dy = bx - ax, by - ay
    L2 = dx * dx + dy * dy
    t = ((x - ax) * dx + (y - ay) * dy) / L2
    da = ((x - ax) ** 2 + (y - ay) ** 2).sqrt()
    db = ((x - bx) ** 2 + (y - by) ** 2).sqrt()
    line = abs((x - ax) * dy - (y - ay) * dx) / L2.sqrt()
    if t > 0 and t < 1:
        return line
    if t <= 0:
        return da
    if t >= 1:
        return db
    # the foot parameter straddles an end: the distance lies between the line's and the end's
    lo = line.lower()
    hi = (da if t.mid() < 0.5 else db).upper()
    return lo.union(hi)


def foot_parameter(a, b, x: arb, y: arb) -> arb:
    """The parameter t of the projection of the ball point (x, y) on the line a + t (b − a)."""
    ax, ay = to_arb(a[0]), to_arb(a[1])
    dx, dy = to_arb(b[0]) - ax, to_arb(b[1]) - ay
    return ((x - ax) * dx + (y - ay) * dy) / (dx * dx + dy * dy)
