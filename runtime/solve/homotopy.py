"""Parameter homotopy for the triple offset system (far-away and badly scaled vertices).

Role: the last numeric route, used when msolve is not installed and both null spaces refuse
(:mod:`runtime.solve.macaulay`, :mod:`runtime.solve.toric`); the toric null space now finds the
far vertices that motivated it, in 0.1–0.4 s instead of 1–10 s here.

Why: the Macaulay null-space solver (:mod:`runtime.solve.macaulay`) reads the number of finite
solutions off a *degree gap* in a fixed chart (configuration scaled into the unit disc).
Generalised Voronoi vertices of hyperbolas and parabolas can lie 10³–10⁶ times farther out than
the sites; in that chart they are numerically indistinguishable from the solutions at infinity,
the gap disappears and the solver refuses (measured: 25 of 80 random configurations, and the
validation cases ``hyperbolas_b`` and ``parabolas_b``).

What: a coefficient-parameter homotopy (Morgan–Sommese) inside the family of *true* offsets.
Each conic slot i is parametrised by its canonical-family parameters q_i (ellipse/hyperbola
family x² + c·y² + e: (c, e); parabola y² − 2px: p; circle: rho) and its rigid motion
(angle θ_i, translation t_i); its offset is o_family(U, V, R; q_i) with
(U, V) = Rot(θ_i)·((x, y) − t_i).  Complex rotations keep U² + V² = |x − t_i|², so every point
of the complexified parameter space is the offset of a (complex) conic of the same family: the
family is irreducible and its generic number of isolated solutions is the generic count N of
the generic count passed in by the caller (:data:`runtime.solve.configurations.CONFIG_TABLE`).

1. *Start system*: a random real configuration of the same families well inside the unit disc,
   solved by the null-space route (it must give exactly N distinct refined solutions; cached per
   family triple).
2. Two straight segments in parameter space, start → random complex parameters → target (the
   target in its working frame: C1's axes, scaled into the unit disc).  A generic complex path
   avoids the discriminant (real codimension 2) with probability one, so the N paths are smooth
   for t < 1 and their endpoints contain every isolated nonsingular finite target solution.
3. Paths are tracked in *circle-space* coordinates: the circle of centre (x, y) and squared
   radius R is A(X² + Y²) − 2xX − 2yY + T = 0, a point [A : x̂ : ŷ : T̂] of P³ with x = x̂/A,
   y = ŷ/A, T̂/A = x² + y² − R; the offsets become polynomials of degree 6 / 5 / 2 (ellipse and
   hyperbola / parabola / circle family) in (x, y, T).  A circle 10⁶ times larger than the sites
   is close to a line (A → 0), an ordinary point of P³.  (Measured first: the weighted projective
   closure of (x, y, R) has a whole curve of common solutions at infinity, W = 0, x² + y² = R,
   which far-away paths approach and stall on.)  Random affine chart a·Z = 1; vectorised RK4
   predictor on the Davidenko equation, Newton corrector, per-path step control from the first
   correction; a step is accepted only when the corrector contracts quickly; endpoints that
   coincide (a path jump) are re-tracked with smaller steps and a stricter corrector bound.
4. Endpoints with A ≠ 0 are mapped back, Newton-refined on the exact-family offsets in world
   coordinates (:func:`runtime.solve.newton.newton_refine`) and checked (residual, distinctness).

Nothing here is trusted blindly: the solutions go through the same certification as the
null-space ones (Krawczyk per solution, completeness only when N distinct simple solutions are
proven, :mod:`runtime.certify.complete`).  If some paths diverge (a non-generic target with
solutions at infinity, e.g. conics sharing an axis of symmetry) the finite endpoints are still
returned but fewer than N, so completeness is not claimed.

Length: one algorithm, a certified-step parameter homotopy (start system, path tracking,
end games), whose steps share the tracker state.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np

from ..artefacts import load_offset
from ..algebra.polyalg import CanonicalOffset, WorkingFrame
from ..result import LocatorError

#: step-size control (t ∈ [0, 1] on each segment)
H_START = 0.02
H_MAX = 0.1
H_MIN = 1e-9
#: Newton corrector: accepted when the first correction is below BETA (relative) and the
#: corrections contract by at least CONTRACT; converged when below CORR_TOL
BETA = 1e-3
CONTRACT = 0.25
CORR_TOL = 1e-8
#: a correction this small that stops contracting is at the rounding level: converged
STALL_TOL = 1e-6
MAX_CORR = 4
#: endpoints with |A| / max|Z| below this are taken to be at infinity
INF_TOL = 1e-10
#: maximum number of predictor-corrector steps per segment (a safety net, not a target)
MAX_STEPS = 4000


# =========================================================================== family polynomials

@lru_cache(maxsize=8)
def _family(family: str):
    """The family offset in *circle-space* coordinates: o(u, v, u² + v² − T; q) as a polynomial in
    (u, v, T; q), T = u² + v² − R the power of the canonical origin with respect to the circle.
    Returns (exponents (T, 3 + m), coefficients (T,), parameter names, total degree in u, v, T)."""
    from fractions import Fraction
    from math import comb

    off = load_offset(family)
    acc: dict[tuple, Fraction] = {}
    for e, c in off.terms:
        i, j, k, rest = e[0], e[1], e[2], tuple(e[3:])
        # (u² + v² − T)^k = Σ k!/(a! b! g!) u^2a v^2b (−T)^g
        for a_ in range(k + 1):
            for b_ in range(k - a_ + 1):
                g = k - a_ - b_
                m = comb(k, a_) * comb(k - a_, b_) * (-1) ** g
                key = (i + 2 * a_, j + 2 * b_, g) + rest
                acc[key] = acc.get(key, 0) + Fraction(c) * m
    keys = sorted(k for k, v in acc.items() if v != 0)
    E = np.array(keys, dtype=np.int64)
    C = np.array([float(acc[k]) for k in keys])
    C = C / np.abs(C).max()
    d = int((E[:, 0] + E[:, 1] + E[:, 2]).max())
    return E, C, tuple(off.parameters), d


def _pow(z, d):
    out = np.empty((d + 1,) + z.shape, dtype=complex)
    out[0] = 1
    for i in range(1, d + 1):
        out[i] = out[i - 1] * z
    return out


def _eval_family(family: str, U, V, T, A, Q, need_q: bool = True):
    """Value and partial derivatives (U, V, T, A-explicit, q_1..q_m) of the homogenised family
    offset Σ c·U^i V^j T^k A^(d−i−j−k) q^a at arrays of points (n,); Q has shape (n, m)."""
    E, C, names, d = _family(family)
    vars_ = [U, V, T, A] + [Q[:, l] for l in range(Q.shape[1])]
    ex = np.concatenate([E[:, :3], (d - E[:, 0] - E[:, 1] - E[:, 2])[:, None], E[:, 3:]], axis=1)
    P = [_pow(v, int(ex[:, k].max())) for k, v in enumerate(vars_)]
    facs = [P[k][ex[:, k]] for k in range(len(vars_))]          # each (T, n)
    mono = np.ones_like(facs[0])
    for f in facs:
        mono = mono * f
    val = C @ mono
    grads = []
    for k in range(len(vars_) if need_q else 4):
        e = ex[:, k]
        if e.max() == 0:
            grads.append(np.zeros_like(val))
            continue
        g = P[k][np.maximum(e - 1, 0)] * e[:, None]
        for kk, f in enumerate(facs):
            if kk != k:
                g = g * f
        grads.append(C @ g)
    return val, grads


# =========================================================================== parameters

def _family_params(off: CanonicalOffset) -> list[float]:
    p = off.params
    if off.family == "ellipse":
        return [float(p["c"]), float(p["e"])]
    if off.family == "parabola":
        return [float(p["p"])]
    return [float(p["rho"])]


def _scaled_params(family: str, q: list[float], L: float) -> list[float]:
    """Family parameters after the similarity (u, v) -> (u, v)/L."""
    if family == "ellipse":
        return [q[0], q[1] / L ** 2]
    return [q[0] / L]


def slot_parameters(off: CanonicalOffset, wf: WorkingFrame) -> np.ndarray:
    """Parameter vector (θ, tx, ty, q...) of a conic in the working frame ``wf``."""
    th = math.atan2(float(off.sin), float(off.cos)) - math.atan2(wf.sin, wf.cos)
    tx, ty = wf.to_work(float(off.tx), float(off.ty))
    return np.array([th, tx, ty] + _scaled_params(off.family, _family_params(off), wf.L), dtype=complex)


# =========================================================================== system

@dataclass
class _System:
    """The triple system in homogeneous circle-space coordinates Z = (A, X, Y, T) of P³ (the
    circle A(x² + y²) − 2Xx − 2Yy + T = 0; centre (X/A, Y/A), R = (X² + Y² − A·T)/A²) on the
    affine chart chart·Z = 1.  Far-away circles tend to lines (A → 0), regular points of P³."""

    families: tuple[str, str, str]
    chart: np.ndarray                       # (4,) complex

    def eval(self, Z, P, need_dP: bool = True):
        """F (n, 4), Jacobian in Z (n, 4, 4) and ∂F/∂P per slot (list of (n, 3 + m)) at points Z
        (n, 4) with per-path parameters P = list of (n, 3 + m) arrays (θ, tx, ty, q...)."""
        A, X, Y, T = Z.T
        n = len(Z)
        F = np.empty((n, 4), dtype=complex)
        J = np.zeros((n, 4, 4), dtype=complex)
        dP = []
        for i, fam in enumerate(self.families):
            th, tx, ty = P[i][:, 0], P[i][:, 1], P[i][:, 2]
            c, s = np.cos(th), np.sin(th)
            a_, b_ = X - tx * A, Y - ty * A
            U = c * a_ + s * b_
            V = -s * a_ + c * b_
            Ti = T - 2 * (X * tx + Y * ty) + (tx * tx + ty * ty) * A
            val, g = _eval_family(fam, U, V, Ti, A, P[i][:, 3:], need_q=need_dP)
            oU, oV, oT, oA = g[:4]
            F[:, i] = val
            J[:, i, 0] = oA + oU * (-c * tx - s * ty) + oV * (s * tx - c * ty) + oT * (tx * tx + ty * ty)
            J[:, i, 1] = oU * c - oV * s - 2 * oT * tx
            J[:, i, 2] = oU * s + oV * c - 2 * oT * ty
            J[:, i, 3] = oT
            if not need_dP:
                continue
            d = np.empty((n, P[i].shape[1]), dtype=complex)
            d[:, 0] = oU * V - oV * U
            d[:, 1] = -oU * c * A + oV * s * A + oT * (-2 * X + 2 * tx * A)
            d[:, 2] = -oU * s * A - oV * c * A + oT * (-2 * Y + 2 * ty * A)
            for l, gq in enumerate(g[4:]):
                d[:, 3 + l] = gq
            dP.append(d)
        F[:, 3] = Z @ self.chart - 1
        J[:, 3, :] = self.chart
        return F, J, dP


def _norm(Z):
    """Scale of a point of P³ on the chart: max |Z_k|."""
    return np.max(np.abs(Z), axis=1)


def _err(D, Z):
    """Relative size of a correction D at points Z."""
    return np.max(np.abs(D), axis=1) / np.maximum(_norm(Z), 1e-300)


def _solve(J, r):
    try:
        return np.linalg.solve(J, r[..., None])[..., 0]
    except np.linalg.LinAlgError:
        out = np.empty_like(r)
        for k in range(len(r)):
            out[k] = np.linalg.lstsq(J[k], r[k], rcond=None)[0]
        return out


@dataclass
class TrackStats:
    steps: int = 0
    rejected: int = 0
    failed: int = 0
    evals: int = 0
    seconds: float = 0.0


def track(system: _System, Z0: np.ndarray, P0: list[np.ndarray], P1: list[np.ndarray],
          h_max: float = H_MAX, stats: TrackStats | None = None, beta: float = BETA):
    """Track the solutions Z0 of the system at parameters P0 (one vector per slot) along the
    straight segment to P1.  Returns (Z at t = 1 (n, 4), ok (n,) bool, t reached (n,))."""
    st = stats if stats is not None else TrackStats()
    t_start = time.perf_counter()
    n = len(Z0)
    Z = np.array(Z0, dtype=complex)
    t = np.zeros(n)
    h = np.full(n, min(H_START, h_max))
    active = np.ones(n, dtype=bool)
    ok = np.zeros(n, dtype=bool)
    dPdt = [p1 - p0 for p0, p1 in zip(P0, P1)]

    def params(tt):
        return [p0[None, :] + tt[:, None] * dp[None, :] for p0, dp in zip(P0, dPdt)]

    def tangent(Zc, tt):
        F, J, dP = system.eval(Zc, params(tt))
        Ht = np.zeros((len(Zc), 4), dtype=complex)
        for i in range(3):
            Ht[:, i] = dP[i] @ dPdt[i]
        st.evals += 1
        return _solve(J, -Ht)

    for _ in range(MAX_STEPS):
        idx = np.nonzero(active)[0]
        if len(idx) == 0:
            break
        st.steps += 1
        tt, zz = t[idx], Z[idx]
        dt = np.minimum(h[idx], 1.0 - tt)
        # RK4 predictor
        k1 = tangent(zz, tt)
        k2 = tangent(zz + 0.5 * dt[:, None] * k1, tt + 0.5 * dt)
        k3 = tangent(zz + 0.5 * dt[:, None] * k2, tt + 0.5 * dt)
        k4 = tangent(zz + dt[:, None] * k3, tt + dt)
        zp = zz + (dt[:, None] / 6.0) * (k1 + 2 * k2 + 2 * k3 + k4)
        t1 = tt + dt
        zp, accept, e0 = _correct(system, zp, params(t1), beta, st)
        a_idx, r_idx = idx[accept], idx[~accept]
        st.rejected += len(r_idx)
        Z[a_idx] = zp[accept]
        t[a_idx] = t1[accept]
        # step size from the size of the first correction (RK4: error ~ h^5)
        with np.errstate(divide="ignore", invalid="ignore"):
            fac = 0.8 * (beta / np.maximum(e0, 1e-300)) ** 0.2
        fac = np.where(np.isfinite(fac), fac, 0.5)
        h[a_idx] = np.minimum(h[a_idx] * np.clip(fac[accept], 0.5, 2.0), h_max)
        h[r_idx] = h[r_idx] * np.clip(fac[~accept], 0.1, 0.5)
        done = a_idx[t[a_idx] >= 1.0]
        ok[done] = True
        active[done] = False
        dead = r_idx[h[r_idx] < H_MIN]
        active[dead] = False
    st.failed += int((~ok).sum())
    st.seconds += time.perf_counter() - t_start
    return Z, ok, t


def _dup_mask(Z, tol: float = 1e-6):
    """True for endpoints that coincide (relative, chart coordinates) with another endpoint."""
    if len(Z) < 2:
        return np.zeros(len(Z), dtype=bool)
    sc = np.maximum(_norm(Z), 1e-300)
    Zs = Z / sc[:, None]
    D = np.max(np.abs(Zs[:, None, :] - Zs[None, :, :]), axis=2)
    np.fill_diagonal(D, np.inf)
    return (D < tol).any(axis=1)


def _correct(system: _System, zp, Pt, beta: float, st: TrackStats):
    """Newton corrector of a predicted batch ``zp`` at parameters ``Pt``: (corrected points, accepted
    (bool), size of the first correction).  A point is accepted when its first correction is below
    ``beta`` (relative), its corrections then contract by :data:`CONTRACT` (or stall at the rounding
    level, below :data:`STALL_TOL`), and one falls below :data:`CORR_TOL` within :data:`MAX_CORR`
    steps: the predicted point was in Newton's region of quadratic convergence of the path (the
    predictor-corrector safeguard of path tracking; Allgower and Georg 1990, ch. 3)."""
    accept = np.ones(len(zp), dtype=bool)
    conv = np.zeros(len(zp), dtype=bool)
    prev = None
    e0 = np.full(len(zp), np.inf)
    for it in range(MAX_CORR):
        F, J, _ = system.eval(zp, Pt, need_dP=False)
        st.evals += 1
        D = _solve(J, -F)
        e = _err(D, zp)
        e = np.where(np.isfinite(e), e, np.inf)
        if it == 0:
            e0 = e
            accept &= e < beta
        else:
            stalled = (e < STALL_TOL) & (prev < STALL_TOL)
            conv |= accept & stalled
            accept &= (e <= CONTRACT * prev) | (e < CORR_TOL) | conv
        zp = np.where((accept & ~conv)[:, None], zp + D, zp)
        conv |= accept & (e < CORR_TOL)
        prev = e
        if np.all(conv | ~accept):
            break
    return zp, accept & conv, e0


def track_segment(system: _System, Z0, P0, P1, h_max: float = H_MAX, stats: TrackStats | None = None,
                  rounds: int = 2, final: bool = False):
    """:func:`track` with repair: paths that failed or ended on the same point as another path
    (a path jump) are re-tracked with 3× smaller maximal steps and a 10× stricter first-correction
    bound, up to ``rounds`` times (close but distinct endpoints of the final segment stay; the
    world-coordinate refinement separates or merges them).  On the
    final segment, paths stalling at t > 0.99 are not re-tracked (endpoint at infinity or
    singular endpoint of a non-generic target)."""
    Z, ok, t = track(system, Z0, P0, P1, h_max=h_max, stats=stats)
    hm, beta = h_max, BETA
    for _ in range(rounds):
        bad = _dup_mask(Z) | ~ok
        if final:
            bad &= ~(~ok & (t > 0.99))
        if not bad.any():
            break
        hm, beta = hm / 3, beta / 10
        Zb, okb, tb = track(system, Z0[bad], P0, P1, h_max=hm, stats=stats, beta=beta)
        Z[bad], ok[bad], t[bad] = Zb, okb, tb
    return Z, ok, t


# =========================================================================== start systems

@dataclass
class StartSystem:
    families: tuple[str, str, str]
    params: list[np.ndarray]                # per slot (θ, tx, ty, q...), complex
    points: np.ndarray                      # (N, 3) complex (x, y, R) in the start coordinates
    seed: int
    seconds: float


def _random_conic(family: str, rng):
    from ..sites.conic import Conic
    from fractions import Fraction

    def fr(x):
        return Fraction(x).limit_denominator(1000)

    cx, cy = (fr(v) for v in rng.uniform(-0.5, 0.5, 2))
    th = float(rng.uniform(0, math.pi))
    # Pythagorean rotation close to th (exact rational cos/sin)
    m = math.tan(th / 2)
    tq = fr(m)
    cs, sn = (1 - tq * tq) / (1 + tq * tq), 2 * tq / (1 + tq * tq)
    if family == "ellipse":
        A, B = fr(rng.uniform(0.25, 0.5)), fr(rng.uniform(0.1, 0.22))
        if rng.uniform() < 0.5:
            return Conic.ellipse((cx, cy), (A, B), rotation=(cs, sn))
        return Conic.hyperbola((cx, cy), (A, B), rotation=(cs, sn))
    if family == "parabola":
        return Conic.parabola((cx, cy), fr(rng.uniform(0.1, 0.4)), rotation=(cs, sn))
    return Conic.circle((cx, cy), radius=fr(rng.uniform(0.1, 0.3)))


@lru_cache(maxsize=16)
def start_system(families: tuple[str, str, str], nullspace_solve, expected: int | None) -> StartSystem:
    """A random real configuration of these families (per slot) with all ``expected`` (the generic
    number N) solutions found by ``nullspace_solve(c1, c2, c3)`` (the null-space route of
    :mod:`runtime.solve.generalised`, passed in by the caller; a few seeds are tried; deterministic)."""
    if expected is None:
        raise LocatorError(f"no generic solution count for {families}; homotopy needs one")
    errors = []
    t0 = time.perf_counter()
    for seed in range(1, 9):
        rng = np.random.default_rng(1000 + seed)
        conics = [_random_conic(f, rng) for f in families]
        try:
            sol = nullspace_solve(*conics)
        except (LocatorError, ValueError) as exc:
            errors.append(f"seed {seed}: {exc}"[:160])
            continue
        if len(sol.points) != expected or not np.all(sol.residuals < 1e-11):
            errors.append(f"seed {seed}: {len(sol.points)} solutions")
            continue
        wf = WorkingFrame(1.0, 0.0, 0.0, 0.0, 1.0)
        offs = [CanonicalOffset(c) for c in conics]
        params = [slot_parameters(o, wf) for o in offs]
        return StartSystem(families, params, sol.points.astype(complex), seed, time.perf_counter() - t0)
    raise LocatorError(f"no start system for {families}: " + "; ".join(errors))


# =========================================================================== driver

@dataclass
class HomotopyInfo:
    n_paths: int
    n_finite: int
    n_infinite: int
    n_failed: int
    start_seed: int
    retries: int
    stats: dict = field(default_factory=dict)
    timings: dict = field(default_factory=dict)


def _to_chart(pts, chart):
    """Affine (x, y, R) -> circle-space (A, X, Y, T) = λ(1, x, y, x² + y² − R) on the chart."""
    H = np.stack([np.ones(len(pts), dtype=complex), pts[:, 0], pts[:, 1],
                  pts[:, 0] ** 2 + pts[:, 1] ** 2 - pts[:, 2]], axis=1)
    return H / (H @ chart)[:, None]


def homotopy_solve(offs: list[CanonicalOffset], wf: WorkingFrame, *, nullspace_solve, expected: int | None,
                   seed: int = 3, max_retries: int = 2):
    """All finite solutions of the triple system of ``offs`` by parameter homotopy.

    ``nullspace_solve(c1, c2, c3)`` solves the start system (the caller's null-space route) and
    ``expected`` is the generic number of solutions of the family triple.

    Returns (points (M, 3) complex in *world* coordinates, HomotopyInfo); M ≤ N, with M < N
    when some paths end at infinity or fail (then completeness cannot be claimed)."""
    fams = tuple(o.family for o in offs)
    tm: dict[str, float] = {}
    t0 = time.perf_counter()
    start = start_system(fams, nullspace_solve, expected)
    tm["start_system"] = time.perf_counter() - t0
    target = [slot_parameters(o, wf) for o in offs]
    rng = np.random.default_rng(seed)
    stats = TrackStats()
    Z1 = None
    for attempt in range(max_retries + 1):
        chart = rng.standard_normal(4) + 1j * rng.standard_normal(4)
        chart /= np.linalg.norm(chart)
        system = _System(fams, chart)
        mid = [(p0 + p1) / 2 + (rng.standard_normal(len(p0)) + 1j * rng.standard_normal(len(p0))) * 0.5
               * np.maximum(1.0, np.abs(p1))
               for p0, p1 in zip(start.params, target)]
        Z0 = _to_chart(start.points, chart)
        Z1, ok1, _ = track_segment(system, Z0, start.params, mid, stats=stats)
        if ok1.all() and not _dup_mask(Z1).any():
            break                        # the generic mid system has its N distinct solutions
    else:
        raise LocatorError(f"homotopy: could not track the start system of {fams} to a generic complex "
                           f"system in {max_retries + 1} attempts")
    Z2, ok2, treached = track_segment(system, Z1, mid, target, stats=stats, final=True)
    # endpoints: paths that reached t = 1, and paths that stalled close to it (an endpoint at
    # infinity or a singular endpoint makes the steps collapse), polished by Newton at t = 1
    near = ~ok2 & (treached > 0.99)
    Ze = _polish(system, Z2[ok2 | near], target)
    Aw = Ze[:, 0]
    scale = _norm(Ze)
    finite = np.isfinite(scale) & (np.abs(Aw) > INF_TOL * scale)
    Zf = Ze[finite]
    xw, yw = Zf[:, 1] / Zf[:, 0], Zf[:, 2] / Zf[:, 0]
    Rw = xw * xw + yw * yw - Zf[:, 3] / Zf[:, 0]
    x, y = wf.to_world(xw, yw)
    pts = np.stack([x, y, Rw * wf.L ** 2], axis=1)
    tm["track"] = stats.seconds
    info = HomotopyInfo(len(start.points), len(pts), int((~finite).sum()), int((~ok2).sum()), start.seed,
                        attempt, stats={"steps": stats.steps, "rejected": stats.rejected, "evals": stats.evals},
                        timings=tm)
    return pts, info


def _polish(system: _System, Z, P, iters: int = 6):
    """Newton steps at fixed parameters (one vector per slot) on all rows of Z."""
    Pn = [np.repeat(p[None, :], len(Z), axis=0) for p in P]
    Z = Z.copy()
    for _ in range(iters):
        F, J, _ = system.eval(Z, Pn, need_dP=False)
        D = _solve(J, -F)
        D = np.where(np.isfinite(D), D, 0)
        Z = Z + D
    return Z
