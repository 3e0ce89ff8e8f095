"""Proofs for the Voronoi edges of circle and point sites, used by :mod:`runtime.voronoi.verify.certificate`.

The bisector of two disjoint circle/point sites is known in closed form (thesis §3.1: the
distance to a circle is | |q − c| − ρ |, additively weighted points are circles):

* **exterior pair** (neither disc contains the other): d_i = |q − c_i| − ρ_i and the bisector is
  the branch |q − c_i| − |q − c_j| = ρ_i − ρ_j of a hyperbola with foci c_i, c_j (a line when
  ρ_i = ρ_j).  With m the midpoint, e_x the unit vector from c_i to c_j, e_y = rot90(e_x),
  2c = |c_j − c_i|, a = (ρ_i − ρ_j)/2 and b = √(c² − a²) > 0 (disjointness gives c > |a|),
  the whole bisector is ``q(u) = m + a·cosh(u)·e_x + b·sinh(u)·e_y``, u ∈ ℝ, a graph over e_y;
* **nested pair** (site K inside the disc of circle J): d_J = ρ_J − |q − c_J| inside, and the
  bisector is the ellipse |q − c_J| + |q − c_K| = ρ_J + ρ_K =: 2A with foci c_J, c_K,
  ``q(t) = m + A·cos(t)·e_x + B·sin(t)·e_y``, B = √(A² − c²).

An edge (i, j) is a parameter interval of this curve.  It is proved free of third sites by

1. **Discs** (:mod:`runtime.voronoi.verify.arc_search`) on finite sub-intervals [u_a, u_b]: the
   arc lies in the disc of centre q(u_m) and radius R = the larger arc length from q(u_m) to an
   end (|q'(u)| ≤ c·cosh u for the hyperbola, ≤ A for the ellipse), enlarged by a rounding bound
   of the float curve.  Every distance function is 1-Lipschitz, so d_k − d_i ≥ lo_k(q_m) − hi_i(q_m) − 2R there; sharper, along the
   arc d_k − d_i changes by at most L·(arc length) with L ≥ |∇d_k − ∇d_i| on the disc (for a
   circle the gradient is the unit vector ±(q − c)/|q − c|, which turns by at most R/(|q_m − c| − R)
   on the disc).  Intervals that do not decide are halved (capped depth); a half only re-tests
   the sites its parent could not exclude (candidates come once from a k-d tree on the centres);
2. **exact zeros** for the third site k0 of an end vertex (where d_k0 = d_i at the end, so no
   bound can decide near it): d_k0 − d_i vanishes on the bisector exactly at the Voronoi
   vertices of the triple (i, j, k0), all of which the exact solver of thesis §3.1.3 lists; if
   none lies strictly inside the edge's parameter interval, d_k0 − d_i has one sign on the open
   edge, decided at one interior point;
3. **the unbounded tail** u ∈ [U, ±∞): with τ = e^{∓u} ∈ (0, τ_U] and Z(τ) = τ·(q − m),
   G_k = |q − c_k| − ρ_k − d_i = (2 Z·(C_i − C_k) + τ(|C_k|² − |C_i|²)) / (|Z − τC_k| + |Z − τC_i|)
   + ρ_i − ρ_k (C = centres relative to m), a quotient of a quadratic in τ and a positive
   Lipschitz function, continuous up to τ = 0 (the asymptote).  Interval bounds on τ-intervals,
   halved until G_k > 0 is decided, cover the whole infinite arc (rounding: a first-order bound
   1e-12·(1 + c/b)²·(scale + |numerator terms|/denominator), far above the few ulps involved).

Floating-point: the curve's constants (m, e_x, a, b) are floats; the true curve differs from the
computed one by at most ``curve_error`` (a first-order rounding bound with a factor 64 of
safety and the conditioning c/b of b = √(c² − a²)); every bound above is widened by it and by
``rounding_slack`` of :mod:`runtime.voronoi.geometry`.
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from scipy.spatial import cKDTree

from ..geometry import rounding_slack

__all__ = ["CircleTable", "Bisector", "bisector", "prove_tail", "params", "EPS", "MAX_DEPTH"]

EPS = 2.0 ** -53
MAX_DEPTH = 48


#: tables of at most this many sites list the sites near a point by testing every pair (no tree)
SMALL_TABLE = 64
#: the largest circles (at most this many) searched one by one, so that the k-d tree's queries are
#: widened only by the largest radius among the others (a few big circles among many small ones
#: would otherwise widen every query to thousands of sites)
BIG_SITES = 64


class CircleTable:
    """Flat arrays of circle/point sites (centre, radius) with a k-d tree on the centres, and
    rigorous vectorised distance bounds (the formula of :class:`geometry.CircleGeometry`).

    ``big``: the indices of the (at most :data:`BIG_SITES`) largest circles when their radii
    exceed twice ``r_small``, the largest radius of the other sites (else empty and ``r_small`` =
    ``rmax``): searches list the others through the tree widened by ``r_small`` and the big ones
    by their own radii."""

    def __init__(self, geoms):
        self._setup(np.array([[g.cx, g.cy] if g.kind == "circle" else [g.x0, g.y0] for g in geoms], float),
                    np.array([g.rho if g.kind == "circle" else 0.0 for g in geoms], float))

    @classmethod
    def from_arrays(cls, C, R) -> "CircleTable":
        """The table of the circles of centres C (n, 2) and radii R (n,) (0: a point)."""
        t = cls.__new__(cls)
        t._setup(np.asarray(C, float).reshape(-1, 2), np.asarray(R, float))
        return t

    def _setup(self, C, R):
        self.C, self.R, self.n = C, R, len(R)
        self.C1 = np.abs(C).sum(axis=1)           # |c|₁ of each centre (the rounding slack's scale)
        self._tree = None                         # the k-d tree, made on first use (a local proof's
                                                  # small table never queries it)
        self.rmax = float(self.R.max()) if self.n else 0.0
        self.scale = float(np.abs(self.C).max() + self.rmax + 1.0) if self.n else 1.0
        self.big, self.r_small = np.zeros(0, int), self.rmax
        if self.n > 2 * BIG_SITES:
            order = np.argsort(self.R)
            r_small = float(self.R[order[-BIG_SITES - 1]])
            if self.rmax > 2 * r_small:
                self.big = np.sort(order[-BIG_SITES:][self.R[order[-BIG_SITES:]] > r_small])
                self.r_small = r_small
        self.is_big = np.zeros(self.n, bool)
        self.is_big[self.big] = True

    @property
    def tree(self) -> cKDTree:
        """The k-d tree of the centres."""
        if self._tree is None:
            self._tree = cKDTree(self.C)
        return self._tree

    def big_near(self, Q, reach):
        """Flat (row, site) pairs of the big sites whose disc may come within ``reach[row]`` of
        Q[row] (|q − c_k| ≤ (reach + ρ_k)(1 + 1e-12) + 1e-12·scale: rounding of a few ulps)."""
        rows, cols = [np.zeros(0, int)], [np.zeros(0, int)]
        if not len(self.big):
            return rows[0], cols[0]
        for start in range(0, len(Q), 4096):
            q = Q[start:start + 4096]
            D = np.hypot(q[:, None, 0] - self.C[self.big, 0], q[:, None, 1] - self.C[self.big, 1])
            lim = (reach[start:start + 4096, None] + self.R[self.big]) * (1 + 1e-12) + 1e-12 * self.scale
            r, c = np.nonzero(D <= lim)
            rows.append(start + r)
            cols.append(self.big[c])
        return np.concatenate(rows), np.concatenate(cols)

    def bounds(self, P, k):
        """(lo, hi) of d(P[m], site k[m]), rigorous."""
        P = np.asarray(P, float)
        Rk = self.R[k]
        V = P - self.C[k]
        d = np.abs(np.hypot(V[:, 0], V[:, 1]) - Rk)
        s = rounding_slack(np.abs(P).sum(axis=1) + self.C1[k] + Rk)
        return np.maximum(d - s, 0.0), d + s

    def near(self, Q, reach):
        """Flat (row, site) pairs: sites whose disc may come within ``reach[row]`` of Q[row]
        (fixed-size k-nearest queries, widened where they may have missed a site)."""
        Q = np.asarray(Q, float)
        reach0 = np.broadcast_to(np.asarray(reach, float), (len(Q),))
        if self.n <= SMALL_TABLE:
            # a few sites (a local update's proof): every pair tested, |q − c_k| ≤ reach + ρ_k with
            # the margin of big_near, instead of the tree's queries widened by the largest radius
            D = np.hypot(Q[:, None, 0] - self.C[None, :, 0], Q[:, None, 1] - self.C[None, :, 1])
            rows, cols = np.nonzero(D <= (reach0[:, None] + self.R[None, :]) * (1 + 1e-12) + 1e-12 * self.scale)
            return rows.astype(int), cols.astype(int)
        brows, bcols = self.big_near(Q, reach0)
        reach = reach0 + self.r_small                 # every site not in `big` has radius <= r_small
        rows_all, cols_all = [brows], [bcols]
        order = np.argsort(reach)
        for chunk in np.array_split(order, max(1, len(order) // 512)):
            todo = chunk
            kq = min(16, self.n)
            while len(todo):
                ub = float(reach[todo].max()) * (1 + 1e-12)
                dist, ind = self.tree.query(Q[todo], k=kq, distance_upper_bound=ub)
                dist, ind = dist.reshape(len(todo), -1), ind.reshape(len(todo), -1)
                hit = dist <= reach[todo][:, None] * (1 + 1e-12)
                r, c = np.nonzero(hit)
                full = hit[:, -1] if kq < self.n else np.zeros(len(todo), bool)
                keep = ~full[r] & ~self.is_big[np.minimum(ind[r, c], self.n - 1)]
                rows_all.append(todo[r[keep]])
                cols_all.append(ind[r[keep], c[keep]])
                todo = todo[full]
                kq = min(kq * 4, self.n)
        return np.concatenate(rows_all).astype(int), np.concatenate(cols_all).astype(int)


class Bisector:
    """The exact bisector curve of two circle/point sites (see the module docstring)."""

    def __init__(self, kind, m, ex, c, a, b, i, j):
        self.kind = kind          # "hyperbola" (u ∈ ℝ) or "ellipse" (t ∈ [0, 2π))
        mx, my = float(m[0]), float(m[1])
        ex0, ex1 = float(ex[0]), float(ex[1])
        self.m = np.array([mx, my])
        self.ex = np.array([ex0, ex1])
        self.ey = np.array([-ex1, ex0])
        self.c, self.a, self.b = float(c), float(a), float(b)
        self.i, self.j = i, j
        cond = 1.0 + (c / b if b > 0 else math.inf)
        self.err0 = 64 * EPS * cond * ((abs(mx) + abs(my)) + abs(self.a) + abs(self.b) + self.c)

    def point(self, u):
        u = np.asarray(u, float)
        if self.kind == "hyperbola":
            X, Y = self.a * np.cosh(u), self.b * np.sinh(u)
        else:
            X, Y = self.a * np.cos(u), self.b * np.sin(u)
        return self.m + X[..., None] * self.ex + Y[..., None] * self.ey

    def param(self, P):
        """Parameter of the curve point 'nearest' P: same e_y coordinate (hyperbola), same polar
        angle in the scaled frame (ellipse)."""
        V = np.atleast_2d(np.asarray(P, float)) - self.m
        x, y = V @ self.ex, V @ self.ey
        if self.kind == "hyperbola":
            return np.arcsinh(y / self.b)
        return np.mod(np.arctan2(y / self.b, x / self.a), 2 * math.pi)

    def curve_error(self, u):
        """Bound on |q_true(u) − q_float(u)| (first-order rounding, see module docstring)."""
        u = np.asarray(u, float)
        if self.kind == "hyperbola":
            return self.err0 * np.cosh(np.minimum(np.abs(u), 700.0)) * 4
        return np.full(u.shape, self.err0 * 4)

    def piece_radius(self, ua, ub):
        """Radius of a disc around q((ua+ub)/2) containing the arc q([ua, ub])."""
        um = 0.5 * (ua + ub)
        if self.kind == "hyperbola":
            r = self.c * np.maximum(np.sinh(um) - np.sinh(ua), np.sinh(ub) - np.sinh(um))
        else:
            r = max(self.a, self.b) * 0.5 * (ub - ua)
        return r * (1 + 1e-12) + self.curve_error(np.maximum(np.abs(ua), np.abs(ub)))


def bisector(table: CircleTable, i: int, j: int) -> Bisector | str:
    """The bisector of sites i, j, or a one-line reason why the pair is not a valid edge pair."""
    (cix, ciy), (cjx, cjy) = table.C[i].tolist(), table.C[j].tolist()
    ri, rj = float(table.R[i]), float(table.R[j])
    dx, dy = cjx - cix, cjy - ciy
    D = math.hypot(dx, dy)
    tol = 1e-12 * table.scale
    if D > ri + rj + tol:
        c, a = D / 2, (ri - rj) / 2
        return Bisector("hyperbola", ((cix + cjx) / 2, (ciy + cjy) / 2), (dx / D, dy / D), c, a,
                        math.sqrt(c * c - a * a), i, j)
    if D < abs(ri - rj) - tol:               # one inside the other's disc: ellipse
        J, K = (i, j) if ri > rj else (j, i)
        cJ, cK = table.C[J], table.C[K]
        ex = (cK - cJ) / D if D > 0 else np.array([1.0, 0.0])
        A, c = (table.R[J] + table.R[K]) / 2, D / 2
        return Bisector("ellipse", (cJ + cK) / 2, ex, c, A, math.sqrt(A * A - c * c), i, j)
    return f"sites {i} and {j} are not disjoint within the float filter: no bisector arc to prove"


class _TailTerms(NamedTuple):
    """The quotient G_k = N_k(τ)/D_k(τ) + ρ_i − ρ_k of the tail (module docstring, item 3) for the
    third sites ks: with w = C_i − C_k and Z(τ) = (a(1 + τ²)/2, σb(1 − τ²)/2) in the frame (e_x,
    e_y), N_k(τ) = 2Z·w + τ(|C_k|² − |C_i|²) = al + s·τ + ga·τ² (al = a·w_x + σb·w_y,
    ga = a·w_x − σb·w_y); ``slack`` bounds the rounding of the constants (conditioning c/b)."""
    bis: object
    sigma: int
    ks: np.ndarray
    Cx: np.ndarray
    Cy: np.ndarray
    al: np.ndarray
    ga: np.ndarray
    s: np.ndarray
    dr: np.ndarray
    nCk: np.ndarray
    nCi: float
    slack: np.ndarray


class _TailBound(NamedTuple):
    """Bounds of G_k on τ-intervals [t0, t1]: the lower bound g_lo (rounding sl included), the
    midpoint tm, the denominator there den_m, and the numerator's coefficients (A_, be, G_)."""
    g_lo: np.ndarray
    sl: np.ndarray
    tm: np.ndarray
    den_m: np.ndarray
    A_: np.ndarray
    be: np.ndarray
    G_: np.ndarray


def _tail_terms(table, bis, sigma, ks) -> _TailTerms:
    """The :class:`_TailTerms` of the third sites ks on the branch of ``bis`` going to σ∞."""
    i = bis.i
    a, b, c = bis.a, bis.b, bis.c
    Cr = table.C - bis.m
    Cx, Cy = Cr @ bis.ex, Cr @ bis.ey
    wx, wy = Cx[i] - Cx[ks], Cy[i] - Cy[ks]
    s = (Cx[ks] ** 2 + Cy[ks] ** 2) - (Cx[i] ** 2 + Cy[i] ** 2)
    al = a * wx + sigma * b * wy
    ga = a * wx - sigma * b * wy
    dr = table.R[i] - table.R[ks]
    nCk = np.hypot(Cx[ks], Cy[ks])
    nCi = math.hypot(Cx[i], Cy[i])
    scale = nCk + nCi + c + np.abs(table.R[ks]) + table.R[i] + 1e-300
    slack = 1e-12 * scale * (1.0 + c / b) ** 2 + 2 * bis.err0 * 4
    return _TailTerms(bis, sigma, ks, Cx, Cy, al, ga, s, dr, nCk, nCi, slack)


def _tail_bound(tt: _TailTerms, idx, t0, t1) -> _TailBound:
    """Interval bounds of G_k (k = ks[idx]) on [t0, t1]: the numerator's minimum over the interval
    (its ends, and the vertex of the parabola when it opens upwards inside), the denominator
    |Z − τC_k| + |Z − τC_i| at the midpoint ± L·(half-width) with L = 2c·t1 + |C_k| + |C_i| its
    Lipschitz bound, and the rounding of the quotient's evaluation."""
    bis, sigma, ks, i = tt.bis, tt.sigma, tt.ks, tt.bis.i
    a, b, c = bis.a, bis.b, bis.c
    Cx, Cy = tt.Cx, tt.Cy
    tm, hw = 0.5 * (t0 + t1), 0.5 * (t1 - t0)
    be = tt.s[idx]
    A_, G_ = tt.al[idx], tt.ga[idx]
    f0 = A_ + be * t0 + G_ * t0 * t0
    f1 = A_ + be * t1 + G_ * t1 * t1
    num_lo = np.minimum(f0, f1)
    with np.errstate(divide="ignore", invalid="ignore"):
        tv = -be / (2 * G_)
    inside = (G_ > 0) & (tv > t0) & (tv < t1)
    fv = A_ - be * be / (4 * np.where(G_ != 0, G_, 1.0))
    num_lo = np.where(inside, np.minimum(num_lo, fv), num_lo)
    Zx = a * (1 + tm * tm) / 2
    Zy = sigma * b * (1 - tm * tm) / 2
    den_m = (np.hypot(Zx - tm * Cx[ks[idx]], Zy - tm * Cy[ks[idx]])
             + np.hypot(Zx - tm * Cx[i], Zy - tm * Cy[i]))
    lip = 2 * c * t1 + tt.nCk[idx] + tt.nCi
    den_lo = np.maximum(den_m - lip * hw, 0.0)
    den_hi = den_m + lip * hw
    with np.errstate(divide="ignore", invalid="ignore"):
        q = np.where(num_lo >= 0, num_lo / den_hi, num_lo / np.where(den_lo > 0, den_lo, np.nan))
    # rounding: the constants (conditioning c/b) and the evaluation of the quotient
    mag = (np.abs(A_) + np.abs(be) * t1 + np.abs(G_) * t1 * t1) / np.where(den_lo > 0, den_lo, np.inf)
    sl = tt.slack[idx] + 1e-12 * (1.0 + c / b) ** 2 * mag
    g_lo = q + tt.dr[idx] - sl
    return _TailBound(g_lo, sl, tm, den_m, A_, be, G_)


def _proved_closer(tt: _TailTerms, idx, bd: _TailBound, ok):
    """A proved failure: the detail (k, point, "closer") of the first interval where G_k < 0 at
    the midpoint (its value plus the rounding bound is negative), or None."""
    fm = bd.A_ + bd.be * bd.tm + bd.G_ * bd.tm * bd.tm
    gm = fm / bd.den_m + tt.dr[idx] + bd.sl
    neg = ~ok & (gm < 0)
    if neg.any():
        r0 = int(np.nonzero(neg)[0][0])
        return (int(tt.ks[idx[r0]]), _tail_point(tt.bis, bd.tm[r0], tt.sigma), "closer")
    return None


def _tied_at_asymptote(tt: _TailTerms, idx, bd: _TailBound, bad, t0):
    """A site tied with i at the asymptote (G_k(0) = al/D(0) + ρ_i − ρ_k within rounding of 0:
    collinear points, sites touching one line) cannot be decided by subdividing τ: the detail
    (k, point, "undecided", all such sites) of the undecided intervals at τ = 0, or None."""
    tied = bad & (t0 == 0) & (np.abs(bd.A_ / np.where(bd.den_m > 0, bd.den_m, np.inf) + tt.dr[idx]) <= 4 * bd.sl)
    if tied.any():
        rs = np.nonzero(tied)[0]
        r0 = int(rs[0])
        return (int(tt.ks[idx[r0]]), _tail_point(tt.bis, bd.tm[r0], tt.sigma), "undecided",
                sorted({int(tt.ks[idx[r]]) for r in rs.tolist()}))
    return None


def prove_tail(table: CircleTable, bis: Bisector, U: float, sigma: int, exempt=()):
    """Prove G_k > 0 on the hyperbola branch u ∈ [U, σ∞) for every k ∉ {i, j} ∪ exempt, by
    interval bounds on τ = e^{−σu} ∈ [0, τ_U] (module docstring, item 3).  Returns (ok, detail);
    a detail of sites tied with i at the asymptote has a fourth entry listing all of them."""
    if bis.kind != "hyperbola":
        return False, (None, None, "an ellipse has no unbounded part")
    i, j = bis.i, bis.j
    tauU = math.exp(-sigma * U)
    if not math.isfinite(tauU) or tauU > 1e300:
        return False, (None, None, "tail parameter out of range")
    others = np.ones(table.n, bool)
    others[[i, j, *exempt]] = False
    ks = np.nonzero(others)[0]
    if not len(ks):
        return True, None
    tt = _tail_terms(table, bis, sigma, ks)
    idx = np.arange(len(ks))
    T0 = np.zeros(len(ks))
    T1 = np.full(len(ks), tauU)
    for depth in range(MAX_DEPTH + 20):
        if not len(idx):
            return True, None
        t0, t1 = T0, T1
        bd = _tail_bound(tt, idx, t0, t1)
        ok = bd.g_lo > 0
        if not ok.all():
            closer = _proved_closer(tt, idx, bd, ok)
            if closer is not None:
                return False, closer
        bad = ~ok
        if depth >= 6:
            tied = _tied_at_asymptote(tt, idx, bd, bad, t0)
            if tied is not None:
                return False, tied
        idx, T0, T1 = idx[bad], t0[bad], t1[bad]
        if not len(idx):
            return True, None
        if len(idx) > 200000:
            break
        M = 0.5 * (T0 + T1)
        idx = np.concatenate([idx, idx])
        T0, T1 = np.concatenate([T0, M]), np.concatenate([M, T1])
    r0 = 0
    return False, (int(ks[idx[r0]]), _tail_point(bis, 0.5 * (T0[r0] + T1[r0]), sigma), "undecided")


def _tail_point(bis: Bisector, tau: float, sigma: int):
    if tau <= 0:
        return (math.inf, math.inf)
    u = -sigma * math.log(tau)
    return tuple(float(v) for v in bis.point(np.array([u]))[0])


def params(biss, idx, P):
    """Vectorised :meth:`Bisector.param`: the parameter of point P[m] on bisector biss[idx[m]]."""
    idx = np.asarray(idx, int)
    P = np.asarray(P, float).reshape(-1, 2)
    if not len(idx):
        return np.zeros(0)
    hyp = np.array([b.kind == "hyperbola" for b in biss])[idx]
    M = np.array([b.m for b in biss])[idx]
    EX = np.array([b.ex for b in biss])[idx]
    EY = np.array([b.ey for b in biss])[idx]
    a = np.array([b.a for b in biss])[idx]
    b_ = np.array([b.b for b in biss])[idx]
    V = P - M
    x, y = (V * EX).sum(1), (V * EY).sum(1)
    with np.errstate(all="ignore"):
        uh = np.arcsinh(y / b_)
        ue = np.mod(np.arctan2(y / b_, x / a), 2 * math.pi)
    return np.where(hyp, uh, ue)
