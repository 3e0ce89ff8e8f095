"""R3 along straight edges of a point anchor (for :mod:`runtime.segments.certificate_edges`):
two points, an end and its segment or arc, the two curves of a smooth joint — where the common
distance is ρ = |x − P| for a point P.

For every closed site k, h_k = d_k² − ρ² is the minimum over the points p of k of
|x − p|² − |x − P|², affine in x, hence concave along the line; it is ≥ 0 at proved end vertices
(their emptiness) and > 0 where a proved tail starts, hence > 0 on the open arc — unless it
vanishes at both ends (a site at the radius of both end vertices), when one interior value > 0
(the middle, in arb) suffices: a concave h ≥ 0 vanishing at both ends and at an interior point
vanishes on the whole interval.  On the line through the centre of two half circles joined at
both ends ρ = |x − j| on each ray from the centre (j its joint): the argument runs on each ray,
with every other site proved farther than ρ at the centre.

Public API: :class:`LineProofs` (mixed into the edge prover).
"""
from __future__ import annotations

from .certificate_curves import q_arb
from .certificate_sites import POINT, hypot

__all__ = ["LineProofs"]


class LineProofs:
    """The concavity proofs of straight edges (module docstring)."""

    def _concave(self) -> bool:
        """Concavity of h_k = d_k² − ρ² along a line of a point anchor (module docstring)."""
        c, lo, hi = self.curve, self.lo, self.hi
        if c.anchor2 is not None:
            return self._split_line()
        if lo[0] != "v" or hi[0] != "v":
            return True
        both = (self._at_radius(lo[2]) & self._at_radius(hi[2])) - self.skip - {self.i, self.j}
        t = (lo[1] + hi[1]) / 2
        X, Y = c.xy(t)
        rho = c.rho(t, X, Y)
        return self._farther_between(both, X, Y, rho)

    def _split_line(self) -> bool:
        """The line through the centre of two half circles: ρ = |x − j| on each ray from the
        centre (j its joint), where h_k = d_k² − ρ² is concave; with every other site farther than
        ρ at the centre (in balls) the argument of :meth:`_concave` runs on each ray's part."""
        T, c, lo, hi = self.T, self.curve, self.lo, self.hi
        split = q_arb(c.split)
        inside = (lo[0] == "inf" or lo[1] < split) and (hi[0] == "inf" or hi[1] > split)
        ok = True
        if inside:
            X, Y = c.xy(split)
            rho = T.distance(self.i, X, Y)
            for k in T.near(float(X.mid()), float(Y.mid()), float(rho.upper())):
                if k not in (self.i, self.j) and k not in self.skip and not T.distance(k, X, Y) > rho:
                    self.report(f"site {k} is not proved farther than its sites at the centre", k)
                    ok = False
            return ok
        if lo[0] != "v" or hi[0] != "v":
            return True                        # a vertex and a tail on one ray
        anchor = c.anchor if lo[1] > split else tuple(q_arb(v) for v in c.anchor2)
        both = (self._at_radius(lo[2]) & self._at_radius(hi[2])) - self.skip - {self.i, self.j}
        X, Y = c.xy((lo[1] + hi[1]) / 2)
        rho = hypot(X - anchor[0], Y - anchor[1])
        return self._farther_between(both, X, Y, rho)

    def _farther_between(self, both, X, Y, rho) -> bool:
        """Every site of ``both`` (at the radius at both end vertices) strictly farther than ρ at
        the middle point (X, Y); the others are reported."""
        ok = True
        for k in sorted(both):
            if not self.T.distance(k, X, Y) > rho:
                self.report(f"site {k} is at the distance of its sites at both ends and not proved "
                            "farther in between", k)
                ok = False
        return ok

    def _at_radius(self, vp) -> set:
        """The sites that may be at exactly the radius of a proved vertex: its listed sites, the
        corner point, curves ending at a listed point (nearest point clamped there)."""
        T = self.T
        out = set(vp.listed) | ({vp.corner} if vp.corner is not None else set())
        return out | {s for p in list(out) if T.kind[p] == POINT for s in T.incident[p]}
