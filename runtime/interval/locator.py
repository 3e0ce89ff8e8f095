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
from .verify import (circle_position, conflict_status, d2_ball, distance_to, neighbourhood, site_status,
                     special_points)

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
            where = circle_position(p, r_lo, r_hi)
            if where == "inside":
                return None, "blocked"  # a site point strictly inside: not a true vertex
            if where == "undecided":
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


class _Search:
    """The data of one locator call: the parsed sites, the search domain ``dom`` (a Box), the proved
    vertex bound (or None), a region of radius ``g`` around the domain that holds every site point
    relevant to a vertex of the domain (its empty circles have radius at most ``rho``), the site
    samples, and the running account (``stats``, ``notes``, ``complete``, ``uncertain_points``)."""

    def __init__(self, curves, domain):
        self.sites = [parse_curve(c, f"C{i + 1}") for i, c in enumerate(curves)]
        default, self.bound = search_domain(self.sites)
        dom_t = tuple(float(v) for v in (default if domain is None else domain))
        self.dom = _domain_box(dom_t)
        diam = float(max(self.dom.width))
        sreg = (dom_t[0] - diam, dom_t[1] + diam, dom_t[2] - diam, dom_t[3] + diam)
        samples = _samples(self.sites, sreg)
        # r = d(q, C_i)² ≤ rmax on the domain, so every empty circle of a vertex in it has radius ≤ rho,
        # and the region (the domain grown by g ≥ 2 rho) holds every site point that circle can touch.
        self.rmax = _r_max(samples, self.dom)
        self.rho = math.sqrt(self.rmax)
        g = max(self.rho, diam) * 2
        self.region = Box(np.array([self.dom.lo[0] - g, self.dom.lo[1] - g]),
                          np.array([self.dom.hi[0] + g, self.dom.hi[1] + g]))
        self.allsamples = np.concatenate([s for s in samples if s.size] or [np.zeros((0, 4))])
        self.bounded = self.bound is not None and self.bound.inside(dom_t)
        self.notes = [_domain_note(dom_t, self.bound, self.bounded)]
        self.stats = {"boxes": 0, "systems": 0, "undecided_boxes": 0, "rejected": {}}
        self.complete = True
        self.uncertain_points: list = []

    def record(self, sysm, res, max_boxes: int):
        """Account for one branch-and-prune run: an incomplete run (undecided boxes, exhausted budget)
        makes the whole answer incomplete."""
        self.stats["boxes"] += res.boxes
        self.stats["systems"] += 1
        self.stats.setdefault("solver", []).append({"label": sysm.label, **res.stats, "boxes": res.boxes,
                                                    "seconds": res.seconds})
        if not res.complete:
            self.complete = False
            self.stats["undecided_boxes"] += len(res.undecided)
            self.uncertain_points += [b.mid[:2].tolist() for b in res.undecided[:20]]
            if res.exhausted:
                self.notes.append(f"{sysm.label}: box budget {max_boxes} exhausted")

    def reject(self, why: str):
        self.stats["rejected"][why] = self.stats["rejected"].get(why, 0) + 1


def _domain_note(dom_t, bound, bounded: bool) -> str:
    box_text = f"x in [{dom_t[0]:.6g}, {dom_t[1]:.6g}], y in [{dom_t[2]:.6g}, {dom_t[3]:.6g}]"
    if bounded:
        return (f"search domain {box_text} contains the proved bound on all vertices (disk of radius "
                f"{bound.radius:.6g} around ({bound.centre[0]:.6g}, {bound.centre[1]:.6g}))")
    if bound is None:
        return (f"search domain {box_text}; no bound on the vertices is proved for these sites (unbounded "
                "site, or bisectors that meet at infinity): complete=False, vertices outside are not searched")
    return (f"search domain {box_text} does not contain the proved bound on all vertices (disk of radius "
            f"{bound.radius:.6g} around ({bound.centre[0]:.6g}, {bound.centre[1]:.6g})): complete=False")


def _search_original(sr: _Search, opts: SolverOptions, use_samples: bool) -> list[_Candidate]:
    """§6.1: the 8-unknown system (q, p_1, p_2, p_3) for every combination of site features (normal
    foot, end point, singular point); solutions in (or overlapping) the domain are candidates."""
    feats = []
    for c in sr.sites[:3]:
        ep, sing, nts = special_points(c, sr.region)
        sr.notes.extend(nts)
        feats.append(site_features(c, ep, sing))
    hooks = [sample_hook(sr.allsamples, r_lower_original)] if use_samples else []
    cands = []
    for combo in itertools.product(*feats):
        box8 = original_domain(sr.sites, sr.dom, sr.rho)
        if box8 is None:
            continue
        sysm = original_system(sr.sites, combo, hooks)
        res = solve(sysm, box8, opts)
        sr.record(sysm, res, opts.max_boxes)
        for s in res.solutions:
            if sr.dom.contains_point(s.tight.mid[:2]) or sr.dom.overlaps(Box(s.tight.lo[:2], s.tight.hi[:2])):
                cands.append(_Candidate(s, combo))
    return cands


def _search_offset(sr: _Search, opts: SolverOptions, use_samples: bool, timings: dict) -> list[_Candidate]:
    """§6.3: the 3-unknown system (q, r) of generalised offsets; each solution is lifted to a
    certified solution of the original system (:func:`_lift`) or rejected with a reason; a solution
    neither lifted nor proved absent (blocked, no real foot) makes the answer incomplete."""
    hooks = [sample_hook(sr.allsamples, r_lower_offset)] if use_samples else []
    sysm = offset_system(sr.sites, hooks)
    box3 = Box(np.array([sr.dom.lo[0], sr.dom.lo[1], 0.0]), np.array([sr.dom.hi[0], sr.dom.hi[1], sr.rmax]))
    t1 = time.perf_counter()
    res = solve(sysm, box3, opts)
    sr.record(sysm, res, opts.max_boxes)
    timings["search"] = time.perf_counter() - t1
    t2 = time.perf_counter()
    cands = []
    for s in res.solutions:
        Q = Box(s.tight.lo[:2].copy(), s.tight.hi[:2].copy())
        r = s.tight.arbs()[2]
        if arb_hi(r) <= 0:
            continue
        sol8, why = _lift(sr.sites, Q, r, sr.region, sr.stats)
        sr.reject(why)
        if sol8 is not None:
            cands.append(_Candidate(sol8, (("normal",),) * 3))
        elif why not in ("blocked", "no-real-foot"):
            sr.complete = False
            sr.uncertain_points.append(Q.mid.tolist())
    timings["lift"] = time.perf_counter() - t2
    return cands


def _own_statuses(sr: _Search, cd: _Candidate) -> list[str] | None:
    """The true-vertex test of a candidate against its own three sites (:func:`.verify.site_status`;
    an arc's foot outside its ``where`` set blocks it): None when some site point is proved strictly
    inside the empty circle, else one status per site ("clear" when proved empty)."""
    statuses = []
    for i in range(3):
        kind = cd.features[i][0]
        own_kind = "point" if kind == "point" else "normal"
        site = sr.sites[i]
        if site.where and kind == "normal":
            pa = cd.P[i].arbs()
            where = site.where_status(pa[0], pa[1])
            if where == "out":
                return None
            if where == "unknown":
                statuses.append("unknown")
                continue
        st, _info = site_status(site, cd.Q, cd.r, cd.P[i], sr.region, own_kind)
        if st == "blocked":
            return None
        statuses.append(st)
    return statuses


def _vertex(sr: _Search, cd: _Candidate, statuses: list[str]) -> VoronoiVertex:
    """A located vertex and its conflict with C4 (Thm 5.2.2): certified when the true-vertex test
    and the conflict decision are both proved; otherwise the numerical answer, with a note."""
    true_v = all(s == "clear" for s in statuses)
    conf = conflict_status(sr.sites[3], cd.Q, cd.r, sr.region)
    radius = math.sqrt(max(0.0, float(cd.r.mid())))
    dist = distance_to(sr.sites[3], cd.Q, arb_hi(cd.r), sr.region)
    d4 = None if dist is None else 0.5 * (dist[0] + dist[1])
    in_conf = d4 < radius if conf is None and dist is not None else conf
    q = cd.Q.mid
    if not true_v:
        sr.notes.append(f"vertex near ({q[0]:.6g}, {q[1]:.6g}): true-vertex test undecided")
    if conf is None:
        sr.notes.append(f"vertex near ({q[0]:.6g}, {q[1]:.6g}): conflict with C4 undecided by intervals "
                        "(tangent or nearly tangent fourth site); numerical answer given")
    return VoronoiVertex(
        x=float(q[0]), y=float(q[1]), radius=radius, distance_to_fourth=d4, in_conflict=in_conf,
        certified=bool(true_v and conf is not None),
        tangent=False,
        info={"q_width": float(max(cd.Q.width)), "r_lo": arb_lo(cd.r), "r_hi": arb_hi(cd.r),
              "true_vertex": "proved" if true_v else "undecided", "conflict": "proved" if conf is not None
              else "numerical", "features": [f[0] for f in cd.features],
              "foot_points": [p.mid.tolist() for p in cd.P]})


def _judge(sr: _Search, cands: list[_Candidate]) -> list[VoronoiVertex]:
    """Candidates to vertices: overlapping copies are dropped, candidates proved blocked are rejected."""
    vertices: list[VoronoiVertex] = []
    seen: list[Box] = []
    for cd in cands:
        if any(o.overlaps(cd.Q) for o in seen):
            continue
        statuses = _own_statuses(sr, cd)
        if statuses is None:
            sr.reject("not-true-vertex")
            continue
        seen.append(cd.Q)
        vertices.append(_vertex(sr, cd, statuses))
    vertices.sort(key=lambda v: (v.x, v.y))
    return vertices


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

    Steps: the search data (:class:`_Search`), the branch-and-prune search of one formulation
    (:func:`_search_original`, :func:`_search_offset`), the true-vertex and conflict decisions of
    each candidate (:func:`_judge`).
    """
    if formulation not in FORMULATIONS:
        raise ValueError(f"formulation must be one of {FORMULATIONS}, got {formulation!r}")
    curves = list(curves)
    if len(curves) != 4:
        raise LocatorError(f"the conflict locator takes four sites C1..C4, got {len(curves)}")
    t0 = time.perf_counter()
    sr = _Search(curves, domain)
    opts = SolverOptions(bisection=bisection, shave_3b=shave_3b, max_boxes=max_boxes, progress=progress,
                         verbose=verbose)
    timings: dict = {}
    t1 = time.perf_counter()
    if formulation == "original":
        cands = _search_original(sr, opts, use_samples)
    else:
        cands = _search_offset(sr, opts, use_samples, timings)
    timings.setdefault("search", time.perf_counter() - t1)
    t3 = time.perf_counter()
    vertices = _judge(sr, cands)
    timings["verify"] = time.perf_counter() - t3
    timings["total"] = time.perf_counter() - t0
    complete = sr.complete and sr.bounded
    if sr.uncertain_points:
        sr.notes.append(f"{sr.stats['undecided_boxes']} undecided boxes / unresolved candidates near "
                        + ", ".join(f"({p[0]:.4g}, {p[1]:.4g})" for p in sr.uncertain_points[:5]))
    sr.notes.append(f"stats: boxes={sr.stats['boxes']} systems={sr.stats['systems']} "
                    f"rejected={sr.stats['rejected']}")
    return LocatorResult(conflict=any(v.in_conflict for v in vertices), vertices=vertices,
                         method=f"interval-{formulation}", timings=timings, complete=complete, notes=sr.notes)


def locate_conflicts_interval(c1, c2, c3, c4, formulation: str = "offset", domain=None, **kw) -> LocatorResult:
    """Same locator for four conics (runtime.sites.conic.Conic objects or validation-case dicts)."""
    return locate_conflicts_semialgebraic([c1, c2, c3, c4], domain=domain, formulation=formulation, **kw)
