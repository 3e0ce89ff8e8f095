"""The unbounded end of a Voronoi edge of bounded convex sites, to infinity (thesis §1.2).

**Unbounded edges** (:func:`prove_tail`).  The chain of strips (:mod:`runtime.voronoi.verify.strips`)
proves the edge from its vertex up to a polyline point at about ``TAIL_CUT`` times the scene's
radius (:mod:`runtime.voronoi.verify.curved`); beyond, support functions
(thesis §1.2 on far regions; Schneider, *Convex Bodies*, §1.7) take over.  Let every site lie
in the disc D(m, W) and h_S(θ) = max_{p ∈ S} u(θ)·(p − m)
(:class:`runtime.voronoi.verify.support.SupportTable`, the formula of
:func:`runtime.interval.bound.support_function`).  For q = m + t·u, t > W:

* d(q, S) ≥ t − h_S(u) (the supporting line of conv S with normal u separates q from S);
* d(q, S) ≤ |q − p_u| = √((t − h)² + h'(θ)²) ≤ t − h_S(u) + h_S'(θ)²/(2(t − W)), p_u the support
  point, whose component across u is h'(θ) (so e_S := d − (t − h_S) ∈ [0, h'²/(2(t − W))]);
* for the gradient, ∇d_S(q) = (q − p)/|q − p| with p the nearest point, the support point of the
  normal direction ν, |ν − u| ≤ α = asin(W/(t − W)); the support point moves by at most ρ_S·|Δθ|
  (ρ_S the largest radius of curvature: a²/b, r, 0), and h_S + h_S'' = ρ_S(θ) ∈ [0, ρ_S], so
  t·∂_θ d_S = −κ_S·(p − m)·u⊥ with κ_S = t/|q − p| ∈ [1/(1 + W/t), 1/(1 − W/t)] and
  (p − m)·u⊥ ∈ h_S'(θ_c) ± (ρ_S(α + δ) + W·δ) on an angular cell of half-width δ.

m is moved, for the tail of (i, j), onto the normal line of p_i at the float asymptotic direction
θ* (a zero of g = h_i − h_j where i, j lead), so that h_i' ≈ 0 and the bound on e_i is sharp.
On the sector Σ = {t ≥ T, θ ∈ [θa, θb]} ∋ θ*, with f = d_i − d_j ∈ [−g − e_j, −g + e_i], cells in
(τ = 1/t, θ) (τ = 0 included, so Σ is covered to infinity), each halved until it satisfies

(F) f has one strict sign on the cell (β does not meet it; also to first order in 1/t,
    :func:`runtime.voronoi.verify.far_field.gap_lower`), or
(A)+(M) every other site k is farther than d_i = d_j on the cell (d_k − d_s > 0 for s = i or j to
    first order in 1/t, :func:`runtime.voronoi.verify.far_field.gap_lower`, which keeps the term
    h_k'²/(2t) that max(h_i − e_i, h_j − e_j) > h_k drops: near-ties at infinity need it,
    or the distance bounds on the cell's disc as in (T2), or to first order
    d_k − d_i ≥ lo_k(C) − hi_i(C) − R·(|G_k − G_i| + s_k + s_i) with the gradient enclosures, or
    to second order, :func:`runtime.voronoi.verify.distance_gap.gap_lower`, or on β only,
    :func:`runtime.voronoi.verify.distance_gap.bisector_gap_lower`) and
    σ·∂f/∂θ > 0 on it (the enclosure above, or the gradient enclosures on the cell's disc);

and on the rays θa, θb: σ·f < 0, resp. > 0, for all t ≥ T (τ-intervals, same bounds).  Then on
every circle t = const ≥ T, θ ↦ f is negative then positive (σ = 1) with all its zeros in (M)
cells, where it strictly increases: exactly one zero θ(t), continuous (implicit functions).  So
β ∩ Σ is one curve from the circle t = T to infinity, closer to i, j than to every other site,
with the asymptotic direction in the sector.  **Link**: two points Q± of the circle t = T inside
the chain's last rectangle (shrunk by the arc's sagitta), with f(Q−), f(Q+) of opposite proved
signs, bracket θ(T): the curve starts inside that rectangle, on the chain's arc (β meets the
rectangle in one arc, all proved).  Hence chain ∪ tail is the whole edge from its vertex to
infinity.  For the accounting of ends at infinity, :func:`prove_tail` also returns an interval
J = [α, β] ∋ θ* inside the sector on which only i and j attain max_k h_k and g has strict opposite
signs at α and β.  Not proved (reported): tails whose chain does not reach T > 2W, a lead of i, j
too narrow for the 4096-direction scan, cells undecided within the work limit.  A vertex-less
edge has two tails, one per end of its chain.

Distance values come from :class:`runtime.voronoi.verify.site_table.SiteTable`, one call for all
third sites of a round of cells.

Length: one sector argument (rays, cells, their (F), (A), (M) tests in floats and, within the
rounding margin, in balls, and the lead interval J) whose steps share the cell records
(:class:`_Sector`, :class:`_Cells`, :class:`_PairValues`).
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ...certify.cell_cover import cell_balls, halve
from .conic_tail import halve_tau, prove_conic_tail, quarter_cells, sector_grid
from .distance_gap import bisector_gap_lower, gap_lower
from . import far_field
from .support_balls import SupportBalls
from .site_table import gradient_enclosure
from . import strips
from .strips import evaluate_rows, gap_rows
from .tail_link import link_arc

__all__ = ["prove_tail", "TAIL_WORK", "TAIL_WORK_MORE", "MORE_TAILS"]

#: cells per sector attempt of :func:`prove_tail`; a tail left undecided within it is tried once
#: more with TAIL_WORK_MORE, at most MORE_TAILS tails per diagram (measured on 512 random ellipses:
#: two tails next to far vertices, 10³–10⁴ scene units out, are proved with 600000, and with them
#: the accounting of the ends at infinity; each such retry cost about 3 s on 2000 ellipses)
TAIL_WORK = 60000
TAIL_WORK_MORE = 600000
MORE_TAILS = 2
#: at most this many undecided cells of a round are retried in balls (support_balls), each with at
#: most BALL_SITES third sites within the float rounding margin
BALL_CELLS = 256
BALL_SITES = 8
#: ball evaluations per sector at most (a tie closer than the float directions can resolve is
#: left undecided soon rather than after many rounds of cells at the float resolution)
BALL_BUDGET = 4000


def _imul(a0, a1, b0, b1):
    """Interval product [a0, a1]·[b0, b1] (float; callers add their own margins)."""
    p = np.stack([a0 * b0, a0 * b1, a1 * b0, a1 * b1])
    return p.min(0), p.max(0)


def _arc_dot(V, tha, thb):
    """(min, max) over θ ∈ [θa, θb] (θb − θa < π) of u(θ)·v for the rows v of V (float)."""
    ea = np.cos(tha) * V[:, 0] + np.sin(tha) * V[:, 1]
    eb = np.cos(thb) * V[:, 0] + np.sin(thb) * V[:, 1]
    nv = np.hypot(V[:, 0], V[:, 1])
    phi = np.arctan2(V[:, 1], V[:, 0])
    inside = ((phi - tha) % (2 * math.pi)) <= thb - tha
    opposite = ((phi + math.pi - tha) % (2 * math.pi)) <= thb - tha
    lo = np.where(opposite, -nv, np.minimum(ea, eb))
    hi = np.where(inside, nv, np.maximum(ea, eb))
    return lo, hi


def _eps1(hp_abs, W, t0):
    """h'²/(2(t0 − W)): d(m + t·u, S) − (t − h_S(u)) ∈ [0, this] when |h_S'(u)| ≤ hp_abs, t ≥ t0 > W."""
    return hp_abs * hp_abs / (2.0 * (t0 - W)) * (1 + 1e-12)


def prove_tail(sup, table, pair, link, scale, max_work: int = TAIL_WORK):
    """Prove the unbounded end of the edge (i, j) beyond the link point (module docstring,
    *Unbounded edges*).

    ``link`` = (P0, t, n, L, w, s_x): the chain's last rectangle {P0 + s·t + λ·n : s ∈ [0, L],
    |λ| ≤ w} (proved: β meets it in one arc, all of it closer to i, j than to other sites) and
    the position s_x on its axis where the link circle crosses it.  Returns (ok, message, J)
    with J = (α, β, σ): the interval of directions for the accounting (module docstring)."""
    i, j = pair
    if not sup.ok:
        # a parabola or a hyperbola among the sites: asymptotic enclosures instead of support functions
        return prove_conic_tail(sup.geoms, table, pair, link, scale, max_work)
    m, W = sup.m, sup.W
    P0, tv, nv, L, w, sx = link
    X = np.asarray(P0, float) + sx * np.asarray(tv, float)
    r = float(math.hypot(X[0] - m[0], X[1] - m[1]))
    if not r > 2.0 * W:
        return False, "the proved part does not reach far enough for the tail argument", None
    thX = math.atan2(X[1] - m[1], X[0] - m[0])
    # ---- the asymptotic direction: a zero of g = h_i − h_j where i, j are the two largest
    ths = sup.lead_direction(i, j, thX)
    if ths is None:
        return False, "no direction where its two sites lead the support functions", None
    # centre on the normal line of site i's support point in the asymptotic direction: there
    # h_i' ≈ 0, which makes the upper bound d_i ≤ t − h_i + h_i'²/(2(t − W)) sharp (module docstring)
    m = m + float(sup.hp(i, ths)) * np.array([-math.sin(ths), math.cos(ths)])
    sup = sup.recentred(m)
    W = sup.W
    r = float(math.hypot(X[0] - m[0], X[1] - m[1]))
    if not r > 2.0 * W:
        return False, "the proved part does not reach far enough for the tail argument", None
    thX = math.atan2(X[1] - m[1], X[0] - m[0])
    ths = thX + ((ths - thX + math.pi) % (2 * math.pi)) - math.pi     # same branch as thX
    # ---- the link: two points of the circle |q − m| = r inside the rectangle, near its two
    # lateral sides (where the chain proved f's signs), with f of opposite signs
    ok, msg, phi_lo, phi_hi, r = link_arc(m, table, pair, link, scale)
    if not ok:
        return False, msg, None
    dl = 0.5 * (phi_hi - phi_lo)
    thX = 0.5 * (phi_lo + phi_hi)
    msg = "no sector decided"
    lo0, hi0 = min(ths, thX - dl), max(ths, thX + dl)
    for half in (0.005, 0.02, 0.06, 0.15, 0.4):
        tha, thb = lo0 - half, hi0 + half
        gb = float(sup.h(i, thb) - sup.h(j, thb))
        ga = float(sup.h(i, tha) - sup.h(j, tha))
        if not (gb * ga < 0):
            continue
        sigma = -1.0 if gb > 0 else 1.0          # σ·f > 0 on the ray θb, f ≈ −g far away
        ok, msg = _prove_sector(sup, table, pair, tha, thb, sigma, r, scale, max_work)
        if ok:
            J = _lead_interval(sup, i, j, ths, tha, thb)
            if J is None:
                return False, "no interval of directions around the asymptote where its sites lead", None
            return True, None, J
    return False, msg, None


def _lead_interval(sup, i, j, ths, tha, thb):
    """An interval J = [α, β] ⊂ (θa, θb) around the float asymptotic direction ths on which only
    i and j attain max_k h_k and h_i − h_j has strict opposite signs at α and β (for the
    accounting of :func:`runtime.voronoi.verify.closure.verify_accounting_conics`), or None.
    Within the float rounding margin the signs and the comparisons are taken in balls
    (:mod:`runtime.voronoi.verify.support_balls`: near-ties at infinity, whose lead intervals are
    narrower than the float margin allows)."""
    mu = sup.mu
    others = np.array([k for k in range(sup.n) if k not in (i, j)], int)
    balls = SupportBalls(sup)
    for eta in (1e-3, 1e-5, 1e-7, 1e-9, 1e-11, 1e-13, 1e-14):
        a, b = ths - eta, ths + eta
        if not (tha < a and b < thb):
            continue
        ga = float(sup.h(i, a) - sup.h(j, a))
        gb = float(sup.h(i, b) - sup.h(j, b))
        if not (ga * gb < 0 and min(abs(ga), abs(gb)) > 4 * mu):
            sa, sb = balls.sign(i, j, a), balls.sign(i, j, b)
            if not sa * sb < 0:
                continue
            gb = float(sb)
        e = np.linspace(a, b, 9)
        c0, c1 = e[:-1], e[1:]
        good = True
        # the sites that may come within the margin somewhere on [a, b]: h_k ≤ h_k(θm) + W·|θ − θm|
        # (|h_k'| ≤ W), each float value within mu; the others have gap > 0 on every cell below
        reach = sup.h(others, 0.5 * (a + b)) + sup.W * (0.5 * (b - a)) + 4 * mu if len(others) else None
        for _ in range(30):
            thc, half = cell_balls(c0, c1)
            lo = np.maximum(sup.h_range(i, thc, half)[0], sup.h_range(j, thc, half)[0])
            okc = np.ones(len(thc), bool)
            if len(others):
                cand = others[~(reach < (lo - (sup.W * half + sup.mu)).min())]
                gap = lo[None, :] - sup.h(cand[:, None], thc[None, :]) - (sup.W * half + sup.mu)[None, :]
                okc &= (gap > 0).all(0)
                near = np.nonzero(~okc & (gap > -64 * mu).all(0) & ((gap <= 0).sum(0) <= BALL_SITES))[0]
                if len(near) <= BALL_CELLS:
                    for c in near.tolist():
                        okc[c] = all(balls.gap_lower(i, k, float(thc[c]), float(half[c]))
                                     or balls.gap_lower(j, k, float(thc[c]), float(half[c]))
                                     for k in cand[gap[:, c] <= 0].tolist())
            if okc.all():
                break
            c0, c1 = c0[~okc], c1[~okc]
            if len(c0) > 4096:
                good = False
                break
            c0, c1 = halve(c0, c1, np.ones(len(c0), bool))
        else:
            good = False
        if good:
            return (a, b, 1.0 if gb < 0 else -1.0)
    return None


class _Sector(NamedTuple):
    """The sector Σ = {t ≥ T0, θ ∈ [θa, θb]} of :func:`_prove_sector`, the sign σ of ∂f/∂θ to
    prove on it, and what every step needs (the support table, the site table, the work limit)."""
    sup: object
    table: object
    pair: tuple
    tha: float
    thb: float
    sigma: float
    T0: float
    scale: float
    max_work: int


class _Cells(NamedTuple):
    """One round of cells of the sector in (τ = 1/t, θ): the angular centre and half-width, the
    radii t0 ≤ t ≤ t1 (t1 = ∞ where τa = 0, fin false), the direction U of the centre, the bound
    e_i, e_j of d − (t − h) at t0 (:func:`_eps1`), the disc (Cf, R) covering a finite cell (Rf = 0
    and Cf on the circle t = T0 for an infinite one: the gradient enclosures are taken there)."""
    tb: np.ndarray
    thc: np.ndarray
    half: np.ndarray
    t0: np.ndarray
    t1: np.ndarray
    fin: np.ndarray
    U: np.ndarray
    R: np.ndarray
    Cf: np.ndarray
    Rf: np.ndarray
    e_i: np.ndarray
    e_j: np.ndarray


class _PairValues(NamedTuple):
    """Distance bounds Vi, Vj of the pair at the cells' centres Cf (hi_i, hi_min = min(hi_i,
    hi_j): upper bounds of d_i = d_j on β), and the gradient enclosures (G, s, valid) on the discs."""
    Vi: object
    Vj: object
    hi_i: np.ndarray
    hi_min: np.ndarray
    Gi: np.ndarray
    si: np.ndarray
    vi: np.ndarray
    Gj: np.ndarray
    sj: np.ndarray
    vj: np.ndarray


def _third_sites(sec, oth, need, okA, c, pv):
    """(A) of :func:`_prove_sector` on the cells ``need``: okA[c] is cleared where a site of ``oth``
    is not proved farther than the pair on cell c (support functions to first order in 1/t; then
    distance bounds on the cell's disc, to first or second order)."""
    sup, table, pair, scale = sec.sup, sec.table, sec.pair, sec.scale
    fin, Cf, R, Rf = c.fin, c.Cf, c.R, c.Rf
    Vi, Vj, Gi, si, vi, hi_i, hi_min = pv.Vi, pv.Vj, pv.Gi, pv.si, pv.vi, pv.hi_i, pv.hi_min
    # support functions to first order (far_field.gap_lower): on β, d_i = d_j, so a lower bound of
    # d_k − d_i or of d_k − d_j on the cell suffices
    cell = (c.thc[need][None, :], c.half[need][None, :], c.t0[need][None, :], c.t1[need][None, :])
    k_ = oth[:, None]
    fail = ~((far_field.gap_lower(sup, pair[0], k_, *cell) > 0) | (far_field.gap_lower(sup, pair[1], k_, *cell) > 0))
    okA[need] &= ~(fail & ~fin[need][None, :]).any(0)
    kk, cc = np.nonzero(fail & fin[need][None, :])
    rows, ks = need[cc], oth[kk]
    # the bounding disc first: d_k ≥ |q − c_k| − ρ_k (cheap); the table only for the rest
    V_ = Cf[rows] - sup.cen[ks]
    lo_disc = np.hypot(V_[:, 0], V_[:, 1]) - sup.rho[ks]
    lo_disc -= 1e-12 * (np.abs(Cf[rows]).sum(1) + np.abs(sup.cen[ks]).sum(1) + sup.rho[ks]) + sup.mu
    far_k = lo_disc - R[rows] > hi_min[rows] + R[rows]
    rows, ks = rows[~far_k], ks[~far_k]
    if not len(rows):
        return
    # distance bounds on the cell's disc, or to first order
    # d_k − d_i ≥ (lo_k − hi_i)(C) − R·sup|∇d_k − ∇d_i| on the disc; one call for all sites
    Vk = evaluate_rows(table, Cf[rows], ks)
    okk = Vk.lo - R[rows] > hi_min[rows] + R[rows]
    Gk, sk, vk = gradient_enclosure(Cf[rows], Vk, Rf[rows], scale)
    lip = np.hypot(*(Gk - Gi[rows]).T) + sk + si[rows]
    lip = np.where(vk & vi[rows] & np.isfinite(lip), np.minimum(lip, 2.0), 2.0) * (1 + 1e-12)
    okk |= Vk.lo - hi_i[rows] - lip * R[rows] > 0
    # to second order (distance_gap.gap_lower), where the first order fails
    left = np.nonzero(~okk & fin[rows])[0]
    if len(left):
        Cl, Vl = Cf[rows[left]], Vk.take(left)
        okk[left] |= gap_rows(gap_lower, Cl, (Vl, Vi.take(rows[left])), R[rows[left]], scale) > 0
        left = left[~okk[left]]
        okk[left] |= gap_rows(bisector_gap_lower, Cf[rows[left]],
                              (Vk.take(left), Vi.take(rows[left]), Vj.take(rows[left])),
                              R[rows[left]], scale) > 0
    np.logical_and.at(okA, rows, okk)


def _ball_cells(sup, balls, pair, oth, cells, cell, okF, okA, okM):
    """(F), then (A), of :func:`_prove_sector` on the few ``cells`` left undecided, in balls
    (:meth:`runtime.voronoi.verify.support_balls.SupportBalls.gap_lower`): only the third sites
    whose float bound (far_field.gap_lower) misses by less than the rounding margin."""
    i, j = pair
    thc, half, t0, t1 = cell
    okF, fF = okF
    for c in cells.tolist():
        C = (float(thc[c]), float(half[c]), float(t0[c]), float(t1[c]))
        if not okF[c] and fF[c] > -64 * sup.mu and (balls.gap_lower(j, i, *C) or balls.gap_lower(i, j, *C)):
            okF[c] = True
            continue
        if okA[c] or not okM[c] or not len(oth):
            continue
        lo = np.maximum(far_field.gap_lower(sup, i, oth, *C), far_field.gap_lower(sup, j, oth, *C))
        miss = lo <= 0
        if miss.sum() <= BALL_SITES and (lo[miss] > -64 * sup.mu).all():
            okA[c] = all(balls.gap_lower(i, k, *C) or balls.gap_lower(j, k, *C) for k in oth[miss].tolist())


def _prove_sector(sup, table, pair, tha, thb, sigma, T0, scale, max_work):
    """(A) third sites, (M) σ·∂f/∂θ > 0 on Σ = {t ≥ T0, θ ∈ [θa, θb]}, (R) σ·f < 0 on the ray θa
    and > 0 on the ray θb; cells in (τ = 1/t, θ), halved until decided (module docstring).
    Returns (ok, message)."""
    sec = _Sector(sup, table, pair, tha, thb, sigma, T0, scale, max_work)
    oth = _sector_third_sites(sec)
    for th, want in ((tha, -1.0), (thb, 1.0)):
        msg = _prove_ray(sec, th, want)
        if msg is not None:
            return False, msg
    return _prove_cells(sec, oth)


def _sector_third_sites(sec):
    """The third sites that the cells must test: a site k is farther on the whole sector when
    d_k ≥ t − h_k > t − max(h_i − e_i, h_j − e_j) ≥ d_i = d_j on β, with h bounded over the
    sector (|h'| ≤ W) and e at t = T0 (the largest).  Over the sector h_k ≤ max_θ u(θ)·(c_k − m) + r_k
    and h_k ≥ min_θ u(θ)·(c_k − m) + b_k with r_k, b_k the largest / smallest semi-axis; u·v over
    an arc of directions is extreme at its ends or at ±v/|v| (:func:`_arc_dot`)."""
    sup, pair = sec.sup, sec.pair
    W, m, mu = sup.W, sup.m, sup.mu
    oth = np.array([k for k in range(sup.n) if k not in pair], int)
    thm, hw = (float(v) for v in cell_balls(sec.tha, sec.thb))
    dlo, dhi = _arc_dot(sup.cen - m, sec.tha, sec.thb)
    slack = 1e-12 * (np.abs(sup.cen - m).sum(1) + sup.rho) + mu
    small = np.minimum(sup.sa, sup.sb)
    lead = max(float(dlo[s_] + small[s_] - slack[s_]) - _eps1(float(sup.hp_abs(s_, thm, hw)), W, sec.T0)
               for s_ in pair)
    if len(oth):
        oth = oth[~(dhi[oth] + sup.rho[oth] + slack[oth] < lead)]
    return oth


def _prove_ray(sec, th, want):
    """(R) on the ray θ = th, t ≥ T0: σ·f has the sign ``want`` on τ-intervals covering [0, 1/T0],
    halved until decided by :func:`_ray_signs`.  Returns None (proved) or the message."""
    i, j = sec.pair
    gv = float(sec.sup.h(i, th) - sec.sup.h(j, th))
    T_a, T_b = np.array([0.0]), np.array([1.0 / sec.T0])
    work = 0
    while len(T_a):
        work += len(T_a)
        if work > sec.max_work:
            return f"the sign of d_{i} - d_{j} on the ray at angle {th:.6g} is undecided"
        bad = ~_ray_signs(sec, th, want, gv, T_a, T_b)
        if not bad.any():
            break
        T_a, T_b = halve_tau(T_a, T_b, bad)
    return None


def _ray_signs(sec, th, want, gv, T_a, T_b):
    """Is σ·f of the sign ``want`` on the ray's pieces 1/t ∈ [T_a, T_b]?  By f ∈ [−g − e_j, −g + e_i]
    (g = h_i − h_j = ``gv``, e at the piece's nearest point), or to first order in 1/t
    (far_field.gap_lower: d_i − d_j ≥ gap_lower(j, i), ≤ −gap_lower(i, j)), or, on a finite piece,
    by the distance bounds at its midpoint widened by its half-length (d is 1-Lipschitz)."""
    i, j = sec.pair
    sup, sigma = sec.sup, sec.sigma
    W, m, mu = sup.W, sup.m, sup.mu
    t0 = 1.0 / T_b
    e_i = _eps1(sup.hp_abs(i, th, 0.0), W, t0)
    e_j = _eps1(sup.hp_abs(j, th, 0.0), W, t0)
    f_lo, f_hi = -gv - 2 * mu - e_j, -gv + 2 * mu + e_i      # f ∈ [−g − e_j, −g + e_i]
    ok = np.where(want * sigma > 0, f_lo > 0, f_hi < 0)
    t_far = np.where(T_a > 0, 1.0 / np.where(T_a > 0, T_a, 1.0), np.inf)
    ray = (np.full(len(T_a), th), 0.0, t0, t_far)
    ok |= np.where(want * sigma > 0, far_field.gap_lower(sup, j, i, *ray) > 0,
                   far_field.gap_lower(sup, i, j, *ray) > 0)
    fin = T_a > 0
    if fin.any():
        t1 = np.where(fin, 1.0 / np.where(fin, T_a, 1.0), t0)
        tc = 0.5 * (t0 + t1)
        C = m + tc[:, None] * np.array([math.cos(th), math.sin(th)])
        R = np.where(fin, 0.5 * (t1 - t0), np.inf) * (1 + 1e-12) + 1e-12 * (sec.scale + tc)
        n_ = len(C)
        V = evaluate_rows(sec.table, np.concatenate([C, C]), np.repeat([i, j], n_))
        fl, fh = V.lo[:n_] - V.hi[n_:] - 2 * R, V.hi[:n_] - V.lo[n_:] + 2 * R
        ok |= fin & (((want * sigma > 0) & (fl > 0)) | ((want * sigma < 0) & (fh < 0)))
    return ok


def _prove_cells(sec, oth):
    """The 2-D cells of Σ in (τ, θ): each round decides (F) or (A) and (M) on its cells
    (:func:`_far_sign`, :func:`_third_sites_round`, :func:`_monotone`), retries the near-ties at
    infinity in balls, and quarters the cells left undecided.  Returns (ok, message)."""
    mu = sec.sup.mu
    ta, tb, h0, h1 = sector_grid(sec.tha, sec.thb, 1.0 / sec.T0)
    okA_last = np.ones(len(ta), bool)
    work = 0
    balls = None
    while len(ta):
        work += len(ta)
        if work > sec.max_work:
            return False, _undecided(ta, tb, h0, h1, okA_last)
        c = _cell_discs(sec, ta, tb, h0, h1)
        pv = _pair_values(sec, c)
        # (F) first: cells where β does not pass need no (A), (M)
        okF, fF = _far_sign(sec, c, pv)
        okA = _third_sites_round(sec, oth, c, pv, okF)
        okM = _monotone(sec, c, pv)
        bad = ~(okF | (okA & okM))
        # near-ties at infinity within the float rounding margin: the same bounds in balls, on
        # the cells where (F) misses by less than the margin or only (A) fails
        near = np.nonzero(bad & ((fF > -64 * mu) | (okM & ~okA)))[0][:BALL_CELLS]
        balls = balls or SupportBalls(sec.sup)
        if len(near) and balls.calls < BALL_BUDGET:
            _ball_cells(sec.sup, balls, sec.pair, oth, near, (c.thc, c.half, c.t0, c.t1), (okF, fF), okA, okM)
            bad = ~(okF | (okA & okM))
        if not bad.any():
            return True, None
        # halve the undecided cells: infinite cells in τ and θ, finite ones across their longer side
        ta, tb, h0, h1, okA_last = quarter_cells((ta, tb, h0, h1, okA), bad, W=sec.sup.W)
    return True, None


def _undecided(ta, tb, h0, h1, okA_last):
    """The message for a sector left undecided within the work limit: the farthest cell, and
    whether (A) or (M) failed there in the last round."""
    k = int(np.argmax(tb))
    what = "third site" if not okA_last[k] else "monotonicity"
    return (f"the tail is undecided ({what}) near angle {0.5 * (h0[k] + h1[k]):.6g}, "
            f"distance {1.0 / tb[k]:.6g} from the scene's centre")


def _cell_discs(sec, ta, tb, h0, h1):
    """The :class:`_Cells` of a round: a finite cell {1/t ∈ [τa, τb], θ ∈ [θ0, θ1]} lies in the disc
    of centre m + tc·u(θc), tc = (t0 + t1)/2, and radius t1·δ + (t1 − t0)/2 (δ the angular
    half-width), widened by rounding."""
    sup = sec.sup
    i, j = sec.pair
    W, m = sup.W, sup.m
    thc, half = cell_balls(h0, h1)
    t0 = 1.0 / tb
    e_i = _eps1(sup.hp_abs(i, thc, half), W, t0)
    e_j = _eps1(sup.hp_abs(j, thc, half), W, t0)
    fin = ta > 0
    t1 = np.where(fin, 1.0 / np.where(fin, ta, 1.0), np.inf)
    tc = np.where(fin, 0.5 * (t0 + t1), t0)
    U = np.column_stack([np.cos(thc), np.sin(thc)])
    C = m + tc[:, None] * U
    R = np.where(fin, t1 * half + 0.5 * (t1 - t0) + 1e-12 * (sec.scale + tc), np.inf) * (1 + 1e-12)
    Cf = np.where(fin[:, None], C, m + sec.T0 * U)
    Rf = np.where(fin, R, 0.0)
    return _Cells(tb, thc, half, t0, t1, fin, U, R, Cf, Rf, e_i, e_j)


def _pair_values(sec, c):
    """The :class:`_PairValues` of the pair on the cells: one table call for i and j, and the
    gradient enclosures of :func:`runtime.voronoi.verify.site_table.gradient_enclosure`."""
    i, j = sec.pair
    nc = len(c.thc)
    Vij = evaluate_rows(sec.table, np.concatenate([c.Cf, c.Cf]), np.repeat([i, j], nc))
    Vi, Vj = Vij.part(0, nc), Vij.part(nc, 2 * nc)
    hi_i, hi_min = Vi.hi, np.minimum(Vi.hi, Vj.hi)
    Gi, si, vi = gradient_enclosure(c.Cf, Vi, c.Rf, sec.scale)
    Gj, sj, vj = gradient_enclosure(c.Cf, Vj, c.Rf, sec.scale)
    return _PairValues(Vi, Vj, hi_i, hi_min, Gi, si, vi, Gj, sj, vj)


def _far_sign(sec, c, pv):
    """(F): f = d_i − d_j has one strict sign on the cell, so β does not meet it: by
    f ∈ [−g − e_j, −g + e_i] with g = h_i − h_j ∈ g(θc) ± (2W·δ + 2μ) (|h'| ≤ W), or to first order
    in 1/t (far_field.gap_lower: d_i − d_j ≥ gap_lower(j, i) > 0 or d_j − d_i ≥ gap_lower(i, j) > 0),
    or by the distance bounds on a finite cell's disc.  Returns (okF, the first-order bound fF)."""
    sup = sec.sup
    i, j = sec.pair
    W, mu = sup.W, sup.mu
    gc = sup.h(i, c.thc) - sup.h(j, c.thc)
    gr = 2 * W * c.half + 2 * mu
    okF = (-(gc + gr) - c.e_j > 0) | (-(gc - gr) + c.e_i < 0)
    fF = np.maximum(far_field.gap_lower(sup, j, i, c.thc, c.half, c.t0, c.t1),
                    far_field.gap_lower(sup, i, j, c.thc, c.half, c.t0, c.t1))
    okF |= fF > 0
    if c.fin.any():
        okF |= c.fin & ((pv.Vi.lo - pv.Vj.hi - 2 * c.R > 0) | (pv.Vi.hi - pv.Vj.lo + 2 * c.R < 0))
    return okF, fF


def _third_sites_round(sec, oth, c, pv, okF):
    """(A) on the cells where (F) failed (:func:`_third_sites`), in groups of cells with at most
    ROWS_PER_CALL (cell, site) rows: temporaries bounded independently of the number of sites;
    every row is tested as in one call."""
    okA = np.ones(len(c.thc), bool)
    need = np.nonzero(~okF)[0]
    if len(oth) and len(need):
        step = max(1, strips.ROWS_PER_CALL // len(oth))
        for a0 in range(0, len(need), step):
            _third_sites(sec, oth, need[a0:a0 + step], okA, c, pv)
    return okA


def _monotone(sec, c, pv):
    """(M) σ·∂f/∂θ > 0 on the cell: t·∂_θ d_s = −κ_s·(p_s − m)·u⊥ with κ_s ∈ [1/(1 + W/t),
    1/(1 − W/t)] and (p_s − m)·u⊥ ∈ h_s'(θc) ± (ρ_s(α + δ) + W·δ), α = asin(W/(t − W)) (module
    docstring); else, on a finite cell, σ(∇d_i − ∇d_j)·u⊥ > 0 with the gradient enclosures on
    its disc (u⊥ within δ of u⊥(θc))."""
    sup, sigma = sec.sup, sec.sigma
    i, j = sec.pair
    W, mu = sup.W, sup.mu
    Wt = W * c.tb
    alpha = np.arcsin(np.minimum(1.0, Wt / (1 - Wt)))
    k_lo, k_hi = 1.0 / (1 + Wt), 1.0 / (1 - Wt)
    parts = []
    for s in (i, j):
        pc = sup.hp(s, c.thc)
        rr = sup.rcurv[s] * (alpha + c.half) + W * c.half + mu
        parts.append(_imul(k_lo, k_hi, pc - rr, pc + rr))
    d_lo = parts[1][0] - parts[0][1]          # −κ_i P_i + κ_j P_j
    d_hi = parts[1][1] - parts[0][0]
    d_lo, d_hi = d_lo - 1e-12 * W, d_hi + 1e-12 * W
    okM = (d_lo > 0) if sigma > 0 else (d_hi < 0)
    if c.fin.any() and not okM.all():
        Df = pv.Gi - pv.Gj
        perp = np.column_stack([-c.U[:, 1], c.U[:, 0]])
        # σ·Df(q)·u⊥(θ) ≥ σ·(Gi − Gj)·u⊥(θc) − (si + sj) − |Df(q)|·δ, |Df(q)| ≤ |Gi − Gj| + si + sj
        s_ij = pv.si + pv.sj
        val = sigma * (Df * perp).sum(1) - (np.hypot(Df[:, 0], Df[:, 1]) + s_ij) * c.half - s_ij - 1e-12
        okM |= c.fin & pv.vi & pv.vj & (val > 0)
    return okM
