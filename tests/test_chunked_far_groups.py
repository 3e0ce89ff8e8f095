"""The bounded edges near the hull proved in groups by angle (runtime/voronoi/chunked_certificate.py,
``far_groups``): each group is a chunk that keeps every site and skips the accounting at infinity,
so that the workers of a cluster share the edges whose empty circles are nearly half-planes.

On 300 random disjoint circles (tests/cgal/cgal_peer.random_disjoint_circles) built whole, whose
edges near the hull have vertices with empty circles wider than a twentieth of the scene: split
into three groups (serially, and on a LocalCluster of two worker threads, whose default is one
group per worker) the certificate proves every vertex and edge, as with the edges in the chunk of
the unbounded edges; the groups partition those edges; and a far edge whose polyline is moved off
its bisector is refused in its group.
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from curvedvoronoi.runtime.voronoi import chunked_certificate as cc
from curvedvoronoi.runtime.voronoi.construction import voronoi
from curvedvoronoi.runtime.voronoi.structure import Diagram, DiagramEdge

sys.path.insert(0, str(Path(__file__).parent / "cgal"))
import cgal_peer  # noqa: E402


@pytest.fixture(scope="module")
def diagram():
    d = voronoi(cgal_peer.random_disjoint_circles(300, 3), progress=False)
    assert d.certified
    return d


def _chunks(d, n=4):
    """Bounded edges in n strips by x of their first node (the unbounded and far ones go where
    chunked_verify puts them)."""
    x = np.array([e.polyline[0][0] for e in d.edges])
    cuts = np.quantile(x, np.linspace(0, 1, n + 1)[1:-1])
    lab = np.searchsorted(cuts, x)
    return [np.nonzero(lab == k)[0].tolist() for k in range(n)]


def test_far_edges_exist_and_their_groups_partition_them(diagram):
    reach = cc._Reach(diagram)
    far = reach.far_edges(diagram)
    assert len(far) >= 6
    groups = cc._far_groups(diagram, far, reach, 3)
    assert len(groups) == 3 and sorted(sum(groups, [])) == sorted(far)
    assert min(map(len, groups)) >= len(far) // 3


@pytest.mark.parametrize("far_groups", [1, 3])
def test_the_certificate_in_far_groups_proves_every_part(diagram, far_groups):
    out = cc.chunked_verify(diagram, _chunks(diagram), far_groups=far_groups)
    assert out.ok and all(out.vertices) and all(out.edges), out.problems


def test_far_groups_on_two_workers(diagram):
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        seen = []
        orig = cc._chunk_results

        def spy(D, parts, client_, reach=None):
            seen.extend(parts)
            return orig(D, parts, client_, reach)
        cc._chunk_results = spy
        try:
            out = cc.chunked_verify(diagram, _chunks(diagram), client)
        finally:
            cc._chunk_results = orig
    assert out.ok and all(out.edges)
    far = set(cc._Reach(diagram).far_edges(diagram))
    groups = [set(ids) for ids, hull, every in seen if every and not hull]
    assert len(groups) == 2 and set().union(*groups) == far


def test_a_far_edge_off_its_bisector_is_refused_in_its_group(diagram):
    far = cc._Reach(diagram).far_edges(diagram)
    t = far[len(far) // 2]
    e = diagram.edges[t]
    P = [list(p) for p in e.polyline]
    k = len(P) // 2
    ax, ay = P[k - 1] if k else P[0]
    bx, by = P[k + 1] if k + 1 < len(P) else P[-1]
    # a node pushed sideways by a hundred tolerances plus a thousandth of the edge's span
    L = float(np.hypot(bx - ax, by - ay)) or 1.0
    off = 100 * e.tolerance + 1e-3 * L
    P[k] = [P[k][0] - (by - ay) / L * off, P[k][1] + (bx - ax) / L * off]
    edges = list(diagram.edges)
    edges[t] = DiagramEdge(e.id, tuple(e.sites), tuple(e.ends), e.closed, P, e.tolerance)
    bad = Diagram(list(diagram.sites), list(diagram.vertices), edges)
    out = cc.chunked_verify(bad, _chunks(bad), far_groups=3)
    assert not out.ok and not out.edges[t]
    assert sum(not f for f in out.edges) == 1
