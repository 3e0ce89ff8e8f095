"""Pictures: the window fits the sites, polylines are clipped to it, nothing crashes far away
(runtime/voronoi/plot.py)."""
from __future__ import annotations

import math

import numpy as np
import pytest

pytest.importorskip("matplotlib", reason="the picture needs matplotlib (test extra)")


def test_clip_polyline_hand_computed():
    from curvedvoronoi.runtime.voronoi.plot import clip_polyline

    w = (0.0, 1.0, 0.0, 1.0)
    # a horizontal line through the unit square: cut at x = 0 and x = 1
    assert np.allclose(clip_polyline([[-1, 0.5], [2, 0.5]], w), [[0, 0.5], [1, 0.5]])
    # leaves through the corner (1, 1), comes back through y = 1 at x = 3 − 2.5·(2/2.1)
    P = clip_polyline([[0.2, 0.2], [0.5, 0.5], [2, 2], [3, 3], [0.5, 0.9]], w)
    assert np.allclose(P[:3], [[0.2, 0.2], [0.5, 0.5], [1, 1]]) and np.isnan(P[3]).all()
    assert np.allclose(P[4:], [[3 - 2.5 * 2 / 2.1, 1], [0.5, 0.9]])
    assert len(clip_polyline([[2, 2], [3, 3]], w)) == 0
    assert len(clip_polyline([[1e300, 0], [-1e300, 1e-300]], w)) == 2   # far ends: the crossing only


def test_window_fits_points_and_an_unbounded_sites_vertex():
    import curvedvoronoi as cv
    from curvedvoronoi.runtime.voronoi.plot import fit_window

    sites = [cv.Point(0, 0), cv.Point(4, 0), cv.Conic.parabola(vertex=(30, 40), p=1, rotation=(0, 1))]
    d = cv.Diagram(sites, [], [])
    x0, x1, y0, y1 = fit_window(d)
    for x, y in ((0, 0), (4, 0), (30, 40), (30, 40.5)):      # the points, the parabola's vertex and focus
        assert x0 < x <= x1 and y0 < y <= y1
    assert x1 - x0 == pytest.approx(y1 - y0) and x1 - x0 < 2 * 42


def test_plot_window_parameter_and_far_vertex_arrow(tmp_path):
    import curvedvoronoi as cv

    # three unit circles nearly in a row: the vertex is the circumcentre of the centres, x = 5 and
    # 25 + y² = 15² + (y − 0.3)², so y = 200.09 / 0.6 ≈ 333.5, far above the window
    d = cv.voronoi([(0, 0, 1), (10, 0, 1), (20, 0.3, 1)], certify=False)
    (v,) = d.vertices
    assert v.x == pytest.approx(5) and v.y == pytest.approx(200.09 / 0.6)
    fig = d.plot(tmp_path / "a.png", window=(-5, 25, -15, 15))
    ax = fig.axes[0]
    assert ax.get_xlim() == (-5, 25) and ax.get_ylim() == (-15, 15)
    arrows = [t for t in ax.texts if getattr(t, "arrow_patch", None) is not None]
    assert len(arrows) == 1
    tip = arrows[0].xy
    assert -5 <= tip[0] <= 25 and 14 < tip[1] <= 15                # on the top border
    assert math.atan2(tip[1] - 0, tip[0] - 10) == pytest.approx(math.atan2(v.y, v.x - 10), abs=1e-9)
    with pytest.raises(ValueError, match="xmin < xmax"):
        d.plot(tmp_path / "b.png", window=(1, 0, 0, 1))
