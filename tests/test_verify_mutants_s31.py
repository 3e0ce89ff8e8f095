"""Wrong diagrams that only the verifier's exact routes can refuse, and the circle route's
Jacobian enclosure, written against hand-made weakenings of runtime/voronoi/verify (edge_checks,
exact_edges, vertices) that the other tests let through (bench/results/mutation.md).  Each test
asserts a fact derived by hand below, in exact arithmetic, never the verifier's own output.

* A wrong edge whose third site is nearer by far less than the floats resolve.  Points
  A = (0, 0), B = (2, 0), C = (1, ε), ε = 2⁻⁴⁰: the circle through them (thesis §1.2, the empty
  circle of a Delaunay triangle) is centred at V = (1, y₀), y₀ = (ε² − 1)/(2ε) ≈ −5.5·10¹¹.  On
  the bisector x = 1 of A and B, d_C² − d_A² = (y − ε)² − (1 + y²) = −2ε(y − y₀), negative for
  every y ∈ (y₀, ε): above V, C is strictly nearer than A and B, so the edge of A, B drawn from V
  upwards is no Voronoi edge.  On the first seven eighths of the way from V to the line AB
  (y₀ < y ≤ y₀/8), d_C + d_A ≥ 2|y| ≥ |y₀|/4, so |d_C − d_A| = 2ε(y − y₀)/(d_C + d_A) ≤ 7ε < 10⁻¹¹
  while the distances exceed 6·10¹⁰ (float resolution ~10⁻⁵): the floats cannot tell the sign
  there, and only an exact decision refuses the edge (its own flag must be False, whatever else
  refuses the diagram).  The same with C the circle of radius ρ = 1/4 centred at (1, ε + ρ), its
  lowest point (1, ε) (the exact circle route): for y < ε, d_C = ε − y and d_A = √(1 + y²), so
  d_C < d_A iff (ε − y)² < 1 + y², the same condition, the same V; above V, C is nearer all the
  way up (for y > ε + ρ, d_C = y − ε − 2ρ < y < d_A), so V is the only vertex.  (The true
  diagram of that triple is certified through the slope of d_C − d_A at V,
  tests/test_circle_edge_clear.py; here only the refusal of the wrong edge is asserted.)

* A far ray cut by a site that is not one of its vertex's.  With A, B, C as above (points) and
  D = (3, −ε): on x = 1, f_D(y) = |q − D|² − |q − A|² = 4 + (y + ε)² − (1 + y²) = 3 + 2εy + ε²,
  positive at V (f_D(y₀) = 2 + 2ε²: D is outside V's empty circle, V stays a vertex) and negative
  below y₁ = −(3 + ε²)/(2ε) < y₀: the ray of A, B from V downwards holds points where D is
  strictly nearer, so in the diagram of A, B, C with D added as a fourth site that ray is no edge
  (the edge of A, B ends at the vertex (1, y₁) of A, B, D; the four points' own diagram, with
  that vertex, is certified).

* The tails after an exact decision.  The same ray with two more points: D' = (3, ε), farther on
  the whole ray (f_D'(y) = 3 − 2εy + ε² > 0 for y < 0) but within 10⁻¹¹ of A's distance on its
  first stretch (f_D' ≤ 5 there while the distances are ~10¹²), so that only the exact route
  decides it; and E = (1 + 2³⁰, −η), X = 2⁶⁰ − 1, η = εX/4: f_E(y) = X + 2ηy + η² is ≥ X/2 on the
  stretch y ∈ [2y₀, y₀] (E clearly farther there, f_E(y₀) > 0: V stays empty) and negative below
  y_E = −(X + η²)/(2η) ≈ −2⁴¹ = 4y₀, where E cuts the ray's tail (d_E − d_A → −η ≈ −2.7·10⁸
  along it).  The ray is no edge however the exact decision of D' comes out.

* A dip between two vertices (the exact circle route).  Circles i, j of radius 1 centred (∓2, 0),
  points a = (0, 5), b = (0, −5): the edge of i, j is the segment of x = 0 between the vertices
  (0, ±8/3) of (i, j, a) and (i, j, b) (|(0, 8/3) − (0, 5)| = 7/3 = √(4 + 64/9) − 1).  A fifth site,
  the point k = (1 − δ, 0), δ = 2⁻⁶⁰, is nearer than i and j at the origin, a point of that edge
  (d_k = 1 − δ < 1 = d_i), and farther at both vertices (|k − (0, ±8/3)|² = (1 − δ)² + 64/9 >
  49/9 = (7/3)²): it cuts the edge in a dip of depth δ between two vertices of (i, j, k) (added as
  a site to the diagram of i, j, a, b).  Far below the floats; only the exact circle route
  (:func:`circle_edge_clear`: a vertex of (i, j, k) strictly between the edge's ends) refuses it.
  Without b the edge of i, j runs from (0, 8/3) down to infinity (or, with a = (0, −5), from
  (0, −8/3) up), and k cuts its tail the same way (a vertex of (i, j, k) beyond the vertex end);
  without a and b it is the whole line x = 0, and k cuts it all the same.

* A circle that its centre does not represent.  Points A = (0, 0), B = (2, 0), C = (1, 1): the
  edge of A, B is the ray x = 1, y ≤ 0, from the vertex (1, 0).  Add the circle K of radius
  ρ = 1/2 + 2⁻⁶⁰ centred (3, 1/2): its centre is farther than A on the whole ray (f = |q − c_K|² −
  |q − A|² = 3 − y + 1/4 > 0 for y ≤ 0), but K itself is nearer far out: d_K − d_A → 1/2 − ρ = −2⁻⁶⁰
  (at (1, −2⁶²): 3 + 1/4 − ρ² + 2⁶² < 2ρ√(1 + 2¹²⁴), checked in Fractions), so the ray is no edge;
  the floats see a tie at infinity, and only the exact circle route refuses it (the points' route,
  which takes K for its centre, would accept it).  With one more circle K′ of radius 1/2 − 2⁻⁶⁰
  centred (−1, 1/2) listed before K, tied at infinity the other way (d_K′ − d_A → +2⁻⁶⁰) and farther
  on the whole ray (|q − c_K′| − |q − A| > 1/2 > ρ′ there: 4 + (|y| + 1/2)² > (1/2 + √(1 + y²))²
  ⟺ 3 + |y| > √(1 + y²)), the exact decision of K′ must not exempt K with it.
"""
from __future__ import annotations

import copy
from fractions import Fraction as F

import pytest

from curvedvoronoi.runtime.predicates.circles import Circle, Point


def _doc(sites):
    from curvedvoronoi.runtime.voronoi.construction import voronoi

    return voronoi(sites, certify=False).to_json()


@pytest.mark.parametrize("rho", [F(0), F(1, 4)])
def test_an_edge_cut_by_a_third_site_below_the_float_resolution_is_refused(rho):
    from curvedvoronoi.runtime.voronoi.verify.certificate import verify

    eps = F(1, 2 ** 40)
    y0 = (eps * eps - 1) / (2 * eps)
    doc = _doc([Point(0, 0), Point(2, 0), Point(1, eps) if rho == 0 else Circle.from_radius(1, eps + rho, rho)])
    (v,) = doc["vertices"]
    assert sorted(v["sites"]) == [0, 1, 2]
    assert abs(F(v["x"]) - 1) <= 1e-9 and abs(F(v["y"]) - y0) <= 1e-9 * abs(y0)
    e = next(e for e in doc["edges"] if sorted(e["sites"]) == [0, 1])
    pos = doc["edges"].index(e)
    if rho == 0:
        assert verify(doc).ok        # the true diagram: the edge of A, B goes down from V
    for step in (10.0, 1e3, 1e6):    # the polyline's second point fixes the direction: upwards
        d = copy.deepcopy(doc)
        d["edges"][pos]["polyline"] = [[v["x"], v["y"]], [v["x"], v["y"] + step]]
        # the fact: at every point (1, y), y0 < y < ε, of the drawn edge C is strictly nearer than A
        y = F(v["y"]) + F(step)
        assert y0 < y < eps and (y - eps) ** 2 < 1 + y * y
        cert = verify(d)
        assert not cert.ok and not cert.edges[pos], (cert.edges, cert.problems)
        assert any(p.startswith(f"edge {e['id']} ") for p in cert.problems), cert.problems


# ----------------------------------------------------------------------------- the circle route's Jacobian box

def test_the_circle_routes_jacobian_enclosure_holds_on_its_whole_cube(monkeypatch):
    """:func:`runtime.voronoi.verify.vertices._krawczyk` hands the kernel's Krawczyk test
    (Krawczyk 1969; Moore, Kearfott & Cloud §8.2) a radius J_rad such that every Jacobian of
    F_l(x, y, r) = |q − c_l|² − (r + ρ_l)² on the cube Z̃ + [−ρ, ρ]³ lies within J_rad of the float
    J̃ at Z̃, entrywise (thesis §3.1.3: the circle/point vertex system).  J's entries are affine in
    one coordinate each, ∂(2(x − c_x))/∂x = 2: at a corner z = Z̃ + ρ·s (s ∈ {±1}³) the exact
    J(z) − J̃ = (2(Z̃ − c) − J̃) + 2ρ·s, so the box term must be 2ρ, not ρ.  Checked in Fractions
    (the float data read exactly) at the eight corners of every cube tried, and on a random
    interior point; the test is not vacuous: on most rows the Jacobian moves by more than 1.5ρ
    over the cube and ρ exceeds the data's rounding by far."""
    import numpy as np

    from curvedvoronoi.runtime.voronoi.verify import vertices as V

    seen = []
    real_bound, real_test = V.float_contraction_bound, V.float_krawczyk_test

    def bound(Y, J, J_rad):
        seen.append([np.array(J, float), np.array(J_rad, float), None])
        return real_bound(Y, J, J_rad)

    def test(b, Delta, r):
        seen[-1][2] = np.array(r, float)
        return real_test(b, Delta, r)

    monkeypatch.setattr(V, "float_contraction_bound", bound)
    monkeypatch.setattr(V, "float_krawczyk_test", test)
    rng = np.random.default_rng(31)
    n = 60
    # triples built around a known vertex (q, r): c_l = q + (r + ρ_l)(cos θ_l, sin θ_l), the angles
    # spread or bunched within 10⁻⁶…10⁻² (nearly collinear sites, a nearly singular Jacobian)
    q = rng.uniform(-10, 10, (n, 2))
    r = rng.uniform(0.5, 20, (n, 1)) * 10.0 ** rng.integers(0, 3, (n, 1))
    Rho = rng.uniform(0, 1, (n, 3)) * rng.integers(0, 2, (n, 1))         # half of them points
    spread = np.where(rng.integers(0, 2, (n, 1)) == 1, 10.0 ** rng.uniform(-6, -2, (n, 1)), 2.0)
    th = rng.uniform(0, 2 * np.pi, (n, 1)) + spread * rng.uniform(-1, 1, (n, 3))
    C = q[:, None, :] + (r + Rho)[..., None] * np.stack([np.cos(th), np.sin(th)], -1)
    Z0 = np.concatenate([q, r], -1) * (1 + 1e-9 * rng.normal(size=(n, 3)))
    ok, Z, H = V._krawczyk(C, Rho, Z0, 20.0)
    assert seen
    wide = 0
    checked = 0
    for J, J_rad, rho in seen:
        for m in range(n):
            if not (np.isfinite(Z[m]).all() and np.isfinite(J[m]).all() and np.isfinite(J_rad[m]).all()):
                continue
            r_ = F(float(rho[m, 0]))
            assert (rho[m] == rho[m, 0]).all()
            Zm = [F(float(v)) for v in Z[m]]
            corners = [[Zm[a] + s[a] * r_ for a in range(3)] for s in
                       [(sx, sy, sr) for sx in (-1, 1) for sy in (-1, 1) for sr in (-1, 1)]]
            w = rng.uniform(-1, 1, 3)
            corners.append([Zm[a] + F(float(w[a])) * r_ for a in range(3)])
            dev = 0
            for z in corners:
                for l in range(3):
                    exact = (2 * (z[0] - F(float(C[m, l, 0]))), 2 * (z[1] - F(float(C[m, l, 1]))),
                             -2 * (z[2] + F(float(Rho[m, l]))))
                    for a in range(3):
                        d_ = abs(exact[a] - F(float(J[m, l, a])))
                        assert d_ <= F(float(J_rad[m, l, a])), (m, l, a)
                        dev = max(dev, d_)
            checked += 1
            # not vacuous: the Jacobian moves by more than 1.5ρ over the cube, and ρ is more than 64
            # units in the last place of the data (so ρ plus a rounding allowance would not cover it)
            mag = float(np.abs(Z[m]).sum() + np.abs(C[m]).sum() + Rho[m].sum())
            wide += bool(dev > F(3, 2) * r_ and float(rho[m, 0]) > 64 * 2.0 ** -53 * mag)
    assert ok.sum() > n // 4 and checked > 100 and wide > checked // 2, (ok.sum(), checked, wide)


def test_a_far_ray_cut_by_another_site_is_refused():
    from curvedvoronoi.runtime.voronoi.verify.certificate import verify

    eps = F(1, 2 ** 40)
    y0 = (eps * eps - 1) / (2 * eps)
    y1 = -(3 + eps * eps) / (2 * eps)
    f_D = lambda y: 3 + 2 * eps * y + eps * eps          # |q − D|² − |q − A|² at q = (1, y)
    assert f_D(y0) > 0 and f_D(y1) == 0 and f_D(y1 - 1) < 0 and y1 < y0
    sites = [Point(0, 0), Point(2, 0), Point(1, eps)]
    doc = _doc(sites)
    (v,) = doc["vertices"]
    assert abs(F(v["y"]) - y0) <= 1e-9 * abs(y0)
    e = next(e for e in doc["edges"] if sorted(e["sites"]) == [0, 1])
    pos = doc["edges"].index(e)
    assert e["ends"][1] is None and e["polyline"][-1][1] < v["y"]       # the ray from V downwards
    d = copy.deepcopy(doc)
    d["sites"].append({"point": ["3", str(-eps)]})
    cert = verify(d)
    assert not cert.ok and not cert.edges[pos], (cert.edges, cert.problems)
    assert any(p.startswith(f"edge {e['id']} ") for p in cert.problems), cert.problems
    # the four points' own diagram: the edge of A, B ends at (1, y1), and it is certified
    doc4 = _doc(sites + [Point(3, -eps)])
    w = next(w for w in doc4["vertices"] if sorted(w["sites"]) == [0, 1, 3])
    assert abs(F(w["y"]) - y1) <= 1e-9 * abs(y1) and abs(F(w["x"]) - 1) <= 1e-9
    assert verify(doc4).ok


def test_the_tail_is_still_searched_after_an_exact_decision():
    from curvedvoronoi.runtime.voronoi.verify.certificate import verify

    eps = F(1, 2 ** 40)
    y0 = (eps * eps - 1) / (2 * eps)
    X = F(2 ** 60 - 1)
    eta = eps * X / 4
    f_D = lambda y: 3 - 2 * eps * y + eps * eps             # D' = (3, ε)
    f_E = lambda y: X + 2 * eta * y + eta * eta             # E = (1 + 2^30, −η)
    yE = -(X + eta * eta) / (2 * eta)
    assert f_D(y0) > 0 and f_D(2 * y0) > 0 and f_D(2 * y0) <= 5     # affine: > 0 on the whole ray
    assert f_E(y0) > 0 and f_E(2 * y0) >= X / 2 and yE < 2 * y0 and f_E(yE - 1) < 0
    doc = _doc([Point(0, 0), Point(2, 0), Point(1, eps)])
    e = next(e for e in doc["edges"] if sorted(e["sites"]) == [0, 1])
    pos = doc["edges"].index(e)
    d = copy.deepcopy(doc)
    d["sites"] += [{"point": ["3", str(eps)]}, {"point": [str(1 + 2 ** 30), str(-eta)]}]
    cert = verify(d)
    assert not cert.ok and not cert.edges[pos], (cert.edges, cert.problems)
    assert any(p.startswith(f"edge {e['id']} ") for p in cert.problems), cert.problems


@pytest.mark.parametrize("bounded, side", [(True, 1), (False, 1), (False, -1), (False, 0)])
def test_a_dip_of_a_point_between_two_vertices_of_circles_is_refused(bounded, side):
    from curvedvoronoi.runtime.voronoi.verify.certificate import verify

    delta = F(1, 2 ** 60)
    k = (1 - delta, F(0))
    u = (F(0), F(8, 3))
    # the vertex (0, 8/3): |u − a| = 7/3 and |u − c_i| − 1 = √(4 + 64/9) − 1 = 10/3 − 1 = 7/3
    assert abs(u[1] - 5) == F(7, 3) and (F(10, 3)) ** 2 == 4 + u[1] ** 2
    assert k[0] ** 2 + u[1] ** 2 > F(7, 3) ** 2            # k farther than i, j at both vertices
    assert k[0] < 1                                         # d_k(0, 0) = 1 − δ < 1 = d_i(0, 0)
    doc = _doc([Circle.from_radius(-2, 0, 1), Circle.from_radius(2, 0, 1)] + [Point(0, 5 * side)] * abs(side)
               + [Point(0, -5)] * bounded)
    e = next(e for e in doc["edges"] if sorted(e["sites"]) == [0, 1])
    pos = doc["edges"].index(e)
    ends = [next(v for v in doc["vertices"] if v["id"] == t) for t in e["ends"] if t is not None]
    assert sorted(round(v["y"] * 3) for v in ends) == ([-8, 8] if bounded else [8 * side] if side else [])
    assert all(abs(v["x"]) < 1e-9 for v in ends) and len(e["ends"]) == 2
    if side and not bounded:      # the end at infinity is away from a, past the origin
        assert min(p[1] * side for p in e["polyline"]) < 0
    assert verify(doc).ok
    d = copy.deepcopy(doc)
    d["sites"].append({"point": [str(k[0]), "0"]})
    cert = verify(d)
    assert not cert.ok and not cert.edges[pos], (cert.edges, cert.problems)
    assert any(p.startswith(f"edge {e['id']} ") for p in cert.problems), cert.problems


@pytest.mark.parametrize("with_tied_farther_circle", [False, True])
def test_a_circle_cutting_a_ray_far_out_is_not_taken_for_its_centre(with_tied_farther_circle):
    from curvedvoronoi.runtime.voronoi.verify.certificate import verify

    rho = F(1, 2) + F(1, 2 ** 60)
    y = -F(2 ** 62)
    lhs = 3 + F(1, 4) - rho * rho - y                      # 4 + (y − 1/2)² − ρ² − 1 − y², y < 0
    assert lhs > 0 and lhs * lhs < 4 * rho * rho * (1 + y * y)        # d_K < d_A at (1, y)
    assert all(3 - t + F(1, 4) > 0 for t in (F(0), y))                 # the centre farther (affine in y)
    doc = _doc([Point(0, 0), Point(2, 0), Point(1, 1)])
    e = next(e for e in doc["edges"] if sorted(e["sites"]) == [0, 1])
    pos = doc["edges"].index(e)
    (v,) = doc["vertices"]
    assert abs(v["x"] - 1) < 1e-12 and abs(v["y"]) < 1e-12 and e["polyline"][-1][1] < 0
    d = copy.deepcopy(doc)
    if with_tied_farther_circle:
        r2 = F(1, 2) - F(1, 2 ** 60)
        d["sites"].append({"circle": {"centre": ["-1", "1/2"], "radius_squared": str(r2 * r2)}})
    d["sites"].append({"circle": {"centre": ["3", "1/2"], "radius_squared": str(rho * rho)}})
    cert = verify(d)
    assert not cert.ok and not cert.edges[pos], (cert.edges, cert.problems)
    assert any(p.startswith(f"edge {e['id']} ") for p in cert.problems), cert.problems
