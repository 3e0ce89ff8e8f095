"""Build and run the CGAL Apollonius-graph peer (apollonius_edges.cpp), shared by tests/test_cgal.py
and bench/bench_voronoi.py.  The binary is cached in the temp directory, keyed by the source hash."""
from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))     # tests/: the shared scenes
from scenes import random_disjoint_circles  # noqa: E402,F401  (re-exported: the peer's scenes are the tests')

SOURCE = Path(__file__).with_name("apollonius_edges.cpp")
HEADER = "/usr/include/CGAL/Apollonius_graph_2.h"


class PeerMissing(RuntimeError):
    """g++ or CGAL (Debian package libcgal-dev) is not installed."""


def build() -> Path:
    """Compile the peer once (about 20 s of CPU) and return the path of the binary."""
    return compile_peer(SOURCE, "ag")


def compile_peer(source: Path, tag: str) -> Path:
    """Compile a CGAL peer program once per source hash (g++ -O2, into the temporary directory,
    atomically renamed) and return the path of the binary; ``PeerMissing`` without g++ or CGAL."""
    gxx = shutil.which("g++")
    if gxx is None:
        raise PeerMissing("g++ not found (apt-get install g++)")
    if not os.path.exists(HEADER):
        raise PeerMissing("CGAL headers not found (apt-get install libcgal-dev)")
    digest = hashlib.sha256(source.read_bytes()).hexdigest()[:16]
    out = Path(tempfile.gettempdir()) / f"curvedvoronoi_cgal_{tag}_{digest}"
    if not out.exists():
        tmp = out.with_suffix(f".{os.getpid()}.tmp")
        subprocess.run([gxx, "-O2", "-std=c++17", "-DNDEBUG", "-o", str(tmp), str(source)], check=True,
                       capture_output=True, text=True)
        os.replace(tmp, out)
    return out


def delaunay_edges(circles) -> tuple[list[tuple[int, int]], float, int]:
    """CGAL's Apollonius graph of (x, y, r) float circles: (sorted edges, build seconds, hidden count)."""
    binary = build()
    lines = [str(len(circles))] + [f"{x!r} {y!r} {r!r}" for x, y, r in circles]
    res = subprocess.run([str(binary)], input="\n".join(lines) + "\n", capture_output=True, text=True, check=True)
    out = res.stdout.split("\n")
    hidden = int(out[0].split()[1])
    seconds = float(out[1].split()[1])
    edges = sorted(tuple(int(t) for t in ln.split()) for ln in out[2:] if ln.strip())
    return edges, seconds, hidden


def delaunay_edges_nondegenerate(circles):
    """CGAL's Apollonius graph of (x, y, r) float circles without its degenerate edges (the binary's
    ``--degenerate`` mode: CGAL's exact Is_degenerate_edge_2 on the two triangles of each edge).

    Returns (sorted pairs sharing a Voronoi edge of positive length, build seconds, hidden count,
    triangulation edges as (i, j, degenerate, length) with the double-precision length of the dual
    Voronoi edge, inf for an unbounded one).  Apollonius_graph_2 is a triangulation: on co-circular
    input it also lists pairs whose Voronoi edge has length zero; those are left out of the pairs."""
    binary = build()
    lines = [str(len(circles))] + [f"{x!r} {y!r} {r!r}" for x, y, r in circles]
    res = subprocess.run([str(binary), "--degenerate"], input="\n".join(lines) + "\n", capture_output=True,
                         text=True, check=True)
    out = res.stdout.split("\n")
    hidden = int(out[0].split()[1])
    seconds = float(out[1].split()[1])
    raw = []
    for ln in out[2:]:
        if ln.strip():
            i, j, dg, length = ln.split()
            raw.append((int(i), int(j), dg == "1", float(length)))
    edges = sorted({(i, j) for i, j, dg, _ in raw if not dg})
    return edges, seconds, hidden, raw


