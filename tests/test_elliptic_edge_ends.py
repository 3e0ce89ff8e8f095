"""The end vertices of an edge next to an elliptic piece (runtime/segments/certificate_ellipse_edges.py):
a point where an edge (i, k) ends is equidistant from i and k and nearer to no other site, so a
vertex proved to lie on the diagram with its own listed sites must list both i and k to end it.
An edge given an end vertex that lists i but not k is refused as a fault, by name, before any
curve is drawn; the same edge with its true pair is not refused for its ends."""
from __future__ import annotations

import pytest

import curvedvoronoi as cv
from curvedvoronoi.runtime.segments.certificate_ellipse_edges import prove_piece_edge
from curvedvoronoi.runtime.segments.certificate_sites import SiteTable
from curvedvoronoi.runtime.segments.certificate_vertices import prove_vertices
from curvedvoronoi.runtime.sites.elliptic_arc import EllipticArc
from curvedvoronoi.runtime.voronoi.structure import DiagramEdge

SCENE = [cv.Arc.elliptic((0, 0), (4, 0), "1/2", 0.3, 2.5), (0, 5), (3, -2), (-4, 3)]


@pytest.fixture(scope="module")
def proved():
    D = cv.voronoi(SCENE, certify=False)
    T = SiteTable(D.sites)
    vproofs = prove_vertices(D, T, [])
    vindex = {v.id: n for n, v in enumerate(D.vertices)}
    pieces = {k for k, s in enumerate(D.sites) if isinstance(s, EllipticArc)}
    edges = [e for e in D.edges if pieces & set(e.sites) and None not in e.ends
             and all(vproofs[vindex[u]].ok for u in e.ends)]
    assert edges, "the scene has an edge of a piece between two proved vertices"
    return D, T, vproofs, vindex, edges


def test_an_end_vertex_not_listing_the_edge_s_site_is_a_fault(proved):
    D, T, vproofs, vindex, edges = proved
    for e in edges:
        i = e.sites[0]
        v0 = D.vertices[vindex[e.ends[0]]]
        for k in sorted(set(range(len(D.sites))) - set(v0.sites)):
            wrong = DiagramEdge(e.id, (i, k), e.ends, False, e.polyline, e.tolerance, False)
            problems: list = []
            assert not prove_piece_edge(T, D, wrong, vindex, vproofs, problems).ok
            assert problems and problems[0].fault, [str(p) for p in problems]
            assert f"its end vertex {e.ends[0]} does not list both its sites" in str(problems[0])


def test_the_true_pair_passes_the_end_checks(proved):
    D, T, vproofs, vindex, edges = proved
    for e in edges:
        problems: list = []
        prove_piece_edge(T, D, e, vindex, vproofs, problems)
        assert not any("does not list both its sites" in str(p) or "is not a vertex" in str(p) for p in problems)
