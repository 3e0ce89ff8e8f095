"""The direct construction of the diagram left in a deleted circle's or point's region
(runtime.voronoi.hole_region) against the construction's local diagram, high-precision distances,
corrupted candidates and CGAL.

* Deletions of random circles and points inside the scene take the direct path ("local build":
  "hole region"), are certified, give the batch build's Delaunay graph of the remaining sites, and
  the independent verifier proves the result; the same deletions with the direct path switched off
  (the construction's local diagram) give the same vertices (same sites, positions within 1e-9).
* Every new vertex is equidistant from its three sites: distances recomputed with mpmath at 50
  digits from the exact sites agree to 1e-12 relative.
* Soundness does not rest on the candidate: a candidate with one vertex moved by 1e-2 or one new
  edge dropped is refused by the proofs or the closure check; the deletion then takes the
  construction's local diagram and is still certified and equal to the batch build.
* After deletions through the direct path the Delaunay graph equals CGAL's Apollonius graph after
  CGAL's own removals (tests/cgal/apollonius_dynamic.cpp).
"""
from __future__ import annotations

import random
import sys
from pathlib import Path

import mpmath
import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).with_name("cgal")))
import cgal_peer  # noqa: E402

import curvedvoronoi as cv  # noqa: E402
from curvedvoronoi.runtime.voronoi import insertion  # noqa: E402


def _scene(seed, n, points=False):
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < n:
        x, y = rng.uniform(0, 100, 2)
        r = 0.0 if points else float(np.exp(rng.uniform(np.log(0.05), np.log(10))))
        if all(np.hypot(x - a, y - b) > r + c + 1e-3 for a, b, c in out):
            out.append((float(x), float(y), r))
    return out


def _vertices(d):
    return sorted((v.sites, v.x, v.y, v.radius) for v in d.vertices)


def _inner(sc, rng, k):
    """k indices of sites away from the border of the square (deletions with bounded regions)."""
    inner = [t for t, (x, y, _) in enumerate(sc) if 20 < x < 80 and 20 < y < 80]
    return rng.sample(inner, k)


def _delete(d, sc, idx, mode):
    """Delete the sites of ``sc`` at the original indices ``idx`` one after the other; returns the
    diagram, the remaining sites in the diagram's order and the routes taken."""
    cur = list(range(len(sc)))
    hows = []
    for k, t in enumerate(idx):
        i = cur.index(t)
        d = d.delete_site(i, renumber=mode, inplace=k > 0)
        assert d.certified, d.problems[:3]
        hows.append(d.stats.get("local build"))
        if mode == "shift":
            cur.pop(i)
        else:
            cur[i] = cur[-1]
            cur.pop()
    return d, [sc[t] for t in cur], hows


@pytest.mark.parametrize("seed,points,mode", [(0, False, "shift"), (1, False, "last"), (2, True, "last"),
                                              (3, False, "shift")])
def test_direct_hole_equals_the_construction_path(monkeypatch, seed, points, mode):
    sc = _scene(seed, 80, points)
    idx = _inner(sc, random.Random(seed), 8)
    d, rest, hows = _delete(cv.voronoi(sc), sc, idx, mode)
    assert hows.count("hole region") >= 6, hows
    assert d.delaunay_edges() == cv.voronoi(rest, certify=False).delaunay_edges()
    assert cv.verify(d, d.sites).ok
    monkeypatch.setattr(insertion, "hole_region", lambda *a, **k: None)
    ref, _, hows_ref = _delete(cv.voronoi(sc), sc, idx, mode)
    assert "hole region" not in hows_ref
    A, B = _vertices(d), _vertices(ref)
    assert [a[0] for a in A] == [b[0] for b in B]
    for a, b in zip(A, B):
        assert np.allclose(a[1:], b[1:], rtol=1e-9, atol=1e-9 * 100)


@pytest.mark.mpmath_dps(50)
def test_new_vertices_are_equidistant_at_50_digits():
    sc = _scene(7, 40)
    d = cv.voronoi(sc)
    direct = 0
    for t in _inner(sc, random.Random(7), 5):
        before = {(v.sites, v.x, v.y) for v in d.vertices}
        i = next(k for k, s in enumerate(d.sites) if (float(s.cx), float(s.cy)) == sc[t][:2])
        d = d.delete_site(i, renumber="last", inplace=True)
        assert d.certified
        if d.stats.get("local build") != "hole region":
            continue
        direct += 1
        for v in d.vertices:
            if (v.sites, v.x, v.y) in before:
                continue
            p = (mpmath.mpf(v.x), mpmath.mpf(v.y))
            dist = [mpmath.sqrt((p[0] - mpmath.mpf(str(s.cx))) ** 2 + (p[1] - mpmath.mpf(str(s.cy))) ** 2)
                    - mpmath.sqrt(mpmath.mpf(str(s.r2))) for s in (d.sites[k] for k in v.sites)]
            spread = max(dist) - min(dist)
            assert spread <= 1e-12 * (1 + abs(v.x) + abs(v.y)), (v.sites, spread)
            assert abs(dist[0] - mpmath.mpf(v.radius)) <= 1e-11 * (1 + abs(v.x) + abs(v.y))
    assert direct >= 3


def _corrupt(kind):
    real = insertion.hole_region

    def bad(*a, **k):
        res = real(*a, **k)
        if res is None or not res["new_v"]:
            return None
        if kind == "move":
            res["new_v"][0][0].x += 1e-2
        else:
            res["new_e"].pop()
        return res
    return bad


@pytest.mark.parametrize("kind", ["move", "drop edge"])
def test_corrupted_candidates_are_refused(monkeypatch, kind):
    sc = _scene(11, 50)
    monkeypatch.setattr(insertion, "hole_region", _corrupt(kind))
    d, rest, hows = _delete(cv.voronoi(sc), sc, _inner(sc, random.Random(11), 5), "shift")
    assert "hole region" not in hows
    assert d.delaunay_edges() == cv.voronoi(rest, certify=False).delaunay_edges()
    assert cv.verify(d, d.sites).ok


def test_cgal_after_direct_deletions(cgal_peer_program):
    """The Delaunay graph after deletions through the direct path equals CGAL's Apollonius graph
    after CGAL's own removals of the same sites (tests/cgal/apollonius_dynamic.cpp)."""
    import cgal_dynamic

    sc = cgal_peer.random_disjoint_circles(300, 4)
    d = cv.voronoi(sc)
    rng = random.Random(4)
    ops, hows = [], []
    for k in range(20):
        i = rng.randrange(len(d.sites))
        d = d.delete_site(i, inplace=k > 0)
        assert d.certified, d.problems[:3]
        hows.append(d.stats.get("local build"))
        ops.append(("-", i))
    assert hows.count("hole region") >= 15, hows
    _, _, hidden, edges = cgal_dynamic.run(sc, ops)
    assert hidden == 0 and d.delaunay_edges() == edges
