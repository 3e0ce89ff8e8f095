"""The two systems of thesis chapter 6.

(a) *Original curves* (§6.1, App. D.1): unknowns the vertex q = (x, y) and one foot point
    p_i = (x_i, y_i) per site; per site two equations — ``f_i(p_i) = 0`` and the normality
    ``(x − x_i)·∂_y f_i(p_i) − (y − y_i)·∂_x f_i(p_i) = 0`` (a *feature* of the site: the smooth
    part; arcs add their endpoints ``f = h_k = 0`` and rational singular points as point
    features) — and the equal squared distances ``|q−p_1|² = |q−p_2|² = |q−p_3|²``.
    8 equations, 8 unknowns.
(b) *Generalised offsets* (§6.3, App. D.2 with rigid motions only): unknowns (x, y, r), r the
    squared radius, equations ``o_i(x, y, r) = 0`` with ``o_i`` the canonical offset composed
    with the conic's rigid motion.  3 equations, 3 unknowns.

Both get the same necessary true-vertex constraints from rigorous sample points
(``|q − s|² ≥ r`` for every sample s of C1..C3), the "PV" inequalities of App. D made finite.
"""
from __future__ import annotations

import numpy as np
from flint import arb

from .boxes import Box
from .curves import Curve
from .offsets import conic_offset
from .poly import Poly
from .solver import Inequality, System

VARS_A = ("x", "y", "x1", "y1", "x2", "y2", "x3", "y3")
VARS_B = ("x", "y", "r")
#: Taylor forms for system (a) (low degree: the natural + mean-value forms are cheaper)
TAYLOR_ORIGINAL = True


def _embed(p: Poly, i: int) -> Poly:
    return p.rename(VARS_A, [2 + 2 * i, 3 + 2 * i])


def site_features(curve: Curve, endpoints, singular) -> list:
    """Features of a site: ('normal',), ('endpoint', k, ...) and ('point', (sx, sy))."""
    feats = [("normal",)]
    for k, _e in enumerate(curve.where):
        if any(ep.get("k") == k for ep in endpoints):
            feats.append(("endpoint", k))
    for s in singular:
        feats.append(("point", s))
    return feats


def feature_equations(curve: Curve, i: int, feat) -> tuple[list, list]:
    x = Poly.var(VARS_A, 0)
    y = Poly.var(VARS_A, 1)
    xi = Poly.var(VARS_A, 2 + 2 * i)
    yi = Poly.var(VARS_A, 3 + 2 * i)
    f = _embed(curve.f, i)
    ineqs = []
    if feat[0] == "normal":
        n = (x - xi) * _embed(curve.fy, i) - (y - yi) * _embed(curve.fx, i)
        eqs = [f, n]
        ineqs = [Inequality(_embed(h, i), s) for h, s in curve.where]
    elif feat[0] == "endpoint":
        k = feat[1]
        eqs = [f, _embed(curve.where[k][0], i)]
        ineqs = [Inequality(_embed(h, i), s) for kk, (h, s) in enumerate(curve.where) if kk != k]
    elif feat[0] == "point":
        sx, sy = feat[1]
        eqs = [xi - sx, yi - sy]
    else:
        raise ValueError(f"unknown feature {feat}")
    return eqs, ineqs


def foot_contractor(curve: Curve, i: int):
    """Block (SubEq3B-like) contraction of the foot point p_i with the two site equations
    (f_i, n_i) only, q in the box acting as interval parameters (parametric Krawczyk)."""
    from .verify import CRIT, crit_polys
    from .solver import krawczyk

    polys = crit_polys(curve)
    sub = System(CRIT, 2, polys, [], [], [arb(0), arb(0)], f"foot[{curve.name}]")
    k = 2 + 2 * i

    def contract(box: Box):
        qa = Box(box.lo[:2], box.hi[:2]).arbs()
        sub.params = qa
        pb = Box(box.lo[k:k + 2].copy(), box.hi[k:k + 2].copy())
        for _ in range(3):
            st, nb = krawczyk(sub, pb)
            if st == "empty":
                return None
            if nb is None or np.all(nb.width >= 0.9 * pb.width):
                pb = nb if nb is not None else pb
                break
            pb = nb
        out = box.copy()
        out.lo[k:k + 2] = pb.lo
        out.hi[k:k + 2] = pb.hi
        return out

    return contract


def original_system(curves: list[Curve], features: tuple, hooks=()) -> System:
    x = Poly.var(VARS_A, 0)
    y = Poly.var(VARS_A, 1)
    eqs, ineqs = [], []
    d2 = []
    for i in range(3):
        e, q = feature_equations(curves[i], i, features[i])
        eqs.extend(e)
        ineqs.extend(q)
        xi = Poly.var(VARS_A, 2 + 2 * i)
        yi = Poly.var(VARS_A, 3 + 2 * i)
        d2.append((x - xi) ** 2 + (y - yi) ** 2)
    eqs.append(d2[0] - d2[1])
    eqs.append(d2[0] - d2[2])
    label = "original[" + ",".join(f[0] for f in features) + "]"
    cons = [foot_contractor(curves[i], i) for i in range(3) if features[i][0] == "normal"]
    return System(VARS_A, 8, eqs, ineqs, list(hooks), [], label, taylor=TAYLOR_ORIGINAL, contractors=cons)


def original_domain(curves, dom: Box, rho: float) -> Box:
    lo = [dom.lo[0], dom.lo[1]]
    hi = [dom.hi[0], dom.hi[1]]
    for c in curves[:3]:
        bx = [dom.lo[0] - rho, dom.hi[0] + rho, dom.lo[1] - rho, dom.hi[1] + rho]
        if c.bbox is not None:
            bx = [max(bx[0], c.bbox[0]), min(bx[1], c.bbox[1]), max(bx[2], c.bbox[2]), min(bx[3], c.bbox[3])]
        if bx[0] > bx[1] or bx[2] > bx[3]:
            return None
        lo += [bx[0], bx[2]]
        hi += [bx[1], bx[3]]
    return Box(np.array(lo), np.array(hi))


def offset_polys(curves: list[Curve]) -> list[Poly]:
    out = []
    for c in curves:
        if c.conic is None:
            raise ValueError(f"site {c.name}: the offset formulation needs a conic with an exact canonical frame "
                             "(rational rotation); use formulation='original'")
        if c.is_arc:
            raise ValueError(f"site {c.name}: arcs are not supported by the offset formulation")
        k = c.conic
        out.append(conic_offset(k["kind"], k["params"], k["cos"], k["sin"], k["tx"], k["ty"], VARS_B))
    return out


def offset_system(curves: list[Curve], hooks=()) -> System:
    return System(VARS_B, 3, offset_polys(curves[:3]), [], list(hooks), [], "offset", taylor=True)


# ---------------------------------------------------------------------- sample constraints
def sample_hook(samples: np.ndarray, r_lower):
    """Rigorous pruning hook: discard a box if a proven site point s lies strictly inside the
    circle for every q in the box, i.e. max |q − s|² < min r (App. D "PV" inequalities)."""
    if samples.size == 0:
        return lambda box, xs: False
    sxl, sxh, syl, syh = samples[:, 0], samples[:, 1], samples[:, 2], samples[:, 3]

    def hook(box: Box, xs) -> bool:
        rl = r_lower(box)
        if rl <= 0:
            return False
        dx = np.maximum(np.abs(box.hi[0] - sxl), np.abs(sxh - box.lo[0]))
        dy = np.maximum(np.abs(box.hi[1] - syl), np.abs(syh - box.lo[1]))
        ub = (dx * dx + dy * dy) * (1 + 1e-12)
        return bool(np.any(ub < rl * (1 - 1e-12)))

    return hook


def _gap(alo, ahi, blo, bhi):
    return max(0.0, alo - bhi, blo - ahi)


def r_lower_original(box: Box) -> float:
    best = 0.0
    for i in range(3):
        gx = _gap(box.lo[0], box.hi[0], box.lo[2 + 2 * i], box.hi[2 + 2 * i])
        gy = _gap(box.lo[1], box.hi[1], box.lo[3 + 2 * i], box.hi[3 + 2 * i])
        best = max(best, (gx * gx + gy * gy) * (1 - 1e-12))
    return best


def r_lower_offset(box: Box) -> float:
    return float(box.lo[2])
