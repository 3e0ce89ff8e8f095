"""The Voronoi regions of a diagram as clipped shapely polygons, and the diagram as GeoDataFrames.

Construction of :func:`diagram_cells` (issue 35, item 2):

1. every edge's polyline, its ends snapped onto its vertices' coordinates (so that the edges at a
   vertex meet exactly); an end at infinity is continued straight along the polyline's last
   segment beyond the clip region (exact for point sites, whose edges are straight; a curved edge
   is approximated past the far point the construction drew it to, which lies far outside the
   sites' box);
2. the polylines that meet the clip polygon, noded with its boundary (``shapely.union_all``: the
   crossings are computed once, so every piece ends exactly on the boundary) and polygonized; the
   faces inside the clip polygon tile it, and a closed edge around a nested site cuts a hole in
   the face around it;
3. each face goes to the site nearest to a point inside it (``point_on_surface``, queried with
   :meth:`runtime.voronoi.queries.SiteIndex.nearest`, proved), and the faces of one site are
   merged.  Segment sites (their open interiors, with their endpoints as point sites) follow the
   diagram's convention: beyond an endpoint, the endpoint's region.

The boundary of a cell is therefore the edges' polylines, within their ``tolerance`` of the true
curves.  A cell is a Polygon (with holes for nested sites); a clip polygon that is not convex
can split a region, and then the cell is a MultiPolygon.

Public API: :func:`diagram_cells`, :func:`default_clip`, :func:`diagram_geopandas` (with its three
frames :func:`cell_frame`, :func:`edge_frame`, :func:`site_frame`), :func:`site_outlines`,
:class:`DiagramFrames`.
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from .queries import site_index

__all__ = ["DiagramFrames", "default_clip", "diagram_cells", "diagram_geopandas", "cell_frame", "edge_frame",
           "site_frame", "site_outlines"]


def _shapely():
    try:
        import shapely
    except ImportError:
        raise ImportError("Diagram.cells needs shapely (pip install shapely, or the geo extra)") from None
    return shapely


def default_clip(diagram, margin: float = 0.1) -> tuple[float, float, float, float]:
    """The sites' bounding box grown by ``margin`` of its size on every side (xmin, ymin, xmax,
    ymax).  Unbounded sites (hyperbolas, parabolas) count by their frame's origin ± their
    semi-axes (4p for a parabola); a box of size 0 (one point) gets size 1."""
    boxes = []
    for g in site_index(diagram).geoms:
        if g.bounded:
            boxes.append(g.bounding_box())
        else:
            s = max(float(getattr(g, "a", 0.0) or 0.0), float(getattr(g, "b", 0.0) or 0.0),
                    4 * float(getattr(g, "p", 0.0) or 0.0))
            boxes.append((g.tx - s, g.ty - s, g.tx + s, g.ty + s))
    if not boxes:
        return (-1.0, -1.0, 1.0, 1.0)
    B = np.array(boxes, float)
    x0, y0, x1, y1 = B[:, 0].min(), B[:, 1].min(), B[:, 2].max(), B[:, 3].max()
    w, h = x1 - x0, y1 - y0
    size = max(w, h)
    if not size > 0:
        size = max(1.0, abs(x0), abs(y0))
    mx, my = margin * (w if w > 0 else size), margin * (h if h > 0 else size)
    return (float(x0 - mx), float(y0 - my), float(x1 + mx), float(y1 + my))


def _clip_polygon(diagram, clip):
    shapely = _shapely()
    if clip is None:
        clip = default_clip(diagram)
    if isinstance(clip, shapely.Geometry):
        if clip.geom_type not in ("Polygon", "MultiPolygon") or clip.is_empty:
            raise ValueError(f"clip must be a box (xmin, ymin, xmax, ymax) or a non-empty polygon, got {clip.geom_type}")
        return clip
    try:
        x0, y0, x1, y1 = (float(v) for v in clip)
    except (TypeError, ValueError):
        raise ValueError(f"clip must be a box (xmin, ymin, xmax, ymax) or a shapely polygon, got {clip!r}") from None
    if not (x0 < x1 and y0 < y1):
        raise ValueError(f"clip box {clip!r} is empty (need xmin < xmax and ymin < ymax)")
    return shapely.box(x0, y0, x1, y1)


def edge_polylines(diagram, bounds) -> list[np.ndarray]:
    """Each edge's polyline with its ends snapped onto its vertices and its ends at infinity
    continued straight to beyond the box ``bounds`` (xmin, ymin, xmax, ymax)."""
    pos = {v.id: (v.x, v.y) for v in diagram.vertices}
    x0, y0, x1, y1 = bounds
    cx, cy, diag = (x0 + x1) / 2, (y0 + y1) / 2, math.hypot(x1 - x0, y1 - y0)
    out = []
    for e in diagram.edges:
        L = np.array(e.polyline, dtype=float).reshape(-1, 2)
        if len(L) < 2:
            continue
        if e.closed:
            out.append(L)
            continue
        for k, end in ((0, e.ends[0]), (-1, e.ends[1])):
            if end is not None:
                L[k] = pos[end]
        if e.ends[1] is None:
            L = np.vstack([L, _beyond(L[-2], L[-1], cx, cy, diag)])
        if e.ends[0] is None:
            L = np.vstack([_beyond(L[1], L[0], cx, cy, diag), L])
        out.append(L)
    return out


def _beyond(p, q, cx, cy, diag):
    """A point on the ray from p through q, beyond q, outside the disc (c, diag)."""
    u = q - p
    n = math.hypot(*u)
    if not n > 0:
        return q
    return q + u / n * (diag + math.hypot(q[0] - cx, q[1] - cy) + 1.0)


def diagram_cells(diagram, clip=None) -> list:
    """One shapely geometry per site, its clipped Voronoi region (see the module docstring)."""
    shapely = _shapely()
    region = _clip_polygon(diagram, clip)
    m = len(diagram.sites)
    if m == 0:
        return []
    lines = np.array([shapely.LineString(L) for L in edge_polylines(diagram, region.bounds)], dtype=object)
    if len(lines):          # whole lines, noded with the boundary: clipping first would leave
        lines = lines[shapely.intersects(lines, region)]     # ends a rounding off the boundary
    noded = shapely.union_all(np.concatenate([np.asarray(lines, dtype=object),
                                              np.array([region.boundary], dtype=object)]))
    faces = np.asarray(shapely.get_parts(shapely.polygonize(shapely.get_parts(noded))), dtype=object)
    if len(faces):
        reps = shapely.point_on_surface(faces)
        keep = shapely.contains(region, reps)
        faces, reps = faces[keep], reps[keep]
    cells = [shapely.Polygon()] * m
    if not len(faces):
        return cells
    idx = site_index(diagram)
    xy = shapely.get_coordinates(reps)
    owner = idx.nearest(xy).index
    tied = owner < 0        # a face's inner point on a bisector (should not happen): the float answer
    if tied.any():
        owner[tied] = idx.nearest(xy[tied], prove=False).index
    order = np.argsort(owner, kind="stable")
    cuts = np.nonzero(np.diff(owner[order]))[0] + 1
    for part in np.split(order, cuts):
        group = faces[part]
        cells[int(owner[part[0]])] = group[0] if len(group) == 1 else shapely.coverage_union_all(group)
    return cells


class DiagramFrames(NamedTuple):
    """:meth:`Diagram.to_geopandas`: the cells, the edges and the sites as GeoDataFrames."""

    cells: object
    edges: object
    sites: object


def diagram_geopandas(diagram, crs=None, clip=None) -> DiagramFrames:
    """GeoDataFrames of the diagram, ``crs`` passed through.

    * ``cells``: one row per site (``site``, ``kind``, ``label``; the clipped cell);
    * ``edges``: one row per edge (``id``, ``site_i``, ``site_j``, ``end_0``, ``end_1`` vertex
      ids or missing at infinity, ``closed``, ``tolerance``, ``certified``; the polyline);
    * ``sites``: one row per site (``site``, ``kind``, ``label``; a Point for a point site,
      otherwise the curve sampled as a LineString, unbounded curves within the clip box).
    """
    region = _clip_polygon(diagram, clip)
    return DiagramFrames(cell_frame(diagram, crs, region), edge_frame(diagram, crs),
                         site_frame(diagram, crs, region.bounds))


def _geopandas():
    try:
        import geopandas as gpd
        import pandas as pd
    except ImportError:
        raise ImportError("Diagram.to_geopandas needs geopandas (pip install geopandas)") from None
    return gpd, pd


def cell_frame(diagram, crs=None, clip=None):
    """The ``cells`` GeoDataFrame of :func:`diagram_geopandas` (``clip`` as in :func:`diagram_cells`)."""
    gpd, _ = _geopandas()
    idx = site_index(diagram)
    labels = [getattr(s, "label", None) for s in diagram.sites]
    return gpd.GeoDataFrame({"site": list(range(len(diagram.sites))), "kind": [g.kind for g in idx.geoms],
                             "label": labels},
                            geometry=diagram_cells(diagram, _clip_polygon(diagram, clip)), crs=crs)


def edge_frame(diagram, crs=None):
    """The ``edges`` GeoDataFrame of :func:`diagram_geopandas`."""
    gpd, pd = _geopandas()
    shapely = _shapely()
    E = diagram.edges
    ends = [[e.ends[k] for e in E] for k in (0, 1)]
    return gpd.GeoDataFrame(
        {"id": [e.id for e in E], "site_i": [e.sites[0] for e in E], "site_j": [e.sites[1] for e in E],
         "end_0": pd.array(ends[0], dtype="Int64"), "end_1": pd.array(ends[1], dtype="Int64"),
         "closed": [bool(e.closed) for e in E], "tolerance": [float(e.tolerance) for e in E],
         "certified": [bool(e.certified) for e in E]},
        geometry=[shapely.LineString(np.asarray(e.polyline, float)) for e in E], crs=crs)


def site_frame(diagram, crs=None, window=None, *, circles_as_points: bool = False):
    """The ``sites`` GeoDataFrame of :func:`diagram_geopandas`.  ``circles_as_points``: a circle
    site is its centre (a Point) and the column ``radius`` its radius (0 for point sites, missing
    for other kinds), the form GeoParquet input takes; other sites are sampled curves."""
    gpd, _ = _geopandas()
    shapely = _shapely()
    idx = site_index(diagram)
    kinds = [g.kind for g in idx.geoms]
    if window is None:
        window = default_clip(diagram)
    round_ = [k in ("point", "circle") for k in kinds] if circles_as_points else [False] * len(kinds)
    outlines = iter(site_outlines(diagram, window, which=[i for i, r in enumerate(round_) if not r]))
    geoms, radius = [], []
    for g, r in zip(idx.geoms, round_):
        if r:
            geoms.append(shapely.Point(g.x0, g.y0) if g.kind == "point" else shapely.Point(g.cx, g.cy))
            radius.append(0.0 if g.kind == "point" else float(g.rho))
            continue
        radius.append(math.nan)
        parts = next(outlines)
        if not parts:
            geoms.append(None)
        elif len(parts) > 1:
            geoms.append(shapely.MultiLineString(parts))
        else:
            geoms.append(shapely.LineString(parts[0]) if len(parts[0]) >= 2 else shapely.Point(parts[0][0]))
    cols = {"site": list(range(len(kinds))), "kind": kinds, "label": [getattr(s, "label", None) for s in diagram.sites]}
    if circles_as_points:
        cols["radius"] = radius
    return gpd.GeoDataFrame(cols, geometry=geoms, crs=crs)


def site_outlines(diagram, window=None, pieces: int = 256, which=None) -> list[list[np.ndarray]]:
    """Each site as a list of polylines ((n, 2) float arrays): one single-row array for a point
    site; otherwise the curve sampled with spacing 1/``pieces`` of its size (of the window's for an
    unbounded curve, kept within ``window`` = (xmin, ymin, xmax, ymax), default
    :func:`default_clip`), closed curves (circles, ellipses) ending at their first point, one
    polyline per piece inside the window (the two branches of a hyperbola are two pieces).  An
    unbounded curve missing the window has no polyline.  The samples lie on the curve (to float
    rounding); between them the polyline is a chord, as for the edges.  ``which``: only these
    sites (indices, in order)."""
    if window is None:
        window = default_clip(diagram)
    out = []
    geoms = site_index(diagram).geoms
    for g in (geoms if which is None else [geoms[i] for i in which]):
        if g.kind == "point":
            out.append([np.array([[g.x0, g.y0]], dtype=float)])
            continue
        x0, y0, x1, y1 = g.bounding_box() if g.bounded else window
        spacing = max(x1 - x0, y1 - y0) / pieces
        S = np.asarray(g.samples(spacing, window), dtype=float).reshape(-1, 2)
        if g.kind in ("circle", "ellipse"):
            out.append([np.vstack([S, S[:1]])] if len(S) else [])
            continue
        # samples are at most `spacing` apart along the curve: a longer step leaves the window
        cut = np.nonzero(np.hypot(*np.diff(S, axis=0).T) > 3 * spacing)[0] + 1
        out.append([P for P in np.split(S, cut) if len(P) >= 2] or ([S] if len(S) == 1 else []))
    return out
