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
