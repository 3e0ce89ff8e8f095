"""Local insertion of a segment, a circular arc or a point into a certified diagram of points,
segments and circular arcs (thesis §1.2: a new site only takes from the regions it touches;
elementary sites, §2.2).

The new piece P brings up to three elementary sites σ (its open interior and the endpoints not
yet sites).  The update:

1. **Conflict**: the old vertices whose empty circle P enters (float distance from the closed P to
   the centre below the radius plus a margin of 10⁻⁸·(1 + |x| + |y| + r), a hundred times the
   certificate's position tolerance, plus an arc's float error bound,
   :func:`runtime.segments.local_update.site_distance`; the others, *kept*, are at least that
   margin outside).
2. **Local diagram**: the diagram of P and the sites near the conflict circles
   (:func:`runtime.segments.construction.segment_voronoi`, passed in as ``build``).  Taken from it:
   its vertices with a new site (and those reproducing a conflict vertex), and its edges with a new
   site or an end at a taken vertex; removed: the conflict vertices and the edges ending there.
3. **Proof** of the changed part with the certificate's routines on a diagram of the taken parts
   and their end vertices, against every site that can reach them
   (:func:`runtime.segments.local_update.prove_part`, whose docstring says why the sites it leaves
   out cannot matter); the closure (one incident edge per consecutive pair, ends listing their
   pair) at every taken vertex and every kept vertex that lost or gained an edge.

Cost.  The keys, boxes and vertex arrays of the diagram are an
:class:`runtime.segments.local_update.EditIndex` carried from edit to edit (built once, linear in
N, at the first edit of a batch-built diagram); the conflict test and the neighbourhood are
vectorised over its arrays (distances on the circles near the piece only); the local diagram, the
matching (in a box about the change) and the proof see only the neighbourhood.  What stays linear
in N is a few numpy passes (the conflict prefilter, the edges at the removed vertices) and, without
``inplace``, the copies of the lists and the index; with it the diagram's lists and the index are
edited by a few row moves (:meth:`runtime.segments.local_update.EditIndex.replace_rows`).

Why the kept part keeps its proof.  Let G' be the diagram with P.  (a) A kept vertex's circle was
empty of the old sites (old certificate) and P is strictly outside it: it is a vertex of G'.  (b) A
proved edge (σ, k) of G' and a kept edge (i, j) never meet: at a common point y, d_σ(y) = d_k(y)
is below every other distance, while d_i(y) = d_j(y) is at most every old distance — contradiction
whether k ∈ {i, j} or not; the same at a new vertex.  (c) When every taken edge is bounded, the
closure at the taken vertices makes the taken edges of each new site σ a closed chain: the whole
boundary of σ's region in G' (a region is contractible, certificate step 5), which is therefore
bounded.  A kept edge has a kept end vertex (outside every new region by (a)) or no vertex (an
unbounded line or branch); by (b) it does not cross the boundary, so it lies outside the new
regions, where the nearest sites are the old ones: it is a whole edge of G'.  (d) Every edge of G'
between old sites ending at a new vertex is the one edge of its pair there (closure, proved now);
every other one lies outside the new regions, so it is a whole edge of G; its finite ends are
vertices of G' and G; if one was removed (a conflict within the margin that the local diagram did
not reproduce), the closure at the other end fails, and no removed edge goes to infinity (checked):
so it is kept.  (e) The new
regions are bounded, so no new site touches the convex hull's boundary: the unbounded ends of G'
are those of G, all kept.  So the spliced diagram is G', and ``certified`` is proved.  Anything
else — a taken edge to infinity, a new site without a taken edge, a local diagram with a new site
that is not one of P's, a local vertex that matches nothing, a proof or closure that fails, sites
other than points, segments and circular arcs (elliptic pieces), a piece repeating a site or
continuing a curve straight or smoothly through its end, ending at a smooth joint, a crossing —
returns a reason, and the caller rebuilds (:mod:`runtime.segments.edits`).

Circular arcs.  Nothing in (a)–(e) depends on the kind of site: (a) uses the old certificate and
the conflict test (for an arc a float distance whose error bound is added to the margin), (b) and
(d) only distances, (c) and (e) that every region is contractible — certificate step 5
(:mod:`runtime.segments.certificate`) proves it for an open arc's region too (it retracts onto
the arc along the segments to the nearest points), and the proofs of the changed part are the
certificate's own arc routines (arc bisectors, radial rays at the ends, vertices at an arc's
centre).  The one place where the segment argument used convexity — the reach of the proof's
site table — has its arc bound in :mod:`runtime.segments.local_update`.  What the update cannot
do locally is a change of the elementary sites around P beyond adding P's: P continuing a curve
with opposite tangents at an end that is a point site (the point would stop being a site: a
straight merge, or a smooth joint), or ending at a smooth joint (the joint would become a site);
both are refused, as is a local diagram with a new site that is not P's.  A circle is inserted
as its two halves at once (one update, P their union): the new sites are the two open arcs, their
common ends are smooth joints and no sites.

Numbering: the old elementary sites keep their indices; the new ones are appended (in the local
diagram's order: endpoints, then the interior) with ``source`` N, the new input index.  Old
vertex and edge ids are kept; new ones take fresh ids above the largest.

Public API: :func:`insert_locally` (the returned diagram carries its ``edit_index``).
"""
from __future__ import annotations

import time

import numpy as np

from ..voronoi.site_input import SiteError
from .crossings import check_pieces
from .local_update import (EditIndex, KeptVertices, SitesWithNew, Splice, changed_part_holds, conflict_mask, curve_ends,
                           editable, leaving, listing, local_diagram, local_result, opposite, point_key, site_box, site_key,
                           with_joint_partners)

__all__ = ["insert_locally"]

#: the neighbourhood: sites within this many times the conflict region's size of it
RING = 1.0


def insert_locally(D, piece, source: int, build, index=None, inplace: bool = False):
    """The diagram ``D`` (certified, points, segments, arcs) with ``piece`` (a Segment, Arc or Point;
    or a list of them from one input piece: a circle's two halves) added, updated locally and proved
    (module docstring); or a str: why not (then rebuild).
    ``index``: D's :class:`runtime.segments.local_update.EditIndex` from the previous edit, if any;
    the result carries its own as ``edit_index``.  ``inplace``: D's lists of vertices and edges are
    edited in place once the change is proved (they become the result's)."""
    t0 = time.perf_counter()
    secs: dict = {}
    parts = list(piece) if isinstance(piece, list) else [piece]
    got = _admissible(D, parts, index)
    if isinstance(got, str):
        return got
    index, plo, phi = got
    n = len(D.sites)
    # 1. conflict
    conflict = conflict_mask(index, parts)
    if not conflict.any():
        return "no vertex in conflict"
    cv_ = np.nonzero(conflict)[0]
    hood = _neighbourhood(D, index, cv_, plo, phi)
    secs["locate"] = time.perf_counter() - t0
    # 2. local diagram
    t1 = time.perf_counter()
    L = local_diagram(build, [D.sites[k] for k in hood] + parts)
    if isinstance(L, str):
        return L
    secs["local build"] = time.perf_counter() - t1
    t2 = time.perf_counter()
    glob, new_sites = _global_sites(L, index.keys, n)
    if not new_sites or not {site_key(s) for s in new_sites} <= _expected_sites(parts):
        return "the local diagram's new sites are not the piece's"
    sp = _taken(D, L, index, glob, cv_)
    if isinstance(sp, str):
        return sp
    for s in range(len(new_sites)):
        if not any(n + s in e.sites for e in sp.edges):
            return "a new site has no edge in the local diagram"
    removed_ids = {D.vertices[t].id for t in cv_.tolist()}
    gone_mask = listing(index.EE, removed_ids, index.id_bound)
    gone = [D.edges[t] for t in np.nonzero(gone_mask)[0].tolist()]
    if any(u is None for e in gone for u in e.ends):
        return "a removed edge goes to infinity"
    touched = {u for e in gone for u in e.ends} - removed_ids
    touched |= {u for e in sp.edges for u in e.ends} - sp.taken_ids
    secs["splice"] = time.perf_counter() - t2
    # 3. proof of the changed part
    t3 = time.perf_counter()
    sites = _Appended(D.sites, new_sites)                # the sites with the new ones, uncopied
    removed_rows = set(cv_.tolist())
    new_keys = {site_key(s): n + t for t, s in enumerate(new_sites)}
    new_boxes = np.array([site_box(s) for s in new_sites], float).reshape(-1, 4)
    why = _proved(D, sites, index, SitesWithNew(index, new_keys, new_boxes), sp, removed_rows, gone_mask, touched)
    if why is not None:
        return why
    secs["prove"] = time.perf_counter() - t3
    # 4. the edit (nothing fails after this): D's lists and index, or copies of them
    if inplace:
        D.sites.extend(new_sites)
        sites, vertices, edges, sources = D.sites, D.vertices, D.edges, D.sources
    else:
        index = index.copy()
        sites = list(D.sites) + new_sites
        vertices, edges, sources = list(D.vertices), list(D.edges), list(D.sources)
    index.replace_rows(vertices, "v", cv_.tolist(), sp.vertices)
    index.replace_rows(edges, "e", np.flatnonzero(gone_mask).tolist(), sp.edges)
    index.keys.update(new_keys)
    index.append_sites(new_boxes)
    sources.extend([source] * len(new_sites))
    out = local_result(D, sites, vertices, edges, sp, index, len(cv_), len(hood), secs)
    out.sources = sources
    return out


def _admissible(D, parts, index):
    """(index, lo, hi): D's edit index and the pieces' float box, when the insertion of ``parts``
    can be local; else why not.  Refused: an uncertified diagram, sites or pieces other than points,
    segments and circular arcs, a piece repeating a site or meeting another, and a change of the
    elementary sites around the piece beyond adding its own (module docstring: an end at a smooth
    joint or inside a merged segment, a curve continued straight or smoothly through its end)."""
    if not D.certified:
        return "the diagram is not certified"
    for q in parts:
        if not editable(q):
            return f"a {type(q).__name__} piece"
    fresh = EditIndex.of(D, index)
    if fresh is not index and not all(editable(s) for s in D.sites):
        return "the diagram has sites other than points, segments and circular arcs"
    index = fresh
    keys = index.keys
    if any(site_key(q) in keys for q in parts):
        return "the piece repeats a site"
    boxes = np.array([site_box(q) for q in parts], float)
    plo, phi = boxes[:, :2].min(axis=0), boxes[:, 2:].max(axis=0)
    near = index.near(plo, phi)
    # crossings, and continuations through an end (a merge of elementary segments, a smooth joint
    # made or split): the rebuild decides
    try:
        check_pieces([D.sites[k] for k in near] + parts)
    except SiteError:
        return "the piece meets another"
    for q in parts:
        for e in curve_ends(q):
            at = [k for k in near if e in curve_ends(D.sites[k])]
            if point_key(e) not in keys:
                if at:
                    return "the piece ends at a smooth joint or inside a merged segment"
                continue
            if any(opposite(leaving(D.sites[k], e), leaving(q, e)) for k in at):
                return "the piece continues a curve straight or smoothly through its end"
    return index, plo, phi


def _neighbourhood(D, index, cv_, plo, phi) -> list:
    """The sites of the local diagram (sorted numbers): those whose boxes meet the box of the
    conflict circles (rows ``cv_``) and the piece (``plo``, ``phi``) widened by :data:`RING` times
    its size, with the partners of their curves at smooth joints."""
    XY, R = index.XY, index.R
    lo = np.minimum((XY[cv_] - R[cv_, None]).min(axis=0), plo)
    hi = np.maximum((XY[cv_] + R[cv_, None]).max(axis=0), phi)
    pad = RING * float(np.max(hi - lo)) + 1e-9
    lo, hi = lo - pad, hi + pad
    return sorted(with_joint_partners(set(index.near(lo, hi)), index, D.sites))


def _global_sites(L, keys, n: int):
    """(glob, new_sites): the global number of each site of the local diagram L (an old site's
    own, a new site's n, n + 1, ... in L's order) and the new sites."""
    glob = []                          # local site -> global site
    new_sites = []
    for s in L.sites:
        k = keys.get(site_key(s))
        if k is None:
            k = n + len(new_sites)
            new_sites.append(s)
        glob.append(k)
    return glob, new_sites


def _expected_sites(parts) -> set:
    """The keys of the new elementary sites: the pieces and their ends, but an end two of them
    share (a circle's smooth joints are no sites)."""
    own_ends = [e for q in parts for e in curve_ends(q)]
    return {site_key(q) for q in parts} | {point_key(e) for e in own_ends if own_ends.count(e) == 1}


def _taken(D, L, index, glob, cv_):
    """The :class:`runtime.segments.local_update.Splice` of the parts of L the insertion takes (step
    2 of the module docstring): its vertices with a new site or reproducing a conflict vertex
    (same sites, centre within 10⁻⁶·(1 + |x| + |y| + r)), its edges with a new site or an end at a
    taken vertex; or why they cannot be spliced."""
    V, n = D.vertices, len(D.sites)
    removed_by_sites: dict = {}
    for t in set(cv_.tolist()):
        removed_by_sites.setdefault(tuple(V[t].sites), []).append(V[t])
    removed_mask = np.zeros(len(V), bool)
    removed_mask[cv_] = True
    next_v = D.stats.get("next vertex id") or max((v.id for v in V), default=-1) + 1
    next_e = D.stats.get("next edge id") or max((e.id for e in D.edges), default=-1) + 1
    sp = Splice(KeptVertices(index, V, removed_mask), next_v, next_e)

    def chosen(t, lv, gs):
        tol = 1e-6 * (1 + abs(lv.x) + abs(lv.y) + lv.radius)
        return any(s >= n for s in gs) or any(abs(w.x - lv.x) + abs(w.y - lv.y) < tol
                                              for w in removed_by_sites.get(gs, ()))
    sp.take_vertices(L, glob, chosen)
    for le in L.edges:
        gp = tuple(glob[s] for s in le.sites)
        if not (any(s >= n for s in gp) or sp.at_taken(le)):
            continue
        why = sp.take_edge(le, gp, sp.ends_of(le))
        if why is not None:
            return why
    return sp


def _proved(D, sites, index, new_index, sp, removed_rows, gone_mask, touched):
    """None when the changed part is proved and closed (step 3 of the module docstring: the taken
    parts and the kept ends of taken edges, the closure at the taken vertices and the kept ones
    ``touched``, which lost or gained an edge), else why not.  ``removed_rows``: the rows of the
    removed vertices; ``gone_mask``: the removed edges (a boolean row mask)."""
    V = D.vertices
    vid = {v.id: v for v in sp.vertices}
    for t in (index.vertex_rows(touched).tolist() if touched else ()):
        if t not in removed_rows:
            vid[V[t].id] = V[t]
    ends_needed = sorted({u for e in sp.edges for u in e.ends} - sp.taken_ids)

    def near_edges(check_ids):
        return [D.edges[t] for t in index.edges_at(check_ids).tolist() if not gone_mask[t]]
    return changed_part_holds(sites, new_index, vid, sp, ends_needed, touched | sp.taken_ids, near_edges)


class _Appended:
    """The sequence ``old + new`` read by index without copying ``old`` (the proof of an insertion
    reads a few sites of the diagram and the new ones, :func:`runtime.segments.local_update.prove_part`)."""

    def __init__(self, old, new):
        self.old, self.new, self.n = old, new, len(old)

    def __len__(self) -> int:
        return self.n + len(self.new)

    def __getitem__(self, k: int):
        return self.old[k] if k < self.n else self.new[k - self.n]
