"""The guides of several edges split together (runtime.voronoi.verify.bisector_guide.adapt_many) are
split exactly as each alone: the flat pass computes every value row by row, and each guide keeps its
own stopping rule (no split left, its node cap, its rounds).  Checked on the bisectors of ellipse
pairs with different caps, rounds and end widths, batched in both orders; and each split guide's new
nodes lie on the bisector (|d_i − d_j| tiny next to the distances, dense float check)."""
from __future__ import annotations

from fractions import Fraction as F

import numpy as np
import pytest

from curvedvoronoi.runtime.sites.conic import Conic
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify.bisector_guide import AdaptJob, ProjectJob, adapt, adapt_many, project_many
from curvedvoronoi.runtime.voronoi.verify.site_table import SiteTable, run_lockstep


@pytest.fixture(scope="module")
def table():
    sites = [Conic.ellipse(centre=(0, 0), axes=(2, 1)),
             Conic.ellipse(centre=(7, 0), axes=(F(5, 2), F(3, 4)), rotation=(F(3, 5), F(4, 5))),
             Conic.ellipse(centre=(3, 6), axes=(F(3, 2), 1), rotation=(F(5, 13), F(12, 13)))]
    return SiteTable([site_geometry(s) for s in sites], 16.0)


JOBS = [  # (guide, pair, frac, tol, rounds, cap, ends)
    (np.array([[3.4, -6.0], [3.6, 0.0], [3.2, 7.0]]), (0, 1), 0.1, 1e-3, 12, 4000, (None, None)),
    (np.array([[-4.0, 3.0], [6.0, 2.0]]), (0, 2), 0.1, 1e-4, 12, 12, (None, 1e-5)),
    (np.array([[4.0, 2.0], [9.0, 5.0], [12.0, 7.0]]), (1, 2), 0.02, 1e-4, 3, 4000, (1e-4, None)),
    (np.array([[3.5, -1.0], [3.5, 1.0]]), (0, 1), 1.0, 1e-2, 12, 4000, (None, None)),
]


def _run(table, jobs):
    gens = [adapt(S, pair, frac, tol, 16.0, rounds, cap, ends) for S, pair, frac, tol, rounds, cap, ends in jobs]
    return run_lockstep(gens, table, {AdaptJob: adapt_many, ProjectJob: project_many})


def test_guides_split_together_are_split_as_each_alone(table):
    alone = [_run(table, [jb])[0] for jb in JOBS]
    for order in (JOBS, JOBS[::-1]):
        together = _run(table, order)
        if order is not JOBS:
            together = together[::-1]
        for a, b in zip(alone, together):
            assert a.shape == b.shape and np.array_equal(a, b)
    # the caps and the rounds bind: the capped guide stays within 12 nodes, the others were split
    assert len(alone[1]) <= 12
    assert len(alone[0]) > len(JOBS[0][0]) and len(alone[2]) > len(JOBS[2][0])


def test_the_inserted_nodes_lie_on_the_bisector(table):
    for (S, pair, *_), out in zip(JOBS, _run(table, JOBS)):
        new = np.array([p for p in out if not any(np.array_equal(p, q) for q in S)])
        if not len(new):
            continue
        g = [table.geoms[k] for k in pair]
        for q in new:
            lo_i, hi_i = g[0].distance_bounds(q)
            lo_j, hi_j = g[1].distance_bounds(q)
            assert abs(0.5 * (lo_i + hi_i) - 0.5 * (lo_j + hi_j)) <= 1e-9 * (1 + hi_i)


def test_narrow_end_widths_split_the_end_segments_further(table):
    S0 = np.array([[3.4, -6.0], [3.6, 0.0], [3.2, 7.0]])
    S, = _run(table, [(S0, (0, 1), 0.1, 1e-3, 12, 4000, (None, None))])
    S = S[1:-1]                  # the inserted nodes: a guide on the bisector, ends included
    free, narrow = _run(table, [(S, (0, 1), 0.1, 1e-3, 12, 4000, (None, None)),
                                (S, (0, 1), 0.1, 1e-3, 12, 4000, (1e-9, 1e-9))])
    # the wanted half-width at an end node is capped by its end width: the segments next to the
    # ends are split further, the guide already fine for the free ends is left as it is
    first = lambda P: float(np.hypot(*(P[1] - P[0])))
    assert np.array_equal(free, S)
    assert len(narrow) > len(free) and first(narrow) < first(free)


def test_midpoints_left_unprojected_are_within_half_the_width(table):
    """``_midpoints`` projects only the segments whose end tangents leave room for a split: on the
    nodes of a fine guide of each pair's bisector (float Newton projections), every segment it
    leaves has its projected midpoint (computed here for all) within tmin/2 of the chord, and it
    does leave most of them (the test is not vacuous); a bent segment is projected."""
    from curvedvoronoi.runtime.voronoi.verify.bisector_guide import _midpoints, project_rows
    from curvedvoronoi.runtime.voronoi.verify.strips import evaluate_rows
    rng = np.random.default_rng(5)
    skipped = 0
    for (S0, pair, *_rest) in JOBS[:3]:
        t = np.sort(rng.uniform(0, 1, 60))
        P = S0[0] + t[:, None] * (S0[-1] - S0[0])
        d = S0[-1] - S0[0]
        X, _ = project_rows(table, P, np.repeat(d[None, :], len(P), 0), np.full(len(P), pair[0]),
                            np.full(len(P), pair[1]))
        XX = np.concatenate([X, X])
        V = evaluate_rows(table, XX, np.repeat(pair, len(X)))
        G = (XX - V.F) / V.d[:, None]
        D = G[:len(X)] - G[len(X):]
        U = D / np.hypot(*D.T)[:, None]
        A, B = X[:-1], X[1:]
        I, J = np.full(len(A), pair[0]), np.full(len(A), pair[1])
        for tmin in (1e-6, 1e-4, 1e-2):
            tm = np.full(len(A), tmin)
            Mn, dev = _midpoints(table, A, B, I, J, U[:-1], U[1:], tm)
            _, true_dev = project_rows(table, 0.5 * (A + B), B - A, I, J)
            left = dev == 0
            assert (true_dev[left] <= 0.5 * tmin * (1 + 1e-6) + 1e-12).all()
            assert np.array_equal(Mn[left], 0.5 * (A + B)[left])
            skipped += left.sum()
            bent = true_dev > tmin
            assert not (left & bent).any()
    assert skipped > 60
