"""Completeness of a certified vertex list (runtime/certify/complete.py,
``completeness_with_vertices``) when a certificate's box is looser than the solution's enclosure,
and the chart test that encloses the solutions (runtime/certify/chart.py) from non-real starts.

A certificate box is any proved enclosure of its vertex: widening it (here by ±10⁻¹⁰ in x, y and R)
keeps it an enclosure of the same vertex, so the vertex list is exactly as complete as before.  The
scene is the validation set's first "mixed" case with three true vertices (the vertex list of the
validation data, built independently of the certification)."""
from __future__ import annotations

import dataclasses
import json
from fractions import Fraction

from flint import arb

from curvedvoronoi.runtime.certify.chart import certify_in_chart
from curvedvoronoi.runtime.certify.complete import completeness_with_vertices
from curvedvoronoi.runtime.certify.conflicts import certify_vertex
from curvedvoronoi.runtime.sites.conic import Conic
from curvedvoronoi.runtime.solve.vertices import generalised_vertices
from curvedvoronoi.runtime.validation import required_cases_path


def _mixed_case():
    cases = json.loads(required_cases_path().read_text())["cases"]
    case = next(c for c in cases if c["group"] == "mixed" and len(c["vertices"]) == 3)
    return case, [Conic.from_coefficients(*e["coefficients"]) for e in case["conics"]]


def test_a_looser_certificate_box_still_matches_its_solution():
    """Each of the three validation vertices is certified; with every certificate box widened by
    ±10⁻¹⁰ the boxes no longer lie inside the solutions' enclosures but overlap them, and the list is
    still proved complete (the overlap is closed by Krawczyk's test on a box holding both, which
    holds one zero of the offset system), without any retightening."""
    case, (c1, c2, c3, c4) = _mixed_case()
    sol = generalised_vertices(c1, c2, c3)
    certs = [certify_vertex(c1, c2, c3, v["x"], v["y"], Fraction(v["radius"]) ** 2, c4) for v in case["vertices"]]
    assert all(c.proven and c.true_vertex for c in certs)
    loose = [dataclasses.replace(c, box=tuple(b + arb(0, 1e-10) for b in c.box)) for c in certs]
    ok, note = completeness_with_vertices(c1, c2, c3, sol.points, sol.info.expected, loose, retighten=None)
    assert ok, note


def test_a_real_zero_reached_from_a_nonreal_start_is_never_called_nonreal():
    """Started 10⁻⁴ off the real axis next to a real vertex (x, y, R) of the validation data, the
    chart's complex Newton converges to that real zero (the 60 solutions are simple and far apart),
    and Krawczyk's complex box around it meets the real axis in every component.  Such a box holds
    one zero, real or not -- it may be reported 'real' (proved otherwise) or given up, never 'nonreal'
    when it lies on the real vertex."""
    case, cs = _mixed_case()
    for v in case["vertices"]:
        x, y, R = float(v["x"]), float(v["y"]), float(v["radius"]) ** 2
        res = certify_in_chart(cs[:3], [x + 1e-4j, y - 1e-4j, R + 1e-4j])
        if res is None or res[0] == "real":
            continue
        K = res[1]
        on_vertex = all(abs(float(k.real.mid()) - t) < 1e-9 for k, t in zip(K, (x, y, R)))
        assert not on_vertex, (v, K)


def test_a_nonreal_solution_two_millionths_off_the_real_axis_is_proved_nonreal():
    """Circles of radius 1/2 at (∓1, 0) and of radius 3/2 at (0, b), b = 2⁻¹⁸.  At b = 0 the third
    circle touches both others from outside-in at (±3/2, 0) and the offset system
    ((x − a)² + (y − c)² − r² − R)² = 4r²R has double real zeros at (∓1/2, 0, 1); for b > 0 each splits
    into a conjugate pair with y ≈ (1 ± i)·b/2, i.e. 1.9·10⁻⁶ off the real axis (the zero is found
    here with mpmath at 50 digits from the system written out above, not with the library).  The
    chart test from that zero proves a box holding it and excluding the real axis ('nonreal'): the
    imaginary part is above its nearly-real threshold of 10⁻⁶ relative."""
    import mpmath

    from flint import acb

    mpmath.mp.dps = 50
    try:
        b = mpmath.mpf(2) ** -18
        circ = [(-1, 0, mpmath.mpf(1) / 2), (1, 0, mpmath.mpf(1) / 2), (0, b, mpmath.mpf(3) / 2)]

        def offsets(x, y, R):
            return [((x - a) ** 2 + (y - c) ** 2 - r * r - R) ** 2 - 4 * r * r * R for a, c, r in circ]

        z = mpmath.findroot(offsets, (mpmath.mpc(-0.5, 0), mpmath.mpc(b / 2, b / 2), mpmath.mpc(1, 0)))
        assert abs(z[1].imag - b / 2) < b / 100 and max(abs(v) for v in offsets(*z)) < mpmath.mpf(10) ** -40
        s = [complex(t) for t in z]
    finally:
        mpmath.mp.dps = 15
    cs = [Conic.from_coefficients(1, 0, 1, -2 * a, -2 * c, a * a + c * c - r * r)
          for a, c, r in ((-1, 0, Fraction(1, 2)), (1, 0, Fraction(1, 2)), (0, Fraction(1, 2 ** 18), Fraction(3, 2)))]
    res = certify_in_chart(cs, s)
    assert res is not None and res[0] == "nonreal", res
    K = res[1]
    assert all(k.contains(acb(t.real, t.imag)) for k, t in zip(K, s)) or \
        all(abs(complex(k.real.mid(), k.imag.mid()) - t) < 1e-12 for k, t in zip(K, s))
    assert any(not k.imag.contains(0) for k in K)


def test_starts_a_thousandth_off_the_real_solutions_are_certified_back():
    """The 8 real solutions (x, y, R) of the mixed case's offset system (60 in all), each moved by a
    relative 10⁻³ (x(1 + 10⁻³), y(1 − 10⁻³), R(1 + 10⁻³)): Newton's quadratic convergence brings
    such a start to the simple zero within a few steps (10⁻³ → 10⁻⁶ → 10⁻¹²), and the ball test
    (``method="arb"``, 64 bits, 4 Newton steps) then proves a real box around the same solution."""
    import numpy as np

    from curvedvoronoi.runtime.certify.complete import certify_solutions

    case, cs = _mixed_case()
    sol = generalised_vertices(*cs[:3])
    P = np.asarray(sol.points)
    real = P[np.abs(P.imag).max(axis=1) < 1e-9].real
    assert len(real) == 8
    out = certify_solutions(*cs[:3], real * (1 + 1e-3 * np.array([1, -1, 1])), method="arb", prec=64, iters=4)
    for s, (kind, K) in zip(real, out):
        assert kind == "real", (s, kind)
        assert all(abs(float(k.mid()) - t) < 1e-9 * (1 + abs(t)) for k, t in zip(K, s)), (s, K)
