"""Certificate of single scenes with an elliptic piece (bench/results/elliptic_arcs.md, "The first
certified diagram with an elliptic piece"): edges and vertices proved, construction and certificate
CPU seconds (time.process_time), wall seconds and /proc/loadavg, one markdown row per scene.

Command: OPENBLAS_NUM_THREADS=1 .venv/bin/python bench/bench_elliptic_certified.py [scene names]
"""
import sys, time
import curvedvoronoi as cv
from curvedvoronoi.runtime.segments.certificate import verify_segments
RING = [(4, 0), (3, 3), (0, 4), (-3, 2), (-3, -2), (0, -3), (3, -3)]
SCENES = {
    "quarter arc 0.2..1.3 in the ring": lambda: [cv.Arc.elliptic((0, 0), (2, 0), "1/2", 0.2, 1.3)] + RING,
    "arc 0.3..2.5 in the ring": lambda: [cv.Arc.elliptic((0, 0), (2, 0), "1/2", 0.3, 2.5)] + RING,
    "arc (0,0),(4,0),1/2, 0.3..2.5 + 3 points": lambda: [cv.Arc.elliptic((0, 0), (4, 0), "1/2", 0.3, 2.5), (0, 5), (3, -2), (-4, 3)],
}
for name in sys.argv[1:] or SCENES:
    load0 = open("/proc/loadavg").read().split()[:3]
    t = time.process_time()
    D = cv.voronoi(SCENES[name](), certify=False)
    tb = time.process_time() - t
    t, w = time.process_time(), time.perf_counter()
    C = verify_segments(D)
    tc, wc = time.process_time() - t, time.perf_counter() - w
    load1 = open("/proc/loadavg").read().split()[:3]
    print(f"| {name} | {sum(C.edges)} / {len(C.edges)} | {sum(C.vertices)} / {len(C.vertices)} | {'yes' if C.ok else 'no'} | "
          f"{tb:.2f} | {tc:.2f} / {wc:.2f} | `{' '.join(load0)}` → `{' '.join(load1)}` |", flush=True)
    for p in C.problems[:6]:
        print("   ", p, flush=True)
