"""The unbounded ends every diagram of the sites has (step 5 of :mod:`runtime.segments.certificate`).

Far away in a direction u the nearest sites are those with the largest support h(u) = max over
the site of u·p: the distance of R u + s u^⊥ from a site is R − h(u) + O(1/R).  A point's
support is u·p; a segment's is its ends'; an arc's is c·u + ρ when u lies in its closed angular
range and its ends' otherwise.  Where one site has the largest support, it alone owns the far
region; at a direction u where several sites tie, those sites touch the support line
{x : u·x = h(u)} — points, segments lying on it, arcs touching it at c + ρu (at an end e when u
is the radial direction of e; the arc then lies on the side it leaves e to) — and, sorted along
the line, cut the far region into slabs: each consecutive pair has exactly one edge going to
infinity in direction u, and there are no others (an unbounded edge's far points have both its
sites at the largest support of their direction).

**Keys.**  An end is named by its sorted site pair and a key: the exact direction (up to scale)
when it is rational — two points, an end and its curve (perpendicular or radial), the two curves
of a smooth joint (the normal line) — and ``("tangent", ±1)`` for the asymptote of a point and an
arc, or of two arcs (a common tangent of a circle with a point or another circle, irrational in
general): the sign of (z_j − z_i) × u for the sorted pair (i, j), z a point or an arc's centre;
likewise for an elliptic piece and a point or another curve (no end shared), z the point of the
piece's ellipse with outward normal u (its support point: the tangency point of the asymptote, so
for a point p on that tangent (z − p) × u = ±|z − p||u| ≠ 0).

**Without arcs** the directions are the outward normals of the exact rational convex hull of the
point sites (every site lies in it).  **With arcs** let Q be the point sites and smooth joints (all
curve ends) and H_Q its exact hull.  An arc pokes out of H_Q exactly when some side normal n of
H_Q lies in its open range with c·n + ρ|n| above the side (exact in squares); if none does, the
directions are again H_Q's side normals (an arc ending at a hull vertex with its radial inside the
vertex's normal cone would poke out).  Otherwise the support envelope is found in floats (a
hull of samples) as a cyclic sequence of atoms (points of Q and arcs), and *proved*: each
transition between consecutive atoms is the root of h_Y − h_X = K·u + C = 0 where the difference
increases (a side normal, an arc's radial at its end, or a tangent), the atoms' direction
intervals have lengths ≥ 0 summing to 2π (a ball strictly between 0 and 4π, each length in
[0, 2π)), each arc's interval lies in its closed range, and on each atom's interval every other
atom (hull vertices of Q, arcs that poke out; a circle's support bounds an arc's) has a support
≤ the atom's: a difference K·u + C ≥ 0 on an interval holds when it does at both ends and, if its
minimum direction −K lies inside, C ≥ |K|.  Ties at each transition direction are then found
exactly (rational directions: rationals and squares) or by balls with an exact test for points
on a tangent (irrational directions; an undecided one is a limit).

Public API: :func:`expected_infinite_ends`, :func:`envelope_ties`, :func:`infinite_key`, :func:`tangent_sign`,
:func:`convex_hull`.
"""
from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
from flint import arb

from ..certify.foot import to_arb
from ..predicates.orientation import orient2d
from .certificate_envelope import Undecided, envelope_directions, tangent_ties
from .certificate_sites import ARC, ELLIPSE, POINT, SEGMENT, SiteTable, direction_key

__all__ = ["expected_infinite_ends", "envelope_ties", "infinite_key", "tangent_sign", "convex_hull"]

TWO_PI = 2 * math.pi


def convex_hull(pts: list) -> list:
    """Strict convex hull (no collinear points), counter-clockwise, exact (Andrew's monotone chain;
    each turn by :func:`runtime.predicates.orientation.orient2d`, a float filter backed by exact
    integers)."""
    pts = sorted(set(pts))
    if len(pts) <= 2:
        return pts
    lower: list = []
    for p in pts:
        while len(lower) >= 2 and orient2d(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    upper: list = []
    for p in reversed(pts):
        while len(upper) >= 2 and orient2d(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    return lower[:-1] + upper[:-1]


def _ball(v) -> arb:
    return v if isinstance(v, arb) else to_arb(Fraction(v))


def _z(T: SiteTable, k: int, ux=None, uy=None):
    if T.kind[k] == ELLIPSE:
        # the point of the piece's ellipse where u is the outward normal: the support point
        # c + ((u·M) M + (u·N) N)/|(u·M, u·N)| (arb balls)
        s = T.sites[k]
        ux, uy = _ball(ux), _ball(uy)
        cx, cy, Mx, My, Nx, Ny = (to_arb(q) for q in (*s.c, *s.M, *s.N))
        um, un = ux * Mx + uy * My, ux * Nx + uy * Ny
        h = (um * um + un * un).sqrt()
        return cx + (um * Mx + un * Nx) / h, cy + (um * My + un * Ny) / h
    return T.cen[k] if T.kind[k] == ARC else T.a[k]


def tangent_sign(T: SiteTable, i: int, j: int, ux, uy) -> int | None:
    """The sign of (z_j − z_i) × u for the sorted pair (module docstring); None if undecided."""
    i, j = sorted((i, j))
    (xi, yi), (xj, yj) = _z(T, i, ux, uy), _z(T, j, ux, uy)
    if any(isinstance(q, arb) for q in (xi, yi, xj, yj)):
        (xi, yi), (xj, yj) = (_ball(xi), _ball(yi)), (_ball(xj), _ball(yj))
    dx, dy = xj - xi, yj - yi
    if isinstance(ux, arb) or isinstance(dx, arb):
        v = _ball(dx) * _ball(uy) - _ball(dy) * _ball(ux)
    else:
        v = dx * uy - dy * ux
    return 1 if v > 0 else (-1 if v < 0 else None)


def infinite_key(T: SiteTable, i: int, j: int, u, rational: bool):
    """The key of an unbounded end of the pair (i, j) in direction u (rationals when ``rational``,
    else arb balls) — module docstring; None when it is not decided or the pair has no such end."""
    ki, kj = T.kind[i], T.kind[j]
    tangent = ((ARC in (ki, kj) or ELLIPSE in (ki, kj)) and not (T.is_endpoint(i, j) or T.is_endpoint(j, i)) and
               not T.shared_joint(i, j) and SEGMENT not in (ki, kj))
    if tangent:
        sg = tangent_sign(T, i, j, u[0], u[1])
        return None if sg is None else ("tangent", sg)
    if not rational:
        return None
    return direction_key(u)


# ====================================================================== without arcs
def _points_only(T: SiteTable) -> list:
    pts = list(T.point_index)
    if len(pts) < 2:
        return []
    hull = convex_hull(pts)
    out = []
    for p, q, u in _sides(hull):
        out.extend(_side_pairs(T, u, p))
    return out


def _sides(hull):
    if len(hull) == 2:                       # all on one line: both sides
        p, q = hull
        d = (q[0] - p[0], q[1] - p[1])
        return [(p, q, (d[1], -d[0])), (q, p, (-d[1], d[0]))]
    out = []
    for m in range(len(hull)):
        p, q = hull[m], hull[(m + 1) % len(hull)]
        out.append((p, q, (q[1] - p[1], -(q[0] - p[0]))))
    return out


# ====================================================================== ties at a direction
def _support_floats(T: SiteTable, u):
    """Float support of every site in direction u (floats), with a rounding margin."""
    ux, uy = float(u[0]), float(u[1])
    h = np.maximum(T.A @ [ux, uy], T.B @ [ux, uy])
    for k in T.cen:
        cx, cy = T.C[k]
        inr = T.in_range(k, Fraction(u[0]) if not isinstance(u[0], arb) else u[0],
                         Fraction(u[1]) if not isinstance(u[1], arb) else u[1], closed=True)
        if inr is not False:
            h[k] = max(h[k], cx * ux + cy * uy + T.R[k] * math.hypot(ux, uy))
    mag = (T.scale + 1.0) * (abs(ux) + abs(uy) + 1.0)
    return h, 1e-9 * mag


def _on_support(T: SiteTable, u, q, r, pt) -> bool:
    """u·pt equals the support q + r|u| (q, r rationals, r ≥ 0), exactly."""
    d = u[0] * pt[0] + u[1] * pt[1] - q
    return d == 0 if r == 0 else (d > 0 and d * d == r * r * (u[0] * u[0] + u[1] * u[1]))


def _rational_ties(T: SiteTable, u, ref) -> list:
    """Sites whose support in the rational direction u equals the reference's: a rational point
    (support u·p) or ("arc", k) (support u·c_k + ρ_k|u|, an arc on a tangent of rational
    direction)."""
    if isinstance(ref[0], str):
        q, r = u[0] * T.cen[ref[1]][0] + u[1] * T.cen[ref[1]][1], T.rad[ref[1]]
    else:
        q, r = u[0] * ref[0] + u[1] * ref[1], Fraction(0)
    n2 = u[0] * u[0] + u[1] * u[1]
    hf, m = _support_floats(T, u)
    cand = np.nonzero(np.abs(hf - (float(q) + float(r) * math.sqrt(float(n2)))) <= m)[0].tolist()
    out = []
    for k in cand:
        if T.kind[k] == POINT:
            if _on_support(T, u, q, r, T.a[k]):
                out.append(k)
        elif T.kind[k] == SEGMENT:
            if all(_on_support(T, u, q, r, p) for p in (T.a[k], T.b[k])):
                out.append(k)
        elif T.kind[k] == ELLIPSE:
            _piece_off_support(T, k, u, q, r)
        else:
            c, rho = T.cen[k], T.rad[k]
            # u·c + ρ|u| = q + r|u|  ⟺  u·c − q = (r − ρ)|u|
            d, e = u[0] * c[0] + u[1] * c[1] - q, r - rho
            tie = d == 0 if e == 0 else (d * e > 0 and d * d == e * e * n2)
            if tie and T.in_range(k, u[0], u[1], closed=True):
                out.append(k)
    return out


def _piece_off_support(T: SiteTable, k: int, u, q, r) -> None:
    """An elliptic piece whose end is near the support line: it adds no tie.  The accounting runs
    only when every piece lies strictly inside the point sites' hull but at ends that are point
    sites (:func:`runtime.segments.certificate_ellipse_sites.pieces_inside_hull`), so the piece
    meets the support line at most at such an end e; there it must leave e strictly into the inner
    side (u·t < 0 for the exact direction t leaving e): then its support in direction u is
    attained at e alone, far away its nearest point in those directions is e (the tie is the point
    site's), and its normal line at e is not along u.  Else Undecided (a tangent there)."""
    if r != 0:
        raise Undecided(f"elliptic piece {k} next to an arc's tangent support line")
    for code in T.ends[k] or ():
        e = T.pt(code)
        if u[0] * e[0] + u[1] * e[1] == q:
            t = T.leaving(k, code)
            if not (code >= 0 and u[0] * t[0] + u[1] * t[1] < 0):
                raise Undecided(f"elliptic piece {k} touches a support line along its tangent")


def _items(T: SiteTable, ties, u, b, exact: bool):
    """(position, rank, site) along the support line (b: its direction), sorted; None if two
    items cannot be ordered.  ``exact``: u, b rationals; else arb balls."""
    items = []
    for k in ties:
        if T.kind[k] == POINT:
            items.append((_dot(b, T.a[k], exact), 0, k))
        elif T.kind[k] == SEGMENT:
            pa, pb = _dot(b, T.a[k], exact), _dot(b, T.b[k], exact)
            lo = pa if _lt(pa, pb) else pb
            items.append((lo, 1, k))
        else:
            e = None
            for code in T.ends[k]:
                w = tuple(v - c for v, c in zip(T.pt(code), T.cen[k]))
                if exact and w[0] * u[1] - w[1] * u[0] == 0 and w[0] * u[0] + w[1] * u[1] > 0:
                    e = code
            if e is None:
                items.append((_dot(b, T.cen[k], exact), 0, k))
            else:
                t = T.leaving(k, e)
                rank = 1 if (t[0] * b[0] + t[1] * b[1]) > 0 else -1
                items.append((_dot(b, T.pt(e), exact), rank, k))
    for x in range(len(items)):
        for y in range(x + 1, len(items)):
            if _cmp(items[x], items[y]) is None:
                return None
    import functools
    return sorted(items, key=functools.cmp_to_key(lambda p, q: _cmp(p, q)))


def _dot(b, p, exact):
    return b[0] * p[0] + b[1] * p[1] if exact else b[0] * to_arb(p[0]) + b[1] * to_arb(p[1])


def _lt(x, y):
    return bool(x < y)


def _cmp(p, q):
    if isinstance(p[0], arb) or isinstance(q[0], arb):
        if p[0] < q[0]:
            return -1
        if p[0] > q[0]:
            return 1
        return None
    if p[0] != q[0]:
        return -1 if p[0] < q[0] else 1
    if p[1] == q[1]:
        return None
    return -1 if p[1] < q[1] else 1


def _pairs(T: SiteTable, items, u, exact: bool):
    out = []
    for (_, _, k0), (_, _, k1) in zip(items, items[1:]):
        key = infinite_key(T, k0, k1, u, exact)
        if key is None or not _consecutive_ok(T, k0, k1):
            return None
        out.append((tuple(sorted((k0, k1))), key))
    return out


def _consecutive_ok(T, i, j) -> bool:
    """A pair that may share an unbounded edge: two points, an end and its curve, two curves of
    a joint, a point or an arc with an arc."""
    ki, kj = T.kind[i], T.kind[j]
    if ki == POINT and kj == POINT:
        return True
    if T.is_endpoint(i, j) or T.is_endpoint(j, i):
        return True
    if T.shared_joint(i, j):
        return True
    return SEGMENT not in (ki, kj)


def _side_pairs(T: SiteTable, u, p_ref):
    """The consecutive pairs of tie sites in the rational direction u (support of the reference:
    a point, or ("arc", k))."""
    ties = _rational_ties(T, u, p_ref)
    if not T.has_arcs:
        return _points_segments(T, ties, u, p_ref)
    b = (-u[1], u[0])
    items = _items(T, ties, u, b, True)
    if items is None:
        raise Undecided(f"sites {sorted(ties)} touch a support line at one point")
    out = _pairs(T, items, u, True)
    if out is None:
        raise Undecided(f"sites {sorted(ties)}: an unexpected pair on a support line")
    return out


def _points_segments(T, ties, u, p):
    d = (-u[1], u[0])
    on = sorted(((q[0] - p[0]) * d[0] + (q[1] - p[1]) * d[1], k) for k in ties if T.kind[k] == POINT
                for q in (T.a[k],))
    key = direction_key(u)
    out = []
    for (_, k0), (_, k1) in zip(on, on[1:]):
        seg = T.segment_of.get(frozenset((k0, k1)))
        if seg is None:
            out.append((tuple(sorted((k0, k1))), key))
        else:
            out.append((tuple(sorted((k0, seg))), key))
            out.append((tuple(sorted((seg, k1))), key))
    return out


# ====================================================================== with arcs
def expected_infinite_ends(T: SiteTable):
    """The (sorted site pair, key) of every unbounded end of the true diagram (module docstring),
    with multiplicity; a message (str) when it is not decided (a limit)."""
    try:
        return _points_only(T) if not T.has_arcs else _with_arcs(T)
    except Undecided as exc:
        return f"the unbounded ends are not decided: {exc}"


def _q_points(T: SiteTable) -> list:
    return sorted(set(T.point_index) | {p for p, _ in T.joints})


def _pokes(T: SiteTable, hull) -> list:
    if len(hull) < 3:
        return sorted(T.cen)
    out = []
    for k in sorted(T.cen):
        c, rho = T.cen[k], T.rad[k]
        for p, q, n in _sides(hull):
            if not T.in_range(k, n[0], n[1]):
                continue
            gap = n[0] * p[0] + n[1] * p[1] - (n[0] * c[0] + n[1] * c[1])
            if gap < 0 or gap * gap < rho * rho * (n[0] * n[0] + n[1] * n[1]):
                out.append(k)
                break
    return out


def _with_arcs(T: SiteTable) -> list:
    return [end for pairs, _, _ in envelope_ties(T) for end in pairs]


def envelope_ties(T: SiteTable):
    """For each tie direction u of the support envelope of points, segments and arcs (module
    docstring, "With arcs"): (the consecutive pairs with their keys, u, ``rational``) — u exact
    rationals when ``rational``, else arb balls; raises :class:`Undecided`."""
    Q = _q_points(T)
    hull = convex_hull(Q)
    poking = _pokes(T, hull)
    if not poking:
        for p, q, u in _sides(hull):
            yield _side_pairs(T, u, p), u, True
        return
    for d in envelope_directions(T, hull, poking):
        if d[0] == "rational":
            yield _side_pairs(T, d[1], d[2]), d[1], True
        else:
            ties, u = tangent_ties(T, d)
            b = (-u[1], u[0])
            items = _items(T, ties, u, b, False)
            pairs = None if items is None else _pairs(T, items, u, False)
            if pairs is None:
                raise Undecided(f"sites {sorted(ties)} on a common tangent are not ordered")
            yield pairs, u, False
