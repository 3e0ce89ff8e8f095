"""The edge between an elliptic piece and its end point, beyond the centre of curvature, when it
runs on to a vertex with the piece's other end (runtime/segments/ellipse_bisectors.py,
``perpendicular_edge``).

Scene (the ring benchmark's scene 11, bench/bench_elliptic_ring.py seed 1): the arc φ ∈ [0.11, 1.22]
of (x/2)² + y² = 1 and nine integer points around it.  The end e = e(0.11) owns the normal line at e
out to its centre of curvature K, then the foot curve: the points equidistant from e and an inner
foot e(φ), φ moving into the arc.  The edge ends at a vertex below the ellipse that is equidistant
from both ends of the arc (the foot has reached the other end, φ = 1.22).  Its polyline must follow
that curve: every point of every segment of it (sampled) is, to within its stated tolerance, as near
to e as to the arc, both distances computed here by dense sampling of the arc (no library code).
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import curvedvoronoi as cv

POINTS = [(4, 1), (0, 4), (-3, 3), (-3, -2), (-3, -3), (0, -5), (1, -4), (3, -4), (5, 0)]


@pytest.fixture(scope="module")
def diagram():
    return cv.voronoi([cv.Arc.elliptic((0, 0), (2, 0), "1/2", 0.11, 1.22)] + POINTS, certify=False)


def _distances(Q, phi0=0.11, phi1=1.22, n=100001):
    """For each point q: the distance to the closed arc, and the least local minimum of
    φ ↦ |q − (2 cos φ, sin φ)| away from the end φ0 (a sample no larger than its neighbours, the
    last sample counted when it is below the one before), by dense sampling (no library code)."""
    phi = np.linspace(phi0, phi1, n)
    X, Y = 2 * np.cos(phi), np.sin(phi)
    d_arc, d_inner = [], []
    for q in Q:
        f = np.hypot(X - q[0], Y - q[1])
        d_arc.append(f.min())
        loc = np.nonzero((f[1:-1] <= f[:-2]) & (f[1:-1] <= f[2:]))[0] + 1
        cand = list(f[loc]) + ([f[-1]] if f[-1] < f[-2] else [])
        d_inner.append(min(cand) if cand else math.inf)
    return np.array(d_arc), np.array(d_inner)


def test_the_end_edge_beyond_the_centre_of_curvature_follows_its_curve(diagram):
    phi_e = 0.11
    e = np.array([2 * math.cos(phi_e), math.sin(phi_e)])
    n = np.array([math.cos(phi_e) / 2, 2 * math.sin(phi_e)])           # outward normal of x²/4 + y² = 1
    n /= np.hypot(*n)
    rho = (4 * math.sin(phi_e) ** 2 + math.cos(phi_e) ** 2) ** 1.5 / 2    # radius of curvature at e
    # the end point site and the arc's interior site, from the diagram's site list
    ends = [k for k, s in enumerate(diagram.sites) if isinstance(s, cv.Point)
            and np.hypot(float(s.x) - e[0], float(s.y) - e[1]) < 1e-12]
    arcs = [k for k, s in enumerate(diagram.sites) if not isinstance(s, cv.Point)]
    assert len(ends) == 1 and len(arcs) == 1
    pair = tuple(sorted((ends[0], arcs[0])))
    edges = [d for d in diagram.edges if tuple(sorted(d.sites)) == pair]
    assert len(edges) == 1
    P = np.asarray(edges[0].polyline, float)
    tol = float(edges[0].tolerance)
    depth = (e - P) @ n
    assert depth.max() > rho + 1.0, "the edge should run far beyond the centre of curvature"
    t = np.linspace(0, 1, 11)[:, None]
    Q = np.concatenate([P[k] + t * (P[k + 1] - P[k]) for k in range(len(P) - 1)])
    d_e = np.hypot(Q[:, 0] - e[0], Q[:, 1] - e[1])
    d_arc, d_inner = _distances(Q)
    # every point of the drawn edge is as near to e as to the arc (both 1-Lipschitz: within twice
    # its distance from the edge), and beyond the centre of curvature (with a margin for the
    # sampling) a second nearest point of the arc, away from e, ties with e
    assert np.abs(d_e - d_arc).max() <= 2 * tol + 1e-9
    deep = (e - Q) @ n > rho + 0.05
    assert deep.sum() > 10
    gap = np.abs(d_inner[deep] - d_e[deep])
    assert gap.max() <= 2 * tol + 1e-6, (gap.max(), tol, Q[deep][gap.argmax()])


def test_the_diagram_is_certified(diagram):
    """The certificate follows the end curve to the vertex where the foot reaches the arc's other
    end (runtime/segments/certificate_ellipse_junction.py), and proves the whole diagram."""
    from curvedvoronoi.runtime.segments.certificate import verify_segments

    cert = verify_segments(diagram)
    assert cert.ok, cert.problems
