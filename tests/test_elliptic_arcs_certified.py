"""A diagram with an elliptic arc piece certified whole (runtime/segments/certificate_ellipse_*.py):
the verdict, the diagram checked against an independent reference, corrupted documents refused
with the part named, and the secant identity behind the new proofs checked in mpmath.

The reference is this file's own, in mpmath at 20 digits from the exact site data: the distance to
a point is |q − p|; to the closed piece e(φ) = c + cos φ M + sin φ N, φ from atan2 of its exact
start direction over the exact span, the minimum of f(φ) = |q − e(φ)|² over 129 samples refined
by golden-section search around the best one, and both ends.  The diagram's tests are slow (the
certificate, about 6 s CPU, runs three times; the reference at some 1500 points).  Nothing of the library's distance code
is used.
"""
from __future__ import annotations

import copy
import math
import random
from fractions import Fraction as F

import mpmath
import numpy as np
import pytest
from flint import arb

import curvedvoronoi as cv
from curvedvoronoi.runtime.segments.certificate import verify_segments
from curvedvoronoi.runtime.segments.certificate_ellipse_secant import (end_factor, end_foot_t, monotone_piece,
                                                                      on_ellipse, secant_factor)
from curvedvoronoi.runtime.segments.ellipse_pieces import PieceData
from curvedvoronoi.runtime.sites.elliptic_arc import EllipticArc

pytestmark = pytest.mark.mpmath_dps(20)

RING = [(4, 0), (3, 3), (0, 4), (-3, 2), (-3, -2), (0, -3), (3, -3)]


def scene():
    """A quarter-ellipse arc (x/2)² + y² = 1, φ from 0.2 to 1.3, inside a ring of integer points."""
    return [cv.Arc.elliptic((0, 0), (2, 0), "1/2", 0.2, 1.3)] + RING


# ------------------------------------------------------------------------------ the reference
def mpf(q):
    q = F(str(q)) if not isinstance(q, (int, float, F)) else q
    if hasattr(q, "numerator"):
        return mpmath.mpf(int(q.numerator)) / int(q.denominator)
    return mpmath.mpf(q)


class RefPiece:
    """An elliptic piece from its exact data, with its own distance (module docstring)."""

    def __init__(self, s: EllipticArc):
        self.c = [mpf(v) for v in s.c]
        self.M = [mpf(v) for v in s.M]
        self.N = [mpf(v) for v in s.N]
        self.p0 = mpmath.atan2(mpf(s.ua[1]), mpf(s.ua[0]))
        span = mpmath.atan2(mpf(s.ua[0] * s.ub[1] - s.ua[1] * s.ub[0]), mpf(s.ua[0] * s.ub[0] + s.ua[1] * s.ub[1]))
        self.p1 = self.p0 + (span if span > 0 else span + 2 * mpmath.pi)

    def point(self, p):
        return [self.c[k] + mpmath.cos(p) * self.M[k] + mpmath.sin(p) * self.N[k] for k in (0, 1)]

    def f(self, q, p):
        e = self.point(p)
        return (q[0] - e[0]) ** 2 + (q[1] - e[1]) ** 2

    def distance(self, q):
        n = 128
        ts = [self.p0 + (self.p1 - self.p0) * k / n for k in range(n + 1)]
        vals = [self.f(q, t) for t in ts]
        k = min(range(n + 1), key=lambda m: vals[m])
        a, b = ts[max(k - 1, 0)], ts[min(k + 1, n)]
        g = (mpmath.sqrt(5) - 1) / 2
        for _ in range(70):
            x1, x2 = b - g * (b - a), a + g * (b - a)
            if self.f(q, x1) < self.f(q, x2):
                b = x2
            else:
                a = x1
        return mpmath.sqrt(min(self.f(q, (a + b) / 2), vals[0], vals[-1]))


def reference(sites):
    out = []
    for s in sites:
        if isinstance(s, EllipticArc):
            out.append(RefPiece(s).distance)
        else:
            p = (mpf(s.cx), mpf(s.cy))
            out.append(lambda q, p=p: mpmath.sqrt((q[0] - p[0]) ** 2 + (q[1] - p[1]) ** 2))
    return out


def distances(ref, q):
    q = (mpmath.mpf(float(q[0])), mpmath.mpf(float(q[1])))
    return [d(q) for d in ref]


@pytest.fixture(scope="module")
def certified():
    D = cv.voronoi(scene(), certify=False)
    return D, verify_segments(D)


def _piece_index(D):
    return next(k for k, s in enumerate(D.sites) if isinstance(s, EllipticArc))


# ------------------------------------------------------------------------------ the verdict
@pytest.mark.slow
def test_the_diagram_with_an_elliptic_piece_is_certified(certified):
    D, C = certified
    assert C.ok, [str(p) for p in C.problems]
    assert C.complete and all(C.vertices) and all(C.edges) and not C.problems
    k = _piece_index(D)
    assert any(k in (int(s) for s in e.sites) for e in D.edges)


@pytest.mark.slow
def test_the_edge_of_the_arc_s_end_runs_through_its_centre_of_curvature(certified):
    """The scene exercises the junction: the edge of the arc's start E = e(φ₀) and the piece
    crosses E's normal line outside the ellipse and passes E's centre of curvature
    C = E − R ν (R = |e'|³/(ab), a = 2, b = 1), computed here."""
    D, C = certified
    k = _piece_index(D)
    arc = D.sites[k]
    ref = RefPiece(arc)
    phi = ref.p0                                   # the start: atan2 of the exact direction (≈ 0.2)
    E = ref.point(phi)
    tx, ty = -2 * mpmath.sin(phi), mpmath.cos(phi)
    sp = mpmath.sqrt(tx * tx + ty * ty)
    R = sp ** 3 / 2
    cc = (E[0] - R * ty / sp, E[1] + R * tx / sp)
    Eq = tuple(arc.c[m] + arc.ua[0] * arc.M[m] + arc.ua[1] * arc.N[m] for m in (0, 1))
    ends = [n for n, s in enumerate(D.sites) if not isinstance(s, EllipticArc)
            and (F(str(s.cx)), F(str(s.cy))) == Eq]
    assert len(ends) == 1
    edge = next(e for e in D.edges if sorted(int(s) for s in e.sites) == sorted((k, ends[0])))
    P = np.asarray(edge.polyline, float)
    seg = [np.hypot(*(np.array([float(cc[0]), float(cc[1])]) - (P[m] + u * (P[m + 1] - P[m]))))
           for m in range(len(P) - 1) for u in np.linspace(0, 1, 21)]
    assert min(seg) < 10 * edge.tolerance
    outward = [(p[0] - float(E[0])) * float(ty) - (p[1] - float(E[1])) * float(tx) for p in P]
    assert max(outward) > 0.5 and min(outward) < -0.5 * float(R)


@pytest.mark.slow
def test_the_certified_diagram_agrees_with_the_mpmath_reference(certified):
    """Every edge's polyline (nodes and midpoints) is equidistant from its two sites and not
    farther than any other site; every vertex is at distance r from its listed sites and not
    nearer to any other (tolerances: the edge's own, 1e-9 for vertices)."""
    D, C = certified
    ref = reference(D.sites)
    for e in D.edges:
        P = np.asarray(e.polyline, float)
        P = P[(np.abs(P) < 30).all(axis=1)]
        Q = np.vstack([P, (P[1:] + P[:-1]) / 2])
        i, j = (int(s) for s in e.sites)
        tol = 2 * float(e.tolerance) + 1e-9
        for q in Q:
            d = distances(ref, q)
            own = min(d[i], d[j])
            assert abs(d[i] - d[j]) <= tol, (e.id, q)
            assert min(x for m, x in enumerate(d) if m not in (i, j)) >= own - tol, (e.id, q)
    for v in D.vertices:
        d = distances(ref, (v.x, v.y))
        listed = {int(s) for s in v.sites}
        for m, x in enumerate(d):
            if m in listed:
                assert abs(x - v.radius) < 1e-9, (v.id, m)
            else:
                assert x > v.radius - 1e-9, (v.id, m)


@pytest.mark.slow
def test_a_dense_grid_agrees_with_the_diagram_s_pairs(certified):
    """Neighbouring grid points (step 0.4 over [−5.2, 5.2]²) with different nearest sites (mpmath)
    have an edge of the diagram between those sites."""
    D, C = certified
    ref = reference(D.sites)
    pairs = {tuple(sorted(int(s) for s in e.sites)) for e in D.edges}
    xs = np.arange(-5.2, 5.201, 0.4)
    near = {}
    for x in xs:
        for y in xs:
            d = distances(ref, (x, y))
            order = sorted(range(len(d)), key=lambda m: d[m])
            if d[order[1]] - d[order[0]] > 1e-12:
                near[(round(x / 0.4), round(y / 0.4))] = order[0]
    seen = set()
    for (a, b), s in near.items():
        for nb in ((a + 1, b), (a, b + 1)):
            t = near.get(nb)
            if t is not None and t != s:
                seen.add(tuple(sorted((s, t))))
    assert seen and seen <= pairs, seen - pairs


@pytest.mark.slow
def test_an_arc_across_a_vertex_of_its_ellipse_is_certified():
    """The arc φ ∈ [0.3, 2.5] of the same ellipse is cut at the minor vertex (0, 1) into two pieces
    with a smooth joint there: certified too, the edge of the two pieces runs along the joint's
    normal x = 0 through the joint, and the diagram agrees with the mpmath reference."""
    D = cv.voronoi([cv.Arc.elliptic((0, 0), (2, 0), "1/2", 0.3, 2.5)] + RING, certify=False)
    C = verify_segments(D)
    assert C.ok, [str(p) for p in C.problems]
    pieces = [k for k, s in enumerate(D.sites) if isinstance(s, EllipticArc)]
    assert len(pieces) == 2
    joint = [e for e in D.edges if sorted(int(s) for s in e.sites) == pieces]
    assert len(joint) == 1
    P = np.asarray(joint[0].polyline, float)
    assert np.abs(P[:, 0]).max() < 1e-9 and P[:, 1].min() < 1 < P[:, 1].max()
    ref = reference(D.sites)
    for e in D.edges:
        i, j = (int(s) for s in e.sites)
        P = np.asarray(e.polyline, float)
        P = P[(np.abs(P) < 30).all(axis=1)]
        for q in np.vstack([P, (P[1:] + P[:-1]) / 2]):
            d = distances(ref, q)
            tol = 2 * float(e.tolerance) + 1e-9
            assert abs(d[i] - d[j]) <= tol and min(x for m, x in enumerate(d) if m not in (i, j)) >= min(d[i], d[j]) - tol


# ------------------------------------------------------------------------------ corruptions
@pytest.mark.slow
def test_an_edge_pushed_off_its_curve_is_refused_by_name(certified):
    """The curved edges of the piece (the junction edge of its end, a foot curve) bent off their
    curve by twenty tolerances in the middle: refused with that edge named, the others proved."""
    D, C = certified
    k = _piece_index(D)
    curved = [n for n, e in enumerate(D.edges)
              if k in (int(s) for s in e.sites) and None not in e.ends and len(e.polyline) > 8]
    assert len(curved) >= 2
    for n in sorted(curved, key=lambda n: -len(D.edges[n].polyline))[:2]:
        doc = copy.deepcopy(D.to_json())
        ed = doc["edges"][n]
        P = np.asarray(ed["polyline"], float)
        t = P[-1] - P[0]
        nrm = np.array([-t[1], t[0]]) / np.hypot(*t)
        push = 20 * float(ed["tolerance"]) + 1e-6
        ed["polyline"] = [list(p + push * nrm * math.sin(math.pi * m / (len(P) - 1))) for m, p in enumerate(P)]
        C2 = verify_segments(doc)
        assert not C2.ok and not C2.edges[n], n
        assert any(p.edge == ed["id"] for p in C2.problems), (n, [str(p) for p in C2.problems])
        assert sum(C2.edges) == len(D.edges) - 1                  # the others stay proved


@pytest.mark.slow
def test_a_moved_vertex_is_refused_by_name(certified):
    D, C = certified
    k = _piece_index(D)
    n = next(n for n, v in enumerate(D.vertices) if k in (int(s) for s in v.sites))
    doc = copy.deepcopy(D.to_json())
    v = doc["vertices"][n]
    v["x"] += 1e-3
    C2 = verify_segments(doc)
    assert not C2.ok and not C2.vertices[n]
    assert any(p.vertex == v["id"] for p in C2.problems), [str(p) for p in C2.problems]
    touching = [m for m, e in enumerate(doc["edges"]) if v["id"] in e["ends"]]
    assert touching and not any(C2.edges[m] for m in touching)


# ------------------------------------------------------------------------------ the identity
def _random_piece(rng):
    """A piece between two vertices of a random ellipse with a rational frame (M ⟂ N)."""
    a, b = rng.choice([(3, 4), (5, 12), (8, 15)])
    m = rng.choice([1, 2, 3])
    r = F(*rng.choice([(1, 2), (2, 3), (1, 3)]))
    M = (F(a * m), F(b * m))
    N = (-b * m * r, a * m * r)                       # M ⟂ N, |N| = r|M|, det(M, N) > 0
    c = (F(rng.randint(-3, 3)), F(rng.randint(-3, 3)))
    q = rng.randint(0, 3)
    ts = sorted(rng.sample(range(1, 20), 2))

    def unit(t):                                     # rational point of the unit circle, first quadrant
        u = F(t, 21)
        return ((1 - u * u) / (1 + u * u), 2 * u / (1 + u * u))
    ua, ub = unit(ts[0]), unit(ts[1])
    rot = [(lambda p: p), (lambda p: (-p[1], p[0])), (lambda p: (-p[0], -p[1])), (lambda p: (p[1], -p[0]))][q]
    ua, ub = rot(ua), rot(ub)
    p0 = math.atan2(float(ua[1]), float(ua[0]))
    span = math.atan2(float(ua[0] * ub[1] - ua[1] * ub[0]), float(ua[0] * ub[0] + ua[1] * ub[1]))
    return PieceData(c, M, N, ua, ub, p0, p0 + span)


def _mp_point(P, p):
    return [mpf(P.c[k]) + mpmath.cos(p) * mpf(P.M[k]) + mpmath.sin(p) * mpf(P.N[k]) for k in (0, 1)]


def _mp_normal(P, p):
    tx = -mpmath.sin(p) * mpf(P.M[0]) + mpmath.cos(p) * mpf(P.N[0])
    ty = -mpmath.sin(p) * mpf(P.M[1]) + mpmath.cos(p) * mpf(P.N[1])
    n = mpmath.sqrt(tx * tx + ty * ty)
    return ty / n, -tx / n


def test_the_secant_identity_in_mpmath():
    """|x − e(ψ)|² − t² = 4 sin²((ψ − φ*)/2)·L for x = e(φ*) + σ t ν(φ*), L from
    secant_factor, at random frames, parameters, sides and distances."""
    rng = random.Random(5)
    for _ in range(40):
        P = _random_piece(rng)
        assert monotone_piece(P)
        psi_cs = P.ua if rng.random() < 0.5 else P.ub
        psi = mpmath.atan2(mpf(psi_cs[1]), mpf(psi_cs[0]))
        phi = mpmath.mpf(rng.uniform(P.phi0, P.phi1))
        t = mpmath.mpf(rng.uniform(0, 5))
        sg = rng.choice([-1, 1])
        e, nu = _mp_point(P, phi), _mp_normal(P, phi)
        x = [e[k] + sg * t * nu[k] for k in (0, 1)]
        q = _mp_point(P, psi)
        lhs = (x[0] - q[0]) ** 2 + (x[1] - q[1]) ** 2 - t * t
        L = secant_factor(P, psi_cs, arb(str(phi)), arb(str(t)), sg)
        rhs = 4 * mpmath.sin((psi - phi) / 2) ** 2 * mpmath.mpf(float(L.mid()))
        assert abs(lhs - rhs) < 1e-12 * (1 + abs(lhs)), (lhs, rhs)


def test_the_end_foot_curve_is_equidistant_from_the_end_and_its_foot():
    """x = e(φ) − t_E(φ) ν(φ) has |x − E| = t_E(φ) (E = e(ψ)), and t_E(ψ) is E's radius of curvature."""
    rng = random.Random(6)
    for _ in range(30):
        P = _random_piece(rng)
        cs = P.ua
        psi = mpmath.atan2(mpf(cs[1]), mpf(cs[0]))
        for phi in (mpmath.mpf(rng.uniform(P.phi0, P.phi1)), psi):
            C, S = arb(str(mpmath.cos(phi))), arb(str(mpmath.sin(phi)))
            tx = -mpmath.sin(phi) * mpf(P.M[0]) + mpmath.cos(phi) * mpf(P.N[0])
            ty = -mpmath.sin(phi) * mpf(P.M[1]) + mpmath.cos(phi) * mpf(P.N[1])
            sp = mpmath.sqrt(tx * tx + ty * ty)
            t = mpmath.mpf(float(end_foot_t(P, cs, C, S, arb(str(sp))).mid()))
            e, nu = _mp_point(P, phi), _mp_normal(P, phi)
            x = [e[k] - t * nu[k] for k in (0, 1)]
            E = _mp_point(P, psi)
            assert abs(mpmath.sqrt((x[0] - E[0]) ** 2 + (x[1] - E[1]) ** 2) - t) < 1e-12 * (1 + t)
            if phi == psi:
                det = mpf(P.M[0] * P.N[1] - P.M[1] * P.N[0])
                assert abs(t - sp ** 3 / det) < 1e-12 * (1 + t)


def test_the_end_factor_identity_in_mpmath():
    """|x − e(φ)|² − |x − E|² = 4 sin((φ − ψ)/2)·W(φ, x) at random points x."""
    rng = random.Random(7)
    for _ in range(40):
        P = _random_piece(rng)
        psi = mpmath.atan2(mpf(P.ua[1]), mpf(P.ua[0]))
        E = _mp_point(P, psi)
        phi = mpmath.mpf(rng.uniform(P.phi0, P.phi1))
        x = [mpmath.mpf(rng.uniform(-8, 8)), mpmath.mpf(rng.uniform(-8, 8))]
        e = _mp_point(P, phi)
        lhs = (x[0] - e[0]) ** 2 + (x[1] - e[1]) ** 2 - (x[0] - E[0]) ** 2 - (x[1] - E[1]) ** 2
        W = end_factor(P, arb(str(psi)), (arb(str(E[0])), arb(str(E[1]))), arb(str(phi)),
                       arb(str(x[0])), arb(str(x[1])))
        rhs = 4 * mpmath.sin((phi - psi) / 2) * mpmath.mpf(float(W.mid()))
        assert abs(lhs - rhs) < 1e-10 * (1 + abs(lhs)), (lhs, rhs)


def test_the_monotone_rule_decides_the_nearest_point_on_inner_normals():
    """On a piece between two vertices, the foot e(φ*) of a point on its inner normal is the
    nearest point of the closed piece (dense mpmath sampling) exactly when L > 0 at both ends."""
    rng = random.Random(8)
    agree = {True: 0, False: 0}
    for _ in range(60):
        P = _random_piece(rng)
        phi = mpmath.mpf(rng.uniform(P.phi0, P.phi1))
        t = mpmath.mpf(rng.uniform(0.05, 6))
        e, nu = _mp_point(P, phi), _mp_normal(P, phi)
        x = [e[k] - t * nu[k] for k in (0, 1)]
        n = 400
        best = min(((x[0] - q[0]) ** 2 + (x[1] - q[1]) ** 2)
                   for q in (_mp_point(P, P.phi0 + (P.phi1 - P.phi0) * m / n) for m in range(n + 1)))
        ends = [secant_factor(P, cs, arb(str(phi)), arb(str(t)), -1) for cs in (P.ua, P.ub)]
        if all(L > 0 for L in ends):
            assert best >= t * t - 1e-20
            agree[True] += 1
        elif any(L < 0 for L in ends):
            assert best < t * t
            agree[False] += 1
    assert agree[True] and agree[False]


def test_on_ellipse_is_exact():
    P = _random_piece(random.Random(9))
    q = (P.c[0] + P.ua[0] * P.M[0] + P.ua[1] * P.N[0], P.c[1] + P.ua[0] * P.M[1] + P.ua[1] * P.N[1])
    assert on_ellipse(P, q) == P.ua
    assert on_ellipse(P, (q[0] + 1, q[1])) is None
