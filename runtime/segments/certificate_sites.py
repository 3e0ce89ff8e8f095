"""The sites of a point/segment/arc diagram as the certificate reads them: the exact table with its
float and ball views (admissibility is :mod:`runtime.segments.certificate_admissible`, the
unbounded ends :mod:`runtime.segments.certificate_hull`).

Curve ends are *end codes*: a point site's index, or −2 − m for the m-th smooth joint (a point
that is no site where exactly two curves, not both segments, end leaving it in opposite
directions).  An arc runs counter-clockwise from its start a to its end b; the direction
w from its centre is in its open range when a → w → b counter-clockwise (cross products, exact
for rationals, decided or not for balls).  The distance to an arc is | |x − c| − ρ | when the
direction of x − c is in its closed range, else the nearer end's; its nearest point is an end e
alone exactly when the direction lies strictly in the half of its gap next to e (two half-planes
through the centre: from the gap's middle to e), or on e's boundary direction.

Public API: :class:`SiteTable`, :func:`direction_key`, :data:`POINT`, :data:`SEGMENT`,
:data:`ARC`, :func:`sq`, :func:`hypot`.

Length: one table (the exact sites, their float and ball views and the cached arc ranges, ends
and end directions that every proof of the certificate reads); splitting it would pass the same
caches between modules.
"""
from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
from flint import arb
from scipy.spatial import cKDTree

from ..certify.foot import to_arb
from ..predicates.circles import Point
from ..sites.arc import Arc
from ..sites.elliptic_arc import EllipticArc
from ..sites.kinds import SiteKind
from ..sites.segment import Segment
from ..sites.rationals import to_fraction
from .certificate_ellipses import bounding_disc, float_bounds as ellipse_float_bounds, is_piece
from .certificate_ellipses import owned_by_end as ellipse_owned_by_end
from .distance import distances, float_error
from .ellipse_pieces import PieceData, piece_distance_ball

__all__ = ["SiteTable", "direction_key", "POINT", "SEGMENT", "ARC", "ELLIPSE", "sq", "hypot"]

# plain ints (an enum member in a numpy comparison costs a failed metaclass lookup per call)
POINT, SEGMENT, ARC, ELLIPSE = (int(k) for k in (SiteKind.POINT, SiteKind.SEGMENT, SiteKind.ARC, SiteKind.ELLIPTIC_ARC))
EPS = np.finfo(float).eps


def sq(x: arb) -> arb:
    """x² as a non-negative ball (arb's ``x ** 2`` is NaN, and x·x has a negative lower end, for a
    ball around 0)."""
    return (x * x).nonnegative_part()


def hypot(dx: arb, dy: arb) -> arb:
    """√(dx² + dy²), also for balls around 0."""
    return (sq(dx) + sq(dy)).nonnegative_part().sqrt()


def _cross(u, v):
    return u[0] * v[1] - u[1] * v[0]


def _opposite(u, v) -> bool:
    return _cross(u, v) == 0 and u[0] * v[0] + u[1] * v[1] < 0


def direction_key(v) -> tuple:
    """A rational direction up to positive scaling, as an exact hashable key."""
    x, y = Fraction(v[0]), Fraction(v[1])
    m = max(abs(x), abs(y))
    return (x / m, y / m) if m else (Fraction(0), Fraction(0))


class SiteTable:
    """Exact and float views of the elementary sites.

    ``kind[k]``: POINT / SEGMENT / ARC / ELLIPSE (an elliptic piece, ``piece[k]`` its
    :class:`runtime.segments.ellipse_pieces.PieceData`; None for an unsupported site); ``a[k]``, ``b[k]``: exact
    ends (a = b for a point; an arc runs counter-clockwise from a to b); ``cen[k]``, ``rad[k]``:
    an arc's centre and radius; ``ends[k]``: the *end codes* of a curve — a point-site index, or
    −2 − m for the smooth joint ``joints[m]`` = (point, (curve, curve)) — None when an end is
    neither; ``incident[p]``: curves ending at point site p; ``A``, ``B``, ``C``, ``R``: float
    ends, centres and radii; a k-d tree over bounding discs (a chord's disc for an arc of at most
    180°, the circle's disc otherwise) with the largest radius ``hmax``."""

    def __init__(self, sites):
        self.sites = list(sites)
        n = self.n = len(self.sites)
        #: exact conditions derived from the sites alone (certificate_rules.linear_rule), by key
        self.rule_cache: dict = {}
        self.kind: list = []
        self.a: list = []
        self.b: list = []
        self.cen: dict = {}
        self.rad: dict = {}
        self.unsupported: list[int] = []
        #: elliptic pieces (:mod:`runtime.segments.certificate_ellipses`) by index
        self.piece: dict = {}
        zero = (Fraction(0), Fraction(0))
        for k, s in enumerate(self.sites):
            if isinstance(s, Arc):
                self.kind.append(ARC)
                self.a.append(tuple(map(to_fraction, s.a)))
                self.b.append(tuple(map(to_fraction, s.b)))
                self.cen[k] = tuple(map(to_fraction, s.c))
                self.rad[k] = to_fraction(s.rho)
            elif isinstance(s, EllipticArc) and is_piece(s):
                self.kind.append(ELLIPSE)
                self.a.append(tuple(map(to_fraction, s.a)))
                self.b.append(tuple(map(to_fraction, s.b)))
                self.piece[k] = PieceData.of(s)
            elif isinstance(s, Segment):
                self.kind.append(SEGMENT)
                self.a.append(tuple(map(to_fraction, s.p)))
                self.b.append(tuple(map(to_fraction, s.q)))
            elif isinstance(s, Point):
                self.kind.append(POINT)
                p = (to_fraction(s.x), to_fraction(s.y))
                self.a.append(p)
                self.b.append(p)
            else:
                self.kind.append(None)
                self.unsupported.append(k)
                self.a.append(zero)
                self.b.append(zero)
        self.has_arcs = bool(self.cen)
        self.point_index: dict = {}
        self.repeated_points: list = []
        for k in range(n):
            if self.kind[k] == POINT:
                if self.a[k] in self.point_index:
                    self.repeated_points.append((self.point_index[self.a[k]], k))
                else:
                    self.point_index[self.a[k]] = k
        self._ends_and_joints()
        self._floats()
        self._arb: dict = {}

    # ------------------------------------------------------------------ ends, joints
    def is_curve(self, k: int) -> bool:
        return self.kind[k] in (SEGMENT, ARC, ELLIPSE)

    def _ends_and_joints(self):
        n = self.n
        self.ends: list = [None] * n
        self.incident: dict = {k: [] for k in range(n) if self.kind[k] == POINT}
        self.segment_of: dict = {}
        self.joints: list = []
        self.bad_ends: list = []
        loose: dict = {}
        for k in range(n):
            if self.is_curve(k):
                for which, p in enumerate((self.a[k], self.b[k])):
                    if p not in self.point_index:
                        loose.setdefault(p, []).append((k, which))
        code_of: dict = {}
        for p, lst in loose.items():
            if len(lst) == 2 and lst[0][0] != lst[1][0]:
                (k1, w1), (k2, w2) = lst
                both_segments = self.kind[k1] == SEGMENT and self.kind[k2] == SEGMENT
                if not both_segments and _opposite(self._tangent(k1, w1), self._tangent(k2, w2)):
                    code = -2 - len(self.joints)
                    self.joints.append((p, (k1, k2)))
                    code_of[(k1, w1)] = code_of[(k2, w2)] = code
                    continue
            for k, which in lst:
                self.bad_ends.append((k, p))
        for k in range(n):
            if not self.is_curve(k):
                continue
            codes = []
            for which, p in enumerate((self.a[k], self.b[k])):
                codes.append(self.point_index[p] if p in self.point_index else code_of.get((k, which)))
            if None in codes:
                continue
            self.ends[k] = tuple(codes)
            for c in codes:
                if c >= 0:
                    self.incident[c].append(k)
            if self.kind[k] == SEGMENT and min(codes) >= 0:
                self.segment_of.setdefault(frozenset(codes), k)

    def _tangent(self, k: int, which: int):
        """The exact direction in which curve k leaves its start (which = 0) or end (1)."""
        if self.kind[k] == SEGMENT:
            (ax, ay), (bx, by) = self.a[k], self.b[k]
            return (bx - ax, by - ay) if which == 0 else (ax - bx, ay - by)
        if self.kind[k] == ELLIPSE:
            s = self.sites[k]
            t = s.tangent(s.ua if which == 0 else s.ub)
            return t if which == 0 else (-t[0], -t[1])
        (cx, cy), (px, py) = self.cen[k], (self.a[k] if which == 0 else self.b[k])
        rx, ry = px - cx, py - cy
        return (-ry, rx) if which == 0 else (ry, -rx)

    def which_end(self, s: int, code: int) -> int:
        """0 when the end code is curve s's start, 1 when it is its end."""
        return 0 if self.ends[s][0] == code else 1

    def leaving(self, s: int, code: int):
        """The exact direction in which curve s leaves its end ``code``."""
        return self._tangent(s, self.which_end(s, code))

    def curvature(self, s: int, code: int) -> Fraction:
        """The signed curvature of curve s leaving its end ``code`` (left turn > 0); not defined
        (ValueError) for an elliptic piece (irrational in general)."""
        if self.kind[s] == ELLIPSE:
            raise ValueError(f"curve {s}: the curvature of an elliptic piece is not exact")
        if self.kind[s] != ARC:
            return Fraction(0)
        return (1 if self.which_end(s, code) == 0 else -1) / self.rad[s]

    def pt(self, code: int):
        """Exact coordinates of a point site (code ≥ 0) or a smooth joint (code ≤ −2)."""
        return self.a[code] if code >= 0 else self.joints[-2 - code][0]

    def pt_arb(self, code: int):
        return self._cached(("pt", code), lambda: tuple(to_arb(c) for c in self.pt(code)))

    def joint_curves(self, code: int):
        return self.joints[-2 - code][1]

    def shared_joint(self, i: int, j: int):
        """The smooth joint codes curves i and j share (a list, usually of one)."""
        if not (self.is_curve(i) and self.is_curve(j)) or self.ends[i] is None or self.ends[j] is None:
            return []
        return [c for c in set(self.ends[i]) & set(self.ends[j]) if c <= -2]

    def is_point(self, k: int) -> bool:
        return self.kind[k] == POINT

    def is_endpoint(self, p: int, s: int) -> bool:
        """Point site p is an end of curve s."""
        return p >= 0 and self.is_curve(s) and self.ends[s] is not None and p in self.ends[s]

    def end_index(self, s: int, p: int) -> int:
        """0 when the end code p is the start a of curve s, 1 when it is b."""
        return 0 if self.ends[s][0] == p else 1

    # ------------------------------------------------------------------ arcs
    def _cached(self, key, make):
        v = self._arb.get(key)
        if v is None:
            v = self._arb[key] = make()
        return v

    def arc_mid(self, k: int):
        """An exact direction of the angular middle of arc k (not normalised; cached)."""
        return self._cached(("mid", k), lambda: self._arc_mid(k))

    def arc_mid_arb(self, k: int):
        """:meth:`arc_mid` as balls (cached)."""
        return self._cached(("mid_arb", k), lambda: tuple(to_arb(c) for c in self.arc_mid(k)))

    def _arc_mid(self, k: int):
        (cx, cy) = self.cen[k]
        ua = (self.a[k][0] - cx, self.a[k][1] - cy)
        ub = (self.b[k][0] - cx, self.b[k][1] - cy)
        cr = _cross(ua, ub)
        if cr == 0:
            return (-ua[1], ua[0])
        s = 1 if cr > 0 else -1
        return (s * (ua[0] + ub[0]), s * (ua[1] + ub[1]))

    def _range_data(self, k: int):
        """(a − c, b − c, their cross product, and the first two as balls) of arc k, cached."""
        def make():
            (cx, cy) = self.cen[k]
            ua = (self.a[k][0] - cx, self.a[k][1] - cy)
            ub = (self.b[k][0] - cx, self.b[k][1] - cy)
            return ua, ub, _cross(ua, ub), (to_arb(ua[0]), to_arb(ua[1])), (to_arb(ub[0]), to_arb(ub[1]))
        return self._cached(("range", k), make)

    def in_range(self, k: int, wx, wy, closed: bool = False):
        """The direction (wx, wy) from arc k's centre lies in its open (or closed) angular range:
        True / False, or None when balls do not decide.  Exact for rationals."""
        ua, ub, ab, ua_b, ub_b = self._range_data(k)
        if isinstance(wx, arb) or isinstance(wy, arb):
            ua, ub = ua_b, ub_b
        ca = ua[0] * wy - ua[1] * wx
        cb = wx * ub[1] - wy * ub[0]

        def pos(v):
            if closed:
                return True if v >= 0 else (False if v < 0 else None)
            return True if v > 0 else (False if v <= 0 else None)

        pa, pb = pos(ca), pos(cb)
        if ab == 0:
            return pa
        if ab > 0:
            if pa is False or pb is False:
                return False
            return True if (pa and pb) else None
        if pa or pb:
            return True
        if pa is False and pb is False:
            return False
        return None

    def arb_arc(self, k: int):
        key = ("arc", k)
        v = self._arb.get(key)
        if v is None:
            v = tuple(to_arb(c) for c in self.cen[k]) + (to_arb(self.rad[k]),)
            self._arb[key] = v
        return v

    # ------------------------------------------------------------------ floats
    def _floats(self):
        n = self.n
        self.A = np.array([[float(p[0]), float(p[1])] for p in self.a], dtype=float).reshape(-1, 2)
        self.B = np.array([[float(p[0]), float(p[1])] for p in self.b], dtype=float).reshape(-1, 2)
        self.C = np.full((n, 2), np.nan)
        self.R = np.full(n, np.nan)
        self.karr = np.array([-1 if k is None else k for k in self.kind], dtype=np.int8)
        self.mid = (self.A + self.B) / 2
        self.half = np.hypot(*(self.B - self.A).T) / 2 if n else np.zeros(0)
        for k in self.cen:
            self.C[k] = (float(self.cen[k][0]), float(self.cen[k][1]))
            self.R[k] = float(self.rad[k])
            ua = np.array(self.A[k]) - self.C[k]
            ub = np.array(self.B[k]) - self.C[k]
            if ua[0] * ub[1] - ua[1] * ub[0] < 0:           # more than a half circle
                self.mid[k], self.half[k] = self.C[k], self.R[k]
            self.half[k] = self.half[k] * (1 + 1e-12) + 1e-300
        for k in self.piece:
            self.mid[k], self.half[k] = bounding_disc(self.sites[k])
        self.hmax = float(self.half.max()) if n else 0.0
        mags = [np.abs(self.A).max(initial=0.0), np.abs(self.B).max(initial=0.0)]
        if self.cen:
            arcs = list(self.cen)
            mags.append(float((np.abs(self.C[arcs]).max(axis=1) + self.R[arcs]).max()))
        for k in self.piece:
            mags.append(float(np.abs(self.mid[k]).max() + self.half[k]))
        self.scale = 1.0 + float(max(mags))
        self.tree = cKDTree(self.mid) if n else None
        # per site, the floats of :func:`runtime.segments.certificate_float_bounds.bounds_at`
        # (ends, their largest magnitude, the arc's centre, radius and centre magnitude; None
        # for an elliptic piece)
        rows = []
        for k in range(n):
            if self.kind[k] == ELLIPSE:
                rows.append(None)
                continue
            ax, ay = float(self.A[k, 0]), float(self.A[k, 1])
            bx, by = float(self.B[k, 0]), float(self.B[k, 1])
            arc = None
            if self.kind[k] == ARC:
                cx, cy = float(self.C[k, 0]), float(self.C[k, 1])
                arc = (cx, cy, float(self.R[k]), max(abs(cx), abs(cy)))
            rows.append((ax, ay, bx, by, max(abs(ax), abs(ay), abs(bx), abs(by)), arc))
        self.float_rows = rows

    def float_bounds(self, idx, Q):
        """Float lower and upper bounds of the distances from Q[r] to site idx[r] (rigorous up to
        the rounding margins of :func:`runtime.segments.distance.float_error`)."""
        idx = np.asarray(idx, dtype=np.int64)
        A, B = self.A[idx], self.B[idx]
        d, _ = distances(A, B, Q)
        err = float_error(A, B, Q) + 8 * EPS * self.scale
        lo, hi = d - err, d + err
        arc = self.karr[idx] == ARC
        if arc.any():
            C, R = self.C[idx[arc]], self.R[idx[arc]]
            Qa, Aa, Ba = Q[arc], A[arc], B[arc]
            W = Qa - C
            nw = np.hypot(W[:, 0], W[:, 1])
            circle = np.abs(nw - R)
            ends = np.minimum(np.hypot(*(Qa - Aa).T), np.hypot(*(Qa - Ba).T))
            ua, ub = Aa - C, Ba - C
            ca = ua[:, 0] * W[:, 1] - ua[:, 1] * W[:, 0]
            cb = W[:, 0] * ub[:, 1] - W[:, 1] * ub[:, 0]
            ab = ua[:, 0] * ub[:, 1] - ua[:, 1] * ub[:, 0]
            m = 64 * EPS * (np.abs(Qa).max(axis=1) + np.abs(C).max(axis=1) + R + 1.0) ** 2
            sure_in = np.where(ab > m, (ca > m) & (cb > m), np.where(ab < -m, (ca > m) | (cb > m), False))
            sure_out = np.where(ab > m, (ca < -m) | (cb < -m), np.where(ab < -m, (ca < -m) & (cb < -m), False))
            e = 64 * EPS * (np.abs(Qa).max(axis=1) + np.abs(C).max(axis=1) + R + 1.0) + 8 * EPS * self.scale
            lo_a = np.where(sure_in, circle, np.where(sure_out, ends, np.minimum(circle, ends))) - e
            hi_a = np.where(sure_in, circle, ends) + e
            lo[arc], hi[arc] = lo_a, hi_a
        ell = self.karr[idx] == ELLIPSE
        if ell.any():
            ie = idx[ell]
            lo[ell], hi[ell] = ellipse_float_bounds(self.mid[ie], self.half[ie], A[ell], B[ell], Q[ell], self.scale)
        return lo, hi

    def near(self, x: float, y: float, radius: float) -> list[int]:
        """Every site whose distance from (x, y) may be ≤ ``radius`` (a superset: the k-d tree
        query is widened by the largest bounding radius and a rounding margin)."""
        if self.tree is None or not np.isfinite(radius) or not (np.isfinite(x) and np.isfinite(y)):
            return list(range(self.n))
        r = radius + self.hmax + 1e-9 * (self.scale + abs(x) + abs(y) + radius)
        return self.tree.query_ball_point([x, y], r)

    def pool(self, x: float, y: float, radius: float, limit: int = 256):
        """The sites :meth:`near` finds for the disc of ``radius`` about (x, y), kept with that
        disc as a superset for the smaller discs inside it (:meth:`near_in`); None when they are
        more than ``limit`` (then a k-d tree query per disc is cheaper)."""
        if self.tree is None or not (np.isfinite(radius) and np.isfinite(x) and np.isfinite(y)):
            return None
        cands = self.near(x, y, radius)
        if len(cands) > limit:
            return None
        r = radius + self.hmax + 1e-9 * (self.scale + abs(x) + abs(y) + radius)
        return x, y, r, [(k, float(self.mid[k, 0]), float(self.mid[k, 1])) for k in cands]

    def near_in(self, pool, x: float, y: float, radius: float) -> list[int]:
        """:meth:`near` for the disc of ``radius`` about (x, y), from a :meth:`pool` whose disc
        contains it: the pool holds every site whose bounding-disc centre is within the pool's
        widened radius R of its centre p (k-d tree), and when |q − p| + r ≤ R (1 − 10⁻¹²) in
        floats (hypot faithful, one addition: relative errors far below the slack) every centre
        within r of q is within R of p; those within r (1 + 10⁻¹²) of q in floats are kept, a
        superset of :meth:`near`'s sites up to the same widening.  Without a pool, or when the disc
        leaves it, :meth:`near`."""
        if pool is None or not (np.isfinite(radius) and np.isfinite(x) and np.isfinite(y)):
            return self.near(x, y, radius)
        px, py, R, cands = pool
        r = radius + self.hmax + 1e-9 * (self.scale + abs(x) + abs(y) + radius)
        if not math.hypot(x - px, y - py) + r <= R * (1 - 1e-12):
            return self.near(x, y, radius)
        r *= 1 + 1e-12
        hyp = math.hypot
        return [k for k, mx, my in cands if hyp(mx - x, my - y) <= r]

    # ------------------------------------------------------------------ balls
    def arb_ends(self, k: int):
        """(ax, ay, bx, by) as arb balls (cached; the working precision is the certificate's)."""
        v = self._arb.get(k)
        if v is None:
            v = tuple(to_arb(c) for c in self.a[k] + self.b[k])
            self._arb[k] = v
        return v

    def distance(self, k: int, X: arb, Y: arb) -> arb:
        """A ball holding the distance from every point of the box (X, Y) to the closed site k."""
        ax, ay, bx, by = self.arb_ends(k)
        if self.kind[k] == POINT:
            return hypot(X - ax, Y - ay)
        if self.kind[k] == ELLIPSE:
            return piece_distance_ball(self.piece[k], X, Y)
        if self.kind[k] == ARC:
            cx, cy, rho = self.arb_arc(k)
            wx, wy = X - cx, Y - cy
            inside = self.in_range(k, wx, wy, closed=True)
            circle = abs(hypot(wx, wy) - rho)
            if inside is True:
                return circle
            da, db = hypot(X - ax, Y - ay), hypot(X - bx, Y - by)
            lo = da.lower() if da.lower() < db.lower() else db.lower()
            hi = da.upper() if da.upper() < db.upper() else db.upper()
            if inside is False:
                return arb(lo).union(arb(hi))
            lo = lo if lo < circle.lower() else circle.lower()
            return arb(lo).union(arb(hi))
        dx, dy = bx - ax, by - ay
        L2 = dx * dx + dy * dy
        t = ((X - ax) * dx + (Y - ay) * dy) / L2
        if t > 0 and t < 1:
            return abs((X - ax) * dy - (Y - ay) * dx) / L2.sqrt()
        if t <= 0:
            return hypot(X - ax, Y - ay)
        if t >= 1:
            return hypot(X - bx, Y - by)
        line = abs((X - ax) * dy - (Y - ay) * dx) / L2.sqrt()
        end = hypot(X - ax, Y - ay) if t.mid() < 0.5 else hypot(X - bx, Y - by)
        return line.lower().union(end.upper())

    def foot(self, k: int, X: arb, Y: arb) -> arb:
        """The foot parameter of (X, Y) on the line of segment k."""
        ax, ay, bx, by = self.arb_ends(k)
        dx, dy = bx - ax, by - ay
        return ((X - ax) * dx + (Y - ay) * dy) / (dx * dx + dy * dy)

    def owned_by_end(self, k: int, e: int, X: arb, Y: arb):
        """Curve k's nearest point to every point of the box is its end e alone (the tie then
        belongs to e): True / False / None.  Segment: the foot beyond e (or at e); arc: the
        direction from the centre in the half of the gap next to e."""
        if self.kind[k] == SEGMENT:
            u = self.foot(k, X, Y)
            if self.end_index(k, e) == 0:
                return True if u <= 0 else (False if u > 0 else None)
            return True if u >= 1 else (False if u < 1 else None)
        if self.kind[k] == ELLIPSE:
            return ellipse_owned_by_end(self.piece[k], self.end_index(k, e), X, Y)
        cx, cy, _ = self.arb_arc(k)
        wx, wy = X - cx, Y - cy
        g = self.arc_mid_arb(k)
        gx, gy = -g[0], -g[1]
        ex, ey = self._cached(("end_dir", k, e), lambda: tuple(to_arb(v - c) for v, c in zip(self.pt(e), self.cen[k])))
        if self.end_index(k, e) == 0:             # from the gap's middle counter-clockwise to a
            p, q = gx * wy - gy * wx, wx * ey - wy * ex
        else:                                     # from b counter-clockwise to the gap's middle
            p, q = ex * wy - ey * wx, wx * gy - wy * gx
        if p > 0 and q > 0:
            return True
        if p < 0 or q < 0:
            return False
        return None
