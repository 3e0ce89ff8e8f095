"""The Delaunay graph of random disjoint circles against CGAL's Apollonius_graph_2 (an independent,
exact-predicate peer; Karavelas & Yvinec, ESA 2002), compiled from tests/cgal/apollonius_edges.cpp.

Needs g++ and the CGAL headers (Debian: libcgal-dev).  When they are missing the test is skipped
with a message naming the package, except in CI (env CI set), where it fails."""
from __future__ import annotations

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).with_name("cgal")))
import cgal_peer  # noqa: E402

from curvedvoronoi.runtime.voronoi.construction import voronoi  # noqa: E402


@pytest.fixture(scope="module")
def peer(cgal_peer_program):
    return cgal_peer_program


@pytest.mark.parametrize("n,seed", [(10, 0), (10, 1), (10, 2), (50, 3), (50, 4), (300, 5), (1000, 6)])
def test_delaunay_edges_equal_cgal(peer, n, seed):
    circles = cgal_peer.random_disjoint_circles(n, seed)
    expected, _, hidden = cgal_peer.delaunay_edges(circles)
    assert hidden == 0
    certify = n <= 50          # the verifier's time grows faster than the construction's
    d = voronoi(circles, certify=certify)
    assert [p for p in d.problems if "certify=False" not in p] == []
    assert d.certified is certify
    assert d.delaunay_edges() == expected
    assert all(v.certified for v in d.vertices)


def test_delaunay_edges_equal_cgal_mixed_radii(peer):
    """Radii spread over two orders of magnitude, and points (radius 0)."""
    circles = cgal_peer.random_disjoint_circles(60, 7, rmin=0.05, rmax=4.0)
    circles = [(x, y, 0.0 if m % 5 == 0 else r) for m, (x, y, r) in enumerate(circles)]
    expected, _, hidden = cgal_peer.delaunay_edges(circles)
    assert hidden == 0
    assert voronoi(circles, certify=False).delaunay_edges() == expected


def test_cgal_comparison_can_fail(peer):
    """The comparison is not vacuous: dropping one circle changes CGAL's graph."""
    circles = cgal_peer.random_disjoint_circles(30, 8)
    full, _, _ = cgal_peer.delaunay_edges(circles)
    fewer, _, _ = cgal_peer.delaunay_edges(circles[:-1])
    assert fewer != full
    assert voronoi(circles[:-1], certify=False).delaunay_edges() == fewer


def test_far_hull_vertex_found_through_the_verifier(peer, monkeypatch):
    """A small circle (site 2) 1e-3 inside the common tangent of sites 0 and 1: the unbounded edge
    (0, 1) starts at a vertex ~10⁵ away.  The coarse samples of sites 0 and 1 retreat from that
    tangent more than site 2 does, so the sampled hull passes through site 2; the construction's
    convex-hull check finds it, and without that check the verifier finds the missing edge, names
    the sites, and the rebuild with finer samples agrees with CGAL."""
    cs = [(0.0, 0.0, 1.0), (60.0, 80.0, 1.0), (30.3992, 39.7006, 0.5), (0.0, 80.0, 1.0), (30.0, 60.0, 1.0)]
    expected, _, hidden = cgal_peer.delaunay_edges(cs)
    assert hidden == 0 and (0, 1) in expected
    assert voronoi(cs, certify=False).delaunay_edges() == expected
    import curvedvoronoi.runtime.voronoi.construction as construction

    monkeypatch.setattr(construction, "hull_neighbours", lambda S, sites: set())
    d = voronoi(cs)
    assert d.certified, d.problems
    assert d.stats.get("verify_refinements", 0) >= 1
    assert d.delaunay_edges() == expected
