"""Small things a user of the API expects: the public exceptions and result types exported, a
diagram equal to its copy, unique GeoJSON feature ids with the user's CRS, type information."""
from __future__ import annotations

import copy
from pathlib import Path

import curvedvoronoi as cv


def test_public_exceptions_and_result_types_are_exported():
    from curvedvoronoi.runtime.result import NumericalRefusal
    from curvedvoronoi.runtime.voronoi.site_input import SiteError
    from curvedvoronoi.runtime.voronoi.structure import DiagramEdge, DiagramVertex
    from curvedvoronoi.runtime.voronoi.verify.certificate import Certificate

    assert cv.NumericalRefusal is NumericalRefusal and cv.SiteError is SiteError
    assert cv.DiagramVertex is DiagramVertex and cv.DiagramEdge is DiagramEdge and cv.Certificate is Certificate
    assert issubclass(cv.RangeRefusal, cv.NumericalRefusal)
    assert {"SiteError", "NumericalRefusal", "Certificate", "DiagramVertex", "DiagramEdge"} <= set(cv.__all__)


def test_a_diagram_equals_its_copy_and_not_a_changed_one():
    d = cv.voronoi([(0, 0, 1), (4, 0, 1), (2, 4, 0)], certify=False)
    c = copy.deepcopy(d)
    assert d == c
    c.edges[0].polyline = c.edges[0].polyline + 1e-9
    assert d != c


def test_geojson_feature_ids_are_unique_and_the_crs_is_written():
    d = cv.voronoi([(0, 0, 1), (4, 0, 1), (2, 4, 0)])
    gj = d.to_geojson(crs="EPSG:32633")
    ids = [f["id"] for f in gj["features"]]
    assert len(ids) == len(set(ids)) == len(d.edges) + len(d.vertices)
    assert gj["crs"] == {"type": "name", "properties": {"name": "EPSG:32633"}}
    assert "crs" not in d.to_geojson()


def test_the_package_ships_type_information():
    assert (Path(cv.__file__).parent / "py.typed").exists()
