"""Segments and circular arcs seen as site geometries (distance, rigorous bounds, samples).

The proximity queries of :mod:`runtime.voronoi.queries` (nearest site, cells) ask every site
for the interface of :class:`runtime.voronoi.geometry.SiteGeometry`: ``distance``,
``distance_bounds``, ``bounding_box``, ``samples``.  Points, circles and conics have theirs in
:mod:`runtime.voronoi.conic_geometry`; the open interiors of segments and arcs (thesis §2.2) get
them here, from the one distance implementation of :mod:`runtime.segments.distance`.

Public API: :class:`SegmentGeometry`, :class:`ArcGeometry`.
"""
from __future__ import annotations

import numpy as np

from ..sites.segment import Segment
from .distance import arc_distances, distances as segment_distances, float_error as segment_float_error

__all__ = ["SegmentGeometry", "ArcGeometry"]


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
        P = self.samples(self.rho / 64)
        return (*P.min(axis=0).tolist(), *P.max(axis=0).tolist())

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
