"""Where the resident memory of ``voronoi`` goes: the peak RSS of each phase of the construction.

A sampler thread reads this process's RSS (``/proc/self/statm``) every 20 ms and charges it to the
phase running: the sample triangulation (``Samples.triangulation``: qhull or the local update),
the walks (``SampleTriangulation.walks``), the vertices (``apollonius_vertices``), their emptiness
(``prove_empty``), the near-degenerate groups, the assembly, the contact order, the hull check,
the edge polylines and (``--certify``) the verifier.  The phases are found by wrapping the
functions that :mod:`runtime.voronoi.construction` calls (names looked up in its namespace), so
the construction itself is unchanged.  Figures are MB above the RSS once the library is imported
(a three-circle diagram built) and the sites made; a phase name repeated with ``#k`` is its k-th
round.  Linux only.

Run:  OPENBLAS_NUM_THREADS=1 python bench/memory_phases.py 30000 [--certify] [--scene clustered] [--whole-qhull]
"""
from __future__ import annotations

import argparse
import os
import sys
import threading
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))


def rss_mb() -> float:
    with open("/proc/self/statm") as fh:
        return int(fh.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2 ** 20


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("n", type=int)
    ap.add_argument("--certify", action="store_true")
    ap.add_argument("--scene", choices=("random", "clustered"), default="random")
    ap.add_argument("--whole-qhull", action="store_true",
                    help="qhull on all samples at once (no strips: the figures before strip_delaunay)")
    a = ap.parse_args()
    import scenes
    from curvedvoronoi.runtime.voronoi import construction as C
    from curvedvoronoi.runtime.voronoi import sample_delaunay as SD
    from curvedvoronoi.runtime.voronoi import strip_delaunay
    if a.whole_qhull:
        strip_delaunay.STRIP_POINTS = 1 << 62

    sites = (scenes.clustered_circles(a.n, 31, cluster=0.1) if a.scene == "clustered"
             else scenes.random_disjoint_circles(a.n, 1))
    C.voronoi([(0, 0, 1), (4, 0, 1), (2, 4, 1)], certify=a.certify, progress=False)
    phase, peaks, order, count = ["start"], {}, [], {}

    def enter(label):
        count[label] = count.get(label, 0) + 1
        phase[0] = f"{label}#{count[label]}"

    def wrap(owner, name, label):
        f = getattr(owner, name)

        def g(*args, **kw):
            enter(label)
            try:
                return f(*args, **kw)
            finally:
                phase[0] = f"between ({label} done)"
        setattr(owner, name, g)

    for name, label in [("apollonius_vertices", "vertices"), ("prove_empty", "emptiness"),
                        ("near_degenerate_clusters", "near-degenerate"), ("assemble_vertices", "assembly"),
                        ("contact_order_triples", "contact order"), ("hull_neighbours", "hull check"),
                        ("edge_polylines", "edge polylines")]:
        wrap(C, name, label)
    wrap(C.Samples, "triangulation", "sample triangulation")
    wrap(SD.SampleTriangulation, "walks", "walks")
    if a.certify:
        from curvedvoronoi.runtime.voronoi.verify import certificate
        wrap(certificate, "verify", "verifier")
    base = rss_mb()
    stop = [False]

    def sampler():
        while not stop[0]:
            r, p = rss_mb(), phase[0]
            if p not in peaks:
                order.append(p)
            peaks[p] = max(peaks.get(p, 0.0), r)
            time.sleep(0.02)

    th = threading.Thread(target=sampler, daemon=True)
    th.start()
    t = time.perf_counter()
    d = C.voronoi(sites, certify=a.certify, progress=False)
    seconds = time.perf_counter() - t
    phase[0] = "end"
    time.sleep(0.1)
    stop[0] = True
    th.join()
    print(f"n={a.n} scene={a.scene} certify={a.certify}: {d.stats.get('samples')} samples, "
          f"{d.stats.get('rounds')} rounds, {len(d.vertices)} vertices, {len(d.edges)} edges, "
          f"certified={d.certified}, {seconds:.1f} s, RSS with the input {base:.0f} MB, "
          f"{d.stats.get('triangulations')} full triangulations (strips: {not a.whole_qhull}), "
          f"load {os.getloadavg()[0]:.2f}")
    print("| phase | peak RSS above the input MB | kB per site |\n|---|---:|---:|")
    for p in order:
        print(f"| {p} | {peaks[p] - base:.0f} | {(peaks[p] - base) * 1024 / a.n:.1f} |")


if __name__ == "__main__":
    main()
