"""Bisector curves of an arc and another site, by the contact angle (for
:mod:`runtime.segments.certificate_edges`).

Our formulation: a point v at distance t from the arc s (centre c, radius ρ) with its contact
c + ρ u(φ) in the arc's interior lies on the ray v = c + (ρ + σ t) u(φ) (σ = +1 outside the circle,
−1 inside); v is at the same distance t from the other site k when

* k a point p (D = c − p):          |D + (ρ + σt) u|² = t²,
* k a segment on the line n̂·x + c₀ = 0 (n̂ its unit left normal), touched on the side τ:
                                     n̂·v + c₀ = τ t,
* k an arc (c₂, ρ₂) touched from the side σ₂ (D = c − c₂):  |D + (ρ + σt) u|² = (ρ₂ + σ₂ t)²,

each linear in t once σ² = 1 is used: t(φ) = N(φ)/Δ(φ) with N = n₀ + n₁·u and Δ = d₀ + d₁·u
(n₀ = −(|D|² + ρ²), n₁ = −2ρD, d₀ = 2σρ, d₁ = 2σD for a point; n₀ = n̂·c + c₀, n₁ = ρn̂, d₀ = τ,
d₁ = −σn̂ for a segment; n₀ = ρ₂² − ρ² − |D|², n₁ = −2ρD, d₀ = 2(σρ − σ₂ρ₂), d₁ = 2σD for an arc).
The curve is parametrised by the offset θ = φ − α from the arc's start angle α, in [0, β]; its
derivatives are closed forms (u' = u^⊥, u'' = −u): with R = ρ + σt, v' = R'u + R u^⊥ and
v'' = (R'' − R) u + 2R' u^⊥, so a chord of a piece of parameter length Δθ stays within
Δθ²/8 · max(|R'' − R| + 2|R'|) of the curve.  σ, τ and σ₂ are read at a proved end vertex (an
edge never crosses a circle or a line it is equidistant from: t > 0 on it); an edge with no
finite end is a whole branch outside both circles (σ = σ₂ = +1, k a point or an arc).  Two arcs
of equal radii seen from the same side have the perpendicular bisector of their centres as
bisector (d₀ = 0): ``straight``, its chords are the curve.

Where Δ vanishes the curve goes to infinity (the pole, a hyperbola-like branch of a point or an
arc outside the circle): Δ(φ) = d₁·(u(φ) − u(φ∞)) = 2 sin(δ/2) E(φ) with δ = φ − φ∞,
E = d₁·u^⊥((φ + φ∞)/2), so t = N/(2 sin(δ/2) E) and 1/t are smooth up to the pole
(:mod:`runtime.segments.certificate_tails`).

Public API: :class:`ArcCurve`, :func:`normalise`, :func:`side_of`.
"""
from __future__ import annotations

from flint import arb

from ..certify.foot import to_arb
from .certificate_sites import ARC, POINT, SEGMENT, SiteTable, hypot, sq

__all__ = ["ArcCurve", "normalise", "side_of"]


def normalise(ph: arb, beta: arb) -> arb:
    """The representative of the angle offset ``ph`` in [(β − 2π)/2, (β + 2π)/2): the arc's
    range [0, β] is inside, the cut is in the middle of its gap."""
    tp = 2 * arb.pi()
    lo = (beta - tp) / 2
    for _ in range(8):
        if ph < lo:
            ph += tp
        elif ph >= lo + tp:
            ph -= tp
        else:
            break
    return ph


class ArcCurve:
    """The bisector of arc s and site k with sides σ (of s's circle), τ (of k's line) or σ₂ (of
    k's circle); parameter θ ∈ [0, β] (module docstring)."""

    kind = "arc"

    def __init__(self, T: SiteTable, s: int, k: int, sigma: int, tau: int = 1):
        self.T, self.s, self.k, self.sigma, self.tau = T, s, k, sigma, tau
        #: two arcs seen from the same side with equal radii: the bisector of their centres
        self.straight = T.kind[k] == ARC and sigma * T.rad[s] == tau * T.rad[k]
        cx, cy, rho = T.arb_arc(s)
        self.c, self.r = (cx, cy), rho
        (qcx, qcy) = T.cen[s]
        self.alpha = arb.atan2(to_arb(T.a[s][1] - qcy), to_arb(T.a[s][0] - qcx))
        beta = arb.atan2(to_arb(T.b[s][1] - qcy), to_arb(T.b[s][0] - qcx)) - self.alpha
        tp = 2 * arb.pi()
        while beta <= 0:
            beta += tp
        self.beta = beta
        sg = sigma
        if T.kind[k] == POINT:
            px, py = T.arb_ends(k)[:2]
            Dx, Dy = cx - px, cy - py
            self.n0 = -(sq(Dx) + sq(Dy) + rho * rho)
            self.n1 = (-2 * rho * Dx, -2 * rho * Dy)
            self.d0 = 2 * sg * rho
            self.d1 = (2 * sg * Dx, 2 * sg * Dy)
        elif T.kind[k] == SEGMENT:
            ax, ay, bx, by = T.arb_ends(k)
            L = ((bx - ax) * (bx - ax) + (by - ay) * (by - ay)).sqrt()
            nx, ny = -(by - ay) / L, (bx - ax) / L
            c0 = -(nx * ax + ny * ay)
            self.n0 = nx * cx + ny * cy + c0
            self.n1 = (rho * nx, rho * ny)
            self.d0 = arb(tau)
            self.d1 = (-sg * nx, -sg * ny)
        else:
            c2x, c2y, r2 = T.arb_arc(k)
            Dx, Dy = cx - c2x, cy - c2y
            self.n0 = r2 * r2 - rho * rho - sq(Dx) - sq(Dy)
            self.n1 = (-2 * rho * Dx, -2 * rho * Dy)
            self.d0 = 2 * (sg * rho - tau * r2)
            self.d1 = (2 * sg * Dx, 2 * sg * Dy)

    # ------------------------------------------------------------------ evaluation
    def u(self, th):
        ph = self.alpha + th
        return ph.cos(), ph.sin()

    def _nd(self, th):
        ux, uy = self.u(th)
        N = self.n0 + self.n1[0] * ux + self.n1[1] * uy
        Dn = self.d0 + self.d1[0] * ux + self.d1[1] * uy
        N1 = -self.n1[0] * uy + self.n1[1] * ux
        D1 = -self.d1[0] * uy + self.d1[1] * ux
        return ux, uy, N, Dn, N1, D1

    def t(self, th):
        _, _, N, Dn, _, _ = self._nd(th)
        return N / Dn

    def xy(self, th):
        ux, uy, N, Dn, _, _ = self._nd(th)
        R = self.r + self.sigma * (N / Dn)
        return self.c[0] + R * ux, self.c[1] + R * uy

    def rho(self, th, X=None, Y=None):
        return self.t(th)

    def _t1(self, th):
        ux, uy, N, Dn, N1, D1 = self._nd(th)
        t = N / Dn
        return ux, uy, t, (N1 - t * D1) / Dn, N, Dn, N1, D1

    def drho(self, th, X=None, Y=None):
        return self._t1(th)[3]

    def dxy(self, th):
        ux, uy, t, t1, *_ = self._t1(th)
        R, R1 = self.r + self.sigma * t, self.sigma * t1
        return R1 * ux - R * uy, R1 * uy + R * ux

    def _derivs(self, th):
        """(v', v'') on the parameter ball θ."""
        ux, uy, t, t1, N, Dn, N1, D1 = self._t1(th)
        N2, D2 = self.n0 - N, self.d0 - Dn          # N'' = −n₁·u = n₀ − N
        t2 = (N2 - t * D2 - 2 * t1 * D1) / Dn
        R, R1, R2 = self.r + self.sigma * t, self.sigma * t1, self.sigma * t2
        v1 = (R1 * ux - R * uy, R1 * uy + R * ux)
        v2 = ((R2 - R) * ux - 2 * R1 * uy, (R2 - R) * uy + 2 * R1 * ux)
        return v1, v2

    def chord_bound(self, t0: arb, t1: arb, target: float = 0.0) -> arb:
        """:meth:`chord_bound_parts` with 8, 32, 128, 512 sub-pieces until below ``target``."""
        parts = 8
        while True:
            b = self.chord_bound_parts(t0, t1, parts)
            if b.upper() <= target or parts >= 512:
                return b
            parts *= 4

    def chord_bound_parts(self, t0: arb, t1: arb, parts: int = 8) -> arb:
        """Chord-to-curve deviation bound of the piece between the parameters t0 and t1: the
        smaller of Δθ²/8 · max|v''| and ℓ² κ/8 (ℓ ≤ Σ δθ max|v'| its length over ``parts``
        sub-pieces, κ its largest curvature |v' × v''|/|v'|³; a curve of curvature ≤ κ
        parametrised by length s stays within s(ℓ − s) κ/2 of its chord)."""
        lo_t, hi_t = t0.union(t1).lower(), t0.union(t1).upper()
        dt = arb(hi_t) - arb(lo_t)
        step = dt / parts
        b1 = arb(0)
        length = arb(0)
        kappa = arb(0)
        curved = True
        for m in range(parts):
            K = (arb(lo_t) + m * step).union(arb(lo_t) + (m + 1) * step)
            (ax, ay), (bx, by) = self._derivs(K)
            b1 = b1.max(arb(hypot(bx, by).upper()))
            sp = hypot(ax, ay)
            length += step * arb(sp.upper())
            lo = sp.lower()
            if lo > 0:
                kappa = kappa.max(arb((abs(ax * by - ay * bx) / (arb(lo) ** 3)).upper()))
            else:
                curved = False
        b1 = dt * dt * b1 / 8
        if curved:
            b2 = length * length * kappa / 8
            if b2.upper() < b1.upper():
                return b2
        return b1

    def param(self, X, Y):
        """θ of the direction of (X, Y) from the centre, measured from the arc's middle direction m
        (atan2 of (m × w, m·w): its cut, the gap's middle, is far from the range) plus β/2."""
        mx, my = (to_arb(v) for v in self.T.arc_mid(self.s))
        wx, wy = X - self.c[0], Y - self.c[1]
        return arb.atan2(mx * wy - my * wx, mx * wx + my * wy) + self.beta / 2

    def vertex_param(self, vp):
        """θ of a proved end vertex: exactly 0 (β) when it lists the site at the arc's start (end)
        and is there, or is the corner at that end; else from its box."""
        T, s = self.T, self.s
        raw = self.param(vp.x, vp.y)
        for which, code in enumerate(T.ends[s]):
            site = code if code >= 0 else next((o for o in T.joint_curves(code) if o != s), None)
            exact = arb(0) if which == 0 else self.beta
            # listed with the site at that end, and there (a closed pair of arcs has both)
            if site in vp.listed and s in vp.listed and abs(float((raw - exact).mid())) < 1e-6:
                return exact
            if vp.corner is not None and vp.corner == code:         # the corner at that end
                return exact
        return raw

    # ------------------------------------------------------------------ the pole
    def poles(self):
        """The offsets θ (balls, normalised) where Δ vanishes, or [] if it does not."""
        d1x, d1y = self.d1
        nd = (d1x * d1x + d1y * d1y).sqrt()
        ratio = -self.d0 / nd
        if not (ratio > -1 and ratio < 1):
            return []
        kappa = arb.atan2(d1y, d1x)
        w = ratio.acos()
        return [normalise(kappa + w - self.alpha, self.beta), normalise(kappa - w - self.alpha, self.beta)]


def side_of(T: SiteTable, s: int, k: int, vps, P):
    """(σ, τ): read at the proved end vertices of positive radius, else at the middle point of the
    polyline P (sound either way: the curve of these sides is then proved to be the edge); None
    when the vertices disagree or nothing decides."""
    found = None
    pts = [(vp.x, vp.y) for vp in vps if vp.r is not None and vp.r > 0]
    if not pts:
        m = P[len(P) // 2] if len(P) > 2 else (P[0] + P[-1]) / 2
        pts = [(arb(float(m[0])), arb(float(m[1])))]
    for x, y in pts:
        cx, cy, rho = T.arb_arc(s)
        d = ((x - cx) * (x - cx) + (y - cy) * (y - cy)) - rho * rho
        sg = 1 if d > 0 else (-1 if d < 0 else None)
        if T.kind[k] == SEGMENT:
            ax, ay, bx, by = T.arb_ends(k)
            v = -(by - ay) * (x - ax) + (bx - ax) * (y - ay)
            tau = 1 if v > 0 else (-1 if v < 0 else None)
        elif T.kind[k] == ARC:
            c2x, c2y, r2 = T.arb_arc(k)
            d2 = ((x - c2x) * (x - c2x) + (y - c2y) * (y - c2y)) - r2 * r2
            tau = 1 if d2 > 0 else (-1 if d2 < 0 else None)
        else:
            tau = 1
        if sg is None or tau is None or (found is not None and found != (sg, tau)):
            return None
        found = (sg, tau)
    return found
