"""The order of a vertex's sites around it: counter-clockwise by contact point (thesis §1.2).

A vertex of k sites has its edges between cyclically consecutive sites
(:class:`runtime.voronoi.structure.DiagramVertex`).  At a corner c of the input (radius 0) the
curves ending at c are ordered by the direction in which they leave c, and c itself sits in the
reflex gap (> 180°) if there is one — otherwise c's region is the point alone.  Elsewhere the
sites are ordered by the angle of their contact points seen from the vertex; a curve touching at
one of its ends shares that contact with the end's point site and is placed on the side where it
leaves the contact.

Public API: :func:`corner_order`, :func:`contact_order`, :func:`contact_orders`.
"""
from __future__ import annotations

import math

import numpy as np

from .bisectors import arc_range
from .elementary import ARC, ELLIPSE, POINT, SEGMENT, ElementarySites
from .ellipse_pieces import piece_feet, piece_points, piece_tangent

__all__ = ["corner_order", "contact_order", "contact_orders"]


def corner_order(E: ElementarySites, c: int) -> tuple:
    """The sites of the corner vertex c: the segments ending at c by angle, c itself inserted in
    the reflex gap (> 180°) if there is one; starting with the smallest index."""
    segs = E.incident[c]
    cx, cy = E.A[c]
    ang = []
    for s in segs:            # the direction in which the curve leaves c
        if E.kind[s] == ARC:
            rx, ry = cx - E.C[s][0], cy - E.C[s][1]
            tx, ty = (-ry, rx) if int(E.ends[s, 0]) == c else (ry, -rx)
        elif E.kind[s] == ELLIPSE:
            tx, ty = piece_tangent(E.ellipse[s], 0 if int(E.ends[s, 0]) == c else 1)
        else:
            o = int(E.ends[s, 1]) if int(E.ends[s, 0]) == c else int(E.ends[s, 0])
            tx, ty = E.A[o][0] - cx, E.A[o][1] - cy
        ang.append(math.atan2(ty, tx))
    order = [s for _, s in sorted(zip(ang, segs))]
    angs = sorted(ang)
    out = list(order)
    for k in range(len(order)):
        gap = (angs[(k + 1) % len(order)] - angs[k]) % (2 * math.pi) if len(order) > 1 else 2 * math.pi
        if gap > math.pi:
            out = order[:k + 1] + [c] + order[k + 1:]
            break
    m = out.index(min(out))
    return tuple(out[m:] + out[:m])


def contact_order(E: ElementarySites, members, sol) -> tuple:
    """Sites sorted counter-clockwise by their contact points seen from the vertex.  A curve
    touching at one of its ends shares that contact with the end's point site: it comes just
    after it when the curve leaves the contact counter-clockwise around the vertex, just before
    otherwise (its region lies on that side)."""
    v = np.array([sol.x, sol.y])
    ang = []
    for s in members:
        lean = 0.0
        if E.kind[s] == POINT or E.kind[s] == SEGMENT:
            ang.append(float(_straight_angles(E, np.array([s]), v[None, :])[0]))
            continue
        if E.kind[s] == ARC:
            w = v - E.C[s]
            if np.hypot(*w) <= 1e-9 * E.rho[s]:          # the arc's centre: contact along the arc
                al, be = arc_range(E, s)
                w = np.array([math.cos(al + be / 2), math.sin(al + be / 2)])
            f = E.C[s] + E.rho[s] * w / np.hypot(*w)
            for end, P in ((0, E.A[s]), (1, E.B[s])):
                if np.hypot(*(f - P)) <= 1e-9 * (1 + E.rho[s]):
                    r = P - E.C[s]
                    lean = _lean(f - v, np.array([-r[1], r[0]]) if end == 0 else np.array([r[1], -r[0]]))
        else:                                             # an elliptic piece
            P = E.ellipse[s]
            _d, phi = piece_feet(P, v[None, :])
            f = piece_points(P, phi)[0]
            span = P.phi1 - P.phi0
            for end, at in ((0, P.phi0), (1, P.phi1)):
                if abs(float(phi[0]) - at) <= 1e-9 * span:
                    lean = _lean(f - v, piece_tangent(P, end))
        ang.append(math.atan2(f[1] - v[1], f[0] - v[0]) + lean)
    order = [s for _, s in sorted(zip(ang, members))]
    m = order.index(min(order))
    return tuple(order[m:] + order[:m])


def contact_orders(E: ElementarySites, members, V) -> list:
    """:func:`contact_order` of many vertices (``members``: their site tuples, ``V``: their
    positions): those of three point or segment sites on arrays at once (the same angles and the
    same ties, broken by site number), the others one by one."""
    out: list = [None] * len(members)
    V = np.asarray(V, float).reshape(-1, 2)
    rows = [k for k, ms in enumerate(members) if len(ms) == 3]
    if rows:
        M = np.array([members[k] for k in rows], np.int64)
        simple = ((E.kind[M] == POINT) | (E.kind[M] == SEGMENT)).all(axis=1)
        M, R = M[simple], np.array(rows, np.int64)[simple]
        if len(R):
            ang = _straight_angles(E, M.ravel(), np.repeat(V[R], 3, axis=0)).reshape(-1, 3)
            order = _lexsort_rows(ang, M)
            S = np.take_along_axis(M, order, axis=1)
            first = np.argmin(S, axis=1)
            S = np.take_along_axis(S, (first[:, None] + np.arange(3)) % 3, axis=1)
            for k, t in zip(R.tolist(), S.tolist()):
                out[k] = tuple(t)
    for k, ms in enumerate(members):
        if out[k] is None:
            out[k] = contact_order(E, ms, _At(V[k]))
    return out


class _At:
    """A position with the ``x``, ``y`` of a vertex solution."""

    def __init__(self, v):
        self.x, self.y = float(v[0]), float(v[1])


def _lexsort_rows(ang, M) -> np.ndarray:
    """Per row, the column order sorting by angle, then by site (Python's tuple order)."""
    order = np.argsort(M, axis=1, kind="stable")
    a = np.take_along_axis(ang, order, axis=1)
    return np.take_along_axis(order, np.argsort(a, axis=1, kind="stable"), axis=1)


def _straight_angles(E: ElementarySites, S, V) -> np.ndarray:
    """The angle at V of the contact point of point or segment site S (rows), leaned by ±10⁻⁹
    for a segment touched at an end (:func:`_lean`: the side where it leaves the contact)."""
    a, d = E.A[S], E.B[S] - E.A[S]
    dd = d[:, 0] * d[:, 0] + d[:, 1] * d[:, 1]
    seg = E.kind[S] != POINT
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(seg, ((V[:, 0] - a[:, 0]) * d[:, 0] + (V[:, 1] - a[:, 1]) * d[:, 1]) / np.where(seg, dd, 1.0), 0.0)
    f = a + np.clip(t, 0, 1)[:, None] * d
    rx, ry = f[:, 0] - V[:, 0], f[:, 1] - V[:, 1]
    cross = rx * d[:, 1] - ry * d[:, 0]              # the lean along d; along −d it flips
    lean = np.where(seg & (t <= 1e-12), np.where(cross > 0, 1e-9, -1e-9),
                    np.where(seg & (t >= 1 - 1e-12), np.where(-cross > 0, 1e-9, -1e-9), 0.0))
    return np.arctan2(ry, rx) + lean


def _lean(radius_vector, direction) -> float:
    """±10⁻⁹: a curve leaving its contact in ``direction`` lies counter-clockwise (+) or clockwise
    (−) of the contact point around the vertex."""
    return 1e-9 if radius_vector[0] * direction[1] - radius_vector[1] * direction[0] > 0 else -1e-9
