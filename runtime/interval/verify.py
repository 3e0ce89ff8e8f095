"""Rigorous true-vertex and conflict decisions (thesis §6.1, Thm 5.2.2).

For a candidate vertex box Q and squared radius r, a site C is *clear* when no point of C lies
strictly inside the circle (q, √r).  The minimum of ``g(p) = |q − p|²`` over C is reached at a
critical point (``f = 0`` and ``(q − p) ∥ ∇f``), an arc endpoint or a singular point, so it is
enough to enclose all of them inside the disc: a 2-unknown branch-and-prune with q ∈ Q as
interval *parameters* (parametric Krawczyk: one zero per box for every q ∈ Q), pruning the
boxes where ``g > r`` for sure.  The foot point of the vertex itself (g = r exactly) is
recognised by containment in its certified box from the 8-unknown system.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from fractions import Fraction

import numpy as np
from flint import arb

from .boxes import Box, arb_hi, arb_lo
from .curves import Curve
from .poly import Poly
from .solver import System, SolverOptions, krawczyk, solve

CRIT = ("px", "py", "qx", "qy")


def crit_polys(curve: Curve):
    if not hasattr(curve, "_crit"):
        f = curve.f.rename(CRIT, [0, 1])
        fx = curve.fx.rename(CRIT, [0, 1])
        fy = curve.fy.rename(CRIT, [0, 1])
        qx, qy, px, py = (Poly.var(CRIT, k) for k in (2, 3, 0, 1))
        curve._crit = [f, (qx - px) * fy - (qy - py) * fx]
    return curve._crit


def d2_ball(Q: list, P: Box) -> arb:
    pa = P.arbs()
    dx, dy = Q[0] - pa[0], Q[1] - pa[1]
    return dx * dx + dy * dy  # not ** 2: python-flint 0.9 returns nan for a ball centred at 0


@dataclass
class Point:
    box: Box           # uniqueness box (for critical points) or the point enclosure
    tight: Box
    d2: arb
    arc: str           # 'in' | 'out' | 'unknown'
    kind: str          # 'critical' | 'endpoint' | 'singular'
    k: int = -1        # restriction index of an endpoint


def circle_position(p: Point, r_lo: float, r_hi: float) -> str:
    """Where a candidate site point p lies against the circle of squared radius r ∈ [r_lo, r_hi]
    around q ∈ Q (thesis §6.1, the emptiness of the circle): "outside" when p is not a point of the
    site (off its arc) or |q − p|² > r for sure; "inside" when p is a point of the site with
    |q − p|² < r for sure (the circle is not empty); "undecided" otherwise (on the circle, or the
    enclosures overlap)."""
    if p.arc == "out" or arb_lo(p.d2) > r_hi:
        return "outside"
    if arb_hi(p.d2) < r_lo and p.arc == "in":
        return "inside"
    return "undecided"


@dataclass
class Neighbourhood:
    points: list = field(default_factory=list)
    undecided: list = field(default_factory=list)
    boxes: int = 0


def critical_points(curve: Curve, Q: Box, threshold: float, max_boxes: int = 20000) -> Neighbourhood:
    """All critical points of |q − ·|² on the curve with |q − p|² <= threshold (q ∈ Q)."""
    rho = math.sqrt(max(threshold, 0.0)) * (1 + 1e-9) + 1e-300
    lo = [Q.lo[0] - rho, Q.lo[1] - rho]
    hi = [Q.hi[0] + rho, Q.hi[1] + rho]
    if curve.bbox is not None:
        lo = [max(lo[0], curve.bbox[0]), max(lo[1], curve.bbox[2])]
        hi = [min(hi[0], curve.bbox[1]), min(hi[1], curve.bbox[3])]
        if lo[0] > hi[0] or lo[1] > hi[1]:
            return Neighbourhood()
    qlo, qhi = Q.lo.copy(), Q.hi.copy()
    thr = threshold * (1 + 1e-12)

    def far(box: Box, xs) -> bool:
        gx = max(0.0, box.lo[0] - qhi[0], qlo[0] - box.hi[0])
        gy = max(0.0, box.lo[1] - qhi[1], qlo[1] - box.hi[1])
        if (gx * gx + gy * gy) * (1 - 1e-12) > thr:
            return True
        return bool(curve.where) and curve.where_status(xs[0], xs[1]) == "out"

    sysm = System(CRIT, 2, crit_polys(curve), [], [far], Q.arbs(), f"crit[{curve.name}]")
    res = solve(sysm, Box(np.array(lo), np.array(hi)), SolverOptions(bisection="largest", max_boxes=max_boxes,
                                                                      eps=1e-12))
    qa = Q.arbs()
    out = Neighbourhood(boxes=res.boxes)
    for s in res.solutions:
        ta = s.tight.arbs()
        arc = curve.where_status(ta[0], ta[1]) if curve.where else "in"
        out.points.append(Point(s.box, s.tight, d2_ball(qa, s.tight), arc, "critical"))
    out.undecided = list(res.undecided)
    return out


def special_points(curve: Curve, region: Box) -> tuple[list, list, list]:
    """(endpoints, singular points, notes) of a site inside region (cached on the curve).

    Endpoints: zeros of {f, h_k} (certified) that satisfy the other restrictions.  Singular
    points: zeros of {f_x, f_y} on the curve, kept only when they are exact rationals
    (checked with Fractions); others are reported in notes.
    """
    key = (tuple(region.lo), tuple(region.hi))
    cache = curve.__dict__.setdefault("_special", {})
    if key in cache:
        return cache[key]
    endpoints, singular, notes = [], [], []
    names = ("x", "y")
    for k, (h, _s) in enumerate(curve.where):
        sysm = System(names, 2, [curve.f, h], [], [], [], f"endpoint[{curve.name},{k}]")
        res = solve(sysm, region, SolverOptions(bisection="largest", max_boxes=20000))
        for s in res.solutions:
            ta = s.tight.arbs()
            others = Curve(curve.f, [w for kk, w in enumerate(curve.where) if kk != k], curve.name)
            st = others.where_status(ta[0], ta[1]) if others.where else "in"
            if st != "out":
                endpoints.append({"k": k, "box": s.box, "tight": s.tight, "arc": st})
        if not res.complete:
            notes.append(f"{curve.name}: endpoint search for restriction {k} incomplete")
    if curve.conic is None and curve.f.degree() > 2:
        sysm = System(names, 2, [curve.fx, curve.fy], [], [], [], f"singular[{curve.name}]")
        res = solve(sysm, region, SolverOptions(bisection="largest", max_boxes=20000))
        for s in res.solutions:
            ta = s.tight.arbs()
            v = curve.f.arb_eval(ta[0], ta[1])
            if arb_lo(v) > 0 or arb_hi(v) < 0:
                continue
            cand = [Fraction(float(m)).limit_denominator(10**6) for m in s.tight.mid]
            if curve.f(*cand) == 0 and curve.fx(*cand) == 0 and curve.fy(*cand) == 0:
                if curve.where:
                    st = curve.where_status(arb(cand[0].numerator) / cand[0].denominator,
                                            arb(cand[1].numerator) / cand[1].denominator)
                    if st == "out":
                        continue
                singular.append(tuple(cand))
            else:
                notes.append(f"{curve.name}: possible non-rational singular point near {s.tight.mid.tolist()}")
        if not res.complete:
            notes.append(f"{curve.name}: singular point search incomplete")
    cache[key] = (endpoints, singular, notes)
    return cache[key]


def _point_box(pt) -> Box:
    sx, sy = pt
    return Box.from_bounds([(sx, sx), (sy, sy)])


def neighbourhood(curve: Curve, Q: Box, threshold: float, region: Box, max_boxes: int = 20000) -> Neighbourhood:
    """Critical points + endpoints + singular points of the site with |q − p|² <= threshold."""
    nb = critical_points(curve, Q, threshold, max_boxes)
    endpoints, singular, _ = special_points(curve, region)
    qa = Q.arbs()
    for e in endpoints:
        d2 = d2_ball(qa, e["tight"])
        if arb_lo(d2) <= threshold:
            nb.points.append(Point(e["box"], e["tight"], d2, e["arc"], "endpoint", e["k"]))
    for s in singular:
        b = _point_box(s)
        d2 = d2_ball(qa, b)
        if arb_lo(d2) <= threshold:
            nb.points.append(Point(b, b, d2, "in", "singular"))
            # undecided boxes around an exact singular point are explained by it only if it is
            # itself decided; they stay undecided otherwise (handled by the caller)
    return nb


def _same_zero(curve: Curve, p: Point, own: Box, Q: Box) -> bool:
    """Prove that the zero in ``own`` is the zero of point p (uniqueness in the hull of both)."""
    if p.box.contains(own):
        return True
    if not p.box.inflate(2.0, 1e-12).overlaps(own):
        return False
    if p.kind == "critical":
        sysm = System(CRIT, 2, crit_polys(curve), [], [], Q.arbs(), "same")
    elif p.kind == "endpoint":
        sysm = System(("x", "y"), 2, [curve.f, curve.where[p.k][0]], [], [], [], "same")
    else:
        return False
    h = p.box.hull(own).inflate(2.0, 1e-13)
    st, _ = krawczyk(sysm, h)
    return st == "unique"


def site_status(curve: Curve, Q: Box, r: arb, own: Box | None, region: Box,
                own_kind: str = "normal") -> tuple[str, dict]:
    """'clear' (no site point strictly inside the circle), 'blocked' (proven point inside) or 'unknown'."""
    r_lo, r_hi = arb_lo(r), arb_hi(r)
    nb = neighbourhood(curve, Q, r_hi, region)
    status = "clear"
    own_found = own is None
    for p in nb.points:
        if own is not None and ((p.kind != "singular" and _same_zero(curve, p, own, Q))
                                or (p.kind == "singular" and own_kind == "point" and own.contains(p.box))):
            own_found = True
            continue
        where = circle_position(p, r_lo, r_hi)
        if where == "outside":
            continue
        if where == "inside":
            return "blocked", {"point": p.tight.mid.tolist(), "kind": p.kind, "boxes": nb.boxes}
        status = "unknown"
    if nb.undecided:
        status = "unknown"
    if not own_found:
        status = "unknown"
    return status, {"boxes": nb.boxes, "undecided": len(nb.undecided)}


def conflict_status(curve: Curve, Q: Box, r: arb, region: Box):
    """True (a point of C4 strictly inside the circle), False (none inside or on it), None."""
    r_lo, r_hi = arb_lo(r), arb_hi(r)
    nb = neighbourhood(curve, Q, r_hi, region)
    decided = True
    for p in nb.points:
        where = circle_position(p, r_lo, r_hi)
        if where == "inside":
            return True
        if where == "undecided":
            decided = False
    if nb.undecided:
        decided = False
    return False if decided else None


def distance_to(curve: Curve, Q: Box, start: float, region: Box, max_rounds: int = 12):
    """Enclosure (lo, hi) of d(q, C) for q ∈ Q, or None; grows the search disc from start²."""
    thr = max(start, 1e-30)
    for _ in range(max_rounds):
        nb = neighbourhood(curve, Q, thr, region)
        pts = [p for p in nb.points if p.arc != "out" and arb_lo(p.d2) <= thr]
        if pts:
            los = [max(0.0, arb_lo(p.d2)) for p in pts]
            his = [arb_hi(p.d2) for p in pts]
            lo, hi = min(los), min(h for h, p in zip(his, pts) if p.arc == "in") if any(p.arc == "in" for p in pts) else math.inf
            if nb.undecided:
                lo = 0.0 if not pts else lo
            if hi <= thr:
                return math.sqrt(lo), math.sqrt(hi), not nb.undecided
        thr *= 4.0
    return None
