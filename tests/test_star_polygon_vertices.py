"""A regular star polygon of segments (cos/sin floats): its mirror symmetries make vertices whose
empty circle passes, in exact arithmetic of the symmetric figure, through a fifth site, which the
floats move off the circle by about 10⁻¹⁷.  The segment certificate encloses such a vertex again at
TIGHT_PREC bits when its first enclosure leaves a site undecided
(runtime/segments/certificate_vertices.py, _tighten).  Reference: the distances from each vertex
to every site in mpmath at 200 bits of the exact float coordinates, independent of the library.
(The edges between such nearly coincident vertices, 10⁻¹⁶ long, are not proved yet.)"""
from __future__ import annotations

import mpmath
import numpy as np

import curvedvoronoi as cv


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
