"""The unbounded end of a Voronoi edge between two unbounded sites (parabolas, hyperbolas).

Support functions do not exist for a parabola or a hyperbola, and far away their distances grow
like t·c(θ) (:mod:`runtime.voronoi.verify.far_accounting`) with corrections O(√t) (parabola) or
O(1) (hyperbola), so the tail argument of :func:`runtime.voronoi.verify.tail.prove_tail` is
redone with the enclosures of :class:`runtime.voronoi.verify.far_conics.FarConic`: on a cell
{q = m + t·u(θ) : 1/t ∈ [τ0, τ1], θ ∈ [θ0, θ1]} (τ0 = 0 included) q is proved outside the convex
side of the nearest branch of each of i, j, and ∇d_i = u(α_i), ∇d_j = u(α_j) with α in proved
angle intervals.  With f = d_i − d_j and the sector Σ = {t ≥ T, θ ∈ [θa, θb]} (T the link circle's
radius, :func:`runtime.voronoi.verify.tail_link.link_arc`):

(M) on every cell, σ·∂f/∂θ = σ·t·(sin(α_i − θ) − sin(α_j − θ)) > 0 (∂_θ d = t·∇d·u⊥);
(A) on every cell, every other site k is farther than d_i = d_j on β: a lower bound of d_k/t
    (half-planes containing S_k; t − |m − c| − ρ for a bounded site) above min of the upper bounds
    of d_i/t, d_j/t;
(R) on the rays θa, θb: σ·f < 0, resp. > 0, at t = T (distance bounds of the site table at the
    ray's point) and for all t ≥ T, because ∂f/∂t = cos(α_i − θ) − cos(α_j − θ) has that sign on
    τ-cells covering [0, 1/T].

Then on every circle t ≥ T in Σ, θ ↦ f is continuous, of opposite signs at the ends and strictly
monotone: one zero θ(t), continuous (implicit functions), closer to i, j than to every other
site; β ∩ Σ is one curve from the circle t = T to infinity, which starts between the link points
Q± (f of opposite signs there), on the chain's arc.  Chain ∪ tail is the whole edge.  For the
accounting, the interval J of :func:`runtime.voronoi.verify.far_accounting.lead_interval` inside
the open sector is returned.  Tails between an unbounded and a bounded site are reported not
proved (the bounded site's gradient far away would need the support-function enclosures of
:mod:`runtime.voronoi.verify.tail` combined with these).

The cells of a sector to infinity in (τ = 1/t, θ) (:func:`sector_grid`, :func:`halve_tau`,
:func:`quarter_cells`) are shared with the tails of bounded sites
(:func:`runtime.voronoi.verify.tail.prove_tail`): the same covering of Σ, down to τ = 0.

Public API: :func:`prove_conic_tail`, :func:`prove_sector`, :func:`monotone_in_theta`,
:func:`sector_grid`, :func:`halve_tau`, :func:`quarter_cells`, :data:`CONIC_TAIL_WORK`.
"""
from __future__ import annotations

import math

import numpy as np

from .far_accounting import asymptotic_direction, c_float, far_centre, lead_interval
from .far_conics import UNBOUNDED, FarConic, bounded_lower, cos_range, sin_range
from .tail_link import link_arc

__all__ = ["prove_conic_tail", "prove_sector", "monotone_in_theta", "sector_grid", "halve_tau", "quarter_cells",
           "CONIC_TAIL_WORK"]

#: cells per sector attempt
CONIC_TAIL_WORK = 200000


def prove_conic_tail(geoms, table, pair, link, scale, max_work: int = CONIC_TAIL_WORK):
    """(ok, message, J) for the tail of the edge of ``pair`` beyond ``link`` (module docstring;
    the arguments as for :func:`runtime.voronoi.verify.tail.prove_tail`)."""
    i, j = pair
    if geoms[i].kind not in UNBOUNDED or geoms[j].kind not in UNBOUNDED:
        return False, ("a tail between an unbounded and a bounded site is not proved (asymptotic "
                       "enclosures cover parabolas and hyperbolas only)"), None
    n = len(geoms)
    m = far_centre(geoms)
    fars = {k: FarConic(g, m) for k, g in enumerate(geoms) if g.kind in UNBOUNDED}
    ok, msg, phi_lo, phi_hi, r = link_arc(m, table, pair, link, scale)
    if not ok:
        return False, msg, None
    thX = 0.5 * (phi_lo + phi_hi)
    ths = asymptotic_direction(fars, n, i, j, thX)
    if ths is None:
        return False, "no direction where its two sites are the nearest far away", None
    ths = thX + ((ths - thX + math.pi) % (2 * math.pi)) - math.pi
    lo0, hi0 = min(ths, phi_lo), max(ths, phi_hi)
    msg = "no sector decided"
    for half in (0.02, 0.06, 0.15, 0.4):
        tha, thb = lo0 - half, hi0 + half
        ga = float(c_float(fars, i, tha) - c_float(fars, j, tha))
        gb = float(c_float(fars, i, thb) - c_float(fars, j, thb))
        if not ga * gb < 0:
            continue
        sigma = 1.0 if gb > 0 else -1.0        # σ·f > 0 on the ray θb: f/t → c_i − c_j
        ok, msg = prove_sector(geoms, fars, table, pair, tha, thb, sigma, r, m, scale, max_work)
        if ok:
            J = lead_interval(fars, n, i, j, ths, tha, thb)
            if J is None:
                return False, "no interval of directions around the asymptote where its sites are the nearest", None
            return True, None, J
    return False, msg, None


def monotone_in_theta(ai0, ai1, aj0, aj1, th0, th1, sigma):
    """(M): is σ(sin(α_i − θ) − sin(α_j − θ)) > 0 for all α_i ∈ [ai0, ai1], α_j ∈ [aj0, aj1],
    θ ∈ [th0, th1] (∂_θ(d_i − d_j) = t·(∇d_i − ∇d_j)·u⊥(θ), ∇d = u(α))?"""
    si = sin_range(ai0 - th1, ai1 - th0)
    sj = sin_range(aj0 - th1, aj1 - th0)
    return (si[0] - sj[1] > 0) if sigma > 0 else (si[1] - sj[0] < 0)


def sector_grid(tha, thb, tmax, nt: int = 8, nth: int = 8):
    """The first cells (τa, τb, θ0, θ1) of the sector {1/t ∈ [0, tmax], θ ∈ [θa, θb]}: nt × nth
    rectangles in (τ = 1/t, θ), τ = 0 (infinity) included, whose union is the whole sector (the
    last τ-row ends exactly at tmax, whatever the rounding of the grid)."""
    ta = np.repeat(np.linspace(0, tmax, nt + 1)[:-1], nth)
    tb = np.repeat(np.linspace(0, tmax, nt + 1)[1:], nth)
    tb[-nth:] = tmax
    e = np.linspace(tha, thb, nth + 1)
    return ta, tb, np.tile(e[:-1], nt), np.tile(e[1:], nt)


def halve_tau(T_a, T_b, bad):
    """The τ-intervals [T_a, T_b] of a ray where ``bad``, each cut at its midpoint (the two halves
    cover it): the lower halves first, then the upper ones."""
    a_, b_ = T_a[bad], T_b[bad]
    mid = 0.5 * (a_ + b_)
    return np.concatenate([a_, mid]), np.concatenate([mid, b_])


def quarter_cells(cells, bad, W=None):
    """The cells (τa, τb, θ0, θ1, extra arrays...) where ``bad``, cut: cells reaching infinity
    (τa = 0) in τ and θ, finite ones across their longer side (radial extent 1/τa − 1/τb against
    lateral extent (θ1 − θ0)/τa); the pieces cover each cell, and carry the cell's extra values.
    With ``W`` (the sites in a disc of radius W), the radial extent counts for min(1, 4W/t) of its
    length: far out the support bounds lose ~W·(lateral extent)/t across and only
    ~W²·(radial extent)/t² along the rays (:mod:`runtime.voronoi.verify.far_field`)."""
    a_, b_, c_, d_ = (x[bad] for x in cells[:4])
    extra = [x[bad] for x in cells[4:]]
    mt, mh = 0.5 * (a_ + b_), 0.5 * (c_ + d_)
    inf_ = a_ <= 0
    ta_f = np.where(inf_, np.inf, 1.0 / np.where(inf_, 1.0, a_))
    radial = 0.5 * (ta_f - 1.0 / b_)
    if W is not None:
        radial = radial * np.minimum(1.0, 4.0 * W * b_)
    lateral = ta_f * 0.5 * (d_ - c_)
    cut_t = inf_ | (radial >= lateral)
    cut_h = inf_ | (radial < lateral)
    parts = []
    for ct, ch in ((False, False), (True, False), (False, True), (True, True)):
        # quarter (ct, ch): upper τ half if ct, upper θ half if ch; kept when that cut is made
        sel = (cut_t | (not ct)) & (cut_h | (not ch))
        A0 = np.where(cut_t, np.where(ct, mt, a_), a_)
        B0 = np.where(cut_t, np.where(ct, b_, mt), b_)
        C0 = np.where(cut_h, np.where(ch, mh, c_), c_)
        D0 = np.where(cut_h, np.where(ch, d_, mh), d_)
        parts.append([A0[sel], B0[sel], C0[sel], D0[sel]] + [x[sel] for x in extra])
    return tuple(np.concatenate([p_[q] for p_ in parts]) for q in range(len(cells)))


def _third_lower(geoms, fars, m, others, t0, t1, a0, a1):
    """Lower bound of min_k d_k/t over the other sites on the cells."""
    lo = np.full(len(t0), np.inf)
    for k in others:
        g = geoms[k]
        if k in fars:
            val = fars[k].lower(t0, t1, a0, a1, tangents=(0.0, fars[k].p, -fars[k].p, 8 * fars[k].p,
                                                           -8 * fars[k].p) if g.kind == "parabola" else (0.0,))
        else:
            x0, y0, x1, y1 = g.bounding_box()
            c = (0.5 * (x0 + x1), 0.5 * (y0 + y1))
            rad = 0.5 * math.hypot(x1 - x0, y1 - y0)
            val = bounded_lower(m, c, rad, t1)
        lo = np.minimum(lo, val)
    return lo


def prove_sector(geoms, fars, table, pair, tha, thb, sigma, T, m, scale, max_work):
    """(R), (M), (A) of the module docstring on Σ = {t ≥ T, θ ∈ [θa, θb]}."""
    i, j = pair
    others = [k for k in range(len(geoms)) if k not in pair]
    tmax = 1.0 / T
    # ---- rays: the sign at t = T from the table, then the sign of ∂f/∂t on τ-cells
    for th, want in ((tha, -sigma), (thb, sigma)):
        Q = m + T * np.array([math.cos(th), math.sin(th)])
        V = table.evaluate(np.array([Q, Q]), [i, j])
        fl = 4e-12 * (scale + T)
        if not ((want > 0 and V.lo[0] - V.hi[1] > fl) or (want < 0 and V.hi[0] - V.lo[1] < -fl)):
            return False, f"the sign of d_{i} - d_{j} at the start of the ray at angle {th:.6g} is undecided"
        T_a, T_b = np.array([0.0]), np.array([tmax])
        work = 0
        while len(T_a):
            work += len(T_a)
            if work > max_work:
                return False, f"the sign of d_{i} - d_{j} on the ray at angle {th:.6g} is undecided"
            A = np.full(len(T_a), th)
            oki, li, hi_, _ = fars[i].gradient(T_a, T_b, A, A)
            okj, lj, hj, _ = fars[j].gradient(T_a, T_b, A, A)
            ci = cos_range(li - th, hi_ - th)
            cj = cos_range(lj - th, hj - th)
            d_lo, d_hi = ci[0] - cj[1], ci[1] - cj[0]          # ∂f/∂t = cos(α_i − θ) − cos(α_j − θ)
            good = oki & okj & ((d_lo > 0) if want > 0 else (d_hi < 0))
            bad = ~good
            if np.any(bad & (T_b - T_a < 1e-15 * tmax)):
                return False, f"the sign of d_{i} - d_{j} on the ray at angle {th:.6g} is undecided"
            T_a, T_b = halve_tau(T_a, T_b, bad)
    # ---- the sector: 2-D cells in (τ, θ)
    ta, tb, h0, h1 = sector_grid(tha, thb, tmax)
    work = 0
    while len(ta):
        work += len(ta)
        if work > max_work:
            k = int(np.argmax(tb))
            return False, (f"the tail is undecided near angle {0.5 * (h0[k] + h1[k]):.6g}, distance "
                           f"{1.0 / tb[k]:.6g} from the centre ({m[0]:.6g}, {m[1]:.6g})")
        oki, li, hi_, upi = fars[i].gradient(ta, tb, h0, h1)
        okj, lj, hj, upj = fars[j].gradient(ta, tb, h0, h1)
        okM = monotone_in_theta(li, hi_, lj, hj, h0, h1, sigma)
        # (A): the other sites farther than min(d_i, d_j) ≥ d_i = d_j on β
        okA = np.ones(len(ta), bool)
        if others:
            okA = _third_lower(geoms, fars, m, others, ta, tb, h0, h1) > np.minimum(upi, upj) * (1 + 1e-12)
        bad = ~(oki & okj & okM & okA)
        if not bad.any():
            return True, None
        ta, tb, h0, h1 = quarter_cells((ta, tb, h0, h1), bad)
    return True, None
