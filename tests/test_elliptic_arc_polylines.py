"""The polylines of the edges between an elliptic piece and a point site
(runtime/segments/ellipse_bisectors.py, runtime/segments/polyline_refinement.py) are within the
tolerance each edge states, by a reference built here in mpmath from the exact site data.

The bisector of a piece e(φ) = c + cos φ M + sin φ N and a point p, where e(φ) is the nearest point
of the piece, lies on the normal at e(φ) (thesis ch. 4, the offset of the piece at distance t):
γ(φ) = e(φ) + s n(φ) with |γ − p| = |s|, i.e. s = |p − e|² / (2 n·(p − e)).  The reference finds
each polyline node's foot φ on the piece by dense sampling and golden section of |q − e(φ)|²
(the nearest interior local minimum: at an edge's end vertex the piece's end may tie with it), and
checks

* the Hausdorff distance between the polyline and γ over the feet of its two ends (γ densely
  sampled, its maximum distance refined by golden section);
* the bound a certificate can prove for the drawing: every node's distance to γ(φ_node) plus,
  for each chord between consecutive nodes, the smaller of the linear interpolation error
  Δφ²/8 · max|γ''| (de Boor, *A Practical Guide to Splines*, ch. II) and ℓ²κ/8 (arc length ℓ,
  curvature κ) where ℓκ < π/2; γ', γ'' by mpmath's differentiation at five points of each
  step.  A chord drawn by its middle point's deviation alone can miss it a hundredfold where the
  point runs fast along a nearly straight bisector (an end vertex far out).

The certificate's own bound (:func:`runtime.segments.certificate_curves.polyline_bound` with the
foot curve :class:`runtime.segments.certificate_ellipse_curves.FootCurve`) then confirms each
polyline within its stated tolerance; the slow test runs the whole certificate on the scenes.
"""
from __future__ import annotations

import mpmath as mp
import numpy as np
import pytest

import curvedvoronoi as cv
from curvedvoronoi.runtime.segments.certificate_curves import polyline_bound
from curvedvoronoi.runtime.segments.certificate_ellipse_curves import FootCurve
from curvedvoronoi.runtime.segments.certificate_sites import SiteTable

pytestmark = pytest.mark.mpmath_dps(25)

ELL = ((0, 0), (2, 0), "1/2")
# (start, end parameter, points): the scenes of the issue, then three drawn like them
# (parameters in [0, 6) and spans in [0.5, 2.5] to 2 decimals, integer points in [-6, 6]² outside
# the ellipse's 1.5-level set)
SCENES = [
    (0.2, 1.3, [(5, 5), (-4, 1), (0, -3)]),
    (3.64, 5.6, [(2, 1), (1, 6), (-3, 4), (2, -6)]),
    (1.8, 3.14, [(-1, -6), (-6, -5), (-6, 2), (0, 2)]),
    (2.92, 5.19, [(-6, 6), (0, -2), (2, 1), (-3, -2)]),
    (3.82, 4.86, [(-2, -6), (-6, -6), (-4, 4), (2, 5)]),
    (5.14, 5.71, [(3, 3), (5, -4), (-5, 5), (-6, 1)]),
    (4.13, 5.41, [(5, -5), (1, 3), (4, 0), (-2, -2)]),
]


def _mp(x):
    return mp.mpf(x.numerator) / x.denominator


class Reference:
    """The piece and the point from the exact data (rational centre, axes, end directions)."""

    def __init__(self, piece, p):
        self.c = [_mp(v) for v in piece.c]
        self.M = [_mp(v) for v in piece.M]
        self.N = [_mp(v) for v in piece.N]
        u0, u1 = [_mp(v) for v in piece.ua], [_mp(v) for v in piece.ub]
        a0 = mp.atan2(u0[1], u0[0])
        if a0 < piece.phi0 - 1:
            a0 += 2 * mp.pi
        span = mp.atan2(u0[0] * u1[1] - u0[1] * u1[0], u0[0] * u1[0] + u0[1] * u1[1])
        self.p0, self.p1 = a0, a0 + (span if span > 0 else span + 2 * mp.pi)
        self.p = [_mp(v) for v in p]

    def e(self, f):
        C, S = mp.cos(f), mp.sin(f)
        return [self.c[k] + C * self.M[k] + S * self.N[k] for k in (0, 1)]

    def gamma(self, f):
        e = self.e(f)
        C, S = mp.cos(f), mp.sin(f)
        tx, ty = -S * self.M[0] + C * self.N[0], -S * self.M[1] + C * self.N[1]
        L = mp.sqrt(tx * tx + ty * ty)
        n = [ty / L, -tx / L]
        w = [self.p[0] - e[0], self.p[1] - e[1]]
        s = (w[0] ** 2 + w[1] ** 2) / (2 * (n[0] * w[0] + n[1] * w[1]))
        return [e[0] + s * n[0], e[1] + s * n[1]]

    def _d2(self, q, f):
        e = self.e(f)
        return (q[0] - e[0]) ** 2 + (q[1] - e[1]) ** 2

    def _golden(self, q, lo, hi):
        """A critical point of |q − e|² next to its golden section's minimum on [lo, hi] (to
        10⁻⁸): the root of (q − e)·e' there, or None (the minimum is at an end of the piece)."""
        g = (mp.sqrt(5) - 1) / 2
        while hi - lo > mp.mpf(10) ** -8:
            x1, x2 = hi - g * (hi - lo), lo + g * (hi - lo)
            if self._d2(q, x1) < self._d2(q, x2):
                hi = x2
            else:
                lo = x1

        def slope(f):
            e, C, S = self.e(f), mp.cos(f), mp.sin(f)
            return sum((q[k] - e[k]) * (-S * self.M[k] + C * self.N[k]) for k in (0, 1))
        try:
            f = mp.findroot(slope, (lo + hi) / 2, solver="secant")
        except (ValueError, ZeroDivisionError):
            f = None
        return f if f is not None and lo - mp.mpf(10) ** -7 <= f <= hi + mp.mpf(10) ** -7 else None

    def foot(self, q, n=80):
        """The nearest critical point of |q − e(φ)| on the closed piece (a local minimum: at an
        edge's end vertex the piece's end may tie with it), else the nearer end."""
        q = [mp.mpf(float(v)) for v in q]
        fs = [self.p0 + (self.p1 - self.p0) * k / n for k in range(n + 1)]
        ds = [self._d2(q, f) for f in fs]
        best = None
        for k in range(n + 1):
            a, b = max(k - 1, 0), min(k + 1, n)
            if ds[k] <= ds[a] and ds[k] <= ds[b]:
                f = self._golden(q, fs[a], fs[b])
                inside = f is not None and self.p0 - mp.mpf(10) ** -12 <= f <= self.p1 + mp.mpf(10) ** -12
                if inside and (best is None or self._d2(q, f) < self._d2(q, best)):
                    best = f
        return best if best is not None else (fs[0] if ds[0] <= ds[-1] else fs[-1])


def _chord_bound(ref, f0, f1):
    """The distance bound of γ over [f0, f1] from its chord: the smaller of Δφ²/8 · max|γ''| (the
    linear interpolation error) and, where the turning ℓκ is below π/2, ℓ²κ/8 (ℓ ≤ Δφ max|γ'|
    the arc length, κ ≤ max|γ' × γ''| / min|γ'|³: the distance from the chord's line, in arc
    length, vanishes at both ends and has second derivative at most κ), the maxima and minimum
    over five points of the step."""
    d1, d2 = [], []
    for m in range(5):
        f = f0 + (f1 - f0) * m / 4
        d1.append([mp.diff(lambda x: ref.gamma(x)[c], f, 1) for c in (0, 1)])
        d2.append([mp.diff(lambda x: ref.gamma(x)[c], f, 2) for c in (0, 1)])
    w = abs(f1 - f0)
    out = w ** 2 / 8 * max(mp.norm(g) for g in d2)
    low = min(mp.norm(g) for g in d1)
    if low > 0:
        ell = w * max(mp.norm(g) for g in d1)
        kappa = max(abs(a[0] * b[1] - a[1] * b[0]) for a, b in zip(d1, d2)) / low ** 3
        if ell * kappa < mp.pi / 2:
            out = min(out, ell ** 2 * kappa / 8)
    return float(out)


def _poly_dist(Q, V):
    """Distances from the points Q (k × 2) to the polyline V (floats)."""
    A, D = V[:-1], np.diff(V, axis=0)
    L2 = np.where((D * D).sum(1) > 0, (D * D).sum(1), 1.0)
    W = Q[:, None, :] - A[None, :, :]
    u = np.clip((W * D[None]).sum(2) / L2[None], 0, 1)
    return np.hypot(*np.moveaxis(W - u[..., None] * D[None], 2, 0)).min(axis=1)


def _foreign_point_edges(D):
    E = D.elementary
    for e in D.edges:
        i, j = e.sites
        for s, p in ((i, j), (j, i)):
            if s in E.ellipse and p < E.n_points and p not in E.ends[s] and None not in e.ends:
                yield e, s, p


def _diagram(k):
    a0, a1, pts = SCENES[k]
    return cv.voronoi([cv.Arc.elliptic(*ELL, a0, a1)] + pts, certify=False)


@pytest.fixture(scope="module", params=range(len(SCENES)))
def diagram(request):
    return _diagram(request.param)


def test_every_polyline_is_within_its_tolerance_of_the_true_bisector(diagram):
    E = diagram.elementary
    checked = 0
    for e, s, p in _foreign_point_edges(diagram):
        ref = Reference(E.ellipse[s], E.xy[p])
        V = np.asarray(e.polyline, float)
        feet = [ref.foot(q) for q in V]
        node_dev = max(float(mp.sqrt(sum((g - mp.mpf(float(x))) ** 2 for g, x in zip(ref.gamma(f), q))))
                       for f, q in zip(feet, V))
        # the nodes lie on the bisector, in the order of their feet
        assert node_dev <= 1e-9 * (1 + np.abs(V).max()), (e.id, node_dev)
        steps = np.diff([float(f) for f in feet])
        assert (steps > 0).all() or (steps < 0).all(), e.id
        # Hausdorff distance, both ways
        fa, fb = feet[0], feet[-1]
        fs = [fa + (fb - fa) * k / 2000 for k in range(2001)]
        G = np.array([[float(v) for v in ref.gamma(f)] for f in fs])
        dc = _poly_dist(G, V)
        k = int(np.argmax(dc))
        lo, hi = fs[max(k - 1, 0)], fs[min(k + 1, 2000)]
        far = lambda f: -float(_poly_dist(np.array([[float(v) for v in ref.gamma(f)]]), V)[0])  # noqa: E731
        g = (mp.sqrt(5) - 1) / 2
        for _ in range(50):
            x1, x2 = hi - g * (hi - lo), lo + g * (hi - lo)
            lo, hi = (lo, x2) if far(x1) < far(x2) else (x1, hi)
        to_curve = max(float(dc.max()), -far((lo + hi) / 2))
        U = np.linspace(0, 1, 9)[:, None, None]
        dense = (V[:-1][None] + U * np.diff(V, axis=0)[None]).reshape(-1, 2)
        to_polyline = float(_poly_dist(dense, G).max())
        assert max(to_curve, to_polyline) <= e.tolerance, (e.id, to_curve, to_polyline, e.tolerance)
        # the chord error bound of every chord
        worst = max(_chord_bound(ref, f0, f1) for f0, f1 in zip(feet, feet[1:]))
        assert node_dev + worst <= e.tolerance, (e.id, node_dev + worst, e.tolerance)
        checked += 1
    assert checked, "the scene has an edge of a piece and a point between two vertices"


def test_the_certificate_s_bound_confirms_every_polyline(diagram):
    E = diagram.elementary
    T = SiteTable(diagram.sites)
    for e, s, p in _foreign_point_edges(diagram):
        V = np.asarray(e.polyline, float)
        ref = Reference(E.ellipse[s], E.xy[p])
        q = V[len(V) // 2]
        f = ref.foot(q)
        e_, g_ = ref.e(f), ref.gamma(f)
        C, S = mp.cos(f), mp.sin(f)
        tx, ty = -S * ref.M[0] + C * ref.N[0], -S * ref.M[1] + C * ref.N[1]
        sigma = 1 if (g_[0] - e_[0]) * ty - (g_[1] - e_[1]) * tx > 0 else -1   # outer side: +1
        msg = polyline_bound(FootCurve(T, s, p, sigma, 1), V, float(e.tolerance), None, None, (None, None))
        assert msg is None, (e.id, msg)


@pytest.mark.slow
@pytest.mark.parametrize("k", range(4))
def test_the_certificate_refuses_no_polyline_of_the_issue_s_scenes(k):
    a0, a1, pts = SCENES[k]
    D = cv.voronoi([cv.Arc.elliptic(*ELL, a0, a1)] + pts)
    assert not [str(q) for q in D.problems if "is not within its tolerance" in str(q)]
