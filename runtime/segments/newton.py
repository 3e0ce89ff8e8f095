"""Newton's method on many contact systems at once, before their proofs (thesis §3.3.3).

A round of the construction (:mod:`runtime.segments.construction`) meets thousands of candidate
vertices.  Their 3 × 3 contact systems (:func:`runtime.segments.vertices.contact_equations`) are
coded as arrays — a kind per equation (point, line, normal line, arc) and its parameters — and
Newton's iteration runs on all of them together with numpy, each 3 × 3 step by cofactors; a row
whose Jacobian is numerically singular or whose iterate leaves the floats is left undecided.
The limits are then proved together by the float Krawczyk test of
:func:`runtime.segments.vertex_batch.prove_zeros_batch` (every rounding bounded), and the rows it
leaves one by one by :func:`runtime.segments.vertices.prove_zero` (the arb Krawczyk test), with the
same cache as :func:`runtime.segments.vertices.prove_vertex`.  A row
singular to float precision goes to that proof from its seed: a far vertex (radius 10⁸ over sites
10³ apart) is a regular zero whose rows agree to 10⁻¹¹, which the proof's Newton steps at 128 bits
resolve.

Public API: :func:`prove_vertices`.
"""
from __future__ import annotations

import numpy as np

from .elementary import ELLIPSE, ElementarySites
from .vertex_batch import code_point_segment_rows, code_systems, prove_zeros_batch
from .vertices import VertexSolution, arc_centre_vertex, common_point, contact_equations, prove_vertex, prove_zero

__all__ = ["prove_vertices"]


def prove_vertices(E: ElementarySites, items, cache: dict | None = None) -> list:
    """:func:`prove_vertex` for many (triple, seed) items: the float Newton iterations of all of
    them run together (numpy, 3 × 3 systems inverted by cofactors), then the limits are proved
    by the float Krawczyk test of :func:`runtime.segments.vertex_batch.prove_zeros_batch` and
    the rows it leaves by the arb test of :func:`prove_vertex` (cached the same way).  The
    triples of point sites and segments are coded on arrays
    (:func:`runtime.segments.vertex_batch.code_point_segment_rows`), the others one by one
    (:func:`runtime.segments.vertices.contact_equations`)."""
    out: list = [None] * len(items)
    if not len(items):
        return out
    T = np.array([t for t, _s in items], dtype=np.int64).reshape(len(items), -1)
    seeds = np.array([[s[0], s[1]] for _t, s in items], dtype=float)
    if T.shape[1] == 3:
        coded, invalid, K_arr, P_arr, S_arr = code_point_segment_rows(E, T, seeds)
    else:
        coded = invalid = np.zeros(len(items), bool)
    for n in np.nonzero(invalid)[0].tolist():
        seed = items[n][1]
        out[n] = VertexSolution("invalid", float(seed[0]), float(seed[1]), 0.0,
                                reason="a segment and both its endpoints")
    rows, systems = [], []           # systems[i]: row i's equations, None where coded on arrays
    for n in np.nonzero(~coded)[0].tolist():
        triple, seed = items[n]
        if common_point(E, triple) is not None or arc_centre_vertex(E, triple) is not None \
                or any(E.kind[t] == ELLIPSE for t in triple):
            # (elliptic pieces: their foot equation has no closed form for the batched Newton)
            out[n] = prove_vertex(E, triple, seed, cache=cache)
            continue
        eqs = contact_equations(E, triple, seed)
        if eqs is None:
            out[n] = VertexSolution("invalid", float(seed[0]), float(seed[1]), 0.0,
                                    reason="a segment and both its endpoints")
            continue
        rows.append(n)
        systems.append(eqs)
    slow = dict(zip(rows, systems))
    rows = sorted(rows + np.nonzero(coded & ~invalid)[0].tolist())        # in the items' order
    if not rows:
        return out
    systems = [slow.get(n) for n in rows]
    m = len(rows)
    K = np.zeros((m, 3), dtype=np.int64)
    Pm = np.zeros((m, 3, 4))
    sides_arr = np.zeros((m, 3), dtype=np.int64)
    r_idx = np.array(rows, dtype=np.int64)
    fast_rows = np.nonzero(coded[r_idx])[0]
    K[fast_rows], Pm[fast_rows] = K_arr[r_idx[fast_rows]], P_arr[r_idx[fast_rows]]
    sides_arr[fast_rows] = S_arr[r_idx[fast_rows]]
    one = np.nonzero(~coded[r_idx])[0]
    if len(one):
        K[one], Pm[one] = code_systems([systems[i] for i in one.tolist()])
        sides_arr[one] = [[d[3] if k in ("line", "arc") else 0 for k, d, _t in systems[i]] for i in one.tolist()]
    Z = np.zeros((m, 3))
    Z[:, :2] = seeds[r_idx]
    Z[:, 2] = _r_guess_many(K, Pm, Z)
    scale = 1.0 + float(np.max(np.abs(E.A)) if len(E.A) else 0.0)
    alive = np.ones(m, dtype=bool)
    failed = np.zeros(m, dtype=bool)
    for _ in range(40):
        idx = np.nonzero(alive)[0]
        if not len(idx):
            break
        F, J = _residuals(K[idx], Pm[idx], Z[idx])
        step, ok = _solve3(J, F)
        failed[idx[~ok]] = True
        alive[idx[~ok]] = False
        Z[idx[ok]] -= step[ok]
        done = ok & (np.max(np.abs(step), axis=1) <= 1e-15 * scale)
        bad = ok & ~np.isfinite(Z[idx]).all(axis=1)
        failed[idx[bad]] = True
        alive[idx[done | bad]] = False
    pending = []
    sides_l = sides_arr.tolist()
    # the cache keys' positions (Z rounded to 10⁻⁹ of the scale), all rows at once
    with np.errstate(invalid="ignore"):
        Zkey = np.round(Z / (1e-9 * scale)) if cache is not None else Z
    Zkey = np.where(np.isfinite(Zkey), Zkey, 0).astype(np.int64).tolist() if cache is not None else None
    for i, n in enumerate(rows):
        triple, seed = items[n]
        if failed[i]:
            # a numerically singular Jacobian in floats: a far vertex of nearly collinear contacts
            # (radius 10⁸ over sites 10³ apart: the rows of the three contacts agree to 10⁻¹¹)
            # is still a regular zero; the arb proof refines the seed by Newton steps at 128 bits
            # before its box (prove_zero), a true singularity stays undecided there
            z0 = np.array([seed[0], seed[1], 0.0])
            if not np.isfinite(z0).all():
                out[n] = VertexSolution("undecided", float(seed[0]), float(seed[1]), 0.0, reason="Newton failed")
                continue
            z0[2] = _r_guess_many(K[i:i + 1], Pm[i:i + 1], z0[None, :2])[0]
            out[n] = prove_zero(E, triple, _equations(E, items[n], systems[i]), z0, scale)
            continue
        key = None
        if cache is not None:
            key = (tuple(triple), tuple(sides_l[i])) + tuple(Zkey[i])
            if key in cache:
                out[n] = cache[key]
                continue
        pending.append((i, n, key))
    # the float Krawczyk test on all pending limits at once; the rows it leaves go to the arb proof
    sel = [i for i, _n, _key in pending]
    fast = prove_zeros_batch(E, K[sel], Pm[sel], Z[sel], T[r_idx[sel]]) if sel else []
    for (i, n, key), sol in zip(pending, fast):
        if key is not None and key in cache:           # an earlier row of this batch, same limit
            out[n] = cache[key]
            continue
        if sol is None:
            sol = prove_zero(E, items[n][0], _equations(E, items[n], systems[i]), Z[i], scale)
        if key is not None:
            cache[key] = sol
        out[n] = sol
    return out


def _equations(E: ElementarySites, item, eqs):
    """The contact equations of ``item`` = (triple, seed) for the arb proof: ``eqs``, or those of
    :func:`runtime.segments.vertices.contact_equations` for a row coded on arrays."""
    return eqs if eqs is not None else contact_equations(E, item[0], item[1])


def _residuals(K, Pm, Z):
    """F (m × 3) and J (m × 3 × 3) of the contact systems coded by kinds K and parameters Pm."""
    x, y, r = Z[:, 0:1], Z[:, 1:2], Z[:, 2:3]
    p0, p1, p2, p3 = Pm[..., 0], Pm[..., 1], Pm[..., 2], Pm[..., 3]
    dx, dy = x - p0, y - p1
    R = p2 + p3 * r                                     # arcs: ρ + σ r
    F = np.select([K == 0, K == 1, K == 2, K == 3],
                  [dx * dx + dy * dy - r * r, p0 * x + p1 * y + p2 - p3 * r,
                   p0 * (x - p2) + p1 * (y - p3), dx * dx + dy * dy - R * R])
    J = np.empty(K.shape + (3,))
    J[..., 0] = np.select([K == 0, K == 1, K == 2, K == 3], [2 * dx, p0, p0, 2 * dx])
    J[..., 1] = np.select([K == 0, K == 1, K == 2, K == 3], [2 * dy, p1, p1, 2 * dy])
    J[..., 2] = np.select([K == 0, K == 1, K == 2, K == 3], [-2 * r + 0 * p0, -p3, 0 * p0, -2 * p3 * R])
    return F, J


def _solve3(J, F):
    """J⁻¹F row by row by cofactors; ok = False where J is (numerically) singular.  The rows
    are scaled to a largest entry of 1 first (a point's row grows with the radius, a line's
    does not: a far vertex of nearly parallel lines is not singular)."""
    w = np.abs(J).max(axis=2, keepdims=True) + 1e-300
    J, F = J / w, F / w[..., 0]
    a, b, c = J[:, 0], J[:, 1], J[:, 2]
    cof0 = np.cross(b, c)
    det = np.einsum("ij,ij->i", a, cof0)
    cof1 = np.cross(c, a)
    cof2 = np.cross(a, b)
    norm = np.abs(J).reshape(len(J), -1).max(axis=1) + 1e-300
    ok = np.abs(det) > 1e-14 * norm ** 3
    with np.errstate(divide="ignore", invalid="ignore"):
        inv_t = np.stack([cof0, cof1, cof2], axis=1) / np.where(ok, det, 1.0)[:, None, None]
        step = np.einsum("kji,kj->ki", inv_t, F)
    return step, ok


def _r_guess_many(K, Pm, Z):
    x, y = Z[:, 0:1], Z[:, 1:2]
    p0, p1, p2, p3 = Pm[..., 0], Pm[..., 1], Pm[..., 2], Pm[..., 3]
    with np.errstate(divide="ignore", invalid="ignore"):
        guess = np.select([K == 0, K == 1, K == 3],
                          [np.hypot(x - p0, y - p1), np.abs(p0 * x + p1 * y + p2) / np.abs(p3),
                           np.abs(np.hypot(x - p0, y - p1) - p2)], np.nan)
    g = np.nanmean(guess, axis=1)
    return np.where(np.isfinite(g), g, 1.0)
