"""The tail of a circle/point edge (:func:`runtime.voronoi.verify.edges.prove_tail`, thesis §3.1)
is refused when a third site is nearer on a middle part of it only.

Sites: the point i = (−3, 3/2), the circle j of centre (6/5, 1) and radius 11/10, the point
k = (−4/5, 1).  The bisector of i and j is a hyperbola branch q(u), u ∈ ℝ; on it
G_k = d_k − d_i is positive at u = −3 and at infinity (u → +∞), and negative around the
branch's vertex u = 0.  In τ = e^{−u} the numerator of G_k is a quadratic whose minimum lies
inside the first τ-interval [0, e³]: bounds taken at the interval's ends only would miss it.
"""
from __future__ import annotations

import math

import numpy as np

from curvedvoronoi.runtime.voronoi.verify.edges import CircleTable, bisector, prove_tail

C = np.array([[-3.0, 1.5], [1.2, 1.0], [-0.8, 1.0]])
R = np.array([0.0, 1.1, 0.0])


def _d(q, s):
    return abs(math.hypot(q[0] - C[s][0], q[1] - C[s][1]) - R[s])


def test_a_third_site_nearer_in_the_middle_of_a_tail_refuses_it():
    table = CircleTable.from_arrays(C, R)
    bis = bisector(table, 0, 1)
    assert bis.kind == "hyperbola"
    # the facts of the module docstring, at points of the branch (float margins far above rounding)
    start, vertex = bis.point(np.array([-3.0]))[0], bis.point(np.array([0.0]))[0]
    for q in (start, vertex):
        assert abs(_d(q, 0) - _d(q, 1)) < 1e-9                  # on the bisector of i and j
    assert _d(start, 2) - _d(start, 0) > 0.1                     # k farther at the start
    assert _d(vertex, 2) - _d(vertex, 0) < -0.5                  # k nearer at the vertex
    ok, detail = prove_tail(table, bis, -3.0, 1)
    assert not ok, "a tail on which k is nearer around the vertex was proved"
    k, q, why = detail
    assert (k, why) == (2, "closer")
    assert abs(_d(q, 0) - _d(q, 1)) < 1e-9 and _d(q, 2) < _d(q, 0)


def test_the_same_branch_beyond_the_dip_is_proved():
    """Control: from u = 3 on, k is farther (G_k > 0 on the rest of the branch)."""
    table = CircleTable.from_arrays(C, R)
    ok, detail = prove_tail(table, bisector(table, 0, 1), 3.0, 1)
    assert ok, detail
