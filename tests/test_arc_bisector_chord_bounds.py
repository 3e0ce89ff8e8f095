"""The chord-to-curve deviation bound of an arc's bisector piece against the closed-form curve.

Arc s: the unit circle about the origin, counter-clockwise from (3/5, −4/5) to (3/5, 4/5); point
p = (P, 0), P ∈ {2, 3, 4}.  Seen from outside the circle the bisector is the hyperbola branch
|x| − 1 = |x − p| (foci 0 and p, 2a = 1): on the ray of direction u = u(φ), φ = α + θ
(α = atan2(−4, 3), θ the parameter of :class:`runtime.segments.certificate_arcs.ArcCurve`), the
point x = (1 + t) u with t = |p − u|² / (2 (u·p − 1)) (from (1 + t)² − 2(1 + t) u·p + |p|² = t²),
evaluated here in mpmath (30 digits).

:meth:`ArcCurve.chord_bound_parts` bounds the distance from the piece θ ∈ [θ₀, θ₁] to its chord by
the smallest of three proved bounds (its docstring), among them ℓ²κ/8.  A piece of curvature
at least κ_min (and turning below π) deviates from its chord c by at least the sagitta
c²κ_min/8 of the circle of curvature κ_min through its ends, and ℓ/c = 1 + O(ℓ²κ²); so on a short
piece (θ-length 0.02 or 0.05, curvature ratio κ_max/κ_min measured below from the closed form)
ℓ²κ_max/8 with ℓ, κ_max the upper bounds over the sub-pieces (|v′| and κ vary by a few % within
each) lies within 1.1 · κ_max/κ_min of the deviation: the bound must lie in
[deviation, 1.1 · (κ_max/κ_min) · deviation].  A bound that discards ℓ²κ/8 for a cruder one
(the Green-function bound Σ ℓ_m κ_m w_m is 4/3 of it on a circle, ∫₀^ℓ s(ℓ − s)/ℓ ds = ℓ²/6)
stays sound but leaves that range.
"""
from __future__ import annotations

from fractions import Fraction as F

import mpmath as mp
import pytest
from flint import arb

from curvedvoronoi.runtime.predicates.circles import Point
from curvedvoronoi.runtime.segments.certificate_arcs import ArcCurve
from curvedvoronoi.runtime.segments.certificate_sites import SiteTable
from curvedvoronoi.runtime.sites.arc import Arc


def _branch(P):
    """The closed-form point x(θ) of the branch (module docstring), in mpmath."""
    al = mp.atan2(-4, 3)

    def x(th):
        ph = al + th
        ux, uy = mp.cos(ph), mp.sin(ph)
        t = ((P - ux) ** 2 + uy ** 2) / (2 * (ux * P - 1))
        return mp.matrix([(1 + t) * ux, (1 + t) * uy])
    return x


def _deviation_and_curvature_ratio(P, t0, t1, n=400):
    """(max distance of the piece to its chord, max κ / min κ on the piece), by dense sampling of
    the closed form (the curvature from mpmath's numerical derivatives)."""
    with mp.workdps(30):
        x = _branch(P)
        a, b = x(mp.mpf(t0)), x(mp.mpf(t1))
        d = b - a
        L = mp.norm(d)
        dev, kap = mp.mpf(0), []
        for i in range(n + 1):
            th = mp.mpf(t0) + (mp.mpf(t1) - mp.mpf(t0)) * i / n
            q = x(th) - a
            dev = max(dev, abs(q[0] * d[1] - q[1] * d[0]) / L)
            if i % 40 == 0:
                d1 = [mp.diff(lambda s, j=j: x(s)[j], th, 1) for j in (0, 1)]
                d2 = [mp.diff(lambda s, j=j: x(s)[j], th, 2) for j in (0, 1)]
                kap.append(abs(d1[0] * d2[1] - d1[1] * d2[0]) / mp.sqrt(d1[0] ** 2 + d1[1] ** 2) ** 3)
        return float(dev), float(max(kap) / min(kap))


def _curve(P):
    T = SiteTable([Arc((0, 0), 1, (F(3, 5), F(-4, 5)), (F(3, 5), F(4, 5))), Point(P, 0)])
    return ArcCurve(T, 0, 1, 1)


PIECES = [(2, 0.6, 0.62), (3, 0.6, 0.62), (4, 1.2, 1.22), (3, 0.3, 0.32), (4, 0.9, 0.95)]


@pytest.mark.parametrize("P, t0, t1", PIECES)
@pytest.mark.parametrize("refined", [False, True], ids=["8 sub-pieces", "refined"])
def test_a_short_piece_is_bounded_within_its_curvature_variation(P, t0, t1, refined):
    """deviation ≤ bound ≤ 1.1 · (κ_max / κ_min) · deviation, with eight sub-pieces
    (:meth:`ArcCurve.chord_bound_parts`) and refined to 512 (:meth:`ArcCurve.chord_bound`,
    target 0)."""
    dev, ratio = _deviation_and_curvature_ratio(P, t0, t1)
    assert ratio < 1.10                                    # a short, nearly circular piece
    c = _curve(P)
    b = c.chord_bound(arb(t0), arb(t1)) if refined else c.chord_bound_parts(arb(t0), arb(t1), 8)
    b = float(b.upper())
    assert dev <= b <= 1.1 * ratio * dev, (b, dev, b / dev, ratio)
