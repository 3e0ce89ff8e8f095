"""Orientation and incircle of points in the plane: exact signs behind float filters.

The two predicates of Delaunay triangulations of points (thesis §1.2: the Voronoi diagram of
points is dual to it), written once for the whole library, after CGAL's ``Filtered_predicate``:
a float evaluation with a proved error bound decides when the value clears the bound
(:func:`filtered_sign`); otherwise the same determinant is evaluated exactly, in integers (every
float and every rational is a multiple of one common 1/den, so the points times ``den`` are
integers and the sign is unchanged).

Float filters (inputs that are floats, so exact as given):

* orientation: Shewchuk's ``ccwerrboundA`` = (3 + 16ε)ε times |l| + |r|, where det = l − r
  (*Adaptive precision floating-point arithmetic and fast robust geometric predicates*, DCG 18
  (1997), §4.2, ε = 2⁻⁵³);
* incircle: Shewchuk's ``iccerrboundA`` = (10 + 96ε)ε times the permanent.

Both bounds assume no underflow and no overflow.  The filter therefore decides only when every
nonzero coordinate difference it computed lies in [2⁻²⁵⁰, 2²⁵⁰]: then every product of at most
four of them is a normal float (2⁻¹⁰⁰⁰ … 2¹⁰⁰⁰) and the sums of three stay finite; a zero
difference is exact.  Anything else (tiny, huge, inf or NaN) goes to the exact path.

Rational inputs (``fractions.Fraction`` or ints, e.g. the exact ends of segment sites) are first
rounded to floats x̂ = fl(x), |x̂ − x| ≤ u|x| with u = 2⁻⁵³ when x is normal (Higham, *Accuracy
and Stability of Numerical Algorithms*, §2.2).  Then |fl-determinant − determinant| ≤ 6u·M +
O(u²)·M with M = (|ax| + |ox|)(|by| + |oy|) + (|ay| + |oy|)(|bx| + |ox|) (the argument of
Shewchuk's bound with the conversion added); the filter takes 16u·M plus 2⁻¹⁰⁰⁰ for underflow in
the products, and decides only when every nonzero rounded coordinate lies in [2⁻²⁵⁰, 2²⁵⁰] (so
the conversion error is relative and the products of two coordinates are normal).

Public API: :func:`filtered_sign`, :func:`orient2d`, :func:`incircle`, and the vectorised
:func:`orient2d_signs`, :func:`incircle_signs` (float arrays; rows the filter leaves undecided
are decided exactly one by one).
"""
from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

__all__ = ["filtered_sign", "orient2d", "incircle", "orient2d_filter", "orient2d_signs",
           "incircle_filter", "incircle_signs", "ORIENT_BOUND", "INCIRCLE_BOUND"]

EPS = 2.0 ** -53
#: Shewchuk's ccwerrboundA: |fl(det) − det| ≤ ORIENT_BOUND·(|l| + |r|) for float inputs
ORIENT_BOUND = (3 + 16 * EPS) * EPS
#: Shewchuk's iccerrboundA: |fl(det) − det| ≤ INCIRCLE_BOUND·permanent for float inputs
INCIRCLE_BOUND = (10 + 96 * EPS) * EPS
#: the rational inputs' filter factor (module docstring: 16u, more than twice the 6u derived)
ORIENT_RATIONAL = 16 * EPS
#: underflow allowance of the rational filter (products of two normal floats' differences)
TINY = 2.0 ** -1000
#: the range in which every nonzero difference must lie for a filter to decide
SAFE_LO, SAFE_HI = 2.0 ** -250, 2.0 ** 250


def filtered_sign(value: float, bound: float, exact, *args) -> int:
    """The sign of a determinant: ``value`` (its float evaluation) decides when |value| > bound,
    ``bound`` a proved bound of the evaluation's error; else ``exact(*args)`` (returning the
    exact sign) does.  NaN and infinities never decide (every comparison is false)."""
    if value > bound:
        return 1
    if value < -bound:
        return -1
    return exact(*args)


def _safe(*xs) -> bool:
    """Every nonzero x in [SAFE_LO, SAFE_HI] (False for inf and NaN)."""
    return all(x == 0 or SAFE_LO <= abs(float(x)) <= SAFE_HI for x in xs)


def _ratio(v) -> tuple[int, int]:
    """(numerator, denominator) of a float (its exact binary value) or a rational."""
    if isinstance(v, (float, np.floating)):
        return float(v).as_integer_ratio()
    q = Fraction(v)
    return q.numerator, q.denominator


def _integers(points) -> list:
    """The points times the least common denominator of their coordinates: integer pairs with
    the same orientation and incircle signs (a positive common factor)."""
    fr = [(_ratio(x), _ratio(y)) for x, y in points]
    den = math.lcm(*(d for p in fr for _, d in p))
    return [(nx * (den // dx), ny * (den // dy)) for (nx, dx), (ny, dy) in fr]


def _sign(v) -> int:
    return (v > 0) - (v < 0)


def _orient_exact(a, b, c) -> int:
    (ax, ay), (bx, by), (cx, cy) = _integers((a, b, c))
    return _sign((bx - ax) * (cy - ay) - (by - ay) * (cx - ax))


def _incircle_exact(a, b, c, d) -> int:
    pa, pb, pc, (dx, dy) = _integers((a, b, c, d))
    (ax, ay), (bx, by), (cx, cy) = [(x - dx, y - dy) for x, y in (pa, pb, pc)]
    return _sign((ax * ax + ay * ay) * (bx * cy - by * cx) + (bx * bx + by * by) * (cx * ay - cy * ax)
                 + (cx * cx + cy * cy) * (ax * by - ay * bx))


def _all_floats(*xs) -> bool:
    return all(isinstance(x, (float, np.floating)) for x in xs)


def orient2d(a, b, c) -> int:
    """The exact sign of the orientation of (a, b, c): 1 counter-clockwise, −1 clockwise, 0 on
    one line.  Coordinates are floats (numpy's included) or rationals (Fraction, int); the filter
    of the module docstring for each, then integers."""
    (ax, ay), (bx, by), (cx, cy) = a, b, c
    if _all_floats(ax, ay, bx, by, cx, cy):
        ux, uy, vx, vy = bx - ax, by - ay, cx - ax, cy - ay
        if not _safe(ux, uy, vx, vy):
            return _orient_exact(a, b, c)
        l, r = ux * vy, uy * vx
        return filtered_sign(l - r, ORIENT_BOUND * (abs(l) + abs(r)), _orient_exact, a, b, c)
    try:
        fa, fb, fc = [(float(x), float(y)) for x, y in (a, b, c)]
    except OverflowError:
        return _orient_exact(a, b, c)
    (ox, oy), (px, py), (qx, qy) = fa, fb, fc
    if not _safe(ox, oy, px, py, qx, qy):
        return _orient_exact(a, b, c)
    det = (px - ox) * (qy - oy) - (py - oy) * (qx - ox)
    M = (abs(px) + abs(ox)) * (abs(qy) + abs(oy)) + (abs(py) + abs(oy)) * (abs(qx) + abs(ox))
    return filtered_sign(det, ORIENT_RATIONAL * M + TINY, _orient_exact, a, b, c)


def incircle(a, b, c, d) -> int:
    """The exact sign of incircle(a, b, c, d) (float points filtered, others exact): for (a, b, c) counter-clockwise,
    1 when d is strictly inside their circle, 0 on it, −1 outside (Guibas–Stolfi's determinant)."""
    if not _all_floats(*a, *b, *c, *d):
        return _incircle_exact(a, b, c, d)
    rows = [(p[0] - d[0], p[1] - d[1]) for p in (a, b, c)]
    if not _safe(*(v for r in rows for v in r)):
        return _incircle_exact(a, b, c, d)
    (ax, ay), (bx, by), (cx, cy) = rows
    alift, blift, clift = ax * ax + ay * ay, bx * bx + by * by, cx * cx + cy * cy
    det = alift * (bx * cy - by * cx) + blift * (cx * ay - cy * ax) + clift * (ax * by - ay * bx)
    perm = (alift * (abs(bx * cy) + abs(by * cx)) + blift * (abs(cx * ay) + abs(cy * ax))
            + clift * (abs(ax * by) + abs(ay * bx)))
    return filtered_sign(det, INCIRCLE_BOUND * perm, _incircle_exact, a, b, c, d)


def _safe_rows(*cols) -> np.ndarray:
    ok = np.ones(np.broadcast(*cols).shape, bool)
    for v in cols:
        m = np.abs(v)
        ok &= (m == 0) | ((m >= SAFE_LO) & (m <= SAFE_HI))
    return ok


def orient2d_filter(A, B, C):
    """The float filter of :func:`orient2d` on rows of float arrays (n × 2, broadcast):
    (det, decided) with ``decided`` True where sign(det) is the exact sign."""
    A, B, C = (np.asarray(X, float) for X in (A, B, C))
    ux, uy = B[..., 0] - A[..., 0], B[..., 1] - A[..., 1]
    vx, vy = C[..., 0] - A[..., 0], C[..., 1] - A[..., 1]
    l, r = ux * vy, uy * vx
    det = l - r
    with np.errstate(invalid="ignore", over="ignore"):
        decided = (np.abs(det) > ORIENT_BOUND * (np.abs(l) + np.abs(r))) & _safe_rows(ux, uy, vx, vy)
    return det, decided


def orient2d_signs(A, B, C) -> np.ndarray:
    """Exact orientation signs of the rows (A[i], B[i], C[i]) of float arrays (broadcast)."""
    det, decided = orient2d_filter(A, B, C)
    out = np.sign(det).astype(np.int8)
    A, B, C = np.broadcast_arrays(*(np.asarray(X, float) for X in (A, B, C)))
    for i in zip(*np.nonzero(~decided)):
        out[i] = _orient_exact(A[i], B[i], C[i])
    return out


def incircle_filter(A, B, C, D):
    """The float filter of :func:`incircle` on rows of float arrays: (det, decided)."""
    A, B, C, D = (np.asarray(X, float) for X in (A, B, C, D))
    a, b, c = A - D, B - D, C - D
    la, lb, lc = (x[..., 0] ** 2 + x[..., 1] ** 2 for x in (a, b, c))
    t1 = b[..., 0] * c[..., 1] - b[..., 1] * c[..., 0]
    t2 = c[..., 0] * a[..., 1] - c[..., 1] * a[..., 0]
    t3 = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]
    det = la * t1 + lb * t2 + lc * t3
    perm = (la * (np.abs(b[..., 0] * c[..., 1]) + np.abs(b[..., 1] * c[..., 0]))
            + lb * (np.abs(c[..., 0] * a[..., 1]) + np.abs(c[..., 1] * a[..., 0]))
            + lc * (np.abs(a[..., 0] * b[..., 1]) + np.abs(a[..., 1] * b[..., 0])))
    with np.errstate(invalid="ignore", over="ignore"):
        decided = (np.abs(det) > INCIRCLE_BOUND * perm) & _safe_rows(*(x[..., k] for x in (a, b, c) for k in (0, 1)))
    return det, decided


def incircle_signs(A, B, C, D) -> np.ndarray:
    """Exact incircle signs of the rows of float arrays (broadcast)."""
    det, decided = incircle_filter(A, B, C, D)
    out = np.sign(det).astype(np.int8)
    A, B, C, D = np.broadcast_arrays(*(np.asarray(X, float) for X in (A, B, C, D)))
    for i in zip(*np.nonzero(~decided)):
        out[i] = _incircle_exact(A[i], B[i], C[i], D[i])
    return out
