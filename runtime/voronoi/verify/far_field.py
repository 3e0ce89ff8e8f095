"""Distances far from bounded convex sites to first order in 1/t, through support functions
(thesis §1.2 on far regions; Schneider, *Convex Bodies*, §1.7).

Let S be a compact convex set in the disc D(m, W), h(θ) = max_{p ∈ S} u(θ)·(p − m) its support
function, h' its derivative (the lateral coordinate (p(θ) − m)·u⊥ of the support point p(θ)) and
M ≥ sup h'' (h + h'' = ρ(θ) ∈ [0, ρ_max], so M = ρ_max + W serves).  For q = m + t·u(θ), t > W:

* **lower bound**: d(q, S) = max_{|v| = 1} (v·(q − m) − h(v)) (q outside S; every supporting
  half-plane separates).  With v = u(θ + x), cos x ≥ 1 − x²/2 and h(θ + x) ≤ h(θ) + h'(θ)x + M x²/2,
  d ≥ t − h − h'x − (t + M)x²/2, and x = −h'/(t + M) gives

      d(q, S) − t ≥ −h(θ) + h'(θ)² / (2(t + M));

* **upper bound**: d ≤ |q − p(θ)| = √((t − h)² + h'²) ≤ t − h + h'²/(2(t − h)), t − h ≥ t − W:

      d(q, S) − t ≤ −h(θ) + h'(θ)² / (2(t − W)).

The two differ by O(W³/t²), while the zeroth-order bounds t − h ≤ d ≤ t − h + h'²/(2(t − W))
lose the whole term h'²/(2t).  Along the bisector of two sites i, j tied at infinity in the
direction θ* (lateral coordinates ℓ_i, ℓ_j of their support points), a third site k with
h_k(θ*) just below the tie is farther by (h_i − h_k)(θ*) + ((ℓ_k − s)² − (ℓ_i − s)²)/(2t) + O(1/t²)
(s the bisector's lateral offset): when the support gap (h_i − h_k)(θ*) is small against W²/t
over the range of t of a tail, only the first-order term proves k farther.

:func:`gap_lower` bounds d_k − d_s from below on a cell {m + t·u(θ) : t ∈ [t0, t1], |θ − θc| ≤ δ}
(t1 = ∞ allowed), with the support gap h_s − h_k enclosed on the cell to first order about θc
(|h_s'' − h_k''| ≤ M_s + M_k) or through |h'| ≤ W, whichever is larger; the float values of
:class:`runtime.voronoi.verify.support.SupportTable` carry its rounding margin μ.

Public API: :func:`gap_lower`, :func:`support_gap_lower`, :func:`slope_square`.
"""
from __future__ import annotations

import numpy as np

__all__ = ["gap_lower", "support_gap_lower", "slope_square"]


def _curv(sup, k):
    """M_k = ρ_k + W ≥ sup |h_k''| (h'' = ρ(θ) − h, |h| ≤ W)."""
    return sup.rcurv[np.asarray(k)] + sup.W


def slope_square(sup, k, thc, half):
    """(lo, hi) of h_k'(θ)² on [θc − δ, θc + δ] (|h_k''| ≤ M_k, the float h' within μ)."""
    p = np.abs(sup.hp(k, thc))
    r = _curv(sup, k) * np.asarray(half, float) * (1 + 1e-12) + sup.mu
    lo = np.maximum(p - r, 0.0)
    hi = p + r
    return lo * lo * (1 - 1e-12), hi * hi * (1 + 1e-12)


def support_gap_lower(sup, s, k, thc, half):
    """A lower bound of h_s − h_k on [θc − δ, θc + δ]: the larger of the difference of the
    enclosures of :meth:`runtime.voronoi.verify.support.SupportTable.h_range` and the expansion
    about θc, (h_s − h_k)(θc) − |h_s' − h_k'|(θc)·δ − (M_s + M_k)·δ²/2 (module docstring)."""
    half = np.asarray(half, float)
    hs, ps = sup.h_and_slope(s, thc)
    hk, pk = sup.h_and_slope(k, thc)
    mu = sup.mu
    first = (hs - hk) - (np.abs(ps - pk) + 2 * mu) * half * (1 + 1e-12) \
        - 0.5 * (_curv(sup, s) + _curv(sup, k)) * half * half * (1 + 1e-12) - 2 * mu \
        - 1e-15 * (np.abs(hs) + np.abs(hk))
    sep = sup.h_range(s, thc, half)[0] - sup.h_range(k, thc, half)[1]
    return np.maximum(first, sep)


def gap_lower(sup, s, k, thc, half, t0, t1):
    """A lower bound of d_k − d_s on the cell {m + t·u(θ) : t ∈ [t0, t1], |θ − θc| ≤ δ}
    (W < t0 ≤ t1 ≤ ∞): (h_s − h_k) + h_k'²/(2(t1 + M_k)) − h_s'²/(2(t0 − W)), each term at its
    worst on the cell (module docstring)."""
    t0 = np.asarray(t0, float)
    t1 = np.asarray(t1, float)
    W = sup.W
    ak = slope_square(sup, k, thc, half)[0]
    as_ = slope_square(sup, s, thc, half)[1]
    with np.errstate(divide="ignore", invalid="ignore"):
        gain = np.where(np.isfinite(t1), ak / (2.0 * (t1 + _curv(sup, k))), 0.0) * (1 - 1e-12)
    loss = as_ / (2.0 * (t0 - W)) * (1 + 1e-12)
    return support_gap_lower(sup, s, k, thc, half) + gain - loss
