"""Unbounded edges in a direction where several different sites tie (shapes resting on one line).

Circles of several radii and ellipses resting on a common line ℓ (outer normal u: the line
y = −1 under the README's first example) all reach the largest support value h* = h_k(u) in the
direction u.  Their unbounded edges are parallel to u, and no sector of directions around u has
only two leading sites, so :mod:`runtime.voronoi.verify.tail` cannot prove them; when the shapes
are not mirror images, :mod:`runtime.voronoi.verify.mirror_tail` cannot either; nor can it
prove translates of one rotated ellipse on a grid, tied in the axis directions.  Here everything
is exact: u is an axis or Pythagorean direction, and for each site k its support level
h_k(u) = c_k·u + √S_k (c_k, S_k rational; two levels are compared exactly by :func:`same_level`),
its support point p_k(u) with lateral coordinate ℓ_k = p_k·u⊥ enclosed in a rational interval
(a point when √S_k is rational; below, every inequality takes the worst end), with rational bounds
ρ_k⁻ ≤ ρ ≤ ρ_k⁺ on its radii of curvature (a circle: its radius; an ellipse: b²/a and a²/b; a
point: 0).  Blaschke's rolling theorem (a convex body whose radii of curvature lie in
[ρ⁻, ρ⁺] contains the disc of radius ρ⁻ and lies in the disc of radius ρ⁺ tangent to it at
any boundary point, here p_k) gives, with z the height q·u − h* above ℓ and s = q·u⊥,

    F(ρ_k⁺, s − ℓ_k, z) ≤ d_k(q) ≤ F(ρ_k⁻, s − ℓ_k, z),   F(ρ, Δ, z) = √((z + ρ)² + Δ²) − ρ,

the upper bound for q beyond ℓ (outside the site).  For the edge (i, j), ℓ_i < ℓ_j laterally
consecutive among the tied sites, take the half-strip Π = {s ∈ [s_a, s_b], z ≥ z₀} with
ℓ_i < s_a < s_b < ℓ_j, as narrow around the chain's last rectangle as allows.  With z₀ large enough (computed below, exactly):

(S) d_i < d_j on the side s = s_a and d_i > d_j on s = s_b;
(M) ∂_s(d_i − d_j) > 0 on Π: ∂_s d_k = (s − p_s)/d_k = sin φ with p the nearest point of site k
    and φ the angle of its outward normal n(φ) = cos φ·u + sin φ·u⊥ from u, |φ| < π/2 since
    (q − p)·u ≥ z > 0.  Along the boundary, parametrised by the normal's angle,
    p_s(φ) − ℓ_k = ∫₀^φ ρ_k(ψ) cos ψ dψ has the sign of φ (or is 0: a point), and so has
    s − p_s = d_k·sin φ; hence s − ℓ_k = (s − p_s) + (p_s − ℓ_k) has the sign of φ, and s > ℓ_i
    gives ∂_s d_i > 0, s < ℓ_j gives ∂_s d_j < 0 (Π lies strictly between ℓ_i and ℓ_j);
(A) every other site k is farther than the one of i, j on its side: a tied one by the same
    disc bounds (F(ρ_k⁺, ·) > F(ρ_m⁻, ·)), another by its support level h_k(u) < h*
    (d_k ≥ z + h* − h_k(u), while d_m ≤ z + D²/(2z)).

Then β_ij ∩ Π is one curve s(z), z ≥ z₀, to infinity, and closer to i, j than to any other site.
The inequalities between values of F are decided through F(ρ, Δ, z) = z + Δ²/(2(z + ρ)) − E,
0 ≤ E ≤ Δ⁴/(8(z + ρ)³), at the worst s of the interval and for all z ≥ z₀ (each is affine or
monotone in z once multiplied out).  The link with the chain of strips: the chain's last
rectangle lies within the lateral range (s_a, s_b), above z₀, and its caps lie on both sides of
the cross-section through the link point, so the chain's arc crosses that cross-section, where
β has its only point in Π: the chain and the tail join.

Public API: :func:`support_data`, :func:`prove_tied_tail`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction
from typing import NamedTuple

import numpy as np

from .support_balls import site_quadratic

__all__ = ["Support", "support_data", "same_level", "prove_tied_tail", "DIRECTIONS"]

#: exact unit directions tried for a tie: the axes and a few Pythagorean directions
DIRECTIONS = sorted({(Fraction(sx * p, r), Fraction(sy * q, r))
                     for p, q, r in ((1, 0, 1), (0, 1, 1), (3, 4, 5), (4, 3, 5), (5, 12, 13), (12, 5, 13),
                                     (8, 15, 17), (15, 8, 17), (7, 24, 25), (24, 7, 25))
                     for sx in (1, -1) for sy in (1, -1)})


def _sqrt_bounds(q: Fraction, bits: int = 160) -> tuple[Fraction, Fraction]:
    """Rationals lo ≤ √q ≤ hi (q ≥ 0), equal when q is the square of a rational, else
    hi − lo = 1/(den(q)·2^bits) (integer square roots: √(n/d) = √(n·d)/d)."""
    n, d = q.numerator, q.denominator
    rn, rd = math.isqrt(n), math.isqrt(d)
    if rn * rn == n and rd * rd == d:
        return Fraction(rn, rd), Fraction(rn, rd)
    scale = 1 << bits
    r = math.isqrt(n * d * scale * scale)
    return Fraction(r, d * scale), Fraction(r + 1, d * scale)


@dataclass(frozen=True)
class Support:
    """The exact support data of a point, circle or ellipse in a rational unit direction u:
    h(u) = c·u + √S and p(u) = c + w/√S with c, w rational and S ≥ 0 rational (κ M⁻¹u and
    S = uᵀκM⁻¹u for the ellipse (v − c)ᵀM(v − c) = κ; w = r²u, S = r² for a circle; w = 0, S = 0
    for a point), and rational bounds ρ⁻ ≤ ρ ≤ ρ⁺ on the radii of curvature.  √S is irrational
    for most rotated ellipses and circles of irrational radius: levels are compared exactly
    (:func:`same_level`), lateral coordinates through rational enclosures (:meth:`lateral`)."""
    cu: Fraction
    S: Fraction
    cen: tuple
    w: tuple
    rho_lo: Fraction
    rho_hi: Fraction

    def level(self) -> tuple[Fraction, Fraction]:
        """Rational bounds on h(u)."""
        lo, hi = _sqrt_bounds(self.S)
        return self.cu + lo, self.cu + hi

    def lateral(self, nvec) -> tuple[Fraction, Fraction]:
        """Rational bounds on p(u)·n (equal when √S is rational)."""
        cn = self.cen[0] * nvec[0] + self.cen[1] * nvec[1]
        wn = self.w[0] * nvec[0] + self.w[1] * nvec[1]
        if wn == 0:
            return cn, cn
        lo, hi = _sqrt_bounds(self.S)
        a, b = wn / hi, wn / lo
        return (cn + a, cn + b) if wn > 0 else (cn + b, cn + a)


def same_level(a: Support, b: Support) -> bool:
    """Is a.cu + √a.S = b.cu + √b.S, decided exactly?  With d = b.cu − a.cu the equation reads
    √x − √y = d for (x, y) = (a.S, b.S) (or, d < 0, the same with the roles swapped); squaring
    once, √y = (x − y − d²)/(2d) ≥ 0 and y = ((x − y − d²)/(2d))², both rational tests."""
    d = b.cu - a.cu
    x, y = a.S, b.S
    if d == 0:
        return x == y
    if d < 0:
        d, x, y = -d, y, x
    t = (x - y - d * d) / (2 * d)
    return t >= 0 and t * t == y


def _up(x: float) -> Fraction:
    """A rational ≥ x (a relative margin far above the float's rounding)."""
    return Fraction(x + abs(x) * 1e-9 + 1e-300)


def _down(x: float) -> Fraction:
    return Fraction(max(x * (1 - 1e-9), 0.0))


def support_data(site, u) -> Support | None:
    """The :class:`Support` of a point, circle or ellipse in the exact unit direction u; None
    for other kinds or a degenerate conic."""
    quad = site_quadratic(site)          # h(u) = c·u + √(uᵀQu), Q = κM⁻¹ (r²I for a circle)
    if quad is None:
        return None
    cen, (q11, q12, q22), circle = quad
    ux, uy = u
    if circle:
        rlo, rhi = _sqrt_bounds(q11)
        return Support(cen[0] * ux + cen[1] * uy, q11, cen, (q11 * ux, q11 * uy), rlo, rhi)
    w = (q11 * ux + q12 * uy, q12 * ux + q22 * uy)           # Q u
    S = w[0] * ux + w[1] * uy
    if S <= 0:
        return None
    lam = np.linalg.eigvalsh(np.array([[float(q11), float(q12)], [float(q12), float(q22)]]))
    amin, amax = math.sqrt(max(lam.min(), 0.0)), math.sqrt(lam.max())          # semi-axes
    return Support(cen[0] * ux + cen[1] * uy, S, cen, w, _down(amin * amin / amax), _up(amax * amax / amin))


def _F_bounds_hold(rho_far, dfar, rho_near, dnear, z0):
    """Is F(ρ_far, Δ, z) > F(ρ_near, δ, z) for every z ≥ z0 and every pair (Δ, δ) with
    |Δ| ≥ dfar and |δ| ≤ dnear (dfar > dnear ≥ 0)?  Using F(ρ, Δ, z) ≥ z + Δ²/(2(z+ρ)) − Δ⁴/(8(z+ρ)³)
    on the left (at its smallest |Δ|, where it is smallest for z ≥ z0 ≥ Δ: F grows with |Δ|) and
    F ≤ z + δ²/(2(z+ρ)) on the right, multiplied by 2(z+ρ_far)(z+ρ_near):
    (Δ² − δ²)·z + Δ²ρ_near − δ²ρ_far − Δ⁴(z + ρ_near)/(4(z + ρ_far)²) > 0; the first two terms grow
    with z and the last is at most Δ⁴/(4 z)·(1 + ρ_near/z), so the value at z0 with those bounds
    decides."""
    D2, d2 = dfar * dfar, dnear * dnear
    if not (D2 > d2 and z0 > 0):
        return False
    # F(ρ, ·, z) grows with |Δ|: the left side is smallest at |Δ| = dfar, the right largest at dnear
    val = (D2 - d2) * z0 + D2 * rho_near - d2 * rho_far - D2 * D2 * (z0 + rho_near) / (4 * z0 * z0)
    return val > 0 and (D2 - d2) - D2 * D2 / (4 * z0 * z0) > 0


class _Tie(NamedTuple):
    """The edge's tie in the exact direction u (n = u⊥): its sites i, j ordered laterally, their
    :class:`Support` data (``data``, filled where needed), the enclosures [li0, li] ∋ ℓ_i and
    [lj, lj1] ∋ ℓ_j, the lower bound of h* and the half-strip Π = {s ∈ [sa, sb], z ≥ z0}."""
    u: tuple
    nvec: tuple
    data: dict
    i: int
    j: int
    li0: Fraction
    li: Fraction
    lj: Fraction
    lj1: Fraction
    hstar_lo: Fraction
    sa: Fraction
    sb: Fraction
    z0: Fraction


def _exact_direction(link, direction):
    """The exact direction of :data:`DIRECTIONS` nearest the chain's last segment oriented along
    ``direction`` (within 0.05 rad), or None."""
    d = np.asarray(direction, float)
    tv0 = np.asarray(link[1], float)                 # the chain's last segment, oriented outwards
    d = tv0 * (1.0 if float(tv0 @ d) >= 0 else -1.0)
    d = d / max(float(np.hypot(*d)), 1e-300)
    u = max(DIRECTIONS, key=lambda w: float(w[0]) * d[0] + float(w[1]) * d[1])
    if float(u[0]) * d[0] + float(u[1]) * d[1] < math.cos(0.05):
        return None
    return u


def _strip(link, u, nvec, li, lj, hstar):
    """(sa, sb, z0) of the half-strip Π, or a message: the chain's last rectangle lies within the
    lateral range (sa, sb) ⊂ (ℓ_i, ℓ_j), as narrow as that allows (the comparisons take its worst
    points), its caps on both sides of the link's cross-section, and z0 below the link, above ℓ."""
    gap = lj - li            # the smallest possible gap between the support points
    P0, tv, nv, L, w, sx = link
    P0, tv, nv = np.asarray(P0, float), np.asarray(tv, float), np.asarray(nv, float)
    uf, nf = np.array([float(u[0]), float(u[1])]), np.array([float(nvec[0]), float(nvec[1])])
    corners = [P0 + a_ * tv + b_ * nv for a_ in (0.0, L) for b_ in (-w, w)]
    lats = [float(c @ nf) for c in corners]
    marg = 1e-9 * (1 + float(np.abs(P0).sum()) + L)
    sa = max(li + gap / 16, Fraction(min(lats)) - gap / 32)
    sb = min(lj - gap / 16, Fraction(max(lats)) + gap / 32)
    if not (min(lats) > float(sa) + marg and max(lats) < float(sb) - marg):
        return "the chain's last rectangle is not inside the tie's strip"
    X = P0 + sx * tv
    zX = float(X @ uf) - hstar
    cap_z = [float((P0 + a_ * tv) @ uf) - hstar for a_ in (0.0, L)]
    sw = w * abs(float(nv @ uf)) + marg                                   # the caps' tilt
    if not (min(cap_z) + sw < zX < max(cap_z) - sw):
        return "the chain's last rectangle does not straddle the link"
    z0 = Fraction(max(zX, 0.0)) * Fraction(999, 1000)
    if not z0 > 0:
        return "the link is not beyond the tie line"
    return sa, sb, z0


def _monotone_across(tie):
    """(M): ∂_s d_i > 0 and ∂_s d_j < 0 on Π exactly when Π lies strictly between the support
    points' lateral coordinates, ℓ_i < s_a and s_b < ℓ_j, at the enclosures' worst ends (module
    docstring: s − p_s has the sign of s − ℓ_k for every convex site seen from beyond ℓ)."""
    return tie.sa > tie.li and tie.sb < tie.lj


def _bisector_in_strip(tie):
    """(S): d_i < d_j on the side s = sa and d_i > d_j on s = sb (far offsets at their smallest,
    near offsets at their largest, :func:`_F_bounds_hold`)."""
    di, dj = tie.data[tie.i], tie.data[tie.j]
    return (_F_bounds_hold(dj.rho_hi, tie.lj - tie.sa, di.rho_lo, tie.sa - tie.li0, tie.z0)
            and _F_bounds_hold(di.rho_hi, tie.sb - tie.li, dj.rho_lo, tie.lj1 - tie.sb, tie.z0))


def prove_tied_tail(sites, geoms, sup, pair, link, direction):
    """Prove the end of edge (i, j) beyond the chain's last rectangle ``link`` when i and j tie at
    infinity with other sites (module docstring).  ``direction``: a float direction of the edge
    going out (it orients the last segment of the chain, whose direction selects the exact u).  Returns (ok, message, end) with end = ((ux, uy), lateral) as the mirror tails."""
    u = _exact_direction(link, direction)
    if u is None:
        return False, "no exact direction for the tie", None
    nvec = (-u[1], u[0])
    data = dict.fromkeys(range(len(sites)))          # exact support data, computed where needed
    i, j = pair
    data[i], data[j] = support_data(sites[i], u), support_data(sites[j], u)
    if data[i] is None or data[j] is None or not same_level(data[i], data[j]):
        return False, "its sites do not tie exactly in that direction", None
    hstar_lo = data[i].level()[0]
    hstar = float(hstar_lo)
    # lateral coordinates of the support points: rational enclosures (exact when √S is rational);
    # below, each inequality takes the end of an enclosure that makes it hardest to satisfy
    (li0, li), (lj, lj1) = data[i].lateral(nvec), data[j].lateral(nvec)
    if not li < lj:
        (li0, li), (lj, lj1) = data[j].lateral(nvec), data[i].lateral(nvec)
        if not li < lj:
            return False, "its sites touch the tie line at one point or too close to order", None
        i, j = j, i
    strip = _strip(link, u, nvec, li, lj, hstar)
    if isinstance(strip, str):
        return False, strip, None
    tie = _Tie(u, nvec, data, i, j, li0, li, lj, lj1, hstar_lo, *strip)
    if not _monotone_across(tie):
        return False, "the edge's sites are not proved monotone across the strip", None
    if not _bisector_in_strip(tie):
        return False, "the bisector is not proved to stay in the strip", None
    msg = _others_farther(sites, sup, tie)
    if msg is not None:
        return False, msg, None
    return True, None, ((u[0], u[1]), float((li + lj) / 2))


def _others_farther(sites, sup, tie):
    """(A): the other sites.  A site k whose float support level is proved below
    T = h* − D²/(2z₀) is farther than i or j everywhere in Π (d_k ≥ z + h* − h_k(u) while
    d_m ≤ z + D²/(2z)); the others are decided one by one, exactly when they tie (a tied site
    outside [ℓ_i, ℓ_j] by :func:`_F_bounds_hold`).  Returns None (proved) or the message."""
    u, nvec, data, i, j, z0 = tie.u, tie.nvec, tie.data, tie.i, tie.j, tie.z0
    uf = np.array([float(u[0]), float(u[1])])
    far_i, far_j = tie.sb - tie.li0, tie.lj1 - tie.sa                     # largest offsets in Π
    D = max(far_i, far_j)
    T = tie.hstar_lo - D * D / (2 * z0)
    t_down = float(T)
    if Fraction(t_down) > T:
        t_down = math.nextafter(t_down, -math.inf)
    n = len(sites)
    hv = np.asarray(sup.h(np.arange(n), np.full(n, math.atan2(float(u[1]), float(u[0])))), float) \
        + float(np.asarray(sup.m) @ uf)
    mu2 = 2 * float(sup.mu)
    h_up = hv + (np.abs(hv) + mu2) * 1e-9 + mu2 + 1e-300        # ≥ h_k(u), float sums' rounding included
    below = h_up < t_down
    below[[i, j]] = True
    for k in np.nonzero(~below)[0].tolist():
        dk = support_data(sites[k], u)
        if dk is not None and same_level(dk, data[i]):
            lk0, lk1 = dk.lateral(nvec)
            if lk1 < tie.li0:        # left of i: farther than i
                ok = _F_bounds_hold(dk.rho_hi, tie.sa - lk1, data[i].rho_lo, far_i, z0) if tie.sa - lk1 > far_i else False
            elif lk0 > tie.lj1:
                ok = _F_bounds_hold(dk.rho_hi, lk0 - tie.sb, data[j].rho_lo, far_j, z0) if lk0 - tie.sb > far_j else False
            else:
                ok = False     # a tied site between i and j: they are not consecutive
            if not ok:
                return f"site {k}, tied with its sites at infinity, is not proved farther"
            continue
        return f"site {k} is not proved farther beyond the link"
    return None
