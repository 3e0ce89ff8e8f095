"""Rigorous distance bounds for many (point, site) pairs at once, for the diagram verifier.

The proofs of :mod:`runtime.voronoi.verify.strips` and :mod:`runtime.voronoi.verify.tail` ask,
again and again, for enclosures of d(q, S_k) and of ∇d(q, S_k) at a few points q of one edge.
Asked site by site and edge by edge, the cost is the fixed cost of a numpy call (about a
millisecond for a conic's foot points), not the arithmetic.  :class:`SiteTable` holds the float
data of every point, circle and ellipse site in flat arrays and evaluates one call for any mix of
(point, site) pairs; :func:`run_lockstep` runs the edge proofs (generators that yield their
requests) side by side so that one call serves every edge.

Bounds (the same as :mod:`runtime.voronoi.geometry` and :mod:`runtime.voronoi.conic_geometry`,
vectorised over the sites as well as the points):

* point / circle: d = | |q − c| − ρ |, widened by ``rounding_slack`` of the data's size;
* ellipse (thesis §5.2; :mod:`runtime.voronoi.conic_geometry`, *Rigorous bounds*): in the float
  canonical frame of the site's geometry, a float foot parameter t
  (:func:`runtime.voronoi.conic_geometry.ellipse_feet`, many ellipses at once; any accuracy is
  sound) gives the upper bound
  |Q − P(t)| and, for Q outside K, the supporting-line lower bound n(t)·(Q − P(t)) (K convex);
  every value is widened by the rounding allowances of that module (ε_P, the normal's rounding,
  the frame's slack σ).  Pairs where these bounds are not tight to 1e-7 relative (Q inside K,
  near the evolute, non-finite), and every pair with a site of another kind (hyperbola,
  parabola), are handed to the site geometry's own ``distance_bounds``, which is exact to
  float resolution (S-lemma, ball route).  So the table never claims more than the site
  geometries do; it only saves their per-call cost where the cheap bound already decides;
* parabola: the site geometry's own bounds; outside its convex focus side K the gradient
  enclosures below apply;
* hyperbola (both branches one site, X²/a² − Y²/b² = 1 canonical): the site geometry's own
  bounds.  Each branch bounds a convex region K_± (its focus side) and the nearer branch of q is
  the one of the sign of X (for X > 0 the mirror image p = (−X', Y') of a point (X', Y') of the
  left branch lies on the right branch and |q − p| ≤ |q − (X', Y')|), so on a disc that does
  not reach the conjugate axis X = 0 (``sep``, with a margin for the float frame) d is the
  distance to one branch: outside K_± (q between the branches) the
  gradient enclosure of the convex set K_± below applies, inside K_± the one of the inside
  (reach b²/a).  Discs reaching the conjugate axis, where d = min(d_+, d_−) has a ridge and the
  bisectors a corner, get no enclosure.

**Gradient enclosures** (:func:`gradient_enclosure`) for a convex site S and q outside its convex
hull K: ∇d(q) = (q − p)/|q − p| with p the projection of q on K; I − p, like p, is firmly
non-expansive, hence 1-Lipschitz (Bauschke–Combettes, *Convex Analysis and Monotone Operator
Theory*, ch. 4), and x ↦ x/|x| is (1/m)-Lipschitz on {|x| ≥ m} (m·x/|x| is the projection onto
the ball of radius m).  So for q ∈ B(c, R), with x = c − p(c), y = q − p(q), |x − y| ≤ R and
|x|, |y| ≥ d(c) − R: |∇d(q) − ∇d(c)| ≤ R/(d(c) − R); and the float foot point F gives ∇d(c)
within e_F/d(c), where
e_F² = |c − F|² − d(c)² bounds |F − p|² (projection inequality |c − F|² ≥ |c − p|² + |p − F|²,
F ∈ K up to rounding; |c − F| ≥ d(c)).  **Inside** a circle, an ellipse, a parabola or a hyperbola
branch (q in its open convex region, depth d(q) below the reach r of the curve, b²/a, the
radius, p for Y² = 2pX, b²/a for a hyperbola branch: Federer, *Curvature
measures*, Trans. AMS 93 (1959), 4.8 and 4.18): the nearest point p(q) is unique, ∇d(q) =
(q − p)/|q − p|, p is r/(r − t)-Lipschitz where the depth is ≤ t, and for every F on the curve
(c − p)·(F − p) ≤ |F − p|²·d/(2r), so |F − p|² ≤ (|c − F|² − d²)/(1 − d/r); with t = hi + R < r
the enclosure is e_F/d + (1 + r/(r − t))·R/(d − R).  Deeper inside a circle or an ellipse (or
where that enclosure is wider than 0.05), on discs off the medial segment (a circle: its centre),
the distance is C¹ and the box of its Clarke gradient
(:func:`runtime.voronoi.verify.clarke_gradient.off_ridge_gradient`) is used where tighter.

**Groups of sites** (:class:`BoxTree`, for :meth:`SiteTable.near_pairs` with levels).  The
third-site test (T2) of :mod:`runtime.voronoi.verify.strips` proves a site k farther than s = i or
j on a piece's disc B(C, R) by the supporting half-plane of k
(:func:`runtime.voronoi.verify.strips._support_half_planes`): with a unit vector u, the level
base = u·(C − m) − hi_s(C) − R²/(2(lo_s(C) − R)) − 2e·R − 10⁻¹²·size and h_k(u) the support
function of S_k about m, the row passes when base − h − 2·mu − 10⁻¹²·|h| > 0 for an upper bound h
of h_k(u) (the inequality only gets weaker when h grows).  Far from the sites a piece's reach
holds nearly every site, and almost all of them pass; listing them one by one costs more than
the proof.

Here the sites' bounding boxes are held in a binary tree: each node holds a contiguous range of
the sites, split at the median of the box centres along the longer extent, down to leaves of at
most :data:`GROUP_LEAF` sites, and a disc (centre c_g, radius ρ_g) around the union of its boxes
(the half-diagonal from the centre, rounded up).  A site lies in its bounding box, so for every site
k of a node and every float unit u (|u| ≤ 1 + 4u, absorbed in mu, as the rounding of the dot
product is),

    h_k(u) = max over p in S_k of u·(p − m) ≤ u·(c_g − m) + ρ_g,

and a node whose bound passes the test above is dropped for that row with all its sites.  A node
is also dropped when its disc lies beyond the row's reach, |C − c_g| − ρ_g > reach (widened by
the caller): every box in it is then farther than the reach, as the listing requires.
:meth:`BoxTree.walk` descends the tree for all rows at once, level by level, and returns the
sites of the leaves it reaches; what it leaves out is beyond the reach or proved farther, so the
caller's tests see the same undecided sites as with the full listing.

Length: one table and what is read from it row by row — the distance bounds, the third-site
listing (:meth:`SiteTable.near_pairs`), the gradient enclosures — and the lockstep driver.
"""
from __future__ import annotations

import itertools

import time

import numpy as np
from scipy.spatial import cKDTree

from ...sites.foot_points import ellipse_feet
from ...sites.kinds import SiteKind
from ..geometry import EPS, rounding_slack
from .clarke_gradient import off_ridge_gradient
from .ellipse_normal import ellipse_normal_enclosure, frame_errors, tight_gradients

__all__ = ["BoxTree", "SiteTable", "SiteValues", "gradient_enclosure", "run_lockstep"]

#: relative gap above which the table defers to the site geometry's own bounds
FALLBACK_GAP = 1e-7
#: rows per block of :func:`gradient_enclosure`
GRADIENT_ROWS = 50_000
#: :meth:`SiteTable.near_pairs` with levels walks the groups of sites for rows whose reach is at
#: least this many half-diagonals of the largest bounding box (nearer rows: the k-d tree)
GROUP_REACH = 8.0
#: most sites in a leaf of the tree of :class:`BoxTree`
GROUP_LEAF = 4


class SiteValues:
    """Values of :meth:`SiteTable.evaluate` at rows (q, k): rigorous ``lo`` ≤ d(q, S_k) ≤ ``hi``,
    a float foot point ``F`` (on S_k up to rounding), its float distance ``d``, ``base``: q
    proved outside the convex region K that F's curve bounds (for a hyperbola: the branch of
    F, q between the branches), ``inner``: q proved inside the convex region of a circle,
    ellipse, parabola or hyperbola branch whose boundary has reach ``reach``, ``sep``: a lower
    bound of the distance from q to the line where the nearest branch of a hyperbola may switch
    (its conjugate axis; +inf for the other kinds), ``K`` the site of each row and ``table``
    the :class:`SiteTable` (for the tight ellipse gradients of :func:`gradient_enclosure`).
    Gradient enclosures hold on discs of radius R < ``sep`` (module docstring)."""

    __slots__ = ("lo", "hi", "F", "d", "base", "inner", "reach", "sep", "K", "table")

    def __init__(self, lo, hi, F, d, base, inner, reach, sep, K=None, table=None):
        self.lo, self.hi, self.F, self.d, self.base, self.inner, self.reach = lo, hi, F, d, base, inner, reach
        self.sep = sep
        self.K, self.table = K, table

    def part(self, a, b):
        return SiteValues(self.lo[a:b], self.hi[a:b], self.F[a:b], self.d[a:b], self.base[a:b],
                          self.inner[a:b], self.reach[a:b], self.sep[a:b],
                          None if self.K is None else self.K[a:b], self.table)

    def take(self, idx):
        return SiteValues(self.lo[idx], self.hi[idx], self.F[idx], self.d[idx], self.base[idx],
                          self.inner[idx], self.reach[idx], self.sep[idx],
                          None if self.K is None else self.K[idx], self.table)


class SiteTable:
    """Flat float data of the sites (kinds point / circle / ellipse; others via their geometry),
    their bounding boxes and a k-d tree on the boxes' centres (:meth:`near_pairs`)."""

    def __init__(self, geoms, scale):
        self.geoms = geoms
        self.scale = float(scale)
        n = len(geoms)
        self.n = n
        self.kind = np.zeros(n, int)          # SiteKind codes (int(SiteKind.POINT) = 0)
        self.cx, self.cy, self.rho = np.zeros(n), np.zeros(n), np.zeros(n)
        self.a, self.b, self.c, self.s = np.ones(n), np.ones(n), np.ones(n), np.zeros(n)
        for k, g in enumerate(geoms):
            kind = SiteKind.of(g.kind)
            if kind not in (SiteKind.POINT, SiteKind.CIRCLE, SiteKind.ELLIPSE, SiteKind.HYPERBOLA, SiteKind.PARABOLA):
                raise ValueError(f"site {k}: the site table holds points and conics, not a {kind.label}")
            self.kind[k] = kind
            if kind == SiteKind.POINT:
                self.cx[k], self.cy[k] = g.x0, g.y0
            elif kind == SiteKind.CIRCLE:
                self.cx[k], self.cy[k], self.rho[k] = g.cx, g.cy, g.rho
            elif kind == SiteKind.ELLIPSE:
                self.cx[k], self.cy[k], self.a[k], self.b[k], self.c[k], self.s[k] = g.tx, g.ty, g.a, g.b, g.c, g.s
        # convex K (the inside of an ellipse, the focus side of a parabola; not a hyperbola's two
        # regions): the site is the boundary of one convex set
        self.convex = self.kind != SiteKind.HYPERBOLA
        # reach of the boundary from inside (Federer): b²/a for an ellipse (a ≥ b: the ends of
        # the medial axis are the centres of curvature at the major vertices), r for a circle;
        # b²/a for a hyperbola branch X²/a² − Y²/b² = 1 and p for a parabola Y² = 2pX (the
        # radius of curvature at the vertex, the least one; the medial axis of the convex side is
        # the axis ray from that centre of curvature: the depth is concave on the convex side,
        # unbounded along the ray, hence non-decreasing there)
        lo_ax, hi_ax = np.minimum(self.a, self.b), np.maximum(self.a, self.b)
        self.reach = np.where(self.kind == SiteKind.ELLIPSE, lo_ax * lo_ax / hi_ax,
                              np.where(self.kind == SiteKind.CIRCLE, self.rho, 0.0))
        for k, g in enumerate(geoms):
            if g.kind == "hyperbola":
                self.reach[k] = g.b * g.b / g.a
            elif g.kind == "parabola":
                self.reach[k] = g.p
        self.reach = self.reach * (1 - 1e-9)
        self.boxes = np.array([g.bounding_box() for g in geoms], float).reshape(-1, 4)
        # a k-d tree on the centres of the finite bounding boxes (radius: their half-diagonals)
        fin = np.isfinite(self.boxes).all(1)
        self.bounded = np.nonzero(fin)[0]
        self.unbounded = np.nonzero(~fin)[0]
        bx = self.boxes[fin]
        self.box_centre = 0.5 * (bx[:, :2] + bx[:, 2:])
        self.box_half = float((0.5 * np.hypot(bx[:, 2] - bx[:, 0], bx[:, 3] - bx[:, 1])).max()) if len(bx) else 0.0
        self.tree = cKDTree(self.box_centre) if len(bx) else None
        self.calls = 0
        self.fallbacks = 0
        self.tight_rows = 0
        self._frame_err = np.full((n, 6), np.nan)     # frame_errors of the ellipses, when needed
        self._groups = None                            # near_pairs' groups of sites, when needed

    # ------------------------------------------------------------------ tight ellipse gradients
    def ellipse_normals(self, Q, K, F):
        """(G, e, ok): |∇d(q, S_k) − G| ≤ e at the float points Q[m] outside the ellipses
        K[m] where ok (:func:`runtime.voronoi.verify.ellipse_normal.ellipse_normal_enclosure`;
        F: float foot points, a start only)."""
        K = np.asarray(K, int)
        for k in np.unique(K[np.isnan(self._frame_err[K, 0])]):
            g = self.geoms[k]
            self._frame_err[k] = frame_errors(g.exact, g.c, g.s, g.tx, g.ty, g.a, g.b)
        errs = self._frame_err[K]
        self.tight_rows += len(K)
        return ellipse_normal_enclosure(Q, F, self.a[K], self.b[K], self.c[K], self.s[K], self.cx[K],
                                        self.cy[K], errs)

    # ------------------------------------------------------------------ rigorous values
    def evaluate(self, Q, K) -> SiteValues:
        """Bounds, float feet and the outside flags at the rows (Q[m], K[m])."""
        Q = np.asarray(Q, float).reshape(-1, 2)
        K = np.asarray(K, int).reshape(-1)
        self.calls += 1
        m = len(K)
        lo, hi, d = np.zeros(m), np.full(m, np.inf), np.full(m, np.inf)
        F = np.full((m, 2), np.nan)
        base = np.zeros(m, bool)
        inner = np.zeros(m, bool)
        sep = np.full(m, np.inf)
        loose = np.zeros(m, bool)
        kind = self.kind[K]
        x, y = Q[:, 0], Q[:, 1]
        # ---- points and circles
        r = np.nonzero((kind == SiteKind.POINT) | (kind == SiteKind.CIRCLE))[0]
        if len(r):
            k = K[r]
            cx, cy, rho = self.cx[k], self.cy[k], self.rho[k]
            vx, vy = x[r] - cx, y[r] - cy
            nv = np.hypot(vx, vy)
            dd = np.abs(nv - rho)
            sl = rounding_slack(np.abs(x[r]) + np.abs(y[r]) + np.abs(cx) + np.abs(cy) + rho)
            lo[r], hi[r], d[r] = np.maximum(dd - sl, 0.0), dd + sl, dd
            with np.errstate(divide="ignore", invalid="ignore"):
                ux, uy = np.where(nv > 0, vx / nv, 1.0), np.where(nv > 0, vy / nv, 0.0)
            F[r, 0], F[r, 1] = cx + rho * ux, cy + rho * uy
            base[r] = nv > rho * (1 + 1e-12)
            inner[r] = nv < rho * (1 - 1e-12)
        # ---- ellipses
        r = np.nonzero(kind == SiteKind.ELLIPSE)[0]
        if len(r):
            loose[r] = self._ellipses(r, K[r], x[r], y[r], lo, hi, F, d, base, inner)
        # ---- the site geometries' own bounds where the table is not tight or not applicable
        bad = (kind == SiteKind.HYPERBOLA) | (kind == SiteKind.PARABOLA) | loose
        if bad.any():
            idx = np.nonzero(bad)[0]
            for k in np.unique(K[idx]):
                sel = idx[K[idx] == k]
                self.fallbacks += len(sel)
                g = self.geoms[k]
                lo_, hi_ = g.distance_bounds(Q[sel])
                lo[sel], hi[sel] = lo_, hi_
                if kind[sel[0]] in (SiteKind.HYPERBOLA, SiteKind.PARABOLA) or not np.isfinite(F[sel]).all():
                    F_, _ = g.foot_points(Q[sel])
                    F[sel] = F_
                    d[sel] = np.hypot(*(Q[sel] - F_).T)
                if kind[sel[0]] == SiteKind.PARABOLA:
                    # outside / inside the focus side Y² ≤ 2pX (canonical frame; margin far
                    # above rounding)
                    X0, Y0 = g.to_canonical(Q[sel])
                    gv = Y0 * Y0 - 2 * g.p * X0
                    mg = 1e-9 * (Y0 * Y0 + 2 * g.p * np.abs(X0)) + 1e-300
                    base[sel], inner[sel] = gv > mg, gv < -mg
                elif kind[sel[0]] == SiteKind.HYPERBOLA:
                    # between the branches (1 − X²/a² + Y²/b² > 0) or inside the branch of
                    # sign X; the nearest branch is the one of sign X (mirror X ↦ −X), so the
                    # values are those of one convex set on discs that do not reach X = 0
                    X0, Y0 = g.to_canonical(Q[sel])
                    u, v = X0 / g.a, Y0 / g.b
                    gv = 1.0 - u * u + v * v
                    mg = 1e-9 * (1.0 + u * u + v * v)
                    base[sel], inner[sel] = gv > mg, gv < -mg
                    sep[sel] = np.abs(X0) * (1 - 1e-9) - 1e-9 * (np.abs(Q[sel]).sum(1) + abs(g.tx) + abs(g.ty)
                                                              + np.abs(Y0) + g.a + g.b)
        return SiteValues(lo, hi, F, d, base, inner, self.reach[K], sep, K, self)

    def _ellipses(self, r, k, x, y, lo, hi, F, d, base, inner):
        a, b, c, s, tx, ty = self.a[k], self.b[k], self.c[k], self.s[k], self.cx[k], self.cy[k]
        dx, dy = x - tx, y - ty
        X0, Y0 = c * dx + s * dy, -s * dx + c * dy
        # the float foot in the canonical frame, all ellipses at once (conic_geometry's solver)
        X, Y, NX, NY, _ = ellipse_feet(X0, Y0, a, b)
        dX, dY = X0 - X, Y0 - Y
        dist = np.hypot(dX, dY)
        sz = a + b
        scale = sz + np.abs(X) + np.abs(Y)
        up = dist + rounding_slack(scale, 16) + rounding_slack(dist + np.abs(X0) + np.abs(Y0) + scale, 8)
        # supporting line at the foot (conic_geometry: lower bound outside K)
        err = rounding_slack(scale, 16) + 16 * EPS * dist + rounding_slack(np.abs(X0) + np.abs(Y0) + scale, 8)
        tl = np.maximum(NX * dX + NY * dY - err, 0.0)
        g = (X0 / a) ** 2 + (Y0 / b) ** 2
        outside = g > 1 + 1e-9
        tl = np.where(g - 1.0 < 0, 0.0, tl)
        sig = rounding_slack(np.abs(x) + np.abs(y) + np.abs(tx) + np.abs(ty) + np.abs(X0) + np.abs(Y0) + up + sz, 32)
        lo_ = np.maximum(tl - sig, 0.0)
        hi_ = up + sig
        lo[r], hi[r] = lo_, hi_
        F[r, 0], F[r, 1] = tx + c * X - s * Y, ty + s * X + c * Y
        d[r] = dist
        base[r] = outside
        inner[r] = g < 1 - 1e-9
        # inside K the supporting line proves nothing (the geometry's S-lemma bound decides); the
        # same tightness rule as the geometry's own ball-route fallback
        tight = (hi_ - lo_) <= np.maximum(FALLBACK_GAP * hi_, 64 * sig)
        return ~(outside & tight & np.isfinite(lo_) & np.isfinite(hi_))

    # ------------------------------------------------------------------ third sites
    def near_pairs(self, C, reach, pair, levels=None):
        """(rows, sites): the pairs (C[row], site k ∉ pair) (``pair``: two sites, or two arrays with
        one pair per row) with the bounding box of S_k within
        ``reach[row]`` of C[row]; every other site is proved farther than ``reach`` from its
        point (d(q, S) is at least the distance from q to the bounding box of S, and the box
        lies in the disc of its half-diagonal around its centre: the k-d tree query with radius
        reach + max half-diagonal, widened, returns every box that may come that close).
        ``levels`` = (U, base, m, mu), where every site is bounded and convex: rows reaching
        :data:`GROUP_REACH` half-diagonals or more leave out the sites that the supporting
        half-planes (U, base) prove farther, by groups
        (:meth:`BoxTree.walk`)."""
        C = np.asarray(C, float).reshape(-1, 2)
        reach = np.broadcast_to(np.asarray(reach, float), (len(C),))
        rows, ks = [np.zeros(0, int)], [np.zeros(0, int)]
        if len(C) and self.tree is not None:
            r = np.where(np.isfinite(reach), (reach + self.box_half) * (1 + 1e-9) + 1e-9 * self.scale, np.inf)
            big = ~np.isfinite(r) | (r > 1e300)
            walk = np.zeros(len(C), bool)
            if levels is not None and not len(self.unbounded):
                walk = ~(reach < GROUP_REACH * self.box_half)
            qi = np.nonzero(~big & ~walk)[0]
            lists = self.tree.query_ball_point(C[qi], r[qi], return_sorted=False)
            cnt = np.fromiter(map(len, lists), int, len(lists))
            if cnt.any():
                rows.append(np.repeat(qi, cnt))
                ks.append(self.bounded[np.fromiter(itertools.chain.from_iterable(lists), int, int(cnt.sum()))])
            for b_ in np.nonzero(big & ~walk)[0]:        # unbounded reach: every bounded site
                rows.append(np.full(len(self.bounded), b_))
                ks.append(self.bounded)
            wi = np.nonzero(walk)[0]
            if len(wi):
                if self._groups is None:
                    self._groups = BoxTree(self.boxes[self.bounded])
                U, base, m, mu = levels
                lim = np.where(np.isfinite(reach[wi]), reach[wi] * (1 + 1e-9) + 1e-9 * self.scale, np.inf)
                rr, pos = self._groups.walk(C[wi], lim, U[wi], base[wi], m, mu)
                rows.append(wi[rr])
                ks.append(self.bounded[pos])
        for k in self.unbounded:
            rows.append(np.arange(len(C)))
            ks.append(np.full(len(C), k))
        rows, ks = np.concatenate(rows), np.concatenate(ks)
        if np.ndim(pair[0]):            # one pair per row
            keep = (ks != np.asarray(pair[0])[rows]) & (ks != np.asarray(pair[1])[rows])
        else:
            keep = (ks != pair[0]) & (ks != pair[1])
        rows, ks = rows[keep], ks[keep]
        if not len(rows):
            return rows, ks
        bx = self.boxes[ks]
        Cr = C[rows]
        with np.errstate(invalid="ignore"):
            dx = np.maximum(np.maximum(bx[:, 0] - Cr[:, 0], Cr[:, 0] - bx[:, 2]), 0.0)
            dy = np.maximum(np.maximum(bx[:, 1] - Cr[:, 1], Cr[:, 1] - bx[:, 3]), 0.0)
            dd = np.where(np.isfinite(dx) & np.isfinite(dy), np.hypot(dx, dy), 0.0)
        hit = dd * (1 - 1e-12) <= reach[rows]
        return rows[hit], ks[hit]


class BoxTree:
    """Groups of bounded sites, to leave out many third sites of a strip piece at once (module
    docstring, *Groups of sites*): the tree of the boxes (rows xmin, ymin, xmax, ymax, finite),
    ``order`` (box positions), per node the range [a, b) of ``order`` it holds, its first child
    (the second is next to it; −1 at a leaf) and its disc (``centre``, ``radius``)."""

    def __init__(self, boxes):
        bb = np.asarray(boxes, float).reshape(-1, 4)
        cen = 0.5 * (bb[:, :2] + bb[:, 2:])
        order = np.arange(len(bb))
        na, nb, child = [0], [len(bb)], [-1]
        t = 0
        while t < len(na):
            a, b = na[t], nb[t]
            if b - a > GROUP_LEAF:
                idx = order[a:b]
                c = cen[idx]
                ax = int(np.argmax(c.max(0) - c.min(0)))
                mid = (b - a) // 2
                order[a:b] = idx[np.argpartition(c[:, ax], mid)]
                child[t] = len(na)
                na += [a, a + mid]
                nb += [a + mid, b]
                child += [-1, -1]
            t += 1
        self.order, self.a, self.b, self.child = order, np.array(na), np.array(nb), np.array(child)
        box = np.empty((len(na), 4))
        for t in range(len(na) - 1, -1, -1):        # children come after their parent: bottom up
            if child[t] < 0:
                sb = bb[order[na[t]:nb[t]]]
                box[t] = (sb[:, 0].min(), sb[:, 1].min(), sb[:, 2].max(), sb[:, 3].max()) if len(sb) else np.nan
            else:
                c0, c1 = box[child[t]], box[child[t] + 1]
                box[t] = (min(c0[0], c1[0]), min(c0[1], c1[1]), max(c0[2], c1[2]), max(c0[3], c1[3]))
        self.centre = 0.5 * (box[:, :2] + box[:, 2:])
        rx = np.maximum(box[:, 2] - self.centre[:, 0], self.centre[:, 0] - box[:, 0])
        ry = np.maximum(box[:, 3] - self.centre[:, 1], self.centre[:, 1] - box[:, 1])
        self.radius = np.hypot(rx, ry) * (1 + 1e-12) + 1e-15 * (np.abs(self.centre).sum(1) + rx + ry)

    def walk(self, C, lim, U, base, m, mu):
        """(rows, positions): the boxes of the leaves reached from the points C (reach ``lim``,
        widened by the caller; inf for all), every node dropped whose disc lies beyond the reach
        or whose support bound passes base[row, s] − H − 2·mu − 10⁻¹²·|H| > 0,
        H = U[row, s]·(c_g − m) + ρ_g, for s = 0 or 1 (module docstring, *Groups of sites*;
        base −inf: unused)."""
        if not len(self.order):
            return np.zeros(0, int), np.zeros(0, int)
        cmx, cmy = self.centre[:, 0] - m[0], self.centre[:, 1] - m[1]
        ux, uy = (U[:, 0, 0], U[:, 1, 0]), (U[:, 0, 1], U[:, 1, 1])
        bs = (base[:, 0], base[:, 1])
        rr = np.arange(len(C))
        nn = np.zeros(len(C), int)
        out_r, out_p = [np.zeros(0, int)], [np.zeros(0, int)]
        while len(rr):
            rg = self.radius[nn]
            with np.errstate(invalid="ignore"):
                drop = np.hypot(C[rr, 0] - self.centre[nn, 0], C[rr, 1] - self.centre[nn, 1]) - rg > lim[rr]
                for s_ in (0, 1):
                    H = ux[s_][rr] * cmx[nn] + uy[s_][rr] * cmy[nn] + rg * (1 + 1e-12)
                    drop |= bs[s_][rr] - H - 2 * mu - 1e-12 * np.abs(H) > 0
            rr, nn = rr[~drop], nn[~drop]
            leaf = self.child[nn] < 0
            lr, ln = rr[leaf], nn[leaf]
            if len(lr):
                cnt = self.b[ln] - self.a[ln]
                off = np.arange(int(cnt.sum())) - np.repeat(np.cumsum(cnt) - cnt, cnt)
                out_r.append(np.repeat(lr, cnt))
                out_p.append(self.order[np.repeat(self.a[ln], cnt) + off])
            inner = self.child[nn[~leaf]]
            rr, nn = np.concatenate([rr[~leaf], rr[~leaf]]), np.concatenate([inner, inner + 1])
        return np.concatenate(out_r), np.concatenate(out_p)


def gradient_enclosure(Q, V: SiteValues, R, scale, tight=True):
    """(G, slack, valid): |∇d(q) − G| ≤ slack for every q in B(Q, R) where valid (module
    docstring).  ``V`` are the table's values at Q.  Outside a point or a circle of centre c,
    ∇d(Q) = (Q − c)/|Q − c| to a few units in the last place.  Outside an ellipse, where the foot-point
    term e_F/lo of the cheap enclosure dominates the disc's R/(lo − R), ∇d(Q) is enclosed
    through the foot point's Lagrange multiplier instead
    (:mod:`runtime.voronoi.verify.ellipse_normal`, error e_N ≈ 10⁻¹⁴), and the slack is
    e_N + R/(lo − R) on the disc (lo > 2R: the disc stays outside the convex K).  Row by row:
    computed in blocks of :data:`GRADIENT_ROWS` rows (temporaries bounded independently of the
    number of rows, the same values).  ``tight=False``: the cheap enclosure only (no Lagrange
    multiplier, no Clarke box), where its foot-point term e_F/lo is small enough for the caller."""
    Q = np.asarray(Q, float).reshape(-1, 2)
    R = np.broadcast_to(np.asarray(R, float), (len(Q),))
    m = len(Q)
    if m > GRADIENT_ROWS:
        parts = [gradient_enclosure(Q[a:a + GRADIENT_ROWS], V.part(a, a + GRADIENT_ROWS), R[a:a + GRADIENT_ROWS], scale,
                                    tight)
                 for a in range(0, m, GRADIENT_ROWS)]
        return tuple(np.concatenate([p_[t] for p_ in parts]) for t in range(3))
    W = Q - V.F
    dF = np.hypot(W[:, 0], W[:, 1])
    size = np.abs(Q).sum(1) + scale
    dF_hi = dF * (1 + 8 * EPS) + 1e-14 * size
    gap = np.maximum(dF_hi ** 2 - V.lo ** 2, 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        # outside the convex hull: projection onto a convex set
        eF = np.sqrt(gap) + 1e-12 * size
        near = V.sep > R        # hyperbola: one branch is nearest on the whole disc
        valid = V.base & near & (V.lo > 2 * R + eF) & (dF > 0)
        disc = R / (V.lo - R) * (1 + 1e-12)
        slack = eF / V.lo + disc + 1e-12
        # inside a circle / ellipse, at depth t < reach r on the disc: the foot map is
        # r/(r − t)-Lipschitz and |F − p|² ≤ (|c − F|² − d²)/(1 − d/r) (Federer, reach)
        t = V.hi + R
        inn = V.inner & ~V.base & near & (t < V.reach) & (V.reach > 0)
        L = V.reach / (V.reach - t)
        eFi = np.sqrt(gap / (1 - V.hi / V.reach)) + 1e-12 * size
        valid_i = inn & (V.lo > 2 * R + eFi) & (dF > 0)
        slack_i = eFi / V.lo + (1 + L) * R / (V.lo - R) + 1e-12
        G = W / dF[:, None]
    slack = np.where(valid, slack, np.where(valid_i, slack_i, np.inf))
    valid = valid | valid_i
    if tight and V.table is not None and V.K is not None:
        G, slack, valid = tight_gradients(Q, V, V.table, R, disc, G, slack, valid)
        # deep inside a circle or an ellipse (near or beyond the reach) but off its ridge: the
        # Clarke box of the distance (clarke_gradient.off_ridge_gradient), where it is tighter
        deep = np.nonzero(V.inner & ~V.base & ~(slack <= 0.05) & np.isfinite(V.hi) & (V.lo > 2 * R))[0]
        if len(deep):
            G2, s2, v2 = off_ridge_gradient(V.table, Q[deep], V.K[deep], V.lo[deep], V.hi[deep], R[deep],
                                            V.inner[deep])
            better = v2 & ~(s2 >= slack[deep])
            if better.any():
                G, slack, valid = G.copy(), slack.copy(), valid.copy()
                d_ = deep[better]
                G[d_], slack[d_], valid[d_] = G2[better], s2[better], True
    return G, slack, valid


def run_lockstep(gens, table: SiteTable, collective=None, deadline=None):
    """Run generator proofs side by side: each yields requests (Q, K) and receives the
    :class:`SiteValues` at those rows; one :meth:`SiteTable.evaluate` serves all pending requests.
    ``collective`` maps a request type to a function (table, [requests]) -> [results] that
    serves all pending requests of that type at once.  Returns the generators' return values;
    None for those still running at ``deadline`` (a :func:`time.perf_counter` value), which are
    closed then."""
    collective = collective or {}
    out = [None] * len(gens)
    pending = {}
    for t, g in enumerate(gens):
        try:
            pending[t] = next(g)
        except StopIteration as stop:
            out[t] = stop.value
    while pending:
        if deadline is not None and time.perf_counter() > deadline:
            for t in pending:
                gens[t].close()
            break
        answers = {}
        for kind, fn in collective.items():
            keys = [t for t, req in pending.items() if isinstance(req, kind)]
            if keys:
                answers.update(zip(keys, fn(table, [pending[t] for t in keys])))
        keys = [t for t in pending if t not in answers]
        if keys:
            Qs = [np.asarray(pending[t][0], float).reshape(-1, 2) for t in keys]
            Ks = [np.asarray(pending[t][1], int).reshape(-1) for t in keys]
            V = table.evaluate(np.concatenate(Qs), np.concatenate(Ks))
            pos = 0
            for t, q in zip(keys, Qs):
                answers[t] = V.part(pos, pos + len(q))
                pos += len(q)
        nxt = {}
        for t, ans in answers.items():
            try:
                nxt[t] = gens[t].send(ans)
            except StopIteration as stop:
                out[t] = stop.value
        pending = nxt
    return out
