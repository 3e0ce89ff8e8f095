"""Benchmark: local Voronoi vertices and conic distance bounds (thesis §5.2, §6.1).

    python bench/bench_vertex.py

Measures, with one BLAS thread:

* ``refine_vertex`` + ``certify_vertex`` per true vertex of the 30 vendored validation cases
  (seed 1e-4 off the expected vertex), grouped by the kinds of the three sites;
* ``certify_vertex`` on circle/point triples (3×3 Krawczyk route);
* ``distance_bounds`` / ``distance`` throughput per conic kind (10 000 random points), with the
  relative gap of the bounds and the number of points that needed the ball route;
* for comparison, ``runtime.certify.conflicts.certify_vertex`` (the locator's certifier: Lagrange
  polynomial foot enclosures) on the same conic vertices.

Prints a Markdown table and writes it to bench/results/vertex.md with the thread settings.
"""
from __future__ import annotations

import datetime
import pathlib
import platform
import statistics
import sys
import time

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402
from threadpoolctl import threadpool_info, threadpool_limits  # noqa: E402

from curvedvoronoi.runtime.certify.conflicts import certify_vertex as locator_certify  # noqa: E402
from curvedvoronoi.runtime.predicates.circles import Circle, Point  # noqa: E402
from curvedvoronoi.runtime.sites.conic import Conic  # noqa: E402
from curvedvoronoi.runtime.validation import load_cases, repository_cases_path  # noqa: E402
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry  # noqa: E402
from curvedvoronoi.runtime.voronoi.vertex import certify_vertex, refine_vertex  # noqa: E402


def ms(v):
    return f"{1e3 * v:.2f}"


def bench_vertices():
    rows = {}
    rng = np.random.default_rng(0)
    for case in load_cases(repository_cases_path()):
        G = [site_geometry(c) for c in case.conics[:3]]
        key = "+".join(sorted(c.kind for c in case.conics[:3]))
        for v in case.vertices:
            e = v.as_floats()
            sc = 1 + abs(e["x"]) + abs(e["y"]) + e["radius"]
            seed = (e["x"] + 1e-4 * sc * rng.normal(), e["y"] + 1e-4 * sc * rng.normal())
            t0 = time.perf_counter()
            r = refine_vertex(G, *seed)
            t1 = time.perf_counter()
            ok = False
            if r is not None:
                pr = certify_vertex(case.conics[:3], G, r[0], r[1])
                ok = pr.certified
            t2 = time.perf_counter()
            t3 = time.perf_counter()
            if all(c.kind != "circle" for c in case.conics[:3]):
                cv = locator_certify(*case.conics[:3], e["x"], e["y"], e["radius"] ** 2)
                t_loc = time.perf_counter() - t3
                loc_ok = cv.proven
            else:
                t_loc, loc_ok = None, None
            rows.setdefault(key, []).append((t1 - t0, t2 - t1, ok, t_loc, loc_ok))
    return rows


def bench_circles():
    rng = np.random.default_rng(1)
    times, ok = [], 0
    n = 0
    from curvedvoronoi.runtime.predicates.circles import voronoi_vertices_circles
    while n < 200:
        sites = []
        for _ in range(3):
            cx, cy = (int(v) for v in rng.integers(-20, 21, size=2))
            r2 = int(rng.integers(0, 4))
            sites.append(Point(cx, cy) if r2 == 0 else Circle(cx, cy, r2))
        try:
            tv = voronoi_vertices_circles(*sites)
        except Exception:  # noqa: BLE001 - identical/intersecting random sites: skip
            continue
        for v in tv.vertices:
            t0 = time.perf_counter()
            pr = certify_vertex(sites, None, v.x, v.y)
            times.append(time.perf_counter() - t0)
            ok += pr.certified
            n += 1
    return times, ok


def bench_bounds():
    out = []
    rng = np.random.default_rng(2)
    P = rng.uniform(-10, 10, size=(10_000, 2))
    for conic in (Conic.ellipse(centre=(1, 2), axes=(3, 1), rotation=("3/5", "4/5")),
                  Conic.hyperbola(centre=(0, 1), axes=(2, 1), rotation=("5/13", "12/13")),
                  Conic.parabola(vertex=(1, -1), p=1, rotation=("8/17", "15/17"))):
        g = site_geometry(conic)
        t0 = time.perf_counter()
        g.distance(P)
        t1 = time.perf_counter()
        lo, hi = g.distance_bounds(P)
        t2 = time.perf_counter()
        far = hi > 0.05
        gap = float(np.max((hi[far] - lo[far]) / hi[far]))
        out.append((conic.kind, t1 - t0, t2 - t1, gap, g.fallbacks))
    return out


def main():
    with threadpool_limits(limits=1):
        t0 = time.perf_counter()
        vrows = bench_vertices()
        ctimes, cok = bench_circles()
        brows = bench_bounds()
        total = time.perf_counter() - t0
    lines = [f"## bench_vertex — {datetime.datetime.now().isoformat(timespec='seconds')}", "",
             f"python {platform.python_version()}, {platform.machine()}; BLAS threads: "
             + ", ".join(f"{i.get('internal_api')}={i.get('num_threads')}" for i in threadpool_info())
             + " (limited to 1 for the run). Other jobs may share the 2 cores: figures are indicative.",
             "", "### Conic vertices of the validation cases (seed 1e-4 off)", "",
             "| sites | vertices | certified | refine median ms | certify median ms | certify max ms "
             "| runtime.certify.conflicts median ms (proved) |",
             "|---|---|---|---|---|---|---|"]
    for key, rs in sorted(vrows.items()):
        loc = [r[3] for r in rs if r[3] is not None]
        lines.append(f"| {key} | {len(rs)} | {sum(r[2] for r in rs)} | {ms(statistics.median(r[0] for r in rs))} "
                     f"| {ms(statistics.median(r[1] for r in rs))} | {ms(max(r[1] for r in rs))} | "
                     + (f"{ms(statistics.median(loc))} ({sum(bool(r[4]) for r in rs if r[4] is not None)})"
                        if loc else "—") + " |")
    lines += ["", "### Circle / point triples (random integer data, 3×3 Krawczyk)", "",
              "| vertices | certified | median ms | max ms |", "|---|---|---|---|",
              f"| {len(ctimes)} | {cok} | {ms(statistics.median(ctimes))} | {ms(max(ctimes))} |",
              "", "### Distance bounds, 10 000 random points in [-10, 10]²", "",
              "| kind | distance ms | distance_bounds ms | max relative gap (d > 0.05) | ball fallbacks |",
              "|---|---|---|---|---|"]
    for kind, td, tb, gap, fb in brows:
        lines.append(f"| {kind} | {ms(td)} | {ms(tb)} | {gap:.1e} | {fb} |")
    lines += ["", f"total {total:.1f} s", ""]
    text = "\n".join(lines)
    print(text)
    out = pathlib.Path(__file__).resolve().parent / "results" / "vertex.md"
    out.write_text("# Local vertices and distance bounds\n\n" + text)


if __name__ == "__main__":
    main()
