"""Batch evaluation of independent conflict-locator calls with joblib (local or Dask cluster).

The conflict locator (thesis Thm 5.2.2; §3.1.3 for circles) answers one query
(C1, C2, C3, C4) at a time and the queries of a batch are independent, so they parallelise
trivially.  :func:`locate_batch` runs them with :class:`joblib.Parallel`:

* ``backend=None`` / ``"loky"`` (default when ``n_jobs != 1``): local worker processes;
* ``backend="threading"``: threads (little gain: the exact arithmetic holds the GIL);
* ``backend="dask"``: joblib's Dask backend, i.e. the workers of a ``dask.distributed``
  cluster -- for workloads that outgrow one machine.  A ``dask.distributed.Client`` must be
  active (or passed as ``client=``)::

      from dask.distributed import Client, LocalCluster
      with LocalCluster(n_workers=4) as cluster, Client(cluster) as client:
          results = locate_batch(queries, backend="dask", client=client)

  Replace the LocalCluster by the address of a real scheduler (``Client("tcp://host:8786")``)
  to scale out; the workers need this package installed.

Each query is a sequence of four sites in any form accepted by
:func:`runtime.diagram.as_site` (Circle, Conic, (cx, cy, radius), coefficient list).  Four
circles (or points) go to the exact circle locator; anything else to the general conic
locator :mod:`runtime.locator` (a LocatorError says so if it is not installed).  Results are
:class:`runtime.result.LocatorResult` objects, in query order; a query that raises is
returned as the exception object when ``on_error="return"`` (default ``"raise"``).

Caches (per-triple Voronoi vertices) live in each worker process: group queries sharing a
triple into the same chunk (``batch_size``) to reuse them.
"""
from __future__ import annotations

import time
from typing import Any, Sequence

__all__ = ["locate_batch", "vertices_batch", "locate_one"]


def locate_one(query, method: str = "auto"):
    """One conflict-locator call on four sites (circles exact, other conics via runtime.locator)."""
    from .diagram import _conic_locator, as_site

    if len(query) != 4:
        raise ValueError(f"a query is four sites (C1, C2, C3, C4), got {len(query)}")
    sites = [as_site(q) for q in query]
    if all(s.is_circle for s in sites):
        from .circles import locate_conflicts_circles

        return locate_conflicts_circles(*(s.circle for s in sites))
    loc = _conic_locator()
    return loc.locate_conflicts(*(s.get_conic() for s in sites), method=method)


def _vertices_one(triple):
    from .diagram import _conic_locator, as_site
    from .result import VoronoiVertex

    sites = [as_site(q) for q in triple]
    if len(sites) != 3:
        raise ValueError(f"a triple is three sites, got {len(sites)}")
    if all(s.is_circle for s in sites):
        from .circles import voronoi_vertices_circles

        tv = voronoi_vertices_circles(*(s.circle for s in sites))
        return [VoronoiVertex(v.x, v.y, v.radius, certified=True) for v in tv.vertices]
    return list(_conic_locator().voronoi_vertices(*(s.get_conic() for s in sites)))


def _guard(fn, item, on_error, *args):
    try:
        return fn(item, *args)
    except Exception as exc:  # noqa: BLE001 - reported per query when on_error="return"
        if on_error == "raise":
            raise
        return exc


def _run(fn, items: Sequence, n_jobs: int, backend: str | None, batch_size, on_error: str, client, *args):
    import joblib

    if on_error not in ("raise", "return"):
        raise ValueError('on_error must be "raise" or "return"')
    items = list(items)
    if n_jobs == 1 and backend is None:
        return [_guard(fn, it, on_error, *args) for it in items]
    if backend == "dask":
        try:
            import distributed  # noqa: F401
        except ImportError:
            raise ImportError('backend="dask" needs dask.distributed: pip install "dask[distributed]"') from None
        if client is None:
            from distributed import get_client

            try:
                get_client()
            except ValueError:
                raise ValueError('backend="dask" needs an active dask.distributed Client '
                                 "(create one, or pass client=...)") from None
        cfg: dict[str, Any] = {"backend": "dask"}
        if client is not None:
            cfg["client"] = client
        with joblib.parallel_config(**cfg):
            return joblib.Parallel(n_jobs=n_jobs, batch_size=batch_size)(
                joblib.delayed(_guard)(fn, it, on_error, *args) for it in items)
    return joblib.Parallel(n_jobs=n_jobs, backend=backend, batch_size=batch_size)(
        joblib.delayed(_guard)(fn, it, on_error, *args) for it in items)


def locate_batch(queries: Sequence, *, n_jobs: int = -1, backend: str | None = None, batch_size="auto",
                 method: str = "auto", on_error: str = "raise", client=None, timings: dict | None = None):
    """Run the conflict locator on every query (four sites each), in parallel.

    ``n_jobs``/``backend``/``batch_size`` are joblib's (``backend="dask"``: see the module
    docstring).  ``n_jobs=1`` without a backend runs serially in this process.  Returns
    the list of LocatorResult in query order.  If ``timings`` is a dict, the wall time is
    stored in it under ``"seconds"``.
    """
    t0 = time.perf_counter()
    out = _run(locate_one, queries, n_jobs, backend, batch_size, on_error, client, method)
    if timings is not None:
        timings["seconds"] = time.perf_counter() - t0
    return out


def vertices_batch(triples: Sequence, *, n_jobs: int = -1, backend: str | None = None, batch_size="auto",
                   on_error: str = "raise", client=None):
    """True Voronoi vertices of every triple of sites, in parallel (list of VoronoiVertex lists)."""
    return _run(_vertices_one, triples, n_jobs, backend, batch_size, on_error, client)
