"""The segment/arc certificate with elliptic-arc pieces (thesis §2.2 harmless sites, ch. 4 foot
points): vertices touching elliptic pieces are proved, and checked here against an independent
mpmath reference (the distance to a piece by the roots of the foot-point equation f'(φ) = 0 found
with ``mpmath.findroot`` and the two ends — none of the project's distance code); corrupted
diagrams are refused.  The scenes here keep parts the certificate does not prove yet (pieces on the
points' hull, infinite ends of a curve's end), so each is refused as a whole while its unproved edge
is named as a limit, not a fault; certified scenes are in tests/test_elliptic_arcs_certified.py."""
from __future__ import annotations

import copy
import math
import time

import mpmath
import pytest
from flint import arb

import curvedvoronoi as cv
from curvedvoronoi.runtime.segments.certificate import verify_segments
from curvedvoronoi.runtime.segments.certificate_ellipses import end_contact_valid, interior_contact_valid
from curvedvoronoi.runtime.segments.ellipse_pieces import PieceData
from curvedvoronoi.runtime.sites.elliptic_arc import EllipticArc

DPS = 40


# ------------------------------------------------------------------------------ the reference
def _mp(q):
    return mpmath.mpf(q.numerator) / q.denominator


class RefPiece:
    """e(φ) = c + cos φ M + sin φ N on [φ₀, φ₁], from the site's exact data, in mpmath."""

    def __init__(self, s: EllipticArc):
        with mpmath.workdps(DPS):
            self.c = [_mp(v) for v in s.c]
            self.M = [_mp(v) for v in s.M]
            self.N = [_mp(v) for v in s.N]
            ua, ub = [_mp(v) for v in s.ua], [_mp(v) for v in s.ub]
            self.p0 = mpmath.atan2(ua[1], ua[0])
            span = mpmath.atan2(ua[0] * ub[1] - ua[1] * ub[0], ua[0] * ub[0] + ua[1] * ub[1])
            self.p1 = self.p0 + (span if span > 0 else span + 2 * mpmath.pi)

    def point(self, p):
        return [self.c[i] + mpmath.cos(p) * self.M[i] + mpmath.sin(p) * self.N[i] for i in range(2)]

    def distance(self, q):
        """min over the piece of |q − e(φ)|: the ends and every root of f'(φ) = 0 inside."""
        with mpmath.workdps(DPS):
            qx, qy = mpmath.mpf(q[0]), mpmath.mpf(q[1])

            def f(p):
                x, y = self.point(p)
                return (qx - x) ** 2 + (qy - y) ** 2

            def df(p):
                return mpmath.diff(f, p)
            cands = [self.p0, self.p1]
            grid = [self.p0 + (self.p1 - self.p0) * k / 200 for k in range(201)]
            vals = [df(p) for p in grid]
            for a, b, fa, fb in zip(grid, grid[1:], vals, vals[1:]):
                if fa * fb < 0:
                    cands.append(mpmath.findroot(df, (a, b), solver="anderson"))
            return mpmath.sqrt(min(f(p) for p in cands))


def ref_distance(site, q):
    with mpmath.workdps(DPS):
        if isinstance(site, EllipticArc):
            return RefPiece(site).distance(q)
        if isinstance(site, cv.Segment):
            (ax, ay), (bx, by) = [[_mp(v) for v in p] for p in (site.p, site.q)]
            qx, qy = mpmath.mpf(q[0]), mpmath.mpf(q[1])
            t = ((qx - ax) * (bx - ax) + (qy - ay) * (by - ay)) / ((bx - ax) ** 2 + (by - ay) ** 2)
            t = min(max(t, 0), 1)
            return mpmath.hypot(qx - ax - t * (bx - ax), qy - ay - t * (by - ay))
        px, py = (mpmath.mpf(int(v.p)) / int(v.q) for v in (site.cx, site.cy))
        return mpmath.hypot(mpmath.mpf(q[0]) - px, mpmath.mpf(q[1]) - py)


# ------------------------------------------------------------------------------ scenes
def _rectangle(w, h):
    P = [(-w, -h), (w, -h), (w, h), (-w, h)]
    return [cv.Segment(P[i], P[(i + 1) % 4]) for i in range(4)]


SCENES = {
    "arc_and_points": lambda: [cv.Arc.elliptic((0, 0), (4, 0), "1/2", 0.3, 2.5), (0, 5), (3, -2), (-4, 3)],
    "rotated_arc_points_segment": lambda: [cv.Arc.elliptic((1, 1), (3, 4), "1/2", -1.0, 2.0), (1, 1), (7, -2),
                                           (-5, 6), (2, 9), cv.Segment((-6, -6), (-1, -7))],
    "arc_in_rectangle": lambda: [cv.Arc.elliptic((0, 0), (4, 0), "1/2", 0.3, 5.5)] + _rectangle(7, 5),
    "ellipse_in_rectangle": lambda: EllipticArc.from_dxf((0, 0), (3, 0), "2/3", 0, 2 * math.pi) + _rectangle(6, 5),
    "two_arcs": lambda: [cv.Arc.elliptic((0, 0), (3, 0), "1/2", -0.5, 2.0),
                         cv.Arc.elliptic((7, 1), (0, 2), "3/4", 1.0, 4.0), (3, 4), (4, -3)],
}


@pytest.fixture(scope="module", params=sorted(SCENES))
def scene(request):
    D = cv.voronoi(SCENES[request.param](), certify=False)
    # vertices only: a deadline already passed leaves the edges unchecked (a limit; the edges are
    # tests/test_elliptic_arcs_edges.py's)
    return request.param, D, verify_segments(D, deadline=time.perf_counter())


def test_vertices_proved_and_equidistant_by_mpmath(scene):
    name, D, C = scene
    assert not C.ok                       # edges not checked here
    assert not any(p.fault for p in C.problems), [str(p) for p in C.problems]
    assert any(isinstance(s, EllipticArc) for s in D.sites)
    touching = 0
    for v, ok in zip(D.vertices, C.vertices):
        listed = [int(s) for s in v.sites]
        elliptic = any(isinstance(D.sites[s], EllipticArc) for s in listed)
        if len(listed) == 3:
            assert ok, f"{name}: vertex {v.id} {listed} not proved: {[str(p) for p in C.problems]}"
        if not ok:
            assert len(listed) > 3            # only vertices of 4 sites with an elliptic piece are refused
            continue
        touching += elliptic
        q = (float(v.x), float(v.y))
        r = mpmath.mpf(float(v.radius))
        tol = 1e-9 * (1 + abs(q[0]) + abs(q[1]) + float(v.radius))
        for s in listed:
            assert abs(ref_distance(D.sites[s], q) - r) <= tol, (name, v.id, s)
        for s in range(len(D.sites)):
            if s not in listed:
                assert ref_distance(D.sites[s], q) >= r - tol, (name, v.id, s)
    assert touching >= 3


def test_the_diagram_is_refused_as_a_whole_while_an_edge_is_unproved():
    D = cv.voronoi(SCENES["arc_and_points"]())
    assert D.certified is False
    C = cv.verify(D)
    assert not C.ok and all(C.vertices) and not all(C.edges)
    assert not any(p.fault for p in C.problems)
    assert any(p.edge is not None and not p.fault for p in C.problems)


# ------------------------------------------------------------------------------ corruptions
@pytest.fixture(scope="module")
def document():
    D = cv.voronoi(SCENES["rotated_arc_points_segment"](), certify=False)
    return D.to_json()


def _elliptic_vertex(doc):
    kinds = ["elliptic_arc" in s for s in doc["sites"]]
    return next(i for i, v in enumerate(doc["vertices"]) if len(v["sites"]) == 3 and any(kinds[s] for s in v["sites"]))


def _vertex_proofs(doc):
    """The certificate's vertex proofs only (its edge proofs of this scene take ~50 s; a passed
    deadline leaves the edges unchecked, so the certificate is never ``ok``)."""
    return verify_segments(doc, deadline=time.perf_counter())


def test_the_document_as_reported_has_its_vertices_proved(document):
    C = _vertex_proofs(copy.deepcopy(document))
    assert all(C.vertices) and not any(p.fault for p in C.problems)


@pytest.mark.parametrize("delta", [1e-6, 1e-3])
def test_a_moved_vertex_is_refused(document, delta):
    doc = copy.deepcopy(document)
    i = _elliptic_vertex(doc)
    doc["vertices"][i]["x"] += delta
    C = _vertex_proofs(doc)
    assert not C.vertices[i]
    assert any(p.fault and p.vertex == doc["vertices"][i]["id"] for p in C.problems)


def test_a_wrong_radius_is_refused(document):
    doc = copy.deepcopy(document)
    i = _elliptic_vertex(doc)
    doc["vertices"][i]["radius"] *= 1 + 1e-7
    C = _vertex_proofs(doc)
    assert not C.vertices[i] and any(p.fault for p in C.problems)


def test_sites_listed_clockwise_are_refused(document):
    doc = copy.deepcopy(document)
    i = _elliptic_vertex(doc)
    doc["vertices"][i]["sites"] = doc["vertices"][i]["sites"][::-1]
    C = _vertex_proofs(doc)
    assert not C.vertices[i] and any(p.fault for p in C.problems)


def test_a_dropped_edge_is_refused(document):
    doc = copy.deepcopy(document)
    kinds = ["elliptic_arc" in s for s in doc["sites"]]
    k = next(k for k, e in enumerate(doc["edges"]) if any(kinds[s] for s in e["sites"]) and
             all(x is not None for x in e["ends"]))
    del doc["edges"][k]
    doc["delaunay_edges"] = sorted({tuple(sorted(e["sites"])) for e in doc["edges"]})
    doc["delaunay_edges"] = [list(p) for p in doc["delaunay_edges"]]
    C = _vertex_proofs(doc)              # the vertices' accounting of their incident edges sees it
    assert not C.ok
    assert any(p.fault and "incident edge" in str(p) for p in C.problems)


@pytest.mark.slow                 # long check: `invoke test --slow` (not in the README/CI command)
def test_a_pushed_edge_polyline_is_not_certified(document):
    """A polyline pushed off its bisector is never certified."""
    doc = copy.deepcopy(document)
    kinds = ["elliptic_arc" in s for s in doc["sites"]]
    k = next(k for k, e in enumerate(doc["edges"]) if any(kinds[s] for s in e["sites"]))
    doc["edges"][k]["polyline"] = [[x + 0.5, y] for x, y in doc["edges"][k]["polyline"]]
    C = cv.verify(doc)
    assert not C.ok and not C.edges[k]


# ------------------------------------------------------------------------------ contacts
def test_an_end_is_the_nearest_point_only_before_the_centre_of_curvature():
    """Piece φ ∈ [0, π/2] of x²/16 + y²/4 = 1 ends at the minor vertex (0, 2), whose centre of
    curvature is (0, 2 − a²/b) = (0, −6).  From (0, 1) the end is the nearest point (distance 1);
    from (0, −7) (beyond) the mpmath reference finds a nearer point of the piece."""
    arc = EllipticArc((0, 0), (4, 0), "1/2", (1, 0), (0, 1))
    P = PieceData.of(arc)
    ref = RefPiece(arc)
    assert abs(ref.distance((0, 1)) - 1) < 1e-30
    assert ref.distance((0, -7)) < 9 - 0.1
    assert end_contact_valid(P, 1, arb(0), arb(1), arb(1)) is True
    assert end_contact_valid(P, 1, arb(0), arb(-7), arb(9)) is False
    assert end_contact_valid(P, 0, arb(0), arb(1), arb(1)) is False       # the other end: not a contact


def test_an_interior_contact_at_a_local_maximum_is_refused():
    """On the piece φ ∈ [0, π/2] of x²/16 + y²/4 = 1, the inner normal at φ = π/4 has the radius of
    curvature (a² sin² φ + b² cos² φ)^{3/2}/(ab) = 10^{3/2}/8 ≈ 3.95: at depth 1/2 the foot e(π/4)
    is the nearest point (the mpmath distance is 1/2), proved; at depth 6 it is a local maximum of
    the distance along the ellipse, refused."""
    arc = EllipticArc((0, 0), (4, 0), "1/2", (1, 0), (0, 1))
    P = PieceData.of(arc)
    ref = RefPiece(arc)
    with mpmath.workdps(DPS):
        e = ref.point(mpmath.pi / 4)
        n = [mpmath.mpf(1) / mpmath.sqrt(5), mpmath.mpf(2) / mpmath.sqrt(5)]      # outer normal ∝ (x/a², y/b²)
        for depth, proved in ((mpmath.mpf(1) / 2, True), (mpmath.mpf(6), False)):
            q = [float(e[i] - depth * n[i]) for i in range(2)]
            d = ref.distance(q)
            if proved:
                assert abs(d - depth) < 1e-12
            else:
                assert d < depth - 0.1
            R = arb(float(mpmath.hypot(q[0] - e[0], q[1] - e[1])), 1e-12)
            assert (interior_contact_valid(P, arb(q[0]), arb(q[1]), R) is True) is proved


def test_float_bounds_and_distance_balls_hold_the_mpmath_distance():
    """The certificate's float bounds (bounding disc, nearer end) and arb balls of the distance to
    a piece hold the mpmath distance, for points near and far, inside and outside the ellipse."""
    import numpy as np
    from curvedvoronoi.runtime.segments.certificate_sites import ELLIPSE, SiteTable

    D = cv.voronoi(SCENES["two_arcs"](), certify=False)
    T = SiteTable(D.sites)
    pieces = [k for k in range(T.n) if T.kind[k] == ELLIPSE]
    assert len(pieces) == 6
    rng = np.random.default_rng(5)
    Q = np.concatenate([rng.uniform(-5, 12, (12, 2)), rng.normal((0, 0), 0.3, (4, 2)), rng.normal((7, 1), 0.3, (4, 2))])
    for k in pieces:
        lo, hi = T.float_bounds(np.full(len(Q), k), Q)
        for q, l, h in zip(Q, lo, hi):
            d = ref_distance(D.sites[k], q)
            assert l <= d <= h
            ball = T.distance(k, arb(float(q[0])), arb(float(q[1])))
            assert ball.overlaps(arb(mpmath.nstr(d, 30), 1e-28)), (k, q, ball, d)
            assert float(ball.rad()) < 1e-8 * (1 + float(d))


def test_a_curve_end_owns_the_tie_only_where_it_is_the_nearest_point_alone():
    """Emptiness lets an unlisted piece tie at a listed end e only when e is its nearest point
    alone: checked against the mpmath distance (the end's distance equals the piece's, or not)."""
    import numpy as np
    from curvedvoronoi.runtime.segments.certificate_sites import ELLIPSE, SiteTable

    D = cv.voronoi(SCENES["arc_and_points"](), certify=False)
    T = SiteTable(D.sites)
    seen = {True: 0, False: 0}
    for k in range(T.n):
        if T.kind[k] != ELLIPSE:
            continue
        for e in T.ends[k]:
            if e < 0:
                continue
            for q in [(5, -1), (-5, 0), (0, 3), (0, 1), (3, 3), (-4, 2), (2, 0.5), (6, 2)]:
                d, de = ref_distance(D.sites[k], q), ref_distance(D.sites[e], q)
                own = T.owned_by_end(k, e, arb(q[0]), arb(q[1]))
                if own is True:
                    assert abs(d - de) < 1e-25
                if de > d + 1e-6:
                    assert own is not True
                seen[own is True] += 1
    assert seen[True] >= 3 and seen[False] >= 3


def test_both_ends_own_the_tie_only_where_the_piece_bulges_away():
    """On the perpendicular bisector of the chord of the piece φ ∈ [0, π/2] of x²/16 + y²/4 = 1
    (ends (4, 0) and (0, 2)), 10 away from the chord's middle: beyond the centre side the ends are
    the nearest points (mpmath: the piece's distance equals the ends'), on the outer side the piece
    is nearer; only the first is proved owned by both ends."""
    from curvedvoronoi.runtime.segments.certificate_ellipses import owned_by_both_ends

    arc = EllipticArc((0, 0), (4, 0), "1/2", (1, 0), (0, 1))
    P = PieceData.of(arc)
    ref = RefPiece(arc)
    for side in (-1, 1):
        q = (2 + side * 10 / math.sqrt(5), 1 + side * 20 / math.sqrt(5))
        d, de = ref.distance(q), mpmath.hypot(q[0] - 4, q[1])
        own = owned_by_both_ends(P, arb(q[0]), arb(q[1]))
        if side < 0:
            assert abs(d - de) < 1e-12 and own is True      # q in floats: the ends tie to 1e-15
        else:
            assert d < de - 0.1 and own is not True


def test_a_foot_of_the_ellipse_outside_the_piece_is_no_contact():
    """From a point 0.3 inside the ellipse x²/16 + y²/4 = 1 on its normal at φ = 2.5, the ellipse's
    foot e(2.5) is outside the piece φ ∈ [0, π/2] (mpmath: the piece is more than 2 away): a circle
    of radius 0.3 about it does not touch the piece, and is not proved to."""
    arc = EllipticArc((0, 0), (4, 0), "1/2", (1, 0), (0, 1))
    P = PieceData.of(arc)
    with mpmath.workdps(DPS):
        p = mpmath.mpf(2.5)
        e = [4 * mpmath.cos(p), 2 * mpmath.sin(p)]
        n = [mpmath.cos(p) / 4, mpmath.sin(p) / 2]                    # outer normal ∝ (x/a², y/b²)
        m = mpmath.hypot(*n)
        q = [float(e[i] - mpmath.mpf("0.3") * n[i] / m) for i in range(2)]
        assert RefPiece(arc).distance(q) > 2
        R = arb(float(mpmath.hypot(q[0] - e[0], q[1] - e[1])), 1e-12)
    assert interior_contact_valid(P, arb(q[0]), arb(q[1]), R) is not True
