"""Krawczyk boxes of conjugate solutions (runtime.certify.complete.certify_solutions).

The offsets have rational coefficients, so non-real solutions of o1 = o2 = o3 = 0 come in
conjugate pairs and one Krawczyk test per pair suffices (the conjugate box holds the conjugate
solution).  Checked on the four-ellipse demo triple (184 solutions, thesis §5.5): every box is
certified, every numeric solution lies in its own box (so the conjugate boxes were given to the
right solutions), the boxes are pairwise disjoint, and conjugation maps the set of non-real boxes
onto itself.
"""
from __future__ import annotations

from flint import acb, arb

from curvedvoronoi.runtime.certify.complete import certify_solutions
from curvedvoronoi.runtime.predicates.locator import demo_configuration, voronoi_vertices


def _ball(z):
    return z if isinstance(z, acb) else acb(z)


def _contains_point(K, s) -> bool:
    # the numeric point, widened by 1e-9 relative (it is a float approximation of the zero)
    out = []
    for k, v in zip(K, s):
        r = 1e-9 * max(1.0, abs(v))
        out.append(_ball(k).overlaps(acb(arb(v.real, r), arb(v.imag, r))))
    return all(out)


def test_conjugate_boxes_of_the_demo_triple():
    c1, c2, c3, _ = demo_configuration()
    S = voronoi_vertices(c1, c2, c3).solution.points
    assert len(S) == 184
    boxes = certify_solutions(c1, c2, c3, S)
    kinds = [kind for kind, _ in boxes]
    assert None not in kinds
    assert kinds.count("real") == 8 and kinds.count("nonreal") == 176
    for (kind, K), s in zip(boxes, S):
        assert _contains_point(K, s)
    # pairwise disjoint (some coordinate of every pair of boxes does not overlap)
    Ks = [[_ball(k) for k in K] for _, K in boxes]
    for a in range(len(Ks)):
        for b in range(a + 1, len(Ks)):
            assert not all(Ks[a][i].overlaps(Ks[b][i]) for i in range(3))
    # conjugation permutes the non-real boxes: each conjugate box overlaps exactly one box
    nonreal = [K for kind, K in zip(kinds, Ks) if kind == "nonreal"]
    for K in nonreal:
        conj = [k.conjugate() for k in K]
        hits = [L for L in nonreal if all(L[i].overlaps(conj[i]) for i in range(3))]
        assert len(hits) == 1
