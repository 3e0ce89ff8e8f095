"""The Voronoi diagram of points and segments, built by sample-then-refine (thesis §1.2, §2.2).

The combinatorics come from the Delaunay triangulation of labelled samples (every point site,
and points spaced along each open segment; :class:`runtime.voronoi.sample_delaunay.
SampleTriangulation`): a triangle with three labels is a candidate vertex, chains of two-label
triangles are the edges.  Each candidate is then decided by the certified predicates of the
elementary sites:

1. **Vertices** (:func:`runtime.segments.vertices.prove_vertex`): Newton and Krawczyk on the
   3 × 3 contact system; a corner of the input (three sites whose closures share a point c) is
   the vertex c of radius 0, with every segment ending at c.
2. **Emptiness** (:mod:`runtime.segments.emptiness`): every other site strictly farther than the
   radius, by rigorous distance balls; sites found exactly on the circle make a vertex of
   degree k > 3 (decided exactly).
3. **Edges**: walks between vertices (or to infinity), drawn along the closed-form bisectors
   (:mod:`runtime.segments.bisectors`).
4. **Refine**: a candidate that is not a proved empty vertex, a vertex without one edge per
   consecutive pair of its sites, or a walk that cannot be closed halves the sample spacing of
   the sites involved, and the round is repeated: the sample triangulation is updated where
   samples changed, and the proofs of earlier rounds are kept.

The certificate is :func:`runtime.segments.certificate.verify_segments` (independent of this
module); ``certified`` is its verdict.

Length: one round's steps (candidate vertices, proofs, emptiness, walks, degree checks and the
refinement they ask for) read and write the same per-round tables (triangle → vertex, proof →
vertex, the caches kept across rounds); split apart they would pass all of them around.

Public API: :func:`segment_voronoi`, :func:`has_segments`.
"""
from __future__ import annotations

import math
import time

import numpy as np
from scipy.spatial import cKDTree

from ..predicates.circles import Point
from ..sites.arc import Arc, circle_halves
from ..sites.rationals import to_fraction
from ..sites.segment import Segment, as_point_pair
from ..threads import one_blas_thread, without_cyclic_gc
from ..voronoi.site_input import SiteError
from ..voronoi.structure import Diagram, DiagramVertex
from .contact_order import contact_order, corner_order
from .crossings import check_pieces, renamed
from .edges import edge_polylines
from .elementary import ARC, POINT, ElementarySites, decompose
from .emptiness import empty_by_filter, prove_empty
from .exact import contacts_valid
from .sampling import flat, initial_spacing, nearest_point, retriangulation, samples, triangulation
from .walk_checks import far_ends, long_side
from .newton import prove_vertices
from .near_degenerate import splice_clusters
from .parallel_rays import parallel_ray_triangles
from .vertices import common_point

__all__ = ["segment_voronoi", "has_segments"]

MAX_ROUNDS = 10
#: initial sample spacing of a segment: its gap to the nearest non-adjacent site divided by this
SPACING_PER_GAP = 4.0


def has_segments(sites) -> bool:
    """True when ``sites`` holds a :class:`runtime.sites.segment.Segment` or an arc."""
    return any(isinstance(s, (Segment, Arc)) for s in sites)


@one_blas_thread
def segment_voronoi(pieces, sources=None, *, certify: bool = True, tolerance: float | None = None,
                    progress=None) -> Diagram:
    """The Voronoi diagram of points and segments (``Segment``, ``Point`` or (x, y) pieces).

    The diagram's ``sites`` are the elementary sites (:mod:`runtime.segments.elementary`): point
    sites first, then the open interiors of the segments; ``sources`` maps them to the input.
    ``tolerance``: the largest deviation of a curved edge's polyline from its parabola (default
    10⁻⁴ of the extent of the input)."""
    t_start = time.perf_counter()
    pieces = list(pieces)
    sources = list(range(len(pieces))) if sources is None else list(sources)
    expanded = [_as_pieces(p, k) for k, p in enumerate(pieces)]
    first = [k for k, got in enumerate(expanded) for _ in got]      # piece -> input site
    pieces = [q for got in expanded for q in got]
    sources = [src for src, got in zip(sources, expanded) for _ in got]
    try:
        check_pieces(pieces)
    except SiteError as exc:
        if len(first) == len(expanded):
            raise
        # circles became two pieces each: name the input's sites
        raise SiteError(renamed(str(exc), lambda k: f"site {first[k]}")) from None
    E = decompose(pieces, sources)
    if len(E) < 2:
        raise ValueError(f"the Voronoi diagram needs at least 2 sites, got {len(E)}")
    _check_junctions(E)
    lo = np.minimum(E.A.min(axis=0), E.B.min(axis=0))
    hi = np.maximum(E.A.max(axis=0), E.B.max(axis=0))
    if (E.kind == ARC).any():
        arcs = E.kind == ARC
        lo = np.minimum(lo, (E.C[arcs] - E.rho[arcs][:, None]).min(axis=0))
        hi = np.maximum(hi, (E.C[arcs] + E.rho[arcs][:, None]).max(axis=0))
    extent = float(np.max(hi - lo)) or 1.0
    if tolerance is None:
        tolerance = 1e-4 * extent
    spacing = initial_spacing(E)
    stats: dict = {"sites": len(E), "points": E.n_points, "segments": len(E) - E.n_points, "rounds": 0}
    caches: dict = {"proofs": {}, "verdicts": {}}
    vertices, walks, problems, edges = without_cyclic_gc(_rounds)(E, spacing, stats, caches, tolerance, lo, hi)
    D = Diagram(E.sites, vertices, edges, False, problems, stats)
    D.sources = list(E.source)
    D.elementary = E
    if not certify:
        D.problems.append("not verified (certify=False)")
    else:
        try:
            from .certificate import verify_segments
        except ImportError:
            verify_segments = None
        if verify_segments is None:
            D.problems.append("the certificate of segment diagrams is not available: edges not proved")
        else:
            t0 = time.perf_counter()
            cert = verify_segments(D)
            stats["verify_seconds"] = round(time.perf_counter() - t0, 4)
            D.certified = bool(cert.ok) and not problems
            D.problems.extend(cert.problems)
            for e, ok in zip(D.edges, cert.edges):
                e.certified = bool(ok)
            for v, ok in zip(D.vertices, cert.vertices):
                v.certified = v.certified and bool(ok)
    stats["seconds"] = round(time.perf_counter() - t_start, 4)
    return D


def _rounds(E: ElementarySites, spacing, stats, caches, tolerance, lo, hi):
    """Sample, triangulate, prove and refine until a round is consistent (or stalls): the
    vertices, walks, problems and edge polylines of the last round."""
    history: list = []
    for _ in range(MAX_ROUNDS):
        stats["rounds"] += 1
        t0 = time.process_time()
        result = None                  # the previous round's tables are not needed any more
        result, refine = _build_once(E, spacing, stats, caches)
        if not refine:
            refine = far_ends(E, result, tolerance, lo, hi, caches)
        stats.setdefault("round_cpu_seconds", []).append(round(time.process_time() - t0, 3))
        history.append(result[2])
        if not refine or (len(history) >= 3 and history[-1] == history[-2] == history[-3]):
            break            # consistent, or two refinements changed nothing
        idx = np.array(sorted(refine), dtype=int)
        cap = np.array([refine[i] for i in idx.tolist()])
        spacing[idx] = np.minimum(spacing[idx] / 2, cap)
    vertices, walks, problems = result
    edges = edge_polylines(E, vertices, walks, tolerance, lo, hi)
    return vertices, walks, problems, edges


def _as_pieces(p, k) -> list:
    """The pieces of input site k: a Segment, Arc or Point itself; an (x, y) pair a Point; a circle
    of rational radius (a Circle, or an (x, y, r) triple with r > 0) its two half arcs
    (:func:`runtime.sites.arc.circle_halves`); other conics are refused."""
    if isinstance(p, (Segment, Arc)) or (isinstance(p, Point) and p.r2 == 0):
        return [p]
    if hasattr(p, "r2"):
        return circle_halves((p.cx, p.cy), p.r2, getattr(p, "label", None), what=f"site {k}")
    if hasattr(p, "coefficients"):
        raise SiteError(f"site {k}: {p!r}: conics other than circles cannot be mixed with segments yet "
                        "(points, segments, circular arcs and circles of rational radius)")
    if isinstance(p, (tuple, list)) and len(p) == 3:
        r = to_fraction(p[2], f"site {k} radius")
        if r < 0:
            raise SiteError(f"site {k}: radius {p[2]!r} is negative")
        if r > 0:
            return circle_halves((p[0], p[1]), r * r, what=f"site {k}")
        p = p[:2]
    x, y = as_point_pair(p, f"site {k}")
    return [Point(x, y)]


def _check_junctions(E: ElementarySites) -> None:
    """A point where three or more segments meet, two of them straight through, makes a ray of
    points equidistant from three sites: refused with the point named."""
    for p, segs in enumerate(E.incident):
        if len(segs) < 3:
            continue
        px, py = E.xy[p]
        dirs = []
        for s in segs:           # exact tangent directions leaving p
            if E.kind[s] == ARC:
                (cx, cy), _rho = E.arc[s]
                rx, ry = px - cx, py - cy
                dirs.append((-ry, rx) if int(E.ends[s, 0]) == p else (ry, -rx))
            else:
                o = int(E.ends[s, 1]) if int(E.ends[s, 0]) == p else int(E.ends[s, 0])
                dirs.append((E.xy[o][0] - px, E.xy[o][1] - py))
        for a in range(len(dirs)):
            for b in range(a + 1, len(dirs)):
                (ux, uy), (vx, vy) = dirs[a], dirs[b]
                if ux * vy - uy * vx == 0 and ux * vx + uy * vy < 0:
                    raise SiteError(f"point ({px}, {py}): sites {segs[a]} and {segs[b]} continue each other "
                                    f"straight (or smoothly) through a junction of {len(segs)} pieces; split the "
                                    "junction or merge the pair")


# ------------------------------------------------------------------------------------ one round
def _build_once(E: ElementarySites, spacing, stats, caches):
    """Triangulate the samples, prove the candidate vertices, check the walks.
    Returns ((vertices, walks, problems), {site: refine}) with walks mapped to vertex ids.

    Rounds are local: the triangulation of the previous round is updated where samples changed
    (:func:`runtime.segments.sampling.retriangulation`), and the proofs, emptiness verdicts and
    contact orders of earlier rounds are reused (they do not depend on the samples)."""
    extra = caches.setdefault("extra", {})
    graded = caches.setdefault("graded", {})
    P, lab = samples(E, spacing, extra, ends=graded)
    stats["samples"] = int(len(P))
    ghost = len(E)
    if flat(P):
        # all samples on one line: qhull needs a simplex; a far ring of samples of a virtual
        # site ``ghost`` closes the triangulation, and walks reaching it go to infinity
        c = (P.min(axis=0) + P.max(axis=0)) / 2
        R = 1e3 * (float(np.max(P.max(axis=0) - P.min(axis=0))) + 1.0)
        a = np.linspace(0, 2 * np.pi, 33)[:-1] + 0.1
        P = np.vstack([P, c + R * np.column_stack([np.cos(a), np.sin(a)])])
        lab = np.concatenate([lab, np.full(32, ghost)])
        tri = triangulation(P, lab)
        caches.pop("tri", None)
    else:
        prev = caches.pop("tri", None)
        tri = retriangulation(prev, P, lab) if prev is not None else None
        del prev                       # one triangulation alive at a time
        if tri is None:
            tri = triangulation(P, lab, droppable=lab >= E.n_points)
        else:
            stats["local_rounds"] = stats.get("local_rounds", 0) + 1
        caches["tri"] = tri
    P, lab = tri.P, tri.lab            # an updated triangulation keeps its own sample order
    raw = tri.walks()
    threes = np.nonzero(tri.nlab == 3)[0]
    T3 = np.sort(tri.L[threes], axis=1)
    seeds = tri.cc[threes]
    skip = (T3 == ghost).any(axis=1) | ~np.isfinite(seeds).all(axis=1)
    skip |= parallel_ray_triangles(E, T3, seeds)       # far ends of the perpendiculars at a segment's ends
    fin_spacing = np.where(np.isfinite(spacing), spacing, 0.0)
    reaches = 2 * fin_spacing[np.minimum(T3, len(E) - 1)].max(axis=1)
    tree = cKDTree(P)
    hmax = float(np.max(spacing[np.isfinite(spacing)])) if np.isfinite(spacing).any() else 0.0
    refine = _Refine()
    problems: list[str] = []
    vertices: list[DiagramVertex] = []
    key_to_vid: dict = {}
    tri_vid = {}
    proved_cache = caches["proofs"]     # proofs and emptiness verdicts do not depend on the samples
    verdicts = caches["verdicts"]
    near_cache = caches.setdefault("near", {})
    by_sites: dict = {}
    jobs = []
    corners = E.common_points
    for t, triple, seed, sk, reach in zip(threes.tolist(), T3.tolist(), seeds.tolist(), skip.tolist(),
                                         reaches.tolist()):
        if sk:
            tri_vid[t] = "inf"      # the ghost ring, or a flat hull triangle of collinear samples
            continue
        triple = tuple(triple)
        c = corners[triple] if triple in corners else common_point(E, triple)
        if c is not None:
            key = ("corner", c)
            if key not in key_to_vid:
                key_to_vid[key] = len(vertices)
                x, y = E.xy[c]
                vertices.append(DiagramVertex(len(vertices), corner_order(E, c), float(x), float(y), 0.0, True))
            tri_vid[t] = key_to_vid[key]
            continue
        # a seed near a proved solution of its triple (within twice the triple's sample spacing)
        # takes it without a new Newton run; two vertices of one triple that close make the
        # edge checks fail, and the refinement then separates them
        sol = None
        for prev_sol in near_cache.get(triple, ()):
            if math.hypot(prev_sol.x - seed[0], prev_sol.y - seed[1]) <= reach:
                sol = prev_sol
                break
        jobs.append((t, triple, sol, seed))
    # the zeros not known yet: Newton for all of them together, then one arb proof each
    todo = [k for k, job in enumerate(jobs) if job[2] is None]
    fresh_sols = prove_vertices(E, [(jobs[k][1], jobs[k][3]) for k in todo], cache=proved_cache)
    for k, sol in zip(todo, fresh_sols):
        t, triple, _, seed = jobs[k]
        if sol.status == "undecided" and sol.box is not None and "at an end" in sol.reason:
            # a contact exactly at a curve's end (then that end touches too): decided exactly
            verdict = contacts_valid(E, triple, sol)
            if verdict:
                sol.status, sol.reason = "proved", "contact at an end, exact"
            elif verdict is False:
                sol.status, sol.reason = "invalid", "contact outside a curve, exact"
            else:
                sol.reason = "contact at an end, no closed form"
        if sol.status == "proved":
            near = near_cache.setdefault(triple, [])
            if not any(prev_sol is sol for prev_sol in near):
                near.append(sol)
        jobs[k] = (t, triple, sol, seed)
    # candidates crowded closer than any sample spacing: their local diagram, spliced in
    jobs, splice = splice_clusters(E, jobs, vertices, caches)
    # the float emptiness filter on all new proved zeros at once; the rest one by one below
    fresh = {id(so): (tr, so) for _, tr, so, _ in jobs if so.status == "proved" and id(so) not in verdicts}
    verdicts.update(empty_by_filter(E, tree, lab, hmax, list(fresh.values())))
    orders = caches.setdefault("orders", {})
    sol_vid: dict = {}                  # id(sol) -> its vertex in this round
    for t, triple, sol, _seed in jobs:
        vid = None
        if sol.status == "proved":
            vid = sol_vid.get(id(sol))
            if vid is not None:
                tri_vid[t] = vid
                continue
            if id(sol) not in verdicts:
                verdicts[id(sol)] = prove_empty(E, tree, lab, hmax, triple, sol)
            empty, members, culprit = verdicts[id(sol)]
            if empty:
                vid = sol_vid[id(sol)] = _vertex_id(vertices, by_sites, members, sol, E, orders)
            else:
                refine.update(triple)
                if culprit is not None:
                    # a curve entering the circle passed between its samples: its point nearest
                    # to the vertex becomes a sample (it lies inside the circle), however shallow
                    # the intrusion; the triple's curves are sampled twice as densely
                    if E.kind[culprit] != POINT:
                        f = nearest_point(E, int(culprit), (sol.x, sol.y))
                        if not any(np.allclose(f, E.A[int(culprit)] if k_ == 0 else E.B[int(culprit)], rtol=0, atol=0)
                                   for k_ in (0, 1)):
                            extra.setdefault(int(culprit), []).append(f)
                    refine.update(triple)
                    if empty is None:
                        problems.append(f"sites {', '.join(map(str, triple))}: emptiness of the vertex at "
                                        f"({sol.x:.6g}, {sol.y:.6g}) undecided (site {culprit})")
        if vid is None:
            refine.update(triple)
        else:
            tri_vid[t] = vid
    raw = splice.rewire(raw, tri_vid)
    walks = []
    degree: list[list] = [[] for _ in vertices]
    flat_tris = {t for t, v in tri_vid.items() if v == "inf"}
    end_pairs = E.segment_end_pairs
    for pair, start, chain, end in raw:
        if ghost in pair or pair in end_pairs:
            # the two ends of a segment are never neighbours (a circle through both meets the
            # open segment); their samples' cells touch far out when the segment's samples fall
            # a rounding inside the hull edge between its ends
            continue
        if flat_tris and ((start is not None and start[0] == "tri" and start[1] in flat_tris)
                          or (end is not None and end[0] == "tri" and end[1] in flat_tris)) \
                and long_side(tri, pair, start, end, tri_vid):
            continue
        if start is None or start[0] == "bad" or (end is not None and end[0] == "bad"):
            refine.update(pair)
            continue
        ends = []
        ok = True
        for e in (start, end):
            v = None if e[0] == "hull" else tri_vid.get(e[1], -1)
            ok = ok and v != -1
            ends.append(None if v == "inf" else v)
        if not ok:
            refine.update(pair)
            continue
        if ends[0] is not None and ends[0] == ends[1]:
            if vertices[ends[0]].radius == 0 and len(chain) >= 3:
                # a walk from a corner back to it: the two perpendiculars of a nearly flat corner
                # meet in the samples (at about h/δ for an angle δ between them), never in the
                # diagram; finer samples push that point away
                for t_ in pair:
                    if np.isfinite(spacing[t_]):
                        refine.add(t_, spacing[t_] / 4)
                    else:
                        refine.add(t_)
            continue
        for v in ends:
            if v is not None:
                degree[v].append(pair)
        walks.append((pair, ends, (None, None)))
    for v in vertices:
        s_ = v.sites
        want = sorted((a, b) if a < b else (b, a) for a, b in zip(s_, s_[1:] + s_[:1]))
        if sorted(degree[v.id]) != want:
            refine.update(v.sites)
            # an edge missing at a vertex of a point site p and a curve t ending at p: the edge
            # leaves the vertex where t's nearest point is a hair away from p (a hull tangent
            # next to an arc's end, a nearly flat corner), closer than t's first sample:
            # samples of t graded towards p (sampling.corner_grading), 8 times finer at each
            # request, resolve it
            for p_ in v.sites:
                if E.kind[p_] == POINT:
                    for t in v.sites:
                        if E.is_endpoint(p_, t):
                            graded[(int(t), int(p_))] = graded.get((int(t), int(p_)), 0) + 1
            problems.append(f"sites {', '.join(map(str, v.sites))}: the vertex at ({v.x:.6g}, {v.y:.6g}) has incident "
                            f"edges {sorted(degree[v.id])}, expected {want}")
    # point sites are single samples: refine the segments ending at them instead
    out: dict = {}
    for t, cap in refine.items():
        for s_ in ([t] if E.kind[t] != POINT else E.incident[t]):
            out[s_] = min(out.get(s_, np.inf), cap)
    refine = out
    return (vertices, walks, problems), refine


class _Refine(dict):
    """Sites to sample more densely: site -> the largest spacing wanted (∞: halve)."""

    def add(self, t, cap=np.inf):
        t = int(t)
        self[t] = min(self.get(t, np.inf), cap)

    def update(self, sites):
        for t in sites:
            self.add(t)


def _vertex_id(vertices, by_sites, members, sol, E, orders):
    """The id of the vertex with these sites at this position (10⁻⁹ of the scale), new if none;
    ``orders`` keeps each proof's sites, tolerance and contact order across rounds."""
    known = orders.get(id(sol))
    if known is None:
        known = orders[id(sol)] = (tuple(sorted(members)), 1e-9 * (1.0 + abs(sol.x) + abs(sol.y) + sol.r),
                                   contact_order(E, members, sol))
    key, tol, order = known
    for vid in by_sites.get(key, ()):
        v = vertices[vid]
        if abs(v.x - sol.x) <= tol and abs(v.y - sol.y) <= tol:
            return vid
    vid = len(vertices)
    vertices.append(DiagramVertex(vid, order, sol.x, sol.y, sol.r, True))
    by_sites.setdefault(key, []).append(vid)
    return vid
