"""Random elliptic arcs inside a ring of integer points (bench/results/elliptic_arcs.md): how many
whole diagrams the certificate proves, with its CPU seconds (time.process_time) and the problems
of the others.  Each scene: the arc φ ∈ [a₀, a₀ + U(0.5, 2.5)] of (x/2)² + y² = 1 (a₀ uniform,
rounded to 0.01) and 6–9 integer points at radius 3.5–5.5 around it (random angles), built with
``certify=False`` and then given to ``verify_segments``; the arc usually lies inside the points'
hull (pieces on the hull are a stated limit of the certificate).

Command: OPENBLAS_NUM_THREADS=1 .venv/bin/python bench/bench_elliptic_ring.py SEED N
"""
import collections
import math
import sys
import time

import numpy as np

import curvedvoronoi as cv
from curvedvoronoi.runtime.segments.certificate import verify_segments


def scene(rng):
    a0 = round(float(rng.uniform(0, 6.28)), 2)
    a1 = round(a0 + float(rng.uniform(0.5, 2.5)), 2)
    pts = []
    for t in np.sort(rng.uniform(0, 2 * math.pi, int(rng.integers(6, 10)))):
        r = float(rng.uniform(3.5, 5.5))
        p = (int(round(r * math.cos(t))), int(round(r * math.sin(t))))
        if p not in pts:
            pts.append(p)
    return (a0, a1), [cv.Arc.elliptic((0, 0), (2, 0), "1/2", a0, a1)] + pts


def main() -> int:
    seed = int(sys.argv[1]) if len(sys.argv) > 1 else 1
    n = int(sys.argv[2]) if len(sys.argv) > 2 else 12
    rng = np.random.default_rng(seed)
    load0 = open("/proc/loadavg").read().split()[0]
    kinds = collections.Counter()
    ok = cpu = 0.0
    print("| scene | arc φ | points | certified | certificate CPU s | problems |")
    print("|---|---|---|---|---|---|")
    for m in range(n):
        (a0, a1), sites = scene(rng)
        D = cv.voronoi(sites, certify=False)
        t = time.process_time()
        try:
            C = verify_segments(D)
        except Exception as exc:            # a traceback is a result here (counted, named)
            C = None
            probs = [f"raised {type(exc).__name__}: {exc}"]
        dt = time.process_time() - t
        ok += bool(C is not None and C.ok)
        cpu += dt
        if C is not None:
            probs = [str(p) for p in C.problems]
        for p in probs:
            kinds[p.split(":", 1)[-1].strip()[:70]] += 1
        first = "; ".join(probs[:2]).replace("|", "/")
        print(f"| {m} | {a0}..{a1} | {len(sites) - 1} | {'yes' if C is not None and C.ok else 'no'} | {dt:.1f} | "
              f"{first} |", flush=True)
    load1 = open("/proc/loadavg").read().split()[0]
    print(f"\nseed {seed}: certified {int(ok)} of {n}; certificate CPU {cpu:.1f} s in all; load {load0} → {load1}")
    for k, c in kinds.most_common():
        print(f"* {c} × {k}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
