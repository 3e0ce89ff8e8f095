"""The shape test that lets the verifier skip the exact mirror-line search
(runtime.voronoi.verify.curved_edges.shape_invariant / may_mirror).

Facts checked: tr(M)²/(4·det M) of the quadratic part is the closed form (A² + B²)²/(4A²B²) for an
ellipse with semi-axes A, B (M = R·diag(1/A², 1/B²)·Rᵀ up to scale: tr = 1/A² + 1/B²,
det = 1/(A²B²)); it is the same for an ellipse and its exact
reflection; and on every pair of a family of ellipses (equal and unequal shapes, mirrored and
rotated), may_mirror is False only where runtime.predicates.symmetry.mirror_line, the exact
reference, finds no mirror line.
"""
from __future__ import annotations

import itertools
from fractions import Fraction

import pytest

from curvedvoronoi.runtime.predicates.circles import Circle, Point
from curvedvoronoi.runtime.predicates.symmetry import mirror_line
from curvedvoronoi.runtime.sites.conic import Conic
from curvedvoronoi.runtime.voronoi.verify.curved_edges import may_mirror, shape_invariant

F = Fraction


@pytest.mark.parametrize("A, B, rot", [(F(3), F(1), (F(1), F(0))), (F(5, 2), F(3, 4), (F(3, 5), F(4, 5))),
                                       (F(2), F(7, 4), (F(8, 17), F(-15, 17)))])
def test_the_invariant_of_an_ellipse_is_its_closed_form(A, B, rot):
    E = Conic.ellipse(centre=(F(1, 3), F(-2)), axes=(A, B), rotation=rot)
    A2, B2 = A * A, B * B
    assert shape_invariant(E) == (A2 + B2) ** 2 / (4 * A2 * B2)


def test_circles_and_points_have_invariant_one():
    assert shape_invariant(Circle.from_radius(F(1), F(2), F(3))) == 1
    assert shape_invariant(Point(F(5), F(-1))) == 1


def _family():
    out = []
    for (cx, cy), (A, B), (c, s) in itertools.product(
            [(F(0), F(0)), (F(9), F(1, 2)), (F(-4), F(7))], [(F(2), F(1)), (F(2), F(3, 2)), (F(3), F(3, 2))],
            [(F(1), F(0)), (F(3, 5), F(4, 5)), (F(3, 5), F(-4, 5))]):
        out.append(Conic.ellipse(centre=(cx, cy), axes=(A, B), rotation=(c, s)))
    return out


def test_may_mirror_is_false_only_where_the_exact_search_finds_no_mirror_line():
    sites = _family()
    memo: dict = {}
    mirrored = refused = 0
    for i, j in itertools.combinations(range(len(sites)), 2):
        exact = mirror_line(sites[i], sites[j]) is not None
        quick = may_mirror(sites, (i, j), memo)
        assert quick or not exact, (i, j)
        mirrored += exact
        refused += not quick
    # the family holds both kinds: mirror images (equal shapes, mirrored rotations) and shapes
    # that are refused without the exact search
    assert mirrored > 0 and refused > 0


def test_an_ellipse_and_its_reflection_pass_and_a_different_ratio_does_not():
    E = Conic.ellipse(centre=(F(0), F(0)), axes=(F(2), F(1)), rotation=(F(3, 5), F(4, 5)))
    M = Conic.ellipse(centre=(F(6), F(0)), axes=(F(2), F(1)), rotation=(F(3, 5), F(-4, 5)))   # x = 3 mirror
    N = Conic.ellipse(centre=(F(6), F(0)), axes=(F(2), F(1) + F(1, 1024)), rotation=(F(3, 5), F(-4, 5)))
    assert mirror_line(E, M) is not None
    assert may_mirror([E, M, N], (0, 1), {}) and not may_mirror([E, M, N], (0, 2), {})
