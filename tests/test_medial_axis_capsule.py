"""The medial axis of a capsule: the rectangle [−4, 4] × [−2, 2] closed by two elliptic half
caps (x ∓ 4)² + y²/4 = 1, |x| >= 4, joined tangentially to the segments y = ±2.

Closed form (derived independently of the construction): from (x, 0) the distance to the lines
y = ±2 is 2; the squared distance to the right cap at (4 + cos t, 2 sin t), cos t >= 0, is
−3cos²t − 2p·cos t + p² + 4 with p = x − 4, concave in cos t, so its minimum is at cos t ∈ {0, 1}:
the tip (5, 0) at distance 5 − x or the joints (4, ±2).  Hence the segment of the x-axis between
the vertices (±3, 0) (radius 2, touching (±3, ±2) and the tip) is medial with constant radius 2,
and the branches towards the caps end at the centres of curvature (±4, ±3/2) of the joints
(radius of curvature a²/b = 1/2).  A construction that cannot find this must say so."""
from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

import curvedvoronoi as cv


def capsule():
    right = cv.Arc.elliptic((4, 0), (0, 2), Fraction(1, 2), math.pi, 2 * math.pi)
    left = cv.Arc.elliptic((-4, 0), (0, 2), Fraction(1, 2), 0, math.pi)
    assert (right.a, right.b, left.a, left.b) == ((4, -2), (4, 2), (-4, 2), (-4, -2))
    return [right, cv.Segment(right.b, left.a), left, cv.Segment(left.b, right.a)]


def boundary_distance(P):
    """Distance to the capsule's boundary by dense sampling (independent of the library)."""
    t = np.linspace(-math.pi / 2, math.pi / 2, 20001)
    caps = np.vstack([np.column_stack([4 + np.cos(t), 2 * np.sin(t)]),
                      np.column_stack([-4 - np.cos(t), 2 * np.sin(t)])])
    d_cap = np.sqrt(((P[:, None, :] - caps[None, :, :]) ** 2).sum(axis=2)).min(axis=1)
    dx = np.maximum(np.abs(P[:, 0]) - 4, 0)
    d_seg = np.minimum(np.hypot(dx, P[:, 1] - 2), np.hypot(dx, P[:, 1] + 2))
    return np.minimum(d_cap, d_seg)


def test_capsule_medial_axis_is_right_or_reported():
    m = cv.medial_axis(capsule())
    if not m.edges or not any(abs(v.radius - 2) < 1e-9 for v in m.vertices):
        # a failed construction: it must say so, never return an empty axis silently
        assert m.certified is False and m.problems
        if not m.edges and not m.vertices:           # the medial axis of a bounded domain is never empty
            assert any(p.startswith("medial axis:") and "incomplete" in p for p in m.problems), m.problems
        return
    assert m.certified is False                      # elliptic parts are not certified
    tops = sorted((round(v.x, 9), round(v.y, 9)) for v in m.vertices if abs(v.radius - 2) < 1e-9)
    assert tops == [(-3.0, 0.0), (3.0, 0.0)]
    axis = [e for e in m.edges if np.abs(e.polyline[:, 1]).max() < 1e-9]
    xs = np.concatenate([e.polyline[:, 0] for e in axis])
    assert abs(xs.min() + 3) < 1e-9 and abs(xs.max() - 3) < 1e-9
    assert all(np.allclose(e.radius, 2, atol=1e-9) for e in axis)
    ends = {(round(float(p[0]), 6), round(float(p[1]), 6)) for e in m.edges for p in (e.polyline[0], e.polyline[-1])}
    assert {(4.0, 1.5), (4.0, -1.5), (-4.0, 1.5), (-4.0, -1.5)} <= ends
    for e in m.edges:
        assert np.allclose(e.radius, boundary_distance(np.asarray(e.polyline, float)), atol=1e-6)
    assert abs(m.largest_inscribed_circle[2] - 2) < 1e-9


def test_an_empty_diagram_of_the_capsule_is_reported():
    """Two or more sites always have a Voronoi edge: an edgeless diagram carries a problem."""
    D = cv.voronoi(capsule())
    assert D.edges or (D.certified is False and any("no Voronoi edge" in p for p in D.problems))
