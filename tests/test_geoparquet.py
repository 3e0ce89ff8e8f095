"""GeoParquet sites in, partitioned GeoParquet diagrams out (runtime/voronoi/geoparquet.py) and the
``diagram`` command's --out / --scheduler / --sites-per-tile options.

References: the sites written by geopandas from known numbers (exact round trip), scipy's Delaunay
triangulation for point sites (an independent construction: for points in general position the
Voronoi edges are the Delaunay edges), and dask_geopandas reading the written part files.
"""
from __future__ import annotations

import json
import subprocess
import sys
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest

gpd = pytest.importorskip("geopandas")
pytest.importorskip("pyarrow")
import shapely  # noqa: E402
from scipy.spatial import Delaunay  # noqa: E402

import curvedvoronoi as cv  # noqa: E402
from curvedvoronoi.runtime.voronoi.command import diagram_main  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


def _write_sites(path, xy, radius=None, crs="EPSG:32633", labels=None):
    cols = {}
    if radius is not None:
        cols["radius"] = radius
    if labels is not None:
        cols["label"] = labels
    gpd.GeoDataFrame(cols, geometry=shapely.points(np.asarray(xy, float)), crs=crs).to_parquet(path)


def _q(x) -> Fraction:
    """An fmpq as a Fraction."""
    return Fraction(int(x.p), int(x.q))


def _delaunay_pairs(xy) -> set:
    tri = Delaunay(np.asarray(xy, float))
    out = set()
    for a, b, c in tri.simplices.tolist():
        out |= {tuple(sorted(p)) for p in ((a, b), (b, c), (a, c))}
    return out


def test_sites_round_trip_exactly_with_labels_and_crs(tmp_path):
    xy = [(500000.125, 5000000.5), (500010.0, 5000003.25), (500004.5, 5000020.0)]
    radius = [0.0, 1.5, 0.1]
    _write_sites(tmp_path / "s.parquet", xy, radius, labels=["well A", "tree", None])
    sites, crs = cv.read_geoparquet_sites(tmp_path / "s.parquet")
    assert crs.to_epsg() == 32633
    assert type(sites[0]).__name__ == "Point" and type(sites[1]).__name__ == "Circle"
    # exact binary values: the centre and the squared radius as rationals
    assert (_q(sites[1].cx), _q(sites[1].cy)) == (Fraction(500010.0), Fraction(5000003.25))
    assert _q(sites[1].r2) == Fraction(1.5) ** 2
    assert _q(sites[2].r2) == Fraction(0.1) ** 2          # 0.1 at its binary value, squared exactly
    assert [s.label for s in sites] == ["well A", "tree", None]


@pytest.mark.parametrize("case, expected", [
    ("line", "row 1: geometry LineString"),
    ("nan", "row 2: radius is nan"),
    ("negative", "row 0: radius -1.0 is negative"),
])
def test_bad_rows_are_named(tmp_path, case, expected):
    path = tmp_path / "bad.parquet"
    if case == "line":
        geoms = [shapely.Point(0, 0), shapely.LineString([(0, 0), (1, 1)])]
        gpd.GeoDataFrame(geometry=geoms).to_parquet(path)
    else:
        r = [1.0, 1.0, float("nan")] if case == "nan" else [-1.0, 1.0, 1.0]
        _write_sites(path, [(0, 0), (10, 0), (0, 10)], r)
    with pytest.raises(cv.InvalidConicError, match=expected):
        cv.read_geoparquet_sites(path)
    assert diagram_main([str(path), "--quiet"]) == 2


def test_not_parquet_is_one_line_bad_input(tmp_path, capsys):
    path = tmp_path / "junk.parquet"
    path.write_bytes(b"not parquet at all")
    assert diagram_main([str(path), "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "cannot read it as GeoParquet" in err[0]


def test_tiled_command_writes_partitioned_datasets_equal_to_delaunay(tmp_path):
    """Points at UTM scale, built tile by tile (--sites-per-tile), written with --out: the edges read
    back from the GeoParquet datasets are the Delaunay edges of scipy, every edge once, with the
    input's CRS; the cells cover the clip box; diagram.json says certified."""
    rng = np.random.default_rng(7)
    xy = np.column_stack([500000 + rng.uniform(0, 2000, 600), 5000000 + rng.uniform(0, 2000, 600)])
    _write_sites(tmp_path / "pts.parquet", xy)
    out = tmp_path / "out"
    assert diagram_main([str(tmp_path / "pts.parquet"), "--sites-per-tile", "150", "--out", str(out),
                         "--certificate", "chunks", "--quiet"]) == 0
    summary = json.loads((out / "diagram.json").read_text())
    assert summary["certified"] is True and summary["stats"]["tiling"]["tiles"] >= 2
    assert summary["stats"]["tiling"]["certificate"] == "chunks"
    edges = gpd.read_parquet(out / "edges")
    assert edges.crs.to_epsg() == 32633
    assert sorted(edges["id"]) == list(range(len(edges)))
    pairs = {tuple(sorted(p)) for p in zip(edges["site_i"], edges["site_j"])}
    assert len(pairs) == len(edges) and pairs == _delaunay_pairs(xy)
    vertices = gpd.read_parquet(out / "vertices")
    # each vertex is the circumcentre of its three sites: equidistant within rounding
    for row in vertices.itertuples():
        d = np.hypot(*(xy[list(row.sites)] - [row.geometry.x, row.geometry.y]).T)
        assert np.allclose(d, row.radius, rtol=1e-9, atol=1e-6)
    back, back_crs = cv.read_geoparquet_sites(out / "sites")       # the sites dataset reads back as sites
    assert back_crs.to_epsg() == 32633
    order = np.argsort(gpd.read_parquet(out / "sites")["site"].to_numpy())
    assert [(float(back[k].cx), float(back[k].cy)) for k in order] == [tuple(p) for p in xy.tolist()]
    cells = gpd.read_parquet(out / "cells")
    assert len(cells) == len(xy)
    box = shapely.box(*cells.total_bounds)
    assert abs(cells.area.sum() - box.area) < 1e-6 * box.area


def test_circle_sites_are_written_as_centres_and_radii(tmp_path):
    """Circles and points in sites/ are their centres with a radius column (the input form): read
    back, the same exact sites and the same diagram."""
    rng = np.random.default_rng(9)
    sites = [(10 * i + rng.uniform(0, 4), 10 * j + rng.uniform(0, 4), rng.uniform(0.5, 2) if (i + j) % 3 else 0)
             for i in range(6) for j in range(6)]
    d = cv.voronoi(sites)
    assert d.certified
    cv.write_geoparquet(d, tmp_path / "d")
    frame = gpd.read_parquet(tmp_path / "d" / "sites")
    assert set(frame.geom_type) == {"Point"} and "radius" in frame.columns
    back, _ = cv.read_geoparquet_sites(tmp_path / "d" / "sites")
    back = [back[k] for k in np.argsort(frame["site"].to_numpy())]
    assert back == [cv.Point(x, y) if r == 0 else cv.Circle.from_radius(x, y, r) for x, y, r in sites]
    assert cv.voronoi(back).delaunay_edges() == d.delaunay_edges()


def test_parts_are_regions_and_dask_reads_them(tmp_path):
    """write_geoparquet with small parts: each row in exactly one part file, the parts ordered
    by region (their boxes' overlap is small against the whole), read by dask_geopandas."""
    dg = pytest.importorskip("dask_geopandas")
    rng = np.random.default_rng(3)
    xy = rng.uniform(0, 100, (400, 2))
    d = cv.voronoi([tuple(p) for p in xy])
    assert d.certified
    written = cv.write_geoparquet(d, tmp_path / "d", crs=None, part_rows=100)
    assert written["edges"] == -(-len(d.edges) // 100) and written["sites"] == 4
    parts = sorted((tmp_path / "d" / "edges").glob("part.*.parquet"))
    frames = [gpd.read_parquet(p) for p in parts]
    ids = np.concatenate([f["id"].to_numpy() for f in frames])
    assert sorted(ids.tolist()) == [e.id for e in d.edges]
    # grouped by region: the edges of a part (by their representative points inside the sites'
    # box) span a small box, not the whole scene as parts in input order would
    whole = shapely.box(*xy.min(0), *xy.max(0))
    spans = []
    for f in frames:
        rep = f.geometry.representative_point()
        inside = rep[rep.within(whole)]
        spans.append(shapely.box(*inside.total_bounds).area / whole.area)
    assert np.median(spans) < 0.25, spans
    lazy = dg.read_parquet(tmp_path / "d" / "edges")
    assert lazy.npartitions == len(parts) and len(lazy.compute()) == len(d.edges)


def test_option_misuse_is_bad_input(tmp_path, capsys):
    _write_sites(tmp_path / "p.parquet", [(0, 0), (1, 0), (0, 1)])
    assert diagram_main([str(tmp_path / "p.parquet"), "--scheduler", "local", "--time-limit", "5"]) == 2
    assert diagram_main([str(tmp_path / "p.parquet"), "--sites-per-tile", "0"]) == 2
    assert diagram_main([str(tmp_path / "p.parquet"), "--certificate", "chunks"]) == 2      # nothing tiled
    dxf = ROOT / "examples"
    drawing = next(iter(sorted(dxf.glob("*.dxf"))), None)
    if drawing is not None:
        from curvedvoronoi.runtime.segments.command import diagram_main as shapes_main
        with pytest.raises(SystemExit) as exc:
            shapes_main([str(drawing), "--out", str(tmp_path / "o")])
        assert exc.value.code == 2
    assert "error:" in capsys.readouterr().err


@pytest.mark.slow
def test_scheduler_local_cluster_from_the_command_line(tmp_path):
    """``--scheduler local:2`` starts two worker processes: the same edges as scipy's Delaunay."""
    pytest.importorskip("distributed")
    rng = np.random.default_rng(11)
    xy = rng.uniform(0, 1000, (500, 2))
    _write_sites(tmp_path / "pts.parquet", xy, crs=None)
    out = tmp_path / "out"
    r = subprocess.run([sys.executable, "-m", "curvedvoronoi", "diagram", str(tmp_path / "pts.parquet"),
                        "--scheduler", "local:2", "--sites-per-tile", "120", "--out", str(out), "--quiet"],
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    edges = gpd.read_parquet(out / "edges")
    assert {tuple(sorted(p)) for p in zip(edges["site_i"], edges["site_j"])} == _delaunay_pairs(xy)
