"""Step 4 of the certificate (:mod:`runtime.voronoi.verify.certificate`) for point sites, exactly:
the unbounded edges of the Voronoi diagram of points are those of the pairs consecutive on the
boundary of their convex hull, collinear boundary points included.

Circles with rational radii, none inside another (:func:`verify_accounting_discs`): the same with the
boundary of the convex hull of the discs, common tangents decided exactly in a quadratic field.

Public API: :func:`verify_accounting_points`, :func:`verify_accounting_discs`, :func:`hull_candidates`.
"""
from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

from .problems import fault
__all__ = ["verify_accounting_points", "verify_accounting_discs", "hull_candidates"]


def verify_accounting_points(geoms, ends_inf, problems) -> bool:
    """Step 4 for point sites only, exactly (rational arithmetic, so collinear and co-linear hull
    points are decided, not approximated).  Far in direction d the nearest point maximises p·d,
    and among the points tied for the maximum (a side of the convex hull, d its outer normal) the
    nearest is the one whose coordinate along the side is closest; so the unbounded edges of the
    Voronoi diagram are exactly the bisectors of the pairs consecutive on the boundary of the
    convex hull, collinear boundary points included, each going to infinity along the side's outer
    normal (Preparata & Shamos, *Computational Geometry*, §5.5; for collinear points both sides of
    the degenerate hull).  The proved ends (pair, σ: direction σ·rot90(p_j − p_i)) must be exactly
    these, each once."""
    pts = [(Fraction(int(g.exact.cx.p), int(g.exact.cx.q)), Fraction(int(g.exact.cy.p), int(g.exact.cy.q)))
           for g in geoms]
    n = len(pts)
    if n < 2:
        return True
    order = sorted(range(n), key=lambda k: pts[k])

    def cross(o, a, b):
        return ((pts[a][0] - pts[o][0]) * (pts[b][1] - pts[o][1])
                - (pts[a][1] - pts[o][1]) * (pts[b][0] - pts[o][0]))

    def chain(seq):
        out: list = []
        for k in seq:
            while len(out) >= 2 and cross(out[-2], out[-1], k) < 0:     # keep collinear points
                out.pop()
            out.append(k)
        return out

    lower, upper = chain(order), chain(order[::-1])
    boundary = lower[:-1] + upper[:-1]            # counter-clockwise, collinear points kept
    want: dict = {}
    for t in range(len(boundary)):
        a, b = boundary[t], boundary[(t + 1) % len(boundary)]
        i, j = min(a, b), max(a, b)
        # outer normal of the side a → b (ccw boundary: the interior on the left) vs rot90(p_j − p_i)
        ox, oy = pts[b][1] - pts[a][1], -(pts[b][0] - pts[a][0])
        rx, ry = -(pts[j][1] - pts[i][1]), pts[j][0] - pts[i][0]
        key = (i, j, 1 if ox * rx + oy * ry > 0 else -1)
        want[key] = want.get(key, 0) + 1
    got: dict = {}
    ids: dict = {}
    for _, pair, sigma, eid in ends_inf:
        key = (int(pair[0]), int(pair[1]), int(sigma))
        got[key] = got.get(key, 0) + 1
        ids.setdefault(key, eid)
    ok = True
    for key in sorted(set(want) | set(got)):
        w, g = want.get(key, 0), got.get(key, 0)
        if w == g:
            continue
        ok = False
        i, j, sg = key
        if g < w:
            problems.append(fault(f"sites {i}, {j}: consecutive on the convex hull of the points, but no proved "
                                  "unbounded edge between them goes out across that side", kind="infinity",
                                  sites=(i, j)))
        else:
            problems.append(fault(f"edge {ids[key]} (sites {i}, {j}): an unbounded end that the convex hull of the "
                                  "points does not have" + (" (reported more than once)" if w else ""),
                                  kind="infinity", edge=ids[key], sites=(i, j)))
    return ok


def _sign_quadratic(A: Fraction, B: Fraction, D: Fraction) -> int:
    """The exact sign of A + B·√D (D ≥ 0)."""
    sa = (A > 0) - (A < 0)
    sb = (B > 0) - (B < 0)
    if sb == 0 or D == 0:
        return sa
    if sa == 0 or sa == sb:
        return sb if sa == 0 else sa
    diff = A * A - B * B * D          # sa ≠ sb: the larger magnitude wins
    return sa if diff > 0 else (sb if diff < 0 else 0)


def verify_accounting_discs(geoms, ends_inf, problems) -> bool | None:
    """Step 4 for disjoint circles and points with rational radii, none inside another, exactly:
    far in direction u the nearest site maximises h_k(u) = c_k·u + ρ_k, so the unbounded edges are
    those of the pairs consecutive on the boundary of the convex hull of the discs: for each pair
    (a, b) and each of its two outer common tangents L (outer normal u, with
    (c_a − c_b)·u = ρ_b − ρ_a), L supports every disc (c_k·u + ρ_k ≤ c_a·u + ρ_a, decided exactly in
    Q(√Δ), Δ = |c_b − c_a|² − (ρ_a − ρ_b)²) and a, b are consecutive among the discs touching L
    (ordered by their tangent points).  The edge of such a pair goes to infinity in direction u.
    Each proved end (pair, asymptotic direction) is matched with the nearer of its pair's two
    tangents; the proved ends must be exactly the expected ones.  Returns None when the sites do not
    qualify (irrational radius, nesting), so the caller uses the float accounting."""
    discs = _exact_discs(geoms)
    if discs is None:
        return None
    want = _hull_sides(*discs)
    return _ends_match_hull_sides(want, ends_inf, problems)


def _exact_discs(geoms):
    """(C, R, Cf, Rf): the exact rational centres and radii of the sites and their floats; None
    when a radius is irrational or a disc lies inside another (float prefilter)."""
    from ...algebra.quadtower import rational_sqrt

    C, R = [], []
    for g in geoms:
        ex = g.exact
        rho = rational_sqrt(ex.r2) if hasattr(ex, "r2") else None
        if rho is None:
            return None
        C.append((Fraction(int(ex.cx.p), int(ex.cx.q)), Fraction(int(ex.cy.p), int(ex.cy.q))))
        R.append(Fraction(int(rho.p), int(rho.q)))
    Cf = np.array([[float(x), float(y)] for x, y in C])
    Rf = np.array([float(r) for r in R])
    for a in range(len(geoms)):                            # no disc inside another (float prefilter)
        inside = np.hypot(*(Cf - Cf[a]).T) + Rf < Rf[a] + 1e-9 * (np.abs(Cf).max() + Rf.max() + 1)
        inside[a] = False
        if inside.any():
            return None
    return C, R, Cf, Rf


#: directions sampled for the candidates of the hull
HULL_SAMPLES = 4096


def hull_candidates(Cf, Rf) -> list[int]:
    """The discs that may maximise h_k(u) = c_k·u + ρ_k in some direction: at the sample nearest
    to a direction where disc k leads (at most δ = π/HULL_SAMPLES away) h_k is within
    |c_k − c_j|·δ ≤ 2 max|c|·δ of every h_j (h_k' − h_j' = (c_k − c_j)·u⊥), so k is within that
    (widened for the floats) of the sampled maximum."""
    th = np.linspace(0, 2 * np.pi, HULL_SAMPLES, endpoint=False)
    U = np.stack([np.cos(th), np.sin(th)], 1)
    H = Cf @ U.T + Rf[:, None]
    scale = float(np.abs(Cf).max() + Rf.max() + 1.0)
    reach = 2.0 * float(np.hypot(*Cf.T).max()) * (np.pi / HULL_SAMPLES) * (1 + 1e-6) + 1e-9 * scale
    top = H.max(0)
    return sorted(set(np.nonzero((H >= top[None, :] - reach).any(1))[0].tolist()))


def _hull_sides(C, R, Cf, Rf) -> dict:
    """{(a, b, s): u}: the pairs consecutive on the boundary of the convex hull of the discs, with
    the outer normal u of their common tangent s = ±1 that supports every disc (decided exactly
    in Q(√Δ)) and no disc touching it between a's and b's tangent points."""
    scale = float(np.abs(Cf).max() + Rf.max() + 1.0)
    cand = hull_candidates(Cf, Rf)
    want: dict = {}
    for ia, a in enumerate(cand):
        for b in cand[ia + 1:]:
            wx, wy = C[b][0] - C[a][0], C[b][1] - C[a][1]
            w2 = wx * wx + wy * wy
            dl = R[a] - R[b]
            Dl = w2 - dl * dl
            if Dl <= 0:
                continue
            sq = math.sqrt(float(Dl))
            for s in (1, -1):
                # u = (δ·w + s·√Δ·rot90(w)) / |w|²; f_k = (c_k − c_a)·u + ρ_k − ρ_a ≤ 0 for all k
                ok, touch = True, []
                uf = (float(dl) * np.array([float(wx), float(wy)]) + s * sq * np.array([-float(wy), float(wx)])) / float(w2)
                ff = (Cf - Cf[a]) @ uf + Rf - Rf[a]           # float f_k: clearly outside → no exact test
                if (ff > 1e-9 * scale).any():
                    continue
                for k in np.nonzero(ff >= -1e-9 * scale)[0].tolist():
                    vx, vy = C[k][0] - C[a][0], C[k][1] - C[a][1]
                    A = dl * (vx * wx + vy * wy) / w2 + R[k] - R[a]
                    B = s * (-vx * wy + vy * wx) / w2
                    sg = _sign_quadratic(A, B, Dl) if k not in (a, b) else 0
                    if sg > 0:
                        ok = False
                        break
                    if sg == 0:
                        touch.append(k)
                if not ok:
                    continue
                t = np.array([-uf[1], uf[0]])
                pos = {k: float(Cf[k] @ t) for k in touch}
                lo, hi = sorted((pos[a], pos[b]))
                between = [k for k in touch if k not in (a, b) and lo - 1e-9 * scale <= pos[k] <= hi + 1e-9 * scale]
                if between:
                    continue
                want[(a, b, s)] = uf
    return want


def _ends_match_hull_sides(want, ends_inf, problems) -> bool:
    """Each proved end (pair, asymptotic direction) matched with the nearer of its pair's two
    tangents; the proved ends must be exactly the hull's sides, once each."""
    got: dict = {}
    for th_e, pair, _, eid in ends_inf:
        a, b = int(pair[0]), int(pair[1])
        d = np.array([math.cos(th_e), math.sin(th_e)])
        opts = [(float(d @ u), s) for (p, q, s), u in want.items() if (p, q) == (a, b)]
        if not opts:
            problems.append(fault(f"edge {eid} (sites {a}, {b}): an unbounded end that the convex hull of the "
                                  "sites does not have", kind="infinity", edge=eid, sites=(a, b)))
            return False
        opts.sort(reverse=True)
        if len(opts) > 1 and opts[0][0] - opts[1][0] < 1e-9:
            problems.append(f"edge {eid} (sites {a}, {b}): its direction at infinity cannot be told apart")
            return False
        key = (a, b, opts[0][1])
        got[key] = got.get(key, 0) + 1
    ok = True
    for key in sorted(set(want) | set(got)):
        if got.get(key, 0) != 1:
            ok = False
            a, b, _ = key
            problems.append(fault(f"sites {a}, {b}: " + ("consecutive on the convex hull of the sites, but no proved "
                                                        "unbounded edge between them goes out across that side"
                                                        if not got.get(key) else "an unbounded end reported more than once"),
                                  kind="infinity", sites=(a, b)))
    return ok
