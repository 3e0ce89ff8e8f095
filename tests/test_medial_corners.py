"""The bisector of an ellipse and a site nested in it has corners where it crosses the ellipse's
medial axis (the segment of the major axis between the centres of curvature of the major
vertices): the verifier proves such closed edges (runtime.voronoi.verify.medial_corners, the
corner chords of runtime.voronoi.verify.curved), the construction puts a node at each corner
(runtime.voronoi.ridge_nodes), and a polyline that cuts a corner is refused.

References: the corners on the axis by mpmath (d(x, ellipse) by minimising over the ellipse's
parameter, the root of d_E − d_site by findroot) and, for the circle, by the closed form
d_E(X, 0) = b·√(1 − X²/(a² − b²)): 25X² − 42X − 315 = 0 for a = 10, b = 4 and the unit circle.
"""
from __future__ import annotations

import copy
import functools

import mpmath
import numpy as np
import pytest

import curvedvoronoi as cv
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify.medial_corners import medial_corners
from curvedvoronoi.runtime.voronoi.verify.site_table import SiteTable, run_lockstep
from curvedvoronoi.runtime.voronoi.verify.curved_edges import curved_scale

pytestmark = pytest.mark.mpmath_dps(40)

CIRCLE = ([cv.Conic.ellipse((0, 0), (10, 4)), (0, 0, 1)], (10, 4), (0, 1))       # (sites, axes, (x, r))
POINT = ([cv.Conic.ellipse((0, 0), (10, 5)), (1, 0)], (10, 5), (1, 0))


def ellipse_distance_mp(a, b, X):
    """d((X, 0), ellipse x²/a² + y²/b² = 1) by mpmath: the least of φ(θ) = |p(θ) − (X, 0)|² over
    its critical points (findroot of φ' from a dense grid) and θ = 0, π."""
    a, b, X = mpmath.mpf(a), mpmath.mpf(b), mpmath.mpf(X)
    phi = lambda t: (a * mpmath.cos(t) - X) ** 2 + (b * mpmath.sin(t)) ** 2
    dphi = lambda t: -2 * a * mpmath.sin(t) * (a * mpmath.cos(t) - X) + 2 * b * b * mpmath.sin(t) * mpmath.cos(t)
    best = min(phi(mpmath.mpf(0)), phi(mpmath.pi))
    grid = [mpmath.pi * k / 120 for k in range(1, 120)]
    for t0, t1 in zip(grid[:-1], grid[1:]):
        if dphi(t0) * dphi(t1) < 0:
            best = min(best, phi(mpmath.findroot(dphi, (t0, t1), solver="anderson")))
    return mpmath.sqrt(best)


@functools.lru_cache(maxsize=None)
def axis_corners_mp(axes, site):
    """The points X of the major axis's ridge |X| < (a² − b²)/a where d_E = d_site (mpmath)."""
    a, b = axes
    (x0, r) = site
    half = mpmath.mpf(a * a - b * b) / a
    g = lambda X: ellipse_distance_mp(a, b, X) - (abs(X - x0) - r)
    xs = [-half + 2 * half * k / 64 for k in range(1, 64)]
    roots = []
    for u, v in zip(xs[:-1], xs[1:]):
        if g(u) * g(v) < 0:
            roots.append(mpmath.findroot(g, (u, v), solver="anderson"))
    return roots


def verifier_corners(sites):
    """The verifier's enclosures of the corners of the closed edge of ``sites``."""
    d = cv.voronoi(sites, progress=False)
    e = d.edges[0]
    geoms = [site_geometry(s) for s in d.sites]
    scale = curved_scale(geoms)
    table = SiteTable(geoms, scale)
    (found,) = run_lockstep([medial_corners(table, tuple(e.sites), np.asarray(e.polyline), 1e-3, scale)], table)
    return d, found


@pytest.mark.parametrize("case", [CIRCLE, POINT], ids=["circle in 10x4", "point in 10x5"])
def test_certified_and_verified(case):
    d = cv.voronoi(case[0], progress=False)
    assert d.certified, d.problems
    assert len(d.edges) == 1 and d.edges[0].closed
    c = cv.verify(d)
    assert c.ok, c.problems


def test_circle_corner_closed_form():
    X = (42 + mpmath.sqrt(33264)) / 50             # 25X² − 42X − 315 = 0
    roots = axis_corners_mp(*CIRCLE[1:])
    assert len(roots) == 2
    assert abs(roots[1] - X) < mpmath.mpf(10) ** -30 and abs(roots[0] + X) < mpmath.mpf(10) ** -30


@pytest.mark.parametrize("case", [CIRCLE, POINT], ids=["circle in 10x4", "point in 10x5"])
def test_corner_enclosures_against_mpmath(case):
    d, found = verifier_corners(case[0])
    roots = sorted(float(x) for x in axis_corners_mp(*case[1:]))
    assert found is not None and len(found) == 2
    got = sorted(found, key=lambda c: c[1][0])
    for X, (h, m, r) in zip(roots, got):
        assert h == 0
        assert r < 1e-9
        assert m[1] == 0.0                         # the axis of an unrotated ellipse: exact floats
        assert abs(m[0] - X) <= r + 1e-15 * abs(X)
    # the construction's polyline has a node at each corner (within 1e-9)
    P = np.asarray(d.edges[0].polyline)
    for X in roots:
        assert np.hypot(P[:, 0] - X, P[:, 1]).min() < 1e-9


def corner_index(P, X):
    return int(np.argmin(np.hypot(P[:, 0] - X, P[:, 1])))


@pytest.mark.parametrize("case", [CIRCLE, POINT], ids=["circle in 10x4", "point in 10x5"])
def test_corner_moved_off_the_curve_is_refused(case):
    d = cv.voronoi(case[0], progress=False)
    X = max(float(x) for x in axis_corners_mp(*case[1:]))
    bad = copy.deepcopy(d)
    e = bad.edges[0]
    P = np.array(e.polyline, float)
    k = corner_index(P, X)
    P[k, 0] += 4 * e.tolerance                      # along the axis, off the bisector
    if k == 0 or k == len(P) - 1:
        P[0], P[-1] = P[k], P[k]
    e.polyline = P
    c = cv.verify(bad)
    assert not c.ok and not c.edges[0]
    assert any("from the bisector" in str(p) for p in c.problems), c.problems


def distance_mp(a, b, q):
    """d(q, ellipse x²/a² + y²/b² = 1) by mpmath (critical points of the squared distance)."""
    a, b = mpmath.mpf(a), mpmath.mpf(b)
    X, Y = mpmath.mpf(q[0]), mpmath.mpf(q[1])
    phi = lambda t: (a * mpmath.cos(t) - X) ** 2 + (b * mpmath.sin(t) - Y) ** 2
    dphi = lambda t: -2 * a * mpmath.sin(t) * (a * mpmath.cos(t) - X) + 2 * b * mpmath.cos(t) * (b * mpmath.sin(t) - Y)
    grid = [2 * mpmath.pi * k / 240 for k in range(241)]
    best = min(phi(t) for t in grid)
    for t0, t1 in zip(grid[:-1], grid[1:]):
        if dphi(t0) * dphi(t1) < 0:
            best = min(best, phi(mpmath.findroot(dphi, (t0, t1), solver="anderson")))
    return mpmath.sqrt(best)


def loop_point_mp(axes, site, psi):
    """The point of the loop around the nested site (centre (x0, 0), radius r) on the ray from
    its centre at angle psi: t − r = d(p + t·u, E), t − r − d nondecreasing (d is 1-Lipschitz)."""
    x0, r = site
    u = (mpmath.cos(psi), mpmath.sin(psi))
    g = lambda t: t - r - distance_mp(*axes, (x0 + t * u[0], t * u[1]))
    t = mpmath.findroot(g, (mpmath.mpf(r), mpmath.mpf(axes[0]) * 2), solver="anderson")
    return np.array([float(x0 + t * u[0]), float(t * u[1])])


@pytest.mark.parametrize("case", [CIRCLE, POINT], ids=["circle in 10x4", "point in 10x5"])
def test_corner_cut_by_a_chord_is_refused(case):
    """The nodes near the right corner replaced by two points of the bisector (mpmath) whose
    chord passes 2 stated tolerances from the corner: every node on the bisector, the chord
    not within the tolerance; refused, naming the corner."""
    d = cv.voronoi(case[0], progress=False)
    axes, site = case[1], case[2]
    X = max(axes_roots(axes, site))
    bad = copy.deepcopy(d)
    e = bad.edges[0]
    tol = e.tolerance
    # the angle psi whose chord is 2·tol from the corner
    psi = mpmath.findroot(lambda t: X - loop_point_mp(axes, site, t)[0] - 2 * tol, (mpmath.mpf("1e-3"), mpmath.mpf(1)),
                          solver="anderson", tol=1e-20)
    A, B = loop_point_mp(axes, site, psi), loop_point_mp(axes, site, -psi)
    gap = X - A[0]
    assert 1.9 * tol < gap < 2.1 * tol and abs(A[0] - B[0]) < 1e-12 and abs(A[1] + B[1]) < 1e-12
    P = np.array(e.polyline, float)[:-1]
    ang = np.arctan2(P[:, 1], P[:, 0] - site[0])
    keep = np.abs(ang) >= float(psi)
    P = P[keep]
    P = np.roll(P, -int(np.argmax(np.abs(np.arctan2(P[:, 1], P[:, 0] - site[0])))), axis=0)
    # the kept nodes run from the angle −π up to −psi and from psi on: insert B, A in order
    a2 = np.arctan2(P[:, 1], P[:, 0] - site[0])
    k = int(np.nonzero(np.diff(np.sign(a2)) != 0)[0][0]) + 1
    ring = np.vstack([P[:k], [B, A], P[k:]]) if a2[0] > 0 else np.vstack([P[:k], [A, B], P[k:]])
    e.polyline = np.vstack([ring, ring[:1]])
    c = cv.verify(bad)
    assert not c.ok and not c.edges[0]
    assert any("from the corner" in str(p) for p in c.problems), c.problems


def axes_roots(axes, site):
    return [float(x) for x in axis_corners_mp(axes, site)]


def test_rotated_ellipse_with_point():
    """A rotated, translated container: the corners are off the coordinate axes."""
    d = cv.voronoi([cv.Conic.ellipse((1, 2), (10, 5), degrees=30), (2, 2.5)], progress=False)
    assert d.certified, d.problems


@pytest.mark.parametrize("case", [CIRCLE, POINT], ids=["circle in 10x4", "point in 10x5"])
def test_coarse_enclosures_hold_the_corner(case, monkeypatch):
    """With no shrinking rounds the enclosure is the first bracket around the guide's crossing
    (width 0.74): the mpmath corner lies within its radius, and the radius is not slack (the
    corner is off the midpoint by more than a third of it for some corner)."""
    from curvedvoronoi.runtime.voronoi.verify import medial_corners as mc

    monkeypatch.setattr(mc, "ROUNDS", 0)
    d = cv.voronoi(case[0], progress=False)
    e = d.edges[0]
    geoms = [site_geometry(s) for s in d.sites]
    scale = curved_scale(geoms)
    table = SiteTable(geoms, scale)
    roots = sorted(axes_roots(*case[1:]))
    # a guide crossing the axis 0.2 right of the right corner and 0.15 left of the left one
    guide = np.array([[roots[1] + 0.2, -1], [roots[1] + 0.2, 1], [roots[0] - 0.15, 1], [roots[0] - 0.15, -1],
                      [roots[1] + 0.2, -1]])
    (found,) = run_lockstep([mc.medial_corners(table, tuple(e.sites), guide, 0.37, scale)], table)
    got = sorted(found, key=lambda c: c[1][0])
    assert len(got) == 2
    off = []
    for X, (h, m, r) in zip(roots, got):
        assert r >= 0.3
        assert abs(m[0] - X) <= r
        off.append(abs(m[0] - X) / r)
    assert max(off) > 1 / 3, off
