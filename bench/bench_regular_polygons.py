"""Medial axes of regular polygons with float coordinates (cos/sin vertices, shapely buffers).

Their true diagrams have vertex clusters ~10⁻¹⁵ across at the centre
(runtime/segments/near_degenerate.py).  Prints one row per shape: sides, certified, edges,
wall seconds (after one warm-up call), and the problems' count.

    OPENBLAS_NUM_THREADS=1 .venv/bin/python bench/bench_regular_polygons.py [--sweep]

``--sweep`` adds n = 4..12 at 4 rotations, scales 1 and 1000, offsets 0 and (5e5, 5e5/3).
"""
from __future__ import annotations

import argparse
import time

import numpy as np


def shapes(sweep: bool):
    from shapely.geometry import Point

    for n in (4, 5, 6, 7, 8, 12):
        ts = np.linspace(0, 2 * np.pi, n, endpoint=False) + 0.3
        yield f"{n}-gon cos/sin, rotation 0.3", [(np.cos(t), np.sin(t)) for t in ts]
    for q in (4, 8):
        for r, c in ((5, (0, 0)), (1000, (5e5, 4e6))):
            yield f"Point{c}.buffer({r}, {q})", list(Point(*c).buffer(r, q).exterior.coords)[:-1]
    for n in (6, 8):
        ts = np.linspace(0, 2 * np.pi, n, endpoint=False) + 0.3
        yield (f"{n}-gon with a 0.3-scaled hole", ([(np.cos(t), np.sin(t)) for t in ts],
                                                   [(0.3 * np.cos(t), 0.3 * np.sin(t)) for t in ts[::-1]]))
    if sweep:
        for scale, off in ((1, 0.0), (1000, 0.0), (1, 5e5), (1000, 5e5)):
            for n in range(4, 13):
                for rot in (0.0, 0.3, 1.1, 2.0):
                    ts = np.linspace(0, 2 * np.pi, n, endpoint=False) + rot
                    yield (f"{n}-gon scale {scale} offset {off:g} rotation {rot}",
                           [(off + scale * np.cos(t), off / 3 + scale * np.sin(t)) for t in ts])


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--sweep", action="store_true")
    args = ap.parse_args()
    import curvedvoronoi as cv

    cv.medial_axis([(0, 0), (1, 0), (0, 1)])          # imports and caches
    rows, total, bad = [], 0.0, 0
    for name, pts in shapes(args.sweep):
        t0 = time.perf_counter()
        if isinstance(pts, tuple):                     # an outer ring and a hole
            from shapely.geometry import Polygon

            m = cv.medial_axis(Polygon(*pts[:1], [pts[1]]))
            pts = pts[0] + pts[1]
        else:
            m = cv.medial_axis(pts)
        dt = time.perf_counter() - t0
        total += dt
        bad += not m.certified
        rows.append((name, len(pts), m.certified, len(m.edges), dt, len(m.problems)))
        if not args.sweep or not m.certified or "cos/sin" in name or "buffer" in name or "hole" in name:
            print(f"| {name} | {len(pts)} | {m.certified} | {len(m.edges)} | {dt:.2f} | {len(m.problems)} |", flush=True)
    print(f"shapes {len(rows)}, not certified {bad}, total wall {total:.1f} s, worst {max(r[4] for r in rows):.2f} s")


if __name__ == "__main__":
    main()
