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
:func:`runtime.voronoi.construction.as_site` (Circle, Conic, (cx, cy, radius), coefficient list).  Four
circles (or points) go to the exact circle locator; anything else to the general conic
locator :mod:`runtime.predicates.locator` (a LocatorError says so if it is not installed).  Results are
:class:`runtime.result.LocatorResult` objects, in query order; a query that raises is
returned as the exception object when ``on_error="return"`` (default ``"raise"``).

Caches (per-triple Voronoi vertices) live in each worker process: group queries sharing a
triple into the same chunk (``batch_size``) to reuse them.
"""
from __future__ import annotations

import time
from fractions import Fraction
from typing import Any, Sequence

from .circles import Circle, locate_conflicts_circles, voronoi_vertices_circles
from ..sites.conic import Conic
from .locator import locate_conflicts, voronoi_vertices
from ..result import LocatorError, VoronoiVertex
from ..voronoi.construction import as_site

__all__ = ["locate_batch", "vertices_batch", "locate_one", "as_conic"]


def locate_one(query, method: str = "auto"):
    """One conflict-locator call on four sites (circles exact, other conics via runtime.predicates.locator)."""
    if len(query) != 4:
        raise ValueError(f"a query is four sites (C1, C2, C3, C4), got {len(query)}")
    sites = [as_site(q) for q in query]
    if all(isinstance(s, Circle) for s in sites):
        return locate_conflicts_circles(*sites)
    return locate_conflicts(*(as_conic(s) for s in sites), method=method)


def _vertices_one(triple):
    sites = [as_site(q) for q in triple]
    if len(sites) != 3:
        raise ValueError(f"a triple is three sites, got {len(sites)}")
    if all(isinstance(s, Circle) for s in sites):
        tv = voronoi_vertices_circles(*sites)
        return [VoronoiVertex(v.x, v.y, v.radius, certified=True) for v in tv.vertices]
    return list(voronoi_vertices(*(as_conic(s) for s in sites)))


def as_conic(site):
    """A circle site as the equal :class:`runtime.sites.conic.Conic` (points have no conic form)."""
    if isinstance(site, Circle):
        if site.r2 == 0:
            raise LocatorError("a point site mixed with conics is answered by the diagram "
                               "(runtime.voronoi), not by the four-conic locator")
        return Conic.circle(centre=(Fraction(str(site.cx)), Fraction(str(site.cy))), r2=Fraction(str(site.r2)))
    return site


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
