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

Writing (:func:`write_geojson`, and :meth:`runtime.voronoi.structure.Diagram.write_json` through
:func:`write_json_object`) streams the document: one feature (or record) is built, encoded and
written at a time, so a large diagram's document is never held in memory as Python lists; the
text is the same as ``json.dump`` of the whole document.

Public API: :func:`diagram_geojson`, :func:`write_geojson`, :func:`feature_collection`,
:func:`crs_member`, :func:`write_json_object`, :class:`Records`, :data:`PLANAR_CRS_WKT`.
"""
from __future__ import annotations

import json
from typing import Any, Callable, Iterable

import numpy as np

from .cells import site_outlines
from .queries import site_index

__all__ = ["diagram_geojson", "write_geojson", "feature_collection", "crs_member", "write_json_object", "Records",
           "PLANAR_CRS_WKT"]

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
    return feature_collection(list(_features(diagram, sites)), crs)


def write_geojson(diagram, file, crs: Any = None, *, sites: bool = True) -> None:
    """Write :func:`diagram_geojson`'s collection to ``file`` (a text file object) with the text of
    ``json.dump(diagram_geojson(diagram, crs, sites=sites), file)``, one feature at a time."""
    member = crs_member(crs)
    members: list = [("type", "FeatureCollection")] + ([("crs", member)] if member is not None else [])
    write_json_object(file, members + [("features", Records(lambda: _features(diagram, sites)))], None)


def _features(diagram, sites: bool):
    """The features of :func:`diagram_geojson`, one at a time."""
    for e in diagram.edges:
        yield {"type": "Feature", "id": f"edge-{e.id}",
               "geometry": {"type": "LineString", "coordinates": np.asarray(e.polyline, float).tolist()},
               "properties": {"kind": "edge", "number": e.id, "sites": [int(t) for t in e.sites],
                              "ends": [None if t is None else int(t) for t in e.ends],
                              "closed": bool(e.closed), "tolerance": float(e.tolerance),
                              "certified": bool(e.certified)}}
    for v in diagram.vertices:
        yield {"type": "Feature", "id": f"vertex-{v.id}",
               "geometry": {"type": "Point", "coordinates": [float(v.x), float(v.y)]},
               "properties": {"kind": "vertex", "number": v.id, "sites": [int(t) for t in v.sites],
                              "radius": float(v.radius), "certified": bool(v.certified)}}
    if sites and diagram.sites:
        geoms = site_index(diagram).geoms
        for i, (s, parts) in enumerate(zip(diagram.sites, site_outlines(diagram))):
            label = getattr(s, "label", None)
            yield {"type": "Feature", "id": f"site-{i}", "geometry": _site_geometry(parts),
                   "properties": {"kind": "site", "number": i, "shape": geoms[i].kind,
                                  "label": None if label is None else str(label)}}


class Records:
    """A JSON array written one item at a time by :func:`write_json_object`: ``make()`` gives a
    fresh iterator of the items (``list(records)`` materialises them)."""

    def __init__(self, make: Callable[[], Iterable]):
        self.make = make

    def __iter__(self):
        return iter(self.make())


def write_json_object(file, members, indent: int | None = None) -> None:
    """Write the JSON object of ``members`` ((key, value) pairs; a :class:`Records` value is an
    array written item by item) to the text file ``file``, with the text of ``json.dump(dict(members),
    file, indent=indent)`` (RFC 8259; Python's separators: ", " and ": " without indent, "," and
    ": " with it).  Each value or item is encoded by :func:`json.dumps` and re-indented to its
    depth (a JSON string holds no raw newline, so only line breaks between tokens move)."""
    def nl(level):
        return "" if indent is None else "\n" + " " * (indent * level)

    def dump(value, level):
        text = json.dumps(value, indent=indent)
        return text.replace("\n", nl(level)) if indent is not None and level else text

    comma = ", " if indent is None else ","
    file.write("{")
    for k, (key, value) in enumerate(members):
        file.write((comma if k else "") + nl(1) + json.dumps(key) + ": ")
        if not isinstance(value, Records):
            file.write(dump(value, 1))
            continue
        empty = True
        for item in value:
            file.write(("[" if empty else comma) + nl(2) + dump(item, 2))
            empty = False
        file.write("[]" if empty else nl(1) + "]")
    file.write(nl(0) + "}" if members else "}")


def feature_collection(features: list, crs: Any = None) -> dict:
    """A GeoJSON FeatureCollection (RFC 7946) of ``features`` with GDAL's ``crs`` member for
    ``crs`` (:func:`crs_member`)."""
    out: dict = {"type": "FeatureCollection"}
    member = crs_member(crs)
    if member is not None:
        out["crs"] = member
    out["features"] = features
    return out
