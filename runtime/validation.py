"""Loader of validation-case files (``tests/data/validation_cases.json``, described in tests/data/README.md).

Each case gives four conics C1..C4 (exact integer coefficients and their exact canonical
construction) and, for every true Voronoi vertex of (C1, C2, C3) (thesis §5.2,
Def. 5.2.1), the expected radius, distance to C4 and conflict flag (thesis Thm 5.2.2).
The loader turns the conics into :class:`runtime.sites.conic.Conic` objects and keeps the
expected values both as exact decimals (Fraction) and floats.
"""
from __future__ import annotations

import json
import os
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path
from typing import Any

from .sites.conic import Conic

__all__ = ["ValidationCase", "ExpectedVertex", "load_cases", "default_cases_path", "canonical_of"]

_ENV = "CURVEDVORONOI_VALIDATION_CASES"


@dataclass
class ExpectedVertex:
    x: Fraction
    y: Fraction
    radius: Fraction
    distance_to_fourth: Fraction
    margin: Fraction
    in_conflict: bool
    tangent: bool
    raw: dict = field(repr=False, default_factory=dict)

    def as_floats(self) -> dict[str, float]:
        return {k: float(getattr(self, k)) for k in ("x", "y", "radius", "distance_to_fourth", "margin")}


@dataclass
class ValidationCase:
    name: str
    group: str
    conics: list[Conic]
    canonical: list[dict[str, Any]]       # exact: {"type", "cos", "sin", "tx", "ty", params...} (Fractions)
    conflict: bool
    vertices: list[ExpectedVertex]
    raw: dict = field(repr=False, default_factory=dict)


def canonical_of(entry: dict) -> dict[str, Any]:
    """The exact canonical construction of a conic entry (values as Fractions, 'type' kept)."""
    can = entry["canonical"]
    return {k: (v if k == "type" else Fraction(v)) for k, v in can.items()}


def repository_cases_path() -> Path:
    """The validation cases shipped with the repository's tests: ``tests/data/validation_cases.json``."""
    return Path(__file__).resolve().parent.parent / "tests" / "data" / "validation_cases.json"


def default_cases_path(start: str | os.PathLike | None = None) -> Path | None:
    """``$CURVEDVORONOI_VALIDATION_CASES`` if set, else ``tests/data/validation_cases.json`` of the
    repository (``start`` or the parent of the ``runtime`` folder) if it exists, else None."""
    env = os.environ.get(_ENV)
    if env and Path(env).is_file():
        return Path(env)
    cand = (Path(start) / "tests" / "data" / "validation_cases.json" if start is not None
            else repository_cases_path())
    return cand if cand.is_file() else None


def required_cases_path() -> Path:
    """:func:`default_cases_path`, or FileNotFoundError naming where the file was looked for
    (tests use this so that a missing validation file fails loudly instead of running no case)."""
    path = default_cases_path()
    if path is None:
        raise FileNotFoundError(f"validation_cases.json not found at {repository_cases_path()} "
                                f"(a source checkout ships it) and ${_ENV} is not set")
    return path


def load_cases(path: str | os.PathLike) -> list[ValidationCase]:
    """Load every case of a validation file; conics are validated with Conic.from_coefficients."""
    with open(path, encoding="utf-8") as fh:
        data = json.load(fh)
    cases = data["cases"] if isinstance(data, dict) else data
    out = []
    for c in cases:
        conics = [Conic.from_coefficients(*e["coefficients"]) for e in c["conics"]]
        verts = [ExpectedVertex(Fraction(v["x"]), Fraction(v["y"]), Fraction(v["radius"]),
                                Fraction(v["distance_to_fourth"]), Fraction(v["margin"]),
                                bool(v["in_conflict"]), bool(v.get("tangent", False)), v)
                 for v in c["vertices"]]
        out.append(ValidationCase(c["name"], c.get("group", ""), conics,
                                  [canonical_of(e) for e in c["conics"]], bool(c["conflict"]), verts, c))
    return out
