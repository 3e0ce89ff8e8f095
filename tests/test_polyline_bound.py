"""The verifier's Hausdorff bound between a polyline and a bisector arc of circle/point sites
(runtime/voronoi/verify/polyline_bound.py), against dense sampling.

The arc is written in the test from its definition (|q − c_i| − ρ_i = |q − c_j| − ρ_j, solved for
q on each line of a pencil through the foci's midpoint), not with the library's parametrisation;
the Hausdorff distance between a polyline and the sampled arc is measured by brute force.  The
bound must never be below it (soundness) and not far above it (it is useful)."""
from __future__ import annotations

import math
from fractions import Fraction as F

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify.edges import CircleTable, bisector
from curvedvoronoi.runtime.voronoi.verify.polyline_bound import hausdorff_bound
from curvedvoronoi.runtime.predicates.circles import Circle


def arc_points(ci, ri, cj, rj, y0, y1, n):
    """Points of the bisector branch |q − ci| − ri = |q − cj| − rj with coordinate y ∈ [y0, y1]
    across the foci axis (frame: ci, cj on the x-axis), by bisection in x on each line y = const."""
    ys = np.linspace(y0, y1, n)
    out = []
    for y in ys:
        f = lambda x: math.hypot(x - ci, y) - ri - math.hypot(x - cj, y) + rj   # increasing in x
        lo, hi = -1e4, 1e4
        for _ in range(90):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if f(mid) < 0 else (lo, mid)
        out.append((0.5 * (lo + hi), y))
    return np.array(out)


def hausdorff(A, B):
    """Lower and upper estimates of the Hausdorff distance between a polyline A (its segments)
    and the curve densely sampled by B (the cloud's gaps, half the largest spacing, separate them)."""
    def point_seg(P, S0, S1):
        d = S1 - S0
        t = np.clip(((P[:, None, :] - S0[None]) * d[None]).sum(-1) / np.maximum((d * d).sum(-1), 1e-300)[None], 0, 1)
        Q = S0[None] + t[..., None] * d[None]
        return np.hypot(*(P[:, None, :] - Q).transpose(2, 0, 1)).min(1)
    ab = point_seg(B, A[:-1], A[1:]).max()
    # from the polyline to the cloud: sample the segments densely
    S = np.concatenate([A[k] + np.linspace(0, 1, 200)[:, None] * (A[k + 1] - A[k]) for k in range(len(A) - 1)])
    ba = np.hypot(*(S[:, None, :] - B[None]).transpose(2, 0, 1)).min(1).max()
    gap = 0.5 * np.hypot(*np.diff(B, axis=0).T).max()
    return max(ab, ba - gap), max(ab, ba)


@settings(max_examples=15)
@given(ri=st.floats(0.0, 3.0), rj=st.floats(0.0, 3.0), gap=st.floats(0.5, 10.0),
       y0=st.floats(-20, 0), span=st.floats(0.5, 30), npoly=st.integers(2, 6))
def test_bound_holds_against_dense_sampling(ri, rj, gap, y0, span, npoly):
    cj = ri + rj + gap
    sites = [Circle.from_radius(0, 0, ri) if ri > 0 else Circle(0, 0, 0), Circle.from_radius(cj, 0, rj)]
    T = CircleTable([site_geometry(s) for s in sites])
    bis = bisector(T, 0, 1)
    y1 = y0 + span
    poly = arc_points(0.0, ri, cj, rj, y0, y1, npoly)
    dense = arc_points(0.0, ri, cj, rj, y0, y1, 300)
    bound, why = hausdorff_bound(bis, poly)
    assert why is None
    lower, upper = hausdorff(poly, dense)
    assert bound >= lower - 1e-9 * (1 + span)
    assert bound <= 1.1 * upper + 1e-8 * (1 + span + cj)


def test_a_chord_is_bounded_by_its_bulge():
    """Two unequal circles: the chord of a piece of their hyperbola bisector is proved no closer
    than its bulge (the bound is at least the bulge measured from the sampled arc)."""
    sites = [Circle.from_radius(0, 0, 3), Circle.from_radius(10, 0, 0.5)]
    T = CircleTable([site_geometry(s) for s in sites])
    bis = bisector(T, 0, 1)
    dense = arc_points(0.0, 3.0, 10.0, 0.5, -8, 8, 300)
    chord = dense[[0, -1]]
    bound, _ = hausdorff_bound(bis, chord)
    bulge = np.abs((dense - chord[0]) @ np.array([1.0, 0.0])).max()
    assert bound >= bulge - 1e-9 > 0.1


def test_a_chord_across_a_hairpin_is_bounded():
    """A point and a circle of radius 3 whose centre is 3.01 away: their bisector branch is a
    hairpin (it turns by nearly π around its vertex, x ≈ 12|y| far out); the chord joining y = ±1
    and y = ±4 stays far from the vertex, and the bound is at least the sampled distance."""
    sites = [Circle.from_radius(0, 0, 3), Circle(F(301, 100), 0, 0)]
    T = CircleTable([site_geometry(s) for s in sites])
    bis = bisector(T, 0, 1)
    for y in (1.0, 4.0):
        dense = arc_points(0.0, 3.0, 3.01, 0.0, -y, y, 2001)
        chord = dense[[0, -1]]
        bound, why = hausdorff_bound(bis, chord)
        lower, _ = hausdorff(chord, dense)
        assert why is None and bound >= lower - 1e-9 > 1.0
