"""A degree-4 vertex on a mirror line, moved along the mirror just beyond the verifier's largest
intermediate-value segment (runtime/voronoi/verify/exact_vertices.py, ``mirror_vertex``).

Two mirror pairs of ellipses about x = 18 (orbits {a, a'}, {b, b'}): every point of the line is
equidistant from a and a' and from b and b', so the vertex is the zero of g(t) = d_a − d_b along
the line (Anton's thesis, §3.1.3: a vertex of k > 3 sites is proved by equidistance and
emptiness).  The distances are 1-Lipschitz, so |g'| ≤ 2; here the foot directions give
|g'| ≈ 1.1 at the vertex (d_a's normal from the ellipse at (12, 0) has y-component ≈ 0.51, d_b's
from (12, 8) ≈ −0.6).  Moving the reported point by m = 1.2·δ (δ = 10⁻⁸·scale, the widest segment
half-length tried) puts the true zero about m away, beyond δ plus rounding, so g has one sign on
the whole segment [X − δu, X + δu]: no intermediate-value proof exists and the vertex must be
refused — whichever way it is moved.  Yet |g(X)| ≈ 1.3·δ < 2δ, so the overlap of the sites'
distance intervals (widened by δ each) alone does not refuse it: the sign change is the only
thing that does.  The tolerance of a reported vertex is VERTEX_TOL·scale = 10⁻¹⁰·scale, a
hundredth of m, so the moved point is not the vertex by the verifier's own contract either.
"""
from __future__ import annotations

import copy

import pytest

import curvedvoronoi as cv


def _ellipse(x, y, a, b):
    return cv.Conic.ellipse(centre=(x, y), axes=(a, b))


@pytest.fixture(scope="module")
def mirror_doc():
    d = cv.voronoi([_ellipse(12, 0, 2, 1), _ellipse(24, 0, 2, 1), _ellipse(12, 8, 3, 1), _ellipse(24, 8, 3, 1),
                    _ellipse(18, 20, 2, 1)])
    assert d.certified, d.problems
    return d.to_json()


@pytest.mark.parametrize("sign", [1, -1])
def test_a_mirror_vertex_just_beyond_the_widest_segment_is_refused(mirror_doc, sign):
    doc = copy.deepcopy(mirror_doc)
    v = next(x for x in doc["vertices"] if len(x["sites"]) == 4)
    assert v["x"] == 18.0                    # on the mirror line x = 18
    scale = 1 + abs(v["x"]) + abs(v["y"]) + abs(v["radius"])
    m = sign * 1.2e-8 * scale
    v["y"] += m
    for e in doc["edges"]:
        for t, end in enumerate(e["ends"]):
            if end == v["id"]:
                e["polyline"][0 if t == 0 else -1][1] += m
    cert = cv.verify(doc)
    assert not cert.ok
    assert any(p.startswith(f"vertex {v['id']} ") for p in cert.problems), cert.problems


def _distance_to_ellipse(px, py, cx, cy, a, b):
    """d((px, py), ellipse of centre (cx, cy), axes a, b along x, y) in 40-digit mpmath: the
    nearest point (cx + a cos t, cy + b sin t) where the derivative of the squared distance vanishes
    (the start is the direction to the point, which is near the foot for these slim ellipses)."""
    import mpmath

    with mpmath.workdps(40):
        X, Y = mpmath.mpf(px) - cx, mpmath.mpf(py) - cy
        f = lambda t: (X - a * mpmath.cos(t)) ** 2 + (Y - b * mpmath.sin(t)) ** 2      # noqa: E731
        df = lambda t: 2 * (X - a * mpmath.cos(t)) * a * mpmath.sin(t) - 2 * (Y - b * mpmath.sin(t)) * b * mpmath.cos(t)  # noqa: E731
        t = mpmath.findroot(df, mpmath.atan2(Y / b, X / a))
        return mpmath.sqrt(f(t))


def test_the_mirror_vertex_enclosure_holds_the_true_vertex():
    """The reported point X = (18, y* + m) with m = 1.2·δ₁ on the side where g = d_a − d_b > 0
    (δ₁ = 10⁻¹²·scale, the first segment tried): g keeps one sign on [X − δ₁u, X + δ₁u], so the
    proved point may only be claimed within the half-length of a segment on which g changes sign
    (δ₂ = 10⁻¹⁰·scale).  The true zero y* of g on x = 18 is found here in mpmath; the returned
    enclosure radius h must cover |X − y*| = m."""
    import mpmath
    import numpy as np

    from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
    from curvedvoronoi.runtime.voronoi.verify.exact_vertices import symmetric_vertex
    from curvedvoronoi.runtime.voronoi.verify.vertices import VertexInfo

    sites = [_ellipse(12, 0, 2, 1), _ellipse(24, 0, 2, 1), _ellipse(12, 8, 3, 1), _ellipse(24, 8, 3, 1)]
    geoms = [site_geometry(s) for s in sites]
    with mpmath.workdps(40):
        g = lambda y: _distance_to_ellipse(18, y, 12, 0, 2, 1) - _distance_to_ellipse(18, y, 12, 8, 3, 1)  # noqa: E731
        ystar = mpmath.findroot(g, mpmath.mpf("3.529205991704463"))
        radius = float(_distance_to_ellipse(18, ystar, 12, 0, 2, 1))
        slope = (g(ystar + mpmath.mpf(10) ** -8) - g(ystar - mpmath.mpf(10) ** -8)) / (2 * mpmath.mpf(10) ** -8)
    assert slope > 1                         # g increases upwards: X above y* has g(X) > 0
    scale = 1 + 18 + float(ystar) + radius
    m = 1.2e-12 * scale
    y = float(ystar + m)
    assert abs(y - float(ystar)) > 1.1e-12 * scale
    order = (0, 1, 3, 2)                     # counter-clockwise about the vertex, as the diagram lists them
    v = type("V", (), {"id": 1, "sites": order, "x": 18.0, "y": y, "radius": radius})()
    problems: list = []
    info = symmetric_vertex(v, order, geoms, problems, VertexInfo)
    assert info is not None, problems
    assert float(abs(mpmath.mpf(info.y) - ystar)) <= info.h and abs(info.x - 18.0) <= info.h
    # the proved radius interval [2r − r_hi, r_hi] holds the true common distance
    assert 2 * info.r - info.r_hi <= radius <= info.r_hi
