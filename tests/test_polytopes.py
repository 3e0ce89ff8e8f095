"""Exact polyhedral geometry (thesis §3.3.1, Definitions 3.3.1-3.3.2)."""
import math
from fractions import Fraction

import flint
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.spatial import ConvexHull

from curvedvoronoi.precompute.polytopes import (affine_rank, as_points, convex_hull, in_convex_hull, lattice_points,
                                  minkowski_sum, normalized_volume, support, vertices)


def test_support_strophoid():
    # thesis §3.3.1: y^2 - x^2 - x^3 has exponent vectors (0,2), (2,0), (3,0)
    ctx = flint.fmpz_mpoly_ctx.get(("x", "y"), "lex")
    x, y = ctx.gens()
    assert support(y**2 - x**2 - x**3).tolist() == [[0, 2], [2, 0], [3, 0]]
    assert support({(1, 0): 3, (0, 0): 0}).tolist() == [[1, 0]]
    with pytest.raises(ValueError):
        support({(1, 0): 0})


def test_cube_and_simplex_volumes_and_lattice_points():
    cube = [[i, j, k] for i in (0, 1) for j in (0, 1) for k in (0, 1)]
    h = convex_hull(cube)
    assert h.nvolume == 6 and len(h.normals) == 6 and len(h.vertices) == 8
    for k in range(1, 5):
        simplex = [[0, 0, 0], [k, 0, 0], [0, k, 0], [0, 0, k]]
        hs = convex_hull(simplex)
        assert hs.nvolume == k**3
        assert len(lattice_points(hs)) == math.comb(k + 3, 3)
        # E = (Q + δ) ∩ Z^3 with δ < 0: p − δ ∈ Q keeps the coordinate facets and drops the
        # points with x + y + z = k
        pts = lattice_points(hs, (Fraction(-1, 97), Fraction(-1, 89), Fraction(-1, 83)))
        assert len(pts) == math.comb(k + 2, 3)


def test_minkowski_sum_of_segments_is_zonotope():
    segs = [[[0, 0], [1, 0]], [[0, 0], [0, 1]], [[0, 0], [1, 1]]]
    z = minkowski_sum(*segs)
    assert len(z) == 6
    # normalised volume of a zonotope = 2! * sum |det| over pairs
    assert normalized_volume(z) == 2 * (1 + 1 + 1)


def test_lower_dimensional_vertices_and_rank():
    pts = [[0, 0, 0], [1, 1, 0], [2, 2, 0], [0, 2, 0], [1, 2, 0]]
    assert affine_rank(pts) == 2
    assert vertices(pts).tolist() == [[0, 0, 0], [0, 2, 0], [2, 2, 0]]
    assert normalized_volume(pts) == 0
    assert in_convex_hull([1, 1, 0], np.array([[0, 0, 0], [2, 2, 0], [0, 2, 0]])) is True
    assert in_convex_hull([3, 1, 0], np.array([[0, 0, 0], [2, 2, 0], [0, 2, 0]])) is False


point_sets = st.lists(st.tuples(*[st.integers(-6, 6)] * 3), min_size=5, max_size=25)


@settings(max_examples=30, deadline=None)
@given(point_sets)
def test_hull_matches_qhull_volume_and_contains_points(pts):
    pts = as_points(pts)
    if affine_rank(pts) < 3:
        return
    h = convex_hull(pts)
    assert abs(h.nvolume - 6 * ConvexHull(pts.astype(float)).volume) < 1e-6
    assert h.contains(pts).all()
    # vertices are exactly the points that are not in the hull of the others
    for i, p in enumerate(pts.tolist()):
        others = np.delete(pts, i, axis=0)
        is_vertex = p in h.vertices.tolist()
        assert (in_convex_hull(p, others) is True) == (not is_vertex)


@settings(max_examples=15, deadline=None)
@given(point_sets, point_sets)
def test_minkowski_sum_vertices_and_volume(a, b):
    a, b = as_points(a), as_points(b)
    full = as_points((a[:, None, :] + b[None, :, :]).reshape(-1, 3))
    red = minkowski_sum(a, b)
    assert set(map(tuple, red.tolist())) <= set(map(tuple, full.tolist()))
    assert normalized_volume(red) == normalized_volume(full)
    if affine_rank(full) == 3:
        assert convex_hull(full).vertices.tolist() == red.tolist()
