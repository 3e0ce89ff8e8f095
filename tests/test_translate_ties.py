"""Translates of one rotated ellipse on a square grid tie at infinity in the axis directions
(runtime/voronoi/verify/tied_tail.py): h_k(u) = c_k·u + √S with the same irrational √S for every
translate, so the sites of a column tie exactly in the directions ±x and those of a row in ±y, and
their unbounded edges are parallel there.  The levels are compared exactly
(:func:`same_level`), the lateral coordinates of the support points through rational enclosures.

The reference uses none of the library's geometry: distances to each ellipse by dense sampling of
its parametrised boundary c + R(θ)(a cos t, b sin t); the Delaunay pairs are read from the nearest
site on a fine grid, the unbounded edges from the nearest sites on a circle of radius 10⁵."""
from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest

import curvedvoronoi as cv
from curvedvoronoi.runtime.voronoi.verify.tied_tail import Support, same_level, support_data


def grid(nx, ny, a, b, degrees, step=10, shift=None):
    out = []
    for x in range(nx):
        for y in range(ny):
            cx, cy = x * step, y * step
            if shift is not None and (x, y) == shift[0]:
                cx += shift[1]
            out.append((cx, cy, a, b, degrees))
    return out


def sites_of(scene):
    return [cv.Conic.ellipse((cx, cy), (a, b), degrees=deg) for cx, cy, a, b, deg in scene]


def distances(scene, X, Y, m=2000):
    t = np.linspace(0, 2 * np.pi, m, endpoint=False)
    out = []
    for cx, cy, a, b, deg in scene:
        r = math.radians(deg)
        bx = cx + a * np.cos(t) * math.cos(r) - b * np.sin(t) * math.sin(r)
        by = cy + a * np.cos(t) * math.sin(r) + b * np.sin(t) * math.cos(r)
        D = np.full(X.shape, np.inf)
        for k in range(0, m, 250):
            D = np.minimum(D, np.hypot(X[..., None] - bx[k:k + 250], Y[..., None] - by[k:k + 250]).min(-1))
        out.append(D)
    return np.stack(out)


def reference_pairs(scene, lo, hi, n=240):
    X, Y = np.meshgrid(np.linspace(lo, hi, n), np.linspace(lo, hi, n))
    first = distances(scene, X, Y).argmin(0)
    pairs = set()
    for a, b in ((first[:, 1:], first[:, :-1]), (first[1:, :], first[:-1, :])):
        for i, j in zip(a[a != b].tolist(), b[a != b].tolist()):
            pairs.add((min(i, j), max(i, j)))
    return pairs


def reference_unbounded(scene, centre, radius=1e5, half=100.0, step=0.05, n=20000):
    """Pairs of sites nearest at consecutive points far away: on four segments of lateral half-width
    ``half`` at distance ``radius`` in the axis directions (where translates tie: sampled every
    ``step``), and on the circle of that radius outside those segments' angular windows."""
    pairs = set()
    s = np.arange(-half, half, step)
    for ux, uy in ((1, 0), (-1, 0), (0, 1), (0, -1)):
        X, Y = centre[0] + radius * ux - s * uy, centre[1] + radius * uy + s * ux
        owner = distances(scene, X, Y, m=1500).argmin(0)
        pairs |= {tuple(sorted((int(a), int(b)))) for a, b in zip(owner[:-1], owner[1:]) if a != b}
    th = np.linspace(0, 2 * np.pi, n, endpoint=False)
    window = half / radius
    axis = np.abs((th + np.pi / 4) % (np.pi / 2) - np.pi / 4) < window
    owner = distances(scene, centre[0] + radius * np.cos(th), centre[1] + radius * np.sin(th), m=1500).argmin(0)
    nxt, nxt_axis = np.roll(owner, -1), np.roll(axis, -1)
    pairs |= {tuple(sorted((int(a), int(b)))) for a, b, w, w2 in zip(owner, nxt, axis, nxt_axis)
              if a != b and not w and not w2}
    return pairs


@pytest.mark.parametrize("nx, ny, degrees", [(3, 3, 10), pytest.param(3, 3, 45, marks=pytest.mark.slow),
                                              pytest.param(4, 2, 30, marks=pytest.mark.slow)])
def test_a_grid_of_rotated_translates_is_certified_and_matches_the_reference(nx, ny, degrees):
    scene = grid(nx, ny, 3, 2, degrees)
    d = cv.voronoi(sites_of(scene), progress=False)
    assert d.certified, d.problems[:3]
    ref = reference_pairs(scene, -15, 10 * max(nx, ny) + 5)
    ref |= reference_unbounded(scene, (5 * (nx - 1), 5 * (ny - 1)))
    assert set(d.delaunay_edges()) == ref
    unbounded = {tuple(e.sites) for e in d.edges if None in e.ends}
    assert unbounded == reference_unbounded(scene, (5 * (nx - 1), 5 * (ny - 1)))


def test_a_translate_moved_off_the_tie_is_not_taken_for_a_tie():
    """The middle ellipse of a column moved right by 10⁻⁹: it leads alone in the direction +x;
    its exact level differs, so the tie route refuses.  The combinatorial diagram is unchanged
    (the column's order at infinity stays the same), so a certified answer equals the reference."""
    scene = grid(2, 3, 3, 2, 45, shift=((1, 1), 1e-9))
    u = (Fraction(1), Fraction(0))
    sites = sites_of(scene)
    moved, above = support_data(sites[4], u), support_data(sites[5], u)
    assert not same_level(moved, above)
    assert same_level(support_data(sites[3], u), above)
    d = cv.voronoi(sites, progress=False)
    if d.certified:
        assert set(d.delaunay_edges()) == reference_pairs(scene, -15, 35) | reference_unbounded(scene, (5, 10))


def test_same_level_is_exact():
    """a.cu + √a.S = b.cu + √b.S decided exactly: equal irrational roots, rational roots with
    different offsets, and near-ties of 10⁻³⁰ either way."""
    S = lambda cu, s: Support(Fraction(cu), Fraction(s), (0, 0), (0, 0), 0, 0)   # noqa: E731
    assert same_level(S(1, 2), S(1, 2))
    assert not same_level(S(1, 2), S(1, Fraction(2) + Fraction(1, 10 ** 30)))
    assert same_level(S(0, Fraction(9, 4)), S(1, Fraction(1, 4)))          # 3/2 = 1 + 1/2
    assert same_level(S(1, Fraction(1, 4)), S(0, Fraction(9, 4)))
    assert not same_level(S(0, Fraction(9, 4)), S(1, Fraction(1, 4) + Fraction(1, 10 ** 30)))
    assert not same_level(S(0, 2), S(Fraction(1, 10 ** 30), 2))
    assert not same_level(S(0, 8), S(Fraction(1), 2))                       # 2√2 ≠ 1 + √2
    assert same_level(S(0, 8), S(0, 8)) and not same_level(S(0, 8), S(0, 2))
    # √x − √y = d rational with x, y not squares only when d = 0: 3√2 − 2√2 = √2 is irrational
    assert not same_level(S(0, 18), S(Fraction(1), 8))
    # squaring admits √y = t < 0: 0 + √1 ≠ 1 + √4 although ((1 − 4 − 1)/2)² = 4
    assert not same_level(S(0, 1), S(1, 4))


@pytest.mark.parametrize("seed", range(5))
def test_support_enclosures_bracket_the_support_point(seed):
    """The level and the lateral coordinate of a rotated ellipse's support point in u = (3/5, 4/5)
    against the closed form h = c·u + √(a²(u·e₁)² + b²(u·e₂)²) evaluated with mpmath at 200 digits;
    the enclosures are narrower than 10⁻³⁰."""
    import mpmath
    with mpmath.workdps(200):
        rng = np.random.default_rng(seed)
        cx, cy = (float(v) for v in rng.uniform(-50, 50, 2))
        a, b, deg = float(rng.uniform(1, 5)), float(rng.uniform(0.3, 1)), float(rng.uniform(0, 180))
        site = cv.Conic.ellipse((cx, cy), (a, b), degrees=deg)
        u = (Fraction(3, 5), Fraction(4, 5))
        sd = support_data(site, u)
        lo, hi = sd.level()
        llo, lhi = sd.lateral((-u[1], u[0]))
        # the conic's exact coefficients define the ellipse; recover its axes from them in mpmath
        A, B, C, D, E, F = (mpmath.mpf(Fraction(x).numerator) / Fraction(x).denominator for x in sd_coefficients(site))
        M = mpmath.matrix([[A, B / 2], [B / 2, C]])
        cen = mpmath.lu_solve(M, mpmath.matrix([-D / 2, -E / 2]))
        kappa = (cen.T * M * cen)[0] - F
        U = mpmath.matrix([mpmath.mpf(3) / 5, mpmath.mpf(4) / 5])
        W = mpmath.lu_solve(M, U) * kappa
        h = (cen.T * U)[0] + mpmath.sqrt((W.T * U)[0])
        p = cen + W / mpmath.sqrt((W.T * U)[0])
        lat = -p[0] * U[1] + p[1] * U[0]
        assert mpmath.mpf(lo.numerator) / lo.denominator <= h <= mpmath.mpf(hi.numerator) / hi.denominator
        assert mpmath.mpf(llo.numerator) / llo.denominator <= lat <= mpmath.mpf(lhi.numerator) / lhi.denominator
        assert hi - lo < Fraction(1, 10 ** 30) and lhi - llo < Fraction(1, 10 ** 30)
        assert abs(float(h) - (cx * 0.6 + cy * 0.8) - math.hypot(a * math.cos(math.radians(deg) - math.atan2(0.8, 0.6)),
                                                                b * math.sin(math.radians(deg) - math.atan2(0.8, 0.6)))) < 1e-9


def sd_coefficients(site):
    from curvedvoronoi.runtime.predicates.symmetry import site_coefficients
    return site_coefficients(site)


def test_a_far_vertex_above_a_row_of_translates_is_proved():
    """Translates at (0, 0), (7, 0), (13, 1/4): the first two tie downwards (parallel edges), the
    third leads upwards, so the bisector x = 3.5 of the first two ends at a vertex about 156 above
    the row, outside the disc where the edges' finite parts are cut; the edge of (0, 1) runs from
    there across the scene down to infinity."""
    scene = [(0, 0, 2, 1, 0), (7, 0, 2, 1, 0), (13, 0.25, 2, 1, 0)]
    d = cv.voronoi(sites_of(scene), progress=False)
    assert d.certified, d.problems[:3]
    (v,) = d.vertices
    D = distances(scene, np.array([v.x]), np.array([v.y]), m=20000)[:, 0]
    assert 100 < v.y < 250 and abs(v.x - 3.5) < 1e-6
    assert D.max() - D.min() < 1e-3 and abs(D.mean() - v.radius) < 1e-3
    assert {tuple(e.sites) for e in d.edges if None in e.ends} == reference_unbounded(scene, (6.5, 0))
