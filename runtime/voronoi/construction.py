"""The Voronoi diagram of many sites, built output-sensitively by *sample-then-refine*.

Thesis §1.2 (Prop. 1.2.1) and §5.1–5.2 define the diagram: a vertex is the centre of a circle
touching k ≥ 3 sites and empty of all sites; an edge is an arc of points with exactly two
nearest sites.  Here the *combinatorics* come from a cheap, robust approximation and only the
*local* certified predicates are run, once per output vertex (the thesis' incremental insertion
re-tests every vertex: O(n) heavy work per site):

1. **Sites** (:mod:`runtime.voronoi.site_input`): intersecting or repeated sites are rejected
   with an error naming the pair.
2. **Sampling** (:mod:`runtime.voronoi.sampling`): every site is sampled with a spacing set by
   its size and its gap to the other sites.
3. **Sample Delaunay triangulation** (:mod:`runtime.voronoi.sample_delaunay`, qhull), every
   sample labelled with its site; 3-label triangles are candidate vertices, walks across the
   bichromatic sides give the edges (:mod:`runtime.voronoi.sample_walks`, vectorised).
4. **Vertices**: circles and points by vectorised Newton + float Krawczyk proofs
   (:mod:`runtime.voronoi.apollonius_vertices`), triples with a conic by
   :mod:`runtime.voronoi.conic_vertices`; emptiness by rigorous distance bounds
   (:mod:`runtime.voronoi.vertex_emptiness`); sites found exactly on a vertex's circle make it
   a vertex of degree k (:mod:`runtime.voronoi.cocircular`); nearly co-circular circles are
   resolved exactly (:mod:`runtime.voronoi.near_degenerate`).
5. **Edges** (:mod:`runtime.voronoi.edge_polylines`): walk circumcentres projected onto the
   bisectors, with a measured tolerance.
6. **Refine.**  A 3-label triangle whose triple has no proved, empty vertex near it, a vertex
   without exactly one incident edge per consecutive pair of its sites, a walk that cannot be
   closed, or two bounded sites consecutive on the convex hull of the sites without an unbounded
   edge between them (:func:`runtime.voronoi.sampling.hull_neighbours`; a coarse sample of a third
   site can stick out between theirs), makes the spacing of the sites involved shrink (to √(2rδ) when a site enters a
   circle of radius r by δ — samples s apart misplace distances by about s²/8r — else by half).
   The next round does not redo the triangulation: the old samples of the refined sites are
   removed and the new ones inserted by a batch Bowyer–Watson update on the *conflict region*
   only (:meth:`runtime.voronoi.sample_delaunay.SampleTriangulation.update`), and only the
   candidates of new triangles are refined again.  With ``certify=True`` the verifier's
   problems that name sites refine those sites four times and rebuild (3 times at most).
   Whatever stays unproved is listed in ``problems`` and the diagram is ``certified=False``.

Why not CGAL-style incremental insertion: this needs only the two certified predicates every
site kind has (vertex existence, emptiness), no edge-interior conflict predicate for curved
bisectors, and its heavy work is vectorised; completeness is the verifier's argument.

Length: the rounds of sample-then-refine and their bookkeeping (the statistics, the refinement
of the sites a round or the verifier names, the rebuild) are one loop over shared state, kept
together here: just over 400 lines.

Public API: :func:`voronoi`, :func:`as_site`, :func:`check_disjoint`, :func:`sites_equal`,
:class:`SiteError`.
"""
from __future__ import annotations

import math
import time

import numpy as np

from ..threads import one_blas_thread, without_cyclic_gc
from .apollonius_vertices import apollonius_vertices
from .cocircular import assemble_vertices, consecutive_pairs, contact_order_triples
from .collinear_points import collinear, collinear_points_diagram
from .conic_geometry import site_geometry
from .conic_vertices import conic_vertices
from .deletion import delete_site
from .edge_polylines import edge_polylines
from .equal_circles import equal_circles_diagram
from .frame import local_frame
from .insertion import insert_site
from .near_degenerate import near_degenerate_clusters
from .sampling import Samples, hull_neighbours, initial_spacing, release_free_memory
from .site_arrays import SiteArrays
from .site_input import SiteError, as_site, check_disjoint, sites_equal
from .structure import Diagram, DiagramVertex
from .vertex_emptiness import prove_empty

__all__ = ["voronoi", "build_diagram", "ConstructionState", "as_site", "check_disjoint", "SiteError",
           "sites_equal"]


class ConstructionState:
    """What :func:`runtime.voronoi.deletion.delete_site` needs: site arrays, samples, conic vertex
    cache, the entry points ``build`` (:func:`build_diagram`) and ``scratch`` (:func:`voronoi`), so
    that it imports nothing of this module, and ``delete`` and ``insert``
    (:func:`runtime.voronoi.insertion.insert_site`) for the diagram.  Not serialised."""

    def __init__(self, S, samples, cache):
        self.S, self.samples, self.cache = S, samples, cache
        self.build, self.scratch, self.delete, self.insert = build_diagram, voronoi, delete_site, insert_site

MAX_ROUNDS = 8
#: rebuilds driven by the verifier's problems (sites it names are sampled 4x finer)
VERIFY_ROUNDS = 3



@one_blas_thread
@without_cyclic_gc
def voronoi(sites, *, certify: bool = True, progress=None, time_limit: float | None = None) -> Diagram:
    """The Voronoi diagram of ``sites`` (thesis §1.2, §5.1–5.2), built by sample-then-refine.

    Parameters
    ----------
    sites : list
        :class:`runtime.sites.circle.Circle`, :class:`runtime.sites.circle.Point`,
        :class:`runtime.sites.conic.Conic` or (cx, cy, r) tuples (r = 0: a point); pairwise disjoint.
    certify : bool
        Run the independent verifier (:func:`runtime.voronoi.verify.certificate.verify`) at the end;
        ``diagram.certified`` is its verdict.  Without it the diagram is never certified.
    progress : bool or None
        Show a progress bar (tqdm) over the rounds; None: only for more than 2000 sites.
    time_limit : float or None
        Seconds; when exceeded, the current (partial) diagram is returned, ``certified=False``.

    Returns
    -------
    Diagram
        Vertices (k ≥ 3 sites each) are ``certified`` when existence and emptiness were proved.
        Edge polylines join the end vertices through points projected onto the bisector;
        ``tolerance`` is measured, not proved; the edges' proof is the verifier's.

    Examples
    --------
    >>> import curvedvoronoi as cv
    >>> d = cv.voronoi([(0, 0, 1), (4, 0, 1), (2, 4, 1)], certify=False)
    >>> len(d.vertices), d.delaunay_edges()
    (1, [(0, 1), (0, 2), (1, 2)])
    """
    t_start = time.perf_counter()
    deadline = None if time_limit is None else t_start + float(time_limit)
    sites = list(sites)
    if any(type(s).__name__ in ("Segment", "Arc", "EllipticArc") for s in sites):    # points, segments, arcs: §2.2
        from ..segments.construction import segment_voronoi
        return segment_voronoi(sites, certify=certify, progress=progress)
    sites = [as_site(s) for s in sites]
    if len(sites) < 2:
        raise ValueError(f"the Voronoi diagram needs at least 2 sites, got {len(sites)}")
    geoms = [site_geometry(s) for s in sites]
    frame, local = local_frame(sites, geoms)     # far sites: built at the origin
    if frame is not None:
        return frame.to_global(voronoi(local, certify=certify, progress=progress, time_limit=time_limit), sites)
    check_disjoint(sites, geoms)
    notes: list[str] = []
    S = SiteArrays(sites, geoms)
    stats: dict = {"sites": len(sites), "rounds": 0, "samples": 0}
    if S.all_circles and not S.R.any() and collinear(S.C):
        return collinear_points_diagram(S, sites, notes, certify, stats, t_start)
    timing = {"input": time.perf_counter() - t_start}
    samples = Samples(S, initial_spacing(S))
    D = build_diagram(S, samples, {}, notes, stats, timing, certify=certify, progress=progress,
                      deadline=deadline, time_limit=time_limit, t_start=t_start)
    if certify and not D.certified and (deadline is None or time.perf_counter() < deadline):
        # equal circles not certified: their diagram is their centres' (exact triangulation)
        E = equal_circles_diagram(sites, voronoi, progress=progress,
                                  time_limit=None if deadline is None else deadline - time.perf_counter())
        if E is not None and E.certified:
            return E
    return D


@without_cyclic_gc
def build_diagram(S: SiteArrays, samples: Samples, cache: dict, notes, stats, timing, *, certify=True,
                  progress=None, deadline=None, time_limit=None, t_start=None, edge_filter=None) -> Diagram:
    """The rounds of :func:`voronoi` from a sampling state (``samples``, whose triangulation may
    already exist, e.g. after a deletion): refinement rounds, edges, verification.  The diagram
    keeps the state in ``construction`` for :func:`runtime.voronoi.deletion.delete_site`.
    ``edge_filter(vertices, edges_raw)``, with ``certify=False``: the raw edges (pair, start,
    chain, end, ends) whose polylines are wanted, the others dropped (a local update splices only
    the edges at its new vertices, :mod:`runtime.voronoi.insertion`)."""
    sites = S.sites
    if t_start is None:
        t_start = time.perf_counter()
    if progress is None:
        progress = len(sites) > 2000
    bar = None
    if progress:
        try:
            from tqdm import tqdm
            bar = tqdm(desc="voronoi rounds", unit="round", leave=False)
        except ImportError:
            bar = None
    result = None
    interrupted = False
    try:
        verify = None
        if certify:
            try:
                from .verify.certificate import verify
            except ImportError:
                verify = None
        for vround in range(VERIFY_ROUNDS):
            result = _rounds(S, samples, stats, timing, deadline, cache, bar)
            D = result["diagram"]
            t0 = time.perf_counter()
            if result.get("timed_out"):          # past the limit: the vertices only, marked partial
                break
            release_free_memory()
            raw = result["edges_raw"]
            if edge_filter is not None and not certify:
                raw = edge_filter(D.vertices, raw)
            D.edges = edge_polylines(S, result["tri"], D.vertices, raw)
            result["edges_raw"] = None        # the walks' lists are freed: the verifier starts lower
            release_free_memory()
            timing["edges"] = timing.get("edges", 0) + time.perf_counter() - t0
            if not certify or verify is None or result.get("timed_out") or D.problems:
                break
            t0 = time.perf_counter()
            cert = verify(D, sites, deadline=deadline, progress=progress)
            release_free_memory()
            timing["verify"] = timing.get("verify", 0) + time.perf_counter() - t0
            result["certificate"] = cert
            from .verify.problems import faulted_sites
            named = faulted_sites(cert.problems, D) if not cert.ok else set()
            if cert.ok or not named or (deadline is not None and time.perf_counter() > deadline):
                break
            # the verifier found what the sampling missed: refine the sites it names and rebuild
            stats["verify_refinements"] = stats.get("verify_refinements", 0) + 1
            idx = np.array(sorted(named), dtype=int)
            samples.refine(idx, samples.spacing[idx] / 4)
    except KeyboardInterrupt:
        if result is None or "diagram" not in result:
            raise
        interrupted = True
    finally:
        if bar is not None:
            bar.close()
    D = result["diagram"]
    if interrupted and not D.edges and result.get("edges_raw"):
        D.edges = edge_polylines(S, result["tri"], D.vertices, result["edges_raw"])
    D.problems[:0] = notes
    D.stats.update(stats)
    if result.get("timed_out"):
        D.problems.append(f"time limit of {time_limit} s reached: partial diagram")
    if interrupted:
        D.problems.append("interrupted (Ctrl-C): partial diagram of the last finished round")
    cert = result.get("certificate")
    if not certify:
        D.problems.append("not verified (certify=False)")
    elif verify is None:
        D.problems.append("verifier runtime.voronoi.verify.certificate not available: edges not proved")
    elif cert is not None and not interrupted:
        vertices_ok = all(v.certified for v in D.vertices)
        D.certified = bool(cert.ok) and vertices_ok and not D.problems
        D.problems.extend(cert.problems)
        for e, ok in zip(D.edges, cert.edges):
            e.certified = bool(ok)
        for v, ok in zip(D.vertices, cert.vertices):
            v.certified = v.certified and bool(ok)
    elif not D.problems:
        D.problems.append("not verified")
    timing["total"] = time.perf_counter() - t_start
    D.stats["seconds"] = {k: round(v, 4) for k, v in timing.items()}
    if samples.tri is not None:
        samples.tri.compact()       # kept for deletions: its derived arrays are made again on use
        release_free_memory()
    D.construction = ConstructionState(S, samples, cache)
    return D


def _rounds(S, samples, stats, timing, deadline, cache, bar):
    """Sample-triangulate-prove rounds until the combinatorics are consistent (or MAX_ROUNDS)."""
    result = None
    for _ in range(MAX_ROUNDS):
        if result is not None and deadline is not None and time.perf_counter() > deadline:
            result["timed_out"] = True      # the refinement would start after the time limit
            break
        stats["rounds"] = stats.get("rounds", 0) + 1
        result = None           # the last round's diagram and walks are not needed by the next
        result, refine = _build_once(S, samples, stats, timing, deadline, cache)
        if bar is not None:
            bar.update(1)
        if not refine or result.get("timed_out"):
            break
        idx = np.array(sorted(refine), dtype=int)
        cap = np.array([refine[i] for i in idx.tolist()])
        samples.refine(idx, np.minimum(samples.spacing[idx] / 2, cap))
    t0 = time.perf_counter()
    _contact_ordered(S, result["diagram"].vertices)     # the kept round's vertices only
    timing["walks"] = timing.get("walks", 0) + time.perf_counter() - t0
    return result


def _contact_ordered(S, vertices):
    """The vertices of three sites listed counter-clockwise like those of degree k (one batch,
    :func:`runtime.voronoi.cocircular.contact_order_triples`), in place."""
    three = [v for v in vertices if len(v.sites) == 3]
    if three:
        ordered = contact_order_triples(S, [[v.x, v.y] for v in three], [v.sites for v in three])
        for v, row in zip(three, ordered.tolist()):
            v.sites = tuple(row)


def _build_once(S: SiteArrays, samples: Samples, stats, timing, deadline, cache):
    """One pass: (updated) sample triangulation, walks, vertices, consistency checks.  Returns
    ({"diagram": D (vertices only), "tri", "edges_raw"}, sites to refine)."""
    t0 = time.perf_counter()
    release_free_memory()
    tri = samples.triangulation(stats)
    release_free_memory()
    stats["samples"] = int(len(tri.P))
    timing["sample+delaunay"] = timing.get("sample+delaunay", 0) + time.perf_counter() - t0
    t1 = time.perf_counter()
    raw = tri.walks()
    tri.walk_list = None        # the walks are ``raw`` (freed with it); the triangulation keeps no copy
    release_free_memory()
    timing["walks"] = timing.get("walks", 0) + time.perf_counter() - t1
    t2 = time.perf_counter()
    threes = np.nonzero(tri.nlab == 3)[0]
    T3 = np.sort(tri.L[threes], axis=1)
    seeds = tri.cc[threes]
    if S.all_circles:
        cid, clusters, tri.seed[threes] = apollonius_vertices(S, T3, seeds, stats, known=tri.seed[threes])
    else:
        cid, clusters = conic_vertices(S, T3, seeds, stats, cache)
    empty, culprit = prove_empty(S, clusters, stats)
    # candidates that a site misses or enters by a relative 1e-7 or less: the local diagram of the
    # sites that close is decided exactly (runtime.voronoi.near_degenerate), not by finer samples
    groups: dict = {}
    n_old = len(clusters)
    if S.all_circles:
        local, groups = near_degenerate_clusters(S, clusters, empty, stats)
        if local:
            e2, c2 = prove_empty(S, local, stats)
            clusters = clusters + local
            empty, culprit = list(empty) + list(e2), list(culprit) + list(c2)
    replaced = {c: g for g, cs in groups.items() for c in cs}
    timing["vertices"] = timing.get("vertices", 0) + time.perf_counter() - t2
    timed_out = deadline is not None and time.perf_counter() > deadline
    t3 = time.perf_counter()
    refine: dict = {}   # site -> spacing cap (inf: halve)
    problems: list[str] = []

    def ask(sites_, cap=np.inf):
        for t in sites_:
            refine[int(t)] = min(refine.get(int(t), np.inf), cap)

    # final vertices: proved, empty clusters (merged into vertices of degree k where the exact test
    # found further sites touching) and the local edges of near-degenerate groups
    usable = [c for c, cl in enumerate(clusters) if cl["ok"] and empty[c] is True]
    usable_set = set(usable)
    vertices, cluster_vid, group_out, local_edges, vgroup = assemble_vertices(
        S, clusters, usable, groups, n_old, problems, DiagramVertex)
    for c, cl in enumerate(clusters):
        tr = cl["triple"]
        if c in usable_set or c in replaced:
            continue
        # a site entering the circle by δ: samples s apart misplace distances near a vertex of
        # radius r by about s²/(8r), so s = √(2 r δ) separates the two configurations
        dp = cl.get("intrusion")
        cap = math.sqrt(2 * max(cl["rlo"], 0.0) * dp) if dp is not None and dp > 0 else np.inf
        ask(tr, cap)
        if culprit[c] is not None:
            ask([culprit[c]], cap)
        if not cl["ok"]:
            problems.append(f"sites {tr[0]}, {tr[1]}, {tr[2]}: candidate vertex near "
                            f"({cl['x']:.6g}, {cl['y']:.6g}) not proved")
        elif empty[c] is False:
            problems.append(f"sites {tr[0]}, {tr[1]}, {tr[2]}: candidate vertex at ({cl['x']:.6g}, "
                            f"{cl['y']:.6g}) is not empty (site {culprit[c]} enters its circle)")
        else:
            problems.append(f"sites {tr[0]}, {tr[1]}, {tr[2]}: emptiness of the vertex at "
                            f"({cl['x']:.6g}, {cl['y']:.6g}) undecided (site {culprit[c]})")
    cvid = np.full(len(clusters) + 1, -1, dtype=np.int64)
    for c, vid in cluster_vid.items():
        cvid[c] = vid
    for c, g in replaced.items():
        cvid[c] = -2 - g         # a triangle of a near-degenerate group: its vertex depends on the pair
    ttv = np.full(len(tri.nlab), -1, dtype=np.int64)
    ttv[threes] = cvid[np.asarray(cid, dtype=np.int64)]
    # the candidates are not read below: freed before the edges (the round's peak is after them)
    del clusters, empty, culprit, cid, cvid
    # edges
    edges_raw = []
    degree = [[] for _ in vertices]
    for pair, start, chain, end in raw:
        if (start is not None and start[0] == "bad") or (end is not None and end[0] == "bad"):
            ask(pair)
            problems.append(f"sites {pair[0]}, {pair[1]}: an edge walk could not be closed")
            continue
        ends = []
        okv = True
        codes = []
        for e in (start, end):
            if e is None or e[0] == "hull":
                ends.append(None)
            else:
                v = int(ttv[e[1]])
                codes.append(-2 - vgroup[v] if v in vgroup else v)
                if v <= -2:
                    v = group_out.get(-2 - v, {}).get(tuple(pair), -1)
                if v < 0:
                    okv = False
                ends.append(v)
        if len(codes) == 2 and codes[0] == codes[1] and codes[0] <= -2:
            continue   # inside one near-degenerate group: its local edges are added below
        if not okv:
            ask(pair)
            continue
        if ends[0] is not None and ends[0] == ends[1]:
            continue   # between two triangles of one vertex
        for v in ends:
            if v is not None:
                degree[v].append(pair)
        edges_raw.append((pair, start, chain, end, ends))
    for pr, (va, vb) in local_edges:
        degree[va].append(pr)
        degree[vb].append(pr)
        edges_raw.append((pr, ("local", -1), [], ("local", -1), [va, vb]))
    for v in vertices:
        want = sorted(consecutive_pairs(v.sites))
        if sorted(degree[v.id]) != want:
            ask(v.sites)
            problems.append(f"sites {', '.join(map(str, v.sites))}: the vertex at ({v.x:.6g}, {v.y:.6g}) has "
                            f"incident edges {sorted(degree[v.id])}, expected "
                            f"{', '.join(f'({a}, {b})' for a, b in want)}")
    # sites consecutive on the convex hull of the sites have an unbounded edge; a coarse sample of a
    # third site can hide it (its samples stick out between theirs): refine both
    if S.bounded.all():
        ht, _ = np.nonzero(tri.nb == -1)
        unbounded = {pair for pair, start, _, end in raw if (start and start[0] == "hull") or (end and end[0] == "hull")}
        for a, b in sorted(hull_neighbours(S, np.unique(tri.L[ht])) - unbounded):
            ask((a, b))
            problems.append(f"sites {a}, {b}: consecutive on the convex hull of the sites, but no unbounded edge "
                            "between them was found")
    timing["walks"] += time.perf_counter() - t3
    stats["candidate_triangles"] = int(len(threes))
    D = Diagram(S.sites, vertices, [], False, problems, {})
    return {"diagram": D, "timed_out": timed_out, "tri": tri, "edges_raw": edges_raw}, \
        ({} if timed_out else refine)

