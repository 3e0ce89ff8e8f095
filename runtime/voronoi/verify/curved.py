"""Proofs for Voronoi edges of curved sites (ellipses, parabolas, hyperbolas, circles and points).

Used by :mod:`runtime.voronoi.verify.certificate` for an edge (i, j) between two proved vertices when one of
i, j (or a third site of an end vertex) is an ellipse, where the bisector has no closed form
(thesis §5.1–5.2).  The proof is a chain of strips around the reported polyline
(:mod:`runtime.voronoi.verify.strips`: in each strip the bisector is one monotone arc, closer to
i and j than to every other site); an unbounded edge is proved by the chain up to a point at
``TAIL_CUT`` times the scene's radius and beyond it by :func:`runtime.voronoi.verify.tail.prove_tail`.

The reported polyline only guides the proof: its nodes are moved onto β (float Newton steps
along the segments' normals), nodes where it turns back are dropped, and a segment is split
(its projected midpoint inserted) while the arc strays from the chord by more than a tenth of
the wanted strip half-width (about 3x the stated tolerance, at most 0.03·d·|∇d_i − ∇d_j|, since
the gradient enclosures of the monotonicity test have slack ~ R/d); when a third site stays
undecided the strips are narrowed (factors 0.2, 0.05) and the guide re-split; when the bisector
leaves a strip the guide is refined (segments halved).  Nothing is assumed of the guide: the
strips decide.

:func:`prove_curved_edge` is a generator: its distance requests, guide projections and node
widths (:func:`runtime.voronoi.verify.bisector_guide.project_many`, ``adapt_many``,
``node_width_many``, ``vertex_taper_many``; the guide's refinement lives there) and attempts at a
chain of strips (:func:`prove_widths_many`: widths, flat runs and extensions of all chains in flat
arrays, then :func:`runtime.voronoi.verify.strips.prove_strips_many`) are served for all edges at
once by :func:`runtime.voronoi.verify.site_table.run_lockstep` (:func:`prove_curved_edges`), every
value computed row by row as for one edge alone.  A vertex-less edge
(infinite both ways) is cut at both ends and gets two tails.  A closed edge (around a nested
site) is a chain that closes up.  Edges of a parabola (convex) and of a hyperbola (each branch convex; the
gradient enclosures of :mod:`runtime.voronoi.verify.site_table` hold on discs that do not reach
its conjugate axis) are, up to their unbounded ends (the tails need bounded sites); an edge of a
hyperbola crossing its conjugate axis (a corner of the bisector) is reported not proved.

**Corners on an ellipse's medial axis.**  The bisector of an ellipse and a site nested in it has
a corner where it crosses the ellipse's ridge (:mod:`runtime.voronoi.verify.medial_corners`),
where the guide would turn by more than 60°.  Each crossing is enclosed first (a proved point
x_c of β on the ridge); a drawn polyline farther than its stated tolerance from x_c is refused
(it cuts the corner).  The guide's nodes within 2ε of x_c are replaced by the chord [A, B], A and
B the guide's points at distance ε on either side moved onto β: the corner is then inside one
strip whose direction bisects it, where f is monotone across by the Clarke generalised gradient
(Clarke 1983, Lebourg's theorem; :mod:`runtime.voronoi.verify.strips` (T1)), and the chord's
strip gets the half-width w_c = 1.5·dist(x_c, AB) + 2·(enclosure radius) at both nodes, a
rectangle (above the rule of a quarter of the adjacent segments; kept only where w_c·sin θ is at
most the chord's length and its neighbours', θ the turn at A or B).  The arcs still chain: the
cross-section of the previous strip at A, {A + λ·n : |λ| ≤ w_c}, lies in the chord's rectangle
(at s = λ·sin θ ∈ [−e, L + e] with e ≥ w_c·sin θ, |λ·cos θ| ≤ w_c, its constant half-width), and
so does the next strip's cross-section at B; the arc of β in the neighbour crosses that
cross-section, at a point of β in the chord's rectangle, hence on the chord's arc.  Nothing
else changes: the strips decide.

**Chaining at the nodes.**  Strip l ends at node P (half-width W there) and strip l + 1 starts at
P, turned by θ.  The arc of β in strip l crosses its cross-section at P, {P + λ·n_l : |λ| ≤ W},
at one point X; in the coordinates of strip l + 1, X = (s', λ') = (±λ·sin θ, λ·cos θ), with
s' ∈ [−e, e] (its extension e ≥ W·sin θ before P) and |λ'| ≤ W·cos θ.  Strip l + 1's half-width
there is W + k·s' ≥ W − |k|·W·sin θ for the slope k of its trapezoid, which is at least W·cos θ
when |k| ≤ tan(θ/2).  Then X lies in strip l + 1, whose arc of β, being the only one there,
passes through X: the two arcs join.  The same holds with the roles exchanged (strip l's slope).
(In floats: (T4) puts X at |λ| ≤ W·(1 − 10⁻¹²), a margin far above the rounding of the frames —
|t| = 1 within a few ulps — and sin θ is bounded from the cross product, :func:`turn_sines`.)
Where both slopes exceed tan(θ/2) (the cap s = L + e of strip l alone does not lie in the next
trapezoid: its corner reaches W·(sin²θ + cos θ) > W), :func:`chained_nodes_many` adds a node at
distance W·sin θ along strip l + 1 with half-width W (a rectangle next to P, k = 0).  At the
closing node of a closed chain (half-widths W_a ≤ W_b on its two sides) the strip of W_b is made
flat there and the cross-section of the other is used: W_a·cos θ ≤ W_b.

Length: one proof, the chain of strips of an edge, from its drawn polyline (corners, cut of the
unbounded ends, nodes moved onto β) through its rounds of guides and strip widths to the links
with its tails; each step is a function whose docstring states what it checks, and the chaining
argument above is shared by all of them.
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ...sites.kinds import SiteKind
from ..geometry import EPS
from .site_table import run_lockstep
from .bisector_guide import (AdaptJob, ProjectJob, TaperJob, WidthJob, adapt, adapt_many, cut_outside, node_width,
                             node_width_many, project, project_many, refine, vertex_taper, vertex_taper_many)
from .medial_corners import distance_to_polyline, may_cross_ridges, medial_corners
from .strips import StripsJob, prove_strips_many, rot90

__all__ = ["prove_curved_edge", "prove_curved_edges", "cut_corners", "TAIL_CUT", "TIME_LIMIT"]

TAIL_CUT = 12.0         # the chain proves an unbounded edge up to TAIL_CUT·(scene radius), the tail beyond
EDGE_WORK = 80000       # pieces tested per edge, all attempts together, before giving up
#: an edge that spends EDGE_WORK may go on to EDGE_WORK_MORE, drawing from a pool shared by all the
#: edges of one call, of EXTRA_EDGES such top-ups.  Measured (random ellipses, with the tail retry
#: of runtime.voronoi.verify.tail): 512 sites, 1512 → 1518 of 1520 edges proved, verification
#: 6.7 → 7.1 s; 2000 sites, 5956 → 5959 of 5979, 25 → 30 s.  A pool of 12 proved one more edge at
#: 512 sites but cost 48 s at 2000: the edges that need it lie next to vertices 10³–10⁵ scene
#: units out, where a piece meets many third sites
EDGE_WORK_MORE = 400000
EXTRA_EDGES = 4
LONG = 50000.0          # strips at least (edge length)/LONG wide (3x this), at most 0.03·d·|∇d_i − ∇d_j|
#: the strip widths tried per guide: (factor of the nodes' half-widths, of r + 1 at an end vertex)
WIDTHS = ((1.0, 1e-3), (0.3, 1e-5), (3.0, 1e-3))


_ELLIPSE, _HYPERBOLA = int(SiteKind.ELLIPSE), int(SiteKind.HYPERBOLA)     # codes in SiteTable.kind

#: the message of an edge whose proof was stopped at the deadline
TIME_LIMIT = "time limit reached before the edge was proved"


def prove_curved_edges(table, jobs, deadline=None, sup=None):
    """:func:`prove_curved_edge` for every job (scale, pair, P, v0, v1, tol), side by side.
    Returns their results (ok, message, beyond) in order; (False, :data:`TIME_LIMIT`, []) for
    the edges still running at ``deadline`` (a :func:`time.perf_counter` value).  ``sup``: the
    sites' support functions when they are all bounded and convex (the strips' far pieces,
    :func:`runtime.voronoi.verify.strips.prove_strips_many`)."""
    pool = WorkPool(EXTRA_EDGES * (EDGE_WORK_MORE - EDGE_WORK))

    def strips_many(table_, reqs):
        return prove_strips_many(table_, reqs, sup=sup)

    def widths_many(table_, reqs):
        return prove_widths_many(table_, reqs, sup=sup)
    ridges = may_cross_ridges(table, [job[1] for job in jobs], [job[2] for job in jobs])
    disc = scene_disc(table.geoms) if any(job[3] is None or job[4] is None for job in jobs) else False
    out = run_lockstep([prove_curved_edge(table, *job, pool=pool, ridges=r, disc=disc) for job, r in zip(jobs, ridges)],
                       table,
                       {ChainJob: widths_many, StripsJob: strips_many, ProjectJob: project_many,
                        AdaptJob: adapt_many, WidthJob: node_width_many, TaperJob: vertex_taper_many},
                       deadline=deadline)
    return [(False, TIME_LIMIT, []) if r is None else r for r in out]


class WorkPool:
    """The work shared by the edges of one :func:`prove_curved_edges` call beyond their own
    :data:`EDGE_WORK`: ``left`` pieces, drawn by :meth:`EdgeWork.go_on`."""
    __slots__ = ("left",)

    def __init__(self, left: int):
        self.left = left


class EdgeWork:
    """The pieces one edge may still test: :data:`EDGE_WORK`, decreased by the strips' proofs
    (:func:`runtime.voronoi.verify.strips.prove_strips_many` decreases ``left`` by the pieces it
    tests), topped up once from a :class:`WorkPool` when spent."""
    __slots__ = ("left", "pool", "topped")

    def __init__(self, pool: WorkPool | None = None):
        self.left = EDGE_WORK
        self.pool = pool
        self.topped = False

    def go_on(self) -> bool:
        """After a failed attempt: may the edge go on?  Yes while its work is not overspent
        (``left`` ≥ 0); once it is, after one top-up of at most EDGE_WORK_MORE − EDGE_WORK pieces
        from the pool; no when the pool is empty or the edge was topped up already."""
        if self.left >= 0:
            return True
        more = min(self.pool.left, EDGE_WORK_MORE - EDGE_WORK) if self.pool is not None and not self.topped else 0
        if more <= 0:
            return False
        self.pool.left -= more
        self.left += more
        self.topped = True
        return True


class ChainEnds(NamedTuple):
    """The ends of one edge's chain of strips.  ``v0``, ``v1``: its end vertices (None: an
    unbounded end, cut at ``TAIL_CUT``·``rad``, listed in ``far_ends``: 0 the start, 1 the end);
    ``k0``, ``k1``: the third sites of each vertex; ``h0``, ``h1``: 2·h + tol of each vertex
    (0 at an unbounded end); ``tapers``: per vertex, (sin θ, w_v) of :func:`vertex_taper` or None;
    ``guide``: per vertex, the narrowest strip half-width tried there (the guide must follow β
    within it), None at an unbounded end."""
    v0: object
    v1: object
    k0: tuple | None
    k1: tuple | None
    h0: float
    h1: float
    tapers: list
    guide: tuple
    far_ends: list
    rad: float


class RoundGuide(NamedTuple):
    """The guide of one round of attempts: nodes ``S``, segment lengths ``L``, unit tangents ``T``
    and normals ``N``, upper bounds of the sines of the turns at the inner nodes ``sinang``
    (:func:`turn_sines`), the corners' chords (j, w_c) of :func:`cut_corners`, the
    nodes' half-widths ``wnode`` (:func:`node_width`, narrowed), ``Lmin`` the shorter adjacent
    segment of each node and ``cap`` the vertices' taper at each node."""
    S: np.ndarray
    L: np.ndarray
    T: np.ndarray
    N: np.ndarray
    sinang: np.ndarray
    chords: list
    wnode: np.ndarray
    Lmin: np.ndarray
    cap: np.ndarray


def prove_curved_edge(table, scale, pair, P, v0, v1, tol, closed=False, pool=None, ridges=True, disc=False):
    """Prove an edge of convex sites along its polyline P (ends at the vertices v0, v1; either may
    be None = infinity, then up to a point at ``TAIL_CUT`` times the scene's radius; both None: a
    vertex-less edge, infinite both ways, or with ``closed`` a closed curve around a nested site,
    the chain of strips then closing up).  Returns (ok, message or None, beyond): ``beyond`` lists,
    per unbounded end, a dict with the cut ``point`` and the ``link`` rectangle for
    :func:`runtime.voronoi.verify.tail.prove_tail`.  ``pool``: the :class:`WorkPool` of work
    beyond :data:`EDGE_WORK` shared by the edges of one call (module constants).  ``ridges``:
    False where P crosses no ridge of an ellipse of the pair for certain
    (:func:`runtime.voronoi.verify.medial_corners.may_cross_ridges`: no corner to enclose).
    ``disc``: :func:`scene_disc` of the table's sites when known.  Generator (requests to
    ``table``)."""
    S = np.array(P, float)
    msg = hyperbola_corner(table, pair, S)
    if msg is not None:
        return False, msg, None
    if closed:
        if v0 is not None or v1 is not None or len(S) < 4:
            return False, "a closed edge needs no end vertices and a polyline around its site", None
        if np.hypot(*(S[0] - S[-1])) <= 1e-12 * scale:
            S = S[:-1]
    cuts, msg = (yield from corner_cuts(table, pair, S, v0, v1, tol, closed, scale)) if ridges else ([], None)
    if msg is not None:
        return False, msg, None
    S, far_ends, rad, msg = cut_far_ends(table.geoms, S, v0, v1, closed, disc)
    if msg is not None:
        return False, msg, None
    if len(S) >= 2:
        S = yield from guide_onto_bisector(S, pair, v0, v1, closed)
    if closed:
        if cuts:            # start the chain far from the corners (its first node is kept)
            far = np.min([np.hypot(S[:, 0] - m[0], S[:, 1] - m[1]) for m, _, _ in cuts], axis=0)
            S = np.roll(S, -int(np.argmax(far)), axis=0)
        S = np.vstack([S, S[:1]])           # the chain returns to its first node
    if v0 is not None:
        S[0] = (v0.x, v0.y)
    if v1 is not None:
        S[-1] = (v1.x, v1.y)
    ends = yield from chain_ends(pair, v0, v1, far_ends, rad, scale)
    return (yield from prove_chain(S, pair, ends, cuts, tol, closed, scale, EdgeWork(pool)))


def hyperbola_corner(table, pair, S):
    """The message refusing an edge of a hyperbola whose polyline S crosses (or touches) the
    conjugate axis X = 0, else None: a strip across it always holds a piece whose disc reaches
    it, where the gradient enclosures stop (the nearer branch switches: a corner of β)."""
    for h in pair:
        if table.kind[h] == _HYPERBOLA:
            X0, _ = table.geoms[h].to_canonical(S)
            if np.any(np.sign(X0[:-1]) != np.sign(X0[1:])) or np.any(X0 == 0):
                return f"the edge crosses the conjugate axis of hyperbola {h} (a corner of the bisector)"
    return None


def corner_cuts(table, pair, S, v0, v1, tol, closed, scale):
    """The corners of β on the medial axis of an ellipse of the pair (module docstring, "Corners
    on an ellipse's medial axis"): (cuts, message).  A drawn polyline farther than its stated
    tolerance from a proved corner x_c (dist − r > tol) is refused (it cuts the corner: the
    message).  Each corner (x_c, r, ε) in ``cuts`` is cut by a chord at ε = 2·(node width at
    x_c), at most a tenth of its distance to the end vertices and the other corners, kept where
    ε > 100·r (the corner's enclosure radius).  Generator."""
    cuts = []
    if any(table.kind[h] == _ELLIPSE for h in pair) and len(S) >= 2:
        drawn = np.vstack([S, S[:1]]) if closed else S
        step = max(min(tol, 1e-2 * scale) if math.isfinite(tol) else 1e-2 * scale, 1e-9 * scale)
        found = yield from medial_corners(table, pair, drawn, step, scale)
        for h, m, r in found or ():
            dist = float(distance_to_polyline(m, drawn).min())
            if math.isfinite(tol) and dist - r > tol * (1 + 1e-9) + 1e-12 * scale:
                return cuts, (f"the polyline passes {dist:.3g} from the corner ({m[0]:.9g}, {m[1]:.9g}) of the "
                              f"bisector on the medial axis of site {h} (stated tolerance {tol:.3g})")
        if found:
            wc = yield from node_width(np.array([m for _, m, _ in found]), pair, tol, scale)
            ends = [np.array((v.x, v.y)) for v in (v0, v1) if v is not None]
            for (h, m, r), w_ in zip(found, wc):
                eps = 2.0 * float(w_)
                others = [float(np.hypot(*(m - q))) for q in ends] + \
                         [float(np.hypot(*(m - m2))) for _, m2, _ in found if m2 is not m]
                eps = min([eps] + [0.1 * o for o in others])
                if eps > 100 * r:
                    cuts.append((m, r, eps))
    return cuts, None


def scene_disc(geoms):
    """(centre, rad) of the bounded sites' bounding box: rad half its diagonal plus 1; None when
    no site is bounded."""
    fb = [g.bounding_box() for g in geoms if g.bounded]
    if not fb:
        return None
    bx = np.array(fb, float)
    cen = 0.5 * (bx[:, :2].min(0) + bx[:, 2:].max(0))
    return cen, 0.5 * float(np.hypot(*(bx[:, 2:].max(0) - bx[:, :2].min(0)))) + 1.0


def cut_far_ends(geoms, S, v0, v1, closed, disc=False):
    """Cut the guide S of an unbounded edge at ``TAIL_CUT`` times the scene's radius ``rad`` (half
    the diagonal of the bounded sites' bounding box, plus 1): the chain proves it up to there,
    the tail (:func:`runtime.voronoi.verify.tail.prove_tail`) beyond.  A vertex-less edge is cut
    both ways from its first node inside that disc.  Returns (S, far_ends, rad, message or None),
    ``far_ends`` the unbounded ends (0: start, 1: end).  ``disc``: :func:`scene_disc` of
    ``geoms`` when known."""
    far_ends = [t for t, v in enumerate((v0, v1)) if v is None and not closed]
    rad = 0.0
    if not far_ends:
        return S, far_ends, rad, None
    disc = scene_disc(geoms) if disc is False else disc
    if disc is None:     # only unbounded sites: their tails are not proved (support functions need bounded ones)
        return S, far_ends, rad, "an unbounded end next to unbounded sites only is not proved"
    cen, rad = disc
    Rc = TAIL_CUT * rad
    if len(far_ends) == 1:
        S = cut_outside(S, cen, Rc) if v1 is None else cut_outside(S[::-1], cen, Rc)[::-1]
    else:
        # no vertex: from the first node inside the disc, cut both ways
        inside = np.nonzero(np.hypot(S[:, 0] - cen[0], S[:, 1] - cen[1]) <= Rc)[0]
        if not len(inside):
            return S, far_ends, rad, "the polyline does not come near the sites"
        a_ = int(inside[0])
        S = np.vstack([cut_outside(S[:a_ + 1][::-1], cen, Rc)[::-1][:-1], cut_outside(S[a_:], cen, Rc)])
    return S, far_ends, rad, None


def guide_onto_bisector(S, pair, v0, v1, closed):
    """The nodes of the guide S (at least two) moved onto β (float Newton steps along the
    neighbours' chord; also the cut of an unbounded end; only a guide: the strips decide).  An
    inner node that does not project is dropped (the midpoint of the chord that replaces it is
    projected by :func:`adapt`), and so are inner nodes where the guide turns back by more than
    60° (off-bisector or misplaced points).  Generator."""
    lo_k = 1 if v0 is not None else 0
    hi_k = len(S) - 1 if v1 is not None else len(S)
    ks = np.arange(lo_k, hi_k)
    if len(ks):
        if closed:          # the neighbours of a closed guide are cyclic
            dirs = S[(ks + 1) % len(S)] - S[(ks - 1) % len(S)]
        else:
            dirs = S[np.minimum(ks + 1, len(S) - 1)] - S[np.maximum(ks - 1, 0)]
        Xn, dev = yield from project(S[ks], dirs, pair)
        okn = np.isfinite(dev) & np.isfinite(Xn).all(1)
        S[ks[okn]] = Xn[okn]
        drop = ks[~okn]
        if not closed:
            drop = drop[(drop > 0) & (drop < len(S) - 1)]
        if len(drop) and len(S) - len(drop) >= (4 if closed else 2):
            S = np.delete(S, drop, axis=0)
    for _ in range(len(S)):
        if len(S) < 3:
            break
        sg = S[1:] - S[:-1]
        Tg = sg / np.maximum(np.hypot(sg[:, 0], sg[:, 1]), 1e-300)[:, None]
        cg = (Tg[:-1] * Tg[1:]).sum(1)
        if not cg.min() < 0.5:
            break
        S = np.delete(S, int(np.argmin(cg)) + 1, axis=0)
    return S


def chain_ends(pair, v0, v1, far_ends, rad, scale):
    """The :class:`ChainEnds` of an edge: at a vertex v, its third sites, h = 2·v.h + v.tol, the
    taper of the half-widths (at most w_v + s·sin θ / 2 at arc length s from v, θ the angle there
    between β and the bisector of a third site: :func:`vertex_taper`), and the narrowest strip
    half-width tried there, max(min(1e-5·(r + 1), w_v), 8·h) (the guide must follow β within
    it).  Generator."""
    k0 = tuple(s for s in v0.sites if s not in pair) if v0 is not None else None
    k1 = tuple(s for s in v1.sites if s not in pair) if v1 is not None else None
    h0 = (v0.h * 2 + v0.tol) if v0 is not None else 0.0
    h1 = (v1.h * 2 + v1.tol) if v1 is not None else 0.0
    tapers = []
    for v, ks_ in ((v0, k0), (v1, k1)):
        tapers.append(None if v is None or not ks_ else (yield from vertex_taper(v, pair, ks_)))
    guide = tuple(None if v is None else max(min(1e-5 * (v.r + 1.0), tp[1] if tp else math.inf),
                                             8 * h + 1e-12 * scale)
                  for v, h, tp in ((v0, h0, tapers[0]), (v1, h1, tapers[1])))
    return ChainEnds(v0, v1, k0, k1, h0, h1, tapers, guide, far_ends, rad)


def prove_chain(S_guide, pair, ends, cuts, tol, closed, scale, work):
    """Chains of strips along the guide S_guide, tried with strips narrowed by the factors 1,
    0.2, 0.05 while a third site stays undecided (the strips, and the pieces' discs, too wide);
    the strip half-widths ~ 3·wtol, wtol the stated tolerance or more on a long edge
    ((length)/:data:`LONG`, a bounded piece count).  Returns (ok, message, beyond).  Generator."""
    S = S_guide
    wtol = max(tol, float(np.hypot(*(S[1:] - S[:-1]).T).sum()) / LONG) if len(S) >= 2 else tol
    for narrow in (1.0, 0.2, 0.05):
        done, last_msg = yield from narrowed_chain(S_guide.copy(), pair, ends, cuts, narrow, wtol, closed, scale,
                                                   work)
        if done is not None:
            return done
        if last_msg is None or "a third site" not in last_msg:
            break
    return False, last_msg, None


def narrowed_chain(S, pair, ends, cuts, narrow, wtol, closed, scale, work):
    """Up to three rounds of guides (the second and third refined: segments halved, nodes moved
    onto β) and per round the strip widths of :data:`WIDTHS`, at most four proofs of strips in
    all; a round stops at a strip the bisector leaves or where f is not monotone (the guide is
    refined rather than other widths tried).  Returns (result or None, last message): the result
    (ok, message, beyond) ends the edge (proved, degenerate, or its work spent).  Generator."""
    last_msg = None
    attempts = 0
    for round_ in range(3):
        if round_:
            S = yield from refine(S, pair)
        S, g, msg = yield from round_guide(S, pair, ends, cuts, narrow, wtol, closed, scale)
        if msg is not None:
            return (False, msg, None), last_msg
        if g is None:
            last_msg = "polyline turns by more than 60 degrees"
            continue
        for wfac, endfac in WIDTHS:
            # with flat runs at the turns, so that consecutive strips hold each other's node
            # cross-sections (module docstring, "Chaining at the nodes")
            ok, msg, W = yield from prove_widths(g, ends, wfac, endfac, closed, scale, pair, work)
            if ok:
                return (True, None, tail_links(g, W, ends)), None
            last_msg = msg
            attempts += 1
            if W is None:
                continue
            if not work.go_on():
                return (False, msg + " (work limit of the edge reached)", None), last_msg
            if attempts >= 4:
                break
            if "bisector leaves" in msg or "monotonicity" in msg:
                break       # refine the guide rather than try other widths
        if attempts >= 4:
            break
    return None, last_msg



def turn_sines(Ta, Tb):
    """(sin_lo, sin_up): bounds of sin θ for the turns θ ∈ [0, π/2] between the float unit vectors
    Ta and Tb (rows), from |Ta × Tb| (|Ta|, |Tb| within 2 ulps of 1; the cross product within
    2 ulps absolute), accurate near θ = 0 where √(1 − cos²θ) loses half the digits."""
    Ta, Tb = np.asarray(Ta, float), np.asarray(Tb, float)
    cr = np.abs(Ta[..., 0] * Tb[..., 1] - Ta[..., 1] * Tb[..., 0])
    return np.maximum(cr * (1 - 1e-14) - 4 * EPS, 0.0), np.minimum(cr * (1 + 1e-14) + 4 * EPS, 1.0)


def round_guide(S, pair, ends, cuts, narrow, wtol, closed, scale):
    """The guide of one round: S split where the arc strays from the chord by more than
    0.1·narrow of the strip width (:func:`adapt`), segments shorter than 1e-12·scale dropped,
    the corners cut by their chords (:func:`cut_corners`).  Returns (S, guide, message): the
    message ends the edge (a degenerate polyline); guide None where the polyline turns by more
    than 60° (cos < 1/2, also from the last segment to the first when closed).  Generator."""
    S = yield from adapt(S, pair, 0.1 * narrow, wtol, scale, ends=ends.guide)
    seg = S[1:] - S[:-1]
    L = np.hypot(seg[:, 0], seg[:, 1])
    if np.any(L <= 1e-12 * scale):
        keep = np.concatenate([[True], L > 1e-12 * scale])
        S = S[keep]
        seg = S[1:] - S[:-1]
        L = np.hypot(seg[:, 0], seg[:, 1])
    if len(S) < 2:
        return S, None, "degenerate polyline"
    chords = []
    if cuts:
        S, chords = yield from cut_corners(S, cuts, pair)
        seg = S[1:] - S[:-1]
        L = np.hypot(seg[:, 0], seg[:, 1])
        if np.any(L <= 1e-12 * scale):
            return S, None, "degenerate polyline at a corner"
    T = seg / L[:, None]
    N = rot90(T)
    cosang = np.clip((T[:-1] * T[1:]).sum(1), -1, 1)
    cos_wrap = float(np.clip((T[-1] * T[0]).sum(), -1, 1)) if closed else 1.0
    if np.any(cosang < math.cos(math.radians(60))) or cos_wrap < math.cos(math.radians(60)):
        return S, None, None
    sinang = turn_sines(T[:-1], T[1:])[1]
    wnode = narrow * (yield from node_width(S, pair, wtol, scale))
    Lmin = np.minimum(np.concatenate([[L[-1] if closed else L[0]], L]),
                      np.concatenate([L, [L[0] if closed else L[-1]]]))
    arc = np.concatenate([[0.0], np.cumsum(L)])
    cap = np.full(len(S), np.inf)
    for tp, sv in ((ends.tapers[0], arc), (ends.tapers[1], arc[-1] - arc)):
        if tp is not None:
            cap = np.minimum(cap, tp[1] + 0.5 * tp[0] * sv)
    return S, RoundGuide(S, L, T, N, sinang, chords, wnode, Lmin, cap), None


class ChainJob:
    """One attempt at the chain of strips of an edge (:func:`prove_widths`): the round's guide ``g``
    (:class:`RoundGuide`), its :class:`ChainEnds`, the factors (``wfac``, ``endfac``) of
    :data:`WIDTHS`, ``closed``, ``scale``, the pair and the edge's :class:`EdgeWork`."""

    __slots__ = ("g", "ends", "wfac", "endfac", "closed", "scale", "pair", "work")

    def __init__(self, g, ends, wfac, endfac, closed, scale, pair, work):
        self.g, self.ends, self.wfac, self.endfac, self.closed = g, ends, wfac, endfac, closed
        self.scale, self.pair, self.work = scale, pair, work


def prove_widths(g, ends, wfac, endfac, closed, scale, pair, work):
    """One attempt at the chain of strips along the guide ``g``: the node half-widths
    (:func:`strip_widths_many`), the flat runs at the turns (:func:`chained_nodes_many`), the
    extensions (:func:`strip_extensions_many`) and (T1)–(T4) on the strips
    (:func:`runtime.voronoi.verify.strips.prove_strips_many`).  Returns (ok, message, W), W the
    node half-widths before the flat runs (for :func:`tail_links`); W None (message
    :data:`NO_CHAIN`) where the strips do not chain.  Generator: the attempts of all edges are
    served together (:func:`prove_widths_many`)."""
    return (yield ChainJob(g, ends, wfac, endfac, closed, scale, pair, work))


#: the message of an attempt whose strips do not chain (:func:`chained_nodes_many`)
NO_CHAIN = "the strips do not chain at a turn of the polyline (no room for a flat run)"


def prove_widths_many(table, jobs, sup=None):
    """:func:`prove_widths` for many :class:`ChainJob` at once: the nodes of all guides in flat
    arrays (each guide's nodes contiguous), every value computed row by row as for one guide
    alone, then one :func:`runtime.voronoi.verify.strips.prove_strips_many` for the chains that
    chain (``sup`` as there).  Returns (ok, message, W) per job."""
    nj = len(jobs)
    W, jn = strip_widths_many(jobs)
    closed = np.array([jb.closed for jb in jobs], bool)
    scale = np.array([jb.scale for jb in jobs], float)
    S2, W2, jn2, chains = chained_nodes_many(np.concatenate([jb.g.S for jb in jobs]), W, jn, closed, scale)
    h0 = np.array([jb.ends.h0 for jb in jobs], float)
    h1 = np.array([jb.ends.h1 for jb in jobs], float)
    T2, N2, L2, e_lo, e_hi = strip_extensions_many(S2, W2, jn2, closed, scale, h0, h1)
    nodes = np.bincount(jn2, minlength=nj)
    nb = np.concatenate([[0], np.cumsum(nodes)])
    sb = np.concatenate([[0], np.cumsum(np.maximum(nodes - 1, 0))])
    wb = np.concatenate([[0], np.cumsum(np.bincount(jn, minlength=nj))])
    idx = np.nonzero(chains)[0].tolist()
    reqs = [StripsJob(S2[nb[t]:nb[t + 1]], T2[sb[t]:sb[t + 1]], N2[sb[t]:sb[t + 1]], L2[sb[t]:sb[t + 1]],
                      e_lo[sb[t]:sb[t + 1]], e_hi[sb[t]:sb[t + 1]], W2[nb[t]:nb[t + 1]], jobs[t].pair,
                      jobs[t].ends.k0, jobs[t].ends.k1, jobs[t].work) for t in idx]
    out = [(False, NO_CHAIN, None)] * nj
    for t, (ok, msg) in zip(idx, prove_strips_many(table, reqs, sup=sup) if reqs else []):
        out[t] = (ok, msg, W[wb[t]:wb[t + 1]])
    return out


def strip_widths_many(jobs):
    """The node half-widths W of many attempts (:class:`ChainJob`), flat, and each node's job.
    Per guide: about 3x the stated tolerance (``wfac``·wnode), at most a quarter of the adjacent
    segments and the vertices' taper, at least 1e-12·scale; a corner's chord gets its w_c at both
    nodes where w_c·sin θ is at most the adjacent lengths (the strips still chain: module
    docstring); at an end vertex at most 0.05·L and ``endfac``·(r + 1), at least 8·h (the
    transversality test (T3) needs the gradient enclosures, slack ~ R/d, well below the angle
    between the bisectors)."""
    nj = len(jobs)
    cnt = np.array([len(jb.g.S) for jb in jobs], int)
    jn = np.repeat(np.arange(nj), cnt)
    wfac = np.array([jb.wfac for jb in jobs], float)[jn]
    scale = np.array([jb.scale for jb in jobs], float)
    W = np.minimum(np.minimum(0.25 * np.concatenate([jb.g.Lmin for jb in jobs]),
                              np.concatenate([jb.g.wnode for jb in jobs]) * wfac),
                   np.concatenate([jb.g.cap for jb in jobs]))
    W = np.maximum(W, 1e-12 * scale[jn])
    first = np.concatenate([[0], np.cumsum(cnt)[:-1]]).astype(int)
    for t, jb in enumerate(jobs):
        if jb.g.chords:
            _chord_widths(W[first[t]:first[t] + cnt[t]], jb.g)
    endfac = np.array([jb.endfac for jb in jobs], float)
    for side, at in ((0, first), (1, first + cnt - 1)):
        vs = [jb.ends.v0 if side == 0 else jb.ends.v1 for jb in jobs]
        has = np.array([v is not None for v in vs], bool)
        if not has.any():
            continue
        r = np.array([v.r if v is not None else 0.0 for v in vs], float)
        h = np.array([jb.ends.h0 if side == 0 else jb.ends.h1 for jb in jobs], float)
        L = np.array([jb.g.L[0] if side == 0 else jb.g.L[-1] for jb in jobs], float)
        we = np.maximum(np.minimum(np.minimum(W[at], 0.05 * L), endfac * (r + 1.0)), 8 * h + 1e-12 * scale)
        W[at[has]] = we[has]
    return W, jn


def _chord_widths(W, g):
    """The half-width w_c of each corner's chord (j, w_c) at both its nodes, in place, where
    w_c·sin θ (θ the turns at its ends) is at most the lengths of the chord and its neighbours."""
    L, sinang = g.L, g.sinang
    for jc, w_c in g.chords:
        sins = [sinang[t_] for t_ in (jc - 1, jc) if 0 <= t_ < len(sinang)]
        lens = [L[t_] for t_ in (jc - 1, jc, jc + 1) if 0 <= t_ < len(L)]
        if w_c * max(sins + [0.0]) <= min(lens):
            W[jc] = W[jc + 1] = w_c


def _segments(S, jn):
    """The segments of the flat polylines S (chain of each node ``jn``, each chain contiguous):
    (start node, length, unit tangent, chain of each segment, turns), a turn m between the
    segments m and m + 1 of one chain (at the node start[m] + 1)."""
    si = np.nonzero(jn[:-1] == jn[1:])[0]
    seg = S[si + 1] - S[si]
    L = np.hypot(seg[:, 0], seg[:, 1])
    T = seg / L[:, None]
    sc = jn[si]
    return si, L, T, sc, np.nonzero(sc[:-1] == sc[1:])[0]


def strip_extensions_many(S2, W2, jn, closed, scale, h0, h1):
    """The strips of the chained guides (S2, W2; the chain of each node ``jn``, each chain
    contiguous; ``closed``, ``scale``, ``h0``, ``h1`` one per chain): unit tangents, normals,
    lengths, and the extensions beyond each end, e ≥ W·sin θ at a turn θ (W the larger node
    half-width of the neighbouring strip, sin θ bounded above by :func:`turn_sines`; module
    docstring, "Chaining at the nodes"), plus 2·h at an end vertex (its enclosure, h = ``h0``,
    ``h1``) and max(W)·sin θ at the closing node of a closed chain; 1e-12·scale for rounding.
    Returns (T2, N2, L2, e_lo, e_hi), the segments of all chains in order."""
    si, L2, T2, sc, tr = _segments(S2, jn)
    N2 = rot90(T2)
    sin2 = turn_sines(T2[tr], T2[tr + 1])[1]
    wn = np.maximum(W2[si], W2[si + 1])
    e_lo, e_hi = np.zeros(len(si)), np.zeros(len(si))
    e_lo[tr + 1] = wn[tr] * sin2
    e_hi[tr] = wn[tr + 1] * sin2
    e_lo = e_lo + 1e-12 * scale[sc]
    e_hi = e_hi + 1e-12 * scale[sc]
    starts = np.nonzero(np.concatenate([[True], sc[1:] != sc[:-1]])[:len(sc)])[0]
    ends_ = np.concatenate([starts[1:] - 1, [len(sc) - 1]])[:len(starts)].astype(int)
    e_lo[starts] = e_lo[starts] + 2 * h0[sc[starts]]
    e_hi[ends_] = e_hi[ends_] + 2 * h1[sc[ends_]]
    for a, b in zip(starts.tolist(), ends_.tolist()):
        if closed[sc[a]]:           # the cap between the last and the first rectangle
            sin_wrap = float(turn_sines(T2[b], T2[a])[1])
            cap = max(W2[si[a]], W2[si[b] + 1]) * sin_wrap
            e_lo[a] += cap
            e_hi[b] += cap
    return T2, N2, L2, e_lo, e_hi


def strip_extensions(S2, W2, ends, closed, scale):
    """:func:`strip_extensions_many` for one chain (``ends``: its h0, h1)."""
    return strip_extensions_many(np.asarray(S2, float), np.asarray(W2, float), np.zeros(len(S2), int),
                                 np.array([closed]), np.array([float(scale)]), np.array([float(ends.h0)]),
                                 np.array([float(ends.h1)]))


def tail_links(g, W, ends):
    """The chain's rectangle at each unbounded end, for the link with its tail
    (:func:`runtime.voronoi.verify.tail.prove_tail`): the end ``point``, the scene's ``rad`` and
    the ``link`` (origin, tangent, normal, length, half-width min(W) of the end segment, and the
    abscissa min(L/2, rad/4) from the far end)."""
    S, L, T, N = g.S, g.L, g.T, g.N
    beyond = []
    for t in ends.far_ends:
        l = 0 if t == 0 else len(L) - 1
        sx = min(0.5 * L[l], 0.25 * ends.rad)
        beyond.append({"point": tuple(S[0] if t == 0 else S[-1]), "rad": ends.rad,
                       "link": (S[l].copy(), T[l].copy(), N[l].copy(), float(L[l]),
                                float(min(W[l], W[l + 1])), sx if t == 0 else float(L[l]) - sx)})
    return beyond


def chained_nodes_many(S, W, jn, closed, scale):
    """The polylines S with node half-widths W (the chain of each node ``jn``, each chain
    contiguous; ``closed`` and ``scale`` one per chain), with a node added where consecutive
    trapezoids would not chain (module docstring, "Chaining at the nodes"): at a turn θ of node j
    where both adjacent strips' half-widths change faster than tan(θ/2) per unit length (θ
    bounded below, :func:`turn_sines`: a turn too small to tell from 0 counts as one), a node at
    distance W_j·sin θ (θ bounded above, plus rounding) along the next segment, of half-width
    W_j, makes that strip a rectangle next to the node (:func:`_flat_runs`).  At the closing node
    of a closed chain the strip with the larger node half-width is made flat there
    (:func:`_closing_run`).  Repeated while nodes are added, at most (nodes + 2) times per chain.
    Returns (S, W, jn, ok): the chains that chain (rows in chain order) and ``ok`` per chain,
    False where such a node does not fit in half a segment (the chain would not be proved to
    join there) or the nodes kept coming."""
    S, W, jn = np.asarray(S, float), np.asarray(W, float), np.asarray(jn, int)
    nc = len(closed)
    cap = np.bincount(jn, minlength=nc) + 2
    ok = np.ones(nc, bool)
    done = []
    for it in range(int(cap.max()) if nc else 0):
        if not len(jn):
            break
        si, L, T, sc, tr = _segments(S, jn)
        m, a, w, failed = _flat_runs(S, W, jn, closed, scale, (si, L, T, sc, tr))
        ok[failed] = False
        grow = np.zeros(nc, bool)
        grow[sc[m]] = True
        ok[grow & (it + 1 >= cap)] = False
        go = grow & ok
        fin = ~grow[jn] & ok[jn]
        done.append((S[fin], W[fin], jn[fin]))
        keep = go[sc[m]]
        m, a, w = m[keep], a[keep], w[keep]
        p = si[m]
        X = np.where((a > 0)[:, None], S[p] + a[:, None] * T[m], S[p + 1] + a[:, None] * T[m])
        order = np.lexsort((np.concatenate([np.zeros(len(S)), a]),
                            np.concatenate([np.zeros(len(S)), np.ones(len(a))]),
                            np.concatenate([np.arange(len(S)), p])))
        S, W, jn = np.vstack([S, X])[order], np.concatenate([W, w])[order], np.concatenate([jn, sc[m]])[order]
        rows = go[jn]
        S, W, jn = S[rows], W[rows], jn[rows]
    S = np.concatenate([d[0] for d in done]) if done else np.zeros((0, 2))
    W = np.concatenate([d[1] for d in done]) if done else np.zeros(0)
    jn = np.concatenate([d[2] for d in done]) if done else np.zeros(0, int)
    order = np.argsort(jn, kind="stable")
    return S[order], W[order], jn[order], ok


def _flat_runs(S, W, jn, closed, scale, segs):
    """The nodes to add (:func:`chained_nodes_many`): (segment m, signed distance a from its start
    (a > 0) or from its end (a < 0), half-width w) of each, and the chains where one does not fit
    in half a segment.  At an inner node j between segments m, m + 1 with slopes k (half-width
    change per unit length) where min(|k_m|, |k_{m+1}|) > tan(θ/2) (tan(θ/2) bounded below by
    sin θ/(1 + cos θ) from the lower sine bound), a = W_j·sin θ (upper bound, plus rounding) along
    m + 1 if a < L_{m+1}/2, else back along m if a < L_m/2."""
    si, L, T, sc, tr = segs
    k = (W[si + 1] - W[si]) / L                         # slope of each trapezoid's half-width
    cos = np.clip((T[tr] * T[tr + 1]).sum(1), -1.0, 1.0)
    sin_lo, sin_up = turn_sines(T[tr], T[tr + 1])
    half = sin_lo / (1 + np.minimum(cos + 4 * EPS, 1.0))        # ≤ tan(θ/2)
    bad = np.minimum(np.abs(k[tr]), np.abs(k[tr + 1])) > half * (1 - 1e-9)
    b = tr[bad]
    wj = W[si[b] + 1]
    a = wj * sin_up[bad] * (1 + 1e-9) + 1e-12 * scale[sc[b]]
    nxt = a < 0.5 * L[b + 1]
    fit = nxt | (a < 0.5 * L[b])
    m, a, w = np.where(nxt, b + 1, b)[fit], np.where(nxt, a, -a)[fit], wj[fit]
    failed = [sc[b][~fit]]
    extra = []
    for c in np.nonzero(closed)[0].tolist():
        lo, hi = int(np.searchsorted(sc, c, "left")), int(np.searchsorted(sc, c, "right"))
        x = _closing_run(W, si, L, T, k, scale[c], lo, hi) if hi - lo >= 2 else ()
        if x == (None,):
            failed.append([c])
        elif x:
            extra.append(x)
    if extra:
        m = np.concatenate([m, [x[0] for x in extra]]).astype(int)
        a = np.concatenate([a, [x[1] for x in extra]])
        w = np.concatenate([w, [x[2] for x in extra]])
    return m, a, w, np.concatenate(failed).astype(int)


def _closing_run(W, si, L, T, k, scale, lo, hi):
    """The node to add at the closing node of a closed chain (segments lo..hi − 1), as a tuple
    (segment, signed distance, half-width), (None,) where it does not fit, () where none is
    needed: with the half-widths W_a at the end of the last strip and W_b at the start of the
    first, the cross-section of the narrower one, turned by θ, must lie in the other:
    (W_b − |k|·W_a·sin θ)·(1 − 10⁻¹²) ≥ W_a·cos θ for W_a ≤ W_b (k the wider strip's slope), else
    that strip is made flat over W_a·sin θ (:func:`chained_nodes_many`)."""
    Tl, Tf = T[hi - 1], T[lo]
    cw = min(float(np.clip(Tl @ Tf, -1.0, 1.0)) + 4 * EPS, 1.0)
    sw = float(turn_sines(Tl, Tf)[1])
    wa, wb = float(W[si[hi - 1] + 1]), float(W[si[lo]])    # end of the last strip, start of the first
    ok_ = ((wb - abs(k[lo]) * wa * sw) * (1 - 1e-12) >= wa * cw) if wa <= wb else \
        ((wa - abs(k[hi - 1]) * wb * sw) * (1 - 1e-12) >= wb * cw)
    if ok_:
        return ()
    a = min(wa, wb) * sw * (1 + 1e-9) + 1e-12 * scale
    if wa <= wb and a < 0.5 * L[lo]:
        return (lo, a, wb)
    if wa > wb and a < 0.5 * L[hi - 1]:
        return (hi - 1, -a, wa)
    return (None,)


def chained_nodes(S, W, closed: bool, scale: float):
    """:func:`chained_nodes_many` for one chain: (S, W) with the added nodes, or (None, None) where
    the strips would not be proved to join."""
    S2, W2, _, ok = chained_nodes_many(S, W, np.zeros(len(S), int), np.array([closed]), np.array([float(scale)]))
    return (S2, W2) if ok[0] else (None, None)


def cut_corners(S, cuts, pair):
    """The guide S with its inner nodes within 2ε of each corner (m, r, ε) replaced by the chord
    [A, B]: A, B the points at distance ε from m towards the nearest kept nodes on either side,
    moved onto β (float Newton steps; only a guide).  Returns (S, chords), chords a list of (j,
    w_c): segment j is the chord of a corner and w_c its half-width (module docstring).
    Generator."""
    for m, r, eps in cuts:
        dist = np.hypot(S[:, 0] - m[0], S[:, 1] - m[1])
        inner = np.arange(1, len(S) - 1)
        run = inner[dist[inner] < 2 * eps]
        if len(run):
            if not np.array_equal(run, np.arange(run[0], run[-1] + 1)):
                continue
            prev, nxt = int(run[0]) - 1, int(run[-1]) + 1
        else:
            k = int(np.argmin(distance_to_polyline(m, S)))
            prev, nxt = k, k + 1
        if dist[prev] < 2 * eps or dist[nxt] < 2 * eps:
            continue            # an end of the chain next to the corner: left as it is
        U = np.array([S[prev] - m, S[nxt] - m])
        U /= np.hypot(U[:, 0], U[:, 1])[:, None]
        Xn, dev = yield from project(m + eps * U, eps * U, pair)
        if not (np.all(np.isfinite(dev)) and np.all(np.isfinite(Xn))):
            continue
        S = np.vstack([S[:prev + 1], Xn, S[nxt:]])
    chords = []
    for m, r, eps in cuts:
        d = distance_to_polyline(m, S)
        j = int(np.argmin(d))
        A, B = S[j], S[j + 1]
        if min(np.hypot(*(A - m)), np.hypot(*(B - m))) < 0.5 * eps:
            continue            # not cut: the guide has a node at the corner
        chords.append((j, 1.5 * d[j] + 2 * r + 1e-12 * (1 + float(np.abs(m).sum()))))
    return S, chords
