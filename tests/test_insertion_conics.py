"""Local insertion and deletion with ellipse sites (thesis §1.2; disjoint convex sites form an
abstract Voronoi diagram, Klein, Mehlhorn & Meiser 1993) against independent references.

* The Delaunay graph of a small scene of ellipses, circles and a point is compared with a dense
  grid of exact nearest-site computations that shares no code with the package: the distance
  from a point to an ellipse is the root of Eberly's secular equation (*Distance from a point to
  an ellipse, an ellipsoid, or a hyperellipsoid*, Geometric Tools 2013) by bisection in numpy,
  from the ellipse's own centre, semi-axes and rotation.  Every pair of sites proved adjacent by
  the grid (a point where both are equally near and every other site farther) is a Delaunay edge,
  and every long edge is found by the grid.
* Inserting the sites one by one (several seeds and orders) gives the batch build's Delaunay
  graph, every result certified, the last one proved by the independent verifier ``cv.verify``.
* Deleting a site and inserting it again restores the diagram; deletions alone give the batch
  diagram of the remaining sites.
* An ellipse meeting or repeating an existing site raises the batch build's SiteError; a site
  nested in an ellipse rebuilds the diagram (outside the local argument).
"""
from __future__ import annotations

import math
import random
from fractions import Fraction

import numpy as np
import pytest

import curvedvoronoi as cv

ROT = [(1, 0), (Fraction(3, 5), Fraction(4, 5)), (Fraction(5, 13), Fraction(12, 13)), (Fraction(4, 5), Fraction(-3, 5))]


def scene(n, seed, side=None):
    """n random sites (two thirds ellipses, then circles, every seventh a point), disjoint
    circumscribed discs 0.3 apart; returns (sites, parameters) with parameters
    ("e", cx, cy, a, b, c, s), ("c", cx, cy, r) or ("p", x, y)."""
    rng = random.Random(seed)
    side = side or 7.0 * math.sqrt(n)
    sites, params, placed = [], [], []
    while len(sites) < n:
        k = len(sites)
        cx = Fraction(round(rng.uniform(0, side) * 32), 32)
        cy = Fraction(round(rng.uniform(0, side) * 32), 32)
        kind = "p" if k % 7 == 6 else ("c" if k % 3 == 2 else "e")
        a = Fraction(round(rng.uniform(1.0, 2.5) * 16), 16) if kind != "p" else Fraction(0)
        if any(math.hypot(float(cx) - x, float(cy) - y) <= float(a) + r + 0.3 for x, y, r in placed):
            continue
        placed.append((float(cx), float(cy), float(a)))
        if kind == "e":
            b = a * Fraction(round(rng.uniform(0.3, 0.9) * 16), 16)
            c, s = rng.choice(ROT)
            sites.append(cv.Conic.ellipse(centre=(cx, cy), axes=(a, b), rotation=(c, s)))
            params.append(("e", float(cx), float(cy), float(a), float(b), float(c), float(s)))
        elif kind == "c":
            sites.append(cv.Circle.from_radius(cx, cy, a))
            params.append(("c", float(cx), float(cy), float(a)))
        else:
            sites.append(cv.Point(cx, cy))
            params.append(("p", float(cx), float(cy)))
    return sites, params


def ellipse_distance(P, cx, cy, a, b, c, s):
    """Distance from the points P to the ellipse (centre, semi-axes a ≥ b, rotation (c, s)):
    Eberly's secular equation G(t) = (a·x/(t + a²))² + (b·y/(t + b²))² − 1 = 0 in the canonical
    first quadrant, decreasing on (−b², ∞), bracketed by t = −b² + b·y (G ≥ 0) and
    t = sqrt(a²x² + b²y²) (G ≤ 0), solved by bisection; the foot point is
    (a²x/(t + a²), b²y/(t + b²))."""
    dx, dy = P[:, 0] - cx, P[:, 1] - cy
    x = np.abs(c * dx + s * dy)
    y = np.abs(-s * dx + c * dy)
    assert (y > 0).all()                # the grid is jittered off the axes
    lo = -b * b + b * y
    hi = np.sqrt(a * a * x * x + b * b * y * y)
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        g = (a * x / (mid + a * a)) ** 2 + (b * y / (mid + b * b)) ** 2 - 1
        lo, hi = np.where(g > 0, mid, lo), np.where(g > 0, hi, mid)
    t = 0.5 * (lo + hi)
    return np.hypot(x - a * a * x / (t + a * a), y - b * b * y / (t + b * b))


def distances(P, params):
    out = []
    for p in params:
        if p[0] == "e":
            out.append(ellipse_distance(P, *p[1:]))
        elif p[0] == "c":
            out.append(np.abs(np.hypot(P[:, 0] - p[1], P[:, 1] - p[2]) - p[3]))
        else:
            out.append(np.hypot(P[:, 0] - p[1], P[:, 1] - p[2]))
    return np.array(out).T


def test_reference_distance_is_the_minimum_over_the_curve():
    # the reference itself, against brute force over 200 000 points of the ellipse
    rng = np.random.default_rng(4)
    P = rng.uniform(-6, 6, (200, 2))
    cx, cy, a, b, c, s = 0.5, -0.25, 3.0, 1.25, 0.6, 0.8
    t = np.linspace(0, 2 * np.pi, 200000, endpoint=False)
    E = np.stack([cx + c * a * np.cos(t) - s * b * np.sin(t), cy + s * a * np.cos(t) + c * b * np.sin(t)], 1)
    brute = np.array([np.hypot(*(E - q).T).min() for q in P])
    got = ellipse_distance(P, cx, cy, a, b, c, s)
    assert np.all(got <= brute + 1e-12) and np.all(brute - got < 1e-6)


def grid_pairs(params, lo, hi, m, seed=0):
    """Pairs of sites proved adjacent on a grid (a point on the segment between two neighbouring
    grid points where the two are equally near, every other site at least 1e-6 farther)."""
    rng = np.random.default_rng(seed)
    xs = np.linspace(lo, hi, m) + rng.uniform(0, 1e-3)
    ys = np.linspace(lo, hi, m) + rng.uniform(0, 1e-3)
    X, Y = np.meshgrid(xs, ys)
    Dg = distances(np.stack([X.ravel(), Y.ravel()], 1), params).reshape(m, m, -1)
    near = Dg.argmin(-1)
    found = set()
    for A, B in (((slice(None), slice(0, -1)), (slice(None), slice(1, None))),
                 ((slice(0, -1), slice(None)), (slice(1, None), slice(None)))):
        I, J = near[A], near[B]
        rows, cols = np.nonzero(I != J)
        P0 = np.stack([X[A][rows, cols], Y[A][rows, cols]], 1)
        P1 = np.stack([X[B][rows, cols], Y[B][rows, cols]], 1)
        i, j = I[rows, cols], J[rows, cols]
        u0, u1 = np.zeros(len(i)), np.ones(len(i))
        for _ in range(50):                      # d_i − d_j changes sign along the segment
            u = 0.5 * (u0 + u1)
            Q = P0 + u[:, None] * (P1 - P0)
            Dq = distances(Q, params)
            f = Dq[np.arange(len(i)), i] - Dq[np.arange(len(i)), j]
            u0, u1 = np.where(f < 0, u, u0), np.where(f < 0, u1, u)
        Q = P0 + (0.5 * (u0 + u1))[:, None] * (P1 - P0)
        Dq = distances(Q, params)
        di = Dq[np.arange(len(i)), i]
        Dq[np.arange(len(i)), i] = np.inf
        Dq[np.arange(len(i)), j] = np.inf
        clear = Dq.min(1) > di + 1e-6
        found |= {tuple(sorted((int(a), int(b)))) for a, b, ok in zip(i, j, clear) if ok}
    return found


@pytest.mark.parametrize("seed", [1, 2])
def test_batch_and_inserted_graphs_match_the_grid_reference(seed):
    sites, params = scene(12, seed)
    side = 7.0 * math.sqrt(12)
    batch = cv.voronoi(sites)
    assert batch.certified
    d = cv.voronoi(sites[:5])
    for s in sites[5:]:
        d = d.insert(s)
        assert d.certified, d.problems[:3]
    assert d.delaunay_edges() == batch.delaunay_edges()
    ref = grid_pairs(params, -4.0, side + 4.0, 500, seed)
    graph = set(batch.delaunay_edges())
    assert ref <= graph, sorted(ref - graph)
    # every edge longer than a few grid steps inside the grid is seen there
    step = (side + 8.0) / 499
    for e in batch.edges:
        P = np.asarray(e.polyline, float)
        inside = P[(P >= -3.0).all(1) & (P <= side + 3.0).all(1)]
        if len(inside) > 1 and np.hypot(*np.diff(inside, axis=0).T).sum() > 6 * step:
            assert tuple(e.sites) in ref, e.sites


@pytest.mark.parametrize("seed", [3, 4, 5])
def test_any_insertion_order_gives_the_batch_diagram(seed):
    sites, _ = scene(16, seed)
    order = list(range(len(sites)))
    random.Random(seed).shuffle(order)
    d = cv.voronoi([sites[t] for t in order[:6]])
    cur = [sites[t] for t in order[:6]]
    hows = []
    for t in order[6:]:
        d = d.insert(sites[t])
        cur.append(sites[t])
        hows.append(d.stats["update"])
        assert d.certified, (d.stats["update"], d.problems[:3])
    assert all(h.startswith("local") for h in hows), hows
    assert d.delaunay_edges() == cv.voronoi(cur, certify=False).delaunay_edges()
    cert = cv.verify(d, cur)
    assert cert.ok, cert.problems[:3]
    assert [v.id for v in d.vertices] == list(range(len(d.vertices)))
    assert [e.id for e in d.edges] == list(range(len(d.edges)))


@pytest.mark.parametrize("renumber", ["shift", "last"])
def test_delete_then_insert_restores(renumber):
    sites, _ = scene(14, 6)
    d = cv.voronoi(sites)
    n = len(sites)
    for i in (0, 4, 9):
        d2 = d.delete_site(i, renumber=renumber)
        assert d2.stats["deletion"].startswith("local") and d2.certified, (d2.stats, d2.problems[:3])
        rest = [s for k, s in enumerate(sites) if k != i] if renumber == "shift" else \
            sites[:i] + [sites[-1]] + sites[i + 1:-1]
        assert d2.delaunay_edges() == cv.voronoi(rest, certify=False).delaunay_edges()
        d3 = d2.insert(sites[i])
        assert d3.certified
        # new index of the old site t
        if renumber == "shift":
            new_of = {t: t - (t > i) for t in range(n) if t != i}
        else:
            new_of = {t: (i if t == n - 1 else t) for t in range(n) if t != i}
        new_of[i] = n - 1
        want = sorted(tuple(sorted((new_of[a], new_of[b]))) for a, b in d.delaunay_edges())
        assert d3.delaunay_edges() == want
        old_v = sorted((tuple(sorted(new_of[t] for t in v.sites)), round(v.x, 8), round(v.y, 8)) for v in d.vertices)
        new_v = sorted((tuple(sorted(v.sites)), round(v.x, 8), round(v.y, 8)) for v in d3.vertices)
        assert old_v == new_v
    assert cv.verify(d3).ok


def test_site_errors_and_nesting():
    sites, params = scene(10, 7)
    d = cv.voronoi(sites)
    k = next(t for t, p in enumerate(params) if p[0] == "e")
    _, cx, cy, a, b, c, s = params[k]
    e = sites[k]
    crossing = cv.Conic.ellipse(centre=(Fraction(cx) + Fraction(a), Fraction(cy)), axes=(Fraction(a), Fraction(b)))
    for bad in (crossing, e):
        with pytest.raises(cv.SiteError) as batch:
            cv.voronoi(sites + [bad], certify=False)
        with pytest.raises(cv.SiteError) as local:
            d.insert(bad)
        assert str(local.value) == str(batch.value)
    inner = cv.Point(Fraction(cx), Fraction(cy))        # the centre: inside the ellipse
    d2 = d.insert(inner)
    assert d2.stats["update"] == "rebuild"
    assert d2.delaunay_edges() == cv.voronoi(sites + [inner], certify=False).delaunay_edges()


def test_unsupported_kinds_are_named():
    d = cv.voronoi([(0, 0, 1), (6, 0, 1), (3, 5, 1)])
    h = cv.Conic.hyperbola(centre=(40, 0), axes=(1, 1), rotation=(1, 0))
    d2 = d.insert(h)                                   # no local update: rebuilt, and said so
    assert d2.stats["update"] == "rebuild (a hyperbola site: no local update)"
    assert d2.delaunay_edges() == cv.voronoi([(0, 0, 1), (6, 0, 1), (3, 5, 1), h]).delaunay_edges()
    segs = [cv.Segment((0, 0), (1, 0)), cv.Segment((0, 2), (1, 3)), cv.Segment((3, 0), (4, 1))]
    s = cv.voronoi(segs, certify=False)
    s2 = s.insert(cv.Segment((5, 5), (6, 5)))               # not certified: rebuilt, and said so
    assert s2.stats["update"] == "rebuild (the diagram is not certified)"
    assert s2.delaunay_edges() == cv.voronoi(segs + [cv.Segment((5, 5), (6, 5))]).delaunay_edges()
    assert s.delete_site(0).delaunay_edges() == cv.voronoi(segs[1:]).delaunay_edges()
    read = cv.Diagram.from_json(s.to_json())                 # no input pieces kept: named
    with pytest.raises(ValueError, match="segment sites"):
        read.insert(cv.Segment((5, 5), (6, 5)))
    with pytest.raises(ValueError, match="segment sites"):
        read.delete_site(0)


def test_cell_radius_bounds_every_dominated_point():
    # brute force: every grid point at least as near to disc i as to each disc of T (the bounds
    # |q − c| − R ≤ d ≤ |q − c| + R) lies within the returned radius; open sides give None
    from curvedvoronoi.runtime.voronoi.conflict import cell_radius

    rng = np.random.default_rng(8)
    for _ in range(20):
        C = rng.uniform(-10, 10, (14, 2))
        R = rng.uniform(0.1, 1.0, 14)
        C[0] = (0.0, 0.0)
        keep = [0] + [k for k in range(1, 14) if np.hypot(*C[k]) > R[0] + R[k] + 0.05]
        C, R = C[keep], R[keep]
        T = list(range(1, len(C)))
        rho = cell_radius(C, R, 0, T)
        g = np.linspace(-60, 60, 601)
        X, Y = np.meshgrid(g, g)
        Q = np.stack([X.ravel(), Y.ravel()], 1)
        lhs = np.hypot(*Q.T) - R[0]
        dom = np.all(lhs[:, None] <= np.hypot(Q[:, None, 0] - C[T, 0], Q[:, None, 1] - C[T, 1]) + R[T], axis=1)
        if rho is None:
            continue
        assert np.hypot(*Q[dom].T).max() <= rho
    # discs on one side only: the region is unbounded
    assert cell_radius(np.array([[0.0, 0.0], [5.0, 0.0], [5.0, 3.0]]), np.array([1.0, 1.0, 1.0]), 0, [1, 2]) is None
