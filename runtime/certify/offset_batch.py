"""Batched floating-point Krawczyk test of the offset system at all listed solutions at once.

Step 1 of the completeness proof (:mod:`runtime.certify.complete`): every listed solution s_k of
o1 = o2 = o3 = 0 gets a box X_k holding exactly one zero, which is simple.  Here all N solutions
are tested together in numpy (IEEE binary64, round-to-nearest, no directed rounding) by the
norm-form Krawczyk test of :func:`runtime.certify.interval_newton.float_krawczyk_test` (Krawczyk
1969; Rump's norm form), with every rounding of the evaluation bounded; a solution it does not
certify goes to the ball (arb/acb) test of :mod:`runtime.certify.solution_boxes`.

*Disc arithmetic.*  A "disc" is a pair (c, ρ) of a float midpoint c (complex128) and a float
radius ρ ≥ 0 standing for {z : |z − c| ≤ ρ}.  With u = 2^-53, every complex float product
satisfies fl(ab) = ab(1 + δ) + η, |δ| ≤ √2·γ₂ < 3u (no FMA) or √5·u (FMA), |η| ≤ 2^-1072
(underflow); so ε_c := 4u and η_c := 2^-1000 are safe.  Hence for a ∈ (â, ρa), b ∈ (b̂, ρb):

    |ab − fl(âb̂)| ≤ |â|ρb + ρa|b̂| + ρaρb + ε_c|â||b̂| + η_c            (D)

Radii are computed in round-to-nearest and then passed through round_up(t) = fl(t·(1+2^-40)) +
2^-1000, which dominates the (≤ 16 relative roundings of size u, and underflow) lost while
computing t from non-negative terms.  |z| is bounded above by abs_upper(z) = fl(fl(|Re z|+|Im z|)·
(1+2^-50)).  Overflow produces inf/nan, which makes every test False (fallback to arb).

*Polynomials.*  p = Σ_t c_t x^{α_t} with exact rational c_t; c̃_t = float(c_t) (correctly
rounded) and the exact |c_t − c̃_t| rounded up is its radius.  Monomials are disc products of disc
powers.  The sum Σ c̃_t M̂_t is a real dot product (Re, Im separately) whose error, for any
summation order / FMA use, is ≤ γ_T Σ|c̃_t||Re M̂_t| (same for Im), so ≤ √2·γ_T Σ|c̃_t||M̂_t|   (P)

*Krawczyk in norm form* (polydisc X = {|x_i − m_i| ≤ r_i}, Y any float matrix): the test
b + Δ r < r with b ≥ |Y F(m)| and Δ ≥ |I − Y M| for every M in the disc enclosures of the
Jacobian over X is :func:`runtime.certify.interval_newton.float_krawczyk_test`, with its proof
(one zero, simple, the only one in X, within b + Δ r of m; real if m is real, as X is then
conjugation-symmetric and F has real coefficients) and the bounds b, Δ computed there.
"""
from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from flint import acb, arb

from .foot import normalised_coefficients, working_prec
from .interval_newton import (UNDERFLOW, UNIT_ROUNDOFF, abs_upper, float_contraction_bound, float_inverse,
                              float_krawczyk_test, float_residual_bound, gamma, round_up)
from .offset_system import OffsetSystem, framed_offset_system

__all__ = ["FloatOffsetSystem", "certify_batch", "clear_float_system_cache", "nearly_real", "NEARLY_REAL"]


_EPS_C = 4 * UNIT_ROUNDOFF


def _dmul(am, ar, bm, br):
    """Disc product (midpoint, radius) of discs (am, ar) and (bm, br), radius by (D) of the module
    docstring; arrays broadcast."""
    cm = am * bm
    aa, ab = abs_upper(am), abs_upper(bm)
    return cm, round_up(aa * br + ar * ab + ar * br + _EPS_C * aa * ab + UNDERFLOW)


class FloatOffsetSystem:
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
        """Discs of the 12 polynomials at the polydiscs (mid[n], rad[n]) (shape N×3): (N×12, N×12).

        Each disc holds the polynomial's values over the polydisc: powers and monomials by the disc
        product (D), the coefficient sum with the dot-product bound (P) plus the coefficients'
        conversion radii (module docstring)."""
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


def _fast_krawczyk(fs: FloatOffsetSystem, m, attempts: int = 6):
    """Batched rigorous Krawczyk (norm form, module docstring) around float points m (N×3).

    The radius r starts at max(4b, 2^-40(|m| + 1)) and, while the test fails, grows to
    max(2(b + Δr), 2r) (an ε-inflation, Rump); up to ``attempts`` radii, stopping when r exceeds
    10^-3 of the point's size.  The schedule only decides which boxes are tried: a box is
    accepted only when b + Δ r < r holds for it.

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


def _newton_np(fs: FloatOffsetSystem, S, real, iters: int = 4):
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
def _fast_system(cos, frame=None) -> FloatOffsetSystem:
    """The float tables of the offsets of the normalised conics ``cos`` (in ``frame``'s coordinates)."""
    conics = [tuple(c) for c in cos]
    return FloatOffsetSystem(framed_offset_system(conics, frame) if frame is not None else OffsetSystem(conics))


#: a listed solution whose imaginary parts are below this fraction of its size is tested as real
#: (on a conjugation-symmetric box, whose unique zero is then real); the others as complex.  Only a
#: choice of test: a wrong choice makes the test fail, never a box wrong (module docstring)
NEARLY_REAL = 1e-6


def nearly_real(S):
    """Rows of S (N×3 complex) to be tested as real points: max|Im| < NEARLY_REAL · max(1, max|s|)."""
    S = np.asarray(S)
    scale = np.maximum(1.0, np.abs(S).max(axis=1))
    return np.abs(S.imag).max(axis=1) < NEARLY_REAL * scale


def clear_float_system_cache() -> None:
    """Forget the per-triple float tables."""
    _fast_system.cache_clear()


def certify_batch(c1, c2, c3, S, frame=None):
    """(kind, K) for each point of S (N×3, in the coordinates of ``frame``; None: world coordinates):
    kind 'real' with arb enclosures, 'nonreal' with acb enclosures of which some excludes the real
    axis, or None (not certified here).  Float Newton picks the midpoints (:func:`_newton_np`, not
    part of the proof); the batched norm-form Krawczyk test proves the boxes (module docstring)."""
    S = np.asarray(S, dtype=complex).reshape(-1, 3)
    out = [(None, None)] * len(S)
    if not len(S):
        return out
    try:
        fs = _fast_system(tuple(normalised_coefficients(c) for c in (c1, c2, c3)), frame)
    except (OverflowError, ValueError):
        return out
    real = nearly_real(S)
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
