"""Proofs that a real solution of the offset system is not a Voronoi vertex (step 5 of
:mod:`runtime.certify.complete`; thesis §5.2–§5.3).

A real solution (x, y, R) of o1 = o2 = o3 = 0 is a point q = (x, y) with a *critical* distance √R
to each conic C_i (a real or complex foot point at squared distance R).  It is a true
Voronoi vertex only if R ≥ 0 and √R = d(q, C_i) for i = 1, 2, 3 (thesis Def. 5.2.1).  It is proved
not to be one when, for the whole enclosure K = (x, y, R):

* R < 0; or
* some C_i has a real foot point strictly closer, D < R with D its squared distance
  (:func:`runtime.certify.foot.real_feet_ball`), so d(q, C_i) < √R; or
* every real foot point of some C_i has D ≠ R (proved D > R or D < R): √R is then the distance to
  a complex critical point only (:func:`not_a_vertex`); or
* a *witness*: a ball holding a point P of some C_i with |P − q|² < R for all q in K
  (:func:`closer_witness`).
"""
from __future__ import annotations

import flint
from flint import arb

from .foot import FootFailure, normalised_coefficients, real_feet_ball

__all__ = ["not_a_vertex", "closer_witness"]


def not_a_vertex(fps, K) -> bool:
    """Prove that the real solution in box K = (x, y, R) is not a true Voronoi vertex."""
    x, y, R = K
    if R < 0:
        return True
    if not R > 0:
        return False
    for fp in fps:
        try:
            feet = real_feet_ball(fp, x, y)
        except FootFailure:
            continue
        if any(f.D < R and not f.possible for f in feet):
            return True
        if all((f.D > R) or (f.D < R) for f in feet):
            return True  # √R is not the distance to any real foot point
    return False


def _conic_points_near(co, fx: float, fy: float):
    """Balls that each contain a point of the conic a·x² + b·xy + c·y² + d·x + e·y + f = 0 (exact
    coefficients ``co``) near (fx, fy): fix x = fx and solve the quadratic in y (and vice versa);
    a root ball of a quadratic with positive discriminant ball contains a true root."""
    a, b, c, d, e, f = (arb(flint.fmpq(t.numerator, t.denominator)) for t in co)
    out = []
    for swap in (False, True):
        if swap:
            a, c, d, e = c, a, e, d
            fx, fy = fy, fx
        X = arb(fx)
        A, B, C = c, b * X + e, a * X * X + d * X + f
        if A.contains(0):
            if not B.contains(0):
                out.append((X, -C / B) if not swap else (-C / B, X))
            continue
        disc = B * B - 4 * A * C
        if not disc > 0:
            continue
        for sgn in (1, -1):
            Y = (-B + sgn * disc.sqrt()) / (2 * A)
            out.append((X, Y) if not swap else (Y, X))
    return out


def closer_witness(conics, fps, K) -> bool:
    """Proof that the real solution in K = (x, y, R) is not a true vertex by a *witness*: a ball
    containing a point of some C_i whose squared distance to every point of (x, y) is < R (then
    d(q, C_i) < √R, thesis Def. 5.2.1).  Seeds: the (possibly only numerical) foot points of the
    three sites at the centre of K -- this covers points on a symmetry axis inside the evolute,
    where the foot enclosures are only "possible"."""
    x, y, R = K
    if not R > 0:
        return False
    for conic, fp in zip(conics, fps):
        co = normalised_coefficients(conic)
        try:
            feet = real_feet_ball(fp, x, y)
        except FootFailure:
            feet = []
        for ft in feet:
            # seeds only (a margin of 1e-7 relative admits feet numerically at distance √R);
            # the proof is D < R below
            if not ft.D < R * 1.0000001 and not ft.possible:
                continue
            try:
                fx, fy = float(ft.px.mid()), float(ft.py.mid())
            except (ValueError, OverflowError):
                continue
            for P in _conic_points_near(co, fx, fy):
                D = (P[0] - x) ** 2 + (P[1] - y) ** 2
                if D < R:
                    return True
    return False
