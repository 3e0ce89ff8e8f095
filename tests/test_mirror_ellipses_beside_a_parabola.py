"""Mirror-image ellipses in a diagram that also holds a parabola.

Four congruent ellipses centred at (±3, ±3) (semi-axes 2 and 1, axes parallel to the coordinate
axes) are mapped onto each other by the reflections x ↦ −x and y ↦ −y; a point fixed by both, the
origin, is therefore equidistant from all four, a Voronoi vertex of degree 4 (thesis §3.3:
equidistance proved by a symmetry fixing a rational point), and the edges between ellipses that
are mirror images lie on the mirror lines x = 0 and y = 0.  A parabola opening upwards from
(0, 30) stays farther than the ellipses near the origin.  A parabola has no support function
(it is unbounded), so the verifier proves the edges of the mirror pairs by strips, not by the
mirror-line route that needs the support table; the diagram built by the construction must get
its vertices and every edge between two vertices proved.  (The edges that run to infinity next
to the parabola are not asserted: tails between a bounded and an unbounded site are outside the
verifier's asymptotic enclosures.)"""
from __future__ import annotations

import mpmath as mp

from curvedvoronoi.runtime.sites.conic import Conic
from curvedvoronoi.runtime.voronoi.construction import voronoi
from curvedvoronoi.runtime.voronoi.verify.certificate import verify


def _sites():
    return [Conic.ellipse((-3, -3), (2, 1)), Conic.ellipse((3, -3), (2, 1)), Conic.ellipse((3, 3), (2, 1)),
            Conic.ellipse((-3, 3), (2, 1)), Conic.parabola((0, 30), 1, rotation=(0, 1))]


def _distance_origin_to_ellipse():
    # min over θ of |(3 + 2 cos θ, 3 + sin θ)|, by mpmath at 30 digits (independent of the code)
    mp.mp.dps = 30
    f = lambda t: mp.sqrt((3 + 2 * mp.cos(t)) ** 2 + (3 + mp.sin(t)) ** 2)
    df = lambda t: mp.diff(f, t)
    t0 = min((mp.mpf(k) * mp.pi / 64 for k in range(128)), key=f)
    return f(mp.findroot(df, t0))


def test_the_symmetric_vertex_and_the_bounded_edges_are_proved():
    D = voronoi(_sites(), certify=False)
    cert = verify(D)
    # the degree-4 vertex is the origin, at the ellipses' common distance
    (v4,) = [v for v in D.vertices if len(v.sites) == 4]
    assert set(v4.sites) == {0, 1, 2, 3}
    assert abs(v4.x) < 1e-12 and abs(v4.y) < 1e-12
    assert abs(v4.radius - float(_distance_origin_to_ellipse())) < 1e-9
    assert all(cert.vertices)
    bounded = [k for k, e in enumerate(D.edges) if None not in e.ends]
    assert len(bounded) >= 4
    assert all(cert.edges[k] for k in bounded)
    # the mirror pairs' edges on x = 0 and y = 0 that end at two vertices are among them
    assert any(set(D.edges[k].sites) == {0, 3} for k in bounded)
    assert any(set(D.edges[k].sites) == {2, 3} for k in bounded)
