"""Benchmark of the homotopy route (runtime.solve.homotopy), the second triple solver.

Rows: the validation triples the null-space route refuses (far vertices: hyperbolas_b; parallel
parabola axes: parabolas_b) and, forced with ``solver="homotopy"``, well-scaled triples that the
null-space route also solves (to compare the two).  Columns: paths, finite endpoints, endpoints at
infinity, stalled paths, start-system time (first call per family triple, cached afterwards),
tracking time, refinement time, the null-space route's time on the same triple (or "refused"),
and the locator's certified / complete flags.  Each configuration is run with one BLAS thread and
with the default threading (threadpoolctl), both recorded.

    python bench/bench_homotopy.py        -> bench/results/homotopy.md
"""
from __future__ import annotations

import json
import os
import sys
import time
from fractions import Fraction
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from threadpoolctl import threadpool_info, threadpool_limits  # noqa: E402

from curvedvoronoi.runtime.sites.conic import Conic  # noqa: E402
from curvedvoronoi.runtime.predicates.locator import clear_cache, locate_conflicts  # noqa: E402
from curvedvoronoi.runtime.result import LocatorError  # noqa: E402
from curvedvoronoi.runtime.validation import required_cases_path  # noqa: E402
from curvedvoronoi.runtime.solve.vertices import generalised_vertices  # noqa: E402

NAMES = ["hyperbolas_b_hyperbola4_conflict", "parabolas_b_parabola4_conflict", "exact_EPC_circle4_tangent",
         "ellipses_a_ellipse4_conflict", "mixed_EHP_parabola4_conflict", "parabolas_a_parabola4_conflict"]


def conics(case):
    return [Conic.from_coefficients(*(Fraction(c) for c in k["coefficients"])) for k in case["conics"]]


def run(case):
    cs = conics(case)
    t0 = time.perf_counter()
    try:
        generalised_vertices(*cs[:3], solver="nullspace")
        ns = f"{time.perf_counter() - t0:.2f}"
    except LocatorError:
        ns = "refused"
    hom = generalised_vertices(*cs[:3], solver="homotopy")
    h = hom.info.homotopy
    tm = hom.info.timings
    clear_cache()
    t1 = time.perf_counter()
    res = locate_conflicts(*cs)
    t_loc = time.perf_counter() - t1
    return (f"{h['paths']} | {len(hom.points)} | {h['at_infinity']} | {h['stalled']} | "
            f"{tm.get('homotopy_start', 0):.2f} | {tm.get('homotopy_track', 0):.2f} | {tm.get('refine', 0):.2f} | "
            f"{ns} | {t_loc:.2f} | {res.certified} | {res.complete}")


def main():
    cases = {c["name"]: c for c in json.loads(required_cases_path().read_text())["cases"]}
    head = ["| case | BLAS threads | paths | finite | at infinity | stalled | start system s | track s | "
            "refine s | null-space route s | locate_conflicts s (auto, certified) | certified | complete |",
            "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    rows = []
    for name in NAMES:
        for limit in (1, None):
            label = "1" if limit == 1 else "default"
            if limit == 1:
                with threadpool_limits(1):
                    r = run(cases[name])
            else:
                r = run(cases[name])
            rows.append(f"| {name} | {label} | {r} |")
            print(rows[-1], flush=True)
    libs = ", ".join(f"{i.get('internal_api')} {i.get('num_threads')} threads" for i in threadpool_info())
    text = "\n".join(head + rows) + (
        f"\n\n`python bench/bench_homotopy.py`; machine: {os.cpu_count()} CPUs; thread pools: {libs}; "
        "start-system time is paid once per family triple and process (cached).\n")
    print(text)
    out = ROOT / "bench" / "results" / "homotopy.md"
    with out.open("a") as fh:
        fh.write(f"\n## {time.strftime('%Y-%m-%d %H:%M')}\n\n" + text)


if __name__ == "__main__":
    main()
