"""Project tasks (invoke): ``invoke --list``.

* ``invoke regenerate``       -- rebuild every artefact in generated/ (progress + timings shown)
* ``invoke check-generated``  -- rebuild into a temporary folder and byte-compare with generated/
* ``invoke test``             -- the test suite
* ``invoke bench``            -- every benchmark in bench/ (results appended to bench/results/*.md)
* ``invoke demo``             -- the locator demo
* ``invoke docs``             -- the user guide's pictures (docs/images/), docs/api.md and the HTML
  API reference (pdoc, into docs/_build/api/)
"""
from __future__ import annotations

import filecmp
import sys
import tempfile
import time
from pathlib import Path

from invoke import task, Exit

ROOT = Path(__file__).resolve().parent
GENERATED = ROOT / "generated"


@task(help={"jobs": "parallel worker processes (default 2)", "no_systems": "offsets only"})
def regenerate(c, jobs=2, no_systems=False):
    """Regenerate all artefacts into generated/ (deterministic) and rewrite the manifest."""
    from curvedvoronoi.precompute.pipeline import regenerate as run

    t0 = time.perf_counter()
    timings = run(GENERATED, jobs=int(jobs), with_systems=not no_systems)
    print(f"regenerate: {time.perf_counter() - t0:.1f} s wall")
    for k, v in timings.items():
        print(f"  {k:<28} {v:8.2f} s")


def _tree(root: Path) -> set[str]:
    return {p.relative_to(root).as_posix() for p in root.rglob("*")
            if p.is_file() and "__pycache__" not in p.parts and p.name != "__init__.py"}


@task(help={"jobs": "parallel worker processes (default 2)"})
def check_generated(c, jobs=2):
    """Regenerate into a temporary folder and byte-compare with generated/ (golden-file check)."""
    from curvedvoronoi.precompute.pipeline import regenerate as run

    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "generated"
        run(out, jobs=int(jobs))
        ours, fresh = _tree(GENERATED), _tree(out)
        problems = [f"only in generated/: {p}" for p in sorted(ours - fresh)]
        problems += [f"missing from generated/: {p}" for p in sorted(fresh - ours)]
        problems += [f"differs: generated/{p}" for p in sorted(ours & fresh)
                     if not filecmp.cmp(GENERATED / p, out / p, shallow=False)]
    if problems:
        print("check-generated FAILED: the committed artefacts are not what the generator produces:")
        for p in problems:
            print("  " + p)
        print("run `invoke regenerate` and commit generated/, or find what made the output change")
        raise Exit(code=1)
    print(f"check-generated: OK ({len(ours)} files byte-identical)")


@task(help={"jobs": "test processes side by side (pytest-xdist; 0: one process)"})
def test(c, quick=False, slow=False, all=False, jobs=2):
    """Run the test suite (pytest): the README/CI selection (not ``slow``), or with ``--slow`` the
    long checks alone, with ``--all`` everything; ``jobs`` processes side by side (pytest-xdist)."""
    marks = "" if all else (' -m slow' if slow else ' -m "not slow"')
    par = f" -n {int(jobs)}" if int(jobs) > 0 else ""
    c.run(f"{sys.executable} -m pytest -q" + marks + par + (" -x" if quick else ""), pty=False)


@task(help={"only": "substring of the benchmark file name"})
def bench(c, only=""):
    """Run the benchmarks in bench/ (each writes its table to bench/results/)."""
    scripts = sorted(p for p in (ROOT / "bench").glob("bench_*.py") if only in p.name)
    for script in scripts:
        print(f"== {script.name}")
        c.run(f"{sys.executable} {script}", pty=False)


@task
def demo(c):
    """Run the conflict locator on the built-in four-ellipse example."""
    c.run(f"{sys.executable} -m curvedvoronoi demo", pty=False)


@task(help={"no_figures": "skip the pictures (the slowest part)", "no_html": "skip the pdoc HTML reference"})
def docs(c, no_figures=False, no_html=False):
    """Build the docs: pictures (docs/make_figures.py), docs/api.md (docs/make_api.py), pdoc HTML."""
    t0 = time.perf_counter()
    if not no_figures:
        c.run(f"{sys.executable} {ROOT / 'docs' / 'make_figures.py'}", pty=False)
    c.run(f"{sys.executable} {ROOT / 'docs' / 'make_api.py'}", pty=False)
    if not no_html:
        try:
            import pdoc  # noqa: F401
        except ImportError:
            print("docs: the HTML reference needs pdoc, which is not installed: pip install 'curvedvoronoi[docs]'")
            raise Exit(code=1)
        c.run(f"{sys.executable} -m pdoc -o {ROOT / 'docs' / '_build' / 'api'} curvedvoronoi "
              "curvedvoronoi.runtime.sites.reader curvedvoronoi.runtime.sites.conic curvedvoronoi.runtime.predicates.circles "
              "curvedvoronoi.runtime.predicates.locator curvedvoronoi.runtime.result", pty=False)
    print(f"docs: done in {time.perf_counter() - t0:.1f} s (docs/index.md is the entry point)")
