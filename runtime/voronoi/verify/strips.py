"""A chain of strips that contains one arc of a bisector of convex sites (thesis §5.1–5.2).

Used by :mod:`runtime.voronoi.verify.curved` for an edge (i, j) whose bisector has no closed form
(one of i, j, or a third site, is an ellipse).  For each polyline segment, with unit direction
t, normal n and length L, take the rectangle (a trapezoid when the half-widths of its two nodes
differ) Π = {P_l + s·t + λ·n : s ∈ [−e, L + e], |λ| ≤ w(s)} (e covers the turn to the next
segment and the vertex boxes).  With f = d_i − d_j:

(T1) **monotone**: (∇d_i − ∇d_j)·n has one strict sign σ on Π; where a distance has no gradient
     enclosure (a disc reaching the medial axis inside a circle or an ellipse, where d is not
     differentiable) every g·n, g in the Clarke generalised gradient ∂d_i − ∂d_j
     (:mod:`runtime.voronoi.verify.clarke_gradient`), has the sign σ, and f is strictly
     monotone along n by Lebourg's mean value theorem;
(T4) **crossing**: σ·f > 0 on the side λ = +w and σ·f < 0 on the side λ = −w (to first order
     from the piece's centre, :func:`_sides_from_centre`, or from each side's midpoint, or to
     second order there, :func:`side_second_order`, where the disc terms of the gradient
     enclosures exceed |∇f|, far from the sites).  The sides tested are drawn at
     λ = ±(w − μ), μ = 10⁻¹²·w + 8u·(|C|₁ + w) (u the unit roundoff, C the piece's centre), so
     that their float points lie inside |λ| ≤ w·(1 − 10⁻¹²): β crosses every cross-section with
     that margin, which the chaining at the nodes uses against the rounding of the strips' frames
     (:mod:`runtime.voronoi.verify.curved`, "Chaining at the nodes").

Then every cross-section s = const meets the bisector β exactly once, so β ∩ Π is one arc, a
graph over s (continuous: f is continuous and strictly monotone across; the implicit function
theorem where f is smooth).  Consecutive arcs join: the arc of one strip crosses its
cross-section at the shared node at a point that lies in the next strip (given the extensions
e ≥ w·|sin θ| for the turn θ and a trapezoid slope at most tan(θ/2) on one side of the node, which
the caller ensures: :func:`runtime.voronoi.verify.curved.chained_nodes`, whose module docstring
gives the argument), so the arcs chain into one curve of β through both end vertices (each lies in the first / last rectangle); for a closed
edge (no vertex) the last rectangle hands over to the first and the arcs form a closed curve,
open and closed in β, hence a whole component of β.  Along it:

(T2) every other site k is proved farther on each piece (lo_k − R > min(hi_i, hi_j) + R on a disc
     of radius R covering the piece; d is 1-Lipschitz), or to first order
     d_k − d_i ≥ (lo_k − hi_i)(C) − R·(|G_k − G_i| + s_k + s_i) > 0 with the gradient enclosures
     G ± s on the disc (far from the sites all gradients are nearly equal, so the pieces may be
     much larger than the margin d_k − d_i), or to second order
     (:func:`runtime.voronoi.verify.distance_gap.gap_lower`, and on β only
     :func:`runtime.voronoi.verify.distance_gap.bisector_gap_lower`); the same with j (d_i = d_j on β); sites whose
     bounding box is farther than min(hi_i, hi_j) + 2R from the piece's centre pass without
     evaluation; among bounded convex sites, a site k passes first when the supporting
     half-plane of k normal to ∇d_i(C) (or ∇d_j(C)) proves it farther on the disc
     (:func:`_support_half_planes`: to first order in R, without k's foot point), whole groups
     of sites at once where the bound holds for a disc holding all of them
     (:meth:`runtime.voronoi.verify.site_table.SiteTable.near_pairs` with levels);
(T3) or, for a site k0 tied at the first vertex (k1 at the last; one at a simple vertex, k − 2 at
     a vertex of degree k), the derivative of
     g = d_k0 − d_i along the arc has a proved sign: the arc's tangent is ± rot90(∇f), so
     g' ∝ σ_t·(∇d_k0 − ∇d_i)·rot90(∇d_i − ∇d_j) (transversality at the vertex).  Since g = 0 at
     the vertex, g' > 0 on a run of pieces that starts at the vertex or after a (T2) piece keeps
     g > 0 (symmetrically g' < 0 before the last vertex).

Pieces are the rectangles cut across s, initially ``PIECE`` times as long as the strip is wide;
a piece that fails is halved (its two halves re-tested), the others are done.  A chain gives up
when halving stops deciding pieces (``STALL`` rounds), or when its work limits are spent (the
caller then narrows the strips or reports the edge).  The gradients come with the enclosures of
:func:`runtime.voronoi.verify.site_table.gradient_enclosure`.  The chains of all edges are proved
together (:func:`prove_strips_many`: the pieces of every chain in flat arrays, two calls of
:meth:`runtime.voronoi.verify.site_table.SiteTable.evaluate` per round of halving, or per group
of ``ROWS_PER_CALL``/6 pieces: the memory is bounded independently of the number of pieces),
called once with the chains of every edge by :mod:`runtime.voronoi.verify.curved`.

Length: one test — the strip chain — written as its named steps (the pieces' geometry, (T1)
:func:`_monotone`, (T4) :func:`_sides`, (T2) :func:`_farther`, (T3) :func:`_tied_derivative`, the
flat chains and the rounds of halving), each with its inequality in its docstring.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..geometry import EPS
from .clarke_gradient import difference_range
from .distance_gap import bisector_gap_lower, gap_lower
from .site_table import SiteValues, gradient_enclosure

__all__ = ["ROWS_PER_CALL", "StripsJob", "evaluate_rows", "gap_rows", "prove_strips_many",
           "rot90", "side_second_order"]

MAX_DEPTH = 40
STALL = 3           # rounds of halving without progress before giving up
#: a chain gives up past this many failing pieces in a round or tested pieces in all: a long edge
#: far from the sites needs many (50 363 pieces for an edge 1.3·10⁶ long, 0.002 wide, between
#: two ellipses of random_ellipses(10000, 1)); a chain that cannot pass may spend them before it is refused
MAX_FAILING, MAX_WORK = 40000, 64000
PIECE = 16.0        # initial pieces: PIECE times as long as the strip is wide (99 % pass at 16 on random ellipses)
#: rows per call of the row-wise evaluations (:func:`evaluate_rows`, :func:`gap_rows`): their
#: temporaries then take memory bounded independently of N, and the results, computed row by row,
#: are the same arrays as in one call
ROWS_PER_CALL = 50_000

_FIELDS = ("lo", "hi", "F", "d", "base", "inner", "reach", "sep")


def evaluate_rows(table, Q, K, rows=None):
    """``table.evaluate(Q, K)`` (:meth:`runtime.voronoi.verify.site_table.SiteTable.evaluate`,
    row-wise) in calls of at most ``rows`` rows (default :data:`ROWS_PER_CALL`, read at the call),
    the values concatenated."""
    rows = ROWS_PER_CALL if rows is None else int(rows)
    Q = np.asarray(Q, float).reshape(-1, 2)
    K = np.asarray(K, int).reshape(-1)
    m = len(K)
    if m <= rows:
        return table.evaluate(Q, K)
    parts = [table.evaluate(Q[a:a + rows], K[a:a + rows]) for a in range(0, m, rows)]
    cat = [np.concatenate([getattr(v, f) for v in parts]) for f in _FIELDS]
    return SiteValues(*cat, np.concatenate([v.K for v in parts]), table)


def gap_rows(bound, Q, Vs, R, scale, rows=None):
    """``bound(Q, *Vs, R, scale)`` for a row-wise lower bound of :mod:`runtime.voronoi.verify.distance_gap`
    (:func:`gap_lower`, :func:`bisector_gap_lower`) in calls of at most ``rows`` rows (default
    :data:`ROWS_PER_CALL`, read at the call), concatenated."""
    rows = ROWS_PER_CALL if rows is None else int(rows)
    R = np.broadcast_to(np.asarray(R, float), (len(Q),))
    m = len(Q)
    if m <= rows:
        return bound(Q, *Vs, R, scale)
    return np.concatenate([bound(Q[a:a + rows], *(V.part(a, a + rows) for V in Vs), R[a:a + rows], scale)
                           for a in range(0, m, rows)])


def rot90(V):
    return np.column_stack([-V[:, 1], V[:, 0]])


class StripsJob:
    """One chain of strips to prove: the polyline S (segments T, N, L; node half-widths W; cap
    extensions e_lo, e_hi), the pair, the third sites k0, k1 of the end vertices (or None) and
    ``budget``, None or a counter whose ``left`` is the pieces this edge may still test (decreased
    here; :class:`runtime.voronoi.verify.curved.EdgeWork`)."""

    __slots__ = ("S", "T", "N", "L", "e_lo", "e_hi", "W", "pair", "k0", "k1", "budget")

    def __init__(self, S, T, N, L, e_lo, e_hi, W, pair, k0, k1, budget):
        self.S, self.T, self.N, self.L, self.e_lo, self.e_hi, self.W = S, T, N, L, e_lo, e_hi, W
        self.pair, self.k0, self.k1, self.budget = pair, k0, k1, budget


def side_second_order(Qs, t, h, fval, Vi, Vj, Gi, si, Gj, sj, scale):
    """(T4') on the sides {Qs + s·t : |s| ≤ h} where ``fval`` is a lower bound of ς·f at the
    midpoint Qs (f = d_i − d_j, ς = ±1 the sign wanted on that side; every other term is
    symmetric in i, j): True where ς·f > 0 on the whole side.

    Outside a convex set K with nearest point p(q) and unit normal n = ∇d, the Hessian is
    ∇²d = τ τᵀ/(d + ρ) with τ ⟂ n and ρ ≥ 0 the radius of curvature at p (∇²d = (I − Dp − n nᵀ)/d
    and Dp = ρ/(ρ + d)·τ τᵀ, the projection's derivative; a.e. for a corner, where d is still
    C^{1,1}).  So along the side d_k'' ∈ [0, M_k], M_k = (|t × G_k| + s_k)²/(lo_k − h), with the
    disc enclosures G_k ± s_k of ∇d_k on B(Qs, h) (d_k ≥ lo_k − h there), and
    |f''| ≤ max(M_i, M_j).  Taylor at the midpoint: ς·f(Qs + s·t) ≥ fval − h·|∇f(Qs)·t| − h²/2·max M,
    with ∇f(Qs) from the point enclosures (radius 0).  Needs Qs's disc outside both convex sets
    (``base``; a hyperbola: one branch nearest on the disc, ``sep`` > h)."""
    G0i, s0i, v0i = gradient_enclosure(Qs, Vi, 0.0, scale)
    G0j, s0j, v0j = gradient_enclosure(Qs, Vj, 0.0, scale)
    with np.errstate(divide="ignore", invalid="ignore"):
        first = (np.abs(((G0i - G0j) * t).sum(1)) + s0i + s0j) * (1 + 1e-12)
        out = (Vi.base & Vj.base & (Vi.sep > h) & (Vj.sep > h) & (Vi.lo > 2 * h) & (Vj.lo > 2 * h)
               & v0i & v0j)
        ci = np.minimum(np.abs(Gi[:, 0] * t[:, 1] - Gi[:, 1] * t[:, 0]) + si, 1.0)
        cj = np.minimum(np.abs(Gj[:, 0] * t[:, 1] - Gj[:, 1] * t[:, 0]) + sj, 1.0)
        M = np.maximum(ci * ci / (Vi.lo - h), cj * cj / (Vj.lo - h)) * (1 + 1e-12)
        # rounding of fval = lo − hi: half an ulp of the larger operand
        rnd = 2 * EPS * (np.abs(Vi.lo) + np.abs(Vi.hi) + np.abs(Vj.lo) + np.abs(Vj.hi))
        low = fval - rnd - h * first * (1 + 1e-12) - 0.5 * h * h * M * (1 + 1e-12)
    return out & np.isfinite(low) & (low > 0)


class _Pieces(NamedTuple):
    """The trapezoid pieces (seg, [sa, sb]) of a group: job ``jb`` of each, centre C at
    ``sm`` along the segment (unit direction Tn, normal Nn), the radius R of a disc covering the
    piece, the length ``side_len`` of half a lateral side, its side midpoints Qp, Qm = C ± (w − μ)·Nn
    ((T4) in the module docstring), the pair (Ip, Jp) of its chain and the sides' offset ws = w − μ."""
    seg: np.ndarray
    jb: np.ndarray
    sm: np.ndarray
    Tn: np.ndarray
    Nn: np.ndarray
    C: np.ndarray
    R: np.ndarray
    side_len: np.ndarray
    Qp: np.ndarray
    Qm: np.ndarray
    Ip: np.ndarray
    Jp: np.ndarray
    ws: np.ndarray


def _pieces(scale, seg, sa, sb, chains) -> _Pieces:
    """The geometry of the pieces: R = |(half length, larger half-width)|·(1 + 10⁻¹²) + 10⁻¹⁵·scale
    covers the trapezoid from its centre; a lateral side has half length half·√(1 + slope²)."""
    sj, Sg, Tg, Ng, W0, slope, I, J = chains[:8]
    jb = sj[seg]
    sm = 0.5 * (sa + sb)
    Tn, Nn = Tg[seg], Ng[seg]
    C = Sg[seg] + sm[:, None] * Tn
    half = 0.5 * (sb - sa)
    wa = np.maximum(W0[seg] + slope[seg] * sa, 0.0)
    wb = np.maximum(W0[seg] + slope[seg] * sb, 0.0)
    w = 0.5 * (wa + wb)                           # half-width at the piece centre
    R = np.hypot(half, np.maximum(wa, wb)) * (1 + 1e-12) + 1e-15 * scale
    side_len = half * np.sqrt(1 + slope[seg] ** 2) * (1 + 1e-12)
    ws = w - (1e-12 * w + 8 * EPS * (np.abs(C).sum(1) + w))      # (T4): the sides drawn inside
    Qp, Qm = C + ws[:, None] * Nn, C - ws[:, None] * Nn
    return _Pieces(seg, jb, sm, Tn, Nn, C, R, side_len, Qp, Qm, I[jb], J[jb], ws)


def _monotone(table, depth, sigma, P: _Pieces, Vi, Vj, enc_i, enc_j):
    """(T1): the range [mono_lo, mono_hi] of g·n over the gradients g of f = d_i − d_j on each
    piece's disc has the strict sign σ of its chain; where a distance has no gradient enclosure (a
    disc reaching the medial axis inside a circle or an ellipse) over its Clarke generalised
    gradient (:func:`runtime.voronoi.verify.clarke_gradient.difference_range`, Lebourg's theorem).
    At depth 0, σ of a chain without one is set from its first piece decided here (the groups run
    in piece order; a chain's earlier pieces are undecided, so σ does not matter there).
    Returns t1 per piece."""
    (Gi, si, vi), (Gj, sj_, vj) = enc_i, enc_j
    mono = ((Gi - Gj) * P.Nn).sum(1)
    sf = si + sj_
    mono_lo, mono_hi = mono - sf, mono + sf
    mono_ok = vi & vj
    miss = np.nonzero(~(mono_ok & ((mono_lo > 0) | (mono_hi < 0))))[0]
    if len(miss):
        # undecided pieces: the gradient enclosures intersected with the Clarke ranges
        lo_, hi_, ok_ = difference_range(table, P.C[miss], P.R[miss], P.Nn[miss], (P.Ip[miss], P.Jp[miss]),
                                         (Vi.take(miss), Vj.take(miss)),
                                         ((Gi[miss], si[miss], vi[miss]), (Gj[miss], sj_[miss], vj[miss])))
        mono_lo[miss], mono_hi[miss], mono_ok[miss] = lo_, hi_, ok_
    if depth == 0:
        dec = np.nonzero(mono_ok & ((mono_lo > 0) | (mono_hi < 0)))[0]
        first_job, first = np.unique(P.jb[dec], return_index=True)
        new = sigma[first_job] == 0
        sigma[first_job[new]] = np.where(mono_lo[dec[first[new]]] > 0, 1.0, -1.0)
    sg_p = sigma[P.jb]
    return mono_ok & np.where(sg_p > 0, mono_lo > 0, mono_hi < 0)


def _side_direction(P: _Pieces, slope, sg):
    """The unit direction of the lateral side sg = ±1 of each piece: T + sg·slope·N, normalised."""
    tside = P.Tn + (sg * slope[P.seg])[:, None] * P.Nn
    return tside / np.hypot(*tside.T)[:, None]


def _sides(table, scale, slope, sigma, P: _Pieces, t1, enc_i, enc_j, Vi, Vj):
    """(T4) on the lateral sides of the pieces where (T1) holds (False elsewhere: such a piece
    fails anyway): σ·f > 0 on the side +w and < 0 on the side −w, f = d_i − d_j.  First from
    the values at the centre, to first order (:func:`_sides_from_centre`) and to second order
    (:func:`_sides_centre_second_order`), no new evaluation; then, for the pieces left, from the
    values at each side's midpoint (:func:`_sides_at_midpoints`)."""
    side_ok = t1 & _sides_from_centre(slope, sigma, P, enc_i, enc_j, Vi, Vj)
    left = np.nonzero(t1 & ~side_ok)[0]
    if len(left):
        side_ok[left] = _sides_centre_second_order(scale, slope, sigma, P, left, Vi.take(left), Vj.take(left))
        left = left[~side_ok[left]]
    if len(left):
        side_ok[left] = _sides_at_midpoints(table, scale, slope, sigma, P, left)
    return side_ok


def _sides_from_centre(slope, sigma, P: _Pieces, enc_i, enc_j, Vi, Vj):
    """(T4) from the centre C, to first order: a point of the side sg is
    q = C + sg·ws·N + τ·t_s (|τ| ≤ side_len, t_s the side's unit direction), in the disc B(C, R)
    on which ∇f lies within D ± (s_i + s_j), D = G_i − G_j (the enclosures of the pieces, valid on
    the disc; Lebourg's mean value theorem where d is only Lipschitz).  With ς = sg·σ the sign
    wanted and ς·sg = σ,

        ς·f(q) ≥ ς·f(C) + σ·ws·(D·N) − side_len·|D·t_s| − (s_i + s_j)·R,

    ς·f(C) ≥ lo_i − hi_j (ς = 1) or lo_j − hi_i (ς = −1).  The main terms are those of the
    midpoint route: ς·f at the side's midpoint is about ς·f(C) + σ·ws·|∇f·N|.  True per piece where
    the bound is > 0 on both sides (rounding: 2u per value, 10⁻¹² relative on each product)."""
    (Gi, si, vi), (Gj, sj_, vj) = enc_i, enc_j
    sg_p = sigma[P.jb]
    D = Gi - Gj
    sf = si + sj_
    size = np.abs(D).sum(1) + sf
    rnd = 2 * EPS * (np.abs(Vi.lo) + np.abs(Vi.hi) + np.abs(Vj.lo) + np.abs(Vj.hi))
    ok = vi & vj & (sg_p != 0)
    with np.errstate(invalid="ignore"):
        along = sg_p * (D * P.Nn).sum(1) * P.ws - 1e-12 * P.ws * size
        for sg in (1.0, -1.0):
            across = np.abs((D * _side_direction(P, slope, sg)).sum(1))
            fC = np.where(sg * sg_p > 0, Vi.lo - Vj.hi, Vj.lo - Vi.hi)
            low = (fC - rnd + along - (P.side_len * across + sf * P.R) * (1 + 1e-12)
                   - 1e-12 * P.side_len * size)
            ok &= np.isfinite(low) & (low > 0)
    return ok


def _sides_centre_second_order(scale, slope, sigma, P: _Pieces, idx, Vi, Vj):
    """(T4) from the centre C of the pieces idx (``Vi``, ``Vj``: the values at their centres), to
    second order: a distance to a convex set is convex, and C^{1,1} off the set with
    0 ≤ ∇²d ≤ 1/d (module docstring of :func:`side_second_order`), so on a disc B(C, R) where
    d_i, d_j ≥ m − R, m = min(lo_i, lo_j) > 2R, and for q = C + sg·ws·N + τ·t_s (a point of the
    side sg, |τ| ≤ side_len, |q − C| ≤ R),

        ς·f(q) ≥ ς·f(C) + σ·ws·(D₀·N) − side_len·|D₀·t_s| − s₀·R − R²/(2(m − R)),

    with ∇f(C) within D₀ ± s₀ (the cheap point enclosures at C, radius 0: their foot-point term,
    about 10⁻⁷·d or less, is far below the other terms) and ς = sg·σ.  The disc term
    of the first-order route, (s_i + s_j)·R ≈ 2R²/d, is here R²/(2d): far from the sites, where
    the pieces are long, this decides most of the pieces that route leaves.  Needs C's disc
    outside both convex sets (``base``; a hyperbola: one branch nearest on the disc, ``sep`` > R).
    True per piece where the bound is > 0 on both sides."""
    C, R, ws, side_len = P.C[idx], P.R[idx], P.ws[idx], P.side_len[idx]
    G0i, s0i, v0i = gradient_enclosure(C, Vi, 0.0, scale, tight=False)
    G0j, s0j, v0j = gradient_enclosure(C, Vj, 0.0, scale, tight=False)
    sg_p = sigma[P.jb[idx]]
    D0, s0 = G0i - G0j, s0i + s0j
    size = np.abs(D0).sum(1) + s0
    rnd = 2 * EPS * (np.abs(Vi.lo) + np.abs(Vi.hi) + np.abs(Vj.lo) + np.abs(Vj.hi))
    ok = (Vi.base & Vj.base & (Vi.sep > R) & (Vj.sep > R) & (Vi.lo > 2 * R) & (Vj.lo > 2 * R)
          & v0i & v0j & (sg_p != 0))
    with np.errstate(invalid="ignore", divide="ignore"):
        quad = 0.5 * R * R / (np.minimum(Vi.lo, Vj.lo) - R)
        along = sg_p * (D0 * P.Nn[idx]).sum(1) * ws - 1e-12 * ws * size
        for sg in (1.0, -1.0):
            across = np.abs((D0 * _side_direction(P, slope, sg)[idx]).sum(1))
            fC = np.where(sg * sg_p > 0, Vi.lo - Vj.hi, Vj.lo - Vi.hi)
            low = (fC - rnd + along - (side_len * across + s0 * R + quad) * (1 + 1e-12)
                   - 1e-12 * side_len * size)
            ok &= np.isfinite(low) & (low > 0)
    return ok


def _sides_at_midpoints(table, scale, slope, sigma, P: _Pieces, idx):
    """(T4) on the pieces idx from the lower bound fval of ς·f at each side's midpoint Qs
    (ς = ±σ), first order: fval − rate·side_len > 0 with rate ≥ |∇f·t| on the side (the
    gradient enclosures where they exist, else 2: f is 2-Lipschitz); where that fails, second
    order (:func:`side_second_order`: far from the sites the gradients' disc terms R/d exceed
    |∇f|).  Four evaluation rows per piece."""
    n = len(idx)
    Ip, Jp, side_len = P.Ip[idx], P.Jp[idx], P.side_len[idx]
    V = evaluate_rows(table, np.concatenate([P.Qp[idx], P.Qp[idx], P.Qm[idx], P.Qm[idx]]),
                      np.concatenate([Ip, Jp, Ip, Jp]))
    sg_p = sigma[P.jb[idx]]
    ok = np.ones(n, bool)
    for b, (Qs, sg) in enumerate(((P.Qp[idx], 1.0), (P.Qm[idx], -1.0))):
        Vis, Vjs = V.part(2 * b * n, (2 * b + 1) * n), V.part((2 * b + 1) * n, (2 * b + 2) * n)
        tside = _side_direction(P, slope, sg)[idx]
        Gis, sis, vis = gradient_enclosure(Qs, Vis, side_len, scale)
        Gjs, sjs, vjs = gradient_enclosure(Qs, Vjs, side_len, scale)
        rate = np.abs(((Gis - Gjs) * tside).sum(1)) + sis + sjs
        rate = np.where(vis & vjs & np.isfinite(rate), np.minimum(rate, 2.0), 2.0) * (1 + 1e-12)
        pos_f = sg * sg_p > 0
        fval = np.where(pos_f, Vis.lo - Vjs.hi, Vjs.lo - Vis.hi)
        okb = fval - rate * side_len > 0
        redo = np.nonzero(~okb & vis & vjs)[0]
        if len(redo):
            okb[redo] = side_second_order(Qs[redo], tside[redo], side_len[redo], fval[redo],
                                          Vis.take(redo), Vjs.take(redo), Gis[redo], sis[redo],
                                          Gjs[redo], sjs[redo], scale)
        ok &= okb
    return ok


def _farther(table, scale, P: _Pieces, rows, Vk, Vi, Vj, enc_i, enc_j, enc_k):
    """(T2) per (piece, third site k) row: d_k > min(d_i, d_j) on the piece's disc — by
    lo_k − R > min(hi_i, hi_j) + R (d is 1-Lipschitz); or to first order
    d_k − d_x ≥ (lo_k − hi_x)(C) − R·sup|∇d_k − ∇d_x| (x = i and x = j); or to second order
    (:func:`runtime.voronoi.verify.distance_gap.gap_lower`, then on β only
    :func:`runtime.voronoi.verify.distance_gap.bisector_gap_lower`)."""
    (Gi, si, vi), (Gj, sj_, vj), (GK, SK, VK) = enc_i, enc_j, enc_k
    C, Rr = P.C, P.R[rows]
    okk = Vk.lo - Rr > np.minimum(Vi.hi, Vj.hi)[rows] + Rr
    for G_, s_, v_, h_ in ((Gi, si, vi, Vi.hi), (Gj, sj_, vj, Vj.hi)):
        lip = np.hypot(*(GK - G_[rows]).T) + SK + s_[rows]
        lip = np.where(VK & v_[rows] & np.isfinite(lip), np.minimum(lip, 2.0), 2.0) * (1 + 1e-12)
        okk |= Vk.lo - h_[rows] - lip * Rr > 0
    left = np.nonzero(~okk)[0]
    if len(left):
        Cl, Vl = C[rows[left]], Vk.take(left)
        for Vx in (Vi, Vj):
            okk[left] |= gap_rows(gap_lower, Cl, (Vl, Vx.take(rows[left])), Rr[left], scale) > 0
        left = left[~okk[left]]
        okk[left] |= gap_rows(bisector_gap_lower, C[rows[left]],
                              (Vk.take(left), Vi.take(rows[left]), Vj.take(rows[left])), Rr[left], scale) > 0
    return okk


def _tied_derivative(chains, P: _Pieces, rows, ks, okk, enc_i, enc_j, enc_k):
    """(T3) for the rows whose third site k is tied with the pair at the first vertex (K0, wanted
    g' > 0) or the last (K1, g' < 0), g = d_k − d_i along the arc: the arc's tangent is
    ± rot90(∇f), so g' has the sign of σ_t·(∇d_k − ∇d_i)·rot90(∇f), σ_t = sign(rot90(∇f)·t) when
    |rot90(∇f)·t| exceeds its enclosure radius; want·value − err·(1 + 10⁻⁹) − 10⁻¹² > 0 with err
    the product bound of the two enclosures.  A site tied at both ends: g' > 0 in the first half
    of the chain, < 0 in the second.  ``okk`` is updated in place."""
    K0, K1, start, total = chains[8:]
    (Gi, si, _), (Gj, sj_, _), (GK, SK, VK) = enc_i, enc_j, enc_k
    Df, sf = Gi - Gj, si + sj_
    jr = P.jb[rows]
    pos = start[P.seg[rows]] + P.sm[rows]
    for KK, OTHER, want in ((K0, K1, 1.0), (K1, K0, -1.0)):
        sel = np.nonzero((KK[jr] == ks[:, None]).any(1) & ~okk)[0]
        if not len(sel):
            continue
        r_ = rows[sel]
        Dg = GK[sel] - Gi[r_]
        sg_ = si[r_] + SK[sel]
        rf = rot90(Df[r_])
        tt = (rf * P.Tn[r_]).sum(1)
        dec_t = np.abs(tt) > sf[r_]
        val = np.sign(tt) * (Dg * rf).sum(1)
        err = np.hypot(*Dg.T) * sf[r_] + np.hypot(*Df[r_].T) * sg_ + sf[r_] * sg_
        t3 = dec_t & VK[sel] & (want * val - err * (1 + 1e-9) - 1e-12 > 0)
        half_ok = (pos[sel] <= 0.5 * total[jr[sel]]) if want > 0 else (pos[sel] > 0.5 * total[jr[sel]])
        same = (OTHER[jr[sel]] == ks[sel][:, None]).any(1)
        t3 &= ~same | half_ok
        okk[sel] |= t3


def _support_half_planes(sup, P: _Pieces, rows, ks, Vi, Vj, enc_i, enc_j, levels=None):
    """(T2) by supporting half-planes (module docstring): True per row (piece, site k) with
    d_k − d_s > 0 on the piece's disc B(C, R) for s = i or j.  With u* = ∇d_s(C) and p* the
    nearest point of s to C, for q in the disc, √(a² + b²) ≤ a + b²/(2a) on the components of
    q − p* along and across u* gives d_s(q) ≤ |q − p*| ≤ d_s(C) + u*·(q − C) + R²/(2(d_s(C) − R));
    every unit u gives d_k(q) ≥ u·(q − m) − h_k(u) (h_k the support function about m).  With u
    the unit float gradient of the pieces' enclosures G ± e (:func:`gradient_enclosure`, valid on
    the disc, hence at C), |u − u*| ≤ 2e, the terms in q cancel up to R·|u − u*|:

        d_k − d_s ≥ u·(C − m) − h_k(u) − hi_s(C) − R²/(2(lo_s(C) − R)) − 2e·R.

    No trigonometry and no foot point of k: far from the sites, where the pieces are long and
    every site comes within reach, this decides most rows before the table is called.
    ``levels``: (pcs, U, base) of :func:`_half_plane_levels` for sorted pieces pcs holding every
    row (computed here when None)."""
    if levels is None:
        pcs, inv = np.unique(rows, return_inverse=True)
        U, base = _half_plane_levels(sup, P, pcs, Vi, Vj, enc_i, enc_j)
    else:
        pcs, U, base = levels
        inv = np.searchsorted(pcs, rows)
    best = np.full(len(rows), -np.inf)
    for s_ in (0, 1):
        hk = sup.support_at(ks, U[inv, s_])
        best = np.maximum(best, base[inv, s_] - hk - 2 * sup.mu - 1e-12 * np.abs(hk))
    return best > 0


def _half_plane_levels(sup, P: _Pieces, pcs, Vi, Vj, enc_i, enc_j):
    """(U, base) of :func:`_support_half_planes` on the pieces pcs: per piece and s = i, j (axis 1)
    the unit float gradient u of s's enclosure at C and the level
    u·(C − m) − hi_s(C) − R²/(2(lo_s(C) − R)) − 2e·R − 10⁻¹²·size (−inf where the enclosure is not
    valid on the disc, lo_s ≤ R or |G| ≤ 1/2), so that a site k with
    base − h_k(u) − 2·mu − 10⁻¹²·|h_k(u)| > 0 is farther than s on the piece's disc."""
    Cm = P.C[pcs] - sup.m
    R = P.R[pcs]
    U = np.empty((len(pcs), 2, 2))
    base = np.empty((len(pcs), 2))
    for s_, (V, (Ge, ee, ve)) in enumerate(((Vi, enc_i), (Vj, enc_j))):
        Vp = V.take(pcs)
        G, e, valid = Ge[pcs], ee[pcs], ve[pcs]
        nG = np.hypot(G[:, 0], G[:, 1])
        ok = valid & (Vp.lo > R) & (nG > 0.5) & np.isfinite(e)
        u = G / np.where(ok, nG, 1.0)[:, None]
        loss = R * R / (2 * np.where(ok, Vp.lo - R, 1.0)) * (1 + 1e-12) + 2 * (e + 4 * EPS) * R * (1 + 1e-12)
        b_ = (u * Cm).sum(1) - Vp.hi - loss
        size = np.abs(Cm).sum(1) + np.abs(Vp.hi) + sup.W
        U[:, s_] = u
        base[:, s_] = np.where(ok, b_ - 1e-12 * size, -np.inf)
    return U, base


def _third_sites(table, scale, chains, P: _Pieces, pre, Vi, Vj, enc_i, enc_j, sup=None):
    """(T2)/(T3) on the pieces where (T1) and (T4) hold: every site whose bounding box comes
    within min(hi_i, hi_j) + 2R of the piece's centre (:meth:`SiteTable.near_pairs`) is farther
    (by supporting half-planes when the support functions ``sup`` are given,
    :func:`_support_half_planes`, whose levels also leave out whole groups of sites in
    ``near_pairs``; else :func:`_farther`) or, tied at an end vertex, moves away along the arc
    (:func:`_tied_derivative`).  True per piece where all of them pass."""
    p = len(P.seg)
    third_ok = np.ones(p, bool)
    hi = np.minimum(Vi.hi, Vj.hi)
    pidx = np.nonzero(pre)[0]
    levels = None
    if sup is not None and len(pidx):
        # the half-plane levels once per piece: they drop whole groups of sites in near_pairs
        levels = (pidx, *_half_plane_levels(sup, P, pidx, Vi, Vj, enc_i, enc_j))
    rows, ks = table.near_pairs(P.C[pidx], (hi + 2 * P.R)[pidx], (P.Ip[pidx], P.Jp[pidx]),
                                levels=None if levels is None else (levels[1], levels[2], sup.m, sup.mu))
    rows = pidx[rows]
    if sup is not None and len(rows):
        keep = ~_support_half_planes(sup, P, rows, ks, Vi, Vj, enc_i, enc_j, levels)
        rows, ks = rows[keep], ks[keep]
    if len(rows):
        Vk = evaluate_rows(table, P.C[rows], ks)
        enc_k = gradient_enclosure(P.C[rows], Vk, P.R[rows], scale)
        okk = _farther(table, scale, P, rows, Vk, Vi, Vj, enc_i, enc_j, enc_k)
        _tied_derivative(chains, P, rows, ks, okk, enc_i, enc_j, enc_k)
        np.logical_and.at(third_ok, rows, okk)
    return third_ok


def _test_pieces(table, scale, depth, sigma, seg, sa, sb, chains, sup=None):
    """(T1)–(T4) on the pieces (seg, [sa, sb]) of :func:`prove_strips_many`: (good, t1, side_ok) per
    piece.  At depth 0, σ of each chain without one is set from its first piece decided here.
    Two evaluation rows per piece (i and j at the centre), four more (at both side midpoints) where
    (T4) is not decided from the centre."""
    P = _pieces(scale, seg, sa, sb, chains)
    p = len(sa)
    V = evaluate_rows(table, np.concatenate([P.C, P.C]), np.concatenate([P.Ip, P.Jp]))
    Vi, Vj = V.part(0, p), V.part(p, 2 * p)
    enc_i = gradient_enclosure(P.C, Vi, P.R, scale)
    enc_j = gradient_enclosure(P.C, Vj, P.R, scale)
    t1 = _monotone(table, depth, sigma, P, Vi, Vj, enc_i, enc_j)
    side_ok = _sides(table, scale, chains[5], sigma, P, t1, enc_i, enc_j, Vi, Vj)
    pre = t1 & side_ok
    third_ok = _third_sites(table, scale, chains, P, pre, Vi, Vj, enc_i, enc_j, sup)
    return pre & third_ok, t1, side_ok


def _ties(k) -> tuple:
    return () if k is None else ((k,) if np.isscalar(k) else tuple(k))


def _chains(jobs):
    """The segments of all jobs in flat arrays: ``chains`` = (job of each segment, start S, unit
    direction T, normal N, half-width W0 at the start and slope (w(s) = W0 + slope·s: trapezoids),
    pair I, J, the sites tied with the pair at the first (K0) and last (K1) vertex, −1 padded —
    one at a simple vertex, k − 2 at a vertex of degree k —, each segment's start along its chain,
    each chain's length), and the lengths, smaller half-widths and cap extensions of the segments."""
    nj = len(jobs)
    sj = np.repeat(np.arange(nj), [len(jb.L) for jb in jobs])
    Sg = np.concatenate([jb.S[:-1] for jb in jobs])
    Tg = np.concatenate([jb.T for jb in jobs])
    Ng = np.concatenate([jb.N for jb in jobs])
    Lg = np.concatenate([jb.L for jb in jobs])
    W0 = np.concatenate([jb.W[:-1] for jb in jobs])
    slope = (np.concatenate([jb.W[1:] for jb in jobs]) - W0) / Lg
    Wmin = np.minimum(W0, np.concatenate([jb.W[1:] for jb in jobs]))
    elo = np.concatenate([jb.e_lo for jb in jobs])
    ehi = np.concatenate([jb.e_hi for jb in jobs])
    start = np.concatenate([np.concatenate([[0.0], np.cumsum(jb.L)[:-1]]) for jb in jobs])
    total = np.array([float(jb.L.sum()) for jb in jobs])
    I = np.array([jb.pair[0] for jb in jobs])
    J = np.array([jb.pair[1] for jb in jobs])
    width = max([1] + [len(_ties(jb.k0)) for jb in jobs] + [len(_ties(jb.k1)) for jb in jobs])
    K0 = np.full((nj, width), -1)
    K1 = np.full((nj, width), -1)
    for t, jb in enumerate(jobs):
        K0[t, :len(_ties(jb.k0))] = _ties(jb.k0)
        K1[t, :len(_ties(jb.k1))] = _ties(jb.k1)
    return (sj, Sg, Tg, Ng, W0, slope, I, J, K0, K1, start, total), Lg, Wmin, elo, ehi


def _initial_pieces(Lg, Wmin, elo, ehi):
    """(seg, sa, sb): each segment with its caps [−e_lo, L + e_hi] cut into pieces PIECE times as
    long as the strip is wide (at most 400 per segment)."""
    init = np.minimum(np.maximum(np.ceil((Lg + elo + ehi) / (2 * PIECE * Wmin)).astype(int), 1), 400)
    seg = np.repeat(np.arange(len(Lg)), init)
    r = np.arange(len(seg)) - np.repeat(np.cumsum(init) - init, init)
    span = (Lg + elo + ehi)[seg]
    return seg, -elo[seg] + r / init[seg] * span, -elo[seg] + (r + 1) / init[seg] * span


def _test_groups(table, depth, sigma, seg, sa, sb, chains, sup=None):
    """:func:`_test_pieces` on the pieces in groups of at most ROWS_PER_CALL / 6 (at most six
    evaluation rows per piece): memory bounded independently of N; every piece is tested as in one group
    (row-wise tests; σ of a chain is set at its first decided piece, before any piece needs it)."""
    p = len(sa)
    good, t1, side_ok = np.zeros(p, bool), np.zeros(p, bool), np.zeros(p, bool)
    step = max(1, ROWS_PER_CALL // 6)
    for a0 in range(0, p, step):
        g_, t_, s_ = _test_pieces(table, table.scale, depth, sigma, seg[a0:a0 + step], sa[a0:a0 + step],
                                  sb[a0:a0 + step], chains, sup)
        good[a0:a0 + step], t1[a0:a0 + step], side_ok[a0:a0 + step] = g_, t_, s_
    return good, t1, side_ok


def _failures(out, chains, seg, sm, jb, good, t1, side_ok, give_up) -> None:
    """The message of each chain given up: the first undecided piece and the first of (T1), (T4),
    (T2)/(T3) that it failed."""
    Sg, Tg = chains[1], chains[2]
    badidx = np.nonzero(~good & give_up[jb])[0]
    tj, first = np.unique(jb[badidx], return_index=True)
    for t, b in zip(tj, badidx[first]):
        what = ("monotonicity" if not t1[b] else
                "the bisector leaves the polyline's strip" if not side_ok[b] else "a third site")
        Cb = Sg[seg[b]] + sm[b] * Tg[seg[b]]
        out[t] = (False, f"not proved near ({Cb[0]:.9g}, {Cb[1]:.9g}): {what} undecided")


def prove_strips_many(table, jobs, sup=None):
    """(T1)–(T4) for many :class:`StripsJob` at once: the pieces of all chains in flat arrays,
    two calls of ``table.evaluate`` per round of halving.  Returns (ok, message or None) per job.
    Per round: a chain whose pieces all pass is proved; one with failing pieces gives up at
    MAX_DEPTH, past its work limits (:data:`MAX_FAILING` failing pieces, :data:`MAX_WORK` tested, or its ``budget``
    spent), or when halving has decided almost no piece for STALL rounds (the strip, not the
    pieces, is too wide: R stays ≥ w; the caller narrows it); otherwise its failing pieces are
    halved and the passing ones are done.  ``sup``: the sites' support functions
    (:class:`runtime.voronoi.verify.support.SupportTable`, all sites bounded and convex), which
    decide (T2) first where they can (:func:`_support_half_planes`)."""
    nj = len(jobs)
    out = [None] * nj
    chains, Lg, Wmin, elo, ehi = _chains(jobs)
    seg, sa, sb = _initial_pieces(Lg, Wmin, elo, ehi)
    sigma = np.zeros(nj)
    work, stall = np.zeros(nj, int), np.zeros(nj, int)
    for depth in range(MAX_DEPTH):
        if not len(sa):
            break
        jb = chains[0][seg]
        good, t1, side_ok = _test_groups(table, depth, sigma, seg, sa, sb, chains, sup)
        if depth == 0:
            for t in np.nonzero(sigma == 0)[0]:
                out[t] = (False, "the bisector's direction is not decided (monotonicity)")
        sm = 0.5 * (sa + sb)
        running = np.array([o is None for o in out])
        cnt = np.bincount(jb, minlength=nj)
        nbad = np.bincount(jb[~good], minlength=nj)
        work += cnt
        for t in np.nonzero(cnt)[0]:
            if jobs[t].budget is not None:
                jobs[t].budget.left -= int(cnt[t])
        stall = np.where((cnt > 0) & (nbad > 0.98 * cnt) & (depth >= 2), stall + 1, 0)
        spent = np.array([jb_.budget is not None and jb_.budget.left < 0 for jb_ in jobs])
        for t in np.nonzero(running & (cnt > 0) & (nbad == 0))[0]:
            out[t] = (True, None)
        give_up = running & (nbad > 0) & ((depth == MAX_DEPTH - 1) | (nbad > MAX_FAILING) | (work > MAX_WORK)
                                          | (stall >= STALL) | spent)
        if give_up.any():
            _failures(out, chains, seg, sm, jb, good, t1, side_ok, give_up)
        still = np.array([o is None for o in out])
        bad = ~good & still[jb]
        # keep the good pieces out; halve the bad ones
        seg = np.concatenate([seg[bad], seg[bad]])
        sa, sb = np.concatenate([sa[bad], sm[bad]]), np.concatenate([sm[bad], sb[bad]])
    return [o if o is not None else (False, "not proved") for o in out]
