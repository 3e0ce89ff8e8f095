"""CircleTable.near (runtime.voronoi.verify.edges): the (point, site) pairs it lists contain every
site whose disc comes within the reach of the point, |q − c_k| − ρ_k ≤ reach, against brute force
over all pairs; for small tables (every pair tested) and large ones (the k-d tree widened by the
largest radius, the big circles one by one), with radii spread over four orders of magnitude."""
from __future__ import annotations

import numpy as np
import pytest

from curvedvoronoi.runtime.voronoi.verify.edges import SMALL_TABLE, CircleTable


@pytest.mark.parametrize("n,seed", [(12, 0), (SMALL_TABLE, 1), (SMALL_TABLE + 1, 2), (400, 3)])
def test_near_lists_every_site_within_reach(n, seed):
    rng = np.random.default_rng(seed)
    C = rng.uniform(-100, 100, (n, 2))
    R = np.exp(rng.uniform(np.log(0.01), np.log(30), n)) * (rng.random(n) > 0.2)
    table = CircleTable.from_arrays(C, R)
    Q = rng.uniform(-120, 120, (300, 2))
    reach = np.exp(rng.uniform(np.log(0.1), np.log(40), len(Q)))
    rows, cols = table.near(Q, reach)
    got = set(zip(rows.tolist(), cols.tolist()))
    gap = np.hypot(Q[:, None, 0] - C[None, :, 0], Q[:, None, 1] - C[None, :, 1]) - R[None, :]
    r, c = np.nonzero(gap <= reach[:, None] * (1 - 1e-9))
    want = set(zip(r.tolist(), c.tolist()))
    assert want, "the random data must give pairs within reach"
    assert want <= got, sorted(want - got)[:5]
