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
