"""Admissible segment and point sites: no crossings, overlaps, T-junctions or repeats (thesis §1.2:
the diagram is defined for sites that meet at most where a segment's endpoint is also a site).

:func:`check_pieces` accepts a list of :class:`runtime.sites.segment.Segment` and point sites
(:class:`runtime.predicates.circles.Point`) when segments meet only at common endpoints and a point
lies on no segment except at one of its endpoints (it is then the same point as that endpoint).
Otherwise it raises :class:`runtime.voronoi.site_input.SiteError` with one line naming the first
offending pair by index, e.g.::

    sites 3 and 7: segments cross at (1/2, 3)
    sites 2 and 5: the endpoint (1, 0) of site 5 lies in the interior of segment 2 (a T-junction: split site 2 there)
    sites 0 and 4: collinear segments overlap from (0, 0) to (1, 0)
    sites 1 and 6: the same segment repeated (remove one)
    sites 2 and 9: the point (1, 1) lies in the interior of segment 2 (split the segment there)
    sites 4 and 8: the same point repeated (remove one)

Every decision is exact (Fraction orientation tests); floats only choose which pairs to test.

1. Repeated points and segments: every endpoint and point gets an integer id from a dict keyed by
   its exact coordinates, so equal points and equal (unordered) segments are found by hashing.
2. Candidate pairs: a uniform grid of cell size ``h`` (the larger of the median segment extent and
   ``sqrt(area / n)``).  A segment is entered in the cells along it: in each column (for a segment
   closer to horizontal; rows otherwise) the rows between its heights at the column's two sides,
   widened by ``delta = 2^-40 M`` (M: the largest |coordinate|).  Every float error of this walk
   (rounding the rational endpoints to doubles, the slope, the heights, the cell indices) is below
   ``32 u M`` with ``u = 2^-53``, far below ``delta``, so two pieces with a common point share a cell.
   Two pieces are a candidate pair when they share a cell.
3. Float filter: with all coordinates of the pair at most ``Mp`` in absolute value
   (``2^-400 <= Mp <= 2^400``), an orientation ``(b - a) x (c - a)`` or a dot product evaluated in
   doubles from the rounded coordinates is within ``E = 2^-44 Mp^2`` of the exact value of the
   rational data (a bound of ``64 u Mp^2`` follows from ``|x~ - x| <= u Mp`` and three roundings;
   the margin is a factor 8).  A pair is accepted without the exact test when
   * both endpoints of one segment lie beyond ``E`` on the same side of the other's line, or the
     bounding boxes are apart by more than ``2^-48 Mp`` (all rounding errors are below ``2^-52 Mp``);
   * the two segments share one endpoint p and ``|orient(p, b, d)| > E`` or ``dot(b - p, d - p) < -E``
     (b, d the other endpoints: then they meet only at p);
   * a point p is not an endpoint of the segment [a, b] and ``|orient(a, b, p)| > E``.
   Every other candidate pair is decided exactly with Fractions, in increasing order of (i, j).

Cost: O(n log n) plus the candidate pairs, which are few when segments are about as long as the
spacing between them (maps, meshes, drawings).  The bad case of a uniform grid is many long
segments close together (e.g. 10⁵ long parallel stripes), or many pieces through one small cell.

Public API: :func:`check_pieces`.
"""
from __future__ import annotations

from fractions import Fraction

import numpy as np

from ..sites.segment import Segment
from ..voronoi.site_input import SiteError

__all__ = ["check_pieces"]

_U = 2.0 ** -53
_DELTA = 2.0 ** -40          # grid widening, relative to the largest |coordinate|
_ORIENT = 2.0 ** -44         # float orientation / dot error bound, relative to Mp^2
_BOX = 2.0 ** -48            # bounding-box separation margin, relative to Mp
_LO, _HI = 2.0 ** -400, 2.0 ** 400


def check_pieces(pieces, *, float_filter: bool = True) -> None:
    """Raise :class:`SiteError` unless the segments and points ``pieces`` are admissible sites of
    a segment Voronoi diagram (see the module docstring); None when they are.

    ``float_filter=False`` decides every candidate pair exactly (for testing the filter)."""
    n = len(pieces)
    segs, pts = _classify(pieces)
    ids, P, Q, vid, coords = _vertex_ids(pieces, segs, pts)
    _check_repeats(segs, pts, P, Q, vid)
    if n < 2 or not segs:
        return
    F = _floats(coords)                                    # vertex id -> (x, y) doubles
    A = np.full((n, 2), np.nan)
    B = np.full((n, 2), np.nan)
    va = np.full(n, -1, dtype=np.int64)
    vb = np.full(n, -1, dtype=np.int64)
    s_idx = np.array(segs, dtype=np.int64)
    va[s_idx] = [P[i] for i in segs]
    vb[s_idx] = [Q[i] for i in segs]
    if pts:
        p_idx = np.array(pts, dtype=np.int64)
        va[p_idx] = [vid[i] for i in pts]
        vb[p_idx] = va[p_idx]
    A[:] = F[va]
    B[:] = F[vb]
    is_seg = np.zeros(n, dtype=bool)
    is_seg[s_idx] = True
    M = float(np.abs(F).max()) if F.size else 0.0
    i, j = _candidate_pairs(A, B, is_seg, M)
    if float_filter:
        keep = ~_float_accepts(A, B, va, vb, is_seg, i, j)
        i, j = i[keep], j[keep]
    for a, b in zip(i.tolist(), j.tolist()):
        msg = _exact_contact(a, b, is_seg, va, vb, coords)
        if msg:
            raise SiteError(f"sites {a} and {b}: {msg}")


# =====================================================================================
# Input, ids and repeats
# =====================================================================================

def _classify(pieces) -> tuple[list[int], list[int]]:
    from ..predicates.circles import Circle

    segs, pts = [], []
    for k, s in enumerate(pieces):
        if isinstance(s, Segment):
            segs.append(k)
        elif isinstance(s, Circle) and s.r2 == 0:
            pts.append(k)
        else:
            raise SiteError(f"site {k}: {type(s).__name__} is not a segment or a point (this check takes "
                            "Segment and Point sites)")
    return segs, pts


def _point_key(s) -> tuple[Fraction, Fraction]:
    return (Fraction(int(s.cx.p), int(s.cx.q)), Fraction(int(s.cy.p), int(s.cy.q)))


def _vertex_ids(pieces, segs, pts):
    """ids: exact point -> id; P, Q: segment index -> endpoint ids; vid: point index -> id."""
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
    for k in pts:
        vid[k] = vertex(_point_key(pieces[k]))
    return ids, P, Q, vid, coords


def _check_repeats(segs, pts, P, Q, vid) -> None:
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
    if bad:
        a, b, msg = min(bad)
        raise SiteError(f"sites {a} and {b}: {msg}")


def _floats(coords) -> np.ndarray:
    try:
        F = np.array([(float(x), float(y)) for x, y in coords], dtype=float).reshape(-1, 2)
    except OverflowError:
        raise SiteError("a coordinate is too large for the float grid (|value| > 1e308): rescale the "
                        "input") from None
    if F.size and float(np.abs(F).max()) > 1e300:
        raise SiteError("a coordinate is too large for the float grid (|value| > 1e300): rescale the input")
    return F


# =====================================================================================
# Candidate pairs: the grid
# =====================================================================================

def _candidate_pairs(A, B, is_seg, M) -> tuple[np.ndarray, np.ndarray]:
    """(i, j), i < j, sorted, unique: pieces sharing a grid cell, at least one a segment."""
    n = len(A)
    delta = _DELTA * M + 2.0 ** -1000
    lo = np.minimum(A, B).min(axis=0)
    hi = np.maximum(A, B).max(axis=0)
    W, H = hi - lo
    ext = np.maximum(np.abs(B[:, 0] - A[:, 0]), np.abs(B[:, 1] - A[:, 1]))[is_seg]
    h = max(float(np.median(ext)) if ext.size else 0.0, float(np.sqrt(W * H / n)), max(W, H) / n, 64 * delta)
    origin = lo - 2 * h
    steep = np.abs(B[:, 1] - A[:, 1]) > np.abs(B[:, 0] - A[:, 0])
    pieces, cells = [], []
    for mask, (u, v) in ((~steep, (0, 1)), (steep, (1, 0))):
        idx = np.nonzero(mask)[0]
        if idx.size:
            k, cu, cv = _walk(A[idx][:, u], A[idx][:, v], B[idx][:, u], B[idx][:, v], origin[u], origin[v], h, delta)
            col, row = (cu, cv) if u == 0 else (cv, cu)
            pieces.append(idx[k])
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
    keep = (a != b) & (is_seg[a] | is_seg[b])
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


# =====================================================================================
# Float filter
# =====================================================================================

def _orient(a, b, c):
    return (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])


def _dot(p, b, d):
    return (b[:, 0] - p[:, 0]) * (d[:, 0] - p[:, 0]) + (b[:, 1] - p[:, 1]) * (d[:, 1] - p[:, 1])


def _float_accepts(A, B, va, vb, is_seg, i, j) -> np.ndarray:
    """True where the pair (i, j) is certainly admissible (see the module docstring, step 3)."""
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


# =====================================================================================
# Exact decision of one pair
# =====================================================================================

def _fmt(p) -> str:
    return f"({p[0]}, {p[1]})"


def _o(a, b, c) -> Fraction:
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])


def _exact_contact(i, j, is_seg, va, vb, exact) -> str | None:
    """The contact of pieces i < j in words, or None when they are admissible together."""
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
