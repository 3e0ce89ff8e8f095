"""The support cones of the disc search (runtime/voronoi/verify/arc_search.py, module docstring item 2)
against the exact bisector, evaluated in mpmath at 50 digits from the sites' binary values:

* every point q of the true arc of a piece lies outside circle i with |u_q − u0| ≤ κ, u_q =
  (q − c_i)/|q − c_i| (``_Curves.cones``), on pieces near the sites and far out on the branch, on
  either side of the branch's vertex;
* a site tied with i at a point q of the arc (a point on the rim of q's empty circle: d_k(q) =
  d_i(q) exactly up to the rounding of its coordinates) is never cleared by the cone
  (``_Curves.support_clear``), and the cleared sites of random scenes have d_k > d_i at every
  sampled arc point;
* such a tied site is always among the candidates the search lists (``_queries`` and
  ``CircleTable.near``) or cleared by the disc bound of item 1, also when it lies across the
  scene from site i, at the edge of the box that bounds |c_k − c_i|.
"""
from __future__ import annotations

import mpmath as mp
import numpy as np
import pytest

from curvedvoronoi.runtime.voronoi.verify.arc_search import _Curves, _queries
from curvedvoronoi.runtime.voronoi.verify.edges import CircleTable, bisector

mp.mp.dps = 50


def _exact_curve(C, R, i, j):
    """q(u) of the exact bisector branch of sites i, j (edges.py's parametrisation), in mpmath."""
    ci = [mp.mpf(float(x)) for x in C[i]]
    cj = [mp.mpf(float(x)) for x in C[j]]
    ri, rj = mp.mpf(float(R[i])), mp.mpf(float(R[j]))
    dx, dy = cj[0] - ci[0], cj[1] - ci[1]
    D = mp.sqrt(dx * dx + dy * dy)
    ex, ey = (dx / D, dy / D), (-dy / D, dx / D)
    m = ((ci[0] + cj[0]) / 2, (ci[1] + cj[1]) / 2)
    c, a = D / 2, (ri - rj) / 2
    b = mp.sqrt(c * c - a * a)

    def q(u):
        u = mp.mpf(float(u))
        X, Y = a * mp.cosh(u), b * mp.sinh(u)
        return (m[0] + X * ex[0] + Y * ey[0], m[1] + X * ex[1] + Y * ey[1])
    return q, ci, ri


def _dist(q, c, r):
    return abs(mp.sqrt((q[0] - c[0]) ** 2 + (q[1] - c[1]) ** 2) - r)


def _scene(rng, n_bg=300, shift=0.0):
    """Sites i = 0, j = 1 (circles or points, disjoint) and background sites in a box (moved by
    ``shift`` along the diagonal: site i near a corner of the sites' box)."""
    while True:
        ci, cj = rng.uniform(-10, 10, 2), rng.uniform(-10, 10, 2)
        ri, rj = rng.choice([0.0, rng.uniform(0, 3)]), rng.choice([0.0, rng.uniform(0, 3)])
        if np.hypot(*(ci - cj)) > (ri + rj) * 1.05 + 0.1:
            break
    bg = rng.uniform(-40, 40, (n_bg, 2)) + shift
    return np.vstack([ci, cj, bg]), np.r_[ri, rj, rng.uniform(0, 0.5, n_bg) * (rng.uniform(size=n_bg) < 0.5)]


def _pieces(rng, m=40):
    """Parameter intervals [A, B]: short and long, near the vertex and far out on either side."""
    A = rng.uniform(-12, 12, m)
    A[: m // 4] = rng.uniform(-1, 1, m // 4)
    L = 10 ** rng.uniform(-4, 0.7, m)
    return A, A + L


def _cones(C, R, A, B):
    table = CircleTable.from_arrays(C, R)
    bis = bisector(table, 0, 1)
    ctx = _Curves(table, [(bis, float(A.min()), float(B.max()), ())])
    job = np.zeros(len(A), int)
    return table, ctx, job, ctx.cones(job, A, B)


@pytest.mark.parametrize("seed", range(8))
def test_every_point_of_the_true_arc_lies_in_the_cone(seed):
    rng = np.random.default_rng(7100 + seed)
    C, R = _scene(rng, n_bg=0)
    A, B = _pieces(rng)
    table, ctx, job, (u0, kappa, ok) = _cones(C, R, A, B)
    q, ci, ri = _exact_curve(C, R, 0, 1)
    assert ok.sum() >= len(A) // 3                 # the far pieces of the branch have cones
    for p in np.nonzero(ok)[0]:
        for s in np.linspace(0, 1, 41):
            x = q(A[p] + s * (B[p] - A[p]))
            v = (x[0] - ci[0], x[1] - ci[1])
            n = mp.sqrt(v[0] ** 2 + v[1] ** 2)
            assert n > ri
            gap = mp.sqrt((v[0] / n - mp.mpf(float(u0[p, 0]))) ** 2 + (v[1] / n - mp.mpf(float(u0[p, 1]))) ** 2)
            assert gap <= mp.mpf(float(kappa[p])), (p, s, float(gap), float(kappa[p]))


def _tied_sites(rng, C, R, A, B, ok, per=6):
    """Point sites on the rim of the empty circle of arc points q (d_k(q) = d_i(q)), at lateral
    offsets across the scene: (piece, site position) pairs."""
    q, ci, ri = _exact_curve(C, R, 0, 1)
    out = []
    lo, hi = C.min(axis=0), C.max(axis=0)
    for p in np.nonzero(ok)[0]:
        for _ in range(per):
            x = q(A[p] + rng.uniform(0, 1) * (B[p] - A[p]))
            r = _dist(x, ci, ri)
            # a rim point inside the scene's box: an angle around the direction back to c_i
            back = mp.atan2(ci[1] - x[1], ci[0] - x[0])
            for _try in range(40):
                lat = rng.uniform(-1, 1) * float(np.hypot(*(hi - lo)))
                th = back + mp.asin(max(-1, min(1, mp.mpf(lat) / r)))
                k = np.array([float(x[0] + r * mp.cos(th)), float(x[1] + r * mp.sin(th))])
                clear_of_sites = np.all(np.hypot(*(C - k).T) > R + 1e-6)
                if np.all(k >= lo) and np.all(k <= hi) and clear_of_sites:
                    out.append((p, k))
                    break
    return out


@pytest.mark.parametrize("seed", range(6))
def test_a_tied_site_is_never_cleared_and_always_a_candidate(seed):
    rng = np.random.default_rng(7200 + seed)
    C, R = _scene(rng)
    A, B = _pieces(rng, m=24)
    _, _, _, (_, _, ok) = _cones(C, R, A, B)
    tied = _tied_sites(rng, C, R, A, B, ok)
    assert len(tied) >= 10
    C2 = np.vstack([C] + [k for _, k in tied])
    R2 = np.r_[R, np.zeros(len(tied))]
    table, ctx, job, cone = _cones(C2, R2, A, B)
    rows = np.array([p for p, _ in tied])
    ks = len(C) + np.arange(len(tied))
    cleared = ctx.support_clear(cone, rows, ks, np.zeros(len(tied), int))
    assert not cleared.any()
    _, Q, _, _, Rd = ctx.discs(job, A, B)
    hi = np.minimum(table.bounds(Q, np.zeros(len(A), int))[1], table.bounds(Q, np.ones(len(A), int))[1])
    P, reach = _queries(ctx, job, Q, Rd, hi, cone)
    assert (np.abs(P - Q).sum(axis=1) > 0).any()           # some pieces list by the far ball
    prow, pk = table.near(P, reach)
    listed = set(zip(prow.tolist(), pk.tolist()))
    lo_k = table.bounds(Q[rows], ks)[0]
    by_disc = lo_k - hi[rows] - 2 * Rd[rows] > 0
    for t, (p, _) in enumerate(tied):
        assert by_disc[t] or (p, int(ks[t])) in listed, (p, tied[t])


@pytest.mark.parametrize("seed", range(6))
def test_cleared_sites_are_farther_than_site_i_on_the_arc(seed):
    rng = np.random.default_rng(7300 + seed)
    C, R = _scene(rng, n_bg=120)
    A, B = _pieces(rng, m=16)
    table, ctx, job, cone = _cones(C, R, A, B)
    q, ci, ri = _exact_curve(C, R, 0, 1)
    rows = np.repeat(np.arange(len(A)), len(C) - 2)
    ks = np.tile(np.arange(2, len(C)), len(A))
    cleared = ctx.support_clear(cone, rows, ks, np.zeros(len(rows), int))
    assert cleared.sum() > 0
    for t in np.nonzero(cleared)[0][::7]:
        p, k = rows[t], ks[t]
        ck, rk = [mp.mpf(float(x)) for x in C[k]], mp.mpf(float(R[k]))
        for s in np.linspace(0, 1, 9):
            x = q(A[p] + s * (B[p] - A[p]))
            assert _dist(x, ck, rk) > _dist(x, ci, ri)


@pytest.mark.parametrize("seed", range(6))
def test_every_site_the_cone_leaves_is_listed_or_cleared_by_the_disc(seed):
    """Sites placed behind the support line of site i by f·|c_i − c_k|·κ (f < 1: not cleared by
    the cone, which allows |c_i − c_k|·κ), across the scene (up to the corner of the box opposite
    site i, where |c_i − c_k| meets its bound D_i): the candidate query must list each unless
    the disc bound clears it."""
    rng = np.random.default_rng(7500 + seed)
    C, R = _scene(rng, shift=30.0 * (seed % 2))
    A, B = _pieces(rng, m=24)
    A, B = A[np.abs(A) > 4], B[np.abs(A) > 4]            # far pieces: the queries by the far ball
    _, _, _, (u0, kappa, ok) = _cones(C, R, A, B)
    lo, hi = C.min(axis=0), C.max(axis=0)
    new, rows = [], []
    for p in np.nonzero(ok)[0]:
        perp = np.array([-u0[p, 1], u0[p, 0]])
        for f in (0.3, 0.6, 0.9, 0.99):
            # the farthest lateral offsets the box allows on either side, and random ones
            with np.errstate(divide="ignore"):
                reach = [min(((hi - C[0]) / (sg * perp)).clip(0).tolist() + ((lo - C[0]) / (sg * perp)).clip(0).tolist(),
                             key=lambda x: x if x > 0 else np.inf) for sg in (1, -1)]
            for b in [0.999 * reach[0], -0.999 * reach[1]] + (rng.uniform(-1, 1, 6) * float(np.hypot(*(hi - lo)))).tolist():
                a = R[0]
                for _it in range(30):                    # a = ρ_i − f·|(a, b)|·κ
                    a = R[0] - f * np.hypot(a, b) * kappa[p]
                k = C[0] + a * u0[p] + b * perp
                if np.all(k >= lo) and np.all(k <= hi) and np.all(np.hypot(*(C - k).T) > R + 1e-6):
                    new.append(k)
                    rows.append(p)
    assert len(new) >= 20
    C2, R2 = np.vstack([C, new]), np.r_[R, np.zeros(len(new))]
    table, ctx, job, cone = _cones(C2, R2, A, B)
    rows = np.array(rows)
    ks = len(C) + np.arange(len(new))
    assert not ctx.support_clear(cone, rows, ks, np.zeros(len(ks), int)).any()
    _, Q, _, _, Rd = ctx.discs(job, A, B)
    hi_ = np.minimum(table.bounds(Q, np.zeros(len(A), int))[1], table.bounds(Q, np.ones(len(A), int))[1])
    P, reach = _queries(ctx, job, Q, Rd, hi_, cone)
    far_ball = np.abs(P - Q).sum(axis=1) > 0
    assert far_ball[rows].mean() > 0.5
    prow, pk = table.near(P, reach)
    listed = set(zip(prow.tolist(), pk.tolist()))
    by_disc = table.bounds(Q[rows], ks)[0] - hi_[rows] - 2 * Rd[rows] > 0
    for t in range(len(ks)):
        assert by_disc[t] or (int(rows[t]), int(ks[t])) in listed, t
