"""Unbounded edges between mirror-image sites, to infinity (thesis §1.2; grids of identical shapes).

When identical shapes sit in a row, several of them tie for the largest support value h_k(θ*)
in the direction θ* of the row's normal: their unbounded edges are parallel, and the sector
argument of :mod:`runtime.voronoi.verify.tail` (a cone of directions where only the edge's two
sites lead) cannot exist.  Such rows are mirror-symmetric, and mirrors give exact facts
(:mod:`runtime.predicates.symmetry`): if the reflection in a rational line ℓ maps site i onto
site j, with i and j strictly on opposite sides, the bisector of i and j is exactly ℓ.

:func:`prove_mirror_tail` proves the edge (i, j) beyond the chain of strips
(:mod:`runtime.voronoi.verify.curved`) when i and j are mirror images: the chain's last rectangle
proved that the bisector ℓ crosses it in one arc, all closer to i, j than to the other sites; let
P be the exact point of ℓ on the rectangle's link position and R = {P + t·u : t ≥ 0} the ray of ℓ
going out.  Every other site k is proved strictly farther than i (= j) on R by one of

(A) **support**: with F a point of site i (its foot from P, a float within rounding of the curve),
    a = (P − F)·u > 0 and b = (P − F)·u⊥: for q = P + t·u, d_i(q) ≤ |q − F| ≤ a + t + b²/(2a)
    and d_k(q) ≥ (q − m)·u − h_k(u) (the supporting line of k), so
    d_k − d_i ≥ (F − m)·u − h_k(u) − b²/(2a) > 0 suffices (all widened by rounding bounds);
(B) **mirror**: a reflection maps i (or j) exactly onto k, with i (or j) and the whole ray strictly
    on one side of its line (exact rational signs for the ray, float margins for the site's box):
    then d_i < d_k on that open half-plane.

Then R is part of the edge, to infinity, and the edge is the chain's arc followed by R.  For the
accounting of the ends at infinity (:func:`runtime.voronoi.verify.closure.verify_accounting_conics`)
the end is recorded with its exact direction u (a rational vector) and the pair: ends in one
direction are checked there against the sites tied in that direction.

Public API: :func:`prove_mirror_tail`.
"""
from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

from ...predicates.symmetry import mirror_line

__all__ = ["prove_mirror_tail"]


def _side_box(box, n, k):
    """The strict side (+1, −1) of the line n·q = k on which the float box lies, with a margin
    (0: not decided)."""
    x0, y0, x1, y1 = box
    if not all(math.isfinite(v) for v in box):
        return 0
    nx, ny, kf = float(n[0]), float(n[1]), float(k)
    vals = [nx * x + ny * y - kf for x in (x0, x1) for y in (y0, y1)]
    marg = 1e-9 * (abs(nx) + abs(ny)) * (abs(x0) + abs(x1) + abs(y0) + abs(y1) + 1.0) + 1e-9 * abs(kf)
    if min(vals) > marg:
        return 1
    if max(vals) < -marg:
        return -1
    return 0


def prove_mirror_tail(sites, geoms, sup, pair, link):
    """Prove the end of edge (i, j) beyond the chain's last rectangle ``link`` (as in
    :func:`runtime.voronoi.verify.tail.prove_tail`) when i and j are mirror images (module
    docstring).  Returns (ok, message, end) with end = (exact direction (ux, uy), lateral
    coordinate of the ray's line) for the accounting, or None."""
    i, j = pair
    line = mirror_line(sites[i], sites[j])
    if line is None:
        return False, "no mirror maps its two sites onto each other", None
    n, k = line
    si, sj = _side_box(geoms[i].bounding_box(), n, k), _side_box(geoms[j].bounding_box(), n, k)
    if si == 0 or sj == 0 or si == sj:
        return False, "its sites are not strictly on opposite sides of their mirror", None
    P0, tv, nv, L, w, sx = link
    X = np.asarray(P0, float) + sx * np.asarray(tv, float)
    Xq = (Fraction(float(X[0])), Fraction(float(X[1])))
    nn = n[0] * n[0] + n[1] * n[1]
    lam = (n[0] * Xq[0] + n[1] * Xq[1] - k) / nn
    P = (Xq[0] - lam * n[0], Xq[1] - lam * n[1])          # exact point of ℓ near X
    Pf = np.array([float(P[0]), float(P[1])])
    if abs(float((Pf - X) @ np.asarray(nv, float))) > 0.5 * w:
        return False, "the mirror line leaves the chain's last rectangle", None
    d = (-n[1], n[0])                                      # direction of ℓ, exact
    if (float(d[0]) * (X[0] - sup.m[0]) + float(d[1]) * (X[1] - sup.m[1])) < 0:
        d = (n[1], -n[0])                                  # the outward one
    dn = math.hypot(float(d[0]), float(d[1]))
    u = np.array([float(d[0]), float(d[1])]) / dn
    uperp = np.array([-u[1], u[0]])
    th = math.atan2(u[1], u[0])
    scale = float(np.abs(Pf).sum() + sup.W + np.abs(sup.m).sum() + 1.0)
    eps = 1e-12 * scale + 8 * sup.mu
    # (A) support bound, with F the foot of i (and of j) from P
    feet = []
    for s in (i, j):
        F, _ = geoms[s].foot_points(Pf[None, :])
        a = float((Pf - F[0]) @ u)
        b = float((Pf - F[0]) @ uperp)
        if a > 0:
            feet.append((float((F[0] - sup.m) @ u) - b * b / (2 * a) * (1 + 1e-9) - eps))
    base = max(feet) if feet else -math.inf
    others = np.array([t for t in range(len(geoms)) if t not in pair], int)
    if not len(others):
        return True, None, ((d[0], d[1]), float(Pf @ uperp))
    hk = sup.h(others, np.full(len(others), th))
    todo = others[~(base - hk - sup.mu > 0)]
    # (B) mirrors onto the remaining sites
    for t in todo.tolist():
        for s in (i, j):
            ml = mirror_line(sites[s], sites[t])
            if ml is None:
                continue
            m2, k2 = ml
            side = _side_box(geoms[s].bounding_box(), m2, k2)
            val = m2[0] * P[0] + m2[1] * P[1] - k2
            slope = m2[0] * d[0] + m2[1] * d[1]
            if side != 0 and val * side > 0 and slope * side >= 0:
                break
        else:
            return False, f"site {t} is not proved farther on the mirror line to infinity", None
    return True, None, ((d[0], d[1]), float(Pf @ uperp))
