"""Boundary tests written against the surviving soundness mutants of the diagram verifier
(issue 31 item 3; bench/results/mutation.md, the seed-32 sample of runtime/voronoi/verify/*.py).

Each test states an exact fact derived by hand below, on both sides of the inequality a mutant
weakened, never from the verifier's own output.

* Exact point-edge predicate (:func:`point_edge_clear`).  Sites A = (-1, 0), B = (1, 0),
  C = (0, 1).  The bisector of A, B is q(t) = (0, 2t) (m = 0, n = rot90(B − A) = (0, 2)); for a
  point k = (0, −κ) the power difference is f_k(t) = |q − k|² − |q − A|² = 4κt + κ² − 1.  The edge
  from the vertex (0, 0) of A, B, C (t = 0) upwards to infinity (direction +1) has k strictly
  farther on the OPEN edge iff f_k(0) = κ² − 1 ≥ 0 (the slope 4κ is > 0): κ = 1 touches the
  vertex only (clear), κ = 1 + 10⁻⁹ is clear, κ = 1 − 10⁻⁹ cuts the edge at t = (1 − κ²)/4κ.
  Downwards (direction −1) f_k → −∞: never clear.
"""
from __future__ import annotations

import math
from fractions import Fraction as F
from types import SimpleNamespace

import numpy as np
import pytest

from curvedvoronoi.runtime.predicates.circles import Circle, Point
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry

A, B, C = Point(-1, 0), Point(1, 0), Point(0, 1)


def _geoms(*sites):
    return [site_geometry(s) for s in sites]


# ----------------------------------------------------------------------------- point_edge_clear

@pytest.mark.parametrize("kappa, clear", [(F(1), True), (1 + F(1, 10 ** 9), True), (1 - F(1, 10 ** 9), False),
                                          (F(1, 2), False), (F(3), True)])
def test_point_edge_clear_at_a_touching_end_vertex(kappa, clear):
    from curvedvoronoi.runtime.voronoi.verify.exact_edges import point_edge_clear

    G = _geoms(A, B, C, Point(0, -kappa))
    assert point_edge_clear(G, 0, 1, 3, (0, 1, 2), ("inf", 1)) is clear
    assert point_edge_clear(G, 0, 1, 3, ("inf", 1), (0, 1, 2)) is clear       # the ends in either order
    assert point_edge_clear(G, 0, 1, 3, (0, 1, 2), ("inf", -1)) is False       # f_k → −∞ downwards


def test_point_edge_clear_between_two_vertices():
    """The bounded edge of A, B between the circumcentres of (A, B, C) at t = 0 and of
    (A, B, E), E = (0, −3): circumcentre (0, −4/3), t = −2/3.  k = (0, −κ): f_k(t) = 4κt + κ² − 1
    must be ≥ 0 at both ends: at t = −2/3, κ² − 8κ/3 − 1 = (κ − 3)(κ + 1/3) ≥ 0 iff κ ≥ 3 (κ > 0),
    and at t = 0, κ ≥ 1.  k = (0, 3) mirrored, i.e. κ = −3: f = −12t + 8 > 0 on [−2/3, 0]."""
    from curvedvoronoi.runtime.voronoi.verify.exact_edges import point_edge_clear

    for kappa, clear in ((F(3), True), (3 + F(1, 10 ** 9), True), (3 - F(1, 10 ** 9), False), (F(-3), True),
                         (F(2), False)):
        G = _geoms(A, B, C, Point(0, -3), Point(0, -kappa))
        assert point_edge_clear(G, 0, 1, 4, (0, 1, 2), (0, 1, 3)) is clear, kappa


def test_point_edge_clear_of_a_collinear_tie_at_infinity():
    """k on the line AB: β = 2 n·(A − k) = 0 and f_k ≡ α = |k|² − 1 is constant on the bisector:
    k = (3, 0) is farther everywhere (α = 8), k = (1/2, 0) nearer everywhere (α = −3/4)."""
    from curvedvoronoi.runtime.voronoi.verify.exact_edges import point_edge_clear

    G = _geoms(A, B, C, Point(3, 0), Point(F(1, 2), 0))
    assert point_edge_clear(G, 0, 1, 3, (0, 1, 2), ("inf", 1)) is True
    assert point_edge_clear(G, 0, 1, 3, (0, 1, 2), ("inf", -1)) is True
    assert point_edge_clear(G, 0, 1, 4, (0, 1, 2), ("inf", 1)) is False


# ----------------------------------------------------------------------------- exact_third_site_clear

def test_exact_route_refuses_an_end_vertex_with_a_circle():
    """The exact point route needs point end vertices (circumcentres): with an end vertex of
    A, B and a circle it must answer 'not proved' (False), and here k = (0, −1/2) lies ON the
    bisector of A, B below the vertex, so it truly cuts the edge: claiming it farther is false.
    The same edge with the point vertex (A, B, C): f_k(0) = −3/4 < 0, also False."""
    from curvedvoronoi.runtime.voronoi.verify.exact_edges import exact_third_site_clear

    G = _geoms(A, B, C, Point(0, F(-1, 2)), Circle.from_radius(0, 5, 1))
    e = SimpleNamespace(ends=(7, None), id=0)
    det = (3, None, "undecided")
    for third in (4, 2):
        vinfo = {7: SimpleNamespace(sites=(0, 1, third), id=7)}
        assert exact_third_site_clear(G, vinfo, e, (0, 1), [(None, -1)], det) is False
    # and a site the search did not leave undecided is never handed to the exact route
    vinfo = {7: SimpleNamespace(sites=(0, 1, 2), id=7)}
    G2 = _geoms(A, B, C, Point(0, -3))
    assert exact_third_site_clear(G2, vinfo, e, (0, 1), [(None, 1)], (3, None, "undecided")) is True
    assert exact_third_site_clear(G2, vinfo, e, (0, 1), [(None, 1)], (3, None, "closer")) is False


# ----------------------------------------------------------------------------- whole diagrams

def _doc(sites):
    from curvedvoronoi.runtime.voronoi.construction import voronoi

    return voronoi(sites, certify=False).to_json()


def test_an_edge_run_through_the_other_vertex_of_its_triple_is_named():
    """Circles i = (−2, 0), j = (2, 0) of radius 1 and k = (0, 1/10) of radius 1/2: the bisector of
    i, j is the line x = 0, and on it d_k = d_i at two points, the vertices of (i, j, k) (one above,
    one below k).  The edge of i, j from the upper vertex is forged to go DOWN to infinity through
    (0, 0), where d_k = 0.4 < d_i = 1 (k cuts it), and through the lower vertex: rejected, the
    edge named."""
    import copy

    from curvedvoronoi.runtime.voronoi.verify.certificate import verify

    doc = _doc([Circle.from_radius(-2, 0, 1), Circle.from_radius(2, 0, 1), Circle.from_radius(0, F(1, 10), F(1, 2))])
    assert verify(doc).ok
    top = max(doc["vertices"], key=lambda v: v["y"])
    bot = min(doc["vertices"], key=lambda v: v["y"])
    assert top["y"] > 0 > bot["y"] and sorted(top["sites"]) == sorted(bot["sites"]) == [0, 1, 2]
    d = copy.deepcopy(doc)
    e = next(e for e in d["edges"] if sorted(e["sites"]) == [0, 1] and e["ends"][0] == top["id"])
    e["polyline"] = [[top["x"], top["y"]], [0.0, 0.0], [bot["x"], bot["y"]], [0.0, -50.0]]
    cert = verify(d)
    pos = d["edges"].index(e)
    assert not cert.ok and not cert.edges[pos], cert.problems
    assert any(p.startswith(f"edge {e['id']} ") for p in cert.problems), cert.problems


def test_edges_left_unchecked_at_the_deadline_are_not_proved():
    """``deadline`` already past: no edge of A, B, C is checked (all three are unbounded), none
    may be flagged proved, and the certificate says why."""
    import time

    from curvedvoronoi.runtime.voronoi.verify.certificate import verify

    doc = _doc([A, B, C])
    assert verify(doc).ok
    cert = verify(doc, deadline=time.perf_counter() - 1.0)
    assert not cert.ok and not any(cert.edges), (cert.edges, cert.problems)
    assert any("time limit reached" in p for p in cert.problems), cert.problems


def test_a_one_point_polyline_is_rejected():
    """An edge needs a polyline of at least two points (a segment from its vertex); one point
    bounds nothing."""
    import copy

    from curvedvoronoi.runtime.voronoi.verify.certificate import verify

    doc = _doc([A, B, C])
    for pos in range(3):
        d = copy.deepcopy(doc)
        e = d["edges"][pos]
        e["polyline"] = e["polyline"][:1]
        cert = verify(d)
        assert not cert.ok and not cert.edges[pos], cert.problems
        assert any(p.startswith(f"edge {e['id']} ") for p in cert.problems), cert.problems


def test_symmetric_three_circles_verify():
    """Circles (−2, 0), (2, 0) of radius 1 and (0, 0) of radius 1/2 (disjoint: gaps 1/2): on the
    bisector x = 0 of the outer two, d_k = |y| − 1/2 = d_i = √(4 + y²) − 1 at |y| = 15/4: two
    vertices (0, ±15/4) of radius 13/4."""
    from curvedvoronoi.runtime.voronoi.verify.certificate import verify

    doc = _doc([Circle.from_radius(-2, 0, 1), Circle.from_radius(2, 0, 1), Circle.from_radius(0, 0, F(1, 2))])
    got = sorted((round(v["y"], 9), round(v["radius"], 9)) for v in doc["vertices"])
    assert got == [(-3.75, 3.25), (3.75, 3.25)]
    cert = verify(doc)
    assert cert.ok, cert.problems


def _nested_sites():
    from curvedvoronoi.runtime.sites.conic import Conic

    return [Conic.ellipse(centre=(0, 0), axes=(6, 5), rotation=(1, 0)), Circle.from_radius(F(1, 2), F(3, 10), 1),
            Conic.ellipse(centre=(14, 1), axes=(2, 1), rotation=(1, 0))]


def test_a_document_without_delaunay_edges_is_verified():
    """The ``delaunay_edges`` field is optional (compared only when present)."""
    from curvedvoronoi.runtime.voronoi.verify.certificate import verify

    doc = _doc(_nested_sites())
    assert "delaunay_edges" in doc
    del doc["delaunay_edges"]
    cert = verify(doc)
    assert cert.ok, cert.problems


@pytest.mark.parametrize("kind", ["circle", "ellipse"])
def test_a_closed_edge_with_a_site_index_out_of_range_is_named_not_a_crash(kind):
    """Site 1 (a circle) is nested in site 0; the closed edge around it relabelled (0, 7) in a
    diagram of three sites: rejected (no exception), the edge named."""
    import copy

    from curvedvoronoi.runtime.voronoi.verify.certificate import verify

    sites = _nested_sites()
    if kind == "circle":
        sites = [Circle.from_radius(0, 0, 5)] + sites[1:2] + [Circle.from_radius(14, 1, 1)]
    doc = _doc(sites)
    d = copy.deepcopy(doc)
    e = next(e for e in d["edges"] if e["closed"])
    e["sites"] = [0, 7]
    cert = verify(d)
    assert not cert.ok and not cert.edges[d["edges"].index(e)], cert.problems
    assert any(p.startswith(f"edge {e['id']} ") for p in cert.problems), cert.problems


def test_a_degree_four_conic_vertex_moved_with_its_edges_is_named():
    """Four equal ellipses x²/4 + y² = 1 centred at (0, 0), (6, 0), (0, 4), (6, 4): the mirrors
    x = 3 and y = 2 map them onto each other, so (3, 2) is equidistant from all four, a vertex of
    degree 4.  Moved to (3 + 1e-7, 2) with its four edges' ends moved along, no symmetry of the
    sites fixes the reported point any more (the mirrors fix only x = 3): the vertex is rejected
    and named."""
    import copy

    from curvedvoronoi.runtime.sites.conic import Conic
    from curvedvoronoi.runtime.voronoi.verify.certificate import verify

    doc = _doc([Conic.ellipse(centre=(6 * i, 4 * j), axes=(2, 1)) for i in range(2) for j in range(2)])
    (v,) = doc["vertices"]
    assert (v["x"], v["y"], len(v["sites"])) == (3.0, 2.0, 4)
    assert verify(doc).ok
    bad = copy.deepcopy(doc)
    v = bad["vertices"][0]
    v["x"] += 1e-7
    for e in bad["edges"]:
        for k, end in ((0, e["ends"][0]), (-1, e["ends"][1])):
            if end == v["id"]:
                e["polyline"][k] = [v["x"], v["y"]]
    cert = verify(bad)
    assert not cert.ok and not cert.vertices[0], cert.problems
    assert any(p.startswith(f"vertex {v['id']} ") for p in cert.problems), cert.problems


# ----------------------------------------------------------------------------- exact signs and mirrors

@pytest.mark.parametrize("A, B, D, sign", [
    (F(-2), F(1), F(4), 0),                          # −2 + √4 = 0 exactly
    (F(2), F(-1), F(4), 0),
    (F(-2), F(1), F(4) + F(1, 10 ** 9), 1),          # √(4 + 1e-9) > 2
    (F(-2), F(1), F(4) - F(1, 10 ** 9), -1),
    (F(2), F(-1), F(4) + F(1, 10 ** 9), -1),
    (F(-3), F(2), F(9, 4), 0),                       # −3 + 2·(3/2)
    (F(-3), F(2), F(2), -1),                         # 2√2 < 3
    (F(0), F(-1), F(2), -1), (F(5), F(0), F(7), 1), (F(-5), F(3), F(0), -1),
])
def test_sign_of_a_quadratic_surd(A, B, D, sign):
    """The sign of A + B·√D, decided by hand (perfect squares and their neighbours)."""
    from curvedvoronoi.runtime.voronoi.verify.hull_points import _sign_quadratic

    assert _sign_quadratic(A, B, D) == sign


def _mirror_scene():
    """Sites 0 = ellipse x²/4 + y² = 1, 2 = its translate by (6, 0) (mirror images in the line
    6x = 18, i.e. x = 3; site 0 lies on the side x < 3), 1 = an ellipse of other axes at (0, 4)
    (no mirror onto site 2)."""
    from curvedvoronoi.runtime.sites.conic import Conic

    sites = [Conic.ellipse(centre=(0, 0), axes=(2, 1)), Conic.ellipse(centre=(0, 4), axes=(3, 1)),
             Conic.ellipse(centre=(6, 0), axes=(2, 1))]
    return sites, _geoms(*sites)


@pytest.mark.parametrize("Q, dominated", [((2, 10), True), ((3, 10), True), ((3 + F(1, 10 ** 9), 10), False),
                                          ((4, -7), False), ((3, -50), True)])
def test_mirror_dominates_a_segment_only_on_its_side(Q, dominated):
    """d_0 < d_2 exactly on the open half-plane x < 3 (site 2 is site 0 reflected in x = 3): the
    segment from P = (1, 10) to Q is dominated by site 0 iff Q has x ≤ 3 (the segment is open at
    the mirror)."""
    from curvedvoronoi.runtime.voronoi.verify.mirror_tail import dominated_on

    sites, G = _mirror_scene()
    P = (F(1), F(10))
    got = dominated_on(sites, G, (0, 1), 2, P, None, Q=(F(Q[0]), F(Q[1])))
    assert got == (0 if dominated else None)
    # a segment lying on the mirror itself is not inside the open half-plane
    assert dominated_on(sites, G, (0, 1), 2, (F(3), F(0)), None, Q=(F(3), F(5))) is None


@pytest.mark.parametrize("P, d, dominated", [((1, 10), (0, 1), True), ((1, 10), (-1, 0), True),
                                             ((1, 10), (1, 0), False), ((1, 10), (1, 1000), False),
                                             ((3, 0), (-1, 0), False)])
def test_mirror_dominates_a_ray_only_inside_its_half_plane(P, d, dominated):
    """The ray P + t·d (t ≥ 0) stays in x < 3 iff P does and d_x ≤ 0."""
    from curvedvoronoi.runtime.voronoi.verify.mirror_tail import dominated_on

    sites, G = _mirror_scene()
    got = dominated_on(sites, G, (0, 1), 2, (F(P[0]), F(P[1])), (F(d[0]), F(d[1])), ray=True)
    assert got == (0 if dominated else None)


# ----------------------------------------------------------------------------- Hausdorff bound, ellipse bisector

@pytest.mark.parametrize("n", [5, 8, 16])
def test_polyline_bound_of_an_ellipse_bisector(n):
    """Circle (1, 0) of radius 1 nested in the circle (0, 0) of radius 5: R − |q| = |q − c| − r gives
    |q| + |q − c| = R + r = 6, the ellipse with foci 0, c, centre (1/2, 0), a = 3,
    b = √(9 − 1/4) = √35/2.  An inscribed n-gon (nodes ON the ellipse) is at Hausdorff distance
    max over its sides of the arc's largest normal deviation from the chord (each arc is a convex
    graph over its chord): the bound must be at least that (measured on 2·10⁵ curve samples) and
    within 1 % of it."""
    from curvedvoronoi.runtime.voronoi.verify.edges import CircleTable, bisector
    from curvedvoronoi.runtime.voronoi.verify.polyline_bound import hausdorff_bound

    bis = bisector(CircleTable(_geoms(Circle.from_radius(0, 0, 5), Circle.from_radius(1, 0, 1))), 0, 1)
    assert bis.kind == "ellipse"
    a, b = 3.0, math.sqrt(35) / 2
    t = np.linspace(0, 2 * np.pi, n + 1) + 0.3
    P = np.column_stack([0.5 + a * np.cos(t), b * np.sin(t)])
    dev = 0.0
    for k in range(n):
        s = np.linspace(t[k], t[k + 1], 20001)
        S = np.column_stack([0.5 + a * np.cos(s), b * np.sin(s)])
        d = P[k + 1] - P[k]
        nrm = np.array([-d[1], d[0]]) / np.hypot(*d)
        dev = max(dev, float(np.abs((S - P[k]) @ nrm).max()))
    bound, why = hausdorff_bound(bis, P)
    assert why is None
    assert dev <= bound <= 1.01 * dev + 1e-9, (dev, bound)


# ----------------------------------------------------------------------------- accounting at infinity (circles)

def test_circle_accounting_needs_every_unbounded_edge():
    """Circles c0 = (0, 0) r 1, c1 = (10, 0) r 2, c2 = (4, 8) r 1/2 (pairwise disjoint, centres not
    collinear): far in direction u the nearest site maximises c_k·u + ρ_k, and each of the three
    sites wins an open sector of directions, so each pair has exactly one unbounded edge.  With the
    three proved ends the accounting closes; without any one of them, between the two ends left
    there is a sector won by the other site, which no site shared by those ends owns."""
    from curvedvoronoi.runtime.voronoi.construction import voronoi
    from curvedvoronoi.runtime.voronoi.verify.closure import verify_accounting
    from curvedvoronoi.runtime.voronoi.verify.edge_checks import check_edges
    from curvedvoronoi.runtime.voronoi.verify.edges import CircleTable
    from curvedvoronoi.runtime.voronoi.verify.vertices import prove_vertices

    D = voronoi([Circle.from_radius(0, 0, 1), Circle.from_radius(10, 0, 2), Circle.from_radius(4, 8, F(1, 2))],
                certify=False)
    geoms = [site_geometry(s) for s in D.sites]
    T = CircleTable(geoms)
    problems: list = []
    vinfo, vok = prove_vertices(D, list(D.sites), geoms, T, problems)
    eok, ends, _ = check_edges(D, geoms, T, vinfo, vok, problems, {})
    assert all(eok) and not problems and len(ends) == 3, problems
    assert sorted(tuple(sorted(int(s) for s in t[1])) for t in ends) == [(0, 1), (0, 2), (1, 2)]
    assert verify_accounting(3, T, ends, [])
    for a in range(3):
        probs: list = []
        assert not verify_accounting(3, T, ends[:a] + ends[a + 1:], probs)
        assert any("far directions" in p or "at infinity" in p for p in probs), probs


# ----------------------------------------------------------------------------- zeros of d_k − d_i on an arc

@pytest.mark.parametrize("uz, lo, hi, inside", [
    (1.0, 0.5, 2.0, True), (3.0, 0.5, 2.0, False), (0.4, 0.5, 2.0, False),
    (0.5, 6.0, 7.0, True),                      # the arc wraps past 2π: 0.5 + 2π ∈ [6, 7]
    (0.5 + 2 * math.pi, 6.0, 7.0, True), (1.0, 6.0, 7.0, False), (5.9, 6.0, 7.0, False),
])
def test_a_zero_on_an_ellipse_arc_is_found_modulo_a_turn(uz, lo, hi, inside):
    """On an ellipse bisector (angle parameter, period 2π) the zero at angle uz lies on the arc
    [lo, hi] iff uz ≡ some angle of [lo, hi] mod 2π; a zero on the arc means site k cuts the edge
    (True, a problem naming the edge)."""
    from curvedvoronoi.runtime.voronoi.verify.exact_edges import zero_on_arc

    problems: list = []
    bis = SimpleNamespace(kind="ellipse")
    got = zero_on_arc("edge 5 (sites 0, 1)", bis, [(0.0, 0.0)], [uz], None, lo, hi, lo, hi, (0, 1, 2), problems)
    assert got is inside
    assert bool(problems) is inside and all(p.startswith("edge 5 ") for p in problems)


@pytest.mark.parametrize("uz, inside", [(0.0, True), (-1e-10, True), (1.0 + 1e-10, True), (0.5, True),
                                        (-1e-6, False), (1.0 + 1e-6, False), (-3.0, False)])
def test_a_zero_at_the_end_of_a_hyperbola_arc_counts_as_on_it(uz, inside):
    """Hyperbola branch, arc u ∈ [0, 1]: a zero within float noise (1e-10) of an end cannot be
    told from the end, so it is counted on the arc (rejecting is the safe side); 1e-6 away it is
    off the arc."""
    from curvedvoronoi.runtime.voronoi.verify.exact_edges import zero_on_arc

    bis = SimpleNamespace(kind="hyperbola")
    assert zero_on_arc("edge 5 (sites 0, 1)", bis, [(0.0, 0.0)], [uz], None, 0.0, 1.0, 0.0, 1.0, (0, 1, 2), []) is inside


def test_point_accounting_rejects_a_missing_or_doubled_end():
    """Points A, B, C: the convex hull has three sides, one unbounded edge across each."""
    from curvedvoronoi.runtime.voronoi.construction import voronoi
    from curvedvoronoi.runtime.voronoi.verify.edge_checks import check_edges
    from curvedvoronoi.runtime.voronoi.verify.hull_points import verify_accounting_points
    from curvedvoronoi.runtime.voronoi.verify.vertices import prove_vertices

    from curvedvoronoi.runtime.voronoi.verify.edges import CircleTable

    D = voronoi([A, B, C], certify=False)
    geoms = [site_geometry(s) for s in D.sites]
    T = CircleTable(geoms)
    problems: list = []
    vinfo, vok = prove_vertices(D, list(D.sites), geoms, T, problems)
    eok, ends, _ = check_edges(D, geoms, T, vinfo, vok, problems, {})
    assert all(eok) and not problems and len(ends) == 3, problems
    assert verify_accounting_points(geoms, ends, [])
    for a in range(3):
        probs: list = []
        assert not verify_accounting_points(geoms, ends[:a] + ends[a + 1:], probs)
        assert probs
        probs = []
        assert not verify_accounting_points(geoms, ends + [ends[a]], probs)
        assert any(p.startswith(f"edge {ends[a][3]} ") for p in probs), probs


def test_a_degree_four_vertex_of_circles_whose_triple_has_two_vertices():
    """Circles i = (−2, 0), j = (2, 0) of radius 1, k = (0, 1/10) of radius 1/2 and the point
    p = (0, 9).  On x = 0, d_i = √(4 + y²) − 1 and d_k = |y − 1/10| − 1/2 meet at y = 24/5 (radius
    21/5) and at y = −91/30 (radius 79/30): the triple i, j, k has two Voronoi vertices.  p is at
    distance 9 − 24/5 = 21/5 from (0, 24/5): that vertex has degree 4 (p tangent, exactly), and
    the other vertex of the triple, 7.8 away, must not be mistaken for it."""
    from curvedvoronoi.runtime.voronoi.verify.certificate import verify

    doc = _doc([Circle.from_radius(-2, 0, 1), Circle.from_radius(2, 0, 1), Circle.from_radius(0, F(1, 10), F(1, 2)),
                Point(0, 9)])
    got = sorted((len(v["sites"]), round(v["y"], 9), round(v["radius"], 9)) for v in doc["vertices"])
    assert got == [(3, round(-91 / 30, 9), round(79 / 30, 9)), (4, 4.8, 4.2)]
    cert = verify(doc)
    assert cert.ok and cert.complete, cert.problems


def test_two_parabolas_give_a_certificate_not_an_exception():
    """Parabolas y = x² + 1 and y = −x² − 1 (disjoint, mirror images in y = 0): one edge, the line
    y = 0 (the mirror), unbounded both ways.  verify must answer with a certificate (proved, or
    the unproved part named), never raise."""
    from curvedvoronoi.runtime.sites.conic import Conic
    from curvedvoronoi.runtime.voronoi.verify.certificate import verify

    doc = _doc([Conic.from_coefficients(1, 0, 0, 0, -1, 1), Conic.from_coefficients(-1, 0, 0, 0, -1, -1)])
    assert [(sorted(e["sites"]), e["ends"]) for e in doc["edges"]] == [([0, 1], [None, None])]
    cert = verify(doc)
    assert cert.ok or cert.problems


# ----------------------------------------------------------------------------- ties at infinity

def test_a_row_tied_at_infinity_by_a_mirror_and_by_support_levels():
    """Ellipses x²/4 + y² = 1 at (0, 0) and (6, 0) (mirror images in x = 3) and the unit circle at
    (12, 0): all three touch y = 1 and y = −1, so they tie at infinity in the directions ±(0, 1)
    (support level 1 each).  The first pair is tied by its mirror, the second (an ellipse and a
    circle, no mirror maps one onto the other) by its exact support points (6, ±1), (12, ±1).
    The diagram: the line x = 3 between the ellipses and one curve between the ellipse at (6, 0)
    and the circle, both unbounded both ways (parallel ends), no vertex."""
    from curvedvoronoi.runtime.sites.conic import Conic
    from curvedvoronoi.runtime.voronoi.verify.certificate import verify

    doc = _doc([Conic.ellipse(centre=(0, 0), axes=(2, 1)), Conic.ellipse(centre=(6, 0), axes=(2, 1)),
                Circle.from_radius(12, 0, 1)])
    assert not doc["vertices"]
    assert sorted((tuple(sorted(e["sites"])), tuple(e["ends"])) for e in doc["edges"]) == \
        [((0, 1), (None, None)), ((1, 2), (None, None))]
    e01 = next(e for e in doc["edges"] if sorted(e["sites"]) == [0, 1])
    assert all(abs(x - 3.0) <= 1e-9 for x, _ in e01["polyline"])
    cert = verify(doc)
    assert cert.ok and cert.complete, cert.problems


def test_a_refusal_is_always_explained_nesting_depth_two():
    """Circles c0 = (0, 0) r 10 ⊃ c1 = (1, 0) r 5 ⊃ c2 = (2, 0) r 1 (|c1 − c0| + 5 = 6 < 10,
    |c2 − c1| + 1 = 2 < 5) and c3 = (30, 0) r 2 outside: the diagram is the loop around c1 in c0, the
    loop around c2 in c1 and one unbounded edge between c0 and c3, no vertex.  Whatever the
    verifier can prove of the nesting, a certificate that is not ok must say why."""
    from curvedvoronoi.runtime.voronoi.verify.certificate import verify

    doc = _doc([Circle.from_radius(0, 0, 10), Circle.from_radius(1, 0, 5), Circle.from_radius(2, 0, 1),
                Circle.from_radius(30, 0, 2)])
    assert not doc["vertices"]
    assert sorted((tuple(sorted(e["sites"])), e["closed"]) for e in doc["edges"]) == \
        [((0, 1), True), ((0, 3), False), ((1, 2), True)]
    cert = verify(doc)
    assert cert.ok or cert.problems, (cert.ok, cert.complete, cert.edges)


def test_edges_whose_tails_start_after_the_deadline_are_not_proved(monkeypatch):
    """The deadline passes between the batch search of the arcs and the tails (made deterministic
    by replacing the clock test: not past at its first reading, past at every later one): the
    three edges of A, B, C are unbounded, so their tails are not started and none is proved."""
    from curvedvoronoi.runtime.voronoi.verify import edge_checks
    from curvedvoronoi.runtime.voronoi.verify.certificate import verify

    doc = _doc([A, B, C])
    calls = []

    def past(deadline):
        calls.append(deadline)
        return deadline is not None and len(calls) > 1

    monkeypatch.setattr(edge_checks, "past", past)
    cert = verify(doc, deadline=1e300)
    assert len(calls) > 1
    assert not cert.ok and not any(cert.edges), (cert.edges, cert.problems)
    assert any("time limit reached" in p for p in cert.problems), cert.problems


# ----------------------------------------------------------------------------- a mirror ray's support bound

@pytest.mark.parametrize("kx, clear", [(F(1, 2), False), (F(3, 10), False), (F(-1, 2), True), (F(-1), True)])
def test_mirror_ray_support_bound_keeps_its_curvature_term(kx, clear):
    """Circles i: centre (0, 2), j: centre (0, −2), radius 1 (mirror images in y = 0), and the
    point k = (κ, 0) on the mirror.  The ray of the mirror from P = (2, 0) along u = (1, 0): the
    foot of i from P is F = (0, 2) + (2, −2)/(2√2) = (1/√2, 2 − 1/√2), so a = (P − F)·u = 2 − 1/√2,
    b = (P − F)·u⊥ = −(2 − 1/√2) and d_i(P) = 2√2 − 1.

    κ = 1/2: d_k(P) = 3/2 < 2√2 − 1 (25/4 < 8), so k is strictly closer than i at the ray's start
    and the ray is NOT part of the edge (i, j): the verdict must be False.  Yet (F − k)·u =
    1/√2 − 1/2 > 0, i.e. k lies behind F: only the term b²/(2a) ≈ 0.65 of the support bound
    d_i(P + t·u) ≤ a + t + b²/(2a) keeps k among the sites still to prove; κ = 3/10 likewise
    (d_k(P) = 17/10 < 2√2 − 1).

    κ = −1/2 and −1: d_k(P + t·u) = 2 − κ + t ≥ 5/2 + t while d_i = √((2 + t)² + 4) − 1 ≤ 2 + t
    (√(x² + 4) ≤ x + 1 for x ≥ 3/2): k is farther on the whole ray, and (κ − F_x) ≤ −1/2 − 1/√2
    < −b²/(2a) ≈ −0.65 is within the support bound's reach: proved."""
    from curvedvoronoi.runtime.voronoi.verify.mirror_tail import ray_clear
    from curvedvoronoi.runtime.voronoi.verify.support import SupportTable

    sites = [Circle(0, 2, 1), Circle(0, -2, 1), Point(kx, 0)]
    G = _geoms(*sites)
    ok, msg, end = ray_clear(sites, G, SupportTable(G), (0, 1), (F(2), F(0)), (F(1), F(0)))
    assert ok is clear, msg
    if clear:
        assert end == ((F(1), F(0)), 0.0)          # direction u, lateral coordinate of the mirror y = 0
    else:
        assert "site 2" in msg


# ----------------------------------------------------------------------------- the sector of a tie at infinity

def test_a_tied_sector_stays_where_its_extreme_sites_lead():
    """Ellipse E: x²/100² + y² = 1 and the point K = (20, 1) (outside E: 20²/100² + 1 > 1) tie at
    infinity in the direction u = (0, 1): both support levels are exactly 1.  At θ = π/2 − x,
    h_E = √(100² sin²x + cos²x) and h_K = 20 sin x + cos x; h_K > h_E iff (20 s + c)² > 100² s² + c²
    iff 40 c > (100² − 20²) s (s > 0), i.e. iff tan x < 40/9600: K leads only on
    0 < x < atan(1/240) ≈ 0.00417, E on x < 0 (where h_K < cos x ≤ h_E).  To first order K leads
    (its support point lies 20 farther along u⊥), but E's radius of curvature at its support
    point is 100²/1 = 10⁴: h_E − h_K ≈ −20x + ½(10⁴ − 0)·x² turns positive at x ≈ 0.004.

    The sector [θ* − δ⁻, θ* + δ⁺] that the accounting walks must lie where the claimed extreme
    sites lead: h_K > h_E on [θ* − δ⁻, θ*) and h_E > h_K on (θ*, θ* + δ⁺] (checked on the closed
    forms at 401 angles).  A half-width that drops the curvature term of
    h_s − h_k = (ℓ_s − ℓ_k)·x + ½(h_s'' − h_k'')·x² (|h''| ≤ ρ + W, ρ ≤ 10⁴, W ≈ 100) reaches
    about 0.05, past the crossing."""
    from curvedvoronoi.runtime.sites.conic import Conic
    from curvedvoronoi.runtime.voronoi.verify.support import SupportTable
    from curvedvoronoi.runtime.voronoi.verify.ties_at_infinity import tied_sectors

    sites = [Conic.ellipse(centre=(0, 0), axes=(100, 1)), Point(20, 1)]
    G = _geoms(*sites)
    problems: list = []
    got = tied_sectors(SupportTable(G), sites, [(math.pi / 2, (0, 1), ("mirror", (F(0), F(1)), 0.0), 7)], problems)
    assert got is not None, problems
    (a0, a1, first, eid, last), = got
    assert (first, eid, last) == ((0, 1), 7, (0, 1))
    assert a0 < math.pi / 2 < a1

    def lead(t):                                    # h_K − h_E at θ = t
        return 20 * math.cos(t) + math.sin(t) - math.sqrt(100 ** 2 * math.cos(t) ** 2 + math.sin(t) ** 2)

    below = np.linspace(a0, math.pi / 2, 401)[:-1]
    above = np.linspace(math.pi / 2, a1, 401)[1:]
    assert min(lead(t) for t in below) > 0
    assert max(lead(t) for t in above) < 0


# ----------------------------------------------------------------------------- the link of a tail

@pytest.mark.parametrize("x0, nx, linked", [(0.0, -1.0, True), (0.0, 1.0, True), (3.0, -1.0, False),
                                            (3.0, 1.0, False), (-3.0, -1.0, False), (-3.0, 1.0, False)])
def test_a_tail_links_only_to_a_rectangle_that_the_bisector_crosses(x0, nx, linked):
    """Points i = (−100, 0), j = (100, 0), k = (0, −200): the edge (i, j) is the ray x = 0 from
    the vertex (0, −75) upwards (on x = 0, d_i² = 10⁴ + y² and d_k² = (y + 200)² are equal at
    y = −75, and k is farther above).  The tail
    beyond the rectangle {x0 + λ·nx, 1000 + s : s ∈ [0, 10], |λ| ≤ 1} (link circle through
    (x0, 1005)) is proved only if the bisector crosses that rectangle: for x0 = 0 it does (the
    true edge), for x0 = ±3 the rectangle lies wholly on one side of x = 0 (f = d_i − d_j has
    one sign on it), so the chain ∪ tail would not be one curve: not proved, whatever side n
    points to."""
    from curvedvoronoi.runtime.voronoi.verify.site_table import SiteTable
    from curvedvoronoi.runtime.voronoi.verify.support import SupportTable
    from curvedvoronoi.runtime.voronoi.verify.tail import prove_tail

    G = _geoms(Point(-100, 0), Point(100, 0), Point(0, -200))
    link = (np.array([x0, 1000.0]), np.array([0.0, 1.0]), np.array([nx, 0.0]), 10.0, 1.0, 5.0)
    ok, msg, J = prove_tail(SupportTable(G), SiteTable(G, 1000.0), (0, 1), link, 1000.0)
    assert ok is linked, msg
    if linked:
        assert J[0] < math.pi / 2 < J[1]            # the asymptotic direction u = (0, 1)
    else:
        assert "crossing of the link circle" in msg
