"""The weighted-degree Macaulay null-space solver of a square system in (x, y, R) (thesis §5.5).

The numeric core of :mod:`runtime.solve.generalised`: the Macaulay matrix M of o1, o2, o3 in
(x, y, R) with weighted degree (1, 1, 2) up to degree d (rows: monomial multiples m·o_i,
columns: monomials), its null space projected on the columns of degree ≤ d − h (pivoted QR of the
top-degree columns, then of the projected matrix), the rank profile by degree and its first
*degree gap*, which gives the number N of finite solutions (Dreesen, Batselier and De Moor;
Telen, Mourrain and Van Barel, truncated normal forms), then a stable monomial basis,
multiplication matrices for x and y and the solutions read off the eigenvectors of a random
combination.  The Newton refinement is :mod:`runtime.solve.newton`, the chain of attempts and
fallbacks :mod:`runtime.solve.generalised`.

Public API: :func:`solve_nullspace`, :func:`monomials`, :func:`macaulay_matrix`,
:func:`macaulay_blocks`, :func:`work_array`, :class:`SolveInfo`, :func:`add_timings`,
:data:`TOP_DEGREES`.

Length: one solver; the matrix blocks, the projected null space and the reading of the roots share
the graded monomial indexing (:func:`monomials`) and the block pattern of the matrix.
"""
from __future__ import annotations

import math
import threading
import time
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np
import scipy.linalg as sla

from .householder import householder_apply, rank_from_values
from ..result import LocatorError

__all__ = ["solve_nullspace", "monomials", "macaulay_matrix", "macaulay_blocks", "work_array", "SolveInfo",
           "TOP_DEGREES", "add_timings"]

#: number of top weighted degrees eliminated before the null space is taken
TOP_DEGREES = 3
#: numerical-rank thresholds (relative) and the minimal accepted gap between kept and dropped
#: singular values / pivots
RANK_TOL = 1e-9
GAP_RATIO = 1e3
#: rank profile of the (orthonormal) null space: singular values above PROFILE_TOL count; a decision
#: is clear when the first dropped one is ≤ PROFILE_NOISE and the ratio across the cut ≥ GAP_RATIO
PROFILE_TOL = 1e-11
PROFILE_NOISE = 1e-12
#: σ_min² above which a block of rows of the orthonormal null space is taken as full column rank
#: from the singular values of the complementary rows (:func:`_find_gap`): 1 − ŝ² is off by at most
#: ‖ZᵀZ − I‖ + rounding (measured ≤ 3e-15 on the validation triples, and within 4e-16 of the direct
#: σ_min²), so this is σ_min ≥ 1e-6, far above PROFILE_TOL
FULL_RANK_SQ = 1e-12


# =========================================================================== monomials

@lru_cache(maxsize=32)
def monomials(d: int):
    """Monomials x^i y^j R^k of weighted degree i + j + 2k ≤ d, graded: (exps (n, 3), degrees (n,),
    index cube with cube[i, j, k] = column or −1)."""
    mons = []
    for deg in range(d + 1):
        for k in range(deg // 2 + 1):
            r = deg - 2 * k
            for i in range(r, -1, -1):
                mons.append((i, r - i, k))
    E = np.array(mons, dtype=np.int64).reshape(-1, 3)
    degs = E[:, 0] + E[:, 1] + 2 * E[:, 2]
    cube = -np.ones((d + 1, d + 1, d // 2 + 1), dtype=np.int64)
    cube[E[:, 0], E[:, 1], E[:, 2]] = np.arange(len(E))
    E.setflags(write=False)
    degs.setflags(write=False)
    return E, degs, cube


def macaulay_matrix(polys: list[dict], wdegs: list[int], d: int) -> np.ndarray:
    """Dense Macaulay matrix of the polynomials {(i, j, k): c} up to weighted degree d (rows scaled
    to unit 2-norm)."""
    supports = tuple((tuple(p.keys()), dp) for p, dp in zip(polys, wdegs) if dp <= d)
    nrows, ncols, flat = _macaulay_pattern(supports, d)
    M = np.zeros(nrows * ncols)
    M[flat] = _macaulay_values(polys, wdegs, d)
    return M.reshape(nrows, ncols)


def _macaulay_values(polys, wdegs, d):
    """The nonzero entries of the Macaulay matrix in the order of :func:`_macaulay_pattern`."""
    vals = []
    for p, dp in zip(polys, wdegs):
        if dp > d:
            continue
        pc = np.fromiter(p.values(), dtype=float, count=len(p))
        vals.append(np.tile(pc / np.linalg.norm(pc), len(monomials(d - dp)[0])))
    return np.concatenate(vals) if vals else np.zeros(0)


def macaulay_blocks(polys: list[dict], wdegs: list[int], d: int, top: int):
    """The Macaulay matrix of :func:`macaulay_matrix` split for the projected null space, filled
    directly from the cached pattern (no dense matrix, no copies): (MH, ML, MU, shape) with MH, ML
    the rows touching a column of degree > d − top restricted to those columns and to the others
    (Fortran order, for LAPACK), MU the remaining rows on the other columns, and the shape of the
    whole matrix.  The blocks live in per-thread scratch arrays (:func:`work_array`): the next call
    in the same thread overwrites them."""
    supports = tuple((tuple(p.keys()), dp) for p, dp in zip(polys, wdegs) if dp <= d)
    nt, nu, nh, nl, shape, sel, pos = _split_pattern(supports, d, top)
    vals = _macaulay_values(polys, wdegs, d)
    blocks = []
    for b, ((m, n), s, q) in enumerate(zip(((nt, nh), (nt, nl), (nu, nl)), sel, pos)):
        B = work_array(f"macaulay_block_{b}", m * n)
        B.fill(0.0)
        B[q] = vals[s]
        blocks.append(B.reshape((m, n), order="F"))
    return blocks[0], blocks[1], blocks[2], shape


_workspace = threading.local()


def work_array(name: str, size: int) -> np.ndarray:
    """A float64 scratch array of ``size`` entries, reused per thread (valid until the next request
    of the same name in the same thread).  Fresh multi-megabyte arrays are mapped page by page on
    first touch: measured 2 ms per solve for the Macaulay blocks alone."""
    buf = getattr(_workspace, name, None)
    if buf is None or buf.size < size:
        buf = np.empty(size)
        setattr(_workspace, name, buf)
    return buf[:size]


@lru_cache(maxsize=32)
def _split_pattern(supports, d: int, top: int):
    """Block structure of :func:`macaulay_blocks`: row counts (touching, untouched), column counts
    (degree > d − top, the others), the matrix shape, and per block the entries of the pattern of
    :func:`_macaulay_pattern` that fall in it with their column-major positions.  A row counts as
    touching when its *support* meets the top-degree columns (a structurally zero coefficient only
    adds a zero row to the top block: same projected null space)."""
    nrows, ncols, flat = _macaulay_pattern(supports, d)
    degs = monomials(d)[1]
    r, c = np.divmod(np.asarray(flat), ncols)
    hi = degs > d - top
    touch = np.zeros(nrows, dtype=bool)
    touch[r[hi[c]]] = True
    trow, urow = np.cumsum(touch) - 1, np.cumsum(~touch) - 1
    hcol, lcol = np.cumsum(hi) - 1, np.cumsum(~hi) - 1
    nt, nh = int(touch.sum()), int(hi.sum())
    nu, nl = nrows - nt, ncols - nh
    in_h, in_t = hi[c], touch[r]
    sel = (np.nonzero(in_h)[0], np.nonzero(~in_h & in_t)[0], np.nonzero(~in_h & ~in_t)[0])
    pos = (trow[r[sel[0]]] + nt * hcol[c[sel[0]]], trow[r[sel[1]]] + nt * lcol[c[sel[1]]],
           urow[r[sel[2]]] + nu * lcol[c[sel[2]]])
    for a in sel + pos:
        a.setflags(write=False)
    return nt, nu, nh, nl, (nrows, ncols), sel, pos


@lru_cache(maxsize=32)
def _macaulay_pattern(supports, d: int):
    """Positions (flat, row-major) of the coefficients in the Macaulay matrix of polynomials with
    the given supports ((exponent tuples, weighted degree) per polynomial) up to degree d: row of
    m·p for each monomial m of degree ≤ d − deg p, in the order of :func:`monomials`.  Depends on
    the supports only (the same for every member of a family triple), hence cached."""
    E, degs, cube = monomials(d)
    flat, row0 = [], 0
    for exps, dp in supports:
        pe = np.array(exps, dtype=np.int64).reshape(-1, 3)
        S = monomials(d - dp)[0]
        cols = cube[S[:, None, 0] + pe[None, :, 0], S[:, None, 1] + pe[None, :, 1],
                    S[:, None, 2] + pe[None, :, 2]]
        if (cols < 0).any():
            raise LocatorError("internal error: offset degree exceeds its family's weighted degree")
        flat.append(((row0 + np.arange(len(S)))[:, None] * len(E) + cols).ravel())
        row0 += len(S)
    flat = np.concatenate(flat) if flat else np.zeros(0, dtype=np.int64)
    flat.setflags(write=False)
    return row0, len(E), flat


# =========================================================================== solver

@dataclass
class SolveInfo:
    degree: int
    n_finite: int
    gap_degree: int
    rank_profile: dict
    gap_ratio: float
    matrix_shape: tuple[int, int]
    nullspace: str = ""
    n_deflated: int = 0
    expected: int | None = None
    failed_attempts: list = field(default_factory=list)
    timings: dict[str, float] = field(default_factory=dict)
    homotopy: dict | None = None
    #: residuals of the roots in the solver's own coordinates when they replace those in (x, y, R)
    root_residuals: np.ndarray | None = None
    #: the list holds a pair of roots closer than their forward-error estimates (a near-double
    #: pair, or one root reached twice), or repeated rows of a cluster: the certification decides
    provisional: bool = False
    #: rows of the toric list that repeat another in an unresolved cluster (runtime.solve.toric,
    #: step 6): left to the certification's search for the missing roots
    padded: int = 0


def add_timings(into: dict, other: dict) -> None:
    """Add the stage times of ``other`` to ``into`` (seconds per stage name, as in
    :attr:`SolveInfo.timings`)."""
    for k, v in other.items():
        into[k] = into.get(k, 0.0) + v


def _nullspace(M, degs, d, top):
    """Orthonormal basis of the null space of M restricted to the columns of degree ≤ d − top
    ("projected": :func:`_projected_nullspace`), or, when a rank decision there is not clear-cut,
    of the whole null space ("full": pivoted QR of Mᵀ)."""
    hi = degs > d - top
    if top > 0:
        # rows m·o_i of weighted degree ≤ d − top vanish on the top-degree columns: they pass
        # unchanged into the projected matrix
        MH = M[:, hi]
        touch = np.any(MH != 0, axis=1)
        Z = _projected_nullspace(np.asfortranarray(MH[touch]), np.asfortranarray(M[np.ix_(touch, ~hi)]),
                                 M[np.ix_(~touch, ~hi)])
        if Z is not None:
            return Z, degs[~hi], "projected"
    return _full_nullspace(M), degs, "full"


def _full_nullspace(M):
    Q, R, _ = sla.qr(M.T, pivoting=True, mode="full", check_finite=False)
    dr = np.abs(np.diag(R))
    r, ratio = rank_from_values(dr, RANK_TOL * dr[0])
    if ratio < GAP_RATIO:
        raise LocatorError(f"Macaulay solver: numerical rank of the Macaulay matrix not clear (ratio {ratio:.1e})")
    return Q[:, r:]


def _projected_nullspace(MH, ML, MU):
    """Orthonormal basis of {z : [MH ML; 0 MU]·(w, z) = 0 for some w} -- the null space of the
    Macaulay matrix projected on its low-degree columns -- or None when a rank decision is not
    clear-cut.  MH, ML: the rows touching the top-degree columns (Fortran order; overwritten),
    MU: the others.  Pivoted QR of MH (Householder, Q not formed): with r_h its rank, the
    trailing columns Q₂ of Q span range(MH)^⊥, so the projected matrix is N = [Q₂ᵀ·ML; MU]; its
    null space is spanned by the trailing columns of the orthogonal factor of the pivoted QR of
    Nᵀ (Golub & Van Loan §5.4.2; LAPACK ormqr, Q not formed).  Measured: equally exact variants
    (Q₂ formed and multiplied, or only the first r_h reflectors applied) move the null space of
    the spread-out generic triple by 3e-12 to 1e-8 (its top block's smallest kept pivot is 2e-6)
    and there lose a root of a five-root cluster to deflation; so this arithmetic is kept."""
    nt, nl = ML.shape
    if nt:
        qh, tauh, _, dr = _pivoted_qr(MH)
        rh, ratio_h = rank_from_values(dr, RANK_TOL * dr[0]) if len(dr) else (0, math.inf)
        if ratio_h < GAP_RATIO:
            return None
        k = nt - rh
        N = work_array("projected_matrix", (k + MU.shape[0]) * nl).reshape(k + MU.shape[0], nl)
        N[:k] = householder_apply(qh, tauh, ML, "T")[rh:]
    else:
        N = np.empty((MU.shape[0], nl))
    N[N.shape[0] - MU.shape[0]:] = MU
    if N.shape[0] == 0:
        return np.eye(nl)
    qn, taun, _, dn = _pivoted_qr(N.T)
    rn, ratio_n = rank_from_values(dn, RANK_TOL * dn[0]) if len(dn) else (0, math.inf)
    if ratio_n < GAP_RATIO:
        return None
    tail = np.zeros((nl, nl - rn), order="F")
    tail[rn:, :] = np.eye(nl - rn)
    return householder_apply(qn, taun, tail, "N")


def _pivoted_qr(A):
    """Column-pivoted Householder QR of A in place (LAPACK geqp3, called as scipy.linalg.qr calls
    it, so the same factors), without forming R: (reflectors, tau, 0-based pivots, |diag R|).
    scipy's R is a fresh triangular copy of which only the diagonal is read here."""
    geqp3, = sla.get_lapack_funcs(("geqp3",), (A,))
    lwork = geqp3(A, lwork=-1, overwrite_a=True)[-2][0].real.astype(np.int_)
    qr, jpvt, tau, _, info = geqp3(A, lwork=lwork, overwrite_a=True)
    if info < 0:
        raise LocatorError(f"internal error: LAPACK geqp3 failed (info {info})")
    return qr, tau, jpvt - 1, np.abs(np.diagonal(qr)[:min(qr.shape)])


def _find_gap(Z, dl, kmax, hint, kmin=1):
    """First degree k (searched from ``hint`` upwards, then downwards) with r_k = r_{k+1} where both
    rank decisions are clear-cut (ratio ≥ GAP_RATIO, dropped values ≤ PROFILE_NOISE).  ``Z`` has
    orthonormal columns (both null-space routes of :func:`_nullspace`)."""
    cache: dict[int, tuple[int, float, float]] = {}

    def rank(k):
        if k not in cache:
            rows = dl <= k
            if rows.all():
                # Z has orthonormal columns: all its singular values are 1
                cache[k] = (Z.shape[1], math.inf, 0.0)
                return cache[k]
            rest = ~rows
            if rest.sum() < Z.shape[1]:
                # ZᵀZ = I: the singular values of Z[rows] below 1 are √(1 − s²) for the singular
                # values s of the fewer other rows; a smallest one clearly away from 0 (its square
                # ≥ FULL_RANK_SQ, far above the error of 1 − ŝ²) is full column rank, clear-cut,
                # without the SVD of the tall block
                s_max = np.linalg.norm(Z[rest], 2)
                if 1.0 - s_max * s_max >= FULL_RANK_SQ:
                    cache[k] = (Z.shape[1], math.inf, 0.0)
                    return cache[k]
            sv = np.linalg.svd(Z[rows], compute_uv=False)
            r, ratio = rank_from_values(sv, PROFILE_TOL)
            dropped = sv[r] if r < len(sv) else 0.0
            cache[k] = (r, ratio, dropped)
        return cache[k]

    def clear(k):
        r, ratio, dropped = rank(k)
        return ratio >= GAP_RATIO and dropped <= PROFILE_NOISE

    hint = min(max(hint, kmin), kmax - 1)
    order = list(range(hint, kmax)) + list(range(hint - 1, kmin - 1, -1))
    for k in order:
        if rank(k)[0] == Z.shape[1] > 0 and clear(k):
            # full column rank at k: the rows of degree ≤ k + 1 contain those of degree ≤ k, so no
            # singular value decreases (interlacing) and r_{k+1} = r_k, clear-cut (nothing dropped)
            return k, rank(k)[0], rank(k)[1], {kk: v[0] for kk, v in sorted(cache.items())}
        if rank(k)[0] == rank(k + 1)[0] and rank(k)[0] > 0 and clear(k) and clear(k + 1):
            return k, rank(k)[0], min(rank(k)[1], rank(k + 1)[1]), {kk: v[0] for kk, v in sorted(cache.items())}
    return None, 0, 0.0, {kk: v[0] for kk, v in sorted(cache.items())}


def solve_nullspace(polys: list[dict], wdegs: list[int], d: int, top: int = TOP_DEGREES,
                    gap_hint: int | None = None, seed: int = 7,
                    eigen: str = "dense") -> tuple[np.ndarray, SolveInfo]:
    """All finite solutions (complex, working coordinates, shape (N, 3)) of a square system in
    (x, y, R) by the Macaulay null-space / degree-gap method.  Raises LocatorError when no clear
    degree gap is found.

    Steps: the null space of the Macaulay matrix (:func:`_macaulay_nullspace`), its first degree
    gap (:func:`_find_gap`: the number N of finite solutions), the multiplication maps on a stable
    monomial basis (:func:`_multiplication_maps`), the eigenvectors of a random combination, and
    the solutions read off them (:func:`_roots_from_eigenvectors`)."""
    tm = {"fill": 0.0, "nullspace": 0.0}
    E, degs, cube = monomials(d)
    Z, dl, how, shape = _macaulay_nullspace(polys, wdegs, d, top, degs, tm)
    t2 = time.perf_counter()
    if Z.shape[1] == 0:
        tm["eigen"] = 0.0
        return np.zeros((0, 3), dtype=complex), SolveInfo(d, 0, -1, {}, math.inf, shape, how, timings=tm)
    kmax = int(dl.max())
    gap, nfin, gap_ratio, profile = _find_gap(Z, dl, kmax, gap_hint if gap_hint is not None else d - 4,
                                              kmin=max(wdegs) - 1)
    if gap is None:
        raise LocatorError(f"Macaulay solver: no clear degree gap up to degree {kmax} (rank profile {profile}, "
                           f"{how} null space); the configuration may be too degenerate for the numeric route")
    nfin = profile[gap]
    W, rows1, Mx, My = _multiplication_maps(Z, dl, gap, nfin, E, cube)
    rng = np.random.default_rng(seed)
    a, b = rng.standard_normal(2)
    Mg = a * Mx + b * My
    t3 = time.perf_counter()
    tm["nullspace"] += t3 - t2
    if eigen != "dense":
        # ARPACK (scipy.sparse.linalg.eigs) returns at most N − 2 of the N eigenpairs and was slower
        # than LAPACK for N − 2 (bench/results/locator.md): every solution is needed, so dense only.
        raise ValueError(f"eigen={eigen!r}: only 'dense' is supported (see bench/bench_locator.py)")
    _, V = sla.eig(Mg, overwrite_a=True, check_finite=False)
    roots = _roots_from_eigenvectors(W, V, dl[rows1], gap, E, cube, tm, t3)
    info = SolveInfo(d, nfin, gap, profile, gap_ratio, shape, how, timings=tm)
    return roots, info


def _macaulay_nullspace(polys, wdegs, d: int, top: int, degs, tm: dict):
    """(Z, degrees of its rows, "projected" or "full", shape of M): an orthonormal basis Z of the
    null space of the Macaulay matrix M of degree d, projected on the columns of degree ≤ d − top
    when ``top`` > 0 and the projected rank decisions are clear (:func:`_projected_nullspace`),
    else of all of M (:func:`_full_nullspace`).  Its rows are indexed by monomials: the dual space
    of the quotient ring, truncated (Dreesen, Batselier and De Moor 2012; thesis §5.5)."""
    Z = None
    t0 = time.perf_counter()
    if top > 0:
        MH, ML, MU, shape = macaulay_blocks(polys, wdegs, d, top)
        t1 = time.perf_counter()
        tm["fill"] += t1 - t0
        Z = _projected_nullspace(MH, ML, MU)
        dl, how = degs[degs <= d - top], "projected"
        t0 = time.perf_counter()
        tm["nullspace"] += t0 - t1
    if Z is None:
        M = macaulay_matrix(polys, wdegs, d)
        shape = M.shape
        t1 = time.perf_counter()
        tm["fill"] += t1 - t0
        Z, dl, how = _full_nullspace(M), degs, "full"
        tm["nullspace"] += time.perf_counter() - t1
    return Z, dl, how, shape


def _multiplication_maps(Z, dl, gap: int, nfin: int, E, cube):
    """(W, rows of degree ≤ gap + 1, Mx, My): the null space compressed to its N = ``nfin`` columns
    that live at the finite solutions (SVD of the rows of degree ≤ gap + 1, the degree gap
    separating them from those at infinity), a numerically stable monomial basis B (pivoted QR on
    the rows of degree ≤ gap), and the multiplication maps by x and by y on it, W[x·B] = W[B]·Mx
    (Telen, Mourrain and Van Barel, truncated normal forms): their eigenvalues are the x and y of
    the N solutions."""
    rows1 = np.nonzero(dl <= gap + 1)[0]
    if Z.shape[1] == nfin:
        # no solutions at infinity in the null space: the compression would only change the basis
        # (the multiplication maps below are then similar, same eigenvalues and eigenvectors in W)
        W = Z[rows1]
    else:
        _, _, Vt = np.linalg.svd(Z[rows1], full_matrices=False)
        W = Z[rows1] @ Vt[:nfin].T      # (n_rows1, nfin); rows indexed like the first monomials
    # stable basis: pivoted QR on the rows of degree ≤ gap (only the pivots are used)
    rows0 = np.nonzero(dl <= gap)[0]
    piv = _pivoted_qr(W[rows0].T)[2]
    B = rows0[piv[:nfin]]
    EB = E[B]
    xB = cube[EB[:, 0] + 1, EB[:, 1], EB[:, 2]]
    yB = cube[EB[:, 0], EB[:, 1] + 1, EB[:, 2]]
    lu = sla.lu_factor(W[B], check_finite=False)
    Mx = sla.lu_solve(lu, W[xB], check_finite=False)
    My = sla.lu_solve(lu, W[yB], check_finite=False)
    return W, rows1, Mx, My


def _roots_from_eigenvectors(W, V, dl1, gap: int, E, cube, tm: dict, t3: float):
    """The solutions (x, y, R) read off the eigenvectors V (columns) of a combination of the
    multiplication maps: W·v evaluates every monomial of degree ≤ gap + 1 at one solution (up to
    scale; ``dl1`` their degrees), so with the normalising monomial m of degree ≤ gap − 1 of largest
    |value|, (x, y, R) = (x·m, y·m, R·m) / m.  W is real: two real products instead of one complex
    one, for the candidate normalising monomials, then only the three shifted entries per root.
    Adds the seconds since ``t3`` to ``tm["eigen"]``."""
    cand = np.nonzero(dl1 <= gap - 1)[0]
    Wc = W[cand]
    Kc = Wc @ V.real + 1j * (Wc @ V.imag)
    t4 = time.perf_counter()
    tm["eigen"] = t4 - t3
    Ec = E[cand]
    cols = np.arange(V.shape[1])
    idx_m = np.argmax(np.abs(Kc), axis=0)
    m = Ec[idx_m]
    km = Kc[idx_m, cols]
    # the shifted monomials x·m, y·m, R·m: few distinct rows (the normalising monomials repeat)
    sh = np.stack([cube[m[:, 0] + 1, m[:, 1], m[:, 2]], cube[m[:, 0], m[:, 1] + 1, m[:, 2]],
                   cube[m[:, 0], m[:, 1], m[:, 2] + 1]])
    need, where = np.unique(sh, return_inverse=True)
    Wn = W[need]
    Kn = Wn @ V.real + 1j * (Wn @ V.imag)
    kx, ky, kR = (Kn[where.reshape(sh.shape)[t], cols] for t in range(3))
    roots = np.stack([kx / km, ky / km, kR / km], axis=1)
    tm["eigen"] += time.perf_counter() - t4
    return roots
