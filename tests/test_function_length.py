"""The verifier's rooms are small enough to enter (issue 34, CGAL's traits style): no function in
runtime/voronoi/verify/ is longer than 80 lines, its steps named, each with its inequality in its
docstring; the rule is shown to see a long function."""
from __future__ import annotations

import ast
import pathlib

ROOT = pathlib.Path(__file__).resolve().parents[1]


# ----------------------------------------------------------------------------- rooms one can enter

#: the longest function allowed in the verifier (def line to last line, docstring included)
VERIFY_FUNCTION_LINES = 80


def long_functions(files, limit: int = VERIFY_FUNCTION_LINES) -> list[str]:
    """``file:function (n lines)`` for each function (methods and nested ones included) longer
    than ``limit`` lines."""
    out = []
    for f in files:
        for node in ast.walk(ast.parse(f.read_text())):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                n = node.end_lineno - node.lineno + 1
                if n > limit:
                    out.append(f"{f.name}:{node.name} ({n} lines)")
    return sorted(out)


def test_no_verifier_function_is_over_80_lines():
    files = sorted((ROOT / "runtime/voronoi/verify").rglob("*.py"))
    assert len(files) > 20
    assert not long_functions(files), long_functions(files)


def test_the_length_rule_sees_a_long_function(tmp_path):
    body = "".join(f"    x{k} = {k}\n" for k in range(VERIFY_FUNCTION_LINES - 1))
    planted = tmp_path / "planted.py"
    inner = body.replace("    ", "        ")
    planted.write_text(f"def short():\n{body}\n\nclass K:\n    def long(self):\n{inner}        return 0\n")
    assert long_functions([planted]) == [f"planted.py:long ({VERIFY_FUNCTION_LINES + 1} lines)"]
