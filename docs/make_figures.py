"""Pictures of the user guide, written to docs/images/ (``invoke docs`` runs this script).

* ``fig_5_5_1.png`` -- the four ellipses of thesis Fig. 5.5.1 (rigid-motion version,
  :func:`runtime.predicates.locator.demo_configuration`), the true Voronoi vertices of every triple and
  their empty circles (thesis Def. 5.2.1), coloured by whether the remaining site conflicts.
* ``offsets.png`` -- one conic of each family with its generalised offsets (thesis ch. 4,
  App. B): the zero set of the offset polynomial o(x, y, R) at a few squared distances R = r².
* ``diagram_ellipses.png`` -- the Voronoi diagram of a few ellipses with its curved edges, when
  :func:`curvedvoronoi.voronoi` is available (skipped with a message otherwise).

Usage: ``python docs/make_figures.py [--only NAME]``.
"""
from __future__ import annotations

import argparse
import math
import os
import sys
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import curvedvoronoi as cv  # noqa: E402

OUT = HERE / "images"
SITE_COLOURS = ["tab:blue", "tab:green", "tab:purple", "tab:brown", "tab:olive", "tab:cyan", "tab:pink"]


def _draw_site(ax, site, colour, label, n=400, extent=None):
    from curvedvoronoi.runtime.predicates.circles import Circle

    if isinstance(site, Circle):
        if site.r2 == 0:
            ax.plot([float(site.cx)], [float(site.cy)], "o", color=colour, ms=4, label=label)
            return
        t = np.linspace(0, 2 * np.pi, n)
        ax.plot(float(site.cx) + site.rho * np.cos(t), float(site.cy) + site.rho * np.sin(t), color=colour,
                lw=2, label=label)
        return
    pts = np.array(site.sample(n, extent=extent))
    if site.kind == "hyperbola":        # two branches, drawn separately
        h = len(pts) // 2
        ax.plot(pts[:h, 0], pts[:h, 1], color=colour, lw=2, label=label)
        ax.plot(pts[h:, 0], pts[h:, 1], color=colour, lw=2)
    elif site.kind in ("ellipse", "circle"):
        pts = np.vstack([pts, pts[:1]])
        ax.plot(pts[:, 0], pts[:, 1], color=colour, lw=2, label=label)
    else:
        ax.plot(pts[:, 0], pts[:, 1], color=colour, lw=2, label=label)


def fig_5_5_1(path: Path) -> str:
    """All four triples of the demo configuration: vertices, empty circles, conflicts."""
    from itertools import combinations

    from curvedvoronoi.runtime.predicates.locator import demo_configuration

    sites = demo_configuration()
    fig, ax = plt.subplots(figsize=(7.5, 7))
    for i, s in enumerate(sites):
        _draw_site(ax, s, SITE_COLOURS[i], f"site {i} (C{i + 1})")
    shown = {"kept": False, "conflict": False}
    lines = []
    for tri in combinations(range(4), 3):
        other = ({0, 1, 2, 3} - set(tri)).pop()
        res = cv.locate_conflicts(*(sites[i] for i in tri), sites[other])
        for v in res.vertices:
            conflict = bool(v.in_conflict)
            colour = "tab:red" if conflict else "black"
            key = "conflict" if conflict else "kept"
            label = None
            if not shown[key]:
                label = ("vertex entered by the remaining site (conflict)" if conflict
                         else "vertex whose empty circle the remaining site does not enter")
                shown[key] = True
            ax.add_patch(plt.Circle((v.x, v.y), v.radius, fill=False, ls="--", lw=1, color=colour))
            ax.plot([v.x], [v.y], "o", color=colour, ms=6, label=label)
            ax.annotate(f"{tri}", (v.x, v.y), textcoords="offset points", xytext=(5, 5), fontsize=8, color=colour)
            lines.append(f"triple {tri} + site {other}: vertex ({v.x:.4f}, {v.y:.4f}) radius {v.radius:.4f} "
                         f"conflict={conflict} certified={res.certified}")
    ax.plot([], [], ls="--", color="grey", label="empty circle tangent to the triple (dashed, colour of its vertex)")
    ax.set_aspect("equal")
    ax.set_title("Thesis Fig. 5.5.1 configuration: Voronoi vertices of each triple\n"
                 "red = in conflict with the fourth site, black = not")
    ax.legend(loc="lower right", fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return "\n".join(lines)


def fig_offsets(path: Path) -> str:
    """Generalised offsets o(x, y, R) = 0 of one conic per family at R = r², r in RADII."""
    from curvedvoronoi.runtime.algebra.polyalg import CanonicalOffset

    radii = (0.25, 0.5, 1.0)
    conics = [("ellipse  x²/4 + y² = 1", cv.Conic.ellipse(axes=(2, 1))),
              ("hyperbola  x² − y² = 1", cv.Conic.hyperbola(axes=(1, 1))),
              ("parabola  y² = 2x", cv.Conic.parabola(p=1)),
              ("circle  x² + y² = 1", cv.Conic.circle(radius=1))]
    fig, axes = plt.subplots(2, 2, figsize=(9, 9))
    colours = ["tab:orange", "tab:red", "tab:purple"]
    for ax, (title, conic) in zip(axes.flat, conics):
        off = CanonicalOffset(conic)
        xs = np.linspace(-4, 4, 401)
        X, Y = np.meshgrid(xs, xs)
        for r, col in zip(radii, colours):
            val, _, absval = off.eval_grad(X.ravel(), Y.ravel(), np.full(X.size, r * r))
            Z = (val / np.maximum(absval, 1e-300)).reshape(X.shape)
            ax.contour(X, Y, Z, levels=[0], colors=[col], linewidths=1.2)
            ax.plot([], [], color=col, label=f"offset at distance r = {r}")
        _draw_site(ax, conic, "tab:blue", "the conic", extent=4)
        ax.set_xlim(-4, 4)
        ax.set_ylim(-4, 4)
        ax.set_aspect("equal")
        ax.set_title(title, fontsize=10)
        ax.grid(alpha=0.3)
        ax.legend(loc="upper left", fontsize=7)
    fig.suptitle("Generalised offsets (thesis ch. 4, App. B): zero sets of o(x, y, R), R = r²")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return f"offsets at r = {radii}"


def diagram_sites():
    """The sites of the diagram picture (also used by examples/voronoi_of_ellipses.py)."""
    return [cv.Conic.ellipse(centre=(0, 0), axes=(2, 1)),
            cv.Conic.ellipse(centre=(6, 1), axes=(Fraction(3, 2), 1), rotation=("3/5", "4/5")),
            cv.Conic.ellipse(centre=(2, 6), axes=(2, Fraction(2, 3)), rotation=("5/13", "12/13")),
            cv.Conic.ellipse(centre=(7, 7), axes=(1, Fraction(1, 2)), rotation=("8/17", "15/17")),
            cv.Circle.from_radius(-4, 5, 1)]


def fig_diagram(path: Path) -> str:
    try:
        voronoi = cv.voronoi
    except (ImportError, AttributeError) as exc:
        return f"skipped: curvedvoronoi.voronoi is not available ({exc})"
    sites = diagram_sites()
    D = voronoi(sites)
    fig, ax = plt.subplots(figsize=(8, 7.5))
    for i, s in enumerate(sites):
        _draw_site(ax, s, SITE_COLOURS[i % len(SITE_COLOURS)], f"site {i}")
    first = True
    for e in D.edges:
        P = np.asarray(e.polyline, dtype=float)
        if len(P):
            ax.plot(P[:, 0], P[:, 1], color="tab:orange", lw=1.5,
                    label="Voronoi edge (curved, polyline)" if first else None)
            first = False
    for k, v in enumerate(D.vertices):
        ax.plot([v.x], [v.y], "o", color="black", ms=4, label="Voronoi vertex" if k == 0 else None)
    ax.set_xlim(-10, 14)
    ax.set_ylim(-6, 13)
    ax.set_aspect("equal")
    ax.set_title(f"Voronoi diagram of four ellipses and a circle ({len(D.vertices)} vertices, "
                 f"{len(D.edges)} edges, certified={D.certified})", fontsize=10)
    ax.legend(loc="lower right", fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return f"{len(D.vertices)} vertices, {len(D.edges)} edges, certified={D.certified}"


from fractions import Fraction  # noqa: E402  (used by diagram_sites)

FIGURES = {"fig_5_5_1": fig_5_5_1, "offsets": fig_offsets, "diagram_ellipses": fig_diagram}


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--only", choices=sorted(FIGURES), help="make one figure")
    p.add_argument("--out", default=str(OUT), help="output folder (default docs/images)")
    a = p.parse_args(argv)
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    for name, make in FIGURES.items():
        if a.only and name != a.only:
            continue
        t0 = time.perf_counter()
        info = make(out / f"{name}.png")
        print(f"{name}.png ({time.perf_counter() - t0:.1f} s): {info}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
