"""The verifier run on pieces of a diagram on Dask workers, and why the pieces prove the whole.

:func:`runtime.voronoi.verify.certificate.verify` proves a reported diagram H equal to the true
diagram G in four steps (its module docstring): (1) every vertex is a true vertex, (2) every edge
is a whole true edge between its proved ends, (3) closure: each vertex has exactly one edge per
pair of cyclically consecutive sites, every site has an edge, and (4) the ends at infinity are
all there; then H ⊂ G is closed under incidence, so H is a union of components of G, and every
component of G (sites not nested: every component is unbounded, thesis Prop. 1.2.1) has an
unbounded end, which (4) places in H.

Steps (1) and (2) are local: a vertex's proof reads its sites and the sites near its circle, an
edge's proof its two sites, its end vertices and the sites near its arc, never another edge.
So :func:`chunked_verify` hands the edges, in spatial chunks (one per tile), each with the
vertices it ends at, to the verifier on the workers (or runs them here one after the other, in
one chunk's memory); a vertex or an edge proved in its chunk is proved.  Step (3) is run here on the whole diagram
(:func:`runtime.voronoi.verify.closure.verify_closure`: combinatorics only).

Step (4): one more chunk holds every unbounded edge of H (few: about the number of sites on the
hull), and no other unbounded edge is in any chunk, so its verifier run proves them and runs the
accounting at infinity on exactly the ends of H (which also keeps it on its fast route); the
other chunks skip the accounting (``verify(..., at_infinity=False)``).  The unbounded edges
are the costly ones near the hull (their empty discs are nearly half-planes, with every site
a candidate), proved once.  In all runs the closure of the sub-diagram fails by
construction (its vertices lack the edges of other chunks), so its lines of that kind -- a
vertex's missing edge of a pair, a site without an edge -- are set aside, and any other line
refuses the certificate.  This reads the accounting's verdict from its lines: every refusal of
the accounting functions (:mod:`runtime.voronoi.verify.closure`,
:mod:`runtime.voronoi.verify.hull_points`) appends a line before returning False (checked by
reading them; a verdict field in the certificate would make this direct).

**Sites per chunk.**  A vertex's or an edge's proof reads only the sites that can enter its empty
circles, so a chunk of bounded edges of circle and point sites is handed only those (the union of
discs of :mod:`runtime.voronoi.reach`'s kind, as the local insertion proof uses: each vertex's
disc widened by a few vertex tolerances, and one disc per edge that holds the empty circle of
every point within the edge's tolerance of its polyline, :meth:`_Reach._edge_discs`).  When the
chunk's proofs succeed,
each true empty circle of a vertex lies in its disc (when the vertex's proof box is coarse next to
the tolerance, the chunk returns the radius that holds it,
:func:`runtime.voronoi.verify.vertices.local_reach`, and the vertex counts as proved only if no
site left out of the chunk comes that close; otherwise the edges at such vertices are proved once
more as one chunk handed also every site within those radii, whose own radii are checked the same
way) and each true arc within its tolerance
of its polyline (what the verifier proves), so every empty circle lies in those discs and a site
left out cannot enter one: the proofs hold for all the sites.  The chunk of unbounded edges keeps
every site (its accounting at infinity and disjointness test read them all), and takes the bounded
edges with a vertex whose empty circle is wider than a twentieth of the sites' span (near the hull,
where the empty circles hold most sites anyway); all chunks keep every site when a site is a
conic.  A chunk's set-up is then the size of the chunk, not of the diagram.

Two reported vertices with the same sites close enough to be one vertex reported twice (within
the sum of their proof radii, :func:`_duplicates`) also refuse it: the closure does not see a duplicate, and the verifier's overlap check of edges of one pair runs in one chunk only.

A refusal is not a disproof: the caller then runs the verifier on the whole diagram, whose
problems name what to rebuild.

Public API: :func:`chunked_verify`, :class:`ChunkedCertificate`.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

__all__ = ["chunked_verify", "ChunkedCertificate"]


@dataclass
class ChunkedCertificate:
    """``ok`` when every vertex and edge is proved in its chunk, the closure holds and the
    accounting at infinity is proved; ``problems`` says what refused it; ``vertices`` and ``edges``
    are the flags in diagram order; ``seconds`` the wall time of the chunks and of the closure
    and the accounting, and of :func:`_chunk_results`' ``timing`` (the sub-diagrams made here,
    the chunks' CPU seconds on the workers: where the chunks' wall time goes)."""

    ok: bool
    problems: list
    vertices: list
    edges: list
    seconds: dict = field(default_factory=dict)


#: a bounded edge with an end vertex whose empty circle is wider than this fraction of the span of
#: the sites goes to the chunk that keeps every site
FAR = 0.05


class _Reach:
    """The circle and point sites of D as :func:`runtime.voronoi.reach.sites_meeting_discs` reads
    them (centres, radii, a k-d tree), made once per certificate; None-like when a site is
    neither (conics: every chunk then gets every site)."""

    def __init__(self, D):
        from scipy.spatial import cKDTree

        from .conic_geometry import site_geometry

        self.geoms = [site_geometry(s) for s in D.sites]
        self.ok = bool(self.geoms) and all(g.kind in ("point", "circle") for g in self.geoms)
        if not self.ok:
            return
        self.C = np.array([[g.x0, g.y0] if g.kind == "point" else [g.cx, g.cy] for g in self.geoms], float)
        self.R = np.array([0.0 if g.kind == "point" else g.rho for g in self.geoms], float)
        self.rmax = float(self.R.max())
        self.tree = cKDTree(self.C)
        self.slot = np.arange(len(self.R))
        self.extra: list = []

    def sites(self, D, vids, edge_ids):
        """The sites that can enter the empty circle of a vertex ``vids`` or of a point of a bounded
        edge ``edge_ids`` (module docstring), with the sites of those vertices and edges; every
        site when an edge has fewer than two polyline points."""
        from .reach import sites_meeting_discs
        from .verify.vertices import local_default

        own = {s for t in edge_ids for s in D.edges[t].sites} | {s for u in vids for s in D.vertices[u].sites}
        pts, rad = [np.zeros((0, 2))], [np.zeros(0)]
        if vids:
            V = np.array([[D.vertices[u].x, D.vertices[u].y, D.vertices[u].radius] for u in vids], float)
            pts.append(V[:, :2])
            rad.append(np.array([local_default(D.vertices[u]) for u in vids]) * (1 + 1e-9)
                       + 1e-9 * (np.abs(V[:, :2]).sum(axis=1) + 1))
        if edge_ids:
            polys = [np.asarray(D.edges[t].polyline, float).reshape(-1, 2) for t in edge_ids]
            if min(len(P) for P in polys) < 2:
                return list(range(len(self.R)))
            X0, r = self._edge_discs(D, edge_ids, polys)
            pts.append(X0)
            rad.append(r)
        near = sites_meeting_discs(self, np.vstack(pts), np.concatenate(rad))
        return sorted(own.union(near))

    def _edge_discs(self, D, edge_ids, polys):
        """One disc per edge holding the empty circle of every point of its true arc, all edges at
        once: a point q of the arc lies within the tolerance t of a segment of the polyline, so
        within t + ℓ of one of its points P (ℓ the edge's longest segment), and r(q) = d_i(q) ≤
        d_i(P) + t + ℓ (distances are 1-Lipschitz), so the empty circle of q lies in the disc of
        centre X0 (the polyline's first point) and radius max_P (|P − X0| + d_i(P)) + 2(t + ℓ)
        (:func:`runtime.voronoi.reach.polyline_reach`, the local insertion proof's one disc, widened
        for rounding)."""
        from .reach import polyline_reach

        X0 = np.array([P[0] for P in polys])
        i = np.array([D.edges[t].sites[0] for t in edge_ids])
        reach = polyline_reach(polys, self.C[i], self.R[i], [D.edges[t].tolerance for t in edge_ids], X0)
        size = max(float(np.abs(P).sum(axis=1).max()) for P in polys)
        return X0, reach * (1 + 1e-9) + 1e-9 * (size + 1)

    def far_edges(self, D) -> list:
        """The bounded edges with an end vertex whose empty circle is wider than FAR of the span
        of the sites' centres (near the hull: their discs hold most sites, so they go with the
        unbounded edges to the chunk that keeps every site)."""
        if not self.ok or not D.vertices:
            return []
        span = float(np.ptp(self.C, axis=0).max()) if len(self.C) > 1 else 0.0
        wide = np.array([v.radius > FAR * span for v in D.vertices], bool)
        return [e.id for e in D.edges if None not in e.ends and wide[list(e.ends)].any()]

    def meeting(self, P, r) -> list:
        """The sites whose disc comes within r_j of P_j for some j
        (:func:`runtime.voronoi.reach.sites_meeting_discs`)."""
        from .reach import sites_meeting_discs

        return sites_meeting_discs(self, np.asarray(P, float), np.asarray(r, float))


def _sub_diagram(D, edge_ids, keep=None):
    """The edges ``edge_ids`` of D with the vertices they end at, renumbered; and the vertex ids
    back.  ``keep``: the sites to keep (sorted indices, renumbered in that order), default all."""
    from .structure import Diagram, DiagramEdge, DiagramVertex

    vids = sorted({u for t in edge_ids for u in D.edges[t].ends if u is not None})
    new = {u: k for k, u in enumerate(vids)}
    if keep is None:
        sites, snew = list(D.sites), None
    else:
        sites, snew = [D.sites[k] for k in keep], {k: m for m, k in enumerate(keep)}

    def ren(ss):
        return tuple(ss) if snew is None else tuple(snew[s] for s in ss)

    verts = [DiagramVertex(k, ren(D.vertices[u].sites), D.vertices[u].x, D.vertices[u].y, D.vertices[u].radius)
             for k, u in enumerate(vids)]
    edges = [DiagramEdge(k, ren(D.edges[t].sites), tuple(None if u is None else new[u] for u in D.edges[t].ends),
                         D.edges[t].closed, D.edges[t].polyline, D.edges[t].tolerance)
             for k, t in enumerate(edge_ids)]
    return Diagram(sites, verts, edges), vids


def _part(D, ids, hull, reach, extra=()):
    """(sub-diagram, vertex ids, kept sites) of one chunk: the chunk of the unbounded edges
    (``hull``: it runs the accounting at infinity) keeps every site (None); a chunk of bounded
    edges of circle and point sites keeps the sites that can reach it (module docstring), and those
    within the radii of ``extra``, (vertex, radius) pairs."""
    if hull or reach is None or not reach.ok:
        return (*_sub_diagram(D, ids), None)
    vids = sorted({u for t in ids for u in D.edges[t].ends if u is not None})
    keep = reach.sites(D, vids, ids)
    if extra:
        keep = sorted(set(keep).union(reach.meeting([[D.vertices[u].x, D.vertices[u].y] for u, _ in extra],
                                                    [R for _, R in extra])))
    return (*_sub_diagram(D, ids, keep), keep)


def verify_chunk(sub, at_infinity: bool = True) -> tuple[list, list, list, list]:
    """The verifier on one chunk (runs in a worker): vertex flags, edge flags, problem records,
    and [vertex, radius] for the proved vertices whose true empty circles may reach past the
    chunk's sites (:func:`runtime.voronoi.verify.vertices.local_reach`); ``at_infinity``: whether
    it runs the accounting of the unbounded ends."""
    from .verify.certificate import verify
    from .verify.problems import records

    cert = verify(sub, progress=False, at_infinity=at_infinity)
    return ([bool(v) for v in cert.vertices], [bool(e) for e in cert.edges], records(cert.problems),
            list(cert.stats.get("vertex_reach", ())))


def _timed_chunk(sub, at_infinity: bool = True):
    """:func:`verify_chunk` and the CPU seconds it took (on the worker); ``sub`` a sub-diagram or
    its :func:`pack`."""
    t = time.process_time()
    out = verify_chunk(unpack(sub) if isinstance(sub, tuple) else sub, at_infinity)
    return out, time.process_time() - t


def pack(sub) -> tuple:
    """A sub-diagram as a few arrays and lists, for the trip to a worker: Dask ships every numpy
    array of an object as a frame of its own, and a polyline per edge made about 2·10⁵ frames
    per chunk (the driver, not the workers, was then the chunks' long pole).  :func:`unpack`
    rebuilds an equal diagram."""
    polys = [np.asarray(e.polyline, float).reshape(-1, 2) for e in sub.edges]
    off = np.cumsum([0] + [len(P) for P in polys]).astype(np.int64)
    V = [(tuple(v.sites), v.x, v.y, v.radius) for v in sub.vertices]
    E = [(tuple(e.sites), tuple(e.ends), e.closed, e.tolerance) for e in sub.edges]
    return list(sub.sites), V, E, np.concatenate(polys) if polys else np.zeros((0, 2)), off


def unpack(packed):
    """The sub-diagram of :func:`pack`."""
    from .structure import Diagram, DiagramEdge, DiagramVertex

    sites, V, E, P, off = packed
    verts = [DiagramVertex(k, ss, x, y, r) for k, (ss, x, y, r) in enumerate(V)]
    edges = [DiagramEdge(k, ss, ends, closed, P[off[k]:off[k + 1]], tol) for k, (ss, ends, closed, tol) in enumerate(E)]
    return Diagram(sites, verts, edges)


def _chunk_results(D, parts, client, reach=None, timing=None):
    """(edge ids, vertex ids, :func:`verify_chunk` result) of each chunk: on the workers as they
    finish, or here one at a time (each sub-diagram made just before its run).  ``timing``
    (a dict) gathers the seconds spent here making the sub-diagrams (``parts``), and the CPU
    seconds of the chunks' runs, their sum and largest (``runs``, ``longest run``)."""
    timing = {} if timing is None else timing
    for k in ("parts", "runs", "longest run"):
        timing.setdefault(k, 0.0)

    def made(ids, hull):
        t = time.perf_counter()
        out = _part(D, ids, hull, reach)
        timing["parts"] += time.perf_counter() - t
        return out

    def ran(res):
        out, sec = res
        timing["runs"] += sec
        timing["longest run"] = max(timing["longest run"], sec)
        return out

    if client is None:
        for ids, hull in parts:
            sub, vids, keep = made(ids, hull)
            yield ids, vids, keep, ran(_timed_chunk(sub, hull))
        return
    from distributed import as_completed

    # at most two chunks per worker in flight: the driver holds (and the scheduler keeps) only
    # the sub-diagrams being proved, not all of them at once
    todo = list(parts)
    width = 2 * max(1, len(client.scheduler_info().get("workers", {})))
    futures: dict = {}

    def submit():
        ids, hull = todo.pop(0)
        sub, vids, keep = made(ids, hull)
        fut = client.submit(_timed_chunk, pack(sub), hull, pure=False)
        futures[fut] = (ids, vids, keep)
        return fut

    pending = as_completed([submit() for _ in range(min(width, len(todo)))])
    for fut in pending:
        ids, vids, keep = futures.pop(fut)
        result = ran(fut.result())
        fut.release()
        if todo:
            pending.add(submit())
        yield ids, vids, keep, result


def _expected_in_part(rec) -> bool:
    """A closure line that a sub-diagram fails by construction (module docstring)."""
    msg = rec.get("message", "")
    return ((rec.get("kind") == "vertex" and msg.rstrip().endswith("here"))
            or (rec.get("kind") == "site" and "has no edge" in msg))


def _record(D, reach, ids, vids, keep, result, vflag, eflag, unexpected, wider, radii) -> None:
    """Enter one chunk's :func:`verify_chunk` result: its proved vertices and edges into ``vflag``,
    ``eflag``; its lines beyond the expected closure lines into ``unexpected``.  A vertex proved in a
    coarse box whose radius (:func:`runtime.voronoi.verify.vertices.local_reach`) reaches a site
    left out of the chunk stays unproved here and goes to ``wider`` as (vertex, radius); when the
    chunk kept every site (``keep`` None) the radius reaches nothing left out.  ``radii``: the
    largest such radius of each vertex (for :func:`_duplicates`)."""
    vok, eok, recs, far = result
    vok = list(vok)
    for m, R in far:
        radii[vids[m]] = max(R, radii.get(vids[m], 0.0))
    if keep is not None and far:
        kept = set(keep)
        if set(reach.meeting([[D.vertices[vids[m]].x, D.vertices[vids[m]].y] for m, _ in far],
                             [R for _, R in far])) - kept:
            for m, R in far:    # vertex by vertex, to find the ones that reach past the chunk
                v = D.vertices[vids[m]]
                if any(k not in kept for k in reach.meeting([[v.x, v.y]], [R])):
                    vok[m] = False
                    wider.append((vids[m], R))
    vflag[np.asarray(vids, dtype=np.int64)[np.asarray(vok, bool)]] = True
    eflag[np.asarray(ids, dtype=np.int64)[np.asarray(eok, bool)]] = True
    unexpected.extend(r["message"] for r in recs if not _expected_in_part(r))


def _duplicates(D, radii) -> list:
    """Problems for two reported vertices with the same sites that may be one vertex reported
    twice.  A proved vertex v lies within tol + (2 + √2)·h of its true vertex, at most half of
    s_v = R_v − r_v, R_v its radius (:func:`runtime.voronoi.verify.vertices.local_reach`: a
    chunk lists it in ``radii`` where it exceeds :func:`runtime.voronoi.verify.vertices.local_default`,
    which bounds it otherwise); two reports of one true vertex are then within (s_u + s_v)/2, and
    any pair within s_u + s_v refuses.  (Distinct vertices of one triple can be close: a fixed
    fraction of the scene refused 2·10⁵ random circles, whose far vertices make that fraction 0.3.)"""
    from .verify.vertices import local_default

    out: list = []
    seen: dict = {}
    for v in D.vertices:
        s_v = radii.get(v.id, local_default(v)) - v.radius
        for (x, y, s_u) in seen.get(frozenset(v.sites), ()):
            if math.hypot(x - v.x, y - v.y) <= (s_u + s_v) * (1 + 1e-9):
                out.append(f"vertex of sites {tuple(v.sites)} near ({v.x:.6g}, {v.y:.6g}) reported twice")
        seen.setdefault(frozenset(v.sites), []).append((v.x, v.y, s_v))
    return out


def chunked_verify(D, chunks, client=None) -> ChunkedCertificate:
    """Prove D (module docstring): ``chunks`` is a list of lists of edge indices covering every
    edge; one verifier task per chunk on ``client``'s workers, or, with no client, the chunks
    here one after the other (the verifier's memory is then one chunk's, not the diagram's)."""
    from .verify.closure import verify_closure

    t0 = time.perf_counter()
    problems: list = []
    vflag = np.zeros(len(D.vertices), bool)
    eflag = np.zeros(len(D.edges), bool)
    reach = _Reach(D)
    unbounded = [e.id for e in D.edges if None in e.ends]
    unbounded += reach.far_edges(D) if unbounded else []
    # the chunk of the unbounded edges (and of the edges near the hull, whose empty circles reach
    # most sites) first: it runs the accounting at infinity; then the bounded edges of each chunk
    parts = [(unbounded, True)] if unbounded else []
    parts += [(p, False) for p in (sorted(set(ids) - set(unbounded)) for ids in chunks) if p]
    if not unbounded:             # no end at infinity reported: one chunk still runs the accounting
        parts = [(ids, k == 0) for k, (ids, _) in enumerate(parts)] or [([], True)]
    unexpected: list = []
    wider: list = []              # (vertex, radius): coarse vertices whose radius reaches past their chunk
    radii: dict = {}              # vertex: the largest local_reach radius a chunk listed
    timing: dict = {}
    for ids, vids, keep, result in _chunk_results(D, parts, client, reach, timing):
        _record(D, reach, ids, vids, keep, result, vflag, eflag, unexpected, wider, radii)
    if wider:
        # once more with every site within those radii: the edges at those vertices as one chunk
        vset = {u for u, _ in wider}
        ids = sorted({e.id for e in D.edges if any(u in vset for u in e.ends if u is not None)})
        sub, vids, keep = _part(D, ids, False, reach, extra=wider)
        again: list = []
        _record(D, reach, ids, vids, keep, verify_chunk(sub, False), vflag, eflag, unexpected, again, radii)
        unexpected.extend(f"vertex {u}: its proof box's radius {R:.6g} reaches past the sites handed to it "
                          "(twice: its chunk's, then every site within its first radius)" for u, R in again)
    t1 = time.perf_counter()
    if not vflag.all():
        problems.append(f"{int((~vflag).sum())} vertices not proved in their chunks")
    if not eflag.all():
        problems.append(f"{int((~eflag).sum())} edges not proved in their chunks")
    # the chunk of the unbounded edges runs the accounting at infinity on all the ends of D; any
    # line a chunk writes beyond its expected closure lines refuses
    problems.extend(f"in a chunk: {m}" for m in dict.fromkeys(unexpected))
    closure: list = []
    if not verify_closure(D, len(D.sites), closure, {}):
        problems.extend(closure or ["closure not proved"])
    problems.extend(_duplicates(D, radii))
    t2 = time.perf_counter()
    ok = not problems
    return ChunkedCertificate(ok, problems, vflag.tolist(), eflag.tolist(),
                              {"chunks": t1 - t0, "closure": t2 - t1, **timing})
