"""The enclosures that :mod:`runtime.voronoi.verify.conic_vertices` hands to the kernel's float
Krawczyk test, checked against 40-digit values of the sites' distance functions.

For F(q) = (d_i − d_j, d_i − d_k)(q) and a square c + [−ρ, ρ]², the test needs |F(c)| ≤ F_rad and
|J(q) − A| ≤ J_rad entrywise for every q of the square (A the float Jacobian at c).  The reference
distance of q to a conic Q(x, y) = Ax² + Bxy + Cy² + Dx + Ey + F = 0 is |q − p| with p the
solution of the Lagrange system q − p = λ∇Q(p), Q(p) = 0 found by mpmath at 40 digits from a
float start, its gradient (q − p)/|q − p| (q outside the convex ellipse: the nearest point is the
unique critical point on the near side).  Centres c are taken off the vertex (F(c) ≠ 0) and at
vertices whose Jacobian is nearly singular (a vertex 4 000 scene units from its sites, where the
rows G_i − G_j and G_i − G_k are nearly parallel), where the float Jacobian alone is far from
the Jacobians over the square.
"""
from __future__ import annotations

import sys
from pathlib import Path

import mpmath
import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))

from scenes import random_ellipses  # noqa: E402

from curvedvoronoi.runtime.sites.conic import Conic  # noqa: E402
from curvedvoronoi.runtime.voronoi.conic_geometry import site_geometry  # noqa: E402
from curvedvoronoi.runtime.voronoi.verify.conic_vertices import RHOS, vertex_enclosures  # noqa: E402
from curvedvoronoi.runtime.voronoi.verify.curved_edges import curved_scale  # noqa: E402
from curvedvoronoi.runtime.voronoi.verify.site_table import SiteTable  # noqa: E402



pytestmark = pytest.mark.mpmath_dps(40)


@pytest.fixture(autouse=True)
def _mpmath_digits():
    """40 digits for this module's references, restored after each test (another module's
    setting must not leak in, nor this one out)."""
    with mpmath.workdps(40):
        yield


def _foot(conic, q, start):
    """The nearest point of the ellipse to q (outside it), 40 digits: Lagrange system from ``start``."""
    A, B, C, D, E, F = (mpmath.mpf(int(v.numerator)) / int(v.denominator) if hasattr(v, "numerator")
                        else mpmath.mpf(v) for v in conic.coefficients)
    qx, qy = mpmath.mpf(q[0]), mpmath.mpf(q[1])

    def eqs(x, y, lam):
        gx, gy = 2 * A * x + B * y + D, B * x + 2 * C * y + E
        return [qx - x - lam * gx, qy - y - lam * gy, A * x * x + B * x * y + C * y * y + D * x + E * y + F]

    x0, y0 = mpmath.mpf(start[0]), mpmath.mpf(start[1])
    gx, gy = 2 * A * x0 + B * y0 + D, B * x0 + 2 * C * y0 + E
    lam0 = ((qx - x0) * gx + (qy - y0) * gy) / (gx * gx + gy * gy)
    x, y, _ = mpmath.findroot(eqs, (x0, y0, lam0), tol=mpmath.mpf(10) ** -35)
    return x, y


def _reference(sites, geoms, trip, q):
    """40-digit (d_i, d_j, d_k) and gradients at q."""
    d, G = [], []
    for k in trip:
        start = geoms[k].foot_points(np.array([q], float))[0][0]
        x, y = _foot(sites[k], q, start)
        vx, vy = mpmath.mpf(q[0]) - x, mpmath.mpf(q[1]) - y
        n = mpmath.sqrt(vx * vx + vy * vy)
        d.append(n)
        G.append((vx / n, vy / n))
    return d, G


def _three_ellipses():
    return [Conic.ellipse(centre=(0, 0), axes=(3, 1), rotation=(1, 0)),
            Conic.ellipse(centre=(9, 1), axes=(2, 1), rotation=("3/5", "4/5")),
            Conic.ellipse(centre=(4, 8), axes=("5/2", "3/2"), rotation=("4/5", "-3/5"))]


def _cases():
    """(sites, triple, vertex) for a vertex near its sites and one 4 000 units out."""
    import curvedvoronoi as cv

    out = []
    s3 = _three_ellipses()
    d3 = cv.voronoi(s3, certify=False)
    v = d3.vertices[0]
    out.append((s3, tuple(v.sites), (v.x, v.y)))
    s200 = random_ellipses(200, 1)
    d200 = cv.voronoi(s200, certify=False)
    far = max(d200.vertices, key=lambda w: w.radius)
    assert far.radius > 1000
    out.append((s200, tuple(far.sites), (far.x, far.y)))
    return out


@pytest.fixture(scope="module")
def cases():
    return _cases()


@pytest.mark.parametrize("offset", [0.0, 1e-9, 1e-6])
def test_the_residual_bound_holds_off_the_vertex(cases, offset):
    """|F_b(c)| ≤ F_rad_b at centres c = vertex + offset·(1, −1)·(1 + |v|): the distance bounds
    enclose F(c) however far from 0 it is."""
    for sites, trip, v in cases:
        geoms = [site_geometry(s) for s in sites]
        table = SiteTable(geoms, curved_scale(geoms))
        size = 1 + abs(v[0]) + abs(v[1])
        c = np.array([v[0] + offset * size, v[1] - offset * size])
        _, F_rad, _, valid = vertex_enclosures(table, c, [trip], [RHOS[0] * size], table.scale)
        assert valid[0]
        d, _ = _reference(sites, geoms, trip, c)
        F_true = [abs(d[0] - d[1]), abs(d[0] - d[2])]
        for b in range(2):
            assert F_true[b] <= mpmath.mpf(F_rad[0, b]), (trip, b, F_true[b], F_rad[0, b])
        if offset:
            # the bound is not slack by a factor 4: the test above is sharp where F(c) is large
            assert max(F_true) > mpmath.mpf(F_rad[0].max()) / 4


@pytest.mark.parametrize("rel", sorted(set(RHOS)))
def test_the_jacobian_bound_holds_over_the_square(cases, rel):
    """|J(q) − A| ≤ J_rad entrywise at the centre, the corners and the side midpoints of every
    tried square c + [−ρ, ρ]², J(q) from the 40-digit gradients."""
    for sites, trip, v in cases:
        geoms = [site_geometry(s) for s in sites]
        table = SiteTable(geoms, curved_scale(geoms))
        c = np.array(v, float)
        rho = rel * (1 + abs(v[0]) + abs(v[1]) + float(geoms[trip[0]].distance(c[None, :])[0]))
        A, _, J_rad, valid = vertex_enclosures(table, c, [trip], [rho], table.scale)
        assert valid[0]
        worst = mpmath.mpf(0)
        for sx in (-1, 0, 1):
            for sy in (-1, 0, 1):
                q = (mpmath.mpf(c[0]) + sx * mpmath.mpf(rho), mpmath.mpf(c[1]) + sy * mpmath.mpf(rho))
                _, G = _reference(sites, geoms, trip, q)
                J = [[G[0][0] - G[1][0], G[0][1] - G[1][1]], [G[0][0] - G[2][0], G[0][1] - G[2][1]]]
                for a in range(2):
                    for b in range(2):
                        dev = abs(J[a][b] - mpmath.mpf(A[0, a, b]))
                        assert dev <= mpmath.mpf(J_rad[0, a, b]), (trip, rel, sx, sy, a, b, dev, J_rad[0, a, b])
                        worst = max(worst, dev / (2 * mpmath.mpf(2) ** -53 * abs(mpmath.mpf(A[0, a, b]))))
        # the Jacobians over the square are not within the float subtraction's rounding of A:
        # the gradient slack over the square is needed
        assert worst > 1, worst
