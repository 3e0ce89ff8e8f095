"""The edge of two elliptic pieces joined at an end J of their ellipse's major axis: the axis itself,
from a vertex on J's normal line, through J's centre of curvature K, to the vertex where the mirror
feet reach the far end of the shorter piece (for :mod:`runtime.segments.certificate_ellipse_edges`;
thesis §2.2 — an elliptic arc split at the vertices of its ellipse into harmless pieces —, ch. 4:
the foot points of the ellipse and its offset).

Frame e(φ) = c + cos φ M + sin φ N with M ⟂ N (exact rationals).  Let U be the semi-axis through J
(J = c + U, U = ±M or ±N), V the other one, a² = |U|² > b² = |V|² (J ends the major axis).  On the
axis x(μ) = c + μU (J at μ = 1, the centre at μ = 0), a point e of the ellipse with
C = U·(e − c)/a² (the cosine of its parameter measured from J) has

    |x(μ) − e|² = g_μ(C) = (a² − b²) C² − 2a²μ C + a²μ² + b²,

a convex quadratic in C.  A piece ending at J lies in one quadrant of the frame, so C runs once
over [C_far, 1] along it (C_far the far end's exact cosine, in [0, 1)): the piece's squared
distance is the minimum of g_μ over [C_far, 1], attained at the clamp of C*(μ) = a²μ/(a² − b²).
For μ ≥ μ_min = (a² − b²) max(C_i, C_j)/a² the clamp is the same for both pieces i, j, so on that
part of the axis d_i = d_j = ρ(μ) exactly, with

    ρ² = a²(μ − 1)²                    for μ ≥ μ_K = (a² − b²)/a²  (the contact is J; K = x(μ_K)),
    ρ² = b²(1 − a²μ²/(a² − b²))        for μ_min ≤ μ ≤ μ_K  (two mirror feet, C = C*(μ)),

ρ C¹ at μ_K (ρ = b²/a, (ρ²)' = −2b² from both sides).  So (C1) of the edge proof needs no
nearest-point test on the pieces: it is this identity, given that the edge's lower end vertex lies
at μ ≥ μ_min.  (The minor axis has a² < b²: g_μ is concave there and the axis is no bisector
beyond the normal line's part: not this rule.)

End vertices (both on the axis, proved):

* a vertex whose equation for both pieces is the normal line at J (the choice of
  :mod:`runtime.segments.certificate_vertices`, both pieces touched at J): on the axis by that
  equation; its μ is the projection of its box, proved > μ_K;
* a vertex listing a point site p that is the far end of one piece s, with C_p > C_other: the axis
  meets the normal line at p at μ_p = (a² − b²) C_p/a² = μ_min (the normal at the point of cosine
  C meets the axis where C*(μ) = C).  x_p = x(μ_p) is equidistant from p, from s (the clamp is C_p:
  p itself) and from the other piece (its mirror foot, at C = C_p inside it: the one interior strict
  local minimum of the distance), so it is a zero of the vertex's system — the normal line at p
  for s, the distance to the interior minimum for the other — and it lies in the vertex's proved
  box (exact rational comparison), which holds one zero: x_p is the vertex, μ_p its exact
  parameter.

Third sites (step (C2)): a point e of a site's closure (a point site, a curve's end) is farther
than ρ on the open edge by an exact rule (:meth:`AxisCurve.farther_rule`): q(μ) = |x(μ) − e|² − ρ²
is a convex quadratic with leading coefficient a⁴/(a² − b²) on [μ_p, μ_K] — decided exactly in
rationals: q(μ_p) ≥ 0, q(μ_K) > 0 and q > 0 at its vertex when that lies in (μ_p, μ_K) (a tie at
μ_p is then left increasing: by strict convexity q > 0 past it) — and affine on
[μ_K, μ_hi], positive at μ_K and ≥ 0 at the upper vertex (its empty circle: d_k(v) ≥ r bounds every
point of site k's closure), so positive between.  Other sites by the distance balls and the
derivative runs of the edge proof.  Through J itself (an end vertex outside the ellipse) ρ = 0 at
J only, where both pieces are at distance 0 and every other site farther, as on the normal line.

Public API: :class:`AxisCurve`, :func:`axis_edge`.
"""
from __future__ import annotations

from fractions import Fraction

from flint import arb

from ..certify.foot import to_arb
from .certificate_ellipse_curves import StraightLine
from .certificate_sites import ELLIPSE, SiteTable

__all__ = ["AxisCurve", "axis_edge"]


def _exact(x: arb) -> Fraction:
    """The exact value of a ball of radius 0 (an end of a ball)."""
    m, e = x.man_exp()
    m, e = int(m), int(e)
    return Fraction(m * 2 ** e) if e >= 0 else Fraction(m, 2 ** -e)


def _holds(X: arb, q: Fraction) -> bool:
    """The rational q lies in the ball X (exact comparison with its ends)."""
    return X.is_finite() and _exact(X.lower()) <= q <= _exact(X.upper())


def _dot(u, v) -> Fraction:
    return Fraction(u[0]) * Fraction(v[0]) + Fraction(u[1]) * Fraction(v[1])


class AxisCurve(StraightLine):
    """x(μ) = c + μU, ρ(μ) of the module docstring, for pieces ``i`` and ``j`` joined at the major
    vertex ``code`` (a smooth joint of two pieces of one ellipse)."""

    kind = "ellipse-axis"

    @staticmethod
    def frame(T: SiteTable, i: int, j: int, code: int):
        """(U, a², b², {piece: C_far}) when pieces i, j of one ellipse with M ⟂ N are joined at
        the end ``code`` of its major axis, else None (exact)."""
        if T.kind[i] != ELLIPSE or T.kind[j] != ELLIPSE or code not in T.ends[i] or code not in T.ends[j]:
            return None
        P, Q = T.piece[i], T.piece[j]
        if not (P.c == Q.c and P.M == Q.M and P.N == Q.N) or _dot(P.M, P.N) != 0:
            return None
        cs = [P.ua, P.ub][T.which_end(i, code)]
        cos, sin = Fraction(cs[0]), Fraction(cs[1])
        if sin == 0 and abs(cos) == 1:
            U = tuple(cos * Fraction(m) for m in P.M)
            V, pick = P.N, 0
        elif cos == 0 and abs(sin) == 1:
            U = tuple(sin * Fraction(n) for n in P.N)
            V, pick = P.M, 1
        else:
            return None
        sign = cos if pick == 0 else sin
        a2, b2 = _dot(U, U), _dot(V, V)
        J = tuple(Fraction(P.c[m]) + U[m] for m in range(2))
        if not a2 > b2 or tuple(Fraction(v) for v in T.pt(code)) != J:
            return None
        far = {}
        for s in (i, j):
            R = T.piece[s]
            w = T.which_end(s, code)
            here = [R.ua, R.ub][w]
            if Fraction(here[pick]) != sign or Fraction(here[1 - pick]) != 0:
                return None
            C = sign * Fraction([R.ua, R.ub][1 - w][pick])
            if not 0 <= C < 1:
                return None
            far[s] = C
        return U, a2, b2, far

    def __init__(self, T: SiteTable, i: int, j: int, code: int):
        got = self.frame(T, i, j, code)
        if got is None:
            raise ValueError("not two pieces joined at an end of their ellipse's major axis")
        self.T, self.i, self.j, self.code = T, i, j, code
        self.Uq, self.a2q, self.b2q, self.far = got
        P = T.piece[i]
        self.cq = tuple(Fraction(v) for v in P.c)
        self.muK = (self.a2q - self.b2q) / self.a2q
        self.mu_min = (self.a2q - self.b2q) * max(self.far.values()) / self.a2q
        self.cuts = (float(self.muK),)
        super().__init__(tuple(to_arb(v) for v in self.cq), tuple(to_arb(v) for v in self.Uq))
        self.a = to_arb(self.a2q).sqrt()
        self.b2 = to_arb(self.b2q)
        self.k2 = to_arb(self.a2q * self.b2q / (self.a2q - self.b2q))    # a²b²/(a² − b²)
        self.muK_arb = to_arb(self.muK)
        self.at: dict = {}

    # ------------------------------------------------------------------ ρ by the two formulas
    def _split(self, J):
        """(part of J at or past μ_K − ε, part at or before μ_K + ε), None where J does not reach
        (ε: the ball of μ_K): each formula on its closed side of K covers ρ there."""
        lo, hi = arb(J.lower()), arb(J.upper())
        kl, kh = arb(self.muK_arb.lower()), arb(self.muK_arb.upper())
        near = lo.max(kl).union(hi) if hi >= kl else None
        far = lo.union(hi.min(kh)) if lo <= kh else None
        return near, far

    def _rho_far(self, m):
        return (self.b2 - self.k2 * m * m).nonnegative_part().sqrt()

    def rho(self, J, X=None, Y=None):
        near, far = self._split(J)
        out = None
        if near is not None:
            out = (abs(near - 1) * self.a).nonnegative_part()
        if far is not None:
            v = self._rho_far(far)
            out = v if out is None else out.union(v)
        return out

    def drho(self, J, X=None, Y=None):
        near, far = self._split(J)
        out = None
        if near is not None:
            if near > 1:
                out = self.a
            elif near < 1:
                out = -self.a
            else:
                out = self.a.union(-self.a)
        if far is not None:
            v = -self.k2 * far / self._rho_far(far)
            out = v if out is None else out.union(v)
        return out

    def contacts_ok(self, J, X, Y, R):
        """(C1): d_i = d_j = ρ on the open edge by the exact identity of the module docstring
        (its end vertices were proved at μ ≥ μ_min by :func:`axis_edge`)."""
        return True

    # ------------------------------------------------------------------ exact third points
    def point_in_box(self, mu: Fraction):
        """x(μ), exact."""
        return tuple(self.cq[m] + mu * self.Uq[m] for m in range(2))

    def far_end_vertex(self, s: int, p: int, vp):
        """μ_p of the module docstring when the vertex proof ``vp`` lists p, the far end of piece
        s with C_p > C_other, and its box holds x(μ_p); else None."""
        other = self.j if s == self.i else self.i
        T = self.T
        if p < 0 or p not in T.ends[s] or p == self.code or p not in vp.listed:
            return None
        Cp = self.far[s]
        if not Cp > self.far[other]:
            return None
        mu = (self.a2q - self.b2q) * Cp / self.a2q
        x = self.point_in_box(mu)
        if not (_holds(vp.x, x[0]) and _holds(vp.y, x[1])):
            return None
        return mu

    def farther_rule(self):
        """A test ``e ↦ bool``: the exact point e is farther than ρ on the open edge (μ_p, μ_hi)
        (module docstring; μ_p = ``mu_lo`` exact < μ_K, set by :func:`axis_edge`, μ_hi > μ_K at
        the proved upper vertex, whose empty circle bounds q there)."""
        a2, b2, muK, mu_lo = self.a2q, self.b2q, self.muK, self.mu_lo
        A = a2 * a2 / (a2 - b2)
        memo: dict = {}

        def farther(e) -> bool:
            e = tuple(Fraction(v) for v in e)
            if e not in memo:
                D = (self.cq[0] - e[0], self.cq[1] - e[1])
                B = 2 * _dot(self.Uq, D)
                C = _dot(D, D) - b2

                def excess(m):
                    return (A * m + B) * m + C
                ok = True
                if excess(mu_lo) < 0:
                    ok = False
                m0 = -B / (2 * A)
                if mu_lo < m0 < muK and not excess(m0) > 0:
                    ok = False
                if not excess(muK) > 0:           # then the affine part past K is > 0 up to μ_hi
                    ok = False
                memo[e] = ok
            return memo[e]
        return farther


def axis_edge(T: SiteTable, i: int, j: int, code: int, vps, contacts):
    """(curve, parameter balls of the end vertices) for the edge of pieces i, j joined at the major
    vertex ``code``, or a message.  ``contacts[n]``: for end vertex n, the pair of contacts of i and
    j as chosen for the vertex's equations — ("end", code, ·) on J's normal line, ("end", p, ·) at
    an end p, ("inside", Φ) — (:func:`runtime.segments.certificate_ellipse_edges` reads them with the
    vertex proof's float choices)."""
    if AxisCurve.frame(T, i, j, code) is None:
        return "a vertex of the edge of two joined elliptic pieces is not on the joint's normal line"
    c = AxisCurve(T, i, j, code)
    thetas, kinds = [], []
    for vp, got in zip(vps, contacts):
        heads = [(g or ("",))[:2] for g in got]
        if all(h == ("end", code) for h in heads):
            mu = c.vertex_param(vp)
            if not mu > c.muK_arb:
                return "an end vertex of the axis edge on the joint's normal line is not proved before the centre of curvature"
            thetas.append(mu)
            kinds.append("joint")
            continue
        mu = None
        for s, h, o in ((i, heads[0], heads[1]), (j, heads[1], heads[0])):
            if h[0] == "end" and isinstance(h[1], int) and h[1] >= 0 and o[0] == "inside":
                mu = c.far_end_vertex(s, h[1], vp)
                if mu is not None:
                    break
        if mu is None:
            return "a vertex of the edge of two joined elliptic pieces is not on the joint's normal line"
        thetas.append(to_arb(mu))
        kinds.append(mu)
    if kinds.count("joint") != 1:
        return "the axis edge does not run from the far end's vertex to a vertex on the joint's normal line"
    c.mu_lo = next(k for k in kinds if k != "joint")
    return c, thetas
