"""Exact vertex proofs for circle and point sites (thesis §3.1.3), where floats cannot decide.

* A vertex of degree k > 3 (co-circular sites): the tower vertex of three of its sites, every
  other listed site exactly tangent, the sites listed counter-clockwise by contact points.
* Emptiness of a nearly co-circular vertex: the sign of |q − c|² − (r + ρ)² in the tower.

The exact arithmetic is that of :mod:`runtime.predicates.circles` (quadratic towers).

* A vertex of degree k > 3 with conic sites: equidistance proved by a symmetry fixing a rational
  point (:mod:`runtime.predicates.symmetry`).

Public API: :func:`cocircular_vertex`, :func:`symmetric_vertex`, :func:`exact_tower_vertex`,
:func:`exact_emptiness`.
"""
from __future__ import annotations

from fractions import Fraction

import math

__all__ = ["cocircular_vertex", "symmetric_vertex", "exact_tower_vertex", "exact_emptiness"]

EPS = 2.0 ** -53
VERTEX_TOL = 1e-10      # as in runtime.voronoi.verify.vertices


def vname(v) -> str:
    return f"vertex {v.id} (sites {', '.join(str(int(s)) for s in v.sites)})"


def cocircular_vertex(v, sites, geoms, problems, VertexInfo):
    """A reported vertex of k > 3 circle/point sites, proved exactly (thesis §3.1.3): the vertex of
    three of its sites in the quadratic tower of :func:`runtime.predicates.circles.
    voronoi_vertices_circles`, every other listed site exactly tangent to its circle
    (:func:`runtime.predicates.circles.decide_conflict`: the sign of |q − c|² − (r + ρ)² is 0),
    and the listed order counter-clockwise by contact points.  The order matters: the vertex's
    edges are those of consecutive sites (:mod:`runtime.voronoi.cocircular`), which the closure
    step requires.  Returns a ``VertexInfo`` (the class is passed in) whose ``exact`` holds the
    tower vertex, or None (problem recorded)."""
    from ...predicates.circles import decide_conflict, voronoi_vertices_circles
    from ...result import LocatorError

    name = vname(v)
    if not all(geoms[s].kind in ("point", "circle") for s in sites):
        return symmetric_vertex(v, sites, geoms, problems, VertexInfo)
    k = len(sites)
    tv = best = None
    for t in range(k):
        base = [sites[(t + u) % k] for u in range(3)]
        try:
            tv = voronoi_vertices_circles(*[geoms[s].exact for s in base])
        except LocatorError:
            continue
        if tv.vertices:
            break
    if tv is None or not tv.vertices:
        problems.append(f"{name}: no three of its sites have a Voronoi vertex")
        return None
    best = min(tv.vertices, key=lambda w: math.hypot(w.x - v.x, w.y - v.y))
    h = 2e-16 * (abs(best.x) + abs(best.y) + best.radius) + 1e-300
    tol = VERTEX_TOL * (1 + abs(best.x) + abs(best.y) + abs(best.radius))
    for w in tv.vertices:
        if w is not best and math.hypot(w.x - best.x, w.y - best.y) <= 2 * (tol + 2 * h):
            problems.append(f"{name}: two vertices of sites {', '.join(map(str, base))} are too close to tell apart")
            return None
    for s in sites:
        if s in base:
            continue
        dec = decide_conflict(tv, best, geoms[s].exact)
        if not dec.tangent:
            problems.append(f"{name}: site {s} does not touch the circle of sites {', '.join(map(str, base))} "
                            f"({'it enters it' if dec.in_conflict else 'it stays outside'})")
            return None
    # counter-clockwise order of the contact points: direction ±(c − q) (− inside a circle)
    ang = []
    for s in sites:
        g = geoms[s]
        cx, cy = (g.cx, g.cy) if g.kind == "circle" else (g.x0, g.y0)
        dx, dy = cx - best.x, cy - best.y
        dist = math.hypot(dx, dy)
        if g.kind == "circle" and dist < g.rho:          # the vertex inside site s: contact away from c
            dx, dy = -dx, -dy
        err = 16 * EPS * (abs(best.x) + abs(best.y) + abs(cx) + abs(cy) + best.radius) + 2 * h
        if not dist > 1e3 * err:
            problems.append(f"{name}: the contact point of site {s} cannot be placed")
            return None
        ang.append((math.atan2(dy, dx), err / dist))
    a = [t for t, _ in ang]
    rank = sorted(range(k), key=lambda t: a[t])
    start = rank.index(0)
    if [rank[(start + t) % k] for t in range(k)] != list(range(k)):
        problems.append(f"{name}: its sites are not listed counter-clockwise around it")
        return None
    for t in range(k):
        p, q = rank[t], rank[(t + 1) % k]
        gap = (a[q] - a[p]) % (2 * math.pi)
        if not gap > 4 * (ang[p][1] + ang[q][1]):
            problems.append(f"{name}: the contact points of sites {sites[p]} and {sites[q]} are too close to order")
            return None
    info = VertexInfo(v.id, tuple(sites), best.x, best.y, best.radius, h, None, key=(tuple(sorted(sites)), id(best)))
    info.exact = (tv, best)
    info.geoms = geoms          # for the exact vertices of its triples (edge proofs)
    return info


def exact_tower_vertex(inf, geoms):
    """(TripleVertices, CircleVertex): the exact vertex (thesis §3.1.3) of a proved circle/point
    vertex ``inf``: the one vertex of three of its sites within the proof's reach (the proved zero
    of the system is one of the at most two tower vertices; when both are within reach, None).
    Cached on ``inf``."""
    from ...predicates.circles import voronoi_vertices_circles
    from ...result import LocatorError

    ex = getattr(inf, "exact", None)
    if ex is not None:
        return ex
    if not all(geoms[s].kind in ("point", "circle") for s in inf.sites):
        return None
    try:
        tv = voronoi_vertices_circles(*[geoms[s].exact for s in inf.sites[:3]])
    except LocatorError:
        return None
    near = [w for w in tv.vertices if math.hypot(w.x - inf.x, w.y - inf.y) <= 4 * (inf.tol + inf.h)]
    if len(near) != 1:
        return None
    inf.exact = (tv, near[0])
    inf.geoms = geoms
    return inf.exact


def exact_emptiness(inf, k, geoms) -> str | None:
    """Where site k lies relative to the empty circle of the circle/point vertex ``inf``, decided
    exactly (:func:`runtime.predicates.circles.decide_conflict` on the tower vertex of three of
    its sites): "outside", "inside", "touches" (then the vertex has more sites than listed), or
    None when the tower vertex cannot be identified with the proved one."""
    from ...predicates.circles import decide_conflict

    if not all(geoms[s].kind in ("point", "circle") for s in (*inf.sites, k)):
        return None
    ex = exact_tower_vertex(inf, geoms)
    if ex is None:
        return None
    dec = decide_conflict(ex[0], ex[1], geoms[k].exact)
    if dec.in_conflict:
        return "inside"
    return "touches" if dec.tangent else "outside"


def symmetric_vertex(v, sites, geoms, problems, VertexInfo):
    """A reported vertex of k > 3 sites, some of them conics, proved by symmetry: a rational point
    p at the reported position is fixed by isometries that join all its sites
    (:func:`runtime.predicates.symmetry.equidistant_by_symmetry`), so every site is at exactly the
    same distance r from p; r is enclosed by the sites' rigorous distance bounds at p.  With the
    emptiness of p (every other site strictly farther, checked by the caller) p is a Voronoi vertex
    whose sites are exactly these.  The listed order is checked on the float foot points (an order
    that is not the true one makes the closure step demand edges that cannot be proved).  Returns
    a ``VertexInfo`` or None (problem recorded)."""
    import numpy as np

    from ...predicates.symmetry import equidistant_by_symmetry, rational_candidates

    name = vname(v)
    reach = 1e-12 * (1 + abs(v.x) + abs(v.y) + abs(v.radius))
    exact = [geoms[s].exact for s in sites]
    p = next((q for q in rational_candidates(v.x, v.y, reach) if equidistant_by_symmetry(exact, q)), None)
    if p is None:
        info = mirror_vertex(v, sites, geoms, VertexInfo)
        if info is not None:
            return _checked_order(info, v, sites, geoms, problems)
        problems.append(f"{name}: its {len(sites)} sites are not proved equidistant (no symmetry of them "
                        "fixes the reported point)")
        return None
    x, y = float(p[0]), float(p[1])
    # the box's half-width: twice the exact offset of float(p) from p (Fractions: a float minus a
    # Fraction would be computed in floats, i.e. 0), rounded up
    off = max(abs(Fraction(x) - p[0]), abs(Fraction(y) - p[1]))
    h = float(off) * 2 * (1 + 1e-15) + 1e-300
    P = np.array([[x, y]])
    lo = max(float(geoms[s].distance_bounds(P)[0][0]) for s in sites) - 2 * h
    hi = min(float(geoms[s].distance_bounds(P)[1][0]) for s in sites) + 2 * h
    if not lo <= hi:
        problems.append(f"{name}: the distance bounds of its sites do not overlap")
        return None
    info = VertexInfo(v.id, tuple(sites), x, y, 0.5 * (lo + hi), h, None,
                      key=(tuple(sorted(sites)), p))
    info.r_hi = hi
    info.exact_point = p
    return _checked_order(info, v, sites, geoms, problems)


def _checked_order(info, v, sites, geoms, problems):
    """The vertex ``info`` if its sites are listed counter-clockwise by their float foot points,
    else None (problem recorded)."""
    import numpy as np

    P = np.array([[info.x, info.y]])
    ang = []
    for s in sites:
        F, _ = geoms[s].foot_points(P)
        ang.append(math.atan2(F[0, 1] - info.y, F[0, 0] - info.x))
    k = len(sites)
    rank = sorted(range(k), key=lambda t: ang[t])
    start = rank.index(0)
    gaps = [(ang[rank[(t + 1) % k]] - ang[rank[t]]) % (2 * math.pi) for t in range(k)]
    if [rank[(start + t) % k] for t in range(k)] != list(range(k)) or min(gaps) < 1e-6:
        problems.append(f"{vname(v)}: its sites are not listed counter-clockwise around it")
        return None
    return info


def mirror_vertex(v, sites, geoms, VertexInfo):
    """A reported vertex of k > 3 sites on a mirror line of theirs at an irrational point: a line
    whose reflection maps the sites onto themselves in two orbits {a, a'}, {b, b'} makes every point
    of it equidistant from a and a', and from b and b'; g(t) = d_a − d_b along the line changes sign
    around the reported point (rigorous distance bounds at the two ends of a short segment), so
    some point p of the segment has all the sites at one distance (intermediate values), within
    the segment's half-length of the reported point.  Returns a ``VertexInfo`` (``h`` covering the
    segment, the radius enclosed on it) or None."""
    import numpy as np

    from ...predicates.symmetry import mirror_orbits

    found = mirror_orbits([geoms[s].exact for s in sites])
    if found is None or len(found[1]) != 2:
        return None
    (n, k), orbits = found
    a, b = sites[orbits[0][0]], sites[orbits[1][0]]
    nf = np.array([float(n[0]), float(n[1])])
    nn = float(np.hypot(*nf))
    u = np.array([-nf[1], nf[0]]) / nn                                  # along the line
    X = np.array([v.x, v.y], float)
    X = X - ((X @ nf - float(k)) / nn) * (nf / nn)                      # onto the line (floats)
    off = abs(float(np.array([v.x, v.y]) @ nf - float(k))) / nn
    scale = 1 + abs(v.x) + abs(v.y) + abs(v.radius)
    if off > 1e-9 * scale:
        return None
    for delta in (1e-12 * scale, 1e-10 * scale, 1e-8 * scale):
        E = np.array([X - delta * u, X + delta * u])
        # the segment's end points, as floats, are off the exact line by rounding only; the
        # distances are 1-Lipschitz, so a sign proved at a float point within ε of the line's
        # point holds there up to 2ε: take ε as a few ulps of the coordinates
        eps = 8 * EPS * float(np.abs(E).max() + 1)
        la, ha = geoms[a].distance_bounds(E)
        lb, hb = geoms[b].distance_bounds(E)
        g_hi, g_lo = ha - lb + 2 * eps, la - hb - 2 * eps
        if (g_hi[0] < 0 and g_lo[1] > 0) or (g_lo[0] > 0 and g_hi[1] < 0):
            P = X[None, :]
            lo = max(float(geoms[s].distance_bounds(P)[0][0]) for s in sites) - delta - eps
            hi = min(float(geoms[s].distance_bounds(P)[1][0]) for s in sites) + delta + eps
            if not lo <= hi:
                return None
            info = VertexInfo(v.id, tuple(sites), float(X[0]), float(X[1]), 0.5 * (lo + hi), delta + eps, None,
                              key=(tuple(sorted(sites)), round(float(X[0]), 9), round(float(X[1]), 9)))
            info.r_hi = hi
            return info
    return None
