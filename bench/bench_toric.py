"""The toric null space in circle space (runtime/solve/toric.py) on many random triples.

For each random rigid configuration (tests/test_locator.random_configuration: rational rotations,
positions in [-3, 3]², kinds E ellipse, H hyperbola, P parabola, C circle) and each spread factor s
(the centres multiplied by s, the sites kept: small sites far apart):

* toric route alone (``generalised_vertices(..., solver="toric")``): does it return the bound's
  number of solutions, and in what time;
* its real solutions against the exact real roots of the rational system (msolve, independent):
  equal numbers and one solution per isolating box (1e-6 relative);
* the locator's default route: time, certified, complete, and which solver answered (weighted null
  space, toric null space, exact msolve).

    OPENBLAS_NUM_THREADS=1 python bench/bench_toric.py              # 4 mixes x 10 seeds x spreads 1, 10
    OPENBLAS_NUM_THREADS=1 python bench/bench_toric.py --seeds 3     # quicker

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


def spread(conics, s: int):
    """The same sites with centres (translations) multiplied by s."""
    out = []
    for c in conics:
        a, b, cc, d, e, f = c.coefficients
        # translate by (s − 1)·t, t the centre / vertex of the canonical frame
        fr = c.exact_frame               # rational rotations: exact translation
        tx, ty = fr.tx, fr.ty
        dx, dy = (s - 1) * tx, (s - 1) * ty
        # q(x − dx, y − dy)
        d2 = d - 2 * a * dx - b * dy
        e2 = e - b * dx - 2 * cc * dy
        f2 = f + a * dx * dx + b * dx * dy + cc * dy * dy - d * dx - e * dy
        out.append(Conic.from_coefficients(a, b, cc, d2, e2, f2))
    return out


def route_of(notes) -> str:
    text = " ".join(notes)
    if "exact real solutions" in text or "exact route" in text:
        return "exact"
    if "toric" in text:
        return "toric"
    return "weighted"


def main():
    from test_locator import random_configuration

    ap = argparse.ArgumentParser()
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--spreads", default="1,10")
    args = ap.parse_args()
    spreads = [int(s) for s in args.spreads.split(",")]
    load0 = os.getloadavg()[0]
    rows = defaultdict(list)
    for mix in MIXES:
        for seed in range(200, 200 + args.seeds):
            base = random_configuration(mix, seed)
            for s in spreads:
                cs = spread(base, s) if s != 1 else base
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
             f"{os.environ.get('OPENBLAS_NUM_THREADS')}, seeds 200..{199 + args.seeds}, spreads {spreads})", "",
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
    text = "\n".join(lines)
    print(text)
    with open(ROOT / "bench" / "results" / "toric.md", "a") as fh:
        fh.write(text + "\n")


if __name__ == "__main__":
    main()
