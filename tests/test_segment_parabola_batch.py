"""Parabolic edges drawn many at once (:func:`runtime.segments.bisectors.parabola_polylines`):
every point is equidistant from the focus and the segment's line (the definition of the
bisector), the stated bound covers the true parabola between the polyline's points (dense
sampling of the closed-form parabola through its focus–directrix equation, solved independently
for each sample), and each row equals the same edge drawn alone."""
import numpy as np
import pytest

import curvedvoronoi as cv
from curvedvoronoi.runtime.segments.bisectors import parabola_polylines
from curvedvoronoi.runtime.segments.elementary import POINT, decompose


def _scene(seed):
    rng = np.random.default_rng(seed)
    pieces, rows = [], []
    for k in range(12):
        x0, y0 = 100 * k, int(rng.integers(-50, 50))
        length, lift = int(rng.integers(5, 60)), int(rng.integers(1, 40))
        pieces.append(cv.Segment((x0, y0), (x0 + length, y0 + int(rng.integers(-20, 20)))))
        pieces.append(cv.Point(x0 + int(rng.integers(0, length)), y0 + lift + 25))
    E = decompose(pieces)
    for s in range(E.n_points, len(E)):
        p = [q for q in range(E.n_points) if q not in E.ends[s] and abs(E.A[q, 0] - E.A[s, 0]) < 80][0]
        rows.append((p, s))
    return E, rows


def _on_parabola(E, p, s, u):
    """The point of the bisector over foot u: on the normal at f(u), at the height h solving
    |f + h n − P|² = h² (equidistance), h = |f − P|² / (2 n·(P − f))."""
    a, b, P = E.A[s], E.B[s], E.A[p]
    d = b - a
    n = np.array([-d[1], d[0]]) / np.hypot(*d)
    n = n if np.dot(P - a, n) > 0 else -n
    f = a + np.outer(u, d)
    h = np.sum((f - P) ** 2, axis=1) / (2 * ((P - f) @ n))
    return f + h[:, None] * n


@pytest.mark.parametrize("seed", [1, 2])
def test_parabolic_edges_at_once_are_exact_and_within_their_bound(seed):
    E, rows = _scene(seed)
    rng = np.random.default_rng(seed + 10)
    p, s = np.array([r[0] for r in rows]), np.array([r[1] for r in rows])
    u = np.sort(rng.uniform(0.02, 0.98, (len(rows), 2)), axis=1)
    P0 = np.array([_on_parabola(E, int(a), int(b), u[k, :1])[0] for k, (a, b) in enumerate(rows)])
    P1 = np.array([_on_parabola(E, int(a), int(b), u[k, 1:])[0] for k, (a, b) in enumerate(rows)])
    tol = 1e-3
    Q, start, bound = parabola_polylines(E, p, s, P0, P1, tol)
    polys = np.split(Q, start[1:])
    for k, (pp, ss) in enumerate(rows):
        poly = polys[k]
        assert E.kind[pp] == POINT and np.array_equal(poly[0], P0[k]) and np.array_equal(poly[-1], P1[k])
        # equidistant from the focus and the line: the bisector's definition
        a, b = E.A[ss], E.B[ss]
        d = b - a
        to_line = np.abs((poly - a) @ np.array([-d[1], d[0]])) / np.hypot(*d)
        to_focus = np.hypot(*(poly - E.A[pp]).T)
        assert np.max(np.abs(to_line - to_focus)) <= 1e-9 * (1 + np.max(to_focus))
        # the true arc between consecutive points stays within the bound of the chord
        foot = (poly - a) @ d / (d @ d)
        worst = 0.0
        for j in range(len(poly) - 1):
            X = _on_parabola(E, pp, ss, np.linspace(foot[j], foot[j + 1], 33))
            c, e = poly[j], poly[j + 1]
            w = e - c
            t = np.clip((X - c) @ w / (w @ w), 0, 1)
            worst = max(worst, float(np.max(np.hypot(*(c + t[:, None] * w - X).T))))
        assert worst <= bound[k]
        # the same edge drawn alone: the same points and bound
        Q1, _st, b1 = parabola_polylines(E, [pp], [ss], P0[k], P1[k], tol)
        assert np.array_equal(Q1, poly) and b1[0] == bound[k]
