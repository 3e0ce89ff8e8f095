"""Polyline nodes at the corners of a bisector on the medial axis of an ellipse containing it.

Inside an ellipse X²/a² + Y²/b² < 1 (a ≥ b, canonical frame) the nearest point of the ellipse
jumps across the ridge |X| < (a² − b²)/a, Y = 0 (the medial axis: H. I. Choi, S. W. Choi,
H. P. Moon, Pacific J. Math. 181 (1997)), so the bisector of the ellipse and a site nested in it
has a corner where it crosses that segment (there d_E = b·√(1 − X²/(a² − b²)): the normal
from (X, 0) meets the ellipse where cos θ = aX/(a² − b²)).
A polyline whose nodes all lie near the bisector can still cut such a corner by a chord, far
from the curve; the chord-midpoint measure of the stated tolerance misses it.  Here each
crossing of a polyline with a ridge gets a node at the corner: the root of f = d_i − d_j on the
axis, bracketed around the crossing and bisected in floats (a guide only: the verifier proves
the edge, :mod:`runtime.voronoi.verify.medial_corners`).

Public API: :func:`insert_ridge_nodes`.
"""
from __future__ import annotations

import numpy as np

__all__ = ["insert_ridge_nodes"]

BISECTIONS = 60
GROW = 40


def _axis(g):
    """(centre, unit major-axis vector, ridge half-length) of an ellipse geometry."""
    a, b = float(g.a), float(g.b)
    u = np.array([g.c, g.s]) if a >= b else np.array([-g.s, g.c])
    big, small = max(a, b), min(a, b)
    return np.array([g.tx, g.ty], float), u, (big - small) * (big + small) / big


def _root_on_axis(S, pair, cen, u, half, X0, step):
    """A float root of d_i − d_j on the major axis near X0, or None."""
    lab = np.array(pair, dtype=np.int64)

    def f(X):
        P = np.repeat((cen + X * u)[None, :], 2, axis=0)
        d, _ = S.dist_grad(P, lab)
        return d[0] - d[1]

    lim = half * (1 - 1e-9)
    st = step
    for _ in range(GROW):
        lo, hi = max(X0 - st, -lim), min(X0 + st, lim)
        flo, fhi = f(lo), f(hi)
        if np.sign(flo) * np.sign(fhi) < 0:
            break
        st *= 2
        if st > 4 * half:
            return None
    else:
        return None
    for _ in range(BISECTIONS):
        mid = 0.5 * (lo + hi)
        fm = f(mid)
        if fm == 0:
            return mid
        if np.sign(fm) == np.sign(flo):
            lo, flo = mid, fm
        else:
            hi = mid
    return 0.5 * (lo + hi)


def _near_box(S, Q, seg, H):
    """Mask of the segments k → k + 1 (``seg``) whose bounding box meets the bounding box of
    site H[m], widened by 1e-9 of the coordinates: a crossing of the ridge of ellipse H[m], a
    segment inside the ellipse, lies there even as computed in floats (the crossing point is
    within a few roundings of the segment and of the ridge)."""
    A, C, B = Q[seg], Q[seg + 1], S.boxes[H]
    lo, hi = np.minimum(A, C), np.maximum(A, C)
    with np.errstate(invalid="ignore", over="ignore"):
        m = 1e-9 * (np.abs(A).sum(axis=1) + np.abs(C).sum(axis=1) + np.abs(B).sum(axis=1) + 1.0)
        return ((lo[:, 0] <= B[:, 2] + m) & (hi[:, 0] >= B[:, 0] - m)
                & (lo[:, 1] <= B[:, 3] + m) & (hi[:, 1] >= B[:, 1] - m))


def insert_ridge_nodes(S, Q, own, PI, PJ):
    """The polylines (points Q, edge index ``own``, sorted by edge) with a node inserted at each
    crossing of an edge of an ellipse site with that ellipse's ridge (module docstring)."""
    if len(Q) < 2:
        return Q, own
    seg = np.nonzero(own[1:] == own[:-1])[0]            # segments k → k + 1 of one edge
    sides = [side[own[seg]] for side in (PI, PJ)]
    near = [np.unique(H[_near_box(S, Q, seg, H)]).tolist() for H in sides]
    ells = {h: _axis(S.geoms[h]) for h in sorted(set(near[0]) | set(near[1])) if S.geoms[h].kind == "ellipse"}
    if not ells:
        return Q, own
    ins_at, ins_pt = [], []
    for H, hs in zip(sides, near):
        for h in hs:
            if h not in ells:
                continue
            cen, u, half = ells[h]
            if half <= 0:
                continue
            ks = seg[H == h]
            D0, D1 = Q[ks] - cen, Q[ks + 1] - cen
            v = np.array([-u[1], u[0]])
            y0, y1 = D0 @ v, D1 @ v
            cross = y0 * y1 < 0
            t = np.where(cross, y0 / np.where(cross, y0 - y1, 1.0), 0.0)
            X0 = D0 @ u + t * ((D1 - D0) @ u)
            for k, x0 in zip(ks[cross & (np.abs(X0) < half)].tolist(), X0[cross & (np.abs(X0) < half)].tolist()):
                pair = (int(PI[own[k]]), int(PJ[own[k]]))
                step = max(1e-3 * float(np.hypot(*(Q[k + 1] - Q[k]))), 1e-12 * S.scale)
                X = _root_on_axis(S, pair, cen, u, half, x0, step)
                if X is None:
                    continue
                p = cen + X * u
                if min(np.hypot(*(p - Q[k])), np.hypot(*(p - Q[k + 1]))) <= 1e-12 * S.scale:
                    continue
                ins_at.append(k + 1)
                ins_pt.append(p)
    if not ins_at:
        return Q, own
    order = np.argsort(ins_at, kind="stable")
    at = np.array(ins_at)[order]
    return np.insert(Q, at, np.array(ins_pt)[order], axis=0), np.insert(own, at, own[at - 1])
