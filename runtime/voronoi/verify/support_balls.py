"""Support functions in ball arithmetic from the exact site data, for near-ties at infinity.

The float support functions of :class:`runtime.voronoi.verify.support.SupportTable` carry a rounding
margin μ ≈ 10⁻¹¹ of the scene's size.  Where sites tie at infinity to within a few μ (support
values h_i(θ*), h_k(θ*) closer than that), no float comparison separates them.  Here the same
quantities are enclosed in arb balls (python-flint) at growing precision, from the sites' exact
rational data: a point, circle or ellipse {v : (v − c)ᵀM(v − c) ≤ κ} has

    h(θ) = u·(c − m) + √(uᵀAu),  h'(θ) = u⊥·(c − m) + uᵀAu⊥/√(uᵀAu),  A = κM⁻¹

(A = r²I for a circle, 0 for a point; Schneider, *Convex Bodies*, §1.7), with u = u(θ) for a float
(exact binary) θ and m the float centre of the SupportTable, both exact as rationals.  The cell
bounds are those of :mod:`runtime.voronoi.verify.far_field` (first order in 1/t; |h''| ≤ M =
ρ + W) with every term a ball: :meth:`SupportBalls.gap_lower` is positive only when
d_k − d_s > 0 is proved on the cell.  The precision doubles from 64 to 1024 bits while a ball's
radius, not the cell's size, decides (its radius above a quarter of its distance to 0).  An exact
tie (h_s = h_k at the tie direction, e.g. shapes resting on one line) is never decided here; it
is left to the exact route (:mod:`runtime.voronoi.verify.tied_tail`).

Public API: :func:`site_quadratic`, :class:`SupportBalls`, :func:`sole_maximum`.
"""
from __future__ import annotations

import math
from fractions import Fraction

import flint
import numpy as np

from ...certify.cell_cover import CellTest, walk_cells
from ...predicates.symmetry import site_centre, site_coefficients

__all__ = ["site_quadratic", "SupportBalls", "sole_maximum", "PRECISIONS"]

#: working precisions (bits) tried in turn
PRECISIONS = (64, 128, 256, 512, 1024)


def site_quadratic(site):
    """(c, (A11, A12, A22), circle) with h(u) = c·u + √(uᵀAu) exactly (rationals), or None for a
    site that is not a point, circle or ellipse (module docstring)."""
    co = site_coefficients(site)
    a, b, c, d, e, f = co
    if hasattr(site, "r2") or (a == c and b == 0):
        cen = site_centre(site)
        if cen is None or a == 0:
            return None
        r2 = cen[0] ** 2 + cen[1] ** 2 - f / a
        if r2 < 0:
            return None
        return cen, (r2, Fraction(0), r2), True
    if 4 * a * c - b * b <= 0:
        return None                                   # not an ellipse
    cen = site_centre(site)
    m11, m12, m22 = a, b / 2, c
    kappa = m11 * cen[0] ** 2 + 2 * m12 * cen[0] * cen[1] + m22 * cen[1] ** 2 - f
    if m11 < 0:
        m11, m12, m22, kappa = -m11, -m12, -m22, -kappa
    if kappa <= 0:
        return None
    det = m11 * m22 - m12 * m12
    return cen, (kappa * m22 / det, -kappa * m12 / det, kappa * m11 / det), False


def _ball(x):
    """An exact arb of a Fraction or float."""
    if isinstance(x, Fraction):
        return flint.arb(flint.fmpq(x.numerator, x.denominator))
    return flint.arb(float(x))


def _undecided_by_rounding(x) -> bool:
    """Is the ball x straddling 0 only because of its radius (not of the quantity)?"""
    return x.rad() > abs(x.mid()) / 4


class SupportBalls:
    """The support functions of the sites of a SupportTable ``sup`` about its centre m, as balls
    (module docstring); site data read exactly from ``sup.geoms[k].exact`` when first needed."""

    def __init__(self, sup):
        self.sup = sup
        self._data = {}
        #: number of :meth:`gap_lower` calls so far (callers bound their work with it)
        self.calls = 0

    def _site(self, k):
        if k not in self._data:
            q = site_quadratic(self.sup.geoms[k].exact)
            if q is None:
                raise ValueError(f"site {k} has no exact support function")
            self._data[k] = q
        return self._data[k]

    def h_hp(self, k, th):
        """(h_k(θ), h_k'(θ)) as balls at the current precision (θ a float)."""
        (cx, cy), (a11, a12, a22), _ = self._site(int(k))
        t = _ball(float(th))
        ux, uy = t.cos(), t.sin()
        dx, dy = _ball(cx) - _ball(float(self.sup.m[0])), _ball(cy) - _ball(float(self.sup.m[1]))
        A11, A12, A22 = _ball(a11), _ball(a12), _ball(a22)
        Q = A11 * ux * ux + 2 * A12 * ux * uy + A22 * uy * uy
        h = ux * dx + uy * dy
        hp = -uy * dx + ux * dy
        if a11 == 0 and a12 == 0 and a22 == 0:
            return h, hp                                 # a point
        s = Q.sqrt()
        return h + s, hp + ((A22 - A11) * ux * uy + A12 * (ux * ux - uy * uy)) / s

    def _gap(self, s, k, thc, half, t0, t1):
        """The ball lower bound of d_k − d_s of :meth:`gap_lower` at the current precision."""
        sup = self.sup
        W = _ball(float(sup.W))
        Ms, Mk = _ball(float(sup.rcurv[s])) + W, _ball(float(sup.rcurv[k])) + W
        d = _ball(float(half))
        hs, ps = self.h_hp(s, thc)
        hk, pk = self.h_hp(k, thc)
        val = (hs - hk) - abs(ps - pk) * d - (Ms + Mk) * d * d / 2
        lo_k = abs(pk) - Mk * d
        if t1 is not None and math.isfinite(t1) and (lo_k > 0):
            val += lo_k * lo_k / (2 * (_ball(float(t1)) + Mk))
        if t0 is not None:
            hi_s = abs(ps) + Ms * d
            val -= hi_s * hi_s / (2 * (_ball(float(t0)) - W))
        return val

    def gap_lower(self, s, k, thc, half, t0=None, t1=None) -> bool:
        """Is d_k − d_s > 0 proved on the cell {m + t·u(θ) : t ∈ [t0, t1], |θ − θc| ≤ δ} to first
        order in 1/t (:mod:`runtime.voronoi.verify.far_field`, every term a ball)?  With t0 = None:
        is h_s − h_k > 0 on the angular cell (the support functions alone, at infinity)?"""
        self.calls += 1
        for prec in PRECISIONS:
            with flint.ctx.workprec(prec):
                v = self._gap(int(s), int(k), thc, half, t0, t1)
                if v > 0:
                    return True
                if not _undecided_by_rounding(v):
                    return False
        return False

    def sign(self, s, k, th) -> int:
        """The proved sign of h_s(θ) − h_k(θ) (0: undecided at every precision)."""
        for prec in PRECISIONS:
            with flint.ctx.workprec(prec):
                v = self.h_hp(int(s), th)[0] - self.h_hp(int(k), th)[0]
                if v > 0:
                    return 1
                if v < 0:
                    return -1
                if not _undecided_by_rounding(v):
                    return 0
        return 0


def sole_maximum(sup, s, g0, g1, max_work: int = 20000, rivals=None) -> bool:
    """Is h_s > h_k on [g0, g1] for every other site k (or every k in ``rivals``)?  Float cells
    first (h_s − h_k ≥ the difference at the centre − 2W·δ − 2μ), balls for the rows within the
    rounding margin (:meth:`SupportBalls.gap_lower`); cells halved until decided."""
    balls = SupportBalls(sup)
    ks = np.array([k for k in (range(sup.n) if rivals is None else rivals) if k != s], int)
    if not len(ks):
        return True
    e = np.linspace(g0, g1, 9)
    a, b = np.tile(e[:-1], len(ks)), np.tile(e[1:], len(ks))
    K = np.repeat(ks, len(e) - 1)

    def test(c, half, K):
        hs, ps = sup.h_and_slope(s, c)
        hk, pk = sup.h_and_slope(K, c)
        lo = np.maximum(hs - hk - 2 * sup.W * half,
                        hs - hk - (np.abs(ps - pk) + 2 * sup.mu) * half
                        - 0.5 * (sup.rcurv[s] + sup.rcurv[K] + 2 * sup.W) * half * half) - 2 * sup.mu
        ok = lo * (1 - 1e-12) > 0
        near = np.nonzero(~ok & (lo > -16 * sup.mu))[0]
        if len(near) > 4096:
            near = near[:0]
        for r in near.tolist():
            ok[r] = balls.gap_lower(s, K[r], float(c[r]), float(half[r]))
        return CellTest(fault=None, undecided=~ok)

    return walk_cells(a, b, test, max_work, carry=(K,), smallest=1e-15 * (1 + abs(g0))).proved
