"""Unbounded edges in a direction where several different sites tie (shapes resting on one line).

Circles of several radii and ellipses resting on a common line ℓ (outer normal u: the line
y = −1 under the README's first example) all reach the largest support value h* = h_k(u) in the
direction u.  Their unbounded edges are parallel to u, and no sector of directions around u has
only two leading sites, so :mod:`runtime.voronoi.verify.tail` cannot prove them; when the shapes
are not mirror images, :mod:`runtime.voronoi.verify.mirror_tail` cannot either.  Here everything
is exact (rational): u is an axis or Pythagorean direction, and for each site k its support
point p_k(u) (lateral coordinate ℓ_k = p_k·u⊥) and support level, with rational bounds
ρ_k⁻ ≤ ρ ≤ ρ_k⁺ on its radii of curvature (a circle: its radius; an ellipse: b²/a and a²/b; a
point: 0).  Blaschke's rolling theorem (a convex body whose radii of curvature lie in
[ρ⁻, ρ⁺] contains the disc of radius ρ⁻ and lies in the disc of radius ρ⁺ tangent to it at
any boundary point, here p_k) gives, with z the height q·u − h* above ℓ and s = q·u⊥,

    F(ρ_k⁺, s − ℓ_k, z) ≤ d_k(q) ≤ F(ρ_k⁻, s − ℓ_k, z),   F(ρ, Δ, z) = √((z + ρ)² + Δ²) − ρ,

the upper bound for q beyond ℓ (outside the site).  For the edge (i, j), ℓ_i < ℓ_j laterally
consecutive among the tied sites, take the half-strip Π = {s ∈ [s_a, s_b], z ≥ z₀} with
ℓ_i < s_a < s_b < ℓ_j, as narrow around the chain's last rectangle as allows.  With z₀ large enough (computed below, exactly):

(S) d_i < d_j on the side s = s_a and d_i > d_j on s = s_b;
(M) ∂_s(d_i − d_j) > 0 on Π: ∂_s d_k = (s − p_s)/d_k with p the nearest point of site k, whose
    outward normal makes an angle φ ≤ φ_max with u (q is far beyond ℓ), so p lies within
    ρ_k⁺·φ_max of p_k(u) laterally; s − p_s > 0 for i and < 0 for j;
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
from fractions import Fraction

import numpy as np

from ...predicates.symmetry import site_centre, site_coefficients

__all__ = ["support_data", "prove_tied_tail", "DIRECTIONS"]

#: exact unit directions tried for a tie: the axes and a few Pythagorean directions
DIRECTIONS = sorted({(Fraction(sx * p, r), Fraction(sy * q, r))
                     for p, q, r in ((1, 0, 1), (0, 1, 1), (3, 4, 5), (4, 3, 5), (5, 12, 13), (12, 5, 13),
                                     (8, 15, 17), (15, 8, 17), (7, 24, 25), (24, 7, 25))
                     for sx in (1, -1) for sy in (1, -1)})


def _sqrt_rational(q: Fraction):
    if q < 0:
        return None
    n, d = q.numerator, q.denominator
    rn, rd = math.isqrt(n), math.isqrt(d)
    return Fraction(rn, rd) if rn * rn == n and rd * rd == d else None


def _up(x: float) -> Fraction:
    """A rational ≥ x (a relative margin far above the float's rounding)."""
    return Fraction(x * (1 + 1e-9) + 1e-300)


def _down(x: float) -> Fraction:
    return Fraction(max(x * (1 - 1e-9), 0.0))


def support_data(site, u):
    """(h, p, ρ⁻, ρ⁺) of a point, circle or ellipse in the exact unit direction u: the support
    level h = max_{q ∈ K} q·u, the support point p, rational bounds on the radii of curvature;
    None when they are not rational (an irrational radius or support point) or the kind differs."""
    co = site_coefficients(site)
    a, b, c, d, e, f = co
    ux, uy = u
    if hasattr(site, "r2") or (a == c and b == 0):
        cen = site_centre(site)
        if cen is None:
            return None
        r2 = cen[0] ** 2 + cen[1] ** 2 - f / a if a != 0 else None
        if r2 is None or r2 < 0:
            return None
        r = _sqrt_rational(r2)
        if r is None:
            return None
        return (cen[0] * ux + cen[1] * uy + r, (cen[0] + r * ux, cen[1] + r * uy), r, r)
    if 4 * a * c - b * b <= 0:
        return None                                   # not an ellipse
    cen = site_centre(site)
    # (v − cen)ᵀ M (v − cen) = κ with M = [[a, b/2], [b/2, c]] positive definite
    m11, m12, m22 = a, b / 2, c
    kappa = m11 * cen[0] ** 2 + 2 * m12 * cen[0] * cen[1] + m22 * cen[1] ** 2 - f
    if m11 < 0:
        m11, m12, m22, kappa = -m11, -m12, -m22, -kappa
    if kappa <= 0:
        return None
    det = m11 * m22 - m12 * m12
    i11, i12, i22 = m22 / det, -m12 / det, m11 / det        # M⁻¹
    w = (kappa * (i11 * ux + i12 * uy), kappa * (i12 * ux + i22 * uy))   # κ M⁻¹ u
    S = w[0] * ux + w[1] * uy
    rs = _sqrt_rational(S)
    if rs is None or rs <= 0:
        return None
    p = (cen[0] + w[0] / rs, cen[1] + w[1] / rs)
    lam = np.linalg.eigvalsh(np.array([[float(kappa * i11), float(kappa * i12)], [float(kappa * i12), float(kappa * i22)]]))
    amin, amax = math.sqrt(max(lam.min(), 0.0)), math.sqrt(lam.max())          # semi-axes
    return (cen[0] * ux + cen[1] * uy + rs, p, _down(amin * amin / amax), _up(amax * amax / amin))


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


def prove_tied_tail(sites, geoms, sup, pair, link, direction):
    """Prove the end of edge (i, j) beyond the chain's last rectangle ``link`` when i and j tie at
    infinity with other sites (module docstring).  ``direction``: a float direction of the edge
    going out (it orients the last segment of the chain, whose direction selects the exact u).  Returns (ok, message, end) with end = ((ux, uy), lateral) as the mirror tails."""
    d = np.asarray(direction, float)
    tv0 = np.asarray(link[1], float)                 # the chain's last segment, oriented outwards
    d = tv0 * (1.0 if float(tv0 @ d) >= 0 else -1.0)
    d = d / max(float(np.hypot(*d)), 1e-300)
    u = max(DIRECTIONS, key=lambda w: float(w[0]) * d[0] + float(w[1]) * d[1])
    if float(u[0]) * d[0] + float(u[1]) * d[1] < math.cos(0.05):
        return False, "no exact direction for the tie", None
    nvec = (-u[1], u[0])
    data = [support_data(s, u) for s in sites]
    i, j = pair
    if data[i] is None or data[j] is None or data[i][0] != data[j][0]:
        return False, "its sites do not tie exactly in that direction", None
    hstar = data[i][0]
    lat = lambda p: p[0] * nvec[0] + p[1] * nvec[1]                      # noqa: E731
    li, lj = lat(data[i][1]), lat(data[j][1])
    if li == lj:
        return False, "its sites touch the tie line at one point", None
    if li > lj:
        i, j, li, lj = j, i, lj, li
    gap = lj - li
    # the chain's last rectangle: lateral range inside the strip (sa, sb), caps on both sides of
    # the link; the strip is as narrow as that allows (the comparisons below take its worst points)
    P0, tv, nv, L, w, sx = link
    P0, tv, nv = np.asarray(P0, float), np.asarray(tv, float), np.asarray(nv, float)
    uf, nf = np.array([float(u[0]), float(u[1])]), np.array([float(nvec[0]), float(nvec[1])])
    corners = [P0 + a_ * tv + b_ * nv for a_ in (0.0, L) for b_ in (-w, w)]
    lats = [float(c @ nf) for c in corners]
    marg = 1e-9 * (1 + float(np.abs(P0).sum()) + L)
    sa = max(li + gap / 16, Fraction(min(lats)) - gap / 32)
    sb = min(lj - gap / 16, Fraction(max(lats)) + gap / 32)
    if not (min(lats) > float(sa) + marg and max(lats) < float(sb) - marg):
        return False, "the chain's last rectangle is not inside the tie's strip", None
    X = P0 + sx * tv
    zX = float(X @ uf) - float(hstar)
    cap_z = [float((P0 + a_ * tv) @ uf) - float(hstar) for a_ in (0.0, L)]
    sw = w * abs(float(nv @ uf)) + marg                                   # the caps' tilt
    if not (min(cap_z) + sw < zX < max(cap_z) - sw):
        return False, "the chain's last rectangle does not straddle the link", None
    z0 = Fraction(max(zX, 0.0)) * Fraction(999, 1000)
    if not z0 > 0:
        return False, "the link is not beyond the tie line", None
    # (M): the nearest points of i and j stay laterally within ρ⁺·φ_max of their support points;
    # tan φ ≤ (lateral distance from Π to the site) / z₀, the site within ρ_k of its centre
    def phi_max(k):
        cl = float(np.asarray(sup.cen[k], float) @ nf)
        rk = float(sup.rho[k]) * (1 + 1e-9) + 2 * float(sup.mu)
        off = max(abs(float(s_) - p_) for s_ in (sa, sb) for p_ in (cl - rk, cl + rk))
        return _up(off) / z0
    if not (sa - li > data[i][3] * phi_max(i) and lj - sb > data[j][3] * phi_max(j)):
        return False, "the edge's sites are not proved monotone across the strip", None
    # (S): the sides of the strip
    if not (_F_bounds_hold(data[j][3], lj - sa, data[i][2], sa - li, z0)
            and _F_bounds_hold(data[i][3], sb - li, data[j][2], lj - sb, z0)):
        return False, "the bisector is not proved to stay in the strip", None
    # (A): the other sites
    far_i, far_j = sb - li, lj - sa                                       # largest offsets in Π
    for k in range(len(sites)):
        if k in (i, j):
            continue
        dk = data[k]
        if dk is not None and dk[0] == hstar:
            lk = lat(dk[1])
            if lk < li:        # left of i: farther than i
                ok = _F_bounds_hold(dk[3], sa - lk, data[i][2], far_i, z0) if sa - lk > far_i else False
            elif lk > lj:
                ok = _F_bounds_hold(dk[3], lk - sb, data[j][2], far_j, z0) if lk - sb > far_j else False
            else:
                ok = False     # a tied site between i and j: they are not consecutive
            if not ok:
                return False, f"site {k}, tied with its sites at infinity, is not proved farther", None
            continue
        hk = _up(float(sup.h(k, math.atan2(float(u[1]), float(u[0]))) + float(np.asarray(sup.m) @ uf)) + 2 * sup.mu)
        g = hstar - hk
        D = max(far_i, far_j)
        if not (g > 0 and g > D * D / (2 * z0)):
            return False, f"site {k} is not proved farther beyond the link", None
    return True, None, ((u[0], u[1]), float((li + lj) / 2))
