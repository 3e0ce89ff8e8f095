"""Krawczyk boxes of the listed solutions of the offset system, and their disjointness.

Steps 1–3 of the completeness proof of :mod:`runtime.certify.complete` (thesis §5.3–§5.5):

1. every listed solution s_k of o1 = o2 = o3 = 0 is enclosed in a box X_k by a Krawczyk test
   (Krawczyk 1969; interval Newton, Moore/Neumaier): with Y ≈ J(m)⁻¹,

       K(X) = m − Y·F(m) + (I − Y·J(X))(X − m) ⊂ int X                                  (K)

   proves one zero in X, the only one, simple.  First the batched float test of
   :mod:`runtime.certify.offset_batch`, then ball arithmetic (:func:`runtime.certify.offset_system.krawczyk_complex`,
   via :func:`runtime.certify.interval_newton.krawczyk_inflation`) for what it left.  Of a numerically
   conjugate pair only one is tested: the offsets have real coefficients, so the conjugate of a
   box with a unique simple zero is a box with a unique simple zero, the conjugate one
   (:func:`conjugate_box`);
2. the boxes are pairwise disjoint (:func:`boxesboxes_disjoint`), so the zeros are distinct;
3. a point tested as real is tested on a conjugation-symmetric box, whose unique zero is then real;
   a complex box is kept only if some coordinate excludes the real axis (proved non-real).

All tests run on the offsets composed with the exact similarity to the scene frame (dyadic centre,
power-of-two scale, :func:`runtime.certify.offset_system.scene_frame`); the frame boxes are mapped
back to (x, y, R) in ball arithmetic (:func:`_from_frame`).  Newton steps and the choice of tests
(real or complex, precision, number of steps) only pick midpoints: a box is returned only when (K)
holds for it.
"""
from __future__ import annotations

from fractions import Fraction

import flint
import numpy as np
from flint import acb, arb

from .foot import working_prec
from .offset_batch import certify_batch, nearly_real
from .offset_system import OffsetSystem, framed_offset_system, krawczyk_complex, newton_track, scene_frame

__all__ = ["certify_solutions", "conjugate_box", "box_kind", "boxes_disjoint", "boxes_disjoint_all_pairs",
           "balls_overlap"]


def _scene_frame_or_none(c1, c2, c3):
    """The exact scene frame of :func:`certify_solutions` (None: world coordinates)."""
    try:
        frame = tuple(Fraction(t) for t in scene_frame((c1, c2, c3)))
    except ValueError:
        return None
    return None if frame == (0, 0, 1) else frame


def _to_frame(S, frame):
    """Float images (u, v, S) of world points (x, y, R) (midpoints only, not part of any proof)."""
    px, py, s = (float(t) for t in frame)
    return (S - np.array([px, py, 0.0])) / np.array([s, s, s * s])


def _from_frame(box, frame):
    """World enclosure of a frame box: x = px + s·u, y = py + s·v, R = s²·S in ball arithmetic
    (the affine bijection maps the unique zero in the box to the unique zero in the image; real
    coefficients keep a real zero real)."""
    kind, K = box
    if kind is None:
        return box
    px, py, s = (arb(flint.fmpq(t.numerator, t.denominator)) for t in frame)
    conv = (lambda t: t) if kind == "real" else acb
    return kind, [conv(px) + conv(s) * K[0], conv(py) + conv(s) * K[1], conv(s * s) * K[2]]


def certify_solutions(c1, c2, c3, solutions, *, prec: int = 64, iters: int = 4, method: str = "auto",
                      frame="scene"):
    """Krawczyk boxes for every solution: list of (kind, K) with kind 'real' | 'nonreal' | None.

    ``method``: ``"arb"`` -- complex-ball (acb) Krawczyk per solution at ``prec`` bits;
    ``"fast"`` -- the batched rigorous floating-point Krawczyk test (:func:`certify_batch`) only;
    ``"auto"`` (default) -- the fast test, then the arb path (at ≥ 128 bits: what binary64 could not
    certify rarely succeeds at 64 bits) for the solutions it did not certify.

    ``frame``: the tests run on the offset system in the exact scene coordinates (u, v, S) of
    :func:`runtime.certify.offset_system.scene_frame` (x = px + s·u, y = py + s·v, R = s²·S, dyadic px, py,
    power-of-two s; ``"scene"``, default), or in world coordinates (None), or in a given exact
    (px, py, s).  A spread-out scene has world coordinates ~10²–10³ and R ~10⁴–10⁶: the float test
    then fails on cancellation in the degree-8 offsets; in scene coordinates it is the compact case.
    The boxes returned are world boxes (:func:`_from_frame`)."""
    if method not in ("auto", "fast", "arb"):
        raise ValueError(f"method must be 'auto', 'fast' or 'arb', got {method!r}")
    S = np.asarray(solutions, dtype=complex).reshape(-1, 3)
    if isinstance(frame, str):
        if frame != "scene":
            raise ValueError(f"frame must be 'scene', None or (px, py, s), got {frame!r}")
        frame = _scene_frame_or_none(c1, c2, c3)
    if frame is not None:
        frame = tuple(Fraction(t) for t in frame)
        if frame == (0, 0, 1):
            frame = None
    Sf = _to_frame(S, frame) if frame is not None else S
    rep, mate = _conjugate_pairs(Sf)
    out = _certify_framed(c1, c2, c3, Sf[rep], prec, iters, method, frame)
    if frame is not None:
        out = [_from_frame(b, frame) for b in out]
    boxes = [None] * len(S)
    for k, b in zip(rep, out):
        boxes[k] = b
    for j, k in mate.items():
        boxes[j] = conjugate_box(boxes[k])
    return boxes


def _conjugate_pairs(S):
    """(rep, mate): indices of the solutions to certify, and {j: k} for non-real solutions S_j
    that are numerically the conjugate of a certified S_k.  The offsets have real coefficients,
    so the conjugate of a Krawczyk box of S_k is a box with a unique, simple zero -- the
    conjugate zero -- and S_j needs no test of its own (:func:`conjugate_box`).  The pairing is
    only a choice of work: whatever it pairs, every box returned still holds a unique zero, and
    distinctness is proved afterwards on all boxes (:func:`boxes_disjoint`)."""
    n = len(S)
    if n < 2:
        return np.arange(n), {}
    nonreal = np.nonzero(~nearly_real(S))[0]
    if len(nonreal) < 2:
        return np.arange(n), {}
    P = S[nonreal]
    scale = np.maximum(1.0, np.abs(P).max(axis=1))
    # nearest conjugate by the first coordinate, mutual, then checked on all three (to 1e-6 of the
    # size: a tolerance of the numeric stage's accuracy; any pairing is sound, see above)
    D = np.abs(P[:, None, 0] - np.conj(P[None, :, 0]))
    np.fill_diagonal(D, np.inf)
    near = np.argmin(D, axis=1)
    a = np.arange(len(P))
    pair = ((a < near) & (near[near] == a)
            & (np.abs(P - np.conj(P[near])).max(axis=1) < 1e-6 * np.maximum(scale, scale[near])))
    mate = {int(nonreal[b]): int(nonreal[a]) for a, b in zip(a[pair], near[pair])}
    keep = np.ones(n, dtype=bool)
    keep[list(mate)] = False
    return np.nonzero(keep)[0].astype(np.int64), mate


def conjugate_box(box):
    """The conjugate of a non-real Krawczyk box (kind 'nonreal', acb enclosures); (None, None) for
    anything else (that solution is then tested on its own by the callers' retries)."""
    kind, K = box
    if kind != "nonreal":
        return None, None
    return "nonreal", [k.conjugate() for k in K]


def _certify_framed(c1, c2, c3, S, prec, iters, method, frame):
    """Boxes of the points S (frame coordinates): the float batch first (``method`` 'auto' or
    'fast'), then the ball test (:func:`_ball_box`) at ≥ 128 bits for what it left."""
    if method != "arb":
        out = certify_batch(c1, c2, c3, S, frame)
        failed = [k for k, (kind, _) in enumerate(out) if kind is None]
        if method == "fast" or not failed:
            return out
        again = _certify_framed(c1, c2, c3, S[failed], max(prec, 128), iters, "arb", frame)
        for k, b in zip(failed, again):
            out[k] = b
        return out
    sys = framed_offset_system((c1, c2, c3), frame) if frame is not None else OffsetSystem((c1, c2, c3))
    with working_prec(prec):
        return [_ball_box(sys, s, iters) for s in S]


def _ball_box(sys, s, iters):
    """(kind, K) of the ball Krawczyk test (K) at the working precision around Newton's polish of
    s (:func:`runtime.certify.offset_system.newton_track`, midpoints only), (None, None) if it fails.
    A point tested as real (:func:`runtime.certify.offset_batch.nearly_real`) is projected to the
    real axis and tested on a conjugation-symmetric box."""
    real = bool(nearly_real(s[None, :])[0])
    m = [acb(float(t.real), 0.0 if real else float(t.imag)) for t in s]
    m, _ = newton_track(sys, m, real, iters)
    res = krawczyk_complex(sys, m, symmetric=real)
    if res is None and real and np.any(s.imag != 0):
        # a conjugate pair closer to the real axis than 10⁻⁶ of its size (a near-double
        # real root split into the complex plane): real Newton cannot reach either zero,
        # complex Newton from the unprojected point does
        real = False
        m, _ = newton_track(sys, [acb(complex(t)) for t in s], False, max(iters, 8))
        res = krawczyk_complex(sys, m, symmetric=False)
    if res is None:
        return None, None
    return box_kind(res[0], real)


def box_kind(K, real: bool):
    """Step 3, reality of the unique zero in a Krawczyk box K: ('real', real parts of K) when K was
    tested as conjugation-symmetric (the offsets have real coefficients, so the conjugate of the
    zero is a zero in K, hence the zero itself); ('nonreal', K) when some coordinate of K excludes
    the real axis; else (None, K): reality undecided, not certified."""
    if real:
        return "real", [k.real for k in K]
    if any(not k.imag.contains(0) for k in K):
        return "nonreal", K
    return None, K


def boxes_disjoint(Ks, pairs: list | None = None) -> bool:
    """Step 2: are the boxes pairwise disjoint?  Two boxes X_a, X_b are disjoint when some
    coordinate's balls are, X_a,i ∩ X_b,i = ∅; then their unique zeros differ.  With a list
    ``pairs``, every overlapping pair (a, b) is appended to it instead of stopping at the first.
    A float prefilter finds the candidate pairs: with c, ρ the float midpoint and radius of a real
    or imaginary part, its interval is [c − w, c + w], w = ρ + (|c| + ρ)·2^-45 + 2^-1000 ≥ the
    true half-width plus the conversion roundings, so a pair whose float intervals miss each other
    in some coordinate is disjoint; only the others are decided by ball arithmetic
    (:func:`balls_overlap`), and the answer is that of the all-pairs test."""
    n = len(Ks)
    if n < 2:
        return True
    lo = np.empty((n, 6))
    hi = np.empty((n, 6))
    mid_list, rad_list = [], []
    for K in Ks:
        for i in range(3):
            z = K[i]
            if isinstance(z, arb):
                mid_list.append(float(z.mid()))
            else:
                if not isinstance(z, acb):
                    z = acb(z)
                # the midpoint (both parts in one conversion) and a radius bounding both parts'
                # radii (acb.rad() ≥ hypot of the two; an arb's own radius for a real ball)
                mid_list.append(complex(z.mid()))
            rad_list.append(float(z.rad()))
    mids = np.array(mid_list, dtype=complex).reshape(n, 3)
    rads = np.array(rad_list, dtype=float).reshape(n, 3)
    # float() rounds to nearest: widen by 2^-45·(|c| + rr) (≫ the few roundings) + tiny
    for part, c in enumerate((mids.real, mids.imag)):
        w = rads + (np.abs(c) + rads) * 2.0 ** -45 + 2.0 ** -1000
        lo[:, part::2], hi[:, part::2] = c - w, c + w
    if not (np.isfinite(lo).all() and np.isfinite(hi).all()):
        return boxes_disjoint_all_pairs(Ks)
    block = 256
    for a0 in range(0, n, block):
        a1 = min(n, a0 + block)
        meet = np.ones((a1 - a0, n), dtype=bool)
        for c in range(6):      # coordinate by coordinate (measured 10x faster than .all(axis=2))
            meet &= lo[a0:a1, None, c] <= hi[None, :, c]
            meet &= lo[None, :, c] <= hi[a0:a1, None, c]
        for a, b in zip(*np.nonzero(meet)):
            a = int(a) + a0
            if b > a and all(balls_overlap(Ks[a][i], Ks[b][i]) for i in range(3)):
                if pairs is None:
                    return False
                pairs.append((a, int(b)))
    return not pairs


def boxes_disjoint_all_pairs(Ks) -> bool:
    n = len(Ks)
    for a in range(n):
        for b in range(a + 1, n):
            if all(balls_overlap(Ks[a][i], Ks[b][i]) for i in range(3)):
                return False
    return True


def balls_overlap(p, q) -> bool:
    pa = p if isinstance(p, acb) else acb(p)
    qa = q if isinstance(q, acb) else acb(q)
    return pa.overlaps(qa)
