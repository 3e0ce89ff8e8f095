"""Degenerate inputs with closed-form diagrams (issue 30): grids, collinear and co-circular points,
co-circular circles, sites tangent to one line, a symmetric grid of identical ellipses.

Contract under test (DESIGN.md §7 "Degenerate vertices"): a Voronoi vertex may have k ≥ 3 sites,
decided exactly on the input's rational values; ``vertex.sites`` lists them counter-clockwise by
the angle of their contact point with the empty circle seen from the vertex, rotated so that the
smallest index comes first; ``vertex.degree == len(vertex.sites)``; ``delaunay_edges()`` lists the
pairs sharing a Voronoi edge of positive length (a square's diagonals are not Delaunay edges).

Every expectation below is written from the geometry in this file (cell centres of grids, mirror
lines, circumcentres, one Newton solve on the test's own ellipse distance); nothing is taken from
the library's output and no library distance or geometry code is called.  Each case is checked in
four separate tests (certified; vertices; edges with their end vertices and polylines; Delaunay
graph), so that a failure names the aspect that is wrong.
"""
from __future__ import annotations

import math
from collections import Counter
from dataclasses import dataclass, field
from fractions import Fraction

import numpy as np
import pytest

import curvedvoronoi as cv


# ----------------------------------------------------------------------------- test-side geometry
def ellipse_foot(px: float, py: float, cx: float, cy: float, a: float, b: float) -> tuple[float, float]:
    """Nearest point to (px, py), outside the axis-aligned ellipse of centre (cx, cy) and semi-axes
    a (along x), b (along y), on the ellipse.  By symmetry the foot point lies in the quadrant of
    the point: dense sampling of t ∈ [0, π/2] on (a cos t, b sin t), then Newton on the derivative
    h(t) = (b² − a²) sin t cos t + a x sin t − b y cos t of half the squared distance."""
    x, y = abs(px - cx), abs(py - cy)
    ts = np.linspace(0.0, math.pi / 2, 4001)
    d2 = (x - a * np.cos(ts)) ** 2 + (y - b * np.sin(ts)) ** 2
    t = float(ts[int(np.argmin(d2))])
    for _ in range(60):
        s, c = math.sin(t), math.cos(t)
        h = (b * b - a * a) * s * c + a * x * s - b * y * c
        dh = (b * b - a * a) * (c * c - s * s) + a * x * c + b * y * s
        if dh == 0:
            break
        t_new = min(max(t - h / dh, 0.0), math.pi / 2)
        if t_new == t:
            break
        t = t_new
    return (cx + math.copysign(a * math.cos(t), px - cx), cy + math.copysign(b * math.sin(t), py - cy))


def ellipse_distance(px, py, cx, cy, a, b) -> float:
    fx, fy = ellipse_foot(px, py, cx, cy, a, b)
    return math.hypot(px - fx, py - fy)


def newton_vertex(geo, start) -> tuple[float, float, float]:
    """The point equidistant from the three test-side sites ``geo`` near ``start`` (2-D Newton on
    d0 − d1, d0 − d2 with a central-difference Jacobian): (x, y, radius)."""
    p = np.array(start, dtype=float)

    def F(q):
        d = [g.dist(q[0], q[1]) for g in geo]
        return np.array([d[0] - d[1], d[0] - d[2]])

    for _ in range(60):
        f = F(p)
        hstep = 1e-7 * max(1.0, float(np.max(np.abs(p))))
        J = np.column_stack([(F(p + hstep * e) - F(p - hstep * e)) / (2 * hstep) for e in np.eye(2)])
        step = np.linalg.solve(J, f)
        p = p - step
        if np.max(np.abs(step)) < 1e-15 * max(1.0, float(np.max(np.abs(p)))):
            break
    assert np.max(np.abs(F(p))) < 1e-12
    return float(p[0]), float(p[1]), geo[0].dist(*p)


@dataclass
class Disc:
    """A point (r = 0) or circle site, as the test sees it."""
    x: float
    y: float
    r: float = 0.0

    def dist(self, px, py):
        return math.hypot(px - self.x, py - self.y) - self.r

    def contact_angle(self, vx, vy):
        return math.atan2(self.y - vy, self.x - vx)


@dataclass
class Ell:
    """An axis-aligned ellipse site, as the test sees it."""
    x: float
    y: float
    a: float
    b: float

    def dist(self, px, py):
        return ellipse_distance(px, py, self.x, self.y, self.a, self.b)

    def contact_angle(self, vx, vy):
        fx, fy = ellipse_foot(vx, vy, self.x, self.y, self.a, self.b)
        return math.atan2(fy - vy, fx - vx)


def ccw_from(vx, vy, angles: dict[int, float]) -> tuple[int, ...]:
    """Site indices sorted counter-clockwise by angle, rotated to start at the smallest index."""
    order = sorted(angles, key=lambda i: angles[i])
    k = order.index(min(order))
    return tuple(order[k:] + order[:k])


# ----------------------------------------------------------------------------- expected diagrams
@dataclass
class V:
    sites: tuple[int, ...]
    x: float
    y: float
    radius: float


@dataclass
class E:
    pair: tuple[int, int]
    ends: tuple            # two entries: index into the case's vertex list, or None (infinity)
    #: straight edges: the polyline lies on the line through `anchor` with direction `direction`,
    #: between its end vertices (or beyond the vertex along `direction` for an end at infinity)
    anchor: tuple | None = None
    direction: tuple | None = None


@dataclass
class Case:
    name: str
    sites: list                       # what is passed to cv.voronoi
    geo: list                         # Disc / Ell per site (test-side distances)
    vertices: list[V]
    edges: list[E]
    delaunay: list[tuple[int, int]]
    scale: float = 1.0                # a length of the scene (spacing): sets the position tolerance
    note: str = ""
    down: set = field(default_factory=set)     # pairs whose unbounded edge goes to y = −∞
    up: set = field(default_factory=set)       # pairs whose unbounded edge goes to y = +∞


def pos_tol(case: Case, *coords) -> float:
    """1e-9 (relative to the scene's spacing) plus 4 ulps of the coordinates' magnitude: a vertex at
    2²¹ + 1/16 is a double, but a frame change may cost an ulp or two."""
    return 1e-9 * max(1.0, case.scale) + 4 * math.ulp(max([1.0] + [abs(c) for c in coords]))


def grid_case(n: int, origin=(0, 0), spacing=1, as_float=True) -> Case:
    """n×n points (ox + s·i, oy + s·j), site index j·n + i (x fastest).

    Vertices: the (n−1)² cell centres (ox + s(i + ½), oy + s(j + ½)), each equidistant (s√2/2)
    from its four corners and farther from every other grid point: degree 4.  Seen from the centre
    the corners (i, j), (i+1, j), (i+1, j+1), (i, j+1) lie at angles −135°, −45°, 45°, 135°, so that
    is the counter-clockwise order, and (i, j) has the smallest index.
    Edges: horizontal neighbours (i, j), (i+1, j) share the vertical line x = ox + s(i + ½) between
    the centres of cells (i, j−1) and (i, j) (infinity below row 0 / above row n−1); vertical
    neighbours likewise on y = oy + s(j + ½).  2n(n−1) edges, 4(n−1) of them unbounded.  The
    diagonals of a cell meet its centre only: no edge, not Delaunay."""
    ox, oy = origin
    s = spacing
    idx = lambda i, j: j * n + i  # noqa: E731
    conv = float if as_float else Fraction
    sites = [(conv(ox + s * i), conv(oy + s * j), 0) for j in range(n) for i in range(n)]
    geo = [Disc(float(ox + s * i), float(oy + s * j)) for j in range(n) for i in range(n)]
    cell = {}
    verts = []
    for j in range(n - 1):
        for i in range(n - 1):
            cell[i, j] = len(verts)
            verts.append(V((idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)),
                           float(ox + s * (i + Fraction(1, 2))), float(oy + s * (j + Fraction(1, 2))),
                           float(s) * math.sqrt(2) / 2))
    edges = []
    for j in range(n):
        for i in range(n - 1):      # horizontal neighbours: vertical bisector
            below, above = cell.get((i, j - 1)), cell.get((i, j))
            edges.append(E((idx(i, j), idx(i + 1, j)), (below, above),
                           (float(ox + s * (i + Fraction(1, 2))), float(oy + s * j)), (0.0, 1.0)))
    for j in range(n - 1):
        for i in range(n):          # vertical neighbours: horizontal bisector
            left, right = cell.get((i - 1, j)), cell.get((i, j))
            edges.append(E((idx(i, j), idx(i, j + 1)), (left, right),
                           (float(ox + s * i), float(oy + s * (j + Fraction(1, 2)))), (1.0, 0.0)))
    delaunay = sorted(e.pair for e in edges)
    assert len(edges) == 2 * n * (n - 1) and len(verts) == (n - 1) ** 2
    return Case(f"grid{n}" + ("" if origin == (0, 0) else "_far"), sites, geo, verts, edges, delaunay,
                scale=float(s))


def collinear_case(name, ts, p0, u) -> Case:
    """Points p0 + t·u for t in ts (given unsorted): no vertex; between neighbours along the line the
    perpendicular bisector is a whole line (both ends at infinity); nothing else (the bisector of
    non-neighbours is separated from them by the point in between)."""
    pts = [(p0[0] + t * u[0], p0[1] + t * u[1]) for t in ts]
    order = sorted(range(len(ts)), key=lambda k: ts[k])
    edges = []
    for a, b in zip(order, order[1:]):
        mid = ((pts[a][0] + pts[b][0]) / 2, (pts[a][1] + pts[b][1]) / 2)
        edges.append(E(tuple(sorted((a, b))), (None, None), mid, (-u[1], u[0])))
    return Case(name, [(x, y, 0) for x, y in pts], [Disc(x, y) for x, y in pts], [], edges,
                sorted(e.pair for e in edges))


def cocircular_points_case(name, pts, centre=(0, 0)) -> Case:
    """Points on one circle about ``centre`` (no other site): one vertex of degree k at the centre,
    radius = the circle's; the angularly adjacent pairs share the ray from the centre through the
    midpoint of their chord; non-adjacent pairs meet at the centre only."""
    cx, cy = centre
    R = math.hypot(pts[0][0] - cx, pts[0][1] - cy)
    for x, y in pts:   # exact check that the data is co-circular (integers)
        assert (Fraction(x) - cx) ** 2 + (Fraction(y) - cy) ** 2 == Fraction(pts[0][0] - cx) ** 2 + Fraction(pts[0][1] - cy) ** 2
    ang = {k: math.atan2(y - cy, x - cx) for k, (x, y) in enumerate(pts)}
    sites = ccw_from(cx, cy, ang)
    edges = []
    for t in range(len(sites)):
        a, b = sites[t], sites[(t + 1) % len(sites)]
        mx, my = (pts[a][0] + pts[b][0]) / 2 - cx, (pts[a][1] + pts[b][1]) / 2 - cy
        edges.append(E(tuple(sorted((a, b))), (0, None), (float(cx), float(cy)), (mx, my)))
    return Case(name, [(x, y, 0) for x, y in pts], [Disc(x, y) for x, y in pts],
                [V(sites, float(cx), float(cy), R)], edges, sorted(e.pair for e in edges), scale=R)


def cocircular_circles_case(name, circles, rho) -> Case:
    """Circles (x, y, r), all outside the circle of radius rho about the origin and tangent to it
    (|centre| − r = rho exactly): one vertex of degree k at the origin with radius rho, the
    angularly adjacent pairs joined by an edge from the origin to infinity (the circles lie on the
    hull of their union, each once, in angular order: checked by the caller's choice of data)."""
    for x, y, r in circles:
        assert Fraction(x) ** 2 + Fraction(y) ** 2 == (Fraction(r) + rho) ** 2
    ang = {k: math.atan2(y, x) for k, (x, y, r) in enumerate(circles)}
    sites = ccw_from(0.0, 0.0, ang)
    edges = []
    for t in range(len(sites)):
        a, b = sites[t], sites[(t + 1) % len(sites)]
        edges.append(E(tuple(sorted((a, b))), (0, None)))
    return Case(name, list(circles), [Disc(*c) for c in circles], [V(sites, 0.0, 0.0, float(rho))], edges,
                sorted(e.pair for e in edges), scale=float(rho))


def hidden_circle_case() -> Case:
    """Four circles tangent to the circle of radius 4 about the origin: |(6, 8)| = 10 = 4 + 6,
    |(−8, 6)| = 10 = 4 + 6, |(−4, −3)| = 5 = 4 + 1, |(0, −9)| = 9 = 4 + 5 (pairwise disjoint:
    centre distances √200, √221, √325, √97, 17, √52 exceed the sums of radii).  The small circle 2
    lies inside the hull of the union (the outer tangent of the big circles 1 and 3 passes beyond
    it), so its region is bounded: one vertex of degree 4 at the origin (angular order 0, 1, 2, 3),
    a second vertex W of (1, 2, 3) on the far side of circle 2, edges (1, 2) and (2, 3) from the
    origin to W, (1, 3) from W to infinity, (0, 1) and (0, 3) from the origin to infinity.  The pair
    (1, 3) meets at the origin only at a point (not an edge there) and shares the edge beyond W.
    W is solved by Newton on the test's distances from a start on the ray through circle 2's
    centre beyond it, (−9.5, −7)."""
    circles = [(6, 8, 6), (-8, 6, 6), (-4, -3, 1), (0, -9, 5)]
    for x, y, r in circles:
        assert x * x + y * y == (r + 4) ** 2
    geo = [Disc(*c) for c in circles]
    o = V(ccw_from(0.0, 0.0, {k: g.contact_angle(0.0, 0.0) for k, g in enumerate(geo)}), 0.0, 0.0, 4.0)
    assert o.sites == (0, 1, 2, 3)
    x, y, r = newton_vertex(geo[1:], (-9.5, -7.0))
    assert math.hypot(x, y) > 5 and geo[0].dist(x, y) > r + 1
    w = V(ccw_from(x, y, {k: geo[k].contact_angle(x, y) for k in (1, 2, 3)}), x, y, r)
    edges = [E((0, 1), (0, None)), E((0, 3), (0, None)), E((1, 2), (0, 1)), E((2, 3), (0, 1)),
             E((1, 3), (1, None))]
    return Case("cocircular_circles_hidden", circles, geo, [o, w], edges,
                [(0, 1), (0, 3), (1, 2), (1, 3), (2, 3)], scale=4.0)


def readme_case() -> Case:
    """The README's example: circles (0,0,1), (4,0,1), point (2,4), ellipse centre (10,0) axes (2,1).

    Circles 0, 1 and the ellipse 3 all touch y = −1 from above (and y = +1 from below), so the
    half-plane y < −1 is an empty 'circle at infinity' touching 0, 1 and 3: downward the unbounded
    edges are (0, 1) (the vertical line x = 2) and (1, 3), consecutive along the line; site 1
    separates 0 from 3, so (0, 3) is no edge.  Above, the point (2, 4) lies in y > 1, so the upper
    hull is 0, 2, 3: unbounded edges (0, 2) and (2, 3) going up.  Four sites on the hull, every one
    once: a triangulated quadrilateral, two vertices (0, 1, 2) and (1, 3, 2) and one bounded edge
    (1, 2).

    Vertex of (0, 1, 2): on x = 2 by symmetry of the two circles; √(4 + y²) − 1 = 4 − y gives
    y = 21/10, radius 19/10 (the ellipse is ≥ 6 away).  Vertex of (1, 2, 3): solved here by Newton
    on the test's own distances."""
    sites = [(0, 0, 1), (4, 0, 1), (2, 4, 0), cv.Conic.ellipse(centre=(10, 0), axes=(2, 1))]
    geo = [Disc(0, 0, 1), Disc(4, 0, 1), Disc(2, 4, 0), Ell(10, 0, 2, 1)]
    # vertex of (1, 2, 3): Newton on the test's own distances from a hand-picked start (7, 5)
    x, y, r123 = newton_vertex(geo[1:], (7.0, 5.0))
    assert geo[0].dist(x, y) > r123 + 1          # the fourth site stays outside: a true vertex
    va = V(ccw_from(2.0, 2.1, {0: geo[0].contact_angle(2, 2.1), 1: geo[1].contact_angle(2, 2.1),
                               2: geo[2].contact_angle(2, 2.1)}), 2.0, 2.1, 1.9)
    vb = V(ccw_from(x, y, {k: geo[k].contact_angle(x, y) for k in (1, 2, 3)}), x, y, r123)
    edges = [E((0, 1), (0, None), (2.0, 2.1), (0.0, -1.0)), E((0, 2), (0, None)), E((1, 2), (0, 1)),
             E((1, 3), (1, None)), E((2, 3), (1, None))]
    return Case("readme", sites, geo, [va, vb], edges, [(0, 1), (0, 2), (1, 2), (1, 3), (2, 3)],
                scale=1.0, down={(0, 1), (1, 3)}, up={(0, 2), (2, 3)})


def ellipse_grid_case() -> Case:
    """3×3 identical ellipses, centres (6i, 4j), semi-axes 2 (x) and 1 (y), site index 3j + i.

    Two translates A, B of one ellipse with A's centre mirrored to B's across a line L (here the
    vertical line x = 6i + 3 or the horizontal line y = 4j + 2: the ellipse is symmetric about its
    axes) are mirror images; a point on A's side of L is strictly nearer to A (its nearest point of B
    mirrors to a point of A at least as near).  Chaining two mirrors, the Voronoi region of (i, j) is
    exactly the grid cell [6i − 3, 6i + 3] × [4j − 2, 4j + 2]: the diagram is that of the grid of
    centres.  Hence 4 vertices of degree 4 at (3, 2), (9, 2), (3, 6), (9, 6), each at distance
    dist((3, 2), ellipse at the origin) from its four ellipses, and 12 edges on the mirror lines:
    2 per row on x = 3, 9 (3 rows) and 2 per column on y = 2, 6 (3 columns); the 4 of the middle
    row and column are bounded, the 8 others go to infinity.  Contact points: the foot point of
    (3, 2) on the ellipse at (0, 0) lies in that ellipse's upper-right quadrant (angle in
    (−180°, −90°) seen from the vertex), and the other three are its mirror images, so the order is
    that of the corners: (i, j), (i+1, j), (i+1, j+1), (i, j+1)."""
    n = 3
    sites = [cv.Conic.ellipse(centre=(6 * i, 4 * j), axes=(2, 1)) for j in range(n) for i in range(n)]
    geo = [Ell(6 * i, 4 * j, 2, 1) for j in range(n) for i in range(n)]
    base = grid_case(n, spacing=1)
    radius = ellipse_distance(3, 2, 0, 0, 2, 1)
    verts = [V(v.sites, 6 * v.x, 4 * v.y, radius) for v in base.vertices]
    edges = [E(e.pair, e.ends, (6 * e.anchor[0], 4 * e.anchor[1]), e.direction) for e in base.edges]
    return Case("ellipse_grid3", sites, geo, verts, edges, base.delaunay, scale=4.0)


CASES = [
    grid_case(2), grid_case(3), grid_case(5),
    grid_case(2, origin=(2 ** 20, -2 ** 21), spacing=Fraction(1, 8)),
    grid_case(3, origin=(2 ** 20, -2 ** 21), spacing=Fraction(1, 8)),
    grid_case(5, origin=(2 ** 20, -2 ** 21), spacing=Fraction(1, 8)),
    collinear_case("collinear6", [7, 0, 10, 1, 4, 3], (0, 0), (1, 0)),
    collinear_case("collinear6_slanted", [3, -1, 0, 5, 2, 8], (1, 1), (1, 2)),   # on y = 2x − 1
    cocircular_points_case("square", [(0, 0), (2, 0), (2, 2), (0, 2)], centre=(1, 1)),
    cocircular_points_case("cocircular6", [(3, 4), (-5, 0), (3, -4), (5, 0), (-3, -4), (-3, 4)]),
    cocircular_points_case("cocircular12", [(0, 5), (4, -3), (-3, 4), (5, 0), (-4, -3), (3, 4), (0, -5),
                                            (-5, 0), (4, 3), (-4, 3), (3, -4), (-3, -4)]),
    cocircular_circles_case("four_equal_circles", [(5, 0, 1), (0, 5, 1), (-5, 0, 1), (0, -5, 1)], 4),
    # different radii, centres at |c| = rho + r with rho = 4: 5 = 4 + 1, 6 = 4 + 2, 10 = 4 + 6,
    # 7 = 4 + 3; pairwise disjoint (centre distances √61, √136, √149, 15, 13, √74 exceed r_i + r_j)
    cocircular_circles_case("cocircular_circles_radii", [(5, 0, 1), (0, 6, 2), (-10, 0, 6), (0, -7, 3)], 4),
    hidden_circle_case(),
    readme_case(),
    ellipse_grid_case(),
]
BY_NAME = {c.name: c for c in CASES}
_DIAGRAMS: dict = {}


def diagram(case: Case):
    if case.name not in _DIAGRAMS:
        _DIAGRAMS[case.name] = cv.voronoi(case.sites, time_limit=120)
    return _DIAGRAMS[case.name]


def _match_vertices(case: Case, d) -> dict:
    """Actual vertex id -> index of the expected vertex at that position (None if none)."""
    out = {}
    for v in d.vertices:
        hit = [k for k, w in enumerate(case.vertices)
               if abs(v.x - w.x) <= pos_tol(case, w.x, w.y) and abs(v.y - w.y) <= pos_tol(case, w.x, w.y)]
        out[v.id] = hit[0] if len(hit) == 1 else None
    return out


def _edge_key(pair, ends):
    return (tuple(pair), tuple(sorted(ends, key=lambda t: (t is None, -1 if t is None else t))))


NAMES = [c.name for c in CASES]


def test_the_expectations_are_consistent():
    """Self-check of the hand-written data: every vertex's k pairs of consecutive sites are edges
    ending there, every expected edge's sites are at its expected end vertices (at the radius), and
    the Delaunay graph is the set of edge pairs.  Independent of the library."""
    for case in CASES:
        for k, v in enumerate(case.vertices):
            assert len(v.sites) >= 3, case.name
            for s in v.sites:
                assert abs(case.geo[s].dist(v.x, v.y) - v.radius) <= 1e-9 * max(1.0, v.radius), (case.name, s)
            for s in set(range(len(case.sites))) - set(v.sites):
                assert case.geo[s].dist(v.x, v.y) > v.radius + 1e-6, (case.name, s)   # empty, exactly k sites
            pairs = {tuple(sorted((v.sites[t], v.sites[(t + 1) % len(v.sites)]))) for t in range(len(v.sites))}
            at_v = {e.pair for e in case.edges if k in e.ends}
            assert pairs == at_v, case.name
        assert sorted({e.pair for e in case.edges}) == case.delaunay, case.name


@pytest.mark.parametrize("name", NAMES)
def test_certified(name):
    d = diagram(BY_NAME[name])
    assert d.certified, d.problems
    assert d.problems == []


@pytest.mark.parametrize("name", NAMES)
def test_vertices(name):
    """Number of vertices, and per expected vertex: position (1e-9), radius (1e-9 relative), sites in
    counter-clockwise order starting with the smallest index, degree, certified."""
    case = BY_NAME[name]
    d = diagram(case)
    got = [(v.sites, v.x, v.y) for v in d.vertices]
    assert len(d.vertices) == len(case.vertices), got
    match = _match_vertices(case, d)
    assert sorted(m for m in match.values() if m is not None) == list(range(len(case.vertices))), got
    for v in d.vertices:
        w = case.vertices[match[v.id]]
        assert tuple(v.sites) == w.sites, (v.x, v.y)
        assert v.degree == len(w.sites) == len(v.sites)
        assert abs(v.radius - w.radius) <= 1e-9 * max(1.0, w.radius)
        assert v.certified, (v.sites, v.x, v.y)


@pytest.mark.parametrize("name", NAMES)
def test_edges(name):
    """The multiset of (site pair, end vertices) equals the expected one (end vertices matched by
    position, None = infinity); polylines start/end at their end vertices, their points are on the
    bisector (equidistant by the test's distances; on the expected line and within the segment or
    ray for straight edges); unbounded edges go the expected way."""
    case = BY_NAME[name]
    d = diagram(case)
    match = _match_vertices(case, d)
    actual = Counter(_edge_key(e.sites, [None if t is None else match.get(t, "?") for t in e.ends])
                     for e in d.edges)
    expected = Counter(_edge_key(e.pair, e.ends) for e in case.edges)
    assert actual == expected, (actual - expected, expected - actual)
    by_key = {_edge_key(e.pair, e.ends): e for e in case.edges}
    pos = {v.id: (v.x, v.y) for v in d.vertices}
    for e in d.edges:
        assert not e.closed
        ends = [None if t is None else match[t] for t in e.ends]
        want = by_key[_edge_key(e.sites, ends)]
        P = np.asarray(e.polyline, dtype=float)
        assert P.ndim == 2 and P.shape[1] == 2 and len(P) >= 2
        for t, end in ((0, e.ends[0]), (-1, e.ends[1])):
            if end is not None:
                assert np.allclose(P[t], pos[end], rtol=0, atol=pos_tol(case, *pos[end])), (e.sites, P[t])
        i, j = e.sites
        for x, y in P:
            if math.hypot(x - P[0][0], y - P[0][1]) > 1e6 * case.scale:
                continue           # far points: float distances lose the digits; the line check covers them
            di, dj = case.geo[i].dist(x, y), case.geo[j].dist(x, y)
            # the polyline's points are projected onto the bisector (voronoi's docstring); only the
            # chords between them may stray (by e.tolerance)
            assert abs(di - dj) <= 1e-9 * max(1.0, di) + 4 * math.ulp(max(abs(x), abs(y), 1.0)), (e.sites, x, y, di, dj)
            for s in range(len(case.sites)):
                if s not in (i, j):
                    assert case.geo[s].dist(x, y) >= di - 1e-7 * max(1.0, di), (e.sites, s, x, y)
        if want.anchor is not None:
            ax, ay = want.anchor
            ux, uy = want.direction
            nu = math.hypot(ux, uy)
            ux, uy = ux / nu, uy / nu
            off = np.abs((P[:, 0] - ax) * uy - (P[:, 1] - ay) * ux)     # distance to the line
            scale = np.maximum(1.0, np.hypot(P[:, 0] - ax, P[:, 1] - ay))
            assert np.all(off <= 1e-9 * case.scale * scale + 8 * math.ulp(max(abs(ax), abs(ay), 1.0))), e.sites
            ts = (P[:, 0] - ax) * ux + (P[:, 1] - ay) * uy            # parameter along the line
            known = [(end, pos[end]) for end in e.ends if end is not None]
            params = [(pp[0] - ax) * ux + (pp[1] - ay) * uy for _, pp in known]
            slack = pos_tol(case, ax, ay) * 4
            if len(known) == 2:
                lo, hi = min(params), max(params)
                assert np.all(ts >= lo - slack) and np.all(ts <= hi + slack), e.sites
                assert hi - lo > 0.5 * case.scale            # positive length (a cell side)
            elif len(known) == 1:
                # a ray from its vertex: through the anchor when the anchor is elsewhere on the line
                # (grids: the midpoint of the two sites), else along +direction (co-circular points:
                # the anchor is the centre, the direction points to the chord's midpoint)
                way = 1.0 if abs(params[0]) <= slack else math.copysign(1.0, -params[0])
                beyond = (ts - params[0]) * way
                assert np.all(beyond >= -slack), e.sites
                assert np.max(beyond) > case.scale, e.sites        # it does leave the vertex
        if e.ends.count(None) >= 1 and (case.up or case.down):
            far_y = P[-1][1] if e.ends[1] is None else P[0][1]
            near = [pos[t][1] for t in e.ends if t is not None]
            if tuple(e.sites) in case.down:
                assert far_y < min(near) - 1, e.sites
            if tuple(e.sites) in case.up:
                assert far_y > max(near) + 1, e.sites


@pytest.mark.parametrize("name", NAMES)
def test_delaunay_edges(name):
    """Pairs sharing a Voronoi edge of positive length only: grid neighbours (no cell diagonals),
    consecutive collinear points, angularly adjacent co-circular sites."""
    case = BY_NAME[name]
    assert diagram(case).delaunay_edges() == case.delaunay


def test_square_diagonals_are_not_delaunay_edges():
    """The four co-circular corners of a square meet at one vertex; the diagonals (0, 2), (1, 3)
    have a zero-length bisector piece there and are not Delaunay edges."""
    d = diagram(BY_NAME["square"])
    assert (0, 2) not in d.delaunay_edges() and (1, 3) not in d.delaunay_edges()
    assert [v.degree for v in d.vertices] == [4]


def test_grid_given_as_exact_fractions():
    """The far grid with the coordinates given as Fractions instead of floats: same diagram."""
    case = grid_case(3, origin=(2 ** 20, -2 ** 21), spacing=Fraction(1, 8), as_float=False)
    sites = [cv.Point(x, y) for x, y, _ in case.sites]
    d = cv.voronoi(sites, time_limit=120)
    assert d.certified, d.problems
    assert d.delaunay_edges() == case.delaunay
    assert sorted(v.sites for v in d.vertices) == sorted(v.sites for v in case.vertices)


def test_nearly_cocircular_square_is_not_merged():
    """The square's fourth corner moved off the circle by 2⁻²⁰ (outward): the exact diagram has two
    vertices of degree 3 joined by a tiny edge (0, 2) or (1, 3), never one vertex of degree 4."""
    eps = 2.0 ** -20
    sites = [(0.0, 0.0, 0), (2.0, 0.0, 0), (2.0 + eps, 2.0 + eps, 0), (0.0, 2.0, 0)]
    # corner 2 outward: triangle (0, 1, 3) has the circumcircle of the square, corner 2 is outside it,
    # so (0, 1, 3) is a Delaunay triangle and its diagonal (1, 3) is a Delaunay edge
    d = cv.voronoi(sites, time_limit=120)
    assert d.certified, d.problems
    assert sorted(v.degree for v in d.vertices) == [3, 3]
    assert d.delaunay_edges() == [(0, 1), (0, 3), (1, 2), (1, 3), (2, 3)]


def test_json_format_2_round_trip_keeps_degree_4():
    d = diagram(BY_NAME["grid3"])
    doc = d.to_json()
    assert doc["format"] == "curvedvoronoi.diagram/2"
    back = cv.Diagram.from_json(doc) if hasattr(cv, "Diagram") else type(d).from_json(doc)
    assert sorted(tuple(v.sites) for v in back.vertices) == sorted(v.sites for v in BY_NAME["grid3"].vertices)
    assert all(v.degree == 4 for v in back.vertices)
    assert back.delaunay_edges() == BY_NAME["grid3"].delaunay


def test_json_format_1_is_read():
    """A version-1 document written by hand: three points (0,0), (4,0), (0,4), one vertex (2, 2) of
    radius √8, three unbounded edges."""
    from curvedvoronoi.runtime.voronoi.structure import Diagram

    r = math.sqrt(8)
    doc = {"format": "curvedvoronoi.diagram/1",
           "sites": [{"point": ["0", "0"]}, {"point": ["4", "0"]}, {"point": ["0", "4"]}],
           "vertices": [{"id": 0, "sites": [0, 1, 2], "x": 2.0, "y": 2.0, "radius": r, "certified": True}],
           "edges": [{"id": 0, "sites": [0, 1], "ends": [0, None], "closed": False,
                      "polyline": [[2.0, 2.0], [2.0, -10.0]], "tolerance": 0.0, "certified": True},
                     {"id": 1, "sites": [0, 2], "ends": [0, None], "closed": False,
                      "polyline": [[2.0, 2.0], [-10.0, 2.0]], "tolerance": 0.0, "certified": True},
                     {"id": 2, "sites": [1, 2], "ends": [0, None], "closed": False,
                      "polyline": [[2.0, 2.0], [10.0, 10.0]], "tolerance": 0.0, "certified": True}],
           "delaunay_edges": [[0, 1], [0, 2], [1, 2]], "certified": True, "problems": [], "stats": {}}
    d = Diagram.from_json(doc)
    assert [v.degree for v in d.vertices] == [3]
    assert d.delaunay_edges() == [(0, 1), (0, 2), (1, 2)]
    assert d.to_json()["format"] == "curvedvoronoi.diagram/2"
