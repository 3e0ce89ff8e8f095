"""The point/segment/arc certificate (runtime/segments/certificate*.py) on exact inputs at the
float boundaries of its filters: large, non-dyadic coordinates, where a float filter without the
scene's scale would drop the exact candidates.

Every verdict is derived in the docstrings from the closed form of the diagram (a translation
moves the Voronoi diagram with the sites and leaves every direction at infinity unchanged)."""
from __future__ import annotations

from fractions import Fraction as F

import pytest

from curvedvoronoi.runtime.predicates.circles import Point
from curvedvoronoi.runtime.segments.certificate_hull import expected_infinite_ends
from curvedvoronoi.runtime.segments.certificate_sites import SiteTable
from curvedvoronoi.runtime.sites.arc import Arc


def _quarter_at(cx, cy):
    """The quarter arc of radius 2 centred at (cx, cy) from its end e0 = c + (2, 0) to e1 = c + (0, 2)
    (counter-clockwise) with both ends as point sites: sites 0 = e0, 1 = e1, 2 = the arc."""
    e0, e1 = (cx + 2, cy), (cx, cy + 2)
    return SiteTable([Point(*e0), Point(*e1), Arc((cx, cy), 2, e0, e1)])


def test_the_ends_at_infinity_of_a_far_translated_quarter_arc():
    """The quarter arc centred at the origin has three unbounded edges (test_arc_certificate's closed
    form): the radial rays through its ends, e0 with the arc in direction (1, 0) and e1 with the arc in
    direction (0, 1), and the bisector of e0 and e1 in direction (−1, −1).  Far away in a direction u
    the nearest sites are those of largest support u·p, and a translation by t adds u·t to every
    site's support, so the ties -- and the three ends -- are the same for the arc centred at
    t = (10⁹ + 1/3, −3·10⁹ + 3/4).  There the supports are about 10⁹·|u| and their floats are off by
    about 10⁻⁷ (t is not a double): the float filter of the ties must allow for the scene's size."""
    T = _quarter_at(F(10 ** 9) + F(1, 3), F(-3 * 10 ** 9) + F(3, 4))
    ends = expected_infinite_ends(T)
    assert not isinstance(ends, str), ends
    assert sorted(ends) == sorted([((0, 1), (-1, -1)), ((0, 2), (1, 0)), ((1, 2), (0, 1))])


@pytest.mark.parametrize("gap", [F(1, 10 ** 15), F(1, 10 ** 20)])
def test_an_arc_a_hair_inside_a_triangle_leaves_the_triangles_ends(gap):
    """The points 0 = (−2, 0), 1 = (6, 0), 2 = (2, 6) span a triangle; the half circle of radius 1
    centred at c = (2, 1 + gap) below its diameter (counter-clockwise from (1, 1 + gap) to (3, 1 + gap),
    through (2, gap)) lies strictly inside it: its lowest point is gap > 0 above the side y = 0, and
    the other sides are farther than 1 from c.  So no direction has the arc (or its ends 3, 4) among
    the sites of largest support, and the unbounded edges are those of the three points alone: the
    perpendicular bisectors of the hull's sides, in the directions of their outward normals (0, −1)
    for 0–1, (6, 4) ~ (1, 2/3) for 1–2 and (−6, 4) ~ (−1, 2/3) for 0–2.  The gap (10⁻¹⁵, 10⁻²⁰) is
    below the float resolution of the scene: only exact arithmetic separates the arc from the side."""
    cy = 1 + gap
    T = SiteTable([Point(-2, 0), Point(6, 0), Point(2, 6), Point(1, cy), Point(3, cy), Arc((2, cy), 1, (1, cy), (3, cy))])
    ends = expected_infinite_ends(T)
    assert not isinstance(ends, str), ends
    assert sorted(ends) == sorted([((0, 1), (0, -1)), ((1, 2), (1, F(2, 3))), ((0, 2), (-1, F(2, 3)))])


def test_two_distinct_unsupported_sites_are_a_limit_not_a_repeated_curve():
    """Two different whole circles (radius 1 at the origin, radius 2 at (5, 0)) are sites this
    certificate does not prove (its docstring: points, segments and arcs only): each is a limit of the
    certificate (``fault`` False), and since they are different curves no problem may call them the
    same curve repeated (a fault, which would send a construction refining a correct diagram)."""
    from curvedvoronoi.runtime.predicates.circles import Circle
    from curvedvoronoi.runtime.segments.certificate_admissible import admissibility

    problems = admissibility(SiteTable([Circle(0, 0, 1), Circle(5, 0, 2), Point(10, 10)]))
    assert sorted(p.sites for p in problems) == [(0,), (1,)]
    assert not any(p.fault for p in problems)


def _two_arcs_and_their_homothety_centre():
    """The upper half circles of radius 1 at (0, 0) and of radius 2 at (10, 0), their ends, and the
    point (−10, 0): the centre of the homothety (factor 2) taking the first circle to the second, so
    both external common tangents of the circles pass through it.  The upper tangent touches both
    arcs (at the directions 90° + asin(1/10) from their centres, inside both ranges [0°, 180°]) and
    passes through the point: three sites on one support line of irrational direction."""
    from curvedvoronoi.runtime.voronoi.structure import Diagram

    sites = [Point(-10, 0), Point(1, 0), Point(-1, 0), Point(12, 0), Point(8, 0),
             Arc((0, 0), 1, (1, 0), (-1, 0)), Arc((10, 0), 2, (12, 0), (8, 0))]
    return Diagram(sites, [], [])


def test_an_empty_diagram_of_sites_with_undecided_ends_is_not_complete():
    """The Voronoi diagram of seven sites has edges; an empty diagram is not it, so it may be neither
    ok nor complete -- here also when the ends at infinity are a limit of the certificate (collinear
    ties on an irrational common tangent, not claimed by its docstring)."""
    from curvedvoronoi.runtime.segments.certificate import verify_segments

    c = verify_segments(_two_arcs_and_their_homothety_centre())
    assert not c.ok
    assert not c.complete
