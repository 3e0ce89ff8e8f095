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
closed circle; a point y of an edge (i, j) needs the sites within d_i(y) of y (t below: the edge's
``tolerance``).
A point y of the curve is within t of a point z of a polyline step [p, q] (the bound the edge proof
checks piece by piece), d_i is convex along the step and 1-Lipschitz, so d_i(y) ≤ max(d_i(p),
d_i(q)) + t, and every site within d_i(y) of y meets the disc about the step's midpoint of radius
max(d_i(p), d_i(q)) + |q − p|/2 + 2t; a vertex needs the sites meeting its circle.  The table
holds every site whose float box meets one of these discs (radii widened by :data:`WIDEN` = 10⁻⁸
relative to 1 + |x| + |y| + r, a hundred times the certificate's vertex position tolerance: the
float centres and radii are that close to the proved ones, float boxes of exact sites and the
float distances within a few ulps), and the closure of each
curve (its end point sites), which the table's end codes need.  A site outside the table is
therefore farther than the distance to the nearest site from every point the proof is about, and
the proof against the table is the proof against all sites.

Public API: :class:`EditIndex`, :class:`KeptVertices`, :func:`site_key`, :func:`point_key`, :func:`site_box`,
:func:`piece_ends`, :func:`piece_distance`, :func:`conflicts`, :func:`closure_holds`, :func:`spliced_edge`,
:func:`prove_part`, :func:`vertex_sites`, :func:`edge_arrays`, :data:`MARGIN`, :data:`WIDEN`.
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

__all__ = ["EditIndex", "KeptVertices", "site_key", "point_key", "site_box", "piece_ends", "piece_distance", "conflicts",
           "closure_holds", "spliced_edge", "prove_part", "vertex_sites", "edge_arrays", "MARGIN", "WIDEN"]

#: margin of the conflict test, relative to 1 + |x| + |y| + r of the vertex (a hundred times the
#: certificate's position tolerance)
MARGIN = 1e-8
#: relative widening of the reach discs of :func:`prove_part`: above the certificate's vertex
#: position tolerance (10⁻¹⁰ relative) and the rounding of float boxes and distances
WIDEN = 1e-8


def _ints(p) -> tuple:
    """An exact point (Fractions) as (num, den, num, den): a key of ints hashes fast."""
    return (p[0].numerator, p[0].denominator, p[1].numerator, p[1].denominator)


def site_key(s) -> tuple:
    """The exact key of an elementary site (a segment's ends sorted), a tuple of ints."""
    if isinstance(s, Segment):
        a = (Fraction(s.p[0]), Fraction(s.p[1]))
        b = (Fraction(s.q[0]), Fraction(s.q[1]))
        a, b = sorted((a, b))
        return (1,) + _ints(a) + _ints(b)
    return (0,) + _ints((Fraction(str(s.cx)), Fraction(str(s.cy))))


def point_key(p) -> tuple:
    """The key of the point site at the exact point ``p``."""
    return (0,) + _ints((Fraction(p[0]), Fraction(p[1])))


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


def vertex_sites(vertices, width: int = 3) -> np.ndarray:
    """The site lists of ``vertices`` as rows of an int array padded with −1."""
    w = max([width] + [len(v.sites) for v in vertices])
    out = np.full((len(vertices), w), -1, dtype=np.int64)
    for r, v in enumerate(vertices):
        out[r, :len(v.sites)] = v.sites
    return out


def edge_arrays(edges):
    """The site pairs and the end vertex ids (−1 for infinity) of ``edges``, as (m, 2) int arrays."""
    ES = np.array([e.sites for e in edges], dtype=np.int64).reshape(-1, 2)
    EE = np.array([[-1 if u is None else u for u in e.ends] for e in edges], dtype=np.int64).reshape(-1, 2)
    return ES, EE


def _stack(A, B):
    """Rows of A then rows of B, the narrower padded with −1."""
    w = max(A.shape[1], B.shape[1])
    pad = lambda M: np.hstack([M, np.full((len(M), w - M.shape[1]), -1, M.dtype)])  # noqa: E731
    return np.vstack([pad(A), pad(B)])


class EditIndex:
    """The per-diagram arrays a local update reads, kept from one edit to the next so that an
    edit does not rebuild them from all sites: ``keys`` (exact site key -> index), ``boxes``
    (n, 4) float boxes; in ``D.vertices`` order ``XY``/``R`` the centres and radii, ``VS`` the
    site lists (padded with −1), ``VID`` the ids; in ``D.edges`` order ``ES`` the site pairs and ``EE`` the end
    vertex ids (−1 at infinity).  :meth:`of` builds it (linear in N, once) or returns the
    diagram's own when it still fits."""

    def __init__(self, keys, boxes, XY, R, VS, VID, ES, EE):
        self.keys, self.boxes, self.XY, self.R = keys, boxes, XY, R
        self.VS, self.VID, self.ES, self.EE = VS, VID, ES, EE

    @classmethod
    def build(cls, D) -> "EditIndex":
        keys = {site_key(s): k for k, s in enumerate(D.sites)}
        boxes = np.array([site_box(s) for s in D.sites], float).reshape(-1, 4)
        XY = np.array([[v.x, v.y] for v in D.vertices], float).reshape(-1, 2)
        R = np.array([v.radius for v in D.vertices], float)
        VID = np.array([v.id for v in D.vertices], dtype=np.int64)
        return cls(keys, boxes, XY, R, vertex_sites(D.vertices), VID, *edge_arrays(D.edges))

    @classmethod
    def of(cls, D, index=None) -> "EditIndex":
        """``index`` when it matches D's sizes, else a fresh one."""
        if index is not None and len(index.keys) == len(D.sites) == len(index.boxes) \
                and len(index.R) == len(D.vertices) == len(index.VS) and len(index.ES) == len(D.edges):
            return index
        return cls.build(D)

    def spliced(self, keys, boxes, keep_v, new_v, keep_e, new_e) -> "EditIndex":
        """The index after a splice: the rows ``keep_v`` / ``keep_e`` (boolean masks) of the vertex
        and edge arrays, then the rows of the vertices ``new_v`` and edges ``new_e``."""
        XY = np.vstack([self.XY[keep_v], np.array([[v.x, v.y] for v in new_v], float).reshape(-1, 2)])
        R = np.concatenate([self.R[keep_v], np.array([v.radius for v in new_v], float)])
        VS = _stack(self.VS[keep_v], vertex_sites(new_v, 1))
        VID = np.concatenate([self.VID[keep_v], np.array([v.id for v in new_v], dtype=np.int64)])
        ES, EE = edge_arrays(new_e)
        return EditIndex(keys, boxes, XY, R, VS, VID, np.vstack([self.ES[keep_e], ES]),
                         np.vstack([self.EE[keep_e], EE]))

    def near(self, lo, hi) -> list[int]:
        """The sites whose box meets the box [lo, hi]."""
        b = self.boxes
        return np.nonzero((b[:, 0] <= hi[0]) & (b[:, 2] >= lo[0]) & (b[:, 1] <= hi[1])
                          & (b[:, 3] >= lo[1]))[0].tolist()

    def vertices_in(self, lo, hi) -> np.ndarray:
        """Rows of the vertices whose centre lies in the box [lo, hi]."""
        X = self.XY
        return np.nonzero((X[:, 0] >= lo[0]) & (X[:, 0] <= hi[0]) & (X[:, 1] >= lo[1]) & (X[:, 1] <= hi[1]))[0]

    def vertex_rows(self, ids) -> np.ndarray:
        """Rows of the vertices with an id among ``ids``."""
        return np.nonzero(np.isin(self.VID, np.fromiter(ids, np.int64)))[0]

    def edges_at(self, ids) -> np.ndarray:
        """Rows of the edges with an end vertex among ``ids``."""
        return np.nonzero(np.isin(self.EE, np.fromiter(ids, np.int64)).any(axis=1))[0]


class KeptVertices:
    """Finds the kept vertex (a vertex of D outside ``removed``, a boolean row mask) that a local
    diagram's vertex reproduces: the same sites in the same cyclic order (smallest first) and the
    same centre within 10⁻⁶·(1 + |x| + |y| + r); one numpy pass over the centres per question."""

    def __init__(self, index: EditIndex, vertices, removed):
        self.index, self.vertices, self.removed = index, vertices, removed

    def find(self, gs, x: float, y: float, r: float) -> int:
        """The id of the one matching kept vertex, or −1."""
        X = self.index.XY
        tol = 1e-6 * (1 + abs(x) + abs(y) + r)
        rows = np.nonzero(np.abs(X[:, 0] - x) + np.abs(X[:, 1] - y) < tol)[0].tolist()
        hits = [self.vertices[t] for t in rows if not self.removed[t] and tuple(self.vertices[t].sites) == gs]
        return hits[0].id if len(hits) == 1 else -1


def spliced_edge(le, gp, ends, eid: int):
    """The local diagram's edge ``le`` of the site pair ``gp`` (the diagram's numbering) as an edge
    ``eid`` of the edited diagram between the vertices ``ends`` (None: at infinity, −1: matching
    no vertex), sites in increasing order (the polyline reversed with them); a reason (str) when
    it cannot be spliced: it goes to infinity or ends at a vertex that matches none."""
    if None in ends or le.closed:
        return "a changed edge goes to infinity"
    if -1 in ends:
        return "a changed edge ends at a vertex of the local diagram that matches none"
    i, j = gp
    poly = np.asarray(le.polyline, float)
    if i > j:
        i, j = j, i
        ends = ends[::-1]
        poly = poly[::-1].copy()
    return DiagramEdge(eid, (i, j), tuple(ends), False, poly, le.tolerance, False)


def closure_holds(edges, check) -> bool:
    """Each vertex of ``check`` has exactly one incident edge per cyclically consecutive pair of its
    sites and no other; every edge ending at one lists a consecutive pair of it."""
    want = {v.id for v in check}
    at: dict = {u: Counter() for u in want}
    for e in edges:
        a, b = e.ends
        if a in want or b in want:
            pair = tuple(sorted(e.sites))
            for u in e.ends:
                if u in want:
                    at[u][pair] += 1
    return all(Counter(v.site_pairs()) == at[v.id] for v in check)


def reach_discs(vertices, edges, sites) -> np.ndarray:
    """Discs (x, y, r), one per vertex and one per polyline step of each edge, that every site
    that can matter to the proof of ``vertices`` and ``edges`` meets (module docstring)."""
    out = [(v.x, v.y, v.radius) for v in vertices]
    for e in edges:
        P = np.asarray(e.polyline, float).reshape(-1, 2)
        a, b = piece_ends(sites[e.sites[0]])
        d = piece_distance(a, b, P)
        t = float(e.tolerance)
        if len(P) == 1:
            out.append((P[0, 0], P[0, 1], d[0] + 2 * t))
            continue
        h = np.hypot(*np.diff(P, axis=0).T)
        M = np.maximum(d[:-1], d[1:])
        mid = (P[:-1] + P[1:]) / 2
        out.extend(zip(mid[:, 0], mid[:, 1], M + h / 2 + 2 * t))
    D = np.array(out, float).reshape(-1, 3)
    D[:, 2] = D[:, 2] * (1 + WIDEN) + WIDEN * (1 + np.abs(D[:, :2]).sum(axis=1))
    return D


def sites_meeting(index: EditIndex, D: np.ndarray) -> set:
    """The sites whose float box meets one of the discs D (rows x, y, r)."""
    lo = (D[:, :2] - D[:, 2:]).min(axis=0)
    hi = (D[:, :2] + D[:, 2:]).max(axis=0)
    cand = np.asarray(index.near(lo, hi), dtype=np.int64)
    if not len(cand):
        return set()
    B = index.boxes[cand]
    dx = np.maximum(np.maximum(B[:, None, 0] - D[None, :, 0], D[None, :, 0] - B[:, None, 2]), 0.0)
    dy = np.maximum(np.maximum(B[:, None, 1] - D[None, :, 1], D[None, :, 1] - B[:, None, 3]), 0.0)
    hit = (dx * dx + dy * dy <= (D[None, :, 2]) ** 2).any(axis=1)
    return set(cand[hit].tolist())


def prove_part(sites, index: EditIndex, vertices, edges, problems: list) -> bool:
    """Prove ``vertices`` (changed vertices and the kept ends of changed edges) and ``edges``
    against the sites that can reach them (module docstring); sites, vertices and edges are in the
    global numbering of ``sites``/``index``.  True when every part is proved."""
    if not vertices and not edges:
        return True
    chosen = sites_meeting(index, reach_discs(vertices, edges, sites))
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
