"""The sites of a point/segment diagram as the certificate reads them: exact table, admissibility,
and the unbounded ends every diagram of these sites has (steps 1 and 5 of
:mod:`runtime.segments.certificate`).

**Admissible sites** (exact): every site is a :class:`runtime.predicates.circles.Point` or a
:class:`runtime.sites.segment.Segment` (its open interior); no point or segment is repeated; both
endpoints of every segment are point sites of the list; segments meet only at common endpoints
and no point lies in a segment's interior (:func:`runtime.segments.crossings.check_pieces`,
exact Fraction orientations); two segments meeting at 180° at a point of degree 2 are merged
(the elementary decomposition of :mod:`runtime.segments.elementary`), and no junction of three or
more segments continues straight through (there a whole ray is equidistant from three sites).

**Unbounded ends** (:func:`expected_infinite_ends`, exact rational hull of the point sites —
every site lies in it, a segment's endpoints being point sites): far away in a direction u the
nearest sites are those with the largest support h(u) = max over the site of u·p; it is a single
point site for u inside the normal cone of a hull vertex (a segment ending there ties with it,
but its foot is clamped to that endpoint, which by convention owns the tie), and for u the outward
normal of a hull side it is every site on that side's line.  Those sites, sorted along the line
(points and the interiors of segments lying on it between their endpoints), cut the far region
into slabs perpendicular to the line, so each consecutive pair has exactly one edge going to
infinity in direction u (a perpendicular bisector, or the perpendicular to a segment at its
endpoint), and there are no others.  All sites on one line: the two normals.

Public API: :class:`SiteTable`, :func:`admissibility`, :func:`expected_infinite_ends`,
:func:`direction_key`.
"""
from __future__ import annotations

from fractions import Fraction

import numpy as np
from flint import arb
from scipy.spatial import cKDTree

from ..certify.foot import to_arb
from ..predicates.circles import Point
from ..sites.segment import Segment
from ..voronoi.verify.problems import Problem, fault

__all__ = ["SiteTable", "admissibility", "expected_infinite_ends", "direction_key", "POINT", "SEGMENT", "sq",
           "hypot"]

POINT, SEGMENT = 0, 1


def sq(x: arb) -> arb:
    """x² as a non-negative ball (arb's ``x ** 2`` is NaN, and x·x has a negative lower end, for a
    ball around 0)."""
    return (x * x).nonnegative_part()


def hypot(dx: arb, dy: arb) -> arb:
    """√(dx² + dy²), also for balls around 0."""
    return (sq(dx) + sq(dy)).nonnegative_part().sqrt()


def _frac(v) -> Fraction:
    if isinstance(v, Fraction):
        return v
    if hasattr(v, "p") and hasattr(v, "q"):          # flint fmpq
        return Fraction(int(v.p), int(v.q))
    return Fraction(v)


class SiteTable:
    """Exact and float views of the elementary sites.

    ``kind[k]``: POINT / SEGMENT (None for an unsupported site); ``a[k]``, ``b[k]``: exact endpoint
    pairs (a = b for a point); ``ends[k]``: the point-site indices of a segment's endpoints (None
    when an endpoint is not a point site); ``incident[p]``: segments ending at point site p;
    ``A``, ``B``: float endpoints; a k-d tree over the midpoints with the largest half-length
    ``hmax`` (d(q, S) ≥ |q − mid(S)| − half(S))."""

    def __init__(self, sites):
        self.sites = list(sites)
        n = len(self.sites)
        self.n = n
        self.kind: list = []
        self.a: list = []
        self.b: list = []
        self.unsupported: list[int] = []
        for k, s in enumerate(self.sites):
            if isinstance(s, Segment):
                self.kind.append(SEGMENT)
                self.a.append(tuple(map(_frac, s.p)))
                self.b.append(tuple(map(_frac, s.q)))
            elif isinstance(s, Point):
                self.kind.append(POINT)
                p = (_frac(s.x), _frac(s.y))
                self.a.append(p)
                self.b.append(p)
            else:
                self.kind.append(None)
                self.unsupported.append(k)
                self.a.append((Fraction(0), Fraction(0)))
                self.b.append((Fraction(0), Fraction(0)))
        self.point_index: dict = {}
        self.repeated_points: list = []
        for k in range(n):
            if self.kind[k] == POINT:
                if self.a[k] in self.point_index:
                    self.repeated_points.append((self.point_index[self.a[k]], k))
                else:
                    self.point_index[self.a[k]] = k
        self.ends: list = [None] * n
        self.incident: dict = {k: [] for k in range(n) if self.kind[k] == POINT}
        self.segment_of: dict = {}
        for k in range(n):
            if self.kind[k] == SEGMENT:
                ia, ib = self.point_index.get(self.a[k]), self.point_index.get(self.b[k])
                if ia is not None and ib is not None:
                    self.ends[k] = (ia, ib)
                    self.incident[ia].append(k)
                    self.incident[ib].append(k)
                    self.segment_of.setdefault(frozenset((ia, ib)), k)
        self.A = np.array([[float(p[0]), float(p[1])] for p in self.a], dtype=float).reshape(-1, 2)
        self.B = np.array([[float(p[0]), float(p[1])] for p in self.b], dtype=float).reshape(-1, 2)
        self.mid = (self.A + self.B) / 2
        self.half = np.hypot(*(self.B - self.A).T) / 2 if n else np.zeros(0)
        self.hmax = float(self.half.max()) if n else 0.0
        self.scale = 1.0 + (float(np.max(np.abs(np.concatenate([self.A, self.B])))) if n else 0.0)
        self.tree = cKDTree(self.mid) if n else None
        self._arb: dict = {}

    def is_point(self, k: int) -> bool:
        return self.kind[k] == POINT

    def is_endpoint(self, p: int, s: int) -> bool:
        """Point site p is an endpoint of segment site s."""
        return self.kind[s] == SEGMENT and self.ends[s] is not None and p in self.ends[s]

    def end_index(self, s: int, p: int) -> int:
        """0 when point site p is the endpoint a of segment s, 1 when it is b."""
        return 0 if self.ends[s][0] == p else 1

    def arb_ends(self, k: int):
        """(ax, ay, bx, by) as arb balls (cached; the working precision is the certificate's)."""
        v = self._arb.get(k)
        if v is None:
            v = tuple(to_arb(c) for c in self.a[k] + self.b[k])
            self._arb[k] = v
        return v

    def near(self, x: float, y: float, radius: float) -> list[int]:
        """Every site whose distance from (x, y) may be ≤ ``radius`` (a superset: the k-d tree
        query is widened by the largest half-length and a rounding margin)."""
        if self.tree is None or not np.isfinite(radius) or not (np.isfinite(x) and np.isfinite(y)):
            return list(range(self.n))
        r = radius + self.hmax + 1e-9 * (self.scale + abs(x) + abs(y) + radius)
        return self.tree.query_ball_point([x, y], r)

    def distance(self, k: int, X: arb, Y: arb) -> arb:
        """A ball holding the distance from every point of the box (X, Y) to the closed site k
        (the closed segment for a segment site)."""
        ax, ay, bx, by = self.arb_ends(k)
        if self.kind[k] == POINT:
            return hypot(X - ax, Y - ay)
        dx, dy = bx - ax, by - ay
        L2 = dx * dx + dy * dy
        t = ((X - ax) * dx + (Y - ay) * dy) / L2
        if t > 0 and t < 1:
            return abs((X - ax) * dy - (Y - ay) * dx) / L2.sqrt()
        if t <= 0:
            return hypot(X - ax, Y - ay)
        if t >= 1:
            return hypot(X - bx, Y - by)
        # the foot straddles an end: between the line's distance and the nearer end's
        line = abs((X - ax) * dy - (Y - ay) * dx) / L2.sqrt()
        end = hypot(X - ax, Y - ay) if t.mid() < 0.5 else hypot(X - bx, Y - by)
        return line.lower().union(end.upper())

    def foot(self, k: int, X: arb, Y: arb) -> arb:
        """The foot parameter of (X, Y) on the line of segment k."""
        ax, ay, bx, by = self.arb_ends(k)
        dx, dy = bx - ax, by - ay
        return ((X - ax) * dx + (Y - ay) * dy) / (dx * dx + dy * dy)


def admissibility(T: SiteTable) -> list:
    """Problems that make the sites inadmissible (module docstring); empty when admissible."""
    out = []
    for k in T.unsupported:
        out.append(Problem(f"site {k}: {type(T.sites[k]).__name__} is not a point or a segment: this certificate "
                           "proves diagrams of points and segments only", kind="site", sites=(k,), fault=False))
    for p, q in T.repeated_points:
        out.append(fault(f"sites {p} and {q}: the same point repeated", kind="site", sites=(p, q)))
    seen: dict = {}
    for k in range(T.n):
        if T.kind[k] != SEGMENT:
            continue
        for end in (T.a[k], T.b[k]):
            if end not in T.point_index:
                out.append(fault(f"site {k}: the endpoint ({end[0]}, {end[1]}) of the segment is not a point "
                                 "site of the diagram (every endpoint is its own site)", kind="site", sites=(k,)))
        key = frozenset((T.a[k], T.b[k]))
        if key in seen:
            out.append(fault(f"sites {seen[key]} and {k}: the same segment repeated", kind="site",
                             sites=(seen[key], k)))
        seen.setdefault(key, k)
    if out:
        return out
    try:
        from .crossings import check_pieces
        from ..voronoi.site_input import SiteError
    except ImportError:                       # pragma: no cover - ships with the package
        return [Problem("sites: the crossing check (runtime.segments.crossings) is not available", kind="site", fault=False)]
    try:
        check_pieces([s for s in T.sites])
    except SiteError as exc:
        return [fault(f"sites not admissible: {exc}", kind="site")]
    for p, segs in T.incident.items():
        dirs = [_out_dir(T, s, p) for s in segs]
        for x in range(len(dirs)):
            for y in range(x + 1, len(dirs)):
                (ux, uy), (vx, vy) = dirs[x], dirs[y]
                if ux * vy - uy * vx == 0 and ux * vx + uy * vy < 0:
                    what = ("two segments meeting at 180 degrees at a point of degree 2 are one elementary "
                            "site (merge them)") if len(segs) == 2 else \
                        "a junction of three or more segments continues straight through (a ray equidistant from three sites)"
                    out.append(fault(f"point site {p}: segments {segs[x]} and {segs[y]}: {what}", kind="site",
                                     sites=(p, segs[x], segs[y])))
    return out


def _out_dir(T: SiteTable, s: int, p: int):
    """The direction of segment s leaving its endpoint p (exact)."""
    o = T.b[s] if T.ends[s][0] == p else T.a[s]
    return (o[0] - T.a[p][0], o[1] - T.a[p][1])


def direction_key(v) -> tuple:
    """A rational direction up to positive scaling, as an exact hashable key."""
    x, y = Fraction(v[0]), Fraction(v[1])
    m = max(abs(x), abs(y))
    return (x / m, y / m) if m else (Fraction(0), Fraction(0))


def _cross(o, a, b) -> Fraction:
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])


def _hull(pts: list) -> list:
    """Strict convex hull (no collinear points), counter-clockwise, exact (Andrew's monotone chain)."""
    pts = sorted(set(pts))
    if len(pts) <= 2:
        return pts
    lower: list = []
    for p in pts:
        while len(lower) >= 2 and _cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    upper: list = []
    for p in reversed(pts):
        while len(upper) >= 2 and _cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    return lower[:-1] + upper[:-1]


def expected_infinite_ends(T: SiteTable) -> list[tuple[tuple[int, int], tuple]]:
    """The (sorted site pair, direction key) of every unbounded end of the true diagram (module
    docstring), with multiplicity."""
    pts = list(T.point_index)
    if len(pts) < 2:
        return []
    hull = _hull(pts)
    if len(hull) == 2:                       # all sites on one line: both sides
        p, q = hull
        d = (q[0] - p[0], q[1] - p[1])
        sides = [(p, q, (d[1], -d[0])), (p, q, (-d[1], d[0]))]
    else:
        sides = []
        for m in range(len(hull)):
            p, q = hull[m], hull[(m + 1) % len(hull)]
            sides.append((p, q, (q[1] - p[1], -(q[0] - p[0]))))
    P = np.array([[float(x), float(y)] for x, y in pts])
    keys = list(T.point_index.values())
    out = []
    for p, q, u in sides:
        d = (q[0] - p[0], q[1] - p[1])
        # float filter: points clearly off the side's line are skipped; the rest decided exactly
        fd = np.array([float(d[0]), float(d[1])])
        cr = (P[:, 0] - float(p[0])) * fd[1] - (P[:, 1] - float(p[1])) * fd[0]
        mag = (np.abs(P).max(axis=1) + abs(float(p[0])) + abs(float(p[1])) + 1.0) * (np.abs(fd).max() + 1.0)
        cand = np.nonzero(np.abs(cr) <= 1e-9 * mag)[0]
        on = []
        for c in cand:
            x = pts[c]
            if _cross(p, q, x) == 0:
                s = (x[0] - p[0]) * d[0] + (x[1] - p[1]) * d[1]
                on.append((s, keys[c]))
        on.sort()
        key = direction_key(u)
        for (_, k0), (_, k1) in zip(on, on[1:]):
            seg = T.segment_of.get(frozenset((k0, k1)))
            if seg is None:
                out.append((tuple(sorted((k0, k1))), key))
            else:
                out.append((tuple(sorted((k0, seg))), key))
                out.append((tuple(sorted((seg, k1))), key))
    return out
