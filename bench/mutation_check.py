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

The soundness mode (``--modules``, issue 31 item 3) samples operators that weaken a proof, re-runs
survivors after new tests (``--replay``), merges a sample with its re-runs and readings (``--merge``)
and prints the summary of every sampled group with the standard score killed / (mutants −
equivalent) (``--score``).

Length: one benchmark driver holding two mutation modes (the core predicates' token flips and the
soundness operators) with their sampling, replay, merge and score reports, which share the tree copy
and the test runner; split, the pieces would import each other's private helpers.
"""
from __future__ import annotations

import argparse
import ast
import io
import os
import random
import re
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


# ============================================================================ soundness mutants
# (issue 31 item 3): the verifier (runtime/voronoi/verify/**) and the certification stage
# (runtime/certify/**), with operators that WEAKEN soundness, generated from the AST.

#: default modules of the soundness mode (globs relative to the repository)
SOUND_MODULES = ["runtime/voronoi/verify/**/*.py", "runtime/certify/**/*.py"]

#: the diagram verifier's subset, fastest and most targeted first (``-x`` stops at the first failure, so a
#: killed mutant costs little; a survivor runs all of it, ~15 s unmutated on the shared machine).
#: The 2026-11 run (seed 32) used this list; the first run (seed 31) had test_voronoi_verify first and
#: test_symmetry instead of test_symmetry_proofs / test_polyline_bound.
_VERIFY_TESTS = ["tests/test_mirror_edge_third_sites.py", "tests/test_vertex_reach_closed_balls.py",
                 "tests/test_verify_boundaries.py", "tests/test_verify_mutants.py",
                 # a wrong far edge whose third site only exact arithmetic refuses, the circle route's
                 # Jacobian box at its cubes' corners (hand mutants of edge_checks, exact_edges and
                 # vertices that survive the rest)
                 "tests/test_verify_mutants_s31.py", "tests/test_verify_float_boundaries.py",
                 "tests/test_verify_deadline.py", "tests/test_polyline_bound.py",
                 "tests/test_degenerate.py", "tests/test_symmetry_proofs.py", "tests/test_degenerate_cgal.py",
                 "tests/test_voronoi_verify.py",
                 # the vertex enclosures against high-precision values (hand mutants of vertices.py and
                 # conic_vertices.py that survive the rest)
                 "tests/test_circle_vertex_boxes.py", "tests/test_conic_vertex_enclosures.py",
                 # the chains of strips' hard places among 200 random ellipses (~30 s; kills the guide's
                 # node cap and its projected-node filter, bisector_guide.py:229 and :157)
                 "tests/test_curved_edge_guides.py",
                 # the strip test's (T2)/(T4) and the drawn points' tolerance at their boundaries
                 # (closed-form scenes: kill first-order terms halved, a tolerance tripled)
                 "tests/test_strip_boundaries.py", "tests/test_polyline_point_tolerance.py",
                 # the tail's (M) cells against the sampled derivative, the circle route's tail next to
                 # a thin hyperbola, the tied tail's lateral sign lemma (kill the enclosure halved, the
                 # gradient fallback loosened, the rounding allowance's sign flipped)
                 "tests/test_tail_monotone_boundaries.py", "tests/test_circle_tail_near_tie.py",
                 "tests/test_tied_tail_lateral_sign.py"]
_CERTIFY_TESTS = ["tests/test_certify_steps.py", "tests/test_certify_stated_limits.py", "tests/test_chart_nearly_real_pair.py",
                  "tests/test_chart_choice_far_circle.py", "tests/test_certify_conflict_boundaries.py", "tests/test_certify_completeness_boundaries.py", "tests/test_certify_kernel_boundaries.py", "tests/test_certify.py", "tests/test_certify_chart.py", "tests/test_certify_conjugates.py",
                  "tests/test_certify_dimension.py", "tests/test_certify_fast_system.py",
                  "tests/test_certify_boundaries.py", "tests/test_locator_certified.py",
                  "tests/test_interval_newton.py", "tests/test_voronoi_vertex.py",
                  # only proven vertex certificates match a solution (complete.py's completeness count)
                  "tests/test_nongeneric.py::test_far_vertex_matched_by_a_tighter_vertex_box"]
#: the proof kernel's own boundary tests first (Krawczyk on balls and on float batches)
_KERNEL_TESTS = ["tests/test_certify_inflation_boundaries.py", "tests/test_certify_kernel_boundaries.py", "tests/test_certify_boundaries.py",
                 "tests/test_float_krawczyk.py", "tests/test_interval_newton.py"]
_SEGMENT_CERT_TESTS = ["tests/test_common_tangent_ties.py", "tests/test_arc_bisector_chord_bounds.py",
                       "tests/test_exact_vertex_radicals.py",
                       "tests/test_segment_certificate_boundaries.py", "tests/test_segment_certificate_mutants.py", "tests/test_segment_certificate.py",
                       "tests/test_arc_certificate.py", "tests/test_segment_voronoi.py",
                       # whole circles as two half arcs (kills certificate_arcs.py's start-parameter match)
                       "tests/test_segment_circles.py"]
#: the far field's own tests (accounting at infinity next to unbounded sites, nesting, big circles)
_FAR_TESTS = ["tests/test_circle_table_big_sites.py", "tests/test_far_field.py", "tests/test_nested_container.py",
              "tests/test_far_conics.py"]
#: boundary tests of the verifier's rounding allowances (the catch-all subset of the verifier's modules)
_VERIFY_BOUNDARY_TESTS = ["tests/test_cocircular_vertex_box.py", "tests/test_support_function_rounding.py",
                          "tests/test_mirror_bisector_tolerance.py", "tests/test_line_bisector_parameter_slack.py",
                          "tests/test_accounting_near_tie_balls.py", "tests/test_far_field_second_order.py"]
#: module prefix -> test files run against its mutants (first match wins); files that do not exist
#: in the copy are left out
SOUND_TESTS: list[tuple[str, list[str]]] = [
    # the verifier's newer modules: their own tests first (arc_search: the batched disc search of
    # an arc's third sites; polyline_bound: the Hausdorff bound of an edge's polyline)
    ("runtime/voronoi/verify/arc_search.py", ["tests/test_arc_search_rounded_curve.py", "tests/test_arc_search_subnormal_scene.py",
                                              "tests/test_arc_search_boundaries.py", "tests/test_arc_search_resolution.py",
                                              "tests/test_arc_search.py", "tests/test_arc_search_refused_job.py"]
     + _VERIFY_TESTS),
    ("runtime/voronoi/verify/polyline_bound.py", ["tests/test_polyline_bound_far_parallel.py",
                                                  "tests/test_polyline_bound_boundaries.py", "tests/test_polyline_bound.py"]
     + _VERIFY_TESTS),
    # bisector_guide: the guide of the chains of strips (its hard places among random ellipses, a
    # vertex beyond the tail cut)
    # strips: the supporting half-planes of (T2) against distances sampled on the disc (~25 s), (T3)
    # against the closed-form derivative along a point bisector
    ("runtime/voronoi/verify/strips.py", ["tests/test_strips_mutants_s38.py", "tests/test_strip_tied_derivative.py",
                                          "tests/test_strip_side_margin.py", "tests/test_strip_side_conjugate_axis.py",
                                          "tests/test_strip_support_half_planes.py",
                                          "tests/test_strip_chunks.py"]
     + _VERIFY_TESTS),
    # the modules first sampled with seed 39 (--spread over the 17 never sampled since the split):
    # each module's own tests (found by their imports of it) before the verifier's subset
    ("runtime/voronoi/verify/far_field.py", ["tests/test_far_field.py", "tests/test_far_field_second_order.py"]
     + _FAR_TESTS + _VERIFY_TESTS),
    ("runtime/voronoi/verify/hull_nesting.py", ["tests/test_hull_nesting_mutants_s39.py", "tests/test_nested_container.py"] + _FAR_TESTS + _VERIFY_TESTS),
    ("runtime/voronoi/verify/hull_points.py", ["tests/test_hull_candidates_between_samples.py",
                                               "tests/test_proof_inequalities.py"] + _VERIFY_TESTS),
    ("runtime/voronoi/verify/medial_corners.py", ["tests/test_medial_corners.py", "tests/test_medial_corner_without_bracket.py"]
     + _VERIFY_TESTS),
    ("runtime/voronoi/verify/mirror_tail.py", ["tests/test_mirror_edge_third_sites.py",
                                               "tests/test_mirror_bisector_tolerance.py"] + _VERIFY_TESTS),
    ("runtime/voronoi/verify/outcome.py", ["tests/test_problems_faulted_sites.py", "tests/test_problem_records.py"] + _VERIFY_TESTS),
    ("runtime/voronoi/verify/problems.py", ["tests/test_problems_faulted_sites.py", "tests/test_problem_records.py"] + _VERIFY_TESTS),
    ("runtime/voronoi/verify/support.py", ["tests/test_support_table.py", "tests/test_support_function_rounding.py"]
     + _VERIFY_TESTS),
    ("runtime/voronoi/verify/support_balls.py", ["tests/test_support_balls_mutants_s39.py", "tests/test_accounting_near_tie_balls.py", "tests/test_tail_near_tie.py"]
     + _VERIFY_TESTS),
    ("runtime/voronoi/verify/tail_link.py", ["tests/test_far_conics.py"] + _VERIFY_TESTS),
    ("runtime/voronoi/verify/tail.py", ["tests/test_tail_monotone_boundaries.py", "tests/test_far_conics.py",
                                        "tests/test_tail_near_tie.py"] + _VERIFY_TESTS),
    ("runtime/voronoi/verify/tied_tail.py", ["tests/test_tied_tail_lateral_sign.py", "tests/test_translate_ties.py",
                                             "tests/test_tied_tails.py", "tests/test_proof_inequalities.py"]
     + _VERIFY_TESTS),
    ("runtime/voronoi/verify/ties_at_infinity.py", ["tests/test_ties_at_infinity_mutants_s39.py", "tests/test_tied_tails.py", "tests/test_translate_ties.py",
                                                    "tests/test_accounting_near_tie_balls.py"] + _VERIFY_TESTS),
    ("runtime/voronoi/verify/vertices.py", ["tests/test_circle_vertex_boxes.py", "tests/test_cocircular_vertex_box.py",
                                            "tests/test_vertex_reach_closed_balls.py", "tests/test_proof_inequalities.py"]
     + _VERIFY_TESTS),
    # the modules' own boundary tests, written for the survivors of the seed-38 sample
    ("runtime/voronoi/verify/closure.py", ["tests/test_closure_accounting_arcs.py", "tests/test_closure_mutants_s38.py",
                                           "tests/test_verify_fewer_than_two_sites.py"] + _FAR_TESTS + _VERIFY_TESTS),
    ("runtime/voronoi/verify/document.py", ["tests/test_document_mutants_s38.py"] + _VERIFY_TESTS),
    ("runtime/voronoi/verify/curved.py", ["tests/test_curved_mutants_s38.py", "tests/test_strip_chaining_tiny_turns.py",
                                          "tests/test_strip_chaining.py"] + _VERIFY_TESTS),
    ("runtime/voronoi/verify/distance_gap.py", ["tests/test_distance_gap_mutants_s38.py",
                                                "tests/test_second_order_bounds.py"] + _VERIFY_TESTS),
    ("runtime/voronoi/verify/conic_vertices.py", ["tests/test_conic_vertices_mutants_s38.py",
                                                  "tests/test_conic_vertex_newton_start.py"] + _VERIFY_TESTS),
    ("runtime/voronoi/verify/clarke_gradient.py", ["tests/test_clarke_gradient_thin_ellipse.py",
                                                   "tests/test_clarke_gradient.py"] + _VERIFY_TESTS),
    ("runtime/voronoi/verify/site_table.py", ["tests/test_gradient_enclosure_inside_circle.py",
                                              "tests/test_gradient_enclosure_discs.py", "tests/test_gradient_blocks.py"]
     + _VERIFY_TESTS),
    ("runtime/voronoi/verify/exact_vertices.py", ["tests/test_exact_vertices_mutants_s38.py", "tests/test_verify_repeated_site.py",
                                                  "tests/test_symmetric_vertex_box.py"] + _VERIFY_TESTS),
    # sites given as pairs, the empty diagram, the tails between conics, mirror ellipses beside a
    # parabola (no support table): the seed-38 stricter survivors (the catch-all's tests kept)
    ("runtime/voronoi/verify/certificate.py", ["tests/test_verify_site_forms.py", "tests/test_verify_fewer_than_two_sites.py"]
     + _VERIFY_BOUNDARY_TESTS + _VERIFY_TESTS),
    ("runtime/voronoi/verify/conic_tail.py", ["tests/test_far_conics.py"] + _VERIFY_BOUNDARY_TESTS + _VERIFY_TESTS),
    ("runtime/voronoi/verify/curved_edges.py", ["tests/test_mirror_ellipses_beside_a_parabola.py"]
     + _VERIFY_BOUNDARY_TESTS + _VERIFY_TESTS),
    ("runtime/voronoi/verify/ellipse_normal.py", ["tests/test_ellipse_normal_mutants_s38.py",
                                                  "tests/test_ellipse_normal.py"] + _VERIFY_TESTS),
    ("runtime/voronoi/verify/far_accounting.py", ["tests/test_far_accounting_mutants_s38.py"] + _FAR_TESTS + _VERIFY_TESTS),
    ("runtime/voronoi/verify/far_conics.py", _FAR_TESTS + _VERIFY_TESTS),
    ("runtime/voronoi/verify/equal_circles.py", ["tests/test_equal_circles_reduction.py"] + _VERIFY_TESTS),
    ("runtime/voronoi/verify/bisector_guide.py", ["tests/test_adapt_many.py", "tests/test_guide_projection_and_bend_rules.py",
                                                  "tests/test_curved_edge_guides.py", "tests/test_verify_float_boundaries.py"]
     + _VERIFY_TESTS),
    # boundary tests of the verifier's rounding allowances: the box of an exact co-circular vertex,
    # the support functions' mu (also recentred), an edge's stated tolerance (mirror ellipses); the
    # accounting at infinity where only the ball fallback decides, the far field's δ² term
    ("runtime/voronoi/verify/", _VERIFY_BOUNDARY_TESTS + _VERIFY_TESTS),
    # the verifier run chunk by chunk on Dask workers (a LocalCluster of threads in the tests)
    ("runtime/voronoi/chunked_certificate.py", ["tests/test_chunked_certificate_mutants.py",
                                                "tests/test_chunked_certificate_ties.py",
                                                "tests/test_chunked_certificate_meeting_circles.py"]),
    # krawczyk / foot / interval_newton serve the diagram's vertex proofs too (runtime/voronoi/vertex.py)
    ("runtime/certify/krawczyk.py", _KERNEL_TESTS + _CERTIFY_TESTS + ["tests/test_voronoi_verify.py"]),
    ("runtime/certify/foot.py", _CERTIFY_TESTS + ["tests/test_voronoi_verify.py"]),
    ("runtime/certify/interval_newton.py", _KERNEL_TESTS + _CERTIFY_TESTS + ["tests/test_voronoi_verify.py"]),
    # offset_system: Newton's stopping rule of the tracked solutions at its boundary first
    ("runtime/certify/offset_system.py", ["tests/test_newton_track_stopping_rule.py"] + _CERTIFY_TESTS),
    ("runtime/certify/", _CERTIFY_TESTS),
    # the segment/arc certificate (verify_segments)
    ("runtime/segments/certificate", _SEGMENT_CERT_TESTS),
]

#: operand names that read as a width, a slack, an error term or a safety margin (drop-term)
_SLACK = re.compile(r"(^h\d?$|^H\d?$|^h_|_h$|^hh|eps|tol|slack|margin|rad|err|wid|pad|lip|^L$|delta|half|^w\d?$|"
                    r"^W$|gap|infl|fuzz|ulp|^s[FI]$|^sl|^dJ|^contr|^base$|^sig|^mag|^scale|^r_?hi|^r_?lo|^prec)", re.I)
_NOFACTOR_CALLS = {"range", "round", "int", "len", "enumerate", "zip", "print", "reshape", "format", "isclose",
                   "linspace", "arange", "zeros", "ones", "full", "empty", "eye", "max_iter", "islice"}
STRICT = {ast.Lt: ast.LtE, ast.LtE: ast.Lt, ast.Gt: ast.GtE, ast.GtE: ast.Gt}
DIRECTION = {ast.Lt: ast.Gt, ast.LtE: ast.GtE, ast.Gt: ast.Lt, ast.GtE: ast.LtE}
SOUND_OPERATORS = ["cmp-strict", "cmp-direction", "drop-term", "factor", "skip-continue", "skip-problem",
                   "drop-conjunct", "early-success"]


def _names(node: ast.AST) -> list[str]:
    out = []
    for n in ast.walk(node):
        if isinstance(n, ast.Name):
            out.append(n.id)
        elif isinstance(n, ast.Attribute):
            out.append(n.attr)
    return out


def _slack_like(node: ast.AST) -> bool:
    if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) and not isinstance(node.value, bool):
        return 0 < abs(node.value) < 1e-3
    if any(_SLACK.search(n) for n in _names(node)):
        return True
    return any(isinstance(n, ast.Constant) and isinstance(n.value, float) and 0 < abs(n.value) < 1e-3
               for n in ast.walk(node))


def _parents(tree: ast.AST) -> dict:
    par = {}
    for p in ast.walk(tree):
        for c in ast.iter_child_nodes(p):
            par[c] = p
    return par


def _fmt_num(v) -> str:
    return repr(v)


def enumerate_sound_mutants(path: str, src: str) -> list[dict]:
    """Every soundness-weakening mutation of ``src`` (one per mutant): dicts with the source span
    (line, col, end_line, end_col; columns in characters), the replacement text, the operator
    (``kind``), the enclosing function and a one-line description."""
    tree = ast.parse(src)
    par = _parents(tree)
    lines = src.splitlines(keepends=True)
    docs = _docstring_lines(src)
    spans = sorted(((n.lineno, n.end_lineno, n.name) for n in ast.walk(tree)
                    if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef))), key=lambda t: t[0])

    def owner(line: int) -> str:
        best = "<module>"
        for a, b, name in spans:
            if a <= line <= b:
                best = name
        return best

    def chars(line: int, col_bytes: int) -> int:
        return len(lines[line - 1].encode("utf-8")[:col_bytes].decode("utf-8", errors="ignore"))

    out: list[dict] = []

    def add(node, new: str, kind: str, what: str, stmt: bool = False):
        if node.lineno in docs:
            return
        old = ast.get_source_segment(src, node) or ""
        out.append(dict(path=path, line=node.lineno, col=chars(node.lineno, node.col_offset),
                        end_line=node.end_lineno, end_col=chars(node.end_lineno, node.end_col_offset),
                        old=old, new=new, kind=kind, function=owner(node.lineno), what=what, stmt=stmt))

    def expr(node) -> str:
        return "(" + ast.unparse(node) + ")"

    for node in ast.walk(tree):
        # ---- comparisons: strictness and direction, one operator at a time
        if isinstance(node, ast.Compare):
            for i, op in enumerate(node.ops):
                for kind, table in (("cmp-strict", STRICT), ("cmp-direction", DIRECTION)):
                    if type(op) in table:
                        new = ast.Compare(left=node.left, ops=list(node.ops), comparators=node.comparators)
                        new.ops[i] = table[type(op)]()
                        add(node, expr(new), kind, f"{type(op).__name__} -> {table[type(op)].__name__}")
        # ---- drop a width / slack term: x + h -> x, lo - H -> lo, h + x -> x
        elif isinstance(node, ast.BinOp) and isinstance(node.op, (ast.Add, ast.Sub)):
            if _slack_like(node.right) and not (isinstance(node.left, ast.Constant) and isinstance(node.op, ast.Sub)):
                add(node, expr(node.left), "drop-term", f"drop {ast.unparse(node.right)[:40]}")
            elif isinstance(node.op, ast.Add) and _slack_like(node.left) and not _slack_like(node.right):
                add(node, expr(node.right), "drop-term", f"drop {ast.unparse(node.left)[:40]}")
        # ---- loosen a constant factor: c -> 0, c -> 2c
        elif isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) \
                and not isinstance(node.value, bool) and node.value not in (0, 1):
            p = par.get(node)
            q = p
            while isinstance(q, ast.UnaryOp):
                q = par.get(q)
            ok_ctx = False
            if isinstance(q, ast.BinOp) and not (isinstance(q.op, ast.Pow) and q.right is node):
                ok_ctx = True
            elif isinstance(q, ast.Compare):
                ok_ctx = True
            elif isinstance(q, (ast.Assign, ast.AnnAssign)) and owner(node.lineno) == "<module>":
                ok_ctx = True
            if ok_ctx:
                gp = par.get(q)
                while isinstance(gp, (ast.BinOp, ast.UnaryOp)):
                    gp = par.get(gp)
                if isinstance(gp, (ast.Subscript, ast.keyword)) or isinstance(gp, ast.Call) and (
                        isinstance(gp.func, ast.Name) and gp.func.id in _NOFACTOR_CALLS
                        or isinstance(gp.func, ast.Attribute) and gp.func.attr in _NOFACTOR_CALLS):
                    ok_ctx = False
            if ok_ctx:
                add(node, "0", "factor", f"{node.value!r} -> 0")
                add(node, _fmt_num(node.value * 2), "factor", f"{node.value!r} -> {node.value * 2!r}")
        # ---- skip a case
        elif isinstance(node, ast.Continue):
            add(node, "pass", "skip-continue", "continue -> pass", stmt=True)
        elif isinstance(node, ast.Expr) and isinstance(node.value, ast.Call) \
                and isinstance(node.value.func, ast.Attribute) and node.value.func.attr in ("append", "extend") \
                and "problem" in ast.unparse(node.value.func.value).lower():
            add(node, "pass", "skip-problem", "problems.append deleted", stmt=True)
        elif isinstance(node, ast.AugAssign) and isinstance(node.op, ast.BitAnd):
            add(node, "pass", "drop-conjunct", f"{ast.unparse(node.target)} &= ... deleted", stmt=True)
        elif isinstance(node, ast.BoolOp) and isinstance(node.op, ast.And):
            for i in range(len(node.values)):
                rest = node.values[:i] + node.values[i + 1:]
                new = rest[0] if len(rest) == 1 else ast.BoolOp(op=ast.And(), values=rest)
                add(node, expr(new), "drop-conjunct", f"drop conjunct {ast.unparse(node.values[i])[:40]}")
        # ---- return early with success
        elif isinstance(node, ast.Return) and node.value is not None:
            v = node.value
            first = v.elts[0] if isinstance(v, ast.Tuple) and v.elts else v
            if isinstance(first, ast.Constant) and first.value is False:
                add(first, "True", "early-success", "return False -> True")
        elif isinstance(node, ast.Assign) and isinstance(node.value, ast.Constant) and node.value.value is False:
            add(node.value, "True", "early-success", f"{ast.unparse(node.targets[0])[:30]} = False -> True")
    # the unparsed replacement must compile and differ from the source
    good = []
    for m in out:
        try:
            mutated = apply_span(src, m)
            compile(mutated, path, "exec")
        except (SyntaxError, ValueError):
            continue
        if ast.dump(ast.parse(mutated)) != ast.dump(tree):
            good.append(m)
    good.sort(key=lambda m: (m["line"], m["col"], m["kind"], m["new"]))
    return good


def apply_span(src: str, m: dict) -> str:
    lines = src.splitlines(keepends=True)
    a, b = m["line"] - 1, m["end_line"] - 1
    head, tail = lines[a][:m["col"]], lines[b][m["end_col"]:]
    seg = "".join(lines[a:b + 1])[len(lines[a][:m["col"]]):]
    seg = seg[:len(seg) - len(tail)] if tail else seg
    if m["old"] and seg != m["old"]:
        raise ValueError(f"span mismatch at {m['path']}:{m['line']}")
    return "".join(lines[:a]) + head + m["new"] + tail + "".join(lines[b + 1:])


def sample_stratified(muts: list[dict], n: int, seed: int, spread: bool = False) -> list[dict]:
    """``n`` mutants spread evenly over the strata (module, operator): each stratum gets
    floor(n / strata) or one more, a small stratum gives its spare quota to the others; within a
    stratum a seeded sample.  Deterministic for a given candidate list and seed.

    With fewer mutants than strata the strata served first are, by default, the first in
    alphabetical order (the last modules get none); ``spread`` serves them round-robin over the
    modules instead (each module's operators in a seeded order), so every module gets about
    n / modules mutants."""
    rng = random.Random(seed)
    strata: dict[tuple[str, str], list[dict]] = {}
    for m in muts:
        strata.setdefault((m["path"], m["kind"]), []).append(m)
    keys = sorted(strata)
    for k in keys:
        rng.shuffle(strata[k])
    if spread:
        by_mod: dict[str, list] = {}
        for k in keys:
            by_mod.setdefault(k[0], []).append(k)
        for ks in by_mod.values():
            rng.shuffle(ks)
        keys = [ks[i] for i in range(max(map(len, by_mod.values()), default=0))
                for ks in by_mod.values() if i < len(ks)]
    quota = {k: 0 for k in keys}
    left = min(n, len(muts))
    while left > 0:
        open_ = [k for k in keys if quota[k] < len(strata[k])]
        if not open_:
            break
        share = max(1, left // len(open_))
        for k in open_:
            if left == 0:
                break
            take = min(share, len(strata[k]) - quota[k], left)
            quota[k] += take
            left -= take
    chosen = [m for k in keys for m in strata[k][:quota[k]]]
    return sorted(chosen, key=lambda m: (m["path"], m["line"], m["col"], m["kind"]))


#: test files run before every module's subset (``--first-tests``: a re-run of survivors with the
#: tests written for them first, so that a kill costs seconds; a survivor still runs the whole subset)
FIRST_TESTS: list[str] = []
#: ``--only-first``: run only FIRST_TESTS (they belong to the module's subset, so a failure there is
#: a failure of the subset under ``-x``: a kill; a mutant they do not kill keeps its earlier status)
ONLY_FIRST = False


def _tests_for(rel: str, tree: Path) -> list[str]:
    for prefix, tests in SOUND_TESTS:
        if rel.startswith(prefix):
            # a test file, or one test of it ("file::name"): kept when the file exists in the copy
            chosen = FIRST_TESTS if ONLY_FIRST else FIRST_TESTS + tests
            return [t for t in dict.fromkeys(chosen) if (tree / t.split("::")[0]).exists()]
    return []


def _failing_ids(tree: Path, tests: list[str], timeout: float) -> tuple[list[str], str]:
    """Node ids that fail on the UNMUTATED copy (others' work in progress): deselected in every
    mutant run of that subset, and listed in the report."""
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", PYTHONPATH=str(tree), PYTHONDONTWRITEBYTECODE="1")
    cmd = [sys.executable, "-m", "pytest", "-q", "-rfE", "-p", "no:cacheprovider", "-m", "not slow", *tests]
    p = subprocess.run(cmd, cwd=tree, env=env, capture_output=True, text=True, timeout=timeout * 4)
    bad = []
    for line in p.stdout.splitlines():
        if line.startswith(("FAILED ", "ERROR ")):
            bad.append(line.split()[1])
    return bad, (p.stdout.strip().splitlines() or [""])[-1]


def _check_copy_is_imported(tree: Path, rel: str) -> None:
    """The tests must import the COPY, not the editable install of the repository."""
    mod = "curvedvoronoi." + rel[:-3].replace("/", ".").replace(".__init__", "")
    env = dict(os.environ, PYTHONPATH=str(tree), PYTHONDONTWRITEBYTECODE="1")
    p = subprocess.run([sys.executable, "-c", f"import {mod} as m; print(m.__file__)"], cwd=tree, env=env,
                       capture_output=True, text=True)
    where = p.stdout.strip()
    if not where.startswith(str(tree)):
        raise SystemExit(f"the tests would import {mod} from {where or p.stderr.strip()[-200:]}, not the copy {tree}")


def _run_mutant(tree: Path, m: dict, tests: list[str], deselect: list[str], timeout: float) -> tuple[str, float, str]:
    f = tree / m["path"]
    src = f.read_text()
    try:
        f.write_text(apply_span(src, m))
        cmd_extra = [a for d in deselect for a in ("--deselect", d)]
        st, dt, last = run_tests(tree, tests + cmd_extra, None, timeout)
    finally:
        f.write_text(src)
    return st, dt, last


def _replay(allm: list[dict], path: str, statuses: set | None = None) -> list[dict]:
    """The mutants of an earlier run (its .jsonl), found again in today's tree by module, operator,
    old and new text (the nearest line wins: others edit the modules meanwhile)."""
    import json

    out, pending = [], []
    for line in Path(path).read_text().splitlines():
        r = json.loads(line)
        if statuses and r.get("status") not in statuses:
            continue
        cands = [m for m in allm if (m["path"], m["kind"], m["old"], m["new"]) == (r["path"], r["kind"], r["old"], r["new"])]
        if not cands and r["kind"] == "skip-problem":
            # the problem's text was reworded meanwhile (e.g. wrapped in a record): the same
            # statement deleted, found by its function and the nearest line
            import difflib

            cands = [m for m in allm if (m["path"], m["kind"], m["function"]) == (r["path"], r["kind"], r["function"])
                     and abs(m["line"] - r["line"]) <= 15]
            if cands:
                best = max(cands, key=lambda m: difflib.SequenceMatcher(None, m["old"], r["old"]).ratio())
                cands = [best]
                print(f"replay: {r['path']}:{r['line']} {r['kind']} matched by function and text at line {best['line']}",
                      flush=True)
        if not cands:
            print(f"replay: {r['path']}:{r['line']} {r['kind']} {r['what']} no longer in the source", flush=True)
            continue
        same = [m for m in cands if (m["what"], m["function"]) == (r["what"], r["function"])]
        if not same and not (len(cands) == 1 and len(r["old"]) >= 12):
            # moved to another function: only a long text found once is the same mutant; a short
            # one (`0.5`, `2`, `False`) elsewhere is another mutant (a false kill otherwise)
            print(f"replay: {r['path']}:{r['line']} {r['kind']} {r['what']}: not in {r['function']} any more, "
                  f"{len(cands)} look-alike(s) elsewhere not taken (replay by hand)", flush=True)
            continue
        pending.append((r, same or cands))
    # others edit the modules meanwhile: a text that occurs once gives the file's line shift, and a
    # text that occurs several times (a constant, `False`) is taken nearest to its shifted line
    shifts: dict = {}
    for r, cands in pending:
        if len(cands) == 1:
            shifts.setdefault(r["path"], []).append((r["line"], cands[0]["line"] - r["line"]))
    for r, cands in pending:
        # the shift of the nearest uniquely found mutant of the same file (edits shift a region)
        near = min(shifts.get(r["path"], [(r["line"], 0)]), key=lambda t: abs(t[0] - r["line"]))
        want = r["line"] + near[1]
        best = min(cands, key=lambda m: abs(m["line"] - want))
        if len(cands) > 1 and (abs(best["line"] - want) > 3
                               or sum(abs(m["line"] - want) == abs(best["line"] - want) for m in cands) > 1):
            # the same text several times in the function and none where the shift puts it:
            # the code around it moved, and the nearest look-alike may be another mutant
            print(f"replay: {r['path']}:{r['line']} {r['kind']} {r['what']}: {len(cands)} look-alikes, none at "
                  f"line {want} (±3): not taken (replay by hand)", flush=True)
            continue
        if len(cands) > 1:
            print(f"replay: {r['path']}:{r['line']} {r['kind']} {r['what']}: {len(cands)} candidates, "
                  f"line {best['line']} taken (shift {near[1]} of the mutant at line {near[0]})", flush=True)
        out.append(best)
    return out


def main_soundness(args) -> int:
    import concurrent.futures as cf
    import glob
    import json

    t_start = time.perf_counter()
    trees = [copy_tree(Path(f"{args.work}-{j}") if args.jobs > 1 else Path(args.work)) for j in range(args.jobs)]
    tree = trees[0]
    pats = args.modules or SOUND_MODULES
    rels = sorted({str(Path(p).relative_to(tree)) for pat in pats for p in glob.glob(str(tree / pat), recursive=True)
                   if p.endswith(".py")})
    allm: list[dict] = []
    for rel in rels:
        allm += enumerate_sound_mutants(rel, (tree / rel).read_text())
    if args.list:
        for m in allm:
            print(f"{m['path']}:{m['line']} {m['kind']} {m['what']}")
        print(len(allm), "candidates")
        return 0
    if args.replay:
        chosen = _replay(allm, args.replay, set(args.replay_status.split(",")) if args.replay_status else None)
    else:
        chosen = sample_stratified(allm, args.max_mutants, args.seed, spread=args.spread)
    print(f"{len(allm)} candidate mutants in {len(rels)} modules; sample of {len(chosen)} (seed {args.seed})", flush=True)
    subsets = sorted({tuple(_tests_for(m["path"], tree)) for m in chosen})
    deselect: dict[tuple, list[str]] = {}
    baseline_notes = []
    for sub in subsets:
        _check_copy_is_imported(tree, next(m["path"] for m in chosen if tuple(_tests_for(m["path"], tree)) == sub))
        if args.skip_baseline:
            deselect[sub] = []
            baseline_notes.append((sub, [], "baseline skipped (--skip-baseline)"))
            continue
        bad, last = _failing_ids(tree, list(sub), args.timeout)
        deselect[sub] = bad
        baseline_notes.append((sub, bad, last))
        print(f"baseline {' '.join(s.replace('tests/', '') for s in sub)}: {last}; deselected {bad}", flush=True)
    rows: list[dict] = []
    jsonl = Path(args.out).with_suffix(".jsonl")

    def work(job: int, m: dict) -> dict:
        sub = tuple(_tests_for(m["path"], trees[job]))
        st, dt, last = _run_mutant(trees[job], m, list(sub), deselect[sub], args.timeout)
        return dict(m, status=st, seconds=dt, last=last, tests=" ".join(sub))

    with jsonl.open("w") as fh:
        if args.jobs == 1:
            results = (work(0, m) for m in chosen)
        else:
            ex = cf.ThreadPoolExecutor(args.jobs)
            import queue
            free: "queue.Queue[int]" = queue.Queue()
            for j in range(args.jobs):
                free.put(j)

            def w(m):
                j = free.get()
                try:
                    return work(j, m)
                finally:
                    free.put(j)
            results = ex.map(w, chosen)
        for i, r in enumerate(results, 1):
            rows.append(r)
            fh.write(json.dumps(r) + "\n")
            fh.flush()
            print(f"[{i}/{len(chosen)}] {r['path']}:{r['line']} {r['kind']} {r['what']}: {r['status']} "
                  f"({r['seconds']:.0f} s)", flush=True)
    total = time.perf_counter() - t_start
    write_sound_report(rows, args, total, len(allm), baseline_notes)
    return 0


def write_sound_report(rows, args, total, n_candidates, baseline_notes) -> None:
    cmdline = " ".join(a if " " not in a else repr(a) for a in sys.argv[1:])
    killed = sum(r["status"] == "killed" for r in rows)
    surv = [r for r in rows if r["status"] == "survived"]
    tmo = sum(r["status"] == "timeout" for r in rows)
    L = [f"## {args.title}", "",
         f"Command: `OPENBLAS_NUM_THREADS=1 python bench/mutation_check.py {cmdline}` — sample seed {args.seed}, "
         f"{len(rows)} of {n_candidates} candidate mutants (stratified by module and operator), "
         f"{total:.0f} s wall on a shared 2-core machine.", "",
         f"**{killed} of {len(rows)} killed ({100 * killed / max(1, len(rows)):.0f} %), {len(surv)} survived, "
         f"{tmo} timed out.**  Each mutant: `pytest -x -q -m 'not slow'` on the module's test subset "
         f"(timeout {args.timeout:.0f} s), in a copy of the tree.", ""]
    for sub, bad, last in baseline_notes:
        L.append(f"- subset {', '.join(s.replace('tests/', '') for s in sub)}: unmutated `{last}`"
                 + (f"; failing before any mutation, deselected: {', '.join(bad)}" if bad else ""))
    L += ["", "| module | operator | mutants | killed | survived | timeout |", "|---|---|---|---|---|---|"]
    agg: dict[tuple[str, str], list[int]] = {}
    for r in rows:
        a = agg.setdefault((r["path"], r["kind"]), [0, 0, 0, 0])
        a[0] += 1
        a[1] += r["status"] == "killed"
        a[2] += r["status"] == "survived"
        a[3] += r["status"] == "timeout"
    for (p, k), a in sorted(agg.items()):
        L.append(f"| {p.replace('runtime/', '')} | {k} | {a[0]} | {a[1]} | {a[2]} | {a[3]} |")
    L += ["", "| operator | mutants | killed | survived |", "|---|---|---|---|"]
    for k in SOUND_OPERATORS:
        rs = [r for r in rows if r["kind"] == k]
        if rs:
            L.append(f"| {k} | {len(rs)} | {sum(r['status'] == 'killed' for r in rs)} | "
                     f"{sum(r['status'] == 'survived' for r in rs)} |")
    L += ["", "Survivors (and timeouts):", "", "| file:line | function | operator | diff |", "|---|---|---|---|"]
    for r in rows:
        if r["status"] in ("survived", "timeout", "no tests"):
            old = r["old"].replace("\n", " ").replace("|", "\\|")
            new = r["new"].replace("|", "\\|")
            L.append(f"| {r['path']}:{r['line']} | {r['function']} | {r['kind']} ({r['status']}) | "
                     f"`{old[:90]}` → `{new[:90]}` |")
    text = "\n".join(L) + "\n"
    print(text)
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    if args.append and out.exists():
        with out.open("a") as fh:
            fh.write("\n" + text)
    else:
        out.write_text(text)



#: readings of a surviving mutant that cannot turn a wrong diagram into a proved one (merge_report):
#: equivalent (no verdict can change), heuristic (numerical steering before a proof), unreachable
#: (needs an input excluded earlier), redundant (another check rejects the same inputs), stricter
#: (the mutant only rejects more), message (verdict unchanged, only the problem text is lost), sound
#: (a weaker bound or test that is still a valid one: it accepts more, never a wrong diagram).
#: ``rounding`` (a slack of a few ulps) and ``OPEN`` are counted as open.
SOUND_EXPLAINED = ("equivalent", "heuristic", "unreachable", "redundant", "stricter", "message", "sound")


def _mkey(r: dict) -> str:
    return f"{r['path']}:{r['line']} {r['kind']} {r['what']}"


def final_rows(first: str, after: list[str]) -> list[dict]:
    """The records of a sample (``first``, a .jsonl), each with ``final``: its status after the
    re-runs ``after`` (.jsonl files of ``--replay``; a mutant killed once stays killed, tests being
    only added)."""
    import json

    rows = [json.loads(x) for x in Path(first).read_text().splitlines()]
    # a re-run record is the same mutant when module, operator, old and new text agree, within the
    # same function, at the nearest line (a constant such as `4` or `2` recurs in a module)
    later: dict[tuple, list] = {}
    reworded: list[dict] = []
    for a in after:
        for x in Path(a).read_text().splitlines():
            r = json.loads(x)
            later.setdefault((r["path"], r["kind"], r["old"], r["new"]), []).append(r)
            if r["kind"] == "skip-problem":
                reworded.append(r)

    twins: dict[tuple, int] = {}
    twin_lines: dict[tuple, list] = {}
    for r in rows:
        k5 = (r["path"], r["kind"], r["old"], r["new"], r["function"])
        twins[k5] = twins.get(k5, 0) + 1
        twin_lines.setdefault(k5, []).append((r["line"], r.get("col", 0)))

    def _same(r):
        cands = [x for x in later.get((r["path"], r["kind"], r["old"], r["new"]), [])
                 if x["function"] == r["function"]]
        if not cands:
            return None
        k5 = (r["path"], r["kind"], r["old"], r["new"], r["function"])
        if twins[k5] > 1:
            # the same text twice in one function (both sampled): a re-run record speaks for the
            # sampled twin nearest to its line, then column, only (equally near two: for neither),
            # so one kill is never counted for two mutants
            def _owner(x):
                ds = sorted(((abs(x["line"] - ln), abs(x.get("col", 0) - co)), (ln, co)) for ln, co in twin_lines[k5])
                return ds[0][1] if len(ds) < 2 or ds[0][0] < ds[1][0] else None
            cands = [x for x in cands if _owner(x) == (r["line"], r.get("col", 0))]
            if not cands:
                return None
        return "killed" if any(x["status"] == "killed" for x in cands) else cands[-1]["status"]

    def _later(r):
        got = _same(r)
        if got is None and r["kind"] == "skip-problem":
            # the statement was reworded meanwhile: as _replay, the same function, the nearest line
            near = [x for x in reworded if (x["path"], x["function"]) == (r["path"], r["function"])
                    and abs(x["line"] - r["line"]) <= 15]
            if near:
                import difflib

                got = max(near, key=lambda x: difflib.SequenceMatcher(None, x["old"], r["old"]).ratio())["status"]
        return got if got is not None else r["status"]

    for r in rows:
        r["final"] = r["status"] if r["status"] == "killed" else _later(r)
    return rows


def merge_report(first: str, after: list[str], verdicts: str | None, title: str) -> str:
    """The table of a sample (``first``, a .jsonl) with the survivors re-run after new tests
    (``after``) and the reading of each remaining survivor (``verdicts``: a JSON object mapping
    "path:line kind what" to "equivalent: why" / "heuristic: why" / ...)."""
    import json

    rows = final_rows(first, after)
    why = json.loads(Path(verdicts).read_text()) if verdicts else {}
    n = len(rows)
    k0 = sum(r["status"] == "killed" for r in rows)
    k1 = sum(r["final"] == "killed" for r in rows)
    left = [r for r in rows if r["final"] != "killed"]
    reading = {r["path"] + str(r["line"]) + r["kind"] + r["what"]: why.get(_mkey(r), "").split(":")[0].strip() or "unread"
               for r in left}
    eq = [r for r in left if reading[r["path"] + str(r["line"]) + r["kind"] + r["what"]] in SOUND_EXPLAINED]
    rnd = [r for r in left if reading[r["path"] + str(r["line"]) + r["kind"] + r["what"]] == "rounding"]
    counts: dict = {}
    for v in reading.values():
        counts[v] = counts.get(v, 0) + 1
    L = [f"## {title}", "",
         f"**Before the new tests: {k0} of {n} killed ({100 * k0 / max(1, n):.0f} %).  After: {k1} of {n} killed "
         f"({100 * k1 / max(1, n):.0f} %); of the {len(left)} left, {len(eq)} are explained as equivalent for "
         f"soundness ({' / '.join(SOUND_EXPLAINED)}), {len(rnd)} are rounding slacks (explained, no test reaches "
         f"them), {len(left) - len(eq) - len(rnd)} are open.**  Readings of the survivors: "
         + ", ".join(f"{k} {v}" for k, v in sorted(counts.items(), key=lambda kv: (-kv[1], kv[0]))) + ".", "",
         "| module | operator | mutants | killed before | killed after | left |", "|---|---|---|---|---|---|"]
    agg: dict = {}
    for r in rows:
        a = agg.setdefault((r["path"], r["kind"]), [0, 0, 0, 0])
        a[0] += 1
        a[1] += r["status"] == "killed"
        a[2] += r["final"] == "killed"
        a[3] += r["final"] != "killed"
    for (p, k), a in sorted(agg.items()):
        L.append(f"| {p.replace('runtime/', '')} | {k} | {a[0]} | {a[1]} | {a[2]} | {a[3]} |")
    L += ["", "| module | mutants | killed before | killed after | explained | rounding | open |",
          "|---|---|---|---|---|---|---|"]
    for p in sorted({r["path"] for r in rows}):
        rs = [r for r in rows if r["path"] == p]
        lf = [r for r in rs if r["final"] != "killed"]
        ex = sum(reading[r["path"] + str(r["line"]) + r["kind"] + r["what"]] in SOUND_EXPLAINED for r in lf)
        rd = sum(reading[r["path"] + str(r["line"]) + r["kind"] + r["what"]] == "rounding" for r in lf)
        L.append(f"| {p.replace('runtime/', '')} | {len(rs)} | {sum(r['status'] == 'killed' for r in rs)} | "
                 f"{sum(r['final'] == 'killed' for r in rs)} | {ex} | {rd} | {len(lf) - ex - rd} |")
    L.append(f"| **all** | {n} | {k0} | {k1} | {len(eq)} | {len(rnd)} | {len(left) - len(eq) - len(rnd)} |")
    L += ["", "| operator | mutants | killed before | killed after |", "|---|---|---|---|"]
    for k in SOUND_OPERATORS:
        rs = [r for r in rows if r["kind"] == k]
        if rs:
            L.append(f"| {k} | {len(rs)} | {sum(r['status'] == 'killed' for r in rs)} | "
                     f"{sum(r['final'] == 'killed' for r in rs)} |")
    L += ["", "Survivors of the first run (diff line; result after the new tests; reading):", "",
          "| file:line | function | operator | diff | after | reading |", "|---|---|---|---|---|---|"]
    for r in rows:
        if r["status"] == "killed":
            continue
        old = r["old"].replace("\n", " ").replace("|", "\\|")
        new = r["new"].replace("|", "\\|")
        old = " ".join(old.split())
        L.append(f"| {r['path'].replace('runtime/', '')}:{r['line']} | {r['function']} | {r['kind']} | "
                 f"`{old[:70]}` → `{new[:70]}` | {r['final']} | {why.get(_mkey(r), '').replace('|', '/')} |")
    return "\n".join(L) + "\n"


#: the mutation score in the standard way (mutmut, PIT, Stryker): killed / (mutants − equivalent),
#: where *equivalent* means that no input can change any observable verdict (ok, complete,
#: certified, a vertex's or an edge's flag, an exception instead of a result).  Of the readings
#: above, equivalent, unreachable, redundant (another check gives the same verdict) and message (the
#: verdict is unchanged, only a problem's text) count as equivalent; stricter (rejects more),
#: heuristic (may change whether a part is proved), rounding and OPEN do not.  Exceptions one by
#: one in bench/results/mutation_standard.json ("equivalent: why" / "not: why").
STANDARD_EQUIVALENT = ("equivalent", "unreachable", "redundant", "message")

#: the sampled groups: (name, first .jsonl, re-run .jsonl glob, verdicts .json, key in mutation_standard.json)
SCORE_GROUPS = [
    ("verifier, runtime/voronoi/verify/*.py (seed-32 sample of 2247)", "mutation_verify_sample.jsonl",
     "mutation_verify_rerun*.jsonl", "mutation_verify_verdicts.json", "verify"),
    ("newer verifier modules: verify/arc_search.py, bisector_guide.py, polyline_bound.py (seed 36), "
     "voronoi/chunked_certificate.py (all 13, seed 37)", "mutation_newverify_sample.jsonl",
     "mutation_newverify_rerun*.jsonl", "mutation_newverify_verdicts.json", "newverify"),
    ("segment/arc certificate, runtime/segments/certificate*.py (seed-33 sample of 1532)",
     "mutation_segments_sample.jsonl", "mutation_segments_rerun*.jsonl", "mutation_segments_verdicts.json", "seg"),
    ("certification stage, runtime/certify/*.py (seed-34 sample of 711)", "mutation_certify_sample.jsonl",
     "mutation_certify_rerun*.jsonl", "mutation_certify_verdicts.json", "cert"),
    ("proof kernel, runtime/certify/interval_newton.py + krawczyk.py (all 92)", "mutation_kernel_full.jsonl",
     "mutation_kernel_rerun*.jsonl", "mutation_kernel_verdicts.json", "kernel"),
    ("verifier after its split into named steps, runtime/voronoi/verify/*.py (seed-38 sample of 3689)",
     "mutation_verify38_sample.jsonl", "mutation_verify38_rerun*.jsonl", "mutation_verify38_verdicts.json",
     "verify38"),
    ("verifier modules never sampled since the split, runtime/voronoi/verify/far_field.py … vertices.py "
     "(17 modules, seed-39 --spread sample of 1636)", "mutation_verify39_sample.jsonl", "mutation_verify39_rerun*.jsonl",
     "mutation_verify39_verdicts.json", "verify39"),
]


def score_table(results: Path) -> str:
    """One summary table of every sampled group (SCORE_GROUPS): raw killed ratio, the standard
    score killed / (mutants − equivalent), and the survivors by reading."""
    import json

    std = json.loads((results / "mutation_standard.json").read_text()) \
        if (results / "mutation_standard.json").exists() else {}
    L = ["| group | mutants | killed | equivalent | not equivalent, sound (stricter / heuristic / other) | "
         "rounding | open | raw killed / mutants | standard: killed / (mutants − equivalent) | "
         "killed + explained for soundness |",
         "|---|---|---|---|---|---|---|---|---|---|"]
    for name, first, rerun, verdicts, key in SCORE_GROUPS:
        if not (results / first).exists():
            L.append(f"| {name} | not run | | | | | | | | |")
            continue
        rows = final_rows(str(results / first), sorted(str(p) for p in results.glob(rerun)))
        why = json.loads((results / verdicts).read_text()) if (results / verdicts).exists() else {}
        over = std.get(key, {})
        n, k = len(rows), sum(r["final"] == "killed" for r in rows)
        eq = sound = rnd = opn = 0
        for r in rows:
            if r["final"] == "killed":
                continue
            reading = why.get(_mkey(r), "").split(":")[0].strip() or "unread"
            o = over.get(_mkey(r))
            if o is not None:
                is_eq = o.startswith("equivalent")
            else:
                is_eq = reading in STANDARD_EQUIVALENT
            if is_eq:
                eq += 1
            elif reading in SOUND_EXPLAINED:
                sound += 1
            elif reading == "rounding":
                rnd += 1
            else:
                opn += 1
        L.append(f"| {name} | {n} | {k} | {eq} | {sound} | {rnd} | {opn} | {100 * k / max(1, n):.0f} % | "
                 f"**{100 * k / max(1, n - eq):.0f} %** | {100 * (k + eq + sound) / max(1, n):.0f} % |")
    return "\n".join(L) + "\n"


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
    ap.add_argument("--title", default=None)
    ap.add_argument("--modules", nargs="*", default=None, metavar="GLOB",
                    help="soundness mode: mutate these modules (globs; none given: " + " ".join(SOUND_MODULES) + ")")
    ap.add_argument("--max-mutants", type=int, default=200, help="soundness mode: size of the stratified sample")
    ap.add_argument("--skip-baseline", action="store_true",
                    help="soundness mode: do not run each subset unmutated first (only to continue a run whose "
                         "baselines of the same subsets passed, e.g. the rest of a sample in another order)")
    ap.add_argument("--spread", action="store_true",
                    help="soundness mode: with fewer mutants than strata, serve the strata round-robin over modules")
    ap.add_argument("--jobs", type=int, default=1, help="soundness mode: mutants run side by side (one copy each)")
    ap.add_argument("--list", action="store_true", help="soundness mode: only list the candidate mutants")
    ap.add_argument("--replay", default=None, metavar="JSONL",
                    help="soundness mode: re-run the mutants of an earlier run (its .jsonl) instead of sampling")
    ap.add_argument("--first-tests", nargs="*", default=[], metavar="TEST",
                    help="soundness mode: run these test files first in every subset (re-runs after new tests)")
    ap.add_argument("--only-first", action="store_true",
                    help="with --first-tests: run only those (kills by tests of the subset; survivors keep their status)")
    ap.add_argument("--replay-status", default=None, metavar="S1,S2",
                    help="with --replay: only the mutants that had one of these results (e.g. survived,timeout)")
    ap.add_argument("--merge", nargs="+", default=None, metavar="JSONL",
                    help="write the table of a first run's .jsonl and the .jsonl of its survivors re-run "
                         "after new tests (first file first) to --out; --verdicts reads the survivors' reading")
    ap.add_argument("--verdicts", default=None, metavar="JSON")
    ap.add_argument("--score", action="store_true",
                    help="print the summary table of every sampled group (SCORE_GROUPS) from bench/results")
    args = ap.parse_args(argv)
    if args.score:
        print(score_table(ROOT / "bench" / "results"), end="")
        return 0
    FIRST_TESTS[:] = args.first_tests
    global ONLY_FIRST
    ONLY_FIRST = args.only_first
    if args.merge:
        text = merge_report(args.merge[0], args.merge[1:], args.verdicts,
                            args.title or "Soundness mutants of the verifier and the certification stage")
        print(text)
        Path(args.out).write_text(text) if not args.append else Path(args.out).open("a").write("\n" + text)
        return 0
    if args.modules is not None:
        if args.timeout == 300 and "--timeout" not in (argv if argv is not None else sys.argv):
            args.timeout = 120
        args.title = args.title or "Soundness mutants of the verifier and the certification stage"
        return main_soundness(args)
    args.title = args.title or "Mutation check of the core predicates"
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
