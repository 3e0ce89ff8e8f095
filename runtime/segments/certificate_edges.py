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
* **R3 on lines of a point anchor** (two points; an endpoint e and its segment, where ρ = |x − e|):
  h_k = d_k² − ρ² is concave along the line (the minimum over the points p of site k of
  |x − p|² − |x − P|², affine in x), ≥ 0 at proved end vertices (their emptiness) and > 0 where a
  proved tail starts, hence > 0 on the open arc — unless h_k vanishes at both ends (a site at the
  radius of both end vertices), when one interior value > 0 (the middle, in arb) suffices: a
  concave h ≥ 0 vanishing at both ends and at an interior point vanishes on the whole interval.
  No subdivision is needed for these edges.
* **R3** otherwise (parabolas, bisectors of two segments): g_k = d_k − ρ > 0 on pieces of the
  parameter interval, with covers next to end vertices where g_k vanishes
  (:mod:`runtime.segments.certificate_pieces`).
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
from .certificate_curves import Line, bisector_curve, down, polyline_bound, up
from .certificate_pieces import PieceProofs
from .certificate_rules import affine_rules, prove_tail
from .certificate_sites import POINT, SEGMENT, SiteTable, direction_key

__all__ = ["EdgeProof", "prove_edges"]



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


class _EdgeProver(PieceProofs):
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
