"""Sites inside one ellipse: far away in every direction the ellipse is the nearest site
(h_k < h_E for every site k inside it), so the diagram has no unbounded edge, and the accounting
at infinity holds with none (runtime/voronoi/verify/hull_nesting.sole_leader).  The reference uses
none of the library's geometry: distances to the circles in closed form, to the ellipse by dense
sampling of its boundary; the Delaunay pairs are read from the nearest site on a grid."""
from __future__ import annotations

import copy

import numpy as np

import curvedvoronoi as cv

SCENE = [("e", 0, 0, 10, 6), ("c", 2, 0, 1), ("c", -3, 1, 1.5)]


def sites():
    return [cv.Conic.ellipse((t[1], t[2]), (t[3], t[4])) if t[0] == "e" else (t[1], t[2], t[3]) for t in SCENE]


def distances(X, Y):
    t = np.linspace(0, 2 * np.pi, 4000, endpoint=False)
    bx, by = 10 * np.cos(t), 6 * np.sin(t)
    D = np.full(X.shape, np.inf)
    for k in range(0, len(t), 500):
        D = np.minimum(D, np.hypot(X[..., None] - bx[k:k + 500], Y[..., None] - by[k:k + 500]).min(-1))
    out = [D]
    for _, x, y, r in SCENE[1:]:
        out.append(np.abs(np.hypot(X - x, Y - y) - r))
    return np.stack(out)


def test_circles_inside_an_ellipse_are_certified_without_unbounded_edges():
    d = cv.voronoi(sites(), progress=False)
    assert d.certified, d.problems
    assert all(None not in e.ends for e in d.edges)
    X, Y = np.meshgrid(np.linspace(-30, 30, 301), np.linspace(-30, 30, 301))
    first = distances(X, Y).argmin(0)
    pairs = set()
    for a, b in ((first[:, 1:], first[:, :-1]), (first[1:, :], first[:-1, :])):
        pairs |= {(min(i, j), max(i, j)) for i, j in zip(a[a != b].tolist(), b[a != b].tolist())}
    assert set(d.delaunay_edges()) == pairs
    far = distances(np.array([100.0, -100, 0, 0]), np.array([0.0, 0, 100, -100]))
    assert (far.argmin(0) == 0).all()                 # the ellipse is nearest far away


def test_two_disjoint_ellipses_without_their_unbounded_edges_are_refused():
    d = cv.voronoi([cv.Conic.ellipse((0, 0), (3, 2)), cv.Conic.ellipse((10, 0), (3, 2))], progress=False)
    assert d.certified
    bad = copy.deepcopy(d.to_json())
    bad["edges"] = []
    bad["delaunay_edges"] = []
    assert not cv.verify(bad).ok


def test_two_containers_without_the_edge_between_them_are_refused():
    """Two ellipses, each holding two circles: the edges around the circles are consistent on
    their own, and only the accounting at infinity sees the missing unbounded edge of the two
    ellipses (neither contains the other, so neither leads in every direction)."""
    s = [cv.Conic.ellipse((0, 0), (10, 6)), (2, 0, 1), (-3, 1, 1.5),
         cv.Conic.ellipse((40, 0), (10, 6)), (42, 0, 1), (37, 1, 1.5)]
    d = cv.voronoi(s, progress=False)
    assert d.certified, d.problems
    doc = d.to_json()
    bad = copy.deepcopy(doc)
    bad["edges"] = [e for e in bad["edges"] if sorted(e["sites"]) != [0, 3]]
    assert len(bad["edges"]) < len(doc["edges"])
    for t, e in enumerate(bad["edges"]):
        e["id"] = t
    bad["delaunay_edges"] = sorted({tuple(sorted(e["sites"])) for e in bad["edges"]})
    c = cv.verify(bad)
    assert not c.ok


def test_a_circle_poking_out_between_the_first_cell_centres_is_not_taken_as_nested():
    """A circle of radius 1/100 centred 9.995 from the centre of a circle of radius 10 reaches
    10.005 in the direction θ = 0, a boundary of the walk's first cells (centres at odd multiples
    of π/64, where h_small < h_big by about 0.007): the nesting walk must halve down to the cells
    where h_small > h_big (|θ| < 0.0316) and refuse; the same circle centred 9.98 (reaching 9.99)
    is nested.  The sites meet in the first case, so the hulls are not disjoint either."""
    from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
    from curvedvoronoi.runtime.voronoi.verify.hull_nesting import hulls_disjoint
    from curvedvoronoi.runtime.voronoi.verify.support import SupportTable

    for d, nested in ((9.995, False), (9.98, True)):
        assert (d + 0.01 < 10) is nested
        geoms = [site_geometry(cv.Conic.ellipse((0, 0), (10, 10))),
                 site_geometry(cv.Conic.ellipse((d, 0), (0.01, 0.01)))]
        problems = []
        assert hulls_disjoint(SupportTable(geoms), problems, 400000) is nested
        assert bool(problems) is not nested
