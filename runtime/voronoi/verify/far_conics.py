"""Far from the scene: enclosures of the distance to a parabola or a hyperbola and of its gradient.

On a cell of polar coordinates about a centre m, q = m + t·u(θ), τ = 1/t ∈ [τ0, τ1] (τ0 = 0: the
cell reaches infinity), θ ∈ [θ0, θ1], every bound below is an inequality between functions of
(τ, cos θ, sin θ) that are linear in q after division by t, evaluated with interval arithmetic
(float, every result widened by a relative 1e-12).  In the canonical frame of the site (X along
its axis; :meth:`runtime.sites.conic.Conic.frame`), X0/t = cos(θ − φ) + τ·x_m and
Y0/t = sin(θ − φ) + τ·y_m with (x_m, y_m) the canonical coordinates of m.

**Parabola** Y² = 2pX, K = {Y² ≤ 2pX} its convex side, c(s) = (s²/2p, s).  For q with Y0 < 0
(else reflect Y ↦ −Y) the nearest point of the curve is c(s*) with s* < 0 the only negative zero
of f(s) = −(q − c(s))·c'(s) = s³/(2p²) + s(1 − X0/p) − Y0: the monic cubic s³ + Bs − 2p²Y0 has
roots summing to 0 with product 2p²Y0 < 0, so exactly one is negative; f < 0 before it and > 0
on (s*, 0] (f(0) = −Y0 > 0), and the other arm is farther (mirror in the axis).  Hence
f(S1) < 0 < f(S2) with S1 < S2 ≤ 0 proves s* ∈ (S1, S2) (S1 = −∞ on cells reaching infinity).
q is outside K when Y0² > 2pX0; then ∇d = ν(s*) with ν(s) = (−p, s)/√(p² + s²) the outward
normal (distance to the convex set K), whose angle atan2(s, −p) is monotone in s.  Upper
bound: d ≤ |Y0| when X0 ≥ 0 (the curve point (X0, −√(2pX0)) lies between q and the axis),
else d ≤ |X0| + |Y0| (the vertex).

**Hyperbola** X²/a² − Y²/b² = 1 (both branches are one site), c(w) = (a cosh w, b sinh w).  For
q with X0 > 0 and Y0 > 0 (else reflect) the nearest point is on the upper right quarter (two
mirrors), at the only zero w* > 0 of g(w) = −(q − c)·c' = cosh w·F(tanh w),
F(v) = (a² + b²)·v/√(1 − v²) − aX0·v − bY0 convex on [0, 1) with F(0) = −bY0 < 0: g(W1) < 0 <
g(W2) proves w* ∈ (W1, W2) (W2 = ∞ on cells reaching infinity).  q is outside the convex side
of the right branch when aY0 − bX0 > 0 (above the asymptote); then ∇d = ν(w*),
ν(w) ∝ (−b cosh w, a sinh w), whose angle decreases from π to atan2(a, −b).  Upper bound, with
q = s·e + δ·n (e = (a, b)/c, n = (−b, a)/c, c = √(a² + b²)): d ≤ |δ| + b when s ≥ c (the branch
point below the asymptote point s·e is within b(σ − √(σ² − 1)) ≤ b of it, σ = s/c), else
d ≤ |X0 − a| + |Y0| (the vertex).

**Lower bounds** (third sites): d(q, S) ≥ the signed distance of q to any half-plane containing
S: tangent half-planes of K for a parabola, (q − c(S))·ν(S) = (−pX0 + S·Y0 − S²/2)/√(p² + S²);
for a hyperbola the minimum over its branches of max(±aY0 − bX0, …)/c and a − X0 (each branch
lies in its asymptotic cone and beyond its vertex); for a bounded site in the disc D(c, ρ),
d ≥ t − |m − c| − ρ.

Public API: :class:`FarConic`, :func:`cos_range`, :func:`sin_range`, :func:`bounded_lower`,
:func:`parabola_foot_sign`, :func:`hyperbola_foot_sign`, :func:`parabola_foot_guess`,
:func:`hyperbola_foot_guess`, :func:`parabola_outside`, :func:`above_asymptote`,
:func:`parabola_upper`, :func:`hyperbola_upper`, :data:`UNBOUNDED`.
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["FarConic", "cos_range", "sin_range", "bounded_lower", "UNBOUNDED", "parabola_foot_sign",
           "hyperbola_foot_sign", "parabola_foot_guess", "hyperbola_foot_guess", "parabola_outside",
           "above_asymptote", "parabola_upper", "hyperbola_upper"]

UNBOUNDED = ("parabola", "hyperbola")
REL = 1e-12          # relative widening of every interval operation
ANG = 1e-12          # widening of every float angle (atan2 of rounded data)
TWO_PI = 2.0 * math.pi


def cos_range(a0, a1):
    """Enclosure of cos over the angle intervals [a0, a1] (arrays, a0 ≤ a1), widened by ANG."""
    a0 = np.asarray(a0, float) - ANG
    a1 = np.asarray(a1, float) + ANG
    c0, c1 = np.cos(a0), np.cos(a1)
    lo, hi = np.minimum(c0, c1), np.maximum(c0, c1)
    k = np.ceil(a0 / TWO_PI)
    hi = np.where(TWO_PI * k <= a1, 1.0, hi)
    k = np.ceil((a0 - math.pi) / TWO_PI)
    lo = np.where(TWO_PI * k + math.pi <= a1, -1.0, lo)
    return lo - 4e-16, hi + 4e-16


def sin_range(a0, a1):
    """Enclosure of sin over [a0, a1] (sin x = cos(x − π/2))."""
    return cos_range(np.asarray(a0, float) - 0.5 * math.pi, np.asarray(a1, float) - 0.5 * math.pi)


def _scale_iv(lo, hi, c):
    """[lo, hi]·c for a float c."""
    return (np.minimum(lo * c, hi * c), np.maximum(lo * c, hi * c))


def _pad(lo, hi, mag):
    return lo - REL * mag - 1e-300, hi + REL * mag + 1e-300


def bounded_lower(m, centre, radius, t1):
    """Lower bound of d/t on a cell with τ ≤ t1 for a site in the disc D(centre, radius):
    d ≥ |q − c| − ρ ≥ t − |m − c| − ρ."""
    off = math.hypot(centre[0] - m[0], centre[1] - m[1]) * (1 + REL) + radius * (1 + REL)
    return 1.0 - np.asarray(t1, float) * off * (1 + REL) - 1e-15


class FarConic:
    """A parabola or hyperbola site seen from far away (module docstring), about the centre m."""

    def __init__(self, g, m):
        fr = g.exact.frame
        self.kind = g.kind
        if self.kind not in UNBOUNDED:
            raise ValueError(f"FarConic needs a parabola or a hyperbola, not a {self.kind}")
        self.cs, self.sn = float(fr.cos), float(fr.sin)
        self.tx, self.ty = float(fr.tx), float(fr.ty)
        self.phi = math.atan2(self.sn, self.cs)
        if self.kind == "parabola":
            self.p = float(fr.params["p"])
        else:
            self.a, self.b = math.sqrt(float(fr.params["A2"])), math.sqrt(float(fr.params["B2"]))
            self.c = math.hypot(self.a, self.b)
        dx, dy = float(m[0]) - self.tx, float(m[1]) - self.ty
        self.xm = self.cs * dx + self.sn * dy
        self.ym = -self.sn * dx + self.cs * dy
        self.err = 1e-12 * (abs(dx) + abs(dy) + 1.0)

    # ------------------------------------------------------------------ frame
    def coords(self, t0, t1, a0, a1):
        """Enclosures (Xlo, Xhi, Ylo, Yhi) of X0/t, Y0/t on the cells τ ∈ [t0, t1], θ ∈ [a0, a1]."""
        cl, ch = cos_range(np.asarray(a0) - self.phi, np.asarray(a1) - self.phi)
        sl, sh = sin_range(np.asarray(a0) - self.phi, np.asarray(a1) - self.phi)
        t0, t1 = np.asarray(t0, float), np.asarray(t1, float)
        xl = np.minimum(t0 * self.xm, t1 * self.xm) - t1 * self.err
        xh = np.maximum(t0 * self.xm, t1 * self.xm) + t1 * self.err
        yl = np.minimum(t0 * self.ym, t1 * self.ym) - t1 * self.err
        yh = np.maximum(t0 * self.ym, t1 * self.ym) + t1 * self.err
        Xlo, Xhi = _pad(cl + xl, ch + xh, 1.0 + t1 * abs(self.xm))
        Ylo, Yhi = _pad(sl + yl, sh + yh, 1.0 + t1 * abs(self.ym))
        return Xlo, Xhi, Ylo, Yhi

    # ------------------------------------------------------------------ pair members
    def gradient(self, t0, t1, a0, a1):
        """(ok, αlo, αhi, dup): on the cells where ok, q is outside the convex side of the nearest
        branch, ∇d(q) = u(α) with α ∈ [αlo, αhi] (world angles), and d/t ≤ dup."""
        X = self.coords(t0, t1, a0, a1)
        t0, t1 = np.asarray(t0, float), np.asarray(t1, float)
        if self.kind == "parabola":
            ok, lo, hi, up = self._parabola(t0, t1, *X)
        else:
            ok, lo, hi, up = self._hyperbola(t0, t1, *X)
        ok &= lo <= hi
        return ok, lo + self.phi - ANG, hi + self.phi + ANG, up

    def _parabola(self, t0, t1, Xlo, Xhi, Ylo, Yhi):
        p = self.p
        neg, pos = Yhi < 0, Ylo > 0
        flip = pos                                  # reflect Y ↦ −Y: Y0 < 0 in the frame used
        yl, yh = np.where(flip, -Yhi, Ylo), np.where(flip, -Ylo, Yhi)
        ok = neg | pos
        ok &= parabola_outside(t0, t1, Xhi, yh, p) > 0
        # float guides of s* at the corners, then the proved bracket (S1, S2)
        S1, S2 = self._bracket_guides(t0, t1, Xlo, Xhi, yl, yh)
        ok &= parabola_foot_sign(S2, t0, t1, Xlo, Xhi, yl, yh, p)[0] > 0
        fin = np.isfinite(S1)
        S1f = np.where(fin, S1, -1.0)
        ok &= ~fin | (parabola_foot_sign(S1f, t0, t1, Xlo, Xhi, yl, yh, p)[1] < 0)
        # normal angle atan2(s, −p) ∈ [atan2(S2, −p), atan2(S1, −p)] (s < 0), −π/2 at s = −∞
        lo = np.arctan2(-np.abs(S2), -p)             # −π at S2 = 0 (a signed zero would give +π)
        hi = np.where(fin, np.arctan2(-np.abs(S1f), -p), -0.5 * math.pi)
        lo, hi = np.where(flip, -hi, lo), np.where(flip, -lo, hi)
        return ok, lo, hi, parabola_upper(Xlo, Xhi, yl)

    def _bracket_guides(self, t0, t1, Xlo, Xhi, yl, yh):
        """Float guesses S1 < S2 ≤ 0 of the foot parameter's range on the cells (the proofs check
        them); S1 = −∞ on cells reaching infinity."""
        p = self.p
        pts = []
        for X, Y, T in ((Xlo, yh, t1), (Xhi, yl, t1), (Xhi, yh, t1), (Xlo, yl, t1),
                        (Xlo, yh, t0), (Xhi, yl, t0), (Xhi, yh, t0), (Xlo, yl, t0)):
            with np.errstate(divide="ignore", invalid="ignore"):
                tt = np.where(T > 0, 1.0 / np.where(T > 0, T, 1.0), np.nan)
            pts.append(parabola_foot_guess(X * tt, Y * tt, p))
        P = np.array(pts)
        fin = np.isfinite(P[4:]).all(0)
        smax = np.nanmax(P[:4], 0)
        smin = np.where(fin, np.nanmin(P, 0), -np.inf)
        spread = np.where(fin, smax - smin, 0.0)
        S2 = np.minimum(smax + 0.25 * spread + 1e-6 * (abs(smax) + p), 0.0)
        S1 = smin - 0.25 * spread - 1e-6 * (abs(smin) + p)
        return np.where(t0 > 0, S1, -np.inf), S2

    def _hyperbola(self, t0, t1, Xlo, Xhi, Ylo, Yhi):
        a, b, c = self.a, self.b, self.c
        fx, fy = Xhi < 0, Yhi < 0                   # reflections X ↦ −X, Y ↦ −Y
        ok = ((Xlo > 0) | fx) & ((Ylo > 0) | fy)
        xl, xh = np.where(fx, -Xhi, Xlo), np.where(fx, -Xlo, Xhi)
        yl, yh = np.where(fy, -Yhi, Ylo), np.where(fy, -Ylo, Yhi)
        ok &= above_asymptote(xh, yl, a, b) > 0
        W1, W2 = self._w_guides(t0, t1, xl, xh, yl, yh)
        ok &= hyperbola_foot_sign(W1, t0, t1, xl, xh, yl, yh, a, b)[1] < 0
        fin = np.isfinite(W2)
        W2f = np.where(fin, W2, 0.0)
        ok &= ~fin | (hyperbola_foot_sign(W2f, t0, t1, xl, xh, yl, yh, a, b)[0] > 0)
        sh1, ch1 = np.sinh(W1), np.cosh(W1)
        sh2, ch2 = np.sinh(W2f), np.cosh(W2f)
        # normal angle atan2(a sinh w, −b cosh w), decreasing in w, atan2(a, −b) at w = ∞
        hi = np.arctan2(a * sh1, -b * ch1)
        lo = np.where(fin, np.arctan2(a * sh2, -b * ch2), math.atan2(a, -b))
        lo, hi = np.where(fx, math.pi - hi, lo), np.where(fx, math.pi - lo, hi)
        lo, hi = np.where(fy, -hi, lo), np.where(fy, -lo, hi)
        return ok, lo, hi, hyperbola_upper(t0, t1, xl, xh, yl, yh, a, b)

    def _w_guides(self, t0, t1, xl, xh, yl, yh):
        """Float guesses 0 ≤ W1 < W2 of the foot parameter's range; W2 = ∞ on cells reaching
        infinity."""
        a, b = self.a, self.b
        pts = []
        for X, Y, T in ((xl, yh, t1), (xh, yl, t1), (xh, yh, t1), (xl, yl, t1),
                        (xl, yh, t0), (xh, yl, t0), (xh, yh, t0), (xl, yl, t0)):
            with np.errstate(divide="ignore", invalid="ignore"):
                tt = np.where(T > 0, 1.0 / np.where(T > 0, T, 1.0), np.nan)
            pts.append(hyperbola_foot_guess(X * tt, Y * tt, a, b))
        P = np.array(pts)
        fin = np.isfinite(P[4:]).all(0)
        wmin = np.nanmin(P[:4], 0)
        wmax = np.where(fin, np.nanmax(P, 0), np.inf)
        spread = np.where(fin, wmax - wmin, 0.0)
        W1 = np.maximum(wmin - 0.25 * spread - 1e-6 * (1 + wmin), 0.0)
        W2 = wmax + 0.25 * spread + 1e-6 * (1 + wmax)
        return W1, np.where(t0 > 0, W2, np.inf)

    # ------------------------------------------------------------------ third sites
    def lower(self, t0, t1, a0, a1, tangents=(0.0,)):
        """Lower bound of d/t on the cells (half-planes containing the site, module docstring);
        ``tangents``: parameters S of the parabola's tangent half-planes tried."""
        Xlo, Xhi, Ylo, Yhi = self.coords(t0, t1, a0, a1)
        t1 = np.asarray(t1, float)
        best = np.zeros_like(Xlo)
        if self.kind == "parabola":
            p = self.p
            for S in tangents:
                nrm = math.hypot(p, S)
                v = -p * Xhi + np.where(S >= 0, S * Ylo, S * Yhi) - t1 * 0.5 * S * S
                mag = p * abs(Xhi) + abs(S) * np.maximum(abs(Ylo), abs(Yhi)) + t1 * S * S
                best = np.maximum(best, (v - REL * mag) / nrm * (1 - REL))
            return best
        a, b, c = self.a, self.b, self.c
        ay = (a * Ylo, a * Yhi)
        mag = a * np.maximum(abs(Ylo), abs(Yhi)) + b * np.maximum(abs(Xlo), abs(Xhi)) + a * t1
        right = np.maximum.reduce([(ay[0] - b * Xhi) / c, (-ay[1] - b * Xhi) / c, -Xhi])
        left = np.maximum.reduce([(ay[0] + b * Xlo) / c, (-ay[1] + b * Xlo) / c, Xlo])
        # a − X0 ≥ −X0 and a + X0 ≥ X0 (τ ≥ 0): the vertex terms are kept without a·τ
        return np.maximum(np.minimum(right, left) - 4 * REL * mag, 0.0)

    # ------------------------------------------------------------------ asymptotic cone
    def rays(self):
        """World angles of the site's asymptotic cone (its rays): the axis of a parabola, the four
        asymptote directions of a hyperbola."""
        if self.kind == "parabola":
            return [self.phi]
        al = math.atan2(self.b, self.a)
        return [self.phi + al, self.phi - al, self.phi + math.pi + al, self.phi + math.pi - al]


def parabola_outside(t0, t1, Xhi, Yhi, p):
    """Lower bound of (Y0/t)² − 2pτ·X0/t for Y0/t ≤ Yhi < 0, X0/t ≤ Xhi, τ ∈ [t0, t1]: > 0 proves
    q outside the convex side Y² ≤ 2pX of the parabola."""
    two_px = 2 * p * np.maximum(t0 * Xhi, t1 * Xhi)
    return Yhi * Yhi * (1 - 4 * REL) - two_px - REL * np.abs(two_px) - 1e-300


def above_asymptote(Xhi, Ylo, a, b):
    """Lower bound of a·Y0/t − b·X0/t (X0/t ≤ Xhi, Y0/t ≥ Ylo): > 0 proves q above the asymptote
    bX = aY, outside the convex side of the right branch (X0, Y0 > 0)."""
    return a * Ylo - b * Xhi - REL * (a * np.abs(Ylo) + b * np.abs(Xhi)) - 1e-300


def parabola_upper(Xlo, Xhi, Ylo):
    """Upper bound of d/t for q outside the parabola with Y0/t ∈ [Ylo, ·] ⊂ (−∞, 0): |Y0| when
    X0 ≥ 0, else |X0| + |Y0| (module docstring)."""
    return np.where(Xlo >= 0, -Ylo, -Ylo + np.maximum(np.abs(Xlo), np.abs(Xhi))) * (1 + 4 * REL)


def hyperbola_upper(t0, t1, xl, xh, yl, yh, a, b):
    """Upper bound of d/t for q above the asymptote of the right branch, X0/t ∈ [xl, xh],
    Y0/t ∈ [yl, yh], τ ∈ [t0, t1]: |δ| + b when s ≥ c, else the distance to the vertex (a, 0)
    (module docstring)."""
    c = math.hypot(a, b)
    s_lo = (a * xl + b * yl) / c * (1 - 4 * REL)
    dlt = np.maximum(np.abs(a * yh - b * xl), np.abs(a * yl - b * xh)) / c
    far = s_lo > c * t1 * (1 + 4 * REL)
    ymax = np.maximum(np.abs(yl), np.abs(yh))
    near = np.maximum.reduce([np.abs(xl - a * t1), np.abs(xh - a * t0), np.abs(xl - a * t0),
                              np.abs(xh - a * t1)]) + ymax
    return np.where(far, dlt + b * t1, near) * (1 + 8 * REL) + 1e-15


def parabola_foot_sign(S, t0, t1, Xlo, Xhi, Ylo, Yhi, p):
    """Enclosure (lo, hi) of f(S)/t = τ(S³/(2p²) + S) − (S/p)·X0/t − Y0/t over τ ∈ [t0, t1],
    X0/t ∈ [Xlo, Xhi], Y0/t ∈ [Ylo, Yhi], for S ≤ 0 (module docstring, *Parabola*: lo > 0
    proves s* < S, hi < 0 proves s* > S, when Y0 < 0)."""
    A = S ** 3 / (2 * p * p) + S                    # ≤ 0 for S ≤ 0
    c = -S / p                                      # ≥ 0
    lo = t1 * A + c * Xlo - Yhi
    hi = t0 * A + c * Xhi - Ylo
    mag = REL * (t1 * np.abs(A) + c * np.maximum(np.abs(Xlo), np.abs(Xhi)) + np.maximum(np.abs(Ylo), np.abs(Yhi)))
    return lo - mag, hi + mag


def hyperbola_foot_sign(W, t0, t1, Xlo, Xhi, Ylo, Yhi, a, b):
    """Enclosure (lo, hi) of g(W)/t = τ(a² + b²) sinh W cosh W − a sinh W·X0/t − b cosh W·Y0/t
    for W ≥ 0, X0, Y0 > 0 (module docstring, *Hyperbola*: lo > 0 proves w* < W, hi < 0 proves
    w* > W)."""
    sh, ch = np.sinh(W), np.cosh(W)
    E = (a * a + b * b) * sh * ch                   # ≥ 0
    lo = t0 * E - a * sh * Xhi - b * ch * Yhi
    hi = t1 * E - a * sh * Xlo - b * ch * Ylo
    mag = REL * (t1 * E + a * sh * np.maximum(np.abs(Xlo), np.abs(Xhi)) + b * ch * np.maximum(np.abs(Ylo), np.abs(Yhi)))
    return lo - mag, hi + mag


def parabola_foot_guess(X0, Y0, p):
    """Float s* of the point (X0, Y0) with Y0 < 0 (module docstring; bisection, NaN where X0 or
    Y0 is NaN)."""
    X0, Y0 = np.asarray(X0, float), np.asarray(Y0, float)
    lo = -2.0 * (np.abs(Y0) + np.sqrt(2 * p * np.abs(X0)) + p) - 1.0
    hi = np.zeros_like(lo)
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        f = mid ** 3 / (2 * p * p) + mid * (1 - X0 / p) - Y0
        lo, hi = np.where(f < 0, mid, lo), np.where(f < 0, hi, mid)
    return np.where(np.isfinite(X0) & np.isfinite(Y0), 0.5 * (lo + hi), np.nan)


def hyperbola_foot_guess(X0, Y0, a, b):
    """Float w* of the point (X0, Y0), X0, Y0 > 0 (module docstring; bisection on
    (a² + b²) sinh w − aX0 tanh w − bY0, whose zero is below asinh((aX0 + bY0)/(a² + b²)))."""
    X0, Y0 = np.asarray(X0, float), np.asarray(Y0, float)
    ok = np.isfinite(X0) & np.isfinite(Y0)
    Xs, Ys = np.where(ok, X0, 1.0), np.where(ok, Y0, 1.0)
    lo = np.zeros_like(Xs)
    hi = np.arcsinh(np.abs(a * Xs + b * Ys) / (a * a + b * b)) + 1.0
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        g = (a * a + b * b) * np.sinh(mid) - a * Xs * np.tanh(mid) - b * Ys
        lo, hi = np.where(g < 0, mid, lo), np.where(g < 0, hi, mid)
    return np.where(ok, 0.5 * (lo + hi), np.nan)
