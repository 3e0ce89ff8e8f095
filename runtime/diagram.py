"""Semi-dynamic Delaunay graph and Voronoi diagram of conics (thesis §1.2, Prop. 1.2.1).

The sites (circles, points, ellipses, hyperbolas, parabolas) are inserted one by one.  The
structure keeps

* the **triangles**: a triple of sites (i, j, k) together with one of its *true Voronoi
  vertices* q (the centre of a circle touching the three sites and empty of *all* sites,
  thesis §5.2, Def. 5.2.1) and the radius of that empty circle;
* the **edges** of the Delaunay graph: pairs of sites whose Voronoi regions share a Voronoi
  edge (a point whose nearest sites are exactly those two).

Insertion of a site s (the update of §1.2, in its simplest complete form)
--------------------------------------------------------------------------
1. *Deletion.*  Every current vertex v of a triple (i, j, k) is tested against s with the
   conflict locator ("retain only the solutions where the Voronoi vertex is v", §1.2): v is
   deleted iff s enters the open empty circle of v.  The vertices of a triple do not depend
   on the fourth site, so they are computed once per triple and cached (requirement 2 of
   issue 8); a conflict test against a cached triple only evaluates the sign of
   d(q, s) − radius.  (§1.2 notes that only the regions met by s and their neighbours need
   testing; we test every vertex, which is simpler and costs one cheap sign per vertex.)
2. *Creation.*  A new vertex w of V(S ∪ {s}) has s and two old sites i, j as nearest sites,
   so in V(S) the nearest sites of w are exactly i and j: w lies on the Voronoi edge (i, j)
   of V(S) (§1.2: "each new Voronoi vertex ... belongs to ... Voronoi edges of V(S)").
   Hence the candidate triples are (i, j, s) for the Delaunay edges (i, j) of the graph
   *before* the insertion (``candidates="edges"``, default) -- or for all pairs
   (``candidates="all"``, which does not rely on the edge set).  Every true vertex of a
   candidate triple is kept iff no other site conflicts with it (one locator sign per site).
3. *Edges.*  Two sites sharing a Voronoi vertex are Delaunay neighbours (certified with the
   vertex).  Two sites can also be neighbours *without* a common vertex: the closed Voronoi
   edge around a site nested inside another (Prop. 1.2.1: the diagram is then disconnected
   and the Delaunay graph has a dangling edge), and unbounded edges of "strip"
   configurations (e.g. three collinear points or circles in a row).  Such a vertex-less
   Voronoi edge is a whole connected component of the bisector of the pair.  They are found
   *numerically*: rays are shot along the normals of the new site s (both sides) and
   marched (sphere tracing with the 2-Lipschitz function min_k d_k − d_s) to the first
   point where another site k is as close as s; that point lies on the boundary of the
   region of s, on the edge (s, k).  For each pair found this way that shares no vertex a
   few of these edge points are stored.  Inserting a site never creates an adjacency between
   old sites; a vertex-less component either survives entirely, is cut (then it gets new
   vertices (i, j, s)) or disappears, so a stored point is kept as long as the new site is
   farther from it than i and j.  An edge supported only by such numeric evidence is
   reported with ``certified=False`` and makes the whole diagram uncertified.  With two
   sites, the single edge is certified (the bisector of two distinct curves is never empty).

Certification: every vertex computation and conflict decision carries the locator's
``certified`` flag; :attr:`DelaunayGraph.certified` is True iff all of them are certified and
every reported edge is certified; :attr:`DelaunayGraph.uncertified_decisions` lists the
exceptions.  The *search* for vertex-less edges is numeric (its completeness is not proved);
in ``candidates="edges"`` mode the completeness of the vertex set also relies on it.

Locators: triples of circles (and points) use the exact circle locator
(:mod:`runtime.circles`, §3.1.3).  Any triple or conflict test involving a non-circular
conic uses the general conic locator :mod:`runtime.locator` (``voronoi_vertices`` and
``locate_conflicts``); if that module is not available a :class:`LocatorError` says so.

Public API: :class:`DelaunayGraph`, :func:`build_diagram`, :func:`as_site`,
:func:`distance_field`, :func:`run_diagram`, :func:`diagram_main`.
"""
from __future__ import annotations

import json
import math
import sys
import time
from dataclasses import dataclass
from fractions import Fraction
from typing import Any, Iterable, Sequence

import numpy as np

from .result import InvalidConicError, LocatorError

__all__ = ["Site", "as_site", "DiagramVertex", "DelaunayGraph", "build_diagram", "distance_field",
           "read_sites", "run_diagram", "diagram_main", "conic_locator_available"]


# =====================================================================================
# Sites
# =====================================================================================


def _conic_module():
    from . import conic

    return conic


def conic_locator_available() -> bool:
    """True iff the general conic locator (runtime.locator) can be imported."""
    try:
        from . import locator  # noqa: F401
    except ImportError:
        return False
    return hasattr(locator, "voronoi_vertices") and hasattr(locator, "locate_conflicts")


def _conic_locator():
    try:
        from . import locator
    except ImportError as exc:
        raise LocatorError(
            "the Voronoi diagram of non-circular conics needs the general conic locator "
            f"(runtime.locator), which is not available in this installation ({exc}); "
            "diagrams of circles and points work without it") from None
    for name in ("voronoi_vertices", "locate_conflicts"):
        if not hasattr(locator, name):
            raise LocatorError(f"runtime.locator has no {name}(): the general conic locator is incomplete")
    return locator


@dataclass(eq=False)
class Site:
    """A site of the diagram: a :class:`runtime.circles.Circle` (points: radius 0) and/or a
    :class:`runtime.conic.Conic`.  ``circle`` is set iff the site is a circle or a point."""

    circle: Any = None
    conic: Any = None
    #: float description: kind and canonical frame (cos, sin, tx, ty, params)
    kind: str = ""
    frame: Any = None

    @property
    def is_circle(self) -> bool:
        return self.circle is not None

    @property
    def fcircle(self) -> tuple[float, float, float]:
        """(cx, cy, radius) as floats (circles and points)."""
        fc = self.__dict__.get("_fc")
        if fc is None:
            c = self.circle
            fc = self.__dict__["_fc"] = (float(c.cx), float(c.cy), math.sqrt(float(c.r2)))
        return fc

    def get_conic(self):
        """The Conic of the site (created from the circle when needed; points have none)."""
        if self.conic is None:
            if self.circle.r2 == 0:
                raise LocatorError("a point site cannot be passed to the conic locator (not a proper conic)")
            C = _conic_module().Conic
            c = self.circle
            self.conic = C.circle(centre=(Fraction(int(c.cx.p), int(c.cx.q)), Fraction(int(c.cy.p), int(c.cy.q))),
                                  r2=Fraction(int(c.r2.p), int(c.r2.q)))
        return self.conic

    def key(self):
        if self.circle is not None:
            return ("circle", self.circle.cx, self.circle.cy, self.circle.r2)
        return ("conic", self.conic.primitive_coefficients)

    def to_dict(self) -> dict:
        if self.circle is not None:
            c = self.circle
            # x² + y² − 2cx x − 2cy y + (cx² + cy² − r2) = 0
            co = [1, 0, 1, -2 * c.cx, -2 * c.cy, c.cx * c.cx + c.cy * c.cy - c.r2]
            return {"coefficients": [str(v) for v in co], "kind": "point" if c.r2 == 0 else "circle",
                    "centre": [float(c.cx), float(c.cy)], "radius": math.sqrt(float(c.r2))}
        d = {"coefficients": [str(v) for v in self.conic.coefficients], "kind": self.conic.kind}
        return d

    # ---------------------------------------------------------------- float geometry
    def size(self) -> float:
        if self.kind in ("circle", "point"):
            return math.sqrt(float(self.circle.r2))
        p = self.frame.params
        if self.kind == "parabola":
            return float(p["p"])
        return math.sqrt(max(float(p["A2"]), float(p["B2"])))

    def centre(self) -> tuple[float, float]:
        if self.circle is not None:
            return float(self.circle.cx), float(self.circle.cy)
        return float(self.frame.tx), float(self.frame.ty)

    def __repr__(self) -> str:
        if self.circle is not None:
            return f"Site({self.kind}: centre=({float(self.circle.cx):g}, {float(self.circle.cy):g}), r={self.size():g})"
        return f"Site({self.conic!r})"


def as_site(obj) -> Site:
    """Site from a Circle, a Conic, a (cx, cy, radius) triple, a coefficient list
    [a, b, c, d, e, f] or a dict {"coefficients": [...]} (the ``locate`` schema)."""
    from .circles import Circle, as_circle

    if isinstance(obj, Site):
        return obj
    if isinstance(obj, dict):
        if "coefficients" not in obj:
            raise InvalidConicError(f'a site dict needs "coefficients": [a, b, c, d, e, f], got keys {sorted(obj)}')
        obj = obj["coefficients"]
    if isinstance(obj, Circle):
        return Site(circle=obj, kind="point" if obj.r2 == 0 else "circle")
    Conic = _conic_module().Conic
    if isinstance(obj, (list, tuple)) and len(obj) == 6:
        coeffs = [Fraction(v.strip()) if isinstance(v, str) else v for v in obj]
        try:
            obj = Conic.from_coefficients(*coeffs)
        except (ValueError, ZeroDivisionError) as exc:
            raise InvalidConicError(str(exc)) from None
    if isinstance(obj, Conic):
        if obj.kind == "circle":
            circ = Circle.from_coefficients(*obj.coefficients)
            return Site(circle=circ, conic=obj, kind="circle")
        return Site(conic=obj, kind=obj.kind, frame=obj.frame)
    circ = as_circle(obj)
    return Site(circle=circ, kind="point" if circ.r2 == 0 else "circle")


# =====================================================================================
# Float geometry: distance fields, samples with normals (plots and the numeric edge search)
# =====================================================================================


def _conic_param_samples(site: Site, n: int, extent: float):
    """Canonical samples (X, Y), tangents (TX, TY), params t and branch ids of a conic."""
    fr = site.frame
    p = fr.params
    if site.kind == "ellipse":
        A, B = math.sqrt(float(p["A2"])), math.sqrt(float(p["B2"]))
        t = np.linspace(0, 2 * np.pi, n, endpoint=False)
        return [(A * np.cos(t), B * np.sin(t), -A * np.sin(t), B * np.cos(t), t, 0)]
    if site.kind == "hyperbola":
        A, B = math.sqrt(float(p["A2"])), math.sqrt(float(p["B2"]))
        T = math.asinh(max(extent, B) / B) + 0.5
        t = np.linspace(-T, T, n)
        return [(br * A * np.cosh(t), B * np.sinh(t), br * A * np.sinh(t), B * np.cosh(t), t, br) for br in (1, -1)]
    pp = float(p["p"])
    U = math.asinh(max(extent, pp) / pp) + 0.5
    t = pp * np.sinh(np.linspace(-U, U, n))  # multiscale sampling of Y
    return [(t * t / (2 * pp), t, t / pp, np.ones_like(t), t, 0)]


def _conic_point(site: Site, t, br):
    p = site.frame.params
    if site.kind == "ellipse":
        A, B = math.sqrt(float(p["A2"])), math.sqrt(float(p["B2"]))
        ct, st = np.cos(t), np.sin(t)
        return (A * ct, B * st), (-A * st, B * ct), (-A * ct, -B * st)
    if site.kind == "hyperbola":
        A, B = math.sqrt(float(p["A2"])), math.sqrt(float(p["B2"]))
        ch, sh = np.cosh(t), np.sinh(t)
        return (br * A * ch, B * sh), (br * A * sh, B * ch), (br * A * ch, B * sh)
    pp = float(p["p"])
    return (t * t / (2 * pp), t), (t / pp, np.ones_like(t)), (np.full_like(t, 1 / pp), np.zeros_like(t))


def distance_field(site, X, Y, n: int = 256) -> np.ndarray:
    """Float Euclidean distance from the points (X, Y) (arrays) to the site.

    Circles/points: closed form.  Other conics: nearest of ``n`` parameter samples of the
    canonical form, then Newton steps on the foot-point condition (numeric, not certified:
    used for plots and for the numeric search of vertex-less edges only).
    """
    site = as_site(site)
    X = np.asarray(X, dtype=float)
    Y = np.asarray(Y, dtype=float)
    if site.circle is not None:
        c = site.circle
        return np.abs(np.hypot(X - float(c.cx), Y - float(c.cy)) - math.sqrt(float(c.r2)))
    fr = site.frame
    cs, sn, tx, ty = float(fr.cos), float(fr.sin), float(fr.tx), float(fr.ty)
    dx, dy = X.ravel() - tx, Y.ravel() - ty
    X0, Y0 = cs * dx + sn * dy, -sn * dx + cs * dy
    ext = float(np.max(np.hypot(X0, Y0))) if X0.size else 1.0
    best = np.full(X0.shape, np.inf)
    for PX, PY, _TX, _TY, ts, br in _conic_param_samples(site, n, 2 * ext + site.size()):
        for a in range(0, X0.size, 4096):
            x0, y0 = X0[a:a + 4096], Y0[a:a + 4096]
            D = (PX[None, :] - x0[:, None]) ** 2 + (PY[None, :] - y0[:, None]) ** 2
            t = ts[np.argmin(D, axis=1)]
            for _ in range(6):
                (px, py), (ddx, ddy), (sx, sy) = _conic_point(site, t, br)
                ux, uy = px - x0, py - y0
                g = ux * ddx + uy * ddy
                dg = ddx * ddx + ddy * ddy + ux * sx + uy * sy
                with np.errstate(all="ignore"):
                    tn = np.where(dg > 0, t - g / np.where(dg > 0, dg, 1.0), t)
                (qx, qy), _, _ = _conic_point(site, tn, br)
                better = (qx - x0) ** 2 + (qy - y0) ** 2 < ux * ux + uy * uy
                t = np.where(better, tn, t)
            (px, py), _, _ = _conic_point(site, t, br)
            best[a:a + 4096] = np.minimum(best[a:a + 4096], np.hypot(px - x0, py - y0))
    return best.reshape(X.shape)


def site_samples(site: Site, n: int, extent: float):
    """World points on the site and unit normals: arrays (x, y, nx, ny).  Points: n
    directions around the point (normals = directions)."""
    if site.circle is not None:
        c = site.circle
        r = math.sqrt(float(c.r2))
        t = np.linspace(0, 2 * np.pi, n, endpoint=False)
        ux, uy = np.cos(t), np.sin(t)
        return float(c.cx) + r * ux, float(c.cy) + r * uy, ux, uy
    fr = site.frame
    cs, sn, tx, ty = float(fr.cos), float(fr.sin), float(fr.tx), float(fr.ty)
    xs, ys, nxs, nys = [], [], [], []
    for PX, PY, TX, TY, _t, _br in _conic_param_samples(site, n, extent):
        nrm = np.hypot(TX, TY)
        NX, NY = TY / nrm, -TX / nrm
        xs.append(tx + cs * PX - sn * PY)
        ys.append(ty + sn * PX + cs * PY)
        nxs.append(cs * NX - sn * NY)
        nys.append(sn * NX + cs * NY)
    return np.concatenate(xs), np.concatenate(ys), np.concatenate(nxs), np.concatenate(nys)


def scene_box(sites: Sequence[Site]) -> tuple[float, float, float, float]:
    """(xmin, xmax, ymin, ymax) enclosing the bounded sites (unbounded conics: a window of
    a few focal sizes around their vertex/centre)."""
    xs, ys = [], []
    for s in sites:
        cx, cy = s.centre()
        r = s.size() * (1.0 if s.kind in ("circle", "point", "ellipse") else 4.0)
        xs += [cx - r, cx + r]
        ys += [cy - r, cy + r]
    if not xs:
        return (-1.0, 1.0, -1.0, 1.0)
    return min(xs), max(xs), min(ys), max(ys)


# =====================================================================================
# Locator backends
# =====================================================================================


@dataclass
class _TripleVerts:
    ids: tuple[int, int, int]
    xs: list[float]
    ys: list[float]
    radii: list[float]
    certified: list[bool]
    complete: bool
    handle: Any  # circle TripleVertices, or None for conic triples
    notes: list[str]


@dataclass
class DiagramVertex:
    """A Delaunay triangle: sites (i < j < k, input indices) and a true Voronoi vertex."""

    sites: tuple[int, int, int]
    x: float
    y: float
    radius: float
    certified: bool
    #: index of the vertex in the triple's (sorted) vertex list
    slot: int = 0

    def to_dict(self) -> dict:
        return {"sites": list(self.sites), "x": float(self.x), "y": float(self.y),
                "radius": float(self.radius), "certified": bool(self.certified)}


# =====================================================================================
# The Delaunay graph
# =====================================================================================


class DelaunayGraph:
    """Semi-dynamic Delaunay graph / Voronoi diagram of conic sites (thesis §1.2).

    Parameters
    ----------
    candidates : "edges" (default) or "all"
        Which pairs (i, j) are tried for new vertices (i, j, s) on insertion of s: the
        Delaunay edges before the insertion (§1.2), or every pair.
    cache : bool
        Cache the true Voronoi vertices per triple (default).  ``cache=False`` recomputes
        them for every conflict test (only to measure the speed-up; circles only).
    rays : int
        Number of sample points per site for the numeric search of vertex-less edges.
    on_triple_error : "raise" (default) or "skip"
        What to do when the general conic locator cannot solve a triple: raise its
        LocatorError, or treat the triple as having no vertex and record the skip in
        :meth:`uncertified` (the diagram is then uncertified and may miss vertices).
    progress : bool
        Print a progress bar for insertions on stderr (used by :func:`run_diagram`).
    """

    def __init__(self, sites: Iterable | None = None, *, candidates: str = "edges", cache: bool = True,
                 rays: int = 256, progress: bool = False, order: Sequence[int] | None = None,
                 on_triple_error: str = "raise"):
        if on_triple_error not in ("raise", "skip"):
            raise ValueError('on_triple_error must be "raise" or "skip"')
        self.on_triple_error = on_triple_error
        if candidates not in ("edges", "all"):
            raise ValueError('candidates must be "edges" or "all"')
        self.candidates = candidates
        self.cache = cache
        self.rays = int(rays)
        self.sites: dict[int, Site] = {}
        self.order: list[int] = []  # insertion order of site ids
        self._triples: dict[tuple[int, int, int], _TripleVerts] = {}
        self._vertices: dict[tuple[tuple[int, int, int], int], DiagramVertex] = {}
        self._vert_tv: dict[tuple[tuple[int, int, int], int], _TripleVerts] = {}
        #: numeric evidence of vertex-less edges: pair -> list of points on the edge
        self._free: dict[tuple[int, int], list[tuple[float, float]]] = {}
        self._two_site_edge: tuple[int, int] | None = None
        self.uncertified_decisions: list[str] = []
        self.notes: list[str] = []
        self.stats: dict[str, Any] = {"triples_computed": 0, "triple_requests": 0, "conflict_calls": 0,
                                      "insertions": []}
        if sites is not None:
            sites = list(sites)
            order = list(range(len(sites))) if order is None else list(order)
            if sorted(order) != list(range(len(sites))):
                raise ValueError("order must be a permutation of range(len(sites))")
            for n, i in enumerate(order):
                self.insert(sites[i], site_id=i)
                if progress:
                    _progress(n + 1, len(order))

    # ----------------------------------------------------------------- locator access
    def _triple(self, ids: tuple[int, int, int]) -> _TripleVerts:
        ids = tuple(sorted(ids))
        self.stats["triple_requests"] += 1
        tv = self._triples.get(ids)
        if tv is not None:
            return tv
        self.stats["triples_computed"] += 1
        ss = [self.sites[i] for i in ids]
        try:
            if all(s.is_circle for s in ss):
                from .circles import _vertices_cached, voronoi_vertices_circles

                if self.cache:
                    h = voronoi_vertices_circles(*(s.circle for s in ss))
                else:  # bypass every cache (speed-up measurement)
                    h = _vertices_cached.__wrapped__(tuple(s.circle for s in ss))
                tv = _TripleVerts(ids, [v.x for v in h.vertices], [v.y for v in h.vertices],
                                  [v.radius for v in h.vertices], [True] * len(h.vertices), h.complete, h, list(h.notes))
            else:
                loc = _conic_locator()
                res = loc.voronoi_vertices(*(s.get_conic() for s in ss))
                vs = list(res.vertices if hasattr(res, "vertices") else res)
                vs.sort(key=lambda v: (v.x, v.y))
                # the numeric route does not prove that the vertex list is complete
                complete = bool(getattr(res, "complete", False)) and all(v.certified for v in vs)
                tv = _TripleVerts(ids, [float(v.x) for v in vs], [float(v.y) for v in vs],
                                  [float(v.radius) for v in vs], [bool(v.certified) for v in vs], complete, None, [])
        except LocatorError as exc:
            if self.on_triple_error == "raise" or all(x.is_circle for x in ss):
                raise LocatorError(f"sites {list(ids)}: {exc}") from exc
            msg = str(exc)
            self.uncertified_decisions.append(f"triple {list(ids)} skipped: the conic locator failed "
                                              f"({msg[:160]}{'...' if len(msg) > 160 else ''})")
            self.stats["skipped_triples"] = self.stats.get("skipped_triples", 0) + 1
            tv = _TripleVerts(ids, [], [], [], [], False, None, ["locator failed"])
        if not tv.complete:
            self.uncertified_decisions.append(f"vertex list of triple {list(ids)} not proved complete")
        for k, c in enumerate(tv.certified):
            if not c:
                self.uncertified_decisions.append(f"vertex {k} of triple {list(ids)} not certified")
        if self.cache:
            self._triples[ids] = tv
        return tv

    def _conflict(self, tv: _TripleVerts, slot: int, s_id: int) -> bool:
        """Does site s_id enter the open empty circle of vertex ``slot`` of triple tv?"""
        self.stats["conflict_calls"] += 1
        self.stats["triple_requests"] += 1  # a locator call (C1, C2, C3, s) needs the triple's vertices
        ss = [self.sites[i] for i in tv.ids]
        s = self.sites[s_id]
        if tv.handle is not None and s.is_circle:
            from .circles import _vertices_cached, decide_conflict

            h = tv.handle
            if not self.cache:  # recompute the triple: measures what the cache saves
                h = _vertices_cached.__wrapped__(h.circles)
                self.stats["triples_computed"] += 1
            dec = decide_conflict(h, h.vertices[slot], s.circle)
            if dec.tangent:
                self.notes.append(f"site {s_id} is tangent to the empty circle of vertex {slot} of triple "
                                  f"{list(tv.ids)} (degenerate: four co-circular sites)")
            return dec.in_conflict
        loc = _conic_locator()
        res = loc.locate_conflicts(*(x.get_conic() for x in ss), s.get_conic())
        x, y, r = tv.xs[slot], tv.ys[slot], tv.radii[slot]
        best, bd = None, math.inf
        for v in res.vertices:
            d = math.hypot(float(v.x) - x, float(v.y) - y)
            if d < bd:
                best, bd = v, d
        if best is None or bd > 1e-6 * (1.0 + r):
            raise LocatorError(f"conflict locator on triple {list(tv.ids)} + site {s_id} did not return the vertex "
                               f"({x:.17g}, {y:.17g}) of the cached triple")
        if not best.certified:
            self.uncertified_decisions.append(f"conflict of site {s_id} with vertex {slot} of triple {list(tv.ids)}")
        if best.in_conflict is None:  # undecided by the numeric route: within its uncertainty
            self.notes.append(f"site {s_id} undecided (near-tangent) for vertex {slot} of triple {list(tv.ids)}; "
                              "treated as not in conflict")
            return False
        if best.tangent:
            self.notes.append(f"site {s_id} tangent to the empty circle of vertex {slot} of {list(tv.ids)}")
        return bool(best.in_conflict)

    # ----------------------------------------------------------------- insertion
    def insert(self, site, site_id: int | None = None) -> int:
        """Insert a site; returns its id (default: the number of sites inserted before)."""
        s = as_site(site)
        sid = len(self.sites) if site_id is None else int(site_id)
        if sid in self.sites:
            raise ValueError(f"site id {sid} is already used")
        for j, t in self.sites.items():
            if t.key() == s.key():
                raise LocatorError(f"site {sid} is the same curve as site {j}: the bisector of two equal sites "
                                   "is the whole plane, the diagram is not defined")
        t0 = time.perf_counter()
        calls0, trip0 = self.stats["conflict_calls"], self.stats["triples_computed"]
        old_edges = self.edges()
        self.sites[sid] = s
        self.order.append(sid)
        deleted = created = 0
        m = len(self.order)
        if m == 2:
            self._two_site_edge = tuple(sorted(self.order))
        # 1. deletion of the vertices in conflict with s
        for key, v in list(self._vertices.items()):
            if self._conflict(self._vert_tv[key], v.slot, sid):
                del self._vertices[key]
                del self._vert_tv[key]
                deleted += 1
        # 2. new vertices (i, j, s)
        others = [i for i in self.order if i != sid]
        if self.candidates == "all":
            pairs = [(a, b) for n, a in enumerate(sorted(others)) for b in sorted(others)[n + 1:]]
        else:
            pairs = sorted(old_edges)
        for i, j in pairs:
            tv = self._triple((i, j, sid))
            for slot in range(len(tv.xs)):
                if self._empty_of_all(tv, slot):
                    self._vertices[(tv.ids, slot)] = DiagramVertex(tv.ids, tv.xs[slot], tv.ys[slot], tv.radii[slot],
                                                                   tv.certified[slot], slot)
                    self._vert_tv[(tv.ids, slot)] = tv
                    created += 1
        # 3. vertex-less edges: old evidence that survives, new evidence around s
        if m >= 2:
            self._update_free_edges(sid)
        self.stats["insertions"].append({
            "site": sid, "n_sites": m, "conflict_calls": self.stats["conflict_calls"] - calls0,
            "triples_computed": self.stats["triples_computed"] - trip0, "candidate_pairs": len(pairs),
            "deleted": deleted, "created": created, "seconds": time.perf_counter() - t0})
        return sid

    def _empty_of_all(self, tv: _TripleVerts, slot: int) -> bool:
        x, y, r = tv.xs[slot], tv.ys[slot], tv.radii[slot]
        rest = [k for k in self.order if k not in tv.ids]
        if not rest:
            return True
        # test the likeliest conflicts first (float gap d_k - r); every site is tested exactly
        d = self._dist_matrix(rest, np.array([x]), np.array([y]))[:, 0]
        for n in np.argsort(d, kind="stable"):
            k = rest[int(n)]
            if self._conflict(tv, slot, k):
                return False
        return True

    # ----------------------------------------------------------------- vertex-less edges
    def _update_free_edges(self, sid: int) -> None:
        s = self.sites[sid]
        # (a) old evidence: keep a point while s is farther from it than the pair
        for pair, pts in list(self._free.items()):
            P = np.array(pts)
            di = distance_field(self.sites[pair[0]], P[:, 0], P[:, 1])
            ds = distance_field(s, P[:, 0], P[:, 1])
            keep = [p for p, a, b in zip(pts, di, ds) if b > a * (1 + 1e-9) + 1e-12]
            if keep:
                self._free[pair] = keep
            else:
                del self._free[pair]
        # (b) new evidence: march rays from s
        found = self._shoot(sid)
        vert_pairs = self._vertex_pairs()
        for k, pts in found.items():
            pair = (min(sid, k), max(sid, k))
            if pair in vert_pairs or not pts:
                continue
            step = max(1, len(pts) // 8)
            self._free[pair] = pts[::step][:8]

    def _dist_matrix(self, ids: Sequence[int], X: np.ndarray, Y: np.ndarray) -> np.ndarray:
        """Float distances (len(ids), len(X)) from points to sites (circles vectorised)."""
        out = np.empty((len(ids), len(X)))
        circ = [n for n, i in enumerate(ids) if self.sites[i].is_circle]
        if circ:
            C = np.array([self.sites[ids[n]].fcircle for n in circ])
            out[circ] = np.abs(np.hypot(X[None, :] - C[:, :1], Y[None, :] - C[:, 1:2]) - C[:, 2:3])
        for n, i in enumerate(ids):
            if not self.sites[i].is_circle:
                out[n] = distance_field(self.sites[i], X, Y)
        return out

    def _shoot(self, sid: int) -> dict[int, list[tuple[float, float]]]:
        s = self.sites[sid]
        others = [k for k in self.order if k != sid]
        all_sites = [self.sites[k] for k in self.order]
        x0, x1, y0, y1 = scene_box(all_sites)
        diam = math.hypot(x1 - x0, y1 - y0) + 1e-300
        tmax = 2.0 * diam
        px, py, nx, ny = site_samples(s, self.rays, diam)
        if s.kind == "point":
            P = np.stack([px, py], 1)
            Dn = np.stack([nx, ny], 1)
        else:
            P = np.concatenate([np.stack([px, py], 1)] * 2)
            Dn = np.concatenate([np.stack([nx, ny], 1), -np.stack([nx, ny], 1)])
        h = 1e-3 * diam

        def g_of(Q):
            ds = self._dist_matrix([sid], Q[:, 0], Q[:, 1])[0]
            dk = self._dist_matrix(others, Q[:, 0], Q[:, 1])
            return dk.min(0) - ds, dk.argmin(0)

        n = len(P)
        t = np.full(n, 1e-9 * diam)
        g, _ = g_of(P + t[:, None] * Dn)
        active = g > 0
        lo = t.copy()
        hi = np.full(n, np.nan)
        for _ in range(400):
            idx = np.flatnonzero(active)
            if idx.size == 0:
                break
            step = np.maximum(np.maximum(g[idx] / 2, h), 0.01 * lo[idx])
            tn = lo[idx] + step
            gn, _ = g_of(P[idx] + tn[:, None] * Dn[idx])
            crossed = gn <= 0
            hi[idx[crossed]] = tn[crossed]
            nc = idx[~crossed]
            lo[nc] = tn[~crossed]
            g[nc] = gn[~crossed]
            active[idx[crossed]] = False
            active[nc] = lo[nc] < tmax
        # rays that started in another region (sites meeting at the sample point) have hi = nan
        br = np.flatnonzero(np.isfinite(hi))
        a, b = lo[br], hi[br]
        for _ in range(45):
            mid = 0.5 * (a + b)
            gm, _ = g_of(P[br] + mid[:, None] * Dn[br])
            pos = gm > 0
            a = np.where(pos, mid, a)
            b = np.where(pos, b, mid)
        Q = P[br] + b[:, None] * Dn[br]
        found: dict[int, list[tuple[float, float]]] = {}
        if len(Q):
            _, arg = g_of(Q)
            for q, k in zip(Q, arg):
                found.setdefault(others[int(k)], []).append((float(q[0]), float(q[1])))
        return found

    # ----------------------------------------------------------------- queries
    def _vertex_pairs(self) -> set[tuple[int, int]]:
        out = set()
        for v in self._vertices.values():
            i, j, k = v.sites
            out |= {(i, j), (i, k), (j, k)}
        return out

    def edge_info(self) -> dict[tuple[int, int], dict]:
        """pair -> {"certified", "evidence": "vertex" | "two sites" | "numeric"}."""
        info: dict[tuple[int, int], dict] = {}
        for v in self._vertices.values():
            i, j, k = v.sites
            for p in ((i, j), (i, k), (j, k)):
                e = info.setdefault(p, {"certified": False, "evidence": "vertex"})
                e["certified"] = e["certified"] or v.certified
        if len(self.order) == 2 and self._two_site_edge is not None:
            info[self._two_site_edge] = {"certified": True, "evidence": "two sites"}
        for p in self._free:
            if p not in info:
                info[p] = {"certified": False, "evidence": "numeric"}
        return info

    def edges(self) -> set[tuple[int, int]]:
        """Delaunay edges as pairs (i, j), i < j (site ids)."""
        return set(self.edge_info())

    @property
    def vertices(self) -> list[DiagramVertex]:
        """Voronoi vertices / Delaunay triangles, sorted by (sites, x, y)."""
        return sorted(self._vertices.values(), key=lambda v: (v.sites, v.x, v.y))

    @property
    def triangles(self) -> list[tuple[int, int, int]]:
        """Triples of sites having at least one true Voronoi vertex in the diagram."""
        return sorted({v.sites for v in self._vertices.values()})

    @property
    def certified(self) -> bool:
        """Every decision certified and every edge certified (see module docstring)."""
        return (not self.uncertified_decisions and all(v.certified for v in self._vertices.values())
                and all(e["certified"] for e in self.edge_info().values()))

    def uncertified(self, limit: int = 50) -> list[str]:
        """The decisions that were not proved (locator decisions and numeric edges)."""
        out = list(dict.fromkeys(self.uncertified_decisions))
        if len(out) > limit:
            out = out[:limit] + [f"... and {len(out) - limit} more uncertified locator decisions"]
        for p, e in sorted(self.edge_info().items()):
            if not e["certified"]:
                out.append(f"edge {list(p)} supported only by numeric evidence ({e['evidence']})")
        return out

    def nested_components(self) -> list[list[int]]:
        """Connected components of the Delaunay graph (Prop. 1.2.1: the Voronoi diagram is
        disconnected iff some sites are nested inside another one and away from the rest;
        such a component hangs on the rest through a single, vertex-less edge)."""
        import networkx as nx

        G = self.to_networkx()
        H = G.copy()
        bridges = [tuple(sorted(e)) for e in nx.bridges(G)] if G.number_of_edges() else []
        out = []
        for u, v in bridges:
            if self.edge_info()[(u, v)]["evidence"] != "vertex":
                H.remove_edge(u, v)
        comps = sorted((sorted(c) for c in nx.connected_components(H)), key=lambda c: (len(c), c))
        return comps if len(comps) > 1 else out

    def to_networkx(self):
        import networkx as nx

        G = nx.Graph()
        for i in sorted(self.sites):
            G.add_node(i, kind=self.sites[i].kind, site=self.sites[i].to_dict())
        for (i, j), e in sorted(self.edge_info().items()):
            G.add_edge(i, j, **e)
        for v in self.vertices:
            for a, b in ((0, 1), (0, 2), (1, 2)):
                G.edges[v.sites[a], v.sites[b]].setdefault("vertices", []).append(v.to_dict())
        return G

    def to_dict(self) -> dict:
        ids = sorted(self.sites)
        return {
            "sites": [self.sites[i].to_dict() for i in ids],
            "edges": [list(p) for p in sorted(self.edges())],
            "vertices": [v.to_dict() for v in self.vertices],
            "triangles": [list(t) for t in self.triangles],
            "edge_evidence": [{"sites": list(p), **e} for p, e in sorted(self.edge_info().items())],
            "certified": self.certified,
            "uncertified_decisions": self.uncertified(),
            "notes": list(dict.fromkeys(self.notes)),
            "stats": {k: v for k, v in self.stats.items() if k != "insertions"}
            | {"cache_hit_rate": self.cache_hit_rate()},
        }

    def to_json(self, path=None, **kw) -> str:
        txt = json.dumps(self.to_dict(), indent=kw.pop("indent", 1), **kw)
        if path is not None:
            with open(path, "w") as fh:
                fh.write(txt + "\n")
        return txt

    def cache_hit_rate(self) -> float:
        """Fraction of the requests for the vertices of a triple (one per conflict test and
        per candidate triple) answered without computing them."""
        r, c = self.stats["triple_requests"], self.stats["triples_computed"]
        return 1.0 - c / r if r else 0.0

    def __repr__(self) -> str:
        return (f"DelaunayGraph({len(self.sites)} sites, {len(self.edges())} edges, "
                f"{len(self._vertices)} vertices, certified={self.certified})")


def build_diagram(sites, **kw) -> DelaunayGraph:
    """Insert ``sites`` (any accepted form) in order; see :class:`DelaunayGraph`."""
    return DelaunayGraph(sites, **kw)


# =====================================================================================
# Command line helpers (wired by runtime/cli.py as ``python -m curvedvoronoi diagram``)
# =====================================================================================


def _progress(k: int, n: int, width: int = 30) -> None:
    done = int(width * k / max(n, 1))
    sys.stderr.write(f"\rinserting sites [{'#' * done}{'.' * (width - done)}] {k}/{n}")
    if k == n:
        sys.stderr.write("\n")
    sys.stderr.flush()


def read_sites(path: str) -> list[Site]:
    """Sites from ``{"conics": [{"coefficients": [a, b, c, d, e, f]}, ...]}`` (any number)."""
    from .sites_io import read_coefficient_lists

    out = []
    for i, co in enumerate(read_coefficient_lists(path)):
        try:
            out.append(as_site(co))
        except (ValueError, ZeroDivisionError) as exc:
            raise ValueError(f"conic {i}: {exc}") from None
    return out


def run_diagram(sites_path: str, png: str | None = None, json_out: str | None = None,
                progress: bool = True, **kw) -> DelaunayGraph:
    """Build the diagram of the sites in ``sites_path``; write JSON and/or PNG."""
    sites = read_sites(sites_path)
    G = DelaunayGraph(sites, progress=progress, **kw)
    if json_out:
        G.to_json(json_out)
    if png:
        from .plot import plot_diagram

        plot_diagram(G, png)
    return G


def diagram_main(argv=None) -> int:
    """``python -m curvedvoronoi diagram SITES.json [--png out.png] [--json out.json]``."""
    import argparse

    p = argparse.ArgumentParser(prog="curvedvoronoi diagram",
                                description="Delaunay graph and Voronoi diagram of conics (thesis §1.2)")
    p.add_argument("sites", help='JSON {"conics": [{"coefficients": [a,b,c,d,e,f]}, ...]}')
    p.add_argument("--png", help="write a picture (matplotlib, Agg)")
    p.add_argument("--json", dest="json_out", help="write the diagram as JSON (default: stdout)")
    p.add_argument("--candidates", choices=["edges", "all"], default="edges")
    p.add_argument("--no-progress", action="store_true")
    a = p.parse_args(argv)
    try:
        G = run_diagram(a.sites, png=a.png, json_out=a.json_out, progress=not a.no_progress,
                        candidates=a.candidates)
    except ValueError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    if not a.json_out:
        print(G.to_json())
    print(f"{len(G.sites)} sites, {len(G.edges())} Delaunay edges, {len(G.vertices)} Voronoi vertices, "
          f"certified={G.certified}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(diagram_main())
