"""The cavity of a local Bowyer–Watson step is the connected set of conflict triangles around the
new sample (Bowyer 1981, Watson 1981).

qhull's triangulation of a million samples is Delaunay only up to its tolerance: a sliver of
nearly collinear samples of one segment may have a circumdisk that holds other samples, and, widened
by the rounding room of the conflict test, reaches a new sample far away.  In the 10⁵-segment
scene such a sliver 4 700 units from the new sample joined the cavity; the cavity was then two
pieces and the step refused, every round.  Here the sliver is made by flipping the Delaunay diagonal
of a flat quadrilateral (a valid triangulation that is not Delaunay there), and a sample is
inserted 6 units away, inside the sliver's disk.  The reference for the triangles around the new
sample is scipy's Delaunay triangulation of all the points (unique in general position)."""
import numpy as np
from scipy.spatial import Delaunay

from curvedvoronoi.runtime.voronoi import sample_delaunay
from curvedvoronoi.runtime.voronoi.sample_delaunay import SampleTriangulation


def _neighbours(simp):
    side = {}
    nb = np.full(simp.shape, -1)
    for t, tri in enumerate(simp.tolist()):
        for k in range(3):
            key = frozenset((tri[(k + 1) % 3], tri[(k + 2) % 3]))
            if key in side:
                u, j = side.pop(key)
                nb[t, k], nb[u, j] = u, t
            else:
                side[key] = (t, k)
    return nb


def _flip(simp, a, b):
    """The triangulation with the diagonal (a, b) of its quadrilateral replaced by the other one."""
    two = [t for t, tri in enumerate(simp.tolist()) if a in tri and b in tri]
    assert len(two) == 2
    c, d = (next(v for v in simp[t].tolist() if v not in (a, b)) for t in two)
    out = np.delete(simp, two, axis=0)
    return np.vstack([out, [[c, d, a], [d, c, b]]]), c, d


def test_a_non_delaunay_sliver_far_away_stays_out_of_the_cavity():
    rng = np.random.default_rng(3)
    P = rng.uniform(0, 40, (300, 2))
    flat = np.array([[20.0, 20.0], [22.0, 20.0], [21.0, 20.001], [21.0, 19.999]])
    keep = np.min(np.hypot(*(P[:, None, :] - flat[None, :, :]).transpose(2, 0, 1)), axis=1) > 1.5
    P = np.vstack([P[keep], flat])
    n = len(P)
    a, b, c, d = n - 4, n - 3, n - 2, n - 1        # the Delaunay diagonal of a, c, b, d is (c, d)
    simp = Delaunay(P).simplices
    assert any(c in t and d in t for t in simp.tolist())
    simp, *_ = _flip(simp, c, d)                     # now (a, b): slivers (a, b, c) and (a, b, d)
    # counter-clockwise corners, as qhull's
    area = ((P[simp[:, 1]] - P[simp[:, 0]]) * (P[simp[:, 2]] - P[simp[:, 0]])[:, ::-1] * [1, -1]).sum(axis=1)
    simp[area < 0] = simp[area < 0][:, [0, 2, 1]]
    tri = SampleTriangulation(P, np.arange(n), simp, _neighbours(simp))
    new = np.array([[21.3, 14.2]])                  # inside the disk of (a, b, c), 6 units below it
    cx, cy = 21.0, 20.001 - (1 + 0.001 ** 2) / 0.002
    assert np.hypot(new[0, 0] - cx, new[0, 1] - cy) < (1 + 0.001 ** 2) / 0.002
    out = tri.update(np.zeros(0, np.int64), new, np.array([n]))
    assert out is not None
    allP = np.vstack([P, new])
    ref = Delaunay(allP)
    star_ref = {frozenset(map(tuple, allP[t].tolist())) for t in ref.simplices if n in t}
    k = int(np.nonzero((out.P == new[0]).all(axis=1))[0][0])
    star = {frozenset(map(tuple, out.P[t].tolist())) for t in out.simp if k in t}
    assert star == star_ref
    # the far sliver is left as it was: the update is local
    sliver = {frozenset(map(tuple, P[[a, b, c]].tolist())), frozenset(map(tuple, P[[a, b, d]].tolist()))}
    assert sliver <= {frozenset(map(tuple, out.P[t].tolist())) for t in out.simp}


def test_a_cavity_of_more_than_46341_samples_is_filled_locally(monkeypatch):
    """The keys of the cavity's sides are ``min·m + max`` over its m local samples: above
    m = 46 341 they exceed 2³¹ and must not wrap in qhull's int32 indices (the step then saw no
    boundary side in the local triangulation and declined, forcing a full triangulation).
    Removing every other interior sample of 10⁵ puts nearly every triangle in the cavity and
    leaves m = 5·10⁴ local samples, numbered up to m on the boundary sides.  By default such a
    cavity is declined for memory (``CAVITY_MAX``); with the limit raised it is filled."""
    rng = np.random.default_rng(5)
    P = rng.uniform(0, 1, (100000, 2))
    tri = SampleTriangulation(P, np.arange(len(P)))
    hull = np.zeros(len(P), bool)
    hull[Delaunay(P).convex_hull.ravel()] = True
    remove = np.nonzero(~hull & (np.arange(len(P)) % 2 == 0))[0]
    assert tri.update(remove, np.zeros((0, 2)), np.zeros(0, np.int64)) is None
    monkeypatch.setattr(sample_delaunay, "CAVITY_MAX", 10 ** 6)
    out = tri.update(remove, np.zeros((0, 2)), np.zeros(0, np.int64))
    assert out is not None
    kept = np.setdiff1d(np.arange(len(P)), remove)
    assert np.array_equal(out.P, P[kept])
    ref = {tuple(sorted(t)) for t in Delaunay(P[kept]).simplices.tolist()}
    got = {tuple(sorted(t)) for t in out.simp.tolist()}
    assert got == ref
