"""A certificate that a reported Voronoi diagram of curved sites is *the* diagram (thesis §1.2).

:func:`verify` takes a diagram (a :class:`runtime.voronoi.structure.Diagram` or its JSON form)
and the sites, and either proves it or names what failed.  It does not trust, and does not
call, the construction: it reads only the reported combinatorics (vertex triples, edge pairs and
ends) and uses the polylines only to choose the arc of a bisector and to check their stated
tolerance.

What is proved
--------------
Let G be the true Voronoi graph and H the reported one.

1. **Vertices** (:mod:`runtime.voronoi.verify.vertices`).  Each reported vertex (i, j, k) is a
   true Voronoi vertex within 1e-10·(1 + |x| + |y| + r) of the reported position: for circle/point
   triples both solutions of the Apollonius system are proved by a float Krawczyk test with error
   bounds (falling back to the exact solver of thesis §3.1.3,
   :func:`runtime.predicates.circles.voronoi_vertices_circles`); for triples with a conic, a
   float Krawczyk test on (d_i − d_j, d_i − d_k) proves a unique equidistant point in a tiny box
   (:mod:`runtime.voronoi.verify.conic_vertices`, convex sites), else
   :func:`runtime.voronoi.vertex.certify_vertex` proves existence and uniqueness (Krawczyk on the
   exact foot-point system) and the touching property.  **Emptiness**: every other site k has a
   rigorous lower bound of d(v, S_k) above the upper bound of the radius; far sites are excluded
   first with a k-d tree on bounding discs (d(q, S) ≥ |q − c_S| − h_S).  Undecided → "vertex 12
   (sites 3, 5, 9): site 7 too close to decide".
2. **Edges.**  An edge (i, j) between proved vertices v0, v1 (or infinity) is a parameter
   interval of the exact bisector curve of i and j, and every point of its relative interior is
   strictly closer to i and j than to any other site (:mod:`runtime.voronoi.verify.edges`:
   discs along the arc with Lipschitz and first-order bounds, the exact zeros of d_k − d_i on
   the bisector for the third sites of the end vertices, interval bounds in τ = e^{∓u} for the
   infinite tail).  Hence the open arc is a connected set of points whose two nearest sites are
   i and j, it is a connected component of β_ij ∖ {v0, v1}, and its ends are Voronoi vertices:
   it is a **whole** edge of G.
   Polylines are checked against their stated ``tolerance``: a polyline point whose distance to
   the bisector is proved larger (|d_i − d_j|/2 is a lower bound, d_i − d_j being 2-Lipschitz)
   is a problem, as is a polyline end away from its vertex; for circle and point sites the
   Hausdorff distance between the whole polyline (segments included) and the arc is proved
   within the tolerance (:mod:`runtime.voronoi.verify.polyline_bound`), and the document's own
   fields are checked (:mod:`runtime.voronoi.verify.document`: finite numbers, ``delaunay_edges``
   equal to the edges' pairs, a closed edge winding once around its nested site).
3. **Closure** (:mod:`runtime.voronoi.verify.closure`).  Every vertex (i, j, k) has exactly one
   incident edge per pair of its sites, every edge ends at listed vertices whose triples contain
   its pair (or at infinity), every site has an edge, no two edges of one pair overlap.
4. **Every component of G is represented.**  (a) *At infinity*: the unbounded ends of H, sorted
   by asymptotic direction θ, must be such that consecutive ends share a site s that strictly
   maximises the support function h_k(θ) = c_k·e(θ) + ρ_k on the closed arc between them (ties
   only with the end's own pair at the arc's ends).  Far in direction θ the nearest site is the
   maximiser of h_k(θ) (d_k(t·e) = t − h_k(θ) + O(1/t)), and an unbounded edge of G has an
   asymptotic direction where two sites tie for the maximum; so every unbounded end of G is in H.
   (b) *Bounded components*: by Prop. 1.2.1 a component of G without points at infinity lies
   inside a site containing other sites.  With nesting depth ≤ 1 (a site inside another contains
   none), such a component contains the whole boundary of the region of a nested site K (that
   region is bounded and simply connected, its boundary a Jordan curve), and H contains an edge
   of K (step 3).
   (c) *Ties at infinity* (several sites share the largest h_k(θ*): collinear points, circles
   resting on one line, rows of identical shapes): far in direction θ* the nearest of them is the
   one whose support point is laterally closest, so the ends there are exactly the laterally
   consecutive pairs; decided exactly for points and circles with rational radii (the hull of the
   points or discs, :mod:`runtime.voronoi.verify.hull_points`) and, for conics, where mirrors or
   exact support levels prove the tie (:mod:`runtime.voronoi.verify.ties_at_infinity`; the tails
   by :mod:`runtime.voronoi.verify.mirror_tail` and :mod:`runtime.voronoi.verify.tied_tail`).
   **Why nothing is missing**: H ⊂ G (steps 1–2), and H is closed under incidence in G: at a
   proved vertex of k sites listed counter-clockwise by their contact points, each of the k pairs
   of consecutive sites has exactly one edge germ (the first-order argument of
   :mod:`runtime.voronoi.cocircular`), and H's edge of that pair is a whole edge of G ending
   there (step 2).  Walking from any edge of H along G therefore
   never leaves H, so H is a union of connected components of G (in the plane, the point at
   infinity not counted).  Every component of G contains an unbounded end (then it is in H by
   4a) or is bounded (then in H by 4b).  Hence H = G, and the Delaunay graph is the set of
   site pairs of H's edges.

Vertices of degree k > 3 are proved exactly: circles and points in the quadratic towers of
thesis §3.1.3 (:mod:`runtime.voronoi.verify.exact_vertices`), conics by a symmetry fixing a
rational point (:mod:`runtime.predicates.symmetry`).

Code shared with the construction (a bug there is a bug on both sides): the exact predicates of
:mod:`runtime.predicates.circles` (quadratic towers) and :mod:`runtime.predicates.symmetry`, the
site geometries' distance bounds (:mod:`runtime.voronoi.conic_geometry`), the foot-point vertex
proof :func:`runtime.voronoi.vertex.certify_vertex` (the fallback of conic triples), the local
frame (:mod:`runtime.voronoi.frame`), and the Hausdorff bound of
:mod:`runtime.voronoi.verify.polyline_bound`, which the construction uses to state its
tolerances.  Each is tested against an independent reference (exact arithmetic, dense sampling).

Hypotheses (checked, or the certificate says "not proved"): sites pairwise disjoint; nesting
depth ≤ 1; vertices of three sites simple (no fourth site at the same distance, which the strict
emptiness test enforces; three bisectors crossing transversally: proved on the fast circle route,
where Krawczyk's test proves the Jacobian of the Apollonius system, whose rows are
(r + ρ_l)·(n_l, −1), nonsingular, i.e. ∇(d_0 − d_1) and ∇(d_0 − d_2) independent; assumed on the
exact route); for circle and point sites the rounding of the bisector's float constants is
bounded to first order (module :mod:`runtime.voronoi.verify.edges`).

Sites with an ellipse (with circles and points): vertices as above; an edge between two vertices
is proved by :mod:`runtime.voronoi.verify.curved` (a chain of strips around the polyline in which
the bisector is a monotone graph, :mod:`runtime.voronoi.verify.strips`: gradient enclosures for
convex sites, third sites by distance bounds, first-order bounds or the transversality at the end
vertices); an unbounded edge by the same chain up to a far point, then to infinity by support
functions on a sector of directions (:func:`runtime.voronoi.verify.tail.prove_tail`: in the
sector the bisector is one curve to infinity, closer to i, j than to any other site, linked to
the chain).  All chains run side by side, and every distance enclosure they need comes from one
vectorised call per round (:mod:`runtime.voronoi.verify.site_table`, which defers to the site
geometries' own bounds wherever its cheap bounds are not tight).  Step 4 uses the support
functions h_k(θ) = max_{p ∈ S_k} u(θ)·p of the sites
(:class:`runtime.voronoi.verify.support.SupportTable`,
:func:`runtime.voronoi.verify.closure.verify_accounting_conics`): (b) the convex hulls of the
sites are proved pairwise disjoint, so no site is nested and G has no bounded component; (a)
each unbounded end owns an interval of directions where only its two sites attain max h_k and
h_i − h_j changes sign, and on every arc of directions between them one site strictly leads.
A vertex-less edge (two sites, or sites in a row) is a chain of strips between two cut points
with a tail at each end: the curve is open and closed in the bisector β_ij (each strip and
sector meets β in exactly one arc, all in the curve), so it is a whole component of β_ij, and
both its ends at infinity enter the accounting of step 4.  A parabola is convex (its focus side
K): edges between two vertices with a parabola site are proved by the same chains (gradient
enclosures outside K); an unbounded end between two unbounded sites (parabolas, hyperbolas) is
proved by enclosures of the foot parameter, the gradient and the distance far away
(:func:`runtime.voronoi.verify.conic_tail.prove_conic_tail`) and the ends at infinity are
accounted for by the asymptotic functions c_k(θ) = dist(u(θ), horizon cone of S_k)
(:func:`runtime.voronoi.verify.far_accounting.accounting_unbounded`); an unbounded end between an
unbounded and a bounded site is reported not proved.  A site inside a
circle or an ellipse (nesting depth ≤ 1, proved with support functions:
:func:`runtime.voronoi.verify.closure.verify_accounting_conics`): its closed edge is a chain of
strips that closes up, with gradient enclosures inside the container within the reach of its
boundary (b²/a for an ellipse) and, where the loop crosses the medial axis, enclosures of the
Clarke generalised gradient (:mod:`runtime.voronoi.verify.clarke_gradient`).  Edges of a hyperbola site are proved by the same chains where they
stay on one side of its conjugate axis (there the distance is the distance to the convex region
of the nearer branch, :mod:`runtime.voronoi.verify.site_table`); an edge crossing the conjugate
axis (the bisector has a corner there) is reported not proved; tails and accounting as for a
parabola.  Certificates with an unproved part are never ok.

Command line: ``python -m curvedvoronoi verify DIAGRAM.json [SITES.json]`` (exit 0 proved,
1 not proved, 2 bad input; prints :meth:`Certificate.to_json`).

Public API: :func:`verify`, :func:`verify_files`, :class:`Certificate`.
"""
from __future__ import annotations

import math
import time

from ...threads import one_blas_thread, without_cyclic_gc
from ..conic_geometry import site_geometry
from ..frame import to_local_frame
from .document import check_document
from .edge_checks import check_edges
from .edges import CircleTable
from .equal_circles import centres_diagram, equal_radius, separated_on
from .closure import circles_disjoint, verify_accounting, verify_accounting_conics, verify_closure
from .hull_points import verify_accounting_discs, verify_accounting_points
from .support import SupportTable
from .vertices import local_default, local_reach, prove_vertices
from .outcome import Certificate

__all__ = ["verify", "verify_files", "Certificate"]



# ============================================================================ input

def _as_diagram(diagram):
    from ..structure import Diagram

    if isinstance(diagram, dict):
        return Diagram.from_json(diagram)
    if isinstance(diagram, Diagram) or all(hasattr(diagram, a) for a in ("sites", "vertices", "edges")):
        return diagram
    raise ValueError(f"not a diagram: {type(diagram).__name__} (expected a Diagram or its JSON dict)")


def _as_site(s):
    """A Point / Circle / Conic as is; a pair (x, y) as a point; a tuple (x, y, r) as a circle
    (r = 0: a point) -- the forms :func:`runtime.voronoi.construction.voronoi` takes."""
    from ...predicates.circles import Circle, Point
    from ...sites.conic import Conic

    if isinstance(s, (Circle, Conic)):
        return s
    if isinstance(s, (tuple, list)) and len(s) == 2:
        return Point(*s)
    if isinstance(s, (tuple, list)) and len(s) == 3:
        x, y, r = s
        return Point(x, y) if r == 0 else Circle.from_radius(x, y, r)
    raise ValueError(f"not a site: {s!r} (expected a Point, Circle, Conic, (x, y) or (x, y, r))")


def _same_site(a, b) -> bool:
    from ...sites.reader import site_to_json
    from ...predicates.circles import Circle

    try:
        if isinstance(a, Circle) and isinstance(b, Circle):
            return (a.cx, a.cy, a.r2) == (b.cx, b.cy, b.r2)
        return site_to_json(a) == site_to_json(b)
    except TypeError:
        return False


def _stage_bar(progress, n_edges):
    if progress is None:
        progress = n_edges > 2000
    if not progress:
        return None
    try:
        from tqdm import tqdm
    except ImportError:
        return None
    return tqdm(total=3, desc="verify", unit="stage", leave=False)


def _advance(bar, what, close=False):
    if bar is None:
        return
    bar.set_postfix_str(what)
    bar.update(1)
    if close:
        bar.close()


def verify_files(diagram_path: str, sites_path: str | None = None, progress=None) -> "Certificate":
    """:func:`verify` on a diagram JSON file (and optionally a sites file, any form read by
    :func:`runtime.sites.reader.read_sites`).  ValueError (one line) on unreadable or malformed input."""
    import json

    try:
        with open(diagram_path) as fh:
            doc = json.load(fh)
    except OSError as exc:
        raise ValueError(f"cannot read {diagram_path}: {exc.strerror}") from None
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise ValueError(f"{diagram_path} is not valid JSON: {exc}") from None
    sites = None
    if sites_path is not None:
        from ...sites.reader import read_sites
        sites = read_sites(sites_path, distinct=False, scale=False)
    return verify(doc, sites, progress=progress)


# ============================================================================ the verifier

def _has_pieces(diagram, sites) -> bool:
    """The diagram's (or the given) sites include segments, arcs or elliptic arcs (records
    "segment"/"arc"/"elliptic_arc")."""
    pool = sites if sites is not None else (diagram.get("sites", []) if isinstance(diagram, dict)
                                            else getattr(diagram, "sites", []))
    return any((isinstance(s, dict) and ("segment" in s or "arc" in s or "elliptic_arc" in s))
               or type(s).__name__ in ("Segment", "Arc", "EllipticArc") for s in pool)


@one_blas_thread
@without_cyclic_gc
def verify(diagram, sites=None, *, deadline=None, progress=None, at_infinity: bool = True) -> Certificate:
    """Prove that ``diagram`` is the Voronoi diagram of ``sites`` (default: the diagram's own).

    Parameters
    ----------
    diagram : Diagram or dict
        The diagram or its JSON form (``curvedvoronoi.diagram/2``; /1 is read too).
    sites : list, optional
        The true sites (Point / Circle / Conic).  When given, the diagram's site list must equal
        it (a site the diagram ignores is a problem).
    progress : bool or None
        A tqdm bar over the three stages (vertices, edges, closure and accounting) on stderr; None:
        only for more than 2000 edges.
    deadline : float, optional
        A :func:`time.perf_counter` value: edges not checked by then are not proved
        ("time limit reached: N edges not checked"), and the certificate is not ok.
    at_infinity : bool
        False: no accounting of the unbounded ends (step 4), so never complete nor ok; the flags
        still say what is proved (:mod:`runtime.voronoi.chunked_certificate`).

    Returns
    -------
    Certificate
        ``ok`` only when everything in the module docstring is proved.

    Sites far from the origin are checked in a local frame, translated exactly by a dyadic vector
    (:func:`runtime.voronoi.frame.to_local_frame`: an isometry, so the proof is the reported
    diagram's); problem lines then give coordinates in that frame.

    Examples
    --------
    >>> import curvedvoronoi as cv
    >>> d = cv.voronoi([(0, 0, 1), (4, 0, 1), (2, 4, 1)], certify=False)
    >>> cv.verify(d).ok
    True
    """
    if _has_pieces(diagram, sites):         # points, segments and arcs: their own certificate
        from ...segments.certificate import verify_segments

        return verify_segments(diagram, sites, deadline=deadline)
    T0, timings = time.perf_counter(), {}
    D, sites = to_local_frame(_as_diagram(diagram), sites)
    problems, dsites = [], list(D.sites)
    sites = _input_sites(sites, dsites, problems)
    red = _as_centres(D, sites, dsites, deadline, progress, at_infinity)
    if red is not None:           # equal circles: decided as the diagram of their centres
        return red
    n = len(sites)
    geoms = [site_geometry(s) for s in sites]
    check_document(D, diagram if isinstance(diagram, dict) else None, geoms, problems)
    circular = all(g.kind in ("point", "circle") for g in geoms)
    table = CircleTable(geoms) if circular and n else None
    stats = {"sites": n, "vertices": len(D.vertices), "edges": len(D.edges), "route": "circles" if circular else "mixed"}
    hyp = ["sites pairwise disjoint", "nesting depth <= 1", "vertices simple (transversal bisectors)"]
    timings["input"] = time.perf_counter() - T0

    # ---------------------------------------------------------------- vertices
    t0 = time.perf_counter()
    vinfo, vok = _prove_vertices(D, sites, geoms, table, problems, stats)
    timings["vertices"] = time.perf_counter() - t0
    bar = _stage_bar(progress, len(D.edges))
    _advance(bar, f"{sum(vok)}/{len(vok)} vertices")

    # ---------------------------------------------------------------- edges
    t0 = time.perf_counter()
    eok, ends_inf, intervals = check_edges(D, geoms, table, vinfo, vok, problems, stats, deadline=deadline)
    timings["edges"] = time.perf_counter() - t0
    _advance(bar, f"{sum(eok)}/{len(eok)} edges")

    # ---------------------------------------------------------------- closure + accounting
    t0 = time.perf_counter()
    closure_ok = verify_closure(D, n, problems, intervals)
    account_ok = at_infinity and _accounting(D, n, geoms, table, circular, eok, ends_inf, problems)
    timings["closure"] = time.perf_counter() - t0
    _advance(bar, "closure", close=True)
    complete = closure_ok and account_ok
    ok = complete and all(vok) and all(eok) and not problems
    pairs = sorted({tuple(int(t) for t in e.sites) for e, f in zip(D.edges, eok) if f})
    timings["total"] = time.perf_counter() - T0
    return Certificate(ok, problems, vok, eok, complete, pairs, hyp, stats, timings)


def _prove_vertices(D, sites, geoms, table, problems, stats):
    """:func:`prove_vertices`, and in ``stats["vertex_reach"]`` the [index, radius] of the proved
    vertices whose true empty circles may reach past a local proof's first list of sites
    (:func:`runtime.voronoi.verify.vertices.local_reach`; read by the chunked certificate, which
    hands a chunk only the sites near it, and bounds by these radii how far a proved vertex is
    from its true one)."""
    vinfo, vok = prove_vertices(D, sites, geoms, table, problems, offset=getattr(D, "frame_offset", (0.0, 0.0)))
    stats["vertex_reach"] = [[m, R] for m, (v, f) in enumerate(zip(D.vertices, vok)) if f
                             for R in [local_reach(v, vinfo[v.id]) if v.id in vinfo else math.inf]
                             if R > local_default(v)]
    return vinfo, vok


def _input_sites(sites, dsites, problems) -> list:
    """The true sites: the diagram's own, or the given ones, each compared exactly with the
    diagram's (a count or a site that differs is a problem)."""
    if sites is None:
        return dsites
    sites = [_as_site(s) for s in sites]
    if len(sites) != len(dsites):
        problems.append(f"the diagram has {len(dsites)} sites, the input {len(sites)}")
    for k in range(min(len(sites), len(dsites))):
        if not _same_site(sites[k], dsites[k]):
            problems.append(f"site {k} of the diagram differs from input site {k}")
    return sites


def _accounting(D, n, geoms, table, circular, eok, ends_inf, problems) -> bool:
    """The accounting of the unbounded ends (module docstring): points exactly
    (:func:`verify_accounting_points`); equal disjoint circles as their centres (far away their
    diagram is that of their centres: equal additive weights, ties of collinear centres included);
    other circles by support values, with the exact hull of the discs for ties at infinity
    (circles tangent to one line); conics by support balls (:func:`verify_accounting_conics`)."""
    proved_ends = {t[-1] for t in ends_inf}
    unproved_ends = [e.id for e in D.edges if None in e.ends and e.id not in proved_ends]
    if n and all(g.kind == "point" for g in geoms):
        account_ok = verify_accounting_points(geoms, ends_inf, problems)
    elif circular and len({g.exact.r2 for g in geoms}) == 1:
        # equal disjoint circles: far away their diagram is that of their centres (equal additive
        # weights), so the exact accounting of points applies (ties of collinear centres included)
        account_ok = circles_disjoint(table, problems) and verify_accounting_points(geoms, ends_inf, problems)
    elif circular:
        lines: list = []
        account_ok = verify_accounting(n, table, ends_inf, lines, unproved_ends)
        if not account_ok and all(eok) and circles_disjoint(table, []):
            # ties at infinity (circles tangent to one line): the exact hull of the discs decides
            exact_lines: list = []
            exact_ok = verify_accounting_discs(geoms, ends_inf, exact_lines)
            if exact_ok is not None:
                account_ok, lines = exact_ok, exact_lines
        problems.extend(lines)
    else:
        account_ok = verify_accounting_conics(n, SupportTable(geoms), ends_inf, problems,
                                              unproved_ends=unproved_ends, sites=[g.exact for g in geoms])
    return account_ok


def _as_centres(D, sites, dsites, deadline, progress, at_infinity=True):
    """Equal disjoint circles: the certificate of the diagram of their centres
    (:mod:`runtime.voronoi.verify.equal_circles`: the two diagrams are the same; its refusal is
    the circles' refusal), or None when the sites are not equal circles or not proved disjoint
    (the circle route then decides)."""
    r2 = equal_radius(sites)
    if (r2 is None or len(sites) != len(dsites) or equal_radius(dsites) != r2
            or not all(_same_site(a, b) for a, b in zip(sites, dsites))):
        return None
    T0 = time.perf_counter()
    Dp, centres = centres_diagram(D, dsites, r2)
    c = verify(Dp, centres, deadline=deadline, progress=progress, at_infinity=at_infinity)
    if not c.ok:
        # the centres' diagram is refused: so is the circles' if they are disjoint (the same
        # diagram); if they are not, refusing is still right.  The circle route is not tried.
        # Its vertex and edge flags hold for the circles only where they are proved disjoint
        # (a chunk of the chunked certificate reads them): none when a proved pair is not
        hyp = list(c.hypotheses) + ["equal circles: checked as the diagram of their centres "
                                    "(runtime.voronoi.verify.equal_circles)"]
        apart = not separated_on(dsites, c.delaunay_edges, r2)
        return Certificate(False, c.problems, [f and apart for f in c.vertices], [f and apart for f in c.edges],
                           c.complete, c.delaunay_edges if apart else [], hyp,
                           dict(c.stats, route="equal circles as their centres"), c.timings)
    if separated_on(dsites, c.delaunay_edges, r2):
        return None
    hyp = list(c.hypotheses) + ["equal disjoint circles: proved as the diagram of their centres "
                                "(runtime.voronoi.verify.equal_circles)"]
    stats = dict(c.stats, route="equal circles as their centres")
    timings = dict(c.timings, centres=time.perf_counter() - T0)
    return Certificate(True, [], c.vertices, c.edges, c.complete, c.delaunay_edges, hyp, stats, timings)
