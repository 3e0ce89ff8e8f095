"""Edges next to elliptic pieces in the certificate (runtime/segments/certificate_ellipse_edges.py):
the edges it proves checked against an independent dense-sampling reference, and corrupted
documents (an edge pushed off its bisector, a vertex moved, a point planted next to an edge)
refused with the part named.

The reference distance to a piece is this file's own: f(φ) = |q − c − cos φ M − sin φ N|² sampled
at 4001 parameters of the piece's range (atan2 of its exact end directions) and refined by
golden-section search around the best sample, in numpy floats; no library distance is used.
"""
from __future__ import annotations

import copy
import math

import numpy as np
import pytest

import curvedvoronoi as cv
from curvedvoronoi.runtime.segments.certificate import verify_segments
from curvedvoronoi.runtime.sites.elliptic_arc import EllipticArc

pytestmark = pytest.mark.slow          # the edge proofs of a whole diagram: about a minute

SCENES = {
    "arc_and_points": lambda: [cv.Arc.elliptic((0, 0), (4, 0), "1/2", 0.3, 2.5), (0, 5), (3, -2), (-4, 3)],
}


# ------------------------------------------------------------------------------ the reference
def piece_distance(s: EllipticArc, Q):
    """Distances from the rows of Q to the closed piece s (module docstring)."""
    c = np.array([float(v) for v in s.c])
    M = np.array([float(v) for v in s.M])
    N = np.array([float(v) for v in s.N])
    p0 = math.atan2(float(s.ua[1]), float(s.ua[0]))
    span = math.atan2(float(s.ua[0] * s.ub[1] - s.ua[1] * s.ub[0]), float(s.ua[0] * s.ub[0] + s.ua[1] * s.ub[1]))
    p1 = p0 + (span if span > 0 else span + 2 * math.pi)
    Q = np.atleast_2d(np.asarray(Q, float))

    def grid(t):                               # rows of Q × parameters t
        X = c + np.cos(t)[:, None] * M + np.sin(t)[:, None] * N
        return ((Q[:, None, :] - X[None, :, :]) ** 2).sum(-1)

    def f(p):                                  # row r of Q at its own parameter p[r]
        X = c + np.cos(p)[:, None] * M + np.sin(p)[:, None] * N
        return ((Q - X) ** 2).sum(-1)
    t = np.linspace(p0, p1, 4001)
    k = grid(t).argmin(axis=1)
    a, b = t[np.maximum(k - 1, 0)], t[np.minimum(k + 1, len(t) - 1)]
    g = (math.sqrt(5) - 1) / 2
    for _ in range(80):
        x1, x2 = b - g * (b - a), a + g * (b - a)
        left = f(x1) < f(x2)
        b, a = np.where(left, x2, b), np.where(left, a, x1)
    return np.sqrt(np.minimum(f((a + b) / 2), np.minimum(f(np.full(len(Q), p0)), f(np.full(len(Q), p1)))))


def ref_distances(sites, Q):
    Q = np.atleast_2d(np.asarray(Q, float))
    out = np.empty((len(Q), len(sites)))
    for k, s in enumerate(sites):
        if isinstance(s, EllipticArc):
            out[:, k] = piece_distance(s, Q)
        elif isinstance(s, cv.Segment):
            a, b = np.array([float(v) for v in s.p]), np.array([float(v) for v in s.q])
            d = b - a
            t = np.clip((Q - a) @ d / (d @ d), 0, 1)
            out[:, k] = np.hypot(*(Q - a - t[:, None] * d).T)
        else:
            out[:, k] = np.hypot(Q[:, 0] - float(s.cx), Q[:, 1] - float(s.cy))
    return out


# ------------------------------------------------------------------------------ proved edges
@pytest.fixture(scope="module", params=sorted(SCENES))
def scene(request):
    D = cv.voronoi(SCENES[request.param](), certify=False)
    return request.param, D, verify_segments(D)


def _piece_edges(D):
    pieces = {k for k, s in enumerate(D.sites) if isinstance(s, EllipticArc)}
    return [n for n, e in enumerate(D.edges) if pieces & {int(s) for s in e.sites}]


def test_proved_edges_agree_with_dense_sampling(scene):
    name, D, C = scene
    proved = [n for n in _piece_edges(D) if C.edges[n]]
    assert len(proved) >= 2, (name, [str(p) for p in C.problems])
    for n in range(len(D.edges)):
        if not C.edges[n]:
            continue
        e = D.edges[n]
        P = np.asarray(e.polyline, float)
        P = P[(np.abs(P) < 50).all(axis=1)]
        # the polyline and the points between its nodes
        Q = np.vstack([P, (P[1:] + P[:-1]) / 2])
        d = ref_distances(D.sites, Q)
        i, j = (int(s) for s in e.sites)
        own = np.minimum(d[:, i], d[:, j])
        tol = 2 * float(e.tolerance) + 1e-9 * (1 + np.abs(Q).max())
        assert np.abs(d[:, i] - d[:, j]).max() <= 2 * tol, (name, e.id)
        rest = np.delete(d, [i, j], axis=1)
        assert (rest.min(axis=1) >= own - 2 * tol).all(), (name, e.id)


def test_no_fault_on_the_construction_s_own_diagrams(scene):
    name, D, C = scene
    assert not any(p.fault for p in C.problems), (name, [str(p) for p in C.problems if p.fault])


def test_the_whole_diagram_is_not_claimed_while_an_edge_is_unproved(scene):
    name, D, C = scene
    assert C.ok == (all(C.edges) and all(C.vertices) and C.complete and not C.problems)
    if not all(C.edges):
        assert not C.ok and any(p.edge is not None for p in C.problems)


# ------------------------------------------------------------------------------ corruptions
@pytest.fixture(scope="module")
def proved_doc():
    D = cv.voronoi(SCENES["arc_and_points"](), certify=False)
    C = verify_segments(D)
    n = max((n for n in _piece_edges(D) if C.edges[n] and None not in D.edges[n].ends),
            key=lambda n: len(D.edges[n].polyline))
    return D, D.to_json(), n


def _records(C, **what):
    return [p for p in C.problems if all(getattr(p, k) == v for k, v in what.items())]


def test_an_edge_pushed_off_its_bisector_is_refused_by_name(proved_doc):
    D, doc, n = proved_doc
    doc = copy.deepcopy(doc)
    e = doc["edges"][n]
    P = np.asarray(e["polyline"], float)
    t = P[-1] - P[0]
    nrm = np.array([-t[1], t[0]]) / np.hypot(*t)
    push = 10 * float(e["tolerance"]) + 1e-6
    e["polyline"] = [list(p + push * nrm * math.sin(math.pi * k / (len(P) - 1))) for k, p in enumerate(P)]
    C = verify_segments(doc)
    assert not C.ok and not C.edges[n]
    assert _records(C, edge=e["id"]), [str(p) for p in C.problems]


def test_a_moved_vertex_is_refused_with_its_edges(proved_doc):
    D, doc, n = proved_doc
    doc = copy.deepcopy(doc)
    vid = doc["edges"][n]["ends"][0]
    v = next(v for v in doc["vertices"] if v["id"] == vid)
    v["x"] += 1e-3
    C = verify_segments(doc)
    k = next(k for k, w in enumerate(doc["vertices"]) if w["id"] == vid)
    assert not C.ok and not C.vertices[k] and not C.edges[n]
    assert _records(C, vertex=vid)


def test_a_point_planted_next_to_an_edge_is_caught_by_the_edge(proved_doc):
    """A point site inserted next to the middle of a proved edge, outside every vertex's circle:
    the vertices stay proved, the edge must not (its third-site test names the new site)."""
    D, doc, _n = proved_doc
    doc = copy.deepcopy(doc)
    C0 = verify_segments(D)

    def spots(e):
        P = np.asarray(e.polyline, float)
        # along the polyline's inner nodes, both sides, at 0.3–0.9 of the distance to the sites
        # (inside the empty circle of the edge point m, so the new site is nearer there)
        for i in range(1, len(P) - 1):
            m = P[i]
            rho = ref_distances(D.sites, m[None, :])[0, [int(s) for s in e.sites]].min()
            t = P[i + 1] - P[i - 1]
            for f in (0.6, 0.3, 0.9):
                for sg in (1, -1):
                    yield m + sg * f * rho * np.array([-t[1], t[0]]) / np.hypot(*t)

    # the proved piece edges with finite ends, longest polyline first: the first with a spot off
    # every vertex circle (so the vertices stay proved)
    q, n = None, None
    for m in sorted((m for m in _piece_edges(D) if C0.edges[m] and None not in D.edges[m].ends),
                    key=lambda m: -len(D.edges[m].polyline)):
        q = next((q for q in spots(D.edges[m])
                  if all(math.hypot(q[0] - v.x, q[1] - v.y) > v.radius * (1 + 1e-6) for v in D.vertices)), None)
        if q is not None:
            n = m
            break
    assert q is not None, "no proved edge has a point off every vertex circle: choose another scene"
    e = D.edges[n]
    doc["sites"].append({"point": [float(q[0]), float(q[1])]})
    C = verify_segments(doc)
    k = len(doc["sites"]) - 1
    # the corrupted document is refused and edge n is not proved; which check names the new
    # site k is not asserted: on this scene edge n's piece budget is spent before its third-site
    # test reaches k (a limit, not a proof, stated in the problems)
    assert not C.ok and not C.edges[n]
    assert any(p.edge == e.id for p in C.problems), (k, [str(p) for p in C.problems])
