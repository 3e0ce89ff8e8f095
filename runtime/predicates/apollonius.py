"""Apollonius circles: exact solution of the systems (I)/(II) of thesis §3.1.2–§3.1.3.

For centres c_i (rational), "radii" ρ_i (elements of a quadratic tower, see
:mod:`runtime.algebra.quadtower`) and a sign pattern s = (1, s2, s3), the system

    |q - c_i|^2 - (ρ_i + s_i R)^2 = 0,   i = 1, 2, 3                      (thesis (II))

in the unknowns q = (x, y) and the signed expansion R is solved exactly as in the thesis:
subtracting the first equation from the two others gives two equations linear in (x, y, R)
(the Gröbner basis of Appendix A); x and y are linear in R and the first equation becomes a
quadratic in R.  All quantities stay in a quadratic tower; fractions keep a denominator whose
sign is decided exactly.  Degenerate positions (collinear or concentric centres, a vanishing
leading coefficient, a positive-dimensional solution set) are handled explicitly.

This module also gives the additively weighted point locator of §3.1.2, including the
multiplication matrix M_g of Appendix A (eigenvalues = values of g on the Apollonius circles).
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

from flint import fmpq, fmpq_mat

from ..sites.rationals import parse_rational
from ..algebra.quadtower import ONE, ZERO, Elem, Frac, QuadTower, frac_add, frac_sign, rational_sqrt
from ..result import LocatorError, LocatorResult, VoronoiVertex


@dataclass
class AlgebraicSolution:
    """One real solution of a system (II): q = (X/D, Y/D), signed expansion R = Rn/D."""

    tower: QuadTower
    X: Elem
    Y: Elem
    Rn: Elem
    D: Elem


@dataclass
class Family:
    """A positive-dimensional real solution set of a system (II).

    ``R_fixed`` is None when R runs over all reals along the family (a line of solutions),
    otherwise every member has expansion ``R_fixed`` (concentric centres: q on a circle).
    """

    R_fixed: Frac | None


@dataclass
class SystemSolutions:
    solutions: list[AlgebraicSolution] = field(default_factory=list)
    families: list[Family] = field(default_factory=list)


def _sqrt_in_tower(T: QuadTower, d: Elem) -> tuple[QuadTower, Elem]:
    """√d for d > 0 exactly: rational when d is a rational square, else a new generator."""
    if not isinstance(d, tuple):
        r = rational_sqrt(d)
        if r is not None:
            return T, r
    return T.extend(d)


def solve_system(T: QuadTower, centres, rho, r2, signs) -> SystemSolutions:
    """All real solutions of system (II) for one sign pattern (signs[0] must be +1).

    ``centres``: three (fmpq, fmpq); ``rho``: three tower elements with rho_i^2 = r2_i;
    ``r2``: three fmpq.  Returns the isolated real solutions and any positive-dimensional
    real family (the caller decides whether a family contains true Voronoi vertices).
    """
    assert signs[0] == 1
    out = SystemSolutions()
    c1 = centres[0]
    d = [(c[0] - c1[0], c[1] - c1[1]) for c in centres]
    # rows i = 2, 3 (indices 1, 2):  d_i . q' = mu_i + kappa_i R   (q' = q - c1)
    mu = [None] + [(d[i][0] ** 2 + d[i][1] ** 2 + r2[0] - r2[i]) / 2 for i in (1, 2)]
    kappa = [None] + [T.sub(rho[0], T.mul(fmpq(signs[i]), rho[i])) for i in (1, 2)]
    (d2x, d2y), (d3x, d3y) = d[1], d[2]
    det = d2x * d3y - d2y * d3x

    def emit(Tq: QuadTower, qpx: Elem, qpy: Elem, Rn: Elem, D: Elem):
        # back to absolute coordinates: q = c1 + q'
        out.solutions.append(
            AlgebraicSolution(Tq, Tq.add(qpx, Tq.mul(c1[0], D)), Tq.add(qpy, Tq.mul(c1[1], D)), Rn, D)
        )

    if det != 0:
        inv = 1 / det
        q0 = ((mu[1] * d3y - mu[2] * d2y) * inv, (d2x * mu[2] - d3x * mu[1]) * inv)
        qR = (
            T.mul(T.sub(T.mul(kappa[1], d3y), T.mul(kappa[2], d2y)), inv),
            T.mul(T.sub(T.mul(kappa[2], d2x), T.mul(kappa[1], d3x)), inv),
        )
        A = T.sub(T.add(T.sqr(qR[0]), T.sqr(qR[1])), ONE)
        Bh = T.sub(T.add(T.mul(q0[0], qR[0]), T.mul(q0[1], qR[1])), rho[0])
        C = q0[0] ** 2 + q0[1] ** 2 - r2[0]

        def emit_R(Tq: QuadTower, N: Elem, D: Elem):
            emit(Tq, Tq.add(Tq.mul(q0[0], D), Tq.mul(N, qR[0])), Tq.add(Tq.mul(q0[1], D), Tq.mul(N, qR[1])), N, D)

        sA = T.sign(A)
        if sA != 0:
            disc = T.sub(T.sqr(Bh), T.mul(A, C))
            sD = T.sign(disc)
            if sD < 0:
                return out
            if sD == 0:
                emit_R(T, T.neg(Bh), A)
                return out
            T2, g = _sqrt_in_tower(T, disc)
            emit_R(T2, T2.sub(g, Bh), A)
            emit_R(T2, T2.sub(T2.neg(g), Bh), A)
            return out
        if T.sign(Bh) != 0:
            emit_R(T, T.neg(C), T.mul(fmpq(2), Bh))
            return out
        if C != 0:
            return out
        out.families.append(Family(None))  # a whole line q0 + R qR of solutions
        return out

    # ---- collinear centres (det == 0)
    nz = [i for i in (1, 2) if d[i][0] != 0 or d[i][1] != 0]
    if not nz:
        # all three centres coincide: 0 = mu_i + kappa_i R
        ks = [i for i in (1, 2) if T.sign(kappa[i]) != 0]
        if not ks:
            if mu[1] != 0 or mu[2] != 0:
                return out
            raise LocatorError("two of C1, C2, C3 coincide")
        i = ks[0]
        l = 3 - i
        # consistency: mu_l kappa_i - kappa_l mu_i == 0
        if T.sign(T.sub(T.mul(mu[l], kappa[i]), T.mul(kappa[l], mu[i]))) != 0:
            return out
        R = Frac(fmpq(-1) * mu[i], kappa[i])
        # q on the circle of centre c1 and radius |rho1 + R|
        rad = frac_add(T, Frac(rho[0]), R)
        if frac_sign(T, rad) == 0:
            emit(T, ZERO, ZERO, R.num, R.den)
        else:
            out.families.append(Family(R))
        return out
    j = nz[0]
    l = 3 - j
    dj = d[j]
    nj = dj[0] ** 2 + dj[1] ** 2
    lam = (d[l][0] * dj[0] + d[l][1] * dj[1]) / nj
    kap = T.sub(kappa[l], T.mul(lam, kappa[j]))
    muc = mu[l] - lam * mu[j]
    if T.sign(kap) == 0:
        if muc != 0:
            return out
        # rank one: the three oriented circles are collinear in Laguerre (Minkowski) space;
        # solutions exist iff that line is isotropic, and then they form a line.
        zj = T.mul(fmpq(-signs[j]), rho[j])
        dz = T.sub(zj, T.neg(rho[0]))
        if T.sign(T.sub(nj, T.sqr(dz))) == 0:
            out.families.append(Family(None))
        return out
    # R = -muc / kap; q' on the line dj . q' = mu_j + kappa_j R, q' = p + t w with w ⊥ dj
    RN, RD = fmpq(-1) * muc, kap
    # p = dj (mu_j RD + kappa_j RN) / (nj RD)
    s_ = T.add(T.mul(mu[j], RD), T.mul(kappa[j], RN))
    P = Frac(s_, T.mul(nj, RD))  # p = dj * P
    # E = (rho1 + R)^2 - |p|^2 = (rho1 RD + RN)^2/RD^2 - nj P^2 ; t^2 = E / nj
    r1R = T.add(T.mul(rho[0], RD), RN)
    # common denominator (nj RD)^2 :  E*(nj RD)^2 = nj^2 r1R^2 - nj s_^2
    EN = T.sub(T.mul(nj * nj, T.sqr(r1R)), T.mul(nj, T.sqr(s_)))
    ED = T.sqr(T.mul(nj, RD))  # > 0
    sE = T.sign(EN)
    if sE < 0:
        return out
    # q' = dj * s_/(nj RD) + t * (-djy, djx),  t = ±sqrt(EN/ED/nj) = ±sqrt(EN*nj)/(nj*|nj RD|)
    Dq = T.mul(nj, T.mul(nj, RD))  # common denominator nj^2 RD (sign of RD)
    baseX = T.mul(dj[0] * nj, s_)
    baseY = T.mul(dj[1] * nj, s_)
    RnQ = T.mul(RN, nj * nj)  # R = RN/RD = RN nj^2 / Dq
    if sE == 0:
        emit(T, baseX, baseY, RnQ, Dq)
        return out
    T2, g = _sqrt_in_tower(T, T.mul(EN, nj))
    # t * Dq = ±sqrt(EN nj)/(nj |nj RD|) * nj^2 RD = ±sqrt(EN nj) * sign(RD)
    sRD = T.sign(RD)
    for sg in (1, -1):
        tD = T2.mul(fmpq(sg * sRD), g)
        emit(T2, T2.add(baseX, T2.mul(-dj[1], tD)), T2.add(baseY, T2.mul(dj[0], tD)), RnQ, Dq)
    return out


# =====================================================================================
# Additively weighted points (thesis §3.1.2, Appendix A)
# =====================================================================================


def _aw_site(p) -> tuple[fmpq, fmpq, fmpq]:
    if len(p) != 3:
        raise ValueError("a weighted point is (x, y, w)")
    return tuple(parse_rational(v, "weighted point coordinate") for v in p)  # type: ignore[return-value]


@dataclass
class AWVertex:
    """An additively weighted Voronoi vertex: δ(q, p_i) - w_i = r for i = 1, 2, 3."""

    sol: AlgebraicSolution

    @property
    def x(self) -> float:
        return _f(self.sol, self.sol.X)

    @property
    def y(self) -> float:
        return _f(self.sol, self.sol.Y)

    @property
    def r(self) -> float:
        return _f(self.sol, self.sol.Rn)


def _f(sol: AlgebraicSolution, num: Elem) -> float:
    from ..algebra.quadtower import frac_to_float

    return frac_to_float(sol.tower, Frac(num, sol.D))


def normalise_den(sol: AlgebraicSolution) -> AlgebraicSolution:
    T = sol.tower
    if T.sign(sol.D) < 0:
        return AlgebraicSolution(T, T.neg(sol.X), T.neg(sol.Y), T.neg(sol.Rn), T.neg(sol.D))
    return sol


def aw_vertices(P1, P2, P3) -> list[AWVertex]:
    """Additively weighted Voronoi vertices of three weighted points (thesis §3.1.2), exactly.

    The vertices are the real solutions (x, y, r) of the thesis system c'_i = 0 with
    w_i + r ≥ 0 for i = 1, 2, 3 (so that δ(q, p_i) = w_i + r); r is the signed expansion
    (r > 0: circle externally tangent to the three weight circles, r < 0: internally).
    Raises LocatorError for coincident sites or a continuum of equidistant points.
    """
    sites = [_aw_site(p) for p in (P1, P2, P3)]
    for i in range(3):
        for j in range(i):
            if sites[i][:2] == sites[j][:2]:
                raise LocatorError(
                    f"weighted points P{j + 1} and P{i + 1} have the same location: the additively weighted "
                    "bisector is empty or the whole plane"
                )
    T = QuadTower()
    centres = [(s[0], s[1]) for s in sites]
    w = [s[2] for s in sites]
    res = solve_system(T, centres, w, [x * x for x in w], (1, 1, 1))
    if res.families:
        raise LocatorError("degenerate weighted points: a continuum of additively weighted Voronoi vertices")
    verts = []
    for sol in res.solutions:
        sol = normalise_den(sol)
        Tq = sol.tower
        if all(Tq.sign(Tq.add(Tq.mul(wi, sol.D), sol.Rn)) >= 0 for wi in w):
            verts.append(AWVertex(sol))
    return verts


def locate_conflicts_aw(P1, P2, P3, P4, *, strict: bool = False) -> LocatorResult:
    """Exact Delaunay-graph conflict locator for additively weighted points (thesis §3.1.2).

    Each vertex reports radius = r (the signed expansion, i.e. the common additive distance
    δ(q, p_i) - w_i; negative for an internally tangent circle), distance_to_fourth =
    δ(q, p4) - w4 and in_conflict iff δ(q, p4) - w4 < r, decided exactly as
    g = (x4-x)^2+(y4-y)^2-(r+w4)^2 < 0 together with r + w4 > 0 (the thesis states only the
    sign of g; without r + w4 > 0 a negative g does not mean conflict when r + w4 < 0).
    ``tangent`` iff δ(q, p4) - w4 = r exactly.  With ``strict=True`` a triple with no vertex
    raises LocatorError (the thesis says Δ < 0 cannot happen for a Delaunay triangle).
    """
    t0 = time.perf_counter()
    verts = aw_vertices(P1, P2, P3)
    x4, y4, w4 = _aw_site(P4)
    t1 = time.perf_counter()
    notes = []
    if not verts:
        msg = ("no additively weighted Voronoi vertex: (P1, P2, P3) is not a Delaunay triangle "
               "(thesis §3.1.2 says this cannot occur in the incremental algorithm)")
        if strict:
            raise LocatorError(msg)
        notes.append(msg)
    out = []
    for v in verts:
        s = v.sol
        T = s.tower
        DX = T.sub(s.X, T.mul(x4, s.D))
        DY = T.sub(s.Y, T.mul(y4, s.D))
        D2 = T.add(T.sqr(DX), T.sqr(DY))
        S = T.add(s.Rn, T.mul(w4, s.D))  # (r + w4) * D, D > 0
        g = T.sub(D2, T.sqr(S))
        sg, sS = T.sign(g), T.sign(S)
        in_conflict = sg < 0 and sS > 0
        tangent = sg == 0 and sS >= 0
        r = v.r
        dist = _aw_dist(T, D2, s.D, w4, r, tangent)
        out.append(VoronoiVertex(x=v.x, y=v.y, radius=r, distance_to_fourth=dist, in_conflict=in_conflict,
                                 certified=True, tangent=tangent,
                                 info={"proof": "exact sign in Q(sqrt D)", "sign_g": sg, "sign_r_plus_w4": sS}))
    out.sort(key=lambda v: (v.x, v.y))
    t2 = time.perf_counter()
    return LocatorResult(conflict=any(v.in_conflict for v in out), vertices=out, method="aw-exact",
                         timings={"vertices": t1 - t0, "conflict": t2 - t1}, complete=True, notes=notes)


def _aw_dist(T: QuadTower, D2: Elem, D: Elem, w4: fmpq, r: float, tangent: bool) -> float:
    if tangent:
        return r
    from flint import ctx

    prec = 128
    while True:
        with ctx.workprec(prec):
            v = T._arb(D2, prec).sqrt() / T._arb(D, prec) - w4
        if v.rel_accuracy_bits() >= 60 or prec >= 4096:
            return float(v.mid())
        prec *= 2


def multiplication_matrix_aw(P1, P2, P3, P4) -> tuple[fmpq_mat, tuple[fmpq, fmpq, fmpq]]:
    """The matrix M_g of multiplication by g in Q[x, y, r]/<c'_1, c'_2, c'_3> (Appendix A).

    Basis of the quotient algebra: the standard monomials {1, r}; g = (x4-x)^2+(y4-y)^2-(r+w4)^2.
    The Gröbner basis is {x - (x0 + r xr), y - (y0 + r yr), A r^2 + 2 Bh r + C}.  Returns M_g
    (columns: normal forms of g·1 and g·r) and (A, 2Bh, C).  The eigenvalues of M_g are the
    values of g at the two (complex) Apollonius solutions; eq. (3.1.1) is its characteristic
    polynomial.  Only the generic case (non-collinear centres, A ≠ 0) has a 2-dimensional
    algebra with this basis; otherwise LocatorError.
    """
    sites = [_aw_site(p) for p in (P1, P2, P3, P4)]
    (x1, y1, w1), (x2, y2, w2), (x3, y3, w3), (x4, y4, w4) = sites
    d2x, d2y, d3x, d3y = x2 - x1, y2 - y1, x3 - x1, y3 - y1
    det = d2x * d3y - d2y * d3x
    if det == 0:
        raise LocatorError("collinear centres: the quotient algebra has no basis {1, r} of this form")
    mu2 = (d2x ** 2 + d2y ** 2 + w1 * w1 - w2 * w2) / 2
    mu3 = (d3x ** 2 + d3y ** 2 + w1 * w1 - w3 * w3) / 2
    k2, k3 = w1 - w2, w1 - w3
    x0 = (mu2 * d3y - mu3 * d2y) / det
    y0 = (d2x * mu3 - d3x * mu2) / det
    xr = (k2 * d3y - k3 * d2y) / det
    yr = (d2x * k3 - d3x * k2) / det
    A = xr * xr + yr * yr - 1
    B = 2 * (x0 * xr + y0 * yr - w1)
    C = x0 * x0 + y0 * y0 - w1 * w1
    if A == 0:
        raise LocatorError("the quadratic in r degenerates (A = 0): the algebra is not spanned by {1, r}")
    # g as a polynomial in r (translated coordinates, q' = q - p1)
    ex, ey = x0 - (x4 - x1), y0 - (y4 - y1)
    g2 = xr * xr + yr * yr - 1
    g1 = 2 * (ex * xr + ey * yr) - 2 * w4
    g0 = ex * ex + ey * ey - w4 * w4
    # reduce r^2 = -(B r + C)/A
    n0 = g0 - g2 * C / A
    n1 = g1 - g2 * B / A
    M = fmpq_mat(2, 2, [n0, -n1 * C / A, n1, n0 - n1 * B / A])
    return M, (A, B, C)
