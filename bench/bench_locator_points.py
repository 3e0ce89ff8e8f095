"""The conflict locator with point sites among conics (runtime.predicates.locator, the diagram route).

Random four-site sets: C1..C3 of the kinds of a mix (P point, C circle, E ellipse, H hyperbola) at
rational positions in [-3, 3]² times ``spread``, the conics from tests/test_locator.random_configuration,
C4 an ellipse.  Counts the answers certified and complete, those refused because sites meet (a
one-line error), and the times.  Appends a Markdown table to bench/results/locator_points.md.

    OPENBLAS_NUM_THREADS=1 python bench/bench_locator_points.py [--seeds 20] [--spreads 1,10]
"""
from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from fractions import Fraction
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))

import numpy as np  # noqa: E402

import curvedvoronoi as cv  # noqa: E402

MIXES = ["PPE", "PEE", "PCE", "PPP", "PEH"]


def sites_of(mix: str, seed: int, spread: int, rng) -> list:
    from test_locator import random_configuration

    base = random_configuration("EHEE" if "H" in mix else "EEEE", 2000 + seed, spread=spread)

    def coord():
        return Fraction(int(rng.integers(-30, 31)) * spread, 10)

    out = []
    for k, ch in enumerate(mix):
        if ch == "P":
            out.append(cv.Point(coord(), coord()))
        elif ch == "C":
            out.append(cv.Conic.circle(centre=(coord(), coord()), radius=Fraction(1, 2)))
        else:
            out.append(base[k])
    return out + [base[3]]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=20)
    ap.add_argument("--spreads", default="1,10")
    args = ap.parse_args()
    load0 = os.getloadavg()[0]
    lines = [f"## Points among conics, seeds 0..{args.seeds - 1} ({time.strftime('%Y-%m-%d %H:%M')}, "
             f"OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS')})", "",
             f"Command: `python bench/bench_locator_points.py --seeds {args.seeds} --spreads {args.spreads}`", "",
             "| C1 C2 C3 | spread | certified & complete | refused (sites meet) | median s | max s |",
             "|---|---:|---|---:|---:|---:|"]
    for spread in (int(s) for s in args.spreads.split(",")):
        rng = np.random.default_rng(5)
        for mix in MIXES:
            ok, refused, ts = 0, 0, []
            for seed in range(args.seeds):
                sites = sites_of(mix, seed, spread, rng)
                t0 = time.perf_counter()
                try:
                    res = cv.locate_conflicts(*sites)
                except ValueError:
                    refused += 1
                    continue
                ts.append(time.perf_counter() - t0)
                ok += bool(res.certified and res.complete)
            lines.append(f"| {mix} | {spread} | {ok}/{len(ts)} | {refused} | "
                         f"{statistics.median(ts) if ts else float('nan'):.3f} | {max(ts) if ts else float('nan'):.3f} |")
    lines += ["", f"Cold calls except the first of the process; load average {load0:.1f} at the start, "
              f"{os.getloadavg()[0]:.1f} at the end ({os.cpu_count()} cores shared with other jobs).  Not "
              "complete: hyperbolas (the verifier does not prove their tails) and points nested in an "
              "ellipse whose loop crosses the ellipse's medial axis (a corner).", ""]
    text = "\n".join(lines)
    print(text)
    out = ROOT / "bench" / "results" / "locator_points.md"
    with open(out, "a") as fh:
        fh.write(text + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
