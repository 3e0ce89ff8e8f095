"""Least CPU time of a certified insertion and deletion, robust to a shared machine's load.

Random disjoint circles (tests/cgal/cgal_peer.random_disjoint_circles, N + K + 1 drawn, the first
N built with ``cv.voronoi`` and certified, one more inserted to build the adjacency state): each
of the K others is inserted (``d.insert(c, inplace=True)``) and deleted again
(``d.delete_site(N, renumber="last", inplace=True)``) R times; per circle the least CPU time of
each operation, then the median over the circles.  Every result must be certified.  The least of
R repetitions discounts the time stolen by other processes (the medians of bench_dynamic.py are
2–3× higher under a load of 5 on 2 cores).

Run:  OPENBLAS_NUM_THREADS=1 python bench/bench_insert_repeat.py [--sizes 1000 10000] [--k 20] [--r 5]
      [--no-direct]   (--no-direct: the construction's local diagram instead of star_region)
Prints one line per N with the load (/proc/loadavg) and the thread setting.
"""
from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests" / "cgal"))
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--sizes", nargs="*", type=int, default=[1000, 10000])
    ap.add_argument("--k", type=int, default=20)
    ap.add_argument("--r", type=int, default=5)
    ap.add_argument("--no-direct", action="store_true")
    args = ap.parse_args()
    import cgal_peer
    import curvedvoronoi as cv
    from curvedvoronoi.runtime.voronoi import insertion

    if args.no_direct:
        insertion.star_region = lambda *a, **k: None
    for n in args.sizes:
        circles = cgal_peer.random_disjoint_circles(n + args.k + 1, 1)
        d = cv.voronoi(circles[:n], progress=False)
        assert d.certified
        d = d.insert(circles[n], inplace=True)
        ins, dels, direct = [], [], 0
        for c in circles[n + 1:]:
            bi = bd = float("inf")
            for _ in range(args.r):
                t = time.process_time()
                d = d.insert(c, inplace=True)
                bi = min(bi, time.process_time() - t)
                assert d.certified, d.problems[:3]
                direct += d.stats.get("local build") == "star region"
                t = time.process_time()
                d = d.delete_site(len(d.sites) - 1, renumber="last", inplace=True)
                bd = min(bd, time.process_time() - t)
                assert d.certified, d.problems[:3]
            ins.append(bi)
            dels.append(bd)
        load = Path("/proc/loadavg").read_text().split()[0]
        print(f"N={n} K={args.k} R={args.r} {'construction' if args.no_direct else 'direct'}: insert "
              f"{1000 * statistics.median(ins):.2f} ms, delete (last) {1000 * statistics.median(dels):.2f} ms "
              f"(median over circles of the least CPU time); direct {direct}/{args.k * args.r}; "
              f"load {load}; OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS')}", flush=True)


if __name__ == "__main__":
    main()
