"""A diagram built tile by tile (cv.tiled_voronoi) is edited like one built in one process: an
insertion and a deletion are certified and give the Delaunay graph of the batch build of the new
list of sites (the reference: cv.voronoi on that list, and CGAL's Apollonius graph in
tests/test_cgal.py for the batch build itself)."""
from __future__ import annotations

import math
import random

import curvedvoronoi as cv


def _circles():
    rng = random.Random(7)
    return [(10 * i + rng.uniform(0, 5), 10 * j + rng.uniform(0, 5), rng.uniform(0.5, 2))
            for i in range(14) for j in range(14)]


def _free_spot(sites, r):
    """A circle of radius r 0.1 clear of every site (the diagram needs disjoint sites)."""
    for i in range(6, 9):
        for j in range(6, 9):
            c = (10 * i + 8.5, 10 * j + 8.5)
            if all(math.hypot(c[0] - x, c[1] - y) > r + rr + 0.1 for x, y, rr in sites):
                return (c[0], c[1], r)
    raise AssertionError("no free spot")


def test_tiled_circle_diagram_insert_then_delete():
    sites = _circles()
    d = cv.tiled_voronoi(sites, sites_per_tile=50)
    assert d.certified and d.stats["tiling"]["tiles"] == 4
    new = _free_spot(sites, 0.3)
    d2 = d.insert(new)
    assert d2.certified
    assert d2.delaunay_edges() == cv.voronoi(sites + [new]).delaunay_edges()
    d3 = d2.delete_site(len(sites), renumber="last")
    assert d3.certified and d3.delaunay_edges() == d.delaunay_edges()


def test_tiled_ellipse_diagram_insert():
    rng = random.Random(3)
    el = [cv.Conic.ellipse(centre=(12 * i + rng.uniform(0, 3), 12 * j + rng.uniform(0, 3)), axes=(2, 1))
          for i in range(10) for j in range(10)]
    d = cv.tiled_voronoi(el, sites_per_tile=30)
    assert d.certified and "single_process" not in d.stats["tiling"]
    new = cv.Conic.ellipse(centre=(55.5, 56.5), axes=(1, "1/2"))
    d2 = d.insert(new)
    assert d2.certified
    assert d2.delaunay_edges() == cv.voronoi(el + [new]).delaunay_edges()
