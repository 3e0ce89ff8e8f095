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

Public API: :func:`hausdorff_bound`, :func:`hausdorff_bounds` (many edges at once).
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["hausdorff_bound", "hausdorff_bounds"]


class _Curves:
    """Per-point constants of the bisectors (m, e_x, e_y, a, b, kind, rounding) as flat arrays."""

    def __init__(self, biss, owner):
        self.hyp = np.array([b.kind == "hyperbola" for b in biss], bool)[owner]
        self.m = np.array([b.m for b in biss], float).reshape(-1, 2)[owner]
        self.ex = np.array([b.ex for b in biss], float).reshape(-1, 2)[owner]
        self.ey = np.array([b.ey for b in biss], float).reshape(-1, 2)[owner]
        self.a = np.array([b.a for b in biss], float)[owner]
        self.b = np.array([b.b for b in biss], float)[owner]
        self.err0 = np.array([b.err0 for b in biss], float)[owner]

    def take(self, idx):
        c = object.__new__(_Curves)
        for k in ("hyp", "m", "ex", "ey", "a", "b", "err0"):
            setattr(c, k, getattr(self, k)[idx])
        return c

    def point(self, u):
        with np.errstate(over="ignore"):
            X = np.where(self.hyp, self.a * np.cosh(np.where(self.hyp, u, 0.0)), self.a * np.cos(u))
            Y = np.where(self.hyp, self.b * np.sinh(np.where(self.hyp, u, 0.0)), self.b * np.sin(u))
        return self.m + X[:, None] * self.ex + Y[:, None] * self.ey

    def param(self, P):
        V = P - self.m
        x, y = (V * self.ex).sum(1), (V * self.ey).sum(1)
        with np.errstate(all="ignore"):
            return np.where(self.hyp, np.arcsinh(y / self.b), np.mod(np.arctan2(y / self.b, x / self.a), 2 * math.pi))

    def curve_error(self, u):
        """As :meth:`runtime.voronoi.verify.edges.Bisector.curve_error`."""
        return np.where(self.hyp, self.err0 * np.cosh(np.minimum(np.abs(u), 700.0)) * 4, self.err0 * 4)


def hausdorff_bound(bis, P, closed=False):
    """(bound, None): a proved bound on the Hausdorff distance between the polyline P (n × 2) and
    the arc of ``bis`` it follows; (inf, reason) for a polyline of fewer than two points."""
    P = np.asarray(P, float).reshape(-1, 2)
    if len(P) < 2:
        return math.inf, "fewer than two points"
    return float(hausdorff_bounds([bis], [P])[0]), None


#: edges bounded together (the temporaries of a group take O(its points) memory)
GROUP = 2048


def hausdorff_bounds(biss, polys, foot_steps=4):
    """:func:`hausdorff_bound` of many edges at once (array of bounds; inf for a polyline of fewer
    than two points), in groups of :data:`GROUP` edges.  ``foot_steps``: at most this many Newton
    steps towards each point's foot (:func:`_foot_params`; fewer make the bound less sharp, never
    wrong: a polyline sampled on the curve needs none)."""
    polys = list(polys)
    if len(polys) <= GROUP:
        return _group_bounds(biss, polys, foot_steps)
    return np.concatenate([_group_bounds(biss[s:s + GROUP], polys[s:s + GROUP], foot_steps)
                           for s in range(0, len(polys), GROUP)])


def _group_bounds(biss, polys, foot_steps=4):
    """:func:`hausdorff_bounds` of one group of edges."""
    polys = [np.asarray(P, float).reshape(-1, 2) for P in polys]
    lens = np.array([len(P) for P in polys], int)
    out = np.full(len(polys), math.inf)
    if not len(polys) or lens.sum() == 0:
        return out
    owner = np.repeat(np.arange(len(polys)), lens)
    P = np.concatenate(polys)
    C = _Curves(biss, owner)
    u = _foot_params(C, P, C.param(P), foot_steps)
    Q = C.point(u)
    d = np.hypot(*(P - Q).T) + C.curve_error(u)
    seg = np.nonzero(owner[1:] == owner[:-1])[0]            # segment t joins points t, t + 1
    if not len(seg):
        return out
    du = u[seg + 1] - u[seg]
    hypseg = C.hyp[seg]
    du = np.where(hypseg, du, (du + math.pi) % (2 * math.pi) - math.pi)   # ellipse: below half a turn
    dev = _chord_deviation(C.take(seg), u[seg], u[seg] + du, Q[seg], Q[seg + 1])
    bound = np.maximum(d[seg], d[seg + 1]) + dev
    res = np.full(len(polys), -np.inf)
    np.maximum.at(res, owner[seg], bound)
    ok = lens >= 2
    out[ok] = res[ok] * (1 + 1e-12)
    return out


def _foot_params(C, P, u, iters=4):
    """Parameters of (nearly) the nearest curve points to P: at most ``iters`` Newton steps on
    (q(u) − P)·q'(u) = 0 from the given ones, fewer once every step is below 10⁻¹⁵ of the
    parameter.  Any parameter gives a curve point, so |P − q(u)| bounds the distance whatever the
    accuracy of these steps; they only make the bound sharp."""
    a, b, hyp = C.a, C.b, C.hyp
    V = P - C.m
    x, y = (V * C.ex).sum(1), (V * C.ey).sum(1)
    only_hyp = bool(hyp.all())          # then the np.where below all take their first values
    with np.errstate(all="ignore"):
        for _ in range(iters):
            if only_hyp:
                ch, sh = np.cosh(u), np.sinh(u)
                X, Y, dX, dY = a * ch, b * sh, a * sh, b * ch
                ddX, ddY = X, Y
            else:
                ch, sh = np.cosh(np.where(hyp, u, 0.0)), np.sinh(np.where(hyp, u, 0.0))
                co, si = np.cos(u), np.sin(u)
                X = np.where(hyp, a * ch, a * co)
                Y = np.where(hyp, b * sh, b * si)
                dX = np.where(hyp, a * sh, -a * si)
                dY = np.where(hyp, b * ch, b * co)
                ddX = np.where(hyp, X, -X)
                ddY = np.where(hyp, Y, -Y)
            g = (X - x) * dX + (Y - y) * dY
            dg = dX * dX + dY * dY + (X - x) * ddX + (Y - y) * ddY
            s = g / dg
            step = np.minimum(np.maximum(np.where(np.isfinite(s) & (dg > 0), s, 0.0), -0.5), 0.5)
            u = u - step
            if not (np.abs(step) > 1e-15 * (1.0 + np.abs(u))).any():
                break
    return u


def _chord_deviation(C, ua, ub, Qa, Qb):
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
    a, b, hyp = C.a, C.b, C.hyp
    alpha = a * (n * C.ex).sum(1)
    beta = b * (n * C.ey).sum(1)
    gamma = ((C.m - Qa) * n).sum(1)
    big = np.minimum(np.maximum(np.abs(lo), np.abs(hi)), 700.0)
    only_hyp = bool(hyp.all())          # then the hyperbola's parameters need no masking
    with np.errstate(all="ignore"):
        # hyperbola
        r = -beta / alpha
        ustar = np.arctanh(np.minimum(np.maximum(r, -1 + 1e-16), 1 - 1e-16))
        in_h = (np.abs(r) < 1) & (ustar > lo) & (ustar < hi)
        us = np.where(in_h, ustar, lo)
        h_us, h_big, h_lo, h_hi = (us, big, lo, hi) if only_hyp else (
            np.where(hyp, us, 0.0), np.where(hyp, big, 0.0), np.where(hyp, lo, 0.0), np.where(hyp, hi, 0.0))
        ch_big = np.cosh(h_big)
        f_h = alpha * np.cosh(h_us) + beta * np.sinh(h_us) + gamma
        mag_h = (np.abs(alpha) + np.abs(beta)) * ch_big + np.abs(gamma)
        speed_h = np.sqrt(a * a * np.sinh(h_big) ** 2 + b * b * ch_big ** 2)
        t0 = np.arctan2(b * np.cosh(h_lo), a * np.sinh(h_lo))
        t1 = np.arctan2(b * np.cosh(h_hi), a * np.sinh(h_hi))
        turn_h = np.abs((t1 - t0 + np.pi) % (2 * np.pi) - np.pi)
    if only_hyp:                        # no ellipse: the np.where below all take the hyperbola's values
        dev = np.where(in_h, np.abs(f_h), 0.0) + 1e-12 * mag_h + 4 * C.curve_error(big)
        return np.where(turn_h < np.pi / 2, dev, np.maximum(dev, 0.5 * speed_h * (hi - lo) * (1 + 1e-12)))
    with np.errstate(all="ignore"):
        # ellipse: the first critical angles ≥ lo
        tc = np.arctan2(beta, alpha)
        c1 = tc + 2 * np.pi * np.ceil((lo - tc) / (2 * np.pi))
        c2 = (tc + np.pi) + 2 * np.pi * np.ceil((lo - tc - np.pi) / (2 * np.pi))
        f1 = np.where(c1 < hi, np.abs(alpha * np.cos(c1) + beta * np.sin(c1) + gamma), 0.0)
        f2 = np.where(c2 < hi, np.abs(alpha * np.cos(c2) + beta * np.sin(c2) + gamma), 0.0)
        f_e = np.maximum(f1, f2)
        mag_e = np.abs(alpha) + np.abs(beta) + np.abs(gamma)
        speed_e = np.maximum(np.abs(a), np.abs(b))
        turn_e = (hi - lo) * speed_e / np.maximum(np.minimum(np.abs(a), np.abs(b)), 1e-300)   # ≥ the turning
    f = np.where(hyp, np.where(in_h, np.abs(f_h), 0.0), f_e)
    mag = np.where(hyp, mag_h, mag_e)
    speed = np.where(hyp, speed_h, speed_e)
    turn = np.where(hyp, turn_h, turn_e)
    dev = f + 1e-12 * mag + 4 * C.curve_error(big)
    crude = 0.5 * speed * (hi - lo) * (1 + 1e-12)
    return np.where(turn < np.pi / 2, dev, np.maximum(dev, crude))
