"""Reading and writing sites: the JSON input schema shared by ``locate`` and ``diagram``.

A sites file is an object ``{"sites": [SITE, ...]}`` (the older ``{"conics": [...]}`` is read
the same way).  Sites are numbered from 0 in the order of the list.  A SITE is one of::

    {"point": [x, y]}
    {"circle": {"centre": [x, y], "radius": r}}              # or "radius_squared": r2
    {"coefficients": [a, b, c, d, e, f]}                     # a x² + b xy + c y² + d x + e y + f = 0
    {"ellipse":   {"centre": [x, y], "axes": [A, B], "rotation": ROT}}     # X²/A² + Y²/B² = 1
    {"hyperbola": {"centre": [x, y], "axes": [A, B], "rotation": ROT}}     # X²/A² − Y²/B² = 1
    {"parabola":  {"vertex": [x, y], "p": p, "rotation": ROT}}             # Y² = 2 p X
    {"segment": [[x0, y0], [x1, y1]]}                        # the closed segment, two distinct ends
    {"arc": {"centre": [x, y], "radius": r, "start": [x, y], "end": [x, y]}}     # exact endpoints
    {"arc": {"centre": [x, y], "radius": r, "start_angle": deg, "end_angle": deg}}
    {"elliptic_arc": {"centre": [x, y], "major_axis": [x, y], "ratio": k,
                      "start_direction": [u, v], "end_direction": [u, v]}}   # exact (cos φ, sin φ)
    {"elliptic_arc": {"centre": [x, y], "major_axis": [x, y], "ratio": k,
                      "start_param": φ0, "end_param": φ1}}                  # radians (DXF's ELLIPSE)

Numbers are JSON numbers (floats are taken at their exact binary value) or rational strings such
as ``"3/5"``.  ``ROT`` (optional, default 0) turns the canonical axes: an angle in **degrees**
(multiples of 90 are exact) or an exact rational unit vector ``{"cos": "3/5", "sin": "4/5"}``.
A site may carry a ``"label"`` string (kept on the site object as ``label``, written back by
:func:`site_to_json`) and a ``"source"`` integer >= 0 (the index of the input shape
it came from, e.g. the polygon a segment bounds: :func:`runtime.sites.shapes.pieces_from_geometry`;
the reader accepts and ignores it, :func:`site_to_json` writes it when given).  The canonical
frames are those of thesis §5.3 (the conic is the canonical one moved by a rigid motion); ``A``,
``B`` are semi-axes, ``p`` the parameter of the parabola.  A segment's ends must differ; whether
segments cross is checked by :func:`runtime.segments.crossings.check_pieces`.  An arc
(:class:`runtime.sites.arc.Arc`) runs **counter-clockwise** from its start to its end on the
circle of rational centre and radius; its exact form gives rational endpoints that must lie on
that circle exactly (``(x - cx)² + (y - cy)² = r²``), its DXF-like form gives angles in degrees
realised by :meth:`runtime.sites.arc.Arc.circular` (exact at multiples of 90°, else rational
points of the circle within about 10⁻¹⁶ of the angle); :func:`site_to_json` writes the exact
form.  Arcs take ``"label"`` and ``"source"`` as segments do.  An elliptic arc
(:class:`runtime.sites.elliptic_arc.EllipticArc`) is the counter-clockwise arc φ ↦ c + cos φ M +
sin φ N of DXF's ELLIPSE (N = k·perp(M), 0 < k < 1); its exact form gives the ends' frame
directions (rational unit vectors), its DXF form the parameters in radians.

The document is validated against :data:`SITES_SCHEMA` with the ``jsonschema`` library; every
problem becomes a :class:`ValueError` with one line naming the offending entry, e.g.
``sites[3].circle.radius: -1 is less than the minimum of 0``.  After parsing, :func:`read_sites`
also rejects

* repeated sites (the same curve twice: its Voronoi vertices are not isolated, thesis §5.2), and
* conics whose scale the numeric locator cannot represent: the offset of the conic's family
  (thesis App. B), specialised to its canonical parameters, must have finite float coefficients,
  and the conic's centre and size must lie within ``10^±30`` (:data:`SCALE_LIMIT`), because the
  offsets of degree up to 8 are evaluated in floating point.

Length: the JSON schema of the sites file and its validation messages live with the parser.
"""
from __future__ import annotations

import json
import math
from fractions import Fraction
from .conic import SCALE_LIMIT
from .rationals import to_fraction

__all__ = ["SITES_SCHEMA", "SCALE_LIMIT", "parse_number", "parse_site", "sites_from_document",
           "read_sites", "read_coefficient_lists", "check_distinct", "check_scale", "site_key",
           "site_to_json", "site_label", "load_json_document"]


_RATIONAL = r"^\s*[+-]?(\d+(\.\d*)?|\.\d+)([eE][+-]?\d+)?(\s*/\s*[+-]?\d+)?\s*$"

_NUM = {"type": ["number", "string"], "pattern": _RATIONAL}
_POS = {"type": ["number", "string"], "pattern": _RATIONAL, "exclusiveMinimum": 0}
_XY = {"type": "array", "items": {"$ref": "#/$defs/number"}, "minItems": 2, "maxItems": 2}
_SEGMENT = {"type": "array", "items": {"$ref": "#/$defs/xy"}, "minItems": 2, "maxItems": 2}
_ARC = {"type": "object",
        "properties": {"centre": {"$ref": "#/$defs/xy"}, "radius": {"$ref": "#/$defs/positive"},
                       "start": {"$ref": "#/$defs/xy"}, "end": {"$ref": "#/$defs/xy"},
                       "start_angle": {"$ref": "#/$defs/number"}, "end_angle": {"$ref": "#/$defs/number"}},
        "required": ["centre", "radius"],
        "oneOf": [{"required": ["start", "end"]}, {"required": ["start_angle", "end_angle"]}],
        "additionalProperties": False}
_ELLIPTIC_ARC = {"type": "object",
                 "properties": {"centre": {"$ref": "#/$defs/xy"}, "major_axis": {"$ref": "#/$defs/xy"},
                                "ratio": {"$ref": "#/$defs/positive"},
                                "start_direction": {"$ref": "#/$defs/xy"}, "end_direction": {"$ref": "#/$defs/xy"},
                                "start_param": {"$ref": "#/$defs/number"}, "end_param": {"$ref": "#/$defs/number"}},
                 "required": ["centre", "major_axis", "ratio"],
                 "oneOf": [{"required": ["start_direction", "end_direction"]},
                           {"required": ["start_param", "end_param"]}],
                 "additionalProperties": False}
_ROT = {"anyOf": [{"type": "number"},
                  {"type": "object", "required": ["cos", "sin"], "additionalProperties": False,
                   "properties": {"cos": {"$ref": "#/$defs/number"}, "sin": {"$ref": "#/$defs/number"}}}]}


def _kind_schema(shape: dict, required: list[str]) -> dict:
    return {"type": "object", "properties": shape, "required": required, "additionalProperties": False}


_CENTRED = {"centre": {"$ref": "#/$defs/xy"},
            "axes": {"type": "array", "items": {"$ref": "#/$defs/positive"}, "minItems": 2, "maxItems": 2},
            "rotation": {"$ref": "#/$defs/rotation"}}

#: JSON Schema (draft 2020-12) of a sites file; see the module docstring.
SITES_SCHEMA = {
    "$schema": "https://json-schema.org/draft/2020-12/schema",
    "title": "curvedvoronoi sites",
    "type": "object",
    "properties": {
        "sites": {"type": "array", "minItems": 1, "items": {"$ref": "#/$defs/site"}},
        "conics": {"type": "array", "minItems": 1, "items": {"$ref": "#/$defs/site"}},
        "description": {"type": "string"},
    },
    "oneOf": [{"required": ["sites"]}, {"required": ["conics"]}],
    "$defs": {
        "number": _NUM,
        "positive": _POS,
        "xy": _XY,
        "rotation": _ROT,
        "site": {
            "type": "object",
            "properties": {
                "label": {"type": "string"},
                "source": {"type": "integer", "minimum": 0},
                "point": {"$ref": "#/$defs/xy"},
                "circle": {
                    "type": "object",
                    "properties": {"centre": {"$ref": "#/$defs/xy"},
                                   "radius": {"type": ["number", "string"], "pattern": _RATIONAL, "minimum": 0},
                                   "radius_squared": {"type": ["number", "string"], "pattern": _RATIONAL,
                                                      "minimum": 0}},
                    "required": ["centre"],
                    "oneOf": [{"required": ["radius"]}, {"required": ["radius_squared"]}],
                    "additionalProperties": False},
                "coefficients": {"type": "array", "items": {"$ref": "#/$defs/number"},
                                 "minItems": 6, "maxItems": 6},
                "ellipse": _kind_schema(_CENTRED, ["centre", "axes"]),
                "hyperbola": _kind_schema(_CENTRED, ["centre", "axes"]),
                "parabola": _kind_schema({"vertex": {"$ref": "#/$defs/xy"}, "p": {"$ref": "#/$defs/positive"},
                                          "rotation": {"$ref": "#/$defs/rotation"}}, ["vertex", "p"]),
                "segment": _SEGMENT,
                "arc": _ARC,
                "elliptic_arc": _ELLIPTIC_ARC,
            },
            "additionalProperties": False,
            "oneOf": [{"required": [k]} for k in ("point", "circle", "coefficients", "ellipse", "hyperbola",
                                                   "parabola", "segment", "arc", "elliptic_arc")],
        },
    },
}

_SHAPES = ("point", "circle", "coefficients", "ellipse", "hyperbola", "parabola", "segment", "arc", "elliptic_arc")
_ARC_FORMS = 'needs "start" and "end" (exact points of the circle) or "start_angle" and "end_angle" (degrees)'


# =====================================================================================
# Validation
# =====================================================================================

def _where(path) -> str:
    out = ""
    for p in path:
        out += f"[{p}]" if isinstance(p, int) else (f".{p}" if out else str(p))
    return out or "document"


def _message(err) -> str:
    """One readable line for a jsonschema ValidationError."""
    where = _where(err.absolute_path)
    v, inst = err.validator, err.instance
    if v == "pattern":
        return f"{where}: {inst!r} is not a rational number (write a JSON number or a string such as \"3/5\")"
    if v == "oneOf" and isinstance(inst, dict):
        keys = err.validator_value
        names = [next(iter(k["required"])) for k in keys if "required" in k]
        if where.endswith(".arc"):
            both = [k for k in ("start", "end", "start_angle", "end_angle") if k in inst]
            if any(k in both for k in ("start", "end")) and any(k in both for k in ("start_angle", "end_angle")):
                return f"{where}: give either the endpoints or the angles, not both ({', '.join(map(repr, both))})"
            return f"{where}: {_ARC_FORMS}"
        present = [n for n in names if n in inst]
        if len(present) > 1:
            return f"{where}: give only one of {', '.join(map(repr, present))}"
        if where == "document":
            return 'expected an object {"sites": [...]} (or {"conics": [...]})'
        return f"{where}: needs one of {', '.join(map(repr, names))}"
    if v == "anyOf" and where.endswith("rotation"):
        return f"{where}: rotation must be an angle in degrees or {{\"cos\": c, \"sin\": s}}, got {inst!r}"
    if v == "type" and err.validator_value == ["number", "string"]:
        return f"{where}: {inst!r} is not a number or a rational string"
    if v == "exclusiveMinimum":
        return f"{where}: {inst!r} must be > 0"
    if v in ("minItems", "maxItems") and isinstance(inst, list):
        need = err.schema.get("minItems")
        if need == 6:
            return f"{where}: needs 6 coefficients [a, b, c, d, e, f], got {len(inst)}"
        if need == 1:
            return f"{where}: the list is empty"
        if where.endswith(".segment"):
            return f"{where}: needs 2 endpoints [[x0, y0], [x1, y1]], got {len(inst)}"
        return f"{where}: needs {need} numbers, got {len(inst)}"
    if v == "additionalProperties" and isinstance(inst, dict):
        allowed = set(err.schema.get("properties", {}))
        extra = sorted(k for k in inst if k not in allowed)
        hint = f" (expected {', '.join(map(repr, sorted(allowed)))})" if allowed else ""
        return f"{where}: unknown key {', '.join(map(repr, extra))}{hint}"
    return f"{where}: {err.message}"


def _validate(doc, source: str) -> None:
    from ..optional import require

    jsonschema = require("jsonschema", "reading a sites file")   # a declared dependency
    validator = jsonschema.Draft202012Validator(SITES_SCHEMA)
    errors = list(validator.iter_errors(doc))
    if not errors:
        return
    # the deepest error names the offending entry best (oneOf errors carry their sub-errors)
    err = jsonschema.exceptions.best_match(errors)
    while (err.context and err.validator in ("oneOf", "anyOf") and not _is_shape_choice(err)
           and not _where(err.absolute_path).endswith("rotation")):
        err = jsonschema.exceptions.best_match(err.context)
    raise ValueError(f"{source}: {_message(err)}")


def _is_shape_choice(err) -> bool:
    """A oneOf over required keys (a site's shape, circle radius, top-level sites/conics)."""
    vv = err.validator_value
    return err.validator == "oneOf" and isinstance(vv, list) and all(set(k) == {"required"} for k in vv)


# =====================================================================================
# Parsing
# =====================================================================================

def parse_number(x, where: str = "value") -> Fraction:
    """A JSON number or rational string as an exact Fraction (:func:`runtime.sites.rationals.to_fraction`:
    a float at its exact binary value).  Only what JSON holds is accepted -- int, float, str --
    bools, NaN and infinities are refused (ValueError naming ``where``)."""
    if isinstance(x, bool) or not isinstance(x, (int, float, str)):
        raise ValueError(f"{where}: {x!r} is not a number or a rational string")
    return to_fraction(x, where)


def _rotation(rot, where: str):
    """(cos, sin) from an angle in degrees (exact for multiples of 90) or {"cos", "sin"}."""
    if rot is None:
        return (1, 0)
    if isinstance(rot, dict):
        return (parse_number(rot["cos"], f"{where}.cos"), parse_number(rot["sin"], f"{where}.sin"))
    deg = parse_number(rot, where)
    if isinstance(deg, float) and not math.isfinite(deg):
        raise ValueError(f"{where}: angle {rot!r} is not finite")
    q = Fraction(deg)
    if q.denominator == 1 and q.numerator % 90 == 0:
        return ((1, 0), (0, 1), (-1, 0), (0, -1))[(q.numerator // 90) % 4]
    th = math.radians(float(deg))
    return (math.cos(th), math.sin(th))


def parse_site(entry, where: str = "site"):
    """One site record (see the module docstring) as a :class:`runtime.sites.circle.Point`,
    :class:`runtime.sites.circle.Circle`, :class:`runtime.sites.conic.Conic`,
    :class:`runtime.sites.segment.Segment` or :class:`runtime.sites.arc.Arc`, with the record's
    ``"label"`` as its ``label``.  A ``"source"`` member is ignored.

    ValueError (InvalidConicError for a degenerate or imaginary conic) naming ``where``.  The
    record is assumed to have the right shape; :func:`sites_from_document` validates first."""
    from .circle import Circle, Point
    from .conic import Conic
    from .segment import Segment

    if not isinstance(entry, dict):
        raise ValueError(f"{where}: expected an object, got {entry!r}")
    shapes = [k for k in _SHAPES if k in entry]
    if len(shapes) != 1:
        raise ValueError(f"{where}: needs exactly one of {', '.join(map(repr, _SHAPES))}")
    kind = shapes[0]
    body = entry[kind]
    label = entry.get("label")
    label = label if isinstance(label, str) else None
    try:
        if kind == "point":
            return Point(*(parse_number(v, f"{where}.point") for v in body), label=label)
        if kind == "circle":
            cx, cy = (parse_number(v, f"{where}.circle.centre") for v in body["centre"])
            if "radius_squared" in body:
                r2 = parse_number(body["radius_squared"], f"{where}.circle.radius_squared")
                if Fraction(r2) < 0:
                    raise ValueError(f"{where}.circle.radius_squared: {body['radius_squared']} is less than "
                                     "the minimum of 0")
                return Point(cx, cy, label) if Fraction(r2) == 0 else Circle(cx, cy, r2, label)
            r = parse_number(body["radius"], f"{where}.circle.radius")
            if Fraction(r) < 0:
                raise ValueError(f"{where}.circle.radius: {body['radius']} is less than the minimum of 0")
            return Point(cx, cy, label) if Fraction(r) == 0 else Circle.from_radius(cx, cy, r, label)
        if kind == "segment":
            if not isinstance(body, (list, tuple)) or len(body) != 2:
                raise ValueError(f"{where}.segment: needs 2 endpoints [[x0, y0], [x1, y1]]")
            ends = [tuple(parse_number(v, f"{where}.segment[{k}]") for v in e) for k, e in enumerate(body)]
            return Segment(ends[0], ends[1], label)
        if kind == "arc":
            return _parse_arc(body, f"{where}.arc", label)
        if kind == "elliptic_arc":
            return _parse_elliptic_arc(body, f"{where}.elliptic_arc", label)
        if kind == "coefficients":
            return Conic.from_coefficients(*(parse_number(v, f"{where}.coefficients") for v in body), label=label)
        rot = _rotation(body.get("rotation"), f"{where}.{kind}.rotation")
        if kind == "parabola":
            vx, vy = (parse_number(v, f"{where}.parabola.vertex") for v in body["vertex"])
            return Conic.parabola(vertex=(vx, vy), p=parse_number(body["p"], f"{where}.parabola.p"), rotation=rot,
                                  label=label)
        centre = tuple(parse_number(v, f"{where}.{kind}.centre") for v in body["centre"])
        axes = tuple(parse_number(v, f"{where}.{kind}.axes") for v in body["axes"])
        if any(Fraction(a) <= 0 for a in axes):
            raise ValueError(f"{where}.{kind}.axes: {body['axes']} must be > 0")
        make = Conic.ellipse if kind == "ellipse" else Conic.hyperbola
        return make(centre=centre, axes=axes, rotation=rot, label=label)
    except (KeyError, TypeError) as exc:
        raise ValueError(f"{where}.{kind}: malformed record ({exc})") from None
    except ValueError as exc:
        msg = str(exc)
        if msg.startswith(where):
            raise
        raise type(exc)(f"{where}: {msg}") from None


def _parse_arc(body, where: str, label):
    """An :class:`runtime.sites.arc.Arc` from its record (either form); ValueError naming ``where``."""
    from .arc import Arc

    if not isinstance(body, dict):
        raise ValueError(f"{where}: expected an object, got {body!r}")
    ends = [k for k in ("start", "end") if k in body]
    angles = [k for k in ("start_angle", "end_angle") if k in body]
    if ends and angles:
        raise ValueError(f"{where}: give either the endpoints or the angles, not both "
                         f"({', '.join(map(repr, ends + angles))})")
    if len(ends) != 2 and len(angles) != 2:
        raise ValueError(f"{where}: {_ARC_FORMS}")
    centre = tuple(parse_number(v, f"{where}.centre") for v in body["centre"])
    radius = parse_number(body["radius"], f"{where}.radius")
    if Fraction(radius) <= 0:
        raise ValueError(f"{where}.radius: {body['radius']} must be > 0")
    label = label if isinstance(label, str) else None
    try:
        if angles:
            a0 = parse_number(body["start_angle"], f"{where}.start_angle")
            a1 = parse_number(body["end_angle"], f"{where}.end_angle")
            return Arc.circular(centre, radius, a0, a1, label)
        start = tuple(parse_number(v, f"{where}.start") for v in body["start"])
        end = tuple(parse_number(v, f"{where}.end") for v in body["end"])
        return Arc(centre, radius, start, end, label)
    except ValueError as exc:
        raise type(exc)(f"{where}: {exc}") from None


def _parse_elliptic_arc(body, where: str, label):
    """An :class:`runtime.sites.elliptic_arc.EllipticArc` from its record (either form)."""
    from .elliptic_arc import EllipticArc

    if not isinstance(body, dict):
        raise ValueError(f"{where}: expected an object, got {body!r}")
    centre = tuple(parse_number(v, f"{where}.centre") for v in body["centre"])
    axis = tuple(parse_number(v, f"{where}.major_axis") for v in body["major_axis"])
    ratio = parse_number(body["ratio"], f"{where}.ratio")
    try:
        if "start_direction" in body:
            u0 = tuple(parse_number(v, f"{where}.start_direction") for v in body["start_direction"])
            u1 = tuple(parse_number(v, f"{where}.end_direction") for v in body["end_direction"])
            return EllipticArc(centre, axis, ratio, u0, u1, label)
        out = EllipticArc.from_dxf(centre, axis, ratio, float(Fraction(parse_number(body["start_param"], where))),
                                   float(Fraction(parse_number(body["end_param"], where))), label)
        if len(out) != 1:
            raise ValueError("a whole ellipse is not an arc (give it as an \"ellipse\" site)")
        return out[0]
    except ValueError as exc:
        raise type(exc)(f"{where}: {exc}") from None


def site_label(site, index: int) -> str:
    """``"site 3 (ellipse)"``: how messages name a site (0-based index)."""
    from .arc import Arc
    from .elliptic_arc import EllipticArc
    from .segment import Segment

    if isinstance(site, Segment):
        return f"site {index} (segment)"
    if isinstance(site, Arc):
        return f"site {index} (arc)"
    if isinstance(site, EllipticArc):
        return f"site {index} (elliptic arc)"
    kind = getattr(site, "kind", None) or ("point" if getattr(site, "r2", 1) == 0 else "circle")
    return f"site {index} ({kind})"


def site_key(site) -> tuple:
    """Exact key of the curve a site describes: equal keys iff the same curve.  A circle given by
    coefficients and the same circle given by centre and radius have the same key; a segment's key
    does not depend on the order of its endpoints."""
    from .circle import Circle
    from .arc import Arc
    from .conic import Conic
    from .elliptic_arc import EllipticArc
    from .segment import Segment

    if isinstance(site, Segment):
        return ("segment",) + tuple((str(x), str(y)) for x, y in site.key())
    if isinstance(site, Arc):
        (cx, cy), r, (ax, ay), (bx, by) = site.key()
        return ("arc",) + tuple(map(str, (cx, cy, r, ax, ay, bx, by)))
    if isinstance(site, EllipticArc):
        (cx, cy), (mx, my), k, (u0, v0), (u1, v1) = site.key()
        return ("elliptic_arc",) + tuple(map(str, (cx, cy, mx, my, k, u0, v0, u1, v1)))
    if isinstance(site, Conic) and site.kind == "circle":
        site = Circle.from_coefficients(*site.coefficients)
    if isinstance(site, Circle):
        return ("circle", str(site.cx), str(site.cy), str(site.r2))
    if isinstance(site, Conic):
        return ("conic", tuple(site.primitive_coefficients))
    raise TypeError(f"not a site: {site!r}")


def check_distinct(sites, name: str = "site") -> None:
    """ValueError naming the first repeated site (0-based): a curve given twice has no isolated
    Voronoi vertices with the other sites (thesis §5.2)."""
    seen: dict = {}
    for i, s in enumerate(sites):
        k = site_key(s)
        if k in seen:
            raise ValueError(f"{name} {i} is the same curve as {name} {seen[k]}: repeated sites have no "
                             "isolated Voronoi vertices; remove the duplicate")
        seen[k] = i


def check_scale(conic, where: str = "site") -> None:
    """ValueError when the numeric conic locator cannot represent ``conic`` in floating point:
    its centre or semi-axes outside ``[1/SCALE_LIMIT, SCALE_LIMIT]``, or its family's offset
    (thesis App. B) specialised to its canonical parameters has non-finite float coefficients.
    Circles and points handled by the exact circle locator (§3.1) need no such check."""
    from .conic import Conic

    if not isinstance(conic, Conic):
        return
    fr = conic.frame
    sizes = [math.sqrt(v) if k != "p" else v for k, v in fr.params.items()]
    for name, v in (("centre x", fr.tx), ("centre y", fr.ty)):
        if abs(v) > SCALE_LIMIT:
            raise ValueError(f"{where}: {conic.kind} {name} = {v:.3g} is outside the supported range "
                             f"|value| <= {SCALE_LIMIT:g} (rescale the input)")
    for v in sizes:
        if not (1 / SCALE_LIMIT <= v <= SCALE_LIMIT):
            raise ValueError(f"{where}: {conic.kind} size {v:.3g} (semi-axis or parameter) is outside the "
                             f"supported range [{1 / SCALE_LIMIT:g}, {SCALE_LIMIT:g}] (rescale the input)")
    from ..algebra.polyalg import CanonicalOffset

    try:
        off = CanonicalOffset(conic)
        ok = bool(all(math.isfinite(float(c)) for c in off.coefs))
    except (OverflowError, ZeroDivisionError):
        ok = False
    if not ok:
        raise ValueError(f"{where}: the {conic.kind}'s shape is too extreme for floating point (its offset "
                         "coefficients overflow, e.g. an axis ratio beyond ~1e75); rescale the coefficients")


def _check_count(doc, source: str, expected: int | None) -> None:
    if expected is None or not isinstance(doc, dict):
        return
    for key in ("sites", "conics"):
        if isinstance(doc.get(key), list) and len(doc[key]) != expected:
            raise ValueError(f"{source}: expected {expected} {key}, got {len(doc[key])}")


def sites_from_document(doc, source: str = "sites", *, expected: int | None = None,
                        distinct: bool = True, scale: bool = True) -> list:
    """Validate a parsed JSON document against :data:`SITES_SCHEMA` and return its sites
    (Point, Circle or Conic), checked to be ``expected`` in number, pairwise distinct and within
    the numeric range (:func:`check_distinct`, :func:`check_scale`).  ValueError with one line."""
    _check_count(doc, source, expected)
    _validate(doc, source)
    key = "sites" if "sites" in doc else "conics"
    entries = doc[key]
    sites = [parse_site(e, f"{source}: {key}[{i}]") for i, e in enumerate(entries)]
    if distinct:
        try:
            check_distinct(sites, "site")
        except ValueError as exc:
            raise ValueError(f"{source}: {exc}") from None
    if scale:
        for i, s in enumerate(sites):
            check_scale(s, f"{source}: {key}[{i}]")
    return sites


def load_json_document(path: str, error: type[ValueError] = ValueError):
    """The JSON document of a file; ``error`` (a ValueError) naming the file when it cannot be read
    or is not JSON (undecodable text included)."""
    try:
        with open(path) as fh:
            return json.load(fh)
    except OSError as exc:
        raise error(f"cannot read {path}: {exc.strerror or exc}") from None
    except ValueError as exc:            # JSONDecodeError, UnicodeDecodeError, an over-long integer
        raise error(f"{path} is not valid JSON: {exc}") from None


def read_sites(path: str, expected: int | None = None, *, distinct: bool = True, scale: bool = True) -> list:
    """The sites of a JSON file (see the module docstring), validated, 0-based messages."""
    return sites_from_document(load_json_document(path), path, expected=expected, distinct=distinct, scale=scale)


def read_coefficient_lists(path: str, expected: int | None = None) -> list[list]:
    """The coefficient lists [a, b, c, d, e, f] of a file whose sites are all given by
    ``"coefficients"`` (the older format), checked against the schema."""
    doc = load_json_document(path)
    _check_count(doc, path, expected)
    _validate(doc, path)
    key = "sites" if "sites" in doc else "conics"
    entries = doc[key]
    out = []
    for i, e in enumerate(entries):
        if "coefficients" not in e:
            raise ValueError(f"{path}: {key}[{i}]: this command needs \"coefficients\"")
        out.append([parse_number(c, f"{key}[{i}].coefficients") for c in e["coefficients"]])
    return out


def site_to_json(site, source: int | None = None) -> dict:
    """The exact JSON record of a site: ``{"point": [x, y]}``, ``{"circle": {"centre": [x, y],
    "radius_squared": r2}}``, ``{"coefficients": [a, b, c, d, e, f]}``, ``{"segment": [[x0, y0],
    [x1, y1]]}``, ``{"arc": {"centre": [x, y], "radius": r, "start": [x, y], "end": [x, y]}}`` or
    ``{"elliptic_arc": {...}}`` (the
    exact form, with the site's ``"label"`` when it has one), numbers as rational strings
    (read back by :func:`parse_site` to the same site).  ``"source"`` is written when ``source`` (or else
    the site's attribute ``source``) is not None."""
    from .circle import Circle
    from .arc import Arc
    from .conic import Conic
    from .elliptic_arc import EllipticArc
    from .segment import Segment

    if isinstance(site, Circle):
        if site.r2 == 0:
            out = {"point": [str(site.cx), str(site.cy)]}
        else:
            out = {"circle": {"centre": [str(site.cx), str(site.cy)], "radius_squared": str(site.r2)}}
    elif isinstance(site, Conic):
        out = {"coefficients": [str(v) for v in site.coefficients]}
    elif isinstance(site, Segment):
        out = {"segment": [[str(site.p[0]), str(site.p[1])], [str(site.q[0]), str(site.q[1])]]}
    elif isinstance(site, Arc):
        out = {"arc": {"centre": [str(site.c[0]), str(site.c[1])], "radius": str(site.rho),
                       "start": [str(site.a[0]), str(site.a[1])], "end": [str(site.b[0]), str(site.b[1])]}}
    elif isinstance(site, EllipticArc):
        out = {"elliptic_arc": {"centre": [str(site.c[0]), str(site.c[1])],
                                "major_axis": [str(site.M[0]), str(site.M[1])], "ratio": str(site.ratio),
                                "start_direction": [str(site.ua[0]), str(site.ua[1])],
                                "end_direction": [str(site.ub[0]), str(site.ub[1])]}}
    else:
        raise TypeError(f"not a site: {site!r}")
    label = getattr(site, "label", None)
    if label is not None:
        out["label"] = str(label)
    if source is None:
        source = getattr(site, "source", None)
    if source is not None:
        if isinstance(source, bool) or int(source) != source or source < 0:
            raise ValueError(f"source must be an integer >= 0, got {source!r}")
        out["source"] = int(source)
    return out
