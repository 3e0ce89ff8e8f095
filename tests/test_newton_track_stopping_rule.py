"""Newton's stopping rule of the certification stage (runtime/certify/offset_system.py,
``newton_track``) at its boundary: *converged* means that the last step is strictly below
2^-(prec/2) times the size 1 + max |z_i| of the new point.

On the shift z ↦ z − c (Jacobian the identity) one Newton step from m_0 lands exactly on c, the
step is m_0 − c, and every quantity is a dyadic rational, so the rule is met or not exactly.  At
64 bits the threshold is 2^-32·(1 + max |c_i|).

* c = 0: size 1; a step of 2^-32 (margin 0) is not below it, 2^-32·(1 − 2^-30) is, and
  2^-32·(1 + 2^-30) is not;
* c = (3, 0, 0): size 4, threshold 2^-30; the step 2^-30 (margin 0) is not below it,
  2^-30·(1 − 2^-20) is, 2^-30·(1 + 2^-20) is not (m_0 = 3 + step is a double: 52 bits).
"""
from __future__ import annotations

import flint
import pytest
from flint import acb

from curvedvoronoi.runtime.certify.offset_system import newton_track


class Shift:
    """The system z − c: values and Jacobian rows at the acb point z."""

    def __init__(self, c):
        self.c = [acb(t) for t in c]

    def eval(self, z):
        return [z[i] - self.c[i] for i in range(3)], [[acb(int(i == j)) for j in range(3)] for i in range(3)]


@pytest.fixture
def prec64():
    old = flint.ctx.prec
    flint.ctx.prec = 64
    try:
        yield
    finally:
        flint.ctx.prec = old


@pytest.mark.parametrize("c0, step, converged", [
    (0, 2.0 ** -32, False), (0, 2.0 ** -32 * (1 - 2.0 ** -30), True), (0, 2.0 ** -32 * (1 + 2.0 ** -30), False),
    (3, 2.0 ** -30, False), (3, 2.0 ** -30 * (1 - 2.0 ** -20), True), (3, 2.0 ** -30 * (1 + 2.0 ** -20), False),
], ids=["size 1, margin 0", "size 1, below", "size 1, above", "size 4, margin 0", "size 4, below", "size 4, above"])
def test_a_last_step_equal_to_the_threshold_is_not_convergence(prec64, c0, step, converged):
    m, conv = newton_track(Shift([c0, 0, 0]), [acb(c0 + step), acb(0), acb(0)], True, iters=1)
    assert [complex(t) for t in m] == [complex(c0), 0j, 0j]          # one step lands on c exactly
    assert conv is converged
