"""Benchmark of the circle conflict locator (thesis §3.1.3): filtered batch path and exact path.

Run:  python bench/bench_circles.py [--n 200000] [--exact 300]
Prints a Markdown table and appends it (with thread settings) to bench/results/circles.md.
Each configuration is measured with 1 BLAS thread and with the default thread setting
(the filter is element-wise numpy, so BLAS threads should not matter; measured anyway).
"""
from __future__ import annotations

import argparse
import datetime as _dt
import json
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np
from threadpoolctl import threadpool_info, threadpool_limits

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from curvedvoronoi.runtime.predicates.circles import Circle, locate_conflicts_circles, voronoi_vertices_circles  # noqa: E402
from curvedvoronoi.runtime.predicates.circles import _vertices_cached  # noqa: E402
from curvedvoronoi.runtime.predicates.circles_filter import locate_conflicts_circles_batch  # noqa: E402


def random_uniform(n, seed):
    """Non-degenerate random input: centres U(-5,5)^2, radii U(0,3) (full double precision)."""
    rng = np.random.default_rng(seed)
    X = np.empty((n, 4, 3))
    X[:, :, :2] = rng.uniform(-5, 5, (n, 4, 2))
    X[:, :, 2] = rng.uniform(0, 3, (n, 4))
    return X


def random_dyadic(n, seed):
    """Coarse dyadic input (multiples of 1/16): many ties, collinear and tangent configurations."""
    rng = np.random.default_rng(seed)
    X = np.empty((n, 4, 3))
    X[:, :, :2] = rng.integers(-64, 64, (n, 4, 2)) / 16
    X[:, :, 2] = rng.integers(0, 40, (n, 4)) / 16
    return X


def time_batch(X, repeat=3):
    best = None
    for _ in range(repeat):
        t0 = time.perf_counter()
        r = locate_conflicts_circles_batch(X, on_error="flag")
        dt = time.perf_counter() - t0
        if best is None or dt < best[0]:
            best = (dt, r)
    return best


def time_exact(queries):
    _vertices_cached.cache_clear()
    t0 = time.perf_counter()
    for q in queries:
        locate_conflicts_circles(*q)
    return time.perf_counter() - t0


def validation_circles():
    data = json.loads(Path("/work/tests/data/validation_cases.json").read_text())
    out = []
    for c in data["cases"]:
        if c["group"] == "four_circles":
            out.append([Circle.from_canonical(k["canonical"]) for k in c["conics"]])
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=200_000)
    ap.add_argument("--exact", type=int, default=300)
    args = ap.parse_args()
    load0 = "%.2f %.2f %.2f" % os.getloadavg()  # the 2 cores are shared: throughput varies with load
    rows = []
    Xu = random_uniform(args.n, 1)
    Xd = random_dyadic(args.n // 4, 2)
    for label, limit in (("1 BLAS thread", 1), ("default threads", None)):
        ctxm = threadpool_limits(limits=1) if limit == 1 else threadpool_limits(limits=None)
        with ctxm:
            for name, X in (("batch, uniform random floats", Xu), ("batch, dyadic grid (many ties)", Xd)):
                locate_conflicts_circles_batch(X[:1000], on_error="flag")  # warm-up
                dt, r = time_batch(X)
                ex = r["needed_exact"]
                rows.append((name, label, X.shape[0], X.shape[0] / dt, f"{ex.mean():.4%}",
                             f"filter {r['timings']['filter']:.3f}s, exact {r['timings']['exact']:.3f}s, "
                             f"errors {int(r['error'].sum())}"))
            qs = [[tuple(Xu[i, j]) for j in range(4)] for i in range(args.exact)]
            dt = time_exact(qs)
            rows.append(("exact path, float input (rational radii)", label, len(qs), len(qs) / dt, "100%", ""))
            vc = validation_circles()
            reps = max(1, args.exact // (10 * len(vc)))
            t0 = time.perf_counter()
            for _ in range(reps):
                _vertices_cached.cache_clear()
                for q in vc:
                    locate_conflicts_circles(*q)
            dt = time.perf_counter() - t0
            rows.append(("exact path, irrational radii (four_circles cases)", label, reps * len(vc),
                         reps * len(vc) / dt, "100%", "r2 non-square: tower depth up to 5"))
            # cached triple, many C4 (incremental construction pattern)
            trip = qs[0][:3]
            voronoi_vertices_circles(*trip)
            t0 = time.perf_counter()
            for q in qs:
                locate_conflicts_circles(*trip, q[3])
            dt = time.perf_counter() - t0
            rows.append(("exact path, cached triple, new C4 only", label, len(qs), len(qs) / dt, "100%", ""))
    lines = [
        f"### bench_circles {_dt.datetime.now().isoformat(timespec='seconds')}",
        "",
        f"command: `python bench/bench_circles.py --n {args.n} --exact {args.exact}`; "
        f"python {platform.python_version()}, numpy {np.__version__}, {os.cpu_count()} cores, "
        f"{platform.processor() or platform.machine()}, load average before run {load0}",
        "",
        "| workload | threads | queries | queries/s | exact fallback share | notes |",
        "|---|---|---:|---:|---:|---|",
    ]
    for name, label, n, qps, share, note in rows:
        lines.append(f"| {name} | {label} | {n} | {qps:,.0f} | {share} | {note} |")
    info = [{k: d.get(k) for k in ("internal_api", "num_threads", "version")} for d in threadpool_info()]
    lines += ["", f"threadpool_info: `{json.dumps(info)}`",
              f"env OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS')}", ""]
    text = "\n".join(lines)
    print(text)
    out = ROOT / "bench" / "results" / "circles.md"
    out.parent.mkdir(parents=True, exist_ok=True)
    with out.open("a") as f:
        f.write(text + "\n")


if __name__ == "__main__":
    main()
