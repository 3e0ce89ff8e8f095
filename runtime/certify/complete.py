"""Completeness of a vertex list (thesis §5.3–§5.5: the locator solves o1 = o2 = o3 = 0).

The numeric locator returns all N complex solutions (x, y, R) of the offset system
o1 = o2 = o3 = 0 it found (generalised Voronoi vertices, thesis §5.2) and the *generic count*
of the type configuration (e.g. 184 for three ellipses: generated/counts/root_counts.json, computed by
precompute/root_counts.py with msolve).  Completeness argument:

1. every solution s_k is enclosed in a box X_k by a **complex Krawczyk** test on the exact
   offsets o_i (the verified generic offset of :mod:`runtime.artefacts`, App. B.1–B.2,
   specialised at the conic's exact rational coefficients): X_k holds exactly one solution,
   which is simple (nonsingular Jacobian).  A far solution, terribly conditioned in (x, y, R),
   is instead certified in a chart of P³ of circles [A : x̂ : ŷ : T̂] (:mod:`runtime.certify.chart`)
   and enclosed in (x, y, R) by ball arithmetic.  The tests run on the offsets composed with an
   exact similarity to the scene frame (dyadic centre, power-of-two scale:
   :func:`runtime.certify.offset_system.scene_frame`), so a spread-out scene is as well scaled as
   a compact one; the frame boxes are mapped back to (x, y, R) in ball arithmetic.  Non-real
   solutions come in conjugate pairs (real coefficients): of a numerically conjugate pair only
   one is tested, the other gets the conjugate box, which holds exactly one solution, the
   conjugate one, also simple (step 2 covers any mispairing).  Steps 1–3 are
   :mod:`runtime.certify.solution_boxes` (ball test) and :mod:`runtime.certify.offset_batch`
   (the batched float test); what they leave uncertified is retried or replaced by
   :mod:`runtime.certify.lost_roots`;
2. the enclosures are pairwise disjoint, so the N solutions are distinct;
3. a candidate with tiny imaginary part is tested on a *conjugation-symmetric* box: as the
   o_i have real coefficients, the unique solution in it is real.  Otherwise some coordinate of
   the enclosure must exclude the real axis (proved non-real);
4. if N equals a proved bound on the isolated solutions of *these* conics, these are all of
   them.  The bound is the circle-space mixed volume of the family triple
   (:func:`runtime.certify.root_bound.count_bound`: Li–Wang's BKK bound in C³, after an exact check
   that each offset's circle-space support lies in its family's recorded support); it equals the
   generic count of the precompute (``generated/counts/root_counts.json``: degrees of msolve's
   rational parametrisation of random members over F_p, not the runtime solvers) for every family
   triple, so counting uses the generic count and proves it for the member.  Solutions on
   positive-dimensional components are not covered by counting, so the system is first proved
   zero-dimensional (:func:`runtime.certify.dimension.zero_dimensional`: the projective closure in
   the P³ of circles is finite modulo a prime, hence over Q̄); with finitely many solutions, all are
   isolated and the count bounds them all.  When that proof or the count does not close,
   :func:`completeness_exact` decides from msolve's exact real solutions, which also detects a
   positive-dimensional system.
5. every proven-real solution either matches a certified vertex (its box contains the vertex's
   box) or is proved *not* to be a true vertex: R < 0, or a real foot point on some C_i strictly
   closer than √R, or no real foot point at distance √R (R is the squared distance to a complex
   critical point only), or a witness point of some C_i closer than √R
   (:mod:`runtime.certify.not_a_vertex`).

This module strings the steps together (:func:`_completeness`: :func:`_enclose_all`,
:func:`_replace_lost`, :func:`_prove_distinct`, :func:`_count_closes`) and matches the real
solutions with the certified vertices (:func:`completeness_with_vertices`, which also proves a
vertex at a real solution no candidate matched) or with msolve's exact real solutions
(:func:`completeness_exact`).

Length: one proof, steps 1–5 and the two ways of closing step 5 on the vertices; the steps share
the solution boxes and their failure notes, and the search helpers live in
:mod:`runtime.certify.lost_roots`.

*Tuned constants.*  Precisions (64, 128, 256, 512, 1024 bits), Newton step counts (4, 8, 12, 20,
30), the caps :data:`_MAX_CHART`, :data:`_MAX_DIAGNOSED` and ``lost_roots.MAX_LOST``, the
nearly-real threshold ``offset_batch.NEARLY_REAL`` and the start grids of the lost-root search
were set on measured cases (each named where it is defined: e.g. 30 Newton steps for a conjugate
pair read 2e-9 off the real axis, HHHH ×100).  They choose midpoints, tests and Newton starts
only.  Every box kept satisfies K(X) ⊂ int X for its own X (one simple zero), reality is decided
by symmetry or by an imaginary part excluding 0, distinctness by the final disjointness check of
all N boxes, and the count by the proved bound: a different constant can cost time or make a
proof fail (``complete`` False, with the reason), never make a false ``complete`` True.
"""
from __future__ import annotations

from fractions import Fraction

import flint
import numpy as np
from flint import acb, acb_mat, arb

from .dimension import zero_dimensional
from .foot import foot_polynomial, normalised_coefficients, working_prec
from .interval_newton import krawczyk_image
from .lost_roots import MAX_LOST, certify_split_pairs, moved_solutions, replace_unproved, retry_or_diagnose
from .not_a_vertex import closer_witness, not_a_vertex
from .offset_batch import clear_float_system_cache
from .offset_system import OffsetSystem, exact_offset_terms, inside_disc  # noqa: F401 (re-exported)
from .root_bound import count_bound
from .solution_boxes import balls_overlap, boxes_disjoint, certify_solutions

__all__ = ["clear_certification_caches", "certify_completeness", "completeness_with_vertices", "completeness_exact",
           "one_zero_in_both",
           "OffsetSystem", "certify_solutions", "exact_offset_terms"]

#: at most this many uncertified solutions get the high-precision retry / diagnosis (each costs
#: Newton at 512 bits and Krawczyk at 512/1024 bits; only time, no verdict depends on it)
_MAX_DIAGNOSED = 4
#: the circle-space chart test is tried when at most this many solutions are uncertified (more
#: uncertified solutions mean a bad list rather than a few far solutions; only time depends on it)
_MAX_CHART = 16


def clear_certification_caches() -> None:
    """Forget the per-triple systems of the certification (float and ball coefficient tables,
    scene-frame systems, zero-dimensionality proofs)."""
    from . import dimension, offset_system

    clear_float_system_cache()
    offset_system.clear_offset_system_caches()
    dimension.clear_dimension_cache()


def certify_completeness(c1, c2, c3, solutions, expected_count: int | None, *, max_prec: int = 256):
    """(complete, note): are ``solutions`` (N × 3 complex (x, y, R)) provably *all* the isolated
    solutions of o1 = o2 = o3 = 0, distinct, with reality decided (module docstring)?"""
    ok, note, _ = _completeness(c1, c2, c3, solutions, expected_count)
    return ok, note


def _completeness(c1, c2, c3, solutions, expected_count):
    """(complete, note, real boxes): steps 1–4 of the module docstring."""
    S = np.asarray(solutions, dtype=complex).reshape(-1, 3)
    if expected_count is None:
        return False, "no generic solution count for this configuration", []
    if len(S) != expected_count:
        return False, f"{len(S)} solutions given, generic count is {expected_count}", []
    boxes, first_failed, n_chart, diag = _enclose_all(c1, c2, c3, S)
    ok, lost_note = _replace_lost(c1, c2, c3, S, boxes, first_failed, diag)
    if not ok:
        return False, lost_note, []
    ok, n_more, note = _prove_distinct(c1, c2, c3, S, boxes, first_failed)
    if not ok:
        return False, note, []
    n_chart += n_more
    lost_note = note or lost_note
    ok, note = _count_closes(c1, c2, c3, len(S))
    if not ok:
        return False, note, []
    reals = [K for kind, K in boxes if kind == "real"]
    note = f"{len(S)} distinct simple solutions ({len(reals)} real) = generic count, {note}"
    note += lost_note
    if n_chart:
        note += f" ({n_chart} far solution(s) certified in a circle-space chart)"
    return True, note, reals


def _uncertified(boxes) -> list[int]:
    return [k for k, (kind, _) in enumerate(boxes) if kind is None]


def _enclose_all(c1, c2, c3, S):
    """Step 1 (and 3): a Krawczyk box with its reality decided for every listed solution, where the
    tests succeed: the float batch and 64-bit balls, then 128 and 256 bits with up to 30 Newton
    steps, then for at most :data:`_MAX_CHART` left the circle-space chart of P³
    (:func:`runtime.certify.chart.certify_in_chart`) and the split conjugate pairs, then for at most
    :data:`_MAX_DIAGNOSED` the polished retry at 512/1024 bits or a diagnosis.  Returns
    (boxes, indices the first pass failed on, number certified in a chart, diagnoses); a box
    (None, ·) is uncertified.  Every box returned holds exactly one zero, simple (the tests' proof)."""
    boxes = certify_solutions(c1, c2, c3, S)
    first_failed = _uncertified(boxes)
    for prec in (128, 256):
        failed = _uncertified(boxes)
        if not failed:
            break
        # up to 30 Newton steps: a complex root read next to the real axis (a conjugate pair 5e-5 of
        # its size apart, read 2e-9 off the axis: HHHH ×100, held-out seed 806) needs 10–30 before
        # complex Newton splits the pair
        again = certify_solutions(c1, c2, c3, S[failed], prec=prec, iters=30)
        for k, b in zip(failed, again):
            boxes[k] = b
    failed = _uncertified(boxes)
    n_chart = 0
    if failed and len(failed) <= _MAX_CHART:
        # far (ill-conditioned in (x, y, R)) solutions: Krawczyk in a circle-space chart of P³,
        # world enclosure by ball arithmetic (proof in runtime.certify.chart)
        from .chart import certify_in_chart
        for k in failed:
            box = certify_in_chart((c1, c2, c3), S[k])
            if box is not None:
                boxes[k] = box
                n_chart += 1
        failed = _uncertified(boxes)
    if failed and len(failed) <= _MAX_CHART:
        certify_split_pairs(c1, c2, c3, S, failed, boxes)
        failed = _uncertified(boxes)
    diag = []
    for k in failed[:_MAX_DIAGNOSED]:
        box, text = retry_or_diagnose(c1, c2, c3, S[k])
        if box is not None:
            boxes[k] = box
        else:
            diag.append(f"solution {k}: {text}")
    return boxes, first_failed, n_chart, diag


def _replace_lost(c1, c2, c3, S, boxes, first_failed, diag):
    """(ok, note): solutions still uncertified are replaced by zeros found around them
    (:func:`runtime.certify.lost_roots.replace_unproved`, at most :data:`runtime.certify.lost_roots.MAX_LOST`);
    not ok (note: why) if that fails.  The note of a success says how many were replaced."""
    failed = _uncertified(boxes)
    if not failed:
        return True, ""
    # a point that is no solution (Newton leaves it): e.g. a real point where real Newton stalled
    # between the members of a conjugate pair closer to the real axis than it can tell, while
    # one of the pair was listed twice; search around it
    n_lost = (replace_unproved(c1, c2, c3, S, boxes, moved_solutions(S, boxes, first_failed))
              if len(failed) <= MAX_LOST else 0)
    if not n_lost:
        note = f"{len(failed)} of {len(S)} solutions not certified by Krawczyk"
        if diag:
            note += " (" + "; ".join(diag) + ")"
        return False, note
    return True, (f" ({n_lost} uncertified or overlapping solution(s) replaced by solutions found by Newton at "
                  "128 bits from starts around them)")


def _prove_distinct(c1, c2, c3, S, boxes, first_failed):
    """Step 2, (ok, number certified in a chart, note): the N boxes are pairwise disjoint, so the N
    zeros are distinct.  Overlapping boxes are first certified again in a circle-space chart, then
    replaced by a search (:func:`runtime.certify.lost_roots.replace_unproved`); disjointness is
    checked again on the final boxes.  The note is "" or says what was replaced (or why not ok)."""
    overlaps: list = []
    if boxes_disjoint([K for _, K in boxes], overlaps):
        return True, 0, ""
    # a near-double pair (two simple zeros closer than the first boxes' radii, e.g. small sites
    # far apart): each of them again in a circle-space chart, where Newton separates them and
    # the Krawczyk boxes are tiny; any box that holds a unique zero may replace another
    from .chart import certify_in_chart
    n_chart = 0
    again = sorted({k for pair in overlaps for k in pair})
    if len(again) <= _MAX_CHART:
        for k in again:
            box = certify_in_chart((c1, c2, c3), S[k])
            if box is not None:
                boxes[k] = box
                n_chart += 1
    if boxes_disjoint([K for _, K in boxes]):
        return True, n_chart, ""
    n_lost = replace_unproved(c1, c2, c3, S, boxes, moved_solutions(S, boxes, first_failed))
    if not n_lost:
        return False, n_chart, "two solution enclosures overlap (distinctness not proven)"
    return True, n_chart, (f" ({n_lost} solution(s) whose enclosure overlapped another replaced by solutions "
                           "found by Newton at 128 bits from starts around them)")


def _count_closes(c1, c2, c3, n: int):
    """Step 4, (ok, note): n distinct simple zeros are all the isolated zeros when the system is
    zero-dimensional (:func:`runtime.certify.dimension.zero_dimensional`) and n equals a proved bound
    on its isolated zeros (:func:`runtime.certify.root_bound.count_bound`, Li–Wang)."""
    # counting bounds the *isolated* solutions only: positive-dimensional components are excluded
    # first (runtime.certify.dimension: modular dimension test of the projective closure in circle space)
    zero_dim, dim_note = zero_dimensional(c1, c2, c3)
    if not zero_dim:
        return False, f"{n} distinct simple solutions = generic count, but {dim_note}"
    # the count must be a proved bound on the isolated solutions of *these* conics
    # (runtime.certify.root_bound: circle-space mixed volume, Li–Wang)
    bound, bound_note = count_bound(c1, c2, c3)
    if bound is None or bound != n:
        return False, (f"{n} distinct simple solutions = generic count, but no proved bound equal to it "
                       f"({bound_note})")
    return True, f"{bound_note}; {dim_note}"


def one_zero_in_both(c1, c2, c3, K, B) -> bool:
    """Proof that the zeros of the offset system of (C1, C2, C3) enclosed by the real ball vectors
    K and B (x, y, R) are one point: a Krawczyk test succeeds on a box holding both."""
    return _same_by_krawczyk(OffsetSystem((c1, c2, c3)), K, B)


def _same_by_krawczyk(sys: "OffsetSystem", K, B, prec: int = 128) -> bool:
    """Proof that the solution enclosed by the (real) ball vector K and the vertex enclosed by B
    are the same point: a Krawczyk test succeeds on a box X containing both (the offset system has
    a unique solution in X; the vertex solves the offset system)."""
    with working_prec(prec):
        m = [acb(K[i].mid()) for i in range(3)]
        r = []
        for i in range(3):
            d = abs(K[i].mid() - B[i].mid()) + K[i].rad() + B[i].rad()
            r.append(arb(2 * d.upper() + 2 * (abs(m[i]).abs_upper() + 1) * arb(2) ** (-prec // 2)))
        vals, Jm = sys.eval(m)
        try:
            Y = acb_mat(Jm).mid().inv().mid()
        except ZeroDivisionError:
            return False
        YF = Y * acb_mat([[v] for v in vals])
        dX = [acb(arb(0, ri), arb(0, ri)) for ri in r]
        X = [m[i] + dX[i] for i in range(3)]
        Kr = krawczyk_image(m, YF, Y, acb_mat(sys.eval(X)[1]), dX)
        if not all(inside_disc(Kr[i], m[i], r[i]) for i in range(3)):
            return False
        # X ⊇ K and X ⊇ B by construction (radius ≥ 2·(distance of centres + radii))
        return True


def completeness_with_vertices(c1, c2, c3, solutions, expected_count, certs, *, max_prec: int = 256,
                               retighten=None, certify_at=None, found=None):
    """Completeness of the certified vertex list ``certs`` (CertifiedVertex objects).
    ``retighten(cv)``: a tighter (x, y, R) box of the same vertex as ``cv`` (or None), tried when
    a real solution's enclosure meets only ``cv``'s box but neither contains the other.
    ``certify_at(K)``: a CertifiedVertex started at the real solution box K (or None), tried last
    for a real solution that matches no certified vertex and is not proved to be none; a proven
    true vertex whose box lies inside K (K holds exactly one zero of the offset system) is that
    solution, a vertex the list lacked: it is appended to ``found``.  Measured: three hyperbolas
    100× apart (held-out seed 1004, SkylakeX OpenBLAS kernels), a real pair 3·10⁻⁶ of its size apart
    listed as one candidate twice, which the search of :func:`_replace_lost` completes."""
    ok, note, reals = _completeness(c1, c2, c3, solutions, expected_count)
    if not ok:
        return False, note
    fps = [foot_polynomial(normalised_coefficients(c)) for c in (c1, c2, c3)]
    matched = set()
    with working_prec(128):
        for K in reals:
            hit = [k for k, cv in enumerate(certs) if cv.proven and cv.box is not None
                   and all(K[i].contains(cv.box[i]) for i in range(3))]
            if len(hit) == 1:
                matched.add(hit[0])
                continue
            if hit:
                return False, "a real solution matches several vertices"
            near = [k for k, cv in enumerate(certs) if cv.proven and cv.box is not None
                    and all(balls_overlap(K[i], cv.box[i]) for i in range(3))]
            # a far vertex's 64-bit box may be wider than K and meet it only: one Krawczyk box
            # holding both, or a tighter box of the vertex inside K (:func:`_same_zero`)
            if len(near) == 1 and _same_zero(c1, c2, c3, K, certs[near[0]], retighten):
                matched.add(near[0])
                continue
            if not_a_vertex(fps, K) or closer_witness((c1, c2, c3), fps, K):
                continue
            # undecided: near a double foot point the foot-distance enclosures grow like the square
            # root of the box; a tighter box of the same zero (one inside K, where the zero is
            # unique) at 256 bits usually decides
            Kt = _tighter_real_box(c1, c2, c3, K)
            if Kt is not None and (not_a_vertex(fps, Kt) or closer_witness((c1, c2, c3), fps, Kt)):
                continue
            cv = certify_at(K) if certify_at is not None and found is not None else None
            if cv is not None and cv.proven and cv.box is not None and _same_zero(c1, c2, c3, K, cv, retighten):
                found.append(cv)
                continue
            return False, (f"real solution ({float(K[0].mid()):.6g}, {float(K[1].mid()):.6g}) neither "
                           "matches a certified vertex nor is proved not to be a true vertex")
    unmatched = [k for k, cv in enumerate(certs) if cv.true_vertex and k not in matched]
    if unmatched:
        return False, f"{len(unmatched)} certified vertex(es) not among the solutions"
    return True, note + "; every real solution is a listed vertex or proved not a true vertex"


def _same_zero(c1, c2, c3, K, cv, retighten) -> bool:
    """Proof that the vertex of ``cv`` is the zero of the offset system in the real solution box
    K (which holds exactly one): its box inside K, or one Krawczyk box holding both
    (:func:`_same_by_krawczyk`), or a tighter box of the vertex (``retighten``) inside K.  The
    last serves far vertices: their 64-bit box is wider than K, and the offsets' interval Jacobian
    over a box holding both is too wide for Krawczyk; a vertex box inside K is one zero of the
    offset system in K, which holds exactly one."""
    if all(K[i].contains(cv.box[i]) for i in range(3)):
        return True
    if not all(balls_overlap(K[i], cv.box[i]) for i in range(3)):
        return False
    if _same_by_krawczyk(OffsetSystem((c1, c2, c3)), K, cv.box):
        return True
    B = retighten(cv) if retighten is not None else None
    return B is not None and all(K[i].contains(B[i]) for i in range(3))


def _tighter_real_box(c1, c2, c3, K):
    """A Krawczyk box at 256 bits of the real zero in K (K holds a unique zero), inside K, or None."""
    s = np.array([complex(float(K[i].mid())) for i in range(3)])
    kind, K2 = certify_solutions(c1, c2, c3, s[None, :], prec=256, iters=8, method="arb")[0]
    if kind != "real" or not all(K[i].contains(K2[i]) for i in range(3)):
        return None
    return K2


# --------------------------------------------------------------------------- exact completeness

def _interval_ball(lo: Fraction, hi: Fraction) -> arb:
    """A ball containing the rational interval [lo, hi] (union of the balls of its endpoints)."""
    a = arb(flint.fmpq(lo.numerator, lo.denominator))
    b = arb(flint.fmpq(hi.numerator, hi.denominator))
    return a.union(b)


def vertex_box_from_certificate(cert: dict):
    """(x, y, R) arb balls containing the proven vertex whose ``VoronoiVertex.info['certificate']``
    is ``cert`` (float mid/rad as written by runtime.certify.conflicts), widened for the float rounding of
    mid (≤ 2^-53 relative) and rad; None when the certificate has no box."""
    out = []
    for name in ("x", "y", "R"):
        b = cert.get(name)
        if not b:
            return None
        m, r = float(b["mid"]), float(b["rad"])
        if not (np.isfinite(m) and np.isfinite(r)):
            return None
        out.append(arb(m, r * (1 + 2.0 ** -40) + abs(m) * 2.0 ** -51 + 2.0 ** -1000))
    return tuple(out)


def completeness_exact(c1, c2, c3, boxes, vertex_boxes) -> tuple[bool, str]:
    """Completeness of a certified vertex list from the exact real solutions of the triple system.

    ``boxes``: msolve's isolating boxes ((x_lo, x_hi), (y_lo, y_hi), (R_lo, R_hi)) of *all* real
    solutions of the exact offset system (:mod:`runtime.solve.exact`); ``vertex_boxes``: (x, y, R)
    arb enclosures of the certified true vertices.  Argument: a true Voronoi vertex is a real
    solution of o1 = o2 = o3 = 0 (thesis §5.2–§5.3: √R is a critical distance to each conic), so it
    lies in exactly one box.  (i) Each certified vertex box must meet exactly one exact box -- that
    box's solution is the vertex -- and no two vertices the same box.  (ii) Every other box is
    proved not to hold a true vertex (R < 0, a real foot point strictly closer than √R, or no real
    foot point at distance √R, or a closer witness: :mod:`runtime.certify.not_a_vertex`).  Then the
    certified vertices are all the true vertices."""
    fps = [foot_polynomial(normalised_coefficients(c)) for c in (c1, c2, c3)]
    with working_prec(256):
        K = [tuple(_interval_ball(lo, hi) for lo, hi in b) for b in boxes]
        owner: dict[int, int] = {}
        for v, B in enumerate(vertex_boxes):
            if B is None:
                return False, f"certified vertex {v} has no enclosure to match with the exact solutions"
            hits = [k for k, Kk in enumerate(K) if all(Kk[i].overlaps(B[i]) for i in range(3))]
            if len(hits) != 1:
                return False, (f"vertex {v} meets {len(hits)} of the exact real solution boxes "
                               "(matching not proven)")
            if hits[0] in owner:
                return False, "two certified vertices match the same exact real solution"
            owner[hits[0]] = v
        rest = [k for k in range(len(K)) if k not in owner]
        for k in rest:
            if not not_a_vertex(fps, K[k]) and not closer_witness((c1, c2, c3), fps, K[k]):
                x, y = float(K[k][0].mid()), float(K[k][1].mid())
                return False, (f"exact real solution ({x:.6g}, {y:.6g}) neither matches a certified vertex "
                               "nor is proved not to be a true vertex")
    return True, (f"exact: {len(K)} real solutions of the exact offset system (msolve); {len(owner)} are the "
                  f"certified vertices, {len(rest)} proved not true vertices")
