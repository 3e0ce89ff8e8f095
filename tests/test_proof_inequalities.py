"""Hand-built cases on both sides of inequalities added to the verifier this session, each shown
to fail when the inequality is weakened by hand (see the session's closing note)."""
from __future__ import annotations

import copy
import math
from fractions import Fraction as F

import curvedvoronoi as cv
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry


def test_disc_comparison_of_tied_tails_is_decided_both_ways():
    """F(ρ, Δ, z) = √((z+ρ)² + Δ²) − ρ.  Far site: ρ = 100, |Δ| = 1; near site: ρ = 0, |δ| = 0.9.
    At z = 1 the far distance (≈ 1.005) is *smaller* than the near one (≈ 1.345): not proved.
    From z = 10⁶ on, Δ² > δ² wins: proved (computed here from the definition)."""
    from curvedvoronoi.runtime.voronoi.verify.tied_tail import _F_bounds_hold

    f = lambda rho, d, z: math.sqrt((z + rho) ** 2 + d * d) - rho          # noqa: E731
    assert f(100, 1, 1) < f(0, 0.9, 1)
    assert not _F_bounds_hold(F(100), F(1), F(0), F(9, 10), F(1))
    assert all(f(100, 1, z) > f(0, 0.9, z) for z in (1e6, 1e7))
    assert _F_bounds_hold(F(100), F(1), F(0), F(9, 10), F(10 ** 6))
    assert not _F_bounds_hold(F(1), F(1), F(1), F(1), F(10 ** 6))          # equal offsets: a tie


def _ends_for(d):
    """The proved ends at infinity of a certified circle diagram, as the accounting sees them."""
    from curvedvoronoi.runtime.voronoi.verify.edge_checks import check_edges
    from curvedvoronoi.runtime.voronoi.verify.edges import CircleTable
    from curvedvoronoi.runtime.voronoi.verify.vertices import prove_vertices

    geoms = [site_geometry(s) for s in d.sites]
    table = CircleTable(geoms)
    problems: list = []
    vinfo, vok = prove_vertices(d, d.sites, geoms, table, problems)
    _, ends, _ = check_edges(d, geoms, table, vinfo, vok, problems, {})
    return geoms, ends


def test_disc_hull_accounting_rejects_an_end_across_a_non_hull_side():
    """Circles (0, 0) r 1, (10, 0) r 1 and (5, −3) r 1: the lower hull goes 0 → 2 → 1, so the pair
    (0, 1) has only its upper end.  A second end of (0, 1) going down is refused."""
    from curvedvoronoi.runtime.voronoi.verify.hull_points import verify_accounting_discs

    d = cv.voronoi([(0, 0, 1), (10, 0, F(3, 2)), (5, -3, 1)])
    assert d.certified, d.problems
    geoms, ends = _ends_for(d)
    assert verify_accounting_discs(geoms, ends, []) is True
    up = next(t for t in ends if tuple(t[1]) == (0, 1))
    fake = (((up[0] + math.pi) % (2 * math.pi)), up[1], -up[2], 99)
    assert verify_accounting_discs(geoms, ends + [fake], []) is False


def test_a_listed_site_that_does_not_touch_the_circle_is_rejected():
    """Four equal circles on the circle of radius 5: one vertex of degree 4 at the origin.  Site 3
    moved outward by 10⁻⁹ no longer touches its empty circle, though the document still lists it."""
    d = cv.voronoi([(5, 0, 1), (0, 5, 1), (-5, 0, 1), (0, -5, 1)])
    assert d.certified and d.vertices[0].degree == 4
    doc = d.to_json()
    bad = copy.deepcopy(doc)
    bad["sites"][3] = {"circle": {"centre": ["0", str(F(-5) - F(1, 10 ** 9))], "radius": "1"}}
    cert = cv.verify(bad)
    assert not cert.ok and any("vertex 0" in p for p in cert.problems), cert.problems


def test_a_mirror_vertex_moved_along_its_mirror_is_rejected():
    """The degree-4 vertex of two mirror pairs of ellipses sits on x = 18 at an irrational height;
    moved along the mirror by 10⁻⁶, d_a − d_b no longer changes sign around it: not proved."""
    E = lambda x, y, a, b: cv.Conic.ellipse(centre=(x, y), axes=(a, b))      # noqa: E731
    d = cv.voronoi([E(12, 0, 2, 1), E(24, 0, 2, 1), E(12, 8, 3, 1), E(24, 8, 3, 1), E(18, 20, 2, 1)])
    assert d.certified, d.problems
    doc = d.to_json()
    v = next(x for x in doc["vertices"] if len(x["sites"]) == 4)
    v["y"] += 1e-6
    for e in doc["edges"]:
        for t, end in enumerate(e["ends"]):
            if end == v["id"]:
                e["polyline"][0 if t == 0 else -1][1] += 1e-6
    cert = cv.verify(doc)
    assert not cert.ok and any(f"vertex {v['id']}" in p for p in cert.problems), cert.problems
