"""Infinite ends of the edges of an elliptic piece on the hull of the sites (for
:mod:`runtime.segments.certificate_ellipse_edges`; thesis Prop. 1.2.1 — an edge ends at a vertex
or at a point at infinity —, ch. 4 — the offset x = e(φ) + t ν(φ) of a conic by its foot point —
and §2.2 — a piece's ends are point sites).

Frame e(φ) = c + cos φ M + sin φ N with Δ = det(M, N) > 0 and the outward normal
n(φ) = (e'_y, −e'_x), |n| = |e'|.  A point y with y − c = α_y M + β_y N (Cramer: exact rationals,
:func:`frame_coords`) has

    n(φ)·(e(φ) − y) = Δ g_y(φ),   g_y(φ) = 1 − α_y cos φ − β_y sin φ,                 (1)

since det(aM + bN, −sin φ M + cos φ N) = (a cos φ + b sin φ) Δ with a = cos φ − α_y,
b = sin φ − β_y.  g_y > 0 says that y lies strictly on the inner side of the tangent at e(φ).

**Support witness** (the argument of :mod:`runtime.segments.certificate_tails` for arcs): for a unit
vector ν and a point y, |x − y| ≥ ν·(x − y) (Cauchy–Schwarz), so d_k(x) ≥ ν·x − h_k(ν), h_k the
support function of site k.

**The foot curve of piece s and a point p, outside** (σ = +1): x(φ) = e(φ) + t(φ) ν(φ),
t = −|e − p|² |e'|/(2Δ g_p(φ)) (|x − p| = t), ρ = t.  Its infinite end is at a pole φ∞ where g_p
vanishes — the tangent at e(φ∞) passes through p: with (α, β) = R (cos φ_p, sin φ_p), R > 1 (p
outside the ellipse), φ∞ = φ_p ± arccos(1/R) (:func:`foot_poles`).  Sum to product,
g_p(φ) = α(cos φ∞ − cos φ) + β(sin φ∞ − sin φ) = 2 sin(δ/2) E(φ) with δ = φ − φ∞,
E = α sin φ_m − β cos φ_m, φ_m = (φ + φ∞)/2.  On J = [φ_S, φ∞] (φ∞ an arb ball, reached from
φ_S the way sg), :func:`foot_tail` proves:

1. t > 0 on [φ_S, φ∞): sin(δ/2) has the sign −sg there, so sg·E > 0 on J makes g_p < 0 with no
   zero before the pole; t is continuous there and tends to +∞ (|e − p| > 0: p is off the ellipse);
2. (C1): x − e(φ) lies along the outward normal, so e(φ) is the projection of x on the filled
   ellipse and d_s(x) = t; d_p(x) = t by the choice of t;
3. every other site k is farther: d_k − t ≥ ν·x − h_k(ν) − t = ν·e − h_k(ν) =: G_k(φ) > 0 on J —
   a point y: G_y = Δ g_y/|e'| by (1), so g_y > 0; a segment: both ends; an arc: its support
   bound (:func:`runtime.segments.certificate_tails.support_bound`); a piece of the same ellipse:
   its points e(ψ) have g = 1 − cos(ψ − φ) = 2 sin²((ψ − φ)/2), positive on a cover of its range;
   a piece of another ellipse: its whole ellipse's support ν·c' + |(ν·M', ν·N')|.
   A site on the asymptote's support line (G_k(φ∞) = 0) is not covered, nor a curve other than s
   ending at p (R2): a limit.

So every point of the open tail is equidistant from s and p and strictly nearer to them than to
any other site: it is the end of the edge beyond x(φ_S) (the finite part is proved by the edge's
pieces).

**The normal line at a point-site end e of piece s, outside** (the edge of e and s): x = e + τ ŵ,
ŵ the unit outward normal at e = e(ψ_e), τ > 0.  e is the projection of x on the filled ellipse
(d_s = τ = d_e), and d_k(x) ≥ ŵ·(e − y) + τ > τ for every other site whose points y all have
ŵ·y < ŵ·e (:func:`normal_ray_farther`: rationals for points and segments, balls for arcs, the
sin² form above for pieces of the same ellipse, the ellipse's support for others) — one test for
the whole ray.

Public API: :func:`frame_coords`, :func:`foot_poles`, :func:`foot_tail`, :func:`normal_ray_farther`.
"""
from __future__ import annotations

from fractions import Fraction

from flint import arb

from ..certify.foot import to_arb
from .certificate_ellipse_sites import same_ellipse
from .certificate_sites import ARC, ELLIPSE, POINT, SEGMENT, SiteTable
from .certificate_tails import pole_sectors, positive_on, support_bound
from .ellipse_pieces import piece_point_ball

__all__ = ["frame_coords", "foot_poles", "foot_tail", "normal_ray_farther"]

#: sub-intervals of another piece's parameter range in the sin² test
COVER = 16


def frame_coords(P, y) -> tuple:
    """(α, β), exact rationals, with y − c = α M + β N for piece P's frame."""
    (cx, cy), (Mx, My), (Nx, Ny) = P.c, P.M, P.N
    det = Fraction(Mx) * Ny - Fraction(My) * Nx
    wx, wy = Fraction(y[0]) - cx, Fraction(y[1]) - cy
    return (wx * Ny - wy * Nx) / det, (Mx * wy - My * wx) / det


def g_point(ab, phi):
    """g_y(φ) = 1 − α cos φ − β sin φ of (1), for the exact frame coordinates ``ab`` of y."""
    return 1 - to_arb(ab[0]) * phi.cos() - to_arb(ab[1]) * phi.sin()


def foot_poles(P, p) -> list:
    """The poles φ∞ (arb balls) of the foot curve of piece P and the point p inside the piece's
    open parameter range (module docstring), or [] (p not strictly outside the ellipse)."""
    al, be = frame_coords(P, p)
    r2 = al * al + be * be
    if not r2 > 1:
        return []
    a, b = to_arb(al), to_arb(be)
    phi_p = arb.atan2(b, a)
    w = (1 / to_arb(r2).sqrt()).acos()
    p0, p1 = P.arb_params()
    out = []
    for base in (phi_p + w, phi_p - w):
        for m in range(-2, 3):
            q = base + 2 * m * arb.pi()
            if q > p0 and q < p1:
                out.append(q)
    return out


def _normal_unit(P, phi):
    Mx, My, Nx, Ny = (to_arb(q) for q in (*P.M, *P.N))
    tx, ty = -phi.sin() * Mx + phi.cos() * Nx, -phi.sin() * My + phi.cos() * Ny
    ln = (tx * tx + ty * ty).sqrt()
    return ty / ln, -tx / ln


def _same_ellipse_farther(P, Q, phi_ball_fn, J) -> bool:
    """Every point e(ψ) of piece Q (same ellipse as P, ψ in a cover of its range) has
    g = 2 sin²((ψ − φ)/2) > 0 for φ over J (``phi_ball_fn``: the parameter of the touched point,
    a function of the ball K ⊆ J)."""
    q0, q1 = Q.arb_params()
    for m in range(COVER):
        Psi = q0 + (q1 - q0) * arb(m / COVER).union(arb((m + 1) / COVER))

        def g(K, Psi=Psi):
            h = ((Psi - phi_ball_fn(K)) / 2).sin()
            return h * h
        if not positive_on(g, J):
            return False
    return True


def _other_ellipse_gap(T: SiteTable, k: int, ux, uy, ex, ey):
    """ν·e − (ν·c' + |(ν·M', ν·N')|): the gap below the support of the whole ellipse of piece k."""
    s = T.sites[k]
    cx, cy, Mx, My, Nx, Ny = (to_arb(q) for q in (*s.c, *s.M, *s.N))
    um, un = ux * Mx + uy * My, ux * Nx + uy * Ny
    return ux * ex + uy * ey - (ux * cx + uy * cy + (um * um + un * un).sqrt())


def _site_farther(T: SiteTable, s: int, k: int, J) -> bool:
    """G_k > 0 on J for the foot curve of piece s (module docstring, 3)."""
    P = T.piece[s]
    if T.kind[k] in (POINT, SEGMENT):
        pts = [T.a[k]] if T.kind[k] == POINT else [T.a[k], T.b[k]]
        return all(positive_on(lambda K, ab=frame_coords(P, y): g_point(ab, K), J) for y in pts)
    if T.kind[k] == ELLIPSE and same_ellipse(T.sites[k], T.sites[s]):
        return _same_ellipse_farther(P, T.piece[k], lambda K: K, J)

    def G(K):
        ux, uy = _normal_unit(P, K)
        ex, ey = piece_point_ball(P, K)
        if T.kind[k] == ARC:
            return ux * ex + uy * ey - support_bound(T, k, ux, uy)
        if T.kind[k] == ELLIPSE:
            return _other_ellipse_gap(T, k, ux, uy, ex, ey)
        return arb("nan")
    return positive_on(G, J)


def foot_tail(T: SiteTable, c, p: int, theta_fin, pole, sg: int):
    """Prove the tail of the foot curve ``c`` (piece c.s, point p, σ = +1) from a start φ_S
    between ``theta_fin`` and the pole ``pole`` (reached the way sg) to the pole (module
    docstring, 1–3).  Returns (φ_S as a float, None) or (None, message); φ_S is where t first
    exceeds twice the scene's extent (then 4, 16, … times that) with all of it proved."""
    s = c.s
    if c.sigma != 1:
        return None, "the foot curve inside the ellipse does not reach infinity"
    for k in T.incident.get(p, ()):
        if k != s:
            return None, f"curve {k} ends at the point of the edge: its tail is not covered (R2)"
    P = T.piece[s]
    al, be = (to_arb(v) for v in frame_coords(P, T.a[p]))

    def E(K):
        m = (K + pole) / 2
        return sg * (al * m.sin() - be * m.cos())
    sites = [k for k in range(T.n) if k not in (s, p)]
    gap = float((pole - theta_fin).mid()) * sg
    if not gap > 0:
        return None, "its infinite end is not beyond its finite end"
    last = "t > 0 up to the pole"
    for th_s, J in pole_sectors(c.rho, pole, sg, gap, T.scale, 12):
        if not positive_on(E, J):
            last = "t > 0 up to the pole"
        else:
            bad = next((k for k in sites if not _site_farther(T, s, k, J)), None)
            if bad is None:
                return th_s, None
            last = f"site {bad} is not proved farther than its sites along the infinite end"
    return None, f"its infinite end is not proved ({last})"


def normal_ray_farther(T: SiteTable, s: int, code: int, u) -> str | None:
    """Every site other than piece s and its end ``code`` (a point site) lies strictly below the
    line through e = T.pt(code) perpendicular to the exact outward normal ``u`` there: the ray
    e + τ u, τ > 0, is on the edge of e and s (module docstring).  None, or a message."""
    e = T.pt(code)
    lx, ly = T.leaving(s, code)
    cx, cy = T.sites[s].c
    if u[0] * lx + u[1] * ly != 0 or not u[0] * (cx - e[0]) + u[1] * (cy - e[1]) < 0:
        return "its direction is not the outward normal of the piece at the end"
    for k in T.incident.get(code, ()):
        if k != s:
            return f"curve {k} ends at the end of the edge: its ray is not covered (R2)"
    level = u[0] * e[0] + u[1] * e[1]
    ua, ub = to_arb(u[0]), to_arb(u[1])
    nrm = (ua * ua + ub * ub).sqrt()
    ux, uy = ua / nrm, ub / nrm
    ex, ey = T.pt_arb(code)
    P = T.piece[s]
    which = T.which_end(s, code)
    psi = P.arb_params()[which]
    for k in range(T.n):
        if k in (s, code):
            continue
        if T.kind[k] in (POINT, SEGMENT):
            ok = all(u[0] * y[0] + u[1] * y[1] < level for y in ([T.a[k]] if T.kind[k] == POINT else [T.a[k], T.b[k]]))
        elif T.kind[k] == ARC:
            ok = bool(ux * ex + uy * ey - support_bound(T, k, ux, uy) > 0)
        elif T.kind[k] == ELLIPSE and same_ellipse(T.sites[k], T.sites[s]):
            ok = _same_ellipse_farther(P, T.piece[k], lambda K: psi, arb(0))
        elif T.kind[k] == ELLIPSE:
            ok = bool(_other_ellipse_gap(T, k, ux, uy, ex, ey) > 0)
        else:
            ok = False
        if not ok:
            return f"site {k} is not proved below the support line of the edge's infinite end"
    return None
