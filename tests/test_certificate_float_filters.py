"""The float filters of the segment certificate hold the exact values they stand for.

* :func:`runtime.segments.certificate_float_bounds.bounds_at`: lo ≤ d ≤ hi for the distance d
  from q to a point, a segment or a circular arc (mpmath at 50 digits from the exact rational
  sites), at random points near the sites and at their ends, and the bounds are tight.
* :meth:`runtime.segments.certificate_sites.SiteTable.near_in`: every site within the radius
  (mpmath distance) is among the returned ones, from a pool or not.
* :func:`runtime.segments.certificate_hull.convex_hull` (float orientation filter): on nearly
  collinear rational points the result is the strict convex hull (every turn strictly left in
  rationals, every input point on the inner side of every hull edge, hull vertices among the
  inputs).
"""
from __future__ import annotations

import random
import sys
from fractions import Fraction as F
from pathlib import Path

import mpmath as mp
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))

import curvedvoronoi as cv  # noqa: E402
from curvedvoronoi.runtime.segments.certificate_float_bounds import bounds_at  # noqa: E402
from curvedvoronoi.runtime.segments.certificate_hull import convex_hull  # noqa: E402
from curvedvoronoi.runtime.segments.certificate_sites import ARC, POINT, SiteTable  # noqa: E402
from curvedvoronoi.runtime.segments.construction import segment_voronoi  # noqa: E402
from scenes import random_arcs, random_segments  # noqa: E402

pytestmark = pytest.mark.mpmath_dps(50)


def _mpf(v):
    v = F(v)
    return mp.mpf(v.numerator) / v.denominator


def _distance(T, k, q):
    """The distance from q (floats) to the closed site k, from its exact data in mpmath."""
    qx, qy = mp.mpf(q[0]), mp.mpf(q[1])
    ax, ay = map(_mpf, T.a[k])
    if T.kind[k] == POINT:
        return mp.hypot(qx - ax, qy - ay)
    bx, by = map(_mpf, T.b[k])
    if T.kind[k] == ARC:
        cx, cy = map(_mpf, T.cen[k])
        rho = _mpf(T.rad[k])
        ang = lambda x, y: mp.atan2(y - cy, x - cx)  # noqa: E731
        span = (ang(bx, by) - ang(ax, ay)) % (2 * mp.pi)
        at = (ang(qx, qy) - ang(ax, ay)) % (2 * mp.pi)
        if at <= span:
            return abs(mp.hypot(qx - cx, qy - cy) - rho)
        return min(mp.hypot(qx - ax, qy - ay), mp.hypot(qx - bx, qy - by))
    dx, dy = bx - ax, by - ay
    t = min(max(((qx - ax) * dx + (qy - ay) * dy) / (dx * dx + dy * dy), 0), 1)
    return mp.hypot(qx - ax - t * dx, qy - ay - t * dy)


def _tables():
    segs = segment_voronoi([cv.Segment(*s) for s in random_segments(25, 4)], certify=False)
    arcs = segment_voronoi(random_arcs(16, 3), certify=False)
    return [SiteTable(segs.sites), SiteTable(arcs.sites)]


def _queries(T, rng, k):
    """Points near site k: its ends exactly, and random points around its bounding disc."""
    ax, ay = T.float_rows[k][:2]
    bx, by = T.float_rows[k][2:4]
    mx, my = float(T.mid[k, 0]), float(T.mid[k, 1])
    h = float(T.half[k]) + 1.0
    out = [(ax, ay), (bx, by), (mx, my)]
    out += [(mx + rng.uniform(-2 * h, 2 * h), my + rng.uniform(-2 * h, 2 * h)) for _ in range(6)]
    return out


def test_scalar_float_bounds_hold_the_exact_distance():
    rng = random.Random(7)
    checked = 0
    for T in _tables():
        kinds = set()
        for k in range(T.n):
            for q in _queries(T, rng, k):
                b = bounds_at(T, [k], q[0], q[1])
                assert b is not None
                lo, hi = b[0][0], b[1][0]
                d = _distance(T, k, q)
                assert mp.mpf(lo) <= d <= mp.mpf(hi), (k, q, lo, float(d), hi)
                assert hi - lo <= 1e-12 * T.scale
                kinds.add(T.kind[k])
                checked += 1
        assert POINT in kinds
    assert checked > 300


def test_near_in_keeps_every_site_within_the_radius():
    rng = random.Random(11)
    for T in _tables():
        xs, ys = T.mid[:, 0], T.mid[:, 1]
        for _ in range(30):
            px, py = rng.uniform(xs.min(), xs.max()), rng.uniform(ys.min(), ys.max())
            pool = T.pool(px, py, 40.0)
            for _ in range(5):
                qx, qy = px + rng.uniform(-10, 10), py + rng.uniform(-10, 10)
                radius = rng.uniform(0.5, 25.0)
                got = set(T.near_in(pool, qx, qy, radius))
                want = {k for k in range(T.n) if _distance(T, k, (qx, qy)) <= radius}
                assert want <= got


@pytest.mark.parametrize("seed", range(6))
def test_hull_of_nearly_collinear_rationals_is_the_strict_convex_hull(seed):
    rng = random.Random(seed)
    big = 10 ** rng.choice((0, 6, 15))
    pts = [(F(k * big) + F(rng.randint(-1, 1), 10 ** 17), F(2 * k * big) + F(rng.randint(-1, 1), 10 ** 17))
           for k in range(40)]
    pts += [(F(rng.randint(0, 39) * big), F(rng.randint(0, 78) * big)) for _ in range(5)]
    H = convex_hull(pts)

    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    assert set(H) <= set(pts)
    n = len(H)
    assert n >= 3
    for m in range(n):
        assert cross(H[m], H[(m + 1) % n], H[(m + 2) % n]) > 0
        for p in pts:
            assert cross(H[m], H[(m + 1) % n], p) >= 0
