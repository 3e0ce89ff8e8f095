"""Small things a user of the API expects: the public exceptions and result types exported, a
diagram equal to its copy, unique GeoJSON feature ids with the user's CRS, type information."""
from __future__ import annotations

import copy
import math
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest

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
    assert set(cv.__all__) == set(dir(cv))
    for name in cv.__all__:
        assert getattr(cv, name) is not None


def test_result_types_are_the_classes_of_the_results():
    d = cv.voronoi([(0, 0, 1), (4, 0, 1), (2, 4, 0)])
    assert isinstance(d.vertices[0], cv.DiagramVertex) and isinstance(d.edges[0], cv.DiagramEdge)
    assert isinstance(cv.verify(d), cv.Certificate)
    assert isinstance(d.nearest([[0.0, 0.0]]), cv.NearestResult)
    assert isinstance(cv.load_offset("circle"), cv.OffsetPolynomial)
    L = cv.medial_axis([(0, 0), (4, 0), (4, 2), (0, 2)])
    assert isinstance(L, cv.MedialAxis) and all(isinstance(e, cv.MedialEdge) for e in L.edges)
    assert isinstance(cv.verify(cv.voronoi([cv.Segment((0, 0), (1, 0)), (0, 3)])), cv.Certificate)
    with pytest.raises(cv.SiteError):
        cv.voronoi([(0, 0, 1), (1, 0, 1)])          # discs of radius 1 at distance 1 overlap


def test_pairs_are_points_and_triples_are_circles():
    # the circumcentre of (0, 0), (4, 0), (2, 4) is (2, 3/2), at distance 5/2 from each
    for sites in ([(0, 0), (4, 0), (2, 4)], [[0, 0], [4, 0], [2, 4]], np.array([[0, 0], [4, 0], [2, 4]])):
        d = cv.voronoi(sites)
        assert d.sites == [cv.Point(0, 0), cv.Point(4, 0), cv.Point(2, 4)]
        (v,) = d.vertices
        assert (v.x, v.y, v.radius) == pytest.approx((2, 1.5, 2.5)) and d.certified
    assert cv.voronoi([(0, 0, 1), (4, 0), (0, 4, 0)]).sites == [cv.Circle.from_radius(0, 0, 1), cv.Point(4, 0),
                                                                 cv.Point(0, 4)]
    for bad in [(1,), (1, 2, 3, 4), "ab", 5]:
        with pytest.raises(ValueError, match="not a site"):
            cv.voronoi([bad, (7, 7), (9, 9)])


def test_the_locators_take_pairs_and_triples():
    # circles of radius 1 at (0, 0), (4, 0), (0, 4): the empty tangent circle is centred at (2, 2),
    # radius 2*sqrt(2) - 1 ≈ 1.83, and contains the point (1, 1) (distance sqrt(2))
    for locate in (cv.locate_conflicts, cv.locate_conflicts_circles):
        res = locate((0, 0, 1), (4, 0, 1), (0, 4, 1), (1, 1))
        assert res.certified and res.conflict
        assert [(float(v.x), float(v.y)) for v in res.vertices] == [(2.0, 2.0)]
        assert not locate((0, 0, 1), (4, 0, 1), (0, 4, 1), (9, 9)).conflict


def test_circle_constructors_name_the_radius_or_its_square():
    assert cv.Circle.from_radius(1, 2, 3) == cv.Circle(1, 2, r2=9) == cv.Circle(1, 2, 9)
    assert cv.Circle(0, 0, r2=2).radius_squared == 2


def test_rotations_take_degrees_or_radians_by_name():
    E = cv.Conic.ellipse
    quarter = E(centre=(0, 0), axes=(2, 1), rotation=(0, 1))
    assert E(centre=(0, 0), axes=(2, 1), degrees=90) == quarter == E(centre=(0, 0), axes=(2, 1), degrees=-270)
    # the major axis along y: x²/1 + y²/4 = 1
    assert quarter == cv.Conic.from_coefficients(4, 0, 1, 0, 0, -4)
    f = E(centre=(0, 0), axes=(2, 1), radians=math.pi / 2).frame
    assert (f.cos, f.sin) == pytest.approx((0, 1), abs=1e-15)
    f30, r30 = E((1, 2), (3, 1), degrees=30).frame, E((1, 2), (3, 1), radians=math.pi / 6).frame
    assert (f30.cos, f30.sin) == pytest.approx((math.sqrt(3) / 2, 0.5)) == (r30.cos, r30.sin)
    # a JSON rotation is in degrees and means the same as degrees=
    rec = {"ellipse": {"centre": [1, 2], "axes": [3, 1], "rotation": 30}}
    assert cv.parse_site(rec) == E((1, 2), (3, 1), degrees=30)
    assert cv.Conic.parabola((0, 0), 1, degrees=180) == cv.Conic.from_coefficients(0, 0, 1, 2, 0, 0)   # y² = -2x
    assert cv.Conic.hyperbola((0, 0), (2, 1), degrees=90) == cv.Conic.from_coefficients(-4, 0, 1, 0, 0, -4)
    assert E((0, 0), (2, 1), rotation=(Fraction(3, 5), Fraction(4, 5))).kind == "ellipse"
    for make in (lambda **k: E((0, 0), (2, 1), **k), lambda **k: cv.Conic.hyperbola((0, 0), (2, 1), **k),
                 lambda **k: cv.Conic.parabola((0, 0), 1, **k)):
        with pytest.raises(ValueError, match="degrees=.*radians="):
            make(rotation=90)
        with pytest.raises(ValueError, match="one of"):
            make(rotation=(0, 1), degrees=90)


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
    assert len(ids) == len(set(ids)) == len(d.edges) + len(d.vertices) + len(d.sites)
    assert gj["crs"] == {"type": "name", "properties": {"name": "EPSG:32633"}}
    assert not any("id" in f["properties"] for f in gj["features"])    # GDAL would take it for the feature id
    assert "crs" not in d.to_geojson(crs=False)


def test_short_reprs():
    d = cv.voronoi([(0, 0, 1), (4, 0, 1), (2, 4, 0)])
    for obj in [d, d.vertices[0], d.edges[0], d.sites[0], d.sites[2], cv.Conic.ellipse((0, 0), (2, 1)),
                cv.Segment((0, 0), (1, 0)), cv.Arc.circular((0, 0), 1, 0, 90)]:
        text = repr(obj)
        assert len(text) < 200 and "\n" not in text and text.startswith(type(obj).__name__)
    assert repr(d.edges[0]).count(",") < 12          # the polyline is counted, not listed


def test_the_package_ships_type_information():
    import tomllib

    assert (Path(cv.__file__).parent / "py.typed").exists()
    pyproject = Path(__file__).resolve().parents[1] / "pyproject.toml"
    assert "py.typed" in tomllib.loads(pyproject.read_text())["tool"]["setuptools"]["package-data"]["curvedvoronoi"]


def test_labels_are_carried_but_not_compared():
    a, b = cv.Circle.from_radius(0, 0, 1, label="well"), cv.Circle.from_radius(0, 0, 1)
    assert a == b and hash(a) == hash(b) and (a.label, b.label) == ("well", None)
    assert cv.Point(1, 2, label="p").label == "p" and cv.Circle(0, 0, r2=2, label="c").label == "c"
    e = cv.Conic.ellipse((0, 0), (2, 1), degrees=30, label="lake")
    assert e.label == "lake" and e == cv.Conic.ellipse((0, 0), (2, 1), degrees=30)
    assert copy.deepcopy(e).label == "lake"
    assert cv.parse_site({"point": [1, 2], "label": "p"}).label == "p"
