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

Circular arcs (:class:`runtime.sites.arc.Arc`) are split the same way.  Where exactly two
pieces meet at p with opposite tangents but are not two segments (an arc continuing a segment or
an arc smoothly: a fillet, a stadium), p is **not** a site: it lies in both closures, and the
normal line at p is the bisector of the two open pieces.  Such a *smooth joint* is an end code
−2 − node in :attr:`ElementarySites.ends` (node = index into ``nodes``).

Numbering: point sites first (in order of first appearance), then segment interiors in input
order.  ``source[i]`` is the index of the input piece that produced elementary site i (for a
shared endpoint: the first piece ending there; for a merged segment: the first of its pieces).
Each elementary site carries the ``label`` of that same piece (None when it has none), so labels
reach the diagram's JSON, GeoJSON and GeoDataFrames.

Elliptic arcs (:class:`runtime.sites.elliptic_arc.EllipticArc`) are first cut at the ellipse's
vertices (:meth:`~runtime.sites.elliptic_arc.EllipticArc.pieces`), then each piece is split the same
way; a piece is an elementary site of kind :data:`ELLIPSE` with its
:class:`runtime.segments.ellipse_pieces.PieceData` in :attr:`ElementarySites.ellipse`.

Public API: :class:`ElementarySites`, :func:`decompose`, :data:`POINT`, :data:`SEGMENT`, :data:`ARC`,
:data:`ELLIPSE`.
"""
from __future__ import annotations


import numpy as np

from ..predicates.circles import Point
from ..sites.arc import Arc
from ..sites.elliptic_arc import EllipticArc
from ..sites.kinds import SiteKind
from ..sites.segment import Segment, as_point_pair
from .ellipse_pieces import PieceData

__all__ = ["ElementarySites", "decompose", "POINT", "SEGMENT", "ARC", "ELLIPSE"]

#: site kinds of :attr:`ElementarySites.kind` (codes of :class:`runtime.sites.kinds.SiteKind`)
# plain ints (an enum member in a numpy comparison costs a failed metaclass lookup per call)
POINT, SEGMENT, ARC, ELLIPSE = (int(k) for k in (SiteKind.POINT, SiteKind.SEGMENT, SiteKind.ARC, SiteKind.ELLIPTIC_ARC))
_KIND = {"segment": SEGMENT, "arc": ARC, "ellipse": ELLIPSE}


class _Nodes:
    """Exact coordinates by end code: a point site's index (≥ 0) or −2 − node (a smooth joint)."""

    def __init__(self, nodes, site_node):
        self.nodes, self.site_node = nodes, site_node

    def __getitem__(self, k):
        k = int(k)
        return self.nodes[self.site_node[k]] if k >= 0 else self.nodes[-2 - k]


class ElementarySites:
    """Point sites, open segments and open circular arcs, exact and as float arrays.

    ``sites``: :class:`runtime.sites.circle.Point`, :class:`runtime.sites.segment.Segment`
    and :class:`runtime.sites.arc.Arc` (meaning their open interiors); ``kind``: :data:`POINT` /
    :data:`SEGMENT` / :data:`ARC` per site; ``xy[code]``: the exact coordinates of a point site
    or of a smooth joint (``code`` < −1); ``ends[s]``: the end codes of curve s (its start and end;
    −1 for a point site); ``incident[p]``: the curves ending at point site p; ``A``, ``B``: float
    ends (A = B = the point for a point site); ``C``, ``rho``: centre and radius of an arc (NaN
    otherwise); ``arc[s]``: the exact (centre, radius) of arc s; ``joints``: smooth joint node ->
    its two curves; ``labels[i]``: the label of site i's source piece (also ``sites[i].label``);
    ``ellipse[s]``: the :class:`runtime.segments.ellipse_pieces.PieceData` of an elliptic piece s
    (``C``, ``rho``: its centre and major semi-axis, a magnitude for rounding bounds)."""

    def __init__(self, nodes, point_nodes, curves, source, labels=None):
        self.nodes = list(nodes)
        self.n_points = len(point_nodes)
        self.xy = _Nodes(self.nodes, list(point_nodes))
        node_site = {nd: i for i, nd in enumerate(point_nodes)}
        self.source = list(source)
        n = self.n_points + len(curves)
        self.labels = [None] * n if labels is None else list(labels)
        self.kind = np.array([POINT] * self.n_points + [_KIND[c[0]] for c in curves], dtype=np.int8)
        self.ends = np.full((n, 2), -1, dtype=np.int64)
        self.arc: dict = {}
        self.ellipse: dict = {}
        self.C = np.full((n, 2), np.nan)
        self.rho = np.full(n, np.nan)
        self.sites = [Point(*self.nodes[nd], label=self.labels[i]) for i, nd in enumerate(point_nodes)]
        self.incident: list[list[int]] = [[] for _ in range(self.n_points)]
        self.joints: dict = {}
        for k, (kind, na, nb, data) in enumerate(curves):
            s = self.n_points + k
            codes = [node_site[nd] if nd in node_site else -2 - nd for nd in (na, nb)]
            self.ends[s] = codes
            for nd, code in zip((na, nb), codes):
                if code >= 0:
                    self.incident[code].append(s)
                else:
                    self.joints.setdefault(nd, []).append(s)
            if kind == "segment":
                self.sites.append(Segment(self.nodes[na], self.nodes[nb], self.labels[s]))
            elif kind == "ellipse":
                self.sites.append(data)
                self.ellipse[s] = P_ = PieceData.of(data)
                self.C[s] = (float(P_.c[0]), float(P_.c[1]))
                self.rho[s] = float(np.hypot(float(P_.M[0]), float(P_.M[1])))
            else:
                c, rho = data
                self.sites.append(Arc(c, rho, self.nodes[na], self.nodes[nb], self.labels[s]))
                self.arc[s] = (c, rho)
                self.C[s] = (float(c[0]), float(c[1]))
                self.rho[s] = float(rho)
        P = np.array([[float(x), float(y)] for x, y in self.nodes], dtype=float).reshape(-1, 2)
        self.A = np.empty((n, 2))
        self.B = np.empty((n, 2))
        if self.n_points:
            self.A[:self.n_points] = P[list(point_nodes)]
            self.B[:self.n_points] = P[list(point_nodes)]
        for k, (kind, na, nb, data) in enumerate(curves):
            self.A[self.n_points + k] = P[na]
            self.B[self.n_points + k] = P[nb]
        #: the pairs (p, q), both orders, of point sites that are the two ends of one segment
        self.segment_end_pairs = {(int(a), int(b)) for s in range(self.n_points, n) if self.kind[s] == SEGMENT
                                  for a, b in (self.ends[s], self.ends[s][::-1]) if a >= 0 and b >= 0}
        #: memo of :func:`runtime.segments.vertices.common_point` by triple (it depends on the sites only)
        self.common_points: dict = {}

    def __len__(self) -> int:
        return len(self.sites)

    def is_endpoint(self, p: int, s: int) -> bool:
        """Point site p is an end of curve s."""
        return self.kind[s] != POINT and p in (int(self.ends[s, 0]), int(self.ends[s, 1]))

    def closure_points(self, t: int) -> set:
        """End codes in the closure of site t (itself for a point site)."""
        if self.kind[t] == POINT:
            return {int(t)}
        return {int(self.ends[t, 0]), int(self.ends[t, 1])}


def decompose(pieces, sources=None) -> ElementarySites:
    """The elementary sites of ``pieces`` (:class:`runtime.sites.segment.Segment`,
    :class:`runtime.sites.arc.Arc`, point sites :class:`runtime.sites.circle.Point` or (x, y)
    pairs).  ``sources``: the input index of each piece (default: its position); each elementary
    site takes the ``label`` of the piece it is attributed to (see the module docstring).  The pieces must
    be admissible (no crossings, see :func:`runtime.segments.crossings.check_pieces`, which the
    caller runs first)."""
    if sources is None:
        sources = list(range(len(pieces)))
    index: dict = {}
    nodes: list = []
    nsource: list = []
    nlabel: list = []
    isolated: set = set()
    curves: list = []
    csource: list = []
    clabel: list = []

    def node(p, src, label):
        if p not in index:
            index[p] = len(nodes)
            nodes.append(p)
            nsource.append(src)
            nlabel.append(label)
        return index[p]

    for piece, src in zip(pieces, sources):
        label = getattr(piece, "label", None)
        if isinstance(piece, Segment):
            curves.append(("segment", node(piece.p, src, label), node(piece.q, src, label), None))
        elif isinstance(piece, Arc):
            curves.append(("arc", node(piece.a, src, label), node(piece.b, src, label), (piece.c, piece.rho)))
        elif isinstance(piece, EllipticArc):
            for k, sub in enumerate(piece.pieces()):
                if k:
                    csource.append(src)
                    clabel.append(label)
                curves.append(("ellipse", node(sub.a, src, label), node(sub.b, src, label), sub))
        else:
            isolated.add(node(as_point_pair(piece, f"site {src}"), src, label))
            continue
        csource.append(src)
        clabel.append(label)
    curves, kept, dead = _merge_straight(curves, list(range(len(curves))), nodes, isolated)
    smooth = _smooth_joints(curves, nodes, isolated) - dead
    point_nodes = [nd for nd in range(len(nodes)) if nd not in dead and nd not in smooth]
    return ElementarySites(nodes, point_nodes, curves,
                           [nsource[nd] for nd in point_nodes] + [csource[k] for k in kept],
                           [nlabel[nd] for nd in point_nodes] + [clabel[k] for k in kept])


def _tangent(curve, nd, nodes):
    """The unit-free tangent direction of a curve leaving its end node ``nd``."""
    kind, na, nb, data = curve
    if kind == "segment":
        o = nb if nd == na else na
        return (nodes[o][0] - nodes[nd][0], nodes[o][1] - nodes[nd][1])
    if kind == "ellipse":
        tx, ty = data.tangent(data.ua if nd == na else data.ub)
        return (tx, ty) if nd == na else (-tx, -ty)
    (cx, cy), _ = data
    px, py = nodes[nd]
    rx, ry = px - cx, py - cy
    # counter-clockwise from a to b: leaving a the tangent is +perp(r), leaving b it is −perp(r)
    return (-ry, rx) if nd == na else (ry, -rx)


def _incidence(curves):
    inc: dict = {}
    for k, (_, na, nb, _) in enumerate(curves):
        inc.setdefault(na, []).append(k)
        inc.setdefault(nb, []).append(k)
    return inc


def _opposite(u, v) -> bool:
    return u[0] * v[1] - u[1] * v[0] == 0 and u[0] * v[0] + u[1] * v[1] < 0


def _smooth_joints(curves, nodes, isolated) -> set:
    """Nodes where exactly two curves (not both segments) meet with opposite tangents."""
    out = set()
    for nd, ks in _incidence(curves).items():
        if len(ks) != 2 or nd in isolated or ks[0] == ks[1]:
            continue
        c1, c2 = curves[ks[0]], curves[ks[1]]
        if _opposite(_tangent(c1, nd, nodes), _tangent(c2, nd, nodes)):
            out.add(nd)
    return out


def _merge_straight(curves, csource, nodes, isolated):
    """Merge the two segments of every node shared by exactly two collinear, opposite segments
    (see the module docstring).  Returns (curves, sources, merged-away nodes)."""
    alive = list(curves)
    dead = set()
    changed = True
    while changed:
        changed = False
        for nd, ks in _incidence([c if c is not None else ("x", -1, -1, None) for c in alive]).items():
            live = [k for k in ks if alive[k] is not None]
            if nd < 0 or len(live) != 2 or nd in dead or nd in isolated:
                continue
            k1, k2 = live
            if alive[k1][0] != "segment" or alive[k2][0] != "segment":
                continue
            if not _opposite(_tangent(alive[k1], nd, nodes), _tangent(alive[k2], nd, nodes)):
                continue
            a = alive[k1][1] if alive[k1][2] == nd else alive[k1][2]
            b = alive[k2][1] if alive[k2][2] == nd else alive[k2][2]
            alive[k1] = ("segment", a, b, None)
            alive[k2] = None
            dead.add(nd)
            changed = True
            break
    out = [(c, s) for c, s in zip(alive, csource) if c is not None]
    return [c for c, _ in out], [s for _, s in out], dead
