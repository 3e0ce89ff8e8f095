"""Local updates of the diagram construction against independent references.

* The batch Bowyer–Watson update of the sample triangulation
  (``SampleTriangulation.update``) against a fresh qhull triangulation of the same points: every
  triangle must have an empty circumdisk (checked directly with a k-d tree), the triangles
  with two or three labels (the ones the construction reads) must be qhull's, the areas must
  add up to the hull's; the vectorised edge walks equal the step-by-step walks.
* Deletion of a site (``Diagram.delete_site``) against a construction from scratch without it
  and against CGAL's Apollonius graph of the remaining circles (independent code, exact
  predicates); the remaining sites are renumbered (j > i becomes j − 1).
* Non-generic ellipse inputs (identical translated ellipses, axis-aligned ellipses): every
  vertex proved and the diagram checked on a dense grid.
"""
from __future__ import annotations

import random
import sys
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial import ConvexHull, Delaunay, cKDTree

from curvedvoronoi.runtime.voronoi.construction import voronoi
from curvedvoronoi.runtime.voronoi.sample_delaunay import SampleTriangulation

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "cgal"))
sys.path.insert(0, str(ROOT / "tests"))

import cgal_peer  # noqa: E402
from test_voronoi_construction import _window, check_points, ellipse, grid_check  # noqa: E402


def _circle_samples(C, R, n_per, lab0=0):
    t = 2 * np.pi * np.arange(n_per) / n_per
    P = np.concatenate([np.column_stack([c[0] + r * np.cos(t), c[1] + r * np.sin(t)]) for c, r in zip(C, R)])
    return P, np.repeat(np.arange(lab0, lab0 + len(C)), n_per)


def _multi_label(simp, lab):
    s = np.sort(simp, axis=1)
    L = lab[s]
    multi = ~((L[:, 0] == L[:, 1]) & (L[:, 1] == L[:, 2]))
    return set(map(tuple, s[multi].tolist()))


def _check_delaunay(T: SampleTriangulation):
    P = T.P
    rad = np.hypot(*(P[T.simp[:, 0]] - T.cc).T)
    inside = cKDTree(P).query_ball_point(T.cc, rad * (1 - 1e-9), return_length=True)
    assert (inside == 0).all(), "a triangle of the update has a sample inside its circumdisk"
    A, B, C = (P[T.simp[:, k]] for k in range(3))
    area = np.abs((B[:, 0] - A[:, 0]) * (C[:, 1] - A[:, 1]) - (B[:, 1] - A[:, 1]) * (C[:, 0] - A[:, 0])).sum() / 2
    assert area == pytest.approx(ConvexHull(P).volume, rel=1e-9)
    ref = Delaunay(P)
    assert _multi_label(T.simp, T.lab) == _multi_label(ref.simplices, T.lab)
    # neighbours: symmetric, and across the side opposite corner k
    t, k = np.nonzero(T.nb >= 0)
    u = T.nb[t, k]
    assert np.all((T.nb[u] == t[:, None]).any(axis=1))


@pytest.mark.parametrize("seed", [0, 1])
def test_sample_triangulation_update_is_qhull_delaunay(seed):
    rng = np.random.default_rng(seed)
    C, R = [], []
    while len(C) < 40:                    # disjoint circles in a square
        c, r = rng.uniform(0, 60, 2), rng.uniform(0.5, 2.5)
        if all(np.hypot(*(c - d)) > r + s + 0.3 for d, s in zip(C, R)):
            C.append(c)
            R.append(r)
    P, lab = _circle_samples(C, R, 12)
    T = SampleTriangulation(P, lab)
    # insertion: double the samples of a few circles (the old samples stay), some on the hull
    idx = rng.choice(40, 8, replace=False)
    t = 2 * np.pi * (np.arange(12) + 0.5) / 24 * 2
    Pn = np.concatenate([np.column_stack([C[i][0] + R[i] * np.cos(t), C[i][1] + R[i] * np.sin(t)]) for i in idx])
    T2 = T.update(np.zeros(0, int), Pn, np.repeat(idx, 12))
    assert T2 is not None
    _check_delaunay(T2)
    # the vectorised walks (list ranking) are the step-by-step walks, in the same order
    assert T2.walks() == T2.walks(vectorised=False)
    # removal of all the samples of an interior circle
    inner = [i for i in range(40) if not np.isin(np.nonzero(T2.lab == i)[0],
                                                 T2.simp[np.nonzero(T2.nb == -1)[0]]).any()]
    T3 = T2.update(np.nonzero(T2.lab == inner[0])[0], np.zeros((0, 2)), np.zeros(0, int))
    assert T3 is not None and not (T3.lab == inner[0]).any()
    _check_delaunay(T3)


def test_update_declines_when_a_hull_sample_is_removed():
    P, lab = _circle_samples([(0, 0), (5, 0), (2, 4)], [1, 1, 1], 10)
    T = SampleTriangulation(P, lab)
    assert T.update(np.nonzero(lab == 0)[0], np.zeros((0, 2)), np.zeros(0, int)) is None


def _edges(d):
    return [list(e) for e in d.delaunay_edges()]


def test_delete_circles_equals_scratch_and_cgal(cgal_peer_program):
    circles = cgal_peer.random_disjoint_circles(150, 7)
    d = voronoi(circles, certify=False)
    rng = random.Random(3)
    alive = list(range(len(circles)))
    for _ in range(3):
        k = rng.randrange(len(alive))
        d = d.delete_site(k, certify=False)
        alive.pop(k)
        rest = [circles[i] for i in alive]
        assert d.stats["deletion"] in ("local", "local triangulation declined")
        # renumbered: site j of the result is the j-th remaining input site
        assert [(float(s.cx), float(s.cy)) for s in d.sites] == [(x, y) for x, y, _ in rest]
        assert all(v.certified for v in d.vertices), d.problems
        assert _edges(d) == _edges(voronoi(rest, certify=False))
        assert _edges(d) == [list(e) for e in cgal_peer.delaunay_edges(rest)[0]]
    # the polylines (reused ones included) lie on their bisectors, no other site closer
    check_points(d.sites, d)


def test_delete_hull_circle_and_from_json():
    from curvedvoronoi.runtime.voronoi.structure import Diagram

    circles = [(0, 0, 1), (5, 0, 1), (2, 4, 1), (2, 1.5, 0.3), (8, 3, 1)]
    d = voronoi(circles, certify=False)
    d2 = d.delete_site(4, certify=False)        # a hull site: the local update declines
    assert _edges(d2) == _edges(voronoi(circles[:4], certify=False)) == [[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]]
    with pytest.raises(ValueError, match="no construction state"):
        Diagram.from_json(d.to_json()).delete_site(3, certify=False)
    pts = [(0, 0, 0), (4, 0, 0), (2, 3, 0), (2, 1, 0)]     # points only: rebuilt from scratch
    d4 = voronoi(pts, certify=False).delete_site(3, certify=False)
    assert d4.stats["deletion"] == "rebuild" and _edges(d4) == [[0, 1], [0, 2], [1, 2]]
    with pytest.raises(IndexError):
        d.delete_site(5)


def test_delete_ellipse_equals_scratch_certified():
    sites = [ellipse(0, 0, 2, 1), ellipse(6, 0, 2, 1, Fraction(3, 5), Fraction(4, 5)),
             ellipse(3, 5, 1, Fraction(1, 2)), ellipse(-3, 5, Fraction(3, 2), 1, Fraction(5, 13), Fraction(12, 13)),
             ellipse(3, -5, 1, Fraction(3, 4)), ellipse(3, 1, Fraction(1, 2), Fraction(1, 3))]
    d = voronoi(sites)
    assert d.certified, d.problems
    d2 = d.delete_site(5, certify=True)         # the middle ellipse: its region is shared out (locally)
    ref = voronoi(sites[:5], certify=False)
    assert _edges(d2) == _edges(ref)
    assert all(v.certified for v in d2.vertices)
    check_points(sites[:5], d2, rel=1e-6)
    assert d2.certified, d2.problems


def _translated(n, seed):
    rng = random.Random(seed)
    side = int(np.ceil(np.sqrt(n)))
    return [ellipse(6 * (k % side) + Fraction(rng.randint(-32, 32), 64), 6 * (k // side) + Fraction(rng.randint(-32, 32), 64),
                    2, Fraction(6, 5), Fraction(3, 5), Fraction(4, 5)) for k in range(n)]


def _axis_aligned(n, seed):
    rng = random.Random(seed)
    out, placed = [], []
    while len(out) < n:
        cx, cy = Fraction(rng.randint(0, 30 * 16), 16), Fraction(rng.randint(0, 30 * 16), 16)
        a = Fraction(rng.randint(16, 40), 16)
        b = a * Fraction(rng.randint(5, 14), 16)
        if all(float((cx - x) ** 2 + (cy - y) ** 2) ** 0.5 > float(a + r) + 0.1 for x, y, r in placed):
            out.append(ellipse(cx, cy, a, b))
            placed.append((cx, cy, a))
    return out


@pytest.mark.parametrize("make", [_translated, _axis_aligned], ids=["identical-translated", "axis-aligned"])
def test_non_generic_ellipses_every_vertex_proved(make):
    sites = make(16, 5)
    d = voronoi(sites, certify=False)
    assert d.vertices and all(v.certified for v in d.vertices), d.problems
    assert [p for p in d.problems if "certify=False" not in p] == []
    check_points(sites, d, rel=1e-6)
    grid_check(sites, d, _window(sites, 0.2), n=260)
