"""Krawczyk's test on float batches (runtime/certify/interval_newton.py, norm form with outward
rounding): the bounds b ≥ |Y F(m)| and Δ ≥ |I − Y M| hold against exact rational arithmetic, the
test proves a known simple zero and refuses a box holding two zeros, and the Apollonius vertices
of the diagram, proved through it, contain the exact vertex of thesis §3.1.3."""
from __future__ import annotations

import itertools
import math
from fractions import Fraction

import numpy as np
import pytest

from curvedvoronoi.runtime.certify.interval_newton import (
    abs_upper, float_contraction_bound, float_inverse, float_krawczyk_test, float_residual_bound, round_up)
from curvedvoronoi.runtime.predicates.circles import Circle, voronoi_vertices_circles
from curvedvoronoi.runtime.voronoi.apollonius_vertices import krawczyk_circles
from curvedvoronoi.runtime.voronoi.geometry import CircleGeometry
from curvedvoronoi.runtime.voronoi.site_arrays import SiteArrays

Q = Fraction


def exact_abs(z) -> Fraction:
    return abs(Q(z))


@pytest.mark.parametrize("seed", range(5))
def test_bounds_dominate_exact_arithmetic(seed):
    """Random real 3×3 batches with wide magnitudes and near-cancellation: the float bounds are
    at least the exact |Y F| and |I − Y M| for M at the corners of the Jacobian enclosure."""
    rng = np.random.default_rng(seed)
    n, k = 40, 3
    J = rng.normal(size=(n, k, k)) * 10.0 ** rng.integers(-8, 9, size=(n, 1, 1))
    Y, good = float_inverse(J)
    assert good.all()
    F = (rng.normal(size=(n, k)) * 1e-12) * 10.0 ** rng.integers(-30, 30, size=(n, 1))
    F_rad = np.abs(F) * 1e-3
    J_rad = np.abs(J) * 1e-9
    b = float_residual_bound(Y, F, F_rad)
    D = float_contraction_bound(Y, J, J_rad)
    for t in range(n):
        for i in range(k):
            # |Y F| is convex in F: its largest value on the box F ± F_rad is at a corner
            worst = max(abs(sum(Q(Y[t, i, j]) * (Q(F[t, j]) + sg[j] * Q(F_rad[t, j])) for j in range(k)))
                        for sg in itertools.product((-1, 1), repeat=k))
            assert Q(b[t, i]) >= worst
            for l in range(k):
                for sg in itertools.product((-1, 1), repeat=k):
                    m = [Q(J[t, j, l]) + sg[j] * Q(J_rad[t, j, l]) for j in range(k)]
                    exact = abs((1 if i == l else 0) - sum(Q(Y[t, i, j]) * m[j] for j in range(k)))
                    assert Q(D[t, i, l]) >= exact


def test_complex_bounds_dominate_the_modulus():
    rng = np.random.default_rng(11)
    Y = rng.normal(size=(20, 2, 2)) + 1j * rng.normal(size=(20, 2, 2))
    F = rng.normal(size=(20, 2)) + 1j * rng.normal(size=(20, 2))
    b = float_residual_bound(Y, F, np.zeros((20, 2)))
    for t in range(20):
        for i in range(2):
            re = sum(Q(Y[t, i, j].real) * Q(F[t, j].real) - Q(Y[t, i, j].imag) * Q(F[t, j].imag) for j in range(2))
            im = sum(Q(Y[t, i, j].real) * Q(F[t, j].imag) + Q(Y[t, i, j].imag) * Q(F[t, j].real) for j in range(2))
            assert Q(b[t, i]) ** 2 >= re * re + im * im
    assert (abs_upper(F) >= np.abs(F)).all() and (round_up(np.zeros(3)) > 0).all()


def _circle_system(m, r):
    """F(x, y) = (x² + y² − 1, x − y) near m: zeros ±(1/√2, 1/√2); enclosures over the square."""
    x, y = m
    F = np.array([[x * x + y * y - 1, x - y]])
    F_rad = np.array([[4 * 2.0 ** -52 * (x * x + y * y + 1), 2.0 ** -52 * (abs(x) + abs(y))]])
    J = np.array([[[2 * x, 2 * y], [1.0, -1.0]]])
    J_rad = np.array([[[2 * r + 2.0 ** -50, 2 * r + 2.0 ** -50], [0.0, 0.0]]])
    return F, F_rad, J, J_rad


def test_a_simple_zero_is_proved_and_enclosed():
    z = 1 / math.sqrt(2)
    m = (z + 1e-9, z - 2e-9)
    for r in (1e-8, 1e-6, 1e-3):
        F, F_rad, J, J_rad = _circle_system(m, r)
        Y, _ = float_inverse(J)
        ok, rad = float_krawczyk_test(float_residual_bound(Y, F, F_rad), float_contraction_bound(Y, J, J_rad),
                                      np.array([[r, r]]))
        assert ok[0]
        assert abs(m[0] - z) <= rad[0, 0] and abs(m[1] - z) <= rad[0, 1]


def test_a_box_with_two_zeros_or_none_is_refused():
    F, F_rad, J, J_rad = _circle_system((0.0, 0.0), 1.0)        # holds both zeros ±(1/√2, 1/√2)
    Y, good = float_inverse(J)
    assert not good[0]                                          # J(0, 0) is singular: Y = 0
    ok, _ = float_krawczyk_test(float_residual_bound(Y, F, F_rad), float_contraction_bound(Y, J, J_rad),
                                np.array([[1.0, 1.0]]))
    assert not ok[0]
    m, r = (0.5, 0.5), 0.05                                     # a box with no zero
    F, F_rad, J, J_rad = _circle_system(m, r)
    Y, _ = float_inverse(J)
    ok, _ = float_krawczyk_test(float_residual_bound(Y, F, F_rad), float_contraction_bound(Y, J, J_rad),
                                np.array([[r, r]]))
    assert not ok[0]


def test_apollonius_boxes_hold_the_exact_vertex():
    sites = [Circle.from_radius(0, 0, 1), Circle.from_radius(5, 0, Q(1, 2)), Circle.from_radius(2, 4, Q(3, 4))]
    S = SiteArrays(sites, [CircleGeometry(c) for c in sites])
    tv = voronoi_vertices_circles(*sites)
    T3 = np.array([[0, 1, 2]] * len(tv.vertices))
    M = np.array([[v.x, v.y] for v in tv.vertices]) + 1e-11
    h = np.full(len(M), 1e-9)
    ok, rlo, rhi = krawczyk_circles(S, T3, M, h)
    assert ok.all()
    for v, lo, hi in zip(tv.vertices, rlo, rhi):
        assert lo <= v.radius <= hi
    far = M + 1e-7                                               # the box no longer holds the vertex
    ok, _, _ = krawczyk_circles(S, T3, far, h)
    assert not ok.any()
