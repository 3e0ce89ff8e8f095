"""Solutions the Krawczyk passes did not certify: the conjugate split, the lost-root search, a last
polished retry, and a diagnosis.

The numeric stage (thesis §5.5: eigenvectors of a Macaulay or toric null space, then Newton) may
list a point that is no simple zero of the offset system o1 = o2 = o3 = 0 -- one zero of a close
pair listed twice while its partner is missing, a conjugate pair near the real axis read as two real
points -- or a true zero too ill-conditioned for the first tests.  What is tried here on such
points:

* :func:`certify_split_pairs`: complex Newton from s_k + i·(s_k − s_j) towards a conjugate pair;
* :func:`replace_unproved`: each uncertified or overlapping solution is replaced by a zero found
  elsewhere (the conjugate of a kept non-real box, or Newton from starts around it);
* :func:`retry_or_diagnose`: Newton at 512 bits and Krawczyk at 512/1024 bits, else a numerical
  diagnosis (singular solution, point at infinity of the weighted chart, thesis §4.4).

*Soundness.*  Every box produced here is an ordinary Krawczyk box of
:func:`runtime.certify.solution_boxes.certify_solutions` (one simple zero, K(X) ⊂ int X), and the
caller proves again that all N boxes are pairwise disjoint before counting.  The constants below
(numbers of starts, distances, step multiples, the random seed of the directions) were chosen from
the measured cases their comments name; they decide only *where* Newton starts and so *whether* the
list is completed, never whether a returned box holds a zero: a wrong constant can cost time or a
proof, not a verdict's truth.
"""
from __future__ import annotations

import numpy as np
from flint import acb, acb_mat, arb

from .foot import working_prec
from .offset_system import OffsetSystem, krawczyk_complex, newton_track
from .offset_batch import nearly_real
from .solution_boxes import box_kind, boxes_disjoint, certify_solutions, conjugate_box

__all__ = ["certify_split_pairs", "moved_solutions", "replace_unproved", "retry_or_diagnose", "MAX_LOST"]


#: at most this many solutions with overlapping enclosures are replaced by a search around them
MAX_LOST = 4
#: Newton starts tried around each of them, at the distances _LOST_RADII in turn (relative to the
#: point's size; rule: the decades 10^-5 … 10^-1 -- the roots of a cluster were measured 7e-5 to
#: 2e-3 apart, a lost real root 6e-4 away)
_LOST_STARTS = 30
_LOST_RADII = (1e-5, 1e-4, 1e-3, 1e-2, 1e-1)
#: seed of the random start directions (any seed is sound; a fixed one makes runs repeatable)
_DIRECTIONS_SEED = 17
#: imaginary offsets of the complex starts around a real point that is no solution (relative to
#: its size; rule: the decades 10^-6 … 10^-3 -- measured: a conjugate pair 1e-5 · i off the real
#: axis found from 1e-6 to 1e-3)
_NEAR_REAL_RADII = (1e-6, 1e-5, 1e-4, 1e-3)
#: multiples t of the imaginary part w of a point m + i·w tried as real starts m ± t·w (rule: the
#: half-decades 1, 3, 10, … 1000 -- measured: the lost real root at m + 206·w, its partner at m − 0.1·w)
_PAIR_STEPS = (1.0, 3.0, 10.0, 30.0, 100.0, 300.0, 1000.0)
#: multiples t of s − c tried as starts c + t·(s − c) for a solution listed at s and certified at c
#: (measured: the missing zero of a close pair at t ≈ −0.6)
_MOVED_STEPS = (-0.5, -1.0, -2.0, 2.0, 3.0)
#: at most this many such solutions give starts (each costs len(_MOVED_STEPS) Newton runs per lost root)
_MAX_MOVED = 6
#: relative distance of s_k's nearest neighbour below which a real s_k is tried as half of a split
#: conjugate pair (measured: the two real points 1e-3 apart)
_SPLIT_PAIR_DISTANCE = 1e-3
#: precisions (bits) of the polished retry
_RETRY_PRECS = (512, 1024)


def certify_split_pairs(c1, c2, c3, S, failed, boxes) -> None:
    """A complex-conjugate pair closer to the real axis than the numeric stage can tell comes out
    as two nearby real points (measured: (−12.896, 15.2794, 289.83) twice, 1e-3 apart, Jacobian
    condition 1e10, where msolve finds no real solution).  Real Newton cannot reach either zero and
    stays on the real axis; complex Newton from s_k + i·(s_k − s_j), s_j the nearest other
    solution, goes to the zero on that side.  Each success is an ordinary Krawczyk box (the proof
    of :func:`certify_solutions`); distinctness is proved afterwards with all the others."""
    scale = np.maximum(1.0, np.abs(S).max(axis=1))
    for k in failed:
        if np.any(S[k].imag != 0):
            continue
        d = np.abs(S - S[k]).max(axis=1) / np.maximum(scale, scale[k])
        d[k] = np.inf
        j = int(np.argmin(d))
        if not d[j] < _SPLIT_PAIR_DISTANCE:
            continue
        start = S[k] + 1j * (S[k] - S[j]).real
        kind, K = certify_solutions(c1, c2, c3, start[None, :], prec=128, iters=12, method="arb")[0]
        if kind == "nonreal":
            boxes[k] = (kind, K)


def moved_solutions(S, boxes, first_failed) -> list[tuple[np.ndarray, np.ndarray]]:
    """(s_k, c_k) for the solutions the first Krawczyk pass failed on and a later test certified:
    s_k as listed, c_k the centre of its box (numerical; only starts of a search are made from it),
    at most :data:`_MAX_MOVED` of them, those that moved farthest relative to their size first."""
    out = []
    for k in first_failed:
        kind, K = boxes[k]
        if kind is not None:
            c = np.array([complex(t.mid()) for t in K])
            out.append((float(np.max(np.abs(S[k] - c) / np.maximum(1.0, np.abs(c)))), S[k], c))
    out.sort(key=lambda t: -t[0])
    return [(s, c) for _, s, c in out[:_MAX_MOVED]]


def replace_unproved(c1, c2, c3, S, boxes, moved=()) -> int:
    """Solutions without a Krawczyk box, or whose enclosures overlap another's when no chart
    separates them: typically one root reached twice by the numeric stage while a nearby root of
    the same cluster was missed (small sites far apart: 8 real roots within 2e-3 of each other,
    eigenvectors mixed at 3e-3), or a real point where real Newton stalled between the members of a
    conjugate pair 1e-5 off the real axis (three hyperbolas 10× apart: one of the pair listed
    twice, the other missing, msolve 56 real solutions where the list had 57).

    Every uncertified solution and one member of each overlapping pair are dropped.  A dropped one
    is first replaced by the conjugate of a found or kept non-real box that meets no kept box (the
    offsets have real coefficients: that box holds the conjugate zero, which the list lacks).
    Otherwise Newton at 128 bits runs from starts around it: for a real point m, first the
    complex points m + i·r·v (random real v, r = 1e-6 … 1e-3 of its size: a near-real conjugate
    pair); for a point m + i·w seen as non-real, the real points m ± t·w,
    t = 1 … 1000 (a spurious conjugate pair near the real axis points along the segment between
    two real roots; measured: the lost real root at m + 206·w, msolve 60 real solutions where the
    numeric stage had 58); then random real and complex directions at distances 1e-5 … 1e-1 of its
    size.  Before all these, the points c + t·(s − c) (:data:`_MOVED_STEPS`) on the line of each
    solution ``moved`` (listed at s, certified only by a later test at c): a point listed near the
    two zeros of a close pair is uncertified at first (its error lies along the Jacobian's
    near-null direction, the direction of the pair) and converges to one of them, while the
    eigenvectors gave the other's place to a duplicate elsewhere (measured: three hyperbolas 100×
    apart, a real pair 3e-6 of its size apart, the listed point 5e-6 from the zero it converged to,
    a duplicate 2e3 away).  The first certified box disjoint from all kept boxes replaces it.

    Returns the number replaced if all were, else 0 (``boxes`` may then be partly updated; the
    caller gives up).  Nothing here is assumed: every box is an ordinary Krawczyk box, and the
    disjointness of all N boxes is checked again at the end."""
    drop, kept = _dropped_and_kept(S, boxes)
    if drop is None:
        return 0
    free = _free_conjugates(boxes, kept)
    scale = np.maximum(1.0, np.abs(S).max(axis=1))
    rng = np.random.default_rng(_DIRECTIONS_SEED)
    for k in drop:
        f = next((f for f in free if boxes_disjoint([boxes[j][1] for j in kept] + [f[1]])), None)
        if f is not None:
            boxes[k] = f
            kept.append(k)
            free.remove(f)
            continue
        for start in _search_starts(S[k], scale[k], moved, rng):
            kind, K = certify_solutions(c1, c2, c3, np.asarray(start, dtype=complex)[None, :], prec=128, iters=20,
                                        method="arb")[0]
            if kind is None:
                continue
            if boxes_disjoint([boxes[j][1] for j in kept] + [K]):
                boxes[k] = (kind, K)
                kept.append(k)
                if kind == "nonreal":
                    free.append(conjugate_box(boxes[k]))
                break
        else:
            return 0
    return len(drop) if boxes_disjoint([K for _, K in boxes]) else 0


def _dropped_and_kept(S, boxes):
    """(drop, kept): the solutions without a box, plus the second of each overlapping pair of boxes,
    and the others, whose boxes must be pairwise disjoint; (None, None) when there is nothing to
    drop, more than :data:`MAX_LOST`, or the kept boxes still overlap."""
    drop = [k for k, (kind, _) in enumerate(boxes) if kind is None]
    proved = [k for k in range(len(S)) if k not in drop]
    overlaps: list = []
    boxes_disjoint([boxes[k][1] for k in proved], overlaps)
    for a, b in overlaps:
        if proved[a] not in drop and proved[b] not in drop:
            drop.append(proved[b])
    if not drop or len(drop) > MAX_LOST:
        return None, None
    kept = [k for k in range(len(S)) if k not in drop]
    if not boxes_disjoint([boxes[k][1] for k in kept]):
        return None, None
    return drop, kept


def _free_conjugates(boxes, kept):
    """Conjugates of the kept non-real boxes that meet no kept box: each holds a unique simple zero
    (real coefficients), disjoint from the kept zeros, so a zero the list lacks."""
    conj = [conjugate_box(boxes[j]) for j in kept if boxes[j][0] == "nonreal"]
    pairs: list = []
    boxes_disjoint([boxes[j][1] for j in kept] + [K for _, K in conj], pairs)
    met = {max(a, b) for a, b in pairs if min(a, b) < len(kept) <= max(a, b)}
    return [conj[i - len(kept)] for i in range(len(kept), len(kept) + len(conj)) if i not in met]


def _search_starts(s, size, moved, rng):
    """Newton starts around a dropped solution s (size max(1, max|s|)), in the order of
    :func:`replace_unproved`: the lines of the ``moved`` solutions, then m ± t·w for a point
    m + i·w seen as non-real (a near-double real pair) or m + i·r·v for a real one (a near-real
    conjugate pair), then random real and complex directions at the distances :data:`_LOST_RADII`."""
    m, w = s.real, s.imag
    starts = [c + t * (p - c) for p, c in moved for t in _MOVED_STEPS]
    starts += [m + sg * t * w for t in _PAIR_STEPS for sg in (1.0, -1.0)] if np.any(w != 0) else \
        [m + 1j * r * size * rng.standard_normal(3) for r in _NEAR_REAL_RADII for _ in range(2)]
    for attempt in range(_LOST_STARTS):
        direction = rng.standard_normal(3) + (1j * rng.standard_normal(3) if attempt % 2 else 0.0)
        direction = direction / np.abs(direction).max()
        radius = _LOST_RADII[attempt % len(_LOST_RADII)]
        starts.append(s + radius * size * direction)
    return starts


def retry_or_diagnose(c1, c2, c3, s):
    """Last attempt on a solution the 64/128/256-bit tests did not certify, else a diagnosis.

    Newton is run at 512 bits from ``s``.  If it converges (quadratically, to a point within
    10^-6 relative of ``s``), the polished centre is tested by the complex Krawczyk test at 512 and
    1024 bits -- the same proof as :func:`certify_solutions`, only with a better midpoint: returns
    (box, "").  Otherwise returns (None, text), text naming the reason.  *Not a proof*: the
    diagnosis is numerical.  If Newton does not converge and ``s`` is large, Newton is also run in
    the weighted chart at infinity, x = 1/w, y = v/w, R = q/w² (or x ↔ y), with the offsets
    multiplied by w^{deg_w} (weights 1, 1, 2, thesis §4.4); convergence to w → 0 says that ``s``
    approximates a point at infinity of the offset system -- for a parabola, its offset surface has
    one in the direction normal to the axis -- and not a finite solution; then the solution list
    contains fewer than the generic number of finite solutions and completeness by simple-root
    counting does not apply (either the configuration is non-generic, or a far finite solution
    was missed by the numeric stage: the two cannot be told apart here)."""
    sys = OffsetSystem((c1, c2, c3))
    s = np.asarray(s, dtype=complex)
    scale = max(1.0, float(np.max(np.abs(s))))
    real = bool(nearly_real(s[None, :])[0])
    with working_prec(_RETRY_PRECS[0]):
        m0 = [acb(float(t.real), 0.0 if real else float(t.imag)) for t in s]
        cond = _cond(sys, m0)
        m, conv = newton_track(sys, m0, real, iters=30)
        moved = max(abs(complex(m[i].mid()) - s[i]) for i in range(3)) / scale if conv else np.inf
    if conv and moved < 1e-6:
        for prec in _RETRY_PRECS:
            with working_prec(prec):
                mp = [acb(t) for t in m]
                mp, _ = newton_track(sys, mp, real, iters=3)
                res = krawczyk_complex(sys, mp, symmetric=real)
                if res is None:
                    continue
                kind, K = box_kind(res[0], real)
                if kind is not None:
                    return (kind, K), ""
        return None, (f"(x, y, R) ≈ ({_fmt(s[0])}, {_fmt(s[1])}, {_fmt(s[2])}), Jacobian condition ≈ "
                      f"{cond:.1e}; Newton converges (512 bits) but Krawczyk fails up to "
                      f"{_RETRY_PRECS[-1]} bits: a numerically multiple (singular) solution, for which "
                      "completeness by simple-root counting does not apply")
    text = (f"(x, y, R) ≈ ({_fmt(s[0])}, {_fmt(s[1])}, {_fmt(s[2])}), Jacobian condition ≈ {cond:.1e}; "
            "Newton from it (512 bits) does not converge to it")
    if conv and np.isfinite(moved):
        text += " (it converges to a point at relative distance %.1e)" % moved
    if scale > 1e3:
        at_inf = _newton_at_infinity(sys, s)
        if at_inf is not None:
            ratio_name, ratio, w0, w1 = at_inf
            text += (f"; in the weighted chart at infinity Newton converges linearly to 1/{ratio_name[-1]} = 0 "
                     f"(|w|: {w0:.1e} → {w1:.1e}), direction {ratio_name} ≈ {ratio:.6g}: numerically a "
                     "singular point at infinity, not a finite solution, so fewer than the generic number "
                     "of finite solutions are listed and completeness by simple-root counting does not "
                     "apply (non-generic input, or a far finite solution missed by the numeric stage)")
    return None, text


def _fmt(z: complex) -> str:
    return f"{z.real:.6g}" if abs(z.imag) <= 1e-12 * max(1.0, abs(z)) else f"{z.real:.6g}{z.imag:+.3g}i"


def _cond(sys, m) -> float:
    _, J = sys.eval(m)
    A = np.array([[complex(J[i][j].mid()) for j in range(3)] for i in range(3)])
    with np.errstate(all="ignore"):
        c = float(np.linalg.cond(A))
    return c if np.isfinite(c) else float("inf")


def _newton_at_infinity(sys, s, iters: int = 60, prec: int = 256):
    """Newton in the weighted chart at infinity (see :func:`retry_or_diagnose`); returns
    (name, ratio, |w| start, |w| end) if |w| decreases by ≥ 10^6, else None.  Numerical only."""
    big = 0 if abs(s[0]) >= abs(s[1]) else 1
    with working_prec(prec):
        polys = []
        for T in sys.fmpq_terms:
            D = max(i + j + 2 * k for i, j, k, _ in T)
            polys.append([(D - i - j - 2 * k, (j if big == 0 else i), k, arb(c)) for i, j, k, c in T])
        w = acb(complex(1 / s[big]))
        v = acb(complex(s[1 - big] / s[big]))
        q = acb(complex(s[2] / s[big] ** 2))
        z = [w, v, q]
        w0 = abs(complex(s[big])) ** -1
        try:
            for _ in range(iters):
                F, J = [], []
                for P in polys:
                    f, g0, g1, g2 = acb(0), acb(0), acb(0), acb(0)
                    for a, b, c, co in P:
                        f += co * z[0] ** a * z[1] ** b * z[2] ** c
                        if a:
                            g0 += co * a * z[0] ** (a - 1) * z[1] ** b * z[2] ** c
                        if b:
                            g1 += co * b * z[0] ** a * z[1] ** (b - 1) * z[2] ** c
                        if c:
                            g2 += co * c * z[0] ** a * z[1] ** b * z[2] ** (c - 1)
                    F.append(f)
                    J.append([g0, g1, g2])
                st = acb_mat(J).mid().solve(acb_mat([[f.mid()] for f in F]))
                z = [(z[i] - st[i, 0]).mid() for i in range(3)]
        except ZeroDivisionError:
            pass
        w1 = abs(complex(z[0].mid()))
        ratio = complex(z[1].mid())
    if not (np.isfinite(w1) and w1 < 1e-6 * w0):
        return None
    name = "y/x" if big == 0 else "x/y"
    return name, (ratio.real if abs(ratio.imag) < 1e-9 else ratio), w0, w1
