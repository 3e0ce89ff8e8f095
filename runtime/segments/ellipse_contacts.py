"""Contacts of a Voronoi vertex with an elliptic-arc piece: equations and their validity.

The contact system of :mod:`runtime.segments.vertices` gives an open elliptic piece t touched in
its interior the equation |v − e(φ(v))|² − r² = 0, φ(v) the foot of v on t (thesis ch. 4: the
foot-point equation f' = 0 of :mod:`runtime.segments.ellipse_pieces`).  By the envelope theorem
its gradient in v is 2(v − e(φ(v))): it is a point equation whose point is the foot
(:func:`foot_point`: a float Newton point, or over a box the enclosure of the parametric Krawczyk
test :func:`runtime.segments.ellipse_pieces.foot_enclosure`).  Where the circle touches t at an
end e (e a point site of the triple, or a smooth joint), the normal line of t at e is the
equation, as for segments and circular arcs, but only up to the centre of curvature of t at e:
beyond it e is a local maximum of the distance along the ellipse and the contact is an interior
foot (:func:`past_centre_of_curvature` chooses).  A proved zero touches t as its equation says
when the foot lies strictly inside t (or is the end) and is a nearest point of t
(:func:`ellipse_contact_valid`, by :func:`runtime.segments.ellipse_pieces.nearest_verdict`).

The centre of an ellipse is exactly equidistant from its two minor vertices, its nearest points:
when both lie in the closures of sites of a triple, the centre is a vertex of degree ≥ 3 decided
exactly (:func:`ellipse_centre_vertex`, :func:`ellipse_centre_sites`).

Public API: :func:`past_centre_of_curvature`, :func:`end_parameter`, :func:`foot_phi`,
:func:`foot_point`, :func:`ellipse_contact_valid`, :func:`ellipse_centre_vertex`,
:func:`ellipse_centre_sites`, :func:`both_ends_contact`.
"""
from __future__ import annotations

import math

import numpy as np
from flint import arb

from ..certify.foot import to_arb
from ..certify.interval_newton import KrawczykFailure
from .elementary import ElementarySites
from .ellipse_pieces import foot_enclosure, interior_foot, nearest_verdict, piece_feet

__all__ = ["past_centre_of_curvature", "end_parameter", "foot_phi", "foot_point", "ellipse_contact_valid",
           "ellipse_centre_vertex", "ellipse_centre_sites", "both_ends_contact"]


def past_centre_of_curvature(E: ElementarySites, t: int, e: int, q) -> bool:
    """The point q lies beyond the centre of curvature of elliptic piece t at its end e: along the
    inner normal at e farther than the radius of curvature (a² sin² φ + b² cos² φ)^{3/2} / (ab).
    There e is a local maximum of the distance from q along the ellipse, and the nearest point of
    the piece is an interior foot (two mirror feet at a vertex joint) — floats: this only chooses
    the contact equations, the proof checks the contacts."""
    P = E.ellipse[t]
    c, M, N = P.floats()
    a, b = float(np.hypot(*M)), float(np.hypot(*N))
    phi = P.phi0 if int(E.ends[t, 0]) == e else P.phi1
    T = -np.sin(phi) * M + np.cos(phi) * N
    n = np.array([T[1], -T[0]]) / max(float(np.hypot(*T)), 1e-300)      # outer normal
    ex, ey = (float(v) for v in E.xy[e])
    depth = float(np.dot(np.array([ex, ey]) - np.asarray(q, float), n))
    rho = (a * a * np.sin(phi) ** 2 + b * b * np.cos(phi) ** 2) ** 1.5 / (a * b)
    return depth > rho


def end_parameter(E: ElementarySites, t: int, e: int) -> arb:
    """The enclosure of the parameter of elliptic piece t at its end e."""
    p0, p1 = E.ellipse[t].arb_params()
    return p0 if int(E.ends[t, 0]) == e else p1


def foot_phi(P, x: float, y: float) -> float:
    """The float foot parameter of an elliptic contact: the nearest interior local minimum of the
    squared distance (the contact is in the open piece), else the closed piece's nearest point."""
    phi = interior_foot(P, x, y)
    if phi is None:
        phi = float(piece_feet(P, np.array([[x, y]]))[1][0])
    return phi


def foot_point(P, x, y):
    """The foot e(φ(v)) of v = (x, y) on an elliptic piece: floats (:func:`foot_phi`), or arb
    over a box (the foot enclosure of :func:`runtime.segments.ellipse_pieces.foot_enclosure`)."""
    if isinstance(x, arb):
        Phi = foot_enclosure(P, x, y, foot_phi(P, float(x.mid()), float(y.mid())))
        if Phi is None:
            raise KrawczykFailure("the foot on an elliptic piece is not enclosed")
        c, s = Phi.cos(), Phi.sin()
        return (to_arb(P.c[0]) + c * to_arb(P.M[0]) + s * to_arb(P.N[0]),
                to_arb(P.c[1]) + c * to_arb(P.M[1]) + s * to_arb(P.N[1]))
    phi = foot_phi(P, float(x), float(y))
    c, M, N = P.floats()
    f = c + math.cos(phi) * M + math.sin(phi) * N
    return float(f[0]), float(f[1])


def ellipse_contact_valid(E: ElementarySites, kind: str, d, t: int, x: arb, y: arb, r: arb, triple=()):
    """True when the proved zero (x, y, r) touches elliptic piece t as its equation ``kind`` says:
    "ellipse": the foot strictly inside t and a nearest point of t (an end of t that is a site of
    ``triple`` may tie); "normal" or "point" (an end or smooth joint e): e is a nearest point of
    t (its other end may tie when it is a site of ``triple``).  False when it does not, None when undecided."""
    P = E.ellipse[t]
    if kind == "ellipse":
        Phi = foot_enclosure(P, x, y, foot_phi(P, float(x.mid()), float(y.mid())))
        if Phi is None:
            return None
        p0, p1 = P.arb_params()
        if Phi < p0 or Phi > p1:
            return False
        if not (Phi > p0 and Phi < p1):
            return None
        tied = [k for k in (0, 1) if int(E.ends[t, k]) in {int(v) for v in triple}]
        return nearest_verdict(P, x, y, r, Phi, tied)
    if kind in ("normal", "point"):
        at = (d[2], d[3]) if kind == "normal" else (d[0], d[1])
        e = next((int(v) for v in E.ends[t] if tuple(E.xy[int(v)]) == tuple(at)), None)
        if e is None:
            return None
        tied = [k for k in (0, 1) if int(E.ends[t, k]) != e and int(E.ends[t, k]) in {int(v) for v in triple}]
        return nearest_verdict(P, x, y, r, end_parameter(E, t, e), tied)
    return None


def _minor_vertex_codes(E: ElementarySites, t: int) -> tuple:
    """(the end codes of E at the minor vertices c ± N of piece t's ellipse, the ellipse's key)."""
    P = E.ellipse[t]
    key = (P.c, P.M, P.N)
    tips = {(P.c[0] + P.N[0], P.c[1] + P.N[1]), (P.c[0] - P.N[0], P.c[1] - P.N[1])}
    return tips, key


def ellipse_centre_sites(E: ElementarySites, t: int) -> set:
    """The sites at distance exactly b = |N| from the centre c of piece t's ellipse: the pieces of
    that ellipse whose closure holds a minor vertex c ± N, and point sites there.  From c the
    squared distance to the ellipse is a² cos² φ + b² sin² φ ≥ b² (a > b), with equality exactly at
    the minor vertices, so every other piece of the ellipse is strictly farther."""
    tips, key = _minor_vertex_codes(E, t)
    out = set()
    for s, P in E.ellipse.items():
        if (P.c, P.M, P.N) == key and any(tuple(E.xy[int(v)]) in tips for v in E.ends[s]):
            out.add(int(s))
    for p in range(E.n_points):
        if tuple(E.xy[p]) in tips:
            out.add(p)
    return out


def ellipse_centre_vertex(E: ElementarySites, triple):
    """For a triple of pieces of one ellipse (and point sites at its minor vertices) that holds both
    minor vertices c ± N in its closures: (c, b²) — the centre c is at distance b = |N| from all
    of them (:func:`ellipse_centre_sites`), a Voronoi vertex when no other site comes closer.
    None for other triples."""
    pieces = [int(t) for t in triple if int(t) in E.ellipse]
    if not pieces:
        return None
    tips, key = _minor_vertex_codes(E, pieces[0])
    members = ellipse_centre_sites(E, pieces[0])
    if not all(int(t) in members for t in triple):
        return None
    seen = set()
    for t in triple:
        codes = [int(t)] if int(t) < E.n_points else [int(v) for v in E.ends[int(t)]]
        seen |= {tuple(E.xy[v]) for v in codes} & tips
    if seen != tips:
        return None
    P = E.ellipse[pieces[0]]
    return P.c, P.N[0] ** 2 + P.N[1] ** 2


def both_ends_contact(E: ElementarySites, t: int, seed, tangent_at):
    """The equation of elliptic piece t in a triple that holds both its ends: the foot equation
    when the seed has an interior foot well inside t, else the normal line at the end where the
    derivative f' of the squared distance is nearer zero (there the interior foot leaves t through
    that end: the vertex is on its normal).  ``tangent_at(E, t, e)``: the exact tangent at end e."""
    P = E.ellipse[t]
    span = P.phi1 - P.phi0
    phi = interior_foot(P, float(seed[0]), float(seed[1]))
    if phi is not None and P.phi0 + 1e-3 * span < phi < P.phi1 - 1e-3 * span:
        return ("ellipse", P, t)
    c, M, N = P.floats()
    w = np.asarray(seed, float) - c
    A, B, a2, b2 = float(w @ M), float(w @ N), float(M @ M), float(N @ N)
    slopes = [abs(A * math.sin(p) - B * math.cos(p) + (b2 - a2) * math.sin(p) * math.cos(p)) for p in (P.phi0, P.phi1)]
    e = int(E.ends[t, 0]) if slopes[0] <= slopes[1] else int(E.ends[t, 1])
    return ("normal", tuple(tangent_at(E, t, e)) + tuple(E.xy[e]), t)
