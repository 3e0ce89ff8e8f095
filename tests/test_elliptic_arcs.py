"""Elliptic arcs (DXF ELLIPSE) as sites: diagrams against an independent dense-sampling reference,
a medial axis in closed form, the JSON record, bad input, DXF, and the certificate's verdict.

The reference distance to an elliptic arc is this file's own: the squared distance
f(φ) = |q − c − cos φ M − sin φ N|² is sampled densely over the arc's parameter range (taken from
the test's own DXF parameters, cut at multiples of π/2) and its minimum refined by golden-section
search (f is unimodal near a sampled minimum), in mpmath at 30 digits for vertices and in numpy
floats for grids; it shares no code with the library's distance.
"""
from __future__ import annotations

import json
import math

import mpmath
import numpy as np
import pytest

import curvedvoronoi as cv
from curvedvoronoi.runtime.result import InvalidConicError
from curvedvoronoi.runtime.sites.elliptic_arc import EllipticArc
from curvedvoronoi.runtime.sites.reader import parse_site, site_to_json, sites_from_document
from curvedvoronoi.runtime.voronoi.site_input import SiteError


# ------------------------------------------------------------------------------ the reference
class RefEllipse:
    """One elliptic arc by its DXF data, cut at the ellipse's vertices, with its own distances."""

    def __init__(self, centre, major, ratio, s, e):
        self.c = np.array(centre, float)
        self.M = np.array(major, float)
        self.N = ratio * np.array([-major[1], major[0]], float)
        self.s, self.e = float(s), float(e)
        cuts = [k * math.pi / 2 for k in range(math.floor(self.s / (math.pi / 2)) + 1,
                                                 math.ceil(self.e / (math.pi / 2)))]
        ends = [self.s] + [c for c in cuts if self.s < c < self.e] + [self.e]
        self.pieces = list(zip(ends, ends[1:]))

    def point(self, phi):
        return self.c + math.cos(phi) * self.M + math.sin(phi) * self.N

    def grid_distance(self, Q, lo, hi, n=801):
        """(distance, parameter) from the rows of Q to the closed piece [lo, hi], floats."""
        t = np.linspace(lo, hi, n)
        P = self.c + np.cos(t)[:, None] * self.M + np.sin(t)[:, None] * self.N
        D2 = ((Q[:, None, :] - P[None, :, :]) ** 2).sum(axis=2)
        k = D2.argmin(axis=1)
        a, b = t[np.maximum(k - 1, 0)], t[np.minimum(k + 1, n - 1)]
        g = (math.sqrt(5) - 1) / 2

        def f(p):
            X = self.c + np.cos(p)[:, None] * self.M + np.sin(p)[:, None] * self.N
            return ((Q - X) ** 2).sum(axis=1)
        for _ in range(60):
            x1, x2 = b - g * (b - a), a + g * (b - a)
            left = f(x1) < f(x2)
            b = np.where(left, x2, b)
            a = np.where(left, a, x1)
        p = (a + b) / 2
        return np.sqrt(f(p)), p

    def mp_distance(self, q, lo, hi):
        """The distance from q to the closed piece [lo, hi] in mpmath (30 digits)."""
        with mpmath.workdps(30):
            cx, cy, Mx, My, Nx, Ny = (mpmath.mpf(float(v)) for v in (*self.c, *self.M, *self.N))
            qx, qy = mpmath.mpf(float(q[0])), mpmath.mpf(float(q[1]))

            def f(p):
                return (qx - cx - mpmath.cos(p) * Mx - mpmath.sin(p) * Nx) ** 2 + \
                    (qy - cy - mpmath.cos(p) * My - mpmath.sin(p) * Ny) ** 2
            t = np.linspace(lo, hi, 2001)
            vals = [f(mpmath.mpf(float(p))) for p in t]
            k = int(np.argmin([float(v) for v in vals]))
            a, b = mpmath.mpf(float(t[max(k - 1, 0)])), mpmath.mpf(float(t[min(k + 1, 2000)]))
            g = (mpmath.sqrt(5) - 1) / 2
            for _ in range(120):
                x1, x2 = b - g * (b - a), a + g * (b - a)
                if f(x1) < f(x2):
                    b = x2
                else:
                    a = x1
            return float(mpmath.sqrt(f((a + b) / 2)))


def reference_sites(D, ellipses):
    """Per elementary site of D: ("point", xy) or ("piece", RefEllipse, lo, hi), matched to the
    test's own pieces by their float end points."""
    out = []
    for s in D.sites:
        if isinstance(s, EllipticArc):
            a, b = np.array([float(v) for v in s.a]), np.array([float(v) for v in s.b])
            hit = [(R, lo, hi) for R in ellipses for lo, hi in R.pieces
                   if np.allclose(R.point(lo), a, atol=1e-9) and np.allclose(R.point(hi), b, atol=1e-9)]
            assert len(hit) == 1, s
            out.append(("piece",) + hit[0])
        elif isinstance(s, cv.Segment):
            out.append(("segment", np.array([[float(v) for v in s.p], [float(v) for v in s.q]])))
        else:
            out.append(("point", np.array([float(s.cx), float(s.cy)])))
    return out


def ref_distances(refs, Q):
    """(m × n) distances from the rows of Q to every site; a piece whose nearest point is one of
    its ends gets +inf in the second array (the end's point site owns the tie)."""
    Q = np.atleast_2d(np.asarray(Q, float))
    D = np.empty((len(Q), len(refs)))
    owned = np.empty_like(D)
    for k, r in enumerate(refs):
        if r[0] == "point":
            D[:, k] = np.hypot(*(Q - r[1]).T)
            owned[:, k] = D[:, k]
        elif r[0] == "segment":
            a, b = r[1]
            d = b - a
            t = np.clip((Q - a) @ d / (d @ d), 0, 1)
            D[:, k] = np.hypot(*(Q - a - t[:, None] * d).T)
            owned[:, k] = np.where((t > 0) & (t < 1), D[:, k], np.inf)
        else:
            _, R, lo, hi = r
            d, p = R.grid_distance(Q, lo, hi)
            D[:, k] = d
            # an end of the whole arc is a point site (it owns the tie); a cut at a vertex of the
            # ellipse is a smooth joint of two pieces, no site
            at_end = ((np.abs(p - lo) < 1e-7) & (lo == R.s)) | ((np.abs(p - hi) < 1e-7) & (hi == R.e))
            owned[:, k] = np.where(at_end, np.inf, d)
    return D, owned


def check_against_reference(D, ellipses, box, n_grid=160):
    refs = reference_sites(D, ellipses)
    n = len(refs)
    scale = 1.0 + max(abs(v) for v in box)
    # 1. every vertex: at distance r from its sites (mpmath), no site nearer
    for v in D.vertices:
        q = np.array([v.x, v.y])
        d_all, _ = ref_distances(refs, q)
        for k in v.sites:
            r = refs[k]
            dk = R_mp(r, q) if r[0] == "piece" else d_all[0, k]
            assert abs(dk - v.radius) <= 1e-9 * scale, (v, k, dk)
        others = [k for k in range(n) if k not in v.sites]
        if others:
            assert d_all[0, others].min() >= v.radius - 1e-7 * scale, (v, int(np.argmin(d_all[0, others])))
    # 2. every edge: its polyline points equidistant from its two sites, no other site nearer
    for e in D.edges:
        P = np.asarray(e.polyline, float)
        inside = (np.abs(P) <= 3 * max(abs(x) for x in box)).all(axis=1)
        P = P[inside]
        if not len(P):
            continue
        d_all, _ = ref_distances(refs, P)
        i, j = e.sites
        tol = 1e-6 * scale + 1e-6 * d_all[:, [i, j]].max()
        assert np.max(np.abs(d_all[:, i] - d_all[:, j])) <= tol, (e.sites, np.max(np.abs(d_all[:, i] - d_all[:, j])))
        own = np.minimum(d_all[:, i], d_all[:, j])
        rest = np.delete(d_all, [i, j], axis=1)
        if rest.shape[1]:
            assert (rest.min(axis=1) >= own - tol).all(), e.sites
    # 3. the Delaunay graph: neighbouring grid cells of different nearest sites
    x0, x1, y0, y1 = box
    X, Y = np.meshgrid(np.linspace(x0, x1, n_grid), np.linspace(y0, y1, n_grid))
    Q = np.column_stack([X.ravel(), Y.ravel()])
    _, owned = ref_distances(refs, Q)
    lab = owned.argmin(axis=1).reshape(X.shape)
    counts: dict = {}
    for A, B in ((lab[:, :-1], lab[:, 1:]), (lab[:-1, :], lab[1:, :])):
        m = A != B
        for a, b in zip(A[m].tolist(), B[m].tolist()):
            key = (min(a, b), max(a, b))
            counts[key] = counts.get(key, 0) + 1
    ours = {tuple(sorted(int(s) for s in e.sites)) for e in D.edges}
    strong = {k for k, c in counts.items() if c >= 3}
    assert strong <= ours, sorted(strong - ours)
    h = (x1 - x0) / (n_grid - 1)
    for e in D.edges:
        P = np.asarray(e.polyline, float)
        inner = (P[:, 0] > x0 + 3 * h) & (P[:, 0] < x1 - 3 * h) & (P[:, 1] > y0 + 3 * h) & (P[:, 1] < y1 - 3 * h)
        seg = np.hypot(*np.diff(P, axis=0).T)
        if np.sum(seg[inner[:-1] & inner[1:]]) > 6 * h:
            assert tuple(sorted(e.sites)) in counts, e.sites


def R_mp(r, q):
    _, R, lo, hi = r
    return R.mp_distance(q, lo, hi)


# ------------------------------------------------------------------------------ diagrams
def test_arc_and_points_against_dense_sampling():
    R = RefEllipse((0, 0), (4, 0), 0.5, 0.3, 2.5)
    arc = cv.Arc.elliptic((0, 0), (4, 0), "1/2", 0.3, 2.5)
    D = cv.voronoi([arc, (0, 5), (3, -2), (-4, 3)])
    # the certificate's limits only: edges next to the arc it does not cover, the hull accounting
    # (an unbounded end missing among the proved edges while an unbounded edge is unproved)
    assert all(p.startswith("edge ") or "elliptic piece" in p or p.endswith("among the proved edges")
               for p in D.problems), D.problems
    assert len(D.vertices) >= 4
    check_against_reference(D, [R], (-8, 8, -8, 8))


@pytest.mark.slow                 # long check: `invoke test --slow` (not in the README/CI command)
def test_rotated_arc_points_and_a_segment_against_dense_sampling():
    # M = (3, 4): |M| = 5, ratio 1/2; the arc spans the vertices at φ = 0 and φ = π/2
    R = RefEllipse((1, 1), (3, 4), 0.5, -1.0, 2.0)
    arc = cv.Arc.elliptic((1, 1), (3, 4), "1/2", -1.0, 2.0)
    sites = [arc, (1, 1), (7, -2), (-5, 6), (2, 9), cv.Segment((-6, -6), (-1, -7))]
    D = cv.voronoi(sites)
    assert len(D.vertices) >= 6
    check_against_reference(D, [R], (-10, 12, -10, 12))


@pytest.mark.slow                 # long check: `invoke test --slow` (not in the README/CI command)
def test_two_elliptic_arcs_against_dense_sampling():
    R1 = RefEllipse((0, 0), (3, 0), 0.5, -0.5, 2.0)
    R2 = RefEllipse((7, 1), (0, 2), 0.75, 1.0, 4.0)
    a1 = cv.Arc.elliptic((0, 0), (3, 0), "1/2", -0.5, 2.0)
    a2 = cv.Arc.elliptic((7, 1), (0, 2), "3/4", 1.0, 4.0)
    D = cv.voronoi([a1, a2, (3, 4), (4, -3)])
    check_against_reference(D, [R1, R2], (-6, 12, -7, 9))


def test_certificate_never_claims_elliptic_parts():
    arc = cv.Arc.elliptic((0, 0), (4, 0), "1/2", 0.3, 2.5)
    D = cv.voronoi([arc, (0, 5), (3, -2)])
    assert D.certified is False
    # vertices with elliptic pieces are proved (tests/test_elliptic_arc_certificate.py); the edges
    # next to the arc's ends and its infinite edges are not (tests/test_elliptic_arcs_edges.py)
    assert not all(e.certified for e in D.edges) and D.problems


# ------------------------------------------------------------------------------ medial axis
def test_medial_axis_of_a_half_ellipse_in_closed_form():
    """The right half of x²/25 + y²/9 <= 1 closed by the minor axis: with c² = a² − b² = 16 its
    medial axis holds the piece of the symmetry line y = 0 from the vertex (bc/a, 0) = (12/5, 0)
    (radius 12/5, touching the segment and both quarters) to the centre of curvature
    (c²/a, 0) = (16/5, 0), with inscribed radius b·√(1 − x²/c²) (the distance from (x, 0) to the
    ellipse for |x| <= c²/a)."""
    arc = cv.Arc.elliptic((0, 0), (5, 0), "3/5", -math.pi / 2, math.pi / 2)
    assert (arc.a, arc.b) == ((0, -3), (0, 3))
    m = cv.medial_axis([arc, cv.Segment((0, 3), (0, -3))])
    assert m.certified is False                      # elliptic parts are not certified
    v = [w for w in m.vertices if w.radius > 0]
    assert len(v) == 1 and abs(v[0].x - 2.4) < 1e-12 and abs(v[0].y) < 1e-12 and abs(v[0].radius - 2.4) < 1e-12
    axis = [e for e in m.edges if np.abs(e.polyline[:, 1]).max() < 1e-12]
    assert len(axis) == 1
    xs = axis[0].polyline[:, 0]
    assert abs(xs.min() - 2.4) < 1e-12 and abs(xs.max() - 3.2) < 1e-9
    assert np.allclose(axis[0].radius, 3 * np.sqrt(1 - xs ** 2 / 16), atol=1e-9)
    # every medial point: its radius is the reference distance to the boundary, reached twice
    R = RefEllipse((0, 0), (5, 0), 0.6, -math.pi / 2, math.pi / 2)
    for e in m.edges:
        P = e.polyline[1:-1]
        if not len(P):
            continue
        d_arc = np.minimum(*(R.grid_distance(P, lo, hi)[0] for lo, hi in R.pieces))
        d_seg = np.hypot(np.abs(P[:, 0]), np.maximum(np.abs(P[:, 1]) - 3, 0))
        assert np.allclose(e.radius[1:-1], np.minimum(d_arc, d_seg), atol=1e-7)
    x, y, r = m.largest_inscribed_circle
    assert (round(x, 9), round(y, 9), round(r, 9)) == (2.4, 0.0, 2.4)


# ------------------------------------------------------------------------------ sites, JSON, errors
def test_ends_are_rational_and_exact_at_quarter_turns():
    arc = cv.Arc.elliptic((1, 2), (3, 4), "1/5", 0, math.pi)
    assert arc.a == (4, 6) and arc.b == (-2, -2)
    # a rational point of the ellipse: c + u M + v N with u² + v² = 1 exactly
    arc = cv.Arc.elliptic((0, 0), (2, 0), "1/2", 0.7, 2.0)
    u, v = arc.ua
    assert u * u + v * v == 1 and abs(float(u) - math.cos(0.7)) < 1e-15
    assert arc.a == (2 * u, v)                        # N = (0, 1)
    assert [(p.a, p.b) for p in arc.pieces()][0][1] == (0, 1)


@pytest.mark.parametrize("ratio, axis, match", [(0, (2, 0), "ratio"), (-1, (2, 0), "ratio"), ("3/2", (2, 0), "ratio"),
                                                 (1, (2, 0), "circular"), ("1/2", (0, 0), "major axis")])
def test_bad_input_one_clear_error(ratio, axis, match):
    with pytest.raises(InvalidConicError, match=match) as exc:
        cv.Arc.elliptic((0, 0), axis, ratio, 0, 1)
    assert "\n" not in str(exc.value)


def test_json_record_round_trip_and_schema():
    arc = cv.Arc.elliptic((0, 0), (3, 4), "1/2", 0.25, 1.75, label="rim")
    rec = site_to_json(arc)
    assert set(rec["elliptic_arc"]) == {"centre", "major_axis", "ratio", "start_direction", "end_direction"}
    assert rec["label"] == "rim"
    back = parse_site(json.loads(json.dumps(rec)))
    assert back == arc and back.label == "rim"
    sites = sites_from_document({"sites": [rec, {"elliptic_arc": {"centre": [0, 0], "major_axis": [2, 0],
                                                                  "ratio": "1/2", "start_param": 0,
                                                                  "end_param": 3.141592653589793}}]})
    assert sites[1].b == (-2, 0)
    with pytest.raises(ValueError, match="elliptic_arc"):
        sites_from_document({"sites": [{"elliptic_arc": {"centre": [0, 0], "major_axis": [2, 0], "ratio": "1/2"}}]})
    with pytest.raises(ValueError, match="ratio"):
        sites_from_document({"sites": [{"elliptic_arc": {"centre": [0, 0], "major_axis": [2, 0], "ratio": 2,
                                                         "start_param": 0, "end_param": 1}}]})
    d = cv.voronoi([arc, (0, 0)])
    doc = d.to_json()
    assert sum("elliptic_arc" in s for s in doc["sites"]) == 2    # the arc crosses the vertex φ = π/2: two pieces


def test_crossing_segment_is_refused():
    arc = cv.Arc.elliptic((0, 0), (4, 0), "1/2", 0, math.pi)
    with pytest.raises(SiteError, match="elliptic arc"):
        cv.voronoi([arc, cv.Segment((0, 0), (0, 5))])
    with pytest.raises(SiteError, match="lies on"):
        cv.voronoi([arc, (0, 2), (5, 5)])


@pytest.mark.slow                 # long check: `invoke test --slow` (not in the README/CI command)
def test_dxf_ellipse(tmp_path):
    ezdxf = pytest.importorskip("ezdxf")
    doc = ezdxf.new()
    msp = doc.modelspace()
    msp.add_ellipse((0, 0), major_axis=(4, 0), ratio=0.5, start_param=0.3, end_param=2.5)
    msp.add_ellipse((10, 0), major_axis=(0, 3), ratio=0.5, start_param=0, end_param=2 * math.pi)
    msp.add_point((0, 6))
    path = tmp_path / "e.dxf"
    doc.saveas(path)
    pieces, sources, _labels = cv.read_dxf(path)
    assert [type(p).__name__ for p in pieces] == ["EllipticArc", "EllipticArc", "EllipticArc", "Point"]
    assert sources == [0, 1, 1, 2]
    assert pieces[0] == cv.Arc.elliptic((0, 0), (4, 0), "1/2", 0.3, 2.5)
    assert pieces[1].a == (10, 3) and pieces[1].b == (10, -3)
    D = cv.voronoi(pieces)
    assert D.vertices and D.certified is False


def test_a_contact_at_a_local_maximum_is_never_proved():
    """The normal line at the end e of a piece, beyond the centre of curvature there: e is a local
    maximum of the distance along the ellipse, so the zero of (point e, point p, normal at e) is
    not a vertex (interior points of the piece are nearer; checked here by the reference)."""
    from curvedvoronoi.runtime.segments.elementary import decompose
    from curvedvoronoi.runtime.segments.vertices import prove_zero

    arc = cv.Arc.elliptic((0, 0), (4, 0), "1/2", 0.3, 2.5)
    E = decompose([arc, cv.Point(3, -2)])
    e = next(k for k in range(E.n_points) if abs(float(E.xy[k][0]) - 4 * math.cos(0.3)) < 1e-9)
    p = next(k for k in range(E.n_points) if E.xy[k] == (3, -2))
    s = next(k for k in range(E.n_points, len(E)) if e in E.ends[k])
    tx, ty = arc.tangent(arc.ua)
    eqs = [("point", E.xy[e], e), ("point", E.xy[p], p), ("normal", (tx, ty) + tuple(E.xy[e]), s)]
    sol = prove_zero(E, (e, p, s), eqs, np.array([2.2976, -0.3516, 1.79]), 10.0)
    R = RefEllipse((0, 0), (4, 0), 0.5, 0.3, 2.5)
    nearer = R.mp_distance((sol.x, sol.y), 0.3, math.pi / 2)
    assert nearer < sol.r - 1e-3                  # the reference: the piece comes nearer
    assert sol.status != "proved"
