"""The offline pipeline: derive every artefact (in parallel with joblib) and write the manifest.

``regenerate(out_dir)`` is what ``invoke regenerate`` and ``invoke check-generated`` run.  Work
items run in separate processes (joblib/loky); each returns the artefact *text* (python-flint
objects are not picklable), so the parent writes files in a fixed order and the output does not
depend on scheduling.  Progress is printed as items finish, with their wall-clock times.
"""
from __future__ import annotations

import sys
import time
from pathlib import Path
from typing import Callable

from joblib import Parallel, delayed

from .artefacts import GENERATOR_VERSION, offset_document, write_manifest
from .conics import FAMILIES

# generic first: it is by far the longest (about a minute), the others fill the second core
OFFSET_FAMILIES = ("generic", "ellipse", "parabola", "circle", "lines_parallel", "lines_intersecting")


def _offset_job(family: str) -> tuple[str, str, dict, float]:
    from .offsets import derive_offset  # imported in the worker

    t0 = time.perf_counter()
    der = derive_offset(family)
    text = offset_document(der)
    info = {"terms": len(der.terms), "degree_uv": der.degree_uv()}
    return family, text, info, time.perf_counter() - t0


def regenerate(out_dir: Path, *, jobs: int = 2, families=OFFSET_FAMILIES, with_systems: bool = True,
               progress: Callable[[str], None] | None = None) -> dict[str, float]:
    """Regenerate all artefacts into ``out_dir``; return the wall-clock seconds per item."""
    say = progress or (lambda msg: print(msg, file=sys.stderr, flush=True))
    out_dir = Path(out_dir)
    (out_dir / "offsets").mkdir(parents=True, exist_ok=True)
    timings: dict[str, float] = {}
    inputs: dict[str, dict] = {}
    t_all = time.perf_counter()
    say(f"[regenerate] {len(families)} offset families on {jobs} worker(s) -> {out_dir}")
    results = Parallel(n_jobs=jobs, return_as="generator_unordered")(delayed(_offset_job)(f) for f in families)
    done = 0
    for family, text, info, secs in results:
        done += 1
        rel = f"offsets/{family}.json"
        (out_dir / rel).write_text(text)
        timings[f"offset:{family}"] = secs
        inputs[rel] = {"kind": "offset", "family": family, "conic": FAMILIES[family].equation,
                       "generator_version": GENERATOR_VERSION}
        say(f"[regenerate] ({done}/{len(families)}) offset {family:<19} {info['terms']:>5} terms, "
            f"degree {info['degree_uv']} in (u, v)  {secs:7.2f} s")
    if with_systems:
        try:
            from . import systems
        except ImportError:  # the polyhedral stage is optional until it lands
            systems = None
        if systems is not None and hasattr(systems, "build_all"):
            t0 = time.perf_counter()
            written = systems.build_all(out_dir / "systems", progress=say)
            for path in written:
                rel = Path(path).relative_to(out_dir).as_posix()
                inputs[rel] = {"kind": "newton-matrix", "generator_version": GENERATOR_VERSION}
            timings["systems"] = time.perf_counter() - t0
    write_manifest(out_dir, inputs)
    timings["total"] = time.perf_counter() - t_all
    say(f"[regenerate] done in {timings['total']:.1f} s; manifest written")
    return timings
