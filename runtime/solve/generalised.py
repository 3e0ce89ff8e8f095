"""Generalised Voronoi vertices of three conics: the chain of numeric attempts (thesis §5.3, §5.5).

A *generalised Voronoi vertex* of C1, C2, C3 is a solution (x, y, R) of o1 = o2 = o3 = 0, with
o_i the generalised offset of C_i (thesis §4.4, App. B; R = squared offset distance).  The thesis
reads the solutions off the Schur complement of the Canny–Emiris (sparse resultant) matrix
(§3.3, §5.5); that complement does not exist on true offset coefficients (the offsets are not
generic, bench/results/newton_rank.md), so the solutions come from null spaces instead:

1. offsets composed with the rigid motions and a similarity into a *working frame* (C1's axes,
   configuration cores in the unit disc; :func:`runtime.algebra.polyalg.working_frame`);
2. the weighted-degree Macaulay null space in (x, y, R) (:mod:`runtime.solve.macaulay`: degree
   gap, multiplication maps, eigenvectors), or the toric null space in circle space, where far
   vertices are ordinary points (:mod:`runtime.solve.toric`, :mod:`runtime.solve.toric_roots`);
3. the number of finite solutions checked against the generic count of the type configuration
   (thesis Table 5.1; :mod:`runtime.solve.configurations`, msolve parametrisation degrees);
4. Newton refinement, and deflated restarts for starts lost in eigenvalue clusters
   (:mod:`runtime.solve.newton`).

Honesty rules: a list whose count is not the generic count is refused (solutions far outside the
disc lumped with those at infinity, or a non-generic configuration such as parallel parabola
axes, which this route cannot tell apart); the next attempt is another degree or null space, and
when all refuse, the parameter homotopy of :mod:`runtime.solve.homotopy`, which may return fewer
than the generic count (completeness is then not claimed downstream).  With the exact route
behind (``quick``), a refusal hands the triple to msolve (:mod:`runtime.solve.exact`) early.
Measured: the Newton (Canny–Emiris) polytope support is no smaller than the weighted-degree
support here and 8–19× slower (bench/results/newton_support.md), so the Macaulay support is kept.

Public API: :func:`generalised_vertices`, :class:`TripleSolution`, :class:`AttemptOptions`,
:class:`TripleSystem`, :func:`triple_system`, :func:`nullspace_route`, :func:`homotopy_route`.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass
from functools import partial

import numpy as np

from ..algebra.polyalg import (CanonicalOffset, WorkingFrame, compose_offset, scene_to_site_ratio,
                               working_frame)
from ..result import LocatorError
from .configurations import CONFIG_TABLE, config_entry, modular_count, shared_shape
from .exact import cancel_solve_exact, exact_solved, start_solve_exact
from .homotopy import homotopy_solve
from .macaulay import TOP_DEGREES, SolveInfo, add_timings, solve_nullspace
from .newton import RESIDUAL_TOL, complete_by_deflation, newton_refine
from .toric_roots import TORIC_DISTINCT_TOL, refine_toric_roots, toric_attempt

__all__ = ["generalised_vertices", "TripleSolution", "AttemptOptions", "TripleSystem", "triple_system",
           "nullspace_route", "homotopy_route", "SOLVERS", "TORIC", "TORIC_FIRST_RATIO", "SCALES",
           "QUICK_EXTRA_DEGREE", "DISTINCT_TOL"]

#: the ``solver=`` names of :func:`generalised_vertices`
SOLVERS = ("auto", "nullspace", "toric", "homotopy")
#: enlargements of the working frame tried in turn.  Measured: a 16x larger disc does not recover
#: far-away solutions (the near ones then cluster and the rank decisions blur), so only 1 is used;
#: far solutions are found by the toric null space (runtime.solve.toric).
SCALES = (1,)
#: extra Macaulay degrees tried when the exact route stands behind the numeric one (``quick``;
#: measured on 99 rigid configurations: no success at d0 + 2 after refusals at d0 and d0 + 1)
QUICK_EXTRA_DEGREE = 1
#: marker of the toric null-space attempt in the plan of :func:`generalised_vertices`
TORIC = "toric"
#: scene-to-site ratio (:func:`runtime.algebra.polyalg.scene_to_site_ratio`) from which the toric
#: null space is tried first.  Measured on random triples, seeds 300–307, four mixes, cold calls,
#: total time weighted-first → toric-first: 10× apart (ratios 4–52) 9.4 → 7.5 s, 100× apart (36–512)
#: 11.96 → 9.64 s; compact (ratios 1.2–6.2) 7.1 → 6.0 s, but the demo triple (2.7) 0.13 → 0.20 s, so
#: the weighted null space stays first below the ratio
TORIC_FIRST_RATIO = 8.0
#: refined roots of the weighted null space closer than this (max-norm, scaled by the frame
#: (L, L, L²)) count as one root
DISTINCT_TOL = 1e-8


@dataclass
class TripleSolution:
    """All generalised Voronoi vertices of an ordered triple (world coordinates, complex)."""

    points: np.ndarray          # (N, 3) complex: x, y, R
    residuals: np.ndarray       # (N,) relative residuals after Newton
    conds: np.ndarray           # (N,) Jacobian condition numbers
    info: SolveInfo
    frame: WorkingFrame
    first: int                  # index (0..2) of the conic used as C1 (frame orientation)


@dataclass(frozen=True)
class AttemptOptions:
    """How :func:`generalised_vertices` searches: the starting Macaulay degree (None: the type
    configuration's), the eigen-solver, how many larger degrees to try, whether the homotopy may
    answer when every null space refuses, which ``solver`` (:data:`SOLVERS`), and ``quick`` (the
    exact route stands behind: refuse early)."""

    degree: int | None = None
    eigen: str = "dense"
    max_extra_degree: int = 2
    homotopy: bool = True
    solver: str = "auto"
    quick: bool = False

    def __post_init__(self):
        if self.solver not in SOLVERS:
            raise ValueError(f"solver={self.solver!r}: choose 'auto', 'nullspace', 'toric' or 'homotopy'")

    @property
    def extra_degrees(self) -> int:
        """Larger Macaulay degrees tried after the first (at most :data:`QUICK_EXTRA_DEGREE` when quick)."""
        return min(self.max_extra_degree, QUICK_EXTRA_DEGREE) if self.quick else self.max_extra_degree

    @property
    def homotopy_behind(self) -> bool:
        """May the parameter homotopy answer when every null-space attempt refused?"""
        return self.homotopy and self.solver not in ("nullspace", "toric")


@dataclass(frozen=True)
class TripleSystem:
    """The offset system o1 = o2 = o3 = 0 of an ordered triple in its working frame: the conics,
    their offsets (thesis §4.4), the index of C1 (a conic of largest offset degree, whose axes the
    frame takes: thesis §5.3, C1 in canonical position), the composed offsets, the sorted family
    triple (its type configuration, Table 5.1), the starting Macaulay degree, the generic count
    (None outside the table), the degree-gap hint, and the seconds spent composing."""

    conics: list
    offsets: list
    first: int
    frame: WorkingFrame
    polys: list
    families: tuple[str, ...]
    degree: int
    expected: int | None
    gap_hint: int
    fill_seconds: float


def triple_system(c1, c2, c3, degree: int | None = None) -> TripleSystem:
    """The :class:`TripleSystem` of (C1, C2, C3): offsets, working frame with the axes of a conic of
    largest weighted offset degree (the first on a tie; thesis §5.3), composed offsets, and the
    configuration's degree, generic count and gap hint
    (:func:`runtime.solve.configurations.config_entry`); ``degree`` overrides the starting degree."""
    conics = [c1, c2, c3]
    offs = [CanonicalOffset(c) for c in conics]
    first = max(range(3), key=lambda i: (offs[i].wdeg, -i))
    wf = working_frame(conics, conics[first])
    t0 = time.perf_counter()
    polys = [compose_offset(o, wf) for o in offs]
    fill = time.perf_counter() - t0
    fams = tuple(sorted(o.family for o in offs))
    d0, expected, hint = config_entry(fams)
    return TripleSystem(conics, offs, first, wf, polys, fams, d0 if degree is None else degree, expected,
                        hint, fill)


class _CountMismatch(LocatorError):
    """A clear degree gap, but not at the generic count."""


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

    Steps: the system in its frame (:func:`triple_system`), a visibly non-generic member refused
    (:func:`_refuse_shared_shape`), the plan of attempts (:func:`_attempt_plan`), the first attempt
    that answers (:func:`_first_answer`), the homotopy when every attempt refused
    (:func:`_homotopy_fallback`)."""
    opts = AttemptOptions(degree, eigen, max_extra_degree, homotopy, solver, quick)
    system = triple_system(c1, c2, c3, degree)
    total: dict[str, float] = {"fill": system.fill_seconds}
    errors: list[str] = []
    _refuse_shared_shape(system, opts)
    answer = _first_answer(system, opts, _attempt_plan(system, opts), total, errors)
    if answer is None:
        if not opts.homotopy_behind or system.expected is None:
            raise LocatorError(f"no reliable solution of the offset system for {system.families}: "
                               + "; ".join(errors))
        pts, res, cond, info = _homotopy_fallback(system.offsets, system.frame, system.expected, errors, total)
        n_deflated, wf = 0, system.frame
    else:
        pts, res, cond, info, n_deflated, wf = answer
    info.expected = system.expected
    info.timings = total
    info.n_deflated = n_deflated
    info.failed_attempts = errors
    return TripleSolution(pts, res, cond, info, wf, system.first)


def _refuse_shared_shape(system: TripleSystem, opts: AttemptOptions) -> None:
    """With the exact route behind (quick, solver "auto"): two sites of one shape and orientation
    (translated or scaled copies, parallel parabolas, :func:`runtime.solve.configurations.
    shared_shape`) usually make a non-generic member, on which every null-space attempt fails; the
    complex count modulo a prime (~0.03 s, shared with the dimension proof) decides before any of
    them, and a count other than the generic one (Table 5.1) raises LocatorError."""
    if not (opts.quick and system.expected is not None and opts.solver == "auto" and shared_shape(system.conics)):
        return
    n_member = modular_count(*system.conics)
    if n_member is not None and n_member != system.expected:
        raise LocatorError(f"msolve modulo a prime: {n_member} complex solutions, generic count {system.expected}: "
                           "non-generic configuration (two sites of the same shape and orientation)")


def _attempt_plan(system: TripleSystem, opts: AttemptOptions) -> list:
    """The attempts of :func:`generalised_vertices` in order: (scale, Macaulay degree, top degrees
    projected or 0) for the weighted null space (thesis §5.5), and :data:`TORIC` for the toric null
    space."""
    d0 = system.degree
    attempts: list = [(sc, d, top) for sc in SCALES for d in range(d0, d0 + opts.extra_degrees + 1)
                      for top in (TOP_DEGREES, 0)] if opts.solver in ("auto", "nullspace") else []
    if system.expected is not None and opts.solver in ("auto", "toric"):
        # the toric null space in circle space right after the first weighted attempt (it finds
        # the far vertices that the weighted closure lumps with its curve at infinity), or first
        # for small sites far apart, where the weighted attempt usually refuses
        first_toric = not attempts or scene_to_site_ratio(system.conics, system.frame) >= TORIC_FIRST_RATIO
        attempts.insert(0 if first_toric else 1, TORIC)
    return attempts


def _first_answer(system: TripleSystem, opts: AttemptOptions, attempts: list, total: dict, errors: list[str]):
    """The attempts (thesis §5.5) run in turn until one answers: (pts, res, cond, info, n_deflated,
    frame), or None when all refused (each refusal appended to ``errors``).  With the exact route
    behind (quick), the first refusal asks whether the member is non-generic
    (:func:`_after_refusal`), the attempts stop with LocatorError once the background exact solve
    has answered, and an answer that is not provisional cancels that solve."""
    c1, c2, c3 = system.conics
    frames = {1: (system.frame, system.polys)}
    for attempt in attempts:
        if opts.quick and errors and exact_solved(c1, c2, c3):
            errors.append("the exact route (started in the background) has answered first")
            raise LocatorError("; ".join(errors))
        sc, d, top = (1, -1, 0) if attempt is TORIC else attempt
        if sc not in frames:
            frames[sc] = _scaled_frame(system, sc, total)
        wf, polys = frames[sc]
        try:
            pts, res, cond, info, n_deflated = _solve_attempt(
                attempt, polys, system, wf, total, eigen=opts.eigen, gap_hint=system.gap_hint + (d - system.degree))
        except LocatorError as exc:
            errors.append(f"toric null space: {exc}" if attempt is TORIC else
                          f"scale {sc}, degree {d} ({'projected' if top else 'full'} null space): {exc}")
            if opts.quick and len(errors) == 1 and system.expected is not None:
                _after_refusal(c1, c2, c3, system.expected, errors)
            continue
        if opts.quick and errors and not info.provisional:
            # answered after all: the background solve is waste (a provisional list keeps it: if
            # the certification refuses, the exact route is already under way)
            cancel_solve_exact(c1, c2, c3)
        return pts, res, cond, info, n_deflated, wf
    return None


def _scaled_frame(system: TripleSystem, sc: float, total: dict):
    """The working frame enlarged ``sc`` times (same rotation and centre) and the offsets composed
    with it; the composing time is added to ``total["fill"]``."""
    wf0 = system.frame
    wf = WorkingFrame(wf0.cos, wf0.sin, wf0.px, wf0.py, wf0.L * sc)
    t0 = time.perf_counter()
    polys = [compose_offset(o, wf) for o in system.offsets]
    total["fill"] += time.perf_counter() - t0
    return wf, polys


def _solve_attempt(attempt, polys, system: TripleSystem, wf, total: dict, *, eigen: str, gap_hint: int):
    """One attempt: the roots of the null space (weighted, thesis §5.5, or toric), checked against
    the generic count of Table 5.1 (a different count raises LocatorError: completeness would not
    hold), Newton-refined, completed by deflation; (pts, res, cond, info, n_deflated)."""
    offs, expected = system.offsets, system.expected
    wf_roots = wf
    if attempt is TORIC:
        roots_w, info, wf_roots = toric_attempt(polys, offs, expected, wf)
    else:
        _sc, d, top = attempt
        roots_w, info = solve_nullspace(polys, [o.wdeg for o in offs], d, eigen=eigen, top=top,
                                        gap_hint=gap_hint)
    add_timings(total, info.timings)
    if expected is not None and info.n_finite != expected:
        # fewer: solutions far away lumped with those at infinity, or a non-generic
        # configuration (e.g. parallel parabola axes); completeness is not established
        raise _CountMismatch(f"{info.n_finite} finite solutions found, the generic count for {system.families} "
                             f"is {expected}")
    t1 = time.perf_counter()
    x, y = wf_roots.to_world(roots_w[:, 0], roots_w[:, 1])
    pts = np.stack([x, y, roots_w[:, 2] * wf_roots.L ** 2], axis=1)
    try:
        # the toric roots are Newton-refined in circle space already: Newton in (x, y, R) can
        # move a far vertex to a point of smaller residual but farther from it
        if attempt is TORIC:
            pts, res, cond = refine_toric_roots(offs, pts, info.root_residuals, wf.L)
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
        pts, res, cond, n_deflated = complete_by_deflation(offs, pts, res, cond, wf.L, tol=tol,
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
    n_member = modular_count(c1, c2, c3)
    if n_member is not None and n_member != expected:
        errors.append(f"msolve modulo a prime: {n_member} complex solutions, generic count "
                      f"{expected}: non-generic configuration")
        raise LocatorError("; ".join(errors)) from None
    start_solve_exact(c1, c2, c3)


def _homotopy_fallback(offs, wf, expected, errors, total):
    """Second route when the null-space solve refuses: parameter homotopy (runtime.solve.homotopy;
    coefficient-parameter homotopy of Morgan and Sommese), tracked from a start system of the same
    type configuration.
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


#: the null-space route alone, used by the homotopy to solve its start systems
nullspace_route = partial(generalised_vertices, solver="nullspace")


def homotopy_route(offs, wf):
    """:func:`runtime.solve.homotopy.homotopy_solve` with this module's null-space route for the start
    system and the generic count of the family triple (:data:`runtime.solve.configurations.CONFIG_TABLE`)."""
    expected = CONFIG_TABLE.get(tuple(sorted(o.family for o in offs)), (None, None))[1]
    return homotopy_solve(offs, wf, nullspace_solve=nullspace_route, expected=expected)
