"""Diagrams of fewer than two sites (the boundary of the verifier's domain).

With no site, or a single one, no two sites are ever equidistant nearest sites, so the Voronoi
diagram has no vertex and no edge (Aurenhammer & Klein, "Voronoi diagrams", §1: a Voronoi edge
separates the regions of two sites; one site's region is the whole plane).  A document stating
exactly that is correct and :func:`curvedvoronoi.runtime.voronoi.verify.certificate.verify` must
prove it, complete: there is no end at infinity to account for, so the accounting of the ends
(:func:`curvedvoronoi.runtime.voronoi.verify.closure.verify_accounting`, thesis §1.2) holds
vacuously.  A document that states an edge of a single site's diagram is wrong and is refused."""
from __future__ import annotations

import pytest

from curvedvoronoi.runtime.predicates.circles import Circle
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify.certificate import verify
from curvedvoronoi.runtime.voronoi.verify.closure import verify_accounting
from curvedvoronoi.runtime.voronoi.verify.edges import CircleTable


def _document(sites, edges=()):
    return {"format": "curvedvoronoi.diagram/2", "sites": list(sites), "vertices": [], "edges": list(edges)}


@pytest.mark.parametrize("sites", [
    [],
    [{"point": ["1", "2"]}],
    [{"circle": {"centre": ["1", "2"], "radius_squared": "9"}}],
], ids=["no site", "one point", "one circle"])
def test_the_empty_diagram_of_fewer_than_two_sites_is_proved(sites):
    cert = verify(_document(sites))
    assert cert.problems == []
    assert cert.ok and cert.complete
    assert list(cert.vertices) == [] and list(cert.edges) == []


def test_an_edge_in_the_diagram_of_one_site_is_refused():
    edge = {"id": 0, "sites": [0, 0], "ends": [None, None], "closed": False,
            "polyline": [[0.0, -8.0], [0.0, 8.0]], "tolerance": 1e-9, "certified": False}
    assert not verify(_document([{"point": ["1", "2"]}], [edge])).ok


def test_the_accounting_of_no_ends_holds_for_no_site_and_one_site():
    problems: list[str] = []
    assert verify_accounting(0, None, [], problems) is True
    assert verify_accounting(1, CircleTable([site_geometry(Circle.from_radius(1, 2, 3))]), [], problems) is True
    assert problems == []
