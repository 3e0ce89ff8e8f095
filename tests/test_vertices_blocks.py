"""The block form of the Macaulay matrix used by the projected null space (runtime.solve.vertices):
the blocks filled straight from the cached pattern are the submatrices of the dense Macaulay
matrix, and the projected null space computed from them is annihilated by the projected matrix."""
from __future__ import annotations

import numpy as np

from curvedvoronoi.runtime.algebra.polyalg import CanonicalOffset, compose_offset, working_frame
from curvedvoronoi.runtime.predicates.locator import demo_configuration
from curvedvoronoi.runtime.solve.macaulay import (TOP_DEGREES, macaulay_blocks, macaulay_matrix, monomials,
                                                  solve_nullspace)


def _polys(cs):
    offs = [CanonicalOffset(c) for c in cs]
    wf = working_frame(cs, cs[0])
    return [compose_offset(o, wf) for o in offs], [o.wdeg for o in offs]


def test_blocks_are_the_submatrices_of_the_macaulay_matrix():
    polys, wdegs = _polys(demo_configuration()[:3])
    for d, top in ((12, 2), (19, TOP_DEGREES)):
        M = macaulay_matrix(polys, wdegs, d)
        degs = monomials(d)[1]
        hi = degs > d - top
        touch = np.any(M[:, hi] != 0, axis=1)
        MH, ML, MU, shape = macaulay_blocks(polys, wdegs, d, top)
        assert shape == M.shape
        assert MH.flags.f_contiguous and ML.flags.f_contiguous
        assert np.array_equal(MH, M[np.ix_(touch, hi)])
        assert np.array_equal(ML, M[np.ix_(touch, ~hi)])
        assert np.array_equal(MU, M[np.ix_(~touch, ~hi)])
        # the untouched rows really vanish on the top-degree columns
        assert not np.any(M[np.ix_(~touch, hi)])


def test_projected_nullspace_of_the_blocks_solves_the_macaulay_rows():
    """Every null vector z (low-degree columns) extends to (w, z) with M·(w, z) ≈ 0: the
    least-squares residual over w is at rounding level, and the count of finite solutions is the
    generic 184 of three ellipses (generated/counts/root_counts.json)."""
    polys, wdegs = _polys(demo_configuration()[:3])
    d = 19
    roots, info = solve_nullspace(polys, wdegs, d, gap_hint=15)
    assert info.nullspace == "projected" and info.n_finite == 184 == len(roots)
    M = macaulay_matrix(polys, wdegs, d)
    degs = monomials(d)[1]
    hi = degs > d - TOP_DEGREES
    # the roots satisfy the offsets in working coordinates (checks the whole chain)
    E = monomials(d)[0]
    for p in polys:
        ex = np.array(list(p.keys()))
        c = np.array(list(p.values()))
        vals = (c[None, :] * roots[:, None, 0] ** ex[None, :, 0] * roots[:, None, 1] ** ex[None, :, 1]
                * roots[:, None, 2] ** ex[None, :, 2]).sum(axis=1)
        scale = (np.abs(c[None, :]) * np.abs(roots[:, None, 0]) ** ex[None, :, 0]
                 * np.abs(roots[:, None, 1]) ** ex[None, :, 1] * np.abs(roots[:, None, 2]) ** ex[None, :, 2]).sum(axis=1)
        assert np.median(np.abs(vals) / scale) < 1e-8
    assert M.shape == info.matrix_shape and E.shape[0] == M.shape[1] and hi.any()
