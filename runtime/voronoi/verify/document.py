"""Checks of a diagram document that need no geometry beyond its own fields (thesis §1.2 defines
what the fields mean; :mod:`runtime.voronoi.structure` documents the schema).

* **Finite numbers**: every vertex coordinate and radius, every polyline point and every stated
  tolerance is a finite float, the tolerance ≥ 0 (a NaN would otherwise compare as "within any
  tolerance" or "beyond every bound" depending on how a test is written).
* **The Delaunay graph stated by the document** (``delaunay_edges``, when present) is exactly the
  set of site pairs of its edges: the certificate proves the edges, so a list that differs from
  their pairs is a claim nothing proves.
* **A closed edge winds once** around the site nested inside its loop (thesis Prop. 1.2.1: the
  closed edge is the boundary of the nested site's region, a Jordan curve around it): its polyline's
  winding number about a point of that site is ±1, so a loop traversed twice, or folded back on
  itself, is rejected even where each of its points lies on the bisector.

Public API: :func:`check_document`, :func:`winding_number`.
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["check_document", "winding_number"]


def winding_number(P, c) -> float:
    """The winding number of the closed polyline P (first point = last) about the point c: the sum
    of the signed angles subtended by its segments, over 2π (float; an integer up to rounding when c
    is away from the polyline)."""
    V = np.asarray(P, float) - np.asarray(c, float)
    a = np.arctan2(V[:, 1], V[:, 0])
    d = np.diff(a)
    d = (d + np.pi) % (2 * np.pi) - np.pi
    return float(d.sum() / (2 * np.pi))


def _inner_point(g):
    """A point inside a bounded site's convex region (the centre of its bounding box)."""
    b = g.bounding_box()
    if not all(math.isfinite(v) for v in b):
        return None
    return ((b[0] + b[2]) / 2, (b[1] + b[3]) / 2)


def check_document(D, doc, geoms, problems) -> None:
    """The checks of the module docstring; problems are appended, naming the part.  ``doc``: the
    JSON document when the diagram came as one (its ``delaunay_edges`` are compared), else None."""
    for v in D.vertices:
        if not all(math.isfinite(float(t)) for t in (v.x, v.y, v.radius)):
            problems.append(f"vertex {v.id}: non-finite position or radius")
    for e in D.edges:
        tol = float(e.tolerance)
        if not (math.isfinite(tol) and tol >= 0):
            problems.append(f"edge {e.id} (sites {', '.join(map(str, e.sites))}): its stated tolerance "
                            f"{tol!r} is not a finite number >= 0")
        P = np.asarray(e.polyline, float).reshape(-1, 2)
        if not np.isfinite(P).all():
            problems.append(f"edge {e.id} (sites {', '.join(map(str, e.sites))}): non-finite polyline point")
        elif e.closed:                     # fewer than 3 points wind 0 times: refused below
            pair = [int(s) for s in e.sites]
            if not all(0 <= s < len(geoms) for s in pair):
                continue
            inner = None
            for s, o in (pair, pair[::-1]):
                bs, bo = geoms[s].bounding_box(), geoms[o].bounding_box()
                if all(map(math.isfinite, bs)) and bs[0] >= bo[0] and bs[1] >= bo[1] and bs[2] <= bo[2] and bs[3] <= bo[3]:
                    inner = _inner_point(geoms[s])
                    break
            loop = P if len(P) and (P[0] == P[-1]).all() else np.vstack([P, P[:1]])     # closed as drawn
            w = winding_number(loop, inner) if inner is not None else 0.0
            if not abs(abs(w) - 1) < 1e-6:
                problems.append(f"edge {e.id} (sites {', '.join(map(str, e.sites))}): the closed edge winds "
                                f"{w:.3g} times around the nested site (once expected)")
    if doc is not None and "delaunay_edges" in doc:
        try:
            stated = sorted({tuple(sorted(int(t) for t in p)) for p in doc["delaunay_edges"]})
        except (TypeError, ValueError):
            problems.append("delaunay_edges: not a list of site pairs")
            return
        own = sorted({tuple(sorted(int(t) for t in e.sites)) for e in D.edges})
        if stated != own:
            extra = sorted(set(stated) - set(own))[:3]
            missing = sorted(set(own) - set(stated))[:3]
            problems.append("delaunay_edges: the document's list differs from the pairs of its edges"
                            + (f" (listed, no edge: {extra})" if extra else "")
                            + (f" (edges, not listed: {missing})" if missing else ""))
