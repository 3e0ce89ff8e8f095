"""Regular inputs that floats mislead (issue: "regular inputs fail"): rotated grids of points,
nearly collinear points, grids of rotated translates of one ellipse, a row of translates with a
far vertex, circles inside an ellipse, nested ellipses, regular star polygons (segments), the
medial axis of a disc.  Each row: certified or not,
wall and CPU seconds, vertices and edges.  One BLAS thread (threadpoolctl inside the calls).

    OPENBLAS_NUM_THREADS=1 python bench/bench_regular_inputs.py
"""
from __future__ import annotations

import os
import time

import numpy as np

import curvedvoronoi as cv


def rotated_grid(n, angle, r=None):
    c, s = np.cos(angle), np.sin(angle)
    pts = [(c * x - s * y, s * x + c * y) for x in range(n) for y in range(n)]
    return pts if r is None else [(x, y, r) for x, y in pts]


def star_polygon(n, R=2.0, r=0.8):
    """The closed regular star with n tips at radius R and n reflex corners at radius r (cos/sin
    floats: its mirror symmetries make tied vertices that floats leave nearly tied)."""
    pts = [((R if k % 2 == 0 else r) * np.cos(np.pi * k / n), (R if k % 2 == 0 else r) * np.sin(np.pi * k / n))
           for k in range(2 * n)]
    pts = [(float(x), float(y)) for x, y in pts]
    return [cv.Segment(pts[k], pts[(k + 1) % len(pts)]) for k in range(len(pts))]


def ellipse_grid(n, degrees):
    return [cv.Conic.ellipse((10 * x, 10 * y), (3, 2), degrees=degrees) for x in range(n) for y in range(n)]


CASES = {
    "points: 8 × 8 grid rotated by 0.3 rad": lambda: cv.voronoi(rotated_grid(8, 0.3), progress=False),
    "points: 20 × 20 grid rotated by 1.1 rad": lambda: cv.voronoi(rotated_grid(20, 1.1), progress=False),
    "points: three, 1e-14 off a line": lambda: cv.voronoi([(0, 0), (1, 1e-14), (2, 0)], progress=False),
    "points: four, 1e-12 off a line": lambda: cv.voronoi([(0, 0), (1, 1e-12), (2, 0), (1, 5)], progress=False),
    "circles: 8 × 8 grid rotated by 0.3 rad, r = 0.2": lambda: cv.voronoi(rotated_grid(8, 0.3, 0.2), progress=False),
    "ellipses: 3 × 3 translates rotated 10°": lambda: cv.voronoi(ellipse_grid(3, 10), progress=False),
    "ellipses: 3 × 3 translates rotated 45°": lambda: cv.voronoi(ellipse_grid(3, 45), progress=False),
    "ellipses: 10 × 10 translates rotated 30°": lambda: cv.voronoi(ellipse_grid(10, 30), progress=False),
    "ellipses: translates at (0,0), (7,0), (13,1/4)": lambda: cv.voronoi(
        [cv.Conic.ellipse(c, (2, 1)) for c in ((0, 0), (7, 0), (13, 0.25))], progress=False),
    "circles (2,0,1), (-3,1,1.5) inside ellipse 10 × 6": lambda: cv.voronoi(
        [cv.Conic.ellipse((0, 0), (10, 6)), (2, 0, 1), (-3, 1, 1.5)], progress=False),
    "circle (2,0,1) alone inside ellipse 10 × 6": lambda: cv.voronoi(
        [cv.Conic.ellipse((0, 0), (10, 6)), (2, 0, 1)], progress=False),
    "nested ellipses: 3 × 1.5 at (1, 0.5) rotated 20° inside 10 × 6": lambda: cv.voronoi(
        [cv.Conic.ellipse((0, 0), (10, 6)), cv.Conic.ellipse((1, 0.5), (3, 1.5), degrees=20)], progress=False),
    "ellipse and circle inside ellipse 10 × 6 rotated 30° (a vertex beyond the reach)": lambda: cv.voronoi(
        [cv.Conic.ellipse((0, 0), (10, 6), degrees=30), cv.Conic.ellipse((-2, 1), (2, 1), degrees=-40),
         (4, -1, 1)], progress=False),
    "circle (0,0,1) alone inside ellipse 10 × 4": lambda: cv.voronoi(
        [cv.Conic.ellipse((0, 0), (10, 4)), (0, 0, 1)], progress=False),
    "point (1, 0) inside ellipse 10 × 5": lambda: cv.voronoi(
        [cv.Conic.ellipse((0, 0), (10, 5)), (1, 0)], progress=False),
    "arcs: three tangent to one side of the hull (radii 1, 2, 3)": lambda: cv.voronoi(
        [cv.Arc.circular((10 * k, r), r, 200, 340) for k, r in enumerate((1, 2, 3))]
        + [cv.Segment((5, 30), (15, 31))], progress=False),
    "segments: regular 5-star (10 sides, R = 2, r = 0.8)": lambda: cv.voronoi(star_polygon(5), progress=False),
    "segments: regular 8-star (16 sides, R = 2, r = 0.8)": lambda: cv.voronoi(star_polygon(8), progress=False),
    "medial axis of a disc": lambda: cv.medial_axis(cv.Circle.from_radius(3, -2, 2.5)),
}


def main():
    print(f"load {open('/proc/loadavg').read().split()[:3]}, OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS')}")
    print("| input | certified | wall s | CPU s | vertices | edges | first problem |")
    print("|---|---|---|---|---|---|---|")
    for name, run in CASES.items():
        t, c = time.perf_counter(), time.process_time()
        try:
            d = run()
            row = (d.certified, len(d.vertices), len(d.edges), (str(d.problems[0])[:80] if d.problems else ""))
        except Exception as e:                     # a traceback is a result here
            row = (f"error: {type(e).__name__}", "-", "-", str(e)[:80])
        print(f"| {name} | {row[0]} | {time.perf_counter() - t:.2f} | {time.process_time() - c:.2f} | "
              f"{row[1]} | {row[2]} | {row[3]} |", flush=True)


if __name__ == "__main__":
    main()
