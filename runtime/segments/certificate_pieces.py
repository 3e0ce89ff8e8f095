"""Piecewise proofs along an edge of the point/segment certificate (rule R3 of
:mod:`runtime.segments.certificate_edges`, for parabolas and bisectors of two segments).

g_k = d_k − ρ > 0 (for a segment k ending at the edge's point on a parabola: its foot
beyond that point) on the open arc.  The parameter interval is cut into pieces, each
proved by a rigorous lower bound (float filters with rounding margins: d_k(x) ≥ d_k(q) − |x − q|
with ρ below its ball's upper end, and the mean-value form with Lipschitz bounds on the distance
gradients; then :meth:`runtime.segments.certificate_sites.SiteTable.distance` and the
mean-value form in arb on the box of the piece);
pieces that fail are halved, for the failing sites only; candidates come from a k-d tree over
bounding discs.  At an end vertex where k is at the radius, g_k vanishes: there g_k' > 0 (into
the arc) is proved on [τ*, τ* + δ] (the gradient of the distance to a closed convex set,
(x − F)/|x − F|, is continuous off the set; g_k ≥ 0 at every proved vertex), or, for a segment k
ending at an R1 point e, its foot stays clamped beyond e there (then d_k = d_e > ρ by R1), or,
at a corner c of radius 0 (the curve is c + τ u), g_k(τ) ≥
τ (D_k − D_i) with D_i = ρ/τ and D_k the distance from u to the line of k (|u| when k leaves c
away from u), proved > 0 for all τ > 0.

Public API: :class:`PieceProofs` (mixed into the edge prover, which supplies ``T``, ``curve``,
``i``, ``j``, ``skip``, ``r1`` and ``report``).
"""
from __future__ import annotations

import math

import numpy as np
from flint import arb

from .certificate_curves import down, interval, q_arb, up
from .certificate_rules import corner_ratio
from .certificate_sites import POINT, SEGMENT, hypot
from .distance import distances, float_error

__all__ = ["PieceProofs", "MAX_PIECES", "FIRST_PIECES"]

EPS = np.finfo(float).eps
#: pieces of one edge before the proof gives up
MAX_PIECES = 4000
#: the finite part of an edge is first cut into this many pieces
FIRST_PIECES = 8


class PieceProofs:
    """The piecewise part of an edge proof (module docstring)."""

    def _value_fn(self, k):
        T, c = self.T, self.curve
        if c.kind == "parabola" and T.kind[k] == SEGMENT and any(p in (self.i, self.j) for p in T.ends[k]):
            p = self.i if T.kind[self.i] == POINT else self.j
            which = T.end_index(k, p)
            sign, shift = (-1, 0) if which == 0 else (1, 1)
            (ax, ay), (bx, by) = T.a[k], T.b[k]
            dx, dy = q_arb(bx - ax), q_arb(by - ay)
            L2 = dx * dx + dy * dy

            def value(t, X, Y, rho):
                return sign * (T.foot(k, X, Y) - shift)

            def deriv(t, X, Y):
                gx, gy = c.dxy(t)
                return sign * (gx * dx + gy * dy) / L2
            return value, deriv

        def value(t, X, Y, rho):
            return T.distance(k, X, Y) - rho

        def deriv(t, X, Y):
            ax, ay, bx, by = T.arb_ends(k)
            if T.kind[k] == SEGMENT:
                u = T.foot(k, X, Y)
                u = u.max(arb(0)).min(arb(1))
                fx, fy = ax + u * (bx - ax), ay + u * (by - ay)
            else:
                fx, fy = ax, ay
            dx, dy = X - fx, Y - fy
            gx, gy = c.dxy(t)
            return (dx * gx + dy * gy) / hypot(dx, dy) - c.drho(t, X, Y)
        return value, deriv


    def _tie_cover(self, k, end, at_lo: bool, deriv, span: float):
        """The float parameter up to which (from ``end``) g_k > 0 on the open arc is proved, or None:
        g_k(τ*) = 0 and g_k' > 0 into the arc on [τ*, τ* + δ] (the largest δ = span/4^m found)."""
        vp, t0 = end[2], end[1]
        if vp.corner is not None:
            if not corner_ratio(self.T, self.curve, k, vp.corner, at_lo):
                return None
            return math.inf if at_lo else -math.inf
        base, back = (up(t0), down(t0)) if at_lo else (down(t0), up(t0))
        tests = [lambda J, X, Y: deriv(J, X, Y) * (1 if at_lo else -1)] + self._clamps(k)
        best = None
        for test in tests:
            reach = self._prefix(test, back, base, span, at_lo)
            if reach is not None and (best is None or (reach > best if at_lo else reach < best)):
                best = reach
        return best

    def _prefix(self, fn, back: float, base: float, span: float, at_lo: bool, budget: int = 40):
        """A parameter ``reach`` such that fn > 0 on the interval from ``back`` (the far side of the
        end's ball) to ``reach``: the first piece shrinks until it is proved, then the next pieces,
        doubling, extend it while they are proved.  None if no first piece is proved."""
        c = self.curve
        sgn = 1 if at_lo else -1
        width, start, reach = span / 2, back, None
        while budget > 0 and width > 1e-14 * (abs(base) + span):
            budget -= 1
            end = (base if reach is None else reach) + sgn * width
            J = interval(min(start, end), max(start, end))
            X, Y = c.xy(J)
            if fn(J, X, Y) > 0:
                reach, start = end, end
                if abs(end - base) >= span:
                    break
                width *= 2
            elif reach is None:
                width /= 4
            else:
                width /= 4
                if width < abs(reach - base) / 64:
                    break
        return reach

    def _clamps(self, k) -> list:
        """For a segment k ending at an R1 point e: the test "k's foot is clamped beyond e" (then
        d_k = d_e, and d_e > ρ on the open arc by R1, proved for the whole edge)."""
        T, out = self.T, []
        if T.kind[k] == SEGMENT:
            for which, e in enumerate(T.ends[k]):
                if e in self.r1:
                    sign, shift = (-1, 0) if which == 0 else (1, 1)
                    out.append(lambda J, X, Y, sign=sign, shift=shift: sign * (T.foot(k, X, Y) - shift))
        return out


    def _float_centred(self, idx, pa: float, pb: float, t, X, Y):
        """The mean-value bound in floats, for many sites at once (True: g_k > 0 on the piece).

        With q a float point within δq of γ(τ_m) (τ_m the middle parameter), R ≥ |x − q| on the
        piece's box and u_k(q) = (q − F_k(q))/d_k(q) the gradient of d_k:
        g_k(τ_m) ≥ d_k(q) − d_i(q) − 2δq (distances are 1-Lipschitz; ρ = d_i on the arc), and
        |g_k'| ≤ |γ'|·(|u_k(q) − u_i(q)| + 4R/d_k(q) + 4R/d_i(q)) on the piece when both distances
        exceed R (x − F(x) is 1-Lipschitz for the projection F on a convex set, and
        |a/|a| − b/|b|| ≤ 2|a − b|/(|a| + |b|) in an inner-product space (Dunkl–Williams), so
        |u_k(x) − u_k(q)| ≤ 2R/(2d_k(q) − R)); floats carry their rounding bounds
        (:func:`runtime.segments.distance.float_error`) and a relative slack."""
        T, c = self.T, self.curve
        m = (pa + pb) / 2
        hw = max(m - pa, pb - m) * (1 + 4 * EPS)
        tm = arb(m)
        Xm, Ym = c.xy(tm)
        qx, qy = float(Xm.mid()), float(Ym.mid())
        dq = float(Xm.rad()) + float(Ym.rad()) + 4 * EPS * (abs(qx) + abs(qy))
        R = (abs(float(X.mid()) - qx) + float(X.rad()) + abs(float(Y.mid()) - qy) + float(Y.rad())) * (1 + 4 * EPS)
        gx, gy = c.dxy(t)
        gp = up(abs(gx) + abs(gy))
        sites = np.concatenate([[self.i], idx])
        A, B = T.A[sites], T.B[sites]
        Q = np.repeat([[qx, qy]], len(sites), axis=0)
        d, tt = distances(A, B, Q)
        err = float_error(A, B, Q) + 8 * EPS * T.scale
        F = A + tt[:, None] * (B - A)
        with np.errstate(divide="ignore", invalid="ignore"):
            U = (Q - F) / d[:, None]
            dlo = d - err
            L = gp * (np.abs(U[1:] - U[0]).sum(axis=1) + 2 * R / (2 * dlo[1:] - R) + 2 * R / (2 * dlo[0] - R) + 1e-12)
            rounding = err[1:] + err[0] + 2 * dq + 16 * EPS * (T.scale + abs(qx) + abs(qy))
            lower = (d[1:] - d[0]) - rounding - L * hw
        return (dlo[1:] > R) & (dlo[0] > R) & np.isfinite(lower) & (lower > 0)

    def _centred(self, k, t, X, Y, pa: float, pb: float) -> bool:
        """g_k > 0 on the piece by the mean-value form g(m) + g'(piece)·(τ − m)."""
        fns = self._fns.get(k)
        if fns is None:
            fns = self._fns[k] = self._value_fn(k)
        value, deriv = fns
        c = self.curve
        tm = arb((pa + pb) / 2)
        Xm, Ym = c.xy(tm)
        g = value(tm, Xm, Ym, c.rho(tm, Xm, Ym)) + deriv(t, X, Y) * (t - tm)
        return bool(g > 0) or any(test(t, X, Y) > 0 for test in self._clamps(k))

    def _pieces(self, a: float, b: float, special) -> bool:
        T, c = self.T, self.curve
        skip = self.skip | {self.i, self.j}
        cuts = np.linspace(a, b, FIRST_PIECES + 1)
        cuts[0], cuts[-1] = a, b
        stack = [(float(cuts[m]), float(cuts[m + 1]), None) for m in range(FIRST_PIECES)][::-1]
        self._fns: dict = {}
        count = 0
        min_w = (b - a) * 2.0 ** -44
        bad: dict = {}
        while stack:
            pa, pb, cands = stack.pop()
            count += 1
            if count > MAX_PIECES:
                self.report_limit("too many pieces: sites too close to the edge to decide")
                return False
            t = interval(pa, pb)
            X, Y = c.xy(t)
            rho = c.rho(t, X, Y)
            qx, qy = float(X.mid()), float(Y.mid())
            rq = float(X.rad()) + float(Y.rad())
            rho_hi = up(rho)
            near = [k for k in T.near(qx, qy, rho_hi + rq) if k not in skip]
            if cands is not None:
                near = [k for k in near if k in cands]
            if not near:
                continue
            plain = [k for k in near if k not in special]
            failed = []
            if plain:
                idx = np.array(plain, dtype=int)
                Q = np.repeat([[qx, qy]], len(idx), axis=0)
                d, _ = distances(T.A[idx], T.B[idx], Q)
                err = float_error(T.A[idx], T.B[idx], Q) + 8 * EPS * T.scale
                clear = d - err - rq > rho_hi
                # a site nearer than ρ at the piece's centre (in floats) is not tried in arb: halve
                hopeless = d + err <= float(rho.mid()) - float(rho.rad())
                rest = ~clear & ~hopeless
                if rest.any():
                    clear[rest] = self._float_centred(idx[rest], pa, pb, t, X, Y)
                for k, cl, h in zip(plain, clear.tolist(), hopeless.tolist()):
                    if cl:
                        continue
                    if h or (not T.distance(k, X, Y) - rho > 0 and not self._centred(k, t, X, Y, pa, pb)):
                        failed.append(k)
            for k in near:
                if k not in special:
                    continue
                value, cover_lo, cover_hi = special[k]
                if pb <= cover_lo or pa >= cover_hi:
                    continue
                if not value(t, X, Y, rho) > 0 and not self._centred(k, t, X, Y, pa, pb):
                    failed.append(k)
            if not failed:
                continue
            if pb - pa <= min_w:
                for k in failed:
                    bad.setdefault(k, (pa, pb))
                continue
            m = (pa + pb) / 2
            fs = set(failed)
            stack.append((m, pb, fs))
            stack.append((pa, m, fs))
        for k, (pa, pb) in sorted(bad.items()):
            t = arb((pa + pb) / 2)
            X, Y = c.xy(t)
            value = special[k][0] if k in special else (lambda t, X, Y, rho: T.distance(k, X, Y) - rho)
            v = value(t, X, Y, c.rho(t, X, Y))
            where = f"near ({float(X.mid()):.6g}, {float(Y.mid()):.6g})"
            if v < 0:
                self.report(f"site {k} is closer than its sites {where}", k)
            else:
                self.report(f"site {k} is too close to its sites to decide {where}", k)
        return not bad
