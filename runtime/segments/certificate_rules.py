"""The rules of an edge proof decided at its ends and at infinity (see
:mod:`runtime.segments.certificate_edges` for the whole proof): R1 (an endpoint of a segment site
of the edge) and R2 (a segment ending at a point site of the edge) along lines, where the foot
parameter is affine in the curve's parameter, and the infinite tails of straight edges.

**R1** k is an endpoint of a segment i (or j): d_k > d_i exactly when the foot of x on i is not k;
the foot is affine in the parameter (on the parabola it *is* the parameter), so it suffices that
it is on the right side at both ends (exactly at k at an end vertex listing k or at the corner k,
proved strictly otherwise) and not at k at both.  On the perpendicular at an endpoint e of s the
foot is e everywhere, so the other endpoint is always farther.

**R2** k is a segment with an endpoint e ∈ {i, j}: d_k ≤ d_e always, so the foot of x on k must be
clamped strictly beyond e (then d_k = d_e and the tie is e's by convention); along lines the foot
is affine: end values as for R1, and towards infinity the exact slope (w·(b − a) in rationals).

**Tails** (perpendicular bisectors of points and perpendiculars at endpoints, ρ = |x − P| for a
point P): with x = O + s w_∞, |x − p|² − |x − P|² = C_p + 2 s w_∞·(P − p) is affine in s for each
point p of a site k; if the slopes are ≥ 0 at k's endpoints (hence on all of k) and
d_k² − ρ² > 0 at s = S, then d_k² − ρ² — the minimum over k's points of nondecreasing functions —
stays positive for all s ≥ S.  Slopes are decided exactly where their float value is below a
margin; d_k² − ρ² at S is accepted in floats above 10⁻⁹ (|x| + M)², far above its rounding error
(a few units of 2⁻⁵³ (|x| + M)², M the largest coordinate), and decided exactly otherwise.

**Corners** (:func:`corner_ratio`): at a corner vertex c of radius 0 the curve is the line
c + τ u; a segment k through c is farther than the edge's sites on the whole ray when
D_k − D_i > 0 (ρ = τ D_i exactly; d_k ≥ τ D_k).

Public API: :func:`affine_rules`, :func:`prove_tail`, :func:`tied`, :func:`corner_ratio`.
"""
from __future__ import annotations

from fractions import Fraction

import numpy as np

from .certificate_curves import Line, exact_d2, q_arb
from .certificate_sites import POINT, SEGMENT
from .distance import distances

__all__ = ["affine_rules", "prove_tail", "tied", "corner_ratio"]

#: float margin (relative) above which a float sign is trusted
FLOAT_MARGIN = 1e-9


def tied(end, k) -> bool:
    """Site k ties with the edge's sites at this end (a vertex listing k, or the corner k)."""
    return end[0] == "v" and (k in end[2].listed or end[2].corner == k)

def affine_rules(pr) -> bool:
    """R1 for every curve and R2 along lines (module docstring)."""
    T, c, i, j = pr.T, pr.curve, pr.i, pr.j
    ok = True
    pr.skip = set()
    for s in (i, j):
        if T.kind[s] != SEGMENT:
            continue
        for which, k in enumerate(T.ends[s]):
            if k in (i, j):
                continue
            pr.skip.add(k)
            if c.kind == "perp":
                continue                      # the foot on s is the other endpoint, exactly
            g = _foot_rule(pr, s, which, away=True)
            if not _affine_ok(pr, g, s, k):
                ok = False
    for p in (i, j):
        if T.kind[p] != POINT:
            continue
        for k in T.incident[p]:
            if k in (i, j):
                continue
            if any(q in (i, j) for q in T.ends[k] if q != p):
                pr.report(f"segment {k} joins both its sites and is closer than them", k)
                pr.skip.add(k)
                ok = False
                continue
            if c.kind == "parabola":
                continue                      # proved with the R3 pieces
            pr.skip.add(k)
            which = T.end_index(k, p)
            g = _foot_rule(pr, k, which, away=False)
            if not _affine_ok(pr, g, k, k):
                ok = False
    return ok

def _foot_rule(pr, s, which, away):
    """g(τ) from the foot f on segment s: away from endpoint ``which`` (f > 0 or f < 1, R1) or
    beyond it (f < 0 or f > 1, R2); returns (value at a vertex box, exact slope per τ or None)."""
    T, c = pr.T, pr.curve
    sign = (1 if which == 0 else -1) * (1 if away else -1)
    shift = 0 if which == 0 else 1

    def at(vp):
        return sign * (T.foot(s, vp.x, vp.y) - shift)

    slope = None
    if isinstance(c, Line) and c.wq is not None:
        (ax, ay), (bx, by) = T.a[s], T.b[s]
        slope = sign * (c.wq[0] * (bx - ax) + c.wq[1] * (by - ay)) / ((bx - ax) ** 2 + (by - ay) ** 2)
    return at, slope, sign, shift, s

def _affine_ok(pr, g, s, k) -> bool:
    at, slope, sign, shift, s = g
    lo, hi = pr.lo, pr.hi
    vals = []
    for end in (lo, hi):
        if end[0] == "inf":
            vals.append(None)
        elif tied(end, k):
            vals.append(0)
        else:
            v = at(end[2])
            if not v > 0:
                what = "is closer than its sites at an end vertex" if v < 0 else "is too close to decide at an end vertex"
                pr.report(f"site {k} {what} (foot on segment {s})", k)
                return False
            vals.append(1)
    if vals[0] is not None and vals[1] is not None:
        if vals[0] == 0 and vals[1] == 0:
            pr.report(f"site {k} ties with its sites along the whole edge", k)
            return False
        return True
    # an infinite end: exact slope (τ grows towards hi)
    c = pr.curve
    if vals[0] is None and vals[1] is None:
        (ox, oy), (ax, ay), (bx, by) = c.Oq, pr.T.a[s], pr.T.b[s]
        f0 = ((ox - ax) * (bx - ax) + (oy - ay) * (by - ay)) / ((bx - ax) ** 2 + (by - ay) ** 2)
        good = slope == 0 and sign * (f0 - shift) > 0
    elif vals[1] is None:
        good = slope > 0 or (slope == 0 and vals[0] == 1)
    else:
        good = slope < 0 or (slope == 0 and vals[1] == 1)
    if not good:
        pr.report(f"site {k} is closer than its sites towards infinity (foot on segment {s})", k)
    return good


def prove_tail(pr, sgn: int, s_min: float):
    """Prove the tail s ≥ S (x = O + s·sgn·w) for every site but i, j and the affine-rule
    ones; returns S·sgn as the float parameter where the finite part ends, or None."""
    T, c = pr.T, pr.curve
    (ox, oy), (wx, wy) = c.Oq, c.wq
    wx, wy = sgn * wx, sgn * wy
    px, py = c.anchor_q
    idx = np.array([k for k in range(T.n) if k not in pr.skip and k not in (pr.i, pr.j)], dtype=int)
    if len(idx) == 0:
        return max(s_min, 0.0) + 1.0
    fw = np.array([float(wx), float(wy)])
    fP = np.array([float(px), float(py)])
    fO = np.array([float(ox), float(oy)])
    A, B = T.A[idx], T.B[idx]
    M = T.scale + float(np.abs(fO).max()) + float(np.abs(fP).max())
    nw = float(np.abs(fw).max()) + 1e-300
    slopes = np.stack([(fP - A) @ fw, (fP - B) @ fw], axis=1)
    doubt = np.nonzero((slopes < FLOAT_MARGIN * nw * M).any(axis=1))[0]
    failed = []
    for m in doubt.tolist():
        k = int(idx[m])
        for p in {T.a[k], T.b[k]}:
            if wx * (px - p[0]) + wy * (py - p[1]) < 0:
                failed.append(k)
                break
    if failed:
        for k in failed:
            pr.report(f"site {k} is nearer than its sites far along the infinite end", k)
        return None
    def values(S):
        X = fO + S * fw
        d, _ = distances(A, B, np.repeat(X[None, :], len(idx), axis=0))
        rho = float(np.hypot(*(X - fP)))
        return d * d - rho * rho, (float(np.abs(X).max()) + M) ** 2

    S = max(s_min, 0.0) + 1.0
    for _ in range(200):
        val, mag = values(S)
        hard = val <= FLOAT_MARGIN * mag
        if not hard.any() or not (slopes[hard] > FLOAT_MARGIN * nw * M).all():
            break                            # all clear, or a flat direction: decided exactly below
        S *= 2
    val, mag = values(S)
    Sq = Fraction(S)
    xq = (ox + Sq * wx, oy + Sq * wy)
    rho2 = (xq[0] - px) ** 2 + (xq[1] - py) ** 2
    for m in np.nonzero(val <= FLOAT_MARGIN * mag)[0].tolist():
        k = int(idx[m])
        if not exact_d2(T, k, xq) > rho2:
            failed.append(k)
    if failed:
        for k in failed:
            pr.report(f"site {k} is not proved farther than its sites along the infinite end", k)
        return None
    return S


def corner_ratio(T, c, k: int, cpt: int, at_lo: bool) -> bool:
    """Segment k (through the corner point site ``cpt``, the origin O of the line c) is strictly
    farther than the edge's sites on the whole ray from the corner into the arc (``at_lo``: the
    arc has τ > 0): g_k(c + τ u) ≥ τ (D_k − D_i) with D_i = ρ/τ and D_k the distance from u to the
    line of k, or |u| when k leaves c away from u (exact for the clamped foot, a lower bound
    otherwise: the distance to a segment is at least the distance to its line)."""
    if not (isinstance(c, Line) and tuple(c.Oq) == tuple(T.a[cpt])) or T.kind[k] != SEGMENT:
        return False
    ux, uy = c.w if at_lo else (-c.w[0], -c.w[1])
    o = T.ends[k][1] if T.ends[k][0] == cpt else T.ends[k][0]
    (ox, oy), (cx, cy) = T.a[o], T.a[cpt]
    dx, dy = q_arb(ox - cx), q_arb(oy - cy)
    norm_u = (ux * ux + uy * uy).sqrt()
    dot = ux * dx + uy * dy
    Dk = norm_u if dot < 0 else abs(ux * dy - uy * dx) / (dx * dx + dy * dy).sqrt()
    if c.anchor is not None:
        Di = norm_u
    else:
        (nx, ny), _ = c.side
        Di = nx * ux + ny * uy
    return bool(Dk - Di > 0)
