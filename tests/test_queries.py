"""Nearest-site queries, distances, array views, cells and GeoDataFrames (issue 35, items 1-2).

The references are independent of the library's distance code: exact rational arithmetic for
points and circles (signs of sums of square roots decided by squaring, in Fractions), mpmath for
conics, scipy's and shapely's Voronoi diagrams for point sites."""
from __future__ import annotations

import math
import random
from fractions import Fraction as F

import mpmath as mp
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import curvedvoronoi as cv

shapely = pytest.importorskip("shapely")


# ---------------------------------------------------------------- exact reference (Fractions)
def _sgn(x) -> int:
    return (x > 0) - (x < 0)


def _sign_sqrt1(e, Z, f) -> int:
    """sign(e·√Z + f), Z ≥ 0, rationals."""
    se = _sgn(e) if Z else 0
    sf = _sgn(f)
    if se == 0:
        return sf
    if sf == 0 or se == sf:
        return se
    return se * _sgn(e * e * Z - f * f)


def _sign_sqrt2(a, X, b, Y, c) -> int:
    """sign(a·√X + b·√Y + c), X, Y ≥ 0, rationals."""
    sa, sb = (_sgn(a) if X else 0), (_sgn(b) if Y else 0)
    sp = sb if sa == 0 else sa if (sb == 0 or sa == sb) else sa * _sgn(a * a * X - b * b * Y)
    sc = _sgn(c)
    if sp == 0:
        return sc
    if sc == 0 or sp == sc:
        return sp
    s = _sign_sqrt1(2 * a * b, X * Y, a * a * X + b * b * Y - c * c)      # sign(p² − c²)
    return sp if s > 0 else sc if s < 0 else 0


def exact_compare(q, s, t) -> int:
    """sign(d(q, s) − d(q, t)) for circles s, t = (cx, cy, ρ) (ρ = 0: a point), q rational:
    d = σ(√D − ρ) with σ = sign(D − ρ²)."""
    def terms(c):
        D = (q[0] - c[0]) ** 2 + (q[1] - c[1]) ** 2
        return D, c[2], (1 if D >= c[2] ** 2 else -1)

    Di, ri, si = terms(s)
    Dj, rj, sj = terms(t)
    return _sign_sqrt2(F(si), Di, F(-sj), Dj, sj * rj - si * ri)


def exact_nearest(q, circles) -> list[int]:
    """Indices of all nearest circles of q, exactly."""
    best = [0]
    for j in range(1, len(circles)):
        s = exact_compare(q, circles[j], circles[best[0]])
        if s < 0:
            best = [j]
        elif s == 0:
            best.append(j)
    return best


def as_sites(circles):
    return [cv.Point(x, y) if r == 0 else cv.Circle.from_radius(x, y, r) for x, y, r in circles]


def check_against_exact(d, circles, P):
    res = d.nearest(P)
    for row, p in enumerate(P):
        q = (F(float(p[0])), F(float(p[1])))
        want = exact_nearest(q, circles)
        if len(want) == 1:
            assert res.index[row] == want[0] and res.proved[row], (row, p, want, res.index[row])
            assert row not in res.ties
        else:
            assert res.index[row] == -1 and not res.proved[row], (row, p, want)
            assert res.ties[row] == tuple(want) and res.exact[row], (row, p, want, res.ties.get(row))
    return res


def random_circles(n, seed, *, points=0, box=40):
    rng = random.Random(seed)
    out = []
    while len(out) < n + points:
        r = F(0) if len(out) >= n else F(rng.randint(2, 12), 4)
        c = (F(rng.randint(0, 8 * box), 8), F(rng.randint(0, 8 * box), 8), r)
        if all((c[0] - o[0]) ** 2 + (c[1] - o[1]) ** 2 > (c[2] + o[2]) ** 2 for o in out):
            out.append(c)
    return out


@pytest.fixture(scope="module")
def mixed():
    circles = random_circles(20, 1, points=10)
    return circles, cv.voronoi(as_sites(circles))


@pytest.fixture(scope="module")
def nested():
    return cv.voronoi(cv.read_sites("runtime/data/example_sites.json"))


# ---------------------------------------------------------------- nearest
def test_nearest_matches_exact_brute_force_on_points_and_circles(mixed):
    circles, d = mixed
    rng = np.random.default_rng(2)
    P = np.vstack([rng.uniform(-10, 50, (300, 2)), [[1e3, 1e3], [-500.0, 20.0], [20.0, 20.0]],
                   [[float(c[0]), float(c[1])] for c in circles]])       # the centres too
    res = check_against_exact(d, circles, P)
    assert res.proved.all()
    D = np.array([[abs(math.hypot(p[0] - c[0], p[1] - c[1]) - c[2]) for c in circles] for p in P])
    assert np.allclose(res.distance, D.min(axis=1), rtol=1e-12, atol=1e-12)
    fast = d.nearest(P, prove=False)
    assert (fast.index == res.index).all() and not fast.proved.any()


def test_nearest_with_a_big_circle_holding_nested_sites():
    big = [(F(0), F(0), F(100))]
    inner = random_circles(15, 3, points=5, box=60)
    circles = big + [(x - 30, y - 30, r) for x, y, r in inner] + [(F(150), F(0), F(2)), (F(0), F(-140), F(0))]
    d = cv.Diagram(as_sites(circles))          # queries need only the sites
    rng = np.random.default_rng(4)
    ang = rng.uniform(0, 2 * np.pi, 100)
    P = np.vstack([rng.uniform(-120, 160, (200, 2)), np.column_stack([99.5 * np.cos(ang), 99.5 * np.sin(ang)])])
    check_against_exact(d, circles, P)


def test_ties_on_edges_and_at_vertices_are_exact():
    pts = [(F(0), F(0), F(0)), (F(4), F(0), F(0)), (F(0), F(4), F(0)), (F(4), F(4), F(0)), (F(9), F(1), F(0))]
    d = cv.Diagram(as_sites(pts))
    P = np.array([[2.0, 2.0],            # the degree-4 vertex of the square
                  [2.0, -1.0],           # on the edge of (0, 0) and (4, 0)
                  [2.0 + 2.0 ** -45, -1.0],   # just off it: decided exactly
                  [2.0, 2.0 - 2.0 ** -50],    # on the edge of (0, 0) and (4, 0), next to the vertex
                  [2.0 - 2.0 ** -50, 2.0 - 2.0 ** -50]])
    res = check_against_exact(d, pts, P)
    assert res.ties == {0: (0, 1, 2, 3), 1: (0, 1), 3: (0, 1)} and res.index.tolist()[2:] == [1, -1, 0]
    assert res.exact.tolist() == [True, True, False, True, False]
    circles = [(F(-5), F(0), F(1)), (F(5), F(0), F(1)), (F(0), F(5), F(1)), (F(14), F(0), F(3))]
    d = cv.voronoi(as_sites(circles))
    P = np.array([[0.0, 0.0],            # vertex of the three unit circles (distance 4)
                  [8.5, 0.0],            # on the hyperbolic edge of (5, 0, 1) and (14, 0, 3): 3.5 − 1 = 5.5 − 3
                  [10.0, 0.0], [0.0, -3.0]])
    res = check_against_exact(d, circles, P)
    assert res.ties[0] == (0, 1, 2) and res.ties[1] == (1, 3) and res.exact[[0, 1]].all()
    assert res.distance[0] == pytest.approx(4.0) and res.distance[1] == pytest.approx(2.5)
    # the library's own vertices: every site of a vertex is in the tie, or the vertex is exact
    for v in d.vertices:
        r = d.nearest(np.array([[v.x, v.y]]))
        assert r.index[0] in v.sites or set(r.ties.get(0, ())) <= set(v.sites)


def test_tie_between_mirror_conics_is_reported_undecided():
    E = [cv.Conic.ellipse(centre=(-5, 0), axes=(2, 1)), cv.Conic.ellipse(centre=(5, 0), axes=(2, 1))]
    d = cv.Diagram(E)
    res = d.nearest(np.array([[0.0, 1.0], [0.5, 1.0]]))
    assert res.index[0] == -1 and res.ties[0] == (0, 1) and not res.exact[0] and not res.proved[0]
    assert res.index[1] == 1 and res.proved[1]


@given(st.lists(st.tuples(st.integers(0, 6), st.integers(0, 6)), min_size=2, max_size=10, unique=True),
       st.lists(st.tuples(st.integers(-2, 14), st.integers(-2, 14)), min_size=1, max_size=20))
@settings(max_examples=40, deadline=None)
def test_grid_points_ties_hypothesis(sites, queries):
    pts = [(F(x), F(y), F(0)) for x, y in sites]
    d = cv.Diagram(as_sites(pts))
    check_against_exact(d, pts, np.array(queries, float) / 2)


def _conic_distance_mp(kind, centre, axes, rot, q):
    """Distance from q to the conic, mpmath (30 digits): dense samples of the parameter, then
    Newton on the derivative of the squared distance."""
    mp.mp.dps = 30
    cx, cy = (mp.mpf(v) for v in centre)
    c, s = (mp.mpf(F(v).numerator) / F(v).denominator for v in rot)
    qx, qy = mp.mpf(q[0]), mp.mpf(q[1])

    def point(t):
        if kind == "ellipse":
            X, Y = axes[0] * mp.cos(t), axes[1] * mp.sin(t)
        else:                                   # parabola Y² = 2pX
            X, Y = t * t / (2 * axes[0]), t
        return cx + c * X - s * Y, cy + s * X + c * Y

    def f(t):
        x, y = point(t)
        return (x - qx) ** 2 + (y - qy) ** 2

    ts = np.linspace(0, 2 * np.pi, 721) if kind == "ellipse" else np.linspace(-40, 40, 1601)
    t0 = min(ts, key=lambda t: float(f(mp.mpf(t))))
    try:
        t1 = mp.findroot(lambda t: mp.diff(f, t), mp.mpf(t0))
        val = min(f(t1), f(mp.mpf(t0)))
    except (ValueError, ZeroDivisionError):
        val = f(mp.mpf(t0))
    return float(mp.sqrt(val))


CONICS = [("ellipse", (0, 0), (3, 1), ("3/5", "4/5")), ("ellipse", (10, 2), (2, 1), (1, 0)),
          ("parabola", (-8, 0), (1,), (-1, 0))]


def test_nearest_and_site_distance_on_conics_against_mpmath():
    sites = [cv.Conic.ellipse(centre=c, axes=a, rotation=r) if k == "ellipse" else cv.Conic.parabola(vertex=c, p=a[0], rotation=r)
             for k, c, a, r in CONICS] + [cv.Circle.from_radius(5, -6, 1)]
    d = cv.Diagram(sites)
    rng = np.random.default_rng(5)
    P = rng.uniform(-12, 14, (25, 2))
    ref = np.array([[_conic_distance_mp(*cs, p) for cs in CONICS] + [abs(math.hypot(p[0] - 5, p[1] + 6) - 1)] for p in P])
    D = d.site_distance(P)
    assert D.shape == (25, 4) and np.allclose(D, ref, rtol=1e-9, atol=1e-9)
    lo, hi = d.site_distance(P, bounds=True)
    assert (lo <= ref + 1e-12).all() and (ref <= hi + 1e-12).all()
    assert np.allclose(d.site_distance(P, sites=[3, 0]), ref[:, [3, 0]])
    res = d.nearest(P)
    srt = np.sort(ref, axis=1)
    clear = srt[:, 1] - srt[:, 0] > 1e-8
    assert clear.sum() > 20
    assert (res.index[clear] == ref.argmin(axis=1)[clear]).all() and res.proved[clear].all()
    assert np.allclose(res.distance, srt[:, 0], rtol=1e-9, atol=1e-9)


def test_bad_query_shapes():
    d = cv.Diagram(as_sites([(F(0), F(0), F(0)), (F(1), F(0), F(0))]))
    with pytest.raises(ValueError):
        d.nearest(np.zeros((3, 3)))
    with pytest.raises(ValueError):
        d.nearest(np.array([[np.nan, 0.0]]))
    assert d.nearest([0.2, 0.0]).index.tolist() == [0]


# ---------------------------------------------------------------- array views
def test_array_views_against_the_edge_list(nested):
    for d in (nested, cv.voronoi([(0, 0, 1), (4, 0, 1), (2, 4, 0)])):
        V, RS, RV = d.vertex_array, d.ridge_sites, d.ridge_vertices
        assert V.shape == (len(d.vertices), 2) and RS.shape == RV.shape == (len(d.edges), 2)
        assert RS.dtype.kind == RV.dtype.kind == "i"
        for t, e in enumerate(d.edges):
            assert tuple(RS[t]) == tuple(e.sites)
            for k in (0, 1):
                if e.ends[k] is None:
                    assert RV[t, k] == -1
                else:
                    v = d.vertices[RV[t, k]]
                    assert v.id == e.ends[k] and tuple(V[RV[t, k]]) == (v.x, v.y)
    closed = [t for t, e in enumerate(nested.edges) if e.closed]
    assert closed and (nested.ridge_vertices[closed] == -1).all()


def test_array_views_against_scipy_voronoi():
    from scipy.spatial import Voronoi

    rng = np.random.default_rng(6)
    P = rng.uniform(0, 100, (40, 2))
    d = cv.voronoi([(float(x), float(y), 0) for x, y in P])
    vor = Voronoi(P)
    ours = {tuple(sorted(s)): sorted(map(tuple, np.round(d.vertex_array[[v for v in rv if v >= 0]], 6).tolist()))
            for s, rv in zip(d.ridge_sites.tolist(), d.ridge_vertices.tolist())}
    theirs = {tuple(sorted(s)): sorted(map(tuple, np.round(vor.vertices[[v for v in rv if v >= 0]], 6).tolist()))
              for s, rv in zip(vor.ridge_points.tolist(), vor.ridge_vertices)}
    assert ours == theirs


# ---------------------------------------------------------------- cells
def _check_tiling(cells, region, tol):
    area = sum(c.area for c in cells)
    assert abs(area - region.area) <= tol * region.length + 1e-9 * region.area
    tree = shapely.STRtree(cells)
    for i, j in tree.query(cells, predicate="intersects").T:
        if i < j:
            assert cells[i].intersection(cells[j]).area <= 1e-9 * region.area


def _site_samples(d, i, window):
    from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry

    g = site_geometry(d.sites[i])
    return g.samples(0.5, window)


@pytest.mark.parametrize("clip", [None, (5.0, 5.0, 30.0, 35.0), "polygon"])
def test_cells_tile_the_clip_region_and_hold_their_sites(mixed, clip):
    circles, d = mixed
    if clip == "polygon":                       # not convex: cells may be split
        clip = shapely.Polygon([(-5, -5), (45, -5), (45, 45), (20, 10), (-5, 45)])
    cells = d.cells(clip)
    from curvedvoronoi.runtime.voronoi.cells import default_clip

    region = shapely.box(*default_clip(d)) if clip is None else clip if not isinstance(clip, tuple) else shapely.box(*clip)
    assert len(cells) == len(d.sites)
    tol = max(e.tolerance for e in d.edges) + 1e-9
    _check_tiling(cells, region, tol)
    for i, cell in enumerate(cells):
        S = _site_samples(d, i, region.bounds)
        inside = shapely.contains_xy(region, S[:, 0], S[:, 1])
        if inside.any():
            assert shapely.covers(cell.buffer(tol), shapely.points(S[inside])).all(), i
        else:
            assert cell.is_empty or cell.area < 0.3 * region.area


def test_cells_of_nested_sites_make_holes(nested):
    cells = nested.cells()
    (e,) = [e for e in nested.edges if e.closed]
    outer, inner = e.sites if cells[e.sites[0]].area > cells[e.sites[1]].area else e.sites[::-1]
    assert len(cells[outer].interiors) == 1 and len(cells[inner].interiors) == 0
    hole = shapely.Polygon(cells[outer].interiors[0])
    assert hole.symmetric_difference(cells[inner]).area < 1e-9 * hole.area
    from curvedvoronoi.runtime.voronoi.cells import default_clip

    _check_tiling(cells, shapely.box(*default_clip(nested)), max(f.tolerance for f in nested.edges) + 1e-9)


def test_cells_outside_the_clip_are_empty(mixed):
    circles, d = mixed
    x, y, r = (float(v) for v in circles[0])
    cells = d.cells((x - r / 2, y - r / 2, x + r / 2, y + r / 2))
    assert cells[0].area == pytest.approx(r * r) and all(c.is_empty and c.geom_type == "Polygon" for c in cells[1:])
    with pytest.raises(ValueError):
        d.cells((1, 1, 0, 2))


@pytest.fixture(scope="module")
def points_diagram():
    rng = np.random.default_rng(7)
    P = rng.uniform(0, 100, (50, 2))
    return P, cv.voronoi([(float(x), float(y), 0) for x, y in P])


def test_point_cells_against_scipy_bounded_regions(points_diagram):
    from scipy.spatial import Voronoi

    P, d = points_diagram
    vor = Voronoi(P)
    lo, hi = vor.vertices.min(axis=0) - 10, vor.vertices.max(axis=0) + 10
    cells = d.cells((lo[0], lo[1], hi[0], hi[1]))
    bounded = 0
    for i in range(len(P)):
        reg = vor.regions[vor.point_region[i]]
        if reg and -1 not in reg:
            bounded += 1
            poly = shapely.Polygon(vor.vertices[reg])
            assert poly.symmetric_difference(cells[i]).area < 1e-8 * poly.area, i
    assert bounded > 20


def test_point_cells_against_shapely_voronoi_polygons(points_diagram):
    P, d = points_diagram
    box = shapely.box(-20, -30, 130, 110)
    cells = d.cells(box)
    polys = shapely.get_parts(shapely.voronoi_polygons(shapely.MultiPoint(P), extend_to=box))
    for poly in polys:
        poly = poly.intersection(box)
        (i,) = [i for i in range(len(P)) if poly.contains(shapely.Point(P[i]))]
        assert poly.symmetric_difference(cells[i]).area < 1e-8 * box.area, i


def test_cells_of_conics_tile(nested):
    sites = [cv.Conic.ellipse(centre=(0, 0), axes=(3, 1), rotation=("3/5", "4/5")),
             cv.Conic.ellipse(centre=(10, 2), axes=(2, 1)), cv.Circle.from_radius(5, -6, 1), cv.Point(4, 6)]
    d = cv.voronoi(sites)
    box = (-10, -15, 20, 15)
    cells = d.cells(box)
    _check_tiling(cells, shapely.box(*box), max(e.tolerance for e in d.edges) + 1e-9)
    for i, cell in enumerate(cells):
        S = _site_samples(d, i, box)
        assert shapely.covers(cell.buffer(max(e.tolerance for e in d.edges)), shapely.points(S)).all(), i


# ---------------------------------------------------------------- geopandas
def test_to_geopandas_reads_back(nested, tmp_path):
    gpd = pytest.importorskip("geopandas")
    g = nested.to_geopandas(crs="EPSG:32633")
    assert len(g.cells) == len(g.sites) == len(nested.sites) and len(g.edges) == len(nested.edges)
    for name in ("cells", "edges", "sites"):
        frame = getattr(g, name)
        path = tmp_path / f"{name}.gpkg"
        frame.to_file(path)
        back = gpd.read_file(path)
        assert back.crs == frame.crs and back.crs.to_epsg() == 32633 and len(back) == len(frame)
    back = gpd.read_file(tmp_path / "cells.gpkg")
    assert np.allclose(back.geometry.area.to_numpy(), [c.area for c in nested.cells()])
    assert back["site"].tolist() == list(range(len(nested.sites)))
    e = gpd.read_file(tmp_path / "edges.gpkg")
    assert e[["site_i", "site_j"]].to_numpy().tolist() == nested.ridge_sites.tolist()
    assert nested.to_geopandas().cells.crs is None


def test_to_geopandas_without_geopandas(nested, monkeypatch):
    import sys

    monkeypatch.setitem(sys.modules, "geopandas", None)
    with pytest.raises(ImportError, match="geopandas"):
        nested.to_geopandas()


def test_nearest_in_blocks_equals_one_block(mixed, monkeypatch):
    from curvedvoronoi.runtime.voronoi import queries

    circles, d = mixed
    P = np.vstack([np.random.default_rng(8).uniform(-5, 45, (200, 2)), [[float(circles[0][0]) + 1.0, 0.0]] * 3,
                   [[2.0, 2.0]]])
    whole = d.nearest(P)
    monkeypatch.setattr(queries, "_CHUNK_PAIRS", 50)
    parts = d.nearest(P)
    assert all((getattr(whole, f) == getattr(parts, f)).all() for f in ("index", "distance", "proved", "exact"))
    assert whole.ties == parts.ties


# ---------------------------------------------------------------- segment sites
def _exact_segment_d2(q, a, b):
    """Squared distance from q to the closed segment [a, b] (Fractions; a = b: a point)."""
    dx, dy = b[0] - a[0], b[1] - a[1]
    L2 = dx * dx + dy * dy
    t = min(max(((q[0] - a[0]) * dx + (q[1] - a[1]) * dy) / L2, F(0)), F(1)) if L2 else F(0)
    return (q[0] - a[0] - t * dx) ** 2 + (q[1] - a[1] - t * dy) ** 2


def test_nearest_on_segment_sites_with_the_endpoint_convention():
    segs = [((F(0), F(0)), (F(4), F(0))), ((F(6), F(1)), (F(9), F(5)))]
    pts = [s[k] for s in segs for k in (0, 1)] + [(F(2), F(3))]
    sites = [cv.Point(*p) for p in pts] + [cv.Segment(*s) for s in segs]
    pieces = [(p, p) for p in pts] + segs
    d = cv.Diagram(sites)
    rng = np.random.default_rng(9)
    P = np.vstack([rng.uniform(-3, 12, (150, 2)), [[2.0, 1.5], [-1.0, -1.0], [4.0, 0.0], [5.0, -1.0], [2.0, -2.0]]])
    res = d.nearest(P)
    for row, p in enumerate(P):
        q = (F(float(p[0])), F(float(p[1])))
        D = [_exact_segment_d2(q, a, b) for a, b in pieces]
        want = [j for j, v in enumerate(D) if v == min(D)]
        # the interior of a segment tied with its own endpoint gives way to the endpoint
        want = [j for j in want if not (j >= len(pts) and set(pieces[j]) & {pieces[i][0] for i in want if i < len(pts)})]
        if len(want) == 1:
            assert res.index[row] == want[0] and res.proved[row], (p, want)
        else:
            assert res.ties[row] == tuple(want) and res.exact[row] and res.index[row] == -1, (p, want)
    assert res.ties == {150: (4, 5)} and res.index[151:].tolist() == [0, 1, 1, 5]
    assert np.allclose(res.distance[150:], [1.5, math.sqrt(2), 0.0, math.sqrt(2), 2.0])


def test_cells_of_segment_sites_tile():
    sites = [cv.Segment((0, 0), (4, 0)), cv.Point(2, 3), cv.Segment((6, 1), (9, 5))]
    d = cv.voronoi(sites)
    from curvedvoronoi.runtime.voronoi.cells import default_clip
    from curvedvoronoi.runtime.voronoi.queries import site_index

    box = default_clip(d)
    cells = d.cells()
    tol = max(e.tolerance for e in d.edges) + 1e-9
    _check_tiling(cells, shapely.box(*box), tol)
    for i, g in enumerate(site_index(d).geoms):
        S = g.samples(0.25, box)
        if g.kind == "segment":
            S = S[1:-1]                         # the open interior
        assert shapely.covers(cells[i].buffer(tol), shapely.points(S)).all(), i
