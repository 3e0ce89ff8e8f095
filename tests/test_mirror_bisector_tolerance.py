"""An edge's stated tolerance at its float resolution (runtime/voronoi/verify/curved_edges.py):
a polyline point farther from the bisector than the tolerance is refused, up to the verifier's
relative allowance of 1e-9 for the rounding of the float data (the same allowance as for the
proved Hausdorff bound of the whole polyline, runtime/voronoi/verify/edge_checks.py).

Reference (closed form, none of the library's geometry): the ellipses X²/4 + Y² = 1 centred at
(∓5, 0) are mirror images in the line x = 0, which is therefore their bisector; a point (δ, 0)
lies on the common major axis, where the nearest points of both ellipses are their major
vertices (±3, 0) and (∓3, 0), so d_0 − d_1 = (2 + δ) − (2 − δ) = 2δ and its distance from the
bisector is δ exactly."""
from __future__ import annotations

import copy

import pytest

import curvedvoronoi as cv


@pytest.fixture(scope="module")
def mirror_pair():
    d = cv.voronoi([cv.Conic.ellipse(centre=(-5, 0), axes=(2, 1)), cv.Conic.ellipse(centre=(5, 0), axes=(2, 1))])
    assert d.certified and len(d.edges) == 1
    return d.to_json()


def _with_point_on_the_axis(doc, tol, delta):
    D = copy.deepcopy(doc)
    e = D["edges"][0]
    assert sorted(e["sites"]) == [0, 1] and e["ends"] == [None, None]
    e["tolerance"] = tol
    P = e["polyline"]
    k = next(t for t, p in enumerate(P) if p[1] > 0)
    assert P[k - 1][1] < 0               # the polyline crosses the axis between k − 1 and k
    P.insert(k, [delta, 0.0])
    return D


@pytest.mark.parametrize("tol, rel, ok", [(1.0, 0.0, True), (1.0, 5e-10, True), (0.5, 5e-10, True),
                                          (1.0, -0.1, True), (1.0, 2e-9, False), (0.5, 3e-9, False)])
def test_a_polyline_point_at_the_tolerance_up_to_its_rounding_allowance_is_accepted(mirror_pair, tol, rel, ok):
    """The point at distance δ = tol·(1 + rel) from the bisector: within the allowance
    (rel ≤ 5·10⁻¹⁰ < 10⁻⁹) the edge is proved, beyond it (rel ≥ 2·10⁻⁹) the point is named."""
    delta = tol * (1 + rel)
    cert = cv.verify(_with_point_on_the_axis(mirror_pair, tol, delta))
    assert cert.ok is ok, cert.problems
    if not ok:
        assert any("from the bisector" in p and "polyline point" in p for p in cert.problems)
