"""A proved bound on the Hausdorff distance between an edge's polyline and its bisector arc, for
circle and point sites (the bisector in closed form, :class:`runtime.voronoi.verify.edges.Bisector`:
q(u) = m + a·cosh u·e_x + b·sinh u·e_y, or m + A·cos t·e_x + B·sin t·e_y around a nested site).

Each polyline point P_t is given the curve parameter u_t of :meth:`Bisector.param`; the curve
point q(u_t) is within ``curve_error`` of the float one, so d_t = |P_t − q(u_t)| + error bounds
the distance from P_t to the arc.  The sub-arcs q([u_t, u_{t+1}]) join the polyline's first
point's foot to its last one's, so they cover the edge's arc between its ends (that the points
stay on that arc is checked by the caller; a loop traversed twice by the winding number of
:mod:`runtime.voronoi.verify.document`).  Each sub-arc
is convex; when it turns by less than π/2 it is a graph over its chord, and its Hausdorff
distance to the chord is the largest value of f(u) = n·(q(u) − q(u_t)) (n the chord's normal),
found in closed form (:func:`_chord_deviation`); otherwise half its length bounds it.  The chord
and the segment [P_t, P_{t+1}] are within max(d_t, d_{t+1}) of each other (convex combinations),
so the Hausdorff distance between the polyline and the arc is at most
max_t (max(d_t, d_{t+1}) + dev_t).

An end at infinity: the polyline's last point is a far point of the edge (checked like the others);
the part of the edge beyond it is not drawn, and the bound covers the drawn part.

Public API: :func:`hausdorff_bound`.
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["hausdorff_bound"]


def hausdorff_bound(bis, P, closed=False):
    """(bound, None): a proved bound on the Hausdorff distance between the polyline P (n × 2) and
    the arc of ``bis`` it follows; (inf, reason) for a polyline of fewer than two points."""
    P = np.asarray(P, float).reshape(-1, 2)
    if len(P) < 2:
        return math.inf, "fewer than two points"
    u = np.asarray(bis.param(P), float).reshape(-1)
    du = np.diff(u)
    if bis.kind == "ellipse":
        du = (du + math.pi) % (2 * math.pi) - math.pi          # steps below half a turn
    Q = bis.point(u)
    d = np.hypot(*(P - Q).T) + bis.curve_error(u)
    dev = _chord_deviation(bis, u[:-1], u[:-1] + du, Q[:-1], Q[1:])
    bound = np.maximum(d[:-1], d[1:]) + dev
    return float(bound.max()) * (1 + 1e-12), None


def _chord_deviation(bis, ua, ub, Qa, Qb):
    """Bound on the Hausdorff distance between the arc q([ua, ub]) and its chord [q(ua), q(ub)]:
    f(u) = n·(q(u) − q(ua)) (n the chord's unit normal) is α·ch(u) + β·sh(u) + γ (cos, sin for an
    ellipse) and vanishes at both ends, so its extreme value on the piece is at the critical point
    α·sh(u) + β·ch(u) = 0 (resp. −α·sin t + β·cos t = 0) when that lies inside; the arc is a graph
    over its chord when it turns by less than π/2 (else the bound is half its length).  Floats with
    a relative margin and the curve's rounding error."""
    lo, hi = np.minimum(ua, ub), np.maximum(ua, ub)
    T = Qb - Qa
    L = np.hypot(T[:, 0], T[:, 1])
    n = np.column_stack([-T[:, 1], T[:, 0]]) / np.where(L > 0, L, 1.0)[:, None]
    a, b = bis.a, bis.b
    alpha = a * (n @ bis.ex)
    beta = b * (n @ bis.ey)
    gamma = ((bis.m - Qa) * n).sum(1)
    hyp = bis.kind == "hyperbola"
    with np.errstate(all="ignore"):
        if hyp:
            r = -beta / alpha
            ustar = np.where(np.abs(r) < 1, np.arctanh(np.clip(r, -1 + 1e-16, 1 - 1e-16)), lo)
            inside = (np.abs(r) < 1) & (ustar > lo) & (ustar < hi)
            us = np.where(inside, ustar, lo)
            f = alpha * np.cosh(us) + beta * np.sinh(us) + gamma
            mag = np.abs(alpha) * np.cosh(np.maximum(np.abs(lo), np.abs(hi))) \
                + np.abs(beta) * np.cosh(np.maximum(np.abs(lo), np.abs(hi))) + np.abs(gamma)
            speed = np.sqrt(a * a * np.sinh(np.maximum(np.abs(lo), np.abs(hi))) ** 2
                            + b * b * np.cosh(np.maximum(np.abs(lo), np.abs(hi))) ** 2)
            # turning of the tangent (a·sh u, b·ch u) between the ends
            t0 = np.arctan2(b * np.cosh(lo), a * np.sinh(lo))
            t1 = np.arctan2(b * np.cosh(hi), a * np.sinh(hi))
            turn = np.abs((t1 - t0 + np.pi) % (2 * np.pi) - np.pi)
        else:
            t1 = np.arctan2(beta, alpha)
            cands = np.stack([t1, t1 + np.pi])
            k = np.ceil((lo[None, :] - cands) / (2 * np.pi))
            cands = cands + 2 * np.pi * k                    # first critical angle ≥ lo
            inside2 = cands < hi[None, :]
            f = np.where(inside2, alpha * np.cos(cands) + beta * np.sin(cands) + gamma, 0.0)
            f = np.abs(f).max(0)
            inside = inside2.any(0)
            mag = np.abs(alpha) + np.abs(beta) + np.abs(gamma)
            speed = np.full(len(lo), max(abs(a), abs(b)))
            turn = (hi - lo) * max(abs(a), abs(b)) / max(min(abs(a), abs(b)), 1e-300)   # ≥ the turning
    dev = np.where(inside, np.abs(f), 0.0) + 1e-12 * mag + 4 * bis.curve_error(np.maximum(np.abs(lo), np.abs(hi)))
    crude = 0.5 * speed * (hi - lo) * (1 + 1e-12)
    return np.where(turn < np.pi / 2, dev, np.maximum(dev, crude))
