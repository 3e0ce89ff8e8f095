"""The independent certificate of point/segment/arc Voronoi diagrams (runtime/segments/certificate.py)
with circular arcs and smooth joints.

Hand-built diagrams in closed form — a lone quarter arc (the vertex at its centre, the radial rays
through its ends, the bisector of its ends), an arc with a point inside its circle (an ellipse arc
between two vertices on the radial lines of the arc's ends), an arc with a point outside (a
hyperbola arc between two vertices on those radial lines), a stadium (the two centres, the middle
segment as the edge of the two sides, the normal lines at the four smooth joints), a rounded
rectangle — are proved; corrupted copies are rejected with the faulty part named (a vertex moved,
an arc-centre vertex with a site inside its disc or without an end, an arc's bisector drawn as its
chord, an infinite end going the wrong way).  Then the construction's output on these and on
scenes with tails (branches of a point or an arc outside a circle), full circles of arcs and
S-curves."""
from __future__ import annotations

import copy
import math
from fractions import Fraction as F

import numpy as np
import pytest

import curvedvoronoi as cv
from curvedvoronoi.runtime.predicates.circles import Point
from curvedvoronoi.runtime.segments.certificate import verify_segments
from curvedvoronoi.runtime.segments.certificate_hull import expected_infinite_ends
from curvedvoronoi.runtime.segments.certificate_sites import SiteTable
from curvedvoronoi.runtime.sites.arc import Arc
from curvedvoronoi.runtime.sites.segment import Segment
from curvedvoronoi.runtime.voronoi.structure import Diagram, DiagramEdge, DiagramVertex

TOL = 1e-12
FAR = 50.0


def diagram(sites, vertices, edges) -> Diagram:
    """vertices: (sites, x, y, r); edges: (pair, ends, polyline, tolerance)."""
    V = [DiagramVertex(n, tuple(s), float(x), float(y), float(r)) for n, (s, x, y, r) in enumerate(vertices)]
    E = [DiagramEdge(n, tuple(p), tuple(ends), False, np.asarray(poly, float).reshape(-1, 2), tol)
         for n, (p, ends, poly, tol) in enumerate(edges)]
    return Diagram(list(sites), V, E)


def faults(c, kind=None, **fields):
    return [p for p in c.problems if (kind is None or p.kind == kind) and
            all(getattr(p, k, None) == v for k, v in fields.items())]


# ------------------------------------------------------------------------------------ closed forms
def quarter():
    """The arc of radius 2 from (2, 0) to (0, 2): the vertex at its centre (0, 0) with radius 2
    (contacts: the end (2, 0), the whole arc, the end (0, 2)); the radial rays through the ends;
    the bisector of the ends towards (−1, −1)."""
    sites = [Point(2, 0), Point(0, 2), Arc((0, 0), 2, (2, 0), (0, 2))]
    return diagram(sites, [((0, 2, 1), 0, 0, 2)],
                   [((0, 2), (0, None), [(0, 0), (FAR, 0)], TOL),
                    ((1, 2), (0, None), [(0, 0), (0, FAR)], TOL),
                    ((0, 1), (0, None), [(0, 0), (-FAR, -FAR)], TOL)])


def _polar(r_of, a, b, n=257):
    th = np.linspace(a, b, n)
    r = r_of(th)
    return np.stack([r * np.cos(th), r * np.sin(th)], axis=1)


def point_inside():
    """The upper half circle of radius 2 and the point p = (0, 1/2): the ellipse
    |v − p| = 2 − |v|, r(θ) = (15/4)/(4 − sin θ), between the vertices (±15/16, 0) of radius 17/16
    on the radial lines of the arc's ends; below, the bisectors of p and the ends meet at
    (0, −15/4) (radius 17/4), whence the bisector of the two ends goes down."""
    sites = [Point(2, 0), Point(-2, 0), Point(0, F(1, 2)), Arc((0, 0), 2, (2, 0), (-2, 0))]
    ellipse = _polar(lambda t: 3.75 / (4 - np.sin(t)), 0.0, math.pi)
    ellipse[0], ellipse[-1] = (15 / 16, 0), (-15 / 16, 0)
    return diagram(sites,
                   [((0, 3, 2), 15 / 16, 0, 17 / 16), ((1, 2, 3), -15 / 16, 0, 17 / 16), ((0, 2, 1), 0, -3.75, 4.25)],
                   [((2, 3), (0, 1), ellipse, 1e-3),
                    ((0, 3), (0, None), [(15 / 16, 0), (FAR, 0)], TOL),
                    ((1, 3), (1, None), [(-15 / 16, 0), (-FAR, 0)], TOL),
                    ((0, 2), (0, 2), [(15 / 16, 0), (0, -3.75)], TOL),
                    ((1, 2), (1, 2), [(-15 / 16, 0), (0, -3.75)], TOL),
                    ((0, 1), (2, None), [(0, -3.75), (0, -FAR)], TOL)])


def point_outside():
    """The quarter arc of radius 2 from (2, 0) to (0, 2) and the point p = (3, 3): the arc's centre
    is a vertex (the disc of radius 2 is empty), the radial rays end where p takes over, at (7, 0)
    and (0, 7) (radius 5), joined by the hyperbola |v − p| = |v| − 2: v = (2 + t) u(θ),
    t = (22 − 12 s)/(2 (3 s − 2)), s = cos θ + sin θ."""
    sites = [Point(2, 0), Point(0, 2), Point(3, 3), Arc((0, 0), 2, (2, 0), (0, 2))]

    def r_of(th):
        s = np.cos(th) + np.sin(th)
        return 2 + (22 - 12 * s) / (2 * (3 * s - 2))
    hyperbola = _polar(r_of, 0.0, math.pi / 2)
    hyperbola[0], hyperbola[-1] = (7, 0), (0, 7)
    return diagram(sites,
                   [((0, 3, 1), 0, 0, 2), ((0, 2, 3), 7, 0, 5), ((1, 3, 2), 0, 7, 5)],
                   [((0, 3), (0, 1), [(0, 0), (7, 0)], TOL),
                    ((1, 3), (0, 2), [(0, 0), (0, 7)], TOL),
                    ((0, 1), (0, None), [(0, 0), (-FAR, -FAR)], TOL),
                    ((2, 3), (1, 2), hyperbola, 1e-3),
                    ((0, 2), (1, None), [(7, 0), (7 + 3 * FAR, -FAR)], TOL),
                    ((1, 2), (2, None), [(0, 7), (-FAR, 7 + 3 * FAR)], TOL)])


def stadium():
    """Two sides and two half circles meeting smoothly (no point sites): vertices at the centres
    (0, 1) and (4, 1) of radius 1, the middle segment as the edge of the two sides, the normal lines
    at the four joints (through the joints) to infinity."""
    sites = [Segment((0, 0), (4, 0)), Arc((4, 1), 1, (4, 0), (4, 2)), Segment((4, 2), (0, 2)),
             Arc((0, 1), 1, (0, 2), (0, 0))]
    return diagram(sites, [((0, 2, 3), 0, 1, 1), ((0, 1, 2), 4, 1, 1)],
                   [((0, 2), (0, 1), [(0, 1), (4, 1)], TOL),
                    ((0, 3), (0, None), [(0, 1), (0, -FAR)], TOL),
                    ((2, 3), (0, None), [(0, 1), (0, FAR)], TOL),
                    ((0, 1), (1, None), [(4, 1), (4, -FAR)], TOL),
                    ((1, 2), (1, None), [(4, 1), (4, FAR)], TOL)])


def rounded_rectangle():
    """The 4 × 3 rectangle with fillets of radius 1: the fillets' centres are vertices (each with
    the two sides it joins), the medial axis (1.5, 1.5)–(2.5, 1.5) with its four diagonal branches,
    the eight joint normals to infinity."""
    sites = [Segment((1, 0), (3, 0)), Arc((3, 1), 1, (3, 0), (4, 1)), Segment((4, 1), (4, 2)),
             Arc((3, 2), 1, (4, 2), (3, 3)), Segment((3, 3), (1, 3)), Arc((1, 2), 1, (1, 3), (0, 2)),
             Segment((0, 2), (0, 1)), Arc((1, 1), 1, (0, 1), (1, 0))]
    V = [((4, 5, 6), 1, 2, 1), ((0, 1, 2), 3, 1, 1), ((0, 6, 7), 1, 1, 1), ((2, 3, 4), 3, 2, 1),
         ((0, 4, 6), 1.5, 1.5, 1.5), ((0, 2, 4), 2.5, 1.5, 1.5)]
    E = [((5, 6), (0, None), [(1, 2), (-FAR, 2)]), ((4, 6), (0, 4), [(1, 2), (1.5, 1.5)]),
         ((4, 5), (0, None), [(1, 2), (1, FAR)]), ((1, 2), (1, None), [(3, 1), (FAR, 1)]),
         ((0, 2), (1, 5), [(3, 1), (2.5, 1.5)]), ((0, 1), (1, None), [(3, 1), (3, -FAR)]),
         ((0, 7), (2, None), [(1, 1), (1, -FAR)]), ((0, 6), (2, 4), [(1, 1), (1.5, 1.5)]),
         ((6, 7), (2, None), [(1, 1), (-FAR, 1)]), ((3, 4), (3, None), [(3, 2), (3, FAR)]),
         ((2, 4), (3, 5), [(3, 2), (2.5, 1.5)]), ((2, 3), (3, None), [(3, 2), (FAR, 2)]),
         ((0, 4), (4, 5), [(1.5, 1.5), (2.5, 1.5)])]
    return diagram(sites, V, [e + (TOL,) for e in E])


CLOSED_FORMS = {"quarter arc": quarter, "point inside": point_inside, "point outside": point_outside,
                "stadium": stadium, "rounded rectangle": rounded_rectangle}


@pytest.mark.parametrize("name", sorted(CLOSED_FORMS))
def test_closed_form_arc_diagrams_are_proved(name):
    D = CLOSED_FORMS[name]()
    c = verify_segments(D)
    assert c.ok, c.problems
    assert c.complete and all(c.vertices) and all(c.edges)
    assert c.delaunay_edges == sorted({tuple(sorted(e.sites)) for e in D.edges})


def test_the_unbounded_ends_with_arcs():
    """The support envelope: the quarter arc's three directions; the arc and a point outside its
    circle give a tangent end (a hyperbola branch) named ("tangent", ±1)."""
    T = SiteTable(quarter().sites)
    assert sorted(expected_infinite_ends(T)) == sorted([((0, 1), (-1, -1)), ((0, 2), (1, 0)), ((1, 2), (0, 1))])
    sites = [Point(3, 4), Point(-4, 3), Point(7, 8), Arc((0, 0), 5, (3, 4), (-4, 3))]
    ends = expected_infinite_ends(SiteTable(sites))
    assert sorted(p for p, _ in ends) == [(0, 1), (0, 2), (1, 3), (2, 3)]
    assert [k for p, k in ends if p == (2, 3)] == [("tangent", -1)]
    T = SiteTable(stadium().sites)                     # smooth joints: no point sites at all
    assert sorted(expected_infinite_ends(T)) == sorted([((0, 3), (0, -1)), ((0, 1), (0, -1)),
                                                        ((2, 3), (0, 1)), ((1, 2), (0, 1))])


# ------------------------------------------------------------------------------------ corruptions
def test_a_moved_arc_centre_vertex_is_rejected():
    D = stadium()
    D.vertices[0].y += 1e-6
    c = verify_segments(D)
    assert not c.ok and not c.vertices[0] and c.vertices[1]
    assert faults(c, "vertex", vertex=0)


def test_an_arc_centre_vertex_with_a_site_inside_its_disc_is_rejected():
    D = stadium()
    D.sites.append(Point(F(-1, 2), 1))                 # inside the left half disc
    c = verify_segments(D)
    assert not c.ok and not c.vertices[0]
    assert any(4 in p.sites and "inside" in p for p in faults(c, "vertex", vertex=0))


def test_an_arc_centre_vertex_without_an_end_is_rejected():
    D = quarter()
    D.vertices[0].sites = (0, 2, 3)                    # not a site
    assert not verify_segments(D).vertices[0]
    D = point_outside()
    D.vertices[0].sites = (0, 3, 2)                    # (3, 3) instead of the end (0, 2)
    c = verify_segments(D)
    assert not c.vertices[0] and faults(c, "vertex", vertex=0)


def test_an_arc_centre_vertex_listed_clockwise_is_rejected():
    D = quarter()
    D.vertices[0].sites = (0, 1, 2)
    c = verify_segments(D)
    assert not c.vertices[0] and any("counter-clockwise" in p for p in faults(c, "vertex", vertex=0))


def test_an_arc_bisector_drawn_as_its_chord_is_rejected():
    D = point_inside()
    D.edges[0].polyline = np.array([[15 / 16, 0.0], [-15 / 16, 0.0]])
    c = verify_segments(D)
    assert not c.ok and not c.edges[0] and all(c.edges[1:])
    assert any("polyline" in p for p in faults(c, "edge", edge=0))
    D = point_outside()
    D.edges[3].polyline = np.array([[7.0, 0.0], [0.0, 7.0]])
    c = verify_segments(D)
    assert not c.edges[3] and any("polyline" in p for p in faults(c, "edge", edge=3))


def test_an_infinite_end_going_the_wrong_way_is_rejected():
    D = quarter()
    D.edges[2].polyline = np.array([[0.0, 0.0], [FAR, FAR]])      # through the arc
    c = verify_segments(D)
    assert not c.ok and not c.edges[2]
    assert faults(c, "edge", edge=2) and faults(c, "infinity")
    D = stadium()
    D.edges[1].polyline = np.array([[0.0, 1.0], [0.0, FAR]])      # the joint normal drawn upwards
    c = verify_segments(D)
    assert not c.ok and faults(c, "infinity")


def test_a_branch_to_infinity_drawn_the_other_way_is_rejected():
    """The hyperbola-like branch of an arc and a point outside its circle, turned back at its
    vertex: its polyline no longer goes towards the pole of the way it is drawn."""
    D = _build(SCENES["branch to infinity"])
    assert verify_segments(D).ok
    e = next(e for e in D.edges if None in e.ends and len(e.polyline) > 2)
    P = e.polyline if e.ends[1] is None else e.polyline[::-1]
    Q = np.array([P[0], 2 * P[0] - P[-1]])
    e.polyline = Q if e.ends[1] is None else Q[::-1]
    c = verify_segments(D)
    assert not c.ok and not c.edges[e.id] and faults(c, "edge", edge=e.id)


def test_a_vertex_moved_along_an_arc_bisector_is_rejected():
    D = point_inside()
    D.vertices[0].x += 1e-6
    D.edges[0].polyline[0, 0] += 1e-6
    c = verify_segments(D)
    assert not c.vertices[0] and faults(c, "vertex", vertex=0)


def test_inadmissible_arc_sites_are_refused():
    arc = Arc((0, 0), 2, (2, 0), (0, 2))
    c = verify_segments(diagram([Point(2, 0), arc], [], []))           # the end (0, 2) is no site
    assert not c.ok and any("endpoint" in p for p in faults(c, "site"))
    s = stadium()
    c = verify_segments(diagram(list(s.sites) + [Point(0, 0)], [], []))   # a point at a smooth joint
    assert not c.ok and any("smoothly" in p for p in faults(c, "site"))
    sites = [Point(0, 0), Point(2, 0), Point(2, 2), Segment((0, 0), (2, 0)), Arc((0, 2), 2, (0, 0), (2, 2))]
    c = verify_segments(diagram(sites, [], []))                          # tangent at (0, 0): a limit
    assert not c.ok and any(not p.fault and "tangent" in p for p in c.problems)


# ------------------------------------------------------------------------------------ the construction
def _build(pieces):
    return cv.voronoi(pieces, certify=False)


SCENES = {
    "quarter arc": [Arc((0, 0), 2, (2, 0), (0, 2))],
    "point inside": [Arc((0, 0), 2, (2, 0), (-2, 0)), (0, F(1, 2))],
    "point outside": [Arc((0, 0), 2, (2, 0), (0, 2)), (3, 3)],
    "branch to infinity": [Arc((0, 0), 5, (3, 4), (-4, 3)), (7, 8)],
    "whole branch": [Arc((0, 0), 1, (0, -1), (-1, 0)), (5, F(1, 3))],
    "two arcs": [Arc((0, 0), 1, (1, 0), (0, 1)), Arc((5, 0), 2, (5, 2), (3, 0))],
    "stadium": [Segment((0, 0), (4, 0)), Arc((4, 1), 1, (4, 0), (4, 2)), Segment((4, 2), (0, 2)),
                Arc((0, 1), 1, (0, 2), (0, 0))],
    "rounded rectangle": list(rounded_rectangle().sites),
    "half disc": [Arc((0, 0), 1, (1, 0), (-1, 0)), Segment((-1, 0), (1, 0))],
    "circle of four arcs": [Arc((0, 0), 2, (2, 0), (0, 2)), Arc((0, 0), 2, (0, 2), (-2, 0)),
                            Arc((0, 0), 2, (-2, 0), (0, -2)), Arc((0, 0), 2, (0, -2), (2, 0)), (F(1, 2), F(1, 3))],
    "S curve": [Arc((0, 0), 1, (0, -1), (0, 1)), Arc((0, 2), 1, (0, 3), (0, 1))],
}


@pytest.mark.parametrize("name", sorted(SCENES))
def test_the_construction_with_arcs_is_proved(name):
    D = _build(SCENES[name])
    c = verify_segments(D)
    assert c.ok, c.problems[:5]


def test_the_construction_and_its_hand_built_twins_agree():
    for name in ("quarter arc", "point inside", "point outside", "stadium"):
        D = _build(SCENES[name])
        H = CLOSED_FORMS[name]()
        key = lambda d: sorted((tuple(sorted(v.sites)), round(v.x, 9), round(v.y, 9), round(v.radius, 9))
                               for v in d.vertices)
        assert key(D) == key(H), name
        assert verify_segments(D).delaunay_edges == verify_segments(H).delaunay_edges


def test_mutations_of_a_constructed_arc_diagram_are_rejected():
    D = _build(SCENES["rounded rectangle"] + [(F(1, 2), F(3, 2)), (F(7, 2), F(4, 3))])
    assert verify_segments(D).ok
    curved = [e for e in D.edges if len(e.polyline) > 2]
    finite = next(e for e in D.edges if None not in e.ends)

    def mutated(f):
        M = copy.deepcopy(D)
        f(M)
        return M

    def rounded(M):
        return next(v for v in M.vertices if v.radius > 0)

    mutations = {
        "ends swapped": lambda M: setattr(M.edges[finite.id], "ends", finite.ends[::-1]),
        "vertex dropped": lambda M: M.vertices.pop(len(M.vertices) // 2),
        "vertex radius off": lambda M: setattr(rounded(M), "radius", rounded(M).radius * (1 + 1e-7)),
        "edge repeated": lambda M: M.edges.append(DiagramEdge(len(M.edges), finite.sites, finite.ends, False,
                                                              finite.polyline.copy(), finite.tolerance)),
    }
    if curved:
        mutations["arc bisector shifted"] = lambda M: setattr(
            M.edges[curved[0].id], "polyline", curved[0].polyline + 3 * curved[0].tolerance)
    for name, f in mutations.items():
        assert not verify_segments(mutated(f)).ok, name
