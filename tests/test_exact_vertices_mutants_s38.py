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
