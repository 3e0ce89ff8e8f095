"""The tiles' diagrams, reported on global site indices, and their stitch into one diagram.

Each tile T (and the rim outside the sites' box B, :class:`runtime.voronoi.tiling.Rim`) is built
by :func:`runtime.voronoi.construction.voronoi` on its input S_T; :func:`build_tile` reports what
the locality lemma of :mod:`runtime.voronoi.tiling` lets it vouch for.

**What a region vouches for.**  A tile reports the vertices of its diagram whose float position
lies in its grid cell grown by μ (cells on the boundary of B extend to infinity) and whose empty
circle passes :func:`runtime.voronoi.tiling.local_vertex`; a vertex inside B that fails makes
the tile grow its halo and be rebuilt (``grow`` > 0), one outside B is left to the rim.  The rim
reports the vertices outside B whose circle misses the inner box B_w, and the edges to
infinity whose finite end passes the same test (else the rim grows).  An edge is reported with
its two ends by a region that vouches for one of them.  By the lemma every vertex of the
diagram of S in B is a vertex of the diagram of S_T for the tile T containing it, at the same
point, so it is reported.

**Stitch** (:func:`stitch`).  Vertex copies are merged by site set and position (within 1e-7 of
the scene's size; a triple of circles can have two vertices, told apart by position); copies
that disagree on the cyclic order of the sites or on the radius are refused
(:class:`StitchError`).  An edge copy is kept when both its ends are stitched vertices (or at
infinity), keyed by its site pair and its ends; copies with the same key are merged.  The merged
vertex keeps its first copy's position, and an edge reported with another copy's position has its
end moved onto it and its tolerance widened by the move (:func:`_snapped`: copies of a vertex far
from the sites differ by up to the merge tolerance).  Edges
without vertices (two sites, sites in a row) are not stitched: the caller builds such scenes in
one process.  Nothing here *proves* completeness: a vertex outside B whose circle reaches
into B_w, or a long edge whose far end no region matched, would be missing, and the
verifier says so.

**Certificate.**  The stitched diagram is a :class:`runtime.voronoi.structure.Diagram` on the
global site indices; the caller (:mod:`runtime.voronoi.distributed`) hands it to the independent
verifier (:func:`runtime.voronoi.verify.certificate.verify`), which proves every vertex and
edge and that nothing is missing (closure and accounting at infinity).  The lemma is what makes
the stitched combinatorics right; the proof of the result is the verifier's.

Public API: :func:`build_tile`, :func:`stitch`, :class:`StitchError`.
"""
from __future__ import annotations

import math
import time

import numpy as np

from .tiling import Rim, local_vertex

__all__ = ["build_tile", "stitch", "StitchError"]


class StitchError(ValueError):
    """Two tiles report incompatible copies of one vertex or edge."""


def _inside(cell, x, y) -> bool:
    return cell[0] <= x <= cell[2] and cell[1] <= y <= cell[3]


def build_tile(sites, index, region, margin: float, certify: bool = False) -> dict:
    """Build the diagram of a region's input (``sites``, global ``index``; the region a
    :class:`Tile` or the :class:`Rim`) and report, on global indices: the vertices it vouches
    for (a tile: in its cell grown by ``margin`` and passing :func:`local_vertex`; the rim:
    outside B and passing :meth:`Rim.outside`), ``grow``: how far the empty circle of a vertex
    the region must report sticks out (> 0: grow and rebuild), the edges with at least one
    vouched end (with both ends' site sets and positions; the rim reports the edges to infinity,
    whose finite end must pass :meth:`Rim.outside`), the problems and timings.  Runs in
    a worker: arguments and result are plain data."""
    from .construction import voronoi

    t0 = time.perf_counter()
    index = np.asarray(index, dtype=np.int64)
    d = voronoi(list(sites), certify=certify, progress=False)
    verts = {}
    grow = 0.0
    rim = isinstance(region, Rim)
    if not rim:
        cell = region.cell(margin)
        bx0, by0, bx1, by1 = region.bound
        inner_b = (bx0 - margin, by0 - margin, bx1 + margin, by1 + margin)
    for v in d.vertices:
        if rim:
            if not region.reports(v.x, v.y):
                continue
            out = region.outside(v.x, v.y, v.radius)
        else:
            if not _inside(cell, v.x, v.y):
                continue
            out = local_vertex(region, v.x, v.y, v.radius)
            if out > 0 and not _inside(inner_b, v.x, v.y):
                continue                    # outside B: the rim's to vouch for
        if out > 0:
            grow = max(grow, out)
            continue
        verts[v.id] = (tuple(int(index[s]) for s in v.sites), v.x, v.y, v.radius, bool(v.certified))
    pos = {v.id: v for v in d.vertices}
    edges = []
    vertexless = 0
    for e in d.edges:
        if e.ends[0] is None and e.ends[1] is None:
            vertexless += 1
            continue
        if None in e.ends:
            if not rim:
                continue                    # an end at infinity: the rim's to report
            v = pos[e.ends[0] if e.ends[1] is None else e.ends[1]]
            out = region.outside(v.x, v.y, v.radius)
            if out > 0:                     # the finite end is not vouched for: grow the rim
                grow = max(grow, out)
                continue
        elif not any(u in verts for u in e.ends):
            continue
        ends = tuple(None if u is None else (tuple(int(index[s]) for s in pos[u].sites), pos[u].x, pos[u].y)
                     for u in e.ends)
        edges.append((tuple(int(index[s]) for s in e.sites), ends, np.asarray(e.polyline, float),
                      float(e.tolerance), bool(e.certified)))
    return {"tile": region.index, "vertices": list(verts.values()), "edges": edges, "vertexless": vertexless,
            "grow": grow, "certified": bool(d.certified), "problems": list(d.problems)[:5], "sites": len(index),
            "seconds": time.perf_counter() - t0, "construction": d.stats.get("seconds", {})}


def _merge_key(sites_, x, y, tol, table):
    """The global id of the vertex with site set ``sites_`` near (x, y) in ``table`` (a dict
    frozenset -> list of (x, y, id)), or None."""
    for (px, py, gid) in table.get(frozenset(sites_), ()):
        if abs(px - x) <= tol and abs(py - y) <= tol:
            return gid
    return None


def _snapped(poly, tolerance, gends, vertices):
    """The polyline of an edge with its end points moved onto the merged vertices ``gends`` (a
    polyline runs from ends[0] to ends[1]), and its tolerance widened by the largest move: the
    copies of a vertex reported by two tiles differ by up to the merge tolerance (far from the
    sites, where the vertex is ill-conditioned), and an edge from the second tile ended at its own
    copy.  Moving a polyline's end point by δ moves each point of its last segment by at most δ,
    so the true arc within t of the old polyline is within t + δ of the new one."""
    P = np.array(poly, dtype=float).reshape(-1, 2)
    shift = 0.0
    for k, g in ((0, gends[0]), (len(P) - 1, gends[1])):
        if g is None or not len(P):
            continue
        v = vertices[g]
        d = math.hypot(P[k, 0] - v.x, P[k, 1] - v.y)
        if d > 0:
            P[k] = (v.x, v.y)
            shift = max(shift, d)
    if shift == 0.0:
        return poly, tolerance
    # the move and the new sum, rounded up
    return P, float(tolerance + shift * (1 + 1e-12) + 4e-16 * (abs(tolerance) + shift))


def stitch(sites, reports, scale: float):
    """The diagram of all ``sites`` from the tiles' ``reports`` (:func:`build_tile`): vertices
    merged by site set and position, edges by site pair and end vertices.  Returns a
    :class:`runtime.voronoi.structure.Diagram` (not certified) and stitch statistics.
    :class:`StitchError` when two copies disagree (a vertex's cyclic order, an edge's ends)."""
    from .structure import Diagram, DiagramEdge, DiagramVertex

    tol = 1e-7 * scale
    table: dict = {}
    vertices: list = []
    copies = 0
    for rep in sorted(reports, key=lambda r: r["tile"]):
        for (vs, x, y, r, ok) in rep["vertices"]:
            gid = _merge_key(vs, x, y, tol, table)
            if gid is not None:
                copies += 1
                w = vertices[gid]
                if tuple(w.sites) != tuple(vs) or abs(w.radius - r) > tol:
                    raise StitchError(f"tiles disagree on the vertex of sites {vs} near ({x:.6g}, {y:.6g})")
                w.certified = w.certified and ok
                continue
            table.setdefault(frozenset(vs), []).append((x, y, len(vertices)))
            vertices.append(DiagramVertex(len(vertices), tuple(vs), float(x), float(y), float(r), ok))
    edges: list = []
    seen: dict = {}
    unmatched = 0
    for rep in sorted(reports, key=lambda r: r["tile"]):
        for (pair, ends, poly, tolerance, ok) in rep["edges"]:
            gends = []
            for end in ends:
                gends.append(None if end is None else _merge_key(end[0], end[1], end[2], tol, table))
            if any(end is not None and g is None for end, g in zip(ends, gends)):
                unmatched += 1          # an end outside every reporting cell: another copy has it
                continue
            key = (tuple(pair), frozenset(gends) if None not in gends else (tuple(g for g in gends if g is not None),))
            if key in seen:
                continue
            seen[key] = len(edges)
            poly, tolerance = _snapped(poly, tolerance, gends, vertices)
            edges.append(DiagramEdge(len(edges), tuple(sorted(pair)), tuple(gends), False, poly, tolerance, ok))
    # a polyline runs from ends[0] to ends[1]: pairs are stored sorted, as the construction does
    D = Diagram(list(sites), vertices, edges, False, [], {})
    return D, {"vertex_copies_merged": copies, "edge_copies_unmatched": unmatched,
               "vertices": len(vertices), "edges": len(edges)}
