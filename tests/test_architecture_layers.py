"""The layers of docs/architecture.md and the "one of each" rule: the site kinds enumerated once
(runtime/sites/kinds.py) and agreeing with every geometry."""
from __future__ import annotations

import doctest

import pytest

from curvedvoronoi.runtime.predicates.circles import Circle
from curvedvoronoi.runtime.sites import kinds
from curvedvoronoi.runtime.sites.conic import Conic
from curvedvoronoi.runtime.sites.kinds import SiteKind
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry


def test_site_kinds_doctests():
    assert doctest.testmod(kinds).failed == 0


SITES = [
    (Circle(0, 0, 0), SiteKind.POINT),
    (Circle(1, 2, 4), SiteKind.CIRCLE),
    (Conic.from_coefficients(1, 0, 1, 0, 0, -4), SiteKind.CIRCLE),          # a circle given as a conic
    (Conic.ellipse(centre=(0, 0), axes=(3, 1)), SiteKind.ELLIPSE),
    (Conic.hyperbola(centre=(0, 0), axes=(1, 2)), SiteKind.HYPERBOLA),
    (Conic.parabola(vertex=(0, 0), p=1), SiteKind.PARABOLA),
]


@pytest.mark.parametrize("site, kind", SITES, ids=[k.label + str(i) for i, (_, k) in enumerate(SITES)])
def test_every_geometry_spells_its_kind_from_the_enumeration(site, kind):
    g = site_geometry(site)
    assert g.kind == kind.label and g.site_kind is kind
    assert g.bounded == kind.bounded == all(abs(v) < float("inf") for v in g.bounding_box())


def test_kind_codes_and_labels():
    # the codes the verifier's flat site table stores (0 point, 1 circle, 2 ellipse, 3 hyperbola,
    # 4 parabola) must not move: arrays written with them compare against the members
    assert [int(k) for k in SiteKind][:5] == [0, 1, 2, 3, 4]
    assert [k.label for k in SiteKind] == ["point", "circle", "ellipse", "hyperbola", "parabola", "segment", "arc"]
    assert all(SiteKind.of(k.label) is k and SiteKind.of(int(k)) is k for k in SiteKind)
    assert [k.label for k in SiteKind if k.circular] == ["point", "circle"]
    assert [k.label for k in SiteKind if not k.bounded] == ["hyperbola", "parabola"]
    with pytest.raises(ValueError, match="unknown site kind 'line'"):
        SiteKind.of("line")
