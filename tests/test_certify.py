"""Certification of the conic locator (issue 5; thesis §5.2 Thm 5.2.2, §5.5, §3.3.3).

Facts asserted: every certified answer agrees with the validation oracle / an independent
mpmath reference (tests/reference.py); near-degenerate inputs (margins ±1e-6, ±1e-9 at an
irrational vertex) are decided and certified; exact tangency built from rational data is
recognised exactly (margin 0, no conflict); non-vertices are never certified.
"""
from __future__ import annotations

import json
import math
import random
from fractions import Fraction

import mpmath
import numpy as np
import pytest

from curvedvoronoi.runtime.validation import required_cases_path as _validation_path
from curvedvoronoi.runtime.certify.conflicts import certify_completeness, certify_result, certify_vertex, simplest_rational
from curvedvoronoi.runtime.certify.complete import _completeness
from curvedvoronoi.runtime.sites.conic import Conic
from curvedvoronoi.runtime.result import LocatorResult, VoronoiVertex

from reference import RefConic, ref_distance  # noqa: E402  (tests/ on sys.path via pytest rootdir)

DATA = _validation_path()
CASES = json.loads(DATA.read_text())["cases"]


def _conics(case):
    return [Conic.from_coefficients(*e["coefficients"]) for e in case["conics"]]


def _expected_sign(v):
    return 0 if v["tangent"] else (-1 if v["in_conflict"] else 1)


# --------------------------------------------------------------------------- validation data

@pytest.mark.parametrize("case", CASES, ids=[c["name"] for c in CASES])
def test_validation_vertices_certified(case):
    c1, c2, c3, c4 = _conics(case)
    for v in case["vertices"]:
        cv = certify_vertex(c1, c2, c3, v["x"], v["y"], Fraction(v["radius"]) ** 2, c4)
        assert cv.proven and cv.true_vertex, cv.note
        assert cv.sign == _expected_sign(v)
        # the proven box is consistent with the oracle's 30-digit values (accurate to ~25 digits)
        for ball, ref in ((cv.box[0], v["x"]), (cv.box[1], v["y"]), (cv.radius, v["radius"])):
            assert abs(float(ball.mid()) - float(ref)) <= 1e-12 * (1 + abs(float(ref)))
            assert float(ball.rad()) < 1e-12 * (1 + abs(float(ref)))
        if cv.sign != 0:
            m = cv.margin
            assert abs(float(m.mid()) - float(v["margin"])) <= 1e-12 + 1e-9 * abs(float(v["margin"]))


@pytest.mark.parametrize("case", [c for c in CASES if c["group"] == "exactly_tangent"],
                         ids=lambda c: c["name"])
def test_validation_exact_tangency(case):
    c1, c2, c3, c4 = _conics(case)
    tv = [v for v in case["vertices"] if v["tangent"]]
    assert len(tv) == 1
    v = tv[0]
    cv = certify_vertex(c1, c2, c3, float(v["x"]), float(v["y"]), float(v["radius"]) ** 2, c4)
    assert cv.proven and cv.kind == "exact-rational"
    assert cv.sign == 0 and cv.tangent_exact and float(cv.margin.mid()) == 0.0
    xq, yq, Rq = cv.exact
    assert abs(float(xq) - float(v["x"])) < 1e-25 and abs(float(yq) - float(v["y"])) < 1e-25
    assert abs(float(Rq) - float(v["radius"]) ** 2) < 1e-12


@pytest.mark.parametrize("case", [c for c in CASES if c["group"] == "near_degenerate"],
                         ids=lambda c: c["name"])
def test_validation_near_degenerate(case):
    c1, c2, c3, c4 = _conics(case)
    v = min(case["vertices"], key=lambda w: abs(float(w["margin"])))
    cv = certify_vertex(c1, c2, c3, float(v["x"]), float(v["y"]), float(v["radius"]) ** 2, c4)
    assert cv.proven and cv.kind == "krawczyk"
    assert cv.sign == (1 if float(v["margin"]) > 0 else -1)
    assert cv.margin.overlaps(mpmath_ball(v["margin"], 1e-20)) or \
        abs(float(cv.margin.mid()) - float(v["margin"])) < 1e-18


def mpmath_ball(s, rad):
    from flint import arb
    return arb(s, rad)


# --------------------------------------------------------------------------- near-degenerate, irrational centre

def _irrational_vertex():
    case = next(c for c in CASES if c["name"] == "hyperbolas_a_near_circle_1e-7")
    c1, c2, c3, _ = _conics(case)
    v = case["vertices"][0]
    return (c1, c2, c3), case, v


@pytest.mark.parametrize("margin", ["1e-6", "-1e-6", "1e-9", "-1e-9"])
def test_near_tangent_circle_irrational_centre(margin):
    """C4 = circle with rational data at relative distance `margin` from the empty circle."""
    (c1, c2, c3), case, v = _irrational_vertex()
    mpmath.mp.dps = 50
    q = (mpmath.mpf(v["x"]), mpmath.mpf(v["y"]))
    r = mpmath.mpf(v["radius"])
    centre = (Fraction(v["x"]) + Fraction(6), Fraction(v["y"]) - Fraction(5))
    dist = mpmath.sqrt((q[0] - mpmath.mpf(centre[0].numerator) / centre[0].denominator) ** 2 +
                       (q[1] - mpmath.mpf(centre[1].numerator) / centre[1].denominator) ** 2)
    rho = dist - r * (1 + mpmath.mpf(margin))
    rho_q = Fraction(mpmath.nstr(rho, 40))
    c4 = Conic.circle(centre=centre, radius=rho_q)
    cv = certify_vertex(c1, c2, c3, float(v["x"]), float(v["y"]), float(v["radius"]) ** 2, c4)
    assert cv.proven
    assert cv.sign == (1 if float(margin) > 0 else -1)
    assert abs(float(cv.margin.mid()) / float(margin) - 1) < 1e-6
    # the empty circle's centre is irrational: the exact path cannot have been used
    assert cv.kind == "krawczyk"


@pytest.mark.parametrize("margin", ["1e-9", "-1e-9"])
def test_near_tangent_translated_ellipse(margin):
    """C4 = an ellipse translated (rationally) along its normal to relative distance `margin`,
    distances from the independent mpmath reference."""
    (c1, c2, c3), case, v = _irrational_vertex()
    mpmath.mp.dps = 45
    x, y, r = (mpmath.mpf(v[k]) for k in ("x", "y", "radius"))
    spec = {"type": "ellipse", "cos": "3/5", "sin": "4/5", "tx": "-1", "ty": "14", "A2": "2", "B2": "1/2"}
    d0 = ref_distance(RefConic(spec), x, y, dps=45)
    target = r * (1 + mpmath.mpf(margin))
    # translate along the direction from q to the ellipse centre: distance changes by ~δ·cos
    ex, ey = mpmath.mpf(-1) - x, mpmath.mpf(14) - y
    n = mpmath.sqrt(ex ** 2 + ey ** 2)
    ux, uy = ex / n, ey / n
    t = target - d0  # Newton on t: d(q, E + t·u) = target
    for _ in range(30):
        s = dict(spec, tx=str(Fraction(mpmath.nstr(-1 + t * ux, 42))), ty=str(Fraction(mpmath.nstr(14 + t * uy, 42))))
        dt = ref_distance(RefConic(s), x, y, dps=45)
        h = mpmath.mpf(10) ** -20
        s2 = dict(spec, tx=str(Fraction(mpmath.nstr(-1 + (t + h) * ux, 42))), ty=str(Fraction(mpmath.nstr(14 + (t + h) * uy, 42))))
        slope = (ref_distance(RefConic(s2), x, y, dps=45) - dt) / h
        step = (dt - target) / slope
        t -= step
        if abs(step) < mpmath.mpf(10) ** -36:
            break
    s = dict(spec, tx=str(Fraction(mpmath.nstr(-1 + t * ux, 42))), ty=str(Fraction(mpmath.nstr(14 + t * uy, 42))))
    c4 = Conic.from_canonical("ellipse", cos=Fraction(3, 5), sin=Fraction(4, 5), tx=Fraction(s["tx"]),
                              ty=Fraction(s["ty"]), A2=2, B2=Fraction(1, 2))
    m_ref = ref_distance(RefConic(s), x, y, dps=45) / r - 1
    assert abs(m_ref / mpmath.mpf(margin) - 1) < 1e-6
    cv = certify_vertex(c1, c2, c3, float(x), float(y), float(r) ** 2, c4)
    assert cv.proven and cv.sign == (1 if float(margin) > 0 else -1)
    assert abs(float(cv.margin.mid()) / float(m_ref) - 1) < 1e-6


# --------------------------------------------------------------------------- exact tangency from rational data

def _touching(kind, Q, rho, u, size):
    """A conic touching the circle (Q, rho) from outside at the rational point Q + rho·u."""
    (cx, cy), (ux, uy) = Q, u
    Px, Py = cx + rho * ux, cy + rho * uy
    if kind == "circle":
        return Conic.circle(centre=(Px + size * ux, Py + size * uy), radius=size)
    if kind == "ellipse":
        A = size
        return Conic.from_canonical("ellipse", cos=ux, sin=uy, tx=Px + A * ux, ty=Py + A * uy,
                                    A2=A * A, B2=A * A / 4)
    if kind == "parabola":
        return Conic.from_canonical("parabola", cos=ux, sin=uy, tx=Px, ty=Py, p=size)
    if kind == "hyperbola":
        A = rho + size  # A > rho keeps the other branch outside the circle
        return Conic.from_canonical("hyperbola", cos=ux, sin=uy, tx=Px - A * ux, ty=Py - A * uy,
                                    A2=A * A, B2=size)
    raise ValueError(kind)


DIRS = [(Fraction(3, 5), Fraction(4, 5)), (Fraction(-12, 13), Fraction(5, 13)), (Fraction(8, 17), Fraction(-15, 17)),
        (Fraction(-7, 25), Fraction(-24, 25)), (Fraction(20, 29), Fraction(21, 29))]


@pytest.mark.parametrize("kinds", [("circle", "ellipse", "parabola", "circle"),
                                   ("ellipse", "parabola", "hyperbola", "parabola"),
                                   ("hyperbola", "circle", "ellipse", "ellipse"),
                                   ("parabola", "parabola", "ellipse", "hyperbola")])
def test_exact_tangency_rational_construction(kinds):
    Q, rho = (Fraction(1, 3), Fraction(-2, 7)), Fraction(5, 4)
    sizes = [Fraction(1, 2), Fraction(2, 3), Fraction(3, 4), Fraction(5, 6)]
    cs = [_touching(k, Q, rho, DIRS[i], sizes[i]) for i, k in enumerate(kinds)]
    cv = certify_vertex(*cs[:3], float(Q[0]) + 1e-13, float(Q[1]) - 1e-13, float(rho) ** 2, cs[3])
    assert cv.proven and cv.true_vertex
    assert cv.kind == "exact-rational" and cv.sign == 0 and cv.tangent_exact
    assert cv.exact == (Q[0], Q[1], rho * rho)
    # move C4 away / into the circle by a rational 1e-25: decided by balls, certified
    for eps, sign in ((Fraction(1, 10 ** 25), 1), (Fraction(-1, 10 ** 25), -1)):
        u = DIRS[3]
        fr = cs[3]
        co = cs[3].coefficients
        # translate C4 by eps·u: f(x − εu_x, y − εu_y)
        a, b, c, d, e, f = co
        tx, ty = eps * u[0], eps * u[1]
        moved = Conic.from_coefficients(a, b, c, d - 2 * a * tx - b * ty, e - 2 * c * ty - b * tx,
                                        f + a * tx * tx + b * tx * ty + c * ty * ty - d * tx - e * ty)
        cw = certify_vertex(*cs[:3], float(Q[0]), float(Q[1]), float(rho) ** 2, moved)
        assert cw.proven and cw.sign == sign and not cw.tangent_exact
        del fr


# --------------------------------------------------------------------------- never certify a wrong answer

def test_non_vertices_never_certified():
    case = next(c for c in CASES if c["name"] == "four_circles" or c["group"] == "four_circles")
    c1, c2, c3, c4 = _conics(case)
    from curvedvoronoi.runtime.solve.vertices import generalised_vertices
    sol = generalised_vertices(c1, c2, c3)
    true = {(round(float(v["x"]), 6), round(float(v["y"]), 6)) for v in case["vertices"]}
    n_false = 0
    for x, y, R in sol.points:
        if abs(x.imag) + abs(y.imag) + abs(R.imag) > 1e-8 or R.real <= 0:
            continue
        cv = certify_vertex(c1, c2, c3, x.real, y.real, R.real, c4)
        is_true = (round(x.real, 6), round(y.real, 6)) in true
        assert cv.proven == is_true
        if not is_true:
            n_false += 1
            assert cv.true_vertex is False  # proved: a point of some site is strictly closer
    assert n_false >= 1
    # a random point is not a vertex: no proof
    cv = certify_vertex(c1, c2, c3, 0.123, 4.56, 2.0, c4)
    assert not cv.proven


# --------------------------------------------------------------------------- property test vs independent reference

def _rand_conic(rng):
    kind = rng.choice(["ellipse", "parabola", "hyperbola", "circle"])
    a, b = rng.choice(DIRS)
    tx, ty = Fraction(rng.randint(-30, 30), 10), Fraction(rng.randint(-30, 30), 10)
    if kind == "circle":
        return {"type": "circle", "cos": 1, "sin": 0, "tx": tx, "ty": ty, "r2": Fraction(rng.randint(1, 9), 4)}
    if kind == "parabola":
        return {"type": "parabola", "cos": a, "sin": b, "tx": tx, "ty": ty, "p": Fraction(rng.randint(1, 9), 10)}
    A2, B2 = Fraction(rng.randint(2, 16), 4), Fraction(rng.randint(1, 8), 4)
    return {"type": kind, "cos": a, "sin": b, "tx": tx, "ty": ty, "A2": A2, "B2": B2}


def _conic_of(spec):
    d = dict(spec)
    kind = d.pop("type")
    return Conic.from_canonical(kind, **d)


@pytest.mark.parametrize("seed", range(4))
def test_property_agrees_with_reference(seed):
    """Candidates from the numeric locator (runtime.solve.vertices); certified answers checked against
    50-digit distances of the independent reference oracle."""
    from curvedvoronoi.runtime.solve.vertices import voronoi_vertices_triple
    from curvedvoronoi.runtime.result import LocatorError
    rng = random.Random(seed)
    for _attempt in range(10):  # the numeric locator may refuse a configuration: draw another
        specs = [_rand_conic(rng) for _ in range(4)]
        try:
            cs = [_conic_of(s) for s in specs]
            tv = voronoi_vertices_triple(*cs[:3])
        except (LocatorError, ValueError):
            continue
        if tv.vertices:
            break
    else:
        raise AssertionError("no usable random configuration in 10 draws")
    refs = [RefConic(s) for s in specs]
    checked = 0
    for v in tv.vertices:
        cv = certify_vertex(*cs[:3], v.x, v.y, v.radius ** 2, cs[3])
        if not cv.proven:
            continue
        x, y = mpmath.mpf(cv.box[0].mid().str(40, radius=False)), mpmath.mpf(cv.box[1].mid().str(40, radius=False))
        r = mpmath.mpf(cv.radius.mid().str(40, radius=False))
        # distances are 1-Lipschitz in q: the proven balls bound the admissible deviation
        tol = sum(float(b.rad()) for b in (cv.box[0], cv.box[1], cv.radius)) + 1e-30
        for rc in refs[:3]:
            assert abs(ref_distance(rc, x, y, dps=40) - r) <= tol
        d4 = ref_distance(refs[3], x, y, dps=40)
        if abs(d4 - r) > mpmath.mpf(10) ** -18 * r:
            assert cv.sign == (1 if d4 > r else -1)
        checked += 1
    assert checked == len(tv.vertices)


# --------------------------------------------------------------------------- completeness and certify_result

def test_certify_result_and_completeness():
    from curvedvoronoi.runtime.solve.vertices import generalised_vertices
    case = next(c for c in CASES if c["group"] == "mixed" and len(c["vertices"]) == 3)
    c1, c2, c3, c4 = _conics(case)
    sol = generalised_vertices(c1, c2, c3)
    ok, note = certify_completeness(c1, c2, c3, sol.points, sol.info.expected)
    assert ok, note
    # dropping a solution, or a wrong count, is not complete
    assert not certify_completeness(c1, c2, c3, sol.points[1:], sol.info.expected)[0]
    assert not certify_completeness(c1, c2, c3, sol.points, None)[0]
    # numeric result with a duplicated vertex and one bogus vertex
    verts = [VoronoiVertex(x=float(v["x"]) + 1e-12, y=float(v["y"]), radius=float(v["radius"]))
             for v in case["vertices"]]
    verts.append(VoronoiVertex(x=verts[0].x, y=verts[0].y, radius=verts[0].radius))
    res = LocatorResult(conflict=False, vertices=verts, method="numeric")
    out = certify_result(res, c1, c2, c3, c4, solutions=sol.points, expected_count=sol.info.expected)
    assert out.complete and out.certified, out.notes
    assert len(out.vertices) == len(case["vertices"])
    assert out.conflict == case["conflict"]
    # a vertex missing from the candidates is found and proved at its real solution, and a
    # candidate that proves nothing (Newton leaves it) is dropped once the list is proved complete:
    # the answer is still the validation file's vertices (exact rationals, an independent source)
    stray = VoronoiVertex(x=verts[0].x + 0.5, y=verts[0].y - 0.5, radius=verts[0].radius)
    res2 = LocatorResult(conflict=False, vertices=verts[:-2] + [stray], method="numeric")
    out2 = certify_result(res2, c1, c2, c3, c4, solutions=sol.points, expected_count=sol.info.expected)
    assert out2.complete and out2.certified, out2.notes
    assert any("found and proved at a real solution" in n for n in out2.notes), out2.notes
    assert any("not proved, and the proved list is complete without it" in n for n in out2.notes), out2.notes
    exp = sorted((float(Fraction(v["x"])), float(Fraction(v["y"]))) for v in case["vertices"])
    got = sorted((v.x, v.y) for v in out2.vertices)
    assert len(got) == len(exp) and all(math.hypot(a - c, b - d) <= 1e-9 * (1 + abs(c) + abs(d))
                                        for (a, b), (c, d) in zip(got, exp))
    assert out2.conflict == case["conflict"]
    # with a solution list that is not all of them (one solution dropped) nothing is dropped either
    out2c = certify_result(res2, c1, c2, c3, c4, solutions=sol.points[1:], expected_count=sol.info.expected)
    assert not out2c.complete and not out2c.certified and len(out2c.vertices) == len(exp)
    # without the solution list nothing is found or dropped (two vertices and the stray candidate),
    # and the list is not complete
    out2b = certify_result(res2, c1, c2, c3, c4)
    assert not out2b.complete and not out2b.certified and len(out2b.vertices) == len(exp)
    # without a solution list completeness is not claimed
    out3 = certify_result(res, c1, c2, c3, c4)
    assert not out3.complete and all(v.certified for v in out3.vertices)


def test_a_proof_of_another_vertex_is_not_taken_for_a_missing_one():
    """The completeness proof adds a vertex found at a real solution K only when its proof is of the
    zero in K (its box inside K, or one Krawczyk box holding both): given a proof of one of the
    other vertices at every K, the list with a vertex missing stays not complete and nothing is
    found; given a proof at K itself, it is complete."""
    from curvedvoronoi.runtime.certify.complete import completeness_with_vertices
    from curvedvoronoi.runtime.solve.vertices import generalised_vertices

    case = next(c for c in CASES if c["group"] == "mixed" and len(c["vertices"]) == 3)
    c1, c2, c3, c4 = _conics(case)
    sol = generalised_vertices(c1, c2, c3)
    vs = [(float(Fraction(v["x"])), float(Fraction(v["y"])), float(Fraction(v["radius"]))) for v in case["vertices"]]
    certs = [certify_vertex(c1, c2, c3, x, y, r * r) for x, y, r in vs]
    assert all(cv.proven for cv in certs)
    wrong, found = [], []
    ok, note = completeness_with_vertices(c1, c2, c3, sol.points, sol.info.expected, certs[1:],
                                          certify_at=lambda K: certs[1], found=wrong)
    assert not ok and not wrong, note
    # nor a box that only meets K: a proof whose box holds two vertices (no Krawczyk box holds
    # both zeros) and whose "tighter" box is that same wide box, not inside K
    from dataclasses import replace as _replace
    from flint import arb as _arb
    wide = tuple(_arb((certs[0].box[i].mid() + certs[1].box[i].mid()) / 2,
                      abs(certs[0].box[i].mid() - certs[1].box[i].mid()) + 1) for i in range(3))
    both = _replace(certs[1], box=wide)
    ok, note = completeness_with_vertices(c1, c2, c3, sol.points, sol.info.expected, certs[1:],
                                          certify_at=lambda K: both, retighten=lambda cv: cv.box, found=wrong)
    assert not ok and not wrong, note
    ok, note = completeness_with_vertices(c1, c2, c3, sol.points, sol.info.expected, certs[1:],
                                          certify_at=lambda K: certify_vertex(c1, c2, c3, K[0].mid(), K[1].mid(),
                                                                              K[2].mid()), found=found)
    assert ok and len(found) == 1, note
    assert abs(float(found[0].box[0].mid()) - vs[0][0]) <= 1e-9 * (1 + abs(vs[0][0]))


def test_distinct_vertices_whose_boxes_cannot_be_told_apart_are_never_merged(monkeypatch):
    """Two proven vertices are merged only when one Krawczyk box of the offset system holds both
    (runtime.certify.conflicts.certify_result).  With the box comparison made to answer "cannot
    tell" for every pair (as for overlapping boxes of a near-double pair), the three distinct
    vertices of a validation case stay three, uncertified and named not proven distinct."""
    from curvedvoronoi.runtime.certify import conflicts

    case = next(c for c in CASES if c["group"] == "mixed" and len(c["vertices"]) == 3)
    c1, c2, c3, c4 = _conics(case)
    verts = [VoronoiVertex(x=float(v["x"]), y=float(v["y"]), radius=float(v["radius"])) for v in case["vertices"]]
    monkeypatch.setattr(conflicts, "_same_solution", lambda a, b: None)
    out = certify_result(LocatorResult(conflict=False, vertices=verts, method="numeric"), c1, c2, c3, c4)
    assert len(out.vertices) == 3 and not any(v.certified for v in out.vertices)
    assert any("two vertices not proven distinct" in n for n in out.notes)
    assert not any("same vertex as another" in n for n in out.notes)


def test_simplest_rational():
    assert simplest_rational(Fraction(66, 100), Fraction(67, 100)) == Fraction(2, 3)
    assert simplest_rational(Fraction(-34, 100), Fraction(-33, 100)) == Fraction(-1, 3)
    assert simplest_rational(Fraction(1), Fraction(1)) == 1
    x = Fraction(355, 113)
    assert simplest_rational(x - Fraction(1, 10 ** 9), x + Fraction(1, 10 ** 9)) == x


# --------------------------------------------------------------------------- fast (float) completeness path

def _solved_triple(name_group="mixed"):
    from curvedvoronoi.runtime.solve.vertices import generalised_vertices
    case = next(c for c in CASES if c["group"] == name_group and len(c["vertices"]) == 3)
    c1, c2, c3, _ = _conics(case)
    return c1, c2, c3, generalised_vertices(c1, c2, c3)


def test_fast_path_agrees_with_arb_path():
    """Every box of the rigorous float Krawczyk test has the same kind as the acb path's box and the
    two enclosures intersect (both contain the unique solution); most solutions are fast-certified."""
    from curvedvoronoi.runtime.certify.complete import certify_solutions
    c1, c2, c3, sol = _solved_triple()
    S = np.asarray(sol.points)
    fast = certify_solutions(c1, c2, c3, S, method="fast")
    n_fast = sum(k is not None for k, _ in fast)
    assert n_fast >= 0.8 * len(S)
    idx = [k for k, (kind, _) in enumerate(fast) if kind is not None][::7]
    arbb = certify_solutions(c1, c2, c3, S[idx], method="arb", prec=128, iters=8)
    for k, (kind_a, Ka) in zip(idx, arbb):
        kind_f, Kf = fast[k]
        assert kind_a == kind_f
        assert all(a.overlaps(f) for a, f in zip(Ka, Kf))
        if kind_f == "real":  # the real solution is within the float box, compared with mpmath-free arb
            assert all(abs(float(a.mid()) - float(f.mid())) <= float(f.rad()) + float(a.rad()) for a, f in zip(Ka, Kf))
    # "auto" certifies everything (fast path + arb fallback) and the completeness proof succeeds
    auto = certify_solutions(c1, c2, c3, S)
    assert all(kind is not None for kind, _ in auto)
    assert _completeness(c1, c2, c3, S, sol.info.expected)[0]


def test_fast_path_rejects_bad_solution_lists():
    c1, c2, c3, sol = _solved_triple()
    S = np.asarray(sol.points).copy()
    N = sol.info.expected
    assert _completeness(c1, c2, c3, S, N)[0]
    # duplicated solutions (replacing others): count right, but boxes coincide, more of them than the
    # lost-root search replaces -> not complete
    D = S.copy()
    D[1:6] = D[0]
    ok, note, _ = _completeness(c1, c2, c3, D, N)
    assert not ok and "overlap" in note
    # missing solution (N - 1 given) -> not complete
    assert not _completeness(c1, c2, c3, S[1:], N)[0]
    # perturbed "solutions" far from any solution cannot be certified: more of them than the chart
    # test and the lost-root search take on -> not complete
    P = S.copy()
    P[:20] = P[:20] + np.array([0.37 + 0.11j, -0.23 + 0.05j, 1.7 - 0.3j]) * (1 + np.abs(P[:20]))
    ok, note, _ = _completeness(c1, c2, c3, P, N)
    assert not ok and "not certified" in note
    # five of them: Newton in a chart or around them may reach zeros; then the list is proved only if
    # the N enclosures are disjoint, and its real solutions are exactly the correct list's
    P = S.copy()
    P[:5] = P[:5] + np.array([0.37 + 0.11j, -0.23 + 0.05j, 1.7 - 0.3j]) * (1 + np.abs(P[:5]))
    ok, note, reals = _completeness(c1, c2, c3, P, N)
    if ok:
        ref = _completeness(c1, c2, c3, S, N)[2]
        assert len(reals) == len(ref)
        assert all(sum(all(a.overlaps(b) for a, b in zip(K, K0)) for K0 in ref) == 1 for K in reals)
    # one such point in place of a non-real solution: the conjugate of its partner's box holds the
    # lost zero, which replaces it (and the real solutions are still exactly the list's real ones)
    k = int(np.nonzero(np.abs(S.imag).max(axis=1) > 1e-3)[0][0])
    P = S.copy()
    P[k] = P[k] + np.array([0.37 + 0.11j, -0.23 + 0.05j, 1.7 - 0.3j]) * (1 + np.abs(P[k]))
    ok, note, reals = _completeness(c1, c2, c3, P, N)
    assert ok and "replaced" in note
    assert len(reals) == len(_completeness(c1, c2, c3, S, N)[2])
    # a slightly perturbed solution converges back onto its solution: still a valid (complete) list
    Q = S.copy()
    Q[0] = Q[0] * (1 + 1e-9)
    assert _completeness(c1, c2, c3, Q, N)[0]


def test_fast_path_point_not_near_a_solution_is_not_certified():
    """The float Krawczyk test never certifies a point with a large residual (random points)."""
    from curvedvoronoi.runtime.certify.offset_batch import certify_batch
    c1, c2, c3, _ = _solved_triple()
    rng = np.random.default_rng(7)
    P = rng.normal(size=(50, 3)) + 1j * rng.normal(size=(50, 3))
    P[:, 2] *= 10
    out = certify_batch(c1, c2, c3, P)
    assert all(kind is None for kind, _ in out)


def test_disjoint_sweep_matches_all_pairs():
    from flint import acb, arb
    from curvedvoronoi.runtime.certify.solution_boxes import boxes_disjoint, boxes_disjoint_all_pairs
    rng = np.random.default_rng(3)
    for trial in range(30):
        n = 25
        c = rng.integers(0, 4, size=(n, 3)) + 1j * rng.integers(0, 4, size=(n, 3)) * (trial % 2)
        r = rng.uniform(0.05, 0.6, size=(n, 3))
        Ks = [[acb(arb(float(c[a, i].real), float(r[a, i])), arb(float(c[a, i].imag), float(r[a, i])))
               if trial % 3 else arb(float(c[a, i].real), float(r[a, i])) for i in range(3)] for a in range(n)]
        assert boxes_disjoint(Ks) == boxes_disjoint_all_pairs(Ks)


def test_integer_specialisation_equals_artefact_specialise():
    """offset_terms' integer-arithmetic specialisation equals OffsetPolynomial.specialise (scaled)."""
    from curvedvoronoi.runtime.artefacts import load_offset
    from curvedvoronoi.runtime.certify.offset_system import offset_terms
    from curvedvoronoi.runtime.certify.foot import normalised_coefficients
    o = load_offset("generic")
    rnd = random.Random(5)
    for _ in range(3):
        co = normalised_coefficients([Fraction(rnd.randint(-40, 40), rnd.randint(1, 30)) for _ in range(6)])
        spec = o.specialise(**dict(zip("abcdef", co)))
        m = max(abs(v) for v in spec.values())
        assert sorted(offset_terms.__wrapped__(co)) == sorted((i, j, k, v / m) for (i, j, k), v in spec.items())


def test_epc_tangent_far_point_is_certified_in_a_circle_space_chart():
    """exact_EPC_circle4_tangent: the 60th solution (x ≈ -4.7e5, Jacobian condition ~5e22 in
    (x, y, R)) was once diagnosed as a point at infinity; the homotopy (runtime.solve.homotopy) and the
    circle-space Krawczyk test (runtime.certify.chart) show it is a finite simple real solution, so
    completeness is proven: 60 distinct simple solutions = the generic CEP count.  Whether the
    completeness proof needs the chart for it depends on the BLAS kernel's rounding of the list
    (with OpenBLAS Sandybridge kernels the (x, y, R) Krawczyk test already succeeds), so the chart's
    proof of that solution is asserted on its own."""
    from curvedvoronoi.runtime.certify.chart import certify_in_chart
    from curvedvoronoi.runtime.sites.conic import Conic
    from curvedvoronoi.runtime.predicates.locator import voronoi_vertices
    from curvedvoronoi.runtime.certify.complete import certify_completeness
    d = json.loads(DATA.read_text())
    c = [x for x in d["cases"] if x["name"] == "exact_EPC_circle4_tangent"][0]
    cs = [Conic.from_coefficients(*(Fraction(v) for v in k["coefficients"])) for k in c["conics"]][:3]
    sol = voronoi_vertices(*cs).solution
    ok, note = certify_completeness(*cs, sol.points, sol.info.expected)
    assert ok, note
    assert note.startswith("60 distinct simple solutions")
    P = np.asarray(sol.points)
    far = int(np.argmax(np.abs(P[:, 0])))
    assert abs(P[far, 0]) > 1e5 and np.max(np.abs(P[far].imag)) <= 1e-6 * np.max(np.abs(P[far]))
    box = certify_in_chart(tuple(cs), P[far])
    assert box is not None and box[0] == "real"
    # the list reads it only to its conditioning (1.4e-6 of its size off with Haswell kernels)
    assert abs(float(box[1][0].mid()) - P[far, 0].real) <= 1e-5 * abs(P[far, 0])
