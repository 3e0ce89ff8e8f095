"""Interval-analysis Delaunay-graph conflict locator (thesis chapter 6).

``locate_conflicts_semialgebraic(sites, ...)`` finds every true Voronoi vertex of the first
three sites inside a bounded domain with the branch-and-prune solver of :mod:`.solver`, on
either formulation of :mod:`.formulations`, then decides rigorously for each vertex that it is
a *true* vertex (no site point strictly inside the empty circle, :mod:`.verify`) and whether
the fourth site enters the circle (Thm 5.2.2).

``complete`` is True only when the search domain provably contains every vertex: the domain must
contain the disk of :func:`.bound.vertex_bound` (a support-function bound for three bounded sites).
Without such a bound (unbounded sites, bisectors meeting at infinity) the answer is
``complete=False`` whatever the box: a vertex of three unit circles can lie 5000 units away.
"""
from __future__ import annotations

import itertools
import math
import time

import numpy as np

from ..result import LocatorError, LocatorResult, VoronoiVertex

from .bound import VertexBound, vertex_bound
from .boxes import Box, arb_hi, arb_lo
from .curves import Curve, parse_curve
from .formulations import (offset_system, original_domain, original_system, r_lower_offset,
                           r_lower_original, sample_hook, site_features)
from .solver import Solution, SolverOptions, krawczyk, newton_point, solve, tighten
from .verify import (conflict_status, d2_ball, distance_to, neighbourhood, site_status, special_points)

FORMULATIONS = ("original", "offset")


def default_domain(sites: list[Curve]) -> tuple:
    """Box around the data: bounding boxes of bounded sites, centres of unbounded conics,
    grown by half its size on each side (at least 1)."""
    xs, ys = [], []
    for c in sites[:3]:
        if c.bbox is not None:
            xs += [c.bbox[0], c.bbox[1]]
            ys += [c.bbox[2], c.bbox[3]]
        elif c.conic is not None:
            xs.append(float(c.conic["tx"]))
            ys.append(float(c.conic["ty"]))
    if not xs:
        xs, ys = [-1.0, 1.0], [-1.0, 1.0]
    cx, cy = 0.5 * (min(xs) + max(xs)), 0.5 * (min(ys) + max(ys))
    h = max(max(xs) - min(xs), max(ys) - min(ys), 1.0)
    return (cx - h, cx + h, cy - h, cy + h)


def search_domain(sites: list[Curve]) -> tuple[tuple, "VertexBound | None"]:
    """(default search domain, proved vertex bound or None): the box of the bound of
    :func:`.bound.vertex_bound` when the sites admit one, else :func:`default_domain` (a box around
    the data, which proves nothing)."""
    bound = vertex_bound(sites)
    return (bound.box() if bound is not None else default_domain(sites)), bound


def _domain_box(domain) -> Box:
    if isinstance(domain, Box):
        return domain
    if len(domain) != 4:
        raise ValueError("domain must be (xmin, xmax, ymin, ymax)")
    xmin, xmax, ymin, ymax = domain
    if not (xmin < xmax and ymin < ymax) or not all(math.isfinite(float(v)) for v in domain):
        raise ValueError(f"invalid domain {domain}")
    return Box.from_bounds([(xmin, xmax), (ymin, ymax)])


def _samples(sites, region):
    xmin, xmax, ymin, ymax = region
    out = []
    for c in sites[:3]:
        s = np.zeros((0, 4))
        if c.bbox is not None:  # a bounded site: sample it where it is (a large region misses small sites)
            bx0, bx1, by0, by1 = (float(v) for v in c.bbox)
            pad = 0.05 * max(bx1 - bx0, by1 - by0)
            s = c.sample_points((bx0 - pad, bx1 + pad, by0 - pad, by1 + pad))
        if s.size == 0:
            s = c.sample_points(region)
        k = 0
        reg = list(region)
        while s.size == 0 and k < 4:  # unbounded or far site: look further out
            w = reg[1] - reg[0]
            reg = [reg[0] - w, reg[1] + w, reg[2] - w, reg[3] + w]
            s = c.sample_points(tuple(reg))
            k += 1
        out.append(s)
    return out


def _r_max(samples, dom: Box) -> float:
    """Upper bound of r = d(q, C_i)² for q in the domain: min over samples of max |q − s|²."""
    best = math.inf
    for s in samples:
        if s.size == 0:
            continue
        dx = np.maximum(np.abs(dom.hi[0] - s[:, 0]), np.abs(s[:, 1] - dom.lo[0]))
        dy = np.maximum(np.abs(dom.hi[1] - s[:, 2]), np.abs(s[:, 3] - dom.lo[1]))
        best = min(best, float(np.min(dx * dx + dy * dy)) * (1 + 1e-9))
    if not math.isfinite(best):
        raise LocatorError("no point of the sites found near the domain; give a domain or bounded sites")
    return best


class _Candidate:
    def __init__(self, sol8: Solution, features):
        t = sol8.tight
        self.T = t
        self.Q = Box(t.lo[:2].copy(), t.hi[:2].copy())
        self.P = [Box(t.lo[2 + 2 * i:4 + 2 * i].copy(), t.hi[2 + 2 * i:4 + 2 * i].copy()) for i in range(3)]
        qa = self.Q.arbs()
        self.r = d2_ball(qa, self.P[0])
        self.features = features


def _lift(sites, Q: Box, r, region: Box, stats: dict):
    """Offset solution (q, r) -> certified solution of the original 8-unknown system, or a reason."""
    r_lo, r_hi = arb_lo(r), arb_hi(r)
    feet = []
    for i in range(3):
        nb = neighbourhood(sites[i], Q, r_hi, region)
        on = []
        for p in nb.points:
            lo, hi = arb_lo(p.d2), arb_hi(p.d2)
            if p.arc == "out" or lo > r_hi:
                continue
            if hi < r_lo and p.arc == "in":
                return None, "blocked"  # a site point strictly inside: not a true vertex
            on.append(p)
        crit_on = [p for p in on if p.kind == "critical"]
        if not on and not nb.undecided:
            return None, "no-real-foot"
        if len(crit_on) != 1 or len(on) != 1:
            return None, "ambiguous-foot"
        feet.append(crit_on[0].tight.mid)
    sysm = original_system(sites, (("normal",),) * 3)
    x0 = np.concatenate([Q.mid] + feet)
    x = newton_point(sysm, x0)
    if x is None:
        return None, "lift-newton-failed"
    scale = max(1.0, float(np.max(np.abs(x))))
    for eps in (1e-12, 1e-10, 1e-8):
        b = Box(x - eps * scale, x + eps * scale)
        st, nb8 = krawczyk(sysm, b)
        if st == "unique":
            return Solution(b, tighten(sysm, nb8), x), "lifted"
    return None, "lift-krawczyk-failed"


def locate_conflicts_semialgebraic(curves, domain=None, formulation: str = "original", max_boxes: int = 300_000,
                                   progress=None, verbose: bool = False, bisection: str = "smear",
                                   shave_3b: bool = False, use_samples: bool = True) -> LocatorResult:
    """Conflict locator for four semi-algebraic curve sites (thesis ch. 6).

    ``curves``: four sites C1..C4, each a polynomial (sympy string, Poly, flint mpoly), a dict
    ``{"poly": ..., "where": ["y >= 0", ...]}`` (an arc), a validation-case conic dict or a
    ``runtime.sites.conic.Conic``.  ``domain = (xmin, xmax, ymin, ymax)`` bounds the search for the
    vertices (default: the box of the proved vertex bound :func:`.bound.vertex_bound` when there
    is one, else :func:`default_domain`); ``complete`` is True only if the domain contains the
    proved bound and the whole domain was processed with no undecided box.
    ``formulation``: "original" (8 unknowns, §6.1) or
    "offset" (3 unknowns, generalised offsets of conics, §6.3).
    """
    if formulation not in FORMULATIONS:
        raise ValueError(f"formulation must be one of {FORMULATIONS}, got {formulation!r}")
    curves = list(curves)
    if len(curves) != 4:
        raise LocatorError(f"the conflict locator takes four sites C1..C4, got {len(curves)}")
    t0 = time.perf_counter()
    sites = [parse_curve(c, f"C{i + 1}") for i, c in enumerate(curves)]
    default, bound = search_domain(sites)
    if domain is None:
        domain = default
    dom_t = tuple(float(v) for v in domain)
    dom = _domain_box(dom_t)
    diam = float(max(dom.width))
    sreg = (dom_t[0] - diam, dom_t[1] + diam, dom_t[2] - diam, dom_t[3] + diam)
    samples = _samples(sites, sreg)
    rmax = _r_max(samples, dom)
    rho = math.sqrt(rmax)
    g = max(rho, diam) * 2
    region = Box(np.array([dom.lo[0] - g, dom.lo[1] - g]), np.array([dom.hi[0] + g, dom.hi[1] + g]))
    allsamples = np.concatenate([s for s in samples if s.size] or [np.zeros((0, 4))])
    box_text = f"x in [{dom_t[0]:.6g}, {dom_t[1]:.6g}], y in [{dom_t[2]:.6g}, {dom_t[3]:.6g}]"
    bounded = bound is not None and bound.inside(dom_t)
    if bounded:
        notes = [f"search domain {box_text} contains the proved bound on all vertices (disk of radius "
                 f"{bound.radius:.6g} around ({bound.centre[0]:.6g}, {bound.centre[1]:.6g}))"]
    elif bound is None:
        notes = [f"search domain {box_text}; no bound on the vertices is proved for these sites (unbounded "
                 "site, or bisectors that meet at infinity): complete=False, vertices outside are not searched"]
    else:
        notes = [f"search domain {box_text} does not contain the proved bound on all vertices (disk of radius "
                 f"{bound.radius:.6g} around ({bound.centre[0]:.6g}, {bound.centre[1]:.6g})): complete=False"]
    opts = SolverOptions(bisection=bisection, shave_3b=shave_3b, max_boxes=max_boxes, progress=progress,
                         verbose=verbose)
    timings = {}
    stats = {"boxes": 0, "systems": 0, "undecided_boxes": 0, "rejected": {}}
    complete = True
    cands: list[_Candidate] = []
    uncertain_points = []

    t1 = time.perf_counter()
    if formulation == "original":
        feats = []
        for c in sites[:3]:
            ep, sing, nts = special_points(c, region)
            notes.extend(nts)
            feats.append(site_features(c, ep, sing))
        hooks = [sample_hook(allsamples, r_lower_original)] if use_samples else []
        for combo in itertools.product(*feats):
            box8 = original_domain(sites, dom, rho)
            if box8 is None:
                continue
            sysm = original_system(sites, combo, hooks)
            res = solve(sysm, box8, opts)
            stats["boxes"] += res.boxes
            stats["systems"] += 1
            stats.setdefault("solver", []).append({"label": sysm.label, **res.stats, "boxes": res.boxes,
                                                   "seconds": res.seconds})
            if not res.complete:
                complete = False
                stats["undecided_boxes"] += len(res.undecided)
                uncertain_points += [b.mid[:2].tolist() for b in res.undecided[:20]]
                if res.exhausted:
                    notes.append(f"{sysm.label}: box budget {max_boxes} exhausted")
            for s in res.solutions:
                if dom.contains_point(s.tight.mid[:2]) or dom.overlaps(Box(s.tight.lo[:2], s.tight.hi[:2])):
                    cands.append(_Candidate(s, combo))
    else:
        hooks = [sample_hook(allsamples, r_lower_offset)] if use_samples else []
        sysm = offset_system(sites, hooks)
        box3 = Box(np.array([dom.lo[0], dom.lo[1], 0.0]), np.array([dom.hi[0], dom.hi[1], rmax]))
        res = solve(sysm, box3, opts)
        stats["boxes"] += res.boxes
        stats["systems"] += 1
        stats["solver"] = [{"label": sysm.label, **res.stats, "boxes": res.boxes, "seconds": res.seconds}]
        if not res.complete:
            complete = False
            stats["undecided_boxes"] += len(res.undecided)
            uncertain_points += [b.mid[:2].tolist() for b in res.undecided[:20]]
            if res.exhausted:
                notes.append(f"offset: box budget {max_boxes} exhausted")
        timings["search"] = time.perf_counter() - t1
        t2 = time.perf_counter()
        for s in res.solutions:
            Q = Box(s.tight.lo[:2].copy(), s.tight.hi[:2].copy())
            r = s.tight.arbs()[2]
            if arb_hi(r) <= 0:
                continue
            sol8, why = _lift(sites, Q, r, region, stats)
            stats["rejected"][why] = stats["rejected"].get(why, 0) + 1
            if sol8 is not None:
                cands.append(_Candidate(sol8, (("normal",),) * 3))
            elif why not in ("blocked", "no-real-foot"):
                complete = False
                uncertain_points.append(Q.mid.tolist())
        timings["lift"] = time.perf_counter() - t2
    timings.setdefault("search", time.perf_counter() - t1)

    t3 = time.perf_counter()
    vertices: list[VoronoiVertex] = []
    seen: list[Box] = []
    for cd in cands:
        if any(o.overlaps(cd.Q) for o in seen):
            continue
        statuses = []
        blocked = False
        for i in range(3):
            kind = cd.features[i][0]
            own_kind = "point" if kind == "point" else "normal"
            if sites[i].where and kind == "normal":
                pa = cd.P[i].arbs()
                if sites[i].where_status(pa[0], pa[1]) == "out":
                    blocked = True
                    break
                if sites[i].where_status(pa[0], pa[1]) == "unknown":
                    statuses.append("unknown")
                    continue
            st, _info = site_status(sites[i], cd.Q, cd.r, cd.P[i], region, own_kind)
            if st == "blocked":
                blocked = True
                break
            statuses.append(st)
        if blocked:
            stats["rejected"]["not-true-vertex"] = stats["rejected"].get("not-true-vertex", 0) + 1
            continue
        seen.append(cd.Q)
        true_v = all(s == "clear" for s in statuses)
        conf = conflict_status(sites[3], cd.Q, cd.r, region)
        radius = math.sqrt(max(0.0, float(cd.r.mid())))
        dist = distance_to(sites[3], cd.Q, arb_hi(cd.r), region)
        d4 = None if dist is None else 0.5 * (dist[0] + dist[1])
        if conf is None and dist is not None:
            in_conf = d4 < radius
        else:
            in_conf = conf
        q = cd.Q.mid
        vertices.append(VoronoiVertex(
            x=float(q[0]), y=float(q[1]), radius=radius, distance_to_fourth=d4, in_conflict=in_conf,
            certified=bool(true_v and conf is not None),
            tangent=False,
            info={"q_width": float(max(cd.Q.width)), "r_lo": arb_lo(cd.r), "r_hi": arb_hi(cd.r),
                  "true_vertex": "proved" if true_v else "undecided", "conflict": "proved" if conf is not None
                  else "numerical", "features": [f[0] for f in cd.features],
                  "foot_points": [p.mid.tolist() for p in cd.P]}))
        if not true_v:
            complete = complete  # listed but uncertified
            notes.append(f"vertex near ({q[0]:.6g}, {q[1]:.6g}): true-vertex test undecided")
        if conf is None:
            notes.append(f"vertex near ({q[0]:.6g}, {q[1]:.6g}): conflict with C4 undecided by intervals "
                         "(tangent or nearly tangent fourth site); numerical answer given")
    vertices.sort(key=lambda v: (v.x, v.y))
    timings["verify"] = time.perf_counter() - t3
    timings["total"] = time.perf_counter() - t0
    if not bounded:
        complete = False
    if uncertain_points:
        notes.append(f"{stats['undecided_boxes']} undecided boxes / unresolved candidates near "
                     + ", ".join(f"({p[0]:.4g}, {p[1]:.4g})" for p in uncertain_points[:5]))
    notes.append(f"stats: boxes={stats['boxes']} systems={stats['systems']} rejected={stats['rejected']}")
    return LocatorResult(conflict=any(v.in_conflict for v in vertices), vertices=vertices,
                         method=f"interval-{formulation}", timings=timings, complete=complete, notes=notes)


def locate_conflicts_interval(c1, c2, c3, c4, formulation: str = "offset", domain=None, **kw) -> LocatorResult:
    """Same locator for four conics (runtime.sites.conic.Conic objects or validation-case dicts)."""
    return locate_conflicts_semialgebraic([c1, c2, c3, c4], domain=domain, formulation=formulation, **kw)
