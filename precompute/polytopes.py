"""Exact integer polyhedral geometry: supports, Newton polytopes, Minkowski sums, lattice points.

Thesis §3.3.1 (Definitions 3.3.1–3.3.3): the *support* of a Laurent polynomial is the set of
exponent vectors of its nonzero terms, its *Newton polytope* the convex hull of the support, and
the Minkowski sum ``A + B = {a + b}``.  Everything here is exact:

* point sets are ``numpy`` ``int64`` arrays of shape ``(m, N)`` (one exponent vector per row);
* floating point (Qhull through :class:`scipy.spatial.ConvexHull`, HiGHS through
  :func:`scipy.optimize.linprog`) is only used to *propose* an answer, which is then re-checked
  in exact integer / rational arithmetic (python ``int``, :class:`fractions.Fraction`,
  ``flint.fmpz_mat``).  A proposal that fails its exact check raises :class:`ArithmeticError`
  (for the hull) or is discarded conservatively (vertex reduction keeps a point it cannot
  prove redundant, which never changes a polytope).

Certificate used for :class:`ExactHull` (full-dimensional point sets): every facet hyperplane is
recomputed from integer points as a primitive integer normal ``n`` and offset ``h`` and
``n·p <= h`` is checked for every input point (so each hyperplane supports the set), and the
oriented integer "area vectors" (generalised cross products) of the triangulated boundary
simplices sum to zero (Minkowski's relation: the boundary is closed, so no facet is missing).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction
from typing import Iterable, Sequence

import flint
import numpy as np
from scipy.optimize import linprog
from scipy.spatial import ConvexHull, QhullError

__all__ = [
    "as_points", "support", "affine_rank", "ExactHull", "convex_hull", "vertices",
    "minkowski_sum", "normalized_volume", "lattice_points", "in_convex_hull", "generalised_cross",
]


# ----------------------------------------------------------------------------------------------
# supports
# ----------------------------------------------------------------------------------------------
def as_points(points: Iterable[Sequence[int]]) -> np.ndarray:
    """Integer point set as a sorted, duplicate-free ``int64`` array of shape ``(m, N)``."""
    arr = np.asarray(list(points) if not isinstance(points, np.ndarray) else points)
    if arr.ndim != 2 or arr.shape[0] == 0:
        raise ValueError(f"a point set must be a non-empty 2-d array, got shape {arr.shape}")
    if not np.issubdtype(arr.dtype, np.integer):
        if not np.all(arr == np.round(arr)):
            raise ValueError("points must have integer coordinates")
        arr = np.round(arr)
    arr = arr.astype(np.int64)
    return np.unique(arr, axis=0)


def support(poly, nvars: int | None = None) -> np.ndarray:
    """Support (Definition 3.3.1) of a polynomial.

    ``poly`` is a python-flint ``fmpz_mpoly`` / ``fmpq_mpoly`` or a mapping
    ``{exponent tuple: coefficient}``; zero coefficients are ignored.
    """
    terms = poly.to_dict() if hasattr(poly, "to_dict") else dict(poly)
    pts = [tuple(int(e) for e in k) for k, c in terms.items() if c != 0]
    if not pts:
        raise ValueError("the zero polynomial has an empty support")
    if nvars is not None and len(pts[0]) != nvars:
        raise ValueError(f"expected {nvars} variables, got {len(pts[0])}")
    return as_points(pts)


def affine_rank(points: np.ndarray) -> int:
    """Dimension of the affine hull of ``points`` (exact, via ``flint.fmpz_mat.rank``)."""
    pts = np.asarray(points, dtype=np.int64)
    if len(pts) == 1:
        return 0
    diff = (pts[1:] - pts[0]).tolist()
    return flint.fmpz_mat(diff).rank()


# ----------------------------------------------------------------------------------------------
# exact convex hull (full-dimensional sets)
# ----------------------------------------------------------------------------------------------
def generalised_cross(vectors: list[list[int]]) -> list[int]:
    """Generalised cross product of N-1 integer vectors in Z^N (cofactor expansion, exact)."""
    n = len(vectors) + 1
    out = []
    for j in range(n):
        minor = [[v[k] for k in range(n) if k != j] for v in vectors]
        det = int(flint.fmpz_mat(minor).det()) if n > 1 else 1
        out.append((-1) ** j * det)
    return out


@dataclass
class ExactHull:
    """Exact H- and V-description of the convex hull of a full-dimensional integer point set.

    ``normals @ x <= offsets`` describes the polytope (primitive integer normals, one row per
    facet, sorted); ``vertices`` are the vertices (sorted rows); ``nvolume`` is the normalised
    volume N!·Vol (an integer); ``simplices`` the triangulated boundary (indices into
    ``vertices``).
    """

    vertices: np.ndarray
    normals: np.ndarray
    offsets: np.ndarray
    nvolume: int
    simplices: np.ndarray

    @property
    def dim(self) -> int:
        return self.vertices.shape[1]

    def contains(self, points: np.ndarray, shift: Sequence[Fraction] | None = None) -> np.ndarray:
        """Boolean mask of ``points`` lying in the closed polytope (+ ``shift``), exactly."""
        pts = np.asarray(points, dtype=np.int64)
        if shift is None:
            return np.all(pts @ self.normals.T <= self.offsets, axis=1)
        den = math.lcm(*(Fraction(s).denominator for s in shift))
        num = np.array([int(Fraction(s) * den) for s in shift], dtype=np.int64)
        # p ∈ Q + s  <=>  n·(p − s) <= h  <=>  den·n·p <= den·h + n·num
        lhs = den * (pts @ self.normals.T)
        rhs = den * self.offsets + self.normals @ num
        return np.all(lhs <= rhs, axis=1)


def convex_hull(points: np.ndarray) -> ExactHull:
    """Exact convex hull of a full-dimensional integer point set (see the module docstring)."""
    pts = as_points(points)
    m, n = pts.shape
    if n == 1:
        lo, hi = int(pts[:, 0].min()), int(pts[:, 0].max())
        if lo == hi:
            raise ValueError("point set is not full-dimensional")
        return ExactHull(np.array([[lo], [hi]]), np.array([[-1], [1]]), np.array([-lo, hi]),
                         hi - lo, np.array([[0], [1]]))
    if affine_rank(pts) < n:
        raise ValueError("point set is not full-dimensional")
    try:
        hull = ConvexHull(pts.astype(float), qhull_options="Qt")
    except QhullError as exc:  # pragma: no cover - Qhull failure on a full-dimensional set
        raise ArithmeticError(f"Qhull failed: {exc}") from exc
    vidx = np.unique(hull.simplices)
    verts = pts[vidx]
    remap = {int(v): i for i, v in enumerate(vidx)}
    simp = np.array([[remap[int(v)] for v in s] for s in hull.simplices], dtype=np.int64)
    centroid2 = [Fraction(int(c), len(verts)) for c in verts.sum(axis=0)]
    facets: dict[tuple[int, ...], int] = {}
    area = [0] * n
    nvol = 0
    py_verts = verts.tolist()
    for s in simp.tolist():
        base = py_verts[s[0]]
        vecs = [[py_verts[k][j] - base[j] for j in range(n)] for k in s[1:]]
        nrm = generalised_cross(vecs)
        if not any(nrm):
            continue  # degenerate (flat) simplex of a triangulated facet: no area
        dot_c = sum(Fraction(nrm[j]) * (centroid2[j] - base[j]) for j in range(n))
        if dot_c > 0:
            nrm = [-c for c in nrm]
            dot_c = -dot_c
        area = [a + c for a, c in zip(area, nrm)]
        # normalised volume of the cone from the centroid: |det| = |n·(base − centroid)|
        nvol += -dot_c
        g = math.gcd(*nrm)
        prim = tuple(c // g for c in nrm)
        h = sum(prim[j] * base[j] for j in range(n))
        if facets.setdefault(prim, h) != h:
            raise ArithmeticError("Qhull proposed two parallel facets with the same normal")
    if any(area):
        raise ArithmeticError("hull certificate failed: boundary area vectors do not sum to 0")
    normals = np.array(sorted(facets), dtype=np.int64)
    offsets = np.array([facets[tuple(r)] for r in normals.tolist()], dtype=np.int64)
    if not np.all(pts @ normals.T <= offsets):
        raise ArithmeticError("hull certificate failed: a point lies outside a proposed facet")
    if nvol.denominator != 1:
        raise ArithmeticError("normalised volume of a lattice polytope must be an integer")
    order = np.lexsort(verts.T[::-1])
    inv = np.empty_like(order)
    inv[order] = np.arange(len(order))
    return ExactHull(verts[order], normals, offsets, int(nvol), inv[simp])


def normalized_volume(points: np.ndarray) -> int:
    """N!·Vol_N(conv(points)) (0 if the set is not full-dimensional), exact."""
    pts = as_points(points)
    if affine_rank(pts) < pts.shape[1]:
        return 0
    return convex_hull(pts).nvolume


# ----------------------------------------------------------------------------------------------
# vertices (any dimension) and Minkowski sums
# ----------------------------------------------------------------------------------------------
def in_convex_hull(point: Sequence[int], points: np.ndarray) -> bool | None:
    """Exact membership certificate: True if ``point`` is proven in conv(points), False if an
    LP says no, None if the LP proposed a combination that failed its exact re-check."""
    pts = np.asarray(points, dtype=np.int64)
    m, n = pts.shape
    a_eq = np.vstack([pts.T.astype(float), np.ones((1, m))])
    b_eq = np.concatenate([np.asarray(point, dtype=float), [1.0]])
    res = linprog(np.zeros(m), A_eq=a_eq, b_eq=b_eq, bounds=[(0, None)] * m, method="highs")
    if res.status != 0:
        return False
    # exact re-check on a basic support (<= n+1 points): solve the affine combination exactly
    idx = np.flatnonzero(res.x > 1e-9)
    if len(idx) > n + 1:
        idx = idx[np.argsort(-res.x[idx])][: n + 1]
    sub = pts[idx]
    mat = flint.fmpq_mat([[int(sub[k][j]) for k in range(len(idx))] for j in range(n)]
                         + [[1] * len(idx)])
    rhs = flint.fmpq_mat([[int(c)] for c in point] + [[1]])
    try:
        if len(idx) == mat.nrows():
            lam = mat.solve(rhs)
        else:  # least-squares-free exact solve: use the normal equations (full column rank)
            mt = mat.transpose()
            lam = (mt * mat).solve(mt * rhs)
            if mat * lam != rhs:
                return None
    except ZeroDivisionError:
        return None
    if all(lam[k, 0] >= 0 for k in range(len(idx))):
        return True
    return None


def vertices(points: np.ndarray) -> np.ndarray:
    """Vertices of conv(points) (sorted rows), exact, in any dimension.

    Full-dimensional sets use :func:`convex_hull`; lower-dimensional ones an LP per point with
    an exact re-check, keeping a point unless it is *proven* redundant.
    """
    pts = as_points(points)
    if len(pts) <= 2:
        return pts
    n = pts.shape[1]
    if affine_rank(pts) == n:
        return convex_hull(pts).vertices
    keep = np.ones(len(pts), dtype=bool)
    for i in range(len(pts)):
        others = pts[keep & (np.arange(len(pts)) != i)]
        if in_convex_hull(pts[i], others) is True:
            keep[i] = False
    return pts[keep]


def minkowski_sum(*point_sets: np.ndarray, reduce: bool = True) -> np.ndarray:
    """Minkowski sum (Definition 3.3.2) of point sets.

    With ``reduce`` (default) only the vertices of the sum are returned (vertices of each
    summand are summed, then reduced exactly); otherwise the full set {a + b + ...}.
    """
    if not point_sets:
        raise ValueError("need at least one point set")
    acc = as_points(point_sets[0])
    if reduce:
        acc = vertices(acc)
    for s in point_sets[1:]:
        s = as_points(s)
        if reduce:
            s = vertices(s)
        acc = as_points((acc[:, None, :] + s[None, :, :]).reshape(-1, acc.shape[1]))
        if reduce:
            acc = vertices(acc)
    return acc


# ----------------------------------------------------------------------------------------------
# lattice points
# ----------------------------------------------------------------------------------------------
def lattice_points(hull: ExactHull, shift: Sequence[Fraction] | None = None,
                   chunk: int = 2_000_000) -> np.ndarray:
    """All integer points of the polytope ``hull`` (+ ``shift``), sorted lexicographically.

    With a generic shift δ this is the set E = (Q + δ) ∩ Z^N of Theorem 3.3.14.
    """
    n = hull.dim
    sh = [Fraction(0)] * n if shift is None else [Fraction(s) for s in shift]
    lo = [math.floor(int(hull.vertices[:, j].min()) + sh[j]) for j in range(n)]
    hi = [math.ceil(int(hull.vertices[:, j].max()) + sh[j]) for j in range(n)]
    # enumerate the box slice by slice along the first coordinate (bounded memory)
    out = []
    rest = [np.arange(lo[j], hi[j] + 1, dtype=np.int64) for j in range(1, n)]
    grid = (np.stack(np.meshgrid(*rest, indexing="ij"), axis=-1).reshape(-1, n - 1)
            if n > 1 else np.zeros((1, 0), dtype=np.int64))
    for x0 in range(lo[0], hi[0] + 1):
        for start in range(0, len(grid), chunk):
            g = grid[start:start + chunk]
            cand = np.hstack([np.full((len(g), 1), x0, dtype=np.int64), g])
            mask = hull.contains(cand, sh if shift is not None else None)
            if mask.any():
                out.append(cand[mask])
    if not out:
        return np.zeros((0, n), dtype=np.int64)
    res = np.vstack(out)
    return res[np.lexsort(res.T[::-1])]
