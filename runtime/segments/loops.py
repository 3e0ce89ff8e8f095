"""Drawings as boundary pieces, the pieces joined into closed loops, and the domain they bound.

:func:`read_shape`: the pieces of a DXF drawing, a GeoJSON document or a sites file (segments,
arcs, points), with a name for each piece (the DXF entity -- type, handle, layer -- or GeoJSON
member it came from) for one-line errors.  :func:`read_domain`: the domain of the medial axis
(thesis §2.3):

* **GeoJSON**: every Polygon of the document (a Polygon, a MultiPolygon, Features, collections):
  its first ring is the outer boundary, the others its holes.  Several polygons give the union
  of their medial axes; they must not overlap or touch.  Other geometry types are refused.
* **DXF** and **sites JSON** (segment and arc records): the pieces are joined end to end into
  closed loops -- a segment's ends are its two endpoints, an arc's its ``a`` and ``b`` (a closed
  LWPOLYLINE / POLYLINE with bulges is one loop; LINEs and ARCs joined end to end make one too;
  two arcs of one circle make a circular loop).  The rule: **the loop that contains all the
  others is the outer boundary, the others are holes.**  Refused, with one line naming the
  entities: an open end (a piece end not joined to another piece), three or more pieces at one
  point (loops touching), a POINT, a site that is neither a segment nor an arc (a whole circle,
  a conic: draw a circle as two arcs), several loops none of which contains all the others (two
  domains side by side), and a loop inside a hole (an island: a second domain).

**Containment with arcs.**  "Loop i lies inside loop j": the even-odd rule for one point of loop
i (its first segment's midpoint, else its first arc's start ``a``) against the **exact** pieces of
loop j, in floating point -- no polyline approximation, so loops closer than an arc's sagitta are
told apart: each arc is split at the top and bottom of its circle into y-monotone pieces, crossed
by the horizontal ray at x = c_x ± √(ρ² − (y − c_y)²) when their end heights straddle the point's
(the segments' half-open rule: a ray through a joint counts once).  The loops are disjoint
(checked before), so the point is on no other loop.

Public API: :func:`read_shape`, :func:`read_domain`, :func:`shape_kind`, :func:`check_named`,
:func:`closed_loops`, :func:`outer_and_holes`, :func:`loop_contains`.
"""
from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np

from ..predicates.circles import Point
from ..result import InvalidConicError
from ..sites.arc import Arc
from ..sites.segment import Segment
from ..sites.reader import load_json_document
from ..sites.shapes import ShapeError

__all__ = ["read_shape", "read_domain", "shape_kind", "check_named", "closed_loops", "outer_and_holes",
           "loop_contains"]


# =====================================================================================
# Reading drawings: pieces, sources, and a name for each piece (for one-line errors)
# =====================================================================================

def shape_kind(path: str) -> str:
    """"dxf", "geojson" or "sites" (a .json holding GeoJSON -- a top-level "type" -- is "geojson")."""
    suffix = Path(path).suffix.lower()
    if suffix in (".dxf", ".geojson"):
        return suffix[1:]
    try:
        with open(path) as fh:
            head = fh.read(1 << 16)
    except OSError:
        return "sites"                  # the sites reader reports it
    return "geojson" if re.match(r'\s*\{\s*"type"\s*:', head) else "sites"


class _Names:
    """``names(k)``: the input piece k named for a message -- the DXF entity (type, handle, layer)
    or GeoJSON member it came from and its piece number there, or ``site k``."""

    def __init__(self, kind: str, path: str, pieces, sources, skip=(), doc=None):
        self.kind, self.path, self.pieces, self.sources, self.skip = kind, path, pieces, sources, skip
        self.doc = doc
        self._members = None

    def member(self, src: int) -> str:
        if self._members is None:
            self._members = self._member_names()
        return self._members[src] if 0 <= src < len(self._members) else f"member {src}"

    def _member_names(self) -> list[str]:
        if self.kind == "dxf":
            from ..sites.dxf import SUPPORTED
            import ezdxf

            skip = {str(t).upper() for t in self.skip}
            return [f"{e.dxftype()} (handle {e.dxf.get('handle', '?')}, layer {e.dxf.get('layer', '0')!r})"
                    for e in ezdxf.readfile(self.path).modelspace()
                    if e.dxftype() not in skip and e.dxftype() in SUPPORTED]
        doc = self.doc if isinstance(self.doc, dict) else {}
        kind = doc.get("type")
        if kind == "FeatureCollection":
            return [f"feature {i} ({(f.get('geometry') or {}).get('type')})"
                    for i, f in enumerate(doc.get("features", []))]
        if kind == "GeometryCollection":
            return [f"geometry {i} ({g.get('type')})" for i, g in enumerate(doc.get("geometries", []))]
        if kind in ("MultiPolygon", "MultiLineString", "MultiPoint"):
            return [f"{kind[5:]} {i}" for i in range(len(doc.get("coordinates", [])))]
        if kind == "Feature":
            return [f"the feature ({(doc.get('geometry') or {}).get('type')})"]
        return [f"the {kind}"]

    def __call__(self, k: int) -> str:
        what = type(self.pieces[k]).__name__.lower()
        if self.kind == "sites":
            return f"site {k} ({what})"
        src = self.sources[k]
        nth = sum(1 for j in range(k) if self.sources[j] == src)
        same = sum(1 for s in self.sources if s == src)
        return self.member(src) + (f" {what} {nth}" if same > 1 else "")


def read_shape(path: str, *, skip=()) -> tuple[list, list[int], object]:
    """``(pieces, sources, names)`` of a DXF drawing, a GeoJSON document or a sites file:
    :func:`runtime.sites.dxf.read_dxf`, :func:`runtime.sites.shapes.pieces_from_geometry` or
    :func:`runtime.sites.reader.read_sites`; ``names(k)`` names piece k for a message."""
    kind = shape_kind(path)
    if kind == "dxf":
        from ..sites.dxf import read_dxf

        pieces, sources, _ = read_dxf(path, skip=skip)
        return pieces, sources, _Names(kind, path, pieces, sources, skip)
    if kind == "geojson":
        from ..sites.shapes import pieces_from_geometry

        doc = load_json_document(path, ShapeError)
        try:
            pieces, sources = pieces_from_geometry(doc)
        except ShapeError as exc:
            raise ShapeError(f"{path}: {exc}") from None
        return pieces, sources, _Names(kind, path, pieces, sources, doc=doc)
    from ..sites.reader import read_sites

    pieces = read_sites(path)
    sources = list(range(len(pieces)))
    return pieces, sources, _Names(kind, path, pieces, sources)


def check_named(pieces, names, path: str) -> None:
    """:func:`runtime.segments.crossings.check_pieces` with the pieces named as in the input."""
    from .crossings import check_pieces, renamed

    try:
        check_pieces(pieces)
    except InvalidConicError as exc:
        raise ShapeError(f"{path}: {renamed(str(exc), names)}") from None


# =====================================================================================
# Closed loops and containment
# =====================================================================================

def _ends(p) -> tuple:
    return (tuple(p.p), tuple(p.q)) if isinstance(p, Segment) else (tuple(p.a), tuple(p.b))


def _boundary_kinds(pieces, names, path: str) -> None:
    for k, p in enumerate(pieces):
        if isinstance(p, Point):
            raise ShapeError(f"{path}: {names(k)}: a point is not part of a closed boundary (the medial axis "
                             "needs closed loops of segments and arcs)")
        if not isinstance(p, (Segment, Arc)):
            raise ShapeError(f"{path}: {names(k)}: a {type(p).__name__.lower()} is not supported in the boundary "
                             "of the medial axis (segments and arcs only; draw a circle as two arcs)")


def closed_loops(pieces, names, path: str) -> list[list[int]]:
    """The segments and arcs joined end to end into closed loops (lists of piece indices, in
    order); ShapeError naming the pieces otherwise (module docstring)."""
    _boundary_kinds(pieces, names, path)
    at: dict = {}
    for k, p in enumerate(pieces):
        for end in _ends(p):
            at.setdefault(end, []).append(k)
    for pt, ks in at.items():
        xy = f"({pt[0]}, {pt[1]})"
        if len(ks) == 1:
            raise ShapeError(f"{path}: {names(ks[0])}: its end {xy} is not joined to another segment or arc (the "
                             "medial axis needs closed boundaries: closed polylines, or pieces joined end to end)")
        if len(ks) > 2:
            what = "segments" if all(isinstance(pieces[k], Segment) for k in ks) else "pieces"
            raise ShapeError(f"{path}: {len(ks)} {what} meet at {xy} ({', '.join(names(k) for k in ks[:3])}"
                             f"{', ...' if len(ks) > 3 else ''}): the boundary must be disjoint simple closed "
                             "loops (loops touching at a corner are not allowed)")
    seen = [False] * len(pieces)
    loops = []
    for k0 in range(len(pieces)):
        if seen[k0]:
            continue
        loop, k, pt = [], k0, _ends(pieces[k0])[1]
        while not seen[k]:
            seen[k] = True
            loop.append(k)
            a, b = at[pt]
            k = b if a == k else a
            e0, e1 = _ends(pieces[k])
            pt = e1 if e0 == pt else e0
        loops.append(loop)
    return loops


def _monotone(arc: Arc) -> list[tuple]:
    """The arc as y-monotone pieces (cx, cy, ρ, y_start, y_end, side): side +1 on the right half
    of the circle (x = c_x + √(ρ² − (y − c_y)²)), -1 on the left half."""
    (cx, cy), r, (ax, ay), (bx, by) = arc.float_data()
    t0 = math.atan2(ay - cy, ax - cx)
    span = (math.atan2(by - cy, bx - cx) - t0) % (2 * math.pi) or 2 * math.pi
    ts, ys = [t0], [ay]
    k = math.floor((t0 - math.pi / 2) / math.pi) + 1          # the first top/bottom after the start
    while math.pi / 2 + k * math.pi < t0 + span:
        ts.append(math.pi / 2 + k * math.pi)
        ys.append(cy + r if k % 2 == 0 else cy - r)
        k += 1
    ts.append(t0 + span)
    ys.append(by)
    return [(cx, cy, r, ys[i], ys[i + 1], 1.0 if math.cos((ts[i] + ts[i + 1]) / 2) >= 0 else -1.0)
            for i in range(len(ts) - 1)]


def _geometry(pieces) -> tuple[np.ndarray, np.ndarray]:
    """(segments k x 2 x 2, y-monotone arc pieces m x 6) of a loop, as floats."""
    segs = [p.float_endpoints() for p in pieces if isinstance(p, Segment)]
    arcs = [m for p in pieces if isinstance(p, Arc) for m in _monotone(p)]
    return np.array(segs, float).reshape(-1, 2, 2), np.array(arcs, float).reshape(-1, 6)


def _inside(geom, Q: np.ndarray) -> np.ndarray:
    """Even-odd rule: the points Q (n x 2) strictly inside the loop ``geom`` (:func:`_geometry`)."""
    S, R = geom
    x, y = Q[:, 0][:, None], Q[:, 1][:, None]
    A, B = S[:, 0], S[:, 1]
    cond = (A[:, 1][None, :] > y) != (B[:, 1][None, :] > y)
    with np.errstate(divide="ignore", invalid="ignore"):
        xc = A[:, 0][None, :] + (y - A[:, 1][None, :]) * (B[:, 0] - A[:, 0])[None, :] / (B[:, 1] - A[:, 1])[None, :]
    count = np.sum(cond & (x < xc), axis=1)
    cx, cy, r, y0, y1, side = (R[:, i][None, :] for i in range(6))
    cond = (y0 > y) != (y1 > y)
    xc = cx + side * np.sqrt(np.maximum(r * r - (y - cy) ** 2, 0.0))
    return (count + np.sum(cond & (x < xc), axis=1)) % 2 == 1


def _probe(pieces) -> tuple[float, float]:
    """A point of the loop (on no other loop): its first segment's midpoint, else its first arc's start."""
    for s in pieces:
        if isinstance(s, Segment):
            (x0, y0), (x1, y1) = s.float_endpoints()
            return ((x0 + x1) / 2, (y0 + y1) / 2)
    return pieces[0].float_data()[2]


def loop_contains(outer_pieces, inner_pieces) -> bool:
    """The loop ``inner_pieces`` lies inside the loop ``outer_pieces`` (two disjoint closed loops of
    segments and arcs; the even-odd rule for one point, module docstring)."""
    return bool(_inside(_geometry(outer_pieces), np.array([_probe(inner_pieces)]))[0])


def _loop_name(loop, names, sources) -> str:
    src = {sources[k] for k in loop}
    return names.member(src.pop()) if len(src) == 1 and names.kind != "sites" else f"the loop through {names(loop[0])}"


def outer_and_holes(loops_pieces, loop_names, path: str) -> tuple[int, list[int]]:
    """(outer, holes) by the rule: the loop containing all the others is the outer boundary."""
    n = len(loops_pieces)
    probes = np.array([_probe(s) for s in loops_pieces]).reshape(-1, 2)
    inside = np.zeros((n, n), bool)                           # inside[i, j]: loop i in loop j
    for j, s in enumerate(loops_pieces):
        inside[:, j] = _inside(_geometry(s), probes)
        inside[j, j] = False
    outer = [j for j in range(n) if all(inside[i, j] for i in range(n) if i != j)]
    if not outer:
        tops = [i for i in range(n) if not inside[i].any()]
        pair = " and ".join(loop_names[i] for i in tops[:2])
        raise ShapeError(f"{path}: {n} closed boundaries and none contains all the others ({pair} lie side by "
                         "side): the outer boundary must contain every hole; put each domain in its own file")
    o = outer[0]
    for i in range(n):
        for j in range(n):
            if i != o and j != o and inside[i, j]:
                raise ShapeError(f"{path}: {loop_names[i]} lies inside the hole {loop_names[j]} (an island in a "
                                 "hole is a second domain): put it in its own file")
    return o, [i for i in range(n) if i != o]


# =====================================================================================
# The domain of the medial axis
# =====================================================================================

def _polygons(doc, path: str) -> list[tuple[str, list]]:
    """(name, rings) of every Polygon of a GeoJSON document; other geometry types refused."""
    out: list = []

    def walk(g, where):
        if not isinstance(g, dict):
            raise ShapeError(f"{path}: {where}: expected a GeoJSON object")
        t = g.get("type")
        if t == "FeatureCollection":
            for i, f in enumerate(g.get("features") or []):
                walk(f, f"feature {i}")
        elif t == "Feature":
            if g.get("geometry") is None:
                raise ShapeError(f"{path}: {where}: the feature has no geometry (null)")
            walk(g["geometry"], where)
        elif t == "GeometryCollection":
            for i, m in enumerate(g.get("geometries") or []):
                walk(m, f"{where} member {i}")
        elif t == "MultiPolygon":
            for i, c in enumerate(g.get("coordinates") or []):
                out.append((f"{where} polygon {i}", c))
        elif t == "Polygon":
            out.append((f"{where} (Polygon)", g.get("coordinates") or []))
        else:
            raise ShapeError(f"{path}: {where} ({t}): the medial axis needs polygons (Polygon or MultiPolygon); "
                             "remove it")

    walk(doc, "geometry")
    if not out:
        raise ShapeError(f"{path}: no polygon (the medial axis needs a Polygon or MultiPolygon)")
    return out


def read_domain(path: str, *, skip=()) -> tuple[list, list, list, list]:
    """``(outer, holes, pieces, sources)`` of the domain in a GeoJSON, DXF or sites file (see the
    module docstring for the rule); ``outer`` and each hole are lists of Segments and Arcs.  With
    several GeoJSON polygons, ``outer`` is the first shell and ``holes`` every other ring (the
    medial axis of the union is the union of the medial axes)."""
    if shape_kind(path) == "geojson":
        return _geojson_domain(load_json_document(path, ShapeError), path)
    pieces, sources, names = read_shape(path, skip=skip)
    if not pieces:
        raise ShapeError(f"{path}: no segments or arcs")
    _boundary_kinds(pieces, names, path)
    check_named(pieces, names, path)
    loops = closed_loops(pieces, names, path)
    rings = [[pieces[k] for k in loop] for loop in loops]
    o, holes = outer_and_holes(rings, [_loop_name(lp, names, sources) for lp in loops], path)
    order = [k for loop in [loops[o]] + [loops[h] for h in holes] for k in loop]
    return rings[o], [rings[h] for h in holes], [pieces[k] for k in order], [sources[k] for k in order]


def _geojson_domain(doc, path: str) -> tuple[list, list, list, list]:
    from ..sites.shapes import pieces_from_geometry

    rings, rnames, owner = [], [], []
    for p, (where, coords) in enumerate(_polygons(doc, path)):
        if not isinstance(coords, list) or not coords:
            raise ShapeError(f"{path}: {where}: empty polygon")
        for r, ring in enumerate(coords):
            name = f"{where} {'shell' if r == 0 else f'hole {r - 1}'}"
            try:
                segs, _ = pieces_from_geometry({"type": "Polygon", "coordinates": [ring]})
            except ShapeError as exc:
                raise ShapeError(f"{path}: {name}: {str(exc).split(': ', 1)[-1]}") from None
            rings.append(segs)
            rnames.append(name)
            owner.append(p)
    pieces = [s for r in rings for s in r]
    sources = [owner[k] for k, r in enumerate(rings) for _ in r]
    piece_names = [f"{rnames[k]} segment {i}" for k, r in enumerate(rings) for i in range(len(r))]
    check_named(pieces, lambda k: piece_names[k], path)
    _touching(rings, rnames, path)
    _check_polygons(rings, rnames, owner, path)
    return rings[0], rings[1:], pieces, sources


def _touching(rings, rnames, path: str) -> None:
    seen: dict = {}
    for r, segs in enumerate(rings):
        for s in segs:
            end = tuple(s.p)
            if end in seen and seen[end] != r:
                raise ShapeError(f"{path}: {rnames[seen[end]]} and {rnames[r]} touch at ({end[0]}, {end[1]}): "
                                 "rings must be disjoint")
            seen[end] = r


def _check_polygons(rings, rnames, owner, path: str) -> None:
    """Holes inside their shell and not inside each other; polygons not inside each other's area."""
    geoms = [_geometry(s) for s in rings]
    probes = [np.array([_probe(s)]) for s in rings]

    def within(k, j):
        return bool(_inside(geoms[j], probes[k])[0])

    shells = [k for k in range(len(rings)) if k == 0 or owner[k] != owner[k - 1]]
    for k in range(len(rings)):
        if k in shells:
            continue
        sh = max(s for s in shells if s <= k)
        if not within(k, sh):
            raise ShapeError(f"{path}: {rnames[k]} is not inside its shell")
        for j in range(sh + 1, len(rings)):
            if j != k and owner[j] == owner[k] and within(k, j):
                raise ShapeError(f"{path}: {rnames[k]} lies inside {rnames[j]} (holes must not nest)")
    for a in shells:
        for b in shells:
            if a != b and within(a, b):
                if not any(owner[h] == owner[b] and h != b and within(a, h) for h in range(len(rings))):
                    raise ShapeError(f"{path}: {rnames[a]} lies inside the polygon of {rnames[b]} (polygons must "
                                     "not overlap)")
