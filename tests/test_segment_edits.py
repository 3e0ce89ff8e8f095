"""Insertion and deletion of input pieces in diagrams of segments and points
(runtime/segments/edits.py): after every edit the diagram must be the Voronoi diagram of the new
list of pieces, checked against a batch build of that list and against CGAL's
Segment_Delaunay_graph_2 (tests/cgal/sdg_peer.py, an independent exact implementation), with
sites compared by exact keys (elementary-site numbers change with the list)."""
from __future__ import annotations

import random
import sys
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest

import curvedvoronoi as cv

sys.path.insert(0, str(Path(__file__).with_name("cgal")))
sys.path.insert(0, str(Path(__file__).parent))
import sdg_peer  # noqa: E402
from scenes import orient, random_points_off, random_segments  # noqa: E402


def cgal_ready():
    sdg_peer.build_or_skip()


def without_straight_joints(segs):
    """The segments of ``segs`` kept greedily so that no two continue each other straight through a
    common end: such a pair is one elementary segment here and a joint point site for CGAL."""
    out: list = []
    for a, b in segs:
        straight = False
        for c, e in out:
            for p, u in ((c, e), (e, c)):
                for q, v in ((a, b), (b, a)):
                    if p == q and orient(u, p, v) == 0 and (u[0] - p[0]) * (v[0] - p[0]) + (u[1] - p[1]) * (v[1] - p[1]) < 0:
                        straight = True
        if not straight:
            out.append((a, b))
    return out


def key(site):
    if isinstance(site, cv.Segment):
        return sdg_peer.segment_key(site.p, site.q)
    return sdg_peer.point_key(Fraction(str(site.cx)), Fraction(str(site.cy)))


def graph(d):
    """The Delaunay graph over exact site keys."""
    keys = [key(s) for s in d.sites]
    assert len(set(keys)) == len(keys)
    return {frozenset((keys[i], keys[j])) for i, j in d.delaunay_edges()}


def as_piece(p):
    return cv.Segment(*p) if isinstance(p[0], tuple) else p


def cgal_graph(pieces):
    segs = [p for p in pieces if isinstance(p[0], tuple)]
    pts = [p for p in pieces if not isinstance(p[0], tuple)]
    return sdg_peer.segment_delaunay_edges(pts, segs, degenerate=True)[0]


def check(d, pieces):
    """d is the certified diagram of ``pieces`` (tuples), as the batch build and CGAL say."""
    assert d.certified, d.problems[:4]
    assert max(d.sources) == len(pieces) - 1
    for k, s in enumerate(d.sites):                  # each site comes from the piece its source names
        p = pieces[d.sources[k]]
        if isinstance(s, cv.Segment):
            assert key(s) == sdg_peer.segment_key(*p)
        elif isinstance(p[0], tuple):
            assert key(s) in (sdg_peer.point_key(*p[0]), sdg_peer.point_key(*p[1]))
        else:
            assert key(s) == sdg_peer.point_key(*p)
    batch = cv.voronoi([as_piece(p) for p in pieces])
    if d.stats["update"] == "local":                 # new sites appended
        assert sorted([key(s) for s in d.sites], key=str) == sorted([key(s) for s in batch.sites], key=str)
    else:                                            # a rebuild numbers the sites as the batch build
        assert [key(s) for s in d.sites] == [key(s) for s in batch.sites]
        assert d.delaunay_edges() == batch.delaunay_edges()
    assert graph(d) == graph(batch)
    assert graph(d) == cgal_graph(pieces)
    assert cv.verify(d).ok


def index_is_fresh(d):
    """The edit index a local edit carries on equals the one built from the diagram afresh."""
    from curvedvoronoi.runtime.segments.local_update import EditIndex

    got, want = d.construction.index, EditIndex.build(d)
    assert got.keys == want.keys
    assert np.array_equal(got.boxes, want.boxes)
    assert np.array_equal(got.XY, want.XY) and np.array_equal(got.R, want.R) and np.array_equal(got.VID, want.VID)
    w = min(got.VS.shape[1], want.VS.shape[1])
    assert np.array_equal(np.sort(got.VS[:, :w], axis=1), np.sort(want.VS[:, :w], axis=1))
    assert np.array_equal(got.ES, want.ES) and np.array_equal(np.sort(got.EE, axis=1), np.sort(want.EE, axis=1))


@pytest.mark.parametrize("seed,shared", [(1, False), (2, True), (3, True)])
def test_random_insert_delete_sequences_equal_batch_and_cgal(seed, shared):
    cgal_ready()
    rng = random.Random(seed)
    pool = without_straight_joints(random_segments(14, seed, box=60, shared=shared))  # non-crossing
    assert len(pool) >= 11
    pieces = pool[:8]
    reserve = pool[8:]
    d = cv.voronoi([as_piece(p) for p in pieces])
    d.stats["update"] = "none"
    check(d, pieces)
    routes = []
    for step in range(6):
        if reserve and (step % 2 == 0 or len(pieces) < 4):
            p = reserve.pop()
            d = d.insert(cv.Segment(*p), inplace=step % 3 == 0)
            pieces.append(p)
            assert d.stats["update_input"] == len(pieces) - 1
        else:
            i = rng.randrange(len(pieces))
            last = step % 4 == 1
            d = d.delete_site(i, renumber="last" if last else "shift")
            if last and i < len(pieces) - 1:
                pieces[i] = pieces.pop()
            else:
                del pieces[i]
        routes.append(d.stats["update"])
        assert routes[-1] == "local" or routes[-1].startswith("rebuild")     # the route is named
        check(d, pieces)
    print(routes)


def test_points_mixed_with_segments():
    cgal_ready()
    pieces = [((0, 0), (6, 0)), ((0, 4), (5, 7)), (3, 2), ((8, 1), (9, 6))]
    d = cv.voronoi([as_piece(p) for p in pieces])
    d = d.insert((2, -3))
    pieces.append((2, -3))
    check(d, pieces)
    d = d.delete_site(2)                                 # the point (3, 2)
    del pieces[2]
    check(d, pieces)
    assert sdg_peer.point_key(3, 2) not in {key(s) for s in d.sites}


def test_deletion_then_reinsertion_restores_the_graph():
    pool = without_straight_joints(random_segments(12, 7, box=50, shared=True))
    d = cv.voronoi([cv.Segment(*p) for p in pool])
    before = graph(d)
    for i in (0, 5, len(pool) - 1):
        gone = d.delete_site(i)
        assert graph(gone) != before
        back = gone.insert(cv.Segment(*pool[i]))
        assert back.certified, back.problems[:4]
        assert graph(back) == before


def test_a_shared_endpoint_stays_while_another_segment_has_it():
    d = cv.voronoi([cv.Segment((0, 0), (4, 0)), cv.Segment((4, 0), (4, 3)), cv.Segment((9, 9), (10, 9))])
    one = d.delete_site(0)
    keys = {key(s) for s in one.sites}
    assert sdg_peer.point_key(4, 0) in keys and sdg_peer.point_key(0, 0) not in keys
    assert sdg_peer.segment_key((0, 0), (4, 0)) not in keys
    two = one.delete_site(0)                             # now (4, 0)-(4, 3), input 0 after the shift
    keys = {key(s) for s in two.sites}
    assert keys == {sdg_peer.point_key(9, 9), sdg_peer.point_key(10, 9), sdg_peer.segment_key((9, 9), (10, 9))}
    assert two.certified
    with pytest.raises(IndexError, match="input piece"):
        d.delete_site(3)


def test_a_crossing_insertion_is_refused_like_the_batch_build():
    segs = [cv.Segment((0, 0), (4, 0)), cv.Segment((0, 3), (4, 5))]
    d = cv.voronoi(segs)
    for bad in (cv.Segment((2, -1), (2, 1)),            # crosses segment 0
                cv.Segment((1, 0), (1, 2)),             # ends inside segment 0
                cv.Segment((2, 0), (6, 0))):            # overlaps segment 0
        with pytest.raises(cv.SiteError) as edit:
            d.insert(bad)
        with pytest.raises(cv.SiteError) as batch:
            cv.voronoi(segs + [bad])
        assert str(edit.value) == str(batch.value)
    assert len(d.sites) == 6 and d.certified                  # the diagram is left as it was
    with pytest.raises(cv.SiteError):
        d.insert((2, 0))                                # a point inside a segment


def test_insertions_inside_the_scene_are_local_and_equal_cgal():
    # 150 disjoint segments; three more drawn by the same generator (so none crosses) and put in:
    # away from the convex hull the new regions are bounded, the route is local, and the result
    # is the diagram of the 153 segments (CGAL, and the independent verifier)
    cgal_ready()
    pool = random_segments(153, 4)
    pieces = pool[:150]
    d = cv.voronoi([cv.Segment(*p) for p in pieces])
    routes = []
    for p in pool[150:]:
        d = d.insert(cv.Segment(*p))
        pieces.append(p)
        routes.append(d.stats["update"])
        assert d.certified
        assert d.sources[-1] == len(pieces) - 1
        if routes[-1] == "local":
            index_is_fresh(d)
    for q in random_points_off(pieces, 3, 5):            # points off the segments, inside
        d = d.insert(q)
        pieces.append(tuple(q))
        routes.append(d.stats["update"])
        assert d.certified
    assert routes.count("local") >= 4, routes
    assert graph(d) == cgal_graph(pieces)
    assert cv.verify(d).ok
    back = d.delete_site(150)                        # a deletion after local insertions: rebuilt
    assert graph(back) == cgal_graph(pieces[:150] + pieces[151:])


def test_a_wrong_local_diagram_is_never_spliced():
    # the splice trusts nothing of the local diagram: one missing edge of the new segment fails
    # the closure, one vertex moved by 10^-3 fails its proof; either way the update is refused
    # (insert_locally returns why, and Diagram.insert rebuilds)
    from curvedvoronoi.runtime.segments.construction import segment_voronoi
    from curvedvoronoi.runtime.segments.local_insertion import insert_locally

    pool = random_segments(153, 4)
    d = cv.voronoi([cv.Segment(*p) for p in pool[:150]])
    new = next(cv.Segment(*p) for p in pool[150:]
               if not isinstance(insert_locally(d, cv.Segment(*p), 150, segment_voronoi), str))

    def missing_edge(pieces, certify):
        L = segment_voronoi(pieces, certify=certify)
        s = len(L.sites) - 1                          # the new segment's interior
        k = next(t for t, e in enumerate(L.edges) if s in e.sites and None not in e.ends)
        del L.edges[k]
        return L

    def moved_vertex(pieces, certify):
        L = segment_voronoi(pieces, certify=certify)
        s = len(L.sites) - 1
        v = next(v for v in L.vertices if s in v.sites)
        v.x += 1e-3
        return L

    assert "closure" in insert_locally(d, new, 150, missing_edge)
    assert "not proved" in insert_locally(d, new, 150, moved_vertex)


def test_an_insertion_in_place_equals_the_copying_one():
    pieces = [cv.Segment(*p) for p in without_straight_joints(random_segments(30, 5, box=80))]
    new = pieces.pop()
    a = cv.voronoi(pieces)
    b = cv.voronoi(pieces)
    va, ea = list(a.vertices), list(a.edges)
    c = a.insert(new)                                 # a copy: a unchanged
    assert a.vertices == va and a.edges == ea
    d = b.insert(new, inplace=True)
    assert d is b and c.stats["update"] == d.stats["update"] == "local"
    assert [(v.id, v.sites, v.x, v.y) for v in c.vertices] == [(v.id, v.sites, v.x, v.y) for v in d.vertices]
    assert [(e.id, e.sites, e.ends) for e in c.edges] == [(e.id, e.sites, e.ends) for e in d.edges]
    assert d.certified and cv.verify(d).ok
