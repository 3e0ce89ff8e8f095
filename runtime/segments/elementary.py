"""Elementary sites of a segment Voronoi diagram: points and open segments (thesis §2.2).

A set of closed segments and points is decomposed, as in CGAL's segment Delaunay graph
(Karavelas, *A robust and efficient implementation for the segment Voronoi diagram*, 2004) and
Boost.Polygon, into the "harmless sites" of Alt and Schwarzkopf (thesis §2.2): every distinct
endpoint and isolated point is one **point site**, every segment contributes its **open interior**.
The distance to an open interior is the distance to the closed segment, so a point equidistant
from an endpoint e and the interior of a segment s ending at e (the half-plane beyond e) belongs
to e: e's region is bounded by the line through e perpendicular to s.

Two consecutive segments that meet at a common endpoint p at an angle of exactly 180° (p is the
endpoint of these two only) are merged into one elementary segment and p is not a site: the
union is the same closed set, and the merged site keeps the bisectors linear and parabolic
(with p as a site, the whole perpendicular at p would be equidistant from three sites).

Numbering: point sites first (in order of first appearance), then segment interiors in input
order.  ``source[i]`` is the index of the input piece that produced elementary site i (for a
shared endpoint: the first piece ending there; for a merged segment: the first of its pieces).

Public API: :class:`ElementarySites`, :func:`decompose`.
"""
from __future__ import annotations

from fractions import Fraction

import numpy as np

from ..predicates.circles import Point
from ..sites.segment import Segment, as_point_pair

__all__ = ["ElementarySites", "decompose", "POINT", "SEGMENT"]

#: site kinds of :attr:`ElementarySites.kind`
POINT, SEGMENT = 0, 1


class ElementarySites:
    """Point sites and open segments, exact and as float arrays.

    ``sites``: :class:`runtime.predicates.circles.Point` and :class:`runtime.sites.segment.Segment`
    (meaning its open interior); ``kind``: :data:`POINT` / :data:`SEGMENT` per site; ``xy``: the
    exact coordinates of the point sites; ``ends[s]``: the site indices of the two endpoints of
    segment site s (−1 for a point site); ``incident[p]``: the segment sites ending at point site
    p; ``A``, ``B``: float endpoints (n × 2; A = B = the point for a point site)."""

    def __init__(self, points, segments, source):
        self.xy: list[tuple[Fraction, Fraction]] = list(points)
        self.n_points = len(points)
        self.seg_ends: list[tuple[int, int]] = [tuple(s) for s in segments]
        self.source = list(source)
        self.sites = [Point(*p) for p in self.xy] + [Segment(self.xy[a], self.xy[b]) for a, b in self.seg_ends]
        n = len(self.sites)
        self.kind = np.array([POINT] * self.n_points + [SEGMENT] * len(self.seg_ends), dtype=np.int8)
        self.ends = np.full((n, 2), -1, dtype=np.int64)
        if self.seg_ends:
            self.ends[self.n_points:] = np.array(self.seg_ends, dtype=np.int64)
        self.incident: list[list[int]] = [[] for _ in range(self.n_points)]
        for s, (a, b) in enumerate(self.seg_ends):
            self.incident[a].append(self.n_points + s)
            self.incident[b].append(self.n_points + s)
        P = np.array([[float(x), float(y)] for x, y in self.xy], dtype=float).reshape(-1, 2)
        self.A = np.empty((n, 2))
        self.B = np.empty((n, 2))
        self.A[:self.n_points] = P
        self.B[:self.n_points] = P
        if self.seg_ends:
            E = np.array(self.seg_ends)
            self.A[self.n_points:] = P[E[:, 0]]
            self.B[self.n_points:] = P[E[:, 1]]

    def __len__(self) -> int:
        return len(self.sites)

    def is_endpoint(self, p: int, s: int) -> bool:
        """Point site p is an endpoint of segment site s."""
        return self.kind[s] == SEGMENT and p in (int(self.ends[s, 0]), int(self.ends[s, 1]))


def decompose(pieces, sources=None) -> ElementarySites:
    """The elementary sites of ``pieces`` (:class:`runtime.sites.segment.Segment`, point sites
    :class:`runtime.predicates.circles.Point` or (x, y) pairs).  ``sources``: the input index of
    each piece (default: its position).  The pieces must be admissible (no crossings, see
    :func:`runtime.segments.crossings.check_pieces`, which the caller runs first)."""
    if sources is None:
        sources = list(range(len(pieces)))
    index: dict = {}
    points: list = []
    psource: list = []
    segs: list = []
    ssource: list = []

    def point_id(p, src):
        if p not in index:
            index[p] = len(points)
            points.append(p)
            psource.append(src)
        return index[p]

    for piece, src in zip(pieces, sources):
        if isinstance(piece, Segment):
            segs.append((point_id(piece.p, src), point_id(piece.q, src)))
            ssource.append(src)
        else:
            point_id(as_point_pair(piece, f"site {src}"), src)
    segs, ssource, points, psource = _merge_straight(segs, ssource, points, psource)
    return ElementarySites(points, segs, psource + ssource)


def _merge_straight(segs, ssource, points, psource):
    """Merge the two segments of every endpoint shared by exactly two collinear, opposite
    segments (see the module docstring); renumber the remaining points."""
    inc: dict = {}
    for s, (a, b) in enumerate(segs):
        inc.setdefault(a, []).append(s)
        inc.setdefault(b, []).append(s)
    alive = list(segs)
    dead_point = set()
    changed = True
    while changed:
        changed = False
        for p, ss in list(inc.items()):
            live = [s for s in ss if alive[s] is not None]
            if len(live) != 2 or p in dead_point:
                continue
            s1, s2 = live
            a = alive[s1][0] if alive[s1][1] == p else alive[s1][1]
            b = alive[s2][0] if alive[s2][1] == p else alive[s2][1]
            (ax, ay), (px, py), (bx, by) = points[a], points[p], points[b]
            cross = (px - ax) * (by - ay) - (py - ay) * (bx - ax)
            dot = (px - ax) * (bx - px) + (py - ay) * (by - py)
            if cross != 0 or dot <= 0:
                continue
            alive[s1] = (a, b)
            alive[s2] = None
            inc[b] = [s1 if s == s2 else s for s in inc[b]]
            dead_point.add(p)
            changed = True
    keep = [i for i in range(len(points)) if i not in dead_point]
    renum = {old: new for new, old in enumerate(keep)}
    out_segs, out_src = [], []
    for s, e in enumerate(alive):
        if e is not None:
            out_segs.append((renum[e[0]], renum[e[1]]))
            out_src.append(ssource[s])
    return out_segs, out_src, [points[i] for i in keep], [psource[i] for i in keep]
