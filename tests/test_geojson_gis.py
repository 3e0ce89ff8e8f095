"""The diagram's GeoJSON read back by a GIS reader (geopandas through GDAL/pyogrio): sites with their
labels, unique feature ids, the user's CRS or a planar one, never longitude/latitude by default."""
from __future__ import annotations

import json
import math
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

import curvedvoronoi as cv

gpd = pytest.importorskip("geopandas")
pyproj = pytest.importorskip("pyproj")

ROOT = Path(__file__).resolve().parents[1]


def _scene():
    return [cv.Circle.from_radius(0, 0, 1, label="well A"), cv.Point(4, 0, label="pump"),
            cv.Conic.ellipse(centre=(2, 6), axes=(2, 1), degrees=90, label="lake"),
            cv.Circle(7, 5, r2=2), (9, -2)]


def _read(path):
    """The file read by geopandas, with the warnings GDAL raised while reading it."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        frame = gpd.read_file(path)
    return frame, [str(w.message) for w in caught]


@pytest.fixture(scope="module")
def diagram():
    return cv.voronoi(_scene())


def test_features_ids_and_crs_survive_a_gis_reader(diagram, tmp_path):
    d = diagram
    path = tmp_path / "d.geojson"
    path.write_text(json.dumps(d.to_geojson(crs="EPSG:32633")))
    g, warned = _read(path)
    assert not [w for w in warned if "Several features with id" in w], warned
    assert g.crs == pyproj.CRS("EPSG:32633")
    assert len(g) == len(d.edges) + len(d.vertices) + len(d.sites)
    assert g["id"].is_unique
    assert sorted(g["id"]) == sorted([f"edge-{e.id}" for e in d.edges] + [f"vertex-{v.id}" for v in d.vertices]
                                     + [f"site-{i}" for i in range(len(d.sites))])
    assert (g["kind"] == "edge").sum() == len(d.edges) and (g["kind"] == "vertex").sum() == len(d.vertices)


def test_sites_are_features_with_their_labels_on_the_curves(diagram, tmp_path):
    d = diagram
    path = tmp_path / "d.geojson"
    path.write_text(json.dumps(d.to_geojson(crs="EPSG:32633")))
    g, _ = _read(path)
    S = g[g["kind"] == "site"].sort_values("number")
    assert S["number"].tolist() == list(range(len(d.sites)))
    assert S["label"].tolist()[:3] == ["well A", "pump", "lake"] and S["label"].iloc[3:].isna().all()
    assert S["shape"].tolist() == ["circle", "point", "ellipse", "circle", "point"]
    geom = S.geometry.tolist()
    # the point sites are their points; the curves' samples lie on the curves
    assert (geom[1].x, geom[1].y) == (4, 0) and (geom[4].x, geom[4].y) == (9, -2)
    ring = np.asarray(geom[0].coords)
    assert np.allclose(np.hypot(ring[:, 0], ring[:, 1]), 1, atol=1e-12) and geom[0].is_closed
    ring = np.asarray(geom[3].coords)
    assert np.allclose(np.hypot(ring[:, 0] - 7, ring[:, 1] - 5), math.sqrt(2), atol=1e-12)
    E = np.asarray(geom[2].coords)          # x²/1 + y²/4 = 1 around (2, 6): the major axis turned to y
    assert np.allclose((E[:, 0] - 2) ** 2 + (E[:, 1] - 6) ** 2 / 4, 1, atol=1e-9)
    # the length of the sampled circle is that of the circle, within its chords
    assert geom[0].length == pytest.approx(2 * math.pi, rel=1e-3)


def test_without_a_crs_the_file_is_planar_not_longitude_latitude(diagram, tmp_path):
    path = tmp_path / "d.geojson"
    path.write_text(json.dumps(diagram.to_geojson()))
    g, _ = _read(path)
    assert g.crs is not None and not g.crs.is_geographic and g.crs != pyproj.CRS("EPSG:4326")
    assert "Engineering" in g.crs.type_name
    # strict RFC 7946 on request: then the reader falls back to its default, longitude/latitude
    path.write_text(json.dumps(diagram.to_geojson(crs=False)))
    assert "crs" not in diagram.to_geojson(crs=False)
    assert _read(path)[0].crs == pyproj.CRS("EPSG:4326")


def test_a_pyproj_crs_is_written_by_its_authority_code(diagram):
    gj = diagram.to_geojson(crs=pyproj.CRS.from_epsg(2056))
    assert gj["crs"] == {"type": "name", "properties": {"name": "EPSG:2056"}}


def test_labels_survive_the_diagram_json(diagram):
    doc = json.loads(json.dumps(diagram.to_json()))
    assert [s.get("label") for s in doc["sites"]] == ["well A", "pump", "lake", None, None]
    back = cv.Diagram.from_json(doc)
    assert [getattr(s, "label", None) for s in back.sites] == ["well A", "pump", "lake", None, None]
    assert back.sites == diagram.sites


def test_hyperbola_branches_are_two_lines_and_unbounded_sites_stay_near_the_sites(tmp_path):
    d = cv.voronoi([cv.Conic.hyperbola(centre=(0, 0), axes=(1, 1), label="h"), (0, 3), (0, -3)])
    feats = [f for f in d.to_geojson()["features"] if f["properties"]["kind"] == "site"]
    h = feats[0]["geometry"]
    assert h["type"] == "MultiLineString" and len(h["coordinates"]) == 2
    for branch in h["coordinates"]:
        P = np.asarray(branch)
        assert np.allclose(P[:, 0] ** 2 - P[:, 1] ** 2, 1, atol=1e-9)
        assert len(set(np.sign(P[:, 0]))) == 1          # one branch each: no chord across the centre


def test_the_cli_writes_labels_sites_and_the_crs(tmp_path):
    sites = tmp_path / "sites.json"
    sites.write_text(json.dumps({"sites": [{"circle": {"centre": [500000, 5000000], "radius": 10}, "label": "well"},
                                           {"point": [500040, 5000000], "label": "pump"},
                                           {"point": [500020, 5000030]}]}))
    out = {k: tmp_path / f"d.{k}" for k in ("json", "geojson")}
    r = subprocess.run([sys.executable, "-m", "curvedvoronoi", "diagram", str(sites), "--json", str(out["json"]),
                        "--geojson", str(out["geojson"]), "--crs", "EPSG:32633", "--quiet"],
                       cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    assert [s.get("label") for s in json.loads(out["json"].read_text())["sites"]] == ["well", "pump", None]
    g, warned = _read(out["geojson"])
    assert g.crs == pyproj.CRS("EPSG:32633") and not [w for w in warned if "Several features" in w]
    assert g[g["kind"] == "site"].sort_values("number")["label"].tolist()[:2] == ["well", "pump"]
