"""Second-order lower bounds of d_k − d_i on a disc, for the third-site tests of the verifier.

Far from the sites every gradient ∇d is nearly the same, and the margin by which a third site k
is farther than the pair (i, j) on β is small compared with the first-order loss of a disc of
radius R, R·(s_k + s_i) with s ≈ R/d (:func:`runtime.voronoi.verify.site_table.gradient_enclosure`).
The convexity of the distance to a convex set gives a bound whose loss is R²/(2d) instead
(:func:`gap_lower`); on the bisector β of i and j, d_k − d_i may be traded for
d_k − (1 + λ)d_i + λd_j with any λ, which removes the gradient along ∇(d_i − d_j) of a near-tie
(:func:`bisector_gap_lower`).  Used by (T2) of :mod:`runtime.voronoi.verify.strips` and (A) of
:mod:`runtime.voronoi.verify.tail`.
"""
from __future__ import annotations

import numpy as np

from ..geometry import EPS
from .site_table import SiteValues, gradient_enclosure

__all__ = ["convex_side", "gap_lower", "bisector_gap_lower"]


def convex_side(V: SiteValues, R):
    """Rows whose disc B(Q, R) lies outside the convex set K of the site (a hyperbola: of the
    branch nearest on the whole disc), where d = d_K is convex with ∇²d = ττᵀ/(d + ρ) ≤ ττᵀ/d
    (τ ⟂ ∇d, ρ ≥ 0 the radius of curvature at the foot; :func:`gap_lower`)."""
    R = np.broadcast_to(np.asarray(R, float), V.lo.shape)
    return V.base & (V.sep > R) & (V.lo > 2 * R)


def gap_lower(Q, Vk, Vi, R, scale):
    """A lower bound of d_k − d_i on the disc B(Q, R) (−inf where not proved), to second order.

    Outside a convex set K, d = d_K is convex and ∇d = (q − p)/d with p the projection; its
    Hessian (a.e.; d is C^{1,1} there) is (I − Dp − n nᵀ)/d with Dp symmetric, 0 ≤ Dp ≤ I and
    Dp·n = 0 (the projection's derivative), so 0 ≤ ∇²d ≤ 1/d.  Hence on the disc, with
    G ± s the point enclosures of the gradients at Q (:func:`gradient_enclosure`, radius 0):
    d_k(q) ≥ d_k(Q) + ∇d_k(Q)·(q − Q) (convex) and d_i(q) ≤ d_i(Q) + ∇d_i(Q)·(q − Q) +
    |q − Q|²/(2(lo_i − R)), so

        d_k − d_i ≥ lo_k − hi_i − R·(|G_k − G_i| + s_k + s_i) − R²/(2(lo_i − R)),

    the second-order term R²/(2d) in place of the first-order bound's R·(s_k + s_i) ≈ 4R²/d
    (:mod:`runtime.voronoi.verify.strips` (T2)), and the gradients at Q to 10⁻¹⁴ for ellipses."""
    Q = np.asarray(Q, float).reshape(-1, 2)
    R = np.broadcast_to(np.asarray(R, float), (len(Q),))
    out = np.full(len(Q), -np.inf)
    ok = convex_side(Vk, R) & convex_side(Vi, R)
    ok &= Vk.lo - Vi.hi > 0         # the bound is below lo_k − hi_i: the others need no gradients
    rows = np.nonzero(ok)[0]
    if not len(rows):
        return out
    Vk_, Vi_ = Vk.take(rows), Vi.take(rows)
    zero = np.zeros(len(rows))
    Gk, sk, vk = gradient_enclosure(Q[rows], Vk_, zero, scale)
    Gi, si, vi = gradient_enclosure(Q[rows], Vi_, zero, scale)
    Rr = R[rows]
    with np.errstate(divide="ignore", invalid="ignore"):
        first = (np.hypot(*(Gk - Gi).T) + sk + si) * (1 + 1e-12)
        second = Rr * Rr / (2 * (Vi_.lo - Rr)) * (1 + 1e-12)
        rnd = 2 * EPS * (np.abs(Vk_.lo) + np.abs(Vi_.hi))
        low = Vk_.lo - Vi_.hi - rnd - Rr * first * (1 + 1e-12) - second
    out[rows] = np.where(vk & vi & np.isfinite(low), low, -np.inf)
    return out


def bisector_gap_lower(Q, Vk, Vi, Vj, R, scale):
    """A lower bound of d_k − d_i on β ∩ B(Q, R), β = {d_i = d_j} (−inf where not proved).

    On β, d_k − d_i = g_λ := d_k − (1 + λ)·d_i + λ·d_j for every real λ; λ is taken (in floats:
    any value is sound) to cancel the component of ∇(d_k − d_i) along ∇(d_i − d_j), so that a
    third site whose bisector with i meets β at a small angle (a near-tie) leaves g_λ a small
    gradient on the disc.  With the coefficients c = (1, −(1 + λ), λ) of (d_k, d_i, d_j), the
    bounds at Q, the point enclosures G ± s of the gradients and 0 ≤ ∇²d ≤ 1/d outside each
    convex set (:func:`gap_lower`):

        g_λ ≥ Σ c·(lo or hi) − R·(|Σ c·G| + Σ |c|·s) − R²/2·Σ_{c < 0} |c|/(lo − R)

    on the whole disc, hence on β ∩ B(Q, R)."""
    Q = np.asarray(Q, float).reshape(-1, 2)
    R = np.broadcast_to(np.asarray(R, float), (len(Q),))
    out = np.full(len(Q), -np.inf)
    ok = convex_side(Vk, R) & convex_side(Vi, R) & convex_side(Vj, R)
    rows = np.nonzero(ok)[0]
    if not len(rows):
        return out
    Vk_, Vi_, Vj_ = Vk.take(rows), Vi.take(rows), Vj.take(rows)
    zero = np.zeros(len(rows))
    Gk, sk, vk = gradient_enclosure(Q[rows], Vk_, zero, scale)
    Gi, si, vi = gradient_enclosure(Q[rows], Vi_, zero, scale)
    Gj, sj, vj = gradient_enclosure(Q[rows], Vj_, zero, scale)
    Rr = R[rows]
    with np.errstate(divide="ignore", invalid="ignore"):
        Df = Gi - Gj
        lam = ((Gk - Gi) * Df).sum(1) / (Df * Df).sum(1)
        lam = np.clip(np.where(np.isfinite(lam), lam, 0.0), -1e3, 1e3)
        ci, cj = -(1.0 + lam), lam
        val = (Vk_.lo + np.where(ci < 0, ci * Vi_.hi, ci * Vi_.lo) + np.where(cj < 0, cj * Vj_.hi, cj * Vj_.lo))
        rnd = 8 * EPS * (np.abs(Vk_.lo) + (np.abs(ci) + 1) * (np.abs(Vi_.lo) + np.abs(Vi_.hi))
                         + (np.abs(cj) + 1) * (np.abs(Vj_.lo) + np.abs(Vj_.hi)))
        grad = Gk + ci[:, None] * Gi + cj[:, None] * Gj
        first = (np.hypot(*grad.T) + sk + np.abs(ci) * si + np.abs(cj) * sj) * (1 + 1e-12) + 8 * EPS * (1 + np.abs(lam))
        second = 0.5 * Rr * Rr * (np.where(ci < 0, -ci / (Vi_.lo - Rr), 0.0)
                                  + np.where(cj < 0, -cj / (Vj_.lo - Rr), 0.0)) * (1 + 1e-12)
        low = val - rnd - Rr * first * (1 + 1e-12) - second
    out[rows] = np.where(vk & vi & vj & np.isfinite(low), low, -np.inf)
    return out
