"""The contact systems of point/segment triples coded on arrays
(runtime/segments/vertex_batch.code_point_segment_rows) as runtime/segments/newton.prove_vertices
proves them: each equation kind chosen as in thesis §1.2 / §2.2 (a point, a segment's line on the
seed's side, the normal line at a segment's end that is itself a site of the triple, no circle for
a segment with both its ends), checked against vertices computed exactly with Fractions by hand;
a foot parameter just outside [0, 1] is not proved; on random scenes the codes equal those of the
per-triple equations (contact_equations + code_systems)."""
from __future__ import annotations

from fractions import Fraction as Q

import numpy as np
import pytest
from flint import arb

from curvedvoronoi.runtime.predicates.circles import Point
from curvedvoronoi.runtime.segments.elementary import decompose
from curvedvoronoi.runtime.segments.newton import prove_vertices
from curvedvoronoi.runtime.segments.vertex_batch import code_point_segment_rows, code_systems
from curvedvoronoi.runtime.segments.vertices import contact_equations
from curvedvoronoi.runtime.sites.segment import Segment

from scenes import random_segments


def _index(E, xy=None, seg=None):
    """The elementary site of the point ``xy`` or of the segment with ends ``seg``."""
    for i in range(len(E.kind)):
        if xy is not None and E.kind[i] == 0 and tuple(E.xy[i]) == xy:
            return i
        if seg is not None and E.kind[i] != 0 and {tuple(E.xy[int(e)]) for e in E.ends[i]} == set(seg):
            return i
    raise KeyError((xy, seg))


def _contains(box, exact):
    return all(b.contains(arb(str(Q(v).numerator)) / arb(str(Q(v).denominator))) for b, v in zip(box, exact))


def _prove(E, triple, seed):
    return prove_vertices(E, [(tuple(triple), np.array(seed, float))], cache={})[0]


@pytest.mark.parametrize("a, proved", [(Q(1) - Q(1, 10 ** 9), True), (Q(1) + Q(1, 10 ** 9), False), (Q(-7), True)])
def test_two_points_and_a_segment_below_them(a, proved):
    # points (0, 1), (2, 1), segment (a, 0)-(5, 0): the vertex is (1, 1) of radius 1 (x = 1 by
    # symmetry, 1 + (y − 1)² = y²), on the seed's side y > 0 of the line; foot parameter
    # (1 − a)/(5 − a) -- 2.5e-10 outside [0, 1] for a = 1 + 1e-9: then not a vertex
    E = decompose([Segment((a, 0), (5, 0)), Point(0, 1), Point(2, 1)])
    triple = (_index(E, xy=(0, 1)), _index(E, xy=(2, 1)), _index(E, seg=((a, 0), (5, 0))))
    sol = _prove(E, triple, (1.02, 0.97))
    assert (sol.status == "proved") == proved, sol.reason
    if proved:
        assert _contains(sol.box, (1, 1, 1))
    else:
        assert sol.status == "invalid"


def test_the_line_side_is_the_seed_side():
    # the same two points mirrored below the segment (0, 0)-(5, 0): (0, −1), (2, −1) give (1, −1), r = 1
    E = decompose([Segment((-3, 0), (5, 0)), Point(0, -1), Point(2, -1)])
    triple = (_index(E, seg=((-3, 0), (5, 0))), _index(E, xy=(0, -1)), _index(E, xy=(2, -1)))
    sol = _prove(E, triple, (0.9, -1.1))
    assert sol.status == "proved" and _contains(sol.box, (1, -1, 1))


@pytest.mark.parametrize("q, centre", [((1, 3), (Q(1), Q(3, 2))), ((2, 3), (Q(1), Q(5, 3)))])
def test_a_segment_end_in_the_triple_takes_the_normal_line(q, centre):
    # the segment (1, 0)-(6, 0), its end p = (1, 0) and a point q above: the circle touches the
    # segment at p, so its centre is on the normal x = 1 and equidistant from p and q:
    # (1 − q_x)² + (y − q_y)² = y²  =>  y = ((1 − q_x)² + q_y²) / (2 q_y)
    E = decompose([Segment((1, 0), (6, 0)), Point(*q)])
    p, qq, s = _index(E, xy=(1, 0)), _index(E, xy=q), _index(E, seg=((1, 0), (6, 0)))
    y = (Q(1 - q[0]) ** 2 + Q(q[1]) ** 2) / (2 * q[1])
    assert (Q(1), y) == centre
    for triple in ((p, qq, s), (s, p, qq), (qq, s, p)):
        sol = _prove(E, triple, (1.1, float(y) + 0.1))
        assert sol.status == "proved", sol.reason
        assert _contains(sol.box, (1, y, y))


def test_a_segment_with_both_its_ends_has_no_circle():
    E = decompose([Segment((0, 0), (4, 0))])
    p, q, s = _index(E, xy=(0, 0)), _index(E, xy=(4, 0)), _index(E, seg=((0, 0), (4, 0)))
    rows, invalid, _K, _P, _S = code_point_segment_rows(E, np.array([[p, q, s], [s, q, p]]), np.ones((2, 2)))
    assert rows.all() and invalid.all()
    sol = _prove(E, (p, s, q), (2.0, 1.0))
    assert sol.status == "invalid"


def test_three_segments_of_a_corner_are_the_corner_vertex():
    # three segments meeting at c = (1, 2): the vertex c of radius 0 (a common point of the
    # closures), not a contact system
    c = (1, 2)
    E = decompose([Segment(c, (5, 2)), Segment(c, (1, 7)), Segment(c, (-3, -1))])
    segs = [i for i in range(len(E.kind)) if E.kind[i] != 0]
    rows, invalid, _K, _P, _S = code_point_segment_rows(E, np.array([segs]), np.array([[1.0, 2.0]]))
    assert not rows[0] and not invalid[0]
    sol = _prove(E, segs, (1.0, 2.0))
    assert sol.status == "proved" and sol.r == 0 and tuple(E.xy[sol.corner]) == c


@pytest.mark.parametrize("seed", [1, 2])
def test_the_array_codes_equal_the_per_triple_equations_on_random_scenes(seed):
    segs = random_segments(40, seed)
    E = decompose([Segment(*s) for s in segs])
    rng = np.random.default_rng(seed)
    n = len(E.kind)
    # random triples, and triples with a segment's end (normal lines) or both ends (no circle)
    T = [rng.choice(n, 3, replace=False) for _ in range(300)]
    for s in range(E.n_points, n):
        a, b = (int(v) for v in E.ends[s])
        T += [np.array([a, s, int(rng.integers(n))]), np.array([s, b, a])]
    T = np.array([t for t in T if len(set(t.tolist())) == 3])
    S = rng.uniform(-50, 1050, (len(T), 2))
    rows, invalid, K, P, sides = code_point_segment_rows(E, T, S)
    assert rows.sum() > 0.5 * len(T) and invalid.any()
    for i in range(len(T)):
        eqs = contact_equations(E, tuple(T[i].tolist()), S[i])
        ends = {c for t in T[i] for c in ((int(t),) if E.kind[t] == 0 else (int(E.ends[t, 0]), int(E.ends[t, 1])))}
        common = any(all(c in ((int(t),) if E.kind[t] == 0 else tuple(int(v) for v in E.ends[t])) for t in T[i])
                     for c in ends)
        assert rows[i] == (not common)
        if not rows[i]:
            continue
        assert invalid[i] == (eqs is None)
        if eqs is None:
            continue
        K1, P1 = code_systems([eqs])
        assert (K[i] == K1[0]).all() and (P[i] == P1[0]).all()
        assert tuple(sides[i]) == tuple(d[3] if k == "line" else 0 for k, d, _t in eqs)
