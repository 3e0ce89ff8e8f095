"""The accounting of the ends at infinity with unbounded sites (runtime/voronoi/verify/
far_accounting.py, ``accounting_unbounded``): two ends consecutive in angle must share a site.

Far out, the directions strictly between two consecutive ends at infinity of a complete diagram
meet no edge, so they all lie in one cell; that cell's boundary contains both unbounded edges,
so its site belongs to both pairs (the cyclic sequence of unbounded edges, thesis Prop. 1.2.1 and
the module docstring).  Two ends whose site pairs are disjoint cannot be consecutive, whatever
their directions: the accounting must refuse them, and with them the completeness claim.
The scene is that of tests/test_far_conics.py (two parabolas, a hyperbola, three points), whose
unbounded sites are proved separated, so the refusal is the accounting's own.
"""
from __future__ import annotations

import math

from curvedvoronoi.runtime.predicates.circles import Point
from curvedvoronoi.runtime.sites.conic import Conic
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify import far_accounting as FA


def _geoms():
    sites = [Conic.parabola(vertex=(0, 12), p=3, rotation=(0, 1)), Conic.parabola(vertex=(0, -12), p=3, rotation=(0, -1)),
             Conic.hyperbola(centre=(0, 0), axes=(14, 14), rotation=(1, 0)), Point(1, 2), Point(-3, -1), Point(2, -4)]
    return [site_geometry(s) for s in sites]


def test_consecutive_ends_with_disjoint_pairs_are_refused():
    geoms = _geoms()
    # two ends, far apart in angle, of the disjoint pairs (0, 2) and (1, 3): each is the other's
    # neighbour on both sides
    ends = [(0.15, (0, 2), (0.1, 0.2), 0), (math.pi + 0.15, (1, 3), (math.pi + 0.1, math.pi + 0.2), 1)]
    probs: list = []
    assert not FA.accounting_unbounded(geoms, ends, probs)
    assert any("share no site" in str(p) for p in probs), probs
