"""Vertex proofs of the point/segment certificate (step 2 of :mod:`runtime.segments.certificate`),
independent of the construction's vertex code.

A reported vertex v (sites s_0 … s_{k−1}, position, radius) is proved as follows.

* **Corner** (the closures of all listed sites share a point site c): v = c exactly, radius 0.
  The sites at distance 0 from c are c and the segments ending at c; the listed sites must be
  exactly those segments sorted counter-clockwise by their exact directions (half-plane and
  cross-product comparisons of rationals), with c inserted between the two segments bounding the
  reflex angle (> 180°) when there is one.  Emptiness is admissibility: no other site contains c.
* **k = 3**: each listed site contributes a *touching-type* distance: |v − p| for a point, the
  signed distance σ·ℓ(v) to the line of a segment touched in its interior (σ: the side of the
  reported position), and for a segment s whose endpoint e is also listed the circle touches s at
  e, so v lies on the perpendicular to s at e: the equation (b − a)·(v − e) = 0 (a circle through e
  tangent to the line of s elsewhere would meet that line twice).  The k − 1 = 2 equations
  (perpendiculars, and d_{D0} − d_{Dj} over the distance-carrying sites) in (x, y) are solved by
  float Newton from the reported position and proved by Krawczyk
  (:func:`runtime.certify.interval_newton.krawczyk_inflation`) at 128 bits: one zero in a small
  box K, r = d_{D0}(K).  It is a vertex of the three sites when r > 0 and the foot parameter of
  every interior contact is in (0, 1) (then the line's distance is the closed segment's).
* **k > 3**: three sites whose equations (|v − p|² = r², a x + b y + c = σ r √(a² + b²), the
  perpendicular) have a regular Jacobian at the report are solved in closed form by sympy; the
  solution near the report is enclosed in arb from its radicals, and every other listed site's
  equation is proved to vanish exactly (``sympy.minimal_polynomial(residual) == z``).
* The reported position and radius are within :data:`VERTEX_TOL`·(1 + |x| + |y| + r) of the proved
  ones, and the contacts are counter-clockwise in the listed order: the counter-clockwise angles
  between consecutive contact points are enclosed in (0, 2π) and their sum (a multiple of 2π) is
  below 4π.  A segment touched at its listed endpoint e has e's contact point; for k ≥ 4 the pair
  is ordered as s just after e when s leaves e counter-clockwise around v.
* **Emptiness**: every other site is strictly farther than r (rigorous
  :meth:`runtime.segments.certificate_sites.SiteTable.distance` lower bound above the radius; sites far from v
  are excluded by a k-d tree over bounding discs and a float filter with rounding margins), except
  a segment with a listed endpoint e, which is always within r of v: its foot on it must be clamped
  strictly beyond e (then its distance is e's and the tie is e's by convention).

Public API: :class:`VertexProof`, :func:`prove_vertices`, :data:`VERTEX_TOL`.
"""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
from flint import arb, fmpq

from ..certify.interval_newton import KrawczykFailure, krawczyk_inflation
from ..voronoi.verify.problems import Problem, fault
from .certificate_exact import exact_vertex
from .certificate_sites import POINT, SEGMENT, SiteTable, hypot
from .distance import distances, float_error

__all__ = ["VertexProof", "prove_vertices", "VERTEX_TOL", "exact_direction_order"]

#: reported vertex positions and radii must be this close (relative) to the proved ones
VERTEX_TOL = 1e-10


@dataclass
class VertexProof:
    """``ok``: the vertex is proved; ``x``, ``y``, ``r``: arb enclosures of the exact vertex;
    ``corner``: the point site at a radius-0 vertex; ``listed``: its sites."""

    ok: bool
    x: arb | None = None
    y: arb | None = None
    r: arb | None = None
    corner: int | None = None
    listed: frozenset = frozenset()


def prove_vertices(D, T: SiteTable, problems: list) -> list[VertexProof]:
    out = []
    for v in D.vertices:
        try:
            out.append(_prove(T, v, problems))
        except (ValueError, ZeroDivisionError, ArithmeticError) as exc:      # pragma: no cover - defensive
            problems.append(Problem(f"vertex {v.id}: not proved ({exc.__class__.__name__}: {exc})", kind="vertex",
                                    vertex=v.id, sites=_valid(T, v.sites), fault=False))
            out.append(VertexProof(False))
    return out


def _valid(T, sites):
    return tuple(int(s) for s in sites if 0 <= int(s) < T.n)


def _name(v) -> str:
    return f"vertex {v.id} (sites {', '.join(map(str, v.sites))})"


def _tol(v) -> float:
    return VERTEX_TOL * (1 + abs(float(v.x)) + abs(float(v.y)) + abs(float(v.radius)))


def _prove(T: SiteTable, v, problems) -> VertexProof:
    sites = tuple(int(s) for s in v.sites)
    k = len(sites)
    name = _name(v)
    if k < 3 or len(set(sites)) != k or not all(0 <= s < T.n for s in sites):
        problems.append(fault(f"{name}: a vertex needs 3 or more distinct valid sites", kind="vertex",
                              vertex=v.id, sites=_valid(T, sites)))
        return VertexProof(False)
    if not all(math.isfinite(float(t)) for t in (v.x, v.y, v.radius)):
        return VertexProof(False)
    if any(T.kind[s] is None or (T.kind[s] == SEGMENT and T.ends[s] is None) for s in sites):
        return VertexProof(False)
    common = None
    for s in sites:
        pts = {s} if T.kind[s] == POINT else set(T.ends[s])
        common = pts if common is None else common & pts
    if common:
        return _corner(T, v, sites, next(iter(common)), problems)
    return _general(T, v, sites, problems)


# ------------------------------------------------------------------------------------ corners
def _half(d) -> int:
    return 0 if (d[1] > 0 or (d[1] == 0 and d[0] > 0)) else 1


def _cmp(d, e) -> int:
    h, g = _half(d), _half(e)
    if h != g:
        return h - g
    c = d[0] * e[1] - d[1] * e[0]
    return -1 if c > 0 else (1 if c < 0 else 0)


def exact_direction_order(T: SiteTable, c: int) -> list:
    """The corner list of point site c: its segments counter-clockwise by exact direction, c
    inserted in the reflex gap (> 180°) if there is one."""
    segs = list(T.incident[c])
    pc = T.a[c]

    def out_dir(s):
        o = T.b[s] if T.ends[s][0] == c else T.a[s]
        return (o[0] - pc[0], o[1] - pc[1])

    order = sorted(segs, key=functools.cmp_to_key(lambda s, t: _cmp(out_dir(s), out_dir(t))))
    m = len(order)
    if m == 1:
        return order + [c]
    for t in range(m):
        d, e = out_dir(order[t]), out_dir(order[(t + 1) % m])
        if d[0] * e[1] - d[1] * e[0] < 0:
            return order[:t + 1] + [c] + order[t + 1:]
    return order


def _same_cycle(a, b) -> bool:
    if len(a) != len(b) or set(a) != set(b):
        return False
    m = list(b).index(a[0])
    return list(a) == list(b[m:]) + list(b[:m])


def _corner(T: SiteTable, v, sites, c, problems) -> VertexProof:
    name = _name(v)
    want = exact_direction_order(T, c)
    if set(sites) != set(want):
        problems.append(fault(f"{name}: the sites at distance 0 from the corner point site {c} are "
                              f"{sorted(want)}, the vertex lists {sorted(sites)}", kind="vertex", vertex=v.id,
                              sites=sites))
        return VertexProof(False)
    if not _same_cycle(sites, want):
        problems.append(fault(f"{name}: the sites of the corner {c} are not listed counter-clockwise "
                              f"(expected the cyclic order {tuple(want)})", kind="vertex", vertex=v.id, sites=sites))
        return VertexProof(False)
    x, y = T.a[c]
    tol = _tol(v)
    if not (abs(float(v.x) - float(x)) <= tol and abs(float(v.y) - float(y)) <= tol and abs(float(v.radius)) <= tol):
        problems.append(fault(f"{name}: the corner vertex is the point site {c} at ({x}, {y}) with radius 0, "
                              f"reported at ({v.x!r}, {v.y!r}) with radius {v.radius!r}", kind="vertex",
                              vertex=v.id, sites=sites))
        return VertexProof(False)
    return VertexProof(True, T.arb_ends(c)[0], T.arb_ends(c)[1], arb(0), c, frozenset(sites))


# ------------------------------------------------------------------------------------ general
def _terms(T: SiteTable, sites, xr, yr):
    """Per listed site: ("pt", px, py) | ("ln", nx, ny, c, σ) | ("pp", dx, dy, ex, ey, e, s) with
    exact Fractions; None when a segment lists both its endpoints or σ is undecided."""
    out = []
    listed = set(sites)
    for s in sites:
        if T.kind[s] == POINT:
            out.append(("pt",) + T.a[s])
            continue
        ends = [e for e in T.ends[s] if e in listed]
        (ax, ay), (bx, by) = T.a[s], T.b[s]
        if len(ends) == 2:
            return None
        if ends:
            ex, ey = T.a[ends[0]]
            out.append(("pp", bx - ax, by - ay, ex, ey, ends[0], s))
            continue
        nx, ny = -(by - ay), bx - ax
        c = -(nx * ax + ny * ay)
        side = float(nx) * xr + float(ny) * yr + float(c)
        if side == 0:
            return None
        out.append(("ln", nx, ny, c, 1 if side > 0 else -1))
    return out


def _value(term, x, y, num):
    """The touching-type distance (or the perpendicular's residual) at (x, y); ``num`` converts
    exact coefficients (float or arb)."""
    if term[0] == "pt":
        return math.hypot(x - num(term[1]), y - num(term[2])) if num is float else \
            hypot(x - num(term[1]), y - num(term[2]))
    if term[0] == "ln":
        nx, ny, c, sg = num(term[1]), num(term[2]), num(term[3]), term[4]
        nn = (nx * nx + ny * ny) ** 0.5 if num is float else (nx * nx + ny * ny).sqrt()
        return sg * (nx * x + ny * y + c) / nn
    return num(term[1]) * (x - num(term[3])) + num(term[2]) * (y - num(term[4]))


def _grad(term, x, y, num):
    if term[0] == "pt":
        dx, dy = x - num(term[1]), y - num(term[2])
        d = math.hypot(dx, dy) if num is float else hypot(dx, dy)
        return dx / d, dy / d
    if term[0] == "ln":
        nx, ny, sg = num(term[1]), num(term[2]), term[4]
        nn = (nx * nx + ny * ny) ** 0.5 if num is float else (nx * nx + ny * ny).sqrt()
        return sg * nx / nn, sg * ny / nn
    return num(term[1]), num(term[2])


def _arbq(q):
    return arb(fmpq(q.numerator, q.denominator))


def _system(terms, num):
    """F, J of the k − 1 equations: perpendiculars, then d_{D0} − d_{Dj}."""
    perps = [t for t in terms if t[0] == "pp"]
    dist = [t for t in terms if t[0] != "pp"]

    def F(z):
        x, y = z
        out = [_value(t, x, y, num) for t in perps]
        d0 = _value(dist[0], x, y, num)
        return out + [d0 - _value(t, x, y, num) for t in dist[1:]]

    def J(z):
        x, y = z
        rows = [list(_grad(t, x, y, num)) for t in perps]
        g0 = _grad(dist[0], x, y, num)
        for t in dist[1:]:
            g = _grad(t, x, y, num)
            rows.append([g0[0] - g[0], g0[1] - g[1]])
        return rows
    return F, J, dist[0]


def _general(T: SiteTable, v, sites, problems) -> VertexProof:
    name = _name(v)
    xr, yr = float(v.x), float(v.y)
    terms = _terms(T, sites, xr, yr)
    if terms is None or not any(t[0] != "pp" for t in terms):
        problems.append(fault(f"{name}: no circle of positive radius touches these sites there (a segment and "
                              "both its endpoints, or a site through the reported centre)", kind="vertex",
                              vertex=v.id, sites=sites))
        return VertexProof(False)
    if len(sites) == 3:
        box = _krawczyk(terms, xr, yr)
        if box is None:
            problems.append(Problem(f"{name}: no proved equidistant point near the reported position (Krawczyk "
                                    "failed)", kind="vertex", vertex=v.id, sites=sites))
            return VertexProof(False)
        X, Y = box
        F, J, d0 = _system(terms, _arbq)
        R = _value(d0, X, Y, _arbq)
    else:
        sol = exact_vertex(terms, v, sites, _tol(v))
        if isinstance(sol, str):
            problems.append(Problem(f"{name}: {sol}", kind="vertex", vertex=v.id, sites=sites,
                                    fault=sol.startswith("site")))
            return VertexProof(False)
        X, Y, R = sol
    if not R > 0:
        problems.append(fault(f"{name}: the equidistant point has no positive radius", kind="vertex", vertex=v.id,
                              sites=sites))
        return VertexProof(False)
    for s, t in zip(sites, terms):
        if t[0] == "ln":
            u = T.foot(s, X, Y)
            if not (u > 0 and u < 1):
                what = "outside" if (u < 0 or u > 1) else "at an end of"
                problems.append(fault(f"{name}: the circle touches the line of segment {s} {what} the segment",
                                      kind="vertex", vertex=v.id, sites=sites))
                return VertexProof(False)
    tol = _tol(v)
    if not ((X - xr).abs_upper() <= tol and (Y - yr).abs_upper() <= tol and (R - float(v.radius)).abs_upper() <= tol):
        problems.append(fault(f"{name}: the proved vertex is at ({float(X.mid())!r}, {float(Y.mid())!r}) radius "
                              f"{float(R.mid())!r}, reported at ({xr!r}, {yr!r}) radius {float(v.radius)!r}",
                              kind="vertex", vertex=v.id, sites=sites))
        return VertexProof(False)
    if not _ccw(T, sites, terms, X, Y):
        problems.append(fault(f"{name}: the sites are not listed counter-clockwise by their contact points",
                              kind="vertex", vertex=v.id, sites=sites))
        return VertexProof(False)
    if not _empty(T, v, sites, X, Y, R, problems):
        return VertexProof(False)
    return VertexProof(True, X, Y, R, None, frozenset(sites))


def _krawczyk(terms, xr, yr):
    Ff, Jf, _ = _system(terms, float)
    z = np.array([xr, yr])
    with np.errstate(all="ignore"):
        for _ in range(30):
            try:
                f = np.array(Ff(z), dtype=float)
                step = np.linalg.solve(np.array(Jf(z), dtype=float), f)
            except (np.linalg.LinAlgError, ValueError, ZeroDivisionError):
                return None
            z = z - step
            if not np.all(np.isfinite(z)):
                return None
            if np.max(np.abs(step)) <= 1e-16 * (1 + np.max(np.abs(z))):
                break
    Fa, Ja, _ = _system(terms, _arbq)
    try:
        # a floor of 2^-80 of the scale: a coordinate that is exact in floats (YF_i = 0) must not
        # start at a radius below the second-order coupling of the other one
        floor = arb(1 + float(np.max(np.abs(z)))) * arb(2) ** -80
        K, _X = krawczyk_inflation(Fa, Ja, [arb(float(z[0])), arb(float(z[1]))], floor=floor)
    except (KrawczykFailure, ZeroDivisionError, ValueError):
        return None
    return K[0], K[1]


# ------------------------------------------------------------------------------------ order
def _ccw(T: SiteTable, sites, terms, X, Y) -> bool:
    k = len(sites)
    C = []
    for s, t in zip(sites, terms):
        ax, ay, bx, by = T.arb_ends(s)
        if t[0] == "pt":
            C.append((ax, ay, None))
        elif t[0] == "ln":
            u = T.foot(s, X, Y)
            C.append((ax + u * (bx - ax), ay + u * (by - ay), None))
        else:
            e = t[5]
            ex, ey = T.arb_ends(e)[:2]
            o = T.ends[s][1] if T.ends[s][0] == e else T.ends[s][0]
            ox, oy = T.arb_ends(o)[:2]
            C.append((ex, ey, (e, ox - ex, oy - ey)))
    total = arb(0)
    two_pi = 2 * arb.pi()
    for m in range(k):
        s, s2 = sites[m], sites[(m + 1) % k]
        c, c2 = C[m], C[(m + 1) % k]
        tie = (c[2] is not None and c[2][0] == s2) or (c2[2] is not None and c2[2][0] == s)
        if tie:
            if k >= 4:
                seg_first = c[2] is not None and c[2][0] == s2
                ex, ey, (e, ox, oy) = (c if seg_first else c2)
                cr = (ex - X) * oy - (ey - Y) * ox
                if not ((cr < 0) if seg_first else (cr > 0)):
                    return False
            continue
        ux, uy, vx, vy = c[0] - X, c[1] - Y, c2[0] - X, c2[1] - Y
        cr = ux * vy - uy * vx
        dt = ux * vx + uy * vy
        if cr > 0:
            total += arb.atan2(cr, dt)
        elif cr < 0:
            total += arb.atan2(cr, dt) + two_pi
        elif dt < 0:
            total += arb.pi() + (cr / dt).atan()
        else:
            return False
    return bool(total < 2 * two_pi)


# ------------------------------------------------------------------------------------ emptiness
def _empty(T: SiteTable, v, sites, X, Y, R, problems) -> bool:
    listed = set(sites)
    name = _name(v)
    cx, cy = float(X.mid()), float(Y.mid())
    rad = float(X.rad()) + float(Y.rad())
    r_hi = float(R.upper())
    cand = [k for k in T.near(cx, cy, r_hi + 2 * rad) if k not in listed]
    if not cand:
        return True
    cand = np.array(cand, dtype=int)
    Q = np.repeat([[cx, cy]], len(cand), axis=0)
    d, _ = distances(T.A[cand], T.B[cand], Q)
    err = float_error(T.A[cand], T.B[cand], Q) + 8 * np.finfo(float).eps * T.scale
    clear = d - err - 2 * rad > r_hi * (1 + 1e-12) + 1e-300
    ok = True
    for k, c in zip(cand.tolist(), clear.tolist()):
        if c:
            continue
        if T.kind[k] == SEGMENT:
            le = [e for e in T.ends[k] if e in listed]
            if le:
                u = T.foot(k, X, Y)
                good = len(le) == 1 and ((u < 0) if T.ends[k][0] == le[0] else (u > 1))
                if not good:
                    problems.append(fault(f"{name}: segment {k} is closer than the radius (its nearest point is "
                                          f"not its listed endpoint {le[0]}), or too close to decide",
                                          kind="vertex", vertex=v.id, sites=tuple(sites) + (k,)))
                    ok = False
                continue
        dk = T.distance(k, X, Y)
        if not dk > R:
            what = "inside the circle" if dk < R else "too close to decide (on the circle?)"
            problems.append(fault(f"{name}: site {k} is {what}", kind="vertex", vertex=v.id,
                                  sites=tuple(sites) + (k,)))
            ok = False
    return ok
