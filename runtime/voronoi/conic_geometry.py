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
The closest point of q on C (per branch for the hyperbola) and the outward unit normal of K
there come from :mod:`runtime.sites.foot_points` (the bracketed root of the normal condition,
thesis §5.2, by safeguarded Newton iteration, vectorised over the query points).  The point is
evaluated from its parameter, so it lies on the curve to rounding.  The rigorous bounds below
hold for any parameter; the accuracy of the root only decides their tightness (and hence how
often the ball route is needed).

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

Length: the three conic kinds share the rounding allowances that their rigorous bounds are
proved with; splitting them would separate a bound from its proof.
"""
from __future__ import annotations

import math

import numpy as np

from ..predicates.circles import Circle
from ..sites.conic import Conic
from ..sites.kinds import SiteKind
from ..sites.intersection import conic_value, exact_coefficients
from ..sites.foot_points import ellipse_feet, ellipse_foot_points, feet_to_world, hyperbola_feet, parabola_feet
from .geometry import EPS, CircleGeometry, PointGeometry, SiteGeometry, rounding_slack

__all__ = ["ConicGeometry", "CentralConicGeometry", "EllipseGeometry", "HyperbolaGeometry", "ParabolaGeometry",
           "conic_geometry", "site_geometry", "site_inside", "ellipse_feet",
           "ellipse_foot_points", "ellipse_samples"]

#: relative gap above which the fast bounds defer to the ball route
_FALLBACK_GAP = 1e-7


class ConicGeometry(SiteGeometry):
    """Common part of the conic geometries: canonical frame, transforms, bounds driver."""

    def __init__(self, conic: Conic):
        if not isinstance(conic, Conic):
            raise TypeError(f"expected a Conic, got {conic!r}")
        self.exact = conic
        fr = conic.frame
        self.kind = SiteKind.of(fr.kind).label
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
        return feet_to_world(P, X, Y, NX, NY, self.c, self.s, self.tx, self.ty)

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


#: ellipses sampled together by :func:`ellipse_samples`, and distinct shapes whose arc-length
#: tables are made together (its temporaries: a few arrays of this many rows × 2048 floats)
SAMPLE_BLOCK = 256
#: more samples than this on one ellipse: its own ``np.interp`` (linear in the table) is faster
#: than the blocks' bisection (logarithmic per sample)
DENSE = 256
#: parameters of the arc-length table (as :meth:`ConicGeometry._sample_param`)
TABLE = 2048


def ellipse_samples(geoms, spacings):
    """The samples of many ellipses, ``geoms[k].samples(spacings[k])`` for every k, as one array
    and the number of samples of each: the same points, float for float (the arc-length table
    of :meth:`ConicGeometry._sample_param` on 2048 parameters, its ``np.linspace`` and
    ``np.interp`` evaluated for a block of ellipses at once; an ellipse with more than
    :data:`DENSE` samples is sampled by its own method).  The table depends on the semi-axes
    only: it is made once for the ellipses of one shape (a, b) (translated and rotated copies)."""
    tt = np.linspace(0.0, 2 * math.pi, TABLE)
    ct, st = np.cos(tt), np.sin(tt)
    sp = np.maximum(np.asarray(spacings, float).reshape(-1), 1e-300)
    a = np.array([g.a for g in geoms], dtype=float)
    b = np.array([g.b for g in geoms], dtype=float)
    parts = [None] * len(geoms)
    # the table only where the samples may be few (the perimeter exceeds 4a: more than DENSE
    # samples for sure are left to the ellipse's own method, which builds its table itself)
    tab = np.nonzero(4.4 * a <= DENSE * sp)[0]
    if len(tab):
        shapes, shape = np.unique(np.column_stack([a[tab], b[tab]]), axis=0, return_inverse=True)
        by_shape = np.argsort(shape.reshape(-1), kind="stable")
        cut = np.searchsorted(shape.reshape(-1)[by_shape], np.arange(0, len(shapes) + SAMPLE_BLOCK, SAMPLE_BLOCK))
        for blk in range(len(cut) - 1):
            L, ok, cum = _arc_tables(shapes[blk * SAMPLE_BLOCK:(blk + 1) * SAMPLE_BLOCK], ct, st)
            mine = by_shape[cut[blk]:cut[blk + 1]]
            for c0 in range(0, len(mine), SAMPLE_BLOCK):
                sub = mine[c0:c0 + SAMPLE_BLOCK]
                _table_samples(geoms, tab[sub], shape.reshape(-1)[sub] - blk * SAMPLE_BLOCK, sp, (L, ok, cum, tt), parts)
    for c, part in enumerate(parts):
        if part is None:
            parts[c] = np.asarray(geoms[c].samples(float(spacings[c])), float).reshape(-1, 2)
    counts = np.array([len(p) for p in parts], dtype=np.int64)
    return (np.concatenate(parts) if parts else np.zeros((0, 2))), counts


def _arc_tables(shapes, ct, st):
    """For the semi-axes ``shapes`` (rows (a, b)): the chord lengths' sum L of the polyline of
    (a cos t, b sin t) on the table's parameters, whether every chord is positive and L finite,
    and the cumulative chord lengths (the table of :meth:`ConicGeometry._sample_param`)."""
    seg = np.hypot(np.diff(shapes[:, :1] * ct, axis=1), np.diff(shapes[:, 1:] * st, axis=1))
    L = seg.sum(axis=1)
    return L, (seg > 0).all(axis=1) & np.isfinite(L), np.cumsum(seg, axis=1)


def _table_samples(geoms, rows, sh, sp, tables, parts):
    """The samples of the ellipses ``geoms[rows]`` (their shapes' rows ``sh`` of ``tables``) that
    have at most :data:`DENSE` samples, into ``parts``: ``np.linspace(0, L, n)`` and ``np.interp``
    on the table, float for float (the others are left to their own method)."""
    L, ok, cum, tt = tables
    m = len(tt)
    need = np.ceil(1.1 * L[sh] / sp[rows]) + 1
    n = np.minimum(np.maximum(np.where(np.isfinite(need), need, 2.0 ** 62), 2), 2_000_000).astype(np.int64)
    few = (n <= DENSE) & ok[sh]
    rows, sh, nr = rows[few], sh[few], n[few]
    q = np.repeat(np.arange(len(rows)), nr)
    r = sh[q]
    k = np.arange(len(q)) - np.repeat(np.cumsum(nr) - nr, nr)
    # np.linspace(0, L, n): k·(L/(n − 1)) + 0 (its last point, L, is the first again: dropped
    # below); np.interp on the table (cum non-decreasing): on [cum[j], cum[j + 1]) the slope
    # (t[j + 1] − t[j])/(cum[j + 1] − cum[j]) times (x − cum[j]) plus t[j], at the end t[m − 1]
    x = k * (L[r] / (nr[q] - 1)) + 0.0
    last = k == nr[q] - 1
    # j = np.searchsorted(cum[row], x, side="right"), the number of table sums ≤ x (cum is
    # non-decreasing), by bisection on all rows at once
    j, hi = np.zeros(len(x), np.int64), np.full(len(x), m - 1, np.int64)
    while (j < hi).any():
        mid = (j + hi) // 2
        le = cum[r, np.minimum(mid, m - 2)] <= x
        j, hi = np.where(le, mid + 1, j), np.where(le, hi, mid)
    prev = np.where(j > 0, cum[r, np.maximum(j - 1, 0)], 0.0)
    nxt = cum[r, np.minimum(j, m - 2)]
    with np.errstate(divide="ignore", invalid="ignore"):     # j = m − 1: the end, no slope
        slope = (tt[np.minimum(j + 1, m - 1)] - tt[j]) / (nxt - prev)
    tq = np.where(j >= m - 1, tt[m - 1], slope * (x - prev) + tt[np.minimum(j, m - 1)])
    G = [geoms[c] for c in rows.tolist()]
    gx = np.array([g.a for g in G])[q] * np.cos(tq)
    gy = np.array([g.b for g in G])[q] * np.sin(tq)
    cc, ss, tx, ty = (np.array([getattr(g, v) for g in G])[q] for v in ("c", "s", "tx", "ty"))
    P = np.column_stack([tx + cc * gx - ss * gy, ty + ss * gx + cc * gy])
    keep = ~last                      # the last point repeats the first
    for c, part in zip(rows.tolist(), np.split(P[keep], np.cumsum(nr - 1)[:-1])):
        parts[c] = part


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

    def _feet_canonical(self, X0, Y0):
        return hyperbola_feet(X0, Y0, self.a, self.b)

    def _branch_feet(self, X0, Y0, first):
        X2, Y2, NX2, NY2, _ = hyperbola_feet(X0, Y0, self.a, self.b, far_branch=True)
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
        return parabola_feet(X0, Y0, self.p)

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
    make = {SiteKind.ELLIPSE: EllipseGeometry, SiteKind.HYPERBOLA: HyperbolaGeometry,
            SiteKind.PARABOLA: ParabolaGeometry}.get(SiteKind.of(conic.kind))
    return site_geometry(conic) if make is None else make(conic)


def site_inside(A, B) -> bool:
    """For two disjoint sites (:func:`runtime.sites.intersection.sites_intersect` false): whether A lies in the open region
    {g_B < 0} bounded by B (inside an ellipse or circle, on the focus side of a parabola, inside
    a hyperbola branch).  A point of A is tested with an exact rational evaluation of g_B (signs
    normalised so that g_B < 0 on B's convex side); A is connected per branch, and every
    component of A lies on one side since A does not meet B, so one point per component decides
    (a hyperbola A is inside only if both branches are).  The tested point is the float vertex
    of A's canonical frame (within ~1e-16 relative of A), so the answer is exact unless A and B
    are closer than that."""
    from fractions import Fraction

    cb = exact_coefficients(B)
    if cb[0] == "point":
        return False
    a, b, c, d, e, f = cb
    ca = exact_coefficients(A)
    if ca[0] == "point":
        pts = [(ca[1], ca[2])]
    else:
        geo = site_geometry(A)
        kind = SiteKind.of(geo.kind)
        if kind is SiteKind.CIRCLE:
            P = np.array([[geo.cx + geo.rho, geo.cy]])
        elif kind is SiteKind.HYPERBOLA:
            P = np.vstack([geo.from_canonical(np.array([geo.a]), np.array([0.0])),
                           geo.from_canonical(np.array([-geo.a]), np.array([0.0]))])
        elif kind is SiteKind.ELLIPSE:
            P = geo.from_canonical(np.array([geo.a]), np.array([0.0]))
        else:
            P = geo.from_canonical(np.array([0.0]), np.array([0.0]))
        pts = [(Fraction(float(p[0])), Fraction(float(p[1]))) for p in P]
    # sign convention: s·f_B < 0 on the convex side; reference point certainly there: the
    # centre (ellipse/circle), a point of the axis beyond the vertex (parabola, hyperbola)
    if isinstance(B, Conic) and SiteKind.of(B.kind).bounded:         # an ellipse or a circle
        den = 4 * a * c - b * b
        ref = ((b * e - 2 * c * d) / den, (b * d - 2 * a * e) / den)
    elif not isinstance(B, Conic):
        ref = (Fraction(int(B.cx.p), int(B.cx.q)), Fraction(int(B.cy.p), int(B.cy.q)))
    else:
        gb = site_geometry(B)
        far = 2 * gb._sz() + 1.0
        ref = tuple(Fraction(float(v)) for v in gb.from_canonical(np.array([far]), np.array([0.0]))[0])
    s = -1 if conic_value((a, b, c, d, e, f), *ref) > 0 else 1
    return all(s * conic_value((a, b, c, d, e, f), px, py) < 0 for px, py in pts)


def site_geometry(site) -> SiteGeometry:
    """The geometry of a site: a :class:`runtime.sites.circle.Circle` (r2 = 0 is a point), a
    :class:`runtime.sites.conic.Conic` (circles among them go to :class:`CircleGeometry`)."""
    if isinstance(site, Circle):
        return PointGeometry(site) if site.r2 == 0 else CircleGeometry(site)
    if isinstance(site, Conic):
        if SiteKind.of(site.kind) is SiteKind.CIRCLE:
            a, _, _, d, e, f = site.coefficients
            return CircleGeometry(Circle.from_coefficients(a, 0, a, d, e, f))
        return conic_geometry(site)
    raise TypeError(f"not a site: {site!r} (expected a Circle, a point or a Conic)")
