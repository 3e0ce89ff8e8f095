"""Step 2 of the diagram certificate (:mod:`runtime.voronoi.verify.certificate`): the checks of every edge.

Per edge: its site pair and end vertices (proved, on its bisector), its polyline (ends at the
vertices, points within the stated tolerance of the bisector and on the edge's arc), the
parameter interval of the edge on the exact bisector of circle/point sites, the exact-zero
argument for the third sites of its end vertices, then -- batched over all edges -- the third-site
searches of :mod:`runtime.voronoi.verify.edges` (finite arcs and infinite tails).  When a site is
an ellipse, every edge goes to :mod:`runtime.voronoi.verify.curved_edges` (chains of strips, all
edges side by side; unbounded ends in a sector of directions or along a mirror line).  Where the
floats cannot decide a third site of a circle/point edge, :mod:`runtime.voronoi.verify.exact_edges`
decides it exactly.

Length: the checks of one edge, in the order they run — the screen of the document's data
(:func:`_screen`, :func:`_end_vertices`), the parameter range, the polyline on the arc, the end
vertices' third sites, the batched sign checks, the arcs and tails — each a named step.
"""
from __future__ import annotations

import math

import numpy as np

from .problems import fault
from .arc_search import prove_arcs
from .edges import bisector, params
from .exact_edges import (SHALLOW, exact_third_site_clear, far_point_edges, search_with_exact_fallback,
                          tower_points_apart, triple_others, zero_on_arc)
from .exact_vertices import exact_tower_vertex
from .polyline_bound import hausdorff_bounds
from .curved_edges import curved_edges, curved_job, curved_scale, drawn_points, ends_at_vertices, past

__all__ = ["check_edges"]


class _EdgeName:
    """'edge 7 (sites 3, 5)', formatted only when a problem line uses it (most edges have none)."""

    __slots__ = ("e",)

    def __init__(self, e):
        self.e = e

    def __str__(self) -> str:
        return f"edge {self.e.id} (sites {', '.join(str(int(s)) for s in self.e.sites)})"

    def __format__(self, spec) -> str:
        return format(str(self), spec)


def _ename(e) -> _EdgeName:
    return _EdgeName(e)


def check_edges(D, geoms, table, vinfo, vok, problems, stats, deadline=None):
    """Step 2 of :mod:`runtime.voronoi.verify.certificate` for every reported edge.  Returns (flags in
    diagram order, unbounded ends (θ, pair, σ, id), parameter intervals per pair).  Edges not
    checked by ``deadline`` (a :func:`time.perf_counter` value) are not proved, and one problem
    line says how many."""
    late = [0]        # edges left unchecked at the deadline
    ends_inf: list = []      # (theta, pair, sigma, edge id)
    intervals: dict = {}     # pair -> list of (kind, lo, hi, edge id)
    eok, cands, curved = _screen(D, geoms, table, vinfo, vok, problems)
    curved_edges(curved, geoms, problems, eok, ends_inf, deadline, late)
    if past(deadline) and cands:
        late[0] += len(cands)
        for c in cands:
            eok[c[0]] = False
        cands = []
    jobs = []
    for (pos, e, name, pair, P, endv, bis), pre in zip(cands, _precompute(cands, table)):
        job = _edge_job(e, name, pair, P, endv, bis, table, problems, pre)
        eok[pos] = job is not None
        if job is not None:
            jobs.append((pos, e, name, pair, bis, job))
    # the end vertices' third sites: one sign on the open arc, decided at interior points
    jobs = _sign_checks(jobs, table, eok, problems, geoms, vinfo)
    _prove_arcs_and_tails(jobs, table, geoms, vinfo, eok, problems, ends_inf, intervals, deadline, late)
    stats["unbounded_ends"] = len(ends_inf)
    if late[0]:
        problems.append(f"time limit reached: {late[0]} edges not checked")
    return eok, ends_inf, intervals


def _screen(D, geoms, table, vinfo, vok, problems):
    """(eok, cands, curved): each edge's site pair valid, its polyline at least two finite points,
    its end vertices listed, proved and on its bisector; then the edges next to a curved site go
    to ``curved`` (their jobs), the others with their bisector to ``cands``."""
    n = len(geoms)
    eok: list[bool] = []
    vok_by_id = {v.id: f for v, f in zip(D.vertices, vok)}
    cands, curved, cscale = [], [], None
    for e in D.edges:
        name = _ename(e)
        pair = tuple(int(s) for s in e.sites)
        if len(pair) != 2 or not (0 <= pair[0] < pair[1] < n):
            problems.append(f"{name}: invalid site pair (need 0 <= i < j < {n})")
            eok.append(False)
            continue
        P = np.asarray(e.polyline, float).reshape(-1, 2)
        if len(P) < 2 or not np.isfinite(P).all():
            problems.append(f"{name}: polyline needs at least 2 finite points")
            eok.append(False)
            continue
        endv = _end_vertices(name, pair, tuple(e.ends), vok_by_id, vinfo, problems)
        if endv is None:
            eok.append(False)
            continue
        if table is None:
            if cscale is None:
                cscale = curved_scale(geoms)
            job = curved_job(e, name, pair, P, endv, cscale, problems)
            eok.append(False)
            if job is not None:
                curved.append((len(eok) - 1, e, name, job))
            continue
        bis = bisector(table, *pair)
        if isinstance(bis, str):
            problems.append(f"{name}: {bis}")
            eok.append(False)
            continue
        eok.append(True)
        cands.append((len(eok) - 1, e, name, pair, P, endv, bis))
    return eok, cands, curved


def _end_vertices(name, pair, ends, vok_by_id, vinfo, problems):
    """The end vertices' records (None for an end at infinity), or None when one is not listed,
    not proved, or does not have both sites of the edge (problems recorded for each)."""
    endv = []
    bad = False
    for t, vid in enumerate(ends):
        if vid is None:
            endv.append(None)
            continue
        if vid not in vok_by_id:
            problems.append(f"{name}: end {t} is vertex {vid}, which is not listed")
            bad = True
            continue
        if not vok_by_id[vid] or vid not in vinfo:
            problems.append(f"{name}: end vertex {vid} is not proved")
            bad = True
            continue
        w = vinfo[vid]
        if not set(pair) <= set(w.sites):
            problems.append(f"{name}: ends at vertex {vid} (sites {', '.join(map(str, w.sites))}), "
                            "which is not on its bisector")
            bad = True
            continue
        endv.append(w)
    return None if bad else endv


def _prove_arcs_and_tails(jobs, table, geoms, vinfo, eok, problems, ends_inf, intervals, deadline, late):
    """Edges of points far out, proved exactly at once; Lipschitz discs on the finite parts of the
    others, all edges at once (:func:`prove_arcs`); then the searches with their exact fallback
    and the tails.  A proved edge records its unbounded ends and its parameter interval."""
    exact = far_point_edges(geoms, vinfo, table.scale, jobs) if table is not None else set()
    rest = [t for t in range(len(jobs)) if t not in exact]
    found = prove_arcs(table, [(jobs[t][4], *jobs[t][5][:3]) for t in rest],
                       max_depth=SHALLOW, max_pieces=4096 + 64 * len(rest), deadline=deadline) if rest else []
    arcs = [(True, None)] * len(jobs)
    for t, res in zip(rest, found):
        arcs[t] = res
    for t, ((pos, e, name, pair, bis, (lo, hi, exempt, tails, full_lo, full_hi, _)), (ok, det)) in enumerate(zip(jobs, arcs)):
        if past(deadline) and (not ok or tails):     # proved finite arcs cost nothing more
            late[0] += 1
            eok[pos] = False
            continue
        if t not in exact:
            ok, det = search_with_exact_fallback(table, geoms, vinfo, e, pair, bis, lo, hi, exempt, tails, ok, det)
        if not ok:
            problems.append(_search_problem(name, e, pair, det))
            eok[pos] = False
            continue
        for U, sigma in tails:
            d = bis.a * bis.ex + sigma * bis.b * bis.ey
            ends_inf.append((math.atan2(d[1], d[0]) % (2 * math.pi), pair, sigma, e.id))
        intervals.setdefault(pair, []).append((bis.kind, full_lo, full_hi, e.id))


def _search_problem(name, e, pair, det):
    """The problem line of an edge whose search failed: a site proved closer (a fault), a tail not
    proved beyond the finite part, or a site too close to decide (reported as a fault, with its sites)."""
    k, q, why = det[:3]
    where = "" if q is None else f" near ({q[0]:.9g}, {q[1]:.9g})"
    if why == "closer":
        return fault(f"{name}: site {k} is closer than its sites{where}", kind="edge", edge=e.id, sites=(*pair, k))
    if k is None:
        return f"{name}: not proved beyond the finite part: {why}"
    return fault(f"{name}: site {k} too close to decide{where}", kind="edge", edge=e.id, sites=(*pair, k))


def _sign_checks(jobs, table, eok, problems, geoms, vinfo):
    """For each job and each exempt third site k: prove d_k > d_i at one of five interior points
    of the arc (d_k − d_i has no zero on the open arc, so this fixes its sign), or, where the floats
    cannot tell (a vertex 10⁹ out, where three nearly collinear points' circle is centred), exactly
    on the whole edge for points and circles (:func:`exact_third_site_clear`).  Drops failing
    jobs (problem recorded)."""
    fr = np.array([0.5, 0.25, 0.75, 0.125, 0.875])
    req = [(t, k) for t, (_, _, _, _, _, job) in enumerate(jobs) for k in job[6]]
    if not req:
        return jobs
    T = np.array([r[0] for r in req])
    K = np.array([r[1] for r in req])
    Q, E, I = [], [], []
    for t in T:
        bis, (lo, hi) = jobs[t][4], jobs[t][5][:2]
        u = lo + fr * (hi - lo)
        Q.append(bis.point(u))
        E.append(bis.curve_error(u))
        I.append(bis.i)
    Q = np.concatenate(Q)
    E = np.concatenate(E)
    I = np.repeat(np.array(I), len(fr))
    Kr = np.repeat(K, len(fr))
    lo_i, hi_i = table.bounds(Q, I)
    lo_k, hi_k = table.bounds(Q, Kr)
    pos = (lo_k - E > hi_i + E).reshape(-1, len(fr)).any(-1)
    drop = set()
    for r in np.nonzero(~pos)[0]:
        t = int(T[r])
        if t in drop:
            continue
        pos_e, e, name, pair = jobs[t][:4]
        q = Q[r * len(fr)]
        neg = (hi_k + E < lo_i - E).reshape(-1, len(fr))[r].any()
        if not neg and exact_third_site_clear(geoms, vinfo, e, pair, jobs[t][5][3], (int(K[r]), q, "undecided")):
            continue
        drop.add(t)
        problems.append(fault(f"{name}: site {int(K[r])} " + ("is closer than its sites" if neg else "too close to decide")
                              + f" near ({q[0]:.9g}, {q[1]:.9g})", kind="edge", edge=e.id, sites=(*pair, int(K[r]))))
        eok[pos_e] = False
    return [jb for t, jb in enumerate(jobs) if t not in drop]


def _precompute(cands, table):
    """Batched float work of the per-edge checks: parameters of the end vertices, of the polyline
    points and of the other solutions of the end triples, and the lower bounds |d_i − d_j|/2 of
    the distance of the inner polyline points to the bisector."""
    biss = [c[6] for c in cands]
    pts, idx, tags = [], [], []
    for t, (_, e, _, pair, P, (v0, v1), bis) in enumerate(cands):
        for name, w in (("v0", v0), ("v1", v1)):
            if w is not None:
                pts.append([[w.x, w.y]]), idx.append([t]), tags.append((t, name, 1))
                if w.others:
                    pts.append(np.asarray(w.others, float).reshape(-1, 2))
                    idx.append([t] * len(w.others)), tags.append((t, "o" + name, len(w.others)))
        mid = P[len(P) // 2] if len(P) > 2 else 0.5 * (P[0] + P[-1])
        inner = P if e.closed else P[drawn_points(e, P)]
        pts += [P[:1], P[-1:], mid[None, :], inner]
        idx += [[t], [t], [t], [t] * len(inner)]
        tags += [(t, "first", 1), (t, "last", 1), (t, "mid", 1), (t, "inner", len(inner))]
    out = [dict() for _ in cands]
    if not cands:
        return out
    for o, hb in zip(out, hausdorff_bounds(biss, [c[4] for c in cands])):
        o["hausdorff"] = float(hb)
    X = np.concatenate([np.asarray(p, float).reshape(-1, 2) for p in pts])
    I = np.concatenate([np.asarray(i, int) for i in idx])
    U = params(biss, I, X)
    Ei = np.array([c[3][0] for c in cands])[I]
    Ej = np.array([c[3][1] for c in cands])[I]
    lo_i, hi_i = table.bounds(X, Ei)
    lo_j, hi_j = table.bounds(X, Ej)
    LB = np.maximum(lo_i - hi_j, lo_j - hi_i) / 2
    # per edge with inner points: the largest lower bound and the extreme parameters (the checks
    # of :func:`_polyline_on_arc` that pass need no more)
    counts = np.array([cnt for _, name, cnt in tags])
    starts = np.cumsum(counts) - counts
    inner = [k for k, (_, name, cnt) in enumerate(tags) if name == "inner" and cnt > 0]
    if inner:
        rows = np.concatenate([np.arange(starts[k], starts[k] + counts[k]) for k in inner])
        seg = np.cumsum(counts[inner]) - counts[inner]
        lbmax = np.maximum.reduceat(LB[rows], seg).tolist()
        umin = np.minimum.reduceat(U[rows], seg).tolist()
        umax = np.maximum.reduceat(U[rows], seg).tolist()
        for k, a, b, c in zip(inner, lbmax, umin, umax):
            out[tags[k][0]].update(lbmax=a, umin=b, umax=c)
    for (t, name, cnt), pos in zip(tags, starts.tolist()):
        out[t][name] = U[pos:pos + cnt]
        if name == "inner":
            out[t]["lb"] = LB[pos:pos + cnt]
    return out


def _edge_job(e, name, pair, P, endv, bis, table, problems, pre):
    """Checks of one edge that need no search (ends, polyline, exact zeros of the end vertices'
    third sites); returns (lo, hi, exempt, tails, full_lo, full_hi, signs) for the searches, or
    None (problem recorded)."""
    if not ends_at_vertices(name, P, endv, table.scale, problems):
        return None
    got = _parameter_range(e, name, pair, endv, bis, table, problems, pre)
    if got is None:
        return None
    lo, hi, tails = got
    if not _polyline_on_arc(e, name, pair, P, bis, table, problems, pre, lo, hi, tails):
        return None
    full_lo = -math.inf if any(s < 0 for _, s in tails) else lo
    full_hi = math.inf if any(s > 0 for _, s in tails) else hi
    got = _end_third_sites(e, name, pair, endv, bis, problems, pre, (lo, hi, full_lo, full_hi))
    if got is None:
        return None
    exempt, signs = got
    return lo, hi, exempt, tails, full_lo, full_hi, signs


def _parameter_range(e, name, pair, endv, bis, table, problems, pre):
    """(lo, hi, tails): the bisector's parameter interval of the edge — a closed edge one turn of
    an ellipse, an edge to infinity (hyperbola) its finite part up to U, at most the end vertex's
    distance to its sites along the branch, then the tails (U, σ) —, or None (problem recorded).
    End vertices that coincide on the bisector are accepted only when their exact tower points
    are proved apart (a very short edge: the exact search decides its third sites)."""
    v0, v1 = endv
    i, j = pair
    two_pi = 2 * math.pi
    # --- the parameter range of the edge (and the tails)
    tails = []           # (U, sigma)
    if e.closed:
        if bis.kind != "ellipse" or v0 is not None or v1 is not None:
            problems.append(f"{name}: a closed edge needs a site nested in the other and no end vertex")
            return None
        t0 = float(pre["first"][0])
        lo, hi = t0, t0 + two_pi
    elif v0 is None and v1 is None:
        if bis.kind != "hyperbola":
            problems.append(f"{name}: an edge without vertices around a nested site must be closed")
            return None
        lo, hi = -1.0, 1.0
        tails = [(1.0, 1), (-1.0, -1)]
    elif v0 is None or v1 is None:
        if bis.kind != "hyperbola":
            problems.append(f"{name}: goes to infinity on a bounded bisector (nested sites)")
            return None
        u0 = float(pre["v0"][0]) if v1 is None else float(pre["v1"][0])
        uf = float(pre["last"][0]) if v1 is None else float(pre["first"][0])
        if not abs(uf - u0) > 1e-14 * (1 + abs(u0)):
            problems.append(f"{name}: cannot tell which way the edge goes to infinity from its polyline")
            return None
        sigma = 1 if uf > u0 else -1
        # the finite part: an arc of length at most the vertex's distance to its sites (the
        # tail's bound takes every site at once beyond it; a long finite arc far from the
        # sites would meet many candidate sites in the disc search)
        w = v0 if v1 is None else v1
        r_v = abs(math.hypot(w.x - table.C[i, 0], w.y - table.C[i, 1]) - table.R[i])
        U = u0 + sigma * min(1.0, max(abs(math.asinh(math.sinh(u0) + sigma * r_v / bis.c) - u0), 1e-3))
        lo, hi = (u0, U) if sigma > 0 else (U, u0)
        tails = [(U, sigma)]
    else:
        u0, u1 = float(pre["v0"][0]), float(pre["v1"][0])
        if bis.kind == "hyperbola":
            lo, hi = min(u0, u1), max(u0, u1)
        else:
            L = (u1 - u0) % two_pi
            if v0 is v1:
                L = two_pi
            tp = float(pre["mid"][0])
            if (tp - u0) % two_pi <= L:
                lo, hi = u0, u0 + L
            else:
                lo, hi = u1, u1 + (two_pi - L)
        if not hi - lo > 1e-12:
            ex0 = exact_tower_vertex(v0, v0.geoms) if hasattr(v0, "geoms") else None
            ex1 = exact_tower_vertex(v1, v1.geoms) if hasattr(v1, "geoms") else None
            if bis.kind != "hyperbola" or ex0 is None or ex1 is None or not tower_points_apart(ex0[1], ex1[1]):
                problems.append(f"{name}: its end vertices coincide on the bisector")
                return None
            hi = max(hi, lo)      # a very short edge: the exact search decides its third sites
    return lo, hi, tails


def _polyline_on_arc(e, name, pair, P, bis, table, problems, pre, lo, hi, tails) -> bool:
    """Each drawn point within the stated tolerance of the bisector (its lower bound ``lb`` ≤
    tol·(1 + 10⁻⁹) + 10⁻¹²·scale) and on the edge's arc (parameter in [lo, hi] up to 10⁻⁶, the
    tails' sides open); then the whole polyline, segments included, within the tolerance of the
    arc (the Hausdorff bound, up to 10⁻⁹ of the coordinates' magnitude)."""
    two_pi = 2 * math.pi
    # --- polyline points: within tolerance of the bisector and on the edge's arc
    inner = P[drawn_points(e, P)] if not e.closed else P
    first = 0 if e.closed else drawn_points(e, P).start
    if len(inner):
        lb = pre["lb"]
        tol = float(e.tolerance) if math.isfinite(e.tolerance) else math.inf
        thr = tol * (1 + 1e-9) + 1e-12 * table.scale
        far = np.nonzero(lb > thr)[0] if not pre["lbmax"] <= thr else ()
        if len(far):
            p = int(far[0])
            problems.append(f"{name}: polyline point {p + first} ({inner[p, 0]:.9g}, {inner[p, 1]:.9g}) "
                            f"is at least {lb[p]:.3g} from the bisector (stated tolerance {tol:.3g})")
            return False
        if not e.closed:
            up = pre["inner"]
            outside = None
            if bis.kind == "ellipse":
                off = (up - lo) % two_pi
                outside = off > (hi - lo) + 1e-6
            else:
                a_ = -math.inf if any(sg < 0 for _, sg in tails) else lo
                b_ = math.inf if any(sg > 0 for _, sg in tails) else hi
                # all parameters within [a_, b_] up to 10⁻⁶ of 1 + |u| when the extreme ones are,
                # with a margin for the rounding of u ± slack (else each point is tested)
                umin, umax = pre["umin"], pre["umax"]
                inside = (umin >= a_ - 1e-6 * (1 + abs(umin)) * (1 - 1e-9)
                          and umax <= b_ + 1e-6 * (1 + abs(umax)) * (1 - 1e-9))
                if not inside:
                    slack_u = 1e-6 * (1 + np.abs(up))
                    outside = (up < a_ - slack_u) | (up > b_ + slack_u)
            if outside is not None and outside.any():
                p = int(np.nonzero(outside)[0][0])
                problems.append(fault(f"{name}: polyline point {p + first} ({inner[p, 0]:.9g}, {inner[p, 1]:.9g}) "
                                      "is not on the arc between its ends", kind="edge", edge=e.id, sites=pair))
                return False
    # --- the whole polyline, segments included, within the stated tolerance of the arc (Hausdorff)
    tol = float(e.tolerance)
    bound = pre["hausdorff"]
    # (up to the rounding of the float data: 1e-9 of the coordinates' magnitude)
    if not (bound <= tol * (1 + 1e-9) + 1e-9 * table.scale
            or bound <= tol * (1 + 1e-9) + 1e-9 * (table.scale + float(np.abs(P).max()))):
        problems.append(f"{name}: its polyline is proved only within {bound:.3g} of the bisector arc "
                        f"(stated tolerance {tol:.3g})")
        return False
    return True


def _end_third_sites(e, name, pair, endv, bis, problems, pre, span):
    """(exempt, signs) for the third sites of the end vertices: d_k − d_i has no zero on the open
    arc (exact zeros of the vertices of (i, j, k), :func:`zero_on_arc`); ``signs``: the sites whose
    one sign on the arc is then decided at interior points (batched).  None: problem recorded."""
    v0, v1 = endv
    i, j = pair
    lo, hi, full_lo, full_hi = span
    # --- third sites of the end vertices: exact zeros of d_k - d_i on the bisector
    exempt = set()
    signs = []
    for w, w2 in ((v0, v1), (v1, v0)):
        if w is None:
            continue
        for k in [s for s in w.sites if s not in pair]:
            if k in exempt:
                continue
            if len(w.sites) == 3:
                if w.others is None:
                    continue      # conic triple: k stays in the search (undecided near the vertex)
                others = w.others
                uo = pre.get("ov0" if w is v0 else "ov1", [])
            else:
                others = triple_others(w, i, j, k)
                if others is None:
                    problems.append(f"{name}: the vertices of sites {', '.join(map(str, sorted((i, j, k))))} "
                                    "are not known exactly")
                    return None
                uo = bis.param(np.asarray(others, float).reshape(-1, 2)) if others else []
            exempt.add(k)
            same = w2 is not None and k in w2.sites
            bad = zero_on_arc(name, bis, others, uo, w2 if same else None, lo, hi, full_lo, full_hi, (i, j, k), problems,
                              edge=e.id)
            if bad:
                return None
            if w2 is None or same:
                signs.append(k)   # one sign on the open arc: decided at interior points (batched)
            # else: d_k − d_i has no zero on the arc and is > 0 at the other end w2, whose
            # emptiness (k strictly outside) is proved: it is positive on the whole open arc
    return exempt, signs
