"""The random scenes of the tests and the benchmarks, one generator per scene.

Points and segments (integer coordinates) for the segment-site Voronoi tests and their peers
(tests/cgal/sdg_peer.py, tests/peers_boost.py), checked with exact integer orientation tests;
disjoint circles (for the curved-site tests, the CGAL peer tests/cgal/cgal_peer.py and
bench/bench_voronoi.py, bench/bench_verify.py, bench/bench_degenerate.py) and disjoint ellipses
with exact rational data.  Every generator is deterministic in its seed (``random.Random(seed)``).
Benchmarks import this module (their scripts put ``tests/`` on ``sys.path``), so a test and a
benchmark of the same scene draw the same sites."""
from __future__ import annotations

import math
import random
from fractions import Fraction

MIN_LENGTH = 3          # segment lengths are uniform in [MIN_LENGTH, MAX_LENGTH] before rounding
MAX_LENGTH = 30
MEAN_LENGTH = (MIN_LENGTH + MAX_LENGTH) / 2
SPREAD = 4.0            # box side = SPREAD·√n·MEAN_LENGTH: about 1/SPREAD² segments per MEAN_LENGTH²


def orient(a, b, c) -> int:
    """Sign of the turn a → b → c (exact on integers)."""
    d = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    return (d > 0) - (d < 0)


def _on_segment(a, b, p) -> bool:
    """p (collinear with a, b) lies on the closed segment [a, b]."""
    return min(a[0], b[0]) <= p[0] <= max(a[0], b[0]) and min(a[1], b[1]) <= p[1] <= max(a[1], b[1])


def segments_meet(a, b, c, d) -> bool:
    """The closed segments [a, b] and [c, d] have a common point (crossing, touching, overlap)."""
    o1, o2, o3, o4 = orient(a, b, c), orient(a, b, d), orient(c, d, a), orient(c, d, b)
    if o1 * o2 < 0 and o3 * o4 < 0:
        return True
    return ((o1 == 0 and _on_segment(a, b, c)) or (o2 == 0 and _on_segment(a, b, d))
            or (o3 == 0 and _on_segment(c, d, a)) or (o4 == 0 and _on_segment(c, d, b)))


def meet_only_at(s, t, p) -> bool:
    """Segments s and t, both with the endpoint p, have no other common point."""
    d = s[1] if s[0] == p else s[0]
    b = t[1] if t[0] == p else t[0]
    if orient(p, d, b) != 0:
        return True
    return (d[0] - p[0]) * (b[0] - p[0]) + (d[1] - p[1]) * (b[1] - p[1]) < 0


class _Grid:
    """Accepted segments bucketed in square cells of side ``cell`` (each segment in every cell its
    bounding box overlaps), for the rejection tests."""

    def __init__(self, cell: int):
        self.cell = cell
        self.buckets: dict = {}
        self.segments: list = []

    def _cells(self, a, b):
        c = self.cell
        for gx in range(min(a[0], b[0]) // c, max(a[0], b[0]) // c + 1):
            for gy in range(min(a[1], b[1]) // c, max(a[1], b[1]) // c + 1):
                yield gx, gy

    def near(self, a, b):
        found = set()
        for g in self._cells(a, b):
            found.update(self.buckets.get(g, ()))
        return found

    def free(self, a, b, allowed=None) -> bool:
        """[a, b] meets no accepted segment, except those of ``allowed`` {index: common endpoint},
        which it may meet at that endpoint only."""
        allowed = allowed or {}
        for i in self.near(a, b):
            s = self.segments[i]
            if i in allowed:
                if not meet_only_at(s, (a, b), allowed[i]):
                    return False
            elif segments_meet(s[0], s[1], a, b):
                return False
        return True

    def add(self, a, b) -> int:
        self.segments.append((a, b))
        i = len(self.segments) - 1
        for g in self._cells(a, b):
            self.buckets.setdefault(g, []).append(i)
        return i


def _box_side(n: int, box) -> int:
    return int(box) if box is not None else max(2 * MAX_LENGTH, int(SPREAD * math.sqrt(n) * MEAN_LENGTH))


def _step(rng, a, side):
    """A random integer point at distance about U[MIN_LENGTH, MAX_LENGTH] from a, in the box, or None."""
    ang = rng.uniform(0.0, 2.0 * math.pi)
    r = rng.uniform(MIN_LENGTH, MAX_LENGTH)
    b = (a[0] + round(r * math.cos(ang)), a[1] + round(r * math.sin(ang)))
    if b == a or not (0 <= b[0] <= side and 0 <= b[1] <= side):
        return None
    return b


def random_segments(n: int, seed: int, *, box=None, shared=False):
    """n random pairwise non-crossing segments with integer endpoints, as [((x0, y0), (x1, y1))].

    Lengths are uniform in [3, 30] (then rounded to the integer grid), directions uniform, and the
    endpoints lie in the square [0, side]² with side = ``box`` or 4·√n·16.5, so the density (about
    1/16 segment per 16.5² area) does not depend on n.  Candidates are drawn one at a time and
    rejected when they meet an accepted segment (crossing, touching or overlapping, decided with
    exact integer orientations); a uniform grid of cell 30 keeps this local (n = 10⁴ in about a
    second).

    ``shared=False``: the segments are pairwise disjoint (no common endpoints).
    ``shared=True``: the segments form chains that share endpoints and are otherwise disjoint:
    about a third of the chains are closed star-shaped polygons (3 to 8 vertices at sorted random
    angles around a centre, radius 4 to 15), the others open polylines (random walks of 1 to 10
    segments; a walk that cannot continue after 20 tries stops).  Consecutive segments of a chain
    meet at their common vertex only (an angle of 180° is allowed, overlap is not); a chain's other
    segments and other chains are not met at all.  The chain vertices are in order, segment k of a
    polyline ends where segment k+1 starts."""
    rng = random.Random(seed)
    side = _box_side(n, box)
    grid = _Grid(MAX_LENGTH)
    out: list = []
    tries = 0
    while len(out) < n:
        tries += 1
        if tries > 1000 * n + 10000:
            raise RuntimeError(f"box {side} too small for {n} segments")
        a = (rng.randint(0, side), rng.randint(0, side))
        if not shared:
            b = _step(rng, a, side)
            if b is not None and grid.free(a, b):
                grid.add(a, b)
                out.append((a, b))
            continue
        if rng.random() < 1 / 3 and n - len(out) >= 3:
            poly = _star_polygon(rng, a, min(rng.randint(3, 8), n - len(out)), side)
            if poly is None:
                continue
            k = len(poly)
            edges = [(poly[j], poly[(j + 1) % k]) for j in range(k)]
            ok = all(grid.free(*e) for e in edges)
            # within the polygon: consecutive edges meet at their common vertex only, others not at all
            for j in range(k):
                for m in range(j + 1, k):
                    if m == j + 1:
                        ok = ok and meet_only_at(edges[j], edges[m], poly[m])
                    elif j == 0 and m == k - 1:
                        ok = ok and meet_only_at(edges[j], edges[m], poly[0])
                    else:
                        ok = ok and not segments_meet(*edges[j], *edges[m])
            if ok:
                for e in edges:
                    grid.add(*e)
                    out.append(e)
            continue
        steps = min(rng.randint(1, 10), n - len(out))
        prev = None                         # index of the chain's last segment
        for _ in range(steps):
            for _attempt in range(20):
                b = _step(rng, a, side)
                if b is not None and grid.free(a, b, {prev: a} if prev is not None else None):
                    break
            else:
                break
            prev = grid.add(a, b)
            out.append((a, b))
            a = b
    return out


def _star_polygon(rng, centre, k, side):
    """k integer vertices at sorted random angles around centre (radius 4..15), or None when two
    vertices coincide or one leaves the box."""
    radius = rng.uniform(4.0, 15.0)
    angles = sorted(rng.uniform(0.0, 2.0 * math.pi) for _ in range(k))
    pts = []
    for t in angles:
        r = radius * rng.uniform(0.6, 1.0)
        p = (centre[0] + round(r * math.cos(t)), centre[1] + round(r * math.sin(t)))
        if not (0 <= p[0] <= side and 0 <= p[1] <= side):
            return None
        pts.append(p)
    if len(set(pts)) < k:
        return None
    return pts


def random_points_off(segments, m: int, seed: int, *, box=None):
    """m distinct random integer points in the bounding box of ``segments`` (or [0, box]²), none on a
    segment (closed: endpoints excluded too), as [(x, y)]."""
    rng = random.Random(seed)
    if box is None:
        xs = [c[0] for s in segments for c in s] or [0, 10]
        ys = [c[1] for s in segments for c in s] or [0, 10]
        lo, hi = (min(xs), min(ys)), (max(xs), max(ys))
    else:
        lo, hi = (0, 0), (box, box)
    grid = _Grid(MAX_LENGTH)
    for a, b in segments:
        grid.add(a, b)
    out: list = []
    taken: set = set()
    while len(out) < m:
        p = (rng.randint(lo[0], hi[0]), rng.randint(lo[1], hi[1]))
        if p not in taken and grid.free(p, p):
            taken.add(p)
            out.append(p)
    return out


def random_disjoint_circles(n: int, seed: int, *, rmin=0.5, rmax=3.0, gap=1e-3, side=None):
    """n random pairwise disjoint (not nested) circles (x, y, r) in floats, at distance more than
    ``gap`` apart, radii uniform in [rmin, rmax], centres uniform in a square of side ``side``
    (default 10·√n), by rejection with a uniform grid of cell 2·rmax + gap."""
    rng = random.Random(seed)
    side = 10.0 * math.sqrt(n) if side is None else float(side)
    cell = 2 * rmax + gap
    grid: dict = {}
    out: list[tuple[float, float, float]] = []
    while len(out) < n:
        x, y, r = rng.uniform(0, side), rng.uniform(0, side), rng.uniform(rmin, rmax)
        gx, gy = int(x // cell), int(y // cell)
        if any(math.hypot(x - out[i][0], y - out[i][1]) <= r + out[i][2] + gap
               for dx in (-1, 0, 1) for dy in (-1, 0, 1) for i in grid.get((gx + dx, gy + dy), ())):
            continue
        grid.setdefault((gx, gy), []).append(len(out))
        out.append((x, y, r))
    return out


#: rational rotations (cos, sin) from Pythagorean triples: they keep rotated ellipses exact
ROTATIONS = [(Fraction(1), Fraction(0)), (Fraction(3, 5), Fraction(4, 5)), (Fraction(5, 13), Fraction(12, 13)),
             (Fraction(8, 17), Fraction(15, 17)), (Fraction(4, 5), Fraction(-3, 5)), (Fraction(0), Fraction(1))]


def random_ellipses(n: int, seed: int, rotations=None, *, side=None):
    """n ellipses with disjoint circumscribed discs (hence disjoint), exact rational coefficients:
    centres on the grid 1/64 in a square of side ``side`` (default 8·√n), major semi-axis in
    [1, 3] and ratio in [0.3, 0.9] on the grid 1/16, a rotation from ``rotations`` (default
    :data:`ROTATIONS`)."""
    from curvedvoronoi.runtime.sites.conic import Conic

    rotations = rotations or ROTATIONS
    rng = random.Random(seed)
    side = 8.0 * math.sqrt(n) if side is None else float(side)
    placed = []
    out = []
    while len(out) < n:
        cx = Fraction(round(rng.uniform(0, side) * 64), 64)
        cy = Fraction(round(rng.uniform(0, side) * 64), 64)
        a = Fraction(round(rng.uniform(1.0, 3.0) * 16), 16)
        b = a * Fraction(round(rng.uniform(0.3, 0.9) * 16), 16)
        if any(math.hypot(float(cx) - x, float(cy) - y) <= float(a) + r + 0.05 for x, y, r in placed):
            continue
        c, s = rng.choice(rotations)
        out.append(Conic.ellipse(centre=(cx, cy), axes=(a, b), rotation=(c, s)))
        placed.append((float(cx), float(cy), float(a)))
    return out


def random_arcs(n: int, seed: int, cell: int = 40):
    """n circular arcs, one in each of n random cells of a ⌈√n⌉ × ⌈√n⌉ grid of cells of side
    ``cell``: integer centre and radius (3 to cell/2 − 4) with the disc inside the cell (so the arcs
    are pairwise disjoint), integer start angle and span (10° to 180°) in degrees."""
    import math
    import random

    import curvedvoronoi as cv

    rng = random.Random(seed)
    side = math.ceil(math.sqrt(n))
    out = []
    for k in rng.sample(range(side * side), n):
        gx, gy = k % side, k // side
        r = rng.randint(3, cell // 2 - 4)
        slack = cell // 2 - 1 - r
        cx = cell * gx + cell // 2 + rng.randint(-slack, slack)
        cy = cell * gy + cell // 2 + rng.randint(-slack, slack)
        a0 = rng.randint(0, 359)
        out.append(cv.Arc.circular((cx, cy), r, a0, a0 + rng.randint(10, 180)))
    return out


def clustered_circles(n: int, seed: int, *, cluster: float = 0.3, big: float | None = None):
    """n pairwise disjoint (not nested) circles (x, y, r): a uniform background
    (:func:`random_disjoint_circles`, side 10·√n), a dense cluster of ``cluster``·n small circles
    (radii in [0.02, 0.1]) in a square of side √n about the centre of the scene (where the lines of
    a 2 × 2 grid of tiles cross), and one circle of radius ``big`` (default 0.2 of the side: larger
    than a tile of a 3 × 3 grid) centred at (side/4, 3·side/4); background circles meeting the cluster's square or the
    big circle are dropped, so the scene has about n sites."""
    side = 10.0 * math.sqrt(n)
    m = int(cluster * n)
    small = random_disjoint_circles(m, seed + 1, rmin=0.02, rmax=0.1, gap=1e-3, side=math.sqrt(n))
    c0 = side / 2 - math.sqrt(n) / 2
    small = [(x + c0, y + c0, r) for x, y, r in small]
    R = 0.2 * side if big is None else float(big)
    bx, by = side / 4, 3 * side / 4
    bg = random_disjoint_circles(n - m, seed, side=side)
    lo, hi = c0 - 4.0, c0 + math.sqrt(n) + 4.0
    keep = [(x, y, r) for x, y, r in bg
            if not (lo < x < hi and lo < y < hi) and math.hypot(x - bx, y - by) > R + r + 0.5]
    return keep + small + [(bx, by, R)]
