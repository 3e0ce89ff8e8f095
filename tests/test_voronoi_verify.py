"""The diagram verifier (runtime.voronoi.verify.certificate): it proves correct diagrams and REJECTS corrupted ones.

References independent of the verifier and of the construction:
* points and equal-radius circles: qhull's Voronoi diagram of the centres (scipy.spatial.Voronoi);
  equal radii shift every distance by the same amount, so the diagram is that of the centres;
* unequal circles: brute force over all triples with the exact Apollonius solver of thesis §3.1.3
  and the exact conflict test (runtime.predicates.circles.decide_conflict).
Each corruption (an edge removed, a vertex moved by 1e-6, two edges' site pairs swapped, a site
the diagram ignores, a shifted polyline) must give ok=False with a problem naming the part.
"""
from __future__ import annotations

import copy
import itertools
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.spatial import Voronoi

from curvedvoronoi.runtime.predicates.circles import Circle, Point, decide_conflict, voronoi_vertices_circles
from curvedvoronoi.runtime.voronoi.structure import Diagram, DiagramEdge, DiagramVertex
from curvedvoronoi.runtime.voronoi.verify.certificate import verify

sys.path.insert(0, str(Path(__file__).parent))
from scenes import random_disjoint_circles, random_ellipses  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


# ----------------------------------------------------------------------------- references

def qhull_diagram(P, rho=0.0, far=50.0):
    """The Voronoi diagram of points P (or of equal circles of radius rho centred at P) from qhull,
    in the curvedvoronoi.diagram/1 structure."""
    P = np.asarray(P, float)
    sites = [Point(float(x), float(y)) if rho == 0 else Circle.from_radius(float(x), float(y), rho) for x, y in P]
    vor = Voronoi(P)
    trip = {}
    for (p, q), rv in zip(vor.ridge_points, vor.ridge_vertices):
        for v in rv:
            if v >= 0:
                trip.setdefault(v, set()).update((int(p), int(q)))
    verts = []
    for v, s in sorted(trip.items()):
        assert len(s) == 3, "degenerate test input"
        x, y = vor.vertices[v]
        verts.append(DiagramVertex(int(v), tuple(sorted(s)), float(x), float(y),
                                   float(np.hypot(*(vor.vertices[v] - P[min(s)]))) - rho, True))
    centre = P.mean(axis=0)
    edges = []
    for eid, ((p, q), rv) in enumerate(zip(vor.ridge_points, vor.ridge_vertices)):
        p, q = int(p), int(q)
        i, j = min(p, q), max(p, q)
        if min(rv) >= 0:
            poly = vor.vertices[rv]
            ends = (int(rv[0]), int(rv[1]))
        else:
            v = [x for x in rv if x >= 0][0]
            t = P[q] - P[p]
            t /= np.linalg.norm(t)
            n = np.array([-t[1], t[0]])
            mid = P[[p, q]].mean(axis=0)
            d = np.sign(np.dot(mid - centre, n)) * n
            poly = np.array([vor.vertices[v], vor.vertices[v] + far * d])
            ends = (int(v), None)
        edges.append(DiagramEdge(eid, (i, j), ends, False, poly, 1e-12, True))
    return Diagram(sites, verts, edges)


def random_points(rng, n, box=10.0):
    return rng.uniform(0, box, (n, 2))


def exact_vertex_triples(circles):
    """Brute force (independent of the verifier): the triples of all true Voronoi vertices."""
    cs = [Circle.from_radius(*c) for c in circles]
    out = []
    for t in itertools.combinations(range(len(cs)), 3):
        tv = voronoi_vertices_circles(*(cs[i] for i in t))
        for w in tv.vertices:
            if all(not decide_conflict(tv, w, cs[k]).in_conflict and not decide_conflict(tv, w, cs[k]).tangent
                   for k in range(len(cs)) if k not in t):
                out.append(t)
    return sorted(out)


def construct(sites):
    from curvedvoronoi.runtime.voronoi.construction import voronoi

    return voronoi(sites, certify=False)


# ----------------------------------------------------------------------------- correct diagrams

def test_three_circles_by_hand_and_json_roundtrip():
    D = construct([(0, 0, 1), (4, 0, 1), (2, 4, 1)])
    cert = verify(D)
    assert cert.ok and cert.complete, cert.problems
    assert cert.delaunay_edges == [(0, 1), (0, 2), (1, 2)]
    assert verify(json.loads(json.dumps(D.to_json()))).ok


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_points_qhull_reference_is_proved(seed):
    D = qhull_diagram(random_points(np.random.default_rng(seed), 40))
    cert = verify(D)
    assert cert.ok, cert.problems[:5]
    assert all(cert.vertices) and all(cert.edges)


def test_equal_circles_qhull_reference_is_proved():
    C = np.array([c[:2] for c in random_disjoint_circles(30, 11, rmin=0.5, rmax=0.5, gap=0.2, side=30)])
    cert = verify(qhull_diagram(C, rho=0.5))
    assert cert.ok, cert.problems[:5]


@pytest.mark.parametrize("seed", [0, 3])
def test_unequal_circles_match_the_exact_brute_force(seed):
    circles = random_disjoint_circles(7, seed, rmin=0.2, rmax=1.5, gap=0.1, side=12)
    D = construct(circles)
    cert = verify(D)
    assert cert.ok, cert.problems
    assert sorted(tuple(sorted(v.sites)) for v in D.vertices) == exact_vertex_triples(circles)


def test_nested_sites_closed_edge_is_proved():
    D = construct([(0, 0, 10), (3, 1, 1), (-4, 2, 0.5), (20, 0, 1), (0, 20, 2)])
    cert = verify(D)
    assert cert.ok, cert.problems
    D2 = construct([(0, 0, 10), (1, 1, 1)])           # one nested site: a closed vertex-less edge
    assert D2.edges[0].closed and verify(D2).ok
    bad = copy.deepcopy(D2)
    bad.edges = []
    cert = verify(bad)
    assert not cert.ok and any("site 0 has no edge" in p or "site 1 has no edge" in p for p in cert.problems)


def test_two_sites_single_edge_is_proved():
    D = construct([(0, 0, 1), (5, 1, 2)])
    assert verify(D).ok


# ----------------------------------------------------------------------------- corruptions

@pytest.fixture(scope="module")
def circle_diagram():
    return construct(random_disjoint_circles(20, 4, rmin=0.2, rmax=1.5, gap=0.1, side=30))


@pytest.fixture(scope="module")
def point_diagram():
    return qhull_diagram(random_points(np.random.default_rng(21), 30))


@pytest.fixture(params=["circles", "points"])
def base(request, circle_diagram, point_diagram):
    D = circle_diagram if request.param == "circles" else point_diagram
    assert verify(D).ok
    return copy.deepcopy(D)


def test_removed_edge_is_rejected(base):
    e = next(e for e in base.edges if None not in e.ends)
    base.edges.remove(e)
    cert = verify(base)
    assert not cert.ok
    pair = f"({e.sites[0]}, {e.sites[1]})"
    assert any(f"vertex {e.ends[0]} " in p and pair in p for p in cert.problems), cert.problems


def test_moved_vertex_is_rejected(base):
    v = base.vertices[len(base.vertices) // 2]
    v.x += 1e-6
    cert = verify(base)
    assert not cert.ok and not cert.vertices[len(base.vertices) // 2]
    assert any(p.startswith(f"vertex {v.id} ") for p in cert.problems), cert.problems


def test_swapped_site_pairs_are_rejected(base):
    a, b = [e for e in base.edges if None not in e.ends and e.sites != base.edges[0].sites][:2]
    a.sites, b.sites = b.sites, a.sites
    cert = verify(base)
    assert not cert.ok
    assert any(p.startswith(f"edge {a.id} ") for p in cert.problems)
    assert any(p.startswith(f"edge {b.id} ") for p in cert.problems)


def test_ignored_site_inside_is_rejected(base):
    v = base.vertices[0]
    extra = Point(v.x + 0.01 * v.radius, v.y)                # inside the empty circle of vertex 0
    sites = list(base.sites) + [extra]
    cert = verify(base, sites)
    n = len(base.sites)
    assert not cert.ok
    assert any(f"site {n}" in p for p in cert.problems), cert.problems
    base.sites = sites                                       # also when the diagram lists it
    cert = verify(base)
    assert not cert.ok and any(f"site {n} has no edge" in p for p in cert.problems)


def test_ignored_site_far_away_is_rejected(base):
    far = Point(1e4, -3e4)           # no vertex is affected: only the unbounded edges and the accounting
    base.sites = list(base.sites) + [far]
    cert = verify(base)
    assert not cert.ok
    assert any(f"site {len(base.sites) - 1}" in p for p in cert.problems)


def test_shifted_polyline_is_rejected(base):
    e = next(e for e in base.edges if len(e.polyline) >= 2 and None not in e.ends)
    P = np.array(e.polyline, float)
    if len(P) == 2:                                           # give it an interior point
        P = np.array([P[0], 0.5 * (P[0] + P[1]), P[1]])
    t = P[-1] - P[0]
    n = np.array([-t[1], t[0]]) / np.hypot(*t)
    P[1:-1] += (1e-3 + 4 * e.tolerance) * n                  # beyond its stated tolerance
    e.polyline = P
    cert = verify(base)
    assert not cert.ok and any(p.startswith(f"edge {e.id} ") for p in cert.problems), cert.problems


def test_wrong_unbounded_direction_is_rejected(point_diagram):
    D = copy.deepcopy(point_diagram)
    e = next(e for e in D.edges if e.ends[1] is None)
    P = np.array(e.polyline, float)
    P[-1] = P[0] - (P[-1] - P[0])                             # points the wrong way to infinity
    e.polyline = P
    cert = verify(D)
    assert not cert.ok and any(p.startswith(f"edge {e.id} ") for p in cert.problems)


@settings(max_examples=15)
@given(st.integers(0, 10 ** 6), st.integers(0, 10 ** 6), st.sampled_from([1e-7, 1e-5, 1e-3]))
def test_random_points_proved_and_random_vertex_move_rejected(seed, which, delta):
    rng = np.random.default_rng(seed)
    D = qhull_diagram(random_points(rng, 12))
    assert verify(D).ok
    v = D.vertices[which % len(D.vertices)]
    ang = rng.uniform(0, 2 * np.pi)
    v.x += delta * 10 * np.cos(ang)
    v.y += delta * 10 * np.sin(ang)
    assert not verify(D).ok


# ----------------------------------------------------------------------------- command line

def test_cli_verify_exit_codes(tmp_path, point_diagram):
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    good = tmp_path / "good.json"
    good.write_text(json.dumps(point_diagram.to_json()))
    bad_doc = point_diagram.to_json()
    bad_doc["vertices"][0]["x"] += 1e-6
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(bad_doc))
    junk = tmp_path / "junk.json"
    junk.write_text("{not json")

    def run(*a):
        return subprocess.run([sys.executable, "-m", "curvedvoronoi", "verify", "-v", *a], cwd=ROOT, env=env,
                              capture_output=True, text=True, timeout=300)

    r = run(str(good))
    assert r.returncode == 0 and json.loads(r.stdout)["ok"] is True
    r = run(str(bad))
    assert r.returncode == 1 and json.loads(r.stdout)["ok"] is False
    assert run(str(junk)).returncode == 2


# ----------------------------------------------------------------------------- ellipses

@pytest.fixture(scope="module")
def ellipse_diagram():
    from curvedvoronoi.runtime.sites.conic import Conic

    sites = [Conic.ellipse(centre=(0, 0), axes=(3, 1), rotation=(1, 0)),
             Conic.ellipse(centre=(10, 1), axes=(2, 1), rotation=("3/5", "4/5")),
             Conic.ellipse(centre=(4, 8), axes=(3, 2), rotation=(1, 0)), (15, 9, 1)]
    return construct(sites)


def test_ellipse_edges_proved_and_corruptions_rejected(ellipse_diagram):
    D = copy.deepcopy(ellipse_diagram)
    cert = verify(D)
    assert all(cert.vertices)
    bounded = [t for t, e in enumerate(D.edges) if None not in e.ends]
    assert bounded and all(cert.edges[t] for t in bounded), cert.problems
    # unbounded edges proved to infinity (support functions), ends at infinity accounted for
    assert cert.ok and cert.complete, cert.problems
    e = D.edges[bounded[0]]
    P = np.array(e.polyline, float)
    t = P[-1] - P[0]
    n = np.array([-t[1], t[0]]) / np.hypot(*t)
    P[1:-1] += (1e-3 + 4 * e.tolerance) * n
    e.polyline = P
    cert = verify(D)
    assert not cert.edges[bounded[0]] and any(p.startswith(f"edge {e.id} ") for p in cert.problems)
    D = copy.deepcopy(ellipse_diagram)
    D.vertices[0].x += 1e-6
    cert = verify(D)
    assert not cert.vertices[0] and any(p.startswith(f"vertex {D.vertices[0].id} ") for p in cert.problems)


def test_duplicated_edge_and_fake_vertex_are_rejected(point_diagram):
    D = copy.deepcopy(point_diagram)
    e = copy.deepcopy(next(e for e in D.edges if None not in e.ends))
    e.id = 10 ** 6
    D.edges.append(e)
    cert = verify(D)
    assert not cert.ok and any(f"2 edges ({e.sites[0]}, {e.sites[1]})" in p for p in cert.problems), cert.problems
    D = copy.deepcopy(point_diagram)
    v = D.vertices[0]
    D.vertices.append(DiagramVertex(10 ** 6, v.sites, v.x + 1.0, v.y, v.radius, True))
    cert = verify(D)
    assert not cert.ok and not cert.vertices[-1]
    assert any(p.startswith(f"vertex {10 ** 6} ") for p in cert.problems)


# ----------------------------------------------------------------------------- ellipse diagrams, completeness

@pytest.fixture(scope="module", params=[(13, 8), (19, 6)])
def random_ellipse_diagram(request):
    seed, n = request.param
    return construct(random_ellipses(n, seed))


def test_random_ellipse_diagram_is_certified_and_matches_dense_sampling(random_ellipse_diagram):
    from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry

    D = random_ellipse_diagram
    cert = verify(D)
    assert cert.ok and cert.complete, cert.problems
    assert any(None in e.ends for e in D.edges)
    # independent reference: nearest sites on a dense grid (float distances); every pair of grid
    # neighbours with different nearest sites, away from ties, is a Delaunay edge
    G = [site_geometry(s) for s in D.sites]
    xs = np.linspace(-120, 120, 241)
    X, Y = np.meshgrid(xs, xs)
    Q = np.column_stack([X.ravel(), Y.ravel()])
    d = np.array([g.distance(Q) for g in G])
    lab = d.argmin(0).reshape(X.shape)
    pairs = set()
    for A, B in ((lab[:, :-1], lab[:, 1:]), (lab[:-1, :], lab[1:, :])):
        for a, b in zip(A[A != B], B[A != B]):
            pairs.add((min(int(a), int(b)), max(int(a), int(b))))
    assert pairs and pairs <= set(cert.delaunay_edges), pairs - set(cert.delaunay_edges)
    # far away in direction θ the nearest site maximises the support function: the sites seen on a
    # large circle are exactly the sites of the unbounded edges
    th = np.linspace(0, 2 * np.pi, 3600, endpoint=False)
    far = 1e6 * np.column_stack([np.cos(th), np.sin(th)])
    seen = set(np.array([g.distance(far) for g in G]).argmin(0).tolist())
    assert seen == {int(s) for e in D.edges if None in e.ends for s in e.sites}


def _ends_at_infinity(D):
    from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
    from curvedvoronoi.runtime.voronoi.verify.edge_checks import check_edges
    from curvedvoronoi.runtime.voronoi.verify.vertices import prove_vertices

    geoms = [site_geometry(s) for s in D.sites]
    problems: list = []
    vinfo, vok = prove_vertices(D, list(D.sites), geoms, None, problems)
    eok, ends, _ = check_edges(D, geoms, None, vinfo, vok, problems, {})
    assert all(eok) and not problems, problems
    return geoms, ends


def test_ellipse_accounting_rejects_wrong_order_and_missing_end(random_ellipse_diagram):
    from curvedvoronoi.runtime.voronoi.verify.closure import verify_accounting_conics
    from curvedvoronoi.runtime.voronoi.verify.support import SupportTable

    D = random_ellipse_diagram
    geoms, ends = _ends_at_infinity(D)
    sup = SupportTable(geoms)
    n = len(geoms)
    assert len(ends) >= 3
    probs: list = []
    assert verify_accounting_conics(n, sup, ends, probs), probs
    order = sorted(range(len(ends)), key=lambda t: ends[t][0])
    # wrong asymptotic order: two consecutive ends exchange their site pairs
    for a in range(len(order)):
        bad = list(ends)
        p, q = order[a], order[(a + 1) % len(order)]
        bad[p] = (ends[p][0], ends[q][1], ends[p][2], ends[p][3])
        bad[q] = (ends[q][0], ends[p][1], ends[q][2], ends[q][3])
        probs = []
        assert not verify_accounting_conics(n, sup, bad, probs)
        assert any("unbounded edge" in m for m in probs), probs
    # an unbounded end missing
    named = 0
    for a in range(len(ends)):
        probs = []
        assert not verify_accounting_conics(n, sup, ends[:a] + ends[a + 1:], probs)
        assert any("at infinity" in m or "far directions" in m for m in probs), probs
        # the same gap, where the diagram has that edge but its end was not proved: the edge is named
        probs = []
        assert not verify_accounting_conics(n, sup, ends[:a] + ends[a + 1:], probs, unproved_ends=[ends[a][3]])
        gap = [m for m in probs if "share no site" in m]
        assert all(f"is not proved (unbounded edge {ends[a][3]})" in m for m in gap), gap
        named += bool(gap)
    assert named


def test_ellipse_diagram_with_removed_unbounded_edge_is_rejected(random_ellipse_diagram):
    D = copy.deepcopy(random_ellipse_diagram)
    e = next(e for e in D.edges if None in e.ends)
    D.edges.remove(e)
    cert = verify(D)
    assert not cert.ok and not cert.complete
    assert any("at infinity" in p or "far directions" in p for p in cert.problems), cert.problems


def test_ellipse_tail_rejects_a_far_site_on_the_asymptote(random_ellipse_diagram):
    from curvedvoronoi.runtime.predicates.circles import Point

    D = copy.deepcopy(random_ellipse_diagram)
    e = next(e for e in D.edges if e.ends[1] is None)
    P = np.array(e.polyline, float)
    u = (P[-1] - P[-2]) / np.hypot(*(P[-1] - P[-2]))
    far = P[-1] + 5.0 * np.hypot(*P[-1]) * u          # beyond every polyline: only the tail sees it
    D.sites = list(D.sites) + [Point(float(far[0]), float(far[1]))]
    cert = verify(D)
    assert not cert.ok
    assert any(p.startswith(f"edge {e.id} ") and "not proved beyond" in p for p in cert.problems), cert.problems


@pytest.mark.parametrize("yk, proved", [(-1.0, False), (-200.0, True)])
def test_tail_third_site_closer_on_a_middle_stretch(yk, proved):
    """Sites i = (−100, 0), j = (100, 0), k = (0, yk): on the bisector x = 0,
    d_i − d_k = √(10⁴ + y²) − (y − yk) ≈ 5000/y + yk, so for yk = −1 the site k is closer for
    y < ~5000 (a vertex (i, j, k) at y ≈ 5000), while k never leads at infinity
    (h_k(π/2) = yk < 0 = h_i).  The tail beyond y = 1000 must be rejected; for yk = −200 it is
    the true edge (k farther for y > 25) and must be proved."""
    from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
    from curvedvoronoi.runtime.voronoi.verify.site_table import SiteTable
    from curvedvoronoi.runtime.voronoi.verify.support import SupportTable
    from curvedvoronoi.runtime.voronoi.verify.tail import prove_tail

    geoms = [site_geometry(s) for s in (Point(-100, 0), Point(100, 0), Point(0, yk))]
    y_vertex = (1e4 - yk * yk) / (-2 * yk)            # d_i = d_k on x = 0
    assert (y_vertex > 1000) != proved
    link = (np.array([0.0, 1000.0]), np.array([0.0, 1.0]), np.array([-1.0, 0.0]), 10.0, 1.0, 5.0)
    ok, msg, J = prove_tail(SupportTable(geoms), SiteTable(geoms, 1000.0), (0, 1), link, 1000.0)
    assert ok == proved, msg
    if proved:
        assert J[0] < np.pi / 2 < J[1]


# ----------------------------------------------------------------------------- batched bounds and strips

def test_site_table_bounds_contain_the_sampled_distance():
    """The verifier's multi-site table (runtime.voronoi.verify.site_table) against dense sampling of
    the curves: lo ≤ d ≤ hi at points outside, inside (deferred to the site's own bounds), on the
    axes and far away; its float foot points lie on the curves."""
    from curvedvoronoi.runtime.sites.conic import Conic
    from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
    from curvedvoronoi.runtime.voronoi.verify.site_table import SiteTable

    sites = [Conic.ellipse(centre=(1, 2), axes=(3, 1), rotation=("3/5", "4/5")),
             Conic.ellipse(centre=(-6, 0), axes=(2, "3/2"), rotation=(1, 0)),
             Circle.from_radius(5, -5, 2), Point(-3, 7)]
    G = [site_geometry(s) for s in sites]
    table = SiteTable(G, 20.0)
    rng = np.random.default_rng(7)
    Q = np.vstack([rng.uniform(-12, 12, (150, 2)), rng.uniform(-500, 500, (20, 2)),
                   [[1, 2], [-6, 0], [-6, 1.0], [-9, 0], [5, -5], [-3, 7]]])
    for k, g in enumerate(G):
        V = table.evaluate(Q, np.full(len(Q), k))
        assert np.all(V.lo <= V.hi)
        if g.kind == "ellipse":
            t = np.linspace(0, 2 * np.pi, 200001)
            X, Y = g.a * np.cos(t), g.b * np.sin(t)
            C = np.column_stack([g.tx + g.c * X - g.s * Y, g.ty + g.s * X + g.c * Y])
            d = np.array([np.hypot(*(C - q).T).min() for q in Q])     # ≥ the distance
            h = g.a * (t[1] - t[0])                                    # sample spacing on the curve
            err = np.where(d > h, h * h / 4 * (1 / np.maximum(d, h) + g.a / g.b ** 2), h) + 1e-12
            assert np.all(V.lo <= d + 1e-12) and np.all(V.hi >= d - err)
            assert np.all(np.abs(g.distance(V.F)) < 1e-9)             # feet on the curve
        else:
            ref_lo, ref_hi = g.distance_bounds(Q)
            assert np.all(V.lo <= ref_hi) and np.all(V.hi >= ref_lo)


@pytest.mark.parametrize("margin", [0.5, 1e-4])
def test_ellipse_edge_with_a_closer_ignored_site_is_rejected(random_ellipse_diagram, margin):
    """A point site at d_i − margin·d_i from the middle of a bounded edge (so closer to that point
    than its two sites, however slightly) must make the edge fail: the third-site bounds of the
    strips, first-order ones included, may not accept it."""
    from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry

    D = copy.deepcopy(random_ellipse_diagram)
    geoms = [site_geometry(s) for s in D.sites]
    # the longest bounded edge whose probe point stays clear of every site (the probe must be a
    # valid, disjoint point site)
    for e in sorted((e for e in D.edges if None not in e.ends), key=lambda e: -len(e.polyline)):
        P = np.array(e.polyline, float)
        mid = P[len(P) // 2]
        gi = geoms[e.sites[0]]
        di = float(gi.distance(mid[None, :])[0])
        t = P[len(P) // 2 + 1] - P[len(P) // 2 - 1]
        n = np.array([-t[1], t[0]]) / np.hypot(*t)     # across the edge: away from both sites' feet
        Fi, _ = gi.foot_points(mid[None, :])
        if np.dot(n, mid - Fi[0]) < 0:
            n = -n
        q = mid + (1 - margin) * di * n
        if all(g.distance(q[None, :])[0] >= 0.1 * di * margin for g in geoms):
            break
    else:
        raise AssertionError("no bounded edge admits a probe point clear of the sites")
    D.sites = list(D.sites) + [Point(float(q[0]), float(q[1]))]
    cert = verify(D)
    assert not cert.ok
    assert not cert.edges[D.edges.index(e)], cert.problems


def test_ellipse_diagram_corruptions_are_rejected(random_ellipse_diagram):
    """Perturbed vertex, dropped edge, swapped site pairs of two bounded edges: each must fail."""
    D0 = random_ellipse_diagram
    bounded = [t for t, e in enumerate(D0.edges) if None not in e.ends]
    assert len(bounded) >= 2
    D = copy.deepcopy(D0)
    D.vertices[-1].y -= 1e-7
    cert = verify(D)
    assert not cert.ok and not cert.vertices[-1], cert.problems
    D = copy.deepcopy(D0)
    e = D.edges.pop(bounded[0])
    cert = verify(D)
    assert not cert.ok and any(f"vertex {e.ends[0]} " in p for p in cert.problems), cert.problems
    D = copy.deepcopy(D0)
    a = D.edges[bounded[0]]
    b = next(D.edges[t] for t in bounded[1:] if D.edges[t].sites != a.sites)
    a.sites, b.sites = b.sites, a.sites
    cert = verify(D)
    assert not cert.ok
    assert not cert.edges[D.edges.index(a)] and not cert.edges[D.edges.index(b)], cert.problems


# ----------------------------------------------------------------------------- vertex-less edges of conic sites

def _row_of_ellipses(n):
    from curvedvoronoi.runtime.sites.conic import Conic

    base = [Conic.ellipse(centre=(0, 0), axes=(3, 1), rotation=(1, 0)),
            Conic.ellipse(centre=(10, 1), axes=(2, 1), rotation=("3/5", "4/5")),
            Conic.ellipse(centre=(20, 3), axes=(2, 1), rotation=(1, 0))]
    return base[:n]


@pytest.mark.parametrize("n", [2, 3])
def test_vertexless_ellipse_edges_are_proved_and_match_dense_sampling(n):
    """Two or three ellipses in a row: the diagram has no vertex, each edge is a whole bisector,
    infinite both ways (chain of strips + two tails).  Reference: nearest sites on a dense grid."""
    from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry

    D = construct(_row_of_ellipses(n))
    assert not D.vertices and all(e.ends == (None, None) for e in D.edges)
    cert = verify(D)
    assert cert.ok and cert.complete, cert.problems
    G = [site_geometry(s) for s in D.sites]
    xs = np.linspace(-300, 300, 301)
    X, Y = np.meshgrid(xs, xs)
    lab = np.array([g.distance(np.column_stack([X.ravel(), Y.ravel()])) for g in G]).argmin(0).reshape(X.shape)
    pairs = {(min(int(a), int(b)), max(int(a), int(b)))
             for A, B in ((lab[:, :-1], lab[:, 1:]), (lab[:-1, :], lab[1:, :])) for a, b in zip(A[A != B], B[A != B])}
    assert pairs == set(cert.delaunay_edges) == {(k, k + 1) for k in range(n - 1)}


def test_vertexless_ellipse_edge_corruptions_are_rejected():
    D0 = construct(_row_of_ellipses(3))
    D = copy.deepcopy(D0)
    D.edges.pop(0)                                             # a missing vertex-less edge
    cert = verify(D)
    assert not cert.ok and not cert.complete, cert.problems
    D = copy.deepcopy(D0)
    D.edges[0].sites = (0, 2)                                  # the wrong pair
    cert = verify(D)
    assert not cert.ok and not cert.edges[0], cert.problems
    D = copy.deepcopy(D0)                                      # a site the diagram ignores, on an edge
    P = np.array(D.edges[1].polyline, float)
    mid = P[np.argmin(np.hypot(P[:, 0] - 15, P[:, 1] - 2))]
    D.sites = list(D.sites) + [Point(float(mid[0]), float(mid[1]))]
    cert = verify(D)
    assert not cert.ok and not cert.edges[1], cert.problems


# ----------------------------------------------------------------------------- a parabola site

def _parabola_scene():
    from curvedvoronoi.runtime.sites.conic import Conic

    return [Conic.parabola(vertex=(0, -6), p=1, rotation=(0, -1)),
            Conic.ellipse(centre=(0, 4), axes=(2, 1), rotation=(1, 0)),
            Conic.ellipse(centre=(7, 5), axes=(2, 1), rotation=("3/5", "4/5")),
            Conic.ellipse(centre=(-6, 6), axes=(3, 1), rotation=(1, 0)), (3, 12, 1)]


def test_parabola_diagram_bounded_edges_proved_tails_reported():
    """With a parabola (an unbounded convex site) the bounded edges, the parabola's included, are
    proved (gradient enclosures outside its focus side); the unbounded ends are reported not
    proved, so the certificate is not ok.  Reference: the pairs of the proved edges are
    neighbours on a dense grid."""
    from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry

    D = construct(_parabola_scene())
    cert = verify(D)
    bounded = [t for t, e in enumerate(D.edges) if None not in e.ends]
    assert bounded and all(cert.edges[t] for t in bounded), cert.problems
    assert any(0 in D.edges[t].sites for t in bounded)
    assert not cert.ok and not cert.complete
    assert all(("not proved beyond" in p or "completeness" in p) for p in cert.problems), cert.problems
    G = [site_geometry(s) for s in D.sites]
    xs = np.linspace(-20, 20, 401)
    X, Y = np.meshgrid(xs, xs)
    lab = np.array([g.distance(np.column_stack([X.ravel(), Y.ravel()])) for g in G]).argmin(0).reshape(X.shape)
    pairs = {(min(int(a), int(b)), max(int(a), int(b)))
             for A, B in ((lab[:, :-1], lab[:, 1:]), (lab[:-1, :], lab[1:, :])) for a, b in zip(A[A != B], B[A != B])}
    assert {tuple(D.edges[t].sites) for t in bounded} <= pairs


def test_parabola_edge_with_an_ignored_site_is_rejected():
    D = construct(_parabola_scene())
    e = next(e for e in D.edges if None not in e.ends and 0 in e.sites)
    assert verify(D).edges[D.edges.index(e)]
    P = np.array(e.polyline, float)
    mid = P[len(P) // 2]
    D.sites = list(D.sites) + [Point(float(mid[0]), float(mid[1]) + 0.05)]
    cert = verify(D)
    assert not cert.edges[D.edges.index(e)], cert.problems


# ----------------------------------------------------------------------------- conic vertices in float Krawczyk

def test_conic_vertex_krawczyk_agrees_with_the_exact_route(random_ellipse_diagram):
    """The float Krawczyk proof on the distance differences (runtime.voronoi.verify.conic_vertices)
    against the arb Krawczyk proof on the foot-point system (runtime.voronoi.vertex.certify_vertex):
    the same vertices, within the boxes; a wrong triple or a far start point is not proved."""
    from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
    from curvedvoronoi.runtime.voronoi.verify.conic_vertices import prove_conic_vertices
    from curvedvoronoi.runtime.voronoi.vertex import certify_vertex

    D = random_ellipse_diagram
    G = [site_geometry(s) for s in D.sites]
    trips = [tuple(v.sites) for v in D.vertices]
    res = prove_conic_vertices(G, trips, [(v.x, v.y) for v in D.vertices], 100.0)
    assert sum(r is not None for r in res) >= len(res) - 1
    for v, r in zip(D.vertices, res):
        if r is None:
            continue
        proof = certify_vertex([D.sites[s] for s in v.sites], [G[s] for s in v.sites], v.x, v.y)
        assert proof.certified
        (xl, xh), (yl, yh) = proof.box
        h = r[2]
        assert xl - h <= r[0] <= xh + h and yl - h <= r[1] <= yh + h
        assert r[3] <= proof.radius_bounds[1] and proof.radius_bounds[0] <= r[4]
    # a triple without a vertex near the point: the test must not pass
    v = D.vertices[0]
    k = next(s for s in range(len(G)) if s not in v.sites)
    wrong = prove_conic_vertices(G, [(v.sites[0], v.sites[1], k)], [(v.x, v.y)], 100.0)[0]
    assert wrong is None or np.hypot(wrong[0] - v.x, wrong[1] - v.y) > 1e-3


def test_ellipse_vertex_with_a_wrong_triple_is_rejected(random_ellipse_diagram):
    D = copy.deepcopy(random_ellipse_diagram)
    v = D.vertices[0]
    k = next(s for s in range(len(D.sites)) if s not in v.sites)
    v.sites = tuple(sorted((v.sites[0], v.sites[1], k)))
    cert = verify(D)
    assert not cert.ok and not cert.vertices[0], cert.problems


# ----------------------------------------------------------------------------- a conic nested in a conic

def _nested_scene(b=5):
    from curvedvoronoi.runtime.sites.conic import Conic

    return [Conic.ellipse(centre=(0, 0), axes=(6, b), rotation=(1, 0)), (0.5, 0.3, 1),
            Conic.ellipse(centre=(14, 1), axes=(2, 1), rotation=(1, 0))]


def test_nested_circle_in_ellipse_closed_edge_is_proved_and_matches_dense_sampling():
    """A circle inside an ellipse: the closed edge around it is a closed chain of strips (gradient
    enclosures inside the ellipse, within the reach b²/a of its boundary), the nesting is proved
    with support functions; the certificate is complete.  Reference: a dense grid."""
    from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry

    D = construct(_nested_scene())
    closed = [e for e in D.edges if e.closed]
    assert len(closed) == 1 and set(closed[0].sites) == {0, 1}
    cert = verify(D)
    assert cert.ok and cert.complete, cert.problems
    G = [site_geometry(s) for s in D.sites]
    xs = np.linspace(-40, 40, 321)
    X, Y = np.meshgrid(xs, xs)
    lab = np.array([g.distance(np.column_stack([X.ravel(), Y.ravel()])) for g in G]).argmin(0).reshape(X.shape)
    pairs = {(min(int(a), int(b)), max(int(a), int(b)))
             for A, B in ((lab[:, :-1], lab[:, 1:]), (lab[:-1, :], lab[1:, :])) for a, b in zip(A[A != B], B[A != B])}
    assert pairs == set(cert.delaunay_edges) == {(0, 1), (0, 2)}


def test_nested_closed_edge_corruptions_are_rejected():
    D0 = construct(_nested_scene())
    t = next(t for t, e in enumerate(D0.edges) if e.closed)
    D = copy.deepcopy(D0)
    D.edges.pop(t)                                              # the region of the circle is missing
    cert = verify(D)
    assert not cert.ok and any("site 1 has no edge" in p for p in cert.problems), cert.problems
    D = copy.deepcopy(D0)
    e = D.edges[t]
    P = np.array(e.polyline, float)
    P[:, 0] += 3 * e.tolerance + 1e-3                           # the loop shifted beyond its tolerance
    e.polyline = P
    cert = verify(D)
    assert not cert.ok and not cert.edges[t], cert.problems
    D = copy.deepcopy(D0)                                       # the loop reported twice
    e = copy.deepcopy(D.edges[t])
    e.id = 10 ** 6
    D.edges.append(e)
    cert = verify(D)
    assert not cert.ok and any("second edge of the pair" in p for p in cert.problems), cert.problems
    D = copy.deepcopy(D0)                                       # an ignored point on the loop
    q = np.array(D.edges[t].polyline, float)[5]
    D.sites = list(D.sites) + [Point(float(q[0]), float(q[1]))]
    cert = verify(D)
    assert not cert.ok and not cert.edges[t], cert.problems


def test_closed_edge_across_the_medial_axis_is_proved():
    """In a flatter ellipse (b²/a below the depth of the loop) the loop crosses the medial axis of
    the ellipse, where its distance is not differentiable: proved with the Clarke generalised
    gradient (verify/clarke_gradient.py; references in tests/test_clarke_gradient.py)."""
    D = construct(_nested_scene(b=4))
    cert = verify(D)
    t = next(t for t, e in enumerate(D.edges) if e.closed)
    assert cert.ok and cert.edges[t], cert.problems


def test_nesting_two_deep_is_reported():
    D = construct(_nested_scene() + [(0.5, 0.3, 0)])         # a point inside the nested circle
    cert = verify(D)
    assert not cert.ok and any("nested two deep" in p for p in cert.problems), cert.problems


# ----------------------------------------------------------------------------- a hyperbola site

def _hyperbola_scene():
    from curvedvoronoi.runtime.sites.conic import Conic

    return [Conic.hyperbola(centre=(0, 0), axes=(8, 8), rotation=(1, 0)),
            Conic.ellipse(centre=(0, 2), axes=(2, 1), rotation=(1, 0)),
            Conic.ellipse(centre=(-1, 7), axes=(2, 1), rotation=("3/5", "4/5")),
            (3, -3, 1), (-2, -4, 0)]


def _conjugate_x(D, t):
    """Canonical X (across the conjugate axis x = 0) of the polyline points of edge t."""
    return np.array(D.edges[t].polyline, float)[:, 0]


def test_hyperbola_and_parabola_gradient_enclosures_contain_the_sampled_gradient():
    """Between the branches the distance to a hyperbola is the distance to the convex region of
    the nearer branch, inside a branch's region (or a parabola's focus side) the depth below the
    reach b²/a (p): the table's gradient enclosure G ± slack on B(q, R) contains the central
    difference gradient of the sampled distance at points of the disc; a disc reaching the
    conjugate axis (where the nearer branch switches and d has a ridge) gets no enclosure."""
    from curvedvoronoi.runtime.sites.conic import Conic
    from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
    from curvedvoronoi.runtime.voronoi.verify.site_table import SiteTable, gradient_enclosure

    rng = np.random.default_rng(3)
    h = 1e-6
    for site, box in ((Conic.hyperbola(centre=(1, 2), axes=(3, 2), rotation=("3/5", "4/5")), (6, 8)),
                      (Conic.parabola(vertex=(1, -1), p=2, rotation=("5/13", "12/13")), (6, 6))):
        g = site_geometry(site)
        table = SiteTable([g], 10.0)
        X, Y = rng.uniform(-box[0], box[0], 1500), rng.uniform(-box[1], box[1], 1500)
        Q = g.from_canonical(X, Y)
        R = rng.choice([0.01, 0.05, 0.2], len(Q))
        V = table.evaluate(Q, np.zeros(len(Q), int))
        G, slack, valid = gradient_enclosure(Q, V, R, 10.0)
        assert (valid & V.base).sum() > 100 and (valid & V.inner).sum() > 20
        if g.kind == "hyperbola":
            assert not np.any(valid & (np.abs(X) <= R))           # the ridge is not crossed
        for q, Gq, s, r in zip(Q[valid], G[valid], slack[valid], R[valid]):
            u = rng.normal(size=2)
            p = q + 0.99 * r * rng.uniform() ** 0.5 * u / np.hypot(*u)
            grad = np.array([(g.distance(p + e)[0] - g.distance(p - e)[0]) / (2 * h)
                             for e in (np.array([h, 0.0]), np.array([0.0, h]))])
            assert np.hypot(*(grad - Gq)) <= s + 1e-6


def test_hyperbola_edges_proved_and_match_dense_sampling():
    """With a hyperbola site (both branches one site) and bounded sites between its branches,
    the edges of the hyperbola that stay on one side of its conjugate axis are proved (gradient
    enclosures of the nearer branch's convex region); the edges crossing the conjugate axis
    (a corner of the bisector, where the nearer branch switches) are reported not proved, and so
    is the accounting with an unbounded site: not ok.  Reference: nearest sites on a dense grid
    (the pairs of the proved edges are neighbours) and float distances on the polylines."""
    from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry

    D = construct(_hyperbola_scene())
    cert = verify(D)
    assert all(cert.vertices)
    hyp = [t for t, e in enumerate(D.edges) if 0 in e.sites]
    one_side = [t for t in hyp if abs(np.sign(_conjugate_x(D, t)).sum()) == len(D.edges[t].polyline)]
    assert len(one_side) >= 3 and all(cert.edges[t] for t in one_side), cert.problems
    assert all(cert.edges[t] for t, e in enumerate(D.edges) if 0 not in e.sites), cert.problems
    assert not cert.ok and not cert.complete
    crossing = [t for t in hyp if t not in one_side]
    assert crossing and not any(cert.edges[t] for t in crossing)
    assert all(("crosses the conjugate axis" in p or "completeness" in p) for p in cert.problems), cert.problems
    G = [site_geometry(s) for s in D.sites]
    xs = np.linspace(-12, 12, 481)
    X, Y = np.meshgrid(xs, xs)
    lab = np.array([g.distance(np.column_stack([X.ravel(), Y.ravel()])) for g in G]).argmin(0).reshape(X.shape)
    pairs = {(min(int(a), int(b)), max(int(a), int(b)))
             for A, B in ((lab[:, :-1], lab[:, 1:]), (lab[:-1, :], lab[1:, :])) for a, b in zip(A[A != B], B[A != B])}
    proved = [t for t, ok in enumerate(cert.edges) if ok]
    assert {tuple(sorted(D.edges[t].sites)) for t in proved} <= pairs
    for t in proved:
        P = np.array(D.edges[t].polyline, float)
        d = np.array([g.distance(P) for g in G])
        i, j = D.edges[t].sites
        assert np.all(np.abs(d[i] - d[j]) < 1e-6 * (1 + d[i]))
        others = np.delete(d, [i, j], axis=0)
        assert np.all(others.min(0)[1:-1] > d[i][1:-1] - 1e-9)


def test_hyperbola_edge_corruptions_are_rejected():
    """A point site the diagram ignores, 0.05 from a proved edge of the hyperbola, and a dropped
    edge of the hyperbola are rejected."""
    D0 = construct(_hyperbola_scene())
    cert0 = verify(D0)
    t = next(t for t, e in enumerate(D0.edges) if 0 in e.sites and cert0.edges[t])
    D = copy.deepcopy(D0)
    P = np.array(D.edges[t].polyline, float)
    mid, nxt = P[len(P) // 2], P[len(P) // 2 + 1]
    nrm = np.array([-(nxt - mid)[1], (nxt - mid)[0]]) / np.hypot(*(nxt - mid))
    D.sites = list(D.sites) + [Point(float(mid[0] + 0.05 * nrm[0]), float(mid[1] + 0.05 * nrm[1]))]
    cert = verify(D)
    assert not cert.ok and not cert.edges[t], cert.problems
    D = copy.deepcopy(D0)
    pair = tuple(D.edges[t].sites)
    del D.edges[t]
    cert = verify(D)
    assert not cert.ok
    assert any(f"no edge {pair} ends here" in p for p in cert.problems), cert.problems


@pytest.mark.parametrize("what", ["edges", "tails"])
def test_edges_and_tails_past_their_work_limit_get_a_bounded_second_chance(random_ellipse_diagram, monkeypatch, what):
    """An edge whose strips spend EDGE_WORK pieces may go on to EDGE_WORK_MORE from a pool shared by
    the edges of the diagram, and a tail undecided within TAIL_WORK is tried once more with
    TAIL_WORK_MORE: with tiny first budgets and no second chance the proofs stop at the limit (and
    say so); with the second chance the same diagram is proved."""
    from curvedvoronoi.runtime.voronoi.verify import curved, tail

    D = random_ellipse_diagram
    if what == "edges":
        monkeypatch.setattr(curved, "EDGE_WORK", 40)
        pool, said = (curved, "EXTRA_EDGES"), "work limit of the edge reached"
    else:
        monkeypatch.setattr(tail.prove_tail, "__defaults__", (2,))
        pool, said = (tail, "MORE_TAILS"), "undecided"
    monkeypatch.setattr(*pool, 0)
    cert = verify(D)
    assert not cert.ok and any(said in p for p in cert.problems), cert.problems
    monkeypatch.setattr(*pool, len(D.edges))
    cert = verify(D)
    assert cert.ok, cert.problems
