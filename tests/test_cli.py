"""Command line: `python -m runtime offsets|locate|demo|diagram` as a user runs it."""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def run(*args, cwd=ROOT):
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    return subprocess.run([sys.executable, "-m", "curvedvoronoi", *args], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=300)


def test_help_and_offsets_table():
    assert run("--help").returncode == 0
    out = run("offsets", "--json")
    assert out.returncode == 0
    rows = {r["family"]: r for r in json.loads(out.stdout)}
    assert rows["ellipse"]["degree_uv"] == 8 and rows["ellipse"]["terms"] == 104
    assert rows["parabola"]["degree_uv"] == 6 and rows["circle"]["degree_uv"] == 4


def test_locate_example_is_certified_and_matches_the_demo():
    out = run("locate", "examples/four_ellipses.json")
    assert out.returncode == 0, out.stderr
    res = json.loads(out.stdout)
    assert res["certified"] and res["complete"] and res["conflict"]
    demo = json.loads(run("demo").stdout)
    assert [round(v["x"], 12) for v in demo["vertices"]] == [round(v["x"], 12) for v in res["vertices"]]
    v = res["vertices"][0]
    assert v["in_conflict"] == (v["distance_to_fourth"] < v["radius"])


@pytest.mark.parametrize("doc, message", [
    ("{not json", "not valid JSON"),
    ('{"conics": [1, 2]}', "expected 4 conics"),
    ('{"conics": [{"coefficients": [1, 0, 1, 0, 0, 1]}, {"coefficients": [1, 0, 1, 0, 0, -1]},'
     ' {"coefficients": [1, 0, 1, 0, 0, -4]}, {"coefficients": [1, 0, 1, 0, 0, -9]}]}', "imaginary"),
    ('{"conics": [{"coefficients": ["nan", 0, 1, 0, 0, 1]}, {"coefficients": [1, 0, 1, 0, 0, -1]},'
     ' {"coefficients": [1, 0, 1, 0, 0, -4]}, {"coefficients": [1, 0, 1, 0, 0, -9]}]}', "not a rational"),
    ('{"conics": [{"coefficients": [1, 0, -1, 0, 0, 0]}, {"coefficients": [1, 0, 1, 0, 0, -1]},'
     ' {"coefficients": [1, 0, 1, 0, 0, -4]}, {"coefficients": [1, 0, 1, 0, 0, -9]}]}', "degenerate"),
])
def test_bad_input_exits_2_with_one_line(tmp_path, doc, message):
    f = tmp_path / "in.json"
    f.write_text(doc)
    out = run("locate", str(f))
    assert out.returncode == 2
    assert message in out.stderr and out.stderr.count("\n") == 1 and "Traceback" not in out.stderr


def test_diagram_cli_writes_json_and_png(tmp_path):
    pytest.importorskip("matplotlib", reason="the picture needs matplotlib (test extra)")
    j, p = tmp_path / "d.json", tmp_path / "d.png"
    out = run("diagram", "runtime/data/example_sites.json", "--json", str(j), "--png", str(p), "--no-progress")
    assert out.returncode == 0, out.stderr
    doc = json.loads(j.read_text())
    assert len(doc["sites"]) == 9 and doc["edges"] and all(i < k for i, k in doc["edges"])
    assert p.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
