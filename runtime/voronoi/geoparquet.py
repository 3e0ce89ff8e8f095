"""GeoParquet sites in, spatially partitioned GeoParquet diagrams out.

Input (:func:`read_geoparquet_sites`): a GeoParquet file, or a directory of part files (as Dask
and Spark write them), whose geometries are Points: a point site, or a circle when the optional
column ``radius`` is positive (thesis §3.1.2: a point is a circle of radius 0).  An optional
column ``label`` (or ``id``) names each site.  Coordinates and radii are taken exactly at their
binary value, as everywhere in the library.  Anything else -- another geometry type, a missing or
non-finite coordinate, a negative or non-finite radius -- is refused with one line naming the row.

Output (:func:`write_geoparquet`): a directory holding ``edges/``, ``vertices/``, ``cells/`` and
``sites/``, each a GeoParquet dataset of part files ``part.NNNNN.parquet`` (rows grouped by a
grid over the plane, so that a part covers one region, as the tiles of
:func:`runtime.voronoi.distributed.tiled_voronoi` do), readable by ``geopandas.read_parquet``
and, part by part, by ``dask_geopandas.read_parquet``; and ``diagram.json`` with ``certified``,
the problems and the statistics.  The columns are those of
:meth:`runtime.voronoi.structure.Diagram.to_geopandas`, except that point and circle sites are
written as their centres with a ``radius`` column (the input form, so ``sites/`` reads back as
sites); vertices have ``id``, ``sites`` (a list), ``radius``, ``certified``.  The CRS is passed through: the input's CRS when the diagram was read
from GeoParquet.  The diagram is held in memory while it is written (the parts bound what a
reader loads at once, not what this process holds).

Needs geopandas and pyarrow (``pip install "curvedvoronoi[parquet]"``).

Public API: :func:`read_geoparquet_sites`, :func:`write_geoparquet`, :class:`GeoParquetSites`.
"""
from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from ..result import InvalidConicError
from ..predicates.circles import Circle, Point
from .cells import cell_frame, edge_frame, site_frame

__all__ = ["read_geoparquet_sites", "write_geoparquet", "GeoParquetSites", "PART_ROWS"]

#: rows per part file of the written datasets (at most)
PART_ROWS = 100_000


class GeoParquetSites(NamedTuple):
    """The sites read from GeoParquet and the dataset's CRS (a ``pyproj.CRS`` or None)."""

    sites: list
    crs: Any


def _geopandas():
    import importlib.util

    if importlib.util.find_spec("geopandas") is None or importlib.util.find_spec("pyarrow") is None:
        raise ImportError("GeoParquet needs geopandas and pyarrow (pip install geopandas pyarrow)")
    import geopandas as gpd

    return gpd


def read_geoparquet_sites(path) -> GeoParquetSites:
    """The point and circle sites of a GeoParquet file or directory (see the module docstring).

    Raises :class:`runtime.result.InvalidConicError` (one line naming the row) on bad input and
    ``ValueError`` when the file cannot be read as GeoParquet."""
    gpd = _geopandas()
    try:
        frame = gpd.read_parquet(path)
    except (OSError, ValueError) as exc:
        first = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise ValueError(f"{path}: cannot read it as GeoParquet ({first})") from None
    if len(frame) == 0:
        raise InvalidConicError(f"{path}: no rows")
    geom = frame.geometry
    kinds = geom.geom_type.to_numpy()
    bad = np.nonzero(kinds != "Point")[0]
    if len(bad):
        r = int(bad[0])
        raise InvalidConicError(f"{path}: row {r}: geometry {kinds[r]}; GeoParquet sites are Points (with an "
                                "optional 'radius' column for circles); segments and polygons: use GeoJSON or DXF")
    X = geom.x.to_numpy(dtype=float)
    Y = geom.y.to_numpy(dtype=float)
    R = frame["radius"].to_numpy(dtype=float) if "radius" in frame.columns else np.zeros(len(frame))
    for name, col in (("x", X), ("y", Y), ("radius", R)):
        nonfinite = np.nonzero(~np.isfinite(col))[0]
        if len(nonfinite):
            r = int(nonfinite[0])
            raise InvalidConicError(f"{path}: row {r}: {name} is {col[r]} (sites need finite numbers)")
    negative = np.nonzero(R < 0)[0]
    if len(negative):
        r = int(negative[0])
        raise InvalidConicError(f"{path}: row {r}: radius {R[r]} is negative")
    key = "label" if "label" in frame.columns else ("id" if "id" in frame.columns else None)
    labels = [None] * len(frame) if key is None else [None if _missing(v) else str(v) for v in frame[key]]
    sites = [Point(float(x), float(y), label) if r == 0 else Circle.from_radius(float(x), float(y), float(r), label)
             for x, y, r, label in zip(X.tolist(), Y.tolist(), R.tolist(), labels)]
    return GeoParquetSites(sites, frame.crs)


def _missing(v) -> bool:
    return v is None or (isinstance(v, float) and math.isnan(v))


def _parts(points: np.ndarray, rows: int) -> list[np.ndarray]:
    """Row indices grouped into parts of at most ``rows`` rows, each part one region of the
    plane: the rows ordered by a k × k grid over their representative points (row-major, a
    serpentine in x so that consecutive parts are neighbours), then cut into equal runs."""
    n = len(points)
    if n <= rows:
        return [np.arange(n)]
    k = max(1, int(math.ceil(math.sqrt(n / rows))))
    lo = points.min(axis=0)
    span = np.maximum(points.max(axis=0) - lo, 1e-300)
    cell = np.minimum(((points - lo) / span * k).astype(np.int64), k - 1)
    gx = np.where(cell[:, 1] % 2 == 0, cell[:, 0], k - 1 - cell[:, 0])
    order = np.lexsort((points[:, 0], gx, cell[:, 1]))
    return np.array_split(order, -(-n // rows))


def _write_dataset(frame, directory: Path, rows: int) -> int:
    directory.mkdir(parents=True, exist_ok=True)
    for old in directory.glob("part.*.parquet"):
        old.unlink()
    if len(frame) == 0:
        frame.to_parquet(directory / "part.00000.parquet")
        return 1
    rep = frame.geometry.representative_point()
    pts = np.column_stack([rep.x.to_numpy(dtype=float), rep.y.to_numpy(dtype=float)])
    pts = np.where(np.isfinite(pts), pts, 0.0)          # empty cells: any part
    parts = _parts(pts, rows)
    for k, idx in enumerate(parts):
        frame.iloc[np.sort(idx)].to_parquet(directory / f"part.{k:05d}.parquet")
    return len(parts)


def write_geoparquet(diagram, directory, crs: Any = None, *, clip: Any = None, part_rows: int = PART_ROWS) -> dict:
    """Write ``diagram`` as GeoParquet datasets under ``directory`` (see the module docstring);
    returns ``{dataset: number of part files}``.  ``crs`` is passed through (None: no CRS
    recorded; GIS tools then ask); ``clip`` bounds the cells as in
    :meth:`runtime.voronoi.structure.Diagram.cells`."""
    gpd = _geopandas()
    import shapely

    out = Path(directory)
    out.mkdir(parents=True, exist_ok=True)
    V = diagram.vertices
    vertices = gpd.GeoDataFrame(
        {"id": [v.id for v in V], "sites": [list(map(int, v.sites)) for v in V],
         "radius": [float(v.radius) for v in V], "certified": [bool(v.certified) for v in V]},
        geometry=shapely.points(np.array([[v.x, v.y] for v in V], dtype=float).reshape(-1, 2)), crs=crs)
    written = {}
    builders = (("edges", lambda: edge_frame(diagram, crs)), ("vertices", lambda: vertices),
                ("cells", lambda: cell_frame(diagram, crs, clip)),
                ("sites", lambda: site_frame(diagram, crs, circles_as_points=True)))
    for name, build in builders:                      # one frame alive at a time
        written[name] = _write_dataset(build(), out / name, part_rows)
    summary = {"format": "curvedvoronoi.geoparquet/1", "certified": bool(diagram.certified),
               "problems": [str(p) for p in diagram.problems], "datasets": written,
               "stats": json.loads(json.dumps(diagram.stats, default=_plain))}
    (out / "diagram.json").write_text(json.dumps(summary, indent=1))
    return written


def _plain(x):
    if isinstance(x, np.generic):
        return x.item()
    if isinstance(x, np.ndarray):
        return x.tolist()
    return str(x)
