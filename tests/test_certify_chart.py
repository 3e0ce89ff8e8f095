"""Certification of far solutions in circle-space charts (runtime.certify.chart; thesis §4.4, §5.3–§5.5).

Facts asserted: the circle-space offsets satisfy Q_i(A, x̂, ŷ, T̂) = c_i·A^{d_i}·o_i(x̂/A, ŷ/A,
(x̂² + ŷ²)/A² − T̂/A) exactly (random rational points, all charts); the far solution of
exact_EPC_circle4_tangent (|x| ≈ 4.7e5, Jacobian condition ≈ 10²² in (x, y, R)) is certified in a
chart and agrees with the independent parameter homotopy (runtime.solve.homotopy), so the locator's
answer is complete and certified and still equals the validation oracle; ordinary solutions get
the same kind and overlapping enclosures in a chart as in world coordinates; a perturbed far
solution is refused by the Krawczyk test at the perturbed point, and Newton in the chart certifies
the true one instead; corrupted solution lists are refused or repaired, never proved wrong.
"""
from __future__ import annotations

import json
import random
from fractions import Fraction

import numpy as np
import pytest
from flint import acb, arb, fmpq

from curvedvoronoi.runtime.algebra.circle_space import circle_space_terms
from curvedvoronoi.runtime.certify.chart import (ChartSystem, certify_in_chart, chart_polynomials, choose_charts,
                                   world_from_chart)
from curvedvoronoi.runtime.certify.complete import _completeness, certify_solutions
from curvedvoronoi.runtime.certify.offset_system import OffsetSystem, krawczyk_complex, offset_terms
from curvedvoronoi.runtime.certify.foot import normalised_coefficients, working_prec
from curvedvoronoi.runtime.sites.conic import Conic
from curvedvoronoi.runtime.solve.exact import solve_exact
from curvedvoronoi.runtime.validation import required_cases_path

CASES = json.loads(required_cases_path().read_text())["cases"]


def _case(name):
    c = next(c for c in CASES if c["name"] == name)
    return c, [Conic.from_coefficients(*(Fraction(v) for v in k["coefficients"])) for k in c["conics"]]


@pytest.fixture(scope="module")
def epc():
    from curvedvoronoi.runtime.predicates.locator import voronoi_vertices
    case, cs = _case("exact_EPC_circle4_tangent")
    sol = voronoi_vertices(*cs[:3]).solution
    S = np.asarray(sol.points)
    far = int(np.argmax(np.abs(S).max(axis=1)))
    return case, cs, S, sol.info.expected, far


# --------------------------------------------------------------------------- polynomial identity

def _eval(terms, pt):
    out = Fraction(0)
    for *e, c in terms:
        t = Fraction(c)
        for v, k in zip(pt, e):
            t *= v ** k
        out += t
    return out


def _random_conic(kind, rnd):
    r = lambda: Fraction(rnd.randint(-60, 60), rnd.randint(1, 9))  # noqa: E731
    if kind == "circle":
        a = Fraction(rnd.randint(1, 30), rnd.randint(1, 7))
        return (a, 0, a, r(), r(), r())
    if kind == "parabola":
        p, q = r(), r()
        return (p * p, 2 * p * q, q * q, r(), r(), r())
    while True:
        a, b, c = r(), r(), r()
        disc = b * b - 4 * a * c
        if (kind == "ellipse" and disc < 0) or (kind == "hyperbola" and disc > 0):
            return (a, b, c, r(), r(), r())


@pytest.mark.parametrize("kind", ["ellipse", "hyperbola", "parabola", "circle"])
def test_chart_polynomial_identity(kind):
    """Q_i(1, x, y, x² + y² − R) = c_i·o_i(x, y, R), and in every chart
    Q_i(A, x̂, ŷ, T̂) = c_i·A^{d_i}·o_i(x̂/A, ŷ/A, (x̂² + ŷ²)/A² − T̂/A), exactly (seeded random
    rationals); the chart system's balls contain the exact values."""
    rnd = random.Random(["ellipse", "hyperbola", "parabola", "circle"].index(kind) + 11)
    for _ in range(2):
        co = normalised_coefficients([Fraction(v) for v in _random_conic(kind, rnd)])
        o = offset_terms(co)
        q = circle_space_terms({(i, j, k): v for i, j, k, v in o})
        ((d, Q, c),) = chart_polynomials((co,))
        assert d == max(sum(e) for e in q) and all(sum(e) == d for e in Q)
        assert d < max(i + j + 2 * k for i, j, k, _ in o)        # much lower than weighted degree 8
        Qt = [(*e, v) for e, v in Q.items()]
        for _ in range(6):
            x, y, R = (Fraction(rnd.randint(-99, 99), rnd.randint(1, 13)) for _ in range(3))
            ov = _eval(o, (x, y, R))
            assert _eval([(i, j, k, v) for (i, j, k), v in q.items()], (x, y, x * x + y * y - R)) == ov
            assert _eval(Qt, (1, x, y, x * x + y * y - R)) == c * ov
            A, xh, yh, Th = (Fraction(rnd.randint(-99, 99) or 1, rnd.randint(1, 13)) for _ in range(4))
            wx, wy = xh / A, yh / A
            val = c * A ** d * _eval(o, (wx, wy, wx * wx + wy * wy - Th / A))
            assert _eval(Qt, (A, xh, yh, Th)) == val
            for j in range(4):   # chart j: h_j = 1, the homogeneous point scaled by 1/h_j
                h = [A, xh, yh, Th]
                u = [h[t] / h[j] for t in range(4) if t != j]
                with working_prec(128):
                    (g,), _ = ChartSystem(((d, Q, c),), j).eval([acb(arb(t.numerator) / t.denominator)
                                                                 for t in u], jac=False)
                    exact = val / h[j] ** d
                    assert g.contains(arb(exact.numerator) / exact.denominator)


def test_chart_degrees_epc():
    """Degrees of the circle-space offsets of exact_EPC's conics (ellipse, parabola, circle)."""
    _, cs = _case("exact_EPC_circle4_tangent")
    P = chart_polynomials(tuple(normalised_coefficients(c) for c in cs[:3]))
    assert [d for d, _, _ in P] == [6, 5, 6]


# --------------------------------------------------------------------------- exact_EPC far solution

def test_epc_far_solution_certified_in_chart(epc):
    case, cs, S, N, far = epc
    s = S[far]
    assert abs(s[0]) > 1e5
    # the world-coordinate Krawczyk test fails on it (that is why the chart is needed) ...
    assert certify_solutions(*cs[:3], S[far:far + 1], prec=256, iters=8)[0][0] is None
    # ... the chart test certifies a real finite simple solution
    res = certify_in_chart(cs[:3], s)
    assert res is not None and res[0] == "real"
    W = res[1]
    assert all(isinstance(w, arb) for w in W)
    assert all(float(w.rad()) < 1e-12 * abs(float(w.mid())) for w in W)
    # independent reference: the parameter homotopy (tracks in P³ of circles) finds the same point
    from curvedvoronoi.runtime.solve.vertices import generalised_vertices
    H = np.asarray(generalised_vertices(*cs[:3], solver="homotopy").points)
    h = H[int(np.argmin(np.abs(H[:, 0] - float(W[0].mid()))))]
    for w, ref in zip(W, h):
        assert abs(float(w.mid()) - ref.real) <= 1e-8 * abs(ref)
    # necessary condition: the exact offsets, evaluated on the enclosure, contain 0
    with working_prec(256):
        vals, _ = OffsetSystem(cs[:3]).eval([acb(w) for w in W], jac=False)
        assert all(v.contains(0) for v in vals)


def test_epc_locator_complete_and_certified():
    """locate_conflicts on exact_EPC: complete and certified, and the answer equals the oracle."""
    from curvedvoronoi.runtime.predicates.locator import clear_cache, locate_conflicts
    case, cs = _case("exact_EPC_circle4_tangent")
    clear_cache()
    res = locate_conflicts(*cs)
    assert res.complete, res.notes
    assert res.certified
    assert any("circle-space chart" in n for n in res.notes)
    assert res.conflict is case["conflict"] is False
    assert len(res.vertices) == len(case["vertices"])
    for ev in case["vertices"]:
        ex, ey, er = float(ev["x"]), float(ev["y"]), float(ev["radius"])
        v = min(res.vertices, key=lambda v: abs(v.x - ex) + abs(v.y - ey))
        assert abs(v.x - ex) <= 1e-8 and abs(v.y - ey) <= 1e-8 and abs(v.radius - er) <= 1e-8
        assert v.certified and v.in_conflict is False
        assert v.tangent is ev["tangent"]
    assert sum(v.tangent for v in res.vertices) == 1


def test_chart_agrees_with_world_on_ordinary_solutions(epc):
    """On ordinary (well-conditioned) solutions the chart test gives the same kind as the world
    test, and the two enclosures intersect (both contain the unique solution)."""
    _, cs, S, _, far = epc
    idx = [k for k in range(len(S)) if k != far][::6]
    world = certify_solutions(*cs[:3], S[idx], method="arb", prec=128, iters=8)
    kinds = set()
    for k, (kind, K) in zip(idx, world):
        assert kind is not None
        res = certify_in_chart(cs[:3], S[k])
        assert res is not None and res[0] == kind
        kinds.add(kind)
        assert all((a if isinstance(a, acb) else acb(a)).overlaps(b if isinstance(b, acb) else acb(b))
                   for a, b in zip(res[1], K))
    assert kinds == {"real", "nonreal"}


# --------------------------------------------------------------------------- negative controls

@pytest.mark.parametrize("rel", [(1e-3, 1e-3, 0.0), (-1e-3, 0.0, 0.0), (0.0, 0.0, 1e-3), (1e-3, -2e-3, 1e-3)])
def test_perturbed_far_solution_never_certified_wrongly(epc, rel):
    """A far 'solution' moved by 1e-3 relative: the Krawczyk test at the perturbed chart point
    itself fails (the verifier refuses a wrong point); Newton in the chart fails, or reaches a zero
    whose certified box holds one of msolve's exact real solutions (for three of the four
    perturbations: the far solution itself, whose box meets the unperturbed one's)."""
    _, cs, S, _, far = epc
    p = S[far] * (1 + np.array(rel))
    polys = chart_polynomials(tuple(normalised_coefficients(c) for c in cs[:3]))
    j, u = choose_charts(p)[0]
    with working_prec(128):
        assert krawczyk_complex(ChartSystem(polys, j), [acb(float(t.real)) for t in u], symmetric=True) is None
    res, ref = certify_in_chart(cs[:3], p), certify_in_chart(cs[:3], S[far])
    assert ref is not None and ref[0] == "real"
    if res is not None:
        assert res[0] == "real"
        exact = solve_exact(*cs[:3]).boxes
        with working_prec(256):
            hits = [b for b in exact if all(w.overlaps(_ball(lo).union(_ball(hi))) for w, (lo, hi) in zip(res[1], b))]
        assert len(hits) == 1
        if rel != (0.0, 0.0, 1e-3):
            assert all(a.overlaps(b) for a, b in zip(res[1], ref[1]))


def _ball(q: Fraction) -> arb:
    return arb(fmpq(q.numerator, q.denominator))


def test_perturbed_far_solution_list(epc):
    """Corrupted solution lists: a far solution perturbed by 1e-3 still stands for the true one
    (same proved real solutions); five copies of it in place of five others are refused
    (distinctness); one copy in place of another is repaired by the lost-root search; a point where
    no solution lies, in place of the far one, is refused."""
    _, cs, S, N, far = epc
    ok0, _, reals0 = _completeness(*cs[:3], S, N)
    assert ok0
    P = S.copy()
    P[far] = P[far] * (1 + np.array([1e-3, 1e-3, 0]))
    ok, note, reals = _completeness(*cs[:3], P, N)
    assert ok and len(reals) == len(reals0)
    assert all(any(all(a.overlaps(b) for a, b in zip(K, K0)) for K0 in reals0) for K in reals)
    # duplicating the far solution (replacing five others) is caught by distinctness
    D = S.copy()
    D[[(far + k) % len(S) for k in range(1, 6)]] = S[far]
    ok, note, _ = _completeness(*cs[:3], D, N)
    assert not ok and "overlap" in note
    # in place of one other solution, the lost-root search finds the one replaced, and the proved
    # real solutions are those of the correct list
    D = S.copy()
    D[(far + 1) % len(S)] = S[far]
    ok, note, reals = _completeness(*cs[:3], D, N)
    assert ok and "replaced" in note
    assert len(reals) == len(reals0)
    # the far solution dropped: an ordinary one twice and a point that is no solution in its place
    D = S.copy()
    D[far] = S[far] * (1 + np.array([0.5, -0.3, 0.2]))
    ok, note, _ = _completeness(*cs[:3], D, N)
    assert not ok


def test_world_from_chart_excludes_infinity():
    """An A-ball containing 0 (a chart point possibly at infinity) gives no world enclosure."""
    with working_prec(64):
        assert world_from_chart(1, [arb(0, 1e-9), arb(0.5), arb(2)]) is None
        W = world_from_chart(1, [arb(0.25), arb(0.5), arb(2)])
        assert [float(w.mid()) for w in W] == [4.0, 2.0, 4.0 ** 2 + 2.0 ** 2 - 8.0]
