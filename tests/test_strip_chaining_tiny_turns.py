"""Chaining of strips at turns too small for √(1 − cos²θ) (runtime/voronoi/verify/curved.py,
"Chaining at the nodes").

At a turn θ of 10⁻⁹ rad the dot product of the two float unit tangents rounds to 1, so
√(1 − cos²θ) = 0 and the turn looks straight; yet where both adjacent trapezoids narrow away from
the node faster than tan(θ/2), strip l's cross-section at the node reaches W·(1 − |k|·sin θ) > W·cos θ
outside strip l + 1 — by about W·|k|·θ, far above the rounding of the coordinates.  The sines come
from the cross product (:func:`turn_sines`), and the chaining is checked here exactly: every float
of the strips (nodes, tangents, half-widths, extensions) read as a rational, the cross-sections'
ends solved in each strip's own frame with :class:`fractions.Fraction`."""
from fractions import Fraction as Fr
from types import SimpleNamespace

import mpmath
import numpy as np
import pytest

from curvedvoronoi.runtime.voronoi.verify.curved import chained_nodes, strip_extensions, turn_sines


def _in_strip(P0, t, L, w0, w1, e_lo, e_hi, X):
    """X in the trapezoid {P0 + s·t + λ·n : s ∈ [−e_lo, L + e_hi], |λ| ≤ w0 + (w1 − w0)·s/L}
    (t, n = rot90(t) the strip's float vectors, |t| ≠ 1 exactly: s, λ solved exactly)."""
    tx, ty = Fr(t[0]), Fr(t[1])
    dx, dy = X[0] - Fr(P0[0]), X[1] - Fr(P0[1])
    tt = tx * tx + ty * ty
    s = (dx * tx + dy * ty) / tt
    lam = (dx * -ty + dy * tx) / tt
    w = Fr(w0) + (Fr(w1) - Fr(w0)) / Fr(L) * s
    return -Fr(e_lo) <= s <= Fr(L) + Fr(e_hi) and abs(lam) <= w


def _chains_exactly(S, T, L, e_lo, e_hi, W):
    """Every inner node: one strip's cross-section there (both ends, shortened by 10⁻¹² of the
    half-width: the frames' own rounding, |t| = 1 within 10⁻¹⁶, is not what is checked here) lies
    in the other strip."""
    for j in range(1, len(S) - 1):
        a, b = j - 1, j
        P = (Fr(S[j][0]), Fr(S[j][1]))
        ok = False
        for u, v in ((a, b), (b, a)):
            nx, ny = -Fr(T[u][1]), Fr(T[u][0])
            w = Fr(W[j]) * (1 - Fr(1, 10 ** 12))
            ends = [(P[0] + sg * w * nx, P[1] + sg * w * ny) for sg in (1, -1)]
            if all(_in_strip(S[v], T[v], L[v], W[v], W[v + 1], e_lo[v], e_hi[v], X) for X in ends):
                ok = True
        if not ok:
            return False
    return True


NO_ENDS = SimpleNamespace(h0=0.0, h1=0.0)


@pytest.mark.parametrize("theta", [1e-9, 3e-8])
def test_a_tiny_turn_between_narrowing_trapezoids_gets_a_flat_run(theta):
    S = np.array([[0.0, 0.0], [10.0, 0.0], [20.0, 10.0 * np.tan(theta)]])
    W = np.array([0.1, 2.5, 0.1])                  # slopes ∓0.24, far above tan(θ/2)
    T = (S[1:] - S[:-1]) / np.hypot(*(S[1:] - S[:-1]).T)[:, None]
    # the exact sine of the turn between the float tangents, and what √(1 − cos²) makes of it
    mpmath.mp.dps = 40
    ta, tb = [mpmath.matrix([mpmath.mpf(x) for x in t]) for t in T]
    exact = abs(ta[0] * tb[1] - ta[1] * tb[0]) / (mpmath.norm(ta) * mpmath.norm(tb))
    lo, up = turn_sines(T[0], T[1])
    assert lo <= exact <= up and up - lo < 1e-14
    if theta < 1e-8:
        assert np.sqrt(1 - np.clip(T[0] @ T[1], -1, 1) ** 2) == 0.0     # the turn looked straight
    # without a flat run the node does not chain (the failure the flat run prevents)
    T0, _, L0, elo0, ehi0 = strip_extensions(S, W, NO_ENDS, False, 20.0)
    assert not _chains_exactly(S, T0, L0, elo0, ehi0, W)
    S2, W2 = chained_nodes(S, W, False, 20.0)
    assert len(S2) > len(S)
    T2, _, L2, elo2, ehi2 = strip_extensions(S2, W2, NO_ENDS, False, 20.0)
    assert _chains_exactly(S2, T2, L2, elo2, ehi2, W2)


def test_a_straight_run_with_constant_widths_is_left_alone():
    S = np.array([[0.0, 0.0], [10.0, 0.0], [20.0, 0.0], [30.0, 0.0]])
    W = np.array([0.5, 0.5, 0.5, 0.5])
    S2, W2 = chained_nodes(S, W, False, 30.0)
    assert len(S2) == len(S)
    T2, _, L2, elo2, ehi2 = strip_extensions(S2, W2, NO_ENDS, False, 30.0)
    assert _chains_exactly(S2, T2, L2, elo2, ehi2, W2)


def test_no_room_for_a_flat_run_is_reported():
    # a 40° turn at a node of half-width 2.5 between segments of length 1: the flat run would be
    # 2.5·sin 40° ≈ 1.6 long, more than half of either segment
    th = np.radians(40)
    S = np.array([[0.0, 0.0], [1.0, 0.0], [1 + np.cos(th), np.sin(th)]])
    W = np.array([0.01, 2.5, 0.01])
    assert chained_nodes(S, W, False, 10.0) == (None, None)
