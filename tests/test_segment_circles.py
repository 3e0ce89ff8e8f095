"""Whole circles among segments, arcs and points: each circle of rational radius is its two half
arcs (runtime.sites.arc.circle_halves), one source.

References are independent of the package: distances from the definitions in numpy (a circle:
| |p − c| − r |; a segment: the clamped projection; a point: hypot), the Apollonius-graph
construction of ``cv.voronoi`` on the same circles and points (a different algorithm and code path,
itself compared with CGAL in tests/test_cgal.py), and the closed-form medial axis of an annulus.
"""
from __future__ import annotations

import math
import random

import numpy as np
import pytest

import curvedvoronoi as cv
from curvedvoronoi.runtime.segments.construction import segment_voronoi
from curvedvoronoi.runtime.sites.arc import Arc, circle_halves
from curvedvoronoi.runtime.voronoi.site_input import SiteError


def _seg_dist(P, a, b):
    a, b = np.asarray(a, float), np.asarray(b, float)
    d = b - a
    t = np.clip(((P - a) @ d) / (d @ d), 0.0, 1.0)
    return np.hypot(*(P - (a + t[:, None] * d)).T)


def _distances(P, scene):
    """Distances from the points P (m × 2) to each input site of ``scene`` (m × n)."""
    cols = []
    for kind, data in scene:
        if kind == "circle":
            (cx, cy), r = data
            cols.append(np.abs(np.hypot(P[:, 0] - cx, P[:, 1] - cy) - r))
        elif kind == "segment":
            cols.append(_seg_dist(P, *data))
        else:
            cols.append(np.hypot(P[:, 0] - data[0], P[:, 1] - data[1]))
    return np.column_stack(cols)


def _scene(seed: int, n_circles: int, n_segments: int, n_points: int, side: int = 60):
    """Disjoint integer circles, segments and points with a clearance of 1 between any two."""
    rng = random.Random(seed)
    scene: list = []
    while len(scene) < n_circles + n_segments + n_points:
        k = len(scene)
        if k < n_circles:
            item = ("circle", ((rng.randint(0, side), rng.randint(0, side)), rng.randint(1, 5)))
        elif k < n_circles + n_segments:
            a = (rng.randint(0, side), rng.randint(0, side))
            b = (a[0] + rng.randint(-12, 12), a[1] + rng.randint(-12, 12))
            if a == b:
                continue
            item = ("segment", (a, b))
        else:
            item = ("point", (rng.randint(0, side), rng.randint(0, side)))
        if all(_clearance(item, other) >= 1 for other in scene):
            scene.append(item)
    return scene


def _clearance(u, v) -> float:
    """A lower bound of the distance between two scene items, by dense sampling of u's outline
    (exact enough at the clearance 1 asked of integer data)."""
    if u[0] == "circle" and v[0] == "circle":
        (c1, r1), (c2, r2) = u[1], v[1]
        return math.dist(c1, c2) - r1 - r2
    if v[0] == "circle":
        u, v = v, u
    if u[0] == "circle":
        (c, r) = u[1]
        P = np.array([v[1]], float) if v[0] == "point" else \
            np.array(v[1][0], float) + np.linspace(0, 1, 400)[:, None] * (np.subtract(v[1][1], v[1][0]))
        return float(np.min(np.hypot(P[:, 0] - c[0], P[:, 1] - c[1]))) - r - 0.05 if v[0] != "point" else \
            math.dist(v[1], c) - r
    if u[0] == "point" and v[0] == "point":
        return math.dist(u[1], v[1])
    if u[0] == "point":
        u, v = v, u
    P = np.array(u[1][0], float) + np.linspace(0, 1, 400)[:, None] * np.subtract(u[1][1], u[1][0])
    if v[0] == "point":
        return float(np.min(np.hypot(P[:, 0] - v[1][0], P[:, 1] - v[1][1]))) - 0.05
    return float(np.min(_seg_dist(P, *v[1]))) - 0.05


def _sites(scene):
    out = []
    for kind, data in scene:
        if kind == "circle":
            out.append(cv.Circle.from_radius(data[0][0], data[0][1], data[1]))
        elif kind == "segment":
            out.append(cv.Segment(*data))
        else:
            out.append(data)
    return out


def test_circle_halves_are_the_circle():
    (upper, lower) = circle_halves((1, 2), 9)
    assert upper == Arc((1, 2), 3, (4, 2), (-2, 2)) and lower == Arc((1, 2), 3, (-2, 2), (4, 2))
    with pytest.raises(ValueError, match=r"radius √2 is not rational"):
        circle_halves((0, 0), 2)


@pytest.mark.parametrize("seed", [1, 2])
def test_every_edge_point_is_equidistant_from_its_two_input_sites_and_nearest(seed):
    scene = _scene(seed, 8, 8, 4)
    d = cv.voronoi(_sites(scene))
    assert d.certified, d.problems[:3]
    assert sorted(set(d.sources)) == list(range(len(scene)))
    checked = 0
    for e in d.edges:
        a, b = d.sources[e.sites[0]], d.sources[e.sites[1]]
        if a == b:                  # the two halves of a circle, or a segment and its end
            continue
        P = np.asarray(e.polyline, float)
        P = P[np.all(np.abs(P) < 1e3, axis=1)]          # the far points of unbounded edges
        D = _distances(P, scene)
        tol = 2 * e.tolerance + 1e-9 * (1 + np.abs(P).max())
        assert np.all(np.abs(D[:, a] - D[:, b]) <= tol), (a, b)
        assert np.all(np.minimum(D[:, a], D[:, b]) <= D.min(axis=1) + tol), (a, b)
        checked += len(P)
    assert checked > 100


@pytest.mark.parametrize("seed", [3, 4])
def test_circles_and_points_give_the_apollonius_graph(seed):
    scene = _scene(seed, 12, 0, 6)
    sites = _sites(scene)
    d = segment_voronoi(sites)
    assert d.certified, d.problems[:3]
    pairs = {tuple(sorted((d.sources[e.sites[0]], d.sources[e.sites[1]]))) for e in d.edges}
    pairs = {p for p in pairs if p[0] != p[1]}
    reference = cv.voronoi(sites)                  # the Apollonius construction: sites are the input
    assert reference.certified
    assert pairs == set(reference.delaunay_edges())


def test_the_medial_axis_of_an_annulus_is_the_middle_circle():
    R, r = 5, 1
    m = cv.medial_axis(cv.Circle.from_radius(0, 0, R), [cv.Circle.from_radius(0, 0, r)])
    assert m.certified and len(m.edges) >= 2
    for e in m.edges:
        P = np.asarray(e.polyline, float)
        assert np.allclose(np.hypot(P[:, 0], P[:, 1]), (R + r) / 2, atol=1e-6)
        assert np.allclose(e.radius, (R - r) / 2, atol=1e-6)
    # the whole middle circle is covered: the angles of the edges' points leave no gap over 10°
    ang = np.sort(np.concatenate([np.arctan2(*np.asarray(e.polyline, float)[:, ::-1].T) for e in m.edges]))
    assert np.max(np.diff(np.concatenate([ang, [ang[0] + 2 * np.pi]]))) < math.radians(10)


def test_an_off_centre_hole_against_dense_sampling():
    """Points of the medial axis of a disc with an off-centre circular hole are equidistant from
    the two circles, at the reported radius (definition, numpy)."""
    m = cv.medial_axis(cv.Circle.from_radius(0, 0, 10), [cv.Circle.from_radius(3, 1, 2)])
    assert m.certified and m.edges
    for e in m.edges:
        P = np.asarray(e.polyline, float)
        d_out = 10 - np.hypot(P[:, 0], P[:, 1])
        d_in = np.hypot(P[:, 0] - 3, P[:, 1] - 1) - 2
        assert np.allclose(d_out, d_in, atol=2 * e.tolerance + 1e-9)
        assert np.allclose(e.radius, d_out, atol=2 * e.tolerance + 1e-9)


def test_bad_circles_among_segments_are_named_by_input_index():
    with pytest.raises(SiteError, match=r"^site 1 and site 2: .*cross"):
        cv.voronoi([(20, 20), cv.Segment((0, 0), (10, 0)), (5, 1, 2)])
    with pytest.raises(SiteError, match=r"^site 0 and site 1: .*touch at \(2, 0\) \(tangent\)"):
        cv.voronoi([cv.Segment((0, 0), (4, 0)), (2, 2, 2)])
    with pytest.raises(ValueError, match=r"^site 1: the radius √2 is not rational"):
        cv.voronoi([cv.Segment((0, 0), (4, 0)), cv.Circle(9, 9, 2)])
    with pytest.raises(SiteError, match=r"conics other than circles"):
        cv.voronoi([cv.Segment((0, 0), (4, 0)), cv.Conic.ellipse(centre=(9, 9), axes=(2, 1))])


def test_a_dxf_circle_is_one_source_of_two_half_arcs(tmp_path):
    ezdxf = pytest.importorskip("ezdxf")
    doc = ezdxf.new()
    msp = doc.modelspace()
    msp.add_line((0, 0), (10, 0), dxfattribs={"layer": "walls"})
    msp.add_circle((5, 4), 1.5, dxfattribs={"layer": "holes"})
    path = str(tmp_path / "c.dxf")
    doc.saveas(path)
    pieces, sources, labels = cv.read_dxf(path)
    assert pieces[1:] == circle_halves((5, 4), 2.25) and sources == [0, 1, 1] and labels == ["walls", "holes", "holes"]
    d = cv.voronoi(pieces)
    assert d.certified
