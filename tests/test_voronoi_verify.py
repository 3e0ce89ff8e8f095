"""The diagram verifier (runtime.voronoi.verify): it proves correct diagrams and REJECTS corrupted ones.

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
from curvedvoronoi.runtime.voronoi.verify import verify

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


def random_disjoint_circles(rng, n, box=30.0, rmin=0.2, rmax=1.5, gap=0.1):
    out = []
    while len(out) < n:
        x, y = rng.uniform(0, box, 2)
        r = rng.uniform(rmin, rmax)
        if all((x - a) ** 2 + (y - b) ** 2 > (r + c + gap) ** 2 for a, b, c in out):
            out.append((float(x), float(y), float(r)))
    return out


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
    rng = np.random.default_rng(11)
    C = np.array([c[:2] for c in random_disjoint_circles(rng, 30, rmin=0.5, rmax=0.5, gap=0.2)])
    cert = verify(qhull_diagram(C, rho=0.5))
    assert cert.ok, cert.problems[:5]


@pytest.mark.parametrize("seed", [0, 3])
def test_unequal_circles_match_the_exact_brute_force(seed):
    circles = random_disjoint_circles(np.random.default_rng(seed), 7, box=12.0)
    D = construct(circles)
    cert = verify(D)
    assert cert.ok, cert.problems
    assert sorted(tuple(v.sites) for v in D.vertices) == exact_vertex_triples(circles)


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
    return construct(random_disjoint_circles(np.random.default_rng(4), 20))


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
        return subprocess.run([sys.executable, "-m", "curvedvoronoi", "verify", *a], cwd=ROOT, env=env,
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

def random_ellipses(rng, n, box=30.0):
    """n pairwise disjoint ellipses (discs around them disjoint) with rational data and rotations
    (cos, sin) = ((1 − s²)/(1 + s²), 2s/(1 + s²))."""
    from fractions import Fraction

    from curvedvoronoi.runtime.sites.conic import Conic

    out, used = [], []
    while len(out) < n:
        a = round(float(rng.uniform(1, 3)), 2)
        b = round(float(rng.uniform(0.4, 1)) * a, 2)
        c = np.round(rng.uniform(-box, box, 2), 2)
        if any(np.hypot(*(c - d)) < a + ad + 1.0 for d, ad in used):
            continue
        s = Fraction(int(rng.integers(-9, 10)), 7)
        cs, sn = (1 - s * s) / (1 + s * s), 2 * s / (1 + s * s)
        out.append(Conic.ellipse(centre=(Fraction(str(c[0])), Fraction(str(c[1]))),
                                 axes=(Fraction(str(a)), Fraction(str(b))), rotation=(str(cs), str(sn))))
        used.append((c, a))
    return out


@pytest.fixture(scope="module", params=[13, 19])
def random_ellipse_diagram(request):
    rng = np.random.default_rng(request.param)
    return construct(random_ellipses(rng, int(rng.integers(4, 9))))


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
    from curvedvoronoi.runtime.voronoi.verify_edge_checks import check_edges
    from curvedvoronoi.runtime.voronoi.verify_vertices import prove_vertices

    geoms = [site_geometry(s) for s in D.sites]
    problems: list = []
    vinfo, vok = prove_vertices(D, list(D.sites), geoms, None, problems)
    eok, ends, _ = check_edges(D, geoms, None, vinfo, vok, problems, {})
    assert all(eok) and not problems, problems
    return geoms, ends


def test_ellipse_accounting_rejects_wrong_order_and_missing_end(random_ellipse_diagram):
    from curvedvoronoi.runtime.voronoi.verify_closure import verify_accounting_conics
    from curvedvoronoi.runtime.voronoi.verify_support import SupportTable

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
    for a in range(len(ends)):
        probs = []
        assert not verify_accounting_conics(n, sup, ends[:a] + ends[a + 1:], probs)
        assert any("at infinity" in m or "far directions" in m for m in probs), probs


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
    from curvedvoronoi.runtime.voronoi.verify_sitetable import SiteTable
    from curvedvoronoi.runtime.voronoi.verify_support import SupportTable
    from curvedvoronoi.runtime.voronoi.verify_tail import prove_tail

    geoms = [site_geometry(s) for s in (Point(-100, 0), Point(100, 0), Point(0, yk))]
    y_vertex = (1e4 - yk * yk) / (-2 * yk)            # d_i = d_k on x = 0
    assert (y_vertex > 1000) != proved
    link = (np.array([0.0, 1000.0]), np.array([0.0, 1.0]), np.array([-1.0, 0.0]), 10.0, 1.0, 5.0)
    ok, msg, J = prove_tail(SupportTable(geoms), SiteTable(geoms, 1000.0), (0, 1), link, 1000.0)
    assert ok == proved, msg
    if proved:
        assert J[0] < np.pi / 2 < J[1]
