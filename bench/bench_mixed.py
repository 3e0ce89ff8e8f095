"""Benchmark: mixed volume of the cyclic-7 system (a classical polyhedral-homotopy test case,
mixed volume 924; Björck–Fröberg / Verschelde's PHCpack demos) with the exact lifting and mixed
cells of ``precompute.mixed`` (thesis §3.3.1, Thm 3.3.13).

    python bench/bench_mixed.py     # writes bench/results/mixed.md

The value 924 is asserted (a known fact); the time is recorded, not asserted.
"""
from __future__ import annotations

import datetime
import pathlib
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from curvedvoronoi.precompute.mixed import mixed_volume  # noqa: E402


def cyclic(n: int) -> list[list[tuple[int, ...]]]:
    """Supports of the cyclic-n system: sum over i of the products of k consecutive x's, k < n,
    and x_1...x_n - 1."""
    sup = []
    for k in range(1, n):
        sup.append([tuple(1 if (j - i) % n < k else 0 for j in range(n)) for i in range(n)])
    sup.append([tuple([1] * n), tuple([0] * n)])
    return sup


def main() -> None:
    rows = []
    for n, expected in ((5, 70), (6, 156), (7, 924)):
        t = time.perf_counter()
        mv = mixed_volume(cyclic(n))
        dt = time.perf_counter() - t
        assert mv == expected, (n, mv)
        rows.append(f"| cyclic-{n} | {mv} | {dt:.2f} |")
    table = "\n".join([f"## {datetime.date.today()} (one process)", "",
                       "| system | mixed volume | seconds |", "|---|---|---|", *rows, ""])
    print(table)
    (ROOT / "bench" / "results" / "mixed.md").write_text(table)


if __name__ == "__main__":
    main()
