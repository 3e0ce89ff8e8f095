"""Generalised offsets of conics for the offset formulation (thesis §4.4, §6.3, App. B.3/B.4).

The canonical offsets are the implicit equations in (u, v, R) — R the *squared* offset
distance — of the families ``x² + c·y² + e`` (ellipse / hyperbola, degree 8, 104 terms),
``y² − 2·p·x`` (parabola, 23 terms) and the circle ``(u² + v² − R − ρ²)² − 4Rρ²``.

They are taken from ``runtime.artefacts.load_offset(family)`` when the lead's artefacts are
available, and otherwise recomputed here with python-flint (``res_y(res_x(f, n), res_x(f, d))``,
factor, and keep the factor that vanishes at an exact rational point ``p + k∇f(p)``,
``R = k²|∇f(p)|²`` of the offset — DESIGN.md §3: the resultant has a spurious factor).

Offsets are covariant under *rigid motions only* (DESIGN.md pitfall on App. D.2): the offset of
a moved conic is the canonical offset composed with ``(u, v) = rotation·((x, y) − t)``, R
unchanged.
"""
from __future__ import annotations

from fractions import Fraction
from functools import lru_cache

from flint import fmpq, fmpq_mpoly_ctx, fmpz_mpoly_ctx

from .poly import Poly

FAMILIES = {
    "ellipse_hyperbola": ("u", "v", "R", "c", "e"),
    "parabola": ("u", "v", "R", "p"),
}


def _from_artefacts(family: str) -> Poly | None:
    try:
        from .. import artefacts
    except Exception:  # noqa: BLE001 - artefacts module not landed yet
        return None
    load = getattr(artefacts, "load_offset", None)
    if load is None:
        return None
    names = {"ellipse_hyperbola": ("ellipse", "ellipse_hyperbola", "x2_cy2_e"),
             "parabola": ("parabola", "y2_2px")}[family]
    for nm in names:
        try:
            off = load(nm)
        except Exception:  # noqa: BLE001
            continue
        vars_ = tuple(off.variables)
        if set(vars_) != set(FAMILIES[family]):
            continue
        p = Poly(vars_, dict(off.terms))
        order = [vars_.index(v) for v in FAMILIES[family]]
        return Poly(FAMILIES[family], {tuple(e[i] for i in order): c for e, c in p.terms.items()})
    return None


def _compute(family: str) -> Poly:
    names = ("x", "y") + FAMILIES[family]
    ctx = fmpz_mpoly_ctx.get(names, "lex")
    g = dict(zip(names, ctx.gens()))
    x, y, u, v, R = g["x"], g["y"], g["u"], g["v"], g["R"]
    if family == "ellipse_hyperbola":
        c, e = g["c"], g["e"]
        f = x**2 + c * y**2 + e
        fx, fy = 2 * x, 2 * c * y
        # test point: c=2, e=-3, foot (1,1), grad (2,4), k=1/2 -> (2,3), R=5
        test = {"u": 2, "v": 3, "R": 5, "c": 2, "e": -3}
    else:
        p = g["p"]
        f = y**2 - 2 * p * x
        fx, fy = -2 * p, 2 * y
        # p=1/2: foot (1,1), grad (-1,2), k=1 -> (0,3), R=5
        test = {"u": 0, "v": 3, "R": 5, "p": Fraction(1, 2)}
    n = (u - x) * fy - (v - y) * fx
    d = (u - x) ** 2 + (v - y) ** 2 - R
    res = f.resultant(n, "x").resultant(f.resultant(d, "x"), "y")
    _, factors = res.factor()
    for fac, _mult in factors:
        if fac.degrees()[names.index("u")] == 0:
            continue
        poly = Poly(names, {tuple(e): c for e, c in fac.to_dict().items()})
        poly = Poly(FAMILIES[family], {e[2:]: c for e, c in poly.terms.items()})
        vals = [Fraction(test[v_]) for v_ in FAMILIES[family]]
        if poly(*vals) != 0:
            continue
        # second check: another offset point must also vanish (spurious factors fail one of them)
        if family == "ellipse_hyperbola":
            # c=-1/3 (hyperbola), e=-1: foot (2,3)?  4 - 3 - 1 = 0; grad (4,-2), k=1 -> (6,1), R=20
            chk = [6, 1, 20, Fraction(-1, 3), -1]
        else:
            # p=2: foot (2,2)? 4 - 8 != 0; foot (1/2, 2)? 4 - 2 = 2 no; foot (2, 2*sqrt2) irrational;
            # foot (8, ... ) y^2 = 4x: (1,2): grad (-4,4), k=1/2 -> (-1,4), R=8
            chk = [-1, 4, 8, 2]
        if poly(*[Fraction(c_) for c_ in chk]) != 0:
            continue
        return poly
    raise RuntimeError(f"no offset factor found for {family}")


@lru_cache(maxsize=None)
def canonical_offset(family: str) -> Poly:
    """Implicit generalised offset of a canonical family, variables ``FAMILIES[family]``."""
    if family not in FAMILIES:
        raise ValueError(f"unknown offset family {family!r}; expected one of {sorted(FAMILIES)}")
    p = _from_artefacts(family)
    return p if p is not None else _compute(family)


def conic_offset(kind: str, params: dict, cos, sin, tx, ty, names=("x", "y", "r")) -> Poly:
    """Offset polynomial o(x, y, r) (r = squared distance) of a conic in canonical frame.

    Frame convention (validation data / CONIC_API): ``(X, Y) = (cos(x−tx) + sin(y−ty),
    −sin(x−tx) + cos(y−ty))``; ellipse ``X²/A2 + Y²/B2 = 1``, hyperbola ``X²/A2 − Y²/B2 = 1``,
    parabola ``Y² = 2pX``, circle ``X² + Y² = r2``.  All inputs are exact rationals and the
    rotation must satisfy cos² + sin² = 1 exactly (a rigid motion).
    """
    cos, sin, tx, ty = (Fraction(v) for v in (cos, sin, tx, ty))
    if cos * cos + sin * sin != 1:
        raise ValueError("offset formulation needs an exact rotation (cos² + sin² = 1); "
                         "App. D.2's non-rigid substitution is not an offset")
    ctx3 = fmpq_mpoly_ctx.get(tuple(names), "lex")
    x, y, r = ctx3.gens()
    q = lambda a: fmpq(a.numerator, a.denominator)  # noqa: E731
    U = q(cos) * (x - q(tx)) + q(sin) * (y - q(ty))
    V = -q(sin) * (x - q(tx)) + q(cos) * (y - q(ty))
    ctx_uvr = fmpq_mpoly_ctx.get(("u", "v", "R"), "lex")
    kind = kind.lower()
    if kind == "circle":
        r2 = Fraction(params["r2"])
        u, v, R = ctx_uvr.gens()
        canon = (u**2 + v**2 - R - q(r2)) ** 2 - 4 * q(r2) * R
    else:
        if kind in ("ellipse", "hyperbola"):
            A2, B2 = Fraction(params["A2"]), Fraction(params["B2"])
            c = A2 / B2 if kind == "ellipse" else -A2 / B2
            vals = {"c": c, "e": -A2}
            fam = "ellipse_hyperbola"
            if c == 1:
                raise ValueError("ellipse with equal axes is a circle: use kind='circle' (the degree-8 "
                                 "offset degenerates for c = 1, DESIGN.md §3)")
        elif kind == "parabola":
            vals = {"p": Fraction(params["p"])}
            fam = "parabola"
        else:
            raise ValueError(f"unknown conic kind {kind!r}")
        off = canonical_offset(fam)
        terms: dict = {}
        for e, cf in off.terms.items():
            k = cf
            for name, ex in zip(off.names[3:], e[3:]):
                k *= vals[name] ** ex
            key = e[:3]
            terms[key] = terms.get(key, Fraction(0)) + k
        canon = ctx_uvr.from_dict({k: q(v) for k, v in terms.items() if v})
    moved = canon.compose(U, V, r)
    return Poly(tuple(names), {tuple(e): Fraction(int(c.p), int(c.q)) for e, c in moved.to_dict().items()})
