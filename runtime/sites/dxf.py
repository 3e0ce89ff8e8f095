"""Segment, arc and point sites from a DXF drawing (ezdxf), with exact coordinates.

:func:`read_dxf` reads the modelspace entities in file order:

=============================  ===================================================================
LINE                           one :class:`runtime.sites.segment.Segment`
ARC                            one :class:`runtime.sites.arc.Arc` (:meth:`Arc.circular`: DXF's
                               angles in degrees, counter-clockwise in the entity's OCS)
CIRCLE                         its two half arcs (:func:`runtime.sites.arc.circle_halves`), one
                               source: the whole circle is the site, its radius the float's value
POINT                          one :class:`runtime.sites.circle.Point`
ELLIPSE                        one :class:`runtime.sites.elliptic_arc.EllipticArc`
                               (:meth:`EllipticArc.from_dxf`: centre, major-axis vector, ratio,
                               parameters in radians), a whole ellipse its two halves
LWPOLYLINE, POLYLINE (2-D)     a piece per pair of consecutive distinct vertices: a Segment, or an
                               Arc where the first vertex has a nonzero bulge; a closed polyline
                               also gets its closing piece (none of length 0)
=============================  ===================================================================

Coordinates are doubles in DXF and are taken at their exact binary value
(:func:`runtime.sites.rationals.to_fraction`).  Each piece gets

* a **source**: the index of its entity among the supported entities of the modelspace (LINE,
  ARC, CIRCLE, POINT, LWPOLYLINE, POLYLINE, counted from 0 in file order, skipped types not counted), so
  that ``sources[i] == k`` maps piece i back to the k-th such entity;
* a **label**: the entity's layer name (also the Segment's or Arc's ``label``).

**Extrusion.**  ARC and 2-D polylines live in their entity's object coordinate system: extrusion
+z is the WCS; extrusion -z mirrors x (the arbitrary axis algorithm gives the OCS x axis
(-1, 0, 0)), so the drawing's points are read as (-x, y), a bulge changes sign and an arc's
counter-clockwise run from its start to its end angle becomes the counter-clockwise run from the
mirrored end to the mirrored start (exactly: the arc is built in the OCS, then its rational points
are mirrored).  Any other extrusion is refused (not in the xy plane).

**Bulges.**  A bulge b = tan(θ/4) between rational vertices p, q gives a rational centre; the
radius |q - p| (1 + b²) / (4 |b|) is rational only when |q - p| is (e.g. not for p = (0, 0),
q = (1, 1)).  Then the arc is **snapped** rather than refused (most drawn bulges have irrational
radii): it keeps its endpoints p and q exactly (the polyline stays connected) and its centre
moves along the perpendicular bisector of pq to c = p + r u, u a rational unit vector within
about 2⁻⁵⁰ radians of the direction from p to the exact centre (from t = tan(φ/2) with
denominator at most 2⁵³), so that r = |q - p|² / (2 u·(q - p)) is rational.  The included angle
changes by about 2⁻⁴⁹ radians, so the arc moves by about 10⁻¹⁵ |q - p|, far below the drawing's
own precision.  Bulges too flat for this (|b| below about 2⁻⁴¹, where u·(q - p) <= 2⁻⁴⁰ |q - p|)
are refused: draw a line segment.

Refused with a one-line :class:`runtime.sites.shapes.ShapeError` naming the entity type, handle
and layer: curves other than lines, circles and ellipses (SPLINE, HATCH, ..., a curve- or
spline-fit polyline) -- planned, not supported yet; an ELLIPSE of ratio 1 (a circle: draw an ARC);
other entity types (TEXT, INSERT, DIMENSION, ...; pass ``skip={"TEXT", ...}`` to ignore them);
polygon and polyface meshes; coordinates with z != 0 (the diagram is planar: flatten the drawing
first; a 3-D POLYLINE is read when all its z are 0); extrusions other than ±z; zero-length LINEs;
ARCs of radius 0 or whose start and end angles give the same point.  The pieces are not checked
against each other here: :func:`runtime.segments.crossings.check_pieces` does it.

ezdxf is optional (``pip install ezdxf``) and imported only here, when a file is read.

Public API: :func:`read_dxf`.
"""
from __future__ import annotations

import math
from fractions import Fraction

from ..result import InvalidConicError
from .rationals import to_fraction
from .shapes import ShapeError

__all__ = ["read_dxf", "SUPPORTED", "CURVED"]

#: entity types read as sites
SUPPORTED = ("LINE", "ARC", "CIRCLE", "POINT", "LWPOLYLINE", "POLYLINE", "ELLIPSE")
#: entity types refused because they need curves other than circular and elliptic arcs (planned)
CURVED = ("SPLINE", "HATCH", "MPOLYGON", "HELIX", "REGION", "ARC_DIMENSION")
_NOT_YET = ("curves other than line segments, circular and elliptic arcs are not supported yet (planned); replace it by "
            "a polyline of line segments and arcs")


def read_dxf(path, *, skip=()) -> tuple[list, list[int], list[str]]:
    """``(pieces, sources, labels)`` of the modelspace of the DXF file ``path`` (see the module
    docstring); ``skip``: entity types to ignore (e.g. ``{"TEXT", "MTEXT", "DIMENSION"}``).

    :class:`runtime.sites.shapes.ShapeError` (a ValueError) with one line, e.g.
    ``drawing.dxf: SPLINE (handle 2F, layer 'walls'): curves other than line segments, circular and
    elliptic arcs are not supported yet (planned); ...``; ImportError naming the pip command without ezdxf."""
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
                raise ShapeError(f"{where}: {_NOT_YET}")
            raise ShapeError(f"{where}: not a supported site entity (supported: {', '.join(SUPPORTED)}); "
                             f"remove it or pass skip={{{kind!r}}}")
        got = _entity_pieces(e, kind, where)
        layer = str(e.dxf.get("layer", "0"))
        for k, p in enumerate(got):
            if hasattr(p, "r2"):                 # a Point is frozen: the same point with the label
                got[k] = type(p)(p.cx, p.cy, layer)
            elif hasattr(p, "label"):
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
    from .circle import Point
    from .segment import Segment

    if kind == "POINT":
        return [Point(*_xy(e.dxf.location, where))]
    if kind == "LINE":
        a, b = _xy(e.dxf.start, f"{where} start"), _xy(e.dxf.end, f"{where} end")
        if a == b:
            raise ShapeError(f"{where}: the line has length 0 (both ends at ({a[0]}, {a[1]})); use a POINT")
        return [Segment(a, b)]
    if kind == "ARC":
        return [_arc_entity(e, where)]
    if kind == "CIRCLE":
        return _circle_entity(e, where)
    if kind == "ELLIPSE":
        return _ellipse_entity(e, where)
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
            raise ShapeError(f"{where}: a curve- or spline-fit polyline: {_NOT_YET}")
        flip = mode == "AcDb2dPolyline" and _ocs_flip(e, where)     # a 3-D polyline is in WCS
        elevation = e.dxf.get("elevation", None) if mode == "AcDb2dPolyline" else None
        elevation = elevation[2] if elevation is not None else 0
        closed = bool(e.is_closed)
        verts = [(tuple(v.dxf.location), v.dxf.get("bulge", 0) if mode == "AcDb2dPolyline" else 0)
                 for v in e.vertices]
    # (point, bulge of the edge leaving it); a repeated vertex keeps the later bulge
    pts: list = []
    for k, (loc, bulge) in enumerate(verts):
        x, y = _xy(loc, f"{where} vertex {k}", elevation)
        try:
            b = to_fraction(bulge or 0, "bulge")
        except InvalidConicError as exc:
            raise ShapeError(f"{where} vertex {k}: {exc}") from None
        p, b = ((-x, y), -b) if flip else ((x, y), b)
        if pts and pts[-1][0] == p:
            pts[-1] = (p, b, k)
        else:
            pts.append((p, b, k))
    if closed and len(pts) > 1 and pts[-1][0] == pts[0][0]:
        pts.pop()
    curved = closed and any(b for _, b, _ in pts)
    if len(pts) < 2 or (closed and len(pts) < 3 and not curved):
        raise ShapeError(f"{where}: fewer than {3 if closed else 2} distinct vertices ({len(pts)})")
    edges = list(zip(pts, pts[1:] + pts[:1] if closed else pts[1:]))
    return [_bulge_arc(p, q, b, f"{where} vertex {k}") if b else Segment(p, q) for (p, b, k), (q, _, _) in edges]


def _arc_entity(e, where: str):
    """An ARC entity as an exact Arc (built in the OCS, mirrored for extrusion -z)."""
    from .arc import Arc

    flip = _ocs_flip(e, where)
    centre = _xy(e.dxf.center, f"{where} centre")
    try:
        arc = Arc.circular(centre, to_fraction(e.dxf.radius, "radius"), to_fraction(e.dxf.start_angle, "start angle"),
                           to_fraction(e.dxf.end_angle, "end angle"))
    except InvalidConicError as exc:
        raise ShapeError(f"{where}: {exc}") from None
    if not flip:
        return arc
    (cx, cy), (ax, ay), (bx, by) = arc.c, arc.a, arc.b
    return Arc((-cx, cy), arc.rho, (-bx, by), (-ax, ay))


def _ellipse_entity(e, where: str) -> list:
    """An ELLIPSE entity (WCS centre and major axis; extrusion −z turns its parameters clockwise:
    φ ∈ [s, e] there is ψ = −φ ∈ [−e, −s] counter-clockwise) as elliptic arcs."""
    from .elliptic_arc import EllipticArc

    flip = _ocs_flip(e, where)
    c = _xy(e.dxf.center, f"{where} centre")
    M = _xy(e.dxf.major_axis, f"{where} major axis")
    s, t = float(e.dxf.start_param), float(e.dxf.end_param)
    if t <= s:
        t += 2 * math.pi
    if flip:
        s, t = -t, -s
    try:
        return EllipticArc.from_dxf(c, M, to_fraction(e.dxf.ratio, "ratio"), s, t)
    except InvalidConicError as exc:
        raise ShapeError(f"{where}: {exc}") from None


def _circle_entity(e, where: str) -> list:
    """A CIRCLE entity as its two half arcs (:func:`runtime.sites.arc.circle_halves`; the radius is
    the float's exact value, so rational; an extrusion −z mirrors the centre)."""
    from .arc import circle_halves

    cx, cy = _xy(e.dxf.center, f"{where} centre")
    if _ocs_flip(e, where):
        cx = -cx
    r = to_fraction(e.dxf.radius, "radius")
    if not r > 0:
        raise ShapeError(f"{where}: the circle has radius {r}; use a POINT")
    return circle_halves((cx, cy), r * r, what=where)


def _bulge_arc(p, q, b: Fraction, where: str):
    """The arc of a polyline edge from p to q with bulge b: exact when its radius is rational, else
    snapped (module docstring)."""
    from .arc import Arc

    try:
        return Arc.from_bulge(p, q, b)
    except InvalidConicError as exc:
        if "irrational" not in str(exc):
            raise ShapeError(f"{where}: {exc}") from None
    dx, dy = q[0] - p[0], q[1] - p[1]
    k = (1 - b * b) / (4 * b)
    cx, cy = (p[0] + q[0]) / 2 - k * dy, (p[1] + q[1]) / 2 + k * dx       # the exact centre (rational)
    nice = _nice_centre(p, q, (cx, cy), b > 0)
    if nice is not None:
        return nice
    phi = math.atan2(float(cy - p[1]), float(cx - p[0]))
    ux, uy = _rational_unit(phi)
    L = dx * dx + dy * dy
    ud = ux * dx + uy * dy
    if ud <= 0 or not (ud * ud > L * Fraction(1, 1 << 80)):
        r0 = math.hypot(float(cx - p[0]), float(cy - p[1]))
        raise ShapeError(f"{where}: bulge {float(b):g} is too flat to snap its irrational radius (~{r0:.6g}) to a "
                         "rational one; replace the arc by a line segment")
    r = L / (2 * ud)
    c = (p[0] + r * ux, p[1] + r * uy)
    return Arc(c, r, p, q) if b > 0 else Arc(c, r, q, p)


def _nice_centre(p, q, c, ccw: bool):
    """The arc a drawing meant: CAD programs store the bulge of a fillet (tan 22.5° for a quarter
    circle) as a float, so the exact centre of the float bulge is a rational point next to a simple
    one ((5, 1) for the fillet from (5, 0) to (6, 1)).  The first of the centres with denominators up
    to 1, 10, ..., 10⁶ near it that is equidistant from p and q at a rational distance, and within
    10⁻⁹ of the float centre relative to |q − p|, is taken; None if there is none (then the centre
    is snapped, see the module docstring).  Exact tangency with the neighbouring pieces, which a
    snapped centre loses by about 10⁻¹⁶ radians, is kept this way."""
    from .arc import Arc, exact_sqrt

    chord = math.hypot(float(q[0] - p[0]), float(q[1] - p[1]))
    for k in range(7):
        D = 10 ** k
        cx, cy = c[0].limit_denominator(D), c[1].limit_denominator(D)
        r2 = (p[0] - cx) ** 2 + (p[1] - cy) ** 2
        if r2 != (q[0] - cx) ** 2 + (q[1] - cy) ** 2:
            continue
        if math.hypot(float(cx - c[0]), float(cy - c[1])) > 1e-9 * chord:
            continue
        r = exact_sqrt(r2)
        if r is not None and r > 0:
            return Arc((cx, cy), r, p, q) if ccw else Arc((cx, cy), r, q, p)
    return None


def _rational_unit(phi: float) -> tuple[Fraction, Fraction]:
    """A rational unit vector within about 2⁻⁵⁰ radians of the direction phi: the point of t =
    tan(φ/2), |t| <= 1 (turned by 180° when |φ| > 90°), t within 2⁻⁵³ of its float value with
    denominator at most 2⁵³."""
    turn = abs(phi) > math.pi / 2
    if turn:
        phi = phi - math.copysign(math.pi, phi)
    t = Fraction(math.tan(phi / 2)).limit_denominator(1 << 53)
    x, y = (1 - t * t) / (1 + t * t), 2 * t / (1 + t * t)
    return (-x, -y) if turn else (x, y)


def _ocs_flip(e, where: str) -> bool:
    """A planar entity's OCS: extrusion +z is the WCS, -z mirrors x (the arbitrary axis algorithm
    gives the x axis (-1, 0, 0)); anything else is not in the xy plane."""
    ex = tuple(e.dxf.get("extrusion", (0, 0, 1)))
    if ex == (0, 0, 1):
        return False
    if ex == (0, 0, -1):
        return True
    raise ShapeError(f"{where}: extrusion {ex} (an entity not in the xy plane) is not supported; only +z and -z "
                     "are read")
