"""Edge polylines of the segment diagram from the walks of the sample triangulation.

Each walk of two-label triangles joins two vertices (or a vertex and infinity) along the bisector
of its two sites; the polyline is drawn on the closed-form bisector
(:func:`runtime.segments.bisectors.edge_polyline`).  An infinite end goes the way along the
bisector on which the two sites stay the nearest (a third site takes over at once the other way),
to a far point outside the scene: at 4 times the sites' extent plus twice the distance of the
edge's finite vertex from the scene's centre.

Public API: :func:`edge_polylines`, :func:`vertex_error`, :func:`walk_hint`.
"""
from __future__ import annotations

import math

import numpy as np

from ..voronoi.structure import DiagramEdge
from .bisectors import (OTHER, PARABOLA, STRAIGHT, arc_bisector_points, arc_sides, bisector_kind, edge_polyline,
                        line_direction, line_point, parabola_polylines, simple_kinds)
from .distance import clearance, site_distances
from .ellipse_bisectors import ellipse_step, perpendicular_edge
from .elementary import ARC, ELLIPSE, POINT, ElementarySites

__all__ = ["edge_polylines", "vertex_error", "walk_hint"]


def walk_hint(tri, e):
    """A point in the direction of a walk's end (the circumcentre of the hull triangle)."""
    if e is None or e[0] not in ("hull", "tri"):
        return None
    return tri.cc[e[1]] + 0.0


def _outward(E: ElementarySites, i: int, j: int, base, d, far) -> float:
    """+1 or −1: the way along the straight bisector of i and j, from its vertex ``base``, on
    which i and j stay the nearest sites (the other way a third site takes over at once)."""
    eps = 1e-6 * max(far, float(np.hypot(*base)))
    best, sgn = None, 1.0
    for s in (1.0, -1.0):
        q = base + s * eps * d
        dd = site_distances(E, np.arange(len(E)), np.repeat(q[None, :], len(E), axis=0))
        own = max(dd[i], dd[j])
        _drop_ties(E, i, j, dd, own)
        dd[[i, j]] = np.inf
        margin = float(dd.min() - own)
        if best is None or margin > best:
            best, sgn = margin, s
    return sgn


def _drop_ties(E: ElementarySites, i: int, j: int, dd, own) -> None:
    """A curve ending at point site i (or j) is exactly as near as that end wherever its nearest
    point is the end: such ties say nothing about the way along a bisector (set to ∞ in ``dd``)."""
    for p in (i, j):
        if E.kind[p] == POINT:
            for t in E.incident[p]:
                if dd[t] >= own - 1e-12 * (1.0 + own):
                    dd[t] = np.inf


def _arc_step(E: ElementarySites, i: int, j: int, base, far):
    """(step, (σ, τ)): the way (+1 counter-clockwise on the arc, −1 not) and the sides of the arc
    bisector of i and j leaving its vertex ``base`` on which i and j stay the nearest sites.  At
    a corner the vertex lies on both sites and does not tell the sides: all four are tried."""
    s, other = (i, j) if E.kind[i] == ARC else (j, i)
    c = E.C[s]
    th = math.atan2(base[1] - c[1], base[0] - c[0])
    own_sides = arc_sides(E, s, other, base)
    tries = [own_sides] + [(a, b) for a in (1, -1) for b in (1, -1) if (a, b) != own_sides]
    best, out = None, (1, own_sides)
    for sides in tries:
        for st in (1, -1):
            # a step of 10⁻⁶ in the contact angle, shortened while it moves the point by more
            # than 10⁻³ of ``far``: near the pole of a far vertex's branch (radius 10⁸, a pole
            # 5·10⁻⁴ away in angle) 10⁻⁶ moves it by 10⁷, and both ways would be skipped
            for delta in 10.0 ** -np.arange(6, 13):
                V, t = arc_bisector_points(E, s, other, sides[0], sides[1], np.array([th + st * delta]))
                if not (np.isfinite(t[0]) and t[0] > 0) or np.hypot(*(V[0] - base)) <= 1e-3 * far:
                    break
            if not (np.isfinite(t[0]) and t[0] > 0) or np.hypot(*(V[0] - base)) > 1e-3 * far:
                continue
            dd = site_distances(E, np.arange(len(E)), np.repeat(V, len(E), axis=0))
            if abs(dd[i] - dd[j]) > 1e-9 * (1 + t[0]):
                continue            # not a point of this bisector branch
            margin = clearance(dd, i, j)
            if best is None or margin > best:
                best, out = margin, (st, sides)
    return out


def edge_polylines(E: ElementarySites, vertices, walks, tol, lo, hi):
    """Polylines along the closed-form bisectors; infinite ends at far points in the walk's
    direction.  The straight and parabolic edges with two finite ends (nearly all of them) are
    drawn together on arrays (:func:`runtime.segments.bisectors.parabola_polylines`), the others
    one by one."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    centre = (lo + hi) / 2
    far_sites = 4 * float(np.max(hi - lo) + 1.0)
    batch = _finite_simple(E, vertices, walks, tol)
    scale = 1.0 + float(np.max(np.abs(E.A))) if len(E.A) else 1.0
    error = [vertex_error(v, scale) for v in vertices]
    out = []
    for w, (pair, ends, _hints) in enumerate(walks):
        got = batch.get(w)
        if got is None:
            got = _one_edge(E, vertices, pair, ends, tol, lo, centre, far_sites)
            if got is None:
                continue
        i, j = pair
        bound = got[1] + max((error[e] for e in ends if e is not None), default=0.0)
        out.append(DiagramEdge(len(out), (i, j), tuple(ends), False, got[0], bound, False))
    return out


def vertex_error(v, scale: float) -> float:
    """The distance between the float vertex ``v`` and the true vertex that the vertex proofs
    aim at: the batched float Krawczyk test (:mod:`runtime.segments.vertex_batch`) keeps a box
    of radius ≤ 2⁻⁴⁰ (1 + |x| + |y| + r), and the arb proof
    (:func:`runtime.segments.vertices.prove_zero`) inflates from 2⁻⁴⁴ (scale + r), ``scale`` =
    1 + the sites' largest coordinate.  The radius matters: at the centre of a 64-gon of radius
    10⁴ the vertices near (5, 3) are intersections of nearly parallel lines, known to 10⁻¹⁰,
    not to 10⁻¹² of |x| + |y|.  Each edge's polyline starts and ends at float vertices, so its
    stated bound adds this.  A claim, not a proof: the certificate checks every bound with its
    own vertex boxes and refuses the edge, by name, where it does not hold."""
    return 2.0 ** -40 * (1.0 + abs(v.x) + abs(v.y) + abs(v.radius)) + 2.0 ** -44 * (scale + abs(v.radius))


def _finite_simple(E: ElementarySites, vertices, walks, tol) -> dict:
    """{walk: (polyline, bound)} of the walks with two finite ends whose bisector is straight or
    a parabola of focal distance > 0: a straight edge is the chord of its ends (bound: their
    rounding, 10⁻¹² of their scale), a parabolic one :func:`parabola_polylines`."""
    if not walks or not vertices:
        return {}
    ends = np.array([[-1 if e is None else e for e in w[1]] for w in walks], np.int64).reshape(-1, 2)
    pairs = np.array([w[0] for w in walks], np.int64).reshape(-1, 2)
    ok = (ends >= 0).all(axis=1)
    kind = simple_kinds(E, pairs[:, 0], pairs[:, 1])
    ok &= kind != OTHER
    if not ok.any():
        return {}
    VX = np.array([(v.x, v.y) for v in vertices], float).reshape(-1, 2)
    out: dict = {}
    line = np.nonzero(ok & (kind == STRAIGHT))[0]
    if len(line):
        Q = VX[ends[line]]                                    # (m, 2, 2)
        bound = 1e-12 * (1.0 + np.abs(Q).reshape(len(line), 4).max(axis=1))
        out.update(zip(line.tolist(), zip(Q, bound.tolist())))
    par = np.nonzero(ok & (kind == PARABOLA))[0]
    if len(par):
        i, j = pairs[par, 0], pairs[par, 1]
        p = np.where(E.kind[i] == POINT, i, j)
        s = np.where(E.kind[i] == POINT, j, i)
        d = E.B[s] - E.A[s]
        focal = (E.A[p, 0] - E.A[s, 0]) * -d[:, 1] + (E.A[p, 1] - E.A[s, 1]) * d[:, 0]
        keep = focal != 0                  # a point on the segment's line: one by one
        par, p, s = par[keep], p[keep], s[keep]
        if len(par):
            Q, start, bound = parabola_polylines(E, p, s, VX[ends[par, 0]], VX[ends[par, 1]], tol)
            out.update(zip(par.tolist(), zip(np.split(Q, start[1:]), bound.tolist())))
    return out


def _one_edge(E: ElementarySites, vertices, pair, ends, tol, lo, centre, far_sites):
    """(polyline, bound) of one walk's edge, or None when it is not drawn."""
    i, j = pair
    fin = [None if e is None else np.array([vertices[e].x, vertices[e].y]) for e in ends]
    kind = bisector_kind(E, i, j)
    step, sides = 1, None
    if kind == "perpendicular" and ELLIPSE in (E.kind[i], E.kind[j]):
        # the normal at an elliptic piece's end bends beyond the centre of curvature
        return perpendicular_edge(E, i, j, fin[0], fin[1], tol, far_sites + 2 * max(
            (float(np.hypot(*(f - centre))) for f in fin if f is not None), default=0.0))
    # an infinite end is drawn to 4 times the sites' extent, or twice as far out as its finite
    # vertex: one far vertex (10⁸ beyond sites 10³ apart) does not stretch every other
    # infinite edge to 10⁸ (long chords near their poles)
    far = far_sites + 2 * max((float(np.hypot(*(f - centre))) for f in fin if f is not None), default=0.0)
    if fin[0] is None or fin[1] is None:
        if kind in ("parabola", "segments"):
            return None           # these bisectors are bounded: the walk is an artefact
        if kind == "arc":
            base = fin[0] if fin[0] is not None else fin[1]
            step, sides = (1, None) if base is None else _arc_step(E, i, j, base, far)
        elif kind == "ellipse":
            base = fin[0] if fin[0] is not None else fin[1]
            if base is None:
                return None           # a whole bisector without vertices: not drawn
            step, sides = ellipse_step(E, i, j, base, far)
        else:
            base = fin[0] if fin[0] is not None else fin[1]
            d = line_direction(E, i, j, base)
            if base is None:
                base = line_point(E, i, j)
            R = far + float(np.hypot(*(base - centre)))
            if fin[0] is None and fin[1] is None:
                fin = [base - d * R, base + d * R]
            else:
                sgn = _outward(E, i, j, base, d, far)
                fin = [base + sgn * d * R if f is None else f for f in fin]
    poly, t = edge_polyline(E, i, j, fin[0], fin[1], tol, far=far + float(np.hypot(*(lo - centre))), sides=sides,
                            centre=centre, step=step)
    if len(poly) < 2:
        return None
    return poly, t
