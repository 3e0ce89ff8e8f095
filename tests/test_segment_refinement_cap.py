"""The integer regular 256-gon of radius 10⁷: near its centre hundreds of sides are tied to within
the rounding of their integer vertices, and the sample refinement of the construction doubled the
samples of every side each round (3 328 → 798 093 in 7 rounds, qhull taking minutes per round on
these nearly cocircular samples).  The refinement now stops at SAMPLE_GROWTH_CAP times the first
round's samples and says so: an uncertified diagram with the reason named, not an hour's wait.
The cap sits well above what consistent scenes use (≤ 2.3× measured on random segments, the gear
and regular polygons; the 64-gon below grows less than 3×)."""
from __future__ import annotations

import math

import shapely

import curvedvoronoi as cv
from curvedvoronoi.runtime.segments.construction import MIN_SAMPLE_CAP, SAMPLE_GROWTH_CAP


def _ngon(R, n):
    return shapely.Polygon([(round(R * math.cos(2 * math.pi * k / n)), round(R * math.sin(2 * math.pi * k / n)))
                            for k in range(n)])


def test_a_runaway_refinement_stops_and_names_the_reason():
    m = cv.medial_axis(_ngon(10 ** 7, 256))
    grown = m.diagram.stats["round_samples"]
    assert not m.certified
    assert grown[-1] > max(SAMPLE_GROWTH_CAP * grown[0], MIN_SAMPLE_CAP) >= max(grown[:-1])
    assert any(p.startswith("the refinement stopped after") and "nearly degenerate" in p for p in m.diagram.problems)


def test_a_consistent_polygon_does_not_reach_the_cap():
    m = cv.medial_axis(_ngon(10 ** 6, 64))
    grown = m.diagram.stats["round_samples"]
    assert m.certified and grown[-1] < 3 * grown[0]
    assert not any("refinement stopped" in p for p in m.diagram.problems)
