"""Krawczyk existence-and-uniqueness proofs for a Voronoi vertex (foot-point formulation).

The system is the "original curves" formulation of thesis §6.1 (App. D.1), here used only as
a *verifier* around a numeric candidate (the thesis' branch and prune, ch. 6, searches with it).
Unknowns z = (x, y, x1, y1, x2, y2, x3, y3): the vertex q and one foot point p_i per conic C_i;

    f_i(p_i) = 0,   (x − x_i) ∂_y f_i(p_i) − (y − y_i) ∂_x f_i(p_i) = 0      (i = 1, 2, 3)
    |q − p_1|² − |q − p_2|² = 0,   |q − p_1|² − |q − p_3|² = 0.

Every equation has degree ≤ 2 with the *exact* rational coefficients of the conics, whatever
their type, so no (possibly irrational) canonical frame is needed.  Krawczyk's theorem
(Moore 1977; thesis §3.3.3): with m ∈ X, any matrix Y,

    K(X) = m − Y F(m) + (I − Y J(X)) (X − m) ⊂ int X   ⇒   F has exactly one zero in X,

where J(X) encloses the Jacobian over X.  Everything is evaluated with python-flint ``arb``.
"""
from __future__ import annotations

from fractions import Fraction

from flint import arb, arb_mat

from .foot import to_arb
from .interval_newton import KrawczykFailure, krawczyk_inflation

__all__ = ["FootSystem", "KrawczykFailure"]


class FootSystem:
    """The 8×8 foot-point system of three conics with exact (normalised) coefficients."""

    def __init__(self, coefficient_triples: list[tuple[Fraction, ...]]):
        if len(coefficient_triples) != 3:
            raise ValueError("the foot-point system needs exactly three conics")
        self.exact = [tuple(c) for c in coefficient_triples]

    def _co(self):
        return [tuple(to_arb(v) for v in co) for co in self.exact]

    def residual(self, z: list[arb]) -> list[arb]:
        x, y = z[0], z[1]
        out = []
        sq = []
        for i, (a, b, c, d, e, f) in enumerate(self._co()):
            xi, yi = z[2 + 2 * i], z[3 + 2 * i]
            fx = 2 * a * xi + b * yi + d
            fy = b * xi + 2 * c * yi + e
            out.append(a * xi * xi + b * xi * yi + c * yi * yi + d * xi + e * yi + f)
            out.append((x - xi) * fy - (y - yi) * fx)
            dx, dy = x - xi, y - yi
            sq.append(dx * dx + dy * dy)  # not ** 2: arb's pow is NaN on a ball containing 0
        out.append(sq[0] - sq[1])
        out.append(sq[0] - sq[2])
        return out

    def jacobian(self, z: list[arb]) -> arb_mat:
        x, y = z[0], z[1]
        J = [[arb(0)] * 8 for _ in range(8)]
        for i, (a, b, c, d, e, f) in enumerate(self._co()):
            xi, yi = z[2 + 2 * i], z[3 + 2 * i]
            cx, cy = 2 + 2 * i, 3 + 2 * i
            fx = 2 * a * xi + b * yi + d
            fy = b * xi + 2 * c * yi + e
            r0, r1 = 2 * i, 2 * i + 1
            J[r0][cx], J[r0][cy] = fx, fy
            J[r1][0], J[r1][1] = fy, -fx
            J[r1][cx] = -fy + (x - xi) * b - (y - yi) * 2 * a
            J[r1][cy] = (x - xi) * 2 * c + fx - (y - yi) * b
        x1, y1 = z[2], z[3]
        for row, k in ((6, 4), (7, 6)):
            xk, yk = z[k], z[k + 1]
            J[row][0], J[row][1] = 2 * (xk - x1), 2 * (yk - y1)
            J[row][2], J[row][3] = -2 * (x - x1), -2 * (y - y1)
            J[row][k], J[row][k + 1] = 2 * (x - xk), 2 * (y - yk)
        return arb_mat(J)

    # ------------------------------------------------------------------ numerics
    def newton(self, z: list, prec_bits: int, iters: int = 12) -> list[arb]:
        """Newton's method on exact midpoints (no rigour needed: Krawczyk checks the result)."""
        z = [arb(v).mid() for v in z]
        tol = arb(2) ** (-prec_bits + 8)
        for _ in range(iters):
            Fm = arb_mat([[v] for v in self.residual(z)])
            try:
                step = self.jacobian(z).solve(Fm)
            except ZeroDivisionError:
                raise KrawczykFailure("singular Jacobian in Newton's method") from None
            z = [(zi - step[i, 0]).mid() for i, zi in enumerate(z)]
            scale = max(abs(float(v.mid())) for v in z) + 1.0
            if all((abs(step[i, 0]) < tol * scale) for i in range(8)):
                break
        return z

    def krawczyk(self, m: list[arb], attempts: int = 6) -> list[arb]:
        """A box around the exact point m proved to hold exactly one zero (else KrawczykFailure).

        Returns the enclosure K ∩ X; the (larger) box X in which the zero is unique is kept in
        ``self.last_uniqueness_box``.  The test is :func:`runtime.certify.interval_newton.krawczyk_inflation`."""
        enclosure, X = krawczyk_inflation(self.residual, lambda z: self.jacobian(z).tolist(), m,
                                          attempts=attempts, floor_bits=24)
        self.last_uniqueness_box = X
        return enclosure
