"""The bivariate product behind compose_offset (runtime.algebra.polyalg._mul2) gives the same
floating-point coefficients bit for bit whichever operand its loop runs over: every coefficient is
the same sequence of rounded products added from +0.0 (extra exact zeros leave such a sum
unchanged), checked against the plain loop over the terms of A on triangular arrays with zeros."""
from __future__ import annotations

import numpy as np

from curvedvoronoi.runtime.algebra.polyalg import _mul2


def _reference(A, B):
    out = np.zeros((A.shape[0] + B.shape[0] - 1, A.shape[1] + B.shape[1] - 1))
    for a in range(A.shape[0]):
        for b in range(A.shape[1]):
            if A[a, b] != 0:
                out[a:a + B.shape[0], b:b + B.shape[1]] += A[a, b] * B
    return out


def test_mul2_is_bit_identical_to_the_loop_over_the_terms_of_a():
    rng = np.random.default_rng(3)
    for _ in range(200):
        n, m = rng.integers(1, 10, size=2)
        A = np.triu(rng.standard_normal((n, n)))[:, ::-1].copy() * 10.0 ** rng.integers(-3, 4)
        B = rng.standard_normal((m, m)) * (rng.random((m, m)) < 0.7)
        B[-1, -1] = 0.0 if m > 1 else B[-1, -1]
        for X, Y in ((A, B), (B, A)):
            got, ref = _mul2(X, Y), _reference(X, Y)
            assert got.shape == ref.shape
            assert got.tobytes() == ref.tobytes()        # bit for bit, signs of zeros included
