"""Conflict locator on non-generic configurations (symmetric drawings) and small sites far apart.

Each configuration kind comes from :func:`cases` (also used by tests/test_nongeneric.py): exact
rational conics, rotations from Pythagorean triples.  Prints a Markdown table (kind × cold and
warm time × certified × complete × route) and writes it to bench/results/nongeneric.md; *cold* is
the first call after ``clear_cache()`` (artefacts loaded), *warm* the repeated call.

    OPENBLAS_NUM_THREADS=1 python bench/bench_nongeneric.py [--reference]
    OPENBLAS_NUM_THREADS=1 python bench/bench_nongeneric.py --random 0:10 [--spread 100] [--reference]

``--reference`` also compares every vertex with the independent oracle tests/reference.py.
``--random a:b`` runs every kind of :func:`random_nongeneric` (seeded random drawings with
symmetry) on seeds a..b−1 and appends a table per kind.
"""
from __future__ import annotations

import os
import platform
import sys
import time
from fractions import Fraction as F
from pathlib import Path

import numpy as np

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


#: kinds of :func:`random_nongeneric` (drawings with symmetry; each is a non-generic member of its
#: family for the counting argument, or has a shared direction that makes it so)
RANDOM_KINDS = ("identical translated ellipses", "homothetic parallel ellipses", "axis-aligned ellipses",
                "identical translated hyperbolas", "equal circles", "parallel parabola axes",
                "opposite parabola axes", "shared symmetry axis", "collinear centres", "coaxial mixed sites")

_ROTS = [(3, 4, 5), (5, 12, 13), (8, 15, 17), (7, 24, 25), (20, 21, 29), (12, 35, 37), (9, 40, 41)]


def random_nongeneric(kind: str, seed: int, spread: int = 1) -> list:
    """Four exact conics (C1, C2, C3, C4) of a non-generic ``kind`` (one of :data:`RANDOM_KINDS`),
    drawn from ``seed``: rotations from Pythagorean triples, semi-axes in quarters (1 to 5/2 and
    1/2 to the first), positions on the half-integer grid of [-8, 8]²; C1–C3 have pairwise
    disjoint bounding discs (ellipses, circles) and C4 is a small ellipse near their centroid.
    Parabolas and hyperbolas may cross the other sites.  ``spread`` multiplies the positions (not
    the sizes): small sites far apart."""
    if kind not in RANDOM_KINDS:
        raise ValueError(f"unknown kind {kind!r}; choose one of {RANDOM_KINDS}")
    rng = np.random.default_rng([int(seed), RANDOM_KINDS.index(kind)])

    def rot():
        a, b, h = _ROTS[int(rng.integers(len(_ROTS)))]
        sa, sb = (1 if rng.random() < 0.5 else -1), (1 if rng.random() < 0.5 else -1)
        return (F(sa * a, h), F(sb * b, h))

    def axes():
        A = F(int(rng.integers(4, 11)), 4)
        return A, F(int(rng.integers(2, 4 * A)), 4)

    def point():
        return (F(int(rng.integers(-16, 17)) * spread, 2), F(int(rng.integers(-16, 17)) * spread, 2))

    def centres(radii, on_line=None):
        """three centres, bounding discs 1/2 apart, not collinear unless ``on_line`` (direction)"""
        while True:
            if on_line is None:
                cs = [point() for _ in radii]
            else:
                o, (c, s) = point(), on_line
                cs = [(o[0] + k * c, o[1] + k * s) for k in (F(int(rng.integers(-24, 25)) * spread, 2) for _ in radii)]
            far = all((float(p[0] - q[0]) ** 2 + float(p[1] - q[1]) ** 2) ** 0.5 >= float(r + t) + 0.5
                      for i, (p, r) in enumerate(zip(cs, radii)) for q, t in zip(cs[i + 1:], radii[i + 1:]))
            area = (cs[1][0] - cs[0][0]) * (cs[2][1] - cs[0][1]) - (cs[1][1] - cs[0][1]) * (cs[2][0] - cs[0][0])
            if far and (on_line is not None or area != 0):
                return cs

    E, H, P, C = Conic.ellipse, Conic.hyperbola, Conic.parabola, Conic.circle
    if kind == "identical translated ellipses":
        (A, B), r = axes(), rot()
        pos = centres([A] * 3)
        sites = [E(c, (A, B), r) for c in pos]
    elif kind == "homothetic parallel ellipses":
        (A, B), r = axes(), rot()
        ks = [F(int(k), 4) for k in rng.choice(np.arange(2, 9), size=3, replace=False)]
        pos = centres([k * A for k in ks])
        sites = [E(c, (k * A, k * B), r) for c, k in zip(pos, ks)]
    elif kind == "axis-aligned ellipses":
        ab = [axes() for _ in range(3)]
        pos = centres([a[0] for a in ab])
        sites = [E(c, a) for c, a in zip(pos, ab)]
    elif kind == "identical translated hyperbolas":
        (A, B), r = axes(), rot()
        pos = centres([A / 2] * 3)
        sites = [H(c, (B, A / 2), r) for c in pos]
    elif kind == "equal circles":
        rad = F(int(rng.integers(2, 9)), 4)
        pos = centres([rad] * 3)
        sites = [C(c, rad) for c in pos]
    elif kind == "parallel parabola axes":
        r = rot()
        pos = centres([F(1)] * 3)
        sites = [P(c, F(int(rng.integers(2, 9)), 4), r) for c in pos]
    elif kind == "opposite parabola axes":
        (A, B), (c, s) = axes(), rot()
        pos = v = centres([F(1), F(1), A])
        sites = [P(v[0], F(int(rng.integers(2, 9)), 4), (c, s)), P(v[1], F(int(rng.integers(2, 9)), 4), (-c, -s)),
                 E(v[2], (A, B), rot())]
    elif kind == "shared symmetry axis":
        (c, s) = rot()
        ab = [axes() for _ in range(2)]
        pos = v = centres([ab[0][0], ab[1][0], F(1)], on_line=(c, s))
        turn = [(c, s) if rng.random() < 0.5 else (-s, c) for _ in range(2)]
        sg = 1 if rng.random() < 0.5 else -1
        sites = [E(v[0], ab[0], turn[0]), E(v[1], ab[1], turn[1]), P(v[2], F(int(rng.integers(2, 9)), 4), (sg * c, sg * s))]
    elif kind == "coaxial mixed sites":
        # three sites of any kinds (ellipse, hyperbola, parabola, circle) symmetric about one line
        (c, s) = rot()
        kinds = [str(k) for k in rng.choice(list("EHPC"), size=3)]
        ab = [axes() for _ in range(3)]
        pos = v = centres([a[0] for a in ab], on_line=(c, s))
        sites = []
        for k, q, (A, B) in zip(kinds, v, ab):
            turn = (c, s) if rng.random() < 0.5 else (-s, c)
            sg = 1 if rng.random() < 0.5 else -1
            sites.append(E(q, (A, B), turn) if k == "E" else H(q, (A, B), turn) if k == "H" else
                         C(q, A) if k == "C" else P(q, F(int(rng.integers(2, 9)), 4), (sg * c, sg * s)))
    else:  # collinear centres
        ab = [axes() for _ in range(3)]
        pos = centres([a[0] for a in ab], on_line=rot())
        sites = [E(q, a, rot()) for q, a in zip(pos, ab)]
    gx, gy = (sum(float(q[i]) for q in pos) / 3 for i in (0, 1))
    c4 = E((F(round(2 * gx) + int(rng.integers(-2, 3)), 2), F(round(2 * gy) + int(rng.integers(-2, 3)), 2)),
           (F(1, 2), F(1, 3)), rot())
    return sites + [c4]


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


def _matches_reference(cs, res) -> bool:
    """Every vertex of the independent oracle tests/reference.py is one of ours (to 1e-7
    relative), and each of ours that its grid seeding missed is confirmed by its own Newton and
    dense true-vertex check (tests/test_locator.py: small features far out, e.g. vertices of radius
    0.3 where parallel parabolas meet 700 units away)."""
    sys.path.insert(0, str(ROOT / "tests"))
    from reference import reference_vertices
    from test_locator import _confirmed_by_reference

    rv = reference_vertices(*cs[:3])

    def near(a, v):
        return abs(float(a[0]) - v.x) < 1e-7 * (1 + abs(v.x)) and abs(float(a[1]) - v.y) < 1e-7 * (1 + abs(v.y))

    return (all(sum(near(a, v) for v in res.vertices) == 1 for a in rv)
            and all(any(near(a, v) for a in rv) or _confirmed_by_reference(cs, v) for v in res.vertices))


def run_random(seeds: range, reference: bool = False, spread: int = 1):
    """Every kind of :func:`random_nongeneric` on ``seeds``: cold time, certified and complete,
    route, and (``reference``) agreement with the oracle; a table per kind appended to
    bench/results/nongeneric.md.  ``spread`` multiplies the positions (small sites far apart)."""
    import statistics
    from collections import Counter

    from curvedvoronoi.runtime.predicates.locator import clear_cache, locate_conflicts
    from curvedvoronoi.runtime.result import LocatorError

    load0 = os.getloadavg()
    locate_conflicts(*_demo())
    lines = [f"## Random non-generic configurations, seeds {seeds.start}..{seeds.stop - 1}, spread {spread} "
             f"({time.strftime('%Y-%m-%d %H:%M')}, OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS')})", "",
             f"Command: `OPENBLAS_NUM_THREADS=1 python bench/bench_nongeneric.py --random {seeds.start}:{seeds.stop}"
             + (f" --spread {spread}" if spread != 1 else "")
             + (" --reference`" if reference else "`"), "",
             "| kind | triples | median s | max s | certified & complete | answered by | matches reference |",
             "|---|---:|---:|---:|---|---|---|"]
    for kind in RANDOM_KINDS:
        ts, ok, routes, refs = [], 0, Counter(), 0
        for seed in seeds:
            cs = random_nongeneric(kind, seed, spread)
            clear_cache()
            t0 = time.perf_counter()
            try:
                res = locate_conflicts(*cs)
            except LocatorError as exc:
                ts.append(time.perf_counter() - t0)
                routes["refused"] += 1
                print(kind, seed, f"{ts[-1]:.3f}", "refused:", str(exc)[:200], flush=True)
                continue
            ts.append(time.perf_counter() - t0)
            ok += bool(res.certified and res.complete)
            routes[_route(res)] += 1
            match = _matches_reference(cs, res) if reference else None
            refs += bool(match)
            print(kind, seed, f"{ts[-1]:.3f}", res.certified, res.complete, len(res.vertices), _route(res),
                  "" if match is None else ("reference: yes" if match else "reference: NO"), flush=True)
        lines.append(f"| {kind} | {len(ts)} | {statistics.median(ts):.3f} | {max(ts):.3f} | {ok}/{len(ts)} | "
                     + ", ".join(f"{k} {v}" for k, v in sorted(routes.items())) + " | "
                     + (f"{refs}/{len(ts)} |" if reference else "not run |"))
    threads = (f"{os.environ['CURVEDVORONOI_MSOLVE_THREADS']} (CURVEDVORONOI_MSOLVE_THREADS)"
               if os.environ.get("CURVEDVORONOI_MSOLVE_THREADS") else "2 when a second core is idle at the call, else 1")
    lines += ["", f"Cold calls (`clear_cache()` before each); msolve threads: {threads}; load average {load0[0]:.1f} at the start, {os.getloadavg()[0]:.1f} at the end "
              f"({os.cpu_count()} cores shared with other jobs).", ""]
    text = "\n".join(lines)
    print(text)
    out = ROOT / "bench" / "results" / "nongeneric.md"
    with out.open("a") as fh:
        fh.write("\n" + text)
    return text


if __name__ == "__main__":
    if "--random" in sys.argv:
        a, b = sys.argv[sys.argv.index("--random") + 1].split(":")
        sp = int(sys.argv[sys.argv.index("--spread") + 1]) if "--spread" in sys.argv else 1
        run_random(range(int(a), int(b)), reference="--reference" in sys.argv, spread=sp)
    else:
        run(reference="--reference" in sys.argv)
