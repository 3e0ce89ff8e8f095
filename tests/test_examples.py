"""The runnable examples (examples/*.py), the Python snippets of the user guide, and the
docstring examples of the public API, run as a user runs them."""
from __future__ import annotations

import doctest
import importlib
import json
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def run_script(path: Path, *args, timeout=300):
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", PYTHONPATH=str(ROOT))
    return subprocess.run([sys.executable, str(path), *args], cwd=ROOT, env=env, capture_output=True,
                          text=True, timeout=timeout)


def test_every_example_script_is_tested_here():
    scripts = {p.name for p in (ROOT / "examples").glob("*.py")}
    assert scripts == {"quickstart.py", "locate_from_json.py", "voronoi_of_ellipses.py"}


def test_quickstart():
    out = run_script(ROOT / "examples" / "quickstart.py")
    assert out.returncode == 0, out.stderr
    # the thesis Fig. 5.5.1 configuration: one certified vertex of sites 0, 1, 2, entered by site 3
    assert "conflict=True certified=True complete=True" in out.stdout
    assert "vertex (2.401431, 1.880629) radius 1.510415" in out.stdout
    # three unit circles at (0,0), (4,0), (0,4): empty circle centred (2, 2), radius 2√2 − 1
    assert "circles: vertex (2.0, 2.0), radius 1.828427" in out.stdout
    assert "refused: imaginary ellipse" in out.stdout


def test_locate_from_json_matches_the_cli(tmp_path):
    out = run_script(ROOT / "examples" / "locate_from_json.py")
    assert out.returncode == 0, out.stderr
    assert "certified=True" in out.stdout
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", PYTHONPATH=str(ROOT))
    cli = subprocess.run([sys.executable, "-m", "curvedvoronoi", "locate", "examples/sites_forms.json", "-q"],
                         cwd=ROOT, env=env, capture_output=True, text=True, timeout=300)
    assert cli.returncode == 0, cli.stderr
    res = json.loads(cli.stdout)
    for v in res["vertices"]:
        assert f"vertex ({v['x']:.6f}, {v['y']:.6f}) radius {v['radius']:.6f}" in out.stdout


def test_voronoi_of_ellipses(tmp_path):
    import curvedvoronoi as cv

    try:
        cv.voronoi  # noqa: B018
    except (ImportError, AttributeError) as exc:
        pytest.fail(f"curvedvoronoi.voronoi is not importable: {exc}")
    png = tmp_path / "d.png"
    out = run_script(ROOT / "examples" / "voronoi_of_ellipses.py", str(png), timeout=600)
    assert out.returncode == 0, out.stderr[-2000:]
    m = re.search(r"(\d+) Voronoi vertices, (\d+) edges", out.stdout)
    assert m and int(m.group(1)) >= 1 and int(m.group(2)) >= 1
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def python_blocks(md: Path) -> list[str]:
    return re.findall(r"```python\n(.*?)\n```", md.read_text(), flags=re.S)


def test_user_guide_python_snippets_run():
    blocks = python_blocks(ROOT / "docs" / "index.md")
    assert blocks
    for code in blocks:
        env = dict(os.environ, OPENBLAS_NUM_THREADS="1", PYTHONPATH=str(ROOT))
        out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, env=env, capture_output=True, text=True,
                             timeout=300)
        assert out.returncode == 0, (code, out.stderr[-2000:])


@pytest.mark.parametrize("module", ["curvedvoronoi", "curvedvoronoi.runtime.sites.conic",
                                    "curvedvoronoi.runtime.sites.circle", "curvedvoronoi.runtime.sites.reader"])
def test_docstring_examples(module):
    mod = importlib.import_module(module)
    res = doctest.testmod(mod, optionflags=doctest.ELLIPSIS)
    assert res.failed == 0
    if module in ("curvedvoronoi", "curvedvoronoi.runtime.sites.conic", "curvedvoronoi.runtime.sites.circle"):
        assert res.attempted > 0


def test_api_reference_covers_every_public_name(tmp_path):
    out = run_script(ROOT / "docs" / "make_api.py", "--out", str(tmp_path / "api.md"))
    assert out.returncode == 0, out.stdout + out.stderr
    import curvedvoronoi as cv

    fresh, committed = (tmp_path / "api.md").read_text(), (ROOT / "docs" / "api.md").read_text()
    for name in cv.__all__:
        if name != "__version__":
            assert f"## {name}\n" in fresh and f"## {name}\n" in committed, name


def test_user_guide_links_and_pictures_exist():
    for md in [ROOT / "docs" / "index.md", *(ROOT / "docs" / "cli").glob("*.md")]:
        for target in re.findall(r"\]\(([^)#]+)(?:#[^)]*)?\)", md.read_text()):
            if "://" not in target:
                assert (md.parent / target).exists(), f"{md.name}: broken link {target}"
    assert {p.name for p in (ROOT / "docs" / "cli").glob("*.md")} >= {"locate.md", "diagram.md", "demo.md",
                                                                       "offsets.md"}
