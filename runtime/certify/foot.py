"""Rigorous point-to-conic distances through the Lagrange (foot-point) polynomial.

Thesis §4.1 defines the generalised offset of a curve through its *foot points*: the points
p of the conic C: pᵀAp + 2bᵀp + f = 0 (A = [[a, b/2], [b/2, c]], b = (d/2, e/2)) at which
q − p is normal to C.  The normality condition with a Lagrange multiplier λ reads

    p − q = −λ (A p + b)   ⇔   M(λ) p = q − λ b,   M(λ) = I + λ A,

so p(λ) = adj M(λ) (q − λ b) / det M(λ) and, substituting into the conic,

    F_q(λ) = wᵀ A w + 2 det M · bᵀ w + f · det M²,      w = adj M(λ) (q − λ b),

a polynomial of degree ≤ 4 in λ whose coefficients are exact rational polynomials in q.
Facts used by the certificates (proved in the module docstring of :mod:`runtime.certify.conflicts`):

* a *real* foot point has a *real* λ (for p real, A p + b ≠ 0 because the centre is not on a
  non-degenerate conic), and conversely a real root λ with det M(λ) ≠ 0 gives a real foot point;
* foot points with det M(λ₀) = 0 exist only if F_q(λ₀) = 0 (then w(λ₀) = 0), so if no real root of
  F_q makes det M vanish, the real roots of F_q list *all* real foot points;
* the squared distance to p(λ) is D(λ) = N(λ) / det M(λ)², N(λ) = |w − det M · q|².

Hence d(q, C)² = min over the real roots λ of F_q of D(λ), which this module encloses with
ball arithmetic (python-flint ``acb_poly.roots`` gives isolating balls; reality is proved with
conjugation-symmetric isolating boxes) or decides exactly for rational q (``fmpq_poly``).

Length: the Lagrange polynomial, its exact and ball forms and the isolation of its real roots are
one procedure; the proofs of the enclosures refer to each other.
"""
from __future__ import annotations

from contextlib import contextmanager
from dataclasses import dataclass
from fractions import Fraction
from functools import lru_cache

import flint
from flint import acb, acb_poly, arb, arb_poly, fmpq, fmpq_poly

__all__ = ["FootPolynomial", "foot_polynomial", "working_prec", "RealFoot", "real_feet_ball",
           "exact_polynomials", "to_arb", "normalised_coefficients", "FootFailure"]

Poly3 = dict  # {(i, j, k): Fraction}, monomial X^i Y^j L^k


@contextmanager
def working_prec(prec: int):
    """Set python-flint's working precision (bits) for the block."""
    old = flint.ctx.prec
    flint.ctx.prec = int(prec)
    try:
        yield
    finally:
        flint.ctx.prec = old


def to_arb(q: Fraction) -> arb:
    """Ball containing the rational q (rounded at the current precision)."""
    return arb(fmpq(q.numerator, q.denominator))


def normalised_coefficients(conic) -> tuple[Fraction, ...]:
    """Exact coefficients of a Conic (or a 6-sequence), scaled by an exact power of two so that the
    largest has magnitude in [1/2, 1) -- the same curve, better balanced balls."""
    co = getattr(conic, "coefficients", conic)
    co = tuple(Fraction(c) for c in co)
    if len(co) != 6:
        raise ValueError(f"a conic needs 6 coefficients (a, b, c, d, e, f), got {len(co)}")
    if not any(co[:3]):
        raise ValueError("not a conic: a = b = c = 0")
    m = max(abs(c) for c in co)
    e = m.numerator.bit_length() - m.denominator.bit_length() + 1
    s = Fraction(1, 2 ** e) if e >= 0 else Fraction(2 ** -e)
    return tuple(c * s for c in co)


# --------------------------------------------------------------------------- exact poly algebra

def _add(p: Poly3, q: Poly3, s: Fraction = Fraction(1)) -> Poly3:
    out = dict(p)
    for k, v in q.items():
        out[k] = out.get(k, 0) + s * v
    return {k: v for k, v in out.items() if v != 0}


def _mul(p: Poly3, q: Poly3) -> Poly3:
    out: dict = {}
    for (i1, j1, k1), v1 in p.items():
        for (i2, j2, k2), v2 in q.items():
            key = (i1 + i2, j1 + j2, k1 + k2)
            out[key] = out.get(key, 0) + v1 * v2
    return {k: v for k, v in out.items() if v != 0}


def _c(v) -> Poly3:
    v = Fraction(v)
    return {(0, 0, 0): v} if v else {}


X: Poly3 = {(1, 0, 0): Fraction(1)}
Y: Poly3 = {(0, 1, 0): Fraction(1)}
L: Poly3 = {(0, 0, 1): Fraction(1)}


def _by_power(p: Poly3) -> list[list[tuple[int, int, Fraction]]]:
    deg = max((k for (_, _, k) in p), default=-1)
    out: list[list] = [[] for _ in range(deg + 1)]
    for (i, j, k), v in p.items():
        out[k].append((i, j, v))
    return out


@dataclass(frozen=True)
class FootPolynomial:
    """F_q(λ), N_q(λ) and det M(λ) of one conic, with coefficients polynomial in q = (X, Y)."""

    coefficients: tuple[Fraction, ...]
    F: tuple  # per power of λ: list of (i, j, coef)
    N: tuple
    det: tuple[Fraction, ...]  # det M(λ), coefficients in λ (no q dependence)

    @property
    def is_circle(self) -> bool:
        return self.coefficients[0] == self.coefficients[2] and self.coefficients[1] == 0

    # ---------------------------------------------------------------- ball evaluation
    def _eval(self, groups, x, y, powx, powy):
        out = []
        for grp in groups:
            s = 0
            for i, j, v in grp:
                s = s + to_arb(v) * powx[i] * powy[j]
            out.append(s if grp else arb(0))
        return out

    def at_ball(self, x: arb, y: arb):
        """(F coefficients, N coefficients) as arb lists (low → high) at the ball point (x, y)."""
        powx, powy = [arb(1)], [arb(1)]
        for _ in range(8):
            powx.append(powx[-1] * x)
            powy.append(powy[-1] * y)
        return self._eval(self.F, x, y, powx, powy), self._eval(self.N, x, y, powx, powy)

    def at_rational(self, x: Fraction, y: Fraction):
        """(F, N) as exact fmpq_poly at the rational point (x, y)."""
        def ev(groups):
            return fmpq_poly([fmpq(*_nd(sum((v * x ** i * y ** j for i, j, v in grp), Fraction(0))))
                              for grp in groups])
        return ev(self.F), ev(self.N)

    def det_poly_exact(self) -> fmpq_poly:
        return fmpq_poly([fmpq(*_nd(v)) for v in self.det])

    def det_at(self, lam):
        d = self.det
        return to_arb(d[0]) + lam * (to_arb(d[1]) + lam * to_arb(d[2]))

    def foot_point(self, lam, x, y):
        """p(λ) for the ball (or acb) λ: adj M (q − λ b) / det M (circles: reduced forms)."""
        a, b, c, d, e, _ = (to_arb(v) for v in self.coefficients)
        sx, sy = x - lam * d / 2, y - lam * e / 2
        dm = self.det_at(lam)
        if self.is_circle:
            return sx / dm, sy / dm, dm
        wx = (1 + lam * c) * sx - lam * b / 2 * sy
        wy = -lam * b / 2 * sx + (1 + lam * a) * sy
        return wx / dm, wy / dm, dm

    def lagrange(self, px, py, x, y):
        """λ = −(p − q)·g / |g|², g = A p + b (the multiplier of a foot point p of q)."""
        a, b, c, d, e, _ = (to_arb(v) for v in self.coefficients)
        gx = a * px + b / 2 * py + d / 2
        gy = b / 2 * px + c * py + e / 2
        return -((px - x) * gx + (py - y) * gy) / (gx * gx + gy * gy)


def _nd(v: Fraction) -> tuple[int, int]:
    return (v.numerator, v.denominator)


@lru_cache(maxsize=512)
def foot_polynomial(coefficients: tuple[Fraction, ...]) -> FootPolynomial:
    """Build F, N, det M exactly for the (normalised) coefficients a..f (thesis §4.1)."""
    a, b, c, d, e, f = coefficients
    h = Fraction(1, 2)
    sx = _add(X, _mul(_c(-d * h), L))
    sy = _add(Y, _mul(_c(-e * h), L))
    if a == c and b == 0:
        # circle: M(λ) = (1 + aλ) I; divide the common factor (1 + aλ) out of adj M and det M
        # (otherwise F_q has the spurious double root λ = −1/a for every q)
        det = _add(_c(1), _mul(_c(a), L))
        m11 = m22 = _c(1)
        m12 = {}
    else:
        det = _add(_add(_c(1), _mul(_c(a + c), L)), _mul(_c(a * c - b * b / 4), _mul(L, L)))
        m11 = _add(_c(1), _mul(_c(c), L))
        m22 = _add(_c(1), _mul(_c(a), L))
        m12 = _mul(_c(-b * h), L)
    wx = _add(_mul(m11, sx), _mul(m12, sy))
    wy = _add(_mul(m12, sx), _mul(m22, sy))
    Aw_x = _add(_mul(_c(a), wx), _mul(_c(b * h), wy))
    Aw_y = _add(_mul(_c(b * h), wx), _mul(_c(c), wy))
    F = _add(_mul(wx, Aw_x), _mul(wy, Aw_y))
    F = _add(F, _mul(_mul(_c(2), det), _add(_mul(_c(d * h), wx), _mul(_c(e * h), wy))))
    F = _add(F, _mul(_c(f), _mul(det, det)))
    rx = _add(wx, _mul(det, X), Fraction(-1))
    ry = _add(wy, _mul(det, Y), Fraction(-1))
    N = _add(_mul(rx, rx), _mul(ry, ry))
    dl = [Fraction(0)] * 3
    for (_, _, k), v in det.items():
        dl[k] = v
    return FootPolynomial(tuple(coefficients), tuple(tuple(g) for g in _by_power(F)),
                          tuple(tuple(g) for g in _by_power(N)), tuple(dl))


# --------------------------------------------------------------------------- real feet

@dataclass
class RealFoot:
    """One real foot point: isolating ball of λ, the point p, and the squared distance D.

    ``possible=True`` marks an enclosure from a cluster zone around a singular multiplier
    (q on or near a symmetry axis): the point may not exist, so it can only *rule out* closer
    points (D > R), never prove one."""

    lam: arb
    px: arb
    py: arb
    D: arb
    possible: bool = False


class FootFailure(Exception):
    """The real feet could not be enclosed rigorously at this precision (near-degenerate q)."""


def _acb_real_roots(poly: acb_poly, deg: int) -> list[arb]:
    """Isolating enclosures of all real roots of a real polynomial given by ball coefficients.

    Every root ball from ``acb_poly.roots`` holds exactly one root (validated by Arb); a root is
    proved real when the conjugation-symmetric hull of its ball meets no other ball, proved
    non-real when its imaginary part excludes 0.  Otherwise :class:`FootFailure`.
    """
    try:
        roots = poly.roots()
    except ValueError as exc:
        raise FootFailure(f"roots not isolated ({exc})") from None
    if len(roots) != deg:
        raise FootFailure("root count mismatch")
    P = arb_poly([c.real for c in poly.coeffs()])
    reals = []
    for i, z in enumerate(roots):
        im = z.imag
        if not im.contains(0):
            continue
        hull = acb(z.real, arb(0, im.abs_upper()))
        if any(hull.overlaps(w) for j, w in enumerate(roots) if j != i):
            raise FootFailure("cannot separate a root from its conjugate")
        reals.append(_newton_contract(P, z.real))
    return reals


def _newton_contract(P: arb_poly, r: arb, steps: int = 80) -> arb:
    """Interval Newton contraction of the isolating interval r of a simple real root of the
    ball polynomial (every root of every polynomial in the ball stays enclosed).  P'(r) comes
    from the Taylor form at the midpoint; while it still contains 0 (wide isolating interval),
    the interval is bisected on the sign of P (r holds exactly one root, a simple one, so P
    changes sign across it)."""
    for _ in range(steps):
        m = arb(r.mid())
        _, dI = _taylor_enclosures(P, m, r)
        if dI.contains(0):
            lo, hi = arb(r.lower()), arb(r.upper())
            if not (hi > m and m > lo):
                break
            fl, fm, fh = P(lo), P(m), P(hi)
            if (fl < 0 and fm > 0) or (fl > 0 and fm < 0):
                r = lo.union(m)
            elif (fm < 0 and fh > 0) or (fm > 0 and fh < 0):
                r = m.union(hi)
            else:
                break
            continue
        nr = m - P(m) / dI
        if not nr.overlaps(r):
            raise FootFailure("interval Newton excluded an isolated root")
        nr = nr.intersection(r)
        if not nr.rad() < r.rad() * 0.75:
            return nr
        r = nr
    return r


def _hull(a: arb, b: arb) -> arb:
    return a.union(b)


def _subdivide_real_roots(P: arb_poly, lo: arb, hi: arb, zones: list[arb], max_steps: int = 6000):
    """Real roots of the ball polynomial P in [lo, hi] outside the ``zones`` (exclusion intervals):
    bisection with exclusion (0 ∉ P(I), centred form) and monotonicity (0 ∉ P'(I)) tests.
    Returns isolating intervals (one simple root each) or raises FootFailure (cluster)."""
    tiny = (abs(lo) + abs(hi) + 1) * arb(2) ** (-flint.ctx.prec + 12)
    out, stack, steps = [], [(lo, hi)], 0
    while stack:
        steps += 1
        if steps > max_steps:
            raise FootFailure("real root isolation did not terminate")
        a, b = stack.pop()
        if not b > a:
            continue
        # cut out exclusion zones
        cut = False
        for Z in zones:
            zl, zh = Z.lower(), Z.upper()
            if zh <= a or zl >= b:
                continue
            if zl > a:
                stack.append((a, zl))
            if zh < b:
                stack.append((zh, b))
            cut = True
            break
        if cut:
            continue
        I = _hull(a, b)
        m = arb(I.mid())
        FI, dI = _taylor_enclosures(P, m, I)
        if not FI.contains(0):
            continue
        if not dI.contains(0):
            fa, fb = P(a), P(b)
            if (fa < 0 and fb > 0) or (fa > 0 and fb < 0):
                out.append(I)
                continue
            if (fa > 0 and fb > 0) or (fa < 0 and fb < 0):
                continue
        if not (b - a) > tiny:
            raise FootFailure("cluster of real roots (q near the evolute or an axis)")
        c = arb((a + (b - a) * arb("0.4990234375")).mid())
        stack.append((a, c))
        stack.append((c, b))
    return [_newton_contract(P, r) for r in out]


def _taylor_enclosures(P: arb_poly, m: arb, I: arb) -> tuple[arb, arb]:
    """Enclosures of P(I) and P'(I) from the Taylor expansion of P at the point m ∈ I:
    P(m + h) = Σ t_k h^k with t_k = P^(k)(m)/k! and h ∈ I − m.  Unlike Horner's scheme on the
    interval (whose overestimation is O(|I|·|P|) and does not shrink near a multiple root
    far from 0) the overestimation is O(|I|·|P''|), so intervals next to a cluster of roots
    (the zones around singular multipliers) are excluded after O(log) bisections."""
    t = list(P.coeffs())  # repeated synthetic division by (λ − m): Taylor coefficients at m
    n = len(t)
    for k in range(n - 1):
        for j in range(n - 2, k - 1, -1):
            t[j] = t[j] + m * t[j + 1]
    r = (I - m).abs_upper()
    hk = [arb(1)]
    for _ in range(n):
        hk.append(arb(0, hk[-1].rad() * r if len(hk) > 1 else r))
    val = t[0] if n else arb(0)
    der = arb(0)
    for k in range(1, n):
        val = val + t[k] * hk[k]
        der = der + k * t[k] * hk[k - 1]
    return val, der


def _root_bound(P: arb_poly) -> arb:
    cs = P.coeffs()
    lead = abs(cs[-1]).lower()
    return (1 + max(abs(c).upper() for c in cs[:-1]) / lead).upper()


def _eig_data(fp: "FootPolynomial"):
    """Eigen-decomposition of A (balls): list of (μ0, e0, μ1, e1) for each nonzero μ0."""
    a, b, c = (to_arb(v) for v in fp.coefficients[:3])
    disc = ((a - c) ** 2 + b * b).sqrt()
    mus = [(a + c + disc) / 2, (a + c - disc) / 2]
    out = []
    for k, mu in enumerate(mus):
        if fp.coefficients[0] * fp.coefficients[2] - fp.coefficients[1] ** 2 / 4 == 0 and k == 1:
            continue  # parabola: the zero eigenvalue gives no singular multiplier
        # eigenvector of mu: (b/2, mu − a) or (mu − c, b/2), the better conditioned one
        v1 = (b / 2, mu - a)
        v2 = (mu - c, b / 2)
        n1 = v1[0] ** 2 + v1[1] ** 2
        n2 = v2[0] ** 2 + v2[1] ** 2
        v, n = (v1, n1) if n1.mid() > n2.mid() else (v2, n2)
        if not n > 0:
            raise FootFailure("eigenvector not separated from 0")
        s = n.sqrt()
        e0 = (v[0] / s, v[1] / s)
        e1 = (-e0[1], e0[0])
        out.append((mu, e0, mus[1 - k], e1))
    return out


def _cluster_feet(fp: "FootPolynomial", Z: arb, mu0, e0, mu1, e1, x, y) -> list[RealFoot]:
    """Enclosures of every real foot point whose multiplier lies in the zone Z around λ0 = −1/μ0:
    in eigen-coordinates p1 = (q1 − λβ1)/(1 + λμ1) and μ0 p0² + 2β0 p0 + μ1 p1² + 2β1 p1 + f = 0."""
    d, e, f = (to_arb(v) for v in fp.coefficients[3:])
    bx, by = d / 2, e / 2
    q0, q1 = e0[0] * x + e0[1] * y, e1[0] * x + e1[1] * y
    b0, b1 = e0[0] * bx + e0[1] * by, e1[0] * bx + e1[1] * by
    den = 1 + Z * mu1
    if den.contains(0):
        raise FootFailure("cluster zone meets the second singular multiplier")
    p1 = (q1 - Z * b1) / den
    disc = b0 * b0 - mu0 * (mu1 * p1 * p1 + 2 * b1 * p1 + f)
    if disc < 0:
        return []
    sq = disc.nonnegative_part().sqrt()
    out = []
    for sg in (1, -1):
        p0 = (-b0 + sg * sq) / mu0
        px, py = p0 * e0[0] + p1 * e1[0], p0 * e0[1] + p1 * e1[1]
        out.append(RealFoot(Z, px, py, (px - x) ** 2 + (py - y) ** 2, possible=True))
    return out


def real_feet_ball(fp: "FootPolynomial", x: arb, y: arb, zones_out: list | None = None) -> list[RealFoot]:
    """All real foot points of the ball point (x, y) on the conic, with squared distances.

    First Arb's complex root isolation; if the roots cannot be separated (typically q on a
    symmetry axis of the conic, where F_q has a double root at a singular multiplier λ0 whose
    feet are a conjugate pair), real root isolation by subdivision outside small zones around
    the singular multipliers, and rigorous enclosures of the feet inside the zones."""
    Fc, Nc = fp.at_ball(x, y)
    while Fc and Fc[-1].is_zero():
        Fc.pop()
    deg = len(Fc) - 1
    if deg < 1 or Fc[-1].contains(0):
        raise FootFailure("leading coefficient of the foot polynomial not separated from 0")
    try:
        lams = _acb_real_roots(acb_poly([acb(c) for c in Fc]), deg)
        return [_foot(fp, lam, x, y) for lam in lams]
    except FootFailure:
        pass
    P = arb_poly(Fc)
    B = _root_bound(P)
    zones, cl = [], []
    if not fp.is_circle:
        rho = (B + 1) * arb(2) ** (-(flint.ctx.prec // 4))
        for mu0, e0, mu1, e1 in _eig_data(fp):
            lam0 = -1 / mu0
            Z = lam0 + arb(0, rho.upper())
            zones.append(Z)
            if P(Z).contains(0):
                cl += _cluster_feet(fp, Z, mu0, e0, mu1, e1, x, y)
    lams = _subdivide_real_roots(P, -B, B, zones)
    if zones_out is not None:
        zones_out.extend(zones)
    return [_foot(fp, lam, x, y) for lam in lams] + cl


def _foot(fp: "FootPolynomial", lam: arb, x, y) -> RealFoot:
    px, py, dm = fp.foot_point(lam, x, y)
    if dm.contains(0):
        raise FootFailure("det(I + λA) not separated from 0 at a real root (q on a symmetry axis "
                          "inside the evolute)")
    D = (px - x) ** 2 + (py - y) ** 2
    return RealFoot(lam, px, py, D)


def exact_polynomials(fp: "FootPolynomial", x: Fraction, y: Fraction):
    """(F_q, N_q, det M) as exact fmpq_poly for a rational point q."""
    F, N = fp.at_rational(x, y)
    return F, N, fp.det_poly_exact()
