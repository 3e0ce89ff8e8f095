"""(T4') of the strip test (runtime/voronoi/verify/strips.py, ``side_second_order``) next to a
hyperbola: its second-order bound |f''| ≤ M rests on d being the distance to one convex set on the
side's disc.  Between the branches of X² − Y² = 1, d is the smaller of the two branches' distances,
with a concave corner on the conjugate axis X = 0, so a side that reaches the axis (``sep`` < h) is
outside the bound's hypothesis.  Built here: a point site i whose distance has the same slope along
the side as the right branch's at the side's midpoint, 0.02 nearer there, so that the first-order
term vanishes and the second-order bound would say d_j − d_i > 0 on the whole side — while past the
axis d_j follows the left branch and d_j − d_i changes sign (distances by scipy, independently of
the verifier).  The side must be refused; the same side moved off the axis, where d_j − d_i > 0
holds, is accepted."""
import math

import numpy as np
from scipy.optimize import minimize_scalar

import curvedvoronoi as cv
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry
from curvedvoronoi.runtime.voronoi.verify import strips
from curvedvoronoi.runtime.voronoi.verify.site_table import SiteTable, gradient_enclosure

HYPERBOLA = cv.Conic.from_coefficients(1, 0, -1, 0, 0, -1)      # X² − Y² = 1
H = 0.2                                                          # half-length of the side


def branch_distance(q, sgn):
    f = lambda u: math.hypot(sgn * math.cosh(u) - q[0], math.sinh(u) - q[1])
    return minimize_scalar(f, bounds=(-6, 6), method="bounded", options={"xatol": 1e-13}).fun


def hyperbola_distance(q):
    return min(branch_distance(q, 1), branch_distance(q, -1))


def scene(x0):
    """Midpoint (x0, 2) on a side along X; the point i at distance d_j − 0.02 whose distance has
    the right branch's slope along X there."""
    Qs = np.array([x0, 2.0])
    d0 = hyperbola_distance(Qs)
    e = 1e-6
    c = -(branch_distance(Qs + [e, 0], 1) - branch_distance(Qs - [e, 0], 1)) / (2 * e)
    p = Qs + (d0 - 0.02) * np.array([c, -math.sqrt(1 - c * c)])
    return Qs, p


def verdict(Qs, p):
    geoms = [site_geometry(s) for s in (cv.Point(float(p[0]), float(p[1])), HYPERBOLA)]
    table = SiteTable(geoms, 10.0)
    Q, t, h = Qs[None, :], np.array([[1.0, 0.0]]), np.array([H])
    Vi = strips.evaluate_rows(table, Q, np.array([0]))
    Vj = strips.evaluate_rows(table, Q, np.array([1]))
    Gi, si, _ = gradient_enclosure(Q, Vi, h, 10.0)
    Gj, sj, _ = gradient_enclosure(Q, Vj, h, 10.0)
    fval = Vj.lo - Vi.hi                     # a lower bound of ς·f, ς = −1: d_j − d_i
    return bool(strips.side_second_order(Q, t, h, fval, Vi, Vj, Gi, si, Gj, sj, 10.0)[0])


def gap_along_side(Qs, p):
    return [hyperbola_distance(Qs + [s, 0]) - math.hypot(*(Qs + [s, 0] - p)) for s in np.linspace(-H, H, 17)]


def test_a_side_across_the_conjugate_axis_is_refused():
    Qs, p = scene(1e-3)
    assert min(gap_along_side(Qs, p)) < -0.05          # d_j − d_i changes sign on the side
    assert not verdict(Qs, p)


def test_the_same_side_off_the_axis_is_accepted():
    Qs, p = scene(0.5)
    assert min(gap_along_side(Qs, p)) > 0.01
    assert verdict(Qs, p)
