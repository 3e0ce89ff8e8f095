"""Distances, feet and contacts of elliptic-arc pieces, in floats and rigorously with arb.

A piece (:meth:`runtime.sites.elliptic_arc.EllipticArc.pieces`) is e(φ) = c + cos φ M + sin φ N,
φ ∈ [φ₀, φ₁] inside one quadrant of the frame (between two vertices of the ellipse), M ⟂ N.  For a
point q, with w = q − c, A = w·M, B = w·N, a² = |M|², b² = |N|², the squared distance to e(φ) is

    f(φ) = |w|² − 2A cos φ − 2B sin φ + a² cos² φ + b² sin² φ,
    f'(φ) = 2A sin φ − 2B cos φ + (b² − a²) sin 2φ,   f''(φ) = 2A cos φ + 2B sin φ + 2(b² − a²) cos 2φ.

The distance from q to the closed piece is min f^½ over [φ₀, φ₁] (the ellipse's distance where the
foot lies inside the piece, else an end's; thesis ch. 4 for the foot-point equation f' = 0).
Between two vertices the evolute is a convex arc without cusps, so f has at most two critical
points on a piece (a minimum, then a maximum, or the reverse).

* Floats (:func:`piece_distances`): f on 33 parameters per piece, safeguarded Newton steps from
  every sampled local minimum, and the two ends.
* Float bounds (:func:`piece_distance_bounds`): f on a grid, refined where it is lowest, with
  the interpolation remainder max|f''| h²/8 and the rounding written out.
* Balls (:func:`piece_distance_ball`): a lower bound of f over a cover of [φ₀, φ₁] by intervals on
  which f' has a proved sign (f monotone: its value at the near end, a point evaluation) or which
  are tiny intervals around a float critical point (a second-order Taylor form with f'' over the
  interval); the upper bound is f at points of the piece.  The parameter ends are enclosed by
  ``atan2`` of the exact rational frame directions.
* The foot of a box of points (:func:`foot_enclosure`): a one-dimensional parametric Krawczyk test
  on f'/2 = 0: every point of the box has exactly one critical point in the returned interval.
* A contact is a nearest point (:func:`nearest_verdict`): f'' > 0 around the contact (a strict
  local minimum) and f proved above r² on the rest of the piece.

Public API: :class:`PieceData`, :func:`piece_distances`, :func:`piece_distance_bounds`, :func:`piece_feet`,
:func:`piece_distance_ball`, :func:`foot_enclosure`, :func:`nearest_verdict`, :func:`piece_points`,
:func:`piece_lengths`, :func:`piece_at_lengths`, :func:`piece_tangent`, :func:`closest_at_an_end`, :func:`interior_foot`,
:func:`interior_minimum`, :func:`piece_point_ball`.

Length: one piece's distance function f in floats and balls (the ball helpers are private to it);
the construction and the certificate share these as the one implementation of each operation.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from flint import arb

from ..certify.foot import to_arb

__all__ = ["PieceData", "piece_distances", "piece_distance_bounds", "piece_feet", "piece_distance_ball", "foot_enclosure", "nearest_verdict",
           "piece_points", "piece_lengths", "piece_at_lengths", "piece_tangent", "closest_at_an_end", "interior_foot",
           "interior_minimum", "piece_point_ball"]

#: parameters sampled per piece by the float distance
FLOAT_SAMPLES = 33


@dataclass
class PieceData:
    """One piece: exact centre ``c``, axis vectors ``M``, ``N`` and end directions ``ua``, ``ub``
    (rational (cos, sin)); float parameters ``phi0 < phi1``."""

    c: tuple
    M: tuple
    N: tuple
    ua: tuple
    ub: tuple
    phi0: float
    phi1: float

    @classmethod
    def of(cls, arc) -> "PieceData":
        _c, _M, _N, p0, p1 = arc.float_data()
        return cls(arc.c, arc.M, arc.N, arc.ua, arc.ub, p0, p1)

    def floats(self):
        f = float
        return (np.array([f(self.c[0]), f(self.c[1])]), np.array([f(self.M[0]), f(self.M[1])]),
                np.array([f(self.N[0]), f(self.N[1])]))

    def arb_params(self):
        """Enclosures of (φ₀, φ₁): atan2 of the exact start direction, plus the exact span."""
        u0, v0 = to_arb(self.ua[0]), to_arb(self.ua[1])
        p0 = arb.atan2(v0, u0)
        if self.phi0 > 3.0 and p0 < 0:       # atan2's cut at π: the float branch is φ₀ ≈ π
            p0 = p0 + 2 * arb.pi()
        cross = self.ua[0] * self.ub[1] - self.ua[1] * self.ub[0]
        dot = self.ua[0] * self.ub[0] + self.ua[1] * self.ub[1]
        span = arb.atan2(to_arb(cross), to_arb(dot))
        if span < 0:
            span = span + 2 * arb.pi()
        return p0, p0 + span


# ------------------------------------------------------------------------------------- floats
def _f(W2, A, B, a2, b2, phi):
    c, s = np.cos(phi), np.sin(phi)
    return W2 - 2 * A * c - 2 * B * s + a2 * c * c + b2 * s * s


def _coords(P: PieceData, Q):
    c, M, N = P.floats()
    W = np.asarray(Q, float).reshape(-1, 2) - c
    return (np.einsum("ij,ij->i", W, W), W @ M, W @ N, float(M @ M), float(N @ N))


def piece_feet(P: PieceData, Q):
    """(distances, foot parameters) from the rows of Q to the closed piece (floats): f on
    :data:`FLOAT_SAMPLES` parameters, safeguarded Newton steps on f' = 0 from the two lowest sampled
    local minima of each row (f has at most two critical points on a piece, so at most one
    interior local minimum, next to a sampled one), and the two ends."""
    W2, A, B, a2, b2 = _coords(P, Q)
    W2, A, B = W2[:, None], A[:, None], B[:, None]
    grid = np.linspace(P.phi0, P.phi1, FLOAT_SAMPLES)
    h = grid[1] - grid[0]
    F = _f(W2, A, B, a2, b2, grid[None, :])
    rows = np.arange(len(F))
    local = np.ones_like(F, dtype=bool)
    local[:, 1:] &= F[:, 1:] <= F[:, :-1]
    local[:, :-1] &= F[:, :-1] <= F[:, 1:]
    G = np.where(local, F, np.inf)
    k1 = np.argmin(G, axis=1)
    G[rows, k1] = np.inf
    G[rows, np.maximum(k1 - 1, 0)] = np.inf
    G[rows, np.minimum(k1 + 1, FLOAT_SAMPLES - 1)] = np.inf
    k2 = np.where(np.isfinite(G.min(axis=1)), np.argmin(G, axis=1), k1)
    phi = grid[np.column_stack([k1, k2])]
    lo, hi = np.maximum(phi - h, P.phi0), np.minimum(phi + h, P.phi1)
    for _ in range(8):
        c, s = np.cos(phi), np.sin(phi)
        d1 = 2 * A * s - 2 * B * c + (b2 - a2) * 2 * s * c
        d2 = 2 * A * c + 2 * B * s + 2 * (b2 - a2) * (c * c - s * s)
        with np.errstate(divide="ignore", invalid="ignore"):
            step = np.where(d2 > 0, d1 / d2, 0.0)
        phi = np.clip(phi - step, lo, hi)
    Fn = _f(W2, A, B, a2, b2, phi)
    allF = np.concatenate([F[:, [0, -1]], Fn], axis=1)
    allP = np.concatenate([np.broadcast_to(grid[[0, -1]], (len(F), 2)), phi], axis=1)
    k = np.argmin(allF, axis=1)
    best = allF[rows, k]
    return np.sqrt(np.maximum(best, 0.0)), allP[rows, k]


def piece_distances(P: PieceData, Q):
    """Distances from the rows of Q to the closed piece (floats)."""
    return piece_feet(P, Q)[0]


#: float rounding unit
_U = 2.0 ** -53


def _second_derivative_bound(A, B, a2, b2):
    """L₂ ≥ |f''| = |2A cos φ + 2B sin φ + 2(b² − a²) cos 2φ| for every φ (floats, inflated)."""
    return (2 * np.abs(A) + 2 * np.abs(B) + 2 * abs(b2 - a2)) * (1 + 1e-12)


def _interval_lower(F, L2, h):
    """Per row and interval of a grid with steps ≤ h: min of f over the interval ≥ min of its two
    end values − max|f''| h²/8 (the interpolation remainder f''(ξ)/2 (φ − g₀)(φ − g₁))."""
    return np.minimum(F[:, :-1], F[:, 1:]) - (L2 * (h * h / 8))[:, None]


def piece_distance_bounds(P: PieceData, Q):
    """(lo, hi): rigorous float bounds on the distances from the rows of Q to the closed piece.

    f on 65 parameters over [φ₀, φ₁]; then, six times, the run of intervals of each row from the
    first to the last whose bound is below the least value found is cut into 32; every interval's
    minimum is bounded below by its smaller end
    value minus L₂h²/8, L₂ = 2|A| + 2|B| + 2|b² − a²| ≥ |f''|.  The upper bound is the least value
    at the samples (points of the piece; after six cuts they are 10⁻¹¹ of the range apart).  Rounding: the float data c, M, N, the sampled cos/sin and the
    arithmetic move each value of f by at most 64u(‖q‖₁ + ‖c‖₁ + |M| + |N|)², far above the
    γ_n bounds of the few operations; the float range [φ₀, φ₁] is within δ = 16u(1 + |φ₀| + |φ₁|)
    of the exact one (``atan2`` of the rounded directions), where f moves by at most
    L₁δ, L₁ = 2|A| + 2|B| + |b² − a²| ≥ |f'|."""
    Q = np.asarray(Q, float).reshape(-1, 2)
    W2, A, B, a2, b2 = _coords(P, Q)
    W2c, Ac, Bc = W2[:, None], A[:, None], B[:, None]
    c, _M, _N = P.floats()
    L1 = (2 * np.abs(A) + 2 * np.abs(B) + abs(b2 - a2)) * (1 + 1e-12)
    L2 = _second_derivative_bound(A, B, a2, b2)
    size = np.abs(Q).sum(axis=1) + abs(c[0]) + abs(c[1]) + math.sqrt(a2) + math.sqrt(b2)
    err = 64 * _U * size * size + L1 * 16 * _U * (1 + abs(P.phi0) + abs(P.phi1))
    grid = np.linspace(P.phi0, P.phi1, 65)
    h = float(np.max(np.diff(grid))) * (1 + 1e-12)
    F = _f(W2c, Ac, Bc, a2, b2, grid[None, :])
    G = np.broadcast_to(grid, F.shape)
    lb = _interval_lower(F, L2, np.full(len(Q), h))
    best = F.min(axis=1)
    rows = np.arange(len(Q))[:, None]
    for _level in range(6):
        # the run of intervals from the first to the last whose bound is below the least value
        # found, cut in 32: the others hold no value below it, and the run holds the sample
        # that attains it, so the minimum over the piece is the minimum over the run
        below = lb < best[:, None]
        none = ~below.any(axis=1)
        first = np.where(none, np.argmin(lb, axis=1), np.argmax(below, axis=1))
        last = np.where(none, first, lb.shape[1] - 1 - np.argmax(below[:, ::-1], axis=1))
        G = np.linspace(G[rows[:, 0], first], G[rows[:, 0], last + 1], 33, axis=1)          # ends exact
        hs = np.max(np.diff(G, axis=1), axis=1) * (1 + 1e-12)
        F = _f(W2c, Ac, Bc, a2, b2, G)
        best = np.minimum(best, F.min(axis=1))
        lb = _interval_lower(F, L2, hs)
    low = lb.min(axis=1) - err
    lo = np.sqrt(np.maximum(low, 0.0)) * (1 - 4 * _U)
    hi = np.sqrt(np.maximum(best + err, 0.0)) * (1 + 4 * _U)
    return lo, hi


def piece_points(P: PieceData, phi):
    """The points e(φ) (floats, (k, 2))."""
    c, M, N = P.floats()
    phi = np.asarray(phi, float)
    return c + np.cos(phi)[:, None] * M + np.sin(phi)[:, None] * N


def piece_lengths(P: PieceData, n: int = 64):
    """(cumulative arc lengths at ``n + 1`` equally spaced parameters, those parameters)."""
    phi = np.linspace(P.phi0, P.phi1, n + 1)
    X = piece_points(P, phi)
    return np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(X, axis=0).T))]), phi


# ---------------------------------------------------------------------------------------- arb
class _Balls:
    """A, B, |w|², a², b² of a box of points (arb) for one piece."""

    def __init__(self, P: PieceData, x: arb, y: arb):
        wx, wy = x - to_arb(P.c[0]), y - to_arb(P.c[1])
        Mx, My, Nx, Ny = (to_arb(v) for v in (*P.M, *P.N))
        self.W2 = (wx * wx).nonnegative_part() + (wy * wy).nonnegative_part()
        self.A, self.B = wx * Mx + wy * My, wx * Nx + wy * Ny
        self.a2, self.b2 = Mx * Mx + My * My, Nx * Nx + Ny * Ny

    def f(self, phi: arb) -> arb:
        c, s = phi.cos(), phi.sin()
        return self.W2 - 2 * self.A * c - 2 * self.B * s + self.a2 * c * c + self.b2 * s * s

    def g(self, phi: arb) -> arb:             # f'/2
        c, s = phi.cos(), phi.sin()
        return self.A * s - self.B * c + (self.b2 - self.a2) * s * c

    def dg(self, phi: arb) -> arb:            # f''/2
        c, s = phi.cos(), phi.sin()
        return self.A * c + self.B * s + (self.b2 - self.a2) * (c * c - s * s)


#: halvings of a piece's parameter range in the monotonicity test of :func:`closest_at_an_end`,
#: and in its cover by monotone and concave parts (:func:`_end_by_cover`)
MONOTONE_DEPTH = 4
COVER_DEPTH = 5


def _hull(lo: arb, hi: arb) -> arb:
    return lo.lower().union(hi.upper())


def _g_over(S: _Balls, lo: arb, hi: arb, I: arb) -> arb:
    """f'/2 over I = [lo, hi]: the natural extension intersected with the mean-value forms
    centred at both ends (sharp next to a critical point, where the sign is decided)."""
    d = S.g(I)
    slope = S.dg(I)
    w = arb(0).union(hi - lo)
    for cand in (S.g(lo) + slope * w, S.g(hi) - slope * w):
        if cand.overlaps(d):
            d = d.intersection(cand)
    return d


def _lower_f(S: _Balls, lo: arb, hi: arb, crit, depth: int = 0) -> arb:
    """A lower bound (a ball's lower end) of f over φ ∈ [lo, hi] (exact arb points)."""
    I = _hull(lo, hi)
    d = _g_over(S, lo, hi, I)
    if d > 0:
        return S.f(lo).lower()
    if d < 0:
        return S.f(hi).lower()
    w = float((hi - lo).upper())
    if depth >= 14 or w < 1e-9 or any(float(lo.mid()) <= c <= float(hi.mid()) for c in crit) and w < 1e-5:
        m = arb((float(lo.mid()) + float(hi.mid())) / 2)
        h = I - m
        hh = (h * h).nonnegative_part()
        return (S.f(m) + 2 * S.g(m) * h + S.dg(I) * hh).lower()
    inner = [c for c in crit if float(lo.mid()) + 2e-6 < c < float(hi.mid()) - 2e-6]
    cuts = sorted({x for c in inner for x in (c - 1e-6, c + 1e-6)}) if inner else [(float(lo.mid()) + float(hi.mid())) / 2]
    pts = [lo] + [arb(x) for x in cuts] + [hi]
    out = None
    for a, b in zip(pts, pts[1:]):
        v = _lower_f(S, a, b, crit, depth + 1)
        out = v if out is None or v < out else out
    return out


def _critical_floats(P: PieceData, x: float, y: float) -> list:
    """Float critical points of f on the piece for the point (x, y) (sign changes of f', refined)."""
    W2, A, B, a2, b2 = (float(v[0]) if np.ndim(v) else float(v) for v in _coords(P, [[x, y]]))
    # the uniform grid, refined geometrically towards both ends: a minimum and a maximum of f
    # close to an end (a foot about to leave the piece there) fall in different cells
    span = P.phi1 - P.phi0
    near = span * 0.5 ** np.arange(6, 30)
    grid = np.unique(np.concatenate([np.linspace(P.phi0, P.phi1, FLOAT_SAMPLES), P.phi0 + near, P.phi1 - near]))

    def d1(p):
        return 2 * A * np.sin(p) - 2 * B * np.cos(p) + (b2 - a2) * np.sin(2 * p)
    vals = d1(grid)
    zero = grid[vals == 0].tolist()
    k = np.nonzero(vals[:-1] * vals[1:] < 0)[0]
    lo, hi, flo = grid[k], grid[k + 1], vals[k]
    for _ in range(60):                 # bisection on all sign changes at once
        m = (lo + hi) / 2
        fm = d1(m)
        left = fm * flo > 0
        lo, flo = np.where(left, m, lo), np.where(left, fm, flo)
        hi = np.where(left, hi, m)
    return sorted(zero + ((lo + hi) / 2).tolist())


def interior_foot(P: PieceData, x: float, y: float) -> float | None:
    """The parameter of the nearest interior local minimum of f (a foot inside the open piece),
    None when f has none (floats)."""
    W2, A, B, a2, b2 = (float(v[0]) if np.ndim(v) else float(v) for v in _coords(P, [[x, y]]))
    best = None
    for c in _critical_floats(P, x, y):
        if not P.phi0 < c < P.phi1:
            continue
        if 2 * A * math.cos(c) + 2 * B * math.sin(c) + 2 * (b2 - a2) * math.cos(2 * c) <= 0:
            continue
        val = float(_f(W2, A, B, a2, b2, c))
        if best is None or val < best[0]:
            best = (val, c)
    return None if best is None else best[1]


def piece_distance_ball(P: PieceData, x: arb, y: arb) -> arb:
    """An arb ball holding the distance from every point of the box (x, y) to the closed piece."""
    S = _Balls(P, x, y)
    p0, p1 = P.arb_params()
    lo, hi = arb(p0.lower()), arb(p1.upper())
    crit = _critical_floats(P, float(x.mid()), float(y.mid()))
    low = _lower_f(S, lo, hi, crit)
    # upper bound: f at points of the piece (the exact ends, interior float parameters)
    ends = [to_arb(P.ua[0]), to_arb(P.ua[1])], [to_arb(P.ub[0]), to_arb(P.ub[1])]
    ups = []
    for u, v in ends:
        ups.append(S.W2 - 2 * S.A * u - 2 * S.B * v + S.a2 * u * u + S.b2 * v * v)
    span = P.phi1 - P.phi0
    for c in crit:
        if P.phi0 + 1e-9 * span < c < P.phi1 - 1e-9 * span:
            ups.append(S.f(arb(c)))
    up = None
    for u in ups:
        up = u.upper() if up is None or u.upper() < up else up
    low = low if low > 0 else arb(0)
    return low.sqrt().union(up.sqrt())


def foot_enclosure(P: PieceData, x: arb, y: arb, phi: float):
    """An interval Φ around ``phi`` in which f'(φ) = 0 has exactly one root for every point of
    the box (x, y) (parametric Krawczyk on f'/2), or None."""
    S = _Balls(P, x, y)
    # float Newton steps at the box's centre first: the test's box is then a few ulps wide
    W2, A, B, a2, b2 = (float(v[0]) if np.ndim(v) else float(v) for v in _coords(P, [[float(x.mid()), float(y.mid())]]))
    for _ in range(4):
        c, s = math.cos(phi), math.sin(phi)
        d2 = A * c + B * s + (b2 - a2) * (c * c - s * s)
        if d2 == 0 or not math.isfinite(d2):
            break
        phi = phi - (A * s - B * c + (b2 - a2) * s * c) / d2
    m = arb(phi)
    dgm = S.dg(m)
    if not (dgm > 0 or dgm < 0):
        return None
    Y = arb(1.0 / float(dgm.mid()))
    gm = S.g(m)
    r = max(4 * abs(float((Y * gm).mid())) + float((Y * gm).rad()) * 4, 1e-30 * (1 + abs(phi)))
    for _ in range(12):
        X = m + arb(0, r)
        K = m - Y * gm + (1 - Y * S.dg(X)) * (X - m)
        if K.is_finite() and K.lower() > X.lower() and K.upper() < X.upper():
            return K
        r = max(2 * float(abs(K - m).upper()) if K.is_finite() else 4 * r, 2 * r)
        if r > 1e-2:
            return None
    return None


def interior_minimum(P: PieceData, x: arb, y: arb, phi: float):
    """The enclosure Φ of :func:`foot_enclosure` when it lies strictly inside the piece's open
    parameter range and f'' > 0 on it (for every point of the box (x, y), a strict local minimum
    of f inside the piece, the only one: f has at most two critical points on a piece), else None."""
    Phi = foot_enclosure(P, x, y, phi)
    if Phi is None:
        return None
    p0, p1 = P.arb_params()
    if not (Phi > p0 and Phi < p1 and _Balls(P, x, y).dg(Phi) > 0):
        return None
    return Phi


def piece_point_ball(P: PieceData, Phi: arb):
    """Balls holding the points e(φ) = c + cos φ M + sin φ N for φ in Φ."""
    c, s = Phi.cos(), Phi.sin()
    return (to_arb(P.c[0]) + c * to_arb(P.M[0]) + s * to_arb(P.N[0]),
            to_arb(P.c[1]) + c * to_arb(P.M[1]) + s * to_arb(P.N[1]))


def nearest_verdict(P: PieceData, x: arb, y: arb, r: arb, Phi: arb, tied_ends=()):
    """True when, for every point of the box (x, y), the piece has no point strictly nearer than
    the critical point enclosed by ``Phi`` at squared distance r²: f'' > 0 on a neighbourhood of
    Φ (a strict local minimum) and f > r² on the rest of the piece, except that an end listed in
    ``tied_ends`` (0: start, 1: end; a point site at distance exactly r) may tie, f increasing
    away from it.  False when the critical point is a strict local maximum or a point of the
    piece is proved nearer; None otherwise."""
    S = _Balls(P, x, y)
    r2 = (r * r).nonnegative_part()
    p0, p1 = P.arb_params()
    if S.dg(Phi) < 0:
        return False
    span = P.phi1 - P.phi0
    delta = 1e-6 * span
    nlo = Phi.lower() - arb(delta)
    nhi = Phi.upper() + arb(delta)
    nlo = nlo if nlo > p0 else arb(p0.lower())
    nhi = nhi if nhi < p1 else arb(p1.upper())
    if not S.dg(_hull(nlo, nhi)) > 0:
        return None
    lo, hi = arb(p0.lower()), arb(p1.upper())
    # a tied end: f increasing away from it on a proved stretch, which is then left out
    for end in tied_ends:
        for frac in (1e-2, 1e-4, 1e-6, 1e-8):
            w = arb(frac * span)
            if end == 0 and float(lo.mid()) + frac * span < float(nlo.mid()):
                if _g_over(S, lo, lo + w, _hull(lo, lo + w)) > 0:
                    lo = lo + w
                    break
            if end == 1 and float(hi.mid()) - frac * span > float(nhi.mid()):
                if _g_over(S, hi - w, hi, _hull(hi - w, hi)) < 0:
                    hi = hi - w
                    break
    crit = _critical_floats(P, float(x.mid()), float(y.mid()))
    far = [c for c in crit if not float(nlo.mid()) <= c <= float(nhi.mid())]
    verdict = True
    for a, b in ((lo, nlo), (nhi, hi)):
        if not float(b.mid()) > float(a.mid()):
            continue
        low = _lower_f(S, a, b, far)
        if low > r2.upper():
            continue
        # a proved nearer point: an interior float critical point, evaluated
        for c in far:
            if float(a.mid()) < c < float(b.mid()) and S.f(arb(c)) < r2:
                return False
        verdict = None
    return verdict


def piece_at_lengths(P: PieceData, frac=None, from_end: int | None = None, dist=None):
    """Points of the piece at arc-length fractions ``frac`` ∈ [0, 1] from its start, or at arc
    lengths ``dist`` from its end ``from_end`` (0: start, 1: end); floats (k, 2)."""
    cum, phi = piece_lengths(P, 256)
    L = cum[-1]
    if frac is not None:
        s = np.asarray(frac, float) * L
    else:
        d = np.clip(np.asarray(dist, float), 0.0, L)
        s = d if from_end == 0 else L - d
    return piece_points(P, np.interp(s, cum, phi))


def piece_tangent(P: PieceData, end: int) -> np.ndarray:
    """The unit tangent leaving the piece's start (``end`` = 0) or end (1) into the piece (floats)."""
    _c, M, N = P.floats()
    phi = P.phi0 if end == 0 else P.phi1
    t = -math.sin(phi) * M + math.cos(phi) * N
    t = t if end == 0 else -t
    return t / max(float(np.hypot(*t)), 1e-300)


def _monotone_sign(S: _Balls, lo: arb, hi: arb, depth: int = 0) -> int:
    """+1 or −1 when f'/2 has that strict sign on every part of a cover of [lo, hi] (halved up to
    MONOTONE_DEPTH times where undecided), then f is strictly monotone on [lo, hi]; 0 otherwise.
    One evaluation over a whole piece is loose for a box of points a few 10⁻³ wide, where the
    halves decide."""
    d = _g_over(S, lo, hi, _hull(lo, hi))
    if d > 0:
        return 1
    if d < 0:
        return -1
    if depth >= MONOTONE_DEPTH:
        return 0
    m = arb((float(lo.mid()) + float(hi.mid())) / 2)
    first = _monotone_sign(S, lo, m, depth + 1)
    if first == 0:
        return 0
    return first if _monotone_sign(S, m, hi, depth + 1) == first else 0


def closest_at_an_end(P: PieceData, x: arb, y: arb):
    """The ends proved to hold, for every point of the box (x, y), the nearest points of the closed
    piece: (0,) or (1,) when f is monotone on the piece, or increasing away from that end on a
    neighbourhood and above that end's value on the rest; (0, 1) when f increases away from both
    ends near them and stays above both ends' values in between; None when not proved."""
    S = _Balls(P, x, y)
    p0, p1 = P.arb_params()
    lo, hi = arb(p0.lower()), arb(p1.upper())
    d = _monotone_sign(S, lo, hi)
    if d > 0:
        return (0,)
    if d < 0:
        return (1,)
    delta = arb(0.05 * (P.phi1 - P.phi0))
    crit = _critical_floats(P, float(x.mid()), float(y.mid()))
    fe = []
    for u, v in (P.ua, P.ub):
        u, v = to_arb(u), to_arb(v)
        fe.append(S.W2 - 2 * S.A * u - 2 * S.B * v + S.a2 * u * u + S.b2 * v * v)
    rising = [_g_over(S, lo, lo + delta, _hull(lo, lo + delta)) > 0,
              _g_over(S, hi - delta, hi, _hull(hi - delta, hi)) < 0]
    for end, rest in ((0, (lo + delta, hi)), (1, (lo, hi - delta))):
        if rising[end] and _lower_f(S, rest[0], rest[1], crit) > fe[end].upper():
            return (end,)
    if all(rising):
        top = fe[0].upper() if fe[0].upper() > fe[1].upper() else fe[1].upper()
        if _lower_f(S, lo + delta, hi - delta, crit) > top:
            return (0, 1)
    return _end_by_cover(S, P, lo, hi)


def _end_by_cover(S: _Balls, P: PieceData, lo: arb, hi: arb):
    """(0,) or (1,) from a cover of [lo, hi] by parts where f is increasing (f' > 0), decreasing
    (f' < 0) or concave (f'' < 0): on each part f is smallest at an end of the part (the left one,
    the right one, one of both), so when the part at the chosen end is monotone into it and f at
    each other part's candidate ends exceeds f at the chosen end, that end is the unique nearest
    point (a concave part at that end: its other end is compared too, f being strictly concave
    from the exact end on).  The comparisons are differences f(φ) − f(end), linear in the box's point with the
    small factor e(φ) − e(end): a box a few 10⁻² wide still decides ends whose values differ by
    less than the spread of f itself over the box (which :func:`_lower_f` against an end's ball
    needs).  None when not proved (an interior minimum, or parts undecided after COVER_DEPTH
    halvings)."""
    parts = []

    def cover(a: arb, b: arb, depth: int) -> bool:
        I = _hull(a, b)
        g = _g_over(S, a, b, I)
        if g > 0 or g < 0:
            parts.append((a, b, 1 if g > 0 else -1))
            return True
        if S.dg(I) < 0:
            parts.append((a, b, 0))
            return True
        if depth >= COVER_DEPTH:
            return False
        m = arb((float(a.mid()) + float(b.mid())) / 2)
        return cover(a, m, depth + 1) and cover(m, b, depth + 1)
    if not cover(lo, hi, 0):
        return None

    def above(phi: arb, cs) -> bool:            # f(φ) − f(end) > 0
        c, s = phi.cos(), phi.sin()
        ce, se = (to_arb(v) for v in cs)
        return (-2 * S.A * (c - ce) - 2 * S.B * (s - se) + S.a2 * (c * c - ce * ce)
                + S.b2 * (s * s - se * se)) > 0
    for which, into, others, cs in ((1, -1, parts[:-1], P.ub), (0, 1, parts[1:], P.ua)):
        a, b, lab = parts[-1 if which else 0]
        if lab not in (into, 0):
            continue
        # a concave part at the end: f > min(f(end), f(its other end)) inside it (strictly concave
        # on the part from the exact end on), so its other end is a candidate too
        pts = [] if lab == into else [a if which else b]
        pts += [x for a, b, lab in others for x in ((a,) if lab > 0 else (b,) if lab < 0 else (a, b))]
        if all(above(x, cs) for x in pts):
            return (which,)
    return None
