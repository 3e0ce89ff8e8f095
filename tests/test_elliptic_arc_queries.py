"""Proximity queries on diagrams with elliptic arcs (thesis §1.1): ``Diagram.nearest``,
``site_distance`` and ``cells`` take the arcs' pieces (runtime/segments/geometry.EllipticArcGeometry),
with rigorous float bounds (runtime/segments/ellipse_pieces.piece_distance_bounds) and the endpoint
convention of §2.2 for points whose nearest point of a piece is proved to be its end.

Reference: the distance to an arc by 4001 parameter samples of the exact float data refined by a
golden-section search (numpy and mpmath; no library distance code), and, for the bounds, the same
in mpmath at 30 digits from the exact rational data."""
from __future__ import annotations

import math
from fractions import Fraction

import mpmath
import numpy as np
import pytest
import shapely

import curvedvoronoi as cv
from curvedvoronoi.runtime.segments.ellipse_pieces import PieceData, piece_distance_bounds
from curvedvoronoi.runtime.sites.elliptic_arc import EllipticArc

RING = [(4, 0), (3, 3), (0, 4), (-3, 2), (-3, -2), (0, -3), (3, -3)]


def _mp(v):
    return mpmath.mpf(v.numerator) / v.denominator


def reference_distance(arc, q, dps=30):
    """min over φ of |e(φ) − q| for the closed arc, in mpmath from its exact data: 400 samples,
    then a golden-section search around the best one (the ends included)."""
    with mpmath.workdps(dps):
        c, M, N = ([_mp(v) for v in p] for p in (arc.c, arc.M, arc.N))
        p0 = mpmath.atan2(_mp(arc.ua[1]), _mp(arc.ua[0]))
        span = (mpmath.atan2(_mp(arc.ub[1]), _mp(arc.ub[0])) - p0) % (2 * mpmath.pi)
        qx, qy = mpmath.mpf(float(q[0])), mpmath.mpf(float(q[1]))

        def f(t):
            x = c[0] + mpmath.cos(t) * M[0] + mpmath.sin(t) * N[0] - qx
            y = c[1] + mpmath.cos(t) * M[1] + mpmath.sin(t) * N[1] - qy
            return mpmath.sqrt(x * x + y * y)

        n = 400
        ts = [p0 + span * k / n for k in range(n + 1)]
        vals = [f(t) for t in ts]
        k = min(range(n + 1), key=vals.__getitem__)
        a, b = ts[max(k - 1, 0)], ts[min(k + 1, n)]
        g = (mpmath.sqrt(5) - 1) / 2
        for _ in range(90):
            m1, m2 = b - g * (b - a), a + g * (b - a)
            if f(m1) < f(m2):
                b = m2
            else:
                a = m1
        return min(f((a + b) / 2), vals[0], vals[-1])


def float_reference(arc, Q):
    """The same in floats for many points: 4001 samples and a vectorised golden-section search."""
    (cx, cy), (Mx, My), (Nx, Ny), p0, p1 = arc.float_data()
    Q = np.asarray(Q, float)

    def f(t):
        return np.hypot(cx + np.cos(t) * Mx + np.sin(t) * Nx - Q[:, :1], cy + np.cos(t) * My + np.sin(t) * Ny - Q[:, 1:])

    ts = np.linspace(p0, p1, 4001)
    vals = f(ts[None, :])
    k = np.argmin(vals, axis=1)
    a, b = ts[np.maximum(k - 1, 0)][:, None], ts[np.minimum(k + 1, 4000)][:, None]
    g = (math.sqrt(5) - 1) / 2
    for _ in range(60):
        m1, m2 = b - g * (b - a), a + g * (b - a)
        left = f(m1) < f(m2)
        b, a = np.where(left, m2, b), np.where(left, a, m1)
    return np.minimum(f((a + b) / 2)[:, 0], vals.min(axis=1))


def reference_nearest(sites, Q):
    """(index, margin) of the nearest site of each row: points by hypot, arcs by float_reference
    (an arc at its end point's distance, to 10⁻⁹, left out: the convention of §2.2)."""
    D = np.empty((len(Q), len(sites)))
    points = {}
    for k, s in enumerate(sites):
        if not isinstance(s, EllipticArc):
            D[:, k] = np.hypot(Q[:, 0] - float(s.cx), Q[:, 1] - float(s.cy))
            points[(Fraction(str(s.cx)), Fraction(str(s.cy)))] = k
    for k, s in enumerate(sites):
        if isinstance(s, EllipticArc):
            D[:, k] = float_reference(s, Q)
            for end in (s.a, s.b):     # §2.2: where an end is the arc's nearest point, the end's site wins
                j = points.get(tuple(end))
                if j is not None:
                    D[np.abs(D[:, k] - D[:, j]) <= 1e-9 * (1 + D[:, j]), k] = np.inf
    order = np.sort(D, axis=1)
    return np.argmin(D, axis=1), order[:, 1] - order[:, 0]


@pytest.fixture(scope="module")
def diagram():
    arc = cv.Arc.elliptic((0, 0), (2, 0), "1/2", 0.2, 2.5)          # two pieces, a joint at (0, 1)
    return cv.voronoi([arc] + RING, certify=False)


def test_piece_bounds_enclose_the_distance():
    rng = np.random.default_rng(7)
    for _ in range(8):
        M = (int(rng.integers(1, 9)), int(rng.integers(-5, 6)))
        arc = cv.Arc.elliptic((int(rng.integers(-5, 5)), int(rng.integers(-5, 5))), M, f"{rng.integers(1, 9)}/10",
                              float(rng.uniform(0, 3)), float(rng.uniform(3.2, 6)))
        for piece in arc.pieces():
            a = np.array([float(piece.a[0]), float(piece.a[1])])
            Q = np.vstack([a + rng.normal(size=(2, 2)) * 10.0 ** e for e in (-6, -2, 0, 3)])
            lo, hi = piece_distance_bounds(PieceData.of(piece), Q)
            for q, l, h in zip(Q, lo, hi):
                d = reference_distance(piece, q)
                assert l <= d <= h, (piece, q, l, float(d), h)
                assert h - l <= 1e-6 * float(d) + 1e-5     # near the arc: ≈ √(L₂h²/8)


def test_the_interval_bound_holds_on_a_coarse_grid():
    """The inequality every lower bound stands on: on a grid of step h, min f over an interval ≥
    its smaller end value − L₂h²/8 with L₂ = 2|A| + 2|B| + 2|b² − a²| (f'' at most L₂).  Checked
    on 65-point grids against 400 samples of each interval; some intervals hold an interior minimum
    where the bound is within a factor 2 of the true gap, so a bound 10 times smaller fails."""
    from curvedvoronoi.runtime.segments.ellipse_pieces import _coords, _f, _interval_lower, _second_derivative_bound

    rng = np.random.default_rng(11)
    cases = []
    for _ in range(30):
        M = (int(rng.integers(1, 9)), int(rng.integers(-5, 6)))
        arc = cv.Arc.elliptic((0, 0), M, f"{rng.integers(1, 9)}/10", 0.1, 1.4)
        cases.append((arc, np.array([float(arc.a[0]), float(arc.a[1])]) * rng.uniform(0.2, 3) + rng.normal(size=2)))
    for M, k in (((4, 0), "1/4"), ((3, 4), "1/5"), ((6, -1), "1/3")):
        # q near the centre on the major axis, q − c = (1 − k²) cos φ* · M: f'(φ*) = 0 at the midpoint
        # φ* of the grid's interval nearest π/2 − 0.2, where f'' ≈ 1.9(a² − b²) against
        # L₂ ≈ 2.4(a² − b²): the (b² − a²) term of L₂ is what bounds it
        arc = cv.Arc.elliptic((0, 0), M, k, 0.9, math.pi / 2)
        grid = np.linspace(*arc.parameters(), 65)
        mids = (grid[:-1] + grid[1:]) / 2
        phi = mids[np.argmin(np.abs(mids - (math.pi / 2 - 0.2)))]
        cases.append((arc, (1 - float(Fraction(k)) ** 2) * math.cos(phi) * np.array(M, float)))
    tight = 0
    for arc, q in cases:
        P = PieceData.of(arc.pieces()[0])
        W2, A, B, a2, b2 = _coords(P, [q])
        L2 = _second_derivative_bound(A, B, a2, b2)
        grid = np.linspace(P.phi0, P.phi1, 65)
        h = float(np.max(np.diff(grid)))
        lb = _interval_lower(_f(W2[:, None], A[:, None], B[:, None], a2, b2, grid[None, :]), L2, np.array([h]))[0]
        for k in range(64):
            t = np.linspace(grid[k], grid[k + 1], 401)
            true_min = _f(W2, A, B, a2, b2, t).min()
            assert lb[k] <= true_min + 1e-12 * (1 + abs(true_min)), (arc, q, k)
            ends = min(_f(W2, A, B, a2, b2, grid[k:k + 2]))
            tight += ends - true_min > 0.1 * (ends - lb[k])
    assert tight >= 5


def test_near_ties_of_a_piece_and_a_point_are_decided_by_balls(diagram):
    """Query points where the piece is nearer than the point site (4, 0) by ±3·10⁻¹⁴ (the float
    reference is good to ~10⁻¹⁵): the float bounds (rounding ~10⁻¹³ here) cannot separate them,
    the balls can; the answer is the nearer one, proved."""
    k = next(k for k, s in enumerate(diagram.sites) if isinstance(s, EllipticArc) and s.parameters()[0] < 0.3)
    j = next(j for j, s in enumerate(diagram.sites) if not isinstance(s, EllipticArc) and (s.cx, s.cy) == (4, 0))
    arc = diagram.sites[k]
    S = np.array([4.0, 0.0])
    for y in (1.0, 1.2):            # above the normal at the start (1.96, 0.2): the foot is inside
        for delta, want in ((3e-14, k), (-3e-14, j)):
            lo, hi = 2.0, 4.0               # d(q, point) − d(q, arc) − δ changes sign along y = const
            for _ in range(200):
                x = (lo + hi) / 2
                q = np.array([[x, y]])
                g = np.hypot(*(q[0] - S)) - float(float_reference(arc, q)[0]) - delta
                lo, hi = (x, hi) if g > 0 else (lo, x)
            q = np.array([[lo, y]])
            lo_b, hi_b = diagram.site_distance(q, [k, j], bounds=True)
            assert lo_b[0, 0] < hi_b[0, 1] and lo_b[0, 1] < hi_b[0, 0]       # a near tie for the floats
            got = diagram.nearest(q)
            assert got.proved[0] and got.index[0] == want, (y, delta, got)


def test_nearest_equals_the_brute_force_reference(diagram):
    Q = np.random.default_rng(3).uniform(-6, 6, size=(400, 2))
    got = diagram.nearest(Q)
    want, margin = reference_nearest(diagram.sites, Q)
    clear = margin > 1e-6
    assert clear.sum() >= 390
    assert got.proved[clear].all()
    assert (got.index[clear] == want[clear]).all()
    pieces = [k for k, s in enumerate(diagram.sites) if isinstance(s, EllipticArc)]
    assert np.isin(got.index, pieces).sum() >= 20          # the arcs are answered, not only the points
    d = diagram.site_distance(Q)
    for k in pieces:
        assert np.allclose(d[:, k], float_reference(diagram.sites[k], Q), rtol=1e-9, atol=1e-12)


def test_beyond_an_end_the_end_point_is_the_nearest_site(diagram):
    """On the outer normal at the arc's start e(0.2), beyond it, the nearest point of the closed
    piece is its end: a tie of the piece and the end's point site, given to the point (§2.2)."""
    k = next(k for k, s in enumerate(diagram.sites) if isinstance(s, EllipticArc) and s.parameters()[0] < 0.3)
    piece = diagram.sites[k]
    end = next(j for j, s in enumerate(diagram.sites) if not isinstance(s, EllipticArc)
               and (Fraction(str(s.cx)), Fraction(str(s.cy))) == tuple(piece.a))
    (cx, cy), M, N, p0, _p1 = piece.float_data()
    e = np.array([cx + math.cos(p0) * M[0] + math.sin(p0) * N[0], cy + math.cos(p0) * M[1] + math.sin(p0) * N[1]])
    t = -math.sin(p0) * np.array(M) + math.cos(p0) * np.array(N)
    normal = np.array([t[1], -t[0]]) / np.hypot(*t)                # outward for a counter-clockwise arc
    Q = e + np.outer([0.05, 0.2, 0.5], normal) + np.outer([-0.05, -0.1, -0.2], t / np.hypot(*t))
    got = diagram.nearest(Q)
    assert got.proved.all() and (got.index == end).all(), got


def test_cells_tile_the_clip_box_and_hold_their_nearest_points(diagram):
    box = (-6, -6, 6, 6)
    cells = diagram.cells(clip=box)
    assert abs(sum(c.area for c in cells) - 144) < 1e-6
    assert shapely.union_all(cells).area == pytest.approx(144, abs=1e-6)
    for k, s in enumerate(diagram.sites):
        if isinstance(s, EllipticArc):
            assert cells[k].area > 0.5
    Q = np.random.default_rng(5).uniform(-6, 6, size=(300, 2))
    want, margin = reference_nearest(diagram.sites, Q)
    for q, w, m in zip(Q, want, margin):
        if m > 1e-2:
            assert cells[w].buffer(1e-9).contains(shapely.Point(*q)), (q, w)


def test_inserting_into_a_diagram_with_elliptic_arcs_rebuilds_it():
    arc = cv.Arc.elliptic((0, 0), (2, 0), "1/2", 0.2, 1.3)
    d = cv.voronoi([arc] + RING[:4], certify=False)
    e = d.insert((-3, -3), certify=True)
    assert e.stats["update"].startswith("rebuild (an insertion into a diagram with pieces other than")
    batch = cv.voronoi([arc] + RING[:4] + [(-3, -3)], certify=True)
    assert e.certified == batch.certified
    assert sorted(e.delaunay_edges()) == sorted(batch.delaunay_edges())


def test_an_exact_tie_with_a_point_that_is_not_an_end_stays_a_tie():
    """q = (0, −1/4) on the minor axis of x²/4 + y² = 1, whose vertex (0, 1) (the joint of the arc's
    two pieces, not a site) is its nearest point on the arc (radius of curvature 4): d = 5/4, and
    the point site (0, −3/2) is at 5/4 too.  The distances cannot be told apart, and no end of a
    piece is that point: an undecided tie, never a proved answer."""
    arc = cv.Arc.elliptic((0, 0), (2, 0), "1/2", 0.2, 2.5)
    d = cv.voronoi([arc, (0, -1.5), (4, 0), (-4, 1)], certify=False)
    got = d.nearest(np.array([[0.0, -0.25], [0.0, 0.25]]))
    j = next(j for j, s in enumerate(d.sites) if not isinstance(s, EllipticArc) and Fraction(str(s.cy)) == Fraction(-3, 2))
    assert not got.proved[0] and got.index[0] == -1 and j in got.ties[0], got
    assert len(got.ties[0]) >= 2 and any(isinstance(d.sites[t], EllipticArc) for t in got.ties[0])
    # (0, 1/4): the two pieces at 3/4 through their common joint, on the joint's normal, their edge
    assert not got.proved[1] and all(isinstance(d.sites[t], EllipticArc) for t in got.ties[1])


def test_bounding_boxes_hold_the_arcs_extreme_points():
    """The query index prunes by the discs of these boxes, so they must hold the whole curve: the
    circular arc from −10° to 10° of radius 64 reaches x = 64 at 0° (between samples 0.87° apart),
    the elliptic piece from 0.2 to 1.3 of (x/2)² + y² = 1 has its extremes at its ends, and a
    half ellipse from −π/2 to π/2 reaches x = 2 at its major vertex; against dense samples."""
    from curvedvoronoi.runtime.segments.geometry import ArcGeometry, EllipticArcGeometry

    g = ArcGeometry(cv.Arc.circular((0, 0), 64, -10, 10))
    assert g.bounding_box()[2] >= 64
    for geom in (g, ArcGeometry(cv.Arc.circular((3, -2), 5, 100, 350)),
                 EllipticArcGeometry(cv.Arc.elliptic((0, 0), (2, 0), "1/2", 0.2, 1.3)),
                 EllipticArcGeometry(cv.Arc.elliptic((1, 1), (3, 4), "1/3", -math.pi / 2, math.pi / 2))):
        x0, y0, x1, y1 = geom.bounding_box()
        P = geom.samples(1e-4)
        assert (P[:, 0] >= x0).all() and (P[:, 0] <= x1).all() and (P[:, 1] >= y0).all() and (P[:, 1] <= y1).all()
        if not (isinstance(geom, EllipticArcGeometry) and geom.exact.M[1] != 0):   # (rotated frames: a looser box)
            assert max(P[:, 0].min() - x0, x1 - P[:, 0].max(), P[:, 1].min() - y0, y1 - P[:, 1].max()) < 1e-6
    x0, y0, x1, y1 = EllipticArcGeometry(cv.Arc.elliptic((0, 0), (2, 0), "1/2", -math.pi / 2, math.pi / 2)).bounding_box()
    assert x1 >= 2 and y0 <= -1 and y1 >= 1 and x0 <= 0 < x0 + 1e-12
