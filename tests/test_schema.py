"""The JSON input schema (runtime/sites/reader.py): every site form describes the curve it says
(checked against hand-derived equations and points sampled on the curve), and every malformed
entry gives one line naming it, 0-based."""
from __future__ import annotations

import json
import math
from fractions import Fraction

import pytest
from hypothesis import given, settings, strategies as st

from curvedvoronoi.runtime.predicates.circles import Circle, Point
from curvedvoronoi.runtime.sites.conic import Conic
from curvedvoronoi.runtime.sites.reader import (SITES_SCHEMA, parse_site, read_sites, site_key, site_to_json,
                                            sites_from_document)


def one(entry):
    return sites_from_document({"sites": [entry]}, "in.json")[0]


def proportional(u, v) -> bool:
    u, v = [Fraction(x) for x in u], [Fraction(x) for x in v]
    k = next(i for i, x in enumerate(u) if x != 0)
    return v[k] != 0 and all(x * v[k] == y * u[k] for x, y in zip(u, v))


# ----------------------------------------------------------------------------- the forms

def test_point_and_circle_forms():
    p = one({"point": [1, "2/3"]})
    assert isinstance(p, Point) and (Fraction(str(p.x)), Fraction(str(p.y))) == (1, Fraction(2, 3))
    c = one({"circle": {"centre": [1, 2], "radius": "3/2"}})
    assert isinstance(c, Circle) and Fraction(str(c.radius_squared)) == Fraction(9, 4)
    c2 = one({"circle": {"centre": [1, 2], "radius_squared": "9/4"}})
    assert site_key(c) == site_key(c2)
    # the same circle by coefficients: (x-1)² + (y-2)² = 9/4  <=>  4x² + 4y² - 8x - 16y + 11 = 0
    c3 = one({"coefficients": [4, 0, 4, -8, -16, 11]})
    assert c3.kind == "circle" and site_key(c3) == site_key(c)
    assert isinstance(one({"circle": {"centre": [0, 0], "radius": 0}}), Point)


def test_ellipse_with_rational_rotation_is_the_hand_derived_equation():
    # X = (3x + 4y)/5, Y = (-4x + 3y)/5, X²/4 + Y² = 1  <=>  73x² - 72xy + 52y² - 100 = 0
    e = one({"ellipse": {"centre": [0, 0], "axes": [2, 1], "rotation": {"cos": "3/5", "sin": "4/5"}}})
    assert proportional(e.coefficients, [73, -72, 52, 0, 0, -100])


def test_rotation_in_degrees_multiples_of_90_are_exact():
    a = one({"ellipse": {"centre": [1, 2], "axes": [3, 1], "rotation": 90}})
    b = one({"ellipse": {"centre": [1, 2], "axes": [1, 3]}})
    assert a == b and all(Fraction(v).denominator == 1 for v in a.coefficients)
    h = one({"hyperbola": {"centre": [0, 0], "axes": [2, 1], "rotation": 180}})
    assert proportional(h.coefficients, [1, 0, -4, 0, 0, -4])          # x²/4 - y² = 1


def test_parabola_form():
    # vertex (1, 0), p = 2, opening towards +y (rotation 90°): x' = x - 1, (x')² = 4 y
    par = one({"parabola": {"vertex": [1, 0], "p": 2, "rotation": 90}})
    assert par.kind == "parabola" and proportional(par.coefficients, [1, 0, 0, -2, -4, 1])


def decimal(lo, hi):
    return st.integers(lo * 100, hi * 100).map(lambda k: k / 100)


@settings(max_examples=40)
@given(decimal(-180, 180), decimal(1, 5), decimal(1, 5), decimal(-10, 10), decimal(-10, 10), decimal(0, 7))
def test_ellipse_in_degrees_passes_through_its_parametrised_points(deg, A, B, cx, cy, t):
    e = one({"ellipse": {"centre": [cx, cy], "axes": [A, B], "rotation": deg}})
    th = math.radians(deg)
    X, Y = A * math.cos(t), B * math.sin(t)
    x, y = cx + X * math.cos(th) - Y * math.sin(th), cy + X * math.sin(th) + Y * math.cos(th)
    a, b, c, d, f_, g = (float(v) for v in e.normalized_coefficients)   # max |coefficient| in [1, 2)
    value = a * x * x + b * x * y + c * y * y + d * x + f_ * y + g
    assert abs(value) <= 1e-9 * (1 + abs(x) + abs(y)) ** 2


@settings(max_examples=40)
@given(st.integers(1, 9), st.integers(1, 9), st.integers(-5, 5), st.integers(-5, 5))
def test_exact_hyperbola_contains_its_rational_points(m, n, a, b):
    # rotation from the Pythagorean triple (m² - n², 2mn, m² + n²), axes (2, 1);
    # the rational point X = 2(1 + s²)/(1 - s²), Y = 2s/(1 - s²) with s = 1/3 satisfies X²/4 - Y² = 1
    if m == n:
        return
    h2 = m * m + n * n
    cs, sn = Fraction(m * m - n * n, h2), Fraction(2 * m * n, h2)
    h = one({"hyperbola": {"centre": [a, b], "axes": [2, 1],
                           "rotation": {"cos": str(cs), "sin": str(sn)}}})
    s = Fraction(1, 3)
    X, Y = 2 * (1 + s * s) / (1 - s * s), 2 * s / (1 - s * s)
    assert X * X / 4 - Y * Y == 1
    x, y = a + cs * X - sn * Y, b + sn * X + cs * Y
    assert h(x, y) == 0


@pytest.mark.parametrize("site", [Point("1/3", 2), Circle.from_radius(1, 2, "5/7"), Circle(0, 0, 2),
                                  Conic.parabola(vertex=(1, 2), p=3, rotation=("3/5", "-4/5"))])
def test_site_to_json_reads_back_to_the_same_curve(site):
    back = parse_site(json.loads(json.dumps(site_to_json(site))))
    assert site_key(back) == site_key(site)


def test_old_conics_key_and_example_files_still_read():
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    sites = read_sites(str(root / "examples" / "four_ellipses.json"), expected=4)
    assert [s.kind for s in sites] == ["ellipse"] * 4
    assert len(read_sites(str(root / "runtime" / "data" / "example_sites.json"))) == 9


# ----------------------------------------------------------------------------- messages

@pytest.mark.parametrize("doc, message", [
    ({"sites": [{"point": [0, 0]}, {"point": [1, 0]}, {"point": [0, 1]},
                {"circle": {"centre": [1, 2], "radius": -1}}]},
     "sites[3].circle.radius: -1 is less than the minimum of 0"),
    ({"sites": [{"circle": {"centre": [1, 2], "radius": "-1"}}]}, "sites[0].circle.radius: -1 is less than"),
    ({"sites": [{"point": [0, "a"]}]}, "sites[0].point[1]: 'a' is not a rational number"),
    ({"sites": [{"elipse": {}}]}, "sites[0]: unknown key 'elipse'"),
    ({"sites": [{}]}, "sites[0]: needs one of 'point', 'circle'"),
    ({"sites": [{"point": [0, 1], "circle": {"centre": [0, 0], "radius": 1}}]}, "sites[0]: give only one of"),
    ({"sites": [{"coefficients": [1, 2, 3]}]}, "sites[0].coefficients: needs 6 coefficients"),
    ({"sites": [{"ellipse": {"centre": [0, 0], "axes": [2, 0]}}]}, "sites[0].ellipse.axes[1]: 0 must be > 0"),
    ({"sites": [{"ellipse": {"centre": [0, 0], "axes": [2, 1], "rotation": "x"}}]},
     "sites[0].ellipse.rotation: rotation must be an angle in degrees"),
    ({"sites": [{"circle": {"centre": [0, 0]}}]}, "sites[0].circle: needs one of 'radius', 'radius_squared'"),
    ({"sites": []}, "sites: the list is empty"),
    ({"site": []}, 'expected an object {"sites": [...]}'),
    ({"conics": [{"coefficients": [1, 0, 1, 0, 0, 1]}]}, "conics[0]: imaginary ellipse"),
    ({"sites": [{"point": [0, 0]}, {"coefficients": [1, 0, 1, 0, 0, 1]}]}, "sites[1]: imaginary ellipse"),
    ({"sites": [{"point": [0, 0]}, {"point": [0, 0.0]}]}, "site 1 is the same curve as site 0"),
    ({"sites": [{"coefficients": [1, 0, 1, 0, 0, -1]}, {"circle": {"centre": [0, 0], "radius": 1}}]},
     "site 1 is the same curve as site 0"),
    ({"sites": [{"coefficients": [1e300, 0, 1, 0, 0, -1]}]}, "sites[0]: ellipse size 1e-150"),
    ({"sites": [{"ellipse": {"centre": [1e200, 0], "axes": [2, 1]}}]}, "sites[0]: ellipse centre x = 1e+200"),
])
def test_bad_entries_are_named_in_one_line(doc, message):
    with pytest.raises(ValueError) as exc:
        sites_from_document(doc, "in.json")
    text = str(exc.value)
    assert text.startswith("in.json: ") and message in text and "\n" not in text


def test_the_schema_itself_is_a_valid_draft_2020_12_schema():
    import jsonschema

    jsonschema.Draft202012Validator.check_schema(SITES_SCHEMA)
