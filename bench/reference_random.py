"""Certified locator vs the independent reference (tests/reference.py) on random configurations.

For each type mix (EEEE, HHHH, PPPP, EPHC) and seed (the same generator as tests/test_locator.py),
runs the default certified ``locate_conflicts`` and the grid-seeded 40-digit reference; records the
route of the triple solve (null space / homotopy / interval fallback), certified / complete flags,
vertices compared, disagreements (a certified vertex or flag that differs from the reference, or a
reference vertex we miss while claiming complete) and vertices found by us but not by the reference
(confirmed at high precision by the reference's own Newton).  Table -> bench/results/reference_random.md.

    OPENBLAS_NUM_THREADS=1 python bench/reference_random.py [--n 20] [--mixes EEEE,HHHH]
"""
from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))

from curvedvoronoi.runtime.predicates.locator import locate_conflicts, voronoi_vertices  # noqa: E402
from curvedvoronoi.runtime.result import LocatorError  # noqa: E402
from reference import reference_locate  # noqa: E402
from test_locator import MIXES, _close, _confirmed_by_reference, random_configuration  # noqa: E402


def one(cs):
    t0 = time.perf_counter()
    try:
        res = locate_conflicts(*cs)
    except LocatorError as exc:
        return dict(status="refused", why=str(exc)[:80], t=time.perf_counter() - t0)
    t = time.perf_counter() - t0
    route = "interval" if res.method.startswith("auto:") else "?"
    if route == "?":
        try:
            route = voronoi_vertices(*cs[:3]).solution.info.nullspace
            route = "homotopy" if route == "homotopy" else "null space"
        except LocatorError:
            route = "?"
    ref = reference_locate(*cs)
    got = list(res.vertices)
    bad = missed_by_us = ref_missed = 0
    for e in ref:
        m = [g for g in got if _close(g.x, e["x"], 1e-7) and _close(g.y, e["y"], 1e-7)]
        if not m:
            missed_by_us += 1
            continue
        g = m[0]
        got.remove(g)
        if g.certified and not (_close(g.radius, e["radius"], 1e-7) and g.in_conflict == e["in_conflict"]):
            bad += 1
    for g in got:
        if _confirmed_by_reference(cs, g):
            ref_missed += 1
        elif g.certified:
            bad += 1
    if res.complete and missed_by_us:
        bad += missed_by_us
    if res.certified and res.conflict != any(e["in_conflict"] for e in ref) and not ref_missed:
        bad += 1
    return dict(status="ok", route=route, certified=res.certified, complete=res.complete,
                vertices=len(res.vertices), ref=len(ref), bad=bad, missed=missed_by_us,
                ref_missed=ref_missed, t=t)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=20)
    ap.add_argument("--mixes", default=",".join(MIXES))
    a = ap.parse_args()
    rows = ["| mix | configs | null space | homotopy | interval fallback | refused | certified+complete "
            "| vertices (ours / reference) | missed by us | found only by us (confirmed) | disagreements "
            "| median s | max s |", "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for mix in a.mixes.split(","):
        st = dict(n=0, ns=0, hom=0, itv=0, ref=0, cert=0, v=0, vr=0, missed=0, rmiss=0, bad=0)
        ts = []
        for seed in range(a.n):
            cs = random_configuration(mix, 1000 * MIXES.index(mix) + seed)
            r = one(cs)
            st["n"] += 1
            ts.append(r["t"])
            if r["status"] == "refused":
                st["ref"] += 1
                print(mix, seed, "refused", r["why"], flush=True)
                continue
            st["ns"] += r["route"] == "null space"
            st["hom"] += r["route"] == "homotopy"
            st["itv"] += r["route"] == "interval"
            st["cert"] += bool(r["certified"])
            st["v"] += r["vertices"]
            st["vr"] += r["ref"]
            st["missed"] += r["missed"]
            st["rmiss"] += r["ref_missed"]
            st["bad"] += r["bad"]
            print(mix, seed, r, flush=True)
        ts.sort()
        rows.append(f"| {mix} | {st['n']} | {st['ns']} | {st['hom']} | {st['itv']} | {st['ref']} | {st['cert']} | "
                    f"{st['v']} / {st['vr']} | {st['missed']} | {st['rmiss']} | {st['bad']} | "
                    f"{ts[len(ts) // 2]:.2f} | {ts[-1]:.2f} |")
    text = "\n".join(rows) + (f"\n\n`python bench/reference_random.py --n {a.n}` "
                              f"(OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS')}); "
                              "'missed by us' counts only toward disagreements when the answer claims complete.\n")
    print(text)
    out = ROOT / "bench" / "results" / "reference_random.md"
    with out.open("a") as fh:
        fh.write(f"\n## {time.strftime('%Y-%m-%d %H:%M')}\n\n" + text)


if __name__ == "__main__":
    main()
