"""Voronoi vertices of convex conic sites proved in floating point, all at once (thesis §6.1).

A Voronoi vertex of the sites i, j, k is a zero of F(q) = (d_i(q) − d_j(q), d_i(q) − d_k(q))
with every other site farther (the emptiness test of :mod:`runtime.voronoi.verify.vertices`):
there d_i = d_j = d_k = r, the distance being the minimum over each curve, so the circle of
radius r about q touches the three sites and no other.  For convex sites (points, circles,
ellipses, parabolas) and q outside their convex hulls the distance functions are C¹ with
∇d = (q − p)/|q − p|, enclosed on a disc by
:func:`runtime.voronoi.verify.site_table.gradient_enclosure`.

**Krawczyk's test** (Krawczyk 1969; Moore, Kearfott & Cloud, *Introduction to Interval
Analysis*, SIAM 2009, §8.2) on the square B = c + [−ρ, ρ]², decided by the kernel's float test
:func:`runtime.certify.interval_newton.float_krawczyk_test` (its proof and rounding model, Higham
§3.1, there).  The enclosures handed to it: F(c) within Fa of 0, Fa from the rigorous distance
bounds (|d_i − d_j| ≤ max(|lo_i − hi_j|, |hi_i − lo_j|)); with J̃ the float Jacobian at c (rows
G_i − G_j, G_i − G_k), every Jacobian J(q), q ∈ B, within E_b + 2u|J̃| of J̃ entrywise in row b
(E_b the sum of the two gradient slacks on the circumscribed disc B(c, ρ√2), a bound of the row's
2-norm deviation and so of each entry's; u|J̃| the float subtraction).  The mean-value form of the
kernel's proof needs only these (F(q) − F(c) = J̄(q − c) with J̄ an average of Jacobians on the
segment [c, q] ⊂ B, the enclosures being convex).  Vertices whose sites are not all
convex, or where the test fails for every tried ρ, are left to the exact route
(:func:`runtime.voronoi.vertex.certify_vertex`, arb Krawczyk on the foot-point system).
"""
from __future__ import annotations

import numpy as np

from ...certify.interval_newton import (UNIT_ROUNDOFF, float_contraction_bound, float_inverse, float_krawczyk_test,
                                        float_residual_bound, round_up)
from .site_table import SiteTable, gradient_enclosure

__all__ = ["prove_conic_vertices", "vertex_enclosures"]

#: half-widths of the tried boxes, relative to 1 + |x| + |y| + r (below the verifier's vertex tolerance)
RHOS = (2e-11, 1e-12, 4e-11)
NEWTON = 4


def prove_conic_vertices(geoms, triples, X, scale, table=None):
    """For float vertices X[m] of the triples (i, j, k) of convex sites: per row, None (not
    proved here) or (x, y, h, r_lo, r_hi): a unique zero of F in the square of centre (x, y) and
    half-width h, with radius in [r_lo, r_hi].  ``table``: a :class:`SiteTable` of ``geoms``
    to reuse (its per-ellipse frame errors are computed once), else one is built."""
    T = np.asarray(triples, int).reshape(-1, 3)
    X = np.asarray(X, float).reshape(-1, 2).copy()
    out = [None] * len(T)
    if not len(T):
        return out
    if table is None:
        table = SiteTable(geoms, scale)
    ok_sites = table.convex[T].all(1)
    idx = np.nonzero(ok_sites)[0]
    if not len(idx):
        return out
    I, J, K = T[idx, 0], T[idx, 1], T[idx, 2]
    C = X[idx]
    n = len(idx)
    # float Newton on F (a better centre; nothing is assumed of it)
    for _ in range(NEWTON):
        V = table.evaluate(np.concatenate([C, C, C]), np.concatenate([I, J, K]))
        Gi, Gj, Gk = (_unit(C, V.part(a * n, (a + 1) * n)) for a in range(3))
        f1, f2 = V.d[:n] - V.d[n:2 * n], V.d[:n] - V.d[2 * n:]
        J11, J12 = (Gi - Gj).T
        J21, J22 = (Gi - Gk).T
        det = J11 * J22 - J12 * J21
        with np.errstate(divide="ignore", invalid="ignore"):
            dx = (J22 * f1 - J12 * f2) / det
            dy = (-J21 * f1 + J11 * f2) / det
        good = np.isfinite(dx) & np.isfinite(dy) & (np.hypot(dx, dy) < 1e-3 * (1 + np.abs(C).sum(1)))
        C = C - np.where(good[:, None], np.column_stack([dx, dy]), 0.0)
    todo = np.arange(n)
    for rel in RHOS:
        if not len(todo):
            break
        c = C[todo]
        m = len(todo)
        i_, j_, k_ = I[todo], J[todo], K[todo]
        V = table.evaluate(np.concatenate([c, c, c]), np.concatenate([i_, j_, k_]))
        Vi = V.part(0, m)
        r0 = Vi.d
        rho = rel * (1 + np.abs(c).sum(1) + np.where(np.isfinite(r0), r0, 0.0))
        A, F_rad, J_rad, valid, Rd = _enclosures(c, V, m, rho, scale)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            Y, invertible = float_inverse(A)                 # any float matrix will do (Krawczyk)
            b = float_residual_bound(Y, np.zeros_like(F_rad), F_rad)
            won, _ = float_krawczyk_test(b, float_contraction_bound(Y, A, J_rad), np.column_stack([rho, rho]))
        proved = valid & invertible & won
        for t in np.nonzero(proved)[0]:
            r_lo = max(float(Vi.lo[t]) - float(Rd[t]), 0.0)
            r_hi = float(Vi.hi[t]) + float(Rd[t])
            out[int(idx[todo[t]])] = (float(c[t, 0]), float(c[t, 1]), float(rho[t]), r_lo, r_hi)
        todo = todo[~proved]
    return out


def vertex_enclosures(table, c, triples, rho, scale):
    """The enclosures handed to the kernel's Krawczyk test on the squares c + [−ρ, ρ]² (module
    docstring) for the rows (c, (i, j, k), ρ): (A, F_rad, J_rad, valid) with A the float
    Jacobian at c, |F(c)| ≤ F_rad and |J(q) − A| ≤ J_rad entrywise for every q of the square,
    where ``valid`` (the gradient enclosures hold on the square's circumscribed disc)."""
    c = np.asarray(c, float).reshape(-1, 2)
    T = np.asarray(triples, int).reshape(-1, 3)
    m = len(c)
    V = table.evaluate(np.concatenate([c, c, c]), np.concatenate([T[:, 0], T[:, 1], T[:, 2]]))
    A, F_rad, J_rad, valid, _ = _enclosures(c, V, m, np.asarray(rho, float).reshape(-1), scale)
    return A, F_rad, J_rad, valid


def _enclosures(c, V, m, rho, scale):
    """(A, F_rad, J_rad, valid, Rd) from the table's values V at the rows (c, i), (c, j), (c, k)."""
    Vi, Vj, Vk = V.part(0, m), V.part(m, 2 * m), V.part(2 * m, 3 * m)
    Rd = rho * np.sqrt(2.0) * (1 + 1e-12)
    Gi, si, vi = gradient_enclosure(c, Vi, Rd, scale)
    Gj, sj, vj = gradient_enclosure(c, Vj, Rd, scale)
    Gk, sk, vk = gradient_enclosure(c, Vk, Rd, scale)
    # F(c) enclosed by the distance bounds: |F_b(c)| ≤ Fa_b (one rounded subtraction each)
    F1a = np.maximum(np.abs(Vi.lo - Vj.hi), np.abs(Vi.hi - Vj.lo))
    F2a = np.maximum(np.abs(Vi.lo - Vk.hi), np.abs(Vi.hi - Vk.lo))
    A = np.stack([Gi - Gj, Gi - Gk], axis=1)            # (m, 2, 2) float Jacobian at c
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        F_rad = round_up(np.column_stack([F1a, F2a]))
        # row b of every J(q), q ∈ B, is within E_b of the exact G_i − G_j (2-norm), so
        # each of its entries is; the float subtraction adds u·|A| (Higham §2.2)
        E = np.column_stack([si + sj, si + sk])
        J_rad = round_up(E[:, :, None] + 2 * UNIT_ROUNDOFF * np.abs(A))
    return A, F_rad, J_rad, vi & vj & vk, Rd


def _unit(C, V):
    with np.errstate(divide="ignore", invalid="ignore"):
        return (C - V.F) / V.d[:, None]
