"""Sites for the interval locator: real algebraic curves, optionally restricted to arcs.

A site is ``{(x, y) : f(x, y) = 0, h_k(x, y) ⋆_k 0}`` (thesis §6.1, Def. 1.0.1 with one
equation per component).  Conics also carry their exact canonical frame, needed by the
offset formulation (§6.3).  Rigorous *sample points* (boxes proven to contain a point of the
site, by an exact sign change on a vertical or horizontal line) give necessary conditions
``|q − s|² ≥ r`` for a true Voronoi vertex (no site point strictly inside the empty circle).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from fractions import Fraction

import numpy as np
from flint import arb, fmpq, fmpq_poly

from .boxes import arb_hi, arb_lo, interval_arb
from .poly import Poly, parse_poly

XY = ("x", "y")
_SENSES = (">=", "<=", ">", "<")


@dataclass
class Curve:
    f: Poly
    where: list = field(default_factory=list)  # list of (Poly, sense)
    name: str = ""
    conic: dict | None = None  # {'kind','params','cos','sin','tx','ty'} exact
    bbox: tuple | None = None  # rigorous outer (xmin, xmax, ymin, ymax) when bounded

    def __post_init__(self):
        if self.f.names != XY:
            raise ValueError(f"curve polynomial must be in (x, y), got {self.f.names}")
        if self.f.degree() < 1:
            raise ValueError(f"site {self.name or self.f}: polynomial of degree < 1")
        self.fx = self.f.diff(0)
        self.fy = self.f.diff(1)
        self._samples: dict = {}

    @property
    def is_arc(self) -> bool:
        return bool(self.where)

    def where_status(self, xa: arb, ya: arb) -> str:
        """'in' if every restriction holds on the ball, 'out' if one certainly fails, else 'unknown'."""
        status = "in"
        for h, sense in self.where:
            v = h.arb_eval(xa, ya)
            lo, hi = arb_lo(v), arb_hi(v)
            if sense == ">=":
                ok, bad = lo >= 0, hi < 0
            elif sense == ">":
                ok, bad = lo > 0, hi <= 0
            elif sense == "<=":
                ok, bad = hi <= 0, lo > 0
            else:
                ok, bad = hi < 0, lo >= 0
            if bad:
                return "out"
            if not ok:
                status = "unknown"
        return status

    # ------------------------------------------------------------------ rigorous samples
    def sample_points(self, region, lines: int = 24) -> np.ndarray:
        """Boxes [xlo, xhi, ylo, yhi] each proven to contain a point of the site (in region)."""
        key = (tuple(float(v) for v in region), lines)
        if key in self._samples:
            return self._samples[key]
        xmin, xmax, ymin, ymax = (float(v) for v in region)
        out = []
        for axis in (0, 1):
            lo, hi = (xmin, xmax) if axis == 0 else (ymin, ymax)
            olo, ohi = (ymin, ymax) if axis == 0 else (xmin, xmax)
            for k in range(lines):
                c = Fraction(lo + (hi - lo) * (k + 0.5 + 0.123) / (lines + 0.5))
                up = self._restrict(axis, c)
                if up is None or up.degree() < 1:
                    continue
                try:
                    roots = up.complex_roots()
                except Exception:  # noqa: BLE001
                    continue
                for rt, _m in roots:
                    re = float(rt.real.mid())
                    if abs(float(rt.imag.mid())) > 1e-8 * (1 + abs(re)) or not (olo <= re <= ohi):
                        continue
                    d = 1e-10 * (1 + abs(re))
                    a, b = Fraction(re - d), Fraction(re + d)
                    va, vb = up(fmpq(a.numerator, a.denominator)), up(fmpq(b.numerator, b.denominator))
                    if va * vb >= 0:
                        continue
                    fa, fb = float(a), float(b)
                    if axis == 0:
                        bx = [float(c), float(c), fa, fb]
                    else:
                        bx = [fa, fb, float(c), float(c)]
                    if c != Fraction(float(c)):
                        continue
                    if self.where and self.where_status(interval_arb(bx[0], bx[1]), interval_arb(bx[2], bx[3])) != "in":
                        continue
                    out.append(bx)
        arr = np.array(out, dtype=float).reshape(-1, 4)
        self._samples[key] = arr
        return arr

    def _restrict(self, axis: int, c: Fraction):
        """Univariate fmpq_poly f(c, y) (axis 0) or f(x, c) (axis 1)."""
        deg = self.f.degree(1 - axis)
        coeffs = [Fraction(0)] * (deg + 1)
        for (i, j), v in self.f.terms.items():
            if axis == 0:
                coeffs[j] += v * c**i
            else:
                coeffs[i] += v * c**j
        while coeffs and coeffs[-1] == 0:
            coeffs.pop()
        if not coeffs:
            return None
        return fmpq_poly([fmpq(v.numerator, v.denominator) for v in coeffs])


# ---------------------------------------------------------------------- parsing
def _parse_where(items) -> list:
    import sympy

    x, y = sympy.symbols("x y")
    out = []
    for it in items or []:
        if isinstance(it, tuple) and len(it) == 2 and it[1] in _SENSES:
            out.append((parse_poly(it[0], XY), it[1]))
            continue
        rel = sympy.sympify(it, locals={"x": x, "y": y}) if isinstance(it, str) else it
        op = getattr(rel, "rel_op", None)
        if op not in _SENSES:
            raise ValueError(f"restriction {it!r} must be an inequality (>=, >, <=, <)")
        out.append((Poly.from_sympy(rel.lhs - rel.rhs, XY), op))
    return out


def conic_frame_poly(kind, params, cos, sin, tx, ty) -> Poly:
    cos, sin, tx, ty = (Fraction(v) for v in (cos, sin, tx, ty))
    X = Poly(XY, {(1, 0): cos, (0, 1): sin, (0, 0): -cos * tx - sin * ty})
    Y = Poly(XY, {(1, 0): -sin, (0, 1): cos, (0, 0): sin * tx - cos * ty})
    kind = kind.lower()
    if kind == "ellipse":
        return X * X * (1 / Fraction(params["A2"])) + Y * Y * (1 / Fraction(params["B2"])) - 1
    if kind == "hyperbola":
        return X * X * (1 / Fraction(params["A2"])) - Y * Y * (1 / Fraction(params["B2"])) - 1
    if kind == "parabola":
        return Y * Y - X * (2 * Fraction(params["p"]))
    if kind == "circle":
        return X * X + Y * Y - Fraction(params["r2"])
    raise ValueError(f"unknown conic kind {kind!r}")


def _conic_bbox(conic) -> tuple | None:
    kind = conic["kind"]
    c, s = float(conic["cos"]), float(conic["sin"])
    tx, ty = float(conic["tx"]), float(conic["ty"])
    if kind == "ellipse":
        a2, b2 = float(conic["params"]["A2"]), float(conic["params"]["B2"])
    elif kind == "circle":
        a2 = b2 = float(conic["params"]["r2"])
    else:
        return None
    hx = math.sqrt(c * c * a2 + s * s * b2) * (1 + 1e-9) + 1e-12
    hy = math.sqrt(s * s * a2 + c * c * b2) * (1 + 1e-9) + 1e-12
    return (tx - hx, tx + hx, ty - hy, ty + hy)


def _conic_from_canonical(can: dict) -> dict:
    kind = can["type"] if "type" in can else can["kind"]
    params = {k: Fraction(str(can[k])) for k in ("A2", "B2", "p", "r2") if k in can}
    if "params" in can:
        params.update({k: Fraction(str(v)) for k, v in can["params"].items()})
    return {"kind": kind, "params": params, "cos": Fraction(str(can["cos"])), "sin": Fraction(str(can["sin"])),
            "tx": Fraction(str(can["tx"])), "ty": Fraction(str(can["ty"]))}


def _from_conic_object(obj, name) -> Curve:
    coeffs = [Fraction(c) for c in obj.coefficients]
    f = Poly(XY, {(2, 0): coeffs[0], (1, 1): coeffs[1], (0, 2): coeffs[2], (1, 0): coeffs[3],
                  (0, 1): coeffs[4], (0, 0): coeffs[5]})
    conic = None
    fr = getattr(obj, "exact_frame", None)
    if fr is not None:
        conic = {"kind": fr.kind, "params": {k: Fraction(v) for k, v in fr.params.items()},
                 "cos": Fraction(fr.cos), "sin": Fraction(fr.sin), "tx": Fraction(fr.tx), "ty": Fraction(fr.ty)}
    bbox = _conic_bbox(conic) if conic else None
    if bbox is None and getattr(obj, "kind", None) in ("ellipse", "circle") and getattr(obj, "frame", None) is not None:
        fr = obj.frame
        fc = {"kind": fr.kind, "params": dict(fr.params), "cos": fr.cos, "sin": fr.sin, "tx": fr.tx, "ty": fr.ty}
        b = _conic_bbox(fc)
        if b is not None:  # float frame: widen generously
            w = max(b[1] - b[0], b[3] - b[2])
            bbox = (b[0] - 1e-6 * w, b[1] + 1e-6 * w, b[2] - 1e-6 * w, b[3] + 1e-6 * w)
    return Curve(f, [], name, conic, bbox)


def parse_curve(spec, name: str = "") -> Curve:
    """Accepts a Curve, a runtime.sites.conic.Conic, a validation-case conic dict
    ({"coefficients": [...], "canonical": {...}}), a dict {"poly": ..., "where": [...]}
    or a bare polynomial (sympy string / Poly / python-flint mpoly)."""
    if isinstance(spec, Curve):
        return spec
    if hasattr(spec, "coefficients") and not isinstance(spec, dict):
        return _from_conic_object(spec, name)
    if isinstance(spec, dict):
        if "canonical" in spec or "coefficients" in spec:
            conic = _conic_from_canonical(spec["canonical"]) if "canonical" in spec else None
            if "coefficients" in spec:
                a, b, c, d, e, f0 = (Fraction(str(v)) for v in spec["coefficients"])
                f = Poly(XY, {(2, 0): a, (1, 1): b, (0, 2): c, (1, 0): d, (0, 1): e, (0, 0): f0})
            else:
                f = conic_frame_poly(conic["kind"], conic["params"], conic["cos"], conic["sin"], conic["tx"], conic["ty"])
            if conic is None:
                try:
                    from ..sites.conic import Conic

                    return _from_conic_object(Conic.from_coefficients(*spec["coefficients"]), name)
                except ImportError:
                    pass
            return Curve(f, _parse_where(spec.get("where")), name, conic, _conic_bbox(conic) if conic else None)
        if "poly" in spec:
            return Curve(parse_poly(spec["poly"], XY), _parse_where(spec.get("where")), name or str(spec["poly"]),
                         None, tuple(spec["bbox"]) if spec.get("bbox") else None)
        raise ValueError(f"cannot read site {spec!r}: expected keys 'poly' or 'coefficients'/'canonical'")
    return Curve(parse_poly(spec, XY), [], name or str(spec))
