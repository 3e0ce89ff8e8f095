"""Roots of the toric null space in world coordinates (thesis §5.5; Telen, Mourrain and Van Barel).

:func:`runtime.solve.toric.solve_toric` solves the offsets of a triple in circle space, where
vertices far from the sites are ordinary points.  This module makes it one attempt of
:func:`runtime.solve.generalised.generalised_vertices`: when a cluster of roots stays unresolved
in the scene's frame, the system is solved again in a frame centred at the cluster
(:func:`toric_attempt`); the roots are then Newton-refined in (x, y, R) only where that helps
(:func:`refine_toric_roots`).

Public API: :func:`toric_attempt`, :func:`refine_toric_roots`, :data:`RECENTRE_SCALE`,
:data:`TORIC_DISTINCT_TOL`.
"""
from __future__ import annotations

import numpy as np

from ..algebra.polyalg import WorkingFrame, compose_offset
from ..result import LocatorError
from .macaulay import SolveInfo, add_timings
from .newton import RESIDUAL_TOL, newton_refine
from .toric import DILATION_STEPS, ToricShort, solve_toric

__all__ = ["toric_attempt", "refine_toric_roots", "RECENTRE_SCALE", "TORIC_DISTINCT_TOL"]

#: scale of the frame centred at the least accurate root of a provisional toric list, relative to
#: the scene's (:func:`toric_attempt`)
RECENTRE_SCALE = 1 / 3
#: refined toric roots closer than this (max-norm, scaled by the frame (L, L, L²)) count as one
#: root; they come deduplicated from circle space (:func:`runtime.solve.toric.projective_newton`)
TORIC_DISTINCT_TOL = 1e-13


def toric_attempt(polys, offs, expected, wf):
    """The toric null space (:func:`runtime.solve.toric.solve_toric`) as an attempt of
    :func:`runtime.solve.generalised.generalised_vertices`: roots in working coordinates, a
    SolveInfo, and the working frame of the roots.

    When the first column polytope leaves a cluster unresolved (fewer distinct roots than the
    bound, or a provisional list), the system is solved again in the frame with the same rotation,
    centred at the cluster (:meth:`runtime.solve.toric._Pool.cluster_centres`: where the traces put
    the missing roots, then the least accurate pooled root, until one list is not provisional), of
    :data:`RECENTRE_SCALE` times the scale; that list is taken unless it is provisional too, and
    otherwise the scene's frame goes on with the next polytope, its pool kept.  Why: the scene's frame is centred between the sites, and a cluster of
    roots next to the sites but far from that centre is a small relative perturbation of large
    coordinates (T = x² + y² − R with R ≪ x² + y²), which the eigenvectors mix.  Measured on three
    hyperbolas 100× apart (seed 703): ten roots within 3–15 units of (146, 30), four real and two of
    them true vertices, 1 % of the frame's scale 305 apart; ten eigenvalue problems on two polytopes
    left seven of them missing (177 distinct of 184; msolve answered in 3.4–5 s), and centred there
    the toric null space finds all 184."""
    families = [o.family for o in offs]
    first, rest = DILATION_STEPS[:1], DILATION_STEPS[1:]
    found, timings, pool, centres, failure = [], {}, None, [], None
    try:
        roots, tinfo = solve_toric(polys, families, expected, dilations=first)
        found.append((roots, tinfo, wf))
        centres = tinfo.centres if tinfo.provisional else []
    except ToricShort as exc:
        pool, centres, failure = exc.pool, exc.pool.cluster_centres(), exc
        add_timings(timings, exc.timings)
    except LocatorError as exc:
        failure = exc
    for centre in centres:
        x, y = wf.to_world(*centre)
        wf2 = WorkingFrame(wf.cos, wf.sin, float(x), float(y), wf.L * RECENTRE_SCALE)
        try:
            roots2, tinfo2 = solve_toric([compose_offset(o, wf2) for o in offs], families, expected)
        except LocatorError:
            continue
        found.append((roots2, tinfo2, wf2))
        if not tinfo2.provisional:
            break
    centred_better = any(f is not wf and (not t.provisional or pool is None or t.distinct > pool.count())
                         for _, t, f in found)
    if not centred_better and rest and (pool is not None or (found and found[0][1].provisional)):
        # the scene's frame goes on with the next polytopes, the first polytope's roots kept
        # (unless the centred frame resolved more of the cluster)
        pool = pool if pool is not None else found[0][1].pool
        try:
            found.append((*solve_toric(polys, families, expected, dilations=rest, pool=pool), wf))
        except LocatorError as exc:
            failure = exc
    if not found:
        raise failure
    for _, t, _ in found:
        add_timings(timings, t.timings)
    # a list that is not provisional, else the one with the most distinct roots (the earlier on a tie)
    result = min(found, key=lambda r: (r[1].provisional, -r[1].distinct))
    result[1].timings = timings
    roots, tinfo, wf = result
    info = SolveInfo(-1, tinfo.n_finite, -1, {}, tinfo.rank_ratio, tinfo.matrix_shape,
                     f"toric {tinfo.polytope}", timings=dict(tinfo.timings), root_residuals=tinfo.residuals,
                     provisional=tinfo.provisional, padded=tinfo.padded)
    return roots, info, wf


def refine_toric_roots(offs, pts, cs_res, L):
    """Newton in (x, y, R) on the roots of the toric null space, already refined in circle space
    (backward errors ``cs_res`` < 1e-12 there).  Near the scene it sharpens an ill-conditioned
    root whose (x, y, R) residual is large; far away, or in a cluster of nearby roots, it can move
    a root along the ill-conditioned direction or onto its neighbour (measured: two of 184 merged).
    So a refined root is kept only where the circle-space one had a large (x, y, R) residual, the
    refined one has a small one, and the refined roots stay distinct; elsewhere the circle-space
    root stays, with its residual."""
    out, r0, cond = newton_refine(offs, pts, iters=0, scale=L)
    res = np.minimum(r0, cs_res)
    # only roots whose (x, y, R) residual shows they need it: Newton on a far root with a tiny
    # residual already moves it along the ill-conditioned direction (measured 2e-6 relative)
    need = np.nonzero(~(r0 < RESIDUAL_TOL))[0]
    if len(need) == 0:
        return out, res, cond
    p1, r1, c1 = newton_refine(offs, pts[need], scale=L)
    take = need[np.isfinite(r1) & (r1 < RESIDUAL_TOL)]
    keep = np.isin(need, take)
    new = out.copy()
    new[take] = p1[keep]
    # a refined root that coincides with another root slid onto it: keep its circle-space value
    D = np.array([L, L, L * L])
    P = new / D[None, :]
    close = np.abs(P[take, None, :] - P[None, :, :]).max(axis=2) <= TORIC_DISTINCT_TOL
    close[np.arange(len(take)), take] = False
    take, keep_idx = take[~close.any(axis=1)], np.nonzero(keep)[0][~close.any(axis=1)]
    out[take], res[take], cond[take] = p1[keep_idx], r1[keep_idx], c1[keep_idx]
    return out, res, cond
