"""Admissible segment, arc and point sites: no crossings, tangencies, overlaps, T-junctions or
repeats (thesis §1.2: the diagram is defined for sites that meet at most where an endpoint of a
piece is also an endpoint of the other).

:func:`check_pieces` accepts a list of :class:`runtime.sites.segment.Segment`,
:class:`runtime.sites.arc.Arc` and point sites (:class:`runtime.sites.circle.Point`) when
segments and arcs meet only at common endpoints and a point lies on no segment or arc except at
one of its endpoints (it is then the same point as that endpoint).  Otherwise it raises
:class:`runtime.voronoi.site_input.SiteError` with one line naming the first offending pair by
index, e.g.::

    sites 3 and 7: segments cross at (1/2, 3)
    sites 2 and 5: the endpoint (1, 0) of site 5 lies in the interior of segment 2 (a T-junction: split site 2 there)
    sites 0 and 4: collinear segments overlap from (0, 0) to (1, 0)
    sites 1 and 6: the same segment repeated (remove one)
    sites 2 and 9: the point (1, 1) lies in the interior of segment 2 (split the segment there)
    sites 4 and 8: the same point repeated (remove one)
    sites 0 and 1: segment 1 and arc 0 cross at ≈(0.7071067812, 0.7071067812)
    sites 0 and 1: arc 0 and arc 1 touch at (2, 0) (tangent)
    sites 1 and 3: the endpoint (0, 1) of site 3 lies in the interior of arc 1 (a T-junction: split site 1 there)
    sites 0 and 2: arcs of the same circle overlap from (1, 0) to (0, 1) (counter-clockwise)
    sites 0 and 2: the same arc repeated (remove one)
    sites 2 and 4: the point (3/5, 4/5) lies in the interior of arc 2 (split the arc there)

A contact point is printed exactly when it is rational, else as ``≈(x, y)`` (10 digits).

Every decision is exact; floats only choose which pairs to test.

1. Repeated points, segments and arcs: every endpoint and point gets an integer id from a dict
   keyed by its exact coordinates, so equal points, equal (unordered) segments and equal arcs
   (same centre, radius, start and end) are found by hashing.
2. Candidate pairs: a uniform grid of cell size ``h`` (the larger of the median extent of the
   segments and arcs and ``sqrt(area / n)``).  A segment is entered in the cells along it: in each
   column (for a segment closer to horizontal; rows otherwise) the rows between its heights at the
   column's two sides, widened by ``delta = 2^-40 M`` (M: the largest |coordinate|, arcs' centre
   ± radius included).  Every float error of this walk (rounding the rational endpoints to doubles,
   the slope, the heights, the cell indices) is below ``32 u M`` with ``u = 2^-53``, far below
   ``delta``, so two pieces with a common point share a cell.  An arc is cut exactly at the
   extreme points of its circle (centre ± radius along the axes) that lie in it into at most five
   pieces monotone in x and y, each inside the box of its two ends; a piece longer than ``h`` is
   cut further at points ``c + ρ(cos φ, sin φ)`` of float angles spaced about ``h/ρ``, at least
   ``h/(2ρ)`` inside the piece's angular range, whose float error (``8 u M / ρ + 2u`` radians for
   the ends' angles, ``6 u M`` for the points) is far below that margin and ``delta``.  The arc
   enters the cells of these boxes widened by ``delta``.  Two pieces are a candidate pair when
   they share a cell.
3. Float filter: with all coordinates of the pair at most ``Mp`` in absolute value (for an arc:
   ``|centre| + radius``; ``2^-400 <= Mp <= 2^400``), an orientation ``(b - a) x (c - a)`` or a
   dot product evaluated in doubles from the rounded coordinates is within ``E = 2^-44 Mp^2`` of
   the exact value of the rational data (a bound of ``64 u Mp^2`` follows from
   ``|x~ - x| <= u Mp`` and three roundings; the margin is a factor 8).  A pair of segments and
   points is accepted without the exact test when
   * both endpoints of one segment lie beyond ``E`` on the same side of the other's line, or the
     bounding boxes are apart by more than ``2^-48 Mp`` (all rounding errors are below ``2^-52 Mp``);
   * the two segments share one endpoint p and ``|orient(p, b, d)| > E`` or ``dot(b - p, d - p) < -E``
     (b, d the other endpoints: then they meet only at p);
   * a point p is not an endpoint of the segment [a, b] and ``|orient(a, b, p)| > E``.
   A pair with an arc (centre c, radius ρ; ``2^-200 <= Mp <= 2^200``) uses ``E2 = 2^-42 Mp^2`` and
   ``E4 = 2^-38 Mp^4``: the float values of ``f(p) = |p - c|² - ρ²``, of dot products and of
   ``2 (c - p)·d - |d|²`` are within ``2^-45 Mp^2`` of the exact ones (``ρ <= Mp``, ``|c| <= Mp``),
   and ``orient(p, q, c)² - ρ²|q - p|²`` within ``2^-42 Mp^4`` (``|orient| <= 8 Mp²``, its error
   ``2^-47 Mp²``), a factor 8 or more below the margins.  It is accepted when
   * the bounding boxes are apart by more than ``2^-48 Mp`` (an arc's box: its ends and the
     extreme points of its circle in it, errors below ``3 u Mp``);
   * a point p is an endpoint of the arc, or ``|f(p)| > E2`` (off the circle);
   * a segment [p, q] (d = q - p): its line misses the circle (``orient(p, q, c)² - ρ²|d|² > E4``),
     or it lies in the open disk (``f(p), f(q) < -E2``), or the foot of c lies beyond p
     (``(c - p)·d < -E2``) and ``f(p) > E2`` (or the same at q);
   * a segment with exactly one endpoint p at an endpoint of the arc whose line meets the circle
     again outside the segment (``(c - p)·d < -E2`` or ``2 (c - p)·d - |d|² > E2``);
   * two arcs on circles apart (``|c1 - c2|² - (ρ1 + ρ2)² > E2``) or nested
     (``(ρ1 - ρ2)² - |c1 - c2|² > E2``).
   Every other candidate pair is decided exactly with Fractions, in increasing order of (i, j).
4. Exact contacts with arcs.  A line P + t d meets the circle where
   ``|d|² t² + 2 (w·d) t + |w|² - ρ² = 0`` (w = P - c): ``t = t0 ± √Δ / |d|²`` with rational
   ``t0`` and ``Δ``; two circles meet on their radical line at ``X0 ± √S · perp(c2 - c1)``.  When
   ``Δ`` (``S``) is the square of a rational the points are rational and every test is a Fraction
   comparison; otherwise each coordinate, the parameter t and the cross products deciding whether
   the point's direction from the centre lies in the arc's angular range are numbers ``p + q√Δ``
   of Q(√Δ), whose sign is decided exactly (opposite signs of p and q: compare ``p²`` with
   ``q²Δ``).  An irrational point is never an endpoint (the endpoints are rational), so such a
   contact is a crossing; a double root (``Δ = 0``) is a tangency.  Arcs of one circle overlap
   exactly when an endpoint of one lies in the open other or they share their start or their end.

Cost: O(n log n) plus the candidate pairs, which are few when pieces are about as long as the
spacing between them (maps, meshes, drawings).  The bad case of a uniform grid is many long
pieces close together (e.g. 10⁵ long parallel stripes), or many pieces through one small cell.

Length: the grid, the float filter and the exact predicates share the piece tables built here and
are one decision procedure; splitting them would only scatter its error analysis.

Public API: :func:`check_pieces`.
"""
from __future__ import annotations

import math
import re
from fractions import Fraction

import numpy as np

from ..sites.arc import Arc
from ..sites.elliptic_arc import EllipticArc
from ..sites.kinds import SiteKind
from .ellipse_crossings import check_elliptic
from ..sites.segment import Segment
from ..voronoi.site_input import SiteError

__all__ = ["check_pieces"]

_U = 2.0 ** -53
_DELTA = 2.0 ** -40          # grid widening, relative to the largest |coordinate|
_ORIENT = 2.0 ** -44         # float orientation / dot error bound, relative to Mp^2
_BOX = 2.0 ** -48            # bounding-box separation margin, relative to Mp
_LO, _HI = 2.0 ** -400, 2.0 ** 400
_ARC2 = 2.0 ** -42           # arc filter: margin of degree-2 quantities, relative to Mp^2
_ARC4 = 2.0 ** -38           # arc filter: margin of degree-4 quantities, relative to Mp^4
_ARC_LO, _ARC_HI = 2.0 ** -200, 2.0 ** 200

_POINT, _SEG, _ARC = int(SiteKind.POINT), int(SiteKind.SEGMENT), int(SiteKind.ARC)


def renamed(message: str, names) -> str:
    """A message of :func:`check_pieces` with each piece index k written ``names(k)`` (the pieces
    as the input names them: a DXF entity, a polyline's edge, a circle of the input); the wording
    of the messages is this module's, so is this reading of them."""
    m = re.match(r"sites (\d+) and (\d+): (.*)$", message, re.S)
    if m:
        a, b, rest = int(m.group(1)), int(m.group(2)), m.group(3)
        rest = re.sub(r"\b(?:site|segment|arc) (\d+)\b", lambda mm: names(int(mm.group(1))), rest)
        return f"{names(a)} and {names(b)}: {rest}"
    return re.sub(r"^site (\d+):", lambda mm: names(int(mm.group(1))) + ":", message)


def check_pieces(pieces, *, float_filter: bool = True) -> None:
    """Raise :class:`SiteError` unless the segments, arcs and points ``pieces`` are admissible
    sites of a Voronoi diagram of pieces (see the module docstring); None when they are.

    ``float_filter=False`` decides every candidate pair exactly (for testing the filter).
    Elliptic arcs are tested in floats by :func:`runtime.segments.ellipse_crossings.check_elliptic`
    (the other pieces exactly, as always)."""
    elliptic = [k for k, p in enumerate(pieces) if isinstance(p, EllipticArc)]
    if elliptic:
        rest = [k for k in range(len(pieces)) if k not in set(elliptic)]
        try:
            check_pieces([pieces[k] for k in rest], float_filter=float_filter)
        except SiteError as exc:
            raise SiteError(renamed(str(exc), lambda k: f"site {rest[k]}")) from None
        check_elliptic(pieces, elliptic)
        return
    n = len(pieces)
    segs, pts, arcs = _classify(pieces)
    ids, P, Q, vid, coords = _vertex_ids(pieces, segs, pts, arcs)
    _check_repeats(pieces, segs, pts, arcs, P, Q, vid)
    if n < 2 or not (segs or arcs):
        return
    F = _floats(coords)                                    # vertex id -> (x, y) doubles
    kind = np.zeros(n, dtype=np.int8)
    va = np.full(n, -1, dtype=np.int64)
    vb = np.full(n, -1, dtype=np.int64)
    for group, code in ((segs, _SEG), (arcs, _ARC)):
        if group:
            idx = np.array(group, dtype=np.int64)
            kind[idx] = code
            va[idx] = [P[i] for i in group]
            vb[idx] = [Q[i] for i in group]
    if pts:
        p_idx = np.array(pts, dtype=np.int64)
        va[p_idx] = [vid[i] for i in pts]
        vb[p_idx] = va[p_idx]
    A = F[va]
    B = F[vb]
    LO, HI = np.minimum(A, B), np.maximum(A, B)
    MAG = np.max(np.abs(np.concatenate([A, B], axis=1)), axis=1)
    C = np.full((n, 2), np.nan)
    R = np.full(n, np.nan)
    arc_parts: dict[int, list] = {}
    for k in arcs:
        C[k], R[k], parts = _arc_floats(pieces[k])
        arc_parts[k] = parts
        ends = np.array([e for part in parts for e in part])
        LO[k], HI[k] = ends.min(axis=0), ends.max(axis=0)
        MAG[k] = max(abs(C[k, 0]), abs(C[k, 1])) + R[k]
    M = float(MAG.max())
    i, j = _candidate_pairs(A, B, kind, LO, HI, C, R, arc_parts, M)
    if float_filter and i.size:
        plain = (kind[i] != _ARC) & (kind[j] != _ARC)
        accept = np.zeros(len(i), dtype=bool)
        accept[plain] = _float_accepts(A, B, va, vb, kind == _SEG, i[plain], j[plain])
        accept[~plain] = _arc_float_accepts(kind, A, B, C, R, LO, HI, MAG, va, vb, i[~plain], j[~plain])
        i, j = i[~accept], j[~accept]
    for a, b in zip(i.tolist(), j.tolist()):
        if kind[a] == _ARC or kind[b] == _ARC:
            msg = _arc_contact(a, b, pieces)
        else:
            msg = _exact_contact(a, b, kind == _SEG, va, vb, coords)
        if msg:
            raise SiteError(f"sites {a} and {b}: {msg}")


# =====================================================================================
# Input, ids and repeats
# =====================================================================================

def _classify(pieces) -> tuple[list[int], list[int], list[int]]:
    from ..predicates.circles import Circle

    segs, pts, arcs = [], [], []
    for k, s in enumerate(pieces):
        if isinstance(s, Segment):
            segs.append(k)
        elif isinstance(s, Arc):
            arcs.append(k)
        elif isinstance(s, Circle) and s.r2 == 0:
            pts.append(k)
        else:
            raise SiteError(f"site {k}: {type(s).__name__} is not a segment or a point (this check takes "
                            "Segment, Arc and Point sites)")
    return segs, pts, arcs


def _point_key(s) -> tuple[Fraction, Fraction]:
    return (Fraction(int(s.cx.p), int(s.cx.q)), Fraction(int(s.cy.p), int(s.cy.q)))


def _vertex_ids(pieces, segs, pts, arcs):
    """ids: exact point -> id; P, Q: segment or arc index -> endpoint ids; vid: point index -> id."""
    ids: dict = {}                     # keyed by integers: hashing Fractions is slow
    coords: list = []
    P, Q, vid = {}, {}, {}

    def vertex(pt) -> int:
        x, y = pt
        key = (x.numerator, x.denominator, y.numerator, y.denominator)
        v = ids.get(key)
        if v is None:
            v = ids[key] = len(coords)
            coords.append(pt)
        return v

    for k in segs:
        s = pieces[k]
        P[k] = vertex(s.p)
        Q[k] = vertex(s.q)
    for k in arcs:
        s = pieces[k]
        P[k] = vertex(s.a)
        Q[k] = vertex(s.b)
    for k in pts:
        vid[k] = vertex(_point_key(pieces[k]))
    return ids, P, Q, vid, coords


def _check_repeats(pieces, segs, pts, arcs, P, Q, vid) -> None:
    bad = []
    first: dict = {}
    for k in pts:
        key = ("p", vid[k])
        if key in first:
            bad.append((first[key], k, "the same point repeated (remove one)"))
        else:
            first[key] = k
    for k in segs:
        key = ("s",) + tuple(sorted((P[k], Q[k])))
        if key in first:
            bad.append((first[key], k, "the same segment repeated (remove one)"))
        else:
            first[key] = k
    for k in arcs:
        key = ("a", pieces[k].c, pieces[k].rho, P[k], Q[k])
        if key in first:
            bad.append((first[key], k, "the same arc repeated (remove one)"))
        else:
            first[key] = k
    if bad:
        a, b, msg = min(bad)
        raise SiteError(f"sites {a} and {b}: {msg}")


_TOO_LARGE = "a coordinate is too large for the float grid (|value| > 1e300): rescale the input"


def _floats(coords) -> np.ndarray:
    try:
        F = np.array([(float(x), float(y)) for x, y in coords], dtype=float).reshape(-1, 2)
    except OverflowError:
        raise SiteError("a coordinate is too large for the float grid (|value| > 1e308): rescale the "
                        "input") from None
    if F.size and float(np.abs(F).max()) > 1e300:
        raise SiteError(_TOO_LARGE)
    return F


def _quadrant(dx, dy) -> int:
    """The half-open quadrant [90k°, 90(k+1)°) of the nonzero direction (dx, dy)."""
    if dx > 0 and dy >= 0:
        return 0
    if dx <= 0 and dy > 0:
        return 1
    if dx < 0 and dy <= 0:
        return 2
    return 3


def _monotone_parts(arc) -> list[tuple]:
    """The arc cut (exactly) at the extreme points of its circle: [(start, end), ...] counter-
    clockwise, each part inside one closed quadrant, hence monotone in x and y."""
    (cx, cy), r, a, b = arc.c, arc.rho, arc.a, arc.b
    ext = [(cx + r, cy), (cx, cy + r), (cx - r, cy), (cx, cy - r)]     # ext[k]: where quadrant k starts
    ax, ay, bx, by = a[0] - cx, a[1] - cy, b[0] - cx, b[1] - cy
    ka, kb = _quadrant(ax, ay), _quadrant(bx, by)
    if ka == kb and ax * by - ay * bx > 0:
        return [(a, b)]
    out = []
    cur, k = a, ka
    for _ in range(4):
        nxt = ext[(k + 1) % 4]
        out.append((cur, nxt))
        cur, k = nxt, (k + 1) % 4
        if k == kb:
            break
    if cur != b:
        out.append((cur, b))
    return out


def _arc_floats(arc):
    """(centre, radius, monotone parts as float point pairs) of an arc."""
    try:
        c = (float(arc.c[0]), float(arc.c[1]))
        r = float(arc.rho)
        parts = [((float(p[0]), float(p[1])), (float(q[0]), float(q[1]))) for p, q in _monotone_parts(arc)]
    except OverflowError:
        raise SiteError(_TOO_LARGE) from None
    if max(abs(c[0]), abs(c[1])) + r > 1e300:
        raise SiteError(_TOO_LARGE)
    return c, r, parts


# =====================================================================================
# Candidate pairs: the grid
# =====================================================================================

def _candidate_pairs(A, B, kind, LO, HI, C, R, arc_parts, M) -> tuple[np.ndarray, np.ndarray]:
    """(i, j), i < j, sorted, unique: pieces sharing a grid cell, at least one a segment or arc."""
    n = len(A)
    delta = _DELTA * M + 2.0 ** -1000
    lo = LO.min(axis=0)
    hi = HI.max(axis=0)
    W, H = hi - lo
    ext = (HI - LO).max(axis=1)[kind != _POINT]
    h = max(float(np.median(ext)) if ext.size else 0.0, float(np.sqrt(W * H / n)), max(W, H) / n, 64 * delta)
    origin = lo - 2 * h
    steep = np.abs(B[:, 1] - A[:, 1]) > np.abs(B[:, 0] - A[:, 0])
    flat = kind != _ARC
    pieces, cells = [], []
    for mask, (u, v) in ((flat & ~steep, (0, 1)), (flat & steep, (1, 0))):
        idx = np.nonzero(mask)[0]
        if idx.size:
            k, cu, cv = _walk(A[idx][:, u], A[idx][:, v], B[idx][:, u], B[idx][:, v], origin[u], origin[v], h, delta)
            col, row = (cu, cv) if u == 0 else (cv, cu)
            pieces.append(idx[k])
            cells.append(col * np.int64(1 << 31) + row)
    if arc_parts:
        k, col, row = _arc_cells(C, R, arc_parts, origin, h, delta)
        pieces.append(k)
        cells.append(col * np.int64(1 << 31) + row)
    piece = np.concatenate(pieces)
    cell = np.concatenate(cells)
    order = np.lexsort((piece, cell))
    piece, cell = piece[order], cell[order]
    I, J = [], []
    act = np.arange(len(cell) - 1)
    step = 1
    while act.size:
        nxt = act + step
        ok = nxt < len(cell)
        act, nxt = act[ok], nxt[ok]
        same = cell[act] == cell[nxt]
        act, nxt = act[same], nxt[same]
        I.append(piece[act])
        J.append(piece[nxt])
        step += 1
    if not I:
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    I, J = np.concatenate(I), np.concatenate(J)
    a, b = np.minimum(I, J), np.maximum(I, J)
    keep = (a != b) & ((kind[a] != _POINT) | (kind[b] != _POINT))
    key = np.sort(a[keep] * np.int64(n) + b[keep])
    if key.size:
        key = key[np.concatenate(([True], key[1:] != key[:-1]))]
    return key // n, key % n


def _walk(u0, v0, u1, v1, ou, ov, h, delta):
    """(piece, column, row) of the cells along segments with |du| >= |dv| (points: du = dv = 0)."""
    swap = u1 < u0
    u0, u1 = np.where(swap, u1, u0), np.where(swap, u0, u1)
    v0, v1 = np.where(swap, v1, v0), np.where(swap, v0, v1)
    du = u1 - u0
    slope = np.divide(v1 - v0, du, out=np.zeros_like(du), where=du > 0)
    c0 = np.floor((u0 - delta - ou) / h).astype(np.int64)
    c1 = np.floor((u1 + delta - ou) / h).astype(np.int64)
    k = c1 - c0 + 1
    seg = np.repeat(np.arange(len(u0)), k)
    start = np.repeat(np.cumsum(k) - k, k)
    col = c0[seg] + (np.arange(len(seg)) - start)
    ua = np.clip(ou + col * h, u0[seg], u1[seg])
    ub = np.clip(ou + (col + 1) * h, u0[seg], u1[seg])
    va = v0[seg] + (ua - u0[seg]) * slope[seg]
    vb = v0[seg] + (ub - u0[seg]) * slope[seg]
    r0 = np.floor((np.minimum(va, vb) - 3 * delta - ov) / h).astype(np.int64)
    r1 = np.floor((np.maximum(va, vb) + 3 * delta - ov) / h).astype(np.int64)
    m = r1 - r0 + 1
    ent = np.repeat(np.arange(len(seg)), m)
    start = np.repeat(np.cumsum(m) - m, m)
    row = r0[ent] + (np.arange(len(ent)) - start)
    return seg[ent], col[ent], row


def _arc_cells(C, R, arc_parts, origin, h, delta):
    """(piece, column, row) of the cells of the boxes covering the arcs (module docstring, step 2)."""
    owner, boxes = [], []
    for k, parts in arc_parts.items():
        (cx, cy), r = C[k], R[k]
        for p, q in parts:
            chain = [p]
            t0 = math.atan2(p[1] - cy, p[0] - cx)
            span = (math.atan2(q[1] - cy, q[0] - cx) - t0) % (2 * math.pi)
            m = math.ceil(span * r / h) if span < math.pi else 1      # a part spans at most 90°
            for s in range(1, m):
                phi = t0 + span * s / m
                chain.append((cx + r * math.cos(phi), cy + r * math.sin(phi)))
            chain.append(q)
            for e, f in zip(chain, chain[1:]):
                owner.append(k)
                boxes.append((min(e[0], f[0]), min(e[1], f[1]), max(e[0], f[0]), max(e[1], f[1])))
    owner = np.array(owner, dtype=np.int64)
    box = np.array(boxes, dtype=float).reshape(-1, 4)
    c0 = np.floor((box[:, 0] - delta - origin[0]) / h).astype(np.int64)
    c1 = np.floor((box[:, 2] + delta - origin[0]) / h).astype(np.int64)
    r0 = np.floor((box[:, 1] - delta - origin[1]) / h).astype(np.int64)
    r1 = np.floor((box[:, 3] + delta - origin[1]) / h).astype(np.int64)
    nc, nr = c1 - c0 + 1, r1 - r0 + 1
    cnt = nc * nr
    ent = np.repeat(np.arange(len(owner)), cnt)
    off = np.arange(len(ent)) - np.repeat(np.cumsum(cnt) - cnt, cnt)
    return owner[ent], c0[ent] + off // nr[ent], r0[ent] + off % nr[ent]


# =====================================================================================
# Float filter
# =====================================================================================

def _orient(a, b, c):
    return (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])


def _dot(p, b, d):
    return (b[:, 0] - p[:, 0]) * (d[:, 0] - p[:, 0]) + (b[:, 1] - p[:, 1]) * (d[:, 1] - p[:, 1])


def _float_accepts(A, B, va, vb, is_seg, i, j) -> np.ndarray:
    """True where the pair (i, j) of segments and points is certainly admissible (module docstring,
    step 3)."""
    a, b, c, d = A[i], B[i], A[j], B[j]
    ss = is_seg[i] & is_seg[j]
    # a point (j, or i) that is an endpoint of the other piece, a segment: decided by the exact ids
    seg_pt = is_seg[i] & ~is_seg[j]
    pt_seg = ~is_seg[i] & is_seg[j]
    out = (seg_pt & ((va[j] == va[i]) | (va[j] == vb[i]))) | (pt_seg & ((va[i] == va[j]) | (va[i] == vb[j])))
    Mp = np.max(np.abs(np.concatenate([a, b, c, d], axis=1)), axis=1)
    usable = (Mp >= _LO) & (Mp <= _HI)
    Mp = np.where(usable, Mp, 1.0)
    E = _ORIENT * Mp * Mp
    gap = _BOX * Mp
    fl = np.zeros(len(i), dtype=bool)
    for ax in (0, 1):                                   # bounding boxes apart
        lo_i, hi_i = np.minimum(a[:, ax], b[:, ax]), np.maximum(a[:, ax], b[:, ax])
        lo_j, hi_j = np.minimum(c[:, ax], d[:, ax]), np.maximum(c[:, ax], d[:, ax])
        fl |= (lo_j - hi_i > gap) | (lo_i - hi_j > gap)
    o1, o2, o3, o4 = _orient(a, b, c), _orient(a, b, d), _orient(c, d, a), _orient(c, d, b)
    side = ((o1 > E) & (o2 > E)) | ((o1 < -E) & (o2 < -E)) | ((o3 > E) & (o4 > E)) | ((o3 < -E) & (o4 < -E))
    fl |= ss & side
    for si in (0, 1):                                   # one common endpoint p; other ends q, r
        for sj in (0, 1):
            share = ss & ((va[i] if si == 0 else vb[i]) == (va[j] if sj == 0 else vb[j]))
            if share.any():
                p, q = (a, b) if si == 0 else (b, a)
                r = d if sj == 0 else c
                fl |= share & ((np.abs(_orient(p, q, r)) > E) | (_dot(p, q, r) < -E))
    fl |= seg_pt & (np.abs(o1) > E)                     # o1 = orient(a, b, point j)
    fl |= pt_seg & (np.abs(o3) > E)                     # o3 = orient(c, d, point i)
    return out | (fl & usable)


def _arc_float_accepts(kind, A, B, C, R, LO, HI, MAG, va, vb, i, j) -> np.ndarray:
    """True where the pair (i, j), one of them an arc, is certainly admissible (module docstring,
    step 3)."""
    swap = kind[i] != _ARC
    x, y = np.where(swap, j, i), np.where(swap, i, j)            # x: an arc; y: any piece
    Mp = np.maximum(MAG[x], MAG[y])
    usable = (Mp >= _ARC_LO) & (Mp <= _ARC_HI)
    Mp = np.where(usable, Mp, 1.0)
    E2, E4, gap = _ARC2 * Mp * Mp, _ARC4 * Mp ** 4, _BOX * Mp
    ok = np.zeros(len(i), dtype=bool)
    for ax in (0, 1):                                   # bounding boxes apart
        ok |= (LO[y, ax] - HI[x, ax] > gap) | (LO[x, ax] - HI[y, ax] > gap)
    c, r, p, q = C[x], R[x], A[y], B[y]
    ky = kind[y]

    def f(z):                                           # |z - c|² - ρ²
        return (z[:, 0] - c[:, 0]) ** 2 + (z[:, 1] - c[:, 1]) ** 2 - r * r

    fp, fq = f(p), f(q)
    at_a = (va[y] == va[x]) | (va[y] == vb[x])          # y's first point is an endpoint of the arc
    at_b = (vb[y] == va[x]) | (vb[y] == vb[x])
    pt = ky == _POINT
    ok |= pt & (at_a | (np.abs(fp) > E2))
    sg = ky == _SEG
    d = q - p
    L = d[:, 0] ** 2 + d[:, 1] ** 2
    cr = _orient(p, q, c)
    wd = _dot(p, c, q)                                  # (c - p)·(q - p)
    qd = (c[:, 0] - q[:, 0]) * d[:, 0] + (c[:, 1] - q[:, 1]) * d[:, 1]    # (c - q)·(q - p)
    ok |= sg & (cr * cr - r * r * L > E4)                                 # the line misses the circle
    ok |= sg & (fp < -E2) & (fq < -E2)                                    # inside the open disk
    ok |= sg & (((wd < -E2) & (fp > E2)) | ((qd > E2) & (fq > E2)))       # nearest point an end, outside
    ok |= sg & at_a & ~at_b & ((wd < -E2) | (2 * wd - L > E2))            # the second meeting off the segment
    ok |= sg & at_b & ~at_a & ((qd > E2) | (-2 * qd - L > E2))
    ar = ky == _ARC
    c2, r2 = C[y], R[y]
    D2 = (c[:, 0] - c2[:, 0]) ** 2 + (c[:, 1] - c2[:, 1]) ** 2
    ok |= ar & ((D2 - (r + r2) ** 2 > E2) | ((r - r2) ** 2 - D2 > E2))    # circles apart or nested
    return ok & usable


# =====================================================================================
# Exact decision of one pair
# =====================================================================================

def _fmt(p) -> str:
    return f"({p[0]}, {p[1]})"


def _o(a, b, c) -> Fraction:
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])


def _exact_contact(i, j, is_seg, va, vb, exact) -> str | None:
    """The contact of pieces i < j (segments and points) in words, or None when they are
    admissible together."""
    if is_seg[i] and is_seg[j]:
        return _segments_contact(i, j, exact[int(va[i])], exact[int(vb[i])], exact[int(va[j])], exact[int(vb[j])])
    if is_seg[i]:
        s, p = i, j
    else:
        s, p = j, i
    a, b, x = exact[int(va[s])], exact[int(vb[s])], exact[int(va[p])]
    if x in (a, b) or _o(a, b, x) != 0 or not (min(a, b) < x < max(a, b)):
        return None
    return f"the point {_fmt(x)} lies in the interior of segment {s} (split the segment there)"


def _segments_contact(i, j, a, b, c, d) -> str | None:
    o1, o2, o3, o4 = _o(a, b, c), _o(a, b, d), _o(c, d, a), _o(c, d, b)
    if o1 == 0 and o2 == 0:                     # collinear: compare along the line (lexicographic order)
        s0, s1 = sorted((a, b))
        t0, t1 = sorted((c, d))
        lo, hi = max(s0, t0), min(s1, t1)
        if lo < hi:
            if (s0, s1) == (t0, t1):
                return "the same segment repeated (remove one)"
            return f"collinear segments overlap from {_fmt(lo)} to {_fmt(hi)}"
        return None                             # apart, or one common endpoint
    if (o1 > 0 and o2 > 0) or (o1 < 0 and o2 < 0) or (o3 > 0 and o4 > 0) or (o3 < 0 and o4 < 0):
        return None
    # one common point: an endpoint on the other segment, or a proper crossing
    for o, e, own, other, seg in ((o1, c, j, i, (a, b)), (o2, d, j, i, (a, b)), (o3, a, i, j, (c, d)),
                                  (o4, b, i, j, (c, d))):
        if o == 0:
            if e in seg:
                return None                     # a common endpoint (the segments are not collinear)
            return (f"the endpoint {_fmt(e)} of site {own} lies in the interior of segment {other} "
                    f"(a T-junction: split site {other} there)")
    t = o3 / (o3 - o4)
    x = (a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]))
    return f"segments cross at {_fmt(x)}"


# ------------------------------------------------------------------ with arcs: Q(√D)

def _sign(p, q=0, D=0) -> int:
    """The sign of p + q√D (D > 0 not the square of a rational when q != 0)."""
    sp = (p > 0) - (p < 0)
    if q == 0:
        return sp
    sq = (q > 0) - (q < 0)
    if sp == 0 or sp == sq:
        return sq
    return sp if p * p > q * q * D else sq         # p² = q²D is impossible: √D is irrational


def _sqrt(v: Fraction) -> Fraction | None:
    """√v when v >= 0 is the square of a rational, else None."""
    v = Fraction(v)
    n, d = v.numerator, v.denominator
    rn, rd = math.isqrt(n), math.isqrt(d)
    return Fraction(rn, rd) if rn * rn == n and rd * rd == d else None


def _in_arc(arc, U0, U1=(0, 0), D=0) -> bool:
    """The direction U0 + U1·√D (from the centre, nonzero) lies in the closed angular range of the
    arc: the test of :meth:`Arc.contains_direction` with its two cross products in Q(√D)."""
    ax, ay = arc.a[0] - arc.c[0], arc.a[1] - arc.c[1]
    bx, by = arc.b[0] - arc.c[0], arc.b[1] - arc.c[1]
    ca = _sign(ax * U0[1] - ay * U0[0], ax * U1[1] - ay * U1[0], D)       # a → u counter-clockwise
    cb = _sign(U0[0] * by - U0[1] * bx, U1[0] * by - U1[1] * bx, D)       # u → b counter-clockwise
    ab = ax * by - ay * bx
    if ab > 0:
        return ca >= 0 and cb >= 0
    if ab < 0:
        return ca >= 0 or cb >= 0
    return ca >= 0                                                        # a half circle


def _approx(X0, X1, D) -> str:
    """≈(x, y) for the irrational point X0 + X1·√D."""
    try:
        s = math.sqrt(float(D))
        return f"≈({float(X0[0]) + float(X1[0]) * s:.10g}, {float(X0[1]) + float(X1[1]) * s:.10g})"
    except (OverflowError, ValueError):
        return "an irrational point"


def _kind_name(piece) -> str:
    return "arc" if isinstance(piece, Arc) else "segment"


def _meeting(X, i, end_i, j, end_j, tangent, pieces) -> str | None:
    """The contact of pieces i and j at the rational point X (on both), or None for a common
    endpoint."""
    if end_i and end_j:
        return None
    if end_i or end_j:
        own, other = (i, j) if end_i else (j, i)
        return (f"the endpoint {_fmt(X)} of site {own} lies in the interior of {_kind_name(pieces[other])} {other} "
                f"(a T-junction: split site {other} there)")
    verb = "touch" if tangent else "cross"
    tail = " (tangent)" if tangent else ""
    return f"{_kind_name(pieces[i])} {i} and {_kind_name(pieces[j])} {j} {verb} at {_fmt(X)}{tail}"


def _arc_contact(i, j, pieces) -> str | None:
    """The contact of pieces i < j, one of them an arc, in words, or None when admissible."""
    si, sj = pieces[i], pieces[j]
    if isinstance(si, Arc) and isinstance(sj, Arc):
        return _arcs_contact(i, si, j, sj, pieces)
    k, arc, m, other = (i, si, j, sj) if isinstance(si, Arc) else (j, sj, i, si)
    if isinstance(other, Segment):
        return _arc_segment_contact(k, arc, m, other, pieces)
    x = _point_key(other)
    c = arc.c
    if x in (arc.a, arc.b) or (x[0] - c[0]) ** 2 + (x[1] - c[1]) ** 2 != arc.rho ** 2:
        return None
    if _in_arc(arc, (x[0] - c[0], x[1] - c[1])):
        return f"the point {_fmt(x)} lies in the interior of arc {k} (split the arc there)"
    return None


def _arc_segment_contact(k, arc, m, seg, pieces) -> str | None:
    c, r = arc.c, arc.rho
    P, Q = seg.p, seg.q
    d = (Q[0] - P[0], Q[1] - P[1])
    w = (P[0] - c[0], P[1] - c[1])
    L = d[0] * d[0] + d[1] * d[1]
    wd = w[0] * d[0] + w[1] * d[1]
    disc = wd * wd - L * (w[0] * w[0] + w[1] * w[1] - r * r)   # t = t0 ± √disc / L
    if disc < 0:
        return None
    t0 = -wd / L
    root = _sqrt(disc)
    lo, hi = min(k, m), max(k, m)
    if root is not None:                                        # rational meeting points
        for t in sorted({t0 - root / L, t0 + root / L}):
            if 0 <= t <= 1:
                X = (P[0] + t * d[0], P[1] + t * d[1])
                if _in_arc(arc, (X[0] - c[0], X[1] - c[1])):
                    ends = {k: X in (arc.a, arc.b), m: t in (0, 1)}
                    msg = _meeting(X, lo, ends[lo], hi, ends[hi], root == 0, pieces)
                    if msg:
                        return msg
        return None
    for s in (-1, 1):                                           # irrational: inside both, never an end
        q = Fraction(s) / L
        if _sign(t0, q, disc) > 0 and _sign(1 - t0, -q, disc) > 0:
            X0 = (P[0] + t0 * d[0], P[1] + t0 * d[1])
            X1 = (q * d[0], q * d[1])
            if _in_arc(arc, (X0[0] - c[0], X0[1] - c[1]), X1, disc):
                return (f"{_kind_name(pieces[lo])} {lo} and {_kind_name(pieces[hi])} {hi} cross at "
                        f"{_approx(X0, X1, disc)}")
    return None


def _arcs_contact(i, a1, j, a2, pieces) -> str | None:
    (c1, r1), (c2, r2) = (a1.c, a1.rho), (a2.c, a2.rho)
    if c1 == c2:
        return _same_circle(a1, a2) if r1 == r2 else None       # concentric circles do not meet
    e = (c2[0] - c1[0], c2[1] - c1[1])
    E = e[0] * e[0] + e[1] * e[1]
    lam = (r1 * r1 - r2 * r2 + E) / (2 * E)                     # X0 = c1 + lam·e on the radical line
    S = (r1 * r1 - lam * lam * E) / E                           # X = X0 ± √S·perp(e)
    if S < 0:
        return None
    X0 = (c1[0] + lam * e[0], c1[1] + lam * e[1])
    n = (-e[1], e[0])
    root = _sqrt(S)
    if root is not None:
        for X in sorted({(X0[0] + root * n[0], X0[1] + root * n[1]), (X0[0] - root * n[0], X0[1] - root * n[1])}):
            if _in_arc(a1, (X[0] - c1[0], X[1] - c1[1])) and _in_arc(a2, (X[0] - c2[0], X[1] - c2[1])):
                msg = _meeting(X, i, X in (a1.a, a1.b), j, X in (a2.a, a2.b), root == 0, pieces)
                if msg:
                    return msg
        return None
    for s in (1, -1):
        X1 = (s * n[0], s * n[1])
        if (_in_arc(a1, (X0[0] - c1[0], X0[1] - c1[1]), X1, S)
                and _in_arc(a2, (X0[0] - c2[0], X0[1] - c2[1]), X1, S)):
            return f"arc {i} and arc {j} cross at {_approx(X0, X1, S)}"
    return None


def _same_circle(a1, a2) -> str | None:
    """Two arcs of one circle: None when they meet at most at endpoints."""
    c = a1.c

    def inside(arc, X) -> bool:                 # in the closed arc
        return _in_arc(arc, (X[0] - c[0], X[1] - c[1]))

    def open_(arc, X) -> bool:
        return X not in (arc.a, arc.b) and inside(arc, X)

    if a1.a == a2.a and a1.b == a2.b:
        return "the same arc repeated (remove one)"
    if not (a1.a == a2.a or a1.b == a2.b or open_(a1, a2.a) or open_(a1, a2.b) or open_(a2, a1.a)
            or open_(a2, a1.b)):
        return None
    # the first overlapping piece starts at a start point inside the other arc and ends at the
    # first end point met counter-clockwise
    s = a2.a if inside(a1, a2.a) and a2.a != a1.b else a1.a
    if a1.b == a2.b:
        t = a1.b
    else:
        t = a2.b if inside(Arc(c, a1.rho, s, a1.b), a2.b) else a1.b
    return f"arcs of the same circle overlap from {_fmt(s)} to {_fmt(t)} (counter-clockwise)"
