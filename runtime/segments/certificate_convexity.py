"""Straight edges of two segments next to crowded vertices, settled by convexity (rule R3 of
:mod:`runtime.segments.certificate_edges`, at the end vertices' own balls).

Along the bisector line c(τ) = O + τ w of two segments i and j the edge's distance ρ is affine
(the signed distance to i's line; the feet stay in the segments between the proved ends), and the
distance d_k to a point or a segment (a closed convex set) is convex in τ; so g_k = d_k − ρ is
convex on the edge's parameter interval [a, b] and lies above its tangents at a and b.  With
a, b the parameters of the two proved end vertices (tight arb balls, not floats), g_k > 0 on the
open interval (a, b) in each of these cases:

1. g_k(a) ≥ 0 and g_k'(a) > 0 (the tangent at a is positive beyond a), or g_k(b) ≥ 0 and
   g_k'(b) < 0;
2. g_k(a) > 0 and g_k'(a) ≥ 0, or g_k(b) > 0 and g_k'(b) ≤ 0;
3. g_k(a), g_k(b) > 0, g_k'(a) < 0 < g_k'(b) and the tangents' zeros are ordered:
   a − g_k(a)/g_k'(a) > b − g_k(b)/g_k'(b).

g_k(a) ≥ 0 holds exactly for a site listed at the vertex (it is at the radius there, by the
vertex proof); otherwise it is proved > 0 in arb.  g_k'(a) exists: the vertex is off the closed
site k (a listed site at a vertex of positive radius, or a site not listed, whose distance is
> ρ ≥ 0 there; a site listed at a corner is not tried).  This is what a cluster of vertices within 10⁻¹⁵ of each other needs
(regular polygons with float coordinates, :mod:`runtime.segments.near_degenerate`): there every
side of the polygon is within 10⁻¹⁶ of the radius at both ends of a tiny edge, and float
parameters (and pieces of float width) cannot separate the ties, while the end vertices' balls
from Krawczyk at the certificate's precision can.  Such an edge (a site not listed at an end vertex within 10⁻⁹ of its radius, an edge shorter than
10⁻⁹, or float parameters coarser than that: nearly parallel segments, whose bisector is
parametrised from their far intersection) has every site near it tried; other edges only their
near ties at the end vertices, and the rest is left to the pieces.

Public API: :func:`settled_by_convexity`, :func:`convex_positive`.
"""
from __future__ import annotations

import numpy as np

from .certificate_curves import Line
from .certificate_pieces import distance_gradient
from .certificate_sites import ARC

__all__ = ["settled_by_convexity", "convex_positive", "NEAR_TIE"]

EPS = float(np.finfo(float).eps)
#: a site within this (times 1 + |x| + |y| + r) of an end vertex's radius is tried here
NEAR_TIE = 1e-9


def settled_by_convexity(pr, lo, hi) -> set:
    """The sites k (not i, j, not already settled in ``pr.skip``) proved farther than the edge's
    sites on the whole open edge by the tangent cases of the module docstring; ``lo``, ``hi``:
    the edge's ends ("v", parameter, vertex proof, id).  Empty unless the edge is straight between
    two segments with two proved end vertices of positive radius."""
    c, T = pr.curve, pr.T
    if not (isinstance(c, Line) and c.anchor is None and c.side is not None and lo[0] == "v" and hi[0] == "v"):
        return set()
    ends = (lo, hi)
    if not all(end[2].ok and end[2].x is not None and end[2].r is not None for end in ends):
        return set()
    cands: set = set()
    for end in ends:
        vp = end[2]
        x, y, r = float(vp.x.mid()), float(vp.y.mid()), float(vp.r.mid())
        tol = NEAR_TIE * (1 + abs(x) + abs(y) + r)
        idx = np.array([k for k in T.near(x, y, r + tol) if k not in (pr.i, pr.j) and k not in pr.skip
                        and T.kind[k] != ARC], dtype=int)
        if len(idx):
            dlo, _dhi = T.float_bounds(idx, np.repeat([[x, y]], len(idx), axis=0))
            cands.update(int(k) for k in idx[dlo <= r + tol])
    (x0, y0, r0), (x1, y1, r1) = ((float(e[2].x.mid()), float(e[2].y.mid()), float(e[2].r.mid())) for e in ends)
    length = abs(x1 - x0) + abs(y1 - y0)
    scale = 1 + max(abs(x0), abs(y0), abs(x1), abs(y1), r0, r1)
    w = float(abs(c.w[0]).upper()) + float(abs(c.w[1]).upper())
    coarse = EPS * max(abs(float(lo[1].mid())), abs(float(hi[1].mid()))) * w
    if not cands and length > NEAR_TIE * scale and coarse <= NEAR_TIE * scale:
        return set()
    # crowded, tiny, or its float parameters too coarse for pieces: every site near the edge
    idx = T.near((x0 + x1) / 2, (y0 + y1) / 2, length / 2 + max(r0, r1) + NEAR_TIE * scale)
    cands.update(int(k) for k in idx if k not in (pr.i, pr.j) and k not in pr.skip and T.kind[k] != ARC)
    out = set()
    for k in sorted(cands):
        if convex_positive(T, c, k, lo, hi):
            out.add(k)
    return out


def _end_values(T, c, k, end):
    """(g_k ≥ 0 known, g_k > 0 proved, g_k, g_k') at the end vertex ``end``; None for a site listed
    at a vertex not proved of positive radius (a corner on k: no derivative there)."""
    tau, vp = end[1], end[2]
    if k in vp.listed and not (vp.corner is None and vp.r > 0):
        return None
    X, Y = c.xy(tau)
    g = T.distance(k, X, Y) - c.rho(tau, X, Y)
    gx, gy = distance_gradient(T, k, X, Y)
    w = c.dxy(tau)
    dg = gx * w[0] + gy * w[1] - c.drho(tau, X, Y)
    pos = bool(g > 0)
    return (k in vp.listed) or pos, pos, g, dg


def convex_positive(T, c, k, lo, hi) -> bool:
    """g_k > 0 on the open edge by cases 1–3 of the module docstring (False for an arc k: its
    distance is not convex along lines)."""
    if T.kind[k] == ARC:
        return False
    va, vb = _end_values(T, c, k, lo), _end_values(T, c, k, hi)
    if va is None or vb is None:
        return False
    (na, pa, ga, da), (nb, pb, gb, db) = va, vb
    if not (da.is_finite() and db.is_finite()):
        return False
    if (na and da > 0) or (nb and db < 0):
        return True
    if (pa and da >= 0) or (pb and db <= 0):
        return True
    if pa and pb and da < 0 and db > 0:
        za = lo[1] - ga / da
        zb = hi[1] - gb / db
        return bool(za > zb)
    return False
