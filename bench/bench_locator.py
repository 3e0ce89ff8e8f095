"""Benchmark of the conic conflict locator (issue 4; thesis §5.5 took ~180 s for four ellipses).

Per configuration type (validation triples of tests/data/validation_cases.json plus random rigid
configurations): median time of each stage of the triple route (fill = offset composition +
Macaulay matrix, nullspace, eigen, refine, filter), end-to-end time of ``locate_conflicts`` with
an empty cache, the time of a further C4 against a cached triple, and peak Python memory
(tracemalloc) -- with 1 BLAS thread and with the default thread setting (threadpoolctl).
Also: dense LAPACK ``eig`` vs ARPACK ``eigs`` on the multiplication matrix (``--eigen``).

    python bench/bench_locator.py            # table, appended to bench/results/locator.md
    python bench/bench_locator.py --quick    # fewer repetitions
    OPENBLAS_NUM_THREADS=1 python bench/bench_locator.py --generic   # certified generic triples, cold/warm
    OPENBLAS_NUM_THREADS=1 python bench/bench_locator.py --all-certified   # every configuration, certified
    OPENBLAS_NUM_THREADS=1 python bench/bench_locator.py --far   # the null-space refusals, certified
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
import tracemalloc
from collections import defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))

from threadpoolctl import threadpool_info, threadpool_limits  # noqa: E402

from curvedvoronoi.runtime.sites.conic import Conic  # noqa: E402
from curvedvoronoi.runtime.predicates.locator import clear_cache, locate_conflicts  # noqa: E402
from curvedvoronoi.runtime.result import LocatorError  # noqa: E402

DATA = ROOT / "tests" / "data" / "validation_cases.json"
STAGES = ["fill", "nullspace", "eigen", "refine", "filter"]


def configurations():
    """(type, four conics) pairs: validation cases (except four circles, which use the exact
    locator) and random rigid configurations from tests/test_locator.py."""
    from test_locator import random_configuration

    out = []
    for case in json.loads(DATA.read_text())["cases"]:
        cs = [Conic.from_coefficients(*k["coefficients"]) for k in case["conics"]]
        if all(c.kind == "circle" for c in cs):
            continue
        t = "".join(sorted(("E" if c.kind in ("ellipse", "hyperbola") else c.kind[0].upper()) for c in cs[:3]))
        out.append((t, cs))
    for mix, kinds in [("EEE", "EEEE"), ("PPP", "PPPP"), ("EHP", "EHPE"), ("CEP", "CEPE")]:
        for seed in range(3):
            cs = random_configuration(kinds, 77 + seed)
            t = "".join(sorted(("E" if c.kind in ("ellipse", "hyperbola") else c.kind[0].upper()) for c in cs[:3]))
            out.append((t, cs))
    return out


def run(configs, repeat):
    rows = defaultdict(lambda: defaultdict(list))
    refused = defaultdict(int)
    for t, cs in configs:
        for _ in range(repeat):
            clear_cache()
            tracemalloc.start()
            t0 = time.perf_counter()
            try:
                res = locate_conflicts(*cs, method="triple")
            except LocatorError:
                tracemalloc.stop()
                refused[t] += 1
                break
            total = time.perf_counter() - t0
            peak = tracemalloc.get_traced_memory()[1]
            tracemalloc.stop()
            # a further C4 against the cached triple
            t1 = time.perf_counter()
            locate_conflicts(cs[0], cs[1], cs[2], cs[3], method="triple")
            cached = time.perf_counter() - t1
            r = rows[t]
            for s in STAGES:
                r[s].append(res.timings.get(s, 0.0))
            r["distances"].append(res.timings.get("distances", 0.0))
            r["total"].append(total)
            r["cached C4"].append(cached)
            r["peak MiB"].append(peak / 2 ** 20)
    return rows, refused


def eigen_compare():
    """Dense eig vs ARPACK eigs (k = N − 2) on the multiplication matrix of a triple of ellipses."""
    import scipy.linalg as sla
    from scipy.sparse.linalg import eigs

    from curvedvoronoi.runtime.solve import vertices as V

    cs = [Conic.from_coefficients(*k["coefficients"]) for k in json.loads(DATA.read_text())["cases"][4]["conics"]]
    captured = {}
    orig = V.sla.eig

    def spy(M, **kw):
        captured["M"] = M
        return orig(M, **kw)

    V.sla.eig = spy
    try:
        V.generalised_vertices(*cs[:3])
    finally:
        V.sla.eig = orig
    M = captured["M"]
    n = M.shape[0]
    out = {}
    for name, f in [("dense eig (all N)", lambda: sla.eig(M)),
                    ("ARPACK eigs k=N-2", lambda: eigs(M, k=n - 2)),
                    ("ARPACK eigs k=20", lambda: eigs(M, k=20))]:
        ts = []
        for _ in range(3):
            t0 = time.perf_counter()
            f()
            ts.append(time.perf_counter() - t0)
        out[name] = min(ts)
    return n, out


def table(label, rows, refused):
    lines = [f"### {label}", "",
             "| triple type | runs | " + " | ".join(STAGES) + " | distances | total (4 conics) | cached C4 | peak MiB | refused |",
             "|---|---|" + "---|" * (len(STAGES) + 6)]
    for t in sorted(set(list(rows) + list(refused))):
        r = rows.get(t, {})
        med = {k: statistics.median(v) for k, v in r.items()} if r else {}
        cells = [f"{med.get(s, float('nan')):.4f}" for s in STAGES]
        lines.append(f"| {t} | {len(r.get('total', []))} | " + " | ".join(cells)
                     + f" | {med.get('distances', float('nan')):.4f} | {med.get('total', float('nan')):.3f}"
                     + f" | {1000 * med.get('cached C4', float('nan')):.2f} ms | {med.get('peak MiB', float('nan')):.1f}"
                     + f" | {refused.get(t, 0)} |")
    return lines + [""]


def child(repeat: int, limit: int | None) -> str:
    configs = configurations()
    with threadpool_limits(limits=limit):
        rows, refused = run(configs, repeat)
        info = [{k: d.get(k) for k in ("internal_api", "num_threads", "version")} for d in threadpool_info()]
    env = os.environ.get("OPENBLAS_NUM_THREADS")
    label = (f"OPENBLAS_NUM_THREADS={env!s}, threadpool_limits({limit}); threadpool_info "
             f"`{json.dumps(info)}`")
    lines = table(label, rows, refused)
    if limit == 1:
        with threadpool_limits(limits=1):
            n, eig = eigen_compare()
        lines += [f"Eigen stage, EEE multiplication matrix {n}×{n}, 1 BLAS thread: "
                  + ", ".join(f"{k}: {v * 1000:.1f} ms" for k, v in eig.items()), ""]
    return "\n".join(lines)


def generic_triple(repeat: int = 5) -> str:
    """End-to-end certified-and-complete ``locate_conflicts`` on generic triples (the demo quadruple
    and bench_nongeneric's spread-out generic triple): *cold* = after ``clear_cache()`` (every
    per-triple result and certification table forgotten, artefacts loaded), *warm* = cached triple;
    minimum and median over ``repeat`` runs, with the stage timings of the last cold run."""
    sys.path.insert(0, str(ROOT / "bench"))
    from bench_nongeneric import cases
    from curvedvoronoi.runtime.predicates.locator import demo_configuration

    triples = {"generic compact (demo)": demo_configuration(),
               "spread-out generic triple": cases()["spread-out generic triple"]}
    locate_conflicts(*demo_configuration())
    load0 = os.getloadavg()[0]
    lines = [f"### Generic triples, certified and complete ({time.strftime('%Y-%m-%d %H:%M')}, "
             f"OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS')}, repeat={repeat})", "",
             "| triple | cold min (s) | cold median (s) | warm median (s) | certified | complete | stages of a cold run (ms) |",
             "|---|---:|---:|---:|---|---|---|"]
    for name, cs in triples.items():
        cold, warm = [], []
        for _ in range(repeat):
            clear_cache()
            t0 = time.perf_counter()
            res = locate_conflicts(*cs)
            cold.append(time.perf_counter() - t0)
            t0 = time.perf_counter()
            locate_conflicts(*cs)
            warm.append(time.perf_counter() - t0)
        stages = ", ".join(f"{k} {v * 1000:.0f}" for k, v in res.timings.items())
        lines.append(f"| {name} | {min(cold):.3f} | {statistics.median(cold):.3f} | {statistics.median(warm):.4f} | "
                     f"{res.certified} | {res.complete} | {stages} |")
    lines += ["", f"Load average {load0:.1f} at the start, {os.getloadavg()[0]:.1f} at the end (2 cores shared "
              "with other jobs).  `certify_total` includes the completeness proof (Krawczyk on all 184 "
              "solutions in the scene frame, disjointness, zero-dimensionality by msolve over F_p, started "
              "in the background at the beginning of the call).", ""]
    return "\n".join(lines)


def all_certified() -> str:
    """Every configuration of :func:`configurations` (validation cases except four circles, random
    rigid ones) through the default route (``method="auto"``: certification, completeness, exact
    fallbacks): cold time (after ``clear_cache()``), certified, complete, how completeness closed."""
    from curvedvoronoi.runtime.result import NumericalRefusal

    locate_conflicts(*configurations()[0][1])
    load0 = os.getloadavg()[0]
    lines = [f"### Every configuration, certified route ({time.strftime('%Y-%m-%d %H:%M')}, "
             f"OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS')}, cold calls)", "",
             "| type | cold (s) | certified | complete | completeness by |", "|---|---:|---|---|---|"]
    times = []
    for t, cs in configurations():
        clear_cache()
        t0 = time.perf_counter()
        try:
            res = locate_conflicts(*cs)
        except (LocatorError, NumericalRefusal) as exc:
            dt = time.perf_counter() - t0
            times.append(dt)
            lines.append(f"| {t} | {dt:.3f} | refused | – | {type(exc).__name__}: {str(exc)[:80]} |")
            continue
        dt = time.perf_counter() - t0
        times.append(dt)
        note = next((n for n in reversed(res.notes) if n.startswith("certify completeness")), "")
        how = ("exact real solutions (msolve)" if "exact:" in note else
               "counting + zero-dimensionality" if "zero-dimensional" in note else note[:60])
        lines.append(f"| {t} | {dt:.3f} | {res.certified} | {res.complete} | {how} |")
    lines += ["", f"{len(times)} configurations: median {statistics.median(times):.3f} s, max {max(times):.3f} s; "
              f"load average {load0:.1f} at the start, {os.getloadavg()[0]:.1f} at the end.", ""]
    return "\n".join(lines)


#: configurations whose null-space route refuses (``generalised_vertices(..., homotopy=False,
#: quick=True)``, measured 2026-11-23): indices into :func:`configurations` and random rigid
#: configurations (kinds, seed) of tests/test_locator.random_configuration -- vertices far outside the
#: scene, or non-generic members
FAR_CONFIGURATIONS = ([8, 12, 32, 34], [("PPPP", s) for s in (102, 104, 105, 107, 109, 110, 111)]
                      + [("EHPE", s) for s in (103, 105, 106)]
                      + [("HHHH", s) for s in (100, 101, 104, 106, 109, 110, 111)] + [("CEPE", 110)])


def far_certified() -> str:
    """The 22 configurations of :data:`FAR_CONFIGURATIONS` through the certified default route:
    cold time, certified, complete."""
    from test_locator import random_configuration

    cfgs = configurations()
    runs = [(f"validation #{i} ({cfgs[i][0]})", cfgs[i][1]) for i in FAR_CONFIGURATIONS[0]]
    runs += [(f"{k} seed {s}", random_configuration(k, s)) for k, s in FAR_CONFIGURATIONS[1]]
    load0 = os.getloadavg()[0]
    lines = [f"### Null-space refusals, certified route ({time.strftime('%Y-%m-%d %H:%M')}, "
             f"OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS')}, cold calls)", "",
             "| configuration | cold (s) | certified | complete |", "|---|---:|---|---|"]
    times = []
    for name, cs in runs:
        clear_cache()
        t0 = time.perf_counter()
        res = locate_conflicts(*cs)
        times.append(time.perf_counter() - t0)
        lines.append(f"| {name} | {times[-1]:.2f} | {res.certified} | {res.complete} |")
    lines += ["", f"{len(times)} configurations: median {statistics.median(times):.2f} s, max {max(times):.2f} s, "
              f"sum {sum(times):.1f} s; load average {load0:.1f} at the start, {os.getloadavg()[0]:.1f} at the end.",
              ""]
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--child", choices=["1", "default"])
    ap.add_argument("--generic", action="store_true",
                    help="only the certified end-to-end timing of generic triples (appended to locator.md)")
    ap.add_argument("--all-certified", action="store_true",
                    help="every configuration through the certified default route (appended to locator.md)")
    ap.add_argument("--repeat", type=int, default=5, help="cold/warm runs per triple with --generic")
    ap.add_argument("--far", action="store_true",
                    help="the configurations the null-space route refuses, certified (appended to locator.md)")
    args = ap.parse_args()
    if args.generic or args.all_certified or args.far:
        text = generic_triple(args.repeat) if args.generic else all_certified() if args.all_certified else far_certified()
        print(text)
        with open(ROOT / "bench" / "results" / "locator.md", "a") as fh:
            fh.write("\n" + text + "\n")
        return
    repeat = 1 if args.quick else 3
    if args.child:
        print(child(repeat, 1 if args.child == "1" else None))
        return
    # each thread setting in a fresh process: OpenBLAS reads OPENBLAS_NUM_THREADS at start-up, and a
    # runtime threadpool_limits(1) alone did not remove the slowdown of an already threaded OpenBLAS
    # (measured on the 2-core machine: EEE null space 0.12 s with the variable vs ~4 s without)
    parts = [f"## bench_locator.py ({time.strftime('%Y-%m-%d %H:%M')}, repeat={repeat}, median seconds)", ""]
    for mode, env_val in [("1", "1"), ("default", None), ("1", None)]:
        env = dict(os.environ)
        env.pop("OPENBLAS_NUM_THREADS", None)
        if env_val is not None:
            env["OPENBLAS_NUM_THREADS"] = env_val
        cmd = [sys.executable, __file__, "--child", mode] + (["--quick"] if args.quick else [])
        out = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True).stdout
        parts.append(out)
    text = "\n".join(parts)
    print(text)
    with open(ROOT / "bench" / "results" / "locator.md", "a") as fh:
        fh.write(text + "\n")


if __name__ == "__main__":
    main()
