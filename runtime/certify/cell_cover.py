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

:func:`walk_cells` is the branch-and-bound loop of those walks, written once: balls for the
cells, a caller's test on each ball, halving of the undecided cells, a work budget.

Public API: :func:`cell_balls`, :func:`halve`, :func:`walk_cells` (with its records
:class:`CellTest` and :class:`CoverOutcome`).
"""
from __future__ import annotations

from typing import Callable, NamedTuple

import numpy as np

__all__ = ["cell_balls", "halve", "walk_cells", "CellTest", "CoverOutcome"]


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


class CellTest(NamedTuple):
    """A caller's verdict on the balls [c − half, c + half] of one round of cells (per cell):
    ``fault`` where the statement is proved false at some direction of the cell (None: the
    test never refutes), ``undecided`` where it is not proved on the whole cell."""

    fault: np.ndarray | None
    undecided: np.ndarray


class CoverOutcome(NamedTuple):
    """The end of :func:`walk_cells`: ``proved`` (every cell decided), else the ``exit``
    ("fault", "undecided" or "budget") and, for the first two, the ``cell`` (a, b, *carry)
    of the first cell that ended the walk."""

    proved: bool
    exit: str
    cell: tuple | None = None


def _first(a, b, carry, mask) -> tuple:
    i = int(np.flatnonzero(mask)[0])
    return (float(a[i]), float(b[i]), *(x[i] for x in carry))


def walk_cells(a, b, test: Callable[..., CellTest], max_work: int, carry=(), smallest=None) -> CoverOutcome:
    """Prove a statement on every float cell [a_i, b_i] (branch and bound, module docstring).

    Each round: the cells are counted against ``max_work`` (the running total of cells tested;
    over it: exit "budget"); :func:`cell_balls` gives c, half with [a, b] ⊆ [c − half, c + half];
    ``test(c, half, *carry)`` returns a :class:`CellTest`; a cell with ``fault`` ends the walk
    (exit "fault"); an undecided cell with half < ``smallest`` (when given) ends it too (exit
    "undecided": halving no longer helps); the other undecided cells are halved by :func:`halve`
    (``carry``: per-cell arrays, such as a rival site, that follow their cells).  The cells
    never dropped by halving cover the initial ones exactly, so when none is left undecided
    (``proved``), the statement holds on the union of the initial cells, provided ``test``
    declares decided only cells whose whole ball satisfies it.

    The walks of the verifier map onto it as follows (all four answer False on every exit
    but "decided", as before the loop was shared): :func:`runtime.voronoi.verify.closure.
    verify_accounting_conics`' site dominance (fault: a rival larger at a cell's centre; no
    ``smallest``), :func:`runtime.voronoi.verify.support_balls.sole_maximum` (no fault;
    ``smallest`` 10⁻¹⁵(1 + |g0|)), the asymptotic functions of :mod:`runtime.voronoi.verify.
    far_accounting` (no fault; ``smallest`` 10⁻¹³) and the nesting of :mod:`runtime.voronoi.
    verify.hull_nesting` (fault: the inner support value above the outer one at a centre; no
    ``smallest``).
    """
    carry = tuple(carry)
    work = 0
    while len(a):
        work += len(a)
        if work > max_work:
            return CoverOutcome(False, "budget")
        c, half = cell_balls(a, b)
        verdict = test(c, half, *carry)
        if verdict.fault is not None and np.any(verdict.fault):
            return CoverOutcome(False, "fault", _first(a, b, carry, verdict.fault))
        bad = verdict.undecided
        if smallest is not None:
            stuck = bad & (half < smallest)
            if np.any(stuck):
                return CoverOutcome(False, "undecided", _first(a, b, carry, stuck))
        a, b, *carry = halve(a, b, bad, *carry)
    return CoverOutcome(True, "decided")
