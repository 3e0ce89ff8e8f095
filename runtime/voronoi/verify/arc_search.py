"""The disc search of :mod:`runtime.voronoi.verify.edges` (its docstring, item 1): d_k > d_i on a
finite arc of the bisector of two circle/point sites, for every third site k, many edges at once.

The arc is cut into pieces; each piece lies in a disc around its mid point q_m (radius R: the
larger arc length to an end, plus the rounding bound of the float curve).  Every distance
function is 1-Lipschitz, so d_k − d_i ≥ lo_k(q_m) − hi_i(q_m) − 2R on the piece; sharper, d_k −
d_i changes by at most L·(arc length) with L ≥ |∇d_k − ∇d_i| on the disc (:func:`_slope_bound`).
Candidate sites come once from the k-d tree of the centres; a piece that does not decide a site
is halved and its halves re-test only that site.

2. **Support cones** (a hyperbola arc outside circle i): for q on the arc, with u_q = (q −
c_i)/|q − c_i|, d_i(q) = (q − c_i)·u_q − ρ_i and d_k(q) ≥ |q − c_k| − ρ_k ≥ (q − c_k)·u_q − ρ_k, so

    d_k(q) − d_i(q) ≥ (c_i − c_k)·u_q + ρ_i − ρ_k = h_i(u_q) − h_k(u_q),

h the support function of a site's disc.  The arc of a piece lies in the triangle of its ends and
the meeting point of their tangents (a convex arc), so its directions u_q lie within κ of one
unit vector u_0 (:meth:`_Curves.cones`), and (c_i − c_k)·u_q ≥ (c_i − c_k)·u_0 − |c_i − c_k|·κ.
Near the hull the pieces' empty discs are nearly half-planes; their arcs run nearly radially
away from c_i and κ is small (about |c_i − c_j|·(1/t_a − 1/t_b) for the distances t of the ends),
so this decides every site but those nearly as far out in direction u_0 as site i — where the
disc bound 1 needs pieces far shorter than the scene's spacing, with every site a candidate.
Such a piece lists its candidates from the k-d tree as the sites meeting a ball far out in
direction u_0 whose boundary follows the line h_i(u_0) − D_i·κ across the sites (D_i bounding
|c_k − c_i|; :func:`_queries`), not the sites meeting the ball of its disc.

Memory: pieces whose disc is large next to their distance to the sites are halved before the
candidates are listed (few candidates per piece), and the (piece, candidate) pairs are searched
in groups of at most :data:`PAIRS` (a piece far outside the sites' hull can have every site as a
candidate), so the search takes memory independent of the number of edges.
"""
from __future__ import annotations

import time

import numpy as np

from .edges import EPS, MAX_DEPTH, SMALL_TABLE, CircleTable

__all__ = ["prove_arcs", "BATCH", "PAIRS", "REFINE"]


def _slope_bound(table: CircleTable, Q, ks, I, R):
    """Bound on |∇d_k − ∇d_i| over the discs B(Q, R) (first-order enclosure along the arc): for
    a circle/point site the gradient of d is the unit vector ±(q − c)/|q − c|, which moves by at
    most R/(|Q − c| − R) over the disc when the disc stays on one side of the circle; otherwise
    the Lipschitz constant 2.

    When the disc lies outside both sites (both gradients +(q − c)/|q − c|), also the direct
    bound |a/|a| − b/|b|| ≤ 2|a − b|/|b| (a = q − c_k, b = q − c_i, so a − b = c_i − c_k): at most
    2|c_i − c_k|/(|Q − c_i| − R) on the disc.  Far from the sites (the arcs near the hull, whose
    empty discs are nearly half-planes) this is much smaller than the turn of each gradient,
    R/(|Q − c| − R), which stays near 1 on a piece as long as its distance."""
    out = np.full(len(Q), 2.0)
    dirs, ok, lip, outside = [], np.ones(len(Q), bool), np.zeros(len(Q)), np.ones(len(Q), bool)
    for s in (ks, I):
        V = Q - table.C[s]
        nv = np.hypot(V[:, 0], V[:, 1])
        side = nv - table.R[s]
        ok &= (np.abs(side) > R * (1 + 1e-9)) & (nv > R * (1 + 1e-9))
        outside &= side > R * (1 + 1e-9)
        with np.errstate(divide="ignore", invalid="ignore"):
            dirs.append(np.sign(side)[:, None] * V / nv[:, None])
            lip += R / (nv - R)
    with np.errstate(invalid="ignore", divide="ignore"):
        L = np.hypot(*(dirs[0] - dirs[1]).T) * (1 + 1e-12) + 1e-15 + lip * (1 + 1e-12)
        Vi = Q - table.C[I]
        gap = np.hypot(*(table.C[I] - table.C[ks]).T)
        direct = 2 * gap / (np.hypot(Vi[:, 0], Vi[:, 1]) * (1 - 1e-12) - R) * (1 + 1e-9) + 1e-15
        L = np.where(outside & np.isfinite(direct) & (direct > 0), np.minimum(L, direct), L)
    return np.where(ok & np.isfinite(L), np.minimum(L, out), out)


BATCH = 4096          # jobs prepared together
PAIRS = 1 << 16       # (piece, candidate site) pairs searched together: memory O(PAIRS), not O(edges)
REFINE = 16           # at most this many halvings of the pieces before the candidate sites are listed
#: up to this many pieces (failing piece-site pairs in the search) in a round, a piece is cut into
#: 2, 4 or 8 as its margin asks (fewer rounds: a local update's proof is a few edges, where each
#: round's fixed cost dominates); above, halved (a whole diagram's edges, where the work dominates)
FEW_PIECES = 1024


def prove_arcs(table: CircleTable, jobs, init: int = 4, max_depth: int = MAX_DEPTH, max_pieces: int = 400000,
               deadline=None):
    """Prove d_k > d_i (= d_j) on the bisector arc u ∈ [ua, ub] for every site k ∉ {i, j} ∪ exempt,
    for many edges at once (module docstring, item 1): ``jobs`` is a list of (Bisector, ua, ub,
    exempt).  Returns a list of (ok, detail) in the order of ``jobs``; detail is None or
    (site k, (x, y), "closer" | "undecided").  ``max_depth``: halvings of a piece before a site is
    reported undecided; ``max_pieces``: undecided pieces (all jobs) before giving up, shared
    between the batches of :data:`BATCH` jobs in proportion to their size (each group of pieces of
    a batch searched together may use the batch's share); past ``deadline``
    (a :func:`time.perf_counter` value) the undecided jobs are reported "time limit".

    The arc of a job is cut into pieces (halved where the piece's disc is large next to the
    distance to the edge's sites, so that few sites are candidates); the pieces are searched in
    groups of at most :data:`PAIRS` candidate pairs (a piece far outside the sites' hull may have
    every site as a candidate); a job is proved when all its pieces are."""
    nj = len(jobs)
    out = [(True, None)] * nj
    npieces = 0
    for s in range(0, nj, BATCH):
        ctx = _Curves(table, jobs[s:s + BATCH])
        job, A, B = ctx.pieces(init)
        if len(job) * table.n <= PAIRS:
            ends = np.zeros(0, int)     # every (piece, site) pair fits one group (a small table)
        else:
            _, Q, _, _, R = ctx.discs(job, A, B)
            # the number of candidate sites of each piece, to group the pieces (an estimate: the big
            # circles of the table count for all, the others through the tree as CircleTable.near does)
            hi = np.minimum(table.bounds(Q, ctx.I[job])[1], table.bounds(Q, ctx.J[job])[1])
            P, reach = _queries(ctx, job, Q, R, hi, ctx.cones(job, A, B))
            count = (table.tree.query_ball_point(P, (reach + table.r_small) * (1 + 1e-9), return_length=True)
                     + 1 + len(table.big))
            ends = np.searchsorted(np.cumsum(count), np.arange(PAIRS, int(count.sum()) + PAIRS, PAIRS), side="right")
        start, alive, res = 0, np.ones(ctx.n, bool), [(True, None)] * ctx.n
        budget = max(1, max_pieces * ctx.n // nj)
        for end in np.unique(np.append(np.maximum(ends, 1), len(job))).tolist():
            if end <= start:
                continue
            npieces += _search(ctx, job[start:end], A[start:end], B[start:end], alive, res, max_depth, budget,
                               deadline)
            start = end
        out[s:s + ctx.n] = res
    prove_arcs.last_pieces = npieces
    return out


class _Curves:
    """The bisector curves of a group of jobs, as flat arrays."""

    def __init__(self, table, jobs):
        self.table, self.jobs, self.n = table, jobs, len(jobs)
        lo, hi = (table.C.min(axis=0), table.C.max(axis=0)) if table.n else (np.zeros(2), np.zeros(2))
        self.box_centre, self.box_half = 0.5 * (lo + hi), 0.5 * float(np.hypot(*(hi - lo)))
        self.hyp = np.array([b.kind == "hyperbola" for b, *_ in jobs])
        self.only_hyp = bool(self.hyp.all())
        self.M0 = np.array([b.m for b, *_ in jobs])
        self.EX = np.array([b.ex for b, *_ in jobs])
        self.EY = np.array([b.ey for b, *_ in jobs])
        self.Aa = np.array([b.a for b, *_ in jobs])
        self.Bb = np.array([b.b for b, *_ in jobs])
        self.Cc = np.array([b.c for b, *_ in jobs])
        self.E0 = np.array([b.err0 for b, *_ in jobs])
        self.I = np.array([b.i for b, *_ in jobs])
        self.J = np.array([b.j for b, *_ in jobs])
        self.X = np.full((self.n, max([2] + [len(j[3]) for j in jobs])), -1, int)
        for t, (_, _, _, ex) in enumerate(jobs):
            ex = sorted(ex)
            self.X[t, :len(ex)] = ex

    def pieces(self, init):
        """``init`` pieces per job (equal steps of sinh u on a hyperbola, of t on an ellipse),
        cut while a piece's disc radius exceeds half the distance from its mid point to the
        edge's sites: (job, A, B) with the pieces of a job consecutive."""
        f = np.linspace(0.0, 1.0, init + 1)
        hyp, jobs = self.hyp, self.jobs
        ua = np.array([j[1] for j in jobs])
        ub = np.array([j[2] for j in jobs])
        sa, sb = np.sinh(np.where(hyp, ua, 0.0)), np.sinh(np.where(hyp, ub, 0.0))
        K = np.where(hyp[:, None], np.arcsinh(sa[:, None] + f[None, :] * (sb - sa)[:, None]),
                     ua[:, None] + f[None, :] * (ub - ua)[:, None])
        K[:, 0], K[:, -1] = ua, ub
        job = np.repeat(np.arange(self.n), init)
        A, B = K[:, :-1].ravel(), K[:, 1:].ravel()
        for _ in range(REFINE):
            _, Q, _, _, R = self.discs(job, A, B)
            hi = np.minimum(self.table.bounds(Q, self.I[job])[1], self.table.bounds(Q, self.J[job])[1])
            big = R > 0.5 * hi
            if not big.any():
                break
            # a big piece is cut into 2, 4 or 8 equal parameter steps, about as many as bring its
            # disc below a quarter of the distance (the disc radius is about proportional to the
            # step); with few pieces, when each got all the steps it asked for, they are not
            # tested again (the search cuts any that still fail: this only saves a round)
            few = len(job) <= FEW_PIECES
            with np.errstate(all="ignore"):
                want = np.ceil(np.log2(R[big] / (0.25 * hi[big])))
            parts = np.left_shift(1, np.where(want >= 1, np.minimum(want, 3 if few else 1), 1)
                                  .astype(np.int64))   # NaN: 2
            done = few and bool((want <= 3).all())
            if len(job) + int(parts.sum()) - len(parts) > 64 * self.n:
                break
            jb, ab, bb = np.repeat(job[big], parts), np.repeat(A[big], parts), np.repeat(B[big], parts)
            pb = np.repeat(parts, parts)
            t = np.arange(len(pb)) - np.repeat(np.cumsum(parts) - parts, parts)
            a_new = ab + (bb - ab) * (t / pb)
            b_new = np.where(t + 1 == pb, bb, ab + (bb - ab) * ((t + 1) / pb))
            job = np.concatenate([job[~big], jb])
            A, B = np.concatenate([A[~big], a_new]), np.concatenate([B[~big], b_new])
            if done:
                break
        order = np.lexsort((A, job))
        return job[order], A[order], B[order]

    def discs(self, job, A, B):
        """For the pieces [A, B] of the jobs' curves: the mid parameters, the mid points q(u_m), the
        arc radii (the disc of that radius around q(u_m) holds the arc), the rounding bounds and
        the radii of the discs holding the float-evaluated arcs."""
        Mid = 0.5 * (A + B)
        h = self.hyp[job]
        Aa, Bb = self.Aa[job], self.Bb[job]
        if self.only_hyp:   # no ellipse: the values the np.where below take, with fewer operations
            with np.errstate(over="ignore"):
                sm = np.sinh(Mid)
                Q = self.M0[job] + (Aa * np.cosh(Mid))[:, None] * self.EX[job] + (Bb * sm)[:, None] * self.EY[job]
                Rh = self.Cc[job] * np.maximum(sm - np.sinh(A), np.sinh(B) - sm)
                err = 4 * self.E0[job] * np.cosh(np.minimum(np.maximum(np.abs(A), np.abs(B)), 700.0))
            err = err + 16 * EPS * (np.abs(Q).sum(axis=1) + 1.0)
            Rarc = Rh * (1 + 1e-12)
            return Mid, Q, Rarc, err, Rarc + err
        with np.errstate(over="ignore"):
            Xc = np.where(h, Aa * np.cosh(np.where(h, Mid, 0.0)), Aa * np.cos(Mid))
            Yc = np.where(h, Bb * np.sinh(np.where(h, Mid, 0.0)), Bb * np.sin(Mid))
        Q = self.M0[job] + Xc[:, None] * self.EX[job] + Yc[:, None] * self.EY[job]
        amax = np.maximum(np.abs(A), np.abs(B))
        with np.errstate(over="ignore"):
            Rh = self.Cc[job] * np.maximum(np.sinh(np.where(h, Mid, 0.0)) - np.sinh(np.where(h, A, 0.0)),
                                           np.sinh(np.where(h, B, 0.0)) - np.sinh(np.where(h, Mid, 0.0)))
            err = 4 * self.E0[job] * np.where(h, np.cosh(np.where(h, np.minimum(amax, 700.0), 0.0)), 1.0)
        Re = np.maximum(Aa, Bb) * 0.5 * (B - A)
        err = err + 16 * EPS * (np.abs(Q).sum(axis=1) + 1.0)          # evaluation of q(u_m)
        Rarc = np.where(h, Rh, Re) * (1 + 1e-12)
        return Mid, Q, Rarc, err, Rarc + err

    def cones(self, job, A, B):
        """Support cones of the pieces (module docstring, item 2): (u0, κ, ok) with |u_q − u0| ≤ κ
        for every point q of the true arc of a piece, and ok where the piece is a hyperbola arc
        whose triangle (ends, meeting point of the tangents, widened by the curve's rounding
        bound e) lies outside circle i.  u0 is the direction to the float end q(A), a corner of
        the float triangle K, so the directions of K (a cone narrower than π: c_i ∉ K) lie within
        max_v |e_v − u0| of u0 (e_v those of the corners); a point of the true arc is within e of
        K, which turns its direction by at most 2e/(dist(c_i, K) − e)."""
        table, h = self.table, self.hyp[job]
        A0, B0 = np.where(h, A, 0.0), np.where(h, B, 0.0)
        M0, EX, EY, Aa, Bb = self.M0[job], self.EX[job], self.EY[job], self.Aa[job], self.Bb[job]
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            ch = np.cosh(0.5 * (B0 - A0))
            mid = 0.5 * (A0 + B0)
            corners = [M0 + (Aa * np.cosh(t))[:, None] * EX + (Bb * np.sinh(t))[:, None] * EY for t in (A0, B0)]
            # the tangents at q(A), q(B) of m + a·cosh u·e_x + b·sinh u·e_y meet at
            # m + (a·cosh μ·e_x + b·sinh μ·e_y)/cosh δ, μ = (A + B)/2, δ = (B − A)/2
            corners.append(M0 + (Aa * np.cosh(mid) / ch)[:, None] * EX + (Bb * np.sinh(mid) / ch)[:, None] * EY)
            amax = np.minimum(np.maximum(np.abs(A0), np.abs(B0)), 700.0)
            size = np.max([np.abs(V).sum(axis=1) for V in corners], axis=0)
            e = 8 * self.E0[job] * np.cosh(amax) + 32 * EPS * (size + 1.0)
            Ci = table.C[self.I[job]]
            W = [V - Ci for V in corners]
            nw = [np.hypot(w[:, 0], w[:, 1]) for w in W]
            u0 = W[0] / nw[0][:, None]
            cm = np.maximum(*[np.hypot(*(w / n[:, None] - u0).T) for w, n in zip(W[1:], nw[1:])])
            spread = np.maximum(*[np.hypot(*(V - corners[0]).T) for V in corners[1:]])
            dmin = (nw[0] - spread) * (1 - 1e-12) - e          # ≤ the distance from c_i to K ⊕ B(e)
            kappa = (cm + 2 * e / dmin) * (1 + 1e-9) + 1e-12
            ok = h & (dmin > table.R[self.I[job]] * (1 + 1e-12) + 1e-12 * table.scale) & (kappa < 2)
        return u0, kappa, ok & np.isfinite(kappa) & np.isfinite(u0).all(axis=1)

    def support_clear(self, cone, rows, ks, I):
        """For the (piece row, site k) pairs: True where the support cone of the piece proves d_k >
        d_i on its arc (module docstring, item 2); ``cone`` as :meth:`cones` returns it, ``rows``
        indexing its pieces, ``I`` the piece's site i."""
        u0, kappa, ok = cone
        t = self.table
        g = t.C[I] - t.C[ks]
        s = (g * u0[rows]).sum(axis=1) + t.R[I] - t.R[ks] - np.hypot(g[:, 0], g[:, 1]) * kappa[rows]
        slack = 1e-12 * (t.C1[I] + t.C1[ks] + t.R[I] + t.R[ks] + 1.0)
        return ok[rows] & (s > slack)


def _queries(ctx: _Curves, job, Q, R, hi, cone):
    """The balls (centres, radii) whose sites are the candidates of the pieces: the ball of the
    piece's disc (radius hi + 2R, hi the distance to its sites), or, for a piece whose support
    cone (module docstring, item 2) lists fewer sites, a ball far out in direction u0.  A site k
    the cone does not clear has a_k = (c_k − c_i)·u0 ≥ ρ_i − ρ_k − D_i·κ − s (s its rounding
    slack, D_i ≥ |c_k − c_i|), so with P = c_i + t·u0, t > D_i, and t' = t − ρ_i + D_i·κ + s:
    |P − c_k|² = (t − a_k)² + b_k² ≤ (t' + ρ_k)² + D_i², |P − c_k| ≤ t' + ρ_k + D_i²/(2t'): the
    site meets the ball of radius t' + D_i²/(2t') around P."""
    table = ctx.table
    Q, reach = Q.copy(), hi + 2 * R
    u0, kappa, ok = cone
    if not ok.any():
        return Q, reach
    I = ctx.I[job]
    Ci = table.C[I]
    Di = (np.hypot(*(Ci - ctx.box_centre).T) + ctx.box_half) * (1 + 1e-12) + 1e-12 * table.scale
    t = 1e4 * (Di + table.rmax + 1.0)
    s = 1e-12 * (table.C1[I] + float(table.C1.max()) + table.R[I] + table.rmax + 1.0)
    with np.errstate(over="ignore", invalid="ignore"):
        tp = t - table.R[I] + Di * kappa + s
        far = (tp + Di * Di / (2 * tp)) * (1 + 1e-12) + 1e-12 * t
        # the band of sites each ball meets, across the scene, against the ring of the disc
        better = ok & (2 * Di * (Di * kappa + table.r_small) < 4 * np.pi * R * (hi + 2 * R))
    Q[better] = Ci[better] + t[better, None] * u0[better]
    reach[better] = far[better]
    return Q, reach


def _search(ctx: _Curves, job, A, B, alive, out, max_depth, max_pieces, deadline):
    """The disc search (module docstring, item 1) on the pieces (job, A, B); records failures in
    ``out`` (and clears ``alive``) for the jobs of ``ctx``.  Returns the number of pieces examined.

    A piece that does not decide a site is cut into 2, 4 or 8 equal parameter steps: about as
    many as its Lipschitz margin asks for (the arc radius shrinks with the step), at most
    ``max_depth`` halvings in all from the first pieces."""
    table, I, J, X = ctx.table, ctx.I, ctx.J, ctx.X
    npieces = 0
    pp = kk = None          # candidate pairs (piece, site); children inherit only failing pairs
    dep = np.zeros(len(job), np.int64)      # halvings of each piece
    for _ in range(max_depth + 1):
        if not len(job):
            break
        if deadline is not None and time.perf_counter() > deadline:
            for jj in np.unique(job).tolist():       # pieces left: not decided in time
                if alive[jj]:
                    alive[jj] = False
                    out[jj] = (False, (None, None, "time limit"))
            break
        npieces += len(job)
        Mid, Q, Rarc, err, R = ctx.discs(job, A, B)
        lo_i, hi_i = table.bounds(Q, I[job])
        lo_j, hi_j = table.bounds(Q, J[job])
        hi = np.minimum(hi_i, hi_j)
        if pp is None:
            if table.n > SMALL_TABLE:
                rows, ks = table.near(*_queries(ctx, job, Q, R, hi, ctx.cones(job, A, B)))
            else:       # a local proof's few sites: every pair is listed anyway
                rows, ks = table.near(Q, hi + 2 * R)
            jr = job[rows]
            keep = (ks != I[jr]) & (ks != J[jr]) & ~(X[jr] == ks[:, None]).any(axis=1)
            pp, kk = rows[keep], ks[keep]
        rows, ks = pp, kk
        if not len(rows):
            break
        lo_k, hi_k = table.bounds(Q[rows], ks)
        closer = hi_k + R[rows] < np.maximum(lo_i, lo_j)[rows] - R[rows]
        for t in np.nonzero(closer)[0]:
            jj = int(job[rows[t]])
            if alive[jj]:
                alive[jj] = False
                out[jj] = (False, (int(ks[t]), tuple(Q[rows[t]]), "closer"))
        fail = lo_k - hi[rows] - 2 * R[rows] <= 0
        if fail.any():
            fr = np.nonzero(fail)[0]
            up, inv = np.unique(rows[fr], return_inverse=True)      # the cones of these pieces only
            fail[fr] = ~ctx.support_clear(ctx.cones(job[up], A[up], B[up]), inv, ks[fr], I[job[rows[fr]]])
        need = np.ones(len(rows))               # the factor by which the piece's arc must shrink
        if fail.any():
            fr = np.nonzero(fail)[0]
            slope = _slope_bound(table, Q[rows[fr]], ks[fr], I[job[rows[fr]]], R[rows[fr]])
            gap = lo_k[fr] - hi_i[rows[fr]] - 2 * err[rows[fr]]
            spent = slope * Rarc[rows[fr]]
            fail[fr] = gap - spent <= 0
            with np.errstate(all="ignore"):
                need[fr] = np.where(gap > 0, spent / gap, 2.0)
        fail &= alive[job[rows]]
        if not fail.any():
            break
        pf, kf = rows[fail], ks[fail]
        bad_pieces, inv = np.unique(pf, return_inverse=True)
        if len(bad_pieces) > max_pieces:
            deep = np.ones(len(pf), bool)
        else:
            deep = dep[pf] >= max_depth
        for t in np.nonzero(deep)[0]:
            jj = int(job[pf[t]])
            if alive[jj]:
                alive[jj] = False
                out[jj] = (False, (int(kf[t]), tuple(Q[pf[t]]), "undecided"))
        if deep.all():
            break
        job, A, B, dep, pp, kk = _cut(job, A, B, dep, bad_pieces, inv, need[fail], kf, ~deep,
                                      len(pf) <= FEW_PIECES, max_depth)
    return npieces


def _cut(job, A, B, dep, bad, inv, need, kf, live, few, max_depth):
    """The children of the bad pieces ``bad`` of the disc search: each cut into 2, 4 or 8 equal
    parameter steps, about as many as the largest ``need`` (the factor by which the arc must shrink,
    per failing pair; ``inv`` its piece among ``bad``, ``kf`` its site) asks — halved when the
    round has many failing pairs (``few`` false: every child inherits them, their work dominates) —
    and at most ``max_depth`` halvings in all; the children tile their parent exactly (equal floats
    at the joints).  The failing pairs of the ``live`` pieces go to every child.  Returns (job, A,
    B, dep, pp, kk) of the children."""
    want = np.zeros(len(bad))
    np.maximum.at(want, inv, np.nan_to_num(need, nan=2.0, posinf=8.0))
    with np.errstate(all="ignore"):
        bits = np.ceil(np.log2(want * 2.5))
    bits = np.where(bits >= 1, np.minimum(bits, 3 if few else 1), 1).astype(np.int64)
    bits = np.minimum(bits, np.maximum(max_depth - dep[bad], 1))
    parts = np.left_shift(1, bits)
    pb = np.repeat(parts, parts)
    t = np.arange(len(pb)) - np.repeat(np.cumsum(parts) - parts, parts)
    ab, bb = np.repeat(A[bad], parts), np.repeat(B[bad], parts)
    A_new = ab + (bb - ab) * (t / pb)
    B_new = np.where(t + 1 == pb, bb, ab + (bb - ab) * ((t + 1) / pb))
    first = np.cumsum(parts) - parts                # first child of each bad piece
    pl, kl = inv[live], kf[live]
    reps = parts[pl]
    pp = np.repeat(first[pl], reps) + (np.arange(int(reps.sum())) - np.repeat(np.cumsum(reps) - reps, reps))
    return np.repeat(job[bad], parts), A_new, B_new, np.repeat(dep[bad] + bits, parts), pp, np.repeat(kl, reps)
