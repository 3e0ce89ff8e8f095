"""Exact edge proofs among point sites: the bisector of two points is a line (thesis §3.1, ρ = 0).

On the bisector of the points p_i, p_j, written q(t) = m + t·n with m = (p_i + p_j)/2 and
n = rot90(p_j − p_i), the power difference of a third point p_k,

    f_k(t) = |q(t) − p_k|² − |q(t) − p_i|² = |m − p_k|² − |m − p_i|² + 2t·n·(p_i − p_k),

is affine in t with rational coefficients, and d_k > d_i ⟺ f_k > 0.  So "p_k is farther than
p_i, p_j on the open edge t ∈ (t0, t1)" is decided exactly from the signs of f_k at the ends
(t0, t1 rational: a vertex of point sites is the circumcentre of three of them) and of the slope
at an infinite end.  This decides the cases the float bounds cannot: third points that tie at
infinity (collinear points: parallel bisectors, f_k constant along the edge), and third points
that touch an end vertex.

Public API: :func:`point_edge_clear`, :func:`circumcentre`.
"""
from __future__ import annotations

from fractions import Fraction

__all__ = ["point_edge_clear", "circumcentre"]


def _xy(g):
    return Fraction(int(g.exact.cx.p), int(g.exact.cx.q)), Fraction(int(g.exact.cy.p), int(g.exact.cy.q))


def circumcentre(geoms, sites):
    """The exact centre of the circle through the point sites ``sites[:3]`` (None if collinear)."""
    (ax, ay), (bx, by), (cx, cy) = (_xy(geoms[s]) for s in sites[:3])
    d = 2 * (ax * (by - cy) + bx * (cy - ay) + cx * (ay - by))
    if d == 0:
        return None
    a2, b2, c2 = ax * ax + ay * ay, bx * bx + by * by, cx * cx + cy * cy
    return ((a2 * (by - cy) + b2 * (cy - ay) + c2 * (ay - by)) / d,
            (a2 * (cx - bx) + b2 * (ax - cx) + c2 * (bx - ax)) / d)


def point_edge_clear(geoms, i, j, k, end0, end1) -> bool:
    """Is point site k strictly farther than the point sites i, j on the whole open edge?

    ``end0``, ``end1``: the edge's ends, each a tuple of the end vertex's sites or
    ``("inf", s)``: infinity in the direction s·rot90(p_j − p_i), s = ±1.  All sites must be
    points.  Exact (rational arithmetic)."""
    (ix, iy), (jx, jy), (kx, ky) = _xy(geoms[i]), _xy(geoms[j]), _xy(geoms[k])
    mx, my = (ix + jx) / 2, (iy + jy) / 2
    nx, ny = -(jy - iy), jx - ix
    alpha = (mx - kx) ** 2 + (my - ky) ** 2 - (mx - ix) ** 2 - (my - iy) ** 2
    beta = 2 * (nx * (ix - kx) + ny * (iy - ky))
    n2 = nx * nx + ny * ny
    ts = []
    for end in (end0, end1):
        if end[0] == "inf":
            ts.append(("inf", end[1]))
            continue
        c = circumcentre(geoms, end)
        if c is None:
            return False
        ts.append(("t", ((c[0] - mx) * nx + (c[1] - my) * ny) / n2))
    for kind, val in ts:
        if kind == "inf":
            # f_k → sign(beta)·val·∞ (or alpha when beta = 0)
            if beta * val < 0 or (beta == 0 and alpha <= 0):
                return False
        elif alpha + beta * val < 0:
            return False
    # both ends ≥ 0; f_k affine: positive on the open interval unless identically zero
    return not (beta == 0 and alpha == 0)
