"""Equal disjoint circles: their Voronoi diagram is the Voronoi diagram of their centres.

**Theorem.**  Let C_k = ∂D(c_k, ρ), k = 1..n, be circles of one radius ρ > 0 with
|c_i − c_j| > 2ρ for i ≠ j.  Then for every point q the set of sites nearest to q is the set of
centres nearest to q; so the two Voronoi diagrams (vertices, edges, and the sites of each) are
the same, and a vertex's radius is the centres' radius minus ρ.

*Proof.*  Outside every disc, d(q, C_k) = |q − c_k| − ρ: the same order as |q − c_k| (additively
weighted points with equal weights, thesis §3.1.2).  Inside D_k, at t = |q − c_k| ≤ ρ:
d(q, C_k) = ρ − t, and for j ≠ k, d(q, C_j) ≥ |q − c_j| − ρ ≥ |c_j − c_k| − t − ρ > ρ − t, so C_k
alone is nearest; and |q − c_j| ≥ |c_j − c_k| − t > 2ρ − t ≥ t = |q − c_k|, so c_k alone is the
nearest centre.  ∎

The separation needs checking only on the Delaunay edges of the centres: a nearest neighbour c_j
of c_i is a Delaunay neighbour (the open disc of diameter [c_i, c_j] holds no centre, and no
other centre lies on its circle, since such a centre would be nearer to c_i than c_j; so the
midpoint lies on the Voronoi edge of c_i and c_j), hence min_{i≠j} |c_i − c_j| is attained on a
Delaunay edge.  The comparison |c_i − c_j|² > 4ρ² is exact (rational centres and r2 = ρ²).

Used by :func:`runtime.voronoi.verify.certificate.verify`: a diagram of equal circles that the
circle route does not prove is proved as the diagram of the centres (point sites, whose
predicates are exact: :mod:`runtime.voronoi.verify.exact_edges`), and the separation is checked
on that diagram's Delaunay edges.

Public API: :func:`equal_radius`, :func:`centres_diagram`, :func:`separated_on`.
"""
from __future__ import annotations

import copy
import math

from ...predicates.circles import Circle, Point

__all__ = ["equal_radius", "centres_diagram", "separated_on"]


def equal_radius(sites):
    """The common squared radius r2 > 0 of ``sites`` when all are circles (not points) of that
    same exact r2, else None."""
    if not sites or not all(isinstance(s, Circle) and not isinstance(s, Point) for s in sites):
        return None
    r2 = {s.r2 for s in sites}
    if len(r2) != 1:
        return None
    (r,) = r2
    return r if r > 0 else None


def centres_diagram(D, sites, r2):
    """The diagram D of the circles ``sites`` (radius √r2) read as a diagram of their centres:
    point sites, vertex radii plus ρ (a float; the verifier compares reported radii within its
    tolerance), the same edges.  Returns (diagram, centres)."""
    rho = math.sqrt(float(r2))
    centres = [Point(s.cx, s.cy) for s in sites]
    Dp = copy.copy(D)
    Dp.sites = [Point(s.cx, s.cy) for s in D.sites]
    Dp.vertices = [copy.copy(v) for v in D.vertices]
    for v in Dp.vertices:
        v.radius = float(v.radius) + rho
    Dp.edges = [copy.copy(e) for e in D.edges]
    Dp.problems = []
    Dp.stats = {}
    if hasattr(Dp, "construction"):
        Dp.construction = None
    return Dp, centres


def separated_on(sites, pairs, r2) -> list[str]:
    """Problems (empty when none): the pairs of ``pairs`` whose centres are not more than 2ρ apart
    (exact, |c_i − c_j|² > 4·r2)."""
    bad = []
    for i, j in pairs:
        a, b = sites[i], sites[j]
        if (a.cx - b.cx) ** 2 + (a.cy - b.cy) ** 2 <= 4 * r2:
            bad.append(f"sites {i}, {j}: equal circles not disjoint (centres at most 2 radii apart)")
    return bad
