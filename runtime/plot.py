"""Pictures of the Voronoi diagram and Delaunay graph of conics (like thesis Fig. 1.0.5-1.0.7).

Drawn: the sites (conics, circles, points), the certified Voronoi vertices with their empty
circles (dashed), the Delaunay edges (straight segments between the site centres, dotted
when supported only by numeric evidence) and the Voronoi edges.  The Voronoi edges are
*traced numerically*: for every Delaunay edge (i, j) the zero level set of d_i − d_j is
contoured on a grid, restricted to the points where no other site is closer (float
distances of :func:`runtime.diagram.distance_field`).  The picture is an illustration; the
certified content is in the vertices and edges of the :class:`~runtime.diagram.DelaunayGraph`.

Uses matplotlib with the non-interactive Agg backend.
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["plot_diagram"]


def _window(G, pad: float = 0.25):
    from .diagram import scene_box

    x0, x1, y0, y1 = scene_box([G.sites[i] for i in sorted(G.sites)])
    for v in G.vertices:  # include vertices whose empty circle is not huge
        if v.radius < 2 * max(x1 - x0, y1 - y0, 1e-9):
            x0, x1, y0, y1 = min(x0, v.x), max(x1, v.x), min(y0, v.y), max(y1, v.y)
    w = max(x1 - x0, y1 - y0, 1e-9)
    cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
    h = w * (0.5 + pad)
    return cx - h, cx + h, cy - h, cy + h


def plot_diagram(G, path: str | None = None, *, grid: int = 500, show_circles: bool = True,
                 window=None, title: str | None = None, dpi: int = 120):
    """Draw the diagram of ``G`` (a DelaunayGraph); save to ``path`` (PNG) if given.

    Returns the matplotlib Figure.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Circle as CirclePatch

    from .diagram import site_samples

    ids = sorted(G.sites)
    x0, x1, y0, y1 = window or _window(G)
    fig, ax = plt.subplots(figsize=(8, 8))
    # --- Voronoi edges, traced numerically on a grid
    xs = np.linspace(x0, x1, grid)
    ys = np.linspace(y0, y1, grid)
    X, Y = np.meshgrid(xs, ys)
    if len(ids) >= 2:
        D = G._dist_matrix(ids, X.ravel(), Y.ravel()).reshape(len(ids), grid, grid)
        pos = {i: n for n, i in enumerate(ids)}
        for (i, j), e in sorted(G.edge_info().items()):
            a, b = pos[i], pos[j]
            F = D[a] - D[b]
            if len(ids) > 2:
                rest = np.delete(D, [a, b], axis=0).min(axis=0)
                F = np.where(rest < np.minimum(D[a], D[b]), np.nan, F)
            if np.all(np.isnan(F)):
                continue
            ax.contour(X, Y, F, levels=[0.0], colors="tab:blue", linewidths=1.4)
    # --- sites
    diam = math.hypot(x1 - x0, y1 - y0)
    for i in ids:
        s = G.sites[i]
        if s.kind == "point":
            cx, cy, _ = s.fcircle
            ax.plot([cx], [cy], "ko", ms=4)
        elif s.kind == "circle":
            cx, cy, r = s.fcircle
            ax.add_patch(CirclePatch((cx, cy), r, fill=False, ec="black", lw=1.6))
        else:
            px, py, _, _ = site_samples(s, 800, diam)
            if s.kind == "hyperbola":
                h = len(px) // 2
                ax.plot(px[:h], py[:h], "k-", lw=1.6)
                ax.plot(px[h:], py[h:], "k-", lw=1.6)
            elif s.kind == "ellipse":
                ax.plot(np.append(px, px[0]), np.append(py, py[0]), "k-", lw=1.6)
            else:
                ax.plot(px, py, "k-", lw=1.6)
        cx, cy = s.centre()
        ax.annotate(str(i), (cx, cy), fontsize=9, color="dimgray", ha="center", va="center")
    # --- Delaunay edges
    for (i, j), e in sorted(G.edge_info().items()):
        (ax_, ay_), (bx_, by_) = G.sites[i].centre(), G.sites[j].centre()
        ax.plot([ax_, bx_], [ay_, by_], color="tab:green", lw=1.0, alpha=0.8,
                ls="-" if e["certified"] else ":")
    # --- Voronoi vertices and empty circles
    for v in G.vertices:
        if show_circles:
            ax.add_patch(CirclePatch((v.x, v.y), v.radius, fill=False, ec="tab:red", lw=0.6, ls="--", alpha=0.5))
        ax.plot([v.x], [v.y], "o", color="tab:red" if v.certified else "orange", ms=4)
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_aspect("equal")
    ax.set_title(title or (f"{len(ids)} sites, {len(G.edges())} Delaunay edges (green), "
                           f"{len(G.vertices)} Voronoi vertices (red: certified, orange: not), certified={G.certified}"), fontsize=9)
    fig.tight_layout()
    if path is not None:
        fig.savefig(path, dpi=dpi)
        plt.close(fig)
    return fig
