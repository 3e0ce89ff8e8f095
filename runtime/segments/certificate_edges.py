"""Edge proofs of the point/segment/arc certificate (step 3 of :mod:`runtime.segments.certificate`).

An edge (i, j) between its end vertices (proved, listing i and j) or infinity is an arc of the
exact bisector curve of i and j, parametrised in closed form
(:func:`runtime.segments.certificate_curves.bisector_curve`: a line, a parabola by the foot
parameter, an arc's bisector by the contact angle, :mod:`runtime.segments.certificate_arcs`).
A proved end vertex lies exactly on that curve (it is equidistant from i and j with contacts in
the closed sites; for two segments the curve is the angle bisector through the sides of such a
vertex; for an arc the sides σ, τ are read there), so its parameter is enclosed by projecting its
box (exactly 0 or β for an arc touched at its end).  The straight bisectors of an arc's end and the
arc (the radial ray from the centre through the end) and of the two curves of a smooth joint (the
normal line, on the rays from the arcs' centres through the joint) hold only on part of their
line: the edge's parameter interval must lie there.  Along the curve the touching-type distances
are the true ones: the feet on segments are affine (lines) or the parameter (parabola) and in
[0, 1] at both ends; along an arc's bisector the contact angle stays in the arc's range by
construction and the partner's contact is a condition of the pieces.  So every point of the open
arc is equidistant from i and j, and must be strictly closer to them than to every other site k,
under the convention (a tie between an end and its curve belongs to the end):

* **R1, R2** (an end of a curve of the edge; a curve ending at a point of the edge):
  :mod:`runtime.segments.certificate_rules` — along lines decided at the ends and at infinity,
  along curves as conditions of the pieces.
* **R3 on lines of a point anchor** (two points; an end and its segment or arc; a smooth joint —
  ρ = |x − P|): h_k = d_k² − ρ² is concave along the line for *every* closed site k (the minimum
  over the points p of k of |x − p|² − |x − P|², affine in x), ≥ 0 at proved end vertices (their
  emptiness) and > 0 where a proved tail starts, hence > 0 on the open arc — unless h_k vanishes at
  both ends (a site at the radius of both end vertices), when one interior value > 0 (the middle,
  in arb) suffices.
* **R3** otherwise (parabolas, bisectors of two segments, arcs' bisectors): g_k = d_k − ρ > 0 on
  pieces of the parameter interval, with covers next to end vertices where g_k vanishes
  (:mod:`runtime.segments.certificate_pieces`).
* **Infinite ends**: straight ones (two points, an endpoint's perpendicular, an arc end's radial
  ray, a joint's normal line) by :func:`runtime.segments.certificate_rules.prove_tail`; an arc's
  hyperbola-like branch up to its pole by :mod:`runtime.segments.certificate_tails`.

The polyline lies within the stated tolerance of the arc
(:func:`runtime.segments.certificate_curves.polyline_bound`).

Public API: :class:`EdgeProof`, :func:`prove_edges`.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np
from flint import arb, ctx

from ..certify.foot import working_prec
from ..voronoi.verify.problems import Problem, fault
from .certificate_curves import Line, bisector_curve, down, polyline_bound, q_arb, up
from .certificate_edge_conditions import arc_conditions, cover_conditions
from .certificate_convexity import settled_by_convexity
from .certificate_lines import LineProofs
from .certificate_pieces import PieceProofs
from .certificate_rules import affine_rules, prove_tail
from .certificate_sites import POINT, SiteTable, direction_key
from .certificate_tails import arc_pole, arc_tail

__all__ = ["EdgeProof", "prove_edges"]

STRAIGHT_INFINITE = ("points", "perp", "radial", "joint")


@dataclass
class EdgeProof:
    """``ok``: proved; ``infinite``: (sorted pair, key) of each infinite end (an exact direction,
    or ("tangent", ±1) for an arc's branch)."""

    ok: bool
    infinite: list = field(default_factory=list)


def prove_edges(D, T: SiteTable, vproofs, problems, deadline=None) -> list[EdgeProof]:
    vindex = {v.id: n for n, v in enumerate(D.vertices)}
    out = []
    for e in D.edges:
        if deadline is not None and time.perf_counter() > deadline:
            out.append(EdgeProof(False, _EdgeProver(T, D, e, vindex, vproofs, []).directions_only()))
            problems.append(Problem(f"edge {e.id}: time limit reached, not checked", kind="edge", edge=e.id,
                                    fault=False))
            continue
        try:
            out.append(_prove_edge(T, D, e, vindex, vproofs, problems))
        except (ValueError, ZeroDivisionError, ArithmeticError) as exc:      # pragma: no cover - defensive
            problems.append(Problem(f"edge {e.id}: not proved ({exc.__class__.__name__}: {exc})", kind="edge",
                                    edge=e.id, fault=False))
            out.append(EdgeProof(False, _EdgeProver(T, D, e, vindex, vproofs, []).directions_only()))
    return out


def _prove_edge(T: SiteTable, D, e, vindex, vproofs, problems) -> EdgeProof:
    """One edge; a straight edge of two nearly parallel segments that fails is tried once more at
    4 times the precision: its line is parametrised from the segments' far intersection O, and
    the parameters x − O of its end vertices cancel about log2(|O| / length) bits."""
    own: list = []
    prover = _EdgeProver(T, D, e, vindex, vproofs, own)
    proof = prover.run()
    curve = getattr(prover, "curve", None)
    if not proof.ok and isinstance(curve, Line) and curve.kind == "segments" and curve.anchor is None:
        with working_prec(4 * ctx.prec):
            again: list = []
            retry = _EdgeProver(T, D, e, vindex, vproofs, again).run()
        if retry.ok:
            proof, own = retry, again
    problems.extend(own)
    return proof


class _EdgeProver(PieceProofs, LineProofs):
    def __init__(self, T: SiteTable, D, e, vindex, vproofs, problems):
        self.T, self.D, self.e = T, D, e
        self.vindex, self.vproofs, self.problems = vindex, vproofs, problems
        self.i, self.j = (int(s) for s in e.sites) if len(e.sites) == 2 else (-1, -1)
        self.name = f"edge {e.id} (sites {', '.join(map(str, e.sites))})"
        self.conditions: list = []
        self.linear: list = []

    # -------------------------------------------------------------- reporting
    def report(self, msg, *extra):
        self.problems.append(fault(f"{self.name}: {msg}", kind="edge", edge=self.e.id,
                                   sites=(self.i, self.j) + tuple(x for x in extra if x >= 0)))

    def report_limit(self, msg, *extra):
        self.problems.append(Problem(f"{self.name}: {msg}", kind="edge", edge=self.e.id,
                                     sites=(self.i, self.j) + tuple(x for x in extra if x >= 0), fault=False))

    # -------------------------------------------------------------- set-up
    def _setup(self) -> str | None:
        T, e, i, j = self.T, self.e, self.i, self.j
        if not (0 <= i < T.n and 0 <= j < T.n) or i == j:
            return "needs two distinct valid sites"
        if T.kind[i] is None or T.kind[j] is None or any(T.is_curve(s) and T.ends[s] is None for s in (i, j)):
            return "unsupported site"
        if e.closed:
            return "a diagram of points, segments and arcs has no closed edge"
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
        curve = bisector_curve(T, i, j, [vp for vp in self.endv if vp is not None and vp.ok], self.P)
        if isinstance(curve, str):
            return curve
        self.curve = curve
        return None

    def _infinite_signs(self):
        """+1/−1 per infinite end: the way of τ towards it (from the polyline); None for a finite end."""
        c = self.curve
        tau = [float(c.param(arb(float(p[0])), arb(float(p[1]))).mid()) for p in (self.P[0], self.P[-1])]
        fin = [None if vp is None else (float(c.vertex_param(vp).mid()) if vp.ok and vp.x is not None else None)
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
        signs = self._infinite_signs()
        if isinstance(self.curve, Line) and self.curve.wq is not None:
            return self._dirs(signs)
        if self.curve.kind == "arc":
            out = []
            for end, sg in enumerate(signs):
                if sg:
                    vp = self.endv[1 - end]
                    m = self.P[len(self.P) // 2]
                    ref = self.curve.param(arb(float(m[0])), arb(float(m[1]))) if vp is None else \
                        self.curve.vertex_param(vp)
                    pole = arc_pole(self.curve, ref, sg)
                    if pole is not None:
                        from .certificate_hull import tangent_sign
                        a = self.curve.u(pole)
                        key = tangent_sign(self.T, self.i, self.j, a[0], a[1])
                        if key is not None:
                            out.append((tuple(sorted((self.i, self.j))), ("tangent", key)))
            return out
        return []

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
        signs = [None, None]
        if None in e.ends:
            straight = isinstance(c, Line) and c.wq is not None and c.kind in STRAIGHT_INFINITE
            if not (straight or c.kind == "arc"):
                self.report("only bisectors of two points, perpendiculars at an endpoint, radial rays at an arc's "
                            "end, normal lines at a smooth joint and an arc's branches reach infinity")
                return EdgeProof(False)
            signs = self._infinite_signs()
            if 0 in signs:
                self.report("the polyline does not show which way the edge goes to infinity")
                return EdgeProof(False)
            if straight:
                for sg in signs:
                    if sg and c.valid[0 if sg < 0 else 1] is not None:
                        self.report("its line holds only on a ray from an arc's centre, and it goes the other way "
                                    "to infinity")
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
        ends = [("inf", signs[end]) if vp is None else ("v", c.vertex_param(vp), vp, e.ends[end])
                for end, vp in enumerate(self.endv)]
        order = self._order(ends, signs)
        if order is None:
            return EdgeProof(False, infinite)
        self.lo, self.hi = order
        if not self._in_valid_range():
            return EdgeProof(False, infinite)
        ok = affine_rules(self)
        if c.kind == "arc":
            self.conditions = arc_conditions(self)
        elif self.linear:
            self.conditions = arc_conditions(self, only_linear=True)
        if c.kind == "arc" and None in e.ends:
            infinite = self.directions_only()
        ok = self._positivity() and ok
        lo, hi = self.lo, self.hi
        msg = polyline_bound(c, self.P, float(e.tolerance), lo[1] if lo[0] == "v" else None,
                             hi[1] if hi[0] == "v" else None, self.endv)
        if msg is not None:
            self.report(msg)
            ok = False
        return EdgeProof(ok, infinite)

    def _order(self, ends, signs):
        if ends[0][0] == "inf" and ends[1][0] == "inf":
            if signs[0] == signs[1]:
                self.report("both infinite ends go the same way")
                return None
            return (ends[0], ends[1]) if signs[0] < 0 else (ends[1], ends[0])
        if ends[0][0] == "inf" or ends[1][0] == "inf":
            fin = ends[0] if ends[0][0] == "v" else ends[1]
            inf = ends[1] if fin is ends[0] else ends[0]
            return (fin, inf) if inf[1] > 0 else (inf, fin)
        t0, t1 = ends[0][1], ends[1][1]
        if t0 < t1:
            return ends[0], ends[1]
        if t1 < t0:
            return ends[1], ends[0]
        self.report("its two ends are the same point (zero length) or too close to order")
        return None

    def _in_valid_range(self) -> bool:
        """The parameter interval lies where the curve is the bisector: a ray's side, an arc's
        angular range."""
        c, lo, hi = self.curve, self.lo, self.hi
        if isinstance(c, Line):
            vlo, vhi = c.valid

            def centre(end):                       # the ray's origin: an arc's centre vertex
                return end[0] == "v" and end[2].centre_of in (self.i, self.j)
            if (vlo is not None and lo[0] == "v" and not centre(lo) and not lo[1] >= q_arb(vlo)) or \
                    (vhi is not None and hi[0] == "v" and not centre(hi) and not hi[1] <= q_arb(vhi)):
                self.report("it leaves the ray from an arc's centre on which its line is the bisector")
                return False
            return True
        if c.kind == "arc":
            def inside(p):
                return (p.is_exact() and p == 0) or p is c.beta or bool(p > 0 and p < c.beta)
            if not all(inside(end[1]) for end in (lo, hi) if end[0] == "v"):
                self.report("its contact leaves the arc's angular range at an end vertex")
                return False
        return True

    # -------------------------------------------------------------- R3 (and conditions)
    def _positivity(self):
        c, lo, hi = self.curve, self.lo, self.hi
        ok = True
        a = down(lo[1]) if lo[0] == "v" else None
        b = up(hi[1]) if hi[0] == "v" else None
        if c.kind == "arc":
            for end, sg in ((hi, 1), (lo, -1)):
                if end[0] != "inf":
                    continue
                fin = lo if sg > 0 else hi
                if fin[0] == "v":
                    theta_fin = fin[1]
                else:                              # a whole branch: from a point of its polyline
                    m = self.P[len(self.P) // 2]
                    theta_fin = c.param(arb(float(m[0])), arb(float(m[1])))
                pole = arc_pole(c, theta_fin, sg)
                if pole is None:
                    self.report("its curve has no infinite branch that way")
                    return False
                res = arc_tail(self, sg, pole, theta_fin)
                if res is None:
                    return False
                if sg > 0:
                    b = res[0]
                else:
                    a = res[0]
        else:
            if hi[0] == "inf":
                S = prove_tail(self, +1, a if a is not None else 0.0)
                if S is None:
                    return False
                b = S
            if lo[0] == "inf":
                S = prove_tail(self, -1, -(b if hi[0] == "v" else 0.0))
                if S is None:
                    return False
                a = -S
        span = b - a
        if not span > 0:
            self.report("its parameter interval is empty")
            return False
        if isinstance(c, Line) and c.anchor is not None:
            return self._concave()
        self.skip |= settled_by_convexity(self, lo, hi)
        special = self._ties(lo, hi, span)
        if special is None:
            ok = False
            special = {}
        ok = cover_conditions(self, span) and ok
        return self._pieces(a, b, special) and ok

    def _ties(self, lo, hi, span):
        """The sites at the radius of an end vertex, with their covers: {k: (value, lo, hi)}."""
        T = self.T
        special: dict = {}
        self.r1 = {e for s in (self.i, self.j) if T.is_curve(s) for e in T.ends[s]} - {self.i, self.j}
        ties: dict = {}
        for end in (lo, hi):
            if end[0] != "v":
                continue
            vp = end[2]
            near = set(vp.listed) | {s for p in vp.listed if T.kind[p] == POINT for s in T.incident[p]}
            near = {k for k in near if k not in (self.i, self.j) and k not in self.skip}
            ties[id(end)] = {k for k in near if k in vp.listed or
                             not self._value_fn(k)[0](end[1], vp.x, vp.y, vp.r) > 0}
        ok = True
        for k in set().union(*ties.values()) if ties else set():
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
        return special if ok else None
