"""Benchmark: the diagram of many circles in one process against the tiled diagram
(runtime/voronoi/distributed.py) built sequentially and on a distributed.LocalCluster of 1 and 2
worker processes.

Scene: random disjoint circles of tests/scenes.py (``random_disjoint_circles(n, 1)``).  Each row
runs in a fresh Python process (so peak RSS is the row's own) and builds the certified diagram:
``voronoi(certify=True)`` or ``tiled_voronoi(certify=True)``.  Certificate seconds: the
verifier's time (``stats["seconds"]["verify"]``; with the rebuilds it drives, the sum of its
runs), in the driver process or, on a cluster, in chunks on the workers (column "route");
construction seconds: the rest of the wall time (tiles, stitch, refinement rebuilds).  Also the
driver's and the largest worker's peak RSS, the number of tiles, halo growths, and whether the
Delaunay graph equals the one-process graph.  LocalCluster start-up is not counted (it is
reported apart).

Run:  python bench/bench_scale.py [--sizes 10000,100000] [--modes single,tiled,cluster1,cluster2]
(writes bench/results/scale.md).  ``--scene clustered`` uses ``clustered_circles(n, 31, cluster=0.1)``
(a dense cluster, one circle larger than a tile); ``--cgal`` also builds CGAL's Apollonius graph
(tests/cgal/cgal_peer.py) in the row's process and reports whether the Delaunay graph equals it;
``--max-rss-gb G`` caps each row's address space (RLIMIT_AS) at G GB; ``--append`` adds a dated
section to the results file instead of replacing it; ``--no-certify`` times the construction only.
Memory: each row also reports its RSS once the input is built (sites, and CGAL's graph with
``--cgal``) and the library imported (a three-circle diagram built), and the peak RSS of the
construction from there (Linux: VmHWM reset by
``/proc/self/clear_refs``), i.e. the peak above the footprint with the input, per site.
One BLAS thread (OPENBLAS_NUM_THREADS=1 and threadpoolctl inside the calls); workers have one thread
each.  Other processes on the machine make figures noisy: the
load average is recorded before and after.
"""
from __future__ import annotations

import argparse
import hashlib
import json
import os
import resource
import subprocess
import sys
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))


def sites_per_tile(n: int) -> int:
    """About 16 tiles from 10⁵ sites, 4 from 10⁴ (a few tiles per worker)."""
    return max(2000, n // 16) if n >= 40000 else max(1000, n // 4)


def _rss_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def _status_mb(field: str) -> float:
    """VmRSS / VmHWM of this process (Linux), MB."""
    with open("/proc/self/status") as fh:
        for line in fh:
            if line.startswith(field + ":"):
                return int(line.split()[1]) / 1024.0
    return float("nan")


def _reset_peak() -> bool:
    """Reset this process's peak RSS (VmHWM) to its current RSS (Linux: clear_refs 5)."""
    try:
        with open("/proc/self/clear_refs", "w") as fh:
            fh.write("5")
        return True
    except OSError:
        return False


def scene(name: str, n: int):
    import scenes

    if name == "clustered":
        return scenes.clustered_circles(n, 31, cluster=0.1)
    return scenes.random_disjoint_circles(n, 1)


def one(mode: str, n: int, scene_name: str = "random", cgal: bool = False, certify: bool = True,
        certificate: str = "whole") -> dict:
    """One row, in this process."""
    import curvedvoronoi as cv

    sites = scene(scene_name, n)
    out = {"mode": mode, "n": n, "sites": len(sites), "scene": scene_name}
    if cgal:
        sys.path.insert(0, str(ROOT / "tests" / "cgal"))
        import cgal_peer

        expected, out["cgal_seconds"], _ = cgal_peer.delaunay_edges(sites)
    client = cluster = None
    if mode.startswith("cluster"):
        from distributed import Client, LocalCluster

        t = time.perf_counter()
        import dask

        # the scheduler runs in this (driver) process, which also stitches and serialises the chunks:
        # a worker's heartbeat can wait minutes at 10⁶ sites, and the default worker-ttl (5 min)
        # then drops a live worker (seen at 10⁶ in session 32)
        with dask.config.set({"distributed.scheduler.worker-ttl": "1h"}):
            cluster = LocalCluster(n_workers=int(mode[-1]), threads_per_worker=1, processes=True,
                                   dashboard_address=None, env={"OPENBLAS_NUM_THREADS": "1"})
        client = Client(cluster)
        out["startup"] = time.perf_counter() - t
    # the footprint with the input: the library imported (a three-circle diagram built), the sites (and
    # CGAL's graph) made; the peak is measured from here
    cv.voronoi([(0, 0, 1), (4, 0, 1), (2, 4, 1)], certify=certify, progress=False)
    out["peak_reset"] = _reset_peak()
    out["rss_input"] = _status_mb("VmRSS")
    t = time.perf_counter()
    if mode == "single":
        d = cv.voronoi(sites, certify=certify, progress=False)
    else:
        d = cv.tiled_voronoi(sites, client=client, sites_per_tile=sites_per_tile(n), certify=certify,
                             progress=False, certificate=certificate)
        info = d.stats["tiling"]
        out["tiles"], out["growths"], out["rim_sites"] = info.get("tiles"), info.get("halo_growths"), info.get("rim_sites")
        out["refined"] = info.get("refined_by_verifier")
        out["route"] = info.get("certificate", "whole")
    total = time.perf_counter() - t
    out["certificate"] = float(d.stats["seconds"].get("verify", 0.0))
    out["construction"] = total - out["certificate"]
    out["certified"] = bool(d.certified)
    out["graph"] = hashlib.sha256(json.dumps(d.delaunay_edges()).encode()).hexdigest()[:12]
    out["rounds"] = d.stats.get("rounds")
    if cgal:
        got = d.delaunay_edges()
        out["equals_cgal"] = got == expected
        out["missing_vs_cgal"] = len(set(map(tuple, expected)) - set(map(tuple, got)))
    out["rss_driver"] = _rss_mb()
    out["rss_peak"] = _status_mb("VmHWM")         # since the reset: the construction's own peak
    if client is not None:
        out["rss_worker"] = max(client.run(_rss_mb).values())
        client.close()
        cluster.close()
    return out


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--sizes", default="10000,100000")
    ap.add_argument("--modes", default="single,tiled,cluster1,cluster2")
    ap.add_argument("--one", nargs=2, metavar=("MODE", "N"))
    ap.add_argument("--out", default=str(ROOT / "bench" / "results" / "scale.md"))
    ap.add_argument("--scene", choices=("random", "clustered"), default="random")
    ap.add_argument("--cgal", action="store_true")
    ap.add_argument("--max-rss-gb", type=float, default=None)
    ap.add_argument("--append", action="store_true")
    ap.add_argument("--no-certify", action="store_true", help="construction only (certified is then 'no')")
    ap.add_argument("--certificate", choices=("whole", "chunks"), default="whole",
                    help="tiled rows: the stitched diagram proved whole or chunk by chunk (tiled_voronoi)")
    a = ap.parse_args()
    if a.one:
        if a.max_rss_gb:
            cap = int(a.max_rss_gb * 2 ** 30)
            resource.setrlimit(resource.RLIMIT_AS, (cap, cap))
        print(json.dumps(one(a.one[0], int(a.one[1]), a.scene, a.cgal, not a.no_certify, a.certificate)))
        return
    load0 = os.getloadavg()
    started = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    rows = []
    for n in [int(s) for s in a.sizes.split(",")]:
        for mode in a.modes.split(","):
            extra = ["--scene", a.scene] + (["--cgal"] if a.cgal else []) + \
                (["--max-rss-gb", str(a.max_rss_gb)] if a.max_rss_gb else []) + \
                (["--no-certify"] if a.no_certify else []) + ["--certificate", a.certificate]
            t_row = time.strftime("%H:%M", time.gmtime())
            load_row = os.getloadavg()[0]
            r = subprocess.run([sys.executable, __file__, "--one", mode, str(n), *extra], capture_output=True, text=True,
                               env=dict(os.environ, OPENBLAS_NUM_THREADS="1"))
            if r.returncode != 0:
                print(r.stderr[-3000:], file=sys.stderr)
                rows.append({"mode": mode, "n": n, "error": r.stderr.strip().splitlines()[-1][:120],
                             "started": t_row, "load": load_row})
                continue
            rows.append(json.loads(r.stdout.strip().splitlines()[-1]))
            rows[-1].update(started=t_row, load=load_row)
            print(rows[-1], flush=True)
    load1 = os.getloadavg()
    base = {r["n"]: r for r in rows if r["mode"] == "single" and "error" not in r}
    flags = (f" --scene {a.scene}" if a.scene != "random" else "") + (" --cgal" if a.cgal else "") + \
        (f" --max-rss-gb {a.max_rss_gb:g}" if a.max_rss_gb else "") + (" --append" if a.append else "") + \
        (" --no-certify" if a.no_certify else "") + \
        (f" --certificate {a.certificate}" if a.certificate != "whole" else "")
    lines = ["# Tiled diagrams: one process, tiles in sequence, LocalCluster of 1 and 2 workers"
             if not a.append else f"## Run of {started}: {a.scene} circles", "",
             f"Command: `OPENBLAS_NUM_THREADS=1 .venv/bin/python bench/bench_scale.py --sizes {a.sizes} "
             f"--modes {a.modes}{flags}`", "",
             f"Date: {started}; machine: {os.cpu_count()} cores shared with other jobs; load average "
             f"{load0[0]:.2f} before, {load1[0]:.2f} after.  One BLAS thread; LocalCluster(processes=True, "
             "threads_per_worker=1); every row in a fresh process; scene "
             f"`{'clustered_circles(n, 31, cluster=0.1)' if a.scene == 'clustered' else 'random_disjoint_circles(n, 1)'}`.",
             f"Rows: `voronoi(certify={not a.no_certify})` or `tiled_voronoi(certify={not a.no_certify})`; "
             "certificate s = the verifier's time "
             "(route `whole`: in the driver process; `chunks`: vertex and edge proofs on the workers, closure here); "
             "construction s = the rest of the wall time.", "",
             "| n | mode | tiles | halo growths | rim sites | construction s | vs one process | certificate s | "
             "certificate route | certified | same graph | driver RSS MB | worker RSS MB | cluster start s |",
             "|---:|---|---:|---:|---:|---:|---:|---:|---|---|---|---:|---:|---:|"]
    for r in rows:
        if "error" in r:
            lines.append(f"| {r['n']} | {r['mode']} | error: {r['error']} |" + " |" * 10)
            continue
        b = base.get(r["n"])
        ratio = f"{r['construction'] / b['construction']:.2f}" if b else "-"
        same = ("yes" if r["graph"] == b["graph"] else "NO") if b else "-"
        lines.append(f"| {r['n']} | {r['mode']} | {r.get('tiles', 1)} | {r.get('growths', '-')} | "
                     f"{r.get('rim_sites') or '-'} | {r['construction']:.1f} | {ratio} | {r['certificate']:.1f} | "
                     f"{r.get('route', 'whole')} | {'yes' if r['certified'] else 'no'} | {same} | {r['rss_driver']:.0f} | "
                     f"{r['rss_worker']:.0f} | {r['startup']:.1f} |".replace("| None |", "| - |")
                     if "rss_worker" in r else
                     f"| {r['n']} | {r['mode']} | {r.get('tiles', 1)} | {r.get('growths', '-')} | "
                     f"{r.get('rim_sites') or '-'} | {r['construction']:.1f} | {ratio} | {r['certificate']:.1f} | "
                     f"{r.get('route', 'whole')} | {'yes' if r['certified'] else 'no'} | {same} | {r['rss_driver']:.0f} | - | - |")
    if a.cgal or a.append:
        lines += ["", "Per row: sites, refinement rounds, CGAL `Apollonius_graph_2` build seconds and whether the "
                  "Delaunay graph equals CGAL's (missing edges), row start (UTC) and load average then.", "",
                  "| n | mode | sites | rounds | CGAL s | = CGAL | missing | started | load |",
                  "|---:|---|---:|---:|---:|---|---:|---|---:|"]
        for r in rows:
            eq = r.get("equals_cgal")
            lines.append(f"| {r['n']} | {r['mode']} | {r.get('sites', '-')} | {r.get('rounds', '-')} | "
                         f"{r['cgal_seconds']:.2f} | " if "cgal_seconds" in r else
                         f"| {r['n']} | {r['mode']} | {r.get('sites', '-')} | {r.get('rounds', '-')} | - | ")
            lines[-1] += (f"{'-' if eq is None else ('yes' if eq else 'NO')} | {r.get('missing_vs_cgal', '-')} | "
                          f"{r.get('started', '-')} | {r.get('load', 0):.2f} |")
    mem = [r for r in rows if "rss_peak" in r and r.get("peak_reset")]
    if mem:
        lines += ["", "Memory: RSS with the input built (sites, CGAL's graph), the peak RSS of the construction "
                  "(VmHWM reset before it; certified rows include the verifier), and the peak above the input "
                  "per site.", "",
                  "| n | mode | certify | input RSS MB | peak RSS MB | above input MB | kB per site |",
                  "|---:|---|---|---:|---:|---:|---:|"]
        for r in mem:
            above = r["rss_peak"] - r["rss_input"]
            lines.append(f"| {r['n']} | {r['mode']} | {'no' if a.no_certify else 'yes'} | {r['rss_input']:.0f} | "
                         f"{r['rss_peak']:.0f} | {above:.0f} | {above * 1024 / r['sites']:.1f} |")
    if a.append:
        with open(a.out, "a") as fh:
            fh.write("\n" + "\n".join(lines) + "\n")
    else:
        Path(a.out).write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
