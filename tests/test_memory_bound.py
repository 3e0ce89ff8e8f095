"""Peak memory of a circle diagram's build and verification, per site.

The bound asserted here is generous (about twice the measured figure, see bench/results/voronoi.md);
the target itself (a few kB per site at 10⁵ circles) lives in bench/bench_voronoi.py.  The
measurement runs in a fresh process: its peak resident set (``ru_maxrss``) minus its resident set
once the sites are made, divided by the number of sites.  A verifier that holds all its (piece,
candidate site) pairs at once (about 100 kB per site at 10⁴ circles) or a build that keeps
every round's walks alive fails it.
"""
from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
N = 5000
#: kB per circle above the footprint with the input: build, then build and verification (measured
#: 2026-11-27 at 5 000 circles: about 21 and 41 kB; at 10 000: 19–22 and 34–38 kB; before the
#: verifier searched in bounded groups: 36 and 116 kB at 10 000)
BOUND_KB = 64

PROBE = r"""
import json, resource, sys
sys.path.insert(0, {tests!r})
from scenes import random_disjoint_circles
from curvedvoronoi.runtime.voronoi.construction import voronoi
from curvedvoronoi.runtime.voronoi.verify.certificate import verify

def resident_mb():
    with open("/proc/self/statm") as fh:
        return int(fh.read().split()[1]) * resource.getpagesize() / 2 ** 20

def peak_mb():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024

sites = random_disjoint_circles({n}, 3)
base = max(resident_mb(), peak_mb())
d = voronoi(sites, certify=False, progress=False)
built = peak_mb()
cert = verify(d, list(d.sites), progress=False)
print(json.dumps({{"base": base, "build": built, "verify": peak_mb(), "ok": bool(cert.ok),
                  "vertices": len(d.vertices)}}))
"""


def test_peak_memory_per_circle_site():
    if not os.path.exists("/proc/self/statm"):
        import pytest

        pytest.skip("needs /proc/self/statm (Linux)")
    code = PROBE.format(tests=str(ROOT / "tests"), n=N)
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=600,
                         env=dict(os.environ, OPENBLAS_NUM_THREADS="1"))
    assert res.returncode == 0, res.stderr[-2000:]
    m = json.loads(res.stdout.strip().splitlines()[-1])
    assert m["ok"] and m["vertices"] > 1.9 * N          # a full diagram was built and proved
    for stage in ("build", "verify"):
        per_site_kb = (m[stage] - m["base"]) * 1024 / N
        assert per_site_kb <= BOUND_KB, (stage, round(per_site_kb, 1), m)


# ---- far candidate vertices: the emptiness proof does not list every site

def _site_arrays(circles):
    from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
    from curvedvoronoi.runtime.voronoi.site_arrays import SiteArrays
    from curvedvoronoi.runtime.voronoi.site_input import as_site

    sites = [as_site(c) for c in circles]
    return SiteArrays(sites, [site_geometry(s) for s in sites])


def _candidate(triple, x, y, r):
    """A proved candidate vertex (the fields :func:`prove_empty` reads), centre (x, y), radius r."""
    return {"ok": True, "x": x, "y": y, "h": 0.0, "rlo": r, "rhi": r, "triple": tuple(triple), "exact": None}


def test_far_candidate_holding_every_site_lists_only_the_nearest():
    """A 3-label sample triangle can propose a vertex far outside the sites whose circle holds all
    of them (its k-d tree disc then held all 2 000 sites, and 10⁵ such lists exhausted 18 GB).  The
    nearest sites already prove it is not a vertex: at most NEAREST (vertex, site) pairs, and the
    site named really lies inside the circle (float distances, margins of 10³)."""
    import sys

    sys.path.insert(0, str(ROOT / "tests"))
    from scenes import random_disjoint_circles

    from curvedvoronoi.runtime.voronoi.site_arrays import NEAREST
    from curvedvoronoi.runtime.voronoi.vertex_emptiness import prove_empty

    circles = random_disjoint_circles(2000, 5)
    S = _site_arrays(circles)
    x, y, r = -1e5, 200.0, 1e5 + 2000.0           # the scene (side 447) lies inside this circle
    assert all(math.hypot(cx - x, cy - y) + cr < r - 1e3 for cx, cy, cr in circles)
    stats: dict = {}
    res, culprit = prove_empty(S, [_candidate((0, 1, 2), x, y, r)], stats)
    assert res == [False]
    cx, cy, cr = circles[culprit[0]]
    assert math.hypot(cx - x, cy - y) + cr < r
    assert stats["emptiness_pairs"] <= NEAREST < len(circles)
    assert "wide_emptiness_queries" not in stats


def _ring(inside: bool):
    """Three unit circles touching the circle (0, 50) from outside (the triple), 100 circles of
    radius 0.05 centred at 50.06 (0.01 outside it) and, when ``inside``, one of radius 0.1 centred
    at 50.08 (0.02 inside it: its centre is farther than the 100 others'), and a circle of radius
    0.1 far away: the disc of the circle widened by the largest small radius meets more than
    NEAREST small sites, and the nearest centres show none entering."""
    circles = [(51 * math.cos(a), 51 * math.sin(a), 1.0) for a in (0.0, 2.1, 4.2)]
    for m in range(100):
        a = 0.3 + m * 0.0175
        circles.append((50.06 * math.cos(a), 50.06 * math.sin(a), 0.05))
    circles.append((500.0, 0.0, 0.1))
    if inside:
        circles.append((50.08 * math.cos(1.2), 50.08 * math.sin(1.2), 0.1))
    return circles



def test_wide_empty_circle_lists_every_site_that_may_enter():
    """A disc meeting more sites than the nearest-sites look-up holds is proved empty only after
    every site that may enter is listed (batched); a site 0.02 inside, whose centre is not among
    the NEAREST nearest, is found."""
    from curvedvoronoi.runtime.voronoi.site_arrays import NEAREST
    from curvedvoronoi.runtime.voronoi.vertex_emptiness import prove_empty

    for inside in (False, True):
        circles = _ring(inside)
        S = _site_arrays(circles)
        rows, cols, complete = S.nearest_sites(np.array([[0.0, 0.0]]), np.array([50.0]))
        assert not complete[0] and len(set(cols.tolist()) - {0, 1, 2}) == NEAREST
        stats: dict = {}
        res, culprit = prove_empty(S, [_candidate((0, 1, 2), 0.0, 0.0, 50.0)], stats)
        assert stats["wide_emptiness_queries"] == 1
        assert stats["emptiness_pairs"] >= 100
        if inside:
            assert res == [False] and culprit == [104]
        else:
            assert res == [True]


def test_nearest_sites_equal_the_full_list_when_complete():
    """Where the k nearest centres reach beyond the disc, :meth:`nearest_sites` gives exactly the
    sites of :meth:`near_sites` (a k-d tree ball query, the reference)."""
    import sys

    sys.path.insert(0, str(ROOT / "tests"))
    from scenes import random_disjoint_circles

    circles = random_disjoint_circles(500, 6)
    S = _site_arrays(circles)
    rng = np.random.default_rng(1)
    Q = rng.uniform(0, 224, (300, 2))
    reach = rng.uniform(0.1, 40, 300)
    rows, cols, complete = S.nearest_sites(Q, reach, k=8)
    full_r, full_c = S.near_sites(Q, reach)
    got = {(int(a), int(b)) for a, b in zip(rows, cols)}
    want = {(int(a), int(b)) for a, b in zip(full_r, full_c)}
    assert got <= want
    done = set(np.nonzero(complete)[0].tolist())
    assert {p for p in want if p[0] in done} == {p for p in got if p[0] in done}
    assert 0 < len(done) < len(Q)
