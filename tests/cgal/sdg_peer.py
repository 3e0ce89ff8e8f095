"""Build and run the CGAL segment-Delaunay-graph peer (segment_delaunay.cpp): the Delaunay graph of
points and non-crossing segments over *elementary sites* (a closed segment [p, q] is the point p,
the point q and the open segment; an endpoint shared by several segments is one site).

Keys of elementary sites are exact and hashable (shared with tests/peers_boost.py):
a point is ``("p", Fraction(x), Fraction(y))``, a segment interior is
``("s", (Fraction(x0), Fraction(y0)), (Fraction(x1), Fraction(y1)))`` with its endpoints sorted;
a Delaunay edge is a frozenset of two keys.  The binary is compiled once and cached in the temp
directory, keyed by the source hash; ``PeerMissing`` when g++ or the CGAL headers are absent."""
from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import tempfile
from fractions import Fraction
from pathlib import Path

SOURCE = Path(__file__).with_name("segment_delaunay.cpp")
HEADER = "/usr/include/CGAL/Segment_Delaunay_graph_2.h"


class PeerMissing(RuntimeError):
    """g++ or CGAL (Debian package libcgal-dev, with libgmp-dev) is not installed."""


def build() -> Path:
    """Compile the peer once (about 10 s of CPU) and return the path of the binary."""
    gxx = shutil.which("g++")
    if gxx is None:
        raise PeerMissing("g++ not found (apt-get install g++)")
    if not os.path.exists(HEADER):
        raise PeerMissing("CGAL headers not found (apt-get install libcgal-dev)")
    digest = hashlib.sha256(SOURCE.read_bytes()).hexdigest()[:16]
    out = Path(tempfile.gettempdir()) / f"curvedvoronoi_cgal_sdg_{digest}"
    if not out.exists():
        tmp = out.with_suffix(f".{os.getpid()}.tmp")
        res = subprocess.run([gxx, "-O2", "-std=c++17", "-DNDEBUG", "-o", str(tmp), str(SOURCE), "-lgmp", "-lmpfr"],
                             capture_output=True, text=True)
        if res.returncode != 0:
            if "gmp" in res.stderr.lower():
                raise PeerMissing("GMP not found (apt-get install libgmp-dev libmpfr-dev): " + res.stderr[-500:])
            raise RuntimeError("compiling the CGAL segment Delaunay peer failed:\n" + res.stderr[-3000:])
        os.replace(tmp, out)
    return out


def build_or_skip() -> Path:
    """:func:`build` for a test: skipped where g++ or CGAL is missing, failed under CI (which
    installs them)."""
    import pytest

    try:
        return build()
    except PeerMissing as exc:
        if os.environ.get("CI"):
            pytest.fail(f"CGAL segment peer unavailable in CI: {exc}")
        pytest.skip(f"the comparison with CGAL's Segment_Delaunay_graph_2 needs g++ and libcgal-dev (apt-get): {exc}")


def point_key(x, y) -> tuple:
    """Key of a point site (exact)."""
    return ("p", Fraction(x), Fraction(y))


def segment_key(a, b) -> tuple:
    """Key of the open segment between a and b (exact, endpoints sorted)."""
    a = (Fraction(a[0]), Fraction(a[1]))
    b = (Fraction(b[0]), Fraction(b[1]))
    return ("s",) + tuple(sorted((a, b)))


def _parse_site(text: str) -> tuple:
    tok = text.split()
    c = [Fraction(float(t)) for t in tok[1:]]      # %.17g round-trips the double exactly
    if tok[0] == "p":
        return ("p", c[0], c[1])
    return segment_key((c[0], c[1]), (c[2], c[3]))


def _input(points, segments) -> str:
    lines = [str(len(points) + len(segments))]
    lines += [f"{x!r} {y!r} {x!r} {y!r}" for x, y in points]
    seen = set()
    for (x0, y0), (x1, y1) in segments:
        if (x0, y0) == (x1, y1):
            raise ValueError(f"degenerate segment {(x0, y0)}-{(x1, y1)}: pass it as a point")
        k = segment_key((x0, y0), (x1, y1))
        if k not in seen:                  # CGAL would insert a repeated segment twice
            seen.add(k)
            lines.append(f"{x0!r} {y0!r} {x1!r} {y1!r}")
    return "\n".join(lines) + "\n"


def run(points, segments, *, degenerate=False):
    """Raw output: (list of (key, key, degenerate flag or None) per triangulation edge, seconds)."""
    binary = build()
    args = [str(binary)] + (["--degenerate"] if degenerate else [])
    res = subprocess.run(args, input=_input(points, segments), capture_output=True, text=True)
    if res.returncode != 0:
        raise RuntimeError(f"CGAL segment Delaunay peer failed ({res.returncode}): {res.stderr[-2000:]}")
    seconds = float(res.stderr.split("seconds", 1)[1].split()[0])
    cache: dict = {}

    def site(text):
        k = cache.get(text)
        if k is None:
            k = cache[text] = _parse_site(text)
        return k

    raw = []
    for ln in res.stdout.splitlines():
        if not ln.strip():
            continue
        parts = ln.split(" | ")
        flag = (parts[2].strip() == "1") if degenerate else None
        raw.append((site(parts[0]), site(parts[1]), flag))
    return raw, seconds


def segment_delaunay_edges(points, segments, *, degenerate=False):
    """CGAL's Segment_Delaunay_graph_2 of ``points`` [(x, y)] and non-crossing ``segments``
    [((x0, y0), (x1, y1))] (integers, or floats taken exactly; segments may share endpoints, a point
    may equal a segment endpoint, nothing may touch a segment's interior).

    Returns (set of Delaunay edges, each a frozenset of two elementary-site keys; build seconds).
    Every segment contributes its two endpoints as point sites, so the edges include the
    "secondary" ones between a segment interior and its own endpoints.  With ``degenerate=True``
    the edges whose dual Voronoi edge has length zero (triangulation diagonals at a Voronoi
    vertex of degree >= 4, decided by CGAL's exact Is_degenerate_edge_2) are dropped: a pair is
    kept when at least one of its triangulation edges is not degenerate."""
    raw, seconds = run(points, segments, degenerate=degenerate)
    edges = {frozenset((a, b)) for a, b, flag in raw if not flag}
    assert all(len(e) == 2 for e in edges), "an edge from a site to itself"
    return edges, seconds
