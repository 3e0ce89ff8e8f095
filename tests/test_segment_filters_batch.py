"""Two array filters of the segment construction against exact references: the emptiness float
filter's verdict that a site enters a candidate vertex's circle (runtime/segments/emptiness.
filter_block: the nearest site proved inside, the lowest index on a tie; an exact tie on the
circle left undecided), and the far ends of the perpendiculars at a segment's two ends
(runtime/segments/parallel_rays.parallel_ray_triangles), each compared with Fraction arithmetic."""
from __future__ import annotations

from fractions import Fraction as Q

import numpy as np
import pytest
from flint import arb
from scipy.spatial import cKDTree

from curvedvoronoi.runtime.predicates.circles import Point
from curvedvoronoi.runtime.segments.elementary import decompose
from curvedvoronoi.runtime.segments.emptiness import filter_block, prove_empty
from curvedvoronoi.runtime.segments.newton import prove_vertices
from curvedvoronoi.runtime.segments.parallel_rays import FAR, parallel_ray_triangles
from curvedvoronoi.runtime.segments.vertices import VertexSolution
from curvedvoronoi.runtime.sites.segment import Segment


def _job(extra):
    """The vertex (1, 1), r² = 2, of the points (0, 0), (2, 0), (0, 2), proved, among the
    points ``extra``; the points are their own samples (spacing 0)."""
    pts = [(Q(0), Q(0)), (Q(2), Q(0)), (Q(0), Q(2))] + [(Q(x), Q(y)) for x, y in extra]
    E = decompose([Point(*p) for p in pts])
    idx = {tuple(E.xy[i]): i for i in range(E.n_points)}
    triple = tuple(idx[p] for p in pts[:3])
    sol = prove_vertices(E, [(triple, np.array([1.01, 0.99]))], cache={})[0]
    assert sol.status == "proved"
    tree = cKDTree(E.A[:E.n_points])
    lab = np.arange(E.n_points)
    return E, tree, lab, triple, sol, idx


def _inside(extra, idx):
    """Exactly: the sites strictly inside the circle |v − (1, 1)|² < 2, nearest first, then by index."""
    d2 = {idx[(Q(x), Q(y))]: (Q(x) - 1) ** 2 + (Q(y) - 1) ** 2 for x, y in extra}
    return sorted((v, k) for k, v in d2.items() if v < 2)


@pytest.mark.parametrize("extra", [
    [(2, Q(2) - Q(1, 2 ** 30))],                       # inside by ~2^-30 / √2
    [(2, Q(2) - Q(1, 2 ** 30)), (Q(3, 2), Q(1, 4))],   # two inside, the second nearer
    [(1, Q(-1, 4)), (Q(-1, 4), 1), (1, Q(9, 4))],      # three at the same distance 5/4
    [(Q(3, 2), Q(1, 4)), (3, 3), (-1, 1)],             # one inside, two outside
])
def test_a_site_inside_the_circle_is_the_culprit_of_the_filter(extra):
    E, tree, lab, triple, sol, idx = _job(extra)
    ref = _inside(extra, idx)
    assert ref
    got = filter_block(E, tree, lab, 0.0, [(triple, sol)])[id(sol)]
    nearest = min(v for v, _k in ref)
    assert got == (False, triple, min(k for v, k in ref if v == nearest))
    assert got == prove_empty(E, tree, lab, 0.0, triple, sol)


def test_a_site_exactly_on_the_circle_is_left_to_the_exact_decision():
    # (2, 2) is on the circle (a vertex of degree 4): neither empty nor entered by floats
    E, tree, lab, triple, sol, idx = _job([(2, 2), (5, 5)])
    assert _inside([(2, 2), (5, 5)], idx) == []
    assert id(sol) not in filter_block(E, tree, lab, 0.0, [(triple, sol)])
    empty, members, _culprit = prove_empty(E, tree, lab, 0.0, triple, sol)
    assert empty is True and set(members) == set(triple) | {idx[(Q(2), Q(2))]}


def _on_circle_points(sol, count):
    """Rational points 1 + (cos θ − sin θ, sin θ + cos θ) exactly on the circle |v − (1, 1)|² = 2
    (cos θ, sin θ = (m² − n², 2mn)/(m² + n²)) whose float distance from the float centre falls
    below the float radius -- a plain float comparison would take them as inside."""
    out = []
    for m in range(2, 40):
        for n in range(1, m):
            c, s = Q(m * m - n * n, m * m + n * n), Q(2 * m * n, m * m + n * n)
            x, y = 1 + c - s, 1 + s + c
            assert (x - 1) ** 2 + (y - 1) ** 2 == 2
            if np.hypot(float(x) - sol.x, float(y) - sol.y) < sol.r and (x, y) not in out:
                out.append((x, y))
                if len(out) == count:
                    return out
    raise AssertionError("no float-inside rational point found")


def test_points_exactly_on_the_circle_are_not_taken_inside_by_rounding():
    _E, _tree, _lab, _triple, sol, _idx = _job([])
    extra = _on_circle_points(sol, 3)
    E, tree, lab, triple, sol, idx = _job(extra)
    assert _inside(extra, idx) == []
    assert id(sol) not in filter_block(E, tree, lab, 0.0, [(triple, sol)])


@pytest.mark.parametrize("rho, wxy, wr", [(Q(14142135, 10 ** 7), 2.0 ** -20, 2.0 ** -20),
                                          (Q(1414, 1000), 2.0 ** -20, 2.0 ** -20),
                                          (Q(14142130, 10 ** 7), 2.0 ** -40, 2.0 ** -20)])
def test_an_entering_site_must_enter_for_every_vertex_of_the_box(rho, wxy, wr):
    # a candidate known only to the box |x − 1|, |y − 1| ≤ wxy, |r − √2| ≤ wr and the point
    # p = (1, 1 − ρ): p enters the circle of every (x, y, r) of the box iff its largest distance
    # over the box, at most ρ + √2·wxy (at least ρ + wxy), stays below the smallest radius R − wr
    E, tree, lab, triple, _sol, idx = _job([(1, 1 - rho)])
    R = float(np.sqrt(2.0))
    sol = VertexSolution("proved", 1.0, 1.0, R, (arb(1, wxy), arb(1, wxy), arb(R, wr)))
    always = rho + Q(3, 2) * Q(wxy) < Q(R) - Q(wr)                 # √2 < 3/2
    somewhere_not = rho + Q(wxy) >= Q(R) - Q(wr)
    assert always != somewhere_not
    got = filter_block(E, tree, lab, 0.0, [(triple, sol)]).get(id(sol))
    if somewhere_not:
        assert got is None
    else:
        assert got == (False, triple, idx[(Q(1), 1 - rho)])


def test_a_diagonal_site_must_enter_for_every_vertex_of_the_box():
    # p = (1 − a, 1 − a) at distance √2·a from the centre, a box |x − 1|, |y − 1| ≤ w: its corner
    # (1 + w, 1 + w) is √2·(a + w) from p, more than the smallest radius R − w_r here although
    # p is inside the centre's circle by more than w
    w, wr = 2.0 ** -20, 2.0 ** -40
    R = float(np.sqrt(2.0))
    a = 1 - Q(85, 100) * Q(w)
    assert 2 * (a + Q(w)) ** 2 >= (Q(R) - Q(wr)) ** 2               # not inside at that corner
    assert 2 * a * a < (Q(R) - Q(w) - Q(wr)) ** 2                   # inside at the centre by > w
    E, tree, lab, triple, _sol, idx = _job([(1 - a, 1 - a)])
    sol = VertexSolution("proved", 1.0, 1.0, R, (arb(1, w), arb(1, w), arb(R, wr)))
    assert id(sol) not in filter_block(E, tree, lab, 0.0, [(triple, sol)])


def test_an_empty_circle_passes_the_filter():
    E, tree, lab, triple, sol, idx = _job([(2, Q(2) + Q(1, 2 ** 30)), (-1, -1)])
    assert _inside([(2, Q(2) + Q(1, 2 ** 30)), (-1, -1)], idx) == []
    assert filter_block(E, tree, lab, 0.0, [(triple, sol)])[id(sol)] == (True, triple, None)


@pytest.mark.parametrize("a, b, end_first", [((0, 0), (3, 4), False), ((3, 4), (0, 0), False),
                                               ((0, 0), (3, 4), True)])
def test_far_circumcentres_of_a_segment_and_its_two_ends(a, b, end_first):
    # segment s of length 5 with its ends p, q (and a second segment far off: the scene's box);
    # triangle (p, q, s) is taken when its circumcentre c is farther than FAR lengths of s from
    # s's midpoint and FAR scene sizes from the box's centre (exact reference in Fractions).
    # ``end_first``: the end b listed first as a point, so s runs from the higher site index
    E = decompose(([Point(*b)] if end_first else []) + [Segment(a, b), Segment((10, 0), (10, 2))])
    s = next(i for i in range(E.n_points, len(E.kind)) if {tuple(E.xy[int(e)]) for e in E.ends[i]} == {a, b})
    other = next(i for i in range(E.n_points, len(E.kind)) if i != s)
    p, q = sorted(int(e) for e in E.ends[s])
    r = sorted(int(e) for e in E.ends[other])[0]
    mid = (Q(a[0] + b[0], 2), Q(a[1] + b[1], 2))
    centre, scene = (Q(5), Q(2)), Q(10)
    # along the perpendicular through the midpoint (direction (−4, 3)/5), at distances t
    seeds, T3, want = [], [], []
    for t in (Q(4999), Q(5001), Q(10 ** 4), Q(10 ** 5), Q(-10 ** 5)):
        c = (mid[0] - 4 * t / 5, mid[1] + 3 * t / 5)
        d_mid2 = (c[0] - mid[0]) ** 2 + (c[1] - mid[1]) ** 2
        d_box2 = (c[0] - centre[0]) ** 2 + (c[1] - centre[1]) ** 2
        for tri, own in (([p, q, s], True), ([p, r, s], False), ([p, q, other], False)):
            seeds.append((float(c[0]), float(c[1])))
            T3.append(sorted(tri))
            want.append(own and d_mid2 > (FAR * 5) ** 2 and d_box2 > (FAR * scene) ** 2)
    assert (E.ends[s, 0] > E.ends[s, 1]) == end_first
    got = parallel_ray_triangles(E, np.array(T3), np.array(seeds))
    assert got.tolist() == want
    assert any(want) and not all(want[0::3])
