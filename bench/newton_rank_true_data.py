"""Is the Canny–Emiris Newton matrix singular on true conic data?  (DESIGN §3, issue 4 "known obstacle")

For a Table 5.1 configuration (or a three-conic vertex system), the generic matrix STRUCTURE from
generated/systems/ is filled with (a) random integers and (b) the coefficients of the true
conflict-locator system of a validation case (C1 in canonical position, Ci = canonical offsets
composed with the exact rational rigid motions of the case, §5.3 simplifications, f0 a random
linear form), and its rank is computed exactly modulo a 62-bit prime (python-flint nmod_mat).
Also the rank of the M11 block (the block whose inverse the thesis' Schur complement needs).

    python bench/newton_rank_true_data.py [CONFIG CASE ...]     (default: EEE and PPP triples)

Writes the table to bench/results/newton_rank.md.
"""
from __future__ import annotations

import json
import random
import sys
import time
from fractions import Fraction
from pathlib import Path

import flint
import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from curvedvoronoi.precompute import systems  # noqa: E402
from curvedvoronoi.runtime.validation import default_cases_path  # noqa: E402

PRIME = 4611686018427388039   # 2^62 + 135, prime


def _motion(c1: dict, ci: dict) -> tuple[Fraction, ...]:
    """(a, b, c, d): Ci's canonical coordinates as a X1 − b Y1 + c, b X1 + a Y1 + d."""
    F = Fraction
    c1c, c1s, t1x, t1y = F(c1["cos"]), F(c1["sin"]), F(c1["tx"]), F(c1["ty"])
    cic, cis, tix, tiy = F(ci["cos"]), F(ci["sin"]), F(ci["tx"]), F(ci["ty"])
    a = c1c * cic + c1s * cis
    b = c1s * cic - c1c * cis
    c = cic * (t1x - tix) + cis * (t1y - tiy)
    d = -cis * (t1x - tix) + cic * (t1y - tiy)
    return tuple(flint.fmpq(t.numerator, t.denominator) for t in (a, b, c, d))


def _params(can: dict) -> tuple[str, dict]:
    def F(v):
        q = Fraction(v)
        return flint.fmpq(q.numerator, q.denominator)
    if can["type"] == "parabola":
        return "P", {"p": F(can["p"])}
    if can["type"] == "ellipse":
        return "E", {"c": F(can["A2"]) / F(can["B2"]), "e": -F(can["A2"])}
    if can["type"] == "hyperbola":
        return "E", {"c": -F(can["A2"]) / F(can["B2"]), "e": -F(can["A2"])}
    raise ValueError(f"no Table 5.1 family for {can['type']}")


def true_system(case: dict, nconics: int):
    cans = [k["canonical"] for k in case["conics"][:nconics]]
    kinds = [_params(c)[0] for c in cans]
    variables = systems.VARS if nconics == 4 else systems.VARS3
    ctx = flint.fmpq_mpoly_ctx.get(variables, "lex")
    rng = random.Random(1)
    f0 = ctx.constant(rng.randint(1, 99))
    for g in ctx.gens():
        f0 = f0 + rng.randint(1, 99) * g
    k1, p1 = _params(cans[0])
    o1 = systems.offset_poly(k1, ctx, "r", None, p1)
    polys = [f0, o1]
    for i in range(1, nconics):
        ki, pi = _params(cans[i])
        dist = "R" if i == 3 else "r"
        oi = systems.offset_poly(ki, ctx, dist, _motion(cans[0], cans[i]), pi)
        term = systems.simplify_term(k1, ki, dist)
        if term is not None:
            term = term[: len(variables)]
            c1, ci = systems._coeff(o1, term), systems._coeff(oi, term)
            oi = oi * c1 - o1 * ci
        polys.append(oi)
    return "".join(kinds), polys


def ranks(config: str, coefficient_lists) -> tuple[int, int, int, int, float]:
    z = np.load(ROOT / "generated" / "systems" / f"system_{config}.npz", allow_pickle=False)
    head = json.loads((ROOT / "generated" / "systems" / f"system_{config}.json").read_text())
    n, n00 = head["size"], head["n00"]
    dense = np.zeros((n, n), dtype=object)
    offs = z["support_offsets"]
    flat = []
    for i, cs in enumerate(coefficient_lists):
        assert len(cs) == offs[i + 1] - offs[i]
        flat.extend(int(c) % PRIME for c in cs)
    flat = np.array(flat, dtype=object)
    dense[z["rows"], z["cols"]] = flat[offs[z["poly"]] + z["term"]]
    t0 = time.perf_counter()
    full = flint.nmod_mat(dense.tolist(), PRIME).rank()
    m11 = flint.nmod_mat(dense[n00:, n00:].tolist(), PRIME).rank()
    return n, full, n - n00, m11, time.perf_counter() - t0


def _mod(q) -> int:
    q = Fraction(int(q.p), int(q.q)) if hasattr(q, "p") else Fraction(q)
    return q.numerator % PRIME * pow(q.denominator % PRIME, -1, PRIME) % PRIME


def coefficients_on_structure(config: str, polys) -> list[list[int]]:
    z = np.load(ROOT / "generated" / "systems" / f"system_{config}.npz", allow_pickle=False)
    sup, offs = z["supports"], z["support_offsets"]
    out = []
    for i, p in enumerate(polys):
        d = {tuple(int(e) for e in k): v for k, v in p.to_dict().items()}
        mons = [tuple(int(e) for e in m) for m in sup[offs[i]:offs[i + 1]]]
        extra = set(d) - set(mons)
        if extra:
            raise ValueError(f"{config}: true polynomial {i} has monomials outside the generic support")
        out.append([_mod(d[m]) if m in d else 0 for m in mons])
    return out


def main(argv):
    cases = {c["name"]: c for c in json.loads(default_cases_path().read_text())["cases"]}
    todo = list(zip(argv[::2], argv[1::2])) or [("EEE", "ellipses_a_ellipse4_conflict"),
                                                 ("PPP", "parabolas_a_parabola4_conflict")]
    rows = ["| system | case | size | rank (random fill) | rank (true data) | M11 size | M11 rank (random) "
            "| M11 rank (true) | seconds |", "|---|---|---|---|---|---|---|---|---|"]
    for config, name in todo:
        kinds, polys = true_system(cases[name], len(config))
        assert kinds == config, (kinds, config)
        true_c = coefficients_on_structure(config, polys)
        rng = random.Random(0)
        rand_c = [[rng.randrange(1, PRIME) for _ in cs] for cs in true_c]
        n, rr, n11, r11r, t1 = ranks(config, rand_c)
        _, rt, _, r11t, t2 = ranks(config, true_c)
        rows.append(f"| {config} | {name} | {n} | {rr} | {rt} | {n11} | {r11r} | {r11t} | {t1 + t2:.1f} |")
        print(rows[-1], flush=True)
    text = "\n".join(rows) + "\n"
    out = ROOT / "bench" / "results" / "newton_rank.md"
    with out.open("a") as fh:
        fh.write(f"\n## {time.strftime('%Y-%m-%d %H:%M')} (rank mod {PRIME})\n\n" + text)
    print(text)


if __name__ == "__main__":
    main(sys.argv[1:])
