"""The diagram as GeoJSON for GIS tools: edges, vertices and sites, with a coordinate reference system.

RFC 7946 GeoJSON has no CRS member and fixes WGS 84 longitude/latitude; GDAL (hence QGIS,
geopandas through pyogrio or fiona, ogr2ogr) still reads the 2008 form
``"crs": {"type": "name", "properties": {"name": ...}}`` and otherwise assumes EPSG:4326.  A
Voronoi diagram is Euclidean (thesis §1.2: distances in the plane), so its coordinates are
planar; to keep GIS tools from taking them for degrees, :func:`diagram_geojson` always writes
the ``crs`` member:

* the user's CRS when one is given (``"EPSG:32633"``, a ``urn:ogc:def:crs:...`` name, WKT);
* otherwise :data:`PLANAR_CRS_WKT`, a WKT2 *engineering* CRS (a local Cartesian plane without
  a geographic datum, unit-less), which GDAL reads as ``LOCAL_CS`` and pyproj as an
  Engineering CRS; only ``crs=False`` leaves the member out (strict RFC 7946 output, which
  readers take for longitude/latitude).

Feature ids are unique across kinds (``"edge-3"``, ``"vertex-3"``, ``"site-3"``: GDAL renumbers
features whose ids repeat, and takes an integer ``id`` *property* for the feature id, so the
number of the edge, vertex or site is the property ``number``); every feature has ``kind``.  Sites are
Points (point sites) or LineStrings / MultiLineStrings sampled along the curve
(:func:`runtime.voronoi.cells.site_outlines`: a circle is its circumference, not a disc;
an unbounded conic is cut to a window around the sites, the two branches of a hyperbola are two
lines), with their ``label`` and ``shape``.

Public API: :func:`diagram_geojson`, :func:`feature_collection`, :func:`crs_member`, :data:`PLANAR_CRS_WKT`.
"""
from __future__ import annotations

from typing import Any

import numpy as np

from .cells import site_outlines
from .queries import site_index

__all__ = ["diagram_geojson", "feature_collection", "crs_member", "PLANAR_CRS_WKT"]

#: a local Cartesian plane (x east, y north), unit-less: the CRS written when the user gives none
PLANAR_CRS_WKT = ('ENGCRS["curvedvoronoi planar coordinates",EDATUM["unknown"],CS[Cartesian,2],'
                  'AXIS["x",east,ORDER[1],LENGTHUNIT["unknown",1]],'
                  'AXIS["y",north,ORDER[2],LENGTHUNIT["unknown",1]]]')


def crs_member(crs: Any = None) -> dict | None:
    """GDAL's ``crs`` member for ``crs``: a string (``"EPSG:32633"``, a URN, WKT), an object with
    ``to_wkt()`` (a ``pyproj.CRS``: its WKT), None (:data:`PLANAR_CRS_WKT`) or False (no member)."""
    if crs is False:
        return None
    if crs is None:
        name = PLANAR_CRS_WKT
    elif isinstance(crs, str):
        name = crs
    elif hasattr(crs, "to_authority") and crs.to_authority() is not None:
        name = ":".join(crs.to_authority())
    elif hasattr(crs, "to_wkt"):
        name = crs.to_wkt()
    else:
        raise ValueError(f"crs must be a string such as 'EPSG:32633', a pyproj CRS, None or False, got {crs!r}")
    return {"type": "name", "properties": {"name": name}}


def _site_geometry(parts: list[np.ndarray]) -> dict | None:
    if not parts:
        return None
    if len(parts) == 1 and len(parts[0]) == 1:
        return {"type": "Point", "coordinates": parts[0][0].tolist()}
    if len(parts) == 1:
        return {"type": "LineString", "coordinates": parts[0].tolist()}
    return {"type": "MultiLineString", "coordinates": [P.tolist() for P in parts]}


def diagram_geojson(diagram, crs: Any = None, *, sites: bool = True) -> dict:
    """A GeoJSON FeatureCollection of the diagram (see the module docstring).

    * edges: LineStrings, properties ``kind="edge"``, ``number`` (the edge's id), ``sites``,
      ``ends``, ``closed``, ``tolerance``, ``certified``;
    * vertices: Points, ``kind="vertex"``, ``number`` (the vertex's id), ``sites``, ``radius``,
      ``certified``;
    * sites (unless ``sites=False``): ``kind="site"``, ``number`` (the site's index), ``shape``
      (point, circle, ellipse, hyperbola, parabola, segment, arc), ``label`` (or null).

    No property is called ``id``: GDAL takes an integer ``id`` property for the feature id, and
    the numbers of edges, vertices and sites repeat across kinds.
    """
    feats = []
    for e in diagram.edges:
        feats.append({"type": "Feature", "id": f"edge-{e.id}",
                      "geometry": {"type": "LineString", "coordinates": np.asarray(e.polyline, float).tolist()},
                      "properties": {"kind": "edge", "number": e.id, "sites": [int(t) for t in e.sites],
                                     "ends": [None if t is None else int(t) for t in e.ends],
                                     "closed": bool(e.closed), "tolerance": float(e.tolerance),
                                     "certified": bool(e.certified)}})
    for v in diagram.vertices:
        feats.append({"type": "Feature", "id": f"vertex-{v.id}",
                      "geometry": {"type": "Point", "coordinates": [float(v.x), float(v.y)]},
                      "properties": {"kind": "vertex", "number": v.id, "sites": [int(t) for t in v.sites],
                                     "radius": float(v.radius), "certified": bool(v.certified)}})
    if sites and diagram.sites:
        geoms = site_index(diagram).geoms
        for i, (s, parts) in enumerate(zip(diagram.sites, site_outlines(diagram))):
            label = getattr(s, "label", None)
            feats.append({"type": "Feature", "id": f"site-{i}", "geometry": _site_geometry(parts),
                          "properties": {"kind": "site", "number": i, "shape": geoms[i].kind,
                                         "label": None if label is None else str(label)}})
    return feature_collection(feats, crs)


def feature_collection(features: list, crs: Any = None) -> dict:
    """A GeoJSON FeatureCollection (RFC 7946) of ``features`` with GDAL's ``crs`` member for
    ``crs`` (:func:`crs_member`)."""
    out: dict = {"type": "FeatureCollection"}
    member = crs_member(crs)
    if member is not None:
        out["crs"] = member
    out["features"] = features
    return out
