"""Rigorous enclosures of the distance from a point to a conic (ball arithmetic).

Rigorous route (:func:`squared_distance_ball`, :func:`distance_ball`): every real foot point is
enclosed through the Lagrange polynomial F_q(λ) of :mod:`runtime.certify.foot` (thesis §4.1,
exact coefficients), d² ≥ the smallest lower bound; d² ≤ |q − p|² for a true curve point p next
to the float closest point; at degenerate q (symmetry axes, evolute cusps) the enclosure is
narrowed to the real roots of the exact tangency polynomial (every critical value of the
squared distance is a root).  The result encloses d(q, C); for a ball q it encloses d(q', C)
for every q' in the box (d is 1-Lipschitz).
"""
from __future__ import annotations

import math
from fractions import Fraction
from typing import Any

import flint
from flint import arb

from ..certify.foot import (FootFailure, foot_polynomial, normalised_coefficients, real_feet_ball,
                           to_arb, working_prec)
from .conic import Conic, to_fraction
from .foot_points import canonical_foot_points
from ..result import InvalidConicError

__all__ = ["distance_ball", "distance_sign_vs", "squared_distance_ball", "tangency_polynomial"]


def _as_ball(v, prec: int) -> arb:
    if isinstance(v, arb):
        return v
    if isinstance(v, flint.fmpq):
        return arb(v)
    q = to_fraction(v, "coordinate")
    return arb(flint.fmpq(q.numerator, q.denominator))


def _interval(lo: arb, hi: arb) -> arb:
    return lo.union(hi)


def _exact_fraction(v) -> Fraction:
    """Exact rational value of an exact input (Fraction, int, str, float, fmpq, arb of radius 0)."""
    if isinstance(v, arb):
        if v.rad() != 0:
            raise ValueError("expected an exact point (arb of radius 0)")
        m, e = v.mid().man_exp()
        m, e = int(m), int(e)
        return Fraction(m * 2 ** e) if e >= 0 else Fraction(m, 2 ** -e)
    if isinstance(v, flint.fmpq):
        return Fraction(int(v.p), int(v.q))
    return to_fraction(v, "coordinate")


def _param_sq_distance(kind: str, prm: dict, X0: arb, Y0: arb, t: arb, sg: int = 1) -> arb:
    """|q − p(t)|² for the point p(t) of the canonical conic (balls; p(t) is a true curve point):

    ellipse  (a cos t, b sin t), hyperbola (σ a cosh t, b sinh t), parabola (t²/2p, t).
    """
    if kind == "ellipse":
        X, Y = prm["A2"].sqrt() * t.cos(), prm["B2"].sqrt() * t.sin()
    elif kind == "hyperbola":
        X, Y = sg * prm["A2"].sqrt() * t.cosh(), prm["B2"].sqrt() * t.sinh()
    elif kind == "parabola":
        X, Y = t * t / (2 * prm["p"]), t
    else:
        raise InvalidConicError(f"unknown conic kind {kind!r}")
    return (X - X0) ** 2 + (Y - Y0) ** 2


def _curve_upper(conic: Conic, qx: Fraction, qy: Fraction):
    """Rigorous upper bound of d(q, C)² (an exact arb) from the float closest point: the squared
    distance to a true point of the curve near it, evaluated in ball arithmetic.  D is stationary
    at the foot point, so the bound is tight to about the square of the float error."""
    fr = conic.frame_arb(flint.ctx.prec)
    X0, Y0 = fr.to_canonical(arb(flint.fmpq(qx.numerator, qx.denominator)),
                             arb(flint.fmpq(qy.numerator, qy.denominator)))
    kind, ffr = fr.kind, conic.frame
    Xf, Yf = float(X0.mid()), float(Y0.mid())
    if not (math.isfinite(Xf) and math.isfinite(Yf)):
        return None
    U = None
    for X, Y, _ok in canonical_foot_points(kind, ffr.params, Xf, Yf, all_candidates=True):
        sg = 1
        if kind == "ellipse":
            t = math.atan2(Y / math.sqrt(ffr.params["B2"]), X / math.sqrt(ffr.params["A2"]))
        elif kind == "hyperbola":
            sg = 1 if X >= 0 else -1
            t = math.asinh(Y / math.sqrt(ffr.params["B2"]))
        else:
            t = Y
        if not math.isfinite(t):
            continue
        D = _param_sq_distance(kind, fr.params, X0, Y0, arb(t), sg)
        if D.is_finite():
            U = D.upper() if U is None or D.upper() < U else U
    return U


def _real_roots_of(Pz: flint.fmpz_poly) -> list[arb]:
    """Real parts of the isolating balls of the roots of Pz that may be real (imaginary part
    containing 0), at the current precision."""
    return [z.real for z, _m in Pz.complex_roots() if z.imag.contains(0)]


def _tight(lo: arb, hi: arb, prec: int) -> bool:
    return bool((hi - lo) <= arb(2) ** (-prec) * (1 + abs(hi)))


def squared_distance_ball(conic: Conic, x, y, prec: int = 128, max_prec: int | None = None):
    """Rigorous enclosure [lo, hi] (two exact arb numbers) of d((x, y), C)² for a point
    (x, y) given exactly (Fraction, int, float, rational string, fmpq, arb of radius 0; an arb
    with a radius gives the enclosure over the box, by the 1-Lipschitz bound).  Returns
    (lo, hi, info); ``info['tight']`` says whether hi − lo ≤ 2^-prec (1 + hi) was reached.

    Thesis §5.2 (foot points; d² is the smallest critical value of |q − p|² on C):

    1. every real foot point of q is enclosed through the Lagrange polynomial F_q(λ)
       (:func:`runtime.certify.foot.real_feet_ball`); d² ≥ min of their lower bounds, and
       d² ≤ the upper bound of any foot proven to exist (or the largest of all bounds: the
       nearest point *is* one of the enclosed feet);
    2. d² ≤ |q − p|² for a true curve point p next to the float closest point;
    3. if [lo, hi] is still wide (degenerate q: on a symmetry axis, at an evolute cusp, where
       feet are only enclosed in cluster zones), d² is refined as a real root of the exact
       tangency polynomial P(δ) (:func:`tangency_polynomial`, every critical value is a root):
       d² lies in the hull of the root balls of P meeting [lo, hi].

    The precision doubles from prec + 32 up to ``max_prec`` (default 4 (prec + 32)); at the
    cap the narrowest correct enclosure found is returned (never a guess).
    """
    if isinstance(x, arb) and x.rad() != 0 or isinstance(y, arb) and y.rad() != 0:
        return _squared_distance_box(conic, x, y, prec)
    qx, qy = _exact_fraction(x), _exact_fraction(y)
    wp = prec + 32
    cap = max_prec if max_prec is not None else 4 * wp
    info: dict[str, Any] = {"prec": wp, "method": None, "tight": False, "evals": 0, "exhausted": False}
    if conic.kind == "circle":
        with flint.ctx.workprec(wp):
            fr = conic.frame_arb(wp)
            X0, Y0 = fr.to_canonical(arb(flint.fmpq(qx.numerator, qx.denominator)),
                                     arb(flint.fmpq(qy.numerator, qy.denominator)))
            d = _sqrt_nonneg(X0 * X0 + Y0 * Y0) - fr.params["r2"].sqrt()
            d2 = d * d
            info.update(method="circle", tight=_tight(d2.lower(), d2.upper(), prec))
            return d2.lower(), d2.upper(), info
    fp = foot_polynomial(normalised_coefficients(conic))
    with working_prec(wp):
        U = _curve_upper(conic, qx, qy)
    Pz = None
    best = None
    p = wp
    while p <= cap:
        with working_prec(p):
            info["prec"] = p
            lo, hi = arb(0), U
            try:
                feet = real_feet_ball(fp, to_arb(qx), to_arb(qy))
            except FootFailure:
                feet = []
            if feet:
                Ds = [f.D for f in feet]
                flo = Ds[0].lower()
                for D in Ds[1:]:
                    if D.lower() < flo:
                        flo = D.lower()
                if flo > lo:
                    lo = flo
                ups = [D.upper() for D in Ds if D.is_finite()]
                cand = [f.D.upper() for f in feet if not f.possible and f.D.is_finite()]
                if len(ups) == len(Ds):
                    top = ups[0]
                    for v in ups[1:]:
                        top = v if v > top else top
                    cand.append(top)
                for v in cand:
                    if hi is None or v < hi:
                        hi = v
            if hi is not None and lo > hi:
                raise RuntimeError(f"inconsistent distance enclosures at q = ({qx}, {qy}): "
                                   f"lower {lo} > upper {hi}")
            if hi is not None and best is None or hi is not None and (hi - lo) < (best[1] - best[0]):
                best = (lo, hi)
                info["method"] = "feet"
            if hi is not None and _tight(lo, hi, prec):
                info.update(tight=True)
                return lo, hi, info
            # refinement: d² is a real root of the exact tangency polynomial
            if Pz is None:
                P = tangency_polynomial(conic, qx, qy)
                Pz = False if P == 0 else flint.fmpz_poly([int(c * P.denom()) for c in P.coeffs()])
            if Pz is not False:
                rs = [r for r in _real_roots_of(Pz) if r.upper() >= lo and (hi is None or r.lower() <= hi)]
                if rs:
                    E = rs[0]
                    for r in rs[1:]:
                        E = E.union(r)
                    elo = E.lower() if E.lower() > lo else lo
                    ehi = E.upper() if hi is None or E.upper() < hi else hi
                    if best is None or (ehi - elo) < (best[1] - best[0]):
                        best = (elo, ehi)
                        info["method"] = "tangency"
                    if _tight(elo, ehi, prec):
                        info.update(tight=True)
                        return elo, ehi, info
        p *= 2
    if best is None:
        raise ArithmeticError(f"no enclosure of the distance from ({qx}, {qy}) to the conic "
                              f"up to {cap} bits")
    return best[0], best[1], info


def _squared_distance_box(conic: Conic, x, y, prec: int):
    """Enclosure of d(q', C)² over the box of ball inputs (d is 1-Lipschitz)."""
    d = distance_ball(conic, x, y, prec)
    d2 = d * d
    return d2.lower(), d2.upper(), {"tight": False, "method": "box"}


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
        if isinstance(x, arb) or isinstance(y, arb):
            bx, by = _as_ball(x, wp), _as_ball(y, wp)
            mx, my = bx.mid(), by.mid()
            rx, ry = bx.rad(), by.rad()
        else:  # exact input: no rounding of the point
            mx, my = _exact_fraction(x), _exact_fraction(y)
            rx = ry = arb(0)
        lo, hi, _ = squared_distance_ball(conic, mx, my, prec)
        if not (lo >= 0):
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
