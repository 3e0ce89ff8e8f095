"""The shape test that lets the verifier skip the exact mirror-line search
(runtime.voronoi.verify.curved_edges.shape_key / may_mirror).

Facts checked: the key of an ellipse is its semi-axes (A, B), A ≥ B, given exactly to the
constructor, whatever its centre and rotation; a circle's is its radius; and on every pair of a
family of ellipses and circles (equal and unequal shapes, mirrored and rotated), may_mirror is
False only where runtime.predicates.symmetry.mirror_line, the exact reference, finds no mirror line.
"""
from __future__ import annotations

import itertools
from fractions import Fraction

import pytest

from curvedvoronoi.runtime.predicates.circles import Circle, Point
from curvedvoronoi.runtime.predicates.symmetry import mirror_line
from curvedvoronoi.runtime.sites.conic import Conic
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify.curved_edges import may_mirror, shape_key

F = Fraction


@pytest.mark.parametrize("A, B, rot", [(F(3), F(1), (F(1), F(0))), (F(5, 2), F(3, 4), (F(3, 5), F(4, 5))),
                                       (F(2), F(7, 4), (F(8, 17), F(-15, 17)))])
def test_the_key_of_an_ellipse_is_its_semi_axes(A, B, rot):
    E = Conic.ellipse(centre=(F(1, 3), F(-2)), axes=(A, B), rotation=rot)
    kind, a, b = shape_key(site_geometry(E))
    assert kind == "ellipse" and abs(a - float(max(A, B))) < 1e-13 and abs(b - float(min(A, B))) < 1e-13


def test_the_key_of_a_circle_is_its_radius_and_a_point_has_none():
    assert shape_key(site_geometry(Circle.from_radius(F(1), F(2), F(3)))) == ("circle", 3.0)
    assert shape_key(site_geometry(Point(F(5), F(-1)))) == ("point",)


def _family():
    out = []
    for (cx, cy), (A, B), (c, s) in itertools.product(
            [(F(0), F(0)), (F(9), F(1, 2)), (F(-4), F(7))], [(F(2), F(1)), (F(2), F(3, 2)), (F(3), F(3, 2))],
            [(F(1), F(0)), (F(3, 5), F(4, 5)), (F(3, 5), F(-4, 5))]):
        out.append(Conic.ellipse(centre=(cx, cy), axes=(A, B), rotation=(c, s)))
    return out


def test_may_mirror_is_false_only_where_the_exact_search_finds_no_mirror_line():
    sites = _family() + [Circle.from_radius(F(1), F(2), F(3)), Circle.from_radius(F(9), F(2), F(3)),
                         Circle.from_radius(F(1), F(2), F(5, 2)), Point(F(0), F(1)), Point(F(4), F(1))]
    geoms = [site_geometry(s) for s in sites]
    mirrored = refused = 0
    for i, j in itertools.combinations(range(len(sites)), 2):
        exact = mirror_line(sites[i], sites[j]) is not None
        quick = may_mirror(geoms, (i, j))
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
    G = [site_geometry(s) for s in (E, M, N)]
    assert may_mirror(G, (0, 1)) and not may_mirror(G, (0, 2))
