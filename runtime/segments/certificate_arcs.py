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

from flint import arb, ctx

from ..certify.foot import to_arb
from .certificate_sites import ARC, POINT, SEGMENT, SiteTable, hypot, sq

__all__ = ["ArcCurve", "normalise", "side_of"]

#: evaluations kept by :meth:`ArcCurve._nd` (the parameter balls of the pieces in hand)
RECENT = 8
#: most sub-pieces of one chord bound (:meth:`ArcCurve.chord_bound_parts`)
SUB_PIECES = 64


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
        self.n0, self.n1, self.d0, self.d1 = self._coefficients(k, tau)
        self._partners: dict = {}
        self._recent: list = []

    def _coefficients(self, k: int, tau: int):
        """(n₀, n₁, d₀, d₁) of the bisector of s (on the side σ) and site k (side τ of its line or
        circle; module docstring)."""
        T, sg, rho = self.T, self.sigma, self.r
        cx, cy = self.c
        if T.kind[k] == POINT:
            px, py = T.arb_ends(k)[:2]
            Dx, Dy = cx - px, cy - py
            return (-(sq(Dx) + sq(Dy) + rho * rho), (-2 * rho * Dx, -2 * rho * Dy), 2 * sg * rho,
                    (2 * sg * Dx, 2 * sg * Dy))
        if T.kind[k] == SEGMENT:
            ax, ay, bx, by = T.arb_ends(k)
            L = ((bx - ax) * (bx - ax) + (by - ay) * (by - ay)).sqrt()
            nx, ny = -(by - ay) / L, (bx - ax) / L
            c0 = -(nx * ax + ny * ay)
            return nx * cx + ny * cy + c0, (rho * nx, rho * ny), arb(tau), (-sg * nx, -sg * ny)
        c2x, c2y, r2 = T.arb_arc(k)
        Dx, Dy = cx - c2x, cy - c2y
        return (r2 * r2 - rho * rho - sq(Dx) - sq(Dy), (-2 * rho * Dx, -2 * rho * Dy), 2 * (sg * rho - tau * r2),
                (2 * sg * Dx, 2 * sg * Dy))

    # ------------------------------------------------------------------ other sites, algebraically
    def farther(self, k: int, th, tau: int = 1, deriv: bool = False):
        """A ball whose positivity on the parameter ball θ proves d_k > t at the curve's points
        there (t > 0 being a condition of the edge), or with ``deriv`` its θ-derivative.

        Written with the pair's own algebra: for a point k, |x − p|² − t² = tΔ_k − N_k on the
        curve (x = c + (ρ + σt)u; the bisector of s and k is N_k = tΔ_k); for an arc k,
        |x − c_k|² − (t + ρ_k)² = tΔ_k − N_k with its outer side (then d_k ≥ |x − c_k| − ρ_k > t);
        for a segment k, τ(n̂·x + c₀) − t = τ(N_k − tΔ_k) with τ = ±1 (d_k ≥ τ(n̂·x + c₀)).  With
        t = N/Δ these are (NΔ_k − N_kΔ)/Δ, resp. τ(N_kΔ − NΔ_k)/Δ: the numerator, a
        trigonometric polynomial of degree 2 in θ, times the sign of Δ (decided on the ball, else
        the result is not positive).  Smooth up to the pole, unlike d_k − t on boxes of the far
        curve (where the sites look alike and the margins are tiny)."""
        key = (k, tau)
        co = self._partners.get(key)
        if co is None:
            co = self._partners[key] = self._coefficients(k, tau if self.T.kind[k] == SEGMENT else 1)
        n0, n1, d0, d1 = co
        ux, uy, N, Dn, N1, D1 = self._nd(th)
        sgn = 1 if Dn > 0 else (-1 if Dn < 0 else 0)
        if sgn == 0:
            return arb(-1)
        Nk = n0 + n1[0] * ux + n1[1] * uy
        Dk = d0 + d1[0] * ux + d1[1] * uy
        side = sgn if self.T.kind[k] != SEGMENT else -sgn * tau
        if not deriv:
            return side * (N * Dk - Nk * Dn)
        Nk1 = -n1[0] * uy + n1[1] * ux
        Dk1 = -d1[0] * uy + d1[1] * ux
        return side * (N1 * Dk + N * Dk1 - Nk1 * Dn - Nk * D1)

    def farther_centred(self, k: int, th, pa: float, pb: float, tau: int = 1) -> bool:
        """:meth:`farther` > 0 on [pa, pb] ⊆ θ by the mean-value form."""
        tm = arb((pa + pb) / 2)
        g = self.farther(k, tm, tau) + self.farther(k, th, tau, deriv=True) * (th - tm)
        return bool(g > 0)

    # ------------------------------------------------------------------ evaluation
    def u(self, th):
        ph = self.alpha + th
        return ph.cos(), ph.sin()

    def _nd(self, th):
        # the same parameter ball is evaluated for every other site of a piece: the last few
        # results are kept by the ball's identity (held, so its id is not reused) and precision
        prec = ctx.prec
        for ball, p, res in self._recent:
            if ball is th and p == prec:
                return res
        ux, uy = self.u(th)
        N = self.n0 + self.n1[0] * ux + self.n1[1] * uy
        Dn = self.d0 + self.d1[0] * ux + self.d1[1] * uy
        N1 = -self.n1[0] * uy + self.n1[1] * ux
        D1 = -self.d1[0] * uy + self.d1[1] * ux
        res = (ux, uy, N, Dn, N1, D1)
        self._recent.append((th, prec, res))
        if len(self._recent) > RECENT:
            del self._recent[0]
        return res

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

    def _frame_derivs(self, th):
        """(|v'|, |v''|, v' × v'') on the parameter ball θ, from the coordinates in the orthonormal
        frame (u, u^⊥): v' = (R', R), v'' = (R'' − R, 2R'), so |v'|² = R'² + R², |v''|² =
        (R'' − R)² + 4R'², v' × v'' = 2R'² − R(R'' − R) (no cancellation between the frame's
        components, which a ball of θ would blur)."""
        ux, uy, t, t1, N, Dn, N1, D1 = self._t1(th)
        N2, D2 = self.n0 - N, self.d0 - Dn          # N'' = −n₁·u = n₀ − N
        t2 = (N2 - t * D2 - 2 * t1 * D1) / Dn
        R, R1, R2 = self.r + self.sigma * t, self.sigma * t1, self.sigma * t2
        return hypot(R1, R), hypot(R2 - R, 2 * R1), 2 * sq(R1) - R * (R2 - R)

    def chord_bound(self, t0: arb, t1: arb, target: float = 0.0) -> arb:
        """:meth:`chord_bound_parts` with 8, 32, 128, 512 sub-pieces until below ``target``."""
        parts = 8
        while True:
            b = self.chord_bound_parts(t0, t1, parts)
            if b.upper() <= target or parts >= 512:
                return b
            parts *= 4

    def chord_bound_parts(self, t0: arb, t1: arb, parts: int = 8) -> arb:
        """Chord-to-curve deviation bound of the piece between the parameters t0 and t1, over
        ``parts`` sub-pieces m of parameter length δθ (lengths ℓ_m ≤ δθ max|v'|, curvatures
        κ_m ≤ max|v' × v''| / min|v'|³): the smallest of

        * Δθ²/8 · max|v''| (the distance from v(θ) to the linear interpolation of its ends);
        * ℓ²κ/8 (ℓ = Σ ℓ_m, κ = max κ_m) and Σ_m ℓ_m κ_m w_m with w_m = 1/(1/S_m + 1/S'_m)
          (S_m = Σ_{k≤m} ℓ_k, S'_m = Σ_{k≥m} ℓ_k), when the total turning Σ ℓ_m κ_m is below
          π/2.  For the arc-length parametrisation, the signed distance h(s) from the chord's
          line has h(0) = h(ℓ) = 0 and |h''| ≤ κ(s), so |h(s)| ≤ ∫ G(s, σ) κ(σ) dσ with the
          Green function G(s, σ) ≤ σ(ℓ − σ)/ℓ = 1/(1/σ + 1/(ℓ − σ)) ≤ w_m on sub-piece m (and
          ≤ s(ℓ − s)κ/2 for a constant bound κ).  The turning below π/2 keeps every tangent within
          π/2 of the chord's direction (a mean of the tangents), so the projection on the chord
          is monotone and the nearest point of the chord's line lies on the chord itself.  The
          weighted form is what proves the far pieces of a hyperbola-like branch, long but
          nearly straight (κ decays like the cube of the distance)."""
        lo_t, hi_t = t0.union(t1).lower(), t0.union(t1).upper()
        dt = arb(hi_t) - arb(lo_t)
        step = dt / parts
        b1 = arb(0)
        lens, kaps = [], []
        curved = True
        # sub-pieces in order; one where |v'| varies by more than a factor 2 is halved (near a
        # pole |v'| grows like 1/δ²: the halving there is geometric), up to SUB_PIECES in all
        todo = [(arb(lo_t) + m * step, arb(lo_t) + (m + 1) * step) for m in range(parts)][::-1]
        count = parts
        while todo:
            ka, kb = todo.pop()
            K = ka.union(kb)
            sp, acc, cross = self._frame_derivs(K)
            lo = sp.lower()
            if count < SUB_PIECES and not (lo > 0 and sp.upper() <= 2 * lo):
                km = (ka + kb) / 2
                todo += [(km, kb), (ka, km)]
                count += 1
                continue
            b1 = b1.max(arb(acc.upper()))
            lens.append(arb(((kb - ka) * arb(sp.upper())).upper()))
            if lo > 0:
                kaps.append(arb((abs(cross) / (arb(lo) ** 3)).upper()))
            else:
                curved = False
        b1 = dt * dt * b1 / 8
        if not curved:
            return b1
        length = sum(lens, arb(0))
        kappa = arb(0)
        turning = arb(0)
        for ln, kp in zip(lens, kaps):
            kappa = kappa.max(kp)
            turning += ln * kp
        if not turning < arb.pi() / 2:
            return b1
        best = b1
        b2 = length * length * kappa / 8
        if b2.upper() < best.upper():
            best = b2
        before = arb(0)
        b3 = arb(0)
        for m, (ln, kp) in enumerate(zip(lens, kaps)):
            before += ln
            after = length - before + ln
            b3 += ln * kp / (1 / before + 1 / after)
        if b3.upper() < best.upper():
            best = b3
        return best

    def param(self, X, Y):
        """θ of the direction of (X, Y) from the centre, measured from the arc's middle direction m
        (atan2 of (m × w, m·w): its cut, the gap's middle, is far from the range) plus β/2."""
        mx, my = self.T.arc_mid_arb(self.s)
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
