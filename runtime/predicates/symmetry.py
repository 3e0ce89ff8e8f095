"""Equal distances proved by symmetry: a point fixed by isometries that permute the sites.

If an isometry g of the plane fixes the point p and maps site A onto site B, then
d(p, B) = d(g(p), g(A)) = d(p, A) exactly.  The inputs people draw are full of such symmetries
(grids of identical shapes, mirror-symmetric arrangements), and their Voronoi vertices of degree
k > 3 sit at the fixed points: there the k sites are equidistant, which no float computation can
show and an exact algebraic one shows only at great cost (thesis §5.5: such configurations make the
offset systems exactly singular).  This module decides it exactly with rational arithmetic: p is
rational, the candidate isometries are the eight of the dihedral group D4 about p (reflections in
the horizontal, vertical and diagonal lines through p, rotations by multiples of π/2; all map
rational points to rational points), and a site's image is compared with the other sites by their
exact conic coefficients up to a common factor.  The sites are equidistant from p when the
isometries join them all (one class of the equivalence they generate).

Sites: :class:`runtime.sites.conic.Conic`, :class:`runtime.predicates.circles.Circle` and
:class:`runtime.predicates.circles.Point` (a point is the conic (x − a)² + (y − b)² = 0).

Public API: :func:`site_coefficients`, :func:`equidistant_by_symmetry`, :func:`rational_candidates`.
"""
from __future__ import annotations

from fractions import Fraction

__all__ = ["site_coefficients", "equidistant_by_symmetry", "rational_candidates"]

#: the linear parts of D4: (m11, m12, m21, m22), q ↦ p + M (q − p)
D4 = ((1, 0, 0, 1), (-1, 0, 0, 1), (1, 0, 0, -1), (-1, 0, 0, -1),
      (0, 1, 1, 0), (0, -1, -1, 0), (0, -1, 1, 0), (0, 1, -1, 0))


def _q(v) -> Fraction:
    if isinstance(v, Fraction):
        return v
    if hasattr(v, "p") and hasattr(v, "q"):            # flint.fmpq
        return Fraction(int(v.p), int(v.q))
    return Fraction(v)


def site_coefficients(site) -> tuple[Fraction, ...]:
    """Exact (a, b, c, d, e, f) of a·x² + b·xy + c·y² + d·x + e·y + f = 0, scaled so that the first
    non-zero coefficient is 1 (a site is determined by this tuple)."""
    if hasattr(site, "coefficients") and not hasattr(site, "r2"):
        co = [_q(v) for v in site.coefficients]
    else:
        cx, cy = _q(site.cx), _q(site.cy)
        r2 = _q(getattr(site, "r2", 0))
        co = [Fraction(1), Fraction(0), Fraction(1), -2 * cx, -2 * cy, cx * cx + cy * cy - r2]
    lead = next(v for v in co if v != 0)
    return tuple(v / lead for v in co)


def _image(co, M, p):
    """Coefficients of g(C) for g(q) = p + M(q − p), M orthogonal (so g⁻¹(q) = p + Mᵀ(q − p))."""
    a, b, c, d, e, f = co
    m11, m12, m21, m22 = M
    px, py = p
    # v = g⁻¹(q) = Mᵀ q + t, t = p − Mᵀ p; C(v) = 0 ⟺ g(C)(q) = 0
    tx = px - (m11 * px + m21 * py)
    ty = py - (m12 * px + m22 * py)
    # vx = m11·qx + m21·qy + tx, vy = m12·qx + m22·qy + ty
    ux, uy, u0 = (m11, m21, tx), (m12, m22, ty), None
    del u0

    def mul(P, Q):
        out: dict = {}
        for (i1, j1), c1 in P.items():
            for (i2, j2), c2 in Q.items():
                out[(i1 + i2, j1 + j2)] = out.get((i1 + i2, j1 + j2), 0) + c1 * c2
        return out

    X = {(1, 0): ux[0], (0, 1): ux[1], (0, 0): ux[2]}
    Y = {(1, 0): uy[0], (0, 1): uy[1], (0, 0): uy[2]}
    terms = [(a, mul(X, X)), (b, mul(X, Y)), (c, mul(Y, Y)), (d, X), (e, Y), (f, {(0, 0): 1})]
    tot: dict = {}
    for coef, P in terms:
        for k, v in P.items():
            tot[k] = tot.get(k, 0) + coef * v
    new = [Fraction(tot.get(k, 0)) for k in ((2, 0), (1, 1), (0, 2), (1, 0), (0, 1), (0, 0))]
    lead = next(v for v in new if v != 0)
    return tuple(v / lead for v in new)


def equidistant_by_symmetry(sites, p) -> bool:
    """Are all ``sites`` at the same distance from the rational point ``p``, proved by the D4
    isometries about p that map one site onto another (module docstring)?  Exact."""
    p = (_q(p[0]), _q(p[1]))
    cos = [site_coefficients(s) for s in sites]
    index = {c: t for t, c in enumerate(cos)}
    parent = list(range(len(cos)))

    def find(a):
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    for M in D4[1:]:
        for t, co in enumerate(cos):
            u = index.get(_image(co, M, p))
            if u is not None:
                parent[find(u)] = find(t)
    return len({find(t) for t in range(len(cos))}) == 1


def rational_candidates(x: float, y: float, reach: float):
    """Rational points within ``reach`` (max-norm) of (x, y): the exact value of the floats and
    their best approximations with denominators up to 2¹⁰ (symmetric drawings have simple
    fixed points)."""
    out = []
    fx, fy = Fraction(x), Fraction(y)
    for den in (None, 1, 2, 4, 8, 16, 64, 256, 1024):
        qx = fx if den is None else fx.limit_denominator(den)
        qy = fy if den is None else fy.limit_denominator(den)
        if abs(qx - fx) <= reach and abs(qy - fy) <= reach and (qx, qy) not in out:
            out.append((qx, qy))
    return out
