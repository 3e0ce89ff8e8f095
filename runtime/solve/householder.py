"""Rank decisions and Householder products of pivoted QR factorisations (Golub & Van Loan,
*Matrix Computations*, 4th ed., §5.2 and §5.4.2).

Both Macaulay null-space solvers (:mod:`runtime.solve.macaulay`, weighted degree in (x, y, R);
:mod:`runtime.solve.toric`, a polytope in circle space) take null spaces from a column-pivoted
QR of the transposed matrix: its numerical rank is read off |diag R| and the trailing columns of
the orthogonal factor are applied with LAPACK ``ormqr`` without forming Q.
"""
from __future__ import annotations

import math

import numpy as np
import scipy.linalg as sla

from ..result import LocatorError

__all__ = ["householder_apply", "rank_from_values"]


def rank_from_values(vals: np.ndarray, tol: float) -> tuple[int, float]:
    """Numerical rank from decreasing magnitudes (singular values or |diag R|): the number above
    ``tol``, and the ratio across the cut (inf when nothing is dropped or kept)."""
    if len(vals) == 0:
        return 0, math.inf
    r = int((vals > tol).sum())
    if r == len(vals) or r == 0:
        return r, math.inf
    return r, (vals[r - 1] / vals[r]) if vals[r] > 0 else math.inf


def householder_apply(qr, tau, C, trans: str):
    """Q·C (trans "N") or Qᵀ·C ("T") for the full orthogonal Q of a raw Householder QR
    (``scipy.linalg.qr(mode="raw")``), by LAPACK ormqr."""
    ormqr, = sla.get_lapack_funcs(("ormqr",), (qr,))
    qr = np.asfortranarray(qr[:, :len(tau)])      # a wide matrix has min(m, n) reflectors
    C = np.asfortranarray(C, dtype=qr.dtype)
    _, work, info = ormqr("L", trans, qr, tau, C, -1)
    lwork = max(int(work[0].real), 1)
    out, _, info = ormqr("L", trans, qr, tau, C, lwork, overwrite_c=True)
    if info != 0:
        raise LocatorError(f"internal error: LAPACK ormqr failed (info {info})")
    return out
