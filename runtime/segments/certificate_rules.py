"""The rules of an edge proof decided at its ends and at infinity (see
:mod:`runtime.segments.certificate_edges` for the whole proof): R1 (an endpoint of a segment site
of the edge) and R2 (a curve ending at a point site of the edge) as *linear conditions*
g·x + g₀ > 0, and the infinite tails of straight edges.

**R1** k is an endpoint of a segment i (or j): d_k > d_i exactly when the foot of x on i is not k;
the foot is affine along lines and *is* the parameter of a parabola, so on a finite edge it
suffices that it is on the right side at both ends (exactly at k at an end vertex listing k or at
the corner k, proved strictly otherwise) and not at k at both.  On the perpendicular at an
endpoint, the radial ray at an arc's end and the normal line at a smooth joint the curve's
nearest point is the edge's point everywhere, so its other end is always farther; a curve's end
that is a smooth joint is no site (its foot condition holds between the end vertices for the same
reason).  Along an arc's bisector R1 is a condition of the piecewise proof.

**R2** k is a curve with an end e ∈ {i, j} (a point site): d_k ≤ d_e always, so k's nearest
point must be e alone, strictly beyond it (then d_k = d_e and the tie is e's by convention): for
a segment its foot beyond e (f < 0 or f > 1), for an arc the direction from its centre strictly in
the half of its gap next to e — two linear conditions (half-planes through the centre).  An arc
whose two ends are the edge's two points has both as nearest points exactly on the side of its
gap: (x − c)·g > 0, g the gap's middle direction (a segment there is closer: a fault).  Along
lines these are affine in the parameter: end values as for R1, and towards infinity the exact
slope; along curves they are proved with the pieces.

**Tails** (straight infinite edges, ρ = |x − P| for a point P: two points, an endpoint's
perpendicular, an arc end's radial ray, a smooth joint's normal line): with x = O + s w_∞,
|x − p|² − |x − P|² = C_p + 2 s w_∞·(P − p) is affine in s for each point p of a site k; if the
slopes are ≥ 0 on all of k — the support of k in direction w_∞ is at most w_∞·P (an arc's is
c·w + ρ|w| when w is in its range: squares) — and d_k² − ρ² > 0 at s = S, then d_k² − ρ² — the
minimum over k's points of nondecreasing functions — stays positive for all s ≥ S.  Values at S
are accepted in floats above 10⁻⁹ (|x| + M)², and decided exactly otherwise (an arc's distance in
squares).

**Corners** (:func:`corner_ratio`): at a corner vertex c of radius 0 the curve is the line
c + τ u; a curve k through c is farther than the edge's sites on the whole ray when
D_k − D_i > 0 (ρ = τ D_i exactly; d_k ≥ τ D_k with D_k the distance from u to the line of a
segment, |u| when it leaves c away from u or the ray stays in the half of an arc's gap next to
c, and u·n̂ for an arc when u leaves its circle outwards, n̂ its outer normal at c).

Along curves an arc k ending at e needs only its direction outside its open range: its other
end is farther than the edge's sites anyway (an end of the edge's curves, R1; a site, R3; a joint
with a curve that R3 proves farther).

Public API: :func:`affine_rules`, :func:`linear_rule`, :func:`outside_range_rule`,
:func:`range_lines`, :func:`prove_tail`, :func:`tied`, :func:`corner_ratio`, :func:`exact_gt`.
"""
from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
from flint import arb

from .certificate_curves import Line, exact_d2, q_arb
from .certificate_sites import ARC, POINT, SEGMENT

__all__ = ["convex_tangents", "affine_rules", "linear_rule", "outside_range_rule", "range_lines", "prove_tail", "tied", "corner_ratio",
           "exact_gt"]

#: float margin (relative) above which a float sign is trusted
FLOAT_MARGIN = 1e-9

STRAIGHT_THROUGH = ("perp", "radial", "joint")


def tied(end, k) -> bool:
    """Site k ties with the edge's sites at this end (a vertex listing k, or the corner k)."""
    return end[0] == "v" and (k in end[2].listed or end[2].corner == k)


def linear_rule(T, k, e, away: bool) -> list:
    """The linear conditions (gx, gy, g0) — each g·x + g₀ > 0 — saying that curve k's nearest
    point is not its end e (``away``, R1: a segment's foot) or is e alone (R2).  Exact rationals
    that depend on the sites only: computed once per (k, e, away) for the site table."""
    key = (k, e, away)
    rules = T.rule_cache.get(key)
    if rules is None:
        rules = T.rule_cache[key] = tuple(_linear_rule(T, k, e, away))
    return list(rules)


def _linear_rule(T, k, e, away: bool) -> list:
    which = T.end_index(k, e)
    if T.kind[k] == SEGMENT:
        (ax, ay), (bx, by) = T.a[k], T.b[k]
        dx, dy = bx - ax, by - ay
        L2 = dx * dx + dy * dy
        sign = (1 if which == 0 else -1) * (1 if away else -1)
        shift = 0 if which == 0 else 1
        # sign · (foot − shift), foot = ((x − a)·d)/L2
        return [(sign * dx / L2, sign * dy / L2, sign * (-(ax * dx + ay * dy) / L2 - shift))]
    (cx, cy) = T.cen[k]
    g = T.arc_mid(k)
    gx, gy = -g[0], -g[1]
    ex, ey = (T.pt(e)[0] - cx, T.pt(e)[1] - cy)

    def cross_with(ux, uy, first: bool):
        # first: u × (x − c) = ux (y − cy) − uy (x − cx);  else (x − c) × u
        if first:
            return (-uy, ux, uy * cx - ux * cy)
        return (uy, -ux, -uy * cx + ux * cy)
    if which == 0:
        return [cross_with(gx, gy, True), cross_with(ex, ey, False)]
    return [cross_with(ex, ey, True), cross_with(gx, gy, False)]


def range_lines(T, k):
    """(ua × (x − c), (x − c) × ub) of arc k as (gx, gy, g0): both > 0 inside an arc of at most
    180°, one of them inside a larger one."""
    (cx, cy) = T.cen[k]
    ua = (T.a[k][0] - cx, T.a[k][1] - cy)
    ub = (T.b[k][0] - cx, T.b[k][1] - cy)
    return (-ua[1], ua[0], ua[1] * cx - ua[0] * cy), (ub[1], -ub[0], -ub[1] * cx + ub[0] * cy)


def outside_range_rule(T, k):
    """(mode, conditions) saying that the direction from arc k's centre misses its open range:
    "max" (one of them > 0) or "all"."""
    ga, gb = range_lines(T, k)
    na, nb = tuple(-v for v in ga), tuple(-v for v in gb)
    (cx, cy) = T.cen[k]
    ab = (T.a[k][0] - cx) * (T.b[k][1] - cy) - (T.a[k][1] - cy) * (T.b[k][0] - cx)
    if ab > 0:
        return "max", [na, nb]
    if ab < 0:
        return "all", [na, nb]
    return "all", [na]


def affine_rules(pr) -> bool:
    """R1 for points and segments along lines and parabolas, R2 along lines (module docstring);
    sets ``pr.skip`` (the sites these rules, or the arc rules, settle) and ``pr.linear`` (R2
    conditions left to the pieces: (k, "all" or "max", [(gx, gy, g0)])."""
    T, c, i, j = pr.T, pr.curve, pr.i, pr.j
    ok = True
    pr.skip = set()
    pr.linear = []
    arc_curve = c.kind == "arc"
    for s in (i, j):
        if not T.is_curve(s):
            continue
        for k in T.ends[s]:
            if k < 0 or k in (i, j):
                continue
            pr.skip.add(k)
            if c.kind in STRAIGHT_THROUGH or arc_curve or T.kind[s] == ARC:
                continue                      # automatic, or a condition of the arc's pieces
            if not _affine_ok(pr, linear_rule(T, s, k, True), k):
                ok = False
    for p in (i, j):
        if T.kind[p] != POINT:
            continue
        for k in T.incident[p]:
            if k in (i, j) or k in pr.skip:
                continue
            if any(q in (i, j) for q in T.ends[k] if q != p):
                pr.skip.add(k)
                if T.kind[k] == ARC:              # its nearest points are its two ends: the gap side
                    g = T.arc_mid(k)
                    (cx, cy) = T.cen[k]
                    conds = [(-g[0], -g[1], g[0] * cx + g[1] * cy)]
                    if isinstance(c, Line):
                        ok = _affine_ok(pr, conds, k) and ok
                    else:
                        pr.linear.append((k, "all", conds))
                    continue
                pr.report(f"curve {k} joins both its sites and is closer than them", k)
                ok = False
                continue
            pr.skip.add(k)
            if not isinstance(c, Line):             # proved with the pieces
                pr.linear.append((k,) + (outside_range_rule(T, k) if T.kind[k] == ARC else
                                         ("all", linear_rule(T, k, p, False))))
                continue
            if not _affine_ok(pr, linear_rule(T, k, p, False), k):
                ok = False
    return ok


def _affine_ok(pr, conds, k) -> bool:
    """Each condition g·x + g₀ > 0 on the open edge (finite ends: values; infinite: slopes)."""
    lo, hi = pr.lo, pr.hi
    c = pr.curve
    for gx, gy, g0 in conds:
        vals = []
        for end in (lo, hi):
            if end[0] == "inf":
                vals.append(None)
                continue
            vp = end[2]
            ax, ay, a0 = _arb_rule(pr.T, gx, gy, g0)
            v = ax * vp.x + ay * vp.y + a0
            if v > 0:
                vals.append(1)
            elif tied(end, k) or (pr.T.kind[k] == ARC and all(e in vp.listed for e in pr.T.ends[k])):
                vals.append(0)                    # an arc's two listed ends: on its gap's middle
            else:
                what = "is closer than its sites at an end vertex" if v < 0 else \
                    "is too close to decide at an end vertex"
                pr.report(f"site {k} {what}", k)
                return False
        if vals[0] is not None and vals[1] is not None:
            if vals[0] == 0 and vals[1] == 0:
                pr.report(f"site {k} ties with its sites along the whole edge", k)
                return False
            continue
        # an infinite end: the exact slope (τ grows towards hi)
        slope = None if c.wq is None else gx * c.wq[0] + gy * c.wq[1]
        if slope is None:
            pr.report(f"site {k}: no exact slope towards infinity", k)
            return False
        if vals[0] is None and vals[1] is None:
            good = slope == 0 and gx * c.Oq[0] + gy * c.Oq[1] + g0 > 0
        elif vals[1] is None:
            good = slope > 0 or (slope == 0 and vals[0] == 1)
        else:
            good = slope < 0 or (slope == 0 and vals[1] == 1)
        if not good:
            pr.report(f"site {k} is closer than its sites towards infinity", k)
            return False
    return True


def _arb_rule(T, gx, gy, g0):
    """The balls q_arb(gx), q_arb(gy), q_arb(g0) of a linear condition, cached in the site table
    (the conditions depend on the sites only; the certificate runs at one working precision)."""
    key = ("arb", gx, gy, g0)
    v = T.rule_cache.get(key)
    if v is None:
        v = T.rule_cache[key] = (q_arb(gx), q_arb(gy), q_arb(g0))
    return v


def exact_gt(T, k, x, r2) -> bool:
    """d_k(x)² > r2 exactly, for a rational point x."""
    if T.kind[k] != ARC:
        return exact_d2(T, k, x) > r2
    (cx, cy), rho = T.cen[k], T.rad[k]
    w = (x[0] - cx, x[1] - cy)
    D2 = w[0] * w[0] + w[1] * w[1]
    if D2 == 0:
        return rho * rho > r2
    if T.in_range(k, w[0], w[1], closed=True):
        L = D2 + rho * rho - r2                  # (√D2 − ρ)² > r2  ⟺  L > 2ρ√D2
        return L > 0 and L * L > 4 * rho * rho * D2
    return min((q[0] - x[0]) ** 2 + (q[1] - x[1]) ** 2 for q in (T.a[k], T.b[k])) > r2


def _support_ok(T, k, w, P) -> bool:
    """The support of site k in direction w is at most w·P (exact)."""
    hp = w[0] * P[0] + w[1] * P[1]
    if any(w[0] * q[0] + w[1] * q[1] > hp for q in {T.a[k], T.b[k]}):
        return False
    if T.kind[k] != ARC or not T.in_range(k, w[0], w[1], closed=True):
        return True
    (cx, cy), rho = T.cen[k], T.rad[k]
    gap = hp - (w[0] * cx + w[1] * cy)
    return gap >= 0 and gap * gap >= rho * rho * (w[0] * w[0] + w[1] * w[1])


def prove_tail(pr, sgn: int, s_min: float):
    """Prove the tail s ≥ S (x = O + s·sgn·w) for every site but i, j and the rule ones; returns
    S as the float parameter distance where the finite part ends, or None."""
    T, c = pr.T, pr.curve
    (ox, oy), (wx, wy) = c.Oq, c.wq
    wx, wy = sgn * wx, sgn * wy
    px, py = c.anchor_q if (sgn > 0 or c.anchor2 is None) else c.anchor2
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
    arcs = T.karr[idx] == ARC
    if arcs.any():                            # the circle's support point, when in the range
        C, R = T.C[idx[arcs]], T.R[idx[arcs]]
        circ = (fP - C) @ fw - R * float(np.hypot(*fw))
        slopes[arcs, 0] = np.minimum(slopes[arcs, 0], circ)
    doubt = np.nonzero((slopes < FLOAT_MARGIN * nw * M).any(axis=1))[0]
    failed = [int(idx[m]) for m in doubt.tolist() if not _support_ok(T, int(idx[m]), (wx, wy), (px, py))]
    if failed:
        for k in failed:
            pr.report(f"site {k} is nearer than its sites far along the infinite end", k)
        return None

    def values(S):
        X = fO + S * fw
        lo, _ = T.float_bounds(idx, np.repeat(X[None, :], len(idx), axis=0))
        rho = float(np.hypot(*(X - fP)))
        return np.sign(lo) * lo * lo - rho * rho, (float(np.abs(X).max()) + M) ** 2

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
        if not exact_gt(T, k, xq, rho2):
            failed.append(k)
    if failed:
        for k in failed:
            pr.report(f"site {k} is not proved farther than its sites along the infinite end", k)
        return None
    return S


def corner_ratio(T, c, k: int, cpt: int, at_lo: bool, far=None) -> bool:
    """Curve k (through the corner point site ``cpt``, the origin O of the line c) is strictly
    farther than the edge's sites on the whole ray from the corner into the arc (``at_lo``: the
    arc has τ > 0; ``far``: the point box of the arc's other end, None at infinity):
    g_k(c + τ u) ≥ τ (D_k − D_i) (module docstring)."""
    if not (isinstance(c, Line) and tuple(c.Oq) == tuple(T.a[cpt])) or not T.is_curve(k):
        return False
    ux, uy = c.w if at_lo else (-c.w[0], -c.w[1])
    norm_u = (ux * ux + uy * uy).sqrt()
    (cx, cy) = T.a[cpt]
    if T.kind[k] == ARC:
        from .certificate_corner_curves import ray_in_gap_half

        (kx, ky), rho = T.cen[k], T.rad[k]
        if ray_in_gap_half(T, k, cpt, ux, uy, far):
            Dk = norm_u                       # the corner is the arc's nearest point on the ray
        else:
            Dk = (ux * q_arb(cx - kx) + uy * q_arb(cy - ky)) / q_arb(rho)
            if not Dk > 0:
                return False
    else:
        o = T.ends[k][1] if T.ends[k][0] == cpt else T.ends[k][0]
        (ox, oy) = T.pt(o)
        dx, dy = q_arb(ox - cx), q_arb(oy - cy)
        dot = ux * dx + uy * dy
        Dk = norm_u if dot < 0 else abs(ux * dy - uy * dx) / (dx * dx + dy * dy).sqrt()
    if c.anchor is not None:
        Di = norm_u
    else:
        (nx, ny), _ = c.side
        Di = nx * ux + ny * uy
    return bool(Dk - Di > 0)


def convex_tangents(T, c, k: int, fns, a: float, b: float) -> bool:
    """g_k = d_k − ρ > 0 on the whole straight edge c(τ), τ ∈ [a, b], by convexity.

    Along a bisector of two lines ρ is affine, and the distance to a point or a segment (a convex
    set) is convex, so g_k is convex and lies above its tangents at a and b.  With g_k(a),
    g_k(b) > 0 the tangent at a is positive up to a + g(a)/(−g'(a)) and the tangent at b from
    b − g(b)/g'(b) on: the two ranges cover [a, b] when the first ends after the second starts,
    or when a tangent's slope points away from its zero.  Nearly parallel segments make edges
    10⁶ long whose clearance changes by 10⁻⁵ per unit: pieces cannot cover them, two tangents
    do.  ``fns``: the (value, derivative) functions of g_k on balls."""
    if not (isinstance(c, Line) and c.anchor is None and T.kind[k] != ARC and math.isfinite(a)
            and math.isfinite(b) and b > a):
        return False
    value, deriv = fns
    ends = []
    for tau in (arb(a), arb(b)):
        X, Y = c.xy(tau)
        ends.append((value(tau, X, Y, c.rho(tau, X, Y)), deriv(tau, X, Y)))
    (ga, da), (gb, db) = ends
    if not (ga > 0 and gb > 0 and da.is_finite() and db.is_finite()):
        return False
    if da >= 0 or db <= 0:
        return True
    return bool(da < 0 and db > 0 and arb(a) - ga / da > arb(b) - gb / db)
