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
