"""A tight proved enclosure of ∇d(q, E) for a point q outside an ellipse site E.

The cheap enclosure of :func:`runtime.voronoi.verify.site_table.gradient_enclosure` bounds the
float foot point's error by the gap between the distance bounds, e_F = √(|q − F|² − lo²), which
is of order √(2 d·w) for bounds of width w: far from the sites (d ≈ 3·10⁴, w ≈ 10⁻⁹) it leaves
an error of 3·10⁻⁷ in ∇d, whatever the accuracy of F.  Here the foot point is enclosed through
its Lagrange multiplier instead (thesis §5.2, the normal condition; Eberly, *Distance from a
point to an ellipse*, 2011), which gives ∇d(q) to a few units of 10⁻¹⁴.

**The multiplier.**  In the exact canonical frame of E (X²/a² + Y²/b² = 1, a, b > 0) let
(X, Y) be the coordinates of q.  The nearest point p of the convex region K bounded by E
satisfies q − p = μ·(p_X/a², p_Y/b²) with μ ≥ 0 (Lagrange), i.e. p = (a²X/(a² + μ),
b²Y/(b² + μ)) and

    F(μ) = (aX/(a² + μ))² + (bY/(b² + μ))² − 1 = 0.

On μ > −min(a², b²) each term of F is non-increasing in μ, strictly unless its numerator is 0,
and F → −1 as μ → ∞.  **Claim**: if 0 < μ_lo < μ_hi with F(μ_lo) > 0 > F(μ_hi), then F has
exactly one zero μ* on (−min(a², b²), ∞), it lies in (μ_lo, μ_hi), q lies outside K
(F(0) ≥ F(μ_lo) > 0 is X²/a² + Y²/b² > 1), and ∇d(q) = N(μ*)/|N(μ*)| with
N(μ) = (X/(a² + μ), Y/(b² + μ)).  Proof: F(μ_lo) > 0 needs a non-zero term, so X or Y ≠ 0
and F is strictly decreasing there: the zero is unique and bracketed;
p(μ*) lies on E and q − p(μ*) = μ*·∇g(p)/2 with μ* > 0 is an outward normal at p, so q − p lies in
the normal cone of the convex K at p, which characterises p as the projection of q on K
(Schneider, *Convex Bodies*, §1.2); ∇d(q) = (q − p)/|q − p| = N(μ*)/|N(μ*)| since
q − p = μ*·N(μ*).

**Enclosure.**  The exact frame (cos θ, sin θ, t, a, b) of the site is known only as the float
frame the site geometry uses plus proved errors (:func:`frame_errors`, from the 128-bit balls of
:meth:`runtime.sites.conic.Conic.frame_arb` the float frame is rounded from).  With |X| ∈ [x_l,
x_h], |Y| ∈ [y_l, y_h], a ∈ [a_l, a_h], b ∈ [b_l, b_h] (rounding of the float transform of q
included), each term of F lies between (a_l x_l/(a_h² + μ))² and (a_h x_h/(a_l² + μ))², so
F(μ) ∈ [F⁻(μ), F⁺(μ)] for every frame in the box, and F⁻(μ_lo) > 0 > F⁺(μ_hi) proves the
claim for the exact frame.  Then N(μ*) lies in the box with |N_X| ∈ [x_l/(a_h² + μ_hi),
x_h/(a_l² + μ_lo)] (sign of X; both signs when x_l = 0), likewise N_Y; with centre N₀ and
half-diagonal h, |N/|N| − N₀/|N₀|| ≤ h/(|N₀| − h) (x ↦ m·x/|x| is the projection onto the
ball of radius m, 1-Lipschitz on |x| ≥ m).  The world gradient R(θ)·n is compared with the float
rotation: ‖R(θ) − R_f‖ ≤ |Δcos| + |Δsin|.  Every float expression is evaluated in
round-to-nearest with Higham's γ_n allowances (:mod:`runtime.certify.interval_newton`),
non-negative bounds widened by 4u relative plus an absolute 2^-1000 (underflow).

μ is found by float Newton steps on F from the float foot point (any value is sound: a bracket
that fails leaves the row to the cheap enclosure), and bracketed by μ ± δ/|F'(μ)| for δ = 2·10⁻¹⁴ … 10⁻⁸ (F changes by about ±δ
across), the tightest that is proved.
"""
from __future__ import annotations

import math
from typing import NamedTuple

import flint
import numpy as np

from ...certify.interval_newton import UNDERFLOW, UNIT_ROUNDOFF, gamma
from ...sites.frame import FRAME_PREC
from ...sites.kinds import SiteKind

__all__ = ["frame_errors", "ellipse_normal_enclosure", "multiplier_bounds", "tight_gradients", "BRACKETS"]

#: the multiplier brackets tried, tightest first: μ ± δ/|F'(μ)| (F changes by about δ across)
BRACKETS = (2e-14, 1e-12, 1e-10, 1e-8)

_U = UNIT_ROUNDOFF


def frame_errors(conic, c, s, tx, ty, a, b):
    """(e_c, e_s, e_tx, e_ty, e_a, e_b): upper bounds of |c − cos θ|, |s − sin θ|, |tx − t_x|,
    |ty − t_y|, |a − √A2|, |b − √B2| between the float frame (c, s, tx, ty, a, b) of an ellipse
    site and its exact canonical frame, from the 128-bit ball frame of ``conic``
    (:meth:`runtime.sites.conic.Conic.frame_arb`; each ball contains the exact value)."""
    with flint.ctx.workprec(FRAME_PREC):
        fr = conic.frame_arb(FRAME_PREC)
        balls = (fr.cos, fr.sin, fr.tx, fr.ty, fr.params["A2"].sqrt(), fr.params["B2"].sqrt())
        out = []
        for f, x in zip((c, s, tx, ty, a, b), balls):
            e = (flint.arb(float(f)) - x).abs_upper()
            v = float(e)            # rounds to nearest: one more relative 2^-52 up
            out.append(v * (1 + 2.0 ** -50) + 2.0 ** -1070 if math.isfinite(v) else math.inf)
    return tuple(out)


def _up(v):
    """An upper bound of the exact value of a non-negative float expression ``v`` of at most a
    few roundings already accounted for by the caller, plus this product's own rounding
    (the kernel's ``round_up`` widens by 2^-40 relative, too coarse here)."""
    return v * (1 + 4 * _U) + UNDERFLOW


def _lower(v, n):
    """A lower bound of an exact non-negative quantity whose float evaluation ``v`` took n
    roundings (relative error ≤ γ_n), itself rounded once more."""
    return np.maximum(v * (1 - 2 * gamma(n + 1)) - UNDERFLOW, 0.0)


def _upper(v, n):
    return _up(v * (1 + 2 * gamma(n + 1)))


def multiplier_bounds(mu, xl, xh, yl, yh, al, ah, bl, bh):
    """(F⁻, F⁺): F(μ) ∈ [F⁻, F⁺] for every |X| ∈ [xl, xh], |Y| ∈ [yl, yh], a ∈ [al, ah],
    b ∈ [bl, bh] (all ≥ 0; μ ≥ 0 exact floats), F as in the module docstring."""
    t1l = _lower((al * xl / (ah * ah + mu)) ** 2, 6)
    t2l = _lower((bl * yl / (bh * bh + mu)) ** 2, 6)
    t1h = _upper((ah * xh / (al * al + mu)) ** 2, 6)
    t2h = _upper((bh * yh / (bl * bl + mu)) ** 2, 6)
    Fl = (t1l + t2l - 1.0) - gamma(3) * (t1l + t2l + 1.0) - UNDERFLOW
    Fh = (t1h + t2h - 1.0) + gamma(3) * (t1h + t2h + 1.0) + UNDERFLOW
    return Fl, Fh


class _FrameBox(NamedTuple):
    """The float canonical coordinates (X0, Y0) of the query points and the box of the exact
    ones: |X| ∈ [xl, xh], |Y| ∈ [yl, yh], a ∈ [al, ah], b ∈ [bl, bh]; eX, eY bound |X − X0|,
    |Y − Y0| (module docstring, **Enclosure**)."""

    X0: np.ndarray
    Y0: np.ndarray
    eX: np.ndarray
    eY: np.ndarray
    xl: np.ndarray
    xh: np.ndarray
    yl: np.ndarray
    yh: np.ndarray
    al: np.ndarray
    ah: np.ndarray
    bl: np.ndarray
    bh: np.ndarray


def _frame_box(Q, a, b, c, s, tx, ty, errs) -> _FrameBox:
    """The exact canonical coordinates X = c*(x − tx*) + s*(y − ty*), Y likewise, and the exact
    axes, boxed from the float frame and its proved errors ``errs`` (:func:`frame_errors`): the
    data errors plus the float evaluation (three roundings per product term, Higham's γ₄)."""
    ec, es, etx, ety, ea, eb = errs.T
    x, y = Q[:, 0], Q[:, 1]
    dx, dy = x - tx, y - ty
    X0, Y0 = c * dx + s * dy, -s * dx + c * dy
    adx, ady = np.abs(dx) + etx, np.abs(dy) + ety
    rnd = 2 * gamma(4) * (np.abs(c) * np.abs(dx) + np.abs(s) * np.abs(dy))
    eX = _up(ec * adx + es * ady + np.abs(c) * etx + np.abs(s) * ety + rnd
                  + 2 * gamma(4) * (ec * adx + es * ady))
    rnd = 2 * gamma(4) * (np.abs(s) * np.abs(dx) + np.abs(c) * np.abs(dy))
    eY = _up(es * adx + ec * ady + np.abs(s) * etx + np.abs(c) * ety + rnd
                  + 2 * gamma(4) * (es * adx + ec * ady))
    xl, xh = np.maximum(np.abs(X0) - eX, 0.0), _up(np.abs(X0) + eX)
    yl, yh = np.maximum(np.abs(Y0) - eY, 0.0), _up(np.abs(Y0) + eY)
    al, ah = np.maximum(a - ea, 0.0) * (1 - 2 * _U), _up(a + ea)
    bl, bh = np.maximum(b - eb, 0.0) * (1 - 2 * _U), _up(b + eb)
    return _FrameBox(X0, Y0, eX, eY, xl, xh, yl, yh, al, ah, bl, bh)


def _float_multiplier(Fw, X0, Y0, a, b, c, s, tx, ty):
    """(μ, F'-magnitude): a float multiplier from the float foot point ``Fw``, then four Newton
    steps on F (a guess only: any value is sound, the bracket is what is proved), and
    |F'(μ)| = 2·Σ u_i²/(a_i² + μ) there."""
    Fw = np.asarray(Fw, float).reshape(-1, 2)
    fX = c * (Fw[:, 0] - tx) + s * (Fw[:, 1] - ty)
    fY = -s * (Fw[:, 0] - tx) + c * (Fw[:, 1] - ty)
    mu = np.hypot(X0 - fX, Y0 - fY) / np.hypot(fX / (a * a), fY / (b * b))
    a2, b2 = a * a, b * b
    for _ in range(4):
        u1, u2 = a * X0 / (a2 + mu), b * Y0 / (b2 + mu)
        f = u1 * u1 + u2 * u2 - 1.0
        fp = -2.0 * (u1 * u1 / (a2 + mu) + u2 * u2 / (b2 + mu))
        step = np.where(np.isfinite(f / fp), -f / fp, 0.0)
        mu = np.where(np.isfinite(mu + step) & (mu + step > 0), mu + step, mu)
    u1, u2 = a * X0 / (a2 + mu), b * Y0 / (b2 + mu)
    slope = 2.0 * (u1 * u1 / (a2 + mu) + u2 * u2 / (b2 + mu))
    return mu, slope


def _unit_normal_ball(bx, idx, lo_mu, hi_mu):
    """(ux, uy, en, mlow): for rows ``idx`` with μ* ∈ (lo_mu, hi_mu), N(μ*) lies in the box
    |N_X| ∈ [xl/(ah² + μ_hi), xh/(al² + μ_lo)] (sign of X0; both signs when the lower end is 0),
    likewise N_Y; (ux, uy) = N₀/|N₀| for its centre N₀, and |N/|N| − N₀/|N₀|| ≤ en = h/(|N₀| − h)
    for its half-diagonal h, valid where mlow = |N₀| − h (rounded down) > 0 (module docstring)."""
    xl_, xh_, yl_, yh_ = bx.xl[idx], bx.xh[idx], bx.yl[idx], bx.yh[idx]
    al_, ah_, bl_, bh_ = bx.al[idx], bx.ah[idx], bx.bl[idx], bx.bh[idx]
    nxl = _lower(xl_ / (ah_ * ah_ + hi_mu), 3)
    nxh = _upper(xh_ / (al_ * al_ + lo_mu), 3)
    nyl = _lower(yl_ / (bh_ * bh_ + hi_mu), 3)
    nyh = _upper(yh_ / (bl_ * bl_ + lo_mu), 3)
    sx, sy = np.sign(bx.X0[idx]), np.sign(bx.Y0[idx])
    # centre and radius per component (both signs possible when the lower end is 0)
    cx = np.where(nxl > 0, sx * 0.5 * (nxl + nxh), 0.0)
    rx = np.where(nxl > 0, _up(0.5 * (nxh - nxl) + 2 * _U * nxh), nxh)
    cy = np.where(nyl > 0, sy * 0.5 * (nyl + nyh), 0.0)
    ry = np.where(nyl > 0, _up(0.5 * (nyh - nyl) + 2 * _U * nyh), nyh)
    n0 = np.hypot(cx, cy)
    h = _up(np.hypot(rx, ry) * (1 + 2 * _U))
    mlow = n0 * (1 - 4 * _U) - h
    en = _up(h / mlow * (1 + 4 * _U))
    return cx / n0, cy / n0, en, mlow


def _bracket_rows(bx, mu, slope, idx, delta):
    """(lo_mu, hi_mu, done) for rows ``idx``: the bracket μ ± δ/|F'(μ)| and where it is proved,
    0 < μ_lo with F⁻(μ_lo) > 0 > F⁺(μ_hi) for every frame in the box (module docstring, Claim)."""
    mu_, slope_ = mu[idx], slope[idx]
    lims = (bx.xl[idx], bx.xh[idx], bx.yl[idx], bx.yh[idx], bx.al[idx], bx.ah[idx], bx.bl[idx], bx.bh[idx])
    lo_mu = mu_ - delta / slope_
    hi_mu = mu_ + delta / slope_
    Fl, _ = multiplier_bounds(lo_mu, *lims)
    _, Fh = multiplier_bounds(hi_mu, *lims)
    return lo_mu, hi_mu, (lo_mu > 0) & (Fl > 0) & (Fh < 0)


def ellipse_normal_enclosure(Q, Fw, a, b, c, s, tx, ty, errs):
    """(G, e, ok) per row: |∇d(q, E) − G| ≤ e for the exact ellipse E at the float point q = Q
    where ``ok`` (module docstring); ``Fw`` a float foot point in the world (only a start for μ),
    (a, b, c, s, tx, ty) the float frame and ``errs`` the (m, 6) array of
    :func:`frame_errors` of each row's site.  Steps: the box of the exact frame
    (:func:`_frame_box`), a float multiplier (:func:`_float_multiplier`), then for each bracket
    width of ``BRACKETS`` the rows not yet enclosed: the bracket (:func:`_bracket_rows`), the
    unit normal's ball (:func:`_unit_normal_ball`) and the world rotation."""
    Q = np.asarray(Q, float).reshape(-1, 2)
    m = len(Q)
    errs = np.asarray(errs, float).reshape(m, 6)
    ec, es = errs[:, 0], errs[:, 1]
    a, b, c, s, tx, ty = (np.broadcast_to(np.asarray(v, float), (m,)) for v in (a, b, c, s, tx, ty))
    with np.errstate(all="ignore"):
        bx = _frame_box(Q, a, b, c, s, tx, ty, errs)
        mu, slope = _float_multiplier(Fw, bx.X0, bx.Y0, a, b, c, s, tx, ty)
        G = np.full((m, 2), np.nan)
        e = np.full(m, np.inf)
        ok = np.zeros(m, bool)
        good = (np.isfinite(mu) & (mu > 0) & (slope > 0) & np.isfinite(bx.eX) & np.isfinite(bx.eY)
                & (bx.al > 0) & (bx.bl > 0) & np.isfinite(errs).all(1))
        for delta in BRACKETS:
            # the rows not yet enclosed only (every value below is computed row by row)
            idx = np.nonzero(good & ~ok)[0]
            if not len(idx):
                break
            lo_mu, hi_mu, done = _bracket_rows(bx, mu, slope, idx, delta)
            if not done.any():
                continue
            ux, uy, en, mlow = _unit_normal_ball(bx, idx, lo_mu, hi_mu)
            # float unit vector (≤ 4u off the exact cx/|c|), rotated by the float frame (≤ 4u),
            # the exact rotation within |Δc| + |Δs|
            rot = ec[idx] + es[idx]
            et = _up((1 + rot) * (en + 4 * _U) + rot + 8 * _U)
            gx, gy = c[idx] * ux - s[idx] * uy, s[idx] * ux + c[idx] * uy
            fine = done & (mlow > 0) & np.isfinite(et)
            r_ = idx[fine]
            G[r_, 0], G[r_, 1] = gx[fine], gy[fine]
            e[r_] = et[fine]
            ok[r_] = True
    return G, e, ok


def tight_gradients(Q, V, table, R, disc, G, slack, valid):
    """Improve the enclosures (G, slack, valid) of ∇d on the discs B(Q, R) (``disc``: R/(lo − R),
    the disc term) where the foot-point term dominates: outside a point or a circle of centre c,
    ∇d(Q) = (Q − c)/|Q − c| (the float difference is off by u per coordinate, the normalisation
    by a few u); outside an ellipse, :func:`ellipse_normal_enclosure` through ``table``
    (:meth:`runtime.voronoi.verify.site_table.SiteTable.ellipse_normals`).  Both need the disc
    outside the site's convex set (``base`` and lo > 2R).  ``V``: the table's values at Q.
    Returns the new (G, slack, valid)."""
    kq = table.kind[V.K]
    R = np.broadcast_to(np.asarray(R, float), (len(Q),))
    G, slack, valid = G.copy(), slack.copy(), valid.copy()
    with np.errstate(divide="ignore", invalid="ignore"):
        dF = np.hypot(*(Q - V.F).T)
        want = V.base & (V.lo > 2 * R) & np.isfinite(V.lo) & (slack > 1.25 * disc + 1e-11)
        pc = np.nonzero(want & ((kq == SiteKind.POINT) | (kq == SiteKind.CIRCLE)))[0]
        if len(pc):
            cq = np.column_stack([table.cx[V.K[pc]], table.cy[V.K[pc]]])
            Wc = Q[pc] - cq
            nW = np.hypot(Wc[:, 0], Wc[:, 1])
            ec = 8 * _U * (np.abs(Q[pc]).sum(1) + np.abs(cq).sum(1)) / (nW * (1 - 4 * _U)) + 8 * _U
            st = (ec + disc[pc] * (1 + 8 * _U)) * (1 + 4 * _U)
            better = (nW > 0) & np.isfinite(st) & (st < slack[pc])
            r_ = pc[better]
            G[r_] = Wc[better] / nW[better][:, None]
            slack[r_] = st[better]
            valid[r_] = True
        rows = np.nonzero(want & (kq == SiteKind.ELLIPSE) & (dF > 0))[0]
    if len(rows):
        Gt, et, okt = table.ellipse_normals(Q[rows], V.K[rows], V.F[rows])
        with np.errstate(divide="ignore", invalid="ignore"):
            st = (et + disc[rows] * (1 + 8 * _U)) * (1 + 4 * _U)
        better = okt & np.isfinite(st) & (st < slack[rows])
        r_ = rows[better]
        G[r_] = Gt[better]
        slack[r_] = st[better]
        valid[r_] = True
    return G, slack, valid
