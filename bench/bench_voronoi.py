"""Benchmark of the Voronoi diagram construction (runtime/voronoi/construction.py).

Rows: random disjoint circles (N = 100, 1000, 10000) against CGAL's Apollonius_graph_2 in the
same run (tests/cgal/apollonius_edges.cpp, built with g++ -O2; needs libcgal-dev); deletion of 10
random sites, one after the other, from 1000 circles (``Diagram.delete_site``, each result's
Delaunay graph compared with CGAL's graph of the remaining circles); random disjoint ellipses
(N = 32, 128, 512, 2000); identical ellipses (same axes and rotation) on a jittered grid and
axis-aligned ellipses with random axes (non-generic inputs, N = 128, 512); mixed conics
(ellipses, circles, points, two parabolas and a hyperbola, N = 100).  Each case runs in a fresh
subprocess (peak RSS = ru_maxrss of that process, imports included); construction time is
certify=False; the verifier (runtime.voronoi.verify.certificate) is timed separately where affordable.
"triple solves" = local vertex proofs (one Newton + Krawczyk per vertex candidate cluster);
"full triple solves" = exact solves of all the vertices of a triple (the circle fallback of thesis
§3.1.3, used when the float filter cannot decide).  bench/results/voronoi_per_site.png plots the
CPU time per site against N.

Run:  python bench/bench_voronoi.py [--quick]      (writes bench/results/voronoi.md and the PNG)
      python bench/bench_voronoi.py --circles 10000 30000 [--seed 0]   (circles only, built and verified)
Memory: "kB/site above input" is (peak RSS − RSS once the sites are made) / N, after the build
and (in brackets) after the verification.
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
sys.path.insert(0, str(ROOT / "tests"))
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

from scenes import ROTATIONS, random_ellipses  # noqa: E402  (the scenes of the tests: tests/scenes.py)


def grid_ellipses(n: int, seed: int):
    """n identical ellipses (semi-axes 2 and 6/5, rotation (3/5, 4/5)) centred on a square grid of
    step 6 with a jitter of at most 1/2 in each coordinate: disjoint (circumscribed discs of radius
    2 at distance ≥ 5), non-generic (every triple is made of translates of one ellipse)."""
    from curvedvoronoi.runtime.sites.conic import Conic

    rng = random.Random(seed)
    side = math.ceil(math.sqrt(n))
    out = []
    for k in range(n):
        gx, gy = k % side, k // side
        cx = 6 * gx + Fraction(rng.randint(-32, 32), 64)
        cy = 6 * gy + Fraction(rng.randint(-32, 32), 64)
        out.append(Conic.ellipse(centre=(cx, cy), axes=(Fraction(2), Fraction(6, 5)),
                               rotation=(Fraction(3, 5), Fraction(4, 5))))
    return out


def axis_aligned_ellipses(n: int, seed: int):
    """n random disjoint ellipses with random semi-axes and rotation 0 (axes parallel to x and y)."""
    return random_ellipses(n, seed, rotations=[(Fraction(1), Fraction(0))])


def mixed_conics(n: int, seed: int):
    """About n disjoint sites: two parabolas (opening up from y = side + 4 and down from y = −4, p = 3)
    and a hyperbola (centre (h, h), h = side/2, semi-axes h + 4, branches beyond x = −4 and x = side
    + 4) around a square of side 8√n holding random ellipses, circles and points (a fifth each of
    circles and points), kept only when their bounding disc stays 1/2 away from every other site.
    The parabolas grow quadratically and the hyperbola's branches linearly (slope 1): disjoint."""
    from curvedvoronoi.runtime.predicates.circles import Circle, Point
    from curvedvoronoi.runtime.sites.conic import Conic
    from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry

    rng = random.Random(seed)
    side = 8.0 * math.sqrt(n)
    h = Fraction(round(side / 2))
    unbounded = [Conic.parabola(vertex=(h, 2 * h + 4), p=3, rotation=(0, 1)),
                 Conic.parabola(vertex=(h, -4), p=3, rotation=(0, -1)),
                 Conic.hyperbola(centre=(h, h), axes=(h + 4, h + 4), rotation=(1, 0))]
    geo = [site_geometry(u) for u in unbounded]
    out, placed = list(unbounded), []
    import numpy as np

    while len(out) < n:
        cx = Fraction(round(rng.uniform(0, side) * 64), 64)
        cy = Fraction(round(rng.uniform(0, side) * 64), 64)
        u = rng.random()
        r = 0.0 if u < 0.2 else float(Fraction(round(rng.uniform(0.5, 2.5) * 16), 16))
        if any(math.hypot(float(cx) - x, float(cy) - y) <= r + rr + 0.5 for x, y, rr in placed):
            continue
        if any(g.distance(np.array([[float(cx), float(cy)]]))[0] <= r + 0.5 for g in geo):
            continue
        if u < 0.2:
            out.append(Point(cx, cy))
        elif u < 0.4:
            out.append(Circle(cx, cy, Fraction(r) ** 2))
        else:
            a = Fraction(r)
            b = a * Fraction(round(rng.uniform(0.3, 0.9) * 16), 16)
            c, s = rng.choice(ROTATIONS)
            out.append(Conic.ellipse(centre=(cx, cy), axes=(a, b), rotation=(c, s)))
        placed.append((float(cx), float(cy), r))
    return out


def make_sites(kind: str, n: int, seed: int):
    import cgal_peer

    if kind in ("circles", "circles-delete"):
        return cgal_peer.random_disjoint_circles(n, seed)
    return {"ellipses": random_ellipses, "ellipses-grid": grid_ellipses, "ellipses-axis": axis_aligned_ellipses,
            "mixed": mixed_conics}[kind](n, seed)


def run_case(kind: str, n: int, seed: int, verify: bool) -> dict:
    import resource

    from threadpoolctl import threadpool_info

    from curvedvoronoi.runtime.voronoi.construction import voronoi

    sites = make_sites(kind, n, seed)
    base = max(resident_mb(), resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024)
    t0, c0 = time.perf_counter(), time.process_time()
    d = voronoi(sites, certify=False)
    t1, c1 = time.perf_counter(), time.process_time()
    build_peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    out = {"kind": kind, "n": n, "seconds": t1 - t0, "cpu_seconds": c1 - c0, "vertices": len(d.vertices), "edges": len(d.edges),
           "vertices_certified": sum(v.certified for v in d.vertices),
           "problems": [p for p in d.problems if "certify=False" not in p][:3],
           "rounds": d.stats.get("rounds"), "samples": d.stats.get("samples"),
           "triple_solves": d.stats.get("triple_solves", 0), "full_triple_solves": d.stats.get("full_triple_solves", 0),
           "stages": d.stats.get("seconds"), "delaunay_edges": d.delaunay_edges(),
           "threadpools": [(p["internal_api"], p["num_threads"]) for p in threadpool_info()]}
    if kind == "circles-delete":
        import cgal_peer

        rng = random.Random(seed)
        alive = list(range(n))
        times, same, how = [], [], []
        for _ in range(10):
            k = rng.randrange(len(alive))
            c2 = time.process_time()
            d = d.delete_site(k, certify=False)
            times.append(time.process_time() - c2)
            alive.pop(k)
            how.append(d.stats.get("deletion"))
            rest = [sites[i] for i in alive]
            try:
                edges, _, _ = cgal_peer.delaunay_edges(rest)
                same.append([list(e) for e in edges] == [list(e) for e in d.delaunay_edges()])
            except cgal_peer.PeerMissing:
                same.append(None)
            if any(not v.certified for v in d.vertices) or [p for p in d.problems if "certify=False" not in p]:
                out["problems"] = [p for p in d.problems if "certify=False" not in p][:3] or ["unproved vertex"]
        out.update(delete_cpu_seconds=times, delete_same_as_cgal=same, delete_how=how,
                   vertices=len(d.vertices), vertices_certified=sum(v.certified for v in d.vertices),
                   edges=len(d.edges), rounds=d.stats.get("rounds"), samples=d.stats.get("samples"),
                   triple_solves=d.stats.get("triple_solves", 0),
                   full_triple_solves=d.stats.get("full_triple_solves", 0))
        out.pop("delaunay_edges")
    if verify:
        from curvedvoronoi.runtime.voronoi.verify.certificate import verify as verify_fn

        t2 = time.perf_counter()
        c2 = time.process_time()
        cert = verify_fn(d, [d.sites[i] for i in range(len(d.sites))])
        out["verify_seconds"] = time.perf_counter() - t2
        out["verify_cpu_seconds"] = time.process_time() - c2
        out["verified"] = bool(cert.ok)
    out["peak_rss_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    out["input_rss_mb"] = base
    out["build_kb_per_site"] = (build_peak - base) * 1024 / n
    out["peak_kb_per_site"] = (out["peak_rss_mb"] - base) * 1024 / n
    return out


def resident_mb() -> float:
    """Resident set of this process now (Linux /proc; else 0)."""
    import resource

    try:
        with open("/proc/self/statm") as fh:
            return int(fh.read().split()[1]) * resource.getpagesize() / 2 ** 20
    except OSError:
        return 0.0


def per_site_plot(rows, path):
    """CPU µs per site against N (log x) for the circle and ellipse rows."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4))
    for kind, mark in (("circles", "o-"), ("ellipses", "s-"), ("ellipses-grid", "^--"), ("ellipses-axis", "v--")):
        pts = sorted((r["n"], 1e6 * r["cpu_seconds"] / r["n"]) for r in rows if r.get("kind") == kind and "error" not in r)
        if pts:
            ax.plot(*zip(*pts), mark, label=kind)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("N (sites)")
    ax.set_ylabel("construction CPU µs per site")
    ax.set_title("voronoi(sites, certify=False), one core")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(loc="center left")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--case", nargs=4, metavar=("KIND", "N", "SEED", "VERIFY"))
    ap.add_argument("--quick", action="store_true", help="small sizes only")
    ap.add_argument("--only", nargs="*", help="run only these kinds (no PNG)")
    ap.add_argument("--circles", nargs="*", type=int, metavar="N",
                    help="only random circles of these sizes, built and verified (no PNG)")
    ap.add_argument("--seed", type=int, default=1, help="seed of the random scenes (default 1)")
    args = ap.parse_args()
    if args.case:
        kind, n, seed, ver = args.case
        print(json.dumps(run_case(kind, int(n), int(seed), ver == "1")))
        return
    import cgal_peer

    if args.quick:
        plan = [("circles", 100, True), ("circles", 1000, False), ("circles-delete", 1000, False),
                ("ellipses", 32, True), ("ellipses-grid", 128, False), ("ellipses-axis", 128, False),
                ("mixed", 100, False)]
    else:
        plan = [("circles", 100, True), ("circles", 1000, True), ("circles", 10000, False),
                ("circles-delete", 1000, False),
                ("ellipses", 32, True), ("ellipses", 128, False), ("ellipses", 512, False), ("ellipses", 2000, False),
                ("ellipses-grid", 128, False), ("ellipses-grid", 512, False),
                ("ellipses-axis", 128, False), ("ellipses-axis", 512, False), ("mixed", 100, True)]
    if args.only:
        plan = [p for p in plan if p[0] in args.only]
    if args.circles:
        plan = [("circles", n, True) for n in args.circles]
        args.only = ["circles"]
    rows = []
    for kind, n, ver in plan:
        seed = args.seed
        res = subprocess.run([sys.executable, __file__, "--case", kind, str(n), str(seed), "1" if ver else "0"],
                             capture_output=True, text=True, env=dict(os.environ, OPENBLAS_NUM_THREADS="1"))
        if res.returncode != 0:
            rows.append({"kind": kind, "n": n, "error": (res.stderr.strip().splitlines() or ["?"])[-1]})
            continue
        r = json.loads(res.stdout.strip().splitlines()[-1])
        if kind in ("circles", "circles-delete"):
            try:
                edges, sec, hidden = cgal_peer.delaunay_edges(cgal_peer.random_disjoint_circles(n, seed))
                r["cgal_seconds"] = sec
                if kind == "circles":
                    r["cgal_same"] = [list(e) for e in edges] == r["delaunay_edges"]
                else:
                    r["cgal_same"] = all(r["delete_same_as_cgal"])
            except cgal_peer.PeerMissing as exc:
                r["cgal_seconds"] = None
                r["cgal_same"] = str(exc)
        rows.append(r)
        print(kind, n, {k: v for k, v in r.items() if k != "delaunay_edges"}, file=sys.stderr)
    lines = [f"## bench_voronoi {time.strftime('%Y-%m-%d %H:%M')}  seed={args.seed}  OPENBLAS_NUM_THREADS=1  "
             f"threadpools={rows[0].get('threadpools')}  cpus={os.cpu_count()}  load={os.getloadavg()[0]:.1f}",
             "",
             "Construction = `voronoi(sites, certify=False)` (sampling, qhull Delaunay with local Bowyer–Watson "
             "updates in the refinement rounds, walks, proved vertices, edge polylines); verify = "
             "`runtime.voronoi.verify.certificate.verify` on its output; CGAL = Apollonius_graph_2 insertion only (filtered "
             "exact predicates, g++ -O2), same run. One process per case; peak RSS includes the imports. Wall "
             "times are noisy when other jobs share the machine (see load); CPU s is the construction's process "
             "time, and the CPU ratio compares it with CGAL's time. circles-delete: 10 deletions one after the "
             "other from the 1000-circle diagram (`Diagram.delete_site`); its time columns are the mean CPU s "
             "per deletion, rounds to triple solves those of the last deletion, its CGAL s the CGAL build of all "
             "1000 circles, and \"= CGAL\" holds when all 10 "
             "results have CGAL's Delaunay graph of the remaining circles. Triple solves: local vertex proofs "
             "(all rounds); full: exact all-vertex solves of a triple (fallback).",
             "",
             "| sites | N | construction s (wall) | CPU s | CPU µs/site | rounds | samples | vertices (proved) | "
             "triple solves (full) | verify s (CPU s) | CGAL s | ratio wall (CPU) | Delaunay graph = CGAL | peak RSS MB | "
             "kB/site above input: build (with verify) | problems |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if "error" in r:
            lines.append(f"| {r['kind']} | {r['n']} | error: {r['error']} ||||||||||||||")
            continue
        cg = r.get("cgal_seconds")
        if r["kind"] == "circles-delete":
            ts = r["delete_cpu_seconds"]
            wall = cpu = sum(ts) / len(ts)
            ratio = f"{cpu / cg:.2f}x of a build" if cg else "-"
            per_site = f"{1e3 * cpu:.0f} ms per deletion"
        else:
            wall, cpu = r["seconds"], r["cpu_seconds"]
            ratio = f"{wall / cg:.0f}x ({cpu / cg:.0f}x)" if cg else "-"
            per_site = f"{1e6 * cpu / r['n']:.0f}"
        vcpu = f" ({r['verify_cpu_seconds']:.2f})" if "verify_cpu_seconds" in r else ""
        lines.append(
            f"| {r['kind']} | {r['n']} | {wall:.3f} | {cpu:.3f} | {per_site} | {r['rounds']} | "
            f"{r['samples']} | {r['vertices']} ({r['vertices_certified']}) | "
            f"{r.get('triple_solves', 0)} ({r.get('full_triple_solves', 0)}) | "
            f"{r.get('verify_seconds', float('nan')):.2f}"
            f"{vcpu}"
            f"{' ok' if r.get('verified') else (' not ok' if 'verified' in r else '')} | "
            f"{cg if cg is None else f'{cg:.4f}'} | {ratio} | {r.get('cgal_same', '-')} | {r['peak_rss_mb']:.0f} | "
            f"{r.get('build_kb_per_site', float('nan')):.1f} ({r.get('peak_kb_per_site', float('nan')):.1f}) | "
            f"{'; '.join(r['problems']) or '-'} |")
    if not args.only:
        per_site_plot(rows, ROOT / "bench" / "results" / "voronoi_per_site.png")
        lines += ["", "Per-site CPU time against N: `bench/results/voronoi_per_site.png`."]
    text = "\n".join(lines) + "\n"
    print(text)
    out = ROOT / "bench" / "results" / "voronoi.md"
    out.parent.mkdir(exist_ok=True)
    with open(out, "a") as fh:
        fh.write(text + "\n")


if __name__ == "__main__":
    main()
