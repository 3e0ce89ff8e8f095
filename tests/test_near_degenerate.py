"""Regular polygons with float coordinates: vertex clusters far below any sample spacing.

A regular n-gon drawn with cos/sin vertices (or shapely's ``Point.buffer``) has float, i.e. exact
binary rational, coordinates: its sides are not exactly tangent to one circle, and the true
Voronoi diagram has n − 2 vertices within ~10⁻¹⁵ of the centre (times the coordinates' size),
joined by edges of that length (thesis §1.2: the diagram of the exact input).  The reference here
is independent of the library: every triple of sides is solved in mpmath at 60 digits (the point
equidistant from three lines, on their inner sides) and kept when every other side is farther —
the vertices of the minimisation diagram of the sides' distances, which is the medial axis of a
convex polygon.  Boost.Polygon on rounded integers is not a reference: rounding changes the
near-degenerate structure.
"""
from __future__ import annotations

import itertools
from types import SimpleNamespace

import mpmath
import numpy as np
import pytest
from flint import arb

import curvedvoronoi as cv
from curvedvoronoi.runtime.segments.certificate_convexity import settled_by_convexity
from curvedvoronoi.runtime.segments.certificate_curves import bisector_curve
from curvedvoronoi.runtime.segments.certificate_sites import SiteTable
from curvedvoronoi.runtime.segments.certificate_vertices import VertexProof
from curvedvoronoi.runtime.segments.elementary import POINT, SEGMENT



pytestmark = pytest.mark.mpmath_dps(60)


@pytest.fixture(autouse=True)
def _mpmath_digits():
    """60 digits for this module's references, restored after each test (another module's
    setting must not leak in, nor this one out)."""
    with mpmath.workdps(60):
        yield


def ngon(n, rot=0.3, scale=1.0, off=(0.0, 0.0)):
    ts = np.linspace(0, 2 * np.pi, n, endpoint=False) + rot
    return [(off[0] + scale * np.cos(t), off[1] + scale * np.sin(t)) for t in ts]


def _lines(pts):
    """Per side (p_k, p_k+1): (a, b, c) in mpmath with a x + b y + c > 0 inside, normalised, from
    the exact float coordinates."""
    out = []
    n = len(pts)
    area = sum(pts[k][0] * pts[(k + 1) % n][1] - pts[(k + 1) % n][0] * pts[k][1] for k in range(n))
    sgn = 1 if area > 0 else -1
    for k in range(n):
        (x0, y0), (x1, y1) = (mpmath.mpf(v) for v in pts[k]), (mpmath.mpf(v) for v in pts[(k + 1) % n])
        a, b = -(y1 - y0) * sgn, (x1 - x0) * sgn
        c = -(a * x0 + b * y0)
        N = mpmath.sqrt(a * a + b * b)
        out.append((a / N, b / N, c / N))
    return out


def reference_vertices(pts):
    """{frozenset of side indices: (x, y, r)}: the medial axis vertices of the convex polygon
    ``pts`` (counter-clockwise) inside it, from all triples of sides in mpmath; sides at the
    radius within 10⁻⁴⁰ (an exact tie) join the vertex."""
    L = _lines(pts)
    out = {}
    for tri in itertools.combinations(range(len(L)), 3):
        A = mpmath.matrix([[L[k][0], L[k][1], -1] for k in tri])
        rhs = mpmath.matrix([-L[k][2] for k in tri])
        try:
            x, y, r = mpmath.lu_solve(A, rhs)
        except ZeroDivisionError:
            continue
        if r <= 0:
            continue
        d = [L[k][0] * x + L[k][1] * y + L[k][2] for k in range(len(L))]
        if min(d) < r - mpmath.mpf(10) ** -40 * (1 + abs(x) + abs(y) + r):
            continue
        key = frozenset(k for k in range(len(L)) if d[k] <= r + mpmath.mpf(10) ** -40 * (1 + abs(x) + abs(y) + r))
        out[key] = (x, y, r)
    return out


def check_against_reference(pts, m):
    D = m.diagram
    E = D.elementary
    ref = reference_vertices(pts)
    P = [tuple(map(float, p)) for p in pts]
    side_of = {}
    for s in range(len(E)):
        if E.kind[s] == SEGMENT:
            a = (float(E.xy[int(E.ends[s, 0])][0]), float(E.xy[int(E.ends[s, 0])][1]))
            b = (float(E.xy[int(E.ends[s, 1])][0]), float(E.xy[int(E.ends[s, 1])][1]))
            for k in range(len(P)):
                if {a, b} == {P[k], P[(k + 1) % len(P)]}:
                    side_of[s] = k
    assert len(side_of) == len(P)
    got = {}
    for v in m.vertices:
        if v.radius > 0:
            got[frozenset(side_of[s] for s in v.sites)] = (v.x, v.y, v.radius)
    assert set(got) == set(ref)
    scale = 1 + max(abs(x) + abs(y) for x, y in P)
    for key, (x, y, r) in ref.items():
        gx, gy, gr = got[key]
        assert abs(gx - x) <= 1e-12 * scale and abs(gy - y) <= 1e-12 * scale and abs(gr - r) <= 1e-12 * scale
    # every corner has its bisector edge (between the two sides meeting there), toward the centre
    pairs = {tuple(sorted(side_of[s] for s in e.sites)) for e in m.edges if all(s in side_of for s in e.sites)}
    n = len(P)
    for k in range(n):
        assert tuple(sorted((k, (k + 1) % n))) in pairs
    # edges within their stated tolerance of the bisectors, no other side nearer (mpmath)
    L = _lines(pts)
    for e in m.edges:
        i, j = (side_of[s] for s in e.sites)
        for x, y in np.asarray(e.polyline)[:: max(1, len(e.polyline) // 8)]:
            d = [L[k][0] * x + L[k][1] * y + L[k][2] for k in range(n)]
            tol = 2 * e.tolerance + 1e-13 * scale
            assert abs(d[i] - d[j]) <= tol
            assert min(d) >= min(d[i], d[j]) - tol


@pytest.mark.parametrize("n", range(4, 13))
def test_regular_ngon_float_coordinates(n):
    # rotation 0: for even n opposite sides are parallel up to 10⁻¹⁶ (their bisector's origin is
    # their intersection, 10³² away: the certificate retries such an edge at 4 times its precision)
    for rot in (0.0, 0.3, 1.1):
        pts = ngon(n, rot)
        m = cv.medial_axis(pts)
        assert m.certified, m.problems[:3]
        check_against_reference(pts, m)


@pytest.mark.parametrize("scale, off", [(1000.0, (0.0, 0.0)), (1.0, (5e5, 5e5 / 3)), (1000.0, (5e5, 4e6))])
@pytest.mark.parametrize("n", [5, 6, 8, 11])
def test_regular_ngon_scales_and_offsets(n, scale, off):
    pts = ngon(n, 2.0, scale, off)
    m = cv.medial_axis(pts)
    assert m.certified, m.problems[:3]
    check_against_reference(pts, m)


@pytest.mark.parametrize("quad_segs", [4, 8])
@pytest.mark.parametrize("r, c", [(5.0, (0.0, 0.0)), (1.0, (0.1, 0.2)), (1000.0, (5e5, 4e6))])
def test_shapely_buffer(r, c, quad_segs):
    """16 and 32 sides (shapely's coordinates are mirror images in places: exact ties of degree > 3
    next to near ties); with 32 sides the perpendiculars at a side's ends are nearly parallel to the
    neighbours' (runtime/segments/parallel_rays.py)."""
    geometry = pytest.importorskip("shapely.geometry")
    pts = list(geometry.Point(*c).buffer(r, quad_segs).exterior.coords)[:-1]
    m = cv.medial_axis(geometry.Polygon(pts))
    assert m.certified, m.problems[:3]
    check_against_reference(pts, m)


def test_exact_integer_square_still_degree_four():
    m = cv.medial_axis([(0, 0), (2, 0), (2, 2), (0, 2)])
    assert m.certified
    centre = [v for v in m.vertices if v.radius > 0]
    assert len(centre) == 1 and len(centre[0].sites) == 4 and (centre[0].x, centre[0].y) == (1.0, 1.0)


def test_wrong_diagonal_is_rejected():
    """The float square's two centre vertices swapped for the other diagonal of the quadrilateral
    of normals (sites listed, positions moved to those triples' equidistant points): the
    certificate must refuse."""
    pts = ngon(4, 0.3)
    m = cv.medial_axis(pts)
    assert m.certified
    D = m.diagram
    cen = [v for v in D.vertices if v.radius > 0]
    assert len(cen) == 2
    a, b = (set(v.sites) for v in cen)
    shared = sorted(a & b)
    other = sorted(a ^ b)
    from curvedvoronoi.runtime.voronoi.structure import Diagram, DiagramEdge, DiagramVertex

    E = D.elementary
    L = {}
    for s in range(len(E)):
        if E.kind[s] == SEGMENT:
            (x0, y0), (x1, y1) = ((mpmath.mpf(float(c)) for c in E.xy[int(E.ends[s, k])]) for k in (0, 1))
            aa, bb = -(y1 - y0), x1 - x0
            N = mpmath.sqrt(aa * aa + bb * bb)
            L[s] = (aa / N, bb / N, -(aa * x0 + bb * y0) / N)
    new_v = []
    for keep in shared:
        tri = sorted(other + [keep])
        A = mpmath.matrix([[L[k][0], L[k][1], -1] for k in tri])
        x, y, r = mpmath.lu_solve(A, mpmath.matrix([-L[k][2] for k in tri]))
        new_v.append((tri, float(x), float(y), float(abs(r))))
    verts = [v for v in D.vertices if v.radius == 0]
    ids = {}
    out_v = []
    for v in verts:
        ids[v.id] = len(out_v)
        out_v.append(DiagramVertex(len(out_v), v.sites, v.x, v.y, v.radius, True))
    for tri, x, y, r in new_v:
        out_v.append(DiagramVertex(len(out_v), tuple(tri), x, y, r, True))
    assert len(out_v) == len(verts) + 2
    edges = []
    for e in D.edges:
        if all(x is None or x in ids for x in e.ends):
            edges.append(DiagramEdge(len(edges), e.sites, tuple(None if x is None else ids[x] for x in e.ends),
                                     False, e.polyline, e.tolerance))
    from curvedvoronoi.runtime.segments.certificate import verify_segments

    bad = Diagram(D.sites, out_v, edges, False, [], {})
    cert = verify_segments(bad)
    assert not cert.ok


# ------------------------------------------------------------------ the convexity rule, by hand
def _pr(h: float, half: float, kx: float = 0.0):
    """Two parallel segments y = 0 and y = 2 (the edge is the line y = 1, ρ = 1) and a point site
    k = (kx, 1 + h); the edge runs from x = −half to x = half (end vertices of radius 1)."""
    from curvedvoronoi.runtime.predicates.circles import Point
    from curvedvoronoi.runtime.sites.segment import Segment

    sites = [Point(-10, 0), Point(10, 0), Point(-10, 2), Point(10, 2), Point(kx, 1 + h),
             Segment((-10, 0), (10, 0)), Segment((10, 2), (-10, 2))]
    T = SiteTable(sites)
    vps = [VertexProof(True, arb(x), arb(1), arb(1), listed=frozenset({5, 6})) for x in (-half, half)]
    c = bisector_curve(T, 5, 6, vps, np.array([[-half, 1.0], [half, 1.0]]))
    ends = [("v", c.param(vp.x, vp.y), vp, k) for k, vp in enumerate(vps)]
    lo, hi = sorted(ends, key=lambda e: float(e[1].mid()))
    return SimpleNamespace(curve=c, T=T, i=5, j=6, skip=set()), lo, hi


@pytest.mark.parametrize("h, half, proved", [
    (1.2, 0.5, True),       # g = √(x² + 1.44) − 1 ≥ 0.2: the two tangents' zeros cross
    (0.95, 0.5, False),     # g(0) = −0.05 < 0 although g(±0.5) > 0
    (1.01, 5.0, False),     # g ≥ 0.01 > 0, but the tangents at ±5 do not cover the middle
])
def test_convexity_tangent_cases(h, half, proved):
    from curvedvoronoi.runtime.segments import certificate_convexity as cc

    pr, lo, hi = _pr(h, half)
    assert cc.convex_positive(pr.T, pr.curve, 4, lo, hi) is proved


def test_convexity_monotone_case():
    """A site whose margin only grows along the edge is proved from the end where it is least;
    one nearer than ρ at both ends is not."""
    from curvedvoronoi.runtime.segments import certificate_convexity as cc

    pr, _, _ = _pr(1.5, 0.5)
    vps = [VertexProof(True, arb(x), arb(1), arb(1), listed=frozenset({5, 6})) for x in (0.1, 0.6)]
    ends = [("v", pr.curve.param(vp.x, vp.y), vp, k) for k, vp in enumerate(vps)]
    lo, hi = sorted(ends, key=lambda e: float(e[1].mid()))
    assert cc.convex_positive(pr.T, pr.curve, 4, lo, hi)
    pr, _, _ = _pr(0.05, 0.5)         # growing along the edge, but negative at its start
    assert not cc.convex_positive(pr.T, pr.curve, 4, lo, hi)
    pr, lo, hi = _pr(0.4, 0.6)          # g(±0.6) = √0.52 − 1 < 0
    assert not cc.convex_positive(pr.T, pr.curve, 4, lo, hi)
    assert 4 not in settled_by_convexity(pr, lo, hi)


def test_convexity_tiny_edge_settles_near_ties():
    """An edge 10⁻¹² long with k 10⁻¹³ farther than ρ from its middle is settled (float pieces
    could not); with k 10⁻¹³ nearer it is not."""
    for h, want in ((1 + 1e-13, True), (1 - 1e-13, False)):
        pr, _, _ = _pr(h, 0.5, 0.3 + 5e-13)
        vps = [VertexProof(True, arb(x), arb(1), arb(1), listed=frozenset({5, 6})) for x in (0.3, 0.3 + 1e-12)]
        ends = [("v", pr.curve.param(vp.x, vp.y), vp, k) for k, vp in enumerate(vps)]
        lo, hi = sorted(ends, key=lambda e: float(e[1].mid()))
        assert (4 in settled_by_convexity(pr, lo, hi)) is want


def test_convexity_refuses_a_site_tied_along_the_edge():
    """A segment k collinear with j (y = 2, x in [20, 30]) is at distance exactly ρ = 1 all along
    the edge y = 1, x in [25, 28.125] (dyadic parameters: g_k' = 0 exactly in arb), and listed at
    both end vertices: g_k ≡ 0.  No tangent case applies (the edge is not an edge of the diagram)."""
    from curvedvoronoi.runtime.predicates.circles import Point
    from curvedvoronoi.runtime.segments import certificate_convexity as cc
    from curvedvoronoi.runtime.sites.segment import Segment

    sites = [Point(-10, 0), Point(40, 0), Point(-10, 2), Point(10, 2), Point(20, 2), Point(30, 2),
             Segment((-10, 0), (40, 0)), Segment((10, 2), (-10, 2)), Segment((20, 2), (30, 2))]
    T = SiteTable(sites)
    vps = [VertexProof(True, arb(x), arb(1), arb(1), listed=frozenset({6, 7, 8})) for x in (25, 28.125)]
    c = bisector_curve(T, 6, 7, vps, np.array([[25.0, 1.0], [28.125, 1.0]]))
    ends = sorted([("v", c.param(vp.x, vp.y), vp, k) for k, vp in enumerate(vps)], key=lambda e: float(e[1].mid()))
    assert not cc.convex_positive(T, c, 8, ends[0], ends[1])


def test_convexity_refuses_an_arc():
    """Inside an arc's circle its distance R − |x − c| is concave along the edge: at x = −0.5 the
    clearance is 0.28 and growing, at x = 0.5 it is −0.31 (the arc is nearer than ρ).  A tangent at
    the start would wrongly cover the edge; arcs are not tried."""
    from fractions import Fraction as F

    from curvedvoronoi.runtime.predicates.circles import Point
    from curvedvoronoi.runtime.segments import certificate_convexity as cc
    from curvedvoronoi.runtime.sites.arc import Arc
    from curvedvoronoi.runtime.sites.segment import Segment

    c, R = (F(-3, 10), F(11, 10)), F(3, 2)
    a = (c[0] + R * F(-143, 145), c[1] + R * F(-24, 145))       # at about −170°
    b = (c[0] + R * F(143, 145), c[1] + R * F(-24, 145))        # at about −10°
    sites = [Point(-10, 0), Point(40, 0), Point(-10, 2), Point(10, 2), Point(*a), Point(*b),
             Segment((-10, 0), (40, 0)), Segment((10, 2), (-10, 2)), Arc(c, R, a, b)]
    T = SiteTable(sites)
    vps = [VertexProof(True, arb(x), arb(1), arb(1), listed=frozenset({6, 7})) for x in (-0.5, 0.5)]
    curve = bisector_curve(T, 6, 7, vps, np.array([[-0.5, 1.0], [0.5, 1.0]]))
    ends = sorted([("v", curve.param(vp.x, vp.y), vp, k) for k, vp in enumerate(vps)], key=lambda e: float(e[1].mid()))
    X, Y = curve.xy(ends[1][1])
    assert T.distance(8, X, Y) < 1                                # the arc is nearer than ρ at x = 0.5
    assert not cc.convex_positive(T, curve, 8, ends[0], ends[1])


def _mp_distance(E, s, x, y):
    """mpmath distance from (x, y) to the closed elementary site s (a point or a segment)."""
    px, py = mpmath.mpf(x), mpmath.mpf(y)
    (ax, ay) = (mpmath.mpf(float(v)) for v in E.xy[int(E.ends[s, 0]) if E.kind[s] != POINT else s])
    if E.kind[s] == POINT:
        return mpmath.hypot(px - ax, py - ay)
    (bx, by) = (mpmath.mpf(float(v)) for v in E.xy[int(E.ends[s, 1])])
    dx, dy = bx - ax, by - ay
    t = min(max(((px - ax) * dx + (py - ay) * dy) / (dx * dx + dy * dy), 0), 1)
    return mpmath.hypot(px - ax - t * dx, py - ay - t * dy)


@pytest.mark.parametrize("n", [6, 8])
def test_regular_ngon_with_regular_hole(n):
    """A float n-gon with a concentric hole of the same angles: each outer side is parallel to an
    inner one up to rounding (a mid-parallel edge whose bisector meets at ~10¹⁶), and the hole's
    inside has a centre cluster.  Certified; every edge point equidistant from its two sites and
    no site nearer (mpmath distances to the closed sites)."""
    ts = np.linspace(0, 2 * np.pi, n, endpoint=False) + 0.3
    outer = [(np.cos(t), np.sin(t)) for t in ts]
    hole = [(0.3 * np.cos(t), 0.3 * np.sin(t)) for t in ts[::-1]]
    geometry = pytest.importorskip("shapely.geometry")
    m = cv.medial_axis(geometry.Polygon(outer, [hole]))
    assert m.certified, m.problems[:3]
    E = m.diagram.elementary
    assert len(m.edges) == 4 * n
    for e in m.edges:
        i, j = e.sites
        for x, y in np.asarray(e.polyline)[:: max(1, len(e.polyline) // 6)]:
            d = [_mp_distance(E, s, x, y) for s in range(len(E))]
            tol = 2 * e.tolerance + 1e-13
            assert abs(d[i] - d[j]) <= tol
            assert min(d) >= min(d[i], d[j]) - tol


@pytest.mark.parametrize("n", [6, 8, 12])
def test_points_on_a_float_circle_with_a_segment(n):
    """n point sites at cos/sin (not exactly co-circular) and a far segment (the segment route):
    the centre cluster is the Delaunay structure of the points, here checked against all triples
    of points in mpmath (circumcentre; every other point strictly outside the circle)."""
    from curvedvoronoi import Segment
    from curvedvoronoi.runtime.segments.construction import segment_voronoi

    ts = np.linspace(0, 2 * np.pi, n, endpoint=False) + 0.3
    pts = [(float(np.cos(t)), float(np.sin(t))) for t in ts]
    D = segment_voronoi(pts + [Segment((10.0, 10.0), (12.0, 11.0))])
    assert D.certified, D.problems[:3]
    P = [(mpmath.mpf(x), mpmath.mpf(y)) for x, y in pts]
    ref = set()
    for tri in itertools.combinations(range(n), 3):
        (ax, ay), (bx, by), (cx, cy) = (P[k] for k in tri)
        dd = 2 * (ax * (by - cy) + bx * (cy - ay) + cx * (ay - by))
        ux = ((ax ** 2 + ay ** 2) * (by - cy) + (bx ** 2 + by ** 2) * (cy - ay) + (cx ** 2 + cy ** 2) * (ay - by)) / dd
        uy = ((ax ** 2 + ay ** 2) * (cx - bx) + (bx ** 2 + by ** 2) * (ax - cx) + (cx ** 2 + cy ** 2) * (bx - ax)) / dd
        r2 = (ax - ux) ** 2 + (ay - uy) ** 2
        if all((P[k][0] - ux) ** 2 + (P[k][1] - uy) ** 2 > r2 for k in range(n) if k not in tri):
            ref.add(frozenset(tri))
    got = {frozenset(v.sites) for v in D.vertices if max(v.sites) < n}
    assert got == ref and len(ref) == n - 2
