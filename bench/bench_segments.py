"""Benchmark of the segment Voronoi diagram (issue 32): random segments, random circular arcs and a
gear outline read from a DXF file, with Boost.Polygon and CGAL timed in the same run.

Rows:
* **random segments** (tests/scenes.py ``random_segments``, the generator of the peer tests;
  pairwise disjoint integer segments, N = 10³, 10⁴, and 10⁵ with ``--big``): construction time
  (``segment_voronoi(..., certify=False)``), certificate time (``verify_segments`` on that diagram,
  what ``certify=True`` runs after the construction), their total; peak RSS above the baseline
  (``ru_maxrss`` high-water mark of the case's own subprocess, baseline taken after the imports, a
  warm-up on 20 segments and the scene); Boost.Polygon's ``Construct()`` (pyvoronoi,
  tests/peers_boost.py) and CGAL's Segment_Delaunay_graph_2 insertion (tests/cgal/sdg_peer.py,
  g++ -O2) on the same input; the ratios; whether our Delaunay graph over elementary sites equals
  CGAL's (``degenerate=True``: zero-length diagonals dropped) and Boost's (the keys of
  tests/test_segment_cgal.py); rounds and samples (``d.stats``).
* **random circular arcs** (N = 10³, and 10⁴ with ``--big``): ``Arc.circular`` with integer centres
  and radii and integer start/end angles in degrees, one arc per cell of a square grid of cells of
  side 40, the circle's disc inside its cell (so arcs are pairwise disjoint); construction time,
  certificate time and verdict (no peer handles arcs).
* **gear outline from DXF**: a 50-tooth gear of 2 000 segments with a 64-gon bore, and the same gear
  with its roots and tips as bulge arcs (38 segments + 2 arcs a tooth) and a bore of two bulge
  semicircles, written with ezdxf to a temporary file, read with ``cv.read_dxf``, then
  ``cv.medial_axis(outer, holes, certify=False)`` and the certificate of its Voronoi diagram (what
  ``certify=True`` runs); time, certified, medial-axis edges.
* **profile**: cProfile of the construction on the first segment scene, internal time grouped by
  module (where the construction's time goes), with the certificate's own phase timings.

Every case runs in its own subprocess with a timeout; the certificate gets a deadline
(``verify_segments(..., deadline=)``: edges left unchecked are not certified).  One BLAS thread
(threadpoolctl and OPENBLAS_NUM_THREADS=1).

Run:  OPENBLAS_NUM_THREADS=1 python bench/bench_segments.py [--big] [--only segments arcs gear profile]
      (appends the tables to bench/results/segments.md)
"""
from __future__ import annotations

import argparse
import json
import math
import os
import random
import re
import resource
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests" / "cgal"))
sys.path.insert(0, str(ROOT / "tests"))
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

NOT_VERIFIED = "not verified (certify=False)"
_ITEM = re.compile(r"(edge|vertex|site) \d+")      # the item a certificate problem is about


# ----------------------------------------------------------------------------- scenes
def random_arcs(n: int, seed: int, cell: int = 40):
    """tests/scenes.py ``random_arcs`` (one generator for tests and benchmarks)."""
    import scenes

    return scenes.random_arcs(n, seed, cell)


GEAR_TEETH, GEAR_R, GEAR_DEPTH, BORE_R = 50, 50000, 4000, 10000


def gear_outline(arcs: bool):
    """The gear's vertices [(x, y, bulge)] (integers, counter-clockwise; bulge of the edge leaving
    the vertex).  Each tooth spans 2π/50: root (0 to 0.2 of it, radius R − depth), rising flank
    (0.2 to 0.45, radius R − depth + depth·s^1.5), tip (0.45 to 0.75, radius R), falling flank.
    Segments only: 10 segments for each of the four parts (2 000 segments).  With arcs: the root and
    the tip are one bulge arc each (bulge tan(θ/4), θ their angle at the centre; the radius is
    snapped to a rational one by read_dxf), the flanks 19 segments each (2 000 pieces)."""
    step = 2 * math.pi / GEAR_TEETH
    out = []

    def add(a, rad, bulge=0.0):
        out.append((round(rad * math.cos(a)), round(rad * math.sin(a)), bulge))

    for k in range(GEAR_TEETH):
        a0 = k * step
        if arcs:
            m = 19
            add(a0, GEAR_R - GEAR_DEPTH, math.tan(0.2 * step / 4))
            for i in range(m):
                add(a0 + (0.2 + 0.25 * i / m) * step, GEAR_R - GEAR_DEPTH + GEAR_DEPTH * (i / m) ** 1.5)
            add(a0 + 0.45 * step, GEAR_R, math.tan(0.3 * step / 4))
            for i in range(m):
                add(a0 + (0.75 + 0.25 * i / m) * step, GEAR_R - GEAR_DEPTH * (i / m) ** 1.5)
        else:
            m = 10
            for i in range(m):
                add(a0 + 0.2 * step * i / m, GEAR_R - GEAR_DEPTH)
            for i in range(m):
                add(a0 + (0.2 + 0.25 * i / m) * step, GEAR_R - GEAR_DEPTH + GEAR_DEPTH * (i / m) ** 1.5)
            for i in range(m):
                add(a0 + (0.45 + 0.3 * i / m) * step, GEAR_R)
            for i in range(m):
                add(a0 + (0.75 + 0.25 * i / m) * step, GEAR_R - GEAR_DEPTH * (i / m) ** 1.5)
    return out


def bore(arcs: bool):
    if arcs:        # two semicircles (bulge 1): centre (0, 0), radius BORE_R, rational
        return [(-BORE_R, 0, 1.0), (BORE_R, 0, 1.0)]
    return [(round(BORE_R * math.cos(2 * math.pi * k / 64)), round(BORE_R * math.sin(2 * math.pi * k / 64)), 0.0)
            for k in range(64)]


def write_gear_dxf(path: str, arcs: bool) -> None:
    import ezdxf

    doc = ezdxf.new()
    msp = doc.modelspace()
    msp.add_lwpolyline([(x, y, 0, 0, b) for x, y, b in gear_outline(arcs)], format="xyseb", close=True)
    msp.add_lwpolyline([(x, y, 0, 0, b) for x, y, b in bore(arcs)], format="xyseb", close=True)
    doc.saveas(path)


# ----------------------------------------------------------------------------- one case per subprocess
def _maxrss_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0      # KiB on Linux


_T0 = time.perf_counter()


def _phase(name: str) -> None:
    """A progress line on stderr: the driver names the phase of a case that is killed or fails."""
    print(f"PHASE {name} (from {time.perf_counter() - _T0:.0f} s of the case, peak RSS so far "
          f"{_maxrss_mb() / 1024:.1f} GiB)", file=sys.stderr, flush=True)


def _setup():
    import importlib

    for mod in ("numpy", "scipy.spatial"):      # load the BLAS libraries before limiting their threads
        importlib.import_module(mod)
    from threadpoolctl import threadpool_info, threadpool_limits

    threadpool_limits(limits=1)
    return [(p["internal_api"], p["num_threads"]) for p in threadpool_info()]


def _verifier():
    try:
        from curvedvoronoi.runtime.segments.certificate import verify_segments
        return verify_segments, None
    except Exception as exc:  # noqa: BLE001 - the certificate is being edited by others: report it
        return None, f"{type(exc).__name__}: {str(exc).splitlines()[0][:160] if str(exc) else ''}"


def _certify(out: dict, d, limit: float, rss0: float) -> None:
    """The certificate of ``d`` (what certify=True runs after the construction), timed."""
    verify, err = _verifier()
    construction_problems = [p for p in d.problems if p != NOT_VERIFIED]
    out["construction_problems"] = len(construction_problems)
    out["first_construction_problem"] = construction_problems[0][:160] if construction_problems else ""
    if verify is None:
        out.update(certificate_error=err, certified=False)
        return
    _phase("certificate")
    t0, c0 = time.perf_counter(), time.process_time()
    try:
        cert = verify(d, deadline=time.perf_counter() + limit)
    except Exception as exc:  # noqa: BLE001
        out.update(cert_seconds=time.perf_counter() - t0, cert_cpu=time.process_time() - c0, certified=False,
                   certificate_error=f"{type(exc).__name__}: {str(exc).splitlines()[0][:160] if str(exc) else ''}")
        return
    out.update(cert_seconds=time.perf_counter() - t0, cert_cpu=time.process_time() - c0,
               rss_cert_mb=_maxrss_mb() - rss0, cert_ok=bool(cert.ok),
               certified=bool(cert.ok) and not construction_problems,
               cert_problems=len(cert.problems),
               first_cert_problem=str(cert.problems[0])[:160] if cert.problems else "",
               cert_items=len({m.group(0) for m in map(_ITEM.match, map(str, cert.problems)) if m}),
               cert_timings={k: round(v, 3) for k, v in (cert.timings or {}).items()},
               edges_certified=sum(bool(e) for e in cert.edges), deadline_hit=cert.timings.get("total", 0) >= limit)


def run_segments(spec: dict) -> dict:
    pools = _setup()
    import curvedvoronoi as cv
    import scenes
    from curvedvoronoi.runtime.segments.construction import segment_voronoi

    out = {"threadpools": pools}
    warm = segment_voronoi([cv.Segment(*s) for s in scenes.random_segments(20, 0)], certify=False)
    verify, _ = _verifier()
    if verify is not None:
        try:
            verify(warm)
        except Exception:  # noqa: BLE001 - reported on the real scene
            pass
    t0 = time.perf_counter()
    segs = scenes.random_segments(spec["n"], spec["seed"], shared=spec.get("shared", False))
    pieces = [cv.Segment(*s) for s in segs]
    out.update(n=len(segs), scene_seconds=time.perf_counter() - t0)
    rss0 = _maxrss_mb()
    out["rss_baseline_mb"] = rss0
    t0, c0 = time.perf_counter(), time.process_time()
    _phase("construction")
    d = segment_voronoi(pieces, certify=False)
    out.update(seconds=time.perf_counter() - t0, cpu=time.process_time() - c0, rss_build_mb=_maxrss_mb() - rss0,
               stats=d.stats, vertices=len(d.vertices), edges=len(d.edges))
    # the construction's figures go into the phase line: a case killed in the certificate keeps them
    _phase(f"certificate; construction done: {out['seconds']:.1f} s ({out['cpu']:.1f} s CPU), "
           f"{d.stats.get('rounds')} rounds, {d.stats.get('samples')} samples, {len(d.vertices)} vertices, "
           f"{len(d.edges)} edges, RSS +{out['rss_build_mb']:.0f} MB")
    _certify(out, d, spec["cert_limit"], rss0)
    # peers, after our measurements (Boost runs in this process; CGAL in its own)
    from fractions import Fraction

    def key(site):
        import sdg_peer

        if isinstance(site, cv.Segment):
            return sdg_peer.segment_key(site.p, site.q)
        return sdg_peer.point_key(Fraction(str(site.x)), Fraction(str(site.y)))

    _phase("peers")
    keys = [key(s) for s in d.sites]
    ours = {frozenset((keys[i], keys[j])) for i, j in d.delaunay_edges()}
    out["delaunay"] = len(ours)
    try:
        import sdg_peer

        cgal, sec = sdg_peer.segment_delaunay_edges([], segs, degenerate=True)
        out.update(cgal_seconds=sec, cgal_edges=len(cgal), eq_cgal=ours == cgal, ours_not_cgal=len(ours - cgal),
                   cgal_not_ours=len(cgal - ours))
    except Exception as exc:  # noqa: BLE001 - PeerMissing or a build failure
        out["cgal_error"] = f"{type(exc).__name__}: {str(exc)[:120]}"
    try:
        from peers_boost import boost_delaunay_edges

        boost, sec = boost_delaunay_edges([], segs)
        out.update(boost_seconds=sec, boost_edges=len(boost), eq_boost=ours == boost, ours_not_boost=len(ours - boost),
                   boost_not_ours=len(boost - ours))
    except Exception as exc:  # noqa: BLE001 - pyvoronoi missing
        out["boost_error"] = f"{type(exc).__name__}: {str(exc)[:120]}"
    return out


def run_arcs(spec: dict) -> dict:
    pools = _setup()
    import curvedvoronoi as cv
    from curvedvoronoi.runtime.segments.construction import segment_voronoi

    out = {"threadpools": pools}
    warm = segment_voronoi(random_arcs(9, 0), certify=False)
    verify, _ = _verifier()
    if verify is not None:
        try:
            verify(warm)
        except Exception:  # noqa: BLE001
            pass
    arcs = random_arcs(spec["n"], spec["seed"])
    out["n"] = len(arcs)
    rss0 = _maxrss_mb()
    out["rss_baseline_mb"] = rss0
    t0, c0 = time.perf_counter(), time.process_time()
    _phase("construction")
    d = cv.voronoi(arcs, certify=False)
    out.update(seconds=time.perf_counter() - t0, cpu=time.process_time() - c0, rss_build_mb=_maxrss_mb() - rss0,
               stats=d.stats, vertices=len(d.vertices), edges=len(d.edges))
    # the construction's figures go into the phase line: a case killed in the certificate keeps them
    _phase(f"certificate; construction done: {out['seconds']:.1f} s ({out['cpu']:.1f} s CPU), "
           f"{d.stats.get('rounds')} rounds, {d.stats.get('samples')} samples, {len(d.vertices)} vertices, "
           f"{len(d.edges)} edges, RSS +{out['rss_build_mb']:.0f} MB")
    _certify(out, d, spec["cert_limit"], rss0)
    return out


def run_gear(spec: dict) -> dict:
    import tempfile

    pools = _setup()
    import curvedvoronoi as cv
    from curvedvoronoi.runtime.segments.construction import segment_voronoi

    out = {"threadpools": pools}
    warm = segment_voronoi([cv.Segment((0, 0), (1, 0)), cv.Segment((0, 2), (1, 3))], certify=False)
    verify, _ = _verifier()
    if verify is not None:
        try:
            verify(warm)
        except Exception:  # noqa: BLE001
            pass
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "gear.dxf")
        write_gear_dxf(path, spec["arcs"])
        out["dxf_bytes"] = os.path.getsize(path)
        t0 = time.perf_counter()
        pieces, sources, _ = cv.read_dxf(path)
        out["read_seconds"] = time.perf_counter() - t0
        # the CLI's domain rule (runtime/segments/command.py); the loops by entity when it refuses
        try:
            from curvedvoronoi.runtime.segments.command import read_domain

            outer, holes, _, _ = read_domain(path)
            out["domain"] = "read_domain"
        except Exception as exc:  # noqa: BLE001
            out["domain"] = f"by entity (read_domain: {type(exc).__name__}: {str(exc).split(': ', 1)[-1][:100]})"
            outer = [p for p, s in zip(pieces, sources) if s == 0]
            holes = [[p for p, s in zip(pieces, sources) if s == 1]]
    out["segments"] = sum(isinstance(p, cv.Segment) for p in pieces)
    out["arcs"] = sum(isinstance(p, cv.Arc) for p in pieces)
    rss0 = _maxrss_mb()
    out["rss_baseline_mb"] = rss0
    t0, c0 = time.perf_counter(), time.process_time()
    _phase("construction")
    m = cv.medial_axis(outer, holes, certify=False)
    out.update(seconds=time.perf_counter() - t0, cpu=time.process_time() - c0, rss_build_mb=_maxrss_mb() - rss0,
               stats=m.diagram.stats, medial_edges=len(m.edges), medial_vertices=len(m.vertices),
               vertices=len(m.diagram.vertices), edges=len(m.diagram.edges),
               inscribed=[round(float(v), 3) for v in (m.largest_inscribed_circle or ())])
    _certify(out, m.diagram, spec["cert_limit"], rss0)
    return out


def run_profile(spec: dict) -> dict:
    import cProfile
    import pstats

    pools = _setup()
    import curvedvoronoi as cv
    import scenes
    from curvedvoronoi.runtime.segments.construction import segment_voronoi

    segment_voronoi([cv.Segment(*s) for s in scenes.random_segments(20, 0)], certify=False)
    pieces = [cv.Segment(*s) for s in scenes.random_segments(spec["n"], spec["seed"])]
    pr = cProfile.Profile()
    t0 = time.perf_counter()
    pr.enable()
    d = segment_voronoi(pieces, certify=False)
    pr.disable()
    wall = time.perf_counter() - t0
    st = pstats.Stats(pr)
    by_module: dict = {}
    funcs = []
    for (fname, line, func), (cc, nc, tt, ct, _) in st.stats.items():
        if fname == "~" or fname.startswith("<"):
            mod = "C functions (numpy, qhull, builtins)"
        elif "site-packages" in fname:
            mod = fname.split("site-packages/", 1)[1].split("/", 1)[0] + " (Python side)"
        else:
            try:
                mod = str(Path(fname).resolve().relative_to(ROOT))
            except ValueError:
                mod = Path(fname).name
        by_module[mod] = by_module.get(mod, 0.0) + tt
        if not fname.endswith("threads.py"):
            funcs.append((ct, f"{Path(fname).name}:{line}({func})", nc))
    top_cum = sorted(funcs, reverse=True)
    return {"threadpools": pools, "n": len(pieces), "wall": wall, "stats": d.stats,
            "by_module": sorted(by_module.items(), key=lambda kv: -kv[1])[:10],
            "top_cumulative": [(round(c, 3), name, n) for c, name, n in top_cum[:14]]}


RUNNERS = {"segments": run_segments, "arcs": run_arcs, "gear": run_gear, "profile": run_profile}


# ----------------------------------------------------------------------------- driver
def _loadavg() -> str:
    try:
        return Path("/proc/loadavg").read_text().strip()
    except OSError:
        return " ".join(f"{v:.2f}" for v in os.getloadavg())


def _rss_gb(pid: int) -> float:
    try:
        for ln in Path(f"/proc/{pid}/status").read_text().splitlines():
            if ln.startswith("VmRSS:"):
                return int(ln.split()[1]) / 2 ** 20
    except (OSError, ValueError):
        pass
    return 0.0


def run_case(spec: dict, max_rss_gb: float) -> dict:
    """One case in a subprocess, killed after ``spec["timeout"]`` s or above ``max_rss_gb`` GiB of RSS
    (the machine is shared); a failure names the phase it happened in (the case's PHASE lines)."""
    import tempfile

    t0 = time.perf_counter()
    spec = dict(spec, load_start=_loadavg())
    killed, peak = None, 0.0
    with tempfile.TemporaryFile("w+") as out, tempfile.TemporaryFile("w+") as err:
        proc = subprocess.Popen([sys.executable, __file__, "--case", json.dumps(spec)], stdout=out, stderr=err,
                                text=True, env=dict(os.environ, OPENBLAS_NUM_THREADS="1"))
        while proc.poll() is None:
            time.sleep(1.0)
            peak = max(peak, _rss_gb(proc.pid))
            if time.perf_counter() - t0 > spec["timeout"]:
                killed = f"no return after {time.perf_counter() - t0:.0f} s (subprocess timeout {spec['timeout']} s)"
            elif peak > max_rss_gb:
                killed = (f"killed at {peak:.1f} GiB RSS (limit --max-rss-gb {max_rss_gb:g}) after "
                          f"{time.perf_counter() - t0:.0f} s")
            if killed:
                proc.kill()
                proc.wait()
        out.seek(0)
        err.seek(0)
        stdout, stderr = out.read(), err.read()
    phases = [ln for ln in stderr.splitlines() if ln.startswith("PHASE ")]
    if killed or proc.returncode != 0:
        msg = killed or ([ln for ln in stderr.strip().splitlines() if not ln.startswith("PHASE ")] or ["?"])[-1][:200]
        r = {"error": msg + (f"; in {phases[-1][6:]}" if phases else "")}
    else:
        r = json.loads(stdout.strip().splitlines()[-1])
    r.update(spec=spec, load_end=_loadavg(), wall_case=time.perf_counter() - t0, peak_rss_gb=round(peak, 2))
    print(spec["kind"], spec.get("n", spec.get("arcs")), {k: v for k, v in r.items() if k not in ("spec",)},
          file=sys.stderr, flush=True)
    return r


def _f(v, fmt=".2f", dash="-"):
    return dash if v is None else format(v, fmt)


def _yn(v):
    return "-" if v is None else ("yes" if v else "no")


def _cell(text: str) -> str:
    return (text or "-").replace("|", "/")


def _outcome(r: dict) -> str:
    if "error" in r:
        return r["error"]
    if r.get("certificate_error"):
        return "certificate: " + r["certificate_error"]
    bits = []
    if r.get("construction_problems"):
        bits.append(f"{r['construction_problems']} construction problems, first: {r['first_construction_problem']}")
    if r.get("cert_problems"):
        bits.append(f"certificate: {r['cert_problems']} problems on {r.get('cert_items', '?')} edges/vertices/sites, "
                    f"first: {r['first_cert_problem']}")
    if r.get("deadline_hit"):
        bits.append("certificate deadline reached")
    return "; ".join(bits) or "-"


def segments_table(rows) -> list[str]:
    lines = ["| N | seed | samples | rounds | construction s (CPU) | certificate s | total s | "
             "peak RSS MB constr. / +cert. | Boost s | CGAL s | constr./Boost | total/Boost | = CGAL | = Boost | "
             "certified | load (start → end) | outcome |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        s = r["spec"]
        load = f"{s['load_start'].split()[0]} → {r['load_end'].split()[0]}"
        if "error" in r:
            lines.append(f"| {s['n']} | {s['seed']} | - | - | - | - | - | - | - | - | - | - | - | - | no | {load} | "
                         f"{_cell(r['error'])} |")
            continue
        st = r["stats"]
        cert = r.get("cert_seconds")
        total = r["seconds"] + cert if cert is not None else None
        b = r.get("boost_seconds")
        eqc = _yn(r.get("eq_cgal"))
        if not r.get("eq_cgal", True):
            eqc += f" (−{r['cgal_not_ours']} +{r['ours_not_cgal']})"
        eqb = _yn(r.get("eq_boost"))
        if not r.get("eq_boost", True):
            eqb += f" (−{r['boost_not_ours']} +{r['ours_not_boost']})"
        lines.append(
            f"| {r['n']} | {s['seed']} | {st.get('samples', '-')} | {st.get('rounds', '-')} | "
            f"{r['seconds']:.2f} ({r['cpu']:.2f}) | {_f(cert)} | {_f(total)} | "
            f"{r['rss_build_mb']:.0f} / {_f(r.get('rss_cert_mb'), '.0f')} | {_f(b, '.4f')} | "
            f"{_f(r.get('cgal_seconds'), '.4f')} | {_f(r['seconds'] / b if b else None, '.0f')}× | "
            f"{_f(total / b if b and total else None, '.0f')}× | {eqc} | {eqb} | {_yn(r.get('certified'))} | {load} | "
            f"{_cell(_outcome(r))} |")
    return lines


def arcs_table(rows) -> list[str]:
    lines = ["| N arcs | seed | samples | rounds | vertices | edges | construction s (CPU) | certificate s | "
             "peak RSS MB constr. / +cert. | certified | load (start → end) | outcome |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        s = r["spec"]
        load = f"{s['load_start'].split()[0]} → {r['load_end'].split()[0]}"
        if "error" in r:
            lines.append(f"| {s['n']} | {s['seed']} | - | - | - | - | - | - | - | no | {load} | {_cell(r['error'])} |")
            continue
        st = r["stats"]
        lines.append(f"| {r['n']} | {s['seed']} | {st.get('samples', '-')} | {st.get('rounds', '-')} | "
                     f"{r['vertices']} | "
                     f"{r['edges']} | {r['seconds']:.2f} ({r['cpu']:.2f}) | {_f(r.get('cert_seconds'))} | "
                     f"{r['rss_build_mb']:.0f} / {_f(r.get('rss_cert_mb'), '.0f')} | {_yn(r.get('certified'))} | "
                     f"{load} | "
                     f"{_cell(_outcome(r))} |")
    return lines


def gear_table(rows) -> list[str]:
    lines = ["| outline | segments + arcs | read_dxf s | domain | samples | rounds | medial axis s (CPU) | "
             "certificate s | certified | medial edges | medial vertices | diagram edges | largest inscribed circle "
             "| peak RSS MB | load (start → end) | outcome |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        s = r["spec"]
        name = "gear, bulge arcs" if s["arcs"] else "gear, segments"
        load = f"{s['load_start'].split()[0]} → {r['load_end'].split()[0]}"
        if "error" in r:
            lines.append(f"| {name} | - | - | - | - | - | - | - | no | - | - | - | - | - | {load} | "
                         f"{_cell(r['error'])} |")
            continue
        st = r["stats"]
        lines.append(f"| {name} | {r['segments']} + {r['arcs']} | {r['read_seconds']:.2f} | {_cell(r['domain'])} | "
                     f"{st.get('samples', '-')} | {st.get('rounds', '-')} | {r['seconds']:.2f} ({r['cpu']:.2f}) | "
                     f"{_f(r.get('cert_seconds'))} | {_yn(r.get('certified'))} | {r['medial_edges']} | "
                     f"{r['medial_vertices']} | {r['edges']} | {r['inscribed']} | {r['rss_build_mb']:.0f} / "
                     f"{_f(r.get('rss_cert_mb'), '.0f')} | {load} | {_cell(_outcome(r))} |")
    return lines


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--case", help=argparse.SUPPRESS)
    ap.add_argument("--big", action="store_true", help="also 10⁵ random segments and 10⁴ arcs (many minutes)")
    ap.add_argument("--only", nargs="*", choices=sorted(RUNNERS), help="run only these parts")
    ap.add_argument("--sizes", nargs="*", type=int, help="segment sizes (default 1000 10000, + 100000 with --big)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--max-rss-gb", type=float, default=12.0,
                    help="kill a case whose resident memory exceeds this (GiB; the machine is shared)")
    ap.add_argument("--cert-limit", type=float,
                    help="certificate deadline in s for every segment size (default 300, 1200, 7200 s by size)")
    ap.add_argument("--no-write", action="store_true")
    args = ap.parse_args()
    if args.case:
        spec = json.loads(args.case)
        print(json.dumps(RUNNERS[spec["kind"]](spec), default=str))
        return
    parts = args.only or ["segments", "arcs", "gear", "profile"]
    sizes = args.sizes or ([1000, 10000] + ([100000] if args.big else []))
    limits = {1000: (600, 300), 10000: (2400, 1200), 100000: (14400, 7200)}     # (subprocess timeout, certificate)
    load0 = _loadavg()
    t_start = time.perf_counter()
    seg_rows, arc_rows, gear_rows, prof = [], [], [], None
    if "segments" in parts:
        for n in sizes:
            to, cl = limits.get(n, (14400, 7200))
            cl = args.cert_limit if args.cert_limit is not None else cl
            spec = {"kind": "segments", "n": n, "seed": args.seed, "timeout": to, "cert_limit": cl}
            seg_rows.append(run_case(spec, args.max_rss_gb))
    if "arcs" in parts:
        for n in [1000] + ([10000] if args.big else []):
            to, cl = limits[n]
            spec = {"kind": "arcs", "n": n, "seed": args.seed, "timeout": to, "cert_limit": cl}
            arc_rows.append(run_case(spec, args.max_rss_gb))
    if "gear" in parts:
        for arcs in (False, True):
            spec = {"kind": "gear", "arcs": arcs, "timeout": 900, "cert_limit": 300}
            gear_rows.append(run_case(spec, args.max_rss_gb))
    if "profile" in parts:
        prof = run_case({"kind": "profile", "n": min(sizes), "seed": args.seed, "timeout": 900}, args.max_rss_gb)

    pools = next((r["threadpools"] for r in seg_rows + arc_rows + gear_rows if "threadpools" in r), "?")
    cmd = "OPENBLAS_NUM_THREADS=1 python bench/bench_segments.py " + " ".join(sys.argv[1:])
    lines = [f"## bench_segments {time.strftime('%Y-%m-%d %H:%M')}  OPENBLAS_NUM_THREADS="
             f"{os.environ.get('OPENBLAS_NUM_THREADS')}  threadpools={pools}  cpus={os.cpu_count()}",
             "",
             f"Command: `{cmd.strip()}` (git {_git_head()}; {time.perf_counter() - t_start:.0f} s in all).  "
             f"/proc/loadavg at the start: `{load0}`, at the end: `{_loadavg()}` (other agents share the 2 cores; "
             "each row gives the 1-min load at its start and end).",
             ""]
    if seg_rows:
        lines += ["### Random segments (tests/scenes.py `random_segments(n, seed)`, pairwise disjoint, integer)", "",
                  "construction = `segment_voronoi(pieces, certify=False)` (crossing check, rounds of sampling, "
                  "triangulation and proofs, edge polylines); certificate = `verify_segments(d, deadline=)` on that "
                  "diagram (what `certify=True` adds); peak RSS = `ru_maxrss` of the case's subprocess above its "
                  "baseline (imports, a warm-up and the scene); Boost = pyvoronoi `Construct()`; CGAL = "
                  "Segment_Delaunay_graph_2 insertion (g++ -O2, filtered exact predicates); = CGAL / = Boost: our "
                  "Delaunay graph over elementary sites equals the peer's (`degenerate=True` for CGAL), else "
                  "(−edges missing here, +edges only here).", ""]
        lines += segments_table(seg_rows) + [""]
    if arc_rows:
        lines += ["### Random circular arcs (`Arc.circular`, integer centres and radii, integer degrees, discs in "
                  "disjoint grid cells)", "", "construction = `cv.voronoi(arcs, certify=False)`; certificate = "
                  "`verify_segments` on it. No peer handles arcs.", ""]
        lines += arcs_table(arc_rows) + [""]
    if gear_rows:
        lines += ["### Gear outline from DXF (ezdxf → `cv.read_dxf` → `cv.medial_axis`)", "",
                  f"{GEAR_TEETH} teeth, outer radius {GEAR_R}, tooth depth {GEAR_DEPTH}, bore radius {BORE_R} "
                  "(integer vertices, LWPOLYLINEs); medial axis s = `cv.medial_axis(outer, holes, certify=False)`; "
                  "certificate = `verify_segments` on its diagram (what `certify=True` adds). Diagram edges = edges "
                  "of the Voronoi diagram of the boundary (inside and outside).", ""]
        lines += gear_table(gear_rows) + [""]
    if prof and "error" not in prof:
        lines += [f"### Where the construction's time goes (cProfile, random segments N = {prof['n']}, seed "
                  f"{args.seed}; {prof['wall']:.1f} s under the profiler; stats {prof['stats']})", "",
                  "| module | internal s |", "|---|---|"]
        lines += [f"| {m} | {t:.2f} |" for m, t in prof["by_module"]]
        lines += ["", "| function | cumulative s | calls |", "|---|---|---|"]
        lines += [f"| {name} | {c:.2f} | {n} |" for c, name, n in prof["top_cumulative"]]
        lines.append("")
    cert_t = [(_label(r["spec"]), r["cert_timings"]) for r in seg_rows + arc_rows + gear_rows if r.get("cert_timings")]
    if cert_t:
        lines += ["Certificate phases (s, `verify_segments(...).timings`): " +
                  "; ".join(f"{n}: {t}" for n, t in cert_t), ""]
    rounds_t = [(_label(r["spec"]), r["stats"]) for r in seg_rows if r.get("stats", {}).get("round_cpu_seconds")]
    if rounds_t:
        lines += ["Construction rounds (CPU s per round, `d.stats['round_cpu_seconds']`; rounds that updated the "
                  "previous sample triangulation locally, `d.stats['local_rounds']`): " +
                  "; ".join(f"{n}: {st['round_cpu_seconds']}, {st.get('local_rounds', 0)} local" for n, st in rounds_t), ""]
    text = "\n".join(lines) + "\n"
    print(text)
    if not args.no_write:
        out = ROOT / "bench" / "results" / "segments.md"
        out.parent.mkdir(exist_ok=True)
        with open(out, "a") as fh:
            fh.write(text + "\n")


def _label(spec: dict) -> str:
    if spec["kind"] == "gear":
        return "gear with arcs" if spec["arcs"] else "gear"
    return f"{spec['kind']} {spec['n']}"


def _git_head() -> str:
    """The commit, with "+ local changes" when the checkout differs from it (others' edits)."""
    try:
        head = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"], capture_output=True,
                              text=True).stdout.strip()
        if not head:
            return "not a git checkout"
        dirty = subprocess.run(["git", "-C", str(ROOT), "status", "--porcelain", "--untracked-files=no", "--",
                                "runtime", "curvedvoronoi"], capture_output=True, text=True).stdout.strip()
        return head + (" + uncommitted changes in runtime/" if dirty else "")
    except OSError:
        return "?"


if __name__ == "__main__":
    main()
