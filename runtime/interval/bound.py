"""A proved bound on the Voronoi vertices of three bounded sites (support-function argument).

The interval locator of thesis ch. 6 searches a bounded domain; a domain only proves the vertex
list complete if *every* vertex lies inside it.  A vertex of three unit circles can lie 5000
units away (nearly collinear centres), so no box "around the data" is a bound.  This module
derives one from the sites themselves.

Argument.  Let S be a compact site, m a fixed point, W >= max_{p in S} |p − m|, and
h(u) = max_{p in S} u·(p − m) its support function (u a unit vector).  For q = m + t·u with
t > W:

* lower bound: d(q, S) >= d(q, conv S) >= u·(q − m) − h(u) = t − h(u)  (separating line);
* upper bound: with p_u in S a support point (u·(p_u − m) = h(u); extreme points of conv S lie
  in S), |q − p_u|² = (t − h)² + |p_u^⊥|², so d(q, S) <= t − h(u) + W² / (2 (t − W)).

Hence a point equidistant from S1, S2, S3 (d1 = d2 = d3, in particular a Voronoi vertex, thesis
Def. 5.2.1) at distance t > W from m satisfies |h_i(u) − h_j(u)| <= W² / (2 (t − W)) for every
pair, i.e. ``t <= W + W² / (2 φ(u))`` with φ(u) = max_{i<j} |h_i(u) − h_j(u)|.  If φ > 0 on the
whole unit circle, every vertex lies in the disk of radius ``W + W² / (2 min φ)`` around m, and
more precisely in the star-shaped region t <= W + W² / (2 φ(u)), whose bounding box is the search
domain (:meth:`VertexBound.box`).

min φ is bounded below rigorously on a grid of N angles: each h_i is W-Lipschitz in the angle
(each interval enclosure below as well), so φ(θ) >= φ(θ_k) − W·δ for |θ − θ_k| <= δ/2, δ = 2π/N;
floating-point evaluation errors are covered by an explicit margin.

Support functions: ellipse x = c + Rot·(A cos s, B sin s): h(u) = u·(c − m) + sqrt(A² u_X² + B² u_Y²)
with (u_X, u_Y) = Rotᵀu; circle: u·(c − m) + r.  Other bounded sites (arcs, curves with a rigorous
bounding box) give the enclosure h(u) in [u·(c − m) − ρ, u·(c − m) + ρ] for a disk (c, ρ) that
contains the site.  Unbounded sites (hyperbolas, parabolas, curves without a box): no bound.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .curves import Curve

__all__ = ["VertexBound", "support_function", "vertex_bound"]

_EPS_REL = 1e-12        # margin for rounding errors in the float evaluation of h (relative to W)
_MAX_GRID = 1 << 22


@dataclass(frozen=True)
class VertexBound:
    """All points equidistant from the three sites lie in the disk |q − centre| <= radius."""
    centre: tuple[float, float]
    radius: float
    phi_min: float      # rigorous lower bound of min_u φ(u)
    grid: int           # number of angles used

    extent: tuple[float, float, float, float]  # box of the star-shaped region t <= t(u), inside the disk

    def box(self) -> tuple[float, float, float, float]:
        """(xmin, xmax, ymin, ymax): a box that contains every point equidistant from the sites."""
        return self.extent

    def inside(self, domain) -> bool:
        """True if the box ``domain = (xmin, xmax, ymin, ymax)`` contains :meth:`box`."""
        xmin, xmax, ymin, ymax = (float(v) for v in domain)
        b = self.box()
        return xmin <= b[0] and xmax >= b[1] and ymin <= b[2] and ymax >= b[3]


def _site_support(c: Curve):
    """(centre (cx, cy), support(u, m) -> (lo, hi) arrays, reach ρ) or None if unbounded/unknown.

    ``reach`` bounds max |p − centre| over the site."""
    k = c.conic
    if k is not None and not c.is_arc and k["kind"] in ("ellipse", "circle"):
        cx, cy = float(k["tx"]), float(k["ty"])
        if k["kind"] == "circle":
            r = math.sqrt(float(k["params"]["r2"]))

            def supp(ux, uy, m, r=r, cx=cx, cy=cy):
                v = ux * (cx - m[0]) + uy * (cy - m[1]) + r
                return v, v
            return (cx, cy), supp, r
        a2, b2 = float(k["params"]["A2"]), float(k["params"]["B2"])
        cs, sn = float(k["cos"]), float(k["sin"])
        nrm = math.hypot(cs, sn)
        cs, sn = cs / nrm, sn / nrm

        def supp(ux, uy, m, a2=a2, b2=b2, cs=cs, sn=sn, cx=cx, cy=cy):
            uX = cs * ux + sn * uy
            uY = -sn * ux + cs * uy
            v = ux * (cx - m[0]) + uy * (cy - m[1]) + np.sqrt(a2 * uX * uX + b2 * uY * uY)
            return v, v
        return (cx, cy), supp, math.sqrt(max(a2, b2))
    if c.bbox is not None:
        xmin, xmax, ymin, ymax = (float(v) for v in c.bbox)
        if not all(math.isfinite(v) for v in (xmin, xmax, ymin, ymax)):
            return None
        cx, cy = 0.5 * (xmin + xmax), 0.5 * (ymin + ymax)
        rho = 0.5 * math.hypot(xmax - xmin, ymax - ymin) * (1 + 1e-12)

        def supp(ux, uy, m, rho=rho, cx=cx, cy=cy):
            v = ux * (cx - m[0]) + uy * (cy - m[1])
            return v - rho, v + rho
        return (cx, cy), supp, rho
    return None


def support_function(site: Curve, ux, uy, centre=(0.0, 0.0)):
    """Enclosure (lo, hi) of the support function h(u) = max_{p in site} u·(p − centre) for unit
    vectors (ux, uy) (floats or arrays; exact for ellipses and circles up to rounding, a disk
    enclosure for other bounded sites); None for an unbounded site or one without a bounding box."""
    sup = _site_support(site)
    if sup is None:
        return None
    return sup[1](np.asarray(ux, dtype=float), np.asarray(uy, dtype=float), tuple(float(v) for v in centre))


def vertex_bound(sites, max_grid: int = _MAX_GRID) -> VertexBound | None:
    """Proved bound on the points equidistant from the first three sites, or None.

    None means no bound could be proved: a site is unbounded (hyperbola, parabola, curve with no
    bounding box), or φ vanishes somewhere (e.g. collinear centres of equal circles, where the
    bisectors meet at infinity) or is too small to be resolved on ``max_grid`` angles.
    """
    sup = [_site_support(c) for c in list(sites)[:3]]
    if any(s is None for s in sup):
        return None
    m = (sum(s[0][0] for s in sup) / 3.0, sum(s[0][1] for s in sup) / 3.0)
    W = max(math.hypot(s[0][0] - m[0], s[0][1] - m[1]) + s[2] for s in sup)
    W = W * (1 + 1e-12) + 1e-300
    margin = 4 * _EPS_REL * W

    def phi_cells(n: int):
        """Angles θ_k and rigorous lower bounds of φ on the cells |θ − θ_k| <= π/n."""
        th = np.arange(n) * (2 * math.pi / n)
        ux, uy = np.cos(th), np.sin(th)
        iv = [s[1](ux, uy, m) for s in sup]
        phi = np.zeros(n)
        for i in range(3):
            for j in range(i + 1, 3):
                gap = np.maximum(iv[i][0] - iv[j][1], iv[j][0] - iv[i][1])
                phi = np.maximum(phi, gap)
        return th, phi, phi - W * (2 * math.pi / n) - margin

    n = 4096
    th, phi, low = phi_cells(n)
    while float(np.min(low)) <= 0:
        fmin = float(np.min(phi))
        if fmin <= margin:
            return None
        need = int(math.ceil(2 * math.pi * W / (0.5 * fmin))) + 1
        n_new = max(2 * n, 1 << max(need - 1, 1).bit_length())
        if n_new > max_grid:
            return None
        n = n_new
        th, phi, low = phi_cells(n)
    lower = float(np.min(low))
    # per cell: t <= W + W²/(2 φ_k); cos/sin vary by at most δ/2 over a cell
    t = (W + W * W / (2 * low)) * (1 + 1e-9)
    half = math.pi / n * (1 + 1e-9)
    ext = (m[0] - max(W, float(np.max(t * (half - np.cos(th))))), m[0] + max(W, float(np.max(t * (np.cos(th) + half)))),
           m[1] - max(W, float(np.max(t * (half - np.sin(th))))), m[1] + max(W, float(np.max(t * (np.sin(th) + half)))))
    pad = 1e-9 * float(np.max(t))
    ext = (ext[0] - pad, ext[1] + pad, ext[2] - pad, ext[3] + pad)
    radius = float(np.max(t))
    return VertexBound(centre=m, radius=radius, phi_min=lower, grid=n, extent=ext)
