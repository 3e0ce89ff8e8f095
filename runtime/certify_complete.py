"""Completeness of a vertex list (thesis §5.3–§5.5: the locator solves o1 = o2 = o3 = 0).

The numeric locator returns all N complex solutions (x, y, R) of the offset system
o1 = o2 = o3 = 0 it found (generalised Voronoi vertices, thesis §5.2) and the *generic count*
of the type configuration (e.g. 184 for three ellipses, DESIGN §5).  Completeness argument:

1. every solution s_k is enclosed in a box X_k by a **complex Krawczyk** test on the exact
   offsets o_i (the verified generic offset of :mod:`runtime.artefacts`, App. B.1–B.2,
   specialised at the conic's exact rational coefficients): X_k holds exactly one solution,
   which is simple (nonsingular Jacobian);
2. the enclosures are pairwise disjoint, so the N solutions are distinct;
3. a candidate with tiny imaginary part is tested on a *conjugation-symmetric* box: as the
   o_i have real coefficients, the unique solution in it is real.  Otherwise some coordinate of
   the enclosure must exclude the real axis (proved non-real);
4. if N equals the generic count, these are all the isolated solutions: by the coefficient-
   parameter theorem (Morgan–Sommese) a member of a family has at most the generic number of
   isolated solutions.  **Caveat**: the generic counts of ``runtime.vertices.CONFIG_TABLE`` were
   measured numerically (DESIGN §5), not proved; completeness is relative to them.  Solutions on
   positive-dimensional components are not covered (non-generic input).
5. every proven-real solution either matches a certified vertex (its box contains the vertex's
   box) or is proved *not* to be a true vertex: R < 0, or a real foot point on some C_i strictly
   closer than √R, or no real foot point at distance √R (R is the squared distance to a complex
   critical point only).

If any step fails, ``complete`` is False and the note says which.
"""
from __future__ import annotations

from fractions import Fraction
from functools import lru_cache

import flint
import numpy as np
from flint import acb, acb_mat, arb

from .artefacts import load_offset
from .certify_foot import (FootFailure, foot_polynomial, normalised_coefficients, real_feet_ball, to_arb,
                           working_prec)

__all__ = ["certify_completeness", "completeness_with_vertices", "OffsetSystem", "certify_solutions"]


@lru_cache(maxsize=256)
def _offset_terms(co: tuple[Fraction, ...]):
    o = load_offset("generic")
    a, b, c, d, e, f = co
    spec = o.specialise(a=a, b=b, c=c, d=d, e=e, f=f)
    m = max(abs(v) for v in spec.values())
    return tuple((i, j, k, v / m) for (i, j, k), v in spec.items())


class OffsetSystem:
    """o1, o2, o3 in (x, y, R) with exact rational coefficients, evaluated in acb."""

    def __init__(self, conics):
        self.terms = [_offset_terms(normalised_coefficients(c)) for c in conics]

    def _coeffs(self):
        return [[(i, j, k, to_arb(v)) for i, j, k, v in T] for T in self.terms]

    def eval(self, z, jac: bool = True):
        u, v, w = z
        U, V, W = [acb(1)], [acb(1)], [acb(1)]
        for _ in range(9):
            U.append(U[-1] * u)
            V.append(V[-1] * v)
            W.append(W[-1] * w)
        vals, J = [], []
        for T in self._coeffs():
            s, gu, gv, gw = acb(0), acb(0), acb(0), acb(0)
            for i, j, k, c in T:
                vw = V[j] * W[k]
                s += c * U[i] * vw
                if jac:
                    if i:
                        gu += (c * i) * U[i - 1] * vw
                    uw = U[i] * W[k]
                    if j:
                        gv += (c * j) * V[j - 1] * uw
                    if k:
                        gw += (c * k) * U[i] * V[j] * W[k - 1]
            vals.append(s)
            J.append([gu, gv, gw])
        return vals, J


def _krawczyk_c(sys: OffsetSystem, m: list[acb], symmetric: bool, attempts: int = 5):
    """Complex Krawczyk test around the (exact) point m; returns (K, X) or None."""
    vals, Jm = sys.eval(m)
    try:
        Y = acb_mat(Jm).mid().inv().mid()
    except ZeroDivisionError:
        return None
    F = acb_mat([[v] for v in vals])
    YF = Y * F
    scale = max(abs(mi).abs_upper() for mi in m) + 1
    r = [max(4 * abs(YF[i, 0]).abs_upper(), (abs(m[i]).abs_upper() + 1) * arb(2) ** (-flint.ctx.prec // 2))
         for i in range(3)]
    I3 = acb_mat(3, 3)
    for i in range(3):
        I3[i, i] = acb(1)
    for _ in range(attempts + 3):
        dX = [acb(arb(0, ri), arb(0, ri)) for ri in r]
        X = [m[i] + dX[i] for i in range(3)]
        _, JX = sys.eval(X)
        C = I3 - Y * acb_mat(JX)
        CdX = C * acb_mat([[d] for d in dX])
        K = [m[i] - YF[i, 0] + CdX[i, 0] for i in range(3)]
        if all(_inside(K[i], m[i], r[i]) for i in range(3)):
            return K, X
        r = [max(2 * abs(K[i] - m[i]).abs_upper(), 2 * r[i]) for i in range(3)]
    return None


def _inside(k: acb, m: acb, r: arb) -> bool:
    d = k - m
    return bool((abs(d.real).abs_upper() < r) and (abs(d.imag).abs_upper() < r))


def certify_solutions(c1, c2, c3, solutions, *, prec: int = 64, iters: int = 4):
    """Krawczyk boxes for every solution: list of (kind, K) with kind 'real' | 'nonreal' | None."""
    sys = OffsetSystem((c1, c2, c3))
    S = np.asarray(solutions, dtype=complex)
    out = []
    with working_prec(prec):
        for s in S:
            scale = max(1.0, float(np.max(np.abs(s))))
            nearly_real = float(np.max(np.abs(s.imag))) < 1e-6 * scale
            m = [acb(float(t.real), 0.0 if nearly_real else float(t.imag)) for t in s]
            m = _newton_c(sys, m, real=nearly_real, iters=iters)
            res = _krawczyk_c(sys, m, symmetric=nearly_real)
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
    for _ in range(iters):
        vals, J = sys.eval(m)
        try:
            step = acb_mat(J).mid().solve(acb_mat([[v.mid()] for v in vals]))
        except ZeroDivisionError:
            return m
        m = [(m[i] - step[i, 0]).mid() for i in range(3)]
        if real:
            m = [acb(t.real.mid(), 0) for t in m]
    return m


def _disjoint(Ks) -> bool:
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
    for prec in (128, 256):
        failed = [k for k, (kind, _) in enumerate(boxes) if kind is None]
        if not failed:
            break
        again = certify_solutions(c1, c2, c3, S[failed], prec=prec, iters=8)
        for k, b in zip(failed, again):
            boxes[k] = b
    failed = [k for k, (kind, _) in enumerate(boxes) if kind is None]
    if failed:
        return False, f"{len(failed)} of {len(S)} solutions not certified by Krawczyk", []
    if not _disjoint([K for _, K in boxes]):
        return False, "two solution enclosures overlap (distinctness not proven)", []
    reals = [K for kind, K in boxes if kind == "real"]
    return True, f"{len(S)} distinct simple solutions ({len(reals)} real) = generic count", reals


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


def completeness_with_vertices(c1, c2, c3, solutions, expected_count, certs, *, max_prec: int = 256):
    """Completeness of the certified vertex list ``certs`` (CertifiedVertex objects)."""
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
            if not _not_a_vertex(fps, K):
                return False, (f"real solution ({float(K[0].mid()):.6g}, {float(K[1].mid()):.6g}) neither "
                               "matches a certified vertex nor is proved not to be a true vertex")
    unmatched = [k for k, cv in enumerate(certs) if cv.true_vertex and k not in matched]
    if unmatched:
        return False, f"{len(unmatched)} certified vertex(es) not among the solutions"
    return True, note + "; every real solution is a listed vertex or proved not a true vertex"
