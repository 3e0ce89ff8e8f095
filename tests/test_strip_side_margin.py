"""(T4) of the strip test draws the lateral sides inside the trapezoid (runtime/voronoi/verify/
strips.py): the side midpoints Qp, Qm, as floats, lie at |λ| ≤ w(s)·(1 − 10⁻¹²) in the strip's
own frame, so that β crosses every cross-section with the margin the chaining at the nodes uses
against the rounding of the frames (runtime/voronoi/verify/curved.py, "Chaining at the nodes").
Checked exactly: every float read as a rational, (s, λ) solved in the frame (S, t, n = rot90(t))
with |t| ≠ 1 as stored, w(s) = W0 + slope·s."""
from fractions import Fraction as Fr

import numpy as np
import pytest

from curvedvoronoi.runtime.voronoi.verify import strips


def _frame(S0, t, X):
    tx, ty = Fr(t[0]), Fr(t[1])
    dx, dy = Fr(X[0]) - Fr(S0[0]), Fr(X[1]) - Fr(S0[1])
    tt = tx * tx + ty * ty
    return (dx * tx + dy * ty) / tt, (-dx * ty + dy * tx) / tt


@pytest.mark.parametrize("seed", range(6))
def test_side_points_lie_inside_the_trapezoid_by_a_relative_margin(seed):
    rng = np.random.default_rng(seed)
    m = 40
    far = 10.0 ** rng.uniform(0, 8, m)                   # segments up to 10⁸ from the origin
    S = rng.normal(0, 1, (m, 2)) * far[:, None]
    ang = rng.uniform(0, 2 * np.pi, m)
    L = 10.0 ** rng.uniform(-3, 3, m)
    E = S + L[:, None] * np.column_stack([np.cos(ang), np.sin(ang)])
    seg = E - S
    Lf = np.hypot(seg[:, 0], seg[:, 1])
    T = seg / Lf[:, None]
    N = strips.rot90(T)
    scale = float(np.abs(S).max()) + 1.0
    W0 = np.maximum(10.0 ** rng.uniform(-12, 0, m) * L, 1e-12 * scale)
    W1 = np.maximum(10.0 ** rng.uniform(-12, 0, m) * L, 1e-12 * scale)
    slope = (W1 - W0) / Lf
    chains = (np.arange(m), S, T, N, W0, slope, np.zeros(m, int), np.ones(m, int))
    k = 5
    pseg = np.repeat(np.arange(m), k)
    a = rng.uniform(0, 1, (m, k))
    b = rng.uniform(0, 1, (m, k))
    sa = (np.minimum(a, b) * Lf[:, None]).ravel()
    sb = (np.maximum(a, b) * Lf[:, None]).ravel() + 1e-9 * Lf[pseg]
    P = strips._pieces(scale, pseg, sa, sb, chains)
    margin = 1 - Fr(1, 10 ** 12)
    for r in range(len(pseg)):
        g = pseg[r]
        for Q, side in ((P.Qp[r], 1), (P.Qm[r], -1)):
            s, lam = _frame(S[g], T[g], Q)
            w = Fr(W0[g]) + Fr(slope[g]) * s
            assert side * lam > 0, (r, side)
            assert abs(lam) <= w * margin, (r, side, float(abs(lam) / w - 1))
