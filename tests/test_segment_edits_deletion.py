"""Local deletion of input pieces from diagrams of points and segments
(runtime/segments/local_deletion.py through Diagram.delete_site): after every deletion the diagram
must be the Voronoi diagram of the remaining pieces — its Delaunay graph over exact site keys equal
to a batch build's and to CGAL's Segment_Delaunay_graph_2 (tests/cgal/sdg_peer.py, an independent
exact implementation), certified, and accepted by the independent verifier cv.verify."""
from __future__ import annotations

import random
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import curvedvoronoi as cv

sys.path.insert(0, str(Path(__file__).parent))
from scenes import random_segments  # noqa: E402
from test_segment_edits import as_piece, cgal_graph, cgal_ready, check, graph, index_is_fresh, key, sdg_peer, without_straight_joints  # noqa: E402

from curvedvoronoi.runtime.segments.construction import segment_voronoi  # noqa: E402
from curvedvoronoi.runtime.segments.local_deletion import delete_locally  # noqa: E402


def inner_pieces(pieces, count, rng):
    """Indices of pieces well inside the scene (their regions are bounded: the local route)."""
    xs = [c for p in pieces for q in ((p,) if not isinstance(p[0], tuple) else p) for c in (q[0],)]
    ys = [c for p in pieces for q in ((p,) if not isinstance(p[0], tuple) else p) for c in (q[1],)]
    x0, x1, y0, y1 = min(xs), max(xs), min(ys), max(ys)
    w, h = x1 - x0, y1 - y0

    def inside(p):
        ends = (p,) if not isinstance(p[0], tuple) else p
        return all(x0 + w / 4 < x < x1 - w / 4 and y0 + h / 4 < y < y1 - h / 4 for x, y in ends)
    idx = [i for i, p in enumerate(pieces) if inside(p)]
    rng.shuffle(idx)
    return idx[:count]


def test_inner_deletions_are_local_and_equal_batch_and_cgal():
    cgal_ready()
    rng = random.Random(5)
    pieces = random_segments(150, 4)
    d = cv.voronoi([cv.Segment(*p) for p in pieces])
    routes = []
    for step in range(4):
        i = inner_pieces(pieces, 1, rng)[0]
        last = step % 2 == 1
        d = d.delete_site(i, renumber="last" if last else "shift", inplace=step == 2)
        if last and i < len(pieces) - 1:
            pieces[i] = pieces.pop()
        else:
            del pieces[i]
        routes.append(d.stats["update"])
        check(d, pieces)
        assert d.stats["update_input"] == i
        if routes[-1] == "local":
            index_is_fresh(d)
    assert routes.count("local") >= 3, routes
    d = d.insert((333.5, 333.5))
    if d.stats["update"] == "local":
        index_is_fresh(d)


def test_a_piece_sharing_its_endpoints_is_deleted_locally():
    # a closed square in the middle of a scene: deleting one side removes its interior only, the
    # corners stay (the neighbouring sides keep them), and a kept corner's source moves on to a
    # remaining piece; then a side of the open chain left, and its free corner goes
    cgal_ready()
    square = [((330, 330), (350, 330)), ((350, 330), (350, 350)), ((350, 350), (330, 350)), ((330, 350), (330, 330))]
    scene = [p for p in random_segments(120, 11) if not any(320 <= x <= 360 and 320 <= y <= 360 for x, y in p)]
    pieces = scene[:40] + square + scene[40:]
    d = cv.voronoi([as_piece(p) for p in pieces])
    n0 = len(d.sites)
    d = d.delete_site(40)                               # the side (330, 330)-(350, 330), source of both corners
    del pieces[40]
    assert d.stats["update"] == "local", d.stats["update"]
    assert len(d.sites) == n0 - 1                       # only the interior went
    check(d, pieces)
    d = d.delete_site(40)                               # (350, 330)-(350, 350): the corner (350, 330) is free now
    del pieces[40]
    assert d.stats["update"] == "local", d.stats["update"]
    assert sdg_peer.point_key(350, 330) not in {key(s) for s in d.sites}
    assert sdg_peer.point_key(350, 350) in {key(s) for s in d.sites}
    check(d, pieces)


def test_a_point_that_is_also_an_endpoint():
    # the point (6, 4) is an input piece and an end of a segment: deleting either keeps the site
    cgal_ready()
    scene = [p for p in random_segments(80, 2) if all(not (0 <= x <= 12 and 0 <= y <= 12) for x, y in p)]
    pieces = [((6, 4), (9, 9)), (6, 4), (40, 40)] + scene
    d = cv.voronoi([as_piece(p) for p in pieces])
    one = d.delete_site(1)                              # the point piece: the sites stay
    assert [key(s) for s in one.sites] == [key(s) for s in d.sites]
    assert one.delaunay_edges() == d.delaunay_edges()
    check(one, pieces[:1] + pieces[2:])
    two = d.delete_site(0)                              # the segment: (6, 4) stays, (9, 9) goes
    rest = pieces[1:]
    keys = {key(s) for s in two.sites}
    assert sdg_peer.point_key(6, 4) in keys and sdg_peer.point_key(9, 9) not in keys
    check(two, rest)


def test_deleting_a_joint_of_two_straight_segments_is_rebuilt_right():
    # (0, 0)-(5, 0) and (5, 0)-(9, 0) with the point (5, 0) as a third piece: (5, 0) is a site;
    # without the point the two segments are one elementary segment (a batch build merges them)
    pieces = [((0, 0), (5, 0)), ((5, 0), (9, 0)), (5, 0), ((2, 6), (7, 8)), ((1, -7), (8, -5))]
    d = cv.voronoi([as_piece(p) for p in pieces])
    e = d.delete_site(2)
    assert e.stats["update"].startswith("rebuild (the deletion joins two segments straight")
    b = cv.voronoi([as_piece(p) for p in pieces[:2] + pieces[3:]])
    assert [key(s) for s in e.sites] == [key(s) for s in b.sites] and e.certified
    assert graph(e) == graph(b)


def test_deleting_the_last_piece_is_a_clear_error():
    d = cv.voronoi([cv.Segment((0, 0), (3, 1)), cv.Segment((5, 5), (6, 9))])
    one = d.delete_site(0)
    assert len(one.sites) == 3 and one.certified
    with pytest.raises(ValueError, match="at least 2 sites: deleting the last input piece"):
        one.delete_site(0)


def test_a_wrong_local_diagram_is_never_spliced():
    # the splice trusts nothing of the local diagram: one missing edge fails the closure, one
    # vertex moved by 10^-3 fails its proof; either way the deletion is refused (a reason string)
    pieces = random_segments(150, 4)
    d = cv.voronoi([cv.Segment(*p) for p in pieces])
    keys = {key(s): k for k, s in enumerate(d.sites)}
    i = inner_pieces(pieces, 1, random.Random(1))[0]
    a, b = pieces[i]
    gone = [keys[sdg_peer.segment_key(a, b)], keys[sdg_peer.point_key(*a)], keys[sdg_peer.point_key(*b)]]
    assert not isinstance(delete_locally(d, gone, segment_voronoi), str)

    def missing_edge(sites, certify):
        L = segment_voronoi(sites, certify=certify)
        x, y = (a[0] + b[0]) / 2, (a[1] + b[1]) / 2
        k = min((t for t, e in enumerate(L.edges) if None not in e.ends),
                key=lambda t: min(abs(px - x) + abs(py - y) for px, py in L.edges[t].polyline))
        del L.edges[k]
        return L

    def moved_vertex(sites, certify):
        L = segment_voronoi(sites, certify=certify)
        x, y = (a[0] + b[0]) / 2, (a[1] + b[1]) / 2
        v = min(L.vertices, key=lambda v: abs(v.x - x) + abs(v.y - y))
        v.x += 1e-3
        return L

    assert "closure" in delete_locally(d, gone, missing_edge)
    assert "not proved" in delete_locally(d, gone, moved_vertex)


SCENE = without_straight_joints(random_segments(40, 9, box=160, shared=True))


@settings(max_examples=6, deadline=None)
@given(st.lists(st.integers(0, 10 ** 6), min_size=2, max_size=3), st.booleans())
def test_random_deletion_sequences_equal_batch(draws, last):
    cgal_ready()
    pieces = list(SCENE)
    d = cv.voronoi([cv.Segment(*p) for p in pieces])
    for r in draws:
        i = r % len(pieces)
        d = d.delete_site(i, renumber="last" if last else "shift")
        if last and i < len(pieces) - 1:
            pieces[i] = pieces.pop()
        else:
            del pieces[i]
        assert d.certified, d.problems[:3]
        batch = cv.voronoi([cv.Segment(*p) for p in pieces])
        assert graph(d) == graph(batch)
        assert sorted(key(s) for s in d.sites) == sorted(key(s) for s in batch.sites)
    assert graph(d) == cgal_graph(pieces)


def test_the_part_proof_sees_a_site_it_does_not_list():
    # prove_part proves against the sites that can reach the part, not only the part's own sites:
    # a point put inside a vertex's empty circle, or next to an edge's middle (closer than the
    # edge's sites), makes the proof fail; without it the same part is proved
    from curvedvoronoi.runtime.segments.local_update import EditIndex, piece_distance, piece_ends, prove_part
    from curvedvoronoi.runtime.voronoi.structure import Diagram

    d = cv.voronoi([cv.Segment(*p) for p in random_segments(60, 3)])
    index = EditIndex.build(d)
    vid = {v.id: v for v in d.vertices}
    v = max(d.vertices, key=lambda v: v.radius)
    assert prove_part(list(d.sites), index, [v], [], [])

    def off_the_ends(e):
        """A point closer to a polyline point of e than e's sites, outside both end vertices' circles
        (only the edge's own reach sees it), or None."""
        ends = [vid[u] for u in e.ends]
        a, b = piece_ends(d.sites[e.sites[0]])
        for m in np.asarray(e.polyline, float):
            di = float(piece_distance(a, b, m[None, :])[0])
            for t in np.linspace(0, 2 * np.pi, 16, endpoint=False):
                q = m + 0.9 * di * np.array([np.cos(t), np.sin(t)])
                if all(np.hypot(q[0] - w.x, q[1] - w.y) > 1.05 * w.radius for w in ends):
                    return ends, q
        return None
    e, (ends, q) = next((e, f) for e in d.edges if None not in e.ends for f in [off_the_ends(e)] if f)
    assert prove_part(list(d.sites), index, ends, [e], [])
    for part_v, part_e, x, y in (([v], [], v.x + v.radius / 2, v.y), (ends, [e], q[0], q[1])):
        sites = list(d.sites) + [cv.Point(round(x, 3), round(y, 3))]
        other = EditIndex.build(Diagram(sites, d.vertices, d.edges))
        assert not prove_part(sites, other, part_v, part_e, [])
