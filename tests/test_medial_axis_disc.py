"""The medial axis of a disc is its centre (closed form: the distance to the circle, ρ − |q − c|,
has its only maximum there, and every other point has one nearest boundary point).  The Voronoi
diagram of the circle's two half arcs has no vertex there, so the medial axis has no edge and one
point, which must still be reported, with the largest inscribed circle the disc itself."""
from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

import curvedvoronoi as cv


@pytest.mark.parametrize("cx, cy, rho", [(0, 0, 10), (3, -2, Fraction(5, 2)), (500000, 4649776, 30)])
def test_the_medial_axis_of_a_disc_is_its_centre(cx, cy, rho):
    m = cv.medial_axis(cv.Circle.from_radius(cx, cy, rho))
    assert m.certified and m.edges == []
    assert [(v.x, v.y, v.radius) for v in m.vertices] == [(float(cx), float(cy), float(rho))]
    assert m.largest_inscribed_circle == (float(cx), float(cy), float(rho))
    # the reference: the maximum of ρ − |q − c| over a grid through the disc is at the centre
    g = np.linspace(-float(rho), float(rho), 41)
    X, Y = np.meshgrid(float(cx) + g, float(cy) + g)
    clearance = float(rho) - np.hypot(X - float(cx), Y - float(cy))
    k = np.unravel_index(np.argmax(clearance), clearance.shape)
    assert (X[k], Y[k]) == (float(cx), float(cy))
    points = [f for f in m.to_geojson()["features"] if f["geometry"]["type"] == "Point"
              and str(f.get("id", "")).startswith("medial-vertex")]
    assert len(points) == 1 and m.to_shapely().is_empty


def test_a_disc_with_a_hole_has_edges_and_no_extra_point():
    """Annulus of radii 10 and 4: the medial axis is the circle of radius 7 (edges only)."""
    m = cv.medial_axis(cv.Circle.from_radius(0, 0, 10), holes=[cv.Circle.from_radius(0, 0, 4)])
    assert m.certified and m.edges
    for e in m.edges:
        assert np.allclose(np.hypot(e.polyline[:, 0], e.polyline[:, 1]), 7, atol=e.tolerance + 1e-9)
        assert np.allclose(e.radius, 3, atol=e.tolerance + 1e-9)
    assert all(v.id >= 0 for v in m.vertices)
