"""Three arcs of the random 10⁴-arc scene (tests/scenes.py random_arcs(10000, 1), inputs 3847,
1981, 8297) whose diagram has a vertex at radius about 9.8·10⁷.

The arcs 1981 and 8297 both reach x = 2 (their leftmost points (2, 3660) and (2, 1821) lie in
their ranges), so the convex hull of the sites has the side x = 2 between them; the end
(≈ 2.0037, 2379.2) of arc 3847 lies 0.0037 inside that side.  Its region is therefore bounded,
closed far to the left by a vertex of that end and the two arcs at about (−9.78·10⁷, 2740.5).
Samples of the arcs lie a sagitta inside the hull (the end was a corner of the samples' hull: the
sample diagram gave it two infinite edges), and the far vertex's 3 × 3 contact system is
singular to float precision (its rows agree to 10⁻¹¹), so before the fix the construction left
the end with infinite edges (three arcs) or a vertex without one of its edges (the 10⁴ scene).

Checked against tests/arc_reference.py (mpmath distances from the definitions, no runtime code):
the far vertex solved by mpmath's root finder on d_end = d_a = d_b, every other site farther
there, and the infinite edge of the two arcs leaving it to the left along their bisector.
"""
from __future__ import annotations

import sys
from fractions import Fraction
from pathlib import Path

import mpmath
import numpy as np
import pytest

import curvedvoronoi as cv

sys.path.insert(0, str(Path(__file__).parent))
from arc_reference import distance, mp, nearest_margin, site_data  # noqa: E402

#: (centre, radius, start degrees, end degrees) of inputs 3847, 1981, 8297 of random_arcs(10000, 1)
ARCS = [((8, 2379), 6, 130, 178), ((17, 3660), 15, 102, 205), ((18, 1821), 16, 133, 235)]


@pytest.fixture(scope="module")
def diagram():
    return cv.voronoi([cv.Arc.circular(c, r, a0, a1) for c, r, a0, a1 in ARCS])


def _sites(d):
    """(end, arc a, arc b): the elementary sites of the end (178°) of the first arc and of the
    interiors of the other two."""
    end = next(k for k, s in enumerate(d.sites) if not isinstance(s, cv.Arc)
               and abs(float(s.x) - 2.0037) < 1e-3 and abs(float(s.y) - 2379.2) < 1e-1)
    a = next(k for k, s in enumerate(d.sites) if isinstance(s, cv.Arc) and tuple(s.c) == (17, 3660))
    b = next(k for k, s in enumerate(d.sites) if isinstance(s, cv.Arc) and tuple(s.c) == (18, 1821))
    return end, a, b


def test_the_end_lies_inside_the_hull_side_of_the_two_arcs(diagram):
    """The scene's premise, exactly: both arcs reach x = 2, the end lies at x > 2 between them."""
    end, _a, _b = _sites(diagram)
    p = diagram.sites[end]
    assert Fraction(str(p.x)) > 2 and 1821 < Fraction(str(p.y)) < 3660
    for (cx, _cy), r, a0, a1 in ARCS[1:]:
        assert a0 <= 180 <= a1 and cx - r == 2


def test_certified_with_the_far_vertex(diagram):
    d = diagram
    assert d.certified, d.problems[:3]
    end, a, b = _sites(d)
    far = [v for v in d.vertices if set(v.sites) == {end, a, b}]
    assert len(far) == 1 and far[0].radius > 9e7
    # the end's region is bounded: none of its edges goes to infinity
    assert not [e for e in d.edges if end in e.sites and None in e.ends]


def test_far_vertex_against_the_reference(diagram):
    d = diagram
    end, a, b = _sites(d)
    v = next(v for v in d.vertices if set(v.sites) == {end, a, b})
    S = [site_data(s) for s in d.sites]
    with mpmath.workdps(40):
        def f(x, y):
            de = distance(S[end], (x, y))
            return [distance(S[a], (x, y)) - de, distance(S[b], (x, y)) - de]
        x, y = mp(v.x), mp(v.y)
        h = mpmath.mpf(10) ** -12 * abs(x)
        for _ in range(30):                   # Newton with central differences, 40 digits
            f0 = f(x, y)
            fx = [(u - w) / (2 * h) for u, w in zip(f(x + h, y), f(x - h, y))]
            fy = [(u - w) / (2 * h) for u, w in zip(f(x, y + h), f(x, y - h))]
            det = fx[0] * fy[1] - fx[1] * fy[0]
            dx = (f0[0] * fy[1] - f0[1] * fy[0]) / det
            dy = (fx[0] * f0[1] - fx[1] * f0[0]) / det
            x, y = x - dx, y - dy
            if abs(dx) + abs(dy) < mpmath.mpf(10) ** -20 * abs(x):
                break
        assert max(abs(g) for g in f(x, y)) < mpmath.mpf(10) ** -15
        ref = distance(S[end], (x, y))
        assert abs(x - mp(v.x)) < 1e-6 * ref and abs(y - mp(v.y)) < 1e-6 * ref
        assert abs(ref - mp(v.radius)) < 1e-6 * ref
        assert nearest_margin(S, a, b, (x, y)) >= -1e-20       # the end is at the radius too
        # the first arc is as near as its end there (its nearest point is that end: the tie
        # belongs to the end); every other site is farther
        own = next(k for k, s in enumerate(d.sites) if isinstance(s, cv.Arc) and tuple(s.c) == (8, 2379))
        assert distance(S[own], (x, y)) >= ref - mpmath.mpf(10) ** -20
        others = [k for k in range(len(S)) if k not in (end, a, b, own)]
        assert min(distance(S[k], (x, y)) for k in others) > ref


def test_infinite_edge_of_the_two_arcs_leaves_the_far_vertex_outwards(diagram):
    d = diagram
    end, a, b = _sites(d)
    v = next(v for v in d.vertices if set(v.sites) == {end, a, b})
    e = next(e for e in d.edges if set(e.sites) == {a, b})
    assert None in e.ends and v.id in e.ends
    P = np.asarray(e.polyline, dtype=float)
    tail = P[-1] if e.ends[1] is None else P[0]
    assert tail[0] < v.x                                   # further out to the left
    S = [site_data(s) for s in d.sites]
    with mpmath.workdps(40):
        for q in P[1:-1][:: max(1, len(P) // 8)]:
            x = (mp(q[0]), mp(q[1]))
            da, db = distance(S[a], x), distance(S[b], x)
            # on the bisector within the stated tolerance, with the two arcs the nearest sites
            assert abs(da - db) <= 2 * e.tolerance
            assert nearest_margin(S, a, b, x) > -2 * e.tolerance
