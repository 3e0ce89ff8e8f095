"""Tiles of the plane with a halo of neighbouring sites, the locality lemma, and the stitch.

The Voronoi diagram is local (thesis §1.2, Prop. 1.2.1): a point x belongs to the cell of its
nearest sites, and only sites within its nearest distance matter.  Parallel constructions of
Voronoi and Delaunay tessellations cut the domain into blocks, give each block a *ghost zone*
of neighbouring sites and grow the ghost zone until every empty ball of the block's diagram is
inside it (T. Peterka, D. Morozov, C. Phillips, "High-performance computation of
distributed-memory parallel 3D Voronoi and Delaunay tessellation", SC14; the same growth rule
is the one used here).

Setting.  Sites are bounded, convex and pairwise disjoint, and none lies inside another (no
nesting: checked by the caller; nested scenes are built in one process).  K_s is the closed
convex region bounded by site s (a point is its own region), B the bounding box of all the
sites (every K_s ⊂ B).  Write d̂_s(x) for the distance from x to K_s.  Without nesting the nearest
sites of x for the true distances (to the curves) are its nearest sites for d̂: outside every
K_s the two agree, and inside K_s the site s is the unique nearest site for both (any other
site lies outside K_s, so a segment from x to it crosses the curve of s first).

Tiles.  A grid of nx × ny closed boxes T covers B; the tile's input S_T is the set of sites whose
bounding box meets the box T_h = T grown by the halo h on every side.  Sides of T on the
boundary of B need no halo (no site lies beyond B), so only the *interior* sides count below.

**Locality lemma.**  Let x ∈ T and let s* be a site with d̂_{s*}(x) ≤ ρ, where ρ ≤ h + a(x) and
a(x) is the distance from x to the nearest interior side line of T (x inside T; negative a
little outside).  Then the disc D(x, ρ) meets B only inside T_h, so every site s with
d̂_s(x) ≤ ρ has a point in T_h ∩ B and is in S_T; in particular s* ∈ S_T and the nearest sites
of x in S and in S_T coincide, at the same distance.  Hence, if this holds at every point of a
region Q, the diagram of S and that of S_T are equal on Q, vertex for vertex (same sites, same
empty circle) and edge piece for edge piece.

**The halo bound** (checked before a tile is built, :func:`halo_holds`; lemma of the Peterka et al. ghost zone).  Q = T⁺, the tile
grown by a margin μ (so that a vertex on a tile side is found by both neighbours within float
error).  Cover Q by a grid of nodes g of spacing δ: every x ∈ Q is within ε = δ/√2 of a node.
For each node, U(g) ≥ min_s d̂_s(g) is a rigorous upper bound taken from a few sites near g
(d̂_s(g) ≤ max(0, |g − c_s| − ρ_s) for a disc D(c_s, ρ_s) ⊂ K_s: the circle itself, ρ = 0 for
a point, the minor semi-axis for an ellipse; any site gives an upper bound, so the search
for near sites needs no proof).  The distance d̂ is 1-Lipschitz and a is 1-Lipschitz, so if

    U(g) + 2ε ≤ h + a(g)          at every node g,

the lemma's hypothesis holds at every x ∈ Q with ρ = U(g) + ε (U(g) + ε bounds d̂_s(x) for the
site s that gave U(g), and U(g) + ε ≤ h + a(g) − ε ≤ h + a(x)).  When it fails, h is doubled
(and the grid redrawn) until it holds; h ≥ 2·diam(B) always passes (U ≤ diam(B) + μ), so this
ends.  The bound proves more than needed near the tile's centre and is about the largest empty
circle near its sides, as in Peterka et al.'s criterion.

**One point** (:func:`local_vertex`).  A vertex v of the diagram of S_T with radius r (float;
the construction proves it to 1e-10 relative, η covers that) is a vertex of the diagram of S,
with the same sites, when the bounding box of D(v, r + η) ∩ B lies in T_h: a site outside S_T
misses T_h, hence the disc, so the circle stays empty.  Outside B the grid does not reach, and
the region there is the **rim** (:class:`Rim`): the sites meeting B ∖ int(B_w), B_w the box B
shrunk by w; a vertex whose disc D(v, r + η) misses B_w is a vertex of the diagram of S by the
same argument (every site lies in B, and those meeting B ∖ B_w are the rim's).  Far outside B
the empty circles are huge but meet B only in a thin cap along its side, so w of a few spacings
suffices; when a vertex the rim must report fails, w is doubled and the rim rebuilt.

The tiles' diagrams are built and stitched by :mod:`runtime.voronoi.stitch`.

Public API: :class:`Tile`, :class:`Rim`, :class:`SiteDiscs`, :func:`tile_grid`, :func:`site_discs`,
:func:`nested_pair`, :func:`upper_distance`, :func:`halo_holds`, :func:`grow_halo`,
:func:`tile_input`, :func:`local_vertex`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

__all__ = ["Tile", "Rim", "SiteDiscs", "tile_grid", "site_discs", "nested_pair", "upper_distance", "halo_holds",
           "grow_halo", "tile_input", "local_vertex", "MARGIN"]

#: relative slack on float distances (a few roundings of hypot and subtraction, generously)
SLACK = 1e-12
#: the tile margin μ, relative to the scale of B: far above the vertices' float error (1e-10)
MARGIN = 1e-7
#: grid spacing of the halo bound, as a fraction of the halo
GRID_FRACTION = 6.0
#: the largest grid of the halo bound; a finer one (a halo below 1/80 of the tile) is not checked
MAX_NODES = 250_000


@dataclass
class Tile:
    """One tile: ``box`` (x0, y0, x1, y1), grid position ``ij``, which sides are ``interior``
    (left, bottom, right, top; the others lie on the boundary of B), the ``halo`` h and how many
    times it was doubled (``growths``)."""

    index: int
    ij: tuple[int, int]
    box: tuple[float, float, float, float]
    interior: tuple[bool, bool, bool, bool]
    halo: float
    bound: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 0.0)
    growths: int = 0
    history: list = field(default_factory=list)

    def halo_box(self) -> tuple[float, float, float, float]:
        """T_h: the box grown by the halo on its interior sides, to infinity on the others."""
        x0, y0, x1, y1 = self.box
        h = self.halo
        L, Bo, R, T = self.interior
        return (x0 - h if L else -math.inf, y0 - h if Bo else -math.inf,
                x1 + h if R else math.inf, y1 + h if T else math.inf)

    def cell(self, margin: float) -> tuple[float, float, float, float]:
        """The tile's cell for reporting vertices: the box grown by ``margin``, unbounded beyond B."""
        x0, y0, x1, y1 = self.box
        L, Bo, R, T = self.interior
        return (x0 - margin if L else -math.inf, y0 - margin if Bo else -math.inf,
                x1 + margin if R else math.inf, y1 + margin if T else math.inf)


@dataclass
class SiteDiscs:
    """For each site: bounding box (rows x0, y0, x1, y1, enlarged by the rounding slack), a
    centre c and a radius ρ with the disc D(c, ρ) inside the site's region (shrunk by the slack),
    and the circumscribed radius (for the nesting test); a k-d tree on the centres."""

    boxes: np.ndarray
    centres: np.ndarray
    inner: np.ndarray
    outer: np.ndarray
    scale: float
    tree: object = None

    def bound(self) -> tuple[float, float, float, float]:
        b = self.boxes
        return float(b[:, 0].min()), float(b[:, 1].min()), float(b[:, 2].max()), float(b[:, 3].max())


def site_discs(sites) -> SiteDiscs:
    """:class:`SiteDiscs` of exact sites (points, circles, ellipses).  ValueError for an unbounded
    site (hyperbola, parabola): the tiling needs bounded sites."""
    from scipy.spatial import cKDTree
    from .conic_geometry import site_geometry

    geoms = [site_geometry(s) for s in sites]
    boxes = np.array([g.bounding_box() for g in geoms], dtype=float)
    if not np.isfinite(boxes).all():
        raise ValueError("tiled diagrams need bounded sites (points, circles, ellipses)")
    scale = float(np.abs(boxes).max()) + float((boxes[:, 2:] - boxes[:, :2]).max()) + 1.0
    centres = np.column_stack([(boxes[:, 0] + boxes[:, 2]) / 2, (boxes[:, 1] + boxes[:, 3]) / 2])
    inner = np.zeros(len(geoms))
    outer = np.hypot(boxes[:, 2] - boxes[:, 0], boxes[:, 3] - boxes[:, 1]) / 2
    for t, g in enumerate(geoms):
        if g.kind == "circle":
            centres[t] = (g.cx, g.cy)
            inner[t] = outer[t] = g.rho
        elif g.kind == "point":
            centres[t] = (g.x0, g.y0)
            outer[t] = 0.0
        elif g.kind == "ellipse":
            inner[t] = min(g.a, g.b)          # the bounding box is centred on the ellipse's centre
            outer[t] = max(g.a, g.b)
        else:
            raise ValueError(f"tiled diagrams need points, circles or ellipses, not a {g.kind}")
    slack = SLACK * scale * 16
    inner = np.maximum(inner * (1 - 1e-9) - slack, 0.0)
    outer = outer * (1 + 1e-9) + slack
    boxes = boxes + np.array([-slack, -slack, slack, slack])
    return SiteDiscs(boxes, centres, inner, outer, scale, cKDTree(centres))


def nested_pair(D: SiteDiscs) -> tuple[int, int] | None:
    """A pair (container, inner site) whose centre lies in the container's circumscribed disc
    (a superset of the nested pairs), or None: with None no site lies inside another."""
    for t in np.argsort(-D.outer)[: len(D.outer)]:
        if D.outer[t] <= 0:
            break
        for u in D.tree.query_ball_point(D.centres[t], D.outer[t]):
            if u != t:
                return int(t), int(u)
    return None


def tile_grid(D: SiteDiscs, sites_per_tile: int, halo: float | None = None) -> list[Tile]:
    """Tiles over B: about n / ``sites_per_tile`` squarish boxes; the initial halo (default: three
    times the mean spacing √(area / n))."""
    x0, y0, x1, y1 = D.bound()
    n = len(D.centres)
    w, hgt = max(x1 - x0, 1e-300), max(y1 - y0, 1e-300)
    count = max(1, math.ceil(n / max(1, int(sites_per_tile))))
    nx = max(1, round(math.sqrt(count * w / hgt)))
    ny = max(1, math.ceil(count / nx))
    if halo is None:
        halo = 3.0 * math.sqrt(w * hgt / n)
    xs = np.linspace(x0, x1, nx + 1)
    ys = np.linspace(y0, y1, ny + 1)
    xs[-1], ys[-1] = x1, y1
    tiles = []
    for j in range(ny):
        for i in range(nx):
            tiles.append(Tile(len(tiles), (i, j), (float(xs[i]), float(ys[j]), float(xs[i + 1]), float(ys[j + 1])),
                              (i > 0, j > 0, i < nx - 1, j < ny - 1), float(halo), (x0, y0, x1, y1)))
    return tiles


def upper_distance(D: SiteDiscs, P: np.ndarray, k: int = 6) -> np.ndarray:
    """Rigorous upper bounds of min_s d̂_s(p) for the rows p of P, from the k sites with the
    nearest centres and the 8 largest sites (any site gives an upper bound)."""
    k = min(k, len(D.centres))
    _, idx = D.tree.query(P, k=k)
    idx = np.asarray(idx).reshape(len(P), k)
    big = np.argsort(-D.inner)[:8]
    idx = np.hstack([idx, np.broadcast_to(big, (len(P), len(big)))])
    d = np.hypot(P[:, None, 0] - D.centres[idx, 0], P[:, None, 1] - D.centres[idx, 1]) - D.inner[idx]
    u = np.maximum(d, 0.0).min(axis=1)
    return u * (1 + 8 * SLACK) + 8 * SLACK * (D.scale + np.abs(P).sum(axis=1))


def _side_distance(tile: Tile, P: np.ndarray) -> np.ndarray:
    """a(p): the distance from p to the nearest interior side line of the tile, measured inwards
    (negative outside the tile); +inf when no side is interior."""
    x0, y0, x1, y1 = tile.box
    cols = []
    L, Bo, R, T = tile.interior
    if L:
        cols.append(P[:, 0] - x0)
    if Bo:
        cols.append(P[:, 1] - y0)
    if R:
        cols.append(x1 - P[:, 0])
    if T:
        cols.append(y1 - P[:, 1])
    return np.min(np.column_stack(cols), axis=1) if cols else np.full(len(P), np.inf)


def halo_holds(D: SiteDiscs, tile: Tile, margin: float) -> bool:
    """The halo bound of the module docstring on T⁺ = the tile grown by ``margin``."""
    if not any(tile.interior):
        return True
    x0, y0, x1, y1 = tile.box
    delta = tile.halo / GRID_FRACTION
    nx = max(1, math.ceil((x1 - x0 + 2 * margin) / delta))
    ny = max(1, math.ceil((y1 - y0 + 2 * margin) / delta))
    if (nx + 1) * (ny + 1) > MAX_NODES:
        return False                       # a halo this small next to the tile: grow it (not proved)
    gx = np.linspace(x0 - margin, x1 + margin, nx + 1)
    gy = np.linspace(y0 - margin, y1 + margin, ny + 1)
    step = max((x1 - x0 + 2 * margin) / nx, (y1 - y0 + 2 * margin) / ny) * (1 + 1e-12)
    eps = step / math.sqrt(2.0)
    X, Y = np.meshgrid(gx, gy)
    P = np.column_stack([X.ravel(), Y.ravel()])
    return bool(np.all(upper_distance(D, P) + 2 * eps <= tile.halo + _side_distance(tile, P)))


def grow_halo(D: SiteDiscs, tile: Tile, margin: float, at_least: float = 0.0) -> Tile:
    """Double the tile's halo (at least to ``at_least``) until :func:`halo_holds`; returns the tile."""
    x0, y0, x1, y1 = D.bound()
    diameter = math.hypot(x1 - x0, y1 - y0)
    while tile.halo < at_least:
        tile.halo *= 2.0
        tile.growths += 1
    while not halo_holds(D, tile, margin):
        if tile.halo > 4 * diameter + 1:     # cannot happen: h ≥ 2·diam(B) passes
            raise RuntimeError("halo bound does not hold at twice the diameter of the sites' box")
        tile.halo *= 2.0
        tile.growths += 1
    tile.history.append(tile.halo)
    return tile


def tile_input(D: SiteDiscs, tile: Tile) -> np.ndarray:
    """S_T: indices of the sites whose bounding box meets T_h."""
    hx0, hy0, hx1, hy1 = tile.halo_box()
    b = D.boxes
    return np.nonzero((b[:, 2] >= hx0) & (b[:, 0] <= hx1) & (b[:, 3] >= hy0) & (b[:, 1] <= hy1))[0]


def local_vertex(tile: Tile, x: float, y: float, r: float) -> float:
    """How far the bounding box of D((x, y), r + η) ∩ B sticks out of T_h on the interior sides
    (≤ 0: the vertex is a vertex of the whole diagram, by the lemma at one point)."""
    eta = 1e-8 * (1 + abs(x) + abs(y) + abs(r))
    rr = r + eta
    bx0, by0, bx1, by1 = tile.bound
    # the disc meets the strip by0 ≤ y ≤ by1 within the half-width √(rr² − dy²), dy the gap to it
    dy = max(by0 - y, y - by1, 0.0)
    dx = max(bx0 - x, x - bx1, 0.0)
    if dx > rr or dy > rr:
        return -math.inf                    # the disc misses B: no site can enter it
    hw = math.sqrt(max(rr * rr - dy * dy, 0.0)) * (1 + 1e-12) + eta
    hh = math.sqrt(max(rr * rr - dx * dx, 0.0)) * (1 + 1e-12) + eta
    hx0, hy0, hx1, hy1 = tile.halo_box()
    return max(hx0 - max(x - hw, bx0), hy0 - max(y - hh, by0), min(x + hw, bx1) - hx1, min(y + hh, by1) - hy1)


@dataclass
class Rim:
    """The region outside B, built from the sites meeting the rim B ∖ int(B_w), B_w = B shrunk by
    the ``width`` w: a vertex outside B whose disc D(v, r + η) misses B_w is a vertex of the whole
    diagram (the lemma at one point: every site entering the disc meets B ∖ B_w)."""

    bound: tuple[float, float, float, float]
    width: float
    index: int = -1
    growths: int = 0

    def inner(self) -> tuple[float, float, float, float]:
        x0, y0, x1, y1 = self.bound
        return (x0 + self.width, y0 + self.width, x1 - self.width, y1 - self.width)

    def sites(self, D: "SiteDiscs") -> np.ndarray:
        ix0, iy0, ix1, iy1 = self.inner()
        b = D.boxes
        if ix0 >= ix1 or iy0 >= iy1:
            return np.arange(len(b))
        return np.nonzero((b[:, 0] <= ix0) | (b[:, 1] <= iy0) | (b[:, 2] >= ix1) | (b[:, 3] >= iy1))[0]

    def reports(self, x: float, y: float) -> bool:
        x0, y0, x1, y1 = self.bound
        return not (x0 <= x <= x1 and y0 <= y <= y1)

    def outside(self, x: float, y: float, r: float) -> float:
        """r + η minus a lower bound of the distance from (x, y) to B_w (≤ 0: proved vertex)."""
        ix0, iy0, ix1, iy1 = self.inner()
        if ix0 >= ix1 or iy0 >= iy1:
            return -math.inf
        d = math.hypot(max(ix0 - x, x - ix1, 0.0), max(iy0 - y, y - iy1, 0.0)) * (1 - 1e-12)
        return r + 1e-8 * (1 + abs(x) + abs(y) + abs(r)) - d
