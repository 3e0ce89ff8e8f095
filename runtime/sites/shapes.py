"""Segment and point sites from shapely geometries and GeoJSON (thesis §2.2: a polygon, a polyline
or a point set is a semi-algebraic set made of segments and points).

:func:`pieces_from_geometry` cuts a geometry into its pieces, :class:`runtime.sites.segment.Segment`
and :class:`runtime.sites.circle.Point`, with exact coordinates: a float is taken at its exact
binary value (:func:`runtime.sites.rationals.to_fraction`), nothing is rounded or snapped.

* A LineString gives one segment per pair of consecutive vertices; repeated consecutive vertices
  are dropped first (a zero-length segment is no site).
* A ring (LinearRing, the shell and each hole of a Polygon) gives one segment per edge; the closing
  vertex, which repeats the first, gives no extra segment, and an unclosed GeoJSON ring is closed.
* Point and MultiPoint give points; Multi* geometries, GeometryCollection, a GeoJSON Feature /
  FeatureCollection and a Python list of geometries give the pieces of their members, in order.

Each piece gets a *source*: the index of the member it came from (the polygon of a MultiPolygon,
the member of a collection, the feature of a FeatureCollection, the item of a list; 0 for a single
geometry), so that results can be mapped back to the user's shapes.

Refused with a one-line :class:`ShapeError`: empty geometries (and features without geometry),
rings with fewer than 3 distinct vertices, lines with fewer than 2, NaN / infinite coordinates,
unknown types, and **3-D coordinates**: the diagram is planar and a z would be silently lost, so
the message asks to drop it first (``shapely.force_2d``).  The pieces are not checked against each
other here: :func:`runtime.segments.crossings.check_pieces` refuses crossings, overlaps and repeats
(two polygons sharing an edge give that edge twice).

shapely is optional: GeoJSON dicts (and any object with ``__geo_interface__``) need only this
module; a shapely object is read through shapely's exact ``__geo_interface__``.

Public API: :func:`pieces_from_geometry`, :class:`ShapeError`.
"""
from __future__ import annotations

from collections.abc import Mapping
from fractions import Fraction

from ..result import InvalidConicError
from .rationals import to_fraction

__all__ = ["pieces_from_geometry", "ShapeError"]


class ShapeError(InvalidConicError):
    """A geometry that cannot be cut into segment and point sites (one line naming it)."""


_POINTISH = ("Point", "MultiPoint")
_LINEAR = ("LineString", "LinearRing", "MultiLineString", "Polygon", "MultiPolygon")
_TYPES = _POINTISH + _LINEAR + ("GeometryCollection",)


def pieces_from_geometry(geom) -> tuple[list, list[int]]:
    """``(pieces, sources)``: the segments and points of ``geom`` (see the module docstring) and,
    for each piece, the index of the input member it came from.

    ``geom``: a shapely geometry, a GeoJSON geometry / Feature / FeatureCollection dict, an object
    with ``__geo_interface__``, or a list of these.  :class:`ShapeError` (a ValueError) names the
    offending member, e.g. ``geometry 2 (Polygon) hole 0 vertex 3: coordinate x is not finite``.

    >>> pieces, sources = pieces_from_geometry(
    ...     {"type": "Polygon", "coordinates": [[[0, 0], [2, 0], [0, 1], [0, 0]]]})
    >>> pieces, sources
    ([Segment((0, 0), (2, 0)), Segment((2, 0), (0, 1)), Segment((0, 1), (0, 0))], [0, 0, 0])
    """
    pieces: list = []
    sources: list[int] = []
    for index, where, member in _members(geom):
        got = _pieces(_mapping(member, where), where)
        pieces += got
        sources += [index] * len(got)
    return pieces, sources


# =====================================================================================
# Members and mappings
# =====================================================================================

def _members(geom):
    """(source index, name, geometry) of the top-level members of ``geom``."""
    if isinstance(geom, (list, tuple)):
        if not geom:
            raise ShapeError("the list of geometries is empty")
        return [(i, f"geometry {i}", g) for i, g in enumerate(geom)]
    m = _mapping(geom, "geometry")
    kind = m.get("type")
    if kind == "FeatureCollection":
        feats = m.get("features")
        if not isinstance(feats, (list, tuple)) or not feats:
            raise ShapeError("FeatureCollection: it has no features (empty)")
        return [(i, f"feature {i}", _feature_geometry(f, f"feature {i}")) for i, f in enumerate(feats)]
    if kind == "Feature":
        return [(0, "feature", _feature_geometry(m, "feature"))]
    if kind == "GeometryCollection":
        members = _collection(m, "geometry")
        return [(i, f"geometry {i}", g) for i, g in enumerate(members)]
    if kind in ("MultiPoint", "MultiLineString", "MultiPolygon"):
        parts = _coordinates(m, "geometry")
        if not parts:
            raise ShapeError(f"geometry ({kind}): empty geometry")
        sub = kind[len("Multi"):]
        return [(i, f"geometry {i}", {"type": sub, "coordinates": c}) for i, c in enumerate(parts)]
    return [(0, "geometry", m)]


def _feature_geometry(f, where: str):
    f = _mapping(f, where)
    if f.get("type") != "Feature":
        raise ShapeError(f"{where}: expected a GeoJSON Feature, got type {f.get('type')!r}")
    g = f.get("geometry")
    if g is None:
        raise ShapeError(f"{where}: the feature has no geometry (null)")
    return g


def _mapping(geom, where: str) -> Mapping:
    """The GeoJSON mapping of ``geom`` (a dict, a shapely geometry, a ``__geo_interface__``)."""
    if isinstance(geom, Mapping):
        return geom
    if type(geom).__module__.split(".")[0] == "shapely":
        from ..optional import require

        shapely = require("shapely", "reading shapely geometries")
        if not isinstance(geom, shapely.Geometry):
            raise ShapeError(f"{where}: unsupported shapely object {type(geom).__name__}")
        if geom.is_empty:
            raise ShapeError(f"{where} ({geom.geom_type}): empty geometry")
    gi = getattr(geom, "__geo_interface__", None)
    if isinstance(gi, Mapping):
        return gi
    raise ShapeError(f"{where}: unsupported input {type(geom).__name__} (expected a shapely geometry, a GeoJSON "
                     "geometry / Feature / FeatureCollection dict, or a list of these)")


def _collection(m, where: str) -> list:
    geoms = m.get("geometries")
    if not isinstance(geoms, (list, tuple)):
        raise ShapeError(f"{where} (GeometryCollection): 'geometries' must be a list")
    if not geoms:
        raise ShapeError(f"{where} (GeometryCollection): empty geometry")
    return list(geoms)


def _coordinates(m, where: str):
    if "coordinates" not in m:
        raise ShapeError(f"{where} ({m.get('type')}): missing 'coordinates'")
    c = m["coordinates"]
    if not isinstance(c, (list, tuple)):
        raise ShapeError(f"{where} ({m.get('type')}): 'coordinates' must be a list, got {type(c).__name__}")
    return c


# =====================================================================================
# Pieces of one geometry
# =====================================================================================

def _pieces(m: Mapping, where: str) -> list:
    from .circle import Point

    kind = m.get("type")
    if kind not in _TYPES:
        if kind in ("Feature", "FeatureCollection"):
            raise ShapeError(f"{where}: a {kind} inside a geometry (features belong at the top level)")
        raise ShapeError(f"{where}: unsupported geometry type {kind!r} (supported: {', '.join(_TYPES)})")
    name = f"{where} ({kind})"
    if kind == "GeometryCollection":
        out = []
        for k, g in enumerate(_collection(m, name)):
            out += _pieces(_mapping(g, f"{name} member {k}"), f"{name} member {k}")
        return out
    coords = _coordinates(m, name)
    if len(coords) == 0:
        raise ShapeError(f"{name}: empty geometry")
    if kind == "Point":
        return [Point(*_xy(coords, name))]
    if kind == "MultiPoint":
        return [Point(*_xy(c, f"{name} point {k}")) for k, c in enumerate(coords)]
    if kind == "LineString":
        return _chain(coords, name, ring=False)
    if kind == "LinearRing":
        return _chain(coords, name, ring=True)
    if kind == "Polygon":
        out = []
        for k, ring in enumerate(coords):
            out += _chain(ring, f"{name} {'shell' if k == 0 else f'hole {k - 1}'}", ring=True)
        return out
    # MultiLineString / MultiPolygon nested in a collection: their parts keep the member's source
    sub = kind[len("Multi"):]
    out = []
    for k, c in enumerate(coords):
        out += _pieces({"type": sub, "coordinates": c}, f"{name} part {k}")
    return out


def _xy(c, where: str) -> tuple[Fraction, Fraction]:
    if not isinstance(c, (list, tuple)):
        raise ShapeError(f"{where}: a position must be a list [x, y], got {c!r}")
    if len(c) != 2:
        if len(c) > 2:
            raise ShapeError(f"{where}: 3-D coordinates {tuple(c)!r} are not supported (the diagram is planar); "
                             "drop z first, e.g. shapely.force_2d(geometry)")
        raise ShapeError(f"{where}: a position needs 2 coordinates, got {len(c)}")
    try:
        return to_fraction(c[0], "coordinate x"), to_fraction(c[1], "coordinate y")
    except InvalidConicError as exc:
        raise ShapeError(f"{where}: {exc}") from None


def _chain(coords, where: str, ring: bool) -> list:
    """Segments between consecutive distinct vertices (a ring: closed, no zero-length closing edge)."""
    from .segment import Segment

    if not isinstance(coords, (list, tuple)):
        raise ShapeError(f"{where}: expected a list of positions, got {coords!r}")
    if len(coords) == 0:
        raise ShapeError(f"{where}: empty geometry")
    pts: list = []
    for k, c in enumerate(coords):
        p = _xy(c, f"{where} vertex {k}")
        if not pts or pts[-1] != p:
            pts.append(p)
    if ring:
        if len(pts) > 1 and pts[-1] == pts[0]:
            pts.pop()
        if len(pts) < 3:
            raise ShapeError(f"{where}: a ring needs at least 3 distinct vertices, got {len(pts)}")
        pts.append(pts[0])
    elif len(pts) < 2:
        raise ShapeError(f"{where}: a line needs at least 2 distinct vertices, got {len(pts)}")
    return [Segment(a, b) for a, b in zip(pts, pts[1:])]
