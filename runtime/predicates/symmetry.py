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

Sites: :class:`runtime.sites.conic.Conic`, :class:`runtime.sites.circle.Circle` and
:class:`runtime.sites.circle.Point` (a point is the conic (x − a)² + (y − b)² = 0).

**Mirrors.**  If the reflection in a line ℓ maps site A onto site B and A lies strictly on one side
H of ℓ, then d(q, A) < d(q, B) for every q in the open half-plane H (the nearest point p of A to
the mirror image of q satisfies |q − p| < |q̄ − p| since p and q lie on the same side), and the
bisector of A and B is exactly ℓ.  :func:`mirror_line` finds such a line (the perpendicular
bisector of the centres, checked exactly on the coefficients).

Public API: :func:`site_coefficients`, :func:`equidistant_by_symmetry`, :func:`rational_candidates`,
:func:`site_centre`, :func:`mirror_line`, :func:`mirror_orbits`.
"""
from __future__ import annotations

import functools
from fractions import Fraction

from scipy.cluster.hierarchy import DisjointSet

from ..sites.rationals import to_fraction

__all__ = ["site_coefficients", "equidistant_by_symmetry", "rational_candidates", "site_centre", "mirror_line",
           "mirror_orbits"]

#: the linear parts of D4: (m11, m12, m21, m22), q ↦ p + M (q − p)
D4 = ((1, 0, 0, 1), (-1, 0, 0, 1), (1, 0, 0, -1), (-1, 0, 0, -1),
      (0, 1, 1, 0), (0, -1, -1, 0), (0, -1, 1, 0), (0, 1, -1, 0))


def _q(v) -> Fraction:
    return to_fraction(v)


def site_coefficients(site) -> tuple[Fraction, ...]:
    """Exact (a, b, c, d, e, f) of a·x² + b·xy + c·y² + d·x + e·y + f = 0, scaled so that the first
    non-zero coefficient is 1 (a site is determined by this tuple).  Cached per site object."""
    try:
        return _coefficients_cached(site)
    except TypeError:                  # an unhashable site
        return _coefficients(site)


@functools.lru_cache(maxsize=65536)
def _coefficients_cached(site):
    return _coefficients(site)


def _coefficients(site):
    if hasattr(site, "coefficients") and not hasattr(site, "r2"):
        co = [_q(v) for v in site.coefficients]
    else:
        cx, cy = _q(site.cx), _q(site.cy)
        r2 = _q(getattr(site, "r2", 0))
        co = [Fraction(1), Fraction(0), Fraction(1), -2 * cx, -2 * cy, cx * cx + cy * cy - r2]
    lead = next(v for v in co if v != 0)
    return tuple(v / lead for v in co)


@functools.lru_cache(maxsize=65536)
def _image(co, M, p):
    """Coefficients of g(C) for g(q) = p + M(q − p), M orthogonal (so g⁻¹(q) = p + Mᵀ(q − p))."""
    m11, m12, m21, m22 = M
    px, py = p
    # v = g⁻¹(q) = Mᵀ q + t, t = p − Mᵀ p; C(v) = 0 ⟺ g(C)(q) = 0
    tx = px - (m11 * px + m21 * py)
    ty = py - (m12 * px + m22 * py)
    return _substitute(co, (m11, m21, tx), (m12, m22, ty))


def _substitute(co, ux, uy):
    """Normalised coefficients of C(vx, vy) with vx = ux[0]·x + ux[1]·y + ux[2], vy likewise:
    with v = A·q + t and C(v) = vᵀMv + N·v + f, the image has M' = AᵀMA, N' = Aᵀ(2Mt + N),
    f' = tᵀMt + N·t + f."""
    a, b, c, d, e, f = co
    a11, a12, t1 = ux
    a21, a22, t2 = uy
    m11, m12, m22 = a, b / 2, c
    # M·A
    p11, p12 = m11 * a11 + m12 * a21, m11 * a12 + m12 * a22
    p21, p22 = m12 * a11 + m22 * a21, m12 * a12 + m22 * a22
    n11 = a11 * p11 + a21 * p21
    n12 = a11 * p12 + a21 * p22
    n22 = a12 * p12 + a22 * p22
    # 2Mt + N
    w1 = 2 * (m11 * t1 + m12 * t2) + d
    w2 = 2 * (m12 * t1 + m22 * t2) + e
    new = [n11, 2 * n12, n22, a11 * w1 + a21 * w2, a12 * w1 + a22 * w2,
           m11 * t1 * t1 + 2 * m12 * t1 * t2 + m22 * t2 * t2 + d * t1 + e * t2 + f]
    new = [Fraction(v) for v in new]
    lead = next(v for v in new if v != 0)
    return tuple(v / lead for v in new)


def equidistant_by_symmetry(sites, p) -> bool:
    """Are all ``sites`` at the same distance from the rational point ``p``, proved by the D4
    isometries about p that map one site onto another (module docstring)?  Exact."""
    p = (_q(p[0]), _q(p[1]))
    cos = [site_coefficients(s) for s in sites]
    index = {c: t for t, c in enumerate(cos)}
    classes = DisjointSet(range(len(cos)))
    for M in D4[1:]:
        for t, co in enumerate(cos):
            u = index.get(_image(co, M, p))
            if u is not None:
                classes.merge(u, t)
                if classes.n_subsets == 1:
                    return True
    return classes.n_subsets == 1


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


def site_centre(site):
    """The exact centre of a circle, point or central conic (None for a parabola): the zero of the
    gradient of a·x² + b·xy + c·y² + d·x + e·y + f."""
    return _centre(site_coefficients(site))


def _centre(co):
    a, b, c, d, e, _ = co
    det = 4 * a * c - b * b
    if det == 0:
        return None
    return ((b * e - 2 * c * d) / det, (b * d - 2 * a * e) / det)


def mirror_line(site_a, site_b):
    """The line ℓ = {q : n·q = k} (n, k rational) whose reflection maps site_a exactly onto site_b,
    tried as the perpendicular bisector of their centres; None if that reflection does not."""
    return _mirror(site_coefficients(site_a), site_coefficients(site_b))


def _reflect(co, n, k):
    """Coefficients of the reflection of a conic in the line n·q = k."""
    nn = n[0] * n[0] + n[1] * n[1]
    m11, m12 = 1 - 2 * n[0] * n[0] / nn, -2 * n[0] * n[1] / nn
    m22 = 1 - 2 * n[1] * n[1] / nn
    t = (2 * k * n[0] / nn, 2 * k * n[1] / nn)
    return _substitute(co, (m11, m12, t[0]), (m12, m22, t[1]))


def mirror_orbits(sites):
    """A line n·q = k whose reflection maps the set of ``sites`` onto itself, and the orbits (sets
    of indices; a site on the line is its own orbit), tried among the perpendicular bisectors of
    the centres of pairs of sites; None if none does.  Points of the line are equidistant from the
    two sites of an orbit."""
    cos = [site_coefficients(x) for x in sites]
    index = {c: t for t, c in enumerate(cos)}
    for a in range(len(cos)):
        for b in range(a + 1, len(cos)):
            ml = _mirror(cos[a], cos[b])
            if ml is None:
                continue
            image = [index.get(_reflect(co, *ml)) for co in cos]
            if all(t is not None for t in image):
                orbits = sorted({tuple(sorted({t, image[t]})) for t in range(len(cos))})
                return ml, orbits
    return None


@functools.lru_cache(maxsize=65536)
def _mirror(co_a, co_b):
    ca, cb = _centre(co_a), _centre(co_b)
    if ca is None or cb is None or ca == cb:
        return None
    n = (cb[0] - ca[0], cb[1] - ca[1])
    k = (n[0] * (ca[0] + cb[0]) + n[1] * (ca[1] + cb[1])) / 2
    nn = n[0] * n[0] + n[1] * n[1]
    # reflection q ↦ q − 2 (n·q − k) n / |n|² = M q + t (its own inverse)
    m11, m12 = 1 - 2 * n[0] * n[0] / nn, -2 * n[0] * n[1] / nn
    m22 = 1 - 2 * n[1] * n[1] / nn
    t = (2 * k * n[0] / nn, 2 * k * n[1] / nn)
    image = _substitute(co_a, (m11, m12, t[0]), (m12, m22, t[1]))
    return (n, k) if image == co_b else None
