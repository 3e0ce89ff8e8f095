"""The accounting of the ends at infinity on the circle route (runtime/voronoi/verify/closure.py,
``verify_accounting``): between two consecutive unbounded edges, one shared site must own every
far direction of the arc between them — over the whole arc, not only at its start.

Three points A = (0, 0), B = (10, 0), C = (5, 8): their diagram has three unbounded edges, in the
directions normal to AB, BC and CA pointing away from the third point (closed form).  With the
three ends the accounting holds; with BC's end left out, A would have to own the far directions
from AB's end round to CA's — an arc of length > π where B and C lead (h_k(θ) = c_k·e(θ)): it must
be refused.  Also two circles and a point, where the radii shift the directions."""
import math

import numpy as np
import pytest

from curvedvoronoi.runtime.voronoi.verify import closure
from curvedvoronoi.runtime.voronoi.verify.edges import CircleTable


def outward(p, q, r):
    """Direction (angle) of the unbounded bisector of the points p, q, away from r."""
    d = np.array(q, float) - np.array(p, float)
    nrm = np.array([-d[1], d[0]])
    if nrm @ (np.array(r, float) - (np.array(p) + np.array(q)) / 2) > 0:
        nrm = -nrm
    return math.atan2(nrm[1], nrm[0]) % (2 * math.pi)


PTS = [(0.0, 0.0), (10.0, 0.0), (5.0, 8.0)]


def ends(skip=None):
    A, B, C = PTS
    out = [(outward(A, B, C), (0, 1), 1, 0), (outward(B, C, A), (1, 2), 1, 1), (outward(C, A, B), (0, 2), 1, 2)]
    return [e for e in out if e[3] != skip]


def test_the_three_ends_of_a_triangle_close_up():
    problems = []
    assert closure.verify_accounting(3, CircleTable.from_arrays(PTS, [0, 0, 0]), ends(), problems), problems


@pytest.mark.parametrize("skip", [0, 1, 2])
def test_a_missing_end_is_refused(skip):
    problems = []
    assert not closure.verify_accounting(3, CircleTable.from_arrays(PTS, [0, 0, 0]), ends(skip), problems)
    assert problems


def test_an_owner_leading_at_the_start_of_its_arc_but_not_over_all_of_it_is_refused():
    """The square A, B, C, D = (0, 0), (10, 0), (10, 10), (0, 10) (far ends AB at 3π/2, BC at 0, CD at
    π/2, DA at π) with BC's and CD's ends replaced by one end of (B, D) at 3π/4: B leads just after
    AB's end (3π/2) but C leads from 0 on, so B cannot own the arc from 3π/2 round to 3π/4 + 2π.
    The test at the arc's start alone passes; over the whole arc it must fail."""
    sq = [(0.0, 0.0), (10.0, 0.0), (10.0, 10.0), (0.0, 10.0)]
    ends_ = [(3 * math.pi / 2, (0, 1), 1, 0), (3 * math.pi / 4, (1, 3), 1, 1), (math.pi, (0, 3), 1, 2)]
    problems = []
    assert not closure.verify_accounting(4, CircleTable.from_arrays(sq, [0, 0, 0, 0]), ends_, problems)
    assert any("no single site owns" in str(p) for p in problems)
    # the true ends close up
    true_ends = [(3 * math.pi / 2, (0, 1), 1, 0), (0.0, (1, 2), 1, 1), (math.pi / 2, (2, 3), 1, 2), (math.pi, (0, 3), 1, 3)]
    assert closure.verify_accounting(4, CircleTable.from_arrays(sq, [0, 0, 0, 0]), true_ends, [])


def test_conics_with_unbounded_regions_and_no_end_at_infinity_are_refused():
    """Two disjoint ellipses side by side both lead in some far directions (h_k(θ) = c_k·e(θ) +
    √(eᵀAe)): with no unbounded end proved, the accounting must fail — unless one site contains
    all others, which the second case shows (a circle inside an ellipse: no unbounded edge)."""
    import curvedvoronoi as cv
    from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
    from curvedvoronoi.runtime.voronoi.verify.support import SupportTable

    side = [site_geometry(cv.Conic.ellipse((0, 0), (3, 1))), site_geometry(cv.Conic.ellipse((10, 0), (2, 1)))]
    problems = []
    assert not closure.verify_accounting_conics(2, SupportTable(side), [], problems)
    assert problems
    nested = [site_geometry(cv.Conic.ellipse((0, 0), (10, 6))), site_geometry(cv.Circle.from_radius(1, 1, 1))]
    assert closure.verify_accounting_conics(2, SupportTable(nested), [], [])
