"""The verifier's circle table (runtime/voronoi/verify/edges.py CircleTable) with a few big
circles among many small ones: its searches list the big circles one by one and widen the k-d tree
only by the largest of the other radii, and still find every site they must (against brute force),
and the disjointness check finds a big circle meeting a small one (runtime/voronoi/verify/closure.py)."""
from __future__ import annotations

import numpy as np

from curvedvoronoi.runtime.voronoi.verify.closure import circles_disjoint
from curvedvoronoi.runtime.voronoi.verify.edges import BIG_SITES, CircleTable


def _scene(seed=0, n=3000, big=5):
    rng = np.random.default_rng(seed)
    C = rng.uniform(0, 1000, (n, 2))
    R = rng.uniform(0.01, 0.2, n)
    R[:big] = rng.uniform(50, 120, big)           # a few big circles
    return C, R


def test_near_lists_every_site_within_reach_and_few_others():
    C, R = _scene()
    t = CircleTable.from_arrays(C, R)
    assert 0 < len(t.big) <= BIG_SITES and t.r_small <= 0.2 and set(range(5)) <= set(t.big.tolist())
    Q = np.random.default_rng(1).uniform(-50, 1050, (400, 2))
    reach = np.random.default_rng(2).uniform(0, 30, 400)
    rows, ks = t.near(Q, reach)
    got = set(zip(rows.tolist(), ks.tolist()))
    assert len(got) == len(rows)                           # no pair twice
    # brute force: every site whose disc comes within reach of q (|q - c| - rho <= reach) is listed
    D = np.hypot(Q[:, None, 0] - C[:, 0], Q[:, None, 1] - C[:, 1]) - R
    need = set(zip(*np.nonzero(D <= reach[:, None])))
    assert need <= got
    # and the listing is not widened by the big radii (120 here): a small site listed is within
    # reach + r_small of q, a big one within reach (rounding aside)
    big = np.isin(ks, t.big)
    assert (D[rows, ks][~big] <= reach[rows][~big] + t.r_small + 1e-9).all()
    assert (D[rows, ks][big] <= reach[rows][big] + 1e-9).all()


def test_a_big_circle_meeting_a_small_one_is_found():
    # a clean scene: small circles on a grid far from one big circle
    g = np.array([(x, y) for x in range(0, 1000, 10) for y in range(0, 1000, 10)], float)
    C = np.vstack([[[2000.0, 2000.0]], g])
    R = np.concatenate([[100.0], np.full(len(g), 0.5)])
    t = CircleTable.from_arrays(C, R)
    assert list(t.big) == [0]
    assert circles_disjoint(t, []) is True
    # a small circle moved onto the big circle's rim: found, named by its index
    C2, probs = C.copy(), []
    C2[len(g)] = [2000.0 + 100.2, 2000.0]              # 100.2 - 0.5 < 100 + ... : meets the rim
    assert circles_disjoint(CircleTable.from_arrays(C2, R), probs) is False
    assert f"sites 0 and {len(g)}" in str(probs[0])
    # two big circles meeting each other (each beyond the other's tree query R + r_small): found
    C4 = np.vstack([C, [[2000.0 + 180.0, 2000.0]]])
    R4 = np.concatenate([R, [90.0]])
    probs = []
    assert circles_disjoint(CircleTable.from_arrays(C4, R4), probs) is False
    assert f"sites 0 and {len(C)}" in str(probs[0])
    # two small circles crossing, neither centre inside the other disc (centres 0.9 apart, radii 0.5)
    C5 = C.copy()
    C5[2] = C5[1] + [0.9, 0.0]
    probs = []
    assert circles_disjoint(CircleTable.from_arrays(C5, R), probs) is False
    assert "sites 1 and 2" in str(probs[0])
    # a small circle just outside (gap 1e-6 of the scale): disjoint
    C3 = C.copy()
    C3[len(g)] = [2000.0 + 100.5 + 1e-3, 2000.0]
    assert circles_disjoint(CircleTable.from_arrays(C3, R), []) is True
