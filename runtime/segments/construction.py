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

A round works on arrays over all candidates and walks at once (numpy): the known zeros of
the candidates' triples (:class:`runtime.segments.proved_zeros.ZeroTable`), corners, vertex
numbers, the walks' ends and the degree check (:func:`runtime.segments.walk_checks.
degree_mismatches`).  Python loops remain (a) over the zeros proved for the first time (one
arb Krawczyk proof each, :func:`runtime.segments.newton.prove_vertices`, and those the float
emptiness filter leaves to the arb and exact tests), (b) over the candidates and walks that
fail (a refinement request, a culprit sample, a problem text: few after the first round),
(c) over the walks of the sample triangulation, which
:meth:`runtime.voronoi.sample_delaunay.SampleTriangulation.walks` gives as Python tuples, and
over the vertex objects of the round (their :class:`runtime.voronoi.structure.DiagramVertex`
numbers).

Length: one round's steps (candidate vertices, proofs, emptiness, walks, degree checks and the
refinement they ask for) read and write the same per-round tables (triangle → vertex, proof →
vertex, the caches kept across rounds); split apart they would pass all of them around.

Public API: :func:`segment_voronoi`, :func:`has_segments`.
"""
from __future__ import annotations

import time

import numpy as np
from scipy.spatial import cKDTree

from ..predicates.circles import Point
from ..sites.arc import Arc, circle_halves
from ..sites.elliptic_arc import EllipticArc
from ..sites.rationals import to_fraction
from ..sites.segment import Segment, as_point_pair
from ..threads import one_blas_thread, without_cyclic_gc
from ..voronoi.site_input import SiteError
from ..voronoi.structure import Diagram, DiagramVertex
from .contact_order import corner_order
from .crossings import check_pieces, renamed
from .edges import edge_polylines
from .edits import SegmentEdits
from .elementary import ARC, POINT, ElementarySites, decompose
from .exact import contacts_valid
from .hull_samples import hull_samples
from .sampling import flat, initial_spacing, nearest_point, retriangulation, samples, triangulation
from .proved_zeros import EMPTY, ENTERED, UNDECIDED, ZeroTable
from .walk_checks import BAD, NONE, TRI, VERTEX, degree_mismatches, far_ends, long_side, pair_keys, walk_arrays
from .newton import prove_vertices
from .near_degenerate import CLUSTER_RADIUS, splice_clusters
from .parallel_rays import parallel_ray_triangles
from .vertices import common_point

__all__ = ["segment_voronoi", "has_segments"]

MAX_ROUNDS = 10
#: refinement stops once the samples exceed this many times the first round's (and
#: MIN_SAMPLE_CAP): measured growth is at most 2.3× on random segments, gears and regular polygons,
#: while the integer 256-gon of radius 10⁷ (a vertex tied with hundreds of sites at its centre)
#: grew 3 328 → 798 093 samples in 7 rounds, its qhull calls taking minutes each
SAMPLE_GROWTH_CAP = 8
MIN_SAMPLE_CAP = 20000
#: initial sample spacing of a segment: its gap to the nearest non-adjacent site divided by this
SPACING_PER_GAP = 4.0


def has_segments(sites) -> bool:
    """True when ``sites`` holds a :class:`runtime.sites.segment.Segment` or an arc."""
    return any(isinstance(s, (Segment, Arc, EllipticArc)) for s in sites)


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
    edits = SegmentEdits(pieces, segment_voronoi) if sources is None else None
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
    if (E.kind >= ARC).any():
        arcs = E.kind >= ARC                      # circular arcs and elliptic pieces (C ± major semi-axis)
        lo = np.minimum(lo, (E.C[arcs] - E.rho[arcs][:, None]).min(axis=0))
        hi = np.maximum(hi, (E.C[arcs] + E.rho[arcs][:, None]).max(axis=0))
    extent = float(np.max(hi - lo)) or 1.0
    if tolerance is None:
        tolerance = 1e-4 * extent
    spacing = initial_spacing(E)
    stats: dict = {"sites": len(E), "points": E.n_points, "segments": len(E) - E.n_points, "rounds": 0}
    caches: dict = {"proofs": {}, "extra": hull_samples(E)}
    vertices, walks, problems, edges = without_cyclic_gc(_rounds)(E, spacing, stats, caches, tolerance, lo, hi)
    D = Diagram(E.sites, vertices, edges, False, problems, stats)
    D.sources = list(E.source)
    D.elementary = E
    D.construction = edits                      # Diagram.insert / delete_site (runtime.segments.edits)
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
        stats.setdefault("round_samples", []).append(stats["samples"])
        history.append(result[2])
        if not refine or (len(history) >= 3 and history[-1] == history[-2] == history[-3]):
            break            # consistent, or two refinements changed nothing
        first = stats["round_samples"][0]
        if stats["samples"] > max(SAMPLE_GROWTH_CAP * first, MIN_SAMPLE_CAP):
            result[2].append(f"the refinement stopped after {len(history)} rounds: the samples grew from {first} to "
                             f"{stats['samples']} without a consistent round, around sites "
                             f"{sorted(int(t) for t in refine)[:12]} (a nearly degenerate configuration, e.g. "
                             "one vertex tied with many sites); the diagram is incomplete there")
            break
        idx = np.array(sorted(refine), dtype=int)
        cap = np.array([refine[i] for i in idx.tolist()])
        spacing[idx] = np.minimum(spacing[idx] / 2, cap)
    vertices, walks, problems = result
    edges = edge_polylines(E, vertices, walks, tolerance, lo, hi)
    if not edges:
        # two or more sites always have an edge (the bisector of the nearest pair): an empty
        # diagram is a construction that lost everything, never an answer
        problems.append(f"no Voronoi edge found among {len(E)} sites after {stats['rounds']} rounds (a diagram "
                        f"of two or more sites has at least one edge): the candidate vertices were not proved "
                        f"and the walks of sites {sorted(int(t) for t in refine)} end nowhere; the diagram is "
                        "incomplete")
    return vertices, walks, problems, edges


def _as_pieces(p, k) -> list:
    """The pieces of input site k: a Segment, Arc or Point itself; an (x, y) pair a Point; a circle
    of rational radius (a Circle, or an (x, y, r) triple with r > 0) its two half arcs
    (:func:`runtime.sites.arc.circle_halves`); other conics are refused."""
    if isinstance(p, (Segment, Arc, EllipticArc)) or (isinstance(p, Point) and p.r2 == 0):
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
            elif E.kind[s] > ARC:                 # an elliptic piece: its exact end tangent
                arc = E.sites[s]
                tx, ty = arc.tangent(arc.ua if int(E.ends[s, 0]) == p else arc.ub)
                dirs.append((tx, ty) if int(E.ends[s, 0]) == p else (-tx, -ty))
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
        tri = _entered_flipped(triangulation(P, lab), caches)
        caches.pop("tri", None)
    else:
        prev = caches.pop("tri", None)
        tri = retriangulation(prev, P, lab) if prev is not None else None
        del prev                       # one triangulation alive at a time
        if tri is None:
            tri = triangulation(P, lab, droppable=lab >= E.n_points)
        else:
            stats["local_rounds"] = stats.get("local_rounds", 0) + 1
        tri = _entered_flipped(tri, caches)
        caches["tri"] = tri
    P, lab = tri.P, tri.lab            # an updated triangulation keeps its own sample order
    raw = tri.walks()
    threes = np.nonzero(tri.nlab == 3)[0]
    T3 = np.sort(tri.L[threes], axis=1)
    seeds = tri.cc[threes]
    m = len(threes)
    skip = (T3 == ghost).any(axis=1) | ~np.isfinite(seeds).all(axis=1)
    skip |= parallel_ray_triangles(E, T3, seeds)       # far ends of the perpendiculars at a segment's ends
    fin_spacing = np.where(np.isfinite(spacing), spacing, 0.0)
    reaches = 2 * fin_spacing[np.minimum(T3, len(E) - 1)].max(axis=1)
    tree = cKDTree(P)
    hmax = float(np.max(spacing[np.isfinite(spacing)])) if np.isfinite(spacing).any() else 0.0
    refine = _Refine()
    problems: list[str] = []
    zeros = caches.setdefault("zeros", ZeroTable(len(E)))
    # per candidate: its vertex (INF: the ghost ring, or a flat hull triangle of collinear
    # samples; −1: none), its corner (a common point of the triple's closures, −1: none) and the
    # row of its proved zero (−1: none)
    vid = np.where(skip, INF, -1)
    corner = _corners(E, T3, skip)
    row = np.full(m, -1, np.int64)
    open_ = np.nonzero(~skip & (corner == -1))[0]
    # a seed near a proved solution of its triple (within twice the triple's sample spacing)
    # takes it without a new Newton run; two vertices of one triple that close make the edge
    # checks fail, and the refinement then separates them
    row[open_] = zeros.near(zeros.keys(T3[open_]), seeds[open_], reaches[open_])
    # the zeros not known yet: Newton for all of them together, then one arb proof each
    todo = open_[row[open_] < 0]
    fresh_sols = prove_vertices(E, [(tuple(T3[j].tolist()), seeds[j]) for j in todo.tolist()],
                                cache=caches["proofs"])
    proved = []
    for j, sol in zip(todo.tolist(), fresh_sols):
        if sol.status == "undecided" and sol.box is not None and "at an end" in sol.reason:
            # a contact exactly at a curve's end (then that end touches too): decided exactly
            verdict = contacts_valid(E, tuple(T3[j].tolist()), sol)
            if verdict:
                sol.status, sol.reason = "proved", "contact at an end, exact"
            elif verdict is False:
                sol.status, sol.reason = "invalid", "contact outside a curve, exact"
            else:
                sol.reason = "contact at an end, no closed form"
        if sol.status == "proved":
            proved.append((j, sol))
    if proved:
        idx = np.array([j for j, _ in proved], np.int64)
        row[idx] = zeros.add_many([tuple(T3[j].tolist()) for j in idx.tolist()], [s for _, s in proved])
    # corners: the vertex c of radius 0
    vertices: list[DiagramVertex] = []
    corner_vertices = caches.setdefault("corner_vertices", {})
    at = np.nonzero(corner != -1)[0]
    codes, first = np.unique(corner[at], return_index=True)
    for c in codes[np.argsort(first)].tolist():
        v = corner_vertices.get(c)
        if v is None:
            x, y = E.xy[c]
            v = corner_vertices[c] = DiagramVertex(-1, corner_order(E, c), float(x), float(y), 0.0, True)
        v.id = len(vertices)
        vertices.append(v)
    if len(at):
        vid[at] = np.array([corner_vertices[c].id for c in corner[at].tolist()], np.int64)
    has = np.nonzero(row >= 0)[0]
    # candidates crowded closer than any sample spacing: their local diagram, spliced in
    # (only the candidates with a zero of another candidate that close can be in a cluster)
    crowd = has[_crowded(zeros, row[has])]
    jobs = [(int(threes[j]), tuple(T3[j].tolist()), zeros.sols[r], seeds[j])
            for j, r in zip(crowd.tolist(), row[crowd].tolist())]
    _, splice = splice_clusters(E, jobs, vertices, caches)
    if splice.tri_cluster:
        has = has[~np.isin(threes[has], np.array(list(splice.tri_cluster), np.int64))]
    zeros.decide(E, tree, lab, hmax, row[has])
    state = zeros.state[row[has]]
    emp = has[state == EMPTY]
    vrow = zeros.vertex[row[emp]]
    rows_, first = np.unique(vrow, return_index=True)
    base_id = len(vertices)
    for r in rows_[np.argsort(first)].tolist():
        v = zeros.diagram_vertex[r]
        v.id = len(vertices)
        vertices.append(v)
    if len(emp):
        lookup = np.full(int(rows_.max()) + 1, -1, np.int64)
        lookup[rows_[np.argsort(first)]] = base_id + np.arange(len(rows_))
        vid[emp] = lookup[vrow]
    # candidates that are not a proved empty vertex: their sites are refined
    for j in np.nonzero((vid == -1) & ~skip)[0].tolist():
        triple = tuple(T3[j].tolist())
        if threes[j] in splice.tri_cluster:
            continue
        refine.update(triple)
        r = int(row[j])
        if r < 0 or zeros.state[r] == EMPTY:
            continue
        culprit = zeros.culprit[r]
        if culprit is not None:
            # a curve entering the circle passed between its samples: its point nearest to the
            # vertex becomes a sample (it lies inside the circle), however shallow the
            # intrusion; the triple's curves are sampled twice as densely
            sol = zeros.sols[r]
            if E.kind[culprit] != POINT:
                f = nearest_point(E, int(culprit), (sol.x, sol.y))
                if not any(np.allclose(f, E.A[int(culprit)] if k_ == 0 else E.B[int(culprit)], rtol=0, atol=0)
                           for k_ in (0, 1)):
                    added = extra.setdefault(int(culprit), [])
                    # a repeated sample would stop the local rounds (retriangulation needs distinct samples)
                    if not any(float(a[0]) == float(f[0]) and float(a[1]) == float(f[1]) for a in added):
                        added.append(f)
            if zeros.state[r] == UNDECIDED:
                problems.append(f"sites {', '.join(map(str, triple))}: emptiness of the vertex at "
                                f"({sol.x:.6g}, {sol.y:.6g}) undecided (site {culprit})")
    walks, hv, hk = _walks(E, tri, raw, splice, threes, vid, vertices, spacing, refine)
    _degree_checks(E, vertices, hv, hk, refine, graded, problems, caches.setdefault("want", {}))
    # point sites are single samples: refine the segments ending at them instead
    out: dict = {}
    for t, cap in refine.items():
        for s_ in ([t] if E.kind[t] != POINT else E.incident[t]):
            out[s_] = min(out.get(s_, np.inf), cap)
    refine = out
    return (vertices, walks, problems), refine


#: the vertex code of a candidate that is the ghost ring or a flat hull triangle (an end at infinity)
INF = -2


def _entered_flipped(tri, caches):
    """The sample triangulation ``tri`` with its quadrilaterals flipped to their exact Delaunay
    diagonal (Lawson's flips, :meth:`runtime.voronoi.sample_delaunay.SampleTriangulation.
    legalized`) where a triangle's triple has a proved zero that the site of the far corner
    enters (found in an earlier round).  qhull and the batch update decide in floats, and a
    curve's point nearest to such a zero (the sample added for the site that entered it) lies
    inside the circle of the triple's samples by the intrusion's depth only, which can be below
    their roundoff (at 4·10⁵ samples of coordinates 10⁴, a depth of 2·10⁻¹⁰): the triangle then
    stays, and the refinement asks for the same sample round after round.  Elsewhere the float
    diagonal is kept: near a curve's end its samples only stand for the curve, and the exact
    diagonal of the samples may be the wrong one for the sites.  The flips are Lawson's (each
    removes a side that is not locally Delaunay, so they end); their candidates are proved like
    any others."""
    zeros = caches.get("zeros")
    if zeros is None or not len(zeros.key):
        return tri
    culprit = np.array([-1 if c is None else int(c) for c in zeros.culprit], np.int64)
    known = (np.isin(zeros.state, (ENTERED, UNDECIDED)) & (culprit >= 0))
    if not known.any():
        return tri
    threes = np.nonzero(tri.nlab == 3)[0]
    rows = threes[np.isin(zeros.keys(np.sort(tri.L[threes], axis=1)), zeros.key[known])]
    if not len(rows):
        return tri
    lab = tri.lab

    def entered(a, b, c, d) -> bool:
        t = sorted((int(lab[a]), int(lab[b]), int(lab[c])))
        if t[0] == t[1] or t[1] == t[2]:
            return False
        at = np.nonzero(known & (zeros.key == zeros.keys(np.array([t], np.int64))[0]))[0]
        return bool((culprit[at] == int(lab[d])).any())

    def allow(p, q, r, d) -> bool:
        return entered(p, q, r, d) or entered(d, r, q, p)

    return tri.legalized(allow, rows)


def _crowded(zeros: ZeroTable, rows) -> np.ndarray:
    """Mask of ``rows`` whose zero has another row's zero within :data:`CLUSTER_RADIUS` of the
    scale (1 + |x| + |y| + r, the largest of ``rows``): a superset of the members of the
    clusters of :func:`runtime.segments.near_degenerate.splice_clusters`."""
    out = np.zeros(len(rows), bool)
    if len(rows) < 2:
        return out
    X = zeros.xy[rows]
    r = np.array([zeros.sols[k].r for k in rows.tolist()])
    scale = float((1.0 + np.abs(X).sum(axis=1) + r).max())
    pairs = cKDTree(X).query_pairs(CLUSTER_RADIUS * scale, output_type="ndarray")
    out[pairs.ravel()] = True
    return out


def _corners(E: ElementarySites, T3, skip) -> np.ndarray:
    """Per sorted triple: the common point of its three sites' closures
    (:func:`runtime.segments.vertices.common_point`, asked only for the triples where one site's
    closure meets both others'), −1 for none (and for ``skip`` rows)."""
    n = len(E)
    cl = np.where((E.kind == POINT)[:, None], np.arange(n)[:, None], E.ends)
    cl = np.vstack([cl, [[-1, -1]]])                   # the ghost label
    C = cl[np.minimum(T3, n)]                          # (m, 3, 2)
    maybe = np.zeros(len(T3), bool)
    for j in (0, 1):
        c = C[:, 0, j]
        maybe |= (c != -1) & (C[:, 1, :] == c[:, None]).any(axis=1) & (C[:, 2, :] == c[:, None]).any(axis=1)
    maybe &= ~skip
    out = np.full(len(T3), -1, np.int64)
    for j in np.nonzero(maybe)[0].tolist():
        c = common_point(E, tuple(T3[j].tolist()))
        if c is not None:
            out[j] = c
    return out


def _walks(E, tri, raw, splice, threes, vid, vertices, spacing, refine) -> list:
    """The edges (pair, [vertex or None, vertex or None], (None, None)) of the walks ``raw``, and
    the walks' ends at vertices with their pair keys; the pairs of walks that end nowhere known
    are refined."""
    ghost = len(E)
    side: dict = {}
    raw = splice.rewire(raw, side)
    base = len(E) + 1
    if not raw:
        return [], np.empty(0, np.int64), np.empty(0, np.int64), np.empty(0, np.int64), np.empty(0, np.int64)
    key, sk, st, ek, et, length = walk_arrays(raw, base, side)
    pa, pb = key // base, key % base
    pos = np.full(len(tri.simp), -1, np.int64)
    pos[threes] = np.arange(len(threes))

    def end_vertex(kind, t):
        v = np.full(len(kind), -3, np.int64)            # −3: at infinity (the hull, a flat triangle)
        tr = kind == TRI
        v[tr] = np.where(pos[t[tr]] >= 0, vid[pos[np.maximum(t[tr], 0)]], -1)
        v[kind == VERTEX] = t[kind == VERTEX]
        v[v == INF] = -3
        return v

    sv, ev = end_vertex(sk, st), end_vertex(ek, et)
    # the two ends of a segment are never neighbours (a circle through both meets the open
    # segment); their samples' cells touch far out when the segment's samples fall a rounding
    # inside the hull edge between its ends
    end_keys = np.array([a * base + b for a, b in E.segment_end_pairs if a < b], np.int64)
    drop = (pa == ghost) | (pb == ghost) | np.isin(key, end_keys)
    flat_tri = vid == INF
    if flat_tri.any():
        touch = ~drop & (((sk == TRI) & (sv == -3)) | ((ek == TRI) & (ev == -3)))
        tri_vid = {int(threes[j]): "inf" for j in np.nonzero(flat_tri)[0].tolist()}
        for w in np.nonzero(touch)[0].tolist():
            pair, start, _chain, end = raw[w]
            if long_side(tri, pair, start, end, tri_vid):
                drop[w] = True
    broken = ~drop & ((sk == NONE) | (sk == BAD) | (ek == BAD) | (sv == -1) | (ev == -1))
    for w in np.nonzero(broken)[0].tolist():
        refine.update(raw[w][0])
    loop = ~drop & ~broken & (sv >= 0) & (sv == ev)
    for w in np.nonzero(loop)[0].tolist():
        if vertices[int(sv[w])].radius == 0 and length[w] >= 3:
            # a walk from a corner back to it: the two perpendiculars of a nearly flat corner
            # meet in the samples (at about h/δ for an angle δ between them), never in the
            # diagram; finer samples push that point away
            for t_ in raw[w][0]:
                if np.isfinite(spacing[t_]):
                    refine.add(t_, spacing[t_] / 4)
                else:
                    refine.add(t_)
    good = np.nonzero(~drop & ~broken & ~loop)[0]
    s_l = np.where(sv[good] >= 0, sv[good], -1).tolist()
    e_l = np.where(ev[good] >= 0, ev[good], -1).tolist()
    walks = [(raw[w][0], [None if a < 0 else a, None if b < 0 else b], (None, None))
             for w, a, b in zip(good.tolist(), s_l, e_l)]
    # the walks' ends at vertices, with their pair keys (for the degree checks)
    at_s, at_e = good[sv[good] >= 0], good[ev[good] >= 0]
    return walks, np.concatenate([sv[at_s], ev[at_e]]), np.concatenate([key[at_s], key[at_e]])


def _degree_checks(E, vertices, hv, hk, refine, graded, problems, want_of) -> None:
    """Every vertex must have one edge per pair of cyclically consecutive sites (``hv``, ``hk``:
    the walks' ends at vertices and their pair keys); otherwise its sites are refined (and a
    point site's curves graded towards it) and the problem named.  ``want_of``: the sorted pair
    keys of each vertex's cyclic site tuple, kept across rounds (keyed by the sites, not by the
    vertex object's ``id``: an id is reused once an earlier round's vertex is freed)."""
    if not vertices:
        return
    base = len(E) + 1
    want = pair_keys([v.sites for v in vertices], base, want_of)
    bad = degree_mismatches(want, hv, hk, len(vertices))
    if not len(bad):
        return
    # the walks' ends grouped by vertex once (not one scan of all ends per bad vertex)
    o = np.argsort(hv, kind="stable")
    lo, hi = np.searchsorted(hv[o], bad, "left"), np.searchsorted(hv[o], bad, "right")
    for v_id, a_, b_ in zip(bad.tolist(), lo.tolist(), hi.tolist()):
        v = vertices[v_id]
        refine.update(v.sites)
        # an edge missing at a vertex of a point site p and a curve t ending at p: the edge
        # leaves the vertex where t's nearest point is a hair away from p (a hull tangent next
        # to an arc's end, a nearly flat corner), closer than t's first sample: samples of t
        # graded towards p (sampling.corner_grading), 8 times finer at each request, resolve it
        for p_ in v.sites:
            if E.kind[p_] == POINT:
                for t in v.sites:
                    if E.is_endpoint(p_, t):
                        graded[(int(t), int(p_))] = graded.get((int(t), int(p_)), 0) + 1
        have = sorted((int(k // base), int(k % base)) for k in hk[o[a_:b_]].tolist())
        want_v = sorted((a, b) if a < b else (b, a) for a, b in zip(v.sites, v.sites[1:] + v.sites[:1]))
        problems.append(f"sites {', '.join(map(str, v.sites))}: the vertex at ({v.x:.6g}, {v.y:.6g}) has incident "
                        f"edges {have}, expected {want_v}")


class _Refine(dict):
    """Sites to sample more densely: site -> the largest spacing wanted (∞: halve)."""

    def add(self, t, cap=np.inf):
        t = int(t)
        self[t] = min(self.get(t, np.inf), cap)

    def update(self, sites):
        for t in sites:
            self.add(t)
