"""Benchmark: incremental Delaunay graph of circles and ellipses (thesis §1.2; issue 8).

Times building the diagram of 10, 20, 50 random circles (exact circle locator, §3.1.3) and of
10, 20 random ellipses (general conic locator, if available; ``--ellipses N,N`` to change,
``--no-ellipses`` to skip), with the per-triple vertex cache and (circles) without it; reports
locator calls per insertion and the cache hit rate.  Also times the batch API (joblib).

Run:  python bench/bench_diagram.py            (appends to bench/results/diagram.md)
Runs once with 1 BLAS thread and once with the default, as the helpers' agreement asks.
"""
from __future__ import annotations

import argparse
import os
import random
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))


def random_circles(seed: int, m: int):
    rnd = random.Random(seed)
    out = set()
    while len(out) < m:
        out.add((rnd.randint(0, 1000) / 10, rnd.randint(0, 1000) / 10, rnd.randint(10, 150) / 10))
    return sorted(out)


def random_ellipses(seed: int, m: int):
    from curvedvoronoi.runtime.conic import Conic

    rnd = random.Random(seed)
    rots = [("3/5", "4/5"), ("4/5", "3/5"), (1, 0), (0, 1), ("5/13", "12/13"), ("12/13", "-5/13")]
    cents: list[tuple[int, int]] = []
    out = []
    while len(out) < m:
        cx, cy = rnd.randint(0, 20 * m), rnd.randint(0, 20 * m)
        if any(abs(cx - a) + abs(cy - b) < 16 for a, b in cents):
            continue
        cents.append((cx, cy))
        out.append(Conic.ellipse(centre=(cx, cy), axes=(rnd.randint(3, 6), rnd.randint(1, 3)), rotation=rnd.choice(rots)))
    return out


def run_one(label, sites, **kw):
    from curvedvoronoi.runtime.diagram import DelaunayGraph

    t = time.perf_counter()
    G = DelaunayGraph(sites, **kw)
    dt = time.perf_counter() - t
    ins = G.stats["insertions"]
    n = len(ins)
    return {
        "case": label, "sites": len(sites), "cache": "on" if kw.get("cache", True) else "off",
        "seconds": dt, "edges": len(G.edges()), "vertices": len(G.vertices),
        "conflict_calls_per_ins": G.stats["conflict_calls"] / n,
        "triples_per_ins": G.stats["triples_computed"] / n,
        "hit_rate": G.cache_hit_rate(), "certified": G.certified,
        "skipped": G.stats.get("skipped_triples", 0),
    }


def main(argv=None) -> int:
    p = argparse.ArgumentParser()
    p.add_argument("--circles", default="10,20,50")
    p.add_argument("--ellipses", default="10,20")
    p.add_argument("--no-ellipses", action="store_true")
    p.add_argument("--no-record", action="store_true")
    p.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    a = p.parse_args(argv)
    if not a.child:
        # once with 1 BLAS thread, once with the default
        out = []
        for env_threads in ("1", None):
            env = dict(os.environ)
            if env_threads:
                env["OPENBLAS_NUM_THREADS"] = env["OMP_NUM_THREADS"] = env["MKL_NUM_THREADS"] = env_threads
            else:
                for k in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
                    env.pop(k, None)
            args = [sys.executable, __file__, "--child", "--circles", a.circles, "--ellipses", a.ellipses]
            if a.no_ellipses or env_threads is None:  # ellipses only once (they dominate the time)
                args.append("--no-ellipses")
            r = subprocess.run(args, env=env, capture_output=True, text=True)
            sys.stderr.write(r.stderr)
            if r.returncode:
                raise SystemExit(f"benchmark child failed ({r.returncode})")
            out.append(r.stdout)
        text = "\n".join(out)
        print(text)
        if not a.no_record:
            res = ROOT / "bench" / "results" / "diagram.md"
            res.parent.mkdir(parents=True, exist_ok=True)
            with open(res, "a") as fh:
                fh.write(text + "\n")
        return 0

    from threadpoolctl import threadpool_info

    from curvedvoronoi.runtime.batch import locate_batch
    from curvedvoronoi.runtime.diagram import conic_locator_available

    rows = []
    for m in [int(x) for x in a.circles.split(",") if x]:
        cs = random_circles(1000 + m, m)
        rows.append(run_one("circles", cs))
        if m <= 20:
            rows.append(run_one("circles", cs, cache=False))
        print(f"circles {m} done", file=sys.stderr)
    if not a.no_ellipses and conic_locator_available():
        for m in [int(x) for x in a.ellipses.split(",") if x]:
            rows.append(run_one("ellipses", random_ellipses(2000 + m, m), on_triple_error="skip"))
            print(f"ellipses {m} done", file=sys.stderr)
    info = [(d.get("internal_api"), d.get("num_threads")) for d in threadpool_info()]
    lines = [f"## bench_diagram {time.strftime('%Y-%m-%d %H:%M')}  OPENBLAS_NUM_THREADS="
             f"{os.environ.get('OPENBLAS_NUM_THREADS', 'default')}  threadpools={info}  cpus={os.cpu_count()}",
             "",
             "| sites | n | cache | build (s) | edges | vertices | locator conflict calls / insertion "
             "| triple solves / insertion | cache hit rate | certified | triples the locator failed on |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['case']} | {r['sites']} | {r['cache']} | {r['seconds']:.2f} | {r['edges']} | {r['vertices']} "
                     f"| {r['conflict_calls_per_ins']:.1f} | {r['triples_per_ins']:.1f} | {r['hit_rate']:.3f} "
                     f"| {r['certified']} | {r['skipped']} |")
    # batch API: 400 independent circle queries, serial vs joblib (2 processes)
    rnd = random.Random(7)
    qs = [[(rnd.randint(0, 100), rnd.randint(0, 100), rnd.randint(1, 10)) for _ in range(4)] for _ in range(400)]
    from curvedvoronoi.runtime import circles

    times = {}
    for label, kw in (("serial", {"n_jobs": 1}), ("joblib loky n_jobs=2", {"n_jobs": 2})):
        circles._vertices_cached.cache_clear()
        t = time.perf_counter()
        locate_batch(qs, **kw)
        times[label] = time.perf_counter() - t
    lines += ["", "| batch (400 circle queries, cold caches) | seconds |", "|---|---|"]
    lines += [f"| {k} | {v:.2f} |" for k, v in times.items()]
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
