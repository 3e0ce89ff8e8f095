"""Infinite ends of an arc's bisector (the hyperbola-like branch of an arc s and a point p, or of
two arcs, outside their circles), proved up to the pole (for
:mod:`runtime.segments.certificate_edges`).

The branch is x(θ) = c + (ρ + t) u(φ), φ = α + θ, t = N/Δ (:mod:`runtime.segments.
certificate_arcs`), for θ between a start θ_S and the pole θ∞ where Δ vanishes; a = u(φ∞) is its
asymptotic direction.  With δ = φ − φ∞ and φ_m = (φ + φ∞)/2, u(φ) − a = 2 sin(δ/2) u^⊥(φ_m) and
Δ = 2 sin(δ/2) E with E = d₁·u^⊥(φ_m): every quantity below is a smooth function on the compact
interval [θ_S, θ∞] (θ∞ an arb ball) and is bounded there by interval arithmetic (with subdivision).

1. **t > 0 up to the pole**: 1/t = 2 sin(δ/2) E/N, sin(δ/2) has the sign of θ − θ∞, so
   (θ∞ − θ)-sign · E/N > 0 on the interval.
2. **Every other site k farther** (the support witness): for any unit vector u,
   d_k(x) ≥ u·x − h_k(u) (h_k the support of k), and u(φ)·x = u·c + ρ + t; so
   d_k − t ≥ G_k(θ) = u·c + ρ − h_k(u(φ)) with h_k ≤ the support of a point, a segment's ends, an
   arc's circle (its ends' when the directions miss its open range).  G_k > 0 on [θ_S, θ∞] for
   every k whose support at a is below the arc's.  A site tying at a (on the asymptote's support
   line) is handled exactly: a point q with (c − q)·a + ρ = 0 (q on the tangent from p: rationals
   and squares) has G_q = 2 sin(δ/2) (c − q)·u^⊥(φ_m), proved of the right sign; otherwise, for a
   point partner p, d_q > d_p ⟺ (x − (p + q)/2)·(p − q) > 0, which is
   (c − m)·(p − q) + ρ u·(p − q) + N u^⊥(φ_m)·(p − q)/E (q and p on one support line); an arc
   tying (its circle on the support line, with a rational asymptote) is proved against its
   circle (:func:`_far_arc_tie`); other ties of arcs are a limit.
3. **Conditions** (R2 for curves ending at p, an arc partner's range) are linear g·x + g₀ > 0;
   times 1/t > 0 they are (g·c + g₀ + ρ g·u)/t + g·u, smooth up to the pole (g·a > 0 needed);
   when g·a = 0 exactly (a rational asymptote, found from the float direction and checked on the
   pole's equation in rationals), divided by 2 sin(δ/2) too: (g·c + g₀ + ρ g·u) E/N + g·u^⊥(φ_m)
   with the sign of θ∞ − θ.

The start θ_S is where t first exceeds twice the scene's extent (then four times that, …) until
all of this is proved; the finite part is proved with the pieces.  The end's key is ("tangent", sign) of :func:`runtime.segments.
certificate_hull.tangent_sign` at a.

Public API: :func:`arc_tail`, :func:`arc_pole`, :func:`support_bound`, :func:`positive_on`.
"""
from __future__ import annotations

from flint import arb

from ..certify.foot import to_arb
from .certificate_hull import tangent_sign
from .certificate_rules import range_lines
from .certificate_sites import ARC, POINT, SEGMENT

__all__ = ["arc_tail", "arc_pole", "support_bound", "positive_on", "pole_sectors"]

DEPTH = 10


def _tangent_at_end(c, which: int) -> bool:
    """The asymptote touches the arc exactly at its start (0) or end (1): the point partner lies
    on the tangent line there, or the arc partner's circle touches it (rationals and squares)."""
    T = c.T
    (cx, cy), rho = T.cen[c.s], T.rad[c.s]
    e = T.a[c.s] if which == 0 else T.b[c.s]
    r = (e[0] - cx, e[1] - cy)
    if T.kind[c.k] == POINT:
        p = T.a[c.k]
        return (p[0] - e[0]) * r[0] + (p[1] - e[1]) * r[1] == 0
    (kx, ky), r2 = T.cen[c.k], T.rad[c.k]
    h = (kx - e[0]) * r[0] + (ky - e[1]) * r[1]           # −ρ·(distance of c₂ below the tangent)
    return h <= 0 and h * h == r2 * r2 * rho * rho


def arc_pole(c, theta_fin, sg: int, other=None):
    """The pole reached from θ_fin going the way sg (θ_fin None: the pole of that side), or None;
    only poles in the arc's closed range (at an end exactly, decided in rationals)."""
    poles = [p for p in c.poles() if (p > 0 and p < c.beta) or (p.overlaps(c.beta) and _tangent_at_end(c, 1))
             or (p.overlaps(arb(0)) and _tangent_at_end(c, 0))]
    if theta_fin is not None:
        poles = [p for p in poles if (p > theta_fin if sg > 0 else p < theta_fin)]
    if not poles:
        return None
    poles.sort(key=lambda p: float(p.mid()))
    return poles[0] if sg > 0 else poles[-1]


def positive_on(fn, J: arb, depth: int = DEPTH) -> bool:
    """fn(ball) > 0 on the parameter ball J (bisection)."""
    stack = [(J, 0)]
    while stack:
        K, d = stack.pop()
        v = fn(K)
        if v > 0:
            continue
        if d >= depth:
            return False
        lo, hi = K.lower(), K.upper()
        m = (lo + hi) / 2
        stack.append((arb(lo).union(arb(m)), d + 1))
        stack.append((arb(m).union(arb(hi)), d + 1))
    return True


class _Branch:
    """Smooth pieces of the branch near its pole (module docstring)."""

    def __init__(self, c, pole, sg):
        self.c, self.pole, self.sg = c, pole, sg
        self.phi_inf = c.alpha + pole

    def parts(self, th):
        c = self.c
        ph = c.alpha + th
        ux, uy = ph.cos(), ph.sin()
        pm = (ph + self.phi_inf) / 2
        wx, wy = -pm.sin(), pm.cos()                  # u^⊥(φ_m)
        sh = ((ph - self.phi_inf) / 2).sin()
        N = c.n0 + c.n1[0] * ux + c.n1[1] * uy
        E = c.d1[0] * wx + c.d1[1] * wy
        return ux, uy, wx, wy, sh, N, E

    def inv_t(self, th):
        _, _, _, _, sh, N, E = self.parts(th)
        return 2 * sh * E / N


def arc_tail(pr, sg: int, pole: arb, theta_fin):
    """Prove the branch from a start θ_S to the pole (sg = +1: θ grows to it); returns (θ_S as a
    float, key) or None (problems reported)."""
    c, T = pr.curve, pr.T
    if c.sigma != 1 or (T.kind[c.k] == ARC and c.tau != 1) or T.kind[c.k] == SEGMENT:
        pr.report("an arc's bisector inside a circle or with a segment does not reach infinity")
        return None
    a = c.u(pole)
    key = tangent_sign(T, pr.i, pr.j, a[0], a[1])
    if key is None:
        pr.report_limit("the direction of its infinite end is not decided")
        return None
    br = _Branch(c, pole, sg)
    base = theta_fin if theta_fin is not None else (arb(0) if sg > 0 else c.beta)
    gap = float((pole - base).mid()) * sg
    if not gap > 0:
        pr.report("its infinite end is not beyond its finite end")
        return None
    sites = [k for k in range(T.n) if k not in pr.skip and k not in (pr.i, pr.j)]
    last = None
    for th_s, J in pole_sectors(c.t, pole, sg, gap, T.scale, 20):
        last = _tail_ok(pr, br, J, sites)
        if last is None:
            return th_s, ("tangent", key)
    k = last
    if isinstance(k, int):
        pr.report(f"site {k} is not proved farther than its sites along the infinite end", k)
    else:
        pr.report_limit(f"its infinite end is not proved ({k})")
    return None


def pole_sectors(t_of, pole: arb, sg: int, gap: float, scale: float, rounds: int):
    """The sectors [θ_S, pole] of a branch going to its pole the way sg on which a tail is tried:
    θ_S the first of pole − sg·gap/2, pole − sg·gap/4, … where the branch's distance t = t_of(θ)
    exceeds 2·scale, then 4, 16, … times that (at most ``rounds`` sectors); none once t stays
    below the target up to 10⁻¹² of the pole.  Yields (θ_S as a float, the ball [θ_S, pole])."""
    target = 2 * scale                       # the tail starts where t exceeds this, then farther
    tiny = 1e-12 * (1 + abs(float(pole.mid())))
    for _ in range(rounds):
        delta = gap / 2
        while delta > tiny:
            t = t_of(arb(float(pole.mid()) - sg * delta))
            if t.is_finite() and t > target:
                break
            delta /= 2
        if delta <= tiny:
            return
        th_s = float(pole.mid()) - sg * delta
        yield th_s, arb(th_s).union(pole)
        target *= 4


def _tail_ok(pr, br, J, sites):
    """None when the tail on J is proved, else the first failing site (or a message)."""
    c, T, sg = br.c, pr.T, br.sg
    if not positive_on(lambda th: -sg * br.parts(th)[6] / br.parts(th)[5], J):
        return "t > 0 up to the pole"
    p = c.k if T.kind[c.k] == POINT else None
    for k in sites:
        if not _far(T, c, br, J, k, p):
            return k
    for k, mode, conds in getattr(pr, "linear", []):
        def one(th, g):
            return _cond_scaled(c, br, th, g, _on_asymptote(T, c, br, g))
        if mode == "max":
            def fmax(th, conds=conds):
                vals = [one(th, g) for g in conds]
                return vals[0].max(vals[1]) if len(vals) > 1 else vals[0]
            if not positive_on(fmax, J):
                return k
            continue
        for g in conds:
            if not positive_on(lambda th, g=g: one(th, g), J):
                return k
    if T.kind[c.k] == ARC:
        if not positive_on(lambda th: _partner_range(T, c, br, th), J):
            return "the partner arc's range"
    return None


def _cond_scaled(c, br, th, g, flat: bool = False):
    """(g·x + g₀)/t on the branch; ``flat``: g·a = 0 exactly, then g·u = 2 sin(δ/2) g·u^⊥(φ_m) and
    the value divided by 2 sin(δ/2) > 0 (of the sign −sg) is returned."""
    gx, gy, g0 = (to_arb(v) for v in g)
    ux, uy, wx, wy, sh, N, E = br.parts(th)
    if flat:
        return -br.sg * ((gx * c.c[0] + gy * c.c[1] + g0 + c.r * (gx * ux + gy * uy)) * E / N + gx * wx + gy * wy)
    s = br.inv_t(th)
    return (gx * c.c[0] + gy * c.c[1] + g0 + c.r * (gx * ux + gy * uy)) * s + gx * ux + gy * uy


def _rational_asymptote(T, c, br):
    """The asymptotic direction as an exact rational vector when it is one (an axis, a simple
    slope: checked exactly on the pole's equation), else None."""
    if hasattr(br, "_ra"):
        return br._ra
    from fractions import Fraction

    br._ra = None
    ux, uy = (float(v.mid()) for v in c.u(br.pole))
    m = max(abs(ux), abs(uy))
    u = (Fraction(ux / m).limit_denominator(1000), Fraction(uy / m).limit_denominator(1000))
    cs, rs = T.cen[c.s], T.rad[c.s]
    if T.kind[c.k] == POINT:
        z, rho = T.a[c.k], rs                 # (p − c)·u = ρ|u|
    else:
        z, rho = T.cen[c.k], rs - T.rad[c.k]  # (c₂ − c)·u = (ρ − ρ₂)|u|
    ku = (z[0] - cs[0]) * u[0] + (z[1] - cs[1]) * u[1]
    if ku * rho >= 0 and ku * ku == rho * rho * (u[0] * u[0] + u[1] * u[1]):
        if (ux * float(u[0]) + uy * float(u[1])) > 0:
            br._ra = u
    return br._ra


def _on_asymptote(T, c, br, g) -> bool:
    """g·a = 0 exactly for the linear function g (a rational asymptote perpendicular to it)."""
    u = _rational_asymptote(T, c, br)
    return u is not None and g[0] * u[0] + g[1] * u[1] == 0


def _partner_range(T, c, br, th):
    k = c.k
    ga, gb = range_lines(T, k)
    va = _cond_scaled(c, br, th, ga, _on_asymptote(T, c, br, ga))
    vb = _cond_scaled(c, br, th, gb, _on_asymptote(T, c, br, gb))
    (cx, cy) = T.cen[k]
    ab = (T.a[k][0] - cx) * (T.b[k][1] - cy) - (T.a[k][1] - cy) * (T.b[k][0] - cx)
    if ab > 0:
        return va.min(vb)
    if ab < 0:
        return va.max(vb)
    return va


def support_bound(T, k, ux, uy):
    """An upper bound of the support of site k in the directions of the balls (ux, uy)."""
    ax, ay, bx, by = T.arb_ends(k)
    h = (ux * ax + uy * ay).max(ux * bx + uy * by)
    if T.kind[k] == ARC:
        cx, cy, rho = T.arb_arc(k)
        inr = T.in_range(k, ux, uy, closed=False)
        if inr is not False:
            h = h.max(ux * cx + uy * cy + rho)
    return h


def _far(T, c, br, J, k, p) -> bool:
    """d_k − t > 0 on the tail (module docstring, 2)."""
    def G(th):
        ux, uy, *_ = br.parts(th)
        return ux * c.c[0] + uy * c.c[1] + c.r - support_bound(T, k, ux, uy)
    if positive_on(G, J):
        return True
    if T.kind[k] == ARC:
        return _far_arc_tie(T, c, br, J, k)
    pts = [T.a[k]] if T.kind[k] == POINT else [T.a[k], T.b[k]]
    for q in pts:
        if not _far_point(T, c, br, J, q, p):
            return False
    return True


def _far_arc_tie(T, c, br, J, k) -> bool:
    """Arc k ties at the asymptote a (its circle touches the support line there too: arcs of
    circles tangent to one side of the hull).  The distance to an arc is at least the distance to
    its circle, |x − c_k| − ρ_k for x outside it, so d_k > t follows from
    |x − c_k|² − (ρ_k + t)² = K + 2ρ u·D + 2t B(u) > 0, D = c − c_k, K = |D|² + ρ² − ρ_k²,
    B(u) = u·D + ρ − ρ_k (the support gap of module docstring 2).  With a rational asymptote and
    B(a) = 0 exactly, B(u) = 2 sin(δ/2) u^⊥(φ_m)·D and 1/t = 2 sin(δ/2) E/N, so the left side
    divided by 2t sin(δ/2) (of the sign −sg) is (K + 2ρ u·D) E/N + 2 u^⊥(φ_m)·D: smooth up to
    the pole, and its limit there is positive exactly when k lies beyond the branch's two sites
    along the common support line."""
    u = _rational_asymptote(T, c, br)
    if u is None:
        return False
    (kx, ky), rk = T.cen[k], T.rad[k]
    (cx, cy), rho = T.cen[c.s], T.rad[c.s]
    uD = u[0] * (cx - kx) + u[1] * (cy - ky)
    if uD * (rk - rho) < 0 or uD * uD != (rk - rho) ** 2 * (u[0] * u[0] + u[1] * u[1]):
        return False                                   # B(a) ≠ 0: not a tie
    Dx, Dy = c.c[0] - to_arb(kx), c.c[1] - to_arb(ky)
    rka = to_arb(rk)
    K = Dx * Dx + Dy * Dy + c.r * c.r - rka * rka

    def F(th):
        ux, uy, wx, wy, _, N, E = br.parts(th)
        return -br.sg * ((K + 2 * c.r * (ux * Dx + uy * Dy)) * E / N + 2 * (wx * Dx + wy * Dy))
    return positive_on(F, J)


def _far_point(T, c, br, J, q, p) -> bool:
    qa = (to_arb(q[0]), to_arb(q[1]))

    def G(th):
        ux, uy, *_ = br.parts(th)
        return ux * (c.c[0] - qa[0]) + uy * (c.c[1] - qa[1]) + c.r
    if positive_on(G, J):
        return True
    ph = c.alpha + br.pole
    bracket = ph.cos() * (c.c[0] - qa[0]) + ph.sin() * (c.c[1] - qa[1]) + c.r
    if p is not None and not (bracket > 0 or bracket < 0) and _on_tangent(T, c, p, q):
        def Gf(th):                                  # G = 2 sin(δ/2) (c − q)·u^⊥(φ_m)
            _, _, wx, wy, sh, _, _ = br.parts(th)
            return -br.sg * ((c.c[0] - qa[0]) * wx + (c.c[1] - qa[1]) * wy)
        if positive_on(Gf, J):
            return True
        pa = T.arb_ends(p)[:2]
        mx, my = (pa[0] + qa[0]) / 2, (pa[1] + qa[1]) / 2
        dx, dy = pa[0] - qa[0], pa[1] - qa[1]

        def L(th):                                   # (x − m)·(p − q), x = c + (ρ + t) u
            ux, uy, wx, wy, sh, N, E = br.parts(th)
            return ((c.c[0] - mx) * dx + (c.c[1] - my) * dy + c.r * (ux * dx + uy * dy) +
                    N * (wx * dx + wy * dy) / E)
        return positive_on(L, J)
    return False


def _on_tangent(T, c, p, q) -> bool:
    """q lies on a tangent line from point p to the circle of the arc (exact)."""
    (px, py), (cx, cy), rho = T.a[p], T.cen[c.s], T.rad[c.s]
    w = (q[0] - px, q[1] - py)
    if w == (0, 0):
        return False
    cr = (cx - px) * w[1] - (cy - py) * w[0]
    return cr * cr == rho * rho * (w[0] * w[0] + w[1] * w[1])
