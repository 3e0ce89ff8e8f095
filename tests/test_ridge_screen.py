"""The screen of ridge crossings (runtime/voronoi/verify/medial_corners.py, :func:`may_cross_ridges`):
where it says a polyline crosses no ridge of an ellipse of its pair, :func:`ridge_crossings`
finds none, so the verifier may skip the corners' enclosure (and the refusal of a polyline that
cuts a corner) there.  Checked against ridge_crossings on random polylines near random rotated
ellipses (some crossing the ridge on one side of the centre only, some off it), with points,
circles and pairs of one ellipse mixed in, and on a closed polyline around a point nested near
the end of a ridge (its crossings all on one side of the centre)."""
import numpy as np

import curvedvoronoi as cv
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify.medial_corners import may_cross_ridges, ridge_crossings
from curvedvoronoi.runtime.voronoi.verify.site_table import SiteTable


def _table(sites):
    return SiteTable([site_geometry(s) for s in sites], 100.0)


def test_the_screen_keeps_every_polyline_that_crosses_a_ridge():
    rng = np.random.default_rng(11)
    n = 24
    sites = [cv.Conic.ellipse((float(x), float(y)), (float(a), float(a * q)), rotation=(float(np.cos(t)), float(np.sin(t))))
             for x, y, a, q, t in zip(rng.uniform(-50, 50, n), rng.uniform(-50, 50, n), rng.uniform(1, 10, n),
                                      rng.uniform(0.2, 0.95, n), rng.uniform(0, 3, n))]
    sites += [cv.Point(3, 4), cv.Circle.from_radius(-20, 7, 2)]          # a point and a circle: no ridge
    table = _table(sites)
    pairs, polys = [], []
    for _ in range(4000):
        h, k = (int(v) for v in rng.integers(len(sites), size=2))
        c = np.array([table.cx[h], table.cy[h]]) + rng.normal(0, rng.choice([1.0, 5.0, 20.0]), 2)
        pairs.append((k, h) if rng.random() < 0.5 else (h, k))
        polys.append(c + np.cumsum(rng.normal(0, rng.choice([0.1, 1.0, 5.0]), (int(rng.integers(2, 8)), 2)), axis=0))
    keep = may_cross_ridges(table, pairs, polys)
    crossing = [bool(ridge_crossings(table, p, P)) for p, P in zip(pairs, polys)]
    assert sum(crossing) > 100 and sum(not k for k in keep) > 1000      # both kinds are there
    assert all(k for k, c in zip(keep, crossing) if c)


def test_a_loop_around_a_point_near_the_end_of_a_ridge():
    # ellipse x²/100 + y²/25 = 1, ridge |X| < 7.5; a small loop around (6, 0) crosses it twice, right
    # of the centre only
    table = _table([cv.Conic.ellipse((0, 0), (10, 5)), cv.Point(6, 0)])
    t = np.linspace(0, 2 * np.pi, 40)
    loop = np.column_stack([6 + 0.8 * np.cos(t), 0.5 * np.sin(t)])
    assert len(ridge_crossings(table, (0, 1), loop)) == 2
    off = loop + [0.0, 3.0]                     # the same loop above the axis
    assert not ridge_crossings(table, (0, 1), off)
    assert may_cross_ridges(table, [(0, 1), (1, 0), (0, 1)], [loop, loop, off]) == [True, True, False]


def test_a_crossing_just_inside_the_end_of_a_ridge_is_kept():
    """The ellipse x²/16 + y²/4 = 1 has its ridge (the centres of curvature of its boundary's
    nearest points) on y = 0 for |x| ≤ 4 − 4/4 = 3.  A segment crossing it at x = 3 − 10⁻⁹, whose
    bounding box meets the ridge's only in the last 10⁻⁹ of it, is kept by the screen."""
    table = _table([cv.Conic.ellipse((0.0, 0.0), (4.0, 2.0)), cv.Circle.from_radius(0, 40, 0)])
    P = np.array([[3 - 1e-9, -1.0], [3 - 1e-9, 1.0]])
    assert ridge_crossings(table, (0, 1), P)
    assert may_cross_ridges(table, [(0, 1)], [P]) == [True]
