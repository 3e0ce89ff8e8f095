"""The sites a local insertion or deletion of circles proves its new parts against
(runtime.voronoi.insertion, step 3 of the module docstring) contain every site that can reach them.

With the one disc around the changed part (centre X0 the mean of the vertices handed to the proof,
forced here for every update), the proofs must see every site whose disc meets the disc of centre
X0 and radius |q − X0| + d_i(q) for every point q of a new bounded arc (d_i(q) the radius of the
empty circle of q, which that disc contains) and for every vertex.  Checked against brute force
over all sites, with the points q on the exact bisector (closed form, thesis §3.1: a hyperbola
branch between the parameters of the edge's end vertices), after insertions and deletions.
"""
from __future__ import annotations

import random
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).with_name("cgal")))
import cgal_peer  # noqa: E402

import curvedvoronoi as cv  # noqa: E402
from curvedvoronoi.runtime.voronoi import insertion  # noqa: E402
from curvedvoronoi.runtime.voronoi.verify.edges import CircleTable, bisector  # noqa: E402


def _key(s):
    return (float(s.cx), float(s.cy), float(s.r2))


def _disc(s):
    return float(s.cx), float(s.cy), float(s.r2) ** 0.5


@pytest.mark.parametrize("seed", [1, 2])
def test_the_proofs_see_every_site_in_the_disc_of_the_changed_part(monkeypatch, seed):
    sc = cgal_peer.random_disjoint_circles(260, seed)
    d = cv.voronoi(sc[:250])
    monkeypatch.setattr(insertion, "ONE_DISC_SITES", 10 ** 9)
    calls = []
    real = insertion.prove_vertices

    def spy(sub, sites, geoms, table, problems, *a, **k):
        calls.append(([_key(s) for s in sites], [(v.x, v.y, v.radius) for v in sub.vertices],
                      [(e.sites, e.ends, {v.id: v for v in sub.vertices}) for e in sub.edges if None not in e.ends]))
        return real(sub, sites, geoms, table, problems, *a, **k)

    monkeypatch.setattr(insertion, "prove_vertices", spy)
    rng = random.Random(seed)
    checked = 0
    for k, c in enumerate(sc[250:]):
        for op in ("insert", "delete"):
            calls.clear()
            if op == "insert":
                d = d.insert(c, inplace=k > 0)
            else:
                d = d.delete_site(rng.randrange(len(d.sites)), renumber="last", inplace=True)
            assert d.certified, d.problems[:3]
            everyone = np.array([_disc(s) for s in d.sites])
            for keys, V, E in calls[:1]:            # the proof of the changed bounded part
                seen = set(keys)
                X0 = np.mean([[x, y] for x, y, _ in V], axis=0)
                reach = max(np.hypot(x - X0[0], y - X0[1]) + r for x, y, r in V)
                G = np.array([(cx, cy, r2 ** 0.5) for cx, cy, r2 in keys])
                table = CircleTable.from_arrays(G[:, :2], G[:, 2])
                for (i, j), ends, verts in E:
                    bis = bisector(table, i, j)
                    P = np.array([[verts[w].x, verts[w].y] for w in ends])
                    u0, u1 = bis.param(P)
                    Q = bis.point(np.linspace(u0, u1, 200))
                    r = np.abs(np.hypot(*(Q - G[i, :2]).T) - G[i, 2])
                    reach = max(reach, float((np.hypot(*(Q - X0).T) + r).max()))
                gap = np.hypot(*(everyone[:, :2] - X0).T) - everyone[:, 2]
                need = {_key(d.sites[t]) for t in np.nonzero(gap < reach * (1 - 1e-6))[0]}
                assert need <= seen, (op, len(need - seen))
                checked += 1
    assert checked >= 15
