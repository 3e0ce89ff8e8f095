"""What a local update of a diagram of points, segments and circular arcs shares between insertion
and deletion (thesis §1.2: an edit changes only the regions it touches): the exact site keys, the
float boxes and the vertex arrays of the diagram kept from edit to edit (:class:`EditIndex`), the
conflict test of a vertex against a piece, the exact ends and tangents of curves (a point where two
curves would continue each other stops being a site, :mod:`runtime.segments.elementary`), the
closure test at changed vertices, and the proof of the changed part (:func:`prove_part`) against
the sites that can reach it.

**Distances.**  The conflict test and the reach discs below use float distances to the closed
sites (:func:`site_distance`); for an arc | |x − c| − ρ | in its range, the nearer end's outside,
with the error bound :data:`ARC_ERROR`·(|c| + ρ + |x|) (cancellation when ρ is large) added to
the margins, so that a vertex called free of a site is free of it exactly.

**Proof of a part.**  The changed vertices and edges are proved with the certificate's routines
(:func:`runtime.segments.certificate_vertices.prove_vertices`,
:func:`runtime.segments.certificate_edges.prove_edges`) against a
:class:`runtime.segments.certificate_sites.SiteTable` of the sites that can reach them, not of all
sites (building the table of all N sites is linear in N).  A vertex needs the sites that meet its
closed circle; a point y of an edge (i, j) needs the sites within d_i(y) = d_j(y) of y (t below: the
edge's ``tolerance``).
A point y of the curve is within t of a point z of a polyline step [p, q] (the bound the edge proof
checks piece by piece), and d_i is 1-Lipschitz, so d_i(y) ≤ d_i(z) + t.  For a point or a segment
d_i is convex along the step, so d_i(z) ≤ M = max(d_i(p), d_i(q)), and every site within d_i(y) of
y meets the disc about the step's midpoint of radius M + |q − p|/2 + 2t; the distance to an arc
is not convex (inside its circle it is ρ − |x − c|), only d_i(z) ≤ min(d_i(p) + |z − p|,
d_i(q) + |z − q|) ≤ M + |q − p|/2, so for an edge of two arcs the radius is M + |q − p| + 2t (of
an arc and a point or segment, the latter is used).  A vertex needs the sites meeting its circle.
The table holds every site whose float box meets one of these discs (radii widened by
:data:`WIDEN` = 10⁻⁸ relative to 1 + |x| + |y| + r, a hundred times the certificate's vertex
position tolerance: the float centres and radii are that close to the proved ones, float boxes of
exact sites — an arc's box holds its ends and the extreme points of its circle in its range — and
the float distances within a few ulps), and the closure of each curve: its end point sites, and at
an end that is a smooth joint the curve continuing there, which the table's end codes need.  A
site outside the table is therefore farther than the distance to the nearest site from every point
the proof is about, and the proof against the table is the proof against all sites.

Public API: :class:`EditIndex`, :class:`KeptVertices`, :func:`site_key`, :func:`point_key`, :func:`site_box`,
:func:`piece_ends`, :func:`piece_distance`, :func:`site_distance`, :func:`distance_error`, :func:`conflicts`,
:func:`curve_ends`, :func:`leaving`, :func:`opposite`, :func:`curves_ending_at`, :func:`editable`,
:func:`closure_holds`, :func:`spliced_edge`, :func:`prove_part`, :func:`vertex_sites`, :func:`edge_arrays`,
:func:`listing`, :func:`conflict_mask`, :class:`SitesWithNew`,
:data:`MARGIN`, :data:`WIDEN`, :data:`ARC_ERROR`; the steps both updates take: :func:`with_joint_partners`,
:func:`local_diagram`, :func:`smallest_first`, :class:`Splice`, :func:`changed_part_holds`, :func:`local_result`.

Length: the shared part of two updates (index, distances, ends, proof, and the steps of the
splice both take, written once); the curve helpers are a few lines each and read by both updates
and the edit state.
"""
from __future__ import annotations

from collections import ChainMap, Counter
from fractions import Fraction

import numpy as np

from ..predicates.circles import Point
from ..sites.arc import Arc
from ..sites.segment import Segment
from ..voronoi.site_input import SiteError
from ..voronoi.structure import Diagram, DiagramEdge, DiagramVertex
from .certificate_edges import prove_edges
from .certificate_sites import SiteTable
from .certificate_vertices import prove_vertices

__all__ = ["EditIndex", "KeptVertices", "site_key", "point_key", "site_box", "piece_ends", "piece_distance", "site_distance",
           "conflicts", "closure_holds", "spliced_edge", "prove_part", "vertex_sites", "edge_arrays", "curve_ends",
           "leaving", "opposite", "editable", "curves_ending_at", "distance_error", "MARGIN", "WIDEN", "ARC_ERROR",
           "with_joint_partners", "local_diagram", "smallest_first", "Splice", "changed_part_holds", "local_result",
           "listing", "conflict_mask", "SitesWithNew"]

#: margin of the conflict test, relative to 1 + |x| + |y| + r of the vertex (a hundred times the
#: certificate's position tolerance)
MARGIN = 1e-8
#: relative widening of the reach discs of :func:`prove_part`: above the certificate's vertex
#: position tolerance (10⁻¹⁰ relative) and the rounding of float boxes and distances
WIDEN = 1e-8
#: float error of an arc's distance, relative to |c| + ρ + |x| (cancellation in |x − c| − ρ and the
#: rounding of the rational centre, radius and ends: a few hundred units in the last place, far above
#: the few ulps of the evaluation)
ARC_ERROR = 1e-13


def editable(s) -> bool:
    """A site the local updates handle: a point, a segment or a circular arc (elliptic pieces and
    other sites are rebuilt)."""
    return isinstance(s, (Segment, Arc)) or (isinstance(s, Point) and s.r2 == 0)


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
    if isinstance(s, Arc):
        rho = Fraction(s.rho)
        return ((2,) + _ints((Fraction(s.c[0]), Fraction(s.c[1]))) + (rho.numerator, rho.denominator)
                + _ints((Fraction(s.a[0]), Fraction(s.a[1]))) + _ints((Fraction(s.b[0]), Fraction(s.b[1]))))
    return (0,) + _ints((Fraction(str(s.cx)), Fraction(str(s.cy))))


def point_key(p) -> tuple:
    """The key of the point site at the exact point ``p``."""
    return (0,) + _ints((Fraction(p[0]), Fraction(p[1])))


def site_box(s) -> tuple:
    """The float box (x0, y0, x1, y1) of a site."""
    if isinstance(s, Segment):
        x0, y0, x1, y1 = float(s.p[0]), float(s.p[1]), float(s.q[0]), float(s.q[1])
        return min(x0, x1), min(y0, y1), max(x0, x1), max(y0, y1)
    if isinstance(s, Arc):
        return _arc_box(s)
    x, y = float(s.cx), float(s.cy)
    return x, y, x, y


def _arc_box(s) -> tuple:
    """The float box of a closed arc: its ends and the extreme points of its circle (centre ± ρ
    along the axes) in its range, an extreme point also taken when the float test of its direction
    is within 10⁻⁹ rad of the range's boundary (the box may be larger; it is smaller only when the
    rounding of the ends relative to ρ exceeds that angle, and then by ρ·(1 − cos δ) for a
    direction error δ: far below the :data:`WIDEN` margin of every disc it is tested against)."""
    (cx, cy), rho, (ax, ay), (bx, by) = s.float_data()
    xs, ys = [ax, bx], [ay, by]
    ua, ub = (ax - cx, ay - cy), (bx - cx, by - cy)
    tol = 1e-9 * rho * rho
    for ex, ey in ((1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)):
        v = (ex * rho, ey * rho)
        if _in_range(ua, ub, v, tol):
            xs.append(cx + v[0])
            ys.append(cy + v[1])
    return min(xs), min(ys), max(xs), max(ys)


def _in_range(ua, ub, v, tol) -> bool:
    """Float test: the direction v lies in the closed counter-clockwise range from ua to ub, or
    within ``tol`` (in cross-product units) of it."""
    ca = ua[0] * v[1] - ua[1] * v[0]
    cb = v[0] * ub[1] - v[1] * ub[0]
    if ua[0] * ub[1] - ua[1] * ub[0] >= 0:
        return ca >= -tol and cb >= -tol
    return ca >= -tol or cb >= -tol


def piece_ends(s):
    """The float ends (a, b) of a segment or point (a = b); an arc's start and end."""
    if isinstance(s, Arc):
        _, _, a, b = s.float_data()
        return np.array(a), np.array(b)
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


def site_distance(s, X):
    """Float distances from the rows of X to the closed site ``s`` (a point, a segment or a circular
    arc).  For an arc: | |x − c| − ρ | when the direction of x − c lies in its closed range (the
    centre itself: ρ), else the distance to the nearer end; near a boundary direction both are
    within rounding of each other (the distance is continuous there), so a float misclassification
    costs no more than the rounding."""
    if not isinstance(s, Arc):
        return piece_distance(*piece_ends(s), X)
    (cx, cy), rho, (ax, ay), (bx, by) = s.float_data()
    Vx, Vy = X[:, 0] - cx, X[:, 1] - cy
    uax, uay, ubx, uby = ax - cx, ay - cy, bx - cx, by - cy
    ca = uax * Vy - uay * Vx
    cb = Vx * uby - Vy * ubx
    inside = (ca >= 0) & (cb >= 0) if uax * uby - uay * ubx >= 0 else (ca >= 0) | (cb >= 0)
    radial = np.abs(np.hypot(Vx, Vy) - rho)
    ends = np.minimum(np.hypot(X[:, 0] - ax, X[:, 1] - ay), np.hypot(X[:, 0] - bx, X[:, 1] - by))
    return np.where(inside, radial, ends)


def distance_error(s, X) -> np.ndarray | float:
    """A bound on the float error of :func:`site_distance` beyond the margin's own scale (zero for
    points and segments, :data:`ARC_ERROR`·(|c| + ρ + |x|) for an arc)."""
    if not isinstance(s, Arc):
        return 0.0
    (cx, cy), rho, _, _ = s.float_data()
    return ARC_ERROR * (abs(cx) + abs(cy) + rho + np.abs(X).sum(axis=1))


def conflicts(s, XY, R):
    """The circles (centres XY, radii R) that the closed site ``s`` (point, segment or arc) enters
    or comes within the margin :data:`MARGIN` of (a boolean row per circle)."""
    if not len(R):
        return np.zeros(0, bool)
    margin = MARGIN * (1 + np.abs(XY).sum(axis=1) + R) + distance_error(s, XY)
    return site_distance(s, XY) < R + margin


def curve_ends(s) -> list:
    """The exact ends of a curve site (a segment's p and q, an arc's start and end), [] for a point."""
    if isinstance(s, Segment):
        return [(Fraction(s.p[0]), Fraction(s.p[1])), (Fraction(s.q[0]), Fraction(s.q[1]))]
    if isinstance(s, Arc):
        return [(Fraction(s.a[0]), Fraction(s.a[1])), (Fraction(s.b[0]), Fraction(s.b[1]))]
    return []


def leaving(s, e) -> tuple:
    """The exact direction in which the curve ``s`` leaves its end ``e`` (an arc runs
    counter-clockwise from its start: leaving the start along +perp(e − c), the end along −perp)."""
    p, q = curve_ends(s)
    if isinstance(s, Segment):
        o = q if e == p else p
        return (o[0] - e[0], o[1] - e[1])
    rx, ry = e[0] - Fraction(s.c[0]), e[1] - Fraction(s.c[1])
    return (-ry, rx) if e == p else (ry, -rx)


def opposite(u, v) -> bool:
    """The exact directions u and v are opposite (the two curves continue each other through the
    point: a straight merge or a smooth joint, :mod:`runtime.segments.elementary`)."""
    return u[0] * v[1] - u[1] * v[0] == 0 and u[0] * v[0] + u[1] * v[1] < 0


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


def _circle_boxes(XY, R) -> np.ndarray:
    """The rows (x − 2r, y − 2r, x + 2r, y + 2r) of circles (centres XY, radii R): what
    :meth:`EditIndex.circles_near` compares."""
    return np.column_stack([XY[:, 0] - 2 * R, XY[:, 1] - 2 * R, XY[:, 0] + 2 * R, XY[:, 1] + 2 * R]).reshape(-1, 4)


def _grown(A: np.ndarray, n: int, need: int, width: int | None = None) -> np.ndarray:
    """A buffer holding the first ``n`` rows of A and room for ``need`` rows (at least twice A's,
    so that appends cost O(1) amortised), ``width`` columns for a 2-d A (new ones padded with −1);
    A itself when it fits."""
    w = A.shape[1] if A.ndim == 2 else None
    if len(A) >= need and (w is None or width is None or width <= w):
        return A
    if w is not None and width is not None and width > w:
        B = np.full((max(need, 2 * len(A)), width), -1, A.dtype)
        B[:n, :w] = A[:n]
        return B
    B = np.empty((max(need, 2 * len(A)),) + A.shape[1:], A.dtype)
    B[:n] = A[:n]
    return B


class EditIndex:
    """The per-diagram arrays a local update reads, kept from one edit to the next so that an
    edit does not rebuild them from all sites: ``keys`` (exact site key -> index), ``boxes``
    (n, 4) float boxes; in ``D.vertices`` order ``XY``/``R`` the centres and radii, ``VS`` the
    site lists (padded with −1), ``VID`` the ids, ``CB`` the boxes (x − 2r, y − 2r, x + 2r, y + 2r) that
    :meth:`circles_near` compares; in ``D.edges`` order ``ES`` the site pairs and ``EE`` the end
    vertex ids (−1 at infinity); ``id_bound`` is above every vertex id (the size of the tables of
    :func:`listing` over ``EE`` and ``VID``).  :meth:`of` builds it (linear in N, once) or returns the
    diagram's own when it still fits.  The arrays are the first rows of buffers with room to
    grow: an edit moves a few rows (:meth:`replace_rows`, :meth:`move_sites`) and appends, it
    copies nothing of size N."""

    def __init__(self, keys, boxes, XY, R, VS, VID, ES, EE):
        self.keys = keys
        self._sites = np.asarray(boxes, float).reshape(-1, 4)
        XY, R = np.asarray(XY, float).reshape(-1, 2), np.asarray(R, float)
        self._rows = {"v": [XY, R, VS, VID, _circle_boxes(XY, R)], "e": [ES, EE]}
        self.ns, self.nv, self.ne = len(self._sites), len(R), len(ES)
        self.id_bound = int(max(np.max(VID, initial=-1), np.max(EE, initial=-1))) + 1
        self._views()

    def _views(self) -> None:
        self.boxes = self._sites[:self.ns]
        self.XY, self.R, self.VS, self.VID, self.CB = (A[:self.nv] for A in self._rows["v"])
        self.ES, self.EE = (A[:self.ne] for A in self._rows["e"])

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

    def copy(self) -> "EditIndex":
        """An index of its own (keys and arrays copied), for an edit that leaves its input alone."""
        return EditIndex(dict(self.keys), self.boxes.copy(), self.XY.copy(), self.R.copy(), self.VS.copy(),
                         self.VID.copy(), self.ES.copy(), self.EE.copy())

    def replace_rows(self, parts: list, kind: str, removed, new) -> None:
        """Delete the rows ``removed`` from ``parts`` (the diagram's list of vertices, ``kind``
        "v", or of edges, "e", aligned with the index's rows of that kind) and from those rows:
        in decreasing order each takes the current last row (a few row moves, not a shift of
        every later row); then append the parts ``new`` to both.  The order of the parts
        changes, list and rows stay aligned."""
        bufs = self._rows[kind]
        n = self.nv if kind == "v" else self.ne
        for r in sorted(set(int(t) for t in removed), reverse=True):
            n -= 1
            if r != n:
                parts[r] = parts[n]
                for A in bufs:
                    A[r] = A[n]
            parts.pop()
        if kind == "v":
            XY, R = np.array([[v.x, v.y] for v in new], float).reshape(-1, 2), np.array([v.radius for v in new], float)
            rows = [XY, R, vertex_sites(new, 1), np.array([v.id for v in new], dtype=np.int64), _circle_boxes(XY, R)]
        else:
            rows = list(edge_arrays(new))
        ids = rows[3] if kind == "v" else rows[1]              # new vertex ids, or the new edges' end ids
        if len(ids):
            self.id_bound = max(self.id_bound, int(ids.max()) + 1)
        k = len(new)
        for t, (A, X) in enumerate(zip(bufs, rows)):
            A = bufs[t] = _grown(A, n, n + k, X.shape[1] if X.ndim == 2 else None)
            if X.ndim == 2:
                A[n:n + k] = -1 if A.dtype.kind == "i" else 0
                A[n:n + k, :X.shape[1]] = X
            else:
                A[n:n + k] = X
        parts.extend(new)
        if kind == "v":
            self.nv = n + k
        else:
            self.ne = n + k
        self._views()

    def move_sites(self, moves: dict, m: int) -> None:
        """Site ``new`` takes the box of site ``old`` for each old -> new of ``moves``; the sites
        from ``m`` on are dropped (keys are the caller's)."""
        for old, new in moves.items():
            self._sites[new] = self._sites[old]
        self.ns = m
        self._views()

    def append_sites(self, boxes) -> None:
        """Append the boxes of new sites (keys are the caller's)."""
        B = np.asarray(boxes, float).reshape(-1, 4)
        self._sites = _grown(self._sites, self.ns, self.ns + len(B))
        self._sites[self.ns:self.ns + len(B)] = B
        self.ns += len(B)
        self._views()

    def box_rows(self, rows) -> np.ndarray:
        """The boxes of the sites ``rows``."""
        return self.boxes[rows]

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
        return np.nonzero(listing(self.VID[:, None], ids, self.id_bound))[0]

    def edges_at(self, ids) -> np.ndarray:
        """Rows of the edges with an end vertex among ``ids``."""
        return np.nonzero(listing(self.EE, ids, self.id_bound))[0]

    def circles_near(self, lo, hi, extra: float = 0.0) -> np.ndarray:
        """Rows of the vertices whose circle (centre, radius r) may come within the margin of
        :func:`conflicts` of a site in the box [lo, hi]: those whose centre is within
        2r + 10⁻⁶·(1 + B) + 2·``extra`` of the box in each coordinate (B: the box's largest
        coordinate; ``extra``: a bound on the sites' :func:`distance_error` at the box).  A centre
        x at distance d from the site is in conflict only if d < r + :data:`MARGIN`·(1 + |x| + r)
        + error, with |x|₁ ≤ 2(B + d): then d < 1.0000001·(r + 10⁻⁸·(1 + 2B) + extra), below the
        bound.  The test reads the stored circle boxes ``CB`` = (x − 2r, y − 2r, x + 2r, y + 2r): the
        centre is that close to [lo, hi] in x iff x − 2r ≤ hi + pad and x + 2r ≥ lo − pad (the same
        inequality; the rounding of x ± 2r, a few units in the last place of |x| + 2r, is far below
        the slack of 10⁻⁶ against the 10⁻⁸ of the margin).  One numpy pass of four comparisons; the
        distances are then taken on these rows only."""
        lo, hi = np.asarray(lo, float), np.asarray(hi, float)
        pad = 1e-6 * (1 + float(np.abs(np.concatenate([lo, hi])).max())) + 2 * extra
        C = self.CB
        return np.flatnonzero((C[:, 0] <= hi[0] + pad) & (C[:, 2] >= lo[0] - pad)
                              & (C[:, 1] <= hi[1] + pad) & (C[:, 3] >= lo[1] - pad))


class SitesWithNew:
    """The sites of an index with new ones appended, for the proof of an insertion before the
    index is edited: ``keys`` (a ChainMap of the new keys over the index's), :meth:`near` and
    :meth:`box_rows` over both (what :func:`prove_part` reads of an index)."""

    def __init__(self, index: EditIndex, new_keys: dict, new_boxes):
        self.index, self.keys = index, ChainMap(new_keys, index.keys)
        self.extra = np.asarray(new_boxes, float).reshape(-1, 4)
        self.n = len(index.boxes)

    def near(self, lo, hi) -> list[int]:
        b = self.extra
        new = np.nonzero((b[:, 0] <= hi[0]) & (b[:, 2] >= lo[0]) & (b[:, 1] <= hi[1]) & (b[:, 3] >= lo[1]))[0]
        return self.index.near(lo, hi) + (self.n + new).tolist()

    def box_rows(self, rows) -> np.ndarray:
        rows = np.asarray(rows, dtype=np.int64)
        old = rows < self.n
        out = np.empty((len(rows), 4))
        out[old] = self.index.boxes[rows[old]]
        out[~old] = self.extra[rows[~old] - self.n]
        return out


def listing(A, values, bound: int | None = None) -> np.ndarray:
    """The rows of the int array A (entries ≥ −1, −1 padding) with an entry among ``values``
    (non-negative ints), as a boolean row mask: one gather per column through a table of the
    values (the −1 entries and those above the largest value read its last, False, slot).
    ``bound``: every entry of A is below it (site numbers below the number of sites, vertex ids
    below :attr:`EditIndex.id_bound`); the table then covers all entries and the gather reads A's
    columns as they are (no clipped copy; an entry beyond the table raises IndexError)."""
    v = np.fromiter(values, np.int64)
    hit = np.zeros(len(A), bool)
    if not len(v) or not len(A):
        return hit
    if bound is None:
        tab = np.zeros(int(v.max()) + 2, bool)
        tab[v] = True
        for c in range(A.shape[1]):
            hit |= tab[np.minimum(A[:, c], len(tab) - 1)]
        return hit
    tab = np.zeros(max(int(bound), int(v.max()) + 1) + 1, bool)      # the last slot (read by −1) stays False
    tab[v] = True
    if A.ndim == 2 and A.shape[1] == 2 and A.flags.c_contiguous:       # a row's two flags as one 16-bit word
        return tab[A].view(np.uint16).ravel() != 0
    for c in range(A.shape[1]):
        hit |= tab[A[:, c]]
    return hit


def conflict_mask(index: EditIndex, pieces, near: list | None = None) -> np.ndarray:
    """The vertices of ``index`` (boolean row mask) whose circle one of ``pieces`` enters or comes
    within the margin of (:func:`conflicts`), the distances taken on the rows
    :meth:`EditIndex.circles_near` the pieces' box only (appended to ``near`` when given)."""
    B = np.array([site_box(q) for q in pieces], float).reshape(-1, 4)
    lo, hi = B[:, :2].min(axis=0), B[:, 2:].max(axis=0)
    corners = np.array([lo, hi, [lo[0], hi[1]], [hi[0], lo[1]]])
    extra = max(float(np.max(distance_error(q, corners))) for q in pieces)
    rows = index.circles_near(lo, hi, extra)
    if near is not None:
        near.append(rows)
    sub = np.zeros(len(rows), bool)
    for q in pieces:
        sub |= conflicts(q, index.XY[rows], index.R[rows])
    out = np.zeros(len(index.R), bool)
    out[rows[sub]] = True
    return out


class KeptVertices:
    """Finds the kept vertex (a vertex of D outside ``removed``, a boolean row mask) that a local
    diagram's vertex reproduces: the same sites in the same cyclic order (smallest first) and the
    same centre within 10⁻⁶·(1 + |x| + |y| + r).  :meth:`restrict` narrows the search, once, to
    the vertices in a box about the change (one numpy pass); a question inside it then reads those
    rows only."""

    def __init__(self, index: EditIndex, vertices, removed):
        self.index, self.vertices, self.removed = index, vertices, removed
        self.rows = self.box = None

    def restrict(self, lo, hi) -> None:
        """Search the vertices whose centre lies in the box [lo, hi] (one numpy pass) for the
        questions whose tolerance box lies inside it (a match is within the tolerance of the
        question in each coordinate); the others still search all vertices."""
        self.box = (np.asarray(lo, float), np.asarray(hi, float))
        self.rows = self.index.vertices_in(*self.box)

    def find(self, gs, x: float, y: float, r: float) -> int:
        """The id of the one matching kept vertex, or −1."""
        tol = 1e-6 * (1 + abs(x) + abs(y) + r)
        rows = None
        if self.rows is not None:
            (x0, y0), (x1, y1) = self.box
            if x0 < x - 2 * tol and x + 2 * tol < x1 and y0 < y - 2 * tol and y + 2 * tol < y1:
                rows = self.rows
        X = self.index.XY if rows is None else self.index.XY[rows]
        hit = np.flatnonzero(np.abs(X[:, 0] - x) + np.abs(X[:, 1] - y) < tol)
        near = (hit if rows is None else rows[hit]).tolist()
        hits = [self.vertices[t] for t in near if not self.removed[t] and tuple(self.vertices[t].sites) == gs]
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


def curves_ending_at(index: EditIndex, sites, p) -> list[int]:
    """The curve sites (numbering of ``sites``/``index``) that have the exact point ``p`` as an end."""
    x, y = float(p[0]), float(p[1])
    pad = 1e-9 * (1 + abs(x) + abs(y))
    return [k for k in index.near((x - pad, y - pad), (x + pad, y + pad)) if k < len(sites) and p in curve_ends(sites[k])]


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
        i, j = e.sites
        s = sites[j] if isinstance(sites[i], Arc) and not isinstance(sites[j], Arc) else sites[i]
        d = site_distance(s, P) + distance_error(s, P)
        t = float(e.tolerance)
        if len(P) == 1:
            out.append((P[0, 0], P[0, 1], d[0] + 2 * t))
            continue
        h = np.hypot(*np.diff(P, axis=0).T)
        M = np.maximum(d[:-1], d[1:])
        mid = (P[:-1] + P[1:]) / 2
        # convex d_s (a point, a segment): d_s <= M along the step; an arc's distance is only
        # 1-Lipschitz: d_s <= M + h/2 there
        step = h if isinstance(s, Arc) else h / 2
        out.extend(zip(mid[:, 0], mid[:, 1], M + step + 2 * t))
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
    B = index.box_rows(cand)
    dx = np.maximum(np.maximum(B[:, None, 0] - D[None, :, 0], D[None, :, 0] - B[:, None, 2]), 0.0)
    dy = np.maximum(np.maximum(B[:, None, 1] - D[None, :, 1], D[None, :, 1] - B[:, None, 3]), 0.0)
    hit = (dx * dx + dy * dy <= (D[None, :, 2]) ** 2).any(axis=1)
    return set(cand[hit].tolist())


def prove_part(sites, index: EditIndex, vertices, edges, problems: list, exclude=frozenset()) -> bool:
    """Prove ``vertices`` (changed vertices and the kept ends of changed edges) and ``edges``
    against the sites that can reach them (module docstring); sites, vertices and edges are in the
    global numbering of ``sites``/``index``.  ``exclude``: numbers of sites that are not sites of
    the edited diagram (a deletion proves in the old numbering, without the deleted sites).  True
    when every part is proved."""
    if not vertices and not edges:
        return True
    chosen = sites_meeting(index, reach_discs(vertices, edges, sites)) - exclude
    chosen |= {s for v in vertices for s in v.sites} | {s for e in edges for s in e.sites}
    if not chosen.isdisjoint(exclude):
        problems.append("a changed part lists a deleted site")
        return False
    for k in list(chosen):
        for p in curve_ends(sites[k]):
            t = index.keys.get(point_key(p))
            if t in exclude:                       # cannot happen: a deleted point is no remaining curve's end
                problems.append(f"site {k} ends at the deleted point site {t}")
                return False
            if t is not None:
                chosen.add(t)
            else:                                  # a smooth joint: the curve continuing there
                chosen.update(u for u in curves_ending_at(index, sites, p) if u not in exclude)
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


# ====================================================================== steps both updates take
def with_joint_partners(hood: set, index: EditIndex, sites) -> set:
    """``hood`` (site numbers) with, for each curve in it ending at a smooth joint (an end that is no
    point site), the curves continuing there: a curve of the neighbourhood keeps its partner, so that
    the local diagram's elementary sites are the diagram's (without the partner, the joint would be
    a curve end and a point site of its own, :mod:`runtime.segments.elementary`, which no site of
    the diagram matches)."""
    for k in list(hood):
        for p in curve_ends(sites[k]):
            if point_key(p) not in index.keys:
                hood.update(curves_ending_at(index, sites, p))
    return hood


def local_diagram(build, sites):
    """The diagram of ``sites`` by ``build`` (the construction that built the edited diagram,
    uncertified), or a str: why it failed.  Its problems (e.g. a construction fault far from the
    changed part, at the edge of the neighbourhood) are not read: what is taken from it is proved,
    and the closure checks that nothing of the changed part is missing."""
    try:
        return build(sites, certify=False)
    except (SiteError, ValueError) as exc:
        return f"the local diagram failed ({exc})"


def smallest_first(gs: tuple) -> tuple:
    """The cyclic sequence of a vertex's sites ``gs`` turned to start at its smallest number (the
    order kept: the diagram's convention, which the closure test and the matching compare)."""
    r = min(range(len(gs)), key=lambda t: gs[t])
    return gs[r:] + gs[:r]


class Splice:
    """What an update takes from its local diagram L into the edited diagram: the vertices
    (``vertices``, fresh ids from ``next_v``) and edges (``edges``, fresh ids from ``next_e``),
    uncertified until the changed part is proved; ``lmap`` maps L's vertex ids to the edited
    diagram's (a taken vertex's fresh id, a matched kept vertex's id, −1 when it matches none);
    L's vertices that are not taken wait in ``pending`` until an edge needs them matched to kept
    vertices (:class:`KeptVertices`)."""

    def __init__(self, kept: KeptVertices, next_v: int, next_e: int):
        self.kept, self.next_v, self.next_e = kept, next_v, next_e
        self.lmap: dict = {}
        self.pending: dict = {}
        self.vertices: list = []
        self.edges: list = []
        self.taken_ids: set = set()

    def take_vertices(self, L, glob, chosen) -> None:
        """Take the vertices of L for which ``chosen(t, lv, gs)`` holds (t: its row, gs: its sites in
        the global numbering ``glob``, smallest first); the others wait in ``pending``."""
        for t, lv in enumerate(L.vertices):
            gs = smallest_first(tuple(glob[s] for s in lv.sites))
            if chosen(t, lv, gs):
                self.lmap[lv.id] = self.next_v
                self.vertices.append(DiagramVertex(self.next_v, gs, lv.x, lv.y, lv.radius, False))
                self.next_v += 1
                continue
            self.pending[lv.id] = (gs, lv.x, lv.y, lv.radius)
        self.taken_ids = {v.id for v in self.vertices}
        B = np.array([site_box(s) for s in L.sites], float).reshape(-1, 4)
        if len(B):                  # the local sites' box: the ends of taken edges lie inside it
            self.kept.restrict(B[:, :2].min(axis=0), B[:, 2:].max(axis=0))

    def at_taken(self, le) -> bool:
        """The local edge ``le`` has an end at a taken vertex."""
        return any(self.lmap.get(u) in self.taken_ids for u in le.ends)

    def ends_of(self, le) -> list:
        """The ends of the local edge ``le`` in the edited diagram (None: at infinity), its ends that
        are not taken matched to kept vertices now."""
        for u in le.ends:
            if u is not None and u not in self.lmap:
                self.lmap[u] = self.kept.find(*self.pending[u]) if u in self.pending else -1
        return [None if u is None else self.lmap[u] for u in le.ends]

    def take_edge(self, le, gp, ends) -> str | None:
        """Take the local edge ``le`` of the global pair ``gp`` between ``ends``
        (:func:`spliced_edge`); a reason when it cannot be spliced."""
        edge = spliced_edge(le, gp, ends, self.next_e)
        if isinstance(edge, str):
            return edge
        self.edges.append(edge)
        self.next_e += 1
        return None


def changed_part_holds(sites, index: EditIndex, vid: dict, splice: Splice, ends_needed, check_ids, near_edges,
                       exclude=frozenset()) -> str | None:
    """None when the changed part is proved and closed, else why not: the taken vertices and edges
    and the kept ends of taken edges proved against every site that can reach them but ``exclude``
    (:func:`prove_part`), then the closure (:func:`closure_holds`) at the vertices ``check_ids``
    (ids; ``vid``: id -> vertex of the edited diagram) among their edges ``near_edges(check_ids)``
    of the kept part and the taken edges."""
    problems: list = []
    if not prove_part(sites, index, splice.vertices + [vid[u] for u in ends_needed], splice.edges, problems, exclude):
        return f"the changed part is not proved ({problems[0] if problems else 'a part failed'})"
    if any(u not in vid for u in check_ids):
        return "the closure at the changed vertices fails (a vertex is missing)"
    if not closure_holds(near_edges(check_ids) + splice.edges, [vid[u] for u in sorted(check_ids)]):
        return "the closure at the changed vertices fails"
    return None


def local_result(D, sites, vertices, edges, splice: Splice, index: EditIndex, removed: int, hood: int, secs: dict):
    """The edited diagram, certified (the changed part proved and closed, the kept part by the
    update's argument): the taken parts marked certified, D's stats with the update's (the next
    fresh ids, the counts of the change, the seconds of each step), and its ``edit_index``."""
    for v in splice.vertices:
        v.certified = True
    for e in splice.edges:
        e.certified = True
    out = Diagram(sites, vertices, edges, True, [], dict(D.stats))
    out.stats["update"] = "local"
    out.stats["next vertex id"], out.stats["next edge id"] = splice.next_v, splice.next_e
    out.stats["changed"] = {"removed vertices": removed, "new vertices": len(splice.vertices),
                            "new edges": len(splice.edges), "neighbourhood sites": hood}
    out.stats["seconds"] = {k: round(t, 4) for k, t in secs.items()}
    out.edit_index = index
    return out
