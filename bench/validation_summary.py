"""Summary of the default certified locator on tests/data/validation_cases.json.

python bench/validation_summary.py  -> Markdown table to stdout and bench/results/validation.md
"""
from __future__ import annotations

import json
import os
import sys
import time
from fractions import Fraction
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from curvedvoronoi.runtime.sites.conic import Conic  # noqa: E402
from curvedvoronoi.runtime.predicates.locator import locate_conflicts  # noqa: E402
from curvedvoronoi.runtime.result import LocatorError  # noqa: E402
from curvedvoronoi.runtime.validation import default_cases_path  # noqa: E402


def main() -> None:
    cases = json.loads(default_cases_path().read_text())["cases"]
    rows, tot = [], dict(cases=0, answered=0, certified=0, complete=0, vertices=0, exp_vertices=0,
                         cert_vertices=0, wrong=0, refused=0)
    for case in cases:
        cs = [Conic.from_coefficients(*(Fraction(c) for c in k["coefficients"])) for k in case["conics"]]
        tot["cases"] += 1
        tot["exp_vertices"] += len(case["vertices"])
        t0 = time.perf_counter()
        try:
            res = locate_conflicts(*cs)
        except LocatorError as exc:
            tot["refused"] += 1
            rows.append(f"| {case['name']} | refused | | | | {str(exc)[:60]} |")
            continue
        dt = time.perf_counter() - t0
        tot["answered"] += 1
        tot["certified"] += res.certified
        tot["complete"] += res.complete
        tot["vertices"] += len(res.vertices)
        ok = len(res.vertices) == len(case["vertices"]) and (res.conflict is case["conflict"])
        for v in res.vertices:
            tot["cert_vertices"] += v.certified
        tot["wrong"] += (res.certified and not ok)
        rows.append(f"| {case['name']} | {len(res.vertices)}/{len(case['vertices'])} | {res.conflict} "
                    f"({case['conflict']}) | {res.certified} | {res.complete} | {dt:.2f} s |")
    head = ["| case | vertices (got/expected) | conflict (expected) | certified | complete | time |",
            "|---|---|---|---|---|---|"]
    summary = (f"\n{tot['cases']} cases: {tot['answered']} answered, {tot['refused']} refused; "
               f"{tot['certified']} certified, {tot['complete']} complete; vertices {tot['vertices']} of "
               f"{tot['exp_vertices']} expected, {tot['cert_vertices']} certified; certified-but-wrong: {tot['wrong']}\n"
               f"(OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS')}, first call per triple includes "
               f"the completeness proof)\n")
    text = "\n".join(head + rows) + "\n" + summary
    print(text)
    out = Path(__file__).resolve().parent / "results" / "validation.md"
    out.parent.mkdir(exist_ok=True)
    with out.open("a") as fh:
        fh.write(f"\n## {time.strftime('%Y-%m-%d %H:%M')}\n\n" + text)


if __name__ == "__main__":
    main()
