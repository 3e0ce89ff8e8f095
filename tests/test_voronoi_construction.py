"""The diagram construction (runtime/voronoi/construction.py) against independent references:

* a dense-grid labelling by nearest site (distances evaluated directly, not by the construction):
  every grid step across which the nearest site changes from i to j, with every other site
  clearly farther at both grid points, proves a point of the Voronoi edge (i, j) (distances are
  1-Lipschitz), so (i, j) must be reported; conversely every reported edge must be seen on the
  grid, and every reported polyline point / vertex must be equidistant from its sites with no
  other site closer;
* scipy's Delaunay triangulation for point sites (the classical Delaunay graph);
* relabelling under permutations of the input;
* bad input (intersecting / repeated sites) -> a one-line error, fast.
"""
from __future__ import annotations

import json
import math
import subprocess
import sys
import time
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial import Delaunay

from curvedvoronoi.runtime.predicates.circles import Circle, Point
from curvedvoronoi.runtime.sites.conic import Conic
from curvedvoronoi.runtime.voronoi.construction import SiteError, voronoi
from curvedvoronoi.runtime.voronoi.structure import Diagram

ROOT = Path(__file__).resolve().parents[1]


# ----------------------------------------------------------------------------- references

def _distance_fn(site):
    """Float distance to a site, written here independently for circles and points; conics use
    the site geometry's distance (foot points), which the construction does not define."""
    if isinstance(site, Circle):
        cx, cy, rho = float(site.cx), float(site.cy), math.sqrt(float(site.r2))
        return lambda P: np.abs(np.hypot(P[:, 0] - cx, P[:, 1] - cy) - rho)
    from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry

    return site_geometry(site).distance


def _dist_matrix(sites, P):
    return np.column_stack([_distance_fn(s)(P) for s in sites])


def grid_check(sites, d: Diagram, window, n=260):
    """Compare the reported diagram with a grid labelled by nearest site; returns the pairs seen."""
    x0, x1, y0, y1 = window
    xs = np.linspace(x0, x1, n)
    ys = np.linspace(y0, y1, n)
    h = max(xs[1] - xs[0], ys[1] - ys[0])
    X, Y = np.meshgrid(xs, ys)
    P = np.column_stack([X.ravel(), Y.ravel()])
    D = _dist_matrix(sites, P)
    order = np.argsort(D, axis=1)
    Ds = np.take_along_axis(D, order, axis=1)
    near = order[:, 0].reshape(n, n)
    # margin: the third site is farther than the second by more than 2h (both endpoints)
    third = Ds[:, 2] if D.shape[1] > 2 else np.full(len(P), np.inf)
    margin_ok = (third - Ds[:, 1] > 2 * h).reshape(n, n)
    second = order[:, 1].reshape(n, n)
    seen = set()
    reported = set(d.delaunay_edges())
    for a, b, ma, mb, sa, sb in (
            (near[:, :-1], near[:, 1:], margin_ok[:, :-1], margin_ok[:, 1:], second[:, :-1], second[:, 1:]),
            (near[:-1, :], near[1:, :], margin_ok[:-1, :], margin_ok[1:, :], second[:-1, :], second[1:, :])):
        m = (a != b) & ma & mb & (sa == b) & (sb == a)
        for i, j in zip(a[m].tolist(), b[m].tolist()):
            seen.add((min(i, j), max(i, j)))
    missing = seen - reported
    assert not missing, f"grid shows Voronoi edges {sorted(missing)} that are not reported"
    # conversely: a reported edge with a point inside the window where every third site is farther
    # by more than 6h must be seen on the grid (the grid cell holding it has corners nearest i and j)
    for e in d.edges:
        if e.sites in seen:
            continue
        Q = _densify(np.asarray(e.polyline), h / 2)
        Q = Q[(Q[:, 0] > x0 + 2 * h) & (Q[:, 0] < x1 - 2 * h) & (Q[:, 1] > y0 + 2 * h) & (Q[:, 1] < y1 - 2 * h)]
        if len(Q) == 0 or len(sites) < 3:
            continue
        DQ = np.sort(_dist_matrix(sites, Q), axis=1)
        assert not np.any(DQ[:, 2] - DQ[:, 1] > 6 * h), f"reported edge {e.sites} is not seen on the grid"
    return seen


def _densify(P, step):
    out = [P[:1]]
    for a, b in zip(P[:-1], P[1:]):
        k = max(1, int(np.ceil(np.hypot(*(b - a)) / step)))
        t = np.linspace(0, 1, k + 1)[1:, None]
        out.append(a + t * (b - a))
    return np.concatenate(out)


def check_points(sites, d: Diagram, rel=1e-7):
    """Every vertex is equidistant from its three sites with no site closer; every polyline point
    is equidistant from its two sites (up to its tolerance) with no other site closer."""
    for v in d.vertices:
        q = np.array([[v.x, v.y]])
        D = _dist_matrix(sites, q)[0]
        tol = rel * (1 + abs(v.x) + abs(v.y) + v.radius)
        assert all(abs(D[s] - v.radius) <= tol for s in v.sites), (v, D[list(v.sites)])
        others = [k for k in range(len(sites)) if k not in v.sites]
        if others:
            assert D[others].min() >= v.radius - tol, (v, D.min())
    for e in d.edges:
        P = np.asarray(e.polyline)
        assert len(P) >= 2
        D = _dist_matrix(sites, P)
        i, j = e.sites
        scale = 1 + np.abs(P).sum(axis=1)
        assert np.all(np.abs(D[:, i] - D[:, j]) / 2 <= e.tolerance + rel * scale), e
        others = [k for k in range(len(sites)) if k not in (i, j)]
        if others:
            assert np.all(D[:, others].min(axis=1) >= np.minimum(D[:, i], D[:, j]) - e.tolerance - rel * scale), e
        if e.closed:
            assert np.array_equal(P[0], P[-1]) and e.ends == (None, None)
        for side, vid in ((0, e.ends[0]), (-1, e.ends[1])):
            if vid is not None:
                v = d.vertices[vid]
                assert set(e.sites) <= set(v.sites)
                assert P[side].tolist() == [v.x, v.y]


def _window(sites, pad=0.6):
    boxes = []
    for s in sites:
        if isinstance(s, Circle):
            r = math.sqrt(float(s.r2))
            boxes.append((float(s.cx) - r, float(s.cy) - r, float(s.cx) + r, float(s.cy) + r))
        else:
            from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry

            boxes.append(site_geometry(s).bounding_box())
    b = np.array(boxes)
    x0, y0, x1, y1 = b[:, 0].min(), b[:, 1].min(), b[:, 2].max(), b[:, 3].max()
    w = max(x1 - x0, y1 - y0)
    return (x0 - pad * w, x1 + pad * w, y0 - pad * w, y1 + pad * w)


def ellipse(cx, cy, a, b, c=1, s=0):
    """The ellipse of centre (cx, cy), semi-axes a, b, rotated by (c, s) (c² + s² = 1), exact."""
    cx, cy, a, b, c, s = (Fraction(t) for t in (cx, cy, a, b, c, s))
    # u = (x−cx)c + (y−cy)s, v = −(x−cx)s + (y−cy)c; b²u² + a²v² − a²b² = 0
    A = b * b * c * c + a * a * s * s
    B = 2 * c * s * (b * b - a * a)
    C = b * b * s * s + a * a * c * c
    D = -2 * A * cx - B * cy
    E = -2 * C * cy - B * cx
    F = A * cx * cx + B * cx * cy + C * cy * cy - a * a * b * b
    return Conic.from_coefficients(A, B, C, D, E, F)


# ----------------------------------------------------------------------------- small facts

def test_three_circles_one_vertex_thesis_definition():
    d = voronoi([(0, 0, 1), (4, 0, 1), (2, 4, 1)], certify=False)
    assert d.delaunay_edges() == [(0, 1), (0, 2), (1, 2)]
    assert len(d.vertices) == 1 and len(d.edges) == 3
    v = d.vertices[0]
    # the vertex is on the symmetry axis x = 2: |(2, y)| − 1 = 4 − y − 1  ->  y = 1.5 − ... exactly:
    # sqrt(4 + y²) = 4 − y  ->  y = 3/2, radius = 5/2 − 1 = 3/2
    assert v.x == pytest.approx(2.0, abs=1e-12) and v.y == pytest.approx(1.5, abs=1e-12)
    assert v.radius == pytest.approx(1.5, abs=1e-12) and v.certified
    assert all(e.ends[1] is None for e in d.edges)  # three unbounded edges


def test_nested_circle_gives_closed_edge_prop_1_2_1():
    sites = [(0, 0, 5), (1, 0, 1), (9, 0, 1), (4, 8, 1)]
    d = voronoi(sites, certify=False)
    closed = [e for e in d.edges if e.closed]
    assert len(closed) == 1 and closed[0].sites == (0, 1) and closed[0].ends == (None, None)
    # the closed edge is the locus |q − c0| + |q − c1| ... check it encloses site 1's centre
    P = closed[0].polyline
    ang = np.unwrap(np.arctan2(P[:, 1], P[:, 0] - 1))
    assert abs(abs(ang[-1] - ang[0]) - 2 * math.pi) < 1e-6
    check_points([Circle.from_radius(*s) for s in sites], d)
    grid_check([Circle.from_radius(*s) for s in sites], d, _window([Circle.from_radius(*s) for s in sites]))


def test_circles_and_points_dense_grid():
    rng = np.random.default_rng(11)
    sites = []
    while len(sites) < 12:
        x, y, r = rng.uniform(0, 30), rng.uniform(0, 30), rng.choice([0.0, rng.uniform(0.5, 3)])
        if all(math.hypot(x - a, y - b) > r + s + 0.5 for a, b, s in sites):
            sites.append((float(x), float(y), float(r)))
    ex = [Point(x, y) if r == 0 else Circle.from_radius(x, y, r) for x, y, r in sites]
    d = voronoi(ex, certify=False)
    check_points(ex, d)
    seen = grid_check(ex, d, _window(ex, 0.3), n=300)
    assert len(seen) >= 15
    # the references fail on a corrupted diagram: a missing edge, a moved vertex
    import copy

    bad = copy.deepcopy(d)
    pair = d.edges[0].sites
    bad.edges = [e for e in bad.edges if e.sites != pair]
    with pytest.raises(AssertionError, match="not reported"):
        grid_check(ex, bad, _window(ex, 0.3), n=300)
    bad = copy.deepcopy(d)
    bad.vertices[0].x += 1e-3
    with pytest.raises(AssertionError):
        check_points(ex, bad)


def test_ellipses_and_points_dense_grid():
    sites = [ellipse(0, 0, 2, 1), ellipse(6, 0, 2, 1, Fraction(3, 5), Fraction(4, 5)),
             ellipse(3, 5, 1, Fraction(1, 2)), Point(3, 2), ellipse(-3, 5, Fraction(3, 2), 1, Fraction(5, 13), Fraction(12, 13)),
             Point(1, -4)]
    d = voronoi(sites, certify=False)
    assert all(v.certified for v in d.vertices), d.problems
    assert [p for p in d.problems if "certify=False" not in p] == []
    check_points(sites, d, rel=1e-6)
    grid_check(sites, d, _window(sites, 0.3), n=260)


def test_point_inside_ellipse_closed_edge():
    sites = [ellipse(0, 0, 4, 2), Point(Fraction(1, 2), Fraction(1, 3)), ellipse(10, 0, 1, 1 + Fraction(1, 2))]
    d = voronoi(sites, certify=False)
    closed = [e for e in d.edges if e.closed]
    assert [e.sites for e in closed] == [(0, 1)]
    check_points(sites, d, rel=1e-6)
    grid_check(sites, d, _window(sites, 0.3), n=240)


# ----------------------------------------------------------------------------- peers

@settings(max_examples=25)
@given(st.lists(st.tuples(st.integers(0, 60), st.integers(0, 60)), min_size=4, max_size=25, unique=True))
def test_points_equal_classical_delaunay(pts):
    P = np.array(pts, float)
    # general position only: skip collinear sets and cocircular quadruples (Delaunay not unique)
    if np.linalg.matrix_rank(P[1:] - P[0]) < 2:
        return
    tri = Delaunay(P)
    # a fourth point on a Delaunay circumcircle makes the Delaunay graph ambiguous: skip (the
    # in-circle determinant of integer points is an integer, exact in floats at this size)
    lifted = np.column_stack([P, (P ** 2).sum(1), np.ones(len(P))])
    for s in tri.simplices.tolist():
        for k in range(len(P)):
            if k not in s and round(np.linalg.det(np.vstack([lifted[s], lifted[k]]))) == 0:
                return
    expected = sorted({(min(a, b), max(a, b)) for s in tri.simplices.tolist()
                       for a, b in ((s[0], s[1]), (s[1], s[2]), (s[0], s[2]))})
    d = voronoi([(x, y, 0) for x, y in pts], certify=False)
    assert d.delaunay_edges() == expected


def test_permutation_relabels_the_same_diagram():
    rng = np.random.default_rng(5)
    sites = []
    while len(sites) < 40:
        x, y, r = rng.uniform(0, 60), rng.uniform(0, 60), rng.uniform(0.3, 2.5)
        if all(math.hypot(x - a, y - b) > r + s + 0.1 for a, b, s in sites):
            sites.append((float(x), float(y), float(r)))
    perm = rng.permutation(len(sites))
    d1 = voronoi(sites, certify=False)
    d2 = voronoi([sites[p] for p in perm], certify=False)
    back = {new: int(old) for new, old in enumerate(perm)}
    relabel = sorted(tuple(sorted((back[i], back[j]))) for i, j in d2.delaunay_edges())
    assert relabel == d1.delaunay_edges()
    v1 = sorted((tuple(sorted(v.sites)), round(v.x, 9), round(v.y, 9)) for v in d1.vertices)
    v2 = sorted((tuple(sorted(back[t] for t in v.sites)), round(v.x, 9), round(v.y, 9)) for v in d2.vertices)
    assert v1 == v2


# ----------------------------------------------------------------------------- errors

def test_intersecting_circles_named():
    with pytest.raises(SiteError, match=r"site 1 and site 2 intersect"):
        voronoi([(0, 0, 1), (5, 0, 1), (6, 0, 1)])
    with pytest.raises(SiteError, match=r"site 0 and site 1 intersect"):   # tangent circles touch
        voronoi([(0, 0, 1), (2, 0, 1), (9, 9, 1)])
    with pytest.raises(SiteError, match=r"site 0 and site 2 intersect"):   # a point on a circle
        voronoi([(0, 0, 5), (9, 9, 1), Point(3, 4)])
    # disjoint (nested, 1e-12 apart) is fine
    voronoi([Circle(0, 0, 1), Circle(0, 0, Fraction(1) - Fraction(1, 10 ** 12)), (5, 5, 1)], certify=False)


def test_intersecting_conics_named():
    with pytest.raises(SiteError, match=r"site 0 and site 1 intersect"):
        voronoi([ellipse(0, 0, 2, 1), ellipse(1, 0, 2, 1), Point(9, 9)])


def test_repeated_site_fast():
    rng = np.random.default_rng(3)
    sites = [(float(x), float(y), 0.0) for x, y in rng.uniform(0, 1000, (2000, 2))]
    sites.append(sites[1234])
    t = time.perf_counter()
    with pytest.raises(SiteError, match=r"site 1234 and site 2000 are the same site"):
        voronoi(sites)
    assert time.perf_counter() - t < 1.0
    with pytest.raises(ValueError, match="at least 2 sites"):
        voronoi([(0, 0, 1)])
    with pytest.raises(ValueError, match="not a site"):
        voronoi([(0, 0, 1), "circle"])


def test_time_limit_returns_partial_uncertified():
    d = voronoi([(0, 0, 1), (4, 0, 1), (2, 4, 1), (9, 9, 1)], time_limit=0.0)
    assert not d.certified and any("time limit" in p for p in d.problems)


# ----------------------------------------------------------------------------- certification and output

def test_certified_by_the_verifier_and_json_roundtrip(tmp_path):
    sites = [(0, 0, 1), (4, 0, 1), (2, 4, 1), (2, 1.2, 0), (0, 0, 0.25), (8, 3, 1)]
    d = voronoi(sites)
    assert d.certified, d.problems
    doc = json.loads(json.dumps(d.to_json()))
    assert doc["format"] == "curvedvoronoi.diagram/2"
    assert doc["delaunay_edges"] == [list(p) for p in d.delaunay_edges()]
    d2 = Diagram.from_json(doc)
    assert d2.sites == d.sites           # exact rationals
    assert d2.delaunay_edges() == d.delaunay_edges()
    assert [np.asarray(e.polyline).tolist() for e in d2.edges] == [e.polyline.tolist() for e in d.edges]
    gj = d.to_geojson()
    kinds = [f["properties"]["kind"] for f in gj["features"]]
    assert kinds.count("edge") == len(d.edges) and kinds.count("vertex") == len(d.vertices)
    G = d.to_networkx()
    assert sorted(tuple(sorted(e)) for e in G.edges()) == sorted(tuple(e.sites) for e in d.edges)


def test_verifier_rejects_a_corrupted_construction():
    """The construction's output is checked by the verifier, which must notice a wrong diagram."""
    d = voronoi([(0, 0, 1), (4, 0, 1), (2, 4, 1), (8, 3, 1)])
    assert d.certified
    from curvedvoronoi.runtime.voronoi.verify.certificate import verify

    doc = d.to_json()
    doc["edges"] = doc["edges"][1:]
    assert not verify(doc).ok


def test_cli_diagram(tmp_path):
    pytest.importorskip("matplotlib")
    f = tmp_path / "sites.json"
    f.write_text(json.dumps({"sites": [{"circle": {"centre": [0, 0], "radius": 1}},
                                       {"circle": {"centre": ["4", "0"], "radius": "1"}},
                                       {"point": [2, 4]}, {"circle": {"centre": [0, 0], "radius": 8}}]}))
    out, png, gj = tmp_path / "d.json", tmp_path / "d.png", tmp_path / "d.geojson"
    r = subprocess.run([sys.executable, "-m", "curvedvoronoi", "diagram", str(f), "--json", str(out), "--png", str(png),
                        "--geojson", str(gj), "--quiet"], cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    doc = json.loads(out.read_text())
    assert doc["format"] == "curvedvoronoi.diagram/2" and doc["certified"] is True
    # three sites nested in site 3: a triangle of mutual edges, site 1 (nearest the rim) touches site 3
    assert {(0, 1), (0, 2), (1, 2), (1, 3)} <= {tuple(p) for p in doc["delaunay_edges"]}
    assert png.stat().st_size > 1000 and json.loads(gj.read_text())["type"] == "FeatureCollection"
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"sites": [{"circle": {"centre": [0, 0], "radius": 1}},
                                         {"circle": {"centre": [1, 0], "radius": 1}}]}))
    r = subprocess.run([sys.executable, "-m", "curvedvoronoi", "diagram", str(bad)], cwd=ROOT,
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 2 and "site 0 and site 1 intersect" in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1


def test_cocircular_points_give_one_certified_vertex_of_degree_four():
    """Four points on one empty circle (a square): the vertex (1/2, 1/2) has degree 4 (the exact
    §3.1.3 test finds the fourth site tangent, not inside).  It is one vertex listing the four
    corners counter-clockwise, with four edges; the diagonals are not Delaunay edges."""
    d = voronoi([(0, 0, 0), (1, 0, 0), (0, 1, 0), (1, 1, 0)])
    assert d.certified, d.problems
    assert len(d.vertices) == 1
    v = d.vertices[0]
    assert (v.x, v.y, v.radius) == pytest.approx((0.5, 0.5, math.sqrt(0.5)), abs=1e-12)
    # counter-clockwise from (0, 0): (1, 0), (1, 1), (0, 1) -> sites 0, 1, 3, 2
    assert v.sites == (0, 1, 3, 2) and v.degree == 4
    assert d.delaunay_edges() == [(0, 1), (0, 2), (1, 3), (2, 3)]
    assert len(d.edges) == 4 and all(e.ends.count(0) == 1 and None in e.ends for e in d.edges)


def test_two_and_collinear_points():
    """No triangulation exists: the edges are the perpendicular bisectors of consecutive points."""
    d = voronoi([(0, 0, 0), (1, 0, 0)])
    assert d.certified and d.delaunay_edges() == [(0, 1)] and d.edges[0].ends == (None, None)
    d = voronoi([(2, 2, 0), (0, 0, 0), (1, 1, 0), (5, 5, 0)], certify=False)
    assert d.delaunay_edges() == [(0, 2), (0, 3), (1, 2)] and not d.vertices
    check_points([Point(2, 2), Point(0, 0), Point(1, 1), Point(5, 5)], d)


@pytest.mark.parametrize("g", [0.004, 0.001])
def test_hull_neighbours_far_apart_keep_their_unbounded_edge(g):
    # circles 0 and 1 have the common supporting line y = −1 and circle 2 lies above it by g, so 0
    # and 1 are consecutive on the convex hull of the sites: the points (50, −t), t → ∞, are
    # nearest to 0 and 1 (their distances differ by o(1) and circle 2 is farther by about g), an
    # unbounded Voronoi edge (0, 1).  With 11 samples per circle the lowest samples of 0 and 1
    # sit 0.0102 above the line and a sample of circle 2 sticks out below their chord.
    circ = [(0.0, 0.0, 1.0), (100.0, 0.0, 1.0), (50.0, -1.0 + g + 0.5, 0.5), (50.0, 20.0, 1.0),
            (20.0, 8.0, 2.0), (80.0, 9.0, 1.5)]
    d = voronoi(circ, certify=False)
    assert (0, 1) in d.delaunay_edges()
    e = [e for e in d.edges if e.sites == (0, 1)]
    assert len(e) == 1 and None in e[0].ends
    assert all(v.certified for v in d.vertices)
    check_points([Circle.from_radius(*c) for c in circ], d)


# ----------------------------------------------------------------------------- order and edge interiors

def test_site_order_does_not_change_the_diagram():
    """The diagram is a function of the set of sites (thesis §1.2): a permuted input gives the
    permuted Delaunay graph and the same vertices (insertion-order independence)."""
    sites = [ellipse(0, 0, 2, 1), ellipse(6, 0, 2, 1, Fraction(3, 5), Fraction(4, 5)),
             ellipse(3, 5, 1, Fraction(1, 2)), Point(3, 2), Circle(-4, 1, 1),
             ellipse(-3, 6, Fraction(3, 2), 1, Fraction(5, 13), Fraction(12, 13)), Point(1, -4), Circle(8, 6, 2)]
    rng = np.random.default_rng(5)
    d = voronoi(sites, certify=False)
    for _ in range(2):
        perm = rng.permutation(len(sites))               # new index k holds old site perm[k]
        dp = voronoi([sites[i] for i in perm], certify=False)
        assert all(v.certified for v in dp.vertices)
        back = {tuple(sorted((int(perm[a]), int(perm[b])))) for a, b in dp.delaunay_edges()}
        assert back == {tuple(sorted(e)) for e in d.delaunay_edges()}
        P = np.array([[v.x, v.y] for v in d.vertices])
        Q = np.array([[v.x, v.y] for v in dp.vertices])
        assert len(P) == len(Q)
        gap = np.min(np.hypot(*(P[:, None, :] - Q[None, :, :]).transpose(2, 0, 1)), axis=1)
        assert gap.max() < 1e-8 * (1 + np.abs(P).max())


def test_a_small_site_cutting_an_edge_in_its_interior():
    """Edge-interior conflict built on purpose: two ellipses far apart share a long edge; a small
    circle near the middle of that edge, far from both of the edge's ends (which lie on the hull:
    the edge is a line-like curve infinite both ways), cuts the edge in its interior.  With it, the
    edge (0, 1) splits in two pieces around the circle's region and the circle has edges with both
    ellipses; deleting the circle restores the single edge (0, 1)."""
    A, B = ellipse(-10, 0, 2, 1), ellipse(10, 0, 2, 1, Fraction(3, 5), Fraction(4, 5))
    small = Circle(0, Fraction(1, 2), Fraction(1, 4))
    d0 = voronoi([A, B], certify=False)
    assert sorted(tuple(sorted(e)) for e in d0.delaunay_edges()) == [(0, 1)]
    d = voronoi([A, B, small], certify=False)
    assert {tuple(sorted(e)) for e in d.delaunay_edges()} == {(0, 1), (0, 2), (1, 2)}
    assert len([e for e in d.edges if tuple(sorted(e.sites)) == (0, 1)]) == 2      # the edge is cut
    assert all(v.certified for v in d.vertices) and len(d.vertices) == 2
    check_points([A, B, small], d, rel=1e-6)
    grid_check([A, B, small], d, (-14, 14, -8, 8), n=220)
    back = d.delete_site(2, certify=False)
    assert sorted(tuple(sorted(e)) for e in back.delaunay_edges()) == [(0, 1)]
    assert len(back.edges) == 1 and not back.vertices


#: nine ellipses of the 512-ellipse benchmark scene (bench/bench_voronoi.py, random_ellipses(512, 1)),
#: primitive integer coefficients; sites 3 and 8 are about 0.14 apart
NARROW_GAP = [
    (11075584, 22708224, 17698816, -6769565184, -8490006912, 1133549099321),
    (23007232, -8552448, 20512768, -6557670272, -3456170496, 744261934753),
    (300032, -73728, 278528, -92455488, -50324224, 10593883593),
    (1282048, 534528, 1437952, -503605248, -435684864, 69231081087),
    (790528, -688128, 589824, -185755520, -20384256, 16733300641),
    (69136, -88704, 43264, -14156758, 5587256, 930804581),
    (589824, 1081344, 905216, -328422912, -392126336, 50778761909),
    (999424, 958464, 1278976, -451835648, -475740864, 67059119349),
    (692224, 0, 1048576, -241867392, -247955456, 35784615057),
]


def test_edge_through_a_narrow_gap_between_two_ellipses():
    """The edge of two ellipses 0.14 apart runs through the gap between them: its polyline points are
    equidistant from both (independent oracle, tests/reference.py), it never turns by 60 degrees or
    more, its stated tolerance is small, and the verifier proves the diagram.  (Circumcentres of the
    sample triangulation that lie inside a site were once kept unprojected: a polyline zigzagging
    through the gap with a stated tolerance of 23, which the verifier refused.)"""
    from reference import ref_distance
    from curvedvoronoi.runtime.voronoi.verify.certificate import verify

    sites = [Conic.from_coefficients(*c) for c in NARROW_GAP]
    d = voronoi(sites, certify=False)
    (e,) = [e for e in d.edges if set(e.sites) == {3, 8}]
    assert e.tolerance < 1e-2
    P = np.asarray(e.polyline)
    T = np.diff(P, axis=0)
    T /= np.hypot(T[:, 0], T[:, 1])[:, None]
    assert np.all((T[1:] * T[:-1]).sum(axis=1) > math.cos(math.radians(60)))
    gap = math.inf
    for x, y in P[1:-1]:
        di, dj = float(ref_distance(sites[3], x, y)), float(ref_distance(sites[8], x, y))
        assert abs(di - dj) <= 1e-6 * max(di, dj) + 1e-9
        gap = min(gap, di + dj)
    assert gap < 0.2
    cert = verify(d, sites)
    assert cert.ok, cert.problems


def test_closed_edge_of_a_point_near_the_boundary_of_its_ellipse_winds_around_it():
    """A point 0.2 inside an ellipse: its closed edge is the loop {q : |q − p| = d(q, E)} around it
    (the point's region is star-shaped from p).  The polyline must wind once around p and lie on
    the bisector (independent oracle).  (The circumcentres of the coarse sample triangulation once
    gave a path out and back along one side, winding number 0.)"""
    from reference import ref_distance

    p = Point(Fraction(-13, 10), Fraction(-2, 5))
    e = Conic.from_coefficients(11232025, 6552000, 2800225, 24616830, 13451965, 12765159)
    sites = [p, Point(Fraction(-7, 5), Fraction(29, 10)), e]
    d = voronoi(sites, certify=False)
    (loop,) = [ed for ed in d.edges if ed.closed]
    assert set(loop.sites) == {0, 2}
    P = np.asarray(loop.polyline) - np.array([float(p.cx), float(p.cy)])
    ang = np.unwrap(np.arctan2(P[:, 1], P[:, 0]))
    assert abs(abs(ang[-1] - ang[0]) - 2 * math.pi) < 1e-9
    for x, y in np.asarray(loop.polyline)[::4]:
        dp = math.hypot(x - float(p.cx), y - float(p.cy))
        assert abs(dp - float(ref_distance(e, x, y))) <= 1e-6 * dp + 1e-9
