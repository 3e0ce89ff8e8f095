"""Samples that qhull leaves out of the segment construction's triangulation are put back locally.

The triangulation of samples (:func:`runtime.segments.sampling.triangulation`) may drop samples
qhull calls coplanar; :func:`runtime.segments.sampling.insert_samples` inserts them again by a
local Bowyer–Watson step.  The reference is the Delaunay triangulation of all the points computed
by scipy from scratch (unique for points in general position: Delaunay 1934)."""
import numpy as np
from scipy.spatial import Delaunay

from curvedvoronoi.runtime.segments.sampling import insert_samples, triangulation


def _triangles(P, simp):
    return {frozenset(map(tuple, P[t].tolist())) for t in simp}


def test_inserted_samples_give_the_delaunay_triangulation_of_all():
    rng = np.random.default_rng(5)
    P = rng.uniform(0, 100, (400, 2))
    new = rng.uniform(10, 90, (30, 2))
    tri = triangulation(P, np.arange(len(P)))
    out = insert_samples(tri, new, np.arange(len(P), len(P) + len(new)))
    assert len(out.P) == len(P) + len(new)
    allP = np.vstack([P, new])
    assert _triangles(out.P, out.simp) == _triangles(allP, Delaunay(allP).simplices)
    # labels travel with their samples
    lab = dict(zip(map(tuple, out.P.tolist()), out.lab.tolist()))
    assert all(lab[tuple(q)] == len(P) + k for k, q in enumerate(new.tolist()))


def test_a_sample_2e5_from_another_at_coordinates_1e4_is_inserted():
    """The configuration of 10⁵ random segments where qhull dropped the one sample showing a
    segment's interior inside an empty circle: a sample 1.9·10⁻⁵ from a segment's end."""
    rng = np.random.default_rng(1)
    P = rng.uniform(-350, 350, (2000, 2)) + [14356.0, 10792.0]
    P = np.vstack([P, [[14356.0, 10792.0]]])
    f = np.array([[14355.999981, 10792.000001]])
    tri = triangulation(P, np.arange(len(P)))
    out = insert_samples(tri, f, np.array([len(P)]))
    allP = np.vstack([P, f])
    assert len(out.P) == len(allP)
    assert _triangles(out.P, out.simp) == _triangles(allP, Delaunay(allP).simplices)


def test_repeated_samples_are_left_out():
    rng = np.random.default_rng(2)
    P = rng.uniform(0, 1, (50, 2))
    tri = triangulation(P, np.arange(50))
    out = insert_samples(tri, np.vstack([P[:3], [[0.5, 0.5], [0.5, 0.5]]]), np.arange(50, 55))
    assert len(out.P) == 51
