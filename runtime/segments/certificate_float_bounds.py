"""Float lower and upper bounds of the distances from one point to a few sites, in scalar floats:
the filter in front of the rigorous balls of the certificate's emptiness and piece proofs (the
distance to an open segment is the distance to the closed one, thesis §2.2).

:meth:`runtime.segments.certificate_sites.SiteTable.float_bounds` evaluates the same bounds with
numpy arrays; a piece of an edge or a vertex circle meets a handful of sites, where numpy's per-call
cost dominates, so :func:`bounds_at` evaluates them one site at a time with the same operations
(one query point q, the sites' float rows ``T.float_rows``).  A bound decides nothing by itself:
a site whose float lower bound clears the radius is skipped, every other one goes on to the arb
ball of :meth:`SiteTable.distance`.

Rounding (Higham, *Accuracy and Stability of Numerical Algorithms*, 2nd ed., §2.2 and §3.1: each
operation of IEEE binary64 round-to-nearest is exact times (1 + δ), |δ| ≤ u = 2⁻⁵³ = ε/2, a sum
of n products off by at most γ_n of the sum of their moduli, γ_n = nu/(1 − nu)).  The site's
float ends a, b and q are the inputs (the site table's floats are within half an ulp of the exact
ends; :data:`SLACK` of T.scale covers that).  Let s = max(|a|, |b|, |q|) (componentwise maxima)
+ 1, L = |b − a|, w = q − a.

* **Segments and points.**  t̂ = clamp(fl(fl(w·d)/fl(d·d)), 0, 1) with d = fl(b − a), w = fl(q − a)
  (t̂ = 0 for a = b).  Whatever its error, F(t̂) = a + t̂ (b − a) lies on the closed segment, so
  d_true ≤ |q − F(t̂)|; and |q − F(t̂)| − d_true ≤ |F(t̂) − F(t*)| = |t̂ − t*| L (triangle
  inequality; clamping is 1-Lipschitz).  The quotient's error: the components of d and w are off
  by u of themselves, the dot products by γ₂ of |w||d| and of L², the division by u: |t̂ − t*| ≤
  γ₉ (|t*| + |w|/L) before clamping, so |t̂ − t*| L ≤ γ₉ (L + |w|) ≤ γ₉ · 2√2 · 2s.  Then
  F̂ = fl(a + fl(t̂ d)) is off from F(t̂) by ≤ γ₃ (|a| + |d|) ≤ γ₃ · 3√2 s, fl(q − F̂) by u of
  itself (≤ u · 2√2 s after the previous terms), and hypot is faithful (≤ 2u of the result,
  ≤ 2u · 2√2 s).  In all |d̂ − d_true| ≤ (8√2 · γ₉ + 3√2 γ₃ + 6√2 u) s < 120 u s = 60 ε s, below the
  64 ε s of :func:`runtime.segments.distance.float_error` used here and there.
* **Arcs** (centre c, radius ρ, ends a, b): the circle's distance | |q − c| − ρ | is off by at
  most 3u(|q| + |c|)·√2 + u ρ + 2u(…) < 64 ε (|q| + |c| + ρ + 1); the end distances as points.
  The range test: the three cross products (a − c) × w, w × (b − c), (a − c) × (b − c) with
  w = q − c, each a difference of two products of differences, are off by ≤ γ₄ · 2 · (2M)² with
  M = max|q| + max|c| + ρ + 1 (|a − c|, |b − c| ≈ ρ, |w| ≤ |q| + |c|), below 64 ε M²: a sign is
  trusted only beyond that margin ("sure in", "sure out"); otherwise the lower bound is the
  smaller of the circle's and the ends' distances (the ends lie on the circle) and the upper
  bound the nearer end's.

These are exactly the margins of :meth:`SiteTable.float_bounds` (the same formulas), so both
paths clear the same sites up to the last bit of a faithful hypot.

Public API: :func:`bounds_at`, :data:`SLACK`.
"""
from __future__ import annotations

import math

__all__ = ["bounds_at", "SLACK"]

EPS = 2.0 ** -52
#: the allowance of the float ends against the exact ones, per unit of the table's scale
SLACK = 8 * EPS


def bounds_at(T, sites, qx: float, qy: float):
    """(lo, hi) lists: float bounds of the distances from (qx, qy) to each site of ``sites`` (as
    :meth:`runtime.segments.certificate_sites.SiteTable.float_bounds`; module docstring), or None
    when a site is an elliptic piece or q is not finite (the numpy path handles those)."""
    if not (math.isfinite(qx) and math.isfinite(qy)):
        return None
    rows = T.float_rows
    base = SLACK * T.scale
    aq = max(abs(qx), abs(qy))
    lo, hi = [], []
    hyp = math.hypot
    for k in sites:
        row = rows[k]
        if row is None:
            return None
        ax, ay, bx, by, mag, arc = row
        if arc is None:
            dx, dy = bx - ax, by - ay
            L2 = dx * dx + dy * dy
            if L2 > 0:
                t = ((qx - ax) * dx + (qy - ay) * dy) / L2
                t = 0.0 if t < 0.0 else (1.0 if t > 1.0 else t)
            else:
                t = 0.0
            d = hyp(qx - (ax + t * dx), qy - (ay + t * dy))
            err = 64 * EPS * ((mag if mag > aq else aq) + 1.0) + base
            lo.append(d - err)
            hi.append(d + err)
            continue
        cx, cy, R, mc = arc
        wx, wy = qx - cx, qy - cy
        circle = abs(hyp(wx, wy) - R)
        ends = min(hyp(qx - ax, qy - ay), hyp(qx - bx, qy - by))
        uax, uay, ubx, uby = ax - cx, ay - cy, bx - cx, by - cy
        ca = uax * wy - uay * wx
        cb = wx * uby - wy * ubx
        ab = uax * uby - uay * ubx
        M = aq + mc + R + 1.0
        m = 64 * EPS * M ** 2
        if ab > m:
            sure_in, sure_out = ca > m and cb > m, ca < -m or cb < -m
        elif ab < -m:
            sure_in, sure_out = ca > m or cb > m, ca < -m and cb < -m
        else:
            sure_in = sure_out = False
        e = 64 * EPS * M + base
        lo.append((circle if sure_in else (ends if sure_out else min(circle, ends))) - e)
        hi.append((circle if sure_in else ends) + e)
    return lo, hi
