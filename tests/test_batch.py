"""Batch evaluation of independent locator calls (runtime/predicates/batch.py): joblib locally and on a
local dask.distributed cluster through joblib's Dask backend.  Results must equal the direct
calls of the exact circle locator (thesis §3.1.3)."""
from __future__ import annotations

import random

import pytest

from curvedvoronoi.runtime.predicates.batch import locate_batch, vertices_batch
from curvedvoronoi.runtime.predicates.circles import locate_conflicts_circles, voronoi_vertices_circles
from curvedvoronoi.runtime.result import LocatorError


def _queries(n=24, seed=3):
    rnd = random.Random(seed)
    return [[(rnd.randint(0, 60), rnd.randint(0, 60), rnd.randint(1, 9)) for _ in range(4)] for _ in range(n)]


def _summary(results):
    return [(r.conflict, [(round(v.x, 9), round(v.y, 9), v.in_conflict) for v in r.vertices]) for r in results]


def test_serial_and_joblib_match_direct_calls():
    qs = _queries()
    direct = [locate_conflicts_circles(*q) for q in qs]
    assert any(r.conflict for r in direct) and not all(r.conflict for r in direct)
    assert _summary(locate_batch(qs, n_jobs=1)) == _summary(direct)
    assert _summary(locate_batch(qs, n_jobs=2, backend="threading")) == _summary(direct)
    assert _summary(locate_batch(qs[:8], n_jobs=2)) == _summary(direct[:8])  # loky processes


def test_vertices_batch():
    ts = [q[:3] for q in _queries(10, seed=5)]
    got = vertices_batch(ts, n_jobs=1)
    for t, vs in zip(ts, got):
        ref = voronoi_vertices_circles(*t).vertices
        assert [(v.x, v.y, v.radius) for v in vs] == [(v.x, v.y, v.radius) for v in ref]


def test_errors_raise_or_return():
    qs = _queries(3) + [[(0, 0, 1), (0, 0, 1), (5, 5, 1), (9, 9, 1)]]  # coincident sites
    with pytest.raises(LocatorError):
        locate_batch(qs, n_jobs=1)
    res = locate_batch(qs, n_jobs=1, on_error="return")
    assert isinstance(res[-1], LocatorError) and all(not isinstance(r, Exception) for r in res[:3])
    with pytest.raises(ValueError):
        locate_batch([[(0, 0, 1)] * 3], n_jobs=1)
    with pytest.raises(ValueError):
        locate_batch(qs, n_jobs=1, on_error="ignore")


def test_dask_backend_local_cluster():
    distributed = pytest.importorskip("distributed", reason='dask.distributed not installed (pip install "dask[distributed]")')
    qs = _queries(12, seed=11)
    direct = _summary([locate_conflicts_circles(*q) for q in qs])
    with pytest.raises(ValueError, match="Client"):
        locate_batch(qs, backend="dask")  # no client active
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        assert _summary(locate_batch(qs, backend="dask")) == direct
        assert _summary(locate_batch(qs, backend="dask", client=client)) == direct
