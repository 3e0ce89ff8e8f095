"""Benchmark of the dynamic diagram: local insertion and deletion of one circle or ellipse, and
proved nearest-site queries, against CGAL's Apollonius_graph_2 and scipy in the same run.

Rows (one subprocess per N, so each N has its own peak RSS):
* random disjoint circles (tests/cgal/cgal_peer.random_disjoint_circles, N + K drawn, the first N
  built with ``cv.voronoi`` and certified); then, one after the other: K insertions of the K
  remaining circles (``d.insert``), K deletions with ``renumber="last"`` and K with the default
  ``renumber="shift"`` (``d.delete_site``), each certified=True.  Reported: the first update
  separately (it builds the adjacency state once, O(N)), then median / max time per operation
  (wall and CPU), how many updates were proved locally, how many re-proved the unbounded edges and
  the accounting at infinity (a site on or near the convex hull) or were rebuilt, and whether every
  result was certified.  The final diagram's Delaunay graph is compared with CGAL's after the same
  operations (tests/cgal/apollonius_dynamic.cpp: CGAL's insert and remove on the same doubles) and
  verified with ``cv.verify`` (the independent verifier, once, at the end).  CGAL's median time per
  operation and the ratio.
* random disjoint ellipses (tests/scenes.random_ellipses; N = 10³ built certified, 10⁴ built with
  certify=False: the verifier needs about a minute per 10³ ellipses): K insertions, K deletions of
  each numbering, each with certify=True (the changed part is proved either way; the result is
  certified only when the batch build was).  No peer handles ellipses: the final Delaunay graph is
  compared with a batch build of the final list of sites.
* nearest-site queries on point sites (N = 10⁴ random points): ``d.nearest`` proved and unproved,
  ``scipy.spatial.cKDTree.query`` and CGAL's ``Apollonius_graph_2::nearest_neighbor`` (with the
  previous answer as hint) on the same 10⁵ random query points, queries per second, and whether the
  answers agree.
* nearest-site queries on the circle diagrams of N ≥ 10⁴ (proved, right after the build) against
  CGAL's ``nearest_neighbor`` on the same circles, queries per second.

N = 10⁵ circles (``--big``) are built by tiles (``cv.tiled_voronoi``, certified by the verifier;
one process runs out of memory), kept in ``--cache DIR`` between runs.  ``--inplace`` makes the
circle updates with ``inplace=True`` (no O(N) copy of the diagram's lists).

One BLAS thread (threadpoolctl and OPENBLAS_NUM_THREADS=1); thread settings and the load average
(/proc/loadavg) are in the table header: the machine is shared, wall times are noisy under load.

* random disjoint segments (``--segments 1000 10000``: only these rows run; tests/scenes.random_segments):
  K insertions of segments, K deletions of each numbering, each certified (runtime/segments/edits.py:
  local insertion and deletion, a rebuild where the change reaches the convex hull),
  CPU median per update and its route against a certified batch build of the final list.
* random disjoint circular arcs (``--arcs 1000 10000 --arc-k 8 --arc-deletes 8``: tests/scenes.random_arcs),
  the same rows as the segments (local insertion and deletion of arcs, runtime/segments/edits.py).

Run:  OPENBLAS_NUM_THREADS=1 python bench/bench_dynamic.py [--sizes 1000 10000] [--big] [--k 20]
          [--ellipses 1000 10000] [--ellipse-k 10]
          [--cache DIR] [--max-rss-gb 6] [--inplace]
      (--big adds N = 10⁵: about 2.8 GB, 15–20 min for the tiled build and as long again for the
      final verification under load; appends a table to bench/results/dynamic.md)
"""
from __future__ import annotations

import argparse
import json
import math
import os
import random
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests" / "cgal"))
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")


def _threads():
    import numpy  # noqa: F401 - load the BLAS before asking threadpoolctl about it
    from threadpoolctl import threadpool_info, threadpool_limits

    threadpool_limits(limits=1)
    return [(p["internal_api"], p["num_threads"]) for p in threadpool_info()]


def _loadavg() -> str:
    try:
        return Path("/proc/loadavg").read_text().split()[0]
    except OSError:
        return f"{os.getloadavg()[0]:.2f}"


def _circles_build(base, n, k, seed, certify, cache):
    """The batch build of the N circles: ``cv.voronoi`` up to 2·10⁴ sites; above, the tiled build
    (``cv.tiled_voronoi``, certified by the whole-diagram verifier: one process runs out of memory at
    10⁵), kept in ``cache`` (a pickle keyed by N, K and the seed) so that a second run does not
    build again.  A tiled diagram carries no construction state: it is given one (the sites'
    arrays, no sample triangulation), which is all that local updates need."""
    import pickle

    import curvedvoronoi as cv

    if n <= 20000:
        t0, c0 = time.perf_counter(), time.process_time()
        d = cv.voronoi(base, progress=False, certify=certify)
        return d, time.perf_counter() - t0, time.process_time() - c0, "voronoi"
    from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
    from curvedvoronoi.runtime.voronoi.construction import ConstructionState
    from curvedvoronoi.runtime.voronoi.site_arrays import SiteArrays

    path = Path(cache) / f"circles_{n}_{k}_{seed}_{'c' if certify else 'u'}.pkl" if cache else None
    if path is not None and path.exists():
        with open(path, "rb") as fh:
            got = pickle.load(fh)
        d, build_s, build_cpu_s, how = got["diagram"], got["build_s"], got["build_cpu_s"], "tiled_voronoi (cached)"
    else:
        t0, c0 = time.perf_counter(), time.process_time()
        d = cv.tiled_voronoi(base, progress=False, certify=certify)
        build_s, build_cpu_s, how = time.perf_counter() - t0, time.process_time() - c0, "tiled_voronoi"
        d.construction = None
        if path is not None:
            path.parent.mkdir(parents=True, exist_ok=True)
            with open(path, "wb") as fh:
                pickle.dump({"diagram": d, "build_s": build_s, "build_cpu_s": build_cpu_s}, fh, protocol=5)
    d.construction = ConstructionState(SiteArrays(d.sites, [site_geometry(s) for s in d.sites]), None, {})
    return d, build_s, build_cpu_s, how


def circles_case(n: int, k: int, seed: int = 1, certify: bool = True, queries: int = 0, cache=None,
                 inplace: bool = False) -> dict:
    import cgal_peer
    import curvedvoronoi as cv

    threads = _threads()
    circles = cgal_peer.random_disjoint_circles(n + k, seed)
    base, extra = circles[:n], circles[n:]
    d, build_s, build_cpu_s, how = _circles_build(base, n, k, seed, certify, cache)
    out = {"case": "circles", "N": n, "K": k, "threads": threads, "build_s": build_s, "build_how": how,
           "build_cpu_s": build_cpu_s, "build_certified": bool(d.certified), "certify": certify}
    if n >= 10000 and queries:
        # proved nearest-site queries on the built circle diagram, against CGAL's nearest_neighbor
        # on the same circles (the Apollonius graph's walk, the previous answer as hint)
        import numpy as np

        C = np.array([(x, y) for x, y, _ in base])
        Q = np.random.default_rng(seed + 7).uniform(C.min(axis=0), C.max(axis=0), (queries, 2))
        d.nearest(Q[:10])                                   # the site index is built once
        t = time.perf_counter()
        r = d.nearest(Q)
        out["nearest_qps"] = queries / (time.perf_counter() - t)
        out["nearest_proved"] = float(np.mean(r.proved))
        try:
            import cgal_dynamic

            _, _, _, _, q_s, near = cgal_dynamic.run(base, [], Q)
            ok = r.index >= 0
            out["cgal_nearest_qps"] = queries / q_s
            out["cgal_nearest_same"] = bool(np.array_equal(np.asarray(near)[ok], r.index[ok]))
        except Exception as exc:  # noqa: BLE001 - PeerMissing or a build failure
            out["cgal_nearest_error"] = f"{type(exc).__name__}: {exc}"
    rng = random.Random(seed)
    cur = list(base)
    ops, rows = [], []

    def timed(kind, fn):
        nonlocal d
        t, c = time.perf_counter(), time.process_time()
        d = fn()
        rows.append({"op": kind, "wall": time.perf_counter() - t, "cpu": time.process_time() - c,
                     "how": d.stats.get("update", d.stats.get("deletion")), "certified": bool(d.certified),
                     "split": d.stats.get("seconds", {}), "changed": d.stats.get("changed", {}),
                     "direct": d.stats.get("local build") in ("star region", "hole region")})

    for c in extra:
        timed("insert", lambda c=c: d.insert(c, certify=certify, inplace=inplace))
        cur.append(c)
        ops.append(("+", c))
    for mode in ("last", "shift"):
        for _ in range(k):
            i = rng.randrange(len(cur))
            timed(f"delete ({mode})", lambda i=i, mode=mode: d.delete_site(i, renumber=mode, certify=certify,
                                                                        inplace=inplace))
            if mode == "shift":
                cur.pop(i)
                ops.append(("-", i))
            else:
                cur[i] = cur[-1]
                cur.pop()
                ops.append(("L", i))
    if certify:
        t = time.perf_counter()
        cert = cv.verify(d, progress=False)
        out["final_verify_s"] = time.perf_counter() - t
        out["final_verified"] = bool(cert.ok)
    out["final_sites_as_expected"] = [(float(s.cx), float(s.cy)) for s in d.sites] == [(x, y) for x, y, _ in cur]
    try:
        import cgal_dynamic

        _, cg_ops, hidden, edges = cgal_dynamic.run(base, ops)
        out["cgal_op_s"] = cg_ops
        out["cgal_same_graph"] = d.delaunay_edges() == edges and hidden == 0
    except Exception as exc:  # noqa: BLE001 - PeerMissing or a build failure
        out["cgal_error"] = f"{type(exc).__name__}: {exc}"
    out["rows"] = rows
    out["peak_rss_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    return out


def ellipses_case(n: int, k: int, seed: int = 1, certify_build: bool = True) -> dict:
    """Random disjoint ellipses (tests/scenes.random_ellipses, N + K drawn): the batch build of
    the first N (certified when ``certify_build``), then K insertions, K deletions with
    renumber="last" and K with "shift", each with certify=True (the changed part proved; the
    result is certified only when the batch build was).  No peer: the final Delaunay graph is
    compared with a batch build of the final list of sites (certify=False)."""
    sys.path.insert(0, str(ROOT / "tests"))
    from scenes import random_ellipses

    import curvedvoronoi as cv

    threads = _threads()
    sites = random_ellipses(n + k, seed)
    base, extra = sites[:n], sites[n:]
    t0, c0 = time.perf_counter(), time.process_time()
    d = cv.voronoi(base, progress=False, certify=certify_build)
    out = {"case": "ellipses", "N": n, "K": k, "threads": threads, "build_s": time.perf_counter() - t0,
           "build_cpu_s": time.process_time() - c0, "build_certified": bool(d.certified), "certify": certify_build}
    rng = random.Random(seed)
    cur = list(base)
    rows = []

    def timed(kind, fn):
        nonlocal d
        t, c = time.perf_counter(), time.process_time()
        d = fn()
        new_e = [e for e in d.edges if not e.certified]
        rows.append({"op": kind, "wall": time.perf_counter() - t, "cpu": time.process_time() - c,
                     "how": d.stats.get("update", d.stats.get("deletion")), "certified": bool(d.certified),
                     "split": d.stats.get("seconds", {}), "changed": d.stats.get("changed", {}),
                     "unproved_parts": len(new_e) if certify_build else None})

    for s in extra:
        timed("insert", lambda s=s: d.insert(s))
        cur.append(s)
    for mode in ("last", "shift"):
        for _ in range(k):
            i = rng.randrange(len(cur))
            timed(f"delete ({mode})", lambda i=i, mode=mode: d.delete_site(i, renumber=mode))
            if mode == "shift":
                cur.pop(i)
            else:
                cur[i] = cur[-1]
                cur.pop()
    out["final_sites_as_expected"] = all(a is b for a, b in zip(d.sites, cur)) and len(d.sites) == len(cur)
    t = time.perf_counter()
    ref = cv.voronoi(cur, progress=False, certify=False)
    out["batch_same_graph"] = d.delaunay_edges() == ref.delaunay_edges()
    out["batch_check_s"] = time.perf_counter() - t
    out["rows"] = rows
    out["peak_rss_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    return out


def nearest_case(n: int, q: int, seed: int = 2) -> dict:
    import numpy as np
    from scipy.spatial import cKDTree

    import curvedvoronoi as cv

    threads = _threads()
    rng = np.random.default_rng(seed)
    side = 10.0 * np.sqrt(n)
    P = rng.uniform(0, side, (n, 2))
    Q = rng.uniform(0, side, (q, 2))
    d = cv.voronoi([(float(x), float(y), 0) for x, y in P], certify=False, progress=False)
    out = {"case": "nearest", "N": n, "Q": q, "threads": threads}
    d.nearest(Q[:10])                                       # the site index is built once
    t = time.perf_counter()
    r = d.nearest(Q)
    out["proved_qps"] = q / (time.perf_counter() - t)
    out["proved_fraction"] = float(np.mean(r.proved))
    t = time.perf_counter()
    r2 = d.nearest(Q, prove=False)
    out["float_qps"] = q / (time.perf_counter() - t)
    tree = cKDTree(P)
    t = time.perf_counter()
    _, idx = tree.query(Q)
    out["scipy_qps"] = q / (time.perf_counter() - t)
    ok = r.index >= 0
    out["same_as_scipy"] = bool(np.array_equal(r.index[ok], idx[ok]))
    out["float_same_as_scipy"] = float(np.mean(r2.index == idx))
    try:
        import cgal_dynamic

        _, _, _, _, q_s, near = cgal_dynamic.run([(float(x), float(y), 0.0) for x, y in P], [], Q)
        out["cgal_qps"] = q / q_s
        out["cgal_same"] = bool(np.array_equal(np.asarray(near)[ok], r.index[ok]))
    except Exception as exc:  # noqa: BLE001
        out["cgal_error"] = f"{type(exc).__name__}: {exc}"
    return out


def segments_case(n: int, k: int, seed: int = 1, deletes: int | None = None, kind: str = "segments",
                  interior: bool = False, final_batch: bool = True) -> dict:
    """Random pairwise disjoint segments (tests/scenes.random_segments, N + K drawn; ``kind="arcs"``:
    circular arcs, tests/scenes.random_arcs): the batch
    build of the first N (certified), then K insertions of the other K (``d.insert``), ``deletes``
    (default K) deletions of random input pieces with renumber="last" and as many with "shift", each certify=True and
    inplace=True; CPU seconds per certified update, its route (``stats["update"]``), and at the end
    a batch build of the final list of pieces (sites and Delaunay graph compared; ``final_batch=False``:
    skipped).  ``interior`` (arcs): the inserted and deleted arcs are drawn from the grid cells off
    the border only (their regions bounded; an edit reaching the convex hull is a rebuild, the cost
    of a batch build)."""
    sys.path.insert(0, str(ROOT / "tests"))
    from scenes import random_arcs, random_segments

    import curvedvoronoi as cv

    threads = _threads()
    if kind == "arcs":
        segs = random_arcs(n + k, seed)
    else:
        segs = [cv.Segment(a, b) for a, b in random_segments(n + k, seed)]
    side = math.ceil(math.sqrt(n + k))    # the grid of tests/scenes.random_arcs

    def inner(p) -> bool:                 # an arc in a grid cell off the border (tests/scenes.random_arcs)
        return all(1 <= int(c) // 40 <= side - 2 for c in p.c)
    if interior and kind == "arcs":
        pick = set(random.Random(seed + 1).sample([t for t, p in enumerate(segs) if inner(p)], k))
        base, extra = [p for t, p in enumerate(segs) if t not in pick], [segs[t] for t in sorted(pick)]
    else:
        base, extra = segs[:n], segs[n:]
    t0, c0 = time.perf_counter(), time.process_time()
    d = cv.voronoi(base, progress=False)
    out = {"case": kind, "N": n, "K": k, "threads": threads, "build_s": time.perf_counter() - t0,
           "build_cpu_s": time.process_time() - c0, "build_certified": bool(d.certified), "seed": seed}
    if not d.certified:                   # every edit would be a rebuild: say so instead of timing batch builds
        return dict(out, error=f"the batch build of seed {seed} is not certified ({len(d.problems)} problems, "
                               f"first: {str(d.problems[0])[:120] if d.problems else '-'})")
    rng = random.Random(seed)
    cur = list(base)
    rows = []

    def timed(kind, fn):
        nonlocal d
        t, c = time.perf_counter(), time.process_time()
        d = fn()
        rows.append({"op": kind, "wall": time.perf_counter() - t, "cpu": time.process_time() - c,
                     "how": d.stats.get("update"), "certified": bool(d.certified)})

    for s in extra:
        timed("insert", lambda s=s: d.insert(s, inplace=True))
        cur.append(s)
    for mode in ("last", "shift"):
        for _ in range(k if deletes is None else deletes):
            i = (rng.choice([t for t, p in enumerate(cur) if inner(p)]) if interior and kind == "arcs"
                 else rng.randrange(len(cur)))
            timed(f"delete ({mode})", lambda i=i, mode=mode: d.delete_site(i, renumber=mode, inplace=True))
            if mode == "shift" or i == len(cur) - 1:
                cur.pop(i)
            else:
                cur[i] = cur.pop()
    if final_batch:
        t, c = time.perf_counter(), time.process_time()
        batch = cv.voronoi(cur, progress=False)
        out["final_batch_s"], out["final_batch_cpu_s"] = time.perf_counter() - t, time.process_time() - c
        out["same_as_batch"] = _same_segment_graph(d, batch) and bool(batch.certified)
    else:
        out["final_batch_s"] = out["final_batch_cpu_s"] = None
        out["same_as_batch"] = "not run"
    out["rows"] = rows
    out["peak_rss_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    return out


def _same_segment_graph(d, batch) -> bool:
    """The two diagrams have the same sites and the same Delaunay graph, over exact site keys (a
    local deletion numbers the sites differently from a batch build)."""
    from curvedvoronoi.runtime.segments.local_update import site_key

    def graph(D):
        keys = [site_key(s) for s in D.sites]
        return sorted(keys), {frozenset((keys[i], keys[j])) for i, j in D.delaunay_edges()}
    return graph(d) == graph(batch)


def _segment_table(results, args, kind: str = "segments") -> list:
    rows = [r for r in results if str(r.get("case")).startswith(kind)]
    if not rows:
        return []
    what = (f"Random disjoint circular arcs (tests/scenes.random_arcs, one per cell of a grid, seed {args.arc_seed}"
            + ("; inserted and deleted arcs only from cells off the grid's border" if args.arc_interior else "")
            + ("; no final batch build" if args.no_final_batch else "") + ")"
            if kind == "arcs" else "Random disjoint segments (tests/scenes.random_segments)")
    k = args.arc_k if kind == "arcs" else args.segment_k
    dels = args.arc_deletes if kind == "arcs" else args.segment_deletes
    lines = ["", f"{what}: batch build of N (certified), then K = "
             f"{k} insertions, {k if dels is None else dels} "
             "deletions with renumber=\"last\" and as many with \"shift\" (certify=True, "
             "inplace=True each; runtime/segments/edits.py).  local / rebuild = the route of stats[\"update\"]; "
             "first = the first update of that kind (the first edit of a batch-built diagram builds the edit "
             "index, linear in N); median and max over all; local median = the median over the local routes; "
             "batch = a certified batch build of the final list of pieces (CPU s), ratio = local median / batch; "
             "same = the edited diagram's sites and Delaunay graph equal the batch build's (exact site keys).", "",
             "| N | op | first CPU s | median CPU s | local median CPU s | max CPU s | local / rebuild | all certified | "
             "batch CPU s | ratio | same as batch | peak RSS MB |", "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if "error" in r:
            lines.append(f"| {r['case']} | error: {r['error']} |" + " |" * 10)
            continue
        for kind in ("insert", "delete (last)", "delete (shift)"):
            got = [x for x in r["rows"] if x["op"] == kind]
            if not got:
                continue
            med = statistics.median(x["cpu"] for x in got)
            loc = [x["cpu"] for x in got if x["how"] == "local"]
            lmed = statistics.median(loc) if loc else None
            n_reb = sum(str(x["how"]).startswith("rebuild") for x in got)
            lines.append(f"| {r['N']} | {kind} | {got[0]['cpu']:.3f} | {_fmt(med, 3)} | {_fmt(lmed, 3)} | "
                         f"{_fmt(max(x['cpu'] for x in got), 2)} | "
                         f"{len(got) - n_reb} / {n_reb} | {all(x['certified'] for x in got)} | "
                         f"{_fmt(r['final_batch_cpu_s'], 2)} | "
                         f"{'-' if lmed is None or not r['final_batch_cpu_s'] else format(lmed / r['final_batch_cpu_s'], '.4f')} | "
                         f"{r['same_as_batch']} | {r['peak_rss_mb']:.0f} |")
    return lines


def _verified(r) -> str:
    if "final_verified" not in r:
        return "not run (certify=False)"
    return f"{'yes' if r['final_verified'] else 'NO'} ({r['final_verify_s']:.1f} s)"


def _fmt(x, nd=4):
    return "-" if x is None else f"{x:.{nd}f}"


def _ellipse_table(results, args) -> list:
    rs = [r for r in results if str(r.get("case")).startswith("ellipses")]
    if not rs:
        return []
    lines = ["", f"Random disjoint ellipses (tests/scenes.random_ellipses): batch build of N, then K = {args.ellipse_k} "
             "insertions, K deletions with renumber=\"last\", K with \"shift\", each with certify=True (the changed "
             "part proved by the verifier's routines against the sites within reach). The batch build is certified for N ≤ "
             f"{args.certify_ellipses_up_to} (\"build certified\"); an update of an uncertified diagram proves the same "
             "parts but is never certified. No peer: \"graph = batch\" compares the final Delaunay graph with a batch "
             "build of the final sites.", "",
             "| N | op | first s | median s (CPU) | max s | local / infinity / rebuild | all certified | "
             "new parts not proved | median split (locate / local build / prove) | build s | build certified | "
             "graph = batch | peak RSS MB |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rs:
        if "error" in r:
            lines.append(f"| {r['case']} | error: {r['error']} |" + " |" * 11)
            continue
        for kind in ("insert", "delete (last)", "delete (shift)"):
            rows = [x for x in r["rows"] if x["op"] == kind]
            first = rows[0]["wall"] if kind == "insert" else None
            rest = rows[1:] if kind == "insert" else rows
            hows = [x["how"] or "" for x in rows]
            n_inf = sum("infinity" in h for h in hows)
            n_reb = sum(h.startswith("rebuild") or h in ("local triangulation declined", "local sample triangulation")
                        for h in hows)
            spl = [x["split"] for x in rest if "prove" in x["split"]]
            split = " / ".join(_fmt(statistics.median(s.get(key, 0) for s in spl)) for key in
                               ("locate", "local build", "prove")) if spl else "-"
            lines.append(f"| {r['N']} | {kind} | {_fmt(first)} | {_fmt(statistics.median(x['wall'] for x in rest))} "
                         f"({_fmt(statistics.median(x['cpu'] for x in rest))}) | {_fmt(max(x['wall'] for x in rest))} | "
                         f"{len(hows) - n_inf - n_reb} / {n_inf} / {n_reb} | {all(x['certified'] for x in rows)} | "
                         f"{sum(x['changed'].get('new_unproved', 0) for x in rows)} | {split} | {r['build_s']:.1f} | {r['build_certified']} | {r['batch_same_graph']} | "
                         f"{r['peak_rss_mb']:.0f} |")
    return lines


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--case", help=argparse.SUPPRESS)
    ap.add_argument("--sizes", nargs="*", type=int, default=[1000, 10000])
    ap.add_argument("--big", action="store_true",
                    help="add N = 100000 (tiled build: about 2.5 GB and 15 min on an idle machine; see --cache)")
    ap.add_argument("--k", type=int, default=20, help="insertions (and deletions of each kind) per N")
    ap.add_argument("--queries", type=int, default=100000)
    ap.add_argument("--ellipses", nargs="*", type=int, default=[1000, 10000],
                    help="N of the ellipse rows (none: skip them)")
    ap.add_argument("--ellipse-k", type=int, default=10, help="insertions (and deletions of each kind) per ellipse N")
    ap.add_argument("--certify-ellipses-up-to", type=int, default=1000,
                    help="ellipse batch builds certified up to this N (the verifier takes ~1 min per 10^3 ellipses)")
    ap.add_argument("--uncertified", action="store_true",
                    help="build and update with certify=False (vertices proved, no edge proofs, never certified): "
                         "for N too large for the verifier's memory")
    ap.add_argument("--segments", nargs="*", type=int, default=None,
                    help="N of the segment rows (insert/delete of segments, runtime/segments/edits.py); given, "
                         "only the segment rows run")
    ap.add_argument("--segment-k", type=int, default=3, help="insertions (and deletions of each kind) per segment N")
    ap.add_argument("--segment-deletes", type=int, default=None,
                    help="deletions of each kind per segment N (default --segment-k; local unless the piece is on the convex hull)")
    ap.add_argument("--arcs", nargs="*", type=int, default=None,
                    help="N of the circular-arc rows (insert/delete of arcs, runtime/segments/edits.py); given, "
                         "only the arc (and --segments) rows run")
    ap.add_argument("--arc-k", type=int, default=3, help="insertions (and deletions of each kind) per arc N")
    ap.add_argument("--arc-deletes", type=int, default=None,
                    help="deletions of each kind per arc N (default --arc-k; local unless the arc is on the convex hull)")
    ap.add_argument("--arc-interior", action="store_true",
                    help="arc rows: insert and delete arcs of grid cells off the border only (bounded regions: the "
                         "local route; an edit reaching the convex hull is a rebuild, the cost of a batch build)")
    ap.add_argument("--arc-seed", type=int, default=1, help="seed of the arc scenes (tests/scenes.random_arcs)")
    ap.add_argument("--no-final-batch", action="store_true",
                    help="arc rows: skip the certified batch build of the final pieces (the comparison)")
    ap.add_argument("--no-write", action="store_true")
    ap.add_argument("--inplace", action="store_true",
                    help="circle updates with inplace=True (the diagram updated in place: no O(N) copy of its lists)")
    ap.add_argument("--max-rss-gb", type=float, default=None,
                    help="address-space limit of each case's process (GB): a case past it stops with MemoryError")
    ap.add_argument("--cache", default=None,
                    help="directory keeping the tiled builds of N > 2·10⁴ circles between runs (pickles)")
    args = ap.parse_args()
    if args.case:
        if args.max_rss_gb:
            lim = int(args.max_rss_gb * 2 ** 30)
            resource.setrlimit(resource.RLIMIT_AS, (lim, lim))
        kind, n = args.case.split(":")
        if kind == "circles":
            res = circles_case(int(n), args.k, certify=not args.uncertified, queries=args.queries,
                               cache=args.cache, inplace=args.inplace)
        elif kind == "segments":
            res = segments_case(int(n), args.segment_k, deletes=args.segment_deletes,
                                final_batch=not args.no_final_batch)
        elif kind == "arcs":
            res = segments_case(int(n), args.arc_k, seed=args.arc_seed, deletes=args.arc_deletes, kind="arcs",
                                interior=args.arc_interior,
                                final_batch=not args.no_final_batch)
        elif kind == "ellipses":
            res = ellipses_case(int(n), args.ellipse_k, certify_build=int(n) <= args.certify_ellipses_up_to)
        else:
            res = nearest_case(int(n), args.queries)
        print(json.dumps(res))
        return
    sizes = list(args.sizes) + ([100000] if args.big else [])
    load0 = _loadavg()
    results = []
    cases = [f"circles:{n}" for n in sizes] + ([] if args.uncertified else ["nearest:10000"])
    cases += [] if args.uncertified else [f"ellipses:{n}" for n in args.ellipses]
    if args.segments is not None or args.arcs is not None:
        cases = [f"segments:{n}" for n in args.segments or []] + [f"arcs:{n}" for n in args.arcs or []]
    for case in cases:
        t0 = time.perf_counter()
        res = subprocess.run([sys.executable, __file__, "--case", case, "--k", str(args.k),
                              "--queries", str(args.queries), "--ellipse-k", str(args.ellipse_k),
                              "--certify-ellipses-up-to", str(args.certify_ellipses_up_to),
                              "--segment-k", str(args.segment_k), "--arc-k", str(args.arc_k)]
                             + (["--segment-deletes", str(args.segment_deletes)] if args.segment_deletes is not None else [])
                             + (["--arc-deletes", str(args.arc_deletes)] if args.arc_deletes is not None else [])
                             + (["--arc-interior"] if args.arc_interior else []) + ["--arc-seed", str(args.arc_seed)]
                             + (["--no-final-batch"] if args.no_final_batch else [])
                             + (["--uncertified"] if args.uncertified else [])
                             + (["--cache", args.cache] if args.cache else [])
                             + (["--inplace"] if args.inplace else [])
                             + (["--max-rss-gb", str(args.max_rss_gb)] if args.max_rss_gb else []),
                             capture_output=True, text=True,
                             env=dict(os.environ, OPENBLAS_NUM_THREADS="1"))
        if res.returncode != 0:
            r = {"case": case, "error": (res.stderr.strip().splitlines() or ["?"])[-1][:200]}
        else:
            r = json.loads(res.stdout.strip().splitlines()[-1])
        r["case_seconds"] = time.perf_counter() - t0
        results.append(r)
        print(case, {k: v for k, v in r.items() if k != "rows"}, file=sys.stderr, flush=True)
    threads = next((r["threads"] for r in results if "threads" in r), None)
    commit = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"], capture_output=True,
                            text=True).stdout.strip()
    lines = [f"## bench_dynamic {time.strftime('%Y-%m-%d %H:%M')}  commit {commit}  OPENBLAS_NUM_THREADS="
             f"{os.environ.get('OPENBLAS_NUM_THREADS')}  threadpools={threads}  cpus={os.cpu_count()}  "
             f"load (/proc/loadavg, 1 min)={load0} (start) {_loadavg()} (end)", "",
             f"Random disjoint circles: batch build of N (certified), then K = {args.k} insertions, K deletions "
             "with renumber=\"last\", K with renumber=\"shift\" (certify=True each"
             f"{', inplace=True' if args.inplace else ''}). \"first\" = the first update "
             "(builds the adjacency state, O(N)); median/max over the others. local = proved locally; infinity = the "
             "unbounded edges and the accounting at infinity re-proved (site on or near the hull); rebuild = the local "
             "splice did not close. CGAL = Apollonius_graph_2 insert/remove on the same doubles, same operations "
             "(tests/cgal/apollonius_dynamic.cpp). direct = updates whose new region was built directly "
             "(runtime/voronoi/star_region.py, hole_region.py) rather than by the construction's local diagram. final verify = "
             "cv.verify on the last diagram.", "",
             "| N | op | first s | median s (CPU) | max s | local / infinity / rebuild | direct | all certified | "
             "median split (locate / local build / prove) | CGAL median s | ratio | build s | final verify | "
             "graph = CGAL | peak RSS MB |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    if not any(str(r.get("case")).startswith("circles") for r in results):
        lines = lines[:2]                  # segment / arc rows only: no circle table
    for r in results:
        if not str(r.get("case")).startswith("circles"):
            continue
        if "error" in r:
            lines.append(f"| {r['case']} | error: {r['error']} |" + " |" * 13)
            continue
        cg = r.get("cgal_op_s")
        k = r["K"]
        for kind, lo, hi in (("insert", 0, k), ("delete (last)", k, 2 * k), ("delete (shift)", 2 * k, 3 * k)):
            rows = [x for x in r["rows"] if x["op"] == kind]
            first = rows[0]["wall"] if kind == "insert" else None
            rest = rows[1:] if kind == "insert" else rows
            med = statistics.median(x["wall"] for x in rest)
            medc = statistics.median(x["cpu"] for x in rest)
            mx = max(x["wall"] for x in rest)
            hows = [x["how"] or "" for x in rows]
            n_inf = sum("infinity" in h for h in hows)
            n_reb = sum(h.startswith("rebuild") or h in ("local triangulation declined", "local sample triangulation")
                        for h in hows)
            n_loc = len(hows) - n_inf - n_reb
            spl = [x["split"] for x in rest if "prove" in x["split"]]
            split = " / ".join(_fmt(statistics.median(s.get(key, 0) for s in spl)) for key in
                               ("locate", "local build", "prove")) if spl else "-"
            cgm = statistics.median(cg[lo:hi]) if cg else None
            ratio = f"{med / cgm:.0f}×" if cgm else "-"
            lines.append(f"| {r['N']} | {kind} | {_fmt(first)} | {_fmt(med)} ({_fmt(medc)}) | {_fmt(mx)} | "
                         f"{n_loc} / {n_inf} / {n_reb} | {sum(bool(x.get('direct')) for x in rows)} | "
                         f"{all(x['certified'] for x in rows)} | {split} | "
                         f"{_fmt(cgm, 6)} | {ratio} | {r['build_s']:.1f} | "
                         f"{_verified(r)} | "
                         f"{r.get('cgal_same_graph', r.get('cgal_error', '-'))} | {r['peak_rss_mb']:.0f} |")
    qrows = [r for r in results if str(r.get("case")).startswith("circles") and "nearest_qps" in r]
    if qrows:
        lines += ["", f"Nearest-site queries on the circle diagrams above (right after the build), {args.queries} "
                  "random query points in the box of the centres (queries/s); CGAL = Apollonius_graph_2::nearest_neighbor "
                  "on the same circles:", "",
                  "| N | build | d.nearest proved | proved rows | CGAL nearest_neighbor | proved answers = CGAL's |",
                  "|---|---|---|---|---|---|"]
        for r in qrows:
            lines.append(f"| {r['N']} | {r.get('build_how', 'voronoi')} | {r['nearest_qps']:.3g} | "
                         f"{r['nearest_proved']:.4f} | {r.get('cgal_nearest_qps', 0):.3g} | "
                         f"{r.get('cgal_nearest_same', r.get('cgal_nearest_error'))} |")
    for r in results:
        if str(r.get("case")) != "nearest" or "error" in r:
            if "error" in r and "nearest" in r.get("case", ""):
                lines += ["", f"nearest: error {r['error']}"]
            continue
        lines += ["", f"Nearest-site queries, N = {r['N']} random points, {r['Q']} random queries (queries/s):", "",
                  "| d.nearest proved | proved rows | d.nearest(prove=False) | scipy cKDTree.query | "
                  "CGAL nearest_neighbor | proved answers = scipy's | = CGAL's |",
                  "|---|---|---|---|---|---|---|",
                  f"| {r['proved_qps']:.3g} | {r['proved_fraction']:.4f} | {r['float_qps']:.3g} | "
                  f"{r['scipy_qps']:.3g} | "
                  f"{r.get('cgal_qps', 0):.3g} | {r['same_as_scipy']} | {r.get('cgal_same', r.get('cgal_error'))} |"]
    lines += _ellipse_table(results, args)
    lines += _segment_table(results, args)
    lines += _segment_table(results, args, "arcs")
    text = "\n".join(lines) + "\n"
    print(text)
    if not args.no_write:
        out = ROOT / "bench" / "results" / "dynamic.md"
        with open(out, "a") as fh:
            fh.write(("\n" if out.exists() and out.stat().st_size else "") + text)


if __name__ == "__main__":
    main()
