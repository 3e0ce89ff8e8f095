"""Branch-and-prune solver for square polynomial systems with inequality constraints.

This is the ALIAS-style general solver of thesis §3.3.3, on python-flint ``arb``:

* **exclusion** of a box when the interval value of an equation does not contain 0
  (natural nested-Horner form, then the mean-value form ``F(m) + J(X)(X-m)``), or when a
  necessary inequality cannot hold, or a user pruning hook says so;
* **Moore–Krawczyk test** (Thm 3.3.16): with ``Y = mid(J(X))^{-1}``,
  ``K(X) = m - Y F(m) + (I - Y J(X))(X - m)``.  ``K(X) ⊂ int X`` proves a unique zero in X
  (Rump's form of the theorem: the norm condition is implied); ``K(X) ∩ X = ∅`` proves none;
  otherwise ``X ∩ K(X)`` is an interval-Newton contraction;
* optional **3B consistency** (ALIAS/3B, ALIAS/Max3B, ALIAS/Delta3B): slices at both ends of
  each variable range are shaved off when they are proven infeasible;
* **bisection** on one variable (``"round-robin"``, ``"largest"``, ``"smear"``), on several
  (``"mixed"``, ALIAS/mixed_bisection) or on all (``"full"``);
* a **box budget** (the ALIAS maximal list size); what is left is returned as undecided.

Results are certified boxes (unique zero proven, with a tight enclosure obtained by iterating
the Krawczyk operator) and undecided boxes.  Nothing undecided is ever reported as a zero.
The operator is :func:`runtime.certify.interval_newton.krawczyk_image`, shared with every other
proof of the runtime.  The module is one algorithm (the branch-and-prune loop with its options),
hence its length.
"""
from __future__ import annotations

import math
import sys
from fractions import Fraction
import time
from dataclasses import dataclass, field
from typing import Callable

import numpy as np
from flint import arb, arb_mat

from .boxes import Box, arb_hi, arb_lo
from .poly import Poly
from ..certify.interval_newton import krawczyk_image

_ZERO = arb(0)
# split slightly off-centre so that rational/dyadic zeros do not sit on a bisection plane
SPLIT_RATIO = 0.5 + 1.0 / 67.0


@dataclass
class Inequality:
    """Necessary condition ``poly (sense) 0`` with sense in {'>=', '>', '<=', '<'} used for pruning."""

    poly: Poly
    sense: str

    def violated(self, v: arb) -> bool:
        if self.sense in (">=", ">"):
            return arb_hi(v) < 0 if self.sense == ">=" else arb_hi(v) <= 0
        return arb_lo(v) > 0 if self.sense == "<=" else arb_lo(v) >= 0


@dataclass
class System:
    """Square system ``equations(vars; params) = 0`` (len(equations) == nvars)."""

    names: tuple
    nvars: int
    equations: list
    inequalities: list = field(default_factory=list)
    #: hooks ``hook(box, arbs) -> True`` to discard a box (must be rigorous)
    prune_hooks: list = field(default_factory=list)
    params: list = field(default_factory=list)  # arb balls for the parameter variables
    label: str = ""
    #: evaluate equations and Jacobian with exact Taylor (centred) forms (no parameters allowed)
    taylor: bool = False
    #: contractors ``c(box) -> Box | None`` (None: no zero in box); must keep every zero
    contractors: list = field(default_factory=list)

    def __post_init__(self):
        if len(self.equations) != self.nvars:
            raise ValueError(f"square system expected: {len(self.equations)} equations, {self.nvars} unknowns")
        self.jac = [[p.diff(j) for j in range(self.nvars)] for p in self.equations]
        self._jac_zero = [[d.is_zero() for d in row] for row in self.jac]
        if self.taylor and self.params:
            raise ValueError("Taylor forms need a system without interval parameters")

    def taylor_eval(self, box: Box):
        """(F(X) enclosures, F(c) exact balls, J(X) enclosures, centre c) from Taylor forms."""
        from .poly import short_dyadic, taylor_form

        w = box.width
        c = [short_dyadic(float(m), float(wi)) for m, wi in zip(box.mid, w)]
        cf = np.array([float(v) for v in c])
        if np.any(cf < box.lo) or np.any(cf > box.hi):
            c = [Fraction(float(m)) for m in box.mid]
            cf = box.mid
        rho = np.maximum(box.hi - cf, cf - box.lo)
        rho = np.nextafter(rho, np.inf) * (1 + 2.0**-50)
        forms = [taylor_form(p, c) for p in self.equations]
        fx = [t.value(rho) for t in forms]
        fc = [t.c0 for t in forms]
        jac = [t.gradient(rho) for t in forms]
        return fx, fc, jac, cf

    # -- rigorous evaluations ------------------------------------------------
    def args(self, xs) -> list:
        return list(xs) + list(self.params)

    def eval_eqs(self, xs) -> list:
        a = self.args(xs)
        return [p.arb_eval(*a) for p in self.equations]

    def eval_jac(self, xs) -> list:
        a = self.args(xs)
        return [[_ZERO if z else d.arb_eval(*a) for d, z in zip(row, zrow)]
                for row, zrow in zip(self.jac, self._jac_zero)]

    def float_params(self):
        return [float(p.mid()) for p in self.params]


@dataclass
class Solution:
    box: Box          # box in which uniqueness was proven
    tight: Box        # certified tight enclosure of the same zero
    point: np.ndarray  # float approximation


@dataclass
class SolveResult:
    solutions: list
    undecided: list
    boxes: int
    exhausted: bool
    seconds: float
    stats: dict

    @property
    def complete(self) -> bool:
        """All boxes processed and none left undecided."""
        return not self.exhausted and not self.undecided


@dataclass
class SolverOptions:
    bisection: str = "smear"      # round-robin | largest | smear | mixed | full
    mixed_k: int | None = None     # variables bisected at once in "mixed" (default n//2)
    krawczyk: bool = True
    mean_value: bool = True
    shave_3b: bool = False
    max3b: float = 0.25            # scaled width below which 3B starts (ALIAS/Max3B, relative)
    delta3b: float = 1.0 / 64      # smallest slice tried (ALIAS/Delta3B, relative to the range)
    eps: float = 1e-13             # scaled width of undecided leaves
    max_boxes: int = 200_000
    progress: Callable | None = None
    progress_every: int = 2000
    verbose: bool = False
    tighten: bool = True


def _rel_width(box: Box, scale: np.ndarray) -> np.ndarray:
    return box.width / scale


def krawczyk(system: System, box: Box, jac=None, fm=None, centre=None):
    """One Moore–Krawczyk step.  Returns (status, box) with status 'unique' | 'empty' | 'unknown'.

    'unique': a unique zero of the system lies in ``box`` (K ⊂ int X); the returned box is X ∩ K.
    'empty': no zero in box.  'unknown': returned box is X ∩ K (a valid contraction), or X.
    """
    n = system.nvars
    xs = box.arbs()
    if jac is None and system.taylor:
        _fx, fm, jac, centre = system.taylor_eval(box)
    if jac is None:
        jac = system.eval_jac(xs)
    mids = box.mid if centre is None else centre
    marb = [arb(float(m)) for m in mids]
    if fm is None:
        fm = system.eval_eqs(marb)
    jmid = np.array([[float(v.mid()) if v.is_finite() else np.nan for v in row] for row in jac])
    if not np.all(np.isfinite(jmid)):
        return "unknown", box
    try:
        y = np.linalg.inv(jmid)
    except np.linalg.LinAlgError:
        return "unknown", box
    if not np.all(np.isfinite(y)):
        return "unknown", box
    ya = arb_mat(y.tolist())
    ks = krawczyk_image(marb, ya * arb_mat([[v] for v in fm]), ya, arb_mat(jac),
                        [xs[i] - marb[i] for i in range(n)])
    klo = np.array([arb_lo(k) for k in ks])
    khi = np.array([arb_hi(k) for k in ks])
    if not (np.all(np.isfinite(klo)) and np.all(np.isfinite(khi))):
        return "unknown", box
    lo = np.maximum(box.lo, klo)
    hi = np.minimum(box.hi, khi)
    if np.any(lo > hi):
        return "empty", None
    if np.all(klo > box.lo) and np.all(khi < box.hi):
        return "unique", Box(lo, hi)
    return "unknown", Box(lo, hi)


def tighten(system: System, box: Box, iterations: int = 40) -> Box:
    """Iterate X <- X ∩ K(X) on a box with a proven unique zero (the zero stays inside)."""
    for _ in range(iterations):
        st, nb = krawczyk(system, box)
        if nb is None:  # cannot happen for a box holding a zero; keep the old box
            break
        shrink = np.max((box.width - nb.width) / np.maximum(box.width, 1e-300))
        box = nb
        if shrink < 1e-3:
            break
    return box


def newton_point(system: System, x0, steps: int = 30):
    names = system.equations
    fp = system.float_params()
    x = np.array(x0, dtype=float)
    for _ in range(steps):
        a = list(x) + fp
        f = np.array([p.float_eval(*a) for p in names])
        j = np.array([[0.0 if z else d.float_eval(*a) for d, z in zip(r, zr)]
                      for r, zr in zip(system.jac, system._jac_zero)])
        try:
            dx = np.linalg.solve(j, f)
        except np.linalg.LinAlgError:
            return None
        x = x - dx
        if not np.all(np.isfinite(x)):
            return None
        if np.max(np.abs(dx)) <= 1e-15 * (1 + np.max(np.abs(x))):
            break
    return x


class Solver:
    """Branch and prune over a domain box (see module docstring)."""

    def __init__(self, system: System, domain: Box, options: SolverOptions | None = None):
        self.system = system
        self.domain = domain
        self.opt = options or SolverOptions()
        w = domain.width.copy()
        w[w <= 0] = 1.0
        self.scale = w
        self.stats = {"excluded_natural": 0, "excluded_mv": 0, "excluded_ineq": 0, "excluded_hook": 0,
                      "excluded_krawczyk": 0, "krawczyk_calls": 0, "contractions": 0, "bisections": 0,
                      "shaved": 0, "merged": 0}

    # ------------------------------------------------------------------ feasibility tests
    def _infeasible(self, box: Box, xs=None) -> bool:
        sysm = self.system
        if xs is None:
            xs = box.arbs()
        a = sysm.args(xs)
        for p in sysm.equations:
            v = p.arb_eval(*a)
            if arb_lo(v) > 0 or arb_hi(v) < 0:
                self.stats["excluded_natural"] += 1
                return True
        for ineq in sysm.inequalities:
            if ineq.violated(ineq.poly.arb_eval(*a)):
                self.stats["excluded_ineq"] += 1
                return True
        for hook in sysm.prune_hooks:
            if hook(box, xs):
                self.stats["excluded_hook"] += 1
                return True
        return False

    def _mv_infeasible(self, box: Box, jac) -> bool:
        sysm = self.system
        marb = [arb(float(m)) for m in box.mid]
        fm = sysm.eval_eqs(marb)
        xs = box.arbs()
        d = [xs[i] - marb[i] for i in range(sysm.nvars)]
        for i, row in enumerate(jac):
            v = fm[i]
            for j, jij in enumerate(row):
                if jij is not _ZERO:
                    v += jij * d[j]
            if arb_lo(v) > 0 or arb_hi(v) < 0:
                self.stats["excluded_mv"] += 1
                return True
        return False

    def _shave(self, box: Box) -> Box | None:
        """3B consistency: cut slices at both ends of each range while they are infeasible."""
        opt = self.opt
        for i in range(len(box)):
            w0 = box.width[i]
            if w0 <= 0:
                continue
            for side in (0, 1):
                frac = 0.5
                while frac * w0 >= opt.delta3b * w0 and box.width[i] > 0:
                    s = box.copy()
                    if side == 0:
                        cut = box.lo[i] + frac * box.width[i]
                        s.hi[i] = cut
                    else:
                        cut = box.hi[i] - frac * box.width[i]
                        s.lo[i] = cut
                    if self._infeasible(s):
                        self.stats["shaved"] += 1
                        if side == 0:
                            box.lo[i] = cut
                        else:
                            box.hi[i] = cut
                    else:
                        frac *= 0.5
            if box.lo[i] > box.hi[i]:
                return None
        if self._infeasible(box):
            return None
        return box

    # ------------------------------------------------------------------ bisection
    def _choose(self, box: Box, jac, depth: int) -> list[int]:
        opt = self.opt
        rw = _rel_width(box, self.scale)
        n = len(rw)
        cand = [i for i in range(n) if rw[i] >= 0.1 * rw.max()]
        if opt.bisection == "full":
            return list(range(n))
        if opt.bisection == "mixed":
            k = opt.mixed_k or max(1, n // 2)
            return list(np.argsort(-rw)[:k])
        if opt.bisection == "round-robin":
            for t in range(n):
                i = (depth + t) % n
                if rw[i] > 0:
                    return [i]
            return [int(np.argmax(rw))]
        if opt.bisection == "smear" and jac is not None:
            best, bi = -1.0, cand[0]
            for j in cand:
                s = 0.0
                for row in jac:
                    v = row[j]
                    if v is not _ZERO:
                        s = max(s, max(abs(arb_lo(v)), abs(arb_hi(v))) * box.width[j])
                # smear normalised by the equation scale is not needed for a choice among columns
                s = s if math.isfinite(s) else math.inf
                if s > best:
                    best, bi = s, j
            if best > 0:
                return [bi]
        return [int(np.argmax(rw))]

    @staticmethod
    def _split(box: Box, idx: list[int]) -> list[Box]:
        out = [box]
        for i in idx:
            nxt = []
            for b in out:
                nxt.extend(b.bisect(i, SPLIT_RATIO))
            out = nxt
        return out

    # ------------------------------------------------------------------ main loop
    def solve(self) -> SolveResult:
        t0 = time.perf_counter()
        opt = self.opt
        sysm = self.system
        stack: list[tuple[Box, int]] = [(self.domain.copy(), 0)]
        solutions: list[Solution] = []
        leaves: list[Box] = []
        processed = 0
        exhausted = False
        while stack:
            if processed >= opt.max_boxes:
                exhausted = True
                break
            box, depth = stack.pop()
            processed += 1
            if opt.progress is not None and processed % opt.progress_every == 0:
                opt.progress({"boxes": processed, "stack": len(stack), "solutions": len(solutions),
                              "undecided": len(leaves), "seconds": time.perf_counter() - t0,
                              "label": sysm.label})
            if opt.verbose and processed % opt.progress_every == 0:
                print(f"[interval {sysm.label}] boxes={processed} stack={len(stack)} sol={len(solutions)} "
                      f"undecided={len(leaves)} t={time.perf_counter() - t0:.1f}s", file=sys.stderr)
            res = self._process(box)
            if res is None:
                continue
            kind, b, jac = res
            if kind == "unique":
                solutions.append(b)
                continue
            if np.max(_rel_width(b, self.scale)) < opt.eps:
                leaves.append(b)
                continue
            self.stats["bisections"] += 1
            for child in reversed(self._split(b, self._choose(b, jac, depth))):
                stack.append((child, depth + 1))
        undecided = leaves + [b for b, _ in stack]
        sols = [self._finish(b) for b in solutions]
        sols, undecided = self._merge(sols, undecided) if not exhausted else (sols, undecided)
        sols = self._dedupe(sols)
        return SolveResult(sols, undecided, processed, exhausted, time.perf_counter() - t0, dict(self.stats))

    def _process(self, box: Box):
        """Returns None (discarded) or (kind, box, jac) with kind 'unique' | 'split'."""
        opt = self.opt
        sysm = self.system
        jac = None
        for _ in range(6):
            xs = box.arbs()
            if self._infeasible(box, xs):
                return None
            for con in sysm.contractors:
                box = con(box)
                if box is None:
                    self.stats["excluded_contractor"] = self.stats.get("excluded_contractor", 0) + 1
                    return None
            xs = box.arbs()
            if opt.shave_3b and np.max(_rel_width(box, self.scale)) <= opt.max3b:
                nb = self._shave(box.copy())
                if nb is None:
                    return None
                box = nb
                xs = box.arbs()
            if not (opt.krawczyk or opt.mean_value):
                return "split", box, None
            fm = centre = None
            if sysm.taylor:
                fx, fm, jac, centre = sysm.taylor_eval(box)
                if any(arb_lo(v) > 0 or arb_hi(v) < 0 for v in fx):
                    self.stats["excluded_mv"] += 1
                    return None
            else:
                jac = sysm.eval_jac(xs)
                if opt.mean_value and self._mv_infeasible(box, jac):
                    return None
            if not opt.krawczyk:
                return "split", box, jac
            self.stats["krawczyk_calls"] += 1
            st, nb = krawczyk(sysm, box, jac, fm, centre)
            if st == "empty":
                self.stats["excluded_krawczyk"] += 1
                return None
            if st == "unique":
                return "unique", nb, jac
            old = _rel_width(box, self.scale)
            new = _rel_width(nb, self.scale)
            if np.max(old - new) > 0.2 * np.max(old):
                self.stats["contractions"] += 1
                box = nb
                continue
            box = nb
            break
        return "split", box, jac

    def _finish(self, box: Box) -> Solution:
        tight = tighten(self.system, box) if self.opt.tighten else box
        return Solution(box=box, tight=tight, point=tight.mid)

    def _merge(self, sols, undecided):
        """Clusters of tiny undecided leaves (e.g. a zero on a bisection plane): try Krawczyk on their hull."""
        tiny = [b for b in undecided if np.max(_rel_width(b, self.scale)) < 1e-6]
        rest = [b for b in undecided if np.max(_rel_width(b, self.scale)) >= 1e-6]
        clusters: list[list[Box]] = []
        for b in tiny:
            grown = b.inflate(1.0, 1e-12 * self.scale)
            hit = [c for c in clusters if any(grown.overlaps(o) for o in c)]
            merged = [b]
            for c in hit:
                merged.extend(c)
                clusters.remove(c)
            clusters.append(merged)
        left = list(rest)
        for c in clusters:
            h = c[0]
            for o in c[1:]:
                h = h.hull(o)
            h = h.inflate(1.5, 1e-12 * self.scale)
            st, nb = krawczyk(self.system, h)
            if st == "empty":
                self.stats["merged"] += 1
                continue
            if st == "unique":
                self.stats["merged"] += 1
                if not any(h.contains(s.tight) for s in sols):
                    sols.append(self._finish(nb))
                continue
            left.extend(c)
        return sols, left

    @staticmethod
    def _dedupe(sols):
        out: list[Solution] = []
        for s in sols:
            # same zero only if it lies in a box where another zero was proven unique
            if any(o.box.contains(s.tight) or s.box.contains(o.tight) for o in out):
                continue
            out.append(s)
        return out


def solve(system: System, domain: Box, options: SolverOptions | None = None, **kw) -> SolveResult:
    if options is None:
        options = SolverOptions(**kw)
    return Solver(system, domain, options).solve()
