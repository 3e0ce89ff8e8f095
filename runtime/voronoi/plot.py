"""Pictures of a Voronoi diagram of curved sites (like thesis Figs. 1.0.5–1.0.7).

Drawn: the sites (black), the curved Voronoi edges as their polylines (blue; dotted where not
certified), the Voronoi vertices (red dots), the Delaunay graph (grey, dashed, between site
anchors: centres of bounded sites, the vertex of a parabola or hyperbola branch) and, optionally,
the empty circles of the vertices (green, dotted).  Uses matplotlib with the Agg backend when saving.

The window is ``(xmin, xmax, ymin, ymax)`` (matplotlib's ``axis`` order).  By default it fits
the sites: the boxes of bounded sites, the points, and for an unbounded site (parabola, hyperbola)
its vertices and foci, plus the Voronoi vertices whose empty circle is not larger than the scene.
Everything is clipped to the window (polylines by Liang–Barsky clipping, before matplotlib sees
them, so far coordinates never reach the renderer); a vertex outside the window is drawn as a red
arrow on the border pointing towards it.

Public API: :func:`plot_diagram`, :func:`fit_window`.
"""
from __future__ import annotations

import math

import numpy as np

from .conic_geometry import site_geometry

__all__ = ["plot_diagram", "fit_window", "COLOURS"]

#: the colours of the picture, named in its legend
COLOURS = {"site": "black", "edge": "tab:blue", "vertex": "tab:red", "delaunay": "grey", "empty": "tab:green"}


class _SegmentShape:
    """What the picture needs of a segment site (thesis §2.2: drawn as the closed segment)."""

    kind = "segment"
    bounded = True

    def __init__(self, seg):
        (self.x0, self.y0), (self.x1, self.y1) = seg.float_endpoints()

    def bounding_box(self):
        return min(self.x0, self.x1), min(self.y0, self.y1), max(self.x0, self.x1), max(self.y0, self.y1)

    def samples(self, spacing, window):
        return np.array([[self.x0, self.y0], [self.x1, self.y1]])


class _ArcShape(_SegmentShape):
    """A circular arc site, drawn counter-clockwise from its start to its end."""

    def __init__(self, arc):
        (self.cx, self.cy), self.rho, (self.x0, self.y0), (self.x1, self.y1) = arc.float_data()
        a0 = math.atan2(self.y0 - self.cy, self.x0 - self.cx)
        span = (math.atan2(self.y1 - self.cy, self.x1 - self.cx) - a0) % (2 * math.pi) or 2 * math.pi
        t = a0 + np.linspace(0, span, 200)
        self.P = np.column_stack([self.cx + self.rho * np.cos(t), self.cy + self.rho * np.sin(t)])

    def bounding_box(self):
        return float(self.P[:, 0].min()), float(self.P[:, 1].min()), float(self.P[:, 0].max()), float(self.P[:, 1].max())

    def samples(self, spacing, window):
        return np.vstack([self.P, self.P[::-1]])


def _shape(site):
    from ..sites.arc import Arc
    from ..sites.segment import Segment

    if isinstance(site, Arc):
        return _ArcShape(site)
    return _SegmentShape(site) if isinstance(site, Segment) else site_geometry(site)


def _key_points(g) -> list[tuple[float, float]]:
    """Points that stand for a site in the window: a point, the corners of a bounded site's box,
    the vertices and foci of a parabola (Y² = 2pX) or hyperbola (X²/a² − Y²/b² = 1)."""
    if g.kind == "point":
        return [(g.x0, g.y0)]
    if g.bounded:
        b = g.bounding_box()
        return [(b[0], b[1]), (b[2], b[3])]
    if g.kind == "parabola":
        X, Y = np.array([0.0, g.p / 2]), np.array([0.0, 0.0])
    else:                                              # hyperbola: both branch vertices and foci
        f = math.hypot(g.a, g.b)
        X, Y = np.array([g.a, -g.a, f, -f]), np.zeros(4)
    return [tuple(map(float, p)) for p in g.from_canonical(X, Y)]


def _internal(win):
    """(xmin, xmax, ymin, ymax) -> (xmin, ymin, xmax, ymax), the order of the site samplers."""
    return win[0], win[2], win[1], win[3]


def fit_window(diagram, geoms=None, pad: float = 0.15) -> tuple[float, float, float, float]:
    """A square window ``(xmin, xmax, ymin, ymax)`` around the sites (see the module docstring)."""
    if geoms is None:
        geoms = [_shape(s) for s in diagram.sites]
    pts = np.array([p for g in geoms for p in _key_points(g)] or [(-1.0, -1.0), (1.0, 1.0)], dtype=float)
    pts = pts[np.isfinite(pts).all(axis=1)]
    if not len(pts):
        pts = np.array([(-1.0, -1.0), (1.0, 1.0)])
    x0, y0 = pts.min(axis=0)
    x1, y1 = pts.max(axis=0)
    w = max(x1 - x0, y1 - y0)
    for v in diagram.vertices:
        if all(math.isfinite(t) for t in (v.x, v.y, v.radius)) and v.radius < 2 * w:
            x0, x1, y0, y1 = min(x0, v.x), max(x1, v.x), min(y0, v.y), max(y1, v.y)
    w = max(x1 - x0, y1 - y0)
    cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
    if not w > 1e-12 * max(1.0, abs(cx), abs(cy)):       # one point: a unit window around it
        w = max(1.0, 1e-6 * max(abs(cx), abs(cy)))
    h = w * (0.5 + pad)
    return cx - h, cx + h, cy - h, cy + h


def clip_polyline(P, win) -> np.ndarray:
    """The parts of the polyline ``P`` (n×2) inside ``win = (xmin, xmax, ymin, ymax)``, as one
    array with rows of NaN between the pieces (matplotlib breaks lines there); Liang–Barsky
    clipping of each segment."""
    P = np.asarray(P, dtype=float).reshape(-1, 2)
    P = P[np.isfinite(P).all(axis=1)]
    if len(P) == 0:
        return np.empty((0, 2))
    if len(P) == 1:
        inside = win[0] <= P[0, 0] <= win[1] and win[2] <= P[0, 1] <= win[3]
        return P if inside else np.empty((0, 2))
    A, B = P[:-1], P[1:]
    D = B - A
    t0, t1 = np.zeros(len(A)), np.ones(len(A))
    with np.errstate(divide="ignore", invalid="ignore"):
        for k, lo, hi in ((0, win[0], win[1]), (1, win[2], win[3])):
            d, a = D[:, k], A[:, k]
            for p, q in ((-d, a - lo), (d, hi - a)):
                r = q / p
                par = p == 0
                t1 = np.where(par & (q < 0), -1.0, t1)               # parallel and outside
                t0 = np.where(~par & (p < 0), np.maximum(t0, r), t0)
                t1 = np.where(~par & (p > 0), np.minimum(t1, r), t1)
    keep = t0 <= t1
    out = []
    for i in np.nonzero(keep)[0]:
        joined = i > 0 and keep[i - 1] and t1[i - 1] == 1.0 and t0[i] == 0.0   # the shared point is inside
        if not joined:
            if out:
                out.append([np.nan, np.nan])
            out.append(A[i] + t0[i] * D[i])
        out.append(A[i] + t1[i] * D[i])
    return np.array(out, dtype=float).reshape(-1, 2)


def _site_curve(g, win, span):
    """Samples of a curved site within the window (a grown copy, for clipping), NaN between runs."""
    grown = (win[0] - 0.05 * span, win[1] + 0.05 * span, win[2] - 0.05 * span, win[3] + 0.05 * span)
    spacing = span / 400
    if g.bounded:
        b = g.bounding_box()
        spacing = max(spacing, max(b[2] - b[0], b[3] - b[1]) / 20000)   # a huge ellipse: at most ~6e4 points
        P = g.samples(spacing, None)
        return clip_polyline(np.vstack([P, P[:1]]), grown)
    iw = _internal(grown)
    corners = np.array([[iw[0], iw[1]], [iw[0], iw[3]], [iw[2], iw[1]], [iw[2], iw[3]]])
    X, Y = g.to_canonical(corners)
    Rw = float(np.max(np.hypot(X, Y)))
    spacing = max(spacing, Rw / 20000)                  # a window far from the site: a coarser curve
    P = g.samples(spacing, iw)
    if len(P) == 0:
        return np.empty((0, 2))
    # the samples come as (possibly several) runs: break at big jumps
    jumps = np.nonzero(np.hypot(*np.diff(P, axis=0).T) > 3 * spacing)[0] + 1
    parts = [clip_polyline(part, grown) for part in np.split(P, jumps)]
    parts = [p for p in parts if len(p)]
    if not parts:
        return np.empty((0, 2))
    sep = np.array([[np.nan, np.nan]])
    return np.vstack([x for p in parts for x in (p, sep)][:-1])


def _anchor(g, win):
    """Where a site's label and Delaunay edges attach: a point, a bounded site's box centre, the
    vertex of a parabola, or the branch vertex of a hyperbola nearer the window's centre."""
    if g.kind == "point":
        return g.x0, g.y0
    if g.bounded:
        b = g.bounding_box()
        return (b[0] + b[2]) / 2, (b[1] + b[3]) / 2
    pts = _key_points(g)[:2] if g.kind == "hyperbola" else _key_points(g)[:1]
    cx, cy = (win[0] + win[1]) / 2, (win[2] + win[3]) / 2
    return min(pts, key=lambda p: math.hypot(p[0] - cx, p[1] - cy))


def _inside(x, y, win):
    return win[0] <= x <= win[1] and win[2] <= y <= win[3]


def _border_arrow(ax, x, y, win, colour):
    """A short arrow on the window's border, on the ray from the window's centre to (x, y)."""
    cx, cy = (win[0] + win[1]) / 2, (win[2] + win[3]) / 2
    hx, hy = (win[1] - win[0]) / 2, (win[3] - win[2]) / 2
    dx, dy = x - cx, y - cy
    n = math.hypot(dx, dy)
    if not (n > 0 and math.isfinite(n)):
        return
    ux, uy = dx / n, dy / n
    s = 0.97 * min(hx / abs(ux) if ux else math.inf, hy / abs(uy) if uy else math.inf)
    L = 0.05 * min(hx, hy)
    tip = (cx + s * ux, cy + s * uy)
    tail = (tip[0] - L * ux, tip[1] - L * uy)
    ax.annotate("", xy=tip, xytext=tail, zorder=6,
                arrowprops=dict(arrowstyle="-|>", color=colour, lw=1.2, shrinkA=0, shrinkB=0))


def plot_diagram(diagram, path_or_ax=None, *, empty_circles: bool = False, title: str | None = None,
                 dpi: int = 120, window=None):
    """Draw ``diagram`` (a :class:`runtime.voronoi.structure.Diagram`).

    ``path_or_ax``: a file path (PNG/SVG/PDF, saved), a matplotlib Axes (drawn on), or None.
    ``window``: ``(xmin, xmax, ymin, ymax)``; default :func:`fit_window`.  ValueError for a window
    that is not four finite numbers with xmin < xmax, ymin < ymax.
    Returns the matplotlib Figure."""
    if window is not None:
        try:
            win = tuple(float(t) for t in window)
        except (TypeError, ValueError):
            win = ()
        if len(win) != 4 or not all(math.isfinite(t) for t in win) or not (win[0] < win[1] and win[2] < win[3]):
            raise ValueError(f"window must be (xmin, xmax, ymin, ymax) with xmin < xmax, ymin < ymax; got {window!r}")
    import matplotlib

    if path_or_ax is None or isinstance(path_or_ax, (str, bytes)) or hasattr(path_or_ax, "__fspath__"):
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    geoms = [_shape(s) for s in diagram.sites]
    if window is None:
        win = fit_window(diagram, geoms)
    if path_or_ax is not None and hasattr(path_or_ax, "plot"):
        ax = path_or_ax
        fig = ax.figure
    else:
        fig, ax = plt.subplots(figsize=(8, 8))
    span = max(win[1] - win[0], win[3] - win[2])
    anchors = [_anchor(g, win) for g in geoms]
    far_sites = 0
    for i, g in enumerate(geoms):
        if g.kind == "point":
            if _inside(g.x0, g.y0, win):
                ax.plot([g.x0], [g.y0], "o", color=COLOURS["site"], ms=3, zorder=4)
        else:
            P = _site_curve(g, win, span)
            if len(P):
                ax.plot(P[:, 0], P[:, 1], "-", color=COLOURS["site"], lw=1.2, zorder=4)
        if len(geoms) <= 60 and _inside(*anchors[i], win):
            ax.annotate(str(i), anchors[i], fontsize=7, color=COLOURS["site"], ha="center", va="center")
        if not _inside(*anchors[i], win):
            far_sites += 1
    for i, j in diagram.delaunay_edges():
        if 0 <= i < len(anchors) and 0 <= j < len(anchors):
            P = clip_polyline([anchors[i], anchors[j]], win)
            if len(P):
                ax.plot(P[:, 0], P[:, 1], "--", color=COLOURS["delaunay"], lw=0.7, zorder=1)
    for e in diagram.edges:
        P = clip_polyline(e.polyline, win)
        if len(P):
            ax.plot(P[:, 0], P[:, 1], "-" if e.certified else ":", color=COLOURS["edge"], lw=1.4, zorder=3)
    inside = [v for v in diagram.vertices if _inside(v.x, v.y, win)]
    outside = [v for v in diagram.vertices if not _inside(v.x, v.y, win)]
    if inside:
        V = np.array([[v.x, v.y] for v in inside])
        ax.plot(V[:, 0], V[:, 1], "o", color=COLOURS["vertex"], ms=3, zorder=5)
    for v in outside:
        _border_arrow(ax, v.x, v.y, win, COLOURS["vertex"])
    if empty_circles:
        t = np.linspace(0, 2 * math.pi, 400)
        for v in diagram.vertices:
            if not (math.isfinite(v.radius) and math.isfinite(v.x) and math.isfinite(v.y)):
                continue
            P = clip_polyline(np.column_stack([v.x + v.radius * np.cos(t), v.y + v.radius * np.sin(t)]), win)
            if len(P):
                ax.plot(P[:, 0], P[:, 1], ":", color=COLOURS["empty"], lw=0.6)
    ax.set_xlim(win[0], win[1])
    ax.set_ylim(win[2], win[3])
    ax.set_aspect("equal")
    handles = [Line2D([], [], color=COLOURS["site"], lw=1.2, label="sites (black)"),
               Line2D([], [], color=COLOURS["edge"], lw=1.4, label="Voronoi edges (blue; dotted: not certified)"),
               Line2D([], [], color=COLOURS["vertex"], marker="o", ls="", ms=4, label="Voronoi vertices (red)"),
               Line2D([], [], color=COLOURS["delaunay"], ls="--", lw=0.7, label="Delaunay graph (grey, dashed)")]
    if outside:
        handles.append(Line2D([], [], color=COLOURS["vertex"], marker=">", ls="-", ms=5, lw=1.2,
                              label=(f"{len(outside)} vertex outside the window (arrow)" if len(outside) == 1 else
                                     f"{len(outside)} vertices outside the window (arrows)")))
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
