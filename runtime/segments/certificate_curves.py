"""Closed-form bisector curves of two elementary sites (points, open segments, open arcs) for the
certificate (:mod:`runtime.segments.certificate_edges` states what is proved with them), the
polyline tolerance check and small arb helpers.

* two points: the perpendicular bisector O + τ w, O the midpoint, w = (p_j − p_i)^⊥ (exact);
* an endpoint e and its segment s: the perpendicular e + τ (b − a)^⊥ (exact); on it the foot on s
  is e, so d_s = |x − e| exactly;
* a point p and a segment s = [a, b] (p not an endpoint, not on the line of s): the parabola by
  the foot parameter t on s, γ(t) = a + t d + d^⊥ ((t − t_p)² L² + H²) / (2 H L) with d = b − a,
  L = |d|², H = d^⊥·(p − a), t_p the foot of p (rational coefficients); the common distance
  ρ(t) = ((t − t_p)² L² + H²) √L / (2 |H| L);
* two segments: the angle bisector σ_i ℓ_i = σ_j ℓ_j of their lines (ℓ the signed distances, σ the
  sides at a proved end vertex of positive radius, where |ℓ| is the radius), through the exact
  intersection of the lines (parallel lines: their mid-parallel through (a_i + a_j)/2);
* an end e of an arc (centre c) and the arc: the radial ray c + τ (e − c), τ > 0 (the direction
  e − c is the range's boundary: d_s = | |x − c| − ρ | = |x − e|);
* the two curves of a smooth joint j: the normal line j + τ w (w = j − c for an arc of the pair),
  restricted to the rays from the arcs' centres through j (1 + τ μ > 0 for w = μ (j − c)); two
  half circles of one circle joined at both ends: the whole line, ρ = |x − j| on each ray from the
  centre to its joint j;
* an arc and another site: :class:`runtime.segments.certificate_arcs.ArcCurve`.

**Polyline tolerance** (:func:`polyline_bound`, a Hausdorff bound; for an arc's bisector piece by
piece against the polyline's segments, :func:`_arc_piece`): each polyline point p_m is
within ε_m of the arc point γ(τ_m) (τ_m its projection, clamped to the arc); the chord between two
arc points deviates from the arc by at most Δu²/(8h) for the parabola (a graph over its directrix
with second derivative 1/h, h the focal distance, Δu the foot distance) and 0 for a line; the
pieces [τ_m, τ_{m+1}] cover the arc between the first and last projections (consecutive pieces
share an end, whatever their order), so the polyline and that arc are within max ε + max sagitta
of each other; the arc between an end vertex and the polyline's end point lies within the
tolerance of that point (checked on the box of the arc piece).

Public API: :class:`Line`, :class:`Parabola`, :func:`bisector_curve`, :func:`polyline_bound`,
:func:`unit_normal`, :func:`exact_d2`, :func:`q_arb`, :func:`interval`, :func:`up`, :func:`down`.
"""
from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
from flint import arb, ctx, fmpq

from ..certify.foot import working_prec
from .certificate_sites import ARC, POINT, SiteTable, hypot, sq

__all__ = ["Line", "Parabola", "bisector_curve", "polyline_bound", "unit_normal", "exact_d2", "q_arb",
           "interval", "up", "down"]

EPS = np.finfo(float).eps

def q_arb(v) -> arb:
    """A ball holding the rational v (a Fraction or an int; exact when it fits the precision)."""
    if type(v) is not Fraction:
        v = Fraction(v)
    return arb(fmpq(v.numerator, v.denominator))


def interval(lo: float, hi: float) -> arb:
    """The ball hull of the floats lo and hi."""
    return arb(lo).union(arb(hi))


def up(x: arb) -> float:
    """A float ≥ every point of x."""
    u = float(x.upper())
    return u + 4 * EPS * abs(u) + 1e-300


def down(x: arb) -> float:
    """A float ≤ every point of x."""
    u = float(x.lower())
    return u - 4 * EPS * abs(u) - 1e-300


class Line:
    """O + τ w; ``anchor`` (a point: ρ = |x − anchor|) or ``side`` (n̂, a: ρ = n̂·(x − a))."""

    def __init__(self, kind, Oq, wq=None, w=None, anchor=None, side=None, valid=(None, None)):
        self.kind = kind
        self.valid = valid
        self.anchor2 = self.split = None
        self.Oq, self.wq = Oq, wq
        self.O = (q_arb(Oq[0]), q_arb(Oq[1]))
        self.w = (q_arb(wq[0]), q_arb(wq[1])) if wq is not None else w
        self.w2 = sq(self.w[0]) + sq(self.w[1])
        self.anchor_q = anchor
        self.anchor = None if anchor is None else (q_arb(anchor[0]), q_arb(anchor[1]))
        self.side = side

    def xy(self, t):
        return self.O[0] + t * self.w[0], self.O[1] + t * self.w[1]

    def dxy(self, t):
        return self.w

    def param(self, X, Y):
        return ((X - self.O[0]) * self.w[0] + (Y - self.O[1]) * self.w[1]) / self.w2

    def rho(self, t, X, Y):
        if self.anchor is not None:
            return hypot(X - self.anchor[0], Y - self.anchor[1])
        (nx, ny), (ax, ay) = self.side
        return nx * (X - ax) + ny * (Y - ay)

    def drho(self, t, X, Y):
        if self.anchor is not None:
            dx, dy = X - self.anchor[0], Y - self.anchor[1]
            return (dx * self.w[0] + dy * self.w[1]) / hypot(dx, dy)
        (nx, ny), _ = self.side
        return nx * self.w[0] + ny * self.w[1]

    def vertex_param(self, vp):
        return self.param(vp.x, vp.y)

    def chord_bound(self, t0, t1, target: float = 0.0):
        return arb(0)


class Parabola:
    """The bisector of point p and segment s, by the foot parameter t on s (module docstring)."""

    kind = "parabola"

    def __init__(self, T: SiteTable, p: int, s: int):
        (ax, ay), (bx, by), (px, py) = T.a[s], T.b[s], T.a[p]
        dx, dy = bx - ax, by - ay
        L2 = dx * dx + dy * dy
        H = dx * (py - ay) - dy * (px - ax)
        self.H_exact = H
        tp = ((px - ax) * dx + (py - ay) * dy) / L2
        self.a = (q_arb(ax), q_arb(ay))
        self.d = (q_arb(dx), q_arb(dy))
        self.L2, self.H, self.tp = q_arb(L2), q_arb(H), q_arb(tp)
        self.sqL = self.L2.sqrt()
        self.absH = abs(self.H)

    def _q_of(self, t):
        u = t - self.tp
        return (u * u * self.L2 * self.L2 + self.H * self.H) / (2 * self.H * self.L2)

    def xy(self, t):
        q = self._q_of(t)
        return self.a[0] + t * self.d[0] - self.d[1] * q, self.a[1] + t * self.d[1] + self.d[0] * q

    def dxy(self, t):
        qp = (t - self.tp) * self.L2 / self.H
        return self.d[0] - self.d[1] * qp, self.d[1] + self.d[0] * qp

    def param(self, X, Y):
        return ((X - self.a[0]) * self.d[0] + (Y - self.a[1]) * self.d[1]) / self.L2

    def rho(self, t, X, Y):
        u = t - self.tp
        return (u * u * self.L2 * self.L2 + self.H * self.H) * self.sqL / (2 * self.absH * self.L2)

    def drho(self, t, X, Y):
        return (t - self.tp) * self.L2 * self.sqL / self.absH

    def sagitta(self, dt: arb) -> arb:
        """Chord-to-arc deviation bound of a piece of foot length dt: Δu²/(8h)."""
        return dt * dt * self.L2 * self.sqL / (8 * self.absH)

    def chord_bound(self, t0, t1, target: float = 0.0):
        return self.sagitta(t1 - t0)

    def vertex_param(self, vp):
        return self.param(vp.x, vp.y)


def bisector_curve(T: SiteTable, i, j, vps, P=None):
    """The bisector curve of i and j, or a message.  ``vps``: proofs of the finite end vertices;
    ``P``: the polyline (it picks the sides of an arc's bisector that no vertex fixes)."""
    ki, kj = T.kind[i], T.kind[j]
    if ki == POINT and kj == POINT:
        (xi, yi), (xj, yj) = T.a[i], T.a[j]
        return Line("points", ((xi + xj) / 2, (yi + yj) / 2), wq=(-(yj - yi), xj - xi), anchor=T.a[i])
    if ki == POINT or kj == POINT:
        p, s = (i, j) if ki == POINT else (j, i)
        (ax, ay), (bx, by) = T.a[s], T.b[s]
        if T.is_endpoint(p, s):
            if T.kind[s] == ARC:
                c = T.cen[s]
                return Line("radial", c, wq=(T.a[p][0] - c[0], T.a[p][1] - c[1]), anchor=T.a[p],
                            valid=(Fraction(0), None))
            return Line("perp", T.a[p], wq=(-(by - ay), bx - ax), anchor=T.a[p])
        if T.kind[s] == ARC:
            return _arc_curve(T, s, p, vps, P)
        par = Parabola(T, p, s)
        if par.H_exact == 0:
            return "the point lies on the line of the segment: they have no bisector arc"
        return par
    joints = T.shared_joint(i, j)
    if joints:
        return _joint_line(T, i, j, joints, P)
    if ARC in (ki, kj):
        s = min(x for x in (i, j) if T.kind[x] == ARC)
        return _arc_curve(T, s, j if s == i else i, vps, P)
    # two segments
    sides = None
    for vp in vps:
        if vp.r is not None and vp.r > 0:
            sg = []
            for s in (i, j):
                nx, ny, ax, ay = unit_normal(T, s)
                val = nx * (vp.x - ax) + ny * (vp.y - ay)
                if not (val > 0 or val < 0):
                    return "the side of a segment at an end vertex is undecided"
                sg.append(1 if val > 0 else -1)
            if sides is not None and sides != sg:
                return "its end vertices lie on different bisectors of the two segments"
            sides = sg
    if sides is None:
        return "no end vertex of positive radius fixes the bisector of the two segments"
    (ai, bi), (aj, bj) = (T.a[i], T.b[i]), (T.a[j], T.b[j])
    di = (bi[0] - ai[0], bi[1] - ai[1])
    dj = (bj[0] - aj[0], bj[1] - aj[1])
    ni, nj = unit_normal(T, i), unit_normal(T, j)
    side = ((sides[0] * ni[0], sides[0] * ni[1]), (ni[2], ni[3]))
    cr = di[0] * dj[1] - di[1] * dj[0]
    if cr == 0:
        same = (di[0] * dj[0] + di[1] * dj[1]) > 0      # n̂_j = ±n̂_i
        if sides[0] == (sides[1] if same else -sides[1]):
            return "the two segments are collinear or on one side of each other: no mid-parallel between them"
        O = ((ai[0] + aj[0]) / 2, (ai[1] + aj[1]) / 2)
        return Line("segments", O, wq=di, side=side)
    # intersection of the two lines: ai + λ di
    lam = ((aj[0] - ai[0]) * dj[1] - (aj[1] - ai[1]) * dj[0]) / cr
    O = (ai[0] + lam * di[0], ai[1] + lam * di[1])
    near = next((vp for vp in vps if vp.x is not None), None)
    extra = 0
    if near is not None:
        size = 1.0 + abs(float(near.x.mid())) + abs(float(near.y.mid()))
        far = abs(float(O[0]) - float(near.x.mid())) + abs(float(O[1]) - float(near.y.mid()))
        if far > 1e3 * size:
            extra = int(math.log2(far / size)) + 16
    with working_prec(ctx.prec + extra):
        ni, nj = unit_normal(T, i), unit_normal(T, j)
        mx = sides[0] * ni[0] - sides[1] * nj[0]
        my = sides[0] * ni[1] - sides[1] * nj[1]
        line = Line("segments", O, w=(-my, mx), side=side)
        if extra:
            # nearly parallel segments meet far away: the origin moves to the end vertex's
            # parameter τ₀ (a float), computed with the bits that x − O cancels, so that the
            # edge's parameters are small floats (pieces of float width resolve it)
            tau0 = float(line.param(near.x, near.y).mid())
            line.O = (line.O[0] + tau0 * line.w[0], line.O[1] + tau0 * line.w[1])
    return line


def _arc_curve(T, s, k, vps, P):
    from .certificate_arcs import ArcCurve, side_of

    sides = side_of(T, s, k, vps, P if P is not None else np.zeros((1, 2)))
    if sides is None:
        return "the sides of the arc's bisector are not decided (its end vertices disagree)"
    return ArcCurve(T, s, k, *sides)


def _joint_line(T, i, j, joints, P):
    """The normal line at the smooth joint of curves i and j, restricted to the rays from the
    arcs' centres through the joint."""
    if len(joints) > 1 and P is not None:             # two joints (a closed pair): the one nearest
        m = P[len(P) // 2]
        joints = sorted(joints, key=lambda c: (float(T.pt(c)[0]) - m[0]) ** 2 + (float(T.pt(c)[1]) - m[1]) ** 2)
    jt = joints[0]
    jx, jy = T.pt(jt)
    if len(joints) == 2 and ARC == T.kind[i] == T.kind[j] and T.cen[i] == T.cen[j]:
        kx, ky = T.pt(joints[1])
        c = T.cen[i]
        if (jx + kx, jy + ky) == (2 * c[0], 2 * c[1]):
            # two half circles of one circle: the rays from the centre through the two joints make
            # a line, ρ = |x − j₁| on the first (τ ≥ −1), |x − j₂| on the second
            line = Line("joint", (jx, jy), wq=(jx - c[0], jy - c[1]), anchor=(jx, jy))
            line.anchor2, line.split = (kx, ky), Fraction(-1)
            return line
    w = None
    for s in (i, j):
        if T.kind[s] == ARC:
            c = T.cen[s]
            w = (jx - c[0], jy - c[1])
            break
    lo, hi = None, None
    for s in (i, j):
        if T.kind[s] != ARC:
            continue
        c = T.cen[s]
        r = (jx - c[0], jy - c[1])
        mu = (w[0] * r[0] + w[1] * r[1]) / (r[0] * r[0] + r[1] * r[1])     # w = μ r
        bound = -1 / mu                                                       # 1 + τμ > 0
        if mu > 0:
            lo = bound if lo is None else max(lo, bound)
        else:
            hi = bound if hi is None else min(hi, bound)
    return Line("joint", (jx, jy), wq=w, anchor=(jx, jy), valid=(lo, hi))


def unit_normal(T: SiteTable, s):
    """(n̂x, n̂y, ax, ay): the unit normal (b − a)^⊥/|b − a| and a point of segment s (arb)."""
    ax, ay, bx, by = T.arb_ends(s)
    nx, ny = -(by - ay), bx - ax
    nn = (nx * nx + ny * ny).sqrt()
    return nx / nn, ny / nn, ax, ay


def polyline_bound(c, P, tol: float, lo, hi, end_vertices):
    """None when the polyline P is within ``tol`` of the arc τ ∈ [lo, hi] of curve c (balls, None
    for an infinite end; module docstring), else a message.  ``end_vertices``: the proofs of the
    vertices at P[0] and P[-1] (None at infinity)."""
    taus = []
    points = []
    dev = arb(0)
    for p in P:
        x, y = arb(float(p[0])), arb(float(p[1]))
        t = c.param(x, y)
        if lo is not None:
            t = t.max(lo)
        if hi is not None:
            t = t.min(hi)
        X, Y = c.xy(t)
        dev = dev.max(hypot(X - x, Y - y))
        taus.append(t)
        points.append((X, Y))
    if c.kind == "arc":
        total = dev
        for m in range(len(P) - 1):
            total = total.max(_arc_piece(c, P[m], P[m + 1], taus[m], taus[m + 1], tol, points[m], points[m + 1]))
    else:
        sag = arb(0)
        for t0, t1 in zip(taus, taus[1:]):
            sag = sag.max(c.chord_bound(t0, t1))
        total = dev + sag
    if not total.upper() <= tol:
        return (f"its polyline is not within its tolerance {tol:.3g} of the arc (bound "
                f"{float(total.upper()):.3g})")
    # the arc between an end vertex and the polyline's end point lies near that point
    for end, (vp, p, t) in enumerate(((end_vertices[0], P[0], taus[0]), (end_vertices[1], P[-1], taus[-1]))):
        if vp is None:
            continue
        tv = c.vertex_param(vp)
        X, Y = c.xy(tv.union(t))
        x, y = float(p[0]), float(p[1])
        fx, fy = arb(abs(X - x).abs_upper()), arb(abs(Y - y).abs_upper())
        if not hypot(fx, fy).upper() <= tol:
            return (f"its polyline does not {('start', 'end')[end]} at its end vertex (within its tolerance "
                    f"{tol:.3g})")
    return None


def _segment_distance(X, Y, A, B) -> arb:
    """A ball holding the distance from the box (X, Y) to the float segment [A, B]."""
    ax, ay = arb(float(A[0])), arb(float(A[1]))
    dx, dy = arb(float(B[0])) - ax, arb(float(B[1])) - ay
    L2 = dx * dx + dy * dy
    if L2 == 0:
        return hypot(X - ax, Y - ay)
    u = (((X - ax) * dx + (Y - ay) * dy) / L2).max(arb(0)).min(arb(1))
    return hypot(X - ax - u * dx, Y - ay - u * dy)


def _arc_piece(c, A, B, t0, t1, tol: float, v0=None, v1=None) -> arb:
    """A bound on the distance from the curve between the parameters t0 and t1 to the polyline
    segment [A, B]: the curve points at n sub-parameters are within d_m of the segment, each
    sub-piece within its chord bound δ_m of its own chord, whose points are within
    max(d_m, d_{m+1}) of the segment (a convex set): max (max(d_m, d_{m+1}) + δ_m), sub-pieces
    halved while above ``tol``.  The segment is within that of the curve too: the curve's
    projection on the segment's line runs between those of its ends (which are within the
    polyline points' deviation of A and B)."""
    v0 = c.xy(t0) if v0 is None else v0              # the curve's points at t0, t1 (given: reused)
    v1 = c.xy(t1) if v1 is None else v1
    if c.straight:                                   # a line: the piece is the chord of its ends
        return _segment_distance(*v0, A, B).max(_segment_distance(*v1, A, B))
    out = arb(0)
    dist = {(float(t.mid()), float(t.rad())): _segment_distance(*v, A, B) for t, v in ((t0, v0), (t1, v1))}

    def d(th):
        key = (float(th.mid()), float(th.rad()))
        if key not in dist:
            dist[key] = _segment_distance(*c.xy(th), A, B)
        return dist[key]
    stack, count = [(t0, t1, 0)], 0
    while stack:                                     # adaptive: halve the sub-pieces above tol
        a, b, depth = stack.pop()
        count += 1
        ends = d(a).max(d(b))
        bound = ends + c.chord_bound_parts(a, b, 1)          # one sub-piece suffices mostly
        if not bound.upper() <= tol:
            bound = ends + c.chord_bound_parts(a, b, 2)
        if not bound.upper() <= tol and depth < 40 and count < 4000:      # NaN/∞ near a pole too
            m = (a + b) / 2
            stack += [(a, m, depth + 1), (m, b, depth + 1)]
            continue
        out = out.max(bound)
    return out


def exact_d2(T: SiteTable, k, x) -> Fraction:
    """The squared distance from the rational point x to site k, exactly."""
    (ax, ay), (bx, by) = T.a[k], T.b[k]
    dx, dy = bx - ax, by - ay
    L2 = dx * dx + dy * dy
    t = Fraction(0) if L2 == 0 else ((x[0] - ax) * dx + (x[1] - ay) * dy) / L2
    t = min(max(t, Fraction(0)), Fraction(1))
    fx, fy = ax + t * dx, ay + t * dy
    return (x[0] - fx) ** 2 + (x[1] - fy) ** 2
