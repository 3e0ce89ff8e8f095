"""Command line: `python -m curvedvoronoi offsets|locate|demo|diagram` as a user runs it."""
from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))


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


FAR_CIRCLES = {"conics": [{"coefficients": [1, 0, 1, 0, 0, -1]},
                          {"coefficients": [1, 0, 1, -20, "-1/50", "990001/10000"]},   # (10, 1/100), r = 1
                          {"coefficients": [1, 0, 1, -40, 0, 399]},
                          {"coefficients": [1, 0, 1, -20, 60, 999]}]}


def _agrees_with_reference(doc: dict, res: dict) -> None:
    """The JSON answer of `locate` against the independent reference oracle (tests/reference.py:
    dense sampling + mpmath Newton, no code shared with the runtime)."""
    from fractions import Fraction

    from curvedvoronoi.runtime.sites.conic import Conic
    from reference import reference_locate

    cs = [Conic.from_coefficients(*(Fraction(str(c)) for c in k["coefficients"])) for k in doc["conics"]]
    ref = reference_locate(*cs)
    assert res["complete"] and res["certified"]
    assert len(res["vertices"]) == len(ref) >= 1
    close = lambda a, b: abs(a - float(b)) <= 1e-8 * max(1.0, abs(float(b)))  # noqa: E731
    for v, e in zip(sorted(res["vertices"], key=lambda v: (v["x"], v["y"])), ref):
        assert close(v["x"], e["x"]) and close(v["y"], e["y"]) and close(v["radius"], e["radius"])
        assert close(v["distance_to_fourth"], e["distance_to_fourth"])
        assert v["certified"] and v["in_conflict"] is e["in_conflict"]
    assert res["conflict"] is any(e["in_conflict"] for e in ref)


def test_locate_example_agrees_with_the_reference():
    out = run("locate", "examples/four_ellipses.json")
    assert out.returncode == 0, out.stderr
    _agrees_with_reference(json.loads((ROOT / "examples" / "four_ellipses.json").read_text()), json.loads(out.stdout))


def test_locate_far_vertex_of_circles_in_closed_form(tmp_path):
    """Nearly collinear unit circles: the vertex is the circumcentre (10, −4999.995) of the centres
    (0, 0), (10, 1/100), (20, 0), radius √(10² + 4999.995²) − 1; site 3 (centre (10, −30)) is at
    distance 4969.995 − 1 from it: in conflict.  The interval route must not claim completeness
    with a box that misses it."""
    f = tmp_path / "far.json"
    f.write_text(json.dumps(FAR_CIRCLES))
    out = run("locate", str(f))
    assert out.returncode == 0, out.stderr
    res = json.loads(out.stdout)
    assert res["certified"] and res["complete"] and res["conflict"]
    [v] = res["vertices"]
    assert abs(v["x"] - 10) < 1e-9 and abs(v["y"] + 4999.995) < 1e-9
    assert abs(v["radius"] - (math.hypot(10, 4999.995) - 1)) < 1e-9
    assert abs(v["distance_to_fourth"] - 4968.995) < 1e-9 and v["in_conflict"] is True


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
    assert len(doc["sites"]) == 9 and doc["edges"] and all(i < k for i, k in doc["delaunay_edges"])
    assert p.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
