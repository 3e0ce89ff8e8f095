"""Emptiness of a candidate vertex's circle among points and segments (thesis §1.2).

A proved zero (x, y, r) of three sites' contact system is a Voronoi vertex when no other site
comes closer than r.  Candidates: the sites with a sample within r + h/2 of the centre (h the
largest sample spacing: every point of a segment lies within h/2 of one of its samples, so a site
without such a sample is farther than r), with a rounding margin.  Each candidate is decided by a
float filter with a rounding-error bound (:func:`runtime.segments.distance.float_error`), then
by arb balls (:func:`runtime.segments.distance.distance_ball`), then exactly
(:mod:`runtime.segments.exact`) when the balls cannot separate d from r: a site exactly on the
circle is a further member of the vertex (degree k > 3).

Many vertices at once: :func:`empty_by_filter` runs the float filter on all of them together
(one k-d tree query, one vectorised distance evaluation) and answers those it proves empty and
those with a site proved inside by the same bound; :func:`prove_empty` takes the rest one by one.

Public API: :func:`prove_empty`, :func:`empty_by_filter`, :func:`filter_block`.
"""
from __future__ import annotations

import numpy as np
from flint import ctx

from ..certify.foot import to_arb
from .distance import float_error, foot_parameter, site_distance_ball, site_distances
from .elementary import ARC, ELLIPSE, POINT, SEGMENT, ElementarySites
from .ellipse_contacts import ellipse_centre_sites
from .ellipse_pieces import closest_at_an_end
from .vertices import direction_in_arc

__all__ = ["prove_empty", "empty_by_filter", "filter_block"]


def _closest_at_an_end(E: ElementarySites, k: int, X, Y) -> bool:
    """Proved: the closest point of curve k to every point of the ball box is one of its ends
    (a segment's foot parameter outside [0, 1], an arc's direction outside its range)."""
    if E.kind[k] == ELLIPSE:            # the nearest end must be a point site (not a smooth joint)
        ends = closest_at_an_end(E.ellipse[k], X, Y)
        return ends is not None and all(int(E.ends[k, e]) >= 0 for e in ends)
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
    if sol.reason == "ellipse centre":
        # the sites at the minor vertices are exactly on the circle (ellipse_centre_sites)
        on = ellipse_centre_sites(E, next(int(t) for t in triple if E.kind[t] == ELLIPSE))
        members += sorted(k for k in on if k not in members)
        triple = tuple(members)
        cand = np.array([k for k in cand.tolist() if k not in on], dtype=np.int64)
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
            if E.kind[k] != POINT and (min(E.ends[k]) >= 0 or E.kind[k] == ELLIPSE) \
                    and _closest_at_an_end(E, k, X, Y):
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


#: jobs per block of :func:`empty_by_filter` (the k-d tree's hit lists are Python lists)
FILTER_BLOCK = 20000


def empty_by_filter(E: ElementarySites, tree, lab, hmax: float, jobs) -> dict:
    """:func:`filter_block` on blocks of :data:`FILTER_BLOCK` jobs (bounded memory)."""
    out: dict = {}
    for k in range(0, len(jobs), FILTER_BLOCK):
        out.update(filter_block(E, tree, lab, hmax, jobs[k:k + FILTER_BLOCK]))
    return out


def filter_block(E: ElementarySites, tree, lab, hmax: float, jobs) -> dict:
    """For ``jobs`` = [(triple, sol), ...] of proved zeros, the verdicts (True, triple, None) of
    those whose every other site within reach is proved farther than r by the float filter of
    :func:`prove_empty` (same reach, same error bound), and the verdicts (False, triple, k) of
    :func:`prove_empty`'s float test of the others -- a site k proved closer than r (the nearest
    such, the lowest index on a tie), keyed by ``id(sol)``; the others are left to
    :func:`prove_empty` (arc centres always are)."""
    jobs = [(t, s) for t, s in jobs if s.reason not in ("arc centre", "ellipse centre")]
    if not jobs:
        return {}
    X = np.array([[s.x, s.y] for _, s in jobs])
    r = np.array([s.r for _, s in jobs])
    rad = np.array([max(float(s.box[0].rad()), float(s.box[1].rad())) for _, s in jobs])
    Rrad = np.array([float(s.box[2].rad()) for _, s in jobs])
    scale = 1.0 + np.abs(X).sum(axis=1) + r
    reach = r + hmax / 2 + 1e-9 * scale + rad
    hits = tree.query_ball_point(X, reach)
    lens = np.fromiter((len(h) for h in hits), dtype=np.int64, count=len(hits))
    if lens.sum():
        rows = np.repeat(np.arange(len(jobs), dtype=np.int64), lens)
        cols = lab[np.concatenate([np.asarray(h, dtype=np.int64) for h in hits if len(h)])].astype(np.int64)
        T = np.array([tuple(t) for t, _s in jobs], dtype=np.int64).reshape(len(jobs), -1)
        keep = ~(cols[:, None] == T[rows]).any(axis=1)
        # one row per (job, site): the distinct sites within reach, other than the triple's
        key = np.unique(rows[keep] * (int(lab.max()) + 1) + cols[keep])
        rows, cols = key // (int(lab.max()) + 1), key % (int(lab.max()) + 1)
    else:
        rows = cols = np.empty(0, np.int64)
    ok = np.ones(len(jobs), dtype=bool)
    if len(rows):
        Q = X[rows]
        d = site_distances(E, cols, Q)
        arcs = np.nan_to_num(np.hypot(*E.C[cols].T) + E.rho[cols])
        ferr = float_error(E.A[cols], E.B[cols], Q)
        err = ferr + 64 * np.finfo(float).eps * arcs + rad[rows] * 2 + Rrad[rows] + 1e-15 * scale[rows]
        bad = ~(d - r[rows] > err)
        # a segment whose closest point is its end, itself a site of the triple (then d = r and
        # that end decides, as in prove_empty): its foot parameter well outside [0, 1]
        seg = bad & (E.kind[cols] == SEGMENT)
        if seg.any():
            i = np.nonzero(seg)[0]
            A_, B_ = E.A[cols[i]], E.B[cols[i]]
            D = B_ - A_
            t = np.einsum("ij,ij->i", Q[i] - A_, D) / np.einsum("ij,ij->i", D, D)
            trip = T[rows[i]]
            e0 = (trip == E.ends[cols[i], 0][:, None]).any(axis=1)
            e1 = (trip == E.ends[cols[i], 1][:, None]).any(axis=1)
            beyond = ((t < -1e-9) & e0) | ((t > 1 + 1e-9) & e1)
            bad[i[beyond]] = False
        ok[np.unique(rows[bad])] = False
        entered = _entered(X, r, rad, Rrad, rows, cols, d, arcs, ferr, ok)
    else:
        entered = {}
    out = {id(s): (True, tuple(t), None) for (t, s), good in zip(jobs, ok.tolist()) if good}
    for i, k in entered.items():
        out[id(jobs[i][1])] = (False, tuple(jobs[i][0]), k)
    return out


def _entered(X, r, rad, Rrad, rows, cols, d, arcs, ferr, ok) -> dict:
    """:func:`prove_empty`'s float test of the pairs (job ``rows``, site ``cols``) at distance
    ``d`` of the jobs not ``ok``: job -> the site proved closer than r by its error bound (the
    same sum, in the same order, with its scale 1 + |x| + |y| + r), the nearest, the lowest index
    on a tie (prove_empty's candidates are sorted)."""
    scale = 1.0 + np.abs(X[:, 0]) + np.abs(X[:, 1]) + r
    err = ferr + 64 * np.finfo(float).eps * arcs + rad[rows] * 2 + Rrad[rows] + 1e-15 * scale[rows]
    inside = np.nonzero(~ok[rows] & (d < r[rows] - err))[0]
    if not len(inside):
        return {}
    order = inside[np.lexsort((cols[inside], d[inside], rows[inside]))]
    first = np.ones(len(order), bool)
    first[1:] = rows[order][1:] != rows[order][:-1]
    return dict(zip(rows[order][first].tolist(), cols[order][first].tolist()))
