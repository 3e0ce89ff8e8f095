"""Elliptic-arc pieces in the point/segment/arc certificate (thesis §2.2 harmless sites, ch. 4
foot points): the piece's float bounds and distance balls, its touching-type distance at a vertex,
and the proofs that a contact is a nearest point of the piece.

A site :class:`runtime.sites.elliptic_arc.EllipticArc` is accepted only as a *piece*: no vertex
of its ellipse strictly inside it (:meth:`EllipticArc.pieces` returns it alone).  On a piece,
e(φ) = c + cos φ M + sin φ N with φ in one quadrant, cos φ and sin φ are monotone, so the piece
lies in the rectangle of frame coordinates spanned by its two ends; the float lower bound of the
distance is the distance to that rectangle's circumscribed disc, the upper bound the nearer end's.
The rigorous distance from a box is :func:`runtime.segments.ellipse_pieces.piece_distance_ball`.

At a vertex v touching the piece inside, the touching-type distance is d(v) = |v − e(φ(v))|, φ(v)
the strict local minimum of f(φ) = |v − e(φ)|² inside the open piece (unique: f has at most two
critical points on a piece), enclosed over a box by the parametric Krawczyk test of
:func:`runtime.segments.ellipse_pieces.interior_minimum` with the piece's parameter range as a
constraint.  By the envelope theorem ∇d = (v − e(φ(v)))/d, so d is C¹ on every box where the
enclosure succeeds and the vertex system's Krawczyk test sees its Jacobian.  A proved zero
touches the piece as its equation says when the critical point is the piece's nearest point
(:func:`runtime.segments.ellipse_pieces.nearest_verdict`: f'' > 0 around it, f > r² on the rest);
a contact at an end e (the vertex on the normal line at e, f'(φ_e) = 0) likewise with φ_e's
enclosure in place of the foot's.

A vertex listing an end e of the piece (a point site, or a joint) may still touch the piece inside
with e at the same distance: then the interior equation, the tie with a listed point-site end
allowed in the nearest-point proof.  A joint of two pieces beyond its centre of curvature is no
contact (a local maximum of the distance along the ellipse): both pieces touch inside.

Public API: :func:`is_piece`, :func:`bounding_disc`, :func:`float_bounds`, :func:`term_value`,
:func:`term_grad`, :func:`contact_point`, :func:`interior_contact_valid`,
:func:`touches_inside`, :func:`past_centre_of_curvature`, :func:`end_contact_valid`,
:func:`normal_residual`, :func:`owned_by_end`, :func:`owned_by_both_ends`.
"""
from __future__ import annotations

import math

import numpy as np
from flint import arb

from .ellipse_pieces import (PieceData, closest_at_an_end, interior_foot, interior_minimum, nearest_verdict,
                             piece_feet, piece_point_ball, piece_points)

__all__ = ["is_piece", "bounding_disc", "float_bounds", "term_value", "term_grad", "contact_point",
           "interior_contact_valid", "touches_inside", "past_centre_of_curvature", "end_contact_valid",
           "normal_residual", "owned_by_end", "owned_by_both_ends"]

EPS = np.finfo(float).eps


def is_piece(site) -> bool:
    """The elliptic arc has no vertex of its ellipse strictly inside (exact)."""
    return len(site.pieces()) == 1


def bounding_disc(site) -> tuple[np.ndarray, float]:
    """(centre, radius) of a float disc holding the piece: the circumscribed disc of the rectangle
    of frame coordinates between its ends (radius widened by 10⁻¹² relative)."""
    (ua, va), (ub, vb) = site.ua, site.ub
    um, vm = (ua + ub) / 2, (va + vb) / 2
    c = np.array([float(site.c[0] + um * site.M[0] + vm * site.N[0]), float(site.c[1] + um * site.M[1] + vm * site.N[1])])
    a2 = float(site.M[0] ** 2 + site.M[1] ** 2)
    b2 = float(site.N[0] ** 2 + site.N[1] ** 2)
    r = math.sqrt(float((ua - ub) ** 2) / 4 * a2 + float((va - vb) ** 2) / 4 * b2)
    return c, r * (1 + 1e-12) + 1e-300


def float_bounds(centre, radius, A, B, Q, scale: float):
    """Float lower and upper bounds of the distances from the rows of Q to pieces with bounding
    discs (centre rows, radii) and ends A, B (rows): the disc's distance, the nearer end's,
    each widened by a rounding margin."""
    lo = np.maximum(np.hypot(*(Q - centre).T) - radius, 0.0)
    hi = np.minimum(np.hypot(*(Q - A).T), np.hypot(*(Q - B).T))
    e = 64 * EPS * (np.abs(Q).max(axis=1) + np.abs(centre).max(axis=1) + radius + 1.0) + 8 * EPS * scale
    return lo - e, hi + e


def _float_foot(P: PieceData, x: float, y: float) -> float:
    """The parameter of the interior local minimum of f (the nearest point of the closed piece when
    there is none; floats)."""
    phi = interior_foot(P, x, y)
    return float(piece_feet(P, [[x, y]])[1][0]) if phi is None else phi


def term_value(P: PieceData, x, y, fl: bool):
    """The touching-type distance |v − e(φ(v))| (floats: to the closed piece; balls: to the
    interior strict local minimum, ValueError when it is not enclosed)."""
    if fl:
        e = piece_points(P, [_float_foot(P, x, y)])[0]
        return math.hypot(x - e[0], y - e[1])
    ex, ey = _foot_point(P, x, y)
    return ((x - ex) * (x - ex) + (y - ey) * (y - ey)).nonnegative_part().sqrt()


def term_grad(P: PieceData, x, y, fl: bool):
    """∇|v − e(φ(v))| = (v − e)/|v − e| (envelope theorem)."""
    if fl:
        phi = _float_foot(P, x, y)
        e = piece_points(P, [phi])[0]
        d = math.hypot(x - e[0], y - e[1])
        return (x - e[0]) / d, (y - e[1]) / d
    ex, ey = _foot_point(P, x, y)
    d = ((x - ex) * (x - ex) + (y - ey) * (y - ey)).nonnegative_part().sqrt()
    return (x - ex) / d, (y - ey) / d


def _foot_enclosure(P: PieceData, x: arb, y: arb) -> arb:
    Phi = interior_minimum(P, x, y, _float_foot(P, float(x.mid()), float(y.mid())))
    if Phi is None:
        raise ValueError("the foot on the elliptic piece is not enclosed inside it")
    return Phi


def _foot_point(P: PieceData, x: arb, y: arb):
    return piece_point_ball(P, _foot_enclosure(P, x, y))


def contact_point(P: PieceData, X: arb, Y: arb):
    """Balls of the contact e(φ(v)) of every point of the box (ValueError when not enclosed)."""
    return _foot_point(P, X, Y)


def interior_contact_valid(P: PieceData, X: arb, Y: arb, R: arb, tied_ends=()):
    """For every point of the box: the piece's nearest point is the interior strict local minimum
    of f (enclosed strictly inside the open piece) at distance R, nothing of the piece nearer,
    except the ends ``tied_ends`` (listed point sites at distance R, f increasing away from them):
    True; False when refuted (a nearer point of the piece, a local maximum); None when undecided
    (also when no interior strict minimum is enclosed)."""
    try:
        Phi = _foot_enclosure(P, X, Y)
    except ValueError:
        return None
    return nearest_verdict(P, X, Y, R, Phi, tied_ends=tuple(tied_ends))


def past_centre_of_curvature(P: PieceData, which: int, x: float, y: float) -> bool:
    """f''(φ_e) < 0 at the float point (x, y) for the end ``which``: the point lies beyond the
    centre of curvature of the piece at that end, where the end is no local minimum of the distance
    along the ellipse (floats: this only chooses the vertex equation, the proof checks it)."""
    c, M, N = P.floats()
    phi = P.phi0 if which == 0 else P.phi1
    w = np.array([x, y]) - c
    A, B = float(w @ M), float(w @ N)
    a2, b2 = float(M @ M), float(N @ N)
    return A * math.cos(phi) + B * math.sin(phi) + (b2 - a2) * math.cos(2 * phi) < 0


def touches_inside(P: PieceData, x: float, y: float, r: float) -> bool:
    """The float point (x, y) has an interior local minimum of f at distance r (relative 10⁻⁷),
    its foot away from the ends: a circle of radius r about it touches the piece inside although
    an end (or joint) of the piece is listed too — the end then ties, or lies beyond the centre of
    curvature (floats: this only chooses the vertex equation, the proof checks it)."""
    phi = interior_foot(P, x, y)
    if phi is None or min(phi - P.phi0, P.phi1 - phi) <= 1e-9 * (P.phi1 - P.phi0):
        return False
    e = piece_points(P, [phi])[0]
    return abs(math.hypot(x - e[0], y - e[1]) - r) <= 1e-7 * (1 + abs(x) + abs(y) + abs(r))


def end_contact_valid(P: PieceData, which: int, X: arb, Y: arb, R: arb, tied_ends=()):
    """For the vertex in the box, on the normal line of the piece at its end ``which`` (0 start,
    1 end; f' = 0 there): f'' > 0 next to that end and f > R² on the rest of the piece, so the end
    is the piece's nearest point at distance R (the other end may tie when in ``tied_ends``: a
    point site listed at distance R, f increasing away from it): True; False when refuted; None
    when undecided."""
    p0, p1 = P.arb_params()
    return nearest_verdict(P, X, Y, R, p0 if which == 0 else p1, tied_ends=tuple(tied_ends))


def normal_residual(P: PieceData, which: int, x: float, y: float) -> float:
    """|f'(φ_e)| / (2 |v − e| |e'(φ_e)|) at the float point v = (x, y) for the end ``which``: the sine
    of the angle between v − e and the normal at e (floats: chooses which end is the contact)."""
    c, M, N = P.floats()
    phi = P.phi0 if which == 0 else P.phi1
    e = c + math.cos(phi) * M + math.sin(phi) * N
    t = -math.sin(phi) * M + math.cos(phi) * N
    w = np.array([x, y]) - e
    return abs(float(w @ t)) / max(float(np.hypot(*w)) * float(np.hypot(*t)), 1e-300)


def owned_by_both_ends(P: PieceData, X: arb, Y: arb):
    """The piece's nearest points to every point of the box are both its ends (f increasing away
    from each near it and above both ends' values between): True, or None when not proved."""
    return True if closest_at_an_end(P, X, Y) == (0, 1) else None


def owned_by_end(P: PieceData, which: int, X: arb, Y: arb):
    """The piece's nearest point to every point of the box is its end ``which`` alone: True, or
    None when not proved."""
    return True if closest_at_an_end(P, X, Y) == (which,) else None
