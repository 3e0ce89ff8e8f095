"""Local Voronoi vertices: float refinement and certification (thesis §5.2, §6.1).

References independent of the code under test: the vendored validation cases (vertices computed
outside the project), the exact circle locator of runtime.predicates.circles (§3.1), and a bisection on a
bisector with the float distance of runtime.sites.distance."""
from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest

from curvedvoronoi.runtime.predicates.circles import Circle, Point, voronoi_vertices_circles
from curvedvoronoi.runtime.sites.conic import Conic
from curvedvoronoi.runtime.sites.distance import distance as conic_distance
from curvedvoronoi.runtime.validation import load_cases, repository_cases_path
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.vertex import (VertexProof, certify_empty, certify_vertex,
                                                  certify_vertices_circles, classify_others,
                                                  refine_vertex)

CASES = load_cases(repository_cases_path())


def _in_box(proof: VertexProof, x, y, r, slack):
    (x0, x1), (y0, y1) = proof.box
    r0, r1 = proof.radius_bounds
    return (x0 - slack <= x <= x1 + slack and y0 - slack <= y <= y1 + slack
            and r0 - slack <= r <= r1 + slack)


@pytest.mark.parametrize("case", CASES, ids=lambda c: c.name)
def test_validation_vertices_refined_and_certified(case):
    """Every true vertex of the validation cases (ellipses, hyperbolas, parabolas, circles,
    mixed, near-degenerate, tangent) is found by refine_vertex from a seed 1e-4 off, certified,
    and the proof's box contains the expected vertex; the fourth site is decided by
    certify_empty as the expected conflict flag."""
    rng = np.random.default_rng(len(case.name))
    G = [site_geometry(c) for c in case.conics]
    for v in case.vertices:
        e = v.as_floats()
        sc = 1 + abs(e["x"]) + abs(e["y"]) + e["radius"]
        seed = (e["x"] + 1e-4 * sc * rng.normal(), e["y"] + 1e-4 * sc * rng.normal())
        r = refine_vertex(G[:3], *seed)
        assert r is not None
        assert math.hypot(r[0] - e["x"], r[1] - e["y"]) <= 1e-9 * sc
        proof = certify_vertex(case.conics[:3], G[:3], r[0], r[1])
        assert proof.certified, proof.reason
        assert _in_box(proof, e["x"], e["y"], e["radius"], 1e-13 * sc)
        assert proof.box[0][1] - proof.box[0][0] <= 1e-9 * sc
        if v.tangent:
            continue
        empty, undecided = certify_empty([G[3]], proof)
        if not v.in_conflict:
            assert empty and undecided == []
        else:
            assert not empty and undecided == [0]
            assert classify_others([G[3]], proof.box, proof.radius_bounds)[0] == -1


def test_perturbed_candidate_gives_the_same_vertex():
    """A candidate 1e-6 off is certified as the true vertex (the proof's box contains the
    reference and excludes the candidate), never as a vertex at the candidate itself."""
    case = next(c for c in CASES if c.group == "mixed" and c.vertices)
    e = case.vertices[0].as_floats()
    proof = certify_vertex(case.conics[:3], None, e["x"] + 1e-6, e["y"])
    assert proof.certified
    assert _in_box(proof, e["x"], e["y"], e["radius"], 1e-12)
    assert not (proof.box[0][0] <= e["x"] + 1e-6 <= proof.box[0][1])
    # a candidate far from any vertex is not certified as itself
    far = certify_vertex(case.conics[:3], None, e["x"] + 0.3, e["y"] - 0.2)
    assert not far.certified or not (far.box[0][0] <= e["x"] + 0.3 <= far.box[0][1])


def test_generalised_vertex_that_is_not_true_is_rejected():
    """Points (−3, 0), (3, 0) and the ellipse x²/4 + y² = 1: q = (0, 4) is equidistant (5) from
    the two points and the far critical point (0, −1) of the ellipse, a solution of the
    foot-point system, but the ellipse point (0, 1) is at distance 3 < 5."""
    sites = [Point(-3, 0), Point(3, 0), Conic.ellipse(centre=(0, 0), axes=(2, 1))]
    proof = certify_vertex(sites, None, 0.0, 4.0, feet=[(-3.0, 0.0), (3.0, 0.0), (0.0, -1.0)])
    assert not proof.certified
    assert "not a true vertex" in proof.reason
    # these three sites have no Voronoi vertex at all: on the bisector x = 0 of the points,
    # d(q, ellipse) = |y| − 1 (or 1 − y² ... ≤ 1 inside) < sqrt(9 + y²) = d(q, points)
    G = [site_geometry(s) for s in sites]
    assert refine_vertex(G, 0.0, 4.0) is None


def _bisector_vertex(p1, p2, conic, s0, s1):
    """The point of the perpendicular bisector of p1 p2 equidistant from the conic, by bisection
    on |q − p1| − d(q, C) with runtime.sites.distance's float distance (an independent route)."""
    m = ((p1[0] + p2[0]) / 2, (p1[1] + p2[1]) / 2)
    dx, dy = p2[0] - p1[0], p2[1] - p1[1]
    n = math.hypot(dx, dy)
    u = (-dy / n, dx / n)

    def f(s):
        q = (m[0] + s * u[0], m[1] + s * u[1])
        return math.hypot(q[0] - p1[0], q[1] - p1[1]) - conic_distance(conic, *q)

    a, b = s0, s1
    fa = f(a)
    assert fa * f(b) < 0
    for _ in range(80):
        c = 0.5 * (a + b)
        if (f(c) < 0) == (fa < 0):
            a, fa = c, f(c)
        else:
            b = c
    s = 0.5 * (a + b)
    return m[0] + s * u[0], m[1] + s * u[1]


def test_points_mixed_with_conics():
    """Three points and two conics (the mix the triple locator refuses): vertices of
    (point, point, conic) against a bisection on the bisector; (point, conic, conic) vertices
    are certified and equidistant by the independent float distance."""
    P = [Point(0, 3), Point(6, 3), Point(3, -3)]
    E = Conic.ellipse(centre=(3, "3/2"), axes=(1, "1/2"))
    H = Conic.parabola(vertex=(-2, -2), p="1/2", rotation=(Fraction(-3, 5), Fraction(4, 5)))
    G = {id(s): site_geometry(s) for s in (*P, E, H)}
    # (P0, P1, E): the bisector x = 3; the vertex lies above the ellipse
    ref = _bisector_vertex((0.0, 3.0), (6.0, 3.0), E, -0.5, 5.0)
    sites = [P[0], P[1], E]
    r = refine_vertex([G[id(s)] for s in sites], ref[0] + 0.01, ref[1] - 0.02)
    assert r is not None and math.hypot(r[0] - ref[0], r[1] - ref[1]) < 1e-9
    proof = certify_vertex(sites, [G[id(s)] for s in sites], r[0], r[1])
    assert proof.certified and _in_box(proof, ref[0], ref[1], proof.radius, 1e-9)
    # (P0, E, H) from a seed on a rough grid search of the equidistance residual
    sites = [P[0], E, H]
    gs = [G[id(s)] for s in sites]
    xs = np.linspace(-6, 8, 141)
    Q = np.array([(x, y) for x in xs for y in xs])
    d = np.array([g.distance(Q) for g in gs])
    res = np.abs(d[0] - d[1]) + np.abs(d[0] - d[2])
    found = 0
    for k in np.argsort(res)[:40]:
        r = refine_vertex(gs, *Q[k])
        if r is None:
            continue
        proof = certify_vertex(sites, gs, r[0], r[1])
        assert proof.certified, proof.reason
        q = (proof.x, proof.y)
        dd = [math.hypot(q[0] - 0, q[1] - 3), conic_distance(E, *q), conic_distance(H, *q)]
        assert max(dd) - min(dd) < 1e-9 * (1 + max(dd))
        assert abs(proof.radius - dd[0]) < 1e-9 * (1 + dd[0])
        found += 1
    assert found >= 1


def test_three_points_and_circles_against_the_exact_circle_locator():
    triples = [
        (Point(0, 0), Point(4, 0), Point(2, 3)),
        (Point(0, 0), Point(4, 0), Circle(2, 3, 1)),
        (Circle(0, 0, 1), Circle(5, 0, 4), Circle(1, 6, Fraction(9, 4))),
        (Circle(0, 0, 25), Point(1, 1), Circle(-1, 0, Fraction(1, 4))),      # nested in a circle
    ]
    n = 0
    for t in triples:
        tv = voronoi_vertices_circles(*t)
        for v in tv.vertices:
            sc = 1 + abs(v.x) + abs(v.y) + v.radius
            G = [site_geometry(s) for s in t]
            r = refine_vertex(G, v.x + 1e-3, v.y - 1e-3)
            assert r is not None and math.hypot(r[0] - v.x, r[1] - v.y) < 1e-9 * sc
            proof = certify_vertex(t, G, r[0], r[1])
            assert proof.certified and proof.method == "krawczyk-circles", proof.reason
            assert _in_box(proof, v.x, v.y, v.radius, 1e-12 * sc)
            n += 1
    assert n >= 4
    proofs = certify_vertices_circles([triples[0]], np.array([[2.0, 0.8333333333333334]]))
    assert proofs[0].certified and abs(proofs[0].y - 5 / 6) < 1e-15


def test_certify_empty_on_corrupted_radius():
    """certify_empty proves a far site outside; it must refuse when the radius bounds are
    corrupted to reach that site."""
    sites = [Point(0, 0), Point(4, 0), Point(2, 3)]
    proof = certify_vertex(sites, None, 2.0, 5 / 6)
    assert proof.certified
    far = site_geometry(Conic.ellipse(centre=(10, 0), axes=(2, 1)))
    near = site_geometry(Conic.ellipse(centre=(2, "5/6"), axes=("1/2", "1/4")))
    ok, und = certify_empty([far, near], proof)
    assert not ok and und == [1]
    ok, und = certify_empty([far], proof)
    assert ok and und == []
    bad_r = (proof.radius_bounds[0], 7.0)         # reaches the far ellipse (distance ~6.06)
    ok, und = certify_empty([far], proof.box, None, bad_r)
    assert not ok and und == [0]
    # the point form (degenerate box)
    ok, und = certify_empty([far], proof.x, proof.y, proof.radius_bounds)
    assert ok


def test_refine_fails_cleanly():
    sites = [Point(0, 0), Point(1, 0), Point(2, 0)]    # collinear: no vertex
    G = [site_geometry(s) for s in sites]
    assert refine_vertex(G, 1.0, 5.0) is None
    proof = certify_vertex(sites, G, 1.0, 5.0)
    assert not proof.certified and proof.reason


def test_corrupted_site_is_not_certified_at_the_old_vertex():
    """The vertex of (C1, C2, C3) is not certified for a triple whose third site is moved by
    1e-5: either the proof fails or its box excludes the old vertex."""
    case = next(c for c in CASES if c.group == "four_ellipses" and c.vertices)
    e = case.vertices[0].as_floats()
    c3 = case.conics[2]
    a, b, c, d, e_, f = c3.coefficients
    # translate by (1e-5, 0): f(x − t, y)
    t = Fraction(1, 10 ** 5)
    moved = Conic.from_coefficients(a, b, c, d - 2 * a * t, e_ - b * t, f - d * t + a * t * t)
    sites = [case.conics[0], case.conics[1], moved]
    proof = certify_vertex(sites, None, e["x"], e["y"])
    assert not proof.certified or not _in_box(proof, e["x"], e["y"], e["radius"], 0.0)
    # the moved triple has its own vertex nearby, proved, and it excludes the old one
    G = [site_geometry(s) for s in sites]
    r = refine_vertex(G, e["x"], e["y"])
    proof = certify_vertex(sites, G, r[0], r[1])
    assert proof.certified and not _in_box(proof, e["x"], e["y"], e["radius"], 0.0)


def test_random_circle_point_triples_against_the_exact_locator():
    rng = np.random.default_rng(11)
    n = 0
    while n < 40:
        sites = []
        for _ in range(3):
            cx, cy = (int(v) for v in rng.integers(-20, 21, size=2))
            r2 = int(rng.integers(0, 4))
            sites.append(Point(cx, cy) if r2 == 0 else Circle(cx, cy, r2))
        try:
            tv = voronoi_vertices_circles(*sites)
        except Exception:   # identical or intersecting random sites
            continue
        G = [site_geometry(s) for s in sites]
        for v in tv.vertices:
            sc = 1 + abs(v.x) + abs(v.y) + v.radius
            r = refine_vertex(G, v.x * (1 + 1e-5), v.y - 1e-5 * sc)
            assert r is not None and math.hypot(r[0] - v.x, r[1] - v.y) < 1e-8 * sc
            proof = certify_vertex(sites, G, r[0], r[1])
            assert proof.certified, proof.reason
            assert _in_box(proof, v.x, v.y, v.radius, 1e-12 * sc)
            n += 1


def test_random_conic_triples_against_the_triple_locator():
    """Random ellipse / hyperbola / parabola triples: every true vertex of the independent
    triple solver (runtime.predicates.locator.voronoi_vertices, Macaulay null space) is refined from a
    seed 1e-4 off and certified, and the proof contains the solver's vertex."""
    from curvedvoronoi.runtime.predicates.locator import voronoi_vertices

    def rot(m, k):
        h = m * m + k * k
        return (Fraction(m * m - k * k, h), Fraction(2 * m * k, h))

    triples = [
        (Conic.ellipse(centre=(0, 0), axes=(2, 1), rotation=rot(2, 1)),
         Conic.parabola(vertex=(5, 1), p="1/2", rotation=rot(1, 2)),
         Conic.hyperbola(centre=(1, 6), axes=(1, "1/2"), rotation=rot(3, 1))),
    ]
    total = 0
    for cs in triples:
        tv = voronoi_vertices(*cs)
        G = [site_geometry(c) for c in cs]
        for v in tv.vertices:
            sc = 1 + abs(v.x) + abs(v.y) + v.radius
            r = refine_vertex(G, v.x + 1e-4 * sc, v.y - 1e-4 * sc)
            assert r is not None and math.hypot(r[0] - v.x, r[1] - v.y) < 1e-8 * sc
            proof = certify_vertex(cs, G, r[0], r[1])
            assert proof.certified, proof.reason
            assert _in_box(proof, v.x, v.y, v.radius, 1e-10 * sc)
            total += 1
    assert total >= 1
