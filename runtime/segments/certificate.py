"""An independent certificate for Voronoi diagrams of points, segments and circular arcs
(thesis §1.2, §2.2).

:func:`verify_segments` takes a :class:`runtime.voronoi.structure.Diagram` (or its JSON form)
whose sites are elementary sites — :class:`runtime.sites.circle.Point`,
:class:`runtime.sites.segment.Segment` and :class:`runtime.sites.arc.Arc` meaning their *open
interiors* — and either proves that it is *the* Voronoi diagram of those sites or names what
failed.  It reads only the reported combinatorics (vertex site lists, edge pairs and ends) and uses
positions and polylines to pick the arcs and check their stated tolerance; it imports nothing of
the construction (:mod:`runtime.segments.vertices`, ``construction``, ``bisectors``,
``emptiness``, ``exact``, …; ``tests/test_architecture.py`` enforces it).  Conventions: the
distance to an open curve is the distance to the closed curve; a point whose nearest points on a
curve are only ends that are point sites belongs to those ends (a point equidistant from an end e
and a curve ending at e, with e as the curve's nearest point, belongs to e).  A **smooth joint**
— a curve end that is no site, where exactly two curves (not both segments) continue each other
with opposite tangents — belongs to both curves' closures; their bisector there is the normal
line.

The proof (the contract of this module)
---------------------------------------
Let G be the true Voronoi graph of the sites (the complement of the union of the open regions)
and H the reported one.

1. **Sites admissible** (:mod:`runtime.segments.certificate_admissible`, exact rationals): points,
   segments and arcs only, none repeated, every curve end a point site or a smooth joint, curves
   meeting only at common ends and no point inside a curve
   (:func:`runtime.segments.crossings.check_pieces`), no two curves leaving a point site in
   opposite directions (merge them; a junction continuing straight or smoothly through); two
   curves leaving it in the same direction are a limit.  Otherwise nothing else is claimed.
2. **Vertices** (:mod:`runtime.segments.certificate_vertices`): each reported vertex is a point at
   distance r from each listed site (touching it at a contact in its closure) and strictly
   farther from every other site (up to the convention), within 10⁻¹⁰·(1 + |x| + |y| + r) of the
   report: corners exactly (v = c, r = 0, the curves at c by exact tangent and curvature order,
   c in the reflex gap); an arc's centre exactly (:mod:`runtime.segments.certificate_corners`:
   every listed site at distance ρ in rationals and squares, the open disc empty, contacts ordered
   with the arc along its whole range after the site at its start and before the site at its end);
   k = 3 by Krawczyk on a 2 × 2 system of touching-type distances of our own (points, lines of
   segments, σ(|v − c| − ρ) for arcs, normal lines at listed ends and joints), with the contact
   direction of an arc proved in its open range, its side σ, the ray from its centre through a
   listed end; k > 3 by the closed-form solution of three of the sites and exact zero tests (sympy,
   :mod:`runtime.segments.certificate_exact`) for the others; contacts counter-clockwise in the
   listed order; emptiness by rigorous distance balls after a k-d tree over bounding discs and
   float pruning (:mod:`runtime.segments.certificate_contacts`).
3. **Edges** (:mod:`runtime.segments.certificate_edges`, curves and polylines in
   :mod:`runtime.segments.certificate_curves` and :mod:`runtime.segments.certificate_arcs`, the
   rules decided at the ends in :mod:`runtime.segments.certificate_rules`, conditions along curves
   in :mod:`runtime.segments.certificate_edge_conditions`, tails in
   :mod:`runtime.segments.certificate_tails`): each reported edge (i, j) is the arc of the exact
   bisector curve (line, parabola, an arc's bisector by its contact angle, the radial ray of an
   arc's end, a joint's normal line) between its two end vertices, or from its vertex to infinity,
   or a whole line or branch, and every point of the open arc is strictly closer to i and j than to
   any other site (up to the convention): concavity of d_k² − ρ² along lines of a point anchor,
   piecewise rigorous lower bounds along the other curves (with conditions: t > 0, a segment
   partner's foot in (0, 1), an arc partner's contact in its range, a curve ending at the edge's
   point owned by it), derivative signs next to end vertices where a third site ties, exact
   asymptotics on straight tails, and on an arc's hyperbola-like branch support witnesses up to the
   pole.  The polyline lies within the stated tolerance of the arc (Hausdorff; for an arc's
   bisector piece by piece against the polyline's segments with curvature bounds).  Hence each
   proved edge is a whole edge of G (a connected component of the set of points with nearest sites
   exactly i and j, bounded by Voronoi vertices or infinity).
4. **Closure** (:func:`closure`, exact on the combinatorics): every vertex of degree k ≥ 3 has
   exactly one incident edge for each of its k cyclically consecutive site pairs and no other
   incident edge; every edge's finite ends are vertices listing both its sites.  With 2 and 3 this
   says that H is a union of connected components of G (a proved vertex of G has exactly the k
   edges of its consecutive pairs in G).  Two edges of one pair cannot overlap: each is a whole edge
   of G, a repeated one is found here (vertex ends) or in 5 (infinite ends).
5. **Completeness** (:mod:`runtime.segments.certificate_hull`, exact or proved): every region is
   contractible.  The region of a point is star-shaped with respect to it (also with the clamped
   zones of its curves: "nearest point e alone" is preserved along segments towards e); the region
   of an open segment is star-shaped with respect to the segment; the region of an open arc is *not*
   star-shaped with respect to a convex set, but every point x of it has its nearest point f(x) in
   the open arc, the segment [x, f(x)] stays in the region (d_s drops by the distance moved, every
   other distance by at most that, the ends' ties too), f is continuous there (the centre is not in
   the region: it is at distance ρ from the ends or the joint curves), so x ↦ (1 − λ) x + λ f(x)
   retracts the region onto the open arc.  So no region has a hole.  A bounded connected component
   C of G would separate the plane (a tree would leave the one region around it adjacent to itself
   across an edge of two distinct sites); the region meeting a small loop around C from outside
   lies outside C and winds around a bounded complementary domain of C: a hole.  So every
   component of G reaches infinity, and its unbounded edges are among the ends of G at infinity:
   one per pair of sites consecutive along a support line of the sites' convex hull (points,
   segments and arcs by their support functions; ties where several sites touch the support line
   of a direction), going out in that direction (a tangent's, for a point or an arc and an arc).
   The reported infinite ends (pair, exact key) must equal that list with multiplicity; then every
   component of G has an edge in H, and by 4 lies in H: H = G.
6. **Document** (:func:`runtime.voronoi.verify.document.check_document`): finite numbers, no
   closed edges, the document's ``delaunay_edges`` equal to its edges' pairs.

``ok`` is True only when all of this is proved; per-vertex and per-edge flags say which parts
are; problems are :class:`runtime.voronoi.verify.problems.Problem` records naming the vertex, edge
and sites (``fault`` False for a limit of the certificate).  Not claimed: diagrams with other sites
(circles, conics), curves tangent at a common point site, collinear ties on an irrational common
tangent, junctions that continue straight through (refused as sites), closed edges (none exist
for these sites: an edge with no end vertex is a line or a branch to infinity).

**Elliptic pieces** (:class:`runtime.sites.elliptic_arc.EllipticArc` cut at its ellipse's vertices,
:mod:`runtime.segments.certificate_ellipses`): their sites, distances and k = 3 vertices are proved
as in 2 (the foot enclosed by a parametric Krawczyk test inside the piece's range, the contact
proved the piece's nearest point); the edges next to them (a piece among the edge's sites or its
end vertices' sites) by :mod:`runtime.segments.certificate_ellipse_edges` (foot curves of a piece
and a point, segment or arc; normal lines at a piece's end and at a joint; two points' bisectors
with their tails), the others as in 3; the crossings of pieces with the other sites by distance
balls (:func:`runtime.segments.certificate_ellipse_sites.pieces_apart`); and 5 when every piece
lies strictly inside the point sites' convex hull but at its point-site ends
(:func:`runtime.segments.certificate_ellipse_sites.pieces_inside_hull`: the unbounded ends are
then those of the points and segments), else, with points, segments and pieces of one ellipse, by
the affine frame of the ellipse, which maps the pieces to arcs of the unit circle and keeps the
support envelope (:func:`runtime.segments.certificate_ellipse_hull.frame_infinite_ends`).  A
missing unbounded end is a fault only when every unbounded edge of the document is proved (an
unproved one names no end).  The region of an open piece retracts onto it as an
arc's does (its nearest point is unique and continuous there).  What that module does not cover
is reported as a limit.  **Shared with the construction:** the piece kernel
:mod:`runtime.segments.ellipse_pieces` (distances, feet and contact verdicts of a piece, in floats
and arb balls) is imported by both sides (the construction's ``distance``, ``vertices``,
``bisectors``, ``emptiness``, … and this certificate's ``certificate_ellipses`` and
``certificate_ellipse_sites``); a fault in its rigorous bounds would be a fault of both.  Its ball
bounds are checked on their own against mpmath at 40 digits (``tests/test_ellipse_pieces.py``,
``tests/test_elliptic_arc_certificate.py``), not against the construction.  The exact orientation
of :mod:`runtime.predicates.orientation` (the convex hull of the point sites here, the exact
Delaunay triangulation of points in the construction) is shared too; it is checked against
sympy's rational determinants (``tests/test_orientation.py``).

Public API: :func:`verify_segments`, :func:`has_segment_sites`, :func:`closure`.
"""
from __future__ import annotations

import time
from collections import Counter

from ..certify.foot import working_prec
from ..sites.arc import Arc
from ..sites.elliptic_arc import EllipticArc
from ..sites.segment import Segment
from ..threads import one_blas_thread
from ..voronoi.verify.document import check_document
from ..voronoi.verify.outcome import Certificate
from ..voronoi.verify.problems import Problem, fault
from .certificate_edges import prove_edges
from .certificate_ellipse_edges import prove_edges_with_pieces
from .certificate_ellipse_hull import frame_infinite_ends
from .certificate_ellipse_sites import pieces_apart, pieces_inside_hull
from .certificate_hull import expected_infinite_ends
from .certificate_admissible import admissibility
from .certificate_sites import SiteTable
from .certificate_vertices import prove_vertices

__all__ = ["verify_segments", "has_segment_sites", "closure", "SegmentCertificate"]

PREC = 128


#: the segment certificate's outcome is the one record of every certificate
SegmentCertificate = Certificate


def has_segment_sites(diagram) -> bool:
    """True when the diagram (or its JSON dict) has a segment, an arc or an elliptic arc site."""
    if isinstance(diagram, dict):
        return any(isinstance(s, dict) and ("segment" in s or "arc" in s or "elliptic_arc" in s)
                   for s in diagram.get("sites", []) or [])
    return any(isinstance(s, (Segment, Arc, EllipticArc)) for s in getattr(diagram, "sites", []) or [])


def _as_diagram(diagram):
    from ..voronoi.structure import Diagram

    if isinstance(diagram, dict):
        return Diagram.from_json(diagram)
    return diagram


def _same(a, b) -> bool:
    if isinstance(a, (Segment, Arc, EllipticArc)) or isinstance(b, (Segment, Arc, EllipticArc)):
        return type(a) is type(b) and a == b
    try:
        return (a.x, a.y) == (b.x, b.y)
    except AttributeError:
        return False


@one_blas_thread
def verify_segments(diagram, sites=None, *, deadline=None) -> Certificate:
    """Prove that ``diagram`` is the Voronoi diagram of its elementary point, segment and arc sites
    (module docstring).  ``sites``: the expected elementary sites (compared exactly); ``deadline``:
    a :func:`time.perf_counter` value after which edges are not checked (not ok)."""
    T0 = time.perf_counter()
    doc = diagram if isinstance(diagram, dict) else None
    D = _as_diagram(diagram)
    problems: list = []
    timings: dict = {}
    if sites is not None:
        sites = list(sites)
        if len(sites) != len(D.sites):
            problems.append(fault(f"the diagram has {len(D.sites)} sites, the input {len(sites)}", kind="site"))
        for k in range(min(len(sites), len(D.sites))):
            if not _same(sites[k], D.sites[k]):
                problems.append(fault(f"site {k} of the diagram differs from input site {k}", kind="site", sites=(k,)))
    with working_prec(PREC):
        T = SiteTable(D.sites)
        stats = {"sites": T.n, "vertices": len(D.vertices), "edges": len(D.edges), "route": "segments"}
        hyp = ["sites admissible (checked)", "an end owns the ties of its curves (convention)"]
        adm = admissibility(T)
        problems.extend(adm)
        check_document(D, doc, [], problems)
        for e in D.edges:
            if e.closed:
                problems.append(fault(f"edge {e.id} (sites {', '.join(map(str, e.sites))}): a diagram of points, "
                                      "segments and arcs has no closed edge", kind="edge", edge=e.id,
                                      sites=tuple(int(s) for s in e.sites if 0 <= int(s) < T.n)))
        timings["sites"] = time.perf_counter() - T0
        if adm:
            return Certificate(False, problems, [False] * len(D.vertices), [False] * len(D.edges), False, [],
                               hyp, stats, timings)
        t0 = time.perf_counter()
        vproofs = prove_vertices(D, T, problems)
        timings["vertices"] = time.perf_counter() - t0
        t0 = time.perf_counter()
        if T.piece:
            # elliptic pieces: :mod:`runtime.segments.certificate_ellipse_edges`
            eproofs = prove_edges_with_pieces(D, T, vproofs, problems, deadline=deadline)
            msg = pieces_apart(T)
            if msg is not None:
                problems.append(Problem(msg, kind="site", sites=tuple(sorted(T.piece)), fault=False))
            outside = pieces_inside_hull(T)
        else:
            outside = None
            eproofs = prove_edges(D, T, vproofs, problems, deadline=deadline)
        timings["edges"] = time.perf_counter() - t0
        t0 = time.perf_counter()
        closure_ok = closure(D, T.n, problems)
        if outside is None:
            expected = expected_infinite_ends(T)
        else:
            expected = frame_infinite_ends(T)
            if isinstance(expected, str):
                expected = f"{outside} ({expected})"
        account_ok = _accounting(expected, D.edges, eproofs, problems)
        timings["closure"] = time.perf_counter() - t0
    vok = [p.ok for p in vproofs]
    eok = [p.ok for p in eproofs]
    complete = closure_ok and account_ok
    ok = complete and all(vok) and all(eok) and not problems
    pairs = sorted({tuple(sorted(int(t) for t in e.sites)) for e, f in zip(D.edges, eok) if f})
    timings["total"] = time.perf_counter() - T0
    return Certificate(ok, problems, vok, eok, complete, pairs, hyp, stats, timings)


def closure(D, n: int, problems: list) -> bool:
    """Step 4 of the module docstring (exact on the combinatorics); problems appended."""
    ok = True
    ids = {v.id: v for v in D.vertices}
    if len(ids) != len(D.vertices):
        problems.append(fault("two vertices share an id", kind="diagram"))
        ok = False
    at: dict = {v.id: [] for v in D.vertices}
    for e in D.edges:
        pair = tuple(sorted(int(s) for s in e.sites))
        name = f"edge {e.id} (sites {', '.join(map(str, e.sites))})"
        if len(pair) != 2 or not all(0 <= s < n for s in pair) or pair[0] == pair[1]:
            problems.append(fault(f"{name}: not a pair of two distinct sites", kind="edge", edge=e.id))
            ok = False
            continue
        for v in e.ends:
            if v is None:
                continue
            if v not in ids:
                problems.append(fault(f"{name}: its end {v} is not a vertex", kind="edge", edge=e.id, sites=pair))
                ok = False
                continue
            at[v].append((e, pair))
            if pair not in ids[v].site_pairs():
                problems.append(fault(f"{name}: its end vertex {v} does not list its sites as consecutive",
                                      kind="edge", edge=e.id, vertex=v, sites=pair))
                ok = False
    for v in D.vertices:
        count = Counter(p for _, p in at.get(v.id, []))
        for p in v.site_pairs():
            if count[p] != 1:
                what = "no incident edge" if count[p] == 0 else f"{count[p]} incident edges"
                problems.append(fault(f"vertex {v.id} (sites {', '.join(map(str, v.sites))}): {what} between its "
                                      f"consecutive sites {p[0]} and {p[1]}", kind="vertex", vertex=v.id, sites=p))
                ok = False
    return ok


def _accounting(expected, edges, eproofs, problems: list) -> bool:
    """Step 5: the proved infinite ends of the edges (``eproofs``, one per edge of ``edges``)
    equal the expected ones (with multiplicity; a message when they are not decided).  While an
    unbounded edge is unproved (a limit: it names no end) a missing end is a limit, not a fault."""
    if isinstance(expected, str):
        problems.append(Problem(expected, kind="infinity", fault=False))
        return False
    unproved = any(None in e.ends and not p.ok and not p.infinite for e, p in zip(edges, eproofs))
    want = Counter(expected)
    got = Counter(t for p in eproofs for t in p.infinite)
    ok = True
    for key, m in sorted((want - got).items(), key=str):
        (a, b), d = key
        msg = f"sites {a} and {b}: no edge goes to infinity between them {_dir(d)} (consecutive on the convex hull)"
        problems.append(Problem(msg + " among the proved edges", kind="infinity", sites=(a, b), fault=False)
                        if unproved else fault(msg, kind="infinity", sites=(a, b)))
        ok = False
    for key, m in sorted((got - want).items(), key=str):
        (a, b), d = key
        problems.append(fault(f"sites {a} and {b}: {m} edge end(s) go to infinity {_dir(d)}, where the diagram "
                              f"has {want.get(key, 0)}", kind="infinity", sites=(a, b)))
        ok = False
    return ok


def _dir(d) -> str:
    if d and d[0] == "tangent":
        return f"along their common tangent ({'left' if d[1] > 0 else 'right'})"
    return f"in the direction ({float(d[0]):.6g}, {float(d[1]):.6g})"
