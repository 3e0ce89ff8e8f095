"""Conflict-locator systems of the thesis (ch. 5, §5.3–5.4, Table 5.1, App. C).

Variables ``(x, y, r, R)``; r and R are *squared* distances (the thesis' "r² → r", §5.3).

* ``o1`` — offset of C1 in canonical position (ellipse/hyperbola ``x² + c·y² + e``, App. B.4;
  parabola ``y² − 2·p·x``, App. B.3 / App. C.1 ``offset1``), at squared distance r;
* ``o2, o3`` — canonical offsets of C2, C3 composed with the motion
  ``u = α x − β y + γ, v = β x + α y + δ`` (App. C: ``(a*x-b*y+c, b*x+a*y+d)``), at distance r;
* ``o4`` — the same for C4 at squared distance R;
* ``f0 = u0 + u1 x + u2 y + u3 r + u4 R`` (the generic linear form of Theorem 3.3.15).

The §5.3 simplifications replace ``o_i`` (i > 1) by ``λ o_i − μ o1`` cancelling a "top" term that
``o_i`` shares with ``o1`` (App. C):  for C1 an ellipse/hyperbola, ``r⁴`` in o2, o3 (same type)
and ``x⁸`` in o4 (same type); for C1 a parabola, ``r³`` in o2, o3 and ``y⁶`` in o4.  When the
types differ no top term is shared and ``o_i`` is kept (``simplify_term`` below returns None).

For the supports (Newton polytopes) the formal parameters α, β, γ, δ, c, e, p are replaced by
seeded random rationals (generic values give the generic supports; Singular's ``mpresmat`` in
App. C works with them as formal parameters, which gives the same supports).

The configurations follow Table 5.1 (rows in the thesis' order).  The thesis labels row 6
"Eh Eh P P" (a duplicate of row 4); its mixed volumes (MV_-4 = MV(o1,o2,o3) = 144 = E,P,P and
MV_-2 = MV_-3 = 192) are those of **E P P E**, which is what we build for that row.

:func:`build_all` writes the Newton-matrix structure artefacts (one per configuration).
"""
from __future__ import annotations

import hashlib
import io
import json
import math
import pathlib
import random
import time
import zipfile
from dataclasses import dataclass
from fractions import Fraction
from typing import Callable, Sequence

import flint
import numpy as np

from .polytopes import support

__all__ = [
    "VARS", "VARS3", "CONFIGURATIONS", "TABLE_5_1_ROWS", "TRIPLES", "offset_poly", "System",
    "conflict_system", "vertex_system", "app_c1_parabola_offset", "build_all", "write_artefact",
]

VARS = ("x", "y", "r", "R")
VARS3 = ("x", "y", "r")

#: Table 5.1 rows: (label as printed, configuration C1 C2 C3 C4 that we build)
TABLE_5_1_ROWS: list[tuple[str, str]] = [
    ("P P P P", "PPPP"), ("P P P Eh", "PPPE"), ("Eh P P P", "EPPP"), ("Eh Eh P P", "EEPP"),
    ("Eh Eh Eh P", "EEEP"), ("Eh Eh P P", "EPPE"), ("Eh Eh P Eh", "EEPE"), ("Eh Eh Eh Eh", "EEEE"),
]
CONFIGURATIONS = [c for _, c in TABLE_5_1_ROWS]
#: three-conic vertex systems {f0, o1, o2, o3} in (x, y, r)
TRIPLES = ["EEE", "PPP", "EPP", "EEP"]

_FAMILY = {"E": "ellipse", "P": "parabola"}


def _rand_q(rng: random.Random) -> flint.fmpq:
    while True:
        q = Fraction(rng.randint(-97, 97), rng.randint(1, 89))
        if q not in (0, 1, -1):
            return flint.fmpq(q.numerator, q.denominator)


def _canonical(family: str):
    """(ctx, poly, params) of the canonical offset in (u, v, R, params...).

    Uses the lead's :func:`precompute.offsets.canonical_offset`; App. C.1's transcription
    (:func:`app_c1_parabola_offset`) is a cross-check in tests/test_systems.py.
    """
    from .offsets import canonical_offset
    ctx, poly = canonical_offset(family)
    return ctx, poly, tuple(ctx.names()[3:])


def app_c1_parabola_offset(ctx, x, y, r, p):
    """App. C.1 ``offset1`` (parabola y² − 2px, squared distance r), transcribed verbatim."""
    return (4*y**6 + 4*x**2*y**4 - 20*p*x*y**4 - 12*r*y**4 + p**2*y**4
            - 16*p*x**3*y**2 - 8*r*x**2*y**2 + 32*p**2*x**2*y**2 + 4*p*r*x*y**2
            - 4*p**3*x*y**2 + 12*r**2*y**2 - 20*p**2*r*y**2 + 16*p**2*x**4 - 16*p*r*x**3
            - 16*p**3*x**3 + 4*r**2*x**2 - 8*p**2*r*x**2 + 4*p**4*x**2
            + 16*p*r**2*x + 16*p**3*r*x - 4*r**3 - 8*p**2*r**2 - 4*p**4*r)


def offset_poly(kind: str, ctx, dist: str, motion=None, params=None):
    """Offset of a conic of ``kind`` ('E'|'P') in ``ctx`` (fmpq_mpoly with x, y, r[, R]).

    ``dist``: name of the squared-distance variable ('r' or 'R'); ``motion``: (α, β, γ, δ) or
    None for the canonical position; ``params``: the family's shape parameters.
    """
    cctx, poly, pnames = _canonical(_FAMILY[kind])
    g = dict(zip(ctx.names(), ctx.gens()))
    x, y = g["x"], g["y"]
    if motion is None:
        u, v = x, y
    else:
        a, b, c, d = (flint.fmpq(t) for t in motion)
        u = a * x - b * y + c
        v = b * x + a * y + d
    subs = [u, v, g[dist]] + [ctx.constant(flint.fmpq(params[k].p, params[k].q)) for k in pnames]
    qpoly = flint.fmpq_mpoly_ctx.get(cctx.names(), "lex").from_dict(
        {k: int(c) for k, c in poly.to_dict().items()})
    return qpoly.compose(*subs, ctx=ctx)


def _coeff(poly, monom: tuple[int, ...]):
    return poly.to_dict().get(monom, 0)


def simplify_term(kind1: str, kind_i: str, dist: str) -> tuple[int, ...] | None:
    """The §5.3 / App. C top term of o_i cancelled with o1, as an exponent of (x, y, r, R)."""
    if kind1 != kind_i:
        return None
    if kind1 == "E":
        return (0, 0, 4, 0) if dist == "r" else (8, 0, 0, 0)
    return (0, 0, 3, 0) if dist == "r" else (0, 6, 0, 0)


@dataclass
class System:
    """A polynomial system ``[f0, o1, ..., oN]`` with its variables and provenance."""

    name: str
    variables: tuple[str, ...]
    polys: list            # fmpq_mpoly, f0 first
    labels: list[str]
    seed: int

    @property
    def supports(self) -> list[np.ndarray]:
        return [support(p) for p in self.polys]


def _params(kind: str, rng: random.Random) -> dict[str, Fraction]:
    if kind == "E":
        return {"c": _rand_q(rng), "e": _rand_q(rng)}
    return {"p": _rand_q(rng)}


def _build(config: str, variables: tuple[str, ...], seed: int, simplify: bool) -> System:
    rng = random.Random(f"{config}:{seed}")
    ctx = flint.fmpq_mpoly_ctx.get(variables, "lex")
    gens = ctx.gens()
    f0 = ctx.constant(_rand_q(rng))
    for gvar in gens:
        f0 = f0 + _rand_q(rng) * gvar
    polys, labels = [f0], ["f0"]
    o1 = offset_poly(config[0], ctx, "r", None, _params(config[0], rng))
    polys.append(o1)
    labels.append("o1")
    for i, kind in enumerate(config[1:], start=2):
        dist = "R" if i == 4 else "r"
        motion = tuple(_rand_q(rng) for _ in range(4))
        oi = offset_poly(kind, ctx, dist, motion, _params(kind, rng))
        label = f"o{i}"
        term = simplify_term(config[0], kind, dist) if simplify else None
        if term is not None:
            term = term[: len(variables)]
            c1, ci = _coeff(o1, term), _coeff(oi, term)
            if c1 == 0 or ci == 0:
                raise ArithmeticError(f"{config}: term {term} missing from o1 or o{i}")
            oi = oi * c1 - o1 * ci
            label = f"{c1}*o{i} - {ci}*o1"
        polys.append(oi)
        labels.append(label)
    return System(config, variables, polys, labels, seed)


def conflict_system(config: str, seed: int = 0, simplify: bool = True) -> System:
    """{f0, o1, o2, o3, o4} in (x, y, r, R) for a Table 5.1 configuration like ``"EEPP"``."""
    if len(config) != 4 or set(config) - {"E", "P"}:
        raise ValueError(f"configuration must be 4 letters from E/P, got {config!r}")
    return _build(config, VARS, seed, simplify)


def vertex_system(triple: str, seed: int = 0, simplify: bool = True) -> System:
    """{f0, o1, o2, o3} in (x, y, r): generalised Voronoi vertices of three conics (§5.2)."""
    if len(triple) != 3 or set(triple) - {"E", "P"}:
        raise ValueError(f"triple must be 3 letters from E/P, got {triple!r}")
    return _build(triple, VARS3, seed, simplify)


# ----------------------------------------------------------------------------------------------
# artefacts (deterministic bytes)
# ----------------------------------------------------------------------------------------------
_ZIP_DATE = (1980, 1, 1, 0, 0, 0)


def _npz_bytes(arrays: dict[str, np.ndarray]) -> bytes:
    """A .npz (zip of .npy) with fixed member order and timestamps: byte-for-byte reproducible."""
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", compression=zipfile.ZIP_DEFLATED) as zf:
        for name in sorted(arrays):
            arr = np.ascontiguousarray(arrays[name])
            if arr.dtype == object:
                raise TypeError(f"array {name} has dtype object (would need pickle)")
            member = io.BytesIO()
            np.lib.format.write_array(member, arr, allow_pickle=False)
            info = zipfile.ZipInfo(f"{name}.npy", date_time=_ZIP_DATE)
            info.compress_type = zipfile.ZIP_DEFLATED
            info.external_attr = 0o644 << 16
            info.create_system = 3
            zf.writestr(info, member.getvalue(), compresslevel=6)
    return buf.getvalue()


def write_artefact(matrix, out_dir: pathlib.Path) -> list[pathlib.Path]:
    """Write ``<name>.npz`` + ``<name>.json`` for a :class:`~precompute.newton_matrix.NewtonMatrix`."""
    out_dir = pathlib.Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    arrays, header = matrix.to_arrays()
    npz = _npz_bytes(arrays)
    header = dict(header)
    header["npz_sha256"] = hashlib.sha256(npz).hexdigest()
    p_npz = out_dir / f"{matrix.name}.npz"
    p_json = out_dir / f"{matrix.name}.json"
    p_npz.write_bytes(npz)
    p_json.write_text(json.dumps(header, indent=1, sort_keys=True) + "\n")
    return [p_json, p_npz]


def build_one(config: str, out_dir: str, seed: int, lifting_seed: int) -> list[str]:
    from .newton_matrix import newton_matrix
    system = (conflict_system if len(config) == 4 else vertex_system)(config, seed)
    mat = newton_matrix(system.polys, variables=system.variables, name=f"system_{config}",
                        lifting_seed=lifting_seed, labels=system.labels)
    mat.provenance = {"configuration": config, "system_seed": seed,
                      "thesis": "ch. 5, Table 5.1, App. C" if len(config) == 4 else "§5.2 (C1,C2,C3)"}
    return [str(p) for p in write_artefact(mat, pathlib.Path(out_dir))]


def build_all(out_dir: pathlib.Path, progress: Callable[[str], None] | None = None, *,
              configurations: Sequence[str] | None = None, n_jobs: int = 2, seed: int = 0,
              lifting_seed: int = 0) -> list[pathlib.Path]:
    """Build the Newton-matrix structure artefacts of all Table 5.1 configurations.

    Writes ``system_<CONF>.npz`` (int arrays) + ``system_<CONF>.json`` (header) per
    configuration into ``out_dir`` and returns the written paths (sorted).  Deterministic:
    same seeds -> same bytes.  Runs configurations in parallel with joblib (``n_jobs``).
    """
    from joblib import Parallel, delayed
    configs = list(configurations) if configurations is not None else list(CONFIGURATIONS)
    out_dir = pathlib.Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    paths: list[pathlib.Path] = []
    jobs = (delayed(build_one)(c, str(out_dir), seed, lifting_seed) for c in configs)
    for c, res in zip(configs, Parallel(n_jobs=n_jobs, return_as="generator")(jobs)):
        paths.extend(pathlib.Path(p) for p in res)
        if progress is not None:
            progress(f"systems: {c} done ({time.perf_counter() - t0:.1f} s)")
    return sorted(paths)
