"""The exact Delaunay triangulation of points (runtime/voronoi/exact_delaunay.py) against a brute
force in rationals written here: every triangle counter-clockwise with no point strictly inside its
circle, the areas summing to the area of the convex hull (Andrew's monotone chain in rationals), so
the triangles tile the hull.  Inputs where floats mislead: a rotated grid (rows 10⁻¹⁶ off their
lines), points 10⁻¹⁴ and 10⁻³⁰⁰ off a line, an exact grid (co-circular quadruples)."""
from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from scipy.spatial import Delaunay

from curvedvoronoi.runtime.voronoi.exact_delaunay import exact_delaunay, is_delaunay


def q(P):
    return [(Fraction(float(x)), Fraction(float(y))) for x, y in P]


def orient(a, b, c):
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])


def inside(a, b, c, d):
    m = [(p[0] - d[0], p[1] - d[1]) for p in (a, b, c)]
    m = [(x, y, x * x + y * y) for x, y in m]
    return (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])) > 0


def hull_area(Q):
    pts = sorted(Q)
    def chain(seq):
        out = []
        for p in seq:
            while len(out) >= 2 and orient(out[-2], out[-1], p) <= 0:
                out.pop()
            out.append(p)
        return out
    h = chain(pts)[:-1] + chain(pts[::-1])[:-1]
    return sum(orient(h[0], h[k], h[k + 1]) for k in range(1, len(h) - 1)) / 2


def brute_force_delaunay(P, simp):
    Q = q(P)
    for t in simp.tolist():
        a, b, c = (Q[k] for k in t)
        assert orient(a, b, c) > 0
        assert not any(inside(a, b, c, Q[k]) for k in range(len(Q)) if k not in t)
    assert sum(orient(*(Q[k] for k in t)) for t in simp.tolist()) / 2 == hull_area(Q)
    assert set(np.unique(simp).tolist()) == set(range(len(Q)))


def rotated_grid(n, angle=0.3):
    c, s = np.cos(angle), np.sin(angle)
    return np.array([(c * x - s * y, s * x + c * y) for x in range(n) for y in range(n)])


SCENES = {
    "random 200": np.random.default_rng(3).uniform(-5, 5, (200, 2)),
    "rotated grid 8": rotated_grid(8),
    "rotated grid 6 at UTM": rotated_grid(6, 1.1) * 7.5 + np.array([500000.3, 4649776.7]),
    "exact grid": np.array([(x, y) for x in range(5) for y in range(4)], float),
    "nearly collinear": np.array([(0, 0), (1, 1e-14), (2, 0), (3, -1e-14), (4, 0), (2, 3)]),
    "a hair off a line": np.array([(0, 0), (1, 1e-300), (2, 0), (3, 0), (1.5, 5)]),
    "three": np.array([(0, 0), (1, 1e-14), (2, 0)]),
}


@pytest.mark.parametrize("name", sorted(SCENES))
def test_exact_delaunay_is_delaunay_by_brute_force(name):
    P = SCENES[name]
    simp, nb = exact_delaunay(P)
    brute_force_delaunay(P, simp)
    assert is_delaunay(P, simp, nb)


def test_general_position_matches_qhull():
    P = SCENES["random 200"]
    simp, _ = exact_delaunay(P)
    ref = Delaunay(P)
    edges = lambda S: {tuple(sorted(e)) for t in S.tolist() for e in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0]))}  # noqa: E731
    assert edges(simp) == edges(ref.simplices)
    assert is_delaunay(P, ref.simplices, ref.neighbors)


def test_collinear_points_have_no_triangulation():
    assert exact_delaunay(np.array([(0, 0), (1, 1), (3, 3), (-2, -2)], float)) is None


def test_is_delaunay_rejects_a_flip_an_inverted_triangle_and_a_missing_point():
    P = np.array([(0, 0), (2, 0), (2, 2), (0, 2.5)], float)
    simp, nb = exact_delaunay(P)
    assert is_delaunay(P, simp, nb)
    # the other diagonal: (0, 2.5) is outside the circle of the first three, so it is not Delaunay
    other = {tuple(sorted(e)) for t in simp.tolist() for e in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0]))}
    diag = [e for e in other if set(e) in ({0, 2}, {1, 3})][0]
    a, b = diag
    c, d = [k for k in range(4) if k not in diag]
    flipped = np.array([[c, d, a], [d, c, b]])
    flipped = np.array([t if orient(*(q(P)[k] for k in t)) > 0 else t[::-1] for t in flipped.tolist()])
    nbf = np.full((2, 3), -1)
    for t in range(2):
        for k in range(3):
            side = {int(flipped[t][(k + 1) % 3]), int(flipped[t][(k + 2) % 3])}
            if side == {c, d}:
                nbf[t, k] = 1 - t
    assert not is_delaunay(P, flipped, nbf)
    assert not is_delaunay(P, simp[:, ::-1], nb[:, ::-1])          # clockwise triangles
    assert not is_delaunay(np.vstack([P, [[1, 1]]]), simp, nb)   # a point left out
