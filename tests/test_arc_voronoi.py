"""Voronoi diagrams and medial axes with circular arcs (thesis §2.2–2.3): closed forms.

References are the definitions written here (distance to a circle |‖q − c‖ − ρ|, to a segment),
never the library's distance code."""
from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

import curvedvoronoi as cv

sys.path.insert(0, str(Path(__file__).parent))

A, S = cv.Arc, cv.Segment


def clean(d):
    return [p for p in d.problems if "not verified" not in p]


def test_lone_quarter_arc_has_its_centre_as_vertex():
    d = cv.voronoi([A.circular((0, 0), 2, 0, 90)], certify=False)
    assert not clean(d)
    assert [(v.x, v.y, v.radius, v.degree) for v in d.vertices] == [(0.0, 0.0, 2.0, 3)]
    # the radial rays through the ends and the bisector of the ends (towards the third quadrant)
    dirs = sorted(tuple(np.round(e.polyline[-1] / np.hypot(*e.polyline[-1]), 9)) for e in d.edges)
    assert dirs == sorted([(0.0, 1.0), (1.0, 0.0), (round(-math.sqrt(0.5), 9), round(-math.sqrt(0.5), 9))])


def test_point_inside_an_arc_gives_an_ellipse_arc():
    # a point p inside the circle (c, ρ): |v - p| = ρ - |v - c|, an ellipse with foci p and c
    d = cv.voronoi([A.circular((0, 0), 2, 0, 180), (0, "1/2")], certify=False)
    assert not clean(d)
    e = [e for e in d.edges if len(e.polyline) > 2]
    assert len(e) == 1
    P = e[0].polyline
    resid = np.hypot(P[:, 0], P[:, 1] - 0.5) + np.hypot(P[:, 0], P[:, 1]) - 2
    assert np.max(np.abs(resid)) < 1e-12
    # its ends: on the x-axis (the radial lines of the arc's ends), |x| = 15/16
    assert sorted(round(abs(d.vertices[v].x), 12) for v in e[0].ends) == [0.9375, 0.9375]


def test_point_outside_an_arc_gives_a_hyperbola_branch():
    d = cv.voronoi([A.circular((0, 0), 2, 0, 90), (3, 3)], certify=False)
    assert not clean(d)
    e = [e for e in d.edges if len(e.polyline) > 2][0]
    P = e.polyline
    assert np.max(np.abs(np.hypot(P[:, 0] - 3, P[:, 1] - 3) - (np.hypot(P[:, 0], P[:, 1]) - 2))) < 1e-12


def stadium():
    return [S((0, 0), (4, 0)), A((4, 1), 1, (4, 0), (4, 2)), S((4, 2), (0, 2)), A((0, 1), 1, (0, 2), (0, 0))]


def test_stadium_medial_axis_is_the_segment_between_the_centres():
    m = cv.medial_axis(stadium(), certify=False)
    assert not clean(m.diagram)
    assert len(m.edges) == 1
    P = m.edges[0].polyline
    assert sorted(map(tuple, P[[0, -1]].round(12))) == [(0.0, 1.0), (4.0, 1.0)]
    assert np.allclose(m.edges[0].radius, 1.0)
    assert len(m.diagram.sites) == 4        # tangent joints are not sites


def test_rounded_rectangle_medial_axis():
    r = [S((1, 0), (5, 0)), A((5, 1), 1, (5, 0), (6, 1)), S((6, 1), (6, 3)), A((5, 3), 1, (6, 3), (5, 4)),
         S((5, 4), (1, 4)), A((1, 3), 1, (1, 4), (0, 3)), S((0, 3), (0, 1)), A((1, 1), 1, (0, 1), (1, 0))]
    m = cv.medial_axis(r, certify=False)
    assert not clean(m.diagram)
    got = sorted((round(v.x, 9), round(v.y, 9), round(v.radius, 9)) for v in m.vertices)
    # the 6 x 4 rectangle's axis, its diagonal branches ending at the fillets' centres
    assert got == [(1, 1, 1), (1, 3, 1), (2, 2, 2), (4, 2, 2), (5, 1, 1), (5, 3, 1)]
    assert m.largest_inscribed_circle == (2.0, 2.0, 2.0)


def test_annulus_medial_axis_is_the_middle_circle():
    outer = [A((0, 0), 3, (3, 0), (-3, 0)), A((0, 0), 3, (-3, 0), (3, 0))]
    inner = [A((0, 0), 1, (1, 0), (-1, 0)), A((0, 0), 1, (-1, 0), (1, 0))]
    m = cv.medial_axis(outer, [inner], certify=False)
    assert not clean(m.diagram)
    P = np.vstack([e.polyline for e in m.edges])
    assert np.max(np.abs(np.hypot(P[:, 0], P[:, 1]) - 2)) < 1e-12
    assert all(np.allclose(e.radius, 1.0) for e in m.edges)
    # the joints at (±3, 0) and (±1, 0) make degree-4 vertices at (±2, 0), decided exactly
    assert sorted((v.x, v.y, v.degree) for v in m.vertices) == [(-2.0, 0.0, 4), (2.0, 0.0, 4)]


def test_square_with_a_circular_hole_against_the_definition():
    hole = [A((5, 5), 2, (7, 5), (3, 5)), A((5, 5), 2, (3, 5), (7, 5))]
    m = cv.medial_axis([(0, 0), (10, 0), (10, 10), (0, 10)], [hole], certify=False)
    assert not clean(m.diagram)

    def boundary_distance(q):
        x, y = q
        walls = min(x, 10 - x, y, 10 - y)
        return min(walls, math.hypot(x - 5, y - 5) - 2)

    for e in m.edges:
        for q, r in zip(e.polyline[1:-1], e.radius[1:-1]):
            assert abs(boundary_distance(q) - r) <= e.tolerance + 1e-9
    # 4 diagonal branches to the corners; around the hole 6 edges: one per wall, the side walls'
    # split where the normal lines of the joints (3, 5) and (7, 5) meet them
    assert len(m.edges) == 10


def test_arc_sites_in_json_and_picture(tmp_path):
    d = cv.voronoi(stadium(), certify=False)
    doc = d.to_json()
    assert any("arc" in s for s in doc["sites"])
    d.plot(tmp_path / "stadium.png")
    assert (tmp_path / "stadium.png").stat().st_size > 1000


@pytest.mark.parametrize("bad", [
    lambda: A((0, 0), 2, (2, 0), (1, 1)),            # end not on the circle
    lambda: A.circular((0, 0), -1, 0, 90),           # negative radius
])
def test_bad_arcs_are_refused(bad):
    with pytest.raises(cv.InvalidConicError):
        bad()


def test_nearest_site_with_arcs_against_the_definition():
    d = cv.voronoi(stadium(), certify=False)
    rng = np.random.default_rng(5)
    Q = rng.uniform([-2, -1], [6, 3], size=(300, 2))

    def dist(site, q):
        if isinstance(site, S):
            (ax, ay), (bx, by) = site.float_endpoints()
            t = max(0.0, min(1.0, ((q[0] - ax) * (bx - ax) + (q[1] - ay) * (by - ay)) / ((bx - ax) ** 2 + (by - ay) ** 2)))
            return math.hypot(q[0] - ax - t * (bx - ax), q[1] - ay - t * (by - ay))
        (cx, cy), rho, (ax, ay), (bx, by) = site.float_data()
        a0 = math.atan2(ay - cy, ax - cx)
        span = (math.atan2(by - cy, bx - cx) - a0) % (2 * math.pi)
        if (math.atan2(q[1] - cy, q[0] - cx) - a0) % (2 * math.pi) <= span:
            return abs(math.hypot(q[0] - cx, q[1] - cy) - rho)
        return min(math.hypot(q[0] - ax, q[1] - ay), math.hypot(q[0] - bx, q[1] - by))

    res = d.nearest(Q)
    for q, i, dd, ok in zip(Q, res.index, res.distance, res.proved):
        ref = [dist(s, q) for s in d.sites]
        if ok:
            assert int(np.argmin(ref)) == i and abs(min(ref) - dd) < 1e-12
        else:       # reported as a tie: two sites within rounding of each other
            assert sorted(ref)[1] - min(ref) < 1e-9


def _arc_distance(site, P):
    """Distances from the points P (n, 2) to a closed arc or a point, by the definitions: to the
    circle where the direction from the centre is within the counter-clockwise range, else to
    the nearer end."""
    if isinstance(site, cv.Arc):
        cx, cy = float(site.c[0]), float(site.c[1])
        a0 = math.atan2(float(site.a[1]) - cy, float(site.a[0]) - cx)
        a1 = math.atan2(float(site.b[1]) - cy, float(site.b[0]) - cx)
        th = np.arctan2(P[:, 1] - cy, P[:, 0] - cx)
        inside = (th - a0) % (2 * math.pi) <= (a1 - a0) % (2 * math.pi)
        dc = np.abs(np.hypot(P[:, 0] - cx, P[:, 1] - cy) - float(site.rho))
        de = np.minimum(np.hypot(P[:, 0] - float(site.a[0]), P[:, 1] - float(site.a[1])),
                        np.hypot(P[:, 0] - float(site.b[0]), P[:, 1] - float(site.b[1])))
        return np.where(inside, dc, de)
    return np.hypot(P[:, 0] - float(site.x), P[:, 1] - float(site.y))


@pytest.mark.parametrize("seed", [1, 3])
def test_random_arcs_edges_where_their_sites_are_nearest(seed):
    # 100 random arcs (tests/scenes.py): every polyline point, far ends of infinite edges
    # included, is no nearer to a third site than to the edge's two sites.  Seed 3 had a hull
    # tangent a hair from an arc's end, drawn as an infinite edge of the end point instead
    import scenes

    d = cv.voronoi(scenes.random_arcs(100, seed))
    assert d.certified, d.problems[:3]
    for e in d.edges:
        P = e.polyline
        D = np.column_stack([_arc_distance(s, P) for s in d.sites])
        i, j = e.sites
        own = np.maximum(D[:, i], D[:, j])
        others = np.delete(D, [i, j], axis=1).min(axis=1)
        assert np.all(others >= own - 1e-6 * (1 + own)), e
