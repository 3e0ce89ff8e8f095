"""Curves for the edges next to elliptic pieces (:mod:`runtime.segments.certificate_ellipse_edges`
states what is proved with them; thesis ch. 4 foot points): the foot curve of a piece and a point,
a segment's line or an arc's circle, parametrised by the foot parameter φ with second-order jets
(γ, γ', γ'' and ρ, ρ'); the normal line at a piece's end or joint; two points' bisector; the
contacts' nearest-point tests on pieces of them, and the distance gradients of the sites on boxes.

Gradients (Clarke, for Lebourg's mean value theorem): points, segments and arcs by
:func:`runtime.segments.certificate_pieces.distance_gradient`; an elliptic piece by
(x − e(Φ))/|x − e(Φ)| where its nearest point is proved unique in Φ — the interior minimum (the
only one: outside by convexity, inside by the secant factor at the piece's ends), or a
stretch next to an end with f'' > 0 on it and f above the distance beyond —, else an end's (the
hull of both ends' when both are nearest).

Public API: :class:`Jet`, :class:`FootCurve`, :class:`StraightLine`, :class:`NormalLine`, :class:`PointsLine`,
:func:`sag_bound`, :func:`secant_nearest`, :func:`widened_nearest`, :func:`partner_ok`,
:func:`other_ends`, :func:`piece_gradient`, :func:`gradient`.

Length: the curve classes share the jets, the nearest-point tests and the chord bound; the
secant identity itself is :mod:`runtime.segments.certificate_ellipse_secant`.
"""
from __future__ import annotations

from flint import arb

from ..certify.foot import to_arb
from .certificate_pieces import distance_gradient
from .certificate_ellipse_secant import end_foot_t, monotone_piece, on_ellipse, secant_factor
from .certificate_sites import ARC, ELLIPSE, POINT, SEGMENT, SiteTable, hypot, sq
from .ellipse_pieces import (closest_at_an_end, interior_foot, interior_minimum, nearest_verdict,
                             piece_distance_ball, piece_feet, piece_point_ball)

__all__ = ["Jet", "FootCurve", "StraightLine", "NormalLine", "PointsLine", "sag_bound", "secant_nearest", "widened_nearest",
           "partner_ok", "other_ends", "piece_gradient", "gradient"]


# ====================================================================== second-order jets
class Jet:
    """(value, first, second derivative) in one parameter, arb balls."""

    __slots__ = ("v", "d", "dd")

    def __init__(self, v, d=0, dd=0):
        self.v, self.d, self.dd = v, d, dd

    @staticmethod
    def of(x):
        return x if isinstance(x, Jet) else Jet(x, 0, 0)

    def __add__(self, o):
        o = Jet.of(o)
        return Jet(self.v + o.v, self.d + o.d, self.dd + o.dd)

    __radd__ = __add__

    def __neg__(self):
        return Jet(-self.v, -self.d, -self.dd)

    def __sub__(self, o):
        return self + (-Jet.of(o))

    def __rsub__(self, o):
        return Jet.of(o) + (-self)

    def __mul__(self, o):
        o = Jet.of(o)
        return Jet(self.v * o.v, self.d * o.v + self.v * o.d, self.dd * o.v + 2 * self.d * o.d + self.v * o.dd)

    __rmul__ = __mul__

    def recip(self):
        r = 1 / self.v
        return Jet(r, -self.d * r * r, (2 * self.d * self.d * r - self.dd) * r * r)

    def __truediv__(self, o):
        return self * Jet.of(o).recip()

    def __rtruediv__(self, o):
        return Jet.of(o) * self.recip()

    def sqrt(self):
        s = self.v.sqrt()
        d = self.d / (2 * s)
        return Jet(s, d, (self.dd - 2 * d * d) / (2 * s))


def _param(phi):
    return Jet(phi, arb(1), arb(0))


def _cos_sin(p: Jet):
    c, s = p.v.cos(), p.v.sin()
    return Jet(c, -s, -c), Jet(s, c, -s)


# ====================================================================== curves
class FootCurve:
    """γ(φ) = e(φ) + σ t(φ) ν(φ) for elliptic piece ``s`` and partner ``k`` (module docstring)."""

    kind = "ellipse-foot"
    straight = False

    def __init__(self, T: SiteTable, s: int, k: int, sigma: int, side2: int):
        self.T, self.s, self.k, self.sigma, self.side2 = T, s, k, sigma, side2
        P = self.P = T.piece[s]
        self.c = tuple(to_arb(v) for v in P.c)
        self.M = tuple(to_arb(v) for v in P.M)
        self.N = tuple(to_arb(v) for v in P.N)
        self.p0, self.p1 = P.arb_params()
        self._memo: dict = {}
        # a point partner on the piece's own ellipse: the closed form t_E without the 0/0 at its
        # parameter (:func:`runtime.segments.certificate_ellipse_secant.end_foot_t`; inside only)
        self.cs = on_ellipse(P, T.a[k]) if T.kind[k] == POINT else None
        self.mono = monotone_piece(P)

    def jets(self, phi):
        key = (phi.mid(), phi.rad())
        hit = self._memo.get(key)
        if hit is not None and hit[0] is phi:
            return hit[1]
        T, k, sg = self.T, self.k, self.sigma
        C, S = _cos_sin(_param(phi))
        ex = C * self.M[0] + S * self.N[0] + self.c[0]
        ey = C * self.M[1] + S * self.N[1] + self.c[1]
        tx = C * self.N[0] - S * self.M[0]           # e'(φ)
        ty = C * self.N[1] - S * self.M[1]
        ln = (tx * tx + ty * ty).sqrt()
        nx, ny = ty / ln, -tx / ln                   # unit outward normal (the frame is counter-clockwise)
        if T.kind[k] == POINT and self.cs is not None:
            t = end_foot_t(self.P, self.cs, C, S, ln) if sg < 0 else Jet(arb("nan"), arb("nan"), arb("nan"))
        elif T.kind[k] == POINT:
            px, py = T.arb_ends(k)[:2]
            Dx, Dy = ex - px, ey - py
            t = -(Dx * Dx + Dy * Dy) / (2 * sg * (nx * Dx + ny * Dy))
        elif T.kind[k] == SEGMENT:
            ax, ay, bx, by = T.arb_ends(k)
            L = (sq(bx - ax) + sq(by - ay)).sqrt()
            hx, hy = -(by - ay) / L, (bx - ax) / L
            c0 = -(hx * ax + hy * ay)
            t = (ex * hx + ey * hy + c0) / (self.side2 - sg * (nx * hx + ny * hy))
        else:
            cx, cy, r2 = T.arb_arc(k)
            Dx, Dy = ex - cx, ey - cy
            t = (r2 * r2 - (Dx * Dx + Dy * Dy)) / (2 * (sg * (nx * Dx + ny * Dy) - self.side2 * r2))
        gx, gy = ex + sg * t * nx, ey + sg * t * ny
        out = (gx, gy, t)
        self._memo = {key: (phi, out)}
        return out

    def xy(self, phi):
        gx, gy, _ = self.jets(phi)
        return gx.v, gy.v

    def dxy(self, phi):
        gx, gy, _ = self.jets(phi)
        return gx.d, gy.d

    def rho(self, phi, X=None, Y=None):
        return self.jets(phi)[2].v

    def drho(self, phi, X=None, Y=None):
        return self.jets(phi)[2].d

    def chord_bound(self, t0, t1, target: float = 0.0):
        """The distance from γ over [t0, t1] to its chord: the smaller of Δφ²/8 · max|γ''| (the
        linear interpolation error) and ℓ²κ/8 (ℓ ≤ Δφ max|γ'| the arc length, κ ≤ max|γ' × γ''| /
        min|γ'|³ the curvature: the distance h(s) from the chord's line in arc length has h = 0
        at both ends and |h''| ≤ κ) when the turning ℓκ is below π/2 (the tangents stay within
        π/2 of the chord's direction, so the nearest point of the line is on the chord)."""
        return sag_bound(self.jets, t0.union(t1))

    def secant_view(self, J, R):
        """[(piece, contact parameters Φ*, distances, side σ)] over J, for the secant tests."""
        return [(self.P, J, R, self.sigma)]

    def param(self, X, Y):
        x, y = float(X.mid()), float(Y.mid())
        phi = interior_foot(self.P, x, y)
        if phi is None:
            phi = float(piece_feet(self.P, [[x, y]])[1][0])
        return arb(phi)

    def vertex_param(self, vp):
        """θ_v of an end vertex, as enclosed by :func:`prove_piece_edge` (``at``, by the proof)."""
        return self.at[id(vp)]

    def contacts_ok(self, J, X, Y, R):
        """(C1) on the piece J (module docstring): True, or a message.  Outside the ellipse
        (σ = +1, t > 0) x − e(φ) lies in the normal cone of the filled ellipse K at e(φ), so e(φ) is
        the projection of x on the convex K, strictly nearer than every other point of K.  Inside
        (σ = −1) on a monotone piece, the secant rule (:func:`secant_nearest`)."""
        if self.sigma < 0 and self.mono:
            ok = secant_nearest(self.T, self.s, J, R)
            if ok is not True:
                return ok
        elif self.sigma < 0 and not widened_nearest(self.P, X, Y, R, J, None, other_ends(self.T, self.s, self.k)):
            return f"the contact with elliptic piece {self.s} is not proved its nearest point"
        return partner_ok(self.T, self.k, self.side2, X, Y, R)


def sag_bound(jets, J, parts: int = 8):
    """:meth:`FootCurve.chord_bound` for a curve given by ``jets`` (θ ↦ (γ_x, γ_y, ρ) jets) on J."""
    a, w = float(J.lower()), float(J.rad()) * 2
    top, speed, low, cross = arb(0), arb(0), None, arb(0)
    for m in range(parts):
        gx, gy, _ = jets(arb(a + m * w / parts).union(arb(a + (m + 1) * w / parts)))
        top = top.max(arb(hypot(gx.dd, gy.dd).upper()))
        sp = hypot(gx.d, gy.d)
        speed = speed.max(arb(sp.upper()))
        lo = arb(sp.lower())
        low = lo if low is None or lo < low else low
        cross = cross.max(arb(abs(gx.d * gy.dd - gy.d * gx.dd).upper()))
    out = arb(w) * arb(w) * top / 8
    if low is not None and low > 0:
        ell = arb(w) * speed
        kappa = cross / (low * low * low)
        if ell * kappa < arb.pi() / 2:
            alt = ell * ell * kappa / 8
            if alt.upper() < out.upper():
                out = alt
    return out


def secant_nearest(T: SiteTable, s: int, Phi, R, at_end=None, end_known: bool = False):
    """(C1) inside (σ = −1) on a monotone piece s by the secant identity
    (:mod:`runtime.segments.certificate_ellipse_secant`): the contact e(φ*), φ* ∈ ``Phi``, at
    distance ρ ∈ ``R`` is a nearest point of the closed piece when L ≥ 0 at both of its ends (L is
    strictly monotone on the piece, so it is then > 0 between them but at an end with L = 0).
    Per end w that is a point site: either the edge's partner, at distance exactly ρ (L = 0, a tie
    that is the partner's), or a third site of the edge, whose proof d > ρ on the open edge is
    L > 0 there (so those are left to the edge's third-site test).  ``at_end`` is the end that is
    the contact itself (a normal line at that end: L = det/|e'|·(R − ρ), R the radius of
    curvature, taken ≥ 0 from the parameter's domain when ``end_known``, else proved > 0); any
    other end (a joint) is proved L > 0 on the balls.  True or a message."""
    P = T.piece[s]
    for w, code in enumerate(T.ends[s]):
        if code >= 0 and w != at_end:
            continue
        if w == at_end and end_known:
            continue
        cs = P.ua if w == 0 else P.ub
        if not secant_factor(P, cs, Phi, R, -1) > 0:
            return f"the contact with elliptic piece {s} is not proved its nearest point (end {w})"
    return True


def widened_nearest(P, X, Y, R, J, end, tied=()) -> bool:
    """For every point q of the box whose f_q has a critical point in J (``end`` None), or is
    increasing away from the piece's end ``end`` (0, 1) with J that end's parameter: nothing of the
    piece is nearer than R.  :func:`runtime.segments.ellipse_pieces.nearest_verdict` with Φ = J
    widened by δ (f'' > 0 around Φ, f > R² beyond; the critical point in J is then the minimum on
    Φ): δ = 4|J|, 2 %, 10 % of the piece's span, the first that decides (a box of width w blurs f
    by O(w), so the margin f − R² ≈ f''δ²/2 beyond Φ needs δ well above w).  ``tied``: ends that
    are point sites other than the edge's, left out next to them where f increases away from them
    (they are third sites, proved farther than ρ on their own)."""
    span = P.phi1 - P.phi0
    p0, p1 = P.arb_params()
    for d in (4 * float(J.rad()) + 1e-12 * span, 0.02 * span, 0.1 * span):
        w = arb(d)
        if end is None:
            Phi = (J - w).union(J + w)
        elif end == 0:
            Phi = p0.union(p0 + w)
        else:
            Phi = (p1 - w).union(p1)
        if nearest_verdict(P, X, Y, R, Phi, tied_ends=tuple(tied)) is True:
            return True
    return False


def partner_ok(T, k, side2, X, Y, R):
    if T.kind[k] == SEGMENT:
        u = T.foot(k, X, Y)
        if not (u >= 0 and u <= 1):
            return f"the foot on segment {k} is not proved inside it"
    elif T.kind[k] == ARC:
        cx, cy, r2 = T.arb_arc(k)
        if T.in_range(k, X - cx, Y - cy, closed=True) is not True or not (r2 + side2 * R >= 0):
            return f"the contact with arc {k} is not proved in its range"
    return True


def other_ends(T: SiteTable, s: int, *pair) -> tuple:
    """The ends (0, 1) of piece s that are point sites not in ``pair``."""
    return tuple(w for w, code in enumerate(T.ends[s]) if code >= 0 and code not in pair)


class StraightLine:
    """γ(t) = o + t w, a straight line through the ball point o = ``origin`` with the direction
    w (balls): what the normal line and two points' bisector share.  γ' = w; a chord of a line is
    the line, so the sag bound is 0; the parameter of a point (X, Y) is its projection
    (X − o)·w / |w|², exact at a point of the line (a vertex on the edge)."""

    straight = True

    def __init__(self, origin, w):
        self.origin, self.w = origin, w
        self.w2 = sq(self.w[0]) + sq(self.w[1])

    def xy(self, t):
        return self.origin[0] + t * self.w[0], self.origin[1] + t * self.w[1]

    def dxy(self, t):
        return self.w

    def chord_bound(self, t0, t1, target: float = 0.0):
        return arb(0)

    def param(self, X, Y):
        return ((X - self.origin[0]) * self.w[0] + (Y - self.origin[1]) * self.w[1]) / self.w2

    def vertex_param(self, vp):
        return self.param(vp.x, vp.y)


class NormalLine(StraightLine):
    """γ(t) = e + t w (t > 0), ρ = t|w|: the normal line at a piece's end or joint ``code``; the
    pieces touched at e are ``pieces`` = [(site, which end)]."""

    kind = "ellipse-normal"

    def __init__(self, T: SiteTable, code: int, w, pieces):
        self.T, self.code, self.pieces = T, code, pieces
        self.e = T.pt_arb(code)
        self.eq = T.pt(code)
        self.wq = w
        super().__init__(self.e, (to_arb(w[0]), to_arb(w[1])))
        self.wn = self.w2.sqrt()

    def rho(self, t, X=None, Y=None):
        return (abs(t) * self.wn).nonnegative_part()

    def drho(self, t, X=None, Y=None):
        if t > 0:
            return self.wn
        if t < 0:
            return -self.wn
        return self.wn.union(-self.wn)

    def outside(self, J, s, which) -> bool:
        """The box over J lies on the outer side of piece s at its end ``which``: t (w·ν_s) > 0,
        ν_s ∝ ±(ℓ_y, −ℓ_x) the outward normal there (ℓ the exact direction leaving the end into
        the piece: + at a start, − at an end), the sign decided in rationals."""
        lx, ly = self.T.leaving(s, self.code)
        dot = self.wq[0] * ly - self.wq[1] * lx
        way = (1 if dot > 0 else -1 if dot < 0 else 0) * (1 if which == 0 else -1)
        return way != 0 and bool(J * way > 0)

    def secant_view(self, J, R):
        out = []
        for s, which in self.pieces:
            P = self.T.piece[s]
            p = P.arb_params()[which]
            out.append((P, p, R, 1 if self.outside(J, s, which) else -1))
        return out

    def contacts_ok(self, J, X, Y, R):
        for s, which in self.pieces:
            P = self.T.piece[s]
            p0, p1 = P.arb_params()
            if monotone_piece(P):
                # outside: the projection on the filled ellipse; inside (or not decided: L only
                # grows with σ) the secant rule with the contact at the end itself
                if self.outside(J, s, which):
                    continue
                ok = secant_nearest(self.T, s, p0 if which == 0 else p1, R, at_end=which)
                if ok is not True:
                    return ok
                continue
            if not widened_nearest(P, X, Y, R, p0 if which == 0 else p1, which,
                                   other_ends(self.T, s, self.code)):
                return f"the end of elliptic piece {s} is not proved its nearest point along the normal line"
        return True


class PointsLine(StraightLine):
    """The perpendicular bisector O + t w of points i and j, ρ = |γ − p_i|."""

    kind = "ellipse-points"

    def __init__(self, T: SiteTable, i: int, j: int):
        (xi, yi), (xj, yj) = T.a[i], T.a[j]
        self.O = (to_arb((xi + xj) / 2), to_arb((yi + yj) / 2))
        super().__init__(self.O, (to_arb(-(yj - yi)), to_arb(xj - xi)))
        self.p = T.arb_ends(i)[:2]

    def rho(self, t, X=None, Y=None):
        x, y = self.xy(t)
        return hypot(x - self.p[0], y - self.p[1])

    def drho(self, t, X=None, Y=None):
        x, y = self.xy(t)
        dx, dy = x - self.p[0], y - self.p[1]
        return (dx * self.w[0] + dy * self.w[1]) / hypot(dx, dy)

    def contacts_ok(self, J, X, Y, R):
        return True


# ====================================================================== gradients
def _secant_unique(T: SiteTable, k: int, X, Y, Phi, R) -> bool:
    """The critical point e(φ*(x)), φ* ∈ Φ, is the unique nearest point of piece k for every x of
    the box at distance in R: x − e(φ*) along the outward normal (σ = +1, the projection on the
    filled ellipse), or inward on a monotone piece with the secant factor L > 0 at both ends
    (:mod:`runtime.segments.certificate_ellipse_secant`)."""
    P = T.piece[k]
    ex, ey = piece_point_ball(P, Phi)
    Mx, My, Nx, Ny = (to_arb(q) for q in (*P.M, *P.N))
    tx, ty = -Phi.sin() * Mx + Phi.cos() * Nx, -Phi.sin() * My + Phi.cos() * Ny
    side = (X - ex) * ty - (Y - ey) * tx
    if not monotone_piece(P):                   # det(M, N) > 0 there: rot(e') is outward
        return False
    if side > 0:
        return True
    if not side < 0:
        return False
    return all(secant_factor(P, cs, Phi, R, -1) > 0 for cs in (P.ua, P.ub))


def piece_gradient(T: SiteTable, k: int, X, Y):
    """An enclosure of the (Clarke) gradient of the distance to elliptic piece k on the box, or
    None (module docstring)."""
    P = T.piece[k]
    x, y = float(X.mid()), float(Y.mid())
    phi = interior_foot(P, x, y)
    if phi is not None:
        Phi = interior_minimum(P, X, Y, phi)
        if Phi is not None:
            ex, ey = piece_point_ball(P, Phi)
            R = hypot(X - ex, Y - ey)
            if R > 0 and (_secant_unique(T, k, X, Y, Phi, R) or nearest_verdict(P, X, Y, R, Phi) is True):
                return (X - ex) / R, (Y - ey) / R
    # the nearest point within a stretch Φ next to an end (f'' > 0 on Φ, f > d² beyond it)
    dist = piece_distance_ball(P, X, Y)
    r = arb(dist.upper())
    span = P.phi1 - P.phi0
    p0, p1 = P.arb_params()
    for frac in (1e-3, 1e-2, 1e-1):
        w = arb(frac * span)
        for Phi in (p0.union(p0 + w), (p1 - w).union(p1)):
            if nearest_verdict(P, X, Y, r, Phi) is True:
                ex, ey = piece_point_ball(P, Phi)
                R = hypot(X - ex, Y - ey)
                if R > 0:
                    return (X - ex) / R, (Y - ey) / R
    which = closest_at_an_end(P, X, Y)
    if which is None:
        return None
    out = None
    for w in which:
        code = T.ends[k][w]
        px, py = T.pt_arb(code)
        dx, dy = X - px, Y - py
        n = hypot(dx, dy)
        if not n > 0:
            return None
        g = (dx / n, dy / n)
        out = g if out is None else (out[0].union(g[0]), out[1].union(g[1]))
    return out


def gradient(T: SiteTable, k: int, X, Y):
    if T.kind[k] == ELLIPSE:
        return piece_gradient(T, k, X, Y)
    gx, gy = distance_gradient(T, k, X, Y)
    if not (gx.is_finite() and gy.is_finite()):
        return None
    return gx, gy
