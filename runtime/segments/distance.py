"""Distances to elementary sites (points and open segments), vectorised and as balls.

The distance from q to the open interior of the segment [a, b] is the distance to the closed
segment: |q − (a + t (b − a))| with t = clamp((q − a)·(b − a) / |b − a|², 0, 1)  (thesis §2.2:
harmless sites; a point site is the case a = b).  :func:`distances` evaluates it in floats for
many (query, site) pairs; :func:`distance_ball` encloses it rigorously at a ball point with
python-flint ``arb`` (exact rational endpoints), the only rigorous distance of the segment code.

For an open circular arc of centre c, radius ρ, counter-clockwise from a to b, the distance is
| |q − c| − ρ | when the direction of q − c lies in the arc's angular range, else the distance to
the nearer end (:func:`site_distances`, :func:`arc_distance_ball`).  Elliptic-arc pieces take
theirs from :mod:`runtime.segments.ellipse_pieces`.

Public API: :func:`distances`, :func:`site_distances`, :func:`distance_ball`,
:func:`arc_distance_ball`, :func:`site_distance_ball`, :func:`float_error`, :func:`foot_parameter`,
:func:`in_arc`, :func:`arc_distances`, :func:`clearance`.
"""
from __future__ import annotations

import numpy as np
from flint import arb

from ..certify.foot import to_arb
from .ellipse_pieces import piece_distance_ball, piece_distances
from .elementary import ARC, ELLIPSE, POINT, SEGMENT

__all__ = ["distances", "distance_ball", "float_error", "foot_parameter", "site_distances", "in_arc", "arc_distances",
           "arc_distance_ball", "site_distance_ball", "clearance"]


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


def clearance(dd, i: int, j: int) -> float:
    """min over k ≠ i, j of d_k − max(d_i, d_j) at a point whose float distances to all sites are
    ``dd``: positive when i and j are nearer than every other site there (the point is on their
    edge), and the larger the more clearly; the construction picks by it the way and side of a
    bisector leaving a vertex.  ``dd`` is changed: d_i and d_j are set to ∞."""
    own = max(dd[i], dd[j])
    dd[[i, j]] = np.inf
    return float(dd.min() - own)


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
        return _hypot(x - ax, y - ay)
    bx, by = to_arb(b[0]), to_arb(b[1])
    dx, dy = bx - ax, by - ay
    L2 = dx * dx + dy * dy
    t = ((x - ax) * dx + (y - ay) * dy) / L2
    da = _hypot(x - ax, y - ay)
    db = _hypot(x - bx, y - by)
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


def _hypot(u: arb, v: arb) -> arb:
    """√(u² + v²) for balls that may contain 0 (arb's u ** 2 is NaN there, and u·u has a
    negative part that sqrt refuses): the squares' non-negative parts."""
    return ((u * u).nonnegative_part() + (v * v).nonnegative_part()).sqrt()


def foot_parameter(a, b, x: arb, y: arb) -> arb:
    """The parameter t of the projection of the ball point (x, y) on the line a + t (b − a)."""
    ax, ay = to_arb(a[0]), to_arb(a[1])
    dx, dy = to_arb(b[0]) - ax, to_arb(b[1]) - ay
    return ((x - ax) * dx + (y - ay) * dy) / (dx * dx + dy * dy)


def in_arc(C, A, B, U):
    """Row by row: the direction U lies in the closed counter-clockwise range of the arc of centre
    C from the point A to the point B (float arrays n × 2)."""
    a = A - C
    b = B - C
    ca = a[:, 0] * U[:, 1] - a[:, 1] * U[:, 0]
    cb = U[:, 0] * b[:, 1] - U[:, 1] * b[:, 0]
    ab = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    small = ab > 0
    return np.where(small, (ca >= 0) & (cb >= 0), (ca >= 0) | (cb >= 0))


def site_distances(E, idx, Q):
    """Distances from Q[r] to elementary site idx[r] of ``E`` (points, segments, arcs; floats)."""
    idx = np.asarray(idx, dtype=np.int64)
    d, _ = distances(E.A[idx], E.B[idx], Q)
    arc = E.kind[idx] == ARC
    if arc.any():
        d[arc] = arc_distances(E.C[idx[arc]], E.rho[idx[arc]], E.A[idx[arc]], E.B[idx[arc]], Q[arc])
    ell = E.kind[idx] == ELLIPSE
    if ell.any():
        rows = np.nonzero(ell)[0]
        for s in np.unique(idx[rows]).tolist():
            at = rows[idx[rows] == s]
            d[at] = piece_distances(E.ellipse[s], Q[at])
    return d


def arc_distances(C, rho, A, B, Q):
    """Row by row: the distance from Q to the closed counter-clockwise arc of centre C, radius
    ρ, from A to B (floats)."""
    W = Q - C
    inside = in_arc(C, A, B, W)
    ends = np.minimum(np.hypot(*(Q - A).T), np.hypot(*(Q - B).T))
    return np.where(inside, np.abs(np.hypot(W[:, 0], W[:, 1]) - rho), ends)


def arc_distance_ball(c, rho, a, b, x: arb, y: arb) -> arb:
    """An arb ball holding the distance from the ball point (x, y) to the closed arc of centre c,
    radius ρ, counter-clockwise from a to b (exact rationals)."""
    cx, cy = to_arb(c[0]), to_arb(c[1])
    ux, uy = x - cx, y - cy
    ax, ay = to_arb(a[0]) - cx, to_arb(a[1]) - cy
    bx, by = to_arb(b[0]) - cx, to_arb(b[1]) - cy
    ca = ax * uy - ay * ux
    cb = ux * by - uy * bx
    ab = (a[0] - c[0]) * (b[1] - c[1]) - (a[1] - c[1]) * (b[0] - c[0])     # exact
    circle = abs(_hypot(ux, uy) - to_arb(rho))
    da = _hypot(x - to_arb(a[0]), y - to_arb(a[1]))
    db = _hypot(x - to_arb(b[0]), y - to_arb(b[1]))
    if ab > 0:
        inside = ca >= 0 and cb >= 0
        outside = ca < 0 or cb < 0
    else:
        inside = ca >= 0 or cb >= 0
        outside = ca < 0 and cb < 0
    if inside:
        return circle
    if outside:
        return _ball_min(da, db)
    # the direction straddles an end of the range: the distance to the whole circle is a lower
    # bound (the ends are on the circle), the nearer end an upper bound
    return circle.lower().union(_ball_min(da, db).upper())


def _ball_min(u: arb, v: arb) -> arb:
    """A ball holding min(s, t) for every s in u, t in v."""
    lo = u.lower() if u.lower() < v.lower() else v.lower()
    hi = u.upper() if u.upper() < v.upper() else v.upper()
    return lo.union(hi)


def site_distance_ball(E, k: int, x: arb, y: arb) -> arb:
    """Ball enclosure of the distance from (x, y) to elementary site k of ``E``."""
    if E.kind[k] == POINT:
        return distance_ball(E.xy[k], E.xy[k], x, y)
    if E.kind[k] == ELLIPSE:
        return piece_distance_ball(E.ellipse[k], x, y)
    a, b = E.xy[int(E.ends[k, 0])], E.xy[int(E.ends[k, 1])]
    if E.kind[k] == SEGMENT:
        return distance_ball(a, b, x, y)
    c, rho = E.arc[k]
    return arc_distance_ball(c, rho, a, b, x, y)
