"""The certification of a conic vertex and its conflict with a fourth conic
(runtime/certify/conflicts.py, ``certify_vertex``) at the boundaries of its exact path, with exact
rational constructions whose answers are derived in the docstrings."""
from __future__ import annotations

from fractions import Fraction as Fr

import flint
from flint import arb, fmpq

from curvedvoronoi.runtime.certify.conflicts import certify_vertex
from curvedvoronoi.runtime.sites.conic import Conic

#: the empty circle of the vertex: centre Q, radius ρ
Q, RHO = (Fr(1, 3), Fr(-2, 7)), Fr(5, 4)
#: rational unit directions and radii of three circles touching it from outside
DIRS = [(Fr(3, 5), Fr(4, 5)), (Fr(-12, 13), Fr(5, 13)), (Fr(8, 17), Fr(-15, 17))]
SIZES = [Fr(1, 2), Fr(2, 3), Fr(3, 4)]


def _holds(ball, q: Fr) -> bool:
    """The ball contains the rational q (converted at 4096 bits, far below any box's radius)."""
    old = flint.ctx.prec
    flint.ctx.prec = 4096
    try:
        return bool(ball.contains(arb(fmpq(q.numerator, q.denominator))))
    finally:
        flint.ctx.prec = old


def _circle(c, s) -> Conic:
    """(x − c_x)² + (y − c_y)² − s² = 0."""
    return Conic.from_coefficients(1, 0, 1, -2 * c[0], -2 * c[1], c[0] ** 2 + c[1] ** 2 - s * s)


def _touching_circles():
    """Circles of radius s centred at Q + (ρ + s)·u: each touches the circle (Q, ρ) from outside at
    Q + ρu, so Q is a Voronoi vertex of the three, at distance exactly ρ from each."""
    return [_circle((Q[0] + (RHO + s) * u[0], Q[1] + (RHO + s) * u[1]), s) for u, s in zip(DIRS, SIZES)]


def test_a_fourth_circle_equal_to_the_empty_circle_is_never_a_crash():
    """The fourth site is the empty circle itself, centred at the vertex: every one of its points is a
    foot of Q at distance exactly ρ, so its foot polynomial at Q is degenerate (a cluster at every
    precision).  The vertex is a true vertex of the three circles; the conflict sign, if proved, is
    0 (C4 touches the empty disc everywhere, no point inside it); and ``certify_vertex`` never
    raises on a failed proof (its docstring) -- the exact path gives up on the cluster."""
    cv = certify_vertex(*_touching_circles(), float(Q[0]), float(Q[1]), float(RHO) ** 2, _circle(Q, RHO))
    assert cv.true_vertex is True
    assert cv.box is not None and all(_holds(b, q) for b, q in zip(cv.box, Q))
    assert not cv.proven or cv.sign == 0


def test_a_candidate_where_no_vertex_lies_is_never_certified():
    """(5, 5) is no Voronoi vertex of the three circles: its distances | |p − c_i| − s_i | to them differ
    (checked below).  ``certify_result`` on the true vertex Q and that candidate may not certify
    the candidate, whatever it decides for Q (Q's certificate needs Q told apart from every other
    kept candidate, and the candidate has no proved box to be told apart by)."""
    import math

    from curvedvoronoi.runtime.certify.conflicts import certify_result
    from curvedvoronoi.runtime.result import LocatorResult, VoronoiVertex

    centres = [(Q[0] + (RHO + s) * u[0], Q[1] + (RHO + s) * u[1]) for u, s in zip(DIRS, SIZES)]
    d = [abs(math.hypot(5 - float(c[0]), 5 - float(c[1])) - float(s)) for c, s in zip(centres, SIZES)]
    assert max(d) - min(d) > 1
    c4 = _circle((Fr(10), Fr(10)), Fr(1))
    res = LocatorResult(conflict=False, vertices=[VoronoiVertex(float(Q[0]), float(Q[1]), float(RHO)),
                                                  VoronoiVertex(5.0, 5.0, 1.0)], method="test")
    out = certify_result(res, *_touching_circles(), c4)
    bogus = [v for v in out.vertices if (v.x, v.y) == (5.0, 5.0)]
    assert not any(v.certified for v in bogus)
    assert all(not v.certified or abs(v.x - float(Q[0])) < 1e-12 for v in out.vertices)
