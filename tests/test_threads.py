"""One BLAS thread inside the library's calls, and the caller's environment untouched
(runtime/threads.py).  Run in a fresh interpreter without OPENBLAS_NUM_THREADS: the test session
itself limits threads (conftest.py)."""
from __future__ import annotations

import os
import subprocess
import sys

PROBE = r"""
import json, os
before = dict(os.environ)
import curvedvoronoi as cv
after_import = dict(os.environ)
d = cv.voronoi([(0, 0, 1), (4, 0, 1), (2, 4, 0)])
after_call = dict(os.environ)
from curvedvoronoi.runtime.threads import one_blas_thread
from threadpoolctl import threadpool_info
inside = one_blas_thread(lambda: [p["num_threads"] for p in threadpool_info() if p["user_api"] == "blas"])()
outside = [p["num_threads"] for p in threadpool_info() if p["user_api"] == "blas"]
print(json.dumps({"import_same": before == after_import, "call_same": before == after_call,
                  "inside": inside, "outside": outside, "certified": d.certified}))
"""

def test_importing_and_calling_leave_the_environment_and_the_blas_threads_alone():
    env = {k: v for k, v in os.environ.items() if k not in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS",
                                                              "MKL_NUM_THREADS", "KMP_DUPLICATE_LIB_OK")}
    env["OPENBLAS_NUM_THREADS"] = "2"                 # the user's choice, as seen outside our calls
    out = subprocess.run([sys.executable, "-c", PROBE], capture_output=True, text=True, env=env, timeout=300)
    assert out.returncode == 0, out.stderr
    import json

    r = json.loads(out.stdout.strip().splitlines()[-1])
    assert r["import_same"] and r["call_same"], r
    assert r["inside"] and all(n == 1 for n in r["inside"]), r
    assert r["outside"] and all(n == 2 for n in r["outside"]), r        # restored after the call
    assert r["certified"]
