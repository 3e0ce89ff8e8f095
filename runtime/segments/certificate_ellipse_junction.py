"""The edge of an elliptic piece and its own end E when it runs through E's centre of curvature:
the normal line at E, then the foot curve of the piece and E (for
:mod:`runtime.segments.certificate_ellipse_edges`; thesis §2.2 — the end is a harmless point site
owning the ties of its piece — and ch. 4, the offset of the ellipse by its foot point).

Let E = e(ψ) be a point-site end of a monotone piece (:func:`runtime.segments.
certificate_ellipse_secant.monotone_piece`), w = (e'_y, −e'_x)(ψ) the exact outward normal,
det = det(M, N).  The boundary between E's region and the piece's is, from outside inwards:

* the **normal line** x = E + u w for u ≥ u_C = −|w|²/det (rational): E is the piece's unique
  nearest point there — outside (u > 0) by convexity, inside because the secant factor
  L(ψ) = |e'(ψ)|² + u det = det·(u − u_C) ≥ 0 at the contact and L > 0 at the piece's other end
  (that end farther than ρ = |u||w|), L strictly monotone along the piece
  (:mod:`runtime.segments.certificate_ellipse_secant`).  At u = u_C, x is E's centre of curvature
  C (ρ = |w|³/det, the radius of curvature): there f(φ) − ρ² vanishes to third order at ψ, the
  point where every first- or second-order test of the nearest point degenerates;
* the **foot curve** γ_E(φ) = e(φ) − t_E(φ) ν(φ), t_E = |e'((φ + ψ)/2)|² |e'(φ)|/det, for φ from ψ
  into the piece: the points of the inner normal at e(φ) equidistant from e(φ) and E, with no 0/0
  at φ = ψ, where γ_E(ψ) = E − (|w|²/det) w = C: the two curves meet at C, both tangent to the
  normal line there (γ_E'(ψ) = −t_E'(ψ) ν(ψ): the evolute's tangent).  Along it L(ψ) = 0 by
  construction, so e(φ) and E are the piece's nearest points when L > 0 at the other end.

Both halves are one curve in the parameter θ: θ ≤ 0 the normal line, u = u_C − θ (θ = 0 at C);
θ ≥ 0 the foot curve at φ = ψ + θ (a start) or ψ − θ (an end).  The curve is C¹ up to a speed
change at θ = 0; every piece of the edge proof lies on one side of θ = 0 (``cuts``), derivative
balls over a piece reaching both sides are unions (Lebourg's mean value theorem holds for the
piecewise C¹ curve), and the chord bound across θ = 0 adds the distance from C to the chord (the
curve on each side lies within its own chord bound of its chord to C, whose points are within
that distance of the whole chord: distance to a convex set is convex).

The region of E on the normal line: a point there is nearer to E than to the piece's interior,
the tie is E's (the certificate's convention), and it is a limit of the piece's region (across
the line f'(ψ) changes sign), so it lies on the diagram; so are the points of γ_E, where the
piece's two nearest points are e(φ) and E.

Public API: :class:`EndCurve`.
"""
from __future__ import annotations

import math
from fractions import Fraction

from flint import arb

from ..certify.foot import to_arb
from .certificate_ellipse_curves import Jet, sag_bound, secant_nearest
from .certificate_ellipse_secant import end_foot_t, monotone_piece, speed2_mid
from .certificate_sites import SiteTable, hypot, sq
from .ellipse_pieces import interior_foot, piece_feet

__all__ = ["EndCurve"]


def _seg_dist(C, A, B):
    """A ball holding the distance from the box C to the segment between the boxes A and B."""
    dx, dy = B[0] - A[0], B[1] - A[1]
    L2 = sq(dx) + sq(dy)
    if not L2 > 0:
        return hypot(C[0] - A[0], C[1] - A[1])
    u = (((C[0] - A[0]) * dx + (C[1] - A[1]) * dy) / L2).max(arb(0)).min(arb(1))
    return hypot(C[0] - A[0] - u * dx, C[1] - A[1] - u * dy)


class EndCurve:
    """The normal line at end ``p`` of piece ``s``, then γ_E (module docstring)."""

    kind = "ellipse-end"
    straight = False
    cuts = (0.0,)

    @staticmethod
    def applies(T: SiteTable, s: int, p: int) -> bool:
        return T.is_endpoint(p, s) and monotone_piece(T.piece[s])

    def __init__(self, T: SiteTable, s: int, p: int):
        self.T, self.s, self.p = T, s, p
        P = self.P = T.piece[s]
        self.which = T.which_end(s, p)
        self.dir = 1 if self.which == 0 else -1
        self.cs = P.ua if self.which == 0 else P.ub
        self.psi = P.arb_params()[self.which]
        (Mx, My), (Nx, Ny) = P.M, P.N
        cp, sp = (Fraction(v) for v in self.cs)
        ex, ey = -sp * Mx + cp * Nx, -sp * My + cp * Ny          # e'(ψ), exact
        self.wq = (ey, -ex)
        self.w = (to_arb(ey), to_arb(-ex))
        self.w2q = ex * ex + ey * ey
        self.wn = to_arb(self.w2q).sqrt()
        self.det = Fraction(Mx) * Ny - Fraction(My) * Nx
        self.uC = -self.w2q / self.det
        self.E = T.pt_arb(p)
        self.Eq = T.pt(p)
        self.c = tuple(to_arb(v) for v in P.c)
        self.M = tuple(to_arb(v) for v in P.M)
        self.N = tuple(to_arb(v) for v in P.N)
        self.at: dict = {}

    # ------------------------------------------------------------------ the two halves
    def _split(self, J):
        """(normal part θ ≤ 0, foot part θ ≥ 0) of the ball J, None where J does not reach."""
        lo, hi = arb(J.lower()), arb(J.upper())
        neg = lo.union(hi.min(arb(0))) if lo <= 0 else None
        pos = lo.max(arb(0)).union(hi) if hi >= 0 else None
        return neg, pos

    def _line(self, th):
        u = to_arb(self.uC) - th
        return (self.E[0] + u * self.w[0], self.E[1] + u * self.w[1]), u

    def _foot(self, th):
        phi = Jet(self.psi + self.dir * th, arb(self.dir), arb(0))
        C = Jet(phi.v.cos(), -phi.v.sin() * self.dir, -phi.v.cos())
        S = Jet(phi.v.sin(), phi.v.cos() * self.dir, -phi.v.sin())
        ex = C * self.M[0] + S * self.N[0] + self.c[0]
        ey = C * self.M[1] + S * self.N[1] + self.c[1]
        tx = C * self.N[0] - S * self.M[0]
        ty = C * self.N[1] - S * self.M[1]
        sp = (tx * tx + ty * ty).sqrt()
        k = speed2_mid(self.P, self.cs, C, S) / to_arb(self.det)          # t_E/|e'(φ)|
        gx, gy = ex - k * ty, ey + k * tx                                 # e − t_E ν
        return gx, gy, end_foot_t(self.P, self.cs, C, S, sp)

    def _parts(self, J, what):
        out = None
        for part, foot in zip(self._split(J), (False, True)):
            if part is None:
                continue
            v = what(part, foot)
            out = v if out is None else tuple(a.union(b) for a, b in zip(out, v))
        return out

    def _value(self, part, foot):
        if foot:
            gx, gy, t = self._foot(part)
            return gx.v, gy.v, t.v, gx.d, gy.d, t.d
        (x, y), u = self._line(part)
        rho = (abs(u) * self.wn).nonnegative_part()
        if u > 0:
            dr = -self.wn
        elif u < 0:
            dr = self.wn
        else:
            dr = self.wn.union(-self.wn)
        return x, y, rho, -self.w[0], -self.w[1], dr

    def _all(self, J):
        return self._parts(J, lambda part, foot: self._value(part, foot))

    def xy(self, J):
        v = self._all(J)
        return v[0], v[1]

    def dxy(self, J):
        v = self._all(J)
        return v[3], v[4]

    def rho(self, J, X=None, Y=None):
        return self._all(J)[2]

    def drho(self, J, X=None, Y=None):
        return self._all(J)[5]

    # ------------------------------------------------------------------ polylines
    def _foot_sag(self, J):
        return sag_bound(lambda th: self._foot(th), J)

    def chord_bound(self, t0, t1, target: float = 0.0):
        J = t0.union(t1)
        if J.upper() <= 0:
            return arb(0)
        if J.lower() >= 0:
            return self._foot_sag(J)
        lo, hi = arb(J.lower()), arb(J.upper())
        A, B = self.xy(lo), self.xy(hi)
        Cp = self.xy(arb(0))
        return self._foot_sag(arb(0).union(hi)) + _seg_dist(Cp, A, B)

    def param(self, X, Y):
        x, y = float(X.mid()), float(Y.mid())
        Ex, Ey = (float(v) for v in self.Eq)
        wx, wy = (float(v) for v in self.wq)
        u = ((x - Ex) * wx + (y - Ey) * wy) / float(self.w2q)
        cands = []
        th = float(self.uC) - u
        if th <= 0:
            cands.append((math.hypot(x - Ex - u * wx, y - Ey - u * wy), th))
        phi = interior_foot(self.P, x, y)
        phis = [phi] if phi is not None else [float(piece_feet(self.P, [[x, y]])[1][0]),
                                              # the foot may have reached the other end (a vertex
                                              # equidistant from both ends: the closed piece's
                                              # nearest point may then be either end)
                                              self.P.phi1 if self.which == 0 else self.P.phi0]
        for phi in phis:
            thf = self.dir * (phi - float(self.psi.mid()))
            if thf >= 0:
                gx, gy, _ = self._foot(arb(thf))
                cands.append((math.hypot(float(gx.v.mid()) - x, float(gy.v.mid()) - y), thf))
        if not cands:
            return arb(0)
        return arb(min(cands)[1])

    def vertex_param(self, vp):
        return self.at[id(vp)]

    def line_param(self, vp):
        """θ of a vertex on the normal line (the projection), a ball."""
        u = ((vp.x - self.E[0]) * self.w[0] + (vp.y - self.E[1]) * self.w[1]) / to_arb(self.w2q)
        return to_arb(self.uC) - u

    def foot_param(self, Phi):
        return self.dir * (Phi - self.psi)

    # ------------------------------------------------------------------ the proof's tests
    def secant_view(self, J, R):
        neg, pos = self._split(J)
        out = []
        if neg is not None:
            u = to_arb(self.uC) - neg
            out.append((self.P, self.psi, (abs(u) * self.wn).nonnegative_part(), 1 if u > 0 else -1))
        if pos is not None:
            _gx, _gy, t = self._foot(pos)
            out.append((self.P, self.psi + self.dir * pos, t.v, -1))
        return out

    def contacts_ok(self, J, X, Y, R):
        """(C1): E's distance is ρ by construction on both halves; the piece's nearest-point test
        by :func:`runtime.segments.certificate_ellipse_curves.secant_nearest` with L ≥ 0 at E from
        the parameter's domain (u ≥ u_C on the line, L(ψ) = 0 on γ_E)."""
        for P, Phi, Rb, sg in self.secant_view(J, R):
            if sg > 0:
                continue
            ok = secant_nearest(self.T, self.s, Phi, Rb, at_end=self.which, end_known=True)
            if ok is not True:
                return ok
        return True
