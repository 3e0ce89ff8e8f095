"""The link between the chain of strips of an unbounded edge and its tail to infinity.

The chain (:mod:`runtime.voronoi.verify.curved`) ends with a rectangle
{P0 + s·t + λ·n : s ∈ [0, L], |λ| ≤ w} in which the bisector β of the pair is proved to be one
arc, all of it closer to the pair than to the other sites.  :func:`link_arc` finds two points
Q± of the circle |q − m| = r through the rectangle's axis point at s_x, inside the rectangle
(shrunk by the arc's sagitta), with d_i − d_j of opposite proved signs: the arc of that circle
between them lies in the rectangle and β crosses it.  A tail prover that shows β to meet the
circle t = r exactly once in a sector containing that arc (:func:`runtime.voronoi.verify.tail.prove_tail`,
:func:`runtime.voronoi.verify.conic_tail.prove_conic_tail`) thereby starts its curve on the
chain's arc (β meets the rectangle in one arc): chain ∪ tail is the whole edge.

Public API: :func:`link_arc`.
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["link_arc"]

EPS = 2.0 ** -53


def link_arc(m, table, pair, link, scale):
    """(ok, message, φ−, φ+, r): the angles about m of Q− and Q+ and the circle's radius r
    (module docstring); ``link`` = (P0, t, n, L, w, s_x)."""
    i, j = pair
    P0, tv, nv, L, w, sx = link
    tv, nv, P0 = np.asarray(tv, float), np.asarray(nv, float), np.asarray(P0, float)
    X = P0 + sx * tv
    r = float(math.hypot(X[0] - m[0], X[1] - m[1]))
    thX = math.atan2(X[1] - m[1], X[0] - m[0])

    def lat(phi):
        return (m + r * np.array([math.cos(phi), math.sin(phi)]) - P0) @ nv

    dlat = -math.sin(thX) * nv[0] + math.cos(thX) * nv[1]
    if abs(dlat) < 0.2:
        return False, "the link circle is nearly tangent to the last proved strip", None, None, r
    Qs = []
    for target in (-0.97 * w, 0.97 * w):
        a_, b_ = thX, thX + 2.0 * (target - lat(thX)) / (r * dlat)
        for _ in range(80):                                 # float bisection on λ(φ) = target
            mid = 0.5 * (a_ + b_)
            if (lat(mid) - target) * (lat(a_) - target) > 0:
                a_ = mid
            else:
                b_ = mid
        Qs.append(0.5 * (a_ + b_))
    phi_lo, phi_hi = min(Qs), max(Qs)
    dl = 0.5 * (phi_hi - phi_lo)
    sag = r * dl * dl
    Q = np.array([[m[0] + r * math.cos(p_), m[1] + r * math.sin(p_)] for p_ in (phi_lo, phi_hi)])
    rel = Q - P0
    sc, lc = rel @ tv, rel @ nv
    # the circle's points at φ± are within 6u·(|m| + r) of the float Q (u = 2⁻⁵³: cos, the
    # product and the sum each rounded; √2 for the two coordinates)
    rnd = 6 * EPS * (abs(m[0]) + abs(m[1]) + r)
    pad = sag + 1e-12 * scale + 2 * rnd
    if not (np.all(sc > pad) and np.all(sc < L - pad) and np.all(np.abs(lc) < w - pad)):
        return False, "the link circle does not cross the last proved strip", None, None, r
    V = table.evaluate(np.concatenate([Q, Q]), [i, i, j, j])
    lo_i, hi_i, lo_j, hi_j = V.lo[:2], V.hi[:2], V.lo[2:], V.hi[2:]
    fl = 4 * rnd + 1e-15 * scale    # f = d_i − d_j is 2-Lipschitz: twice rnd, with a margin of 2
    pos = lo_i - hi_j > fl
    neg = hi_i - lo_j < -fl
    if not ((pos[0] and neg[1]) or (neg[0] and pos[1])):
        return False, "the bisector's crossing of the link circle is not decided", None, None, r
    return True, None, phi_lo, phi_hi, r
