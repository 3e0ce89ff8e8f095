"""Reading the sites file shared by ``locate`` and ``diagram``:
``{"conics": [{"coefficients": [a, b, c, d, e, f]}, ...]}`` with JSON numbers or rational strings.

Every problem is a ValueError with a one-line message naming the file and the conic."""
from __future__ import annotations

import json
from fractions import Fraction


def parse_number(x):
    """A JSON number stays as it is (floats are taken exactly later); a string must be rational."""
    if isinstance(x, bool) or not isinstance(x, (int, float, str)):
        raise ValueError(f"coefficient {x!r} is not a number or a rational string")
    if isinstance(x, str):
        try:
            return Fraction(x.strip())
        except (ValueError, ZeroDivisionError):
            raise ValueError(f"coefficient {x!r} is not a rational number") from None
    return x


def read_coefficient_lists(path: str, expected: int | None = None) -> list[list]:
    """The coefficient lists [a, b, c, d, e, f] of the file's conics, checked for shape and type."""
    try:
        with open(path) as fh:
            doc = json.load(fh)
    except OSError as exc:
        raise ValueError(f"cannot read {path}: {exc.strerror}") from None
    except json.JSONDecodeError as exc:
        raise ValueError(f"{path} is not valid JSON: {exc}") from None
    if not isinstance(doc, dict) or not isinstance(doc.get("conics"), list):
        raise ValueError(f'{path}: expected an object {{"conics": [...]}}')
    conics = doc["conics"]
    if expected is not None and len(conics) != expected:
        raise ValueError(f"{path}: expected {expected} conics, got {len(conics)}")
    if not conics:
        raise ValueError(f"{path}: no conics")
    out = []
    for i, item in enumerate(conics, 1):
        coeffs = item.get("coefficients") if isinstance(item, dict) else None
        if not isinstance(coeffs, list) or len(coeffs) != 6:
            raise ValueError(f'{path}: conic {i} needs "coefficients": [a, b, c, d, e, f]')
        try:
            out.append([parse_number(c) for c in coeffs])
        except ValueError as exc:
            raise ValueError(f"conic {i}: {exc}") from None
    return out


def site_to_json(site) -> dict:
    """The exact JSON record of a site: ``{"point": [x, y]}``, ``{"circle": {"centre": [x, y],
    "radius_squared": r2}}`` or ``{"coefficients": [a, b, c, d, e, f]}``, numbers as rational strings."""
    from .circles import Circle
    from .conic import Conic

    if isinstance(site, Circle):
        if site.r2 == 0:
            return {"point": [str(site.cx), str(site.cy)]}
        return {"circle": {"centre": [str(site.cx), str(site.cy)], "radius_squared": str(site.r2)}}
    if isinstance(site, Conic):
        return {"coefficients": [str(v) for v in site.coefficients]}
    raise TypeError(f"not a site: {site!r}")


def parse_site(entry, where: str = "site"):
    """One site record (the forms of :func:`site_to_json`, and ``{"circle": {"centre": [x, y],
    "radius": r}}``) as a :class:`runtime.circles.Point`, :class:`runtime.circles.Circle` or
    :class:`runtime.conic.Conic`.  ValueError naming ``where`` on a malformed record."""
    from .circles import Circle, Point
    from .conic import Conic

    if not isinstance(entry, dict):
        raise ValueError(f"{where}: expected an object, got {entry!r}")
    if "point" in entry:
        xy = entry["point"]
        if not isinstance(xy, list) or len(xy) != 2:
            raise ValueError(f'{where}: "point" must be [x, y]')
        return Point(*(parse_number(v) for v in xy))
    if "circle" in entry:
        c = entry["circle"]
        if not isinstance(c, dict) or not isinstance(c.get("centre"), list) or len(c["centre"]) != 2:
            raise ValueError(f'{where}: "circle" must be {{"centre": [x, y], "radius": r}}')
        cx, cy = (parse_number(v) for v in c["centre"])
        if "radius_squared" in c:
            return Circle(cx, cy, parse_number(c["radius_squared"]))
        if "radius" not in c:
            raise ValueError(f'{where}: "circle" needs "radius" (or "radius_squared")')
        return Circle.from_radius(cx, cy, parse_number(c["radius"]))
    coeffs = entry.get("coefficients")
    if not isinstance(coeffs, list) or len(coeffs) != 6:
        raise ValueError(f'{where}: needs "coefficients": [a, b, c, d, e, f], "point" or "circle"')
    return Conic.from_coefficients(*(parse_number(v) for v in coeffs))
