"""Segment and point sites from a DXF drawing (ezdxf), with exact coordinates.

:func:`read_dxf` reads the modelspace entities in file order:

=============================  ===================================================================
LINE                           one :class:`runtime.sites.segment.Segment`
POINT                          one :class:`runtime.predicates.circles.Point`
LWPOLYLINE, POLYLINE (2-D)     a Segment per pair of consecutive distinct vertices; a closed
                               polyline also gets its closing segment (none of length 0)
=============================  ===================================================================

Coordinates are doubles in DXF and are taken at their exact binary value
(:func:`runtime.sites.rationals.to_fraction`).  Each piece gets

* a **source**: the index of its entity among the supported entities of the modelspace (LINE,
  POINT, LWPOLYLINE, POLYLINE, counted from 0 in file order, skipped types not counted), so that
  ``sources[i] == k`` maps piece i back to the k-th such entity;
* a **label**: the entity's layer name (also the Segment's ``label``).

Refused with a one-line :class:`runtime.sites.shapes.ShapeError` naming the entity type, handle
and layer: entities that need arcs or curves (ARC, CIRCLE, ELLIPSE, SPLINE, HATCH, a polyline
vertex with a nonzero bulge, a curve- or spline-fit polyline) -- arcs are planned, not supported
yet; other entity types (TEXT, INSERT, DIMENSION, ...; pass ``skip={"TEXT", ...}`` to ignore them);
polygon and polyface meshes; coordinates with z != 0 (the diagram is planar: flatten the drawing
first; a 3-D POLYLINE is read when all its z are 0); polylines not in the xy plane (extrusion other
than +-z); zero-length LINEs.  The pieces
are not checked against each other here: :func:`runtime.segments.crossings.check_pieces` does it.

ezdxf is optional (``pip install ezdxf``) and imported only here, when a file is read.

Public API: :func:`read_dxf`.
"""
from __future__ import annotations

from fractions import Fraction

from ..result import InvalidConicError
from .rationals import to_fraction
from .shapes import ShapeError

__all__ = ["read_dxf", "SUPPORTED", "CURVED"]

#: entity types read as sites
SUPPORTED = ("LINE", "POINT", "LWPOLYLINE", "POLYLINE")
#: entity types refused because they need arcs or curves (planned)
CURVED = ("ARC", "CIRCLE", "ELLIPSE", "SPLINE", "HATCH", "MPOLYGON", "HELIX", "REGION", "ARC_DIMENSION")


def read_dxf(path, *, skip=()) -> tuple[list, list[int], list[str]]:
    """``(pieces, sources, labels)`` of the modelspace of the DXF file ``path`` (see the module
    docstring); ``skip``: entity types to ignore (e.g. ``{"TEXT", "MTEXT", "DIMENSION"}``).

    :class:`runtime.sites.shapes.ShapeError` (a ValueError) with one line, e.g.
    ``drawing.dxf: ARC (handle 2F, layer 'walls'): arcs and curves are not supported yet (planned);
    replace it by a polyline of line segments``; ImportError naming the pip command without ezdxf."""
    from ..optional import require

    ezdxf = require("ezdxf", "reading DXF files")
    try:
        doc = ezdxf.readfile(str(path))
    except OSError as exc:
        raise ShapeError(f"cannot read {path}: {exc.strerror or exc}") from None
    except ezdxf.DXFError as exc:
        raise ShapeError(f"{path} is not a valid DXF file: {exc}") from None
    skip = {str(t).upper() for t in skip}
    pieces: list = []
    sources: list[int] = []
    labels: list[str] = []
    index = 0
    for e in doc.modelspace():
        kind = e.dxftype()
        if kind in skip:
            continue
        where = f"{path}: {_name(e)}"
        if kind not in SUPPORTED:
            if kind in CURVED:
                raise ShapeError(f"{where}: arcs and curves are not supported yet (planned); replace it by a "
                                 "polyline of line segments")
            raise ShapeError(f"{where}: not a supported site entity (supported: {', '.join(SUPPORTED)}); "
                             f"remove it or pass skip={{{kind!r}}}")
        got = _entity_pieces(e, kind, where)
        layer = str(e.dxf.get("layer", "0"))
        for p in got:
            if hasattr(p, "label"):
                p.label = layer
        pieces += got
        sources += [index] * len(got)
        labels += [layer] * len(got)
        index += 1
    return pieces, sources, labels


def _name(e) -> str:
    return f"{e.dxftype()} (handle {e.dxf.get('handle', '?')}, layer {e.dxf.get('layer', '0')!r})"


def _xy(v, where: str, z_offset=0) -> tuple[Fraction, Fraction]:
    """(x, y) of a DXF vector, exact; z (plus ``z_offset``) must be 0."""
    try:
        x, y = to_fraction(v[0], "x"), to_fraction(v[1], "y")
        z = to_fraction(v[2], "z") if len(v) > 2 else Fraction(0)
        z += to_fraction(z_offset, "elevation")
    except InvalidConicError as exc:
        raise ShapeError(f"{where}: {exc}") from None
    if z != 0:
        raise ShapeError(f"{where}: z = {float(z):g} is not 0 (the diagram is planar: flatten the drawing to "
                         "z = 0 first)")
    return x, y


def _entity_pieces(e, kind: str, where: str) -> list:
    from ..predicates.circles import Point
    from .segment import Segment

    if kind == "POINT":
        return [Point(*_xy(e.dxf.location, where))]
    if kind == "LINE":
        a, b = _xy(e.dxf.start, f"{where} start"), _xy(e.dxf.end, f"{where} end")
        if a == b:
            raise ShapeError(f"{where}: the line has length 0 (both ends at ({a[0]}, {a[1]})); use a POINT")
        return [Segment(a, b)]
    if kind == "LWPOLYLINE":
        flip = _ocs_flip(e, where)
        rows = e.get_points("xyb")
        elevation = e.dxf.get("elevation", 0) or 0
        closed = bool(e.closed)
        verts = [((x, y), b) for x, y, b in rows]
    else:
        mode = e.get_mode()
        if mode not in ("AcDb2dPolyline", "AcDb3dPolyline"):
            raise ShapeError(f"{where}: a {mode} (a mesh) is not a site; only 2-D polylines are read")
        if e.dxf.get("flags", 0) & (e.CURVE_FIT_VERTICES_ADDED | e.SPLINE_FIT_VERTICES_ADDED):
            raise ShapeError(f"{where}: a curve- or spline-fit polyline: arcs and curves are not supported yet "
                             "(planned); replace it by a polyline of line segments")
        flip = mode == "AcDb2dPolyline" and _ocs_flip(e, where)     # a 3-D polyline is in WCS
        elevation = e.dxf.get("elevation", None) if mode == "AcDb2dPolyline" else None
        elevation = elevation[2] if elevation is not None else 0
        closed = bool(e.is_closed)
        verts = [(tuple(v.dxf.location), v.dxf.get("bulge", 0)) for v in e.vertices]
    n = len(verts)
    pts: list = []
    for k, (loc, bulge) in enumerate(verts):
        if bulge and (closed or k < n - 1):
            raise ShapeError(f"{where}: vertex {k} has a nonzero bulge ({bulge:g}, an arc segment): arcs are not "
                             "supported yet (planned); replace it by line segments")
        x, y = _xy(loc, f"{where} vertex {k}", elevation)
        p = (-x, y) if flip else (x, y)
        if not pts or pts[-1] != p:
            pts.append(p)
    if closed and len(pts) > 1 and pts[-1] == pts[0]:
        pts.pop()
    if len(pts) < 2 or (closed and len(pts) < 3):
        raise ShapeError(f"{where}: fewer than {3 if closed else 2} distinct vertices ({len(pts)})")
    if closed:
        pts.append(pts[0])
    return [Segment(a, b) for a, b in zip(pts, pts[1:])]


def _ocs_flip(e, where: str) -> bool:
    """A planar polyline's OCS: extrusion +z is the WCS, -z mirrors x (the arbitrary axis algorithm
    gives the x axis (-1, 0, 0)); anything else is not in the xy plane."""
    ex = tuple(e.dxf.get("extrusion", (0, 0, 1)))
    if ex == (0, 0, 1):
        return False
    if ex == (0, 0, -1):
        return True
    raise ShapeError(f"{where}: extrusion {ex} (a polyline not in the xy plane) is not supported")
