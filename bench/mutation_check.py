"""Mutation check of the test suite's teeth on the core predicates.

Each mutant flips one comparison (``<`` <-> ``<=``, ``>`` <-> ``>=``, ``==`` <-> ``!=``), one sign
(unary ``-`` dropped before a number or name), or one boolean literal (``True`` <-> ``False``) at a
site of the exact circle locator (thesis §3.1), the certification stage and the conic locator
(ch. 5), or the interval true-vertex/conflict decisions (ch. 6).  For each mutant the relevant
test files run (``pytest -x -q -m "not slow"``, with a timeout); a mutant is *killed* when the tests
fail, *survived* when they pass, *timeout* when they run past the timeout (not counted as killed).

The mutants are applied to a COPY of the source tree (copied to ``--work``, default /tmp/mut), never
to the repository, and run with the same interpreter.  Sites are enumerated from the tokens of the
chosen functions (``TARGETS`` below) and sampled with a seed (``--seed``, ``--per-file``).

Run::

    OPENBLAS_NUM_THREADS=1 python bench/mutation_check.py [--per-file 6] [--seed 1] [--timeout 300]

writes bench/results/mutation.md (the table, the seed, the thread setting and the survivors).
"""
from __future__ import annotations

import argparse
import ast
import io
import os
import random
import shutil
import subprocess
import sys
import time
import tokenize
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "bench" / "results" / "mutation.md"

#: file -> (functions whose tokens may be mutated (None: all), test files that must kill them, -k filter)
TARGETS: dict[str, tuple[list[str] | None, list[str], str | None]] = {
    "runtime/predicates/circles.py": (["_family_has_vertices", "decide_conflict", "locate_conflicts_circles", "_check_distinct"],
                           ["tests/test_circles.py"], None),
    "runtime/algebra/quadtower.py": (["rational_sqrt", "sign", "_sign_exact", "is_zero", "frac_sign"],
                             ["tests/test_circles.py"], None),
    "runtime/predicates/apollonius.py": (["solve_system", "emit", "aw_vertices", "locate_conflicts_aw"],
                              ["tests/test_circles.py"], None),
    "runtime/predicates/locator.py": (None, ["tests/test_locator.py", "tests/test_locator_certified.py"], None),
    "runtime/certify/conflicts.py": (None, ["tests/test_certify.py", "tests/test_locator_certified.py"], None),
    "runtime/certify/krawczyk.py": (None, ["tests/test_certify.py", "tests/test_certify_chart.py"], None),
    "runtime/interval/verify.py": (None, ["tests/test_interval.py"], None),
    "runtime/interval/bound.py": (None, ["tests/test_interval.py"], "vertex_bound or support or search_domain"),
}

#: behaviour broken on purpose to prove the teeth of the rewritten tests: (what, file, old text,
#: new text, new tests that must fail, tests of the previous suite (git HEAD) that they replace)
TEETH = [
    ("vertex bound without its W²/(2φ) term (a box around the data)", "runtime/interval/bound.py",
     "t = (W + W * W / (2 * low)) * (1 + 1e-9)", "t = (W + 0.0 * W / (2 * low)) * (1 + 1e-9)",
     ["tests/test_interval.py::test_vertex_bound_contains_the_far_vertex",
      "tests/test_interval.py::test_vertex_bound_contains_exact_circle_vertices",
      "tests/test_interval.py::test_vertex_bound_contains_every_validation_vertex"], []),
    ("interval route: complete whenever its box was searched (the old flag)", "runtime/interval/locator.py",
     "    if not bounded:\n        complete = False\n", "",
     ["tests/test_interval.py::test_interval_route_does_not_claim_a_box_that_misses_the_far_vertex",
      "tests/test_interval.py::test_interval_route_on_unbounded_sites_is_never_complete"],
     ["tests/old_test_interval.py::test_validation_offset_formulation"]),
    ("interval route: default domain around the data (the old default)", "runtime/interval/locator.py",
     "return (bound.box() if bound is not None else default_domain(sites)), bound",
     "return default_domain(sites), bound",
     ["tests/test_interval.py::test_default_search_domain_is_the_proved_bound"], []),
    ("conic locator refuses every triple of hyperbolas", "runtime/predicates/locator.py",
     '    all_circles = all(c.kind == "circle" for c in cs)\n',
     '    all_circles = all(c.kind == "circle" for c in cs)\n'
     '    if all(c.kind == "hyperbola" for c in cs[:3]):\n        raise LocatorError("mutant: refused")\n',
     ["tests/test_locator.py::test_reference_random[HHHH]"],
     ["tests/old_test_locator.py::test_reference_random[HHHH]"]),
    ("CLI/JSON: every x off by a relative 1e-6", "runtime/result.py",
     '"x": float(self.x),', '"x": float(self.x) * (1 + 1e-6),',
     ["tests/test_cli.py::test_locate_example_agrees_with_the_reference"],
     ["tests/old_test_cli.py::test_locate_example_is_certified_and_matches_the_demo"]),
    ("CLI/JSON: in_conflict negated", "runtime/result.py",
     '"in_conflict": self.in_conflict,', '"in_conflict": None if self.in_conflict is None else not self.in_conflict,',
     ["tests/test_cli.py::test_locate_example_agrees_with_the_reference",
      "tests/test_cli.py::test_locate_far_vertex_of_circles_in_closed_form"],
     ["tests/old_test_cli.py::test_locate_example_is_certified_and_matches_the_demo"]),
]

FLIP = {"<": "<=", "<=": "<", ">": ">=", ">=": ">", "==": "!=", "!=": "=="}


def _function_spans(src: str) -> list[tuple[str, int, int]]:
    out = []
    for node in ast.walk(ast.parse(src)):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            out.append((node.name, node.lineno, node.end_lineno))
    return out


def _docstring_lines(src: str) -> set[int]:
    lines: set[int] = set()
    for node in ast.walk(ast.parse(src)):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef, ast.Module)):
            body = getattr(node, "body", [])
            if body and isinstance(body[0], ast.Expr) and isinstance(getattr(body[0], "value", None), ast.Constant) \
                    and isinstance(body[0].value.value, str):
                lines.update(range(body[0].lineno, body[0].end_lineno + 1))
    return lines


def enumerate_mutants(path: str, src: str, functions: list[str] | None) -> list[dict]:
    """All candidate mutations of ``src``: dicts with line, col, old, new, function, kind."""
    spans = _function_spans(src)
    skip = _docstring_lines(src)
    toks = list(tokenize.generate_tokens(io.StringIO(src).readline))
    out = []

    def owner(line: int) -> str | None:
        best = None
        for name, a, b in spans:
            if a <= line <= b and (best is None or a >= best[1]):
                best = (name, a)
        return best[0] if best else None

    for i, t in enumerate(toks):
        line, col = t.start
        if line in skip:
            continue
        fn = owner(line)
        if functions is not None and fn not in functions:
            continue
        if fn is None:
            continue
        prev = toks[i - 1] if i else None
        if t.type == tokenize.OP and t.string in FLIP:
            out.append(dict(path=path, line=line, col=col, old=t.string, new=FLIP[t.string], function=fn,
                            kind="comparison"))
        elif t.type == tokenize.NAME and t.string in ("True", "False") and prev is not None \
                and prev.string in ("return", "=", "(", ","):
            out.append(dict(path=path, line=line, col=col, old=t.string,
                            new="False" if t.string == "True" else "True", function=fn, kind="boolean"))
        elif t.type == tokenize.OP and t.string == "-" and prev is not None \
                and (prev.type == tokenize.OP and prev.string in ("(", ",", "=", "return", "[", "*")
                     or prev.string == "return") and toks[i + 1].type in (tokenize.NUMBER, tokenize.NAME):
            out.append(dict(path=path, line=line, col=col, old="-", new="", function=fn, kind="sign"))
    return out


def apply(src: str, m: dict) -> str:
    lines = src.splitlines(keepends=True)
    ln = lines[m["line"] - 1]
    assert ln[m["col"]:m["col"] + len(m["old"])] == m["old"], (m, ln)
    lines[m["line"] - 1] = ln[:m["col"]] + m["new"] + ln[m["col"] + len(m["old"]):]
    return "".join(lines)


def copy_tree(work: Path) -> Path:
    tree = work / "tree"
    work.mkdir(parents=True, exist_ok=True)
    if tree.exists():
        shutil.rmtree(tree)
    shutil.copytree(ROOT, tree, ignore=shutil.ignore_patterns(".venv", ".git", "__pycache__", ".pytest_cache",
                                                              ".hypothesis", "*.egg-info", "build"))
    return tree


def run_tests(tree: Path, tests: list[str], kfilter: str | None, timeout: float,
              marker: str | None = "not slow") -> tuple[str, float, str]:
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", PYTHONPATH=str(tree), PYTHONDONTWRITEBYTECODE="1")
    cmd = [sys.executable, "-m", "pytest", "-x", "-q", "-p", "no:cacheprovider", *tests]
    if marker:
        cmd += ["-m", marker]
    if kfilter:
        cmd += ["-k", kfilter]
    t0 = time.perf_counter()
    try:
        p = subprocess.run(cmd, cwd=tree, env=env, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return "timeout", time.perf_counter() - t0, ""
    dt = time.perf_counter() - t0
    last = (p.stdout.strip().splitlines() or [""])[-1]
    if p.returncode == 0:
        return "survived", dt, last
    if p.returncode == 5:
        return "no tests", dt, last
    return "killed", dt, last


def run_teeth(tree: Path, timeout: float, out: Path, previous: str) -> None:
    """Break each behaviour of TEETH in the copy; the new tests must fail, and the replaced tests of
    the previous suite (read with ``git show PREVIOUS:...``, a read-only git command) are run on the
    same break for comparison."""
    for name in ("test_interval.py", "test_locator.py", "test_cli.py"):
        old = subprocess.run(["git", "-C", str(ROOT), "show", f"{previous}:tests/{name}"], capture_output=True,
                             text=True)
        if old.returncode == 0:
            (tree / "tests" / f"old_{name}").write_text(old.stdout)
    env_extra = {"LOCATOR_REFERENCE_N": "1"}
    rows = ["", "## Teeth of the rewritten tests (behaviour broken on purpose, in a copy of the tree)", "",
            f"`OPENBLAS_NUM_THREADS=1 python bench/mutation_check.py --teeth --previous {previous}` "
            f"(LOCATOR_REFERENCE_N=1; the previous tests are read with `git show {previous}:tests/...`).", "",
            "| broken behaviour | new tests | result | previous tests | result |", "|---|---|---|---|---|"]
    for what, rel, old, new, tests, old_tests in TEETH:
        f = tree / rel
        src = f.read_text()
        assert src.count(old) == 1, (rel, old)
        try:
            f.write_text(src.replace(old, new))
            os.environ.update(env_extra)
            st, dt, last = run_tests(tree, tests, None, timeout, marker=None)
            ost = "-"
            if old_tests:
                ost, _, _ = run_tests(tree, old_tests, None, timeout, marker=None)
                ost = {"survived": "pass (blind)", "killed": "fail"}.get(ost, ost)
        finally:
            f.write_text(src)
        res = {"killed": "fail (caught)", "survived": "PASS (blind)"}.get(st, st)
        print(f"{what}: new {res} ({dt:.0f} s); previous {ost}", flush=True)
        rows.append(f"| {what} (`{rel}`) | {'<br>'.join(t.split('::')[1] for t in tests)} | {res} | "
                    f"{'<br>'.join(t.split('::')[1] for t in old_tests) or '(none)'} | {ost} |")
    text = "\n".join(rows) + "\n"
    print(text)
    with out.open("a") as fh:
        fh.write(text)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--work", default="/tmp/mut")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--per-file", type=int, default=6)
    ap.add_argument("--timeout", type=float, default=300)
    ap.add_argument("--files", nargs="*", default=None, help="subset of TARGETS")
    ap.add_argument("--baseline", action="store_true", help="also run each test subset unmutated first")
    ap.add_argument("--out", default=str(OUT))
    ap.add_argument("--teeth", action="store_true", help="only the TEETH checks (appended to --out)")
    ap.add_argument("--mutant", action="append", default=[], metavar="FILE::LINE_TEXT::OLD::NEW",
                    help="run only this mutant: the first token OLD on the line containing LINE_TEXT")
    ap.add_argument("--previous", default="cf93108",
                    help="git revision holding the suite before the rewrite (for --teeth)")
    ap.add_argument("--append", action="store_true", help="append the table to --out instead of replacing it")
    ap.add_argument("--title", default="Mutation check of the core predicates")
    args = ap.parse_args(argv)
    rng = random.Random(args.seed)
    tree = copy_tree(Path(args.work))
    if args.teeth:
        run_teeth(tree, args.timeout, Path(args.out), args.previous)
        return 0
    rows = []
    files = args.files or list(TARGETS)
    t_start = time.perf_counter()
    wanted: dict[str, list[tuple[str, str, str]]] = {}
    for spec in args.mutant:
        rel, text, old, new = spec.split("::")
        wanted.setdefault(rel, []).append((text, old, new))
    if wanted:
        files = list(wanted)
    for rel in files:
        functions, tests, kfilter = TARGETS[rel]
        f = tree / rel
        src = f.read_text()
        muts = enumerate_mutants(rel, src, functions)
        if rel in wanted:
            chosen = []
            lines = src.splitlines()
            for text, old, new in wanted[rel]:
                ln = next(i for i, line in enumerate(lines, 1) if text in line)
                m = [m for m in muts if m["line"] == ln and m["old"] == old and m["new"] == new]
                assert m, (rel, text, old, new)
                chosen.append(m[0])
        else:
            chosen = sorted(rng.sample(muts, min(args.per_file, len(muts))), key=lambda m: (m["line"], m["col"]))
        if args.baseline:
            st, dt, last = run_tests(tree, tests, kfilter, args.timeout)
            print(f"baseline {rel}: {st} ({dt:.0f} s) {last}", flush=True)
            if st != "survived":
                rows.append(dict(path=rel, line=0, col=0, old="", new="", function="(baseline)", kind="baseline",
                                 status="BASELINE FAILS", seconds=dt, tests=" ".join(tests), last=last,
                                 text=""))
                continue
        for m in chosen:
            try:
                f.write_text(apply(src, m))
                st, dt, last = run_tests(tree, tests, kfilter, args.timeout)
            finally:
                f.write_text(src)
            text = src.splitlines()[m["line"] - 1].strip()
            rows.append(dict(m, status=st, seconds=dt, tests=" ".join(tests), last=last, text=text))
            print(f"{rel}:{m['line']} {m['function']} {m['old']!r}->{m['new']!r}: {st} ({dt:.0f} s)", flush=True)
    total = time.perf_counter() - t_start
    killed = sum(r["status"] == "killed" for r in rows)
    timeouts = sum(r["status"] == "timeout" for r in rows)
    surv = [r for r in rows if r["status"] == "survived"]
    cmdline = " ".join(a if " " not in a else repr(a) for a in (argv if argv is not None else sys.argv[1:]))
    lines = [("## " if args.append else "# ") + args.title,
             "",
             f"Command: `OPENBLAS_NUM_THREADS=1 python bench/mutation_check.py {cmdline}` (BLAS threads: 1; "
             f"{total:.0f} s wall on a shared 2-core machine, noisy).",
             "",
             f"**{killed} of {len(rows)} mutants killed, {len(surv)} survived, {timeouts} timed out** "
             "(the targeted tests ran past the timeout: neither killed nor shown to survive).",
             "Tests run with `pytest -x -q -m 'not slow'` on the listed files, in a copy of the tree.",
             "",
             "| file:line | function | mutation | source line | tests | result | s |",
             "|---|---|---|---|---|---|---|"]
    for r in rows:
        mut = f"`{r['old']}` → `{r['new'] or '(nothing)'}`"
        src_line = r["text"].replace("|", "\\|")[:80]
        lines.append(f"| {r['path']}:{r['line']} | {r['function']} | {mut} | `{src_line}` | "
                     f"{r['tests'].replace('tests/', '')} | {r['status']} | {r['seconds']:.0f} |")
    lines += ["", "Survivors: " + ("none" if not surv else
                                    "; ".join(f"{r['path']}:{r['line']} ({r['function']}, `{r['old']}` → "
                                              f"`{r['new'] or '(nothing)'}`)" for r in surv))]
    text = "\n".join(lines) + "\n"
    print(text)
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    if args.append:
        with Path(args.out).open("a") as fh:
            fh.write("\n" + text)
    else:
        Path(args.out).write_text(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
