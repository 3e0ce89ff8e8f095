"""The candidates of the emptiness test of conic vertices (runtime/voronoi/verify/vertices.py,
``_box_candidates``): every (point, site) pair whose bounding box comes within the reach of the
point must be listed — a site left out is never checked against the vertex's empty circle.
Compared with the brute-force distance from each point to each box (numpy over all pairs, no
k-d tree), on random boxes of mixed sizes, with unbounded boxes (hyperbolas, parabolas)."""
from __future__ import annotations

import numpy as np
from hypothesis import given, settings, strategies as st

from curvedvoronoi.runtime.voronoi.verify.vertices import _box_candidates


def _brute(boxes, X, reach):
    out = set()
    for r, (x, y) in enumerate(X):
        for k, (x0, y0, x1, y1) in enumerate(boxes):
            if not np.isfinite([x0, y0, x1, y1]).all():
                out.add((r, k))
                continue
            dx, dy = max(x0 - x, x - x1, 0.0), max(y0 - y, y - y1, 0.0)
            if np.hypot(dx, dy) <= reach[r]:
                out.add((r, k))
    return out


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2 ** 32 - 1), st.integers(1, 40), st.integers(1, 30), st.booleans())
def test_the_candidates_are_every_box_within_reach(seed, n, m, unbounded):
    rng = np.random.default_rng(seed)
    lo = rng.uniform(-100, 100, (n, 2))
    size = rng.exponential(5.0, (n, 2)) * rng.choice([0.01, 1.0, 20.0], (n, 1))
    boxes = np.hstack([lo, lo + size])
    if unbounded:
        boxes[rng.integers(n), rng.integers(4)] = rng.choice([-np.inf, np.inf])
    X = rng.uniform(-120, 120, (m, 2))
    reach = rng.exponential(15.0, m)
    want = _brute(boxes, X, reach)
    rows, ks = _box_candidates(boxes, X, reach)
    got = set(zip(rows.tolist(), ks.tolist()))
    assert want <= got
    assert len(got) == len(rows)                 # no pair twice
    # and no far pair: listed boxes are within the reach up to 1e-12
    for r, k in got - want:
        x0, y0, x1, y1 = boxes[k]
        d = np.hypot(max(x0 - X[r, 0], X[r, 0] - x1, 0.0), max(y0 - X[r, 1], X[r, 1] - y1, 0.0))
        assert d <= reach[r] * (1 + 1e-11)
