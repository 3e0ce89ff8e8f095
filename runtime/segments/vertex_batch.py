"""Voronoi vertices of points, segments and circular arcs proved many at once, in floats.

The contact system of a triple (:mod:`runtime.segments.vertices`: unknowns z = (x, y, r), one
equation of degree ≤ 2 per site — point, line, normal line, arc) is coded as in
:mod:`runtime.segments.newton`: a kind K per equation and four float parameters P, each the
correctly rounded value of an exact rational (a line's r-coefficient σ·√N within 2u of its value,
u = 2⁻⁵³).  At the Newton limit m, Krawczyk's theorem is decided for all rows together by the
kernel's float test (:func:`runtime.certify.interval_newton.float_krawczyk_test`; Krawczyk 1969,
Moore, Kearfott & Cloud §8.2, Neumaier 1990 §5.1) on boxes |z − m| ≤ ρ, with the enclosures it
needs bounded outward (γ_n = nu/(1 − nu), Higham, *Accuracy and Stability*, §3.1):

* F(m): each equation is a sum of at most four products of differences of correctly rounded
  data and coordinates, so its float value is within γ₁₆ of the sum of the absolute values of
  its terms; for a point or an arc, also within the rounding of the differences x − p (of the
  order u·|p|·|x − p|, small near the site: :func:`residual_bounds`) (point: (|x| + |p_x|)² + (|y| + |p_y|)² + r²; line: |a x| + |b y| + |c| + |σ√N r|;
  normal: |t_x|(|x| + |e_x|) + |t_y|(|y| + |e_y|); arc: (|x| + |c_x|)² + (|y| + |c_y|)² + (|ρ| + |r|)²);
* the Jacobian over the box: a line's and a normal's rows are constant (their float value within
  γ₈ of each entry); a point's row 2(x − p_x, y − p_y, −r) and an arc's 2(x − c_x, y − c_y,
  −σ(ρ + σr)) move by 2ρ_i over the box, plus γ₁₆ of their magnitudes.

A proved zero is a vertex of the triple when r > 0 and each contact lies where its equation says
(:func:`runtime.segments.vertices.prove_zero`'s checks): a segment's foot parameter in [0, 1], an
arc's radius ρ + σr > 0 and contact direction in the arc's range, a normal line at an arc's end on
the side away from its centre.  Each is decided here only when the float value clears its bound
over the whole box by a margin (the same rounding model); r ≤ 0, a contact outside a site and
every undecided case go back to the arb proof (:func:`runtime.segments.vertices.prove_zero`), so
this is a fast path that says "proved" or nothing.

The codes of the triples of point sites and segments (the bulk of a segment scene) are also
written on arrays (:func:`code_point_segment_rows`): the same equations as
:func:`runtime.segments.vertices.contact_equations` chooses and the same floats as
:func:`code_systems` writes, from a table of each segment's correctly rounded line, tangent and
√N computed once per set of sites.

Public API: :func:`prove_zeros_batch`, :func:`code_systems`, :func:`code_point_segment_rows`,
:func:`residual_bounds`, the equation codes :data:`POINT_EQ`, :data:`LINE_EQ`, :data:`NORMAL_EQ`,
:data:`ARC_EQ`.
"""
from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
from flint import arb

from ..certify.interval_newton import (UNIT_ROUNDOFF, float_contraction_bound, float_inverse, float_krawczyk_test,
                                       float_residual_bound, gamma, round_up)
from .elementary import ARC, POINT, SEGMENT, ElementarySites
from .vertices import VertexSolution, segment_floats

__all__ = ["prove_zeros_batch", "code_systems", "code_point_segment_rows", "residual_bounds", "POINT_EQ", "LINE_EQ",
           "NORMAL_EQ", "ARC_EQ"]

#: codes of the equation kinds (as :mod:`runtime.segments.newton` writes them)
POINT_EQ, LINE_EQ, NORMAL_EQ, ARC_EQ = 0, 1, 2, 3

#: the widest box accepted, relative to 1 + |x| + |y| + |r|
TIGHT = 2.0 ** -40

#: ε-inflation attempts (Rump 1983) of the float boxes before a row goes to the arb proof
ATTEMPTS = 4


_CODES = {"point": POINT_EQ, "line": LINE_EQ, "normal": NORMAL_EQ, "arc": ARC_EQ}


def code_systems(systems):
    """(K, P): the kind codes (m × 3) and float parameters (m × 3 × 4) of contact systems of
    :func:`runtime.segments.vertices.contact_equations` without elliptic pieces -- point (p_x,
    p_y), line (a, b, c, σ√N), normal (t_x, t_y, e_x, e_y), arc (c_x, c_y, ρ, σ) -- each the
    correctly rounded float of its exact value (σ√N within 2u)."""
    m = len(systems)
    K = np.zeros((m, 3), dtype=np.int64)
    P = np.zeros((m, 3, 4))
    for i, eqs in enumerate(systems):
        for j, (kind, d, _t) in enumerate(eqs):
            K[i, j] = _CODES[kind]
            if kind == "line":
                a, b, c, sgn, N = d
                P[i, j] = (float(a), float(b), float(c), sgn * math.sqrt(float(N)))
            else:
                vals = [float(v) for v in d]
                P[i, j, :len(vals)] = vals
    return K, P


def code_point_segment_rows(E: ElementarySites, triples, seeds):
    """The rows of ``triples`` (m × 3 site indices, with float ``seeds`` m × 2) made of point
    sites and segments whose two ends are point sites, coded on arrays: (rows, invalid, K, P,
    sides).  ``rows`` (bool, m): such a triple with no common point of the three closures (a
    corner is :func:`runtime.segments.vertices.prove_vertex`'s); ``invalid``: a row holding a
    segment and both its ends (no circle touches the three: ``contact_equations`` is None);
    ``K``, ``P``: the codes of :func:`code_systems` of the row's ``contact_equations`` -- a point
    p, the normal line (t_x, t_y, e_x, e_y) at the end e of a segment when e is a site of the row,
    else the segment's line (a, b, c, σ√N) with σ = ±1 the side of the seed by the same float
    expression; ``sides`` (m × 3): σ on a line's column, 0 elsewhere (the cache key's sides)."""
    T = np.asarray(triples, dtype=np.int64).reshape(-1, 3)
    S = np.asarray(seeds, dtype=float).reshape(-1, 2)
    m = len(T)
    kind = E.kind[T]
    ends = E.ends[T]                                              # m × 3 × 2
    seg = kind == SEGMENT
    pt = kind == POINT
    rows = (pt | seg).all(axis=1) & ~(seg[..., None] & (ends < 0)).any(axis=(1, 2))
    # closures: a point site {t}, a segment {its two ends}; a common point of all three closures
    clo = np.where(pt[..., None], T[..., None], ends)
    common = np.zeros(m, bool)
    for c in (clo[:, 0, 0], clo[:, 0, 1]):
        common |= (c != -1) & ((clo[:, 1] == c[:, None]).any(axis=1)) & ((clo[:, 2] == c[:, None]).any(axis=1))
    rows &= ~common
    K = np.zeros((m, 3), dtype=np.int64)
    P = np.zeros((m, 3, 4))
    sides = np.zeros((m, 3), dtype=np.int64)
    # which ends of each segment column are point sites of the row
    pts = np.where(pt, T, -2)                                    # −2: no point site in that column
    end_in = (ends[..., None] == pts[:, None, None, :]).any(axis=3) & seg[..., None] & rows[:, None, None]
    n_in = end_in.sum(axis=2)
    invalid = rows & (n_in == 2).any(axis=1)
    live = rows & ~invalid
    if seg[live].any():
        L, Tg = segment_floats(E, T[live][seg[live]])
    for j in range(3):
        t = T[:, j]
        p_j = live & pt[:, j]
        K[p_j, j] = POINT_EQ
        P[p_j, j, :2] = E.A[t[p_j]]
        nrm = live & seg[:, j] & (n_in[:, j] == 1)
        if nrm.any():
            e = np.where(end_in[:, j, 0], ends[:, j, 0], ends[:, j, 1])[nrm]
            K[nrm, j] = NORMAL_EQ
            P[nrm, j, :2] = Tg[t[nrm]]
            P[nrm, j, 2:] = E.A[e]
        ln = live & seg[:, j] & (n_in[:, j] == 0)
        if ln.any():
            fa, fb, fc, rootN = L[t[ln]].T
            side = fa * S[ln, 0] + fb * S[ln, 1] + fc
            sgn = np.where(side >= 0, 1, -1)
            K[ln, j] = LINE_EQ
            P[ln, j] = np.stack([fa, fb, fc, sgn * rootN], axis=1)
            sides[ln, j] = sgn
    return rows, invalid, K, P, sides


def residual_bounds(K, P, Z, R):
    """(F, F_rad, J, J_rad) of the coded systems at the box centres Z (m × 3) with radii R (m × 3):
    F within F_rad of the exact equations' values at Z, every Jacobian over the box within J_rad
    of J (module docstring)."""
    g16, g8 = gamma(16), gamma(8)
    x, y, r = Z[:, 0:1], Z[:, 1:2], Z[:, 2:3]
    p0, p1, p2, p3 = P[..., 0], P[..., 1], P[..., 2], P[..., 3]
    ax, ay, ar = np.abs(x), np.abs(y), np.abs(r)
    Rx, Ry, Rr = R[:, 0:1], R[:, 1:2], R[:, 2:3]
    dx, dy = x - p0, y - p1
    Ra = p2 + p3 * r                                              # arcs: ρ + σ r
    pt, ln, nm, ac = K == POINT_EQ, K == LINE_EQ, K == NORMAL_EQ, K == ARC_EQ
    F = np.select([pt, ln, nm, ac], [dx * dx + dy * dy - r * r, p0 * x + p1 * y + p2 - p3 * r,
                                     p0 * (x - p2) + p1 * (y - p3), dx * dx + dy * dy - Ra * Ra])
    mx, my = ax + np.abs(p0), ay + np.abs(p1)                       # |x| + |p_x|, |y| + |p_y|
    mag = np.select([pt, ln, nm, ac],
                    [mx * mx + my * my + ar * ar,
                     np.abs(p0 * x) + np.abs(p1 * y) + np.abs(p2) + np.abs(p3 * r),
                     np.abs(p0) * (ax + np.abs(p2)) + np.abs(p1) * (ay + np.abs(p3)),
                     mx * mx + my * my + (np.abs(p2) + ar) ** 2])
    # point and arc rows: the rounding of the differences d = x − p (float data p̃ = p(1 + δ)):
    # |d̃ − d| ≤ u(|p̃| + |d̃|)(1 + 4u) =: e, so |fl(d̃²) − d²| ≤ e(2|d̃| + e) + u·d̃², and the two
    # additions add at most 2u of the sum (R = ρ + σr likewise, exact for a point: R = r)
    u = UNIT_ROUNDOFF
    ex = u * (np.abs(p0) + np.abs(dx)) * (1 + 4 * u)
    ey = u * (np.abs(p1) + np.abs(dy)) * (1 + 4 * u)
    R_ = np.where(ac, Ra, r)
    eR = np.where(ac, u * (np.abs(p2) + np.abs(Ra)) * (1 + 4 * u), 0.0)
    near = (ex * (2 * np.abs(dx) + ex) + ey * (2 * np.abs(dy) + ey) + eR * (2 * np.abs(R_) + eR)
            + 3 * u * (dx * dx + dy * dy + R_ * R_)) * (1 + 16 * u)
    F_rad = round_up(np.where(pt | ac, np.minimum(near, g16 * mag), g16 * mag))
    J = np.empty(K.shape + (3,))
    J_rad = np.empty(K.shape + (3,))
    J[..., 0] = np.select([pt, ln, nm, ac], [2 * dx, p0, p0, 2 * dx])
    J[..., 1] = np.select([pt, ln, nm, ac], [2 * dy, p1, p1, 2 * dy])
    J[..., 2] = np.select([pt, ln, nm, ac], [-2 * r + 0 * p0, -p3, 0 * p0, -2 * p3 * Ra])
    curved = pt | ac
    J_rad[..., 0] = np.where(curved, 2 * Rx + g16 * 2 * mx, g8 * np.abs(J[..., 0]))
    J_rad[..., 1] = np.where(curved, 2 * Ry + g16 * 2 * my, g8 * np.abs(J[..., 1]))
    J_rad[..., 2] = np.where(curved, 2 * Rr + g16 * 2 * (ar + np.where(ac, np.abs(p2), 0.0)),
                             g8 * np.abs(J[..., 2]))
    return F, F_rad, J, round_up(J_rad)


def _krawczyk(K, P, Z):
    """(ok, rad): the float Krawczyk test with ε-inflation on every row; where ok, the box
    |z − Z| ≤ rad holds exactly one zero of the row's system, simple."""
    m = len(Z)
    floor = (1.0 + np.abs(Z).sum(axis=1, keepdims=True)) * 2.0 ** -44
    R = np.broadcast_to(floor, (m, 3)).copy()
    ok = np.zeros(m, bool)
    rad = np.full((m, 3), np.inf)
    todo = np.arange(m)
    with np.errstate(all="ignore"):
        for attempt in range(ATTEMPTS):
            F, F_rad, J, J_rad = residual_bounds(K[todo], P[todo], Z[todo], R[todo])
            Y, good = float_inverse(J)
            b = float_residual_bound(Y, F, F_rad)
            if attempt == 0:                                     # a first radius 4|Y F(m)|, floored
                R[todo] = np.maximum(R[todo], 4 * b)
                F, F_rad, J, J_rad = residual_bounds(K[todo], P[todo], Z[todo], R[todo])
            passed, r_out = float_krawczyk_test(b, float_contraction_bound(Y, J, J_rad), R[todo])
            passed &= good & np.isfinite(R[todo]).all(axis=1)
            ok[todo[passed]] = True
            rad[todo[passed]] = r_out[passed]
            grow = np.where(np.isfinite(r_out), np.maximum(2 * r_out, 2 * R[todo]), 2 * R[todo])
            R[todo] = grow
            todo = todo[~passed]
            if not len(todo):
                break
    return ok, rad


def _segment_foot_inside(E: ElementarySites, t, Z, rad):
    """Proved: the foot parameter of every point of the box on the line of segment t lies in
    (0, 1); False means undecided.  With D = B − A, the parameter is num/den with
    num = (q − A)·D, den = |D|²; both are evaluated from correctly rounded ends within γ₁₆ of the
    sums of their terms' magnitudes, num moves by |D_x| ρ_x + |D_y| ρ_y over the box."""
    g16 = gamma(16)
    A, B = E.A[t], E.B[t]
    D = B - A
    q = Z[:, :2]
    num = np.einsum("ij,ij->i", q - A, D)
    den = np.einsum("ij,ij->i", D, D)
    sA = np.abs(A) + np.abs(B)
    e_num = round_up(g16 * np.einsum("ij,ij->i", np.abs(q) + np.abs(A), sA)
                     + (1 + g16) * (np.abs(D[:, 0]) * rad[:, 0] + np.abs(D[:, 1]) * rad[:, 1]))
    e_den = round_up(g16 * np.einsum("ij,ij->i", sA, sA))
    return (num - e_num > 0) & (num + e_num < den - e_den)


def _cross_lower(ax, ay, ux, uy, m_a, m_u, rad):
    """A lower bound of a_x u_y − a_y u_x over the box, with a = (ax, ay) within γ₁₆·m_a of the
    float values and u = q − c the box's offsets from a centre (magnitudes m_u, radii rad)."""
    g16 = gamma(16)
    val = ax * uy - ay * ux
    err = round_up(g16 * (m_a[:, 0] * m_u[:, 1] + m_a[:, 1] * m_u[:, 0])
                   + (1 + g16) * (np.abs(ax) * rad[:, 1] + np.abs(ay) * rad[:, 0]))
    return val - err


def _arc_contact_inside(E: ElementarySites, t, sign, Z, rad, orient):
    """Proved: ρ + σr > 0 over the box and the direction from the arc's centre to every point of
    the box lies in arc t's range (:func:`runtime.segments.vertices.direction_in_arc`: for an arc
    of less than a half turn (``orient``) both cross products with its end directions ≥ 0, else
    one of them); False means undecided."""
    g16 = gamma(16)
    rho = E.rho[t]
    r = Z[:, 2]
    R_lo = rho + sign * r - round_up(g16 * (np.abs(rho) + np.abs(r)) + rad[:, 2])
    C, A, B = E.C[t], E.A[t], E.B[t]
    q = Z[:, :2]
    ux, uy = q[:, 0] - C[:, 0], q[:, 1] - C[:, 1]
    m_u = np.abs(q) + np.abs(C)
    a, b = A - C, B - C
    m_a, m_b = np.abs(A) + np.abs(C), np.abs(B) + np.abs(C)
    ca = _cross_lower(a[:, 0], a[:, 1], ux, uy, m_a, m_u, rad)              # a × u
    cb = _cross_lower(-b[:, 0], -b[:, 1], ux, uy, m_b, m_u, rad)            # u × b = (−b) × u
    inside = np.where(orient, (ca > 0) & (cb > 0), (ca > 0) | (cb > 0))
    return (R_lo > 0) & inside


def _normal_beyond_arc_end(E: ElementarySites, t, e_xy, Z, rad):
    """Proved: λ = (q − c)·(e − c) > 0 over the box (the normal line at the end e of arc t, on the
    side away from the centre c); False means undecided."""
    C = E.C[t]
    q = Z[:, :2]
    w = e_xy - C
    lam = np.einsum("ij,ij->i", q - C, w)
    m_w = np.abs(e_xy) + np.abs(C)
    err = round_up(gamma(16) * np.einsum("ij,ij->i", np.abs(q) + np.abs(C), m_w)
                   + (1 + gamma(16)) * (np.abs(w[:, 0]) * rad[:, 0] + np.abs(w[:, 1]) * rad[:, 1]))
    return lam - err > 0


def _arc_orientation(E: ElementarySites, t: int, memo: dict) -> bool:
    """Whether arc t turns by less than a half turn from its start to its end (the exact sign of
    (A − c) × (B − c), as :func:`runtime.segments.vertices.direction_in_arc` computes it)."""
    if t not in memo:
        (cx, cy), _rho = E.arc[t]
        (ax, ay), (bx, by) = E.xy[int(E.ends[t, 0])], E.xy[int(E.ends[t, 1])]
        memo[t] = (Fraction(ax) - cx) * (Fraction(by) - cy) - (Fraction(ay) - cy) * (Fraction(bx) - cx) > 0
    return memo[t]


def prove_zeros_batch(E: ElementarySites, K, P, Z, sites) -> list:
    """For the coded contact systems (kinds ``K`` (m × 3), parameters ``P`` (m × 3 × 4), Newton
    limits ``Z`` (m × 3); ``sites`` (m × 3) the site of each equation, or the rows' equation
    lists of :func:`runtime.segments.vertices.contact_equations`), a proved
    :class:`VertexSolution` where the float test decides the row (module docstring), else None
    (the row goes to the arb proof)."""
    m = len(Z)
    out: list = [None] * m
    if not m:
        return out
    if not isinstance(sites, np.ndarray):
        sites = np.array([[t for _kind, _d, t in eqs] for eqs in sites], dtype=np.int64)
    sites = np.asarray(sites, dtype=np.int64).reshape(m, 3)
    Z = np.asarray(Z, float)
    ok, rad = _krawczyk(K, P, Z)
    ok &= Z[:, 2] - rad[:, 2] > 0                                      # r > 0 on the box
    # a box as tight as the arb proof's (its floor 2^-44 of the scale): the vertex is reported at
    # the box centre, which a wide box (an unconverged, ill-conditioned limit) leaves too far off
    ok &= (rad <= TIGHT * (1.0 + np.abs(Z).sum(axis=1, keepdims=True))).all(axis=1)
    idx = np.nonzero(ok)[0]
    if not len(idx):
        return out
    memo: dict = {}
    for j in range(3):                       # every contact where its equation says, over the box
        kind = K[idx, j]
        site = sites[idx, j]
        good = np.ones(len(idx), bool)
        line = kind == LINE_EQ
        if line.any():
            good[line] = _segment_foot_inside(E, site[line], Z[idx[line]], rad[idx[line]])
        arc = kind == ARC_EQ
        if arc.any():
            orient = np.array([_arc_orientation(E, int(t), memo) for t in site[arc]])
            good[arc] = _arc_contact_inside(E, site[arc], P[idx[arc], j, 3], Z[idx[arc]], rad[idx[arc]], orient)
        normal_arc = (kind == NORMAL_EQ) & (E.kind[site] == ARC)
        if normal_arc.any():
            e_xy = P[idx[normal_arc], j, 2:4]             # the end e, correctly rounded
            good[normal_arc] = _normal_beyond_arc_end(E, site[normal_arc], e_xy, Z[idx[normal_arc]],
                                                      rad[idx[normal_arc]])
        other = ~(line | arc | (kind == POINT_EQ) | ((kind == NORMAL_EQ) & (E.kind[site] == SEGMENT)) | normal_arc)
        good[other] = False                                  # (elliptic pieces are not coded here)
        ok[idx[~good]] = False
        idx = idx[good]
    for i in idx.tolist():
        x, y, r = Z[i]
        out[i] = VertexSolution("proved", float(x), float(y), float(r),
                                (arb(x, rad[i, 0]), arb(y, rad[i, 1]), arb(r, rad[i, 2])))
    return out
