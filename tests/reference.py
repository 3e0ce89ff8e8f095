"""Independent reference oracle for the tests (NOT used by the runtime).

Deliberately shares no code with ``runtime/sites/distance.py`` or the conflict locator:

* point-to-conic distance by dense sampling of a parametrisation of the canonical form
  (numpy, float) followed by a safeguarded Newton/bisection refinement of the foot
  parameter in mpmath (default 40 digits) -- no normal-condition polynomial, no elimination;
* Voronoi vertices of three conics (thesis §5.2, Def. 5.2.1: d1 = d2 = d3 = r > 0) by grid
  seeding of sign changes of d1 − d2 and d1 − d3 on nested grids, float Newton, then Newton
  refinement in mpmath; a vertex is kept when the residuals are below 1e-25·r and a denser
  re-sampling confirms that no point of the three conics is closer than r (true vertex);
* :func:`reference_locate` returns dicts like the vertices of ``validation_cases.json``.

Conics are given as canonical constructions: dicts ``{"type", "cos", "sin", "tx", "ty",
"A2", "B2" | "p" | "r2"}`` (strings/Fractions/numbers), or :class:`runtime.sites.conic.Conic`
objects (then their exact / high-precision canonical frame is used).
"""
from __future__ import annotations

import math
from fractions import Fraction
from typing import Any

import mpmath
import numpy as np

DPS = 40


def _mpf(v) -> mpmath.mpf:
    if isinstance(v, mpmath.mpf):
        return v
    if isinstance(v, str):
        v = Fraction(v)
    if isinstance(v, Fraction):
        return mpmath.mpf(v.numerator) / v.denominator
    return mpmath.mpf(v)


class RefConic:
    """Canonical conic in mpmath (see module docstring for the accepted inputs)."""

    def __init__(self, spec: Any, dps: int = DPS):
        self.dps = dps
        with mpmath.workdps(dps + 10):
            if isinstance(spec, dict):
                d = dict(spec)
                kind = d.pop("type", None) or d.pop("kind")
                vals = {k: _mpf(v) for k, v in d.items()}
            else:  # a runtime.sites.conic.Conic
                fr = spec.exact_frame or spec.frame_mp(dps + 10)
                kind = fr.kind
                vals = {"cos": _mpf(fr.cos), "sin": _mpf(fr.sin), "tx": _mpf(fr.tx), "ty": _mpf(fr.ty)}
                vals.update({k: _mpf(v) for k, v in fr.params.items()})
            self.kind = kind
            self.c, self.s, self.tx, self.ty = vals["cos"], vals["sin"], vals["tx"], vals["ty"]
            n = mpmath.sqrt(self.c ** 2 + self.s ** 2)  # renormalise (exact inputs: n = 1)
            self.c, self.s = self.c / n, self.s / n
            if kind == "ellipse":
                self.a, self.b = mpmath.sqrt(vals["A2"]), mpmath.sqrt(vals["B2"])
            elif kind == "hyperbola":
                self.a, self.b = mpmath.sqrt(vals["A2"]), mpmath.sqrt(vals["B2"])
            elif kind == "circle":
                self.a = self.b = mpmath.sqrt(vals["r2"])
            elif kind == "parabola":
                self.p = vals["p"]
            else:
                raise ValueError(f"unknown kind {kind!r}")
        # float copies
        self.fc, self.fs, self.ftx, self.fty = (float(v) for v in (self.c, self.s, self.tx, self.ty))
        if kind == "parabola":
            self.fp = float(self.p)
            self.size = self.fp
        else:
            self.fa, self.fb = float(self.a), float(self.b)
            self.size = max(self.fa, self.fb)

    # -------------------------------------------------------------- coordinates
    def to_canon(self, x, y, c=None, s=None, tx=None, ty=None):
        c = self.c if c is None else c
        s = self.s if s is None else s
        tx = self.tx if tx is None else tx
        ty = self.ty if ty is None else ty
        dx, dy = x - tx, y - ty
        return c * dx + s * dy, -s * dx + c * dy

    def to_canon_f(self, x, y):
        return self.to_canon(x, y, self.fc, self.fs, self.ftx, self.fty)

    def from_canon(self, X, Y):
        return self.tx + self.c * X - self.s * Y, self.ty + self.s * X + self.c * Y

    # -------------------------------------------------------------- parametrisations
    # branch: 0 for closed curves / parabola, +1 / -1 for the hyperbola branches
    def branches(self):
        return (1, -1) if self.kind == "hyperbola" else (0,)

    def P(self, t, br, lib=mpmath):
        """point, first and second derivative of the parametrisation at t."""
        if self.kind in ("ellipse", "circle"):
            a, b = (self.a, self.b) if lib is mpmath else (self.fa, self.fb)
            ct, st = lib.cos(t), lib.sin(t)
            return (a * ct, b * st), (-a * st, b * ct), (-a * ct, -b * st)
        if self.kind == "hyperbola":
            a, b = (self.a, self.b) if lib is mpmath else (self.fa, self.fb)
            ch, sh = lib.cosh(t), lib.sinh(t)
            return (br * a * ch, b * sh), (br * a * sh, b * ch), (br * a * ch, b * sh)
        p = self.p if lib is mpmath else self.fp
        return (t * t / (2 * p), t), (t / p, 1 + 0 * t), (1 / p + 0 * t, 0 * t)

    def t_range(self, X0, Y0, d0):
        """parameter interval containing every point within d0 of (X0, Y0) (float)."""
        if self.kind in ("ellipse", "circle"):
            return 0.0, 2 * math.pi, True
        if self.kind == "hyperbola":
            return math.asinh((Y0 - d0) / self.fb), math.asinh((Y0 + d0) / self.fb), False
        return Y0 - d0, Y0 + d0, False

    def upper_bound(self, X0, Y0):
        """distance to a vertex of the curve (float) -- an upper bound of the distance."""
        if self.kind == "parabola":
            return math.hypot(X0, Y0)
        return min(math.hypot(X0 - self.fa, Y0), math.hypot(X0 + self.fa, Y0))


def _rtsafe_mp(fun, lo, hi, t0, tol):
    """Safeguarded Newton on g = D' in [lo, hi] with g(lo) <= 0 <= g(hi) (mpmath)."""
    t = t0
    for _ in range(200):
        g, dg = fun(t)
        if g == 0:
            return t
        if g < 0:
            lo = t
        else:
            hi = t
        tn = t - g / dg if dg != 0 else (lo + hi) / 2
        if not (lo < tn < hi):
            tn = (lo + hi) / 2
        if abs(tn - t) <= tol * (1 + abs(t)):
            return tn
        t = tn
    return t


def ref_foot(conic: RefConic, x, y, n: int = 720, dps: int | None = None):
    """(d, Px, Py) in mpmath: the global minimum of the distance, found by sampling n
    parameter values per branch and refining every sampled local minimum in mpmath."""
    dps = dps or conic.dps
    with mpmath.workdps(dps + 10):
        xm, ym = _mpf(x), _mpf(y)
        if not (mpmath.isfinite(xm) and mpmath.isfinite(ym)):
            return mpmath.inf, mpmath.nan, mpmath.nan
        X0, Y0 = conic.to_canon(xm, ym)
        X0f, Y0f = float(X0), float(Y0)
        d0 = conic.upper_bound(X0f, Y0f) * (1 + 1e-9) + 1e-300
        lo, hi, periodic = conic.t_range(X0f, Y0f, d0)
        best = None
        for br in conic.branches():
            if conic.kind == "parabola":  # multiscale about the vertex: s = p sinh(u)
                u0, u1 = math.asinh((Y0f - d0) / conic.fp), math.asinh((Y0f + d0) / conic.fp)
                ts = conic.fp * np.sinh(np.linspace(u0, u1, n))
            else:
                ts = np.linspace(lo, hi, n, endpoint=not periodic)
            (PX, PY), _, _ = conic.P(ts, br, np)
            D = (PX - X0f) ** 2 + (PY - Y0f) ** 2
            idx = []
            for i in range(n):
                if periodic:
                    l, r = D[i - 1], D[(i + 1) % n]
                else:  # the range contains every point within d0: end points are not minima
                    if i == 0 or i == n - 1:
                        continue
                    l, r = D[i - 1], D[i + 1]
                if D[i] < l and D[i] <= r:
                    idx.append(i)
            # the distance has at most 4 critical points: refine the smallest local minima
            idx = sorted(idx, key=lambda i: D[i])[:4]
            for i in idx:
                def g(t, br=br):
                    (px, py), (dx, dy), (ddx, ddy) = conic.P(t, br)
                    ux, uy = px - X0, py - Y0
                    return ux * dx + uy * dy, dx * dx + dy * dy + ux * ddx + uy * ddy

                a_, b_ = mpmath.mpf(ts[i - 1]), mpmath.mpf(ts[(i + 1) % n])
                if periodic and i == n - 1:
                    b_ = b_ + 2 * mpmath.pi
                if periodic and i == 0:
                    a_ = a_ - 2 * mpmath.pi
                ga, gb = g(a_)[0], g(b_)[0]
                if ga <= 0 <= gb:
                    t = _rtsafe_mp(g, a_, b_, mpmath.mpf(ts[i]), mpmath.mpf(10) ** (-dps - 5))
                else:  # end of a non-periodic range or a flat spot: plain golden section
                    t = _golden_mp(lambda t: _dist2(conic, t, br, X0, Y0), a_, b_, dps)
                (px, py), _, _ = conic.P(t, br)
                dd = mpmath.sqrt((px - X0) ** 2 + (py - Y0) ** 2)
                if best is None or dd < best[0]:
                    best = (dd, px, py)
        if best is None:
            return mpmath.inf, mpmath.nan, mpmath.nan
        d, px, py = best
        wx, wy = conic.from_canon(px, py)
        return +d, +wx, +wy


def _dist2(conic, t, br, X0, Y0):
    (px, py), _, _ = conic.P(t, br)
    return (px - X0) ** 2 + (py - Y0) ** 2


def _golden_mp(f, a, b, dps):
    gr = (mpmath.sqrt(5) - 1) / 2
    c, d = b - gr * (b - a), a + gr * (b - a)
    fc, fd = f(c), f(d)
    tol = mpmath.mpf(10) ** (-(dps // 2) - 2)
    while abs(b - a) > tol * (1 + abs(a)):
        if fc < fd:
            b, d, fd = d, c, fc
            c = b - gr * (b - a)
            fc = f(c)
        else:
            a, c, fc = c, d, fd
            d = a + gr * (b - a)
            fd = f(d)
    return (a + b) / 2


def ref_distance(conic, x, y, dps: int = DPS) -> mpmath.mpf:
    """Reference distance (mpmath) from (x, y) to a conic (RefConic, dict or Conic)."""
    rc = conic if isinstance(conic, RefConic) else RefConic(conic, dps)
    return ref_foot(rc, x, y, dps=dps)[0]


# =========================================================================== grid distances

def _grid_foot(conic: RefConic, XS: np.ndarray, YS: np.ndarray, n: int = 512, newton: int = 5):
    """Vectorised float distances and foot points (sampling + Newton steps on the foot
    parameter).  Returns (d, px, py) arrays (world coordinates)."""
    XS, YS = np.asarray(XS, float), np.asarray(YS, float)
    X0, Y0 = conic.to_canon_f(XS, YS)
    X0, Y0 = np.atleast_1d(X0).ravel(), np.atleast_1d(Y0).ravel()
    best = np.full(X0.shape, np.inf)
    bx, by = np.zeros(X0.shape), np.zeros(X0.shape)
    ext = float(np.max(np.hypot(X0, Y0))) + conic.size
    for br in conic.branches():
        if conic.kind in ("ellipse", "circle"):
            ts = np.linspace(0, 2 * math.pi, n, endpoint=False)
        elif conic.kind == "hyperbola":
            T = math.asinh(2 * ext / conic.fb) + 0.5
            ts = np.linspace(-T, T, 2 * n)
        else:  # parabola: s = p sinh(u) for a multiscale sampling
            U = math.asinh(2 * ext / conic.fp) + 0.5
            ts = conic.fp * np.sinh(np.linspace(-U, U, 2 * n))
        (PX, PY), _, _ = conic.P(ts, br, np)
        for k in range(0, X0.size, 2048):
            x0, y0 = X0[k:k + 2048], Y0[k:k + 2048]
            D = (PX[None, :] - x0[:, None]) ** 2 + (PY[None, :] - y0[:, None]) ** 2
            j = np.argmin(D, axis=1)
            t = ts[j]
            for _ in range(newton):
                (px, py), (dx, dy), (ddx, ddy) = conic.P(t, br, np)
                ux, uy = px - x0, py - y0
                g = ux * dx + uy * dy
                dg = dx * dx + dy * dy + ux * ddx + uy * ddy
                tn = np.where(dg > 0, t - g / np.where(dg > 0, dg, 1), t)
                (qx, qy), _, _ = conic.P(tn, br, np)
                better = (qx - x0) ** 2 + (qy - y0) ** 2 < ux * ux + uy * uy
                t = np.where(better, tn, t)
            (px, py), _, _ = conic.P(t, br, np)
            dd = np.sqrt((px - x0) ** 2 + (py - y0) ** 2)
            upd = dd < best[k:k + 2048]
            best[k:k + 2048] = np.where(upd, dd, best[k:k + 2048])
            bx[k:k + 2048] = np.where(upd, px, bx[k:k + 2048])
            by[k:k + 2048] = np.where(upd, py, by[k:k + 2048])
    wx = conic.ftx + conic.fc * bx - conic.fs * by
    wy = conic.fty + conic.fs * bx + conic.fc * by
    return best, wx, wy


def _grid_dist(conic: RefConic, XS, YS, n: int = 512):
    shape = np.shape(XS)
    return _grid_foot(conic, XS, YS, n)[0].reshape(shape)


# =========================================================================== vertices

def _scene(conics):
    cx = np.mean([c.ftx for c in conics])
    cy = np.mean([c.fty for c in conics])
    H = max(max(abs(c.ftx - cx), abs(c.fty - cy)) + 2 * c.size for c in conics)
    return cx, cy, H


def _newton_vertex_mp(cs, q, dps, iters=30):
    with mpmath.workdps(dps + 10):
        x, y = _mpf(q[0]), _mpf(q[1])
        last, grow = None, 0
        for _ in range(iters):
            fs = [ref_foot(c, x, y, dps=dps) for c in cs]
            d = [f[0] for f in fs]
            grads = [((x - f[1]) / f[0], (y - f[2]) / f[0]) for f in fs]
            F1, F2 = d[0] - d[1], d[0] - d[2]
            a, b = grads[0][0] - grads[1][0], grads[0][1] - grads[1][1]
            c, e = grads[0][0] - grads[2][0], grads[0][1] - grads[2][1]
            det = a * e - b * c
            if not mpmath.isfinite(det) or det == 0:
                return None
            dx = ((F1 * e - b * F2) / det, (a * F2 - c * F1) / det)
            x, y = x - dx[0], y - dx[1]
            stp = abs(dx[0]) + abs(dx[1])
            if last is not None and stp > last:
                grow += 1
                if grow >= 3:
                    return None
            last = stp
            if abs(dx[0]) + abs(dx[1]) < mpmath.mpf(10) ** (-dps) * (1 + abs(x) + abs(y)):
                break
        fs = [ref_foot(c, x, y, dps=dps) for c in cs]
        return x, y, [f[0] for f in fs]


def _newton_vertex_float(cs, sx, sy, iters=40):
    """Vectorised float Newton on (d1 - d2, d1 - d3) from many seeds; returns converged points."""
    x, y = np.array(sx, float), np.array(sy, float)
    alive = np.ones(x.shape, bool)
    step = np.full(x.shape, np.inf)
    for _ in range(iters):
        fs = [_grid_foot(c, x, y, n=720) for c in cs]
        d = [f[0] for f in fs]
        with np.errstate(all="ignore"):
            g = [((x - f[1]) / f[0], (y - f[2]) / f[0]) for f in fs]
            F1, F2 = d[0] - d[1], d[0] - d[2]
            a, b = g[0][0] - g[1][0], g[0][1] - g[1][1]
            c, e = g[0][0] - g[2][0], g[0][1] - g[2][1]
            det = a * e - b * c
            dx = (F1 * e - b * F2) / det
            dy = (a * F2 - c * F1) / det
        bad = ~np.isfinite(dx) | ~np.isfinite(dy)
        alive &= ~bad
        dx, dy = np.where(bad, 0, dx), np.where(bad, 0, dy)
        # damp huge steps
        scale = 1 + np.abs(x) + np.abs(y)
        with np.errstate(all="ignore"):
            big = np.hypot(dx, dy) > scale
            fac = np.where(big, scale / np.maximum(np.hypot(dx, dy), 1e-300), 1.0)
        x, y = x - fac * dx, y - fac * dy
        step = fac * np.hypot(dx, dy) / scale
    fs = [_grid_foot(c, x, y, n=720) for c in cs]
    d = [f[0] for f in fs]
    r = d[0]
    # converged points only: along directions where three translated copies of one hyperbola are
    # nearly equidistant (differences of distances tending to constants), damped Newton runs off to
    # infinity with the differences O(1), which 1e-9·r accepts once r is huge (measured: 55 such
    # points at |x| ~ 1e52, all still doubling at the last step)
    ok = (alive & np.isfinite(r) & (r > 0) & (np.abs(d[0] - d[1]) < 1e-9 * r) & (np.abs(d[0] - d[2]) < 1e-9 * r)
          & (step < 1e-6))
    return [(float(u), float(v)) for u, v in zip(x[ok], y[ok])]


def reference_vertices(c1, c2, c3, dps: int = DPS, grid: int = 121, levels: int = 8,
                       growth: float = 4.0):
    """True Voronoi vertices of three conics: list of (x, y, r) as mpf, sorted by (x, y)."""
    cs = [c if isinstance(c, RefConic) else RefConic(c, dps) for c in (c1, c2, c3)]
    cx, cy, H = _scene(cs)
    seeds = []
    for lev in range(levels):
        h = H * growth ** lev
        xs = np.linspace(cx - h, cx + h, grid)
        ys = np.linspace(cy - h, cy + h, grid)
        XS, YS = np.meshgrid(xs, ys, indexing="ij")
        d = [_grid_dist(c, XS, YS) for c in cs]
        f, g = d[0] - d[1], d[0] - d[2]
        sf, sg = np.sign(f), np.sign(g)

        def changes(s):
            c4 = np.stack([s[:-1, :-1], s[1:, :-1], s[:-1, 1:], s[1:, 1:]])
            return (c4.max(axis=0) > 0) & (c4.min(axis=0) < 0) | (c4 == 0).any(axis=0)

        cells = np.argwhere(changes(sf) & changes(sg))
        for i, j in cells:
            seeds.append(((xs[i] + xs[i + 1]) / 2, (ys[j] + ys[j + 1]) / 2, h / grid))
    found: list[tuple[float, float]] = []
    if seeds:
        conv = _newton_vertex_float(cs, [t[0] for t in seeds], [t[1] for t in seeds])
        for u, v in conv:
            if any(math.hypot(u - a, v - b) < 1e-7 * (1 + abs(a) + abs(b)) for a, b in found):
                continue
            found.append((u, v))
    out = []
    for fx, fy in found:
        with mpmath.workdps(dps + 10):
            res = _newton_vertex_mp(cs, (fx, fy), dps)
            if res is None:
                continue
            ok = _check_vertex(cs, res, out, dps)
        if ok:
            out.append(ok)
    out.sort(key=lambda t: (t[0], t[1]))
    return out


def _check_vertex(cs, res, out, dps):
    if True:
        x, y, d = res
        r = d[0]
        if not mpmath.isfinite(r) or r <= 0:
            return None
        tol = mpmath.mpf(10) ** (-25) * r
        if abs(d[0] - d[1]) > tol or abs(d[0] - d[2]) > tol:
            return None
        # true-vertex check: denser sampling finds nothing closer than r
        dense = [ref_foot(c, x, y, n=2880, dps=dps)[0] for c in cs]
        if any(dd < r * (1 - mpmath.mpf(10) ** (-20)) for dd in dense):
            return None
        if any(abs(x - u) + abs(y - v) < mpmath.mpf(10) ** (-15) * (1 + abs(u) + abs(v)) for u, v, _ in out):
            return None
        return (x, y, r)


def reference_locate(c1, c2, c3, c4, dps: int = DPS, **kw) -> list[dict]:
    """Vertices of (c1, c2, c3) with their relation to c4, as dicts with mpf values like the
    vertices of validation_cases.json (x, y, radius, distance_to_fourth, margin,
    in_conflict, tangent); tangent means |margin| < 1e-30."""
    verts = reference_vertices(c1, c2, c3, dps=dps, **kw)
    r4 = c4 if isinstance(c4, RefConic) else RefConic(c4, dps)
    out = []
    with mpmath.workdps(dps + 10):
        for x, y, r in verts:
            d4 = ref_foot(r4, x, y, n=2880, dps=dps)[0]
            m = (d4 - r) / r
            tangent = abs(m) < mpmath.mpf(10) ** (-30)
            out.append({"x": x, "y": y, "radius": r, "distance_to_fourth": d4, "margin": m,
                        "in_conflict": bool(d4 < r and not tangent), "tangent": bool(tangent)})
    return out
