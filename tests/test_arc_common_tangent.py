"""Arcs tangent to one common side of the convex hull (thesis §1.2: the unbounded regions are those
of the sites on the hull, their infinite edges follow its sides).

Three circles of integer data touching one line at integer points are common in random scenes
(the 10⁴-arc benchmark has such sides).  The middle arc touches the hull side in its interior, so
its region is unbounded and it has an infinite edge with each neighbour along the side; the outer
two arcs have none in common.  The reference is independent of the construction: the nearest arc
along a far line parallel to the side, by dense sampling of the arcs (numpy), never with the
project's distance code.
"""
from __future__ import annotations

import copy

import numpy as np
import pytest

import curvedvoronoi as cv


def _arc_points(cx, cy, r, a0, a1, n=4001):
    t = np.radians(np.linspace(a0, a1, n))
    return np.column_stack([cx + r * np.cos(t), cy + r * np.sin(t)])


def _nearest_sources_along(samples, y, xs):
    """The input index of the nearest sampled site at (x, y) for each x, in order, repeats removed."""
    out = []
    for x in xs:
        d = [np.hypot(P[:, 0] - x, P[:, 1] - y).min() for P in samples]
        k = int(np.argmin(d))
        if not out or out[-1] != k:
            out.append(k)
    return out


@pytest.mark.parametrize("radii", [(1, 1, 1), (1, 2, 3), (3, 1, 2)])
def test_three_arcs_on_one_hull_side_have_the_infinite_edges_of_consecutive_contacts(radii):
    # circles of radius r_k centred at (10k, r_k): all touch the line y = 0 at (10k, 0), from above;
    # each arc (200°..340°) contains its lowest point; a segment far above closes the hull
    arcs = [cv.Arc.circular((10 * k, r), r, 200, 340) for k, r in enumerate(radii)]
    arcs.append(cv.Segment((5, 30), (15, 31)))
    d = cv.voronoi(arcs, certify=False, progress=False)
    src = d.sources
    infinite = {frozenset((src[i], src[j])) for e in d.edges if None in e.ends for i, j in [e.sites]}
    # the reference: below the side, far out, the nearest input changes from arc 0 to 1 to 2
    samples = [_arc_points(10 * k, r, r, 200, 340) for k, r in enumerate(radii)]
    samples.append(np.column_stack([np.linspace(5, 15, 2001), np.linspace(30, 31, 2001)]))
    order = _nearest_sources_along(samples, -2000.0, np.linspace(-30, 50, 321))
    assert order == [0, 1, 2]
    assert frozenset((0, 1)) in infinite and frozenset((1, 2)) in infinite
    assert frozenset((0, 2)) not in infinite


@pytest.mark.parametrize("radii", [(1, 1, 1), (1, 2, 3), (3, 1, 2)])
def test_the_tie_at_infinity_of_three_tangent_arcs_is_proved(radii):
    # along the infinite edge of arcs 0 and 1 the third arc's circle touches the same support line
    # (a tie of the asymptote's support): proved against its circle
    arcs = [cv.Arc.circular((10 * k, r), r, 200, 340) for k, r in enumerate(radii)]
    arcs.append(cv.Segment((5, 30), (15, 31)))
    d = cv.voronoi(arcs, progress=False)
    assert d.certified, d.problems[:3]
    assert cv.verify(d).ok


def test_an_arc_moved_beyond_the_support_line_is_not_proved_farther():
    # the diagram of three arcs tangent to y = 0, claimed for the scene whose third arc was moved
    # down by 1/2 (its circle crosses the line): along the infinite edge of arcs 0 and 1 the third
    # arc is nearer far out, and the certificate must say so on that edge
    tangent = [cv.Arc.circular((10 * k, 1), 1, 200, 340) for k in range(3)] + [cv.Segment((5, 30), (15, 31))]
    moved = tangent[:2] + [cv.Arc.circular((20, 0.5), 1, 200, 340)] + tangent[3:]
    d = cv.voronoi(tangent, progress=False)
    assert d.certified
    bad = copy.deepcopy(d)
    bad.sites = list(cv.voronoi(moved, certify=False, progress=False).sites)
    c = cv.verify(bad)
    assert not c.ok
    src = d.sources
    arc = {k: [i for i, s in enumerate(src) if s == k and not isinstance(d.sites[i], cv.Point)][0] for k in range(3)}
    e = next(e for e in d.edges if None in e.ends and set(e.sites) == {arc[0], arc[1]})
    assert any(f"edge {e.id} " in str(p) and f"site {arc[2]} is not proved farther" in str(p) for p in c.problems)
