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

An open elliptic-arc piece t (:mod:`runtime.segments.ellipse_pieces`) touched in its interior
contributes |v − e(φ(v))|² − r² = 0 with φ(v) the foot of v on t: by the envelope theorem its
gradient in v is 2(v − e(φ(v))), so the equation is a point equation whose point is the foot; the
Krawczyk test encloses the foot over its box by a parametric one-dimensional Krawczyk test
(:func:`runtime.segments.ellipse_pieces.foot_enclosure`), and the proved zero touches t when the
foot lies strictly inside t and is its nearest point
(:func:`runtime.segments.ellipse_pieces.nearest_verdict`).  Two pieces of one ellipse meeting at
a vertex of the ellipse (a smooth joint) beyond the joint's centre of curvature are touched at
two feet, one on each piece: then both take the foot equation.

Length: the contact equations, their float and arb forms and the checks of a proved zero's contacts
read the same equation tuples; split apart they would pass them around.

Public API: :class:`VertexSolution`, :func:`prove_vertex`, :func:`prove_zero`, :func:`common_point`,
:func:`contact_equations`, :func:`direction_in_arc`, :func:`segment_floats`.
"""
from __future__ import annotations

import math
import weakref
from dataclasses import dataclass

import numpy as np
from flint import arb, arb_mat, ctx

from ..certify.foot import to_arb
from ..certify.interval_newton import KrawczykFailure, krawczyk_inflation
from .distance import foot_parameter
from .elementary import ARC, ELLIPSE, POINT, SEGMENT, ElementarySites
from .ellipse_contacts import (both_ends_contact, ellipse_centre_vertex, ellipse_contact_valid, foot_point,
                               past_centre_of_curvature)
from .ellipse_pieces import piece_feet

__all__ = ["VertexSolution", "prove_vertex", "prove_zero", "common_point", "contact_equations", "direction_in_arc",
           "arc_centre_vertex", "segment_floats"]

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
    """The end code (a point site, or a smooth joint < −1) in the closures of all three sites."""
    key = tuple(triple)
    if key in E.common_points:
        return E.common_points[key]
    cands = None
    for t in triple:
        pts = E.closure_points(t)
        cands = pts if cands is None else cands & pts
    cands = {c for c in (cands or ()) if c != -1}
    E.common_points[key] = out = next(iter(cands)) if cands else None
    return out


def arc_centre_vertex(E: ElementarySites, triple):
    """For a triple of an arc s and two sites whose closures hold its two ends (its end points,
    or the curves of its smooth joints): the arc's (centre, radius) — the centre is at distance
    ρ from the whole arc (a contact along the arc, not at one point); it is a Voronoi vertex when
    the open disc is empty.  None for other triples."""
    def holds(o, e):
        # an end that is a point site must be that site; a smooth joint, the curve continuing
        # the arc there (tangent to its circle); a curve through a corner may enter the disc
        return o == e if e >= 0 else (E.kind[o] != POINT and e in E.closure_points(o))

    for s in (int(t) for t in triple if E.kind[t] == ARC):
        others = [int(t) for t in triple if int(t) != s]
        ends = [int(E.ends[s, 0]), int(E.ends[s, 1])]
        if len(others) == 2 and any(holds(o1, ends[0]) and holds(o2, ends[1]) for o1, o2 in (others, others[::-1])):
            return E.arc[s]
    return None


def _tangent_at(E: ElementarySites, t: int, e: int):
    """The tangent direction of curve t at its end e (exact): the normal line at e is
    {v : tangent·(v − e) = 0}."""
    ex, ey = E.xy[e]
    if E.kind[t] == SEGMENT:
        (ax, ay), (bx, by) = E.xy[int(E.ends[t, 0])], E.xy[int(E.ends[t, 1])]
        return bx - ax, by - ay
    if E.kind[t] == ELLIPSE:
        arc = E.sites[t]
        return arc.tangent(arc.ua if int(E.ends[t, 0]) == e else arc.ub)
    (cx, cy), _rho = E.arc[t]
    return -(ey - cy), ex - cx


#: per set of sites: the exact lines of its segments and normal lines at curves' ends (they depend
#: on the sites only, like :attr:`ElementarySites.common_points`)
_MEMOS: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def _segment_line(E: ElementarySites, t: int):
    """((a, b, c, N), (a, b, c) as floats): the line a·x + b·y + c = 0 of segment t (exact, the
    normal (a, b) to the left of its direction, N = a² + b²)."""
    (ax, ay), (bx, by) = E.xy[int(E.ends[t, 0])], E.xy[int(E.ends[t, 1])]
    a, b = -(by - ay), bx - ax
    c = -(a * ax + b * ay)
    return (a, b, c, a * a + b * b), (float(a), float(b), float(c))


#: per set of sites: (done, L, T) of :func:`segment_floats`; ``done[t]`` once segment t is written
_FLOATS: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def segment_floats(E: ElementarySites, sites):
    """(L, T): for every segment t of ``sites`` (and those asked for before), L[t] = (fl(a),
    fl(b), fl(c), fl(√fl(N))) of its exact line a·x + b·y + c = 0 (:func:`_segment_line`) and
    T[t] the correctly rounded tangent B − A (:func:`_tangent_at`), as the batched contact
    systems read them (:func:`runtime.segments.vertex_batch.code_point_segment_rows`)."""
    n = len(E.kind)
    done, L, T = _FLOATS.get(E) or _FLOATS.setdefault(E, (np.zeros(n, bool), np.zeros((n, 4)), np.zeros((n, 2))))
    todo = np.unique(sites)
    memo = _MEMOS.setdefault(E, {})
    for t in todo[~done[todo]].tolist():
        line = memo.get(t)
        if line is None:
            line = memo[t] = _segment_line(E, t)
        (_a, _b, _c, N), (fa, fb, fc) = line
        tx, ty = _tangent_at(E, t, int(E.ends[t, 0]))
        L[t] = (fa, fb, fc, math.sqrt(float(N)))
        T[t] = (float(tx), float(ty))
        done[t] = True
    return L, T


def contact_equations(E: ElementarySites, triple, seed, alternate: bool = False):
    """The contact system of ``triple`` (see the module docstring): a list of
    (kind, exact data, site) with kinds "point" (px, py), "line" (a, b, c, σ, N),
    "normal" (tx, ty, ex, ey: the normal line at e of a curve ending there) and
    "arc" (cx, cy, ρ, σ); None when no circle can touch the three.  ``alternate``: for an elliptic
    piece touched at an end or joint, the other choice of :func:`past_centre_of_curvature`."""
    memo = _MEMOS.setdefault(E, {})
    pts = {int(t) for t in triple if E.kind[t] == POINT}
    curves = [int(t) for t in triple if E.kind[t] != POINT]
    joint_of: dict = {}
    for i, t1 in enumerate(curves):          # two curves of a smooth joint: point + normal line
        for t2 in curves[i + 1:]:
            shared = {int(v) for v in E.ends[t1] if v < -1} & {int(v) for v in E.ends[t2] if v < -1}
            if shared:              # two arcs of one circle share both joints: the nearer one
                j = min(shared, key=lambda c: (float(E.xy[c][0]) - seed[0]) ** 2 + (float(E.xy[c][1]) - seed[1]) ** 2)
                if E.kind[t1] == ELLIPSE and E.kind[t2] == ELLIPSE \
                        and past_centre_of_curvature(E, t1, j, seed) != alternate:
                    continue        # beyond the joint's centre of curvature: two feet
                joint_of[t1] = ("point", j)
                joint_of[t2] = ("normal", j)
    eqs = []
    for t in (int(v) for v in triple):
        if E.kind[t] == POINT:
            eqs.append(("point", E.xy[t], t))
            continue
        if t in joint_of:
            what, j = joint_of[t]
            eqs.append(("point", E.xy[j], t) if what == "point" else ("normal", _tangent_at(E, t, j) + E.xy[j], t))
            continue
        ends_in = [p for p in pts if p in (int(E.ends[t, 0]), int(E.ends[t, 1]))]
        if len(ends_in) == 2:
            if E.kind[t] == ELLIPSE:     # a circle through both ends may touch a curved piece between them
                eqs.append(both_ends_contact(E, t, seed, _tangent_at))
                continue
            return None              # both ends of a segment or circular arc and its interior: no circle
        if ends_in:
            e = ends_in[0]
            if E.kind[t] == ELLIPSE and past_centre_of_curvature(E, t, e, seed) != alternate:
                eqs.append(("ellipse", E.ellipse[t], t))      # an interior foot, not the end
            else:
                normal = memo.get((t, e))
                if normal is None:
                    normal = memo[(t, e)] = _tangent_at(E, t, e) + E.xy[e]
                eqs.append(("normal", normal, t))
            continue
        if E.kind[t] == SEGMENT:
            line = memo.get(t)
            if line is None:
                line = memo[t] = _segment_line(E, t)
            (a, b, c, N), (fa, fb, fc) = line
            side = fa * seed[0] + fb * seed[1] + fc
            eqs.append(("line", (a, b, c, 1 if side >= 0 else -1, N), t))
        elif E.kind[t] == ELLIPSE:
            eqs.append(("ellipse", E.ellipse[t], t))
        else:
            (cx, cy), rho = E.arc[t]
            out = (seed[0] - float(cx)) ** 2 + (seed[1] - float(cy)) ** 2 > float(rho) ** 2
            eqs.append(("arc", (cx, cy, rho, 1 if out else -1), t))
    return eqs


def _coefficients(eqs, num, sqrt) -> list[tuple]:
    """The contact equations' coefficients in one arithmetic (``num``: float or arb; a line's
    r-coefficient is side·√(a² + b²))."""
    co = []
    for kind, d, _t in eqs:
        if kind == "line":
            a, b, c, s, N = d
            co.append((kind, num(a), num(b), num(c), s * sqrt(num(N))))
        elif kind == "arc":
            cx, cy, rho, s = d
            co.append((kind, num(cx), num(cy), num(rho), s))
        elif kind == "ellipse":
            co.append((kind, d))
        else:
            co.append((kind,) + tuple(num(v) for v in d))
    return co


def _contact_residuals(co, z, zero):
    """Values and Jacobian rows in (x, y, r) of the contact equations at ``z``, in the arithmetic of
    ``co`` and ``z`` (the same expressions for the float Newton steps and the arb Krawczyk proof):
    point |q − p|² − r², line a·x + b·y + c − side·|(a, b)|·r, normal t·(q − e), arc
    |q − c|² − (ρ + side·r)²."""
    x, y, r = z
    out, J = [], []
    for e in co:
        if e[0] == "point":
            dx, dy = x - e[1], y - e[2]
            out.append(dx * dx + dy * dy - r * r)
            J.append([2 * dx, 2 * dy, -2 * r])
        elif e[0] == "line":
            out.append(e[1] * x + e[2] * y + e[3] - e[4] * r)
            J.append([e[1], e[2], -e[4]])
        elif e[0] == "normal":
            out.append(e[1] * (x - e[3]) + e[2] * (y - e[4]))
            J.append([e[1], e[2], zero])
        elif e[0] == "ellipse":
            fx, fy = foot_point(e[1], x, y)
            dx, dy = x - fx, y - fy
            out.append(dx * dx + dy * dy - r * r)
            J.append([2 * dx, 2 * dy, -2 * r])
        else:
            dx, dy, R = x - e[1], y - e[2], e[3] + e[4] * r
            out.append(dx * dx + dy * dy - R * R)
            J.append([2 * dx, 2 * dy, -2 * e[4] * R])
    return out, J


def _float_system(eqs):
    co = _coefficients(eqs, float, lambda v: v ** 0.5)

    def F(z):
        out, J = _contact_residuals(co, z, 0.0)
        return np.array(out), np.array(J)
    return F


def _arb_system(eqs):
    co = _coefficients(eqs, to_arb, lambda v: v.sqrt())
    return (lambda z: _contact_residuals(co, z, arb(0))[0]), (lambda z: _contact_residuals(co, z, arb(0))[1])


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
    centre = arc_centre_vertex(E, triple)
    if centre is not None:
        (cx, cy), rho = centre
        return VertexSolution("proved", float(cx), float(cy), float(rho), (to_arb(cx), to_arb(cy), to_arb(rho)),
                              reason="arc centre")
    centre = ellipse_centre_vertex(E, triple)
    if centre is not None:
        (cx, cy), b2 = centre
        return VertexSolution("proved", float(cx), float(cy), float(b2) ** 0.5,
                              (to_arb(cx), to_arb(cy), to_arb(b2).sqrt()), reason="ellipse centre")
    sol = _newton_and_proof(E, triple, seed, r_seed, cache, False)
    if sol.status != "proved" and any(E.kind[t] == ELLIPSE for t in triple):
        # the seed chose the contact at an end (or joint) or past its centre of curvature: the
        # other choice (the proof decides which zero, if any, is a vertex)
        other = _newton_and_proof(E, triple, seed, r_seed, cache, True)
        if other.status == "proved":
            return other
    return sol


def _newton_and_proof(E: ElementarySites, triple, seed, r_seed, cache, alternate: bool) -> VertexSolution:
    eqs = contact_equations(E, triple, seed, alternate)
    if eqs is None:
        return VertexSolution("invalid", float(seed[0]), float(seed[1]), 0.0, reason="a segment and both its endpoints")
    F = _float_system(eqs)
    z = np.array([seed[0], seed[1], r_seed if r_seed is not None else 1.0], dtype=float)
    if r_seed is None:
        z[2] = _r_guess(eqs, z)
    scale = 1.0 + float(np.max(np.abs(E.A)) if len(E.A) else 0.0)
    # with an elliptic piece the foot equation is not polynomial: steps are damped to half the
    # radius (a far seed otherwise jumps to the mirror zero of the squared equations, r < 0)
    damped = any(k == "ellipse" for k, _d, _t in eqs)
    for _ in range(80 if damped else 40):
        f, J = F(z)
        try:
            step = np.linalg.solve(J, f)
        except np.linalg.LinAlgError:
            return VertexSolution("undecided", z[0], z[1], z[2], reason="singular system")
        if damped:
            size = float(np.hypot(step[0], step[1]))
            cap = 0.5 * max(abs(float(z[2])), 1e-12 * scale)
            if size > cap:
                step = step * (cap / size)
        z = z - step
        if not np.all(np.isfinite(z)):
            return VertexSolution("undecided", float(seed[0]), float(seed[1]), 0.0, reason="Newton diverged")
        if np.max(np.abs(step)) <= 1e-15 * scale:
            break
    key = None
    if cache is not None:
        sides = tuple(d[3] if k in ("line", "arc") else 0 for k, d, _t in eqs)
        key = (tuple(triple), sides, alternate) + tuple(np.round(z / (1e-9 * scale)).astype(np.int64).tolist())
        if key in cache:
            return cache[key]
    sol = prove_zero(E, triple, eqs, z, scale)
    if key is not None:
        cache[key] = sol
    return sol


def prove_zero(E: ElementarySites, triple, eqs, z, scale) -> VertexSolution:
    """The arb Krawczyk proof of the contact system ``eqs`` of ``triple`` around the float zero
    ``z`` (x, y, r), and the checks that it touches each site where its equation says."""
    old = ctx.prec
    ctx.prec = PREC
    try:
        Fa, Ja = _arb_system(eqs)
        m = [arb(float(v)) for v in z]
        try:
            # an isotropic first radius (2^-44 of the scale): the residuals of the point
            # equations often cancel in Y·F(m), and a radius at the rounding floor in x, y
            # cannot absorb the r² term of the box
            K, _X = krawczyk_inflation(Fa, Ja, m, floor=arb(scale + abs(float(z[2]))) * arb(2) ** -44)
        except KrawczykFailure as exc:
            # an ill-conditioned system (three nearly collinear contacts: a circle of radius
            # 10⁶ over sites 10³ apart) leaves the float zero too far off for the box: Newton
            # steps at the working precision first, then a box at 2^-100 of the scale
            try:
                for _ in range(4):
                    Y = arb_mat(Ja(m)).mid().inv().mid()
                    step = Y * arb_mat([[v] for v in Fa(m)])
                    m = [(m[i] - step[i, 0]).mid() for i in range(3)]
                K, _X = krawczyk_inflation(Fa, Ja, m, floor=arb(scale + abs(float(z[2]))) * arb(2) ** -100)
            except (KrawczykFailure, ZeroDivisionError):
                return VertexSolution("undecided", *z, reason=f"Krawczyk: {exc}")
        x, y, r = K
        if not r > 0:
            return VertexSolution("invalid" if r <= 0 else "undecided", *z, box=tuple(K), reason="radius")
        for kind, d, t in eqs:
            verdict = _contact_valid(E, kind, d, t, x, y, r, triple)
            if verdict is not True:
                return VertexSolution("invalid" if verdict is False else "undecided", *z, box=tuple(K),
                                      reason=f"contact with site {t} outside its interior" if verdict is False
                                      else f"contact with site {t} at an end")
        return VertexSolution("proved", float(x.mid()), float(y.mid()), float(r.mid()), tuple(K))
    finally:
        ctx.prec = old


def _contact_valid(E: ElementarySites, kind, d, t, x, y, r, triple=()):
    """True when the proved zero touches site t where the equation says (a segment's foot in
    [0, 1], an arc's contact direction in its range with ρ + σr > 0, a normal line on the side
    of an arc's end away from the centre), False when it does not, None when undecided."""
    if kind == "line":
        u = foot_parameter(E.xy[int(E.ends[t, 0])], E.xy[int(E.ends[t, 1])], x, y)
        if u < 0 or u > 1:
            return False
        return True if (u >= 0 and u <= 1) else None
    if kind == "arc":
        cx, cy, rho, s = d
        R = to_arb(rho) + s * r
        if R <= 0:
            return False
        if not R > 0:
            return None
        return direction_in_arc(E, t, x - to_arb(cx), y - to_arb(cy))
    if E.kind[t] == ELLIPSE:
        return ellipse_contact_valid(E, kind, d, t, x, y, r, triple)
    if kind == "normal" and E.kind[t] == ARC:
        (cx, cy), _rho = E.arc[t]
        ex, ey = d[2], d[3]
        lam = (x - to_arb(cx)) * to_arb(ex - cx) + (y - to_arb(cy)) * to_arb(ey - cy)
        if lam <= 0:
            return False
        return True if lam > 0 else None
    return True


def direction_in_arc(E: ElementarySites, t: int, ux: arb, uy: arb):
    """The direction (ux, uy) from the centre in the closed range of arc t: True / False / None."""
    (cx, cy), _rho = E.arc[t]
    (ax, ay), (bx, by) = E.xy[int(E.ends[t, 0])], E.xy[int(E.ends[t, 1])]
    ax, ay, bx, by = ax - cx, ay - cy, bx - cx, by - cy
    ca = to_arb(ax) * uy - to_arb(ay) * ux
    cb = ux * to_arb(by) - uy * to_arb(bx)
    if ax * by - ay * bx > 0:
        if ca >= 0 and cb >= 0:
            return True
        if ca < 0 or cb < 0:
            return False
        return None
    if ca >= 0 or cb >= 0:
        return True
    if ca < 0 and cb < 0:
        return False
    return None


def _r_guess(eqs, z):
    rs = []
    for kind, d, _t in eqs:
        if kind == "point":
            rs.append(float(np.hypot(z[0] - float(d[0]), z[1] - float(d[1]))))
        elif kind == "line":
            a, b, c, _s, N = d
            rs.append(abs(float(a) * z[0] + float(b) * z[1] + float(c)) / float(N) ** 0.5)
        elif kind == "arc":
            cx, cy, rho, _s = d
            rs.append(abs(float(np.hypot(z[0] - float(cx), z[1] - float(cy))) - float(rho)))
        elif kind == "ellipse":
            rs.append(float(piece_feet(d, np.array([[z[0], z[1]]]))[0][0]))
    return float(np.mean(rs)) if rs else 1.0

