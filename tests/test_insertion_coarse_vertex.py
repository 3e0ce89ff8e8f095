"""The local insertion proof (runtime/voronoi/insertion.py, ``_prove_among``) lists the sites near
the reported empty circles of the new vertices; a vertex proved in a coarse box may have a true
circle reaching farther (:func:`runtime.voronoi.verify.vertices.local_reach`), and is proved only
if no site left out of the list comes within that radius.  Planted here: a radius that reaches
every site makes the local proof refuse, the update falls back to a rebuild, and the result is
still the certified diagram of the sites (equal to the batch build)."""
from __future__ import annotations

import curvedvoronoi as cv
from curvedvoronoi.runtime.voronoi import insertion
from scenes import random_disjoint_circles


def _scene():
    sites = random_disjoint_circles(200, 3)
    return sites[:-1], sites[-1]


def test_an_insertion_is_local_without_coarse_vertices():
    base, new = _scene()
    d = cv.voronoi(base, progress=False)
    d2 = d.insert(new)
    assert d2.certified and d2.stats["update"].startswith("local")


def test_a_coarse_vertex_reaching_a_left_out_site_sends_the_update_to_a_rebuild(monkeypatch):
    base, new = _scene()
    d = cv.voronoi(base, progress=False)
    monkeypatch.setattr(insertion, "local_reach", lambda v, info: v.radius + 1e9)
    d2 = d.insert(new)
    assert not d2.stats["update"].startswith("local")
    assert d2.certified
    batch = cv.voronoi(base + [new], progress=False)
    assert d2.delaunay_edges() == batch.delaunay_edges()
