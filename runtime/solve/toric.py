"""Generalised Voronoi vertices by a toric Macaulay null space in circle space.

Why: the weighted-degree null space of :mod:`runtime.solve.macaulay` works in (x, y, R), whose
weighted projective closure has a whole curve of common zeros at infinity (W = 0, x² + y² = R).
A vertex far outside the scene is numerically one of them: the degree gap disappears and that
route refuses.  In circle space (x, y, T), T = x² + y² − R (:mod:`runtime.algebra.circle_space`),
a far vertex is an ordinary point near the plane A = 0 of P³; but P³ has its own trouble, a fat
point [0 : 0 : 0 : 1] of multiplicity 32 common to all ellipse and parabola offsets, whose
eigenvalue cluster spoils the eigenvectors (measured: 140–150 of the 184 solutions recovered).

What: replace P³ by the projective toric variety X_P of the offsets' Newton polytope
P = {i + j + k ≤ a, i + j + 2k ≤ b} (a, b from the supports; (6, 8) for ellipses and
hyperbolas, whose normalised volume 184 is the generic count).  The mixed volume equals the
number of solutions of a generic member (:mod:`runtime.certify.root_bound`), so by Bernstein's
second theorem (Bernstein 1975, Thm. B) no solution lies on the toric boundary and the fat point
is blown up into a divisor that holds none.  The eigenvalue method on X_P (Telen, *Numerical
root finding via Cox rings*, J. Pure Appl. Algebra 224, 2020; Bender & Telen, *Toric
eigenvalue methods for solving sparse polynomial systems*, Math. Comp. 91, 2022) is a Macaulay
matrix whose columns are the lattice points of a dilated polytope Q = {i + j + k ≤ A,
i + j + 2k ≤ B}, whose rows are the shifts m·g_i with m + P_i ⊆ Q, and whose null space has
dimension N, the number of solutions, at a large enough Q:

1. null space of the Macaulay matrix (pivoted QR of its transpose); its dimension must be the
   proved bound N: a larger one means solutions at toric infinity or a positive-dimensional
   component, a smaller one an inconsistent rank decision -- both refuse;
2. multiplication maps by h₁/h₀, h_i generic real combinations of the sections 1, x, y, T
   (the coordinates of circle space): shifting the null space by them restricts it to the
   lattice points m with m + {0, e_x, e_y, e_T} ⊆ Q; the N × N matrix (N₀⁺N₁) has the values
   h₁/h₀ at the solutions as eigenvalues, finite everywhere on X_P;
3. each solution is read twice, as two starts for Newton: from the Schur form of the
   multiplication map, whose unitary basis also triangularises the maps of all four sections, so
   that the diagonals give [1 : x : y : T] at each solution without forming an eigenvector
   (Corless, Gianni & Trager, ISSAC 1997), and from the eigenvector, on the row of largest
   |h₀|; both are read in projective circle-space coordinates, so a far vertex (A → 0) is read as
   accurately as a near one, and Newton-refined there (:func:`projective_newton`);
4. a cluster of nearby solutions (small sites far apart: the 8 circles touching three small
   ellipses from inside or outside) can send two starts to one root: the converged roots
   of up to :data:`EIGEN_PAIRS` random pairs (h₀, h₁) are pooled, duplicates judged at the
   accuracy Newton reached, until the bound's number of distinct roots is found; two rows that
   are apart by more than Newton's last steps but less than their forward-error estimates
   (ε·‖J⁻¹‖ times the size of the values: Higham 2002, §25.3) may be one root reached twice, so
   such a pool counts as complete only once these rows are merged (or, when merging leaves fewer
   than the bound, as a near-double pair that Newton resolved, for the certification to prove);
5. when the pool is at most three roots short, the traces of the multiplication maps minus the
   values at the pooled roots give the missing ones (:func:`missing_by_traces`): a root that
   every problem reached but Newton did not converge to is read without an eigenvector;
6. when a cluster is so ill-conditioned that no double-precision step resolves it (measured:
   three ellipses with collinear centres 100× apart, Jacobian singular values 10⁻¹¹ of the
   largest, forward-error estimates 10⁻⁴: five eigenvalue problems at each of two polytopes left
   the pool two roots short), the list is completed by repeating the least accurate rows of the
   cluster (at most :data:`PADDED_MAX`) and marked provisional: the certification's search at
   128 bits around an uncertified or overlapping root (:mod:`runtime.certify.complete`) finds
   the missing ones, or the counting proof fails and the exact route answers;
7. a pool that stays short after the first polytope, or a provisional list, has its worst cluster
   where the traces placed the missing roots, or else at the root with the largest forward-error
   estimate (:meth:`_Pool.cluster_centres`): the caller
   (:func:`runtime.solve.toric_roots.toric_attempt`) solves the system again in a frame centred
   at each in turn, where the cluster is no longer a small relative perturbation of large
   coordinates, and goes on in the scene's frame with the next polytope and the same pool
   (``pool=``, :class:`ToricShort`) only when that does not resolve more of it.

The caller checks residuals in world coordinates and certifies every root (Krawczyk, counting).

Measured on the validation and random rigid triples (bench/results/locator.md, bench/results/toric.md): Q = (Σa − 2,
Σb − 4) has null-space dimension N and a well-conditioned shift for every generic member, with
vertices up to 10¹³ times the scene size; Q = (Σa, Σb) is the fallback.  Everything returned is
checked downstream (Krawczyk per solution, count against the proved bound).

Length: one solver, the eigenvalue method on X_P (Macaulay matrix, null space, Schur and
eigenvector points, projective Newton, the pool of several eigenvalue problems), whose steps
share the circle-space system and the pool.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np
import scipy.linalg as sla

from ..algebra.circle_space import circle_space_float, polytope_bounds
from ..result import LocatorError
from .householder import householder_apply, rank_from_values

__all__ = ["ToricInfo", "ToricShort", "solve_toric", "toric_macaulay_matrix", "polytope_points", "family_polytope", "projective_newton",
           "DILATION_STEPS", "common_eigenvalues", "missing_by_traces"]

#: (ΔA, ΔB) subtracted from (Σa_i, Σb_i) for the column polytope, tried in turn
DILATION_STEPS = ((2, 4), (0, 0))
#: relative |diag R| below which a pivot is numerically zero, and the least accepted ratio
#: across the rank cut
RANK_TOL = 1e-10
GAP_RATIO = 1e4
#: least accepted reciprocal condition (|R₀[-1, -1]| / |R₀[0, 0]|) of the shifted null space
SHIFT_RCOND = 1e-9
#: random pairs (h₀, h₁) of eigenvalue problems pooled at most, and the last Newton correction
#: (max-normalised chart coordinates) below which a root counts as converged
EIGEN_PAIRS = 5
CONVERGED_STEP = 1e-6
#: backward error (relative residual of the homogenised offsets) below which a refined point is a root
ROOT_RESIDUAL = 1e-12
#: at most this many missing roots are read from traces (:func:`missing_by_traces`)
TRACE_MISSING = 3
#: backward error below which a root read from the traces is pooled though Newton has not
#: converged to it (measured: 1.9e-11 at a root 2e-5 from Newton's last iterate, steps 1e-5)
TRACE_RESIDUAL = 1e-9
#: at most this many rows are repeated to complete a pool short of the bound in a cluster (step 6),
#: only where at least as many pooled roots have forward-error estimates above CLUSTER_ERROR
PADDED_MAX = 2
CLUSTER_ERROR = 1e-8
#: the circle-space sections 1, x, y, T (exponents of x, y, T)
SECTIONS = np.array([(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)], dtype=np.int64)


@dataclass
class ToricInfo:
    polytope: tuple[int, int]
    matrix_shape: tuple[int, int]
    n_finite: int
    rank_ratio: float
    shift_rcond: float
    timings: dict[str, float] = field(default_factory=dict)
    #: backward errors of the returned roots in circle space (homogenised offsets)
    residuals: np.ndarray | None = None
    #: rows merged at their forward-error estimates were added back, or rows repeated in a cluster
    #: (:meth:`_Pool.roots`): the list holds the bound's number of rows, not proved distinct roots
    provisional: bool = False
    #: rows repeated to complete the list in a cluster (module docstring, step 6)
    padded: int = 0
    #: distinct roots in the pool (merged at their forward-error estimates)
    distinct: int = 0
    #: working (x, y) of the worst-resolved cluster (:meth:`_Pool.cluster_centres`), where a
    #: provisional list is solved again (step 7)
    centres: list = field(default_factory=list)
    #: the pool of the eigenvalue problems (a later call may go on pooling with further polytopes)
    pool: "_Pool | None" = field(default=None, repr=False)


@lru_cache(maxsize=32)
def polytope_points(a: int, b: int):
    """Lattice points of {i + j + k ≤ a, i + j + 2k ≤ b} in the positive orthant (exponents of
    x, y, T) and the index cube (cube[i, j, k] = column or −1)."""
    pts = [(i, j, k) for k in range(max(b, 0) // 2 + 1) for i in range(a + 1) for j in range(a + 1 - i)
           if i + j + k <= a and i + j + 2 * k <= b]
    E = np.array(pts, dtype=np.int64).reshape(-1, 3)
    cube = -np.ones((a + 2, a + 2, max(b, 0) // 2 + 2), dtype=np.int64)
    if len(E):
        cube[E[:, 0], E[:, 1], E[:, 2]] = np.arange(len(E))
    E.setflags(write=False)
    cube.setflags(write=False)
    return E, cube


def toric_macaulay_matrix(gs, A: int, B: int):
    cols, cube = polytope_points(A, B)
    blocks = []
    for E, C, (a, b) in gs:
        S = polytope_points(A - a, B - b)[0]
        if len(S) == 0:
            continue
        idx = cube[S[:, None, 0] + E[None, :, 0], S[:, None, 1] + E[None, :, 1], S[:, None, 2] + E[None, :, 2]]
        blk = np.zeros((len(S), len(cols)))
        np.put_along_axis(blk, idx, np.broadcast_to(C / np.linalg.norm(C), idx.shape), axis=1)
        blocks.append(blk)
    return np.vstack(blocks), cols, cube


@lru_cache(maxsize=8)
def family_polytope(family: str) -> tuple[int, int]:
    """(a, b) of the family's polytope {i + j + k ≤ a, i + j + 2k ≤ b}: the smallest one holding
    the circle-space support recorded by the precompute (``generated/counts/root_counts.json``,
    checked exactly for each member by :mod:`runtime.certify.root_bound`)."""
    from ..artefacts import load_root_count_bounds

    support = load_root_count_bounds()[1][family]
    return polytope_bounds(np.array(sorted(support), dtype=np.int64))


class ToricShort(LocatorError):
    """The pooled eigenvalue problems found fewer distinct roots than the bound; ``pool`` holds
    them (:meth:`_Pool.cluster_centres` locates the worst-resolved cluster, and a later call may go
    on pooling with further polytopes)."""

    def __init__(self, message: str, pool: "_Pool", timings: dict | None = None):
        super().__init__(message)
        self.pool = pool
        self.timings = timings or {}


def solve_toric(polys: list[dict], families: list[str], expected: int,
                seed: int = 5, *, dilations=DILATION_STEPS, pool: "_Pool | None" = None) -> tuple[np.ndarray, ToricInfo]:
    """All solutions (x, y, R) (complex, working coordinates of the caller, shape (N, 3)) of the
    offsets ``polys`` ({(i, j, k): c} in (x, y, R), float) of conics of the offset ``families``
    (circle, ellipse, parabola), by the toric null space in circle space (module docstring).
    ``expected`` is the proved bound on the number of isolated solutions.  Raises LocatorError
    when the null space does not have dimension ``expected`` or the shifted null space is
    singular at every dilation tried, :class:`ToricShort` (with the pool) when the pooled roots
    stay fewer than the bound.  The column polytopes are ``dilations`` (tried in turn), and the
    roots pool in ``pool`` when one is given (the pool of an earlier call, in the same frame).

    The float composition leaves rounding residues (~10⁻¹⁶ relative) on monomials outside the
    family polytope, where the exact composition cancels; they are dropped."""
    tm: dict[str, float] = {}
    t0 = time.perf_counter()
    ab = [family_polytope(f) for f in families]
    gs = _circle_space_system(polys, ab)
    tm["compose"] = time.perf_counter() - t0
    errors = []
    pool = _Pool() if pool is None else pool
    for dA, dB in dilations:
        A, B = sum(a for a, _ in ab) - dA, sum(b for _, b in ab) - dB
        try:
            Ns, ratio, shape = _shifted_null_space(gs, A, B, expected, tm)
        except LocatorError as exc:
            errors.append(f"polytope ({A}, {B}): {exc}")
            continue
        t1 = time.perf_counter()
        rconds = _pool_eigen(pool, gs, Ns, expected, seed)
        tm["eigen"] = tm.get("eigen", 0.0) + time.perf_counter() - t1
        if pool.complete(expected, fallback=True):
            # merged at the forward-error estimates, fewer than the bound may remain: a near-double
            # pair that Newton resolved (:meth:`_Pool.roots`)
            roots, res, padded = pool.roots(expected, fallback=True)
            return roots, ToricInfo((A, B), shape, expected, ratio, max(rconds), tm, res,
                                    pool.count() != expected or pool.unconverged, padded, pool.count(),
                                    pool.cluster_centres(), pool)
        errors.append(f"polytope ({A}, {B}): {pool.count()} distinct converged roots from {len(rconds)} "
                      f"eigenvalue problems, not the {expected} of the bound (a cluster of nearby solutions, or "
                      f"solutions at toric infinity; shift conditions {', '.join(f'{r:.0e}' for r in rconds)})")
    if len(pool.Z):
        raise ToricShort("toric null space: " + "; ".join(errors), pool, tm)
    raise LocatorError("toric null space: " + "; ".join(errors))


def _circle_space_system(polys, ab):
    """[(exponents, coefficients, (a, b))] of the circle-space offsets, restricted to their family
    polytopes {i + j + k ≤ a, i + j + 2k ≤ b}."""
    gs = []
    for p, (a, b) in zip(polys, ab):
        E, C = circle_space_float(p)
        inside = (E.sum(axis=1) <= a) & (E[:, 0] + E[:, 1] + 2 * E[:, 2] <= b)
        gs.append((E[inside], C[inside], (a, b)))
    return gs


def _shifted_null_space(gs, A: int, B: int, expected: int, tm: dict):
    """(the null space restricted to the shifts by the sections 1, x, y, T: (4, |sub|, N), the
    rank ratio, the Macaulay matrix's shape) at the column polytope (A, B) (module docstring,
    steps 1–2); refuses when the numerical rank is not n − N with a clear gap."""
    t0 = time.perf_counter()
    M, cols, cube = toric_macaulay_matrix(gs, A, B)
    t1 = time.perf_counter()
    tm["fill"] = tm.get("fill", 0.0) + t1 - t0
    n = M.shape[1]
    r = n - expected
    if r <= 0 or r > M.shape[0]:
        raise LocatorError(f"{M.shape[0]} x {n} Macaulay matrix cannot have a null space of dimension {expected}")
    (qr, tau), R, _ = sla.qr(M.T, pivoting=True, mode="raw", check_finite=False)
    dr = np.abs(np.diag(R))
    rank, ratio = rank_from_values(dr, RANK_TOL * dr[0])
    if rank != r or ratio < GAP_RATIO:
        raise LocatorError(f"null space of dimension {n - rank} (ratio {ratio:.1e} across the cut), "
                           f"not the {expected} solutions of the bound: solutions at toric infinity, "
                           "a positive-dimensional component or a non-generic member")
    tail = np.zeros((n, expected))
    tail[r:, :] = np.eye(expected)
    Nul = householder_apply(qr, tau, tail, "N")          # (n, N) orthonormal null-space basis
    # shifts by the sections 1, x, y, T: lattice points m with m + SECTIONS ⊆ Q
    sub = polytope_points(A - 1, B - 2)[0]
    rows = cube[sub[None, :, 0] + SECTIONS[:, None, 0], sub[None, :, 1] + SECTIONS[:, None, 1],
                sub[None, :, 2] + SECTIONS[:, None, 2]]                  # (4, |sub|)
    tm["nullspace"] = tm.get("nullspace", 0.0) + time.perf_counter() - t1
    return Nul[rows], ratio, M.shape


class _Pool:
    """Distinct converged roots (points of P³) of several eigenvalue problems, with each one's
    last Newton correction, forward-error estimate and relative residual (module docstring,
    step 4)."""

    def __init__(self):
        self.Z = np.zeros((0, 4), dtype=complex)
        self.step = np.zeros(0)
        self.err = np.zeros(0)
        self.res = np.zeros(0)
        self.loose = np.zeros(0, dtype=bool)
        self.unconverged = False
        self.missing_near = np.zeros((0, 4), dtype=complex)

    def add(self, Z, step, res, err, converged: bool = False) -> None:
        """Add the converged rows (all rows if ``converged``: the caller vouches for them, and the
        pool is marked ``unconverged``) and their complex conjugates (the offsets are real: the
        conjugate of a root is a root, reached at the same accuracy)."""
        conv = np.ones(len(Z), dtype=bool) if converged else (step < CONVERGED_STEP) & (res < ROOT_RESIDUAL)
        before = len(self.Z)
        Z, step, res, err = (np.concatenate([v[conv], v[conv].conj()]) for v in (Z, step, res, err))
        allZ, allS = np.vstack([self.Z, Z]), np.concatenate([self.step, step])
        allE, allR = np.concatenate([self.err, err]), np.concatenate([self.res, res])
        keep = ~_duplicates(allZ, allS)            # the pool's rows come first and stay
        self.Z, self.step, self.err, self.res = allZ[keep], allS[keep], allE[keep], allR[keep]
        # rows kept when rows closer than their forward-error estimates are merged: a
        # well-conditioned root 1.5e-11 apart from itself was measured, Newton's last steps 1e-12
        # and 4e-16; such a pair is one root reached twice, and a root is missing
        self.loose = ~_duplicates(self.Z, self.err)
        self.unconverged |= converged and len(self.Z) > before

    def count(self) -> int:
        return int(self.loose.sum())

    def cluster_centres(self) -> list[tuple[float, float]]:
        """Working (x, y) (real parts) of the worst-resolved cluster, most telling first: where
        the traces placed the roots still missing (:func:`missing_by_traces`, when Newton from
        there reached known neighbours), then the distinct root with the largest forward-error
        estimate; points at infinity (A = 0) are left out.  Measured: three hyperbolas 100× apart
        (seed 302, OpenBLAS SkylakeX kernels), two roots of a cluster 4e-3 wide missing after five
        eigenvalue problems; the least accurate root lay 4 working units away, the traces' point
        within 3e-3 of them, and the frame centred there resolved all 184 roots; seed 305
        (Sandybridge kernels) the other way round."""
        if not self.loose.any():
            return []
        rows = list(self.missing_near[:1]) + [self.Z[int(np.argmax(np.where(self.loose, self.err, -np.inf)))]]
        out = []
        for A, X, Y, _ in rows:
            if A != 0:
                x, y = complex(X / A).real, complex(Y / A).real
                if np.isfinite(x) and np.isfinite(y) and (x, y) not in out:
                    out.append((x, y))
        return out

    def padding(self, expected: int) -> int:
        """How many rows :meth:`roots` may repeat (module docstring, step 6): the pool is at most
        :data:`PADDED_MAX` rows short and holds at least as many roots of a cluster (forward-error
        estimates above :data:`CLUSTER_ERROR`); else 0."""
        short = expected - len(self.Z)
        if not 0 < short <= PADDED_MAX or int((self.err > CLUSTER_ERROR).sum()) < short:
            return 0
        return short

    def complete(self, expected: int, fallback: bool = False) -> bool:
        n = self.count()
        return n == expected or (fallback and n < expected <= len(self.Z) + self.padding(expected))

    def roots(self, expected: int, fallback: bool = False):
        """(roots (x, y, R) in the working frame, residuals, number of repeated rows).  With
        ``fallback``, when merging at the forward-error estimates leaves fewer than ``expected``
        rows, the merged rows farthest from their kept neighbour (relative to Newton's last step)
        are added back: a near-double pair that Newton resolved, which the certification proves
        distinct (or the counting proof fails and the exact route answers).  If the pool still
        lacks rows, the :meth:`padding` least accurate ones of the cluster are repeated, non-real
        ones first (a repeated real root would be a repeated candidate vertex); the certification
        searches for the missing roots around them."""
        rows = np.nonzero(self.loose)[0]
        padded = 0
        if len(rows) != expected and fallback:
            merged = np.nonzero(~self.loose)[0]
            W = _normalised(self.Z)
            if len(merged):
                gap = np.abs(W[merged][:, None, :] - W[rows][None, :, :]).max(axis=2).min(axis=1)
                order = np.argsort(-gap / np.maximum(self.step[merged], 1e-300), kind="stable")
                rows = np.sort(np.concatenate([rows, merged[order[:expected - len(rows)]]]))
            padded = min(expected - len(rows), self.padding(expected))
            if padded > 0:
                real = np.abs(W[rows].imag).max(axis=1) <= CLUSTER_ERROR
                order = np.lexsort((-self.err[rows], real))
                rows = np.concatenate([rows, rows[order[:padded]]])
        A_, X_, Y_, T_ = self.Z[rows].T
        with np.errstate(divide="ignore", invalid="ignore"):
            roots = np.stack([X_ / A_, Y_ / A_, (X_ * X_ + Y_ * Y_ - A_ * T_) / (A_ * A_)], axis=1)
        return roots, self.res[rows], padded


def _pool_eigen(pool: _Pool, gs, Ns, expected: int, seed: int) -> list[float]:
    """Pool the converged roots of up to :data:`EIGEN_PAIRS` random eigenvalue problems until the
    bound's number of distinct roots is reached; returns the shift conditions."""
    rconds = []
    for attempt in range(EIGEN_PAIRS):
        # the first problem's eigenvectors alone close most triples; from the second on, where
        # clusters are left, the Schur points too
        Z, step, res, err, rc, shifts = _eigen_points(gs, Ns, seed + attempt, schur=attempt > 0)
        rconds.append(rc)
        if Z is None:
            continue
        pool.add(Z, step, res, err)
        short = expected - pool.count()
        if 0 < short <= TRACE_MISSING:
            # a few roots short: the traces give them (:func:`missing_by_traces`); a root that
            # Newton in circle space approaches only slowly (every eigenvalue problem had reached
            # it, none converged) is taken at a backward error below TRACE_RESIDUAL, and the list
            # is then provisional: the certification proves it or the exact route answers
            h0, h1, maps = shifts
            Zm = missing_by_traces(pool.Z[pool.loose], h0, h1, maps(), short)
            if len(Zm):
                missing = projective_newton(gs, Zm)
                pool.add(*missing)
                slow = missing[2] < TRACE_RESIDUAL
                if pool.count() == expected - int(slow.sum()) and slow.any():
                    pool.add(*(v[slow] for v in missing), converged=True)
                # still short: Newton went from the traces' points to known neighbours, and the
                # missing roots lie near those points (a cluster: :meth:`_Pool.cluster_centres`)
                pool.missing_near = Zm if pool.count() < expected else Zm[:0]
        if pool.count() >= expected:
            break
    return rconds


def missing_by_traces(known: np.ndarray, h0: np.ndarray, h1: np.ndarray, Xs: np.ndarray, k: int) -> np.ndarray:
    """The k solutions [A : X : Y : T] of P³ (rows) missing from ``known`` (N − k distinct
    solutions, rows), from traces of the multiplication maps ``Xs`` by the sections s/h₀
    (s = 1, x, y, T; X = Σ h₁[s]·Xs[s] is the map of h₁/h₀).  Their eigenvalues are the values at
    the N solutions, so a trace minus the sum over the known ones is a sum over the missing ones
    (Cox, Little & O'Shea, *Using Algebraic Geometry*, 2nd ed., §2.4): the power sums
    p_j = tr(X^j) − Σ_known λ^j, j = 1 … k, give the missing values λ_u of h₁/h₀ (Newton's
    identities), and tr(X_s·X^j) − Σ_known (s/h₀)·λ^j, j = 0 … k − 1, a Vandermonde system in
    the λ_u for each section's values.  With k = 1 the coordinates are just the traces of the X_s.
    A trace needs no eigenvector: where a cluster leaves a root unreached by every eigenvalue
    problem, this reads it directly (measured: three hyperbolas 100× apart, seed 401, one real
    root 3e-2 of its size from its neighbour, which five problems had reached but to which Newton
    had not converged).  Returns an empty array when the λ_u are not distinct."""
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        w = known @ h0
        vals = known / w[:, None]                                             # (N − k, 4): s/h₀
        if k == 1:
            out = np.array([np.trace(Xs[s]) for s in range(4)]) - vals.sum(axis=0)
            return np.nan_to_num(out)[None, :]
        lam = vals @ h1                                                       # h₁/h₀
        X = np.tensordot(h1, Xs, axes=1)
        powers = [np.eye(len(X))]
        for _ in range(k):
            powers.append(powers[-1] @ X)
        p = np.array([np.trace(powers[j]) - (lam ** j).sum() for j in range(1, k + 1)])
        # Newton's identities: e_j = (Σ_{i=1}^{j} (−1)^{i−1} e_{j−i} p_i) / j
        e = [1.0 + 0j]
        for j in range(1, k + 1):
            e.append(sum((-1) ** (i - 1) * e[j - i] * p[i - 1] for i in range(1, j + 1)) / j)
        lu = np.roots([(-1) ** j * e[j] for j in range(k + 1)])
        if len(lu) != k or not np.isfinite(lu).all() or np.min(np.abs(lu[:, None] - lu[None, :]) + np.eye(k)) == 0:
            return np.zeros((0, 4), dtype=complex)
        V = lu[None, :] ** np.arange(k)[:, None]                              # (k, k): λ_u^j
        q = np.array([[np.sum(Xs[s] * powers[j].T) - (vals[:, s] * lam ** j).sum() for s in range(4)]
                      for j in range(k)])                                     # (k, 4)
        out = np.linalg.solve(V, q)
    return np.nan_to_num(out)


def _eigen_points(gs, Ns, seed: int, schur: bool = True):
    """(points (2N, 4), or (N, 4) without ``schur``, of P³ refined by :func:`projective_newton`,
    their last corrections, relative residuals and forward-error estimates, shift condition,
    (h₀, h₁, a function returning the maps of the sections s/h₀)) for
    the random pair (h₀, h₁) of ``seed`` (module docstring, steps 2–3); (None, None, None, None,
    rcond) when the shifted null space is singular.

    Each solution is read twice, as two starts for Newton:

    * from the **eigenvectors** of X, on the row of largest |h₀| (Telen 2020, §3);
    * from the **Schur form** X = U·S·Uᵀ of the multiplication map X of h₁/h₀: the multiplication
      maps X_s of the four sections s/h₀ commute with X, so Uᵀ·X_s·U is block upper triangular
      too, and its k-th diagonal entry is the value of s/h₀ at the solution of the k-th eigenvalue
      of X (:func:`common_eigenvalues`; Corless, Gianni & Trager, *A reordered Schur factorization
      method for zero-dimensional polynomial systems with multiple roots*, ISSAC 1997).  No
      eigenvector is formed: in a cluster of nearby solutions the eigenvectors are nearly parallel
      (evaluations of the same monomials at nearby points) and ill-conditioned, the Schur vectors
      are orthonormal.

    Measured on three hyperbolas 100× farther apart than their sizes (seed 305): one problem's
    Schur points reach 157–170 distinct roots of 184, its eigenvectors 149–170, and the two
    together 168–176; on 48 random triples at 100× (seeds 300–307) the pooled problems closed 43
    with eigenvectors alone and 46 with both (the other two are non-generic).  The price is one
    real Schur form and twice the Newton work, ~0.12 s per problem instead of ~0.07 s, so the
    first problem of a pool reads eigenvectors only (``schur=False``): on the same 48 triples and
    48 more (seeds 200–207), at 10× and 100×, the median toric time went from 0.09 s to 0.065 s."""
    rng = np.random.default_rng(seed)
    h0, h1 = rng.standard_normal(4), rng.standard_normal(4)
    N0 = np.tensordot(h0, Ns, axes=1)
    N1 = np.tensordot(h1, Ns, axes=1)
    Q0, R0, p0 = sla.qr(N0, mode="economic", pivoting=True, check_finite=False)
    rcond = abs(R0[-1, -1] / R0[0, 0])
    if not rcond > SHIFT_RCOND:
        return None, None, None, None, rcond, None
    X = sla.solve_triangular(R0, Q0.T @ N1[:, p0], check_finite=False)

    Nsp = Ns[:, :, p0]

    @lru_cache(maxsize=1)
    def section_maps():
        """the maps X_s = R₀⁻¹Q₀ᵀ·N_s of the four sections s/h₀ (formed once, when first asked)"""
        return sla.solve_triangular(R0, Q0.T @ Nsp.transpose(1, 0, 2).reshape(Ns.shape[1], -1),
                                    check_finite=False).reshape(len(p0), 4, len(p0)).transpose(1, 0, 2)

    Zs = np.zeros((0, 4), dtype=complex)
    if schur:
        # Schur points: the values of 1/h₀, x/h₀, y/h₀, T/h₀ on the diagonal of Uᵀ·X_s·U
        Zs = common_eigenvalues(X, section_maps())
    # eigenvector points: [1 : x : y : T] at each solution, on the row of largest |h₀|
    _, W = sla.eig(X, overwrite_a=True, check_finite=False)
    Z0 = N0[:, p0] @ W.real + 1j * (N0[:, p0] @ W.imag)                  # (|sub|, N)
    k = np.argmax(np.abs(Z0), axis=0)
    Ze = np.einsum("esj,js->es", Nsp[:, k, :], W)                        # (4, N)
    # eigenvector points first: the pool keeps the rows it found first, and on a conjugate pair
    # closer to the real axis than the eigenvalue accuracy the eigenvectors reach both members,
    # whereas the real Schur form gives two real values whose Newton iterates stay real and stall
    # between them (measured: 17.78 ± 7e-7·i at R ≈ 32820, three hyperbolas 100× apart)
    Z, step, res, err = projective_newton(gs, np.vstack([Ze.T, Zs]))
    return Z, step, res, err, rcond, (h0, h1, section_maps)


def common_eigenvalues(X: np.ndarray, Xs: np.ndarray) -> np.ndarray:
    """The common eigenvalues (N, S) of the commuting real matrices Xs[s] (S × N × N), ordered by a
    real Schur form X = U·S·Uᵀ of X (one of their combinations): the diagonal of Uᵀ·Xs[s]·U for
    a 1 × 1 block of S, and for a 2 × 2 block (a conjugate pair) the eigenvalues of the 2 × 2
    block of Uᵀ·Xs[s]·U in the eigenvector basis of S's block."""
    S, U = sla.schur(X, output="real", check_finite=False)
    Y = np.einsum("sij,jk->sik", Xs, U)
    diag = np.einsum("ik,sik->ks", U, Y)                                        # (N, S)
    Z = diag.astype(complex)
    sub = np.abs(np.diagonal(S, -1)) > 0
    k = np.nonzero(sub)[0]
    if len(k):
        up = np.einsum("ik,sik->ks", U[:, k], Y[:, :, k + 1])                   # (m, S)
        lo = np.einsum("ik,sik->ks", U[:, k + 1], Y[:, :, k])
        blocks = np.empty((len(k), len(Xs), 2, 2))
        blocks[:, :, 0, 0], blocks[:, :, 1, 1] = diag[k], diag[k + 1]
        blocks[:, :, 0, 1], blocks[:, :, 1, 0] = up, lo
        Sb = np.stack([S[k, k], S[k, k + 1], S[k + 1, k], S[k + 1, k + 1]], axis=1).reshape(-1, 2, 2)
        _, V = np.linalg.eig(Sb)                                                # (m, 2, 2)
        Vi = np.linalg.inv(V)
        vals = np.einsum("mab,msbc,mca->msa", Vi, blocks, V)                    # (m, S, 2)
        Z[k] = vals[:, :, 0]
        Z[k + 1] = vals[:, :, 1]
    return Z


def _homogeneous_system(gs, Z: np.ndarray, fixed: np.ndarray, with_size: bool = False):
    """Values (N, 4) and Jacobians (N, 4, 4) of (G_1, G_2, G_3, Z_fixed − 1) at points Z (N, 4);
    with ``with_size`` also the sizes Σ_m |c_m·m(Z)| and values |G_i(Z)| (N, 3) of the relative
    residuals (backward errors)."""
    F = np.empty((len(Z), 4), dtype=complex)
    J = np.zeros((len(Z), 4, 4), dtype=complex)
    size = np.zeros((len(Z), 3))
    tiny = (np.abs(Z) < 1e-100).any()
    for i, (E, C, (a, _b)) in enumerate(gs):
        ex = np.concatenate([(a - E.sum(axis=1))[:, None], E], axis=1)          # (t, 4): A, X, Y, T
        P = np.ones((a + 1, 4, len(Z)), dtype=complex)
        for q in range(1, a + 1):
            P[q] = P[q - 1] * Z.T
        fac = P[ex, np.arange(4)[None, :], :]                                  # (t, 4, N)
        mono = np.prod(fac, axis=1)                                            # (t, N)
        F[:, i] = C @ mono
        if with_size:
            size[:, i] = np.abs(C) @ np.abs(mono)
        for c in range(4):
            if tiny:
                g = ex[:, c][:, None] * P[np.maximum(ex[:, c] - 1, 0), c, :]
                for cc in range(4):
                    if cc != c:
                        g = g * fac[:, cc, :]
                J[:, i, c] = C @ g
            else:
                # ∂/∂Z_c of a monomial = e_c · monomial / Z_c (no coordinate is near 0 here)
                J[:, i, c] = ((C * ex[:, c]) @ mono) / Z[:, c]
    F[:, 3] = Z[np.arange(len(Z)), fixed] - 1.0
    J[np.arange(len(Z)), 3, fixed] = 1.0
    if with_size:
        return F, J, size, np.abs(F[:, :3])
    return F, J


def _newton_steps(J, F):
    with np.errstate(all="ignore"):
        try:
            D = np.linalg.solve(J, -F[..., None])[..., 0]
        except np.linalg.LinAlgError:
            D = np.stack([np.linalg.lstsq(Jk, -Fk, rcond=None)[0] for Jk, Fk in zip(J, F)])
    return np.where(np.isfinite(D), D, 0.0)


def _normalised(Z):
    return Z / Z[np.arange(len(Z)), np.argmax(np.abs(Z), axis=1)][:, None]


def _duplicates(Z, step=None) -> np.ndarray:
    """True for points of P³ (rows, max-normalised) that coincide with an earlier row: closer than
    10 times the larger of their accuracies ``step`` (last Newton corrections, or forward-error
    estimates), and at least 1e-13.  Near-double roots that Newton resolved stay apart (two real
    vertices 1e-9 apart were measured with small sites far apart); the certification proves them
    distinct or the counting proof fails.  A row of non-finite accuracy is never merged.
    Candidate pairs by sort and sweep on the real part of one coordinate at the largest tolerance,
    then each pair at its own tolerance."""
    W = _normalised(Z)
    st = np.zeros(len(W)) if step is None else np.nan_to_num(np.asarray(step, dtype=float), nan=np.inf)
    dup = np.zeros(len(W), dtype=bool)
    with np.errstate(over="ignore"):
        reach = np.maximum(1e-13, 10 * st)
    idx = np.nonzero(np.isfinite(reach) & np.isfinite(W).all(axis=1))[0]
    if len(idx) < 2:
        return dup
    key = W[idx].real[:, np.argmax(np.ptp(W[idx].real, axis=0))]
    order = np.argsort(key, kind="stable")
    ks = key[order]
    end = np.searchsorted(ks, ks + reach[idx].max(), side="right")
    count = end - np.arange(len(ks)) - 1
    first = np.repeat(np.arange(len(ks)), count)
    second = first + 1 + np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count)
    a, b = idx[order[first]], idx[order[second]]
    hi, lo = np.maximum(a, b), np.minimum(a, b)
    close = np.abs(W[hi] - W[lo]).max(axis=1) < np.maximum(reach[hi], reach[lo])
    for i, j in sorted(zip(hi[close].tolist(), lo[close].tolist())):
        if not dup[j]:
            dup[i] = True
    return dup


def projective_newton(gs, Z: np.ndarray, iters: int = 30) -> np.ndarray:
    """Newton on the homogenised circle-space offsets G_i(A, X, Y, T) = A^{a_i}·g_i(X/A, Y/A, T/A)
    at points Z (N, 4) of P³, each in the affine chart of its largest coordinate (vectorised; a
    point stops once its correction is at the rounding level).  A far vertex (A → 0) is as well
    conditioned here as a near one, whereas Newton in (x, y, R) can reach a tiny residual far from
    it (Jacobian condition up to 10¹⁷ measured).  Returns the points, each one's last Newton
    correction, its relative residual, and a forward-error estimate (the larger of the last
    correction and ε·‖J⁻¹‖·Σ|c_m·m(Z)|, the rounding error of the values carried through J⁻¹)."""
    Z = _normalised(np.array(Z, dtype=complex))
    if len(Z) == 0:
        return Z, np.zeros(0), np.zeros(0), np.zeros(0)
    fixed = np.argmax(np.abs(Z), axis=1)
    step = np.full(len(Z), np.inf)
    active = np.arange(len(Z))
    for _ in range(iters):
        F, J = _homogeneous_system(gs, Z[active], fixed[active])
        D = _newton_steps(J, F)
        Z[active] += D
        prev = step[active]
        step[active] = np.abs(D).max(axis=1)
        # done: at the rounding level, or stalled (no longer halving) below 1e-11
        done = (step[active] < 4e-16) | ((step[active] < 1e-11) & (step[active] > 0.5 * prev))
        active = active[~done]
        if len(active) == 0:
            break
    _, J, size, value = _homogeneous_system(gs, Z, fixed, with_size=True)
    with np.errstate(divide="ignore", invalid="ignore"):
        res = np.where(size > 0, value / size, np.inf).max(axis=1)
        # forward error ≲ ‖J⁻¹‖ · (rounding error of the values), the values' rounding error being
        # ~ε · Σ|c_m·m(Z)| (Higham, *Accuracy and Stability of Numerical Algorithms*, §5.1, §25.3)
        smin = np.linalg.svd(J, compute_uv=False)[:, -1]
        err = np.maximum(step, np.where(smin > 0, np.finfo(float).eps * size.max(axis=1) / smin, np.inf))
    return Z, step, res, err
