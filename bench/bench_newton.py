"""Benchmark: Canny–Emiris Newton matrices of the Table 5.1 configurations (thesis §5.4–5.5).

    python bench/bench_newton.py            # structure + timings, 1 BLAS thread and default
    python bench/bench_newton.py --rank     # also rank mod a 32-bit prime of a random filling
                                            # (python-flint nmod_mat; ~2 min for 7995²)

Prints a Markdown table and appends it to bench/results/newton.md.  The thesis' four-ellipse
matrix (Singular mpresmat): 7995 × 7995, 589610 nonzeros (text) / 592682 (re-run), M11 6971,
M00 1024.  Matrix size depends on the direction of the shift δ; we take the sign pattern giving
the smallest E (precompute.newton_matrix.smallest_shift).
"""
from __future__ import annotations

import argparse
import datetime
import pathlib
import platform
import random
import sys
import tempfile
import time

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))

from joblib import Parallel, delayed                      # noqa: E402
from threadpoolctl import threadpool_info, threadpool_limits  # noqa: E402

from curvedvoronoi.precompute.mixed import mixed_volume                 # noqa: E402
from curvedvoronoi.precompute.newton_matrix import newton_matrix        # noqa: E402
from curvedvoronoi.precompute.systems import CONFIGURATIONS, build_all, conflict_system  # noqa: E402

PRIME = 4294967291
THESIS = {"EEEE": "7995 / 589610 (592682 Singular re-run) / 6971 / 1024",
          "PPPP (plain)": "Singular mpresmat re-run: 2553 / 100677 / – / –"}


def one(config: str, rank: bool, simplify: bool = True) -> dict:
    t0 = time.perf_counter()
    s = conflict_system(config, simplify=simplify)
    mat = newton_matrix(s.polys, variables=s.variables)
    t_build = time.perf_counter() - t0
    out = {"config": config + ("" if simplify else " (plain)"), "size": mat.size, "nnz": mat.nnz,
           "density": mat.nnz / mat.size ** 2, "n00": mat.n00, "n11": mat.size - mat.n00,
           "cells": mat.n_cells, "t_build": t_build, "mv0": mixed_volume(s.supports[1:])}
    if rank:
        rng = random.Random(config)
        co = [[rng.randrange(1, PRIME) for _ in a] for a in mat.supports]
        t1 = time.perf_counter()
        out["rank"] = mat.fill_nmod(co, PRIME).rank()
        out["t_rank"] = time.perf_counter() - t1
    return out


def table(rows, rank):
    head = "| config | size | nonzeros | density | M00 | M11 | MV_-0 | cells | build s |"
    sep = "|---|---|---|---|---|---|---|---|---|"
    if rank:
        head += " rank mod p (s) |"
        sep += "---|"
    head += " thesis (size / nnz / M11 / M00) |"
    sep += "---|"
    lines = [head, sep]
    for r in rows:
        line = (f"| {r['config']} | {r['size']} | {r['nnz']} | {100 * r['density']:.2f}% | {r['n00']} | "
                f"{r['n11']} | {r['mv0']} | {r['cells']} | {r['t_build']:.1f} |")
        if rank:
            full = "full" if r["rank"] == r["size"] else f"**{r['rank']}**"
            line += f" {full} ({r['t_rank']:.0f}) |"
        line += f" {THESIS.get(r['config'], '')} |"
        lines.append(line)
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rank", action="store_true")
    ap.add_argument("--configs", nargs="*", default=CONFIGURATIONS)
    args = ap.parse_args()
    report = [f"\n## {datetime.datetime.now().isoformat(timespec='seconds')} — {platform.node()} "
              f"python {platform.python_version()}\n",
              f"threadpool_info: `{[(i['internal_api'], i['num_threads']) for i in threadpool_info()]}`\n"]
    with threadpool_limits(limits=1):
        rows = Parallel(n_jobs=2)(delayed(one)(c, args.rank) for c in args.configs)
    rows.append(one("PPPP", args.rank, simplify=False))
    report.append("Per configuration (joblib 2 workers, 1 BLAS thread; build = system + Newton matrix "
                  "structure):\n")
    report.append(table(rows, args.rank))
    for label, limit in (("1 BLAS thread", 1), ("default BLAS threads", None)):
        with tempfile.TemporaryDirectory() as d, threadpool_limits(limits=limit):
            t0 = time.perf_counter()
            build_all(pathlib.Path(d), n_jobs=2)
            report.append(f"\nbuild_all (8 configurations, joblib n_jobs=2, {label}): "
                          f"{time.perf_counter() - t0:.1f} s")
    text = "\n".join(report) + "\n"
    print(text)
    out = pathlib.Path(__file__).parent / "results" / "newton.md"
    with out.open("a") as fh:
        fh.write(text)


if __name__ == "__main__":
    main()
