"""The toric null space in circle space (runtime/solve/toric.py) on many random triples.

For each random rigid configuration (tests/test_locator.random_configuration: rational rotations,
positions in [-3, 3]², kinds E ellipse, H hyperbola, P parabola, C circle) and each spread factor s
(the centres multiplied by s, the sites kept: small sites far apart)

(``random_configuration(kinds, seed, spread=s)``)

* toric route alone (``generalised_vertices(..., solver="toric")``): does it return the bound's
  number of solutions, and in what time;
* its real solutions against the exact real roots of the rational system (msolve, independent):
  equal numbers and one solution per isolating box (1e-6 relative);
* the locator's default route: time, certified, complete, and which solver answered (weighted null
  space, toric null space, exact msolve).

    OPENBLAS_NUM_THREADS=1 python bench/bench_toric.py              # 6 mixes x 10 seeds x spreads 1, 10
    OPENBLAS_NUM_THREADS=1 python bench/bench_toric.py --seeds 3     # quicker
    OPENBLAS_NUM_THREADS=1 python bench/bench_toric.py --first-seed 300 --seeds 8 --spreads 1000  # held-out seeds
    OPENBLAS_NUM_THREADS=1 python bench/bench_toric.py --scene 24    # the triples of a diagram

``--scene N``: N random disjoint ellipses (axes 1–4, rational rotations, centres over a 60 × 60
square, as a diagram produces them); every vertex (i, j, k) of their diagram (runtime.voronoi,
sample-then-refine, an independent construction) is located with a fourth Delaunay neighbour of i:
time, certified, complete, route, and whether the diagram's vertex is one of the locator's
certified vertices (1e-6 relative).

Appends a table to bench/results/toric.md.
"""
from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from collections import Counter, defaultdict
from fractions import Fraction
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))

import numpy as np  # noqa: E402

from curvedvoronoi.runtime.predicates.locator import clear_cache, locate_conflicts  # noqa: E402
from curvedvoronoi.runtime.result import LocatorError  # noqa: E402
from curvedvoronoi.runtime.sites.conic import Conic  # noqa: E402
from curvedvoronoi.runtime.solve.exact import solve_exact  # noqa: E402
from curvedvoronoi.runtime.solve.vertices import CONFIG_TABLE, generalised_vertices  # noqa: E402

MIXES = ["EEEE", "HHHH", "PPPP", "EPHC", "CEEE", "EEPE"]


def route_of(notes) -> str:
    text = " ".join(notes)
    if "exact real solutions" in text or "exact route" in text:
        return "exact"
    if "toric" in text:
        return "toric"
    return "weighted"


ROTS = [(3, 4, 5), (5, 12, 13), (8, 15, 17), (7, 24, 25), (20, 21, 29), (12, 35, 37), (9, 40, 41)]


def scene_ellipses(n: int, seed: int = 1):
    """n disjoint ellipses (bounding discs 1/2 apart), axes in [1, 4], rational rotations, centres
    on the half-integer grid of [0, 60]²."""
    rng = np.random.default_rng(seed)
    out, discs = [], []
    while len(out) < n:
        A = Fraction(int(rng.integers(4, 17)), 4)
        B = Fraction(int(rng.integers(4, 4 * A + 1)), 4)
        c = (Fraction(int(rng.integers(0, 121)), 2), Fraction(int(rng.integers(0, 121)), 2))
        if any((float(c[0]) - x) ** 2 + (float(c[1]) - y) ** 2 < (float(A) + r + 0.5) ** 2 for x, y, r in discs):
            continue
        a, b, h = ROTS[int(rng.integers(len(ROTS)))]
        sg = 1 if rng.random() < 0.5 else -1
        out.append(Conic.ellipse(centre=c, axes=(A, B), rotation=(Fraction(a, h), Fraction(sg * b, h))))
        discs.append((float(c[0]), float(c[1]), float(A)))
    return out


def scene(n: int) -> str:
    from curvedvoronoi.runtime.voronoi.construction import voronoi

    sites = scene_ellipses(n)
    t0 = time.perf_counter()
    dia = voronoi(sites, certify=False)
    t_dia = time.perf_counter() - t0
    nbr = defaultdict(set)
    for i, j in dia.delaunay_edges():
        nbr[i].add(j)
        nbr[j].add(i)
    load0 = os.getloadavg()[0]
    rows = []
    for v in dia.vertices:
        i, j, k = v.sites
        others = sorted(nbr[i] - {j, k}) or sorted(set(range(n)) - {i, j, k})
        cs = [sites[i], sites[j], sites[k], sites[others[0]]]
        clear_cache()
        t0 = time.perf_counter()
        res = locate_conflicts(*cs)
        dt = time.perf_counter() - t0
        found = any(w.certified and abs(w.x - v.x) <= 1e-6 * max(1.0, abs(v.x))
                    and abs(w.y - v.y) <= 1e-6 * max(1.0, abs(v.y)) for w in res.vertices)
        rows.append((dt, res.certified, res.complete, route_of(res.notes), found))
        print(v.sites, others[0], f"{dt:.3f}", res.certified, res.complete, route_of(res.notes), found, flush=True)
    ts = [r[0] for r in rows]
    routes = Counter(r[3] for r in rows)
    lines = [f"## bench_toric.py --scene {n} ({time.strftime('%Y-%m-%d %H:%M')}, OPENBLAS_NUM_THREADS="
             f"{os.environ.get('OPENBLAS_NUM_THREADS')})", "",
             f"{n} disjoint ellipses (axes 1–4, rational rotations, centres over 60 × 60); diagram in {t_dia:.2f} s "
             f"with {len(dia.vertices)} vertices; each vertex's triple located with a fourth Delaunay neighbour "
             "(cold, `clear_cache()` before each call).", "",
             "| triples | median s | max s | certified & complete | diagram vertex among the certified vertices | answered by |",
             "|---:|---:|---:|---|---|---|",
             f"| {len(rows)} | {statistics.median(ts):.3f} | {max(ts):.3f} | {sum(r[1] and r[2] for r in rows)}/{len(rows)} | "
             f"{sum(r[4] for r in rows)}/{len(rows)} | " + ", ".join(f"{k} {v}" for k, v in sorted(routes.items())) + " |",
             "", f"Load average {load0:.1f} at the start, {os.getloadavg()[0]:.1f} at the end.", ""]
    return "\n".join(lines)


def main():
    from test_locator import random_configuration

    ap = argparse.ArgumentParser()
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--first-seed", type=int, default=200, help="seeds first-seed .. first-seed + seeds - 1")
    ap.add_argument("--spreads", default="1,10")
    ap.add_argument("--scene", type=int, default=0, help="locate the triples of a diagram of this many ellipses")
    ap.add_argument("--mixes", default=",".join(MIXES),
                    help="comma-separated site kinds of C1..C4 (E ellipse, H hyperbola, P parabola, C circle)")
    args = ap.parse_args()
    if args.scene:
        _report(scene(args.scene))
        return
    spreads = [int(s) for s in args.spreads.split(",")]
    load0 = os.getloadavg()[0]
    rows = defaultdict(list)
    mixes = args.mixes.split(",")
    if any(len(m) != 4 or set(m) - set("EHPC") for m in mixes):
        ap.error("--mixes: four letters of E, H, P, C per mix, e.g. EEEE,HPPC")
    for mix in mixes:
        for seed in range(args.first_seed, args.first_seed + args.seeds):
            for s in spreads:
                cs = random_configuration(mix, seed, spread=s)
                fams = tuple(sorted({"hyperbola": "ellipse"}.get(c.kind, c.kind) for c in cs[:3]))
                n = CONFIG_TABLE[fams][1] if fams in CONFIG_TABLE else None
                t0 = time.perf_counter()
                try:
                    sol = generalised_vertices(*cs[:3], solver="toric")
                    ok = len(sol.points) == n
                except LocatorError:
                    sol, ok = None, False
                t_toric = time.perf_counter() - t0
                match = None
                if ok:
                    P = sol.points
                    real = P[np.max(np.abs(P.imag) / np.maximum(1.0, np.abs(P.real)), axis=1) < 1e-9].real
                    ex = solve_exact(*cs[:3])
                    match = len(real) == len(ex.boxes)
                    for box in ex.boxes:
                        inside = np.ones(len(real), dtype=bool)
                        for c, (lo, hi) in enumerate(box):
                            lo, hi = float(lo), float(hi)
                            pad = 1e-6 * max(1.0, abs(lo), abs(hi))
                            inside &= (real[:, c] >= lo - pad) & (real[:, c] <= hi + pad)
                        match &= int(inside.sum()) == 1
                clear_cache()
                t0 = time.perf_counter()
                res = locate_conflicts(*cs)
                t_loc = time.perf_counter() - t0
                rows[(mix, s)].append((ok, t_toric, match, t_loc, res.certified, res.complete, route_of(res.notes)))
                print(mix, seed, s, ok, f"{t_toric:.3f}", match, f"{t_loc:.3f}", res.certified, res.complete,
                      route_of(res.notes), flush=True)
    lines = [f"## bench_toric.py ({time.strftime('%Y-%m-%d %H:%M')}, OPENBLAS_NUM_THREADS="
             f"{os.environ.get('OPENBLAS_NUM_THREADS')}, seeds {args.first_seed}..{args.first_seed + args.seeds - 1}, spreads {spreads})", "",
             "| mix | spread | toric: all N solutions | toric median s | real solutions = msolve's | "
             "locator median s | locator max s | certified & complete | answered by |",
             "|---|---:|---|---:|---|---:|---:|---|---|"]
    for (mix, s), rs in rows.items():
        routes = Counter(r[6] for r in rs)
        lines.append(f"| {mix} | {s} | {sum(r[0] for r in rs)}/{len(rs)} | {statistics.median(r[1] for r in rs):.3f} | "
                     f"{sum(bool(r[2]) for r in rs)}/{sum(r[0] for r in rs)} | {statistics.median(r[3] for r in rs):.3f} | "
                     f"{max(r[3] for r in rs):.3f} | {sum(r[4] and r[5] for r in rs)}/{len(rs)} | "
                     + ", ".join(f"{k} {v}" for k, v in sorted(routes.items())) + " |")
    allr = [r for rs in rows.values() for r in rs]
    lines += ["", f"{len(allr)} triples: toric all-N {sum(r[0] for r in allr)}, real roots = msolve's "
              f"{sum(bool(r[2]) for r in allr)} of those; locator certified & complete {sum(r[4] and r[5] for r in allr)}, "
              f"median {statistics.median(r[3] for r in allr):.3f} s, max {max(r[3] for r in allr):.3f} s; "
              f"load average {load0:.1f} at the start, {os.getloadavg()[0]:.1f} at the end.", ""]
    _report("\n".join(lines))


def _report(text: str) -> None:
    """Print a results block and append it to bench/results/toric.md."""
    print(text)
    with open(ROOT / "bench" / "results" / "toric.md", "a") as fh:
        fh.write(text + "\n")


if __name__ == "__main__":
    main()
