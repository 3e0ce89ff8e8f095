"""Local deletion of elementary sites from a certified diagram of points, segments and circular arcs (thesis
§1.2 read backwards: the regions of the deleted sites are shared out among their neighbours, the
rest of the diagram stays; elementary sites, §2.2).

Let S be the old sites, Δ ⊂ S the deleted ones (the open interior and the endpoints of one input
piece that no other piece keeps, or an isolated point), G the old diagram (certified), G' the
diagram of S' = S ∖ Δ, and H the union of the closed regions of Δ in G (the *hole*: the points
whose nearest point of all sites lies on a deleted site; every y ∈ H sees the segment from y to
its nearest point inside H, so H is connected and contractible).

1. **Changed part.**  Removed: every vertex of G whose closed circle meets a deleted site, or comes
   within the margin :data:`runtime.segments.local_update.MARGIN` of one (the float distance from
   the deleted closed piece to the centre below the radius plus the margin; this includes every
   vertex listing a deleted site, and every vertex whose circle only touches one without listing
   it); and every edge with a deleted site or a removed end vertex (*gone* edges).  Deleting a
   site never shrinks an empty circle, it can only let one grow: a vertex whose circle touches a
   deleted site is a place where G' differs or may differ, which is why "changed" is defined by the
   circles meeting Δ and not by the vertices listing a deleted site.  The hole must be bounded: a
   gone edge going to infinity (a deleted site on the convex hull's boundary) is refused.
2. **Local diagram**: the diagram of the sites near the removed circles, deleted sites excluded
   (the neighbours of Δ in the Delaunay graph among them),
   :func:`runtime.segments.construction.segment_voronoi` passed in as ``build`` — the same
   construction (sampling, triangulation, walks) that built G, not a second one.  Taken from it:
   its vertices whose circle meets Δ within the margin (the vertices of G' inside or on H, and
   those reproducing a removed vertex near H), with fresh ids; its edges with an end at a taken
   vertex, and its edges between two kept vertices of a gone edge's pair with an end at a kept
   vertex that lost an edge (an edge of G' that crosses H without a vertex in it).  Local vertices
   that are not taken are matched to kept vertices (same sites, same position within 10⁻⁶).
3. **Proof** of the taken vertices and edges and of the kept ends of taken edges, against every
   site of S' that can reach them (:func:`runtime.segments.local_update.prove_part`), and the
   closure (one edge per consecutive pair of sites, no other) at every taken vertex and every kept
   vertex that lost or gained an edge.

Why the kept part keeps its proof.  (a) A kept vertex v has no deleted site among its sites and
its closed circle misses Δ: its circle was empty of S (old certificate), so it is empty of
S' ⊂ S, and its sites are still equidistant at its centre: it is a vertex of G' with the same
sites in the same order.  (b) A kept edge (i, j) has i, j ∈ S' and kept (or no) end vertices;
every point y of it has d_i(y) = d_j(y) ≤ d_k(y) for all k ∈ S, hence for all k ∈ S': it lies on
the bisector locus of G', and it runs between vertices of G' by (a) (a kept edge without
vertices would be a whole line or branch, so a gone edge would not be needed to bound H): it is a
whole edge of G'.  (c) Outside H the nearest sites in S and S' are the same, so G' ∖ H = G ∖ H;
every edge of G' meeting H has a vertex of G' inside or on H (then taken, its circle meets Δ) or
crosses H between two points of ∂H that are removed vertices of G, whose gone edges of the same
pair end at kept vertices that lost an edge.  (d) Each region of S' that meets H contains its site
outside the interior of H, so it crosses ∂H: the edges of G' in H and ∂H form a connected graph.
Starting at the kept vertices that lost an edge, the closure there forces the edge of G' of each
lost pair into the result, proved; its other end is in the result (a proved vertex of G'); the
closure at every taken vertex forces all its edges of G' in; by (d) this reaches every vertex and
edge of G' in H.  So the spliced diagram is G', and ``certified`` is proved.  Anything else — an
unbounded hole, a local edge to infinity, a local vertex or site that matches nothing, a proof or
closure that fails, sites other than points, segments and arcs — returns a reason, and the
caller rebuilds (:mod:`runtime.segments.edits`).

Circular arcs.  (a)–(d) use only distances, the old certificate, the proofs of the changed part
(the certificate's arc routines) and the shape of the hole (the segment from y ∈ H to its nearest
point of Δ, true for any closed sites); the regions of S' are contractible for arcs too
(certificate step 5: an open arc's region retracts onto the arc).  The float distance to a deleted
arc carries its error bound in the margin (:func:`runtime.segments.local_update.site_distance`).
A deletion that changes the elementary sites that remain is not local: a deleted arc ending at a
smooth joint (the joint becomes a point site) or leaving two curves continuing each other at a
point (it stops being one) is refused by the caller; a local diagram with a site that is not a
remaining site (a curve of the neighbourhood whose joint partner is missing) is refused here.

Numbering: the remaining sites keep their numbers except the last ones, which move into the
deleted sites' places (:func:`site_moves`, as ``renumber="last"`` does for point sites), so that
only the few vertices and edges of the moved sites are renumbered; vertex and edge ids are kept,
new ones take fresh ids.  The caller sets ``sources``.  The proof (step 3) runs in the old
numbering, against the sites of S but Δ: it is a statement about point sets, and the numbering
the sites carry does not enter it; only then are the sites moved, so a refused deletion leaves
the diagram as it was.  Cost: the conflict test (distances on the circles near Δ only,
:func:`runtime.segments.local_update.conflict_mask`), the neighbourhood, the edges at the changed
vertices and the rows of the moved sites are numpy passes over the
:class:`runtime.segments.local_update.EditIndex` carried from the previous edit (table gathers, no
Python loop over the parts); the local diagram and the proof see the neighbourhood only.  With
``inplace`` the diagram's lists and the index are edited by a few row moves (each removed part
takes the last one's place, :meth:`runtime.segments.local_update.EditIndex.replace_rows`, so the
order of the vertices and edges changes) instead of copied.

Public API: :func:`delete_locally` (the returned diagram carries its ``edit_index``), :func:`site_moves`.
"""
from __future__ import annotations

import time
from typing import NamedTuple

import numpy as np

from ..voronoi.structure import DiagramEdge, DiagramVertex
from .local_update import (EditIndex, KeptVertices, Splice, changed_part_holds, conflict_mask, conflicts, editable, listing,
                           local_diagram, local_result, site_key, smallest_first, with_joint_partners)

__all__ = ["delete_locally", "site_moves"]

#: the neighbourhood: sites within this many times the removed circles' extent of them
RING = 1.0


def site_moves(n: int, deleted) -> dict:
    """Old index -> new index of the sites that move when the sites ``deleted`` leave a list of
    ``n`` (the last remaining sites, in order, into the deleted places below n − len(deleted))."""
    gone = sorted(set(deleted))
    m = n - len(gone)
    tail = [k for k in range(m, n) if k not in set(gone)]
    return dict(zip(tail, [k for k in gone if k < m]))


class Hole(NamedTuple):
    """The changed part of a deletion (step 1 of the module docstring): the ``conflict`` mask and
    its ``rows`` (the removed vertices), ``keep_e`` (the edges that stay), the kept vertices that
    lost an edge (``touched``, ids), the site pairs of the gone edges between remaining sites
    (``gone_pairs``, sorted), the remaining sites of gone edges (``neighbours``), the kept edges
    at the touched vertices (``at_touched``, rows) and the rows whose circle may meet a deleted
    site (``near``, :meth:`runtime.segments.local_update.EditIndex.circles_near`)."""
    conflict: np.ndarray
    rows: np.ndarray
    keep_e: np.ndarray
    touched: set
    gone_pairs: set
    neighbours: set
    at_touched: list
    near: np.ndarray


def delete_locally(D, deleted, build, index=None, inplace: bool = False):
    """The diagram ``D`` (certified, points, segments, arcs) without the elementary sites ``deleted``
    (indices), updated locally and proved (module docstring); or a str: why not (then rebuild).
    ``index``: D's :class:`runtime.segments.local_update.EditIndex` from the previous edit, if any.
    ``inplace``: D's lists of sites, vertices and edges and the index's keys and boxes are edited in
    place once the change is proved (they become the result's); D is untouched when a str is
    returned."""
    t0 = time.perf_counter()
    secs: dict = {}
    got = _admissible(D, deleted, index)
    if isinstance(got, str):
        return got
    index, gone = got
    # 1. changed part
    hole = _hole(D, index, gone)
    if isinstance(hole, str):
        return hole
    hood = _neighbourhood(D, index, hole, set(gone))
    secs["locate"] = time.perf_counter() - t0
    # 2. local diagram
    t1 = time.perf_counter()
    L = local_diagram(build, [D.sites[k] for k in hood])
    if isinstance(L, str):
        return L
    secs["local build"] = time.perf_counter() - t1
    t2 = time.perf_counter()
    sp = _taken(D, L, index, gone, hole)
    if isinstance(sp, str):
        return sp
    secs["splice"] = time.perf_counter() - t2
    # 3. proof, in the old numbering against the remaining sites
    t3 = time.perf_counter()
    why = _proved(D, index, gone, hole, sp)
    if why is not None:
        return why
    secs["prove"] = time.perf_counter() - t3
    # 4. the edit (nothing fails after this): the last remaining sites move into the deleted ones' places
    t4 = time.perf_counter()
    sites, vertices, edges, new_index = _renumbered(D, index, gone, hole, sp, inplace)
    secs["renumber"] = time.perf_counter() - t4
    return local_result(D, sites, vertices, edges, sp, new_index, len(hole.rows), len(hood), secs)


def _admissible(D, deleted, index):
    """(index, gone): D's edit index and the deleted sites (sorted, distinct), when the deletion can
    be local; else why not: an uncertified diagram, sites other than points, segments and circular
    arcs, fewer than two sites remaining."""
    if not D.certified:
        return "the diagram is not certified"
    fresh = EditIndex.of(D, index)
    if fresh is not index and not all(editable(s) for s in D.sites):
        return "the diagram has sites other than points, segments and circular arcs"
    index = fresh
    n = len(D.sites)
    gone = sorted(set(int(k) for k in deleted))
    if not gone or len(gone) >= n - 1:
        return "fewer than two sites remain"
    return index, gone


def _hole(D, index, gone):
    """The :class:`Hole` of the deleted sites ``gone``: the vertices whose closed circle meets a
    deleted site within the margin (:func:`runtime.segments.local_update.conflict_mask`), the edges
    with a deleted site or a removed end; or why the deletion is not local: no vertex in conflict,
    or a gone edge going to infinity (the hole would be unbounded)."""
    V = D.vertices
    gone_set = set(gone)
    near: list = []
    conflict = conflict_mask(index, [D.sites[k] for k in gone], near)
    rows = np.nonzero(conflict)[0]
    if not len(rows):
        return "no vertex in conflict"
    removed_ids = {V[t].id for t in rows.tolist()}
    gone_mask = listing(index.EE, removed_ids, index.id_bound) | listing(index.ES, gone, len(index.boxes))
    gone_e = [D.edges[t] for t in np.nonzero(gone_mask)[0].tolist()]
    if any(e.closed or None in e.ends for e in gone_e):
        return "the hole is unbounded (a removed edge goes to infinity)"
    touched = {u for e in gone_e for u in e.ends} - removed_ids
    gone_pairs = {tuple(sorted(e.sites)) for e in gone_e if gone_set.isdisjoint(e.sites)}
    neighbours = {s for e in gone_e for s in e.sites} - gone_set
    keep_e = ~gone_mask
    at_touched = [t for t in index.edges_at(touched).tolist() if keep_e[t]] if touched else []
    return Hole(conflict, rows, keep_e, touched, gone_pairs, neighbours, at_touched, near[0])


def _neighbourhood(D, index, hole: Hole, gone_set: set) -> list:
    """The sites of the local diagram (sorted numbers, no deleted one): those whose boxes meet the
    box of the removed circles widened by :data:`RING` times its extent, the neighbours of the
    hole, and the partners of their curves at smooth joints."""
    XY, R, rows = index.XY, index.R, hole.rows
    lo = (XY[rows] - R[rows, None]).min(axis=0)
    hi = (XY[rows] + R[rows, None]).max(axis=0)
    pad = RING * float(np.max(hi - lo)) + 1e-9 * (1 + float(np.abs(lo).max()) + float(np.abs(hi).max()))
    hood = set(index.near(lo - pad, hi + pad)) | hole.neighbours
    return sorted(with_joint_partners(hood, index, D.sites) - gone_set)


def _taken(D, L, index, gone, hole: Hole):
    """The :class:`runtime.segments.local_update.Splice` of the parts of L the deletion takes (step
    2 of the module docstring): its vertices whose circle meets a deleted site within the margin,
    its edges with an end at a taken vertex, and its edges of a gone edge's pair crossing the hole
    between kept vertices (an end at a kept vertex that lost an edge, not a kept edge of that pair
    and ends); or why not (a site of L that is no remaining site, an edge that cannot be spliced)."""
    V = D.vertices
    glob = [index.keys.get(site_key(s), -1) for s in L.sites]
    if -1 in glob or set(gone) & set(glob):
        return "a site of the local diagram is not a remaining site"
    lXY = np.array([[v.x, v.y] for v in L.vertices], float).reshape(-1, 2)
    lR = np.array([v.radius for v in L.vertices], float)
    lconf = np.zeros(len(L.vertices), bool)
    for k in gone:
        lconf |= conflicts(D.sites[k], lXY, lR)
    next_v = D.stats.get("next vertex id") or max((v.id for v in V), default=-1) + 1
    next_e = D.stats.get("next edge id") or max((e.id for e in D.edges), default=-1) + 1
    sp = Splice(KeptVertices(index, V, hole.conflict), next_v, next_e)
    inside = lconf.tolist()
    sp.take_vertices(L, glob, lambda t, lv, gs: inside[t])
    touched, gone_pairs = hole.touched, hole.gone_pairs
    kept_at = {(tuple(sorted(D.edges[t].sites)), frozenset(D.edges[t].ends)) for t in hole.at_touched}
    for le in L.edges:
        gp = tuple(glob[s] for s in le.sites)
        at_taken = sp.at_taken(le)
        if not (at_taken or tuple(sorted(gp)) in gone_pairs):
            continue
        ends = sp.ends_of(le)
        through = (tuple(sorted(gp)) in gone_pairs and any(u in touched for u in ends)
                   and (tuple(sorted(gp)), frozenset(ends)) not in kept_at)
        if not (through or at_taken):
            continue
        why = sp.take_edge(le, gp, ends)
        if why is not None:
            return why
    return sp


def _proved(D, index, gone, hole: Hole, sp) -> str | None:
    """None when the changed part is proved and closed (step 3 of the module docstring: the taken
    parts and the kept ends of taken edges, each of which must be a kept vertex that lost an edge,
    the closure at the taken vertices and the kept ones that lost an edge), else why not.  All in
    D's numbering, against the sites of D but ``gone`` (a proof is about point sets: the numbering
    the sites carry does not enter it)."""
    near = hole.near[~hole.conflict[hole.near]]          # a vertex listing a site is at distance r of it
    if listing(index.VS[near], gone).any():
        return "a kept vertex lists a deleted site"
    V, touched = D.vertices, hole.touched
    vid = {v.id: v for v in sp.vertices}
    for r in (index.vertex_rows(touched).tolist() if touched else ()):
        if not hole.conflict[r]:
            vid[V[r].id] = V[r]
    ends_needed = sorted({u for e in sp.edges for u in e.ends} - sp.taken_ids)
    if any(u not in vid for u in ends_needed):
        return "a changed edge ends at a kept vertex that did not lose an edge"

    def near_edges(check_ids):                # the kept edges at the check vertices: those at the touched ones
        return [D.edges[r] for r in hole.at_touched]
    return changed_part_holds(D.sites, index, vid, sp, ends_needed, touched | sp.taken_ids, near_edges,
                              exclude=frozenset(gone))


def _renumbered(D, index, gone, hole: Hole, sp, inplace: bool):
    """(sites, vertices, edges, index) of the remaining diagram, after the proof: the last remaining
    sites moved into the deleted ones' places (:func:`site_moves`), the kept vertices and edges that
    list a moved site replaced by renumbered copies, the removed parts deleted (each takes the last
    part's place) and the taken parts (``sp``, renumbered in place: they are new) appended
    (:meth:`runtime.segments.local_update.EditIndex.replace_rows`).  ``inplace``: D's lists and
    index are edited (a few row moves, nothing of size N copied); else copies are (D untouched)."""
    n = len(D.sites)
    m = n - len(gone)
    moves = site_moves(n, gone)
    renumber = lambda k: moves.get(k, k)     # noqa: E731
    gone_keys = [site_key(D.sites[k]) for k in gone]
    if inplace:
        sites, vertices, edges = D.sites, D.vertices, D.edges
    else:
        index = index.copy()
        sites, vertices, edges = list(D.sites), list(D.vertices), list(D.edges)
    keys = index.keys
    for k in gone_keys:
        del keys[k]
    for old, new in moves.items():
        sites[new] = sites[old]
        keys[site_key(sites[new])] = new
    del sites[m:]
    index.move_sites(moves, m)
    if moves:
        mv = list(moves)
        for r in np.nonzero(listing(index.VS, mv, n) & ~hole.conflict)[0].tolist():
            vertices[r] = _renumbered_vertex(vertices[r], renumber, vertices[r].certified)
            index.VS[r, :len(vertices[r].sites)] = vertices[r].sites
        for r in np.nonzero(listing(index.ES, mv, n) & hole.keep_e)[0].tolist():
            edges[r] = _renumbered_edge(edges[r], renumber, edges[r].certified)
            index.ES[r] = edges[r].sites
    for v in sp.vertices:
        v.sites = smallest_first(tuple(renumber(s) for s in v.sites))
    for e in sp.edges:
        _renumber_edge_in_place(e, renumber)
    index.replace_rows(vertices, "v", hole.rows.tolist(), sp.vertices)
    index.replace_rows(edges, "e", np.flatnonzero(~hole.keep_e).tolist(), sp.edges)
    return sites, vertices, edges, index


def _renumbered_vertex(v, renumber, certified: bool):
    """A copy of vertex v with its sites renumbered, the smallest first (cyclic order kept)."""
    return DiagramVertex(v.id, smallest_first(tuple(renumber(s) for s in v.sites)), v.x, v.y, v.radius, certified)


def _renumbered_edge(e, renumber, certified: bool):
    """A copy of edge e with its sites renumbered, the smaller first (ends and polyline turned)."""
    i, j = renumber(e.sites[0]), renumber(e.sites[1])
    if i < j:
        return DiagramEdge(e.id, (i, j), e.ends, e.closed, e.polyline, e.tolerance, certified)
    return DiagramEdge(e.id, (j, i), e.ends[::-1], e.closed, np.asarray(e.polyline)[::-1].copy(), e.tolerance,
                       certified)


def _renumber_edge_in_place(e, renumber) -> None:
    """Renumber the sites of the new edge e, the smaller first (ends and polyline turned)."""
    i, j = renumber(e.sites[0]), renumber(e.sites[1])
    if i < j:
        e.sites = (i, j)
        return
    e.sites, e.ends, e.polyline = (j, i), tuple(e.ends)[::-1], np.asarray(e.polyline)[::-1].copy()
