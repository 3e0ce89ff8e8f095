"""Support functions of bounded convex sites, for the far field of a diagram (thesis §1.2).

Far from every site, in direction u(θ), the nearest site is the one whose support function
h_k(θ) = max_{p ∈ S_k} u(θ)·(p − m) is largest (d(m + t·u, S) = t − h_S(θ) + O(1/t); Schneider,
*Convex Bodies*, §1.7).  :class:`SupportTable` evaluates h_k and h_k' for points, circles and
ellipses with a rounding margin; it serves the unbounded edges
(:func:`runtime.voronoi.verify.tail.prove_tail`) and the accounting of the ends at infinity
(:func:`runtime.voronoi.verify.closure.verify_accounting_conics`).
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["SupportTable"]


class SupportTable:
    """Support functions of bounded convex sites about the centre m of their bounding boxes.

    h_k(θ) = max_{p ∈ S_k} u(θ)·(p − m) (the formula of :func:`runtime.interval.bound.support_function`,
    exact up to rounding: h(u) = u·(c − m) + sqrt(uᵀAu), A = R diag(a², b²) Rᵀ; vectorised over the
    sites: ``h`` accepts arrays of site indices); h_k'(θ) = (p_k(θ) − m)·u⊥(θ) with p_k(θ)
    the support point (∇ of h in u); ρ_k bounds the radius of curvature (a²/b for an ellipse with
    semi-axes a ≥ b, r for a circle, 0 for a point), so h_k + h_k'' = ρ_k(θ) ∈ [0, ρ_k] and the
    support point moves by at most ρ_k·|Δθ|.  W ≥ max_{p ∈ ∪S} |p − m|, so |h_k| ≤ W and
    |h_k'| ≤ W.  Every float value is widened by ``mu`` (rounding of the float data and of the
    evaluation, relative to the scene's size, with a wide margin).  ``ok`` is False when a site is
    not a point, circle or ellipse (no support function)."""

    def __init__(self, geoms):
        #: the site geometries (kept for the far field of unbounded sites when ``ok`` is False:
        #: :mod:`runtime.voronoi.verify.conic_tail`, :mod:`runtime.voronoi.verify.far_accounting`)
        self.geoms = list(geoms)
        self.n = len(geoms)
        self.ok = all(g.kind in ("point", "circle", "ellipse") for g in geoms) and self.n > 0
        if not self.ok:
            return
        bx = np.array([g.bounding_box() for g in geoms], float)
        self.m = 0.5 * (bx[:, :2].min(0) + bx[:, 2:].max(0))
        self.kind, self.cen, self.rho, shape = [], [], [], []
        W = 0.0
        for g in geoms:
            if g.kind == "point":
                c, r = (g.x0, g.y0), 0.0
                shape.append((0.0, 0.0, 1.0, 0.0))
            elif g.kind == "circle":
                c, r = (g.cx, g.cy), g.rho
                shape.append((g.rho, g.rho, 1.0, 0.0))
            else:
                c, r = (g.tx, g.ty), max(g.a, g.b)
                nrm = math.hypot(g.c, g.s)
                shape.append((g.a, g.b, g.c / nrm, g.s / nrm))
            self.kind.append(g.kind)
            self.cen.append(c)
            self.rho.append(r)
            W = max(W, math.hypot(c[0] - self.m[0], c[1] - self.m[1]) + r)
        self.cen = np.array(self.cen, float)
        self.rho = np.array(self.rho, float)
        #: semi-axes and axis direction per site (a circle: a = b = r; a point: 0)
        self.sa, self.sb, self.cs, self.sn = (np.array(v, float) for v in zip(*shape))
        #: the quadratic form A = R diag(a², b²) Rᵀ of each site (h = u·(c − m) + √(uᵀAu)), rows
        #: (A11, A12, A22, A22 − A11)
        a2, b2 = self.sa * self.sa, self.sb * self.sb
        self.quad = np.column_stack([a2 * self.cs * self.cs + b2 * self.sn * self.sn, (a2 - b2) * self.cs * self.sn,
                                     a2 * self.sn * self.sn + b2 * self.cs * self.cs])
        self.quad = np.column_stack([self.quad, self.quad[:, 2] - self.quad[:, 0]])
        self.rcurv = np.array([max(g.a, g.b) ** 2 / min(g.a, g.b) if g.kind == "ellipse" else
                               (g.rho if g.kind == "circle" else 0.0) for g in geoms], float) * (1 + 1e-9)
        self.mu = 1e-11 * (W + float(np.abs(self.m).sum()) + float(np.abs(self.cen).max()) + 1.0)
        self.W = W * (1 + 1e-9) + self.mu

    def recentred(self, m):
        """The same table about another centre m (W and mu recomputed)."""
        import copy

        t = copy.copy(self)
        t.m = np.asarray(m, float)
        W = float(np.max(np.hypot(self.cen[:, 0] - t.m[0], self.cen[:, 1] - t.m[1]) + self.rho))
        t.mu = 1e-11 * (W + float(np.abs(t.m).sum()) + float(np.abs(self.cen).max()) + 1.0)
        t.W = W * (1 + 1e-9) + t.mu
        return t

    def hp_abs(self, k, thc, half):
        """Bound on |h_k'| on [θc − half, θc + half] (|h''| ≤ ρ_k + W)."""
        return np.abs(self.hp(k, thc)) + (self.rcurv[k] + self.W) * half + self.mu

    def _terms(self, k, th):
        """(ux, uy, dx, dy, √(uᵀAu)) for the sites k (an index or an array broadcasting against θ)."""
        th = np.asarray(th, float)
        k = np.asarray(k)
        ux, uy = np.cos(th), np.sin(th)
        q = self.quad[k]
        s = np.sqrt(q[..., 0] * (ux * ux) + q[..., 1] * (2.0 * ux * uy) + q[..., 2] * (uy * uy))
        return ux, uy, self.cen[k, 0] - self.m[0], self.cen[k, 1] - self.m[1], s

    def _h_hp(self, k, th):
        """(h_k(θ), h_k'(θ)) in one pass: h' = (p − m)·u⊥ = v + uᵀA u⊥/√(uᵀAu), v = (c − m)·u⊥,
        uᵀA u⊥ = (A22 − A11)·ux·uy + A12·(ux² − uy²) (0 for a point)."""
        ux, uy, dx, dy, s = self._terms(k, th)
        q = self.quad[np.asarray(k)]
        with np.errstate(divide="ignore", invalid="ignore"):
            w = (q[..., 3] * (ux * uy) + q[..., 1] * (ux * ux - uy * uy)) / s
        return ux * dx + uy * dy + s, (ux * dy - uy * dx) + np.where(s > 0, w, 0.0)

    def h_and_slope(self, k, th):
        """(h_k(θ), h_k'(θ)) in one pass (floats, each within mu)."""
        return self._h_hp(k, th)

    def support_at(self, k, U):
        """Float h_k(u) for the rows u of U (unit vectors, within a few ulps; error ≤ mu): the
        same formula as :meth:`h` without the angle, for the sites k (an array of U's length)."""
        k = np.asarray(k)
        ux, uy = U[:, 0], U[:, 1]
        q = self.quad[k]
        s = np.sqrt(q[:, 0] * (ux * ux) + q[:, 1] * (2.0 * ux * uy) + q[:, 2] * (uy * uy))
        return ux * (self.cen[k, 0] - self.m[0]) + uy * (self.cen[k, 1] - self.m[1]) + s

    def h(self, k, th):
        """Float h_k(θ) (error ≤ mu); k an index or an array broadcasting against θ."""
        ux, uy, dx, dy, s = self._terms(k, th)
        return ux * dx + uy * dy + s

    def hp(self, k, th):
        """Float h_k'(θ) = (p_k(θ) − m)·u⊥(θ) (error ≤ mu)."""
        return self._h_hp(k, th)[1]

    def h_range(self, k, thc, half):
        """Enclosure of h_k on [θc − half, θc + half]: |h'| ≤ W, or to second order (Taylor at θc
        with h' Lipschitz, |h''| = |ρ_k(θ) − h_k| ≤ ρ_k + W a.e.)
        h_k(θc) ± (|h_k'(θc)|·half + (ρ_k + W)·half²/2), the float values within mu."""
        v, d = self._h_hp(k, thc)
        half = np.asarray(half, float)
        r1 = self.W * half
        r2 = (np.abs(d) + self.mu) * half + 0.5 * (self.rcurv[k] + self.W) * half * half
        r = np.minimum(r1, r2) * (1 + 1e-12) + self.mu
        return v - r, v + r

    def _root(self, i, j, a_, b_):
        """Float bisection of g = h_i − h_j on [a_, b_] (a sign change)."""
        ga = self.h(i, a_) - self.h(j, a_)
        for _ in range(60):
            mid = 0.5 * (a_ + b_)
            gm = self.h(i, mid) - self.h(j, mid)
            a_, b_, ga = (mid, b_, gm) if np.sign(gm) == np.sign(ga) else (a_, mid, ga)
        return 0.5 * (a_ + b_)

    def lead_direction(self, i, j, thX):
        """A float zero θ of h_i − h_j where i and j lead every other site's support function,
        the nearest to thX (a float guide for the tail of the edge (i, j)), or None.  A scan of
        4097, then 65537 directions; a lead narrower than that grid (a near-tie at infinity with
        a third site): each sign change refined to its root, kept where i, j lead there."""
        oth = np.array([k for k in range(self.n) if k not in (i, j)], int)
        for npts in (4097, 65537):
            grid = thX + np.linspace(-math.pi, math.pi, npts)
            hi_, hj_ = self.h(i, grid), self.h(j, grid)
            g = hi_ - hj_
            hij = np.maximum(hi_, hj_)
            ch = np.nonzero(np.sign(g[:-1]) != np.sign(g[1:]))[0]
            if len(ch) and len(oth):
                both = np.concatenate([ch, ch + 1])
                top = self.h(oth[:, None], grid[both][None, :]).max(0)
                lead = hij[both] > top
                ch = ch[lead[:len(ch)] & lead[len(ch):]]
            if len(ch):
                c0 = int(ch[np.argmin(np.abs(grid[ch] - thX))])
                return self._root(i, j, grid[c0], grid[c0 + 1])
        roots = [self._root(i, j, grid[c], grid[c + 1]) for c in np.nonzero(np.sign(g[:-1]) != np.sign(g[1:]))[0]]
        roots = [t for t in roots if not len(oth) or float(self.h(i, t)) > float(self.h(oth, t).max())]
        return min(roots, key=lambda t: abs(t - thX)) if roots else None

