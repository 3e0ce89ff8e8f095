"""Conflict locator on non-generic configurations (symmetric drawings) and small sites far apart.

Each configuration kind comes from :func:`cases` (also used by tests/test_nongeneric.py): exact
rational conics, rotations from Pythagorean triples.  Prints a Markdown table (kind × cold and
warm time × certified × complete × route) and writes it to bench/results/nongeneric.md; *cold* is
the first call after ``clear_cache()`` (artefacts loaded), *warm* the repeated call.

    OPENBLAS_NUM_THREADS=1 python bench/bench_nongeneric.py [--reference]

``--reference`` also compares every vertex with the independent oracle tests/reference.py.
"""
from __future__ import annotations

import os
import platform
import sys
import time
from fractions import Fraction as F
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from curvedvoronoi.runtime.sites.conic import Conic  # noqa: E402


def _E(c, ax, rot=(1, 0)):
    return Conic.ellipse(centre=c, axes=ax, rotation=rot)


def _P(v, p, rot=(1, 0)):
    return Conic.parabola(vertex=v, p=p, rotation=rot)


def cases() -> dict[str, list]:
    """kind -> four conics (C1, C2, C3, C4).  Every kind is non-generic for the counting argument
    (solutions at infinity or coinciding in the homotopy) or badly scaled for the numeric route."""
    r1, r2, r3 = (F(3, 5), F(4, 5)), (F(8, 17), F(15, 17)), (F(20, 29), F(-21, 29))
    return {
        # the same ellipse translated three times
        "identical translated ellipses": [_E((0, 0), (2, 1), r1), _E((6, 1), (2, 1), r1), _E((2, 5), (2, 1), r1),
                                          _E((3, 2), (F(1, 2), F(1, 3)))],
        # all axes parallel to the coordinate axes
        "axis-aligned ellipses": [_E((0, 0), (2, 1)), _E((5, 1), (F(3, 2), F(1, 2))), _E((1, 5), (1, F(3, 4))),
                                  _E((3, 2), (F(1, 2), F(1, 3)))],
        # two parabolas with the same axis direction
        "parallel parabola axes": [_P((0, 0), 1), _P((2, 4), F(1, 2)), _E((7, 1), (1, F(1, 2)), r1),
                                   _E((3, 2), (F(1, 2), F(1, 3)))],
        # two parabolas with opposite axis directions
        "opposite parabola axes": [_P((0, 0), 1), _P((6, 1), F(1, 2), (-1, 0)), _E((2, 5), (1, F(1, 2))),
                                   _E((9, 9), (1, F(1, 2)))],
        # three ellipses symmetric about one line (the x-axis)
        "shared symmetry axis": [_E((0, 0), (2, 1)), _E((6, 0), (1, F(1, 2))), _E((3, 0), (F(1, 2), F(1, 4))),
                                 _E((3, 4), (F(1, 2), F(1, 3)))],
        # circle, ellipse, parabola symmetric about y = 0 (examples/symmetric_mixed.json); the exact
        # solution (1, 0) lies on the ellipse's axis inside its evolute
        "shared symmetry axis (C, E, P)": [Conic.from_coefficients(1, 0, 4, 0, 0, -4),
                                           Conic.from_coefficients(1, 0, 1, -6, 0, 8),
                                           Conic.from_coefficients(0, 0, 1, -2, 0, 0),
                                           Conic.from_coefficients(1, 0, 1, 0, -10, 24)],
        # centres on a line, different rotations
        "collinear centres": [_E((0, 0), (2, 1), r1), _E((4, 2), (F(3, 2), F(1, 2)), r2), _E((8, 4), (1, F(1, 2)), r3),
                              _E((3, 6), (F(1, 2), F(1, 3)))],
        # small sites far apart: size / scene = 1/100
        "small sites far apart (1/100)": [_E((0, 0), (1, F(1, 2)), r1), _E((100, 7), (F(3, 4), F(1, 2)), r2),
                                          _E((40, 90), (1, F(3, 4)), r3), _E((50, 30), (1, F(1, 2)))],
        # a spread-out generic triple of small ellipses (once refused by the numeric route: two
        # near-real solutions collapsed onto one)
        "spread-out generic triple": [_E((47, F(73, 2)), (3, F(7, 4)), (F(3, 5), F(-4, 5))),
                                      _E((51, F(43, 2)), (F(15, 4), F(3, 4)), (F(8, 17), F(15, 17))),
                                      _E((14, F(23, 2)), (F(7, 4), F(5, 4)), (F(20, 29), F(-21, 29))),
                                      _E((30, 30), (1, F(1, 2)))],
        # generic compact reference point
        "generic compact (demo)": None,
    }


def _demo():
    from curvedvoronoi.runtime.predicates.locator import demo_configuration
    return demo_configuration()


def _route(res) -> str:
    if any(n.startswith("exact route") or "exact route (msolve)" in n for n in res.notes):
        return "exact (msolve)"
    comp = next((n for n in reversed(res.notes) if n.startswith("certify completeness")), "")
    if comp.startswith("certify completeness: exact"):
        return "numeric + exact completeness"
    return "numeric + counting" if res.complete else "numeric"


def run(reference: bool = False):
    from curvedvoronoi.runtime.predicates.locator import clear_cache, locate_conflicts

    load0 = os.getloadavg()
    t0 = time.perf_counter()
    locate_conflicts(*_demo())           # first call in the process: imports, artefacts
    first = time.perf_counter() - t0
    rows = []
    for kind, cs in cases().items():
        cs = cs or _demo()
        clear_cache()
        t0 = time.perf_counter()
        res = locate_conflicts(*cs)
        cold = time.perf_counter() - t0
        t0 = time.perf_counter()
        locate_conflicts(*cs)
        warm = time.perf_counter() - t0
        ref = ""
        if reference:
            sys.path.insert(0, str(ROOT / "tests"))
            from reference import reference_vertices
            rv = reference_vertices(*cs[:3])
            ok = len(rv) == len(res.vertices) and all(
                any(abs(float(a[0]) - v.x) < 1e-7 * (1 + abs(v.x)) and abs(float(a[1]) - v.y) < 1e-7 * (1 + abs(v.y))
                    for v in res.vertices) for a in rv)
            ref = "yes" if ok else "NO"
        rows.append((kind, cold, warm, res.certified, res.complete, len(res.vertices), _route(res),
                     res.timings.get("exact_solve", 0.0), ref))
    head = ("| configuration | cold (s) | warm (s) | certified | complete | vertices | route | msolve (s) |"
            + (" matches reference |" if reference else ""))
    sep = "|---|---:|---:|---|---|---:|---|---:|" + ("---|" if reference else "")
    lines = [head, sep]
    for kind, cold, warm, cert, comp, nv, route, tex, ref in rows:
        lines.append(f"| {kind} | {cold:.3f} | {warm:.4f} | {cert} | {comp} | {nv} | {route} | {tex:.2f} |"
                     + (f" {ref} |" if reference else ""))
    load1 = os.getloadavg()
    info = (f"\n*cold*: first call after `clear_cache()` (every per-triple result and certification table "
            f"forgotten; artefacts already loaded); *warm*: the same call again (per-triple caches).  "
            f"First call in the process (demo, imports and artefact loading included): {first:.2f} s.  "
            f"OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS')}, msolve threads: {os.environ.get('CURVEDVORONOI_MSOLVE_THREADS') or '2 when a second core is idle at the call, else 1'}, "
            f"{platform.machine()}, {os.cpu_count()} cores; machine shared with other jobs "
            f"(load average {load0[0]:.1f} at the start, {load1[0]:.1f} at the end): times are noisy.\n")
    text = "\n".join(lines) + "\n" + info
    print(text)
    out = ROOT / "bench" / "results" / "nongeneric.md"
    out.parent.mkdir(exist_ok=True)
    out.write_text("# Non-generic configurations (bench/bench_nongeneric.py)\n\n"
                   "Command: `OPENBLAS_NUM_THREADS=1 python bench/bench_nongeneric.py --reference`\n\n" + text)
    return rows


if __name__ == "__main__":
    run(reference="--reference" in sys.argv)
