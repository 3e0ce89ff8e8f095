"""Benchmark: the certified diagram of random disjoint ellipses, construction against certificate.

Scene: ``random_ellipses(n, seed)`` of tests/scenes.py (disjoint circumscribed discs, exact
rational coefficients, centres in a square of side 8·√n).  Each row runs in a fresh Python process
and builds ``voronoi(certify=True)``.  Certificate seconds: the verifier's time
(``stats["seconds"]["verify"]``, summed over its runs when a verifier fault drives a rebuild);
construction seconds: the rest of the wall time; the same split in CPU seconds of the process (the
figures to compare on a loaded machine), its peak RSS
(``ru_maxrss``: input, construction and verifier together), the verdict and the number of
problems left.  One BLAS thread (OPENBLAS_NUM_THREADS=1).  Other processes on the machine make
figures noisy: the load average is recorded before and after each row.

Run:  python bench/bench_ellipses.py [--sizes 2000,10000] [--seed 1] [--max-rss-gb G] [--append]
(writes bench/results/ellipses.md; ``--append`` adds a dated section instead of replacing it;
``--max-rss-gb G`` caps each row's address space, RLIMIT_AS, at G GB).  Target (issue: ellipses):
10⁴ ellipses certified in ≤ 30 s, the certificate ≤ 2× the construction.
"""
from __future__ import annotations

import argparse
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


def _loadavg() -> str:
    try:
        with open("/proc/loadavg") as fh:
            return " ".join(fh.read().split()[:3])
    except OSError:
        return "n/a"


def one(n: int, seed: int) -> dict:
    """One row, in this process."""
    import curvedvoronoi as cv
    from scenes import random_ellipses

    from curvedvoronoi.runtime.voronoi.verify import certificate

    sites = random_ellipses(n, seed)
    verify, spent = certificate.verify, [0.0]

    def timed_verify(*args, **kw):           # the verifier's CPU time (the build imports it per call)
        c0 = time.process_time()
        try:
            return verify(*args, **kw)
        finally:
            spent[0] += time.process_time() - c0

    certificate.verify = timed_verify
    load0 = _loadavg()
    t, c = time.perf_counter(), time.process_time()
    d = cv.voronoi(sites, certify=True, progress=False)
    wall, cpu = time.perf_counter() - t, time.process_time() - c
    certificate.verify = verify
    cert = float(d.stats["seconds"].get("verify", 0.0))
    return {"n": n, "seed": seed, "wall": wall, "cpu": cpu, "certificate": cert, "construction": wall - cert,
            "certificate_cpu": spent[0], "construction_cpu": cpu - spent[0],
            "certified": bool(d.certified), "problems": len(d.problems), "vertices": len(d.vertices),
            "edges": len(d.edges), "rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
            "load": f"{load0} / {_loadavg()}"}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="2000,10000")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--max-rss-gb", type=float, default=0.0)
    ap.add_argument("--out", default=str(ROOT / "bench" / "results" / "ellipses.md"))
    ap.add_argument("--append", action="store_true")
    ap.add_argument("--one", nargs=2, type=int, metavar=("N", "SEED"), help=argparse.SUPPRESS)
    a = ap.parse_args()
    if a.one:
        if a.max_rss_gb:
            lim = int(a.max_rss_gb * 2 ** 30)
            resource.setrlimit(resource.RLIMIT_AS, (lim, lim))
        print(json.dumps(one(*a.one)))
        return
    rows = []
    for n in [int(s) for s in a.sizes.split(",") if s]:
        cmd = [sys.executable, __file__, "--one", str(n), str(a.seed)]
        if a.max_rss_gb:
            cmd += ["--max-rss-gb", str(a.max_rss_gb)]
        r = subprocess.run(cmd, capture_output=True, text=True, env={**os.environ, "OPENBLAS_NUM_THREADS": "1"})
        if r.returncode != 0 or not r.stdout.strip():
            tail = (r.stderr.strip().splitlines() or ["no output"])[-1][:120]
            rows.append({"n": n, "seed": a.seed, "error": tail})
        else:
            rows.append(json.loads(r.stdout.strip().splitlines()[-1]))
        print(rows[-1], flush=True)
    started = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    cmd = "OPENBLAS_NUM_THREADS=1 python bench/bench_ellipses.py --sizes " + a.sizes + f" --seed {a.seed}" + \
        (f" --max-rss-gb {a.max_rss_gb:g}" if a.max_rss_gb else "")
    lines = [f"## Run of {started}", "", f"Command: `{cmd}`; one BLAS thread; each row in a fresh process.", "",
             "| N | construction s (CPU) | certificate s (CPU) | ratio (CPU) | wall s | CPU s | peak RSS MB | "
             "certified | problems | vertices | edges | load before / after |", "|" + "---|" * 12]
    for r in rows:
        if "error" in r:
            lines.append(f"| {r['n']} | error: {r['error']} |" + " |" * 10)
            continue
        lines.append(f"| {r['n']} | {r['construction']:.1f} ({r['construction_cpu']:.1f}) | "
                     f"{r['certificate']:.1f} ({r['certificate_cpu']:.1f}) | "
                     f"{r['certificate'] / max(r['construction'], 1e-9):.2f} "
                     f"({r['certificate_cpu'] / max(r['construction_cpu'], 1e-9):.2f}) | {r['wall']:.1f} | {r['cpu']:.1f} | "
                     f"{r['rss_mb']:.0f} | {r['certified']} | {r['problems']} | {r['vertices']} | {r['edges']} | "
                     f"{r['load']} |")
    text = "\n".join(lines) + "\n"
    out = Path(a.out)
    if a.append and out.exists():
        out.write_text(out.read_text() + "\n" + text)
    else:
        out.write_text("# Random ellipses: construction and certificate (bench/bench_ellipses.py)\n\n" + text)


if __name__ == "__main__":
    main()
