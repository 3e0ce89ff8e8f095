"""The segment Voronoi diagram against two independent peers: CGAL's Segment_Delaunay_graph_2
(exact predicates and constructions; ``--degenerate`` drops its zero-length diagonals) and
Boost.Polygon's Voronoi diagram through pyvoronoi.  The Delaunay graph over elementary sites
(endpoints and open interiors, exact keys) must be identical.

Scenes with two collinear segments continuing each other at a point of degree 2 are left out:
this library merges them into one elementary segment (runtime/segments/elementary.py), while
both peers keep the joint as a point site whose region is a line."""
from __future__ import annotations

import sys
from fractions import Fraction
from pathlib import Path

import pytest

import curvedvoronoi as cv
from curvedvoronoi.runtime.segments.construction import segment_voronoi

sys.path.insert(0, str(Path(__file__).parent))
sys.path.insert(0, str(Path(__file__).with_name("cgal")))
import scenes  # noqa: E402
import sdg_peer  # noqa: E402
from test_segment_peers import peers  # noqa: E402,F401  (fixture: builds the peers or skips)

from peers_boost import boost_delaunay_edges  # noqa: E402


def _key(site):
    if isinstance(site, cv.Segment):
        return sdg_peer.segment_key(site.p, site.q)
    return sdg_peer.point_key(Fraction(str(site.x)), Fraction(str(site.y)))


def our_edges(points, segments):
    d = segment_voronoi([cv.Segment(*s) for s in segments] + list(points), certify=False)
    assert not [p for p in d.problems if "not verified" not in p], d.problems[:3]
    keys = [_key(s) for s in d.sites]
    return {frozenset((keys[i], keys[j])) for i, j in d.delaunay_edges()}, d


def _straight_joint(segments) -> bool:
    ends: dict = {}
    for a, b in segments:
        ends.setdefault(a, []).append(b)
        ends.setdefault(b, []).append(a)
    for p, others in ends.items():
        for i, u in enumerate(others):
            for v in others[i + 1:]:
                if scenes.orient(u, p, v) == 0 and (u[0] - p[0]) * (v[0] - p[0]) + (u[1] - p[1]) * (v[1] - p[1]) < 0:
                    return True
    return False


def compare(points, segments):
    ours, d = our_edges(points, segments)
    cgal, _ = sdg_peer.segment_delaunay_edges(points, segments, degenerate=True)
    assert ours == cgal, (sorted(map(sorted, ours - cgal))[:4], sorted(map(sorted, cgal - ours))[:4])
    if all(abs(c) < 2 ** 30 for s in segments for p in s for c in p):
        boost, _ = boost_delaunay_edges(points, segments)
        assert ours == boost
    return d


@pytest.mark.parametrize("n,seed", [(10, 0), (30, 1), (100, 2), (300, 3)])
def test_random_segments_equal_cgal_and_boost(peers, n, seed):
    compare([], scenes.random_segments(n, seed))


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_polylines_and_polygons_with_shared_endpoints(peers, seed):
    segs = scenes.random_segments(120, seed, shared=True)
    if _straight_joint(segs):
        pytest.skip("a straight joint (merged here, a point site for the peers)")
    compare([], segs)


def test_segments_with_isolated_points(peers):
    segs = scenes.random_segments(60, 7)
    compare(scenes.random_points_off(segs, 25, 8), segs)


def test_rectangle_square_and_star(peers):
    rect = [((0, 0), (4, 0)), ((4, 0), (4, 2)), ((4, 2), (0, 2)), ((0, 2), (0, 0))]
    square = [((0, 0), (2, 0)), ((2, 0), (2, 2)), ((2, 2), (0, 2)), ((0, 2), (0, 0))]
    star = [((0, 0), (3, 1)), ((0, 0), (-1, 3)), ((0, 0), (-2, -2)), ((0, 0), (2, -3))]
    for segs in (rect, square, star):
        compare([], segs)


@pytest.mark.slow
def test_thousand_segments_equal_cgal_and_boost(peers):
    compare([], scenes.random_segments(1000, 11))
