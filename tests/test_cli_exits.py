"""Every exit status of `curvedvoronoi diagram` and `curvedvoronoi verify`, each on an input that
produces it, run as a user runs them (subprocesses).

diagram: 0 certified (or --no-certify ran to its end), 1 written but not certified, 2 bad input
(one line "error: ..."), 130 Ctrl-C (the partial result written, marked not certified).
verify: 0 proved, 1 not proved, 2 bad input.  Exit 3 (numerical refusal) is raised by the
locator's numeric routes only; no diagram input is known to reach it, so it is not tested here.
"""
from __future__ import annotations

import json
import os
import random
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "runtime" / "data" / "example_sites.json"


def cli(*args, timeout=300):
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    return subprocess.run([sys.executable, "-m", "curvedvoronoi", *map(str, args)], cwd=ROOT, env=env,
                          capture_output=True, text=True, timeout=timeout)


def sites_file(tmp_path, sites, name="in.json"):
    f = tmp_path / name
    f.write_text(json.dumps({"sites": sites}))
    return f


def one_line_error(out, code=2):
    assert out.returncode == code, (out.returncode, out.stderr)
    assert out.stderr.startswith("error: ") and out.stderr.count("\n") == 1, out.stderr
    assert "Traceback" not in out.stderr
    return out.stderr


THREE_CIRCLES = [{"circle": {"centre": [0, 0], "radius": 1}}, {"circle": {"centre": [4, 0], "radius": 1}},
                 {"circle": {"centre": [2, 4], "radius": 1}}]


# ----------------------------------------------------------------------------- diagram: 0 and 1

def test_diagram_exit_0_when_certified_and_verify_agrees(tmp_path):
    j = tmp_path / "d.json"
    out = cli("diagram", sites_file(tmp_path, THREE_CIRCLES), "--json", j, "--quiet")
    assert out.returncode == 0 and out.stderr == "", out.stderr
    doc = json.loads(j.read_text())
    assert doc["certified"] is True and doc["problems"] == []
    # three unit circles: the one vertex is the point equidistant from the centres (0,0), (4,0), (2,4):
    # x = 2 and x² + y² = (y − 4)² + 4, so y = 1.5, radius 2.5 − 1
    (v,) = doc["vertices"]
    assert abs(v["x"] - 2) < 1e-9 and abs(v["y"] - 1.5) < 1e-9 and abs(v["radius"] - 1.5) < 1e-9
    r = cli("verify", j)
    assert r.returncode == 0, r.stdout + r.stderr
    assert r.stdout.startswith("proved: 1 vertices, 3 edges") and r.stdout.count("\n") == 1


def test_diagram_exit_1_when_not_certified_but_outputs_written(tmp_path):
    j, g = tmp_path / "d.json", tmp_path / "d.geojson"
    out = cli("diagram", EXAMPLE, "--time-limit", "0", "--json", j, "--geojson", g, "--no-progress")
    assert out.returncode == 1, out.stderr
    assert "Traceback" not in out.stderr and "certified=False" in out.stderr
    doc = json.loads(j.read_text())
    assert doc["certified"] is False and any("time limit" in p for p in doc["problems"])
    assert json.loads(g.read_text())["type"] == "FeatureCollection"


def test_diagram_no_certify_exits_0_not_verified_on_request(tmp_path):
    j = tmp_path / "d.json"
    out = cli("diagram", sites_file(tmp_path, THREE_CIRCLES), "--no-certify", "--json", j, "--quiet")
    assert out.returncode == 0, out.stderr
    doc = json.loads(j.read_text())
    assert doc["certified"] is False and any("not verified" in p for p in doc["problems"])


# ----------------------------------------------------------------------------- diagram: 2

@pytest.mark.parametrize("case", ["nan", "not json", "repeated", "intersecting", "one site", "missing file",
                                  "bad window", "unknown option"])
def test_diagram_bad_input_exits_2_with_one_line(tmp_path, case):
    f = tmp_path / "in.json"
    extra = []
    if case == "nan":
        f.write_text('{"sites": [{"point": [0, 0]}, {"point": [NaN, 1]}]}')
    elif case == "not json":
        f.write_text('{"sites": [')
    elif case == "repeated":
        sites_file(tmp_path, [THREE_CIRCLES[0], THREE_CIRCLES[1], THREE_CIRCLES[0]])
    elif case == "intersecting":      # centres 1.5 apart, radii 1: the circles cross
        sites_file(tmp_path, [THREE_CIRCLES[0], {"circle": {"centre": [1.5, 0], "radius": 1}}])
    elif case == "one site":
        sites_file(tmp_path, THREE_CIRCLES[:1])
    elif case == "missing file":
        f = tmp_path / "nothing_here.json"
    elif case == "bad window":
        sites_file(tmp_path, THREE_CIRCLES)
        extra = ["--png", tmp_path / "d.png", "--window=1,0,0,1"]
    else:
        sites_file(tmp_path, THREE_CIRCLES)
        extra = ["--colour", "red"]
    msg = one_line_error(cli("diagram", f, *extra))
    if case in ("repeated", "intersecting"):
        assert ("site 2" in msg and "site 0" in msg) if case == "repeated" else "site 0 and site 1" in msg
    if case == "bad window":
        assert "xmin < xmax" in msg and not (tmp_path / "d.png").exists()


# ----------------------------------------------------------------------------- diagram: 130

def _disjoint_circles(n_side: int, seed: int) -> list:
    """Circles on a jittered grid of pitch 3 with radius < 0.9 and jitter ≤ 0.5: centres of
    neighbours are ≥ 2 apart, so the circles are disjoint."""
    rng = random.Random(seed)
    return [{"circle": {"centre": [3 * i + rng.uniform(-0.5, 0.5), 3 * j + rng.uniform(-0.5, 0.5)],
                        "radius": rng.uniform(0.2, 0.9)}}
            for i in range(n_side) for j in range(n_side)]


def test_diagram_ctrl_c_exits_130_and_writes_the_partial_result(tmp_path):
    """SIGINT a second after the first refinement round has finished (the progress bar says
    "1round"): the partial result is written, marked not certified and interrupted."""
    f = sites_file(tmp_path, _disjoint_circles(70, 1))         # 4900 circles: several seconds of work
    j = tmp_path / "partial.json"
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    p = subprocess.Popen([sys.executable, "-m", "curvedvoronoi", "diagram", str(f), "--json", str(j)],
                         cwd=ROOT, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    err = bytearray()

    def read():
        while chunk := p.stderr.read1(256) if hasattr(p.stderr, "read1") else p.stderr.read(1):
            err.extend(chunk)

    t = threading.Thread(target=read, daemon=True)
    t.start()
    t0 = time.monotonic()
    while b"1round" not in err and p.poll() is None and time.monotonic() - t0 < 120:
        time.sleep(0.02)
    time.sleep(1.0)             # usually past the rounds, in the verification of the last one
    assert p.poll() is None, "the construction ended before it could be interrupted: " + err.decode()[-500:]
    p.send_signal(signal.SIGINT)
    p.communicate(timeout=120)
    t.join(timeout=10)
    text = err.decode()
    assert p.returncode == 130, text[-1000:]
    assert "Traceback" not in text
    doc = json.loads(j.read_text())
    assert doc["certified"] is False
    assert any(p.startswith("interrupted (Ctrl-C)") for p in doc["problems"])
    assert len(doc["sites"]) == 4900
    # interrupted inside a refinement round: no round's diagram is kept ("no diagram computed");
    # later (edges, verification): the last finished round's diagram, with its edges
    partial = [p for p in doc["problems"] if "partial diagram" in p]
    assert bool(partial) == bool(doc["edges"]), (doc["problems"], len(doc["edges"]))


# ----------------------------------------------------------------------------- verify: 0, 1, 2

@pytest.fixture(scope="module")
def certified_diagram(tmp_path_factory):
    d = tmp_path_factory.mktemp("verify")
    j = d / "d.json"
    out = cli("diagram", EXAMPLE, "--json", j, "--quiet")
    assert out.returncode == 0, out.stderr
    return j


def test_verify_exit_0_summary_v_and_o(certified_diagram, tmp_path):
    doc = json.loads(certified_diagram.read_text())
    out = cli("verify", certified_diagram)
    assert out.returncode == 0 and out.stderr == ""
    assert out.stdout.startswith(f"proved: {len(doc['vertices'])} vertices, {len(doc['edges'])} edges, ")
    out = cli("verify", certified_diagram, "-v")
    assert out.returncode == 0 and json.loads(out.stdout)["ok"] is True and out.stderr.startswith("proved: ")
    cert = tmp_path / "cert.json"
    out = cli("verify", certified_diagram, EXAMPLE, "-o", cert)
    assert out.returncode == 0 and out.stdout.startswith("proved: ")
    c = json.loads(cert.read_text())
    assert c["ok"] is True and len(c["edges"]) == len(doc["edges"]) and all(c["edges"])


def test_verify_exit_1_on_a_moved_vertex(certified_diagram, tmp_path):
    doc = json.loads(certified_diagram.read_text())
    doc["vertices"][0]["x"] += 1e-3           # 1e-3 off: no longer equidistant from its three sites
    bad = tmp_path / "moved.json"
    bad.write_text(json.dumps(doc))
    out = cli("verify", bad)
    assert out.returncode == 1, out.stdout + out.stderr
    assert out.stdout.startswith("NOT proved: ") and "vertex 0 " in out.stdout and out.stdout.count("\n") == 1
    out = cli("verify", bad, "-v")
    assert out.returncode == 1 and json.loads(out.stdout)["ok"] is False


def test_verify_exit_1_when_the_sites_differ(certified_diagram, tmp_path):
    other = sites_file(tmp_path, THREE_CIRCLES)
    out = cli("verify", certified_diagram, other)
    assert out.returncode == 1 and out.stdout.startswith("NOT proved: "), out.stdout + out.stderr


@pytest.mark.parametrize("case", ["not json", "not a diagram", "missing", "malformed"])
def test_verify_bad_input_exits_2(certified_diagram, tmp_path, case):
    f = tmp_path / "x.json"
    if case == "not json":
        f.write_text("{not json")
    elif case == "not a diagram":
        f.write_text("[1, 2]")
    elif case == "malformed":
        doc = json.loads(certified_diagram.read_text())
        doc["vertices"] = "none"
        f.write_text(json.dumps(doc))
    else:
        f = tmp_path / "absent.json"
    one_line_error(cli("verify", f))


# ----------------------------------------------------------------------------- --png never crashes

def test_png_with_far_unbounded_sites_and_a_far_window(tmp_path):
    """A parabola and a hyperbola far from the other sites, drawn in the fitted window and in a
    window that none of the sites meets (both used to raise IndexError)."""
    sites = THREE_CIRCLES + [{"parabola": {"vertex": [30, 40], "p": 1, "rotation": 90}},
                             {"hyperbola": {"centre": [-50, -20], "axes": [2, 1]}}]
    f = sites_file(tmp_path, sites)
    for extra in ([], ["--window=1000,1010,1000,1010"], ["--window=-3,7,-3,7", "--empty-circles"]):
        png = tmp_path / "d.png"
        out = cli("diagram", f, "--png", png, "--quiet", "--no-certify", *extra)   # the picture, not the proof
        assert out.returncode == 0 and "Traceback" not in out.stderr and out.stderr == "", out.stderr
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        png.unlink()
