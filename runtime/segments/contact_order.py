"""The order of a vertex's sites around it: counter-clockwise by contact point (thesis §1.2).

A vertex of k sites has its edges between cyclically consecutive sites
(:class:`runtime.voronoi.structure.DiagramVertex`).  At a corner c of the input (radius 0) the
curves ending at c are ordered by the direction in which they leave c, and c itself sits in the
reflex gap (> 180°) if there is one — otherwise c's region is the point alone.  Elsewhere the
sites are ordered by the angle of their contact points seen from the vertex; a curve touching at
one of its ends shares that contact with the end's point site and is placed on the side where it
leaves the contact.

Public API: :func:`corner_order`, :func:`contact_order`.
"""
from __future__ import annotations

import math

import numpy as np

from .bisectors import arc_range
from .elementary import ARC, ELLIPSE, POINT, ElementarySites
from .ellipse_pieces import piece_feet, piece_points, piece_tangent

__all__ = ["corner_order", "contact_order"]


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
        if E.kind[s] == POINT:
            f = E.A[s]
        elif E.kind[s] == ARC:
            w = v - E.C[s]
            if np.hypot(*w) <= 1e-9 * E.rho[s]:          # the arc's centre: contact along the arc
                al, be = arc_range(E, s)
                w = np.array([math.cos(al + be / 2), math.sin(al + be / 2)])
            f = E.C[s] + E.rho[s] * w / np.hypot(*w)
            for end, P in ((0, E.A[s]), (1, E.B[s])):
                if np.hypot(*(f - P)) <= 1e-9 * (1 + E.rho[s]):
                    r = P - E.C[s]
                    lean = _lean(f - v, np.array([-r[1], r[0]]) if end == 0 else np.array([r[1], -r[0]]))
        elif E.kind[s] == ELLIPSE:
            P = E.ellipse[s]
            _d, phi = piece_feet(P, v[None, :])
            f = piece_points(P, phi)[0]
            span = P.phi1 - P.phi0
            for end, at in ((0, P.phi0), (1, P.phi1)):
                if abs(float(phi[0]) - at) <= 1e-9 * span:
                    lean = _lean(f - v, piece_tangent(P, end))
        else:
            a, b = E.A[s], E.B[s]
            d = b - a
            t = np.dot(v - a, d) / np.dot(d, d)
            f = a + np.clip(t, 0, 1) * d
            if t <= 1e-12:
                lean = _lean(f - v, d)
            elif t >= 1 - 1e-12:
                lean = _lean(f - v, -d)
        ang.append(math.atan2(f[1] - v[1], f[0] - v[0]) + lean)
    order = [s for _, s in sorted(zip(ang, members))]
    m = order.index(min(order))
    return tuple(order[m:] + order[:m])


def _lean(radius_vector, direction) -> float:
    """±10⁻⁹: a curve leaving its contact in ``direction`` lies counter-clockwise (+) or clockwise
    (−) of the contact point around the vertex."""
    return 1e-9 if radius_vector[0] * direction[1] - radius_vector[1] * direction[0] > 0 else -1e-9
