"""Float geometry of conic sites with rigorous distance bounds (thesis §5.1–5.2).

The Voronoi diagram is decided by d(q, C) = min over p ∈ C of |q − p| (thesis §5.2: the foot
points of q are the points of C where q − p is normal to C).  This module implements
:class:`runtime.voronoi.geometry.SiteGeometry` for ellipses, hyperbolas (both branches form one
site) and parabolas, vectorised over many query points with numpy.

Canonical frame (:mod:`runtime.sites.conic`): (X, Y) = R(−θ)(q − t); ellipse X²/a² + Y²/b² = 1
(a ≥ b), hyperbola X²/a² − Y²/b² = 1, parabola Y² = 2pX.  g denotes the canonical quadratic
(ellipse X²/a² + Y²/b² − 1, hyperbola 1 − X²/a² + Y²/b², parabola Y² − 2pX), so that the
convex side K = {g ≤ 0} (the inside of the ellipse, the focus side of the parabola, the two
convex regions bounded by the hyperbola's branches) and C = {g = 0}.

Float foot points
-----------------
By the symmetries of the canonical forms the closest point of q = (u, v) (u, v ≥ 0 after
reflection) lies in the closed quadrant of q; in the natural parameter there it is the unique
sign change of the derivative of the squared distance (thesis §5.2, the normal condition):

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
full bracket decides, as before.  The point is then evaluated from the parameter, so it lies
on the curve to rounding.  The rigorous bounds below hold for any parameter; the accuracy of
the root only decides their tightness (and hence how often the ball route is needed).

Rigorous bounds (``distance_bounds``)
-------------------------------------
Work in the float canonical frame of the float conic C_f (exact binary numbers); then

* the float frame is rounded once from a 128-bit enclosure of the exact frame, and the canonical
  transform of q costs a few roundings, so every point p of the exact conic within distance
  ρ of q has a partner on C_f within σ = rounding_slack(|q| + |t| + |Q| + ρ + a + b, 32)
  (each coordinate is a sum of ≤ 4 products of numbers of that size, each off by ≤ 2 ulps),
  and d(q, C) ∈ [d(Q, C_f) − σ, d(Q, C_f) + σ];
* **upper bound**: |Q − P(t)| for the float point P(t); P(t) is within ε_P =
  rounding_slack(a + b + |P|, 16) of the exact point of C_f of parameter t (libm's cos, sin,
  cosh, sinh are accurate to a few ulps);
* **lower bound outside K** (supporting line): K is convex (per branch for the hyperbola), so
  for every p* ∈ C with outward unit normal n*, K ⊂ {z : n*·(z − p*) ≤ 0} and
  d(q, C) ≥ d(q, K) ≥ n*·(q − p*) whenever q ∉ K; if q ∈ K then n*·(q − p*) ≤ 0, so
  max(0, n*·(q − p*)) is a lower bound in all cases.  The normal is evaluated from the
  parameter (ellipse (b cos t, a sin t), hyperbola (−b cosh t, a sinh t), parabola (−p, s));
  rounding: |n̂ − n*| ≤ 16 ε_u, so the bound loses ε_P + 16 ε_u |Q − P| + dot-product rounding.
  For the hyperbola d(q, C) = min over the two branches, each bounded this way at its own
  foot point.  At the foot point the bound equals the distance (tight).
* **lower bound inside K** (S-lemma, Yakubovich 1971; Pólik & Terlaky, SIAM Rev. 49 (2007)):
  the open disc B(q, r) ⊂ {g ≤ 0} iff there is μ ≥ 0 with −g(z) − μ (r² − |z − q|²) ≥ 0 for
  all z.  Minimising over z in closed form gives r² ≤ h(μ) for every admissible μ:

  - ellipse  h(μ) = 1/μ − u²/(a²μ − 1) − v²/(b²μ − 1),  μ > 1/b²;
  - hyperbola h(μ) = u²/(a²μ + 1) − v²/(b²μ − 1) − 1/μ,  μ > 1/b²;
  - parabola h(μ) = 2pu/μ − p²/μ² − v²/(μ − 1),  μ > 1;

  and for q ∈ {g < 0} every disc of radius r < d(q, C) lies in {g ≤ 0} (it does not meet C),
  so d(q, C) ≥ sqrt(h(μ)) for every admissible μ, with equality at the optimum (the S-lemma is
  lossless).  μ is taken from the float foot point, μ = ∇g(p)·(p − q)/(2|p − q|²), and h is
  evaluated with interval-style error bounds (h is stationary at the optimum, so an error in
  μ costs only second order).
* where neither is tight (relative gap > 1e-7, e.g. exactly on a symmetry axis at an evolute
  cusp), the rigorous ball route :func:`runtime.sites.distance_ball.distance_ball` (Lagrange polynomial of
  the foot points, exact coefficients) is used for those points; the float q is exact.

Length: the three conic kinds share the float foot-point machinery and the rounding allowances
that their rigorous bounds are proved with; splitting them would separate a bound from its proof.
"""
from __future__ import annotations

import math

import numpy as np

from ..predicates.circles import Circle
from ..sites.conic import Conic
from .geometry import EPS, CircleGeometry, PointGeometry, SiteGeometry, rounding_slack

__all__ = ["ConicGeometry", "CentralConicGeometry", "EllipseGeometry", "HyperbolaGeometry", "ParabolaGeometry",
           "conic_geometry", "site_geometry", "sites_intersect", "site_inside", "ellipse_feet",
           "ellipse_foot_points"]

#: relative gap above which the fast bounds defer to the ball route
_FALLBACK_GAP = 1e-7
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
            flat &= ~(newton & small)
            done = small | (~newton & ~((lo < mid) & (mid < hi))) | flat
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
                keep = ~done
                if not keep.any():
                    break
                idx, lo, hi, xn, dx, dxold, tol = (idx[keep], lo[keep], hi[keep], xn[keep], dx[keep],
                                                   dxold[keep], tol[keep])
                lo0, hi0 = lo0[keep], hi0[keep]
                coefs = tuple(c[keep] for c in coefs)
            x = xn
        else:
            slow.append((idx, lo, hi, coefs))
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
    (X, Y, NX, NY, t) as ``_feet_canonical``.  ``a``, ``b``: floats, or arrays aligned with X0
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


def _feet_to_world(P, X, Y, NX, NY, c, s, tx, ty):
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
    return _feet_to_world(P, X, Y, NX, NY, c, s, tx, ty)


class ConicGeometry(SiteGeometry):
    """Common part of the conic geometries: canonical frame, transforms, bounds driver."""

    def __init__(self, conic: Conic):
        if not isinstance(conic, Conic):
            raise TypeError(f"expected a Conic, got {conic!r}")
        self.exact = conic
        fr = conic.frame
        self.kind = fr.kind
        self.c, self.s, self.tx, self.ty = float(fr.cos), float(fr.sin), float(fr.tx), float(fr.ty)
        self.params = {k: float(v) for k, v in fr.params.items()}
        #: statistics: how many points needed the ball route
        self.fallbacks = 0

    # ------------------------------------------------------------------ frames
    def to_canonical(self, P):
        P = np.asarray(P, dtype=float).reshape(-1, 2)
        dx, dy = P[:, 0] - self.tx, P[:, 1] - self.ty
        return self.c * dx + self.s * dy, -self.s * dx + self.c * dy

    def from_canonical(self, X, Y):
        return np.column_stack([self.tx + self.c * X - self.s * Y, self.ty + self.s * X + self.c * Y])

    def _rot(self, NX, NY):
        return np.column_stack([self.c * NX - self.s * NY, self.s * NX + self.c * NY])

    # ------------------------------------------------------------------ to implement per kind
    def _feet_canonical(self, X0, Y0):
        """(X, Y, NX, NY, t): the closest point in canonical coordinates, the outward unit normal
        of K there, and the parameter.  Vectorised."""
        raise NotImplementedError

    def _g(self, X, Y):
        raise NotImplementedError

    def _sz(self):
        """a + b (scale of the canonical curve)."""
        raise NotImplementedError

    # ------------------------------------------------------------------ float API
    def foot_points(self, P):
        P = np.asarray(P, dtype=float).reshape(-1, 2)
        X0, Y0 = self.to_canonical(P)
        X, Y, NX, NY, _ = self._feet_canonical(X0, Y0)
        return _feet_to_world(P, X, Y, NX, NY, self.c, self.s, self.tx, self.ty)

    def distance(self, P):
        P = np.asarray(P, dtype=float).reshape(-1, 2)
        X0, Y0 = self.to_canonical(P)
        X, Y, _, _, _ = self._feet_canonical(X0, Y0)
        return np.hypot(X0 - X, Y0 - Y)

    # ------------------------------------------------------------------ rigorous bounds
    def _tangent_lower(self, X0, Y0, X, Y, NX, NY):
        """max(0, n·(Q − P)) minus its rounding allowance (see the module docstring)."""
        dX, dY = X0 - X, Y0 - Y
        val = NX * dX + NY * dY
        dist = np.hypot(dX, dY)
        scale = self._sz() + np.abs(X) + np.abs(Y)
        eps_p = rounding_slack(scale, 16)
        err = eps_p + 16 * EPS * dist + rounding_slack(np.abs(X0) + np.abs(Y0) + scale, 8)
        return np.maximum(val - err, 0.0)

    def _slemma_lower(self, X0, Y0, X, Y):
        raise NotImplementedError

    def _branch_feet(self, X0, Y0, first):
        """Feet used by the supporting-line bound: a list of (X, Y, NX, NY); ``first`` is the
        closest foot, already computed."""
        return [first]

    def distance_bounds(self, P):
        P = np.asarray(P, dtype=float).reshape(-1, 2)
        X0, Y0 = self.to_canonical(P)
        X, Y, NX, NY, _ = self._feet_canonical(X0, Y0)
        d = np.hypot(X0 - X, Y0 - Y)
        scale = self._sz() + np.abs(X) + np.abs(Y)
        up = d + rounding_slack(scale, 16) + rounding_slack(d + np.abs(X0) + np.abs(Y0) + scale, 8)
        inside = self._g(X0, Y0) < 0
        lo = np.zeros_like(d)
        feet = self._branch_feet(X0, Y0, (X, Y, NX, NY))
        tl = None
        for (Xb, Yb, NXb, NYb) in feet:
            t = self._tangent_lower(X0, Y0, Xb, Yb, NXb, NYb)
            tl = t if tl is None else np.minimum(tl, t)
        lo = np.where(inside, 0.0, tl)
        if inside.any():
            idx = np.nonzero(inside)[0]
            lo[idx] = np.maximum(lo[idx], self._slemma_lower(X0[idx], Y0[idx], X[idx], Y[idx]))
        # frame and transform slack: the float conic vs the exact one, the float Q vs q
        sig = rounding_slack(np.abs(P).sum(axis=1) + abs(self.tx) + abs(self.ty) + np.abs(X0) + np.abs(Y0)
                             + up + self._sz(), 32)
        lo = np.maximum(lo - sig, 0.0)
        hi = up + sig
        # the ball route only where the fast bounds are loose beyond float resolution
        bad = ~((hi - lo) <= np.maximum(_FALLBACK_GAP * hi, 64 * sig))
        bad |= ~np.isfinite(lo) | ~np.isfinite(hi)
        if bad.any():
            lo = lo.copy()
            hi = hi.copy()
            for i in np.nonzero(bad)[0]:
                blo, bhi = self._ball_bounds(float(P[i, 0]), float(P[i, 1]))
                lo[i] = max(blo, lo[i]) if np.isfinite(lo[i]) else blo
                hi[i] = min(bhi, hi[i]) if np.isfinite(hi[i]) else bhi
        return lo, hi

    def _ball_bounds(self, x: float, y: float):
        """Rigorous bounds from :func:`runtime.sites.distance_ball.distance_ball` (floats taken exactly),
        rounded outwards to floats."""
        from ..sites.distance_ball import distance_ball

        self.fallbacks += 1
        D = distance_ball(self.exact, x, y, prec=64)
        lo, hi = float(D.lower()), float(D.upper())
        # float() rounds to nearest: step outwards by one ulp
        return max(math.nextafter(lo, -math.inf), 0.0), math.nextafter(hi, math.inf)

    # ------------------------------------------------------------------ samples
    def _curve_points(self, t, branch=1.0):
        raise NotImplementedError

    def _sample_param(self, t0, t1, spacing, branch=1.0):
        """Points with parameter in [t0, t1], at most ``spacing`` apart along the curve
        (arc length from a fine chord polyline, with a 10% margin)."""
        m = 2048
        tt = np.linspace(t0, t1, m)
        X, Y = self._curve_points(tt, branch)
        seg = np.hypot(np.diff(X), np.diff(Y))
        L = float(seg.sum())
        n = int(min(max(math.ceil(1.1 * L / max(spacing, 1e-300)) + 1, 2), 2_000_000))
        if n > m // 2:
            # refine the polyline so that the arc-length table is fine enough
            m = min(4 * n, 8_000_000)
            tt = np.linspace(t0, t1, m)
            X, Y = self._curve_points(tt, branch)
            seg = np.hypot(np.diff(X), np.diff(Y))
            L = float(seg.sum())
            n = int(min(max(math.ceil(1.1 * L / max(spacing, 1e-300)) + 1, 2), 2_000_000))
        cum = np.concatenate([[0.0], np.cumsum(seg)])
        tq = np.interp(np.linspace(0.0, L, n), cum, tt)
        X, Y = self._curve_points(tq, branch)
        return self.from_canonical(X, Y)

    def _window_radius(self, window):
        if window is None:
            raise ValueError(f"samples of an unbounded site ({self.kind}) need a window "
                             "(xmin, ymin, xmax, ymax)")
        xmin, ymin, xmax, ymax = window
        corners = np.array([[xmin, ymin], [xmin, ymax], [xmax, ymin], [xmax, ymax]], dtype=float)
        X, Y = self.to_canonical(corners)
        return float(np.max(np.hypot(X, Y)))

    @staticmethod
    def _clip(Pts, window, spacing):
        xmin, ymin, xmax, ymax = window
        m = spacing
        keep = ((Pts[:, 0] >= xmin - m) & (Pts[:, 0] <= xmax + m)
                & (Pts[:, 1] >= ymin - m) & (Pts[:, 1] <= ymax + m))
        return Pts[keep]


class CentralConicGeometry(ConicGeometry):
    """A conic with a centre (ellipse, hyperbola): semi-axes a, b of its canonical frame."""

    def __init__(self, conic):
        super().__init__(conic)
        self.a = math.sqrt(self.params["A2"])
        self.b = math.sqrt(self.params["B2"])

    def _sz(self):
        return self.a + self.b


class EllipseGeometry(CentralConicGeometry):
    """An ellipse site X²/a² + Y²/b² = 1 (a ≥ b) in its canonical frame."""

    def _g(self, X, Y):
        return (X / self.a) ** 2 + (Y / self.b) ** 2 - 1.0

    def bounding_box(self):
        a, b, c, s = self.a, self.b, self.c, self.s
        hx = math.sqrt((a * c) ** 2 + (b * s) ** 2)
        hy = math.sqrt((a * s) ** 2 + (b * c) ** 2)
        pad = 1e-12 * (a + abs(self.tx) + abs(self.ty))
        return (self.tx - hx - pad, self.ty - hy - pad, self.tx + hx + pad, self.ty + hy + pad)

    def _curve_points(self, t, branch=1.0):
        return self.a * np.cos(t), self.b * np.sin(t)

    def samples(self, spacing, window=None):
        P = self._sample_param(0.0, 2 * math.pi, spacing)
        return P[:-1]  # the last point repeats the first

    def _feet_canonical(self, X0, Y0):
        return ellipse_feet(X0, Y0, self.a, self.b)

    def _slemma_lower(self, X0, Y0, X, Y):
        a2, b2 = self.params["A2"], self.params["B2"]
        # mu = grad g(p)·(p − q) / (2 |p − q|²), grad g / 2 = (X/a², Y/b²)
        dX, dY = X - X0, Y - Y0
        mu = (X / a2 * dX + Y / b2 * dY) / (dX * dX + dY * dY)
        mu = np.maximum(mu, (1.0 / b2) * (1 + 64 * EPS))
        return _h_lower([(1.0, 1.0 / mu, 0.0)],
                        [(-1.0, X0 * X0, a2 * mu - 1.0, 4 * EPS * (a2 * mu + 1.0)),
                         (-1.0, Y0 * Y0, b2 * mu - 1.0, 4 * EPS * (b2 * mu + 1.0))])


class HyperbolaGeometry(CentralConicGeometry):
    """A hyperbola site X²/a² − Y²/b² = 1 (both branches are one site)."""

    def _g(self, X, Y):
        return 1.0 - (X / self.a) ** 2 + (Y / self.b) ** 2

    def bounding_box(self):
        return (-math.inf, -math.inf, math.inf, math.inf)

    def _curve_points(self, t, branch=1.0):
        return branch * self.a * np.cosh(t), self.b * np.sinh(t)

    def samples(self, spacing, window):
        Rw = self._window_radius(window)
        # window points have |X|, |Y| ≤ Rw: a cosh t ≤ Rw and b |sinh t| ≤ Rw
        T = min(math.asinh(Rw / self.b), math.acosh(max(Rw / self.a, 1.0))) * (1 + 1e-12) + 1e-9
        P = np.vstack([self._sample_param(-T, T, spacing, 1.0), self._sample_param(-T, T, spacing, -1.0)])
        return self._clip(P, window, spacing)

    def _branch_param(self, u, v):
        """Parameter of the foot on the right branch of (u, v), v ≥ 0 (u of any sign)."""
        a, b = self.a, self.b
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
        return np.log(np.maximum(w, 1.0))

    def _foot_branch(self, X0, Y0, branch):
        """Foot on the branch of sign ``branch`` (array of ±1) and outward normal of its K."""
        a, b = self.a, self.b
        u = branch * X0
        sy = _sgn(Y0)
        t = self._branch_param(u, np.abs(Y0))
        ch, sh = np.cosh(t), np.sinh(t)
        X, Y = branch * a * ch, sy * b * sh
        NX, NY = -branch * b * ch, sy * a * sh
        nn = np.hypot(NX, NY)
        return X, Y, NX / nn, NY / nn, t

    def _feet_canonical(self, X0, Y0):
        return self._foot_branch(X0, Y0, _sgn(X0))

    def _branch_feet(self, X0, Y0, first):
        X2, Y2, NX2, NY2, _ = self._foot_branch(X0, Y0, -_sgn(X0))
        return [first, (X2, Y2, NX2, NY2)]

    def _slemma_lower(self, X0, Y0, X, Y):
        a2, b2 = self.params["A2"], self.params["B2"]
        # g = 1 − X²/a² + Y²/b²: grad g / 2 = (−X/a², Y/b²)
        dX, dY = X - X0, Y - Y0
        mu = (-X / a2 * dX + Y / b2 * dY) / (dX * dX + dY * dY)
        mu = np.maximum(mu, (1.0 / b2) * (1 + 64 * EPS))
        return _h_lower([(-1.0, 1.0 / mu, 0.0)],
                        [(+1.0, X0 * X0, a2 * mu + 1.0, 4 * EPS * (a2 * mu + 1.0)),
                         (-1.0, Y0 * Y0, b2 * mu - 1.0, 4 * EPS * (b2 * mu + 1.0))])


class ParabolaGeometry(ConicGeometry):
    """A parabola site Y² = 2pX."""

    def __init__(self, conic):
        super().__init__(conic)
        self.p = self.params["p"]

    def _sz(self):
        return self.p

    def _g(self, X, Y):
        return Y * Y - 2 * self.p * X

    def bounding_box(self):
        return (-math.inf, -math.inf, math.inf, math.inf)

    def _curve_points(self, t, branch=1.0):
        return t * t / (2 * self.p), t

    def samples(self, spacing, window):
        Rw = self._window_radius(window)
        # window points have |X|, |Y| ≤ Rw: |s| ≤ Rw and s² / 2p ≤ Rw
        S = min(Rw, math.sqrt(2 * self.p * Rw)) * (1 + 1e-12) + 1e-9
        return self._clip(self._sample_param(-S, S, spacing), window, spacing)

    def _feet_canonical(self, X0, Y0):
        p = self.p
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

    def _slemma_lower(self, X0, Y0, X, Y):
        p = self.p
        # g = Y² − 2pX: grad g / 2 = (−p, Y)
        dX, dY = X - X0, Y - Y0
        mu = (-p * dX + Y * dY) / (dX * dX + dY * dY)
        mu = np.maximum(mu, 1.0 + 64 * EPS)
        return _h_lower([(1.0, 2 * p * X0 / mu, 0.0), (-1.0, p * p / (mu * mu), 0.0)],
                        [(-1.0, Y0 * Y0, mu - 1.0, 4 * EPS * (mu + 1.0))])


def _h_lower(plain, fractions):
    """Rigorous lower bound of sqrt(max(h, 0)) where h = Σ sign·value (``plain``: values known
    to relative 4 ulps) + Σ sign·num/den (``fractions``: num ≥ 0 to relative 2 ulps, den given
    with an absolute error bound).  A fraction whose denominator is not provably positive
    makes the bound 0 (the multiplier is not admissible)."""
    total = 0.0
    mag = 0.0
    ok = True
    for sg, val, _ in plain:
        total = total + sg * val
        mag = mag + np.abs(val)
    for sg, num, den, err in fractions:
        ok = ok & (den - err > 0)
        safe_lo = np.where(den - err > 0, den - err, 1.0)
        if sg < 0:   # subtracted: use an upper bound of num/den
            q = num / safe_lo
        else:        # added: use a lower bound
            q = num / (den + err)
        total = total + sg * q
        mag = mag + np.abs(q)
    h = total - 8 * EPS * mag - 1e-300
    r = np.sqrt(np.maximum(h, 0.0)) * (1 - 4 * EPS)
    return np.where(ok, r, 0.0)


def conic_geometry(conic) -> SiteGeometry:
    """The :class:`SiteGeometry` of a conic site (circles go to ``CircleGeometry``)."""
    if not isinstance(conic, Conic):
        raise TypeError(f"expected a Conic, got {conic!r}")
    if conic.kind == "ellipse":
        return EllipseGeometry(conic)
    if conic.kind == "hyperbola":
        return HyperbolaGeometry(conic)
    if conic.kind == "parabola":
        return ParabolaGeometry(conic)
    return site_geometry(conic)


# =========================================================================== exact intersection tests

def _coeffs_of(site):
    """Exact rational coefficients (a, b, c, d, e, f) of a conic or circle site, or ('point', x, y)."""
    from fractions import Fraction

    from ..predicates.circles import Circle

    if isinstance(site, Circle):
        cx = Fraction(int(site.cx.p), int(site.cx.q))
        cy = Fraction(int(site.cy.p), int(site.cy.q))
        r2 = Fraction(int(site.r2.p), int(site.r2.q))
        if r2 == 0:
            return ("point", cx, cy)
        return (Fraction(1), Fraction(0), Fraction(1), -2 * cx, -2 * cy, cx * cx + cy * cy - r2)
    if isinstance(site, Conic):
        return tuple(site.coefficients)
    raise TypeError(f"not a site: {site!r}")


def _eval(co, x, y):
    a, b, c, d, e, f = co
    return a * x * x + b * x * y + c * y * y + d * x + e * y + f


def _shear(co, k):
    """Coefficients of the conic after the substitution x -> x + k y (rational k)."""
    a, b, c, d, e, f = co
    return (a, b + 2 * a * k, c + b * k + a * k * k, d, e + d * k, f)


def _tarski_query(p, q=None) -> int:
    """Sturm–Tarski query TaQ(q, p) = #{x real: p(x) = 0, q(x) > 0} − #{x real: p(x) = 0, q(x) < 0}
    for a non-zero fmpq_poly p (q = 1: the number of distinct real roots of p), from the signed
    remainder sequence of p and p'·q (Basu, Pollack & Roy, *Algorithms in Real Algebraic
    Geometry*, Thm 2.73).  Exact."""
    if p.degree() <= 0:
        return 0
    second = p.derivative() if q is None else p.derivative() * q
    chain = [p]
    if not second.is_zero():
        chain.append(second)
        while True:
            r = -(chain[-2] % chain[-1])
            if r.is_zero():
                break
            chain.append(r)

    def variations(at_minus):
        signs = []
        for f in chain:
            lc = f.leading_coefficient()
            sg = 1 if lc > 0 else -1
            if at_minus and f.degree() % 2 == 1:
                sg = -sg
            signs.append(sg)
        return sum(1 for u, v in zip(signs, signs[1:]) if u != v)

    return variations(True) - variations(False)


def _circles_intersect(ca, cb) -> bool:
    """Two circles (x − c)² = ρ² meet iff (ρ1 − ρ2)² ≤ |c1 − c2|² ≤ (ρ1 + ρ2)², decided exactly
    on r_i = ρ_i² by squaring once: |D − r1 − r2| ≤ 2 ρ1 ρ2 ⇔ (D − r1 − r2)² ≤ 4 r1 r2."""
    (x1, y1, r1), (x2, y2, r2) = ca, cb
    D = (x1 - x2) ** 2 + (y1 - y2) ** 2
    t = D - r1 - r2
    return t * t <= 4 * r1 * r2


def _circle_data(co):
    a, b, c, d, e, f = co
    if a == c and b == 0:
        cx, cy = -d / (2 * a), -e / (2 * a)
        return (cx, cy, cx * cx + cy * cy - f / a)
    return None


def sites_intersect(A, B) -> bool:
    """Exactly decide whether two sites (Conic, Circle or Point) have a common real point.

    Two conics: after an exact shear x → x + k y making both y²-coefficients non-zero (a real
    linear bijection: real intersection points correspond), write f_A = a2 y² + a1 y + a0,
    f_B = b2 y² + b1 y + b0 with a2, b2 non-zero constants.  The resultant
    R(x) = (a2 b0 − a0 b2)² − (a2 b1 − a1 b2)(a1 b0 − a0 b1) has the x-coordinates of all complex
    intersections as roots and no others (constant leading coefficients).  At a real root x of R
    the first subresultant S1 = b2 f_A − a2 f_B = s1(x) y + s0(x) gives the common root
    y = −s0/s1, real, when s1(x) ≠ 0; if s1(x) = 0 then f_A(x, ·) and f_B(x, ·) are
    proportional and have a real common root iff their discriminant is ≥ 0.  Real roots are
    counted, and the sign of the discriminant at them decided, with Sturm–Tarski queries over Q
    (python-flint ``fmpq_poly``).  Two circles are compared directly.  Identical conics
    intersect.
    """
    from fractions import Fraction

    from flint import fmpq, fmpq_poly

    ca, cb = _coeffs_of(A), _coeffs_of(B)
    if ca[0] == "point" and cb[0] == "point":
        return ca[1:] == cb[1:]
    if ca[0] == "point":
        return _eval(cb, ca[1], ca[2]) == 0
    if cb[0] == "point":
        return _eval(ca, cb[1], cb[2]) == 0
    ra, rb = _circle_data(ca), _circle_data(cb)
    if ra is not None and rb is not None:
        return _circles_intersect(ra, rb)
    for k in (Fraction(0), Fraction(1), Fraction(-1), Fraction(1, 2), Fraction(2), Fraction(-3, 7)):
        sa, sb = _shear(ca, k), _shear(cb, k)
        if sa[2] != 0 and sb[2] != 0:
            break

    def P(*cs):
        return fmpq_poly([fmpq(c.numerator, c.denominator) for c in cs])

    def split(co):
        a, b, c, d, e, f = co
        return P(c), P(e, b), P(f, d, a)       # coefficients of y², y, 1 as polynomials in x

    a2, a1, a0 = split(sa)
    b2, b1, b0 = split(sb)
    s1 = b2 * a1 - a2 * b1
    s0 = b2 * a0 - a2 * b0
    if s1.is_zero() and s0.is_zero():
        return True  # proportional equations: the same conic
    R = (a2 * b0 - a0 * b2) ** 2 - (a2 * b1 - a1 * b2) * (a1 * b0 - a0 * b1)
    if R.is_zero():
        return True
    if R.degree() <= 0:
        return False
    Rs = R / R.gcd(R.derivative()) if R.derivative().degree() >= 0 else R
    G = Rs.gcd(s1) if not s1.is_zero() else Rs
    free = Rs / G if G.degree() > 0 else Rs
    if free.degree() > 0 and _tarski_query(free) > 0:
        return True
    if G.degree() <= 0 or _tarski_query(G) == 0:
        return False
    # proportional rows at the real roots of G: a common real y iff disc(x) ≥ 0 there
    disc = a1 * a1 - 4 * a2 * a0
    h = G.gcd(disc) if not disc.is_zero() else G
    if h.degree() > 0 and _tarski_query(h) > 0:
        return True                       # disc = 0 at a real root: a real double root y
    Gr = G / h if h.degree() > 0 else G
    n = _tarski_query(Gr)
    return n > 0 and (n + _tarski_query(Gr, disc)) // 2 > 0


def site_inside(A, B) -> bool:
    """For two disjoint sites (``sites_intersect`` false): whether A lies in the open region
    {g_B < 0} bounded by B (inside an ellipse or circle, on the focus side of a parabola, inside
    a hyperbola branch).  A point of A is tested with an exact rational evaluation of g_B (signs
    normalised so that g_B < 0 on B's convex side); A is connected per branch, and every
    component of A lies on one side since A does not meet B, so one point per component decides
    (a hyperbola A is inside only if both branches are).  The tested point is the float vertex
    of A's canonical frame (within ~1e-16 relative of A), so the answer is exact unless A and B
    are closer than that."""
    from fractions import Fraction

    cb = _coeffs_of(B)
    if cb[0] == "point":
        return False
    a, b, c, d, e, f = cb
    ca = _coeffs_of(A)
    if ca[0] == "point":
        pts = [(ca[1], ca[2])]
    else:
        geo = site_geometry(A)
        if geo.kind == "circle":
            P = np.array([[geo.cx + geo.rho, geo.cy]])
        elif geo.kind == "hyperbola":
            P = np.vstack([geo.from_canonical(np.array([geo.a]), np.array([0.0])),
                           geo.from_canonical(np.array([-geo.a]), np.array([0.0]))])
        elif geo.kind == "ellipse":
            P = geo.from_canonical(np.array([geo.a]), np.array([0.0]))
        else:
            P = geo.from_canonical(np.array([0.0]), np.array([0.0]))
        pts = [(Fraction(float(p[0])), Fraction(float(p[1]))) for p in P]
    # sign convention: s·f_B < 0 on the convex side; reference point certainly there: the
    # centre (ellipse/circle), a point of the axis beyond the vertex (parabola, hyperbola)
    if isinstance(B, Conic) and B.kind in ("ellipse", "circle"):
        den = 4 * a * c - b * b
        ref = ((b * e - 2 * c * d) / den, (b * d - 2 * a * e) / den)
    elif not isinstance(B, Conic):
        ref = (Fraction(int(B.cx.p), int(B.cx.q)), Fraction(int(B.cy.p), int(B.cy.q)))
    else:
        gb = site_geometry(B)
        far = 2 * gb._sz() + 1.0
        ref = tuple(Fraction(float(v)) for v in gb.from_canonical(np.array([far]), np.array([0.0]))[0])
    s = -1 if _eval((a, b, c, d, e, f), *ref) > 0 else 1
    return all(s * _eval((a, b, c, d, e, f), px, py) < 0 for px, py in pts)


def site_geometry(site) -> SiteGeometry:
    """The geometry of a site: a :class:`runtime.predicates.circles.Circle` (r2 = 0 is a point), a
    :class:`runtime.sites.conic.Conic` (circles among them go to :class:`CircleGeometry`)."""
    if isinstance(site, Circle):
        return PointGeometry(site) if site.r2 == 0 else CircleGeometry(site)
    if isinstance(site, Conic):
        if site.kind == "circle":
            a, _, _, d, e, f = site.coefficients
            return CircleGeometry(Circle.from_coefficients(a, 0, a, d, e, f))
        return conic_geometry(site)
    raise TypeError(f"not a site: {site!r} (expected a Circle, a point or a Conic)")
