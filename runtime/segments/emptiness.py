"""Emptiness of a candidate vertex's circle among points and segments (thesis §1.2).

A proved zero (x, y, r) of three sites' contact system is a Voronoi vertex when no other site
comes closer than r.  Candidates: the sites with a sample within r + h/2 of the centre (h the
largest sample spacing: every point of a segment lies within h/2 of one of its samples, so a site
without such a sample is farther than r), with a rounding margin.  Each candidate is decided by a
float filter with a rounding-error bound (:func:`runtime.segments.distance.float_error`), then
by arb balls (:func:`runtime.segments.distance.distance_ball`), then exactly
(:mod:`runtime.segments.exact`) when the balls cannot separate d from r: a site exactly on the
circle is a further member of the vertex (degree k > 3).

Public API: :func:`prove_empty`.
"""
from __future__ import annotations

import numpy as np
from flint import ctx

from ..certify.foot import to_arb
from .distance import float_error, foot_parameter, site_distance_ball, site_distances
from .elementary import ARC, POINT, SEGMENT, ElementarySites
from .vertices import direction_in_arc

__all__ = ["prove_empty"]


def _closest_at_an_end(E: ElementarySites, k: int, X, Y) -> bool:
    """Proved: the closest point of curve k to every point of the ball box is one of its ends
    (a segment's foot parameter outside [0, 1], an arc's direction outside its range)."""
    a, b = E.xy[int(E.ends[k, 0])], E.xy[int(E.ends[k, 1])]
    if E.kind[k] == SEGMENT:
        t = foot_parameter(a, b, X, Y)
        return bool(t < 0 or t > 1)
    (cx, cy), _rho = E.arc[k]
    return direction_in_arc(E, k, X - to_arb(cx), Y - to_arb(cy)) is False


def _curve_enters(E: ElementarySites, triple, sol) -> bool:
    """At an arc's centre (radius ρ, touching the whole arc) the other curves of the triple only
    hold an end of the arc in their closure: proved True when one of them comes strictly closer
    than ρ (then the centre is not a vertex).  Undecided cases are decided exactly."""
    X, Y, R = sol.box
    for t in triple:
        if E.kind[t] == POINT:
            continue
        if E.kind[t] == ARC and np.hypot(*(E.C[t] - (sol.x, sol.y))) <= 1e-12 * (1 + E.rho[t]):
            continue                          # the arc whose centre this is
        dk = site_distance_ball(E, t, X, Y)
        if dk < R:
            return True
        if not dk > R:
            from .exact import on_circle
            others = tuple(s_ for s_ in triple if s_ != t)
            if on_circle(E, others + (t,), sol, t) is False:
                return True
    return False


def prove_empty(E: ElementarySites, tree, lab, hmax: float, triple, sol):
    """(empty, members, culprit): empty is True (proved), False (a site enters the circle) or
    None (undecided); members are the triple plus the sites proved exactly on the circle."""
    x, y, r = sol.x, sol.y, sol.r
    X, Y, R = sol.box
    rad = max(float(X.rad()), float(Y.rad()))
    scale = 1.0 + abs(x) + abs(y) + r
    reach = r + hmax / 2 + 1e-9 * scale + rad
    near = np.unique(lab[tree.query_ball_point([x, y], reach)])
    cand = np.array([k for k in near.tolist() if k not in triple], dtype=np.int64)
    members = list(triple)
    if sol.reason == "arc centre" and _curve_enters(E, triple, sol):
        return False, tuple(members), next(t for t in triple if E.kind[t] != POINT)
    if not len(cand):
        return True, tuple(members), None
    Q = np.repeat([[x, y]], len(cand), axis=0)
    d = site_distances(E, cand, Q)
    arcs = np.nan_to_num(np.hypot(*E.C[cand].T) + E.rho[cand])
    err = float_error(E.A[cand], E.B[cand], Q) + 64 * np.finfo(float).eps * arcs + rad * 2 + float(R.rad()) \
        + 1e-15 * scale
    undecided = cand[np.abs(d - r) <= err]
    inside = cand[d < r - err]
    if len(inside):
        return False, tuple(members), int(inside[np.argmin(d[d < r - err])])
    old = ctx.prec
    ctx.prec = 128
    try:
        for k in undecided.tolist():
            dk = site_distance_ball(E, k, X, Y)
            if dk > R:
                continue
            if dk < R:
                return False, tuple(members), k
            if E.kind[k] != POINT and min(E.ends[k]) >= 0 and _closest_at_an_end(E, k, X, Y):
                continue    # closest point of k is an end: a point site tested on its own (a
                #             smooth joint is not a site: then k is decided exactly below)
            from .exact import on_circle
            verdict = on_circle(E, triple, sol, k)
            if verdict is None:
                return None, tuple(members), k
            if verdict is False:
                return False, tuple(members), k
            if verdict == "on":
                members.append(k)
            # "outside": proved farther exactly
    finally:
        ctx.prec = old
    return True, tuple(members), None
