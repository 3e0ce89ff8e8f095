"""Newton refinement and deflation of generalised Voronoi vertices (thesis §5.5, last step).

The roots read off the eigenvectors of a null-space solver are approximations; Newton's method on
the three generalised offsets o1 = o2 = o3 = 0 (thesis §4.4) in (x, y, R) brings them to full
accuracy, with the relative residual |o_i| / Σ|c_m·m| (a backward error) and the condition number
of the row-scaled Jacobian as the measures of each refined point (Higham 2002, §7 and §25.3).
Starts that converge to an already found root, or do not converge (eigenvalue clusters), are
restarted with Newton *deflated* at the found roots (Brown and Gearhart 1971: the step
δ/(1 + Σ_k ℓ(δ)/ℓ(z − z_k)), ℓ a random linear form, keeps the iterate away from every z_k), so
that the list holds distinct roots.  Nothing here proves anything: the certification stage
(:mod:`runtime.certify.complete`) proves the refined list.

Public API: :func:`newton_refine`, :func:`newton_refine_mp`, :func:`offset_values`,
:func:`distinct_mask`, :func:`complete_by_deflation`, :func:`deflated_real_newton`,
:data:`RESIDUAL_TOL`, :data:`MAX_DEFLATED`.
"""
from __future__ import annotations

import numpy as np

from ..algebra.polyalg import CanonicalOffset
from ..result import LocatorError

__all__ = ["newton_refine", "newton_refine_mp", "offset_values", "distinct_mask", "complete_by_deflation",
           "deflated_real_newton", "RESIDUAL_TOL", "MAX_DEFLATED"]

#: residual (relative backward error) accepted for a refined solution
RESIDUAL_TOL = 1e-11
#: at most this many starts are restarted by deflated Newton (:func:`complete_by_deflation`)
MAX_DEFLATED = 6


def newton_refine(offs: list[CanonicalOffset], Z: np.ndarray, iters: int = 8, real: bool = False,
                  scale: float = 1.0, forward_error: bool = False):
    """Vectorised Newton on (o1, o2, o3)(x, y, R) = 0 in world coordinates.

    Returns (refined points, relative residuals (N,), condition numbers (N,)), and with
    ``forward_error`` also forward-error estimates (N,) max_k (|J⁻¹|·ε·Σ|c_m·m|)_k in the scaled
    variables (the rounding error of the values carried through J⁻¹; Higham 2002, §25.3).  The
    relative residual of o_i is |o_i| / Σ|c_m·m| (backward error); the condition number is that of
    the Jacobian with rows scaled to unit norm in the scaled variables (x/L, y/L, R/L²)."""
    Z = np.array(Z, dtype=float if real else complex)
    n = len(Z)
    if n == 0:
        return (Z, np.zeros(0), np.zeros(0)) + ((np.zeros(0),) if forward_error else ())
    D = np.array([scale, scale, scale * scale])
    best = Z.copy()
    best_res = np.full(n, np.inf)
    best_grads = best_absv = None
    for it in range(iters + 1):
        vals, grads, absv = offset_values(offs, Z)
        res = np.max(np.abs(vals) / np.maximum(absv, 1e-300), axis=1)
        better = res < best_res
        best[better] = Z[better]
        best_res[better] = res[better]
        if best_grads is None:
            best_grads = grads.copy()       # Jacobians at ``best`` (only read where best_res < inf)
            best_absv = absv.copy()
        else:
            best_grads[better] = grads[better]
            best_absv[better] = absv[better]
        if it == iters or np.all(res < 4e-16):
            break
        J = grads * D[None, None, :]
        try:
            step = np.linalg.solve(J, -vals[..., None])[..., 0]
        except np.linalg.LinAlgError:
            step = np.stack([np.linalg.lstsq(Ji, -vi, rcond=None)[0] for Ji, vi in zip(J, vals)])
        step = np.where(np.isfinite(step), step, 0)
        Z = Z + step * D[None, :]
    J = best_grads * D[None, None, :]
    Jn = J / np.maximum(np.linalg.norm(J, axis=2, keepdims=True), 1e-300)
    with np.errstate(all="ignore"):
        cond = np.linalg.cond(Jn)
    if not forward_error:
        return best, best_res, cond
    with np.errstate(all="ignore"):
        try:
            Ji = np.linalg.inv(J)
            fe = (np.abs(Ji) @ (np.finfo(float).eps * best_absv)[..., None])[..., 0].max(axis=1)
        except np.linalg.LinAlgError:
            fe = np.zeros(n)
    return best, best_res, cond, np.nan_to_num(fe, nan=0.0, posinf=0.0)


def offset_values(offs, Z):
    """(values (N, 3), gradients (N, 3, 3), Σ|c_m·m| (N, 3)) of the offsets o1, o2, o3 at the
    points Z (N, 3) = (x, y, R) in world coordinates."""
    vals, grads, absv = [], [], []
    for o in offs:
        v, g, a = o.eval_grad(Z[:, 0], Z[:, 1], Z[:, 2])
        vals.append(v)
        grads.append(g)
        absv.append(a)
    return np.stack(vals, axis=1), np.stack(grads, axis=1), np.stack(absv, axis=1)


def newton_refine_mp(offs_mp: list[CanonicalOffset], z, dps: int, iters: int = 20):
    """Newton in mpmath at ``dps`` digits from a real float start; returns (point, relative residual);
    a singular Jacobian stops it where it is (the residual then says it did not converge)."""
    import mpmath
    with mpmath.workdps(dps):
        x = [mpmath.mpf(float(t)) for t in z]
        res = None
        for _ in range(iters):
            F, J, A = [], [], []
            for o in offs_mp:
                v, g, a = o.eval_grad_mp(*x)
                F.append(v)
                J.append(list(g))
                A.append(a)
            res = max(abs(f) / a for f, a in zip(F, A))
            if res < mpmath.mpf(10) ** (-dps + 5):
                break
            try:
                step = mpmath.lu_solve(mpmath.matrix(J), -mpmath.matrix(F))
            except ZeroDivisionError:            # singular Jacobian: Newton stops, not converged
                break
            x = [x[i] + step[i] for i in range(3)]
        return x, res


def distinct_mask(pts, D, tol=1e-8):
    """True for points that do not coincide (scaled max-norm < tol, or with a tolerance per point
    the larger of the two) with an earlier one."""
    Ps = pts / D[None, :]
    keep = np.ones(len(pts), dtype=bool)
    close = np.zeros((len(pts), len(pts)), dtype=bool)
    t = np.broadcast_to(np.asarray(tol, dtype=float), (len(pts),))
    with np.errstate(invalid="ignore"):
        # pairs i > j close in the first coordinate, then the other two on those pairs only
        T = np.maximum(t[:, None], t[None, :])
        i, j = np.nonzero(np.tril(np.abs(Ps[:, None, 0] - Ps[None, :, 0]) < T, -1))
        near = (np.abs(Ps[i, 1:] - Ps[j, 1:]) < T[i, j][:, None]).all(axis=1)
    close[i[near], j[near]] = True
    # only points with a close earlier point can be dropped; decide those in order
    for i in np.nonzero(close.any(axis=1))[0]:
        if np.any(close[i, :i] & keep[:i]):
            keep[i] = False
    return keep


def complete_by_deflation(offs, pts, res, cond, L, iters: int = 40, tol=1e-8, repeated: int = 0):
    """Eigenvalue clusters can send two starts to one root and miss another.  Every start that
    did not converge, or converged to an already found root (closer than ``tol``, scaled max-norm;
    a number or one per point, the larger of two applying), is restarted with Newton deflated at
    the found roots (step δ/(1 + Σ_k ℓ(δ)/ℓ(z − z_k)), ℓ a random linear form).  Raises
    LocatorError when the set of distinct converged roots stays smaller than the count, except
    that up to ``repeated`` rows that repeat a found root (a provisional toric list completed in a
    cluster, :mod:`runtime.solve.toric` step 6) are left as they are, for the certification's
    search at 128 bits."""
    D = np.array([L, L, L * L])
    good = (res < RESIDUAL_TOL) & distinct_mask(pts, D, tol)
    todo = np.nonzero(~good)[0]
    if len(todo) == 0:
        return pts, res, cond, 0
    if len(todo) > MAX_DEFLATED:
        # measured (validation triples + 80 random rigid ones): every attempt with ≤ 5 bad starts
        # was completed, none with ≥ 8, and those failures cost 2.3 s in all
        raise LocatorError(f"{len(todo)} of {len(pts)} generalised vertices did not refine to distinct solutions "
                           "(eigenvalue cluster); too many for deflated restarts")
    rng = np.random.default_rng(11)
    c = (rng.standard_normal(3) + 1j * rng.standard_normal(3)) / D
    pts = pts.copy()
    res = res.copy()
    cond = cond.copy()
    tol = np.broadcast_to(np.asarray(tol, dtype=float), (len(pts),))
    for i in todo:
        found = pts[good]
        t_found = tol[good]
        z = pts[i].astype(complex)
        ok = False
        for _ in range(iters):
            vals, grads, absv = offset_values(offs, z[None, :])
            r = np.max(np.abs(vals[0]) / np.maximum(absv[0], 1e-300))
            if r < RESIDUAL_TOL and np.all(np.max(np.abs((found - z) / D), axis=1) > t_found):
                # a few plain Newton steps to full accuracy; they must not slide back onto a found
                # root (measured: an ill-conditioned found root attracts the polished point, which
                # left a duplicate in the list and one solution missing)
                zz, rr, kk = newton_refine(offs, z[None, :], iters=3, scale=L)
                if np.all(np.max(np.abs((found - zz[0]) / D), axis=1) > t_found):
                    ok = True
                    z, r, k = zz[0], rr[0], kk[0]
                break
            try:
                delta = np.linalg.solve(grads[0], -vals[0])
            except np.linalg.LinAlgError:
                break
            lk = (z[None, :] - found) @ c
            with np.errstate(divide="ignore", invalid="ignore"):
                tau = 1.0 + np.sum((delta @ c) / lk)
                z = z + delta / tau
            if not np.all(np.isfinite(z)):
                break
        if ok:
            pts[i], res[i], cond[i] = z, r, k
            good[i] = True
    if int((~good).sum()) > repeated:
        raise LocatorError(f"{int((~good).sum())} of {len(pts)} generalised vertices could not be refined to "
                           "distinct solutions (eigenvalue cluster); the numeric route is unreliable here")
    return pts, res, cond, len(todo)


def deflated_real_newton(offs, z0, found, L, iters: int = 40):
    """Real Newton on (o1, o2, o3) from z0 deflated at the points ``found`` (step δ/(1 + Σ_k
    ℓ(δ)/ℓ(z − z_k)), ℓ a random linear form); the point if it converges, else None."""
    D = np.array([L, L, L * L])
    c = np.random.default_rng(13).standard_normal(3) / D
    z = np.array(z0, dtype=float)
    for _ in range(iters):
        vals, grads, absv = offset_values(offs, z[None, :])
        r = np.max(np.abs(vals[0]) / np.maximum(absv[0], 1e-300))
        if r < RESIDUAL_TOL and (len(found) == 0 or np.all(np.max(np.abs((found - z) / D), axis=1) > 1e-9)):
            return z
        try:
            delta = np.linalg.solve(grads[0].real, -vals[0].real)
        except np.linalg.LinAlgError:
            return None
        lk = (z[None, :] - found) @ c if len(found) else np.zeros(0)
        with np.errstate(divide="ignore", invalid="ignore"):
            # at a deflated point itself ℓ = 0: the step is infinite and the start gives up below
            tau = 1.0 + (np.sum((delta @ c) / lk) if len(found) else 0.0)
            z = z + delta / tau
        if not np.all(np.isfinite(z)):
            return None
    return None

