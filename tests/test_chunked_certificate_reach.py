"""The sites a chunk of the chunked certificate is handed (runtime/voronoi/chunked_certificate.py,
"Sites per chunk"), against empty circles on the true bisectors.

For random disjoint circles, points of each bounded edge's true bisector arc are found here
(points of the polyline pulled onto {|q − c_i| − ρ_i = |q − c_j| − ρ_j} by Newton steps along the
gradient); the empty circle of such a point q has radius r(q) = |q − c_i| − ρ_i.  Every site
that comes within 10⁻³·r(q) of it, and every site within 10⁻⁷ of a vertex's empty circle, must
be among the chunk's sites (they are the sites the proofs must see); and the chunk's sites must
be far fewer than all of them (the point of handing them out).  The distances are written here,
not taken from the library.

A vertex proved in a coarse box returns the radius that holds its true empty circle; the driver
counts it as proved only when no site left out of its chunk comes that close: a planted radius
that reaches a left-out site unproves it."""
from __future__ import annotations

import math

import numpy as np
import pytest

from curvedvoronoi.runtime.voronoi import chunked_certificate as cc
from curvedvoronoi.runtime.voronoi.construction import voronoi
from scenes import random_disjoint_circles


@pytest.fixture(scope="module")
def diagram():
    d = voronoi(random_disjoint_circles(600, 11), progress=False, certify=False)
    return d


def _centres(d):
    C = np.array([[float(s.cx), float(s.cy)] for s in d.sites])
    R = np.array([math.sqrt(float(s.r2)) for s in d.sites])
    return C, R


def _chunks(d, parts=4):
    """The bounded edges in ``parts`` slices by x, without the edges near the hull (their vertices'
    empty circles wider than a twentieth of the scene), which go with the unbounded ones."""
    far = set(cc._Reach(d).far_edges(d))
    assert far
    bounded = [e.id for e in d.edges if None not in e.ends and e.id not in far]
    xs = np.array([d.vertices[d.edges[t].ends[0]].x for t in bounded])
    order = np.argsort(xs)
    return [sorted(np.asarray(bounded)[c].tolist()) for c in np.array_split(order, parts)]


def test_a_chunk_holds_every_site_that_can_enter_its_empty_circles(diagram):
    d = diagram
    C, R = _centres(d)
    reach = cc._Reach(d)
    assert reach.ok
    sizes = []
    for ids in _chunks(d):
        vids = sorted({u for t in ids for u in d.edges[t].ends})
        keep = set(reach.sites(d, vids, ids))
        sizes.append(len(keep))
        for u in vids:
            v = d.vertices[u]
            gap = np.hypot(C[:, 0] - v.x, C[:, 1] - v.y) - R - v.radius
            assert set(np.nonzero(gap < 1e-7 * (1 + v.radius))[0].tolist()) <= keep
        for t in ids:
            e = d.edges[t]
            i, j = e.sites
            P = np.asarray(e.polyline, float)
            f = np.linspace(0, 1, 11)[:, None, None]
            Q = (P[:-1][None] + f * (P[1:] - P[:-1])[None]).reshape(-1, 2)
            for _ in range(4):              # onto the true bisector: F = d_i − d_j = 0
                Vi, Vj = Q - C[i], Q - C[j]
                ni, nj = np.hypot(*Vi.T), np.hypot(*Vj.T)
                F = (ni - R[i]) - (nj - R[j])
                G = Vi / ni[:, None] - Vj / nj[:, None]
                Q = Q - (F / (G ** 2).sum(axis=1))[:, None] * G
            r = np.hypot(Q[:, 0] - C[i, 0], Q[:, 1] - C[i, 1]) - R[i]
            gap = np.hypot(Q[:, None, 0] - C[None, :, 0], Q[:, None, 1] - C[None, :, 1]) - R[None, :] - r[:, None]
            near = set(np.nonzero((gap < 1e-3 * r[:, None]).any(axis=0))[0].tolist())
            assert near <= keep, (t, sorted(near - keep)[:5])
    assert max(sizes) < 0.6 * len(d.sites)


def _plant(monkeypatch, first, again):
    """verify_chunk returning, for vertex 0 of each bounded chunk, the radius ``first(v)`` (the
    chunks) or ``again(v)`` (the run with the wider sites, told by _part's ``extra``)."""
    real, real_part = cc.verify_chunk, cc._part
    state = {"wider": False}

    def part(D, ids, hull, reach, extra=()):
        state["wider"] = bool(extra)
        return real_part(D, ids, hull, reach, extra)

    def planted(sub, at_infinity=True):
        vok, eok, recs, far = real(sub, at_infinity)
        if not at_infinity and sub.vertices:
            v = sub.vertices[0]
            far = far + [[0, (again if state["wider"] else first)(v)]]
        return vok, eok, recs, far

    monkeypatch.setattr(cc, "_part", part)
    monkeypatch.setattr(cc, "verify_chunk", planted)
    return state


def test_a_coarse_vertex_is_proved_again_with_every_site_within_its_radius(diagram, monkeypatch):
    """A radius reaching sites left out of the chunk: the vertex is not proved there, and is proved
    by the second run, handed every site within that radius."""
    d = diagram
    chunks = _chunks(d)
    assert cc.chunked_verify(d, chunks).ok
    state = _plant(monkeypatch, lambda v: 10 * max(1.0, v.radius) + 1e3, lambda v: v.radius)
    out = cc.chunked_verify(d, chunks)
    assert out.ok, out.problems
    assert state["wider"]                       # the second run happened


def test_a_coarse_vertex_whose_circle_reaches_a_left_out_site_is_not_proved(diagram, monkeypatch):
    """The radius of the second run reaches past the sites it was handed: not proved, named."""
    d = diagram
    chunks = _chunks(d)
    span = float(np.ptp(_centres(d)[0], axis=0).max())
    # the first radius reaches out of the chunk but not over the whole scene; the second beyond it
    _plant(monkeypatch, lambda v: 0.3 * span, lambda v: 10 * span)
    out = cc.chunked_verify(d, chunks)
    assert not out.ok and not all(out.vertices)
    assert any("reaches past the sites handed to it" in str(p) for p in out.problems)


def test_a_site_entering_an_edge_between_its_vertex_circles_unproves_the_edge(diagram):
    """A point site p added to the sites of the diagram (which is not redrawn), placed inside the
    empty circle of the middle point q of a bounded edge (|p − q| = 0.9·r(q)) but outside both end
    vertices' empty circles: p is nearer than the edge's sites at q, so the edge is no edge of the
    new sites.  Only the discs along the edge's arc can hand p to the edge's chunk; with p in it,
    the edge must not be proved there, while its two vertices stay proved."""
    import curvedvoronoi as cv
    from curvedvoronoi.runtime.voronoi.structure import Diagram

    d = diagram
    C, R = _centres(d)
    chunks = _chunks(d)
    placed = None
    for ids in chunks:
        for t in ids:
            e = d.edges[t]
            P = np.asarray(e.polyline, float)
            q = P[len(P) // 2] if len(P) % 2 else 0.5 * (P[len(P) // 2 - 1] + P[len(P) // 2])
            i = e.sites[0]
            r = float(np.hypot(*(q - C[i])) - R[i])
            ends = [d.vertices[u] for u in e.ends]
            for th in np.linspace(0, 2 * np.pi, 72, endpoint=False):
                p = q + 0.9 * r * np.array([math.cos(th), math.sin(th)])
                clear_of_ends = all(math.hypot(p[0] - v.x, p[1] - v.y) > v.radius * 1.05 for v in ends)
                clear_of_sites = (np.hypot(C[:, 0] - p[0], C[:, 1] - p[1]) - R > 0.05).all()
                if clear_of_ends and clear_of_sites:
                    placed = (t, p)
                    break
            if placed:
                break
        if placed:
            break
    assert placed is not None
    t, p = placed
    bad = Diagram(list(d.sites) + [cv.Point(float(p[0]), float(p[1]))], list(d.vertices), list(d.edges))
    out = cc.chunked_verify(bad, chunks)
    assert not out.ok
    assert not out.edges[t]
    assert all(out.vertices[u] for u in d.edges[t].ends)


def test_the_chunked_certificate_says_where_its_time_goes(diagram):
    """``seconds`` splits the chunks' wall time: the sub-diagrams made by the caller (``parts``) and
    the chunks' own CPU seconds (``runs``, their sum; ``longest run``), each positive, the longest
    run at most the sum."""
    out = cc.chunked_verify(diagram, _chunks(diagram))
    s = out.seconds
    assert out.ok
    assert s["parts"] > 0 and s["runs"] > 0 and 0 < s["longest run"] <= s["runs"]
    assert s["parts"] + s["runs"] <= 1.5 * s["chunks"] + 0.5      # serial: both within the chunks' wall time


def test_a_packed_sub_diagram_unpacks_equal(diagram):
    """What goes to a worker (``pack``: sites, vertex and edge records, the polylines in one array)
    unpacks to an equal sub-diagram: the chunk of the unbounded edges (ends None, every site) and a
    chunk of bounded edges with its own sites; and a diagram with a closed edge (a circle inside a
    circle) and an edge of no vertex."""
    reach = cc._Reach(diagram)
    unbounded = [e.id for e in diagram.edges if None in e.ends]
    for ids, hull in ((unbounded, True), (_chunks(diagram)[1], False)):
        sub, _, _ = cc._part(diagram, ids, hull, reach)
        back = cc.unpack(cc.pack(sub))
        assert back == sub and len(back.edges) == len(ids) > 0
    from curvedvoronoi.runtime.voronoi.construction import voronoi

    nested = voronoi([(0, 0, 10), (1, 0, 2), (30, 0, 1)], progress=False)
    assert any(e.closed for e in nested.edges)
    sub, _ = cc._sub_diagram(nested, list(range(len(nested.edges))))
    assert cc.unpack(cc.pack(sub)) == sub
