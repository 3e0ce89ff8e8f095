"""Local insertion of a segment or a point into a certified diagram of points and segments
(thesis §1.2: a new site only takes from the regions it touches; elementary sites, §2.2).

The new piece P brings up to three elementary sites σ (its open interior and the endpoints not
yet sites).  The update:

1. **Conflict**: the old vertices whose empty circle P enters (float distance from P to the
   centre below the radius plus a margin of 10⁻⁸·(1 + |x| + |y| + r), a hundred times the
   certificate's position tolerance; the others, *kept*, are at least that margin outside).
2. **Local diagram**: the diagram of P and the sites near the conflict circles
   (:func:`runtime.segments.construction.segment_voronoi`, passed in as ``build``).  Taken from it:
   its vertices with a new site (and those reproducing a conflict vertex), and its edges with a new
   site or an end at a taken vertex; removed: the conflict vertices and the edges ending there.
3. **Proof** of the changed part with the certificate's routines
   (:func:`runtime.segments.certificate_vertices.prove_vertices`,
   :func:`runtime.segments.certificate_edges.prove_edges`) on a diagram of the taken parts and their
   end vertices, against a site table of *all* sites (emptiness and edge conditions against every
   site, pruned by the certificate's own distance bounds: "restricted to the sites that can
   reach it" is that pruning); the closure (one incident edge per
   consecutive pair, ends listing their pair) at every taken vertex and every kept vertex that
   lost or gained an edge.

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
else — a taken edge to infinity, a new site without a taken edge, a local vertex that matches
nothing, a proof or closure that fails, arcs in the diagram, a piece repeating a site or
continuing a segment straight through its end, a crossing — returns a reason, and the caller
rebuilds (:mod:`runtime.segments.edits`).

Numbering: the old elementary sites keep their indices; the new ones are appended (in the local
diagram's order: endpoints, then the interior) with ``source`` N, the new input index.  Old
vertex and edge ids are kept; new ones take fresh ids above the largest.

Length: the conflict search, the splice and the proof of one update share the maps between the
local diagram's numbering and the global one; apart they would pass all of them around.

Public API: :func:`insert_locally`.
"""
from __future__ import annotations

import time
from collections import Counter
from fractions import Fraction

import numpy as np

from ..predicates.circles import Point
from ..sites.segment import Segment
from ..voronoi.site_input import SiteError
from ..voronoi.structure import Diagram, DiagramEdge, DiagramVertex
from .certificate_edges import prove_edges
from .certificate_sites import SiteTable
from .certificate_vertices import prove_vertices
from .crossings import check_pieces

__all__ = ["insert_locally"]

#: margin of the conflict test, relative to 1 + |x| + |y| + r of the vertex
MARGIN = 1e-8
#: the neighbourhood: sites within this many times the conflict region's size of it
RING = 1.0


def _key(s):
    if isinstance(s, Segment):
        a = (Fraction(s.p[0]), Fraction(s.p[1]))
        b = (Fraction(s.q[0]), Fraction(s.q[1]))
        return ("s",) + tuple(sorted((a, b)))
    return ("p", Fraction(str(s.cx)), Fraction(str(s.cy)))


def _box(s):
    if isinstance(s, Segment):
        x0, y0, x1, y1 = float(s.p[0]), float(s.p[1]), float(s.q[0]), float(s.q[1])
        return min(x0, x1), min(y0, y1), max(x0, x1), max(y0, y1)
    x, y = float(s.cx), float(s.cy)
    return x, y, x, y


def _dist_to_piece(a, b, X):
    """Float distances from the rows of X to the closed segment [a, b] (a point when a == b)."""
    d = b - a
    L2 = float(d @ d)
    if L2 == 0:
        return np.hypot(X[:, 0] - a[0], X[:, 1] - a[1])
    t = np.clip(((X - a) @ d) / L2, 0.0, 1.0)
    F = a + t[:, None] * d
    return np.hypot(X[:, 0] - F[:, 0], X[:, 1] - F[:, 1])


def insert_locally(D, piece, source: int, build):
    """The diagram ``D`` (certified, points and segments) with ``piece`` (a Segment or a Point)
    added, updated locally and proved (module docstring); or a str: why not (then rebuild)."""
    t0 = time.perf_counter()
    secs: dict = {}
    if not D.certified:
        return "the diagram is not certified"
    if not all(isinstance(s, (Segment, Point)) for s in D.sites):
        return "the diagram has arc sites"
    if not isinstance(piece, (Segment, Point)):
        return f"a {type(piece).__name__} piece"
    n = len(D.sites)
    keys = {_key(s): k for k, s in enumerate(D.sites)}
    if _key(piece) in keys:
        return "the piece repeats a site"
    if isinstance(piece, Segment):
        a = np.array([float(piece.p[0]), float(piece.p[1])])
        b = np.array([float(piece.q[0]), float(piece.q[1])])
        ends = [(Fraction(piece.p[0]), Fraction(piece.p[1])), (Fraction(piece.q[0]), Fraction(piece.q[1]))]
    else:
        a = b = np.array([float(piece.cx), float(piece.cy)])
        ends = []
    boxes = np.array([_box(s) for s in D.sites], float)
    # crossings, and straight continuations (a merge of elementary segments): the rebuild decides
    plo, phi = np.minimum(a, b), np.maximum(a, b)
    near = np.nonzero((boxes[:, 0] <= phi[0]) & (boxes[:, 2] >= plo[0]) & (boxes[:, 1] <= phi[1])
                      & (boxes[:, 3] >= plo[1]))[0]
    try:
        check_pieces([D.sites[k] for k in near.tolist()] + [piece])
    except SiteError:
        return "the piece meets another"
    for e in ends:
        k = keys.get(("p",) + e)
        if k is None:
            continue
        for s in near.tolist():
            t = D.sites[s]
            if isinstance(t, Segment) and e in ((Fraction(t.p[0]), Fraction(t.p[1])), (Fraction(t.q[0]), Fraction(t.q[1]))):
                o = t.q if e == (Fraction(t.p[0]), Fraction(t.p[1])) else t.p
                u = (Fraction(o[0]) - e[0], Fraction(o[1]) - e[1])
                w = (ends[1][0] - e[0], ends[1][1] - e[1]) if e == ends[0] else (ends[0][0] - e[0], ends[0][1] - e[1])
                if u[0] * w[1] - u[1] * w[0] == 0 and u[0] * w[0] + u[1] * w[1] < 0:
                    return "the piece continues a segment straight through its end"
    # 1. conflict
    V = D.vertices
    XY = np.array([[v.x, v.y] for v in V], float).reshape(-1, 2)
    R = np.array([v.radius for v in V], float)
    dP = _dist_to_piece(a, b, XY)
    margin = MARGIN * (1 + np.abs(XY).sum(axis=1) + R)
    conflict = dP < R + margin
    if not conflict.any():
        return "no vertex in conflict"
    cv_ = np.nonzero(conflict)[0]
    lo = np.minimum((XY[cv_] - R[cv_, None]).min(axis=0), plo)
    hi = np.maximum((XY[cv_] + R[cv_, None]).max(axis=0), phi)
    pad = RING * float(np.max(hi - lo)) + 1e-9
    lo, hi = lo - pad, hi + pad
    hood = np.nonzero((boxes[:, 0] <= hi[0]) & (boxes[:, 2] >= lo[0]) & (boxes[:, 1] <= hi[1])
                      & (boxes[:, 3] >= lo[1]))[0].tolist()
    secs["locate"] = time.perf_counter() - t0
    # 2. local diagram
    t1 = time.perf_counter()
    try:
        L = build([D.sites[k] for k in hood] + [piece], certify=False)
    except (SiteError, ValueError) as exc:
        return f"the local diagram failed ({exc})"
    if [p for p in L.problems if "not verified" not in p]:
        return "the local diagram has problems"
    secs["local build"] = time.perf_counter() - t1
    t2 = time.perf_counter()
    glob = []                          # local site -> global site
    new_sites = []
    for s in L.sites:
        k = keys.get(_key(s))
        if k is None:
            k = n + len(new_sites)
            new_sites.append(s)
        glob.append(k)
    if not new_sites or len(new_sites) > 3:
        return "the local diagram's new sites are not the piece's"
    is_new = lambda k: k >= n        # noqa: E731
    removed = set(np.nonzero(conflict)[0].tolist())
    removed_ids = {V[t].id for t in removed}
    by_sites: dict = {}
    for t, v in enumerate(V):
        if t not in removed:
            by_sites.setdefault(tuple(v.sites), []).append(v)
    removed_by_sites: dict = {}
    for t in removed:
        removed_by_sites.setdefault(tuple(V[t].sites), []).append(V[t])
    next_v = max((v.id for v in V), default=-1) + 1
    lmap: dict = {}                    # local vertex id -> global id
    taken_v: list = []
    for lv in L.vertices:
        gs = tuple(glob[s] for s in lv.sites)
        r = min(range(len(gs)), key=lambda t: gs[t])
        gs = gs[r:] + gs[:r]           # the smallest index first, order kept
        tol = 1e-6 * (1 + abs(lv.x) + abs(lv.y) + lv.radius)
        if any(is_new(s) for s in gs) or any(abs(w.x - lv.x) + abs(w.y - lv.y) < tol
                                             for w in removed_by_sites.get(gs, ())):
            lmap[lv.id] = next_v
            taken_v.append(DiagramVertex(next_v, gs, lv.x, lv.y, lv.radius, False))
            next_v += 1
            continue
        match = [w for w in by_sites.get(gs, ()) if abs(w.x - lv.x) + abs(w.y - lv.y) < tol]
        if len(match) == 1:
            lmap[lv.id] = match[0].id
    taken_ids = {v.id for v in taken_v}
    next_e = max((e.id for e in D.edges), default=-1) + 1
    taken_e: list = []
    for le in L.edges:
        gp = tuple(glob[s] for s in le.sites)
        ends = [None if u is None else lmap.get(u, -1) for u in le.ends]
        if not (any(is_new(s) for s in gp) or any(u in taken_ids for u in ends)):
            continue
        if None in ends or le.closed:
            return "a changed edge goes to infinity"
        if -1 in ends:
            return "a changed edge ends at a vertex of the local diagram that matches none"
        i, j = gp
        poly = np.asarray(le.polyline, float)
        if i > j:
            i, j = j, i
            ends = ends[::-1]
            poly = poly[::-1].copy()
        taken_e.append(DiagramEdge(next_e, (i, j), tuple(ends), False, poly, le.tolerance, False))
        next_e += 1
    for s in range(len(new_sites)):
        if not any(n + s in e.sites for e in taken_e):
            return "a new site has no edge in the local diagram"
    gone = [e for e in D.edges if set(e.ends) & removed_ids]
    if any(u is None for e in gone for u in e.ends):
        return "a removed edge goes to infinity"
    kept_e = [e for e in D.edges if not (set(e.ends) & removed_ids)]
    touched = {u for e in gone for u in e.ends} - removed_ids
    touched |= {u for e in taken_e for u in e.ends} - taken_ids
    secs["splice"] = time.perf_counter() - t2
    # 3. proof of the changed part
    t3 = time.perf_counter()
    sites = list(D.sites) + new_sites
    kept_v = [v for t, v in enumerate(V) if t not in removed]
    vid = {v.id: v for v in kept_v}
    for v in taken_v:
        vid[v.id] = v
    ends_needed = sorted({u for e in taken_e for u in e.ends} - taken_ids)
    sub = Diagram(sites, taken_v + [vid[u] for u in ends_needed], taken_e)
    T = SiteTable(sites)
    problems: list = []
    vproofs = prove_vertices(sub, T, problems)
    eproofs = prove_edges(sub, T, vproofs, problems)
    if problems or not all(p.ok for p in vproofs) or not all(p.ok for p in eproofs):
        return f"the changed part is not proved ({problems[0] if problems else 'a part failed'})"
    edges = kept_e + taken_e
    if not _closure(edges, [vid[u] for u in sorted(touched | taken_ids) if u in vid], vid):
        return "the closure at the changed vertices fails"
    secs["prove"] = time.perf_counter() - t3
    for v in taken_v:
        v.certified = True
    for e in taken_e:
        e.certified = True
    vertices = [vid[v.id] for v in kept_v] + taken_v
    out = Diagram(sites, vertices, edges, True, [], dict(D.stats))
    out.sources = list(D.sources) + [source] * len(new_sites)
    out.stats["update"] = "local"
    out.stats["changed"] = {"removed vertices": len(removed), "new vertices": len(taken_v),
                            "new edges": len(taken_e), "neighbourhood sites": len(hood)}
    out.stats["seconds"] = {k: round(t, 4) for k, t in secs.items()}
    return out


def _closure(edges, check, vid) -> bool:
    """Each vertex of ``check`` has exactly one incident edge per cyclically consecutive pair of its
    sites and no other; every edge ending at one lists a consecutive pair of it."""
    want = {v.id for v in check}
    at: dict = {u: Counter() for u in want}
    for e in edges:
        pair = tuple(sorted(e.sites))
        for u in e.ends:
            if u in want:
                at[u][pair] += 1
    for v in check:
        pairs = v.site_pairs()
        if Counter(pairs) != at[v.id]:
            return False
    return True
