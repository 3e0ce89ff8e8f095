"""The discs of runtime.voronoi.reach (the sites a local update proves its new parts against)
against brute force and the true bisector arcs.

* ``polyline_pieces``: every point of the polyline (dense samples of each segment) lies within h
  of the midpoint of a piece, and the pieces are no longer than PIECE_REL times the distance to
  the site (or MAX_PIECES per segment).
* ``sites_meeting_discs`` equals the brute-force set {k : |c_k − P_j| − R_k ≤ r_j for some j} on
  random discs over a diagram's adjacency state with sites added and deleted since its k-d tree
  was built (random data: no pair within 1e-6 of the boundary, so the 1e-9 margin changes nothing).
* The containment the insertion's proofs rely on: after inserting circles into a random diagram,
  for points q of the true arc of each new bounded edge (the root of d_i − d_j found by brentq
  across the polyline, an independent computation), the empty circle of q (centre q, radius
  d_i(q)) lies in one of the discs of ``arc_discs`` (the pieces' discs (M, d_i(M) + 2(h + t))).
"""
from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

sys.path.insert(0, str(Path(__file__).with_name("cgal")))
import cgal_peer  # noqa: E402

import curvedvoronoi as cv  # noqa: E402
from curvedvoronoi.runtime.voronoi.adjacency import dynamic_state  # noqa: E402
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry  # noqa: E402
from curvedvoronoi.runtime.voronoi.reach import (  # noqa: E402
    MAX_PIECES, PIECE_REL, arc_discs, polyline_pieces, sites_meeting_discs)


def _circle(cx, cy, r):
    return site_geometry(cv.Circle.from_radius(cx, cy, r))


@pytest.mark.parametrize("seed", range(6))
def test_pieces_cover_the_polyline(seed):
    rng = np.random.default_rng(seed)
    g = _circle(0.0, 0.0, float(rng.uniform(0, 2)))
    P = rng.uniform(-50, 50, (int(rng.integers(2, 8)), 2))
    P = P[np.hypot(*P.T) > g.rho + 0.5]
    if len(P) < 2:
        P = np.array([[10.0, 0.0], [0.0, 30.0]])
    M, h = polyline_pieces(P, g)
    d = np.abs(np.hypot(*P.T) - g.rho)
    count = 0
    for a, b, da, db in zip(P[:-1], P[1:], d[:-1], d[1:]):
        X = a + np.linspace(0, 1, 2001)[:, None] * (b - a)
        gap = (np.hypot(X[:, None, 0] - M[None, :, 0], X[:, None, 1] - M[None, :, 1]) - h[None, :]).min(axis=1)
        assert gap.max() <= 1e-12 * (1 + np.abs(X).max())
        L = float(np.hypot(*(b - a)))
        m = max(1, min(MAX_PIECES, math.ceil(L / (PIECE_REL * min(da, db)))))
        count += m
        assert L / m <= PIECE_REL * min(da, db) * (1 + 1e-12) or m == MAX_PIECES
    assert len(M) == count


def test_one_point_polyline():
    M, h = polyline_pieces([[3.0, 4.0]], _circle(0.0, 0.0, 1.0))
    assert M.tolist() == [[3.0, 4.0]] and h.tolist() == [0.0]


def _diagram(n, seed):
    circles = cgal_peer.random_disjoint_circles(n + 6, seed)
    d = cv.voronoi(circles[:n], certify=False)
    for c in circles[n:]:
        d = d.insert(c, certify=False, inplace=True)
    d = d.delete_site(3, certify=False, renumber="last", inplace=True)
    return d


@pytest.mark.parametrize("seed", range(4))
def test_sites_meeting_discs_is_the_brute_force_set(seed):
    d = _diagram(150, seed)
    dyn = dynamic_state(d)
    assert dyn.extra and (np.asarray(dyn.slot) < 0).any()         # sites added and deleted since the tree
    C = np.array([[float(s.cx), float(s.cy)] for s in d.sites])
    R = np.array([math.sqrt(float(s.r2)) for s in d.sites])
    assert np.allclose(dyn.C[:len(C)], C) and np.allclose(dyn.R[:len(R)], R)
    rng = np.random.default_rng(seed)
    lo, hi = C.min(axis=0), C.max(axis=0)
    for _ in range(20):
        m = int(rng.integers(1, 12))
        P = rng.uniform(lo - 20, hi + 20, (m, 2))
        r = rng.uniform(0, 0.3, m) * float((hi - lo).max())
        gap = np.hypot(C[:, None, 0] - P[None, :, 0], C[:, None, 1] - P[None, :, 1]) - R[:, None] - r[None, :]
        if np.abs(gap).min() < 1e-6:
            continue
        want = sorted(np.nonzero((gap <= 0).any(axis=1))[0].tolist())
        assert sites_meeting_discs(dyn, P, r) == want


def _arc_points(e, gi, gj):
    """Points of the true bisector of circles gi, gj near the polyline of e: d_i − d_j = 0 solved
    by brentq along the normal of each segment at its ends, midpoint and quarter points."""
    P = np.asarray(e.polyline, float)

    def f(q):
        return (math.hypot(q[0] - gi.cx, q[1] - gi.cy) - gi.rho) - (math.hypot(q[0] - gj.cx, q[1] - gj.cy) - gj.rho)

    out = []
    for a, b in zip(P[:-1], P[1:]):
        t = b - a
        L = float(np.hypot(*t))
        if L == 0:
            continue
        nrm = np.array([-t[1], t[0]]) / L
        for s in (0.0, 0.25, 0.5, 0.75, 1.0):
            x = a + s * t
            w = 4 * e.tolerance + 1e-9 * (1 + np.abs(x).sum())
            if f(x - w * nrm) * f(x + w * nrm) > 0:
                continue
            u = brentq(lambda u: f(x + u * nrm), -w, w, xtol=1e-15)
            out.append(x + u * nrm)
    return np.array(out).reshape(-1, 2)


@pytest.mark.parametrize("seed", [1, 2])
def test_empty_circles_of_new_arcs_lie_in_the_piece_discs(seed):
    circles = cgal_peer.random_disjoint_circles(206, seed)
    d = cv.voronoi(circles[:200], certify=False)
    checked = 0
    for c in circles[200:]:
        old = {(tuple(e.sites), tuple(e.ends)) for e in d.edges}
        d = d.insert(c, certify=False, inplace=True)
        G = [site_geometry(s) for s in d.sites]
        for e in d.edges:
            if None in e.ends or (tuple(e.sites), tuple(e.ends)) in old:
                continue
            gi, gj = G[e.sites[0]], G[e.sites[1]]
            M, disc_r = arc_discs(e.polyline, gi, e.tolerance)
            for q in _arc_points(e, gi, gj):
                rq = math.hypot(q[0] - gi.cx, q[1] - gi.cy) - gi.rho
                inside = np.hypot(M[:, 0] - q[0], M[:, 1] - q[1]) + rq <= disc_r * (1 + 1e-12)
                assert inside.any(), (e.sites, q)
                checked += 1
    assert checked > 50


@pytest.mark.parametrize("one_disc", [0, 10 ** 9])
def test_insertions_certified_with_either_reach(monkeypatch, one_disc):
    """Insertions proved against the per-piece discs (``ONE_DISC_SITES = 0``) or the one disc
    (never past the threshold) give the batch build's Delaunay graph, certified, and the
    independent verifier proves the result."""
    from curvedvoronoi.runtime.voronoi import insertion

    monkeypatch.setattr(insertion, "ONE_DISC_SITES", one_disc)
    circles = cgal_peer.random_disjoint_circles(128, 5)
    d = cv.voronoi(circles[:120])
    assert d.certified
    d = d.insert_many(circles[120:])
    assert d.certified, d.problems[:3]
    assert d.delaunay_edges() == cv.voronoi(circles, certify=False).delaunay_edges()
    assert cv.verify(d, circles).ok


def test_proof_sites_hold_every_site_near_the_changed_parts(monkeypatch):
    """The sites handed to the verifier after an insertion (per-piece discs forced) hold every site
    whose disc comes within d(q) + 2t of a point q of a new bounded edge's polyline (t its
    tolerance; within the disc of q's piece) or within r_v of a changed vertex: brute force over
    all sites."""
    from curvedvoronoi.runtime.voronoi import insertion

    monkeypatch.setattr(insertion, "ONE_DISC_SITES", 0)
    seen = []
    real = insertion._prove_among

    def spy(D, dyn, V, pe, near, *a, **k):
        seen.append(([(v.x, v.y, v.radius) for v in V], [(e.polyline, e.tolerance, e.sites) for e in pe],
                     set(near), dyn.C.copy(), dyn.R.copy(), list(dyn.geoms)))
        return real(D, dyn, V, pe, near, *a, **k)

    monkeypatch.setattr(insertion, "_prove_among", spy)
    circles = cgal_peer.random_disjoint_circles(208, 3)
    d = cv.voronoi(circles[:200])
    d.insert_many(circles[200:])
    assert len(seen) >= 5
    for V, E, near, C, R, G in seen:
        want = set()
        for x, y, r in V:
            want |= set(np.nonzero(np.hypot(C[:, 0] - x, C[:, 1] - y) - R <= r * (1 - 1e-9))[0].tolist())
        for P, t, (i, _) in E:
            P = np.asarray(P, float)
            dq = np.abs(np.hypot(P[:, 0] - G[i].cx, P[:, 1] - G[i].cy) - G[i].rho)
            gap = np.hypot(C[:, None, 0] - P[None, :, 0], C[:, None, 1] - P[None, :, 1]) - R[:, None]
            want |= set(np.nonzero((gap <= (dq + 2 * t)[None, :] * (1 - 1e-9)).any(axis=1))[0].tolist())
        assert want <= near, sorted(want - near)
