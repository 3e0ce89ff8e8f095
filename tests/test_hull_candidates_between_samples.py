"""The candidates of the convex hull of discs (runtime/voronoi/verify/hull_points.py): a disc that
leads only on an arc of directions between two sampled directions is still a candidate.

Scene: centres j = (−L, −L), m = (L, L) and k = (a, −a) (a = 10⁻⁶·L), all of radius 1, rotated by
the rational rotation of angle φ = 2·atan(1/2608) ≈ π/4096 (half the spacing of the 4096 sampled
directions).  Before the rotation k leads exactly on the directions within about a/L of
(1, −1)/√2 (a sampled direction); after it, on an arc of width ~2·10⁻⁶ centred midway between two
samples.  At those samples h_k falls below the leader by about |c_k − c_j|⊥·π/4096 =
L√2·7.67·10⁻⁴ ≈ 1.085·10⁻³·L: more than 10⁻³ of the scene's scale, less than the bound
2·max|c|·π/4096 that the candidate rule uses."""
from __future__ import annotations

from fractions import Fraction as Q

import numpy as np

import curvedvoronoi as cv
from curvedvoronoi.runtime.voronoi.verify.hull_points import hull_candidates

L = 1000
T = Q(1, 2608)
COS, SIN = (1 - T * T) / (1 + T * T), 2 * T / (1 + T * T)


def _rotated(x, y):
    return (COS * x - SIN * y, SIN * x + COS * y)


def _centres():
    a = Q(L, 10 ** 6)
    return [_rotated(-L, -L), _rotated(L, L), _rotated(a, -a)]


def test_a_disc_leading_between_two_sampled_directions_is_a_candidate():
    C = _centres()
    Cf = np.array([[float(x), float(y)] for x, y in C])
    assert hull_candidates(Cf, np.ones(3)) == [0, 1, 2]
    # the scene is the one the rule is for: at every sampled direction k is more than 10⁻³ of the
    # scale below the leader, yet it leads on an arc between two of them
    th = np.linspace(0, 2 * np.pi, 4096, endpoint=False)
    H = Cf @ np.stack([np.cos(th), np.sin(th)]) + 1.0
    assert (H.max(axis=0) - H[2]).min() > 1e-3 * (np.abs(Cf).max() + 2)
    u = np.array([float(_rotated(1, -1)[0]), float(_rotated(1, -1)[1])]) / np.sqrt(2)
    assert (Cf[2] @ u) > max(Cf[0] @ u, Cf[1] @ u)


def test_the_diagram_of_the_three_circles_is_certified_with_its_three_unbounded_edges():
    # equal radii: the diagram of the three centres, one vertex (their circumcentre) and the three
    # bisectors' unbounded halves
    d = cv.voronoi([cv.Circle(x, y, 1) for x, y in _centres()])
    assert d.certified
    assert len(d.vertices) == 1 and sorted(tuple(sorted(e.sites)) for e in d.edges) == [(0, 1), (0, 2), (1, 2)]
