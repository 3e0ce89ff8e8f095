"""A curved edge leaving a corner (radius 0) — an arc's bisector from the point site c where its
arc and its partner end (for :meth:`runtime.segments.certificate_pieces.PieceProofs._tie_cover`).

Every site is at distance 0 from c there, so a third curve k through c ties with the edge's sites
at the vertex and its derivative test is void (distances are not differentiable at c).  With
w = x − c, both sides are bounded by homogeneous functions of the direction ŵ:

* t (the edge's common distance) ≤ |ŵ × ê|·|w| for a segment partner leaving c along ê (its
  line's distance, the foot being in the segment), and ≤ |ŵ × t̂|·|w| for an arc touched from
  inside its circle (the circle lies between x and its tangent line t̂ at c);
* d_k ≥ dist(ŵ, ray of k)·|w| for a segment k (it lies on the ray from c along its direction),
  ≥ (ŵ·n̂)|w| for an arc k (n̂ its outer normal at c: |x − c_k| − ρ_k ≥ (x − c)·n̂), and = |w|
  when ŵ keeps x in the half of k's gap next to c (then c is k's nearest point).

On a parameter piece [θ*, θ* + δ] from the corner, w = x(θ) − x(θ*) lies in the cone of the
derivatives x'(piece) (mean value), so ŵ lies in the normalised box of x'(piece); the bound
D_k(ŵ) − D_t(ŵ) > 0 there proves d_k > t on the open piece.

Public API: :func:`curve_corner_test`, :func:`ray_in_gap_half`.
"""
from __future__ import annotations

from flint import arb

from ..certify.foot import to_arb
from .certificate_sites import ARC, SEGMENT, hypot

__all__ = ["curve_corner_test", "ray_in_gap_half"]


def _unit(v):
    return tuple(to_arb(x) for x in v), hypot(to_arb(v[0]), to_arb(v[1]))


def _cross(ax, ay, bx, by):
    return ax * by - ay * bx


def ray_in_gap_half(T, k: int, e: int, ux, uy, far=None) -> bool:
    """The ray e + τ u (τ > 0; up to the point ``far`` when given) from arc k's end e stays in the
    half of k's gap next to e, where e is k's only nearest point: the two half-plane conditions
    of :meth:`runtime.segments.certificate_sites.SiteTable.owned_by_end` are affine in τ, one is 0
    and the other > 0 at τ = 0: the first needs a slope > 0, the second a slope ≥ 0 or a positive
    value at ``far``."""
    (kx, ky) = T.cen[k]
    g = T.arc_mid(k)
    gx, gy = -to_arb(g[0]), -to_arb(g[1])
    ex, ey = to_arb(T.pt(e)[0] - kx), to_arb(T.pt(e)[1] - ky)
    if T.end_index(k, e) == 0:        # cone from g to e: cross(g, w) > 0 (> 0 at e), cross(w, e) ≥ 0 (0 at e)
        zero, other = _cross(ux, uy, ex, ey), (gx, gy, True)
    else:
        zero, other = _cross(ex, ey, ux, uy), (gx, gy, False)
    if not zero > 0:
        return False
    gx, gy, first = other
    slope = _cross(gx, gy, ux, uy) if first else _cross(ux, uy, gx, gy)
    if slope >= 0:
        return True
    if far is None:
        return False
    wx, wy = far[0] - to_arb(kx), far[1] - to_arb(ky)
    return bool((_cross(gx, gy, wx, wy) if first else _cross(wx, wy, gx, gy)) > 0)


def curve_corner_test(pr, k, corner: int, sgn: int):
    """A test fn(J, X, Y) for :meth:`_prefix`: > 0 proves d_k > t on the piece J next to the
    corner; None when no homogeneous bound applies."""
    T, c = pr.T, pr.curve
    if c.kind != "arc" or not T.is_curve(k) or corner not in T.ends[k]:
        return None
    cx, cy = T.pt_arb(corner)
    # an upper bound of t / |w| as a function of the direction
    upper = None
    if T.kind[c.k] == SEGMENT and corner in T.ends[c.k]:
        e = T.leaving(c.k, corner)
        (ex, ey), ne = _unit(e)
        upper = lambda ux, uy: abs(_cross(ux, uy, ex, ey)) / ne
    else:
        for a, side in ((c.s, c.sigma), (c.k, c.tau if T.kind[c.k] == ARC else 1)):
            if T.kind[a] == ARC and side < 0 and corner in T.ends[a]:
                tx, ty = T.leaving(a, corner)
                (tx, ty), nt = _unit((tx, ty))
                upper = lambda ux, uy, tx=tx, ty=ty, nt=nt: abs(_cross(ux, uy, tx, ty)) / nt
                break
    if upper is None:
        return None
    # a lower bound of d_k / |w|
    if T.kind[k] == SEGMENT:
        (ex, ey), ne = _unit(T.leaving(k, corner))

        def lower(ux, uy):
            dot = ux * ex + uy * ey
            return arb(1) if dot < 0 else (abs(_cross(ux, uy, ex, ey)) / ne if dot > 0 else arb(0))
    else:
        kx, ky, rk = T.arb_arc(k)
        nx, ny = (cx - kx) / rk, (cy - ky) / rk

        def lower(ux, uy):
            if ray_in_gap_half(T, k, corner, ux, uy):
                return arb(1)
            return ux * nx + uy * ny

    def test(J, X, Y):
        dx, dy = c.dxy(J)
        n = hypot(dx, dy)
        if not n > 0:
            return arb(-1)
        ux, uy = sgn * dx / n, sgn * dy / n
        return lower(ux, uy) - upper(ux, uy)
    return test
