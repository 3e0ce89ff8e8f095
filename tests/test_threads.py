"""One BLAS thread inside the library's calls, and the caller's environment untouched
(runtime/threads.py).  Run in a fresh interpreter without OPENBLAS_NUM_THREADS: the test session
itself limits threads (conftest.py)."""
from __future__ import annotations

import os
import subprocess
import json
import sys


def run_probe(code: str) -> dict:
    """The JSON line printed by ``code`` in a fresh interpreter whose user asked for 2 BLAS threads."""
    env = {k: v for k, v in os.environ.items() if k not in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS",
                                                              "MKL_NUM_THREADS", "KMP_DUPLICATE_LIB_OK")}
    env["OPENBLAS_NUM_THREADS"] = "2"                 # the user's choice, as seen outside our calls
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=300)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout.strip().splitlines()[-1])


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
    r = run_probe(PROBE)
    assert r["import_same"] and r["call_same"], r
    assert r["inside"] and all(n == 1 for n in r["inside"]), r
    assert r["outside"] and all(n == 2 for n in r["outside"]), r        # restored after the call
    assert r["certified"]


VERIFY_PROBE = r"""
import gc, json
import curvedvoronoi as cv
import curvedvoronoi.runtime.voronoi.verify.certificate as certificate
from threadpoolctl import threadpool_info
seen = []
real = certificate.check_document
def spy(*a, **k):
    seen.append(([p["num_threads"] for p in threadpool_info() if p["user_api"] == "blas"], gc.isenabled()))
    return real(*a, **k)
certificate.check_document = spy
d = cv.voronoi([(0, 0, 1), (4, 0, 1), (2, 4, 0)], certify=False)
ok = cv.verify(d).ok
outside = [p["num_threads"] for p in threadpool_info() if p["user_api"] == "blas"]
print(json.dumps({"seen": seen, "ok": ok, "outside": outside, "gc_after": gc.isenabled()}))
"""


def test_verify_runs_with_one_blas_thread_and_the_cyclic_collector_paused():
    """cv.verify itself (not only the decorator) limits BLAS to one thread and pauses the cyclic
    collector inside the call, and restores both after (a decorator once slid onto a helper
    defined between it and ``verify``)."""
    r = run_probe(VERIFY_PROBE)
    assert r["ok"] and r["seen"], r
    for threads, gc_on in r["seen"]:
        assert threads and all(n == 1 for n in threads) and not gc_on, r
    assert all(n == 2 for n in r["outside"]) and r["gc_after"], r


INSERT_PROBE = r"""
import json
import curvedvoronoi as cv
import curvedvoronoi.runtime.voronoi.insertion as insertion
from threadpoolctl import threadpool_info
seen = []
real = insertion.prove_vertices
def spy(*a, **k):
    seen.append([p["num_threads"] for p in threadpool_info() if p["user_api"] == "blas"])
    return real(*a, **k)
insertion.prove_vertices = spy
d = cv.voronoi([(0, 0, 1), (6, 0, 1), (3, 5, 1), (9, 6, 1), (-4, 7, 1)])
e = d.insert((3, 1.5, 0.5))
outside = [p["num_threads"] for p in threadpool_info() if p["user_api"] == "blas"]
print(json.dumps({"seen": seen, "certified": e.certified, "outside": outside}))
"""


def test_insert_runs_with_one_blas_thread():
    """``Diagram.insert`` limits BLAS to one thread inside the call (the local proofs run there)
    and leaves the caller's setting after it."""
    r = run_probe(INSERT_PROBE)
    assert r["certified"] and r["seen"], r
    assert all(t and all(n == 1 for n in t) for t in r["seen"]), r
    assert all(n == 2 for n in r["outside"]), r
