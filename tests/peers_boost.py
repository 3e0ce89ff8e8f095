"""Boost.Polygon's Voronoi diagram of points and segments (through pyvoronoi), as a peer of the
segment-site diagram: the Delaunay graph over elementary sites, with the keys of
tests/cgal/sdg_peer.py (a point ``("p", Fraction(x), Fraction(y))``, a segment interior
``("s", (Fraction(x0), Fraction(y0)), (Fraction(x1), Fraction(y1)))`` with sorted endpoints).

What Boost produces (pyvoronoi 1.2.8, Boost.Polygon 1.59 voronoi; checked on small cases):

* every input segment gives three cells: its start point (``source_category`` 1), its end point
  (2) and its interior (3); an input point gives one cell (0);
* equal points are ONE cell: the builder sorts the site events and removes duplicates, so an
  endpoint shared by several segments, or an input point equal to an endpoint, has a single cell
  (its ``site`` index is the first occurrence's);
* a point whose incident segments leave no angular gap wider than a half-plane (its region,
  ``{x : (x - p)·(q_i - p) <= 0 for every incident segment [p, q_i]}``, is the point p alone) has
  a cell with ``is_degenerate`` (no incident edge): it is then in no Delaunay edge;
* "secondary" edges (``is_primary`` False) separate a segment interior from its own endpoint;
  they are kept: they are Delaunay edges between elementary sites;
* Boost merges Voronoi vertices closer than 128 ulps (voronoi_diagram's vertex_equality_predicate)
  and drops the edge between them, so an edge of length zero at a Voronoi vertex of degree >= 4
  never appears, and a genuine edge shorter than that relative tolerance would be lost (not seen
  on integer scenes of this size).

Boost's input is integer (int32); pyvoronoi's scaling factor is 1 here, coordinates are used
as given."""
from __future__ import annotations

import time
from fractions import Fraction


def _point_key(p) -> tuple:
    return ("p", Fraction(p[0]), Fraction(p[1]))


def _segment_key(a, b) -> tuple:
    a = (Fraction(a[0]), Fraction(a[1]))
    b = (Fraction(b[0]), Fraction(b[1]))
    return ("s",) + tuple(sorted((a, b)))


def _check_int(v):
    if int(v) != v or abs(v) >= 2 ** 31:
        raise ValueError(f"Boost.Polygon's Voronoi input is int32: {v!r}")
    return int(v)


def boost_delaunay_edges(points, segments):
    """Boost.Polygon's Voronoi diagram (pyvoronoi) of integer ``points`` [(x, y)] and non-crossing
    integer ``segments`` [((x0, y0), (x1, y1))] (endpoints may be shared, a point may equal an
    endpoint; nothing may touch a segment's interior).

    Returns (set of Delaunay edges, each a frozenset of two elementary-site keys; seconds of
    Construct() alone).  Two cells form an edge when they share a Voronoi edge (an edge and its
    twin); edges whose two cells have the same key, or whose two ends are the same Voronoi vertex,
    are dropped (neither was seen)."""
    import pyvoronoi

    pv = pyvoronoi.Pyvoronoi(1)
    for x, y in points:
        pv.AddPoint([_check_int(x), _check_int(y)])
    seen = set()
    for (x0, y0), (x1, y1) in segments:
        if (x0, y0) == (x1, y1):
            raise ValueError(f"degenerate segment {(x0, y0)}-{(x1, y1)}: pass it as a point")
        k = _segment_key((x0, y0), (x1, y1))
        if k not in seen:
            seen.add(k)
            pv.AddSegment([[_check_int(x0), _check_int(y0)], [_check_int(x1), _check_int(y1)]])
    t0 = time.perf_counter()
    pv.Construct()
    seconds = time.perf_counter() - t0
    keys = []
    for _, cell in pv.EnumerateCells():
        if cell.contains_point:
            keys.append(_point_key(pv.RetrievePoint(cell)))
        else:
            a, b = pv.RetrieveSegment(cell)
            keys.append(_segment_key(a, b))
    cell_of, twin_of, zero = [], [], []
    for _, e in pv.EnumerateEdges():
        cell_of.append(e.cell)
        twin_of.append(e.twin)
        zero.append(e.start == e.end and e.start != -1)
    edges = set()
    for i, t in enumerate(twin_of):
        if t < i or zero[i]:
            continue                                  # each pair of twins once; zero length
        a, b = keys[cell_of[i]], keys[cell_of[t]]
        if a != b:
            edges.add(frozenset((a, b)))
    return edges, seconds
