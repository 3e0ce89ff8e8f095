"""Polygons with nearly flat corners and far, ill-conditioned vertices (thesis §2.2), against
CGAL's Segment_Delaunay_graph_2 and Boost.Polygon (exact peers), and against closed forms.

A polygon whose vertices are points of a large circle rounded to integers turns by a few 10⁻³
at each corner, some corners reflex by the rounding: the first inputs a user draws (a gear's
tip, a road's kerb).  The samples next to such a corner see the corner's point site as a spike
reaching σ / (2 sin(δ/2)) into the other side (σ the sample spacing, δ the turning angle).
Three nearly collinear contacts make a vertex of radius 10³ times the scene, whose contact
system is ill-conditioned."""
from __future__ import annotations

import math
import sys
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest

import curvedvoronoi as cv

sys.path.insert(0, str(Path(__file__).parent))
from test_segment_cgal import compare  # noqa: E402
from test_segment_peers import peers  # noqa: E402,F401  (fixture: builds the peers or skips)


def tooth(radius: int, depth: int, width_angle: float, m: int, a0: float = 0.3):
    """A closed polygon: m + 1 points of the circle of ``radius`` rounded to integers (the tip),
    then radially down by ``depth`` (the flanks and the root)."""
    tip = [(round(radius * math.cos(a0 + width_angle * i / m)), round(radius * math.sin(a0 + width_angle * i / m)))
           for i in range(m + 1)]
    r2 = radius - depth
    root = [(round(r2 * math.cos(a0 + width_angle)), round(r2 * math.sin(a0 + width_angle))),
            (round(r2 * math.cos(a0)), round(r2 * math.sin(a0)))]
    pts = tip + root
    return [(pts[i], pts[(i + 1) % len(pts)]) for i in range(len(pts))]


def _turns(segs):
    out = []
    for (a, b), (_b, c) in zip(segs, segs[1:] + segs[:1]):
        ux, uy, vx, vy = b[0] - a[0], b[1] - a[1], c[0] - b[0], c[1] - b[1]
        out.append(math.atan2(ux * vy - uy * vx, ux * vx + uy * vy))
    return out


# radii and angles without exactly collinear consecutive points (merged into one site here, a
# point site between two segments for the peers: see tests/test_segment_cgal.py)
@pytest.mark.parametrize("radius,m,a0", [(50021, 10, -math.pi / 2 + 0.003), (50007, 10, -math.pi / 2 + 0.003),
                                         (50007, 12, 2.5)])
def test_tooth_with_nearly_flat_tip_equals_cgal_and_boost(peers, radius, m, a0):
    segs = tooth(radius, 4000, 0.0377, m, a0)
    turns = _turns(segs)[:m - 1]
    assert max(abs(t) for t in turns) < 0.02            # nearly flat corners along the tip
    assert min(turns) < 0 < max(turns)                  # convex and reflex ones
    compare([], segs)


def test_tooth_with_straight_joints_has_every_edge_at_its_vertices():
    # the gear tooth of bench/bench_segments.py (radius 50000): two consecutive tip segments are
    # exactly collinear (merged), two corners reflex; a far vertex at 3.4·10⁶ of three nearly
    # parallel sites ends the edge below the tip
    segs = tooth(50000, 4000, 0.0377, 10, -math.pi / 2 + 0.003)
    d = cv.voronoi([cv.Segment(*s) for s in segs], certify=False)
    assert [p for p in d.problems if "not verified" not in p] == []
    assert max(v.radius for v in d.vertices) > 1e6


def test_far_vertex_of_three_nearly_collinear_arcs():
    # equal radii 10, centres (0, 0), (2000, 0), (1000, 1): the circle touching the three from
    # outside is centred at their circumcentre (1000, -499999.5), radius 500000.5 - 10
    from curvedvoronoi.runtime.segments.elementary import decompose
    from curvedvoronoi.runtime.segments.vertices import prove_vertex

    arcs = [cv.Arc.circular(c, 10, 200, 340) for c in [(0, 0), (2000, 0), (1000, 1)]]
    E = decompose(arcs)
    curves = [t for t in range(len(E)) if E.kind[t] != 0]
    sol = prove_vertex(E, tuple(curves), (1000.0 + 0.3, -499999.5 + 2.0))
    assert sol.status == "proved", sol.reason
    x, y, r = sol.box
    for ball, exact in zip((x, y, r), (Fraction(1000), Fraction(-999999, 2), Fraction(1000001, 2) - 10)):
        assert ball.contains(float(exact)) or abs(float(ball.mid()) - float(exact)) <= float(ball.rad()) + 1e-9


def test_arcs_with_a_hull_edge_ending_at_a_far_vertex():
    # 55 of the 1000 random arcs of bench/bench_segments.py (seed 1), near the top of the scene:
    # arcs 127 and 146 and the point 36 (an arc's end) touch a circle of radius 1.08·10⁶, whose
    # contact system is ill-conditioned; another vertex sits on an arc's end normal
    import scenes

    arcs = [a for a in scenes.random_arcs(1000, 1)
            if math.hypot(float(a.c[0]) - 819, float(a.c[1]) - 1300) < 250]
    assert len(arcs) == 55
    d = cv.voronoi(arcs, certify=False)
    assert [p for p in d.problems if "not verified" not in p] == []
    far = [v for v in d.vertices if v.radius > 1e6]
    assert len(far) == 1
    # the far vertex is equidistant from its three sites by the definitions (distance to a
    # point; to an arc: |‖q − c‖ − ρ| where the direction is within the arc, else to its ends)
    v = far[0]
    for t in v.sites:
        s = d.sites[t]
        if isinstance(s, cv.Arc):
            cx, cy = float(s.c[0]), float(s.c[1])
            ang = [math.atan2(float(p[1]) - cy, float(p[0]) - cx) for p in (s.a, s.b)]
            th = math.atan2(v.y - cy, v.x - cx)
            if (th - ang[0]) % (2 * math.pi) <= (ang[1] - ang[0]) % (2 * math.pi):
                dist = abs(math.hypot(v.x - cx, v.y - cy) - float(s.rho))
            else:
                dist = min(math.hypot(v.x - float(p[0]), v.y - float(p[1])) for p in (s.a, s.b))
        else:
            dist = math.hypot(v.x - float(s.x), v.y - float(s.y))
        assert abs(dist - v.radius) < 1e-6 * v.radius


def _dist_to_site(site, P):
    """Distances from the points P (n, 2) to a point or a closed segment, by the definitions."""
    if isinstance(site, cv.Segment):
        a = np.array([float(site.p[0]), float(site.p[1])])
        b = np.array([float(site.q[0]), float(site.q[1])])
        d = b - a
        t = np.clip(((P - a) @ d) / (d @ d), 0.0, 1.0)
        return np.hypot(*(P - (a + t[:, None] * d)).T)
    return np.hypot(P[:, 0] - float(site.x), P[:, 1] - float(site.y))


@pytest.mark.parametrize("radius,m,a0", [(50000, 10, -math.pi / 2 + 0.003), (50021, 10, -math.pi / 2 + 0.003)])
def test_tooth_edges_lie_where_their_sites_are_nearest(radius, m, a0):
    # every polyline point, infinite ends included (drawn far out along the ray), is equidistant
    # from the edge's two sites and no other site is nearer; the ray of points 1 and 3 below the
    # tip of radius 50021 leaves a vertex at 6.7·10⁶ downwards, not back through the tooth
    segs = tooth(radius, 4000, 0.0377, m, a0)
    d = cv.voronoi([cv.Segment(*s) for s in segs], certify=False)
    for e in d.edges:
        P = e.polyline
        D = np.column_stack([_dist_to_site(s, P) for s in d.sites])
        i, j = e.sites
        own = np.maximum(D[:, i], D[:, j])
        scale = 1e-9 * (1 + np.abs(P).max(axis=1) + own)
        assert np.all(np.abs(D[:, i] - D[:, j]) <= 1e-6 * (1 + own)), e
        others = np.delete(D, [i, j], axis=1).min(axis=1)
        assert np.all(others >= own - 1e-6 * (1 + own) - scale), (e.sites, e.ends)


@pytest.mark.parametrize("radius,m,a0", [(50000, 10, -math.pi / 2 + 0.003), (50021, 10, -math.pi / 2 + 0.003),
                                         (50007, 12, 2.5)])
def test_tooth_diagrams_are_certified(radius, m, a0):
    # the edges of nearly parallel tip segments run 10⁶ to far vertices with a clearance growing
    # by 10⁻⁵ per unit: the certificate covers them by convexity (two tangents), not by pieces
    segs = tooth(radius, 4000, 0.0377, m, a0)
    d = cv.voronoi([cv.Segment(*s) for s in segs])
    assert d.certified, d.problems[:3]
    assert cv.verify(d).ok
