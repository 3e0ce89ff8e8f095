"""Float foot points of a point on a canonical conic, vectorised over many points (thesis §5.2).

The distance d(q, C) = min over p ∈ C of |q − p| decides the Voronoi diagram (thesis §4.1, §5.1);
its critical points, the foot points, are the points p of C where q − p is normal to C (thesis
§5.2, the normal condition behind Thm 5.2.2).  This module computes the *closest* foot point
(per branch for the hyperbola) in the canonical frame of :mod:`runtime.sites.conic`: ellipse
X²/a² + Y²/b² = 1 (a ≥ b), hyperbola X²/a² − Y²/b² = 1, parabola Y² = 2pX.

By the symmetries of the canonical forms the closest point of q = (u, v) (u, v ≥ 0 after
reflection) lies in the closed quadrant of q; in the natural parameter there it is the unique
sign change of the derivative of the squared distance (the normal condition):

* ellipse (a cos t, b sin t), t ∈ [0, π/2]: D'(t)/2 = (b² − a²) sin t cos t + a u sin t − b v cos t
  (solved in τ = tan(t/2) ∈ [0, 1], where (1 + τ²)² D'/2 is a quartic polynomial);
* hyperbola (a cosh t, b sinh t), t ∈ [0, T]: D'(t)/2 = (a² + b²) sinh t cosh t − a u sinh t − b v cosh t,
  with T = asinh((a|u| + b v)/(a² + b²)) (then D'(T) ≥ 0; solved in w = e^t, where 4w² D'/2 is a
  quartic polynomial);
* parabola (s²/2p, s), s ∈ [0, S]: s³ + 2p(p − u) s − 2p² v, S = max((4p²v)^(1/3), (4p|p − u|)^(1/2)).

Uniqueness follows from the Lagrange form q − p = λ ∇g(p)/2: in the open quadrant the
constraint becomes a strictly monotone function of λ.  The sign change is found to float
resolution by Newton's method safeguarded by bisection (``rtsafe``, Press et al., *Numerical
Recipes*, 3rd ed., §9.4), run on all query points at once (numpy, converged points leave the
active set; Python floats for a handful of points): about six polynomial evaluations per point
instead of 64 halvings.  Where the polynomial vanishes within rounding without a confirmed
sign change (on the axes, near the evolute, where plain Newton fails) plain bisection of the
full bracket decides.  The point is then evaluated from the parameter, so it lies on the curve
to rounding.  Rigorous distance bounds built on these points
(:mod:`runtime.voronoi.conic_geometry`, :mod:`runtime.sites.distance_ball`) hold for any
accuracy of the root; the accuracy only decides their tightness.

Every critical point (up to four, inside the evolute) is listed by :func:`canonical_foot_points`
with the same normal conditions and root finder, on each arc of the curve (quadrant of the
ellipse, half-branch of the hyperbola, half of the parabola) split where the derivative of the
polynomial vanishes, so that each piece holds at most one sign change.

Length: the closest-foot solvers and the list of all critical points share the safeguarded root
finder (scalar and vector forms) and the normal-condition polynomials; one module per
mathematical operation (the foot points of a conic).
"""
from __future__ import annotations

import math

import numpy as np

from ..result import InvalidConicError

__all__ = ["canonical_foot_points", "closest_feet", "ellipse_feet", "ellipse_foot_points", "feet_to_world",
           "hyperbola_branch_feet", "hyperbola_feet", "parabola_feet"]

#: unit roundoff of IEEE double precision
EPS = 2.0 ** -53
#: iteration cap of the safeguarded Newton iteration (a bisection at least every other step)
_MAX_IT = 160
#: bisection halvings of the fallback (the bracket shrinks to float resolution)
_BISECT = 64
#: below this many query points the root finding runs on Python floats (numpy's per-call overhead)
_SCALAR_MAX = 16
#: a Newton step smaller than this (relative) ends the iteration: the error after it is of
#: the order of its square
_NEWTON_TOL = 2.0 ** -30


def _root_scalar(fdf, lo: float, hi: float, x: float) -> float:
    """The sign change of f in [lo, hi] (f(lo) ≤ 0 ≤ f(hi), f < 0 just right of lo) to float
    resolution.  ``fdf(x)`` returns (f, f', m) with m a bound on the magnitudes of the terms
    of f (so |f| ≤ 16 ε m means f = 0 within rounding).

    Newton's method safeguarded by bisection (``rtsafe``, Press et al., *Numerical Recipes*,
    3rd ed., §9.4): a Newton step leaving the bracket, or not halving the step of two iterations
    before, is replaced by a bisection, and the bracket keeps f(lo) < 0 ≤ f(hi).  The iteration
    stops on a Newton step below 2⁻³⁰ relative (the error after it is of the order of its
    square), on a bracket at float resolution, or where f vanishes within rounding; in the
    latter case a sign change in [x − δ, x + δ] (δ four times the rounding-sized width
    16 ε m / |f'|) is confirmed by two more evaluations, otherwise plain bisection of the
    bracket decides (as near the evolute, where f has a near-double root, or next to an end
    of the bracket where f vanishes)."""
    tol = EPS * EPS * (hi - lo)
    dx = dxold = hi - lo
    lo0, hi0 = lo, hi
    if not lo < x < hi:
        x = 0.5 * (lo + hi)
    for _ in range(_MAX_IT):
        f, df, m = fdf(x)
        if f < 0:
            lo = x
        else:       # f ≥ 0 (or NaN, from non-finite input: treated as non-negative)
            hi = x
        newton = df != 0 and lo < x - f / df < hi and abs(2 * f) <= abs(dxold * df)
        if newton and abs(f / df) <= _NEWTON_TOL * abs(x - f / df) + tol:
            return x - f / df
        if abs(f) <= 16 * EPS * m:
            d = 64 * EPS * (m / abs(df) if df != 0 else math.inf) + 4 * EPS * abs(x)
            xl, xr = max(x - d, lo), min(x + d, hi)
            if xl < xr and fdf(xl)[0] < 0 and fdf(xr)[0] >= 0 \
                    and xr - xl <= 1e-6 * (abs(x) + tol):
                return x
            lo, hi = lo0, hi0   # a rounding-level value may have misplaced the bracket
            break
        if newton:
            dxold, dx = dx, f / df
            xn = x - dx
        else:
            dxold, dx = dx, 0.5 * (hi - lo)
            xn = lo + dx
            if not lo < xn < hi:
                return xn
        if abs(dx) <= 2 * EPS * abs(xn) + tol:
            return xn
        x = xn
    for _ in range(_BISECT):
        mid = 0.5 * (lo + hi)
        if not lo < mid < hi:
            break
        if fdf(mid)[0] < 0:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def _root_vector(fdf, lo, hi, x, coefs):
    """Vectorised :func:`_root_scalar`: the same iteration on all entries at once (converged
    entries leave the active set).  ``fdf(x, *coefs)`` returns (f, f', m) elementwise;
    ``coefs`` are arrays aligned with ``x``."""
    out = np.empty_like(x)
    idx = np.arange(x.size)
    lo, hi, x = lo.astype(float), hi.astype(float), x.astype(float)   # copies: updated in place
    x = np.where((lo < x) & (x < hi), x, 0.5 * (lo + hi))
    lo0, hi0 = lo.copy(), hi.copy()
    tol = EPS * EPS * (hi - lo)
    dx = hi - lo
    dxold = dx.copy()
    slow = []  # (idx, lo, hi, coefs) left to bisection
    # rows that finished stay in the arrays (their values unused) until half of them have:
    # each compaction gathers a dozen arrays
    alive = np.ones(x.size, bool)
    err = np.seterr(divide="ignore", invalid="ignore", over="ignore")
    try:
        for _ in range(_MAX_IT):
            f, df, m = fdf(x, *coefs)
            neg = f < 0
            np.copyto(lo, x, where=neg)
            np.copyto(hi, x, where=~neg)   # f ≥ 0 (or NaN, from non-finite input)
            af = np.abs(f)
            flat = af <= 16 * EPS * m
            step = f / df
            xn = x - step
            newton = (lo < xn) & (xn < hi) & (2 * af <= np.abs(dxold * df))
            half = 0.5 * (hi - lo)
            mid = lo + half
            dxold = dx
            dx = np.where(newton, step, half)
            np.copyto(xn, mid, where=~newton)
            # a Newton step below 2⁻³⁰ relative: quadratic convergence makes the new iterate
            # exact to float resolution (simple root); bisection: bracket at float resolution
            small = np.abs(dx) <= np.where(newton, _NEWTON_TOL, 2 * EPS) * np.abs(xn) + tol
            flat &= ~(newton & small) & alive
            done = (small | (~newton & ~((lo < mid) & (mid < hi))) | flat) & alive
            if flat.any():
                np.copyto(xn, x, where=flat)
                # f = 0 within rounding: confirm the sign change around x (else: bisection)
                fi = np.nonzero(flat)[0]
                d = 64 * EPS * m[fi] / np.abs(df[fi]) + 4 * EPS * np.abs(x[fi])
                xl = np.maximum(x[fi] - d, lo[fi])
                xr = np.minimum(x[fi] + d, hi[fi])
                cf = tuple(c[fi] for c in coefs)
                okl = fdf(xl, *cf)[0] < 0
                okr = fdf(xr, *cf)[0] >= 0
                ok = okl & okr & (xl < xr) & (xr - xl <= 1e-6 * (np.abs(x[fi]) + tol[fi]))
                ok = ok & np.isfinite(xl) & np.isfinite(xr)
                nok = fi[~ok]
                if nok.size:
                    # a rounding-level value may have misplaced the bracket: start afresh
                    slow.append((idx[nok], lo0[nok], hi0[nok], tuple(c[nok] for c in coefs)))
                xn[fi] = np.where(ok, x[fi], np.nan)
            if done.any():
                out[idx[done]] = xn[done]
                alive &= ~done
                if not alive.any():
                    break
                if 2 * np.count_nonzero(alive) <= alive.size:
                    keep = alive
                    idx, lo, hi, xn, dx, dxold, tol = (idx[keep], lo[keep], hi[keep], xn[keep], dx[keep],
                                                       dxold[keep], tol[keep])
                    lo0, hi0 = lo0[keep], hi0[keep]
                    coefs = tuple(c[keep] for c in coefs)
                    alive = np.ones(idx.size, bool)
            x = xn
        else:
            slow.append((idx[alive], lo[alive], hi[alive], tuple(c[alive] for c in coefs)))
        for sidx, slo, shi, scf in slow:
            for _ in range(_BISECT):
                mid = 0.5 * (slo + shi)
                neg = fdf(mid, *scf)[0] < 0
                slo = np.where(neg, mid, slo)
                shi = np.where(neg, shi, mid)
            out[sidx] = 0.5 * (slo + shi)
    finally:
        np.seterr(**err)
    return out


def _sgn(v):
    return np.where(v < 0, -1.0, 1.0)


def _ellipse_fdf(x, A, B, C):
    x2 = x * x
    return (A * (x2 * x2 - 1.0) + (B * x2 + C) * x, (4 * A * x + 3 * B) * x2 + C,
            abs(A) * (x2 * x2 + 1.0) + (abs(B) * x2 + abs(C)) * x)


def _hyperbola_fdf(x, k, B, C):
    x2 = x * x
    return (((k * x + B) * x2 + C) * x - k, (4 * k * x + 3 * B) * x2 + C,
            ((k * x + abs(B)) * x2 + abs(C)) * x + k)


def _parabola_fdf(x, k, m):
    return x * (x * x + k) - m, 3 * x * x + k, x * (x * x + abs(k)) + m


def ellipse_feet(X0, Y0, a, b):
    """The closest points of the ellipses X²/a² + Y²/b² = 1 to (X0, Y0), canonical coordinates:
    (X, Y, NX, NY, t): the foot, the outward unit normal of the inside there, and the parameter t of
    (a cos t, b sin t) reduced to [0, π/2].  ``a``, ``b``: floats, or arrays aligned with X0
    (many ellipses at once)."""
    u, v = np.abs(X0), np.abs(Y0)
    k = b * b - a * a
    # in τ = tan(t/2) ∈ [0, 1], (1 + τ²)² D'(t)/2 is the quartic
    # P(τ) = bv (τ⁴ − 1) + 2 (au − k) τ³ + 2 (au + k) τ   (P(0) = −bv ≤ 0 ≤ 4au = P(1));
    # start from the parameter of the radial projection of (u/a, v/b)
    au, bv = a * u, b * v
    cx, cy = b * u, a * v
    r = np.hypot(cx, cy)
    tau0 = np.where(r > 0, cy / np.where(r > 0, r + cx, 1.0), 0.5)
    tau0 = np.clip(tau0, 0.0625, 0.9375)
    if u.size <= _SCALAR_MAX and np.ndim(a) == 0:
        tau = np.array([_root_scalar(lambda x, A=bvi, B=2 * (aui - k), C=2 * (aui + k):
                                     _ellipse_fdf(x, A, B, C), 0.0, 1.0, x0)
                        for aui, bvi, x0 in zip(au.tolist(), bv.tolist(), tau0.tolist())], dtype=float)
    else:
        tau = _root_vector(_ellipse_fdf, np.zeros_like(u), np.ones_like(u), tau0,
                           (bv, 2 * (au - k), 2 * (au + k)))
    t = 2.0 * np.arctan(tau)
    ct, st = np.cos(t), np.sin(t)
    sx, sy = _sgn(X0), _sgn(Y0)
    X, Y = sx * a * ct, sy * b * st
    NX, NY = sx * b * ct, sy * a * st
    nn = np.hypot(NX, NY)
    return X, Y, NX / nn, NY / nn, t


def feet_to_world(P, X, Y, NX, NY, c, s, tx, ty):
    """Feet (X, Y) and unit normals (NX, NY) of the canonical frame (rotation c, s, translation
    tx, ty; floats or arrays) back to the plane: (F, U) of :meth:`SiteGeometry.foot_points`."""
    F = np.column_stack([tx + c * X - s * Y, ty + s * X + c * Y])
    V = P - F
    n = np.hypot(V[:, 0], V[:, 1])
    N = np.column_stack([c * NX - s * NY, s * NX + c * NY])
    # q on the curve (to rounding): the normal of the curve
    tiny = n <= 1e-14 * (1.0 + np.abs(P).sum(axis=1))
    U = np.where(~tiny[:, None], V / np.where(tiny, 1.0, n)[:, None], N)
    return F, U


def ellipse_foot_points(P, a, b, c, s, tx, ty):
    """:meth:`EllipseGeometry.foot_points` for many ellipses at once: row m of ``P`` against the
    ellipse of semi-axes a[m], b[m], rotation (c[m], s[m]), centre (tx[m], ty[m])."""
    P = np.asarray(P, dtype=float).reshape(-1, 2)
    dx, dy = P[:, 0] - tx, P[:, 1] - ty
    X, Y, NX, NY, _ = ellipse_feet(c * dx + s * dy, -s * dx + c * dy, a, b)
    return feet_to_world(P, X, Y, NX, NY, c, s, tx, ty)


def hyperbola_branch_feet(X0, Y0, a, b, branch):
    """The closest points of the branch of sign ``branch`` (array of ±1) of X²/a² − Y²/b² = 1 to
    (X0, Y0), canonical coordinates: (X, Y, NX, NY, t) with (NX, NY) the outward unit normal of
    the convex region {X²/a² − Y²/b² ≥ 1} of that branch and t the parameter of
    (±a cosh t, b sinh t)."""
    u, v = branch * X0, np.abs(Y0)
    k = a * a + b * b
    T = np.arcsinh((a * np.abs(u) + b * v) / k) * (1 + 1e-12) + 1e-300
    # in w = e^t ∈ [1, e^T], 4 w² D'(t)/2 = k (w⁴ − 1) − 2au (w³ − w) − 2bv (w³ + w)
    #   = k w⁴ − 2 (au + bv) w³ + 2 (au − bv) w − k   (−4bv ≤ 0 at w = 1);
    # start from the parameter of the point of the branch at height v
    hi = np.exp(T)
    au, bv = a * u, b * v
    y = v / b
    w0 = np.clip(y + np.sqrt(1.0 + y * y), 1.0, hi)
    w0 = np.where((w0 > 1.0) & (w0 < hi), w0, np.sqrt(hi))
    if u.size <= _SCALAR_MAX:
        w = np.array([_root_scalar(lambda x, B=-2 * (aui + bvi), C=2 * (aui - bvi):
                                   _hyperbola_fdf(x, k, B, C), 1.0, hi_i, x0)
                      for aui, bvi, hi_i, x0 in zip(au.tolist(), bv.tolist(), hi.tolist(), w0.tolist())],
                     dtype=float)
    else:
        w = _root_vector(_hyperbola_fdf, np.ones_like(u), hi, w0,
                         (np.full_like(u, k), -2 * (au + bv), 2 * (au - bv)))
    t = np.log(np.maximum(w, 1.0))
    sy = _sgn(Y0)
    ch, sh = np.cosh(t), np.sinh(t)
    X, Y = branch * a * ch, sy * b * sh
    NX, NY = -branch * b * ch, sy * a * sh
    nn = np.hypot(NX, NY)
    return X, Y, NX / nn, NY / nn, t


def hyperbola_feet(X0, Y0, a, b, far_branch=False):
    """The closest points of the hyperbola X²/a² − Y²/b² = 1 to (X0, Y0): on the branch on the
    side of X0 (the nearer one), or with ``far_branch`` on the other; as
    :func:`hyperbola_branch_feet`."""
    side = _sgn(X0)
    return hyperbola_branch_feet(X0, Y0, a, b, -side if far_branch else side)


def parabola_feet(X0, Y0, p):
    """The closest points of the parabola Y² = 2pX to (X0, Y0), canonical coordinates:
    (X, Y, NX, NY, s) with (NX, NY) the outward unit normal of the focus side {Y² ≤ 2pX} and s
    the parameter of (s²/2p, s)."""
    u, v = X0, np.abs(Y0)
    k = 2 * p * (p - u)
    m = 2 * p * p * v
    S = np.maximum(np.cbrt(2 * m), np.sqrt(2 * np.abs(k))) * (1 + 1e-12) + 1e-300
    # s³ + k s − m: −m ≤ 0 at s = 0; start from the height of q
    s0 = np.clip(v, 0.0, S)
    s0 = np.where((s0 > 0) & (s0 < S), s0, 0.5 * S)
    if u.size <= _SCALAR_MAX:
        s = np.array([_root_scalar(lambda x, k=ki, m=mi: _parabola_fdf(x, k, m), 0.0, Si, x0)
                      for ki, mi, Si, x0 in zip(k.tolist(), m.tolist(), S.tolist(), s0.tolist())], dtype=float)
    else:
        s = _root_vector(_parabola_fdf, np.zeros_like(u), S, s0, (k, m))
    sy = _sgn(Y0)
    X, Y = s * s / (2 * p), sy * s
    NX, NY = -p * np.ones_like(s), sy * s
    nn = np.hypot(NX, NY)
    return X, Y, NX / nn, NY / nn, s


def closest_feet(kind: str, params: dict, X0, Y0):
    """Closest points (X, Y) of the canonical conic ``kind`` with float parameters ``params``
    (A2, B2 / p / r2 of :mod:`runtime.sites.conic`) to the points (X0, Y0) (arrays, canonical
    coordinates).  For a hyperbola the nearer branch (the one on the side of X0); for a circle
    the radial projection ((r, 0) from the centre, where every point is a foot)."""
    X0, Y0 = np.asarray(X0, dtype=float), np.asarray(Y0, dtype=float)
    if kind == "ellipse":
        X, Y, _, _, _ = ellipse_feet(X0, Y0, math.sqrt(params["A2"]), math.sqrt(params["B2"]))
    elif kind == "hyperbola":
        X, Y, _, _, _ = hyperbola_feet(X0, Y0, math.sqrt(params["A2"]), math.sqrt(params["B2"]))
    elif kind == "parabola":
        X, Y, _, _, _ = parabola_feet(X0, Y0, float(params["p"]))
    elif kind == "circle":
        r = math.sqrt(params["r2"])
        n = np.hypot(X0, Y0)
        safe = np.where(n > 0, n, 1.0)
        X, Y = np.where(n > 0, r * X0 / safe, r), np.where(n > 0, r * Y0 / safe, 0.0)
    else:
        raise InvalidConicError(f"unknown conic kind {kind!r}")
    return X, Y


# =========================================================================== all critical points

def _negated(fdfm):
    f, df, m = fdfm
    return -f, -df, m


def _roots_on(fdf, deriv, lo: float, hi: float) -> list[float]:
    """All roots in [lo, hi] of the polynomial f evaluated by ``fdf`` (x -> (f, f', m)), its
    derivative given by the coefficients ``deriv`` (highest first): [lo, hi] is split at the
    real roots of f' (``numpy.roots``; f is monotone between them), every strict sign change
    is bracketed by :func:`_root_scalar`, and a split point where f vanishes within rounding
    (an end of the parameter range on a symmetry axis, a double root on the evolute) is a root."""
    crit = [z.real for z in np.roots(deriv) if abs(z.imag) <= 1e-9 * (1.0 + abs(z.real))] if len(deriv) > 1 else []
    cuts = [lo] + sorted(x for x in crit if lo < x < hi) + [hi]
    vals = [fdf(x) for x in cuts]
    roots = [x for x, (f, _, m) in zip(cuts, vals) if abs(f) <= 16 * EPS * m]
    for (x0, (f0, _, m0)), (x1, (f1, _, m1)) in zip(zip(cuts, vals), zip(cuts[1:], vals[1:])):
        if abs(f0) <= 16 * EPS * m0 or abs(f1) <= 16 * EPS * m1 or (f0 < 0) == (f1 < 0):
            continue
        if f0 < 0:
            roots.append(_root_scalar(fdf, x0, x1, 0.5 * (x0 + x1)))
        else:
            roots.append(_root_scalar(lambda x: _negated(fdf(x)), x0, x1, 0.5 * (x0 + x1)))
    return roots


def canonical_foot_points(kind: str, params: dict, X0: float, Y0: float, all_candidates: bool = False):
    """All critical points of the squared distance from (X0, Y0) to the canonical conic (up to
    four: inside the evolute; thesis §5.2), as a list of (X, Y, True).

    The normal condition of the closest-foot solvers, on each arc where the curve is a graph
    over its parameter: the four quadrant arcs (σx a cos t, σy b sin t), t ∈ [0, π/2], of the
    ellipse (quartic in τ = tan(t/2) ∈ [0, 1]); the four half-branches (σ a cosh t, σy b sinh t),
    t ≥ 0, of the hyperbola (quartic in w = e^t, t ≤ asinh((a|u| + b|v|)/(a² + b²)) beyond which
    D' > 0); the two halves (s²/2p, σy s), s ≥ 0, of the parabola (cubic, s ≤ max((4p²|v|)^(1/3),
    (4p|p − u|)^(1/2))).  Their roots are found by :func:`_roots_on`; points on the axes (shared
    by two arcs) are listed once.  The circle is in closed form (one representative at the centre).
    ``all_candidates`` is accepted for compatibility: every point returned is a bracketed root."""
    X0, Y0 = float(X0), float(Y0)
    pts: list[tuple[float, float]] = []
    if kind == "circle":
        r = math.sqrt(params["r2"])
        n = math.hypot(X0, Y0)
        if n == 0.0:
            return [(r, 0.0, True)]  # every point is a foot point; one representative
        return [(r * X0 / n, r * Y0 / n, True), (-r * X0 / n, -r * Y0 / n, True)]
    if kind == "ellipse":
        a, b = math.sqrt(params["A2"]), math.sqrt(params["B2"])
        k = b * b - a * a
        for sx in (1.0, -1.0):
            for sy in (1.0, -1.0):
                au, bv = a * sx * X0, b * sy * Y0
                A, B, C = bv, 2 * (au - k), 2 * (au + k)
                for tau in _roots_on(lambda x: _ellipse_fdf(x, A, B, C), [4 * A, 3 * B, 0.0, C], 0.0, 1.0):
                    t = 2.0 * math.atan(tau)
                    pts.append((sx * a * math.cos(t), sy * b * math.sin(t)))
        scale = a
    elif kind == "hyperbola":
        a, b = math.sqrt(params["A2"]), math.sqrt(params["B2"])
        k = a * a + b * b
        for sx in (1.0, -1.0):
            for sy in (1.0, -1.0):
                au, bv = a * sx * X0, b * sy * Y0
                hi = math.exp(math.asinh((abs(au) + abs(bv)) / k) * (1 + 1e-12) + 1e-300)
                B, C = -2 * (au + bv), 2 * (au - bv)
                for w in _roots_on(lambda x: _hyperbola_fdf(x, k, B, C), [4 * k, 3 * B, 0.0, C], 1.0, hi):
                    t = math.log(max(w, 1.0))
                    pts.append((sx * a * math.cosh(t), sy * b * math.sinh(t)))
        scale = a + b
    elif kind == "parabola":
        p = float(params["p"])
        kk = 2 * p * (p - X0)
        for sy in (1.0, -1.0):
            m = 2 * p * p * sy * Y0
            hi = max((2 * abs(m)) ** (1.0 / 3.0), math.sqrt(2 * abs(kk))) * (1 + 1e-12) + 1e-300
            for s_ in _roots_on(lambda x: _parabola_fdf(x, kk, m), [3.0, 0.0, kk], 0.0, hi):
                pts.append((s_ * s_ / (2 * p), sy * s_))
        scale = p
    else:
        raise InvalidConicError(f"unknown conic kind {kind!r}")
    tol = 1e-9 * (scale + abs(X0) + abs(Y0))
    out: list[tuple[float, float, bool]] = []
    for X, Y in pts:
        if all(math.hypot(X - U, Y - V) > tol for U, V, _ in out):
            out.append((X, Y, True))
    return out
