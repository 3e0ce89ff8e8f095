"""Euclidean distance from a point to a conic: float foot points and rigorous enclosures.

The distance d(q, C) = min over p ∈ C of |q − p| is the function whose equalities define the
Voronoi diagram of the sites (thesis §5.1–5.2; a Voronoi vertex q has
d(q, C1) = d(q, C2) = d(q, C3)).  Its critical points ("foot points") are the points of C
where q − p is normal to C (thesis §5.2, the normal condition behind Thm 5.2.2).

Float route (:func:`foot_points`, :func:`distance`): in the canonical frame (see
:mod:`runtime.conic`) the normal condition is a univariate polynomial in a parameter that
covers the whole curve:

* ellipse  (a cos θ, b sin θ): quartic in u = tan(θ/2) (θ = π added as a seed);
* hyperbola (σ a √(1 + s²/B), s), σ = ±1: quartic in s = Y (both branches);
* parabola (s²/2p, s): cubic s³ + 2p(p − X0) s − 2p² Y0;
* circle: closed form.

Roots come from ``numpy.roots``; every root with small imaginary part and the curve's
vertices are polished by Newton's method on the derivative of the squared distance in the
smooth parameter, so points on the axes, at the centre and near the evolute are handled.

Rigorous route (:func:`distance_ball`): the canonical frame is computed as python-flint
``arb`` balls from the exact coefficients, q is moved to the canonical frame in ball
arithmetic and the squared distance D(t) along the same parametrisations is minimised by a
rigorous branch and bound (mean value form D(m) + D'(I)(I − m) intersected with the natural
extension).  The curve parameter domain is bounded with an upper bound U of d² (any point
of the curve): |Y − Y0| ≤ √U.  The result encloses d(q, C); for a ball q it encloses
d(q', C) for every q' in the box (d is 1-Lipschitz).
"""
from __future__ import annotations

import math
from fractions import Fraction
from typing import Any

import numpy as np
import flint
from flint import arb

from .conic import Conic, to_fraction
from .result import InvalidConicError

__all__ = ["distance", "foot_points", "distance_ball", "distance_sign_vs", "squared_distance_ball",
           "tangency_polynomial"]


# =========================================================================== float route

def _real_roots(coeffs: list[float], tol: float = 1e-6) -> list[float]:
    c = np.asarray(coeffs, dtype=float)
    nz = np.flatnonzero(np.abs(c) > 0)
    if nz.size == 0:
        return []
    c = c[nz[0]:]
    if c.size <= 1:
        return []
    # scale to avoid overflow in the companion matrix
    c = c / np.max(np.abs(c))
    r = np.roots(c)
    out = []
    for z in r:
        if abs(z.imag) <= tol * (1.0 + abs(z.real)) ** 1:
            out.append(float(z.real))
    return out


def _newton(fun, t0: float, iters: int = 60):
    """Newton on fun(t) -> (g, g') with step control; returns (t, |g|)."""
    t = t0
    g, dg = fun(t)
    for _ in range(iters):
        if g == 0.0 or dg == 0.0 or not math.isfinite(dg):
            break
        step = g / dg
        tn = t - step
        gn, dgn = fun(tn)
        if not math.isfinite(gn):
            break
        # accept only if the residual does not grow too much (keeps us in the basin)
        if abs(gn) > 2.0 * abs(g) and abs(step) > 1e-12 * (1.0 + abs(t)):
            tn = t - 0.5 * step
            gn, dgn = fun(tn)
            if abs(gn) > abs(g):
                break
        if abs(tn - t) <= 4e-16 * (1.0 + abs(t)):
            t, g, dg = tn, gn, dgn
            break
        t, g, dg = tn, gn, dgn
    return t, abs(g)


def _canonical_point(conic: Conic, x: float, y: float):
    fr = conic.frame
    X0, Y0 = fr.to_canonical(float(x), float(y))
    return fr, X0, Y0


def _foot_canonical(kind: str, params: dict, X0: float, Y0: float, all_candidates: bool = False):
    """Critical points of the squared distance from (X0, Y0) to the canonical conic.

    Returns a list of (X, Y, residual_ok).  With ``all_candidates`` the non-converged
    candidates (still points of the curve) are returned too, flagged False.
    """
    out: list[tuple[float, float, bool]] = []
    if kind == "circle":
        r = math.sqrt(params["r2"])
        n = math.hypot(X0, Y0)
        if n == 0.0:
            return [(r, 0.0, True)]  # every point is a foot point; one representative
        return [(r * X0 / n, r * Y0 / n, True), (-r * X0 / n, -r * Y0 / n, True)]

    if kind == "ellipse":
        A, B = params["A2"], params["B2"]
        L = math.sqrt(max(A, B))
        A, B, x0, y0 = A / L ** 2, B / L ** 2, X0 / L, Y0 / L
        a, b = math.sqrt(A), math.sqrt(B)
        scale = abs(B - A) + a * abs(x0) + b * abs(y0) + 1e-300

        def g(th):
            s, c = math.sin(th), math.cos(th)
            return ((B - A) * s * c + a * x0 * s - b * y0 * c,
                    (B - A) * (c * c - s * s) + a * x0 * c + b * y0 * s)

        coeffs = [b * y0, 2 * (a * x0 - (B - A)), 0.0, 2 * (a * x0 + (B - A)), -b * y0]
        seeds = [2 * math.atan(u) for u in _real_roots(coeffs)]
        seeds += [0.0, math.pi / 2, math.pi, 1.5 * math.pi, math.atan2(y0 / b, x0 / a)]
        pts = []
        for th0 in seeds:
            th, res = _newton(g, th0)
            th = math.remainder(th, 2 * math.pi)
            pts.append((th, res <= 1e-9 * scale))
        uniq: list[tuple[float, bool]] = []
        for th, ok in sorted(pts, key=lambda t: (not t[1], t[0])):
            if not ok and not all_candidates:
                continue
            if any(abs(math.remainder(th - u, 2 * math.pi)) < 1e-9 for u, _ in uniq):
                continue
            uniq.append((th, ok))
        return [(L * a * math.cos(th), L * b * math.sin(th), ok) for th, ok in uniq]

    if kind == "hyperbola":
        A, B = params["A2"], params["B2"]
        L = math.sqrt(max(A, B))
        A, B, x0, y0 = A / L ** 2, B / L ** 2, X0 / L, Y0 / L
        a = math.sqrt(A)
        k = A + B
        coeffs = [k * k, -2 * k * B * y0, B * B * y0 * y0 + B * k * k - A * B * x0 * x0,
                  -2 * k * B * B * y0, B ** 3 * y0 * y0]
        seeds = _real_roots(coeffs) + [0.0, y0, y0 * B / k]
        scale = 1.0 + abs(x0) + abs(y0)
        uniq2: list[tuple[float, float, bool]] = []
        for sg in (1.0, -1.0):
            def h(s, sg=sg):
                w = math.sqrt(1.0 + s * s / B)
                X = sg * a * w
                Xp = sg * a * s / (B * w)
                Xpp = sg * a / (B * w ** 3)
                return (X - x0) * Xp + (s - y0), Xp * Xp + (X - x0) * Xpp + 1.0

            for s0 in seeds:
                s, res = _newton(h, s0)
                if not math.isfinite(s):
                    continue
                ok = res <= 1e-9 * scale * (1.0 + abs(s))
                if not ok and not all_candidates:
                    continue
                if any(sg == t[0] and abs(s - t[1]) < 1e-9 * (1.0 + abs(s)) for t in uniq2):
                    continue
                uniq2.append((sg, s, ok))
        return [(L * sg * a * math.sqrt(1.0 + s * s / B), L * s, ok) for sg, s, ok in uniq2]

    if kind == "parabola":
        p = params["p"]
        x0, y0 = X0 / p, Y0 / p  # scaled: p = 1
        coeffs = [1.0, 0.0, 2 * (1 - x0), -2 * y0]

        def cub(s):
            return s ** 3 + 2 * (1 - x0) * s - 2 * y0, 3 * s * s + 2 * (1 - x0)

        seeds = _real_roots(coeffs) + [0.0, y0]
        scale = 1.0 + abs(x0) + abs(y0)
        uniq3: list[tuple[float, bool]] = []
        for s0 in seeds:
            s, res = _newton(cub, s0)
            ok = res <= 1e-9 * scale * (1.0 + s * s) * (1 + abs(s))
            if not ok and not all_candidates:
                continue
            if any(abs(s - t) < 1e-9 * (1.0 + abs(s)) for t, _ in uniq3):
                continue
            uniq3.append((s, ok))
        return [(p * s * s / 2, p * s, ok) for s, ok in uniq3]
    raise InvalidConicError(f"unknown conic kind {kind!r}")


def foot_points(conic: Conic, x, y) -> list[tuple[float, float, float]]:
    """All real critical points of the distance from (x, y) to the curve, as (px, py, dist)
    in world coordinates, sorted by dist.  At the centre of a circle (infinitely many foot
    points) one representative is returned."""
    fr, X0, Y0 = _canonical_point(conic, x, y)
    res = []
    for X, Y, ok in _foot_canonical(fr.kind, fr.params, X0, Y0):
        px, py = fr.from_canonical(X, Y)
        res.append((float(px), float(py), math.hypot(X - X0, Y - Y0)))
    res.sort(key=lambda t: t[2])
    return res


def distance(conic: Conic, x, y) -> float:
    """Euclidean distance from (x, y) to the conic (both branches of a hyperbola)."""
    fr, X0, Y0 = _canonical_point(conic, x, y)
    if fr.kind == "circle":
        return abs(math.hypot(X0, Y0) - math.sqrt(fr.params["r2"]))
    cands = _foot_canonical(fr.kind, fr.params, X0, Y0, all_candidates=True)
    return min(math.hypot(X - X0, Y - Y0) for X, Y, _ in cands)


def closest_point(conic: Conic, x, y) -> tuple[float, float, float]:
    """(px, py, dist) of a closest point of the conic to (x, y)."""
    fr, X0, Y0 = _canonical_point(conic, x, y)
    cands = _foot_canonical(fr.kind, fr.params, X0, Y0, all_candidates=True)
    X, Y, _ = min(cands, key=lambda t: math.hypot(t[0] - X0, t[1] - Y0))
    px, py = fr.from_canonical(X, Y)
    return float(px), float(py), math.hypot(X - X0, Y - Y0)


# =========================================================================== rigorous route

def _as_ball(v, prec: int) -> arb:
    if isinstance(v, arb):
        return v
    if isinstance(v, flint.fmpq):
        return arb(v)
    q = to_fraction(v, "coordinate")
    return arb(flint.fmpq(q.numerator, q.denominator))


def _interval(lo: arb, hi: arb) -> arb:
    return lo.union(hi)


def _taylor_enclosure(derivs, m: arb, I: arb, K: int = 4) -> arb:
    """Enclosure of D over I: sum_{k<K} D^(k)(m) h^k / k! + D^(K)(I) h^K / K!, h = I − m."""
    dm = derivs(m, K - 1)
    dI = derivs(I, K)
    h = I - m
    acc = dI[K] / math.factorial(K)
    for k in range(K - 1, -1, -1):
        acc = acc * h + dm[k] / math.factorial(k)
    return acc


def _bb_minimise(derivs, lo: arb, hi: arb, U: arb, prec: int, max_evals: int = 3000):
    """Rigorous lower bound of min D over [lo, hi] and improved upper bound U.

    ``derivs(t, n)`` returns enclosures of [D(t), D'(t), ..., D^(n)(t)] for an arb t (point
    or interval).  Best-first branch and bound with an order-4 Taylor form intersected with
    the natural extension (the Taylor form keeps the enclosures tight at degenerate minima,
    e.g. at the cusps of the evolute).  Returns (lower, U, evals, exhausted).  Points where D
    is evaluated are exact dyadics, so hi(D(m)) bounds min D from above.
    """
    import heapq

    tol_rel = arb(2) ** (-(prec - 6))
    floor_abs = arb(2) ** (-2 * prec)
    heap: list = []
    counter = 0
    lower_final = None
    evals = 0

    def push(a_, b_):
        nonlocal counter, evals, U
        I = _interval(a_, b_)
        m = ((a_ + b_) / 2).mid()
        Dm = derivs(m, 0)[0]
        evals += 1
        if Dm.upper() < U:
            U = Dm.upper()
        E_nat = derivs(I, 0)[0]
        E_t = _taylor_enclosure(derivs, m, I)
        Elo = E_nat.lower()
        if E_t.lower() > Elo:
            Elo = E_t.lower()
        Ehi = E_nat.upper() if E_nat.upper() < E_t.upper() else E_t.upper()
        counter += 1
        heapq.heappush(heap, (float(Elo.mid()), counter, a_, b_, m, Elo, Ehi))

    push(lo, hi)
    exhausted = False
    while heap:
        _, _, a_, b_, m, Elo, Ehi = heapq.heappop(heap)
        if Elo > U:
            continue
        small = (Ehi - Elo) <= tol_rel * U + floor_abs
        splittable = (m > a_) and (m < b_)
        if small or not splittable:
            lower_final = Elo if lower_final is None or Elo < lower_final else lower_final
            continue
        if evals >= max_evals:
            exhausted = True
            lower_final = Elo if lower_final is None or Elo < lower_final else lower_final
            for item in heap:
                if not (item[5] > U):
                    lower_final = item[5] if item[5] < lower_final else lower_final
            break
        push(a_, m)
        push(m, b_)
    if lower_final is None:  # everything pruned: the minimum is attained at an evaluated point
        lower_final = U
    return lower_final, U, evals, exhausted


def _cos_shift(x: arb, n: int) -> arb:
    """cos(x + nπ/2)."""
    r = n % 4
    return (x.cos(), -x.sin(), -x.cos(), x.sin())[r]


def _sin_shift(x: arb, n: int) -> arb:
    r = n % 4
    return (x.sin(), x.cos(), -x.sin(), -x.cos())[r]


def _derivs_factory(kind: str, prm: dict, X0: arb, Y0: arb, sg: int = 1):
    """Derivatives of the squared distance D along the parametrisation of the canonical conic.

    ellipse  (a cos θ, b sin θ):    D = (A−B)/2 cos 2θ − 2aX0 cos θ − 2bY0 sin θ + (A+B)/2 + |q|²
    hyperbola (σ a cosh t, b sinh t): D = (A+B)/2 cosh 2t − 2σaX0 cosh t − 2bY0 sinh t + (A−B)/2 + |q|²
    parabola (s²/2p, s):             D = s⁴/4p² + (1 − X0/p) s² − 2Y0 s + |q|²
    """
    q2 = X0 * X0 + Y0 * Y0
    if kind == "ellipse":
        A, B = prm["A2"], prm["B2"]
        al, be, ga, de = (A - B) / 2, -2 * A.sqrt() * X0, -2 * B.sqrt() * Y0, (A + B) / 2 + q2

        def derivs(t, n):
            t2 = 2 * t
            out = []
            for k in range(n + 1):
                v = al * (2 ** k) * _cos_shift(t2, k) + be * _cos_shift(t, k) + ga * _sin_shift(t, k)
                out.append(v + de if k == 0 else v)
            return out
        return derivs
    if kind == "hyperbola":
        A, B = prm["A2"], prm["B2"]
        al, be, ga, de = (A + B) / 2, -2 * sg * A.sqrt() * X0, -2 * B.sqrt() * Y0, (A - B) / 2 + q2

        def derivs(t, n):
            ch, sh = t.cosh(), t.sinh()
            ch2, sh2 = (2 * t).cosh(), (2 * t).sinh()
            out = []
            for k in range(n + 1):
                if k % 2 == 0:
                    v = al * (2 ** k) * ch2 + be * ch + ga * sh
                else:
                    v = al * (2 ** k) * sh2 + be * sh + ga * ch
                out.append(v + de if k == 0 else v)
            return out
        return derivs
    if kind == "parabola":
        p = prm["p"]
        c4, c2, c1 = 1 / (4 * p * p), 1 - X0 / p, -2 * Y0

        def derivs(s, n):
            s2 = s * s
            full = [c4 * s2 * s2 + c2 * s2 + c1 * s + q2,
                    4 * c4 * s2 * s + 2 * c2 * s + c1,
                    12 * c4 * s2 + 2 * c2,
                    24 * c4 * s,
                    24 * c4 + 0 * s]
            return full[:n + 1] + [0 * s] * max(0, n - 4)
        return derivs
    raise InvalidConicError(f"unknown conic kind {kind!r}")


def squared_distance_ball(conic: Conic, x, y, prec: int = 128):
    """Rigorous enclosure [lo, hi] (two exact arb numbers) of d((x, y), C)² for a point
    (x, y) given exactly (Fraction, int, float, exact arb).  Returns (lo, hi, info)."""
    wp = prec + 32
    with flint.ctx.workprec(wp):
        qx, qy = _as_ball(x, wp), _as_ball(y, wp)
        fr = conic.frame_arb(wp)
        X0, Y0 = fr.to_canonical(qx, qy)
        kind = fr.kind
        info = {"evals": 0, "exhausted": False}
        if kind == "circle":
            r = fr.params["r2"].sqrt()
            d = _sqrt_nonneg(X0 * X0 + Y0 * Y0) - r
            d2 = d * d
            return d2.lower(), d2.upper(), info
        Xf, Yf = float(X0.mid()), float(Y0.mid())
        ffr = conic.frame
        cands = _foot_canonical(kind, ffr.params, Xf, Yf, all_candidates=True)
        prm = fr.params
        if kind == "ellipse":
            derivs = _derivs_factory(kind, prm, X0, Y0)
            U = None
            for X, Y, _ in cands:
                t = math.atan2(Y / math.sqrt(ffr.params["B2"]), X / math.sqrt(ffr.params["A2"]))
                val = derivs(arb(t), 0)[0].upper()
                U = val if U is None or val < U else U
            lower, U, ev, ex = _bb_minimise(derivs, arb(-3.2), arb(3.2), U, prec)
            info.update(evals=ev, exhausted=ex)
            return lower, U, info
        if kind == "parabola":
            derivs = _derivs_factory(kind, prm, X0, Y0)
            U = None
            for X, Y, _ in cands:
                val = derivs(arb(Y), 0)[0].upper()
                U = val if U is None or val < U else U
            R = _sqrt_nonneg(U).upper()
            lower, U, ev, ex = _bb_minimise(derivs, (Y0 - R).lower(), (Y0 + R).upper(), U, prec)
            info.update(evals=ev, exhausted=ex)
            return lower, U, info
        if kind == "hyperbola":
            b_ = prm["B2"].sqrt()
            fns = {sg: _derivs_factory(kind, prm, X0, Y0, sg) for sg in (1, -1)}
            U = None
            for X, Y, _ in cands:
                sg = 1 if X >= 0 else -1
                t = math.asinh(Y / math.sqrt(ffr.params["B2"]))
                val = fns[sg](arb(t), 0)[0].upper()
                U = val if U is None or val < U else U
            best_lower, evs, exh = None, 0, False
            for sg in (1, -1):
                R = _sqrt_nonneg(U).upper()
                # every point within sqrt(U) of q has |b sinh t − Y0| <= R
                tlo = ((Y0 - R) / b_).asinh().lower()
                thi = ((Y0 + R) / b_).asinh().upper()
                low, U, ev, ex = _bb_minimise(fns[sg], tlo, thi, U, prec)
                evs += ev
                exh = exh or ex
                best_lower = low if best_lower is None or low < best_lower else best_lower
            info.update(evals=evs, exhausted=exh)
            if U < best_lower:
                best_lower = U
            return best_lower, U, info
    raise InvalidConicError(f"unknown conic kind {kind!r}")


def _sqrt_nonneg(x: arb) -> arb:
    """sqrt of the non-negative part of a ball (the quantity is known to be >= 0)."""
    if x.lower() >= 0:
        return x.sqrt()
    return _interval(arb(0), x.upper().sqrt().upper())


def distance_ball(conic: Conic, x, y, prec: int = 128) -> arb:
    """Rigorous enclosure of d((x, y), C) as a flint ``arb``.

    ``x``, ``y`` may be arb balls, Fractions, ints, rational strings or floats (exact binary
    value).  For balls the result encloses d(q', C) for every q' in the box (d is
    1-Lipschitz: d(mid) ± |rad|).  Computed from the exact coefficients of ``conic``.
    """
    wp = prec + 32
    with flint.ctx.workprec(wp):
        bx, by = _as_ball(x, wp), _as_ball(y, wp)
        mx, my = bx.mid(), by.mid()
        rx, ry = bx.rad(), by.rad()
        lo, hi, _ = squared_distance_ball(conic, mx, my, prec)
        if lo < 0 or not (lo >= 0):
            lo = arb(0)
        dlo, dhi = lo.sqrt().lower(), hi.sqrt().upper()
        infl = (rx * rx + ry * ry).sqrt().upper() if (rx != 0 or ry != 0) else arb(0)
        dlo = dlo - infl
        if dlo < 0:
            dlo = arb(0)
        return _interval(dlo.lower(), (dhi + infl).upper())


# =========================================================================== signs / tangency

def _is_exact_rational(v) -> bool:
    return isinstance(v, (int, Fraction, flint.fmpq, flint.fmpz)) and not isinstance(v, bool) or \
        (isinstance(v, str))


def tangency_polynomial(conic: Conic, qx, qy) -> flint.fmpq_poly:
    """P(δ) whose roots contain every critical value δ of the squared distance from the
    rational point q = (qx, qy) to C: the discriminant in λ of det(λ M_C + M_circle(q, δ))
    (the circle of squared radius δ about q is tangent to C).  Exact (fmpq_poly)."""
    qx, qy = to_fraction(qx, "qx"), to_fraction(qy, "qy")
    M = [[flint.fmpq_poly([flint.fmpq(v.numerator, v.denominator)]) for v in row]
         for row in _matrix_of(conic.primitive_coefficients)]
    fq = lambda v: flint.fmpq(v.numerator, v.denominator)  # noqa: E731
    S = [[flint.fmpq_poly([1]), flint.fmpq_poly([0]), flint.fmpq_poly([fq(-qx)])],
         [flint.fmpq_poly([0]), flint.fmpq_poly([1]), flint.fmpq_poly([fq(-qy)])],
         [flint.fmpq_poly([fq(-qx)]), flint.fmpq_poly([fq(-qy)]), flint.fmpq_poly([fq(qx * qx + qy * qy), -1])]]

    def det_at(lam: int):
        m = [[M[i][j] * lam + S[i][j] for j in range(3)] for i in range(3)]
        return (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
                - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
                + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))

    D0, D1, Dm1, D2 = det_at(0), det_at(1), det_at(-1), det_at(2)
    eps = D0
    beta = (D1 + Dm1) / 2 - eps
    S_ = (D1 - Dm1) / 2
    T = D2 - 4 * beta - eps
    alpha = (T - 2 * S_) / 6
    gamma = S_ - alpha
    return (18 * alpha * beta * gamma * eps - 4 * beta ** 3 * eps + beta ** 2 * gamma ** 2
            - 4 * alpha * gamma ** 3 - 27 * alpha ** 2 * eps ** 2)


def _matrix_of(co):
    a, b, c, d, e, f = (Fraction(v) for v in co)
    return [[a, b / 2, d / 2], [b / 2, c, e / 2], [d / 2, e / 2, f]]


def _circle_sign_exact(conic: Conic, qx: Fraction, qy: Fraction, r: Fraction) -> int:
    ex = conic.exact_frame
    u = (qx - ex.tx) ** 2 + (qy - ex.ty) ** 2  # |q - c|²
    rho2 = ex.params["r2"]
    # d² − r² = u + rho2 − r² − 2 sqrt(u rho2)  (d = | |q−c| − rho |)
    S = u + rho2 - r * r
    P = 4 * u * rho2
    if S <= 0:
        return 0 if (S == 0 and P == 0) else -1
    return (S * S > P) - (S * S < P)


def distance_sign_vs(conic: Conic, x, y, radius, prec: int = 128, max_prec: int = 1024,
                     exact_tangency: bool = True) -> int | None:
    """Certified sign of d((x, y), C) − radius: +1, −1, 0 (exact tangency, only for exact
    rational x, y, radius) or None when it could not be decided.

    Ball route at increasing precision; for a rational point and radius the zero case is
    certified algebraically: r² is a root of :func:`tangency_polynomial` and the enclosure
    of d² meets only the isolating ball of that root (d² is itself a root).
    """
    exact = all(_is_exact_rational(v) for v in (x, y, radius))
    if exact:
        qx, qy, r = (to_fraction(v, "value") for v in (x, y, radius))
        if r < 0:
            return 1
        if conic.kind == "circle" and conic.exact_frame is not None:
            return _circle_sign_exact(conic, qx, qy, r)
    p = prec
    while p <= max_prec:
        with flint.ctx.workprec(p + 32):
            d = distance_ball(conic, x, y, prec=p)
            rb = _as_ball(radius, p + 32)
            if d.lower() > rb.upper():
                return 1
            if d.upper() < rb.lower():
                return -1
        p *= 2
    if not (exact and exact_tangency):
        return None
    P = tangency_polynomial(conic, qx, qy)
    if P == 0:
        return None
    r2 = r * r
    if P(flint.fmpq(r2.numerator, r2.denominator)) != 0:
        return None  # d ≠ r but the enclosures could not separate them (should not happen)
    den = P.denom()
    Pz = flint.fmpz_poly([int(c * den) for c in P.coeffs()])
    for p in (prec, 2 * prec, 4 * prec, max_prec):
        with flint.ctx.workprec(p + 32):
            lo, hi, _ = squared_distance_ball(conic, qx, qy, p)
            E = _interval(lo, hi)
            roots = [z.real for z, _m in Pz.complex_roots() if z.imag == 0]
            r2b = arb(flint.fmpq(r2.numerator, r2.denominator))
            meeting = [z for z in roots if z.overlaps(E)]
            if len(meeting) == 1 and meeting[0].overlaps(r2b):
                # the ball meeting E isolates one root; it contains r² (a root) and d² (a root in E)
                others = [z for z in roots if z is not meeting[0]]
                if all(not z.overlaps(r2b) for z in others):
                    return 0
    return None
