"""Filtered, batched circle conflict locator (thesis §3.1.3, CGAL-style filtering).

The predicate of :mod:`runtime.predicates.circles` is evaluated for many queries at once in vectorised
numpy *interval arithmetic*: every floating-point operation is followed by an outward step
``nextafter`` so that the true real value of every intermediate quantity lies in the computed
interval (round-to-nearest errors are at most half an ulp; overflow gives ±inf, invalid
operations NaN, and NaN/inf never decide a sign).  A query is *decided by the filter* only if
every sign the exact algorithm needs (determinant of the linear part, leading coefficient and
discriminant of each quadratic in R, sign of R, the three validity signs ρ_i + s_i R, and the
conflict signs g, ρ4 - ρ, h) is certain from its interval.  All other queries (ties, exact
tangencies, collinear or concentric centres, near-degenerate data) go to the exact path,
which is always able to decide.  The inputs are floats taken at their exact binary values, so
both paths answer the same exact question.
"""
from __future__ import annotations

import time
from fractions import Fraction

import numpy as np

from ..result import LocatorError
from .circles import Circle, locate_conflicts_circles

_INF = np.inf


# ------------------------------------------------------------------ interval primitives
# Outward rounding.  A round-to-nearest result r of an exact real x satisfies
# |x - r| <= max(u|r|, 2^-1075) (u = 2^-53).  With e = fl(fl(|r| 2^-50) + 2^-1060) we have
# e >= 2^-51 |r| + 2^-1061, and fl(r - e) <= r - e + max(u|r - e|, 2^-1075) <= r - u|r| - 2^-1075,
# so fl(r - e) <= x (symmetrically fl(r + e) >= x).  r = ±inf gives NaN or ±inf, never a
# wrong finite bound, and NaN never decides a sign.  This costs 4 flops instead of nextafter.
_REL = 2.0 ** -50
_ABS = 2.0 ** -1060


def _err(x):
    return np.abs(x) * _REL + _ABS


def _dn(x):
    return x - _err(x)


def _up(x):
    return x + _err(x)


def _pt(x):
    return (x, x)


def iadd(a, b):
    return _dn(a[0] + b[0]), _up(a[1] + b[1])


def isub(a, b):
    return _dn(a[0] - b[1]), _up(a[1] - b[0])


def ineg(a):
    return -a[1], -a[0]


def imul(a, b):
    p1 = a[0] * b[0]
    p2 = a[0] * b[1]
    p3 = a[1] * b[0]
    p4 = a[1] * b[1]
    return _dn(np.minimum(np.minimum(p1, p2), np.minimum(p3, p4))), _up(np.maximum(np.maximum(p1, p2), np.maximum(p3, p4)))


def isqr(a):
    lo2 = a[0] * a[0]
    hi2 = a[1] * a[1]
    hi = _up(np.maximum(lo2, hi2))
    lo = np.where((a[0] > 0) | (a[1] < 0), _dn(np.minimum(lo2, hi2)), 0.0)
    # NaN propagation: np.where with a NaN condition picks 0.0; keep NaN visible through hi
    return lo, hi


def idiv(a, b):
    """a / b, meaningful only where b does not contain 0 (callers mask those rows)."""
    p1 = a[0] / b[0]
    p2 = a[0] / b[1]
    p3 = a[1] / b[0]
    p4 = a[1] / b[1]
    return _dn(np.minimum(np.minimum(p1, p2), np.minimum(p3, p4))), _up(np.maximum(np.maximum(p1, p2), np.maximum(p3, p4)))


def isqrt(a):
    return _dn(np.sqrt(np.maximum(a[0], 0.0))), _up(np.sqrt(a[1]))


def ihalf(a):
    return _dn(a[0] * 0.5), _up(a[1] * 0.5)


def pos(a):
    return a[0] > 0


def neg(a):
    return a[1] < 0


def nonzero(a):
    return (a[0] > 0) | (a[1] < 0)


SIGN_SYSTEMS = ((1, 1, 1), (1, 1, -1), (1, -1, 1), (1, -1, -1))


def filter_circles(X: np.ndarray) -> dict[str, np.ndarray]:
    """Interval filter on a (n, 4, 3) float array of circles (cx, cy, radius).

    Returns arrays ``decided``, ``conflict`` and ``n_vertices`` (meaningful where decided).
    """
    n = X.shape[0]
    with np.errstate(all="ignore"):
        c1x, c1y = X[:, 0, 0], X[:, 0, 1]
        rho = [X[:, i, 2] for i in range(4)]
        r2 = [isqr(_pt(r)) for r in rho]
        d = [None] + [(isub(_pt(X[:, i, 0]), _pt(c1x)), isub(_pt(X[:, i, 1]), _pt(c1y))) for i in (1, 2, 3)]
        (d2x, d2y), (d3x, d3y) = d[1], d[2]
        d4x, d4y = d[3]
        mu = [None] + [ihalf(isub(iadd(iadd(isqr(d[i][0]), isqr(d[i][1])), r2[0]), r2[i])) for i in (1, 2)]
        det = isub(imul(d2x, d3y), imul(d2y, d3x))
        decided = nonzero(det)
        q0x = idiv(isub(imul(mu[1], d3y), imul(mu[2], d2y)), det)
        q0y = idiv(isub(imul(d2x, mu[2]), imul(d3x, mu[1])), det)
        C = isub(iadd(isqr(q0x), isqr(q0y)), r2[0])
        rho1 = _pt(rho[0])
        rho4 = _pt(rho[3])
        nvert = np.zeros(n, dtype=np.int64)
        conflict = np.zeros(n, dtype=bool)
        for s in SIGN_SYSTEMS:
            k2 = isub(rho1, _pt(s[1] * rho[1]))
            k3 = isub(rho1, _pt(s[2] * rho[2]))
            qRx = idiv(isub(imul(k2, d3y), imul(k3, d2y)), det)
            qRy = idiv(isub(imul(d2x, k3), imul(d3x, k2)), det)
            A = isub(iadd(isqr(qRx), isqr(qRy)), (1.0, 1.0))
            Bh = isub(iadd(imul(q0x, qRx), imul(q0y, qRy)), rho1)
            disc = isub(isqr(Bh), imul(A, C))
            decided &= nonzero(A) & nonzero(disc)
            has_roots = pos(disc)
            sq = isqrt(disc)
            mBh = ineg(Bh)
            for root in (iadd(mBh, sq), isub(mBh, sq)):
                R = idiv(root, A)
                Rpos, Rneg = pos(R), neg(R)
                v = [iadd(rho1, R)] + [iadd(_pt(rho[i]), R if s[i] == 1 else ineg(R)) for i in (1, 2)]
                invalid = neg(v[0]) | neg(v[1]) | neg(v[2])
                valid = (Rpos | Rneg) & pos(v[0]) & pos(v[1]) & pos(v[2])
                decided &= ~has_roots | invalid | valid
                live = has_roots & valid
                rad = (np.where(Rpos, R[0], -R[1]), np.where(Rpos, R[1], -R[0]))
                ex = isub(iadd(q0x, imul(R, qRx)), d4x)
                ey = isub(iadd(q0y, imul(R, qRy)), d4y)
                D2 = iadd(isqr(ex), isqr(ey))
                g = isub(D2, isqr(iadd(rho4, rad)))
                sd = isub(rho4, rad)
                h = isub(D2, isqr(sd))
                c_true = neg(g) & (neg(sd) | pos(h))
                c_false = pos(g) | (pos(sd) & neg(h))
                decided &= ~live | c_true | c_false
                nvert += live
                conflict |= live & c_true
    return {"decided": decided, "conflict": conflict, "n_vertices": nvert}


def _validate(X) -> np.ndarray:
    X = np.asarray(X, dtype=np.float64)
    if X.ndim != 3 or X.shape[1:] != (4, 3):
        raise ValueError(f"expected an array of shape (n, 4, 3) = (query, circle C1..C4, (cx, cy, radius)); got {X.shape}")
    bad = ~np.isfinite(X).all(axis=(1, 2))
    if bad.any():
        raise ValueError(f"non-finite (NaN/inf) circle data in queries {np.flatnonzero(bad)[:10].tolist()}")
    neg_r = (X[:, :, 2] < 0).any(axis=1)
    if neg_r.any():
        raise ValueError(f"negative radius in queries {np.flatnonzero(neg_r)[:10].tolist()}")
    return X


def locate_conflicts_circles_batch(X, *, chunk: int = 8192, on_error: str = "raise") -> dict[str, np.ndarray]:
    """Batched conflict locator for circles, filtered then exact (thesis §3.1.3).

    ``X``: array (n, 4, 3) of floats: queries × (C1, C2, C3, C4) × (cx, cy, radius); floats are
    taken at their exact binary values.  Returns a dict of numpy arrays:

    * ``conflict`` (bool): C4 conflicts with some true Voronoi vertex of (C1, C2, C3);
    * ``n_vertices`` (int): number of true Voronoi vertices (-1 where an error was flagged);
    * ``needed_exact`` (bool): the interval filter could not decide, the exact path answered;
    * ``certified`` (bool): the answer is proved (always True unless an error was flagged);
    * ``error`` (bool) and, in ``errors``, a list of (row, message) when ``on_error="flag"``.

    Every answer is exact: the filter only decides signs its rigorous intervals certify.
    With ``on_error="raise"`` (default) a degenerate triple (coincident circles, a continuum of
    equidistant points) raises LocatorError naming the query row.
    """
    if on_error not in ("raise", "flag"):
        raise ValueError("on_error must be 'raise' or 'flag'")
    X = _validate(X)
    n = X.shape[0]
    conflict = np.zeros(n, dtype=bool)
    nvert = np.zeros(n, dtype=np.int64)
    decided = np.zeros(n, dtype=bool)
    t0 = time.perf_counter()
    for a in range(0, n, chunk):
        r = filter_circles(X[a:a + chunk])
        decided[a:a + chunk] = r["decided"]
        conflict[a:a + chunk] = r["conflict"]
        nvert[a:a + chunk] = r["n_vertices"]
    t1 = time.perf_counter()
    error = np.zeros(n, dtype=bool)
    errors: list[tuple[int, str]] = []
    for i in np.flatnonzero(~decided):
        cs = [Circle.from_radius(Fraction(float(X[i, j, 0])), Fraction(float(X[i, j, 1])), Fraction(float(X[i, j, 2])))
              for j in range(4)]
        try:
            res = locate_conflicts_circles(*cs)
        except LocatorError as e:
            if on_error == "raise":
                raise LocatorError(f"query {i}: {e}") from e
            error[i] = True
            errors.append((int(i), str(e)))
            conflict[i] = False
            nvert[i] = -1
            continue
        conflict[i] = res.conflict
        nvert[i] = len(res.vertices)
    t2 = time.perf_counter()
    return {
        "conflict": conflict,
        "n_vertices": nvert,
        "needed_exact": ~decided,
        "certified": ~error,
        "error": error,
        "errors": errors,
        "timings": {"filter": t1 - t0, "exact": t2 - t1},
    }
