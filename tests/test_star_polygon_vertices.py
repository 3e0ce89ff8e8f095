"""A regular star polygon of segments (cos/sin floats): its mirror symmetries make vertices whose
empty circle passes, in exact arithmetic of the symmetric figure, through a fifth site, which the
floats move off the circle by about 10⁻¹⁷.  The segment certificate encloses such a vertex again at
TIGHT_PREC bits when its first enclosure leaves a site undecided
(runtime/segments/certificate_vertices.py, _tighten).  Reference: the distances from each vertex
to every site in mpmath at 200 bits of the exact float coordinates, independent of the library.
The edges between such nearly coincident vertices, 10⁻¹⁶ long, are below the float resolution
of their parameter: their ties at the ends are proved over the whole edge at once
(runtime/segments/certificate_pieces.py, _prefix).  The Delaunay graph is compared with CGAL's
Segment_Delaunay_graph_2 on the same doubles (exact predicates; zero-length duals dropped)."""
from __future__ import annotations

import copy
import sys
from fractions import Fraction
from pathlib import Path

import mpmath
import numpy as np
import pytest

import curvedvoronoi as cv

sys.path.insert(0, str(Path(__file__).with_name("cgal")))
import sdg_peer  # noqa: E402


def star(n, R=2.0, r=0.8):
    pts = [((R if k % 2 == 0 else r) * np.cos(np.pi * k / n), (R if k % 2 == 0 else r) * np.sin(np.pi * k / n))
           for k in range(2 * n)]
    return [(float(x), float(y)) for x, y in pts]


def rational(v):
    """An exact rational (Fraction or flint fmpq) as an mpf at the working precision."""
    num, den = (v.numerator, v.denominator) if hasattr(v, "numerator") else (v.p, v.q)
    return mpmath.mpf(int(num)) / int(den)


def distance(site, x, y):
    """Distance from (x, y) to an elementary site: a point, or a segment (its closure)."""
    if type(site).__name__ == "Point":
        return mpmath.hypot(x - rational(site.cx), y - rational(site.cy))
    (ax, ay), (bx, by) = [(rational(c[0]), rational(c[1])) for c in (site.p, site.q)]
    t = ((x - ax) * (bx - ax) + (y - ay) * (by - ay)) / ((bx - ax) ** 2 + (by - ay) ** 2)
    t = min(max(t, 0), 1)
    return mpmath.hypot(x - ax - t * (bx - ax), y - ay - t * (by - ay))


def test_every_vertex_of_a_regular_5_star_is_proved_and_equidistant():
    P = star(5)
    d = cv.voronoi([cv.Segment(P[k], P[(k + 1) % len(P)]) for k in range(len(P))], progress=False)
    cert = cv.verify(d.to_json())
    bad = [v for v, ok in zip(d.vertices, cert.vertices) if not ok]
    assert not bad, [p for p in cert.problems if p.startswith("vertex")][:4]
    assert len(d.vertices) > 10
    with mpmath.workprec(200):
        near = 0
        for v in d.vertices:
            x, y = mpmath.mpf(v.x), mpmath.mpf(v.y)
            ds = [distance(s, x, y) for s in d.sites]
            r = min(ds)
            tol = 1e-12 * (1 + abs(v.x) + abs(v.y))
            assert all(abs(ds[k] - r) <= tol for k in v.sites), v
            assert abs(r - v.radius) <= tol
            # the floats' near ties: an unlisted site within 10⁻¹² of the circle
            near += any(abs(ds[k] - r) <= tol for k in range(len(ds)) if k not in v.sites)
        assert near > 0


@pytest.mark.parametrize("n", [5, 8])
def test_regular_stars_are_certified_and_equal_cgal(n):
    sdg_peer.build_or_skip()
    P = star(n)
    segs = [(P[k], P[(k + 1) % len(P)]) for k in range(len(P))]
    d = cv.voronoi([cv.Segment(a, b) for a, b in segs], progress=False)
    assert d.certified, d.problems[:4]
    keys = [sdg_peer.segment_key(s.p, s.q) if isinstance(s, cv.Segment)
            else sdg_peer.point_key(Fraction(str(s.cx)), Fraction(str(s.cy))) for s in d.sites]
    ours = {frozenset((keys[i], keys[j])) for i, j in d.delaunay_edges()}
    cgal, _ = sdg_peer.segment_delaunay_edges([], segs, degenerate=True)
    assert ours == cgal, (len(ours), len(cgal))
    tiny = [e for e in d.edges if None not in e.ends and np.hypot(*np.diff(np.asarray(e.polyline), axis=0).T).sum() < 1e-12]
    assert tiny                                      # the nearly coincident vertices' edges are there
    m = cv.medial_axis(P)
    assert m.certified, m.problems[:4]


def test_a_star_without_one_of_its_tiny_edges_is_refused():
    """Dropping a 10⁻¹⁶ edge (its end vertices merged into one of degree 4 would be wrong: the
    floats break the tie) or moving its end vertex by 10⁻⁹ is refused."""
    P = star(5)
    d = cv.voronoi([cv.Segment(P[k], P[(k + 1) % len(P)]) for k in range(len(P))], progress=False)
    assert d.certified
    doc = d.to_json()
    t = next(t for t, e in enumerate(doc["edges"]) if None not in e["ends"]
             and np.hypot(*np.diff(np.asarray(e["polyline"]), axis=0).T).sum() < 1e-12)
    bad = copy.deepcopy(doc)
    del bad["edges"][t]
    bad["delaunay_edges"] = sorted({tuple(sorted(e["sites"])) for e in bad["edges"]})
    assert not cv.verify(bad).ok
    bad = copy.deepcopy(doc)
    v = doc["edges"][t]["ends"][0]
    k = next(k for k, w in enumerate(bad["vertices"]) if w["id"] == v)
    bad["vertices"][k]["x"] += 1e-9
    assert not cv.verify(bad).ok


class _Identity:
    """A curve whose point at parameter J is (J, J): the tests below see the interval itself."""

    @staticmethod
    def xy(J):
        return J, J


@pytest.mark.parametrize("at_lo", [True, False])
def test_a_tiny_edge_is_covered_only_from_the_far_side_of_its_end_ball(at_lo):
    """The whole-edge test of a tie cover on an edge below float resolution (PieceProofs._prefix)
    must hold from the far side ``back`` of the end vertex's parameter ball (the exact vertex may
    lie anywhere in it) to the other end: a test positive only beyond the middle of [back, base] is
    refused, one positive on the whole hull is accepted and reaches the far end."""
    from curvedvoronoi.runtime.segments.certificate_pieces import PieceProofs

    base = 2.6757499224999206
    span = 4 * np.spacing(base)
    sgn = 1 if at_lo else -1
    back = base - sgn * 4 * np.spacing(base)                   # half lies strictly between back and base
    pr = type("P", (), {"curve": _Identity()})()
    half = (back + base) / 2
    beyond_half = (lambda J, X, Y: J - half) if at_lo else (lambda J, X, Y: half - J)
    assert PieceProofs._prefix(pr, beyond_half, back, base, span, at_lo) is None
    everywhere = lambda J, X, Y: J * 0 + 1                      # noqa: E731
    reach = PieceProofs._prefix(pr, everywhere, back, base, span, at_lo)
    assert reach == base + sgn * span
    never = lambda J, X, Y: J * 0 - 1                           # noqa: E731
    assert PieceProofs._prefix(pr, never, back, base, span, at_lo) is None
