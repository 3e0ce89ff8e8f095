"""Mixed volumes and regular mixed subdivisions from a random integer lifting (thesis §3.3.1).

Definitions 3.3.3–3.3.6 and Theorem 3.3.7 of the thesis: for supports ``A_1..A_N`` in ``Z^N``
lifted by integers ``w_i: A_i -> Z``, the lower faces of the Minkowski sum of the lifted
polytopes project to a *regular (coherent) mixed subdivision* of ``Q = Q_1 + ... + Q_N``.  A
lower face is selected by an inner normal ``(α, 1)``: it is ``F_1(α) + ... + F_N(α)`` with
``F_i(α) = argmin_{a ∈ A_i} <α, a> + w_i(a)``.  For a generic lifting the subdivision is fine;
its *mixed cells* are the sums of N edges ``{a_i, b_i}`` and the mixed volume is the sum of
their volumes ``|det(b_i − a_i)|`` (normalised so that MV(Q, ..., Q) = N!·Vol(Q)).

Algorithm (``mixed_cells``), after the MixedVol / dynamic-enumeration idea of Gao–Li–Wu and
Mizutani–Takeda–Kojima, simplified:

1. *lower edges* of each lifted support (pairs that are an edge of the lower hull), by LP;
2. depth-first search over the supports, choosing one lower edge per support; a partial choice is
   kept only if the cone of normals ``α`` realising all chosen edges simultaneously has a
   nonempty relative interior (LP with a slack variable, HiGHS);
3. at the last level the normals form a line ``α0 + t·d``: the cells are the breakpoints of the
   lower envelope of the lines ``t -> <α0 + t d, c> + w(c)`` inside the feasible interval —
   found without LPs;
4. every cell is then re-verified in exact rational arithmetic (its normal solved exactly, all
   inequalities checked strictly).  A tie means the lifting is not generic: :class:`NonGenericLifting`.

``mixed_volume`` reduces supports to vertices (exactly), lifts with a seeded
``numpy.random.default_rng`` and sums cell volumes; ``mixed_volume_ie`` is an independent
reference via inclusion–exclusion of exact Minkowski-sum volumes (CLO, Using Algebraic Geometry,
ch. 7 §4).  ``MixedSubdivision.locate`` finds the cell ``F_0 + ... + F_N`` of the mixed
subdivision of N+1 supports containing a point (used for the Canny–Emiris row content, §3.3.1).

Length: lifting, mixed cells and mixed volume are one algorithm (Huber–Sturmfels 1995).
"""
from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Callable, Sequence

import flint
import numpy as np
from scipy.optimize import linprog

from .polytopes import generalised_cross, as_points, minkowski_sum, normalized_volume, vertices

__all__ = [
    "NonGenericLifting", "MixedCell", "random_lifting", "lower_edges", "mixed_cells",
    "mixed_volume", "mixed_volume_ie", "MixedSubdivision", "Cell",
]

_TOL = 1e-7


class NonGenericLifting(ValueError):
    """The lifting is not generic (a tie in an exact check); choose another seed."""


@dataclass(frozen=True)
class MixedCell:
    """A mixed cell: one edge ``(i, j)`` (indices into support k) per support k."""

    edges: tuple[tuple[int, int], ...]
    normal: tuple[Fraction, ...]      # α: the lower face has inner normal (α, 1)
    volume: int                       # |det(b_k − a_k)|


def random_lifting(supports: Sequence[np.ndarray], seed: int = 0, bound: int = 2**15) -> list[np.ndarray]:
    """Seeded, reproducible integer lifting: one int64 array per support, values in [0, bound)."""
    rng = np.random.default_rng(seed)
    return [rng.integers(0, bound, size=len(a), dtype=np.int64) for a in supports]


# ----------------------------------------------------------------------------------------------
# small LP helpers
# ----------------------------------------------------------------------------------------------
def _slack_lp(eq_a, eq_b, ge_a, ge_b, n: int) -> float:
    """max s s.t. eq_a·α = eq_b, ge_a·α − s >= ge_b, s <= 1 (α free).  -inf if infeasible."""
    c = np.zeros(n + 1)
    c[-1] = -1.0
    a_ub = np.hstack([-ge_a, np.ones((len(ge_a), 1))]) if len(ge_a) else None
    b_ub = -ge_b if len(ge_a) else None
    a_eq = np.hstack([eq_a, np.zeros((len(eq_a), 1))]) if len(eq_a) else None
    b_eq = eq_b if len(eq_a) else None
    bounds = [(None, None)] * n + [(None, 1.0)]
    res = linprog(c, A_ub=a_ub, b_ub=b_ub, A_eq=a_eq, b_eq=b_eq, bounds=bounds, method="highs")
    if res.status == 0:
        return -res.fun
    if res.status == 3:  # unbounded cannot happen (s <= 1); treat as feasible
        return 1.0
    return -math.inf


def _edge_rows(a: np.ndarray, w: np.ndarray, i: int, j: int):
    """Equality row and inequality rows for 'edge (i, j) of the lifted support is lower'.

    equality:  <α, a_j − a_i> = w_i − w_j;  inequalities: <α, a_c − a_i> >= w_i − w_c (c ≠ i, j)
    """
    eq_a = (a[j] - a[i]).astype(float)[None, :]
    eq_b = np.array([float(w[i] - w[j])])
    mask = np.ones(len(a), dtype=bool)
    mask[[i, j]] = False
    ge_a = (a[mask] - a[i]).astype(float)
    ge_b = (w[i] - w[mask]).astype(float)
    return eq_a, eq_b, ge_a, ge_b


def _scale(ws: Sequence[np.ndarray]) -> float:
    m = max((int(np.abs(w).max()) for w in ws if len(w)), default=1)
    return float(max(m, 1))


def lower_edges(points: np.ndarray, lifting: np.ndarray) -> list[tuple[int, int]]:
    """Pairs (i, j), i < j, forming an edge of the lower hull of the lifted point set (LP)."""
    a = np.asarray(points, dtype=np.int64)
    w = np.asarray(lifting, dtype=np.int64)
    n = a.shape[1]
    sc = _scale([w])
    out = []
    for i, j in itertools.combinations(range(len(a)), 2):
        eq_a, eq_b, ge_a, ge_b = _edge_rows(a, w, i, j)
        if _slack_lp(eq_a, eq_b / sc, ge_a, ge_b / sc, n) > _TOL:
            out.append((i, j))
    return out


# ----------------------------------------------------------------------------------------------
# exact verification
# ----------------------------------------------------------------------------------------------
def _exact_normal(supports, liftings, edges) -> tuple[Fraction, ...] | None:
    rows, rhs = [], []
    for a, w, (i, j) in zip(supports, liftings, edges):
        rows.append([int(v) for v in (a[j] - a[i])])
        rhs.append([int(w[i] - w[j])])
    mat = flint.fmpq_mat(rows)
    if mat.det() == 0:
        return None
    sol = mat.solve(flint.fmpq_mat(rhs))
    return tuple(Fraction(int(sol[k, 0].p), int(sol[k, 0].q)) for k in range(len(rows)))


def _verify_cell(supports, liftings, edges, alpha) -> bool:
    """Exact check that ``edges`` are exactly the minimisers of <α, ·> + w on each support."""
    den = math.lcm(*(x.denominator for x in alpha))
    num = [int(x * den) for x in alpha]
    for a, w, (i, j) in zip(supports, liftings, edges):
        vals = [sum(num[k] * int(p[k]) for k in range(len(num))) + den * int(wp)
                for p, wp in zip(a.tolist(), w.tolist())]
        m = vals[i]
        if vals[j] != m:
            return False
        for c, v in enumerate(vals):
            if c in (i, j):
                continue
            if v == m:
                raise NonGenericLifting(f"tie at point {a[c].tolist()} for normal {alpha}")
            if v < m:
                return False
    return True


def _volume(supports, edges) -> int:
    rows = [[int(v) for v in (a[j] - a[i])] for a, (i, j) in zip(supports, edges)]
    return abs(int(flint.fmpz_mat(rows).det()))


# ----------------------------------------------------------------------------------------------
# mixed cells
# ----------------------------------------------------------------------------------------------
def _line(eq_a, eq_b, ge_a, ge_b):
    """Normals on a line α0 + t·d (N−1 independent integer equality rows): the feasible open
    interval (lo, hi) of t from the inequalities, or None if it is empty (floats; d exact)."""
    alpha0, *_ = np.linalg.lstsq(eq_a, eq_b, rcond=None)
    # direction: null space of eq_a (integer rows): exact integer generalised cross product
    d = np.array(generalised_cross(np.rint(eq_a).astype(np.int64).tolist()), dtype=np.int64)
    if not d.any():
        return None
    d = d // math.gcd(*d.tolist())
    lo, hi = -math.inf, math.inf
    if len(ge_a):
        g0 = ge_a @ alpha0 - ge_b            # must stay >= 0
        gd = np.rint(ge_a).astype(np.int64) @ d
        scale = np.maximum(1.0, np.abs(ge_b))
        pos, neg = gd > 0, gd < 0
        if np.any(~pos & ~neg & (g0 < _TOL * scale)):
            return None
        if pos.any():
            lo = float(np.max(-g0[pos] / gd[pos]))
        if neg.any():
            hi = float(np.min(-g0[neg] / gd[neg]))
        if math.isfinite(lo) and math.isfinite(hi) and not lo < hi - _TOL * max(1.0, abs(lo), abs(hi)):
            return None
    return alpha0, d, lo, hi


def _line_cells(eq_a, eq_b, ge_a, ge_b, a_last, w_last):
    """Last level: normals on a line; cells = breakpoints of the lower envelope (floats)."""
    line = _line(eq_a, eq_b, ge_a, ge_b)
    if line is None:
        return []
    alpha0, d, lo, hi = line
    icpt = a_last.astype(float) @ alpha0 + w_last.astype(float)
    slope = a_last @ d                                        # exact integers
    m = len(a_last)
    # start: active line at t just above lo (or at -inf: largest slope, then lowest intercept)
    if lo == -math.inf:
        cur = int(np.lexsort((icpt, -slope))[0])
    else:
        v = icpt + lo * slope
        near = np.flatnonzero(v <= v.min() + 1e-9 * max(1.0, abs(float(v.min()))))
        cur = int(near[np.argmin(slope[near])])
    t = lo
    out = []
    for _ in range(m):
        cand = slope < slope[cur]
        if not cand.any():
            break
        tt = (icpt[cand] - icpt[cur]) / (slope[cur] - slope[cand])
        idx = np.flatnonzero(cand)
        k = int(np.argmin(tt))
        tnext = float(tt[k])
        # several lines through the same breakpoint: take the one with the smallest slope next
        close = np.flatnonzero(np.abs(tt - tnext) <= 1e-9 * max(1.0, abs(tnext)))
        if tnext >= hi:
            break
        if len(close) > 1:
            # non-generic in floats: report all pairs, exact check will sort it out
            for kk in close:
                out.append((cur, int(idx[kk])))
            nxt = int(idx[close[np.argmin(slope[idx[close]])]])
        else:
            nxt = int(idx[k])
            if tnext > lo:
                out.append((cur, nxt))
        cur, t = nxt, tnext
    return [tuple(sorted(e)) for e in out]


def mixed_cells(supports: Sequence[np.ndarray], lifting: Sequence[np.ndarray], *,
                progress: Callable[[str], None] | None = None) -> list[MixedCell]:
    """Mixed cells of the regular mixed subdivision of ``Q_1 + ... + Q_N`` induced by ``lifting``.

    ``supports``: N integer arrays ``(m_k, N)``; ``lifting``: N integer arrays ``(m_k,)``.
    The supports are used as given (no vertex reduction).  Each returned cell is exactly
    verified; raises :class:`NonGenericLifting` on a tie.
    """
    sup = [np.asarray(a, dtype=np.int64) for a in supports]
    lif = [np.asarray(w, dtype=np.int64) for w in lifting]
    n_sup = len(sup)
    if n_sup == 0:
        raise ValueError("need at least one support")
    n = sup[0].shape[1]
    if n_sup != n or any(a.shape[1] != n for a in sup):
        raise ValueError(f"mixed cells need N supports in Z^N; got {n_sup} supports in dimension {n}")
    if any(len(a) != len(w) for a, w in zip(sup, lif)):
        raise ValueError("lifting sizes do not match the supports")
    if any(len(a) < 2 for a in sup):
        return []  # a single point: every mixed volume involving it is 0
    sc = _scale(lif)
    edges = [lower_edges(a, w) for a, w in zip(sup, lif)]
    # order: fewest lower edges first; the largest support is handled by the envelope step last
    order = sorted(range(n), key=lambda k: len(edges[k]))
    last = order[-1]
    rows = {}
    for k in order[:-1]:
        rows[k] = [tuple(x / (sc if idx % 2 else 1.0) for idx, x in enumerate(_edge_rows(sup[k], lif[k], i, j)))
                   for (i, j) in edges[k]]
    found: dict[tuple, MixedCell] = {}

    def dfs(level: int, chosen: list[int], eq_a, eq_b, ge_a, ge_b):
        if level == n - 1:
            for e in _line_cells(eq_a, eq_b * sc, ge_a, ge_b * sc, sup[last], lif[last]):
                full = [None] * n
                for k, ei in zip(order[:-1], chosen):
                    full[k] = edges[k][ei]
                full[last] = e
                key = tuple(full)
                if key in found:
                    continue
                alpha = _exact_normal(sup, lif, full)
                if alpha is None or not _verify_cell(sup, lif, full, alpha):
                    continue
                found[key] = MixedCell(key, alpha, _volume(sup, full))
            return
        k = order[level]
        for ei, (ea, eb, ga, gb) in enumerate(rows[k]):
            na = np.vstack([eq_a, ea]) if len(eq_a) else ea
            nb = np.concatenate([eq_b, eb])
            nga = np.vstack([ge_a, ga]) if len(ge_a) else ga
            ngb = np.concatenate([ge_b, gb])
            if level == 0:
                ok = True
            elif level == n - 2:      # the normals now form a line: interval test, no LP
                ok = _line(na, nb * sc, nga, ngb * sc) is not None
            else:
                ok = _slack_lp(na, nb, nga, ngb, n) > _TOL
            if ok:
                dfs(level + 1, chosen + [ei], na, nb, nga, ngb)

    if n == 1:
        # one support on a line: cells are the lower edges themselves
        for (i, j) in edges[0]:
            alpha = _exact_normal(sup, lif, [(i, j)])
            if alpha is not None and _verify_cell(sup, lif, [(i, j)], alpha):
                found[((i, j),)] = MixedCell(((i, j),), alpha, _volume(sup, [(i, j)]))
    else:
        dfs(0, [], np.zeros((0, n)), np.zeros(0), np.zeros((0, n)), np.zeros(0))
    return [found[k] for k in sorted(found)]


def _reduced(supports):
    return [vertices(as_points(a)) for a in supports]


def mixed_volume(supports: Sequence, *, seed: int = 0, reduce: bool = True,
                 return_cells: bool = False):
    """Mixed volume MV(Q_1..Q_N) (Definition 3.3.3, Theorem 3.3.7) as a sum of mixed-cell volumes.

    ``supports`` are integer point sets (anything :func:`as_points` accepts); with ``reduce``
    they are first replaced by the vertices of their Newton polytopes (exact; MV only depends on
    the polytopes).  The lifting is ``random_lifting(supports, seed)``; on a (rare) non-generic
    lifting the next seed is tried.  Normalisation: MV(Q, ..., Q) = N!·Vol(Q).
    """
    sup = _reduced(supports) if reduce else [as_points(a) for a in supports]
    n = sup[0].shape[1]
    if len(sup) != n:
        raise ValueError(f"mixed volume needs N={n} supports, got {len(sup)}")
    for attempt in range(10):
        try:
            cells = mixed_cells(sup, random_lifting(sup, seed + attempt))
        except NonGenericLifting:
            continue
        mv = sum(c.volume for c in cells)
        return (mv, cells, sup) if return_cells else mv
    raise NonGenericLifting("no generic lifting found in 10 attempts")


def mixed_volume_ie(supports: Sequence) -> int:
    """Independent reference: MV = Σ_{S ≠ ∅} (−1)^{N−|S|} Vol_N(Σ_{i∈S} Q_i) (exact hulls)."""
    sup = _reduced(supports)
    n = sup[0].shape[1]
    if len(sup) != n:
        raise ValueError(f"mixed volume needs N={n} supports, got {len(sup)}")
    total = 0
    for k in range(1, n + 1):
        for s in itertools.combinations(range(n), k):
            total += (-1) ** (n - k) * normalized_volume(minkowski_sum(*(sup[i] for i in s)))
    if total % math.factorial(n):
        raise ArithmeticError("inclusion–exclusion gave a non-integer mixed volume")
    return total // math.factorial(n)


# ----------------------------------------------------------------------------------------------
# point location in a (non-square) regular mixed subdivision: Canny–Emiris row content
# ----------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Cell:
    """A full-dimensional cell ``F_0 + ... + F_M`` of a fine regular mixed subdivision.

    ``faces[i]`` are the indices (into support i) of the points spanning F_i (a simplex);
    ``normal`` is α (lower face of the lifted sum with inner normal (α, 1)); exact.
    """

    faces: tuple[tuple[int, ...], ...]
    normal: tuple[Fraction, ...]


@dataclass
class MixedSubdivision:
    """Regular mixed subdivision of ``Q_0 + ... + Q_M`` (any number of supports in Z^N).

    Point location solves ``min Σ w·λ  s.t.  Σ_i Σ_j λ_ij a_ij = q, Σ_j λ_ij = 1, λ >= 0`` (the
    lower hull of the lifted Minkowski sum above q, Canny–Emiris §4); its optimal basis is a
    cell.  A basis is optimal independently of q, so every cell found is then tested against
    all remaining points at once (``B⁻¹ b(q) >= 0``).  Each cell is exactly verified: its
    normal α is solved exactly and every lifted point must lie strictly above the face
    (non-basic) or on it (basic); the barycentric coordinates of each located point are checked
    positive in exact arithmetic.
    """

    supports: list[np.ndarray]
    lifting: list[np.ndarray]
    cells: list[Cell] = field(default_factory=list)

    def __post_init__(self):
        self.supports = [np.asarray(a, dtype=np.int64) for a in self.supports]
        self.lifting = [np.asarray(w, dtype=np.int64) for w in self.lifting]
        self.dim = self.supports[0].shape[1]
        self._owner = np.concatenate([np.full(len(a), i) for i, a in enumerate(self.supports)])
        self._local = np.concatenate([np.arange(len(a)) for a in self.supports])
        m = len(self.supports)
        cols = []
        for i, a in enumerate(self.supports):
            block = np.zeros((self.dim + m, len(a)), dtype=np.int64)
            block[: self.dim] = a.T
            block[self.dim + i] = 1
            cols.append(block)
        self._a = np.hstack(cols)                     # (dim + m) × total
        self._w = np.concatenate(self.lifting)

    def _rhs(self, q_num: np.ndarray, den: int) -> np.ndarray:
        m = len(self.supports)
        return np.hstack([q_num, np.full((len(q_num), m), den, dtype=np.int64)])

    def _lp_basis(self, q: np.ndarray) -> list[int]:
        sc = _scale([self._w])
        b = np.concatenate([q, np.ones(len(self.supports))])
        res = linprog(self._w / sc, A_eq=self._a.astype(float), b_eq=b,
                      bounds=[(0, None)] * self._a.shape[1], method="highs")
        if res.status != 0:
            raise ValueError(f"point {q} is not in the Minkowski sum")
        basis = np.flatnonzero(res.x > 1e-9)
        if len(basis) != self._a.shape[0]:
            raise NonGenericLifting(f"degenerate LP at {q}: {len(basis)} positive weights")
        return sorted(int(k) for k in basis)

    def _exact_cell(self, basis: list[int]) -> tuple[Cell, flint.fmpz_mat, int]:
        a_b = flint.fmpz_mat(self._a[:, basis].tolist())
        det = int(a_b.det())
        if det == 0:
            raise NonGenericLifting("singular basis")
        # dual: y^T A_B = w_B; reduced costs w − y^T A >= 0, > 0 off the basis
        a_bq = flint.fmpq_mat(self._a[:, basis].tolist())
        y = a_bq.transpose().solve(flint.fmpq_mat([[int(self._w[k])] for k in basis]))
        yv = [Fraction(int(y[k, 0].p), int(y[k, 0].q)) for k in range(y.nrows())]
        den = math.lcm(*(v.denominator for v in yv))
        ynum = np.array([int(v * den) for v in yv], dtype=object)
        red = self._w.astype(object) * den - ynum @ self._a.astype(object)
        bset = set(basis)
        for k in range(len(red)):
            if k in bset:
                if red[k] != 0:
                    raise ArithmeticError("basis reduced cost not zero")
            elif red[k] <= 0:
                if red[k] == 0:
                    raise NonGenericLifting("lifting not generic: a point lies on a lower face")
                raise ArithmeticError("LP basis is not optimal in exact arithmetic")
        faces = tuple(tuple(int(self._local[k]) for k in basis if self._owner[k] == i)
                      for i in range(len(self.supports)))
        alpha = tuple(-v for v in yv[: self.dim])
        return Cell(faces, alpha), a_b, det

    def locate(self, points: np.ndarray, shift: Sequence[Fraction],
               progress: Callable[[int, int], None] | None = None) -> np.ndarray:
        """Cell index (into ``self.cells``) of ``p + shift`` for each integer point p.

        ``shift`` must be generic (no p + shift on a cell boundary; checked exactly).
        """
        pts = np.asarray(points, dtype=np.int64)
        sh = [Fraction(s) for s in shift]
        den = math.lcm(*(s.denominator for s in sh))
        snum = np.array([int(s * den) for s in sh], dtype=np.int64)
        q_num = pts * den + snum                      # den·(p + δ)
        rhs = self._rhs(q_num, den)                   # den·b(q)
        owner = np.full(len(pts), -1, dtype=np.int64)
        remaining = np.arange(len(pts))
        while len(remaining):
            i0 = int(remaining[0])
            basis = self._lp_basis(q_num[i0] / den)
            cell, a_b, det = self._exact_cell(basis)
            # test all remaining points: λ = A_B⁻¹·b(q) > 0.  Floats first, exact re-check of
            # every candidate (fmpq inverse, python ints).
            invf = np.linalg.inv(np.array(self._a[:, basis], dtype=float))
            lamf = (rhs[remaining].astype(float) / den) @ invf.T
            cand = np.flatnonzero(np.all(lamf > -1e-6, axis=1))
            if len(cand) == 0 or cand[0] != 0:
                raise ArithmeticError("LP cell does not contain its own point (floats)")
            inv = a_b.inv()  # fmpq_mat
            dd = math.lcm(*(int(inv[r, c].q) for r in range(inv.nrows()) for c in range(inv.ncols())))
            invn = np.array([[int(inv[r, c] * dd) for c in range(inv.ncols())]
                             for r in range(inv.nrows())], dtype=object)
            lam = rhs[remaining[cand]].astype(object) @ invn.T          # dd·den·λ
            if np.any(np.all(lam >= 0, axis=1) & np.any(lam == 0, axis=1)):
                raise NonGenericLifting("shift not generic: a point lies on a cell boundary")
            ok = np.all(lam > 0, axis=1)
            if not ok[0]:
                raise ArithmeticError("LP cell does not contain its own point in exact arithmetic")
            inside = np.zeros(len(remaining), dtype=bool)
            inside[cand[ok]] = True
            self.cells.append(cell)
            owner[remaining[inside]] = len(self.cells) - 1
            remaining = remaining[~inside]
            if progress is not None:
                progress(len(pts) - len(remaining), len(pts))
        return owner
