"""Pictures of docs/segments.md, written to docs/images/.

* ``segments_voronoi.png`` -- the Voronoi diagram of a few segments and points (thesis §2.2).
* ``medial_axis_shapes.png`` -- the medial axes of an L-shape and of a square with a square hole
  (thesis §2.3), with the largest inscribed circle.
* ``fig_2_3_1.png`` -- thesis Fig. 2.3.1: the medial axis of the ellipse x²/4 + y² < 1 (the segment
  |x| <= 3/2, y = 0, with a few maximal discs) and of its inscribed 15-gon and 60-gon
  (``cv.medial_axis``): one branch per convex corner (dotted where the certificate did not prove
  the edge).  The part of each polygon's axis whose two nearest boundary points are at least
  b = 1 apart (the λ-medial axis) is drawn thick and red.

Usage: ``python docs/make_segment_figures.py [--only NAME]`` (about 20 s, most of it the 60-gon).
"""
from __future__ import annotations

import argparse
import math
import os
import sys
import time
from fractions import Fraction
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
A, B = 2, 1                                   # the ellipse of Fig. 2.3.1


def ellipse_polygon(n: int, a=A, b=B, den=1000):
    """n vertices exactly on the ellipse: (a (1 - t²)/(1 + t²), b 2t/(1 + t²)), t a rational close
    to tan(θ_k/2), θ_k = 2πk/n (the same polygons as tests/test_fig_2_3_1.py)."""
    pts = []
    for k in range(n):
        th = 2 * math.pi * k / n
        if abs(th - math.pi) < 1e-12:
            pts.append((Fraction(-a), Fraction(0)))
            continue
        t = Fraction(math.tan(th / 2)).limit_denominator(den)
        pts.append((a * (1 - t * t) / (1 + t * t), b * 2 * t / (1 + t * t)))
    return pts


def segments_voronoi(path: Path) -> None:
    pieces = [cv.Segment((0, 0), (4, 0)), cv.Segment((4, 0), (4, 3)), cv.Segment((0, 2), (2, 3)),
              cv.Segment((1, 5), (3, 4)), (1, 1), (3, 2)]
    d = cv.voronoi(pieces)
    d.plot(path, window=(-2, 6, -2, 6),
           title=f"points and segments: {len(d.sites)} elementary sites, certified={d.certified}")


def medial_axis_shapes(path: Path) -> None:
    fig, axes = plt.subplots(1, 2, figsize=(11, 5.2))
    L = [(0, 0), (4, 0), (4, 1), (1, 1), (1, 3), (0, 3)]
    m = cv.medial_axis(L)
    m.plot(axes[0], title=f"L-shape: {len(m.edges)} edges, certified={m.certified}")
    outer, hole = [(0, 0), (6, 0), (6, 6), (0, 6)], [(2, 2), (4, 2), (4, 4), (2, 4)]
    m = cv.medial_axis(outer, [hole])
    m.plot(axes[1], title=f"square with a hole: {len(m.edges)} edges, certified={m.certified}")
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)


def _chord_parts(m, lam: float):
    """The pieces of the edges' polylines whose two nearest boundary points are >= lam apart."""
    E = m.diagram.elementary
    out = []
    for e in m.edges:
        P = np.asarray(e.polyline, float)
        F = []
        for i in e.sites:
            a, b = E.A[i], E.B[i]
            d = b - a
            L2 = float(d @ d)
            t = np.zeros(len(P)) if L2 == 0 else np.clip((P - a) @ d / L2, 0, 1)
            F.append(a + t[:, None] * d)
        keep = np.hypot(*(F[0] - F[1]).T) >= lam
        if keep.sum() >= 2:
            out.append(P[keep])
    return out


def fig_2_3_1(path: Path) -> None:
    fig, axes = plt.subplots(1, 3, figsize=(15, 3.6))
    s = np.linspace(0, 2 * np.pi, 400)
    X = (A * A - B * B) / A
    ax = axes[0]
    ax.plot(A * np.cos(s), B * np.sin(s), "k-", lw=1.4)
    ax.plot([-X, X], [0, 0], "-", color="tab:blue", lw=2)
    for u in (0.0, 0.35, 0.7, 1.0):              # maximal discs centred at x = X u (radius from the normal)
        th = math.acos(u)
        r = math.hypot(A * math.cos(th) - X * u, B * math.sin(th))
        ax.plot(X * u + r * np.cos(s), r * np.sin(s), "-", color="tab:green", lw=0.6)
    ax.set_title("ellipse x²/4 + y² < 1: medial axis |x| ≤ 3/2 (2 ends)", fontsize=9)
    ax.set_aspect("equal")
    for ax, n in zip(axes[1:], (15, 60)):
        t0 = time.perf_counter()
        m = cv.medial_axis(ellipse_polygon(n))
        leaves = sum(1 for v in m.vertices if v.radius == 0)
        m.plot(ax, inscribed=False, title=f"inscribed {n}-gon: {leaves} leaves, certified={m.certified} "
                                          f"({time.perf_counter() - t0:.0f} s)")
        for P in _chord_parts(m, B):
            ax.plot(P[:, 0], P[:, 1], "-", color="tab:red", lw=2.2)
        ax.plot(A * np.cos(s), B * np.sin(s), "-", color="0.7", lw=0.6, zorder=0)
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)


FIGURES = {"segments_voronoi": segments_voronoi, "medial_axis_shapes": medial_axis_shapes, "fig_2_3_1": fig_2_3_1}


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--only", choices=sorted(FIGURES), help="draw only this picture")
    args = p.parse_args(argv)
    OUT.mkdir(exist_ok=True)
    for name, draw in FIGURES.items():
        if args.only and name != args.only:
            continue
        t0 = time.perf_counter()
        draw(OUT / f"{name}.png")
        print(f"{name}.png ({time.perf_counter() - t0:.1f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
