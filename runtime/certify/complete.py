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
   conjugate one, also simple (:func:`_conjugate_pairs`; step 2 covers any mispairing);
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
   critical point only).

If any step fails, ``complete`` is False and the note says which.

(Longer than 400 lines: the counting proof, its batched float fast path and the exact-route proof
share the enclosure and disjointness helpers; one idea, completeness of a vertex list.)
"""
from __future__ import annotations

import math
from fractions import Fraction
from functools import lru_cache

import flint
import numpy as np
from flint import acb, acb_mat, arb

from .foot import FootFailure, foot_polynomial, normalised_coefficients, real_feet_ball, working_prec
from .dimension import zero_dimensional
from .root_bound import count_bound
from .offset_system import (OffsetSystem, exact_offset_terms, framed_offset_system,  # noqa: F401 (re-exported)
                            inside_disc, krawczyk_complex, newton_track, scene_frame)
from .interval_newton import (UNDERFLOW, UNIT_ROUNDOFF, abs_upper, float_contraction_bound, float_inverse,
                              float_krawczyk_test, float_residual_bound, gamma, krawczyk_image, round_up)

__all__ = ["clear_certification_caches", "certify_completeness", "completeness_with_vertices", "completeness_exact",
           "OffsetSystem", "certify_solutions", "exact_offset_terms"]


# --------------------------------------------------------------------------- fast batched path
#
# Rigorous floating-point Krawczyk test for all N solutions at once (numpy, IEEE binary64,
# round-to-nearest, no directed rounding).  Proof argument (see also the report / tests):
#
# *Disc arithmetic.*  A "disc" is a pair (c, ρ) of a float midpoint c (complex128) and a float
#  radius ρ ≥ 0 standing for {z : |z − c| ≤ ρ}.  With u = 2^-53, every complex float product
#  satisfies fl(ab) = ab(1 + δ) + η, |δ| ≤ √2·γ₂ < 3u (no FMA) or √5·u (FMA), |η| ≤ 2^-1072
#  (underflow); so ε_c := 4u and η_c := 2^-1000 are safe.  Hence for a ∈ (â, ρa), b ∈ (b̂, ρb):
#       |ab − fl(âb̂)| ≤ |â|ρb + ρa|b̂| + ρaρb + ε_c|â||b̂| + η_c.
#  Radii are computed in round-to-nearest and then passed through round_up(t) = fl(t·(1+2^-40))
#  + 2^-1000, which dominates the (≤ 16 relative roundings of size u, and underflow) lost while computing t
#  from non-negative terms.  |z| is bounded above by abs_upper(z) = fl(fl(|Re z|+|Im z|)·(1+2^-50)).
#  Overflow produces inf/nan, which makes every test below False (fallback to arb).
# *Polynomials.*  p = Σ_t c_t x^{α_t} with exact rational c_t; c̃_t = float(c_t) (correctly
#  rounded) and the exact |c_t − c̃_t| rounded up is its radius.  Monomials are disc products of
#  disc powers.  The sum Σ c̃_t M̂_t is a real dot product (Re, Im separately) whose error, for any
#  summation order / FMA use, is ≤ γ_T Σ|c̃_t||Re M̂_t| (same for Im), so ≤ √2·γ_T Σ|c̃_t||M̂_t|.
# *Krawczyk in norm form* (polydisc X = {|x_i − m_i| ≤ r_i}, Y any float matrix): the test
#  b + Δ r < r with b ≥ |Y F(m)| and Δ ≥ |I − Y M| for every M in the disc enclosures of the
#  Jacobian over X is :func:`runtime.certify.interval_newton.float_krawczyk_test`, with its proof
#  (one zero, simple, the only one in X, within b + Δ r of m; real if m is real, as X is then
#  conjugation-symmetric and F has real coefficients) and the bounds b, Δ computed there.

_EPS_C = 4 * UNIT_ROUNDOFF


def _dmul(am, ar, bm, br):
    """Disc product (midpoint, radius) of discs (am, ar) and (bm, br); arrays broadcast."""
    cm = am * bm
    aa, ab = abs_upper(am), abs_upper(bm)
    return cm, round_up(aa * br + ar * ab + ar * br + _EPS_C * aa * ab + UNDERFLOW)


class _FastSystem:
    """Monomial structure of (o_i, ∂o_i/∂x_j) as float matrices with rigorous conversion radii."""

    def __init__(self, sys: "OffsetSystem"):
        # 12 polynomials: o_1..o_3, then ∂o_i/∂(x, y, R) (column 3 + 3i + j).  The coefficients c
        # of o_i are exact rationals: the ball arb(c) at 53 bits has a midpoint c̃ of 53 bits (a
        # double, exactly, in the normal range checked below) and a rigorous radius ≥ |c − c̃|
        # (rounded up by _up).  A derivative coefficient e·c (e ≥ 1 an exponent) is stored as
        # fl(e·c̃), with radius round_up(e·|c − c̃| + u·|fl(e·c̃)|·(1 + 2^-50)) ≥ |e·c − fl(e·c̃)| (one
        # rounding of the product, |e·c̃| ≤ |fl(e·c̃)|/(1 − u); _up covers the roundings of the bound).
        isfinite = math.isfinite
        exps, cols, vals, rads = [], [], [], []
        base = []
        for q, T in enumerate(sys.fmpq_terms):
            ex = np.array([(i, j, k) for i, j, k, _ in T], dtype=np.int64).reshape(-1, 3)
            fs, errs = [], []
            with working_prec(53):
                for *_, v in T:
                    b = arb(v)
                    f = float(b.mid())
                    if not isfinite(f) or (abs(f) < 2.0 ** -1000 and v != 0):
                        raise OverflowError("coefficient out of float range")
                    fs.append(f)
                    errs.append(float(b.rad()))
            f, err = np.array(fs, dtype=float), np.array(errs, dtype=float)
            if len(np.unique(_monomial_keys(ex))) != len(ex):
                raise ValueError("repeated monomial in an offset")      # callers fall back to arb
            base.append((ex, f, err))
            exps.append(ex)
            cols.append(np.full(len(ex), q))
            vals.append(f)
            # the radius of an arb is a 30-bit upper bound, exact as a double; _up adds margin
            rads.append(round_up(err))
        for q, (ex, f, err) in enumerate(base):
            for var in range(3):
                m = ex[:, var] > 0
                e = ex[m, var].astype(float)
                exd = ex[m].copy()
                exd[:, var] -= 1
                fd = f[m] * e
                if not np.isfinite(fd).all():
                    raise OverflowError("coefficient out of float range")
                exps.append(exd)
                cols.append(np.full(len(exd), 3 + 3 * q + var))
                vals.append(fd)
                rads.append(round_up(e * err[m] + UNIT_ROUNDOFF * (1 + 2.0 ** -50) * np.abs(fd)))
        allex = np.concatenate(exps) if exps else np.zeros((0, 3), dtype=np.int64)
        keys, inv = np.unique(_monomial_keys(allex), return_inverse=True)
        monos = _monomials_from_keys(keys)       # sorted lexicographically, like sorted tuples
        self.exps = monos.reshape(-1, 3)
        self.deg = int(self.exps.max()) if len(monos) else 0
        rows, cols = inv.ravel(), np.concatenate(cols) if cols else np.zeros(0, dtype=np.int64)
        C = np.zeros((len(monos), 12))
        R = np.zeros((len(monos), 12))
        C[rows, cols] = np.concatenate(vals) if vals else 0.0
        R[rows, cols] = np.concatenate(rads) if rads else 0.0
        self.C, self.R, self.absC = C, R, np.abs(C)
        self.gT = gamma(len(monos) + 2)

    def eval(self, mid, rad):
        """Discs of the 12 polynomials at the polydiscs (mid[n], rad[n]) (shape N×3): (N×12, N×12)."""
        N = mid.shape[0]
        D = self.deg
        pm = np.empty((D + 1, N, 3), dtype=complex)
        pr = np.empty((D + 1, N, 3))
        pm[0], pr[0] = 1.0, 0.0
        for p in range(1, D + 1):
            pm[p], pr[p] = _dmul(pm[p - 1], pr[p - 1], mid, rad)
        E = self.exps
        am, ar = pm[E[:, 0], :, 0].T, pr[E[:, 0], :, 0].T          # N × T
        am, ar = _dmul(am, ar, pm[E[:, 1], :, 1].T, pr[E[:, 1], :, 1].T)
        am, ar = _dmul(am, ar, pm[E[:, 2], :, 2].T, pr[E[:, 2], :, 2].T)
        vm = am.real @ self.C + 1j * (am.imag @ self.C)
        aa = abs_upper(am)
        # the three float dot products of non-negative numbers may round down by ≤ γ_T (relative)
        vr = round_up((np.sqrt(2) * 1.0000001 * self.gT * (aa @ self.absC) + ar @ (self.absC + self.R)
                  + aa @ self.R + 4 * UNDERFLOW * E.shape[0]) * (1 + 2 * self.gT))
        return vm, vr


#: exponents of the offsets are below 2^16 (degree ≤ 8): a monomial's key packs them in one int64
_KEY_BITS = 16


def _monomial_keys(ex):
    """One int64 per exponent row (i, j, k), ordered like the tuples (i, j, k)."""
    ex = np.asarray(ex, dtype=np.int64).reshape(-1, 3)
    if len(ex) and (ex.min() < 0 or ex.max() >= 1 << _KEY_BITS):
        raise ValueError("exponent out of range")          # callers fall back to arb
    return (ex[:, 0] << (2 * _KEY_BITS)) | (ex[:, 1] << _KEY_BITS) | ex[:, 2]


def _monomials_from_keys(keys):
    mask = (1 << _KEY_BITS) - 1
    return np.stack([keys >> (2 * _KEY_BITS), (keys >> _KEY_BITS) & mask, keys & mask], axis=1)


def _fast_krawczyk(fs: _FastSystem, m, attempts: int = 6):
    """Batched rigorous Krawczyk (norm form, module comment above) around float points m (N×3).

    Returns (ok, rad, r): ok[n] True iff certified; then the unique zero in {|x − m| ≤ r} is simple
    and lies within rad of m (componentwise)."""
    N = m.shape[0]
    vm, vr = fs.eval(m, np.zeros((N, 3)))
    Fm, Fr = vm[:, :3], vr[:, :3]
    J = vm[:, 3:].reshape(N, 3, 3)
    ok = np.zeros(N, dtype=bool)
    rad = np.full((N, 3), np.inf)
    rr = np.full((N, 3), np.inf)
    Y, good = float_inverse(J)
    b = float_residual_bound(Y, Fm, Fr)                                        # ≥ |Y F(m)|
    with np.errstate(all="ignore"):
        scale = np.abs(m).max(axis=1) + 1.0
        r = np.maximum(4 * b, (np.abs(m) + 1.0) * 2.0 ** -40)
        active = good & np.isfinite(b).all(axis=1)
        for _ in range(attempts):
            ids = np.nonzero(active & ~ok)[0]
            if not len(ids):
                break
            vmX, vrX = fs.eval(m[ids], r[ids])
            JX, JXr = vmX[:, 3:].reshape(-1, 3, 3), vrX[:, 3:].reshape(-1, 3, 3)
            win, lhs = float_krawczyk_test(b[ids], float_contraction_bound(Y[ids], JX, JXr), r[ids])
            ok[ids[win]] = True
            rad[ids[win]] = lhs[win]
            rr[ids[win]] = r[ids][win]
            lose = ids[~win]
            r[lose] = np.maximum(2 * lhs[~win], 2 * r[lose])
            active[lose] &= np.isfinite(r[lose]).all(axis=1) & (r[lose].max(axis=1) < 1e-3 * scale[lose])
    return ok, rad, rr


def _newton_np(fs: _FastSystem, S, real, iters: int = 4):
    """Floating-point Newton steps (not part of the proof: it only picks midpoints).  A point
    stops when its relative step is below 2^-50 or no longer halves: it has reached the noise
    of the float evaluation (measured: the refined solutions of the generic triples stall at
    relative steps 1e-11 to 1e-8 from the first step on, so further steps only cost time)."""
    m = S.copy()
    m[real] = m[real].real
    act = np.arange(len(m))
    prev = np.full(len(m), np.inf)
    with np.errstate(all="ignore"):
        for _ in range(iters):
            if not len(act):
                break
            ma = m[act]
            vm, _ = fs.eval(ma, np.zeros(ma.shape))
            J = vm[:, 3:].reshape(-1, 3, 3)
            F = vm[:, :3]
            fin = np.isfinite(J).all(axis=(1, 2)) & np.isfinite(F).all(axis=1)
            fin &= np.abs(np.linalg.det(np.where(fin[:, None, None], J, np.eye(3)))) > 0
            if not fin.any():
                break
            step = np.zeros_like(ma)
            step[fin] = np.linalg.solve(J[fin], F[fin][:, :, None])[:, :, 0]
            new = ma - step
            ra = real[act]
            new[ra] = new[ra].real
            upd = fin & np.isfinite(new).all(axis=1)
            m[act[upd]] = new[upd]
            size = (np.abs(step) / (np.abs(ma) + 1.0)).max(axis=1)
            done = ~upd | (size <= 2.0 ** -50) | (size > 0.5 * prev[act])
            prev[act] = size
            act = act[~done]
    return m


@lru_cache(maxsize=64)
def _fast_system(cos, frame=None) -> _FastSystem:
    conics = [tuple(c) for c in cos]
    return _FastSystem(framed_offset_system(conics, frame) if frame is not None else OffsetSystem(conics))


def _scene_frame_or_none(c1, c2, c3):
    """The exact scene frame of :func:`certify_solutions` (None: world coordinates)."""
    try:
        frame = tuple(Fraction(t) for t in scene_frame((c1, c2, c3)))
    except ValueError:
        return None
    return None if frame == (0, 0, 1) else frame


def clear_certification_caches() -> None:
    """Forget the per-triple systems of the certification (float and ball coefficient tables,
    scene-frame systems, zero-dimensionality proofs)."""
    from . import dimension, offset_system

    _fast_system.cache_clear()
    offset_system.clear_offset_system_caches()
    dimension.clear_dimension_cache()


def _nearly_real(S):
    scale = np.maximum(1.0, np.abs(S).max(axis=1))
    return np.abs(S.imag).max(axis=1) < 1e-6 * scale


def _certify_fast(c1, c2, c3, S, frame=None):
    """Batched fast path of :func:`certify_solutions` (proof in the comment above UNIT_ROUNDOFF), on the
    system in the coordinates of ``frame`` (None: world coordinates) at points S in those coordinates."""
    S = np.asarray(S, dtype=complex).reshape(-1, 3)
    out = [(None, None)] * len(S)
    if not len(S):
        return out
    try:
        fs = _fast_system(tuple(normalised_coefficients(c) for c in (c1, c2, c3)), frame)
    except (OverflowError, ValueError):
        return out
    real = _nearly_real(S)
    m = _newton_np(fs, S, real)
    ok, rad, r = _fast_krawczyk(fs, m)
    with working_prec(64):
        for n in np.nonzero(ok)[0]:
            if real[n]:
                # m[n] is real: the box is conjugation-symmetric, its unique zero is real
                out[n] = ("real", [arb(float(m[n, i].real), float(r[n, i])) for i in range(3)])
                continue
            K = [acb(arb(float(m[n, i].real), float(rad[n, i])), arb(float(m[n, i].imag), float(rad[n, i])))
                 for i in range(3)]
            if any(not k.imag.contains(0) for k in K):
                out[n] = ("nonreal", K)
    return out


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
    ``"fast"`` -- the batched rigorous floating-point Krawczyk test (:func:`_certify_fast`) only;
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
        boxes[j] = _conjugate_box(boxes[k])
    return boxes


def _conjugate_pairs(S):
    """(rep, mate): indices of the solutions to certify, and {j: k} for non-real solutions S_j
    that are numerically the conjugate of a certified S_k.  The offsets have real coefficients,
    so the conjugate of a Krawczyk box of S_k is a box with a unique, simple zero -- the
    conjugate zero -- and S_j needs no test of its own (:func:`_conjugate_box`).  The pairing is
    only a choice of work: whatever it pairs, every box returned still holds a unique zero, and
    distinctness is proved afterwards on all boxes (:func:`_disjoint`)."""
    n = len(S)
    if n < 2:
        return np.arange(n), {}
    nonreal = np.nonzero(~_nearly_real(S))[0]
    if len(nonreal) < 2:
        return np.arange(n), {}
    P = S[nonreal]
    scale = np.maximum(1.0, np.abs(P).max(axis=1))
    # nearest conjugate by the first coordinate, mutual, then checked on all three
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


def _conjugate_box(box):
    """The conjugate of a non-real Krawczyk box (kind 'nonreal', acb enclosures); (None, None) for
    anything else (that solution is then tested on its own by the callers' retries)."""
    kind, K = box
    if kind != "nonreal":
        return None, None
    return "nonreal", [k.conjugate() for k in K]


def _certify_framed(c1, c2, c3, S, prec, iters, method, frame):
    if method != "arb":
        out = _certify_fast(c1, c2, c3, S, frame)
        failed = [k for k, (kind, _) in enumerate(out) if kind is None]
        if method == "fast" or not failed:
            return out
        again = _certify_framed(c1, c2, c3, S[failed], max(prec, 128), iters, "arb", frame)
        for k, b in zip(failed, again):
            out[k] = b
        return out
    sys = framed_offset_system((c1, c2, c3), frame) if frame is not None else OffsetSystem((c1, c2, c3))
    out = []
    with working_prec(prec):
        for s in S:
            scale = max(1.0, float(np.max(np.abs(s))))
            nearly_real = float(np.max(np.abs(s.imag))) < 1e-6 * scale
            m = [acb(float(t.real), 0.0 if nearly_real else float(t.imag)) for t in s]
            m = _newton_c(sys, m, real=nearly_real, iters=iters)
            res = krawczyk_complex(sys, m, symmetric=nearly_real)
            if res is None and nearly_real and np.any(s.imag != 0):
                # a conjugate pair closer to the real axis than 10⁻⁶ of its size (a near-double
                # real root split into the complex plane): real Newton cannot reach either zero,
                # complex Newton from the unprojected point does
                nearly_real = False
                m = _newton_c(sys, [acb(complex(t)) for t in s], real=False, iters=max(iters, 8))
                res = krawczyk_complex(sys, m, symmetric=False)
            if res is None:
                out.append((None, None))
                continue
            K, X = res
            if nearly_real:
                out.append(("real", [k.real for k in K]))
            elif any(not k.imag.contains(0) for k in K):
                out.append(("nonreal", K))
            else:
                out.append((None, K))
    return out


def _newton_c(sys, m, real: bool, iters: int = 4):
    """Newton steps at the working precision (midpoints only, not part of the proof), stopping
    after a step below 2^(−prec/2) relative: quadratic convergence, the point is then at the
    working precision (as :func:`runtime.certify.offset_system.newton_track`)."""
    tol = 2.0 ** (-(flint.ctx.prec // 2))
    for _ in range(iters):
        vals, J = sys.eval(m)
        try:
            step = acb_mat(J).mid().solve(acb_mat([[v.mid()] for v in vals]))
        except ZeroDivisionError:
            return m
        m = [(m[i] - step[i, 0]).mid() for i in range(3)]
        if real:
            m = [acb(t.real.mid(), 0) for t in m]
        if all(float(abs(step[i, 0]).mid()) <= tol * (float(abs(m[i]).mid()) + 1.0) for i in range(3)):
            break
    return m


def _disjoint(Ks, pairs: list | None = None) -> bool:
    """Are the boxes pairwise disjoint?  With a list ``pairs``, every overlapping pair (a, b) is
    appended to it instead of stopping at the first.  A float prefilter (outward-rounded bounds of the six real
    coordinate intervals, all pairs at once in blocks of rows) finds the candidate pairs; only
    those are decided by ball arithmetic (:func:`_ov`), so the answer is the same as the all-pairs
    test."""
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
        return _disjoint_all_pairs(Ks)
    block = 256
    for a0 in range(0, n, block):
        a1 = min(n, a0 + block)
        meet = np.ones((a1 - a0, n), dtype=bool)
        for c in range(6):      # coordinate by coordinate (measured 10x faster than .all(axis=2))
            meet &= lo[a0:a1, None, c] <= hi[None, :, c]
            meet &= lo[None, :, c] <= hi[a0:a1, None, c]
        for a, b in zip(*np.nonzero(meet)):
            a = int(a) + a0
            if b > a and all(_ov(Ks[a][i], Ks[b][i]) for i in range(3)):
                if pairs is None:
                    return False
                pairs.append((a, int(b)))
    return not pairs


def _disjoint_all_pairs(Ks) -> bool:
    n = len(Ks)
    for a in range(n):
        for b in range(a + 1, n):
            if all(_ov(Ks[a][i], Ks[b][i]) for i in range(3)):
                return False
    return True


def _ov(p, q) -> bool:
    pa = p if isinstance(p, acb) else acb(p)
    qa = q if isinstance(q, acb) else acb(q)
    return pa.overlaps(qa)


def certify_completeness(c1, c2, c3, solutions, expected_count: int | None, *, max_prec: int = 256):
    """(complete, note): are ``solutions`` (N × 3 complex (x, y, R)) provably *all* the isolated
    solutions of o1 = o2 = o3 = 0, distinct, with reality decided (module docstring)?"""
    ok, note, _ = _completeness(c1, c2, c3, solutions, expected_count)
    return ok, note


def _completeness(c1, c2, c3, solutions, expected_count):
    S = np.asarray(solutions, dtype=complex).reshape(-1, 3)
    if expected_count is None:
        return False, "no generic solution count for this configuration", []
    if len(S) != expected_count:
        return False, f"{len(S)} solutions given, generic count is {expected_count}", []
    boxes = certify_solutions(c1, c2, c3, S)
    first_failed = [k for k, (kind, _) in enumerate(boxes) if kind is None]
    for prec in (128, 256):
        failed = [k for k, (kind, _) in enumerate(boxes) if kind is None]
        if not failed:
            break
        # up to 30 Newton steps: a complex root read next to the real axis (a conjugate pair 5e-5 of
        # its size apart, read 2e-9 off the axis) needs 10–30 before complex Newton splits the pair
        again = certify_solutions(c1, c2, c3, S[failed], prec=prec, iters=30)
        for k, b in zip(failed, again):
            boxes[k] = b
    failed = [k for k, (kind, _) in enumerate(boxes) if kind is None]
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
        failed = [k for k, (kind, _) in enumerate(boxes) if kind is None]
    if failed and len(failed) <= _MAX_CHART:
        _certify_split_pairs(c1, c2, c3, S, failed, boxes)
        failed = [k for k, (kind, _) in enumerate(boxes) if kind is None]
    diag = []
    for k in failed[:_MAX_DIAGNOSED]:
        box, text = _retry_or_diagnose(c1, c2, c3, S[k])
        if box is not None:
            boxes[k] = box
        else:
            diag.append(f"solution {k}: {text}")
    failed = [k for k, (kind, _) in enumerate(boxes) if kind is None]
    lost_note = ""
    if failed:
        # a point that is no solution (Newton leaves it): e.g. a real point where real Newton stalled
        # between the members of a conjugate pair closer to the real axis than it can tell, while
        # one of the pair was listed twice; search around it
        n_lost = (_replace_unproved(c1, c2, c3, S, boxes, _moved(S, boxes, first_failed))
                  if len(failed) <= _MAX_LOST else 0)
        if not n_lost:
            note = f"{len(failed)} of {len(S)} solutions not certified by Krawczyk"
            if diag:
                note += " (" + "; ".join(diag) + ")"
            return False, note, []
        lost_note = (f" ({n_lost} uncertified or overlapping solution(s) replaced by solutions found by Newton at "
                     "128 bits from starts around them)")
    overlaps: list = []
    if not _disjoint([K for _, K in boxes], overlaps):
        # a near-double pair (two simple zeros closer than the first boxes' radii, e.g. small sites
        # far apart): each of them again in a circle-space chart, where Newton separates them and
        # the Krawczyk boxes are tiny; any box that holds a unique zero may replace another
        from .chart import certify_in_chart
        again = sorted({k for pair in overlaps for k in pair})
        if len(again) <= _MAX_CHART:
            for k in again:
                box = certify_in_chart((c1, c2, c3), S[k])
                if box is not None:
                    boxes[k] = box
                    n_chart += 1
        if not _disjoint([K for _, K in boxes]):
            n_lost = _replace_unproved(c1, c2, c3, S, boxes, _moved(S, boxes, first_failed))
            if not n_lost:
                return False, "two solution enclosures overlap (distinctness not proven)", []
            lost_note = (f" ({n_lost} solution(s) whose enclosure overlapped another replaced by solutions found "
                         "by Newton at 128 bits from starts around them)")
    # counting bounds the *isolated* solutions only: positive-dimensional components are excluded
    # first (runtime.certify.dimension: modular dimension test of the projective closure in circle space)
    zero_dim, dim_note = zero_dimensional(c1, c2, c3)
    if not zero_dim:
        return False, f"{len(S)} distinct simple solutions = generic count, but {dim_note}", []
    # the count must be a proved bound on the isolated solutions of *these* conics
    # (runtime.certify.root_bound: circle-space mixed volume, Li–Wang)
    bound, bound_note = count_bound(c1, c2, c3)
    if bound is None or bound != len(S):
        return False, (f"{len(S)} distinct simple solutions = generic count, but no proved bound equal to it "
                       f"({bound_note})"), []
    reals = [K for kind, K in boxes if kind == "real"]
    note = f"{len(S)} distinct simple solutions ({len(reals)} real) = generic count, {bound_note}; {dim_note}"
    note += lost_note
    if n_chart:
        note += f" ({n_chart} far solution(s) certified in a circle-space chart)"
    return True, note, reals


def _certify_split_pairs(c1, c2, c3, S, failed, boxes) -> None:
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
        if not d[j] < 1e-3:
            continue
        start = S[k] + 1j * (S[k] - S[j]).real
        kind, K = certify_solutions(c1, c2, c3, start[None, :], prec=128, iters=12, method="arb")[0]
        if kind == "nonreal":
            boxes[k] = (kind, K)


def _moved(S, boxes, first_failed) -> list[tuple[np.ndarray, np.ndarray]]:
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


def _replace_unproved(c1, c2, c3, S, boxes, moved=()) -> int:
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
    drop = [k for k, (kind, _) in enumerate(boxes) if kind is None]
    proved = [k for k in range(len(S)) if k not in drop]
    overlaps: list = []
    _disjoint([boxes[k][1] for k in proved], overlaps)
    for a, b in overlaps:
        if proved[a] not in drop and proved[b] not in drop:
            drop.append(proved[b])
    if not drop or len(drop) > _MAX_LOST:
        return 0
    kept = [k for k in range(len(S)) if k not in drop]
    if not _disjoint([boxes[k][1] for k in kept]):
        return 0
    # conjugates of kept non-real boxes that meet no kept box: zeros the list lacks
    conj = [_conjugate_box(boxes[j]) for j in kept if boxes[j][0] == "nonreal"]
    pairs: list = []
    _disjoint([boxes[j][1] for j in kept] + [K for _, K in conj], pairs)
    met = {max(a, b) for a, b in pairs if min(a, b) < len(kept) <= max(a, b)}
    free = [conj[i - len(kept)] for i in range(len(kept), len(kept) + len(conj)) if i not in met]
    scale = np.maximum(1.0, np.abs(S).max(axis=1))
    rng = np.random.default_rng(17)
    for k in drop:
        f = next((f for f in free if _disjoint([boxes[j][1] for j in kept] + [f[1]])), None)
        if f is not None:
            boxes[k] = f
            kept.append(k)
            free.remove(f)
            continue
        # a near-double real pair seen as a conjugate pair m ± i·w: its zeros may be near m ± w·t
        m, w = S[k].real, S[k].imag
        starts = [c + t * (s - c) for s, c in moved for t in _MOVED_STEPS]
        starts += [m + s * t * w for t in _PAIR_STEPS for s in (1.0, -1.0)] if np.any(w != 0) else \
            [m + 1j * r * scale[k] * rng.standard_normal(3) for r in _NEAR_REAL_RADII for _ in range(2)]
        for attempt in range(_LOST_STARTS):
            direction = rng.standard_normal(3) + (1j * rng.standard_normal(3) if attempt % 2 else 0.0)
            direction = direction / np.abs(direction).max()
            radius = _LOST_RADII[attempt % len(_LOST_RADII)]
            starts.append(S[k] + radius * scale[k] * direction)
        for start in starts:
            kind, K = certify_solutions(c1, c2, c3, np.asarray(start, dtype=complex)[None, :], prec=128, iters=20,
                                        method="arb")[0]
            if kind is None:
                continue
            if _disjoint([boxes[j][1] for j in kept] + [K]):
                boxes[k] = (kind, K)
                kept.append(k)
                if kind == "nonreal":
                    free.append(_conjugate_box(boxes[k]))
                break
        else:
            return 0
    return len(drop) if _disjoint([K for _, K in boxes]) else 0


#: at most this many solutions with overlapping enclosures are replaced by a search around them
_MAX_LOST = 4
#: Newton starts tried around each of them, at these distances (relative to the point's size):
#: the roots of a cluster were measured 7e-5 to 2e-3 apart, a lost real root 6e-4 away
_LOST_STARTS = 30
_LOST_RADII = (1e-5, 1e-4, 1e-3, 1e-2, 1e-1)
#: imaginary offsets (relative to the point's size) of the complex starts around a real point
#: that is no solution (measured: a conjugate pair 1e-5 · i off the real axis found from 1e-6 to 1e-3)
_NEAR_REAL_RADII = (1e-6, 1e-5, 1e-4, 1e-3)
#: multiples t of the imaginary part w of a point m + i·w tried as real starts m ± t·w (measured:
#: the lost real root at m + 206·w, its partner at m − 0.1·w)
_PAIR_STEPS = (1.0, 3.0, 10.0, 30.0, 100.0, 300.0, 1000.0)
#: multiples t of s − c tried as starts c + t·(s − c) for a solution listed at s and certified at c
#: (measured: the missing zero of a close pair at t ≈ −0.6)
_MOVED_STEPS = (-0.5, -1.0, -2.0, 2.0, 3.0)
#: at most this many such solutions give starts (each costs len(_MOVED_STEPS) Newton runs per lost root)
_MAX_MOVED = 6
#: at most this many uncertified solutions get the high-precision retry / diagnosis
_MAX_DIAGNOSED = 4
#: the circle-space chart test is tried when at most this many solutions are uncertified
_MAX_CHART = 16
#: precisions (bits) of the polished retry
_RETRY_PRECS = (512, 1024)


def _retry_or_diagnose(c1, c2, c3, s):
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
    nearly_real = float(np.max(np.abs(s.imag))) < 1e-6 * scale
    with working_prec(_RETRY_PRECS[0]):
        m0 = [acb(float(t.real), 0.0 if nearly_real else float(t.imag)) for t in s]
        cond = _cond(sys, m0)
        m, conv = newton_track(sys, m0, nearly_real, iters=30)
        moved = max(abs(complex(m[i].mid()) - s[i]) for i in range(3)) / scale if conv else np.inf
    if conv and moved < 1e-6:
        for prec in _RETRY_PRECS:
            with working_prec(prec):
                mp = [acb(t) for t in m]
                mp, _ = newton_track(sys, mp, nearly_real, iters=3)
                res = krawczyk_complex(sys, mp, symmetric=nearly_real)
                if res is None:
                    continue
                K, _ = res
                if nearly_real:
                    return ("real", [k.real for k in K]), ""
                if any(not k.imag.contains(0) for k in K):
                    return ("nonreal", K), ""
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
    """Newton in the weighted chart at infinity (see :func:`_retry_or_diagnose`); returns
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


def _not_a_vertex(fps, K) -> bool:
    """Prove that the real solution in box K = (x, y, R) is not a true Voronoi vertex."""
    x, y, R = K
    if R < 0:
        return True
    if not R > 0:
        return False
    for fp in fps:
        try:
            feet = real_feet_ball(fp, x, y)
        except FootFailure:
            continue
        if any(f.D < R and not f.possible for f in feet):
            return True
        if all((f.D > R) or (f.D < R) for f in feet):
            return True  # √R is not the distance to any real foot point
    return False


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
                               retighten=None):
    """Completeness of the certified vertex list ``certs`` (CertifiedVertex objects).
    ``retighten(cv)``: a tighter (x, y, R) box of the same vertex as ``cv`` (or None), tried when
    a real solution's enclosure meets only ``cv``'s box but neither contains the other."""
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
                    and all(_ov(K[i], cv.box[i]) for i in range(3))]
            if len(near) == 1 and _same_by_krawczyk(OffsetSystem((c1, c2, c3)), K, certs[near[0]].box):
                matched.add(near[0])
                continue
            if len(near) == 1 and retighten is not None:
                # a far vertex: its 64-bit box is wider than K, and the offsets' interval Jacobian
                # over a box holding both is too wide for Krawczyk; a vertex box inside K is one
                # zero of the offset system in K, which holds exactly one
                B = retighten(certs[near[0]])
                if B is not None and all(K[i].contains(B[i]) for i in range(3)):
                    matched.add(near[0])
                    continue
            if _not_a_vertex(fps, K) or _closer_witness((c1, c2, c3), fps, K):
                continue
            # undecided: near a double foot point the foot-distance enclosures grow like the square
            # root of the box; a tighter box of the same zero (one inside K, where the zero is
            # unique) at 256 bits usually decides
            Kt = _tighter_real_box(c1, c2, c3, K)
            if Kt is None or not (_not_a_vertex(fps, Kt) or _closer_witness((c1, c2, c3), fps, Kt)):
                return False, (f"real solution ({float(K[0].mid()):.6g}, {float(K[1].mid()):.6g}) neither "
                               "matches a certified vertex nor is proved not to be a true vertex")
    unmatched = [k for k, cv in enumerate(certs) if cv.true_vertex and k not in matched]
    if unmatched:
        return False, f"{len(unmatched)} certified vertex(es) not among the solutions"
    return True, note + "; every real solution is a listed vertex or proved not a true vertex"


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
    foot point at distance √R: :func:`_not_a_vertex`).  Then the certified vertices are all the
    true vertices."""
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
            if not _not_a_vertex(fps, K[k]) and not _closer_witness((c1, c2, c3), fps, K[k]):
                x, y = float(K[k][0].mid()), float(K[k][1].mid())
                return False, (f"exact real solution ({x:.6g}, {y:.6g}) neither matches a certified vertex "
                               "nor is proved not to be a true vertex")
    return True, (f"exact: {len(K)} real solutions of the exact offset system (msolve); {len(owner)} are the "
                  f"certified vertices, {len(rest)} proved not true vertices")


def _conic_points_near(co, fx: float, fy: float):
    """Balls that each contain a point of the conic a·x² + b·xy + c·y² + d·x + e·y + f = 0 (exact
    coefficients ``co``) near (fx, fy): fix x = fx and solve the quadratic in y (and vice versa);
    a root ball of a quadratic with positive discriminant ball contains a true root."""
    a, b, c, d, e, f = (arb(flint.fmpq(t.numerator, t.denominator)) for t in co)
    out = []
    for swap in (False, True):
        if swap:
            a, c, d, e = c, a, e, d
            fx, fy = fy, fx
        X = arb(fx)
        A, B, C = c, b * X + e, a * X * X + d * X + f
        if A.contains(0):
            if not B.contains(0):
                out.append((X, -C / B) if not swap else (-C / B, X))
            continue
        disc = B * B - 4 * A * C
        if not disc > 0:
            continue
        for sgn in (1, -1):
            Y = (-B + sgn * disc.sqrt()) / (2 * A)
            out.append((X, Y) if not swap else (Y, X))
    return out


def _closer_witness(conics, fps, K) -> bool:
    """Proof that the real solution in K = (x, y, R) is not a true vertex by a *witness*: a ball
    containing a point of some C_i whose squared distance to every point of (x, y) is < R (then
    d(q, C_i) < √R, thesis Def. 5.2.1).  Seeds: the (possibly only numerical) foot points of the
    three sites at the centre of K -- this covers points on a symmetry axis inside the evolute,
    where the foot enclosures are only "possible"."""
    x, y, R = K
    if not R > 0:
        return False
    for conic, fp in zip(conics, fps):
        co = normalised_coefficients(conic)
        try:
            feet = real_feet_ball(fp, x, y)
        except FootFailure:
            feet = []
        for ft in feet:
            if not ft.D < R * 1.0000001 and not ft.possible:
                continue
            try:
                fx, fy = float(ft.px.mid()), float(ft.py.mid())
            except (ValueError, OverflowError):
                continue
            for P in _conic_points_near(co, fx, fy):
                D = (P[0] - x) ** 2 + (P[1] - y) ** 2
                if D < R:
                    return True
    return False
