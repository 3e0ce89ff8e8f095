"""Piecewise proofs along an edge of the point/segment/arc certificate (rule R3 of
:mod:`runtime.segments.certificate_edges`, for parabolas, bisectors of two segments and arcs'
bisectors).

g_k = d_k − ρ > 0 on the open arc, and the edge's *conditions* (each a function > 0 there: R2
as linear functions g·x + g₀ along curves; along an arc's bisector also t > 0, the foot of a
segment partner in (0, 1), the contact direction of an arc partner in its open range).  The parameter interval is cut into pieces, each
proved by a rigorous lower bound (float filters with rounding margins: d_k(x) ≥ d_k(q) − |x − q|
with ρ below its ball's upper end, and the mean-value form with Lipschitz bounds on the distance
gradients; then :meth:`runtime.segments.certificate_sites.SiteTable.distance` and the
mean-value form in arb on the box of the piece);
pieces that fail are halved, for the failing sites only; candidates come from a k-d tree over
bounding discs.  At an end vertex where k is at the radius, g_k vanishes: there g_k' > 0 (into
the arc) is proved on [τ*, τ* + δ] (the gradient of the distance to a closed convex set,
(x − F)/|x − F|, is continuous off the set; for an arc it is ±(x − c)/|x − c| where the direction
is decided in its range, else the nearer end's; g_k ≥ 0 at every proved vertex), or, for a segment k
ending at an R1 point e, its foot stays clamped beyond e there (then d_k = d_e > ρ by R1), or,
at a corner c of radius 0 (the curve is c + τ u), g_k(τ) ≥
τ (D_k − D_i) with D_i = ρ/τ and D_k the distance from u to the line of k (|u| when k leaves c
away from u), proved > 0 for all τ > 0.  A condition vanishing at an end vertex is covered the
same way by its derivative (a function ≥ 0 there with a positive derivative into the arc).  The
float mean-value filter needs functions with Lipschitz unit gradients: distances to convex sets
(points, segments) and, for arcs, their circles' signed distances (a lower bound of d_k).  Along an
arc's bisector a site may also be proved farther by the pair's algebra
(:meth:`runtime.segments.certificate_arcs.ArcCurve.farther`: a trigonometric polynomial in the
contact angle, smooth up to the pole, so the far parts of a branch near a far vertex — where all
sites look alike and margins decay like 1/ρ — need few pieces), with its derivative as the cover
at a vertex where it is ≥ 0.

Length: one mixin holding the piecewise proof's state (pieces, covers, filters); its filters share
that state and are split only by method.

Public API: :class:`PieceProofs` (mixed into the edge prover, which supplies ``T``, ``curve``,
``i``, ``j``, ``skip``, ``r1``, ``conditions`` and ``report``).
"""
from __future__ import annotations

import math

import numpy as np
from flint import arb

from .certificate_curves import Line, down, interval, q_arb, up
from .certificate_float_bounds import bounds_at
from .certificate_rules import convex_tangents, corner_ratio
from .certificate_sites import ARC, POINT, SEGMENT, hypot
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

        def value(t, X, Y, rho):
            return T.distance(k, X, Y) - rho

        def deriv(t, X, Y):
            gx, gy = c.dxy(t)
            ux, uy = distance_gradient(T, k, X, Y)
            return ux * gx + uy * gy - c.drho(t, X, Y)
        return value, deriv

    def _tie_cover(self, k, end, at_lo: bool, deriv, span: float):
        """The float parameter up to which (from ``end``) g_k > 0 on the open arc is proved, or None:
        g_k(τ*) = 0 and g_k' > 0 into the arc on [τ*, τ* + δ] (the largest δ = span/4^m found)."""
        vp, t0 = end[2], end[1]
        if vp.centre_of == k and isinstance(self.curve, Line):
            # a straight edge leaving the centre of arc k: on the whole open ray the direction from
            # the centre misses k's open range (a condition on the direction only), so k's nearest
            # points are its ends, and those are farther than the edge's sites (R1)
            wx, wy = self.curve.w if at_lo else (-self.curve.w[0], -self.curve.w[1])
            if self.T.in_range(k, wx, wy) is False and all(e in self.r1 for e in self.T.ends[k]):
                return math.inf if at_lo else -math.inf
        base, back = (up(t0), down(t0)) if at_lo else (down(t0), up(t0))
        if vp.corner is not None:
            if isinstance(self.curve, Line):
                other = self.hi if at_lo else self.lo
                far = (other[2].x, other[2].y) if other[0] == "v" else None
                if not corner_ratio(self.T, self.curve, k, vp.corner, at_lo, far):
                    return None
                return math.inf if at_lo else -math.inf
            from .certificate_corner_curves import curve_corner_test

            test = curve_corner_test(self, k, vp.corner, 1 if at_lo else -1)
            return None if test is None else self._prefix(test, back, base, span, at_lo)
        sgn = 1 if at_lo else -1
        tests = []
        if self._farther_at_vertex(k, vp):
            # the algebraic margin of ArcCurve.farther is ≥ 0 at the vertex: its derivative
            tests.append(lambda J, X, Y: self.curve.farther(k, J, deriv=True) * sgn)
        tests += [lambda J, X, Y: deriv(J, X, Y) * sgn] + self._clamps(k) + self._clamp_derivs(k, vp, sgn)
        if self.curve.kind == "arc" and self.T.kind[k] == ARC and vp.ok and vp.x is not None:
            # k's nearest point is its end e on the box (d_k = d_e), e's margin ≥ 0 at the vertex
            for e in (e for e in self.T.ends[k] if e >= 0):
                tests.append(lambda J, X, Y, e=e: self.curve.farther(e, J, deriv=True) * sgn
                             if self.T.owned_by_end(k, e, X, Y) is True else arb(-1))
        best = None
        for test in tests:
            reach = self._prefix(test, back, base, span, at_lo)
            if reach is not None and (best is None or (reach > best if at_lo else reach < best)):
                best = reach
                if abs(best - base) >= span:           # the whole edge: no test does better
                    break
        return best

    def _prefix(self, fn, back: float, base: float, span: float, at_lo: bool, budget: int = 40):
        """A parameter ``reach`` such that fn > 0 on the interval from ``back`` (the far side of the
        end's ball) to ``reach``: the first piece shrinks until it is proved, then the next pieces,
        doubling, extend it while they are proved.  None if no first piece is proved."""
        c = self.curve
        sgn = 1 if at_lo else -1
        width, start, reach = span / 2, back, None
        if not width > 1e-14 * (abs(base) + span):
            # an edge below the float resolution of its parameter (between nearly coincident
            # vertices): the whole edge at once, from the far side of the end's ball (base ± span
            # reaches the other end's ball: floats a ≤ base, b − a exact)
            end = base + sgn * span
            J = interval(min(back, end), max(back, end))
            X, Y = c.xy(J)
            return end if fn(J, X, Y) > 0 else None
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

    def _farther_at_vertex(self, k, vp) -> bool:
        """:meth:`runtime.segments.certificate_arcs.ArcCurve.farther` (outer side) is ≥ 0 at the
        proved vertex: k a point (d_k ≥ r there), or an arc whose circle's outside holds the vertex
        with its direction in k's closed range (then d_k = |x − c_k| − ρ_k ≥ r)."""
        T, c = self.T, self.curve
        if c.kind != "arc" or not vp.ok or vp.x is None:
            return False
        if T.kind[k] == POINT:
            return True
        if T.kind[k] != ARC:
            return False
        cx, cy, rho = T.arb_arc(k)
        wx, wy = vp.x - cx, vp.y - cy
        return bool(hypot(wx, wy) > rho) and T.in_range(k, wx, wy, closed=True) is True

    def _farther(self, k, t, pa: float, pb: float, qx: float, qy: float, X=None, Y=None) -> bool:
        """d_k > ρ on the piece by the curve's algebraic margin (arcs' bisectors; for a segment k
        on the side of its line where the piece's centre (qx, qy) lies; for an arc k by its
        circle, or by its end e where that is its nearest point on the box (X, Y))."""
        T, c = self.T, self.curve
        if c.kind != "arc" or T.kind[k] is None:
            return False
        tau = 1
        if T.kind[k] == SEGMENT:
            (ax, ay), (bx, by) = T.A[k], T.B[k]
            tau = 1 if (bx - ax) * (qy - ay) - (by - ay) * (qx - ax) >= 0 else -1
        if c.farther(k, t, tau) > 0 or c.farther_centred(k, t, pa, pb, tau):
            return True
        if T.kind[k] == ARC and X is not None:
            for e in T.ends[k]:
                if e >= 0 and T.owned_by_end(k, e, X, Y) is True:
                    return self._farther(e, t, pa, pb, qx, qy)
        return False

    def _clamps(self, k) -> list:
        """For a curve k ending at an R1 point e: the test "k's nearest point is e alone" (then
        d_k = d_e, and d_e > ρ on the open arc by R1, proved for the whole edge)."""
        T, out = self.T, []
        if T.kind[k] == SEGMENT:
            for which, e in enumerate(T.ends[k]):
                if e in self.r1:
                    sign, shift = (-1, 0) if which == 0 else (1, 1)
                    out.append(lambda J, X, Y, sign=sign, shift=shift: sign * (T.foot(k, X, Y) - shift))
        elif T.kind[k] == ARC:
            for e in T.ends[k]:
                if e in self.r1:
                    out.append(lambda J, X, Y, e=e: arb(1) if T.owned_by_end(k, e, X, Y) is True else arb(-1))
        return out

    def _clamp_derivs(self, k, vp, sgn) -> list:
        """Tests for a curve k touched at a vertex exactly at its end e ∈ R1 (it is listed with e, or
        e's joint partner): the linear function saying that its nearest point is e — a segment's
        foot beyond e, an arc's direction outside its open range (its other end is farther anyway)
        — vanishes there; its derivative into the arc > 0 (and the arc's other half-plane > 0 on
        the box) keeps it positive."""
        from .certificate_rules import linear_rule, outside_range_rule

        T, c, out = self.T, self.curve, []
        if not T.is_curve(k) or k not in vp.listed:
            return out
        for e in T.ends[k]:
            if e not in self.r1:
                continue
            tie = {e} if e >= 0 else {o for o in T.joint_curves(e) if o != k}
            if not (tie & set(vp.listed)) and vp.corner != e:
                continue
            if T.kind[k] == SEGMENT:
                conds, mode = linear_rule(T, k, e, False), "all"
            else:
                mode, conds = outside_range_rule(T, k)
                which = T.end_index(k, e)
                if mode == "max" or len(conds) == 1:
                    conds = [conds[which if len(conds) > 1 else 0]]
                    mode = "all"
            g = [tuple(q_arb(v) for v in cd) for cd in conds]

            def test(J, X, Y, g=g, e=e):
                dx, dy = c.dxy(J)
                vals = []
                for gx, gy, g0 in g:
                    v0 = gx * X + gy * Y + g0
                    vals.append(v0 if v0 > 0 else (gx * dx + gy * dy) * sgn)
                out_v = vals[0]
                for v in vals[1:]:
                    out_v = out_v.min(v)
                return out_v
            out.append(test)
        return out

    def _float_centred(self, idx, pa: float, pb: float, t, X, Y):
        """The mean-value bound in floats, for many sites at once (True: g_k > 0 on the piece).

        Each site k enters by a function h_k ≤ d_k with a unit gradient u_k of known variation:
        a point or a segment by its distance (the projection F_k on a convex set: u_k =
        (x − F_k(x))/d_k), an arc by its circle's signed distance σ_k(|x − c_k| − ρ_k) ≤ d_k (σ_k
        the side of q; u_k = σ_k (x − c_k)/|x − c_k|).  The edge's own distance ρ is that of its
        non-arc site, or, along the bisector of two arcs, exactly σ(|x − c| − ρ_s) of its arc s.  With q a
        float point within δq of γ(τ_m) (τ_m the middle parameter), R ≥ |x − q| on the piece's
        box: h_k(τ_m) − ρ(τ_m) ≥ h_k(q) − ρ(q) − 2δq (1-Lipschitz functions), and
        |(h_k − ρ)'| ≤ |γ'|·(|u_k(q) − u_0(q)| + 2R/(2e_k − R) + 2R/(2e_0 − R)) on the piece when
        every e = |q − F(q)| (|q − c| for a circle) exceeds R (x − F(x) is 1-Lipschitz for the
        projection on a convex set, x − c trivially, and |a/|a| − b/|b|| ≤ 2|a − b|/(|a| + |b|)
        in an inner-product space (Dunkl–Williams), so |u(x) − u(q)| ≤ 2R/(2e − R)); floats carry
        their rounding bounds (:func:`runtime.segments.distance.float_error`, 64 ulp of the
        magnitudes for a circle) and a relative slack."""
        T, c = self.T, self.curve
        m = (pa + pb) / 2
        hw = max(m - pa, pb - m) * (1 + 4 * EPS)
        tm = arb(m)
        Xm, Ym = c.xy(tm)
        qx, qy = float(Xm.mid()), float(Ym.mid())
        dq = float(Xm.rad()) + float(Ym.rad()) + 4 * EPS * (abs(qx) + abs(qy))
        R = (abs(float(X.mid()) - qx) + float(X.rad()) + abs(float(Y.mid()) - qy) + float(Y.rad())) * (1 + 4 * EPS)
        ref = next((s for s in (self.i, self.j) if T.kind[s] != ARC), None)
        ref_side = None
        if ref is None:
            if c.kind != "arc":
                return np.zeros(len(idx), dtype=bool)
            ref, ref_side = c.s, c.sigma
        gx, gy = c.dxy(t)
        gp = up(abs(gx) + abs(gy))
        sites = np.concatenate([[ref], idx])
        Q = np.repeat([[qx, qy]], len(sites), axis=0)
        if not (np.isfinite(qx) and np.isfinite(qy) and np.isfinite(R) and np.isfinite(gp)):
            return np.zeros(len(idx), dtype=bool)
        d, U, e, err = _float_models(T, sites, Q)
        if ref_side is not None:                   # the edge's own arc: its side, not q's
            with np.errstate(divide="ignore", invalid="ignore"):
                d[0] = ref_side * (e[0] - T.R[ref])
                U[0] = ref_side * (Q[0] - T.C[ref]) / e[0]
        with np.errstate(divide="ignore", invalid="ignore"):
            L = gp * (np.abs(U[1:] - U[0]).sum(axis=1) + 2 * R / (2 * (e[1:] - err[1:]) - R) +
                      2 * R / (2 * (e[0] - err[0]) - R) + 1e-12)
            rounding = err[1:] + err[0] + 2 * dq + 16 * EPS * (T.scale + abs(qx) + abs(qy))
            lower = (d[1:] - d[0]) - rounding - L * hw
        return (e[1:] - err[1:] > R) & (e[0] - err[0] > R) & np.isfinite(lower) & (lower > 0)

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
        if g > 0 or any(test(t, X, Y) > 0 for test in self._clamps(k)):
            return True
        T = self.T
        if c.kind == "arc" and c.sigma == 1:
            # the support witness: d_k − t ≥ u·c + ρ − h_k(u) for the contact direction u (far
            # parts of a branch, where the boxes are large)
            from .certificate_tails import support_bound

            ux, uy = c.u(t)
            if ux * c.c[0] + uy * c.c[1] + c.r - support_bound(T, k, ux, uy) > 0:
                return True
        if T.kind[k] == ARC:
            # outside the arc's closed range on the whole box its distance is its nearer end's:
            # both ends farther, each by the mean-value form of a point
            cx, cy, _ = T.arb_arc(k)
            if T.in_range(k, X - cx, Y - cy, closed=True) is False:
                rm = c.rho(tm, Xm, Ym)
                return all(self._point_centred(T.pt_arb(e), t, X, Y, tm, Xm, Ym, rm) for e in T.ends[k])
        return False

    def _point_centred(self, e, t, X, Y, tm, Xm, Ym, rm) -> bool:
        c = self.curve
        ex, ey = e
        gx, gy = c.dxy(t)
        dx, dy = X - ex, Y - ey
        d = hypot(dx, dy)
        g = hypot(Xm - ex, Ym - ey) - rm + ((dx * gx + dy * gy) / d - c.drho(t, X, Y)) * (t - tm)
        return bool(g > 0)

    def _pieces(self, a: float, b: float, special) -> bool:
        """g_k > 0 for every site near each piece, and every condition (``self.conditions``:
        dicts with ``value``, ``lo``, ``hi`` — the covered ends — and ``name``) > 0."""
        T, c = self.T, self.curve
        skip = self.skip | {self.i, self.j}
        conds = list(enumerate(getattr(self, "conditions", [])))
        cuts = np.linspace(a, b, FIRST_PIECES + 1)
        cuts[0], cuts[-1] = a, b
        stack = [(float(cuts[m]), float(cuts[m + 1]), None) for m in range(FIRST_PIECES)][::-1]
        self._fns: dict = {}
        self._convex: dict = {}
        cleared: set = set()
        count = 0
        min_w = (b - a) * 2.0 ** -44
        bad: dict = {}
        pool = self._pool(a, b)
        while stack:
            pa, pb, cands = stack.pop()
            count += 1
            if count > MAX_PIECES:
                self.report_limit("too many pieces: sites too close to the edge to decide")
                return False
            t = interval(pa, pb)
            X, Y = c.xy(t)
            rho = c.rho(t, X, Y)
            failed = []
            for m, cd in conds:
                if (cands is not None and ("cond", m) not in cands) or pb <= cd["lo"] or pa >= cd["hi"]:
                    continue
                if not cd["value"](t, X, Y, rho) > 0 and not self._centred_fn(cd["fns"], t, X, Y, pa, pb):
                    failed.append(("cond", m))
            if not (rho.is_finite() and X.is_finite() and Y.is_finite()):
                failed.append(("cond", -1))
                near = []
            else:
                qx, qy = float(X.mid()), float(Y.mid())
                rq = float(X.rad()) + float(Y.rad())
                rho_hi = up(rho)
                near = [k for k in T.near_in(pool, qx, qy, rho_hi + rq) if k not in skip and k not in cleared]
                if cands is not None:
                    near = [k for k in near if k in cands]
            plain = [k for k in near if k not in special]
            if plain:
                clear, hopeless = self._float_filter(plain, qx, qy, rq, rho_hi, rho, pa, pb, t, X, Y)
                for k, cl, h in zip(plain, clear, hopeless):
                    if cl:
                        continue
                    if h or (not self._farther(k, t, pa, pb, qx, qy, X, Y) and not T.distance(k, X, Y) - rho > 0
                             and not self._centred(k, t, X, Y, pa, pb)):
                        if not h and self._convex_clear(k, a, b):
                            cleared.add(k)
                        else:
                            failed.append(k)
            for k in near:
                if k not in special:
                    continue
                value, cover_lo, cover_hi = special[k]
                if pb <= cover_lo or pa >= cover_hi:
                    continue
                if not value(t, X, Y, rho) > 0 and not self._centred(k, t, X, Y, pa, pb) and \
                        not self._farther(k, t, pa, pb, qx, qy, X, Y):
                    failed.append(k)
            if not failed:
                continue
            if pb - pa <= min_w:
                for k in failed:
                    bad.setdefault(k, (pa, pb))
                continue
            mid = (pa + pb) / 2
            fs = set(failed)
            if ("cond", -1) in fs:
                fs = None
            stack.append((mid, pb, fs))
            stack.append((pa, mid, fs))
        for k, (pa, pb) in sorted(bad.items(), key=lambda kv: str(kv[0])):
            t = arb((pa + pb) / 2)
            X, Y = c.xy(t)
            where = f"near ({float(X.mid()):.6g}, {float(Y.mid()):.6g})"
            if isinstance(k, tuple):
                name = "its curve is not proved finite" if k[1] < 0 else conds[k[1]][1]["name"]
                self.report(f"{name} {where}")
                continue
            value = special[k][0] if k in special else (lambda t, X, Y, rho: T.distance(k, X, Y) - rho)
            v = value(t, X, Y, c.rho(t, X, Y))
            if v < 0:
                self.report(f"site {k} is closer than its sites {where}", k)
            else:
                self.report(f"site {k} is too close to its sites to decide {where}", k)
        return not bad

    def _pool(self, a: float, b: float):
        """The sites near the whole parameter interval [a, b] (the ball of the curve over it,
        widened by ρ's upper end there): :meth:`runtime.segments.certificate_sites.SiteTable.pool`,
        searched again for each piece inside it; None when unbounded or large."""
        t = interval(a, b)
        X, Y = self.curve.xy(t)
        rho = self.curve.rho(t, X, Y)
        if not (rho.is_finite() and X.is_finite() and Y.is_finite()):
            return None
        rq = float(X.rad()) + float(Y.rad())
        return self.T.pool(float(X.mid()), float(Y.mid()), up(rho) + 2 * rq)

    def _float_filter(self, plain, qx, qy, rq, rho_hi, rho, pa, pb, t, X, Y):
        """(clear, hopeless) lists for the sites ``plain`` near a piece: clear when the float
        lower bound of the distance from the piece's centre q exceeds ρ's upper end by the box's
        radius rq (then g_k > 0 on the whole piece: d_k is 1-Lipschitz), or by the mean-value
        filter :meth:`_float_centred`; hopeless when the float upper bound at q is below ρ's lower
        end (not tried in arb: the piece is halved).  The bounds are those of
        :func:`runtime.segments.certificate_float_bounds.bounds_at` (scalar floats, its rounding
        bounds), or of :meth:`runtime.segments.certificate_sites.SiteTable.float_bounds` when a
        site is an elliptic piece."""
        T = self.T
        b = bounds_at(T, plain, qx, qy)
        if b is None:
            idx = np.array(plain, dtype=int)
            dlo, dhi = T.float_bounds(idx, np.repeat([[qx, qy]], len(idx), axis=0))
            dlo, dhi = dlo.tolist(), dhi.tolist()
        else:
            dlo, dhi = b
        rho_lo = float(rho.mid()) - float(rho.rad())
        clear = [lo - rq > rho_hi for lo in dlo]
        hopeless = [hi <= rho_lo for hi in dhi]
        rest = [m for m in range(len(plain)) if not clear[m] and not hopeless[m]]
        if rest:
            got = self._float_centred(np.array([plain[m] for m in rest], dtype=int), pa, pb, t, X, Y)
            for m, g in zip(rest, got.tolist()):
                clear[m] = g
        return clear, hopeless

    def _convex_clear(self, k, a: float, b: float) -> bool:
        """g_k > 0 on the whole straight edge by :func:`runtime.segments.certificate_rules.
        convex_tangents` (cached per site)."""
        if k not in self._convex:
            fns = self._fns.get(k)
            if fns is None:
                fns = self._fns[k] = self._value_fn(k)
            self._convex[k] = convex_tangents(self.T, self.curve, k, fns, a, b)
        return self._convex[k]

    def _centred_fn(self, fns, t, X, Y, pa: float, pb: float) -> bool:
        """A condition > 0 on the piece by the mean-value form (``fns``: (value, deriv) pairs; one
        proved positive suffices when the condition is their maximum, all when it is one)."""
        c = self.curve
        tm = arb((pa + pb) / 2)
        Xm, Ym = c.xy(tm)
        for value, deriv in fns:
            g = value(tm, Xm, Ym, c.rho(tm, Xm, Ym)) + deriv(t, X, Y) * (t - tm)
            if g > 0:
                return True
        return False


def distance_gradient(T, k, X, Y):
    """A ball enclosure of the gradient of d_k on the box (an infinite ball where it is not
    decided: at a site, or where an arc's nearest point may jump)."""
    ax, ay, bx, by = T.arb_ends(k)
    if T.kind[k] == ARC:
        # the gradient is continuous across the range's boundary (there (x − e)/|x − e| is
        # ±(x − c)/|x − c|): where the box straddles it, the hull of both formulas
        cx, cy, rho = T.arb_arc(k)
        wx, wy = X - cx, Y - cy
        inr = T.in_range(k, wx, wy, closed=True)
        cands = []
        if inr is not False:
            n = hypot(wx, wy)
            side = n - rho
            sg = 1 if side > 0 else (-1 if side < 0 else None)
            if sg is None:
                big = arb("0 +/- inf")
                return big, big
            cands.append((sg * wx / n, sg * wy / n))
        if inr is not True:
            da, db = hypot(X - ax, Y - ay), hypot(X - bx, Y - by)
            if not da > db:
                cands.append(((X - ax) / da, (Y - ay) / da))
            if not db > da:
                cands.append(((X - bx) / db, (Y - by) / db))
        gx, gy = cands[0]
        for hx, hy in cands[1:]:
            gx, gy = gx.union(hx), gy.union(hy)
        return gx, gy
    if T.kind[k] == SEGMENT:
        u = T.foot(k, X, Y)
        u = u.max(arb(0)).min(arb(1))
        fx, fy = ax + u * (bx - ax), ay + u * (by - ay)
    else:
        fx, fy = ax, ay
    dx, dy = X - fx, Y - fy
    n = hypot(dx, dy)
    return dx / n, dy / n


def _float_models(T, sites, Q):
    """Per row: a float lower-bound function h ≤ d_site at Q[r] (the distance for points and
    segments, the circle's signed distance σ(|q − c| − ρ) on q's side σ for arcs), its unit
    gradient, the distance e from Q[r] to the point its gradient is taken from (the foot F or the
    centre c) and a rounding bound for h and e (:meth:`PieceProofs._float_centred`)."""
    A, B = T.A[sites], T.B[sites]
    d, tt = distances(A, B, Q)
    err = float_error(A, B, Q) + 8 * EPS * T.scale
    F = A + tt[:, None] * (B - A)
    arc = T.karr[sites] == ARC
    if arc.any():
        F[arc] = T.C[sites[arc]]
        W = Q[arc] - F[arc]
        n = np.hypot(W[:, 0], W[:, 1])
        rad = T.R[sites[arc]]
        side = np.where(n >= rad, 1.0, -1.0)
        d[arc] = side * (n - rad)
        err[arc] = 64 * EPS * (np.abs(Q[arc]).max(axis=1) + np.abs(F[arc]).max(axis=1) + rad + 1.0) + 8 * EPS * T.scale
    V = Q - F
    e = np.hypot(V[:, 0], V[:, 1])
    with np.errstate(divide="ignore", invalid="ignore"):
        U = V / e[:, None]
    if arc.any():
        U[arc] *= side[:, None]
    return d, U, e, err
