"""Exact edge proofs among point and circle sites (thesis §3.1): where floats cannot decide.

Points: the bisector of two points is a line (ρ = 0).

On the bisector of the points p_i, p_j, written q(t) = m + t·n with m = (p_i + p_j)/2 and
n = rot90(p_j − p_i), the power difference of a third point p_k,

    f_k(t) = |q(t) − p_k|² − |q(t) − p_i|² = |m − p_k|² − |m − p_i|² + 2t·n·(p_i − p_k),

is affine in t with rational coefficients, and d_k > d_i ⟺ f_k > 0.  So "p_k is farther than
p_i, p_j on the open edge t ∈ (t0, t1)" is decided exactly from the signs of f_k at the ends
(t0, t1 rational: a vertex of point sites is the circumcentre of three of them) and of the slope
at an infinite end.  This decides the cases the float bounds cannot: third points that tie at
infinity (collinear points: parallel bisectors, f_k constant along the edge), and third points
that touch an end vertex.

Circle sites (:func:`circle_edge_clear`): the same question on a hyperbola branch is decided by the
exact zeros of d_k − d_i on it (the vertices of the triple i, j, k in a quadratic tower) and their
order along the branch, compared with ball arithmetic at increasing precision.  This proves the
edges, 10⁻¹⁵ long, of nearly co-circular floats.

Public API: :func:`point_edge_clear`, :func:`circle_edge_clear`, :func:`branch_order`,
:func:`circumcentre`, :func:`triple_others`, :func:`exact_third_site_clear`,
:func:`tower_points_apart`, :func:`zero_on_arc`, :func:`search_with_exact_fallback`.
"""
from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

from .problems import fault
from .arc_search import prove_arcs
from .edges import prove_tail
from .exact_vertices import exact_tower_vertex

__all__ = ["point_edge_clear", "points_edge_clear", "far_point_edges", "all_points", "point_ends", "circle_edge_clear", "branch_order", "circumcentre", "triple_others",
           "exact_third_site_clear", "tower_points_apart", "zero_on_arc", "search_with_exact_fallback", "SHALLOW"]

#: halvings of the first float search over all edges; a site still undecided goes to the exact
#: route (circles, points), and only then to the full-depth search (runtime.voronoi.verify.edges)
SHALLOW = 24


def _xy(g):
    return Fraction(int(g.exact.cx.p), int(g.exact.cx.q)), Fraction(int(g.exact.cy.p), int(g.exact.cy.q))


def circumcentre(geoms, sites):
    """The exact centre of the circle through the point sites ``sites[:3]`` (None if collinear)."""
    (ax, ay), (bx, by), (cx, cy) = (_xy(geoms[s]) for s in sites[:3])
    d = 2 * (ax * (by - cy) + bx * (cy - ay) + cx * (ay - by))
    if d == 0:
        return None
    a2, b2, c2 = ax * ax + ay * ay, bx * bx + by * by, cx * cx + cy * cy
    return ((a2 * (by - cy) + b2 * (cy - ay) + c2 * (ay - by)) / d,
            (a2 * (cx - bx) + b2 * (ax - cx) + c2 * (bx - ax)) / d)


def point_edge_clear(geoms, i, j, k, end0, end1) -> bool:
    """Is point site k strictly farther than the point sites i, j on the whole open edge?

    ``end0``, ``end1``: the edge's ends, each a tuple of the end vertex's sites or
    ``("inf", s)``: infinity in the direction s·rot90(p_j − p_i), s = ±1.  All sites must be
    points.  Exact (rational arithmetic)."""
    (ix, iy), (jx, jy), (kx, ky) = _xy(geoms[i]), _xy(geoms[j]), _xy(geoms[k])
    mx, my = (ix + jx) / 2, (iy + jy) / 2
    nx, ny = -(jy - iy), jx - ix
    alpha = (mx - kx) ** 2 + (my - ky) ** 2 - (mx - ix) ** 2 - (my - iy) ** 2
    beta = 2 * (nx * (ix - kx) + ny * (iy - ky))
    n2 = nx * nx + ny * ny
    ts = []
    for end in (end0, end1):
        if end[0] == "inf":
            ts.append(("inf", end[1]))
            continue
        c = circumcentre(geoms, end)
        if c is None:
            return False
        ts.append(("t", ((c[0] - mx) * nx + (c[1] - my) * ny) / n2))
    for kind, val in ts:
        if kind == "inf":
            # f_k → sign(beta)·val·∞ (or alpha when beta = 0)
            if beta * val < 0 or (beta == 0 and alpha <= 0):
                return False
        elif alpha + beta * val < 0:
            return False
    # both ends ≥ 0; f_k affine: positive on the open interval unless identically zero
    return not (beta == 0 and alpha == 0)


def points_edge_clear(geoms, i, j, end0, end1) -> bool:
    """Is every other site strictly farther than the point sites i, j on the whole open edge, all
    sites being points?  :func:`point_edge_clear` for every k at once, filtered: at a finite end
    c (a circumcentre) f_k(c) = |c − p_k|² − |c − p_i|² = 2c·(p_i − p_k) + |p_k|² − |p_i|², at an
    infinite end the slope β_k = 2·rot90(p_j − p_i)·(p_i − p_k) times σ, both in floats with a
    bound on their rounding error (64ε of the terms' magnitudes, and the rounding of c and of the
    coordinates carried through the gradient, with a factor 7 to spare); a site the bound does
    not decide goes to the exact test.  Used where a far edge (the vertex of nearly collinear
    points, 10¹⁶ out) leaves every site undecided by the distance searches."""
    n = len(geoms)
    P = np.array([[float(g.exact.cx), float(g.exact.cy)] for g in geoms])
    pi, pj = P[i], P[j]
    norm = np.hypot(P[:, 0], P[:, 1])
    dik = np.hypot(*(pi - P).T)
    sure = np.ones(n, bool)
    for end in (end0, end1):
        if end[0] == "inf":
            s = float(end[1])
            nv = np.array([-(pj[1] - pi[1]), pj[0] - pi[0]])
            beta = 2 * ((pi - P) @ nv)
            dij = float(np.hypot(*nv))
            err = 1e-13 * (dij * dik + (norm[i] + norm[j] + norm) * (dij + dik))
            sure &= beta * s > err
            continue
        c = circumcentre(geoms, end)
        if c is None:
            return False
        cf = np.array([float(c[0]), float(c[1])])
        cn = float(np.hypot(*cf))
        val = 2 * ((pi - P) @ cf) + norm ** 2 - norm[i] ** 2
        err = 1e-13 * (cn * dik + norm ** 2 + norm[i] ** 2 + cn * (norm + norm[i]))
        sure &= val > err
    sure[[i, j]] = True
    return all(point_edge_clear(geoms, i, j, int(k), end0, end1) for k in np.nonzero(~sure)[0].tolist())


def _vertex_param(w, i_xy, j_xy, prec):
    """Ball enclosure of (q − m)·rot90(c_j − c_i) at the tower vertex w (CircleVertex)."""
    from flint import arb, ctx, fmpq

    def ball(f):
        return arb(fmpq(f.numerator, f.denominator))

    s = w.sol
    T = s.tower
    with ctx.workprec(prec):
        D = T.to_arb(s.D, prec)
        x = T.to_arb(s.X, prec) / D
        y = T.to_arb(s.Y, prec) / D
        (ix, iy), (jx, jy) = i_xy, j_xy
        mx, my = ball((ix + jx) / 2), ball((iy + jy) / 2)
        return (x - mx) * ball(-(jy - iy)) + (y - my) * ball(jx - ix)


def branch_order(ws, i_xy, j_xy):
    """The signs of the pairwise differences of the branch parameters of the tower vertices ``ws``
    on the hyperbola bisector of circles i, j: the parameter y = (q − m)·rot90(c_j − c_i) is
    strictly monotone along the branch (q(u) = m + a·cosh u·e_x + b·sinh u·e_y, thesis §3.1), so
    it orders points of the branch.  Returns the list of parameter balls, refined until every pair
    is separated or 4096 bits (then None: two of them may coincide)."""
    prec = 128
    while prec <= 4096:
        ps = [_vertex_param(w, i_xy, j_xy, prec) for w in ws]
        if all(not (ps[a] - ps[b]).contains(0) for a in range(len(ps)) for b in range(a + 1, len(ps))):
            return ps
        prec *= 4
    return None


def _end_slope(geoms, i, j, k, v, into: int):
    """The sign (+1, −1, or 0: undecided at 4096 bits) of the derivative of d_k − d_i along the
    bisector of the circle/point sites i, j (exterior pair) at its tower vertex v, in the
    direction of the branch parameter s = (q − m)·rot90(c_j − c_i) times ``into``.

    At v (outside the three sites: its empty circle has positive radius) ∇d_s = u_s =
    (v − c_s)/|v − c_s|; the bisector |q − c_i| − |q − c_j| = ρ_i − ρ_j has the tangent
    t = rot90(u_i − u_j), which points the way s grows: with a = v − c_i, b = v − c_j,
    t·rot90(c_j − c_i) = (u_i − u_j)·(a − b) = (|a| + |b|)(1 − cos∠(a, b)) ≥ 0, zero only when
    t = 0 (then the slope is 0: undecided).  The derivative is (u_k − u_i)·t."""
    from flint import arb, ctx, fmpq

    def ball(f):
        return arb(fmpq(f.numerator, f.denominator))

    T, sol = v.sol.tower, v.sol
    (ix, iy), (jx, jy), (kx, ky) = _xy(geoms[i]), _xy(geoms[j]), _xy(geoms[k])
    prec = 128
    while prec <= 4096:
        with ctx.workprec(prec):
            D = T.to_arb(sol.D, prec)
            x, y = T.to_arb(sol.X, prec) / D, T.to_arb(sol.Y, prec) / D

            def unit(cx, cy):
                dx, dy = x - ball(cx), y - ball(cy)
                r = (dx * dx + dy * dy).sqrt()
                return dx / r, dy / r

            (uix, uiy), (ujx, ujy), (ukx, uky) = unit(ix, iy), unit(jx, jy), unit(kx, ky)
            tx, ty = -(uiy - ujy), uix - ujx
            slope = ((ukx - uix) * tx + (uky - uiy) * ty) * into
            if slope > 0:
                return 1
            if slope < 0:
                return -1
        prec *= 4
    return 0


def circle_edge_clear(geoms, i, j, k, u, w) -> bool:
    """Is circle/point site k strictly farther than the circle/point sites i, j (exterior pair, a
    hyperbola branch) on the open edge between the proved vertices u and w, decided exactly?

    ``u``, ``w``: (sites, tower vertex) of the end vertices, or ("inf", σ) for an end at infinity
    where the branch parameter goes to σ·∞ (at least one end must be a vertex).  On the branch d_k − d_i vanishes
    exactly at the Voronoi vertices of (i, j, k) (at most two, listed exactly by thesis §3.1.3); if
    none lies strictly between u and w (compared by :func:`branch_order`), d_k − d_i has one sign
    on the open edge: positive if k is strictly farther at an end (an end vertex whose sites do
    not include k, proved empty); when k is a site of every finite end (d_k = d_i there), the
    sign of its derivative into the edge at an end (:func:`_end_slope`, ball arithmetic), where
    nonzero, is the sign on the edge."""
    from ...predicates.circles import voronoi_vertices_circles
    from ...result import LocatorError

    fin = [t for t in (u, w) if t[0] != "inf"]
    if not fin:
        return False
    try:
        tv = voronoi_vertices_circles(geoms[i].exact, geoms[j].exact, geoms[k].exact)
    except LocatorError:
        return False
    i_xy, j_xy = _xy(geoms[i]), _xy(geoms[j])
    if len(fin) == 1:
        # one end at infinity in the direction σ of the branch parameter: z cuts the edge when
        # it lies beyond the vertex end on that side
        (sites, vu), sigma = fin[0], (u if u[0] == "inf" else w)[1]
        for z in tv.vertices:
            ps = branch_order([vu, z], i_xy, j_xy)
            if ps is None:
                if k not in sites:
                    return False
                continue          # z is the vertex end itself (k touches it)
            if (ps[1] > ps[0]) if sigma > 0 else (ps[1] < ps[0]):
                return False
        return k not in sites or _end_slope(geoms, i, j, k, vu, 1 if sigma > 0 else -1) > 0
    ends = [u[1], w[1]]
    for z in tv.vertices:
        ps = branch_order(ends + [z], i_xy, j_xy)
        if ps is None:
            # z may coincide with an end: it is that end exactly when k is one of its sites
            ps2 = branch_order(ends, i_xy, j_xy)
            if ps2 is None:
                return False
            at_end = False
            for (sites, vw), pw in zip((u, w), ps2):
                if k in sites:
                    pz = _vertex_param(z, i_xy, j_xy, 4096)
                    if (pz - pw).contains(0):
                        at_end = True
            if not at_end:
                return False
            continue
        pu, pw, pz = ps
        lo, hi = (pu, pw) if pu < pw else (pw, pu)
        if lo < pz and pz < hi:
            return False          # site k cuts the edge at z
    if any(k not in sites for sites, _ in (u, w)):
        return True
    ps = branch_order(ends, i_xy, j_xy)
    return ps is not None and _end_slope(geoms, i, j, k, u[1], 1 if ps[1] > ps[0] else -1) > 0


def triple_others(w, i, j, k):
    """The Voronoi vertices of the circle/point triple (i, j, k) other than the degree-k vertex w
    (whose exact vertex is ``w.exact``), exactly (thesis §3.1.3); None when the triple's vertices
    cannot be told apart from w."""
    from ...predicates.circles import voronoi_vertices_circles
    from ...result import LocatorError

    geoms = w.geoms
    if all(geoms[s].kind == "point" for s in (i, j, k)):
        # three points of the proved vertex's circle: their only equidistant point is its centre
        return []
    try:
        tv = voronoi_vertices_circles(geoms[i].exact, geoms[j].exact, geoms[k].exact)
    except LocatorError:
        return None
    out = []
    found = 0
    for z in tv.vertices:
        if math.hypot(z.x - w.x, z.y - w.y) <= 4 * (w.tol + w.h):
            found += 1
        else:
            out.append((z.x, z.y))
    return out if found == 1 else None


def exact_third_site_clear(geoms, vinfo, e, pair, tails, det) -> bool:
    """Is the site a failed search left undecided (a point or circle) strictly farther than the
    edge's two sites on the whole open edge, decided exactly (:func:`point_edge_clear`, :func:`circle_edge_clear`)?"""
    if det is None or det[0] is None or det[2] != "undecided":
        return False
    k = int(det[0])
    if any(geoms[s].kind not in ("point", "circle") for s in (*pair, k)):
        return False
    if any(geoms[s].kind != "point" for s in (*pair, k)):
        # circles: exact zeros on a hyperbola branch between two exact end vertices
        ends = []
        tail_sigmas = [sg for _, sg in tails]
        for vid in e.ends:
            if vid is None:
                if len(tail_sigmas) != 1:
                    return False
                ends.append(("inf", tail_sigmas[0]))
                continue
            ex = exact_tower_vertex(vinfo[vid], geoms)
            if ex is None:
                return False
            ends.append((tuple(vinfo[vid].sites), ex[1]))
        return circle_edge_clear(geoms, pair[0], pair[1], k, ends[0], ends[1])
    ends = point_ends(geoms, vinfo, e, tails)
    return ends is not None and point_edge_clear(geoms, pair[0], pair[1], k, ends[0], ends[1])


def all_points(geoms) -> bool:
    """Are all sites points?"""
    return all(g.kind == "point" for g in geoms)


def point_ends(geoms, vinfo, e, tails):
    """The edge's ends for :func:`point_edge_clear` (vertex sites or ("inf", σ)), or None when an
    end vertex has a site that is not a point or a tail is missing."""
    ends = []
    sigmas = [sg for _, sg in tails]
    for vid in e.ends:
        if vid is None:
            if not sigmas:
                return None
            ends.append(("inf", sigmas.pop(0)))
        elif any(geoms[s].kind != "point" for s in vinfo[vid].sites):
            return None
        else:
            ends.append(tuple(vinfo[vid].sites))
    return ends


def far_point_edges(geoms, vinfo, scale, jobs) -> set:
    """Indices of the edge jobs (pos, edge, name, pair, bisector, (lo, hi, exempt, tails, …)) of a
    diagram of points whose edge has an end vertex more than 10³ scene sizes out (the circle of
    nearly collinear points) and which :func:`points_edge_clear` proves exactly: every other point
    farther on the whole edge, tails included.  The disc searches would meet every site there."""
    if not jobs or not all_points(geoms):
        return set()
    out = set()
    for t, (_, e, _, pair, _, job) in enumerate(jobs):
        if not any(v is not None and max(abs(vinfo[v].x), abs(vinfo[v].y)) > 1e3 * scale for v in e.ends):
            continue
        ends = point_ends(geoms, vinfo, e, job[3])
        if ends is not None and points_edge_clear(geoms, pair[0], pair[1], *ends):
            out.add(t)
    return out


def tower_points_apart(a, b) -> bool:
    """Distinct points: some coordinate's ball enclosures are disjoint (thesis §3.1.3 towers)."""
    from flint import ctx

    prec = 128
    while prec <= 4096:
        with ctx.workprec(prec):
            da = [a.sol.tower.to_arb(v, prec) / a.sol.tower.to_arb(a.sol.D, prec) for v in (a.sol.X, a.sol.Y)]
            db = [b.sol.tower.to_arb(v, prec) / b.sol.tower.to_arb(b.sol.D, prec) for v in (b.sol.X, b.sol.Y)]
        if any(not (p - q).contains(0) for p, q in zip(da, db)):
            return True
        prec *= 4
    return False


def zero_on_arc(name, bis, others, uo, w2, lo, hi, full_lo, full_hi, triple, problems, edge=None) -> bool:
    """Does a zero of d_k − d_i on the bisector (another vertex of the triple) lie on the edge's
    arc?  Zeros at the other end vertex ``w2`` (which holds k too) do not count."""
    two_pi = 2 * math.pi
    for z, uz in zip(others, uo):
        if w2 is not None and math.hypot(z[0] - w2.x, z[1] - w2.y) <= w2.tol + 4 * w2.h:
            continue      # the other solution of the triple is the edge's other end
        uz = float(uz)
        if bis.kind == "ellipse":
            inside = ((uz - lo) % two_pi) < (hi - lo) + 1e-9
        else:
            inside = full_lo - 1e-9 * (1 + abs(uz)) <= uz <= full_hi + 1e-9 * (1 + abs(uz))
        if inside:
            problems.append(fault(f"{name}: the vertex ({z[0]:.9g}, {z[1]:.9g}) of sites "
                                  f"{', '.join(map(str, sorted(triple)))} lies on the edge's arc: "
                                  f"site {triple[2]} cuts the edge", kind="edge", edge=edge, sites=triple))
            return True
    return False


def search_with_exact_fallback(table, geoms, vinfo, e, pair, bis, lo, hi, exempt, tails, ok, det):
    """Finish the third-site search of one circle/point edge after the shallow batch search
    (result ``ok, det``): the tails, then, while a site stays undecided, the exact route
    (:func:`exact_third_site_clear`: the site is proved farther and the search repeated without
    it), else one full-depth float search.  Returns (ok, detail) as
    :func:`runtime.voronoi.verify.arc_search.prove_arcs`."""
    deep = False
    while True:
        if ok:
            for U, sigma in tails:
                ok, det = prove_tail(table, bis, U, sigma, exempt)
                if not ok:
                    break
        if ok:
            return ok, det
        if all_points(geoms) and det is not None and det[2] == "undecided":
            ends = point_ends(geoms, vinfo, e, tails)
            if ends is not None and points_edge_clear(geoms, pair[0], pair[1], *ends):
                return True, None        # every other point farther on the whole edge, tails included
        if exact_third_site_clear(geoms, vinfo, e, pair, tails, det):
            # every site tied with it at infinity (listed by prove_tail) that is also proved farther
            extra = [k for k in (det[3] if len(det) > 3 else ())
                     if k != det[0] and exact_third_site_clear(geoms, vinfo, e, pair, tails, (k,) + tuple(det[1:3]))]
            exempt = set(exempt) | {det[0]} | set(extra)
            ok, det = prove_arcs(table, [(bis, lo, hi, exempt)], max_depth=SHALLOW, max_pieces=256)[0]
            continue
        if deep or det is None or det[2] != "undecided":
            return ok, det
        deep = True
        ok, det = prove_arcs(table, [(bis, lo, hi, exempt)])[0]
