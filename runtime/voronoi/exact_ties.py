"""Near ties of nearest-site queries decided exactly or by balls at rising precision.

Thesis §1.1 (proximity queries); the step 4 of :meth:`runtime.voronoi.queries.SiteIndex.nearest`.
The query float is an exact rational q.  Points and circles: d(q, S)² = D + r² − 2·√(D·r²) with
D = |q − c|², compared by an exact zero test of (A_s − 2√u_s) − (A_t − 2√u_t).  Segments: the
squared distance to a closed segment is rational (the clamped rational foot parameter).  Circular
arcs: |‖q − c‖ − ρ| when the direction q − c lies in the arc's angular range (an exact orientation
test), else the nearer end.  Conics: the ball of :func:`runtime.sites.distance_ball.distance_ball`;
elliptic arcs: the ball of :func:`runtime.segments.ellipse_pieces.piece_distance_ball`.

A segment's or arc's interior tied with its own endpoint gives way to the endpoint (thesis §2.2,
:mod:`runtime.sites.segment`): decided exactly for segments and circular arcs, and for elliptic
arcs where the piece's nearest point is proved to be that end
(:func:`runtime.segments.ellipse_pieces.closest_at_an_end`).

Public API: :func:`decide_nearest`.
"""
from __future__ import annotations

import flint
from flint import arb, fmpq

from ..sites.arc import Arc
from ..sites.rationals import parse_rational

__all__ = ["decide_nearest"]

#: site kinds whose distance to a rational point is decided in exact arithmetic (d² = A − 2√u)
_EXACT_KINDS = ("point", "circle", "segment", "arc")


def decide_nearest(geoms, T, x: float, y: float, precs=(128, 512, 2048)):
    """The nearest among the sites T of the query point (x, y) (taken exactly): (winners,
    exact).  One winner: proved.  Several: ``exact`` says whether their distances are proved
    equal (points and circles, rational arithmetic) or could not be separated (undecided)."""
    qx, qy = parse_rational(float(x), "x"), parse_rational(float(y), "y")
    circ = {j: _circle_terms(geoms[j], qx, qy) for j in T if geoms[j].kind in _EXACT_KINDS}
    cand = list(T)
    for prec in precs:
        with flint.ctx.workprec(prec):
            enc = {j: _enclosure(geoms[j], circ.get(j), x, y, prec) for j in cand}
            up = min(e.upper() for e in enc.values())
            cand = [j for j in cand if enc[j].lower() <= up]
            if len(cand) > 1:
                cand = _piece_end_convention(geoms, cand, x, y)
        if len(cand) == 1:
            return tuple(cand), True
        if all(j in circ for j in cand):
            ref = circ[cand[0]]
            if all(_equal_distances(ref, circ[j]) for j in cand[1:]):
                cand = _endpoint_convention(geoms, cand)
                return tuple(cand), True
    return tuple(cand), False


def _endpoint_convention(geoms, cand):
    """Thesis §2.2 (:mod:`runtime.sites.segment`): a point at equal distance from a segment's or
    an arc's interior and from its endpoint (a point site) belongs to the endpoint."""
    ends = {(geoms[j].exact.cx, geoms[j].exact.cy) for j in cand if geoms[j].kind == "point"}
    return [j for j in cand if not (geoms[j].kind in ("segment", "arc") and (_curve_ends(geoms[j].exact) & ends))]


def _piece_end_convention(geoms, cand, x, y):
    """The same convention for elliptic arcs, whose distances are not decided exactly: an arc
    whose nearest point from (x, y) is proved to be one of its ends, where a candidate point site
    sits, is at exactly that point's distance, and the point wins."""
    pts = {(geoms[j].exact.cx, geoms[j].exact.cy) for j in cand if geoms[j].kind == "point"}
    if not pts:
        return cand
    return [j for j in cand if not (geoms[j].kind == "elliptic_arc"
                                    and {_fmpq_pair(e) for e in geoms[j].nearest_ends(x, y)} & pts)]


def _curve_ends(curve) -> set:
    """The two ends of a Segment or an Arc, as fmpq pairs."""
    if isinstance(curve, Arc):
        return {_fmpq_pair(curve.a), _fmpq_pair(curve.b)}
    return {_fmpq_pair(curve.p), _fmpq_pair(curve.q)}


def _fmpq_pair(p):
    return tuple(fmpq(v.numerator, v.denominator) for v in p)


def _circle_terms(g, qx: fmpq, qy: fmpq):
    """(A, u) with d² = A − 2√u exactly: A = D + r², u = D·r², D = |q − c|² (exact data); for a
    segment, A = the squared distance to the closed segment (rational: the foot parameter is
    the clamped rational (q − a)·(b − a) / |b − a|²), u = 0; for an arc see :func:`_arc_terms`."""
    ex = g.exact
    if g.kind == "arc":
        return _arc_terms(ex, qx, qy)
    if g.kind == "segment":
        (ax, ay), (bx, by) = _fmpq_pair(ex.p), _fmpq_pair(ex.q)
        dx, dy = bx - ax, by - ay
        t = min(max(((qx - ax) * dx + (qy - ay) * dy) / (dx * dx + dy * dy), fmpq(0)), fmpq(1))
        return (qx - ax - t * dx) ** 2 + (qy - ay - t * dy) ** 2, fmpq(0)
    D = (qx - ex.cx) ** 2 + (qy - ex.cy) ** 2
    r2 = fmpq(0) if g.kind == "point" else fmpq(ex.r2)
    return D + r2, D * r2


def _arc_terms(arc, qx: fmpq, qy: fmpq):
    """(A, u) with d² = A − 2√u exactly for the closed counter-clockwise arc of centre c, radius
    ρ from a to b: when w = q − c lies in the arc's angular range (closed; decided by the exact
    signs of the cross products a × w, w × b and a × b, with a, b taken from c) the nearest point
    is c + ρ·w/‖w‖ and d = |‖w‖ − ρ|, i.e. A = ‖w‖² + ρ², u = ‖w‖²·ρ² (w = 0: every point of the
    arc is at ρ, the same formula); otherwise the nearest point is an end: A = min ‖q − end‖², u = 0."""
    cx, cy = _fmpq_pair(arc.c)
    (ax, ay), (bx, by) = _fmpq_pair(arc.a), _fmpq_pair(arc.b)
    wx, wy = qx - cx, qy - cy
    ux, uy, vx, vy = ax - cx, ay - cy, bx - cx, by - cy
    ca, cb, ab = ux * wy - uy * wx, wx * vy - wy * vx, ux * vy - uy * vx
    zero = fmpq(0)
    inside = (ca >= zero and cb >= zero) if ab > zero else (ca >= zero or cb >= zero)
    if inside:
        D = wx * wx + wy * wy
        r2 = fmpq(arc.rho.numerator, arc.rho.denominator) ** 2
        return D + r2, D * r2
    return min((qx - ax) ** 2 + (qy - ay) ** 2, (qx - bx) ** 2 + (qy - by) ** 2), zero


def _enclosure(g, terms, x, y, prec) -> arb:
    if terms is not None:
        A, u = terms
        d2 = arb(A) - 2 * arb(u).sqrt()          # d² ≥ 0: keep the non-negative part
        if d2 >= 0:
            return d2.sqrt()
        return arb(0).union(d2.upper().sqrt()) if d2.upper() > 0 else arb(0)
    if g.kind == "elliptic_arc":
        return g.distance_ball(x, y)
    from ..sites.distance_ball import distance_ball

    return distance_ball(g.exact, x, y, prec=prec)


def _equal_distances(s, t) -> bool:
    """Exact zero test of (A_s − 2√u_s) − (A_t − 2√u_t): x + 2√v = 2√u with x = A_s − A_t,
    u = u_s, v = u_t; squaring, x² + 4v + 4x√v = 4u."""
    (As, u), (At, v) = s, t
    x = As - At
    if x == 0:
        return u == v
    w = (4 * u - x * x - 4 * v) / (4 * x)       # the value √v must have
    return w >= 0 and w * w == v and x + 2 * w >= 0
