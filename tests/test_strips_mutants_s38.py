"""(T3) of the strip test (runtime/voronoi/verify/strips.py, ``_tied_derivative``) inside a circle.

(T3) accepts a piece for a third site k tied with the pair (i, j) at a vertex when the sign of
g' (g = d_k − d_i along the bisector of i and j, whose tangent is ± rot90(∇f), f = d_i − d_j) is
the wanted one on the piece's whole disc B(C, R):

    σ·(∇d_k − ∇d_i)·rot90(∇d_i − ∇d_j) has the sign ``want`` on B(C, R),  σ = sign(rot90(∇f)·T),

decided from enclosures G_x ± s_x of the three gradients on the disc.  With D_g = G_k − G_i and
D_f = G_i − G_j, the product's error is at most |D_g|·s_f + |D_f|·s_g + s_f·s_g (s_f = s_i + s_j,
s_g = s_i + s_k): every term is needed where an enclosure is wide.  Here j is a circle of radius 10
about the origin holding the points i and k, and the discs lie near its centre (its medial axis):
there ∇d_j = −q/|q| turns fast (it is 1/|q|-Lipschitz), so s_j, the interior enclosure
(1 + L)·R/(lo − R) of site_table.gradient_enclosure (Federer's reach, L = reach/(reach − t)), is
large, and k is placed on the ray from the centre through the discs, where ∇d_k comes close to
∇d_j and g' can change sign on a disc.

Expectation from closed forms, not from the verifier: ∇d_p = (q − p)/|q − p| for a point p and
∇d_j = −q/|q| inside the circle (d_j = 10 − |q|); the sign is checked on 600 points of each accepted
disc (200 on its boundary).  Without the |D_g|·s_f term (the seed-32 survivor strips.py:197) (T3)
accepts discs on which that sign changes.
"""
import math
from typing import NamedTuple

import numpy as np
import pytest

import curvedvoronoi as cv
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify import strips
from curvedvoronoi.runtime.voronoi.verify.site_table import SiteTable, gradient_enclosure

RADIUS = 10.0


class Pieces(NamedTuple):
    jb: np.ndarray
    seg: np.ndarray
    sm: np.ndarray
    Tn: np.ndarray


def signed_derivative(q, T, pi, pk):
    """σ·(u_k − u_i)·rot90(u_i − u_j) at the points q (closed-form unit gradients; j is the circle
    of radius RADIUS about the origin, seen from inside)."""
    ui = (q - pi) / np.hypot(*(q - pi).T)[:, None]
    uk = (q - pk) / np.hypot(*(q - pk).T)[:, None]
    uj = -q / np.hypot(*q.T)[:, None]
    f = ui - uj
    rf = np.stack([-f[:, 1], f[:, 0]], 1)
    return np.sign((rf * T).sum(1)) * ((uk - ui) * rf).sum(1)


@pytest.mark.parametrize("seed", range(3))
def test_tied_site_accepted_only_where_the_derivative_keeps_its_sign_near_a_circles_centre(seed):
    rng = np.random.default_rng(seed)
    accepted = 0
    for _ in range(20):
        eps = rng.uniform(0.3, 3.0)                      # the discs' distance to the circle's centre
        phi = rng.uniform(0, 2 * np.pi)
        ray = np.array([math.cos(phi), math.sin(phi)])
        pk = ray * rng.uniform(eps + 1, RADIUS - 0.5)   # k beyond the discs on the ray from the centre
        pi = rng.uniform(-7, 7, 2)
        geoms = [site_geometry(s) for s in (cv.Point(*pi), cv.Circle(0.0, 0.0, RADIUS * RADIUS), cv.Point(*pk))]
        table = SiteTable(geoms, 20.0)
        n = 400
        C = ray * eps + rng.normal(size=(n, 2)) * eps * 0.3
        R = eps * np.exp(rng.uniform(math.log(1e-3), math.log(0.5), n))
        ang = rng.uniform(0, 2 * np.pi, n)
        T = np.stack([np.cos(ang), np.sin(ang)], 1)
        values = [strips.evaluate_rows(table, C, np.full(n, s)) for s in (0, 1, 2)]
        enc = [gradient_enclosure(C, v, R, table.scale) for v in values]
        tied, none = np.array([[2]]), np.array([[-1]])
        for at_end in (False, True):
            want = -1.0 if at_end else 1.0
            chains = (None,) * 8 + ((none, tied) if at_end else (tied, none)) + (np.array([0.0]), np.array([1.0]))
            P = Pieces(np.zeros(n, int), np.zeros(n, int), np.full(n, 0.5), T)
            okk = np.zeros(n, bool)
            strips._tied_derivative(chains, P, np.arange(n), np.full(n, 2), okk, enc[0], enc[1], enc[2])
            for t in np.nonzero(okk)[0]:
                accepted += 1
                th = rng.uniform(0, 2 * np.pi, 600)
                rad = R[t] * np.sqrt(rng.uniform(0, 1, 600))
                rad[:200] = R[t]
                q = C[t] + np.stack([rad * np.cos(th), rad * np.sin(th)], 1)
                val = signed_derivative(q, T[t], pi, pk)
                assert (want * val > 0).all(), (C[t], R[t], T[t], pi, pk, want)
    assert accepted > 1000      # (T3) does decide most of these discs
