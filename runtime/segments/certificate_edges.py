"""Edge proofs of the point/segment certificate (step 3 of :mod:`runtime.segments.certificate`).

An edge (i, j) between its end vertices (proved, listing i and j) or infinity is an arc of the
exact bisector curve of i and j, parametrised in closed form
(:func:`runtime.segments.certificate_curves.bisector_curve`: a line, or a parabola by the foot
parameter).  A proved end vertex lies exactly on that curve (it is equidistant from i and j with
contacts in the closed segments; for two segments the curve is the angle bisector through the
sides of such a vertex), so its parameter is enclosed by projecting its box.  Along the arc the
touching-type distances are the true ones: the feet on the segment sites are affine (lines) or the
parameter itself (parabola) and lie in [0, 1] at both ends.  So every point of the open arc is
equidistant from i and j, and must be strictly closer to them than to every other site k, under
the diagram's convention (a tie between an endpoint and its segment belongs to the endpoint):

* **R1, R2** (k an endpoint of a segment of the edge, or a segment ending at a point of the edge):
  decided on the affine foot parameters along lines and at infinity
  (:mod:`runtime.segments.certificate_rules`); R2 along a parabola is proved like R3 with
  g_k = ∓(foot of k) (beyond the endpoint).
* **R3** any other site: g_k = d_k − ρ > 0.  The parameter interval is cut into pieces, each
  proved by a rigorous lower bound (a float filter with rounding margins, d_k(x) ≥ d_k(q) − |x − q|
  and ρ below its ball's upper end, then
  :meth:`runtime.segments.certificate_sites.SiteTable.distance` on the arb box of the piece);
  pieces that fail are halved, for the failing sites only; candidates come from a k-d tree over
  bounding discs.  At an end vertex listing k, g_k vanishes: there g_k' > 0 (into the arc) is
  proved on [τ*, τ* + δ] (the gradient of the distance to a closed convex set, (x − F)/|x − F|,
  is continuous off the set), or, at a corner c of radius 0 (the curve is c + τ u), g_k(τ) ≥
  τ (D_k − D_i) with D_i = ρ/τ and D_k the distance from u to the line of k (|u| when k leaves c
  away from u), proved > 0 for all τ > 0.
* **Infinite ends** (only perpendicular bisectors of points and perpendiculars at an endpoint):
  :func:`runtime.segments.certificate_rules.prove_tail` proves s ≥ S exactly or with float margins;
  the rest of the edge is a finite interval proved as above.

The polyline lies within the stated tolerance of the arc
(:func:`runtime.segments.certificate_curves.polyline_bound`).

Public API: :class:`EdgeProof`, :func:`prove_edges`.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np
from flint import arb

from ..voronoi.verify.problems import Problem, fault
from .certificate_curves import Line, bisector_curve, down, interval, polyline_bound, q_arb, up
from .certificate_rules import affine_rules, corner_ratio, prove_tail
from .certificate_sites import POINT, SEGMENT, SiteTable, direction_key, hypot
from .distance import distances, float_error

__all__ = ["EdgeProof", "prove_edges"]

EPS = np.finfo(float).eps
#: pieces of one edge before the proof gives up
MAX_PIECES = 4000
#: the finite part of an edge is first cut into this many pieces
FIRST_PIECES = 8


@dataclass
class EdgeProof:
    """``ok``: proved; ``infinite``: (sorted pair, direction key) of each infinite end whose
    direction is exact (lines of points or endpoint perpendiculars)."""

    ok: bool
    infinite: list = field(default_factory=list)


def prove_edges(D, T: SiteTable, vproofs, problems, deadline=None) -> list[EdgeProof]:
    vindex = {v.id: n for n, v in enumerate(D.vertices)}
    out = []
    for e in D.edges:
        if deadline is not None and time.perf_counter() > deadline:
            out.append(EdgeProof(False, _directions(T, e, D, vindex, vproofs)))
            problems.append(Problem(f"edge {e.id}: time limit reached, not checked", kind="edge", edge=e.id,
                                    fault=False))
            continue
        try:
            out.append(_EdgeProver(T, D, e, vindex, vproofs, problems).run())
        except (ValueError, ZeroDivisionError, ArithmeticError) as exc:      # pragma: no cover - defensive
            problems.append(Problem(f"edge {e.id}: not proved ({exc.__class__.__name__}: {exc})", kind="edge",
                                    edge=e.id, fault=False))
            out.append(EdgeProof(False, _directions(T, e, D, vindex, vproofs)))
    return out


def _directions(T, e, D, vindex, vproofs) -> list:
    return _EdgeProver(T, D, e, vindex, vproofs, []).directions_only()


class _EdgeProver:
    def __init__(self, T: SiteTable, D, e, vindex, vproofs, problems):
        self.T, self.D, self.e = T, D, e
        self.vindex, self.vproofs, self.problems = vindex, vproofs, problems
        self.i, self.j = (int(s) for s in e.sites) if len(e.sites) == 2 else (-1, -1)
        self.name = f"edge {e.id} (sites {', '.join(map(str, e.sites))})"

    # -------------------------------------------------------------- reporting
    def report(self, msg, *extra):
        self.problems.append(fault(f"{self.name}: {msg}", kind="edge", edge=self.e.id,
                                   sites=(self.i, self.j) + tuple(extra)))

    def report_limit(self, msg, *extra):
        self.problems.append(Problem(f"{self.name}: {msg}", kind="edge", edge=self.e.id,
                                     sites=(self.i, self.j) + tuple(extra), fault=False))

    # -------------------------------------------------------------- set-up
    def _setup(self) -> str | None:
        T, e, i, j = self.T, self.e, self.i, self.j
        if not (0 <= i < T.n and 0 <= j < T.n) or i == j:
            return "needs two distinct valid sites"
        if T.kind[i] is None or T.kind[j] is None or any(T.kind[s] == SEGMENT and T.ends[s] is None for s in (i, j)):
            return "unsupported site"
        if e.closed:
            return "a diagram of points and segments has no closed edge"
        self.P = np.asarray(e.polyline, dtype=float).reshape(-1, 2)
        if len(self.P) < 2 or not np.isfinite(self.P).all():
            return "needs a finite polyline of at least two points"
        self.endv = []
        for v in e.ends:
            if v is None:
                self.endv.append(None)
                continue
            if v not in self.vindex:
                return f"end {v} is not a vertex of the diagram"
            self.endv.append(self.vproofs[self.vindex[v]])
        if e.ends[0] is not None and e.ends[0] == e.ends[1]:
            return "both ends are the same vertex"
        curve = bisector_curve(T, i, j, [vp for vp in self.endv if vp is not None and vp.ok])
        if isinstance(curve, str):
            return curve
        self.curve = curve
        return None

    def _infinite_signs(self):
        """+1/−1 per infinite end: the way of τ towards it (from the polyline); None for a finite end."""
        c = self.curve
        tau = [float(c.param(arb(float(p[0])), arb(float(p[1]))).mid()) for p in (self.P[0], self.P[-1])]
        fin = [None if vp is None else (float(c.param(vp.x, vp.y).mid()) if vp.ok and vp.x is not None else None)
               for vp in self.endv]
        signs = [None, None]
        for end in (0, 1):
            if self.e.ends[end] is not None:
                continue
            other = 1 - end
            ref = tau[other] if self.e.ends[other] is None else fin[other]
            if ref is None:
                ref = tau[other]
            d = tau[end] - ref
            signs[end] = 0 if d == 0 else (1 if d > 0 else -1)
        return signs

    def directions_only(self) -> list:
        if self._setup() is not None or None not in self.e.ends:
            return []
        if not isinstance(self.curve, Line) or self.curve.wq is None:
            return []
        return self._dirs(self._infinite_signs())

    def _dirs(self, signs):
        pair = tuple(sorted((self.i, self.j)))
        wq = self.curve.wq
        return [(pair, direction_key((sg * wq[0], sg * wq[1]))) for sg in signs if sg]

    # -------------------------------------------------------------- the proof
    def run(self) -> EdgeProof:
        msg = self._setup()
        if msg is not None:
            self.report(msg)
            return EdgeProof(False)
        c, e = self.curve, self.e
        infinite = []
        if None in e.ends:
            if not (isinstance(c, Line) and c.wq is not None and c.kind in ("points", "perp")):
                self.report("only bisectors of two points and perpendiculars at an endpoint reach infinity")
                return EdgeProof(False)
            signs = self._infinite_signs()
            if 0 in signs:
                self.report("the polyline does not show which way the edge goes to infinity")
                return EdgeProof(False)
            infinite = self._dirs(signs)
        for end, vp in enumerate(self.endv):
            if vp is None:
                continue
            if not vp.ok:
                self.report_limit(f"its end vertex {e.ends[end]} is not proved")
                return EdgeProof(False, infinite)
            if self.i not in vp.listed or self.j not in vp.listed:
                self.report(f"its end vertex {e.ends[end]} does not list both its sites")
                return EdgeProof(False, infinite)
        # ends: ("v", τ ball, proof) or ("inf", sign of τ)
        ends = []
        for end, vp in enumerate(self.endv):
            if vp is None:
                ends.append(("inf", signs[end]))
            else:
                ends.append(("v", c.param(vp.x, vp.y), vp, e.ends[end]))
        if ends[0][0] == "inf" and ends[1][0] == "inf":
            if signs[0] == signs[1]:
                self.report("both infinite ends go the same way")
                return EdgeProof(False, infinite)
            lo, hi = (ends[0], ends[1]) if signs[0] < 0 else (ends[1], ends[0])
        elif ends[0][0] == "inf" or ends[1][0] == "inf":
            fin = ends[0] if ends[0][0] == "v" else ends[1]
            inf = ends[1] if fin is ends[0] else ends[0]
            lo, hi = (fin, inf) if inf[1] > 0 else (inf, fin)
        else:
            t0, t1 = ends[0][1], ends[1][1]
            if t0 < t1:
                lo, hi = ends
            elif t1 < t0:
                hi, lo = ends
            else:
                self.report("its two ends are the same point (zero length) or too close to order")
                return EdgeProof(False, infinite)
        self.lo, self.hi = lo, hi
        ok = affine_rules(self)
        ok = self._positivity() and ok
        msg = polyline_bound(c, self.P, float(e.tolerance), lo[1] if lo[0] == "v" else None,
                             hi[1] if hi[0] == "v" else None, self.endv)
        if msg is not None:
            self.report(msg)
            ok = False
        return EdgeProof(ok, infinite)

    # -------------------------------------------------------------- R3 (and R2 on a parabola)
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

    def _positivity(self) -> bool:
        T, c, lo, hi = self.T, self.curve, self.lo, self.hi
        ok = True
        # tails first: they fix the finite parameter range
        a = down(lo[1]) if lo[0] == "v" else None
        b = up(hi[1]) if hi[0] == "v" else None
        if hi[0] == "inf":
            S = prove_tail(self, +1, a if a is not None else 0.0)
            if S is None:
                ok = False
                S = (a if a is not None else 0.0) + 1.0
            b = S
        if lo[0] == "inf":
            S = prove_tail(self, -1, -(b if hi[0] == "v" else 0.0))
            if S is None:
                ok = False
                S = 1.0 - (b if hi[0] == "v" else 0.0)
            a = -S
        if not ok:
            return False
        span = b - a
        if not span > 0:
            self.report("its parameter interval is empty")
            return False
        if isinstance(c, Line) and c.anchor is not None:
            return self._concave()
        # competitors tied at the end vertices
        special: dict = {}
        self.r1 = {e for s in (self.i, self.j) if T.kind[s] == SEGMENT for e in T.ends[s]} - {self.i, self.j}
        if c.kind == "parabola":
            p = self.i if T.kind[self.i] == POINT else self.j
            tied_r2 = {k for k in T.incident[p] if k not in (self.i, self.j)}
        else:
            tied_r2 = set()
        ties: dict = {}
        for end in (lo, hi):
            if end[0] != "v":
                continue
            # g_k = 0 at the vertex for its listed sites, and may be for a segment ending at a
            # listed point (foot clamped there); g_k ≥ 0 for every site (vertex emptiness)
            vp = end[2]
            near = set(vp.listed) | {s for p in vp.listed if T.kind[p] == POINT for s in T.incident[p]}
            near = {k for k in near | tied_r2 if k not in (self.i, self.j) and k not in self.skip}
            ties[id(end)] = {k for k in near if k in vp.listed or
                             not self._value_fn(k)[0](end[1], vp.x, vp.y, vp.r) > 0}
        for k in set().union(*ties.values(), tied_r2):
            value, deriv = self._value_fn(k)
            cover_lo, cover_hi = -math.inf, math.inf
            for end, at_lo in ((lo, True), (hi, False)):
                if end[0] == "v" and k in ties[id(end)]:
                    cv = self._tie_cover(k, end, at_lo, deriv, span)
                    if cv is None:
                        self.report(f"site {k} is not proved farther than its sites next to its end vertex "
                                    f"{end[3]}", k)
                        ok = False
                        cv = -math.inf if at_lo else math.inf
                    if at_lo:
                        cover_lo = cv
                    else:
                        cover_hi = cv
            special[k] = (value, cover_lo, cover_hi)
        return self._pieces(a, b, special) and ok

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

    def _concave(self) -> bool:
        """A line whose common distance is ρ = |x − P| for a point P (two points, or an endpoint and
        its segment): h_k = d_k² − ρ² is concave along it (the minimum over the points p of site k
        of |x − p|² − |x − P|², affine in x), ≥ 0 at proved end vertices (their emptiness) and > 0
        at a proved tail start.  So h_k > 0 on the open arc unless it vanishes at both ends — only
        for sites at the radius of both end vertices — and then (concave, ≥ 0, zero at both ends)
        h_k > 0 inside iff it is at one interior point: the middle, in arb."""
        T, c, lo, hi = self.T, self.curve, self.lo, self.hi
        if lo[0] != "v" or hi[0] != "v":
            return True
        both = (self._at_radius(lo[2]) & self._at_radius(hi[2])) - self.skip - {self.i, self.j}
        t = (lo[1] + hi[1]) / 2
        X, Y = c.xy(t)
        rho = c.rho(t, X, Y)
        ok = True
        for k in sorted(both):
            if not T.distance(k, X, Y) > rho:
                self.report(f"site {k} is at the distance of its sites at both ends and not proved "
                            "farther in between", k)
                ok = False
        return ok

    def _at_radius(self, vp) -> set:
        """The sites that may be at exactly the radius of a proved vertex: its listed sites, the
        corner point, segments ending at a listed point (foot clamped there)."""
        T = self.T
        out = set(vp.listed) | ({vp.corner} if vp.corner is not None else set())
        return out | {s for p in list(out) if T.kind[p] == POINT for s in T.incident[p]}

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

