"""The independent certificate of point/segment Voronoi diagrams (runtime/segments/certificate.py).

Hand-built diagrams in closed form (two points, a lone segment, a segment and a point, a 3-4-5
triangle outline, a 2 x 1 rectangle outline, a square outline with its degree-4 centre) are
accepted; corrupted copies are rejected with the faulty part named (a vertex moved by 1e-6, a
wrong site in a vertex, an edge dropped, a parabola drawn as its chord, an infinite end removed, a
site inside a vertex's circle, a degree-4 vertex split into two degree-3 vertices joined by a
zero-length edge, ...).  Then the construction's output on polygons and random scenes."""
from __future__ import annotations

import copy
import sys
import pathlib

import numpy as np
import pytest

from curvedvoronoi.runtime.predicates.circles import Point
from curvedvoronoi.runtime.sites.segment import Segment
from curvedvoronoi.runtime.segments.certificate import verify_segments
from curvedvoronoi.runtime.voronoi.structure import Diagram, DiagramEdge, DiagramVertex

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))

TOL = 1e-12
FAR = 50.0


def diagram(sites, vertices, edges) -> Diagram:
    """vertices: (sites, x, y, r); edges: (pair, ends, polyline, tolerance)."""
    V = [DiagramVertex(n, tuple(s), float(x), float(y), float(r)) for n, (s, x, y, r) in enumerate(vertices)]
    E = [DiagramEdge(n, tuple(p), tuple(ends), False, np.asarray(poly, float).reshape(-1, 2), tol)
         for n, (p, ends, poly, tol) in enumerate(edges)]
    return Diagram(list(sites), V, E)


def renumber(D: Diagram) -> Diagram:
    D = copy.deepcopy(D)
    for n, e in enumerate(D.edges):
        e.id = n
    return D


def outline(*corners):
    """Point sites of the corners, then the segments between consecutive corners."""
    pts = [Point(*c) for c in corners]
    segs = [Segment(corners[k], corners[(k + 1) % len(corners)]) for k in range(len(corners))]
    return pts + segs


# ------------------------------------------------------------------------------------ closed forms
def two_points():
    return diagram([Point(0, 0), Point(2, 0)], [], [((0, 1), (None, None), [(1, -FAR), (1, FAR)], TOL)])


def lone_segment():
    sites = [Point(0, 0), Point(2, 0), Segment((0, 0), (2, 0))]
    return diagram(sites, [], [((0, 2), (None, None), [(0, -FAR), (0, FAR)], TOL),
                               ((1, 2), (None, None), [(2, -FAR), (2, FAR)], TOL)])


def segment_and_point():
    """Segment [(0, 0), (2, 0)] and the point (1, 1): the parabola y = ((x − 1)² + 1)/2 over the
    segment, between the vertices (0, 1) and (2, 1) of radius 1 (touching the segment at its ends)."""
    sites = [Point(0, 0), Point(2, 0), Point(1, 1), Segment((0, 0), (2, 0))]
    x = np.linspace(0, 2, 65)
    parabola = np.stack([x, ((x - 1) ** 2 + 1) / 2], axis=1)
    sag = (2 / 64) ** 2 / 8              # Δu²/(8h), h = 1
    return diagram(sites,
                   [((0, 3, 2), 0, 1, 1), ((1, 2, 3), 2, 1, 1)],
                   [((2, 3), (0, 1), parabola, sag + 1e-9),
                    ((0, 3), (0, None), [(0, 1), (0, -FAR)], TOL),
                    ((1, 3), (1, None), [(2, 1), (2, -FAR)], TOL),
                    ((0, 2), (0, None), [(0, 1), (-FAR, FAR + 1)], TOL),
                    ((1, 2), (1, None), [(2, 1), (FAR + 2, FAR + 1)], TOL)])


def triangle():
    """The 3-4-5 triangle outline: incircle centre (1, 1), radius 1; corners of radius 0 with their
    perpendiculars outside."""
    sites = outline((0, 0), (4, 0), (0, 3))          # P0 P1 P2, S3 = P0P1, S4 = P1P2, S5 = P2P0
    return diagram(sites,
                   [((3, 4, 5), 1, 1, 1), ((2, 5, 4), 0, 3, 0), ((1, 4, 3), 4, 0, 0), ((0, 3, 5), 0, 0, 0)],
                   [((3, 4), (0, 2), [(1, 1), (4, 0)], TOL),
                    ((4, 5), (0, 1), [(1, 1), (0, 3)], TOL),
                    ((3, 5), (0, 3), [(1, 1), (0, 0)], TOL),
                    ((2, 4), (1, None), [(0, 3), (30, 43)], TOL),
                    ((2, 5), (1, None), [(0, 3), (-FAR, 3)], TOL),
                    ((1, 3), (2, None), [(4, 0), (4, -FAR)], TOL),
                    ((1, 4), (2, None), [(4, 0), (34, 40)], TOL),
                    ((0, 5), (3, None), [(0, 0), (-FAR, 0)], TOL),
                    ((0, 3), (3, None), [(0, 0), (0, -FAR)], TOL)])


def _box_exterior():
    """The 8 perpendiculars at the corners of an axis-parallel box outline (corners P0..P3 from the
    lower left, counter-clockwise; S4 bottom, S5 right, S6 top, S7 left), corner vertex ids 0..3."""
    return lambda w, h: [((0, 4), (0, None), [(0, 0), (0, -FAR)], TOL),
                         ((0, 7), (0, None), [(0, 0), (-FAR, 0)], TOL),
                         ((1, 4), (1, None), [(w, 0), (w, -FAR)], TOL),
                         ((1, 5), (1, None), [(w, 0), (FAR, 0)], TOL),
                         ((2, 5), (2, None), [(w, h), (FAR, h)], TOL),
                         ((2, 6), (2, None), [(w, h), (w, FAR)], TOL),
                         ((3, 6), (3, None), [(0, h), (0, FAR)], TOL),
                         ((3, 7), (3, None), [(0, h), (-FAR, h)], TOL)]


def _corners(w, h):
    return [((0, 4, 7), 0, 0, 0), ((1, 5, 4), w, 0, 0), ((2, 6, 5), w, h, 0), ((3, 7, 6), 0, h, 0)]


def rectangle():
    """The 2 x 1 rectangle: medial axis (0.5, 0.5)–(1.5, 0.5) of radius 1/2, diagonals to the corners."""
    sites = outline((0, 0), (2, 0), (2, 1), (0, 1))
    return diagram(sites, _corners(2, 1) + [((4, 6, 7), 0.5, 0.5, 0.5), ((4, 5, 6), 1.5, 0.5, 0.5)],
                   [((4, 6), (4, 5), [(0.5, 0.5), (1.5, 0.5)], TOL),
                    ((4, 7), (4, 0), [(0.5, 0.5), (0, 0)], TOL),
                    ((6, 7), (4, 3), [(0.5, 0.5), (0, 1)], TOL),
                    ((4, 5), (5, 1), [(1.5, 0.5), (2, 0)], TOL),
                    ((5, 6), (5, 2), [(1.5, 0.5), (2, 1)], TOL)] + _box_exterior()(2, 1))


def square():
    """The 2 x 2 square: one vertex of degree 4 at (1, 1) touching the four sides."""
    sites = outline((0, 0), (2, 0), (2, 2), (0, 2))
    return diagram(sites, _corners(2, 2) + [((4, 5, 6, 7), 1, 1, 1)],
                   [((4, 5), (4, 1), [(1, 1), (2, 0)], TOL),
                    ((5, 6), (4, 2), [(1, 1), (2, 2)], TOL),
                    ((6, 7), (4, 3), [(1, 1), (0, 2)], TOL),
                    ((4, 7), (4, 0), [(1, 1), (0, 0)], TOL)] + _box_exterior()(2, 2))


CLOSED_FORMS = {"two points": two_points, "lone segment": lone_segment, "segment and point": segment_and_point,
                "triangle": triangle, "rectangle": rectangle, "square": square}


@pytest.mark.parametrize("name", sorted(CLOSED_FORMS))
def test_closed_form_diagrams_are_proved(name):
    D = CLOSED_FORMS[name]()
    c = verify_segments(D)
    assert c.ok, c.problems
    assert c.complete and all(c.vertices) and all(c.edges)
    assert c.delaunay_edges == sorted({tuple(e.sites) for e in D.edges})


def test_verify_dispatches_segment_diagrams_and_reads_json():
    from curvedvoronoi.runtime.voronoi.verify.certificate import Certificate, verify

    D = triangle()
    c = verify(D)
    assert isinstance(c, Certificate) and c.ok, c.problems
    doc = D.to_json()
    c = verify(doc)
    assert c.ok, c.problems
    doc["delaunay_edges"] = doc["delaunay_edges"][1:]
    c = verify(doc)
    assert not c.ok and any("delaunay_edges" in p for p in c.problems)
    assert c.to_json()["problem_records"]


# ------------------------------------------------------------------------------------ corruptions
def _faults(c, kind=None, **fields):
    out = []
    for p in c.problems:
        if kind is not None and getattr(p, "kind", None) != kind:
            continue
        if all(getattr(p, k, None) == v for k, v in fields.items()):
            out.append(p)
    return out


def test_a_vertex_moved_by_1e_6_is_rejected():
    D = triangle()
    D.vertices[0].x += 1e-6
    c = verify_segments(D)
    assert not c.ok and not c.vertices[0] and all(c.vertices[1:])
    assert _faults(c, "vertex", vertex=0)
    # the edges at the moved vertex are not proved (their end is not), the others are
    assert not c.edges[0] and c.edges[3]


def test_a_vertex_moved_along_its_bisector_by_1e_6_is_rejected():
    D = rectangle()
    D.vertices[4].x += 1e-6                  # still on the bisector of the top and bottom sides
    D.edges[0].polyline[0, 0] += 1e-6
    c = verify_segments(D)
    assert not c.vertices[4] and _faults(c, "vertex", vertex=4)


def test_a_wrong_site_in_a_vertex_is_rejected():
    D = triangle()
    D.vertices[0].sites = (2, 3, 4)          # the corner point P2 instead of the side S5
    c = verify_segments(D)
    assert not c.ok and not c.vertices[0]
    assert _faults(c, "vertex", vertex=0)


def test_a_corner_vertex_with_a_wrong_order_is_rejected():
    D = triangle()
    D.vertices[3].sites = (0, 5, 3)          # clockwise
    c = verify_segments(D)
    assert not c.vertices[3] and any("counter-clockwise" in p for p in _faults(c, "vertex", vertex=3))


def test_a_dropped_edge_is_found_by_the_closure():
    D = triangle()
    del D.edges[0]                           # (3, 4) from the incircle centre to the corner P1
    c = verify_segments(renumber(D))
    assert not c.ok and not c.complete
    assert all(c.edges)                      # what is there is proved
    bad = _faults(c, "vertex")
    assert {p.vertex for p in bad} == {0, 2} and all(p.sites == (3, 4) for p in bad)


def test_a_parabola_drawn_as_its_chord_is_rejected():
    D = segment_and_point()
    D.edges[0].polyline = np.array([[0.0, 1.0], [2.0, 1.0]])
    c = verify_segments(D)
    assert not c.ok and not c.edges[0] and all(c.edges[1:])
    assert any("polyline" in p for p in _faults(c, "edge", edge=0))


def test_a_polyline_off_its_line_is_rejected():
    D = rectangle()
    D.edges[0].polyline = np.array([[0.5, 0.5], [1.0, 0.5 + 1e-6], [1.5, 0.5]])
    c = verify_segments(D)
    assert not c.edges[0] and any("polyline" in p for p in _faults(c, "edge", edge=0))


def test_a_removed_infinite_end_is_found_by_the_accounting():
    D = rectangle()
    del D.edges[5]                           # (0, 4): the perpendicular down from the corner (0, 0)
    c = verify_segments(renumber(D))
    assert not c.ok and not c.complete
    inf = _faults(c, "infinity")
    assert len(inf) == 1 and inf[0].sites == (0, 4)
    assert _faults(c, "vertex", vertex=0)    # the corner misses that edge too


def test_an_infinite_end_made_finite_is_rejected():
    D = two_points()
    D.vertices.append(DiagramVertex(0, (0, 1, 1), 1.0, 0.0, 1.0))
    D.edges[0].ends = (None, 0)
    c = verify_segments(D)
    assert not c.ok and not c.vertices[0]
    assert _faults(c, "infinity", sites=(0, 1))


def test_an_unbounded_edge_going_the_wrong_way_is_rejected():
    D = triangle()
    D.edges[8].polyline = np.array([[0.0, 0.0], [0.0, FAR]])     # (0, 3) drawn into the triangle
    c = verify_segments(D)
    assert not c.ok and not c.edges[8]
    assert _faults(c, "edge", edge=8) and _faults(c, "infinity")


def test_a_site_inside_a_vertex_circle_is_rejected():
    D = triangle()
    D.sites.append(Point(1.25, 1.1))         # inside the incircle
    c = verify_segments(D)
    assert not c.ok and not c.vertices[0] and all(c.vertices[1:])
    assert any(6 in p.sites and "inside" in p for p in _faults(c, "vertex", vertex=0))
    assert not all(c.edges)


def test_a_site_moved_inside_a_vertex_circle_is_rejected():
    D = segment_and_point()                  # the vertex (0, 1) has radius 1
    D2 = segment_and_point()
    D2.sites[2] = Point(1, 1)
    assert verify_segments(D2).ok
    D.sites.append(Point("0.3", "1.2"))
    c = verify_segments(D)
    assert not c.vertices[0] and any(4 in p.sites for p in _faults(c, "vertex", vertex=0))


def test_a_degree_4_vertex_split_into_two_is_rejected():
    D = square()
    V = D.vertices
    centre = V.pop()
    V.append(DiagramVertex(4, (4, 5, 6), centre.x, centre.y, centre.radius))
    V.append(DiagramVertex(5, (4, 6, 7), centre.x, centre.y, centre.radius))
    E = D.edges
    E[0].ends, E[1].ends = (4, 1), (4, 2)
    E[2].ends, E[3].ends = (5, 3), (5, 0)
    E.append(DiagramEdge(len(E), (4, 6), (4, 5), False, np.array([[1.0, 1.0], [1.0, 1.0]]), TOL))
    c = verify_segments(D)
    assert not c.ok and not c.vertices[4] and not c.vertices[5]
    assert any(7 in p.sites for p in _faults(c, "vertex", vertex=4))
    assert any(5 in p.sites for p in _faults(c, "vertex", vertex=5))
    assert not c.edges[-1]


def test_a_degree_4_vertex_missing_a_site_is_rejected():
    D = square()
    D.vertices[4].sites = (4, 5, 6)
    c = verify_segments(D)
    assert not c.vertices[4] and any(7 in p.sites for p in _faults(c, "vertex", vertex=4))


def test_a_degree_4_vertex_listing_a_far_site_is_rejected():
    D = rectangle()
    D.vertices[4].sites = (4, 5, 6, 7)      # the right side is at distance 1.5, not 0.5
    c = verify_segments(D)
    assert not c.vertices[4] and _faults(c, "vertex", vertex=4)


def test_inadmissible_sites_are_refused():
    D = lone_segment()
    D.sites.append(Point(1, 0))              # on the segment's interior
    c = verify_segments(D)
    assert not c.ok and _faults(c, "site")
    D = lone_segment()
    del D.sites[1]                           # an endpoint that is not a site
    c = verify_segments(diagram(D.sites, [], []))
    assert not c.ok and any("endpoint" in p for p in _faults(c, "site"))
    sites = [Point(0, 0), Point(1, 0), Point(2, 0), Segment((0, 0), (1, 0)), Segment((1, 0), (2, 0))]
    c = verify_segments(diagram(sites, [], []))
    assert not c.ok and any("merge" in p for p in _faults(c, "site"))


def test_an_edge_between_the_wrong_sites_is_rejected():
    D = triangle()
    D.edges[2].sites = (0, 3)                # the diagonal to the corner (0, 0) is (3, 5)
    c = verify_segments(D)
    assert not c.ok and not c.complete and _faults(c, "edge", edge=2)


def test_a_corrupted_document_is_rejected():
    D = triangle()
    D.edges[0].tolerance = float("nan")
    D.vertices[1].radius = float("inf")
    c = verify_segments(D)
    assert not c.ok and not c.vertices[1] and not c.edges[0]


# ------------------------------------------------------------------------------------ the construction
def _construction():
    try:
        from curvedvoronoi.runtime.segments.construction import segment_voronoi
    except ImportError:                                  # pragma: no cover - the construction is elsewhere
        pytest.skip("no segment construction")
    return segment_voronoi


POLYGONS = {
    "triangle": [(0, 0), (4, 0), (0, 3)],
    "square rotated 3-4-5": [(0, 0), (3, 4), (-1, 7), (-4, 3)],
    "square rotated 45": [(0, 0), (1, 1), (0, 2), (-1, 1)],
    "L shape": [(0, 0), (4, 0), (4, 1), (1, 1), (1, 3), (0, 3)],
    "star": [(0, 0), (5, -2), (3, 1), (6, 4), (2, 3), (0, 6), (-1, 2), (-4, 1)],
    "comb": [(0, 0), (9, 0), (9, 3), (8, 3), (8, 1), (6, 1), (6, 3), (5, 3), (5, 1), (3, 1), (3, 3), (0, 3)],
}


@pytest.mark.parametrize("name", sorted(POLYGONS))
def test_the_construction_on_polygons_is_proved(name):
    segment_voronoi = _construction()
    corners = POLYGONS[name]
    pieces = [Segment(corners[k], corners[(k + 1) % len(corners)]) for k in range(len(corners))]
    D = segment_voronoi(pieces, certify=False)
    c = verify_segments(D)
    assert c.ok, c.problems[:5]


@pytest.mark.parametrize("n,seed,shared,points", [(20, 1, False, 0), (20, 2, True, 0), (40, 3, True, 6),
                                                  (40, 4, False, 6)])
def test_the_construction_on_random_scenes_is_proved(n, seed, shared, points):
    segment_voronoi = _construction()
    from scenes import random_points_off, random_segments

    segs = random_segments(n, seed, shared=shared)
    pieces = [Segment(a, b) for a, b in segs] + [Point(*p) for p in random_points_off(segs, points, seed)]
    D = segment_voronoi(pieces, certify=False)
    c = verify_segments(D)
    assert c.ok, c.problems[:5]
    # and a corrupted copy is not: every vertex moved by 1e-6 of the scene
    D.vertices[len(D.vertices) // 2].y += 1e-6 * (1 + abs(D.vertices[len(D.vertices) // 2].y))
    assert not verify_segments(D).ok


def test_mutations_of_a_constructed_diagram_are_rejected():
    """Combinatorial and metric corruptions of a proved diagram: none is accepted."""
    segment_voronoi = _construction()
    from fractions import Fraction

    from scenes import random_points_off, random_segments

    segs = random_segments(12, 21, shared=True)
    pieces = [Segment(a, b) for a, b in segs] + [Point(*p) for p in random_points_off(segs, 3, 21)]
    D = segment_voronoi(pieces, certify=False)
    assert verify_segments(D).ok
    finite = next(e for e in D.edges if None not in e.ends)
    curved = [e for e in D.edges if len(e.polyline) > 2]

    def rounded(M):
        return next(v for v in M.vertices if v.radius > 0)

    def mutated(f):
        M = copy.deepcopy(D)
        f(M)
        return M

    def move_point(M):
        k = next(k for k, s in enumerate(M.sites) if isinstance(s, Point))
        old = (Fraction(int(M.sites[k].x.p), int(M.sites[k].x.q)), Fraction(int(M.sites[k].y.p), int(M.sites[k].y.q)))
        new = (old[0] + Fraction(1, 10 ** 5), old[1])
        M.sites[k] = Point(*new)
        for j, s in enumerate(M.sites):
            if isinstance(s, Segment) and old in (s.p, s.q):
                M.sites[j] = Segment(new if s.p == old else s.p, new if s.q == old else s.q)

    mutations = {
        "ends swapped": lambda M: setattr(M.edges[finite.id], "ends", finite.ends[::-1]),
        "edge repeated": lambda M: M.edges.append(DiagramEdge(len(M.edges), finite.sites, finite.ends, False,
                                                              finite.polyline.copy(), finite.tolerance)),
        "vertex dropped": lambda M: M.vertices.pop(len(M.vertices) // 2),
        "point site moved by 1e-5": move_point,
        "vertex radius off": lambda M: setattr(rounded(M), "radius", rounded(M).radius * (1 + 1e-7)),
    }
    if curved:
        mutations["parabola polyline shifted"] = lambda M: setattr(
            M.edges[curved[0].id], "polyline", curved[0].polyline + 3 * curved[0].tolerance)
    for name, f in mutations.items():
        assert not verify_segments(mutated(f)).ok, name
