"""The batch Delaunay update of the sample triangulation with collinear samples on the hull.

Segments on the convex hull of a scene put runs of collinear samples on the hull of the sample
triangulation; refinement replaces them (new parameters (k + ½)/n) and adds samples on the same
line or beyond the hull.  ``SampleTriangulation.update`` must then give the Delaunay triangulation
of the new samples.  References, independent of the update: a k-d tree count of the samples
strictly inside every triangle's circumdisk (Delaunay's empty-circle property), the area of
scipy's convex hull, and scipy's own Delaunay triangulation of the same points (its triangles of
positive area; the zero-area slivers of collinear hull samples are not unique).
"""
from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial import ConvexHull, Delaunay, cKDTree

from curvedvoronoi.runtime.voronoi.sample_delaunay import SampleTriangulation


def _segment_samples(a, b, n):
    """n samples at parameters (k + ½)/n of the segment ab, computed as the construction does
    (A + t (B − A) in floats: a hair off the line when it is slanted)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    t = (np.arange(n) + 0.5) / n
    return a + t[:, None] * (b - a)


def _empty_circles(T: SampleTriangulation) -> int:
    """Number of (triangle, sample) pairs with the sample strictly inside the circumdisk
    (relative 10⁻⁹), zero-area triangles left out."""
    P = T.P
    A, B, C = (P[T.simp[:, k]] for k in range(3))
    area2 = np.abs((B[:, 0] - A[:, 0]) * (C[:, 1] - A[:, 1]) - (B[:, 1] - A[:, 1]) * (C[:, 0] - A[:, 0]))
    ok = area2 > 1e-9 * np.abs(P).max()
    cc = T.cc[ok]
    rad = np.hypot(*(A[ok] - cc).T)
    return int(cKDTree(P).query_ball_point(cc, rad * (1 - 1e-9), return_length=True).sum())


def _check(T: SampleTriangulation):
    P = T.P
    assert _empty_circles(T) == 0, "a triangle of the update has a sample inside its circumdisk"
    A, B, C = (P[T.simp[:, k]] for k in range(3))
    area = np.abs((B[:, 0] - A[:, 0]) * (C[:, 1] - A[:, 1]) - (B[:, 1] - A[:, 1]) * (C[:, 0] - A[:, 0])) / 2
    assert area.sum() == pytest.approx(ConvexHull(P).volume, rel=1e-9)
    assert len(np.unique(T.simp)) == len(P), "every sample is a corner"
    t, k = np.nonzero(T.nb >= 0)
    u = T.nb[t, k]
    assert np.all((T.nb[u] == t[:, None]).any(axis=1))
    # the same triangles of positive area as scipy's Delaunay triangulation of the same points
    ref = Delaunay(P)
    def big(simp):
        A_, B_, C_ = (P[simp[:, k]] for k in range(3))
        a2 = np.abs((B_[:, 0] - A_[:, 0]) * (C_[:, 1] - A_[:, 1]) - (B_[:, 1] - A_[:, 1]) * (C_[:, 0] - A_[:, 0]))
        s = np.sort(simp[a2 > 1e-6], axis=1)
        return set(map(tuple, s.tolist()))
    assert big(T.simp) == big(ref.simplices)


def _scene(rng, hull_runs):
    """Random interior samples in [5, 95]² and, along the given hull segments (a, b, n), their
    end points and n samples each; labels: one per interior sample, one per segment."""
    pts = [rng.uniform(5, 95, (400, 2))]
    labs = [np.arange(400)]
    ends = []
    for j, (a, b, n) in enumerate(hull_runs):
        pts.append(_segment_samples(a, b, n))
        labs.append(np.full(n, 1000 + j))
        ends += [a, b]
    ends = np.unique(np.array(ends, float), axis=0)
    pts.append(ends)
    labs.append(2000 + np.arange(len(ends)))
    return np.concatenate(pts), np.concatenate(labs)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_replacing_the_collinear_hull_samples_of_segments(seed):
    """The square's four sides are segments on the hull (one slanted side: a hair off its
    line); all their samples are replaced by twice as many, and interior samples move."""
    rng = np.random.default_rng(seed)
    sides = [((0, 0), (100, 0), 25), ((100, 0), (103, 100), 30), ((103, 100), (0, 100), 20), ((0, 100), (0, 0), 17)]
    P, lab = _scene(rng, sides)
    T = SampleTriangulation(P, lab)
    on_hull = (lab >= 1000) & (lab < 2000)
    assert np.isin(np.nonzero(on_hull)[0], T.simp[np.nonzero(T.nb == -1)[0]]).any()
    moved = rng.choice(400, 40, replace=False)
    remove = np.concatenate([np.nonzero(on_hull)[0], moved])
    new = [_segment_samples(a, b, 2 * n) for a, b, n in sides] + [P[moved] + rng.uniform(-1, 1, (40, 2))]
    newlab = np.concatenate([np.full(2 * n, 1000 + j) for j, (_, _, n) in enumerate(sides)] + [lab[moved]])
    T2 = T.update(remove, np.concatenate(new), newlab)
    assert T2 is not None, "collinear hull samples replaced: a local update was expected"
    _check(T2)
    assert len(T2.P) == len(P) - len(remove) + len(newlab)
    # the labels follow their samples
    where = {tuple(p): l for p, l in zip(np.concatenate([P, *new]).tolist(), np.concatenate([lab, newlab]).tolist())}
    assert [where[tuple(p)] for p in T2.P.tolist()] == T2.lab.tolist()


def test_new_samples_on_and_beyond_the_hull():
    """Samples added on the line of a hull side (inside and outside the side) and beyond the
    hull: the hull grows, collinear samples on its new sides."""
    rng = np.random.default_rng(7)
    sides = [((0, 0), (100, 0), 25), ((0, 100), (0, 0), 17)]
    P, lab = _scene(rng, sides)
    T = SampleTriangulation(P, lab)
    extra = np.concatenate([
        np.column_stack([np.linspace(105, 130, 6), np.zeros(6)]),  # the bottom line continued to (130, 0)
        _segment_samples((10, 0), (90, 0), 9) + [0.37, 0],  # on the bottom side, between samples
        _segment_samples((100, 100), (120, 120), 5),        # beyond the top right
        rng.uniform(5, 95, (30, 2)),
    ])
    T2 = T.update(np.zeros(0, int), extra, np.full(len(extra), 5000))
    assert T2 is not None
    _check(T2)
    # and back: the collinear samples of the continued line removed again (the corner (130, 0)
    # stays, so the hull polygon does not change)
    gone = np.nonzero((T2.lab == 5000) & (T2.P[:, 1] == 0) & (T2.P[:, 0] > 100) & (T2.P[:, 0] < 129))[0]
    assert len(gone) == 5
    T3 = T2.update(gone, np.zeros((0, 2)), np.zeros(0, int))
    assert T3 is not None
    _check(T3)


def test_removing_an_extreme_hull_sample_declines():
    """A removed corner of the hull polygon changes the hull: the update declines (a full
    triangulation is made instead) rather than returning a wrong hull."""
    rng = np.random.default_rng(3)
    P, lab = _scene(rng, [((0, 0), (100, 0), 25)])
    T = SampleTriangulation(P, lab)
    corner = int(np.nonzero((P[:, 0] == 100) & (P[:, 1] == 0))[0][0])
    assert T.update(np.array([corner]), np.zeros((0, 2)), np.zeros(0, int)) is None
