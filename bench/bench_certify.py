"""Benchmark: cost of certifying the conic locator (issue 5; thesis §5.5 vs ch. 6).

    python bench/bench_certify.py             # all 30 validation cases, 1 BLAS thread and default
    python bench/bench_certify.py --quick     # 8 cases

Per validation case: numeric stage (``runtime.predicates.locator.locate_conflicts``, per-triple cache cleared),
vertex certification (``certify_vertex`` on every vertex: Krawczyk + true-vertex + conflict sign,
exact fallback when needed), completeness (complex Krawczyk on all generalised vertices), and the
share of vertices / calls that needed the exact path.  Prints a Markdown table and appends it to
bench/results/certify.md with the thread settings (threadpoolctl).
"""
from __future__ import annotations

import argparse
import datetime
import json
import pathlib
import platform
import statistics
import sys
import time

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))

from threadpoolctl import threadpool_info, threadpool_limits  # noqa: E402

from curvedvoronoi.runtime.certify.conflicts import certify_result, certify_vertex  # noqa: E402
from curvedvoronoi.runtime.certify.complete import certify_completeness  # noqa: E402
from curvedvoronoi.runtime.sites.conic import Conic  # noqa: E402

DATA = pathlib.Path(__file__).resolve().parents[1] / "tests" / "data" / "validation_cases.json"


def run(cases, label):
    from curvedvoronoi.runtime.predicates import locator
    from curvedvoronoi.runtime.solve.vertices import generalised_vertices
    rows = []
    for case in cases:
        cs = [Conic.from_coefficients(*e["coefficients"]) for e in case["conics"]]
        locator.clear_cache()
        t0 = time.perf_counter()
        try:
            res = locator.locate_conflicts(*cs, method="triple")
            err = ""
        except Exception as exc:  # noqa: BLE001 - report and continue
            res, err = None, type(exc).__name__
        t_num = time.perf_counter() - t0
        # vertex certification (input: the oracle's vertices if the locator failed)
        verts = ([(v.x, v.y, v.radius ** 2) for v in res.vertices] if res is not None else
                 [(float(v["x"]), float(v["y"]), float(v["radius"]) ** 2) for v in case["vertices"]])
        t1 = time.perf_counter()
        cvs = [certify_vertex(*cs[:3], x, y, R, cs[3]) for x, y, R in verts]
        t_cert = time.perf_counter() - t1
        n_exact = sum(cv.kind == "exact-rational" for cv in cvs)
        proven = sum(cv.proven for cv in cvs)
        # completeness on the generalised vertices (solutions of the triple system)
        try:
            sol = generalised_vertices(*cs[:3])
        except Exception as exc:  # noqa: BLE001 - the numeric solver refused: nothing to certify
            sol, err = None, err or ("solver: " + type(exc).__name__)
        t3 = time.perf_counter()
        ok, note = (certify_completeness(*cs[:3], sol.points, sol.info.expected) if sol is not None
                    else (False, "no solutions"))
        t_comp = time.perf_counter() - t3
        correct = None
        if res is not None and sol is not None:
            out = certify_result(res, *cs, solutions=sol.points, expected_count=sol.info.expected)
            correct = (out.certified, out.conflict == case["conflict"])
        rows.append({"case": case["name"], "n": len(verts), "numeric": t_num, "cert": t_cert,
                     "per_vertex": t_cert / max(len(verts), 1), "exact": n_exact, "proven": proven,
                     "N": len(sol.points) if sol is not None else 0, "complete": ok, "t_complete": t_comp, "locator_err": err,
                     "certified_result": correct})
    return rows


def table(rows, label):
    lines = [f"\n### {label}\n",
             "| case | vertices | proven | exact path | numeric s | certify vertices s | per vertex ms |"
             " solutions N | completeness s | complete | certified & right |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        cr = r["certified_result"]
        lines.append(f"| {r['case']} | {r['n']} | {r['proven']} | {r['exact']} | {r['numeric']:.3f}"
                     f"{' (' + r['locator_err'] + ')' if r['locator_err'] else ''} | {r['cert']:.4f} | "
                     f"{1e3 * r['per_vertex']:.2f} | {r['N']} | {r['t_complete']:.2f} | {r['complete']} | "
                     f"{'–' if cr is None else cr} |")
    nv = sum(r["n"] for r in rows)
    calls = len(rows)
    pv = [1e3 * r["per_vertex"] for r in rows if r["n"]]
    lines.append("")
    lines.append(f"* vertices: {nv}, proven {sum(r['proven'] for r in rows)}; exact path: "
                 f"{sum(r['exact'] for r in rows)} vertices ({100 * sum(r['exact'] for r in rows) / max(nv, 1):.1f}%), "
                 f"{sum(r['exact'] > 0 for r in rows)} of {calls} calls "
                 f"({100 * sum(r['exact'] > 0 for r in rows) / calls:.1f}%)")
    lines.append(f"* per vertex: median {statistics.median(pv):.2f} ms, max {max(pv):.2f} ms; per call "
                 f"(vertices only): mean {1e3 * statistics.mean(r['cert'] for r in rows):.1f} ms vs numeric "
                 f"{1e3 * statistics.mean(r['numeric'] for r in rows):.1f} ms")
    lines.append(f"* completeness: {sum(r['complete'] for r in rows)} of {calls} proven; mean "
                 f"{statistics.mean(r['t_complete'] for r in rows):.2f} s per triple")
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    cases = json.loads(DATA.read_text())["cases"]
    if args.quick:
        cases = cases[::4]
    out = [f"\n## {datetime.datetime.now().isoformat(timespec='seconds')} — {platform.node()} "
           f"python {platform.python_version()}"]
    out.append("threads: " + json.dumps([{k: i.get(k) for k in ("internal_api", "num_threads")}
                                         for i in threadpool_info()]))
    with threadpool_limits(limits=1):
        out.append(table(run(cases, "1 BLAS thread"), "1 BLAS thread"))
    out.append(table(run(cases, "default threads"), "default BLAS threads"))
    text = "\n".join(out)
    print(text)
    res = pathlib.Path(__file__).resolve().parent / "results" / "certify.md"
    with res.open("a") as fh:
        fh.write(text + "\n")


if __name__ == "__main__":
    main()
