"""Tests of runtime.locator (thesis ch. 5; issue 4).

* all 30 validation cases (tests/data/validation_cases.json): vertex counts, x, y, radius,
  distance_to_fourth (relative 1e-8), conflict flags; the two exactly tangent cases must come back
  undecided and uncertified; a case may only be refused (LocatorError) under the documented
  limitation (vertices far outside the scene);
* agreement with the independent reference of tests/reference.py on random rigid configurations
  of ellipses, hyperbolas, parabolas and mixes (a few in CI; LOCATOR_REFERENCE_ALL=1 runs 20 per
  type mix);
* the 'quadruple' route agrees with 'triple'; circles go to the exact circle locator; the per-triple
  cache gives the same answers; invariance under rational rigid motions (hypothesis);
* bad inputs give clear errors.
"""
from __future__ import annotations

import json
import math
import os
import sys
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from curvedvoronoi.runtime.validation import required_cases_path as _validation_path
from curvedvoronoi.runtime.conic import Conic
from curvedvoronoi.runtime.locator import clear_cache, demo_configuration, voronoi_vertices
from curvedvoronoi.runtime.locator import locate_conflicts as _locate_conflicts
from curvedvoronoi.runtime.result import InvalidConicError, LocatorError


def locate_conflicts(*args, **kw):
    """The numeric routes as such (no certification stage, no interval fallback): the
    certified default route is tested in tests/test_locator_certified.py."""
    kw.setdefault("certify", False)
    kw.setdefault("fallback", False)
    return _locate_conflicts(*args, **kw)

sys.path.insert(0, str(Path(__file__).resolve().parent))
from reference import reference_locate  # noqa: E402

DATA = _validation_path()
CASES = json.loads(DATA.read_text())["cases"]


def conics_of(case):
    return [Conic.from_coefficients(*k["coefficients"]) for k in case["conics"]]


def _parallel_parabolas(conics) -> bool:
    """Two parabolas among the first three with parallel axes: a non-generic configuration whose
    smaller count of generalised vertices the numeric route cannot tell from lost far solutions."""
    ps = [c.exact_frame for c in conics[:3] if c.kind == "parabola"]
    return any(a.cos * b.sin == a.sin * b.cos for i, a in enumerate(ps) for b in ps[:i])


def _far(vertices) -> bool:
    return any(float(v["radius"]) > 20 for v in vertices)


def _close(a, b, tol=1e-8):
    return abs(float(a) - float(b)) <= tol * max(1.0, abs(float(b)))


@pytest.mark.parametrize("case", CASES, ids=lambda c: c["name"])
def test_validation_case(case):
    cs = conics_of(case)
    try:
        res = locate_conflicts(*cs)
    except LocatorError:
        assert _far(case["vertices"]) or _parallel_parabolas(cs), "refused a case outside the documented limitations"
        return
    exp = sorted(case["vertices"], key=lambda v: (float(v["x"]), float(v["y"])))
    got = sorted(res.vertices, key=lambda v: (v.x, v.y))
    assert len(got) == len(exp)
    numeric = res.method in ("triple", "quadruple")
    if numeric:
        assert res.certified is False       # numeric route: never claims a proof
    for g, e in zip(got, exp):
        assert _close(g.x, e["x"]) and _close(g.y, e["y"]) and _close(g.radius, e["radius"])
        assert _close(g.distance_to_fourth, e["distance_to_fourth"])
        if numeric:
            assert g.certified is False
        if e["tangent"]:
            # margin exactly 0: the numeric route cannot decide; it must say so
            assert g.in_conflict is None
            assert abs(g.margin) < 1e-9
            assert any("undecided" in n for n in res.notes)
        else:
            assert g.in_conflict == e["in_conflict"]
    if not any(e["tangent"] for e in exp):
        assert res.conflict == case["conflict"]
    else:
        assert res.conflict is False      # no decided conflict in the tangent cases
    if all(c.kind == "circle" for c in cs):
        assert not numeric                  # four circles go to the exact locator (§3.1)


def test_quadruple_agrees_with_triple():
    names = ["ellipses_a_ellipse4_conflict", "parabolas_c_parabola4_noconflict", "mixed_CEP_hyperbola4_conflict",
             "hyperbolas_a_near_circle_-1e-7"]
    for case in (c for c in CASES if c["name"] in names):
        cs = conics_of(case)
        a = locate_conflicts(*cs, method="triple")
        b = locate_conflicts(*cs, method="quadruple")
        assert b.method == "quadruple"
        assert len(a.vertices) == len(b.vertices)
        for u, v in zip(a.vertices, b.vertices):
            assert u.in_conflict == v.in_conflict
            assert _close(u.distance_to_fourth, v.distance_to_fourth, 1e-9)
            assert (v.info["R_minus_r"] > 0) == v.in_conflict
        assert a.conflict == b.conflict == case["conflict"]


def test_cache_same_answer_and_hit():
    clear_cache()
    case = CASES[0]
    cs = conics_of(case)
    first = locate_conflicts(*cs)
    other = conics_of(CASES[1])[3]
    second = locate_conflicts(cs[0], cs[1], cs[2], other)
    assert "cache_lookup" in second.timings
    assert any("cache" in n for n in second.notes)
    assert [(v.x, v.y, v.radius) for v in first.vertices] == [(v.x, v.y, v.radius) for v in second.vertices]
    assert second.conflict == CASES[1]["conflict"]
    # the cached vertices are not mutated by a later query
    third = locate_conflicts(*cs)
    assert [v.in_conflict for v in third.vertices] == [v.in_conflict for v in first.vertices]


def test_demo_matches_reference():
    cs = demo_configuration()
    assert all(c.kind == "ellipse" for c in cs)
    res = locate_conflicts(*cs)
    ref = reference_locate(*cs)
    assert len(res.vertices) == len(ref) >= 1
    for g, e in zip(sorted(res.vertices, key=lambda v: (v.x, v.y)), ref):
        assert _close(g.x, e["x"]) and _close(g.radius, e["radius"])
        assert g.in_conflict == e["in_conflict"]


def test_bad_inputs():
    cs = demo_configuration()
    with pytest.raises(LocatorError, match="unknown method"):
        locate_conflicts(*cs, method="magic")
    with pytest.raises(LocatorError, match="Conic"):
        locate_conflicts(cs[0], cs[1], cs[2], (1, 0, 1, 0, 0, -1))
    with pytest.raises(LocatorError, match="same conic"):
        locate_conflicts(cs[0], cs[1], cs[0], cs[3])
    # the same conic given with scaled coefficients is still the same site
    scaled = Conic.from_coefficients(*(3 * c for c in cs[1].coefficients))
    with pytest.raises(LocatorError, match="same conic"):
        voronoi_vertices(cs[0], cs[1], scaled)
    with pytest.raises(LocatorError, match="circles"):
        locate_conflicts(*cs, method="circles")
    with pytest.raises(InvalidConicError):
        Conic.from_coefficients(1, 0, -1, 0, 0, 0)  # line pair


def test_mixed_circles_and_conics():
    circ = Conic.circle(centre=(Fraction(7, 2), -1), radius=1)
    cs = demo_configuration()
    res = locate_conflicts(cs[0], circ, cs[2], cs[3])
    ref = reference_locate(cs[0], circ, cs[2], cs[3])
    assert len(res.vertices) == len(ref)
    for g, e in zip(sorted(res.vertices, key=lambda v: (v.x, v.y)), ref):
        assert _close(g.x, e["x"]) and _close(g.y, e["y"]) and _close(g.radius, e["radius"])
        assert g.in_conflict == e["in_conflict"]


# --------------------------------------------------------------------- rigid motions

def _move(c: Conic, cos, sin, bx, by) -> Conic:
    """The image of c under p -> Q p + b (Q the rotation (cos, sin)), built exactly."""
    fr = c.exact_frame
    ci, si = fr.cos, fr.sin
    return Conic.from_canonical(fr.kind, ci * cos - si * sin, si * cos + ci * sin,
                                cos * fr.tx - sin * fr.ty + bx, sin * fr.tx + cos * fr.ty + by, **fr.params)


@settings(max_examples=3, deadline=None)
@given(st.sampled_from([(3, 4, 5), (5, 12, 13), (-8, 15, 17), (24, -7, 25)]),
       st.fractions(min_value=-3, max_value=3, max_denominator=8),
       st.fractions(min_value=-3, max_value=3, max_denominator=8))
def test_rigid_motion_invariance(rot, bx, by):
    a, b, h = rot
    cos, sin = Fraction(a, h), Fraction(b, h)
    cs = conics_of(next(c for c in CASES if c["name"] == "mixed_EHP_parabola4_conflict"))
    base = locate_conflicts(*cs)
    moved = locate_conflicts(*(_move(c, cos, sin, bx, by) for c in cs))
    assert len(base.vertices) == len(moved.vertices)
    img = sorted((float(cos) * v.x - float(sin) * v.y + float(bx), float(sin) * v.x + float(cos) * v.y + float(by),
                  v.radius, v.distance_to_fourth, v.in_conflict) for v in base.vertices)
    got = sorted((v.x, v.y, v.radius, v.distance_to_fourth, v.in_conflict) for v in moved.vertices)
    for p, q in zip(img, got):
        for s, t in zip(p[:4], q[:4]):
            assert abs(s - t) <= 1e-8 * max(1.0, abs(s))
        assert p[4] == q[4]


# --------------------------------------------------------------------- independent reference

ROTS = [(3, 4, 5), (5, 12, 13), (8, 15, 17), (7, 24, 25), (20, 21, 29), (12, 35, 37), (9, 40, 41)]


def random_configuration(kinds: str, seed: int):
    """Four conics of the given kinds (E ellipse, H hyperbola, P parabola, C circle) with rational
    rotations (Pythagorean triples) and rational positions in [-3, 3]²."""
    rng = np.random.default_rng(seed)
    out = []
    for i, k in enumerate(kinds):
        a, b, h = ROTS[int(rng.integers(len(ROTS)))]
        sg = 1 if rng.random() < 0.5 else -1
        rot = (Fraction(a, h), Fraction(sg * b, h))
        c = (Fraction(int(rng.integers(-30, 31)), 10), Fraction(int(rng.integers(-30, 31)), 10))
        A = Fraction(int(rng.integers(6, 21)), 10)
        B = Fraction(int(rng.integers(3, 10)), 10)
        if k == "E":
            out.append(Conic.ellipse(centre=c, axes=(A, B), rotation=rot))
        elif k == "H":
            out.append(Conic.hyperbola(centre=c, axes=(B, A / 2), rotation=rot))
        elif k == "P":
            out.append(Conic.parabola(vertex=c, p=B, rotation=rot))
        else:
            out.append(Conic.circle(centre=c, radius=B + Fraction(1, 5)))
    return out


MIXES = ["EEEE", "HHHH", "PPPP", "EPHC"]
N_ALL = 20
N_CI = int(os.environ.get("LOCATOR_REFERENCE_N", "1"))
FULL = os.environ.get("LOCATOR_REFERENCE_ALL") == "1"


def _confirmed_by_reference(cs, v) -> bool:
    """A vertex of ours that the grid-seeded reference did not find: confirm it with the reference's
    own tools (mpmath Newton on d1 = d2 = d3 from our point, dense-sampling true-vertex check)."""
    import mpmath
    import reference as R

    rc = [R.RefConic(c) for c in cs[:3]]
    with mpmath.workdps(R.DPS + 10):
        res = R._newton_vertex_mp(rc, (v.x, v.y), R.DPS)
        if res is None:
            return False
        ok = R._check_vertex(rc, res, [], R.DPS)
    return bool(ok) and _close(v.x, ok[0], 1e-7) and _close(v.y, ok[1], 1e-7) and _close(v.radius, ok[2], 1e-7)


def compare_with_reference(cs):
    """(status, n_vertices, disagreements, reference misses) for one configuration; status 'ok' or
    'refused'.  A vertex of ours missing from the reference counts as a disagreement unless the
    reference's own high-precision check confirms it (its grid seeding can miss tiny features)."""
    try:
        res = locate_conflicts(*cs)
    except LocatorError:
        return "refused", 0, 0, 0
    ref = reference_locate(*cs)
    got = sorted(res.vertices, key=lambda v: (v.x, v.y))
    bad = missed = 0
    unmatched = list(got)
    for e in ref:
        m = [g for g in unmatched if _close(g.x, e["x"], 1e-7) and _close(g.y, e["y"], 1e-7)]
        if not m:
            bad += 1                      # we missed a reference vertex
            continue
        g = m[0]
        unmatched.remove(g)
        if not (_close(g.radius, e["radius"], 1e-7) and _close(g.distance_to_fourth, e["distance_to_fourth"], 1e-7)
                and (g.in_conflict is None or g.in_conflict == e["in_conflict"])):
            bad += 1
    for g in unmatched:
        if _confirmed_by_reference(cs, g):
            missed += 1
        else:
            bad += 1
    return "ok", len(got), bad, missed


@pytest.mark.slow
@pytest.mark.parametrize("mix", MIXES)
def test_reference_random(mix):
    n = N_ALL if FULL else N_CI
    stats = {"ok": 0, "refused": 0, "vertices": 0, "bad": 0, "reference_missed": 0}
    for seed in range(n):
        st_, nv, bad, missed = compare_with_reference(random_configuration(mix, 1000 * MIXES.index(mix) + seed))
        stats[st_] += 1
        stats["vertices"] += nv
        stats["bad"] += bad
        stats["reference_missed"] += missed
    print(mix, stats)
    assert stats["bad"] == 0
    # refusals (LocatorError) are honest but must stay the exception; hyperbolas often have
    # far-away vertices and tight eigenvalue clusters (measured: 7 of 20 refused)
    assert stats["refused"] <= max(1, n // 2 if mix in ("HHHH", "EPHC", "PPPP") else n // 4)
