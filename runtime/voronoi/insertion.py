"""Local insertion (and the local part of deletion) of a point, circle or ellipse site, thesis §1.2.

Thesis §1.2 maintains the diagram as sites arrive: a new site s only takes points from the regions
it touches.  For pairwise-disjoint, non-nested bounded convex sites (points, circles, ellipses)
the distances form an abstract Voronoi diagram (Klein, Mehlhorn & Meiser, CGTA 3 (1993); for
circles, additively weighted points, Karavelas & Yvinec, *Dynamic additively weighted Voronoi
diagrams in 2D*, ESA 2002, §3, the structure of CGAL's ``Apollonius_graph_2::insert``): the
*conflict region* of s — the points of the old Voronoi skeleton strictly closer to s than to
their nearest sites — is connected and meets the boundary of the old region of the site nearest
to any point of the new region (:mod:`runtime.voronoi.conflict`).  The update here:

1. **Locate.**  The old sites nearest to a point of the new region (the centre of a circle, the
   end of an ellipse's major axis; rigorous distance bounds from a k-d tree over the centres of
   the sites' bounding discs, kept between updates); their vertices are tested against s, and the
   conflict is grown through adjacent vertices (breadth first).  A vertex is *kept* only when
   d(v, s) > r_v is proved with rigorous float bounds (an ellipse's own ``distance_bounds``), with
   the verifier's vertex tolerance (:data:`runtime.voronoi.verify.vertices.VERTEX_TOL`) around the
   reported position and radius;
   an undecided vertex is treated as in conflict (removed, and rebuilt if it is still a vertex).
   The point at infinity is a vertex of the skeleton as well (the unbounded edges meet there):
   when the disc of s is not strictly inside the convex hull of the centres of the sites with
   unbounded edges, s may lead in some direction, and those sites and the finite ends of the
   unbounded edges join the search.
2. **Rebuild locally.**  For a circle or point whose disc lies strictly inside the hull of the
   centres of the sites with unbounded edges (s cannot lead at infinity), first the generic picture
   built directly
   (:mod:`runtime.voronoi.star_region`: a new vertex on every edge cut by the conflict region,
   joined around the centre of s; the region of s is star-shaped from it), a candidate checked
   and proved exactly as below; when it does not close or a proof fails, nothing is changed and
   the construction's local diagram follows (``stats["local build"]`` = "star region" when the
   direct one was kept).  After deleting a circle or point, likewise first the diagram of its
   neighbours in its old region built directly (:mod:`runtime.voronoi.hole_region`,
   ``stats["local build"]`` = "hole region").  The diagram of s, the sites of the conflicting
   vertices (or, when no vertex conflicts, the nearest sites) and their Delaunay neighbours is
   built with the
   construction (:func:`runtime.voronoi.construction.voronoi`, reached through the diagram's
   construction state); first with only the sites of the removed vertices' neighbour vertices.
   Its vertices with s, or equal to a removed vertex, replace the removed
   vertices; its edges with an end at such a vertex replace the removed edges (those at a removed
   vertex, and an old edge cut in two by s); only those edges get polylines (the local build's
   ``edge_filter``).  If the splice does not close (a vertex without
   exactly one edge per consecutive pair of its sites) or a proof fails, nothing is changed and
   the local set grows by a ring of Delaunay neighbours (twice); then the whole diagram is rebuilt
   (``stats["update"]`` = "rebuild ...").
3. **Prove only what changed** (``certify=True``): the new vertices and edges, and the kept
   vertices they end at, are proved by the verifier's own routines
   (:func:`runtime.voronoi.verify.vertices.prove_vertices`,
   :func:`runtime.voronoi.verify.edge_checks.check_edges`) against every site that can reach
   them: the sites whose disc comes within R of a centre X0 (the mean of the changed vertices,
   R bounding |q − X0| + r(q) over the changed vertices and the points q of the changed arcs) when
   they are few, else (near the hull, where the empty circles are large and that disc holds most
   of the scene) every site whose disc comes within r_j of P_j for one of the discs (P_j, r_j) of
   :mod:`runtime.voronoi.reach`, one per changed vertex (its empty circle, widened by the vertex
   tolerance) and one per piece of the polylines of the changed bounded edges (the arc lies within
   the proved tolerance of its polyline and distances are 1-Lipschitz, so the empty circle of
   every point q of the arc lies in the disc of a piece).  A site k outside them all has
   d(q, S_k) > r(q) at every such point: it cannot enter any of their empty circles.
   The closure of step 3 of :mod:`runtime.voronoi.verify.certificate` is checked at every vertex
   whose edges changed.

Why the result is proved (H the reported graph after the update, G the true one):

* A **kept vertex** v was proved a vertex of the old sites: its circle is empty of them.  If it
  was tested, d(v, s) > r_v was proved, so the circle is empty of s too.  If it was not tested,
  it is not in conflict: the conflict region is connected and meets the region of the nearest
  site, the breadth-first search started at every vertex of that region that may conflict and
  stopped only at vertices proved outside, and a path along the skeleton leaves the set of
  conflicting vertices only through such a vertex.  (With no conflicting vertex, the conflict lies
  inside one edge of the nearest site, the edge that is cut.)  A path through the point at
  infinity runs along unbounded edges: when s may lead at infinity they are all proved again
  (below), so a missed conflict there fails a proof and the update is redone larger or rebuilt.
* A **kept edge** (i, j) was proved a whole edge of the old diagram: every point of its open arc
  strictly closer to i and j than to the other old sites, its ends vertices.  It has no end at a
  removed vertex and is not the cut edge, so by the connectedness above no point of it is in
  conflict with s: it is a whole edge of the new diagram with the same ends.
* **New** vertices and edges are proved now, as in a full verification, however they were built
  (directly or by the construction: neither is trusted).
* **Closure**: unchanged at untouched vertices (inherited), checked at the others.
* **Components at infinity** (step 4 of the certificate): when no changed edge is unbounded and
  the disc of s lies strictly inside the convex hull of its neighbours' centres, the support
  function of s, h_s(θ) = c_s·e(θ) + ρ_s, is below max_k h_k(θ) in every direction, so the
  unbounded ends, their order and the sites leading between them are those of the old proof.
  Otherwise (a site on or near the hull) the unbounded edges and the accounting at infinity are
  proved again with the verifier's routines (:func:`runtime.voronoi.verify.closure.verify_accounting`,
  or the exact :mod:`runtime.voronoi.verify.hull_points` for points, equal radii and ties);
  ``stats["update"]`` says so.  After inserting a circle or a point this is done among the
  *leaders* (the old sites with an unbounded edge), the new site and the sites of the vertices the
  unbounded edges end at: the old accounting proved every other site strictly below the leaders'
  maximum support function in every direction, and a new site only raises it, so an accounting
  proved among them holds among all sites; the kept unbounded edges (proved against every old
  site) are proved again against that set, the new ones against all sites
  (:func:`_prove_infinity_leaders`).  Otherwise (deletions, ellipses) every unbounded edge, kept
  or new, is proved against all sites and the accounting runs over all sites (O(N) numpy work,
  O(hull) proofs).

Hence ``certified`` is True only when the old diagram was certified (its proofs are reused) and
everything new is proved now.  Updating an uncertified diagram with ``certify=True`` still proves
the new vertices and bounded edges (their ``certified`` flags; failures are listed in
``problems``), but the result is not certified.  Nested sites (closed edges), far-from-origin scenes and unbounded
conics are outside this argument: with a parabola or hyperbola (no support function, so no proof
at infinity), nesting or a far scene the diagram is built and proved again from scratch
(``stats["update"]`` names the reason).

**Ellipses** (with circles and points).  The same argument holds word for word in the abstract
Voronoi diagram: kept vertices and edges keep their proofs, the new site's region is connected.
The new vertices (:mod:`runtime.voronoi.verify.conic_vertices`, else the foot-point proof) and
edges (the chains of strips of :mod:`runtime.voronoi.verify.curved`) are proved by the
verifier's routines against every site that can reach them.  The reach of an arc is not read
from its polyline (for conics the verifier bounds the polyline's distance to the bisector, not
the arc's distance to the polyline) but from the regions (:mod:`runtime.voronoi.conflict`, inequalities
(1)–(3)): every point q of the open arc of an edge (i, j), proved against a set of sites
containing T (about 24 sites nearest to i), lies in i's region among T, hence within ρ of c_i
(:func:`runtime.voronoi.conflict.cell_radius`), its empty circle has radius r(q) ≤ ρ + R_i, and a
site k entering it has |c_k − c_i| < 2ρ + R_i + R_k (:func:`runtime.voronoi.conflict.arc_reach`):
the verifier is handed T and the sites within that reach of the better of the edge's two sites,
and the sites within r_v of each vertex.  When
neither site of an edge is surrounded by its T (a site on the hull), all sites are used.  At
infinity the disc test uses the bounding discs (h_s(θ) ≤ c_s·e(θ) + R_s, the centre of every
site lying in it) and the accounting is
:func:`runtime.voronoi.verify.closure.verify_accounting_conics`.  Nesting of an ellipse is
decided exactly (:func:`runtime.voronoi.conic_geometry.site_inside`) and rebuilds.

The adjacency (vertices and edges of each site, edges of each vertex, the k-d tree) is kept in a
:class:`runtime.voronoi.adjacency.DynamicState` that **moves** to the result: a chain of updates
costs what changes, the first update of a diagram builds it once (O(N)).  What stays linear in N
per update: the result's lists of sites, vertices and edges are new lists (the old diagram is
left unchanged), a copy of pointers that touches every part (about 4 ms of the 20 ms of an
insertion into 10⁵ circles, cProfile), which ``inplace=True`` avoids by updating the diagram
itself (the new list of sites is an O(1) :class:`SiteList` view until then); ``renumber="shift"`` relabels
every part with a later site; the k-d tree over the centres is rebuilt after 64 + 2√N additions
(amortised O(√N log N)); and deletions and ellipse updates near the hull re-prove the unbounded
edges and the accounting at infinity over all sites.  Vertex and edge ids stay positions: a removed
one's slot takes a new one or the last one.  The new site gets index N (the last).

Public API: :func:`insert_site`, :func:`insert_many`, :func:`delete_local`, :func:`local_update`,
:func:`local_diagram`, :class:`LocalState`, :class:`SiteList`.

Length: one argument (locate, splice, prove) shared by insertion and deletion; splitting the splice
from its soundness proof would separate the code from the docstring that justifies it.
"""
from __future__ import annotations

import dataclasses
import math
import time

import numpy as np

from .collinear_points import collinear
from .conic_geometry import site_geometry, site_inside
from .sampling import Samples, initial_spacing
from .site_arrays import SiteArrays
from ..sites.intersection import sites_intersect
from .adjacency import dynamic_state
from .star_region import star_region
from .hole_region import hole_region
from .reach import arc_discs, polyline_reach, sites_meeting_discs
from .conflict import LOCAL_KINDS, arc_reach, disc_inside, nearest_old_sites, outside, site_disc
from .site_input import SiteError, as_site, check_disjoint, sites_equal
from ..threads import one_blas_thread
from .verify.edge_checks import check_edges
from .verify.edges import CircleTable
from .verify.vertices import LOCAL_REACH, VERTEX_TOL, local_default, local_reach, prove_vertices

__all__ = ["insert_site", "insert_many", "delete_local", "local_update", "local_diagram", "LocalState", "SiteList"]

#: coordinates beyond this are built in a local frame by the construction: such scenes are rebuilt
FAR = 1e6
#: the sites of the one disc around the changed part above which the proofs take the per-piece
#: discs of :mod:`runtime.voronoi.reach` (fewer sites, more numpy work)
ONE_DISC_SITES = 64
#: the local diagram of an update is built where its sites are when their centre is within this
#: many times their extent of the origin (the batch build of the scene works there too), else in
#: the construction's local frame
LOCAL_FRAME = 1024.0


class LocalState:
    """The construction state of a diagram made by a local update: the entry points (``scratch``:
    :func:`runtime.voronoi.construction.voronoi`, ``build``, ``delete``) and the
    :class:`runtime.voronoi.adjacency.DynamicState`.  It has no sample triangulation (``samples``
    is None): a deletion that cannot be local rebuilds."""

    samples = None

    def __init__(self, scratch, delete, dynamic, build):
        self.scratch, self.delete, self.dynamic, self.build = scratch, delete, dynamic, build
        self.insert = insert_site


# ============================================================================ insertion

@one_blas_thread
def insert_site(D, site, *, certify: bool = True, inplace: bool = False):
    """The Voronoi diagram of ``D.sites + [site]``; ``D`` is left unchanged (its adjacency state
    moves to the result), or, with ``inplace=True``, ``D`` itself is updated and returned (no copy
    of its lists of sites, vertices and edges: the O(N) part of an update).  ``site``: a point, circle or ellipse in any form
    :func:`runtime.voronoi.site_input.as_site` reads.  A site meeting an existing one raises
    :class:`SiteError` naming the pair, as the batch build does; with a parabola or hyperbola the
    diagram is rebuilt (no local update).  ``stats["update"]`` says "local", "local, unbounded edges and
    accounting at infinity re-proved" (the site on or near the convex hull) or "rebuild ..."."""
    st = D.construction
    if st is None:
        raise ValueError("this diagram has no construction state (read from JSON?): build the diagram of "
                         "the new list of sites with voronoi(...)")
    t0 = time.perf_counter()
    s = as_site(site)
    g = site_geometry(s)
    dyn = dynamic_state(D)
    if g.kind not in LOCAL_KINDS or dyn.unsupported:
        # no support function for a parabola or hyperbola, so no proof at infinity for a local
        # update: the diagram of the new list of sites is built and proved from scratch
        st.dynamic = dyn
        kind = g.kind if g.kind not in LOCAL_KINDS else dyn.unsupported
        return _rebuild(D, st, SiteList(D.sites, append=s), certify,
                        f"rebuild ({_a(kind)} site: no local update)", t0, inplace)
    n = len(D.sites)
    c_disc, rs = site_disc(g)
    cs = np.array(c_disc, float)
    scale = dyn.scale if n else 1.0
    cand = dyn.near(cs, rs + dyn.rmax + 1e-9 * scale)
    try:
        check_disjoint([D.sites[k] for k in cand] + [s], [dyn.geoms[k] for k in cand] + [g])
    except SiteError as exc:
        msg = str(exc)
        if "same site" in msg:
            k = next(k for k in cand if sites_equal(D.sites[k], s))
            raise SiteError(f"site {k} and site {n} are the same site (repeated): remove one") from None
        k = next(k for k in cand if sites_equal(D.sites[k], s) or sites_intersect(D.sites[k], s))
        raise SiteError(f"site {k} and site {n} intersect: the Voronoi diagram needs disjoint sites") from None
    nested = any(_nested(D.sites[k], dyn.geoms[k], dyn.C[k], dyn.R[k], s, g, cs, rs, scale) for k in cand)
    sites2 = SiteList(D.sites, append=s)
    if nested or dyn.closed or not dyn.ids_ok or n < 3 or not D.vertices or scale > FAR:
        st.dynamic = dyn
        return _rebuild(D, st, sites2, certify, "rebuild", t0, inplace)
    dyn.add_site(s, g)
    # the old sites nearest to a point of the new region (rigorous bounds, ties kept)
    A0 = nearest_old_sites(dyn, g, n, scale)
    if A0 is None:
        dyn.remove_site(n, "shift")
        st.dynamic = dyn
        return _rebuild(D, st, sites2, certify, "rebuild (the new site's region not located)", t0, inplace)
    # breadth-first growth of the conflicting vertices
    verts, edges = D.vertices, D.edges
    tested: dict = {}
    X: set = set()
    layer = {v for a in A0 for v in dyn.site_v[a]}
    # the point at infinity is a vertex of the skeleton too: when s may lead in some direction
    # (its disc not strictly inside the hull of the centres of the sites with unbounded edges) the
    # conflict may reach the unbounded edges there, so their sites and finite ends join the search
    hull_sites = sorted({t for e in dyn.unbounded for t in edges[e].sites})
    at_infinity = not disc_inside(dyn.C[hull_sites], cs, rs)
    if at_infinity:
        A0 = sorted(set(A0) | set(hull_sites))
        layer |= {w for e in dyn.unbounded for w in edges[e].ends if w is not None}
    layer = sorted(layer)
    while layer:
        layer = [v for v in layer if v not in tested]
        out = outside(verts, layer, g)
        nxt = set()
        for v, o in zip(layer, out.tolist()):
            tested[v] = o
            if not o:
                X.add(v)
                for e in dyn.v_e[v]:
                    for w in edges[e].ends:
                        if w is not None and w not in tested:
                            nxt.add(w)
        layer = sorted(nxt)
    A = set(A0) | {t for v in X for t in verts[v].sites}
    out = local_update(D, st, dyn, sites2, A, X, set(), "insert", n, certify, t0, inplace=inplace,
                       star=not at_infinity)
    if out is not None:
        return out
    dyn.remove_site(n, "shift")       # the splice did not close: D keeps its state, rebuild
    st.dynamic = dyn
    return _rebuild(D, st, sites2, certify, "rebuild (the local splice did not close)", t0, inplace)


def delete_local(D, i, *, certify: bool = True, renumber: str = "shift", inplace: bool = False):
    """The local deletion of site i (module docstring; same splice and proofs as an insertion:
    the removed vertices are those of site i, the new ones lie in its old region and their circles
    reach it), or None when it does not apply (parabola or hyperbola sites, nesting, fewer than 4 sites, a far
    scene, or a splice that does not close): the caller then uses the construction.  Numbering:
    ``renumber="shift"`` (site j > i becomes j − 1, every part with such a site is relabelled, O(N))
    or ``"last"`` (site N − 1 takes index i, only its parts are relabelled).  ``inplace``: as for
    :func:`insert_site` (when None is returned ``D`` is unchanged)."""
    st = D.construction
    t0 = time.perf_counter()
    dyn = dynamic_state(D)
    n = len(D.sites)
    scale = dyn.scale if not dyn.unsupported and n else 0.0
    if dyn.unsupported or dyn.closed or not dyn.ids_ok or n < 5 or not D.vertices or scale > FAR:
        st.dynamic = dyn
        return None
    X = set(dyn.site_v[i])
    rm_edges = set(dyn.site_e[i])
    dyn.gone = dyn.geoms[i]
    dyn.gone_unbounded = any(None in D.edges[e].ends for e in rm_edges)
    if renumber == "last":
        def new_index(t):
            return i if t == n - 1 else t

        def old_index(t):
            return n - 1 if t == i else t
        sites2 = SiteList(D.sites, swap=i)
    else:
        def new_index(t):
            return t - (t > i)

        def old_index(t):
            return t + (t >= i)
        sites2 = [s for k, s in enumerate(D.sites) if k != i]
    A = {new_index(t) for v in X for t in D.vertices[v].sites if t != i}
    A |= {new_index(t) for e in rm_edges for t in D.edges[e].sites if t != i}
    out = local_update(D, st, dyn, sites2, A, X, rm_edges, "delete", i, certify, t0, renumber, old_index, new_index,
                       inplace=inplace)
    if out is None:
        st.dynamic = dyn
    return out


def insert_many(D, sites, *, certify: bool = True):
    """Insert ``sites`` one after the other (each with :func:`insert_site`); any iterable.  ``D`` is
    left unchanged: the first insertion makes a new diagram, the others update it in place (one
    copy of the lists, not one per site)."""
    first = True
    for s in sites:
        D = insert_site(D, s, certify=certify, inplace=not first)
        first = False
    return D


# ============================================================================ the splice

def local_update(D, st, dyn, sites2, A, X, rm_edges, op, special, certify, t0, renumber="shift",
                 old_index=None, new_index=None, inplace=False, star=False):
    """Replace the vertices ``X`` (ids) and the edges ``rm_edges`` (plus the edges at X) of ``D`` by
    the local diagram of the sites ``A`` and their neighbours (indices of ``sites2``, the new site
    list), then prove the changed part.  ``op`` is "insert" (``special``: the index of the new
    site) or "delete" (``special``: the deleted index in ``D``'s numbering); ``old_index`` and
    ``new_index`` map site indices between the new and ``D``'s numbering.  Returns None when the
    splice does not close with the sites next to the removed vertices, nor with one or two rings of
    neighbours (the caller rebuilds)."""
    old_index = old_index or (lambda t: t)
    new_index = new_index or (lambda t: t)
    direct = None
    if star and op == "insert" and X and not dyn.ellipses:
        # circles and points away from infinity: the new region built directly
        direct = ("star region", lambda: star_region(D, dyn, sites2, X, special))
    elif op == "delete" and X and not dyn.ellipses:
        # circles and points: the neighbours' diagram in the hole built directly
        direct = ("hole region", lambda: hole_region(D, dyn, X, special, new_index))
    if direct is not None:
        # a candidate only, checked and proved as any other; on failure the construction's local
        # diagram below
        name, build = direct
        t1 = time.perf_counter()
        res = build()
        t2 = time.perf_counter()
        if res is not None:
            res["sites2"] = sites2
            dyn.renumber = renumber
            chk = _check(D, dyn, res, op, special, certify, old_index, new_index)
            if chk is not None and chk["ok"]:
                chk["seconds"] = {"locate": round(t1 - t0, 6), "local build": round(t2 - t1, 6),
                                  "prove": round(time.perf_counter() - t2, 6)}
                out = _finish(D, st, dyn, res, op, special, certify, t0, 0, renumber, chk, inplace)
                out.stats["local build"] = name
                return out
    for ring in (0, 1, 2):
        L = set(A)
        if ring == 0:
            # the tightest set: the sites of the removed vertices and of the vertices next to them
            # (the ends of their edges), which the kept edges there need; enough in general
            if not X:
                continue
            L |= {new_index(t) for v in X for e in dyn.v_e[v] for w in D.edges[e].ends if w is not None
                  for t in D.vertices[w].sites if not (op == "delete" and t == special)}
        for _ in range(ring):
            L |= {new_index(t) for a in list(L) for e in dyn.site_e[old_index(a)] for t in D.edges[e].sites
                  if not (op == "delete" and t == special)}
        if op == "insert":
            L.add(special)
        L = sorted(L)
        t1 = time.perf_counter()
        res = _splice(D, st, dyn, sites2, L, X, rm_edges, op, special, old_index)
        t2 = time.perf_counter()
        if res is None:
            continue
        res["sites2"] = sites2
        dyn.renumber = renumber
        chk = _check(D, dyn, res, op, special, certify, old_index, new_index)
        if chk is not None:
            chk["seconds"] = {"locate": round(t1 - t0, 6), "local build": round(t2 - t1, 6),
                              "prove": round(time.perf_counter() - t2, 6)}
        if chk is None or not chk["ok"]:
            continue        # the splice is wrong or unproved: one more ring, then a rebuild
        return _finish(D, st, dyn, res, op, special, certify, t0, ring, renumber, chk, inplace)
    return None


def _splice(D, st, dyn, sites2, L, X, rm_edges, op, special, old_index):
    """The local diagram of sites ``L`` (new numbering) spliced in; None when it does not close."""
    # the local diagram's own problems concern its outskirts (sites missing there) or are notes
    # (a local frame): what is spliced in is checked and proved below, whatever they say
    seen: dict = {}

    def classify(lverts):
        if seen.get("verts") is not lverts:
            seen["verts"] = lverts
            seen["map"] = _classify_vertices(D, dyn, L, X, op, special, old_index, lverts)
        return seen["map"]

    def wanted(lverts, raw):
        """The raw edges the splice reads (those at a new vertex, and after a deletion those between
        kept vertices), or none when the splice cannot close: only their polylines are computed."""
        lv_map = classify(lverts)[0]
        pick = []
        for r in raw:
            _, start, _, end, ends = r
            if start is None and end is None:
                seen["abort"] = True        # a closed edge: the splice below refuses it
                return []
            m = [None if w is None else lv_map.get(w, "?") for w in ends]
            if any(isinstance(x, tuple) and x[0] == "new" for x in m):
                if "?" in m:
                    seen["abort"] = True    # a new edge to an unmatched vertex: no closed splice
                    return []
                pick.append(r)
            elif op == "delete" and "?" not in m and any(x is not None for x in m):
                pick.append(r)
        return pick

    # a state built in a local frame (:mod:`runtime.voronoi.frame`) wraps ``build`` in
    # ``build_in_frame``: the filter would see local coordinates, so every polyline is made
    framed = getattr(st.build, "__name__", "") != "build_diagram"
    loc = local_diagram(st, [sites2[k] for k in L], [dyn.geoms[old_index(k)] for k in L],
                        edge_filter=None if framed else wanted)
    if seen.get("abort"):
        return None
    lv_map, kept_match, new_v = classify(loc.vertices)
    rm_e = set(rm_edges) | {e for v in X for e in dyn.v_e[v]}
    new_e = []
    for le in loc.edges:
        if le.closed:
            return None
        ends = [None if w is None else lv_map.get(w, "?") for w in le.ends]
        pair = tuple(sorted(L[t] for t in le.sites))
        has_new = any(isinstance(x, tuple) and x[0] == "new" for x in ends)
        if not has_new:
            if (op == "delete" and all(x is None or isinstance(x, tuple) for x in ends)
                    and any(x is not None for x in ends)):
                # an edge extended across the removed region between two kept vertices
                lost = [x[1] for x in ends if x is not None and any(
                    tuple(sorted(old_index(t) for t in pair)) == tuple(D.edges[e].sites)
                    for e in dyn.v_e[x[1]] if e in rm_e)]
                if lost and not _has_edge(D, dyn, pair, ends, rm_e, old_index):
                    new_e.append((le, pair, ends))
            continue
        if "?" in ends:
            return None
        new_e.append((le, pair, ends))
    # old edges of a pair ending at a kept vertex where a new edge of that pair ends (cut in two)
    for le, pair, ends in new_e:
        opair = tuple(sorted(old_index(t) for t in pair))
        for x in ends:
            if isinstance(x, tuple) and x[0] == "old":
                for e in dyn.v_e[x[1]]:
                    if tuple(D.edges[e].sites) == opair:
                        rm_e.add(e)
    return {"loc": loc, "L": L, "new_v": new_v, "new_e": new_e, "rm_v": set(X), "rm_e": rm_e}


def _classify_vertices(D, dyn, L, X, op, special, old_index, lverts):
    """(lv_map, kept_match, new_v) for the local vertices ``lverts``: local id -> ("new", k) for
    the vertices spliced in (with the new site, or equal to a removed vertex; after a deletion, a
    vertex whose circle reaches the deleted site) or ("old", id) for a kept vertex it equals."""
    verts = D.vertices
    kept_match = {}
    new_v = []          # (local vertex, global sites tuple)
    lv_map = {}         # local vertex id -> ("new", k) or ("old", id)
    for lv in lverts:
        gs = tuple(L[t] for t in lv.sites)
        r = gs.index(min(gs))
        gs = gs[r:] + gs[:r]
        match = None
        ogs = sorted(old_index(t) for t in gs)
        for vid in dyn.site_v[old_index(gs[0])] if (op == "delete" or gs[0] != special) else ():
            v = verts[vid]
            if ogs == sorted(v.sites) and _close(v, lv):
                match = vid
                break
        if op == "insert":
            fresh = special in gs or (match is not None and match in X)
        else:
            fresh = match is None and _reaches(dyn, lv)
            if match is not None and match in X:
                match = None
        if fresh:
            lv_map[lv.id] = ("new", len(new_v))
            new_v.append((lv, gs))
        elif match is not None and match not in X:
            lv_map[lv.id] = ("old", match)
            kept_match[lv.id] = match
    return lv_map, kept_match, new_v


def local_diagram(st, sites, geoms, edge_filter=None):
    """The diagram of a few sites of the scene (not verified), built where they are: the
    construction's rounds (``st.build``, :func:`runtime.voronoi.construction.build_diagram`) from
    the known geometries, without the entry checks of ``voronoi`` (the sites are disjoint and
    within range: they are sites of the diagram, and the new one was checked).  They are built in
    the scene's frame unless they lie more than :data:`LOCAL_FRAME` times their extent from the
    origin (then, and for collinear points, ``st.scratch``: :func:`runtime.voronoi.construction.voronoi`,
    which builds far sites in a local frame, :mod:`runtime.voronoi.frame`)."""
    box = np.array([g.bounding_box() for g in geoms], float)
    lo, hi = box[:, :2].min(axis=0), box[:, 2:].max(axis=0)
    S = SiteArrays(sites, geoms)
    if (not np.abs((lo + hi) / 2).max() <= LOCAL_FRAME * float((hi - lo).max())
            or (S.all_circles and not S.R.any() and collinear(S.C))):
        return st.scratch(sites, certify=False)
    return st.build(S, Samples(S, initial_spacing(S)), {}, [], {"sites": len(sites), "rounds": 0, "samples": 0},
                    {"input": 0.0}, certify=False, edge_filter=edge_filter)


def _has_edge(D, dyn, pair, ends, rm_e, old_index):
    opair = tuple(sorted(old_index(t) for t in pair))
    want = sorted((-1 if x is None else x[1]) for x in ends)
    w = next(x[1] for x in ends if x is not None)
    return any(tuple(D.edges[e].sites) == opair and sorted(-1 if u is None else u for u in D.edges[e].ends) == want
               for e in dyn.v_e[w] if e not in rm_e)


def _close(v, lv) -> bool:
    tol = 1e-9 * (1 + abs(v.x) + abs(v.y) + abs(v.radius))
    return abs(v.x - lv.x) <= tol and abs(v.y - lv.y) <= tol and abs(v.radius - lv.radius) <= tol


def _reaches(dyn, lv) -> bool:
    """The circle of local vertex ``lv`` reaches the deleted site (its geometry is ``dyn.gone``)."""
    d = float(dyn.gone.distance(np.array([[lv.x, lv.y]], float))[0])
    return d < lv.radius * (1 + 1e-9)


# ============================================================================ apply + prove

def _check(D, dyn, res, op, special, certify, old_index, new_index):
    """Closure and proofs of the splice ``res`` before anything is changed (provisional ids above
    the current ones).  Returns None when the splice is wrong (retry or rebuild), else a dict with
    the new parts' flags, ``ok`` (everything proved), ``how`` and ``problems``."""
    NV, NE = len(D.vertices), len(D.edges)
    proto_v, proto_e = D.vertices[0], D.edges[0]
    rm_v, rm_e = res["rm_v"], res["rm_e"]
    pv = [_clone(proto_v, id=NV + k, sites=gs, x=lv.x, y=lv.y, radius=lv.radius, certified=False)
          for k, (lv, gs) in enumerate(res["new_v"])]

    def pend(x):
        return None if x is None else (NV + x[1] if x[0] == "new" else x[1])

    pe = []
    for k, (le, pair, ends) in enumerate(res["new_e"]):
        # a kept end vertex: the polyline ends exactly at its reported position (the local build's
        # own float position of that vertex may differ in the last bits)
        P = np.array(le.polyline, float)
        for side, x in ((0, ends[0]), (-1, ends[1])):
            if x is not None and x[0] == "old":
                P[side] = (D.vertices[x[1]].x, D.vertices[x[1]].y)
        le.polyline = P
        pe.append(_clone(proto_e, id=NE + k, sites=pair, ends=tuple(pend(x) for x in ends), closed=False,
                                      polyline=P, tolerance=le.tolerance, certified=False))

    def vert(vid):
        if vid >= NV:
            return pv[vid - NV]
        v = D.vertices[vid]
        return v if op == "insert" else _clone(v, sites=_rot(tuple(new_index(t) for t in v.sites)))

    def old_pair(e):
        return tuple(sorted(new_index(t) for t in D.edges[e].sites))

    # closure at every vertex whose edges changed; every local site keeps an edge
    changed = {v.id for v in pv} | {w for e in pe for w in e.ends if w is not None}
    changed |= {w for e in rm_e for w in D.edges[e].ends if w is not None and w not in rm_v}
    problems: list = []
    at: dict = {}                 # vertex id -> the site pairs of the new edges ending there
    for e in pe:
        for w in set(e.ends):
            if w is not None:
                at.setdefault(w, []).append(tuple(e.sites))
    for vid in sorted(changed):
        v = vert(vid)
        k = len(v.sites)
        want = sorted({tuple(sorted((v.sites[t], v.sites[(t + 1) % k]))) for t in range(k)})
        got = [old_pair(e) for e in dyn.v_e[vid] if e not in rm_e] if vid < NV else []
        got = sorted(got + at.get(vid, []))
        if got != want:
            return None
    for t in res["L"]:
        if not any(t in e.sites for e in pe) and not (dyn.site_e[old_index(t)] - rm_e if not (
                op == "insert" and t == special) else set()):
            return None
    ok = True
    flags_v, flags_e = {}, {}
    how = "local"
    full = certify and D.certified
    bounded = [e for e in pe if None not in e.ends] if certify else []
    notes: list = []
    if full:
        ok &= _prove_sub(D, dyn, pv, bounded, vert, op, special, new_index, problems, flags_v, flags_e)
    else:
        # the result cannot be certified (certify=False, or an uncertified diagram): the new
        # vertices must still be proved (else the splice is redone); with certify=True the new
        # bounded edges are proved too, their flags kept and their failures noted
        _prove_sub(D, dyn, pv, bounded, vert, op, special, new_index, notes, flags_v, flags_e)
        ok &= all(flags_v.get(v.id, False) for v in pv)
    if full:
        infinity = (any(None in e.ends for e in pe) or any(None in D.edges[e].ends for e in rm_e)
                    or (op == "insert" and not _inside_hull(dyn, special, res))
                    or (op == "delete" and dyn.gone_unbounded))
        if infinity:
            how = "local, unbounded edges and accounting at infinity re-proved"
            ok &= _prove_infinity(D, dyn, pe, rm_e, vert, op, special, problems, flags_v, flags_e)
    return {"ok": bool(ok) and not problems, "problems": problems, "flags_v": flags_v, "flags_e": flags_e,
            "how": how, "full": full, "notes": notes}


def _finish(D, st, dyn, res, op, special, certify, t0, ring, renumber, chk, inplace=False):
    """Write the checked splice into new lists, or into ``D``'s own with ``inplace`` (ids stay
    positions), and move ``dyn`` to the result."""
    sites2 = res["sites2"]
    was_certified = D.certified
    verts, edges = (D.vertices, D.edges) if inplace else (list(D.vertices), list(D.edges))
    proto_v, proto_e = D.vertices[0], D.edges[0]
    NV, NE = len(D.vertices), len(D.edges)
    rm_v, rm_e = sorted(res["rm_v"]), sorted(res["rm_e"])
    # detach removed parts from the adjacency (in D's numbering), then renumber after a deletion
    for e in rm_e:
        for t in edges[e].sites:
            dyn.site_e[t].discard(e)
        for w in edges[e].ends:
            if w is not None and w not in res["rm_v"]:
                dyn.v_e[w].remove(e)
        dyn.unbounded.discard(e)
    for v in rm_v:
        for t in verts[v].sites:
            dyn.site_v[t].discard(v)
        dyn.v_e[v] = []
    if op == "delete":
        dyn.remove_site(special, renumber)
        verts, edges = _renumber_sites(D, dyn, verts, edges, special, renumber, res)
    # vertices: new ones into the holes, then the last ones moved into what is left
    vid_new = rm_v[:len(res["new_v"])] + list(range(len(verts), len(verts) + max(0, len(res["new_v"]) - len(rm_v))))
    while len(verts) < (max(vid_new) + 1 if vid_new else 0):
        verts.append(None)
        dyn.v_e.append([])
    vremap = {}
    holes = rm_v[len(res["new_v"]):]
    _compact(verts, holes, lambda old, new: _move_vertex(verts, edges, dyn, old, new, vremap, proto_v))
    new_vobjs = []
    for k, (lv, gs) in enumerate(res["new_v"]):
        v = _clone(proto_v, id=vid_new[k], sites=gs, x=lv.x, y=lv.y, radius=lv.radius,
                                certified=chk["flags_v"].get(NV + k, False))
        verts[v.id] = v
        new_vobjs.append(v)
        for t in gs:
            dyn.site_v[t].add(v.id)

    def end_id(x):
        if x is None:
            return None
        return vid_new[x[1]] if x[0] == "new" else vremap.get(x[1], x[1])

    eid_new = rm_e[:len(res["new_e"])] + list(range(len(edges), len(edges) + max(0, len(res["new_e"]) - len(rm_e))))
    while len(edges) < (max(eid_new) + 1 if eid_new else 0):
        edges.append(None)
    _compact(edges, rm_e[len(res["new_e"]):], lambda old, new: _move_edge(edges, dyn, old, new, proto_e))
    for k, (le, pair, ends) in enumerate(res["new_e"]):
        e = _clone(proto_e, id=eid_new[k], sites=pair, ends=tuple(end_id(x) for x in ends),
                                closed=False, polyline=le.polyline, tolerance=le.tolerance,
                                certified=chk["flags_e"].get(NE + k, False))
        edges[e.id] = e
        for t in pair:
            dyn.site_e[t].add(e.id)
        for w in e.ends:
            if w is not None:
                dyn.v_e[w].append(e.id)
        if None in e.ends:
            dyn.unbounded.add(e.id)
    if isinstance(sites2, SiteList):
        sites2 = sites2.realize(inplace)
    if inplace:
        D.sites, D.vertices, D.edges, D.certified, D.problems, D.stats = sites2, verts, edges, False, [], {}
        out = D
    else:
        out = _clone(D, sites=sites2, vertices=verts, edges=edges, certified=False, problems=[], stats={})
    out.construction = LocalState(st.scratch, st.delete, dyn, st.build)
    problems = list(chk["problems"]) + list(chk["notes"])
    if not certify:
        problems.append("not verified (certify=False)")
    elif not was_certified:
        problems.append("not certified: the diagram it was updated from was not certified")
    out.certified = bool(chk["full"] and chk["ok"]) and not problems
    out.problems = problems
    out.stats = {"sites": len(sites2), "update": chk["how"], "rings": ring,
                 "changed": {"vertices_removed": len(rm_v), "vertices_new": len(new_vobjs),
                             "edges_removed": len(rm_e), "edges_new": len(res["new_e"]), "local_sites": len(res["L"]),
                             "new_unproved": sum(not v.certified for v in new_vobjs)
                             + sum(not edges[e].certified for e in eid_new)},
                 "seconds": dict(chk.get("seconds", {}), total=round(time.perf_counter() - t0, 6))}
    if op == "delete":
        out.stats["deletion"] = chk["how"]
    return out


def _compact(lst, holes, move):
    """Fill ``holes`` (sorted positions of removed items) by moving the last items; trailing
    holes are dropped."""
    holes = sorted(holes)
    hs = set(holes)
    while holes:
        last = len(lst) - 1
        if last in hs:
            lst.pop()
            hs.discard(last)
            holes.remove(last)
            continue
        h = holes.pop(0)
        hs.discard(h)
        move(last, h)
        lst.pop()


def _move_vertex(verts, edges, dyn, old, new, vremap, proto):
    v = _clone(verts[old], id=new)
    verts[new] = v
    for t in v.sites:
        dyn.site_v[t].discard(old)
        dyn.site_v[t].add(new)
    for e in dyn.v_e[old]:
        edges[e] = _clone(edges[e], ends=tuple(new if w == old else w for w in edges[e].ends))
    dyn.v_e[new] = dyn.v_e[old]
    dyn.v_e.pop()
    for k, w in list(vremap.items()):
        if w == old:
            vremap[k] = new
    vremap[old] = new


def _move_edge(edges, dyn, old, new, proto):
    e = _clone(edges[old], id=new)
    edges[new] = e
    if old in dyn.unbounded:
        dyn.unbounded.discard(old)
        dyn.unbounded.add(new)
    for t in e.sites:
        dyn.site_e[t].discard(old)
        dyn.site_e[t].add(new)
    for w in e.ends:
        if w is not None:
            lst = dyn.v_e[w]
            lst[lst.index(old)] = new


def _renumber_sites(D, dyn, verts, edges, i, renumber, res):
    """Vertices and edges of the other sites renumbered after deleting site i (``dyn`` already
    renumbered): "shift" rewrites every part with a site above i (O(N)), "last" only those of site
    N − 1.  The renumbered parts are new objects (``D`` keeps its own)."""
    n = len(D.sites)
    rm_v, rm_e = res["rm_v"], res["rm_e"]
    if renumber == "last":
        if i == n - 1:
            return verts, edges
        for v in dyn.site_v[i]:
            if v not in rm_v:
                old = verts[v]
                verts[v] = _clone(old, sites=_rot(tuple(i if t == n - 1 else t for t in old.sites)))
        for e in dyn.site_e[i]:
            if e not in rm_e:
                old = edges[e]
                edges[e] = _clone(old, sites=tuple(sorted(i if t == n - 1 else t for t in old.sites)))
        return verts, edges
    for v, old in enumerate(verts):
        if max(old.sites) > i and v not in rm_v:
            sites = tuple(t - (t > i) for t in old.sites)
            verts[v] = _clone(old, sites=sites if min(old.sites) != i else _rot(sites))
    for e, old in enumerate(edges):
        if old.sites[1] > i and e not in rm_e:
            edges[e] = _clone(old, sites=(old.sites[0] - (old.sites[0] > i), old.sites[1] - 1))
    return verts, edges


def _clone(obj, **changes):
    """A shallow copy of a vertex, edge or diagram with ``changes`` (cheaper than
    dataclasses.replace, which re-runs the constructor: the "shift" renumbering copies half of all
    parts, and an update makes some sixty parts)."""
    if not hasattr(obj, "__dict__"):
        return dataclasses.replace(obj, **changes)
    new = object.__new__(type(obj))
    new.__dict__.update(obj.__dict__)
    new.__dict__.update(changes)
    return new


def _inside_hull(dyn, s, res):
    """The disc of site s lies strictly inside the convex hull of its neighbours' centres (with a
    rounding margin): then h_s(θ) < max_k h_k(θ) for every direction θ."""
    nb = sorted({t for _, gs in res["new_v"] for t in gs if t != s})
    return disc_inside(dyn.C[nb], dyn.C[s], dyn.R[s])


def _new_numbering(dyn, op, special, renumber):
    """(centres, radii, geometries) of the sites in the new numbering (dyn is still in the old)."""
    if op == "insert":
        return dyn.C, dyn.R, dyn.geoms
    i, n = special, len(dyn.C)
    if renumber == "last" and i < n - 1:
        C, R, G = dyn.C.copy(), dyn.R.copy(), list(dyn.geoms)
        C[i], R[i], G[i] = C[-1], R[-1], G[-1]
        return C[:-1], R[:-1], G[:-1]
    return np.delete(dyn.C, i, axis=0), np.delete(dyn.R, i), dyn.geoms[:i] + dyn.geoms[i + 1:]


def _table(C, R):
    """A verifier :class:`runtime.voronoi.verify.edges.CircleTable` from float arrays (the
    attributes its constructor sets from the geometries)."""
    return CircleTable.from_arrays(C, R)


def _prove_sub(D, dyn, pv, pe, vert, op, special, new_index, problems, flags_v, flags_e) -> bool:
    """Prove the new vertices and the bounded new edges ``pe`` (with the kept vertices they end at)
    against every site that can reach them (module docstring, step 3)."""
    vids = sorted({v.id for v in pv} | {w for e in pe for w in e.ends})
    if not vids:
        return True
    V = [vert(v) for v in vids]
    if dyn.ellipses:
        near = _conic_reach(dyn, V, pe, op, special)
        if near is None:
            return _prove_all_sites(D, dyn, V, pe, op, special, problems, flags_v, flags_e)
        return _prove_among(D, dyn, V, pe, near, op, special, new_index, problems, flags_v, flags_e)
    # every site that can enter the empty circle of a vertex or of a point of a bounded arc: first
    # one disc around them all (centre X0, radius M bounding |q − X0| + r(q)), enough when it holds
    # few sites; else (near the hull, where the empty circles are large) the union of one disc per
    # vertex and per piece of polyline (module docstring, step 3; :mod:`runtime.voronoi.reach`)
    XYR = np.array([[w.x, w.y, w.radius] for w in V], float)
    X0 = XYR[:, :2].mean(axis=0)
    M = float((np.hypot(*(XYR[:, :2] - X0).T) + XYR[:, 2]
               + LOCAL_REACH * VERTEX_TOL * (1 + np.abs(XYR).sum(axis=1))).max())
    M = max(M, _arcs_reach(dyn, pe, X0, op, special))
    M = M * (1 + 1e-9) + 1e-9 * float(np.abs(X0).sum() + 1)
    near = dyn.near(X0, M + dyn.rmax)
    if len(near) > ONE_DISC_SITES:
        pts = [np.array([[w.x, w.y] for w in V], float)]
        rad = [np.array([w.radius + LOCAL_REACH * VERTEX_TOL * (1 + abs(w.x) + abs(w.y) + w.radius) for w in V], float)]
        rad[0] = rad[0] * (1 + 1e-9) + 1e-9 * (np.abs(pts[0]).sum(axis=1) + 1)
        for e in pe:
            Mp, rp = arc_discs(e.polyline, dyn.geoms[_old(e.sites[0], op, special, dyn)], e.tolerance)
            pts.append(Mp)
            rad.append(rp)
        near = sites_meeting_discs(dyn, np.vstack(pts), np.concatenate(rad))
    return _prove_among(D, dyn, V, pe, near, op, special, new_index, problems, flags_v, flags_e)


def _arcs_reach(dyn, pe, X0, op, special) -> float:
    """max over the points q of the arcs of the bounded edges ``pe`` (circle and point sites) of a
    bound on |q − X0| + r(q) (:func:`runtime.voronoi.reach.polyline_reach`), the sites renumbered
    to the old diagram's."""
    pe = [e for e in pe if len(e.polyline)]
    if not pe:
        return 0.0
    polys = [np.asarray(e.polyline, float).reshape(-1, 2) for e in pe]
    site = np.array([_old(e.sites[0], op, special, dyn) for e in pe])
    return float(polyline_reach(polys, dyn.C[site], dyn.R[site], [e.tolerance for e in pe], X0).max())


def _conic_reach(dyn, V, pe, op, special):
    """With an ellipse among the sites: the old indices of every site that can reach the vertices
    ``V`` or the arcs of the bounded edges ``pe`` (module docstring, ellipses), or None when a
    site of an edge is not surrounded (:func:`runtime.voronoi.conflict.arc_reach`)."""
    out: set = set()
    for w in V:
        rad = w.radius + LOCAL_REACH * VERTEX_TOL * (1 + abs(w.x) + abs(w.y) + w.radius)
        out.update(dyn.near((w.x, w.y), rad * (1 + 1e-9) + dyn.rmax))
    for e in pe:
        best = None
        for t in e.sites:
            o = _old(t, op, special, dyn)
            T = _surrounding(dyn, o, op, special)
            reach = arc_reach(dyn.C, dyn.R, o, T)
            if reach is not None and (best is None or reach < best[0]):
                best = (reach, o, T)
        if best is None:
            return None
        reach, o, T = best
        out.update(T)
        out.update(dyn.near(dyn.C[o], reach * (1 + 1e-9) + dyn.rmax))
    if op == "delete":
        out.discard(special)
    return out


def _surrounding(dyn, o, op, special, k=24):
    """About k old sites with the centres nearest to site o's, without o and a deleted site (any
    set of sites is sound for :func:`runtime.voronoi.conflict.cell_radius`; the nearest make ρ
    small)."""
    got = set(dyn.nearest(dyn.C[o], k + 2))
    got.discard(o)
    if op == "delete":
        got.discard(special)
    return sorted(got)


def _prove_among(D, dyn, V, pe, near, op, special, new_index, problems, flags_v, flags_e) -> bool:
    """Prove the vertices ``V`` and the bounded edges ``pe`` with the verifier's routines against
    the sites ``near`` (old indices, every site that can reach them) and their own sites."""
    Lp = {new_index(t) for t in near if not (op == "delete" and t == special)}
    Lp = sorted(Lp | {t for v in V for t in v.sites})
    pos = {g: t for t, g in enumerate(Lp)}
    sub_v = [_clone(v, sites=_rot(tuple(pos[t] for t in v.sites))) for v in V]
    sub_e = [_clone(e, sites=tuple(sorted(pos[t] for t in e.sites))) for e in pe]
    geoms = [dyn.geoms[_old(g, op, special, dyn)] for g in Lp]
    sub = _clone(D, sites=[g.exact for g in geoms], vertices=sub_v, edges=sub_e, construction=None)
    table = CircleTable(geoms) if all(g.kind in ("point", "circle") for g in geoms) else None
    local: list = []
    vinfo, vok = prove_vertices(sub, sub.sites, geoms, table, local)
    # a vertex proved in a coarse box: its true empty circle may reach past the sites listed
    # near the reported one; proved only if no other site comes within that radius
    listed = set(Lp)
    for m, (v, f) in enumerate(zip(sub_v, vok)):
        R = local_reach(v, vinfo[v.id]) if f and v.id in vinfo else 0.0
        if f and R > local_default(v):
            out = [t for t in sites_meeting_discs(dyn, [[v.x, v.y]], [R])
                   if not (op == "delete" and t == special) and new_index(t) not in listed]
            if out:
                vok[m] = False
                local.append(f"vertex {m}: proved in a box that reaches site {out[0]}, not among the sites listed near it")
    eok, _, _ = check_edges(sub, geoms, table, vinfo, vok, local, {}) if sub_e else ([], None, None)
    for v, f in zip(V, vok):
        flags_v[v.id] = bool(f)
    for e, f in zip(pe, eok):
        flags_e[e.id] = bool(f)
    problems.extend(f"local proof (sites {Lp[:12]}{'...' if len(Lp) > 12 else ''} numbered 0, 1, ...): {p}"
                    for p in local)
    return all(vok) and all(eok) and not local


def _prove_all_sites(D, dyn, V, pe, op, special, problems, flags_v, flags_e) -> bool:
    """Step 3 with an ellipse among the sites when a site of a new edge is not surrounded: the new
    vertices and edges proved by the verifier's routines against **all** sites (its vertex proofs
    and chains of strips, :mod:`runtime.voronoi.verify.curved`, exclude the far sites themselves;
    O(N) set-up)."""
    _, _, G = _new_numbering(dyn, op, special, dyn.renumber)
    sub = _clone(D, sites=[g.exact for g in G], vertices=V, edges=list(pe), construction=None)
    local: list = []
    vinfo, vok = prove_vertices(sub, sub.sites, G, None, local)
    eok = check_edges(sub, G, None, vinfo, vok, local, {})[0] if pe else []
    for v, f in zip(V, vok):
        flags_v[v.id] = bool(f)
    for e, f in zip(pe, eok):
        flags_e[e.id] = bool(f)
    problems.extend(f"local proof: {p}" for p in local)
    return all(vok) and all(eok) and not local


def _old(g, op, special, dyn):
    """Index in dyn (old numbering) of new-numbering site g; dyn.renumber says how (deletion)."""
    if op == "insert":
        return g
    if dyn.renumber == "last":
        return len(dyn.C) - 1 if g == special else g
    return g + (g >= special)


def _prove_infinity(D, dyn, pe, rm_e, vert, op, special, problems, flags_v, flags_e) -> bool:
    """Step 4a of the certificate after the update: every unbounded edge (kept or new) proved
    against all sites, then the accounting of the ends at infinity (as in
    :func:`runtime.voronoi.verify.certificate.verify` for circles and points)."""
    from .verify.closure import verify_accounting_conics
    from .verify.support import SupportTable

    if op == "insert" and not dyn.ellipses:
        got = _prove_infinity_leaders(D, dyn, pe, rm_e, vert, special, problems, flags_v, flags_e)
        if got is not None:
            return got
    C, R, G = _new_numbering(dyn, op, special, dyn.renumber)
    conic = any(g.kind == "ellipse" for g in G)
    table = None if conic else _table(C, R)
    kept = [e for e in sorted(dyn.unbounded) if e not in rm_e]
    E = [_clone(D.edges[e], sites=tuple(sorted(_new(t, op, special, dyn) for t in D.edges[e].sites)))
         for e in kept] if op == "delete" else [D.edges[e] for e in kept]
    E += [e for e in pe if None in e.ends]
    vids = sorted({w for e in E for w in e.ends if w is not None})
    V = [vert(v) for v in vids]
    sub = _clone(D, sites=[g.exact for g in G], vertices=V, edges=E, construction=None)
    local: list = []
    vinfo, vok = prove_vertices(sub, sub.sites, G, table, local)
    eok, ends_inf, _ = check_edges(sub, G, table, vinfo, vok, local, {})
    for v, f in zip(V, vok):
        flags_v[v.id] = flags_v.get(v.id, True) and bool(f)
    for e, f in zip(E, eok):
        if e.id >= len(D.edges):
            flags_e[e.id] = bool(f)
    if conic:
        proved = {t[-1] for t in ends_inf}
        acc = verify_accounting_conics(len(G), SupportTable(G), ends_inf, local,
                                       unproved_ends=[e.id for e in E if e.id not in proved],
                                       sites=[g.exact for g in G])
    else:
        acc = _accounting_discs(G, table, ends_inf, local, all(eok))
    problems.extend(local)
    return all(vok) and all(eok) and acc and not local


def _prove_infinity_leaders(D, dyn, pe, rm_e, vert, x, problems, flags_v, flags_e):
    """Step 4a after inserting the circle or point x into a certified diagram of circles and
    points, without the work over all N sites that the kept part does not need.

    Leaders: the old sites with an unbounded edge.  The old certificate proved the accounting at
    infinity: between consecutive unbounded ends one site strictly maximises the support function
    h_k(θ) = c_k·e(θ) + ρ_k over every other old site, so every other old site k has
    h_k(θ) < max over the leaders for every θ (strictly, ties at the ends being between the two
    sites of that end's edge, both leaders).  Inserting x only raises the maximum, so the sites
    that can lead in the new diagram are among H = leaders ∪ {x} (with the sites of the vertices
    the unbounded edges end at), and an accounting proved among H (consecutive ends sharing a site
    that strictly leads among H) holds among all sites: a site outside H stays strictly below the
    maximum over H.  The kept unbounded edges were proved whole edges against every old site;
    proving them again against H (which holds x) proves them against every site.  New unbounded
    edges are proved against all sites (the full k-d tree: O(N log N) numpy, not O(N) proofs).
    Returns None when a new unbounded edge has a site outside H (then the caller re-proves
    everything against all sites)."""
    kept = [D.edges[e] for e in sorted(dyn.unbounded) if e not in rm_e]
    new = [e for e in pe if None in e.ends]
    ends_v = sorted({w for e in kept + new for w in e.ends if w is not None})
    H = sorted({t for e in dyn.unbounded for t in D.edges[e].sites} | {x}
               | {t for w in ends_v for t in vert(w).sites})
    pos = {t: k for k, t in enumerate(H)}
    if any(t not in pos for e in new for t in e.sites):
        return None
    GH = [dyn.geoms[t] for t in H]
    tableH = _table(dyn.C[H], dyn.R[H])
    local: list = []
    ends_H: list = []
    ok = True
    # kept unbounded edges (old proofs against the old sites) proved against H, which holds x
    vk = sorted({w for e in kept for w in e.ends if w is not None})
    Vk = [_clone(vert(w), sites=_rot(tuple(pos[t] for t in vert(w).sites))) for w in vk]
    Ek = [_clone(e, sites=tuple(sorted(pos[t] for t in e.sites))) for e in kept]
    if Ek:
        sub = _clone(D, sites=[g.exact for g in GH], vertices=Vk, edges=Ek, construction=None)
        vinfo, vok = prove_vertices(sub, sub.sites, GH, tableH, local)
        eok, ends, _ = check_edges(sub, GH, tableH, vinfo, vok, local, {})
        ok &= all(vok) and all(eok)
        ends_H += ends
        for w, f in zip(vk, vok):
            flags_v[w] = flags_v.get(w, True) and bool(f)
    # new unbounded edges against all sites
    if new:
        vn = sorted({w for e in new for w in e.ends if w is not None})
        Vn = [vert(w) for w in vn]
        sub = _clone(D, sites=[g.exact for g in dyn.geoms], vertices=Vn, edges=new, construction=None)
        table = _table(dyn.C, dyn.R)
        vinfo, vok = prove_vertices(sub, sub.sites, dyn.geoms, table, local)
        eok, ends, _ = check_edges(sub, dyn.geoms, table, vinfo, vok, local, {})
        ok &= all(vok) and all(eok)
        ends_H += [(th, tuple(sorted(pos[t] for t in pair)), sigma, eid) for th, pair, sigma, eid in ends]
        for w, f in zip(vn, vok):
            flags_v[w] = flags_v.get(w, True) and bool(f)
        for e, f in zip(new, eok):
            flags_e[e.id] = bool(f)
    # the accounting among H
    acc = _accounting_discs(GH, tableH, ends_H, local, ok)
    problems.extend(f"at infinity (sites {H[:12]}{'...' if len(H) > 12 else ''} numbered 0, 1, ...): {p}"
                    for p in local)
    return bool(ok and acc and not local)


def _accounting_discs(G, table, ends, local: list, edges_ok: bool) -> bool:
    """The accounting of the ends at infinity among the point and circle sites G (the verifier's
    routes: points, equal radii, the float route, then the exact one when every edge is proved);
    its problems are appended to ``local``."""
    from .verify.closure import circles_disjoint, verify_accounting
    from .verify.hull_points import verify_accounting_discs, verify_accounting_points

    if all(g.kind == "point" for g in G):
        return verify_accounting_points(G, ends, local)
    if len({g.exact.r2 for g in G}) == 1:
        return circles_disjoint(table, local) and verify_accounting_points(G, ends, local)
    lines: list = []
    acc = verify_accounting(len(G), table, ends, lines)
    if not acc and edges_ok:
        exact_lines: list = []
        got = verify_accounting_discs(G, ends, exact_lines)
        if got is not None:
            acc, lines = got, exact_lines
    local.extend(lines)
    return acc


def _new(t, op, special, dyn):
    """New-numbering index of old site t (not the deleted one)."""
    if op == "insert":
        return t
    if dyn.renumber == "last":
        return special if t == len(dyn.C) - 1 else t
    return t - (t > special)


def _rot(t):
    r = t.index(min(t))
    return t[r:] + t[:r]


def _rebuild(D, st, sites2, certify, how, t0, inplace=False):
    out = st.scratch(list(sites2), certify=certify)
    out.stats["update"] = how
    out.stats.setdefault("seconds", {})["update_total"] = round(time.perf_counter() - t0, 6)
    if inplace:
        for f in dataclasses.fields(D):
            setattr(D, f.name, getattr(out, f.name))
        return D
    return out


class SiteList:
    """The new list of sites of an update as an O(1) view of the old one: ``append`` added last,
    or site ``swap`` replaced by the last one and the last dropped (a deletion with
    ``renumber="last"``).  :meth:`realize` makes it a list: a copy (O(N) pointers), or the old
    list changed in place."""

    def __init__(self, base, append=None, swap=None):
        self.base, self.extra, self.swap = base, append, swap
        self.n = len(base) + 1 if swap is None else len(base) - 1

    def __len__(self):
        return self.n

    def __getitem__(self, k):
        k = int(k)
        if not -self.n <= k < self.n:
            raise IndexError(k)
        k %= self.n
        if self.swap is None:
            return self.extra if k == len(self.base) else self.base[k]
        return self.base[-1] if k == self.swap else self.base[k]

    def __iter__(self):
        return (self[k] for k in range(self.n))

    def realize(self, inplace: bool) -> list:
        b = self.base
        if self.swap is None:
            if inplace:
                b.append(self.extra)
                return b
            return b + [self.extra]
        out = b if inplace else list(b)
        out[self.swap] = out[-1]
        out.pop()
        return out


def _nested(site_k, g_k, c_k, r_k, s, g, cs, rs, scale) -> bool:
    """Old site k and the new site s (disjoint) are nested, one inside the other."""
    if g_k.kind in ("point", "circle") and g.kind in ("point", "circle"):
        return math.hypot(*(c_k - cs)) < abs(r_k - rs) + 1e-9 * scale
    if not math.hypot(*(c_k - cs)) < r_k + rs + 1e-9 * scale:
        return False                # disjoint bounding discs
    return site_inside(site_k, s) or site_inside(s, site_k)


def _a(kind: str) -> str:
    return ("an " if kind[0] in "aeiou" else "a ") + kind
