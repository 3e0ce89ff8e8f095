"""Pictures of a Voronoi diagram of curved sites (like thesis Figs. 1.0.5–1.0.7).

Drawn: the sites (black), the curved Voronoi edges as their polylines (blue; dotted where not
certified), the Voronoi vertices (red dots), the Delaunay graph (grey, dashed, between site
anchors: centres of bounded sites, a point of the site for unbounded ones) and, optionally, the
empty circles of the vertices (green, dotted).  Uses matplotlib with the Agg backend when saving.

Public API: :func:`plot_diagram`.
"""
from __future__ import annotations

import math

import numpy as np

from .conic_geometry import site_geometry

__all__ = ["plot_diagram", "COLOURS"]

#: the colours of the picture, named in its legend
COLOURS = {"site": "black", "edge": "tab:blue", "vertex": "tab:red", "delaunay": "grey", "empty": "tab:green"}


def _window(diagram, geoms, pad=0.15):
    boxes = np.array([g.bounding_box() for g in geoms if g.bounded] or [[-1.0, -1.0, 1.0, 1.0]])
    x0, y0, x1, y1 = boxes[:, 0].min(), boxes[:, 1].min(), boxes[:, 2].max(), boxes[:, 3].max()
    w = max(x1 - x0, y1 - y0, 1e-9)
    for v in diagram.vertices:
        if v.radius < 2 * w:
            x0, x1, y0, y1 = min(x0, v.x), max(x1, v.x), min(y0, v.y), max(y1, v.y)
    w = max(x1 - x0, y1 - y0, 1e-9)
    cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
    h = w * (0.5 + pad)
    return cx - h, cy - h, cx + h, cy + h


def _anchor(g, window):
    if g.kind == "point":
        return g.x0, g.y0
    if g.bounded:
        b = g.bounding_box()
        return (b[0] + b[2]) / 2, (b[1] + b[3]) / 2
    P = g.samples((window[2] - window[0]) / 50, window)
    m = len(P) // 2
    return float(P[m, 0]), float(P[m, 1])


def plot_diagram(diagram, path_or_ax=None, *, empty_circles: bool = False, title: str | None = None,
                 dpi: int = 120, window=None):
    """Draw ``diagram`` (a :class:`runtime.voronoi.structure.Diagram`).

    ``path_or_ax``: a file path (PNG/SVG/PDF, saved), a matplotlib Axes (drawn on), or None.
    Returns the matplotlib Figure."""
    import matplotlib

    if path_or_ax is None or isinstance(path_or_ax, (str, bytes)) or hasattr(path_or_ax, "__fspath__"):
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    geoms = [site_geometry(s) for s in diagram.sites]
    win = window or _window(diagram, geoms)
    if path_or_ax is not None and hasattr(path_or_ax, "plot"):
        ax = path_or_ax
        fig = ax.figure
    else:
        fig, ax = plt.subplots(figsize=(8, 8))
    span = win[2] - win[0]
    for i, g in enumerate(geoms):
        if g.kind == "point":
            ax.plot([g.x0], [g.y0], "o", color=COLOURS["site"], ms=3, zorder=4)
        else:
            P = g.samples(span / 400, win)
            if g.bounded:
                P = np.vstack([P, P[:1]])
                ax.plot(P[:, 0], P[:, 1], "-", color=COLOURS["site"], lw=1.2, zorder=4)
            else:
                # unbounded sites come as (possibly several) runs of samples: break at big jumps
                jumps = np.nonzero(np.hypot(*np.diff(P, axis=0).T) > span / 20)[0] + 1
                for part in np.split(P, jumps):
                    ax.plot(part[:, 0], part[:, 1], "-", color=COLOURS["site"], lw=1.2, zorder=4)
        if len(geoms) <= 60:
            ax.annotate(str(i), _anchor(g, win), fontsize=7, color=COLOURS["site"], ha="center", va="center")
    anchors = [_anchor(g, win) for g in geoms]
    for i, j in diagram.delaunay_edges():
        (xa, ya), (xb, yb) = anchors[i], anchors[j]
        ax.plot([xa, xb], [ya, yb], "--", color=COLOURS["delaunay"], lw=0.7, zorder=1)
    for e in diagram.edges:
        P = np.asarray(e.polyline, float)
        ax.plot(P[:, 0], P[:, 1], "-" if e.certified else ":", color=COLOURS["edge"], lw=1.4, zorder=3)
    if diagram.vertices:
        V = np.array([[v.x, v.y] for v in diagram.vertices])
        ax.plot(V[:, 0], V[:, 1], "o", color=COLOURS["vertex"], ms=3, zorder=5)
    if empty_circles:
        t = np.linspace(0, 2 * math.pi, 200)
        for v in diagram.vertices:
            ax.plot(v.x + v.radius * np.cos(t), v.y + v.radius * np.sin(t), ":", color=COLOURS["empty"], lw=0.6)
    ax.set_xlim(win[0], win[2])
    ax.set_ylim(win[1], win[3])
    ax.set_aspect("equal")
    handles = [Line2D([], [], color=COLOURS["site"], lw=1.2, label="sites (black)"),
               Line2D([], [], color=COLOURS["edge"], lw=1.4, label="Voronoi edges (blue; dotted: not certified)"),
               Line2D([], [], color=COLOURS["vertex"], marker="o", ls="", ms=4, label="Voronoi vertices (red)"),
               Line2D([], [], color=COLOURS["delaunay"], ls="--", lw=0.7, label="Delaunay graph (grey, dashed)")]
    if empty_circles:
        handles.append(Line2D([], [], color=COLOURS["empty"], ls=":", label="empty circles (green, dotted)"))
    ax.legend(handles=handles, loc="upper right", fontsize=7)
    status = "certified" if diagram.certified else f"not certified ({len(diagram.problems)} problems)"
    ax.set_title(title or f"Voronoi diagram of {len(diagram.sites)} sites: {len(diagram.vertices)} vertices, "
                 f"{len(diagram.edges)} edges, {status}", fontsize=9)
    if path_or_ax is not None and not hasattr(path_or_ax, "plot"):
        fig.savefig(path_or_ax, dpi=dpi, bbox_inches="tight")
        plt.close(fig)
    return fig
