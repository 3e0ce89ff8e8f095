"""Verified loading of the generated artefacts (no pickle, no eval).

Every read goes through :func:`verified_bytes`, which checks that

* ``MANIFEST.json`` exists, is valid JSON of the supported format and generator version
  (otherwise the artefacts are *stale*: regenerate them);
* the artefact is listed in the manifest and present on disk (otherwise *missing*);
* its sha256 equals the manifest's (otherwise *corrupted*).

Failures raise :class:`ArtefactError` with a message naming the file and the fix
(``invoke regenerate``).  The artefact folder is the installed ``generated`` package, or the
folder named by the environment variable ``CURVEDVORONOI_GENERATED``.
"""
from __future__ import annotations

import hashlib
import json
import os
from dataclasses import dataclass
from fractions import Fraction
from functools import lru_cache
from importlib import resources
from pathlib import Path

SUPPORTED_MANIFEST_FORMAT = "curvedvoronoi.manifest/1"
SUPPORTED_GENERATOR_VERSION = "1"
OFFSET_FORMAT = "curvedvoronoi.offset/1"


class ArtefactError(RuntimeError):
    """A generated artefact is missing, stale or corrupted."""


def _generated_package() -> str:
    """``curvedvoronoi.generated`` when installed (or imported through ``curvedvoronoi``),
    ``generated`` when ``runtime`` is imported as a top-level package from a source tree."""
    parent = __package__.rpartition(".")[0]
    return f"{parent}.generated" if parent else "generated"


def generated_dir() -> Path:
    env = os.environ.get("CURVEDVORONOI_GENERATED")
    if env:
        return Path(env)
    return Path(str(resources.files(_generated_package())))


def _fix() -> str:
    return "regenerate the artefacts with `invoke regenerate` (or reinstall the package)"


@lru_cache(maxsize=8)
def _manifest_cached(root: str, mtime_ns: int) -> dict:
    path = Path(root) / "MANIFEST.json"
    try:
        manifest = json.loads(path.read_text())
    except json.JSONDecodeError as exc:
        raise ArtefactError(f"{path} is not valid JSON ({exc}); {_fix()}") from None
    if not isinstance(manifest, dict) or manifest.get("format") != SUPPORTED_MANIFEST_FORMAT:
        raise ArtefactError(f"{path}: unsupported manifest format {manifest.get('format')!r} "
                            f"(expected {SUPPORTED_MANIFEST_FORMAT!r}); {_fix()}")
    if manifest.get("generator_version") != SUPPORTED_GENERATOR_VERSION:
        raise ArtefactError(f"{path}: artefacts are stale (generator version "
                            f"{manifest.get('generator_version')!r}, this runtime needs "
                            f"{SUPPORTED_GENERATOR_VERSION!r}); {_fix()}")
    return manifest


def load_manifest(root: Path | None = None) -> dict:
    root = Path(root) if root is not None else generated_dir()
    path = root / "MANIFEST.json"
    if not path.is_file():
        raise ArtefactError(f"missing artefact manifest {path}; {_fix()}")
    return _manifest_cached(str(root), path.stat().st_mtime_ns)


def verified_bytes(relpath: str, root: Path | None = None) -> bytes:
    """The bytes of ``generated/<relpath>`` after checking them against the manifest."""
    root = Path(root) if root is not None else generated_dir()
    manifest = load_manifest(root)
    entry = manifest["artefacts"].get(relpath)
    if entry is None:
        raise ArtefactError(f"artefact {relpath!r} is not listed in {root / 'MANIFEST.json'}; {_fix()}")
    path = root / relpath
    if not path.is_file():
        raise ArtefactError(f"missing artefact {path}; {_fix()}")
    data = path.read_bytes()
    digest = hashlib.sha256(data).hexdigest()
    if digest != entry.get("sha256"):
        raise ArtefactError(f"artefact {path} is corrupted: sha256 {digest[:16]}... does not match the "
                            f"manifest's {str(entry.get('sha256'))[:16]}...; {_fix()}")
    return data


def load_json(relpath: str, root: Path | None = None) -> dict:
    data = verified_bytes(relpath, root)
    try:
        return json.loads(data)
    except json.JSONDecodeError as exc:  # hash matched, so the generator wrote bad JSON
        raise ArtefactError(f"artefact {relpath} is not valid JSON ({exc}); {_fix()}") from None


@dataclass(frozen=True)
class OffsetPolynomial:
    """Implicit equation o(u, v, R; params) = 0 of a generalised offset (thesis §4.4, App. B).

    ``terms`` are (exponent vector over ``variables``, exact coefficient).  ``R`` is the squared
    offset distance.  :meth:`specialise` substitutes parameter values and returns the polynomial
    in (u, v, R) as a dict {(i, j, k): coefficient}.
    """

    family: str
    variables: tuple[str, ...]
    parameters: tuple[str, ...]
    terms: tuple[tuple[tuple[int, ...], Fraction], ...]
    degree_uv: int

    def specialise(self, **params) -> dict[tuple[int, int, int], object]:
        missing = set(self.parameters) - set(params)
        if missing:
            raise ValueError(f"offset of {self.family}: missing parameter(s) {sorted(missing)}")
        idx = [self.variables.index(p) for p in self.parameters]
        out: dict[tuple[int, int, int], object] = {}
        for exps, coef in self.terms:
            val = coef
            for p, i in zip(self.parameters, idx):
                if exps[i]:
                    val = val * params[p] ** exps[i]
            key = (exps[0], exps[1], exps[2])
            out[key] = out.get(key, 0) + val
        return {k: v for k, v in out.items() if v != 0}

    def evaluate(self, u, v, R, **params):
        total = 0
        for (i, j, k), c in self.specialise(**params).items():
            total = total + c * u**i * v**j * R**k
        return total


def _parse_offset(doc: dict, relpath: str) -> OffsetPolynomial:
    try:
        if doc["format"] != OFFSET_FORMAT:
            raise ArtefactError(f"{relpath}: unsupported offset format {doc['format']!r}; {_fix()}")
        variables = tuple(doc["variables"])
        n = len(variables)
        terms = []
        for exps, coef in doc["terms"]:
            if len(exps) != n or not all(isinstance(e, int) and e >= 0 for e in exps):
                raise ValueError(f"bad exponent vector {exps!r}")
            terms.append((tuple(exps), Fraction(coef)))
        return OffsetPolynomial(doc["family"], variables, tuple(doc["parameters"]), tuple(terms),
                                int(doc["degree_uv"]))
    except (KeyError, TypeError, ValueError) as exc:
        raise ArtefactError(f"artefact {relpath} is malformed ({exc}); {_fix()}") from None


@lru_cache(maxsize=16)
def _load_offset_cached(family: str, root: str) -> OffsetPolynomial:
    rel = f"offsets/{family}.json"
    return _parse_offset(load_json(rel, Path(root)), rel)


def load_offset(family: str, root: Path | None = None) -> OffsetPolynomial:
    """The verified offset polynomial of a conic family: ``circle``, ``ellipse`` (x²+c·y²+e, also
    hyperbolas), ``parabola`` (y²−2px), ``lines_parallel``, ``lines_intersecting``, ``generic``."""
    root = Path(root) if root is not None else generated_dir()
    return _load_offset_cached(family, str(root))


ROOT_COUNTS_FORMAT = "curvedvoronoi.root_counts/2"


@lru_cache(maxsize=4)
def _load_root_counts_cached(root: str) -> dict:
    rel = "counts/root_counts.json"
    doc = load_json(rel, Path(root))
    try:
        if doc["format"] != ROOT_COUNTS_FORMAT:
            raise ArtefactError(f"{rel}: unsupported format {doc['format']!r}; {_fix()}")
        out = {}
        for key, entry in doc["counts"].items():
            fams = tuple(entry["families"])
            if len(fams) != 3 or fams != tuple(sorted(fams)) or ",".join(fams) != key:
                raise ValueError(f"bad family triple {key!r}")
            n = entry["count"]
            if not isinstance(n, int) or n < 0:
                raise ValueError(f"bad count {n!r} for {key}")
            mv = entry["mixed_volume_circle_space"]
            if not isinstance(mv, int) or mv < n:
                raise ValueError(f"bad mixed volume {mv!r} for {key} (below the count {n})")
            out[fams] = (n, mv)
        supports = {f: frozenset(tuple(int(v) for v in e) for e in exps)
                    for f, exps in doc["circle_space_supports"].items()}
        return {"counts": out, "supports": supports}
    except (KeyError, TypeError, ValueError) as exc:
        raise ArtefactError(f"artefact {rel} is malformed ({exc}); {_fix()}") from None


def load_root_counts(root: Path | None = None) -> dict[tuple[str, str, str], int]:
    """Generic number of finite generalised Voronoi vertices per sorted family triple
    (``generated/counts/root_counts.json``: msolve parametrisation degrees of random members,
    :mod:`precompute.root_counts`), verified against the manifest."""
    root = Path(root) if root is not None else generated_dir()
    return {k: n for k, (n, _mv) in _load_root_counts_cached(str(root))["counts"].items()}


def load_root_count_bounds(root: Path | None = None) -> tuple[dict, dict]:
    """(mixed volume per sorted family triple, circle-space support set per family) of
    ``generated/counts/root_counts.json``: the proved bound behind the counts
    (:mod:`runtime.certify.root_bound`)."""
    root = Path(root) if root is not None else generated_dir()
    doc = _load_root_counts_cached(str(root))
    return {k: mv for k, (_n, mv) in doc["counts"].items()}, dict(doc["supports"])
