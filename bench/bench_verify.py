"""Benchmark: the diagram verifier (runtime.voronoi.verify.certificate) against the construction.

For random disjoint circles (N = 100, 300, 1000) and random disjoint ellipses (N = 32, 128, 512;
both scenes drawn by tests/scenes.py, as in the tests) and the mixed conics of bench/bench_voronoi.py (N = 100:
ellipses, circles, points, two parabolas and a hyperbola; the counts of proved vertices and edges
are reported; the tails between the unbounded sites and the accounting of the directions at
infinity they own are proved by runtime.voronoi.verify.conic_tail and far_accounting) the diagram is built by
``runtime.voronoi.construction.voronoi(certify=False)`` and then verified in the same process; for
random points the diagram comes from qhull (scipy.spatial.Voronoi), so the verifier is timed on a
reference diagram independent of the construction.  Reports seconds (wall and the verifier's CPU
time), the ratio verify / construct (target <= 2), the verdict and the number of problems (a "no"
verdict lists what was not proved).

Run:  python bench/bench_verify.py [--sizes 100,300,1000] [--ellipses 32,128,512] [--mixed 100]
(writes bench/results/verify.md)
Thread settings (threadpoolctl) are recorded; other processes on the machine make figures noisy.
"""
from __future__ import annotations

import argparse
import os
import resource
import sys
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "bench"))
sys.path.insert(0, str(ROOT / "tests"))

import numpy as np  # noqa: E402
import scenes  # noqa: E402  (the scenes of the tests)


def qhull_points_diagram(P, far=50.0):
    from scipy.spatial import Voronoi
    from curvedvoronoi.runtime.predicates.circles import Point
    from curvedvoronoi.runtime.voronoi.structure import Diagram, DiagramEdge, DiagramVertex

    vor = Voronoi(P)
    trip: dict = {}
    for (p, q), rv in zip(vor.ridge_points, vor.ridge_vertices):
        for v in rv:
            if v >= 0:
                trip.setdefault(v, set()).update((int(p), int(q)))
    verts = [DiagramVertex(int(v), tuple(sorted(s)), float(vor.vertices[v][0]), float(vor.vertices[v][1]),
                           float(np.hypot(*(vor.vertices[v] - P[min(s)]))), True) for v, s in sorted(trip.items())]
    centre = P.mean(axis=0)
    edges = []
    for eid, ((p, q), rv) in enumerate(zip(vor.ridge_points, vor.ridge_vertices)):
        p, q = int(p), int(q)
        if min(rv) >= 0:
            poly, ends = vor.vertices[rv], (int(rv[0]), int(rv[1]))
        else:
            v = [x for x in rv if x >= 0][0]
            t = (P[q] - P[p]) / np.linalg.norm(P[q] - P[p])
            n = np.array([-t[1], t[0]])
            d = np.sign(np.dot(P[[p, q]].mean(axis=0) - centre, n)) * n
            poly, ends = np.array([vor.vertices[v], vor.vertices[v] + far * d]), (int(v), None)
        edges.append(DiagramEdge(eid, (min(p, q), max(p, q)), ends, False, poly, 1e-12, True))
    return Diagram([Point(float(x), float(y)) for x, y in P], verts, edges)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="100,300,1000")
    ap.add_argument("--points", default=None, help="sizes of the qhull point diagrams (default: --sizes)")
    ap.add_argument("--ellipses", default="32,128,512")
    ap.add_argument("--mixed", default="100", help="sizes of the mixed conics of bench_voronoi (parabolas, a hyperbola)")
    ap.add_argument("--out", default=str(ROOT / "bench" / "results" / "verify.md"))
    args = ap.parse_args(argv)
    from threadpoolctl import threadpool_info
    from curvedvoronoi.runtime.voronoi.construction import voronoi
    from curvedvoronoi.runtime.voronoi.verify.certificate import verify

    from bench_voronoi import mixed_conics, random_ellipses

    sizes = [int(s) for s in args.sizes.split(",") if s]
    esizes = [int(s) for s in args.ellipses.split(",") if s]
    msizes = [int(s) for s in args.mixed.split(",") if s]
    psizes = sizes if args.points is None else [int(s) for s in args.points.split(",") if s]

    def peak_mb():
        return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    rows = []
    for n in sizes:
        # radii in [0.2, 1.5], gaps above 0.1, ~1 circle per 10 square units
        sites = scenes.random_disjoint_circles(n, n, rmin=0.2, rmax=1.5, gap=0.1, side=float(np.sqrt(10.0 * n)))
        t, c = time.perf_counter(), time.process_time()
        D = voronoi(sites, certify=False)
        tc, cc = time.perf_counter() - t, time.process_time() - c
        t, c = time.perf_counter(), time.process_time()
        cert = verify(D)
        tv, cv = time.perf_counter() - t, time.process_time() - c
        rows.append(("circles", n, len(D.vertices), len(D.edges), (tc, cc), tv, cv, cert, cert.timings, peak_mb()))
        print(f"circles {n}: construct {tc:.2f} s, verify {tv:.2f} s, ok={cert.ok}", file=sys.stderr)
    for label, make, ns in (("ellipses", random_ellipses, esizes), ("mixed conics", mixed_conics, msizes)):
        for n in ns:
            sites = make(n, 1)
            t, c = time.perf_counter(), time.process_time()
            D = voronoi(sites, certify=False)
            tc, cc = time.perf_counter() - t, time.process_time() - c
            t, c = time.perf_counter(), time.process_time()
            cert = verify(D, sites)
            tv, cv = time.perf_counter() - t, time.process_time() - c
            rows.append((label, n, len(D.vertices), len(D.edges), (tc, cc), tv, cv, cert, cert.timings, peak_mb()))
            print(f"{label} {n}: construct {tc:.2f} s, verify {tv:.2f} s, ok={cert.ok}, "
                  f"edges proved {sum(cert.edges)}/{len(cert.edges)}", file=sys.stderr)
    for n in psizes:
        P = np.random.default_rng(n).uniform(0, float(np.sqrt(10.0 * n)), (n, 2))
        D = qhull_points_diagram(P)
        t, c = time.perf_counter(), time.process_time()
        cert = verify(D)
        tv, cv = time.perf_counter() - t, time.process_time() - c
        rows.append(("points (qhull diagram)", n, len(D.vertices), len(D.edges), None, tv, cv, cert, cert.timings,
                     peak_mb()))
        print(f"points {n}: verify {tv:.2f} s, ok={cert.ok}", file=sys.stderr)
    threads = ", ".join(f"{i.get('internal_api')}={i.get('num_threads')}" for i in threadpool_info()) or "none"
    load = ", ".join(f"{x:.2f}" for x in os.getloadavg())
    lines = ["# Diagram verifier (runtime.voronoi.verify.certificate)", "",
             f"Command: `python bench/bench_verify.py --sizes {args.sizes} --ellipses {args.ellipses} "
             f"--mixed {args.mixed}" + ("" if args.points is None else f" --points {args.points}") + "`; "
             f"BLAS threads: {threads}; OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS')}; "
             f"load average at the end (1, 5, 15 min): {load} on {os.cpu_count()} cores.  Machine shared with "
             "other processes: wall timings are noisy (verify CPU s is the verifier's process time).", "",
             "| sites | N | vertices | edges | construct s | construct CPU s | verify s | verify CPU s | "
             "verify/construct (wall) | (CPU) | vertices s | edges s | vertices proved | edges proved | ok | problems | "
             "peak RSS MB |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for kind, n, nv, ne, tcc, tv, cv, cert, tm, rss in rows:
        tc, cc = tcc if tcc else (None, None)
        ratio = f"{tv / tc:.2f}" if tc else "-"
        cratio = f"{cv / cc:.2f}" if cc else "-"
        lines.append(f"| {kind} | {n} | {nv} | {ne} | {'-' if tc is None else f'{tc:.2f}'} | "
                     f"{'-' if cc is None else f'{cc:.2f}'} | {tv:.2f} | {cv:.2f} | {ratio} | {cratio} | "
                     f"{tm.get('vertices', 0):.2f} | {tm.get('edges', 0):.2f} | "
                     f"{sum(cert.vertices)} | {sum(cert.edges)} | "
                     f"{'yes' if cert.ok else 'no'} | {len(cert.problems)} | {rss:.0f} |")
    bad = [(kind, n, cert.problems[:3]) for kind, n, _, _, _, _, _, cert, _, _ in rows if cert.problems]
    if bad:
        lines += ["", "First problems of the diagrams not proved:", ""]
        for kind, n, probs in bad:
            for p in probs:
                lines.append(f"* {kind} {n}: {p}")
    text = "\n".join(lines) + "\n"
    print(text)
    Path(args.out).write_text(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
