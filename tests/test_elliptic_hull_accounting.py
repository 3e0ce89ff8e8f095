"""The unbounded ends of a diagram with elliptic pieces outside the point sites' hull
(runtime.segments.certificate_ellipse_hull; thesis Prop. 1.2.1 — an edge ends at a vertex or at
infinity — and §2.2, the pieces of a conic as sites).

Far away in a direction u the nearest sites are those of largest support h(u) = max over the site
of u·x, so the diagram's unbounded edges go out at the directions where the site of largest
support changes, between the two sites that change there.  The reference below computes that
in numpy alone: the supports of the points, and of each open piece by dense sampling of its
interior, over 8192 directions; each change of the winner is an unbounded end (its pair, a
direction within two sampling steps, and for a common tangent the side: the sign of
(z_j − z_i) × u with z the sampled contacts).  The certificate's list must agree with it exactly
in its pairs (with multiplicity) and within the sampling in its directions.  The configurations:
the two scenes of bench/bench_elliptic_ring.py (seed 1, scenes 5 and 8) whose pieces poke out of
the points' hull, and random arcs of a rotated ellipse among integer points.

The scenes' documents: their unbounded edges (proved one by one by the tail proofs of
runtime.segments.certificate_ellipse_tails) must be accounted for exactly (step 5), and a document
with one of them removed or duplicated must be refused there.  (Slow: the whole certificate
accepts both scenes.)
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import curvedvoronoi as cv
from curvedvoronoi.runtime.certify.foot import working_prec
from curvedvoronoi.runtime.segments.certificate import _accounting, verify_segments
from curvedvoronoi.runtime.segments.certificate_edges import EdgeProof
from curvedvoronoi.runtime.segments.certificate_ellipse_edges import prove_edges_with_pieces
from curvedvoronoi.runtime.segments.certificate_ellipse_hull import frame_infinite_ends
from curvedvoronoi.runtime.segments.certificate_ellipse_sites import pieces_inside_hull
from curvedvoronoi.runtime.segments.certificate_sites import SiteTable
from curvedvoronoi.runtime.segments.certificate_vertices import prove_vertices
from curvedvoronoi.runtime.voronoi.structure import Diagram

#: bench/bench_elliptic_ring.py seed 1: (arc parameters, integer points) of scenes 5 and 8
SCENES = {5: ((1.54, 3.58), [(4, 1), (2, 4), (1, 3), (-2, 4), (-3, 3), (-1, -3), (2, -4)]),
          8: ((1.97, 3.62), [(-4, -3), (-1, -3), (0, -4), (1, -4), (4, -2)])}

N_DIR = 8192
N_SAMPLE = 2000


def elementary(arc, pts) -> list:
    """The arc's ends (point sites), the points and the arc's pieces."""
    ends = [arc.a, arc.b]
    return [cv.Point(*q) for q in ends] + [cv.Point(*q) for q in pts if q not in ends] + arc.pieces()


def reference(sites) -> list:
    """(sorted pair, angle of the direction, side) of each change of the site of largest support,
    numpy only: a point's support u·p, an open piece's by its sampled interior points.  ``side``:
    the sign of (z_j − z_i) × u for the pair (i, j), z the contacts."""
    th = (np.arange(N_DIR) + 0.5) * 2 * math.pi / N_DIR
    U = np.stack([np.cos(th), np.sin(th)], axis=1)
    H, Z = [], []
    for s in sites:
        if hasattr(s, "ua"):
            c, M, N = (np.array([float(v) for v in w]) for w in (s.c, s.M, s.N))
            f0 = math.atan2(float(s.ua[1]), float(s.ua[0]))
            f1 = f0 + ((math.atan2(float(s.ub[1]), float(s.ub[0])) - f0) % (2 * math.pi))
            f = f0 + (f1 - f0) * np.arange(1, N_SAMPLE) / N_SAMPLE
            P = c + np.cos(f)[:, None] * M + np.sin(f)[:, None] * N
            V = U @ P.T
            idx = np.argmax(V, axis=1)
            H.append(V[np.arange(N_DIR), idx])
            Z.append(P[idx])
        else:
            p = np.array([float(s.x), float(s.y)])
            H.append(U @ p)
            Z.append(np.broadcast_to(p, (N_DIR, 2)))
    win = np.argmax(np.array(H), axis=0)
    out = []
    for t in range(N_DIR):
        a, b = int(win[t - 1]), int(win[t])
        if a != b:
            i, j = sorted((a, b))
            d = Z[j][t] - Z[i][t]
            u = U[t]
            out.append(((i, j), th[t] - math.pi / N_DIR, int(np.sign(d[0] * u[1] - d[1] * u[0]))))
    return out



def check_against_reference(sites, ends) -> None:
    ref = reference(sites)
    assert sorted(p for p, _ in ends) == sorted(p for p, _, _ in ref)
    left = list(ref)
    step = 2 * math.pi / N_DIR
    for pair, key in ends:
        match = None
        for r in left:
            if r[0] != pair:
                continue
            if key[0] == "tangent":
                if key[1] == r[2]:
                    match = r
                    break
            else:
                gap = (math.atan2(float(key[1]), float(key[0])) - r[1] + math.pi) % (2 * math.pi) - math.pi
                if abs(gap) <= 2 * step:
                    match = r
                    break
        assert match is not None, (pair, key, ref)
        left.remove(match)


@pytest.mark.parametrize("scene", sorted(SCENES))
def test_the_scenes_unbounded_ends_against_the_support_functions(scene):
    (a0, a1), pts = SCENES[scene]
    sites = elementary(cv.Arc.elliptic((0, 0), (2, 0), "1/2", a0, a1), pts)
    T = SiteTable(sites)
    assert pieces_inside_hull(T) is not None          # a piece pokes out of the points' hull
    ends = frame_infinite_ends(T)
    assert not isinstance(ends, str), ends
    assert any(key[0] == "tangent" for _, key in ends)
    check_against_reference(sites, ends)


def random_configurations(count: int):
    rng = np.random.default_rng(20261129)
    for _ in range(count):
        a0 = round(float(rng.uniform(0, 6.28)), 2)
        a1 = round(a0 + float(rng.uniform(1.0, 3.0)), 2)
        arc = cv.Arc.elliptic((1, -1), (3, 4), "2/5", a0, a1)    # |M| = 5, rotated by atan(4/3)
        pts = []
        for t in np.sort(rng.uniform(0, 2 * math.pi, int(rng.integers(4, 8)))):
            r = float(rng.uniform(4.0, 6.5))
            p = (1 + int(round(r * math.cos(t))), -1 + int(round(r * math.sin(t))))
            if p not in pts:
                pts.append(p)
        yield elementary(arc, pts)


def test_random_arcs_of_a_rotated_ellipse_against_the_support_functions():
    decided = outside = 0
    for sites in random_configurations(8):
        T = SiteTable(sites)
        ends = frame_infinite_ends(T)
        if isinstance(ends, str):                     # refusing is allowed, never a wrong list
            continue
        decided += 1
        outside += pieces_inside_hull(T) is not None
        check_against_reference(sites, ends)
    assert decided >= 6 and outside >= 3, (decided, outside)


def unbounded_proofs(scene):
    """The scene's document reduced to its unbounded edges, each proved (vertices and tails)."""
    (a0, a1), pts = SCENES[scene]
    D = cv.voronoi([cv.Arc.elliptic((0, 0), (2, 0), "1/2", a0, a1)] + pts, certify=False)
    J = D.to_json()
    J["edges"] = [e for e in J["edges"] if None in e["ends"]]
    D = Diagram.from_json(J)
    T = SiteTable(D.sites)
    vp = prove_vertices(D, T, [])
    ep = prove_edges_with_pieces(D, T, vp, [])
    assert all(p.ok for p in ep)
    return T, list(zip(D.edges, ep))


def account(expected, edges_proofs):
    problems = []
    ok = _accounting(expected, [e for e, _ in edges_proofs], [p for _, p in edges_proofs], problems)
    return ok, problems


@pytest.mark.parametrize("scene", sorted(SCENES))
def test_the_documents_unbounded_edges_are_accounted_for_and_corruptions_refused(scene):
    with working_prec(128):
        T, ep = unbounded_proofs(scene)
        expected = frame_infinite_ends(T)
        assert account(expected, ep) == (True, [])
        t = next(n for n, (_, p) in enumerate(ep) if any(k[0] == "tangent" for _, k in p.infinite))
        for corrupt in (ep[:t] + ep[t + 1:], ep + [ep[t]], ep[1:], ep + [ep[0]]):
            ok, problems = account(expected, corrupt)
            assert not ok and problems and all(p.kind == "infinity" and p.fault for p in problems)
        # an unbounded edge left unproved names no end: refused, its missing end a limit
        ok, problems = account(expected, ep[:t] + [(ep[t][0], EdgeProof(False))] + ep[t + 1:])
        assert not ok and problems and not any(p.fault for p in problems)


@pytest.mark.slow
@pytest.mark.parametrize("scene", sorted(SCENES))
def test_the_scenes_are_certified_whole(scene):
    """The whole certificate (every edge, vertex and step 5 by the ellipse's frame) accepts the
    scenes' documents (about 15 s CPU each)."""
    (a0, a1), pts = SCENES[scene]
    D = cv.voronoi([cv.Arc.elliptic((0, 0), (2, 0), "1/2", a0, a1)] + pts, certify=False)
    C = verify_segments(D)
    assert C.ok, [str(p) for p in C.problems]
