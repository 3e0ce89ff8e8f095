"""Voronoi vertices of three elementary sites (points and open segments), proved.

A vertex v of radius r touches each of its three sites (thesis §1.2, §2.2).  With unknowns
z = (x, y, r), each site contributes one equation of degree ≤ 2:

* a point p:                         |v − p|² − r² = 0;
* an open segment s on the line a·x + b·y + c = 0 (a, b = the normal, N = a² + b²), touched in
  its interior on the side σ = ±1:  a x + b y + c − σ r √N = 0;
* an open segment s whose endpoint e is also a site of the triple: the circle touches s at e,
  so v lies on the perpendicular to s at e:  (b_s − a_s)·(v − e) = 0  (a circle through e
  tangent to the line of s elsewhere than at e cannot meet e: a line meets a circle twice).

Three sites whose closures share a point c (a polygon's corner c with its two segments, three
segments of a junction) have the vertex v = c of radius 0, exactly.

Proof (:func:`prove_vertex`): float Newton from the seed, then Krawczyk's test
(:func:`runtime.certify.interval_newton.krawczyk_inflation`, the one Krawczyk of the library) on
the 3 × 3 system in arb with √N as balls: exactly one zero in the box.  It is a vertex of the
three sites when r > 0 and every interior contact has its foot parameter in [0, 1] (then the
distance to the closed segment is the line's); a foot parameter straddling 0 or 1 is a
degeneracy (the endpoint touches too) and is reported undecided.

Public API: :class:`VertexSolution`, :func:`prove_vertex`, :func:`common_point`.
"""
from __future__ import annotations

from dataclasses import dataclass
import numpy as np
from flint import arb, ctx

from ..certify.foot import to_arb
from ..certify.interval_newton import KrawczykFailure, krawczyk_inflation
from .distance import foot_parameter
from .elementary import POINT, ElementarySites

__all__ = ["VertexSolution", "prove_vertex", "common_point"]

PREC = 128


@dataclass
class VertexSolution:
    """``status``: "proved", "invalid" (the zero is not a vertex of the triple: r ≤ 0 or a foot
    outside a segment) or "undecided"; ``x, y, r``: float midpoints; ``box``: arb (x, y, r)
    enclosures (exact for a corner); ``corner``: the common point site index when r = 0."""

    status: str
    x: float
    y: float
    r: float
    box: tuple | None = None
    corner: int | None = None
    reason: str = ""


def common_point(E: ElementarySites, triple) -> int | None:
    """The point site contained in the closures of all three sites, if any."""
    cands = None
    for t in triple:
        pts = {int(t)} if E.kind[t] == POINT else {int(E.ends[t, 0]), int(E.ends[t, 1])}
        cands = pts if cands is None else cands & pts
    return next(iter(cands)) if cands else None


def _equations(E: ElementarySites, triple, seed):
    """[(kind, data)] per site: ("point", (px, py)), ("line", (a, b, c, σ, N)), ("perp", (dx, dy, ex, ey))."""
    eqs = []
    pts = [int(t) for t in triple if E.kind[t] == POINT]
    for t in triple:
        t = int(t)
        if E.kind[t] == POINT:
            eqs.append(("point", E.xy[t]))
            continue
        ia, ib = int(E.ends[t, 0]), int(E.ends[t, 1])
        (ax, ay), (bx, by) = E.xy[ia], E.xy[ib]
        ends_in = [p for p in pts if p in (ia, ib)]
        if len(ends_in) == 2:
            return None              # both endpoints of a segment and its interior: no circle
        if ends_in:
            ex, ey = E.xy[ends_in[0]]
            eqs.append(("perp", (bx - ax, by - ay, ex, ey)))
            continue
        a, b = -(by - ay), bx - ax
        c = -(a * ax + b * ay)
        side = a * seed[0] + b * seed[1] + float(c)
        eqs.append(("line", (a, b, c, 1 if side >= 0 else -1, a * a + b * b)))
    return eqs


def _float_system(eqs):
    co = []
    for kind, d in eqs:
        if kind == "point":
            co.append((kind, float(d[0]), float(d[1])))
        elif kind == "line":
            a, b, c, s, N = d
            co.append((kind, float(a), float(b), float(c), s * float(N) ** 0.5))
        else:
            dx, dy, ex, ey = d
            co.append((kind, float(dx), float(dy), float(ex), float(ey)))

    def F(z):
        x, y, r = z
        out, J = [], []
        for e in co:
            if e[0] == "point":
                out.append((x - e[1]) ** 2 + (y - e[2]) ** 2 - r * r)
                J.append([2 * (x - e[1]), 2 * (y - e[2]), -2 * r])
            elif e[0] == "line":
                out.append(e[1] * x + e[2] * y + e[3] - e[4] * r)
                J.append([e[1], e[2], -e[4]])
            else:
                out.append(e[1] * (x - e[3]) + e[2] * (y - e[4]))
                J.append([e[1], e[2], 0.0])
        return np.array(out), np.array(J)
    return F


def _arb_system(eqs):
    co = []
    for kind, d in eqs:
        if kind == "point":
            co.append((kind, to_arb(d[0]), to_arb(d[1])))
        elif kind == "line":
            a, b, c, s, N = d
            co.append((kind, to_arb(a), to_arb(b), to_arb(c), s * to_arb(N).sqrt()))
        else:
            co.append((kind,) + tuple(to_arb(v) for v in d))

    def F(z):
        x, y, r = z
        out = []
        for e in co:
            if e[0] == "point":
                out.append((x - e[1]) ** 2 + (y - e[2]) ** 2 - r * r)
            elif e[0] == "line":
                out.append(e[1] * x + e[2] * y + e[3] - e[4] * r)
            else:
                out.append(e[1] * (x - e[3]) + e[2] * (y - e[4]))
        return out

    def J(z):
        x, y, r = z
        rows = []
        for e in co:
            if e[0] == "point":
                rows.append([2 * (x - e[1]), 2 * (y - e[2]), -2 * r])
            elif e[0] == "line":
                rows.append([e[1], e[2], -e[4]])
            else:
                rows.append([e[1], e[2], arb(0)])
        return rows
    return F, J


def prove_vertex(E: ElementarySites, triple, seed, r_seed: float | None = None, cache: dict | None = None
                 ) -> VertexSolution:
    """The vertex of ``triple`` (three elementary site indices) near ``seed`` (x, y), proved.
    ``cache``: proofs by (triple, sides, Newton limit rounded to 10⁻⁹ of the scale), so that the
    many sample triangles of one vertex are proved once."""
    c = common_point(E, triple)
    if c is not None:
        x, y = E.xy[c]
        return VertexSolution("proved", float(x), float(y), 0.0,
                              (to_arb(x), to_arb(y), arb(0)), corner=c)
    eqs = _equations(E, triple, seed)
    if eqs is None:
        return VertexSolution("invalid", float(seed[0]), float(seed[1]), 0.0, reason="a segment and both its endpoints")
    F = _float_system(eqs)
    z = np.array([seed[0], seed[1], r_seed if r_seed is not None else 1.0], dtype=float)
    if r_seed is None:
        z[2] = _r_guess(eqs, z)
    scale = 1.0 + float(np.max(np.abs(E.A)) if len(E.A) else 0.0)
    for _ in range(40):
        f, J = F(z)
        try:
            step = np.linalg.solve(J, f)
        except np.linalg.LinAlgError:
            return VertexSolution("undecided", z[0], z[1], z[2], reason="singular system")
        z = z - step
        if not np.all(np.isfinite(z)):
            return VertexSolution("undecided", float(seed[0]), float(seed[1]), 0.0, reason="Newton diverged")
        if np.max(np.abs(step)) <= 1e-15 * scale:
            break
    key = None
    if cache is not None:
        sides = tuple(d[3] if k == "line" else 0 for k, d in eqs)
        key = (tuple(triple), sides) + tuple(np.round(z / (1e-9 * scale)).astype(np.int64).tolist())
        if key in cache:
            return cache[key]
    sol = _prove(E, triple, eqs, z, scale)
    if key is not None:
        cache[key] = sol
    return sol


def _prove(E: ElementarySites, triple, eqs, z, scale) -> VertexSolution:
    old = ctx.prec
    ctx.prec = PREC
    try:
        Fa, Ja = _arb_system(eqs)
        try:
            # an isotropic first radius (2^-44 of the scale): the residuals of the point
            # equations often cancel in Y·F(m), and a radius at the rounding floor in x, y
            # cannot absorb the r² term of the box
            K, _X = krawczyk_inflation(Fa, Ja, [arb(float(v)) for v in z],
                                       floor=arb(scale + abs(float(z[2]))) * arb(2) ** -44)
        except KrawczykFailure as exc:
            return VertexSolution("undecided", *z, reason=f"Krawczyk: {exc}")
        x, y, r = K
        if not r > 0:
            return VertexSolution("invalid" if r <= 0 else "undecided", *z, box=tuple(K), reason="radius")
        for (kind, _d), t in zip(eqs, triple):
            if kind != "line":
                continue
            u = foot_parameter(E.xy[int(E.ends[int(t), 0])], E.xy[int(E.ends[int(t), 1])], x, y)
            if u < 0 or u > 1:
                return VertexSolution("invalid", *z, box=tuple(K), reason=f"foot outside segment {int(t)}")
            if not (u >= 0 and u <= 1):
                return VertexSolution("undecided", *z, box=tuple(K), reason=f"foot at an end of segment {int(t)}")
        return VertexSolution("proved", float(x.mid()), float(y.mid()), float(r.mid()), tuple(K))
    finally:
        ctx.prec = old


def _r_guess(eqs, z):
    rs = []
    for kind, d in eqs:
        if kind == "point":
            rs.append(float(np.hypot(z[0] - float(d[0]), z[1] - float(d[1]))))
        elif kind == "line":
            a, b, c, _s, N = d
            rs.append(abs(float(a) * z[0] + float(b) * z[1] + float(c)) / float(N) ** 0.5)
    return float(np.mean(rs)) if rs else 1.0

