"""Local deletion from a segment diagram with ``inplace=True`` (runtime/segments/local_deletion.py:
the proof in the old numbering, then the diagram's own lists edited): it must give the diagram the
copying deletion gives and the Voronoi diagram of the remaining pieces (a certified batch build,
sites and Delaunay graph over exact site keys), leave the input alone when it copies, and leave
the diagram untouched when the local route is refused.  Also the numpy helpers the local edits
use instead of passes over every part (conflict prefilter, table membership, row removal, the
kept-vertex search box) against their plain definitions."""
from __future__ import annotations

import random
import sys
from pathlib import Path

import numpy as np
import pytest

import curvedvoronoi as cv

sys.path.insert(0, str(Path(__file__).parent))
from scenes import random_segments  # noqa: E402
from test_segment_edits import as_piece, graph, index_is_fresh, key, without_straight_joints  # noqa: E402

from curvedvoronoi.runtime.segments.construction import segment_voronoi  # noqa: E402
from curvedvoronoi.runtime.segments.local_deletion import delete_locally  # noqa: E402
from curvedvoronoi.runtime.segments.local_update import (EditIndex, KeptVertices, conflict_mask, conflicts,  # noqa: E402
                                                         listing, site_key)


def state(d):
    """Everything a deletion may change, as plain values (sites by exact keys, in order)."""
    return ([key(s) for s in d.sites],
            [(v.id, tuple(v.sites), v.x, v.y, v.radius, v.certified) for v in d.vertices],
            [(e.id, tuple(e.sites), tuple(e.ends), e.closed, np.asarray(e.polyline, float).tobytes(), e.certified)
             for e in d.edges],
            list(d.sources), d.certified)


def index_state(index):
    return (dict(index.keys), index.boxes.copy(), index.XY.copy(), index.R.copy(), index.VS.copy(),
            index.VID.copy(), index.ES.copy(), index.EE.copy())


def same_index(a, b) -> bool:
    return a[0] == b[0] and all(np.array_equal(x, y) for x, y in zip(a[1:], b[1:]))


def inner(pieces, rng):
    """A piece well inside the scene (its deletion leaves a bounded hole: the local route)."""
    xs = [c for p in pieces for q in p for c in q[:1]]
    ys = [c for p in pieces for q in p for c in q[1:]]
    x0, x1, y0, y1 = min(xs), max(xs), min(ys), max(ys)
    idx = [i for i, p in enumerate(pieces)
           if all(x0 + (x1 - x0) / 4 < x < x1 - (x1 - x0) / 4 and y0 + (y1 - y0) / 4 < y < y1 - (y1 - y0) / 4 for x, y in p)]
    return rng.choice(idx)


def batch_graph(pieces):
    b = cv.voronoi([as_piece(p) for p in pieces])
    assert b.certified
    return sorted((key(s) for s in b.sites), key=str), graph(b), b


@pytest.mark.parametrize("mode", ["last", "shift"])
def test_in_place_deletion_equals_the_copying_one_and_the_batch_build(mode):
    pieces = random_segments(120, 7)
    a = cv.voronoi([as_piece(p) for p in pieces])
    b = cv.voronoi([as_piece(p) for p in pieces])
    rng = random.Random(3)
    for _ in range(3):
        i = inner(pieces, rng)
        before = state(a)
        c = a.delete_site(i, renumber=mode)
        assert state(a) == before                       # the copy leaves its input alone
        lists = (b.sites, b.vertices, b.edges, b.sources)
        r = b.delete_site(i, renumber=mode, inplace=True)
        assert r is b and c.stats["update"] == b.stats["update"] == "local", (c.stats["update"], b.stats["update"])
        assert all(x is y for x, y in zip(lists, (b.sites, b.vertices, b.edges, b.sources)))   # edited, not replaced
        assert state(b) == state(c)
        if mode == "last" and i < len(pieces) - 1:
            pieces[i] = pieces.pop()
        else:
            del pieces[i]
        a = c
    index_is_fresh(b)
    keys, g, _ = batch_graph(pieces)
    assert b.certified and sorted((key(s) for s in b.sites), key=str) == keys and graph(b) == g
    for k, s in enumerate(b.sites):                     # each site comes from a piece that has it
        p = pieces[b.sources[k]]
        assert key(s) == key(as_piece(p)) or key(s) in (key(cv.Point(*p[0])), key(cv.Point(*p[1])))


def test_shift_deletions_of_chains_give_the_batch_sources():
    # chains share endpoints: deleting a piece keeps an endpoint another piece has, and its source
    # moves to the first remaining piece with it, as the batch build of the remaining pieces numbers it
    pieces = without_straight_joints(random_segments(90, 4, box=300, shared=True))
    d = cv.voronoi([as_piece(p) for p in pieces])
    rng = random.Random(8)
    kept_shared = 0
    for _ in range(4):
        i = inner(pieces, rng)
        shared = sum(1 for j, q in enumerate(pieces) if j != i and set(q) & set(pieces[i]))
        d.delete_site(i, renumber="shift", inplace=True)
        del pieces[i]
        keys, g, b = batch_graph(pieces)
        assert d.certified and sorted((key(s) for s in d.sites), key=str) == keys and graph(d) == g
        if d.stats["update"] == "local":
            kept_shared += shared > 0
            assert {key(s): d.sources[k] for k, s in enumerate(d.sites)} == \
                {key(s): b.sources[k] for k, s in enumerate(b.sites)}
    assert kept_shared >= 1
    index_is_fresh(d)


def test_a_refused_local_deletion_leaves_the_diagram_untouched():
    pieces = random_segments(120, 7)
    d = cv.voronoi([as_piece(p) for p in pieces])
    index = EditIndex.build(d)
    i = inner(pieces, random.Random(1))
    a, b = pieces[i]
    gone = [index.keys[site_key(s)] for s in (cv.Segment(a, b), cv.Point(*a), cv.Point(*b))]
    x, y = (a[0] + b[0]) / 2, (a[1] + b[1]) / 2

    def moved_vertex(sites, certify):
        L = segment_voronoi(sites, certify=certify)
        v = min(L.vertices, key=lambda v: abs(v.x - x) + abs(v.y - y))
        v.x += 1e-3
        return L

    def missing_edge(sites, certify):
        L = segment_voronoi(sites, certify=certify)
        k = min((t for t, e in enumerate(L.edges) if None not in e.ends),
                key=lambda t: min(abs(px - x) + abs(py - y) for px, py in L.edges[t].polyline))
        del L.edges[k]
        return L

    before, ibefore = state(d), index_state(index)
    assert "not proved" in delete_locally(d, gone, moved_vertex, index, inplace=True)
    assert "closure" in delete_locally(d, gone, missing_edge, index, inplace=True)
    assert state(d) == before and same_index(index_state(index), ibefore)
    out = delete_locally(d, gone, segment_voronoi, index, inplace=True)     # the same deletion, proved
    assert not isinstance(out, str) and out.sites is d.sites and out.vertices is d.vertices
    assert len(d.sites) == len(before[0]) - 3


def test_conflict_prefilter_equals_the_distance_over_all_circles():
    rng = np.random.default_rng(4)
    n = 4000
    XY = rng.uniform(-500, 500, (n, 2))
    R = rng.exponential(40, n)
    index = EditIndex({}, np.zeros((0, 4)), XY, R, np.zeros((n, 3), np.int64), np.arange(n), np.zeros((0, 2), np.int64),
                      np.zeros((0, 2), np.int64))
    pieces = [cv.Segment((-3, 7), (40, 2)), cv.Point(100, -250), cv.Segment((0, 0), (1, 0)),
              cv.Arc.circular((0, 0), 50, 10, 100), cv.Arc.circular((0, -10 ** 9), 10 ** 9, 89, 91)]
    # circles touching a piece within rounding: centres at distance r of its end
    for q in pieces:
        want = conflicts(q, XY, R)
        assert np.array_equal(conflict_mask(index, [q]), want)
        assert 0 < want.sum() < n
    assert np.array_equal(conflict_mask(index, pieces[:2]), conflicts(pieces[0], XY, R) | conflicts(pieces[1], XY, R))
    T = np.array([[40.0 + 30.0, 2.0], [-3.0, 7.0 + 5.5]])       # exactly touching circles
    assert conflict_mask(EditIndex({}, np.zeros((0, 4)), T, np.array([30.0, 5.5]), np.zeros((2, 3), np.int64),
                                   np.arange(2), np.zeros((0, 2), np.int64), np.zeros((0, 2), np.int64)),
                         [pieces[0]]).all()


def test_table_membership_equals_numpy():
    rng = np.random.default_rng(5)
    for n, w in ((0, 2), (1, 3), (500, 2), (500, 3)):
        A = rng.integers(-1, 60, (n, w))
        for vals in ([], [0], [59], [3, 7, 7, 200], list(range(0, 60, 3))):
            want = np.isin(A, vals).any(axis=1) if len(vals) else np.zeros(n, bool)
            assert np.array_equal(listing(A, vals), want)
            for bound in (60, 61, 300):                  # entries below the bound: the unclipped gathers
                assert np.array_equal(listing(A, vals, bound), want)
                assert np.array_equal(listing(A[:, ::-1], vals, bound), want)      # columns not contiguous


def test_replacing_rows_keeps_the_list_and_the_arrays_aligned():
    # each part is a vertex whose index rows encode it (centre, radius, sites, id); after removals
    # and appends (past the buffers' room), the list holds the kept and the new parts once each,
    # and row r of every array describes parts[r]
    from curvedvoronoi.runtime.voronoi.structure import DiagramVertex

    rng = np.random.default_rng(6)
    parts = [DiagramVertex(t, (t, t + 1, t + 2), float(t), -float(t), t / 2) for t in range(300)]
    index = EditIndex.build(cv.Diagram([], parts, []))
    fresh = 300
    for step in range(12):
        removed = rng.choice(len(parts), size=int(rng.integers(0, 30)), replace=False)
        new = [DiagramVertex(fresh + t, (fresh + t, 1, 2, 3)[:3 + step % 2], float(fresh + t), -float(fresh + t),
                             (fresh + t) / 2) for t in range(int(rng.integers(0, 60)))]
        fresh += len(new)
        want = sorted([v.id for t, v in enumerate(parts) if t not in set(removed.tolist())] + [v.id for v in new])
        index.replace_rows(parts, "v", removed.tolist(), new)
        assert sorted(v.id for v in parts) == want and len(index.R) == len(parts)
        assert np.array_equal(index.VID, [v.id for v in parts])
        assert np.array_equal(index.XY, [[v.x, v.y] for v in parts]) and np.array_equal(index.R, [v.radius for v in parts])
        assert np.array_equal(index.CB, np.array([[v.x - 2 * v.radius, v.y - 2 * v.radius, v.x + 2 * v.radius,
                                                   v.y + 2 * v.radius] for v in parts]).reshape(-1, 4))
        assert index.id_bound > max(v.id for v in parts)
        assert all(tuple(index.VS[r][index.VS[r] >= 0]) == v.sites for r, v in enumerate(parts))


def test_the_kept_vertex_search_box_finds_what_the_full_search_finds():
    d = cv.voronoi([as_piece(p) for p in random_segments(60, 2)])
    index = EditIndex.build(d)
    removed = np.zeros(len(d.vertices), bool)
    removed[::7] = True
    full = KeptVertices(index, d.vertices, removed)
    boxed = KeptVertices(index, d.vertices, removed)
    lo, hi = index.XY.min(axis=0), index.XY.max(axis=0)
    boxed.restrict(lo + (hi - lo) / 3, hi - (hi - lo) / 3)      # some questions inside, some outside
    inside = 0
    for t, v in enumerate(d.vertices):
        q = (tuple(v.sites), v.x, v.y, v.radius)
        got = boxed.find(*q)
        assert got == full.find(*q) == (-1 if removed[t] else v.id)
        inside += bool(lo[0] + (hi[0] - lo[0]) / 3 < v.x < hi[0] - (hi[0] - lo[0]) / 3)
    assert 0 < inside < len(d.vertices)


def test_a_kept_endpoint_of_three_pieces_takes_the_first_remaining_one():
    # a "Y" of three arms meeting at (330, 330) inside a random scene; the first arm is the source
    # of the common point; deleting it (shift) leaves two arms with the point, and its source must
    # become the first of them, as in the batch build of the remaining pieces
    y = [((330, 330), (345, 333)), ((330, 330), (322, 343)), ((330, 330), (324, 318))]
    scene = [p for p in random_segments(150, 11) if not any(305 <= x <= 360 and 305 <= yy <= 360 for x, yy in p)]
    pieces = scene[:30] + [y[0]] + scene[30:60] + [y[1]] + scene[60:] + [y[2]]
    d = cv.voronoi([as_piece(p) for p in pieces])
    d.delete_site(30, renumber="shift", inplace=True)
    del pieces[30]
    assert d.stats["update"] == "local", d.stats["update"]
    keys, g, b = batch_graph(pieces)
    assert sorted((key(s) for s in d.sites), key=str) == keys and graph(d) == g
    src = {key(s): d.sources[k] for k, s in enumerate(d.sites)}
    assert src == {key(s): b.sources[k] for k, s in enumerate(b.sites)}
    assert src[key(cv.Point(330, 330))] == pieces.index(y[1])


def test_an_edit_in_place_of_a_copy_leaves_the_original_alone():
    # deleting a point piece that is also a segment's end changes only the sources; the copy it
    # returns must not share the edit state (site keys, boxes) with the original, which a later
    # edit in place of the copy changes
    scene = [p for p in random_segments(100, 2) if all(not (0 <= x <= 12 and 0 <= y <= 12) for x, y in p)]
    pieces = [((6, 4), (9, 9)), (6, 4)] + scene
    d0 = cv.voronoi([as_piece(p) for p in pieces])
    i1 = inner(pieces[2:], random.Random(2)) + 2
    d1 = d0.delete_site(i1)                              # a copy carrying its edit index
    del pieces[i1]
    before = state(d1)
    e = d1.delete_site(1)                                # the point piece: a copy, the sites stay
    del pieces[1]
    assert d1.stats["update"] == e.stats["update"] == "local"
    e.delete_site(inner(pieces, random.Random(4)), renumber="last", inplace=True)
    assert e.stats["update"] == "local"
    e.insert(cv.Segment((1, 1), (2, 3)), inplace=True)
    assert state(d1) == before
    index_is_fresh(d1)
