"""Insertion and deletion of circular arcs, and of segments and points in diagrams with arcs
(runtime/segments/edits.py, local_insertion.py, local_deletion.py): after every edit the diagram
must be the Voronoi diagram of the new list of pieces.  The reference is an independent batch
build of that list (``cv.voronoi``, certified): the same elementary sites (exact keys: a local
deletion numbers them differently), the same Delaunay graph, and the same vertices (the same
sites, centres within 10⁻⁷).  Scenes: one arc per cell of a grid (tests/scenes.random_arcs), the
edits in cells away from the grid's border, where the changed regions are bounded and the update
is local (a region reaching the convex hull is rebuilt: the route is in ``stats["update"]``)."""
from __future__ import annotations

import math
import random
import sys
from collections import defaultdict
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest

import curvedvoronoi as cv
from curvedvoronoi.runtime.segments.local_update import site_box, site_distance, site_key

sys.path.insert(0, str(Path(__file__).parent))
from scenes import random_arcs  # noqa: E402

SIDE = 7            # a 7 × 7 grid of cells of side 40, one piece (or two) per cell
CELL = 40


def keys(d):
    return [site_key(s) for s in d.sites]


def same_diagram(d, b) -> None:
    """d and b have the same sites, Delaunay graph and vertices (by exact site keys)."""
    kd, kb = keys(d), keys(b)
    assert sorted(kd) == sorted(kb)
    assert ({frozenset((kd[i], kd[j])) for i, j in d.delaunay_edges()}
            == {frozenset((kb[i], kb[j])) for i, j in b.delaunay_edges()})

    def groups(D, k):
        out = defaultdict(list)
        for v in D.vertices:
            out[frozenset(k[s] for s in v.sites)].append((v.x, v.y))
        return out
    gd, gb = groups(d, kd), groups(b, kb)
    assert gd.keys() == gb.keys()
    for g, pd in gd.items():
        pb = list(gb[g])
        assert len(pd) == len(pb)
        for x, y in pd:                       # each vertex matches one of the batch's, distinct ones
            t = min(range(len(pb)), key=lambda t: math.hypot(pb[t][0] - x, pb[t][1] - y))
            assert math.hypot(pb[t][0] - x, pb[t][1] - y) <= 1e-7 * (1 + abs(x) + abs(y))
            pb.pop(t)


def interior(piece) -> bool:
    """The piece lies in a cell off the grid's border (its region cannot reach the convex hull)."""
    x0, y0, x1, y1 = site_box(piece if not isinstance(piece, tuple) else cv.Point(*piece))
    g = [int((x0 + x1) / 2) // CELL, int((y0 + y1) / 2) // CELL]
    return all(1 <= c <= SIDE - 2 for c in g)


def scene(seed: int, mixed: bool):
    """One arc per cell; ``mixed``: every third arc replaced by its chord (a segment), every fifth
    cell also holding the arc's centre as a point piece."""
    out = []
    for k, a in enumerate(random_arcs(SIDE * SIDE, seed, cell=CELL)):
        if mixed and k % 3 == 1:
            out.append(cv.Segment(a.a, a.b))
        else:
            out.append(a)
        if mixed and k % 5 == 2:
            out.append((a.c[0], a.c[1]))
    return out


def as_site(p):
    return cv.Point(*p) if isinstance(p, tuple) else p


@pytest.mark.parametrize("seed,mixed", [(1, False), pytest.param(2, True, marks=pytest.mark.slow)])
def test_random_insertions_and_deletions_equal_the_batch_build(seed, mixed):
    pieces = scene(seed, mixed)
    rng = random.Random(seed)
    inner = [k for k, p in enumerate(pieces) if interior(as_site(p)) and not isinstance(p, tuple)]
    extra = [pieces[k] for k in rng.sample(inner, 3)]
    cur = [p for p in pieces if not any(p is e for e in extra)]
    d = cv.voronoi(cur, progress=False)
    assert d.certified
    routes = []
    for e in extra:
        d = d.insert(e)
        cur.append(e)
        routes.append(d.stats["update"])
        assert d.certified
        same_diagram(d, cv.voronoi(cur, progress=False))
    for mode in ("last", "shift", "last"):
        i = rng.choice([k for k, p in enumerate(cur) if interior(as_site(p))])
        d = d.delete_site(i, renumber=mode)
        if mode == "shift" or i == len(cur) - 1:
            cur.pop(i)
        else:
            cur[i] = cur.pop()
        routes.append(d.stats["update"])
        assert d.certified
        b = cv.voronoi(cur, progress=False)
        same_diagram(d, b)
        # every elementary site comes from its source piece (the piece itself or one of its ends)
        for s, src in zip(d.sites, d.sources):
            piece = as_site(cur[src])
            assert site_key(s) == site_key(piece) or (isinstance(s, cv.Point) and not isinstance(piece, cv.Point)
                                                      and (Fraction(str(s.cx)), Fraction(str(s.cy))) in
                                                      [tuple(map(Fraction, q)) for q in _ends(piece)])
    assert sum(r == "local" for r in routes) >= 4, routes


def _ends(piece):
    return (piece.a, piece.b) if isinstance(piece, cv.Arc) else (piece.p, piece.q)


def test_deleting_and_reinserting_an_arc_restores_the_diagram():
    pieces = scene(3, False)
    d = cv.voronoi(pieces, progress=False)
    assert d.certified
    i = next(k for k, p in enumerate(pieces) if interior(p))
    gone = d.delete_site(i, renumber="last")
    assert gone.stats["update"] == "local" and gone.certified
    assert site_key(pieces[i]) not in keys(gone)
    back = gone.insert(pieces[i])
    assert back.stats["update"] == "local" and back.certified
    same_diagram(back, d)


def test_a_segment_and_a_point_inserted_among_arcs_are_local():
    pieces = scene(4, False)
    rng = random.Random(4)
    inner = [k for k, p in enumerate(pieces) if interior(p)]
    k1, k2 = rng.sample(inner, 2)
    a1, a2 = pieces[k1], pieces[k2]
    rest = [p for k, p in enumerate(pieces) if k not in (k1, k2)]
    d = cv.voronoi(rest, progress=False)
    seg = cv.Segment(a1.a, a1.b)                  # the chord of a removed arc: in its empty cell
    pt = (a2.c[0], a2.c[1])                       # the centre of another
    d = d.insert(seg)
    assert d.stats["update"] == "local" and d.certified
    d = d.insert(pt)
    assert d.stats["update"] == "local" and d.certified
    same_diagram(d, cv.voronoi(rest + [seg, pt], progress=False))


def test_an_arc_continuing_a_segment_smoothly_is_rebuilt_right():
    # the arc leaves (10, 0) in direction +x, the segment leaves it in direction -x: (10, 0) stops
    # being a site (a smooth joint, runtime/segments/elementary.py) - not a local change
    around = [cv.Arc.circular((-20, 30), 6, 0, 120), cv.Arc.circular((40, -25), 5, 90, 200),
              cv.Segment((-30, -20), (-22, -30)), cv.Arc.circular((35, 30), 4, 200, 300), (0, 40), (30, 5)]
    seg = cv.Segment((0, 0), (10, 0))
    arc = cv.Arc((10, 5), 5, (10, 0), (15, 5))
    d = cv.voronoi(around + [seg], progress=False)
    e = d.insert(arc)
    assert e.stats["update"].startswith("rebuild (the piece continues a curve")
    b = cv.voronoi(around + [seg, arc], progress=False)
    assert e.certified == b.certified
    same_diagram(e, b)
    f = e.delete_site(len(around) + 1)             # the arc again: its end is a smooth joint
    assert f.stats["update"].startswith("rebuild (the piece ends at a smooth joint")
    same_diagram(f, d)


@pytest.mark.parametrize("seed", [5, 6])
def test_the_float_distance_to_an_arc_is_the_distance_to_its_points(seed):
    # the conflict test's distance: never above the distance to any point of the closed arc, and
    # within the sampling step of the nearest sampled point; the arc's box holds all its points
    rng = random.Random(seed)
    for _ in range(20):
        a = cv.Arc.circular((rng.randint(-50, 50), rng.randint(-50, 50)), rng.randint(1, 30),
                            rng.randint(0, 359), rng.randint(0, 359) + 0.5)
        (cx, cy), rho, (ax, ay), (bx, by) = a.float_data()
        t0, t1 = math.atan2(ay - cy, ax - cx), math.atan2(by - cy, bx - cx)
        span = (t1 - t0) % (2 * math.pi)
        T = t0 + np.linspace(0, span, 20001)
        P = np.column_stack([cx + rho * np.cos(T), cy + rho * np.sin(T)])
        x0, y0, x1, y1 = site_box(a)
        tol = 1e-9 * (1 + abs(cx) + abs(cy) + rho)
        assert (P[:, 0] >= x0 - tol).all() and (P[:, 0] <= x1 + tol).all()
        assert (P[:, 1] >= y0 - tol).all() and (P[:, 1] <= y1 + tol).all()
        X = np.column_stack([rng_uniform(rng, cx, 3 * rho), rng_uniform(rng, cy, 3 * rho)])
        X = np.vstack([X, [[cx, cy]]])
        d = site_distance(a, X)
        sampled = np.hypot(X[:, None, 0] - P[None, :, 0], X[:, None, 1] - P[None, :, 1]).min(axis=1)
        assert (d <= sampled + 1e-9 * rho).all()
        assert (d >= sampled - rho * span / 20000).all()


def rng_uniform(rng, c, h):
    return [c + rng.uniform(-h, h) for _ in range(50)]


def test_a_circle_is_inserted_and_deleted_locally_as_its_two_halves():
    # a whole circle enters as two half arcs meeting at smooth joints (no point sites there)
    pieces = scene(3, False)
    i = next(k for k, p in enumerate(pieces) if interior(p))
    a = pieces[i]
    rest = pieces[:i] + pieces[i + 1:]
    d = cv.voronoi(rest, progress=False)
    c = cv.Circle.from_radius(a.c[0], a.c[1], a.rho)
    e = d.insert(c)
    assert e.stats["update"] == "local" and e.certified
    assert len(e.sites) == len(d.sites) + 2
    same_diagram(e, cv.voronoi(rest + [c], progress=False))
    f = e.delete_site(len(rest))
    assert f.stats["update"] == "local" and f.certified
    same_diagram(f, d)
