"""Completeness of a certified vertex list (runtime/certify/complete.py,
``completeness_with_vertices``) when a certificate's box is looser than the solution's enclosure.

A certificate box is any proved enclosure of its vertex: widening it (here by ±10⁻¹⁰ in x, y and R)
keeps it an enclosure of the same vertex, so the vertex list is exactly as complete as before.  The
scene is the validation set's first "mixed" case with three true vertices (the vertex list of the
validation data, built independently of the certification)."""
from __future__ import annotations

import dataclasses
import json
from fractions import Fraction

from flint import arb

from curvedvoronoi.runtime.certify.complete import completeness_with_vertices
from curvedvoronoi.runtime.certify.conflicts import certify_vertex
from curvedvoronoi.runtime.sites.conic import Conic
from curvedvoronoi.runtime.solve.vertices import generalised_vertices
from curvedvoronoi.runtime.validation import required_cases_path


def test_a_looser_certificate_box_still_matches_its_solution():
    """Each of the three validation vertices is certified; with every certificate box widened by
    ±10⁻¹⁰ the boxes no longer lie inside the solutions' enclosures but overlap them, and the list is
    still proved complete (the overlap is closed by Krawczyk's test on a box holding both, which
    holds one zero of the offset system), without any retightening."""
    cases = json.loads(required_cases_path().read_text())["cases"]
    case = next(c for c in cases if c["group"] == "mixed" and len(c["vertices"]) == 3)
    c1, c2, c3, c4 = [Conic.from_coefficients(*e["coefficients"]) for e in case["conics"]]
    sol = generalised_vertices(c1, c2, c3)
    certs = [certify_vertex(c1, c2, c3, v["x"], v["y"], Fraction(v["radius"]) ** 2, c4) for v in case["vertices"]]
    assert all(c.proven and c.true_vertex for c in certs)
    loose = [dataclasses.replace(c, box=tuple(b + arb(0, 1e-10) for b in c.box)) for c in certs]
    ok, note = completeness_with_vertices(c1, c2, c3, sol.points, sol.info.expected, loose, retighten=None)
    assert ok, note
