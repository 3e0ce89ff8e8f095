"""Exact decisions at degenerate vertices of points and segments (degree k > 3, feet at ends).

The contact system of three elementary sites (:mod:`runtime.segments.vertices`) is linear or
quadratic over Q(√N₁, √N₂, √N₃) (N the squared norms of the segments' normals), so a vertex has
closed-form coordinates in radicals.  :func:`exact_vertex` solves it with sympy, picks the root
inside the proved box, and :func:`on_circle` decides *exactly* whether a fourth site lies on the
vertex's circle — the zero test is ``sympy.minimal_polynomial(e) == x`` (an algebraic number is
zero iff its minimal polynomial is x), nonzero signs by evaluation once zero is excluded.  This is
the segment analogue of the quadratic towers of thesis §3.1.3 for circles.

A segment counts as touching only through its open interior (its foot parameter in (0, 1)) or
at an endpoint where the circle is tangent to it; a segment whose closest point is an endpoint
beyond its strip is represented by that endpoint, a site of its own (thesis §2.2).

Public API: :func:`exact_vertex`, :func:`on_circle`, :func:`exact_sign`, :func:`contacts_valid`.
"""
from __future__ import annotations

import sympy as sp

from ..sites.rationals import to_fraction
from .elementary import ARC, ELLIPSE, POINT, ElementarySites
from .vertices import arc_centre_vertex, contact_equations

__all__ = ["exact_vertex", "on_circle", "exact_sign", "contacts_valid"]

_X = sp.Symbol("_z")


def exact_sign(e) -> int:
    """The sign of the real algebraic number ``e`` (a sympy expression in radicals), exactly."""
    e = sp.nsimplify(e) if not isinstance(e, sp.Basic) else e
    if e == 0:
        return 0
    if e.is_Rational:
        return int(bool(e > 0)) - int(bool(e < 0))
    if sp.minimal_polynomial(e, _X) == _X:
        return 0
    v = sp.N(e, 60)
    return 1 if v > 0 else -1


def _srat(v) -> sp.Rational:
    """The SymPy Rational of an exact site coordinate."""
    f = to_fraction(v)
    return sp.Rational(f.numerator, f.denominator)


def exact_vertex(E: ElementarySites, triple, sol):
    """(x, y, r) in radicals: the zero of the triple's contact system
    (:func:`runtime.segments.vertices.contact_equations`) closest to ``sol``."""
    centre = arc_centre_vertex(E, triple)
    if centre is not None:
        (cx, cy), rho = centre
        return _srat(cx), _srat(cy), _srat(rho)
    x, y, r = sp.symbols("x y r", real=True)
    eqs = []
    for kind, d, _t in contact_equations(E, triple, (sol.x, sol.y)):
        if kind == "point":
            px, py = (_srat(v) for v in d)
            eqs.append((x - px) ** 2 + (y - py) ** 2 - r ** 2)
        elif kind == "line":
            a, b, c, N = (_srat(v) for v in (d[0], d[1], d[2], d[4]))
            eqs.append(a * x + b * y + c - d[3] * r * sp.sqrt(N))
        elif kind == "normal":
            tx, ty, ex, ey = (_srat(v) for v in d)
            eqs.append(tx * (x - ex) + ty * (y - ey))
        else:
            cx, cy, rho = (_srat(v) for v in d[:3])
            eqs.append((x - cx) ** 2 + (y - cy) ** 2 - (rho + d[3] * r) ** 2)
    roots = sp.solve(eqs, [x, y, r], dict=True)
    best, bd = None, None
    for s in roots:
        vals = [complex(sp.N(s[v], 30)) for v in (x, y, r)]
        if any(abs(v.imag) > 1e-20 * (1 + abs(v.real)) for v in vals):
            continue
        d = abs(vals[0].real - sol.x) + abs(vals[1].real - sol.y) + abs(vals[2].real - sol.r)
        if bd is None or d < bd:
            best, bd = (sp.radsimp(s[x]), sp.radsimp(s[y]), sp.radsimp(s[r])), d
    if best is None or bd > 1e-6 * (1 + abs(sol.x) + abs(sol.y) + sol.r):
        return None
    return best


def _closed_form(E: ElementarySites, triple, sol):
    """:func:`exact_vertex`, or None when no closed form is found."""
    try:
        return exact_vertex(E, triple, sol)
    except (NotImplementedError, ValueError):
        return None


def _end_points(E: ElementarySites, k: int):
    """The exact end points of curve k, as SymPy rationals."""
    return tuple(tuple(_srat(t) for t in E.xy[int(E.ends[k, i])]) for i in (0, 1))


def on_circle(E: ElementarySites, triple, sol, k: int):
    """"on" (site k touches the vertex's circle), "outside", False (k enters it) or None
    (not decided: no closed form found; always for elliptic pieces)."""
    if any(E.kind[t] == ELLIPSE for t in tuple(triple) + (k,)):
        return None
    v = _closed_form(E, triple, sol)
    if v is None:
        return None
    X, Y, R = v
    if E.kind[k] == POINT:
        px, py = (_srat(t) for t in E.xy[k])
        s = exact_sign((X - px) ** 2 + (Y - py) ** 2 - R ** 2)
        return "on" if s == 0 else ("outside" if s > 0 else False)
    (ax, ay), (bx, by) = _end_points(E, k)
    if E.kind[k] == ARC:
        return _on_arc(E, k, X, Y, R, (ax, ay), (bx, by))
    dx, dy = bx - ax, by - ay
    tnum = (X - ax) * dx + (Y - ay) * dy            # foot parameter × |b − a|²
    L2 = dx * dx + dy * dy
    s0, s1 = exact_sign(tnum), exact_sign(tnum - L2)
    if s0 < 0 or s1 > 0:        # closest point beyond an end
        return _at_end(E, k, 0 if s0 < 0 else 1, X, Y, R)
    if s0 == 0 or s1 == 0:
        ex, ey = (ax, ay) if s0 == 0 else (bx, by)
        s = exact_sign((X - ex) ** 2 + (Y - ey) ** 2 - R ** 2)
        return "on" if s == 0 else ("outside" if s > 0 else False)
    s = exact_sign((dy * (X - ax) - dx * (Y - ay)) ** 2 - L2 * R ** 2)
    return "on" if s == 0 else ("outside" if s > 0 else False)


def _at_end(E: ElementarySites, k: int, end: int, X, Y, R):
    """Curve k's closest point is its end ``end``: a point site decides for itself ("outside"
    for k); a smooth joint (not a site) is k's own contact, compared with R exactly."""
    code = int(E.ends[k, end])
    if code >= 0:
        return "outside"
    ex, ey = (_srat(t) for t in E.xy[code])
    s = exact_sign((X - ex) ** 2 + (Y - ey) ** 2 - R ** 2)
    return "on" if s == 0 else ("outside" if s > 0 else False)


def _on_arc(E: ElementarySites, k: int, X, Y, R, a, b):
    """:func:`on_circle` for an arc: its contact direction decided exactly, then the distance
    | |v − c| − ρ | compared with R."""
    (cx, cy), rho = E.arc[k]
    cx, cy, rho = _srat(cx), _srat(cy), _srat(rho)
    ux, uy = X - cx, Y - cy
    ax, ay, bx, by = a[0] - cx, a[1] - cy, b[0] - cx, b[1] - cy
    ca, cb = exact_sign(ax * uy - ay * ux), exact_sign(ux * by - uy * bx)
    small = ax * by - ay * bx > 0
    inside = (ca >= 0 and cb >= 0) if small else (ca >= 0 or cb >= 0)
    if not inside:              # the closest point is the nearer end
        da = (X - a[0]) ** 2 + (Y - a[1]) ** 2
        db = (X - b[0]) ** 2 + (Y - b[1]) ** 2
        return _at_end(E, k, 0 if exact_sign(da - db) <= 0 else 1, X, Y, R)
    at_a = ca == 0 and exact_sign(ax * ux + ay * uy) > 0     # pointing at a, not at −a
    at_b = cb == 0 and exact_sign(bx * ux + by * uy) > 0
    if at_a or at_b:
        ex, ey = ((ax, ay) if at_a else (bx, by))
        s = exact_sign((X - ex - cx) ** 2 + (Y - ey - cy) ** 2 - R ** 2)
        return "on" if s == 0 else ("outside" if s > 0 else False)
    s = exact_sign((sp.sqrt(ux ** 2 + uy ** 2) - rho) ** 2 - R ** 2)
    return "on" if s == 0 else ("outside" if s > 0 else False)


def contacts_valid(E: ElementarySites, triple, sol) -> bool | None:
    """Decide exactly, at the exact vertex of ``triple`` near ``sol``, that each interior contact
    lies in the closed curve (a segment's foot parameter in [0, 1], an arc's direction in its
    closed range) — the case where a contact is exactly at an end, which balls cannot decide.
    None when no closed form is found (always for elliptic pieces)."""
    if any(E.kind[t] == ELLIPSE for t in triple):
        return None
    v = _closed_form(E, triple, sol)
    if v is None:
        return None
    X, Y, R = v
    for kind, d, t in contact_equations(E, triple, (sol.x, sol.y)):
        if kind == "line":
            (ax, ay), (bx, by) = _end_points(E, t)
            dx, dy = bx - ax, by - ay
            tnum = (X - ax) * dx + (Y - ay) * dy
            if exact_sign(tnum) < 0 or exact_sign(tnum - dx * dx - dy * dy) > 0:
                return False
        elif kind == "arc":
            (cx, cy), _rho = E.arc[t]
            (ax, ay), (bx, by) = ((_srat(w) - _srat(c) for w, c in zip(E.xy[int(E.ends[t, 0])], (cx, cy))),
                                  (_srat(w) - _srat(c) for w, c in zip(E.xy[int(E.ends[t, 1])], (cx, cy))))
            ux, uy = X - _srat(cx), Y - _srat(cy)
            ca, cb = exact_sign(ax * uy - ay * ux), exact_sign(ux * by - uy * bx)
            inside = (ca >= 0 and cb >= 0) if ax * by - ay * bx > 0 else (ca >= 0 or cb >= 0)
            if not inside:
                return False
    return True
