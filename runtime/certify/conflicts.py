"""Certification of the conic conflict locator (thesis §5.2 Thm 5.2.2, §5.5, §3.3.3, ch. 6).

The numeric locator (§5.5: eigenvalues of a multiplication map) produces candidate vertices;
this module *proves* what it reports, or says that it could not.  CGAL-style split: the
numeric stage constructs, this stage decides predicates with filtered exact evaluation.

What is proved for one candidate (``certify_vertex``)
-------------------------------------------------------
1. **Existence and uniqueness** of a solution z* = (q, p1, p2, p3) of the 8×8 foot-point system
   (thesis §6.1, App. D.1; :mod:`runtime.certify.krawczyk`) in a box X, by Krawczyk's test in
   ball arithmetic, at growing precision (64, 128, 256, ... bits).  R = |q − p_i|² is enclosed
   by the intersection of the three balls |X_q − X_{p_i}|².
2. **True Voronoi vertex** (Def. 5.2.1: no point of C1, C2, C3 strictly inside the circle):
   for each i, all real foot points of q on C_i are enclosed rigorously via the Lagrange
   polynomial F_q(λ) (:mod:`runtime.certify.foot`); the one whose isolating interval contains
   the multiplier of p_i *is* p_i (D = R exactly); every other one must have D > R (disjoint
   balls).  A foot point with D < R proves the candidate is **not** a true vertex
   (``true_vertex=False``); a tie (D ball meets R) stays undecided (degenerate input).
3. **Conflict sign** s = sign(d(q, C4) − r): −1 if some real foot point on C4 has D < R
   (certified), +1 if all have D > R, else undecided by balls.
4. **Exact fallback** when the balls still meet: the simplest rationals x̂, ŷ, R̂ in the ball
   enclosures are tried (rational reconstruction, accepted only with a denominator much
   smaller than the precision); then with exact ``fmpq_poly`` arithmetic: F_q is exact, its
   real roots are isolated rigorously, and D(λ_k) = R̂ is *proved* by showing λ_k is a root of
   gcd(F_q, N_q − R̂·det²); this proves q̂ is a true vertex of radius² R̂ (for C1..C3: exactly
   one foot with D = R̂, all other real feet D > R̂), that it is the Krawczyk solution (its foot
   points lie in the Krawczyk boxes, uniqueness), and decides C4 exactly: exact tangency gives
   sign 0, margin exactly 0, no conflict (the empty circle is open).  Irrational vertices that
   are exactly tangent to C4 are *not* decided (sign None, certified False): deciding them
   needs algebraic-number arithmetic on the full system, which is not implemented.
5. **Sites with a common point.**  When C_i and C_j meet at a point X and the empty circle
   touches both there (two parabolas tangent at their common vertex, both touched at it from
   outside), d_i² − d_j² has gradient 2(p_j − p_i) = 0 at the vertex: the two bisector surfaces
   are tangent, the vertex is a singular solution of the foot-point system, and Krawczyk's test
   cannot succeed at any precision.  Such a vertex stays ``certified: false``, and the answer names
   the pair of sites that meet (exact test :func:`runtime.sites.intersection.sites_intersect`),
   the cause the user can act on.

Exact inputs: the conics' exact rational coefficients are used throughout (floats were already
converted at their exact binary value by :class:`runtime.sites.conic.Conic`).  The candidate (x, y, R)
is only a starting point.

Completeness is in :mod:`runtime.certify.complete`.

Length: one procedure, the certification of a locator answer (vertex boxes, touching, emptiness
and conflict signs), with the facts it relies on proved in this docstring.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from functools import partial
from fractions import Fraction
from typing import Any

from flint import arb, fmpq

from .foot import (FootFailure, FootPolynomial, exact_polynomials, foot_polynomial,
                           normalised_coefficients, real_feet_ball, to_arb, working_prec)
from .krawczyk import FootSystem, KrawczykFailure
from ..result import LocatorResult, VoronoiVertex
from ..sites.intersection import sites_intersect

__all__ = ["CertifiedVertex", "certify_vertex", "certify_result", "certify_completeness", "move_tolerance",
           "simplest_rational", "DEFAULT_MAX_PREC"]

DEFAULT_MAX_PREC = 1024


@dataclass
class CertifiedVertex:
    """Outcome of :func:`certify_vertex`.

    ``sign`` is sign(d(q, C4) − r): −1 conflict, 0 exact tangency (no conflict), +1 no conflict,
    None undecided (or no C4).  ``proven`` is True iff ``true_vertex`` is True and, when C4 was
    given, ``sign`` is not None.  Balls (``box``, ``radius``, ``distance_to_fourth``) are
    python-flint ``arb`` enclosures; ``box`` = (x, y, R) with R the squared radius.
    """

    proven: bool
    true_vertex: bool | None
    box: tuple[arb, arb, arb] | None
    feet: list[tuple[arb, arb]] | None
    radius: arb | None
    distance_to_fourth: arb | None
    sign: int | None
    tangent_exact: bool
    kind: str
    prec: int
    time: float
    note: str = ""
    exact: tuple[Fraction, Fraction, Fraction] | None = None
    timings: dict = field(default_factory=dict)

    @property
    def margin(self) -> arb | None:
        """Ball of (d4 − r)/r (exactly 0 when ``tangent_exact``)."""
        if self.tangent_exact:
            return arb(0)
        if self.distance_to_fourth is None or self.radius is None:
            return None
        return self.distance_to_fourth / self.radius - 1

    def info(self) -> dict[str, Any]:
        """JSON-friendly summary for ``VoronoiVertex.info['certificate']``."""
        def b(v):
            return None if v is None else {"mid": float(v.mid()), "rad": float(v.rad())}
        d = {"proven": self.proven, "true_vertex": self.true_vertex, "kind": self.kind,
             "prec": self.prec, "time": self.time, "sign": self.sign,
             "tangent_exact": self.tangent_exact, "note": self.note,
             "x": b(self.box[0]) if self.box else None, "y": b(self.box[1]) if self.box else None,
             "R": b(self.box[2]) if self.box else None, "radius": b(self.radius),
             "distance_to_fourth": b(self.distance_to_fourth), "margin": b(self.margin)}
        if self.exact is not None:
            d["exact"] = [str(v) for v in self.exact]
        return d


# --------------------------------------------------------------------------- helpers

def _ball(v) -> arb:
    if isinstance(v, arb):
        return v
    if isinstance(v, (int, Fraction, str)):
        return to_arb(Fraction(v))
    if isinstance(v, fmpq):
        return arb(v)
    return arb(float(v)) if not hasattr(v, "mid") else arb(v)


def _schedule(max_prec: int, start: int = 64) -> list[int]:
    out, p = [], start
    while p <= max_prec:
        out.append(p)
        p *= 2
    return out or [max_prec]


def _hull_min(a: arb, b: arb) -> arb:
    """A ball containing min(s, t) for every s ∈ a, t ∈ b."""
    lo = a.lower() if a.lower() < b.lower() else b.lower()
    hi = a.upper() if a.upper() < b.upper() else b.upper()
    return lo.union(hi)


def simplest_rational(lo: Fraction, hi: Fraction, max_terms: int = 400) -> Fraction | None:
    """The rational with the smallest denominator in [lo, hi] (continued fractions), or None if
    more than ``max_terms`` partial quotients would be needed."""
    if lo > hi:
        lo, hi = hi, lo
    if lo <= 0 <= hi:
        return Fraction(0)
    if hi < 0:
        r = simplest_rational(-hi, -lo, max_terms)
        return None if r is None else -r
    # 0 < lo <= hi: iterate x -> 1/(x - floor x) on both ends
    h0, h1, k0, k1 = 0, 1, 1, 0  # convergent recursion
    a_lo, a_hi = lo, hi
    for _ in range(max_terms):
        fl = math.floor(a_lo)
        if fl + 1 <= a_hi or a_lo == fl:
            a = fl if a_lo == fl else fl + 1
            return Fraction(a * h1 + h0, a * k1 + k0)
        # both ends in (fl, fl+1): same partial quotient
        h0, h1 = h1, fl * h1 + h0
        k0, k1 = k1, fl * k1 + k0
        a_lo, a_hi = 1 / (a_hi - fl), 1 / (a_lo - fl)
    return None


def _ball_end_points(x: arb) -> tuple[Fraction, Fraction]:
    """The rational end points (lower, upper) of a real ball."""
    lo, hi = x.lower().fmpq(), x.upper().fmpq()
    return Fraction(int(lo.p), int(lo.q)), Fraction(int(hi.p), int(hi.q))


# --------------------------------------------------------------------------- ball checks

class _Outcome:
    def __init__(self):
        self.true_vertex: bool | None = None
        self.sign: int | None = None
        self.D4: arb | None = None
        self.R: arb | None = None
        self.note = ""


def _identify(fp: FootPolynomial, feet, px, py, qx, qy):
    lam = fp.lagrange(px, py, qx, qy)
    idx = [k for k, f in enumerate(feet) if f.lam.overlaps(lam)]
    return idx[0] if len(idx) == 1 and not feet[idx[0]].possible else None


def _ball_checks(box, fps, fp4) -> _Outcome:
    out = _Outcome()
    qx, qy = box[0], box[1]
    R = None
    for i in range(3):
        dx, dy = qx - box[2 + 2 * i], qy - box[3 + 2 * i]
        Ri = dx * dx + dy * dy  # not ** 2: arb's pow is NaN on a ball containing 0
        R = Ri if R is None else R.intersection(Ri)
    out.R = R
    if not R > 0:
        out.note = "radius not separated from 0"
        return out
    undecided = False
    for i, fp in enumerate(fps):
        try:
            feet = real_feet_ball(fp, qx, qy)
        except FootFailure as exc:
            out.note = f"C{i + 1}: {exc}"
            return out
        k = _identify(fp, feet, box[2 + 2 * i], box[3 + 2 * i], qx, qy)
        if k is None:
            out.note = f"C{i + 1}: foot point of the vertex not identified among the real feet"
            return out
        for j, f in enumerate(feet):
            if j == k:
                continue
            if f.D < R and not f.possible:
                out.true_vertex = False
                out.note = f"C{i + 1} has a point strictly inside the circle: not a true vertex"
                return out
            if not f.D > R:
                undecided = True
                out.note = f"C{i + 1}: second foot point at (nearly) the same distance (tie)"
    if undecided:
        return out
    out.true_vertex = True
    if fp4 is not None:
        try:
            feet4 = real_feet_ball(fp4, qx, qy)
        except FootFailure as exc:
            out.note = f"C4: {exc}"
            return out
        if not feet4:
            out.note = "C4: no real foot point enclosed"
            return out
        Ds = [f.D for f in feet4]
        out.D4 = _fold_min(Ds)
        if any(f.D < R and not f.possible for f in feet4):
            out.sign = -1
        elif all(D > R for D in Ds):
            out.sign = 1
        else:
            out.note = "C4 (nearly) tangent to the empty circle: ball arithmetic cannot decide"
    return out


def _fold_min(Ds: list[arb]) -> arb:
    cur = Ds[0]
    for D in Ds[1:]:
        if D < cur:
            cur = D
        elif not D > cur:
            cur = _hull_min(cur, D)
    return cur


# --------------------------------------------------------------------------- exact path

def _exact_equal(F, N, det, R: Fraction, foot, intervals) -> bool:
    """Prove D(λ_k) = R exactly for the real root λ_k of F isolated by ``foot.lam``: λ_k is a root
    of gcd(F, N − R·det²).  ``intervals`` cover every real root of F (isolating intervals and
    cluster zones), so a real root of the gcd meeting only ``foot.lam`` is λ_k."""
    G = N - fmpq(R.numerator, R.denominator) * det * det
    g = F.gcd(G)
    if g.degree() < 1:
        return False
    for z, _m in g.complex_roots():
        if not z.imag.is_zero():
            continue
        hits = [I for I in intervals if I.overlaps(z.real)]
        if len(hits) == 1 and hits[0] is foot.lam:
            return True
    return False


def _classify_exact(fp, xq, yq, Rq, prec, max_prec):
    """Real feet of the rational point: list of ('<' | '=' | '>', foot).  None on failure."""
    F, N, det = exact_polynomials(fp, xq, yq)
    p = prec
    while p <= 8 * max_prec:
        with working_prec(p):
            zones: list = []
            try:
                feet = real_feet_ball(fp, to_arb(xq), to_arb(yq), zones_out=zones)
            except FootFailure:
                p *= 2
                continue
            intervals = [f.lam for f in feet if not f.possible] + zones
            Ra = to_arb(Rq)
            out, pending = [], False
            for f in feet:
                if f.D > Ra:
                    out.append((">", f))
                elif f.possible:
                    pending = True  # a possible foot at (nearly) distance R: cannot conclude
                    break
                elif f.D < Ra:
                    out.append(("<", f))
                elif _exact_equal(F, N, det, Rq, f, intervals):
                    out.append(("=", f))
                else:
                    pending = True  # D ≠ R proven, sign needs more digits
                    break
        if not pending:
            return out
        p *= 2
    return None


def _exact_path(box, fps, fp4, prec: int, max_prec: int, ubox=None):
    """Rational reconstruction + exact decision; returns (x̂, ŷ, R̂, sign) or (None, note)."""
    bound = 2 ** max(prec // 3, 16)
    vals = []
    for ball in (box[0], box[1], box[-1]):
        lo, hi = _ball_end_points(ball)
        r = simplest_rational(lo, hi)
        if r is None or r.denominator > bound:
            return None, "vertex not recognised as rational"
        vals.append(r)
    xq, yq, Rq = vals
    if Rq <= 0:
        return None, "reconstructed radius not positive"
    for i, fp in enumerate(fps):
        cls = _classify_exact(fp, xq, yq, Rq, 2 * prec, max_prec)
        if cls is None:
            return None, f"C{i + 1}: exact classification did not terminate"
        if any(c == "<" for c, _ in cls):
            return None, f"rational guess is not a true vertex (C{i + 1} closer)"
        eq = [f for c, f in cls if c == "="]
        if len(eq) != 1:
            return None, f"C{i + 1}: {len(eq)} feet at distance exactly R (need 1)"
        f = eq[0]
        U = ubox if ubox is not None else box
        if not (U[2 + 2 * i].contains(f.px) and U[3 + 2 * i].contains(f.py)
                and U[0].contains(to_arb(xq)) and U[1].contains(to_arb(yq))):
            return None, "exact vertex is not the Krawczyk solution"
    if fp4 is None:
        return (xq, yq, Rq, None), ""
    cls = _classify_exact(fp4, xq, yq, Rq, 2 * prec, max_prec)
    if cls is None or not cls:
        return None, "C4: exact classification did not terminate"
    if any(c == "<" for c, _ in cls):
        s = -1
    elif any(c == "=" for c, _ in cls):
        s = 0
    else:
        s = 1
    return (xq, yq, Rq, s), ""


# --------------------------------------------------------------------------- public API

#: precisions (bits) tried in turn for the initial foot points: far from a conic, the zones
#: around its singular multipliers (radius 2^(-prec/4) times a crude root bound of the foot
#: polynomial) overlap at low precision (measured: a vertex 4.7e6 away from ellipses of
#: semi-axes 1-2, root bound 1e38, needed 512 bits)
INITIAL_FEET_PRECS = (64, 128, 256, 512)


def _initial_feet(fps, x, y, R):
    for prec in INITIAL_FEET_PRECS:
        z = [x, y]
        try:
            with working_prec(prec):
                xa, ya, Ra = _ball(x), _ball(y), _ball(R)
                for fp in fps:
                    feet = real_feet_ball(fp, xa, ya)
                    if not feet:
                        raise FootFailure("no real foot point")
                    best = min(feet, key=lambda f: abs(float((f.D - Ra).mid())))
                    z += [best.px.mid(), best.py.mid()]
            return z
        except FootFailure:
            if prec == INITIAL_FEET_PRECS[-1]:
                raise


#: relative distance (to the scene scale) by which the proven vertex may differ from the candidate
MOVE_TOL = 1e-6
#: the largest move tolerance a candidate's own forward-error estimate may ask for
#: (:func:`move_tolerance`)
MOVE_TOL_MAX = 1e-4


def move_tolerance(info: dict) -> float:
    """The relative move allowed between a numeric candidate and its proven vertex: MOVE_TOL, or
    ten times the candidate's forward-error estimate when that is larger (its relative residual
    times the Jacobian condition of the offset system there, ``info['residual']`` and
    ``info['jacobian_cond']`` from :mod:`runtime.solve.vertices`: forward error ≲ condition ×
    backward error, Higham 2002, §1.6), at most :data:`MOVE_TOL_MAX`.  Why: a vertex millions of
    frame scales away next to a near-double root is read only to its conditioning (measured:
    collinear centres 100× apart, seed 8, a true vertex at (−7.46·10⁶, 3.11·10⁶) read 2.3·10⁻⁶ of
    its size off with residual 4·10⁻¹⁷ and condition 4.8·10¹¹), and Newton at 64 bits proves it
    there.  Nothing proved depends on it: the proven box is the vertex reported, two candidates
    reaching one vertex are merged, and the completeness proof matches every real solution."""
    try:
        est = 10.0 * float(info["residual"]) * float(info["jacobian_cond"])
    except (KeyError, TypeError, ValueError):
        return MOVE_TOL
    return min(max(MOVE_TOL, est), MOVE_TOL_MAX) if math.isfinite(est) else MOVE_TOL


def _moved(box, x, y, R, tol: float = MOVE_TOL) -> bool:
    cx, cy, cR = (float(Fraction(v)) if isinstance(v, str) else float(v) if not isinstance(v, arb)
                  else float(v.mid()) for v in (x, y, R))
    scale = 1.0 + abs(cx) + abs(cy) + math.sqrt(abs(cR))
    return math.hypot(float(box[0].mid()) - cx, float(box[1].mid()) - cy) > tol * scale


def certify_vertex(c1, c2, c3, x, y, R, c4=None, *, max_prec: int = DEFAULT_MAX_PREC,
                   exact: bool = True, min_prec: int = 64, move_tol: float = MOVE_TOL) -> CertifiedVertex:
    """Prove that a true Voronoi vertex of (C1, C2, C3) lies near (x, y) with squared radius ≈ R,
    and decide sign(d(q, C4) − r) (see the module docstring for what is proved).  The precisions
    tried run from ``min_prec`` to ``max_prec`` bits; a proof farther than ``move_tol`` (relative
    to 1 + |x| + |y| + √R) from (x, y) is refused (Newton left the candidate).

    Conics are :class:`runtime.sites.conic.Conic` objects (or 6-sequences of exact coefficients).
    ``x``, ``y``, ``R`` (R = radius²) may be floats, Fractions, decimal strings or arb balls.
    Never raises on a failed proof: returns ``proven=False`` with a ``note``.
    """
    t0 = time.perf_counter()
    fps = [foot_polynomial(normalised_coefficients(c)) for c in (c1, c2, c3)]
    fp4 = foot_polynomial(normalised_coefficients(c4)) if c4 is not None else None
    system = FootSystem([fp.coefficients for fp in fps])
    timings = {"krawczyk": 0.0, "feet": 0.0, "exact": 0.0}

    def done(**kw):
        kw.setdefault("timings", timings)
        return CertifiedVertex(time=time.perf_counter() - t0, **kw)

    try:
        z = _initial_feet(fps, x, y, R)
    except (FootFailure, ValueError, ZeroDivisionError) as exc:
        return done(proven=False, true_vertex=None, box=None, feet=None, radius=None,
                    distance_to_fourth=None, sign=None, tangent_exact=False, kind="none",
                    prec=64, note=f"initial foot points: {exc}")
    note, last, last_true, moved = "", None, None, None
    for prec in _schedule(max_prec, start=min_prec):
        with working_prec(prec):
            t1 = time.perf_counter()
            try:
                z = system.newton(z, prec)
                box = system.krawczyk(z)
            except KrawczykFailure as exc:
                timings["krawczyk"] += time.perf_counter() - t1
                note = f"{prec} bits: {exc}"
                continue
            t2 = time.perf_counter()
            timings["krawczyk"] += t2 - t1
            if moved is None:
                moved = _moved(box, x, y, R, move_tol)
                if moved:
                    return done(proven=False, true_vertex=None, box=None, feet=None, radius=None,
                                distance_to_fourth=None, sign=None, tangent_exact=False, kind="none",
                                prec=prec, note="Newton left the candidate: no vertex near (x, y)")
            out = _ball_checks(box, fps, fp4)
            timings["feet"] += time.perf_counter() - t2
            R_ball = out.R
            feet = [(box[2 + 2 * i], box[3 + 2 * i]) for i in range(3)]
            full_box = (box[0], box[1], R_ball)
            radius = R_ball.sqrt() if R_ball is not None and R_ball > 0 else None
            d4 = out.D4.sqrt() if out.D4 is not None and out.D4 >= 0 else None
            last = dict(box=full_box, feet=feet, radius=radius, distance_to_fourth=d4, prec=prec)
            last_true = out.true_vertex
            if out.true_vertex is False:
                return done(proven=False, true_vertex=False, sign=None, tangent_exact=False,
                            kind="krawczyk", note=out.note, **last)
            if out.true_vertex and (fp4 is None or out.sign is not None):
                return done(proven=True, true_vertex=True, sign=out.sign, tangent_exact=False,
                            kind="krawczyk", note="", **last)
            note = f"{prec} bits: {out.note}"
            if exact and out.true_vertex and prec >= 128:
                t3 = time.perf_counter()
                res, why = _exact_path((box[0], box[1], *box[2:], R_ball), fps, fp4, prec, max_prec,
                                       ubox=system.last_uniqueness_box)
                timings["exact"] += time.perf_counter() - t3
                if res is not None:
                    xq, yq, Rq, s = res
                    if s == 0:
                        last["distance_to_fourth"] = radius
                    return done(proven=True, true_vertex=True, sign=s, tangent_exact=(s == 0),
                                kind="exact-rational", note="", exact=(xq, yq, Rq), **last)
                note += f"; exact path: {why}"
    if last is None:
        return done(proven=False, true_vertex=None, box=None, feet=None, radius=None,
                    distance_to_fourth=None, sign=None, tangent_exact=False, kind="none",
                    prec=max_prec, note=note)
    return done(proven=False, true_vertex=last_true,
                sign=None, tangent_exact=False, kind="krawczyk", note=note, **last)


def _tighter_vertex_box(c1, c2, c3, cv: CertifiedVertex):
    """(x, y, R) box of the vertex of ``cv`` certified again from 128 bits, or None.  The 64-bit box
    of a far vertex is ~10⁻¹² of its size wide (measured: x ± 2.9e-8 at x ≈ −43481, R ≈ 1.9e9), too
    wide to be matched with the offset system's enclosure of the same zero.  The new box is
    accepted only inside ``cv``'s: its foot-system zero (x, y and the three feet) then lies in the
    Krawczyk image of ``cv``, whose zero is unique in the uniqueness box around it, so both are
    the same vertex."""
    if cv.box is None or cv.feet is None:
        return None
    tv = certify_vertex(c1, c2, c3, cv.box[0].mid(), cv.box[1].mid(), cv.box[2].mid(), None,
                        min_prec=128, max_prec=256, exact=False)
    if not (tv.proven and tv.true_vertex and tv.box is not None and tv.feet is not None):
        return None
    inside = (all(a.contains(b) for a, b in zip(cv.box[:2], tv.box[:2]))
              and all(a[0].contains(b[0]) and a[1].contains(b[1]) for a, b in zip(cv.feet, tv.feet)))
    return tv.box if inside else None


def _same_solution(a: CertifiedVertex, b: CertifiedVertex) -> bool | None:
    """True: provably the same vertex; False: provably distinct; None: cannot tell."""
    if a.box is None or b.box is None:
        return None
    overl = all(u.overlaps(v) for u, v in zip(a.box[:2], b.box[:2]))
    if not overl:
        return False
    return True if all(u.contains(v) or v.contains(u) for u, v in zip(a.box[:2], b.box[:2])) else None


def certify_result(result: LocatorResult, c1, c2, c3, c4, *, solutions=None,
                   expected_count: int | None = None, max_prec: int = DEFAULT_MAX_PREC) -> LocatorResult:
    """A new LocatorResult whose vertices carry proofs (thesis Thm 5.2.2 decided rigorously).

    * each vertex is certified with :func:`certify_vertex`; its coordinates become the midpoints
      of the proven boxes, ``in_conflict``/``tangent`` the proven sign, ``certified`` the proof
      status, ``info['certificate']`` the details;
    * candidates proved *not* to be true vertices are dropped (with a note), candidates proved to
      be the same vertex are merged;
    * ``complete`` is set only by :func:`certify_completeness` on ``solutions`` (all complex
      solutions (x, y, R) of the triple system) with ``expected_count``; otherwise False with a
      note (the candidate list alone cannot prove that no real vertex was missed);
    * ``conflict`` is True iff some vertex is in conflict (proven or numeric).
    """
    t0 = time.perf_counter()
    certs: list[CertifiedVertex] = []
    kept: list[VoronoiVertex] = []
    notes = list(result.notes)
    for v in result.vertices:
        cv = certify_vertex(c1, c2, c3, v.x, v.y, float(v.radius) ** 2, c4, max_prec=max_prec,
                            move_tol=move_tolerance(v.info))
        if cv.true_vertex is False:
            notes.append(f"certify: candidate ({v.x:.6g}, {v.y:.6g}) proved not a true Voronoi vertex; dropped")
            continue
        dup = None
        for k, other in enumerate(certs):
            if _same_solution(cv, other):
                dup = k
                break
        if dup is not None:
            notes.append(f"certify: candidate ({v.x:.6g}, {v.y:.6g}) is the same vertex as another; merged")
            continue
        certs.append(cv)
        kept.append(_proved_vertex(v, cv, c4))
    # distinctness of the certified vertices; two proven boxes that overlap without containment
    # may be one vertex reached from two candidates: one Krawczyk box of the offset system holding
    # both proves it (runtime.certify.complete.one_zero_in_both), and the second is merged
    same: set[int] = set()
    for i in range(len(certs)):
        for j in range(i + 1, len(certs)):
            if i in same or j in same:
                continue
            verdict = _same_solution(certs[i], certs[j])
            if verdict is None and certs[i].proven and certs[j].proven:
                from .complete import one_zero_in_both
                if one_zero_in_both(c1, c2, c3, certs[i].box, certs[j].box):
                    same.add(j)
                    notes.append(f"certify: candidate ({kept[j].x:.6g}, {kept[j].y:.6g}) is the same vertex as "
                                 "another (one Krawczyk box holds both); merged")
                    continue
            if verdict is not False:
                kept[i].certified = kept[j].certified = False
                notes.append("certify: two vertices not proven distinct")
    if same:
        certs = [cv for k, cv in enumerate(certs) if k not in same]
        kept = [nv for k, nv in enumerate(kept) if k not in same]
    if any(not v.certified for v in kept):
        notes.extend(_meeting_sites(c1, c2, c3))
    t_vert = time.perf_counter() - t0
    complete = False
    if solutions is not None:
        from .complete import completeness_with_vertices   # at call time: tests patch the module's proof
        found: list[CertifiedVertex] = []
        complete, note = completeness_with_vertices(
            c1, c2, c3, solutions, expected_count, certs, max_prec=max_prec,
            retighten=partial(_tighter_vertex_box, c1, c2, c3), found=found,
            certify_at=lambda K: certify_vertex(c1, c2, c3, K[0].mid(), K[1].mid(), K[2].mid(), c4, max_prec=max_prec))
        notes.append(f"certify completeness: {note}")
        if complete:
            kept = _complete_list(kept, certs, found, c4, notes)
    else:
        notes.append("certify: completeness not proven (no solution list of the triple system given)")
    timings = dict(result.timings)
    timings["certify_vertices"] = t_vert
    timings["certify_total"] = time.perf_counter() - t0
    conflict = any(v.in_conflict for v in kept)
    return LocatorResult(conflict=conflict, vertices=kept, method=result.method + "+certified",
                         timings=timings, complete=complete, notes=notes)


def _proved_vertex(v: VoronoiVertex | None, cv: CertifiedVertex, c4) -> VoronoiVertex:
    """The vertex reported for candidate ``v`` (None: a vertex found by the completeness proof)
    with its proof ``cv``: coordinates the midpoints of the proven box, ``certified`` the proof
    status, the conflict with C4 its proven sign."""
    if v is None:
        r = float(cv.radius.mid()) if cv.radius is not None else float("nan")
        v = VoronoiVertex(x=float(cv.box[0].mid()), y=float(cv.box[1].mid()), radius=r, certified=False,
                          info={"found_by": "the completeness proof, at a real solution of the triple system"})
    info = dict(v.info)
    info["certificate"] = cv.info()
    nv = VoronoiVertex(x=v.x, y=v.y, radius=v.radius, distance_to_fourth=v.distance_to_fourth,
                       in_conflict=v.in_conflict, certified=False, tangent=v.tangent, info=info)
    if cv.box is not None and cv.radius is not None:
        nv.x, nv.y, nv.radius = float(cv.box[0].mid()), float(cv.box[1].mid()), float(cv.radius.mid())
    if cv.proven:
        nv.certified = True
        if c4 is not None:
            nv.in_conflict = cv.sign == -1
            nv.tangent = cv.sign == 0
            nv.distance_to_fourth = float(cv.radius.mid()) if cv.sign == 0 else float(cv.distance_to_fourth.mid())
    return nv


def _complete_list(kept, certs, found, c4, notes) -> list[VoronoiVertex]:
    """The vertex list once :func:`runtime.certify.complete.completeness_with_vertices` succeeded:
    every real solution of the triple system is then a proven vertex of ``certs`` or ``found``
    (each inside its own solution box, the boxes pairwise disjoint: the proven vertices are
    distinct) or proved not a true vertex.  So a candidate whose proof did not decide
    (``true_vertex`` None: one near-double root listed twice, say) is no further vertex and is
    dropped, a proven one stays certified even where two candidates' boxes could not be told apart
    before, and the vertices found at solutions the list lacked are added."""
    out = []
    for nv, cv in zip(kept, certs):
        if cv.true_vertex is None:
            notes.append(f"certify: candidate ({nv.x:.6g}, {nv.y:.6g}) not proved, and the proved list is "
                         "complete without it; dropped")
            continue
        nv.certified = bool(cv.proven)
        out.append(nv)
    for cv in found:
        nv = _proved_vertex(None, cv, c4)
        notes.append(f"certify: vertex ({nv.x:.6g}, {nv.y:.6g}) found and proved at a real solution that "
                     "no candidate matched")
        out.append(nv)
    return out


def _meeting_sites(c1, c2, c3) -> list[str]:
    """Notes naming the pairs of C1, C2, C3 with a common real point (module docstring, item 5)."""
    out = []
    cs = (c1, c2, c3)
    for i in range(3):
        for j in range(i + 1, 3):
            try:
                meet = sites_intersect(cs[i], cs[j])
            except (TypeError, ValueError, AttributeError):
                continue
            if meet:
                out.append(f"certify: C{i + 1} and C{j + 1} have a common point (they intersect or touch): a vertex "
                           "whose empty circle touches both there is a singular solution of the offset system, "
                           "which interval Newton (Krawczyk) cannot certify; the Voronoi diagram expects disjoint "
                           "sites")
    return out


def certify_completeness(c1, c2, c3, solutions, expected_count: int | None, *,
                         max_prec: int = 256) -> tuple[bool, str]:
    """See :func:`runtime.certify.complete.certify_completeness`."""
    from .complete import certify_completeness as _cc
    return _cc(c1, c2, c3, solutions, expected_count, max_prec=max_prec)
