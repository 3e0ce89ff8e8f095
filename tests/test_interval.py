"""Tests of the interval-analysis conflict locator (thesis ch. 6, §3.3.3, App. D).

Run: OPENBLAS_NUM_THREADS=1 python -m pytest -q tests/test_interval.py
The route runs with its default search domain, computed from the sites alone (a proved bound on
the vertices when the sites are bounded, runtime/interval/bound.py).  In CI, INTERVAL_N (1) random
circle configurations drawn with the session seed printed in the pytest header
(CURVEDVORONOI_TEST_SEED) are compared with the exact circle locator; set INTERVAL_ALL=1 to also
run every validation case the offset formulation accepts (slow: minutes per case).
"""
from __future__ import annotations

import json
import math
import os
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from flint import arb
from hypothesis import given, settings, strategies as st

from curvedvoronoi.runtime.validation import required_cases_path as _validation_path
from curvedvoronoi.runtime.predicates.circles import Circle, locate_conflicts_circles, voronoi_vertices_circles
from curvedvoronoi.runtime.sites.conic import Conic
from curvedvoronoi.runtime.interval import (default_domain, locate_conflicts_interval, locate_conflicts_semialgebraic,
                                            search_domain)
from curvedvoronoi.runtime.interval.bound import support_function, vertex_bound
from curvedvoronoi.runtime.interval.curves import parse_curve
from curvedvoronoi.runtime.predicates.locator import locate_conflicts
from curvedvoronoi.runtime.result import LocatorError
from curvedvoronoi.runtime.interval.boxes import Box, arb_hi, arb_lo, interval_arb
from curvedvoronoi.runtime.interval.offsets import canonical_offset, conic_offset
from curvedvoronoi.runtime.interval.poly import Poly, taylor_form
from curvedvoronoi.runtime.interval.solver import System, krawczyk, solve

DATA = _validation_path()
XY = ("x", "y")


# ---------------------------------------------------------------------- interval core
def _circle_hyperbola():
    return System(XY, 2, [Poly.from_sympy("x**2 + y**2 - 4", XY), Poly.from_sympy("x*y - 1", XY)])


def test_krawczyk_proves_unique_root():
    s = _circle_hyperbola()
    # root (sqrt(2+sqrt3), sqrt(2-sqrt3)) = (1.9318516..., 0.5176380...)
    st_, nb = krawczyk(s, Box.from_bounds([(1.8, 2.05), (0.4, 0.65)]))
    assert st_ == "unique"
    x = math.sqrt(2 + math.sqrt(3))
    assert nb.lo[0] <= x <= nb.hi[0]


def test_krawczyk_rejects_box_without_root():
    s = _circle_hyperbola()
    st_, nb = krawczyk(s, Box.from_bounds([(1.45, 1.55), (0.95, 1.05)]))  # x²+y² < 3.5 there: no root
    assert st_ == "empty" and nb is None
    res = solve(s, Box.from_bounds([(2.5, 3), (2.5, 3)]))
    assert res.solutions == [] and res.complete


def test_branch_and_prune_all_strategies_find_four_roots():
    s = _circle_hyperbola()
    for b in ("round-robin", "largest", "smear", "mixed", "full"):
        res = solve(s, Box.from_bounds([(-3, 3), (-3, 3)]), bisection=b)
        assert res.complete and len(res.solutions) == 4, b
        for sol in res.solutions:
            x, y = sol.point
            assert abs(x * y - 1) < 1e-12 and max(sol.tight.width) < 1e-12


def test_box_budget_gives_undecided_not_roots():
    res = solve(_circle_hyperbola(), Box.from_bounds([(-3, 3), (-3, 3)]), max_boxes=3)
    assert res.exhausted and not res.complete and res.undecided


@settings(max_examples=40, deadline=None)
@given(st.lists(st.integers(-5, 5), min_size=6, max_size=6),
       st.floats(-2, 2), st.floats(-2, 2), st.floats(0, 0.5), st.floats(0, 0.5))
def test_horner_and_taylor_forms_enclose(coeffs, mx, my, wx, wy):
    p = Poly(XY, {(2, 1): coeffs[0], (0, 3): coeffs[1], (1, 1): coeffs[2], (1, 0): coeffs[3], (0, 2): coeffs[4],
                  (0, 0): coeffs[5]})
    box = Box.from_bounds([(mx - wx, mx + wx), (my - wy, my + wy)])
    nat = p.arb_eval(*box.arbs())
    tf = taylor_form(p, [Fraction(mx), Fraction(my)])
    rho = np.array([wx, wy]) * (1 + 1e-15) + 1e-300
    tay = tf.value(rho)
    grad = tf.gradient(rho)
    for t in np.linspace(0, 1, 5):
        for u in np.linspace(0, 1, 5):
            x = Fraction(mx - wx + 2 * wx * t)
            y = Fraction(my - wy + 2 * wy * u)
            v = p(x, y)
            assert arb_lo(nat) <= v <= arb_hi(nat)
            assert arb_lo(tay) <= v <= arb_hi(tay)
            gx, gy = p.diff(0)(x, y), p.diff(1)(x, y)
            assert arb_lo(grad[0]) <= gx <= arb_hi(grad[0]) and arb_lo(grad[1]) <= gy <= arb_hi(grad[1])


def test_interval_conversion_outward():
    for lo, hi in [(0.1, 0.3), (-1e-300, 1e300), (1 / 3, 1 / 3)]:
        a = interval_arb(lo, hi)
        assert arb_lo(a) <= lo and arb_hi(a) >= hi
    third = arb(1) / 3
    assert arb_lo(third) < Fraction(1, 3) < arb_hi(third)


# ---------------------------------------------------------------------- offsets
def test_canonical_offsets_sizes():
    assert len(canonical_offset("ellipse_hyperbola").terms) == 104  # DESIGN.md §5, App. B.4
    assert len(canonical_offset("parabola").terms) == 23             # App. B.3


@settings(max_examples=15, deadline=None)
@given(st.integers(1, 12), st.integers(1, 12), st.sampled_from([(3, 4, 5), (5, 12, 13), (8, 15, 17), (1, 0, 1)]),
       st.integers(-5, 5), st.fractions(-3, 3, max_denominator=7))
def test_moved_offset_vanishes_on_offset_points(a, b, trip, t, k):
    """o(x, y, r) of a rigidly moved ellipse vanishes at p + k∇f(p), r = k²|∇f|² (exact)."""
    c, s, h = trip
    cos, sin = Fraction(c, h), Fraction(s, h)
    A2, B2 = Fraction(a * a), Fraction(b * b) if b != a else Fraction(b * b + 1)
    # rational point on X²/A2 + Y²/B2 = 1 : X = a(1-m²)/(1+m²), Y = b' 2m/(1+m²)
    m = Fraction(t, 3)
    X = a * (1 - m * m) / (1 + m * m)
    Y = Fraction(2) * m / (1 + m * m)
    B2 = Fraction(1) if A2 != 1 else Fraction(4, 1)
    if B2 == 4:
        Y *= 2
    tx, ty = Fraction(1, 3), Fraction(-2, 5)
    o = conic_offset("ellipse", {"A2": A2, "B2": B2}, cos, sin, tx, ty)
    gX, gY = 2 * X / A2, 2 * Y / B2
    PX, PY = X + k * gX, Y + k * gY
    r = k * k * (gX * gX + gY * gY)
    x = cos * PX - sin * PY + tx
    y = sin * PX + cos * PY + ty
    assert o(x, y, r) == 0


# ---------------------------------------------------------------------- proved vertex bound
CASES = json.loads(DATA.read_text())["cases"]


def _case(name):
    return next(c for c in CASES if c["name"] == name)


def _far_circles():
    """Four unit circles; the only vertex of the first three is at (10, -4999.995), in conflict."""
    return [Conic.circle(centre=(0, 0), radius=1), Conic.circle(centre=(10, Fraction(1, 100)), radius=1),
            Conic.circle(centre=(20, 0), radius=1), Conic.circle(centre=(10, -30), radius=1)]


def _in_box(box, x, y):
    return box[0] <= x <= box[1] and box[2] <= y <= box[3]


def test_vertex_bound_contains_every_validation_vertex():
    """The bound is computed from the sites alone; the vertices come from the vendored,
    independently computed validation answers."""
    bounded = 0
    for case in CASES:
        sites = [parse_curve(k) for k in case["conics"][:3]]
        b = vertex_bound(sites)
        kinds = {k["canonical"]["type"] for k in case["conics"][:3]}
        if not kinds <= {"ellipse", "circle"}:
            assert b is None, case["name"]      # an unbounded site: nothing is proved
            continue
        assert b is not None, case["name"]
        bounded += 1
        for v in case["vertices"]:
            assert _in_box(b.box(), float(v["x"]), float(v["y"])), (case["name"], v["x"], v["y"], b.box())
    assert bounded == 10


def test_vertex_bound_contains_the_far_vertex():
    b = vertex_bound([parse_curve(c) for c in _far_circles()])
    assert b is not None and _in_box(b.box(), 10, -4999.995)
    # the box "around the data" does not: that is how the interval route used to miss it
    assert not _in_box(default_domain([parse_curve(c) for c in _far_circles()]), 10, -4999.995)


def test_vertex_bound_refuses_unbounded_and_collinear():
    parabola = Conic.parabola(vertex=(0, 5), p=1, rotation=(1, 0))
    circles = _far_circles()
    assert vertex_bound([parse_curve(c) for c in (circles[0], circles[1], parabola)]) is None
    # equal circles on a line: the bisectors are parallel, the "vertex" is at infinity
    line = [Conic.circle(centre=(5 * k, 0), radius=1) for k in range(3)]
    assert vertex_bound([parse_curve(c) for c in line]) is None


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.integers(-20, 20), st.integers(-20, 20), st.integers(1, 12)), min_size=3, max_size=3),
       st.integers(-3, 3))
def test_vertex_bound_contains_exact_circle_vertices(spec, tilt):
    """Random circle triples, including nearly collinear centres (vertices far away): every
    vertex of the exact circle locator (thesis §3.1.3, no code shared with the bound) lies in
    the bound's box."""
    cs = [Conic.circle(centre=(Fraction(x, 2), Fraction(y, 2)), radius=Fraction(r, 4)) for x, y, r in spec]
    if tilt:   # nearly collinear: middle centre lifted by tilt/100 off the line of the others
        (x0, y0), (x2, y2) = (Fraction(spec[0][0], 2), Fraction(spec[0][1], 2)), (Fraction(spec[2][0], 2),
                                                                                 Fraction(spec[2][1], 2))
        cs[1] = Conic.circle(centre=((x0 + x2) / 2, (y0 + y2) / 2 + Fraction(tilt, 100)), radius=Fraction(spec[1][2], 4))
    try:
        tv = voronoi_vertices_circles(*(Circle.from_coefficients(*c.coefficients) for c in cs))
    except LocatorError:
        return      # coincident circles or a continuum of equidistant points
    b = vertex_bound([parse_curve(c) for c in cs])
    if b is None:
        return
    for v in tv.vertices:
        assert _in_box(b.box(), v.x, v.y), (spec, tilt, v.x, v.y, b.box())


def test_default_search_domain_is_the_proved_bound():
    """Circles of radius 1/2 at (0, 0), (4, 0), (2, 1/4): the vertex is the circumcentre (2, −63/8) of
    the centres, outside the box around the data; the interval route's default domain holds it."""
    sites = [parse_curve(c) for c in (Conic.circle(centre=(0, 0), radius=Fraction(1, 2)),
                                      Conic.circle(centre=(4, 0), radius=Fraction(1, 2)),
                                      Conic.circle(centre=(2, Fraction(1, 4)), radius=Fraction(1, 2)))]
    dom, bound = search_domain(sites)
    assert bound is not None and bound.inside(dom) and _in_box(dom, 2, -63 / 8)
    assert not _in_box(default_domain(sites), 2, -63 / 8)
    far, far_bound = search_domain([parse_curve(c) for c in _far_circles()])
    assert far_bound is not None and _in_box(far, 10, -4999.995)


@settings(max_examples=25, deadline=None)
@given(st.integers(2, 12), st.integers(1, 12), st.sampled_from([(3, 4, 5), (5, 12, 13), (-8, 15, 17), (20, -21, 29)]),
       st.integers(-9, 9), st.integers(-9, 9))
def test_support_function_against_sampled_ellipse(a, b, rot, tx, ty):
    """h(u) = max over the ellipse of u·p, against a dense parametrisation of the rotated ellipse."""
    c, s_, h = rot
    e = Conic.ellipse(centre=(Fraction(tx, 3), Fraction(ty, 3)), axes=(Fraction(a, 4), Fraction(b, 5)),
                      rotation=(Fraction(c, h), Fraction(s_, h)))
    t = np.linspace(0, 2 * np.pi, 20001)
    X, Y = a / 4 * np.cos(t), b / 5 * np.sin(t)
    px = c / h * X - s_ / h * Y + tx / 3
    py = s_ / h * X + c / h * Y + ty / 3
    th = np.linspace(0, 2 * np.pi, 37)
    lo, hi = support_function(parse_curve(e), np.cos(th), np.sin(th))
    dense = np.max(np.outer(np.cos(th), px) + np.outer(np.sin(th), py), axis=1)
    assert np.all(hi >= dense - 1e-12) and np.all(lo <= dense + 1e-6 * max(a, b))


# ---------------------------------------------------------------------- honest flags of the interval route
def test_nearly_tangent_fourth_site_is_not_decided_wrongly():
    """C4 enters the empty circle of (2, 5/6), radius 7/6, by 1e-20 only: the intervals cannot
    decide, so the vertex must not be certified (its in_conflict is then a numerical guess), and a
    certified "no conflict" would be wrong."""
    q, r4, delta = (Fraction(2), Fraction(5, 6)), Fraction(1, 4), Fraction(1, 10 ** 20)
    d = Fraction(7, 6) + r4 - delta
    c4 = Conic.circle(centre=(q[0] + d * Fraction(3, 5), q[1] - d * Fraction(4, 5)), radius=r4)
    cs = [Conic.circle(centre=(0, 0), radius=1), Conic.circle(centre=(4, 0), radius=1),
          Conic.circle(centre=(2, 3), radius=1), c4]
    [v] = locate_conflicts_interval(*cs, domain=(1.5, 2.5, 0.5, 1.2)).vertices
    assert v.certified is False
    assert not (v.certified and v.in_conflict is False)



def test_interval_route_does_not_claim_a_box_that_misses_the_far_vertex():
    """Four unit circles whose one vertex is at (10, -4999.995), in conflict (exact route).  A
    search box around the data finds nothing there: the answer must not be complete/certified."""
    cs = _far_circles()
    exact = locate_conflicts(*cs)
    assert exact.method == "circles-exact" and exact.certified and exact.conflict
    assert [(round(v.x, 6), round(v.y, 6)) for v in exact.vertices] == [(10.0, -4999.995)]
    res = locate_conflicts(*cs, method="interval", domain=(-2, 22, -3, 3))
    assert res.vertices == [] and res.complete is False and res.certified is False
    assert "does not contain the proved bound" in res.notes[0]


def test_interval_route_on_unbounded_sites_is_never_complete():
    """Unbounded sites (a parabola): no proved bound, so complete=False even for a clean search
    that finds every vertex of the reference inside its box."""
    case = _case("mixed_CEP_circle4_noconflict")
    e = case["vertices"][0]
    x, y = float(e["x"]), float(e["y"])
    res = locate_conflicts_interval(*case["conics"], domain=(x - 0.05, x + 0.05, y - 0.05, y + 0.05))
    assert len(res.vertices) == 1 and res.vertices[0].certified
    assert abs(res.vertices[0].x - x) < 1e-8 and abs(res.vertices[0].y - y) < 1e-8
    assert res.complete is False and res.certified is False
    assert "no bound" in res.notes[0]


# ---------------------------------------------------------------------- validation cases, domain from the sites
def check_agreement(case, formulation="offset", **kw):
    """The interval route with its default domain (computed from the sites alone) against the
    vendored validation answers: with bounded sites it must be complete and find exactly the
    reference vertices; otherwise it is not complete, and every reference vertex inside its box is
    found and every vertex it reports is a reference vertex."""
    res = locate_conflicts_interval(*case["conics"], formulation=formulation, **kw)
    exp = sorted(case["vertices"], key=lambda v: (float(v["x"]), float(v["y"])))
    bounded = vertex_bound([parse_curve(k) for k in case["conics"][:3]]) is not None
    if bounded:
        assert res.complete, res.notes
    else:
        assert not res.complete and not res.certified
        box = default_domain([parse_curve(k) for k in case["conics"]])
        exp = [e for e in exp if _in_box(box, float(e["x"]), float(e["y"]))]
    assert len(res.vertices) == len(exp)
    for v, e in zip(res.vertices, exp):
        assert abs(v.x - float(e["x"])) < 1e-8 and abs(v.y - float(e["y"])) < 1e-8
        assert abs(v.radius - float(e["radius"])) < 1e-8
        if abs(float(e["margin"])) > 1e-6:
            assert v.certified
            assert v.in_conflict == e["in_conflict"]
        elif v.certified:
            assert v.in_conflict == e["in_conflict"]
        assert abs(v.distance_to_fourth - float(e["distance_to_fourth"])) < 1e-8
    if res.certified:
        assert res.conflict == case["conflict"]
    return res


def _offset_ok(case):
    return all(k["canonical"]["type"] in ("ellipse", "hyperbola", "parabola", "circle") for k in case["conics"][:3])


def test_validation_case_from_the_sites_alone():
    """circles_b (three circles, 3 vertices, one far below the data): complete from the sites alone
    (measured 6 s on an idle core) and equal to the vendored answers."""
    res = check_agreement(_case("circles_b_circle4_conflict"))
    assert res.certified and "contains the proved bound" in res.notes[0]


if os.environ.get("INTERVAL_ALL") == "1":   # slow (tens of seconds to minutes per case)
    @pytest.mark.slow
    @pytest.mark.parametrize("name", [c["name"] for c in CASES if c["vertices"] and _offset_ok(c)])
    def test_validation_all_cases(name):
        check_agreement(_case(name))


# ---------------------------------------------------------------------- against the exact circle locator
def _same_as_exact(cs, res):
    """The interval answer against the exact circle locator (thesis §3.1.3: algebra in a tower of
    quadratic extensions, no code shared with the branch-and-prune route)."""
    exact = locate_conflicts_circles(*(Circle.from_coefficients(*c.coefficients) for c in cs))
    assert exact.certified
    assert res.complete and res.certified, res.notes
    assert len(res.vertices) == len(exact.vertices)
    for v, e in zip(res.vertices, sorted(exact.vertices, key=lambda v: (v.x, v.y))):
        for a, b in ((v.x, e.x), (v.y, e.y), (v.radius, e.radius), (v.distance_to_fourth, e.distance_to_fourth)):
            assert abs(a - b) <= 1e-8 * max(1.0, abs(b))
        assert v.in_conflict is e.in_conflict
    assert res.conflict is exact.conflict


def test_interval_domain_from_the_sites_alone_circles():
    """Three unit circles centred at (0, 0), (4, 0), (2, 3): the interval route with its default
    domain (the proved bound) is complete and finds the one vertex, the circumcentre (2, 5/6) of the
    centres with radius 13/6 − 1 = 7/6, in conflict with the circle of radius 1/4 at (21/10, −1/2)."""
    cs = [Conic.circle(centre=(0, 0), radius=1), Conic.circle(centre=(4, 0), radius=1),
          Conic.circle(centre=(2, 3), radius=1),
          Conic.circle(centre=(Fraction(21, 10), Fraction(-1, 2)), radius=Fraction(1, 4))]
    res = locate_conflicts(*cs, method="interval")
    assert "contains the proved bound" in res.notes[0]
    [v] = res.vertices
    assert abs(v.x - 2) < 1e-12 and abs(v.y - 5 / 6) < 1e-12 and abs(v.radius - 7 / 6) < 1e-12
    assert abs(v.distance_to_fourth - (math.hypot(1 / 10, 4 / 3) - 1 / 4)) < 1e-12 and v.in_conflict is True
    _same_as_exact(cs, res)


def test_conflict_decided_when_the_vertex_is_right_above_c4():
    """The vertex (2, 5/6) and the centre of C4 share x = 2: the interval distance is a ball centred at
    0 (python-flint 0.9 returns nan for its ``** 2``); the conflict must still be decided."""
    cs = [Conic.circle(centre=(0, 0), radius=1), Conic.circle(centre=(4, 0), radius=1),
          Conic.circle(centre=(2, 3), radius=1), Conic.circle(centre=(2, Fraction(-1, 2)), radius=Fraction(1, 4))]
    [v] = locate_conflicts_interval(*cs, domain=(1.5, 2.5, 0.5, 1.2)).vertices
    assert v.certified and v.in_conflict is True and abs(v.distance_to_fourth - 13 / 12) < 1e-12


def _random_circles(rng):
    """Four circles with rational data; C1..C3 near the corners of a triangle of side ~4, so that
    the proved bound (and the search) stays small."""
    corners = [(0, 0), (4, 0), (2, 3)]
    out = []
    for cx, cy in corners:
        out.append(Conic.circle(centre=(Fraction(int(rng.integers(-5, 6)), 10) + cx,
                                        Fraction(int(rng.integers(-5, 6)), 10) + cy),
                                radius=Fraction(int(rng.integers(3, 11)), 10)))
    out.append(Conic.circle(centre=(Fraction(int(rng.integers(10, 31)), 10), Fraction(int(rng.integers(-10, 21)), 10)),
                            radius=Fraction(int(rng.integers(1, 6)), 10)))
    return out


INTERVAL_N = int(os.environ.get("INTERVAL_N", "1"))


@pytest.mark.slow
def test_interval_matches_exact_circles_sampled():
    """INTERVAL_N random circle configurations drawn with the session seed (CURVEDVORONOI_TEST_SEED,
    printed in the pytest header): the interval route from the sites alone, complete, equals the
    exact circle locator."""
    rng = np.random.default_rng([int(os.environ.get("CURVEDVORONOI_TEST_SEED", "0")), 6])
    for _ in range(INTERVAL_N):
        cs = _random_circles(rng)
        print("circles:", [(str(c.exact_frame.tx), str(c.exact_frame.ty), str(c.exact_frame.params)) for c in cs])
        _same_as_exact(cs, locate_conflicts_interval(*cs))


# ---------------------------------------------------------------------- semi-algebraic sites vs dense sampling
def _dense_reference(samplers, domain, n=170):
    from scipy.spatial import cKDTree

    trees = [cKDTree(s) for s in samplers]
    xs = np.linspace(domain[0], domain[1], n)
    ys = np.linspace(domain[2], domain[3], n)
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    P = np.column_stack([X.ravel(), Y.ravel()])
    D = [t.query(P)[0].reshape(X.shape) for t in trees[:3]]
    a, b = D[0] - D[1], D[0] - D[2]

    def change(F):
        c = np.stack([F[:-1, :-1], F[1:, :-1], F[:-1, 1:], F[1:, 1:]])
        return (c.min(0) <= 0) & (c.max(0) >= 0)

    cells = np.argwhere(change(a) & change(b))
    centres = [((xs[i] + xs[i + 1]) / 2, (ys[j] + ys[j + 1]) / 2) for i, j in cells]
    h = max(xs[1] - xs[0], ys[1] - ys[0])
    clusters: list[list] = []
    for c in centres:
        for cl in clusters:
            if any(math.dist(c, o) < 2.5 * h for o in cl):
                cl.append(c)
                break
        else:
            clusters.append([c])
    return [np.mean(cl, axis=0) for cl in clusters], h, trees


def _param(fn, t):
    return np.column_stack(fn(t))


@pytest.mark.slow                 # long check: `invoke test --slow` (not in the README/CI command)
def test_strophoid_with_three_conics_against_dense_sampling():
    """Fig. 4.1.1's strophoid y² = x² + x³ as C1 with three conics (original formulation)."""
    sites = ["y**2 - x**2 - x**3", "(x-1)**2 + (y-2)**2 - 1/4", "(x+1)**2/4 + (y-2)**2 - 1/9",
             "(x-1/4)**2 + (y-3/2)**2 - 1/100"]
    dom = (-0.05, 0.1, 1.15, 1.3)
    res = locate_conflicts_semialgebraic(sites, domain=dom, formulation="original")
    # the strophoid is unbounded: no proved bound on the vertices, so the box search is not complete
    assert res.complete is False and res.certified is False and all(v.certified for v in res.vertices)
    t = np.linspace(-1, 2.5, 200_000)
    th = np.linspace(0, 2 * np.pi, 100_000)
    strophoid = np.vstack([_param(lambda s: (s, s * np.sqrt(1 + s)), t), _param(lambda s: (s, -s * np.sqrt(1 + s)), t)])
    samplers = [strophoid, _param(lambda a: (1 + 0.5 * np.cos(a), 2 + 0.5 * np.sin(a)), th),
                _param(lambda a: (-1 + 2 / 3 * np.cos(a), 2 + 1 / 3 * np.sin(a)), th),
                _param(lambda a: (0.25 + 0.1 * np.cos(a), 1.5 + 0.1 * np.sin(a)), th)]
    ref, h, trees = _dense_reference(samplers, dom, n=120)
    assert len(ref) == len(res.vertices) >= 1
    for v in res.vertices:
        assert min(math.dist((v.x, v.y), r) for r in ref) < 2 * h
        d = [tr.query([v.x, v.y])[0] for tr in trees]
        assert max(abs(di - v.radius) for di in d[:3]) < 1e-4
        assert abs(d[3] - v.distance_to_fourth) < 1e-4
        assert v.in_conflict == (d[3] < d[0])
    assert res.conflict == any(v.in_conflict for v in res.vertices)


def test_arc_restricted_site_against_dense_sampling():
    """C1 = upper unit half-circle {x²+y²=1, y>=0}: the vertex's nearest point is the arc endpoint (1, 0)."""
    sites = [{"poly": "x**2+y**2-1", "where": ["y >= 0"]}, "(x-3)**2+y**2-1", "(x-3/2)**2+(y+5/2)**2-1/4",
             "(x-3/2)**2+(y+1/5)**2-1/16"]
    dom = (1.0, 1.5, -1.25, -0.75)
    res = locate_conflicts_semialgebraic(sites, domain=dom, formulation="original")
    # sites given as bare polynomials carry no bounding box: no proved bound, not complete
    assert res.complete is False and res.certified is False and all(v.certified for v in res.vertices)
    th = np.linspace(0, 2 * np.pi, 100_000)
    samplers = [_param(lambda a: (np.cos(a), np.sin(a)), np.linspace(0, np.pi, 100_000)),
                _param(lambda a: (3 + np.cos(a), np.sin(a)), th),
                _param(lambda a: (1.5 + 0.5 * np.cos(a), -2.5 + 0.5 * np.sin(a)), th),
                _param(lambda a: (1.5 + 0.25 * np.cos(a), -0.2 + 0.25 * np.sin(a)), th)]
    ref, h, trees = _dense_reference(samplers, dom, n=120)
    assert len(ref) == len(res.vertices) >= 1
    assert any(v.info["features"][0] == "endpoint" for v in res.vertices)
    for v in res.vertices:
        assert min(math.dist((v.x, v.y), r) for r in ref) < 2 * h
        d = [tr.query([v.x, v.y])[0] for tr in trees]
        assert max(abs(di - v.radius) for di in d[:3]) < 1e-4
        assert v.in_conflict == (d[3] < d[0])
    # the full circle would have put a site point strictly inside the empty circle
    full = locate_conflicts_semialgebraic(["x**2+y**2-1"] + sites[1:], domain=(1.15, 1.35, -1.1, -0.9),
                                          formulation="original")
    assert all(math.dist((v.x, v.y), (1.2373, -0.9975)) > 1e-3 for v in full.vertices)


def test_bad_input_errors():
    with pytest.raises(ValueError):
        locate_conflicts_semialgebraic(["x**2+y**2-1"] * 3, formulation="original")
    with pytest.raises(ValueError):
        locate_conflicts_semialgebraic(["x**2+y**2-1"] * 4, formulation="nope")
    with pytest.raises(ValueError):  # offsets need conics with exact frames
        locate_conflicts_semialgebraic(["y**2-x**2-x**3"] * 4, formulation="offset", domain=(-1, 1, -1, 1))
