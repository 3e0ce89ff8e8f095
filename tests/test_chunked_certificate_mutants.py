"""The verifier run chunk by chunk (runtime/voronoi/chunked_certificate.py) refuses what the
whole verifier refuses, on small diagrams whose faults are built by hand.

The chunked certificate proves vertices and edges in chunks, sets aside only the closure lines that
a sub-diagram fails by construction (a vertex's missing edge of a pair, a site without an edge),
runs the closure once on the whole diagram, and reads the accounting at infinity from the chunk of
the unbounded edges (or from the first chunk when no edge is unbounded).  Each test below plants one fault that exactly one of
those parts sees:

* a bounded edge dropped: every chunk sets its vertex lines aside, only the closure of the whole
  diagram names the vertices left without an edge of that pair;
* a bisector line of collinear points dropped (points (0,0), (1,0), (2,0), (3,0): the diagram is
  the three lines x = 1/2, 3/2, 5/2, with no vertex): every other line is a proved whole edge,
  every site keeps an edge and there is no vertex, so the closure holds; only the accounting at
  infinity sees that sites 1 and 2, consecutive on the hull, have no unbounded edge between them;
* the bisector of two points reported twice: no vertex, both sites have an edge; the overlap of the
  two copies (and the accounting, which counts the ends at infinity) refuses it;
* a vertex moved off the Voronoi vertex: not proved in its chunk.

The workers are a LocalCluster of threads (processes=False), as in tests/test_tiled_diagram.py; each
test runs again with no client (the chunks proved here, one after the other).
"""
from __future__ import annotations

import pytest

from curvedvoronoi.runtime.voronoi.chunked_certificate import chunked_verify
from curvedvoronoi.runtime.voronoi.construction import voronoi
from curvedvoronoi.runtime.voronoi.structure import Diagram, DiagramEdge, DiagramVertex

#: four points in general position: vertices (0, 1, 2) and (1, 3, 2), one bounded edge (1, 2)
FOUR = [(0, 0, 0), (4, 1, 0), (1, 5, 0), (5, 6, 0)]


@pytest.fixture(scope="module", params=["workers", "here"])
def client(request):
    """A client of one worker thread, or None: the chunks run here one after the other."""
    if request.param == "here":
        yield None
        return
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as c:
        yield c


def _rebuild(d, vertices, edges) -> Diagram:
    """A diagram of d's sites with the given vertices and edges, renumbered in order."""
    vmap = {v.id: k for k, v in enumerate(vertices)}
    verts = [DiagramVertex(vmap[v.id], tuple(v.sites), v.x, v.y, v.radius) for v in vertices]
    es = [DiagramEdge(k, tuple(e.sites), tuple(None if u is None else vmap[u] for u in e.ends), e.closed,
                      e.polyline, e.tolerance) for k, e in enumerate(edges)]
    return Diagram(list(d.sites), verts, es)


def _one_edge_per_chunk(d):
    return [[k] for k in range(len(d.edges))]


@pytest.fixture(scope="module")
def four():
    d = voronoi(FOUR, progress=False)
    assert d.certified and len(d.vertices) == 2 and len(d.edges) == 5
    return d


def test_a_true_diagram_is_proved_chunk_by_chunk(four, client):
    cc = chunked_verify(four, _one_edge_per_chunk(four), client)
    assert cc.ok and cc.problems == [] and all(cc.vertices) and all(cc.edges)


def test_a_dropped_bounded_edge_is_seen_by_the_closure_of_the_whole(four, client):
    """Without the edge (1, 2) between the two vertices each vertex has no edge of the pair
    (1, 2): the chunks set those lines aside (a chunk lacks other chunks' edges by construction),
    the closure of the whole diagram must refuse."""
    keep = [e for e in four.edges if sorted(e.sites) != [1, 2]]
    bad = _rebuild(four, list(four.vertices), keep)
    cc = chunked_verify(bad, _one_edge_per_chunk(bad), client)
    assert all(cc.vertices) and all(cc.edges)          # what is left is true
    assert not cc.ok
    assert any("(1, 2) ends here" in str(p) for p in cc.problems)


def test_a_missing_line_of_collinear_points_is_seen_at_infinity(client):
    """Points 0..3 on the x-axis: the true diagram is the lines x = 1/2, 3/2, 5/2.  Without the
    line of (1, 2) each remaining line is a whole true edge, every site keeps an edge and there
    is no vertex (the closure holds); sites 1 and 2 are consecutive on the hull (a segment) with
    no unbounded edge between them, which only the accounting at infinity, read from the
    chunks, sees."""
    d = voronoi([(0, 0, 0), (1, 0, 0), (2, 0, 0), (3, 0, 0)], progress=False)
    assert d.certified and len(d.edges) == 3 and not d.vertices
    keep = [e for e in d.edges if sorted(e.sites) != [1, 2]]
    bad = _rebuild(d, [], keep)
    cc = chunked_verify(bad, _one_edge_per_chunk(bad), client)
    assert all(cc.edges)
    assert not cc.ok
    assert any("sites 1, 2" in str(p) for p in cc.problems)


def test_a_diagram_without_unbounded_edges_still_runs_the_accounting_at_infinity(client):
    """Two circles, each around three points: the true diagram is, inside each circle, the
    diagram of its three points and the circle (bounded edges and vertices), and outside, the
    line between the circles.  Without the line every vertex keeps its edges and every site an
    edge (the closure holds), and no edge is left without an end; one chunk must still run
    the accounting at infinity, which sees the circles consecutive on the hull with no unbounded
    edge between them."""
    inner = [(0, 1, 0), (1, -0.5, 0), (-1, -0.5, 0)]
    sites = [(0, 0, 3), *inner, (20, 0, 3), *[(x + 20, y, r) for x, y, r in inner]]
    d = voronoi(sites, progress=False)
    assert d.certified and d.vertices
    keep = [e for e in d.edges if None not in e.ends]
    assert len(keep) == len(d.edges) - 1
    bad = _rebuild(d, list(d.vertices), keep)
    cc = chunked_verify(bad, _one_edge_per_chunk(bad), client)
    assert all(cc.vertices) and all(cc.edges)
    assert not cc.ok


def test_a_bisector_reported_twice_is_refused(client):
    d = voronoi([(0, 0, 0), (4, 1, 0)], progress=False)
    assert d.certified and len(d.edges) == 1
    e = d.edges[0]
    bad = _rebuild(d, [], [e, DiagramEdge(1, e.sites, e.ends, e.closed, e.polyline, e.tolerance)])
    cc = chunked_verify(bad, [[0], [1]], client)
    assert not cc.ok


def test_a_whole_diagram_reported_twice_is_refused(client):
    """Three points: one vertex and three rays, reported twice (same sites, same coordinates):
    each copy alone is a true diagram and the closure of each vertex holds."""
    d = voronoi([(0, 0, 0), (4, 1, 0), (1, 5, 0)], progress=False)
    assert d.certified and len(d.vertices) == 1 and len(d.edges) == 3
    v = d.vertices[0]
    v2 = DiagramVertex(1, tuple(v.sites), v.x, v.y, v.radius)
    edges = list(d.edges) + [DiagramEdge(3 + k, e.sites, tuple(None if u is None else 1 for u in e.ends),
                                         e.closed, e.polyline, e.tolerance) for k, e in enumerate(d.edges)]
    bad = Diagram(list(d.sites), [v, v2], edges)
    cc = chunked_verify(bad, [[0, 1, 2], [3, 4, 5]], client)
    assert not cc.ok


def test_a_vertex_moved_off_its_place_is_not_proved(four, client):
    """Vertex 0 moved by 10⁻³ (its true position is the circumcentre (59/38, 87/38) of points
    0, 1, 2, far above the vertex tolerance): its chunk cannot prove it, and the edges that end
    there no longer end on it."""
    verts = list(four.vertices)
    v = verts[0]
    verts[0] = DiagramVertex(v.id, tuple(v.sites), v.x + 1e-3, v.y, v.radius)
    bad = _rebuild(four, verts, list(four.edges))
    cc = chunked_verify(bad, _one_edge_per_chunk(bad), client)
    assert not cc.vertices[0] and cc.vertices[1]
    assert not cc.ok


#: a circle of radius 20 around three unit circles: every edge is bounded (the outer circle owns
#: all of the plane outside it), so the diagram has no end at infinity
NESTED = [(0, 0, 20), (-5, -3, 1), (5, -3, 1), (0, 6, 1)]


@pytest.mark.parametrize("shift", [0.0, 1e-10])
def test_a_bounded_diagram_reported_twice_is_refused(client, shift):
    """NESTED has no unbounded edge, so a second copy of the whole diagram (its vertices moved by
    ``shift``, far below their proved tolerance) in a chunk of its own is proved in that chunk,
    every vertex of either copy has its edges (closure), and the accounting at infinity has no
    end to count: only the check for a vertex reported twice sees it."""
    d = voronoi(NESTED, progress=False)
    assert d.certified and d.edges and all(None not in e.ends for e in d.edges)
    nv, ne = len(d.vertices), len(d.edges)
    verts = list(d.vertices) + [DiagramVertex(nv + v.id, tuple(v.sites), v.x + shift, v.y, v.radius)
                                for v in d.vertices]
    edges = list(d.edges) + [DiagramEdge(ne + e.id, tuple(e.sites), tuple(nv + u for u in e.ends), e.closed,
                                         e.polyline, e.tolerance) for e in d.edges]
    bad = Diagram(list(d.sites), verts, edges)
    cc = chunked_verify(bad, [list(range(ne)), list(range(ne, 2 * ne))], client)
    assert all(cc.vertices) and all(cc.edges)          # each copy alone is the true diagram
    assert not cc.ok
    assert any("reported twice" in str(p) for p in cc.problems)


def test_two_vertices_of_one_triple_are_not_a_duplicate(client):
    """Circles of radius 5 at (∓6, 0) and one of radius 1/2 at the origin between them: the small
    circle's region is bounded by its bisectors with the two large ones, which meet at two
    vertices (0, ±7/4) of the same three sites (|v − c| − r equal: √(36 + 49/16) − 5 = 25/4 − 5 =
    5/4 = 7/4 − 1/2).  Two vertices of one triple far apart are not one vertex reported twice."""
    d = voronoi([(-6, 0, 5), (6, 0, 5), (0, 0, 0.5)], progress=False)
    assert d.certified and len(d.vertices) == 2
    assert {frozenset(v.sites) for v in d.vertices} == {frozenset((0, 1, 2))}
    assert sorted(round(v.y, 12) for v in d.vertices) == [-1.75, 1.75]
    cc = chunked_verify(d, _one_edge_per_chunk(d), client)
    assert cc.ok and cc.problems == []


def test_two_vertices_of_one_triple_in_a_wide_scene_are_not_a_duplicate(client):
    """The triple above with three far points added: the circle through (∓8·10⁵, 8·10⁵) and
    (0, 7.2·10⁵) has its centre at (0, 4.76·10⁶) (8·10¹¹ + (4.76·10⁶ − 8·10⁵)² = (4.76·10⁶ −
    7.2·10⁵)²), a vertex that makes the scene 4.76·10⁶ wide, so a duplicate test at a fixed
    fraction of the scene (10⁻⁶ of it: 4.8 here) took the two vertices 3.5 apart for one.  Two
    reports of one vertex lie within the sum of their proof radii (a few 10⁻¹⁰ of their own
    coordinates), and these two do not."""
    far = [(-8e5, 8e5, 0), (8e5, 8e5, 0), (0, 7.2e5, 0)]
    d = voronoi([(-6, 0, 5), (6, 0, 5), (0, 0, 0.5)] + far, progress=False)
    assert d.certified
    pair = [v for v in d.vertices if set(v.sites) == {0, 1, 2}]
    assert sorted(round(v.y, 9) for v in pair) == [-1.75, 1.75] and all(abs(v.x) < 1e-9 for v in pair)
    top = [v for v in d.vertices if set(v.sites) == {3, 4, 5}]
    assert len(top) == 1 and abs(top[0].y - 4.76e6) < 1e-3 and abs(top[0].x) < 1e-3
    cc = chunked_verify(d, _one_edge_per_chunk(d), client)
    assert cc.ok and cc.problems == []


def test_a_copy_within_the_coarse_proof_radius_is_refused(client, monkeypatch):
    """NESTED reported twice again, now with every proof box widened to h = 10·tol and the copy
    moved by 15·tol: each copy is still accepted (15·tol ≤ tol + 2h), so both may be one vertex,
    and the duplicate test must use the coarse radii the chunks list (r + 2·tol + 7h: 72·tol
    each), not the first-list radius (5·tol each, 10·tol for the pair, below the 15·tol apart)."""
    from curvedvoronoi.runtime.voronoi.verify import vertices

    real = vertices._vertex_info

    def coarse(*a, **k):
        info = real(*a, **k)
        if info is not None:
            info.h = max(info.h, 10 * info.tol)
        return info

    monkeypatch.setattr(vertices, "_vertex_info", coarse)
    d = voronoi(NESTED, progress=False)
    nv, ne = len(d.vertices), len(d.edges)

    def tol(v):
        return 1e-10 * (1 + abs(v.x) + abs(v.y) + abs(v.radius))

    verts = list(d.vertices) + [DiagramVertex(nv + v.id, tuple(v.sites), v.x + 15 * tol(v), v.y, v.radius)
                                for v in d.vertices]
    edges = list(d.edges) + [DiagramEdge(ne + e.id, tuple(e.sites), tuple(nv + u for u in e.ends), e.closed,
                                         e.polyline, e.tolerance) for e in d.edges]
    bad = Diagram(list(d.sites), verts, edges)
    cc = chunked_verify(bad, [list(range(ne)), list(range(ne, 2 * ne))], client)
    assert all(cc.vertices) and all(cc.edges)
    assert not cc.ok
    assert any("reported twice" in str(p) for p in cc.problems)
