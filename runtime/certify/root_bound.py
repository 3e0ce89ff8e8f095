"""A proved upper bound on the number of isolated solutions of one triple offset system.

Completeness by counting (:mod:`runtime.certify.complete`) needs, for the *given* conics, a number
N such that o1 = o2 = o3 = 0 has at most N isolated complex solutions; then N certified, distinct,
simple solutions are all of them once positive-dimensional components are excluded
(:mod:`runtime.certify.dimension`).  The generic counts of the precompute (msolve's
parametrisation degree of random members modulo a prime) are only lower bounds of the generic
number.  The bound used here is a mixed volume:

1. (x, y, R) ↦ (x, y, T), T = x² + y² − R, is a polynomial automorphism of C³, so the isolated
   solutions of the o_i and of g_i(x, y, T) = o_i(x, y, x² + y² − T) correspond one to one,
   with their multiplicities.
2. Li & Wang, *The BKK root count in C^n* (Math. Comp. 65, 1996), Theorem 2.4: the number of
   isolated zeros in C^n of a square system, counted with multiplicity, is at most the mixed
   volume of the Newton polytopes of its supports *with the origin added*; the mixed volume is
   monotone in each polytope (Bernstein 1975; thesis §3.3.1, Def. 3.3.3).
3. The precompute (:mod:`precompute.root_counts`) records, per offset family, a support set S_f in
   circle space (the union of the sampled members' supports, origin added) and the mixed volume
   MV(S_f1, S_f2, S_f3) for each family triple.  Here the support of each g_i of the given conics
   is checked, exactly, to lie in S_f of its family; then MV(supp g_i ∪ {0}) ≤ MV(S_f1, S_f2, S_f3)
   bounds the isolated solutions.

For every family triple the recorded mixed volume equals msolve's count (8 for CCC … 184 for
EEE), so the generic counts are proved bounds whenever the support check passes.  A member whose
support leaves S_f (a monomial the samples did not show) gets no bound: completeness is then left
to the exact route, never assumed.
"""
from __future__ import annotations

from functools import lru_cache

from ..algebra.circle_space import circle_space_polynomial

__all__ = ["count_bound", "family_of"]


def family_of(conic) -> str:
    """The offset family of a conic (thesis App. B): circle, ellipse (also hyperbolas), parabola."""
    return {"circle": "circle", "ellipse": "ellipse", "hyperbola": "ellipse", "parabola": "parabola"}[conic.kind]


def count_bound(c1, c2, c3) -> tuple[int | None, str]:
    """(N, note): N bounds the isolated complex solutions of the offset system of C1, C2, C3
    (module docstring), or None with the reason when no bound is proved."""
    from ..solve.exact import exact_triple_system

    fams = tuple(family_of(c) for c in (c1, c2, c3))
    polys = exact_triple_system(c1, c2, c3)
    return _bound(fams, tuple(tuple(sorted(p.items())) for p in polys))


@lru_cache(maxsize=256)
def _bound(fams, key) -> tuple[int | None, str]:
    from ..artefacts import load_root_count_bounds

    mvs, supports = load_root_count_bounds()
    mv = mvs.get(tuple(sorted(fams)))
    if mv is None:
        return None, f"no mixed volume recorded for the family triple {fams}"
    for i, (fam, poly) in enumerate(zip(fams, key)):
        sup = {tuple(int(v) for v in e) for e in circle_space_polynomial(dict(poly)).to_dict()}
        outside = sup - supports[fam]
        if outside:
            return None, (f"conic {i + 1}: circle-space monomial {sorted(outside)[0]} outside the recorded "
                          f"support of the {fam} family (no mixed-volume bound)")
    return mv, f"at most {mv} isolated solutions (circle-space mixed volume, Li–Wang)"
