"""Numeric polynomial utilities for the conic conflict locator (thesis §5.3, §5.5).

The generalised offset of a conic C (thesis §4.4, App. B) is stored once per *family* in
canonical coordinates: o(u, v, R) with (u, v) the canonical coordinates of the point and R the
squared offset distance (``runtime.artefacts.load_offset``).  The offset of the actual conic is
obtained by composing it with the rigid motion of C's canonical frame (offsets are covariant
under rigid motions only: a general affine map does not preserve distances, thesis §4.1) and, for numerical work, with a similarity of the plane
(``R`` scales by the square of the ratio).

This module is the thin numeric layer under :mod:`runtime.solve.vertices`:

* :func:`family_and_params` -- which offset family and which parameter values a conic uses
  (ellipse  X²/A2+Y²/B2=1  ->  x² + c·y² + e with c = A2/B2, e = −A2;
   hyperbola X²/A2−Y²/B2=1 ->  c = −A2/B2, e = −A2;  parabola Y²=2pX -> p;  circle -> rho);
* :class:`CanonicalOffset` -- the specialised offset of one conic with vectorised evaluation and
  gradient in *world* coordinates (x, y, R) through its canonical frame (float / complex numpy,
  or mpmath for high-precision Newton steps);
* :class:`WorkingFrame` and :func:`compose_offset` -- the offset expressed as a polynomial in the
  coordinates (x, y, R) of a working frame (rotation, translation, scaling), as a dict
  {(i, j, k): float}, which is what the Macaulay / null-space solver consumes.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..artefacts import load_offset

#: weighted degree (weights 1, 1, 2 for x, y, R) of the offset of each family (Table 4.1)
FAMILY_WEIGHTED_DEGREE = {"ellipse": 8, "parabola": 6, "circle": 4}


def family_and_params(conic, dps: int | None = None) -> tuple[str, dict]:
    """Offset family and its parameter values for ``conic`` (float, or mpmath at ``dps``)."""
    fr = conic.frame if dps is None else conic.frame_mp(dps)
    kind, prm = fr.kind, fr.params
    if kind == "ellipse":
        return "ellipse", {"c": prm["A2"] / prm["B2"], "e": -prm["A2"]}
    if kind == "hyperbola":
        return "ellipse", {"c": -prm["A2"] / prm["B2"], "e": -prm["A2"]}
    if kind == "parabola":
        return "parabola", {"p": prm["p"]}
    if kind == "circle":
        r2 = prm["r2"]
        if dps is None:
            return "circle", {"rho": math.sqrt(r2)}
        import mpmath
        return "circle", {"rho": mpmath.sqrt(r2)}
    raise ValueError(f"no offset family for conic kind {kind!r}")


@lru_cache(maxsize=8)
def _family_terms(family: str):
    off = load_offset(family)
    return off


def _specialise(family: str, params: dict):
    """(exps (T,3) int array, coefs list) of the offset in (u, v, R) for these parameter values
    (floats give floats, mpmath numbers give mpmath numbers)."""
    off = _family_terms(family)
    pidx = [off.variables.index(p) for p in off.parameters]
    is_float = all(isinstance(v, float) for v in params.values())
    acc: dict = {}
    for exps, coef in off.terms:
        if is_float:
            val = float(coef)
        else:
            import mpmath
            val = mpmath.mpf(coef.numerator) / coef.denominator
        for p, i in zip(off.parameters, pidx):
            if exps[i]:
                val = val * params[p] ** exps[i]
        key = (exps[0], exps[1], exps[2])
        acc[key] = acc.get(key, 0) + val
    keys = sorted(acc)
    return np.array(keys, dtype=np.int64).reshape(-1, 3), [acc[k] for k in keys]


class CanonicalOffset:
    """Offset of one conic, evaluated in world coordinates through its canonical frame.

    ``o(x, y, R) = o_family(u, v, R)`` with ``(u, v) = (cos(x−tx)+sin(y−ty), −sin(x−tx)+cos(y−ty))``
    (thesis §5.3: C_i is the canonical conic moved by a rigid motion).
    """

    def __init__(self, conic, dps: int | None = None):
        self.conic = conic
        self.dps = dps
        self.family, self.params = family_and_params(conic, dps)
        fr = conic.frame if dps is None else conic.frame_mp(dps)
        self.frame = fr
        self.cos, self.sin, self.tx, self.ty = fr.cos, fr.sin, fr.tx, fr.ty
        self.exps, coefs = _specialise(self.family, self.params)
        if dps is None:
            self.coefs = np.array(coefs, dtype=float)
        else:
            self.coefs = coefs
        self.wdeg = FAMILY_WEIGHTED_DEGREE[self.family]
        self.du = int(self.exps[:, 0].max())
        self.dv = int(self.exps[:, 1].max())
        self.dR = int(self.exps[:, 2].max())

    # ------------------------------------------------------------------ float / complex
    def uv(self, x, y):
        dx, dy = x - self.tx, y - self.ty
        return self.cos * dx + self.sin * dy, -self.sin * dx + self.cos * dy

    def eval_grad(self, x, y, R):
        """Values, gradients (d/dx, d/dy, d/dR) and the absolute term sums (for relative
        residuals) at arrays of points (numpy, real or complex)."""
        u, v = self.uv(np.asarray(x), np.asarray(y))
        R = np.asarray(R)
        n = u.shape
        up = _powers(u, self.du)
        vp = _powers(v, self.dv)
        Rp = _powers(R, self.dR)
        e = self.exps
        c = self.coefs
        mono = up[e[:, 0]] * vp[e[:, 1]] * Rp[e[:, 2]]          # (T, n)
        val = c @ mono
        absval = np.abs(c) @ np.abs(mono)
        # partial derivatives in u, v, R
        du = (c * e[:, 0]) @ (up[np.maximum(e[:, 0] - 1, 0)] * vp[e[:, 1]] * Rp[e[:, 2]])
        dv = (c * e[:, 1]) @ (up[e[:, 0]] * vp[np.maximum(e[:, 1] - 1, 0)] * Rp[e[:, 2]])
        dR = (c * e[:, 2]) @ (up[e[:, 0]] * vp[e[:, 1]] * Rp[np.maximum(e[:, 2] - 1, 0)])
        gx = self.cos * du - self.sin * dv
        gy = self.sin * du + self.cos * dv
        del n
        return val, np.stack([gx, gy, dR], axis=-1), absval

    # ------------------------------------------------------------------ mpmath
    def eval_grad_mp(self, x, y, R):
        """Value, gradient and absolute term sum at one point in mpmath (uses the mp frame)."""
        dx, dy = x - self.tx, y - self.ty
        u = self.cos * dx + self.sin * dy
        v = -self.sin * dx + self.cos * dy
        val = du = dv = dR = 0
        absval = 0
        for (i, j, k), c in zip(self.exps.tolist(), self.coefs):
            m = u ** i * v ** j * R ** k
            val += c * m
            absval += abs(c * m)
            if i:
                du += c * i * u ** (i - 1) * v ** j * R ** k
            if j:
                dv += c * j * u ** i * v ** (j - 1) * R ** k
            if k:
                dR += c * k * u ** i * v ** j * R ** (k - 1)
        return val, (self.cos * du - self.sin * dv, self.sin * du + self.cos * dv, dR), absval


def _powers(z, d):
    """Array P with P[i] = z**i, i = 0..d (z an array)."""
    z = np.asarray(z)
    out = np.empty((d + 1,) + z.shape, dtype=np.result_type(z, float))
    out[0] = 1
    for i in range(1, d + 1):
        out[i] = out[i - 1] * z
    return out


# =========================================================================== working frame

@dataclass(frozen=True)
class WorkingFrame:
    """Similarity from working coordinates w to world coordinates p:  p = P0 + L·Q·w, with Q the
    rotation (cos, sin) of C1's canonical frame (C1 axis-aligned, thesis §5.3) and L > 0 the
    scale that brings the conics' cores into the unit disc; R_world = L²·R_work."""

    cos: float
    sin: float
    px: float
    py: float
    L: float

    def to_world(self, wx, wy):
        return (self.px + self.L * (self.cos * wx - self.sin * wy),
                self.py + self.L * (self.sin * wx + self.cos * wy))

    def to_work(self, x, y):
        dx, dy = (x - self.px) / self.L, (y - self.py) / self.L
        return self.cos * dx + self.sin * dy, -self.sin * dx + self.cos * dy


def core_points(conic) -> list[tuple[float, float]]:
    """A few world points spanning the 'core' of a conic: axis ends of an ellipse or circle, the
    asymptote box of a hyperbola, vertex / focus / latus rectum ends of a parabola."""
    fr = conic.frame
    prm = fr.params
    if fr.kind in ("ellipse", "hyperbola"):
        a, b = math.sqrt(prm["A2"]), math.sqrt(prm["B2"])
        pts = [(a, b), (a, -b), (-a, b), (-a, -b)]
    elif fr.kind == "circle":
        r = math.sqrt(prm["r2"])
        pts = [(r, r), (r, -r), (-r, r), (-r, -r)]
    else:
        p = prm["p"]
        pts = [(0.0, 0.0), (p / 2, p), (p / 2, -p)]
    return [tuple(float(t) for t in fr.from_canonical(X, Y)) for X, Y in pts]


def working_frame(conics, first) -> WorkingFrame:
    """Working frame: rotation of ``first``'s canonical frame, origin at the centre of the
    bounding box of all core points (in that rotated frame), L = half its diagonal."""
    fr = first.frame
    c, s = float(fr.cos), float(fr.sin)
    pts = np.array([p for cn in conics for p in core_points(cn)])
    # rotated coordinates
    X = c * pts[:, 0] + s * pts[:, 1]
    Y = -s * pts[:, 0] + c * pts[:, 1]
    cx, cy = (X.max() + X.min()) / 2, (Y.max() + Y.min()) / 2
    L = math.hypot(X.max() - X.min(), Y.max() - Y.min()) / 2
    if not (L > 0 and math.isfinite(L)):
        raise ValueError("cannot scale the configuration (degenerate extent)")
    px, py = c * cx - s * cy, s * cx + c * cy
    return WorkingFrame(c, s, px, py, L)


def scene_to_site_ratio(conics, wf: WorkingFrame) -> float:
    """The working frame's half-diagonal L over the largest half-extent of a conic's core points
    (:func:`core_points`): about 1–6 for sites drawn next to each other, 10 and more for small
    sites far apart."""
    r = max(float(np.ptp(np.array(core_points(c)), axis=0).max()) / 2 for c in conics)
    return wf.L / r if r > 0 else math.inf


def compose_offset(off: CanonicalOffset, wf: WorkingFrame) -> dict[tuple[int, int, int], float]:
    """The offset of ``off.conic`` as a polynomial in working coordinates (x, y, R):
    o(u(x, y), v(x, y), L²·R) with u, v affine in (x, y); normalised to max |coef| = 1."""
    # canonical coords as affine functions of working coords
    # world = P0 + L Q w ; canonical = Rot_i (world - t_i)
    ci, si = float(off.cos), float(off.sin)
    # world x = px + L(cw x - sw y) ; world y = py + L(sw x + cw y)
    ax = np.array([wf.L * wf.cos, -wf.L * wf.sin])   # d world_x / d (wx, wy)
    ay = np.array([wf.L * wf.sin, wf.L * wf.cos])
    bx, by = wf.px - float(off.tx), wf.py - float(off.ty)
    U = (ci * ax + si * ay, ci * bx + si * by)        # u = U[0]·w + U[1]
    V = (-si * ax + ci * ay, -si * bx + ci * by)
    du, dv = off.du, off.dv
    Up = _lin_powers(U, du)
    Vp = _lin_powers(V, dv)
    D = off.wdeg
    out = np.zeros((D + 1, D + 1, off.dR + 1))
    L2 = wf.L ** 2
    prods = {}                                        # u^i·v^j, shared by the terms with several k
    for (i, j, k), c in zip(off.exps.tolist(), off.coefs):
        prod = prods.get((i, j))
        if prod is None:
            prod = prods[(i, j)] = _mul2(Up[i], Vp[j])
        n0, n1 = prod.shape
        out[:n0, :n1, k] += c * L2 ** k * prod
    m = np.abs(out).max()
    res = {}
    nz = np.nonzero(np.abs(out) > 1e-300)
    for a, b, k in zip(*nz):
        res[(int(a), int(b), int(k))] = out[a, b, k] / m
    return res


def _lin_powers(lin, d):
    """Coefficient arrays P[i][a, b] of (l0 x + l1 y + l2)^i."""
    (l0, l1), l2 = lin
    base = np.array([[l2, l1], [l0, 0.0]])
    out = [np.ones((1, 1))]
    for _ in range(d):
        out.append(_mul2(out[-1], base))
    return out


def _mul2(A, B):
    """Product of two bivariate polynomials given as coefficient arrays [deg_x, deg_y].  Every
    coefficient is a sum over the terms of A in row-major order; a loop over the entries of B in
    reverse row-major order forms the same sums bit for bit (the extra zero products leave a sum
    started at +0.0 unchanged), in fewer passes when B is the smaller (the powers of a linear form)."""
    n0, n1 = A.shape[0] + B.shape[0] - 1, A.shape[1] + B.shape[1] - 1
    out = np.zeros((n0, n1))
    if B.size < np.count_nonzero(A):
        for e in range(B.shape[0] - 1, -1, -1):
            for f in range(B.shape[1] - 1, -1, -1):
                out[e:e + A.shape[0], f:f + A.shape[1]] += B[e, f] * A
        return out
    for a in range(A.shape[0]):
        for b in range(A.shape[1]):
            c = A[a, b]
            if c != 0:
                out[a:a + B.shape[0], b:b + B.shape[1]] += c * B
    return out


def eval_dict(poly: dict, x, y, R):
    """Evaluate {(i, j, k): c} at (x, y, R) (scalars or arrays)."""
    return sum(c * x ** i * y ** j * R ** k for (i, j, k), c in poly.items())
