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


def _system_job(config: str, out_dir: str) -> tuple[str, list[str], float]:
    from .systems import build_one  # imported in the worker

    t0 = time.perf_counter()
    paths = build_one(config, out_dir, 0, 0)
    return config, paths, time.perf_counter() - t0


def _system_configurations() -> list[str]:
    try:
        from .systems import CONFIGURATIONS, TRIPLES
    except ImportError:  # the polyhedral stage is optional
        return []
    # largest first, so that the two workers finish together
    return sorted(CONFIGURATIONS, key=lambda c: (-c.count("E"), c)) + list(TRIPLES)


def regenerate(out_dir: Path, *, jobs: int = 2, families=OFFSET_FAMILIES, with_systems: bool = True,
               with_counts: bool = True, progress: Callable[[str], None] | None = None) -> dict[str, float]:
    """Regenerate all artefacts into ``out_dir``; return the wall-clock seconds per item.

    Offsets (thesis ch. 4) and Newton-matrix structures (Table 5.1 configurations and the
    three-conic vertex systems) run in one joblib pool: the generic-conic offset (about a
    minute) occupies one worker while the other builds the matrices.  Then the generic root
    counts of the triple systems (:mod:`precompute.root_counts`, msolve over F_p, about a second)
    are derived from the circle/ellipse/parabola offsets just written.
    """
    say = progress or (lambda msg: print(msg, file=sys.stderr, flush=True))
    out_dir = Path(out_dir)
    (out_dir / "offsets").mkdir(parents=True, exist_ok=True)
    configs = _system_configurations() if with_systems else []
    if configs:
        (out_dir / "systems").mkdir(parents=True, exist_ok=True)
    timings: dict[str, float] = {}
    inputs: dict[str, dict] = {}
    t_all = time.perf_counter()
    total = len(families) + len(configs)
    say(f"[regenerate] {len(families)} offset families + {len(configs)} Newton matrices on {jobs} "
        f"worker(s) -> {out_dir}")
    work = [delayed(_offset_job)(f) for f in families[:1]]
    work += [delayed(_system_job)(c, str(out_dir / "systems")) for c in configs]
    work += [delayed(_offset_job)(f) for f in families[1:]]
    done = 0
    for item in Parallel(n_jobs=jobs, return_as="generator_unordered")(work):
        done += 1
        if len(item) == 4:      # offset
            family, text, info, secs = item
            rel = f"offsets/{family}.json"
            (out_dir / rel).write_text(text)
            timings[f"offset:{family}"] = secs
            inputs[rel] = {"kind": "offset", "family": family, "conic": FAMILIES[family].equation,
                           "generator_version": GENERATOR_VERSION}
            say(f"[regenerate] ({done}/{total}) offset {family:<19} {info['terms']:>5} terms, "
                f"degree {info['degree_uv']} in (u, v)  {secs:7.2f} s")
        else:                   # Newton matrix structure
            config, paths, secs = item
            timings[f"system:{config}"] = secs
            for path in paths:
                rel = Path(path).relative_to(out_dir).as_posix()
                inputs[rel] = {"kind": "newton-matrix", "configuration": config, "system_seed": 0,
                               "lifting_seed": 0, "generator_version": GENERATOR_VERSION}
            say(f"[regenerate] ({done}/{total}) Newton matrix {config:<6} {secs:7.2f} s")
    if with_counts and all((out_dir / f"offsets/{f}.json").is_file() for f in ("circle", "ellipse", "parabola")):
        from .root_counts import ROOT_COUNTS_FORMAT, SEED, root_counts_document

        t0 = time.perf_counter()
        (out_dir / "counts").mkdir(parents=True, exist_ok=True)
        rel = "counts/root_counts.json"
        (out_dir / rel).write_text(root_counts_document(out_dir / "offsets"))
        timings["counts"] = time.perf_counter() - t0
        inputs[rel] = {"kind": "root-counts", "format": ROOT_COUNTS_FORMAT, "seed": SEED,
                       "offsets": ["offsets/circle.json", "offsets/ellipse.json", "offsets/parabola.json"],
                       "generator_version": GENERATOR_VERSION}
        say(f"[regenerate] root counts (msolve over F_p, 10 family triples) {timings['counts']:7.2f} s")
    write_manifest(out_dir, inputs)
    timings["total"] = time.perf_counter() - t_all
    say(f"[regenerate] done in {timings['total']:.1f} s; manifest written")
    return timings
