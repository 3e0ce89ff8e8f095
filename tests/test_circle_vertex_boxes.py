"""The float Krawczyk boxes of the verifier's circle route (:mod:`runtime.voronoi.verify.vertices`)
hold exactly one exact zero, checked against the closed-form Apollonius solutions at 50 digits.

For three circles (c_l, ρ_l) the system F_l(x, y, r) = |q − c_l|² − (r + ρ_l)² = 0 is, after
subtracting the first equation, two linear equations giving q = q0 + r·q1 and one quadratic in r
(thesis §3.1.3): two solutions.  The triples here are nearly collinear (lateral offsets 10⁻⁸ to
10⁻² of a line of length 20), so the vertex is far and the Jacobian nearly singular: the residual
of F at the float point and the Jacobian's change across the box decide the test, and a box must
contain the solution it claims and not the other one.
"""
from __future__ import annotations

import mpmath
import numpy as np

from curvedvoronoi.runtime.voronoi.verify import vertices as circle_vertices


def _apollonius(c, p):
    """Both solutions (x, y, r) of the system, 50 digits (float data read exactly)."""
    with mpmath.workdps(50):
        c = [[mpmath.mpf(float(v)) for v in row] for row in c]
        p = [mpmath.mpf(float(v)) for v in p]
        M = mpmath.matrix([[2 * (c[1][0] - c[0][0]), 2 * (c[1][1] - c[0][1])],
                           [2 * (c[2][0] - c[0][0]), 2 * (c[2][1] - c[0][1])]])
        n0 = c[0][0] ** 2 + c[0][1] ** 2 - p[0] ** 2
        rhs0 = mpmath.matrix([c[1][0] ** 2 + c[1][1] ** 2 - p[1] ** 2 - n0, c[2][0] ** 2 + c[2][1] ** 2 - p[2] ** 2 - n0])
        rhs1 = mpmath.matrix([-2 * (p[1] - p[0]), -2 * (p[2] - p[0])])
        q0, q1 = mpmath.lu_solve(M, rhs0), mpmath.lu_solve(M, rhs1)
        a2 = q1[0] ** 2 + q1[1] ** 2 - 1
        a1 = 2 * ((q0[0] - c[0][0]) * q1[0] + (q0[1] - c[0][1]) * q1[1]) - 2 * p[0]
        a0 = (q0[0] - c[0][0]) ** 2 + (q0[1] - c[0][1]) ** 2 - p[0] ** 2
        disc = a1 * a1 - 4 * a2 * a0
        if disc < 0:
            return []
        return [(q0[0] + r * q1[0], q0[1] + r * q1[1], r)
                for r in ((-a1 + s * mpmath.sqrt(disc)) / (2 * a2) for s in (1, -1))]


def test_every_proved_box_holds_exactly_one_exact_solution():
    rng = np.random.default_rng(1)
    n = 3000
    t = rng.uniform(-10, 10, (n, 3))
    lateral = rng.normal(size=(n, 3)) * 10.0 ** rng.uniform(-8, -2, (n, 1))
    C = np.stack([t, lateral], -1)
    Rho = rng.uniform(0, 1, (n, 3)) * rng.integers(0, 2, (n, 1))       # half of them points
    rows, sols = [], []
    for m in range(n):
        both = _apollonius(C[m], Rho[m])
        pos = [z for z in both if z[2] > 0]
        if pos:
            rows.append(m)
            sols.append((pos[0], both))
    C, Rho = C[rows], Rho[rows]
    # float starts a relative 10⁻⁹ off the first solution (the route polishes them by Newton)
    Z = np.array([[float(v) for v in z] for z, _ in sols]) * (1 + 1e-9 * rng.normal(size=(len(rows), 3)))
    ok, Zp, H = circle_vertices._krawczyk(C, Rho, Z, 100.0)
    assert ok.sum() > 300                       # the test is not vacuous
    with mpmath.workdps(50):
        for m in np.nonzero(ok)[0]:
            inside = [all(abs(z[a] - mpmath.mpf(float(Zp[m, a]))) <= mpmath.mpf(float(H[m])) for a in range(3))
                      for z in sols[m][1]]
            assert sum(inside) == 1, (C[m].tolist(), Rho[m].tolist(), Zp[m].tolist(), float(H[m]), inside)
