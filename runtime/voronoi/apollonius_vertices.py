"""Voronoi vertices of three circles or points (Apollonius vertices), refined and proved.

The candidate vertices of a triple are refined by vectorised Newton steps on d_a = d_b = d_c and
*proved* by Krawczyk's test (existence and uniqueness of the equidistant point in a box; Moore,
Kearfott & Cloud, *Introduction to Interval Analysis*, §8.2) in the kernel's float form
(:func:`runtime.certify.interval_newton.float_krawczyk_test`, every rounding bounded); this module
only supplies the enclosures of the distance system.  When the float test cannot decide, the exact
route of thesis §3.1.3 (:func:`runtime.predicates.circles.voronoi_vertices_circles`) decides.  Several candidates near
one true vertex are merged by their triple and a proof (one Krawczyk box holding all their Newton
points), never by a float tolerance alone.

Public API: :func:`newton_vertices`, :func:`krawczyk_circles`, :func:`apollonius_vertices`,
:func:`exact_vertex`.
"""
from __future__ import annotations

import math

import numpy as np

from ..certify.interval_newton import (UNIT_ROUNDOFF, float_contraction_bound, float_inverse, float_krawczyk_test,
                                       float_residual_bound, round_up)
from ..predicates.circles import voronoi_vertices_circles
from ..result import InvalidConicError, LocatorError
from .geometry import rounding_slack
from .site_arrays import SiteArrays

__all__ = ["newton_vertices", "krawczyk_circles", "apollonius_vertices", "exact_vertex"]


@np.errstate(invalid="ignore", over="ignore", divide="ignore")    # non-finite seeds are masked
def newton_vertices(S: SiteArrays, T3, Q, iters=30):
    """Float Newton on d_a = d_b = d_c (a, b, c = T3 columns) from seeds Q; vectorised over the
    candidates still moving (a candidate stops after a step below 1e-15 of its scale, or on a
    singular Jacobian).  Returns the points and the size of the last step (inf: singular)."""
    Q = np.array(Q, dtype=float)
    step = np.full(len(Q), np.inf)
    act = np.arange(len(Q))
    for _ in range(iters):
        if not len(act):
            break
        q, tr = Q[act], T3[act]
        da, Ua = S.dist_grad(q, tr[:, 0])
        db, Ub = S.dist_grad(q, tr[:, 1])
        dc, Uc = S.dist_grad(q, tr[:, 2])
        F1, F2 = da - db, da - dc
        J = np.stack([Ua - Ub, Ua - Uc], axis=1)          # (n, 2, 2)
        det = J[:, 0, 0] * J[:, 1, 1] - J[:, 0, 1] * J[:, 1, 0]
        with np.errstate(divide="ignore", invalid="ignore"):
            dx = (J[:, 1, 1] * F1 - J[:, 0, 1] * F2) / det
            dy = (-J[:, 1, 0] * F1 + J[:, 0, 0] * F2) / det
        # damp huge steps (a seed far from the vertex)
        ln = np.hypot(dx, dy)
        lim = 0.5 * np.maximum(np.minimum(np.minimum(da, db), dc), 1e-300) + 1e-300
        f = np.where(ln > lim * 4, lim * 4 / np.where(ln > 0, ln, 1), 1.0)
        ok = np.isfinite(dx) & np.isfinite(dy)
        dx = np.where(ok, dx * f, 0.0)
        dy = np.where(ok, dy * f, 0.0)
        Q[act, 0] -= dx
        Q[act, 1] -= dy
        st = np.where(ok, np.hypot(dx, dy), np.inf)
        step[act] = st
        moving = ok & (st > 1e-15 * (np.abs(Q[act]).sum(axis=1) + 1e-300))
        act = act[moving]
    return Q, step


def krawczyk_circles(S: SiteArrays, T3, M, h):
    """Krawczyk's test for F = (d_a − d_b, d_a − d_c) = 0 on the squares |q − M|∞ ≤ h (circles and
    points a, b, c = T3 columns), decided by the kernel's float test
    :func:`runtime.certify.interval_newton.float_krawczyk_test` (Krawczyk 1969; Moore, Kearfott &
    Cloud §8.2; its proof and rounding model there).  Returns (ok, rlo, rhi): where ok, the square
    holds exactly one equidistant point, simple, and the radius of its empty circle is in
    [rlo, rhi].

    The enclosures handed to the test, each with its rounding (u = 2^-53, ρB = h√2 the radius of
    the square's circumscribed disc, n = |M − c| and g = n − ρ in floats, both within
    s = :func:`runtime.voronoi.geometry.rounding_slack` of their values for the exact site):

    * the square meets no site and holds no centre (|g| > ρB + s, n > ρB + s + δ), so each
      d = |g| is smooth on it, with gradient U = ±(q − c)/|q − c|;
    * F(M) is within s_a + s_b + u|F̃| of its float value F̃;
    * the float gradient at M is within 8u of U(M) per component for the float centre C (a
      correctly rounded subtraction, hypot within 2u, a division), the exact centre c is within
      δ = 8u(|C_x| + |C_y|) of C, and U is 1/|q − c|-Lipschitz, so over the square every
      component of U is within L = (ρB + δ) / (n − s − ρB − δ) + 8u of the float one; a row of
      the Jacobian (U_a − U_b) is then within L_a + L_b + 2u|J̃| of the float row J̃.
    """
    u = UNIT_ROUNDOFF
    rB = h * math.sqrt(2)
    ds, Us, slack, lip = [], [], [], []
    ok = np.ones(len(M), bool)
    with np.errstate(divide="ignore", invalid="ignore"):
        for col in range(3):
            s = T3[:, col]
            V = M - S.C[s]
            n = np.hypot(V[:, 0], V[:, 1])
            g = n - S.R[s]
            sl = rounding_slack(np.abs(M).sum(axis=1) + np.abs(S.C[s]).sum(axis=1) + S.R[s])
            delta = 8 * u * np.abs(S.C[s]).sum(axis=1)
            ok &= (np.abs(g) > rB + sl) & (n > rB + sl + delta)
            sig = np.where(g >= 0, 1.0, -1.0)
            Us.append(sig[:, None] * V / n[:, None])
            lip.append(round_up((rB + delta) / (n - sl - rB - delta) + 8 * u))
            ds.append(np.abs(g))
            slack.append(sl)
        F = np.column_stack([ds[0] - ds[1], ds[0] - ds[2]])
        F_rad = round_up(np.column_stack([slack[0] + slack[1], slack[0] + slack[2]]) + u * np.abs(F))
        J = np.stack([Us[0] - Us[1], Us[0] - Us[2]], axis=1)
        L = np.column_stack([lip[0] + lip[1], lip[0] + lip[2]])          # per row, every entry
        J_rad = round_up(L[:, :, None] + 2 * u * np.abs(J))
        Y, invertible = float_inverse(J)
        proved, _ = float_krawczyk_test(float_residual_bound(Y, F, F_rad), float_contraction_bound(Y, J, J_rad),
                                        np.column_stack([h, h]))
    ok &= proved & invertible
    # the zero is within ρB of M and d_a is 1-Lipschitz; the sums below round by at most 4u·d_a
    pad = round_up(slack[0] + rB + 4 * u * ds[0])
    return ok, ds[0] - pad, ds[0] + pad


def apollonius_vertices(S: SiteArrays, T3, seeds, stats, known=None):
    """Refine, merge and prove the candidate vertices of circle/point triples.  Returns
    (cluster id per candidate, list of clusters, Newton points) where a cluster is a dict with x,
    y, h, rlo, rhi, ok (proved), triple, first (a member candidate).  ``known``: Newton points of an earlier round (NaN: not
    known) for candidates whose triangle did not change; the proofs are redone from them."""
    Q = np.full((len(T3), 2), np.nan) if known is None else np.array(known, dtype=float).reshape(-1, 2)
    todo = ~np.isfinite(Q).all(axis=1)
    if todo.any():
        Q[todo], _ = newton_vertices(S, T3[todo], seeds[todo])
    # group candidates of one triple whose Newton points nearly agree (consecutive in the order of
    # (triple, x, y) within 1e-9 of the scale); the proof box then holds every member
    scale = np.abs(Q).sum(axis=1) + 1.0
    key = np.lexsort((Q[:, 1], Q[:, 0], T3[:, 2], T3[:, 1], T3[:, 0]))
    Qs, Ts = Q[key], T3[key]
    finite = np.isfinite(Qs).all(axis=1)
    new = np.ones(len(key), bool)
    if len(key) > 1:
        near = np.abs(Qs[1:] - Qs[:-1]).sum(axis=1) <= 1e-9 * scale[key][1:]
        new[1:] = ~((Ts[1:] == Ts[:-1]).all(axis=1) & finite[1:] & finite[:-1] & near)
    heads = np.nonzero(new)[0]
    cs = np.cumsum(new) - 1
    cid = np.empty(len(T3), dtype=np.int64)
    cid[key] = cs
    M = Qs[heads].reshape(-1, 2)
    TT = Ts[heads].reshape(-1, 3)
    spread = np.zeros(len(heads))
    if len(key):
        with np.errstate(invalid="ignore", over="ignore"):          # non-finite rows are masked
            dev = np.where(finite[:, None], np.abs(Qs - M[cs]), 0.0).max(axis=1)
        np.maximum.at(spread, cs, dev)
    clusters = [{"triple": tuple(tr), "first": f, "x": x, "y": y}
                for tr, f, (x, y) in zip(TT.tolist(), key[heads].tolist(), M.tolist())]
    nC = len(clusters)
    fin = np.isfinite(M).all(axis=1)
    Mf = np.where(fin[:, None], M, 0.0)
    sc = np.abs(Mf).sum(axis=1) + S.R[TT].max(axis=1) + 1.0
    ok = np.zeros(nC, bool)
    rlo = np.zeros(nC)
    rhi = np.zeros(nC)
    hh = np.zeros(nC)
    for factor in (1e-12, 1e-9, 1e-6):
        todo = fin & ~ok
        if not todo.any():
            break
        h = np.maximum(factor * sc[todo], 4 * spread[todo] + 1e-300)
        o, lo, hi = krawczyk_circles(S, TT[todo], Mf[todo], h)
        idx = np.nonzero(todo)[0]
        ok[idx[o]] = True
        rlo[idx[o]], rhi[idx[o]], hh[idx[o]] = lo[o], hi[o], h[o]
    stats["krawczyk_filter_failures"] = stats.get("krawczyk_filter_failures", 0) + int((fin & ~ok).sum())
    stats["triple_solves"] = stats.get("triple_solves", 0) + nC
    for c, (o, lo, hi, h) in enumerate(zip(ok, rlo, rhi, hh)):
        clusters[c].update(ok=bool(o), rlo=float(lo), rhi=float(hi), h=float(h), exact=None)
    # exact fallback (thesis §3.1.3) where the filter could not decide
    for c in np.nonzero(~ok)[0].tolist():
        cl = clusters[c]
        stats["exact_vertex_calls"] = stats.get("exact_vertex_calls", 0) + 1
        stats["full_triple_solves"] = stats.get("full_triple_solves", 0) + 1
        i, j, k = cl["triple"]
        try:
            tv = voronoi_vertices_circles(S.sites[i], S.sites[j], S.sites[k])
        except (LocatorError, InvalidConicError):
            continue
        if not tv.vertices:
            continue
        sx, sy = (cl["x"], cl["y"]) if np.isfinite(cl["x"]) else tuple(seeds[cl["first"]])
        v = min(tv.vertices, key=lambda v: math.hypot(v.x - sx, v.y - sy))
        eps = 4e-16 * (abs(v.x) + abs(v.y) + v.radius) + 1e-300
        cl.update(x=v.x, y=v.y, ok=True, rlo=v.radius - eps, rhi=v.radius + eps, h=eps,
                  exact=(tv, v))
    return cid, clusters, Q



def exact_vertex(S, cl):
    i, j, k = cl["triple"]
    tv = voronoi_vertices_circles(S.sites[i], S.sites[j], S.sites[k])
    if not tv.vertices:
        raise ValueError("no vertex")
    v = min(tv.vertices, key=lambda v: math.hypot(v.x - cl["x"], v.y - cl["y"]))
    if math.hypot(v.x - cl["x"], v.y - cl["y"]) > 1e-6 * (abs(v.x) + abs(v.y) + v.radius + 1):
        raise ValueError("exact vertex is not the float one")
    return tv, v

