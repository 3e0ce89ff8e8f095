"""The disc search of :mod:`runtime.voronoi.verify.edges` (its docstring, item 1): d_k > d_i on a
finite arc of the bisector of two circle/point sites, for every third site k, many edges at once.

The arc is cut into pieces; each piece lies in a disc around its mid point q_m (radius R: the
larger arc length to an end, plus the rounding bound of the float curve).  Every distance
function is 1-Lipschitz, so d_k − d_i ≥ lo_k(q_m) − hi_i(q_m) − 2R on the piece; sharper, d_k −
d_i changes by at most L·(arc length) with L ≥ |∇d_k − ∇d_i| on the disc (:func:`_slope_bound`).
Candidate sites come once from the k-d tree of the centres; a piece that does not decide a site
is halved and its halves re-test only that site.

Memory: pieces whose disc is large next to their distance to the sites are halved before the
candidates are listed (few candidates per piece), and the (piece, candidate) pairs are searched
in groups of at most :data:`PAIRS` (a piece far outside the sites' hull can have every site as a
candidate), so the search takes memory independent of the number of edges.
"""
from __future__ import annotations

import time

import numpy as np

from .edges import EPS, MAX_DEPTH, CircleTable

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
            reach = (np.minimum(table.bounds(Q, ctx.I[job])[1], table.bounds(Q, ctx.J[job])[1]) + 2 * R
                     + table.r_small)
            count = table.tree.query_ball_point(Q, reach * (1 + 1e-9), return_length=True) + 1 + len(table.big)
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
