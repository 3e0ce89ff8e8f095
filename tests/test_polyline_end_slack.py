"""An edge's polyline is drawn from its end vertices' reported positions.  The verifier accepts a
reported vertex within tol + 2h of the centre it proves (h: the half-width of the proof box,
:func:`runtime.voronoi.verify.vertices.prove_vertices`), so the end check of every edge route
(:func:`runtime.voronoi.verify.curved_edges.ends_at_vertices`) must accept a polyline starting
there too: a far vertex proved in a coarse box (2·10⁵ tiled circles, a vertex at x ≈ −2.9·10⁵)
was accepted and its three edges refused.  Checked here as the identity "reported vertex
accepted ⇒ polyline from it accepted" on random vertices, and the end check still refusing a
polyline that starts beyond the slack."""
from __future__ import annotations

import math
from types import SimpleNamespace

from hypothesis import given, settings, strategies as st

from curvedvoronoi.runtime.voronoi.verify import vertices
from curvedvoronoi.runtime.voronoi.verify.curved_edges import ends_at_vertices

_scale = st.floats(1.0, 1e6)
_unit = st.floats(0.0, 1.0)


def _vertex(scale, fx, fy, fr, fh):
    x, y, r = scale * (2 * fx - 1), scale * (2 * fy - 1), scale * fr
    info = vertices.VertexInfo(7, (0, 1, 2), x, y, r)
    info.h = fh * 100 * info.tol          # boxes up to 100 tolerances wide (coarse proofs)
    return info


def _moved(info, dist, angle):
    return info.x + dist * math.cos(angle), info.y + dist * math.sin(angle)


@settings(max_examples=300, deadline=None)
@given(_scale, _unit, _unit, _unit, _unit, st.floats(0.0, 0.999), st.floats(0.0, 2 * math.pi))
def test_a_polyline_from_an_accepted_reported_vertex_passes_the_end_check(scale, fx, fy, fr, fh, s, angle):
    info = _vertex(scale, fx, fy, fr, fh)
    x, y = _moved(info, s * (info.tol + 2 * info.h), angle)
    v = SimpleNamespace(id=7, sites=(0, 1, 2), x=x, y=y, radius=info.r)
    problems = []
    assert vertices._matches_report(v, info, (0.0, 0.0), {}, problems), problems
    P = [(x, y), (x + scale, y)]
    assert ends_at_vertices("edge 3", P, (info, None), 1.0 + scale, problems), problems
    assert ends_at_vertices("edge 3", P[::-1], (None, info), 1.0 + scale, problems), problems


@settings(max_examples=200, deadline=None)
@given(_scale, _unit, _unit, _unit, _unit, st.floats(1.01, 100.0), st.floats(0.0, 2 * math.pi))
def test_a_polyline_starting_beyond_the_slack_is_refused(scale, fx, fy, fr, fh, s, angle):
    info = _vertex(scale, fx, fy, fr, fh)
    x, y = _moved(info, s * (info.tol + 2 * info.h) + 2e-12 * (1 + scale), angle)
    problems = []
    assert not ends_at_vertices("edge 3", [(x, y), (x + scale, y)], (info, None), 1.0 + scale, problems)
    assert "polyline starts at" in problems[0] and "not at vertex 7" in problems[0]
