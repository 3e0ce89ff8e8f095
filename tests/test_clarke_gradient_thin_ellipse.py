"""The Clarke range of the distance from inside a thin ellipse (10 × 1, A/B = 10: its boundary point
moves at speed up to A = 10 per unit of parameter), on discs near the boundary and across the
medial axis (runtime/voronoi/verify/clarke_gradient.py, ``clarke_normal_range``): every
(q − p)/|q − p| with q in the disc and p a nearest point of q has its component along n in the
range.  The parameter intervals dropped as too far from the disc (|p̃ − Q| − A·h > hi + 2R) are
where a smaller allowance A·h/2 would drop an interval that holds the feet of the disc's far side:
discs whose feet spread over several intervals (R up to 0.45, lo > 2R, the feet near the minor vertex where
the speed is A).  The feet come from dense sampling of the boundary, not from the verifier."""
import numpy as np
import pytest

import curvedvoronoi as cv
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify.clarke_gradient import clarke_normal_range
from curvedvoronoi.runtime.voronoi.verify.site_table import SiteTable

A, B = 10.0, 1.0
T_ = np.linspace(0, 2 * np.pi, 400000, endpoint=False)
BX, BY = A * np.cos(T_), B * np.sin(T_)


@pytest.mark.parametrize("centre,R", [((0.5, 0.4), 0.28), ((-2.0, -0.2), 0.38), ((0.0, 0.0), 0.45)])
def test_the_range_holds_the_feet_of_every_point_of_the_disc(centre, R):
    T = SiteTable([site_geometry(cv.Conic.ellipse((0, 0), (A, B)))], 11.0)
    Qc = np.array([centre])
    V = T.evaluate(Qc, [0])
    rng = np.random.default_rng(1)
    rr = R * np.sqrt(rng.random(150))
    ph = 2 * np.pi * rng.random(150)
    q = Qc + np.column_stack([rr * np.cos(ph), rr * np.sin(ph)])
    q = np.vstack([q, Qc + R * np.column_stack([np.cos(ph[:60]), np.sin(ph[:60])])])
    k = np.array([np.hypot(qq[0] - BX, qq[1] - BY).argmin() for qq in q])
    g = q - np.column_stack([BX[k], BY[k]])
    g /= np.hypot(*g.T)[:, None]
    decided = 0
    for ang in np.linspace(0, np.pi, 9):
        n = np.array([[np.cos(ang), np.sin(ang)]])
        lo, hi, ok = clarke_normal_range(T, Qc, [0], V.lo, V.hi, R, n, V.inner)
        if not ok[0]:
            continue
        decided += 1
        val = g @ n[0]
        # sampled feet within ~1.6e-4 of a nearest point: the direction within ~1e-3 at depth ≥ 0.15
        assert lo[0] - 2e-3 <= val.min() and val.max() <= hi[0] + 2e-3, (centre, ang, lo, hi, val.min(), val.max())
    assert decided >= 5          # the disc lies inside with lo > 2R: the range is given
