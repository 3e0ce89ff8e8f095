"""The verifier run chunk by chunk (runtime/voronoi/chunked_certificate.py) sets aside only the
closure lines that a sub-diagram fails by construction; a fault seen only by the accounting at
infinity of conic sites tied there must still refuse.

Four equal ellipses (axes 2, 1) centred at (6k, 0), k = 0..3: neighbours are mirror images in the
lines x = 3, 9, 15, so the diagram is those three lines, whole edges with no vertex, and in the
directions ±90° all four sites tie at infinity (equal support values).  Drop the line of sites
(1, 2): every remaining line is a proved whole edge, every site keeps an edge and there is no
vertex, so the closure of the whole diagram holds; only the accounting at infinity
(runtime/voronoi/verify/ties_at_infinity.py: the unbounded edges at a tie must join the
consecutive tied sites) sees that sites 1 and 2 have no unbounded edge between them.  Its line
ends in "... of the sites tied there", like the vertex lines ("... end here") that a chunk sets
aside, but it is not one of them.
"""
from __future__ import annotations

import numpy as np
import pytest

import curvedvoronoi as cv
from curvedvoronoi.runtime.voronoi.chunked_certificate import chunked_verify
from curvedvoronoi.runtime.voronoi.construction import voronoi
from curvedvoronoi.runtime.voronoi.structure import Diagram, DiagramEdge
from curvedvoronoi.runtime.voronoi.verify.certificate import verify


@pytest.fixture(scope="module")
def client():
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as c:
        yield c


def test_a_missing_mirror_line_of_a_row_of_tied_ellipses_is_refused_chunk_by_chunk(client):
    d = voronoi([cv.Conic.ellipse(centre=(6 * k, 0), axes=(2, 1)) for k in range(4)], progress=False)
    assert d.certified and not d.vertices
    lines = {}
    for e in d.edges:
        P = np.asarray(e.polyline, float)
        assert e.ends == (None, None) and np.allclose(P[:, 0], P[0, 0], atol=1e-9)
        lines[tuple(sorted(e.sites))] = float(P[0, 0])
    assert lines == pytest.approx({(0, 1): 3.0, (1, 2): 9.0, (2, 3): 15.0})
    keep = [e for e in d.edges if sorted(e.sites) != [1, 2]]
    bad = Diagram(list(d.sites), [], [DiagramEdge(k, tuple(e.sites), e.ends, e.closed, e.polyline, e.tolerance)
                                      for k, e in enumerate(keep)])
    whole = verify(bad)
    assert not whole.ok and all(whole.edges)
    cc = chunked_verify(bad, [[k] for k in range(len(keep))], client)
    assert all(cc.edges)
    assert not cc.ok
    assert any("tied there" in str(p) for p in cc.problems)
