"""Benchmark of degenerate inputs (issue 30): grids, rings, collinear and co-circular sites,
symmetric conics, GIS coordinates, far-apart sites; each with time, certified and counts.

Rows:
* the cases of the table of issue 30, each against what a user expects (closed form, or CGAL's
  Apollonius_graph_2 on the same doubles without its zero-length edges, tests/cgal/, for the
  float rings and UTM-scale circles);
* a 32×32 grid of integer points and a 10×10 grid of identical ellipses (centres (6i, 4j), semi-axes
  2 and 1), with the time ratio to a random scene of the same size (uniform random points in the
  same square; random disjoint ellipses of bench_voronoi.random_ellipses); target ≤ 3×;
* ``scipy.spatial.Voronoi`` on the point grids and the random points in the same run: time and ridge
  count, zero-length ridges (both ends at one vertex within 1e-9 of the spacing) merged away.

Every case runs in its own subprocess with ``voronoi(..., time_limit=L)`` and a subprocess timeout
(L + 60 s), so one hang does not stop the bench; ``voronoi`` is called with certify=True (the
verifier's verdict is the "certified" column) and its wall and CPU times include the verification.
One BLAS thread (threadpoolctl and OPENBLAS_NUM_THREADS=1).

Run:  OPENBLAS_NUM_THREADS=1 python bench/bench_degenerate.py [--only NAME ...]
      (appends a table to bench/results/degenerate.md)
"""
from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import time
from fractions import Fraction
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests" / "cgal"))
sys.path.insert(0, str(ROOT / "bench"))
sys.path.insert(0, str(ROOT / "tests"))
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")


# ----------------------------------------------------------------------------- scenes
def point_grid(n, origin=(0, 0), spacing=1):
    return [(origin[0] + spacing * i, origin[1] + spacing * j, 0) for j in range(n) for i in range(n)]


def ellipse_grid(n):
    from curvedvoronoi.runtime.sites.conic import Conic

    return [Conic.ellipse(centre=(6 * i, 4 * j), axes=(2, 1)) for j in range(n) for i in range(n)]


def random_points(n, seed):
    import numpy as np

    rng = np.random.default_rng(seed)
    side = math.sqrt(n)
    return [(float(x), float(y), 0) for x, y in rng.uniform(0, side, size=(n, 2))]


def ring12():
    return [(10 * math.cos(2 * math.pi * k / 12), 10 * math.sin(2 * math.pi * k / 12), 1.0) for k in range(12)]


def utm_circles(n, seed):
    """The scene of tests/test_degenerate_cgal.py (one generator for tests and bench)."""
    from test_degenerate_cgal import utm_circles as scene

    return scene(n, seed)


def translated(seed, shift):
    import cgal_peer

    n = 10 + 2 * seed
    return [(x + shift, y + shift, r) for x, y, r in cgal_peer.random_disjoint_circles(n, 100 + seed)]


def readme():
    import curvedvoronoi as cv

    return [(0, 0, 1), (4, 0, 1), (2, 4, 0), cv.Conic.ellipse(centre=(10, 0), axes=(2, 1))]


def ellipses_far_vertex():
    """Four axis-aligned ellipses; the first three have nearly collinear centres (the third 1/4 up),
    so the vertex below them is far (about 400 away)."""
    from curvedvoronoi.runtime.sites.conic import Conic

    return [Conic.ellipse(centre=c, axes=(2, 1)) for c in [(0, 0), (10, 0), (20, Fraction(1, 4)), (10, 8)]]


# name -> (scene builder, what a user expects: (vertices, degree-k>3 vertices, edges) or a CGAL key, time limit)
# expectations from geometry: n×n point grid (n−1)² vertices of degree 4 and 2n(n−1) edges; 6 collinear
# points 5 whole lines; 4 circles on one circle one degree-4 vertex and 4 rays; the k×k ellipse grid is the
# grid of its centres (mirror symmetry, tests/test_degenerate.py); the README example 2 vertices, 5 edges.
CASES = {
    "grid 5×5 integer points": (lambda: point_grid(5), (16, 16, 40), 60),
    "6 collinear points": (lambda: [(x, 0, 0) for x in (0, 1, 3, 4, 7, 10)], (0, 0, 5), 60),
    "4 equal circles centred on one circle": (lambda: [(5, 0, 1), (0, 5, 1), (-5, 0, 1), (0, -5, 1)], (1, 1, 4), 60),
    "3×3 identical axis-aligned ellipses": (lambda: ellipse_grid(3), (4, 4, 12), 60),
    "ring of 12 circles (math.cos/sin floats)": (ring12, "cgal", 60),
    "50 circles near (5e5, 5e6) (UTM)": (lambda: utm_circles(50, 0), "cgal", 60),
    "circle at x = 1e10, two near the origin": (lambda: [(1e10, 0.0, 1.0), (0.0, 0.0, 1.0), (4.0, 0.0, 1.0)], None, 30),
    "circle at x = 1e20, two near the origin": (lambda: [(1e20, 0.0, 1.0), (0.0, 0.0, 1.0), (4.0, 0.0, 1.0)], None, 30),
    "README first example": (readme, (2, 0, 5), 60),
    "4 circles tangent to one circle, 4th moved 1e-8": (
        lambda: [(5.0, 0.0, 1.0), (0.0, 6.0, 2.0), (-10.0, 0.0, 6.0), (0.0, -7.0 - 1e-8, 3.0)], "cgal", 10),
    **{f"random circles +1e6, seed {s}": ((lambda s=s: translated(s, 1e6)), "cgal", 60) for s in range(6)},
    **{f"random circles +2^23, seed {s}": ((lambda s=s: translated(s, 2.0 ** 23)), "cgal", 60) for s in range(6)},
    "4 axis-aligned ellipses, far vertex": (ellipses_far_vertex, None, 60),
    "grid 32×32 integer points": (lambda: point_grid(32), (961, 961, 1984), 600),
    "random points, N = 1024": (lambda: random_points(1024, 1), None, 600),
    "grid 10×10 identical ellipses": (lambda: ellipse_grid(10), (81, 81, 180), 600),
    "random ellipses, N = 100": (lambda: __import__("bench_voronoi").random_ellipses(100, 1), None, 600),
}
RATIOS = [("grid 32×32 integer points", "random points, N = 1024"),
          ("grid 10×10 identical ellipses", "random ellipses, N = 100")]


def run_case(name: str) -> dict:
    import importlib

    for mod in ("numpy", "scipy.spatial"):      # load the BLAS libraries before limiting their threads
        importlib.import_module(mod)
    from threadpoolctl import threadpool_info, threadpool_limits

    import curvedvoronoi as cv

    threadpool_limits(limits=1)
    build, expect, limit = CASES[name]
    sites = build()
    out = {"name": name, "n": len(sites), "time_limit": limit,
           "threadpools": [(p["internal_api"], p["num_threads"]) for p in threadpool_info()]}
    t0, c0 = time.perf_counter(), time.process_time()
    try:
        d = cv.voronoi(sites, time_limit=limit)
    except Exception as exc:  # noqa: BLE001 - the bench records what a user would see
        out.update(seconds=time.perf_counter() - t0, cpu_seconds=time.process_time() - c0,
                   exception=f"{type(exc).__name__}: {str(exc).splitlines()[0][:160] if str(exc) else ''}")
        return out
    out.update(seconds=time.perf_counter() - t0, cpu_seconds=time.process_time() - c0,
               certified=bool(d.certified), vertices=len(d.vertices),
               high_degree=sum(len(v.sites) > 3 for v in d.vertices), edges=len(d.edges),
               problems=len(d.problems), first_problem=(d.problems[0][:140] if d.problems else ""),
               delaunay=[list(p) for p in d.delaunay_edges()])
    if isinstance(expect, tuple):
        out["expected"] = list(expect)
        out["as_expected"] = [out["vertices"], out["high_degree"], out["edges"]] == list(expect)
    return out


def scipy_case(name: str) -> dict:
    """scipy.spatial.Voronoi on a point scene: time and ridges, zero-length ridges merged."""
    import numpy as np
    from scipy.spatial import Voronoi

    pts = np.array([(float(x), float(y)) for x, y, _ in CASES[name][0]()])
    t0 = time.perf_counter()
    vor = Voronoi(pts)
    sec = time.perf_counter() - t0
    tol = 1e-9 * (np.ptp(pts[:, 0]) / math.sqrt(len(pts)))
    zero = 0
    for rv in vor.ridge_vertices:
        if -1 not in rv and np.linalg.norm(vor.vertices[rv[0]] - vor.vertices[rv[1]]) <= tol:
            zero += 1
    # Voronoi vertices that coincide (a degree-4 vertex split by the triangulation) merged to one
    merged_vertices = len({tuple(np.round(v / tol).astype(np.int64)) for v in vor.vertices}) if tol > 0 else len(vor.vertices)
    return {"seconds": sec, "ridges": len(vor.ridge_vertices), "ridges_merged": len(vor.ridge_vertices) - zero,
            "vertices": len(vor.vertices), "vertices_merged": merged_vertices}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--case", help=argparse.SUPPRESS)
    ap.add_argument("--only", nargs="*", help="run only the cases whose name contains one of these words")
    ap.add_argument("--no-write", action="store_true")
    args = ap.parse_args()
    if args.case:
        print(json.dumps(run_case(args.case)))
        return
    names = list(CASES)
    if args.only:
        names = [n for n in names if any(w in n for w in args.only)]
    load0 = os.getloadavg()[0]
    rows = {}
    for name in names:
        limit = CASES[name][2]
        t0 = time.perf_counter()
        try:
            res = subprocess.run([sys.executable, __file__, "--case", name], capture_output=True, text=True,
                                 timeout=limit + 60, env=dict(os.environ, OPENBLAS_NUM_THREADS="1"))
            if res.returncode != 0:
                r = {"name": name, "error": (res.stderr.strip().splitlines() or ["?"])[-1][:160]}
            else:
                r = json.loads(res.stdout.strip().splitlines()[-1])
        except subprocess.TimeoutExpired:
            r = {"name": name, "error": f"no return after {time.perf_counter() - t0:.0f} s (time_limit={limit})"}
        if CASES[name][1] == "cgal" and "delaunay" in r:
            try:
                import cgal_peer

                edges, sec, hidden, _ = cgal_peer.delaunay_edges_nondegenerate(CASES[name][0]())
                r["cgal_seconds"] = sec
                r["as_expected"] = [list(e) for e in edges] == r["delaunay"] and hidden == 0
                r["expected"] = f"CGAL: {len(edges)} edges"
            except Exception as exc:  # noqa: BLE001 - PeerMissing, or a build failure
                r["expected"] = f"CGAL unavailable ({type(exc).__name__})"
        rows[name] = r
        print(name, {k: v for k, v in r.items() if k != "delaunay"}, file=sys.stderr, flush=True)
    scipy_rows = {}
    for name in ("grid 5×5 integer points", "grid 32×32 integer points", "random points, N = 1024"):
        if name in names:
            scipy_rows[name] = scipy_case(name)
    from threadpoolctl import threadpool_info

    first = next((r for r in rows.values() if "threadpools" in r), {})
    lines = [f"## bench_degenerate {time.strftime('%Y-%m-%d %H:%M')}  OPENBLAS_NUM_THREADS="
             f"{os.environ.get('OPENBLAS_NUM_THREADS')}  threadpools={first.get('threadpools', [(p['internal_api'], p['num_threads']) for p in threadpool_info()])}"
             f"  cpus={os.cpu_count()}  load={load0:.1f} (start) {os.getloadavg()[0]:.1f} (end)",
             "",
             "`voronoi(sites, time_limit=L)` with certify=True (times include the verifier), one subprocess per "
             "case with a timeout of L + 60 s. vertices (k>3) = all vertices (those with more than three sites); "
             "expected = from geometry (vertices, degree>3 vertices, edges) or CGAL Apollonius_graph_2 on the same "
             "doubles without its zero-length edges (tests/cgal/, `--degenerate`); ok = counts (or the Delaunay graph, "
             "for CGAL rows) as expected. Wall times are noisy when other jobs share the machine (see load).",
             "",
             "| case | N | wall s | CPU s | L s | certified | vertices (k>3) | edges | expected | ok | problems | first problem / outcome |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for name, r in rows.items():
        if "error" in r or "exception" in r:
            msg = r.get("error") or r.get("exception")
            wall = f"{r['seconds']:.3f}" if "seconds" in r else "-"
            cpu = f"{r['cpu_seconds']:.3f}" if "cpu_seconds" in r else "-"
            lines.append(f"| {name} | {r.get('n', '-')} | {wall} | {cpu} | {CASES[name][2]} | no | - | - | "
                         f"{r.get('expected', '-')} | no | - | {msg.replace('|', '/')} |")
            continue
        exp = r.get("expected", "-")
        if isinstance(exp, list):
            exp = f"{exp[0]} ({exp[1]}), {exp[2]}"
        lines.append(f"| {name} | {r['n']} | {r['seconds']:.3f} | {r['cpu_seconds']:.3f} | {r['time_limit']} | "
                     f"{'yes' if r['certified'] else 'no'} | {r['vertices']} ({r['high_degree']}) | {r['edges']} | "
                     f"{exp} | {'yes' if r.get('as_expected') else ('-' if 'as_expected' not in r else 'no')} | "
                     f"{r['problems']} | {r['first_problem'].replace('|', '/') or '-'} |")
    lines += ["", "Time ratio of the degenerate grid to a random scene of the same size (target ≤ 3×):", "",
              "| grid | random scene | grid s | random s | ratio (wall) | ratio (CPU) |", "|---|---|---|---|---|---|"]
    for g, rnd in RATIOS:
        a, b = rows.get(g, {}), rows.get(rnd, {})
        if "cpu_seconds" in a and "cpu_seconds" in b and "error" not in a and "error" not in b:
            lines.append(f"| {g} | {rnd} | {a['seconds']:.2f} | {b['seconds']:.2f} | "
                         f"{a['seconds'] / b['seconds']:.1f}× | {a['cpu_seconds'] / b['cpu_seconds']:.1f}× |")
        else:
            lines.append(f"| {g} | {rnd} | {a.get('error', '-')} | {b.get('error', '-')} | - | - |")
    if scipy_rows:
        lines += ["", "`scipy.spatial.Voronoi` (qhull) in the same run; ridges merged = ridges minus those whose two "
                  "finite vertices coincide (within 1e-9 of the spacing); vertices merged = distinct vertex positions "
                  "(same tolerance). A n×n grid has 2n(n−1) Voronoi edges of positive length and (n−1)² vertices.", "",
                  "| points | scipy s | ridges | ridges merged | vertices | vertices merged | ours s (wall) | ours edges |",
                  "|---|---|---|---|---|---|---|---|"]
        for name, s in scipy_rows.items():
            r = rows.get(name, {})
            lines.append(f"| {name} | {s['seconds']:.4f} | {s['ridges']} | {s['ridges_merged']} | {s['vertices']} | "
                         f"{s['vertices_merged']} | {r.get('seconds', float('nan')):.3f} | {r.get('edges', '-')} |")
    text = "\n".join(lines) + "\n"
    print(text)
    if not args.no_write:
        out = ROOT / "bench" / "results" / "degenerate.md"
        out.parent.mkdir(exist_ok=True)
        with open(out, "a") as fh:
            fh.write(text + "\n")


if __name__ == "__main__":
    main()
