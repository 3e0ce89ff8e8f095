"""The refinement of a drawn curve's parameters (runtime/segments/polyline_refinement.py) on a
circle of radius r drawn by its angle, where the deviation of the curve's middle point from a
chord of angle Δ is the sagitta r (1 − cos(Δ/2)), computed here in closed form: after the
refinement every step's sagitta is within tol/2, no step was halved that did not need it (its
parent's sagitta was above tol/2), and the parameters keep the drawing's order both ways."""
from __future__ import annotations

import math

import numpy as np
import pytest

from curvedvoronoi.runtime.segments.polyline_refinement import refined_parameters

R = 3.0


def circle(o):
    o = np.asarray(o, float)
    return np.column_stack([R * np.cos(o), R * np.sin(o)]), np.full(len(o), R)


def sagitta(delta):
    return R * (1 - np.cos(np.abs(delta) / 2))


@pytest.mark.parametrize("a, b", [(0.0, 2.5), (2.5, 0.0), (-1.0, 1.0)])
@pytest.mark.parametrize("tol", [1e-3, 1e-6])
def test_every_step_is_within_half_the_tolerance_and_none_is_cut_needlessly(a, b, tol):
    o = refined_parameters(circle, np.linspace(a, b, 33), tol, a > b, most=4096)
    steps = np.diff(o)
    assert (steps > 0).all() if b > a else (steps < 0).all()
    assert o[0] == a and o[-1] == b
    assert sagitta(steps).max() <= tol / 2
    # each step is 1/2^m of a first step; it was halved only while the larger step's sagitta was above tol/2
    first = abs(b - a) / 32
    for s in np.abs(steps):
        m = round(math.log2(first / s))
        assert math.isclose(s * 2 ** m, first, rel_tol=1e-9)
        if m > 0:
            assert sagitta(2 * s) > tol / 2


def test_the_rounds_and_the_piece_count_bound_the_work():
    o = refined_parameters(circle, np.linspace(0.0, 2.5, 33), 1e-15, False, most=4096, rounds=3)
    assert len(o) == 32 * 2 ** 3 + 1              # every step halved three times, then stopped
    o = refined_parameters(circle, np.linspace(0.0, 2.5, 33), 1e-15, False, most=100)
    assert 100 < len(o) <= 2 * 100                # one round past the bound, no more
