"""Docs that run: every ```python block of README.md, docs/*.md and docs/cli/*.md is executed.

Convention (also stated in docs/index.md, "Code in these pages"):

* The blocks of one file run in order in one fresh namespace, with the current directory a
  temporary folder in which ``examples/`` and ``runtime/data/`` of the repository are reachable
  (symbolic links), so ``"examples/four_ellipses.json"`` and ``"out.png"`` work as written.
* A block containing ``>>>`` lines is a **doctest**: every ``>>>`` line runs, and the lines after it
  (up to the next ``>>>`` or blank line) are the claimed output, compared as doctest does, with
  ``...`` matching anything (ELLIPSIS) and runs of white space equal (NORMALIZE_WHITESPACE).
  Printed claims are written this way only (never as a comment such as ``# -> True``).
* A block without ``>>>`` is plain code: it must run without an exception; it claims nothing.
* A block that must not run is fenced ```` ```python no-run: REASON ```` (the reason is required).
"""
from __future__ import annotations

import doctest
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOC_FILES = sorted([ROOT / "README.md", *(ROOT / "docs").glob("*.md"), *(ROOT / "docs" / "cli").glob("*.md")])
FENCE = re.compile(r"^```python([^\n]*)\n(.*?)^```[ \t]*$", re.M | re.S)
FLAGS = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE


def python_blocks(path: Path) -> list[tuple[int, str, str]]:
    """(line number of the fence, the fence's info after ``python``, the code) of each block."""
    text = path.read_text()
    return [(text.count("\n", 0, m.start()) + 1, m.group(1).strip(), m.group(2)) for m in FENCE.finditer(text)]


FILES_WITH_CODE = [p for p in DOC_FILES if python_blocks(p)]


def _sandbox(tmp_path: Path) -> None:
    (tmp_path / "examples").symlink_to(ROOT / "examples")
    (tmp_path / "runtime").mkdir()
    (tmp_path / "runtime" / "data").symlink_to(ROOT / "runtime" / "data")


@pytest.mark.parametrize("path", FILES_WITH_CODE, ids=lambda p: str(p.relative_to(ROOT)))
def test_snippets_run_and_their_claims_hold(path, tmp_path, monkeypatch):
    pytest.importorskip("matplotlib", reason="the snippets draw pictures (test extra)")
    _sandbox(tmp_path)
    monkeypatch.chdir(tmp_path)
    ns: dict = {"__name__": "__doc_snippets__"}
    rel = path.relative_to(ROOT)
    ran = 0
    for lineno, info, code in python_blocks(path):
        if info.startswith("no-run"):
            continue
        assert info == "", f"{rel}:{lineno}: unknown fence info {info!r} (use 'no-run: REASON')"
        name = f"{rel}:{lineno}"
        if re.search(r"^\s*>>> ", code, re.M):
            test = doctest.DocTestParser().get_doctest(code, ns, name, str(path), lineno)
            runner = doctest.DocTestRunner(optionflags=FLAGS)
            report: list[str] = []
            runner.run(test, out=report.append, clear_globs=False)
            ns.update(test.globs)
            assert runner.failures == 0, f"{name}: a claim does not hold\n" + "".join(report)
        else:
            try:
                exec(compile(code, name, "exec"), ns)
            except Exception as exc:   # noqa: BLE001 - report which snippet failed
                pytest.fail(f"{name}: {type(exc).__name__}: {exc}")
        ran += 1
    assert ran, f"{rel}: every python block is no-run"


def test_no_run_blocks_are_few_and_give_a_reason():
    skipped = [(p.relative_to(ROOT), n, info) for p in DOC_FILES for n, info, _ in python_blocks(p)
               if info.startswith("no-run")]
    for rel, n, info in skipped:
        assert re.fullmatch(r"no-run:\s*\S.{9,}", info), f"{rel}:{n}: 'no-run' needs a reason: {info!r}"
    total = sum(len(python_blocks(p)) for p in DOC_FILES)
    assert len(skipped) <= max(1, total // 5), skipped


def test_fence_parser_and_the_convention_is_documented():
    sample = "x\n```python\na = 1\n```\n```python no-run: needs a licence server\nb\n```\n```bash\nc\n```\n"
    text_blocks = [(m.group(1).strip(), m.group(2)) for m in FENCE.finditer(sample)]
    assert text_blocks == [("", "a = 1\n"), ("no-run: needs a licence server", "b\n")]
    index = (ROOT / "docs" / "index.md").read_text()
    assert "no-run" in index and ">>>" in index and "tests/test_doc_snippets.py" in index
