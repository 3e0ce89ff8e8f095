"""What a local update of a diagram of points and segments shares between insertion and deletion
(thesis §1.2: an edit changes only the regions it touches): the exact site keys, the float boxes
and the vertex arrays of the diagram kept from edit to edit (:class:`EditIndex`), the conflict test
of a vertex against a piece, the closure test at changed vertices, and the proof of the changed
part (:func:`prove_part`) against the sites that can reach it.

**Proof of a part.**  The changed vertices and edges are proved with the certificate's routines
(:func:`runtime.segments.certificate_vertices.prove_vertices`,
:func:`runtime.segments.certificate_edges.prove_edges`) against a
:class:`runtime.segments.certificate_sites.SiteTable` of the sites that can reach them, not of all
sites (building the table of all N sites is linear in N).  A vertex needs the sites that meet its
closed circle; a point y of an edge (i, j) needs the sites within d_i(y) of y.  The edge proof
puts the curve within the edge's ``tolerance`` of its polyline, so with M the largest float
distance from a polyline point to the edge's first site, h the longest polyline step and t the
tolerance, every point y of the curve is within h + t of a polyline point and d_i(y) ≤ M + h + t.
Every site meeting such a disc meets the polyline's box widened by 2(M + h + t); the table holds
every site whose float box meets that box widened once more by its own size and a relative
rounding margin of 10⁻⁹ (float boxes of exact sites are within a few ulps), and the closure of
each curve (its end point sites), which the table's end codes need.  A site outside the table is
therefore farther than the distance to the nearest site from every point the proof is about, and
the proof against the table is the proof against all sites.

Public API: :class:`EditIndex`, :func:`site_key`, :func:`point_key`, :func:`site_box`,
:func:`piece_ends`, :func:`piece_distance`, :func:`conflicts`, :func:`closure_holds`,
:func:`prove_part`, :data:`MARGIN`.
"""
from __future__ import annotations

from collections import Counter
from fractions import Fraction

import numpy as np

from ..sites.segment import Segment
from ..voronoi.structure import Diagram, DiagramEdge, DiagramVertex
from .certificate_edges import prove_edges
from .certificate_sites import SiteTable
from .certificate_vertices import prove_vertices

__all__ = ["EditIndex", "site_key", "point_key", "site_box", "piece_ends", "piece_distance", "conflicts",
           "closure_holds", "prove_part", "MARGIN"]

#: margin of the conflict test, relative to 1 + |x| + |y| + r of the vertex (a hundred times the
#: certificate's position tolerance)
MARGIN = 1e-8


def site_key(s) -> tuple:
    """The exact key of an elementary site (a segment's ends sorted)."""
    if isinstance(s, Segment):
        a = (Fraction(s.p[0]), Fraction(s.p[1]))
        b = (Fraction(s.q[0]), Fraction(s.q[1]))
        return ("s",) + tuple(sorted((a, b)))
    return ("p", Fraction(str(s.cx)), Fraction(str(s.cy)))


def point_key(p) -> tuple:
    """The key of the point site at the exact point ``p``."""
    return ("p", Fraction(p[0]), Fraction(p[1]))


def site_box(s) -> tuple:
    """The float box (x0, y0, x1, y1) of a site."""
    if isinstance(s, Segment):
        x0, y0, x1, y1 = float(s.p[0]), float(s.p[1]), float(s.q[0]), float(s.q[1])
        return min(x0, x1), min(y0, y1), max(x0, x1), max(y0, y1)
    x, y = float(s.cx), float(s.cy)
    return x, y, x, y


def piece_ends(s):
    """The float ends (a, b) of a segment or point (a = b)."""
    if isinstance(s, Segment):
        return (np.array([float(s.p[0]), float(s.p[1])]), np.array([float(s.q[0]), float(s.q[1])]))
    a = np.array([float(s.cx), float(s.cy)])
    return a, a


def piece_distance(a, b, X):
    """Float distances from the rows of X to the closed segment [a, b] (a point when a == b)."""
    d = b - a
    L2 = float(d @ d)
    if L2 == 0:
        return np.hypot(X[:, 0] - a[0], X[:, 1] - a[1])
    t = np.clip(((X - a) @ d) / L2, 0.0, 1.0)
    F = a + t[:, None] * d
    return np.hypot(X[:, 0] - F[:, 0], X[:, 1] - F[:, 1])


def conflicts(a, b, XY, R):
    """The circles (centres XY, radii R) that the closed piece [a, b] enters or comes within the
    margin :data:`MARGIN` of (a boolean row per circle)."""
    if not len(R):
        return np.zeros(0, bool)
    margin = MARGIN * (1 + np.abs(XY).sum(axis=1) + R)
    return piece_distance(a, b, XY) < R + margin


class EditIndex:
    """The per-diagram arrays a local update reads, kept from one edit to the next so that an
    edit does not rebuild them from all sites: ``keys`` (exact site key -> index), ``boxes``
    (n, 4) float boxes, ``XY``/``R`` the vertices' centres and radii in ``D.vertices`` order.
    :meth:`of` builds it (linear in N, once) or returns the diagram's own when it still fits."""

    def __init__(self, keys, boxes, XY, R):
        self.keys, self.boxes, self.XY, self.R = keys, boxes, XY, R

    @classmethod
    def build(cls, D) -> "EditIndex":
        keys = {site_key(s): k for k, s in enumerate(D.sites)}
        boxes = np.array([site_box(s) for s in D.sites], float).reshape(-1, 4)
        XY = np.array([[v.x, v.y] for v in D.vertices], float).reshape(-1, 2)
        R = np.array([v.radius for v in D.vertices], float)
        return cls(keys, boxes, XY, R)

    @classmethod
    def of(cls, D, index=None) -> "EditIndex":
        """``index`` when it matches D's sizes, else a fresh one."""
        if index is not None and len(index.keys) == len(D.sites) == len(index.boxes) \
                and len(index.R) == len(D.vertices):
            return index
        return cls.build(D)

    def near(self, lo, hi) -> list[int]:
        """The sites whose box meets the box [lo, hi]."""
        b = self.boxes
        return np.nonzero((b[:, 0] <= hi[0]) & (b[:, 2] >= lo[0]) & (b[:, 1] <= hi[1])
                          & (b[:, 3] >= lo[1]))[0].tolist()

    def vertices_in(self, lo, hi) -> np.ndarray:
        """Rows of the vertices whose centre lies in the box [lo, hi]."""
        X = self.XY
        return np.nonzero((X[:, 0] >= lo[0]) & (X[:, 0] <= hi[0]) & (X[:, 1] >= lo[1]) & (X[:, 1] <= hi[1]))[0]


def closure_holds(edges, check) -> bool:
    """Each vertex of ``check`` has exactly one incident edge per cyclically consecutive pair of its
    sites and no other; every edge ending at one lists a consecutive pair of it."""
    want = {v.id for v in check}
    at: dict = {u: Counter() for u in want}
    for e in edges:
        pair = tuple(sorted(e.sites))
        for u in e.ends:
            if u in want:
                at[u][pair] += 1
    return all(Counter(v.site_pairs()) == at[v.id] for v in check)


def _reach_box(vertices, edges, sites):
    """The box every site that can matter to the proof of ``vertices`` and ``edges`` meets
    (module docstring)."""
    lo = np.full(2, np.inf)
    hi = np.full(2, -np.inf)
    for v in vertices:
        c = np.array([v.x, v.y])
        lo, hi = np.minimum(lo, c - 2 * v.radius), np.maximum(hi, c + 2 * v.radius)
    for e in edges:
        P = np.asarray(e.polyline, float).reshape(-1, 2)
        a, b = piece_ends(sites[e.sites[0]])
        M = float(piece_distance(a, b, P).max())
        h = float(np.hypot(*np.diff(P, axis=0).T).max()) if len(P) > 1 else 0.0
        w = 2 * (M + h + float(e.tolerance))
        lo, hi = np.minimum(lo, P.min(axis=0) - w), np.maximum(hi, P.max(axis=0) + w)
    size = float(np.max(hi - lo))
    pad = size + 1e-9 * (1 + float(np.abs(lo).max()) + float(np.abs(hi).max()))
    return lo - pad, hi + pad


def prove_part(sites, index: EditIndex, vertices, edges, problems: list) -> bool:
    """Prove ``vertices`` (changed vertices and the kept ends of changed edges) and ``edges``
    against the sites that can reach them (module docstring); sites, vertices and edges are in the
    global numbering of ``sites``/``index``.  True when every part is proved."""
    if not vertices and not edges:
        return True
    lo, hi = _reach_box(vertices, edges, sites)
    chosen = set(index.near(lo, hi))
    chosen |= {s for v in vertices for s in v.sites} | {s for e in edges for s in e.sites}
    for k in list(chosen):
        s = sites[k]
        if isinstance(s, Segment):
            for p in (s.p, s.q):
                t = index.keys.get(point_key(p))
                if t is not None:
                    chosen.add(t)
    order = sorted(chosen)
    loc = {k: t for t, k in enumerate(order)}
    T = SiteTable([sites[k] for k in order])
    sub_v = [DiagramVertex(v.id, tuple(loc[s] for s in v.sites), v.x, v.y, v.radius, False) for v in vertices]
    sub_e = [DiagramEdge(e.id, tuple(loc[s] for s in e.sites), e.ends, e.closed, e.polyline, e.tolerance, False)
             for e in edges]
    sub = Diagram(T.sites, sub_v, sub_e)
    vproofs = prove_vertices(sub, T, problems)
    eproofs = prove_edges(sub, T, vproofs, problems)
    return not problems and all(p.ok for p in vproofs) and all(p.ok for p in eproofs)
