"""The lemma behind (M) of runtime/voronoi/verify/tied_tail.py: for a convex site S with support
line ℓ = {p·u = h_S(u)} touching it at p(u) (lateral coordinate ℓ_S = p(u)·u⊥) and a point q beyond
ℓ, the nearest point p of S to q satisfies sign(s − p_s) = sign(s − ℓ_S), s = q·u⊥; so the lateral
derivative ∂_s d_S = (s − p_s)/d_S has the sign of s − ℓ_S, whatever the curvature.

Checked on random rotated ellipses with the nearest point found by dense sampling of the boundary
refined by a bounded scalar minimisation (scipy), independently of the verifier; and the tied-tail
test (M) is shown to accept exactly the half-strips strictly between ℓ_i and ℓ_j."""
import math

import numpy as np
from hypothesis import given, settings, strategies as st
from scipy.optimize import minimize_scalar

from curvedvoronoi.runtime.voronoi.verify import tied_tail


def nearest_point(cx, cy, a, b, rot, q):
    """The nearest point of the ellipse (boundary) to the outside point q: a dense grid of its
    parameter, then a bounded minimisation around the best sample."""
    c, s = math.cos(rot), math.sin(rot)

    def point(t):
        x, y = a * math.cos(t), b * math.sin(t)
        return np.array([cx + c * x - s * y, cy + s * x + c * y])

    ts = np.linspace(0.0, 2 * math.pi, 4001)
    d = [float(np.hypot(*(point(t) - q))) for t in ts]
    k = int(np.argmin(d))
    res = minimize_scalar(lambda t: float(np.hypot(*(point(t) - q))), bounds=(ts[k] - 0.002, ts[k] + 0.002),
                          method="bounded", options={"xatol": 1e-13})
    return point(res.x)


@settings(max_examples=60, deadline=None)
@given(a=st.floats(0.5, 4.0), ratio=st.floats(0.05, 1.0), rot=st.floats(0.0, math.pi),
       s_off=st.floats(-6.0, 6.0), z=st.floats(0.05, 20.0))
def test_the_nearest_point_lies_laterally_between_the_query_and_the_support_point(a, ratio, rot, s_off, z):
    b = a * ratio
    u = np.array([0.0, -1.0])                 # the support line y = −h below the ellipse
    perp = np.array([1.0, 0.0])               # u⊥ = (−u_y, u_x)
    # support point in direction u of the centred ellipse: A u / sqrt(uᵀ A u), A = R diag(a², b²) Rᵀ
    R = np.array([[math.cos(rot), -math.sin(rot)], [math.sin(rot), math.cos(rot)]])
    A = R @ np.diag([a * a, b * b]) @ R.T
    pu = A @ u / math.sqrt(float(u @ A @ u))
    ell = float(pu @ perp)
    if abs(s_off) < 1e-3:
        return
    q = pu + z * u + s_off * perp             # beyond the support line, lateral offset s_off from p(u)
    p = nearest_point(0.0, 0.0, a, b, rot, q)
    s = float(q @ perp)
    assert np.sign(s - float(p @ perp)) == np.sign(s - ell)


class Tie:
    def __init__(self, li, lj, sa, sb):
        self.li, self.lj, self.sa, self.sb = li, lj, sa, sb


def test_monotone_across_accepts_exactly_the_strips_strictly_between_the_support_points():
    from fractions import Fraction as F
    assert tied_tail._monotone_across(Tie(F(0), F(10), F(1), F(9)))
    assert not tied_tail._monotone_across(Tie(F(0), F(10), F(0), F(9)))      # s = ℓ_i on Π: ∂_s d_i = 0
    assert not tied_tail._monotone_across(Tie(F(0), F(10), F(1), F(10)))
    assert not tied_tail._monotone_across(Tie(F(0), F(10), F(-1, 10**9), F(9)))
    assert tied_tail._monotone_across(Tie(F(0), F(10), F(1, 10**9), F(10) - F(1, 10**9)))
