"""Null-space / truncated-normal-form solving on the *polytope-shaped* Newton-matrix support
(thesis §3.3.1, §5.5; Telen–Mourrain–Van Barel, SIAM J. Matrix Anal. Appl. 2018; Bender–Telen,
"Toric eigenvalue methods", 2022) compared with the weighted-degree Macaulay support of
``runtime.solve.vertices.generalised_vertices``.

For a triple configuration (EEE, EEP, PPP) the Canny–Emiris artefact ``generated/systems/
system_<CONF>.npz`` gives the column monomials E and, for each row, (polynomial, multiplier).  We
fill the rows of o1, o2, o3 (the f0 / u-polynomial rows dropped) with the *true* coefficients of
the three offsets written in C1's canonical frame scaled into the unit disc (o1 keeps its
canonical support; o2, o3 get the §5.3 simplification that the artefact's supports assume),
then

1. SVD of the o-rows matrix A (|rows| x |E|): numerical rank, gap, null space Z;
2. sub-supports V ⊂ C = {m ∈ E : m + e_x, m + e_y, m + e_R ∈ E} filtered by a grading w·m ≤ k
   (w = (1,1,2), the Macaulay grading, and w = (1,1,1)); the first k with rank Z[V_k] =
   rank Z[V_k ∪ shifts] (a clear "gap", as in the degree-gap method) gives N; column compression,
   a basis B ⊂ V_k by pivoted QR, multiplication matrices for x, y, R, eig of a random
   combination, (x, y, R) = Rayleigh quotients of the common eigenvectors;
3. match with generalised_vertices (Hungarian assignment on (x/L, y/L, R/L²)).

Variants (rows / columns):

* ``CE``   -- the artefact's Canny–Emiris o-rows on E (what the issue asks);
* ``CE+``  -- *all* multiples m·o_i with m + supp(o_i) ⊂ E ("polytope Macaulay matrix" on E);
* ``CE+1`` -- E enlarged by one Minkowski layer (E ∪ (E + e_x) ∪ (E + e_y) ∪ (E + e_R)), all
  multiples inside it.

    OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 python bench/newton_support_tnf.py [--n 5]

Writes the table to bench/results/newton_support.md (appends).

Finding (bench/results/newton_support.md): E is x·y·R times a weighted-degree (1,1,2) support
(degree 22 / 20 / 16 for EEE / EEP / PPP), not a smaller one; the artefact's rows are rank
deficient and ill-conditioned on true data; all routes here are less reliable and 1.4–19x slower
than the runtime's Macaulay route, so no runtime module uses them.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
from fractions import Fraction
from pathlib import Path

import numpy as np
import scipy.linalg as sla
from scipy.optimize import linear_sum_assignment

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from threadpoolctl import threadpool_info, threadpool_limits  # noqa: E402

from curvedvoronoi.runtime.sites.conic import Conic  # noqa: E402
from curvedvoronoi.runtime.algebra.polyalg import CanonicalOffset, WorkingFrame, compose_offset, core_points  # noqa: E402
from curvedvoronoi.runtime.result import LocatorError  # noqa: E402
from curvedvoronoi.runtime.solve.configurations import config_entry  # noqa: E402
from curvedvoronoi.runtime.solve.generalised import generalised_vertices  # noqa: E402
from curvedvoronoi.runtime.solve.macaulay import TOP_DEGREES, solve_nullspace  # noqa: E402
from curvedvoronoi.runtime.solve.newton import distinct_mask, newton_refine  # noqa: E402

DATA = Path("/work/tests/data/validation_cases.json")
COUNTS = {"EEE": 184, "EEP": 148, "PPP": 93}
VALIDATION = {"EEE": "ellipses_a_ellipse4_conflict", "PPP": "parabolas_a_parabola4_conflict"}
ROTS = [(3, 4, 5), (5, 12, 13), (8, 15, 17), (7, 24, 25), (20, 21, 29), (12, 35, 37), (9, 40, 41)]
SHIFTS = np.array([[1, 0, 0], [0, 1, 0], [0, 0, 1]])
RANK_TOL = 1e-10          # relative singular value threshold on A
PROFILE_TOL = 1e-11       # floor of the rank threshold on the (orthonormal) null-space blocks
GAP = 1e3


# ----------------------------------------------------------------------------- configurations

def random_triple(conf: str, seed: int):
    """Three conics of kinds ``conf`` (E ellipse, P parabola) with distinct rational rotations
    (Pythagorean triples), centres / vertices in [-0.5, 0.5]², semi-axes 0.25..0.5 x 0.075..0.2 (never a
    circle), p in 0.075..0.2 -- the ranges of tests/test_locator.random_configuration / 6."""
    rng = np.random.default_rng(seed)
    out = []
    # three distinct axis directions (equal directions, e.g. parallel parabola axes, are
    # non-generic: fewer finite solutions than the count)
    dirs = rng.choice(2 * len(ROTS), size=len(conf), replace=False)
    for k, dr in zip(conf, dirs):
        a, b, h = ROTS[int(dr) // 2]
        sg = 1 if dr % 2 else -1
        rot = (Fraction(a, h), Fraction(sg * b, h))
        c = (Fraction(int(rng.integers(-5, 6)), 10), Fraction(int(rng.integers(-5, 6)), 10))
        A = Fraction(int(rng.integers(10, 21)), 40)
        B = Fraction(int(rng.integers(3, 9)), 40)
        if k == "E":
            out.append(Conic.ellipse(centre=c, axes=(A, B), rotation=rot))
        else:
            out.append(Conic.parabola(vertex=c, p=B, rotation=rot))
    return out


def validation_triple(name: str):
    case = next(c for c in json.loads(DATA.read_text())["cases"] if c["name"] == name)
    return [Conic.from_coefficients(*k["coefficients"]) for k in case["conics"][:3]]


# ----------------------------------------------------------------------------- structure

def load_structure(conf: str):
    z = np.load(ROOT / "generated" / "systems" / f"system_{conf}.npz", allow_pickle=False)
    sup, off = z["supports"], z["support_offsets"]
    supports = [sup[off[i]:off[i + 1]].astype(np.int64) for i in range(len(off) - 1)]
    pts = z["points"].astype(np.int64)
    row_poly = z["row_poly"].astype(np.int64)
    row_term = z["row_term"].astype(np.int64)
    mult = pts - np.array([supports[i][j] for i, j in zip(row_poly, row_term)])
    keep = row_poly > 0                      # drop the f0 (u-polynomial) rows
    return {"E": pts, "supports": supports, "rows": list(zip(row_poly[keep], mult[keep]))}


def all_multiples(E, supports):
    """Rows m·o_i (i ≥ 1) for every m with m + supp(o_i) ⊂ E."""
    Eset = {tuple(p) for p in E.tolist()}
    rows = []
    for i in range(1, len(supports)):
        A = supports[i]
        cand = set()
        for a in A:
            cand.update(tuple(t) for t in (E - a).tolist())
        for m in sorted(cand):
            if all(tuple(np.add(m, a)) in Eset for a in A.tolist()):
                rows.append((i, np.array(m)))
    return rows


def add_layer(E):
    P = np.vstack([E] + [E + s for s in SHIFTS])
    return np.unique(P, axis=0)


def structure_variant(conf: str, variant: str):
    st = load_structure(conf)
    if variant == "CE":
        return st["E"], st["rows"], st["supports"]
    E = st["E"] if variant == "CE+" else add_layer(st["E"])
    return E, all_multiples(E, st["supports"]), st["supports"]


def structure_note(conf: str) -> str:
    """How E relates to the weighted-degree (1,1,2) Macaulay support: E − (1,1,1) vs the monomials
    of weighted degree ≤ D."""
    from curvedvoronoi.runtime.solve.macaulay import monomials
    E = load_structure(conf)["E"]
    Q = E - 1
    D = int((Q @ np.array([1, 1, 2])).max())
    M = {tuple(m) for m in monomials(D)[0].tolist()}
    S = {tuple(m) for m in Q.tolist()}
    closed = sum(all(tuple(np.add(m, sh)) in S for sh in SHIFTS.tolist()) for m in S)
    return (f"{conf}: |E| = {len(E)}, min exponent {E.min(axis=0).tolist()}; E − (1,1,1) ⊂ weighted degree ≤ {D} "
            f"({len(M)} monomials, {len(M - S)} missing: {sorted(M - S)[:6]}); {closed} of {len(E)} columns have "
            f"their x-, y- and R-shifts in E")


# ----------------------------------------------------------------------------- true system

def c1_frame(conics) -> WorkingFrame:
    """C1's canonical frame (origin = C1's centre / vertex, C1's axes), scaled so that all core
    points lie in the unit disc: o1 keeps its canonical support."""
    fr = conics[0].frame
    pts = np.array([p for c in conics for p in core_points(c)])
    L = float(np.max(np.hypot(pts[:, 0] - fr.tx, pts[:, 1] - fr.ty)))
    return WorkingFrame(float(fr.cos), float(fr.sin), float(fr.tx), float(fr.ty), L)


def true_polys(conf: str, conics, supports):
    """o1, o2, o3 in the C1 frame, §5.3-simplified, projected on the artefact supports (the
    dropped coefficients are rounding noise; their size is returned)."""
    offs = [CanonicalOffset(c) for c in conics]
    wf = c1_frame(conics)
    polys = [compose_offset(o, wf) for o in offs]
    top = (0, 0, 4) if conf[0] == "E" else (0, 0, 3)
    for i in (1, 2):
        if conf[i] == conf[0]:
            lam = polys[i].get(top, 0.0) / polys[0][top]
            p = dict(polys[i])
            for k, v in polys[0].items():
                p[k] = p.get(k, 0.0) - lam * v
            polys[i] = p
    out, noise = [], 0.0
    for i, p in enumerate(polys):
        S = supports[i + 1]
        scale = max(abs(v) for v in p.values())
        keys = {tuple(s) for s in S.tolist()}
        noise = max([noise] + [abs(v) / scale for k, v in p.items() if k not in keys])
        c = np.array([p.get(tuple(s), 0.0) for s in S.tolist()])
        out.append(c / np.linalg.norm(c))
    return out, wf, offs, noise


def fill(E, rows, supports, coefs):
    lo = E.min(axis=0)
    span = E.max(axis=0) - lo + 2
    cube = -np.ones(tuple(span), dtype=np.int64)
    cube[tuple((E - lo).T)] = np.arange(len(E))
    A = np.zeros((len(rows), len(E)))
    for r, (i, m) in enumerate(rows):
        cols = cube[tuple((supports[i] + m - lo).T)]
        A[r, cols] = coefs[i - 1]
    return A, cube, lo


# ----------------------------------------------------------------------------- TNF solve

def _rank_sv(s, tol):
    if len(s) == 0:
        return 0, math.inf, 0.0
    r = int((s > tol).sum())
    dropped = s[r] if r < len(s) else 0.0
    ratio = s[r - 1] / dropped if (0 < r < len(s) and dropped > 0) else math.inf
    return r, ratio, dropped


def tnf_solve(E, cube, lo, Z, weights, expected, tol, seed=7):
    """Gap search along the grading ``weights`` on the closed sub-support (rank threshold ``tol``,
    the estimated error of the null space), then TNF."""
    idx = lambda P: np.where(np.all((P - lo >= 0) & (P - lo < np.array(cube.shape)), axis=1),  # noqa: E731
                             cube[tuple(np.clip(P - lo, 0, np.array(cube.shape) - 1).T)], -1)
    sh = [idx(E + s) for s in SHIFTS]
    closed = np.all(np.stack(sh) >= 0, axis=0)
    w = E @ np.array(weights)
    levels = sorted(set(w[closed].tolist()))
    profile = {}
    found = None
    guided = None                       # (q, k, V, W): best level for the known count
    for k in levels:
        V = np.nonzero(closed & (w <= k))[0]
        W = np.unique(np.concatenate([V] + [s[V] for s in sh]))
        sv = np.linalg.svd(Z[V], compute_uv=False)
        sw = np.linalg.svd(Z[W], compute_uv=False)
        rv, ratv, _ = _rank_sv(sv, tol)
        rw, ratw, _ = _rank_sv(sw, tol)
        profile[k] = (rv, rw, f"{min(ratv, ratw):.0e}")
        if found is None and rv == rw and rv > 0 and min(ratv, ratw) >= GAP:
            found = (k, V, W, rv, min(ratv, ratw), "clear gap")
        if len(sv) >= expected:
            nxt = sw[expected] if len(sw) > expected else 0.0
            q = sv[expected - 1] / nxt if nxt > 0 else math.inf
            if guided is None or q > guided[0]:
                guided = (q, k, V, W)
    info = {"n_closed": int(closed.sum()), "n_E": len(E), "profile": profile}
    if (found is None or found[3] != expected) and guided is not None and guided[0] >= GAP:
        q, k, V, W = guided
        found = (k, V, W, expected, q, "count-guided")
    if found is None:
        return None, info
    k, V, W, N, ratio, how = found
    info.update(level=k, N=N, gap=ratio, nV=len(V), nW=len(W), how=how)
    _, _, Vt = np.linalg.svd(Z[W], full_matrices=False)
    Wc = Z @ Vt[:N].T                       # compressed null space, rows = E
    _, _, piv = sla.qr(Wc[V].T, pivoting=True, mode="economic")
    B = V[piv[:N]]
    lu = sla.lu_factor(Wc[B])
    Ms = [sla.lu_solve(lu, Wc[s[B]]) for s in sh]
    rng = np.random.default_rng(seed)
    c = rng.standard_normal(3)
    _, X = sla.eig(sum(ci * M for ci, M in zip(c, Ms)))
    Xi = np.linalg.inv(X)
    roots = np.stack([np.einsum("ij,jk,ki->i", Xi, M, X) for M in Ms], axis=1)
    info["cond_basis"] = float(np.linalg.cond(Wc[B]))
    return roots, info


# ----------------------------------------------------------------------------- one case

def run_case(conf, conics, variant, ref, struct_cache):
    key = (conf, variant)
    if key not in struct_cache:
        struct_cache[key] = structure_variant(conf, variant)
    E, rows, supports = struct_cache[key]
    t0 = time.perf_counter()
    coefs, wf, offs, noise = true_polys(conf, conics, supports)
    A, cube, lo = fill(E, rows, supports, coefs)
    t1 = time.perf_counter()
    try:
        _, s, Vt = sla.svd(A, full_matrices=True, lapack_driver="gesdd")
    except np.linalg.LinAlgError:          # gesdd did not converge (seen once on CE+1): QR-SVD
        _, s, Vt = sla.svd(A, full_matrices=True, lapack_driver="gesvd")
    r = int((s > RANK_TOL * s[0]).sum())
    gap = s[r - 1] / s[r] if r < len(s) else math.inf
    Z = Vt[r:].T
    # error of the computed null space ~ eps·σ_1/σ_r (Wedin); rank decisions below 10x that are noise
    tol = max(PROFILE_TOL, 10 * np.finfo(float).eps * s[0] / s[r - 1])
    t2 = time.perf_counter()
    out = {"shape": A.shape, "rank": r, "corank": len(E) - r, "sv_gap": gap,
           "sv_at": (s[r - 1] / s[0], s[r] / s[0] if r < len(s) else 0.0), "noise": noise, "tol": tol,
           "t_fill": t1 - t0, "t_svd": t2 - t1}
    best = None
    spent = 0.0
    for weights in [(1, 1, 2), (1, 1, 1)]:
        t3 = time.perf_counter()
        roots, info = tnf_solve(E, cube, lo, Z, weights, COUNTS[conf], tol)
        te = time.perf_counter() - t3
        cand = {"weights": weights, "t_eig": te, **info}
        if roots is not None:
            x, y = wf.to_world(roots[:, 0], roots[:, 1])
            pts = np.stack([x, y, roots[:, 2] * wf.L ** 2], axis=1)
            cand["dist"] = match(pts, ref, wf.L) if ref is not None else None
            cand["dist_refined"] = None
            fin = np.all(np.isfinite(pts), axis=1)
            rp, res, _ = newton_refine(offs, pts[fin], scale=wf.L)
            ok = res < 1e-11
            D = np.array([wf.L, wf.L, wf.L ** 2])
            cand["refined"] = int(distinct_mask(rp[ok], D).sum()) if ok.any() else 0
            if ref is not None and fin.all():
                cand["dist_refined"] = match(rp, ref, wf.L)
        spent += te
        if best is None or cand.get("refined", -1) > best.get("refined", -1):
            best = cand
        if best.get("N") == COUNTS[conf] and best.get("refined") == COUNTS[conf]:
            break
    best["t_eig"] = spent                 # all gradings tried
    out.update(best)
    return out


def match(pts, ref, L):
    D = np.array([L, L, L * L])
    """(max, median) over the optimal one-to-one matching of the scaled max-norm distance."""
    if len(pts) != len(ref):
        return (math.inf, math.inf)
    C = np.max(np.abs((pts[:, None, :] - ref[None, :, :]) / D), axis=2)
    i, j = linear_sum_assignment(C)
    return float(C[i, j].max()), float(np.median(C[i, j]))


def macaulay(conics):
    import inspect
    # the Macaulay null-space route only (newer runtimes add a homotopy fallback)
    kw = {"solver": "nullspace"} if "solver" in inspect.signature(generalised_vertices).parameters else {}
    t0 = time.perf_counter()
    try:
        sol = generalised_vertices(*conics, **kw)
    except LocatorError as exc:
        return None, {"error": str(exc)[:80], "total": time.perf_counter() - t0}
    tm = dict(sol.info.timings)
    tm["total"] = time.perf_counter() - t0
    tm["shape"] = sol.info.matrix_shape
    tm["N"] = sol.info.n_finite
    tm["degree"] = sol.info.degree
    # raw (un-refined) eigen-solutions of the accepted attempt, for an accuracy comparison
    offs = [CanonicalOffset(c) for c in conics]
    wf = sol.frame
    d0, _, hint = config_entry(tuple(sorted(o.family for o in offs)))
    d = sol.info.degree
    roots, _ = solve_nullspace([compose_offset(o, wf) for o in offs], [o.wdeg for o in offs], d,
                               top=TOP_DEGREES if sol.info.nullspace == "projected" else 0,
                               gap_hint=hint + d - d0)
    x, y = wf.to_world(roots[:, 0], roots[:, 1])
    tm["raw"] = match(np.stack([x, y, roots[:, 2] * wf.L ** 2], axis=1), sol.points, wf.L)
    return sol.points, tm


# ----------------------------------------------------------------------------- main

def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=5, help="random configurations per type")
    ap.add_argument("--configs", default="EEE,EEP,PPP")
    ap.add_argument("--variants", default="CE,CE+,CE+1")
    ap.add_argument("--no-write", action="store_true")
    args = ap.parse_args()
    head = ("| conf | case | support | matrix | rank | σ_r/σ_1 | σ_r/σ_{r+1} | null-space rank tol | gap at "
            "w·m ≤ k | N (expected) | distinct Newton-refined | raw eig vs ref: max / median | refined vs ref: max "
            "| fill s | SVD s | gap+TNF+eig s |")
    lines = [head, "|" + "---|" * (head.count("|") - 1)]
    print(head, flush=True)
    struct_cache: dict = {}
    summary = []

    def fmt(v):
        return "–" if v is None else (f"{v:.1e}" if isinstance(v, float) else f"{v[0]:.1e} / {v[1]:.1e}")

    with threadpool_limits(limits=1):
        for conf in args.configs.split(","):
            cases = []
            if conf in VALIDATION:
                cases.append((VALIDATION[conf], validation_triple(VALIDATION[conf])))
            for sd in range(args.n):
                cases.append((f"random {sd}", random_triple(conf, 1000 + sd)))
            for name, conics in cases:
                ref, mt = macaulay(conics)
                if ref is not None:
                    row = (f"| {conf} | {name} | Macaulay (runtime, degree {mt.get('degree', '')}) | "
                           f"{mt['shape'][0]}x{mt['shape'][1]} | – | – | – | 1e-11 | weighted degree | "
                           f"{mt['N']} ({COUNTS[conf]}) | {mt['N']} (reference) | {fmt(mt['raw'])} | 0 (reference) | "
                           f"{mt['fill']:.3f} | {mt['nullspace']:.3f} (QR) | {mt['eigen']:.3f} |")
                else:
                    row = (f"| {conf} | {name} | Macaulay (runtime) | refused: {mt['error']} |" + " |" * 12)
                print(row, flush=True)
                lines.append(row)
                for variant in args.variants.split(","):
                    o = run_case(conf, conics, variant, ref, struct_cache)
                    N = o.get("N")
                    row = (f"| {conf} | {name} | {variant} | {o['shape'][0]}x{o['shape'][1]} | {o['rank']} | "
                           f"{o['sv_at'][0]:.1e} | {o['sv_gap']:.1e} | {o['tol']:.0e} | "
                           f"{o['weights']} ≤ {o.get('level', '–')} ({o.get('how', 'none')}, {o.get('gap', 0):.0e}) | "
                           f"{N if N is not None else 'no gap'} ({COUNTS[conf]}) | {o.get('refined', '–')} | "
                           f"{fmt(o.get('dist'))} | {fmt(o.get('dist_refined'))} | {o['t_fill']:.3f} | "
                           f"{o['t_svd']:.3f} | {o['t_eig']:.3f} |")
                    summary.append((conf, variant, ref is not None, N == COUNTS[conf] and
                                    o.get("refined") == COUNTS[conf],
                                    o.get("dist_refined") is not None and o["dist_refined"][0] < 1e-4))
                    print(row, flush=True)
                    if N is None or os.environ.get("NS_VERBOSE"):
                        print("   profile", o["profile"], flush=True)
                    lines.append(row)
        info = [{k: d.get(k) for k in ("internal_api", "num_threads", "version")} for d in threadpool_info()]
    text = (f"\n## newton_support_tnf.py ({time.strftime('%Y-%m-%d %H:%M')})\n\n"
            f"Command: `OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS')} "
            f"OMP_NUM_THREADS={os.environ.get('OMP_NUM_THREADS')} python bench/newton_support_tnf.py "
            f"--n {args.n} --configs {args.configs} --variants {args.variants}`; threadpool_limits(1); "
            f"threadpool_info `{json.dumps(info)}`\n\n" + "\n".join(lines) + "\n")
    sl = ["", "Structure of the Canny–Emiris column sets:", ""] + [
        "* " + structure_note(c) for c in args.configs.split(",")]
    sl += ["", "| conf | support | cases | all N roots found (N = count, all refine, distinct) | Macaulay route "
          "(runtime) accepted, same cases | support route: all matched with Macaulay ≤ 1e-4 after Newton |", "|---|---|---|---|---|---|"]
    for conf in args.configs.split(","):
        for variant in args.variants.split(","):
            rs = [t for t in summary if t[0] == conf and t[1] == variant]
            sl.append(f"| {conf} | {variant} | {len(rs)} | {sum(t[3] for t in rs)} | {sum(t[2] for t in rs)} | "
                      f"{sum(t[4] for t in rs)} |")
    text += "\n".join(sl) + "\n"
    print("\n".join(sl))
    if not args.no_write:
        with open(ROOT / "bench" / "results" / "newton_support.md", "a") as fh:
            fh.write(text)


if __name__ == "__main__":
    main()
