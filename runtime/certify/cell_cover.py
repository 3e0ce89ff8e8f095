"""Balls that cover float cells, and the halving of undecided cells.

The verifier decides many statements "for every θ in [g0, g1]" (a support function larger than
another on an arc of directions at infinity, a gap at infinity, one convex hull inside another;
thesis §1.2, the diagram's unbounded part) by cutting [g0, g1] into cells [a, b], bounding the
statement on each cell from its value at a centre c and a Lipschitz or Taylor term in the radius
``half``, and halving the cells where that does not decide (branch and bound; Moore, Kearfott &
Cloud, *Introduction to Interval Analysis*, §5.1 and ch. 7).  Every such argument needs

    [a, b] ⊆ [c − half, c + half]      in exact real arithmetic,

and the obvious floats c = fl((a + b)/2), half = (b − a)/2 · (1 + 10⁻¹²) do not give it: fl(a + b)
can be off by half an ulp of a + b, which the relative 10⁻¹² covers only while the cell is wider
than about 10⁴ ulps (a = 1, b = 1 + 3·2⁻⁵²: c = 1 + 2·2⁻⁵², the exact midpoint 1 + 1.5·2⁻⁵², so
c − half > a by half an ulp of 1).  :func:`cell_balls` gives the cover with a proof:

* c = fl(fl(a + b)/2) lies in [a, b] (rounding is monotone and 2a, 2b, a = 2a/2 are exact away
  from overflow and the subnormal range, where the halving is still monotone);
* each of c − a, b − c is a non-negative float difference rounded to nearest, so its exact value
  is at most the next double above its float value (the rounding error is at most half an ulp of
  the result, the step to the next double a whole one);
* ``half`` is the larger of the two, moved up to the next double, then multiplied by 1 + 10⁻¹²
  (kept as the slack of the callers' products of ``half`` with float Lipschitz bounds, as before).

:func:`halve` cuts the undecided cells at their float midpoints: the two new cells [a, m], [m, b]
share the double m ∈ [a, b], so their union is the old cell exactly and no direction is lost.

Public API: :func:`cell_balls`, :func:`halve`.
"""
from __future__ import annotations

import numpy as np

__all__ = ["cell_balls", "halve"]


def cell_balls(a, b):
    """(c, half) for float cells a ≤ b (arrays or scalars): [a, b] ⊆ [c − half, c + half] exactly
    (module docstring)."""
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    c = 0.5 * (a + b)
    half = np.nextafter(np.maximum(c - a, b - c), np.inf) * (1 + 1e-12)
    return c, half


def halve(a, b, undecided, *carry):
    """The cells [a, b] where ``undecided``, each cut at its float midpoint into [a, m] and
    [m, b]; the arrays of ``carry`` (per-cell data such as a site index) follow their cells.
    Returns (a', b', *carry')."""
    a, b = a[undecided], b[undecided]
    mid = 0.5 * (a + b)
    out = [np.concatenate([a, mid]), np.concatenate([mid, b])]
    for x in carry:
        x = x[undecided]
        out.append(np.concatenate([x, x]))
    return tuple(out)
