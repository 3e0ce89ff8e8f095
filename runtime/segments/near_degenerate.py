"""Clusters of Voronoi vertices too close for samples: the local diagram of affine distances.

Input coordinates are doubles, i.e. exact binary rationals, so a shape that is degenerate in
exact arithmetic — a regular polygon, whose sides are all tangent to one circle — is almost never
exactly degenerate as given: the true diagram has n − 2 vertices within ~10⁻¹⁵ of the centre,
joined by edges of that length (thesis §1.2: the diagram is defined by exact predicates on the
input, not by a tolerance).  No sample spacing reaches that scale; the sampled construction
(:mod:`runtime.segments.construction`) sees a cloud of candidate vertices (the equidistant points
of many triples of sites, all within 10⁻¹⁵ of each other) and cannot decide which are empty.

Near such a cluster centre c, every site whose distance to c is within τ of the smallest is an
open segment touched in its interior, on a fixed side: its distance is the affine function
f_s(p) = h_s − u_s·p (u_s the unit normal towards the segment's line, h_s its offset), exactly
(for p near c).  The local diagram is then the minimisation diagram of n affine functions, the
projection of the lower envelope of n planes: dual to the regular triangulation of the points u_s
(all on the unit circle, so in convex position) lifted to the heights h_s (Aurenhammer, *Power
diagrams*, SIAM J. Comput. 16, 1987, §4; Edelsbrunner–Seidel, *Voronoi diagrams and
arrangements*, 1986).  It has n − 2 vertices (one per triangle), n − 3 bounded edges (the
diagonals) and n unbounded edges (the sides of the convex polygon: angularly consecutive normals),
which are the edges leaving the cluster.

Point sites alone work the same way with squared distances: |x − p|² − |x|² = |p|² − 2p·x is
affine with u = 2p (rational), and near-co-circular points are in convex position: their local
diagram is dual to their Delaunay triangulation (the lifting map).  A segment whose nearest
point is beyond an end that is a site of the cluster is left out (such ties belong to the end,
thesis §2.2); points mixed with segment interiors are declined.

The triangulation is built by gift wrapping from a side (i, k) of the polygon: walking in along
the bisector f_i = f_k, the apex is the site m of the chain between i and k that ties first
(the largest parameter t_m); the two sub-chains recurse.  Each comparison of parameters is done in
arb balls with rational inputs (the normals' norms √(a² + b²) enclosed), at increasing precision;
parameters not separated at 512 bits are taken as equal: a vertex of degree > 3 (shapes with
exact symmetries, such as an integer square's centre, or four sides of a float octagon mirrored
exactly), whose sites are then the tied apexes of the chain.  Nothing here is a proof: the certificate
(:func:`runtime.segments.certificate.verify_segments`) proves the spliced vertices and edges like
any others.

Public API: :func:`affine_diagram`, :func:`splice_clusters`, :class:`LocalDiagram`, :class:`Splice`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from flint import arb, ctx, fmpq
from scipy.spatial import cKDTree

from ..sites.rationals import to_fraction
from ..voronoi.structure import DiagramVertex
from .distance import site_distances
from .elementary import POINT, SEGMENT, ElementarySites

__all__ = ["affine_diagram", "splice_clusters", "LocalDiagram", "Splice"]

#: two proved candidate vertices of different triples closer than this (times 1 + |x| + |y| + r)
#: belong to one cluster: far below any sample spacing the construction reaches
CLUSTER_RADIUS = 1e-9
EPS = float(np.finfo(float).eps)
#: at most this (times the scale) above the smallest distance at a cluster's centre, sites take part
SITE_MARGIN = 1e-7
PRECISIONS = (128, 256, 512)
#: parameters not separated at this precision are taken as equal (a vertex of degree > 3; the
#: certificate decides it exactly, :mod:`runtime.segments.certificate_exact`)
TIE_PRECISION = 512


@dataclass
class LocalDiagram:
    """The diagram of a cluster: ``vertices`` (ccw site tuple, x, y, r as floats), ``inner``
    edges (pair, vertex index, vertex index) and ``exits`` (pair -> vertex index): the unbounded
    edges, which leave the cluster."""

    sites: tuple
    vertices: list = field(default_factory=list)
    inner: list = field(default_factory=list)
    exits: dict = field(default_factory=dict)


def _q(v) -> fmpq:
    f = to_fraction(v)
    return fmpq(f.numerator, f.denominator)


def _affine(E: ElementarySites, s: int, c) -> tuple | None:
    """(u_x, u_y, h) as rationals and the norm N² of segment s's line, with f_s(p) = h − u·p, on
    the side of c; None when s is not a segment touched in its interior near c."""
    if E.kind[s] == POINT:
        # |x − p|² − |x|² = |p|² − 2 p·x: affine, with u = 2p (the squared distances of points
        # differ from these by the same |x|², so their minimisation diagram is the same)
        px, py = (_q(v) for v in E.xy[s])
        return (2 * px, 2 * py, px * px + py * py, None)
    if E.kind[s] != SEGMENT:
        return None
    (ax, ay), (bx, by) = (E.xy[int(E.ends[s, k])] for k in (0, 1))
    ax, ay, bx, by = _q(ax), _q(ay), _q(bx), _q(by)
    a, b = by - ay, ax - bx
    c0 = -(a * ax + b * ay)
    A, B = E.A[s], E.B[s]
    d = B - A
    t = float(np.dot(np.asarray(c) - A, d) / np.dot(d, d))
    if not 1e-6 < t < 1 - 1e-6:
        return None                 # the foot is near an end: not affine near c
    val = float(a) * c[0] + float(b) * c[1] + float(c0)
    sigma = 1 if val > 0 else -1
    return (-sigma * a, -sigma * b, sigma * c0, a * a + b * b)


def affine_diagram(E: ElementarySites, sites, centre) -> LocalDiagram | str:
    """The minimisation diagram of the affine distances of ``sites`` (segments touched in their
    interiors near ``centre``), by gift wrapping of the regular triangulation (module docstring);
    a message when the sites are not of that kind or a tie is not decided."""
    sites = sorted(int(s) for s in sites)
    if len(sites) < 3:
        return "fewer than three sites"
    rat = {}
    for s in sites:
        got = _affine(E, s, centre)
        if got is None:
            return f"site {s} is not a segment touched in its interior near the cluster"
        rat[s] = got
    squared = {rat[s][3] is None for s in sites}
    if len(squared) > 1:
        return "points and segment interiors in one cluster (distances and squared distances)"
    squared = squared.pop()
    u0 = (2 * float(centre[0]), 2 * float(centre[1])) if squared else (0.0, 0.0)
    ang = {s: math.atan2(float(rat[s][1]) - u0[1], float(rat[s][0]) - u0[0]) for s in sites}
    order = sorted(sites, key=lambda s: ang[s])      # ccw by contact direction u_s
    angles = sorted(ang.values())
    gaps = [(angles[(k + 1) % len(angles)] - angles[k]) % (2 * math.pi) for k in range(len(angles))]
    if min(gaps) < 1e-9:
        return "two sites with (nearly) parallel normals on the same side"
    old = ctx.prec
    try:
        for prec in PRECISIONS:
            ctx.prec = prec
            got = _wrap(order, rat, squared)
            if not isinstance(got, str):
                got.sites = tuple(sites)
                return got
    finally:
        ctx.prec = old
    return got


def _wrap(order, rat, squared: bool) -> LocalDiagram | str:
    """Gift wrapping at the current arb precision (``squared``: point sites, whose affine functions
    are squared distances minus |x|²)."""
    U = {}
    for s in order:
        ux, uy, h, N2 = rat[s]
        N = arb(1) if N2 is None else arb(N2).sqrt()
        U[s] = (arb(ux) / N, arb(uy) / N, arb(h) / N)
    out = LocalDiagram(tuple(order))

    def solve(chain):
        i, k = chain[0], chain[-1]
        uix, uiy, hi = U[i]
        ukx, uky, hk = U[k]
        wx, wy = uix - ukx, uiy - uky
        w2 = wx * wx + wy * wy
        p0x, p0y = (hi - hk) * wx / w2, (hi - hk) * wy / w2      # on the bisector of i and k
        dx, dy = -(uky - uiy), ukx - uix                            # along it
        m1 = chain[1]
        side = (U[m1][0] - uix) * dx + (U[m1][1] - uiy) * dy
        if side > 0:
            dx, dy = -dx, -dy
        elif not side < 0:
            return "undecided side"
        ts = []
        for m in chain[1:-1]:
            umx, umy, hm = U[m]
            den = (umx - uix) * dx + (umy - uiy) * dy
            if not den < 0:
                return "undecided slope"
            ts.append(((hm - hi) - (umx - uix) * p0x - (umy - uiy) * p0y) / den)
        best = 0                      # the largest, compared in arb (floats round ties away)
        for q in range(1, len(ts)):
            if ts[q] > ts[best] or (not ts[best] > ts[q] and ts[q].mid() > ts[best].mid()):
                best = q
        tied = [q for q in range(len(ts)) if q == best or not ts[best] > ts[q]]
        if len(tied) > 1 and ctx.prec < TIE_PRECISION:
            return "tie"              # not separated yet: more precision
        apex = [q + 1 for q in tied]  # a tie at TIE_PRECISION: one vertex of degree > 3
        px, py = p0x + ts[best] * dx, p0y + ts[best] * dy
        r = hi - uix * px - uiy * py
        if squared:
            r = (r + px * px + py * py).sqrt()
        members = [0] + apex + [len(chain) - 1]
        sites = tuple(chain[q] for q in members)
        m = sites.index(min(sites))
        vid = len(out.vertices)
        out.vertices.append((sites[m:] + sites[:m], float(px.mid()), float(py.mid()), float(r.mid())))
        for qa, qb in zip(members, members[1:]):
            sub = chain[qa:qb + 1]
            pair = tuple(sorted((sub[0], sub[-1])))
            if len(sub) == 2:
                out.exits[pair] = vid
                continue
            got = solve(sub)
            if isinstance(got, str):
                return got
            out.inner.append((pair, vid, got))
        return vid

    got = solve(list(order))
    if isinstance(got, str):
        return got
    out.exits[tuple(sorted((order[0], order[-1])))] = got
    return out


@dataclass
class Splice:
    """The clusters resolved in one round: triangle -> cluster, the local diagrams and the ids
    their vertices got in the round's vertex list."""

    tri_cluster: dict = field(default_factory=dict)
    diagrams: list = field(default_factory=list)
    vids: list = field(default_factory=list)

    def rewire(self, raw, tri_vid) -> list:
        """The walks with those ending in a cluster re-ended at the local vertex of their pair
        (dropped when the pair leaves no cluster there, or when both ends are in one cluster),
        plus the clusters' inner edges."""
        if not self.diagrams:
            return raw
        out = []
        for pair, start, chain, end in raw:
            ends = []
            drop = False
            for e in (start, end):
                k = self.tri_cluster.get(e[1]) if e is not None and e[0] == "tri" else None
                if k is None:
                    ends.append(e)
                    continue
                v = self.diagrams[k].exits.get(tuple(sorted(pair)))
                if v is None or any(x == ("c", k) for x in ends):
                    drop = True
                    break
                ends.append(("c", k))
            if drop:
                continue
            ends = [self._end(e, pair, tri_vid) for e in ends]
            out.append((pair, ends[0], chain, ends[1]))
        for k, D in enumerate(self.diagrams):
            for pair, a, b in D.inner:
                out.append((pair, self._key(k, a, tri_vid), [], self._key(k, b, tri_vid)))
        return out

    def _key(self, k, a, tri_vid):
        key = ("near-degenerate", k, a)
        tri_vid[key] = self.vids[k][a]
        return ("tri", key)

    def _end(self, e, pair, tri_vid):
        if e is None or e[0] != "c":
            return e
        return self._key(e[1], self.diagrams[e[1]].exits[tuple(sorted(pair))], tri_vid)


def splice_clusters(E: ElementarySites, jobs, vertices, caches) -> tuple:
    """(jobs left, :class:`Splice`): the candidate vertices (jobs (triangle, triple, solution,
    seed)) whose proved solutions gather within :data:`CLUSTER_RADIUS` of each other, resolved
    by :func:`affine_diagram`; the local vertices are appended to ``vertices``.  A cluster that
    does not resolve (other kinds of sites, an exact tie) stays with the sampled construction."""
    splice = Splice()
    pts = [(q, sol) for q, (_t, _tr, sol, _s) in enumerate(jobs) if sol.status == "proved"]
    if len(pts) < 2:
        return jobs, splice
    X = np.array([[sol.x, sol.y] for _, sol in pts])
    scale = 1.0 + np.abs(X).sum(axis=1) + np.array([sol.r for _, sol in pts])
    tree = cKDTree(X)
    parent = list(range(len(pts)))

    def find(a):
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    for a, b in tree.query_pairs(CLUSTER_RADIUS * float(scale.max())):
        if abs(X[a] - X[b]).max() <= CLUSTER_RADIUS * min(scale[a], scale[b]):
            parent[find(a)] = find(b)
    groups: dict = {}
    for a in range(len(pts)):
        groups.setdefault(find(a), []).append(a)
    taken = set()
    memo = caches.setdefault("near_degenerate", {})
    for members in groups.values():
        triples = {tuple(jobs[pts[a][0]][1]) for a in members}
        if len(triples) < 2:
            continue
        c = X[members].mean(axis=0)
        key = tuple(sorted(triples))
        if key not in memo:
            spread = float(np.abs(X[members] - c).max())
            memo[key] = _resolve(E, c, float(scale[members].max()), spread)
        D = memo[key]
        if isinstance(D, str):
            continue
        k = len(splice.diagrams)
        splice.diagrams.append(D)
        ids = []
        for sites, x, y, r in D.vertices:
            ids.append(len(vertices))
            vertices.append(DiagramVertex(len(vertices), sites, x, y, r, True))
        splice.vids.append(ids)
        for a in members:
            taken.add(pts[a][0])
            splice.tri_cluster[jobs[pts[a][0]][0]] = k
    if not taken:
        return jobs, splice
    return [job for q, job in enumerate(jobs) if q not in taken], splice


def _owned_by_ends(E: ElementarySites, sites, c) -> list:
    """``sites`` without the segments whose nearest point to c is clearly beyond an end that is a
    point site of the list (by the convention of thesis §2.2 such a tie belongs to the end)."""
    keep = set(int(s) for s in sites)
    for s in list(keep):
        if E.kind[s] != SEGMENT:
            continue
        A, B = E.A[s], E.B[s]
        d = B - A
        t = float(np.dot(np.asarray(c) - A, d) / np.dot(d, d))
        end = int(E.ends[s, 0]) if t < -1e-6 else (int(E.ends[s, 1]) if t > 1 + 1e-6 else None)
        if end is not None and end in keep:
            keep.discard(s)
    return sorted(keep)


def _resolve(E: ElementarySites, c, scale: float, spread: float) -> LocalDiagram | str:
    """The local diagram around c of every site within τ of the nearest (τ: 256 times the spread
    of the cluster's candidates, at least 1000 ulp of the coordinates, at most
    :data:`SITE_MARGIN` of the scale), if all its vertices stay within τ/4 of c: then every other
    site is farther than the local sites there."""
    n = len(E)
    d = site_distances(E, np.arange(n), np.repeat(np.asarray(c, float)[None, :], n, axis=0))
    tau = min(max(256 * spread, 1e3 * EPS * scale), SITE_MARGIN * scale)
    sites = np.nonzero(d <= d.min() + tau)[0].tolist()
    D = affine_diagram(E, _owned_by_ends(E, sites, c), c)
    if isinstance(D, str):
        return D
    if any(math.hypot(x - c[0], y - c[1]) > tau / 4 for _, x, y, _r in D.vertices):
        return "a vertex of the local diagram is outside the cluster"
    return D
