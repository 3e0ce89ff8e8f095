"""The box of a vertex proved by symmetry holds the vertex's exact rational point.

Four congruent ellipses centred at p + (±3, ±3) with p = (1/3, 1/7) are mapped onto each other by
the reflections in the lines x = 1/3 and y = 1/7; p is fixed by both, so it is equidistant from
the four ellipses: a Voronoi vertex of degree 4 at the rational point p (thesis §3.3, equidistance
by a symmetry fixing a rational point).  Neither coordinate of p is a float.

:func:`curvedvoronoi.runtime.voronoi.verify.exact_vertices.symmetric_vertex` returns the proved
vertex as a box (x ± h, y ± h) around float(p) (``VertexInfo``: "a half-width h of its box"); the
box must contain p itself, i.e. h ≥ |float(p) − p| per coordinate, decided here in exact rational
arithmetic."""
from __future__ import annotations

from fractions import Fraction as F

import mpmath as mp
import pytest

from curvedvoronoi.runtime.sites.conic import Conic
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.construction import voronoi
from curvedvoronoi.runtime.voronoi.verify.certificate import verify
from curvedvoronoi.runtime.voronoi.verify.exact_vertices import symmetric_vertex
from curvedvoronoi.runtime.voronoi.verify.vertices import VertexInfo

P = (F(1, 3), F(1, 7))


def _sites(P=P):
    return [Conic.ellipse((P[0] + dx, P[1] + dy), (2, 1)) for dx, dy in ((-3, -3), (3, -3), (3, 3), (-3, 3))]


def _degree_four_vertex(D):
    (v4,) = [v for v in D.vertices if len(v.sites) == 4]
    return v4


def test_the_diagram_of_the_symmetric_ellipses_is_proved():
    D = voronoi(_sites(), certify=False)
    v4 = _degree_four_vertex(D)
    # its radius: the distance from p to the ellipse centred p + (3, 3), by mpmath (independent)
    mp.mp.dps = 30
    f = lambda t: mp.sqrt((3 + 2 * mp.cos(t)) ** 2 + (3 + mp.sin(t)) ** 2)
    t0 = min((mp.mpf(k) * mp.pi / 64 for k in range(128)), key=f)
    r = f(mp.findroot(lambda t: mp.diff(f, t), t0))
    assert abs(v4.radius - float(r)) < 1e-9
    cert = verify(D)
    assert cert.ok and all(cert.vertices) and all(cert.edges)


@pytest.mark.parametrize("p", [P, P[::-1]])     # the larger rounding offset in x, then in y
def test_the_box_of_the_symmetric_vertex_holds_its_rational_point(p):
    sites = _sites(p)
    D = voronoi(sites, certify=False)
    v4 = _degree_four_vertex(D)
    problems: list[str] = []
    info = symmetric_vertex(v4, list(v4.sites), [site_geometry(s) for s in sites], problems, VertexInfo)
    assert problems == [] and info is not None
    assert info.exact_point == p
    h = F(info.h)
    assert abs(F(info.x) - p[0]) <= h and abs(F(info.y) - p[1]) <= h
