"""Edges of a diagram with elliptic pieces (step 3 of :mod:`runtime.segments.certificate` for the
pieces of :mod:`runtime.segments.certificate_ellipses`; thesis §2.2 harmless sites, ch. 4 foot
points).

An edge (i, j) with end vertices v₀, v₁ (proved, listing i and j, of positive radius) is proved to
be the arc γ([θ₀, θ₁]) of an explicit curve γ with a common distance ρ(θ), parametrised so that
by construction |γ(θ) − c_i(θ)| = |γ(θ) − c_j(θ)| = ρ(θ) for contacts c_i, c_j on the closures:

* **foot curve** (i an elliptic piece e(φ) = c + cos φ M + sin φ N, j a point, a segment's line or an
  arc's circle): γ(φ) = e(φ) + σ t(φ) ν(φ), ν the unit outward normal, σ = +1 outside the ellipse,
  −1 inside, and t linear in the partner's equation: t = −|D|²/(2σ ν·D) for a point p (D = e − p),
  t = (n̂·e + c₀)/(τ − σ n̂·ν) for the line n̂·x + c₀ = 0 touched on the side τ, and
  t = (ρ₂² − |D|²)/(2(σ ν·D − σ₂ρ₂)) for a circle (c₂, ρ₂) touched from the side σ₂ (D = e − c₂);
  the parameter is φ itself;
  for a point partner p = e(ψ) on the piece's own ellipse the closed form t = t_E(φ) of
  :func:`runtime.segments.certificate_ellipse_secant.end_foot_t` (inside only, no 0/0 at φ = ψ);
* **normal line** at a piece's end e that is a point site (the edge of e and its piece) or at a
  smooth joint of two pieces: γ(t) = e + t w, w the exact normal, ρ = |t||w|; through e itself
  when the end vertices lie on both sides (ρ = 0 at e only, where both sites of the pair are at
  distance 0 and every other site is farther: e is on the diagram);
* **junction** (:class:`runtime.segments.certificate_ellipse_junction.EndCurve`): the edge of a
  piece and its end E from a vertex on E's normal line to a vertex on the foot curve of the piece
  and E — the normal line down to E's centre of curvature, then that foot curve;
* **major axis** (:class:`runtime.segments.certificate_ellipse_axis.AxisCurve`): two pieces
  joined at an end J of their ellipse's major axis, from a vertex on J's normal line through J's
  centre of curvature to the vertex where the mirror feet reach the far end of the shorter piece;
  ρ in closed form, the contacts by an exact identity, point sites by an exact rule;
* **points**: the perpendicular bisector of two points (an edge with no piece whose end vertex
  lists a piece), ρ = |γ − p_i|.

The sides σ, τ, σ₂ (and the normal's way) are read at the end vertices, where they must agree.
An end vertex v lies on γ at the parameter θ_v: for a foot curve, the unique interior strict local
minimum of f_v(φ) = |v − e(φ)|² (:func:`runtime.segments.ellipse_pieces.interior_minimum`, at most
one on a piece) when the vertex's distance r is proved attained there
(:func:`runtime.segments.ellipse_pieces.nearest_verdict`) — then v = e(θ_v) + σ r ν(θ_v) and the
partner's linear equation along that normal has the one solution t = r, so γ(θ_v) = v —, else the
exact end parameter where the vertex's own equation is the normal line at that end (the choice of
:mod:`runtime.segments.certificate_vertices`, made by the same float tests
:func:`runtime.segments.certificate_ellipses.touches_inside` and
:func:`runtime.segments.certificate_ellipses.past_centre_of_curvature`); for lines the exact
projection.  The balls θ_v at both ends are disjoint and ordered θ₀ < θ₁.

On pieces J of [θ₀, θ₁] (halved while undecided), with the box (X, Y) ⊇ γ(J):

(C0) ρ(J) > 0;
(C1) the contacts are nearest points: on an elliptic piece of the pair nothing of the piece nearer
     than the contact — outside by convexity; inside, on a piece between two vertices of its
     ellipse, by the secant factor L ≥ 0 at the piece's two ends
     (:func:`runtime.segments.certificate_ellipse_curves.secant_nearest`; a point-site end not
     in the pair is a third site, proved farther in (C2), which is L > 0 there), else
     ``nearest_verdict`` with Φ = J, or the end parameter: f'' > 0 around it and f > ρ² on the
     rest, so d_i(γ(θ)) = ρ(θ); a segment partner's foot in [0, 1]; an arc
     partner's direction in its closed range with ρ₂ + σ₂ρ ≥ 0; a point partner: none;
(C2) every other site k is farther: d_k(X, Y) > ρ(J) (rigorous distance balls,
     :meth:`runtime.segments.certificate_sites.SiteTable.distance`; sites outside the k-d tree's
     query pass unevaluated) — or, on the piece J next to an end vertex where k ties (d_k(v) = r),
     the **derivative cone**: g = d_k∘γ − ρ has g(θ_v) ≥ 0 and, by Lebourg's mean value theorem
     for the Lipschitz d_k, g(θ) − g(θ_v) ∈ (θ − θ_v)(∂d_k(box)·γ'(J) − ρ'(J)) with γ(θ) − v in
     (θ − θ_v)·conv γ'(J) ⊆ the box of γ'(J); a positive ball (negative at the far end) proves
     g > 0 on the open edge there.  Gradient enclosures: points, segments and arcs
     (:func:`runtime.segments.certificate_pieces.distance_gradient`); an elliptic piece
     (x − e(Φ))/|x − e(Φ)| where its nearest point is proved the interior minimum Φ, an end's
     where it is proved that end (the hull of both ends' where both).  A point site k on the
     ellipse of the touched piece is farther exactly when the secant factor L(ψ_k) > 0: no double
     zero at a vertex whose contact is k itself.  On the normal line at a piece's point-site
     end, a piece of the same ellipse tied at an end vertex is farther all along an edge that
     leaves that vertex outwards (the secant factor grows with the signed outward distance:
     :func:`normal_line_monotone`).  A runs' anchor is an end vertex or the end of a
     piece where g > 0 was proved directly (:func:`_pieces`).
(R2) a curve k ending at a point site p of the edge has p as its unique nearest point (the tie is
     p's): segments and arcs by their rules, an elliptic piece by the end factor
     ±W(φ, x) > 0 on a cover of its range (:func:`runtime.segments.certificate_ellipse_secant.
     end_factor`), where W vanishes at a vertex listing k and p by the sign of ∓e'(m)·γ' along a
     run from it (W is affine in x).

Every point of the open arc is then equidistant from i and j and strictly nearer to them than to
any other site (a tie with an end of the pair's curves included: it is a site k), so the arc is a
whole edge of the true diagram between its two vertices.  The polyline lies within the stated
tolerance (:func:`runtime.segments.certificate_curves.polyline_bound`; the chord bound of a piece
[t₀, t₁] is the smaller of Δθ²/8 · max|γ''|, the interpolation error of a C² curve, and ℓ²κ/8 —
:func:`runtime.segments.certificate_ellipse_curves.sag_bound`).

Not covered (reported as limits): infinite ends of such edges, two elliptic pieces that are not
joined at a smooth joint (no closed-form t), vertices of radius 0, and edges whose end vertex
lists a piece but whose pair is not one of the above.

The curves and gradients are :mod:`runtime.segments.certificate_ellipse_curves`; the pieces'
crossings and hull :mod:`runtime.segments.certificate_ellipse_sites`.

Public API: :func:`needs_piece_proof`, :func:`prove_piece_edge`, :func:`prove_edges_with_pieces`,
:func:`normal_line_monotone`.

Length: one proof — the routing, the vertex parameters, the pieces with their derivative runs and
the tails read and extend the same edge state; the curves and the site tests are apart.
"""
from __future__ import annotations

import math
import time
from fractions import Fraction
from types import SimpleNamespace

import numpy as np
from flint import arb

from ..certify.foot import to_arb
from ..voronoi.verify.problems import Problem, fault
from .certificate_curves import polyline_bound
from .certificate_ellipse_axis import AxisCurve, axis_edge
from .certificate_edges import EdgeProof, prove_edges
from .certificate_ellipse_curves import FootCurve, NormalLine, PointsLine, gradient, widened_nearest
from .certificate_ellipse_junction import EndCurve
from .certificate_ellipse_sites import same_ellipse
from .certificate_ellipse_tails import foot_poles, foot_tail, normal_ray_farther
from .certificate_hull import infinite_key
from .certificate_ellipse_secant import end_factor, end_tangent, on_ellipse, secant_factor
from .certificate_ellipses import normal_residual, past_centre_of_curvature, touches_inside
from .certificate_sites import ARC, ELLIPSE, POINT, SEGMENT, SiteTable, direction_key, sq
from .ellipse_pieces import closest_at_an_end, interior_foot, interior_minimum, nearest_verdict, piece_point_ball

__all__ = ["needs_piece_proof", "prove_piece_edge", "prove_edges_with_pieces", "normal_line_monotone"]

#: initial pieces of an edge's parameter interval, most pieces tested, deepest halving
FIRST = 8
MAX_PIECES = 200
MAX_DEPTH = 24
#: pieces tested for all the edges of one diagram: this many plus :data:`EDGE_SHARE` per edge
#: routed here (the rest are reported unchecked: a limit)
DIAGRAM_PIECES = 400
EDGE_SHARE = 40


# ====================================================================== routing
def needs_piece_proof(T: SiteTable, D, e, vindex) -> bool:
    """The edge has an elliptic piece among its sites, or an end vertex listing a piece or an end
    of a piece (where the other edge proofs' tie covers would need a piece's gradient)."""
    sites = [int(s) for s in e.sites]
    if any(0 <= s < T.n and T.kind[s] == ELLIPSE for s in sites):
        return True
    for v in e.ends:
        if v is None or v not in vindex:
            continue
        for s in D.vertices[vindex[v]].sites:
            s = int(s)
            if not 0 <= s < T.n:
                continue
            if T.kind[s] == ELLIPSE or (T.kind[s] == POINT and any(T.kind[c] == ELLIPSE for c in T.incident.get(s, ()))):
                return True
    return False


def _end_code(T: SiteTable, s: int, listed):
    """The codes of piece s's ends that a vertex listing ``listed`` touches by the end equation:
    point-site ends listed, joints whose other curve is listed."""
    out = []
    for code in T.ends[s]:
        if code >= 0 and code in listed:
            out.append(code)
        elif code <= -2 and any(o in listed and o != s for o in T.joint_curves(code)):
            out.append(code)
    return out


def _foot_param(T: SiteTable, s: int, vp, v):
    """("inside", θ_v) or ("end", code, θ_v) of vertex v on piece s (module docstring), or None."""
    P = T.piece[s]
    xr, yr, rr = float(v.x), float(v.y), float(v.radius)
    ends = _end_code(T, s, vp.listed)
    ends = [c for c in ends if not (c <= -2 and _past_joint(T, c, xr, yr))]
    if not ends or touches_inside(P, xr, yr, rr):
        phi = interior_foot(P, xr, yr)
        if phi is None:
            return None
        Phi = interior_minimum(P, vp.x, vp.y, phi)
        if Phi is None:
            return None
        tied = tuple(T.which_end(s, c) for c in ends if c >= 0)
        if nearest_verdict(P, vp.x, vp.y, vp.r, Phi, tied_ends=tied) is not True:
            return None
        return ("inside", Phi)
    if len(ends) == 2:
        # a short piece touched at one end (on its normal line), its other end tied: the end
        # equation of runtime.segments.certificate_vertices, the same float choice
        ends.sort(key=lambda c: normal_residual(P, T.which_end(s, c), xr, yr))
        if ends[1] <= -2:
            return None
    if not ends:
        return None
    p0, p1 = P.arb_params()
    return ("end", ends[0], p0 if T.which_end(s, ends[0]) == 0 else p1)


def _past_joint(T: SiteTable, code: int, xr: float, yr: float) -> bool:
    curves = T.joint_curves(code)
    if any(T.kind[o] != ELLIPSE for o in curves):
        return False
    s = min(curves)
    return past_centre_of_curvature(T.piece[s], T.which_end(s, code), xr, yr)


def _sign(x) -> int | None:
    return 1 if x > 0 else (-1 if x < 0 else None)


def _curve(T: SiteTable, D, i: int, j: int, vps, verts):
    """The curve of the edge and the parameter balls of its end vertices, or a message."""
    ki, kj = T.kind[i], T.kind[j]
    if ki == POINT and kj == POINT:
        c = PointsLine(T, i, j)
        return c, [c.vertex_param(vp) for vp in vps]
    joints = T.shared_joint(i, j)
    if ki == ELLIPSE and kj == ELLIPSE:
        if not joints:
            return "two elliptic pieces that are not joined: their bisector is not covered"
        contacts = [[_foot_param(T, t, vp, v) for t in (i, j)] for vp, v in zip(vps, verts)]
        if any((g or ("",))[:2] != ("end", joints[0]) for got in contacts for g in got):
            # past the joint's centre of curvature: the major axis with its mirror feet
            return axis_edge(T, i, j, joints[0], vps, contacts)
        return _normal_line(T, joints[0], [(s, T.which_end(s, joints[0])) for s in (i, j)], vps)
    if ELLIPSE not in (ki, kj):
        return "an edge of two sites that are not elliptic pieces, next to an elliptic piece: not covered"
    s, k = (i, j) if ki == ELLIPSE else (j, i)
    if kj == POINT or ki == POINT:
        got = [_foot_param(T, s, vp, v) for vp, v in zip(vps, verts)]
        if T.is_endpoint(k, s) and all(g is not None and g[:2] == ("end", k) for g in got):
            return _normal_line(T, k, [(s, T.which_end(s, k))], vps)
        if EndCurve.applies(T, s, k) and None not in got and (
                sorted(g[0] for g in got) == ["end", "inside"] or
                sorted(g[1] for g in got) == sorted(T.ends[s]) and all(g[0] == "end" for g in got)):
            return _junction(T, s, k, vps, verts, got)
    # the foot curve: sides at the end vertices
    sides = None
    P = T.piece[s]
    thetas = []
    for vp, v in zip(vps, verts):
        got = _foot_param(T, s, vp, v)
        if got is None:
            return f"the contact of an end vertex with elliptic piece {s} is not enclosed"
        th = got[-1]
        ex, ey = piece_point_ball(P, th)
        Mx, My, Nx, Ny = (to_arb(q) for q in (*P.M, *P.N))
        tx, ty = -th.sin() * Mx + th.cos() * Nx, -th.sin() * My + th.cos() * Ny
        sg = _sign((vp.x - ex) * ty - (vp.y - ey) * tx)
        if T.kind[k] == SEGMENT:
            ax, ay, bx, by = T.arb_ends(k)
            s2 = _sign(-(by - ay) * (vp.x - ax) + (bx - ax) * (vp.y - ay))
        elif T.kind[k] == ARC:
            cx, cy, r2 = T.arb_arc(k)
            s2 = _sign(sq(vp.x - cx) + sq(vp.y - cy) - r2 * r2)
        else:
            s2 = 1
        if sg is None or s2 is None or (sides is not None and sides != (sg, s2)):
            return "the sides of the bisector are not decided at its end vertices"
        sides = (sg, s2)
        thetas.append(th)
    c = FootCurve(T, s, k, *sides)
    return c, thetas


def _inner_side(T: SiteTable, s: int, vp, th) -> bool:
    """The vertex lies on the inner side of the tangent at e(θ) (σ = −1), proved."""
    P = T.piece[s]
    ex, ey = piece_point_ball(P, th)
    Mx, My, Nx, Ny = (to_arb(q) for q in (*P.M, *P.N))
    tx, ty = -th.sin() * Mx + th.cos() * Nx, -th.sin() * My + th.cos() * Ny
    return bool((vp.x - ex) * ty - (vp.y - ey) * tx < 0)


def _junction(T: SiteTable, s: int, p: int, vps, verts, got):
    """The edge of piece s and its end p from a vertex on p's normal line (before the centre of
    curvature) to a vertex on the foot curve γ_E (:class:`runtime.segments.
    certificate_ellipse_junction.EndCurve`); the vertex on γ_E lists p at distance r with the
    contact e(Φ) inside at distance r on the inner side — or the contact at the piece's other
    end, on that end's normal line —, so it is γ_E(Φ) (t_E is the one solution of |x − E| = t
    along that normal, Φ ≠ ψ)."""
    c = EndCurve(T, s, p)
    thetas = []
    for vp, g in zip(vps, got):
        if g[0] == "end" and g[1] != p:
            # the contact at the piece's other end E' (the vertex on E''s normal line, E listed):
            # on the inner side it is γ_E at that end's parameter by the same argument
            th = c.foot_param(g[2])
            if not th > 0 or not _inner_side(T, s, vp, g[2]):
                return "an end vertex of the edge of a piece's end is not proved on the inner foot curve"
        elif g[0] == "end":
            th = c.line_param(vp)
            if not th < 0:
                return "an end vertex of the edge of a piece's end is not proved before the centre of curvature"
        else:
            th = c.foot_param(g[1])
            if not th > 0 or not _inner_side(T, s, vp, g[1]):
                return "an end vertex of the edge of a piece's end is not proved on the inner foot curve"
        thetas.append(th)
    return c, thetas


def _normal_line(T: SiteTable, code: int, pieces, vps):
    s, which = pieces[0]
    tx, ty = T.leaving(s, code)
    w = (ty, -tx)
    c = NormalLine(T, code, w, pieces)
    ts = [c.vertex_param(vp) for vp in vps]
    if None in {_sign(t) for t in ts}:
        return "an end vertex of the normal line is not proved off its foot"
    # an edge through the end e itself (vertices on both sides, ρ = 0 at e) is one edge of e
    # and the piece when e is a point site, of the two pieces at a smooth joint e: e is at
    # distance 0 from both and positive from every other site, the normal line on both sides
    return c, ts


# ====================================================================== the proof
def _end_vertex_proof(v, i: int, j: int, vindex, vproofs, limit, wrong):
    """The proof of the end vertex ``v`` of an edge (i, j), or the failed :class:`EdgeProof` (its
    problem appended): the end must be a vertex of the diagram (else a fault), proved (else a
    limit: the edge's end point is not known to be on the diagram) and list both i and j (else a
    fault: the edge's curve, equidistant from i and j, cannot end there)."""
    if v not in vindex:
        return wrong(f"end {v} is not a vertex of the diagram")
    vp = vproofs[vindex[v]]
    if not vp.ok:
        return limit(f"its end vertex {v} is not proved")
    if i not in vp.listed or j not in vp.listed:
        return wrong(f"its end vertex {v} does not list both its sites")
    return vp


def prove_piece_edge(T: SiteTable, D, e, vindex, vproofs, problems, budget=None) -> EdgeProof:
    """Prove edge ``e`` by the module docstring's argument; problems appended.  ``budget``: a
    one-element list, the pieces left for the diagram (spent here)."""
    budget = [DIAGRAM_PIECES] if budget is None else budget
    name = f"edge {e.id} (sites {', '.join(map(str, e.sites))})"
    i, j = (int(s) for s in e.sites) if len(e.sites) == 2 else (-1, -1)
    pair = tuple(s for s in (i, j) if 0 <= s < T.n)

    def limit(msg, *extra):
        problems.append(Problem(f"{name}: {msg}", kind="edge", edge=e.id, sites=pair + extra, fault=False))
        return EdgeProof(False)

    def wrong(msg, *extra):
        problems.append(fault(f"{name}: {msg}", kind="edge", edge=e.id, sites=pair + extra))
        return EdgeProof(False)
    if len(pair) != 2 or i == j:
        return wrong("needs two distinct valid sites")
    if None in e.ends:
        return _unbounded(T, D, e, i, j, vindex, vproofs, limit, wrong, budget)
    if e.ends[0] == e.ends[1]:
        return wrong("both ends are the same vertex")
    vps, verts = [], []
    for v in e.ends:
        vp = _end_vertex_proof(v, i, j, vindex, vproofs, limit, wrong)
        if isinstance(vp, EdgeProof):
            return vp
        if not vp.r > 0:
            return limit(f"its end vertex {v} has radius 0: not covered next to elliptic pieces")
        vps.append(vp)
        verts.append(D.vertices[vindex[v]])
    got = _curve(T, D, i, j, vps, verts)
    if isinstance(got, str):
        return limit(got)
    curve, thetas = got
    if thetas[0] < thetas[1]:
        order = (0, 1)
    elif thetas[1] < thetas[0]:
        order = (1, 0)
    else:
        return limit("its two end vertices are too close to order along its curve")
    lo_v, hi_v = order
    lo, hi = thetas[lo_v], thetas[hi_v]
    msg = _pieces(T, curve, i, j, lo, hi, vps[lo_v], vps[hi_v], (verts[lo_v], verts[hi_v]), budget)
    if msg is not None:
        return limit(msg[0], *msg[1:]) if not msg[0].startswith("!") else wrong(msg[0][1:], *msg[1:])
    Pn = np.asarray(e.polyline, dtype=float).reshape(-1, 2)
    if len(Pn) < 2 or not np.isfinite(Pn).all():
        return wrong("needs a finite polyline of at least two points")
    curve.at = {id(vps[0]): thetas[0], id(vps[1]): thetas[1]}
    msg = polyline_bound(curve, Pn, float(e.tolerance), lo, hi, vps)
    if msg is not None:
        return limit(msg)          # a bound above the tolerance: not proved (not proved wrong)
    return EdgeProof(True)


def _support_below(T: SiteTable, k: int, w, level, strict: bool = False) -> bool:
    """Every point y of the closed site k has w·y ≤ level (< when ``strict``; exact rationals; an
    elliptic piece by the corners of its parallelogram of frame coordinates — a piece between two
    vertices of its ellipse has monotone frame coordinates cos φ, sin φ, so it lies in the
    parallelogram they span —; arcs are not covered: False)."""
    if T.kind[k] == ARC:
        return False
    if T.kind[k] == ELLIPSE:
        s = T.sites[k]
        pts = [(s.c[0] + u[0] * s.M[0] + v[1] * s.N[0], s.c[1] + u[0] * s.M[1] + v[1] * s.N[1])
               for u in (s.ua, s.ub) for v in (s.ua, s.ub)]
    else:
        pts = [T.a[k], T.b[k]]
    if strict:
        return all(w[0] * Fraction(x) + w[1] * Fraction(y) < level for x, y in pts)
    return all(w[0] * Fraction(x) + w[1] * Fraction(y) <= level for x, y in pts)


def _unbounded(T: SiteTable, D, e, i, j, vindex, vproofs, limit, wrong, budget) -> EdgeProof:
    """An unbounded edge of two points next to elliptic pieces: the perpendicular bisector
    O + t w proved on pieces from its end vertex (or a middle point) to a parameter S beyond, and
    beyond S by monotonicity (the tails of :mod:`runtime.segments.certificate_rules`): with
    x = O + s w∞ and P = p_i, |x − y|² − |x − P|² = C_y + 2s w∞·(P − y) is nondecreasing in s for
    every point y of a site k whose support in the direction w∞ is at most w∞·P, so d_k² − ρ²,
    their minimum, stays above its positive value at S.  A curve k ending at p_i or p_j (R2: its
    nearest point must be that end e alone) is covered by the same monotonicity: g_y =
    |x − y|² − |x − e|² is positive at S for every y ≠ e of k (R2, proved on the piece ending at
    S) and nondecreasing in s (k's support in the direction w∞ is at most w∞·e = w∞·P, checked
    with the other sites), so e stays k's unique nearest point beyond S."""
    if sorted((T.kind[i], T.kind[j])) == sorted((ELLIPSE, POINT)):
        return _unbounded_piece(T, D, e, i, j, vindex, vproofs, limit, wrong, budget)
    if not (T.kind[i] == POINT and T.kind[j] == POINT):
        return limit("an infinite end of an edge next to an elliptic piece is not proved (only two points' "
                     "bisectors and a piece's edges with a point are covered)")
    c = PointsLine(T, i, j)
    Pn = np.asarray(e.polyline, dtype=float).reshape(-1, 2)
    if len(Pn) < 2 or not np.isfinite(Pn).all():
        return wrong("needs a finite polyline of at least two points")
    tp = [float(c.param(arb(float(p[0])), arb(float(p[1]))).mid()) for p in (Pn[0], Pn[-1])]
    fin = [n for n, v in enumerate(e.ends) if v is not None]
    vps = [None, None]
    for n in fin:
        vp = _end_vertex_proof(e.ends[n], i, j, vindex, vproofs, limit, wrong)
        if isinstance(vp, EdgeProof):
            return vp
        vps[n] = vp
    if fin:
        f = fin[0]
        tv = c.vertex_param(vps[f])
        far = tp[1 - f]
        sg = 1 if far > float(tv.mid()) else -1
        S = arb(float(tv.mid()) + sg * max(abs(far - float(tv.mid())), 1.0))
        lo, hi, vlo, vhi = (tv, S, vps[f], None) if sg > 0 else (S, tv, None, vps[f])
        signs = [sg]
    else:
        if tp[0] == tp[1]:
            return wrong("the polyline does not show which way the edge goes to infinity")
        a_, b_ = sorted(tp)
        lo, hi, vlo, vhi = arb(a_ - 1.0), arb(b_ + 1.0), None, None
        signs = [1, -1]
    pair = tuple(sorted((i, j)))
    P = T.a[i]
    infinite = []
    for sg in signs:
        wq = (sg * (-(T.a[j][1] - T.a[i][1])), sg * (T.a[j][0] - T.a[i][0]))
        level = wq[0] * P[0] + wq[1] * P[1]
        bad = [k for k in range(T.n) if k not in (i, j) and not _support_below(T, k, wq, level)]
        if bad:
            return limit(f"site {bad[0]} reaches beyond the tail's monotone zone", bad[0])
        infinite.append((pair, direction_key(wq)))
    verts = tuple(None if vp is None else D.vertices[vindex[e.ends[vps.index(vp)]]] for vp in (vlo, vhi))
    msg = _pieces(T, c, i, j, lo, hi, vlo, vhi, verts, budget)
    if msg is not None:
        problems_msg = limit(msg[0], *msg[1:])
        problems_msg.infinite = infinite
        return problems_msg
    lo_b = lo if vlo is not None else None
    hi_b = hi if vhi is not None else None
    msg = polyline_bound(c, Pn, float(e.tolerance), lo_b, hi_b, vps)
    if msg is not None:
        out = limit(msg)
        out.infinite = infinite
        return out
    return EdgeProof(True, infinite)


def _unbounded_piece(T: SiteTable, D, e, i, j, vindex, vproofs, limit, wrong, budget) -> EdgeProof:
    """An unbounded edge of an elliptic piece s and a point p from its one end vertex v, outside
    the ellipse (:mod:`runtime.segments.certificate_ellipse_tails`): the curve of :func:`_curve`
    — the foot curve of s and p, or the normal line at p when p is an end of s —; the way to
    infinity is read from the polyline's far point.  The foot curve: its pole φ∞ beyond θ_v, the
    tail [φ_S, φ∞) by :func:`runtime.segments.certificate_ellipse_tails.foot_tail`, the finite part
    [θ_v, φ_S] by the pieces; the normal line: the open outer ray by
    :func:`runtime.segments.certificate_ellipse_tails.normal_ray_farther`, the part from v to past
    the end by the pieces when v lies inside.  Then the polyline's bound, its far side open."""
    s, p = (i, j) if T.kind[i] == ELLIPSE else (j, i)
    fin = [n for n, v in enumerate(e.ends) if v is not None]
    if len(fin) != 1:
        return limit("an edge of an elliptic piece and a point with no end vertex: not covered")
    f = fin[0]
    vp = _end_vertex_proof(e.ends[f], i, j, vindex, vproofs, limit, wrong)
    if isinstance(vp, EdgeProof):
        return vp
    if not vp.r > 0:
        return limit(f"its end vertex {e.ends[f]} has radius 0: not covered next to elliptic pieces")
    v = D.vertices[vindex[e.ends[f]]]
    Pn = np.asarray(e.polyline, dtype=float).reshape(-1, 2)
    if len(Pn) < 2 or not np.isfinite(Pn).all():
        return wrong("needs a finite polyline of at least two points")
    got = _curve(T, D, i, j, [vp], [v])
    if isinstance(got, str):
        return limit(got)
    c, (tv,) = got
    far = Pn[-1] if f == 0 else Pn[0]
    tf = float(c.param(arb(float(far[0])), arb(float(far[1]))).mid())
    sg = 1 if tf > float(tv.mid()) else -1
    pair = tuple(sorted((i, j)))
    if isinstance(c, NormalLine):
        which = T.which_end(s, p)
        out = 1 if which == 0 else -1            # w is the outward normal at a start, inward at an end
        if sg != out:
            return limit("its infinite end does not go along the outer normal of the piece's end")
        u = (out * c.wq[0], out * c.wq[1])
        msg = normal_ray_farther(T, s, p, u)
        if msg is not None:
            return limit(msg)
        infinite = [(pair, direction_key(u))]
        if tv * sg > 0:
            lo = hi = None                       # v is on the outer ray: all of it is proved
        else:
            S = arb(sg * max(abs(float(tv.mid())) / 4, 1e-6))
            lo, hi = (tv, S) if sg > 0 else (S, tv)
    elif isinstance(c, FootCurve):
        poles = [q for q in foot_poles(T.piece[s], T.a[p]) if (q > tv if sg > 0 else q < tv)]
        if not poles:
            return limit("no pole of its foot curve lies beyond its end vertex in the piece's range")
        poles.sort(key=lambda q: float(q.mid()))
        pole = poles[0] if sg > 0 else poles[-1]
        th_s, msg = foot_tail(T, c, p, tv, pole, sg)
        if msg is not None:
            return limit(msg)
        Mx, My, Nx, Ny = (to_arb(q) for q in (*T.piece[s].M, *T.piece[s].N))
        key = infinite_key(T, i, j, (-pole.sin() * My + pole.cos() * Ny, pole.sin() * Mx - pole.cos() * Nx), False)
        if key is None:
            return limit("the key of its infinite end is not decided")
        infinite = [(pair, key)]
        lo, hi = (tv, arb(th_s)) if sg > 0 else (arb(th_s), tv)
    else:
        return limit("an infinite end of this edge of a piece and a point is not covered")
    vps = [None, None]
    vps[f] = vp
    if lo is not None:
        vlo, vhi = (vp, None) if sg > 0 else (None, vp)
        verts = (v, None) if sg > 0 else (None, v)
        msg = _pieces(T, c, i, j, lo, hi, vlo, vhi, verts, budget)
        if msg is not None:
            out_ = limit(msg[0], *msg[1:])
            out_.infinite = infinite
            return out_
    c.at = {id(vp): tv}
    lo_b, hi_b = (tv, None) if sg > 0 else (None, tv)
    msg = polyline_bound(c, Pn, float(e.tolerance), lo_b, hi_b, vps)
    if msg is not None:
        out_ = limit(msg)
        out_.infinite = infinite
        return out_
    return EdgeProof(True, infinite)


def _pieces(T: SiteTable, c, i, j, lo, hi, vlo, vhi, verts, budget):
    """(C0)–(C2) on pieces of [lo, hi]; None when proved, else (message, sites…).

    A site k tied at the first vertex (d_k = r there) may be passed on a piece by the sign
    g'(J) > 0 of the derivative cone, computed only where k is not proved farther directly; at
    the end, walking from the first vertex, every piece so passed must start at an *anchor* —
    the vertex (g(θ_v) ≥ 0) or the end of a piece where g > 0 was proved directly (distance ball,
    secant test, outside the query) — reached through pieces passed the same way (then g grows
    from the anchor across the run: Lebourg's mean value theorem piece by piece); symmetrically
    g' < 0 walking down from the last vertex.  The same runs serve the keys of
    :func:`_end_owned` and :func:`_w_owned`."""
    a, b = arb(lo.lower()), arb(hi.upper())
    L = float(b.mid()) - float(a.mid())
    ties = []
    for vp in (vlo, vhi):
        if vp is None:
            ties.append(set())
            continue
        near = T.near(float(vp.x.mid()), float(vp.y.mid()), float(vp.r.upper()) * 1.001 + 1e-9)
        ties.append({k for k in near if k not in (i, j) and not T.distance(k, vp.x, vp.y) > vp.r})
    # the pieces whose end vertex lies on their normal line at an end of the edge (R2 cones)
    normals = []
    for vp, v in ((vlo, verts[0]), (vhi, verts[1])):
        here = set()
        for k in (vp.listed if vp is not None else ()):
            if T.kind[k] == ELLIPSE:
                got = _foot_param(T, k, vp, v)
                if got is not None and got[0] == "end" and got[1] in (i, j):
                    here.add(k)
        normals.append(here)
    wzones = tuple(_w_zone(T, vp, (i, j)) for vp in (vlo, vhi))
    line_rule = _line_rule(T, i, j, vlo, vhi) if isinstance(c, PointsLine) else (
        c.farther_rule() if isinstance(c, AxisCurve) else None)
    step = L / FIRST
    cuts = sorted({float(a.mid()) + m * step for m in range(1, FIRST)} |
                  {x for x in getattr(c, "cuts", ()) if float(a.mid()) < x < float(b.mid())})
    bounds = [float(a.mid())] + cuts + [float(b.mid())]
    todo = [(x0, x1, 0) for x0, x1 in zip(bounds, bounds[1:])][::-1]
    first, last = float(a.mid()), float(b.mid())
    count = 0
    done = []                       # (pa, pb, {k: sign of g' proved}, {k: sign relied on})
    while todo:
        pa, pb, depth = todo.pop()
        count += 1
        budget[0] -= 1
        if count > MAX_PIECES or budget[0] < 0:
            return ("the piece budget is spent before the edge is proved",)
        J = (a if pa == first else arb(pa)).union(b if pb == last else arb(pb))
        slopes: dict = {}
        relied: dict = {}
        bad = _piece(T, c, i, j, J, ties, normals, slopes, relied, pa == first, pb == last, wzones, line_rule)
        if bad is None:
            done.append((pa, pb, slopes, relied))
            continue
        if depth >= MAX_DEPTH:
            return bad
        m = (pa + pb) / 2
        todo += [(m, pb, depth + 1), (pa, m, depth + 1)]
    done.sort(key=lambda d: d[0])
    keys = {key for _, _, _, rel in done for key in rel}
    for key in keys:
        for way in ("lo", "hi"):
            if not any(key in rel and rel[key][1] == way for _, _, _, rel in done):
                continue
            sgn, anchored = None, True          # g ≥ 0 at the end vertex (tied or farther there)
            for _pa, _pb, sl, rel in (done if way == "lo" else done[::-1]):
                if key in rel and rel[key][1] == way:
                    if not anchored or (sgn is not None and rel[key][0] != sgn):
                        k = key[1] if isinstance(key, tuple) else key
                        return (f"site {k} is not proved farther next to an end vertex (the derivative run is "
                                "broken)", k)
                    sgn = rel[key][0]           # g grows away from the anchor across the piece
                elif sl.get(("direct", key)):
                    anchored = True             # g > 0 on the closed piece: a new anchor at its end
                elif not (sgn is not None and sl.get(key) == sgn):
                    anchored = False
    return None


def _end_owned(T: SiteTable, c, k: int, p: int, J, X, Y, R, ends, slopes, relied) -> bool:
    """Elliptic piece k's nearest point is its end p alone at the curve's points over J: f'' > 0
    next to p and f > ρ² on the rest (:func:`widened_nearest`), and f increasing away from p,
    h = (x − p)·L < 0 for the direction L leaving p into k — on the box, or by the derivative
    cone along a run from an end vertex on the normal line at p (h = 0 there; h' = γ'·L < 0 after
    the first vertex, > 0 before the last)."""
    if T.kind[k] != ELLIPSE:
        return False
    P = T.piece[k]
    which = T.which_end(k, p)
    p0, p1 = P.arb_params()
    if not widened_nearest(P, X, Y, R, p0 if which == 0 else p1, which):
        return False
    lx, ly = (to_arb(v) for v in T.leaving(k, p))
    px, py = T.pt_arb(p)
    if (X - px) * lx + (Y - py) * ly < 0:
        slopes[("direct", ("L", k))] = True
        return True
    gx, gy = c.dxy(J)
    slope = gx * lx + gy * ly
    key = ("L", k)
    slopes[key] = 1 if slope > 0 else (-1 if slope < 0 else 0)
    if k in ends[0] and slopes[key] < 0:
        relied[key] = (-1, "lo")
        return True
    if k in ends[1] and slopes[key] > 0:
        relied[key] = (1, "hi")
        return True
    return False


#: sub-intervals of a piece's parameter range for the end-ownership factor W
W_PARTS = 32


def _w_cover(P):
    p0, p1 = P.arb_params()
    return [p0 + (p1 - p0) * arb(q / W_PARTS).union(arb((q + 1) / W_PARTS)) for q in range(W_PARTS)]


def _w_value(T: SiteTable, k: int, p: int, Phi, X, Y):
    P = T.piece[k]
    which = T.which_end(k, p)
    psi = P.arb_params()[which]
    return (1 if which == 0 else -1) * end_factor(P, psi, T.pt_arb(p), Phi, X, Y)


def _w_zone(T: SiteTable, vp, pair) -> dict:
    """{(k, p): parameter sub-intervals q} at an end vertex listing p, a site of the edge and an
    end of elliptic piece k, where ±W(Φ_q, v) > 0 is not proved: the runs of :func:`_w_owned`
    start there (at a proved vertex every site is at distance ≥ r = |v − p|, so ±W ≥ 0 on the
    whole piece there)."""
    out = {}
    if vp is None:
        return out
    for p in pair:
        if not (0 <= p < T.n) or p not in vp.listed:
            continue
        for k in T.incident.get(p, ()):
            if T.kind[k] == ELLIPSE and T.ends[k] is not None and p in T.ends[k]:
                cover = _w_cover(T.piece[k])
                out[(k, p)] = {q for q, Phi in enumerate(cover) if not _w_value(T, k, p, Phi, vp.x, vp.y) > 0}
    return out


def _w_owned(T: SiteTable, c, k: int, ps, J, X, Y, wzones, slopes, relied) -> bool:
    """Elliptic piece k's nearest points over the box are among its ends ``ps`` (sites of the edge,
    all at distance ρ), by the end factor of
    :func:`runtime.segments.certificate_ellipse_secant.end_factor`: on each sub-interval Φ_q of a
    cover of the piece's range ±W_p > 0 for one p of ``ps`` (then f > ρ² there but at p).  Where
    ±W_p vanishes at an end vertex v listing p, W is affine in x, so
    ±W(φ, γ(θ)) = ±W(φ, v) ∓ e'(m)·(γ(θ) − v) ≥ (θ − θ_v)·(∓e'(m(Φ_q))·conv γ') > 0 along a run
    of pieces from v with that slope's sign proved (the runs of :func:`_pieces`)."""
    if T.kind[k] != ELLIPSE:
        return False
    P = T.piece[k]
    ends = []
    for p in ps:
        which = T.which_end(k, p)
        zone = wzones[0].get((k, p), set()) | wzones[1].get((k, p), set())
        ends.append((p, 1 if which == 0 else -1, P.arb_params()[which], zone))
    dxy = c.dxy(J) if any(e[3] for e in ends) else None
    for q, Phi in enumerate(_w_cover(P)):
        accepted = False
        for p, sgn, psi, zone in ends:
            key = ("W", k, p, q)
            if q in zone:
                tx, ty = end_tangent(P, psi, Phi)
                d = -sgn * (tx * dxy[0] + ty * dxy[1])
                slopes[key] = 1 if d > 0 else (-1 if d < 0 else 0)
            if not accepted and _w_value(T, k, p, Phi, X, Y) > 0:
                slopes[("direct", key)] = True
                accepted = True
        for p, sgn, psi, zone in ends:
            if accepted:
                break
            key = ("W", k, p, q)
            if q in wzones[0].get((k, p), ()) and slopes.get(key) == 1:
                relied[key] = (1, "lo")
                accepted = True
            elif q in wzones[1].get((k, p), ()) and slopes.get(key) == -1:
                relied[key] = (-1, "hi")
                accepted = True
        if accepted:
            continue
        a, b = Phi.lower(), Phi.upper()
        parts = [arb(a) + (arb(b) - arb(a)) * arb(m / 8).union(arb((m + 1) / 8)) for m in range(8)]
        if not all(any(_w_value(T, k, p, F, X, Y) > 0 for p, *_ in ends) for F in parts):
            return False
    return True


def _same_ellipse(T: SiteTable, k: int, s: int) -> bool:
    if T.kind[k] != ELLIPSE:
        return False
    a, b = T.sites[k], T.sites[s]
    return a.c == b.c and a.M == b.M and a.N == b.N


def _line_rule(T: SiteTable, i: int, j: int, vlo, vhi):
    """For the bisector γ(t) = O + t w of points i, j: a test ``e ↦ bool`` that an exact point e
    is farther than ρ on the whole open edge.  a(t) = |γ − e|² − |γ − p_i|² =
    |O − e|² − |O − p_i|² + 2t w·(p_i − e) is affine in t, and a(t_v) ≥ 0 at a proved end vertex
    v whenever e is a point site or a point of a site's closure (d_k(v) ≥ r: a tie where k is
    listed, the vertex's empty circle elsewhere).  So a > 0 on the open edge when the slope is
    positive and the lower end is a vertex, negative and the upper end is a vertex, or zero with
    a > 0 at O (rationals: no rounding).  Nearly collinear points make the slope tiny, where boxes
    would need ~1/slope pieces.  ``farther.curve(k)``: the same for every point of a segment or an
    elliptic piece k at once, when the slope has the sign above for all of them (its support in
    the direction ±w strictly below ±w·p_i)."""
    (xi, yi), (xj, yj) = T.a[i], T.a[j]
    ox, oy = (xi + xj) / 2, (yi + yj) / 2
    wx, wy = -(yj - yi), xj - xi
    memo: dict = {}

    def farther(e) -> bool:
        e = tuple(e)
        if e not in memo:
            xe, ye = e
            slope = wx * (xi - xe) + wy * (yi - ye)
            if slope > 0:
                memo[e] = vlo is not None
            elif slope < 0:
                memo[e] = vhi is not None
            else:
                memo[e] = (ox - xe) ** 2 + (oy - ye) ** 2 - (ox - xi) ** 2 - (oy - yi) ** 2 > 0
        return memo[e]

    def curve(k: int) -> bool:
        # every point y of a segment or an elliptic piece k with the slope's sign (its support
        # strictly below w·p_i, or above): a_y > a_y(t_v) ≥ 0 on the open edge for each y, so
        # d_k² − ρ², their minimum over k's compact closure, is positive there too
        level = wx * xi + wy * yi
        return ((vlo is not None and _support_below(T, k, (wx, wy), level, strict=True)) or
                (vhi is not None and _support_below(T, k, (-wx, -wy), -level, strict=True)))
    farther.curve = curve
    return farther


def _owned_end_farther(T: SiteTable, k: int, i: int, j: int, X, Y, line_rule) -> bool:
    """Curve k's nearest point to every point of the box is one of its ends e (``owned_by_end``),
    and e is farther than ρ there: a point site q ∉ {i, j} — then d_k = d_q on the box, and q is a
    site of the table, tested on the same piece (or outside the query: farther on the whole box) —
    or, on two points' bisector, any end by the exact affine rule of :func:`_line_rule` (a smooth
    joint's point lies on the closure of k, so d_k(v) ≥ r bounds it at the end vertices) — on the
    major axis of :mod:`runtime.segments.certificate_ellipse_axis` by its exact rule, likewise."""
    if not T.is_curve(k) or T.ends[k] is None:
        return False
    for q in T.ends[k]:
        if q in (i, j):
            continue
        site = q >= 0 and T.kind[q] == POINT
        if not site and line_rule is None:
            continue
        if T.owned_by_end(k, q, X, Y) is True and (site or line_rule(T.pt(q))):
            return True
    return False


def normal_line_monotone(T: SiteTable, c, k: int, ties) -> bool:
    """On the normal line x = e + t w at a point-site end e = e(ψ) of piece s, a piece k of the same
    ellipse tied at an end vertex v is farther than ρ on the whole open edge when the edge leaves v
    outwards.  By the secant identity (:mod:`runtime.segments.certificate_ellipse_secant`; the
    contact is e(ψ) all along the line), |x − e(φ)|² − ρ² = 4 sin²((φ − ψ)/2) L(φ) with
    L = |e'(m)|² + σ(x) ρ(x) det(M, N)/|e'(ψ)|, where σρ is the signed distance of x from e along
    the outward normal: L is affine and strictly increasing in it.  At v, L(φ) ≥ 0 for every φ of
    k (the proved vertex: d_k(v) ≥ r = ρ(v)); so L > 0 at every point of the edge farther out than v
    (the edge's other end lies that way: the vertex is its lower end and the outward way is +t, or
    its upper end and the outward way −t), and sin² > 0 (k does not hold e: pieces meet at most at
    joints).  Exact: the way is decided in rationals."""
    if T.kind[k] != ELLIPSE or len(c.pieces) != 1 or c.code < 0:
        return False
    s, which = c.pieces[0]
    if not same_ellipse(T.sites[k], T.sites[s]):
        return False
    out_up, out_down = c.outside(arb(1), s, which), c.outside(arb(-1), s, which)
    return (out_up and k in ties[0]) or (out_down and k in ties[1])


def _piece(T: SiteTable, c, i, j, J, ties, ends, slopes, relied, at_lo=False, at_hi=False, wzones=({}, {}),
           line_rule=None):
    X, Y = c.xy(J)
    R = c.rho(J, X, Y)
    if not (X.is_finite() and Y.is_finite() and R.is_finite()):
        return ("its curve is not enclosed (a pole of the foot curve?)",)
    if not (R > 0 or (isinstance(c, (NormalLine, EndCurve, AxisCurve)) and R >= 0)):
        return ("its common distance is not proved positive",)
    ok = c.contacts_ok(J, X, Y, R)
    if ok is not True:
        return (ok,)
    cx, cy = float(X.mid()), float(Y.mid())
    brad = math.hypot(float(X.rad()), float(Y.rad()))
    near = T.near(cx, cy, float(R.upper()) + brad + 1e-9 * (1 + abs(cx) + abs(cy)))
    view = c.secant_view(J, R) if hasattr(c, "secant_view") else None
    dxy = None
    for k in sorted(set(near) | ties[0] | ties[1]):
        if k in (i, j):
            continue
        if k not in near:
            slopes[("direct", k)] = True        # farther than ρ on the whole box
            continue
        if isinstance(c, FootCurve) and c.sigma > 0 and (k in T.ends[c.s] or _same_ellipse(T, k, c.s)):
            # an end of the piece or a piece of its ellipse, outside the ellipse: x − e(φ) is in
            # the normal cone of the filled ellipse at e(φ), every other point of it strictly farther
            slopes[("direct", k)] = True
            continue
        if T.is_curve(k) and T.ends[k] is not None and any(q in (i, j) for q in T.ends[k] if q >= 0):
            # R2: a curve ending at a point site p of the edge is never farther than p; its nearest
            # point must be p alone (the tie is p's by convention)
            ps = [q for q in T.ends[k] if q >= 0 and q in (i, j)]
            if len(ps) == 2 and T.kind[k] == ELLIPSE and (closest_at_an_end(T.piece[k], X, Y) == (0, 1) or
                                                          _w_owned(T, c, k, ps, J, X, Y, wzones, slopes, relied)):
                continue                        # both ends are its nearest points, the edge's sites
            if len(ps) == 1 and (_w_owned(T, c, k, ps, J, X, Y, wzones, slopes, relied) or
                                 T.owned_by_end(k, ps[0], X, Y) is True or
                                 _end_owned(T, c, k, ps[0], J, X, Y, R, ends, slopes, relied)):
                continue
            return (f"curve {k} ending at a site of the edge is not proved to have that end as its nearest "
                    "point", k)
        if line_rule is not None and T.kind[k] == POINT and line_rule(T.a[k]):
            continue                            # farther on the whole open edge (exact, _line_rule)
        if line_rule is not None and T.kind[k] in (SEGMENT, ELLIPSE) and getattr(line_rule, "curve", None) and \
                line_rule.curve(k):
            continue                            # every point of curve k by the same rule
        if isinstance(c, NormalLine) and normal_line_monotone(T, c, k, ties):
            continue                            # farther on the whole open edge (exact, secant factor)
        if (view and _secant_farther(T, k, view)) or T.distance(k, X, Y) > R:
            slopes[("direct", k)] = True
            continue
        if _owned_end_farther(T, k, i, j, X, Y, line_rule):
            continue
        if k in ties[0] or k in ties[1]:
            # the sign of g' = ∂d_k·γ' − ρ' on the piece, for the runs from the end vertices
            g = gradient(T, k, X, Y)
            if g is not None:
                if dxy is None:
                    dxy = c.dxy(J)
                dg = g[0] * dxy[0] + g[1] * dxy[1] - c.drho(J, X, Y)
                slopes[k] = 1 if dg > 0 else (-1 if dg < 0 else 0)
        sl = slopes.get(k, 0)
        if sl > 0 and k in ties[0]:
            relied[k] = (1, "lo")
            continue
        if sl < 0 and k in ties[1]:
            relied[k] = (-1, "hi")
            continue
        return (f"site {k} is not proved farther", k)
    return None


def _secant_farther(T: SiteTable, k: int, view) -> bool:
    """Site k lies on the ellipse of every piece touched over the box, and the secant identity
    proves it farther than ρ: L(ψ) > 0 on the side σ of the view for its parameter ψ — a point
    site, or every ψ of an elliptic piece of that ellipse (a cover of its range; it shares at
    most a smooth joint with the touched piece) (:mod:`runtime.segments.certificate_ellipse_secant`).
    The contact φ* is never ψ on the open edge: a point site is not on the open piece, another
    piece meets it at most at a joint, and the contact reaches a piece's end only at an end vertex
    (a normal line at a joint has both pieces as its pair)."""
    if T.kind[k] == POINT:
        for P, Phi, R, sg in view:
            cs = on_ellipse(P, T.a[k])
            if cs is None or not secant_factor(P, cs, Phi, R, sg) > 0:
                return False
        return True
    if T.kind[k] != ELLIPSE:
        return False
    Q = T.piece[k]
    q0, q1 = Q.arb_params()
    cover = [q0 + (q1 - q0) * arb(m / 16).union(arb((m + 1) / 16)) for m in range(16)]
    for P, Phi, R, sg in view:
        if not (P.c == Q.c and P.M == Q.M and P.N == Q.N):
            return False
        for Psi in cover:
            if not secant_factor(P, (Psi.cos(), Psi.sin()), Phi, R, sg) > 0:
                return False
    return True


# ====================================================================== all edges, crossings
def prove_edges_with_pieces(D, T: SiteTable, vproofs, problems, deadline=None) -> list:
    """Every edge of a diagram with elliptic pieces: :func:`prove_piece_edge` where
    :func:`needs_piece_proof`, :func:`runtime.segments.certificate_edges.prove_edges` for the
    others (their sites and end vertices have nothing to do with a piece: the tie covers there
    never need a piece's gradient; a piece as a farther third site is a distance ball)."""
    vindex = {v.id: n for n, v in enumerate(D.vertices)}
    mine = [needs_piece_proof(T, D, e, vindex) for e in D.edges]
    rest = [e for e, m in zip(D.edges, mine) if not m]
    view = SimpleNamespace(edges=rest, vertices=D.vertices, sites=D.sites)
    others = iter(prove_edges(view, T, vproofs, problems, deadline=deadline))
    out = []
    budget = [DIAGRAM_PIECES + EDGE_SHARE * sum(mine)]
    for e, m in zip(D.edges, mine):
        if not m:
            out.append(next(others))
        elif (deadline is not None and time.perf_counter() > deadline) or budget[0] < 0:
            problems.append(Problem(f"edge {e.id}: time or work limit reached, not checked", kind="edge", edge=e.id,
                                    fault=False))
            out.append(EdgeProof(False))
        else:
            try:
                out.append(prove_piece_edge(T, D, e, vindex, vproofs, problems, budget))
            except (ValueError, ZeroDivisionError, ArithmeticError) as exc:      # pragma: no cover - defensive
                problems.append(Problem(f"edge {e.id}: not proved ({exc.__class__.__name__}: {exc})", kind="edge",
                                        edge=e.id, fault=False))
                out.append(EdgeProof(False))
    return out
