"""The even–odd test of the medial axis (runtime/segments/medial_axis._inside) goes by blocks of
probe rows so that its m × k arrays stay small (the gear with 102 bulge arcs: 7 802 probes against
28 012 chords took 3.7 GB at once).  The blocks must not change an answer: the same rows with
block sizes from one row to all of them, against shapely's point-in-polygon on random polygons
with holes (points off the boundary)."""
from __future__ import annotations

import numpy as np
import shapely

from curvedvoronoi.runtime.segments.medial_axis import _inside


def _chords(poly):
    rings = [poly.exterior] + list(poly.interiors)
    out = []
    for r in rings:
        c = np.asarray(r.coords)
        out.extend(zip(c[:-1], c[1:]))
    return np.array(out, float).reshape(-1, 2, 2)


def test_blocks_give_the_same_parity_as_shapely():
    rng = np.random.default_rng(4)
    for _ in range(20):
        outer = shapely.Point(0, 0).buffer(10, quad_segs=int(rng.integers(2, 12)))
        holes = [shapely.Point(*rng.uniform(-5, 5, 2)).buffer(rng.uniform(0.5, 2), quad_segs=3) for _ in range(3)]
        poly = outer.difference(shapely.union_all(holes))
        if poly.geom_type != "Polygon":
            continue
        Q = rng.uniform(-11, 11, size=(300, 2))
        far = shapely.distance(poly.boundary, shapely.points(Q)) > 1e-9
        Q = Q[far]
        want = shapely.contains_xy(poly, Q[:, 0], Q[:, 1])
        B = _chords(poly)
        for block in (1, 7, len(B), 5 * len(B) + 3, 1 << 22):
            assert (_inside(B, Q, block=block) == want).all()
