"""Admissibility of elliptic arcs among segment, arc and point sites: a float test.

Sites of a diagram of pieces may meet only at common endpoints (thesis §1.2;
:mod:`runtime.segments.crossings` decides this exactly for segments, circular arcs and points).
For an :class:`runtime.sites.elliptic_arc.EllipticArc` this module tests in floats: the arc is
drawn as a polyline of :data:`CHORDS` chords per piece (the deviation of a chord from the ellipse
is at most h²κ/8 for a chord of length h and curvature κ), and every other piece whose box meets
the arc's box (widened by that deviation) is compared with it:

* two chords crossing properly, away from the chords that end at a common endpoint: a crossing;
* the two polylines closer than the chord deviation plus 10⁻⁹ of the scale away from common
  endpoints: a touch (or a crossing the chords missed);
* a point site closer than that to the arc, and not one of its ends: a point on the arc;
* the same elliptic arc twice: a repeat.

This is a test, not a proof: a crossing or touch within the tolerance of the drawing can escape it
or be reported where the exact curves only come close; the certificate
(:func:`runtime.segments.certificate.verify_segments`) does not certify diagrams with elliptic
arcs.  Messages follow :mod:`runtime.segments.crossings` (one line naming both sites by index).

Public API: :func:`check_elliptic`, :data:`CHORDS`.
"""
from __future__ import annotations

import numpy as np

from ..sites.arc import Arc
from ..sites.elliptic_arc import EllipticArc
from ..sites.rationals import to_fraction
from ..sites.segment import Segment
from ..voronoi.site_input import SiteError

__all__ = ["check_elliptic", "CHORDS"]

#: chords per elliptic piece (and per circular arc it is compared with)
CHORDS = 256


def _polyline(piece):
    """(float polyline, exact end points or (), deviation bound of its chords)."""
    if isinstance(piece, Segment):
        a, b = piece.float_endpoints()
        return np.array([a, b], float), (piece.p, piece.q), 0.0
    if isinstance(piece, Arc):
        (cx, cy), rho, a, b = piece.float_data()
        t0 = np.arctan2(a[1] - cy, a[0] - cx)
        span = (np.arctan2(b[1] - cy, b[0] - cx) - t0) % (2 * np.pi) or 2 * np.pi
        t = t0 + np.linspace(0, span, CHORDS + 1)
        P = np.column_stack([cx + rho * np.cos(t), cy + rho * np.sin(t)])
        P[0], P[-1] = a, b
        return P, (piece.a, piece.b), rho * (span / CHORDS) ** 2 / 8
    if isinstance(piece, EllipticArc):
        out, dev = [], 0.0
        for sub in piece.pieces():
            (cx, cy), M, N, p0, p1 = sub.float_data()
            t = np.linspace(p0, p1, CHORDS + 1)
            Q = np.array([cx, cy]) + np.cos(t)[:, None] * np.array(M) + np.sin(t)[:, None] * np.array(N)
            Q[0], Q[-1] = [float(v) for v in sub.a], [float(v) for v in sub.b]
            out.append(Q if not out else Q[1:])
            a2 = max(np.hypot(*M), np.hypot(*N))
            b2 = min(np.hypot(*M), np.hypot(*N))
            # chord length ≤ a·Δφ, curvature ≤ a/b²
            dev = max(dev, (a2 * (p1 - p0) / CHORDS) ** 2 * (a2 / b2 ** 2) / 8)
        return np.concatenate(out), (piece.a, piece.b), dev
    x, y = float(piece.cx), float(piece.cy)
    return np.array([[x, y]]), ((piece.cx, piece.cy),), 0.0


def _cross(o, a, b):
    return (a[..., 0] - o[..., 0]) * (b[..., 1] - o[..., 1]) - (a[..., 1] - o[..., 1]) * (b[..., 0] - o[..., 0])


def _proper_crossing(P, Q):
    """(i, j) of a chord of P crossing a chord of Q properly, or None."""
    a, b = P[:-1, None, :], P[1:, None, :]
    c, d = Q[None, :-1, :], Q[None, 1:, :]
    d1, d2 = _cross(a, b, c), _cross(a, b, d)
    d3, d4 = _cross(c, d, a), _cross(c, d, b)
    hit = (d1 * d2 < 0) & (d3 * d4 < 0)
    if hit.any():
        i, j = np.argwhere(hit)[0]
        return int(i), int(j)
    return None


def _point_chords(X, Q):
    """Distances from the points X to the polyline Q (rows of X)."""
    if len(Q) == 1:
        return np.hypot(*(X - Q[0]).T)
    A, B = Q[:-1][None, :, :], Q[1:][None, :, :]
    D = B - A
    L2 = np.maximum(np.einsum("ijk,ijk->ij", D, D), 1e-300)
    t = np.clip(np.einsum("ijk,ijk->ij", X[:, None, :] - A, D) / L2, 0, 1)
    F = A + t[..., None] * D
    return np.hypot(*(X[:, None, :] - F).transpose(2, 0, 1)).min(axis=1)


def _key(p):
    """An exact hashable key of a point (Fractions: an fmpq equals but does not hash like one)."""
    x, y = (p[0], p[1]) if not hasattr(p, "cx") else (p.cx, p.cy)
    return (to_fraction(x), to_fraction(y))


def check_elliptic(pieces, elliptic) -> None:
    """Raise :class:`SiteError` when an elliptic arc (indices ``elliptic`` into ``pieces``) crosses,
    touches or repeats another piece, or a point site lies on it (float test, see the module
    docstring)."""
    lines = [_polyline(p) for p in pieces]
    boxes = np.array([[*L[0].min(axis=0), *L[0].max(axis=0)] for L in lines])
    scale = 1.0 + float(np.abs(boxes).max()) if len(boxes) else 1.0
    seen = {}
    for k in elliptic:
        key = pieces[k].key()
        if key in seen:
            raise SiteError(f"sites {seen[key]} and {k}: the same elliptic arc repeated (remove one)")
        seen[key] = k
    for k in elliptic:
        Pk, ends_k, dev_k = lines[k]
        for m in range(len(pieces)):
            if m == k or (m in elliptic and m < k):
                continue
            Pm, ends_m, dev_m = lines[m]
            tol = dev_k + dev_m + 1e-9 * scale
            bk, bm = boxes[k], boxes[m]
            if bk[0] > bm[2] + tol or bm[0] > bk[2] + tol or bk[1] > bm[3] + tol or bm[1] > bk[3] + tol:
                continue
            lo, hi = (k, m) if k < m else (m, k)
            shared = {_key(e) for e in ends_k} & {_key(e) for e in ends_m}
            if len(Pm) == 1:
                if shared:
                    continue
                d = _point_chords(Pm, Pk)[0]
                if d <= tol:
                    raise SiteError(f"sites {lo} and {hi}: the point ({Pm[0, 0]:.10g}, {Pm[0, 1]:.10g}) lies on "
                                    f"elliptic arc {k} (float test; split the arc there)")
                continue
            # away from common ends: drop the chords that end there
            keep_k = np.ones(len(Pk) - 1, bool)
            keep_m = np.ones(len(Pm) - 1, bool)
            for e in shared:
                fe = np.array([float(e[0]), float(e[1])])
                for P, keep in ((Pk, keep_k), (Pm, keep_m)):
                    near = np.hypot(*(P - fe).T) <= 1e-12 * scale
                    idx = np.nonzero(near)[0]
                    for i in idx.tolist():
                        keep[max(i - 1, 0):i + 1] = False
            hit = _proper_crossing(Pk, Pm)
            if hit is not None and keep_k[hit[0]] and keep_m[hit[1]]:
                x, y = Pk[hit[0] + 1]
                raise SiteError(f"sites {lo} and {hi}: elliptic arc {k} and {_name(pieces[m])} {m} cross near "
                                f"({x:.10g}, {y:.10g}) (float test)")
            # the chords' vertices and midpoints of each polyline, away from common ends, against
            # the other polyline
            for A_, keepA, B_, keepB in ((Pk, keep_k, Pm, keep_m), (Pm, keep_m, Pk, keep_k)):
                ka, kb = np.nonzero(keepA)[0], np.nonzero(keepB)[0]
                if not len(ka) or not len(kb):
                    continue
                # the kept chords are contiguous (only chords at a polyline's ends are dropped)
                X = np.concatenate([A_[ka], A_[ka + 1], (A_[ka] + A_[ka + 1]) / 2])
                dm = _point_chords(X, B_[kb[0]:kb[-1] + 2])
                if dm.min() <= tol:
                    x, y = X[int(np.argmin(dm))]
                    raise SiteError(f"sites {lo} and {hi}: elliptic arc {k} and {_name(pieces[m])} {m} touch or cross "
                                    f"near ({x:.10g}, {y:.10g}) (float test)")


def _name(piece) -> str:
    return ("elliptic arc" if isinstance(piece, EllipticArc) else "arc" if isinstance(piece, Arc)
            else "segment")
