"""Segments and circular arcs seen as site geometries (distance, rigorous bounds, samples).

The proximity queries of :mod:`runtime.voronoi.queries` (nearest site, cells) ask every site
for the interface of :class:`runtime.voronoi.geometry.SiteGeometry`: ``distance``,
``distance_bounds``, ``bounding_box``, ``samples``.  Points, circles and conics have theirs in
:mod:`runtime.voronoi.conic_geometry`; the open interiors of segments and arcs (thesis §2.2) get
them here, from the one distance implementation of :mod:`runtime.segments.distance`.

Elliptic arcs (:class:`EllipticArcGeometry`) take theirs from the one implementation of a
piece's distance, :mod:`runtime.segments.ellipse_pieces`.

Public API: :class:`SegmentGeometry`, :class:`ArcGeometry`, :class:`EllipticArcGeometry`.
"""
from __future__ import annotations

from fractions import Fraction

import numpy as np
from flint import arb

from ..sites.elliptic_arc import VERTEX_DIRECTIONS
from ..sites.segment import Segment
from .distance import arc_distances, distances as segment_distances, float_error as segment_float_error
from .ellipse_pieces import PieceData, closest_at_an_end, piece_distance_ball, piece_distance_bounds, piece_distances

__all__ = ["SegmentGeometry", "ArcGeometry", "EllipticArcGeometry"]


def _outward(box):
    """An exact box (x0, y0, x1, y1) as floats rounded outwards (4 ulps of its largest coordinate)."""
    out = [float(v) for v in box]
    pad = 4 * np.finfo(float).eps * max(1.0, max(abs(v) for v in out))
    return (out[0] - pad, out[1] - pad, out[2] + pad, out[3] + pad)


class SegmentGeometry:
    """The open interior of a :class:`runtime.sites.segment.Segment` site seen as a site geometry:
    its distance is the distance to the closed segment, evaluated by
    :func:`runtime.segments.distance.distances` with the rounding bound
    :func:`runtime.segments.distance.float_error` (the float endpoints are within half an ulp of
    the exact ones, well inside that bound)."""

    kind = "segment"
    bounded = True

    def __init__(self, seg: Segment):
        self.exact = seg
        a, b = seg.float_endpoints()
        self.A, self.B = np.array(a, float), np.array(b, float)

    def bounding_box(self):
        return (*np.minimum(self.A, self.B).tolist(), *np.maximum(self.A, self.B).tolist())

    def _ends(self, P):
        return np.broadcast_to(self.A, P.shape), np.broadcast_to(self.B, P.shape)

    def distance(self, P):
        P = np.asarray(P, float).reshape(-1, 2)
        return segment_distances(*self._ends(P), P)[0]

    def distance_bounds(self, P):
        P = np.asarray(P, float).reshape(-1, 2)
        A, B = self._ends(P)
        d, err = segment_distances(A, B, P)[0], segment_float_error(A, B, P)
        return np.maximum(d - err, 0.0), d + err

    def samples(self, spacing, window=None):
        n = max(2, int(np.ceil(np.hypot(*(self.B - self.A)) / max(spacing, 1e-300))) + 1)
        t = np.linspace(0.0, 1.0, n)
        return self.A + t[:, None] * (self.B - self.A)


class ArcGeometry(SegmentGeometry):
    """The open interior of a circular :class:`runtime.sites.arc.Arc` site: its distance is the
    distance to the closed arc (:func:`runtime.segments.distance.arc_distances`), with the rounding
    bound of the segments plus 64 ulps of |c| + ρ."""

    kind = "arc"

    def __init__(self, arc):
        self.exact = arc
        c, self.rho, a, b = arc.float_data()
        self.C, self.A, self.B = np.array(c, float), np.array(a, float), np.array(b, float)

    def bounding_box(self):
        """The box of the arc's ends and of the points c ± ρ e_x, c ± ρ e_y its angular range
        holds, exact, then rounded outwards (samples would miss an extreme point by a sagitta)."""
        arc = self.exact
        pts = [arc.a, arc.b] + [(arc.c[0] + ux * arc.rho, arc.c[1] + uy * arc.rho)
                                for ux, uy in VERTEX_DIRECTIONS if arc.contains_direction((ux, uy))]
        return _outward([min(p[0] for p in pts), min(p[1] for p in pts), max(p[0] for p in pts),
                         max(p[1] for p in pts)])

    def distance(self, P):
        P = np.asarray(P, float).reshape(-1, 2)
        C = np.broadcast_to(self.C, P.shape)
        return arc_distances(C, self.rho, *self._ends(P), P)

    def distance_bounds(self, P):
        P = np.asarray(P, float).reshape(-1, 2)
        d = self.distance(P)
        err = segment_float_error(*self._ends(P), P) + 64 * np.finfo(float).eps * (np.hypot(*self.C) + self.rho)
        return np.maximum(d - err, 0.0), d + err

    def samples(self, spacing, window=None):
        a0 = np.arctan2(*(self.A - self.C)[::-1])
        span = (np.arctan2(*(self.B - self.C)[::-1]) - a0) % (2 * np.pi) or 2 * np.pi
        n = max(2, int(np.ceil(self.rho * span / max(spacing, 1e-300))) + 1)
        t = a0 + np.linspace(0.0, span, n)
        return self.C + self.rho * np.column_stack([np.cos(t), np.sin(t)])


class EllipticArcGeometry:
    """A closed :class:`runtime.sites.elliptic_arc.EllipticArc` seen as a site geometry: its
    distance is the least over its pieces (:meth:`EllipticArc.pieces`, between two vertices of the
    ellipse) of :func:`runtime.segments.ellipse_pieces.piece_distances`, with the rigorous float
    bounds of :func:`runtime.segments.ellipse_pieces.piece_distance_bounds` and the arb ball of
    :func:`runtime.segments.ellipse_pieces.piece_distance_ball` for near ties."""

    kind = "elliptic_arc"
    bounded = True

    def __init__(self, arc):
        self.exact = arc
        self.pieces = [PieceData.of(p) for p in arc.pieces()]
        _c, M, N, p0, p1 = arc.float_data()
        self.speed = float(max(np.hypot(*M), np.hypot(*N)))       # ≥ |e'(φ)|
        self.span = p1 - p0

    def bounding_box(self):
        """The box of c + [cos φ]·M + [sin φ]·N with the ranges of cos φ and sin φ over the arc
        (its ends and the frame's vertex directions inside it), exact, then rounded outwards: the
        box of a parallelogram holding the arc, tight for axis-parallel frames, looser for others."""
        arc = self.exact
        us = [arc.ua, arc.ub] + [d for d in VERTEX_DIRECTIONS if arc.contains_direction(d)]
        lo_c, hi_c = min(u[0] for u in us), max(u[0] for u in us)
        lo_s, hi_s = min(u[1] for u in us), max(u[1] for u in us)
        box = []
        for k in (0, 1):
            terms = [(lo_c * arc.M[k], hi_c * arc.M[k]), (lo_s * arc.N[k], hi_s * arc.N[k])]
            box.append((Fraction(arc.c[k]) + sum(min(t) for t in terms), Fraction(arc.c[k]) + sum(max(t) for t in terms)))
        return _outward([box[0][0], box[1][0], box[0][1], box[1][1]])

    def distance(self, P):
        P = np.asarray(P, float).reshape(-1, 2)
        return np.min([piece_distances(p, P) for p in self.pieces], axis=0)

    def distance_bounds(self, P):
        P = np.asarray(P, float).reshape(-1, 2)
        lo, hi = zip(*(piece_distance_bounds(p, P) for p in self.pieces))
        return np.min(lo, axis=0), np.min(hi, axis=0)

    def distance_ball(self, x, y) -> arb:
        """A ball holding the distance from the exact point (x, y) (floats) to the arc, at the
        context's precision."""
        balls = [piece_distance_ball(p, arb(x), arb(y)) for p in self.pieces]
        lo = min(b.lower() for b in balls)
        hi = min(b.upper() for b in balls)
        return lo.union(hi)

    def nearest_ends(self, x, y) -> list:
        """The arc's ends (exact Fraction pairs) proved to be its nearest points from the exact
        point (x, y) (floats): :func:`runtime.segments.ellipse_pieces.closest_at_an_end` on an
        arc of one piece (the diagram's elliptic sites are pieces); [] when not proved."""
        if len(self.pieces) != 1:
            return []
        ends = closest_at_an_end(self.pieces[0], arb(x), arb(y))
        return [(self.exact.a, self.exact.b)[e] for e in (ends or ())]

    def samples(self, spacing, window=None):
        """Points of the arc at most ``spacing`` apart along it (|e'| ≤ max(|M|, |N|))."""
        n = max(2, int(np.ceil(self.speed * self.span / max(spacing, 1e-300))) + 1)
        c, M, N, p0, p1 = self.exact.float_data()
        phi = np.linspace(p0, p1, n)
        c, M, N = (np.array(v, float) for v in (c, M, N))
        return c + np.cos(phi)[:, None] * M + np.sin(phi)[:, None] * N
