"""The Voronoi diagram of collinear points: no sample triangulation exists, the edges are lines.

For points on one line the diagram has no vertex (thesis §1.2: a vertex needs three sites on an
empty circle, and three collinear points lie on no circle); its edges are the perpendicular
bisectors of consecutive points along the line, each a whole line (both ends at infinity).

Public API: :func:`collinear`, :func:`collinear_points_diagram`.
"""
from __future__ import annotations

import time

import numpy as np

from .geometry import rounding_slack
from .structure import Diagram, DiagramEdge

__all__ = ["collinear", "collinear_points_diagram"]


def collinear(C) -> bool:
    """Are the points C (float) on one line (exactly, with the exact float values)?"""
    from fractions import Fraction

    if len(C) < 3:
        return True
    p0 = [Fraction(v) for v in C[0]]
    far = max(range(len(C)), key=lambda m: abs(C[m, 0] - C[0, 0]) + abs(C[m, 1] - C[0, 1]))
    d = [Fraction(C[far, 0]) - p0[0], Fraction(C[far, 1]) - p0[1]]
    return all(d[0] * (Fraction(y) - p0[1]) - d[1] * (Fraction(x) - p0[0]) == 0 for x, y in C.tolist())


def collinear_points_diagram(S, sites, notes, certify, stats, t_start):
    """Collinear point sites (no triangulation exists): the edges are the perpendicular bisectors of
    consecutive points along the line, each a whole line without vertices."""
    C = S.C
    d = C[np.argmax(np.abs(C - C[0]).sum(axis=1))] - C[0]
    d = d / np.hypot(*d)
    order = np.argsort(C @ d, kind="stable")
    nrm = np.array([-d[1], d[0]])
    far = 2.0 * (S.window[2] - S.window[0])
    edges = []
    for a, b in zip(order[:-1].tolist(), order[1:].tolist()):
        m = (C[a] + C[b]) / 2
        poly = np.array([m - far * nrm, m, m + far * nrm])
        tol = float(rounding_slack(np.abs(poly).sum(axis=1).max() + np.abs(C[[a, b]]).sum()))
        edges.append(DiagramEdge(len(edges), (min(a, b), max(a, b)), (None, None), False, poly, tol, False))
    D = Diagram(S.sites, [], edges, False, list(notes), stats)
    if certify:
        try:
            from .verify.certificate import verify
        except ImportError:
            D.problems.append("verifier runtime.voronoi.verify.certificate not available: edges not proved")
        else:
            cert = verify(D, sites)
            D.certified = bool(cert.ok) and not notes
            D.problems.extend(cert.problems)
            for e, ok in zip(D.edges, cert.edges):
                e.certified = bool(ok)
    else:
        D.problems.append("not verified (certify=False)")
    D.stats["seconds"] = {"total": round(time.perf_counter() - t_start, 4)}
    return D
