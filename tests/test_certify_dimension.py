"""Soundness of completeness by counting: zero-dimensionality proof, scene-frame certification.

Independent facts used:

* three conics tangent to the x-axis at the origin, all above it (circles of radii 1 and 3 centred
  on the y-axis, the ellipse x²/9 + (y − 2)²/4 = 1): every point q = (0, t), t < 0, is at distance
  |t| from all three (each lies in y ≥ 0 and contains the origin), so the offset system has the
  curve {x = 0, R = y²} of solutions -- positive-dimensional -- besides isolated ones (msolve with
  x ≠ 0 imposed by x·s = 1 isolates two real ones, (±1.715, 2.278, 1.298));
* the demo quadruple (thesis Fig. 5.5.1 analogue) is generic: 184 simple solutions (msolve count).
"""
from __future__ import annotations

import os
from fractions import Fraction as F

import numpy as np

from curvedvoronoi.runtime.sites.conic import Conic



def _tangent_triple():
    c1 = Conic.from_coefficients(1, 0, 1, 0, -2, 0)      # circle centre (0, 1), radius 1
    c2 = Conic.from_coefficients(1, 0, 1, 0, -6, 0)      # circle centre (0, 3), radius 3
    e = Conic.ellipse(centre=(0, 2), axes=(3, 2))        # x²/9 + (y − 2)²/4 = 1, through the origin
    return c1, c2, e


def test_tangent_triple_has_a_continuum_of_equidistant_points():
    """The fact the other tests rely on, checked with the distance module (dense sampling of t)."""
    from curvedvoronoi.runtime.sites.distance import distance
    for t in np.linspace(-3.0, -0.05, 12):
        ds = [distance(c, 0.0, float(t)) for c in _tangent_triple()]
        assert max(abs(d - abs(t)) for d in ds) < 1e-9


def test_zero_dimensional_generic_and_positive_dimensional():
    from curvedvoronoi.runtime.certify.dimension import zero_dimensional
    from curvedvoronoi.runtime.predicates.locator import demo_configuration
    ok, note = zero_dimensional(*demo_configuration()[:3])
    assert ok, note
    ok, note = zero_dimensional(*_tangent_triple())
    assert not ok
    assert "positive-dimensional" in note


def test_counting_does_not_claim_completeness_on_a_positive_dimensional_system():
    """Isolated solutions of the tangent triple (msolve on the system with x·s = 1 added, which
    removes the curve x = 0) are certified simple and distinct; their number is passed as the
    "generic count", so counting alone would close -- but the system also has a curve of
    solutions (equidistant points), so completeness must not be claimed."""
    from curvedvoronoi.runtime.certify.complete import _completeness, certify_solutions
    from curvedvoronoi.runtime.solve.exact import exact_triple_system, msolve_run, parse_output, system_text
    c1, c2, e = _tangent_triple()
    text = system_text(exact_triple_system(c1, c2, e))
    head, rest = text.split("\n", 1)
    out = parse_output(msolve_run(head + ",s\n" + rest.rstrip("\n") + ",\nx*s-1\n", "-p", "64"))
    S = np.array([[float((lo + hi) / 2) for lo, hi in b[:3]] for b in out[1][1]], dtype=complex)
    assert len(S) >= 1
    boxes = certify_solutions(c1, c2, e, S)
    assert all(kind == "real" for kind, _ in boxes)
    ok, note, _ = _completeness(c1, c2, e, S, len(S))
    assert not ok
    assert "= generic count, but" in note and "positive-dimensional" in note


def test_locator_refuses_a_continuum_of_vertices():
    from curvedvoronoi.runtime.predicates.locator import clear_cache, locate_conflicts
    from curvedvoronoi.runtime.solve.exact import InfinitelyManySolutions
    clear_cache()
    c4 = Conic.ellipse(centre=(5, 5), axes=(1, F(1, 2)))
    try:
        res = locate_conflicts(*_tangent_triple(), c4)
    except InfinitelyManySolutions:
        return
    assert not res.complete


def test_framed_evaluation_matches_world_evaluation():
    """OffsetSystem.eval (one acb matrix product) against a term-by-term evaluation, and the
    scene-frame system at (u, v, S) against the world system at (px + s·u, py + s·v, s²·S) up to
    the constant factor of the normalisation."""
    import flint
    from flint import acb, arb
    from curvedvoronoi.runtime.certify.offset_system import OffsetSystem, framed_offset_system, scene_frame
    from curvedvoronoi.runtime.predicates.locator import demo_configuration
    cs = demo_configuration()[:3]
    sys_w = OffsetSystem(cs)
    z = [acb(arb(1.3, 1e-12), arb(0.2, 1e-12)), acb(-0.7, 0.1), acb(2.5, -0.3)]
    vals, J = sys_w.eval(z)
    u, v, w = z
    for q, T in enumerate(sys_w.terms):
        s = acb(0)
        g = [acb(0), acb(0), acb(0)]
        for i, j, k, c in T:
            c = arb(flint.fmpq(c.numerator, c.denominator))
            s += c * u ** i * v ** j * w ** k
            if i:
                g[0] += c * i * u ** (i - 1) * v ** j * w ** k
            if j:
                g[1] += c * j * u ** i * v ** (j - 1) * w ** k
            if k:
                g[2] += c * k * u ** i * v ** j * w ** (k - 1)
        assert vals[q].overlaps(s)
        assert all(J[q][m].overlaps(g[m]) for m in range(3))
    px, py, sc = scene_frame(cs)
    sys_f = framed_offset_system(cs, (px, py, sc))
    P = [arb(flint.fmpq(t.numerator, t.denominator)) for t in (px, py, sc)]
    zw = [P[0] + P[2] * z[0], P[1] + P[2] * z[1], P[2] * P[2] * z[2]]
    fw, _ = sys_w.eval(zw)
    ff, _ = sys_f.eval(z)
    ratios = [complex((fw[q] / ff[q]).mid()) for q in range(3)]
    for q in range(3):
        # the framed polynomial is the world one composed with the frame, rescaled by a real constant
        assert abs(ratios[q].imag) < 1e-8 * abs(ratios[q])


def test_scene_frame_certifies_spread_out_solutions_with_world_boxes():
    """Spread-out scene (bench_nongeneric's "small sites far apart"): in scene coordinates the
    batched float Krawczyk test certifies many more solutions than in world coordinates, and the
    world boxes returned contain the numeric solutions and agree in kind with world-frame boxes."""
    import sys
    sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "bench"))
    from bench_nongeneric import cases
    from curvedvoronoi.runtime.certify.complete import certify_solutions
    from curvedvoronoi.runtime.predicates.locator import voronoi_vertices
    cs = cases()["small sites far apart (1/100)"][:3]
    S = voronoi_vertices(*cs).solution.points
    world = certify_solutions(*cs, S, method="fast", frame=None)
    scene = certify_solutions(*cs, S, method="fast")
    n_world = sum(k is not None for k, _ in world)
    n_scene = sum(k is not None for k, _ in scene)
    assert n_scene > n_world
    for s, (kind, K), (kw, _) in zip(S, scene, world):
        if kind is None:
            continue
        assert kw in (None, kind)
        for i in range(3):
            lo = K[i].real if kind == "nonreal" else K[i]
            # the numeric point is within 1e-6 (relative) of the enclosure's centre
            assert abs(float(lo.mid()) - s[i].real) <= 1e-6 * (1 + abs(s[i]))
