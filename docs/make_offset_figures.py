"""Figures and tables of docs/offsets.md: generalised offsets of plane algebraic curves (thesis ch. 4).

    python docs/make_offset_figures.py            # docs/images/strophoid_offsets.png (as Fig. 4.1.2)
    python docs/make_offset_figures.py --table    # the Theorem 4.2.18 table (Markdown) on stdout

The picture draws the strophoid y² = x² + x³ and the zero set of its generalised offset
o(u, v, R) (from ``curvedvoronoi.offset``) for a few squared distances R, as thesis Fig. 4.1.2,
with the extraneous circle of the node (rejected by ``offset``) dashed.
"""
from __future__ import annotations

import argparse
import random
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from curvedvoronoi.runtime.algebra.algebraic_offset import offset  # noqa: E402
from curvedvoronoi.runtime.algebra.offset_degrees import offset_degrees_on_line  # noqa: E402
from curvedvoronoi.runtime.algebra.degree_formula import degree_formula  # noqa: E402

#: the curves of the degree table: (name, polynomial)
CURVES = [
    ("circle", "x^2 + y^2 - 1"),
    ("ellipse", "x^2 + 4*y^2 - 4"),
    ("hyperbola", "x^2 - 4*y^2 - 4"),
    ("hyperbola xy = 1", "x*y - 1"),
    ("parabola", "y^2 - 2*x"),
    ("two parallel lines", "y^2 - 1"),
    ("two crossing lines", "x^2 - 4*y^2"),
    ("strophoid (nodal cubic)", "y^2 - x^2 - x^3"),
    ("folium of Descartes (nodal cubic)", "x^3 + y^3 - 3*x*y"),
    ("cuspidal cubic", "y^2 - x^3"),
    ("smooth cubic", "y^2 - x^3 - x - 1"),
    ("three concurrent lines (Remark 4.2.17)", "x^2*y - y^3"),
    ("cardioid", "(x^2 + y^2 - 2*x)^2 - 4*(x^2 + y^2)"),
    ("lemniscate of Bernoulli", "(x^2 + y^2)^2 - 2*(x^2 - y^2)"),
]


def random_curves(count: int, degree: int, seed: int) -> list[tuple[str, str]]:
    rng = random.Random(seed)
    out = []
    for k in range(count):
        terms = [f"({rng.randint(-5, 5)})*x^{i}*y^{j}" for i in range(degree + 1) for j in range(degree + 1 - i)]
        out.append((f"random degree {degree} #{k}", " + ".join(terms)))
    return out


def table_rows(curves, full: bool = True) -> list[dict]:
    rows = []
    for name, f in curves:
        df = degree_formula(f)
        t0 = time.perf_counter()
        if full:
            o = offset(f)
            elim, deg_r, secs = o.degree_uv, o.degrees["R"], time.perf_counter() - t0
        else:
            line = offset_degrees_on_line(f)
            elim, deg_r, secs = line["degree_uv"], line["degree_R"], line["seconds"]
        rows.append({"name": name, "curve": df.curve, "m": df.m, "l": df.l, "sum_infinity": df.sum_infinity,
                     "sum_singular": df.sum_singular, "infinity_correction": df.infinity_correction,
                     "singular_correction": df.singular_correction, "formula": df.degree,
                     "elimination": elim, "normal_feet": df.normal_feet, "degree_R": deg_r,
                     "seconds": round(secs, 2), "method": "full" if full else "line"})
    return rows


def markdown(rows) -> str:
    head = ("| curve | f | m | l | 2lΣ∞ | 2Σ_S | formula | elimination | feet (m²−Σ∞−Σ_S) | deg_R o | time (s) |\n"
            "|---|---|---|---|---|---|---|---|---|---|---|\n")
    body = "".join(
        f"| {r['name']} | `{r['curve']}` | {r['m']} | {r['l']} | {r['infinity_correction']} | "
        f"{r['singular_correction']} | {r['formula']} | {r['elimination']}"
        f"{'' if r['formula'] == r['elimination'] else ' **≠**'} | {r['normal_feet']} | {r['degree_R']} | "
        f"{r['seconds']}{'' if r['method'] == 'full' else ' (line)'} |\n" for r in rows)
    return head + body


def strophoid_figure(path: Path, Rs=(0.04, 0.25, 1.0)) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    o = offset("y^2 - x^2 - x^3")
    terms = [((int(k[0]), int(k[1]), int(k[2])), float(int(c))) for k, c in o.polynomial.to_dict().items()]
    xs = np.linspace(-2.6, 2.2, 900)
    ys = np.linspace(-2.4, 2.4, 900)
    U, V = np.meshgrid(xs, ys)
    fig, ax = plt.subplots(figsize=(7, 7))
    ax.contour(U, V, V**2 - U**2 - U**3, levels=[0], colors="black", linewidths=2.0)
    colours = ["tab:blue", "tab:orange", "tab:green", "tab:red"]
    for R, col in zip(Rs, colours):
        Z = np.zeros_like(U)
        for (i, j, k), c in terms:
            Z += c * U**i * V**j * R**k
        # scale-free sign changes: divide by a positive weight so that contour finds the zero set
        ax.contour(U, V, Z / (1 + U**2 + V**2) ** 5, levels=[0], colors=col, linewidths=1.0)
        th = np.linspace(0, 2 * np.pi, 200)
        ax.plot(np.sqrt(R) * np.cos(th), np.sqrt(R) * np.sin(th), ls="--", lw=0.8, color=col)
        ax.plot([], [], color=col, label=f"generalised offset, R = {R:g} (distance {np.sqrt(R):.2g})")
    ax.plot([], [], color="black", lw=2, label="strophoid y² = x² + x³")
    ax.plot([], [], color="grey", ls="--", lw=0.8, label="extraneous circle of the node (rejected)")
    ax.set_aspect("equal")
    ax.set_xlim(xs[0], xs[-1])
    ax.set_ylim(ys[0], ys[-1])
    ax.legend(loc="lower right", fontsize=8)
    ax.set_title("The strophoid and its generalised offset (cf. thesis Fig. 4.1.2)")
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--table", action="store_true", help="print the Theorem 4.2.18 table (Markdown)")
    ap.add_argument("--random", type=int, default=3, help="random curves of degree 2 and 3 in the table")
    ap.add_argument("--quartic", type=int, default=1, help="random quartics (line restriction, ~35 s each)")
    args = ap.parse_args(argv)
    if args.table:
        rows = table_rows(CURVES)
        rows += table_rows(random_curves(args.random, 2, 1) + random_curves(args.random, 3, 2), full=False)
        rows += table_rows(random_curves(args.quartic, 4, 3), full=False)
        print(markdown(rows))
        return 0
    out = ROOT / "docs" / "images" / "strophoid_offsets.png"
    strophoid_figure(out)
    print(f"wrote {out.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
