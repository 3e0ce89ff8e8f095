"""Build and run the CGAL Apollonius-graph dynamic peer (apollonius_dynamic.cpp: insertions and
removals), shared by tests/test_insertion.py and bench/bench_dynamic.py.  The binary is cached in
the temp directory, keyed by the source hash, like :mod:`cgal_peer`."""
from __future__ import annotations

import subprocess
from pathlib import Path

from cgal_peer import PeerMissing, compile_peer  # noqa: F401  (PeerMissing: re-exported)

SOURCE = Path(__file__).with_name("apollonius_dynamic.cpp")


def build() -> Path:
    """Compile the peer once (about 20 s of CPU) and return the path of the binary."""
    return compile_peer(SOURCE, "agdyn")


def run(circles, ops, queries=None):
    """Build CGAL's Apollonius graph of ``circles`` ((x, y, r) floats), then apply ``ops``: ("+", (x, y, r))
    inserts (the new site is last), ("-", k) removes site k (j > k becomes j − 1), ("L", k) removes
    site k (the last site takes index k).  Returns (build seconds, seconds per op, hidden count,
    sorted Delaunay edges of the final graph in the final numbering).  With ``queries`` (an (n, 2)
    sequence of floats) the result has two more items: the seconds of CGAL's ``nearest_neighbor``
    on all of them and the nearest site of each."""
    binary = build()
    lines = [str(len(circles))] + [f"{x!r} {y!r} {r!r}" for x, y, r in circles] + [str(len(ops))]
    for op, arg in ops:
        lines.append(f"+ {arg[0]!r} {arg[1]!r} {arg[2]!r}" if op == "+" else f"{op} {int(arg)}")
    if queries is not None:
        lines.append(str(len(queries)))
        lines += [f"{float(x)!r} {float(y)!r}" for x, y in queries]
    res = subprocess.run([str(binary)], input="\n".join(lines) + "\n", capture_output=True, text=True, check=True)
    out = res.stdout.split("\n")
    build_s = float(out[0].split()[1])
    op_s = [float(ln.split()[1]) for ln in out[1:1 + len(ops)]]
    hidden = int(out[1 + len(ops)].split()[1])
    rest = out[2 + len(ops):]
    q_s, nearest = None, []
    if rest and rest[0].startswith("queries"):
        q_s = float(rest[0].split()[1])
        nearest = [int(ln.split()[1]) for ln in rest[1:] if ln.startswith("nearest")]
        rest = rest[1 + len(nearest):]
    edges = sorted(tuple(int(t) for t in ln.split()) for ln in rest if ln.strip())
    if queries is not None:
        return build_s, op_s, hidden, edges, q_s, nearest
    return build_s, op_s, hidden, edges
