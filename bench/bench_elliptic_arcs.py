"""Random disjoint elliptic arcs (DXF ELLIPSE) and a DXF read: build time, certificate time, memory.

Scene: n elliptic arcs, one per cell of a square grid of side ``cell`` (so they are disjoint):
integer centre in the cell's middle ± 3, major-axis vector a rational multiple of (cos, sin) of a
random Pythagorean direction with |M| ∈ [6, 14], ratio k/10 (k ∈ 3..8), start and end parameters
drawn in [0, 2π) with a span ≥ 1 rad.  The same arcs are written to a DXF file with ezdxf and read
back by ``cv.read_dxf`` (timed), then ``cv.voronoi(pieces, certify=False)`` (the construction) and
``verify_segments`` (the certificate: vertices with elliptic pieces proved, edges next to them
by runtime/segments/certificate_ellipse_edges.py where it covers them, within a work budget) are
timed separately.

Usage: ``OPENBLAS_NUM_THREADS=1 python bench/bench_elliptic_arcs.py --n 100 --seed 1 [--max-rss-gb 4]``
prints one Markdown table row (times CPU and wall, peak RSS, vertices, edges, rounds, construction
problems, vertices and edges proved by the certificate, certificate faults) and the first problems
on stderr.
"""
from __future__ import annotations

import argparse
import math
import random
import resource
import sys
import tempfile
import time
from fractions import Fraction
from pathlib import Path

PYTHAGOREAN = [(3, 4, 5), (5, 12, 13), (8, 15, 17), (7, 24, 25), (20, 21, 29), (1, 0, 1), (0, 1, 1)]


def random_elliptic_arcs(n: int, seed: int, cell: int = 40):
    """DXF data (centre, major axis, ratio, start, end) of n disjoint elliptic arcs."""
    rng = random.Random(seed)
    side = math.ceil(math.sqrt(n))
    out = []
    for k in range(n):
        gx, gy = k % side, k // side
        c = (gx * cell + cell // 2 + rng.randint(-3, 3), gy * cell + cell // 2 + rng.randint(-3, 3))
        a, b, h = rng.choice(PYTHAGOREAN)
        sx, sy = rng.choice((1, -1)), rng.choice((1, -1))
        length = Fraction(rng.randint(12, 28), 2)
        M = (sx * a * length / h, sy * b * length / h)
        ratio = Fraction(rng.randint(3, 8), 10)
        s = rng.uniform(0, 2 * math.pi)
        e = s + rng.uniform(1.0, 2 * math.pi - 0.3)
        out.append((c, M, ratio, s, e))
    return out


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=100)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--max-rss-gb", type=float, default=4.0)
    args = ap.parse_args()
    limit = int(args.max_rss_gb * 2 ** 30)
    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    import ezdxf

    import curvedvoronoi as cv

    data = random_elliptic_arcs(args.n, args.seed)
    with tempfile.TemporaryDirectory() as tmp:
        doc = ezdxf.new()
        msp = doc.modelspace()
        for c, M, ratio, s, e in data:
            msp.add_ellipse((c[0], c[1]), major_axis=(float(M[0]), float(M[1])), ratio=float(ratio),
                            start_param=s, end_param=e)
        path = Path(tmp) / "arcs.dxf"
        doc.saveas(path)
        t0, c0 = time.perf_counter(), time.process_time()
        pieces, _sources, _labels = cv.read_dxf(path)
        read_wall, read_cpu = time.perf_counter() - t0, time.process_time() - c0
    load0 = Path("/proc/loadavg").read_text().split()[:3]
    t0, c0 = time.perf_counter(), time.process_time()
    D = cv.voronoi(pieces, certify=False)
    build_wall, build_cpu = time.perf_counter() - t0, time.process_time() - c0
    from curvedvoronoi.runtime.segments.certificate import verify_segments
    t0, c0 = time.perf_counter(), time.process_time()
    cert = verify_segments(D)
    cert_wall, cert_cpu = time.perf_counter() - t0, time.process_time() - c0
    load1 = Path("/proc/loadavg").read_text().split()[:3]
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    probs = [p for p in D.problems]
    print(f"| {args.n} | {args.seed} | {len(D.sites)} | {read_wall:.2f} / {read_cpu:.2f} | {build_wall:.2f} / "
          f"{build_cpu:.2f} | {D.stats.get('rounds')} | {len(D.vertices)} | {len(D.edges)} | {len(probs)} | "
          f"{cert_wall:.2f} / {cert_cpu:.2f} | {sum(cert.vertices)} / {len(cert.vertices)} | "
          f"{sum(cert.edges)} / {len(cert.edges)} | "
          f"{sum(1 for q in cert.problems if q.fault)} | {cert.ok} | {rss:.0f} | "
          f"`{' '.join(load0)}` → `{' '.join(load1)}` |")
    for p in probs[:5]:
        print("  problem:", p, file=sys.stderr)
    for q in cert.problems[:8]:
        print("  certificate:", q, "(fault)" if q.fault else "(limit)", file=sys.stderr)
    kinds: dict = {}
    for q in cert.problems:
        what = str(q).split(": ", 1)[-1].split(" between ")[0].split(" (")[0][:70]
        key = ("fault" if q.fault else "limit", q.kind, what)
        kinds[key] = kinds.get(key, 0) + 1
    for key, m in sorted(kinds.items(), key=lambda kv: -kv[1]):
        print(f"  certificate problems: {m} × {key}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
