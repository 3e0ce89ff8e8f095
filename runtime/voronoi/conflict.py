"""The locate step of a local insertion (thesis §1.2): where a new site starts to conflict.

A new site s takes from the old diagram exactly the points strictly closer to s than to their
nearest old site.  For pairwise-disjoint bounded convex sites (points, circles, ellipses) with
no nesting these distances form an abstract Voronoi diagram (Klein, Mehlhorn & Meiser, CGTA 3
(1993); for circles Karavelas & Yvinec, ESA 2002), in which the region R(s) of the new site is
connected and contains s.  The *conflict region* R(s) ∩ (old skeleton) is then connected, and
when it is not empty it meets the boundary of the old region of the site nearest to any point p
of R(s) (a path inside R(s) from p to the conflict region leaves that old region through its
boundary, which is skeleton).  :func:`nearest_old_sites` returns every old site that may be the
nearest to such a point p (rigorous distance bounds, ties kept):

* a circle or a point: p is its centre, with the additively weighted distance |p − c_k| − ρ_k
  (d(c_s, S_k) for a site k outside s; c_s ∈ R(s) since the discs are disjoint and not nested);
* an ellipse: p is the end of its major axis, a point of s to rounding; p ∈ R(s) is checked,
  hi_s(p) < lo_k(p) for every old site k (the sites' own ``distance_bounds``), else None.

:func:`outside` is the vertex test of the breadth-first growth: d(v, s) > r_v proved with the
verifier's vertex tolerance around the reported position and radius.  :func:`disc_inside` is
the test at infinity: a disc strictly inside the convex hull of points (for a site, its centre
and a bounding radius: h_s(θ) ≤ c_s·e(θ) + R_s < max_k c_k·e(θ) ≤ max_k h_k(θ), the centre of a
convex site lying in it).

**The reach of an arc** (:func:`cell_radius`, :func:`arc_reach`): the proofs of an update with
ellipses need every site that can enter the empty circle of a point of a new edge's arc, read from
the regions, not from the polyline.  Let every site k lie in a disc (c_k, R_k) (:func:`site_disc`),
so that for every point q

    |q − c_k| − R_k  ≤  d(q, S_k)  ≤  |q − c_k| + R_k.                                    (1)

*Region.*  If d(q, S_i) ≤ d(q, S_k) for every k of a set T, then by (1)
|q − c_i| − R_i ≤ |q − c_k| + R_k for k ∈ T.  Write q = c_i + t·u (|u| = 1, t ≥ 0), w = c_k − c_i,
s = R_i + R_k.  For t > s, squaring (t − s)² ≤ |t·u − w|² gives 2t(u·w − s) ≤ |w|² − s², so when
u·w > s

    t  ≤  t_k(u) = (|w|² − s²) / (2 (u·w − s))                                            (2)

(and t ≤ s ≤ t_k(u) otherwise, since u·w > s forces |w| > s and t_k(u) ≥ (|w| + s)/2 ≥ s).
Over a sector of directions of angle Δ around u_m, |u − u_m| ≤ Δ/2, hence u·w ≥ u_m·w − |w|Δ/2 =: g_k
and t ≤ (|w|² − s²) / (2 (g_k − s)) whenever g_k > s.  :func:`cell_radius` returns ρ, the largest
over 64 sectors of the smallest such bound over T (None when a sector has none: T does not
surround site i), so |q − c_i| ≤ ρ on the region of i among T — and on its region among any set
of sites containing T.

*Reach.*  Let q be a point of the arc of an edge (i, j) proved (by the verifier, against a set of
sites containing T) nearer to i and j than to those sites, so q lies in that region and, by (1),
its empty circle has radius r(q) = d(q, S_i) ≤ |q − c_i| + R_i ≤ ρ + R_i.  A site k that enters
it has |q − c_k| − R_k ≤ d(q, S_k) < r(q), so

    |c_k − c_i|  ≤  |c_k − q| + |q − c_i|  <  2ρ + R_i + R_k  =  arc_reach + R_k.          (3)

Every site with its centre within :func:`arc_reach` + max_k R_k of c_i is therefore handed to the
proof, which makes it complete: a site outside cannot reach any point of the arc.  (3) is tight
when q is the farthest point of the region in the direction of c_k (t = ρ) and S_i, S_k meet their
discs' far sides (tests/test_insertion_reach.py builds that configuration.)

*Rounding.*  The margins cover the float evaluation: u·w and |w| carry relative errors of a few
units in the last place of |w| + |c_i| (the differences w = c_k − c_i are rounded; scenes whose
coordinates exceed 10⁶ are rebuilt, not updated, so these stay below 10⁻⁹ (|w| + s + 1)); the
quotient (2) is taken only when g_k − s exceeds |w|·Δ/2 ≈ 0.05 |w|, so |w|² − s² ≥ 0.05 |w|² has no
cancellation, and ρ is enlarged by a relative 10⁻⁶ and an absolute 10⁻⁹ (max |w| + 1).

Public API: :func:`site_disc`, :func:`nearest_old_sites`, :func:`outside`, :func:`disc_inside`,
:func:`cell_radius`, :func:`arc_reach`.
"""
from __future__ import annotations

from functools import lru_cache

import numpy as np

from .geometry import rounding_slack
from .verify.vertices import VERTEX_TOL

__all__ = ["site_disc", "nearest_old_sites", "outside", "disc_inside", "cell_radius", "arc_reach", "LOCAL_KINDS"]

EPS = 2.0 ** -53
#: the site kinds a diagram can be edited locally with (bounded convex sites)
LOCAL_KINDS = ("point", "circle", "ellipse")


def site_disc(g):
    """(centre, radius) of a disc containing the site whose centre lies in the site's convex hull:
    a point itself, a circle's disc, an ellipse's circumscribed disc (centre, major semi-axis)."""
    if g.kind == "point":
        return (g.x0, g.y0), 0.0
    if g.kind == "circle":
        return (g.cx, g.cy), g.rho
    if g.kind == "ellipse":
        return (g.tx, g.ty), g.a * (1 + 4 * EPS) + rounding_slack(abs(g.tx) + abs(g.ty) + g.a)
    raise ValueError(f"no bounding disc for a {g.kind} site")


def _candidates(dyn, X, n):
    """About 8 old sites (index < n) with the centres nearest to X (any non-empty set is sound:
    it only sets the search radius of :func:`nearest_old_sites`)."""
    return sorted(k for k in dyn.nearest(X, 9) if k < n)


def nearest_old_sites(dyn, g, n, scale):
    """Every old site (index < n) that may be nearest to the point p of R(s) chosen for the new
    site s of geometry g (module docstring); None when p ∈ R(s) cannot be shown (the caller
    rebuilds)."""
    if g.kind in ("point", "circle"):
        (cx, cy), _ = site_disc(g)
        cs = np.array([cx, cy], float)

        def bounds(pool):
            d = np.hypot(*(dyn.C[pool] - cs).T) - dyn.R[pool]
            slack = rounding_slack(np.abs(dyn.C[pool]).sum(axis=1) + np.abs(cs).sum() + dyn.R[pool]) + 1e-12 * scale
            return d - slack, d + slack
        p = cs
    else:
        p = np.asarray(g.from_canonical(np.array([g.a]), np.array([0.0])), float).reshape(-1, 2)[0]

        def bounds(pool):
            lo, hi = np.empty(len(pool)), np.empty(len(pool))
            for t, k in enumerate(pool):
                lo_k, hi_k = dyn.geoms[k].distance_bounds(p[None, :])
                lo[t], hi[t] = float(lo_k[0]), float(hi_k[0])
            return lo, hi
    pool = _candidates(dyn, p, n)
    _, hi = bounds(pool)
    pool = [k for k in dyn.near(p, float(hi.min()) + dyn.rmax + 2e-12 * scale) if k < n]
    lo, hi = bounds(pool)
    h = float(hi.min())
    if g.kind not in ("point", "circle"):
        # p is a point of s to rounding: it lies in the new region when no old site is as near
        # (sites outside the pool are farther than h ≥ min lo)
        _, hs = g.distance_bounds(p[None, :])
        if not float(hs[0]) < float(lo.min()):
            return None
    return [k for k, l in zip(pool, lo.tolist()) if l <= h]


def outside(verts, ids, g):
    """Proved d(v, s) > r_v for each vertex id (rigorous bounds, the verifier's vertex tolerance
    twice around the reported position and radius; distances are 1-Lipschitz)."""
    if not ids:
        return np.zeros(0, bool)
    P = np.array([[verts[v].x, verts[v].y] for v in ids], float)
    r = np.array([verts[v].radius for v in ids], float)
    tol = 2 * VERTEX_TOL * (1 + np.abs(P).sum(axis=1) + np.abs(r)) + 16 * EPS * np.abs(P).sum(axis=1)
    if g.kind in ("point", "circle"):
        (cx, cy), rs = site_disc(g)
        d = np.abs(np.hypot(P[:, 0] - cx, P[:, 1] - cy) - rs)
        lo = d - rounding_slack(np.abs(P).sum(axis=1) + abs(cx) + abs(cy) + rs)
    else:
        lo, _ = g.distance_bounds(P)
    return lo - tol > r + tol + rounding_slack(r)


def cell_radius(C, R, i, T, sectors: int = 64):
    """A radius ρ such that every point q with |q − c_i| − R_i ≤ |q − c_k| + R_k for all k in T
    lies within ρ of c_i (C, R: centres and radii of discs containing the sites), or None when
    the discs T do not surround disc i: by (1) of the module docstring, every point at least as
    near to site i as to each site of T (i's Voronoi region among any sites including T) lies
    within ρ.  Bound (2) of the module docstring over ``sectors`` sectors of directions."""
    T = np.asarray(T, dtype=int)
    if not len(T):
        return None
    W = np.asarray(C, float)[T] - np.asarray(C, float)[i]
    s = np.asarray(R, float)[T] + float(R[i])
    nw = np.hypot(W[:, 0], W[:, 1])
    th = (np.arange(sectors) + 0.5) * (2 * np.pi / sectors)
    U = np.column_stack([np.cos(th), np.sin(th)])
    lb = U @ W.T - nw[None, :] * (np.pi / sectors) - 1e-9 * (nw[None, :] + s[None, :] + 1.0)
    gap = lb - s[None, :] * (1 + 1e-9)
    with np.errstate(divide="ignore", invalid="ignore"):
        tb = np.where(gap > 0, (nw ** 2 - s ** 2)[None, :] / (2 * gap), np.inf)
    per = tb.min(axis=1)
    if not np.isfinite(per).all():
        return None
    return float(per.max()) * (1 + 1e-6) + 1e-9 * (float(np.abs(W).max()) + 1.0)


def arc_reach(C, R, i, T, sectors: int = 64):
    """2ρ + R_i (ρ = :func:`cell_radius`): every site k that can enter the empty circle of a point
    of site i's region among T (among any sites including T) has |c_k − c_i| < arc_reach + R_k
    (inequality (3) of the module docstring); None when T does not surround site i."""
    rho = cell_radius(C, R, i, T, sectors)
    return None if rho is None else 2.0 * rho + float(np.asarray(R, float)[i])


def disc_inside(P, c, r) -> bool:
    """The disc (c, r) lies strictly inside the convex hull of the points P, with a margin of
    1e-9 of the coordinates (False when it cannot be shown).  The polygon tested is the monotone
    chain of P (Andrew 1979): its vertices are points of P, and a disc on the inner side of every
    one of its edges lies in its kernel, hence in the hull, even if rounding made a chain vertex
    not extreme."""
    P = np.asarray(P, float).reshape(-1, 2)
    if len(P) < 3:
        return False
    chain = _monotone_chain(np.ascontiguousarray(P).tobytes())
    if chain is None:
        return False
    H, E, L, Hmax = chain
    c = np.asarray(c, float)
    dist = (E[:, 0] * (c[1] - H[:, 1]) - E[:, 1] * (c[0] - H[:, 0])) / L     # > 0: inner side
    scale = float(Hmax + np.abs(c).max() + r + 1.0)
    return bool((dist > r + 1e-9 * scale).all())


@lru_cache(maxsize=8)
def _monotone_chain(key: bytes):
    """(H, E, L, max |H|): the counter-clockwise monotone chain (Andrew 1979) of the points whose
    float64 (x, y) pairs are the bytes ``key``, its edge vectors and lengths; None when it has
    fewer than 3 vertices or an edge of length 0 (no disc is shown inside then).  Memoised: the
    insertions into one diagram test against the same hull sites until an update reaches the hull."""
    pts = sorted(set(map(tuple, np.frombuffer(key, float).reshape(-1, 2).tolist())))
    if len(pts) < 3:
        return None

    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    lower, upper = [], []
    for p in pts:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    for p in reversed(pts):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    H = np.array(lower[:-1] + upper[:-1])             # counter-clockwise
    if len(H) < 3:
        return None
    E = np.roll(H, -1, axis=0) - H
    L = np.hypot(E[:, 0], E[:, 1])
    if not (L > 0).all():
        return None
    for a in (H, E, L):
        a.setflags(write=False)
    return H, E, L, float(np.abs(H).max())
