"""The verifier's row-wise evaluations in bounded calls (runtime/voronoi/verify/strips.py:
``evaluate_rows``, ``gap_rows``; used by strips.prove_strips_many and tail's sector proofs).

Every row of :meth:`SiteTable.evaluate` and of the second-order bounds of distance_gap depends on
that row's data alone (the foot-point iteration keeps converged rows out of its active set; the
bounds are elementwise), so cutting the rows into calls of any size must give the very same
floats, and the certificate the very same verdicts.  Checked here with tiny calls (3 to 7 rows)
against one call: bit-for-bit equality of every field on random (point, site) rows of random
ellipse, circle and point scenes (outside, inside and near the sites), and equal certificates
(ok, per-vertex and per-edge flags, problem lines) of random ellipse diagrams.  The tiny calls do
happen: the table counts its calls.
"""
from __future__ import annotations

import numpy as np
import pytest

from scenes import random_disjoint_circles, random_ellipses

import curvedvoronoi as cv
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify import certificate, strips
from curvedvoronoi.runtime.voronoi.verify.distance_gap import bisector_gap_lower, gap_lower
from curvedvoronoi.runtime.voronoi.verify.site_table import SiteTable
from curvedvoronoi.runtime.voronoi.verify.strips import evaluate_rows, gap_rows

FIELDS = ("lo", "hi", "F", "d", "base", "inner", "reach", "sep", "K")


def rows_near(table, m, rng):
    """m rows (Q, k): Q within a few site sizes of the box centre of site k (inside, on and
    outside the sites), k random."""
    K = rng.integers(0, table.n, m)
    bx = table.boxes[K]
    ctr, half = 0.5 * (bx[:, :2] + bx[:, 2:]), 0.5 * (bx[:, 2:] - bx[:, :2])
    Q = ctr + rng.uniform(-4, 4, (m, 2)) * np.maximum(half, 0.5)
    return Q, K


def same(V, W):
    for f in FIELDS:
        a, b = getattr(V, f), getattr(W, f)
        assert a.shape == b.shape and a.dtype == b.dtype, f
        assert np.array_equal(a, b, equal_nan=a.dtype.kind == "f"), f


@pytest.mark.parametrize("seed", [1, 2, 3])
@pytest.mark.parametrize("rows", [3, 7])
def test_evaluate_rows_equals_one_call(seed, rows):
    # ellipses, circles and a point (the table evaluates a site alone: they may overlap here)
    sites = (list(random_ellipses(12, seed)) + [cv.Circle(*c) for c in random_disjoint_circles(6, seed)]
             + [cv.Point(0.25, -1.5)])
    table = SiteTable([site_geometry(s) for s in sites], 40.0)
    rng = np.random.default_rng(seed)
    Q, K = rows_near(table, 101, rng)
    whole = table.evaluate(Q, K)
    c0 = table.calls
    parts = evaluate_rows(table, Q, K, rows=rows)
    assert table.calls - c0 == -(-len(K) // rows)
    same(whole, parts)
    # the second-order gaps of (T2''), row for row: k against i, and on the bisector of i and j
    K2, K3 = rng.integers(0, table.n, len(K)), rng.integers(0, table.n, len(K))
    Vk, Vj = table.evaluate(Q, K2), table.evaluate(Q, K3)
    R = rng.uniform(0.0, 2.0, len(K))
    g1 = gap_lower(Q, Vk, whole, R, 40.0)
    g2 = bisector_gap_lower(Q, Vk, whole, Vj, R, 40.0)
    assert np.array_equal(g1, gap_rows(gap_lower, Q, (Vk, whole), R, 40.0, rows=rows))
    assert np.array_equal(g2, gap_rows(bisector_gap_lower, Q, (Vk, whole, Vj), R, 40.0, rows=rows))
    assert np.isfinite(g1).any() and np.isfinite(g2).any()     # the bounds did prove something


def reports(sites, monkeypatch, rows):
    """The certificate of the built diagram with calls of at most ``rows`` rows, and the number of
    table calls."""
    from curvedvoronoi.runtime.voronoi.verify import site_table

    monkeypatch.setattr(strips, "ROWS_PER_CALL", rows)
    calls = [0]
    ev = site_table.SiteTable.evaluate

    def counted(self, Q, K):
        calls[0] += 1
        return ev(self, Q, K)

    monkeypatch.setattr(site_table.SiteTable, "evaluate", counted)
    d = cv.voronoi(sites, certify=False, progress=False)
    r = certificate.verify(d, progress=False)
    monkeypatch.undo()
    return (bool(r.ok), list(r.vertices), list(r.edges), list(r.problems)), calls[0]


@pytest.mark.parametrize("seed", [1, pytest.param(4, marks=pytest.mark.slow)])
def test_certificate_verdicts_do_not_depend_on_the_call_size(seed, monkeypatch):
    sites = random_ellipses(25, seed)
    one, c1 = reports(sites, monkeypatch, 10 ** 9)
    tiny, c2 = reports(sites, monkeypatch, 5)
    assert c2 > c1 + 50          # the chunked route ran
    assert tiny == one
    assert any(one[2])           # edges were proved (the comparison is not between two failures)
