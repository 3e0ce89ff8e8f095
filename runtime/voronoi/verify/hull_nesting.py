"""Nesting of bounded convex sites, step (b) of the accounting of a diagram's components.

By the thesis' Prop. 1.2.1 a component of the Voronoi diagram without points at infinity exists
only when a site lies inside another's interior.  :func:`hulls_disjoint` proves, with the support
functions h_k of :class:`runtime.voronoi.verify.support.SupportTable` (Schneider, *Convex
Bodies*, §1.7), that the convex hulls of the sites are pairwise disjoint (a direction u with
h_a(u) + h_b(−u) < 0 on a grid of 256 directions) or one inside the open convex region of a
circle or an ellipse (h_in < h_out in every direction, cells of directions halved until
decided: on a cell of half-width δ the difference moves by at most 2W·δ), with nesting depth at
most one (no container is itself nested).  Used by
:func:`runtime.voronoi.verify.closure.verify_accounting_conics` and, for the bounded sites of a
scene with unbounded ones, by :func:`runtime.voronoi.verify.far_accounting.accounting_unbounded`.

Public API: :func:`hulls_disjoint`, :func:`gap_note`.
"""
from __future__ import annotations

import math

import numpy as np

from ...certify.cell_cover import CellTest, walk_cells

__all__ = ["hulls_disjoint", "gap_note", "sole_leader"]


def hulls_disjoint(sup, problems, max_work, names=None) -> bool:
    """Step (b) (module docstring) for the sites of ``sup``; ``names``: the site numbers of the
    diagram for the messages (default: the table's indices)."""
    W, mu = sup.W, sup.mu
    n = sup.n
    name = (lambda k: k) if names is None else (lambda k: names[k])
    # ---- (b) pairwise disjoint convex hulls
    bx = []
    for k in range(n):
        c, r = sup.cen[k], sup.rho[k]
        bx.append((c[0] - r, c[1] - r, c[0] + r, c[1] + r))
    bx = np.array(bx)
    order = np.argsort(bx[:, 0])
    th = np.linspace(0.0, 2 * math.pi, 257)[:-1]
    H = {}
    nested = {}

    def hv(k):
        if k not in H:
            H[k] = (sup.h(k, th), sup.h(k, th + math.pi))
        return H[k]

    for ia in range(n):
        a = int(order[ia])
        for ib in range(ia + 1, n):
            b = int(order[ib])
            if bx[b, 0] > bx[a, 2] + 1e-9 * W:
                break
            if bx[b, 1] > bx[a, 3] + 1e-9 * W or bx[a, 1] > bx[b, 3] + 1e-9 * W:
                continue
            sep = hv(a)[0] + hv(b)[1]
            if np.any(sep < -4 * mu):
                continue
            # not separated: one site strictly inside the other's convex region (h_in < h_out)
            for inner, outer in ((a, b), (b, a)):
                if sup.kind[outer] in ("circle", "ellipse") and _below(sup, inner, outer, max_work):
                    nested[inner] = outer
                    break
            else:
                problems.append(f"sites {min(name(a), name(b))} and {max(name(a), name(b))}: convex hulls not proved disjoint, "
                                "nor one inside the other")
                return False
    deep = sorted(k for k, out in nested.items() if out in nested)
    if deep:
        problems.append(f"site {name(deep[0])} is nested two deep (inside site {name(nested[deep[0]])}, inside site "
                        f"{name(nested[nested[deep[0]]])}): nesting depth > 1 is not handled")
        return False
    return True


def _below(sup, b, a, max_work) -> bool:
    """Is h_b(θ) < h_a(θ) for every θ, i.e. conv S_b inside the open convex region of S_a
    (support functions of convex bodies)?  Cells halved until decided
    (:func:`runtime.certify.cell_cover.walk_cells`), as in
    :func:`runtime.voronoi.verify.closure.verify_accounting_conics`' walk."""
    c0 = np.linspace(0.0, 2 * math.pi, 65)[:-1]
    c1 = c0 + 2 * math.pi / 64

    def test(thc, half):
        diff = sup.h(a, thc) - sup.h(b, thc)
        gap = diff - 2 * sup.W * half - 4 * sup.mu
        # fault: h_b above h_a at a centre (beyond the rounding margin)
        return CellTest(fault=diff < -4 * sup.mu, undecided=~(gap > 0))

    return walk_cells(c0, c1, test, max_work).proved


def sole_leader(sup, max_work) -> int | None:
    """A site c with h_k < h_c in every direction for every other site k (all others inside its
    convex region), proved as in :func:`hulls_disjoint`; None if there is none.  Far away in
    every direction c is then strictly the nearest site (d_k = t − h_k(u) + O(W²/t), the gap
    min_θ (h_c − h_k) > 0 on the compact circle of directions): the diagram has no unbounded edge."""
    # the candidate: the largest support value in some direction, then checked everywhere
    c = int(np.argmax(sup.h(np.arange(sup.n), np.zeros(sup.n))))
    if sup.kind[c] not in ("circle", "ellipse"):
        return None
    return c if all(k == c or _below(sup, k, c, max_work) for k in range(sup.n)) else None


def gap_note(unproved_ends) -> str:
    """What a gap between consecutive proved ends at infinity means: an unbounded edge is missing,
    or it is one of the diagram's unbounded edges whose end was not proved (named)."""
    if not unproved_ends:
        return "an unbounded edge between them is missing"
    ids = sorted(unproved_ends)
    named = ", ".join(map(str, ids[:6])) + (", ..." if len(ids) > 6 else "")
    return (f"an unbounded edge between them is missing, or it is one whose end at infinity is not proved "
            f"(unbounded edge{'s' if len(ids) > 1 else ''} {named})")
