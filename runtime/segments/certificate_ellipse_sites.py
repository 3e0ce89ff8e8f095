"""Elliptic pieces among the other sites, for the certificate (:mod:`runtime.segments.certificate`
steps 1 and 5): proved apart from every other site, and strictly inside the point sites' convex
hull (then the unbounded ends of the diagram are those of its points and segments).

Public API: :func:`pieces_inside_hull`, :func:`pieces_apart`, :func:`same_ellipse`.
"""
from __future__ import annotations

import math
from fractions import Fraction

from flint import arb

from ..certify.foot import to_arb
from .certificate_hull import convex_hull
from .certificate_sites import ELLIPSE, POINT, SEGMENT, SiteTable
from .ellipse_pieces import piece_point_ball

__all__ = ["pieces_inside_hull", "pieces_apart", "same_ellipse"]


def pieces_inside_hull(T: SiteTable) -> str | None:
    """None when every elliptic piece lies strictly inside the convex hull of the point sites
    except at ends that are point sites (exact: the piece lies in the parallelogram of frame
    coordinates between its ends, whose corners other than point-site ends must be strict
    interior points); then the pieces touch no support line of the sites' hull but at point
    sites, and the unbounded ends are those of the points and segments.  Else a message."""
    hull = convex_hull([T.a[k] for k in range(T.n) if T.kind[k] == POINT])
    if len(hull) < 3:
        return "the point sites' convex hull is degenerate"
    sides = [(hull[m], hull[(m + 1) % len(hull)]) for m in range(len(hull))]
    for k in sorted(T.piece):
        s = T.sites[k]
        corners = []
        for u in (s.ua, s.ub):
            for v in (s.ua, s.ub):
                q = (s.c[0] + u[0] * s.M[0] + v[1] * s.N[0], s.c[1] + u[0] * s.M[1] + v[1] * s.N[1])
                corners.append(tuple(Fraction(x) for x in q))
        ends = {T.pt(code) for code in T.ends[k] if code >= 0}
        for q in corners:
            if q in ends:
                continue
            for p, r in sides:
                if not (r[0] - p[0]) * (q[1] - p[1]) - (r[1] - p[1]) * (q[0] - p[0]) > 0:
                    return (f"elliptic piece {k} is not strictly inside the convex hull of the point sites: "
                            "its unbounded ends are not covered")
    return None


def same_ellipse(a, b) -> bool:
    return a.c == b.c and a.M == b.M and a.N == b.N


def _quadrant(s) -> tuple:
    """The closed quadrant of frame directions holding piece s: signs of (cos φ, sin φ) in it."""
    return tuple(1 if u[0] + v[0] > 0 else -1 for u, v in ((s.ua, s.ub),)) + \
        tuple(1 if u[1] + v[1] > 0 else -1 for u, v in ((s.ua, s.ub),))


def _boxes(T: SiteTable, l: int, lo: float, hi: float):
    """A box (X, Y) holding the part [lo, hi] (fractions of the parameter range) of curve l."""
    a, b = arb(lo), arb(hi)
    J = a.union(b)
    if T.kind[l] == SEGMENT:
        ax, ay, bx, by = T.arb_ends(l)
        return ax + J * (bx - ax), ay + J * (by - ay)
    if T.kind[l] == ELLIPSE:
        p0, p1 = T.piece[l].arb_params()
        return piece_point_ball(T.piece[l], p0 + J * (p1 - p0))
    cx, cy, rho = T.arb_arc(l)
    (qcx, qcy) = T.cen[l]
    al = arb.atan2(to_arb(T.a[l][1] - qcy), to_arb(T.a[l][0] - qcx))
    be = arb.atan2(to_arb(T.b[l][1] - qcy), to_arb(T.b[l][0] - qcx)) - al
    while be <= 0:
        be += 2 * arb.pi()
    ph = al + J * be
    return cx + rho * ph.cos(), cy + rho * ph.sin()


def _apart(T: SiteTable, k: int, l: int, budget: int = 4000) -> bool:
    """Curve l has no point on the closed piece k (boxes of l's range, halved, each at a proved
    positive distance from k)."""
    todo = [(0.0, 1.0)]
    while todo:
        budget -= 1
        if budget < 0:
            return False
        lo, hi = todo.pop()
        X, Y = _boxes(T, l, lo, hi)
        if T.distance(k, X, Y) > 0:
            continue
        if hi - lo < 1e-9:
            return False
        m = (lo + hi) / 2
        todo += [(lo, m), (m, hi)]
    return True


def pieces_apart(T: SiteTable) -> str | None:
    """None when every elliptic piece is proved to meet no other site but at its own ends (point
    sites) and joints with pieces of the same ellipse in other quadrants (rigorous distance balls;
    the crossing test of the admissibility step is a float test for pieces); else a message."""
    for k in sorted(T.piece):
        mine = set(T.ends[k])
        for l in range(T.n):
            if l == k:
                continue
            if T.kind[l] == POINT:
                if l in mine:
                    continue
                p = T.arb_ends(l)[:2]
                if not T.distance(k, *p) > 0:
                    return f"point {l} is not proved off elliptic piece {k}"
                continue
            shared = mine & set(T.ends[l] or ())
            if shared:
                if T.kind[l] == ELLIPSE and same_ellipse(T.sites[k], T.sites[l]) and \
                        _quadrant(T.sites[k]) != _quadrant(T.sites[l]) and all(c <= -2 or c >= 0 for c in shared):
                    continue
                return f"curves {k} and {l} share an end: their being apart elsewhere is not proved"
            if l < k and T.kind[l] == ELLIPSE:
                continue                        # the pair was checked from l
            gap = math.hypot(*(T.mid[k] - T.mid[l])) - T.half[k] - T.half[l]
            if gap > 1e-9 * T.scale:
                continue
            if not _apart(T, k, l):
                return f"elliptic piece {k} and curve {l} are not proved apart"
    return None
