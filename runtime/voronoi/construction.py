"""The Voronoi diagram of many sites, built output-sensitively by *sample-then-refine*.

Thesis §1.2 (Prop. 1.2.1) and §5.1–5.2 define the diagram: a vertex is the centre of a circle
touching three sites and empty of all sites; an edge is an arc of points with exactly two
nearest sites.  The thesis builds it incrementally with the conflict locator; an insertion that
re-tests every vertex and solves full triple systems costs O(n) heavy work per site.  Here the
*combinatorics* come from a cheap, robust approximation and only the *local* certified
predicates are run, once per output vertex, so the work is proportional to the output:

1. **Sites → geometries** (:mod:`runtime.voronoi.geometry`).  Intersecting or repeated sites are
   rejected with an error naming the pair (circles and points: exact rational test; conics:
   ``sites_intersect`` of :mod:`runtime.voronoi.conic_geometry`).
2. **Sampling.**  Every site is sampled with spacing ``SPACING_FACTOR``·min(size, gap), the gap a
   lower bound of the distance to the other sites from a k-d tree on bounding discs (floored at
   ``GAP_FLOOR``·size: a narrow gap between two convex sites does not change the combinatorics,
   and where a third site makes it matter the refinement step densifies).  Unbounded sites are
   clipped to a window (the bounded sites' box, enlarged three times).
3. **Sample Delaunay triangulation** (qhull via :class:`scipy.spatial.Delaunay`), every sample
   labelled with its site.  The Voronoi diagram of the samples, restricted to the boundaries
   between different labels, approximates the diagram of the sites (the sites' regions are the
   unions of their samples' cells in the limit of dense sampling).  A triangle with three
   labels (i, j, k) is a candidate vertex (its circumcentre is the seed); triangles with two
   labels {i, j} chain into the edge (i, j).  Walking the dual graph across the bichromatic
   sides gives every edge: from a 3-label triangle to another (an edge between two vertices),
   to the hull (an unbounded edge) or back to the start (a closed, vertex-less edge around a
   nested site, Prop. 1.2.1).
4. **Vertices.**  For circles and points the Apollonius vertex is refined by vectorised Newton
   steps and *proved* by an error-bounded float Krawczyk test (existence and uniqueness of the
   equidistant point in a box; Moore, Kearfott & Cloud, *Introduction to Interval Analysis*,
   §8.2), and shown empty by rigorous distance lower bounds to every site whose bounding disc
   can reach the circle (k-d tree).  When the filter cannot decide, the exact route of thesis
   §3.1.3 (:func:`runtime.circles.voronoi_vertices_circles`, :func:`runtime.circles.decide_conflict`)
   decides.  Triples with a conic use ``refine_vertex`` / ``certify_vertex`` of
   :mod:`runtime.voronoi.vertex`.  Several 3-label triangles near one true vertex are merged by
   their triple and a proof (one Krawczyk box holding all their Newton points), never by a
   float tolerance alone.
5. **Edges.**  The circumcentres along a walk are projected onto the true bisector (Newton
   steps on d_i − d_j along its gradient, using the foot points); the ends are the vertices.
   ``tolerance`` of an edge is max(max |d_i − d_j| / 2 at its points, the deviation of each
   chord midpoint from its projection onto the bisector): a *measured* figure, not a proof;
   the proof that every arc is a true edge is the independent verifier's
   (:func:`runtime.voronoi.verify.verify`).
6. **Refine.**  A 3-label triangle whose triple has no proved, empty vertex near it, a vertex
   without exactly its three incident edges (i, j), (j, k), (i, k), or a walk that cannot be
   closed, makes the spacing of the sites involved shrink and the construction run again (a
   few rounds at most): to √(2rδ) when a site enters a circle of radius r by δ (samples s apart
   misplace distances by about s²/8r), else by half.  With ``certify=True`` the verifier's
   problems that name sites (e.g. a missing unbounded edge whose vertex lies far away, hidden by
   the coarse samples of a third site) refine those sites four times and rebuild (3 times at
   most).  Whatever stays unproved is listed in ``problems`` and the diagram is
   ``certified=False``.

Why sample-then-refine rather than CGAL-style incremental insertion: it needs only the two
certified predicates that exist for every site kind (vertex existence and emptiness), no
edge-interior conflict predicate for curved bisectors (which may be cut several times), and
all heavy work is vectorised numpy/qhull.  Its completeness argument is the verifier's
(every vertex proved, every vertex of full degree, every component represented).

Public API: :func:`voronoi`, :func:`as_site`, :func:`check_disjoint`, :class:`SiteError`.
"""
from __future__ import annotations

import math
import re
import time

import numpy as np
from scipy.spatial import Delaunay, cKDTree

from ..circles import Circle, Point, as_circle, decide_conflict, voronoi_vertices_circles
from ..conic import Conic
from ..result import InvalidConicError, LocatorError
from .conic_geometry import site_geometry
from .geometry import rounding_slack
from .structure import Diagram, DiagramEdge, DiagramVertex

__all__ = ["voronoi", "as_site", "check_disjoint", "SiteError"]

#: sampling spacing as a fraction of min(gap, size)
SPACING_FACTOR = 0.6
#: samples per site: at the first round / at most after refinement
MAX_SAMPLES_FIRST = 2048
MAX_SAMPLES = 1 << 15
MAX_ROUNDS = 8
#: rebuilds driven by the verifier's problems (sites it names are sampled 4x finer)
VERIFY_ROUNDS = 3
#: interior points kept per edge polyline (evenly chosen among the walk's circumcentres; a third
#: of it for conics, whose foot points cost more, before densification)
MAX_EDGE_POINTS = 32
#: polyline chords are split while their midpoint is farther from the bisector than this fraction of
#: the distance to the sites there
DENSIFY_REL = 1e-3
#: the gap used for the first spacing is at least this fraction of the size (narrow gaps between two
#: convex sites do not change the combinatorics; where they do, the refinement rounds densify)
GAP_FLOOR = 0.5


class SiteError(InvalidConicError):
    """Sites that intersect or repeat: the diagram of the thesis (§1.2) needs disjoint sites."""


# ============================================================================ input

def as_site(s):
    """A user site as an exact site: Circle / Point / Conic pass through; a tuple (cx, cy, r)
    is a circle of radius r (r = 0: a point); a list of six numbers is the coefficient list of a
    conic; a dict is a site record of :func:`runtime.sites_io.parse_site`."""
    if isinstance(s, (Circle, Conic)):
        return s
    if isinstance(s, dict):
        from ..sites_io import parse_site
        return parse_site(s)
    if isinstance(s, (list, tuple)) and len(s) == 6:
        return Conic.from_coefficients(*s)
    try:
        cx, cy, r = s
    except (TypeError, ValueError):
        raise InvalidConicError(f"not a site: {s!r} (expected Circle, Point, Conic or (cx, cy, r))") from None
    if r == 0:
        return Point(cx, cy)
    return as_circle((cx, cy, r))


def _circles_meet(a: Circle, b: Circle) -> bool:
    """Exact: do the circles (points) a and b have a common point?  With ρ = √r2:
    (ρa − ρb)² ≤ |ca − cb|² ≤ (ρa + ρb)², decided with rationals only."""
    d2 = (a.cx - b.cx) ** 2 + (a.cy - b.cy) ** 2
    s = a.r2 + b.r2
    p4 = 4 * a.r2 * b.r2
    t = d2 - s
    outer = t <= 0 or t * t <= p4
    u = s - d2
    inner = u <= 0 or u * u <= p4
    return outer and inner


def check_disjoint(sites, geoms=None) -> list[str]:
    """Raise :class:`SiteError` naming the first pair of sites that intersect or repeat.

    Circles and points: candidate pairs from a k-d tree (a pair of overlapping discs is found
    from the larger one), a float filter, then the exact test.  Pairs with a conic: bounding
    boxes, then ``sites_intersect`` of :mod:`runtime.voronoi.conic_geometry`.  Returns notes on
    what could not be checked (no conic intersection test available)."""
    if geoms is None:
        geoms = [site_geometry(s) for s in sites]
    notes: list[str] = []
    circ = [i for i, g in enumerate(geoms) if g.kind in ("point", "circle")]
    if len(circ) > 1:
        idx = np.array(circ)
        C = np.array([[geoms[i].cx if geoms[i].kind == "circle" else geoms[i].x0,
                       geoms[i].cy if geoms[i].kind == "circle" else geoms[i].y0] for i in circ])
        R = np.array([geoms[i].rho if geoms[i].kind == "circle" else 0.0 for i in circ])
        scale = float(np.abs(C).max() + R.max() + 1.0)
        tree = cKDTree(C)
        lists = tree.query_ball_point(C, 2 * R + 1e-9 * scale)
        for a, js in enumerate(lists):
            for b in js:
                if b == a or R[b] > R[a] or (R[b] == R[a] and b < a):
                    continue
                d = math.hypot(C[a, 0] - C[b, 0], C[a, 1] - C[b, 1])
                tol = 1e-9 * scale
                if d > R[a] + R[b] + tol or d < abs(R[a] - R[b]) - tol:
                    continue
                i, j = sorted((int(idx[a]), int(idx[b])))
                if sites_equal(sites[i], sites[j]):
                    raise SiteError(f"site {i} and site {j} are the same site (repeated): remove one")
                if _circles_meet(as_circle(sites[i]) if not isinstance(sites[i], Circle) else sites[i],
                                 as_circle(sites[j]) if not isinstance(sites[j], Circle) else sites[j]):
                    raise SiteError(f"site {i} and site {j} intersect: the Voronoi diagram needs disjoint sites")
    conics = [i for i, g in enumerate(geoms) if g.kind not in ("point", "circle")]
    if conics:
        try:
            from .conic_geometry import sites_intersect
        except ImportError:
            sites_intersect = None
        boxes = np.array([g.bounding_box() for g in geoms], dtype=float)
        for i in conics:
            bi = boxes[i]
            over = ((boxes[:, 0] <= bi[2]) & (boxes[:, 2] >= bi[0]) & (boxes[:, 1] <= bi[3]) & (boxes[:, 3] >= bi[1]))
            for j in np.nonzero(over)[0]:
                j = int(j)
                if j == i or (j in conics and j < i):
                    continue
                a, b = sorted((i, j))
                if sites_equal(sites[a], sites[b]):
                    raise SiteError(f"site {a} and site {b} are the same site (repeated): remove one")
                if sites_intersect is None:
                    notes.append(f"sites {a} and {b}: no conic intersection test available (not checked)")
                    continue
                if sites_intersect(sites[a], sites[b]):
                    raise SiteError(f"site {a} and site {b} intersect: the Voronoi diagram needs disjoint sites")
    return notes


def sites_equal(a, b) -> bool:
    """Exact equality of two sites (conics up to a nonzero factor)."""
    if isinstance(a, Circle) and isinstance(b, Circle):
        return a.cx == b.cx and a.cy == b.cy and a.r2 == b.r2
    ca = getattr(a, "coefficients", None)
    cb = getattr(b, "coefficients", None)
    if ca is None or cb is None:
        return False
    ka = next((k for k, v in enumerate(ca) if v != 0), None)
    kb = next((k for k, v in enumerate(cb) if v != 0), None)
    if ka != kb or ka is None:
        return False
    return all(x * cb[ka] == y * ca[ka] for x, y in zip(ca, cb))


# ============================================================================ site arrays

class _Sites:
    """The geometries plus, when every site is a circle or a point, flat arrays for the
    vectorised paths."""

    def __init__(self, sites, geoms):
        self.sites = sites
        self.geoms = geoms
        self.n = len(geoms)
        self.all_circles = all(g.kind in ("point", "circle") for g in geoms)
        boxes = np.array([g.bounding_box() for g in geoms], dtype=float)
        self.boxes = boxes
        self.bounded = np.array([g.bounded for g in geoms])
        if self.all_circles:
            self.C = np.array([[g.cx, g.cy] if g.kind == "circle" else [g.x0, g.y0] for g in geoms])
            self.R = np.array([g.rho if g.kind == "circle" else 0.0 for g in geoms])
        else:
            fin = np.where(np.isfinite(boxes), boxes, 0.0)
            self.C = np.column_stack([(fin[:, 0] + fin[:, 2]) / 2, (fin[:, 1] + fin[:, 3]) / 2])
            self.R = np.hypot(fin[:, 2] - fin[:, 0], fin[:, 3] - fin[:, 1]) / 2
        b = boxes[self.bounded] if self.bounded.any() else np.zeros((1, 4))
        x0, y0, x1, y1 = b[:, 0].min(), b[:, 1].min(), b[:, 2].max(), b[:, 3].max()
        w = max(x1 - x0, y1 - y0, 1e-9 * (1 + abs(x0) + abs(y0)), 1.0 if not self.bounded.any() else 0.0)
        cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
        self.window = (cx - 1.5 * w, cy - 1.5 * w, cx + 1.5 * w, cy + 1.5 * w)
        self.scale = float(max(abs(cx), abs(cy)) + 2 * w)
        self.size = np.where(self.bounded, self.R, 0.25 * w)
        # "big" sites (checked one by one in emptiness tests): radius beyond 8x the 90th percentile
        pos = self.R[self.bounded & (self.R > 0)]
        big = self.R > 8 * (float(np.percentile(pos, 90)) if len(pos) else 0.0)
        self.big = np.nonzero(big | ~self.bounded)[0]
        small = np.nonzero(~(big | ~self.bounded))[0]
        self.small = small
        self.small_tree = cKDTree(self.C[small]) if len(small) else None
        self.small_rmax = float(self.R[small].max()) if len(small) else 0.0

    # ---- distances, vectorised over (point, site) pairs
    def dist_grad(self, P, lab):
        """Float d(P[m], site lab[m]) and the unit gradient U (from the foot point to P)."""
        P = np.asarray(P, float)
        if self.all_circles:
            V = P - self.C[lab]
            n = np.hypot(V[:, 0], V[:, 1])
            D = np.where(n[:, None] > 0, V / np.where(n > 0, n, 1.0)[:, None], np.array([1.0, 0.0]))
            g = n - self.R[lab]
            return np.abs(g), np.where((g >= 0)[:, None], D, -D)
        d = np.empty(len(P))
        U = np.empty((len(P), 2))
        for s, rows in _groups(lab):
            geo = self.geoms[s]
            d[rows] = geo.distance(P[rows])
            _, U[rows] = geo.foot_points(P[rows])
        return d, U

    def dist_bounds(self, P, lab):
        """Rigorous (lo, hi) of d(P[m], site lab[m])."""
        P = np.asarray(P, float)
        if self.all_circles:
            d, _ = self.dist_grad(P, lab)
            s = rounding_slack(np.abs(P).sum(axis=1) + np.abs(self.C[lab]).sum(axis=1) + self.R[lab])
            return np.maximum(d - s, 0.0), d + s
        lo = np.empty(len(P))
        hi = np.empty(len(P))
        for s, rows in _groups(lab):
            lo[rows], hi[rows] = self.geoms[s].distance_bounds(P[rows])
        return lo, hi

    def near_sites(self, Q, reach):
        """For each query point Q[m], the sites whose bounding disc meets the disc (Q[m], reach[m]):
        returns flat arrays (m, site)."""
        rows, cols = [], []
        if self.small_tree is not None and len(Q):
            lists = self.small_tree.query_ball_point(Q, reach + self.small_rmax)
            lens = np.fromiter((len(x) for x in lists), int, len(lists))
            if lens.sum():
                rows.append(np.repeat(np.arange(len(Q)), lens))
                cols.append(self.small[np.concatenate([np.asarray(x, int) for x in lists if len(x)])])
        for b in self.big:
            if self.bounded[b]:
                dd = np.hypot(Q[:, 0] - self.C[b, 0], Q[:, 1] - self.C[b, 1])
                m = np.nonzero(dd <= reach + self.R[b] + 1e-12 * self.scale)[0]
            else:
                m = np.arange(len(Q))
            rows.append(m)
            cols.append(np.full(len(m), b))
        if not rows:
            return np.zeros(0, int), np.zeros(0, int)
        return np.concatenate(rows), np.concatenate(cols)


def _groups(lab):
    lab = np.asarray(lab)
    order = np.argsort(lab, kind="stable")
    sl = lab[order]
    cuts = np.nonzero(np.diff(sl))[0] + 1
    for part in np.split(order, cuts):
        if len(part):
            yield int(lab[part[0]]), part


# ============================================================================ sampling

def _initial_spacing(S: _Sites) -> np.ndarray:
    """spacing_i = c·min(gap_i, size_i), gap_i a lower bound from bounding discs (k-d tree)."""
    n = S.n
    size = S.size.copy()
    gap = np.full(n, np.inf)
    if n > 1:
        tree = cKDTree(S.C)
        k = min(n, 9)
        dd, jj = tree.query(S.C, k=k)
        for col in range(1, k):
            j = jj[:, col]
            g = dd[:, col] - S.R - S.R[j]
            ok = (g > 0) & S.bounded & S.bounded[j]
            gap = np.where(ok, np.minimum(gap, g), gap)
    gap = np.maximum(np.where(np.isfinite(gap), gap, size), GAP_FLOOR * size)
    sp = SPACING_FACTOR * np.minimum(gap, size)
    sp = np.where(sp > 0, sp, SPACING_FACTOR * size)
    return _clamp_spacing(S, sp, MAX_SAMPLES_FIRST)


def _clamp_spacing(S: _Sites, sp, max_samples):
    perim = 2 * math.pi * S.size
    floor = perim / max_samples
    sp = np.maximum(sp, floor)
    return np.where(sp > 0, sp, 1.0)


def _sample(S: _Sites, spacing):
    """All samples (m, 2) and their site labels."""
    if S.all_circles:
        R = S.R
        nper = np.where(R > 0, np.maximum(8, np.ceil(2 * math.pi * R / spacing)), 1).astype(np.int64)
        lab = np.repeat(np.arange(S.n), nper)
        start = np.concatenate([[0], np.cumsum(nper)[:-1]])
        k = np.arange(len(lab)) - np.repeat(start, nper)
        t = 2 * math.pi * k / nper[lab]
        P = np.column_stack([S.C[lab, 0] + R[lab] * np.cos(t), S.C[lab, 1] + R[lab] * np.sin(t)])
        return P, lab
    parts, labs = [], []
    for i, g in enumerate(S.geoms):
        p = np.asarray(g.samples(float(spacing[i]), S.window), float).reshape(-1, 2)
        parts.append(p)
        labs.append(np.full(len(p), i))
    return np.concatenate(parts), np.concatenate(labs)


# ============================================================================ triangulation and walks

class _Triangulation:
    def __init__(self, P, lab):
        self.P = P
        self.lab = lab
        tri = Delaunay(P)
        self.simp = tri.simplices
        self.nb = tri.neighbors
        L = lab[self.simp]
        self.L = L
        # side k is opposite vertex k: labels L[:, k+1], L[:, k+2]
        self.bich = np.column_stack([L[:, (k + 1) % 3] != L[:, (k + 2) % 3] for k in range(3)])
        nb = self.bich.sum(axis=1)
        self.nlab = np.where(nb == 0, 1, np.where(nb == 3, 3, 2))
        A, B, C = (P[self.simp[:, k]] for k in range(3))
        self.cc = _circumcentres(A, B, C)

    def walks(self):
        """The edges of the labelled triangulation: list of (pair, start, chain, end) where start /
        end are ("tri", t) for a 3-label triangle, ("hull", t, k) for the hull side k of triangle
        t, None for a closed chain (then start is None too), or ("bad", t) for a walk that could not
        be closed; chain = the 2-label triangles in order."""
        nlab = self.nlab
        nbl = self.nb.tolist()
        two = nlab == 2
        ks = np.argsort(~self.bich, axis=1, kind="stable")[:, :2]
        t_idx = np.arange(len(nlab))
        n1 = np.where(two, self.nb[t_idx, ks[:, 0]], -2).tolist()
        n2 = np.where(two, self.nb[t_idx, ks[:, 1]], -2).tolist()
        k1 = ks[:, 0].tolist()
        k2 = ks[:, 1].tolist()
        nl = nlab.tolist()
        L = self.L
        seen = [False] * len(nl)
        out = []

        def pair_of(t, k):
            a, b = int(L[t, (k + 1) % 3]), int(L[t, (k + 2) % 3])
            return (a, b) if a < b else (b, a)

        def walk(cur, k_in, start_t):
            chain = []
            while True:
                if nl[cur] == 3:
                    return chain, ("tri", cur)
                if seen[cur]:
                    return chain, (None if cur == start_t else ("bad", cur))
                seen[cur] = True
                chain.append(cur)
                k_out = k2[cur] if k1[cur] == k_in else k1[cur]
                nxt = nbl[cur][k_out]
                if nxt == -1:
                    return chain, ("hull", cur, k_out)
                if nl[nxt] == 2:
                    k_in = k1[nxt] if n1[nxt] == cur else k2[nxt]
                cur = nxt

        for t in np.nonzero(nlab == 3)[0].tolist():
            for k in range(3):
                u = nbl[t][k]
                if u == -1:
                    out.append((pair_of(t, k), ("tri", t), [], ("hull", t, k)))
                    continue
                if nl[u] == 3:
                    if u > t:
                        out.append((pair_of(t, k), ("tri", t), [], ("tri", u)))
                    continue
                if seen[u]:
                    continue
                chain, end = walk(u, k1[u] if n1[u] == t else k2[u], -1)
                out.append((pair_of(t, k), ("tri", t), chain, end))
        twos = np.nonzero(two)[0].tolist()
        for t in twos:                      # chains from the hull to the hull
            if seen[t]:
                continue
            for nn, kk in ((n1[t], k1[t]), (n2[t], k2[t])):
                if nn == -1:
                    chain, end = walk(t, kk, -1)
                    out.append((pair_of(t, kk), ("hull", t, kk), chain, end))
                    break
        for t in twos:                      # closed chains around nested sites
            if seen[t]:
                continue
            chain, end = walk(t, k1[t], t)
            out.append((pair_of(t, k1[t]), None if end is None else ("bad", t), chain, end))
        return out


def _circumcentres(A, B, C):
    bx, by = B[:, 0] - A[:, 0], B[:, 1] - A[:, 1]
    cx, cy = C[:, 0] - A[:, 0], C[:, 1] - A[:, 1]
    d = 2 * (bx * cy - by * cx)
    b2, c2 = bx * bx + by * by, cx * cx + cy * cy
    with np.errstate(divide="ignore", invalid="ignore"):
        ux = (cy * b2 - by * c2) / d
        uy = (bx * c2 - cx * b2) / d
    return np.column_stack([A[:, 0] + ux, A[:, 1] + uy])


# ============================================================================ vertices

def _newton_vertices(S: _Sites, T3, Q, iters=30):
    """Float Newton on d_a = d_b = d_c (a, b, c = T3 columns) from seeds Q; vectorised.
    Returns the points and the size of the last step."""
    Q = Q.copy()
    step = np.full(len(Q), np.inf)
    for _ in range(iters):
        da, Ua = S.dist_grad(Q, T3[:, 0])
        db, Ub = S.dist_grad(Q, T3[:, 1])
        dc, Uc = S.dist_grad(Q, T3[:, 2])
        F1, F2 = da - db, da - dc
        J = np.stack([Ua - Ub, Ua - Uc], axis=1)          # (n, 2, 2)
        det = J[:, 0, 0] * J[:, 1, 1] - J[:, 0, 1] * J[:, 1, 0]
        with np.errstate(divide="ignore", invalid="ignore"):
            dx = (J[:, 1, 1] * F1 - J[:, 0, 1] * F2) / det
            dy = (-J[:, 1, 0] * F1 + J[:, 0, 0] * F2) / det
        # damp huge steps (a seed far from the vertex)
        ln = np.hypot(dx, dy)
        lim = 0.5 * np.maximum(np.minimum(np.minimum(da, db), dc), 1e-300) + 1e-300
        f = np.where(ln > lim * 4, lim * 4 / np.where(ln > 0, ln, 1), 1.0)
        ok = np.isfinite(dx) & np.isfinite(dy)
        dx = np.where(ok, dx * f, 0.0)
        dy = np.where(ok, dy * f, 0.0)
        Q[:, 0] -= dx
        Q[:, 1] -= dy
        step = np.where(ok, np.hypot(dx, dy), np.inf)
        if np.all(step <= 1e-15 * (np.abs(Q).sum(axis=1) + 1e-300)):
            break
    return Q, step


def _krawczyk_circles(S: _Sites, T3, M, h):
    """Error-bounded float Krawczyk test for d_a = d_b = d_c on the boxes |q − M|∞ ≤ h (circles and
    points; the box must not meet any of the three sites, so each d is smooth there).

    With Y = J(M)⁻¹: K(B) = M − Y·F(M) + (I − Y·J(B))·(B − M); K(B) ⊂ int B proves a unique zero in
    B (Krawczyk 1969; Moore–Kearfott–Cloud §8.2).  The gradient u = (q − c)/|q − c| of a distance
    to a centre is 1/|q − c|-Lipschitz, so over B (radius ρB = h√2) each gradient moves by at most
    ρB / (|M − c| − ρB): this bounds J(B) − J(M).  Returns (ok, rlo, rhi), the radius of the empty
    circle enclosed."""
    rB = h * math.sqrt(2)
    ds, Us, slack, lip = [], [], [], []
    ok = np.ones(len(M), bool)
    for col in range(3):
        s = T3[:, col]
        V = M - S.C[s]
        n = np.hypot(V[:, 0], V[:, 1])
        g = n - S.R[s]
        sl = rounding_slack(np.abs(M).sum(axis=1) + np.abs(S.C[s]).sum(axis=1) + S.R[s])
        ok &= (np.abs(g) > rB + sl) & (n > rB + sl)
        sig = np.where(g >= 0, 1.0, -1.0)
        with np.errstate(divide="ignore", invalid="ignore"):
            Us.append(sig[:, None] * V / n[:, None])
            lip.append(rB / (n - rB) + 4e-16)
        ds.append(np.abs(g))
        slack.append(sl)
    F = np.column_stack([ds[0] - ds[1], ds[0] - ds[2]])
    eF = np.column_stack([slack[0] + slack[1], slack[0] + slack[2]]) * 1.01 + 1e-300
    J = np.stack([Us[0] - Us[1], Us[0] - Us[2]], axis=1)
    E = np.column_stack([lip[0] + lip[1], lip[0] + lip[2]])      # per row, every entry
    det = J[:, 0, 0] * J[:, 1, 1] - J[:, 0, 1] * J[:, 1, 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        Y = np.stack([np.stack([J[:, 1, 1], -J[:, 0, 1]], 1), np.stack([-J[:, 1, 0], J[:, 0, 0]], 1)], 1) / det[:, None, None]
    aY = np.abs(Y)
    YF = np.abs(np.einsum("nij,nj->ni", Y, F))
    I_YJ = np.abs(np.eye(2)[None] - np.einsum("nij,njk->nik", Y, J)) + 1e-15 * np.einsum("nij,njk->nik", aY, np.abs(J))
    # |Y|·E with E[r, :] = E[:, r]: (|Y| E)_{ik} = sum_j |Y_ij| E_j
    YE = (aY * E[:, None, :]).sum(axis=2)[:, :, None] * np.ones((1, 1, 2))
    bound = YF + np.einsum("nij,nj->ni", aY, eF) + np.einsum("nij,nj->ni", I_YJ + YE, np.column_stack([h, h]))
    bound *= 1 + 1e-12
    ok &= np.isfinite(bound).all(axis=1) & (bound < h[:, None]).all(axis=1) & np.isfinite(det) & (det != 0)
    rlo = ds[0] - slack[0] - rB
    rhi = ds[0] + slack[0] + rB
    return ok, rlo, rhi


def _vertices_circles(S: _Sites, T3, seeds, stats):
    """Refine, merge and prove the candidate vertices of circle/point triples.  Returns
    (cluster id per candidate, list of clusters) where a cluster is a dict with x, y, h, rlo,
    rhi, ok (proved), triple."""
    Q, step = _newton_vertices(S, T3, seeds)
    scale = np.abs(Q).sum(axis=1) + 1.0
    # group candidates of one triple whose Newton points nearly agree
    key = np.lexsort((Q[:, 1], Q[:, 0], T3[:, 2], T3[:, 1], T3[:, 0]))
    cid = np.full(len(T3), -1)
    clusters = []
    cur = None
    for m in key.tolist():
        q = Q[m]
        if not np.all(np.isfinite(q)):
            cid[m] = len(clusters)
            clusters.append({"triple": tuple(int(v) for v in T3[m]), "members": [m], "x": q[0], "y": q[1]})
            continue
        if (cur is not None and cur["triple"] == tuple(int(v) for v in T3[m])
                and abs(q[0] - cur["x"]) + abs(q[1] - cur["y"]) <= 1e-9 * scale[m]):
            cur["members"].append(m)
            cur["spread"] = max(cur["spread"], abs(q[0] - cur["x"]), abs(q[1] - cur["y"]))
            cid[m] = cur["id"]
            continue
        cur = {"triple": tuple(int(v) for v in T3[m]), "members": [m], "x": q[0], "y": q[1],
               "spread": 0.0, "id": len(clusters)}
        cid[m] = cur["id"]
        clusters.append(cur)
    nC = len(clusters)
    M = np.array([[c["x"], c["y"]] for c in clusters]).reshape(-1, 2)
    TT = np.array([c["triple"] for c in clusters], dtype=np.int64).reshape(-1, 3)
    spread = np.array([c.get("spread", 0.0) for c in clusters])
    fin = np.isfinite(M).all(axis=1)
    Mf = np.where(fin[:, None], M, 0.0)
    sc = np.abs(Mf).sum(axis=1) + S.R[TT].max(axis=1) + 1.0
    ok = np.zeros(nC, bool)
    rlo = np.zeros(nC)
    rhi = np.zeros(nC)
    hh = np.zeros(nC)
    for factor in (1e-12, 1e-9, 1e-6):
        todo = fin & ~ok
        if not todo.any():
            break
        h = np.maximum(factor * sc[todo], 4 * spread[todo] + 1e-300)
        o, lo, hi = _krawczyk_circles(S, TT[todo], Mf[todo], h)
        idx = np.nonzero(todo)[0]
        ok[idx[o]] = True
        rlo[idx[o]], rhi[idx[o]], hh[idx[o]] = lo[o], hi[o], h[o]
    stats["krawczyk_filter_failures"] = stats.get("krawczyk_filter_failures", 0) + int((fin & ~ok).sum())
    for c, (o, lo, hi, h) in enumerate(zip(ok, rlo, rhi, hh)):
        clusters[c].update(ok=bool(o), rlo=float(lo), rhi=float(hi), h=float(h), exact=None)
    # exact fallback (thesis §3.1.3) where the filter could not decide
    for c in np.nonzero(~ok)[0].tolist():
        cl = clusters[c]
        stats["exact_vertex_calls"] = stats.get("exact_vertex_calls", 0) + 1
        i, j, k = cl["triple"]
        try:
            tv = voronoi_vertices_circles(S.sites[i], S.sites[j], S.sites[k])
        except (LocatorError, InvalidConicError):
            continue
        if not tv.vertices:
            continue
        sx, sy = (cl["x"], cl["y"]) if np.isfinite(cl["x"]) else tuple(seeds[cl["members"][0]])
        v = min(tv.vertices, key=lambda v: math.hypot(v.x - sx, v.y - sy))
        eps = 4e-16 * (abs(v.x) + abs(v.y) + v.radius) + 1e-300
        cl.update(x=v.x, y=v.y, ok=True, rlo=v.radius - eps, rhi=v.radius + eps, h=eps,
                  exact=(tv, v))
    return cid, clusters


def _vertex_generic(S: _Sites, triple, seed, stats):
    """Refine and prove one vertex of a triple with a conic (runtime.voronoi.vertex)."""
    try:
        from .vertex import certify_vertex, refine_vertex
    except ImportError:
        return None
    geoms = [S.geoms[t] for t in triple]
    sites = [S.sites[t] for t in triple]
    try:
        r = refine_vertex(geoms, float(seed[0]), float(seed[1]))
    except Exception as exc:  # noqa: BLE001 - a failed refinement is a problem, not a crash
        stats.setdefault("vertex_errors", []).append(f"{triple}: {exc}")
        return None
    if r is None:
        return None
    x, y, _ = r
    try:
        pf = certify_vertex(sites, geoms, x, y)
    except Exception as exc:  # noqa: BLE001
        stats.setdefault("vertex_errors", []).append(f"{triple}: {exc}")
        return None
    if pf.box is None or not pf.certified:
        return {"triple": tuple(triple), "x": float(x), "y": float(y), "ok": False, "rlo": 0.0, "rhi": 0.0,
                "h": 0.0, "exact": None, "reason": getattr(pf, "reason", "")}
    (xlo, xhi), (ylo, yhi) = pf.box
    return {"triple": tuple(triple), "x": pf.x, "y": pf.y, "ok": bool(pf.certified),
            "rlo": float(pf.radius_bounds[0]), "rhi": float(pf.radius_bounds[1]),
            "box": ((xlo, xhi), (ylo, yhi)), "h": max(xhi - xlo, yhi - ylo) / 2, "exact": None,
            "radius": pf.radius, "reason": getattr(pf, "reason", "")}


def _vertices_generic(S: _Sites, T3, seeds, stats, cache):
    """Candidates of triples with a conic, one proof per vertex.  ``cache`` (triple -> proved
    vertices of earlier rounds) is reused when a seed lies within a quarter of the radius of exactly
    one proved vertex of its triple."""
    cid = np.full(len(T3), -1)
    clusters = []
    by_triple: dict = {}
    for m in range(len(T3)):
        tr = tuple(int(v) for v in T3[m])
        found = None
        for c in by_triple.get(tr, []):
            cl = clusters[c]
            if cl["ok"] and "box" in cl:
                (xlo, xhi), (ylo, yhi) = cl["box"]
                pad = 0.0
                if xlo - pad <= seeds[m, 0] <= xhi + pad and ylo <= seeds[m, 1] <= yhi:
                    found = c
                    break
        if found is None:
            near = [c for c in cache.get(tr, [])
                    if math.hypot(c["x"] - seeds[m, 0], c["y"] - seeds[m, 1]) < 0.25 * c["rlo"]]
            if len(near) == 1:
                cl = dict(near[0])
                stats["vertex_cache_hits"] = stats.get("vertex_cache_hits", 0) + 1
            else:
                cl = _vertex_generic(S, tr, seeds[m], stats)
                if cl is not None and cl["ok"]:
                    cache.setdefault(tr, []).append(dict(cl))
            if cl is None:
                cl = {"triple": tr, "x": float(seeds[m, 0]), "y": float(seeds[m, 1]), "ok": False,
                      "rlo": 0.0, "rhi": 0.0, "h": 0.0, "exact": None}
            # same triple, box overlapping a proved box: same vertex only if one box holds the other
            for c in by_triple.get(tr, []):
                o = clusters[c]
                if o["ok"] and cl["ok"] and _box_contains(o["box"], cl["box"]):
                    found = c
                    break
                if o["ok"] and cl["ok"] and _box_contains(cl["box"], o["box"]):
                    clusters[c] = dict(cl, members=o["members"])
                    found = c
                    break
            if found is None:
                cl["members"] = []
                found = len(clusters)
                clusters.append(cl)
                by_triple.setdefault(tr, []).append(found)
        clusters[found].setdefault("members", []).append(m)
        cid[m] = found
    return cid, clusters


def _box_contains(a, b):
    (axl, axh), (ayl, ayh) = a
    (bxl, bxh), (byl, byh) = b
    return axl <= bxl and bxh <= axh and ayl <= byl and byh <= ayh


def _emptiness(S: _Sites, clusters, stats):
    """Prove that no site enters the empty circle of each proved vertex; returns, per cluster,
    True (empty, proved), False (a site enters: not a Voronoi vertex) or None (undecided), and the
    conflicting site."""
    idx = [c for c, cl in enumerate(clusters) if cl["ok"]]
    res = [None] * len(clusters)
    culprit = [None] * len(clusters)
    if not idx:
        return res, culprit
    M = np.array([[clusters[c]["x"], clusters[c]["y"]] for c in idx])
    H = np.array([clusters[c]["h"] for c in idx]) * math.sqrt(2)
    RLO = np.array([clusters[c]["rlo"] for c in idx])
    RHI = np.array([clusters[c]["rhi"] for c in idx])
    TT = np.array([clusters[c]["triple"] for c in idx])
    rows, cols = S.near_sites(M, RHI + H)
    keep = (cols != TT[rows, 0]) & (cols != TT[rows, 1]) & (cols != TT[rows, 2])
    rows, cols = rows[keep], cols[keep]
    lo, hi = S.dist_bounds(M[rows], cols)
    lo, hi = lo - H[rows], hi + H[rows]
    safe = lo > RHI[rows]
    conflict = hi < RLO[rows]
    bad = np.zeros(len(idx), bool)
    und = np.zeros(len(idx), bool)
    np.logical_or.at(bad, rows[conflict], True)
    undecided = ~safe & ~conflict
    np.logical_or.at(und, rows[undecided], True)
    first_bad = {}
    depth = (RLO[rows] - hi)[conflict]
    for r, c, dp in zip(rows[conflict].tolist(), cols[conflict].tolist(), depth.tolist()):
        if r not in first_bad or dp < clusters[idx[r]].get("intrusion", np.inf):
            first_bad[r] = c
            clusters[idx[r]]["intrusion"] = dp
    und_pairs: dict = {}
    for r, c in zip(rows[undecided].tolist(), cols[undecided].tolist()):
        und_pairs.setdefault(r, []).append(c)
    stats["emptiness_pairs"] = stats.get("emptiness_pairs", 0) + int(len(rows))
    for a, c in enumerate(idx):
        if bad[a]:
            res[c], culprit[c] = False, first_bad[a]
            continue
        if not und[a]:
            res[c] = True
            continue
        # undecided: the exact circle route when everything is a circle
        cl = clusters[c]
        decided = None
        if S.all_circles:
            decided = True
            try:
                tv, v = cl["exact"] or _exact_vertex(S, cl)
                cl["exact"] = (tv, v)
                for k in und_pairs[a]:
                    stats["exact_conflict_calls"] = stats.get("exact_conflict_calls", 0) + 1
                    dec = decide_conflict(tv, v, as_circle(S.sites[k]))
                    if dec.in_conflict:
                        decided, culprit[c] = False, k
                        break
                    if dec.tangent:      # site k touches the empty circle: a degenerate vertex
                        cl.setdefault("tangent", []).append(k)
            except (LocatorError, InvalidConicError, ValueError):
                decided = None
        if decided is None and culprit[c] is None:
            culprit[c] = und_pairs[a][0]
        res[c] = decided
    return res, culprit


def _exact_vertex(S, cl):
    i, j, k = cl["triple"]
    tv = voronoi_vertices_circles(S.sites[i], S.sites[j], S.sites[k])
    if not tv.vertices:
        raise ValueError("no vertex")
    v = min(tv.vertices, key=lambda v: math.hypot(v.x - cl["x"], v.y - cl["y"]))
    if math.hypot(v.x - cl["x"], v.y - cl["y"]) > 1e-6 * (abs(v.x) + abs(v.y) + v.radius + 1):
        raise ValueError("exact vertex is not the float one")
    return tv, v


# ============================================================================ edges

def _project(S: _Sites, P, I, J, iters=6):
    """Newton steps on f = d_I − d_J along ∇f (foot-point normals): points onto the bisector.
    Points already on it (|f| ≤ 1e-12·scale) stop early.  Returns the points and |f|/2."""
    P = P.copy()
    act = np.arange(len(P))
    res = np.zeros(len(P))
    for it in range(iters + 1):
        if not len(act):
            break
        Q = P[act]
        di, Ui = S.dist_grad(Q, I[act])
        dj, Uj = S.dist_grad(Q, J[act])
        f = di - dj
        res[act] = np.abs(f) / 2
        if it == iters:
            break
        G = Ui - Uj
        g2 = (G * G).sum(axis=1)
        with np.errstate(divide="ignore", invalid="ignore"):
            st = np.where(g2 > 1e-30, f / g2, 0.0)
        lim = 0.25 * np.maximum(di, dj)
        st = np.clip(st, -lim, lim)
        P[act] = Q - st[:, None] * G
        keep = np.abs(f) > 1e-12 * (np.abs(Q).sum(axis=1) + di + 1e-300)
        act = act[keep]
    return P, res


def _offset_estimate(S: _Sites, P, I, J):
    """First-order distance from P to the bisector: |d_I − d_J| / |∇(d_I − d_J)|."""
    di, Ui = S.dist_grad(P, I)
    dj, Uj = S.dist_grad(P, J)
    g = np.hypot(*(Ui - Uj).T)
    return np.abs(di - dj) / np.maximum(g, 1e-3), di


# ============================================================================ the construction

def voronoi(sites, *, certify: bool = True, progress=None, time_limit: float | None = None) -> Diagram:
    """The Voronoi diagram of ``sites`` (thesis §1.2, §5.1–5.2), built by sample-then-refine.

    Parameters
    ----------
    sites : list
        :class:`runtime.circles.Circle`, :class:`runtime.circles.Point`, :class:`runtime.conic.Conic`
        or (cx, cy, r) tuples (r = 0: a point).  Sites must be pairwise disjoint.
    certify : bool
        Run the independent verifier (:func:`runtime.voronoi.verify.verify`) at the end;
        ``diagram.certified`` is its verdict.  Without it the diagram is never certified.
    progress : bool or None
        Show a progress bar (tqdm) over the rounds; None: only for more than 2000 sites.
    time_limit : float or None
        Seconds; when exceeded, the current (partial) diagram is returned, ``certified=False``.

    Returns
    -------
    Diagram
        Vertices are ``certified`` when existence, uniqueness near (x, y) and emptiness were
        proved.  Edge polylines join the end vertices through points projected onto the bisector;
        ``tolerance`` is the measured max(|d_i − d_j|/2 at the points, chord-midpoint deviation),
        not a proof; the edges' proof is the verifier's.

    Examples
    --------
    >>> import curvedvoronoi as cv
    >>> d = cv.voronoi([(0, 0, 1), (4, 0, 1), (2, 4, 1)], certify=False)
    >>> len(d.vertices), d.delaunay_edges()
    (1, [(0, 1), (0, 2), (1, 2)])
    """
    t_start = time.perf_counter()
    deadline = None if time_limit is None else t_start + float(time_limit)
    sites = [as_site(s) for s in sites]
    if len(sites) < 2:
        raise ValueError(f"the Voronoi diagram needs at least 2 sites, got {len(sites)}")
    geoms = [site_geometry(s) for s in sites]
    notes = check_disjoint(sites, geoms)
    S = _Sites(sites, geoms)
    stats: dict = {"sites": len(sites), "rounds": 0, "samples": 0}
    if S.all_circles and not S.R.any() and _collinear(S.C):
        return _finish_collinear(S, sites, notes, certify, stats, t_start)
    timing = {"input": time.perf_counter() - t_start}
    spacing = _initial_spacing(S)
    if progress is None:
        progress = len(sites) > 2000
    bar = None
    if progress:
        try:
            from tqdm import tqdm
            bar = tqdm(desc="voronoi rounds", unit="round", leave=False)
        except ImportError:
            bar = None
    result = None
    interrupted = False
    cache: dict = {}
    try:
        verify = None
        if certify:
            try:
                from .verify import verify
            except ImportError:
                verify = None
        for vround in range(VERIFY_ROUNDS):
            result = _rounds(S, spacing, stats, timing, deadline, cache, bar)
            D = result["diagram"]
            t0 = time.perf_counter()
            D.edges = _edge_geometry(S, result["tri"], D.vertices, result["edges_raw"])
            timing["edges"] = timing.get("edges", 0) + time.perf_counter() - t0
            if not certify or verify is None or result.get("timed_out") or D.problems:
                break
            t0 = time.perf_counter()
            cert = verify(D, sites)
            timing["verify"] = timing.get("verify", 0) + time.perf_counter() - t0
            result["certificate"] = cert
            named = _sites_named(cert.problems, D) if not cert.ok else set()
            if cert.ok or not named or (deadline is not None and time.perf_counter() > deadline):
                break
            # the verifier found what the sampling missed: refine the sites it names and rebuild
            stats["verify_refinements"] = stats.get("verify_refinements", 0) + 1
            idx = np.array(sorted(named), dtype=int)
            spacing[idx] = spacing[idx] / 4
            spacing = _clamp_spacing(S, spacing, MAX_SAMPLES)
    except KeyboardInterrupt:
        if result is None or "diagram" not in result:
            raise
        interrupted = True
    finally:
        if bar is not None:
            bar.close()
    D = result["diagram"]
    if interrupted and not D.edges and result.get("edges_raw"):
        D.edges = _edge_geometry(S, result["tri"], D.vertices, result["edges_raw"])
    D.problems[:0] = notes
    D.stats.update(stats)
    if result.get("timed_out"):
        D.problems.append(f"time limit of {time_limit} s reached: partial diagram")
    if interrupted:
        D.problems.append("interrupted (Ctrl-C): partial diagram of the last finished round")
    cert = result.get("certificate")
    if not certify:
        D.problems.append("not verified (certify=False)")
    elif verify is None:
        D.problems.append("verifier runtime.voronoi.verify not available: edges not proved")
    elif cert is not None and not interrupted:
        vertices_ok = all(v.certified for v in D.vertices)
        D.certified = bool(cert.ok) and vertices_ok and not D.problems
        D.problems.extend(cert.problems)
        for e, ok in zip(D.edges, cert.edges):
            e.certified = bool(ok)
        for v, ok in zip(D.vertices, cert.vertices):
            v.certified = v.certified and bool(ok)
    elif not D.problems:
        D.problems.append("not verified")
    timing["total"] = time.perf_counter() - t_start
    D.stats["seconds"] = {k: round(v, 4) for k, v in timing.items()}
    return D


def _collinear(C) -> bool:
    """Are the points C (float) on one line (exactly, with the exact float values)?"""
    from fractions import Fraction

    if len(C) < 3:
        return True
    p0 = [Fraction(v) for v in C[0]]
    far = max(range(len(C)), key=lambda m: abs(C[m, 0] - C[0, 0]) + abs(C[m, 1] - C[0, 1]))
    d = [Fraction(C[far, 0]) - p0[0], Fraction(C[far, 1]) - p0[1]]
    return all(d[0] * (Fraction(y) - p0[1]) - d[1] * (Fraction(x) - p0[0]) == 0 for x, y in C.tolist())


def _finish_collinear(S, sites, notes, certify, stats, t_start):
    """Collinear point sites (no triangulation exists): the edges are the perpendicular bisectors of
    consecutive points along the line, each a whole line without vertices."""
    C = S.C
    d = C[np.argmax(np.abs(C - C[0]).sum(axis=1))] - C[0]
    d = d / np.hypot(*d)
    order = np.argsort(C @ d, kind="stable")
    nrm = np.array([-d[1], d[0]])
    far = 2.0 * (S.window[2] - S.window[0])
    edges = []
    for a, b in zip(order[:-1].tolist(), order[1:].tolist()):
        m = (C[a] + C[b]) / 2
        poly = np.array([m - far * nrm, m, m + far * nrm])
        tol = float(rounding_slack(np.abs(poly).sum(axis=1).max() + np.abs(C[[a, b]]).sum()))
        edges.append(DiagramEdge(len(edges), (min(a, b), max(a, b)), (None, None), False, poly, tol, False))
    D = Diagram(S.sites, [], edges, False, list(notes), stats)
    if certify:
        try:
            from .verify import verify
        except ImportError:
            D.problems.append("verifier runtime.voronoi.verify not available: edges not proved")
        else:
            cert = verify(D, sites)
            D.certified = bool(cert.ok) and not notes
            D.problems.extend(cert.problems)
            for e, ok in zip(D.edges, cert.edges):
                e.certified = bool(ok)
    else:
        D.problems.append("not verified (certify=False)")
    D.stats["seconds"] = {"total": round(time.perf_counter() - t_start, 4)}
    return D


def _rounds(S, spacing, stats, timing, deadline, cache, bar):
    """Sample-triangulate-prove rounds until the combinatorics are consistent (or MAX_ROUNDS)."""
    result = None
    for _ in range(MAX_ROUNDS):
        stats["rounds"] = stats.get("rounds", 0) + 1
        result, refine = _build_once(S, spacing, stats, timing, deadline, cache)
        if bar is not None:
            bar.update(1)
        if not refine or result.get("timed_out"):
            break
        idx = np.array(sorted(refine), dtype=int)
        cap = np.array([refine[i] for i in idx.tolist()])
        spacing[idx] = np.minimum(spacing[idx] / 2, cap)
        spacing[:] = _clamp_spacing(S, spacing, MAX_SAMPLES)
    return result


#: verifier problems that show a fault of the reported diagram (a refinement can fix them); other
#: lines (limits of what the verifier proves, e.g. "not proved beyond ...") do not trigger rebuilds
_FAULT = re.compile(r"closer than its sites|too close to decide|share no site|no single site owns|is missing|"
                    r"has no edge|ends? here|do not close up|not on the arc|overlap|more than once|the vertex \(")
_NAMED = re.compile(r"\b(sites?|edges?|vertex|vertices)\s+((?:\d+(?:\s*(?:,|and)\s*)?)+)")


def _sites_named(problems, D):
    """The sites a verifier's problem lines name: "site 3", "sites 3, 5", "edge 7", "edges 8 and 9",
    "vertex 2" (edges and vertices stand for their sites)."""
    out: set = set()
    for p in problems:
        if not _FAULT.search(p):       # a limitation of the verifier, not a fault of the diagram
            continue
        for kind, nums in _NAMED.findall(p):
            for t in re.findall(r"\d+", nums):
                t = int(t)
                if kind.startswith("site") and t < len(D.sites):
                    out.add(t)
                elif kind.startswith("edge") and t < len(D.edges):
                    out.update(D.edges[t].sites)
                elif kind.startswith("vert") and t < len(D.vertices):
                    out.update(D.vertices[t].sites)
    return out


def _build_once(S: _Sites, spacing, stats, timing, deadline, cache):
    """One sampling + triangulation + vertices + edges pass.  Returns ({"diagram": D}, sites to
    refine)."""
    t0 = time.perf_counter()
    P, lab = _sample(S, spacing)
    tri = _Triangulation(P, lab)
    stats["samples"] = int(len(P))
    timing["sample+delaunay"] = timing.get("sample+delaunay", 0) + time.perf_counter() - t0
    t1 = time.perf_counter()
    raw = tri.walks()
    timing["walks"] = timing.get("walks", 0) + time.perf_counter() - t1
    t2 = time.perf_counter()
    threes = np.nonzero(tri.nlab == 3)[0]
    T3 = np.sort(tri.L[threes], axis=1)
    seeds = tri.cc[threes]
    if S.all_circles:
        cid, clusters = _vertices_circles(S, T3, seeds, stats)
    else:
        cid, clusters = _vertices_generic(S, T3, seeds, stats, cache)
    empty, culprit = _emptiness(S, clusters, stats)
    timing["vertices"] = timing.get("vertices", 0) + time.perf_counter() - t2
    timed_out = deadline is not None and time.perf_counter() > deadline
    t3 = time.perf_counter()
    refine: dict = {}   # site -> spacing cap (inf: halve)
    problems: list[str] = []

    def ask(sites_, cap=np.inf):
        for t in sites_:
            refine[int(t)] = min(refine.get(int(t), np.inf), cap)

    # final vertices: proved, empty clusters
    tri_to_vertex = {}
    vertices: list[DiagramVertex] = []
    cluster_vid = {}
    for c, cl in enumerate(clusters):
        tr = cl["triple"]
        if cl["ok"] and empty[c] is True:
            if cl.get("tangent"):
                problems.append(f"sites {tr[0]}, {tr[1]}, {tr[2]}: degenerate vertex at ({cl['x']:.6g}, "
                                f"{cl['y']:.6g}): site(s) {', '.join(map(str, cl['tangent']))} touch its empty "
                                "circle exactly (a vertex of degree > 3, reported as several vertices)")
            vid = len(vertices)
            cluster_vid[c] = vid
            r = float(cl.get("radius") or 0.0) or float((cl["rlo"] + cl["rhi"]) / 2)
            vertices.append(DiagramVertex(vid, tr, float(cl["x"]), float(cl["y"]), r, True))
        else:
            # a site entering the circle by δ: samples s apart misplace distances near a vertex of
            # radius r by about s²/(8r), so s = √(2 r δ) separates the two configurations
            dp = cl.get("intrusion")
            cap = math.sqrt(2 * max(cl["rlo"], 0.0) * dp) if dp is not None and dp > 0 else np.inf
            ask(tr, cap)
            if culprit[c] is not None:
                ask([culprit[c]], cap)
            if not cl["ok"]:
                problems.append(f"sites {tr[0]}, {tr[1]}, {tr[2]}: candidate vertex near "
                                f"({cl['x']:.6g}, {cl['y']:.6g}) not proved")
            elif empty[c] is False:
                problems.append(f"sites {tr[0]}, {tr[1]}, {tr[2]}: candidate vertex at ({cl['x']:.6g}, "
                                f"{cl['y']:.6g}) is not empty (site {culprit[c]} enters its circle)")
            else:
                problems.append(f"sites {tr[0]}, {tr[1]}, {tr[2]}: emptiness of the vertex at "
                                f"({cl['x']:.6g}, {cl['y']:.6g}) undecided (site {culprit[c]})")
    for m, t in enumerate(threes.tolist()):
        c = int(cid[m])
        if c in cluster_vid:
            tri_to_vertex[t] = cluster_vid[c]
    # edges
    edges_raw = []
    degree = [[] for _ in vertices]
    for pair, start, chain, end in raw:
        if (start is not None and start[0] == "bad") or (end is not None and end[0] == "bad"):
            ask(pair)
            problems.append(f"sites {pair[0]}, {pair[1]}: an edge walk could not be closed")
            continue
        ends = []
        okv = True
        for e in (start, end):
            if e is None or e[0] == "hull":
                ends.append(None)
            else:
                v = tri_to_vertex.get(e[1])
                if v is None:
                    okv = False
                ends.append(v)
        if not okv:
            ask(pair)
            continue
        if ends[0] is not None and ends[0] == ends[1]:
            continue   # between two triangles of one vertex
        for v in ends:
            if v is not None:
                degree[v].append(pair)
        edges_raw.append((pair, start, chain, end, ends))
    for v in vertices:
        a, b, c = v.sites
        if sorted(degree[v.id]) != sorted([(a, b), (a, c), (b, c)]):
            ask(v.sites)
            problems.append(f"sites {a}, {b}, {c}: the vertex at ({v.x:.6g}, {v.y:.6g}) has incident edges "
                            f"{sorted(degree[v.id])}, expected ({a}, {b}), ({a}, {c}), ({b}, {c})")
    timing["walks"] += time.perf_counter() - t3
    stats["candidate_triangles"] = int(len(threes))
    D = Diagram(S.sites, vertices, [], False, problems, {})
    return {"diagram": D, "timed_out": timed_out, "tri": tri, "edges_raw": edges_raw}, \
        ({} if timed_out else refine)


def _edge_geometry(S: _Sites, tri: _Triangulation, vertices, edges_raw):
    """Polylines of the edges: vertex, projected circumcentres, vertex (hull ends extended to the
    window), with their measured tolerance."""
    pts, I, J, owner, fixed = [], [], [], [], []
    far = 2.0 * (S.window[2] - S.window[0])
    for e, (pair, start, chain, end, ends) in enumerate(edges_raw):
        seq = []
        flags = []
        if start is not None and start[0] == "hull":
            seq.append(_hull_point(tri, start, chain[0] if chain else None, far))
            flags.append(False)
        elif ends[0] is not None:
            v = vertices[ends[0]]
            seq.append((v.x, v.y))
            flags.append(True)
        cap = MAX_EDGE_POINTS if S.all_circles else MAX_EDGE_POINTS // 3
        if len(chain) > cap:
            chain = [chain[m] for m in np.linspace(0, len(chain) - 1, cap).round().astype(int)]
        for t in chain:
            seq.append(tuple(tri.cc[t]))
            flags.append(False)
        if end is None:               # closed
            seq.append(seq[0])
            flags.append(False)
        elif end[0] == "hull":
            base = chain[-1] if chain else None
            seq.append(_hull_point(tri, end, base, far, vertex=vertices[ends[0]] if (not chain and ends[0] is not None) else None))
            flags.append(False)
        else:
            v = vertices[ends[1]]
            seq.append((v.x, v.y))
            flags.append(True)
        pts.extend(seq)
        fixed.extend(flags)
        I.extend([pair[0]] * len(seq))
        J.extend([pair[1]] * len(seq))
        owner.extend([e] * len(seq))
    if not pts:
        return []
    P = np.array(pts, dtype=float)
    I = np.array(I)
    J = np.array(J)
    owner = np.array(owner)
    fixed = np.array(fixed)
    free = ~fixed
    Pp = P.copy()
    if free.any():
        Pp[free], _ = _project(S, P[free], I[free], J[free])
    starts = np.searchsorted(owner, np.arange(len(edges_raw)))
    stops = np.searchsorted(owner, np.arange(len(edges_raw)), side="right")
    tau = _leaving_directions(S, vertices, edges_raw)
    polys = []
    for e in range(len(edges_raw)):
        polys.append(_trim(Pp[starts[e]:stops[e]], tau.get((e, 0)), tau.get((e, 1))))
    # measured tolerance on the final polylines: residual at the points, offset of chord midpoints
    lens = np.array([len(p) for p in polys])
    own = np.repeat(np.arange(len(polys)), lens)
    Q = np.concatenate(polys)
    PI = np.array([edges_raw[e][0][0] for e in range(len(polys))])
    PJ = np.array([edges_raw[e][0][1] for e in range(len(polys))])
    if S.all_circles:
        Q, own = _densify(S, Q, own, PI, PJ)
    else:   # conic foot points are costlier: a coarser target
        Q, own = _densify(S, Q, own, PI, PJ, rel=10 * DENSIFY_REL, passes=3)
    pi, pj = PI[own], PJ[own]
    same = own[1:] == own[:-1]
    di, _ = S.dist_grad(Q, pi)
    dj, _ = S.dist_grad(Q, pj)
    tol = np.zeros(len(polys))
    np.maximum.at(tol, own, np.abs(di - dj) / 2)
    mids = ((Q[1:] + Q[:-1]) / 2)[same]
    if len(mids):
        np.maximum.at(tol, own[1:][same], _offset_estimate(S, mids, pi[1:][same], pj[1:][same])[0])
    edges = []
    cuts = np.searchsorted(own, np.arange(len(polys) + 1))
    for e, (pair, start, chain, end, ends) in enumerate(edges_raw):
        poly = Q[cuts[e]:cuts[e + 1]].copy()
        closed = end is None and start is None
        if closed:
            poly[-1] = poly[0]
        edges.append(DiagramEdge(e, pair, (ends[0], ends[1]), closed, poly, float(tol[e]), False))
    return edges


def _densify(S: _Sites, Q, own, PI, PJ, rel=DENSIFY_REL, passes=6):
    """Insert projected chord midpoints where a chord strays from the bisector by more than
    ``rel`` times the distance to the sites there (a few vectorised passes; after the first pass
    only the halves of split chords are examined)."""
    check = np.ones(len(Q), bool)          # examine the chord starting at this point
    for _ in range(passes):
        same = np.nonzero((own[1:] == own[:-1]) & check[:-1])[0]
        if not len(same):
            break
        mids = (Q[same] + Q[same + 1]) / 2
        a, b = PI[own[same]], PJ[own[same]]
        off, dloc = _offset_estimate(S, mids, a, b)
        seg = np.hypot(*(Q[same + 1] - Q[same]).T)
        split = (off > rel * np.maximum(dloc, 1e-12 * S.scale)) & (seg > 1e-9 * S.scale)
        if not split.any():
            break
        k = same[split]
        newp, _ = _project(S, mids[split], a[split], b[split])
        check[:] = False
        check[k] = True
        Q = np.insert(Q, k + 1, newp, axis=0)
        own = np.insert(own, k + 1, own[k])
        check = np.insert(check, k + 1, True)
    return Q, own


def _leaving_directions(S: _Sites, vertices, edges_raw):
    """For each vertex end of an edge (i, j), the unit tangent of the bisector at the vertex pointing
    into the edge: the side where the third site k of the vertex is farther than i and j."""
    keys, V, I, J, K = [], [], [], [], []
    for e, (pair, _, _, _, ends) in enumerate(edges_raw):
        for side, v in enumerate(ends):
            if v is None:
                continue
            vx = vertices[v]
            k = [t for t in vx.sites if t not in pair]
            if len(k) != 1:
                continue
            keys.append((e, side))
            V.append((vx.x, vx.y))
            I.append(pair[0])
            J.append(pair[1])
            K.append(k[0])
    if not keys:
        return {}
    V = np.array(V)
    _, Ui = S.dist_grad(V, np.array(I))
    _, Uj = S.dist_grad(V, np.array(J))
    _, Uk = S.dist_grad(V, np.array(K))
    G = Ui - Uj
    T = np.column_stack([-G[:, 1], G[:, 0]])
    sgn = np.where(((Uk - Ui) * T).sum(axis=1) < 0, -1.0, 1.0)
    T = T * sgn[:, None]
    T /= np.maximum(np.hypot(T[:, 0], T[:, 1]), 1e-300)[:, None]
    return {k: T[m] for m, k in enumerate(keys)}


def _trim(poly, t0, t1):
    """Drop interior polyline points lying behind an end vertex (the circumcentres of the sample
    triangles next to a vertex may overshoot it along the bisector)."""
    if len(poly) <= 2:
        return poly
    keep = np.ones(len(poly), bool)
    if t0 is not None:
        for m in range(1, len(poly) - 1):
            if np.dot(poly[m] - poly[0], t0) > 0:
                break
            keep[m] = False
    if t1 is not None:
        for m in range(len(poly) - 2, 0, -1):
            if np.dot(poly[m] - poly[-1], t1) > 0:
                break
            keep[m] = False
    return poly[keep]


def _hull_point(tri, end, t_chain, far, vertex=None):
    """A far point along the outward normal of a bichromatic hull side (the edge goes to infinity)."""
    _, t, k = end
    a = tri.simp[t, (k + 1) % 3]
    b = tri.simp[t, (k + 2) % 3]
    A, B = tri.P[a], tri.P[b]
    opp = tri.P[tri.simp[t, k]]
    d = B - A
    n = np.array([-d[1], d[0]])
    if np.dot(n, opp - A) > 0:
        n = -n
    n = n / (np.hypot(*n) or 1.0)
    base = tri.cc[t_chain] if t_chain is not None else (np.array([vertex.x, vertex.y]) if vertex is not None
                                                        else (A + B) / 2)
    mid = (A + B) / 2
    base = base if np.all(np.isfinite(base)) else mid
    start = mid if np.dot(base - mid, n) < 0 else base
    return tuple(start + far * n)
