"""The edge of two mirror-image sites lies on their mirror line ℓ (thesis §1.2; the reflection in
ℓ maps one site onto the other, so d_i = d_j exactly on ℓ); it is the part of ℓ where every other
site is strictly farther (:func:`runtime.voronoi.verify.mirror_tail.prove_mirror_edge`).

Each scene below is small enough to decide that fact by hand, with exact bounds: the distance to
a point site is |q − k|, and the distance from q to an ellipse is at most |q − F| for any point F
of it and at least the distance from q to a line the ellipse lies beyond.
"""
from __future__ import annotations

from fractions import Fraction as F
from types import SimpleNamespace

import numpy as np
import pytest

import curvedvoronoi as cv
from curvedvoronoi.runtime.predicates.symmetry import mirror_line
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify.curved_edges import curved_scale
from curvedvoronoi.runtime.voronoi.verify.mirror_tail import prove_mirror_edge
from curvedvoronoi.runtime.voronoi.verify.site_table import SiteTable
from curvedvoronoi.runtime.voronoi.verify.support import SupportTable


def _prove(sites, v0, v1, polyline):
    geoms = [site_geometry(s) for s in sites]
    exact = [g.exact for g in geoms]
    assert mirror_line(exact[0], exact[1]) is not None
    ends = [None if p is None else SimpleNamespace(exact_point=(F(p[0]), F(p[1]))) for p in (v0, v1)]
    ok, msg, _ = prove_mirror_edge(exact, geoms, SiteTable(geoms, curved_scale(geoms)), SupportTable(geoms),
                                   (0, 1), ends[0], ends[1], np.array(polyline, float), False)
    return ok, msg


def _far_pair():
    """Ellipses with axes (2, 1) centred at (1000, 97) and (1000, 103): mirror images in y = 100.
    The first lies in the strip 96 ≤ y ≤ 98 and holds the point (1000, 98)."""
    return [cv.Conic.ellipse(centre=(1000, 97), axes=(2, 1)), cv.Conic.ellipse(centre=(1000, 103), axes=(2, 1))]


def test_a_point_nearer_on_part_of_the_mirror_segment_refuses_it():
    """The segment from (998, 100) to (1002, 100) of the mirror y = 100 with the point site
    k = (999, 501/5): at q = (999, 100), d_k = 1/5 while d_i ≥ 100 − 98 = 2 (the ellipse lies
    below y = 98), so the segment is not part of the edge.  The scene sits a thousand units from
    the origin along ℓ: pieces of ℓ are decided on discs that must cover them wherever ℓ's
    parameter starts."""
    sites = _far_pair() + [cv.Point(F(999), F(501, 5))]
    ok, msg = _prove(sites, (998, 100), (1002, 100), [[998, 100], [1002, 100]])
    assert not ok, "a segment where the point (999, 100.2) is nearer was proved an edge"


def test_a_point_nearer_by_less_than_a_piece_refuses_the_segment():
    """k = (1000, 1019/10), just below the upper ellipse: at q = (1000, 100), d_k = 19/10 while
    d_i ≥ 100 − 98 = 2, so k is nearer there, by less than the first pieces' length (1/2): a
    piece's disc bound lo_k(C) − R > hi_i(C) + R must not be taken the wrong way round."""
    sites = _far_pair() + [cv.Point(F(1000), F(1019, 10))]
    ok, msg = _prove(sites, (998, 100), (1002, 100), [[998, 100], [1002, 100]])
    assert not ok, "a segment where the point (1000, 101.9) is nearer was proved an edge"


def test_the_same_segment_with_the_point_far_along_the_mirror_is_proved():
    """Control: k = (1010, 100).  On the segment, d_i ≤ |q − (1000, 98)| ≤ √8 < 3 while
    d_k ≥ 1010 − 1002 = 8: the segment is part of the edge, and it is proved."""
    sites = _far_pair() + [cv.Point(F(1010), F(100))]
    ok, msg = _prove(sites, (998, 100), (1002, 100), [[998, 100], [1002, 100]])
    assert ok, msg


def _ray_scene():
    """Ellipses with axes (2, 1) at (0, ±3) (mirror y = 0; the upper one holds (0, 2)) and the
    point k = (−10, 0) on the mirror.  On ℓ, q = (x, 0): d_i ≤ |q − (0, 2)| = √(x² + 4) and
    d_k = |x + 10|; for x ≥ −3, x² + 4 < (x + 10)² ⟺ 20x + 96 > 0 holds, so the ray from
    (−3, 0) towards +x is part of the edge; the ray towards −x reaches k (d_k = 0 there)."""
    return [cv.Conic.ellipse(centre=(0, 3), axes=(2, 1)), cv.Conic.ellipse(centre=(0, -3), axes=(2, 1)),
            cv.Point(F(-10), F(0))]


@pytest.mark.parametrize("end", [0, 1])
def test_the_ray_from_a_vertex_away_from_a_third_site_is_proved(end):
    """An edge from the vertex (−3, 0) to infinity along +x, the vertex at either end of the
    polyline: proved, though the other ray of ℓ from (−3, 0) meets k."""
    P = [[-3, 0], [50, 0]]
    v = (-3, 0)
    ok, msg = _prove(_ray_scene(), v if end == 0 else None, v if end == 1 else None, P if end == 0 else P[::-1])
    assert ok, msg


def test_the_whole_mirror_line_through_a_third_site_is_refused():
    """The whole line y = 0 (no end vertex) holds k = (−10, 0), where d_k = 0 < d_i."""
    ok, msg = _prove(_ray_scene(), None, None, [[-50, 0], [50, 0]])
    assert not ok
