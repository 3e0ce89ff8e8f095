"""The taper of the strips at a vertex (runtime/voronoi/verify/bisector_guide.py,
:func:`vertex_taper_many`): θ the smallest angle between ∇d_i − ∇d_j and ∇d_k − ∇d_i over the
third sites k, w_v = d·|∇d_k − ∇d_i|·|∇d_i − ∇d_j|·sin θ / (8 (|∇d_k − ∇d_i| + |∇d_i − ∇d_j|)),
the smallest over k.  Reference: circles, whose distance gradients outside are (x − c)/|x − c| and
distances |x − c| − r in closed form; several vertices served in one call, third sites in either
order."""
from types import SimpleNamespace

import numpy as np
import pytest

import curvedvoronoi as cv
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify.bisector_guide import TaperJob, vertex_taper_many
from curvedvoronoi.runtime.voronoi.verify.site_table import SiteTable

CIRCLES = [(0.0, 0.0, 1.0), (6.0, 0.5, 1.5), (2.0, 7.0, 0.5), (-3.0, 5.0, 2.0), (8.0, 6.0, 1.0)]


def _reference(x, pair, ks):
    g = {}
    d = {}
    for s in (pair[0], pair[1]) + tuple(ks):
        cx, cy, r = CIRCLES[s]
        dist = np.hypot(x[0] - cx, x[1] - cy)
        g[s], d[s] = (np.array(x) - (cx, cy)) / dist, dist - r
    Df = g[pair[0]] - g[pair[1]]
    best = None
    for k in ks:
        Dg = g[k] - g[pair[0]]
        sin = abs(Df[0] * Dg[1] - Df[1] * Dg[0]) / (np.hypot(*Df) * np.hypot(*Dg))
        w = min(d[pair[0]], d[pair[1]]) * np.hypot(*Dg) * np.hypot(*Df) * sin / (8 * (np.hypot(*Dg) + np.hypot(*Df)))
        if best is None or w < best[1]:
            best = (sin, w)
    return best


def test_the_smallest_taper_over_the_third_sites():
    table = SiteTable([site_geometry(cv.Circle.from_radius(*c)) for c in CIRCLES], 20.0)
    cases = [((2.5, 3.0), (0, 1), (2, 3)), ((2.5, 3.0), (0, 1), (3, 2)), ((3.0, 3.5), (1, 2), (4, 0, 3)),
             ((1.0, 4.0), (3, 0), (2,))]
    jobs = [TaperJob(SimpleNamespace(x=x, y=y), pair, ks) for (x, y), pair, ks in cases]
    got = vertex_taper_many(table, jobs)
    refs = [_reference(x, pair, ks) for x, pair, ks in cases]
    # the third sites give clearly different tapers, so the smallest one is the one chosen
    assert len({round(_reference(cases[0][0], (0, 1), (k,))[1], 6) for k in (2, 3)}) == 2
    for g_, r_ in zip(got, refs):
        assert g_ == pytest.approx(r_, rel=1e-9)


def test_node_widths_served_together():
    """The wanted strip half-width at a node x of the bisector of (i, j):
    max(min(max(3·tol, 10⁻⁶·scale), 0.03·min(d_i, d_j)·|∇d_i − ∇d_j|), 10⁻⁹·scale), with the circles'
    closed-form distances and gradients; two guides of different tolerances in one call."""
    from curvedvoronoi.runtime.voronoi.verify.bisector_guide import WidthJob, node_width_many

    table = SiteTable([site_geometry(cv.Circle.from_radius(*c)) for c in CIRCLES], 20.0)
    X = np.array([[2.5, 3.0], [3.0, 3.5], [1.0, 4.0]])
    jobs = [WidthJob(X, (0, 1), 1e-3, 20.0), WidthJob(X[:2], (2, 3), 0.5, 30.0)]
    got = node_width_many(table, jobs)
    for jb, w in zip(jobs, got):
        ref = []
        for x in jb.X:
            g, d = [], []
            for s in jb.pair:
                cx, cy, r = CIRCLES[s]
                dist = np.hypot(x[0] - cx, x[1] - cy)
                g.append((x - (cx, cy)) / dist)
                d.append(dist - r)
            c = 0.03 * min(d) * np.hypot(*(g[0] - g[1]))
            ref.append(max(min(max(3 * jb.tol, 1e-6 * jb.scale), c), 1e-9 * jb.scale))
        assert w == pytest.approx(ref, rel=1e-9)
    assert got[1][0] > 10 * got[0][0]          # the tolerances differ enough to tell the guides apart
