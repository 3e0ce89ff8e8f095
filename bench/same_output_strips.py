"""Same diagram with the sample triangulation strip by strip (runtime/voronoi/strip_delaunay.py)
as with qhull on all samples: builds ``voronoi`` twice in one process (strips off, then on) on
``random_disjoint_circles(n, seed)`` and compares ``to_json()`` without the statistics: Delaunay
edges, vertices (ids, sites, coordinates), edges as (sites, ends) with their polylines (either
direction), verdicts.  Below 5 000 sites the strips are forced (3 000 points, from any count).

Run:  OPENBLAS_NUM_THREADS=1 python bench/same_output_strips.py 10000 1,2,3 [cert]
"""
import os
import sys
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))
import json  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402
import scenes  # noqa: E402
from curvedvoronoi.runtime.voronoi import construction as C  # noqa: E402
from curvedvoronoi.runtime.voronoi import sampling as SM  # noqa: E402
from curvedvoronoi.runtime.voronoi import strip_delaunay as SD  # noqa: E402


def edge_map(doc):
    return {(tuple(sorted(e["sites"])), tuple(sorted(map(str, e["ends"])))): e for e in doc["edges"]}


def compare(j0, j1):
    V0 = np.array([[v["x"], v["y"], v["radius"]] for v in j0["vertices"]])
    V1 = np.array([[v["x"], v["y"], v["radius"]] for v in j1["vertices"]])
    same_sites = [v["sites"] for v in j0["vertices"]] == [v["sites"] for v in j1["vertices"]]
    differ = int((V0 != V1).any(axis=1).sum()) if V0.shape == V1.shape else -1
    rel = float((np.abs(V0 - V1) / np.maximum(np.abs(V0), 1)).max()) if differ > 0 else 0.0
    E0, E1 = edge_map(j0), edge_map(j1)
    same_keys = E0.keys() == E1.keys() and len(E0) == len(j0["edges"])
    worst, other_length, flags = 0.0, 0, 0
    for k, a in E0.items():
        b = E1.get(k)
        if b is None:
            continue
        pa, pb = np.array(a["polyline"]), np.array(b["polyline"])
        if pa.shape != pb.shape:
            other_length += 1
            continue
        d = min(np.abs(pa - pb).max(), np.abs(pa - pb[::-1]).max()) if len(pa) else 0.0
        worst = max(worst, float(d / max(1.0, np.abs(pa).max())))
        flags += a["certified"] != b["certified"]
    others = all(j0[k] == j1[k] for k in j0 if k not in ("vertices", "edges"))
    print(f"  vertices: same ids and sites {same_sites}, {differ} differ, max relative difference {rel:.1e}; "
          f"edges: same (sites, ends) {same_keys}, {other_length} polylines of another length, "
          f"max relative difference {worst:.1e}, certified flags differing {flags}; "
          f"Delaunay edges, verdict, problems, sites equal {others}")


def main():
    n, seeds = int(sys.argv[1]), [int(x) for x in sys.argv[2].split(",")]
    cert = len(sys.argv) > 3 and sys.argv[3] == "cert"
    if n < 5000:
        SM.JOGGLE_ABOVE, SD.STRIP_POINTS = 0, 3000
    used = [0]
    real = SD.strip_delaunay

    def counted(*a, **k):
        r = real(*a, **k)
        used[0] += r is not None
        return r
    SM.strip_delaunay = counted
    for seed in seeds:
        sites = scenes.random_disjoint_circles(n, seed)
        runs = []
        for strips in (False, True):
            keep = SD.STRIP_POINTS
            if not strips:
                SD.STRIP_POINTS = 1 << 62
            used[0], t = 0, time.perf_counter()
            d = C.voronoi(sites, certify=cert, progress=False)
            SD.STRIP_POINTS = keep
            doc = d.to_json()
            doc.pop("stats", None)
            runs.append((d, json.loads(json.dumps(doc)), used[0], time.perf_counter() - t))
            del d
        (d0, j0, _, s0), (d1, j1, u1, s1) = runs
        print(f"n={n} seed={seed}: strip triangulations {u1}; same JSON {j0 == j1}; same Delaunay edges "
              f"{j0['delaunay_edges'] == j1['delaunay_edges']} ({len(j0['delaunay_edges'])}); certified "
              f"{d0.certified}/{d1.certified}; seconds {s0:.1f}/{s1:.1f}; load {os.getloadavg()[0]:.2f}")
        if j0 != j1:
            compare(j0, j1)


if __name__ == "__main__":
    main()
