"""Generalised offsets of conics for the offset formulation (thesis §4.4, §6.3, App. B.3/B.4).

The canonical offsets are the implicit equations in (u, v, R) — R the *squared* offset
distance — of the families ``x² + c·y² + e`` (ellipse / hyperbola, degree 8, 104 terms),
``y² − 2·p·x`` (parabola, 23 terms) and the circle ``(u² + v² − R − ρ²)² − 4Rρ²``.

They are taken from the verified artefacts (``runtime.artefacts.load_offset``, derived offline by
``precompute/offsets.py``); there is no second derivation at run time, and a corrupted artefact
raises ``ArtefactError``.

Offsets are covariant under *rigid motions only* (thesis App. D.2 substitutes a non-orthogonal
affine map, which does not give the offset of the moved conic): the offset of
a moved conic is the canonical offset composed with ``(u, v) = rotation·((x, y) − t)``, R
unchanged.
"""
from __future__ import annotations

from fractions import Fraction
from functools import lru_cache

from flint import fmpq, fmpq_mpoly_ctx

from ..artefacts import ArtefactError, load_offset
from .poly import Poly

FAMILIES = {
    "ellipse_hyperbola": ("u", "v", "R", "c", "e"),
    "parabola": ("u", "v", "R", "p"),
}


def _from_artefacts(family: str) -> Poly:
    """The family's offset from the verified artefacts (:func:`runtime.artefacts.load_offset`: a
    missing, stale or corrupted artefact raises ArtefactError -- never bypassed by a second
    derivation at run time)."""
    off = load_offset({"ellipse_hyperbola": "ellipse", "parabola": "parabola"}[family])
    vars_ = tuple(off.variables)
    if set(vars_) != set(FAMILIES[family]):
        raise ArtefactError(f"offset artefact of {family} has variables {vars_}, expected {FAMILIES[family]}")
    p = Poly(vars_, dict(off.terms))
    order = [vars_.index(v) for v in FAMILIES[family]]
    return Poly(FAMILIES[family], {tuple(e[i] for i in order): c for e, c in p.terms.items()})


@lru_cache(maxsize=None)
def canonical_offset(family: str) -> Poly:
    """Implicit generalised offset of a canonical family, variables ``FAMILIES[family]``."""
    if family not in FAMILIES:
        raise ValueError(f"unknown offset family {family!r}; expected one of {sorted(FAMILIES)}")
    return _from_artefacts(family)


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
                                 "offset of the ellipse family degenerates for c = 1; a circle has the degree-4 offset of thesis Table 4.1)")
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
