"""Bisectors of an elliptic-arc piece and another elementary site, drawn by the foot parameter.

A point v of the bisector of an elliptic piece s (:mod:`runtime.segments.ellipse_pieces`) and a
site o, whose nearest point on s is the interior point e(φ), lies on the normal of s at e(φ):
v = e(φ) + σ t n(φ) with n the outer unit normal, σ = ±1 the side and t = d(v, o) the common
distance (thesis ch. 4: the bisector is where the offsets of s and o at distance t meet).  For a
fixed φ, h(t) = d(e(φ) + σ t n(φ), o) − t is non-increasing (a distance is 1-Lipschitz), so its
root is unique where it exists and is found by bisection.  The edge is the image of the foot
parameters between those of its two vertices, sampled until the estimate of every chord's linear
interpolation error Δφ²/8 · max|γ''| is within half the tolerance
(:func:`runtime.segments.polyline_refinement.interpolation_parameters`); the stated tolerance is
at least twice the largest estimate (where the refinement stops early, a larger tolerance, never
a smaller one).  That is the bound the certificate proves for these edges with interval jets
(:mod:`runtime.segments.certificate_ellipse_edges`); a chord refined by its middle point's
deviation alone can miss it a hundredfold where the point runs fast along a nearly straight
bisector (an end vertex far out, t(φ) steep).

The edge of a piece and its own end point site is the normal line at the end up to the centre of
curvature there, then such a curve (:func:`perpendicular_edge`).

Public API: :func:`ellipse_edge`, :func:`ellipse_step`, :func:`ellipse_bisector_points`,
:func:`perpendicular_edge`, :func:`interior_or_end`, :func:`beyond_curvature`.
"""
from __future__ import annotations

import numpy as np

from .distance import clearance, distances, site_distances
from .elementary import ELLIPSE, POINT, ElementarySites
from .ellipse_pieces import interior_foot, piece_feet, piece_points
from .polyline_refinement import interpolation_parameters

__all__ = ["ellipse_edge", "ellipse_step", "ellipse_bisector_points", "perpendicular_edge", "interior_or_end", "beyond_curvature"]

#: most pieces of one drawn edge
MAX_PIECES = 4096


def _normals(E: ElementarySites, s: int, phi):
    """Outer unit normals of piece s at parameters phi (floats, (k, 2))."""
    _c, M, N = E.ellipse[s].floats()
    phi = np.asarray(phi, float)
    T = -np.sin(phi)[:, None] * M + np.cos(phi)[:, None] * N
    n = np.column_stack([T[:, 1], -T[:, 0]])          # counter-clockwise curve: outer normal
    return n / np.hypot(*n.T)[:, None]


def ellipse_bisector_points(E: ElementarySites, s: int, other: int, sigma: int, phi, tmax: float):
    """Points v(φ) of the bisector of piece s and site ``other`` on side σ and their distances t
    (NaN where no root lies in (0, tmax])."""
    phi = np.asarray(phi, float)
    e = piece_points(E.ellipse[s], phi)
    n = sigma * _normals(E, s, phi)
    k = len(phi)
    if E.kind[other] == POINT:
        # |e + t n − p|² = t²: t = |e − p|² / (2 n·(p − e)), a root where positive
        w = E.A[other] - e
        den = 2 * np.einsum("ij,ij->i", n, w)
        with np.errstate(divide="ignore", invalid="ignore"):
            t = np.einsum("ij,ij->i", w, w) / den
        t = np.where((den > 0) & (t <= tmax), t, np.nan)
        return e + np.nan_to_num(t)[:, None] * n, t
    lo, hi = np.zeros(k), np.full(k, float(tmax))
    h_hi = site_distances(E, np.full(k, other), e + hi[:, None] * n) - hi
    ok = h_hi <= 0
    for _ in range(56):
        m = (lo + hi) / 2
        h = site_distances(E, np.full(k, other), e + m[:, None] * n) - m
        pos = h > 0
        lo = np.where(pos, m, lo)
        hi = np.where(pos, hi, m)
    t = np.where(ok, (lo + hi) / 2, np.nan)
    return e + np.nan_to_num(t)[:, None] * n, t


def _side_and_foot(E: ElementarySites, s: int, P):
    """(σ, foot parameter, distance) of the point P for piece s: the foot is an interior nearest
    point when there is one (at a vertex tied with an end both are nearest: the interior contact
    is the edge's)."""
    P = np.asarray(P, float)
    phi = np.array([interior_or_end(E, s, P)])
    e = piece_points(E.ellipse[s], phi)[0]
    n = _normals(E, s, phi)[0]
    return (1 if float(np.dot(P - e, n)) >= 0 else -1), float(phi[0]), float(np.hypot(*(P - e)))


def _pick(E: ElementarySites, i: int, j: int):
    return (i, j) if E.kind[i] == ELLIPSE else (j, i)


def ellipse_step(E: ElementarySites, i: int, j: int, base, far: float):
    """(step, σ): the way along the foot parameter (+1 increasing) and the side of the bisector
    of i and j leaving its finite vertex ``base`` on which i and j stay the nearest sites."""
    s, other = _pick(E, i, j)
    sigma0, phi0, dist0 = _side_and_foot(E, s, base)
    P = E.ellipse[s]
    span = P.phi1 - P.phi0
    best, out = None, (1, sigma0)
    for sigma in ((sigma0, -sigma0) if dist0 < 1e-12 * (1 + far) else (sigma0,)):
        for st in (1, -1):
            ph = phi0 + st * 1e-4 * span
            if not P.phi0 <= ph <= P.phi1:
                continue
            V, t = ellipse_bisector_points(E, s, other, sigma, np.array([ph]), 4 * far)
            if not (np.isfinite(t[0]) and t[0] > 0):
                continue
            margin = clearance(site_distances(E, np.arange(len(E)), np.repeat(V, len(E), axis=0)), i, j)
            if best is None or margin > best:
                best, out = margin, (st, sigma)
    return out


def ellipse_edge(E: ElementarySites, i: int, j: int, P0, P1, tol: float, far: float, centre, step: int = 1,
                 sigma: int | None = None):
    """The polyline of the edge (i, j) of an elliptic piece and another site from P0 to P1 (None:
    an infinite end, drawn along ``step`` until the curve leaves the disc of radius ``far`` around
    ``centre``, or the piece ends) and its measured deviation."""
    s, other = _pick(E, i, j)
    P = E.ellipse[s]
    centre = np.asarray(centre, float)
    ends = [None if Q is None else np.asarray(Q, float) for Q in (P0, P1)]
    known = [Q for Q in ends if Q is not None]
    if not known:
        return np.empty((0, 2)), 0.0
    feet = [None if Q is None else _side_and_foot(E, s, Q) for Q in ends]
    if sigma is None:
        # the side from the end farther from the piece (an end at a corner lies on the piece)
        sigma = max((f for f in feet if f is not None), key=lambda f: f[2])[0]
    tmax = 4 * far

    def curve(o):
        return ellipse_bisector_points(E, s, other, sigma, np.asarray(o, float), tmax)

    par = [None if f is None else f[1] for f in feet]
    for k in (0, 1):
        if par[k] is None:
            lim = P.phi1 if step > 0 else P.phi0
            o = np.linspace(par[1 - k], lim, 257)
            V, t = curve(o)
            bad = ~(np.isfinite(t) & (t > 0) & (np.hypot(*(V - centre).T) < far))
            bad[0] = False
            par[k] = o[int(np.argmax(bad)) - 1] if bad.any() else o[-1]
    o, est = interpolation_parameters(curve, np.linspace(par[0], par[1], 33), tol, par[0] > par[1], MAX_PIECES)
    V, _t = curve(o)
    for k, Q in ((0, ends[0]), (-1, ends[1])):
        if Q is not None:
            V[k] = Q
    Vm, _ = curve((o[:-1] + o[1:]) / 2)
    dev = distances(V[:-1], V[1:], Vm)[0]
    stated = max(tol, 2 * est, 2 * float(np.nanmax(dev, initial=0.0)))
    return V, stated + 1e-12 * (1.0 + float(np.max(np.abs(V))))


def perpendicular_edge(E: ElementarySites, i: int, j: int, P0, P1, tol: float, far: float):
    """The edge of an elliptic piece s and its end point site p: the normal line of s at p from
    outside through p to the centre of curvature K of s at p (there p is the nearest point of s),
    then the curve of points equidistant from p and an interior foot of s (beyond K the end is a
    local maximum of the distance along the ellipse).  An infinite end (None) is on the outer
    side, at distance ``far`` from p."""
    p, s = (i, j) if E.kind[j] == ELLIPSE else (j, i)
    P = E.ellipse[s]
    at_start = int(E.ends[s, 0]) == p
    phi_e = P.phi0 if at_start else P.phi1
    e = E.A[p]
    n = _normals(E, s, np.array([phi_e]))[0]
    _c, M, N = P.floats()
    a, b = float(np.hypot(*M)), float(np.hypot(*N))
    rho = (a * a * np.sin(phi_e) ** 2 + b * b * np.cos(phi_e) ** 2) ** 1.5 / (a * b)
    K = e - rho * n
    ends = [e + far * n if Q is None else np.asarray(Q, float) for Q in (P0, P1)]
    beyond = [float(np.dot(e - Q, n)) > rho * (1 + 1e-9) for Q in ends]

    sags = [0.0]

    def curve(o):
        """The curve's points at the feet o; K at the foot p itself (where t = |w|²/(2 n·w) is 0/0)."""
        V, t = ellipse_bisector_points(E, s, p, -1, o, 4 * far + 4 * rho)
        at = np.asarray(o) == phi_e
        V[at], t[at] = K, rho
        return V, t

    def curve_to(Q):
        """Points of the curve from K (foot at p) to the point Q beyond K."""
        phi_q = interior_or_end(E, s, Q)
        if phi_q == phi_e:
            # no interior foot ties with p at Q: the foot reached the piece's other end (Q is a
            # vertex with that end point, equidistant from both ends and on the normal at the other)
            phi_q = P.phi1 if at_start else P.phi0
        o, est = interpolation_parameters(curve, np.linspace(phi_e, phi_q, 33), tol, phi_q < phi_e, MAX_PIECES,
                                          rounds=12)
        sags.append(est)
        V, _t = curve(o)
        V[-1] = Q
        return V

    if not any(beyond):
        return np.array(ends), 1e-12 * (1.0 + float(np.max(np.abs(ends))))
    if all(beyond):
        A_, B_ = curve_to(ends[0]), curve_to(ends[1])
        V = np.concatenate([A_[::-1], B_[1:]])
    elif beyond[0]:
        V = np.concatenate([curve_to(ends[0])[::-1], [ends[1]]])
    else:
        V = np.concatenate([[ends[0]], curve_to(ends[1])])
    return V, max(tol, 2 * max(sags)) + 1e-12 * (1.0 + float(np.max(np.abs(V))))


def interior_or_end(E: ElementarySites, s: int, Q) -> float:
    """The foot parameter on piece s of Q: an interior local minimum that is a nearest point of the
    closed piece (to 10⁻⁹), else the nearest point of the closed piece."""
    d, phi = piece_feet(E.ellipse[s], np.asarray(Q, float)[None, :])
    inner = interior_foot(E.ellipse[s], float(Q[0]), float(Q[1]))
    if inner is not None:
        di = float(np.hypot(*(piece_points(E.ellipse[s], [inner])[0] - np.asarray(Q, float))))
        if di <= float(d[0]) * (1 + 1e-9) + 1e-12:
            return inner
    return float(phi[0])


def beyond_curvature(E: ElementarySites, i: int, j: int, V) -> np.ndarray:
    """The part of the polyline V of a "perpendicular" or "joint" edge (i, j) whose points have
    two nearest points on the sites: for an elliptic piece, the points beyond its centre of
    curvature K at the end or joint (cut exactly at K); empty for other sites (there the end is
    the single nearest point all along the edge)."""
    V = np.asarray(V, float)
    s = i if E.kind[i] == ELLIPSE else j if E.kind[j] == ELLIPSE else None
    if s is None:
        return V[:0]
    o = j if s == i else i
    if E.kind[o] != ELLIPSE and o < E.n_points:
        code = o                                   # the end point site
    else:
        common = {int(v) for v in E.ends[s]} & {int(v) for v in E.ends[o]}
        if not common:
            return V[:0]
        code = common.pop()
    P = E.ellipse[s]
    phi_e = P.phi0 if int(E.ends[s, 0]) == code else P.phi1
    e = np.array([float(v) for v in E.xy[code]])
    n = _normals(E, s, np.array([phi_e]))[0]
    _c, M, N = P.floats()
    a, b = float(np.hypot(*M)), float(np.hypot(*N))
    rho = (a * a * np.sin(phi_e) ** 2 + b * b * np.cos(phi_e) ** 2) ** 1.5 / (a * b)
    depth = (e - V) @ n - rho
    keep = depth > 0
    if not keep.any():
        return V[:0]
    out = []
    for k in range(len(V)):
        if k and keep[k] != keep[k - 1]:           # the crossing of K, interpolated
            w = depth[k - 1] / (depth[k - 1] - depth[k])
            out.append(V[k - 1] + w * (V[k] - V[k - 1]))
        if keep[k]:
            out.append(V[k])
    return np.array(out)
