"""Serialisation of exact artefacts into ``generated/`` and the manifest of hashes.

Artefacts are *data*: JSON (and, for matrix structures, ``.npz`` of integer arrays written by
:mod:`precompute.systems`), never pickles.  Every file is written deterministically (sorted keys,
sorted terms, fixed formatting) so that ``invoke check-generated`` can compare regenerated output
byte for byte with the committed one.  ``generated/MANIFEST.json`` records, per artefact, its
sha256, size, kind and the inputs it was built from, plus the generator version; the runtime
loader (:mod:`runtime.artefacts`) refuses missing, stale or corrupted files.
"""
from __future__ import annotations

import hashlib
import json
from pathlib import Path

from . import __name__ as _pkg  # noqa: F401  (keeps the import graph explicit)
from .conics import FAMILIES
from .offsets import OffsetDerivation

#: bump when the *content or format* of any artefact changes; the runtime checks it
GENERATOR_VERSION = "1"
OFFSET_FORMAT = "curvedvoronoi.offset/1"
MANIFEST_FORMAT = "curvedvoronoi.manifest/1"


def _terms_block(terms) -> str:
    lines = [json.dumps([list(e), str(c)], separators=(",", ":")) for e, c in terms]
    return "[\n    " + ",\n    ".join(lines) + "\n  ]"


def offset_document(der: OffsetDerivation) -> str:
    """The JSON text of an offset artefact (deterministic)."""
    fam = FAMILIES[der.family]
    degrees = dict(zip(der.variables, (int(d) for d in der.poly.degrees())))
    header = {
        "format": OFFSET_FORMAT,
        "family": der.family,
        "conic": fam.equation + " = 0",
        "variables": list(der.variables),
        "parameters": list(fam.params),
        "meaning": "generalised offset o(u, v, R) = 0 of the conic: (u, v) a point, R the squared "
                   "offset distance (thesis §4.1, with r^2 -> R as in §5.3)",
        "degree_uv": der.degree_uv(),
        "table_4_1_degree": fam.offset_degree,
        "degrees": degrees,
        "n_terms": len(der.terms),
        "elimination": {
            "method": "Res_y(Res_x(f, n), Res_x(f, d)) over Z (python-flint), factor, keep the factors "
                      "vanishing at exact offset points p + k*grad f(p), R = k^2 |grad f(p)|^2",
            "kept_factors": der.kept_factors,
            "extraneous_factors": der.spurious_factors,
        },
    }
    head = json.dumps(header, indent=2, sort_keys=True)
    return head[:-2] + ',\n  "terms": ' + _terms_block(der.terms) + "\n}\n"


def sha256_file(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def write_manifest(out_dir: Path, inputs: dict[str, dict]) -> Path:
    """Write ``MANIFEST.json`` for every file below ``out_dir`` (except itself and ``__init__.py``)."""
    entries = {}
    for path in sorted(p for p in out_dir.rglob("*") if p.is_file()):
        rel = path.relative_to(out_dir).as_posix()
        if rel in ("MANIFEST.json", "__init__.py") or "__pycache__" in rel:
            continue
        entries[rel] = {
            "sha256": sha256_file(path),
            "bytes": path.stat().st_size,
            "inputs": inputs.get(rel, {}),
        }
    manifest = {
        "format": MANIFEST_FORMAT,
        "generator_version": GENERATOR_VERSION,
        "artefacts": entries,
    }
    target = out_dir / "MANIFEST.json"
    target.write_text(json.dumps(manifest, indent=2, sort_keys=True) + "\n")
    return target
