"""Samples co-circular within qhull's roundoff: where a site was found entering a candidate's
circle, the segment construction reads the next candidates off the *exact* Delaunay diagonal of
the samples (Lawson's flips, runtime/voronoi/exact_delaunay.lawson_flips, applied by
SampleTriangulation.legalized from runtime/segments/construction._entered_flipped).

The scene is cut from ``tests/scenes.random_segments(30008, 1)``: the point sites B = (4357, 9327),
C = (4351, 9284), P = (4314, 9313) are nearly co-circular with the segment s = [B, (4338, 9344)]
ending at B.  The circle of B, C and P has its centre 1.1·10⁻⁴ on s's side of the normal of s at
B, so s enters it by only 2.4·10⁻¹⁰: the true diagram has the vertices (B, s, C) and (C, P, s),
1.3·10⁻⁴ apart, and the only sample of s that can show it is s's point nearest to the centre,
inside the circle of the samples B, C, P by that hair.  At 4·10⁵ samples of coordinates 10⁴ qhull
merged the four samples' facets and drew the diagonal B–P: the candidate (B, C, P) was entered by
s and (B, P, s) by C, round after round, and the batch build of the 30008 segments was not
certified (four vertices each missing an edge).  A small scene does not reach qhull's roundoff,
so the tests below give the construction triangulations whose near-co-circular quadrilaterals
(within 10⁻¹² of the coordinates) have the other diagonal, as qhull's merged facets may.
Truth: CGAL's Segment_Delaunay_graph_2 (exact) and brute-force exact incircle tests."""
from __future__ import annotations

import sys
from fractions import Fraction
from itertools import combinations
from pathlib import Path

import numpy as np
import pytest

import curvedvoronoi as cv
from curvedvoronoi.runtime.segments import construction
from curvedvoronoi.runtime.voronoi.exact_delaunay import lawson_flips
from curvedvoronoi.runtime.voronoi.sample_delaunay import SampleTriangulation, circumcentres, side_neighbours

sys.path.insert(0, str(Path(__file__).parent))
sys.path.insert(0, str(Path(__file__).with_name("cgal")))
import sdg_peer  # noqa: E402

B, C, P = (4357, 9327), (4351, 9284), (4314, 9313)
SEGMENTS = [(B, (4338, 9344)), ((4332, 9270), C), ((4315, 9324), P)]
#: s's point nearest to the circumcentre of B, C, P, as the construction samples it (a float)
F = (4356.999917193289, 9327.000074090216)
#: co-circular within this much of the coordinates: F is 2.4·10⁻¹⁰ inside the circle of B, C, P
#: at coordinates 10⁴, and qhull took the four for co-circular
TOL = 1e-12


def _det(a, b, c, d) -> Fraction:
    """Exact incircle determinant of float or integer points: > 0 when d is strictly inside the
    circle of the counter-clockwise a, b, c."""
    rows = [[Fraction(x) - Fraction(d[0]), Fraction(y) - Fraction(d[1])] for x, y in (a, b, c)]
    m = [[x, y, x * x + y * y] for x, y in rows]
    return (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))


def _ccw(a, b, c) -> Fraction:
    return (Fraction(b[0]) - Fraction(a[0])) * (Fraction(c[1]) - Fraction(a[1])) - \
        (Fraction(b[1]) - Fraction(a[1])) * (Fraction(c[0]) - Fraction(a[0]))


def _other_diagonal(tri: SampleTriangulation, tol: float) -> SampleTriangulation:
    """``tri`` with the other diagonal in every strictly convex quadrilateral of two triangles whose
    four corners are co-circular within ``tol`` times the largest coordinate (one of them that close
    to the circle of the other three, in floats; each triangle in one such flip at most): a triangulation qhull may return for
    samples co-circular within its roundoff."""
    Q, S = tri.P, tri.simp.copy()
    scale = float(np.abs(Q).max())
    used = np.zeros(len(S), bool)
    for t in range(len(S)):
        for k in range(3):
            u = int(tri.nb[t, k])
            if u < 0 or used[t] or used[u] or u < t:
                continue
            p, q, r = (int(S[t, (k + j) % 3]) for j in range(3))
            if _ccw(Q[p], Q[q], Q[r]) < 0:
                q, r = r, q
            s = next(int(v) for v in S[u] if v not in (q, r))
            quad = (p, q, r, s)
            gap = np.inf
            for x in quad:                      # the fourth point against the others' circle
                o = [i for i in quad if i != x]
                with np.errstate(invalid="ignore", divide="ignore"):
                    centre = circumcentres(*(Q[[i]] for i in o))[0]
                    g = abs(np.hypot(*(Q[x] - centre)) - np.hypot(*(Q[o[0]] - centre)))
                if np.isfinite(g):              # three collinear points: no circle
                    gap = min(gap, g)
            if not gap <= tol * scale or _ccw(Q[p], Q[q], Q[s]) <= 0 or _ccw(Q[p], Q[s], Q[r]) <= 0:
                continue
            S[t], S[u] = (p, q, s), (p, s, r)
            used[t] = used[u] = True
    nb = side_neighbours(S, len(Q))
    return SampleTriangulation(Q, tri.lab, S, nb)


def _keys(d):
    def key(site):
        if isinstance(site, cv.Segment):
            return sdg_peer.segment_key(site.p, site.q)
        return sdg_peer.point_key(Fraction(str(site.x)), Fraction(str(site.y)))
    keys = [key(s) for s in d.sites]
    return {frozenset((keys[i], keys[j])) for i, j in d.delaunay_edges()}


def test_the_nearest_point_of_s_is_strictly_inside_the_circle_of_b_c_p():
    """The fact the construction relies on, in exact arithmetic: the float sample F lies strictly
    inside the circle of B, C, P, by a hair, and the Delaunay diagonal of the quadrilateral B, F, P, C
    is F–C."""
    a, b, c = (B, C, P) if _ccw(B, C, P) > 0 else (B, P, C)
    assert _det(a, b, c, F) > 0
    assert _det(a, b, c, F) < Fraction(1, 10 ** 4) * max(abs(x) for x in F) ** 2     # by a hair
    # the triangles (B, F, C) and (F, P, C) have empty circles among the four points
    for tri_, other in (((B, F, C), P), ((F, P, C), B)):
        t = tri_ if _ccw(*tri_) > 0 else (tri_[0], tri_[2], tri_[1])
        assert _det(*t, other) < 0


def test_lawson_flips_give_the_exact_delaunay_triangulation():
    """qhull's diagonal B–P of the quadrilateral B, F, P, C (with a ring of points around it) is
    flipped to F–C, and the result is Delaunay: no point strictly inside any triangle's circle
    (brute force, exact rationals)."""
    ring = [(4335 + 60 * np.cos(a), 9310 + 60 * np.sin(a)) for a in np.linspace(0, 2 * np.pi, 9)[:-1]]
    pts = np.array([B, F, P, C] + ring, float)
    from scipy.spatial import Delaunay
    d = Delaunay(pts)
    wrong = _other_diagonal(SampleTriangulation(pts, np.arange(len(pts)), d.simplices, d.neighbors), 1e-12)
    has = {frozenset(map(int, t)) for t in wrong.simp}
    assert frozenset((0, 2, 3)) in has, "the emulated qhull output has the diagonal B–P"
    got = lawson_flips(wrong.P, wrong.simp, wrong.nb)
    assert got is not None
    simp, nb, changed = got
    assert len(changed) >= 2
    tris = {frozenset(map(int, t)) for t in simp}
    assert frozenset((0, 1, 3)) in tris and frozenset((1, 2, 3)) in tris
    assert np.array_equal(nb, side_neighbours(simp, len(pts)))
    for t in simp.tolist():
        a, b, c = (pts[i] for i in t)
        assert _ccw(a, b, c) > 0
        for m in range(len(pts)):
            if m not in t:
                assert _det(a, b, c, pts[m]) <= 0
    # an exact Delaunay triangulation needs no flip
    assert lawson_flips(pts, simp, nb) is None


def test_delaunay_triangulations_of_random_points_need_no_flip_and_wrong_ones_are_repaired():
    """Random integer points (many co-circular quadruples): qhull's triangulation flipped at random
    interior edges (convex quadrilaterals) is repaired into one with every circle empty."""
    from scipy.spatial import Delaunay
    rng = np.random.default_rng(5)
    pts = rng.integers(0, 12, (60, 2)).astype(float)
    pts = np.unique(pts, axis=0)
    d = Delaunay(pts)
    wrong = _other_diagonal(SampleTriangulation(pts, np.arange(len(pts)), d.simplices, d.neighbors), 1.0)
    assert {frozenset(t) for t in wrong.simp.tolist()} != {frozenset(t) for t in d.simplices.tolist()}
    got = lawson_flips(wrong.P, wrong.simp, wrong.nb)
    assert got is not None
    simp = got[0]
    for t in simp.tolist():
        a, b, c = (pts[i] for i in t)
        if _ccw(a, b, c) < 0:
            b, c = c, b
        for m in range(len(pts)):
            if m not in t:
                assert _det(a, b, c, pts[m]) <= 0


@pytest.fixture
def roundoff_triangulations(monkeypatch):
    """Every sample triangulation the segment construction receives (full and local) with the
    other diagonal in its quadrilaterals co-circular within :data:`TOL` (what qhull did at 4·10⁵
    samples)."""
    full, local = construction.triangulation, construction.retriangulation

    def tri_full(*args, **kw):
        return _other_diagonal(full(*args, **kw), TOL)

    def tri_local(*args, **kw):
        got = local(*args, **kw)
        return None if got is None else _other_diagonal(got, TOL)

    monkeypatch.setattr(construction, "triangulation", tri_full)
    monkeypatch.setattr(construction, "retriangulation", tri_local)


def test_scene_from_random_segments_30008_certified_and_equal_to_cgal(roundoff_triangulations):
    """The three segments of the fault: certified, with the vertices (B, s, C) and (C, P, s), and
    the Delaunay graph of CGAL's Segment_Delaunay_graph_2, although every sample triangulation
    comes with the other diagonal (B–P) where the samples are co-circular within :data:`TOL`."""
    sdg_peer.build_or_skip()
    d = cv.voronoi([cv.Segment(a, b) for a, b in SEGMENTS], progress=False)
    assert d.certified, d.problems[:3]
    s = next(k for k, site in enumerate(d.sites) if isinstance(site, cv.Segment) and site.p == B)
    at = {(float(d.sites[k].x), float(d.sites[k].y)): k for k in range(len(d.sites))
          if not isinstance(d.sites[k], cv.Segment)}
    want = {frozenset((at[B], s, at[C])), frozenset((at[C], at[P], s))}
    assert want <= {frozenset(v.sites) for v in d.vertices}
    cgal, _ = sdg_peer.segment_delaunay_edges([], SEGMENTS, degenerate=True)
    assert _keys(d) == cgal
