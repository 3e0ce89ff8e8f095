"""A new user's first hour: the public API, the frictions once met on a fresh clone, and the
README's two commands run in a temporary bare clone of the repository."""
from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

FOUR_ELLIPSES = [[1, 0, 4, 0, 0, -4], [144, -96, 116, -1248, 316, 2549],
                 ["2642", "-1920", "738", "714", "-3762", "6577"], [1076, -336, 549, -4708, -1356, 7116]]


def cli(*args, env_extra=None, timeout=300, cwd=ROOT, prefix=()):
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", **(env_extra or {}))
    return subprocess.run([sys.executable, *prefix, *(("-m", "curvedvoronoi") if not prefix else ()), *args],
                          cwd=cwd, env=env, capture_output=True, text=True, timeout=timeout)


def sites_file(tmp_path, sites, key="sites"):
    f = tmp_path / "in.json"
    f.write_text(json.dumps({key: sites}))
    return str(f)


def one_line_error(out, code=2):
    assert out.returncode == code, (out.returncode, out.stderr)
    assert out.stderr.startswith("error: ") and out.stderr.count("\n") == 1, out.stderr
    assert "Traceback" not in out.stderr
    return out.stderr


# ----------------------------------------------------------------------------- public API

def test_public_api_imports():
    import curvedvoronoi as cv

    assert re.fullmatch(r"\d+\.\d+\.\d+", cv.__version__)
    from curvedvoronoi.runtime.predicates.circles import Circle, Point
    from curvedvoronoi.runtime.sites.conic import Conic
    from curvedvoronoi.runtime.predicates.locator import locate_conflicts

    assert cv.Conic is Conic and cv.Circle is Circle and cv.Point is Point
    assert cv.locate_conflicts is locate_conflicts
    assert callable(cv.voronoi)
    assert set(cv.__all__) >= {"Conic", "Circle", "Point", "locate_conflicts", "voronoi", "__version__"}
    with pytest.raises(AttributeError):
        cv.no_such_name  # noqa: B018


def test_help_names_the_program_and_version():
    out = cli("--help")
    assert out.returncode == 0 and out.stdout.startswith("usage: curvedvoronoi")
    assert "python -m runtime" not in out.stdout
    import curvedvoronoi as cv

    assert cli("--version").stdout.strip() == f"curvedvoronoi {cv.__version__}"


# ----------------------------------------------------------------------------- frictions

def test_overflowing_coefficients_are_one_clear_line_fast(tmp_path):
    f = sites_file(tmp_path, [{"coefficients": [1e300, 0, 1, 0, 0, -1]}] + [{"coefficients": c}
                                                                            for c in FOUR_ELLIPSES[1:]])
    t0 = time.perf_counter()
    out = cli("locate", f)
    assert time.perf_counter() - t0 < 20          # a subprocess, mostly Python's start-up
    msg = one_line_error(out)
    assert "sites[0]" in msg and "range" in msg


def test_the_same_conic_four_times_is_rejected_within_a_second(tmp_path):
    from curvedvoronoi.runtime.sites.reader import sites_from_document

    doc = {"sites": [{"coefficients": [1, 0, 4, 0, 0, -4]}] * 4}
    t0 = time.perf_counter()
    with pytest.raises(ValueError, match="site 1 is the same curve as site 0"):
        sites_from_document(doc, "in.json", expected=4)
    assert time.perf_counter() - t0 < 1.0
    # the same conic scaled by 3 is the same curve
    doc = {"sites": [{"coefficients": [1, 0, 4, 0, 0, -4]}, {"coefficients": [3, 0, 12, 0, 0, -12]}]}
    with pytest.raises(ValueError, match="site 1 is the same curve as site 0"):
        sites_from_document(doc, "in.json")
    out = cli("locate", sites_file(tmp_path, doc["sites"] * 2), timeout=60)
    assert "same curve" in one_line_error(out)


def test_points_with_ellipses_in_locate_are_answered(tmp_path):
    """Points among ellipses go to the diagram of C1, C2, C3 (proved by the verifier), not to an error."""
    f = sites_file(tmp_path, [{"ellipse": {"centre": [0, 0], "axes": [2, 1]}}, {"point": [5, 0]},
                              {"ellipse": {"centre": [0, 5], "axes": [2, 1], "rotation": 90}},
                              {"point": [1, 1]}])
    out = cli("locate", f, "--quiet")
    assert out.returncode == 0 and out.stderr == "", out.stderr
    res = json.loads(out.stdout)
    assert res["method"] == "diagram+certified" and res["certified"] and res["complete"] and res["vertices"]


def test_points_with_ellipses_through_the_api_are_answered_and_a_point_on_a_site_is_refused():
    import curvedvoronoi as cv

    e1, e2 = cv.Conic.ellipse(centre=(0, 0), axes=(2, 1)), cv.Conic.ellipse(centre=(0, 5), axes=(2, 1))
    res = cv.locate_conflicts(e1, cv.Point(5, 0), e2, cv.Point(1, 1))
    assert res.certified and res.complete and res.vertices
    with pytest.raises(ValueError, match="intersect") as exc:
        cv.locate_conflicts(e1, cv.Point(2, 0), e2, cv.Point(1, 1))
    assert "\n" not in str(exc.value)


def test_circles_and_points_through_the_api_go_to_the_exact_circle_locator():
    """The same four sites as the command-line case below, given as Circle, Conic and Point objects:
    locate_conflicts sends them to the exact circle locator; a circle with ellipses is taken as the
    circle conic (its answer equals the one with Conic.circle)."""
    import curvedvoronoi as cv

    sites = [cv.Circle.from_radius(0, 0, 1), cv.Circle.from_radius(4, 0, 1),
             cv.Conic.from_coefficients(1, 0, 1, 0, -8, 15), cv.Point(1, 1)]
    res = cv.locate_conflicts(*sites)
    assert res.certified and res.conflict and res.method == "circles-exact"
    (v,) = res.vertices
    assert abs(v.x - 2) < 1e-12 and abs(v.y - 2) < 1e-12
    e = cv.Conic.ellipse(centre=(9, 1), axes=(2, 1))
    a = cv.locate_conflicts(sites[0], sites[1], e, sites[2])
    b = cv.locate_conflicts(cv.Conic.circle(centre=(0, 0), radius=1), cv.Conic.circle(centre=(4, 0), radius=1), e,
                            sites[2])
    assert a.certified and (a.conflict, len(a.vertices)) == (b.conflict, len(b.vertices))
    assert all(abs(u.x - w.x) < 1e-12 and abs(u.y - w.y) < 1e-12 for u, w in zip(a.vertices, b.vertices))


def test_points_and_circles_in_locate_use_the_exact_circle_locator(tmp_path):
    # unit circles centred at (0,0), (4,0), (0,4): the empty tangent circle is centred at (2, 2),
    # radius 2√2 - 1 ≈ 1.83; the point (1, 1) lies at distance √2 < 1.83 from its centre: conflict
    f = sites_file(tmp_path, [{"circle": {"centre": [0, 0], "radius": 1}},
                              {"circle": {"centre": [4, 0], "radius": 1}},
                              {"coefficients": [1, 0, 1, 0, -8, 15]},
                              {"point": [1, 1]}])
    out = cli("locate", f, "--quiet")
    assert out.returncode == 0 and out.stderr == ""
    res = json.loads(out.stdout)
    assert res["certified"] and res["conflict"] and res["method"] == "circles-exact"
    (v,) = res["vertices"]
    assert abs(v["x"] - 2) < 1e-12 and abs(v["y"] - 2) < 1e-12
    assert abs(v["radius"] - (2 * 2 ** 0.5 - 1)) < 1e-12
    assert abs(v["distance_to_fourth"] - 2 ** 0.5) < 1e-12


def test_circles_with_ellipses_in_locate(tmp_path):
    f = sites_file(tmp_path, [{"circle": {"centre": [0, 0], "radius": 1}},
                              {"ellipse": {"centre": [5, 0], "axes": [2, 1]}},
                              {"circle": {"centre": [0, 5], "radius": 1}},
                              {"ellipse": {"centre": [3, 3], "axes": [1, "1/2"],
                                           "rotation": {"cos": "3/5", "sin": "4/5"}}}])
    out = cli("locate", f)
    assert out.returncode == 0, out.stderr
    res = json.loads(out.stdout)
    assert res["certified"] and res["vertices"]
    from curvedvoronoi.runtime.sites.conic import Conic
    from curvedvoronoi.runtime.sites.distance import distance

    e = Conic.ellipse(centre=(5, 0), axes=(2, 1))
    for v in res["vertices"]:   # equidistant from the two circles (|q| - 1) and the ellipse
        d0 = (v["x"] ** 2 + v["y"] ** 2) ** 0.5 - 1
        d2 = (v["x"] ** 2 + (v["y"] - 5) ** 2) ** 0.5 - 1
        d1 = float(distance(e, v["x"], v["y"]))
        assert max(abs(d0 - v["radius"]), abs(d2 - v["radius"]), abs(d1 - v["radius"])) < 1e-9


def test_locate_messages_number_sites_from_zero(tmp_path):
    sites = [{"coefficients": c} for c in FOUR_ELLIPSES]
    sites[2] = {"coefficients": [1, 0, 1, 0, 0, 1]}
    assert "sites[2]: imaginary ellipse" in one_line_error(cli("locate", sites_file(tmp_path, sites)))
    from curvedvoronoi.runtime.cli import _zero_based

    assert _zero_based("C1: expected a Conic; C4 too") == "site 0: expected a Conic; site 3 too"


def test_details_name_the_squared_radius(tmp_path):
    out = cli("locate", sites_file(tmp_path, [{"coefficients": c} for c in FOUR_ELLIPSES]), "--details")
    assert out.returncode == 0, out.stderr
    (v,) = json.loads(out.stdout)["vertices"]
    assert '"R"' not in out.stdout
    assert abs(v["info"]["radius_squared"] - v["radius"] ** 2) < 1e-12 * v["radius"] ** 2
    assert "1 true Voronoi vertex of sites 0, 1, 2; 1 in conflict with site 3" in out.stderr


def test_png_without_matplotlib_is_one_line_naming_the_package(tmp_path):
    blocker = tmp_path / "run.py"
    blocker.write_text(
        "import sys\n"
        "class Block:\n"
        "    def find_spec(self, name, path=None, target=None):\n"
        "        if name.split('.')[0] == 'matplotlib':\n"
        "            raise ModuleNotFoundError(f'No module named {name!r}', name=name)\n"
        "sys.meta_path.insert(0, Block())\n"
        f"sys.path.insert(0, {str(ROOT)!r})\n"
        "from curvedvoronoi.runtime.cli import main\n"
        "sys.exit(main(sys.argv[1:]))\n")
    sites = [{"coefficients": [1, 0, 1, 0, 0, -1]}, {"coefficients": [1, 0, 1, -8, 0, 15]},
             {"coefficients": [1, 0, 1, 0, -8, 15]}]
    out = cli("diagram", sites_file(tmp_path, sites), "--png", str(tmp_path / "d.png"), "--no-progress",
              "--json", str(tmp_path / "d.json"), prefix=(str(blocker),))
    msg = one_line_error(out, code=1)
    assert "matplotlib" in msg and "pip install" in msg


def test_missing_extra_message_names_the_extra():
    from curvedvoronoi.runtime.optional import MissingDependencyError, missing_message, require

    assert missing_message("shapely", "Diagram.to_shapely") == (
        "Diagram.to_shapely needs shapely, which is not installed: pip install 'curvedvoronoi[geo]'")
    with pytest.raises(MissingDependencyError, match=r"pip install no_such_package_xyz"):
        require("no_such_package_xyz")


def test_conic_repr_with_a_float_rotation_is_short():
    from curvedvoronoi.runtime.sites.conic import Conic

    e = Conic.ellipse(centre=(0, 0), axes=(2, 1), rotation=0.5)
    assert len(repr(e)) < 100 and "≈" in repr(e)
    # the shown numbers are the coefficients / the largest one: check against cos/sin of 0.5
    import math

    c, s = math.cos(0.5), math.sin(0.5)
    a, b, cc = c * c / 4 + s * s, 2 * c * s * (1 / 4 - 1), s * s / 4 + c * c      # X²/4 + Y² = 1
    m = max(abs(a), abs(b), abs(cc), 1)
    shown = [float(t) for t in repr(e).split("≈")[1].strip(" )").split(",")]
    assert all(abs(x - y / m) < 1e-5 for x, y in zip(shown, [a, b, cc, 0, 0, -1]))


# ----------------------------------------------------------------------------- bare clone

def readme_commands(readme: str) -> list[str]:
    """The README's two commands: the first two ```bash blocks of "Two commands on a fresh machine"."""
    section = readme.split("## Two commands", 1)[1].split("\n## ", 1)[0]
    blocks = re.findall(r"```bash\n(.*?)\n```", section, flags=re.S)
    assert len(blocks) >= 2, "README: expected two ```bash blocks under 'Two commands'"
    return [b.strip() for b in blocks[:2]]


@pytest.mark.slow
@pytest.mark.skipif(bool(os.environ.get("CURVEDVORONOI_SKIP_CLONE_TEST")),
                    reason="run inside the bare-clone test itself (set there to avoid cloning recursively); "
                           "the outer run tests the clone")
def test_readme_commands_in_a_bare_clone(tmp_path):
    """git clone of this repository's HEAD, nothing beside it, then the README's two commands as
    written, each in its own fresh clone (they are independent; run side by side, since pip spends
    most of its time waiting).  Inside the clone the test command runs test_schema.py and
    test_cli.py (PYTEST_ADDOPTS; the full suite is CI's own run of the same command) and a
    collection of the whole suite must find no error."""
    git = shutil.which("git")
    assert git, "git is needed for the bare-clone test"
    top = subprocess.run([git, "rev-parse", "--show-toplevel"], cwd=ROOT, capture_output=True, text=True)
    assert top.returncode == 0, top.stderr
    clones = [tmp_path / "demo", tmp_path / "test"]
    for clone in clones:
        r = subprocess.run([git, "clone", "-q", top.stdout.strip(), str(clone)], capture_output=True, text=True)
        assert r.returncode == 0, r.stderr
    demo_cmd, test_cmd = readme_commands((clones[0] / "README.md").read_text())
    env = {k: v for k, v in os.environ.items()
           if k not in ("VIRTUAL_ENV", "PYTHONPATH", "PYTHONHOME", "PYTEST_ADDOPTS", "PYTEST_CURRENT_TEST")}
    env["CURVEDVORONOI_SKIP_CLONE_TEST"] = "1"
    env_t = dict(env, PYTEST_ADDOPTS="-x -p no:cacheprovider tests/test_schema.py tests/test_cli.py")
    t0 = time.perf_counter()
    procs = [subprocess.Popen(["bash", "-c", cmd], cwd=clone, env=e, stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, text=True)
             for cmd, clone, e in ((demo_cmd, clones[0], env), (test_cmd, clones[1], env_t))]
    outs = []
    for p in procs:
        try:
            outs.append(p.communicate(timeout=900) + (p.returncode,))
        except subprocess.TimeoutExpired:
            for q in procs:
                q.kill()
            pytest.fail("a README command ran for more than 15 minutes")
    (demo_out, demo_err, demo_rc), (test_out, test_err, test_rc) = outs
    assert demo_rc == 0, demo_err[-3000:]
    res = json.loads(demo_out)
    assert res["certified"] and res["conflict"] and len(res["vertices"]) == 1
    assert test_rc == 0, (test_out[-3000:], test_err[-3000:])
    assert re.search(r"\d+ passed", test_out) and " failed" not in test_out
    out = subprocess.run([str(clones[1] / ".venv" / "bin" / "python"), "-m", "pytest", "--co", "-q"],
                         cwd=clones[1], env=env, capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stdout[-3000:] + out.stderr[-3000:]
    summary = out.stdout.strip().splitlines()[-1]
    assert re.fullmatch(r"\d+ tests? collected in .*", summary), summary   # "N errors" would be here
    print(f"README commands in bare clones: {time.perf_counter() - t0:.0f} s wall")
