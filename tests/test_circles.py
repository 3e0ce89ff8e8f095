"""Tests of the exact circle / additively-weighted-point conflict locator (thesis §3.1, App. A).

References used here are independent of the implementation:
* a brute-force distance-field search (grid sign changes of d1-d2, d1-d3 + Newton), written below;
* the `four_circles` group of tests/data/validation_cases.json (50-digit oracle);
* exact constructions with a rational (or Q(√2)) empty circle, where tangency is known exactly;
* exact algebraic identities (rigid-motion invariance, permutations, eigenvalues of M_g).
"""
from __future__ import annotations

import json
import math
from fractions import Fraction as F
from pathlib import Path

import numpy as np
import pytest
from flint import arb, ctx, fmpq
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from curvedvoronoi.runtime.validation import required_cases_path as _validation_path
from curvedvoronoi.runtime.predicates.apollonius import aw_vertices, locate_conflicts_aw, multiplication_matrix_aw, solve_system
from curvedvoronoi.runtime.predicates.circles import Circle, locate_conflicts_circles, voronoi_vertices_circles
from curvedvoronoi.runtime.sites.rationals import parse_rational
from curvedvoronoi.runtime.predicates.circles_filter import filter_circles, locate_conflicts_circles_batch
from curvedvoronoi.runtime.algebra.quadtower import QuadTower
from curvedvoronoi.runtime.result import InvalidConicError, LocatorError

VALIDATION = _validation_path()


# ======================================================================================
# independent brute-force reference
# ======================================================================================
def _dist(c, X, Y):
    return np.abs(np.hypot(X - c[0], Y - c[1]) - c[2])


def _sign_change(Fv):
    s = np.sign(Fv)
    a, b, c, d = s[:-1, :-1], s[1:, :-1], s[:-1, 1:], s[1:, 1:]
    lo = np.minimum(np.minimum(a, b), np.minimum(c, d))
    hi = np.maximum(np.maximum(a, b), np.maximum(c, d))
    return (lo <= 0) & (hi >= 0)


def _newton(cs, x, y, it=60):
    vals = None
    for _ in range(it):
        vals, grads = [], []
        for (cx, cy, r) in cs[:3]:
            dx, dy = x - cx, y - cy
            n = math.hypot(dx, dy)
            if n == 0:
                return None
            s = 1.0 if n >= r else -1.0
            vals.append(abs(n - r))
            grads.append((s * dx / n, s * dy / n))
        Fv = np.array([vals[0] - vals[1], vals[0] - vals[2]])
        J = np.array([[grads[0][0] - grads[1][0], grads[0][1] - grads[1][1]],
                      [grads[0][0] - grads[2][0], grads[0][1] - grads[2][1]]])
        try:
            step = np.linalg.solve(J, Fv)
        except np.linalg.LinAlgError:
            return None
        x, y = x - step[0], y - step[1]
        if not (np.isfinite(x) and np.isfinite(y)):
            return None
        if math.hypot(*step) < 1e-14 * (1 + math.hypot(x, y)):
            break
    return x, y, vals[0]


def reference_vertices(cs, n_tan=401, n_box=201):
    """All q with d(q,C1)=d(q,C2)=d(q,C3)=R>0, |q| up to ~1e4 × scene, by grids + Newton."""
    cx = np.array([c[0] for c in cs[:3]])
    cy = np.array([c[1] for c in cs[:3]])
    r = np.array([c[2] for c in cs[:3]])
    X0, Y0 = cx.mean(), cy.mean()
    S = max(np.ptp(cx), np.ptp(cy), r.max(), 1e-3)
    t = np.tan(np.linspace(-1.0, 1.0, n_tan) * np.arctan(1e4)) * S
    u = np.linspace(-1.5, 1.5, n_box) * (S + r.max()) * 1.5
    found = []
    for gx, gy in ((X0 + t, Y0 + t), (X0 + u, Y0 + u)):
        X, Y = np.meshgrid(gx, gy)
        d = [_dist(c, X, Y) for c in cs[:3]]
        ii, jj = np.nonzero(_sign_change(d[0] - d[1]) & _sign_change(d[0] - d[2]))
        for i, j in zip(ii, jj):
            res = _newton(cs, 0.5 * (gx[j] + gx[j + 1]), 0.5 * (gy[i] + gy[i + 1]))
            if res is None:
                continue
            x, y, R = res
            dd = [abs(math.hypot(x - c[0], y - c[1]) - c[2]) for c in cs[:3]]
            if R <= 1e-9 * S or R > 1e5 * S or max(dd) - min(dd) > 1e-10 * (1 + R):
                continue
            if any(math.hypot(x - a, y - b) < 1e-7 * (1 + R) for a, b, _ in found):
                continue
            found.append((x, y, R))
    return sorted(found)


def _pair_clearance(cs):
    """min over pairs of |dist(c_i,c_j) - (ρi ± ρj)| relative to the scene: small = near tangent."""
    m = math.inf
    for i in range(3):
        for j in range(i):
            dd = math.hypot(cs[i][0] - cs[j][0], cs[i][1] - cs[j][1])
            m = min(m, abs(dd - cs[i][2] - cs[j][2]), abs(dd - abs(cs[i][2] - cs[j][2])))
    return m


def _random_configs(n, seed):
    """Random dyadic circles: disjoint, intersecting, nested, points; no (near-)tangent pairs."""
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < n:
        k = len(out)
        cs = [(float(a), float(b), float(c)) for a, b, c in
              zip(rng.integers(-40, 40, 4) / 8, rng.integers(-40, 40, 4) / 8, rng.integers(0, 24, 4) / 8)]
        if k % 4 == 0:  # C2 contains C1
            cs[1] = (cs[0][0] + 0.375, cs[0][1] - 0.25, cs[0][2] + 1.5)
        elif k % 4 == 1:  # C3 overlapping / inside C1
            cs[2] = (cs[0][0] + 0.5, cs[0][1] + 0.125, max(cs[0][2] - 0.25, 0.0))
        elif k % 8 == 2:  # a point site
            cs[1] = (cs[1][0], cs[1][1], 0.0)
        if _pair_clearance(cs) < 0.1:
            continue
        out.append(cs)
    return out


BRUTE = _random_configs(110, seed=20240607)


def test_brute_force_reference_agreement():
    """Every vertex (x, y, radius), d(q, C4) and conflict agree with the independent search."""
    n_agree = 0
    total_vertices = 0
    for cs in BRUTE:
        res = locate_conflicts_circles(*cs)
        assert res.complete and res.certified
        ours = sorted((v.x, v.y, v.radius, v) for v in res.vertices)
        ref = reference_vertices(cs)
        assert len(ours) == len(ref), (cs, [o[:3] for o in ours], ref)
        for (x, y, R, v), (xr, yr, Rr) in zip(ours, ref):
            assert math.isclose(x, xr, rel_tol=1e-7, abs_tol=1e-9)
            assert math.isclose(y, yr, rel_tol=1e-7, abs_tol=1e-9)
            assert math.isclose(R, Rr, rel_tol=1e-7, abs_tol=1e-9)
            d4 = abs(math.hypot(xr - cs[3][0], yr - cs[3][1]) - cs[3][2])
            assert math.isclose(v.distance_to_fourth, d4, rel_tol=1e-7, abs_tol=1e-9)
            if abs(d4 - Rr) > 1e-6 * Rr:
                assert v.in_conflict == (d4 < Rr)
        n_agree += 1
        total_vertices += len(ours)
    assert n_agree == len(BRUTE)
    assert total_vertices > 120  # a non-trivial sample (145 vertices with this seed)


def test_eight_vertices_collinear_centres():
    """Thesis §3.1.3 says up to seven Apollonius circles are relevant; eight occur (checked by brute force)."""
    cs = [(0.5, 4.125, 0.75), (3.5, 4.125, 2.375), (0.875, 4.125, 0.875), (-1.0, 3.75, 1.125)]
    res = locate_conflicts_circles(*cs)
    assert len(res.vertices) == 8
    assert len(reference_vertices(cs)) == 8
    for v in res.vertices:
        d = [abs(math.hypot(v.x - c[0], v.y - c[1]) - c[2]) for c in cs[:3]]
        assert max(abs(t - v.radius) for t in d) < 1e-12 * (1 + v.radius)


def test_circle_inside_all_three_is_a_vertex():
    """Three mutually intersecting discs with a common part: the circle internally tangent to all
    three (pattern -,-,-) is a true vertex by definition (d(q,Ci) = radius); §3.1.3 first case
    lists only 'the seven Apollonius circles not internally tangent to each'.  Brute force agrees."""
    cs = [(0, 0, 10), (1, 0, 10), (0, 1, 10), (50, 50, 1)]
    res = locate_conflicts_circles(*cs)
    assert len(res.vertices) == 7 == len(reference_vertices([tuple(map(float, c)) for c in cs]))
    v = _find(res, 0.5, 0.5)
    assert v.info["pattern"] == [-1, -1, -1]
    assert math.isclose(v.radius, 10 - math.sqrt(0.5), rel_tol=1e-15)


# ======================================================================================
# validation cases
# ======================================================================================
def _validation_circle_cases():
    data = json.loads(VALIDATION.read_text())
    return [c for c in data["cases"] if all(k["canonical"]["type"] == "circle" for k in c["conics"])]


def test_validation_four_circles():
    cases = _validation_circle_cases()
    assert len(cases) == 3  # the four_circles group; no other group is all-circles
    n_vertices = 0
    for case in cases:
        cs = [Circle.from_canonical(k["canonical"]) for k in case["conics"]]
        assert cs == [Circle.from_coefficients(*k["coefficients"]) for k in case["conics"]]
        res = locate_conflicts_circles(*cs)
        assert res.certified and res.complete and res.method == "circles-exact"
        assert res.conflict == case["conflict"]
        assert len(res.vertices) == len(case["vertices"])
        exp = sorted(case["vertices"], key=lambda e: (float(e["x"]), float(e["y"])))
        for v, e in zip(res.vertices, exp):
            for ours, key in ((v.x, "x"), (v.y, "y"), (v.radius, "radius"), (v.distance_to_fourth, "distance_to_fourth")):
                assert math.isclose(ours, float(e[key]), rel_tol=1e-9, abs_tol=1e-12), (case["name"], key)
            assert v.in_conflict == e["in_conflict"] and v.tangent == e["tangent"]
            assert math.isclose(v.margin, float(e["margin"]), rel_tol=1e-7, abs_tol=1e-12)
            n_vertices += 1
    assert n_vertices == 17


# ======================================================================================
# exact degenerate constructions
# ======================================================================================
def _tangent_site(g, gam, u, rho, contains=False):
    """A circle tangent to the circle (g, gam) at g + gam u: outside it, or containing it."""
    p = (g[0] + gam * u[0], g[1] + gam * u[1])
    sgn = -1 if contains else 1
    return (p[0] + sgn * rho * u[0], p[1] + sgn * rho * u[1], rho)


G, GAM = (F(1), F(2)), F(5)
TANGENT_TRIPLE = [_tangent_site(G, GAM, (F(3, 5), F(4, 5)), F(1)),
                  _tangent_site(G, GAM, (F(-1), F(0)), F(2)),
                  _tangent_site(G, GAM, (F(0), F(-1)), F(7), contains=True)]


def _find(res, x, y):
    hits = [v for v in res.vertices if math.isclose(v.x, x, abs_tol=1e-12) and math.isclose(v.y, y, abs_tol=1e-12)]
    assert len(hits) == 1
    return hits[0]


@pytest.mark.parametrize("u,contains", [((F(-5, 13), F(12, 13)), False), ((F(8, 17), F(-15, 17)), True)])
def test_exactly_tangent_rational(u, contains):
    c4 = _tangent_site(G, GAM, u, F(3, 7), contains=contains) if not contains else _tangent_site(G, GAM, u, F(9), True)
    res = locate_conflicts_circles(*TANGENT_TRIPLE, c4)
    v = _find(res, 1.0, 2.0)
    assert v.radius == 5.0 and v.distance_to_fourth == 5.0
    assert v.tangent and not v.in_conflict and v.certified and v.margin == 0.0
    # a nudge of 1e-15 in the radius of C4 flips the exact decision
    eps = F(1, 10**15)
    grow = (c4[0], c4[1], c4[2] + eps)
    v2 = _find(locate_conflicts_circles(*TANGENT_TRIPLE, grow), 1.0, 2.0)
    assert not v2.tangent and v2.in_conflict == (not contains)
    shrink = (c4[0], c4[1], c4[2] - eps)
    v3 = _find(locate_conflicts_circles(*TANGENT_TRIPLE, shrink), 1.0, 2.0)
    assert not v3.tangent and v3.in_conflict == contains


def test_exactly_tangent_irrational_radii():
    """Empty circle centre (2,2), radius √2; sites with r2 = 2, 2, 8 (ρ3 = 2√2); C4 r2 = 2 or 18."""
    c1, c2, c3 = Circle(0, 0, 2), Circle(4, 4, 2), Circle(5, 5, 8)
    for c4 in (Circle(0, 4, 2), Circle(4, 0, 18)):  # externally tangent / containing the empty circle
        res = locate_conflicts_circles(c1, c2, c3, c4)
        v = _find(res, 2.0, 2.0)
        assert math.isclose(v.radius, math.sqrt(2), rel_tol=1e-15)
        assert v.tangent and not v.in_conflict and v.certified
    # irrational independent radicals (r2 = 3, 5, 7 and 11): exact decisions agree with 200-bit floats
    res = locate_conflicts_circles(Circle(0, 0, 3), Circle(5, 1, 5), Circle(2, 6, 7), Circle(F(5, 2), F(5, 2), 11))
    assert res.certified and len(res.vertices) >= 1
    assert max(v.info["tower_depth"] for v in res.vertices) >= 4
    for v in res.vertices:
        assert v.in_conflict == (v.distance_to_fourth < v.radius)


def test_nested_no_vertex_and_strict():
    cs = [(0, 0, 10), (1, 0, 3), (F(3, 2), 0, 1), (20, 0, 1)]  # C3 in C2 in C1
    res = locate_conflicts_circles(*cs)
    assert res.vertices == [] and res.complete and res.certified and not res.conflict and res.notes
    with pytest.raises(LocatorError, match="no true Voronoi vertex"):
        locate_conflicts_circles(*cs, strict=True)
    # one circle inside another (only C2 ⊂ C1), C3 outside: still no vertex (thesis §3.1.3)
    assert locate_conflicts_circles((0, 0, 10), (1, 0, 3), (30, 0, 1), (0, 0, 1)).vertices == []


def test_point_sites_and_circumcircle():
    res = locate_conflicts_circles((0, 0, 0), (4, 0, 0), (0, 2, 0), (F(2), F(1) + F(1, 10), 0))
    assert len(res.vertices) == 1
    v = res.vertices[0]
    assert (v.x, v.y) == (2.0, 1.0) and math.isclose(v.radius, math.sqrt(5)) and v.in_conflict
    # cocircular fourth point: exactly tangent
    v = locate_conflicts_circles((0, 0, 0), (4, 0, 0), (0, 2, 0), (4, 2, 0)).vertices[0]
    assert v.tangent and not v.in_conflict
    # collinear points: no vertex; point inside a circle: two vertices
    assert locate_conflicts_circles((0, 0, 0), (1, 0, 0), (2, 0, 0), (5, 5, 1)).vertices == []
    assert len(locate_conflicts_circles((0, 0, 0), (0, 0, 3), (1, 0, 0), (5, 5, 1)).vertices) == 2


def test_concentric_and_continuum():
    assert locate_conflicts_circles((0, 0, 1), (0, 0, 2), (0, 0, 3), (5, 5, 1)).vertices == []
    # three circles tangent at the origin with collinear centres: a segment of equidistant points
    with pytest.raises(LocatorError, match="continuum"):
        locate_conflicts_circles((1, 0, 1), (-1, 0, 1), (2, 0, 2), (5, 5, 1))


def test_bad_input():
    with pytest.raises(InvalidConicError, match="not finite"):
        locate_conflicts_circles((float("nan"), 0, 1), (1, 0, 1), (0, 1, 1), (3, 3, 1))
    with pytest.raises(InvalidConicError, match="not finite"):
        locate_conflicts_circles((0, 0, 1), (1, 0, float("inf")), (0, 1, 1), (3, 3, 1))
    with pytest.raises(InvalidConicError, match="negative"):
        locate_conflicts_circles((0, 0, -1), (1, 0, 1), (0, 1, 1), (3, 3, 1))
    with pytest.raises(InvalidConicError, match="negative"):
        Circle(0, 0, -2)
    with pytest.raises(LocatorError, match="same circle"):
        locate_conflicts_circles((0, 0, 1), (0, 0, 1), (0, 5, 1), (3, 3, 1))
    with pytest.raises(InvalidConicError, match="cannot parse"):
        parse_rational("one half")
    with pytest.raises(InvalidConicError, match="bool"):
        parse_rational(True)
    with pytest.raises(InvalidConicError, match="not a circle"):
        Circle.from_coefficients(1, 0, 2, 0, 0, -1)
    with pytest.raises(ValueError, match="shape"):
        locate_conflicts_circles_batch(np.zeros((3, 3, 3)))
    X = np.ones((2, 4, 3))
    X[1, 2, 0] = np.nan
    with pytest.raises(ValueError, match="non-finite"):
        locate_conflicts_circles_batch(X)
    X[1, 2, 0] = 0.0
    X[0, 1, 2] = -1.0
    with pytest.raises(ValueError, match="negative radius"):
        locate_conflicts_circles_batch(X)


def test_input_forms():
    c = Circle.from_radius(0.1, "1/3", "0.25")
    assert F(int(c.cx.p), int(c.cx.q)) == F(0.1)  # float taken at its exact binary value
    assert c.cy == fmpq(1, 3) and c.r2 == fmpq(1, 16)
    assert Circle.from_coefficients(2, 0, 2, -4, 8, 2) == Circle(1, -2, 4)
    r1 = locate_conflicts_circles((0, 0, 1), (5, 0, 2), (1, 4, F(1, 2)), (2, 1, 1))
    r2 = locate_conflicts_circles(Circle(0, 0, 1), Circle(5, 0, 4), Circle(1, 4, F(1, 4)), Circle(2, 1, 1))
    assert [v.to_dict() for v in r1.vertices] == [v.to_dict() for v in r2.vertices]
    tv = voronoi_vertices_circles((0, 0, 1), (5, 0, 2), (1, 4, F(1, 2)))
    assert tv is voronoi_vertices_circles(Circle(0, 0, 1), Circle(5, 0, 4), Circle(1, 4, F(1, 4)))  # cached


# ======================================================================================
# property tests: rational rigid motions and permutations
# ======================================================================================
small = st.fractions(min_value=-6, max_value=6, max_denominator=4)
r2s = st.sampled_from([F(0), F(1, 4), F(1), F(2), F(3), F(9, 4), F(5), F(8)])
circle_st = st.tuples(small, small, r2s)
triple_st = st.lists(circle_st, min_size=4, max_size=4).filter(
    lambda cs: len({c for c in cs[:3]}) == 3)


def _rot(m, n):
    h = m * m + n * n
    return F(m * m - n * n, h), F(2 * m * n, h)


def _signature(res):
    return sorted((round(v.radius, 9), v.in_conflict, v.tangent) for v in res.vertices)


def _safe(cs):
    try:
        return locate_conflicts_circles(*[Circle(*c) for c in cs])
    except LocatorError:
        return None


@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.filter_too_much])
@given(triple_st, st.integers(1, 4), st.integers(0, 3), small, small)
def test_rigid_motion_invariance(cs, m, n, tx, ty):
    cos, sin = _rot(m, n)
    moved = [(cos * x - sin * y + tx, sin * x + cos * y + ty, r2) for x, y, r2 in cs]
    a, b = _safe(cs), _safe(moved)
    assert (a is None) == (b is None)
    if a is None:
        return
    assert a.certified and b.certified
    assert _signature(a) == _signature(b) and a.conflict == b.conflict
    fc, fs = float(cos), float(sin)
    for v in a.vertices:
        x, y = fc * v.x - fs * v.y + float(tx), fs * v.x + fc * v.y + float(ty)
        assert any(math.isclose(w.x, x, abs_tol=1e-9) and math.isclose(w.y, y, abs_tol=1e-9) for w in b.vertices)


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.filter_too_much])
@given(triple_st, st.permutations([0, 1, 2]))
def test_permutation_invariance(cs, perm):
    a = _safe(cs)
    b = _safe([cs[i] for i in perm] + [cs[3]])
    assert (a is None) == (b is None)
    if a is None:
        return
    assert [(v.x, v.y, v.radius, v.in_conflict, v.tangent) for v in a.vertices] == \
           [(v.x, v.y, v.radius, v.in_conflict, v.tangent) for v in b.vertices]


@settings(max_examples=30, deadline=None)
@given(triple_st)
def test_vertices_are_equidistant(cs):
    """Each reported vertex satisfies d(q,Ci) = radius (checked at 200 bits from the exact data)."""
    res = _safe(cs)
    if res is None:
        return
    for v in res.vertices:
        with ctx.workprec(200):
            for x, y, r2 in cs[:3]:
                d = abs(((arb(v.x) - arb(fmpq(x.numerator, x.denominator))) ** 2
                         + (arb(v.y) - arb(fmpq(y.numerator, y.denominator))) ** 2).sqrt()
                        - arb(fmpq(r2.numerator, r2.denominator)).sqrt())
                assert abs(float(d.mid()) - v.radius) < 1e-9 * (1 + v.radius)


# ======================================================================================
# filtered batch path
# ======================================================================================
def _batch_data(n, seed):
    rng = np.random.default_rng(seed)
    X = np.empty((n, 4, 3))
    X[:, :, :2] = rng.integers(-64, 64, (n, 4, 2)) / 16
    X[:, :, 2] = rng.integers(0, 40, (n, 4)) / 16
    X[::7, 1, 2] = 0.0  # point sites
    X[1::11, 2, :2] = X[1::11, 0, :2] + (X[1::11, 1, :2] - X[1::11, 0, :2]) * 2  # collinear centres
    X[2::13, 1, :2] = X[2::13, 0, :2]  # concentric C1, C2
    X[2::13, 1, 2] = X[2::13, 0, 2] + 1
    X[3::17, 1:3, 2] = X[3::17, 0:1, 2]  # equal radii
    # exact tangent rows (dyadic construction around the empty circle (1, 2, 5))
    X[4::19] = [[7, 2, 1], [1, 9, 2], [3, 2, 7], [1, -3.5, 0.5]]
    return X


def test_batch_matches_exact():
    X = _batch_data(1500, seed=3)
    res = locate_conflicts_circles_batch(X, on_error="flag")
    ex = res["needed_exact"]
    assert 0 < ex.mean() < 0.5
    assert ex[4::19].all()  # exact tangency can never be decided by the filter
    assert ex[1::11].all()  # collinear centres: det = 0
    mismatches = 0
    for i in range(X.shape[0]):
        try:
            r = locate_conflicts_circles(*[tuple(X[i, j]) for j in range(4)])
        except LocatorError:
            assert res["error"][i] and res["n_vertices"][i] == -1
            continue
        mismatches += (r.conflict != res["conflict"][i]) + (len(r.vertices) != res["n_vertices"][i])
    assert mismatches == 0
    assert not res["conflict"][4::19].any() and (res["n_vertices"][4::19] >= 1).all()


def test_filter_decides_generic_input():
    rng = np.random.default_rng(11)
    X = np.empty((20000, 4, 3))
    X[:, :, :2] = rng.uniform(-5, 5, (20000, 4, 2))
    X[:, :, 2] = rng.uniform(0, 3, (20000, 4))
    r = filter_circles(X)
    assert r["decided"].mean() > 0.99
    idx = np.flatnonzero(r["decided"])[:: 100]
    for i in idx:
        e = locate_conflicts_circles(*[tuple(X[i, j]) for j in range(4)])
        assert e.conflict == r["conflict"][i] and len(e.vertices) == r["n_vertices"][i]


def test_batch_adversarial_ulps_and_overflow():
    """C4 one ulp off exact tangency, centres one ulp off collinear, data scaled by 2^±600."""
    base = np.array([[7, 2, 1], [1, 9, 2], [3, 2, 7], [1, -3.5, 0.5]], float)  # tangent at (1, 2, 5)
    rows = [base]
    for direction in (np.inf, -np.inf):
        b = base.copy()
        b[3, 2] = np.nextafter(b[3, 2], direction)
        rows.append(b)
        b = base.copy()
        b[3, 1] = np.nextafter(b[3, 1], direction)
        rows.append(b)
    col = np.array([[0, 0, 1], [3, 0.5, 2], [7, 1 + 1 / 6, 1], [5, 5, 1]], float)
    col[2, 1] = np.nextafter(col[2, 1], np.inf)
    rows.append(col)
    rows += [r * 2.0 ** 600 for r in rows[:3]] + [r * 2.0 ** -600 for r in rows[:3]]
    X = np.array(rows)
    res = locate_conflicts_circles_batch(X)
    for i in range(X.shape[0]):
        r = locate_conflicts_circles(*[tuple(X[i, j]) for j in range(4)])
        assert r.conflict == res["conflict"][i] and len(r.vertices) == res["n_vertices"][i]
    assert res["needed_exact"][:5].all()  # within one ulp of tangency: the filter must defer
    # growing C4 by one ulp makes it enter the empty circle (1, 2, 5), shrinking does not
    assert res["conflict"][1] and not res["conflict"][0] and not res["conflict"][3]
    assert (res["conflict"][6:9] == res["conflict"][:3]).all() and (res["conflict"][9:12] == res["conflict"][:3]).all()


def test_batch_error_flag_and_raise():
    X = np.array([[[0, 0, 1], [0, 0, 1], [3, 0, 1], [5, 5, 1]], [[0, 0, 1], [4, 0, 1], [0, 4, 1], [2, 2, 1]]], float)
    r = locate_conflicts_circles_batch(X, on_error="flag")
    assert r["error"].tolist() == [True, False] and r["n_vertices"][0] == -1 and r["conflict"][1]
    with pytest.raises(LocatorError, match="query 0"):
        locate_conflicts_circles_batch(X)


# ======================================================================================
# additively weighted points (§3.1.2, Appendix A)
# ======================================================================================
aw_site = st.tuples(st.integers(-8, 8), st.integers(-8, 8), st.fractions(0, 3, max_denominator=3))


@settings(max_examples=30, deadline=None)
@given(st.lists(aw_site, min_size=4, max_size=4, unique_by=lambda p: p[:2]))
def test_aw_eigenvalues_of_Mg_are_values_of_g(ps):
    """Eq. (3.1.1): every value of g on the Apollonius solutions is a root of det(M_g - λI)."""
    try:
        M, _ = multiplication_matrix_aw(*ps)
    except LocatorError:
        return  # collinear centres or A = 0: not the generic 2-dimensional algebra
    tr, det = M[0, 0] + M[1, 1], M[0, 0] * M[1, 1] - M[0, 1] * M[1, 0]
    q = [(fmpq(x), fmpq(y), fmpq(w.numerator, w.denominator)) for x, y, w in ps]
    res = solve_system(QuadTower(), [p[:2] for p in q[:3]], [p[2] for p in q[:3]], [p[2] ** 2 for p in q[:3]],
                       (1, 1, 1))
    x4, y4, w4 = q[3]
    for s in res.solutions:
        T = s.tower
        DX, DY = T.sub(s.X, T.mul(x4, s.D)), T.sub(s.Y, T.mul(y4, s.D))
        gD2 = T.sub(T.add(T.sqr(DX), T.sqr(DY)), T.sqr(T.add(s.Rn, T.mul(w4, s.D))))  # g * D^2
        D2 = T.sqr(s.D)
        # (g)^2 - tr g + det = 0, times D^4
        val = T.add(T.sub(T.sqr(gD2), T.mul(T.mul(tr, gD2), D2)), T.mul(det, T.sqr(D2)))
        assert T.sign(val) == 0
    # the thesis: Δ of (3.1.1) is >= 0 whenever a real vertex exists
    if aw_vertices(*ps[:3]):
        assert tr * tr - 4 * det >= 0


@settings(max_examples=30, deadline=None)
@given(st.lists(aw_site, min_size=4, max_size=4, unique_by=lambda p: p[:2]))
def test_aw_vertices_and_conflicts(ps):
    try:
        res = locate_conflicts_aw(*ps)
    except LocatorError:
        return
    for v in res.vertices:
        for x, y, w in ps[:3]:
            assert math.isclose(math.hypot(v.x - x, v.y - y) - float(w), v.radius, abs_tol=1e-9)
        x4, y4, w4 = ps[3]
        d4 = math.hypot(v.x - x4, v.y - y4) - float(w4)
        assert math.isclose(d4, v.distance_to_fourth, abs_tol=1e-9)
        if abs(d4 - v.radius) > 1e-9:
            assert v.in_conflict == (d4 < v.radius)


def test_aw_sign_of_r_plus_w4_matters():
    """g < 0 but r + w4 < 0: no conflict (the thesis's test on the sign of g alone would say conflict)."""
    P = [(1, 0, 5), (0, 1, 5), (-1, 0, 5)]
    res = locate_conflicts_aw(*P, (0, F(1, 2), 1))
    v = _find(res, 0.0, 0.0)
    assert v.radius == -4.0 and v.info["sign_g"] < 0 and not v.in_conflict
    res = locate_conflicts_aw(*P, (0, F(1, 2), F(7, 2)))  # δ4 - w4 = -3 > -4: no conflict
    assert not _find(res, 0.0, 0.0).in_conflict
    res = locate_conflicts_aw(*P, (0, F(1, 2), F(9, 2)))  # δ4 - w4 = -4: tangent
    assert _find(res, 0.0, 0.0).tangent
    res = locate_conflicts_aw(*P, (0, F(1, 2), 5))  # -4.5 < -4: conflict
    assert _find(res, 0.0, 0.0).in_conflict


# ======================================================================================
# quadratic tower
# ======================================================================================
def test_tower_zero_detection_with_dependent_radicals():
    T, r2 = QuadTower().extend(fmpq(2))
    T, r8 = T.extend(fmpq(8))
    T, r6 = T.extend(fmpq(6))
    T, r3 = T.extend(fmpq(3))
    assert T.sign(T.sub(r8, T.mul(fmpq(2), r2))) == 0  # √8 - 2√2
    assert T.sign(T.sub(T.mul(r2, r3), r6)) == 0  # √2√3 - √6
    x = T.sub(T.sqr(T.add(r2, r3)), T.add(fmpq(5), T.mul(fmpq(2), r6)))
    assert T.sign(x) == 0
    assert T.sign(T.sub(T.add(r2, r3), fmpq(F(3146, 1000).numerator, F(3146, 1000).denominator))) == 1  # 3.14626..
    assert T.sign(T.sub(T.add(r2, r3), fmpq(3147, 1000))) == -1


@settings(max_examples=60, deadline=None)
@given(st.lists(st.integers(-50, 50), min_size=8, max_size=8), st.sampled_from([2, 3, 5, 7]),
       st.sampled_from([11, 13, 17]))
def test_tower_sign_matches_high_precision(cs, p, q):
    T, a = QuadTower().extend(fmpq(p))
    T, b = T.extend(T.add(fmpq(q), a))  # √(q + √p): a genuinely nested radical
    x = [fmpq(c) for c in cs]
    e = T.add(T.add(x[0], T.mul(x[1], a)), T.mul(T.add(x[2], T.mul(x[3], a)), b))
    with ctx.workprec(300):
        val = T._arb(e, 300)
    s = T.sign(e)
    if val > 0:
        assert s == 1
    elif val < 0:
        assert s == -1
    else:
        assert s == 0 or val.rad() > 1e-80


def test_fourth_equal_to_a_site_is_tangent_everywhere():
    cs = [(0, 0, 1), (5, 0, 2), (1, 4, F(1, 2))]
    res = locate_conflicts_circles(*cs, cs[1])
    assert res.vertices and all(v.tangent and not v.in_conflict for v in res.vertices) and not res.conflict


@pytest.mark.parametrize("cs,n", [
    ([(0, 1, 1), (3, 2, 2), (-4, 3, 3), (50, 50, 1)], 1),  # common tangent line y = 0: leading coefficient A = 0
    ([(0, 1, 1), (3, -2, 2), (-4, 3, 3), (1, 1, 1)], 2),
    ([(0, 0, 1), (4, 0, 1), (8, 0, 1), (1, 1, 0)], 0),  # equal collinear circles: parallel bisectors
    ([(0, 0, 1), (3, 0, 2), (7, 0, 1), (0, 0, 0)], 0),
])
def test_special_positions_against_brute_force(cs, n):
    res = locate_conflicts_circles(*cs)
    ref = reference_vertices([tuple(map(float, c)) for c in cs])
    assert len(res.vertices) == len(ref) == n
    for v, (x, y, R) in zip(res.vertices, ref):
        assert math.isclose(v.x, x, abs_tol=1e-9) and math.isclose(v.y, y, abs_tol=1e-9)
        assert math.isclose(v.radius, R, rel_tol=1e-9)
