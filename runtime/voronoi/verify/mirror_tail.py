"""Unbounded edges between mirror-image sites, to infinity (thesis §1.2; grids of identical shapes).

When identical shapes sit in a row, several of them tie for the largest support value h_k(θ*)
in the direction θ* of the row's normal: their unbounded edges are parallel, and the sector
argument of :mod:`runtime.voronoi.verify.tail` (a cone of directions where only the edge's two
sites lead) cannot exist.  Such rows are mirror-symmetric, and mirrors give exact facts
(:mod:`runtime.predicates.symmetry`): if the reflection in a rational line ℓ maps site i onto
site j, with i and j strictly on opposite sides, the bisector of i and j is exactly ℓ.

:func:`prove_mirror_tail` proves the edge (i, j) beyond the chain of strips
(:mod:`runtime.voronoi.verify.curved`) when i and j are mirror images: the chain's last rectangle
proved that the bisector ℓ crosses it in one arc, all closer to i, j than to the other sites; let
P be the exact point of ℓ on the rectangle's link position and R = {P + t·u : t ≥ 0} the ray of ℓ
going out.  Every other site k is proved strictly farther than i (= j) on R by one of

(A) **support**: with F a point of site i (its foot from P, a float within rounding of the curve),
    a = (P − F)·u > 0 and b = (P − F)·u⊥: for q = P + t·u, d_i(q) ≤ |q − F| ≤ a + t + b²/(2a)
    and d_k(q) ≥ (q − m)·u − h_k(u) (the supporting line of k), so
    d_k − d_i ≥ (F − m)·u − h_k(u) − b²/(2a) > 0 suffices (all widened by rounding bounds);
(B) **mirror**: a reflection maps i (or j) exactly onto k, with i (or j) and the whole ray strictly
    on one side of its line (exact rational signs for the ray, float margins for the site's box):
    then d_i < d_k on that open half-plane.

Then R is part of the edge, to infinity, and the edge is the chain's arc followed by R.  For the
accounting of the ends at infinity (:func:`runtime.voronoi.verify.closure.verify_accounting_conics`)
the end is recorded with its exact direction u (a rational vector) and the pair: ends in one
direction are checked there against the sites tied in that direction.

Public API: :func:`prove_mirror_tail`.
"""
from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

from ...predicates.symmetry import mirror_line

__all__ = ["prove_mirror_tail"]


def _side_box(box, n, k):
    """The strict side (+1, −1) of the line n·q = k on which the float box lies, with a margin
    (0: not decided)."""
    x0, y0, x1, y1 = box
    if not all(math.isfinite(v) for v in box):
        return 0
    nx, ny, kf = float(n[0]), float(n[1]), float(k)
    vals = [nx * x + ny * y - kf for x in (x0, x1) for y in (y0, y1)]
    marg = 1e-9 * (abs(nx) + abs(ny)) * (abs(x0) + abs(x1) + abs(y0) + abs(y1) + 1.0) + 1e-9 * abs(kf)
    if min(vals) > marg:
        return 1
    if max(vals) < -marg:
        return -1
    return 0


def prove_mirror_tail(sites, geoms, sup, pair, link):
    """Prove the end of edge (i, j) beyond the chain's last rectangle ``link`` (as in
    :func:`runtime.voronoi.verify.tail.prove_tail`) when i and j are mirror images (module
    docstring).  Returns (ok, message, end) with end = (exact direction (ux, uy), lateral
    coordinate of the ray's line) for the accounting, or None."""
    line, why = _opposite_mirror(sites, geoms, pair)
    if why == "none":
        return False, "no mirror maps its two sites onto each other", None
    if why == "sides":
        return False, "its sites are not strictly on opposite sides of their mirror", None
    n, k = line
    P0, tv, nv, L, w, sx = link
    X = np.asarray(P0, float) + sx * np.asarray(tv, float)
    Xq = (Fraction(float(X[0])), Fraction(float(X[1])))
    nn = n[0] * n[0] + n[1] * n[1]
    lam = (n[0] * Xq[0] + n[1] * Xq[1] - k) / nn
    P = (Xq[0] - lam * n[0], Xq[1] - lam * n[1])          # exact point of ℓ near X
    Pf = np.array([float(P[0]), float(P[1])])
    if abs(float((Pf - X) @ np.asarray(nv, float))) > 0.5 * w:
        return False, "the mirror line leaves the chain's last rectangle", None
    d = (-n[1], n[0])                                      # direction of ℓ, exact
    if (float(d[0]) * (X[0] - sup.m[0]) + float(d[1]) * (X[1] - sup.m[1])) < 0:
        d = (n[1], -n[0])                                  # the outward one
    return ray_clear(sites, geoms, sup, pair, P, d)


def ray_clear(sites, geoms, sup, pair, P, d):
    """Is every site other than the pair strictly farther than i (= j) on the ray {P + t·d : t ≥ 0}
    of their mirror line (P, d exact rationals)?  Conditions (A) and (B) of the module docstring.
    Returns (ok, message, end) as :func:`prove_mirror_tail`."""
    i, j = pair
    Pf = np.array([float(P[0]), float(P[1])])
    dn = math.hypot(float(d[0]), float(d[1]))
    u = np.array([float(d[0]), float(d[1])]) / dn
    uperp = np.array([-u[1], u[0]])
    th = math.atan2(u[1], u[0])
    scale = float(np.abs(Pf).sum() + sup.W + np.abs(sup.m).sum() + 1.0)
    eps = 1e-12 * scale + 8 * sup.mu
    # (A) support bound, with F the foot of i (and of j) from P
    feet = []
    for s in (i, j):
        F, _ = geoms[s].foot_points(Pf[None, :])
        a = float((Pf - F[0]) @ u)
        b = float((Pf - F[0]) @ uperp)
        if a > 0:
            feet.append((float((F[0] - sup.m) @ u) - b * b / (2 * a) * (1 + 1e-9) - eps))
    base = max(feet) if feet else -math.inf
    others = np.array([t for t in range(len(geoms)) if t not in pair], int)
    end = ((d[0], d[1]), float(Pf @ uperp))
    if not len(others):
        return True, None, end
    hk = sup.h(others, np.full(len(others), th))
    todo = others[~(base - hk - sup.mu > 0)]
    # (B) mirrors onto the remaining sites
    for t in todo.tolist():
        if dominated_on(sites, geoms, pair, t, P, d, ray=True) is None:
            return False, f"site {t} is not proved farther on the mirror line to infinity", None
    return True, None, end


def dominated_on(sites, geoms, pair, t, P, d, ray=False, Q=None):
    """A site of the pair whose mirror image is site t, with the segment [P, Q] (open at the ends
    where it meets the mirror) or the ray from P along d inside the open half-plane of that site:
    then d_i < d_t there (module docstring, (B)).  P, Q, d exact; returns the site or None."""
    for s in pair:
        ml = mirror_line(sites[s], sites[t])
        if ml is None:
            continue
        m2, k2 = ml
        side = _side_box(geoms[s].bounding_box(), m2, k2)
        if side == 0:
            continue
        val = (m2[0] * P[0] + m2[1] * P[1] - k2) * side
        if ray:
            slope = (m2[0] * d[0] + m2[1] * d[1]) * side
            if val > 0 and slope >= 0:
                return s
        else:
            val2 = (m2[0] * Q[0] + m2[1] * Q[1] - k2) * side
            if val >= 0 and val2 >= 0 and (val > 0 or val2 > 0):
                return s
    return None


def _exact_on_line(w, n, k):
    """The exact point of a proved vertex (a symmetric vertex's rational point) if it lies on the
    line n·q = k, else None."""
    p = getattr(w, "exact_point", None)
    if p is None:
        return None
    return p if n[0] * p[0] + n[1] * p[1] == k else None


def _opposite_mirror(sites, geoms, pair):
    """(line, reason): the mirror line n·q = k mapping site i onto site j, with i and j strictly on
    opposite sides of it (their float boxes, :func:`_side_box`), or (None, "none") when no mirror
    maps them onto each other, (None, "sides") when they are not strictly on opposite sides."""
    line = mirror_line(sites[pair[0]], sites[pair[1]])
    if line is None:
        return None, "none"
    n, k = line
    si, sj = _side_box(geoms[pair[0]].bounding_box(), n, k), _side_box(geoms[pair[1]].bounding_box(), n, k)
    if si == 0 or sj == 0 or si == sj:
        return None, "sides"
    return line, None


class _Line:
    """The exact parametrisation s ↦ base + s·d of the line n·q = k (d = (−n_y, n_x), base its
    point nearest the origin), all in rationals."""

    def __init__(self, n, k):
        self.n, self.k = n, k
        self.d = (-n[1], n[0])
        self.dd = self.d[0] * self.d[0] + self.d[1] * self.d[1]

    def param(self, q):
        """The parameter of the projection of q onto the line (exact)."""
        return (q[0] * self.d[0] + q[1] * self.d[1]) / self.dd

    def point(self, s):
        """The point of parameter s (exact)."""
        n, k, d = self.n, self.k, self.d
        base = (k * n[0] / (n[0] * n[0] + n[1] * n[1]), k * n[1] / (n[0] * n[0] + n[1] * n[1]))
        return (base[0] + s * d[0], base[1] + s * d[1])


def prove_mirror_edge(sites, geoms, table, sup, pair, v0, v1, P, closed, max_pieces=20000):
    """Prove a whole edge (i, j) of mirror-image sites: it is the part of their mirror line ℓ
    between its end vertices (exact rational points of ℓ) or from a vertex to infinity, or the
    whole line.  Third sites are proved farther on the finite part by distance bounds on discs
    covering pieces of it (d is 1-Lipschitz: lo_k(C) − R > hi_i(C) + R on a piece of half-length
    R about C), or by a mirror (:func:`dominated_on`; the sites tied at an end vertex), and on the
    rays by :func:`ray_clear`.  Returns (ok, message, ends at infinity as in
    :func:`prove_mirror_tail`)."""
    if closed:
        return False, "a closed edge", []
    line, why = _opposite_mirror(sites, geoms, pair)
    if why == "none":
        return False, "no mirror", []
    if why == "sides":
        return False, "its sites are not strictly on opposite sides of their mirror", []
    ln = _Line(*line)
    ends = []
    for w in (v0, v1):
        ends.append(None if w is None else _exact_on_line(w, ln.n, ln.k))
        if w is not None and ends[-1] is None:
            return False, "an end vertex is not an exact point of the mirror", []
    P = np.asarray(P, float).reshape(-1, 2)
    a, b, rays = _finite_part(ln, ends, P, sup)
    if not b > a:
        return False, "its end vertices coincide", []
    if not _polyline_follows(ln, P, a, b, rays):
        return False, "its polyline leaves the part of the mirror line between its ends", []
    if not _finite_part_clear(sites, geoms, table, pair, ln, a, b, max_pieces):
        return False, "third sites undecided on the mirror line (work limit)", []
    d = ln.d
    out = []
    for s0, sg in rays:
        ok, msg, end = ray_clear(sites, geoms, sup, pair, ln.point(s0), (sg * d[0], sg * d[1]))
        if not ok:
            return False, msg, []
        out.append(end)
    return True, None, out


def _finite_part(ln, ends, P, sup):
    """The finite part [a, b] of ℓ (parameters) and the rays (s0, ±1) beyond it: between two end
    vertices; around the scene (a reach of 4W beyond its centre's projection) for a whole line;
    from the one vertex towards the polyline's unbounded end otherwise."""
    param = ln.param
    sP = [param((Fraction(float(x)), Fraction(float(y)))) for x, y in (P[0], P[-1])]
    reach = Fraction(max(4 * sup.W + float(np.abs(sup.m).sum()), 1.0)) / Fraction(math.sqrt(float(ln.dd)))
    if ends[0] is not None and ends[1] is not None:
        a, b = sorted((param(ends[0]), param(ends[1])))
        rays = []
    elif ends[0] is None and ends[1] is None:
        c = param((Fraction(float(sup.m[0])), Fraction(float(sup.m[1]))))
        a, b = c - reach, c + reach
        rays = [(a, -1), (b, 1)]
    else:
        sv = param(ends[0] if ends[0] is not None else ends[1])
        far = sP[1] if ends[0] is not None else sP[0]       # the polyline's unbounded end
        sg = 1 if far > sv else -1
        a, b = (sv, sv + reach) if sg > 0 else (sv - reach, sv)
        rays = [(b, 1) if sg > 0 else (a, -1)]
    return a, b, rays


def _polyline_follows(ln, P, a, b, rays):
    """Does the polyline stay within the parameters [a, b] of ℓ (up to 1e-9 of its size) on the
    sides where no ray continues?  (Its distance to ℓ was checked against the tolerance.)"""
    sl = 1e-9 * (1.0 + float(np.abs(P).max())) / math.sqrt(float(ln.dd))
    sp = np.array([float(ln.param((Fraction(float(x)), Fraction(float(y))))) for x, y in P])
    lo_ok = any(sg < 0 for _, sg in rays) or (sp >= float(a) - sl).all()
    hi_ok = any(sg > 0 for _, sg in rays) or (sp <= float(b) + sl).all()
    return lo_ok and hi_ok


def _finite_part_clear(sites, geoms, table, pair, ln, a, b, max_pieces):
    """Is every third site farther than i on the part [a, b] of ℓ?  On pieces of half-length R
    about C: lo_k(C) − R > hi_i(C) + R (d is 1-Lipschitz), pieces halved where that fails, unless
    a mirror maps i or j onto k with the whole part on their side (:func:`dominated_on`)."""
    i = pair[0]
    d, point = ln.d, ln.point
    dn = math.sqrt(float(ln.dd))
    fa, fb = float(a), float(b)
    base = np.array([float(point(0)[0]), float(point(0)[1])])
    dv = np.array([float(d[0]), float(d[1])])
    A, B = np.linspace(fa, fb, 9)[:-1], np.linspace(fa, fb, 9)[1:]
    done_mirror: dict = {}
    work = 0
    while len(A):
        work += len(A)
        if work > max_pieces:
            return False
        mid = 0.5 * (A + B)
        C = base[None, :] + mid[:, None] * dv[None, :]
        R = 0.5 * (B - A) * dn * (1 + 1e-9) + 1e-12 * (np.abs(C).sum(1) + 1.0)
        Vi = table.evaluate(C, np.full(len(C), i))
        rows, ks = table.near_pairs(C, Vi.hi + 2 * R, pair)
        if not len(rows):
            break
        Vk = table.evaluate(C[rows], ks)
        ok = Vk.lo - R[rows] > Vi.hi[rows] + R[rows]
        bad = np.nonzero(~ok)[0]
        keep = np.zeros(len(A), bool)
        for t in bad.tolist():
            kk = int(ks[t])
            if kk not in done_mirror:
                done_mirror[kk] = dominated_on(sites, geoms, pair, kk, point(a), d, Q=point(b)) is not None
            if not done_mirror[kk]:
                keep[rows[t]] = True
        if not keep.any():
            break
        A, B, M = A[keep], B[keep], mid[keep]
        A, B = np.concatenate([A, M]), np.concatenate([M, B])
    return True
