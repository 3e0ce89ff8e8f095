"""Benchmark: original-curves (a) vs generalised-offset (b) formulations (thesis Tables 6.4–6.7).

python bench/bench_interval.py [--budget N]   -> prints a Markdown table, appends to bench/results/interval.md
Runs each case with 1 BLAS thread and with the default (the solver itself is single-threaded
python-flint; BLAS only serves 8×8 inversions).
"""
from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from threadpoolctl import threadpool_info, threadpool_limits  # noqa: E402

from curvedvoronoi.runtime.interval import locate_conflicts_interval  # noqa: E402

DATA = Path("/work/tests/data/validation_cases.json")
CASES = ["ellipses_c_ellipse4_conflict", "hyperbolas_a_hyperbola4_conflict"]


def domain(case, pad=0.5):
    xs = [float(v["x"]) for v in case["vertices"]]
    ys = [float(v["y"]) for v in case["vertices"]]
    return (min(xs) - pad, max(xs) + pad, min(ys) - pad, max(ys) + pad)


def run(case, formulation, budget):
    t = time.perf_counter()
    res = locate_conflicts_interval(*case["conics"], formulation=formulation, domain=domain(case), max_boxes=budget)
    dt = time.perf_counter() - t
    boxes = next((n for n in res.notes if n.startswith("stats:")), "")
    ok = len(res.vertices) == len(case["vertices"]) and res.conflict == case["conflict"]
    return dt, res, boxes, ok


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--budget", type=int, default=150_000, help="box budget per system")
    ap.add_argument("--cases", nargs="*", default=CASES)
    ap.add_argument("--threads", nargs="*", default=["1", "default"])
    a = ap.parse_args()
    cases = {c["name"]: c for c in json.loads(DATA.read_text())["cases"]}
    lines = ["", f"## run {time.strftime('%Y-%m-%d %H:%M:%S')} (budget {a.budget} boxes/system)", "",
             "threadpool_info: " + json.dumps([{k: d.get(k) for k in ("internal_api", "num_threads")}
                                               for d in threadpool_info()]), "",
             "| case | BLAS threads | (a) original s | (a) complete / vertices | (b) offset s | (b) complete / vertices | expected vertices | ratio (a)/(b) |",
             "|---|---|---|---|---|---|---|---|"]
    for name in a.cases:
        case = cases[name]
        for th in a.threads:
            ctx = threadpool_limits(1) if th == "1" else threadpool_limits(None)
            with ctx:
                tb, rb, sb, okb = run(case, "offset", a.budget)
                ta, ra, sa, oka = run(case, "original", a.budget)
            ratio = ta / tb
            ratio_s = f"{ratio:.1f}" if ra.complete else f">= {ratio:.1f} (a) not finished"
            lines.append(f"| {name} | {th} | {ta:.1f} | {ra.complete} / {len(ra.vertices)} | {tb:.1f} | "
                         f"{rb.complete} / {len(rb.vertices)} | {len(case['vertices'])} | {ratio_s} |")
            print(lines[-1], file=sys.stderr)
            print(f"   (a) {sa}\n   (b) {sb}", file=sys.stderr)
    out = "\n".join(lines) + "\n"
    print(out)
    res = ROOT / "bench" / "results" / "interval.md"
    res.parent.mkdir(parents=True, exist_ok=True)
    with res.open("a") as fh:
        fh.write(out)


if __name__ == "__main__":
    main()
