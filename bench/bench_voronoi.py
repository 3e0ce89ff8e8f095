"""Benchmark of the Voronoi diagram construction (runtime/voronoi/construction.py).

Random disjoint circles (N = 100, 1000, 10000) against CGAL's Apollonius_graph_2 in the same run
(tests/cgal/apollonius_edges.cpp, built with g++ -O2; needs libcgal-dev), and random disjoint
ellipses (N = 32, 128, 512, 2000).  Each case runs in a fresh subprocess (peak RSS = ru_maxrss of that
process, imports included); construction time is certify=False; the verifier
(runtime.voronoi.verify) is timed separately where it is affordable.

Run:  python bench/bench_voronoi.py [--quick]      (writes bench/results/voronoi.md)
"""
from __future__ import annotations

import argparse
import json
import math
import os
import random
import subprocess
import sys
import time
from fractions import Fraction
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests" / "cgal"))
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

# rational rotations (Pythagorean triples) keep the ellipses exact
ROTATIONS = [(Fraction(1), Fraction(0)), (Fraction(3, 5), Fraction(4, 5)), (Fraction(5, 13), Fraction(12, 13)),
             (Fraction(8, 17), Fraction(15, 17)), (Fraction(4, 5), Fraction(-3, 5)), (Fraction(0), Fraction(1))]


def random_ellipses(n: int, seed: int):
    """n ellipses with disjoint circumscribed discs (hence disjoint), exact rational coefficients."""
    from curvedvoronoi.runtime.sites.conic import Conic

    rng = random.Random(seed)
    side = 8.0 * math.sqrt(n)
    placed = []
    out = []
    while len(out) < n:
        cx = Fraction(round(rng.uniform(0, side) * 64), 64)
        cy = Fraction(round(rng.uniform(0, side) * 64), 64)
        a = Fraction(round(rng.uniform(1.0, 3.0) * 16), 16)
        b = a * Fraction(round(rng.uniform(0.3, 0.9) * 16), 16)
        if any(math.hypot(float(cx) - x, float(cy) - y) <= float(a) + r + 0.05 for x, y, r in placed):
            continue
        c, s = rng.choice(ROTATIONS)
        A = b * b * c * c + a * a * s * s
        B = 2 * c * s * (b * b - a * a)
        C = b * b * s * s + a * a * c * c
        D = -2 * A * cx - B * cy
        E = -2 * C * cy - B * cx
        F = A * cx * cx + B * cx * cy + C * cy * cy - a * a * b * b
        out.append(Conic.from_coefficients(A, B, C, D, E, F))
        placed.append((float(cx), float(cy), float(a)))
    return out


def run_case(kind: str, n: int, seed: int, verify: bool) -> dict:
    import resource

    import cgal_peer
    from threadpoolctl import threadpool_info

    from curvedvoronoi.runtime.voronoi.construction import voronoi

    sites = cgal_peer.random_disjoint_circles(n, seed) if kind == "circles" else random_ellipses(n, seed)
    t0, c0 = time.perf_counter(), time.process_time()
    d = voronoi(sites, certify=False)
    t1, c1 = time.perf_counter(), time.process_time()
    out = {"kind": kind, "n": n, "seconds": t1 - t0, "cpu_seconds": c1 - c0, "vertices": len(d.vertices), "edges": len(d.edges),
           "vertices_certified": sum(v.certified for v in d.vertices),
           "problems": [p for p in d.problems if "certify=False" not in p][:3],
           "rounds": d.stats.get("rounds"), "samples": d.stats.get("samples"),
           "stages": d.stats.get("seconds"), "delaunay_edges": d.delaunay_edges(),
           "threadpools": [(p["internal_api"], p["num_threads"]) for p in threadpool_info()]}
    if verify:
        from curvedvoronoi.runtime.voronoi.verify import verify as verify_fn

        t2 = time.perf_counter()
        cert = verify_fn(d, [d.sites[i] for i in range(len(d.sites))])
        out["verify_seconds"] = time.perf_counter() - t2
        out["verified"] = bool(cert.ok)
    out["peak_rss_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--case", nargs=4, metavar=("KIND", "N", "SEED", "VERIFY"))
    ap.add_argument("--quick", action="store_true", help="small sizes only")
    args = ap.parse_args()
    if args.case:
        kind, n, seed, ver = args.case
        print(json.dumps(run_case(kind, int(n), int(seed), ver == "1")))
        return
    import cgal_peer

    circles = [(100, True), (1000, True), (10000, False)] if not args.quick else [(100, True), (1000, False)]
    ellipses = [(32, True), (128, False), (512, False), (2000, False)] if not args.quick else [(32, True)]
    rows = []
    for kind, cases in (("circles", circles), ("ellipses", ellipses)):
        for n, ver in cases:
            seed = 1
            res = subprocess.run([sys.executable, __file__, "--case", kind, str(n), str(seed), "1" if ver else "0"],
                                 capture_output=True, text=True, env=dict(os.environ, OPENBLAS_NUM_THREADS="1"))
            if res.returncode != 0:
                rows.append({"kind": kind, "n": n, "error": res.stderr.strip().splitlines()[-1]})
                continue
            r = json.loads(res.stdout.strip().splitlines()[-1])
            if kind == "circles":
                try:
                    edges, sec, hidden = cgal_peer.delaunay_edges(cgal_peer.random_disjoint_circles(n, seed))
                    r["cgal_seconds"] = sec
                    r["cgal_same"] = [list(e) for e in edges] == r["delaunay_edges"]
                except cgal_peer.PeerMissing as exc:
                    r["cgal_seconds"] = None
                    r["cgal_same"] = str(exc)
            rows.append(r)
            print(kind, n, {k: v for k, v in r.items() if k != "delaunay_edges"}, file=sys.stderr)
    lines = [f"## bench_voronoi {time.strftime('%Y-%m-%d %H:%M')}  OPENBLAS_NUM_THREADS=1  "
             f"threadpools={rows[0].get('threadpools')}  cpus={os.cpu_count()}  load={os.getloadavg()[0]:.1f}",
             "",
             "Construction = `voronoi(sites, certify=False)` (sampling, qhull Delaunay, walks, proved vertices, "
             "edge polylines); verify = `runtime.voronoi.verify.verify` on its output; CGAL = "
             "Apollonius_graph_2 insertion only (filtered exact predicates, g++ -O2). One process per case; "
             "peak RSS includes the imports. Wall times are noisy when other jobs share the machine (see load); "
             "CPU s is the construction's process time.",
             "",
             "| sites | N | construction s (wall) | CPU s | CPU µs/site | rounds | samples | vertices (proved) | "
             "verify s | CGAL s | ratio (wall) | Delaunay graph = CGAL | peak RSS MB | problems |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if "error" in r:
            lines.append(f"| {r['kind']} | {r['n']} | error: {r['error']} ||||||||||||")
            continue
        cg = r.get("cgal_seconds")
        ratio = f"{r['seconds'] / cg:.0f}x" if cg else "-"
        lines.append(
            f"| {r['kind']} | {r['n']} | {r['seconds']:.3f} | {r['cpu_seconds']:.3f} | "
            f"{1e6 * r['cpu_seconds'] / r['n']:.0f} | {r['rounds']} | "
            f"{r['samples']} | {r['vertices']} ({r['vertices_certified']}) | "
            f"{r.get('verify_seconds', float('nan')):.2f}{' ok' if r.get('verified') else (' not ok' if 'verified' in r else '')} | "
            f"{cg if cg is None else f'{cg:.4f}'} | {ratio} | {r.get('cgal_same', '-')} | {r['peak_rss_mb']:.0f} | "
            f"{'; '.join(r['problems']) or '-'} |")
    text = "\n".join(lines) + "\n"
    print(text)
    out = ROOT / "bench" / "results" / "voronoi.md"
    out.parent.mkdir(exist_ok=True)
    with open(out, "a") as fh:
        fh.write(text + "\n")


if __name__ == "__main__":
    main()
