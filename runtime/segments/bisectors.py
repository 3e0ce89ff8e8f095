"""Bisectors of two elementary sites in closed form, drawn as polylines with a proved deviation.

Thesis §2.2 (harmless sites) and §4 (generalised offsets of degree ≤ 2 here): the bisector of

* two points is their perpendicular bisector (a line);
* an endpoint e and the interior of a segment s ending at e is the perpendicular to s at e;
* a point p and the interior of a segment s (p not an endpoint) is the parabola of focus p and
  directrix the line of s, restricted to the points whose foot lies in s — parametrised here
  by the foot parameter u: v(u) = f(u) + h(u)·n, f(u) = a + u (b − a), n the unit normal on p's
  side and h(u) = |f(u) − p|² / (2 n·(p − f(u)));
* two segment interiors is a line: an angle bisector of their lines, or their mid-parallel;
* two curves meeting at a smooth joint j is the normal line at j;
* an arc (centre c, radius ρ) and any other site is a conic (ch. 4: an offset of the circle
  meets the other site's offset): parametrised by the contact angle θ on the arc,
  v(θ) = c + (ρ + σ t) u(θ), u(θ) = (cos θ, sin θ), σ = +1 outside the circle and −1 inside, and
  t(θ) the distance, rational in u: with a point p (D = c − p, w = u·D)
  t = −(|D|² + 2ρw + ρ²) / (2σ(w + ρ)); with the line n·v + c₀ = τ t (n unit)
  t = (n·c + c₀ + ρ n·u) / (τ − σ n·u); with an arc (c₂, ρ₂, σ₂) (D = c − c₂)
  t = (ρ₂² − ρ² − |D|² − 2ρw) / (2(σw + σρ − σ₂ρ₂)).

A chord of a parabola of focal distance δ (curvature ≤ 1/δ) and length L stays within L²/(8δ)
of its arc (the sagitta bound), which sets the sampling density and the stated tolerance; line
edges are drawn as one straight piece (tolerance: rounding of the end points).

Arc bisectors are drawn by bisection of the parameter until every chord's midpoint is within
half the tolerance of the curve's point at the middle parameter; the stated bound is the requested
tolerance (twice the measured deviation where the bisection stopped above it), not the measured
deviation itself: near a hyperbola-like branch's pole the chords' true deviation exceeds the
midpoints' (a far end point off the curve along its asymptote), and a bound stated at the
measurement would leave the proof no room.  Its proof is the certificate's.

Many straight and parabolic edges are drawn at once on arrays (:func:`simple_kinds`,
:func:`parabola_polylines`: the same formulas, row by row).

Public API: :func:`bisector_kind`, :func:`simple_kinds`, :func:`edge_polyline`,
:func:`parabola_polylines`, :func:`line_direction`, :func:`arc_bisector_points`.
"""
from __future__ import annotations

import math

import numpy as np

from .distance import distances
from .elementary import ARC, ELLIPSE, POINT, SEGMENT, ElementarySites
from .ellipse_bisectors import ellipse_edge
from .ellipse_pieces import piece_tangent
from .polyline_refinement import refined_parameters

__all__ = ["bisector_kind", "simple_kinds", "edge_polyline", "parabola_polylines", "line_direction", "parabola_points",
           "arc_bisector_points", "STRAIGHT", "PARABOLA", "OTHER"]

#: most pieces of one parabolic edge
MAX_PIECES = 4096


def shared_joint(E: ElementarySites, i: int, j: int, near=None) -> int | None:
    """The smooth joint code (< −1) that curves i and j share, if any (two arcs of one circle
    may share both their ends: then the one nearer to ``near``)."""
    if E.kind[i] == POINT or E.kind[j] == POINT:
        return None
    common = {int(v) for v in E.ends[i] if v < -1} & {int(v) for v in E.ends[j] if v < -1}
    if not common:
        return None
    if near is None or len(common) == 1:
        return min(common)
    return min(common, key=lambda c: (float(E.xy[c][0]) - near[0]) ** 2 + (float(E.xy[c][1]) - near[1]) ** 2)


def bisector_kind(E: ElementarySites, i: int, j: int) -> str:
    """"points", "perpendicular" (an end and its curve), "joint" (two curves of a smooth joint),
    "parabola" (a point and a segment), "segments", "arc" (an arc and a site not touching it) or
    "ellipse" (an elliptic piece and a site not touching it, :mod:`runtime.segments.ellipse_bisectors`)."""
    ki, kj = E.kind[i], E.kind[j]
    if ki == POINT and kj == POINT:
        return "points"
    if ki == POINT or kj == POINT:
        p, s = (i, j) if ki == POINT else (j, i)
        if E.is_endpoint(p, s):
            return "perpendicular"
        return "ellipse" if E.kind[s] == ELLIPSE else "arc" if E.kind[s] == ARC else "parabola"
    if shared_joint(E, i, j) is not None:
        return "joint"
    if ELLIPSE in (ki, kj):
        return "ellipse"
    return "arc" if ARC in (ki, kj) else "segments"


#: codes of :func:`simple_kinds`
STRAIGHT, PARABOLA, OTHER = 0, 1, 2


def simple_kinds(E: ElementarySites, I, J) -> np.ndarray:
    """Per pair (I, J) of sites: :data:`STRAIGHT` (kinds "points", "perpendicular" of a segment or
    a circular arc, "segments"), :data:`PARABOLA` or :data:`OTHER` (joints, arcs, elliptic pieces:
    :func:`bisector_kind` one by one); the same kinds as :func:`bisector_kind`, on arrays."""
    I, J = np.asarray(I, np.int64), np.asarray(J, np.int64)
    ki, kj = E.kind[I], E.kind[J]
    out = np.full(len(I), OTHER, np.int8)
    out[(ki == POINT) & (kj == POINT)] = STRAIGHT
    one = (ki == POINT) != (kj == POINT)
    p, s = np.where(ki == POINT, I, J), np.where(ki == POINT, J, I)
    ks = E.kind[s]
    end = (E.ends[s, 0] == p) | (E.ends[s, 1] == p)
    out[one & end & ((ks == SEGMENT) | (ks == ARC))] = STRAIGHT
    out[one & ~end & (ks == SEGMENT)] = PARABOLA
    # two segments: a line unless they share a smooth joint (a code < −1 at both)
    ei, ej = E.ends[I], E.ends[J]
    joint = ((ei[:, :, None] == ej[:, None, :]) & (ei[:, :, None] < -1)).any(axis=(1, 2))
    out[(ki == SEGMENT) & (kj == SEGMENT) & ~joint] = STRAIGHT
    return out


def _tangent(E: ElementarySites, s: int, e_xy) -> np.ndarray:
    """The tangent direction of curve s at its end e (floats)."""
    if E.kind[s] == ARC:
        r = np.asarray(e_xy, float) - E.C[s]
        return np.array([-r[1], r[0]])
    if E.kind[s] == ELLIPSE:
        at_start = np.hypot(*(np.asarray(e_xy, float) - E.A[s])) <= np.hypot(*(np.asarray(e_xy, float) - E.B[s]))
        return piece_tangent(E.ellipse[s], 0 if at_start else 1)
    return E.B[s] - E.A[s]


def line_direction(E: ElementarySites, i: int, j: int, near=None) -> np.ndarray:
    """A unit direction of a straight bisector of kind "points", "perpendicular" or "joint"
    (``near``: a point of the edge, choosing between two joints)."""
    kind = bisector_kind(E, i, j)
    if kind == "points":
        d = E.A[j] - E.A[i]
    elif kind == "perpendicular":
        p, s = (i, j) if E.kind[i] == POINT else (j, i)
        d = _tangent(E, s, E.A[p])
    else:
        jt = shared_joint(E, i, j, near)
        d = _tangent(E, i, [float(v) for v in E.xy[jt]])
    n = np.array([-d[1], d[0]])
    return n / np.hypot(*n)


def line_point(E: ElementarySites, i: int, j: int, near=None) -> np.ndarray:
    """A point of a straight bisector of kind "points", "perpendicular" or "joint"."""
    kind = bisector_kind(E, i, j)
    if kind == "points":
        return (E.A[i] + E.A[j]) / 2
    if kind == "perpendicular":
        return E.A[i if E.kind[i] == POINT else j].copy()
    return np.array([float(v) for v in E.xy[shared_joint(E, i, j, near)]])


def arc_bisector_points(E: ElementarySites, s: int, other: int, sigma: int, tau: int, theta: np.ndarray):
    """Points v(θ) of the bisector of arc s and site ``other`` (see the module docstring) and
    their distances t; σ: the side of the arc's circle, τ: the side of a segment's line."""
    c, rho = E.C[s], E.rho[s]
    U = np.column_stack([np.cos(theta), np.sin(theta)])
    with np.errstate(divide="ignore", invalid="ignore"):
        if E.kind[other] == POINT:
            D = c - E.A[other]
            w = U @ D
            t = -(D @ D + 2 * rho * w + rho * rho) / (2 * sigma * (w + rho))
        elif E.kind[other] == ARC:
            c2, rho2 = E.C[other], E.rho[other]
            D = c - c2
            w = U @ D
            sigma2 = 1 if tau > 0 else -1
            t = (rho2 * rho2 - rho * rho - D @ D - 2 * rho * w) / (2 * (sigma * w + sigma * rho - sigma2 * rho2))
        else:
            a, b = E.A[other], E.B[other]
            d = b - a
            n = np.array([-d[1], d[0]]) / np.hypot(*d)
            c0 = -n @ a
            nu = U @ n
            t = (n @ c + c0 + rho * nu) / (tau - sigma * nu)
    return c + (rho + sigma * t)[:, None] * U, t


def parabola_points(E: ElementarySites, p: int, s: int, u: np.ndarray) -> np.ndarray:
    """Points of the bisector of point site p and segment site s at foot parameters ``u``."""
    a, d, n, P = _parabola_frames(E, np.array([p]), np.array([s]))
    u = np.asarray(u, float)
    return _parabola_at(a[0], d[0], n[0], P[0], u)


def _parabola_frames(E: ElementarySites, p, s):
    """Per row (point site p, segment site s): the segment's start a, its direction d, the unit
    normal n on p's side and the focus P (arrays of rows)."""
    a, P = E.A[s], E.A[p]
    d = E.B[s] - a
    n = np.column_stack([-d[:, 1], d[:, 0]]) / np.hypot(d[:, 0], d[:, 1])[:, None]
    flip = (P[:, 0] - a[:, 0]) * n[:, 0] + (P[:, 1] - a[:, 1]) * n[:, 1] < 0
    n[flip] = -n[flip]
    return a, d, n, P


def _parabola_at(a, d, n, P, u):
    """v(u) = f(u) + h(u)·n, f(u) = a + u d, h(u) = |f(u) − P|² / (2 n·(P − f(u))) (rows of a, d,
    n, P broadcast against the foot parameters u)."""
    Fx, Fy = a[..., 0] + u * d[..., 0], a[..., 1] + u * d[..., 1]
    Wx, Wy = P[..., 0] - Fx, P[..., 1] - Fy
    h = (Wx * Wx + Wy * Wy) / (2 * (Wx * n[..., 0] + Wy * n[..., 1]))
    return np.stack([Fx + h * n[..., 0], Fy + h * n[..., 1]], axis=-1)


def parabola_polylines(E: ElementarySites, p, s, P0, P1, tol: float):
    """The polylines of many parabolic edges at once (rows: point site p, segment site s, end
    points P0 and P1 on their bisector): (one big array of their points, the start of each
    edge's points in it, each edge's deviation bound).  Each edge is cut into n pieces of equal
    foot-parameter step, n from the length L of a 64-chord polyline and the sagitta bound
    L²/(8δ) ≤ tol (δ the focal distance); the bound stated is max chord²/(8δ) plus the rounding
    10⁻¹² of the ends' scale.  All rows need δ > 0."""
    p, s = np.asarray(p, np.int64), np.asarray(s, np.int64)
    P0, P1 = np.asarray(P0, float).reshape(-1, 2), np.asarray(P1, float).reshape(-1, 2)
    a, d, n, P = _parabola_frames(E, p, s)
    dd = d[:, 0] * d[:, 0] + d[:, 1] * d[:, 1]
    u0 = ((P0[:, 0] - a[:, 0]) * d[:, 0] + (P0[:, 1] - a[:, 1]) * d[:, 1]) / dd
    u1 = ((P1[:, 0] - a[:, 0]) * d[:, 0] + (P1[:, 1] - a[:, 1]) * d[:, 1]) / dd
    delta = np.abs((P[:, 0] - a[:, 0]) * -d[:, 1] + (P[:, 1] - a[:, 1]) * d[:, 0]) / np.hypot(d[:, 0], d[:, 1])
    # the foot parameters of np.linspace(u0, u1, k + 1): j·step + u0, the last one u1
    k = np.arange(65.0)
    U = k * ((u1 - u0) / 64)[:, None] + u0[:, None]
    U[:, -1] = u1
    fine = _parabola_at(a[:, None], d[:, None], n[:, None], P[:, None], U)
    length = np.hypot(*np.diff(fine, axis=1).transpose(2, 0, 1)).sum(axis=1)
    pieces = np.minimum(MAX_PIECES, np.maximum(1, np.ceil(length / np.sqrt(8 * delta * tol)))).astype(np.int64)
    start = np.concatenate([[0], np.cumsum(pieces + 1)[:-1]]).astype(np.int64)
    row = np.repeat(np.arange(len(p)), pieces + 1)
    j = np.arange(len(row)) - start[row]
    U = j * ((u1 - u0) / pieces)[row] + u0[row]
    last = start + pieces
    U[last] = u1
    Q = _parabola_at(a[row], d[row], n[row], P[row], U)
    Q[start], Q[last] = P0, P1
    chords = np.hypot(*np.diff(Q, axis=0).T)
    chords[start[1:] - 1] = 0.0                      # between two edges' points
    longest = np.maximum.reduceat(chords, start) if len(p) else np.zeros(0)
    rounding = 1e-12 * (1.0 + np.maximum(np.abs(P0).max(axis=1), np.abs(P1).max(axis=1)))
    return Q, start, longest ** 2 / (8 * delta) + rounding


def edge_polyline(E: ElementarySites, i: int, j: int, P0, P1, tol: float, *, far=None, centre=None,
                  step: int = 1, sides=None):
    """The polyline of the edge (i, j) from P0 to P1 and its deviation bound from the true arc.

    Straight and parabolic bisectors take finite points (far points already placed on the line for
    infinite ends).  An arc bisector (kind "arc") takes None for an infinite end: it is drawn from
    the finite end along the contact angle in the direction ``step`` (+1: counter-clockwise on the
    arc) until it leaves the disc of radius ``far`` around ``centre``."""
    kind = bisector_kind(E, i, j)
    if kind == "arc":
        return _arc_edge(E, i, j, P0, P1, tol, far, centre, step, sides)
    if kind == "ellipse":
        return ellipse_edge(E, i, j, P0, P1, tol, far, centre, step, sides)
    P0 = np.asarray(P0, float)
    P1 = np.asarray(P1, float)
    scale = 1.0 + float(np.max(np.abs(np.concatenate([P0, P1]))))
    rounding = 1e-12 * scale
    if kind != "parabola":
        return np.array([P0, P1]), rounding
    p, s = (i, j) if E.kind[i] == POINT else (j, i)
    Q, _start, bound = parabola_polylines(E, [p], [s], P0, P1, tol)
    return Q, float(bound[0])


def arc_sides(E: ElementarySites, s: int, other: int, P):
    """(σ, τ) of the arc bisector through the point P: σ = +1 when P is outside the circle of
    arc s, τ the side of P for the other site (its line's side, or its circle's)."""
    P = np.asarray(P, float)
    sigma = 1 if np.hypot(*(P - E.C[s])) > E.rho[s] else -1
    if E.kind[other] == ARC:
        tau = 1 if np.hypot(*(P - E.C[other])) > E.rho[other] else -1
    elif E.kind[other] == POINT:
        tau = 1
    else:
        a, b = E.A[other], E.B[other]
        tau = 1 if (b[0] - a[0]) * (P[1] - a[1]) - (b[1] - a[1]) * (P[0] - a[0]) >= 0 else -1
        # n = perp(b − a)/|b − a| points to the left, so τ = +1 on the left
    return sigma, tau


def arc_range(E: ElementarySites, s: int):
    """(α, β): the start angle of arc s and its counter-clockwise span."""
    c = E.C[s]
    alpha = math.atan2(E.A[s][1] - c[1], E.A[s][0] - c[0])
    beta = (math.atan2(E.B[s][1] - c[1], E.B[s][0] - c[0]) - alpha) % (2 * math.pi)
    return alpha, beta or 2 * math.pi


def _offset(E, s, P, alpha, beta):
    c = E.C[s]
    o = (math.atan2(P[1] - c[1], P[0] - c[0]) - alpha) % (2 * math.pi)
    if o > beta:           # rounding just outside the range: the nearer end
        o = beta if o - beta < 2 * math.pi - o else 0.0
    return o


def _arc_edge(E, i, j, P0, P1, tol, far, centre, step, sides=None):
    s, other = (i, j) if E.kind[i] == ARC else (j, i)
    # the sides from the finite end farthest from the arc's circle: an end at a corner lies on
    # the circle (and on the other site), where the sides are not defined
    ends_ = [np.asarray(P, float) for P in (P0, P1) if P is not None]
    ref = max(ends_, key=lambda P: abs(np.hypot(*(P - E.C[s])) - E.rho[s])) if ends_ else None
    sigma, tau = sides if sides is not None else arc_sides(E, s, other, ref if ref is not None else E.C[s] + 2 * E.rho[s])
    alpha, beta = arc_range(E, s)

    def curve(o):
        V, t = arc_bisector_points(E, s, other, sigma, tau, alpha + np.asarray(o, float))
        return V, t

    ends = []
    for P in (P0, P1):
        ends.append(None if P is None else _offset(E, s, np.asarray(P, float), alpha, beta))
    if ends[0] is None and ends[1] is None:
        o = np.linspace(0, beta, 4097)
        V, t = curve(o)
        ok = np.isfinite(t) & (t > 0) & (np.hypot(*(V - centre).T) < far)
        if not ok.any():
            return np.empty((0, 2)), 0.0
        k = int(np.argmax(ok))
        m = k + int(np.argmin(ok[k:])) if not ok[k:].all() else len(ok)
        ends = [_to_far(curve, o[k], o[k - 1] if k else o[k], far, centre),
                _to_far(curve, o[m - 1], o[m] if m < len(o) else o[m - 1], far, centre)]
    else:
        for k in (0, 1):
            if ends[k] is None:
                o0 = ends[1 - k]
                lim = beta if step > 0 else 0.0
                o = np.linspace(o0, lim, 4097)
                V, t = curve(o)
                bad = ~(np.isfinite(t) & (t > 0) & (np.hypot(*(V - centre).T) < far))
                bad[0] = False
                m = int(np.argmax(bad)) if bad.any() else len(o) - 1
                ends[k] = _to_far(curve, o[m - 1], o[m], far, centre) if bad.any() else o[-1]
    o = refined_parameters(curve, np.linspace(ends[0], ends[1], 33), tol, ends[0] > ends[1], MAX_PIECES)
    V, _t = curve(o)
    if P0 is not None:
        V[0] = P0
    if P1 is not None:
        V[-1] = P1
    Vm, _ = curve((o[:-1] + o[1:]) / 2)
    dev = distances(V[:-1], V[1:], Vm)[0]
    scale = 1.0 + float(np.max(np.abs(V)))
    return V, max(tol, 2 * float(np.max(dev, initial=0.0))) + 1e-12 * scale


def _to_far(curve, o_in, o_out, far, centre):
    """The parameter between o_in (inside the far disc, valid) and o_out (outside or invalid)
    where the curve leaves the far disc, by bisection."""
    for _ in range(60):
        m = (o_in + o_out) / 2
        V, t = curve([m])
        if np.isfinite(t[0]) and t[0] > 0 and np.hypot(*(V[0] - centre)) < far:
            o_in = m
        else:
            o_out = m
    return o_in
