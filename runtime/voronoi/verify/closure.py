"""Closure and accounting steps (3 and 4) of the diagram certificate :mod:`runtime.voronoi.verify.certificate`.

* :func:`verify_closure`: every vertex has exactly one edge per pair of its sites, every site has
  an edge, edges of one pair do not overlap on their bisector.
* :func:`verify_accounting`: nesting depth <= 1 (thesis Prop. 1.2.1: components without points at
  infinity come from nested sites) and the ends at infinity: consecutive unbounded ends, sorted by
  asymptotic direction, share a site that strictly maximises the support function
  h_k(θ) = c_k·e(θ) + ρ_k on the arc between them (circle and point sites).
* :func:`verify_accounting_conics`: the same for bounded convex sites (ellipses, circles, points)
  with support functions: convex hulls pairwise disjoint (no nesting), and the intervals of
  directions of the unbounded ends (from :func:`runtime.voronoi.verify.tail.prove_tail`)
  separated by arcs on which one site strictly leads.
"""
from __future__ import annotations

import math

import numpy as np

from ...certify.cell_cover import CellTest, walk_cells
from .far_accounting import accounting_unbounded
from .hull_nesting import gap_note, hulls_disjoint, sole_leader
from .problems import fault
from .support_balls import sole_maximum
from .ties_at_infinity import tied_sectors
from .vertices import vname as _vname

__all__ = ["verify_closure", "verify_accounting", "verify_accounting_conics", "circles_disjoint"]

ANGLE_TOL = 1e-9        # margin for the angular accounting at infinity


def verify_closure(D, n, problems, intervals) -> bool:
    """Step 3 of :mod:`runtime.voronoi.verify.certificate`: incidences (one edge per consecutive pair of
    a vertex's sites), sites without edges, overlaps."""
    ok = True
    inc: dict = {}
    for e in D.edges:
        pair = tuple(int(s) for s in e.sites)
        for vid in e.ends:
            if vid is not None:
                inc.setdefault((vid, pair), []).append(e.id)
    for v in D.vertices:
        sites = [int(s) for s in v.sites]
        if len(sites) < 3 or len(set(sites)) != len(sites):
            ok = False
            continue
        # one edge per cyclically consecutive pair (for three sites: every pair); the vertex proof
        # checked that the sites are listed counter-clockwise by their contact points
        k = len(sites)
        for p in sorted({tuple(sorted((sites[t], sites[(t + 1) % k]))) for t in range(k)}):
            got = inc.get((v.id, p), [])
            if len(got) != 1:
                ok = False
                problems.append(fault(f"{_vname(v)}: {'no' if not got else len(got)} edge{'s' if len(got) > 1 else ''} "
                                      f"({p[0]}, {p[1]}) end{'s' if len(got) <= 1 else ''} here",
                                      kind="vertex", vertex=v.id, sites=sites))
    if n >= 2:
        has = np.zeros(n, bool)
        for e in D.edges:
            for s in e.sites:
                if 0 <= int(s) < n:
                    has[int(s)] = True
        for k in np.nonzero(~has)[0][:20]:
            ok = False
            problems.append(fault(f"site {int(k)} has no edge: its region is missing", kind="site", sites=(k,)))
    # a closed edge is a whole component of its bisector: no other edge of its pair is accepted
    # (a repeated loop would otherwise pass; two components of one bisector are not handled)
    by_pair: dict = {}
    for e in D.edges:
        by_pair.setdefault(tuple(sorted(int(s) for s in e.sites)), []).append(e)
    for pair, es in by_pair.items():
        loops = [e for e in es if e.closed]
        if loops and len(es) > 1:
            ok = False
            other = next(e for e in es if e is not loops[0])
            problems.append(f"edges {loops[0].id} and {other.id} (sites {pair[0]}, {pair[1]}): the closed edge "
                            "is the whole bisector loop, a second edge of the pair is not accepted")
    # edges of one pair must not overlap (the same part of a bisector reported twice)
    for pair, ivs in intervals.items():
        if len(ivs) < 2:
            continue
        hyper = [iv for iv in ivs if iv[0] == "hyperbola"]
        hyper.sort(key=lambda iv: iv[1])
        for a, b in zip(hyper, hyper[1:]):
            if b[1] < a[2] - 1e-12:
                ok = False
                problems.append(fault(f"edges {a[3]} and {b[3]} (sites {pair[0]}, {pair[1]}) overlap on their bisector",
                                      kind="edge", edge=a[3], sites=pair))
        if any(iv[0] == "ellipse" for iv in ivs):
            tot = sum(iv[2] - iv[1] for iv in ivs if iv[0] == "ellipse")
            if tot > 2 * math.pi + 1e-9:
                ok = False
                problems.append(fault(f"edges of sites {pair[0]}, {pair[1]} cover their bisector more than once",
                                      kind="edge", sites=pair))
    return ok


# ============================================================================ accounting

def verify_accounting(n, table, ends_inf, problems, unproved_ends=()) -> bool:
    """Step 4 of the module docstring: nesting depth and the ends at infinity (circles/points).
    ``unproved_ends``: ids of unbounded edges whose end at infinity is not in ``ends_inf`` (their
    proof failed); a gap in the ends is then reported as possibly theirs (:func:`_gap_note`)."""
    if n < 2:
        return True
    C, R = table.C, table.R
    if not circles_disjoint(table, problems):
        return False
    # nesting: k inside the disc of J
    nested_in = [[] for _ in range(n)]
    contains = [[] for _ in range(n)]
    big = np.nonzero(R > 0)[0]
    for J in big:
        ks = table.tree.query_ball_point(C[J], R[J])
        for k in ks:
            if k != J and math.hypot(*(C[k] - C[J])) + R[k] < R[J]:
                nested_in[k].append(int(J))
                contains[int(J)].append(int(k))
    ok = True
    for k in range(n):
        if nested_in[k] and contains[k]:
            ok = False
            problems.append(f"site {k} lies inside site {nested_in[k][0]} and contains site {contains[k][0]}: "
                            "nesting depth > 1 is not handled by the completeness proof")
            break
    # ends at infinity
    outer = [k for k in range(n) if not nested_in[k]]
    if not ends_inf:
        if len(outer) == 1:
            return ok
        problems.append("no unbounded edge is proved, but several outer sites have unbounded regions")
        return False
    ends = sorted(ends_inf, key=lambda t: t[0])
    m = len(ends)
    if m < 2:
        problems.append(fault("a single unbounded edge end: the ends at infinity do not close up", kind="infinity"))
        return False
    for a in range(m):
        ea, eb = ends[a], ends[(a + 1) % m]
        ta, tb = ea[0], eb[0]
        L = (tb - ta) % (2 * math.pi)
        if m == 2 and a == 1 and L == 0:
            L = 2 * math.pi
        shared = set(ea[1]) & set(eb[1])
        if not shared:
            problems.append(fault(f"unbounded edges {ea[3]} and {eb[3]} are consecutive at infinity but share no "
                                  "site: " + gap_note(unproved_ends), kind="infinity", sites=(*ea[1], *eb[1])))
            ok = False
            continue
        if not any(_dominates(s, ta, L, ea[1], eb[1], C, R) for s in shared):
            problems.append(fault(f"between the unbounded edges {ea[3]} and {eb[3]} no single site owns all far "
                                  "directions: an unbounded edge is missing or misplaced", kind="infinity",
                                  sites=(*ea[1], *eb[1])))
            ok = False
    return ok


def circles_disjoint(table, problems) -> bool:
    """Are the circle/point sites pairwise disjoint (float with a margin: a pair that cannot be
    separated counts as meeting)?"""
    C, R = table.C, table.R
    tol = 1e-12 * table.scale
    # candidate pairs (a, b): b within R_a + R_b + tol of a; b small (R_b <= r_small) through the
    # tree, b big (table.big) one by one
    A, B = table.big_near(C, R + tol)
    lists = table.tree.query_ball_point(C, R + table.r_small + tol)
    counts = np.fromiter((len(js) for js in lists), int, len(lists))
    A = np.concatenate([A, np.repeat(np.arange(len(lists)), counts)]).astype(int)
    B = np.concatenate([B, np.fromiter((b for js in lists for b in js), int, int(counts.sum()))]).astype(int)
    keep = A != B
    A, B = np.minimum(A[keep], B[keep]), np.maximum(A[keep], B[keep])
    dd = np.hypot(C[A, 0] - C[B, 0], C[A, 1] - C[B, 1])
    meet = (dd <= R[A] + R[B] + tol) & (dd >= np.abs(R[A] - R[B]) - tol)
    if meet.any():
        first = np.lexsort((B[meet], A[meet]))[0]
        a, b = int(A[meet][first]), int(B[meet][first])
        problems.append(fault(f"sites {a} and {b} intersect or touch (or are too close to decide): "
                              "the diagram of non-disjoint sites is not proved", kind="site", sites=(a, b)))
        return False
    return True


def _dominates(s, ta, L, pa, pb, C, R) -> bool:
    """Does site s strictly maximise h_k(θ) = c_k·e(θ) + ρ_k over θ ∈ [ta, ta + L], ties allowed
    only with the other site of pair pa at ta and of pair pb at ta + L?"""
    n = len(R)
    others = np.array([k for k in range(n) if k != s], int)
    if not len(others):
        return True
    Dv = C[s] - C[others]
    nd = np.hypot(Dv[:, 0], Dv[:, 1])
    dr = R[s] - R[others]
    psi = np.arctan2(Dv[:, 1], Dv[:, 0])
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(nd > 0, -dr / nd, np.where(dr > 0, -np.inf, np.inf))
    always = ratio < -1           # D_k > 0 for every direction (k nested in s)
    never = ratio >= 1
    if never.any():
        return False
    beta = np.arccos(np.clip(ratio, -1.0, 1.0))
    start = (ta - (psi - beta)) % (2 * math.pi)       # position of ta in the positive arc (0, 2β)
    start = np.where(start > 2 * math.pi - ANGLE_TOL, start - 2 * math.pi, start)
    pa_o = [k for k in pa if k != s][0]
    pb_o = [k for k in pb if k != s][0]
    tie_a = (others == pa_o)
    tie_b = (others == pb_o)
    lo_ok = np.where(tie_a, start >= -ANGLE_TOL, start > ANGLE_TOL)
    end = start + L
    hi_ok = np.where(tie_b, end <= 2 * beta + ANGLE_TOL, end < 2 * beta - ANGLE_TOL)
    good = always | (lo_ok & hi_ok)
    return bool(good.all())


# ============================================================================ accounting, conic sites

def verify_accounting_conics(n, sup, ends_inf, problems, max_work: int = 400000, unproved_ends=(), sites=None) -> bool:
    """Step 4 of :mod:`runtime.voronoi.verify.certificate` for bounded convex sites (ellipses, circles, points)
    with the support functions h_k of :class:`runtime.voronoi.verify.support.SupportTable`.

    (b) The convex hulls of the sites are proved pairwise disjoint (a separating direction u with
    h_a(u) + h_b(−u) < 0, or disjoint bounding boxes), or one inside the open convex region of a
    circle or ellipse (h_in < h_out in every direction), with nesting depth ≤ 1 (no container is
    itself nested).  By thesis Prop. 1.2.1 a component of G without points at infinity lies
    inside a container; it contains an edge of the region of a nested site K, whose boundary is
    connected, so it contains that boundary, and H holds an edge of K (step 3) and is closed
    under incidence: the component is in H.  (Nested sites never lead at infinity: h_K < h_out.)
    (a) Each unbounded end e of H (pair i, j) comes with its sector [θa, θb] from
    :func:`runtime.voronoi.verify.tail.prove_tail`: there only i and j attain max_k h_k, h_i − h_j
    has strict opposite signs at θa and θb, and β_ij ∩ {t ≥ T, θ ∈ [θa, θb]} is the edge's tail.
    Here two sectors of one pair are proved disjoint, and on every closed arc of directions that no
    sector covers one site (shared by the pairs of the sectors on either side) strictly maximises
    h_k (cells with |h_s' − h_k'| ≤ 2W).  Then every direction where two sites tie for the maximum
    lies in an open sector of their pair and in no sector of another pair (where another site
    would be the only maximiser).  An unbounded edge of G with sites i', j' has its accumulation
    directions θ' at such ties (d_k(m + t·u) = t − h_k(u) + O(W²/t)); they form a connected set A,
    split into the disjoint relatively open sets A ∩ (open sector of e), so A lies in one open
    sector, of the pair {i', j'}; so the edge eventually enters that sector's region
    {t ≥ T, θ ∈ [θa, θb]}, where β_i'j' is the reported tail: the edge is the reported one.
    With no unbounded end reported, one site must lead in every direction
    (:func:`runtime.voronoi.verify.hull_nesting.sole_leader`: all others inside its convex region),
    so that G has no unbounded edge either.
    """
    if n < 2:
        return True
    if not sup.ok:
        # a parabola or a hyperbola among the sites: asymptotic functions instead of support functions
        return accounting_unbounded(sup.geoms, ends_inf, problems, max_work, unproved_ends)
    if not hulls_disjoint(sup, problems, max_work):
        return False
    # ---- (a) the ends at infinity
    if not ends_inf:
        if sole_leader(sup, max_work) is not None:
            return True          # every other site inside one container: no unbounded edge at all
        problems.append("no unbounded edge is proved, but several sites have unbounded regions")
        return False
    ends = _sectors_at_infinity(sup, sites, ends_inf, problems)
    if ends is None:
        return False
    if len(ends) < 2:
        problems.append(fault("a single unbounded edge end: the ends at infinity do not close up", kind="infinity"))
        return False
    ok = _sectors_of_one_pair_disjoint(ends, problems)
    return _uncovered_arcs_owned(sup, ends, problems, max_work, unproved_ends) and ok


def _sectors_at_infinity(sup, sites, ends_inf, problems):
    """The proved sectors of the ends at infinity, sorted by their first direction, as (a0, a1,
    pair, edge id, pair leaving the sector): a sector of :func:`runtime.voronoi.verify.tail.
    prove_tail`, or the small sector about a direction where several sites tie
    (:func:`runtime.voronoi.verify.ties_at_infinity.tied_sectors`); None when the ties fail."""
    ends = []
    mirror = [t for t in ends_inf if t[2][0] == "mirror"]
    for _, pair, (tha, thb), eid in (t for t in ends_inf if t[2][0] != "mirror"):
        a0 = tha % (2 * math.pi)
        ends.append((a0, a0 + (thb - tha), pair, eid, pair))
    if mirror:
        tied = tied_sectors(sup, sites, mirror, problems)
        if tied is None:
            return None
        ends.extend(tied)
    ends.sort(key=lambda t: t[0])
    return ends


def _sectors_of_one_pair_disjoint(ends, problems) -> bool:
    """Two ends of one pair must have disjoint sectors (step (a))."""
    ok = True
    m = len(ends)
    for a in range(m):
        for b in range(a + 1, m):
            ea, eb = ends[a], ends[b]
            if set(ea[2]) == set(eb[2]):
                lo, hi = eb[0] - ea[0], eb[1] - ea[0]
                L = ea[1] - ea[0]
                if not (lo > L and hi < 2 * math.pi):
                    problems.append(fault(f"unbounded edges {ea[3]} and {eb[3]} of sites {ea[2][0]}, {ea[2][1]} "
                                          "have overlapping asymptotic sectors", kind="infinity", sites=ea[2]))
                    ok = False
    return ok


def _uncovered_arcs_owned(sup, ends, problems, max_work, unproved_ends) -> bool:
    """Walk around the circle of directions: on every arc no sector covers, one site shared by
    the pairs of the sectors on either side strictly maximises h_k (step (a))."""
    ok = True
    m = len(ends)
    cur, cur_end = ends[0], ends[0][1]
    for t in range(1, m + 1):
        nxt = ends[t % m]
        a_next = nxt[0] + (2 * math.pi if t == m else 0.0)
        if a_next > cur_end:
            shared = set(cur[4]) & set(nxt[2])
            if not shared:
                problems.append(fault(f"unbounded edges {cur[3]} and {nxt[3]} are consecutive at infinity but share "
                                      "no site: " + gap_note(unproved_ends), kind="infinity",
                                      sites=(*cur[4], *nxt[2])))
                ok = False
            elif not any(_dominates_conic(sup, s, cur_end, a_next, max_work)
                         or sole_maximum(sup, s, cur_end, a_next) for s in shared):     # near-ties: balls
                problems.append(fault(f"between the unbounded edges {cur[3]} and {nxt[3]} no single site owns all "
                                      "far directions: an unbounded edge is missing or misplaced", kind="infinity",
                                      sites=(*cur[4], *nxt[2])))
                ok = False
        if t < m and nxt[1] > cur_end:
            cur, cur_end = nxt, nxt[1]
    return ok


def _dominates_conic(sup, s, g0, g1, max_work) -> bool:
    """Is h_s(θ) > h_k(θ) for every k ≠ s and θ ∈ [g0, g1]?  Cells halved until decided; on a cell
    of half-width δ, h_s − h_k ≥ (h_s − h_k)(θc) − 2W·δ − 2μ (|h'| ≤ W)."""
    n = sup.n
    W, mu = sup.W, sup.mu
    ks = np.array([k for k in range(n) if k != s], int)
    if not len(ks):
        return True
    nc = 16
    e = np.linspace(g0, g1, nc + 1)
    a, b = np.tile(e[:-1], len(ks)), np.tile(e[1:], len(ks))
    K = np.repeat(ks, nc)

    def test(c, half, K):
        hs = sup.h(s, c)
        hk = sup.h(K, c)                       # elementwise: h_{K[r]}(c[r]), the same floats
        d = hs - hk
        good = d - 2 * W * half - 2 * mu > 0
        # fault: some other site is strictly larger at a direction of the gap
        return CellTest(fault=d + 2 * mu < 0, undecided=~good)

    return walk_cells(a, b, test, max_work, carry=(K,)).proved
