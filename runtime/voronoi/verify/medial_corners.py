"""Corners of a bisector where it crosses the medial axis of an ellipse that contains it.

Inside an ellipse E: X²/a² + Y²/b² < 1 (a ≥ b) the distance d_E is differentiable except on its
ridge, the open segment |X| < (a² − b²)/a of the major axis between the centres of curvature of
the major vertices (H. I. Choi, S. W. Choi, H. P. Moon, *Mathematical theory of medial axis
transform*, Pacific J. Math. 181 (1997); :mod:`runtime.voronoi.verify.clarke_gradient`).  On
the ridge the nearest point of E jumps between the two mirror-image foot points, so the bisector
β of E and a site nested in it (a point, a circle, an ellipse) has a corner there: on the axis
itself d_E = b·√(1 − X²/(a² − b²)) (the normal from (X, 0) meets E where cos θ = aX/(a² − b²)), and β is the union of the two smooth curves d_± = d_k, d_± the distances
to the upper and lower halves, each kept where it is the smaller one.

**Enclosure.**  d_E and d_k are continuous, so f = d_E − d_k changes sign along a segment
[p, q] only if β meets it (intermediate value theorem).  The points tried are floats
c + X·u on the major axis (u its unit vector); each sign is proved by the site table's rigorous
bounds (f > 0 where lo_E − hi_k > 0, f < 0 where hi_E − lo_k < 0), and the bracket is shrunk
by sampling 32 points inside it per round.  The result is a segment [p, q] of proved opposite
signs, hence a point of β within |p − q|/2 of its midpoint: a proved point of the edge on the
ridge (up to the float points' distance from the exact axis, which only matters for its
position, not for its being on β).

**Use.**  :mod:`runtime.voronoi.verify.curved` cuts the strips' guide across each corner by a
chord (a strip whose direction bisects the corner; across the ridge it is proved monotone by
the Clarke generalised gradient, Clarke 1983, Thm 2.3.7 and 2.8.2, in
:mod:`runtime.voronoi.verify.strips` (T1)), and refuses a drawn polyline that passes farther than
its stated tolerance from a proved corner (a chord that cuts the corner).

Public API: :func:`ridge_crossings`, :func:`may_cross_ridges`, :func:`enclose_corners`,
:func:`medial_corners`, :func:`distance_to_polyline`.
"""
from __future__ import annotations

import numpy as np

from ...segments.distance import distances
from ...sites.kinds import SiteKind

__all__ = ["ridge_crossings", "may_cross_ridges", "enclose_corners", "medial_corners", "distance_to_polyline"]

SAMPLES = 32        # points tried inside a bracket per round
ROUNDS = 12         # rounds of shrinking at most
GROW = 40           # doublings of the first bracket at most


def _ridge(table, h):
    """(centre, unit vector of the major axis, half-length of the ridge) of ellipse h."""
    c, s = float(table.c[h]), float(table.s[h])
    a, b = float(table.a[h]), float(table.b[h])
    big, small = max(a, b), min(a, b)
    u = np.array([c, s]) if a >= b else np.array([-s, c])
    return np.array([table.cx[h], table.cy[h]], float), u, (big - small) * (big + small) / big


def ridge_crossings(table, pair, S):
    """The places where the guide S (a polyline) crosses the ridge of an ellipse of ``pair``:
    a list of (h, X) with h the ellipse and X the estimated position along its major axis."""
    S = np.asarray(S, float).reshape(-1, 2)
    out = []
    for h in pair:
        if table.kind[h] != SiteKind.ELLIPSE or len(S) < 2:
            continue
        cen, u, half = _ridge(table, h)
        if half <= 0:
            continue
        D = S - cen
        along = D @ u
        across = D @ np.array([-u[1], u[0]])
        y0, y1 = across[:-1], across[1:]
        # a sign change, or a node on the axis (counted once: as the end of its first segment)
        hit = ((y0 < 0) & (y1 > 0)) | ((y0 > 0) & (y1 < 0)) | ((y1 == 0) & (y0 != 0))
        hit[0] |= (y0[0] == 0) & (y1[0] != 0)
        for k in np.nonzero(hit)[0].tolist():
            t = y0[k] / (y0[k] - y1[k])
            X = float(along[k] + t * (along[k + 1] - along[k]))
            if abs(X) < half and not any(hh == h and abs(XX - X) <= 1e-9 * (1 + half) for hh, XX in out):
                out.append((h, X))
    return out


def may_cross_ridges(table, pairs, polylines):
    """For each pair and polyline (an array of nodes): False where :func:`ridge_crossings` of the
    polyline (or of any polyline through its nodes, closed or not) finds no crossing for certain,
    so that nothing need be enclosed: no site of the pair is an ellipse with a ridge, or the
    polyline's bounding box widened by 10⁻⁶·(1 + the largest coordinate of the polyline and of the
    ridge) misses the bounding box of each ridge segment (a crossing is a point of a segment of
    the polyline on the ridge, computed to a few units in the last place of the coordinates).  The
    margin is far above that rounding: where this says False, :func:`ridge_crossings` returns []."""
    polys = [np.asarray(P, float).reshape(-1, 2) for P in polylines]
    use = np.array([len(P) >= 2 for P in polys], bool)
    out = np.zeros(len(polys), bool)
    if not use.any():
        return out.tolist()
    cnt = np.array([len(P) for P in polys], int)[use]
    Pall = np.concatenate([P for P, u_ in zip(polys, use) if u_])
    starts = np.concatenate([[0], np.cumsum(cnt)[:-1]]).astype(int)
    lo, hi = np.minimum.reduceat(Pall, starts, axis=0), np.maximum.reduceat(Pall, starts, axis=0)
    big = np.maximum.reduceat(np.abs(Pall).max(1), starts)
    pairs = np.array([tuple(p) for p, u_ in zip(pairs, use) if u_], int).reshape(-1, 2)
    rlo, rhi = np.full((len(table.kind), 2), np.nan), np.full((len(table.kind), 2), np.nan)
    for h in np.unique(pairs).tolist():
        if int(table.kind[h]) == SiteKind.ELLIPSE:
            cen, u, half = _ridge(table, h)
            if half > 0:
                rlo[h], rhi[h] = cen - np.abs(u) * half, cen + np.abs(u) * half
    hit = np.zeros(len(pairs), bool)
    for c in (0, 1):        # NaN (no ridge) compares False
        r0, r1 = rlo[pairs[:, c]], rhi[pairs[:, c]]
        pad = 1e-6 * (1.0 + big + np.maximum(np.abs(r0), np.abs(r1)).max(1))[:, None]
        hit |= np.all(lo - pad <= r1, axis=1) & np.all(hi + pad >= r0, axis=1)
    out[use] = hit
    return out.tolist()


def _signs(V, m):
    """Proved signs of f = d_first − d_second at m points (0: undecided) from stacked values."""
    Vi, Vj = V.part(0, m), V.part(m, 2 * m)
    return np.where(Vi.lo - Vj.hi > 0, 1, np.where(Vi.hi - Vj.lo < 0, -1, 0))


def enclose_corners(table, pair, crossings, step, scale):
    """Enclose a point of β near each crossing (h, X) of :func:`ridge_crossings`: a list of
    (h, p, q), [p, q] a segment on the major axis of h with f of proved opposite signs at its
    ends (module docstring), or None where no bracket was found within ``GROW`` doublings of
    ``step``.  Generator (requests (points, sites) to the site table)."""
    out = []
    for h, X in crossings:
        cen, u, half = _ridge(table, h)
        lim = half * (1 - 1e-9)
        st = step
        br = None
        for _ in range(GROW):
            xs = np.array([max(X - st, -lim), X, min(X + st, lim)])
            P = cen + xs[:, None] * u
            V = yield (np.concatenate([P, P]), np.repeat(list(pair), 3))
            sg = _signs(V, 3)
            if sg[0] * sg[2] < 0:
                br = (xs[0], xs[2], int(sg[0]))
                break
            st *= 2
            if st > 4 * half:
                break
        if br is None:
            out.append(None)
            continue
        lo, hi, s_lo = br
        for _ in range(ROUNDS):
            if hi - lo <= 1e-13 * scale:
                break
            xs = np.linspace(lo, hi, SAMPLES + 2)[1:-1]
            P = cen + xs[:, None] * u
            V = yield (np.concatenate([P, P]), np.repeat(list(pair), len(xs)))
            sg = _signs(V, len(xs))
            same = np.nonzero(sg == s_lo)[0]
            other = np.nonzero(sg == -s_lo)[0]
            j = other[0] if len(other) else len(xs)          # the first proved sign change
            new_hi = xs[j] if len(other) else hi
            before = same[same < j]
            new_lo = xs[before[-1]] if len(before) else lo
            if (new_lo, new_hi) == (lo, hi):
                break
            lo, hi = new_lo, new_hi
        out.append((h, cen + lo * u, cen + hi * u))
    return out


def medial_corners(table, pair, S, step, scale):
    """Proved points of the bisector of ``pair`` where the guide S crosses a ridge: a list of
    (h, midpoint, radius) (the point lies within ``radius`` of ``midpoint``; radius covers the
    float rounding of the midpoint), or None when a crossing could not be enclosed.
    Generator."""
    found = yield from enclose_corners(table, pair, ridge_crossings(table, pair, S), step, scale)
    out = []
    for c in found:
        if c is None:
            return None
        h, p, q = c
        m = 0.5 * (p + q)
        out.append((h, m, 0.5 * float(np.hypot(*(q - p))) * (1 + 1e-12) + 4e-16 * (1 + np.abs(m).sum())))
    return out


def distance_to_polyline(x, P):
    """Float distances from the point x to the segments of the polyline P (an array, one per
    segment; :func:`runtime.segments.distance.distances`)."""
    P = np.asarray(P, float).reshape(-1, 2)
    if len(P) == 1:
        P = np.vstack([P, P])
    Q = np.broadcast_to(np.asarray(x, float), (len(P) - 1, 2))
    return distances(P[:-1], P[1:], np.ascontiguousarray(Q))[0]
