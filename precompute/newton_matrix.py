"""Newton (sparse resultant) matrix by the Canny–Emiris construction (thesis §3.3.1).

Canny & Emiris (J. ACM 2000); Cox–Little–O'Shea, *Using Algebraic Geometry*, ch. 7 §6; thesis
Theorems 3.3.13–3.3.15.  For N+1 polynomials ``f_0..f_N`` in N variables with supports
``A_i``:

1. ``Q = Q_0 + ... + Q_N`` (Minkowski sum of the Newton polytopes), a generic small shift δ and
   ``E = (Q + δ) ∩ Z^N`` (rows and columns of the matrix are indexed by E);
2. a generic integer lifting gives a fine regular mixed subdivision of Q; each ``p ∈ E`` lies
   (after + δ) in a unique cell ``F_0 + ... + F_N``; the *row content* of p is ``(i, a)`` with
   ``i`` the largest index such that ``F_i`` is a vertex ``a ∈ A_i`` (the thesis' map μ);
3. row p is ``x^(p − a) · f_i``: its entry in column ``q ∈ E`` is the coefficient of ``x^q``.

The rows with ``i = 0`` (f0 rows) form B_0; reordering rows and columns so that these come first
gives ``M = [[M00, M01], [M10, M11]]`` with M00 of size MV(Q_1..Q_N) (= MV_-0), and the
multiplication map by f0 in C[x^±]/<f_1..f_N> is the transpose of the Schur complement
``M00 − M01 M11⁻¹ M10`` (Theorem 3.3.15).

We store the *structure*: for every nonzero the (row, column, polynomial index, term index);
filling a matrix = putting coefficient ``term`` of polynomial ``poly`` at (row, column).
"""
from __future__ import annotations

import itertools
import math
import random
import time
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Callable, Sequence

import flint
import numpy as np

from .mixed import MixedSubdivision, NonGenericLifting, random_lifting
from .polytopes import as_points, convex_hull, lattice_points, minkowski_sum, support

__all__ = ["NewtonMatrix", "newton_matrix", "default_shift", "smallest_shift"]

FORMAT_VERSION = 1


def default_shift(dim: int, seed: int = 0, signs: Sequence[int] | None = None) -> tuple[Fraction, ...]:
    """A small generic rational shift δ (0 < |δ_k| < 1/100), seeded; optional sign pattern."""
    rng = random.Random(f"delta:{seed}")
    mags = [Fraction(rng.randint(1, 9973), 997_331) for _ in range(dim)]
    if signs is None:
        signs = [1 if rng.random() < 0.5 else -1 for _ in range(dim)]
    return tuple(sg * m for sg, m in zip(signs, mags))


def smallest_shift(hull, seed: int = 0) -> tuple[tuple[Fraction, ...], int]:
    """The shift δ among the 2^N sign patterns of ``default_shift`` giving the fewest points in E.

    |E| = #(Q + δ) ∩ Z^N counts the interior points of Q plus the boundary points of the facets
    whose outer normal n has n·δ > 0, so the direction of δ matters a lot (four ellipses:
    7995 for δ in the positive orthant — Singular's size in the thesis — up to 13213).
    """
    best = None
    for signs in itertools.product((1, -1), repeat=hull.dim):
        delta = default_shift(hull.dim, seed, signs)
        size = len(lattice_points(hull, delta))
        if best is None or size < best[1]:
            best = (delta, size)
    return best


@dataclass
class NewtonMatrix:
    """Structure of a Canny–Emiris Newton matrix (rows/columns ordered with B_0 first)."""

    name: str
    variables: tuple[str, ...]
    supports: list[np.ndarray]            # support of each f_i (rows = exponent vectors, sorted)
    points: np.ndarray                    # E, column monomials, in matrix column order
    row_poly: np.ndarray                  # content i of each row
    row_term: np.ndarray                  # index of a (in supports[i]) of each row
    rows: np.ndarray                      # nonzero structure
    cols: np.ndarray
    poly: np.ndarray
    term: np.ndarray
    n00: int                              # size of M00 (= number of f0 rows)
    shift: tuple[Fraction, ...]
    lifting_seed: int
    n_cells: int = 0
    seconds: float = 0.0
    labels: list[str] = field(default_factory=list)
    provenance: dict = field(default_factory=dict)

    @property
    def size(self) -> int:
        return len(self.points)

    @property
    def nnz(self) -> int:
        return len(self.rows)

    @property
    def row_monomials(self) -> np.ndarray:
        """Exponent of the multiplier x^(p − a) of each row (row = x^(p−a)·f_i)."""
        a = np.array([self.supports[i][j] for i, j in zip(self.row_poly, self.row_term)])
        return self.points - a

    def fill(self, coefficients: Sequence[Sequence], ring=None):
        """Dense matrix (python-flint ``ring`` matrix type, e.g. ``flint.fmpq_mat`` or a lambda
        building ``nmod_mat``) with ``coefficients[i][j]`` = coefficient of ``supports[i][j]``."""
        n = self.size
        dense = [[0] * n for _ in range(n)]
        for r, c, i, j in zip(self.rows.tolist(), self.cols.tolist(), self.poly.tolist(), self.term.tolist()):
            dense[r][c] = coefficients[i][j]
        if ring is None:
            return dense
        return ring(dense)

    def fill_nmod(self, coefficients: Sequence[Sequence[int]], modulus: int) -> flint.nmod_mat:
        n = self.size
        dense = np.zeros((n, n), dtype=np.int64)
        coef = [np.asarray([int(c) % modulus for c in cs], dtype=np.int64) for cs in coefficients]
        flat = np.concatenate(coef)
        offs = np.concatenate([[0], np.cumsum([len(c) for c in coef])[:-1]])
        dense[self.rows, self.cols] = flat[offs[self.poly] + self.term]
        return flint.nmod_mat(dense.tolist(), modulus)

    def to_arrays(self) -> tuple[dict[str, np.ndarray], dict]:
        """(int arrays for the .npz, JSON header) — see :func:`precompute.systems.write_artefact`."""
        sup_all = np.vstack(self.supports).astype(np.int32)
        sup_off = np.concatenate([[0], np.cumsum([len(s) for s in self.supports])]).astype(np.int64)
        arrays = {
            "points": self.points.astype(np.int32),
            "row_poly": self.row_poly.astype(np.int32),
            "row_term": self.row_term.astype(np.int32),
            "rows": self.rows.astype(np.int32),
            "cols": self.cols.astype(np.int32),
            "poly": self.poly.astype(np.int32),
            "term": self.term.astype(np.int32),
            "supports": sup_all,
            "support_offsets": sup_off,
        }
        header = {
            "format": "curvedvoronoi.newton_matrix", "format_version": FORMAT_VERSION,
            "name": self.name, "variables": list(self.variables), "size": self.size,
            "nnz": self.nnz, "density": self.nnz / self.size ** 2, "n00": self.n00,
            "n11": self.size - self.n00, "n_polys": len(self.supports),
            "supports": [s.tolist() for s in self.supports], "labels": list(self.labels),
            "shift": [str(s) for s in self.shift], "lifting_seed": self.lifting_seed,
            "lifting": "precompute.mixed.random_lifting(supports, seed), numpy default_rng, [0, 2^15)",
            "n_cells_located": self.n_cells,
            "column_monomials": self.points.tolist(),
            "row_monomials": self.row_monomials.tolist(), "row_poly": self.row_poly.tolist(),
            "block_order": "rows/columns 0..n00-1 are B_0 (f0 rows) = M00; the rest M11",
            "entry": "M[rows[k], cols[k]] = coefficient of supports[poly[k]][term[k]] in f_poly[k]",
            "provenance": self.provenance,
        }
        return arrays, header


def newton_matrix(polys_or_supports: Sequence, *, variables: Sequence[str] | None = None,
                  name: str = "newton", lifting_seed: int = 0, shift: Sequence[Fraction] | None = None,
                  labels: Sequence[str] = (), progress: Callable[[int, int], None] | None = None
                  ) -> NewtonMatrix:
    """Canny–Emiris Newton matrix structure of N+1 polynomials (or supports) in N variables.

    The first polynomial is f0 (its rows form M00).  Supports are used in full; the lifting is
    ``random_lifting(supports, lifting_seed)`` (next seeds on a non-generic tie), the shift
    the sign pattern of ``default_shift(N, lifting_seed)`` giving the smallest E
    (:func:`smallest_shift`) unless given.
    """
    t0 = time.perf_counter()
    sups = [support(p) if hasattr(p, "to_dict") else as_points(p) for p in polys_or_supports]
    n = sups[0].shape[1]
    if len(sups) != n + 1:
        raise ValueError(f"need N+1 = {n + 1} polynomials in N = {n} variables, got {len(sups)}")
    if variables is None:
        variables = tuple(f"x{k}" for k in range(n))
    hull = convex_hull(minkowski_sum(*sups))
    last_exc = None
    for attempt in range(5):
        seed = lifting_seed + attempt
        delta = tuple(shift) if shift is not None else smallest_shift(hull, seed)[0]
        pts = lattice_points(hull, delta)
        sub = MixedSubdivision(sups, random_lifting(sups, seed))
        try:
            owner = sub.locate(pts, tuple(-d for d in delta), progress=progress)  # cell of p − δ
        except NonGenericLifting as exc:
            last_exc = exc
            continue
        break
    else:
        raise NonGenericLifting(f"no generic lifting/shift after 5 attempts: {last_exc}")
    # row content: largest i with F_i a vertex
    content = []
    for cell in sub.cells:
        i = max(k for k, f in enumerate(cell.faces) if len(f) == 1)
        content.append((i, cell.faces[i][0]))
    row_poly = np.array([content[o][0] for o in owner], dtype=np.int64)
    row_term = np.array([content[o][1] for o in owner], dtype=np.int64)
    # order: B_0 (f0 rows) first, then the rest, each in lexicographic order of p
    order = np.concatenate([np.flatnonzero(row_poly == 0), np.flatnonzero(row_poly != 0)])
    pts, row_poly, row_term = pts[order], row_poly[order], row_term[order]
    n00 = int(np.sum(row_poly == 0))
    # column lookup by mixed-radix keys
    lo = pts.min(axis=0)
    span = pts.max(axis=0) - lo + 1
    strides = np.concatenate([np.cumprod(span[::-1])[::-1][1:], [1]]).astype(np.int64)

    def key(q):
        return (q - lo) @ strides

    keys = key(pts)
    korder = np.argsort(keys)
    skeys = keys[korder]
    rows, cols, polys, terms = [], [], [], []
    for i, a in enumerate(sups):
        sel = np.flatnonzero(row_poly == i)
        if not len(sel):
            continue
        shifts = pts[sel] - a[row_term[sel]]                      # p − a
        tgt = shifts[:, None, :] + a[None, :, :]                  # (rows, terms, N)
        inside = np.all((tgt >= lo) & (tgt < lo + span), axis=2)
        k = key(tgt.reshape(-1, n)).reshape(len(sel), len(a))
        pos = np.searchsorted(skeys, k)
        pos = np.minimum(pos, len(skeys) - 1)
        found = inside & (skeys[pos] == k)
        if not found.all():
            raise ArithmeticError("Canny–Emiris: a row monomial fell outside E (construction bug)")
        rows.append(np.repeat(sel, len(a)))
        cols.append(korder[pos].reshape(-1))
        polys.append(np.full(len(sel) * len(a), i))
        terms.append(np.tile(np.arange(len(a)), len(sel)))
    rows = np.concatenate(rows)
    cols = np.concatenate(cols)
    polys = np.concatenate(polys)
    terms = np.concatenate(terms)
    srt = np.lexsort((cols, rows))
    return NewtonMatrix(name, tuple(variables), sups, pts, row_poly, row_term, rows[srt], cols[srt],
                        polys[srt], terms[srt], n00, tuple(delta), seed, len(sub.cells),
                        time.perf_counter() - t0, list(labels))
