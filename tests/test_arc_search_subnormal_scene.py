"""The disc search of runtime/voronoi/verify/arc_search.py keeps an absolute floor on the rounding
of a curve point (16 ulps of 1 besides the relative terms): in a scene of subnormal coordinates,
where every float operation errs by up to half the smallest subnormal 2^-1074 whatever the size of
its result, the relative error terms underflow to 0 and only that floor covers the rounding.

Sites: the points i = (−10s, 0) and j = (10s, 0) with s = 2^-1067 (exact subnormal doubles).  Their
bisector is the line x = 0, given exactly as q(u) = (0, 10s·sinh u) (m = 0, e_x = (1, 0), a = 0,
b = c = 10s; built here directly, since :func:`bisector`'s float filter refuses so small a scene).
The arc is the one point x* = q(2.3).  The third site k (below, exact doubles) lies at distance
d_i(x*) from x* up to −0.43·2^-1074 (mpmath, 400 bits): it is not strictly farther than i at x*,
so ``prove_arcs`` must refuse.  In doubles (this machine's libm), the rounded point q(2.3) and the
rounded distances put k one subnormal farther than i, so a search without the floor proves it.
"""
from __future__ import annotations

import mpmath as mp

from curvedvoronoi.runtime.predicates.circles import Point
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify.arc_search import prove_arcs
from curvedvoronoi.runtime.voronoi.verify.edges import Bisector, CircleTable

S = 2.0 ** -1067
U0 = 2.3
TINY = 2.0 ** -1074
K = (float.fromhex("0x0.0000000000894p-1022"), float.fromhex("0x0.000000000305dp-1022"))


def _margin_at_the_arc():
    """d_k(x*) − d_i(x*) at 400 bits, in units of 2^-1074."""
    with mp.workprec(400):
        x, y = mp.mpf(0), 10 * mp.mpf(S) * mp.sinh(U0)
        dk = mp.sqrt((x - K[0]) ** 2 + (y - K[1]) ** 2)
        di = mp.sqrt((x + 10 * mp.mpf(S)) ** 2 + y ** 2)
        return (dk - di) / TINY


def test_a_site_tied_within_a_subnormal_is_not_proved_farther():
    m = _margin_at_the_arc()
    assert -1 < m <= 0                                   # tied to within 2^-1074, not farther
    table = CircleTable([site_geometry(Point(*p)) for p in ((-10 * S, 0.0), (10 * S, 0.0), K)])
    bis = Bisector("hyperbola", (0.0, 0.0), (1.0, 0.0), 10 * S, 0.0, 10 * S, 0, 1)
    (ok, detail), = prove_arcs(table, [(bis, U0, U0, ())], max_pieces=64)
    assert not ok and detail[0] == 2
