"""Generic root counts of the triple offset systems (generated/counts/root_counts.json).

* the artefact is what precompute.root_counts computes (deterministic, fixed seeds);
* the known counts (EEE 184, PPP 93, EPP 118; three circles 8, Apollonius) are reproduced;
* a non-generic member (two parabolas with parallel axes) has strictly fewer solutions: the
  samples must be generic, which is why rotations are distinct;
* the rigid-motion composition of the precompute is exact (offset vanishes at exact offset points).
(The comparison with the mixed volume and the null-space solver is in tests/test_vertices.py.)
"""
from __future__ import annotations

import json
import random
from fractions import Fraction as F

from curvedvoronoi.precompute.root_counts import (FAMILIES3, count_mod_p, member_offset, primitive,
                                                  root_counts_document)
from curvedvoronoi.runtime.artefacts import generated_dir, load_root_counts


def _docs():
    return {f: json.loads((generated_dir() / f"offsets/{f}.json").read_text()) for f in FAMILIES3}


def test_artefact_is_reproducible():
    root = generated_dir()
    assert root_counts_document(root / "offsets") == (root / "counts" / "root_counts.json").read_text()


def test_known_counts():
    n = load_root_counts()
    E, P, C = "ellipse", "parabola", "circle"
    assert n[(E, E, E)] == 184 and n[(P, P, P)] == 93 and n[(E, P, P)] == 118
    assert n[(C, C, C)] == 8          # Apollonius: 8 tangent circles of three circles (thesis §3.1)
    assert len(n) == 10


def test_parallel_axes_lose_solutions():
    docs = _docs()
    rot = (F(3, 5), F(4, 5))
    polys = [primitive(member_offset(docs["parabola"], {"p": p}, *rot, tx, ty))
             for p, tx, ty in ((F(1), F(0), F(0)), (F(1, 2), F(2), F(4)))]
    polys.append(primitive(member_offset(docs["parabola"], {"p": F(3, 4)}, F(5, 13), F(12, 13), F(-3), F(1))))
    assert count_mod_p(polys, 1073741827) < load_root_counts()[("parabola",) * 3]


def test_member_offset_is_exact():
    """Circle of radius 5/4 centred at (1/3, −2/7): points at distance d along a rational normal
    are on its offset with R = d²; the rotation must not matter for a circle."""
    doc = _docs()["circle"]
    o = member_offset(doc, {"rho": F(5, 4)}, F(8, 17), F(15, 17), F(1, 3), F(-2, 7))
    rnd = random.Random(3)
    for _ in range(3):
        d = F(rnd.randint(1, 9), 4)
        co, si = F(-5, 13), F(12, 13)
        x, y = F(1, 3) + (F(5, 4) + d) * co, F(-2, 7) + (F(5, 4) + d) * si
        assert sum(v * x ** i * y ** j * (d * d) ** k for (i, j, k), v in o.items()) == 0
    x, y = F(1, 3) + 2 * F(3, 5), F(-2, 7) + 2 * F(4, 5)
    assert sum(v * x ** i * y ** j for (i, j, k), v in o.items() if k == 0) != 0


def test_counts_are_proved_bounds_by_the_circle_space_mixed_volume():
    """Li–Wang: the mixed volume of the circle-space supports (origin added) bounds the isolated
    solutions in C³.  Recomputed here by the independent inclusion–exclusion formula
    (precompute.mixed.mixed_volume_ie, exact hulls) from the recorded supports: it equals the
    recorded mixed volume and msolve's count for every family triple, and is strictly smaller
    than the (x, y, R) mixed volume (the weighted frame has solutions at infinity)."""
    from curvedvoronoi.precompute.mixed import mixed_volume_ie
    from curvedvoronoi.runtime.artefacts import load_root_count_bounds

    mvs, supports = load_root_count_bounds()
    counts = load_root_counts()
    for fams, mv in mvs.items():
        assert mixed_volume_ie([sorted(supports[f]) for f in fams]) == mv == counts[fams], fams
    E = "ellipse"
    assert mvs[(E, E, E)] == 184
    # every support is a lattice set in the polytope {i + j + k ≤ 6, i + j + 2k ≤ 8} for the ellipse
    # family (total degree 6 in circle space, weighted degree 8 as in (x, y, R))
    assert all(i + j + k <= 6 and i + j + 2 * k <= 8 for i, j, k in supports[E])


def test_count_bound_refuses_a_member_outside_the_recorded_support(monkeypatch):
    """A conic whose circle-space support has a monomial the recorded family support lacks gets
    no bound, and completeness by counting is then not claimed (the verifier of the bound fails
    on corrupted data)."""
    from curvedvoronoi.runtime import artefacts
    from curvedvoronoi.runtime.certify import root_bound
    from curvedvoronoi.runtime.predicates.locator import demo_configuration

    c1, c2, c3, _ = demo_configuration()
    bound, note = root_bound.count_bound(c1, c2, c3)
    assert bound == 184, note
    mvs, supports = artefacts.load_root_count_bounds()
    poor = dict(supports)
    poor["ellipse"] = frozenset(supports["ellipse"] - {max(supports["ellipse"])})
    monkeypatch.setattr(artefacts, "load_root_count_bounds", lambda root=None: (mvs, poor))
    root_bound._bound.cache_clear()
    try:
        bound, note = root_bound.count_bound(c1, c2, c3)
        assert bound is None and "outside the recorded support" in note
    finally:
        root_bound._bound.cache_clear()
