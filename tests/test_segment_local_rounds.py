"""Local rounds of the segment construction (runtime/segments/sampling.py ``retriangulation`` and
``triangulation(droppable=)``, runtime/segments/emptiness.py ``empty_by_filter`` in blocks).

References: the Delaunay triangulation of points in general position is unique, so the locally
updated triangulation must have exactly the triangles (as coordinate triples) of qhull run afresh
on the final samples; the diagram built with local rounds must have Boost.Polygon's Delaunay graph
(pyvoronoi, tests/peers_boost.py)."""
from __future__ import annotations

import sys
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial import Delaunay

sys.path.insert(0, str(Path(__file__).parent))
sys.path.insert(0, str(Path(__file__).with_name("cgal")))

from curvedvoronoi.runtime.segments import emptiness  # noqa: E402
from curvedvoronoi.runtime.segments.sampling import retriangulation, triangulation  # noqa: E402


def _triangles(P, simp) -> set:
    return {frozenset(map(tuple, P[t].tolist())) for t in simp}


def _fresh(P) -> set:
    return _triangles(P, Delaunay(P).simplices)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_retriangulation_is_the_delaunay_triangulation_of_the_new_samples(seed):
    rng = np.random.default_rng(seed)
    P = rng.uniform(0, 1000, (3000, 2))
    lab = np.arange(len(P)) // 10
    prev = triangulation(P, lab)
    # a refinement: the samples of some labels are replaced by others near them (none on the hull)
    hull = np.unique(Delaunay(P).convex_hull)
    inner = np.setdiff1d(np.arange(len(P)), hull)
    gone = rng.choice(inner, 300, replace=False)
    keep = np.ones(len(P), bool)
    keep[gone] = False
    new = P[gone] + rng.uniform(-3, 3, (300, 2))
    P2 = np.vstack([P[keep], new, rng.uniform(100, 900, (200, 2))])
    lab2 = np.concatenate([lab[keep], lab[gone], np.full(200, 999)])
    tri = retriangulation(prev, P2, lab2)
    assert tri is not None, "a local update was expected for 500 of 3 000 samples"
    assert len(tri.P) == len(P2)
    assert _triangles(tri.P, tri.simp) == _fresh(P2)
    # labels follow their samples
    where = {tuple(p): l for p, l in zip(P2.tolist(), lab2.tolist())}
    assert [where[tuple(p)] for p in tri.P.tolist()] == tri.lab.tolist()


def test_retriangulation_declines_a_relabelled_sample():
    rng = np.random.default_rng(5)
    P = rng.uniform(0, 100, (500, 2))
    lab = np.arange(len(P))
    prev = triangulation(P, lab)
    lab2 = lab.copy()
    lab2[7] = 10_000
    assert retriangulation(prev, P, lab2) is None


def test_triangulation_drops_coplanar_curve_samples_only():
    rng = np.random.default_rng(3)
    P = rng.uniform(0, 100, (400, 2))
    twin = P[10] + np.array([1e-13, 0.0])          # a rounding away from sample 10
    Q = np.vstack([P, twin])
    lab = np.arange(len(Q))
    tri = triangulation(Q, lab, droppable=lab == len(P))
    assert len(tri.P) == len(P)
    assert _triangles(tri.P, tri.simp) == _fresh(P)
    # a point site may not be dropped: every sample stays a corner (joggled triangulation)
    tri = triangulation(Q, lab, droppable=np.zeros(len(Q), bool))
    assert len(tri.P) == len(Q) and len(np.unique(tri.simp)) == len(Q)


def test_emptiness_filter_blocks_give_the_same_verdicts(monkeypatch):
    """The blocked filter answers exactly as one block over all jobs."""
    import scenes
    from scipy.spatial import cKDTree

    import curvedvoronoi as cv
    from curvedvoronoi.runtime.segments.elementary import decompose
    from curvedvoronoi.runtime.segments.newton import prove_vertices
    from curvedvoronoi.runtime.segments.sampling import initial_spacing, samples

    segs = [cv.Segment(*s) for s in scenes.random_segments(150, 4)]
    E = decompose(segs, list(range(len(segs))))
    sp = initial_spacing(E)
    P, lab = samples(E, sp)
    tri = triangulation(P, lab)
    three = np.nonzero(tri.nlab == 3)[0]
    items = [(tuple(sorted(int(v) for v in tri.L[t])), tri.cc[t]) for t in three if np.isfinite(tri.cc[t]).all()]
    sols = prove_vertices(E, items, cache={})
    jobs = [(tr, so) for (tr, _), so in zip(items, sols) if so.status == "proved"]
    assert len(jobs) > 100
    hmax = float(np.max(sp[np.isfinite(sp)]))
    tree = cKDTree(P)
    whole = emptiness.filter_block(E, tree, lab, hmax, jobs)
    monkeypatch.setattr(emptiness, "FILTER_BLOCK", 7)
    blocked = emptiness.empty_by_filter(E, tree, lab, hmax, jobs)
    assert whole == blocked and len(whole) > 50


def test_local_rounds_keep_boosts_delaunay_graph():
    pytest.importorskip("pyvoronoi")
    import scenes
    import sdg_peer
    from peers_boost import boost_delaunay_edges

    import curvedvoronoi as cv
    from curvedvoronoi.runtime.segments.construction import segment_voronoi

    segs = scenes.random_segments(2000, 1)
    d = segment_voronoi([cv.Segment(*s) for s in segs], certify=False)
    assert d.stats.get("local_rounds", 0) >= 1, d.stats
    assert [p for p in d.problems if "certify=False" not in p] == []

    def key(site):
        if isinstance(site, cv.Segment):
            return sdg_peer.segment_key(site.p, site.q)
        return sdg_peer.point_key(Fraction(str(site.x)), Fraction(str(site.y)))

    keys = [key(s) for s in d.sites]
    ours = {frozenset((keys[i], keys[j])) for i, j in d.delaunay_edges()}
    boost, _ = boost_delaunay_edges([], segs)
    assert ours == boost
