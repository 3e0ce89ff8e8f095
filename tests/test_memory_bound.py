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
import os
import subprocess
import sys
from pathlib import Path

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
