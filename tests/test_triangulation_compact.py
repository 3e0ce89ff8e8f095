"""The sample triangulation that a diagram keeps for deletions is compacted after the construction
(:meth:`runtime.voronoi.sample_delaunay.SampleTriangulation.compact`): the arrays it drops are made
again with the same values (corner labels from scipy's simplices, the number of labels counted per
triangle, circumcentres equidistant from the three corners), the seeds that were set come back
bit for bit (a NaN of another sign, a half-set row), and the polyline memo
(:class:`runtime.voronoi.edge_polylines.PolylineMemo`) answers as a dict built key by key.
"""
from __future__ import annotations

import numpy as np
from scipy.spatial import Delaunay

from curvedvoronoi.runtime.voronoi.edge_polylines import PolylineMemo
from curvedvoronoi.runtime.voronoi.sample_delaunay import SampleTriangulation


def _triangulation():
    rng = np.random.default_rng(5)
    P = rng.uniform(-10, 10, (400, 2))
    lab = (P[:, 0] > 0).astype(np.int64) + 2 * (P[:, 1] > 1.5)          # four labels by quadrant
    d = Delaunay(P)
    return P, lab, d, SampleTriangulation(P, lab, d.simplices, d.neighbors)


def test_dropped_arrays_come_back_with_the_same_values():
    P, lab, d, T = _triangulation()
    assert T.simp.dtype == np.int32 and T.nb.dtype == np.int32
    assert np.array_equal(T.simp, d.simplices) and np.array_equal(T.nb, d.neighbors)
    before = {k: getattr(T, k).copy() for k in ("L", "bich", "nlab", "cc")}
    T.compact()
    assert T._L is None and T._cc is None and T._nlab is None
    # references made apart: labels of the corners, labels counted per triangle, and the
    # circumcentre at equal distance from the three corners
    L = lab[d.simplices]
    assert np.array_equal(T.L, L)
    assert T.nlab.tolist() == [len(set(row)) for row in L.tolist()]
    assert T.bich.tolist() == [[row[(k + 1) % 3] != row[(k + 2) % 3] for k in range(3)] for row in L.tolist()]
    A, B, C = (P[d.simplices[:, k]] for k in range(3))
    ra, rb, rc = (np.hypot(*(X - T.cc).T) for X in (A, B, C))
    assert np.allclose(ra, rb, rtol=1e-9) and np.allclose(ra, rc, rtol=1e-9)
    for k, v in before.items():        # made again: the same bits
        assert np.array_equal(getattr(T, k), v), k


def test_the_seeds_that_were_set_survive_bit_for_bit():
    _, _, _, T = _triangulation()
    rows = [0, 5, 9]                  # any rows: the construction sets those of 3-label triangles
    negative_nan = -np.abs(np.float64(np.nan))
    T.seed[rows[0]] = (1.25, -3.5)
    T.seed[rows[1]] = (np.nan, 7.0)                 # half set
    T.seed[rows[2]] = (negative_nan, negative_nan)   # a NaN of the other sign
    bits = T.seed.copy().view(np.int64)
    T.compact()
    assert len(T._seed_rows[0]) == 3
    assert np.array_equal(T.seed.view(np.int64), bits)


def test_polyline_memo_answers_as_a_dict_of_its_keys():
    keys = np.array([[0.0] * 8 + [3.0], [1.0] * 8 + [4.0], [0.0] * 8 + [3.0]])     # key 0 repeated
    polys = [np.zeros((3, 2)), np.ones((4, 2)), np.full((3, 2), 2.0)]
    memo = PolylineMemo(keys, polys, np.array([0.5, 0.25, 0.125]))
    ref = {}
    for k, p, t in zip(keys, polys, (0.5, 0.25, 0.125)):
        ref[k.tobytes()] = (p, t)
    assert len(memo) == 3
    for k in ref:
        got = memo.get(k)
        assert got[0] is ref[k][0] and got[1] == ref[k][1] and type(got[1]) is float
    assert memo.get(np.full(9, 7.0).tobytes()) is None
