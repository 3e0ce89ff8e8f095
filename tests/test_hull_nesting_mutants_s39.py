"""Step (b) of the accounting (runtime/voronoi/verify/hull_nesting.py, hulls_disjoint): two circles
that touch have neither disjoint convex hulls nor one inside the other's open region, so the step
must refuse them — also when the floats of their bounding boxes, rounded, leave a gap between them.

The circles of radii 2/3 about (0, 0) and 1/3 about (0, 1) touch at (0, 2/3) (the distance of the
centres, 1, is the sum of the radii, exactly); in floats the upper circle's box starts at
1 − fl(1/3) = 0.66666666666666674 and the lower one's ends at fl(2/3) = 0.66666666666666663, 10⁻¹⁶
apart.  The same with the radii swapped (the other circle first in the sweep by box).  Moved apart
by 10⁻⁶ the circles are disjoint, and the step proves it."""
from __future__ import annotations

from fractions import Fraction

import pytest

from curvedvoronoi.runtime.predicates.circles import Circle
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify.hull_nesting import hulls_disjoint
from curvedvoronoi.runtime.voronoi.verify.support import SupportTable


@pytest.mark.parametrize("ra, rb", [(Fraction(2, 3), Fraction(1, 3)), (Fraction(1, 3), Fraction(2, 3))])
def test_touching_circles_whose_float_boxes_part_are_refused(ra, rb):
    lower, upper = Circle.from_radius(0, 0, ra), Circle.from_radius(0, ra + rb, rb)
    sup = SupportTable([site_geometry(lower), site_geometry(upper)])
    # the premise: the rounded boxes do not overlap, though the circles touch
    assert sup.cen[1][1] - sup.rho[1] > sup.cen[0][1] + sup.rho[0]
    problems = []
    assert hulls_disjoint(sup, problems, 400000) is False
    assert problems


@pytest.mark.parametrize("ra, rb", [(Fraction(2, 3), Fraction(1, 3)), (Fraction(1, 3), Fraction(2, 3))])
def test_the_same_circles_apart_are_disjoint(ra, rb):
    lower, upper = Circle.from_radius(0, 0, ra), Circle.from_radius(0, ra + rb + Fraction(1, 10 ** 6), rb)
    problems = []
    assert hulls_disjoint(SupportTable([site_geometry(lower), site_geometry(upper)]), problems, 400000) is True
    assert not problems
