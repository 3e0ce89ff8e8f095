"""The conic locator's route and answer with each OpenBLAS kernel (runtime/solve/toric.py).

The toric null space's eigenvalue problems, Schur forms and Newton steps round differently with
each OpenBLAS kernel (Haswell/AVX2, Sandybridge/AVX, SkylakeX/AVX-512; OpenBLAS picks one from
the CPU, ``OPENBLAS_CORETYPE`` overrides it when the library loads).  On the hardest clusters a
kernel can leave the numeric list unproved, and then the exact route (msolve) answers.  The answer
must not depend on the kernel: for each kernel, in a child process started with that
``OPENBLAS_CORETYPE``, every triple below is located with an empty cache, and the table gives per
kernel how many were certified and complete, how many needed the exact route, the CPU time, and
whether the certified vertices equal those of the first kernel (1e-9 relative).

Triples: the numerical hazards of tests/test_toric.py (small sites 1×–1000× apart: clusters, near
pairs, far roots), the collinear-centres cluster of tests/test_nongeneric.py, and ``--random N``
further random HHHH triples 100× apart (seeds 1100 …).

    python bench/bench_blas_kernels.py                 # three kernels, the hazards + 12 random
    python bench/bench_blas_kernels.py --random 0 --kernels SkylakeX,Haswell

Appends a table to bench/results/blas_kernels.md.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

HAZARDS = [("HHHH", 206, 1), ("EEPE", 204, 10), ("HHHH", 204, 100), ("HHHH", 205, 100), ("EPHC", 304, 10),
           ("HHHH", 300, 100), ("EEEE", 301, 1000), ("HHHH", 302, 100), ("HHHH", 305, 100), ("EEPE", 307, 100),
           ("HHHH", 405, 10), ("HHHH", 401, 100), ("EEPE", 407, 100), ("HHHH", 806, 100), ("HHHH", 904, 100),
           ("EEPE", 904, 1), ("HHHH", 1003, 100), ("HHHH", 1004, 100), ("HHHH", 703, 100),
           ("collinear centres", 8, 100)]


def child(cases):
    """Run in the child process: locate every case, print one JSON line per case."""
    sys.path.insert(0, str(ROOT))
    sys.path.insert(0, str(ROOT / "tests"))
    from blas_kernel import openblas_kernel
    from test_locator import random_configuration
    from test_nongeneric import random_nongeneric

    from curvedvoronoi.runtime.predicates.locator import clear_cache, locate_conflicts

    kernel = openblas_kernel()
    for kinds, seed, spread in cases:
        cs = (random_nongeneric(kinds, seed, spread=spread) if " " in kinds
              else random_configuration(kinds, seed, spread=spread))
        clear_cache()
        t0, w0 = time.process_time(), time.perf_counter()
        res = locate_conflicts(*cs)
        cpu, wall = time.process_time() - t0, time.perf_counter() - w0
        exact = any("exact route" in n or "exact:" in n for n in res.notes)
        print(json.dumps({"kernel": kernel, "case": [kinds, seed, spread], "certified": bool(res.certified),
                          "complete": bool(res.complete), "exact": exact, "cpu": cpu, "wall": wall,
                          "vertices": sorted([v.x, v.y] for v in res.vertices if v.certified)}), flush=True)


def same(a, b):
    return len(a) == len(b) and all(abs(p - q) <= 1e-9 * max(1.0, abs(q)) for u, v in zip(a, b) for p, q in zip(u, v))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--kernels", default="Haswell,Sandybridge,SkylakeX")
    ap.add_argument("--random", type=int, default=12, help="random HHHH triples 100x apart (seeds 1100 ...)")
    ap.add_argument("--child", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child:
        child(json.loads(args.child))
        return
    cases = HAZARDS + [("HHHH", 1100 + k, 100) for k in range(args.random)]
    rows = {}
    for kernel in args.kernels.split(","):
        env = dict(os.environ, OPENBLAS_CORETYPE=kernel, OPENBLAS_NUM_THREADS="1")
        out = subprocess.run([sys.executable, __file__, "--child", json.dumps(cases)], env=env,
                             capture_output=True, text=True)
        if out.returncode:
            sys.exit(f"{kernel}: the child failed:\n{out.stderr[-3000:]}")
        rows[kernel] = [json.loads(line) for line in out.stdout.splitlines() if line.startswith("{")]
    first = next(iter(rows.values()))
    lines = [f"\n## {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())} — {len(cases)} triples ({len(HAZARDS)} hazards, "
             f"{args.random} random HHHH 100× apart), one BLAS thread, load {os.getloadavg()[0]:.1f}\n",
             "| OPENBLAS_CORETYPE | reported kernel | certified & complete | exact route | CPU s of this process "
             "(total; msolve's own process not counted) | wall s (total) | "
             "vertices = first kernel's | exact route on |",
             "|---|---|---|---|---|---|---|---|"]
    for kernel, rs in rows.items():
        ok = sum(r["certified"] and r["complete"] for r in rs)
        ex = [r for r in rs if r["exact"]]
        eq = sum(same(r["vertices"], f["vertices"]) for r, f in zip(rs, first))
        names = ", ".join(f"{r['case'][0]} {r['case'][1]}" for r in ex) or "—"
        lines.append(f"| {kernel} | {rs[0]['kernel'] if rs else '?'} | {ok}/{len(rs)} | {len(ex)} | "
                     f"{sum(r['cpu'] for r in rs):.0f} | {sum(r['wall'] for r in rs):.0f} | {eq}/{len(rs)} | {names} |")
    text = "\n".join(lines) + "\n"
    print(text)
    res = ROOT / "bench" / "results" / "blas_kernels.md"
    if not res.exists():
        res.write_text("# The conic locator with each OpenBLAS kernel (bench/bench_blas_kernels.py)\n")
    with res.open("a") as f:
        f.write(text)


if __name__ == "__main__":
    main()
