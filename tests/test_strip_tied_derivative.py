"""(T3) of the strip test (runtime/voronoi/verify/strips.py, ``_tied_derivative``): a third site k
tied with the pair (i, j) at the chain's first vertex V is accepted on a piece only where
g = d_k − d_i strictly increases along the bisector on the whole piece (decreases, for a site tied
at the last vertex).

Three points: i = (−1, 0), j = (1, 0), so the bisector of i, j is the y axis, and k placed so that V,
the circumcentre of i, j, k, lies on it.  Along the axis, q(s) = V + s·t, the derivative is in
closed form, g'(s) = (u_k − u_i)·t with u_p = (q − p)/|q − p|, and it changes sign once where the
bisectors of (i, j) and (i, k) are nearest to tangent; pieces of every size straddle that place.
Expectation sampled on the piece, not taken from the verifier."""
import math
from typing import NamedTuple

import numpy as np
import pytest

import curvedvoronoi as cv
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify import strips
from curvedvoronoi.runtime.voronoi.verify.site_table import SiteTable, gradient_enclosure


class Pieces(NamedTuple):
    jb: np.ndarray
    seg: np.ndarray
    sm: np.ndarray
    Tn: np.ndarray


def g_prime(V, t, s, pi, pk):
    q = V[None, :] + s[:, None] * t[None, :]
    uk = (q - pk) / np.hypot(*(q - pk).T)[:, None]
    ui = (q - pi) / np.hypot(*(q - pi).T)[:, None]
    return ((uk - ui) * t).sum(1)


@pytest.mark.parametrize("seed", range(8))
@pytest.mark.parametrize("at_end", [False, True])
def test_tied_site_accepted_only_where_g_is_monotone_on_the_whole_piece(seed, at_end):
    rng = np.random.default_rng(seed)
    pi, pj = np.array([-1.0, 0.0]), np.array([1.0, 0.0])
    pk = np.array([rng.uniform(-3, 3), rng.uniform(0.5, 4)]) * rng.choice([-1, 1])
    # the circumcentre of i, j, k lies on x = 0: y with |V − i| = |V − k|
    y = (pk @ pk - 1.0) / (2 * pk[1])
    V = np.array([0.0, y])
    geoms = [site_geometry(cv.Point(*p)) for p in (pi, pj, pk)]
    table = SiteTable(geoms, 10.0)
    L = 20.0
    # the chain of length L leaves V along t; the tie is at its first vertex (s = 0), or at its last
    # (the chain runs towards V: s = L at V)
    want = -1.0 if at_end else 1.0
    # the side of V where k is farther than i (g > 0 along the edge): g' at V has the sign want
    t = np.array([0.0, 1.0])
    if want * g_prime(V, t, np.array([1e-9]), pi, pk)[0] < 0:
        t = -t
    start = -L if at_end else 0.0
    a = rng.uniform(0, L, 300)
    ln = np.exp(rng.uniform(math.log(1e-3), math.log(5.0), 300))
    sa, sb = a, np.minimum(a + ln, L)
    sm = 0.5 * (sa + sb)
    R = 0.5 * (sb - sa) * (1 + 1e-9) + 1e-12
    C = V + (start + sm)[:, None] * t
    Vs = [strips.evaluate_rows(table, C, np.full(len(C), s)) for s in (0, 1, 2)]
    enc = [gradient_enclosure(C, v, R, table.scale) for v in Vs]
    tied = np.array([[2]])
    none = np.array([[-1]])
    chains = (None,) * 8 + ((none, tied) if at_end else (tied, none)) + (np.array([0.0]), np.array([L]))
    P = Pieces(np.zeros(len(C), int), np.zeros(len(C), int), sm, np.tile(t, (len(C), 1)))
    rows, ks = np.arange(len(C)), np.full(len(C), 2)
    okk = np.zeros(len(C), bool)
    strips._tied_derivative(chains, P, rows, ks, okk, enc[0], enc[1], enc[2])
    assert okk.any()
    for r in np.nonzero(okk)[0]:
        s = start + np.linspace(sa[r], sb[r], 41)
        assert (want * g_prime(V, t, s, pi, pk) > 0).all(), (r, sa[r], sb[r])
