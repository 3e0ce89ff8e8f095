"""The medial axis of a polygonal domain (thesis §2.3), from the Voronoi diagram of its boundary.

The medial axis of a domain Ω is the closure of the set of centres of maximal inscribed discs;
for a polygon with holes it is the part inside Ω of the Voronoi diagram of the boundary's
elementary sites (its segments' open interiors and its corners, thesis §2.2), **without** the
edges between a corner and a segment ending there: those are perpendiculars to the boundary at
a reflex corner (inside Ω) or at a convex one (outside), and their points have a single nearest
boundary point (Lee, *Medial axis transformation of a planar shape*, IEEE PAMI 1982).  Every
other Voronoi edge lies entirely inside or entirely outside Ω (it meets the boundary only at
corners, where the radius is 0), so one interior point of each edge decides it, by the even–odd
rule over the boundary's segments.

Thesis Fig. 2.3.1–2.3.2: a curved boundary approximated by segments has a medial axis of another
topology (one branch per convex corner); arcs are needed for curved outlines.

Public API: :func:`medial_axis`, :class:`MedialAxis`, :func:`boundary_pieces`.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..sites.arc import Arc, circle_halves
from ..sites.elliptic_arc import EllipticArc
from ..sites.segment import Segment
from ..voronoi.structure import DiagramEdge, DiagramVertex
from .bisectors import bisector_kind
from .distance import site_distances
from .ellipse_bisectors import beyond_curvature

__all__ = ["medial_axis", "MedialAxis", "MedialEdge", "boundary_pieces"]


@dataclass
class MedialEdge:
    """A piece of the medial axis: the Voronoi edge ``id`` of the boundary sites ``sites``; the
    inscribed circle centred at ``polyline[k]`` has radius ``radius[k]``."""

    id: int
    sites: tuple[int, int]
    ends: tuple
    polyline: np.ndarray
    radius: np.ndarray
    tolerance: float
    certified: bool


@dataclass
class MedialAxis:
    """The medial axis: ``edges`` (polylines with the inscribed radius along them), ``vertices``
    (the diagram's vertices inside the domain, radius 0 at convex corners), ``certified`` (the
    Voronoi diagram of the boundary was proved by the independent certificate) and ``diagram``
    (that Voronoi diagram, whose sites are the boundary's elementary sites)."""

    edges: list
    vertices: list
    certified: bool
    diagram: object = field(repr=False)
    problems: list = field(default_factory=list)

    def __repr__(self) -> str:
        return (f"MedialAxis({len(self.edges)} edges, {len(self.vertices)} vertices, certified={self.certified}, "
                f"{len(self.problems)} problems)")

    @property
    def largest_inscribed_circle(self) -> tuple[float, float, float]:
        """(x, y, r): the largest disc inside the domain (the maximum of the radius function on
        the medial axis is at a vertex, or anywhere on an edge of constant radius)."""
        cands = [(v.radius, -v.x, -v.y) for v in self.vertices]
        for e in self.edges:
            k = int(np.argmax(e.radius))
            cands.append((float(e.radius[k]), -float(e.polyline[k, 0]), -float(e.polyline[k, 1])))
        if not cands:
            return None
        r, mx, my = max(cands)          # ties: the lowest x, then the lowest y
        return (-mx, -my, r)

    def to_shapely(self):
        """A shapely MultiLineString of the edges (needs shapely)."""
        try:
            from shapely.geometry import MultiLineString
        except ImportError:
            raise ImportError("MedialAxis.to_shapely needs shapely (pip install shapely)") from None
        return MultiLineString([np.asarray(e.polyline, float) for e in self.edges])

    def to_geojson(self, crs: Any = None, *, sites: bool = True) -> dict:
        """A GeoJSON (RFC 7946) FeatureCollection of the medial axis and its boundary.

        * one LineString per edge: id ``"medial-edge-N"``, properties ``kind="edge"``, ``number``
          (N), ``sites``, ``ends``, ``radius`` (the inscribed radius at each point), ``tolerance``,
          ``certified``;
        * one Point per vertex: id ``"medial-vertex-N"``, ``kind="vertex"``, ``number`` (the
          vertex's id in the diagram), ``sites``, ``radius``, ``certified``;
        * unless ``sites=False``, the boundary's elementary sites as in
          :meth:`runtime.voronoi.structure.Diagram.to_geojson`: id ``"site-N"``, ``kind="site"``,
          ``number``, ``shape`` (point, segment, arc) and ``label`` (the label of the boundary
          piece, e.g. the DXF layer; or null).

        Ids are unique across kinds (GDAL renumbers repeated feature ids).  ``crs``: the
        coordinate reference system of the boundary (``"EPSG:32633"``, a pyproj CRS), written as
        the ``crs`` member GDAL reads (:func:`runtime.voronoi.geojson.crs_member`); by default a
        planar engineering CRS, so that GIS tools do not take the coordinates for longitude and
        latitude; ``False``: no member."""
        from ..voronoi.geojson import diagram_geojson, feature_collection

        feats = [{"type": "Feature", "id": f"medial-edge-{e.id}",
                  "geometry": {"type": "LineString", "coordinates": np.asarray(e.polyline, float).tolist()},
                  "properties": {"kind": "edge", "number": int(e.id), "sites": [int(t) for t in e.sites],
                                 "ends": [None if t is None else int(t) for t in e.ends],
                                 "radius": np.asarray(e.radius, float).tolist(),
                                 "tolerance": float(e.tolerance), "certified": bool(e.certified)}}
                 for e in self.edges]
        feats += [{"type": "Feature", "id": f"medial-vertex-{v.id}",
                   "geometry": {"type": "Point", "coordinates": [float(v.x), float(v.y)]},
                   "properties": {"kind": "vertex", "number": int(v.id), "sites": [int(t) for t in v.sites],
                                  "radius": float(v.radius), "certified": bool(v.certified)}}
                  for v in self.vertices]
        if sites:
            feats += [f for f in diagram_geojson(self.diagram, False)["features"]
                      if f["properties"]["kind"] == "site"]
        return feature_collection(feats, crs)

    def plot(self, path_or_ax=None, *, inscribed: bool = True, title: str | None = None, dpi: int = 120):
        """Draw the boundary (black), the medial axis (blue; dotted where not certified) and the
        largest inscribed circle (green).  Returns the matplotlib Figure."""
        import matplotlib

        if path_or_ax is None or not hasattr(path_or_ax, "plot"):
            matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        if path_or_ax is not None and hasattr(path_or_ax, "plot"):
            ax = path_or_ax
            fig = ax.figure
        else:
            fig, ax = plt.subplots(figsize=(8, 8))
        for a, b in _boundary_chords(self.diagram.sites):
            ax.plot([a[0], b[0]], [a[1], b[1]], "-", color="black", lw=1.4)
        for e in self.edges:
            P = np.asarray(e.polyline)
            ax.plot(P[:, 0], P[:, 1], "-" if e.certified else ":", color="tab:blue", lw=1.3)
        if inscribed and (self.edges or self.vertices):
            x, y, r = self.largest_inscribed_circle
            t = np.linspace(0, 2 * np.pi, 400)
            ax.plot(x + r * np.cos(t), y + r * np.sin(t), "-", color="tab:green", lw=0.8)
        ax.set_aspect("equal")
        status = "certified" if self.certified else "not certified"
        ax.set_title(title or f"medial axis: {len(self.edges)} edges, {status}", fontsize=9)
        if path_or_ax is not None and not hasattr(path_or_ax, "plot"):
            fig.savefig(path_or_ax, dpi=dpi, bbox_inches="tight")
            plt.close(fig)
        return fig


def _ring_segments(ring, where: str) -> list:
    """A closed ring as pieces: a list of Segments and Arcs (a closed loop), a Circle of rational
    radius (two half arcs), a list of (x, y) vertices, a shapely LinearRing/Polygon exterior or a
    GeoJSON ring."""
    if isinstance(ring, (list, tuple)) and ring and all(isinstance(s, (Segment, Arc, EllipticArc)) for s in ring):
        return list(ring)
    if hasattr(ring, "r2"):                     # a Circle: its two half arcs
        return circle_halves((ring.cx, ring.cy), ring.r2, getattr(ring, "label", None), what=where)
    from ..sites.shapes import pieces_from_geometry

    if isinstance(ring, (list, tuple)):
        coords = [tuple(p) for p in ring]
        if coords and coords[0] != coords[-1]:
            coords.append(coords[0])
        ring = {"type": "Polygon", "coordinates": [coords]}
    pieces, _ = pieces_from_geometry(ring)
    segs = [p for p in pieces if isinstance(p, Segment)]
    if len(segs) < 3:
        raise ValueError(f"{where}: a closed boundary needs at least 3 segments, got {len(segs)}")
    return segs


def boundary_pieces(outer, holes=()) -> list:
    """The segments of the boundary of the domain: ``outer`` (a shapely Polygon — its holes are
    taken too —, LinearRing, GeoJSON Polygon, list of vertices or closed loop of Segments) and
    each hole in ``holes``."""
    segs = _ring_segments(outer, "outer")
    for k, h in enumerate(holes):
        segs += _ring_segments(h, f"hole {k}")
    return segs


def _boundary_chords(sites) -> np.ndarray:
    """The boundary as chords (k × 2 × 2): segments, and arcs by 256 chords each (the probes
    of :func:`medial_axis` are interior points of edges, far from the boundary at that scale)."""
    out = []
    for s in sites:
        if isinstance(s, Segment):
            out.append(s.float_endpoints())
        elif isinstance(s, Arc):
            (cx, cy), rho, (ax, ay), (bx, by) = s.float_data()
            a0 = np.arctan2(ay - cy, ax - cx)
            span = (np.arctan2(by - cy, bx - cx) - a0) % (2 * np.pi) or 2 * np.pi
            t = a0 + np.linspace(0, span, 257)
            P = np.column_stack([cx + rho * np.cos(t), cy + rho * np.sin(t)])
            P[0], P[-1] = (ax, ay), (bx, by)
            out.extend(zip(map(tuple, P[:-1]), map(tuple, P[1:])))
        elif isinstance(s, EllipticArc):
            (cx, cy), M, N, p0, p1 = s.float_data()
            t = np.linspace(p0, p1, 257)
            P = np.array([cx, cy]) + np.cos(t)[:, None] * np.array(M) + np.sin(t)[:, None] * np.array(N)
            P[0], P[-1] = [float(v) for v in s.a], [float(v) for v in s.b]
            out.extend(zip(map(tuple, P[:-1]), map(tuple, P[1:])))
    return np.array(out, dtype=float).reshape(-1, 2, 2)


def _inside(boundary: np.ndarray, Q: np.ndarray, *, block: int = 1 << 22) -> np.ndarray:
    """Even–odd rule: points Q (m × 2) strictly inside the region bounded by the segments
    ``boundary`` (k × 2 × 2) — outer ring and holes together.  The m × k crossing tests go by
    blocks of rows of at most ``block`` entries (an arc is 256 chords: the 7 802 probes of the gear
    with 102 bulge arcs against its 28 012 chords took 3.7 GB at once); each row is computed as before."""
    A, B = boundary[:, 0], boundary[:, 1]
    out = np.zeros(len(Q), bool)
    rows = max(1, block // max(1, len(A)))
    for lo in range(0, len(Q), rows):
        x, y = Q[lo:lo + rows, 0][:, None], Q[lo:lo + rows, 1][:, None]
        cond = (A[:, 1][None, :] > y) != (B[:, 1][None, :] > y)
        with np.errstate(divide="ignore", invalid="ignore"):
            xc = A[:, 0][None, :] + (y - A[:, 1][None, :]) * (B[:, 0] - A[:, 0])[None, :] / (B[:, 1] - A[:, 1])[None, :]
        out[lo:lo + rows] = (np.sum(cond & (x < xc), axis=1) % 2) == 1
    return out


def medial_axis(outer, holes=(), *, certify: bool = True, tolerance: float | None = None) -> MedialAxis:
    """The medial axis of a polygon with holes (see the module docstring).

    >>> import curvedvoronoi as cv
    >>> m = cv.medial_axis([(0, 0), (4, 0), (4, 2), (0, 2)])
    >>> sorted((round(v.x, 9), round(v.y, 9)) for v in m.vertices if v.radius > 0)
    [(1.0, 1.0), (3.0, 1.0)]
    >>> m.largest_inscribed_circle
    (1.0, 1.0, 1.0)
    """
    from .construction import segment_voronoi

    segs = boundary_pieces(outer, holes)
    D = segment_voronoi(segs, certify=certify, tolerance=tolerance)
    E = D.elementary
    bnd = _boundary_chords(D.sites)
    keep = []
    probes = []
    for e in D.edges:
        i, j = e.sites
        P = np.asarray(e.polyline, float)
        if bisector_kind(E, i, j) not in ("perpendicular", "joint"):
            if None in e.ends:
                continue
        else:
            # a perpendicular or joint edge has one nearest boundary point, except for an elliptic
            # piece beyond its centre of curvature at the end (two nearest points there)
            P = beyond_curvature(E, i, j, P)
            if len(P) < 2:
                continue
            e = DiagramEdge(e.id, e.sites, e.ends, e.closed, P, e.tolerance, e.certified)
        k = len(P) // 2
        probes.append((P[k - 1] + P[k]) / 2 if len(P) % 2 == 0 else P[k])
        keep.append(e)
    inside = _inside(bnd, np.array(probes).reshape(-1, 2)) if probes else np.zeros(0, bool)
    edges = []
    used = set()
    for e, ok in zip(keep, inside.tolist()):
        if not ok:
            continue
        P = np.asarray(e.polyline, float)
        i = e.sites[0]
        r = site_distances(E, np.full(len(P), i), P)
        edges.append(MedialEdge(len(edges), e.sites, e.ends, P, r, e.tolerance, e.certified))
        used.update(v for v in e.ends if v is not None)
    vertices = [D.vertices[v] for v in sorted(used)]
    if not edges and segs and all(isinstance(p, Arc) and (p.c, p.rho) == (segs[0].c, segs[0].rho) for p in segs):
        # a disc: every boundary point is nearest to the centre, which is the whole medial axis (the
        # diagram of the circle's arcs has no vertex there); exact, id -1 as it is no diagram vertex
        (cx, cy), rho = segs[0].c, segs[0].rho
        vertices = [DiagramVertex(-1, tuple(range(len(E))), float(cx), float(cy), float(rho), True)]
    problems = list(D.problems)
    if not edges and not vertices:
        # the medial axis of a bounded domain is non-empty (it holds the centre of a largest
        # inscribed disc): an empty one is a construction that failed, never an answer
        problems.append(f"medial axis: no edge and no vertex found for a bounded domain of {len(segs)} boundary "
                        "pieces (its medial axis is never empty): the construction is incomplete")
        return MedialAxis(edges, vertices, False, D, problems)
    return MedialAxis(edges, vertices, bool(D.certified), D, problems)
